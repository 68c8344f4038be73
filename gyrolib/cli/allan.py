"""The ``allan`` command: ``python -m gyrolib allan FILE [--rate-unit U] [--json]``.

The overlapping Allan deviation of a plain rate series — a CSV with a time column ``t`` (s)
and a rate column ``rate`` (any gyro's output; header names matched without regard to
case) — and the noise terms read off it (IEEE Std 952: angle random walk, bias instability,
rate random walk), each with its 1σ uncertainty, or as an upper bound when the data do not
show it (a term's line never lies above the measured deviation:
:func:`gyrolib.gc.logs.allan.noise_terms`).  The series must be evenly sampled (steps within
1 % of their median).  Exit status 0, or 2 on bad input (one line on stderr, nothing on
stdout but, with ``--json``, an error object).
"""

from __future__ import annotations

import argparse
import json
import re
import sys

__all__ = ["add_parser", "run"]

#: Units the rate column may be in, and their factor to rad/s.
RATE_UNITS = ("rad/s", "deg/s", "deg/h")


def add_parser(sub: argparse._SubParsersAction, parser_class: type) -> None:
    p = sub.add_parser("allan", help="Allan deviation and noise terms of a (t, rate) series",
                       description=re.sub(r":\w+:`~?([^`]+)`", r"\1", __doc__.split("\n\n")[1])
                       .replace("``", "").replace("\n", " "))
    p.add_argument("file", metavar="FILE", help="CSV with columns t (s) and rate")
    p.add_argument("--rate-unit", choices=RATE_UNITS, default="rad/s",
                   help="unit of the rate column (default rad/s)")
    p.add_argument("--json", action="store_true", help="print one JSON object (SI)")


def _fail(args: argparse.Namespace, message: str) -> int:
    sys.stderr.write(f"error: {args.file}: {message}\n")
    if args.json:
        sys.stdout.write(json.dumps({"file": args.file, "status": "error",
                                     "error": message}) + "\n")
    return 2


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from gyrolib import units
    from gyrolib.gc.logs.allan import allan_series, noise_terms

    try:
        with open(args.file, encoding="utf-8") as fh:
            header = [h.strip().lower() for h in fh.readline().split(",")]
        data = np.loadtxt(args.file, delimiter=",", skiprows=1, ndmin=2)
    except (OSError, ValueError, UnicodeDecodeError) as exc:
        return _fail(args, f"not a numeric CSV with a header row ({' '.join(str(exc).split())})")
    missing = [c for c in ("t", "rate") if c not in header]
    if missing:
        return _fail(args, f"expected columns t and rate in the header; missing {missing} "
                           f"(got {header})")
    if data.shape[1] != len(header):
        return _fail(args, f"the header has {len(header)} names, the rows {data.shape[1]} cells")
    t, y = data[:, header.index("t")], data[:, header.index("rate")]
    if t.size < 10 or not np.all(np.isfinite(data)):
        return _fail(args, "expected at least 10 rows of finite numbers")
    h = np.diff(t)
    dt = float(np.median(h))
    if not dt > 0 or np.any(np.abs(h - dt) > 0.01 * dt):
        return _fail(args, f"t must increase in even steps (within 1 % of the median step "
                           f"{dt:g} s)")
    y = y * float(units.to_si(1.0, args.rate_unit))
    s = allan_series(y, 1.0 / dt)
    terms = noise_terms(s)
    shown = ((units.UNITS["deg/sqrt_h"], "deg/sqrt(h)"), (units.DEG_PER_HOUR, "deg/h"),
             (units.DEG_PER_HOUR / 60.0, "deg/h/sqrt(h)"))
    if args.json:
        out = {"file": args.file, "status": "ok", "dt": dt, "rows": int(t.size),
               "tau": s.tau.tolist(), "adev": s.adev.tolist(), "adev_lo": s.lo.tolist(),
               "adev_hi": s.hi.tolist(),
               "noise_terms": [{"name": x.name, "value": x.value, "sigma": x.sigma,
                                "lo": x.lo, "hi": x.hi, "unit": "rad/sqrt(s)" if x.slope < 0
                                else ("rad/s" if x.slope == 0 else "rad/s/sqrt(s)"),
                                "identified": x.identified, "tau_s": x.tau} for x in terms]}
        sys.stdout.write(json.dumps(out) + "\n")
        return 0
    lines = [f"Allan deviation of {args.file}: {t.size} rows at {dt:g} s, tau "
             f"{s.tau[0]:g} to {s.tau[-1]:g} s (overlapping, NIST SP 1065)",
             "  noise terms (IEEE Std 952, 1 sigma; '<=' an upper bound: the data do not "
             "show it):"]
    lines += [f"    {x.describe(scale, unit)}" for x, (scale, unit) in zip(terms, shown)]
    sys.stdout.write("\n".join(lines) + "\n")
    return 0
