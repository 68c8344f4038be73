"""Constants of the ``calibrate`` command shared by its modules: the exit statuses, the
summary's columns and the default priors of paper GC's instrument constants (from the
table of inputs, stored with the package).  A leaf: it imports nothing of gyrolib at its
start, so the parser
(:mod:`gyrolib.cli.calibrate`) and the runs (:mod:`gyrolib.cli.calibrate_gc`,
:mod:`gyrolib.cli.calibrate_rsf`, :mod:`gyrolib.cli.outputs`) read the same values without
importing each other."""

from __future__ import annotations

import functools
import json
from pathlib import Path
from typing import Final

__all__ = [  # noqa: F822 - the DEFAULT_* priors are read from DEFAULTS_FILE on first use
           "DEFAULTS_FILE", "DEFAULT_CLOCK_TOLERANCE", "DEFAULT_INCL_BIAS_PRIOR_MG",
           "DEFAULT_OFFSET_PRIOR_ARCSEC", "DEFAULT_SCALE_TOLERANCE", "EXIT_BAD_INPUT",
           "EXIT_INTERRUPTED", "EXIT_INVALID", "FIT_DEFAULT", "FIT_UNITS", "FROM_TABLE",
           "PLOT_SUFFIXES", "SUMMARY_COLUMNS", "table_defaults"]

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
#: (:func:`gyrolib.inputs.default_prior`): ``DEFAULT_SCALE_TOLERANCE`` (relative, H/f and the
#: angle sensor's gain), ``DEFAULT_OFFSET_PRIOR_ARCSEC`` (the angle sensor's null offset,
#: paper arcsec), ``DEFAULT_INCL_BIAS_PRIOR_MG`` (each inclinometer's bias, mg),
#: ``DEFAULT_CLOCK_TOLERANCE`` (the logger's time scale, relative).
FROM_TABLE: Final[dict[str, tuple[str, str]]] = {
    "DEFAULT_SCALE_TOLERANCE": ("gc.sigma_hf_scale", "1"),
    "DEFAULT_OFFSET_PRIOR_ARCSEC": ("gc.sigma_as_offset", "arcsec_paper"),
    "DEFAULT_INCL_BIAS_PRIOR_MG": ("gc.sigma_incl_bias", "mg"),
    "DEFAULT_CLOCK_TOLERANCE": ("gc.sigma_clock", "1"),
}

#: Where the values of :data:`FROM_TABLE` are stored with the package: the table imports
#: numpy and both papers' packages, which neither ``--help`` nor a ``calibrate gc`` run
#: otherwise loads (tests/test_imports.py, tests/cli/test_calibrate.py).  The file is
#: derived, never typed: :func:`table_defaults` computes it, ``python -m
#: gyrolib.cli.constants`` writes it, and tests/gc/test_priors.py fails when it differs from
#: the table.
DEFAULTS_FILE: Final[Path] = Path(__file__).resolve().parents[1] / "data" / "cli_defaults.json"


def table_defaults() -> dict[str, float]:
    """The default priors computed from the table of inputs (imports it)."""
    from gyrolib import inputs, units

    return {name: float(units.from_si(inputs.default_prior(row), unit))
            for name, (row, unit) in FROM_TABLE.items()}


@functools.cache
def _stored() -> dict[str, float]:
    return json.loads(DEFAULTS_FILE.read_text(encoding="utf-8"))


def __getattr__(name: str) -> float:
    if name in FROM_TABLE:
        return float(_stored()[name])
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


if __name__ == "__main__":
    DEFAULTS_FILE.write_text(json.dumps(table_defaults(), indent=1) + "\n", encoding="utf-8")
    print(f"wrote {DEFAULTS_FILE}")
