"""Constants of the ``calibrate`` command shared by its modules: the exit statuses, the
summary's columns and the default priors of paper GC's instrument constants (from the
table of inputs, on first use).  A leaf: it imports nothing at its start, so the parser
(:mod:`gyrolib.cli.calibrate`) and the runs (:mod:`gyrolib.cli.calibrate_gc`,
:mod:`gyrolib.cli.calibrate_rsf`, :mod:`gyrolib.cli.outputs`) read the same values without
importing each other."""

from __future__ import annotations

from typing import Final

__all__ = [  # noqa: F822 - the DEFAULT_* priors are read from the table on first use
           "DEFAULT_CLOCK_TOLERANCE", "DEFAULT_INCL_BIAS_PRIOR_MG", "DEFAULT_OFFSET_PRIOR_ARCSEC",
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

#: The default priors of paper GC's instrument errors, in the units of their options: each
#: the largest plausible value of its row of the table of inputs
#: (:func:`gyrolib.inputs.default_prior`), read on first use (the table imports both papers'
#: packages, which the command line's start does not): ``DEFAULT_SCALE_TOLERANCE`` (relative,
#: H/f and the angle sensor's gain), ``DEFAULT_OFFSET_PRIOR_ARCSEC`` (the angle sensor's null
#: offset, paper arcsec), ``DEFAULT_INCL_BIAS_PRIOR_MG`` (each inclinometer's bias, mg),
#: ``DEFAULT_CLOCK_TOLERANCE`` (the logger's time scale, relative).
_FROM_TABLE: Final[dict[str, tuple[str, str]]] = {
    "DEFAULT_SCALE_TOLERANCE": ("gc.sigma_hf_scale", "1"),
    "DEFAULT_OFFSET_PRIOR_ARCSEC": ("gc.sigma_as_offset", "arcsec_paper"),
    "DEFAULT_INCL_BIAS_PRIOR_MG": ("gc.sigma_incl_bias", "mg"),
    "DEFAULT_CLOCK_TOLERANCE": ("gc.sigma_clock", "1"),
}


def __getattr__(name: str) -> float:
    if name in _FROM_TABLE:
        from gyrolib import inputs, units

        row, unit = _FROM_TABLE[name]
        return float(units.from_si(inputs.default_prior(row), unit))
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
