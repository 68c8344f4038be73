"""Benchmark of paper GC's speed-claim map and shaping sweep (issue 20, item 4).

The map of the book's gc_claims chapter (σ1² and α1 each scaled over two decades on a 7 × 7
grid, both readings of P0, σ_c against the 510-s bound, analyses up to 638 s) and its shaping
sweep (six parameters × three factors, 100 s each), timed three ways in one run:

* the peer: what ``gc.speed_claim_map`` did before issue 20, with the public API — per grid
  point and reading a covariance analysis of 100 s read by ``gc.time_to_sigma``, and one of
  638 s when σ had not crossed by then; the sweep as a loop of covariance analyses;
* ours, one thread (``executor=None``);
* ours on a ``ThreadPoolExecutor`` with one worker per core.

Each of ours is checked against the peer's numbers (to 1e-12 relative) before it is
recorded.  Writes ``benchmarks/results/gc_claims.json``.

    .venv/bin/python benchmarks/bench_gc_claims.py
"""

from __future__ import annotations

import os
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import replace

import numpy as np
from _results import Recorder

from gyrolib import gc
from gyrolib.book.ledger.gc import SIGMA_C, T_BOUND

FACTORS = np.logspace(-1, 1, 7)


def peer_map(p: gc.GyrocompassParams) -> np.ndarray:
    t_max = float(round(1.25 * T_BOUND))
    t_c = np.empty((2, FACTORS.size, FACTORS.size))
    for r, reading in enumerate(("stationary", "zero")):
        for i, fy in enumerate(FACTORS):
            for j, fx in enumerate(FACTORS):
                q = replace(p, shaping_p0=reading, alpha1=p.alpha1 * fy,
                            sigma1_sq=p.sigma1_sq * fx)
                t = gc.time_to_sigma(gc.covariance_analysis(q, 100.0, store_every=10**9),
                                     "omega_gc", SIGMA_C)
                if np.isnan(t):
                    t = gc.time_to_sigma(gc.covariance_analysis(q, t_max, store_every=10**9),
                                         "omega_gc", SIGMA_C)
                t_c[r, i, j] = t
    return t_c


def peer_sweep(p: gc.GyrocompassParams) -> np.ndarray:
    out = []
    for field in gc.SHAPING_FIELDS:
        for f in (0.1, 1.0, 10.0):
            value = getattr(p, field) * f
            value = min(value, 1.0) if field in ("xi1", "xi2") else value
            res = gc.covariance_analysis(replace(p, **{field: value}), 100.0,
                                         store_every=10**9)
            out.append(res.final_std("omega_gc"))
    return np.array(out).reshape(len(gc.SHAPING_FIELDS), 3)


def timed(fn):
    t0 = time.perf_counter()
    out = fn()
    return time.perf_counter() - t0, out


def main() -> None:
    rec = Recorder("gc_claims")
    p = gc.GyrocompassParams()
    gc.time_to_level(p, SIGMA_C, 1.0)  # numba kernels loaded before timing
    cores = os.cpu_count() or 1
    t_peer, ref = timed(lambda: peer_map(p))
    kw = dict(x_field="sigma1_sq", x_factors=FACTORS, y_field="alpha1", y_factors=FACTORS)
    t_one, one = timed(lambda: gc.speed_claim_map(p, SIGMA_C, T_BOUND, **kw))
    with ThreadPoolExecutor(cores) as pool:
        t_all, every = timed(lambda: gc.speed_claim_map(p, SIGMA_C, T_BOUND, executor=pool,
                                                        **kw))
    for m in (one, every):
        np.testing.assert_allclose(m.t_c, ref, rtol=1e-12, atol=0.0, equal_nan=True)
    peer = "the pre-issue-20 loop: 100-s analysis, then 638 s if not crossed"
    rec.case("speed-claim map 7x7x2, one thread", t_one, peer=peer, peer_s=t_peer,
             note="ratio = peer/ours; same t_c to 1e-12 (chunks stopped at the first "
                  "crossing, discretization shared by the P0 readings)")
    rec.case(f"speed-claim map 7x7x2, ThreadPoolExecutor({cores})", t_all, peer=peer,
             peer_s=t_peer, note="ratio = peer/ours; same t_c to 1e-12")
    t_peer_s, ref_s = timed(lambda: peer_sweep(p))
    t_one_s, sw_one = timed(lambda: gc.shaping_sweep(p, 100.0))
    with ThreadPoolExecutor(cores) as pool:
        t_all_s, sw_all = timed(lambda: gc.shaping_sweep(p, 100.0, executor=pool))
    for sw in (sw_one, sw_all):
        np.testing.assert_allclose(sw.sigma_end, ref_s, rtol=1e-12, atol=0.0)
    peer_s = "a loop of covariance analyses"
    rec.case("shaping sweep 6x3 over 100 s, one thread", t_one_s, peer=peer_s,
             peer_s=t_peer_s, note="ratio = peer/ours; the same computation, one thread")
    rec.case(f"shaping sweep 6x3 over 100 s, ThreadPoolExecutor({cores})", t_all_s,
             peer=peer_s, peer_s=t_peer_s, note="ratio = peer/ours; same sigma to 1e-12")
    rec.write()


if __name__ == "__main__":
    main()
