"""The chapters say no more than the ledger: a heading or sentence that calls an item
"reproduced" needs the item's ledger status to be `reproduced`; no chapter decides a verdict
in its own code; the F(8,7) pole is computed once, in the library."""

import re
from pathlib import Path

import numpy as np
import pytest

from gyrolib import gc
from gyrolib.book.ledger import STATUSES, collect

ROOT = Path(__file__).resolve().parents[3]
CHAPTERS = sorted((ROOT / "chapters").glob("*.md"))

_T2_ROLL = tuple(f"rsf.table2.dgamma_sins_{t}" for t in (10, 60, 120))
_T2_DRZ = tuple(f"rsf.table2.dr_z_{t}" for t in (10, 60, 120))
_T3 = tuple(f"rsf.table3.{k}_{t}" for k in ("eps0_t", "dgamma_gs") for t in (10, 60, 120))

#: (phrase, the items it speaks for): the ways the chapters say "reproduced" of an item.
PHRASES: tuple[tuple[str, tuple[str, ...]], ...] = (
    (r"Fig(?:ure|\.) 2,? (?:is )?reproduced|reproduces? Fig(?:ure|\.) 2\b", ("gc.fig2",)),
    (r"Fig(?:ure|\.) 3,? (?:is )?reproduced|reproduces? Fig(?:ure|\.) 3\b",
     ("gc.sigma_gc_100s", "gc.fig3")),
    (r"Fig(?:ure|\.) 4,? (?:is )?reproduced|reproduces? Fig(?:ure|\.) 4\b", ("gc.fig4",)),
    (r"σ at 100 s (?:is )?reproduced|0\.0011.{0,40}\breproduced", ("gc.sigma_gc_100s",)),
    (r"(?:float|rotation).{0,60}\bis reproduced", ("gc.float_rotation_100s",)),
    (r"Table 2's roll errors (?:are )?reproduced", _T2_ROLL),
    (r"Table 2 (?:is )?reproduced|reproduces? Table 2\b", _T2_ROLL + _T2_DRZ),
    (r"(?:lateral deviations?|Δr_z).{0,30}\b(?:is|are) reproduced", _T2_DRZ),
    (r"Table 3 (?:is )?reproduced|reproduces? Table 3\b", _T3),
    (r"error tables are reproduced|tables are reproduced", _T2_ROLL + _T2_DRZ + _T3),
    (r"δK = \S+ is reproduced|worked example.{0,40}\bis reproduced", ("rsf.example.delta_K",)),
    (r"ε0,GS.{0,30}\bis reproduced", ("rsf.gs.eps0_total",)),
)


def offending(text: str, status: dict[str, str]) -> list[str]:
    """Each phrase of :data:`PHRASES` found in ``text`` whose items are not all reproduced."""
    flat = re.sub(r"\s+", " ", text)
    return [f"{m.group(0)!r} -> {[i for i in ids if status[i] != 'reproduced']}"
            for pattern, ids in PHRASES for m in re.finditer(pattern, flat)
            if any(status[i] != "reproduced" for i in ids)]


@pytest.fixture(scope="module")
def status():
    return {it.id: it.status for it in collect()}


def test_phrases_name_ledger_items(status):
    assert all(i in status for _, ids in PHRASES for i in ids)


@pytest.mark.parametrize("path", CHAPTERS, ids=lambda p: p.stem)
def test_no_chapter_calls_an_item_reproduced_that_the_ledger_does_not(path, status):
    assert not offending(path.read_text(encoding="utf-8"), status), path.name


@pytest.mark.parametrize(("sentence", "found"), [
    ("## Figure 3 reproduced", True),            # sigma_gc(100 s) is 'differs: bracketed'
    ("Paper GC's Figure 4 reproduced: the estimate", True),   # a figure is 'redrawn'
    ("Table 3 is reproduced exactly once ε0,GS is truncated", True),
    ("Paper RSF: the error tables are reproduced", True),
    ("Table 2's roll errors are reproduced exactly", False),  # they are
    ("## Figure 3 redrawn", False),
])
def test_the_check_has_power(sentence, found, status):
    """The same check on planted sentences: it flags exactly the wrong ones."""
    assert bool(offending(sentence, status)) is found


def _code_cells(text: str) -> list[str]:
    return re.findall(r"```\{code-cell\}[^\n]*\n(.*?)```", text, flags=re.S)


def deciding(code: str) -> list[str]:
    """Status strings that a piece of code *chooses* (the result of a conditional expression
    or a return): a verdict decided there rather than read from the ledger."""
    status = "|".join(re.escape(s) for s in STATUSES)
    pattern = (rf"[\"'](?:{status})[\"']\s+if\b|\belse\s+[\"'](?:{status})[\"']"
               rf"|\breturn\s+[\"'](?:{status})[\"']")
    return re.findall(pattern, code)


@pytest.mark.parametrize("path", CHAPTERS, ids=lambda p: p.stem)
def test_no_chapter_decides_a_verdict_in_its_code(path):
    """No code cell of a chapter chooses a status string (``"differs: bracketed" if ...``):
    chapters read verdicts from the ledger (looking up a count by status is reading)."""
    cells = _code_cells(path.read_text(encoding="utf-8"))
    assert not [hit for cell in cells for hit in deciding(cell)], path.name


def test_the_decision_check_has_power():
    """The check flags the code the old gc_filter and errata pages had."""
    assert deciding('glue("v", "differs: bracketed" if b else "differs: cause shown")')
    assert deciding('status = "reproduced" if ok else "not reproducible"')
    assert not deciding('n = counts["printed number"].get("reproduced", 0)')


def test_the_printed_f87_pole_is_computed_once_in_the_library():
    """errata and gc_model read the printed F(8,7)'s pole from gc.vibration_filter(...,
    f87="printed").poles(), which equals the closed form −ξα ± α√(ξ² + 1); neither chapter
    computes eigenvalues itself."""
    p = gc.GyrocompassParams()
    poles = gc.vibration_filter(p.alpha1, p.xi1, p.sigma1_sq, f87="printed").poles().real
    a, xi = p.alpha1, p.xi1
    assert poles == pytest.approx(sorted([-xi * a - a * np.hypot(xi, 1.0),
                                          -xi * a + a * np.hypot(xi, 1.0)]), rel=1e-12)
    for name in ("errata.md", "gc_model.md"):
        text = (ROOT / "chapters" / name).read_text(encoding="utf-8")
        assert 'f87="printed"' in text and "linalg.eigvals" not in text, name
