"""The ``race`` command: ``python -m gyrolib race [--params P.toml] [--json]``.

Paper GC's method against the rate-sensor method it replaces (its ref. [3]) for a user's own
instrument: both methods' times to σ_c and the verdict on "more than 50 % faster" by the
ledger's one rule for claims (:func:`gyrolib.book.ledger.item.judge_claim`), at the given
parameters (the reference point) and over :data:`gyrolib.gc.RACE_RANGES`.

The TOML file's top-level keys are fields of :class:`gyrolib.gc.GyrocompassParams` (SI, e.g.
``C_as = 2e-13``, ``sigma_hf_scale = 5e-5``); a table ``[procedure]`` holds fields of
:class:`gyrolib.gc.RateSensorProcedure` (e.g. ``loop_bandwidth = 30.0``, ``T_settle = 20.0``).
A bad file exits with status 2, one line on stderr and nothing on stdout.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import re
import sys

__all__ = ["add_parser", "race_report", "run"]


class _UsageError(Exception):
    """A bad ``--params`` file (its message names the file and the key)."""


def add_parser(sub: argparse._SubParsersAction, parser_class: type) -> None:
    """Add the ``race`` sub-command to ``sub``."""
    # the docstring's paragraph as plain text: a terminal shows no Sphinx role
    text = re.sub(r":\w+:`~?([^`]+)`", r"\1", __doc__.split("\n\n")[1]).replace("``", "")
    p = sub.add_parser("race", help="race GC's method against the rate-sensor method",
                       description=text)
    p.add_argument("--params", metavar="P.toml", default=None,
                   help="GyrocompassParams fields at the top level, RateSensorProcedure "
                   "fields in a [procedure] table (SI); default: the paper's and the book's")
    p.add_argument("--json", action="store_true", help="print the result as JSON")


def _replace(label: str, obj: object, values: dict, where: str) -> object:
    names = [f.name for f in dataclasses.fields(obj)]
    for key, val in values.items():
        if key not in names:
            raise _UsageError(f"{label}: unknown field {where + key!r}: expected one of "
                              f"{', '.join(names)}")
        if isinstance(val, dict | list):
            raise _UsageError(f"{label}: field {where + key!r} must be a number or string; "
                              f"got a {type(val).__name__}")
    try:
        return dataclasses.replace(obj, **values)
    except (TypeError, ValueError) as exc:
        raise _UsageError(f"{label}: bad value: {exc}") from None


def _inputs(path: str | None):
    from gyrolib import gc
    from gyrolib.records import RecordError, load_toml

    params, proc = gc.GyrocompassParams(), gc.RateSensorProcedure()
    if path is None:
        return params, proc
    try:
        data = dict(load_toml(path))
    except RecordError as exc:
        raise _UsageError(str(exc)) from None
    table = data.pop("procedure", {})
    if not isinstance(table, dict):
        raise _UsageError(f"{path}: 'procedure' must be a table of RateSensorProcedure fields")
    return (_replace(path, params, data, ""), _replace(path, proc, table, "procedure."))


def _num(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


def race_report(params=None, procedure=None) -> dict:
    """The race and its verdict as a plain dict (the ``--json`` output).

    Parameters
    ----------
    params : GyrocompassParams, optional
        Paper GC's parameters (default: the paper's).
    procedure : RateSensorProcedure, optional
        The rival's procedure and sensor (default: the book's).

    Returns
    -------
    dict
        ``t_c_gc``, ``t_c_rate_sensor``, ``t_c_rate_sensor_optimal`` (s; ``None``: not
        reached), ``faster_percent``, ``faster_percent_optimal`` (%), ``status`` (by the
        ledger's one rule for claims), ``conditions`` (readable sentences), ``kappa_max``,
        ``kappa_ceiling`` (GC's H/f tolerance), ``holds_at_reference``,
        ``holds_over_ranges``.

    Examples
    --------
    >>> r = race_report()
    >>> r["status"], f"{r['t_c_gc']:.1f} s", f"{r['t_c_rate_sensor_optimal']:.1f} s"
    ('holds under conditions', '24.1 s', '56.4 s')
    """
    from gyrolib import gc
    from gyrolib.book.ledger.item import judge_claim

    result = gc.race(params, procedure)
    cond = result.conditions()
    status, conditions = judge_claim(cond.holds_at_reference,
                                     cond.holds_at_reference and cond.holds_over_ranges,
                                     cond.text())
    return {
        "t_c_gc": _num(result.t_c_gc),
        "t_c_rate_sensor": _num(result.t_c_rate_sensor),
        "t_c_rate_sensor_optimal": _num(result.t_c_rate_sensor_optimal),
        "t1": _num(result.t1), "t2": _num(result.t2), "t1_optimal": _num(result.t1_optimal),
        "faster_percent": _num(result.faster_percent),
        "faster_percent_optimal": _num(result.faster_percent_optimal),
        "claim": "GC's method is more than 50 % faster than the rate-sensor method",
        "status": status, "conditions": conditions,
        "holds_at_reference": cond.holds_at_reference,
        "holds_over_ranges": cond.holds_over_ranges,
        "kappa_max": _num(cond.kappa_max), "kappa_ceiling": _num(cond.kappa_ceiling),
        "params": {k: v for k, v in dataclasses.asdict(result.params).items()},
        "procedure": {k: v for k, v in dataclasses.asdict(result.procedure).items()},
    }


def _text(r: dict) -> str:
    def t(x):
        return "not reached" if x is None else f"{x:.1f} s"

    def pct(x):
        return "undefined" if x is None else f"{x:.0f} %"
    lines = [
        f"GC's method:                          {t(r['t_c_gc'])}",
        f"rate-sensor method, classical:        {t(r['t_c_rate_sensor'])}"
        f"  (GC faster by {pct(r['faster_percent'])})",
        f"rate-sensor method, optimal:          {t(r['t_c_rate_sensor_optimal'])}"
        f"  (GC faster by {pct(r['faster_percent_optimal'])})",
        f"more than 50 % faster:                {r['status']}",
    ]
    if r["conditions"]:
        lines.append("")
        lines.append(r["conditions"])
    return "\n".join(lines) + "\n"


def run(args: argparse.Namespace) -> int:
    """Print the race and its verdict; status 0, or 2 with one line on stderr for a bad
    parameter file."""
    try:
        params, proc = _inputs(args.params)
        report = race_report(params, proc)
    except _UsageError as exc:
        sys.stderr.write(f"python -m gyrolib race: error: {' '.join(str(exc).split())}\n")
        return 2
    except (TypeError, ValueError) as exc:
        sys.stderr.write(f"python -m gyrolib race: error: {' '.join(str(exc).split())}\n")
        return 2
    sys.stdout.write(json.dumps(report, indent=1, ensure_ascii=False) + "\n" if args.json
                     else _text(report))
    return 0
