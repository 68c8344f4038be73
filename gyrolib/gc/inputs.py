"""Paper GC's rows of the table of inputs (:mod:`gyrolib.inputs`): the model's, declared
beside :class:`~gyrolib.gc.GyrocompassParams` (:mod:`gyrolib.gc.model.inputs`), then the
race's rival's, beside :class:`~gyrolib.gc.RateSensorProcedure`
(:mod:`gyrolib.gc.racing.inputs`).

Examples
--------
>>> from gyrolib.gc import inputs
>>> [r.name for r in inputs.ROWS][:2], len(inputs.ROWS)
(['gc.alpha1', 'gc.xi1'], 28)
>>> sorted(inputs.OWNERS)
['GyrocompassParams', 'RateSensorProcedure']
"""

from __future__ import annotations

from typing import Final

from gyrolib.gc.model import inputs as _model
from gyrolib.gc.model.params import GyrocompassParams
from gyrolib.gc.racing import inputs as _racing
from gyrolib.gc.racing.rate_sensor import RateSensorProcedure
from gyrolib.input_rows import Input

__all__ = ["OWNERS", "ROWS"]

#: The dataclasses whose fields the rows set, by the name the rows use.
OWNERS: Final[dict[str, type]] = {
    "GyrocompassParams": GyrocompassParams,
    "RateSensorProcedure": RateSensorProcedure,
}

#: Every row of paper GC, the model's first, then the race's rival's.
ROWS: Final[tuple[Input, ...]] = _model.ROWS + _racing.ROWS
