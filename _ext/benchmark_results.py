"""Sphinx extension: the ``{benchmark-results}`` directive of the Performance page.

Renders every ``benchmarks/results/*.json`` that the benchmark scripts write (format in
``benchmarks/_results.py``): per file, what the script measures (the first paragraph of its
docstring), when and on which machine under which load, and one table row per case.  A new
results file appears on the page at the next build without editing the page: the page is
re-read at every build (it executes no code, so that costs nothing), and each file is a
dependency of it.  A malformed file fails the build with its name and the missing field.
"""

from __future__ import annotations

import ast
import json
import re
from pathlib import Path

from docutils import nodes
from docutils.statemachine import StringList
from sphinx.util.docutils import SphinxDirective

DOC = "chapters/benchmarks"
KEYS = ("benchmark", "date", "machine", "load", "results")
CASE_KEYS = ("case", "ours_s", "peer", "peer_s", "ratio", "target_s", "note")
MACHINE_KEYS = ("cpu", "cores", "python", "numpy")


def _seconds(x) -> str:
    if x is None:
        return "—"
    x = float(x)
    return f"{x:.3g}" if x < 100 else f"{x:.0f}"


_OPTION = re.compile(r"(?<![\w`])(--[A-Za-z][\w-]*)")


def _cell(text) -> str:
    """A table cell: pipes escaped, command-line options as code (smartquotes would turn
    ``--workers`` into an en dash)."""
    if text in (None, ""):
        return "—"
    return _OPTION.sub(r"`\1`", str(text).replace("|", "\\|").replace("\n", " "))


def load(path: Path) -> dict:
    """A results file, checked against the format."""
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except json.JSONDecodeError as exc:
        raise ValueError(f"{path.name}: not JSON ({exc})") from exc
    missing = [k for k in KEYS if k not in doc]
    missing += [f"machine.{k}" for k in MACHINE_KEYS if k not in (doc.get("machine") or {})]
    for i, row in enumerate(doc.get("results") or []):
        missing += [f"results[{i}].{k}" for k in CASE_KEYS if k not in row]
    if missing or not doc.get("results"):
        raise ValueError(f"{path.name}: missing {missing or ['results (empty)']}")
    return doc


def purpose(script: Path) -> str:
    """The first paragraph of a benchmark script's docstring after its title line."""
    if not script.is_file():
        return ""
    doc = ast.get_docstring(ast.parse(script.read_text(encoding="utf-8"))) or ""
    paragraphs = [" ".join(p.split()) for p in doc.split("\n\n") if p.strip()]
    return paragraphs[1] if len(paragraphs) > 1 else (paragraphs[0] if paragraphs else "")


def markdown(doc: dict, script: Path) -> list[str]:
    m = doc["machine"]
    lines = [f"**`{doc['benchmark']}`** — `benchmarks/{script.name}`"
             if script.is_file() else f"**`{doc['benchmark']}`**", ""]
    what = purpose(script)
    if what:
        # the docstring's **emphasis** stays Markdown; a lone * (a product) is escaped
        lines += [re.sub(r"(?<!\*)\*(?!\*)", r"\\*", what), ""]
    load_txt = "unknown" if doc["load"] is None else f"{float(doc['load']):.2f}"
    lines += [f"Run {doc['date']} on {_cell(m['cpu'])}, {m['cores']} cores, Python "
              f"{m['python']}, NumPy {m['numpy']}; 1-minute load average at the start "
              f"{load_txt}.", ""]
    lines += ["| case | ours (s) | peer | peer (s) | ratio | target (s) | note |",
              "| --- | --- | --- | --- | --- | --- | --- |"]
    for row in doc["results"]:
        ratio = "—" if row["ratio"] is None else f"{float(row['ratio']):.3g}"
        lines.append(f"| {_cell(row['case'])} | {_seconds(row['ours_s'])} | "
                     f"{_cell(row['peer'])} | {_seconds(row['peer_s'])} | {ratio} | "
                     f"{_seconds(row['target_s'])} | {_cell(row['note'])} |")
    return [*lines, ""]


class BenchmarkResults(SphinxDirective):
    """``{benchmark-results} benchmarks/results``: render every results file in the folder."""

    required_arguments = 1

    def run(self) -> list[nodes.Node]:
        folder = Path(self.env.srcdir) / self.arguments[0]
        files = sorted(folder.glob("*.json"))
        if not files:
            raise self.error(f"no results file in {folder}: run the scripts in benchmarks/")
        lines: list[str] = []
        for path in files:
            self.env.note_dependency(str(path))
            try:
                doc = load(path)
            except ValueError as exc:
                raise self.error(str(exc)) from exc
            lines += markdown(doc, folder.parent / f"bench_{doc['benchmark']}.py")
        container = nodes.container()
        self.state.nested_parse(StringList(lines, source=str(folder)), self.content_offset,
                                container)
        return container.children


def _always_reread(app, env, added, changed, removed):
    """Re-read the Performance page at every build, so a new results file shows up."""
    return [DOC] if DOC in env.found_docs and DOC not in changed else []


def setup(app):
    app.add_directive("benchmark-results", BenchmarkResults)
    app.connect("env-get-outdated", _always_reread)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1"}
