#!/usr/bin/env python3
"""Benchmark: does every σ the tool prints cover the truth? (issue 34, item 7).  Statistics
over seeds, never asserted in tests (the tests run two fixed seeds of each case:
``tests/references/test_coverage_seeds.py``).  The records are made by
``tests/support/coverage_cases.py``
with every constant drawn from its prior, so the prior is part of the truth.

1. **RSF** (``--rsf``, default 100 flights of 30 s, sensors' errors drawn from their
   tolerances): z = (eps1_hat_mean − ε1/(1+ε1)) / eps1_hat_mean_std.
2. **GC** (``--gc``, default 100 records of 100 s, ψ, ω_gc, δ, γ from P(0), an angle
   offset, inclinometer biases and a gain error from the command's priors): z of ω̂_gc.
   For both: passes when the spread (SD) of z lies in [0.8, 1.25] and the 95 % Wilson
   interval of the share |z| <= 1 contains 68.27 %.
3. **Fitted noise** (``--fit``, default 100 records of ``--fit-duration`` s with α1 × 5,
   σ1² × 4; ``--fit-damaged``, default as many again, the same records with the damage of a
   real log: a gap of 2 % of the record, 100 NaN ``inclinometer_y`` cells and a burst of 5
   angle-sensor outliers of 1 mrad, ``tests/support/gc_faults.damage``): for each kind,
   clean and damaged, the share of each fitted parameter's 95 % interval
   (``gc.profile_intervals``) that holds the truth, with its 95 % Wilson interval
   (``gyrolib.stats.proportion``); passes when that contains 95 %.  Each record's row
   stores each interval's ends (``null`` where open), whether each side's search closed
   on its crossing, and whether a side is suspect (shorter than a quarter of the
   curvature's 1.96 SE in ln, both figures given); the summary counts them per kind.

Each part's CPU time per record is recorded (measured in the process that ran it); the CPU
class with the machine.  ``--workers N`` runs the records on a process pool (any
``concurrent.futures.Executor`` serves :func:`run_cases`); ``--rows FILE`` appends each
finished record to a JSON-lines file as it completes (a long run keeps what it has done, and
``--rows FILE --resume`` skips the seeds already there).

    nice -n 15 .venv/bin/python benchmarks/bench_coverage.py [--rsf 100] [--gc 100]
        [--fit 100] [--fit-damaged 100] [--fit-duration 100] [--name coverage]
        [--workers 2] [--rows FILE]
"""

from __future__ import annotations

import os

# BLAS on one thread in this process and its workers (set before numpy loads; the workers
# inherit it), as the command line, the chapters' kernels and the test workers run it: with
# OpenBLAS's threads, two workers on 2 cores spun 35-58 CPU-s a fitted record (up to 684
# under load) against 11-15 on one thread, for records of the same kind (session 13)
for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import json  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402
from concurrent.futures import Executor, ProcessPoolExecutor, as_completed  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(ROOT))
from _results import Recorder  # noqa: E402

from tests.support.coverage_cases import fit_case, gc_case, rsf_case, wilson  # noqa: E402

#: The names the fitted-noise part fits.
FIT_NAMES = ("alpha1", "sigma1_sq", "C_as", "C_in")


def z_verdict(z: np.ndarray) -> dict:
    """SD of z, the share |z| <= 1 with its Wilson interval, and the pass/fail of each."""
    n = int(z.size)
    k = int(np.sum(np.abs(z) <= 1.0))
    lo, hi = wilson(k, n)
    sd = float(np.std(z, ddof=1)) if n > 1 else float("nan")
    return {"n": n, "sd_z": sd, "sd_in_band": bool(0.8 <= sd <= 1.25),
            "share_abs_z_le_1": k / n if n else None, "wilson_95": [lo, hi],
            "contains_68": bool(lo <= 0.6827 <= hi), "max_abs_z": float(np.max(np.abs(z)))}


def fit_verdict(rows: list[dict], duration: float) -> dict:
    """The fitted-noise part's summary of one kind of record (clean or damaged): per fitted
    name the share of intervals holding the truth with its 95 % Wilson interval, the seeds
    missed, the sides not closed and the sides suspect; every record's interval (its ends,
    closed, suspect: ``sides``); and ω_gc's z spread."""
    done = [r for r in rows if r["covered"]]
    cover = {}
    for nm in FIT_NAMES:
        hits = [r["covered"][nm] for r in done if nm in r["covered"]]
        lo, hi = wilson(sum(hits), len(hits))
        ivs = [(r["seed"], r["intervals"][nm]) for r in done if nm in r.get("intervals", {})]
        cover[nm] = {"n": len(hits), "share": sum(hits) / len(hits) if hits else None,
                     "wilson_95": [lo, hi], "contains_95": bool(lo <= 0.95 <= hi),
                     "missed_seeds": [r["seed"] for r in done
                                      if nm in r["covered"] and not r["covered"][nm]],
                     "sides_not_closed": sum(2 - sum(iv["closed"]) for _, iv in ivs),
                     "sides_suspect": sum(sum(iv["suspect"]) for _, iv in ivs),
                     "suspect_seeds": [s for s, iv in ivs if any(iv["suspect"])]}
    z = np.array([r["z"] for r in done])
    return {"records": len(rows), "duration_s": duration,
            "not_converged": sum(not r["converged"] for r in rows),
            "no_interval": sum(not r["covered"] for r in rows),
            "coverage": cover, "omega_gc": z_verdict(z) if z.size > 1 else None,
            "sides": [{"seed": r["seed"], "name": nm, **iv} for r in done
                      for nm, iv in r.get("intervals", {}).items()]}


def _fit_note(v: dict) -> str:
    return ("95 % interval coverage: " + ", ".join(
        f"{nm} {100 * c['share']:.0f} % [{100 * c['wilson_95'][0]:.0f}, "
        f"{100 * c['wilson_95'][1]:.0f}]" for nm, c in v["coverage"].items()
        if c["share"] is not None)
        + "; sides suspect " + ", ".join(f"{nm} {c['sides_suspect']}"
                                         for nm, c in v["coverage"].items())
        + "; not closed " + ", ".join(f"{nm} {c['sides_not_closed']}"
                                      for nm, c in v["coverage"].items())
        + f"; not converged {v['not_converged']}, without intervals {v['no_interval']}; "
          "CPU s per record")


def _timed(case: Callable[..., dict], seed: int, *args, **kwargs) -> dict:
    """``case(seed, *args, **kwargs)`` with the seed and the CPU seconds of the process that
    ran it."""
    t0 = time.process_time()
    row = case(seed, *args, **kwargs)
    return {**row, "seed": seed, "cpu_s": time.process_time() - t0}


def run_cases(part: str, case: Callable[..., dict], seeds: list[int], *args,
              executor: Executor | None = None, rows_file: Path | None = None,
              resume: bool = False, case_kwargs: dict | None = None) -> list[dict]:
    """``case(seed, *args, **case_kwargs)`` for every seed, on ``executor`` (``None``: in
    this process), in seed order; each finished record is appended to ``rows_file`` (JSON
    lines, with its ``part``) as it completes, and with ``resume`` the seeds already there
    are not run."""
    kw = case_kwargs or {}
    done: dict[int, dict] = {}
    if rows_file is not None and resume and rows_file.is_file():
        for line in rows_file.read_text().splitlines():
            r = json.loads(line)
            if r.get("part") == part and r["seed"] in seeds:
                done[r["seed"]] = r

    def keep(r: dict) -> None:
        done[r["seed"]] = r
        if rows_file is not None:
            with rows_file.open("a") as fh:
                fh.write(json.dumps({"part": part, **r}) + "\n")

    todo = [s for s in seeds if s not in done]
    if executor is None:
        for s in todo:
            keep(_timed(case, s, *args, **kw))
    else:
        for fut in as_completed([executor.submit(_timed, case, s, *args, **kw)
                                 for s in todo]):
            keep(fut.result())
    return [done[s] for s in seeds]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rsf", type=int, default=100)
    ap.add_argument("--gc", type=int, default=100)
    ap.add_argument("--fit", type=int, default=100)
    ap.add_argument("--fit-damaged", type=int, default=None,
                    help="damaged records of the fitted-noise part (default: as --fit)")
    ap.add_argument("--fit-duration", type=float, default=100.0)
    ap.add_argument("--name", default="coverage",
                    help="results file benchmarks/results/NAME.json (a part run alone)")
    ap.add_argument("--workers", type=int, default=1,
                    help="processes (a ProcessPoolExecutor when > 1)")
    ap.add_argument("--rows", type=Path, default=None,
                    help="append each finished record to this JSON-lines file")
    ap.add_argument("--resume", action="store_true",
                    help="with --rows: skip the seeds already in the file")
    args = ap.parse_args()
    executor = ProcessPoolExecutor(args.workers) if args.workers > 1 else None
    run = {"executor": executor, "rows_file": args.rows, "resume": args.resume}
    rec = Recorder(args.name)
    stats: dict = {}
    for name, n, case in (("rsf", args.rsf, rsf_case), ("gc", args.gc, gc_case)):
        if n <= 0:
            continue
        rows = run_cases(name, case, [1000 + s for s in range(n)], **run)
        cpu = sum(r["cpu_s"] for r in rows) / n
        z = np.array([r["z"] for r in rows])
        v = z_verdict(z)
        v["refused"] = int(sum(not r["valid"] for r in rows))
        stats[name] = v
        rec.case(f"{name}: {n} records, z spread and 1-sigma coverage", cpu,
                 note=f"SD(z) {v['sd_z']:.3f} ({'in' if v['sd_in_band'] else 'OUTSIDE'} "
                      f"[0.8, 1.25]); |z| <= 1: {100 * v['share_abs_z_le_1']:.1f} %, Wilson "
                      f"[{100 * v['wilson_95'][0]:.1f}, {100 * v['wilson_95'][1]:.1f}] % "
                      f"({'contains' if v['contains_68'] else 'MISSES'} 68 %); refused "
                      f"{v['refused']}; CPU s per record")
    n_damaged = args.fit if args.fit_damaged is None else args.fit_damaged
    for part, n, damaged in (("fit", args.fit, False), ("fit_damaged", n_damaged, True)):
        if n <= 0:
            continue
        rows = run_cases(part, fit_case, [2000 + s for s in range(n)], args.fit_duration,
                         case_kwargs={"damaged": damaged}, **run)
        cpu = sum(r["cpu_s"] for r in rows) / n
        stats[part] = fit_verdict(rows, args.fit_duration)
        rec.case(f"{part}: {n} {'damaged' if damaged else 'clean'} records of "
                 f"{args.fit_duration:g} s, alpha1 x 5, sigma1^2 x 4", cpu,
                 note=_fit_note(stats[part]))
    rec.doc["stats"] = stats
    rec.write()
    print(json.dumps(stats, indent=1))


if __name__ == "__main__":
    main()
