#!/usr/bin/env python3
"""Benchmark: Monte Carlo of paper GC, 1000 runs × 100 s, truth simulation and filter
(issue 7, target 2; issue 20, item 3: at most 10 s on 2 cores).

Measures the wall time of ``gyrolib.gc.monte_carlo`` (gains computed once; the runs in blocks
of 32 lanes, each block one numba kernel call that draws its runs' own random streams —
SFC64 and numpy's ziggurat — and integrates truth and filter; the blocks on this process's
threads, one per core) against peers run in the same process on the same runs:

* the same call by the commit before issue 36 (``PREVIOUS``, the ziggurat's first try in
  one loop), both in child processes, alternating: what vectorizing the first try on AVX2
  buys;
* the same call on one thread (``executor=ThreadPoolExecutor(1)``): what the second core buys;
* the previous path, kept in the library for ``gc.simulate_truth``: normals drawn by numpy
  (SFC64) per block of 32 runs in Python, the same kernels otherwise
  (``gyrolib.gc.analysis.montecarlo._run_batch``);
* numpy's own generators on the same per-run streams (issue 29, item 6): each run's
  ``Generator(SFC64)`` (spawned from ``SeedSequence(seed)``) fills its block of normals with
  ``standard_normal(out=...)`` (no GIL), the blocks of 32 runs on a ``ThreadPoolExecutor`` of
  one thread per core, the same truth and filter kernel.  It gives the same runs (checked to
  1e-12).  Issue 36: the kernel's copy of SFC64 and the ziggurat stays only while this path
  costs more than 1.15 times its CPU over the whole Monte Carlo on the AVX2 class; the file
  records the decision with its figures (and both generators' ns per normal);
* the draw limit (issue 36): the CPU time of the normals the Monte Carlo needs (23 per run
  and step: two shaping-filter noises on each of 10 fine steps, three sensor noises) at the
  ns per normal of numpy's ``Generator.standard_normal`` measured in the same run; the whole
  Monte Carlo's CPU time is at most 1.3 times it.  Ours, numpy's path and the ns per normal
  alternate over ``--rounds`` rounds (medians quoted; the ratio of the two paths is the median
  of each round's pair, taken under the same load);
* the same call on a ``ProcessPoolExecutor`` of 2 workers (workers started and warmed
  before timing): the cost of handing chunks to an executor (target: within 5 % of the
  in-process threads, plus the workers' one-time model build);
* the library's plain-numpy reference path (``method="reference"``), timed over
  ``--peer-t-end`` seconds and scaled linearly to ``--t-end``.

Each case also reports the process's CPU time (all threads), so that the result can be read
on a loaded machine: on two idle cores the wall time approaches CPU/2.  Also checks that the
result is sound (NEES of ω_gc at 100 s inside its 95 % band).  Writes
``benchmarks/results/gc_monte_carlo.json``.

    .venv/bin/python benchmarks/bench_gc_monte_carlo.py [--runs 1000] [--rounds 3] [--peer-t-end 1]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor
from pathlib import Path

import numpy as np
from _results import Recorder, load, machine, machine_label, previous_tree

from gyrolib import filtering, gc
from gyrolib.filtering.discretization import covariance_factor
from gyrolib.gc.analysis import montecarlo as mcm
from gyrolib.gc.model.discretization import N, discretize
from gyrolib.gc.model.params import GyrocompassParams
from gyrolib.gc.model.state_space import initial_covariance


def timed(fn, *args, **kw) -> tuple[object, float, float]:
    """``(result, wall s, CPU s of this process)``; worker processes' CPU is not counted."""
    c0, t0 = time.process_time(), time.perf_counter()
    out = fn(*args, **kw)
    return out, time.perf_counter() - t0, time.process_time() - c0


def previous_path(p: GyrocompassParams, n_runs: int, t_end: float, seed: int) -> None:
    """The runs as the library made them before per-run streams: one numpy SFC64 generator
    per block of 32 runs, its normals drawn in Python chunk after chunk, same kernels."""
    disc = discretize(p, t_end)
    prep, _ = mcm._prepare(mcm._Recipe(p, p, t_end, None, "fast", 0, mcm.TRUTH_SUBSTEPS))
    rng = np.random.default_rng(seed)
    X0 = rng.standard_normal((n_runs, N)) @ covariance_factor(initial_covariance(p)).T
    mcm._run_batch(prep.tm, disc.n_steps, X0, rng, prep.fm, prep.store_every, "fast")


def numpy_generators(p: GyrocompassParams, n_runs: int, t_end: float, seed: int,
                     chunk: int = 250) -> tuple[np.ndarray, np.ndarray]:
    """``monte_carlo``'s runs with numpy's generators instead of the kernel's copy: the same
    per-run SFC64 streams after the same initial states (``_run_inputs``), each run's
    normals drawn by ``Generator.standard_normal(out=...)`` ``chunk`` steps at a time into a
    runs-first buffer, one transposing copy into the kernel's lane layout, then the same
    truth-and-filter kernel; the blocks of 32 runs on one thread per core.  ``(est, tru)``."""
    prep, _ = mcm._prepare(mcm._Recipe(p, p, t_end, None, "fast", 0, mcm.TRUTH_SUBSTEPS))
    tm, fm, n_steps, se = prep.tm, prep.fm, prep.n_steps, prep.store_every
    X0, states = mcm._run_inputs(p, seed, n_runs)
    B, width = mcm._RUN_BLOCK, 2 * tm.substeps + 3
    est = np.zeros((n_runs, n_steps // se + 1, N))
    tru = np.zeros_like(est)
    tru[:, 0] = X0

    def block(b: int) -> None:
        lanes = range(b * B, min((b + 1) * B, n_runs))
        gens = []
        for r in lanes:
            bg = np.random.SFC64()
            bg.state = {"bit_generator": "SFC64", "state": {"state": states[:, r].copy()},
                        "has_uint32": 0, "uinteger": 0}
            gens.append(np.random.Generator(bg))
        x = np.zeros((N, B))
        x[:, :len(lanes)] = X0[b * B:lanes.stop].T
        x[0] -= tm.off_b[0]
        x[1] -= tm.off_bd[0]
        xh, y, u = np.zeros_like(x), np.zeros_like(x), np.zeros(B)
        buf = np.empty((B, chunk, width))
        noise = np.zeros((chunk, width, B))
        for k0 in range(0, n_steps, chunk):
            steps = min(chunk, n_steps - k0)
            for r, gen in enumerate(gens):
                gen.standard_normal(out=buf[r, :steps])
            noise[:steps, :, :len(gens)] = buf[:len(gens), :steps].transpose(1, 2, 0)
            mcm._mc_block_kernel(k0, noise[:steps], tm, fm, x, xh, y, u, se, est, tru,
                                 b * B, True)

    with ThreadPoolExecutor(len(os.sched_getaffinity(0))) as pool:
        list(pool.map(block, range(-(-n_runs // B))))
    return est, tru


def ns_per_normal(reps: int = 200) -> tuple[float, float]:
    """CPU ns per standard normal: numpy's ``Generator(SFC64).standard_normal`` (32 streams,
    blocks of 250 × 23 into one buffer, as :func:`numpy_generators` draws them) and the
    kernel's copy (the same 32 streams, all lanes at once, blocks of ``_NOISE_CHUNK`` × 23
    into one buffer, as ``gc.monte_carlo`` draws them); ``reps`` × 184 000 normals each.
    Both buffers stay in the cache (an array of all the normals at once would time the
    memory instead)."""
    gens = gc.run_streams(3, mcm._RUN_BLOCK)
    state = np.array([g.bit_generator.state["state"]["state"] for g in gens], np.uint64).T
    tables = (mcm._ZKI, mcm._ZKI_SIGNED, mcm._ZWI, mcm._ZFI)
    chunk = mcm._NOISE_CHUNK
    zbuf, ubuf = np.empty((chunk, 23, mcm._RUN_BLOCK)), np.empty(mcm._RUN_BLOCK, np.uint64)
    mcm._fill_normals(state, zbuf, ubuf, *tables)   # compiled or loaded before timing
    buf = np.empty((250, 23))
    c0 = time.process_time()
    for _ in range(reps):
        for g in gens:
            g.standard_normal(out=buf)
    c1 = time.process_time()
    for _ in range(reps * 250 // chunk):
        mcm._fill_normals(state, zbuf, ubuf, *tables)
    c2 = time.process_time()
    n_np = reps * 250 * 23 * len(gens)
    n_copy = (reps * 250 // chunk) * chunk * 23 * mcm._RUN_BLOCK
    return 1e9 * (c1 - c0) / n_np, 1e9 * (c2 - c1) / n_copy


#: The commit before issue 36's kernel (its ziggurat's first try in one loop, scalar on AVX2).
PREVIOUS = "5ddf2b6"

_CHILD = """
import json, sys, time
from gyrolib import gc
p = gc.GyrocompassParams()
runs, t_end = int(sys.argv[1]), float(sys.argv[2])
gc.monte_carlo(p, 8, 0.5, seed=0)            # numba: compiled or loaded before timing
c0, t0 = time.process_time(), time.perf_counter()
res = gc.monte_carlo(p, runs, t_end, seed=1)
print(json.dumps({"cpu": time.process_time() - c0, "wall": time.perf_counter() - t0,
                  "gyrolib": gc.__file__, "est": float(abs(res.est[:, -1, 3]).sum())}))
"""


def previous_commit(runs: int, t_end: float, rounds: int) -> dict | None:
    """The whole Monte Carlo by this tree and by :data:`PREVIOUS`'s, each in a child process
    (``PYTHONPATH`` its tree), alternating over ``rounds``: medians of CPU and wall time and
    the median of each round's CPU ratio; None when the commit cannot be exported."""
    root = Path(__file__).resolve().parents[1]
    with tempfile.TemporaryDirectory() as tmp:
        tree = previous_tree(Path(tmp), PREVIOUS)
        if tree is None:
            return None
        out: dict[str, list[dict]] = {"ours": [], "previous": []}
        for _ in range(rounds):
            for name, where in (("ours", root), ("previous", tree)):
                env = dict(os.environ, PYTHONPATH=str(where), OPENBLAS_NUM_THREADS="1")
                proc = subprocess.run([sys.executable, "-c", _CHILD, str(runs), str(t_end)],
                                      cwd=where, env=env, capture_output=True, text=True,
                                      check=True)
                out[name].append(json.loads(proc.stdout.splitlines()[-1]))
                print(f"{name}: {out[name][-1]}; load {load()}", flush=True)
    assert out["previous"][0]["gyrolib"].startswith(str(tree)), "the peer's gyrolib"
    same = out["ours"][0]["est"] == out["previous"][0]["est"]
    return {"ours_cpu": float(np.median([r["cpu"] for r in out["ours"]])),
            "prev_cpu": float(np.median([r["cpu"] for r in out["previous"]])),
            "ours_wall": float(np.median([r["wall"] for r in out["ours"]])),
            "prev_wall": float(np.median([r["wall"] for r in out["previous"]])),
            "ratio": float(np.median([q["cpu"] / o["cpu"] for o, q in
                                      zip(out["ours"], out["previous"], strict=True)])),
            "same": same}


#: The copied generator stays only if numpy's path costs more than this times its CPU over
#: the whole Monte Carlo on the AVX2 class (issue 36).
KEEP_COPY_ABOVE = 1.15

#: The whole Monte Carlo's CPU time at most this times its draw limit (issue 36).
DRAW_LIMIT_TARGET = 1.3


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=1000)
    ap.add_argument("--t-end", type=float, default=100.0)
    ap.add_argument("--peer-t-end", type=float, default=1.0)
    ap.add_argument("--rounds", type=int, default=3,
                    help="rounds of ours / numpy's generators / the draw limit, alternating "
                         "(medians quoted)")
    args = ap.parse_args()
    p = GyrocompassParams()
    rec = Recorder("gc_monte_carlo")
    cpu = machine_label(machine())
    n_steps = round(args.t_end / p.dt)
    width = 2 * mcm.TRUTH_SUBSTEPS + 3
    n_normals = args.runs * n_steps * width
    _, first, _ = timed(gc.monte_carlo, p, 8, 0.5, seed=0)  # numba: on-disk cache or compile
    previous_path(p, 8, 0.5, 0)
    numpy_generators(p, 8, 0.5, 0)
    print(f"first call (incl. numba cache load/compile): {first:.2f} s; {cpu}")

    # A/B/C alternating: ours, numpy's generators on the same streams, the draw limit
    ours_w, ours_c, npg_w, npg_c, ns_np, ns_copy, same = [], [], [], [], [], [], []
    for rnd in range(args.rounds):
        res, w, c = timed(gc.monte_carlo, p, args.runs, args.t_end, seed=1)
        ours_w.append(w)
        ours_c.append(c)
        (np_est, np_tru), w, c = timed(numpy_generators, p, args.runs, args.t_end, 1)
        npg_w.append(w)
        npg_c.append(c)
        scale = np.sqrt(np.diagonal(res.P, axis1=1, axis2=2)).max(axis=0) + 1e-300
        same.append(max(np.max(np.abs(np_est - res.est) / scale),
                        np.max(np.abs(np_tru - res.tru) / scale)))
        del np_est, np_tru
        a, b = ns_per_normal()
        ns_np.append(a)
        ns_copy.append(b)
        print(f"round {rnd + 1}: ours {ours_w[-1]:.2f} s wall, {ours_c[-1]:.2f} s CPU; numpy's "
              f"generators {npg_w[-1]:.2f} s wall, {npg_c[-1]:.2f} s CPU; one normal: numpy "
              f"{a:.2f} ns, the copy {b:.2f} ns; load {load()}", flush=True)
    med = {k: float(np.median(v)) for k, v in (("ours", ours_w), ("ours_cpu", ours_c),
                                               ("npg", npg_w), ("npg_cpu", npg_c),
                                               ("ns_np", ns_np), ("ns_copy", ns_copy))}
    same = max(same)
    ours, ours_cpu, ns_numpy = med["ours"], med["ours_cpu"], med["ns_np"]
    draw_limit = 1e-9 * ns_numpy * n_normals
    # the ratio of each round's pair (same load), then the median
    np_over_copy = float(np.median(np.array(npg_c) / np.array(ours_c)))
    keep = np_over_copy > KEEP_COPY_ABOVE

    prev_commit = previous_commit(args.runs, args.t_end, args.rounds)

    with ThreadPoolExecutor(1) as one:
        _, serial, serial_cpu = timed(gc.monte_carlo, p, args.runs, args.t_end, seed=1,
                                      executor=one)
    print(f"peer: one thread: {serial:.2f} s wall, {serial_cpu:.2f} s CPU")
    _, prev, prev_cpu = timed(previous_path, p, args.runs, args.t_end, 1)
    print(f"peer: previous path (numpy normals per block): {prev:.2f} s wall, "
          f"{prev_cpu:.2f} s CPU")
    with ProcessPoolExecutor(2) as pool:
        gc.monte_carlo(p, 64, 0.5, seed=0, executor=pool)     # start and warm the workers
        _, procs, _ = timed(gc.monte_carlo, p, args.runs, args.t_end, seed=1, executor=pool)
    print(f"ProcessPoolExecutor(2): {procs:.2f} s wall")
    nees = res.nees(("omega_gc",)).mean(axis=0)[-1]
    lo, hi = filtering.nees_bounds(1, args.runs)
    sound = "inside" if lo < nees < hi else "OUTSIDE"
    print(f"sanity: NEES(omega_gc) at {args.t_end:g} s = {nees:.3f}, {sound} [{lo:.3f}, {hi:.3f}]")

    _, peer_part, _ = timed(gc.monte_carlo, p, args.runs, args.peer_t_end, seed=1,
                            method="reference")
    peer = peer_part * args.t_end / args.peer_t_end
    print(f"peer: reference numpy path, {args.runs} runs x {args.peer_t_end:g} s: "
          f"{peer_part:.2f} s -> scaled to {args.t_end:g} s: {peer:.1f} s")

    name = f"Monte Carlo, {args.runs} runs × {args.t_end:g} s, truth + filter"
    per = f"{1e9 * ours_cpu / (args.runs * n_steps):.0f} ns of CPU per run and step"
    rounds = f"median of {args.rounds} alternating rounds"
    rec.case(f"{name}: CPU time against its draw limit", ours_cpu,
             peer=f"draw limit: the CPU time of its {n_normals:.3g} standard normals ({width} a "
                  f"run and step) from numpy's Generator(SFC64).standard_normal, "
                  f"{ns_numpy:.2f} ns each, measured in the same run",
             peer_s=draw_limit, target_s=DRAW_LIMIT_TARGET * draw_limit,
             note=f"ratio = draw limit/ours (CPU s; target ≥ {1 / DRAW_LIMIT_TARGET:.3f}, "
                  f"i.e. at most {DRAW_LIMIT_TARGET}× the limit): ours takes "
                  f"{ours_cpu / draw_limit:.2f}× its draw limit; {per}; {rounds}; {cpu}")
    decision = (f"the copy STAYS: numpy's path costs {np_over_copy:.2f}× its CPU, above "
                f"{KEEP_COPY_ABOVE}" if keep else
                f"the copy should GO: numpy's path costs only {np_over_copy:.2f}× its CPU, "
                f"not above {KEEP_COPY_ABOVE}")
    rec.case(f"{name}: the kernel's generator vs numpy's generators (CPU s)", ours_cpu,
             peer="numpy's Generator(SFC64).standard_normal per run on the same streams, "
                  "blocks of 32 runs filled on one thread per core, same kernel (CPU s)",
             peer_s=med["npg_cpu"], target_s=None,
             note=f"ratio = peer/ours; decision (issue 36, on the "
                  f"{machine()['cpu_class']} class): {decision}; wall {ours:.1f} s vs "
                  f"{med['npg']:.1f} s; the same runs to {same:.0e} of the prior scale; one "
                  f"normal costs {ns_numpy:.2f} ns of CPU from numpy against "
                  f"{med['ns_copy']:.2f} ns from the kernel's copy; {rounds}")
    if prev_commit is not None:
        rec.case(f"{name}: vs the previous commit's kernel (CPU s)", prev_commit["ours_cpu"],
                 peer=f"gc.monte_carlo of commit {PREVIOUS} (the ziggurat's first try in one "
                      "loop, which LLVM leaves scalar on AVX2), in a child process",
                 peer_s=prev_commit["prev_cpu"],
                 note=f"ratio = peer/ours of CPU s, the median of each round's ratio "
                      f"{prev_commit['ratio']:.2f}; wall {prev_commit['ours_wall']:.1f} s vs "
                      f"{prev_commit['prev_wall']:.1f} s; both in child processes, alternating, "
                      f"{rounds}; the same estimates to the bit: {prev_commit['same']}; {cpu}")
    rec.case(f"{name}: threads over the cores vs one thread", ours,
             peer="the same call on one thread (executor=ThreadPoolExecutor(1))",
             peer_s=serial, target_s=10.0,
             note=f"ratio = peer/ours; CPU {ours_cpu:.1f} s (threads) vs {serial_cpu:.1f} s "
                  f"(one thread); first call in a fresh process {first:.2f} s; NEES of "
                  f"ω_gc at {args.t_end:g} s {nees:.3f}, {sound} its 95 % band; ours: {rounds}")
    rec.case(f"{name}: vs the previous path", ours,
             peer="previous path: numpy SFC64 normals per block of 32 runs drawn in Python, "
                  "same kernels (gc.montecarlo._run_batch)",
             peer_s=prev, target_s=10.0,
             note=f"ratio = peer/ours; CPU {ours_cpu:.1f} s vs {prev_cpu:.1f} s")
    rec.case(f"{name}: ProcessPoolExecutor(2) vs in-process threads", procs,
             peer="in-process threads (executor=None), same run", peer_s=ours,
             note="ratio = peer/ours (below 1: the executor's overhead); 16 chunks of 64 runs; "
                  "workers started before timing, each builds the 100 s model once (timed)")
    rec.case(f"{name}: vs the plain-numpy reference", ours,
             peer=f"plain-numpy reference path (method='reference'), timed over "
                  f"{args.peer_t_end:g} s and scaled to {args.t_end:g} s",
             peer_s=peer, target_s=30.0, note="ratio = peer/ours")
    # the machine is shared: the load at the end too (the file's "load" is at the start)
    end = load()
    for case in rec.doc["results"]:
        case["note"] += f"; 1-minute load {rec.doc['load']} at the start, {end} at the end"
    rec.write()


if __name__ == "__main__":
    main()
