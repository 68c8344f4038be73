"""The stored claim maps' box shares and tables: every share from enough points that its 95 %
interval is at most ten points wide, the interval the Wilson interval of its counts (scipy's,
a second implementation), the audit's 200,000-point share of gs_vs_sins inside its interval,
and every claim mapped over every row that moves its margin (Fig. 3's drop over the whole
table, flipped by C_as and σ_ω(0))."""

from __future__ import annotations

import math

import pytest
from scipy.stats import binomtest

from gyrolib import inputs
from gyrolib.book.ledger import claims
from gyrolib.claim_map import Share, margin_at

#: The widest 95 % interval of a stored share, and the fewest points of a box.
WIDEST = 0.10
FEWEST = 400
#: gs_vs_sins's share of the same box from 200,000 points (an independent audit's draw).
GS_VS_SINS_AUDIT = 0.176


@pytest.fixture(scope="module")
def maps():
    return claims.stored_maps()


def share_problems(cid: str, sh: Share, box_fails: int) -> list[str]:
    """What is wrong with a stored share (empty: nothing): too few points, an interval wider
    than :data:`WIDEST`, counts that do not add up, or an interval that is not the Wilson
    interval of its counts by scipy."""
    out = []
    if sh.n < FEWEST or sh.n != claims.BOX_POINTS[cid]:
        out.append(f"{cid}: {sh.n} points, the claim's box has {claims.BOX_POINTS[cid]}")
    if sh.hi - sh.lo > WIDEST:
        out.append(f"{cid}: interval {sh.lo:.4f}–{sh.hi:.4f} wider than {WIDEST}")
    k = sh.n - box_fails
    if not math.isclose(sh.value, k / sh.n, abs_tol=1e-12):
        out.append(f"{cid}: share {sh.value} is not {k}/{sh.n}")
    ci = binomtest(k, sh.n).proportion_ci(0.95, method="wilson")
    if not (math.isclose(sh.lo, ci.low, abs_tol=1e-9)
            and math.isclose(sh.hi, ci.high, abs_tol=1e-9)):
        out.append(f"{cid}: interval {sh.lo}–{sh.hi}, scipy's Wilson {ci.low}–{ci.high}")
    return out


#: Claims whose stored share has not been grown to its points yet, with the CPU-s the
#: growth costs (measured per margin; strict: the mark fails once the share is grown).
PENDING: dict[str, float] = {
    "gc.faster_percent": 2800.0,            # stale: its map is recomputed whole (3.6 s a margin)
    "rsf.claim.coordinate_accuracy": 740.0,  # 336 more seeded flights at 2.2 s
    "rsf.claim.only_small_eps1": 700.0,      # the same flights, with the angle reset
}


@pytest.mark.parametrize("cid", [
    pytest.param(c, marks=pytest.mark.xfail(strict=True, reason=f"its box not grown yet "
                                            f"(about {PENDING[c]:.0f} CPU-s)"))
    if c in PENDING else c for c in claims.CLAIMS])
def test_every_share_is_from_enough_points_and_at_most_ten_points_wide(maps, cid):
    """Every mapped claim's share: at least 400 points (2,000 where a margin costs under
    10 ms, :data:`claims.BOX_POINTS`), its interval at most 10 points wide and scipy's Wilson
    interval of its counts."""
    m = maps[cid]
    assert m.share_holding is not None
    assert share_problems(cid, m.share_holding, m.box_fails) == []


def test_share_check_has_power():
    """The 64-point share the book gave gs_vs_sins (6 of 64, 4.4–19.0 %) fails the check:
    too few points and an interval 14.6 points wide."""
    lo, hi = binomtest(6, 64).proportion_ci(0.95, method="wilson")
    old = Share(6 / 64, lo, hi, 64, 2026)
    found = share_problems("rsf.claim.gs_vs_sins", old, 58)
    assert len(found) == 2 and "64 points" in found[0] and "wider" in found[1]


def test_gs_vs_sins_interval_holds_the_audits_share(maps):
    """The audit drew 200,000 points of the same box: 17.6 %, inside the stored interval."""
    sh = maps["rsf.claim.gs_vs_sins"].share_holding
    assert sh.lo <= GS_VS_SINS_AUDIT <= sh.hi
    assert sh.seed == claims.BOX_SEED


def test_drop_2s_is_mapped_over_the_whole_table(maps):
    """Fig. 3's drop reads every row of paper GC, so C_as and σ_ω(0) flip it, at the trend's
    thresholds (the same criterion over the same table)."""
    gc_rows = {r.name for r in inputs.INPUTS if r.name.startswith("gc.")}
    drop, trend = maps["gc.fig3.drop_2s"], maps["gc.claim.trend_holds"]
    assert set(drop.reference) == gc_rows
    assert {"gc.C_as", "gc.sigma_gc0"} <= set(drop.flipping_inputs())
    assert drop.status != "holds"
    for a, b in zip(drop.thresholds, trend.thresholds, strict=True):
        assert (a.input, a.holds_when) == (b.input, b.holds_when)
        assert a.value == pytest.approx(b.value, rel=1e-9)


#: The claims cheap enough to evaluate at both ends of every row of their paper.
CHEAP = ("rsf.example.compensated", "rsf.claim.gs_vs_sins", "rsf.claim.drz_cubic",
         "rsf.claim.drz_kilometres", "gc.fig2.areas")


def rows_that_move(cid: str, claim_inputs: tuple[str, ...]) -> set[str]:
    """The numeric rows of the claim's paper outside ``claim_inputs`` whose range ends move
    the claim's margin, and the readings outside them whose values move it."""
    objs = inputs.reference_objects()
    c = claims.CLAIMS[cid]
    ref = margin_at(c, objs, {})
    paper = cid.split(".")[0] + "."
    moved = set()
    for r in inputs.INPUTS:
        if not r.name.startswith(paper) or r.name in claim_inputs:
            continue
        values = r.values[1:] if r.kind == "reading" else r.bounds()
        for x in values:
            now = margin_at(c, objs, {r.name: x})
            if not math.isclose(now, ref, rel_tol=1e-12, abs_tol=1e-15):
                moved.add(r.name)
    return moved


@pytest.mark.parametrize("cid", CHEAP)
def test_no_row_outside_a_claims_inputs_moves_it(cid):
    """A claim mapped over part of its paper's rows names every input that flips it only if
    the rows left out do not move its margin: each at its range's two ends (each other
    reading) leaves the margin as at the reference."""
    assert rows_that_move(cid, claims.CLAIMS[cid].inputs) == set()


def test_rows_outside_check_has_power():
    """Leave ε1 and the encoder's error out of gs_vs_sins's rows: the check names both."""
    kept = tuple(n for n in claims.CLAIMS["rsf.claim.gs_vs_sins"].inputs
                 if n not in ("rsf.eps1", "rsf.encoder_error"))
    assert rows_that_move("rsf.claim.gs_vs_sins", kept) == {"rsf.eps1", "rsf.encoder_error"}
