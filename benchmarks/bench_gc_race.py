#!/usr/bin/env python3
"""Benchmark: the race of paper GC's method against the rate-sensor method of its ref. [3]
(issue 17, ``gc.race`` and the sweeps of the chapter "Racing the method it replaces").

Cases (best of ``--repeat`` wall times, after one warm-up call that loads numba's cache):

* the classical estimator's σ over two 300-s windows by doubling
  (``RateSensorModel.classical_sigma``) against a peer in the same process: the same
  augmented covariance stepped sample by sample in numpy (σ agreeing to 10⁻⁸, relative;
  the turn and settling a whole number of samples at the defaults);
* ``gc.race()`` at the defaults (GC's 100-s covariance analysis, the classical search, the
  optimal Kalman run, the curves); target 3 s;
* ``RaceResult.conditions()`` (four bisections); target 5 s;
* the chapter's sweeps: the T_rot × T_settle grid (24 cases), the rate-noise sweep (5 cases),
  the σ1² × vibration-frame sweep (6 cases, GC recomputed for each σ1²), and
  ``procedure_for_time`` twice; target 30 s for all of them;
* the Monte Carlo check, 2 × 400 runs of the truth; target 5 s.

The chapter as a whole must execute in under 60 s on 2 cores.  Writes
``benchmarks/results/gc_race.json``.

    .venv/bin/python benchmarks/bench_gc_race.py [--repeat 3]
"""

from __future__ import annotations

import argparse
import time
from dataclasses import replace

import numpy as np
from _results import Recorder

from gyrolib import gc


def best(fn, repeat: int) -> tuple[float, object]:
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), out


def peer_classical(model: gc.RateSensorModel, n1: int, n2: int) -> float:
    """The classical σ by stepping the augmented covariance ``[x; Σr1, Σz1, Σr2, Σz2]`` one
    sample at a time, from the model's public matrices (a plain second implementation)."""
    p, proc = model.params, model.procedure
    n = model.P0.shape[0]
    na = n + 4
    P = np.zeros((na, na))
    P[:n, :n] = model.P0

    def window(P: np.ndarray, H: np.ndarray, ir: int, iz: int, steps: int) -> np.ndarray:
        for _ in range(steps):
            T = np.zeros((na, na))          # y_new = M y + noise, M built explicitly
            T[:n, :n] = model.Phi
            T[n:, n:] = np.eye(4)
            T[ir, :n] = H[0] @ model.Phi
            T[iz, :n] = H[2] @ model.Phi
            S = np.zeros((na, n))
            S[:n] = np.eye(n)
            S[ir], S[iz] = H[0], H[2]
            Pn = T @ P @ T.T + S @ model.Qd @ S.T
            Pn[ir, ir] += model.r[0]
            Pn[iz, iz] += model.r[2]
            P = Pn
        return P

    P = window(P, model.H1, n, n + 1, n1)
    # the turn and the settling: the shaping filters propagate sample by sample
    k = round(proc.overhead / proc.sample_dt)
    A = np.eye(na)
    A[:n, :n] = model.Phi
    Qg = np.zeros((na, na))
    Qg[:n, :n] = model.Qd
    for _ in range(k):
        P = A @ P @ A.T + Qg
    P = window(P, model.H2, n + 2, n + 3, n2)
    c = np.zeros(na)
    c[0] = -1.0
    c[n], c[n + 2] = 0.5 / n1, 0.5 / n2
    c[n + 1], c[n + 3] = (-p.Omega_v / (2 * p.g * n1), -p.Omega_v / (2 * p.g * n2))
    return float(np.sqrt(c @ P @ c))


def chapter_sweeps() -> None:
    p, proc = gc.GyrocompassParams(), gc.RateSensorProcedure()
    gc.race_sweep(p, proc, cases=[{"T_rot": a, "T_settle": b}
                                  for a in (0.0, 10.0, 30.0, 60.0)
                                  for b in (0.0, 10.0, 30.0, 60.0, 120.0, 300.0)])
    gc.race_sweep(p, proc, cases=[{"rate_noise": f * proc.rate_noise}
                                  for f in (0.1, 1.0, 10.0, 100.0, 1000.0)])
    gc.race_sweep(p, proc, cases=[{"sigma1_sq": f * p.sigma1_sq, "vibration_frame": fr}
                                  for fr in gc.VIBRATION_FRAMES for f in (0.1, 1.0, 10.0)])
    gc.procedure_for_time(p, proc, "rate_noise", 1200.0)
    gc.procedure_for_time(p, proc, "overhead", 1200.0)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    rec = Recorder("gc_race")
    t0 = time.perf_counter()
    race = gc.race()          # warm-up: numba cache load (or compile)
    print(f"first call of gc.race(): {time.perf_counter() - t0:.2f} s")

    model = gc.rate_sensor_model()
    n = round(300.0 / model.procedure.sample_dt)
    ours, s_ours = best(lambda: model.classical_sigma(300.0, 300.0), args.repeat)
    peer, s_peer = best(lambda: peer_classical(model, n, n), 1)
    assert abs(s_ours / s_peer - 1) < 1e-8, (s_ours, s_peer)
    rec.case("classical sigma, 2 x 300 s windows (doubling)", ours,
             peer="augmented covariance stepped per sample (numpy)", peer_s=peer,
             note=f"sigma agrees to {abs(s_ours / s_peer - 1):.1e} (relative)")

    t, race = best(gc.race, args.repeat)
    rec.case("gc.race() at the defaults", t, target_s=3.0,
             note=f"t_c: GC {race.t_c_gc:.1f} s, classical {race.t_c_rate_sensor:.1f} s, "
                  f"optimal {race.t_c_rate_sensor_optimal:.1f} s")
    t, _ = best(race.conditions, args.repeat)
    rec.case("RaceResult.conditions() (four bisections)", t, target_s=5.0)
    t, _ = best(chapter_sweeps, 1)
    rec.case("the chapter's sweeps (35 races, 2 procedure_for_time)", t, target_s=30.0)
    p = gc.GyrocompassParams()

    def mc() -> None:
        for tp in (None, replace(p, sigma1_sq=9 * p.sigma1_sq)):
            gc.rate_sensor_monte_carlo(p, t1=race.t1, t2=race.t2, n_runs=400, seed=2024,
                                       truth_params=tp)

    t, _ = best(mc, 1)
    rec.case("Monte Carlo check, 2 x 400 runs", t, target_s=5.0)
    rec.write()


if __name__ == "__main__":
    main()
