#!/usr/bin/env python3
"""Benchmark: the race of paper GC's method against the rate-sensor method of its ref. [3]
(issue 17, ``gc.race`` and the sweeps of the chapter "Racing the method it replaces").

Cases (best of ``--repeat`` wall times, after one warm-up call that loads numba's cache; the
memos of the race, which keep its times per inputs, are emptied before each timed call):

* the classical estimator's σ over two 300-s windows by doubling
  (``RateSensorModel.classical_sigma``, a fresh model each call: the model keeps its power
  sums and σ) against a peer in the same process: the same
  augmented covariance stepped sample by sample in numpy (σ agreeing to 10⁻⁸, relative;
  the turn and settling a whole number of samples at the defaults);
* ``gc.race()`` at the defaults (GC's 100-s covariance analysis, the classical search, the
  optimal Kalman run, the curves); target 3 s;
* ``RaceResult.conditions()`` (four bisections); target 5 s;
* ``gc.race()``, ``RaceResult.conditions()`` and one ``items(params)`` of the ledger's GC
  part against the previous implementation (commit :data:`PREVIOUS`, before issue 29's
  per-model caches and early stop, exported from git into a temporary folder): each in a
  fresh process (after a warm-up call), ours and the previous alternating, best of
  ``--repeat`` (``items`` best of 2); the two trees' race times and conditions compared
  (they must agree to 10⁻¹² relative);
* the chapter's sweeps: the T_rot × T_settle grid (24 cases), the rate-noise sweep (5 cases),
  the σ1² × vibration-frame sweep (6 cases, GC recomputed for each σ1²), and
  ``procedure_for_time`` twice; target 30 s for all of them;
* the Monte Carlo check, 2 × 400 runs of the truth; target 5 s.

The chapter as a whole must execute in under 60 s on 2 cores.  Writes
``benchmarks/results/gc_race.json``.

``--only-cli`` times the command a user runs instead, each case a whole process (wall time,
and the CPU seconds of the process in the note), and writes
``benchmarks/results/gc_race_cli.json``:

* ``race --params FILE`` with its thresholds (the map around the file's parameters), for a
  file near the paper's parameters and one far from them; target 15 s on a 2-core AVX2
  machine;
* ``race`` at the defaults (the stored map, checked by its fingerprint points);
* ``race --no-thresholds`` at the defaults with numba's cache warm, and cold (an empty
  ``NUMBA_CACHE_DIR``: every kernel compiled); target 5 s.

    .venv/bin/python benchmarks/bench_gc_race.py [--repeat 3] [--only-cli]
"""

from __future__ import annotations

import argparse
import json
import math
import os
import resource
import subprocess
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import numpy as np
from _results import Recorder, previous_tree

from gyrolib import gc


def forget_memos() -> None:
    """Empty every memo of the loaded gyrolib modules (``functools`` caches: the race keeps
    its times per inputs, issue 36), so that each timed call computes: a memo's hit, timed,
    is not the race's time (this benchmark's conditions case timed one before)."""
    for name, module in list(sys.modules.items()):
        if name == "gyrolib" or name.startswith("gyrolib."):
            for obj in list(vars(module).values()):
                if callable(getattr(obj, "cache_clear", None)):
                    obj.cache_clear()


def best(fn, repeat: int) -> tuple[float, object]:
    """The best wall time of ``repeat`` calls, each with the memos emptied first."""
    times, out = [], None
    for _ in range(repeat):
        forget_memos()
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


ROOT = Path(__file__).resolve().parents[1]

#: The commit whose race is the peer of the conditions case: before issue 29's per-model
#: caches of the rate-sensor model and the early stop of the optimal search.
PREVIOUS = "a0ae90f"

#: What the child process reports of the race (the numbers both trees must agree on).
_COMPARED = ("t_c_gc", "t_c_rate_sensor", "t_c_rate_sensor_optimal", "t1", "t2", "t1_optimal")
_COMPARED_COND = ("t_needed", "worst_t_gc", "worst_t_classical", "worst_t_optimal",
                  "loop_bandwidth_min", "overhead_min", "rate_noise_min", "kappa_max")


def child(repeat: int) -> None:
    """In a fresh process on the tree of ``PYTHONPATH``: the times of ``gc.race()``,
    ``conditions()`` and one ledger ``items(params)``, and the race's numbers, as JSON."""
    from gyrolib.book.ledger import gc as ledger_gc
    gc.race().conditions()            # warm-up: numba's cache, imports
    t_race, race = best(gc.race, repeat)
    t_cond, cond = best(race.conditions, repeat)
    t_items, _ = best(lambda: ledger_gc.items(gc.GyrocompassParams()), min(repeat, 2))
    values = {k: getattr(race, k) for k in _COMPARED}
    values.update({f"conditions.{k}": getattr(cond, k) for k in _COMPARED_COND})
    print(json.dumps({"gyrolib": gc.__file__, "race_s": t_race, "conditions_s": t_cond,
                      "items_s": t_items, "values": values}))


def run_child(tree: Path, repeat: int) -> dict:
    env = dict(os.environ, PYTHONPATH=str(tree), OPENBLAS_NUM_THREADS="1")
    out = subprocess.run([sys.executable, __file__, "--child", "--repeat", str(repeat)],
                         capture_output=True, text=True, cwd=tree, env=env, check=True)
    res = json.loads(out.stdout.strip().splitlines()[-1])
    assert res["gyrolib"].startswith(str(tree)), (res["gyrolib"], tree)
    return res


def against_previous(rec: Recorder, repeat: int) -> None:
    """``gc.race()``, ``conditions()``, ledger ``items`` against :data:`PREVIOUS`."""
    with tempfile.TemporaryDirectory() as tmp:
        prev = previous_tree(Path(tmp), PREVIOUS)
        if prev is None:
            sys.exit(f"the previous race (commit {PREVIOUS}) cannot be exported from git")
        runs = {"ours": [], "previous": []}
        for _ in range(2):                # alternating, each in a fresh process
            runs["ours"].append(run_child(ROOT, repeat))
            runs["previous"].append(run_child(prev, repeat))
    ours, old = runs["ours"][-1]["values"], runs["previous"][-1]["values"]
    worst = 0.0
    for k, a in ours.items():
        b = old[k]
        if not (a == b or (math.isnan(a) and math.isnan(b))):
            worst = max(worst, abs(a - b) / abs(b))
    assert worst <= 1e-12, (worst, ours, old)
    agree = "identical" if worst == 0.0 else f"agree to {worst:.1e} (relative)"
    for key, case, target in (
            ("race_s", "gc.race() at the defaults, against the previous race", 3.0),
            ("conditions_s", "RaceResult.conditions(), against the previous race", 5.0),
            ("items_s", "ledger gc items(params), against the previous race", None)):
        t_ours = min(r[key] for r in runs["ours"])
        t_old = min(r[key] for r in runs["previous"])
        rec.case(case, t_ours, peer=f"commit {PREVIOUS} (before the per-model caches and "
                 "the early stop), fresh process", peer_s=t_old, target_s=target,
                 note=f"{len(ours)} race and conditions numbers {agree}; best of "
                      f"{2 * (repeat if key != 'items_s' else min(repeat, 2))} calls in 2 "
                      "alternating processes each, OPENBLAS_NUM_THREADS=1")


#: The parameter files of ``race --params``: near the paper's values (twice its vibration
#: σ1²), and far from them (ten times the angle sensor's noise, a slow rebalance loop, a
#: short turn and settling, a tenth of the torquer noise).
CLI_FILES: dict[str, str] = {
    "near": f"sigma1_sq = {2 * gc.GyrocompassParams().sigma1_sq!r}\n",
    "far": "C_as = 2e-12\n[procedure]\nT_rot = 2.0\nT_settle = 3.0\nloop_bandwidth = 1.0\n"
           "rate_noise = 6e-17\n",
}


def run_cli(args: list[str], env: dict[str, str] | None = None) -> tuple[float, float]:
    """``python -m gyrolib ARGS`` as a whole process: (wall s, CPU s of the process)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-m", "gyrolib", *args], cwd=ROOT, check=True,
                   stdout=subprocess.DEVNULL, env={**os.environ, **(env or {})})
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def cli_cases(rec: Recorder, repeat: int) -> None:
    """The ``race`` command as a user runs it (see the module docstring)."""
    env = {"OPENBLAS_NUM_THREADS": "1"}
    run_cli(["race", "--no-thresholds"], env)          # warm-up: numba's cache, bytecode

    def best_of(args, n, extra=None):
        runs = [run_cli(args, {**env, **(extra or {})}) for _ in range(n)]
        return min(runs)

    with tempfile.TemporaryDirectory() as tmp:
        for name, text in CLI_FILES.items():
            path = Path(tmp) / f"{name}.toml"
            path.write_text(text, encoding="utf-8")
            wall, cpu = best_of(["race", "--params", str(path)], 1)
            rec.case(f"race --params FILE ({name}), thresholds included", wall, target_s=15.0,
                     note=f"{cpu:.1f} CPU-s; whole process; file: {' '.join(text.split())}")
        wall, cpu = best_of(["race"], 1)
        rec.case("race at the defaults (the stored map, checked)", wall,
                 note=f"{cpu:.1f} CPU-s; whole process")
        wall, cpu = best_of(["race", "--no-thresholds"], repeat)
        rec.case("race --no-thresholds at the defaults, numba's cache warm", wall, target_s=5.0,
                 note=f"{cpu:.1f} CPU-s; whole process, best of {repeat}")
        cold = Path(tmp) / "numba-cache"
        cold.mkdir()
        wall, cpu = run_cli(["race", "--no-thresholds"],
                            {**env, "NUMBA_CACHE_DIR": str(cold)})
        rec.case("race --no-thresholds at the defaults, numba's cache cold", wall,
                 target_s=5.0, note=f"{cpu:.1f} CPU-s; whole process, an empty "
                                    "NUMBA_CACHE_DIR (every kernel compiled)")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--only-previous", action="store_true",
                    help="run only the cases against the previous race")
    ap.add_argument("--only-cli", action="store_true",
                    help="time the race command as whole processes (gc_race_cli.json)")
    args = ap.parse_args()
    if args.child:
        child(args.repeat)
        return
    if args.only_cli:
        rec = Recorder("gc_race_cli")
        cli_cases(rec, args.repeat)
        rec.write(keep_other_classes=True)
        return
    if args.only_previous:
        rec = Recorder("gc_race")
        against_previous(rec, args.repeat)
        return
    rec = Recorder("gc_race")
    t0 = time.perf_counter()
    race = gc.race()          # warm-up: numba cache load (or compile)
    print(f"first call of gc.race(): {time.perf_counter() - t0:.2f} s")

    model = gc.rate_sensor_model()
    n = round(300.0 / model.procedure.sample_dt)
    # a fresh model for each call: the model keeps its power sums and σ (issue 29)
    fresh = iter([gc.rate_sensor_model() for _ in range(args.repeat)])
    ours, s_ours = best(lambda: next(fresh).classical_sigma(300.0, 300.0), args.repeat)
    peer, s_peer = best(lambda: peer_classical(model, n, n), 1)
    assert abs(s_ours / s_peer - 1) < 1e-8, (s_ours, s_peer)
    rec.case("classical sigma, 2 x 300 s windows (doubling)", ours,
             peer="augmented covariance stepped per sample (numpy)", peer_s=peer,
             note=f"sigma agrees to {abs(s_ours / s_peer - 1):.1e} (relative); a fresh model "
                  "each call (its caches empty)")

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
    against_previous(rec, args.repeat)
    rec.write()


if __name__ == "__main__":
    main()
