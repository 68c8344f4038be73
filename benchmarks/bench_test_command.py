"""Benchmark of the test command on a fresh clone, set-up included: the everyday command
``python3 tasks.py test`` (target ≤ 6 minutes on a quiet 2-core AVX2 machine), or with
``--full`` CI's ``.ci/run``, ``python3 tasks.py test --full`` (target ≤ 60 minutes).

Times what a contributor (or CI) runs, on a fresh ``git clone`` of the current commit in a
temporary folder (no ``.venv``, no ``_build``, no numba cache):

1. ``python3 tasks.py setup`` — the set-up: ``.venv`` created and the pinned environment
   installed (the test command would do it first; timed apart to show its share);
2. the test command itself, as CI runs it (``CI=true``, ``GYROLIB_REQUIRE_BROWSER=1``):
   ``python3 tasks.py test`` (the set-up's idempotence check, the browser, lint, the pinned
   JupyterLab, then pytest on every core, whose session builds the book once from clean in
   the background, prints the PDF and runs the everyday tier; the determinism test compares
   the chapters with their recorded outputs, ``tests/recorded_outputs/``), or with
   ``--full`` ``bash .ci/run`` (the same and the full tier: every test marked ``full``, a
   second execution of every chapter among them).

The total of the two is the fresh-clone time.  The pytest part and its slowest tests come
from pytest's own report, the steps of the session's book build from the line the test
session prints about it.  The 1-minute load average is recorded before each step and after
the last; the one before the first step says whether the machine was quiet (the later ones
include the benchmark's own steps): the target is for a quiet machine, and a run on a busy
one says so in its notes (its time is then an upper bound).  The CPU class (AVX2 or AVX-512,
with family, model and numba's host CPU name) is in the file's machine and in every case's
note: the targets are for the common 2-core AVX2 class.  No peer: the ratio is the share of
the target used.  ``--after-book`` instead times ``python3 tasks.py book`` and then
``python3 tasks.py test``.

Writes ``benchmarks/results/test_command.json`` (``test_command_full.json`` with ``--full``)
and where the core-seconds go — the command's CPU, each step of the session's book build, the
tests, the test files and the single tests that cost most, from the session's timeline
(``GYROLIB_TEST_TIMELINE``, ``tests/conftest.py``) — to ``test_command_cpu.json``
(``test_command_full_cpu.json``).  Each file keeps the latest run of each other CPU class
(``_results.Recorder.write``), which the README's table quotes (``readme_times.py``).
``--dry-run`` prints the steps and the files without running anything.

    .venv/bin/python benchmarks/bench_test_command.py [--full] [--after-book] [--keep] [--dry-run]
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _results import RESULTS, Recorder, children_cpu, load, machine, machine_label

SOURCE = Path(__file__).resolve().parents[1]

#: Targets for the fresh-clone time, set-up included (s, quiet 2-core AVX2 machine): the
#: everyday command and the full one.
TARGET_S = 360.0
TARGET_FULL_S = 3600.0

#: The test command of each tier, and the environment CI gives it (``.ci/run``).
EVERYDAY_CMD = ["python3", "tasks.py", "test"]
FULL_CMD = ["bash", ".ci/run"]
CI_ENV = {"CI": "true", "GYROLIB_REQUIRE_BROWSER": "1"}

#: Above this 1-minute load average before the first step the machine is not quiet.
QUIET_LOAD = 1.0

#: The CPU seconds of the last :func:`timed` command, its processes' and theirs.
LAST_CPU = [0.0]


def timed(cmd: list[str], cwd: Path, **extra_env: str) -> tuple[float, str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith(("VIRTUAL_ENV", "GYROLIB_"))}
    env["PATH"] = os.pathsep.join(p for p in env.get("PATH", "").split(os.pathsep)
                                  if ".venv" not in p)
    env.update(extra_env)
    t0, cpu0 = time.perf_counter(), children_cpu()
    proc = subprocess.run(cmd, cwd=cwd, env=env, text=True, capture_output=True, check=False)
    elapsed = time.perf_counter() - t0
    LAST_CPU[0] = children_cpu() - cpu0
    log = proc.stdout + proc.stderr
    if proc.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed (exit {proc.returncode}) after {elapsed:.0f} s:\n"
                 f"{log[-4000:]}")
    return elapsed, log


def quiet(start: float | None, later: list[float | None] = ()) -> str:
    """The 1-minute load before the first step decides whether the machine was quiet; the
    later readings (before each further step, and at the end) are shown but not judged:
    they include the benchmark's own steps (a test command keeps both cores busy)."""
    if start is None:
        return "load unknown"
    verdict = "quiet" if start <= QUIET_LOAD else "NOT quiet: an upper bound"
    shown = [f"{x:.2f}" for x in later if x is not None]
    return (f"1-minute load {start:.2f} at the start ({verdict})"
            + (f"; {', '.join(shown)} later, from its own steps" if shown else ""))


def record_pytest(rec: Recorder, log: str) -> str:
    """The session book's steps as cases; returns a note on pytest's own report."""
    summary = re.findall(r"=+ (\d+ passed.*?) in ([\d.]+)s", log)
    passed, pytest_s = summary[-1] if summary else ("?", "nan")
    slowest = re.findall(r"^\s*([\d.]+)s (call|setup)\s+(\S+)", log, flags=re.M)[:4]
    slow = "; ".join(f"{name.split('::')[-1]} {float(s):.0f} s" for s, _, name in slowest)
    steps = re.search(r"^the session's book: (.*)$", log, flags=re.M)
    if steps:
        for name, secs in re.findall(r"([^,]+?) ([\d.]+) s(?:,|$)", steps.group(1)):
            rec.case(f"in the test command: {name.strip()}", float(secs),
                     target_s=90.0 if "executes every chapter" in name else None,
                     note="the clean build of the book (every chapter executed, "
                          "ratio = ours/target), in the background while other tests run"
                     if "executes every chapter" in name else "")
    return (f"pytest {float(pytest_s):.0f} s ({passed}), of which the slowest: "
            f"{slow or 'see --durations'}")


def record_cpu(timeline: Path, wall: float, cpu: float, commit: str,
               name: str = "test_command_cpu") -> None:
    """Where the test command's core-seconds go (``benchmarks/results/test_command_cpu.json``):
    the whole command's CPU (every process it waited for) against what the cores could
    give in its wall time, the book's build steps, the tests that read the built book and
    the others, and the files that cost most.  From the session's timeline
    (``GYROLIB_TEST_TIMELINE``, tests/conftest.py): each test's CPU is its worker's own and
    that of the processes it waited for; the browser's is in no test's (Chromium outlives
    them) and is part of the remainder."""
    rows = [json.loads(line) for line in timeline.read_text().splitlines() if line.strip()]
    tests = [r for r in rows if "test" in r]
    steps = [r for r in rows if "book_step" in r]
    rec = Recorder(name)
    cores = os.cpu_count() or 1
    label = f"commit {commit}; {machine_label(machine())}"
    rec.case("the test command: CPU-s of all its processes", cpu, target_s=None,
             note=f"{cores} cores x {wall:.0f} s wall = {cores * wall:.0f} core-s: "
                  f"{100 * cpu / (cores * wall):.0f} % used; {label}")
    for r in steps:
        rec.case(f"book build step: {r['book_step']}", r["cpu"],
                 note=f"CPU-s of the step's processes; wall {r['end'] - r['start']:.0f} s")
    reads_book = {r["test"].split("::")[0] for r in tests
                  if r["start"] >= max((x["end"] for x in steps), default=0.0) - 1.0}
    per_file: dict[str, float] = {}
    for r in tests:
        name = r["test"].split("::")[0]
        per_file[name] = per_file.get(name, 0.0) + r["cpu"] + r["cpu_children"]
    total_tests = sum(per_file.values())
    rec.case("the tests: CPU-s of the workers and the processes they waited for", total_tests,
             note=f"{len(tests)} tests in {len(per_file)} files; the rest of the command's "
                  f"CPU ({cpu - total_tests - sum(r['cpu'] for r in steps):.0f} s) is the "
                  "browser, pytest's collection and start-up, lint and the set-up checks")
    for file, c in sorted(per_file.items(), key=lambda kv: -kv[1])[:15]:
        rec.case(f"test file: {file}", c, note="ran after the book was built"
                 if file in reads_book else "")
    for r in sorted(tests, key=lambda r: -(r["cpu"] + r["cpu_children"]))[:15]:
        rec.case(f"test: {r['test']}", r["cpu"] + r["cpu_children"],
                 note=f"wall {r['wall']:.0f} s")
    rec.write(keep_other_classes=True)


def fresh_clone(rec: Recorder, clone: Path, commit: str, full: bool) -> None:
    load_setup = load()
    t_setup, _ = timed(["python3", "tasks.py", "setup"], clone)
    load_test = load()
    timeline = clone.parent / "timeline.jsonl"
    command = FULL_CMD if full else EVERYDAY_CMD
    t_test, log = timed(command, clone, **CI_ENV, GYROLIB_TEST_TIMELINE=str(timeline))
    cpu_test = LAST_CPU[0]
    load_end = load()
    (clone.parent / "test_command.log").write_text(log)
    pytest_note = record_pytest(rec, log)
    record_cpu(timeline, t_test, cpu_test, commit,
               "test_command_full_cpu" if full else "test_command_cpu")
    loads = f"{quiet(load_setup, [load_test, load_end])}; {machine_label(machine())}"
    shown = " ".join(command)
    what = "full test command" if full else "test command"
    rec.case("set-up on a fresh clone: python3 tasks.py setup (.venv, pinned environment)",
             t_setup, note=f"commit {commit}; {loads}")
    rec.case(f"{what} on a fresh clone: {shown} after the set-up", t_test,
             note=f"{pytest_note}; browser, lint and the JupyterLab set-up the rest; {loads}")
    rec.case(f"fresh clone to a finished {what}, set-up included", t_setup + t_test,
             target_s=TARGET_FULL_S if full else TARGET_S,
             note=f"ratio = ours/target; set-up {t_setup:.0f} s + {what} {t_test:.0f} s; "
                  f"{loads}")


def after_book(rec: Recorder, clone: Path, commit: str) -> None:
    load_book = load()
    t_book, _ = timed(["python3", "tasks.py", "book"], clone)
    rec.case("python3 tasks.py book on a fresh clone (set-up of .venv included)", t_book,
             note=f"commit {commit}; {quiet(load_book)}; {machine_label(machine())}")
    load_test = load()
    t_test, log = timed(["python3", "tasks.py", "test"], clone)
    pytest_note = record_pytest(rec, log)
    rec.case("python3 tasks.py test after python3 tasks.py book (fresh clone)", t_test,
             target_s=300.0,
             note=f"ratio = ours/target; {pytest_note}; lint and set-up checks the rest; "
                  f"{quiet(load_test, [load()])}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--full", action="store_true",
                        help="time the full test command (.ci/run: tasks.py test --full)")
    parser.add_argument("--after-book", action="store_true",
                        help="time tasks.py book, then tasks.py test (the previous measure)")
    parser.add_argument("--keep", action="store_true", help="keep the clone")
    parser.add_argument("--dry-run", action="store_true",
                        help="print the steps and the files written, run nothing")
    args = parser.parse_args()
    if args.full and args.after_book:
        parser.error("--full and --after-book are two different measures: give one")
    name = "test_command_full" if args.full else "test_command"
    if args.dry_run:
        steps = ([["python3", "tasks.py", "book"], EVERYDAY_CMD] if args.after_book else
                 [["python3", "tasks.py", "setup"], FULL_CMD if args.full else EVERYDAY_CMD])
        print(f"git clone {SOURCE} into a temporary folder, then in it:")
        for step in steps:
            print("  " + " ".join(step))
        print(f"writes {RESULTS / (name + '.json')}"
              + ("" if args.after_book else f" and {RESULTS / (name + '_cpu.json')}"))
        return
    rec = Recorder(name)
    tmp = Path(tempfile.mkdtemp(prefix="gyrolib-bench-test-"))
    try:
        clone = tmp / "clone"
        subprocess.run(["git", "clone", "--quiet", str(SOURCE), str(clone)], check=True)
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=clone, text=True,
                                capture_output=True, check=True).stdout.strip()
        if args.after_book:
            after_book(rec, clone, commit)
        else:
            fresh_clone(rec, clone, commit, args.full)
    finally:
        if args.keep:
            print(f"kept {tmp}")
        else:
            shutil.rmtree(tmp, ignore_errors=True)
    rec.write(keep_other_classes=True)


if __name__ == "__main__":
    main()
