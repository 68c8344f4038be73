#!/usr/bin/env python3
"""Benchmark: Monte Carlo of paper GC, 1000 runs × 100 s, truth simulation and filter
(issue 7, target 2).

Measures the wall time of ``gyrolib.gc.monte_carlo`` (gains computed once, all runs
propagated as a batch by a numba kernel; random numbers drawn by numpy in two threads) against
a peer run in the same process: the library's plain-numpy reference path
(``gc.monte_carlo(..., method="reference")``: the same recursion vectorized over runs, one
Python step at a time), timed on the same runs over ``--peer-t-end`` seconds and scaled
linearly to ``--t-end`` (the reference path's cost is linear in the number of steps).  Target:
≤ 30 s.  Two pieces are timed separately with public calls, to say where the time goes: the
covariance analysis behind the gains (``gc.covariance_analysis``) and drawing as many standard
normals as the runs need (9 per run and step) with numpy's SFC64 generator.  Also checks that
the result is sound (NEES of ω_gc inside its 95 % band).  Writes
``benchmarks/results/gc_monte_carlo.json``.

    .venv/bin/python benchmarks/bench_gc_monte_carlo.py [--runs 1000] [--peer-t-end 10]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from _results import Recorder

from gyrolib import filtering, gc
from gyrolib.gc import GyrocompassParams


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=1000)
    ap.add_argument("--t-end", type=float, default=100.0)
    ap.add_argument("--peer-t-end", type=float, default=10.0)
    args = ap.parse_args()
    p = GyrocompassParams()
    rec = Recorder("gc_monte_carlo")
    t0 = time.perf_counter()
    gc.monte_carlo(p, 8, 0.5, seed=0)  # numba: load from the on-disk cache (or compile once)
    first = time.perf_counter() - t0
    print(f"first call (incl. numba cache load/compile): {first:.2f} s")

    t0 = time.perf_counter()
    res = gc.monte_carlo(p, args.runs, args.t_end, seed=1)
    ours = time.perf_counter() - t0
    n_steps = round(args.t_end / p.dt)
    print(f"ours: monte_carlo({args.runs} runs x {args.t_end:g} s): {ours:.2f} s")

    # where the time goes, with public calls only
    t0 = time.perf_counter()
    gc.covariance_analysis(p, args.t_end)
    t_cov = time.perf_counter() - t0
    n_normals = 9 * args.runs * n_steps
    rng = np.random.Generator(np.random.SFC64(1))
    c0 = time.process_time()
    chunk = 10**7
    for start in range(0, n_normals, chunk):
        rng.standard_normal(min(chunk, n_normals - start))
    t_rng = time.process_time() - c0

    t0 = time.perf_counter()
    gc.monte_carlo(p, args.runs, args.peer_t_end, seed=1, method="reference")
    peer_part = time.perf_counter() - t0
    peer = peer_part * args.t_end / args.peer_t_end
    print(f"peer: reference numpy path, {args.runs} runs x {args.peer_t_end:g} s: "
          f"{peer_part:.2f} s -> scaled to {args.t_end:g} s: {peer:.1f} s")
    nees = res.nees(("omega_gc",)).mean(axis=0)[1:]
    lo, hi = filtering.nees_bounds(1, args.runs)
    inside = 100 * np.mean((nees > lo) & (nees < hi))
    print(f"sanity: NEES(omega_gc) inside the 95 % band at {inside:.0f} % of stored times")
    rec.case(f"Monte Carlo, {args.runs} runs × {args.t_end:g} s, truth + filter", ours,
             peer=f"plain-numpy reference path (method='reference'), timed over "
                  f"{args.peer_t_end:g} s and scaled to {args.t_end:g} s",
             peer_s=peer, target_s=30.0,
             note=f"ratio = peer/ours; {1e9 * ours / (args.runs * n_steps):.0f} ns per run and "
                  f"step; of which: covariance analysis for the gains {t_cov:.2f} s, drawing "
                  f"the {n_normals:.1e} standard normals (numpy SFC64, one thread) "
                  f"{t_rng:.1f} s of CPU; first call in a fresh process {first:.2f} s; "
                  f"NEES of ω_gc inside its 95 % band at {inside:.0f} % of stored times")
    rec.write()


if __name__ == "__main__":
    main()
