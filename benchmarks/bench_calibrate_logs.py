#!/usr/bin/env python3
"""Benchmark: calibrating real logs safely (issue 18).  Timings are never asserted in tests.

Cases:

1. **Batch**: ``python -m gyrolib calibrate gc FILE... --summary`` on ``--files`` copies of
   the sample record (100 s at 1 kHz each), in a fresh process, with ``--workers 2``.  Peer:
   the same command with ``--workers 1`` (one file after the other), same machine, same run.
   On two cores the ideal ratio is 2; process start-up (imports, the JIT cache) and the
   reading of the gzip CSV, which runs in the workers too, set how close it gets.
2. **Checks at the door**: ``records.check_gc`` on the sample record (what every read adds).
   Peer: reading the file (``records.read_gc(check=False)``).
3. **Allan deviation**: ``gc.allan_deviation`` on the sample record (three series, octave
   τ, Greenhall confidence intervals).  No peer, no target.
4. **Convention study**: ``gc.convention_study`` on 2 seeds × 100 s (one simulated record and
   two calibrations per seed).  Peer: ``gc.simulate_record`` alone for the same seeds (the
   truth integration dominates).

    nice -n 10 .venv/bin/python benchmarks/bench_calibrate_logs.py [--files 4] [--repeat 2]
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _results import Recorder

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "data" / "gc_record.csv.gz"


def _best(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def _batch(files: list[Path], workers: int, out: Path) -> None:
    proc = subprocess.run([sys.executable, "-m", "gyrolib", "calibrate", "gc", *map(str, files),
                           "--summary", str(out), "--workers", str(workers)],
                          capture_output=True, text=True, cwd=ROOT, check=False)
    if proc.returncode != 0:
        raise SystemExit(f"batch failed ({proc.returncode}): {proc.stderr}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--files", type=int, default=4)
    ap.add_argument("--repeat", type=int, default=2)
    args = ap.parse_args()
    from gyrolib import gc, records

    rec = Recorder("calibrate_logs")
    with tempfile.TemporaryDirectory() as tmp:
        files = []
        for k in range(args.files):
            files.append(Path(tmp) / f"log{k}.csv.gz")
            shutil.copy(SAMPLE, files[-1])
        _batch(files[:1], 1, Path(tmp) / "warm.csv")          # the JIT cache, once
        serial = _best(lambda: _batch(files, 1, Path(tmp) / "s1.csv"), args.repeat)
        parallel = _best(lambda: _batch(files, 2, Path(tmp) / "s2.csv"), args.repeat)
        rec.case(f"batch: {args.files} files x 100 s at 1 kHz, --workers 2, fresh process",
                 parallel, peer="--workers 1", peer_s=serial,
                 note=f"{parallel / args.files:.3g} s per file with 2 workers; best of "
                      f"{args.repeat}")

    record = records.read_gc(SAMPLE, check=False)
    read = _best(lambda: records.read_gc(SAMPLE, check=False), args.repeat)
    check = _best(lambda: records.check_gc(record, label=str(SAMPLE)), args.repeat)
    rec.case("checks at the door: records.check_gc on the sample record (99 000 rows)", check,
             peer="reading the file (read_gc, check=False)", peer_s=read,
             note=f"the checks add {100 * check / read:.2g} % to a read")

    gc.allan_deviation(record)
    allan = _best(lambda: gc.allan_deviation(record), args.repeat)
    rec.case("gc.allan_deviation on the sample record (3 series, octave taus)", allan,
             note="no peer, no target")

    seeds = [1, 2]
    study = _best(lambda: gc.convention_study(t_end=100.0, seeds=seeds), 1)
    sims = _best(lambda: [gc.simulate_record(gc.GyrocompassParams(), 100.0, s)
                          for s in seeds], 1)
    rec.case("gc.convention_study: 2 seeds x 100 s (simulate + 2 calibrations each)", study,
             peer="gc.simulate_record alone, same seeds", peer_s=sims,
             note="ratio < 1: the study costs its simulations plus the calibrations")
    rec.write()


if __name__ == "__main__":
    main()
