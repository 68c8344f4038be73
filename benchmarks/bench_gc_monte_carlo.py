#!/usr/bin/env python3
"""Benchmark: Monte Carlo of paper GC, 1000 runs × 100 s, truth simulation and filter
(issue 7, target 2).

Ours: ``gyrolib.gc.monte_carlo`` (gains computed once, all runs propagated as a
batch by a numba kernel parallel over blocks of runs; random numbers drawn by numpy in two
threads).  Peer, in the same process: the plain-numpy reference path
(``method="reference"``: the same recursion vectorized over runs, one Python step at a time),
timed on the same runs over ``--peer-t-end`` seconds and scaled linearly to ``--t-end``.  The
break-down of our time (covariance + gains, random numbers, kernel) is printed as well.

    .venv/bin/python benchmarks/bench_gc_monte_carlo.py [--runs 1000] [--peer-t-end 10]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from gyrolib import filtering, gc
from gyrolib.gc import GyrocompassParams
from gyrolib.gc import montecarlo as montecarlo_mod


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=1000)
    ap.add_argument("--t-end", type=float, default=100.0)
    ap.add_argument("--peer-t-end", type=float, default=10.0)
    args = ap.parse_args()
    p = GyrocompassParams()
    t0 = time.perf_counter()
    gc.monte_carlo(p, 8, 0.5, seed=0)  # numba: load from the on-disk cache (or compile once)
    print(f"first call (incl. numba cache load/compile): {time.perf_counter() - t0:.2f} s")

    t0 = time.perf_counter()
    res = gc.monte_carlo(p, args.runs, args.t_end, seed=1)
    ours = time.perf_counter() - t0
    n_rs = args.runs * round(args.t_end / p.dt)
    print(f"ours: monte_carlo({args.runs} runs x {args.t_end:g} s): {ours:.2f} s "
          f"({1e9 * ours / n_rs:.0f} ns per run-step; target <= 30 s)")

    # where the time goes: the same pieces timed separately
    t0 = time.perf_counter()
    gc.covariance_analysis(p, args.t_end)
    t_cov = time.perf_counter() - t0
    rngs = montecarlo_mod._block_rngs(np.random.default_rng(1), args.runs)
    n_steps = round(args.t_end / p.dt)
    c0 = time.process_time()
    for rng in rngs:
        for _k0 in range(0, n_steps, montecarlo_mod._CHUNK):
            rng.standard_normal((montecarlo_mod._CHUNK, 9, montecarlo_mod._RUN_BLOCK))
    t_rng = time.process_time() - c0
    disc = gc.discretize(p, args.t_end)
    X0 = np.zeros((args.runs, 10))
    gains = np.zeros((n_steps, 3, 10))
    t0 = time.perf_counter()
    c0 = time.process_time()
    montecarlo_mod._run_batch(disc, X0, None, gains, 100, "fast")  # no random numbers: kernel alone
    t_kern, c_kern = time.perf_counter() - t0, time.process_time() - c0
    print(f"  break-down (CPU seconds): covariance+gains {t_cov:.2f} s wall; random numbers "
          f"{t_rng:.2f} s CPU ({args.runs * 9 * n_steps:.1e} normals, "
          f"{1e9 * t_rng / (args.runs * 9 * n_steps):.0f} ns each); kernel alone "
          f"{c_kern:.2f} s CPU / {t_kern:.2f} s wall")

    t0 = time.perf_counter()
    gc.monte_carlo(p, args.runs, args.peer_t_end, seed=1, method="reference")
    peer_part = time.perf_counter() - t0
    peer = peer_part * args.t_end / args.peer_t_end
    print(f"peer: reference numpy path, {args.runs} runs x {args.peer_t_end:g} s: "
          f"{peer_part:.2f} s -> scaled to {args.t_end:g} s: {peer:.1f} s")
    print(f"ratio peer/ours: {peer / ours:.1f}x")
    nees = res.nees(("omega_gc",)).mean(axis=0)[1:]
    lo, hi = filtering.nees_bounds(1, args.runs)
    inside = 100 * np.mean((nees > lo) & (nees < hi))
    print(f"sanity: NEES(omega_gc) inside the 95 % band at {inside:.0f} % of stored times")


if __name__ == "__main__":
    main()
