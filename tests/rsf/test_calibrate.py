"""rsf.calibrate on records and rsf.run_correction on simulations: both against Eqs. (1)–(3)
written out again here in plain numpy, against each other (they share the correction
routine but cut the data differently: spans between GS angles vs whole intervals), closed
forms on synthetic records with gaps and NaNs, the error model's δK, and the wrapped-count
path."""

from __future__ import annotations

import math

import numpy as np
import pytest

from gyrolib import rsf

CFG = rsf.SimulationConfig(duration=60.0, sample_rate=1000.0)


@pytest.fixture(scope="module")
def flight():
    return rsf.simulate_flight(CFG, seed=77)


def test_equals_run_correction(flight):
    rec = rsf.record_from_simulation(flight)
    res = rsf.calibrate(rec, 1.0)
    run = rsf.run_correction(flight, 1.0)
    np.testing.assert_allclose(res.eps1_hat, run.eps1_hat[0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(res.k, run.k[0], rtol=0, atol=1e-12)
    corrected = run.roll_error_corrected[0] + flight.gamma_true
    np.testing.assert_allclose(res.corrected_angle, corrected, rtol=1e-12, atol=1e-9)


def _reference(inc: np.ndarray, gs: np.ndarray, n_per: int, lag: int = 1):
    """Paper RSF, Eqs. (1)–(3), in plain numpy from the text: over interval i the SINS turn
    Σ ω_x dt and the GS change give ε̂1_i = (Σ ω_x dt − ΔGS)/Σ ω_x dt, K_i = 1 − ε̂1_i
    multiplies the increments of interval i + ``lag`` (1 in the paper) and after."""
    n_int = inc.size // n_per
    sins = inc[: n_int * n_per].reshape(n_int, n_per).sum(axis=1)
    d_gs = gs[n_per : (n_int + 1) * n_per : n_per] - gs[0 : n_int * n_per : n_per]
    eps1_hat = (sins - d_gs) / sins
    k_in_force = np.concatenate([np.ones(lag), 1.0 - eps1_hat])
    k_step = k_in_force[np.minimum(np.arange(inc.size) // n_per, n_int + lag - 1)]
    return eps1_hat, np.concatenate([[0.0], np.cumsum(k_step * inc)])


def test_both_callers_match_eqs_1_to_3_written_out():
    """10.5 s at 1 kHz, Δt = 1 s (a trailing half interval): ε̂1 and the corrected angle of
    run_correction and of calibrate agree with the plain-numpy reference; the same reference
    with K applied one interval early (in its own interval) does not (power)."""
    cfg = rsf.SimulationConfig(duration=10.5, sample_rate=1000.0, n_runs=2)
    sim = rsf.simulate_flight(cfg, seed=31)
    gs = rsf.gs_angle(sim)
    run = rsf.run_correction(sim, 1.0)
    for m in range(2):
        eps1_hat, corrected = _reference(sim.sins_inc[m], gs[m], 1000)
        np.testing.assert_allclose(run.eps1_hat[m], eps1_hat, rtol=0, atol=1e-12)
        np.testing.assert_allclose(run.roll_error_corrected[m] + sim.gamma_true, corrected,
                                   rtol=0, atol=1e-9)
        res = rsf.calibrate(rsf.record_from_simulation(sim, m), 1.0)
        np.testing.assert_allclose(res.eps1_hat, eps1_hat, rtol=0, atol=1e-12)
        np.testing.assert_allclose(res.corrected_angle, corrected, rtol=0, atol=1e-9)
        _, early = _reference(sim.sins_inc[m], gs[m], 1000, lag=0)
        assert np.max(np.abs(early - corrected)) > 1e3 * 1e-9


def test_acceptance_within_predicted_delta_k(flight):
    """With NaNs and a gap, every interval's δK = K(1+ε1) − 1 lies within 3σ of what the
    error model predicts for this record (rsf.predict_delta_k, its σ scaled to the part of
    each interval the data cover); without that scaling the gap's interval fails (power)."""
    rec = rsf.record_from_simulation(flight)
    rng = np.random.default_rng(3)
    inc = rec.sins_increment.copy()
    gs = rec.gs_angle.copy()
    inc[rng.choice(np.arange(1, rec.n), 50, replace=False)] = np.nan
    gs[rng.choice(np.arange(1, rec.n), 50, replace=False)] = np.nan
    keep = ~((rec.t > 20.3) & (rec.t <= 20.8))
    damaged = rsf.RSFRecord(t=rec.t[keep], sins_increment=inc[keep], gs_angle=gs[keep])
    res = rsf.calibrate(damaged, 1.0)
    pred = rsf.predict_delta_k(CFG, 1.0)
    dk = res.delta_k(float(flight.eps1_sins[0]))
    assert res.n_intervals == 60
    assert np.all(np.abs(dk - pred.mean) <= 3.0 * res.delta_k_std(pred))
    gap_interval = 20
    # 300 samples before the gap, 200 after it less the one whose step spans the gap
    assert res.segments[gap_interval] == 2 and res.samples[gap_interval] == 499
    assert abs(dk[gap_interval] - pred.mean) > 3.0 * pred.std
    # the same at the rate the record itself measured
    pred2 = rsf.predict_delta_k(CFG, res.period, rate=res.mean_rate)
    assert pred2.std == pytest.approx(pred.std, rel=0.01)
    assert res.gaps == 1 and res.samples_skipped > 0


def _synthetic(eps1: float, n: int = 2001, dt: float = 0.01, rate: float = 15.7):
    t = np.arange(n) * dt
    wobble = 0.3 * np.sin(2.0 * np.pi * 0.37 * t)            # non-constant rate
    gs = rate * t + wobble
    inc = np.concatenate([[0.0], np.diff(gs)]) * (1.0 + eps1)
    return t, inc, gs


def test_closed_form_with_gaps_and_nans():
    """SINS increments exactly (1 + ε1) × the GS increments: ε̂1 = ε1/(1 + ε1) in every
    interval, whatever samples are missing, provided the step across a gap is dropped."""
    eps1 = 6e-4
    t, inc, gs = _synthetic(eps1)
    inc[[5, 300, 301, 1500]] = np.nan
    gs[[77, 1200]] = np.nan
    keep = ~((t > 7.0) & (t <= 7.5))
    res = rsf.calibrate(rsf.RSFRecord(t=t[keep], sins_increment=inc[keep],
                                      gs_angle=gs[keep]), 2.0)
    assert res.n_intervals == 10
    np.testing.assert_allclose(res.eps1_hat, eps1 / (1 + eps1), rtol=1e-9)
    # power: the step across the gap, if used, spoils its interval
    naive = np.diff(gs[keep])
    bad = np.nansum(inc[keep][1:][(t[keep][1:] > 6.0) & (t[keep][1:] <= 8.0)])
    bad_gs = np.nansum(naive[(t[keep][1:] > 6.0) & (t[keep][1:] <= 8.0)])
    assert abs((bad - bad_gs) / bad - eps1 / (1 + eps1)) > 0.1


def test_residual_and_k_forms():
    eps1 = 1e-3
    t, inc, gs = _synthetic(eps1)
    rec = rsf.RSFRecord(t=t, sins_increment=inc, gs_angle=gs)
    lin = rsf.calibrate(rec, 1.0, k_form="linear")
    rec_ = rsf.calibrate(rec, 1.0, k_form="reciprocal")
    np.testing.assert_allclose(lin.k, 1 - eps1 / (1 + eps1), rtol=1e-12)
    np.testing.assert_allclose(rec_.k, 1 / (1 + eps1 / (1 + eps1)), rtol=1e-12)
    # after the first interval the linear K removes the error exactly: the residual
    # stops growing; uncorrected it grows as ε1 × angle
    after = t >= 1.0
    assert np.ptp(lin.residual[after]) < 1e-9
    assert lin.residual_raw[-1] == pytest.approx(eps1 * (gs[-1] - gs[0]), rel=1e-9)


def test_wrapped_counts_equal_gs_angle(flight):
    a = rsf.calibrate(rsf.record_from_simulation(flight), 1.0)
    b = rsf.calibrate(rsf.record_from_simulation(flight, encoder=True), 1.0)
    np.testing.assert_allclose(b.eps1_hat, a.eps1_hat, rtol=0, atol=1e-12)


def test_wrapped_counts_with_missing_values():
    """Counts of a body turning 0.3 rev per sample; a NaN count drops the two samples it
    touches, and the unwrapping stays exact (closed form again)."""
    n_rev, eps1 = 400, 2e-4
    t = np.arange(3001) * 0.001
    counts_true = np.round(0.3 * n_rev * np.arange(3001)).astype(float)
    c = np.mod(counts_true, n_rev)
    c[[10, 2000]] = np.nan
    ang = counts_true * 2 * math.pi / n_rev
    inc = np.concatenate([[0.0], np.diff(ang)]) * (1 + eps1)
    res = rsf.calibrate(rsf.RSFRecord(t=t, sins_increment=inc, encoder_counts=c,
                                      counts_per_rev=n_rev), 1.0)
    np.testing.assert_allclose(res.eps1_hat, eps1 / (1 + eps1), rtol=1e-9)
    assert res.samples_skipped == 4


def test_bad_input():
    t = np.arange(5) * 0.01
    with pytest.raises(ValueError, match="exactly one of gs_angle and encoder_counts"):
        rsf.RSFRecord(t=t, sins_increment=t, gs_angle=t, encoder_counts=t,
                      counts_per_rev=4)
    with pytest.raises(ValueError, match="encoder_counts must be whole counts"):
        rsf.RSFRecord(t=t, sins_increment=t, encoder_counts=t + 0.5, counts_per_rev=4)
    rec = rsf.RSFRecord(t=t, sins_increment=t, gs_angle=t)
    with pytest.raises(ValueError, match="period must be"):
        rsf.calibrate(rec, -1.0)
    with pytest.raises(TypeError, match="record must be an RSFRecord"):
        rsf.calibrate({"t": t}, 1.0)


def test_jittered_time_stamps_are_not_gaps():
    """±20 % jitter on every time stamp: every sample is still used and the closed form
    holds; a true gap (a missing row) is still detected."""
    eps1 = 6e-4
    t, inc, gs = _synthetic(eps1)
    tj = t + np.random.default_rng(1).uniform(-2e-3, 2e-3, t.size)
    tj[0] = 0.0
    res = rsf.calibrate(rsf.RSFRecord(t=tj, sins_increment=inc, gs_angle=gs), 2.0)
    assert res.gaps == 0 and res.samples_used == t.size - 1
    np.testing.assert_allclose(res.eps1_hat, eps1 / (1 + eps1), rtol=1e-9)
    keep = np.ones(t.size, bool)
    keep[500] = False
    res = rsf.calibrate(rsf.RSFRecord(t=tj[keep], sins_increment=inc[keep],
                                      gs_angle=gs[keep]), 2.0)
    assert res.gaps == 1 and res.samples_used == t.size - 3


# Wraps, slips, gaps, reversals -------------------------------------------------
def _with_gs(rec: rsf.RSFRecord, gs: np.ndarray, inc=None, t=None) -> rsf.RSFRecord:
    return rsf.RSFRecord(t=rec.t if t is None else t,
                         sins_increment=rec.sins_increment if inc is None else inc,
                         gs_angle=gs)


def test_wrapped_gs_angle_is_unwrapped_with_a_note(flight):
    """gs_angle wrapped into [0, 2π) or (−π, π]: the unwrapped record's ε̂1 (to 1e-9 of a
    radian's rounding), with a note saying "wrapped"; a wrong unwrapping (the wraps left in)
    would give ε̂1 far from it (power: the raw spans' ε̂1)."""
    rec = rsf.record_from_simulation(flight)
    ref = rsf.calibrate(rec, 1.0)
    for wrapped, band in ((np.mod(rec.gs_angle, 2 * math.pi), "[0, 2π)"),
                          (np.angle(np.exp(1j * rec.gs_angle)), "(−π, π]")):
        res = rsf.calibrate(_with_gs(rec, wrapped), 1.0)
        np.testing.assert_allclose(res.eps1_hat, ref.eps1_hat, rtol=0, atol=1e-9)
        assert len(res.notes) == 1 and f"wrapped into {band}" in res.notes[0]
        assert res.slips_repaired == 0
        raw = np.diff(wrapped[::1000]) - np.add.reduceat(rec.sins_increment[1:],
                                                         np.arange(0, 60000, 1000))
        assert np.max(np.abs(raw)) > 1.0           # the wraps are really there


def test_whole_turn_slip_repaired_or_refused_quarter_turn_refused(flight):
    """A 2π slip at t = 23.4567 s: repaired (ε̂1 as without it, note with its time) or,
    slips="refuse", refused naming it; a π/2 slip refused naming "quarter turn"; without
    the repair the slipped interval's ε̂1 is off by about 2π/turn (the issue's −6150 ppm)."""
    rec = rsf.record_from_simulation(flight)
    ref = rsf.calibrate(rec, 1.0)
    k = int(np.searchsorted(rec.t, 23.4567))
    gs = rec.gs_angle.copy()
    gs[k:] += 2 * math.pi
    res = rsf.calibrate(_with_gs(rec, gs), 1.0)
    np.testing.assert_allclose(res.eps1_hat, ref.eps1_hat, rtol=0, atol=1e-9)
    assert res.slips_repaired == 1
    assert "slips a whole turn" in res.notes[0] and f"t = {rec.t[k]:.6g} s" in res.notes[0]
    turn = float(np.sum(rec.sins_increment[1:1001]))
    assert abs(2 * math.pi / turn) > 0.3            # what an unrepaired slip would add
    with pytest.raises(ValueError, match=r"slips a whole turn .*refused"):
        rsf.calibrate(_with_gs(rec, gs), 1.0, slips="refuse")
    gs = rec.gs_angle.copy()
    gs[k:] -= math.pi / 2
    with pytest.raises(ValueError, match=rf"quarter turn \(-1 π/2\).*t = {rec.t[k - 1]:.6g} s"):
        rsf.calibrate(_with_gs(rec, gs), 1.0)


def test_gap_is_named_and_reversal_reported_with_abs_rate(flight):
    """A 2 s gap: a note naming the gap, ε̂1 within 4 standard errors of ε1/(1+ε1); a roll
    rate that reverses every 2.5 s: mean |ω| is the flight's 900 °/s (the signed mean
    is near 0), the intervals with a reversal inside are flagged and left out of the mean."""
    rec = rsf.record_from_simulation(flight)
    keep = (rec.t < 30.0) | (rec.t >= 32.0)
    res = rsf.calibrate(rsf.RSFRecord(t=rec.t[keep], sins_increment=rec.sins_increment[keep],
                                      gs_angle=rec.gs_angle[keep]), 1.0)
    assert res.gaps == 1 and res.gap_time == pytest.approx(2.0, abs=2e-3)
    assert "1 gap(s) in the time stamps" in res.notes[0]
    st = res.eps1_stats()
    eps1 = CFG.sins.eps1
    assert abs(st["mean"] - eps1 / (1 + eps1)) < 4 * st["sem"]
    sign = np.where((rec.t // 2.5) % 2 == 0, 1.0, -1.0)
    gs_inc = np.diff(rec.gs_angle, prepend=rec.gs_angle[0])
    rev = rsf.calibrate(rsf.RSFRecord(t=rec.t, sins_increment=rec.sins_increment * sign,
                                      gs_angle=np.cumsum(gs_inc * sign)), 1.0)
    assert math.degrees(rev.mean_rate) == pytest.approx(900.0, rel=0.01)
    assert abs(math.degrees(float(np.mean(rev.rate)))) < 100.0
    assert rev.reverses and rev.reversal.sum() == 12      # t = 2.5, 7.5, ... 57.5 s
    st = rev.eps1_stats()
    assert st["left_out"] == 12 and abs(st["mean"] - eps1 / (1 + eps1)) < 4 * st["sem"]


def test_spread_and_standard_error_of_the_mean(flight):
    """sem = spread/√n.  With independent interval errors (a synthetic record whose scale
    factor is drawn afresh for every interval) the mean's scatter over 40 records is the
    sem within a factor 1.5, and lag1 ≈ 0; on the simulated flights, whose interval errors
    are the GS angle's end-point errors (lag1 ≈ −½, closed form of a telescoping error),
    the sem is an upper bound of the mean's scatter (while the spread is 7.7 times the
    sem: reading it as the mean's error would be far off)."""
    rng = np.random.default_rng(9)
    t = np.arange(60001) * 1e-3
    inc = np.concatenate([[0.0], np.full(60000, math.radians(900.0) * 1e-3)])
    means, sems, lags = [], [], []
    for _ in range(40):
        eps = np.repeat(rng.normal(600e-6, 100e-6, 60), 1000)   # one per interval
        gs = np.concatenate([[0.0], np.cumsum(inc[1:] * (1.0 - eps))])
        st = rsf.calibrate(rsf.RSFRecord(t=t, sins_increment=inc, gs_angle=gs),
                           1.0).eps1_stats()
        means.append(st["mean"])
        sems.append(st["sem"])
        lags.append(st["lag1"])
    assert 1 / 1.5 < float(np.std(means, ddof=1) / np.mean(sems)) < 1.5
    assert abs(float(np.mean(lags))) < 0.1
    cfg = rsf.SimulationConfig(duration=60.0, sample_rate=1000.0, n_runs=40)
    sim = rsf.simulate_flight(cfg, seed=5)
    means, sems, lags = [], [], []
    for m in range(40):
        st = rsf.calibrate(rsf.record_from_simulation(sim, m), 1.0).eps1_stats()
        means.append(st["mean"])
        sems.append(st["sem"])
        lags.append(st["lag1"])
        assert st["sem"] == pytest.approx(st["spread"] / math.sqrt(st["n"]), rel=1e-12)
    assert float(np.std(means, ddof=1)) < float(np.mean(sems))
    assert float(np.mean(lags)) == pytest.approx(-0.5, abs=0.1)
