#!/usr/bin/env python3
"""Benchmark: paper GC's Sobol' study (``gc.sensitivity``) serial against 2 local Dask
workers (issue 19, target ≥ 1.7× on 2 cores).

Measures, in one process on one machine: the cost of one model run (one 100-s covariance
analysis and t_c, ``gc.sensitivity_outputs``, best of 3); a small study (``--n`` base points,
first-order and total indices: ``n (D + 2)`` runs) in this process (the peer), on a
``dask.distributed.LocalCluster`` of 1 worker process (what handing chunks to a worker
costs: its excess over the serial time) and of 2 worker processes (``Client.get_executor()``),
serial and Dask runs alternating ``--repeat`` times, best of each.  The clusters are started
and warmed up (numba's cached kernels loaded in each worker) before the clock starts.
Checks that the three give the same indices (1e-12), and projects the
wall time of a full study from the per-run cost.  Writes
``benchmarks/results/sensitivity.json``.

Every process runs its linear algebra on one thread (``OMP_NUM_THREADS=1`` and the like, set
here before numpy loads, as Dask sets them in its workers), so that the serial peer and a
worker do the same work; the projection uses the serial study's time per run.  On a shared
machine the ratio says as much about the other processes as about the scaling: the results
file records the load average.

    .venv/bin/python benchmarks/bench_sensitivity.py [--n 8] [--repeat 2] [--full-n 4096]
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import logging  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
from _results import Recorder, load  # noqa: E402

from gyrolib import gc  # noqa: E402


def study(n: int, executor=None):
    return gc.sensitivity(n, seed=0, executor=executor, second_order=False)


def main() -> None:
    from dask.distributed import Client, LocalCluster

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=8)
    ap.add_argument("--repeat", type=int, default=2,
                    help="timed pairs (serial, Dask) per cluster size; best of each")
    ap.add_argument("--full-n", type=int, default=4096,
                    help="base sample size of the full study to project (default 4096)")
    args = ap.parse_args()
    rec = Recorder("sensitivity")
    p = gc.GyrocompassParams()
    gc.sensitivity_outputs(p)                       # numba cache load
    per_run = min(_timed(lambda: gc.sensitivity_outputs(p)) for _ in range(3))
    c0 = time.process_time()
    gc.sensitivity_outputs(p)
    cpu_run = time.process_time() - c0
    dims = len(gc.sensitivity_inputs(p))            # the study's D (13 since issue 33)
    runs = args.n * (dims + 2)                      # first-order and total indices
    print(f"one model run at the reference: {per_run:.3f} s wall (best of 3), {cpu_run:.3f} s "
          f"CPU; study: {runs} runs over D = {dims} inputs; load {load()}")

    serial = study(args.n)                          # the reference values
    timings: dict[int, float] = {}
    serial_times: list[float] = []
    for workers in (1, 2):
        with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                          dashboard_address=":0", silence_logs=logging.ERROR) as cluster, \
                Client(cluster) as client:
            ex = client.get_executor()
            gc.sensitivity(2, seed=1, executor=ex, t_end=1.0, t_max=1.0, chunk_size=2)  # warm
            times = []
            for _ in range(args.repeat):        # alternate, so that a change of load hits both
                t0 = time.perf_counter()
                study(args.n)
                serial_times.append(time.perf_counter() - t0)
                t0 = time.perf_counter()
                res = study(args.n, ex)
                times.append(time.perf_counter() - t0)
            timings[workers] = min(times)
        same = np.allclose(res.values, serial.values, rtol=1e-12, atol=0.0)
        print(f"{workers} Dask worker(s): best {timings[workers]:.1f} s of {len(times)}; "
              f"serial best so far {min(serial_times):.1f} s; same values: {same}")
        if not same:
            raise SystemExit("the Dask run differs from the serial run")
    t_serial = min(serial_times)
    overhead = timings[1] / t_serial - 1.0
    print(f"speed-up on 2 workers: {t_serial / timings[2]:.2f}x; 1-worker overhead "
          f"{100 * overhead:+.1f} %")
    full_runs = args.full_n * (dims + 2)
    per_run_serial = t_serial / runs
    rec.case(f"GC Sobol' study, n = {args.n} ({runs} covariance analyses of 100 s), "
             "2 local Dask worker processes", timings[2],
             peer="the same study in this process (executor=None)", peer_s=t_serial,
             note=f"ratio = serial/2 workers = speed-up (target >= 1.7); one model run at "
                  f"the reference {per_run:.3f} s wall (best of 3), {cpu_run:.3f} s CPU (t_c "
                  f"within the 100-s analysis); a sampled run averages "
                  f"{t_serial / runs:.3f} s (where t_c is not reached by 100 s, "
                  f"time_to_level runs on to 510 s); 1 Dask worker "
                  f"{timings[1]:.1f} s, i.e. "
                  f"{100 * overhead:+.1f} % over serial (scheduling and transfer); projected "
                  f"full study n = {args.full_n} ({full_runs} runs): "
                  f"{full_runs * per_run_serial / 3600:.1f} h on one core, "
                  f"{full_runs * per_run_serial / 3600 / 2:.1f} h on 2, "
                  f"{full_runs * per_run_serial / 60 / 32:.0f} min on 32 (at the serial "
                  f"study's {per_run_serial:.3f} s a run); load "
                  f"{load()} at the end (shared machine)")
    rec.write()


def _timed(fn) -> float:
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


if __name__ == "__main__":
    main()
