"""Benchmark of the test command (issue 20, item 2).

Times what a contributor runs, on a fresh ``git clone`` of the current commit in a temporary
folder: first ``python3 tasks.py book`` (set-up of ``.venv`` included: the clone has none),
then the test command ``python3 tasks.py test`` (target ≤ 300 s on 2 cores), whose pytest
builds the book once from clean in the background, prints the PDF and runs every test.  The
pytest part and the slowest tests are taken from pytest's own report, and the steps of the
session's book build (the clean build of every chapter among them, target ≤ 90 s) from the
line the test session prints about it.  No peer: the ratio is
the share of the time budget used.  Writes ``benchmarks/results/test_command.json``.

    .venv/bin/python benchmarks/bench_test_command.py [--keep]
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _results import Recorder, load

SOURCE = Path(__file__).resolve().parents[1]


def timed(cmd: list[str], cwd: Path) -> tuple[float, str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith(("VIRTUAL_ENV", "GYROLIB_"))}
    env["PATH"] = os.pathsep.join(p for p in env.get("PATH", "").split(os.pathsep)
                                  if ".venv" not in p)
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, cwd=cwd, env=env, text=True, capture_output=True, check=False)
    elapsed = time.perf_counter() - t0
    log = proc.stdout + proc.stderr
    if proc.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed (exit {proc.returncode}):\n{log[-4000:]}")
    return elapsed, log


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--keep", action="store_true", help="keep the clone")
    args = parser.parse_args()
    rec = Recorder("test_command")
    tmp = Path(tempfile.mkdtemp(prefix="gyrolib-bench-test-"))
    try:
        clone = tmp / "clone"
        subprocess.run(["git", "clone", "--quiet", str(SOURCE), str(clone)], check=True)
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=clone, text=True,
                                capture_output=True, check=True).stdout.strip()
        load_book = load()
        t_book, _ = timed(["python3", "tasks.py", "book"], clone)
        rec.case("python3 tasks.py book on a fresh clone (set-up of .venv included)", t_book,
                 note=f"commit {commit}; 1-minute load average at its start {load_book}")
        load_test = load()
        t_test, log = timed(["python3", "tasks.py", "test"], clone)
        summary = re.findall(r"=+ (\d+ passed.*?) in ([\d.]+)s", log)
        passed, pytest_s = summary[-1] if summary else ("?", "nan")
        slowest = re.findall(r"^\s*([\d.]+)s (call|setup)\s+(\S+)", log, flags=re.M)[:3]
        slow = "; ".join(f"{name.split('::')[-1]} {float(s):.0f} s" for s, _, name in slowest)
        steps = re.search(r"^the session's book: (.*)$", log, flags=re.M)
        if steps:
            for name, secs in re.findall(r"([^,]+?) ([\d.]+) s(?:,|$)", steps.group(1)):
                rec.case(f"in the test command: {name.strip()}", float(secs),
                         target_s=90.0 if "executes every chapter" in name else None,
                         note="the clean build of the book (every chapter executed, "
                              "ratio = ours/target), in the background while other tests run"
                         if "executes every chapter" in name else "")
        rec.case("python3 tasks.py test after python3 tasks.py book (fresh clone)", t_test,
                 target_s=300.0,
                 note=f"ratio = ours/target; pytest {float(pytest_s):.0f} s ({passed}), of which "
                      f"the slowest: {slow or 'see --durations'}; lint and set-up checks the "
                      f"rest; 1-minute load average at its start {load_test}")
    finally:
        if args.keep:
            print(f"kept {tmp}")
        else:
            shutil.rmtree(tmp, ignore_errors=True)
    rec.write()


if __name__ == "__main__":
    main()
