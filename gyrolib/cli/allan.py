"""The ``allan`` command: ``python -m gyrolib allan FILE [--rate-unit U] [--rate HZ]
[--phase] [--json]``.

The overlapping Allan deviation of one series — a gyro's rate (column ``rate``), or with
--phase its integral (column ``phase``: an angle, or a clock's time error with --rate-unit
1), with a time column ``t`` (s) or, with --rate HZ, at a stated sample rate and no time
column, as allantools and Stable32 read a series — and the noise terms read off it (IEEE
Std 952: angle random walk, bias instability, rate random walk), each with its 1σ
uncertainty, or as an upper bound when the data do not show it.  A term's line, and the
line of its upper bound, never lie above the measured deviation's 68 % upper bound (over
the whole curve) at any τ; a term that IEEE Std 952 reads outside the measured τ range
(the −½ line at 1 s, the +½ line at 3 s) is a bound, printed with the τ range it comes
from.  The bias instability is IEEE Std 952's: the curve's minimum ÷ 0.664.  The file is
read as calibrate reads its records (units rows, decimal commas, ISO time, gzip, tabs,
comments, --columns, --time-unit); rows with a missing value are dropped and counted.  A
time column must step evenly (within 1 % of its median step); without --time-unit, a
gyro's log whose median step is 0.5 or more (2 Hz or slower in s) and fits 10 Hz-10 kHz in
ms or µs is refused, naming the option.  A gyro log not at rest (its rate, averaged over
1 s, departs from its median by more than 1 deg/s) is analysed with a warning: its terms
describe the motion, not the sensor.  Exit status 0, or 2 on bad input (one line on
stderr, nothing on stdout but, with --json, an error object).
"""

from __future__ import annotations

import argparse
import json
import math
import re
import sys

from gyrolib.records.options import add_format_options

__all__ = ["RATE_UNITS", "add_parser", "run"]

#: Units the rate column may be in (``1``: a clock's fractional frequency); a phase column
#: is in the rate unit times s (rad, deg, s).
RATE_UNITS = ("rad/s", "deg/s", "deg/h", "1")


def add_parser(sub: argparse._SubParsersAction, parser_class: type) -> None:
    p = sub.add_parser("allan", help="Allan deviation and noise terms of a rate or phase log",
                       description=re.sub(r":\w+:`~?([^`]+)`", r"\1", __doc__.split("\n\n")[1])
                       .replace("``", "").replace("\n", " "))
    p.add_argument("file", metavar="FILE",
                   help="CSV with columns t (s) and rate (or phase; no t with --rate)")
    p.add_argument("--rate-unit", choices=RATE_UNITS, default="rad/s",
                   help="unit of the rate column (default rad/s; 1 for a clock's fractional "
                        "frequency); with --phase the phase is in rad, deg or s")
    p.add_argument("--rate", type=float, default=None, metavar="HZ",
                   help="the sample rate of a log without a time column (any t column is "
                        "then not read)")
    p.add_argument("--phase", action="store_true",
                   help="the column is phase (the rate's integral: an angle, or a clock's "
                        "time error in s), not rate")
    add_format_options(p, kinds=("time",), t0=False, example="t=time,rate=gyro_x")
    p.add_argument("--json", action="store_true", help="print one JSON object (SI)")


def _fail(args: argparse.Namespace, message: str, hint: str | None = None) -> int:
    line = message if message.startswith(f"{args.file}:") else f"{args.file}: {message}"
    line = " ".join(line.split()) + (f"; try: {hint}" if hint else "")
    sys.stderr.write(f"error: {line}\n")
    if args.json:
        sys.stdout.write(json.dumps({"file": args.file, "status": "error",
                                     "error": line}) + "\n")
    return 2


def _term_json(x) -> dict:
    out = {"name": x.name, "value": x.value, "sigma": x.sigma, "lo": x.lo, "hi": x.hi,
           "unit": x.unit.replace("·", "*").replace("√", "sqrt"),
           "identified": x.identified, "read_at_tau_s": x.read_at,
           "extrapolated": x.extrapolated}
    if x.tau is not None:           # a coefficient of 0 is nowhere: no τ
        out["tau_s"] = x.tau
    return out


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from gyrolib import units
    from gyrolib.gc.logs.allan import (
        REST_LIMIT,
        allan_series,
        curve_upper_bound,
        noise_terms,
        rest_excursion,
    )
    from gyrolib.records.errors import OptionError, RecordError
    from gyrolib.records.options import read_options
    from gyrolib.records.rate_log import read_rate_log

    if args.rate is not None and not (math.isfinite(args.rate) and args.rate > 0):
        return _fail(args, f"--rate must be a sample rate in Hz > 0; got {args.rate}")
    if args.phase and args.rate_unit == "deg/h":
        return _fail(args, "--phase reads a phase in rad, deg or s: give --rate-unit rad/s, "
                           "deg/s or 1")
    try:
        o = read_options(args)
        log = read_rate_log(args.file, sample_rate=args.rate, phase=args.phase,
                            unit=args.rate_unit, time_unit=o["units"]["time"],
                            columns=o["columns"], decimal_comma=o["decimal_comma"])
    except OptionError as exc:
        return _fail(args, str(exc))
    except RecordError as exc:
        hint = exc.hint
        if exc.column == "t" and "not in the header" in str(exc):
            hint = "--rate HZ (a log without a time column)"
        return _fail(args, str(exc), hint)
    except ValueError as exc:       # a bad --columns key, named by the reader
        return _fail(args, " ".join(str(exc).split()))
    unit = "1" if args.rate_unit == "1" else "rad/s"
    s = allan_series(log.values, log.sample_rate, unit=unit,
                     data_type="phase" if args.phase else "freq")
    terms = noise_terms(s)
    bound = curve_upper_bound(s)
    rate = np.diff(log.values) * log.sample_rate if args.phase else log.values
    excursion = rest_excursion(rate, log.sample_rate) if unit == "rad/s" else None
    moving = excursion is not None and excursion > REST_LIMIT
    warning = (f"not at rest: the rate averaged over 1 s departs from its median by up to "
               f"{math.degrees(excursion):.3g} deg/s (more than "
               f"{math.degrees(REST_LIMIT):g} deg/s): the noise terms describe the motion "
               "recorded, not the sensor" if moving else None)
    if unit == "1":
        shown = ((1.0, "sqrt(s)"), (1.0, "1"), (1.0, "1/sqrt(s)"))
    else:
        shown = ((units.UNITS["deg/sqrt_h"], "deg/sqrt(h)"), (units.DEG_PER_HOUR, "deg/h"),
                 (units.DEG_PER_HOUR / 60.0, "deg/h/sqrt(h)"))
    if args.json:
        out = {"file": args.file, "status": "ok", "kind": log.kind, "dt": log.dt,
               "sample_rate_hz": log.sample_rate, "rate_given": log.rate_given,
               "rows": log.rows, "rows_dropped_missing": log.dropped,
               "tau": s.tau.tolist(), "adev": s.adev.tolist(), "adev_lo": s.lo.tolist(),
               "adev_hi": s.hi.tolist(), "adev_hi_curve": bound.tolist(),
               "at_rest": not moving, "rest_excursion_rad_s": excursion,
               "warnings": [warning] if warning else [], "notes": log.notes,
               "noise_terms": [_term_json(x) for x in terms]}
        sys.stdout.write(json.dumps(out) + "\n")
        return 0
    step = "at a stated rate" if log.rate_given else "from its time column"
    lines = [f"Allan deviation of {args.file}: {log.rows} rows ({log.kind}) at "
             f"{log.dt:g} s ({step}), tau {s.tau[0]:g} to {s.tau[-1]:g} s (overlapping, "
             "NIST SP 1065)",
             "  noise terms (IEEE Std 952, 1 sigma; bias instability = curve minimum / "
             "0.664; '<=' an upper bound: the data do not show it):"]
    lines += [f"    {x.describe(scale, u)}" for x, (scale, u) in zip(terms, shown)]
    lines += [f"  WARNING: {warning}"] if warning else []
    lines += [f"  note: {n}" for n in log.notes]
    sys.stdout.write("\n".join(lines) + "\n")
    return 0
