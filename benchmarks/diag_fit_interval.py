#!/usr/bin/env python3
"""Why did a fitted C_as interval's lower side collapse onto its estimate on a record with a
gap, NaN cells and an outlier burst?  On the fitted-noise study's 100-s record of a seed
(α1 × 5, σ1² × 4) with the damage of ``tests/support/gc_faults.damage`` (a 2 s gap, 100
NaN ``inclinometer_y`` cells, 5 angle-sensor outliers of 1 mrad), α1, σ1², C_as, C_in
fitted from the paper's values:

* each interval as ``gc.profile_intervals`` gives it (the fit's outlier cells held out),
  and as the profile gave it before (the outliers counted: the fit's cells dropped), each
  side in ln against the curvature's 1.96 SE;
* 2ΔlnL along C_as's line at steps of ln C_as, three ways: the record with the outliers
  counted, the record less the fit's cells (fixed), and the record less the cells the gate
  (``gc.calibrate`` at the fit's gate) rejects at that point (re-run), with their count.

A diagnosis, not a benchmark of record; its rows go to
``benchmarks/results/diag_fit_interval.rows.jsonl`` (a row a seed: a diagnosis, not a
timed benchmark, so not one of the Performance page's result files).  About 60 CPU-s a seed.

    OPENBLAS_NUM_THREADS=1 .venv/bin/python benchmarks/diag_fit_interval.py [--seeds 101]
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from gyrolib import gc  # noqa: E402
from gyrolib.gc.logs import noise_fit as nf  # noqa: E402
from tests.support.coverage_cases import fit_record  # noqa: E402

OUT = ROOT / "benchmarks" / "results" / "diag_fit_interval.rows.jsonl"
STEPS = (-0.02, -0.01, -0.005, -0.001, 0.001, 0.005, 0.01)


def _sides(f: gc.NoiseFit) -> dict:
    return {nm: {"interval": [float(x) for x in f.interval(nm)],
                 "log_sides": [float(x) for x in f.interval_sides[i]],
                 "curvature_log_half_width": float(f.curvature_half_widths[i]),
                 "suspect": [bool(x) for x in f.suspect_sides[i]]}
            for i, nm in enumerate(f.names)}


def one(seed: int) -> dict:
    t0 = time.process_time()
    sim, rec = fit_record(seed, 100.0, damaged=True)
    fit = gc.fit_noise(rec, gc.GyrocompassParams())
    new = gc.profile_intervals(rec, fit)
    # as traced before: the likelihood at the fit and along the profile counting the outliers
    old = gc.profile_intervals(rec, dataclasses.replace(
        fit, outliers=0, outlier_cells=np.zeros((0, 2), np.int64),
        loglik=gc.innovation_log_likelihood(rec, fit.params)))
    i = fit.names.index("C_as")
    u = fit.cov_log[:, i] / fit.cov_log[i, i]
    theta = np.log(fit.values)
    clean = nf._masked(rec, fit.outlier_cells[:, 0], fit.outlier_cells[:, 1])
    ll_all = gc.innovation_log_likelihood(rec, fit.params)
    line = []
    for d in STEPS:
        q = nf._with(fit.params, fit.names, theta + d * u)
        res = gc.calibrate(rec, q, gate=1.0 - 1e-9, store_every=rec.n + 1)
        rows, sensors = nf._rejected_cells(rec, res)
        line.append({
            "step_ln_C_as": d,
            "outliers_counted": 2 * (ll_all - gc.innovation_log_likelihood(rec, q)),
            "fixed_cells": 2 * (fit.loglik - gc.innovation_log_likelihood(clean, q)),
            "gate_rerun": 2 * (fit.loglik - gc.innovation_log_likelihood(
                nf._masked(rec, rows, sensors), q)),
            "gate_rerun_cells": int(rows.size),
            "same_cells": bool(np.array_equal(np.column_stack([rows, sensors]),
                                              fit.outlier_cells))})
    truth = {"alpha1": sim.params.alpha1, "sigma1_sq": sim.params.sigma1_sq,
             "C_as": sim.params.C_as, "C_in": sim.params.C_incl_y}
    return {"seed": seed, "converged": fit.converged, "outliers": fit.outliers,
            "values": {nm: fit.value(nm) for nm in fit.names}, "truth": truth,
            "now": _sides(new), "outliers_counted": _sides(old), "c_as_line": line,
            "cpu_s": time.process_time() - t0}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, nargs="+", default=[101])
    args = ap.parse_args()
    rows = [one(s) for s in args.seeds]
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text("".join(json.dumps(r) + "\n" for r in rows))
    for r in rows:
        now, before = r["now"]["C_as"], r["outliers_counted"]["C_as"]
        print(f"seed {r['seed']}: C_as sides in ln now {now['log_sides']}, with the "
              f"outliers counted {before['log_sides']}, curvature "
              f"{now['curvature_log_half_width']:.4g}; gate re-run same cells at every step: "
              f"{all(x['same_cells'] for x in r['c_as_line'])}; max |fixed - re-run| "
              f"{max(abs(x['fixed_cells'] - x['gate_rerun']) for x in r['c_as_line']):.3g}; "
              f"{r['cpu_s']:.0f} CPU-s")
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
