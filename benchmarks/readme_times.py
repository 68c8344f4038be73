"""The README's "How long they take": the two commands' measured times, written from the
result files of ``bench_test_command.py`` and ``bench_book_build.py`` (never typed by hand).

    python3 benchmarks/readme_times.py          # rewrite the block in README.md
    python3 benchmarks/readme_times.py --check  # exit 1 if README.md's block is stale

The block lies between ``<!-- times -->`` and ``<!-- /times -->``.  Each row quotes the time,
the target, the machine (CPU and its class: AVX2 or AVX-512, the issue-36 distinction), the
1-minute load before the run (quiet when at most 1.0; otherwise the time is an upper bound),
the date and the commit the benchmark names.  ``tests/project/test_readme_times.py`` checks that the
README holds what this script writes.
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

#: (command shown, result file, case names in order of preference)
ROWS = (
    ("`python3 tasks.py test` on a fresh clone, set-up included", "test_command.json",
     ("fresh clone to a finished test command, set-up included",)),
    ("`python3 tasks.py book` from clean (numba's cache warm)", "book_build.json",
     ("full clean build, every chapter executed",)),
)


def _machine(m: dict) -> str:
    cls = m.get("cpu_class", "class unknown")
    host = m.get("host_cpu")
    detail = f", {host}" if host and host != "unknown" else ""
    return f"{m.get('cores', '?')}-core {m.get('cpu', '?')}, {cls}{detail}"


def _commit(note: str) -> str:
    m = re.search(r"\bcommit ([0-9a-f]{7,40})\b", note or "")
    return m.group(1) if m else "?"


def block(results: Path = RESULTS) -> str:
    """The README's block, from the result files in ``results``."""
    lines = [START,
             "| command | time | target | machine | load before | measured |",
             "| --- | --- | --- | --- | --- | --- |"]
    for shown, name, cases in ROWS:
        path = results / name
        if not path.is_file():
            lines.append(f"| {shown} | not measured | | | | |")
            continue
        doc = json.loads(path.read_text(encoding="utf-8"))
        by_name = {r["case"]: r for r in doc["results"]}
        row = next((by_name[c] for c in cases if c in by_name), None)
        if row is None:
            lines.append(f"| {shown} | not measured | | | | |")
            continue
        notes = " ".join(r.get("note") or "" for r in doc["results"])
        ld = doc.get("load")
        quiet = ("?" if ld is None else
                 f"{ld:.2f} (quiet)" if ld <= QUIET_LOAD else f"{ld:.2f} (busy: an upper bound)")
        target = "" if row.get("target_s") is None else f"≤ {row['target_s']:.0f} s"
        lines.append(f"| {shown} | {row['ours_s']:.0f} s | {target} | {_machine(doc['machine'])} "
                     f"| {quiet} | {doc['date'][:10]}, commit {_commit(notes)} |")
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
