"""The reason codes and their hints of the ``calibrate`` command: the library's table
(:mod:`gyrolib.reasons`), which the verdicts of :func:`gyrolib.gc.judge_record` and
:func:`gyrolib.rsf.judge_record` carry, served here under the command line's name.

Examples
--------
>>> REASONS["no_latitude"].option
'--latitude'
"""

from __future__ import annotations

from gyrolib.reasons import REASONS, Reason, hint, primary

__all__ = ["REASONS", "Reason", "hint", "primary"]
