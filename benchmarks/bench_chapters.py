"""Where the book build's core-seconds go: each chapter's code, cell by cell (issue 36,
item 3).

Each chapter of ``chapters/`` is executed in a fresh Python process (IPython's shell, the
Agg backend, OpenBLAS on one thread, as the build's kernels run), one at a time, after the
ledger has been computed once into a memo that every chapter then reads
(``GYROLIB_LEDGER_MEMO``, as in the build, where the first chapter to ask computes it and the
others wait).  A chapter's CPU time is that of its whole process (interpreter start-up,
imports, every cell, and the processes it started and waited for); its three most expensive
cells are named.  The ledger's own computation is one more case.  There is no peer: this is
a profile, read beside ``book_build.json`` (the clean build's wall time, Sphinx included).
Writes ``benchmarks/results/chapters.json``.

    nice -n 10 .venv/bin/python benchmarks/bench_chapters.py [--only gc_race calibrate]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _results import Recorder, children_cpu, own_cpu

ROOT = Path(__file__).resolve().parents[1]
CHAPTERS = ROOT / "chapters"


def run_one(name: str) -> None:
    """Execute chapter ``name`` cell by cell in this process; print a JSON report."""
    import io
    from contextlib import redirect_stdout

    import jupytext
    import matplotlib
    from IPython.core.interactiveshell import InteractiveShell

    matplotlib.use("Agg")
    os.chdir(CHAPTERS)
    nb = jupytext.read(CHAPTERS / f"{name}.md")
    shell = InteractiveShell.instance()
    cells = []
    for i, cell in enumerate(nb.cells):
        if cell.cell_type != "code":
            continue
        # line magics (%matplotlib inline) need a kernel; the backend is set above
        source = "\n".join(line for line in cell.source.splitlines()
                           if not line.lstrip().startswith("%"))
        c0, w0 = own_cpu() + children_cpu(), time.perf_counter()
        with redirect_stdout(io.StringIO()):
            result = shell.run_cell(source, store_history=False)
        if not result.success:
            raise SystemExit(f"{name}: cell {i} failed: "
                             f"{result.error_before_exec or result.error_in_exec!r}")
        first = next((line for line in cell.source.splitlines()
                      if line.strip() and not line.lstrip().startswith(("#", "%", ":"))), "")
        # backticks and stars would read as markup on the Performance page
        first = first[:80].replace("`", "'").replace("*", "×")
        cells.append({"cell": i, "cpu_s": own_cpu() + children_cpu() - c0,
                      "wall_s": time.perf_counter() - w0, "first_line": first})
    print(json.dumps({"cells": cells}))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--only", nargs="*", help="these chapters (default: all)")
    parser.add_argument("--one", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.one:
        run_one(args.one)
        return
    # the chapters that are notebooks (the build executes them); a plain page has no code cell
    names = args.only or sorted(p.stem for p in CHAPTERS.glob("*.md")
                                if "```{code-cell}" in p.read_text(encoding="utf-8"))
    rec = Recorder("chapters")
    with tempfile.TemporaryDirectory(prefix="gyrolib-bench-chapters-") as memo:
        env = dict(os.environ, MPLBACKEND="Agg", GYROLIB_LEDGER_MEMO=memo)
        env.setdefault("OPENBLAS_NUM_THREADS", "1")
        c0, w0 = children_cpu(), time.perf_counter()
        subprocess.run([sys.executable, "-c", "from gyrolib.book import ledger; "
                        "ledger.collect()"], env=env, check=True, cwd=ROOT)
        rec.case("ledger.collect(), once per build (the chapters read its memo)",
                 children_cpu() - c0,
                 note=f"CPU-s of the whole process (imports included); wall "
                      f"{time.perf_counter() - w0:.1f} s")
        total = 0.0
        for name in names:
            c0, w0 = children_cpu(), time.perf_counter()
            out = subprocess.run([sys.executable, __file__, "--one", name], env=env,
                                 capture_output=True, text=True, cwd=ROOT)
            cpu, wall = children_cpu() - c0, time.perf_counter() - w0
            if out.returncode != 0:
                sys.exit(f"{name} failed:\n{out.stderr[-2000:]}")
            cells = json.loads(out.stdout.strip().splitlines()[-1])["cells"]
            top = sorted(cells, key=lambda c: -c["cpu_s"])[:3]
            total += cpu
            rec.case(f"chapter {name}: its whole process", cpu,
                     note=f"CPU-s (start-up, imports, {len(cells)} code cells, the processes "
                          f"it waited for); wall {wall:.1f} s; most expensive cells: "
                          + "; ".join(f"{c['cpu_s']:.1f} CPU-s cell {c['cell']} "
                                      f"({c['first_line']})" for c in top))
        rec.case(f"all {len(names)} chapters, one at a time", total,
                 note="the sum of the cases above (the ledger not included); the build runs "
                      "two kernels at a time, and Sphinx's own work is in book_build.json")
    rec.write()


if __name__ == "__main__":
    main()
