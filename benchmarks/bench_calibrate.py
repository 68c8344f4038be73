#!/usr/bin/env python3
"""Benchmark: calibration on recorded data (issues 13, 18).

Every GC case is timed against the **previous path**: ``gc.calibrate`` as it was before the
kernel was rewritten for issues 18 and 22 (commit ``PREVIOUS``, loaded from git history into a
module of its own, same process or a fresh one with the same record).  Wall time and CPU time
of the process are both recorded (the machine is shared: under load the wall time of a
single-threaded run is its CPU time stretched by the contention).

1. GC, 100 s at 1 kHz, ``gc.calibrate`` on an in-memory record after the JIT warm-up (target
   <= 1 s); the same with every time stamp jittered (no target).
2. GC, one hour at 1 kHz (3.6·10⁶ rows), ``gc.calibrate`` on an in-memory record, in a fresh
   process each, with one BLAS thread as the command line sets (target <= 5 s on 2 cores;
   peak resident memory recorded, the record alone holds 115 MB).
3. GC, the same hour end to end through the command line: ``python -m gyrolib calibrate gc
   FILE --json`` on a 3.6·10⁶-row CSV (target <= 5 s, peak memory <= 300 MB).  Peer: the
   same command of the previous command line (commit ``PREVIOUS_CLI``, before issue 18's
   speed work: CSV read line by line, every module imported, no overlap of reading and
   filtering), exported from git into a temporary folder and run from there, alternating
   with ours, best of ``--repeat-hour`` each; peak memory and CPU time of both (GNU time).
   Then where the time goes, ours against the previous tree, each in a fresh process:
   ``import gyrolib.cli`` (best of 3) and reading the file alone (``records.GCChunks``).
4. ``gc.fit_noise`` on the 100 s sample record with another vibration spectrum (target
   <= 60 s).  Peer: one ``gc.calibrate`` of the same record (the unit of its cost).
5. GC sample file read + calibrate; RSF, 60 s at 1 kHz against ``rsf.run_correction``.

``--reader`` (issue 27) runs instead, in one run, the CSV reader on the hour's CSV (3.6·10⁶
rows, 175 MB): ours (pyarrow's streaming CSV reader) against the old reader (the
hand-written line parser with its compiled decimal-to-float converter, commit
``PREVIOUS_READER``, exported from git), alternating, each in a fresh process, best of
``--repeat-hour``: reading alone (``records.GCChunks``; target 5 s, aim 3 s), with a hash of
the doubles read (the same values, or the case says they differ), then the command line end
to end on the same file.  Results in ``benchmarks/results/calibrate_reader.json``.

    .venv/bin/python benchmarks/bench_calibrate.py [--repeat 3] [--repeat-hour 2] [--no-hour]
        [--reader] [--write]
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _results import Recorder, previous_tree

ROOT = Path(__file__).resolve().parents[1]

#: The commit whose gc.calibrate is the peer (before issues 18 and 22).
PREVIOUS = "6712084"

#: The commit whose command line is the end-to-end peer (before issue 18's speed work).
PREVIOUS_CLI = "f8a3322"
#: Where the modules the previous path imports live since gc was divided into rooms (issue 29).
ROOMS = {"model": ("params", "discretization", "state_space", "nominal", "shaping_filters"),
         "logs": ("record",), "analysis": ("montecarlo", "covariance")}

#: The commit of the old CSV reader (hand-written parser and records/_fastcsv.py), the
#: peer of ``--reader`` (issue 27).
PREVIOUS_READER = "dac8896"


def previous_calibrate():
    """``calibrate`` of gyrolib/gc/calibration.py at :data:`PREVIOUS`, or None."""
    try:
        src = subprocess.run(["git", "-C", str(ROOT), "show",
                              f"{PREVIOUS}:gyrolib/gc/calibration.py"], capture_output=True,
                             text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return None
    # the modules it imports moved into gc's rooms (issue 29): the same code, new paths
    for room, names in ROOMS.items():
        for name in names:
            src = src.replace(f"gyrolib.gc.{name} ", f"gyrolib.gc.{room}.{name} ")
    path = Path(tempfile.gettempdir()) / f"gyrolib_calibration_{PREVIOUS}.py"
    path.write_text(src)
    spec = importlib.util.spec_from_file_location(f"calibration_{PREVIOUS}", path)
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod
    try:
        spec.loader.exec_module(mod)
    except ImportError:     # the private names it imported are gone
        return None
    return mod.calibrate


def _best(fn, repeat: int) -> tuple[float, float]:
    """Best wall and best CPU time of ``repeat`` calls."""
    wall, cpu = [], []
    for _ in range(repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        fn()
        wall.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    return min(wall), min(cpu)


def _peak_mb() -> float:
    """This process's peak resident memory (MB): VmHWM, which starts afresh at exec (the
    ``ru_maxrss`` of a child started from a large process includes the parent's)."""
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def hour_record(t_end: float = 3600.0):
    """An in-memory record of ``t_end`` s at 1 kHz that the filter accepts: the aperiodic
    nominal motion plus sensor noise on the angle sensor; on the inclinometers the vibration
    N1 of Eq. (6) (exact simulation), fixed tilts of 20″ and sensor noise.  (Not the full
    truth model of ``gc.simulate_record``, whose 10 sub-steps a sample would take minutes
    and 300 MB for an hour.)"""
    from gyrolib import gc
    from gyrolib.units import ARCSEC_PAPER

    p = gc.GyrocompassParams()
    n = round(t_end / p.dt)
    t = np.arange(1, n + 1) * p.dt
    sr = np.sqrt(np.diag(gc.measurement_noise_covariance(p)))
    rng = np.random.default_rng(1)
    n1 = gc.simulate_shaping_filter(p.vibration_filter(), p.dt, n, seed=2)
    tilt = p.g * 20.0 * ARCSEC_PAPER
    angle = gc.nominal_motion_aperiodic(p, t).beta + sr[0] * rng.standard_normal(n)
    return gc.GCRecord(t=t, angle_sensor=angle,
                       inclinometer_y=tilt + n1 + sr[1] * rng.standard_normal(n),
                       inclinometer_z=-tilt + n1 + sr[2] * rng.standard_normal(n))


def hour_child(which: str, t_end: float) -> None:
    """Fresh process: calibrate an in-memory record of t_end s; print JSON."""
    from gyrolib import gc

    p = gc.GyrocompassParams()
    calibrate = gc.calibrate if which == "ours" else previous_calibrate()
    rec = hour_record(t_end)
    calibrate(hour_record(1.0), p)   # JIT warm-up (cache load)
    base = _peak_mb()
    t0, c0 = time.perf_counter(), time.process_time()
    res = calibrate(rec, p, store_every=1000)
    print(json.dumps({"wall": time.perf_counter() - t0, "cpu": time.process_time() - c0,
                      "rows": res.rows, "peak_mb": _peak_mb(), "before_mb": base}))


def read_child(path: str) -> None:
    """Fresh process: read a GC CSV file through records.GCChunks; print JSON."""
    import hashlib

    from gyrolib import records

    digest = hashlib.sha256()
    t0, c0 = time.perf_counter(), time.process_time()
    rows = 0
    for chunk in records.GCChunks(path):
        rows += chunk.n
        for col in (chunk.t, chunk.angle_sensor, chunk.inclinometer_y, chunk.inclinometer_z):
            digest.update(np.ascontiguousarray(col, dtype=np.float64).tobytes())
    print(json.dumps({"wall": time.perf_counter() - t0, "cpu": time.process_time() - c0,
                      "rows": rows, "peak_mb": _peak_mb(), "sha256": digest.hexdigest(),
                      "gyrolib": str(Path(records.__file__).parents[2])}))


def import_child() -> None:
    """Fresh process: ``import gyrolib.cli``; print JSON (wall, CPU, peak memory)."""
    t0, c0 = time.perf_counter(), time.process_time()
    import gyrolib.cli

    print(json.dumps({"wall": time.perf_counter() - t0, "cpu": time.process_time() - c0,
                      "peak_mb": _peak_mb(), "modules": len(sys.modules),
                      "gyrolib": str(Path(gyrolib.cli.__file__).parents[2])}))


def _child(*args: str, tree: Path | None = None, blas_threads: str | None = None) -> dict:
    """Run this script with ``args`` in a fresh process; ``tree``: with the gyrolib exported
    there instead of this worktree's; ``blas_threads``: OPENBLAS_NUM_THREADS."""
    env = dict(os.environ)
    if tree is not None:
        env["PYTHONPATH"] = str(tree)
    if blas_threads is not None:
        env["OPENBLAS_NUM_THREADS"] = blas_threads
    out = subprocess.run([sys.executable, __file__, *args], capture_output=True, text=True,
                         check=True, env=env, cwd=tree or ROOT)
    return json.loads(out.stdout.strip().splitlines()[-1])


def csv_child(path: str, t_end: float) -> None:
    """Fresh process (the parent stays small): write the record of hour_record as CSV."""
    from gyrolib import records

    hr = hour_record(t_end)
    records.write_csv(path, {"t": hr.t, "angle_sensor": hr.angle_sensor,
                             "inclinometer_y": hr.inclinometer_y,
                             "inclinometer_z": hr.inclinometer_z},
                      fmt=["%.3f", "%.9g", "%.9g", "%.9g"])
    print(json.dumps({"path": path}))


def _cli(path: Path, tree: Path | None = None) -> dict:
    """``python -m gyrolib calibrate gc FILE --json`` (``tree``: the gyrolib exported there):
    wall time, peak memory and CPU time (GNU time's maximum resident set size and user +
    system time, the CLI's own: time is a small parent), the estimate, the load average."""
    cmd = [sys.executable, "-m", "gyrolib", "calibrate", "gc", str(path), "--json"]
    if tree is None:    # the hour record has paper GC's Earth rate and no latitude line:
        # this tree needs it stated (else no valid estimate, exit 3); the previous trees
        # took the paper's values by default, so both compute the same estimate
        cmd += ["--latitude", "paper"]
    timer = Path("/usr/bin/time")
    if timer.is_file():
        cmd = [str(timer), "-f", "MAXRSS_KB %M %U %S", *cmd]
    env = dict(os.environ)
    if tree is not None:
        env["PYTHONPATH"] = str(tree)
    load = os.getloadavg()[0]
    t0 = time.perf_counter()
    out = subprocess.run(cmd, capture_output=True, text=True, cwd=tree or ROOT, env=env)
    wall = time.perf_counter() - t0
    peak = cpu = None
    for line in out.stderr.splitlines():
        if line.startswith("MAXRSS_KB "):
            kb, user, system = line.split()[1:4]
            peak, cpu = int(kb) / 1024, float(user) + float(system)
    summary = {}
    if out.returncode in (0, 3):
        try:
            summary = json.loads(out.stdout)
        except json.JSONDecodeError:
            summary = {}
    return {"wall": wall, "status": out.returncode, "peak_mb": peak, "cpu": cpu,
            "load": load, "valid": summary.get("valid"), "omega_gc": summary.get("omega_gc"),
            "omega_gc_std": summary.get("omega_gc_std"),
            "stderr": "\n".join(ln for ln in out.stderr.splitlines()
                                if not ln.startswith("MAXRSS_KB "))[-300:]}


def _best_run(runs: list[dict]) -> dict:
    ok = [r for r in runs if r["status"] in (0, 3)] or runs
    return min(ok, key=lambda r: r["wall"])


def _alternate_cli(path: Path, tree: Path, repeat: int, scratch: Path
                   ) -> tuple[list[dict], list[dict]]:
    """The command line on ``path``, ours and the one in ``tree``, alternating (the same load
    for both, on average), ``repeat`` times each, after both trees' numba caches are filled
    on a 2000-row head of the file in ``scratch`` (a kernel compiled here would be timed)."""
    small = scratch / "small.csv"
    with open(path) as src, open(small, "w") as dst:
        dst.writelines(line for _, line in zip(range(2001), src))
    _cli(small)
    _cli(small, tree)
    ours, peer = [], []
    for _ in range(repeat):
        ours.append(_cli(path))
        peer.append(_cli(path, tree))
    return ours, peer


def _hour_end_to_end(rec_, path: Path, repeat: int, h: dict) -> None:
    """Case 3: the command line on the hour CSV, ours against the previous command line."""
    mb = path.stat().st_size / 2**20
    with tempfile.TemporaryDirectory() as prev_dir:
        tree = previous_tree(Path(prev_dir), PREVIOUS_CLI)
        if tree is None:
            sys.exit(f"the previous command line (commit {PREVIOUS_CLI}) cannot be exported")
        ours, peer = _alternate_cli(path, tree, repeat, Path(prev_dir))
        imp = min((_child("--import-child") for _ in range(3)), key=lambda r: r["wall"])
        imp_p = min((_child("--import-child", tree=tree) for _ in range(3)),
                    key=lambda r: r["wall"])
        rd = _child("--read-child", str(path))
        rd_p = _child("--read-child", str(path), tree=tree)
        assert imp_p["gyrolib"] == rd_p["gyrolib"] == str(tree), "the peer's gyrolib"
    o, q = _best_run(ours), _best_run(peer)
    same = (o["omega_gc"] is not None and q["omega_gc"] is not None
            and abs(o["omega_gc"] - q["omega_gc"]) <= 1e-9 * abs(q["omega_gc"])
            and abs(o["omega_gc_std"] - q["omega_gc_std"]) <= 1e-9 * q["omega_gc_std"])

    def fmt(r: dict) -> str:
        return (f"{r['wall']:.2f} s wall, {r['cpu']:.2f} s CPU, {r['peak_mb']:.0f} MB, load "
                f"{r['load']:.1f}" if r["cpu"] is not None else f"{r['wall']:.2f} s wall")

    rec_.case("gc: 1 h at 1 kHz end to end, python -m gyrolib calibrate gc FILE "
              f"--json ({mb:.0f} MB CSV)", o["wall"],
              peer=f"the previous command line (commit {PREVIOUS_CLI}), same file",
              peer_s=q["wall"], target_s=5.0,
              note=(f"best of {repeat}, alternating; ours {fmt(o)} (target 300 MB); "
                    f"previous {fmt(q)}; exit {o['status']} / {q['status']}, valid "
                    f"{o['valid']}; omega_gc and its sigma "
                    + ("agree to 1e-9 relative" if same else "DIFFER") + "; all runs ours "
                    + ", ".join(f"{r['wall']:.2f}" for r in ours) + " s, previous "
                    + ", ".join(f"{r['wall']:.2f}" for r in peer) + " s"
                    + (f"; stderr: {o['stderr']}" if o["status"] not in (0, 3) else "")))
    rec_.case("gc: import gyrolib.cli (the command line's start), fresh process",
              imp["wall"], peer=f"the same at commit {PREVIOUS_CLI}", peer_s=imp_p["wall"],
              note=(f"best of 3; CPU {imp['cpu']:.2f} s vs {imp_p['cpu']:.2f} s; peak RSS "
                    f"{imp['peak_mb']:.0f} MB vs {imp_p['peak_mb']:.0f} MB; "
                    f"{imp['modules']} vs {imp_p['modules']} modules"))
    rec_.case(f"gc: reading the hour CSV alone (records.GCChunks, {mb:.0f} MB), fresh process",
              rd["wall"], peer=f"the same at commit {PREVIOUS_CLI}", peer_s=rd_p["wall"],
              note=(f"CPU {rd['cpu']:.2f} s vs {rd_p['cpu']:.2f} s (checks at the door "
                    f"included); peak RSS {rd['peak_mb']:.0f} MB vs {rd_p['peak_mb']:.0f} MB; "
                    f"filtering the in-memory hour {h['cpu']:.2f} s CPU"))


def reader_cases(repeat: int, write: bool) -> None:
    """``--reader``: the hour's CSV through ours and the old reader, in one run."""
    rec_ = Recorder("calibrate_reader")
    with tempfile.TemporaryDirectory() as tmp:
        (Path(tmp) / "old").mkdir()
        tree = previous_tree(Path(tmp) / "old", PREVIOUS_READER)
        if tree is None:
            sys.exit(f"the old reader (commit {PREVIOUS_READER}) cannot be exported")
        path = Path(tmp) / "gc_hour.csv"
        _child("--csv-child", str(path), "3600")
        mb = path.stat().st_size / 2**20
        ours, peer = [], []
        for _ in range(repeat):    # alternating: the same load for both, on average
            ours.append(_child("--read-child", str(path)))
            peer.append(_child("--read-child", str(path), tree=tree))
        assert peer[0]["gyrolib"] == str(tree) and ours[0]["gyrolib"] == str(ROOT)
        o, q = min(ours, key=lambda r: r["wall"]), min(peer, key=lambda r: r["wall"])
        same = o["sha256"] == q["sha256"] and o["rows"] == q["rows"]
        rec_.case(f"gc: reading the hour CSV ({o['rows']} rows, {mb:.0f} MB), records.GCChunks,"
                  " fresh process", o["wall"],
                  peer=f"the old reader (hand-written parser + compiled converter, commit "
                       f"{PREVIOUS_READER})", peer_s=q["wall"], target_s=5.0,
                  note=(f"best of {repeat}, alternating; CPU {o['cpu']:.2f} s vs "
                        f"{q['cpu']:.2f} s (checks at the door included); peak RSS "
                        f"{o['peak_mb']:.0f} MB vs {q['peak_mb']:.0f} MB; the doubles read "
                        + ("are identical (same SHA-256)" if same else "DIFFER")
                        + "; all runs ours " + ", ".join(f"{r['wall']:.2f}" for r in ours)
                        + " s, old " + ", ".join(f"{r['wall']:.2f}" for r in peer)
                        + " s; aim 3 s"))
        c_ours, c_peer = _alternate_cli(path, tree, repeat, Path(tmp))
        co, cq = _best_run(c_ours), _best_run(c_peer)
        agree = (co["omega_gc"] is not None and cq["omega_gc"] is not None
                 and abs(co["omega_gc"] - cq["omega_gc"]) <= 1e-12 * abs(cq["omega_gc"]))
        rec_.case(f"gc: 1 h at 1 kHz end to end, python -m gyrolib calibrate gc FILE --json "
                  f"({mb:.0f} MB CSV)", co["wall"],
                  peer=f"the command line at commit {PREVIOUS_READER} (old reader)",
                  peer_s=cq["wall"], target_s=5.0,
                  note=(f"best of {repeat}, alternating; ours {co['wall']:.2f} s wall, "
                        f"{co['cpu']:.2f} s CPU, {co['peak_mb']:.0f} MB; old "
                        f"{cq['wall']:.2f} s wall, {cq['cpu']:.2f} s CPU, "
                        f"{cq['peak_mb']:.0f} MB; exit {co['status']} / {cq['status']}; "
                        "omega_gc " + ("identical to 1e-12" if agree else "DIFFERS")
                        + f"; load {co['load']:.1f}"))
    if write:
        rec_.write()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--repeat-hour", type=int, default=2,
                    help="runs of each command line on the hour CSV (default 2)")
    ap.add_argument("--no-hour", action="store_true", help="skip the one-hour cases")
    ap.add_argument("--write", action="store_true",
                    help="write benchmarks/results/calibrate.json")
    ap.add_argument("--reader", action="store_true",
                    help="only the CSV reader against the old one on the hour's CSV "
                         "(benchmarks/results/calibrate_reader.json)")
    ap.add_argument("--hour-child", nargs=2, metavar=("WHICH", "T_END"),
                    help=argparse.SUPPRESS)
    ap.add_argument("--read-child", help=argparse.SUPPRESS)
    ap.add_argument("--import-child", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--csv-child", nargs=2, metavar=("PATH", "T_END"), help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.csv_child:
        csv_child(args.csv_child[0], float(args.csv_child[1]))
        return
    if args.hour_child:
        hour_child(args.hour_child[0], float(args.hour_child[1]))
        return
    if args.read_child:
        read_child(args.read_child)
        return
    if args.import_child:
        import_child()
        return
    if args.reader:
        reader_cases(args.repeat_hour, args.write)
        return
    from gyrolib import gc, records, rsf

    rec_ = Recorder("calibrate")
    previous = previous_calibrate()
    if previous is None:
        sys.exit(f"the previous path (commit {PREVIOUS}) cannot be loaded from git")
    p = gc.GyrocompassParams()
    sim = gc.simulate_record(p, 100.0, seed=1)
    t0 = time.perf_counter()
    gc.calibrate(sim.record, p)
    previous(sim.record, p)
    print(f"first calls (numba cache load or compile): {time.perf_counter() - t0:.2f} s")

    # 1. 100 s in memory
    ours, ours_cpu = _best(lambda: gc.calibrate(sim.record, p), args.repeat)
    peer, peer_cpu = _best(lambda: previous(sim.record, p), args.repeat)
    rec_.case("gc: 100 s at 1 kHz, in memory, after warm-up", ours,
              peer=f"previous gc.calibrate (commit {PREVIOUS})", peer_s=peer, target_s=1.0,
              note=f"best of {args.repeat}; CPU {ours_cpu:.3f} s vs {peer_cpu:.3f} s")
    rng = np.random.default_rng(2)
    jit = gc.GCRecord(t=sim.record.t + rng.uniform(-1e-5, 1e-5, sim.record.n),
                      angle_sensor=sim.record.angle_sensor,
                      inclinometer_y=sim.record.inclinometer_y,
                      inclinometer_z=sim.record.inclinometer_z)
    ours_j, ours_j_cpu = _best(lambda: gc.calibrate(jit, p), args.repeat)
    peer_j, peer_j_cpu = _best(lambda: previous(jit, p), args.repeat)
    rec_.case("gc: 100 s at 1 kHz, every time stamp jittered (±1 % of dt)", ours_j,
              peer=f"previous gc.calibrate (commit {PREVIOUS})", peer_s=peer_j,
              note=f"Taylor time shift per step; no target; CPU {ours_j_cpu:.3f} s vs "
                   f"{peer_j_cpu:.3f} s")

    # 2., 3. one hour
    if not args.no_hour:
        # one BLAS thread for both, as the command line sets (OpenBLAS's threads make the
        # 60 x 60 exponentials of the step tables 60 times slower here, and then spin)
        h = _child("--hour-child", "ours", "3600", blas_threads="1")
        hp = _child("--hour-child", "previous", "3600", blas_threads="1")
        rec_.case("gc: 1 h at 1 kHz (3.6e6 rows), in memory, fresh process", h["wall"],
                  peer=f"previous gc.calibrate (commit {PREVIOUS}), fresh process",
                  peer_s=hp["wall"], target_s=5.0,
                  note=(f"one BLAS thread for both (as the command line sets); "
                        f"CPU {h['cpu']:.2f} s vs {hp['cpu']:.2f} s; "
                        f"{1e6 * h['cpu'] / h['rows']:.2f} vs "
                        f"{1e6 * hp['cpu'] / hp['rows']:.2f} CPU us/row; peak RSS "
                        f"{h['peak_mb']:.0f} MB vs {hp['peak_mb']:.0f} MB (the record "
                        f"alone 115 MB, its simulation more: {h['before_mb']:.0f} MB before "
                        "the call)"))
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / "gc_hour.csv"
            _child("--csv-child", str(path), "3600")
            _hour_end_to_end(rec_, path, args.repeat_hour, h)

    # 4. the noise fit on 100 s
    wrong = records.read_gc(ROOT / "data" / "gc_record_wrong_spectrum.csv.gz")
    t0, c0 = time.perf_counter(), time.process_time()
    fit = gc.fit_noise(wrong, p)
    fit_wall, fit_cpu = time.perf_counter() - t0, time.process_time() - c0
    one, _ = _best(lambda: gc.calibrate(wrong, p), args.repeat)
    truth = json.loads((ROOT / "data" / "truth.json").read_text())[
        "gc_record_wrong_spectrum.csv.gz"]
    rec_.case("gc: fit_noise on 100 s at 1 kHz (alpha1, sigma1_sq, C_as, C_in)", fit_wall,
              peer="one gc.calibrate of the same record", peer_s=one, target_s=60.0,
              note=(f"CPU {fit_cpu:.1f} s; {fit.n_evaluations} full likelihoods; alpha1 "
                    f"{fit.value('alpha1'):.3g} +- {fit.std_error('alpha1'):.2g} (made with "
                    f"{truth['alpha1']:.3g}), sigma1_sq {fit.value('sigma1_sq'):.3g} +- "
                    f"{fit.std_error('sigma1_sq'):.2g} (made with {p.sigma1_sq:.3g}); "
                    f"{fit.message}"))

    # 5. sample file end to end; RSF
    sample = ROOT / "data" / "gc_record.csv.gz"
    e2e, _ = _best(lambda: gc.calibrate(records.read_gc(sample), p), args.repeat)
    read, _ = _best(lambda: records.read_gc(sample), args.repeat)
    rec_.case("gc: sample file read + calibrate (99 000 rows, gzip CSV)", e2e,
              peer="reading the file alone", peer_s=read, note="no target")
    cfg = rsf.SimulationConfig(duration=60.0, sample_rate=1000.0)
    flight = rsf.simulate_flight(cfg, seed=1)
    rrec = rsf.record_from_simulation(flight)
    rsf.calibrate(rrec, 1.0)
    ours_r, _ = _best(lambda: rsf.calibrate(rrec, 1.0), args.repeat)
    peer_r, _ = _best(lambda: rsf.run_correction(flight, 1.0), args.repeat)
    rec_.case("rsf: 60 s at 1 kHz, in memory", ours_r,
              peer="rsf.run_correction on the SensorRecord (plain numpy)", peer_s=peer_r,
              target_s=0.5, note=f"best of {args.repeat}")
    if args.write:
        rec_.write()


if __name__ == "__main__":
    os.environ.setdefault("PYTHONHASHSEED", "0")
    main()
