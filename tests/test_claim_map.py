"""The one rule over the table of inputs: synthetic claims of two inputs with known
boundaries, the completeness of the thresholds (and its power), the table itself, and the
stored maps against independent computations (each claim's own function, bisected here)."""

from __future__ import annotations

import dataclasses
import functools
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


def notch(o):                # fails only for C_as between 2 and 5 times the reference
    f = o["GyrocompassParams"].C_as / CAS
    return (f - 2.0) * (f - 5.0)


def by_reading(o):           # holds only under the book's reading of the noise levels
    return 1.0 if o["GyrocompassParams"].measurement_noise == "intensity_over_dt" else -1.0


TWO = ("gc.sigma1_sq", "gc.C_as")
XI_STEP = 0.01


def at_fifths(o):            # fails only where ξ1 is a multiple of 0.2 (to its 0.01 quantum)
    return -1.0 if round(o["GyrocompassParams"].xi1 / XI_STEP) % 20 == 0 else 1.0


def xi1_points(o):           # every quantum of ξ1's range
    lo, hi = inputs.row("gc.xi1").bounds()
    return np.round(np.arange(lo, hi + XI_STEP / 2, XI_STEP) / XI_STEP) * XI_STEP


ISOLATED = cm.Claim("t.isolated", at_fifths, ("gc.xi1", "gc.C_as"), "fifths",
                    searches=(cm.PointSearch("gc.xi1", xi1_points, "every 0.01 of its range",
                                             quantum=XI_STEP),))


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


def test_synthetic_claim_failing_at_isolated_points_is_stated_as_such():
    """A claim that fails only at isolated values of ξ1 (0.2, 0.4, …, 1.0): the map states
    the failing points, how they were searched and the search's resolution, and that it holds
    between them; no threshold.  Without the search, grid and bisection call the last point
    a boundary (the defect the statement replaces)."""
    m = cm.map_claim(ISOLATED, n_box=8)
    assert m.status == "holds under conditions" and m.thresholds == ()
    (f,) = m.isolated
    assert f.input == "gc.xi1" and f.isolated
    assert f.points == pytest.approx((0.2, 0.4, 0.6, 0.8, 1.0), abs=1e-12)
    assert f.searched == 91 and f.resolution == pytest.approx(XI_STEP, rel=1e-9)
    text = m.conditions()
    for words in ("searched at 91 points", "every 0.01 of its range", "resolution 0.01",
                  "only at the isolated values 0.2, 0.4, 0.6, 0.8, 1",
                  "holds at every other point searched"):
        assert words in text, words
    assert m.flipping_inputs() == ("gc.xi1",)
    assert cm.ClaimMap.from_dict(json.loads(json.dumps(m.to_dict()))) == m
    assert not cm.predicted_holds(m, "gc.xi1", 0.6004) and cm.predicted_holds(m, "gc.xi1", 0.5)
    plain = cm.map_claim(dataclasses.replace(ISOLATED, searches=()), n_box=0)
    assert [t.holds_when for t in plain.thresholds] == ["below"]     # a false boundary
    assert cm.predicted_holds(plain, "gc.xi1", 0.4)                   # where it fails


def test_completeness_names_a_dropped_isolated_statement():
    """Power: the completeness check (each input alone across its range, its ends included)
    passes with the statement and names ξ1 when the statement is dropped."""
    m = cm.map_claim(ISOLATED, n_box=0)
    assert completeness_violations(ISOLATED, m) == set()
    assert completeness_violations(ISOLATED, dataclasses.replace(m, isolated=())) == {"gc.xi1"}


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
@functools.cache
def _live_holds(claim, name, x):
    """The claim's status with row ``name`` alone at ``x`` (kept: a check and its power
    check evaluate the same places)."""
    return cm.margin_at(claim, inputs.reference_objects(), {name: x}) > 0


def completeness_violations(claim, m, n=13, names=None):
    """Each input of ``claim`` (or of ``names``) varied alone on a grid of ``n`` points other
    than the map's, and at its range's two ends; the inputs at which the live status differs
    from what the map's thresholds and isolated failing points predict."""
    bad = set()
    for name in claim.inputs if names is None else names:
        r = inputs.row(name)
        if r.kind == "reading":
            for val in r.values:
                live = _live_holds(claim, name, val)
                if live != (m.readings[name][val] == "holds"):
                    bad.add(name)
            continue
        u = np.append((np.arange(n) + 0.37) / n, [0.0, 1.0])   # not the map's grid; the ends
        for x in r.to_unit(u):
            near = [t for t in m.thresholds if t.input == name
                    and abs(x / t.value - 1.0) < 5e-3]
            if near:
                continue
            if _live_holds(claim, name, float(x)) != cm.predicted_holds(m, name, float(x)):
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
    # the race's own status differs at 0.999 and 1.001 of the map's threshold: its root lies
    # within 10⁻³ of it (the bisection's tolerance), on the side the map states (two races,
    # where bisecting from ±1 % took seven)
    assert holds(t.value * (1 - 1e-3)) == (t.holds_when == "below")
    assert holds(t.value * (1 + 1e-3)) != (t.holds_when == "below")


def test_west_gyro_threshold_agrees_with_its_filter_and_the_floor():
    """gc.claim.corresponding_gyro fails at the reference, and the map names σ_ψ(0) alone as
    the input below which it would hold: the west gyro's own filter (remaining.west_gyro)
    reaches σ_c at 510 s at 0.999 of the threshold and not at 1.001; and the threshold lies
    below the closed-form bound of the floor, σ_ψ at which σ_c is reached only as t → ∞."""
    from gyrolib.book.ledger import remaining

    m = claims.stored_maps()["gc.claim.corresponding_gyro"]
    assert m.status == "fails"
    (t,) = m.thresholds
    assert (t.input, t.holds_when) == ("gc.sigma_psi0", "below")
    p = gc.GyrocompassParams()
    below, above = (remaining.west_gyro(dataclasses.replace(p, sigma_psi0=t.value * f))
                    for f in (1 - 1e-3, 1 + 1e-3))
    assert below.sigma[-1] <= claims.levels.SIGMA_C < above.sigma[-1]
    assert t.value < above.psi_max


def test_longer_finer_fails_at_whole_encoder_revolutions_as_its_map_states():
    """rsf.claim.longer_finer's encoder part fails at isolated intervals, each a whole number
    of the encoder's revolutions (the GS motor turns it at its speed limit: 2π/W_max = 0.6 s),
    where the encoder's error cancels between the interval's ends.  The stored map states
    exactly those points of Δt's range (a closed form, independent of the search), searched
    at every fifth sample; on the chapter's own sweep function a finer encoder leaves rms δK
    as it is (to 10⁻⁹) at one of them and lowers it at the midpoint to the next.  The
    completeness check passes on Δt (7 off-grid places and the ends) and on ω_x's ends, and
    names Δt when the statement is dropped (30 s, the range's end, is 50 revolutions)."""
    from dataclasses import replace

    from gyrolib.book.ledger import rsf as lrsf
    from gyrolib.rsf.simulation import EncoderModel, GsModel
    from gyrolib.rsf.sweeps import sweep_encoder

    m = claims.stored_maps()["rsf.claim.longer_finer"]
    assert m.status == "holds under conditions" and m.margin > 0
    (f,) = m.isolated
    o = inputs.reference_objects()
    rev = 2 * math.pi / GsModel.from_spec(o["MemsGyroSpec"]).motor_rate_max
    assert rev == pytest.approx(0.6, rel=1e-12)
    lo, hi = inputs.row("rsf.period").bounds()
    expected = [k * rev for k in range(math.ceil(lo / rev), math.floor(hi / rev + 1e-9) + 1)]
    assert f.input == "rsf.period" and f.isolated
    assert f.points == pytest.approx(expected, abs=1e-9)
    assert f.resolution == pytest.approx(0.05, rel=1e-9) and f.quantum == pytest.approx(0.01)
    assert "holds at every other point searched" in m.conditions()
    enc = o["EncoderSpec"]
    # the sweep's seeded flights (the same the margin reads: simulated once, kept)
    record = lrsf.sweep_flights(o["RollGyroSpec"], o["MemsGyroSpec"], enc,
                                float(o["WorkedExample"].omega_x))
    encs = [EncoderModel.from_spec(replace(enc, cycles_per_rev=c))
            for c in (lrsf.SIM_CYCLES[0], lrsf.SIM_CYCLES[-1])]
    whole = sweep_encoder(record, encs, 10 * rev).rms
    assert whole[-1] == pytest.approx(whole[0], rel=1e-9)
    between = sweep_encoder(record, encs, 10.5 * rev).rms
    assert between[-1] < 0.9 * between[0]
    claim = claims.CLAIMS["rsf.claim.longer_finer"]
    assert completeness_violations(claim, m, n=7, names=("rsf.period",)) == set()
    assert completeness_violations(claim, m, n=0, names=("rsf.omega_x",)) == set()
    assert completeness_violations(claim, dataclasses.replace(m, isolated=()), n=7,
                                   names=("rsf.period",)) == {"rsf.period"}


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
    """GC's scale adds κ Ω_h in quadrature: RaceResult.kappa_max (what RaceConditions
    reports) solves for it from the σ curve (a second algorithm); the map's κ threshold must
    agree.  (The method alone: the conditions' three boundary searches are not this check's.)"""
    m = claims.stored_maps()["gc.faster_percent"]
    (t,) = [t for t in m.thresholds if t.input == "gc.sigma_hf_scale"]
    assert gc.race().kappa_max() == pytest.approx(t.value, rel=2e-2)


def test_race_status_and_readings_are_in_the_ledger_json():
    from gyrolib.book.ledger import collect, to_json

    doc = json.loads(to_json(collect()))
    assert doc["schema_version"] == 4
    it = next(i for i in doc["items"] if i["id"] == "gc.faster_percent")
    assert it["status_code"] == "holds_near_reference"
    assert it["status"].startswith("holds only near the reference (")
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
        inputs.Input("x", "x", "GyrocompassParams", ("nope",), "uncertain", "1", "r", 0.1, 10,
                     owner_type=gc.GyrocompassParams)
    with pytest.raises(ValueError, match="positive lower bound"):
        inputs.Input("x", "x", "GyrocompassParams", ("sigma_hf_scale",), "uncertain", "1", "r",
                     0.0, 1.0, relative=False, owner_type=gc.GyrocompassParams)
    with pytest.raises(ValueError, match="owner_type"):
        inputs.Input("x", "x", "GyrocompassParams", ("sigma_hf_scale",), "uncertain", "1", "r",
                     0.1, 10.0, owner_type=gc.RateSensorProcedure)
    with pytest.raises(KeyError, match="known"):
        inputs.row("gc.nope")


def test_time_to_level_carries_the_instrument_terms():
    """The fast 10-state path ignored the instrument terms (an inclinometer bias prior of
    0.5 mg left t_c at 24 s): they now run the whole covariance analysis, and the fast path
    refuses them.  Checked against covariance_analysis over 510 s (a second computation)."""
    from dataclasses import replace

    from gyrolib.gc.analysis.covariance import covariance_analysis, time_to_sigma
    from gyrolib.gc.analysis.speed_claim import _run_omega_gc, time_to_level
    from gyrolib.units import G0

    level = claims._SIGMA_C
    p = replace(gc.GyrocompassParams(), sigma_incl_bias=0.05e-3 * G0)
    t_c = time_to_level(p, level, 510.0)
    # the covariance analysis over 2 s past that time (not the whole 510 s: σ falls
    # monotonically, so a later crossing cannot be the first, and an earlier one or none
    # within the span fails the comparison just the same)
    cov = covariance_analysis(p, math.ceil(t_c) + 2.0, store_every=10)
    assert t_c == pytest.approx(time_to_sigma(cov, "omega_gc", level), abs=0.02)
    big = replace(p, sigma_incl_bias=0.5e-3 * G0)
    assert math.isnan(time_to_level(big, level, 100.0))
    with pytest.raises(ValueError, match="instrument terms"):
        _run_omega_gc((p,), 100.0, 100.0, level)


# each claim's thresholds against the claim's own function, at both sides of the root --------
def _own_status(cid):
    """The status of claim ``cid`` computed by the chapters' own functions, not the margins
    the maps were made with (a second computation of the same verdict)."""
    from gyrolib import rsf
    from gyrolib.gc.analysis.covariance import covariance_analysis

    def status(objs):
        p = objs["GyrocompassParams"]
        if cid == "gc.time_to_sigma_c":       # the race's own GC time (another code path)
            from gyrolib.gc.racing.comparison import _gc_time

            proc = objs["RateSensorProcedure"]     # gc.race(p).t_c_gc, without the rival
            t = _gc_time(p, proc.sigma_c, proc.t_max)
            return bool(np.isfinite(t) and t < 510.0)
        if cid in ("gc.claim.trend_holds", "gc.fig3.drop_2s"):
            cov = covariance_analysis(p, 100.0, store_every=100)
            s = cov.std("omega_gc")
            return bool((s[0] - cov.std_at("omega_gc", 2.0)) / (s[0] - s[-1]) > 0.5)
        if cid == "rsf.claim.gs_vs_sins":
            ex = objs["WorkedExample"]
            r = rsf.gs_vs_sins(roll_gyro=objs["RollGyroSpec"], gs_gyro=objs["MemsGyroSpec"],
                               encoder=objs["EncoderSpec"], omega=ex.table_rate)
            return bool(r.ratio_ideal.min() >= 100.0)
        raise KeyError(cid)
    return status


@pytest.mark.parametrize("cid", ["gc.time_to_sigma_c", "gc.claim.trend_holds",
                                 "rsf.claim.gs_vs_sins"])
def test_thresholds_agree_with_bisecting_the_claims_own_status(cid):
    """Two thresholds of each of these claims against the claim's own status (the chapters'
    functions, not the margins the maps were made with): the status differs at 0.999 and
    1.001 of the map's threshold, the bisection's bracket at the stated tolerance (10⁻³), so
    the own root lies within 10⁻³ of the threshold, on the side the map states.  (Each
    evaluation near the speed claim's thresholds is a covariance analysis of 510 s: the
    bracket is the whole bisection the test command can pay for.  rsf.example.compensated
    has one threshold, bisected above; the other claims have none: the completeness tests
    cover them.)"""
    m = claims.stored_maps()[cid]
    assert len(m.thresholds) >= 2, cid
    status = _own_status(cid)
    objs = inputs.reference_objects()
    for t in m.thresholds[:2]:
        holds = functools.cache(lambda x, name=t.input: status(inputs.apply(objs, {name: x})))
        root = _bisect(holds, t.value * (1 - 1e-3), t.value * (1 + 1e-3), rtol=2.1e-3)
        assert root == pytest.approx(t.value, rel=1e-3), (cid, t.input)
        assert holds(t.value * (1 - 1e-3)) == (t.holds_when == "below"), (cid, t.input)


# completeness of paper GC's claims, within a small CPU budget ------------------------------
GC_CLAIMS = ("gc.faster_percent", "gc.time_to_sigma_c", "gc.claim.trend_holds",
             "gc.claim.psi_separable", "gc.fig3.drop_2s", "gc.fig2.areas",
             "gc.claim.corresponding_gyro")


def _far_place(r):
    """One place in row ``r``'s range, on its scale, off the maps' 9-point grid (u = k/8):
    u = 0.81 when the reference lies in the lower half of the range, else 0.19 (the far side,
    where a monotone margin the map misread would flip first)."""
    ref_u = float(np.interp(r.reference, r.to_unit(np.array([0.0, 1.0])), [0.0, 1.0])
                  if r.scale == "linear" else
                  math.log(r.reference / r.bounds()[0]) / math.log(r.bounds()[1]
                                                                   / r.bounds()[0]))
    return float(r.to_unit(0.81 if ref_u <= 0.5 + 1e-9 else 0.19))


@functools.cache
def _gc_live(cid):
    """The status of claim ``cid`` (its margin's sign, computed here) with each numeric input
    alone at its far off-grid place (:func:`_far_place`), and, for a claim that reads only
    readings, under each reading: {(input, value): holds}.  Paper GC's claims cost a
    covariance analysis (or a race) a point, so one place per input, not a grid: the test
    command's budget."""
    claim = claims.CLAIMS[cid]
    objs = inputs.reference_objects()
    numeric = [n for n in claim.inputs if inputs.row(n).kind != "reading"]
    # the speed claim by its own status (the race's GC time, another code path than its
    # margin's), so that the race's test, run first, has computed those GC times already
    holds = (_own_status(cid) if cid == "gc.time_to_sigma_c"
             else lambda o: claim.margin(o) > 0)
    out = {}
    for name in numeric or claim.inputs:
        r = inputs.row(name)
        for x in (r.values[1:] if r.kind == "reading" else [_far_place(r)]):
            out[(name, x)] = bool(holds(inputs.apply(objs, {name: x})))
    return out


def _gc_violations(m, live):
    """The inputs at which the live status differs from what the map states."""
    bad = set()
    for (name, x), holds in live.items():
        if isinstance(x, str):
            if holds != (m.readings[name][x] == "holds"):
                bad.add(name)
        elif not any(t.input == name and abs(x / t.value - 1.0) < 5e-3
                     for t in m.thresholds) and holds != cm.predicted_holds(m, name, x):
            bad.add(name)
    return bad


@pytest.mark.parametrize("cid", GC_CLAIMS)
def test_every_input_that_flips_a_gc_claim_is_named(cid):
    """Each numeric input of paper GC's claims alone at one place off the map's grid (the
    readings of Fig. 3's drop, its only inputs): the claim's margin computed here must have
    the status the map's thresholds predict."""
    assert _gc_violations(claims.stored_maps()[cid], _gc_live(cid)) == set()


def test_gc_completeness_has_power():
    """Drop the race's σ1² threshold, or its κ one, from the stored map: the same live places
    must name that input; state Fig. 3's C_as threshold on the wrong side: they must name it."""
    m = claims.stored_maps()["gc.faster_percent"]
    live = _gc_live("gc.faster_percent")
    for name in ("gc.sigma1_sq", "gc.sigma_hf_scale"):
        weaker = dataclasses.replace(m, thresholds=tuple(t for t in m.thresholds
                                                         if t.input != name))
        assert name in _gc_violations(weaker, live)
    d = claims.stored_maps()["gc.fig3.drop_2s"]    # over the whole table: C_as flips it
    flipped = tuple(dataclasses.replace(t, holds_when="above") if t.input == "gc.C_as" else t
                    for t in d.thresholds)
    assert "gc.C_as" in _gc_violations(dataclasses.replace(d, thresholds=flipped),
                                       _gc_live("gc.fig3.drop_2s"))


def test_monotone_rows_bracket_with_the_range_ends():
    """A row declared monotone is bracketed by its range's two ends and the reference: the
    same threshold (to the bisection's tolerance) with fewer margins; on a margin that is not
    monotone (two flips) the declaration loses a flip, so it is the caller's knowledge, not a
    free setting; a declared row the claim does not bracket is refused by name."""
    calls = []

    def counted(fn):
        def margin(o):
            calls.append(1)
            return fn(o)
        return margin

    full = cm.map_claim(cm.Claim("t.below", counted(below_three), TWO, "3 - f"), n_box=0)
    n_full = len(calls)
    calls.clear()
    coarse = cm.map_claim(cm.Claim("t.below", counted(below_three), TWO, "3 - f"), n_box=0,
                          monotone=["gc.sigma1_sq", "gc.C_as"])
    assert len(calls) < n_full
    ((t0,), (t1,)) = full.thresholds, coarse.thresholds
    assert (t1.input, t1.holds_when) == (t0.input, t0.holds_when)
    assert t1.factor == pytest.approx(3.0, rel=1e-3)
    assert coarse.settings["monotone"] == ["gc.C_as", "gc.sigma1_sq"]
    assert "monotone" not in full.settings
    # power: a notch (fails for C_as × 2–5 only) declared monotone is lost
    notch_full = cm.map_claim(cm.Claim("t.notch", notch, TWO, "notch"), n_box=0, n_grid=13)
    notch_mono = cm.map_claim(cm.Claim("t.notch", notch, TWO, "notch"), n_box=0, n_grid=13,
                              monotone=["gc.C_as"])
    assert [round(t.factor, 2) for t in notch_full.thresholds] == [2.0, 5.0]
    assert notch_mono.thresholds == ()
    with pytest.raises(ValueError, match=r"monotone.*gc\.xi1"):
        cm.map_claim(cm.Claim("t.below", below_three, TWO, "3 - f"), n_box=0,
                     monotone=["gc.xi1"])


def test_race_margin_monotone_rows_are_monotone_in_the_stored_sweeps():
    """The rows the race's margin is declared monotone in (gc.MARGIN_MONOTONE_ROWS, read by
    race --params to bracket them coarsely) are monotone in the stored map's 9-point
    sweeps, in the direction their physics gives (GC's rows lower the margin, the rival's
    raise it); power: a row that is not (C_as, which slows both methods) is caught."""
    from gyrolib.gc.racing.comparison import MARGIN_MONOTONE_ROWS

    sweeps = claims.stored_maps()["gc.faster_percent"].sweeps

    def direction(name):
        ms = [m for _, m in sweeps[name]]
        steps = np.diff(ms)
        tol = 1e-9 * max(abs(m) for m in ms)
        return ("up" if np.all(steps >= -tol) else "down" if np.all(steps <= tol)
                else "neither")

    for name in MARGIN_MONOTONE_ROWS:
        want = "down" if name.startswith("gc.") else "up"
        assert direction(name) == want, name
    assert direction("gc.C_as") == "neither"


def test_the_rival_does_not_read_gcs_instrument_constants():
    """GC's rows among the race's monotone ones enter GC's method only: the rival's model is
    the same array for array with them at their range's high end."""
    from gyrolib.gc.racing.comparison import MARGIN_MONOTONE_ROWS

    p, proc = gc.GyrocompassParams(), gc.RateSensorProcedure()
    base = gc.rate_sensor_model(p, proc)
    changes = {}
    for name in MARGIN_MONOTONE_ROWS:
        if name.startswith("gc."):
            row = inputs.row(name)
            changes.update({f: row.bounds()[1] for f in row.fields})
    assert set(changes) == {"sigma_hf_scale", "sigma_as_offset", "sigma_incl_bias",
                            "sigma_clock"}
    other = gc.rate_sensor_model(dataclasses.replace(p, **changes), proc)
    arrays = ("F", "Phi", "Qd", "P0", "H1", "H2", "r")
    for name in arrays:
        assert np.array_equal(getattr(base, name), getattr(other, name)), name
    # power: a row the rival does read (the unbalance) changes its model
    moved = gc.rate_sensor_model(dataclasses.replace(p, omega_ub=2 * p.omega_ub), proc)
    assert not all(np.array_equal(getattr(base, n), getattr(moved, n)) for n in arrays)


def test_a_stored_map_reads_its_status_by_the_rule_of_this_version():
    """The status of a stored map follows from its parts (reference margin, flips, share), not
    from the word stored with it: a map stored as "holds under conditions" that holds at none
    of its box's points reads "holds only near the reference"; the same map with a wide share
    keeps "holds under conditions" (power: the share decides)."""
    m = cm.map_claim(cm.Claim("t.below", below_three, TWO, "3 - f"), n_box=16)
    d = m.to_dict()
    d["status"] = "holds under conditions"
    d["share_holding"] = {"value": 0.0, "lo": 0.0, "hi": cm.wilson_interval(0, 16)[1],
                          "n": 16, "seed": 1}
    d["box_fails"] = 16
    assert cm.ClaimMap.from_dict(d).status == "holds only near the reference"
    d["share_holding"] = {"value": 0.75, "lo": 0.5, "hi": 0.9, "n": 16, "seed": 1}
    d["box_fails"] = 4
    assert cm.ClaimMap.from_dict(d).status == "holds under conditions"
    d["margin"] = -1.0
    assert cm.ClaimMap.from_dict(d).status == "fails"


# more box points, the same seed ------------------------------------------------------------
def test_extend_box_is_the_map_with_more_points():
    """A map grown from 16 to 80 box points is the map drawn with 80 at once (the same seed:
    the first 16 draws are kept, only the new 64 evaluated); another seed gives another
    share (power: the points are the seed's); fewer points or another claim are refused by
    name."""
    c = cm.Claim("t.below", below_three, TWO, "3 - f")
    small = cm.map_claim(c, n_box=16, seed=5)
    grown = cm.extend_box(c, small, 80)
    full = cm.map_claim(c, n_box=80, seed=5)
    assert grown.share_holding == full.share_holding
    assert (grown.box_fails, grown.status, grown.settings) == (full.box_fails, full.status,
                                                               full.settings)
    assert grown.thresholds == full.thresholds and grown.fingerprint == full.fingerprint
    other = cm.map_claim(c, n_box=80, seed=6)
    assert other.box_fails != full.box_fails
    with pytest.raises(ValueError, match="n_box"):
        cm.extend_box(c, full, 40)
    with pytest.raises(ValueError, match="drawn for"):
        cm.extend_box(cm.Claim("t.other", below_three, TWO, "3 - f"), small, 80)
