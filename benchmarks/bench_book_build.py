"""Benchmark of the book build (issue 7, targets 3 and 4).

Measures, in one run on this machine:

1. a full clean build (every chapter executed)        target ≤ 180 s
2. a rebuild with nothing changed                      target ≤ 20 s
3. a rebuild after touching one chapter's code         only that chapter re-executes
4. a rebuild after touching gyrolib                    every chapter re-executes (never stale)
5. the peak memory of the whole build process tree     target ≤ 2 GiB

and prints each figure with its ratio to the target.  The peer of the no-op rebuild is the
clean build measured in the same run (their ratio is printed too).  Run it from the project
root with the project's environment:  .venv/bin/python benchmarks/bench_book_build.py
It rebuilds _build/ in place, and restores any file it touches.
"""

from __future__ import annotations

import os
import platform
import re
import shutil
import subprocess
import sys
import threading
import time
from pathlib import Path

import psutil

ROOT = Path(__file__).resolve().parents[1]
JB = Path(sys.executable).with_name("jupyter-book")
CMD = [str(JB), "build", str(ROOT), "--builder", "html", "-W", "-n", "--keep-going"]


def _tree_rss(proc: psutil.Process) -> int:
    total = 0
    for p in [proc, *proc.children(recursive=True)]:
        try:
            total += p.memory_info().rss
        except psutil.Error:
            pass
    return total


def build() -> tuple[float, int, str]:
    """Run one build; return (seconds, peak RSS of the process tree in bytes, log)."""
    env = dict(os.environ, MPLBACKEND="Agg")
    t0 = time.perf_counter()
    popen = subprocess.Popen(CMD, cwd=ROOT, env=env, stdout=subprocess.PIPE,
                             stderr=subprocess.STDOUT, text=True)
    proc = psutil.Process(popen.pid)
    peak = 0
    stop = threading.Event()

    def sample() -> None:
        nonlocal peak
        while not stop.is_set():
            try:
                peak = max(peak, _tree_rss(proc))
            except psutil.Error:
                pass
            time.sleep(0.1)

    thread = threading.Thread(target=sample, daemon=True)
    thread.start()
    log, _ = popen.communicate()
    elapsed = time.perf_counter() - t0
    stop.set()
    thread.join()
    if popen.returncode != 0:
        sys.exit(f"build failed:\n{log[-3000:]}")
    return elapsed, peak, log


def executed(log: str) -> list[str]:
    """Documents myst-nb executed in this build (from its log lines)."""
    found = re.findall(r"(\S+)\.md: Executing notebook", log)
    return sorted({Path(p).relative_to(ROOT).as_posix() for p in found})


def touched(path: Path, text: str):
    original = path.read_text()

    class _Ctx:
        def __enter__(self):
            path.write_text(original + text)

        def __exit__(self, *exc):
            path.write_text(original)

    return _Ctx()


def main() -> None:
    cpu = next((line.split(":", 1)[1].strip() for line in
                Path("/proc/cpuinfo").read_text().splitlines() if "model name" in line), "?")
    print(f"date {time.strftime('%Y-%m-%d')}, {os.cpu_count()} cores, {cpu}, "
          f"python {platform.python_version()}")
    shutil.rmtree(ROOT / "_build", ignore_errors=True)
    t_clean, peak, log = build()
    print(f"clean build     {t_clean:7.1f} s   target 180 s  ratio {t_clean / 180:.2f}   "
          f"peak memory {peak / 2**30:.2f} GiB (target 2 GiB, ratio {peak / 2**31:.2f})")
    t_noop, _, log = build()
    print(f"no-op rebuild   {t_noop:7.1f} s   target  20 s  ratio {t_noop / 20:.2f}   "
          f"clean/no-op {t_clean / t_noop:.1f}x   executed: {executed(log) or 'none'}")
    with touched(ROOT / "chapters" / "status.md", "\n```{code-cell} ipython3\n1 + 1\n```\n"):
        t_one, _, log = build()
    print(f"one chapter     {t_one:7.1f} s   executed: {executed(log)}")
    with touched(ROOT / "gyrolib" / "units.py", "\n# benchmark touch\n"):
        t_lib, _, log = build()
    print(f"gyrolib touched {t_lib:7.1f} s   executed: {executed(log)}")
    build()  # leave _build consistent with the restored sources


if __name__ == "__main__":
    main()
