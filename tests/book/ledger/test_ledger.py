"""The reproduction ledger: complete, well-formed, deterministic, and linked to the book."""

import dataclasses
import json
import os
import re
import shutil
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path

import pytest

import gyrolib
from gyrolib.book import cite
from gyrolib.book.ledger import (
    KINDS,
    SCHEMA_VERSION,
    STATUS_CODES,
    STATUSES_BY_KIND,
    LedgerItem,
    anchor,
    citation,
    collect,
    entries_markdown,
    summary,
    table_markdown,
    to_csv,
    to_json,
)
from gyrolib.book.ledger.remaining import UNDECIDABLE
from tests.conftest import LEDGER_MEMO_ENV, require_built_book, session_book

ROOT = Path(__file__).resolve().parents[3]
FIELDS = {"id", "paper", "location", "quantity", "unit", "paper_value", "reproduced_value",
          "status", "status_code", "note", "chapter", "kind", "evidence", "conditions", "precision",
          "reference", "thresholds", "share_holding", "readings", "margin", "mapped",
          "isolated"}
REQUIRED_IDS = [
    "gc.fig1", "gc.fig4", "gc.claim.trend_holds", "rsf.fig1", "rsf.fig2", "rsf.fig3",
    "gc.float_rotation_100s", "gc.sigma_gc_100s", "gc.fig2.var_N1", "gc.fig2.var_N3",
    "gc.fig2.areas", "gc.claim.corresponding_gyro", "rsf.claim.premise",
    "rsf.claim.no_complication", "rsf.claim.only_small_eps1", "rsf.claim.coordinate_accuracy",
    *[f"rsf.table2.dgamma_sins_{t}" for t in (10, 60, 120)],
    *[f"rsf.table2.dr_z_{t}" for t in (10, 60, 120)],
    *[f"rsf.table3.eps0_t_{t}" for t in (10, 60, 120)],
    *[f"rsf.table3.dgamma_gs_{t}" for t in (10, 60, 120)],
    "rsf.example.delta_K", "rsf.example.compensated",
    # the second audit (#21): claims, figures and every input number of both papers
    "gc.claim.psi_separable", "gc.fig2", "gc.fig3", "gc.faster_percent",
    "rsf.claim.longer_finer", "rsf.claim.drz_cubic",
    *[f"gc.input.{k}" for k in ("I", "H", "f", "Omega_v", "Omega_h", "alpha1", "xi1", "alpha2",
                                "xi2", "omega_ub", "C_as", "C_incl", "dt", "P0_psi",
                                "P0_omega_gc", "P0_tilts", "sigma_c")],
    "gc.ref2_minutes", "gc.ref3_minutes",
    *[f"rsf.input.{k}" for k in ("period", "omega_unc", "omega_example", "omega_table2",
                                 "spin_min_hz", "spin_max_hz")],
    "rsf.encoder.position_error",
]


@pytest.fixture(scope="module")
def items():
    return collect()


def _cli_json(memo: Path | None = None) -> str:
    """The command's JSON: its items read from the folder ``memo`` (a memo of the ledger,
    ``gyrolib.book.ledger.MEMO_ENV``) or, without one, computed by the command; never read
    from the session's memo (``tests/conftest.py``)."""
    env = {k: v for k, v in os.environ.items() if k != LEDGER_MEMO_ENV}
    if memo is not None:
        env[LEDGER_MEMO_ENV] = str(memo)
    out = subprocess.run([sys.executable, "-m", "gyrolib", "ledger", "--json"], check=True,
                         capture_output=True, text=True, cwd=ROOT, env=env)
    return out.stdout


def _book_memo(book, monkeypatch) -> Path:
    """Where the book build keeps its memo of the ledger for today's gyrolib sources: its
    kernels computed the items there, in processes of their own (``_ext/gyrolib_cache.py``
    gives the build a memo folder in its jupyter cache)."""
    import gyrolib.book.ledger as ledger_module

    with monkeypatch.context() as m:
        m.setenv(LEDGER_MEMO_ENV, str(book.cache / "ledger"))
        return ledger_module._memo_file()


def test_every_required_id_is_present(items):
    ids = {it.id for it in items}
    missing = [i for i in REQUIRED_IDS if i not in ids]
    assert not missing, f"ledger lacks {missing}"


def test_statuses_and_fields(items):
    for it in items:
        assert it.status in STATUSES_BY_KIND[it.kind], it
        assert it.evidence.strip(), it.id
        assert it.paper in ("GC", "RSF"), it
        assert it.note and len(it.note.splitlines()) == 1, f"{it.id}: note must be one line"
        assert re.fullmatch(r"[a-z]+(\.[A-Za-z0-9_]+)+", it.id), it.id
        if it.status != "not reproducible" and it.reproduced_value is None:
            # only drawings and curves without a printed number may lack a value, and the
            # statements no computation decides (their evidence says why)
            assert ((it.paper_value == "figure" and it.location.startswith("Fig."))
                    or it.evidence.startswith(UNDECIDABLE)), it.id


def test_cli_json_parses_with_every_field_and_is_byte_identical(items, tmp_path, monkeypatch):
    """The command's JSON is byte for byte the JSON of the test session's ledger (``items``:
    the session's memo, computed once in a test process, ``tests/conftest.py``) and the
    book's ``ledger.json``; the command's items are another computation than the session's:
    the book build's (its kernels computed them, with a memo of their own), or, when the
    build was made from other sources (``GYROLIB_REUSE_BOOK``), the command's own.  Two
    independent computations agree, and the command prints what the book publishes."""
    book = session_book()
    built = _book_memo(book, monkeypatch)
    assert Path(os.environ[LEDGER_MEMO_ENV]) != built.parent  # the session's is another
    # the session's own build (the test command) computed the ledger from today's sources
    assert built.is_file() or not book.fresh, f"the book build left no {built}"
    memo = None
    if built.is_file():  # not the session's memo: a copy, so the build's stays untouched
        memo = tmp_path / "book-memo"
        memo.mkdir()
        shutil.copy2(built, memo / built.name)
    first, second = _cli_json(memo), to_json(items)
    source = "the book build's" if memo else "the command's own"
    assert first == second, f"the command's JSON ({source} computation) != the session's"
    if memo is not None:
        assert (book.html / "ledger.json").read_text(encoding="utf-8") == second
        # power, and proof that the command printed the build's items: one value changed in
        # the build's memo changes the command's JSON
        data = json.loads((memo / built.name).read_text(encoding="utf-8"))
        changed = next(d for d in data if isinstance(d["reproduced_value"], float))
        changed["reproduced_value"] *= 1.5
        (memo / built.name).write_text(json.dumps(data), encoding="utf-8")
        assert _cli_json(memo) != second
    doc = json.loads(first)
    assert doc["version"] == gyrolib.__version__ and doc["title"]
    data = doc["items"]
    assert isinstance(data, list) and data
    for entry in data:
        assert set(entry) == FIELDS, entry
        # the code for programs, the words for readers: a claim's words carry its share
        (status,) = [s for s in STATUSES_BY_KIND[entry["kind"]]
                     if STATUS_CODES[s] == entry["status_code"]]
        assert entry["status"].startswith(status), entry["id"]
        if entry["kind"] == "claim" and entry["share_holding"] and status != "holds":
            assert "% of the box" in entry["status"], entry["id"]
        # cited values carry no more digits than the item's declared precision
        x = entry["reproduced_value"]
        if isinstance(x, float) and x:
            assert x == float(f"{x:.{entry['precision']}g}"), entry["id"]


def test_cli_table_lists_every_item(items, capsys):
    """The command's table (its ``main``, in this process: its exit status and JSON are
    tested in processes of their own above and in ``test_studies.py``)."""
    from gyrolib.cli import main

    assert main(["ledger"]) == 0
    out = capsys.readouterr().out
    for it in items:
        assert it.id in out


def test_summary_counts_add_up_and_reproduced_means_printed_numbers_only(items):
    counts = summary(items)
    assert sum(sum(counts[k].values()) for k in KINDS) == counts["total"] == len(items)
    n_reproduced = sum(it.status == "reproduced" for it in items)
    assert counts["printed number"]["reproduced"] == n_reproduced
    assert all("reproduced" not in counts[k] for k in KINDS if k != "printed number")


def _item(**kw):
    args = dict(id="x.y", paper="GC", location="", quantity="", unit="", paper_value=None,
                reproduced_value=None, status="reproduced", note="n", chapter="c",
                kind="printed number", evidence="e")
    return LedgerItem(**{**args, **kw})


@pytest.mark.parametrize(("kw", "match"), [
    ({"status": "close enough"}, "status of x.y"),
    ({"kind": "input", "status": "reproduced"}, "status of x.y"),       # an echo is no result
    ({"kind": "figure", "status": "reproduced"}, "status of x.y"),      # a drawing neither
    ({"kind": "inferred", "status": "reproduced"}, "status of x.y"),
    ({"kind": "claim", "status": "holds under conditions"}, "conditions"),  # say where
    ({"kind": "claim", "status": "holds", "conditions": "only here"}, "conditions"),
    ({"status": "reproduced", "conditions": "only here"}, "conditions"),  # numbers: none
    ({"evidence": ""}, "evidence"),
    ({"kind": "guess"}, "kind"),
])
def test_item_rejects_a_status_that_does_not_fit_its_kind(kw, match):
    with pytest.raises(ValueError, match=match):
        _item(**kw)


def test_a_failed_claim_states_where_it_would_hold():
    it = _item(kind="claim", status="fails", conditions="it would hold from 2557 °/s up")
    assert it.conditions.startswith("it would hold")
    with pytest.raises(ValueError, match="conditions"):
        _item(kind="claim", status="fails")


def test_every_kind_but_inferred_has_an_item_and_the_review_cases_are_classified(items):
    """Every kind but 'inferred' is in use (the statements no computation can decide are
    claims with the status 'not decidable', their evidence says why): the encoder error, once
    inferred from Table 3, is an input printed by the worked example (second audit)."""
    by_id = {it.id: it for it in items}
    assert {it.kind for it in items} == set(KINDS) - {"inferred"}
    undecided = [it for it in items if it.status == "not decidable"]
    assert len(undecided) >= 2
    assert all(it.evidence.startswith(UNDECIDABLE) and it.conditions for it in undecided)
    for echoed in ("rsf.table1.bias_instability", "rsf.table1.sf_error", "rsf.gs.sigma_rep",
                   "rsf.gs.sigma_stab", "rsf.gs.sf_error", "rsf.encoder.position_error"):
        assert by_id[echoed].kind == "input", echoed
    assert all(it.status == "redrawn" for it in items if it.paper_value == "figure")
    # every input echoes a printed number and says what the book does with it
    for it in items:
        if it.kind == "input":
            assert isinstance(it.paper_value, float) and it.reproduced_value is not None, it.id
            assert it.reproduced_value == pytest.approx(it.paper_value, rel=1e-9), it.id


def test_json_and_markdown_of_a_known_item():
    it = LedgerItem(id="gc.test", paper="GC", location="Fig. 3", quantity="σ|x", unit="m",
                    paper_value=0.5, reproduced_value=0.49273, status="reproduced",
                    note="shown", chapter="chapters/gc_model", anchor="",
                    kind="printed number", evidence="a computation", precision=4)
    assert json.loads(to_json([it]))["items"][0]["reproduced_value"] == 0.4927  # 4 digits
    csv_text = to_csv([it])
    assert csv_text.startswith(f"# Gyro calibration, reproduced (ledger schema "
                               f"{SCHEMA_VERSION}) {gyrolib.__version__}\n")
    assert json.loads(to_json([it]))["schema_version"] == SCHEMA_VERSION == 4
    assert "gc.test" in csv_text and ",0.4927," in csv_text
    md = table_markdown([it], "GC")
    assert "{ref}`Fig. 3 <gc-model>`" in md and "σ\\|x" in md and "0.4927" in md
    assert "{bdg-success}`reproduced`" in md and "{ref}`gc.test <gc.test>`" in md
    assert table_markdown([it], "RSF").count("\n") == 1  # header only: no RSF item
    line = citation(it)
    assert line.startswith("σ|x: 0.4927 m (paper GC, Fig. 3, printed: 0.5; reproduced).")
    assert (f"version {gyrolib.__version__}, ledger item gc.test "
            f"({cite.ledger_location('gc-test')})") in line  # tests/book/test_cite.py: its forms
    entry = entries_markdown([it], "GC")
    assert entry.startswith("(gc.test)=\n") and f"```text\n{line}\n```" in entry
    assert anchor("gc.sigma_gc_100s") == "gc-sigma-gc-100s"


class _Ids(HTMLParser):
    def __init__(self):
        super().__init__()
        self.ids = set()

    def handle_starttag(self, tag, attrs):
        for k, v in attrs:
            if k == "id" and v:
                self.ids.add(v)


def test_every_item_links_to_a_page_and_anchor_of_the_built_book(items):
    html = require_built_book()
    problems = []
    ids: dict[Path, set[str]] = {}  # each page parsed once (a few pages hold every item)
    for it in items:
        page = html / f"{it.chapter}.html"
        if not page.is_file():
            problems.append(f"{it.id}: no page {page.relative_to(html)}")
            continue
        if it.anchor:
            if page not in ids:
                parser = _Ids()
                parser.feed(page.read_text(encoding="utf-8"))
                ids[page] = parser.ids
            if it.anchor not in ids[page]:
                problems.append(f"{it.id}: no anchor #{it.anchor} in {page.name}")
    assert not problems, "\n".join(problems)


def test_concurrent_collects_compute_the_items_once(tmp_path, monkeypatch):
    """Chapters executed at the same time (the build runs two kernels) share one computation:
    while the first collect() computes, a second one waits for the memo instead of computing
    too.  The computation is replaced by a slow counting stub that returns the real items; the
    two calls overlap (the stub sleeps 0.5 s), so without the lock the count would be 2."""
    import threading
    import time

    import gyrolib.book.ledger as ledger_module

    items = collect()
    calls = []

    def slow():
        calls.append(1)
        time.sleep(0.5)
        return items

    monkeypatch.setattr(ledger_module, "_collect", slow)
    monkeypatch.setenv("GYROLIB_LEDGER_MEMO", str(tmp_path))
    out = [None, None]

    def worker(i):
        out[i] = collect()

    threads = [threading.Thread(target=worker, args=(i,)) for i in range(2)]
    for th in threads:
        th.start()
        time.sleep(0.05)
    for th in threads:
        th.join()
    assert len(calls) == 1, f"computed {len(calls)} times"
    assert out[0] == items and out[1] == items


def test_collect_is_computed_once_per_state_of_the_sources_with_a_memo(tmp_path, monkeypatch):
    """With GYROLIB_LEDGER_MEMO (set by the book build) the first collect() computes once and
    writes its items to one file named by the hash of gyrolib's sources; they read back
    equal (floats and all); later calls read that file (a mark put into it comes back)
    instead of computing.  The computation is counted (it returns the session's items: that
    an independent computation gives the same ledger is
    :func:`test_cli_json_parses_with_every_field_and_is_byte_identical`)."""
    import gyrolib.book.ledger as ledger_module

    plain = collect()   # under pytest: read back from the session's memo (conftest)
    computed = []

    def compute():
        computed.append(1)
        return plain

    monkeypatch.setattr(ledger_module, "_collect", compute)
    monkeypatch.setenv("GYROLIB_LEDGER_MEMO", str(tmp_path))
    first = collect()
    files = list(tmp_path.glob("ledger-*.json"))
    assert computed == [1] and len(files) == 1 and first == plain
    assert ledger_module._read_memo(files[0]) == plain
    assert collect() == plain and computed == [1]          # read, not computed again
    data = json.loads(files[0].read_text(encoding="utf-8"))
    data[0]["note"] = "read from the memo"
    files[0].write_text(json.dumps(data), encoding="utf-8")
    assert collect()[0].note == "read from the memo" and computed == [1]
    assert ledger_module._memo_file() == files[0]


def test_a_pure_numbers_citation_has_no_unit_digit_and_reads_as_sentences():
    """A value of unit "1" is cited bare: "0.00017 1" would read as one more digit.  The
    citation line and the entry's note begin as sentences (a Latin first letter raised; a
    symbol such as δ kept, its capital being another symbol).  Power: a unit that is a word
    is still written."""
    it = _item(id="rsf.x", paper="RSF", location="worked example", quantity="relative error",
               unit="1", reproduced_value=0.000171, paper_value=0.093, precision=2,
               status="differs: cause shown", note="the print takes a slip",
               chapter="chapters/rsf_method")
    line = citation(it)
    assert line.startswith("Relative error: 0.00017 (paper RSF, worked example, printed: "
                           "0.093; differs: cause shown). ")
    assert "0.00017 1" not in line
    assert "The print takes a slip." in entries_markdown([it], "RSF")
    metres = citation(dataclasses.replace(it, unit="m"))
    assert metres.startswith("Relative error: 0.00017 m (")
    symbol = citation(dataclasses.replace(it, quantity="δK of K"))
    assert symbol.startswith("δK of K: 0.00017 (")
