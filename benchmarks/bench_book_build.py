"""Benchmark of the book build (issue 7, targets 3 and 4; issue 20, item 4).

Measures the wall time of ``jupyter-book build`` (the command ``python3 tasks.py book`` runs)
in one run on this machine:

1. a full clean build (every chapter executed)        target ≤ 90 s, peak memory ≤ 600 MB;
   peer: the same build one chapter at a time (``GYROLIB_BUILD_JOBS=1``), before it
2. each chapter's execution in that build              as logged, no target
3. a rebuild with nothing changed                      target ≤ 20 s; peer: the clean build
4. a rebuild after touching one chapter's code         only that chapter re-executes
5. a rebuild after touching gyrolib                    every chapter re-executes (never stale)
6. the PDF: single-page build + Chromium print         (``tasks.py pdf``'s steps) no target

Peak memory is the largest sum over the build's process tree (Sphinx, the kernel it runs and
the kernel's own subprocesses), sampled every 0.1 s, in MB of 10⁶ bytes, two ways: resident
set sizes (RSS; a shared library's pages count once per process that maps them) and
proportional set sizes (PSS; each shared page split among the processes that share it: the
memory the build occupies).

The peer of the no-op rebuild is the clean build of the same run (how much the jupyter cache
saves); the other cases have a target only.  The builds run in a temporary copy of the
project (so ``_build/`` of the working tree is left alone), with the project's environment.
Writes ``benchmarks/results/book_build.json`` (keeping the latest run of each other CPU class,
which the README's table quotes).  ``--dry-run`` prints the builds without running them.
``--clean-only`` runs cases 1 and 2 only (a
few minutes instead of six builds); ``--no-peer`` leaves out the one-at-a-time build.

    .venv/bin/python benchmarks/bench_book_build.py [--clean-only] [--no-peer] [--dry-run]
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import psutil
from _results import RESULTS, Recorder, children_cpu

SOURCE = Path(__file__).resolve().parents[1]
ROOT = SOURCE  # the copy being built (set in main)
JB = Path(sys.executable).with_name("jupyter-book")
IGNORE = shutil.ignore_patterns("_build", ".venv", ".git", "__pycache__", "*.egg-info",
                                ".ruff_cache", ".pytest_cache", ".hypothesis")


def cmd(builder: str = "html") -> list[str]:
    return [str(JB), "build", str(ROOT), "--builder", builder, "-W", "-n", "--keep-going"]


def _tree_memory(proc: psutil.Process) -> tuple[int, int]:
    """(RSS, PSS) summed over the process tree, in bytes."""
    rss = pss = 0
    for p in [proc, *proc.children(recursive=True)]:
        try:
            info = p.memory_full_info()
            rss += info.rss
            pss += getattr(info, "pss", info.rss)
        except psutil.Error:
            pass
    return rss, pss


#: CPU seconds (user + system) of the last build's process tree (its reaped descendants:
#: Sphinx and the chapters' kernels).
LAST_CPU = [0.0]


def build(builder: str = "html", **extra_env: str) -> tuple[float, tuple[int, int], str]:
    """Run one build; return (seconds, peak (RSS, PSS) of the process tree in bytes, log)
    (its CPU seconds in :data:`LAST_CPU`)."""
    env = dict(os.environ, MPLBACKEND="Agg", **extra_env)
    cpu0 = children_cpu()
    t0 = time.perf_counter()
    popen = subprocess.Popen(cmd(builder), cwd=ROOT, env=env, stdout=subprocess.PIPE,
                             stderr=subprocess.STDOUT, text=True)
    proc = psutil.Process(popen.pid)
    peak = [0, 0]
    stop = threading.Event()

    def sample() -> None:
        while not stop.is_set():
            try:
                rss, pss = _tree_memory(proc)
                peak[0], peak[1] = max(peak[0], rss), max(peak[1], pss)
            except psutil.Error:
                pass
            time.sleep(0.1)

    thread = threading.Thread(target=sample, daemon=True)
    thread.start()
    log, _ = popen.communicate()
    elapsed = time.perf_counter() - t0
    LAST_CPU[0] = children_cpu() - cpu0
    stop.set()
    thread.join()
    if popen.returncode != 0:
        sys.exit(f"build failed:\n{log[-3000:]}")
    return elapsed, (peak[0], peak[1]), log


def chapter_seconds(log: str) -> dict[str, float]:
    """Each chapter's execution time (s) as myst-nb reports it."""
    found = re.findall(r"(\S+)\.md: Executed notebook in ([\d.]+) seconds", log)
    return {Path(p).relative_to(ROOT).as_posix(): float(s) for p, s in found}


def executed(log: str) -> list[str]:
    """Documents executed in this build (from the log lines of ``_ext/parallel_execute.py``,
    or of myst-nb when it executes a document itself)."""
    found = re.findall(r"(\S+)\.md: Execut(?:ing notebook|ed notebook in)", log)
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
    global ROOT
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--clean-only", action="store_true",
                        help="only the clean build and its chapters' execution times")
    parser.add_argument("--no-peer", action="store_true",
                        help="without the one-chapter-at-a-time peer build (half the time)")
    parser.add_argument("--dry-run", action="store_true",
                        help="print the builds and the file written, run nothing")
    args = parser.parse_args()
    if args.dry_run:
        builds = (([] if args.no_peer else ["clean build, one chapter at a time (the peer)"])
                  + ["clean build"] + ([] if args.clean_only else [
                      "rebuild, nothing changed", "rebuild, one chapter changed",
                      "rebuild, gyrolib changed", "single-page build and the PDF print"]))
        print(f"copy {SOURCE} into a temporary folder, then in it: {'; '.join(builds)}")
        print(f"writes {RESULTS / 'book_build.json'}")
        return
    rec = Recorder("book_build")
    with tempfile.TemporaryDirectory(prefix="gyrolib-bench-build-") as tmp:
        ROOT = Path(tmp) / "book"
        shutil.copytree(SOURCE, ROOT, ignore=IGNORE)
        # the peer first: one chapter at a time (GYROLIB_BUILD_JOBS=1), then the default
        if not args.no_peer:
            t_serial, peak_serial, _ = build(GYROLIB_BUILD_JOBS="1")
            shutil.rmtree(ROOT / "_build")
        t_clean, peak, log = build()
        cpu_clean = LAST_CPU[0]
        n_exec = len(executed(log))
        per_chapter = chapter_seconds(log)
        jobs = os.environ.get("GYROLIB_BUILD_JOBS") or str(len(os.sched_getaffinity(0)))
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=SOURCE, text=True,
                                capture_output=True, check=False).stdout.strip() or "?"
        rec.case("full clean build, every chapter executed", t_clean, target_s=90.0,
                 note=f"commit {commit}; ratio = ours/target; {cpu_clean:.0f} CPU-s in all; "
                      f"{jobs} chapters at a time "
                      f"(_ext/parallel_execute.py); {n_exec} chapters executed in "
                      f"{sum(per_chapter.values()):.0f} s of kernel time; peak memory of the "
                      f"build's process tree {peak[1] / 1e6:.0f} MB PSS, "
                      f"{peak[0] / 1e6:.0f} MB RSS (target 600 MB)")
        if not args.no_peer:
            rec.case(f"full clean build: {jobs} chapters at a time vs one at a time", t_clean,
                     peer="GYROLIB_BUILD_JOBS=1", peer_s=t_serial,
                     note=f"ratio = peer/ours; peak memory {peak[1] / 1e6:.0f} MB PSS vs "
                          f"{peak_serial[1] / 1e6:.0f} MB PSS one at a time (RSS "
                          f"{peak[0] / 1e6:.0f} vs {peak_serial[0] / 1e6:.0f} MB)")
        for doc, seconds in sorted(per_chapter.items(), key=lambda kv: -kv[1]):
            rec.case(f"execution of {doc} in the clean build", seconds,
                     note="execution time in the clean build, chapters running concurrently "
                          "(kernel start-up and imports included); _ext/parallel_execute.py "
                          "starts the longest first by these")
        if args.clean_only:
            rec.write(keep_other_classes=True)
            return
        t_noop, _, log = build()
        rec.case("rebuild with nothing changed", t_noop, peer="the clean build of this run",
                 peer_s=t_clean, target_s=20.0,
                 note=f"ratio = clean/no-op; executed: {', '.join(executed(log)) or 'none'}")
        with touched(ROOT / "chapters" / "status.md",
                     "\n```{code-cell} ipython3\n1 + 1\n```\n"):
            t_one, _, log = build()
        rec.case("rebuild after changing one chapter's code (status)", t_one,
                 note=f"executed: {', '.join(executed(log))} (target: only that chapter)")
        with touched(ROOT / "gyrolib" / "units.py", "\n# benchmark touch\n"):
            t_lib, _, log = build()
        rec.case("rebuild after changing gyrolib", t_lib,
                 note=f"{len(executed(log))} chapters re-executed (target: all {n_exec}, "
                      "never a stale result)")
        build()  # back to the unmodified sources, for the PDF
        t_single, _, log = build("singlehtml")
        t0 = time.perf_counter()
        subprocess.run([sys.executable, str(ROOT / "_ext" / "print_pdf.py"),
                        str(ROOT / "_build" / "singlehtml"), str(ROOT / "_build" / "book.pdf")],
                       check=True, capture_output=True, cwd=ROOT)
        t_print = time.perf_counter() - t0
        rec.case("PDF: single-page build + Chromium print", t_single + t_print,
                 note=f"single-page build {t_single:.1f} s (executed: "
                      f"{', '.join(executed(log)) or 'none'}), print {t_print:.1f} s")
    rec.write(keep_other_classes=True)


if __name__ == "__main__":
    main()
