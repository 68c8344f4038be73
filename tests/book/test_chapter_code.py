"""Verdicts in view: how much of the chapters' code the pages hide.

The chapters are read as notebooks by jupytext (the reader the build itself uses), so a cell's
tags are the ones myst-nb sees.  A code line is a non-blank line of a code cell's source; it is
*removed* from the page when its cell is tagged ``remove-cell`` or ``remove-input``
(``hide-input`` cells stay on the page, collapsed, and count as shown).  The share is computed
over whatever chapters exist, so a chapter added or rewritten by anyone is counted.

Further checks of the pages: no shown cell only glues numbers for the prose; no removed cell
chooses a sentence of the prose by a condition (the call that decides a verdict is in view);
benchmark results appear only on the Performance page.  Each check is also run on a small
notebook built to break it, so that it can fail.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import jupytext
import pytest

ROOT = Path(__file__).resolve().parents[2]
CHAPTERS = sorted((ROOT / "chapters").glob("*.md"))

#: The issue's limit for the share of chapter code lines removed from the pages.
MAX_REMOVED_SHARE = 0.35
REMOVING_TAGS = {"remove-cell", "remove-input"}
GLUE_CALLS = {"gl", "glue"}


def code_lines(nb) -> tuple[int, int]:
    """(code lines, removed code lines) of a notebook."""
    total = removed = 0
    for cell in nb.cells:
        if cell.cell_type != "code":
            continue
        n = sum(1 for line in cell.source.splitlines() if line.strip())
        total += n
        if REMOVING_TAGS & set(cell.metadata.get("tags", [])):
            removed += n
    return total, removed


def _is_glue_call(stmt: ast.stmt) -> bool:
    if not (isinstance(stmt, ast.Expr) and isinstance(stmt.value, ast.Call)):
        return False
    func = stmt.value.func
    name = func.id if isinstance(func, ast.Name) else getattr(func, "attr", None)
    return name in GLUE_CALLS


def bare_glue_cells(nb) -> list[str]:
    """The first line of every shown code cell that consists only of glue calls
    (``gl(...)`` / ``glue(...)``): a cell the reader sees that only feeds the prose."""
    found = []
    for cell in nb.cells:
        if cell.cell_type != "code" or REMOVING_TAGS & set(cell.metadata.get("tags", [])):
            continue
        try:
            body = ast.parse(cell.source).body
        except SyntaxError:  # IPython magics: not a plain glue cell
            continue
        if body and all(_is_glue_call(s) for s in body):
            found.append(cell.source.splitlines()[0])
    return found


def _read(path: Path):
    return jupytext.read(path)


def _notebook(cells: list[tuple[str, list[str]]]):
    """A notebook of code cells (source, tags), as jupytext reads one from MyST."""
    text = ["---", "jupytext:", "  text_representation:", "    extension: .md",
            "    format_name: myst", "---", ""]
    for source, tags in cells:
        text.append("```{code-cell} ipython3")
        if tags:
            text.append(f":tags: [{', '.join(tags)}]")
        text += [source, "```", ""]
    return jupytext.reads("\n".join(text), fmt="md:myst")


def test_the_share_of_removed_chapter_code_is_at_most_35_percent():
    assert CHAPTERS, "no chapters found"
    per_chapter = {p.stem: code_lines(_read(p)) for p in CHAPTERS}
    total = sum(t for t, _ in per_chapter.values())
    removed = sum(r for _, r in per_chapter.values())
    share = removed / total
    detail = ", ".join(f"{name} {r}/{t}" for name, (t, r) in per_chapter.items() if t)
    print(f"\nremoved chapter code: {removed} of {total} lines ({100 * share:.1f} %): {detail}")
    assert share <= MAX_REMOVED_SHARE, (
        f"{removed} of {total} chapter code lines ({100 * share:.1f} %) are removed from the "
        f"pages (remove-cell / remove-input); at most {100 * MAX_REMOVED_SHARE:.0f} % may be. "
        f"Per chapter (removed/total): {detail}")


def test_code_lines_counts_removed_cells_and_ignores_blank_lines():
    nb = _notebook([("x = 1\n\ny = 2", []), ("z = 3", ["remove-cell"]),
                    ("w = 4\nv = 5", ["remove-input"]), ("u = 6", ["hide-input"])])
    assert code_lines(nb) == (6, 3)


def test_the_share_check_fails_on_a_chapter_that_hides_most_of_its_code():
    nb = _notebook([("a = 1", []), ("b = 2\nc = 3", ["remove-input"])])
    total, removed = code_lines(nb)
    assert removed / total == pytest.approx(2 / 3, abs=1e-12)
    assert removed / total > MAX_REMOVED_SHARE


@pytest.mark.parametrize("path", CHAPTERS, ids=[p.stem for p in CHAPTERS])
def test_no_chapter_shows_a_bare_glue_cell(path):
    assert not bare_glue_cells(_read(path)), (
        f"{path.name} shows cells that only glue numbers for the prose (hide them, or put the "
        f"glue next to the computation it reports): {bare_glue_cells(_read(path))}")


def test_the_bare_glue_check_finds_one_and_only_one():
    nb = _notebook([
        ('gl("a", 1.0)\nglue("b", "2", display=False)', []),  # bare: found
        ('gl("c", 1.0)', ["remove-cell"]),                    # hidden: fine
        ('x = f(2)\ngl("d", x)', []),                          # a computation: fine
        ("%time gl('e', 1)", []),                              # a magic: not plain Python
    ])
    assert bare_glue_cells(nb) == ['gl("a", 1.0)']


# ----------------------------------------------------------------------------- verdicts

#: Chapters of other developers that still pick sentences in hidden cells (the
#: rule is theirs to apply there); not strict, since they change while this test exists.
PENDING_HIDDEN_VERDICTS: dict[str, str] = {}


def hidden_choices(nb) -> list[str]:
    """Conditional expressions or statements in removed cells that choose between phrases
    (string constants with a space): a sentence of the prose decided out of the reader's
    sight.  A choice of number format is not one."""
    found = []
    for cell in nb.cells:
        if cell.cell_type != "code" or not REMOVING_TAGS & set(cell.metadata.get("tags", [])):
            continue
        try:
            tree = ast.parse(cell.source)
        except SyntaxError:
            continue
        for node in ast.walk(tree):
            if not isinstance(node, ast.IfExp | ast.If):
                continue
            branches = ([node.body, node.orelse] if isinstance(node, ast.IfExp)
                        else [ast.Module(body=node.body + node.orelse, type_ignores=[])])
            if any(isinstance(n, ast.Constant) and isinstance(n.value, str) and " " in n.value
                   for b in branches for n in ast.walk(b)):
                found.append(" ".join(ast.get_source_segment(cell.source, node).split())[:100])
    return found


@pytest.mark.parametrize("path", [
    pytest.param(p, marks=pytest.mark.xfail(strict=False, reason=PENDING_HIDDEN_VERDICTS[p.stem]))
    if p.stem in PENDING_HIDDEN_VERDICTS else p for p in CHAPTERS], ids=lambda p: p.stem)
def test_no_hidden_cell_picks_a_sentence(path):
    found = hidden_choices(_read(path))
    assert not found, (f"{path.name} decides sentences of its prose in hidden cells (show the "
                       f"cell, or read the verdict from the ledger): {found}")


def test_the_hidden_choice_check_finds_one_and_only_one():
    nb = _notebook([
        ('glue("v", "holds" if x < 1 else "fails badly")', ["remove-cell"]),  # found
        ('glue("w", "holds" if x < 1 else "fails badly")', []),               # shown: fine
        ('gl("n", x, ".2f" if x > 1 else ".3f")', ["remove-cell"]),           # a format: fine
    ])
    assert hidden_choices(nb) == ['"holds" if x < 1 else "fails badly"']


# ----------------------------------------------------------------------------- openings

#: Reference pages (what they are is their finding) and, pending, other developers' chapters.
REFERENCE_PAGES = {"benchmarks", "status", "references", "citing"}
PENDING_OPENINGS: dict[str, str] = {}
FINDING = re.compile(r"^\*\*(The findings, )?[Ii]n short\.\*\*")


def opening(text: str) -> str:
    """The first paragraph after the chapter's ``#`` title (labels and blank lines skipped)."""
    lines = text.split("\n# ", 1)[1].splitlines()[1:]
    para: list[str] = []
    for line in lines:
        if not line.strip() or line.startswith("```{raw}") or line.startswith("<style"):
            if para:
                break
            continue
        if line.startswith("```") and not para:  # a raw block before the prose
            continue
        para.append(line)
    return " ".join(para)


@pytest.mark.parametrize("path", [
    pytest.param(p, marks=pytest.mark.xfail(strict=False, reason=PENDING_OPENINGS[p.stem]))
    if p.stem in PENDING_OPENINGS else p
    for p in CHAPTERS if p.stem not in REFERENCE_PAGES], ids=lambda p: p.stem)
def test_each_chapter_opens_with_its_finding(path):
    first = opening(path.read_text(encoding="utf-8"))
    assert FINDING.match(first), (f"{path.name} should open with its finding in a few plain "
                                  f"sentences (a paragraph starting '**In short.**'); it "
                                  f"opens: {first[:120]!r}")


def test_the_opening_check_reads_the_first_paragraph():
    text = "---\nfront: matter\n---\n\n(label)=\n# Title\n\n**In short.**  It works.\n\nMore.\n"
    assert FINDING.match(opening(text))
    assert not FINDING.match(opening(text.replace("**In short.**  It works.\n\n", "")))


# ----------------------------------------------------------------------------- benchmarks

#: The Performance page: the only chapter that shows benchmark results.
PERFORMANCE_PAGE = "benchmarks"
#: Chapters known to break the rule, each with the reason; the mark is strict, so the test
#: fails as soon as the chapter is fixed, and the entry must then go.
KNOWN_BENCHMARK_TABLES: dict[str, str] = {}


#: Results files of statistical studies, not timings, that a chapter may read: the false-alarm
#: rate and coverage of ``calibrate gc`` over 100 clean seeds and the faults, which
#: the calibrating chapter reports as its evidence; the Performance page shows them too.
STUDY_RESULTS = ("calibrate_faults.json",)


def reads_benchmark_results(nb) -> bool:
    """Whether a notebook's code reads the benchmark scripts' results files (other than the
    statistical studies of :data:`STUDY_RESULTS`)."""
    def timing(src: str) -> bool:
        if "benchmarks" not in src or "results" not in src:
            return False
        names = set(re.findall(r"[\w.-]+\.json", src))
        return not names or not names <= set(STUDY_RESULTS) | {"truth.json"}
    return any(cell.cell_type == "code" and timing(cell.source) for cell in nb.cells)


@pytest.mark.parametrize("path", [
    pytest.param(p, marks=pytest.mark.xfail(strict=True, reason=KNOWN_BENCHMARK_TABLES[p.stem]))
    if p.stem in KNOWN_BENCHMARK_TABLES else p
    for p in CHAPTERS if p.stem != PERFORMANCE_PAGE], ids=lambda p: p.stem)
def test_benchmark_results_are_shown_only_on_the_performance_page(path):
    assert not reads_benchmark_results(_read(path)), (
        f"{path.name} shows benchmark results: they belong on the Performance page "
        f"(chapters/{PERFORMANCE_PAGE}.md), which shows every results file")


def test_the_benchmark_check_finds_a_chapter_that_reads_results():
    nb = _notebook([('bench = json.loads(Path("benchmarks/results/x.json").read_text())', [])])
    assert reads_benchmark_results(nb)
    assert not reads_benchmark_results(_notebook([("x = 1", [])]))
    # the coverage study a chapter may cite, not a timing; a timing beside it is still found
    study = 'st = json.loads((R / "benchmarks" / "results" / "calibrate_faults.json").read_text())'
    timing = '\nt = Path("benchmarks/results/calibrate.json")'
    assert not reads_benchmark_results(_notebook([(study, [])]))
    assert reads_benchmark_results(_notebook([(study + timing, [])]))
