"""Constants of the ``calibrate`` command shared by its modules: the exit statuses, the
summary's columns and the default priors of paper GC's instrument constants.  A leaf: it
imports nothing, so the parser (:mod:`gyrolib.cli.calibrate`) and the runs
(:mod:`gyrolib.cli.calibrate_gc`, :mod:`gyrolib.cli.calibrate_rsf`,
:mod:`gyrolib.cli.outputs`) read the same values without importing each other."""

from __future__ import annotations

from typing import Final

__all__ = ["DEFAULT_CLOCK_TOLERANCE", "DEFAULT_INCL_BIAS_PRIOR_MG", "DEFAULT_OFFSET_PRIOR_ARCSEC",
           "DEFAULT_SCALE_TOLERANCE", "EXIT_BAD_INPUT", "EXIT_INTERRUPTED", "EXIT_INVALID",
           "FIT_DEFAULT", "FIT_UNITS", "PLOT_SUFFIXES", "SUMMARY_COLUMNS"]

#: Exit status of bad input (unreadable, implausible or a bad option).
EXIT_BAD_INPUT: Final[int] = 2
#: Exit status of a run without a valid estimate (paper GC's filter lost lock).
EXIT_INVALID: Final[int] = 3
#: Exit status of a run stopped by Ctrl-C (128 + SIGINT, the shell's convention).
EXIT_INTERRUPTED: Final[int] = 130

#: Columns of ``--summary OUT.csv``, one row per file.
SUMMARY_COLUMNS: Final[tuple[str, ...]] = (
    "file", "method", "quantity", "estimate", "sigma", "unit", "valid", "status", "reason",
    "reason_code", "hint", "notes")

#: Suffixes of the plot files ``--plot`` and ``--allan`` write.
PLOT_SUFFIXES: Final[tuple[str, ...]] = (".png", ".pdf", ".svg", ".jpg", ".jpeg")

#: Units of the noise parameters ``--fit-noise`` can fit (for the printed values).
FIT_UNITS: Final[dict[str, str]] = {
    "alpha1": "rad/s", "sigma1_sq": "m²/s⁴", "xi1": "", "C_as": "rad²·s", "C_in": "m²/s³",
    "C_incl_y": "m²/s³", "C_incl_z": "m²/s³"}
#: The parameters ``--fit-noise`` fits unless ``--fit`` names others.
FIT_DEFAULT: Final[str] = "alpha1,sigma1_sq,C_as,C_in"

#: Default 1σ relative uncertainty of the scale common to H/f and the angle sensor's gain
#: (a floated gyro whose H/f and pick-off gain are known to 0.1 %).
DEFAULT_SCALE_TOLERANCE: Final[float] = 1e-3
#: Default 1σ prior of the angle sensor's null offset (arcsec): covers a logger that starts
#: 1 s late ((H/f) Ω_h · 1 s ≈ 18″).
DEFAULT_OFFSET_PRIOR_ARCSEC: Final[float] = 20.0
#: Default 1σ prior of each inclinometer's bias (mg; real ones: 0.1–1 mg).
DEFAULT_INCL_BIAS_PRIOR_MG: Final[float] = 0.5
#: Default 1σ relative error of the logger's time scale (a crystal's): the table of inputs'
#: ``gc.sigma_clock`` range (a test checks that they agree; read here without importing the
#: table, which loads paper RSF's package).
DEFAULT_CLOCK_TOLERANCE: Final[float] = 1e-4
