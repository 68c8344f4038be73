#!/usr/bin/env python3
"""Benchmark: calibration on recorded data (issue 13).

Cases (targets from the issue; timings are never asserted in tests):

1. GC, 100 s at 1 kHz: ``gc.calibrate`` on an in-memory record after import and JIT warm-up,
   target <= 1 s.  Peer, same process: a plain-numpy filter (the library's per-step ``Φ_k``,
   ``Qd_k`` of ``gc.discretize``, scalar updates in numpy) on the first 10 s of the same
   record, scaled x10.  Also the same record with every time stamp jittered (no target).
2. GC, one hour at 1 kHz (3.6·10⁶ rows) streamed in chunks, in a fresh process: peak resident
   memory (target <= 500 MB) and cost per row against case 1.  The rows are generated chunk by
   chunk (noise about the aperiodic nominal motion), so the generator holds no record either.
3. GC end to end from the sample file (``records.read_gc`` + ``gc.calibrate``), no target.
4. RSF, 60 s at 1 kHz: ``rsf.calibrate`` on an in-memory record, target <= 0.5 s.  Peer:
   ``rsf.run_correction`` (plain numpy) on the simulated ``SensorRecord``.

    .venv/bin/python benchmarks/bench_calibrate.py [--repeat 3] [--no-hour] [--write]
"""

from __future__ import annotations

import argparse
import datetime as _dt
import json
import os
import platform
import resource
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results" / "calibrate.json"


def _best(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def peer_numpy(rec, params) -> float:
    """Plain numpy: per-step Φ_k, Qd_k of gc.discretize, predict, three scalar updates."""
    from gyrolib import gc

    n = rec.n
    disc = gc.discretize(params, n * params.dt)
    mdl = disc.model
    H, r = mdl.H, mdl.r
    beta_n = disc.beta_half[2::2]
    x = np.zeros(10)
    P = gc.initial_covariance(params)
    z = rec.measurements()
    t0 = time.perf_counter()
    for k in range(n):
        Phi, Qd = mdl.phi(k), mdl.qd(k)
        x = Phi @ x
        P = Phi @ P @ Phi.T + Qd
        zk = z[k].copy()
        zk[0] -= beta_n[k]
        for q in range(3):
            h = H[q]
            Ph = P @ h
            S = h @ Ph + r[q]
            kq = Ph / S
            x = x + kq * (zk[q] - h @ x)
            P = P - np.outer(kq, Ph)
    return time.perf_counter() - t0


def hour_child(t_end: float) -> None:
    """Run in a fresh process: stream t_end seconds, print JSON {seconds, rows, peak_mb}."""
    from gyrolib import gc

    p = gc.GyrocompassParams()
    chunk = 100_000
    n_total = round(t_end / p.dt)
    sr = np.sqrt(np.diag(gc.measurement_noise_covariance(p)))
    rng = np.random.default_rng(1)

    def chunks():
        for s in range(0, n_total, chunk):
            t = (np.arange(s, min(s + chunk, n_total)) + 1) * p.dt
            beta = gc.nominal_motion_aperiodic(p, t).beta
            z = rng.standard_normal((t.size, 3)) * sr
            yield gc.GCRecord(t=t, angle_sensor=beta + z[:, 0], inclinometer_y=z[:, 1],
                              inclinometer_z=z[:, 2])

    gc.calibrate(next(chunks()), p)   # JIT warm-up (cache load)
    base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    t0 = time.perf_counter()
    res = gc.calibrate(chunks(), p, store_every=1000)
    sec = time.perf_counter() - t0
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(json.dumps({"seconds": sec, "rows": res.rows, "peak_mb": peak,
                      "peak_before_mb": base}))


def _machine() -> dict:
    cpu = platform.processor() or ""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return {"cpu": cpu, "cores": os.cpu_count(), "python": platform.python_version(),
            "numpy": np.__version__}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--no-hour", action="store_true", help="skip the one-hour case")
    ap.add_argument("--write", action="store_true", help=f"write {RESULTS.relative_to(ROOT)}")
    ap.add_argument("--hour-child", type=float, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.hour_child:
        hour_child(args.hour_child)
        return
    load = os.getloadavg()[0]
    from gyrolib import gc, records, rsf

    p = gc.GyrocompassParams()
    results = []
    sim = gc.simulate_record(p, 100.0, seed=1)
    t0 = time.perf_counter()
    gc.calibrate(sim.record, p)
    print(f"first call (numba cache load or compile): {time.perf_counter() - t0:.2f} s")
    ours = _best(lambda: gc.calibrate(sim.record, p), args.repeat)
    short = gc.GCRecord(t=sim.record.t[:10_000], angle_sensor=sim.record.angle_sensor[:10_000],
                        inclinometer_y=sim.record.inclinometer_y[:10_000],
                        inclinometer_z=sim.record.inclinometer_z[:10_000])
    peer10 = peer_numpy(short, p)
    peer = 10 * peer10
    print(f"GC 100 s @ 1 kHz: ours {ours:.3f} s; peer (numpy, 10 s x10) {peer:.2f} s; "
          f"ratio {peer / ours:.0f}x")
    results.append({"case": "gc: 100 s at 1 kHz, in memory, after warm-up", "ours_s": ours,
                    "peer": "plain-numpy filter, same model (10 s measured, x10)",
                    "peer_s": peer, "ratio": peer / ours, "target_s": 1.0,
                    "note": f"best of {args.repeat}"})
    rng = np.random.default_rng(2)
    jit = gc.GCRecord(t=sim.record.t + rng.uniform(-1e-5, 1e-5, sim.record.n),
                      angle_sensor=sim.record.angle_sensor,
                      inclinometer_y=sim.record.inclinometer_y,
                      inclinometer_z=sim.record.inclinometer_z)
    ours_j = _best(lambda: gc.calibrate(jit, p), args.repeat)
    print(f"GC 100 s @ 1 kHz, every time stamp jittered by up to ±10 µs: {ours_j:.3f} s")
    results.append({"case": "gc: 100 s at 1 kHz, every time stamp jittered (±1 % of dt)",
                    "ours_s": ours_j, "peer": "the same record without jitter",
                    "peer_s": ours, "ratio": ours / ours_j, "target_s": None,
                    "note": "Taylor time shift per step; no target"})
    if not args.no_hour:
        out = subprocess.run([sys.executable, __file__, "--hour-child", "3600"],
                             capture_output=True, text=True, check=True)
        h = json.loads(out.stdout.strip().splitlines()[-1])
        per_row_hour = h["seconds"] / h["rows"]
        per_row_100 = ours / sim.record.n
        print(f"GC 1 h @ 1 kHz streamed: {h['seconds']:.1f} s, {h['rows']} rows, "
              f"{1e6 * per_row_hour:.2f} µs/row (100 s case {1e6 * per_row_100:.2f}); "
              f"peak RSS {h['peak_mb']:.0f} MB (after warm-up {h['peak_before_mb']:.0f} MB)")
        results.append({"case": "gc: 1 h at 1 kHz (3.6e6 rows) streamed in chunks, fresh "
                                "process", "ours_s": h["seconds"], "peer": "gc 100 s case x36",
                         "peer_s": 36 * ours, "ratio": 36 * ours / h["seconds"],
                         "target_s": None,
                         "note": (f"peak RSS {h['peak_mb']:.0f} MB (target <= 500 MB; "
                                  f"{h['peak_before_mb']:.0f} MB already after import and "
                                  "warm-up); "
                                  f"{1e6 * per_row_hour:.2f} us/row vs "
                                  f"{1e6 * per_row_100:.2f} us/row at 100 s")})
    sample = ROOT / "data" / "gc_record.csv.gz"
    e2e = _best(lambda: gc.calibrate(records.read_gc(sample), p), args.repeat)
    read = _best(lambda: records.read_gc(sample), args.repeat)
    print(f"GC sample file end to end: {e2e:.3f} s (reading alone {read:.3f} s)")
    results.append({"case": "gc: sample file read + calibrate (99 000 rows, gzip CSV)",
                    "ours_s": e2e, "peer": "reading the file alone", "peer_s": read,
                    "ratio": read / e2e, "target_s": None, "note": "no target"})
    cfg = rsf.SimulationConfig(duration=60.0, sample_rate=1000.0)
    flight = rsf.simulate_flight(cfg, seed=1)
    rrec = rsf.record_from_simulation(flight)
    rsf.calibrate(rrec, 1.0)
    ours_r = _best(lambda: rsf.calibrate(rrec, 1.0), args.repeat)
    peer_r = _best(lambda: rsf.run_correction(flight, 1.0), args.repeat)
    print(f"RSF 60 s @ 1 kHz: ours {ours_r:.4f} s; peer run_correction {peer_r:.4f} s")
    results.append({"case": "rsf: 60 s at 1 kHz, in memory", "ours_s": ours_r,
                    "peer": "rsf.run_correction on the SensorRecord (plain numpy)",
                    "peer_s": peer_r, "ratio": peer_r / ours_r, "target_s": 0.5,
                    "note": f"best of {args.repeat}"})
    doc = {"benchmark": "calibrate",
           "date": _dt.datetime.now(_dt.UTC).replace(microsecond=0).isoformat(),
           "machine": _machine(), "load": load, "results": results}
    if args.write:
        RESULTS.write_text(json.dumps(doc, indent=2) + "\n")
        print(f"wrote {RESULTS}")


if __name__ == "__main__":
    main()
