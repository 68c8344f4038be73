"""The command line's options of a record's format, beside the reader that honours them:
which header names hold the record's columns (``--columns``), the time origin (``--t0``)
and the units the file's columns are in (``--time-unit``, ``--angle-unit``,
``--accel-unit``).  :func:`add_format_options` adds them to a parser; :func:`read_options` checks
them and returns the reader's keyword arguments.

Importing this module loads neither numpy nor pyarrow (the command line's ``--help`` builds
every parser).
"""

from __future__ import annotations

import argparse
import math

from gyrolib.records.errors import OptionError

__all__ = ["add_format_options", "parse_columns", "read_options"]


def parse_columns(text: str) -> dict[str, str]:
    """``"t=time,angle_sensor=gyro"`` → ``{"t": "time", "angle_sensor": "gyro"}`` (the
    command line's ``--columns``): the record's column name, ``=``, the file's header name.

    Examples
    --------
    >>> parse_columns("t=time, angle_sensor = gyro")
    {'t': 'time', 'angle_sensor': 'gyro'}
    """
    if not isinstance(text, str):
        raise TypeError(f"columns must be a str like 't=time,angle_sensor=gyro'; got "
                        f"{type(text).__name__}")
    out: dict[str, str] = {}
    for part in text.split(","):
        if not part.strip():
            continue
        name, eq, header = part.partition("=")
        name, header = name.strip(), header.strip()
        if not eq or not name or not header:
            raise ValueError(f"columns expects NAME=HEADER pairs separated by commas (e.g. "
                             f"t=time,angle_sensor=gyro); got {part.strip()!r}")
        if name in out:
            raise ValueError(f"columns maps {name!r} twice")
        out[name] = header
    if not out:
        raise ValueError("columns expects at least one NAME=HEADER pair (e.g. t=time)")
    return out


#: The unit options: option -> (the reader's kind, its choices; the first is SI).
UNIT_OPTIONS: dict[str, tuple[str, tuple[str, ...]]] = {
    "--time-unit": ("time", ("s", "ms", "us", "µs")),
    "--angle-unit": ("angle", ("rad", "mrad", "deg", "arcsec")),
    "--accel-unit": ("accel", ("m/s^2", "m/s²", "mg", "g")),
}


def add_format_options(p: argparse.ArgumentParser, *,
                       kinds: tuple[str, ...] = ("time", "angle", "accel"),
                       t0: bool = True, example: str = "t=time,angle_sensor=gyro") -> None:
    """Add the format options (``--columns``, ``--t0`` unless ``t0`` is False,
    ``--decimal-comma``, the unit options of ``kinds``) to ``p``."""
    p.add_argument("--columns", metavar="MAP",
                   help=f"the file's header names of the record's columns, e.g. "
                        f"{example} (default: the names themselves)")
    if t0:
        _add_t0(p)
    p.add_argument("--decimal-comma", action="store_true", default=None,
                   help="the numbers are written with a decimal comma (0,5); default: "
                        "detected when ';' separates the columns and every number of the "
                        "first data line is written d,d (some so and some not is refused)")
    what = {"time": "the time column t", "angle": "the angle columns (angle_sensor; "
            "sins_increment, gs_angle, gs_gyro_angle)", "accel": "the inclinometers"}
    for opt, (kind, choices) in UNIT_OPTIONS.items():
        if kind in kinds:
            p.add_argument(opt, choices=choices, default=None, metavar="UNIT",
                           help=f"the unit of {what[kind]} in the file: {', '.join(choices)} "
                                f"(default {choices[0]}); converted to SI as read")


def _add_t0(p: argparse.ArgumentParser) -> None:
    p.add_argument("--t0", type=float, metavar="S",
                   help="the time stamp of the feedback switch-off: earlier rows are dropped "
                        "(the output says how many) and S is subtracted from every time "
                        "stamp (default: the first row's time when it is an absolute clock, "
                        ">= 1000 s; else none); in the time column's unit")


def read_options(args: argparse.Namespace) -> dict:
    """The reader's keyword arguments from the parsed format options (``columns``, ``t0``,
    ``units``); a bad option raises :class:`~gyrolib.records.errors.OptionError` naming it.

    Examples
    --------
    >>> o = read_options(argparse.Namespace(columns="t=time", t0=None, time_unit="ms"))
    >>> o["columns"], o["units"]["time"], o["units"]["angle"]
    ({'t': 'time'}, 'ms', None)
    """
    try:
        columns = parse_columns(args.columns) if args.columns is not None else None
    except ValueError as exc:
        raise OptionError(f"--columns: {' '.join(str(exc).split())}") from None
    t0 = getattr(args, "t0", None)
    if t0 is not None and not math.isfinite(t0):
        raise OptionError(f"--t0 must be a finite number of seconds; got {t0}")
    units = {kind: getattr(args, opt[2:].replace("-", "_"), None)
             for opt, (kind, _) in UNIT_OPTIONS.items()}
    return {"columns": columns, "t0": t0, "units": units,
            "decimal_comma": getattr(args, "decimal_comma", None)}
