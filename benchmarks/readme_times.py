"""The README's "How long they take": the commands' measured times, one row per command and
CPU class, written from the result files of ``bench_test_command.py`` (the everyday and the
full test command) and ``bench_book_build.py`` (never typed by hand).

    python3 benchmarks/readme_times.py          # rewrite the block in README.md
    python3 benchmarks/readme_times.py --check  # exit 1 if README.md's block is stale

The block lies between ``<!-- times -->`` and ``<!-- /times -->``.  Each command has a row
for each CPU class (:data:`CLASSES`, and any other class a file holds): the latest run of
that class (a results file keeps the latest run of each class, ``_results.Recorder.write``),
or "not measured".  A row quotes the time, the target, whether the target is met (a time
measured on a busy machine is an upper bound: a miss there says so), the machine (CPU and its
class), the 1-minute load before the run (quiet when at most 1.0), the date, the commit the
benchmark names and how many tests passed.  ``tests/project/test_readme_times.py`` checks
that the README holds what this script writes.
"""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results"
START, END = "<!-- times -->", "<!-- /times -->"
QUIET_LOAD = 1.0

#: The CPU classes every command has a row for: the common 2-core AVX2 class the targets are
#: set for, and the AVX-512 development machine.
CLASSES = ("AVX2", "AVX-512")

#: (command shown, result file, case names in order of preference)
ROWS = (
    ("`python3 tasks.py test` on a fresh clone, set-up included", "test_command.json",
     ("fresh clone to a finished test command, set-up included",)),
    ("`python3 tasks.py test --full` (CI) on a fresh clone, set-up included",
     "test_command_full.json",
     ("fresh clone to a finished full test command, set-up included",)),
    ("`python3 tasks.py book` from clean (numba's cache warm)", "book_build.json",
     ("full clean build, every chapter executed",)),
)


def _machine(m: dict) -> str:
    host = m.get("host_cpu")
    detail = f", {host}" if host and host != "unknown" else ""
    return f"{m.get('cores', '?')}-core {m.get('cpu', '?')}{detail}"


def _commit(note: str) -> str:
    m = re.search(r"\bcommit ([0-9a-f]{7,40})\b", note or "")
    return m.group(1) if m else "?"


def _passed(note: str) -> str:
    m = re.search(r"\b(\d+ passed(?:, \d+ skipped)?)", note or "")
    return f", {m.group(1)}" if m else ""


def runs_by_class(doc: dict) -> dict[str, dict]:
    """The file's runs, CPU class -> its latest run (``benchmarks/_results.py``'s
    ``runs_by_class``, repeated here so that the script runs without the environment)."""
    runs: dict[str, dict] = {}
    for run in [doc, *doc.get("other_classes", [])]:
        cls = run.get("machine", {}).get("cpu_class", "class unknown")
        if cls not in runs or run["date"] > runs[cls]["date"]:
            runs[cls] = run
    return runs


def verdict(seconds: float, target: float | None, load: float | None) -> str:
    """Whether the time meets the target, said plainly; on a busy machine (or an unknown
    load) the time is an upper bound, and a miss says so.

    >>> verdict(685.0, 360.0, 1.58), verdict(300.0, 360.0, 0.2), verdict(400.0, 360.0, 0.2)
    ('**missed** (1.9× the target; busy: an upper bound)', 'met', '**missed** (1.1× the target)')
    """
    if target is None:
        return "no target"
    if seconds <= target:
        return "met"
    busy = "" if load is not None and load <= QUIET_LOAD else "; busy: an upper bound"
    return f"**missed** ({seconds / target:.1f}× the target{busy})"


def block(results: Path = RESULTS) -> str:
    """The README's block, from the result files in ``results``."""
    lines = [START,
             "| command | CPU class | time | target | target met? | machine | load before "
             "| measured |",
             "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    for shown, name, cases in ROWS:
        path = results / name
        runs = (runs_by_class(json.loads(path.read_text(encoding="utf-8")))
                if path.is_file() else {})
        classes = [*CLASSES, *sorted(c for c in runs if c not in CLASSES)]
        for cls in classes:
            run = runs.get(cls)
            by_name = {r["case"]: r for r in run["results"]} if run else {}
            row = next((by_name[c] for c in cases if c in by_name), None)
            if row is None:
                lines.append(f"| {shown} | {cls} | not measured | | | | | |")
                continue
            notes = " ".join(r.get("note") or "" for r in run["results"])
            ld = run.get("load")
            quiet = ("?" if ld is None else f"{ld:.2f} (quiet)" if ld <= QUIET_LOAD
                     else f"{ld:.2f} (busy: an upper bound)")
            target = None if row.get("target_s") is None else float(row["target_s"])
            shown_target = "" if target is None else f"≤ {target:.0f} s"
            lines.append(f"| {shown} | {cls} | {row['ours_s']:.0f} s | {shown_target} | "
                         f"{verdict(float(row['ours_s']), target, ld)} | "
                         f"{_machine(run['machine'])} | {quiet} | {run['date'][:10]}, commit "
                         f"{_commit(notes)}{_passed(notes)} |")
    lines.append(END)
    return "\n".join(lines)


def rewrite(text: str, new_block: str) -> str:
    """``text`` with its block replaced (ValueError if it has none)."""
    i, j = text.find(START), text.find(END)
    if i < 0 or j < i:
        raise ValueError(f"README.md has no {START} … {END} block")
    return text[:i] + new_block + text[j + len(END):]


def main(argv: list[str]) -> int:
    readme = ROOT / "README.md"
    text = readme.read_text(encoding="utf-8")
    new = rewrite(text, block())
    if "--check" in argv:
        if new != text:
            print("README.md's measured times are stale: run python3 benchmarks/readme_times.py",
                  file=sys.stderr)
            return 1
        return 0
    readme.write_text(new, encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
