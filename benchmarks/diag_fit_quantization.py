#!/usr/bin/env python3
"""Diagnostic: does the written angle column's resolution bias the fitted C_as?

For fit-coverage seeds (``tests/support/coverage_cases.fit_record``, clean records of 100 s)
the noise is fitted (``gc.fit_noise``, the coverage benchmark's four names) on the record as
simulated, in memory (float64); on the same record written with ``records.write_csv``'s
default format and read back; and, with ``--lsb ARCSEC``, on its angle column rounded to
that step.  One JSON line per seed and variant in ``--out``.

    nice -n 10 .venv/bin/python benchmarks/diag_fit_quantization.py --seeds 2000 2001
        [--lsb 1.0] [--lsb-seeds 2000] --out FILE
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import json  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from gyrolib import gc, records  # noqa: E402
from gyrolib.units import ARCSEC_PAPER  # noqa: E402
from tests.support.coverage_cases import fit_record  # noqa: E402

NAMES = ("alpha1", "sigma1_sq", "C_as", "C_in")


def _fit(rec: gc.GCRecord) -> dict:
    t0 = time.process_time()
    f = gc.fit_noise(rec, gc.GyrocompassParams(), fit=NAMES)
    return {"C_as": f.value("C_as"), "C_as_se": f.std_error("C_as"),
            "converged": bool(f.converged), "cpu_s": time.process_time() - t0}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, nargs="+", required=True)
    ap.add_argument("--lsb", type=float, default=None, help="angle LSB, arcsec")
    ap.add_argument("--lsb-seeds", type=int, nargs="*", default=None)
    ap.add_argument("--out", type=Path, required=True)
    args = ap.parse_args()
    for seed in args.seeds:
        sim, rec = fit_record(seed, 100.0)
        variants = {"memory": rec}
        with tempfile.TemporaryDirectory() as tmp:
            path = records.write_csv(Path(tmp) / "r.csv", {
                "t": rec.t, "angle_sensor": rec.angle_sensor,
                "inclinometer_y": rec.inclinometer_y, "inclinometer_z": rec.inclinometer_z},
                comments=["latitude_deg: 53.9"])
            written = records.read_gc(path, check=False)
        variants["written"] = written
        diff = np.max(np.abs(written.angle_sensor - rec.angle_sensor))
        if args.lsb and (args.lsb_seeds is None or seed in args.lsb_seeds):
            q = args.lsb * ARCSEC_PAPER
            variants[f"lsb_{args.lsb:g}arcsec"] = gc.GCRecord(
                t=rec.t, angle_sensor=np.round(rec.angle_sensor / q) * q,
                inclinometer_y=rec.inclinometer_y, inclinometer_z=rec.inclinometer_z)
        for name, r in variants.items():
            row = {"seed": seed, "variant": name, "truth": sim.params.C_as,
                   "max_abs_angle_diff_written_rad": float(diff), **_fit(r)}
            with args.out.open("a") as fh:
                fh.write(json.dumps(row) + "\n")
            print(json.dumps(row), flush=True)


if __name__ == "__main__":
    main()
