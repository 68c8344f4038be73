"""The ``race`` command: ``python -m gyrolib race [--params P.toml] [--json]``.

Paper GC's method against the rate-sensor method it replaces (its ref. [3]) for a user's own
instrument: both methods' times to σ_c and the verdict on "more than 50 % faster" by the
ledger's one rule for claims, at the given parameters (the book's reference point when
none are given) and over the table of inputs (:mod:`gyrolib.inputs`, ranges as factors of
the given values): every input that flips the verdict, and where.

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
    p.add_argument("--no-thresholds", action="store_true",
                   help="skip the map over the table of inputs (the verdict at the given "
                   "parameters only; seconds instead of minutes)")
    p.add_argument("--inputs", metavar="NAMES", default=None,
                   help="comma-separated rows of the table to vary (default: every input the "
                   "race reads; see python -m gyrolib claims)")
    p.add_argument("--workers", type=int, default=1, metavar="K",
                   help="worker processes for the map (default 1)")


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
    from gyrolib.records import RecordError
    from gyrolib.records.params import race_inputs

    params, proc = gc.GyrocompassParams(), gc.RateSensorProcedure()
    if path is None:
        return params, proc
    try:      # one instrument file with calibrate: 'latitude' read, RSF's tables named
        data, table, notes = race_inputs(path)
    except RecordError as exc:
        raise _UsageError(str(exc)) from None
    out = (_replace(path, params, data, ""), _replace(path, proc, table, "procedure."))
    for note in notes:       # after the checks: a bad file gets its one line only
        sys.stderr.write(f"note: {note}\n")
    return out


def _num(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


def _stored_map(claim):
    """The stored map of ``claim`` (the study ``claim-maps``), checked as the store checks
    it: the study's key against the code's, then this claim's fingerprint points (every
    threshold bracketed, the readings, a sample of the sweeps) within the study's declared
    tolerance.  Returns the map and the number of points that agreed; raises
    :class:`gyrolib.store.StaleStudy` (its one line names the refresh command)."""
    from gyrolib import store
    from gyrolib.book import studies  # noqa: F401  (registers the studies)
    from gyrolib.claim_map import ClaimMap, check_map

    s = store.study("claim-maps")
    data = json.loads(s.file.read_text(encoding="utf-8"))
    h = store.header_of(s.name, data)
    store.check_key(s.name, h.key, s.key())
    if claim.id not in data.get("maps", {}):
        raise store.StaleStudy(s.name, f"it has no map of {claim.id}")
    m = ClaimMap.from_dict(data["maps"][claim.id])
    try:
        n = check_map(claim, m, rtol=h.rtol, atol=h.atol)
    except ValueError as exc:
        raise store.StaleStudy(s.name, str(exc)) from None
    return m, n


def race_report(params=None, procedure=None, *, thresholds: bool = True,
                inputs: tuple[str, ...] | None = None, executor=None) -> dict:
    """The race and its verdict as a plain dict (the ``--json`` output).

    Parameters
    ----------
    params : GyrocompassParams, optional
        Paper GC's parameters (default: the paper's).
    procedure : RateSensorProcedure, optional
        The rival's procedure and sensor (default: the book's).
    thresholds : bool, default True
        Map the claim over the table of inputs around these parameters: at the book's
        reference point the stored map (the study ``claim-maps``), checked by its key and
        this claim's fingerprint points and not recomputed; elsewhere computed by
        :func:`gyrolib.claim_map.map_claim` (its coarse bracket in the rows where the margin
        is monotone).
    inputs : tuple of str, optional
        The rows to vary (default: every row the race reads).
    executor : concurrent.futures.Executor, optional
        Where the map's sweeps run.

    Returns
    -------
    dict
        ``t_c_gc``, ``t_c_rate_sensor``, ``t_c_rate_sensor_optimal`` (s; ``None``: not
        reached), ``faster_percent``, ``faster_percent_optimal`` (%), ``status`` (by the
        ledger's one rule for claims, in the words a reader sees: with the share of the box
        where it holds, when a box was drawn), ``status_code`` (a stable code,
        :data:`gyrolib.claim_map.STATUS_CODES`), ``conditions`` (readable sentences),
        ``reference`` (the values the map was drawn around: the given parameters, or the
        book's reference point), ``at_reference_point`` (whether they are the book's),
        ``map_source`` (``"stored"``: read from the store and checked, ``"computed"``, or
        ``None`` without the map), ``checked_points`` (the stored map's points that agreed),
        ``thresholds`` (each ``{input, value, factor, unit, holds_when}``),
        ``share_holding``, ``readings`` (``None`` without the map), ``kappa_max``,
        ``kappa_ceiling`` (GC's H/f tolerance and the κ above which GC never reaches σ_c),
        ``gc_reaches_sigma_c``.

    Examples
    --------
    >>> r = race_report()
    >>> r["status_code"], f"{r['t_c_gc']:.1f} s", f"{r['t_c_rate_sensor_optimal']:.1f} s"
    ('holds_near_reference', '24.1 s', '56.4 s')
    >>> sorted({t["input"] for t in r["thresholds"]} & {"gc.sigma1_sq", "gc.sigma_hf_scale"})
    ['gc.sigma1_sq', 'gc.sigma_hf_scale']
    """
    from gyrolib import gc
    from gyrolib import inputs as table
    from gyrolib.book.ledger import claims
    from gyrolib.claim_map import STATUS_CODES, Claim, map_claim, status_line
    from gyrolib.gc.racing.comparison import MARGIN_MONOTONE_ROWS

    result = gc.race(params, procedure)
    # the reference sentence and GC's κ tolerance: conditions()' worst corner and
    # one-at-a-time searches are not shown here, so not run
    reference_text = result.reference_text()
    kappa_max = result.kappa_max() if math.isfinite(result.t_c_gc) else 0.0
    kappa_ceiling = result.procedure.sigma_c / result.params.Omega_h
    objs = {**table.reference_objects(), "GyrocompassParams": result.params,
            "RateSensorProcedure": result.procedure}
    claim = claims.CLAIMS["gc.faster_percent"]
    if inputs is not None:
        claim = Claim(claim.id, claim.margin, tuple(inputs), claim.meaning, claim.unit)
    at_reference = inputs is None and all(
        objs[k] == v for k, v in table.reference_objects().items())
    # the race's own sentence names the point it is judged at: the user's values are not the
    # book's reference point
    here = reference_text
    if not at_reference:
        here = here.replace("At the reference point (", "At the given parameters (", 1)
    source, checked = None, None
    if not thresholds:
        v = claims.verdict(claim.id, objs, context=here)
        status, conditions, judged = v.status, v.conditions, v.judged
    else:
        if at_reference:    # the stored map, checked, not recomputed
            m, checked = _stored_map(claim)
            source = "stored"
        else:
            m = map_claim(claim, objs, n_grid=5, rtol=1e-2, n_box=0, executor=executor,
                          monotone=[n for n in MARGIN_MONOTONE_ROWS if n in claim.inputs])
            source = "computed"
        judged = {**m.to_dict(), "mapped": True}
        status = m.status
        conditions = ("" if status == "holds" else
                      f"{m.conditions(given=not at_reference)} {here}".strip())
    reaches = bool(math.isfinite(result.t_c_gc))
    if not reaches:
        conditions = (f"GC's method never reaches σ_c: its scale's drift κ·Ω_h alone is "
                      f"{result.params.scale_drift_sigma / result.procedure.sigma_c:.2g} σ_c "
                      f"(κ = {result.params.sigma_hf_scale:.3g} against the ceiling σ_c/Ω_h "
                      f"= {kappa_ceiling:.3g}), or its filter does not get there within "
                      f"{result.procedure.t_max:g} s. {conditions}").strip()
    return {
        "t_c_gc": _num(result.t_c_gc),
        "t_c_rate_sensor": _num(result.t_c_rate_sensor),
        "t_c_rate_sensor_optimal": _num(result.t_c_rate_sensor_optimal),
        "t1": _num(result.t1), "t2": _num(result.t2), "t1_optimal": _num(result.t1_optimal),
        "faster_percent": _num(result.faster_percent),
        "faster_percent_optimal": _num(result.faster_percent_optimal),
        "claim": "GC's method is more than 50 % faster than the rate-sensor method",
        # the words a reader sees (the share of the box with them) and a stable code
        "status": status_line(status, judged.get("share_holding")),
        "status_code": STATUS_CODES[status],
        "conditions": conditions, "gc_reaches_sigma_c": reaches,
        "reference": judged.get("reference"), "at_reference_point": at_reference,
        "map_source": source, "checked_points": checked,
        "thresholds": judged.get("thresholds"),
        "share_holding": judged.get("share_holding"), "readings": judged.get("readings"),
        "margin": judged.get("margin"),
        "kappa_max": _num(kappa_max), "kappa_ceiling": _num(kappa_ceiling),
        "params": {k: v for k, v in dataclasses.asdict(result.params).items()},
        "procedure": {k: v for k, v in dataclasses.asdict(result.procedure).items()},
    }


def _text(r: dict) -> str:
    def t(x):
        return "not reached" if x is None else f"{x:.1f} s"

    def pct(x):
        if x is None:
            return "GC never reaches σ_c"
        # a negative saving is a slower GC: say so, not "faster by -12 %"
        return f"GC faster by {x:.0f} %" if x >= 0 else f"GC slower by {-x:.0f} %"
    lines = [
        f"GC's method:                          {t(r['t_c_gc'])}",
        f"rate-sensor method, classical:        {t(r['t_c_rate_sensor'])}"
        f"  ({pct(r['faster_percent'])})",
        f"rate-sensor method, optimal:          {t(r['t_c_rate_sensor_optimal'])}"
        f"  ({pct(r['faster_percent_optimal'])})",
        f"more than 50 % faster:                {r['status']}",
    ]
    if r["thresholds"]:
        from gyrolib import inputs as table
        from gyrolib.claim_map import quote_threshold

        others = ("the others at the book's reference point" if r["at_reference_point"]
                  else "the others at the given values")
        src = ("" if r["map_source"] != "stored" else
               f"; the stored map, {r['checked_points']} of its points rechecked")
        lines += ["", f"inputs that flip it, each varied alone ({others}{src}):"]
        for t in r["thresholds"]:
            row = table.row(t["input"])
            lines.append(f"  {row.symbol:<14} {t['input']:<24} holds {t['holds_when']} "
                         f"{quote_threshold(None, t, reference='the given value')}")
    if r["conditions"]:
        lines.append("")
        lines.append(r["conditions"])
    return "\n".join(lines) + "\n"


def run(args: argparse.Namespace) -> int:
    """Print the race and its verdict; status 0, 2 with one line on stderr for a bad
    parameter file, or 3 when the stored map it would print is stale."""
    from gyrolib.store import StaleStudy

    executor = None
    try:
        params, proc = _inputs(args.params)
        names = None if args.inputs is None else tuple(
            n.strip() for n in args.inputs.split(",") if n.strip())
        if names is not None:
            from gyrolib import inputs as table

            for n in names:
                table.row(n)
        if args.workers < 1:
            raise _UsageError("--workers must be >= 1")
        if args.workers > 1 and not args.no_thresholds:
            from concurrent.futures import ProcessPoolExecutor

            executor = ProcessPoolExecutor(args.workers)
        report = race_report(params, proc, thresholds=not args.no_thresholds, inputs=names,
                             executor=executor)
    except KeyError as exc:
        sys.stderr.write(f"python -m gyrolib race: error: --inputs: {exc.args[0]}\n")
        return 2
    except StaleStudy as exc:     # the stored map no longer agrees with the code
        sys.stderr.write(f"python -m gyrolib race: {exc}\n")
        return 3
    except _UsageError as exc:
        sys.stderr.write(f"python -m gyrolib race: error: {' '.join(str(exc).split())}\n")
        return 2
    except (TypeError, ValueError) as exc:
        sys.stderr.write(f"python -m gyrolib race: error: {' '.join(str(exc).split())}\n")
        return 2
    finally:
        if executor is not None:
            executor.shutdown()
    sys.stdout.write(json.dumps(report, indent=1, ensure_ascii=False) + "\n" if args.json
                     else _text(report))
    return 0
