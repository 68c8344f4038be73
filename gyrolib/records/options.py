"""The command line's options of a record's format, beside the reader that honours them:
which header names hold the record's columns (``--columns``) and the time origin
(``--t0``).  :func:`add_format_options` adds them to a parser; :func:`read_options` checks
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


def add_format_options(p: argparse.ArgumentParser) -> None:
    """Add the format options (``--columns``, ``--t0``) to ``p``."""
    p.add_argument("--columns", metavar="MAP",
                   help="the file's header names of the record's columns, e.g. "
                        "t=time,angle_sensor=gyro (default: the names themselves)")
    p.add_argument("--t0", type=float, metavar="S",
                   help="subtract S seconds from every time stamp (default: the first row's "
                        "time when it is an absolute clock, >= 1000 s; else none)")


def read_options(args: argparse.Namespace) -> dict:
    """The reader's keyword arguments from the parsed format options (``columns``, ``t0``);
    a bad option raises :class:`~gyrolib.records.errors.OptionError` naming it.

    Examples
    --------
    >>> read_options(argparse.Namespace(columns="t=time", t0=None))
    {'columns': {'t': 'time'}, 't0': None}
    """
    try:
        columns = parse_columns(args.columns) if args.columns is not None else None
    except ValueError as exc:
        raise OptionError(f"--columns: {' '.join(str(exc).split())}") from None
    if args.t0 is not None and not math.isfinite(args.t0):
        raise OptionError(f"--t0 must be a finite number of seconds; got {args.t0}")
    return {"columns": columns, "t0": args.t0}
