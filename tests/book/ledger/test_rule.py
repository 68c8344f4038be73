"""The ledger's one agreement rule (gyrolib.book.ledger.item): a computed value agrees with a
print of n digits when it lies within half a unit of the last printed digit, unless the item
states another tolerance with its reason.  Edge cases against hand-worked prints, the verdict
that follows from the candidates, and the rule applied to every printed number of the ledger
(recomputed here, independently of the builders)."""

import ast
import math
import subprocess
import sys
from decimal import Decimal
from pathlib import Path

import pytest

from gyrolib.book.ledger import collect
from gyrolib.book.ledger.item import Candidate, agrees, half_unit, judge_claim, printed_verdict

ROOT = Path(__file__).resolve().parents[3]
LEDGER = ROOT / "gyrolib" / "book" / "ledger"


# half a unit of the last printed digit ------------------------------------------------------
@pytest.mark.parametrize(("printed", "half"), [
    ("20", 0.5), (20.0, 0.5),                 # an integer's last digit is its units digit
    ("4590", 0.5), (36730.0, 0.5),            # trailing zeros of an integer count as printed
    ("0.0011", 5e-5), (0.0011, 5e-5),         # leading zeros do not
    ("3.3e-3", 5e-5), (3.3e-3, 5e-5),         # 3.3·10⁻³: its last digit is 0.1·10⁻³
    ("21.25", 0.005), ("0,5", 0.05),          # a decimal comma as the papers print it
    ("0.50", 0.005),                          # a trailing zero after the point, given as text
    (1.86e-6, 5e-9), (600.0, 0.5),
])
def test_half_unit_of_the_last_printed_digit(printed, half):
    assert half_unit(printed) == pytest.approx(half, rel=1e-12)


# agreement, edge cases ---------------------------------------------------------------------
@pytest.mark.parametrize(("value", "printed", "expected"), [
    (20.49, "20", True), (20.51, "20", False),
    (19.51, "20", True), (19.49, "20", False),
    (20.5, "20", True), (19.5, "20", True),      # the boundary (exact in binary) agrees
    (0.00114, 0.0011, True), (0.00116, 0.0011, False),
    (0.00106, "0.0011", True), (0.00104, "0.0011", False),
    (0.001374, 0.0011, False),                   # the book's sigma_gc(100 s) against Fig. 3
    (0.4927, 0.5, True), (0.4427, 0.5, False),   # the float's rotation against '0,5°'
    (0.0033907, 3.3e-3, False), (0.003333, 3.3e-3, True),
    (4590.4, 4590.0, True), (4594.0, 4590.0, False),
    (None, 1.0, False),                          # nothing computed never agrees
])
def test_agreement_edge_cases(value, printed, expected):
    assert agrees(value, printed) is expected


def test_the_boundary_is_exact_on_the_binary_value():
    """0.00115 and 0.00105 are not representable: both binary values lie just below their
    decimal, so the first is inside '0.0011' ± 0.00005 and the second just outside: the rule
    compares the exact binary value, with no slack that could depend on the CPU."""
    x, y = 0.00115, 0.00105
    assert Decimal(x) < Decimal("0.00115") and agrees(x, "0.0011")
    assert Decimal(y) < Decimal("0.00105") and not agrees(y, "0.0011")


def test_a_stated_tolerance_with_its_reason():
    """Table 2's 4590 read to four significant digits (±5): 4594 agrees only with the stated
    tolerance, and a tolerance without a reason (or a reason without a tolerance) is refused."""
    reason = "four significant digits, as 21.25 is printed"
    assert not agrees(4594.0, 4590.0)
    assert agrees(4594.0, 4590.0, tolerance=5.0, reason=reason)
    assert not agrees(4596.0, 4590.0, tolerance=5.0, reason=reason)
    with pytest.raises(ValueError, match=r"^reason"):
        agrees(4594.0, 4590.0, tolerance=5.0)
    with pytest.raises(ValueError, match=r"^reason"):
        agrees(4594.0, 4590.0, reason=reason)
    with pytest.raises(ValueError, match=r"^tolerance"):
        agrees(4594.0, 4590.0, tolerance=-1.0, reason=reason)


@pytest.mark.parametrize(("call", "exc", "name"), [
    (lambda: half_unit("about 0.5"), ValueError, "printed"),
    (lambda: half_unit(math.nan), ValueError, "printed"),
    (lambda: half_unit("inf"), ValueError, "printed"),
    (lambda: half_unit(None), TypeError, "printed"),
    (lambda: half_unit(True), TypeError, "printed"),
    (lambda: agrees("1.0", 1.0), TypeError, "value"),
    (lambda: agrees(math.inf, 1.0), ValueError, "value"),
    (lambda: Candidate("", 1.0), TypeError, "name"),
    (lambda: Candidate("x", math.nan), ValueError, "value"),
    (lambda: printed_verdict(1.0, 1.0, [1.0]), TypeError, "candidates"),
])
def test_bad_input_is_rejected_by_name(call, exc, name):
    with pytest.raises(exc, match=f"^{name}"):
        call()


# the verdict of a printed number from its candidate causes ---------------------------------
@pytest.mark.parametrize(("consistent", "printed", "candidates", "status"), [
    (21.6, 21.6, [], "reproduced"),
    # Table 3 at 10 s: both candidate shortenings of ε0,GS give the print
    (0.0339, 0.033, [0.033, 0.0333], "differs: cause shown"),
    # at 60 s only the two-digit value does: the print shows it (and refutes 12 °/h unrounded)
    (0.2034, 0.198, [0.198, 0.2], "differs: cause shown"),
    # sigma_gc: no reading gives the print, but the two P0 readings span it
    (0.00137, 0.0011, [0.00137, 0.00084], "differs: bracketed"),
    # ...but the consistent value alone does not bracket with a slip: the span is the
    # candidates' (a wrong GS gyro: δK's slip candidates 0.133, the print 0.093)
    (0.0002, 0.093, [0.133, 0.1334], "not reproducible"),
    # Table 2's Δr_z: no candidate, the print far off
    (61.62, 21.25, [], "not reproducible"),
    (0.2034, 0.198, [0.2], "not reproducible"),   # the print outside the span
])
def test_printed_verdict(consistent, printed, candidates, status):
    cands = [Candidate(f"c{i}", x) for i, x in enumerate(candidates)]
    assert printed_verdict(consistent, printed, cands) == status


def test_every_printed_number_of_the_ledger_follows_the_rule():
    """Each 'reproduced' value agrees with its print by the rule, and no other printed number
    does (a stated tolerance is quoted in the evidence and applied here too)."""
    for it in collect():
        if it.kind != "printed number" or not isinstance(it.paper_value, float):
            continue
        rule = ({"tolerance": 5.0, "reason": "stated"} if "±5 stated" in it.evidence
                and it.paper_value >= 1000 else {})
        assert agrees(it.reproduced_value, it.paper_value, **rule) \
            == (it.status == "reproduced"), it.id


# one rule, ordinary imports ------------------------------------------------------------------
def _imports(path: Path) -> set[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    return {node.module for node in ast.walk(tree)
            if isinstance(node, ast.ImportFrom) and node.module}


def test_no_hidden_circle_and_no_second_rule():
    """The paper modules import LedgerItem and the rule from item.py, never from the package
    (which imports them); item.py imports no ledger module; nobody uses __import__; and the
    old private rounding helpers are gone, so every item goes through item.agrees."""
    for name in ("gc.py", "rsf.py"):
        mods = _imports(LEDGER / name)
        assert "gyrolib.book.ledger" not in mods, name
        assert "gyrolib.book.ledger.item" in mods, name
        text = (LEDGER / name).read_text(encoding="utf-8")
        assert "_half_unit" not in text and "_printed_digits" not in text, name
    assert not {m for m in _imports(LEDGER / "item.py") if m.startswith("gyrolib.book")}
    for path in LEDGER.glob("*.py"):
        assert "__import__" not in path.read_text(encoding="utf-8"), path.name


def test_builders_are_small():
    """Each paper module builds its items in small named functions (none over 70 lines)."""
    for name in ("gc.py", "rsf.py"):
        tree = ast.parse((LEDGER / name).read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if isinstance(node, ast.FunctionDef):
                assert node.end_lineno - node.lineno < 70, f"{name}: {node.name}"


def test_a_missing_paper_module_is_an_error():
    """With gyrolib.book.ledger.rsf unimportable, importing the ledger fails loudly instead of
    collecting half a ledger."""
    code = (
        "import sys, importlib.abc\n"
        "class Block(importlib.abc.MetaPathFinder):\n"
        "    def find_spec(self, name, path, target=None):\n"
        "        if name == 'gyrolib.book.ledger.rsf':\n"
        "            raise ModuleNotFoundError(name, name=name)\n"
        "sys.meta_path.insert(0, Block())\n"
        "try:\n"
        "    from gyrolib.book.ledger import collect\n"
        "except ImportError as exc:\n"
        "    print('refused', 'rsf' in str(exc))\n"
        "else:\n"
        "    print('collected', len(collect()))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         cwd=ROOT, check=True).stdout
    assert out.strip() == "refused True"


# the one rule for every claim -----------------------------------------------------------------
@pytest.mark.parametrize(("at_ref", "over", "status"), [
    (True, True, "holds"),
    (True, False, "holds under conditions"),
    (False, False, "fails"),
])
def test_judge_claim_table(at_ref, over, status):
    got, cond = judge_claim(at_ref, over, "where it stops or would hold")
    assert got == status
    assert (cond == "") == (status == "holds")


def test_judge_claim_with_power_on_a_claim_built_to_fail():
    """A claim that fails at its reference point but holds elsewhere in its ranges (the old
    race rule's blind spot: some overhead always makes it hold) is "fails", with the
    conditions saying where it would hold; a "holds under conditions" needs its conditions,
    and holding over ranges that contain a failing reference point is refused."""
    status, cond = judge_claim(False, False, "it would hold from 35 s of overhead up")
    assert status == "fails" and "would hold" in cond
    with pytest.raises(ValueError, match="conditions"):
        judge_claim(False, False, "")
    with pytest.raises(ValueError, match="conditions"):
        judge_claim(True, False, " ")
    with pytest.raises(ValueError, match="holds_over_ranges"):
        judge_claim(False, True, "x")
    with pytest.raises(TypeError, match="holds_at_reference"):
        judge_claim(1, True)
    with pytest.raises(TypeError, match="conditions"):
        judge_claim(True, False, None)


def test_the_race_claim_fails_where_the_rival_is_fast():
    """The race's own verdict, with power: a rival with a quiet, slow loop, no turn and no
    settling reaches σ_c in less than twice GC's time, so "more than 50 % faster" fails at
    that reference point, and the item built on it says so (conditions: where it would
    hold)."""
    from dataclasses import replace as _replace

    from gyrolib import gc as gcm
    from gyrolib.book.ledger import gc as lgc
    proc = _replace(gcm.RateSensorProcedure(), loop_bandwidth=1.0, T_rot=2.0, T_settle=3.0,
                    rate_noise=6e-17)
    r = gcm.race(None, proc)
    cond = r.conditions()
    assert r.faster_percent_optimal < 50.0 and not cond.holds_at_reference
    from gyrolib.book.ledger.claims import verdict

    v = verdict("gc.faster_percent", lgc._objects(r.params, proc),
                context=cond.reference_text())
    assert v.status == "fails" and "does not with" in v.conditions
    assert v.judged["mapped"] is False and v.judged["margin"] < 0
    item = lgc._faster_percent(r.params, r, cond,
                               lgc.study_evidence(gcm.GyrocompassParams()))
    assert item.status == "fails" and item.conditions == v.conditions


def test_every_claim_of_the_ledger_goes_through_the_one_rule():
    """Each claim builder of both paper modules calls the one rule (``verdict``, the map over
    the table of inputs, or ``judge_claim`` for the one claim judged by its own sweeps), and no
    claim builder writes a status literal of its own."""
    for name in ("gc.py", "rsf.py"):
        tree = ast.parse((LEDGER / name).read_text(encoding="utf-8"))
        funcs = {n.name: n for n in ast.walk(tree) if isinstance(n, ast.FunctionDef)}

        def called(node):
            return {c.func.id for c in ast.walk(node) if isinstance(c, ast.Call)
                    and isinstance(c.func, ast.Name)}
        rule = {"judge_claim", "verdict"} | {f for f, n in funcs.items()
                                             if called(n) & {"judge_claim", "verdict"}}
        for fname, node in funcs.items():
            src = ast.get_source_segment((LEDGER / name).read_text(encoding="utf-8"), node)
            if 'kind="claim"' not in src:
                continue
            # the status comes from the rule: a call of it, or the speed evidence it judged
            assert called(node) & rule or ("speed.status" in src
                                           and "speed_evidence" in rule), f"{name}: {fname}"
            for lit in ("\"holds under conditions\"", "\"fails\"", "\"holds\""):
                assert lit not in src, f"{name}: {fname} sets {lit} itself"
    claims = [it for it in collect() if it.kind == "claim"]
    assert len(claims) >= 10
    for it in claims:
        assert (it.conditions == "") == (it.status == "holds"), it.id


# a status that matches its share --------------------------------------------------------------
def _share(k, n=64):
    from gyrolib.claim_map import Share, wilson_interval

    lo, hi = wilson_interval(k, n)
    return Share(k / n, lo, hi, n, 1)


def test_the_share_of_the_box_sets_the_status_and_its_code():
    """Power of the rule: a claim that holds at the reference but flips, at 60 % of 64 box
    points (95 % interval up to 71 %), is "holds under conditions"; at 30 % (up to 42 %) it is
    "holds only near the reference": different statuses and codes, and each status line
    carries its share (the Wilson interval's ends, computed here by hand from k/n)."""
    from gyrolib.claim_map import STATUS_CODES, claim_status, status_line

    wide, narrow = _share(38), _share(19)          # 59 % and 30 % of 64
    assert narrow.hi < 0.5 <= wide.hi
    s_wide, s_narrow = claim_status(True, True, wide), claim_status(True, True, narrow)
    assert (s_wide, s_narrow) == ("holds under conditions", "holds only near the reference")
    assert (STATUS_CODES[s_wide], STATUS_CODES[s_narrow]) == ("holds_in_part",
                                                               "holds_near_reference")
    # the 95 % Wilson interval of 19/64 by hand: centre ± half-width
    z, n, p = 1.959963984540054, 64, 19 / 64
    c = (p + z * z / (2 * n)) / (1 + z * z / n)
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    assert status_line(s_narrow, narrow) == (f"holds only near the reference ({100 * p:.0f} % "
                                             f"of the box, {100 * (c - h):.0f}–"
                                             f"{100 * (c + h):.0f} %)")
    # the boundary: the upper end just under and at one half
    from gyrolib.claim_map import Share

    assert claim_status(True, True, Share(0.4, 0.3, 0.4999, 64, 1)) == \
        "holds only near the reference"
    assert claim_status(True, True, Share(0.4, 0.3, 0.5, 64, 1)) == "holds under conditions"
    # without a flip, or failing at the reference, the share does not matter
    assert claim_status(True, False, narrow) == "holds"
    assert claim_status(False, True, wide) == "fails"
    assert judge_claim(True, False, "κ flips it", narrow)[0] == "holds only near the reference"


def test_an_item_refuses_a_status_that_says_more_than_its_share():
    """A claim item whose share's upper end is below one half cannot be "holds under
    conditions" (nor a wide one "holds only near the reference"): the status line alone must
    not let a reader believe more than the share supports."""
    from dataclasses import asdict

    from gyrolib.book.ledger import LedgerItem

    judged = {"reference": {}, "thresholds": [], "readings": {},
              "share_holding": asdict(_share(0))}
    kw = dict(id="x.y", paper="GC", location="l", quantity="q", unit="1", paper_value="p",
              reproduced_value=None, note="n", chapter="chapters/gc_race", kind="claim",
              evidence="e", conditions="σ_off flips it")
    with pytest.raises(ValueError, match="holds only near the reference"):
        LedgerItem(status="holds under conditions", judged=judged, **kw)
    it = LedgerItem(status="holds only near the reference", judged=judged, **kw)
    assert it.status_code == "holds_near_reference"
    assert it.status_line == "holds only near the reference (0 % of the box, 0–6 %)"
    wide = {**judged, "share_holding": asdict(_share(38))}
    with pytest.raises(ValueError, match="holds under conditions"):
        LedgerItem(status="holds only near the reference", judged=wide, **kw)
    with pytest.raises(ValueError, match="share"):
        LedgerItem(status="holds only near the reference", judged=None, **kw)


def test_no_claim_of_the_ledger_holds_under_conditions_beyond_its_share():
    """Acceptance: no claim whose share's upper end is below 0.5 carries "holds under
    conditions", and every mapped claim's status line (the JSON's ``status``) carries its
    share; the race claim, which holds at none of the box's points, holds only near the
    reference, and its conditions name every input that flips it, σ_off and σ_b included."""
    import json

    from gyrolib import inputs, quote
    from gyrolib.book import ledger
    from gyrolib.book.ledger import claims

    items = collect()
    doc = {d["id"]: d for d in json.loads(ledger.to_json(items))["items"]}
    for it in items:
        share = (it.judged or {}).get("share_holding")
        if it.kind != "claim" or not share:
            continue
        if it.status.startswith("holds ") and share["hi"] < 0.5:
            assert it.status == "holds only near the reference", it.id
        if it.status != "holds":
            assert f"{quote.percent(share['value'])} % of the box" in doc[it.id]["status"], \
                it.id
        assert doc[it.id]["status_code"] == it.status_code
    race = {it.id: it for it in items}["gc.faster_percent"]
    assert race.status_code == "holds_near_reference"
    assert doc["gc.faster_percent"]["status"].startswith("holds only near the reference (0 %")
    m = claims.stored_maps()["gc.faster_percent"]
    for name in ("gc.sigma_as_offset", "gc.sigma_incl_bias", "gc.sigma_hf_scale"):
        assert name in m.flipping_inputs()
    for name in m.flipping_inputs():
        assert inputs.row(name).symbol in race.conditions, name
    assert "σ_off" in race.conditions and "σ_b" in race.conditions
