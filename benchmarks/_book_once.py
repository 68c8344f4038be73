"""Build the book once, as the test session does, into a folder that is kept.

``bench_budget.py`` gives its tests of the built book this one build
(``GYROLIB_REUSE_BOOK=<folder>/_build``), so that no test's CPU includes the build, and reads
from it the figure measurement's share of a clean build (``GYROLIB_FIGURE_CPU_LOG``, written by
``gyrolib._page_figures.page_record`` in every kernel and in Sphinx).  The three steps are the
test session's own (``tests/conftest.py``: the single-page build that executes every chapter
into a fresh jupyter cache, the PDF print, the HTML build from the cache).

    .venv/bin/python benchmarks/_book_once.py FOLDER
"""

from __future__ import annotations

import json
import os
import sys
import time
from pathlib import Path

from _results import children_cpu

ROOT = Path(__file__).resolve().parents[1]
LOG_NAME = "figure_cpu.jsonl"


def build(folder: Path) -> dict:
    """Build into ``folder`` (``folder/_build``); the record of the build (also written to
    ``folder/_build/budget_build.json``): wall and CPU-s of the process tree, each step's
    seconds, each chapter's execution seconds, and the figure log's path."""
    sys.path.insert(0, str(ROOT / "tests"))
    from conftest import _BookBuild  # the test session's build, steps and flags

    folder.mkdir(parents=True, exist_ok=True)
    log = folder / LOG_NAME
    log.unlink(missing_ok=True)
    os.environ["GYROLIB_FIGURE_CPU_LOG"] = str(log)
    cpu0, t0 = children_cpu(), time.perf_counter()
    b = _BookBuild()
    b._build_into(folder)
    record = {"folder": str(folder), "wall_s": round(time.perf_counter() - t0, 1),
              "cpu_s": round(children_cpu() - cpu0, 1), "error": b.error,
              "steps": b.book.seconds if b.book else [],
              "chapters": b.book.chapters if b.book else [], "figure_log": str(log),
              "build_log_tail": {k: v[-3000:] for k, v in b.logs.items()}}
    (folder / "_build").mkdir(exist_ok=True)
    (folder / "_build" / "budget_build.json").write_text(json.dumps(record, indent=1))
    return record


if __name__ == "__main__":
    rec = build(Path(sys.argv[1]).resolve())
    print(json.dumps({k: v for k, v in rec.items() if k != "build_log_tail"}, indent=1))
    sys.exit(1 if rec["error"] else 0)
