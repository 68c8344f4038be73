#!/usr/bin/env python3
"""Diagnostic: does the angle channel carry variance the filter's model does not?

For fit-coverage seeds (``tests/support/coverage_cases.fit_record``, clean records of 100 s,
α1 × 5, σ1² × 4) the filter runs with the *true* parameters (``gc.calibrate``) and the mean
NIS of each sensor is recorded: with a model that describes the record, its expectation is 1
(SE about √(2/n)); an unmodelled variance δ in the angle channel raises the angle sensor's by
about δ/R₁₁, which is what a fitted C_as would absorb.  One JSON line per seed in ``--out``.

    nice -n 10 .venv/bin/python benchmarks/diag_fit_nis_truth.py --seeds 2000 2001 --out FILE
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import json  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from gyrolib import gc  # noqa: E402
from tests.support.coverage_cases import fit_record  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, nargs="+", required=True)
    ap.add_argument("--duration", type=float, default=100.0)
    ap.add_argument("--out", type=Path, required=True)
    args = ap.parse_args()
    for seed in args.seeds:
        sim, rec = fit_record(seed, args.duration)
        res = gc.calibrate(rec, sim.params, store_every=rec.n + 1)
        row = {"seed": seed, "nis_mean": [float(x) for x in res.nis_mean],
               "used": [int(x) for x in res.used]}
        with args.out.open("a") as fh:
            fh.write(json.dumps(row) + "\n")
        print(json.dumps(row), flush=True)


if __name__ == "__main__":
    main()
