"""Sphinx extension: the ``{benchmark-results}`` directive of the Performance page.

Renders every ``benchmarks/results/*.json`` that the benchmark scripts write (format in
``benchmarks/_results.py``) as a report for readers (issue 35, item 4): per file, what was
measured (the first line of its script's docstring, without development references), when,
on which machine class under which load and against which peers; a bar chart of how many
times faster each case is than its peer; one table row per case, with the notes below the
table so that it fits a phone.  A new
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
MACHINE_KEYS = ("cpu", "cpu_class", "host_cpu", "cores", "python", "numpy")


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


_DEV_NOTE = re.compile(r"\s*\((?:issues?|targets?|commit)\b[^)]*\)")


def title(script: Path, name: str) -> str:
    """What a benchmark measures, for a reader: the first line of its script's docstring,
    without the development references in parentheses ("(issues 13, 18)")."""
    if not script.is_file():
        return name
    doc = ast.get_docstring(ast.parse(script.read_text(encoding="utf-8"))) or ""
    first = " ".join(doc.split("\n\n")[0].split()) if doc else name
    first = _DEV_NOTE.sub("", first).replace("``", "").strip()
    first = re.split(r"(?<=[.?])\s(?=[A-Z])", first)[0].rstrip(".")  # its first sentence
    first = re.sub(r"^Benchmark(?: of)?:?\s*", "", first).strip()
    return (first[:1].upper() + first[1:]) if first else name


def _machine(m: dict) -> str:
    return (f"{_cell(cpu_label(m))}, {m['cores']} cores; Python {m['python']}, "
            f"NumPy {m['numpy']}")


def figure_html(doc: dict) -> str:
    """A bar chart of how many times faster each case is than its peer (peer/ours), as an
    ``<img>`` with the PNG inline (2x pixels, shown at half; text 10 pt on a 5-in figure;
    its text measured in the PNG, as the chapters' figures); empty when no case has a
    peer."""
    rows = [(" ".join(str(r["case"]).split()), float(r["peer_s"]) / float(r["ours_s"]))
            for r in doc["results"] if r.get("peer_s") and r.get("ours_s")]
    if not rows:
        return ""
    import base64
    import io

    from matplotlib.figure import Figure

    fig = Figure(figsize=(5.0, 0.9 + 0.42 * len(rows)), dpi=96, layout="constrained")
    ax = fig.subplots()
    labels = [c if len(c) <= 26 else c[:25] + "…" for c, _ in rows]  # the table has them whole
    ratios = [r for _, r in rows]
    ax.barh(range(len(rows)), ratios, color=["#1f77b4" if r >= 1 else "#d62728" for r in ratios])
    ax.axvline(1.0, color="0.2", lw=1)
    ax.set_xscale("log")
    # over less than a decade the log axis labels its minor ticks (1.2×10⁰, 1.4×10⁰, …), which
    # overprint: a few labels, as plain numbers
    import math

    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    low, high = ax.get_xlim()
    decades = math.log10(high / low) if low > 0 and high > low else 2.0
    # and over more than two decades, 1-2-5 labels overprint too (0.005, 0.01, 0.02 …):
    # the decades alone
    subs = ((1.0,) if decades > 2.0 else (1.0, 2.0, 5.0) if decades > 1.0
            else (1.0, 1.2, 1.5, 2.0, 3.0, 5.0, 7.0))
    ax.xaxis.set_major_locator(LogLocator(base=10.0, subs=subs))
    ax.xaxis.set_major_formatter(FuncFormatter(lambda x, _: f"{x:g}"))
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_yticks(range(len(rows)), labels, fontsize=10)
    ax.invert_yaxis()
    ax.tick_params(axis="x", labelsize=10)
    ax.set_xlabel("peer time / our time", fontsize=10)  # > 1: ours faster (the page says)
    buf = io.BytesIO()
    from gyrolib._page_figures import PNG_KEY, page_record

    # the measurement as the page shows it, read back by tests/book/test_page_figures.py
    fig.savefig(buf, format="png", dpi=192, metadata={PNG_KEY: page_record(fig)})
    width, height = (round(x * 96) for x in fig.get_size_inches())
    alt = ("Bar chart of how many times faster each case runs than its peer: "
           + "; ".join(f"{c}: {r:.3g}" for c, r in rows))
    alt = alt.replace('"', "'").replace("<", "(").replace(">", ")")
    data = base64.b64encode(buf.getvalue()).decode()
    return (f'<img class="gyrolib-benchmark-figure" src="data:image/png;base64,{data}" '
            f'alt="{alt}" width="{width}" height="{height}">')


def cpu_label(m: dict) -> str:
    """The CPU with its class (AVX2, AVX-512, or "class unknown" for the files written before
    the class was recorded), family, model and numba's host CPU name."""
    if m["cpu_class"] == "class unknown":
        return f"{m['cpu']} (class unknown)"
    return (f"{m['cpu']}, {m['cpu_class']} (family {m.get('cpu_family')}, model "
            f"{m.get('cpu_model')}, {m['host_cpu']})")


def markdown(doc: dict, script: Path) -> list[str]:
    """The report of one results file: what was measured, on which machine, against which
    peer; the figure (:func:`figure_html`, placed by the directive); the table, with the
    notes below it."""
    m = doc["machine"]
    name = doc["benchmark"]
    source = f"`benchmarks/{script.name}`" if script.is_file() else "its script"
    lines = [f"**{title(script, name)}** (`{name}`, {source})", ""]
    load_txt = "unknown" if doc["load"] is None else f"{float(doc['load']):.2f}"
    peers = list(dict.fromkeys(_cell(r["peer"]) for r in doc["results"] if r["peer"]))
    lines += [f"Measured {doc['date']} on {_machine(m)}; 1-minute load average at the start "
              f"{load_txt}."
              + (f"  Peers, timed in the same run on the same machine: {'; '.join(peers)}."
                 if peers else "  No peer: times against a target."), ""]
    lines += ["| case | ours (s) | peer (s) | ratio | target (s) |",
              "| --- | --- | --- | --- | --- |"]
    notes = []
    for row in doc["results"]:
        ratio = "—" if row["ratio"] is None else f"{float(row['ratio']):.3g}"
        case = _cell(row["case"])
        if row["note"]:
            notes.append(f"{len(notes) + 1}. {_cell(row['note'])}")
            case += f" [{len(notes)}]"
        lines.append(f"| {case} | {_seconds(row['ours_s'])} | {_seconds(row['peer_s'])} | "
                     f"{ratio} | {_seconds(row['target_s'])} |")
    if notes:
        lines += ["", "Notes:", "", *notes]
    return [*lines, ""]


class BenchmarkResults(SphinxDirective):
    """``{benchmark-results} benchmarks/results``: render every results file in the folder."""

    required_arguments = 1

    def run(self) -> list[nodes.Node]:
        folder = Path(self.env.srcdir) / self.arguments[0]
        files = sorted(folder.glob("*.json"))
        if not files:
            raise self.error(f"no results file in {folder}: run the scripts in benchmarks/")
        lines: list[nodes.Node] = []
        for path in files:
            self.env.note_dependency(str(path))
            try:
                doc = load(path)
            except ValueError as exc:
                raise self.error(str(exc)) from exc
            part = nodes.container()
            self.state.nested_parse(
                StringList(markdown(doc, folder.parent / f"bench_{doc['benchmark']}.py"),
                           source=str(path)), self.content_offset, part)
            children = list(part.children)
            figure = figure_html(doc)
            if figure:  # after the paragraph that says what was measured
                children.insert(min(2, len(children)), nodes.raw("", figure, format="html"))
            lines.extend(children)
        return lines


def _always_reread(app, env, added, changed, removed):
    """Re-read the Performance page at every build, so a new results file shows up."""
    return [DOC] if DOC in env.found_docs and DOC not in changed else []


def setup(app):
    app.add_directive("benchmark-results", BenchmarkResults)
    app.connect("env-get-outdated", _always_reread)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1"}
