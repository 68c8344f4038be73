"""The one rule over the table of inputs (issue 33): synthetic claims of two inputs with known
boundaries, the completeness of the thresholds (and its power), the table itself, and the
stored maps against independent computations (each claim's own function, bisected here)."""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest

from gyrolib import claim_map as cm
from gyrolib import gc, inputs
from gyrolib.book.ledger import claims

S1 = inputs.row("gc.sigma1_sq").reference
CAS = inputs.row("gc.C_as").reference


# synthetic claims (module level: an executor pickles them) --------------------------------
def always(o):
    return 1.0


def below_three(o):          # holds for σ1² below 3 times the reference
    return 3.0 - o["GyrocompassParams"].sigma1_sq / S1


def above_three(o):          # fails at the reference, holds above 3 times
    return o["GyrocompassParams"].sigma1_sq / S1 - 3.0


def band(o):                 # holds for C_as between 0.3 and 3 times the reference
    f = o["GyrocompassParams"].C_as / CAS
    return -(f - 0.3) * (f - 3.0)


def by_reading(o):           # holds only under the book's reading of the noise levels
    return 1.0 if o["GyrocompassParams"].measurement_noise == "intensity_over_dt" else -1.0


TWO = ("gc.sigma1_sq", "gc.C_as")


def test_synthetic_holds_has_no_threshold():
    m = cm.map_claim(cm.Claim("t.holds", always, TWO, "1"), n_box=16)
    assert m.status == "holds" and m.thresholds == () and m.conditions() == ""
    assert m.share_holding.value == 1.0 and m.share_holding.n == 16


def test_synthetic_holds_under_conditions_finds_the_threshold():
    m = cm.map_claim(cm.Claim("t.below", below_three, TWO, "3 - f"), n_box=32)
    assert m.status == "holds under conditions"
    (t,) = m.thresholds
    assert t.input == "gc.sigma1_sq" and t.holds_when == "below"
    assert t.factor == pytest.approx(3.0, rel=1e-3)          # the bisection's tolerance
    assert "σ1² below" in m.conditions()
    # the box: σ1² log-uniform over ×[0.1, 10] holds below ×3: ln(30)/ln(100) = 0.739
    assert m.share_holding.lo <= math.log(30) / math.log(100) <= m.share_holding.hi


def test_synthetic_fails_at_reference_and_says_where_it_would_hold():
    m = cm.map_claim(cm.Claim("t.above", above_three, TWO, "f - 3"), n_box=0)
    assert m.status == "fails" and m.share_holding is None
    (t,) = m.thresholds
    assert t.holds_when == "above" and t.factor == pytest.approx(3.0, rel=1e-3)
    assert m.conditions().startswith("It would hold")


def test_synthetic_two_flips_and_a_reading():
    m = cm.map_claim(cm.Claim("t.band", band, TWO, "band"), n_box=0, n_grid=13)
    got = [(t.holds_when, round(t.factor, 2)) for t in m.thresholds]
    assert got == [("above", 0.3), ("below", 3.0)]
    assert cm.flip_share(m, "gc.C_as") == pytest.approx(
        (math.log(0.3 / 0.1) + math.log(10 / 3.0)) / math.log(100), rel=1e-3)
    r = cm.map_claim(cm.Claim("t.read", by_reading, (*TWO, "gc.measurement_noise"), "r"),
                     n_box=0)
    assert r.status == "holds under conditions" and r.thresholds == ()
    assert r.readings == {"gc.measurement_noise": {"intensity_over_dt": "holds",
                                                   "variance": "fails"}}
    assert r.flipping_inputs() == ("gc.measurement_noise",)


def test_map_is_the_same_with_an_executor():
    from concurrent.futures import ThreadPoolExecutor

    c = cm.Claim("t.band", band, TWO, "band")
    with ThreadPoolExecutor(2) as ex:
        a = cm.map_claim(c, n_box=16, executor=ex)
    b = cm.map_claim(c, n_box=16)
    assert a.to_dict() == b.to_dict()


def test_wilson_interval_covers_at_its_rate():
    """A statistical bound: over 2000 seeded binomial draws (p = 0.3, n = 64) the 95 % Wilson
    interval covers p in 93-97 % of them."""
    rng = np.random.default_rng(5)
    k = rng.binomial(64, 0.3, size=2000)
    cover = np.mean([lo <= 0.3 <= hi for lo, hi in (cm.wilson_interval(int(x), 64) for x in k)])
    assert 0.93 <= cover <= 0.97


# completeness: every input that flips a claim is in its thresholds ----------------------
def completeness_violations(claim, m, n=13):
    """Each input of ``claim`` varied alone on a grid of ``n`` points other than the map's;
    the inputs at which the live status differs from what the map's thresholds predict."""
    bad = set()
    objs = inputs.reference_objects()
    for name in claim.inputs:
        r = inputs.row(name)
        if r.kind == "reading":
            for val in r.values:
                live = cm.margin_at(claim, objs, {name: val}) > 0
                if live != (m.readings[name][val] == "holds"):
                    bad.add(name)
            continue
        u = (np.arange(n) + 0.37) / n          # not the map's grid
        for x in r.to_unit(u):
            near = [t for t in m.thresholds if t.input == name
                    and abs(x / t.value - 1.0) < 5e-3]
            if near:
                continue
            if (cm.margin_at(claim, objs, {name: float(x)}) > 0) != cm.predicted_holds(
                    m, name, float(x)):
                bad.add(name)
    return bad


CHEAP = ("rsf.example.compensated", "rsf.claim.gs_vs_sins", "rsf.claim.drz_cubic",
         "rsf.claim.drz_kilometres")


@pytest.mark.parametrize("cid", CHEAP)
def test_every_input_that_flips_a_claim_is_named(cid):
    m = claims.stored_maps()[cid]
    assert completeness_violations(claims.CLAIMS[cid], m) == set()


def test_completeness_check_has_power():
    """Drop one threshold from the stored map: the check must name that input."""
    cid = "rsf.example.compensated"
    m = claims.stored_maps()[cid]
    assert m.thresholds, "the compensation claim flips with the roll rate"
    dropped = m.thresholds[0]
    weaker = dataclasses.replace(m, thresholds=m.thresholds[1:])
    assert dropped.input in completeness_violations(claims.CLAIMS[cid], weaker)
    # and a reading whose status is misreported
    (name, st), *_ = m.readings.items()
    wrong = {**m.readings, name: {k: ("fails" if v == "holds" else "holds")
                                  for k, v in st.items()}}
    assert name in completeness_violations(claims.CLAIMS[cid],
                                           dataclasses.replace(m, readings=wrong))


# the stored maps against independent computations ----------------------------------------
def _race_holds(p, proc):
    r = gc.race(p, proc)     # the claim's own function, not race_margin's fast path
    return min(r.faster_percent, r.faster_percent_optimal) > 50.0


def _bisect(holds, a, b, rtol=1e-3):
    ha = holds(a)
    assert holds(b) != ha, "no change of status in the bracket"
    while b / a - 1.0 > rtol:
        mid = math.sqrt(a * b)
        a, b = (mid, b) if holds(mid) == ha else (a, mid)
    return math.sqrt(a * b)


@pytest.mark.parametrize("name,field", [("gc.sigma1_sq", "sigma1_sq"),
                                        ("gc.sigma_hf_scale", "sigma_hf_scale")])
def test_race_thresholds_agree_with_bisecting_the_race_itself(name, field):
    m = claims.stored_maps()["gc.faster_percent"]
    (t,) = [t for t in m.thresholds if t.input == name]
    p0, proc = gc.GyrocompassParams(), gc.RateSensorProcedure()

    def holds(x):
        return _race_holds(dataclasses.replace(p0, **{field: x}), proc)
    root = _bisect(holds, t.value / 1.01, t.value * 1.01)
    assert root == pytest.approx(t.value, rel=2e-3)
    assert holds(t.value * 0.99) == (t.holds_when == "below")


def test_compensation_threshold_agrees_with_eq7_bisected():
    """rsf.example.compensated: the roll rate from which Eq. (7) compensates 90 %,
    bisected on rsf.compensation_share (the chapter's function), against the map's."""
    from gyrolib import rsf

    m = claims.stored_maps()["rsf.example.compensated"]
    (t,) = [t for t in m.thresholds if t.input == "rsf.omega_x"]

    def holds(w):
        return float(rsf.compensation_share([w]).share[0]) >= 0.9
    assert _bisect(holds, t.value / 1.01, t.value * 1.01) == pytest.approx(t.value, rel=2e-3)
    assert t.holds_when == "above"


def test_race_kappa_threshold_agrees_with_the_closed_form():
    """GC's scale adds κ Ω_h in quadrature: RaceConditions.kappa_max solves for it from the
    σ curve (a second algorithm); the map's κ threshold must agree."""
    m = claims.stored_maps()["gc.faster_percent"]
    (t,) = [t for t in m.thresholds if t.input == "gc.sigma_hf_scale"]
    assert gc.race().conditions().kappa_max == pytest.approx(t.value, rel=2e-2)


def test_race_status_and_readings_are_in_the_ledger_json():
    from gyrolib.book.ledger import collect, to_json

    doc = json.loads(to_json(collect()))
    assert doc["schema_version"] == 2
    it = next(i for i in doc["items"] if i["id"] == "gc.faster_percent")
    names = {t["input"] for t in it["thresholds"]}
    assert {"gc.sigma1_sq", "gc.sigma_hf_scale"} <= names
    assert set(it["readings"]) >= {"gc.measurement_noise", "gc.shaping_p0"}
    assert {"value", "lo", "hi", "n"} <= set(it["share_holding"])
    assert it["reference"]["gc.sigma_hf_scale"] == 0.0


def test_stale_map_fails_loudly(tmp_path):
    m = claims.stored_maps()
    cid = "rsf.claim.drz_kilometres"
    pt = dict(m[cid].fingerprint[0])
    pt["margin"] = pt["margin"] + 0.01
    bad = dataclasses.replace(m[cid], fingerprint=(pt,))
    with pytest.raises(ValueError, match="stale"):
        cm.check_fingerprint(claims.CLAIMS[cid], bad)
    cm.check_fingerprint(claims.CLAIMS[cid], m[cid])   # the stored one agrees


# the table ------------------------------------------------------------------------------
def test_table_rows_name_real_fields_and_defaults_are_references():
    objs = inputs.reference_objects()
    for r in inputs.INPUTS:
        assert inputs.value_of(objs, r) == r.reference
        if r.kind != "reading":
            lo, hi = r.bounds()
            assert lo <= r.reference <= hi
            assert r.reason.strip()
    assert {"gc.measurement_noise", "gc.shaping_p0", "gc.eq1_sign", "rsf.eps0_gs_digits",
            "rsf.eps1_gs_unit"} <= {r.name for r in inputs.rows(kind="reading")}


def test_one_source_of_ranges():
    from gyrolib.book.ledger import gc as lgc

    assert gc.RACE_RANGES["loop_bandwidth"] == inputs.row("race.loop_bandwidth").bounds()
    assert gc.RACE_RANGES["sigma_hf_scale"] == inputs.row("gc.sigma_hf_scale").bounds()
    assert lgc.TREND_FACTORS == inputs.row("gc.sigma1_sq").factors
    assert inputs.default_prior("gc.sigma_hf_scale") == 1e-3


def test_bad_rows_are_refused():
    with pytest.raises(ValueError, match="no field"):
        inputs.Input("x", "x", "GyrocompassParams", ("nope",), "uncertain", "1", "r", 0.1, 10)
    with pytest.raises(ValueError, match="positive lower bound"):
        inputs.Input("x", "x", "GyrocompassParams", ("sigma_hf_scale",), "uncertain", "1", "r",
                     0.0, 1.0, relative=False)
    with pytest.raises(KeyError, match="known"):
        inputs.row("gc.nope")
