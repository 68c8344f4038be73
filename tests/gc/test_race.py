"""The race of paper GC's method against the rate-sensor method it replaces:
``gc.racing.rate_sensor`` and ``gc.racing.comparison``.

Independent references: the ledger's time of GC's filter (itself tested against the
plain-numpy filter of ``tests/support/gc_reference.py``); closed forms of the classical estimator's
variance (white noise: ``q/T``; coloured noise: the double sum of the shaping filters'
autocorrelations over the samples); the information form of the optimal estimator on
static states; a simulated truth (nonlinear, its own grid) with a χ² band, and a wrong truth
that must fail it; for the rebalance loop: the first-order closed form of the
pickoff noise through the loop, a closed-loop truth that passes with the matched model and
fails with the pickoff noise left out, and the acceptance "ten times C_as makes the rival
slower by more than 20 %".
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from gyrolib import gc
from gyrolib.book.ledger import collect
from gyrolib.book.ledger.gc import SIGMA_C
from gyrolib.gc.racing.rate_sensor import RS_STATE_NAMES

BASE = gc.GyrocompassParams()
PROC = gc.RateSensorProcedure()


@pytest.fixture(scope="module")
def result() -> gc.RaceResult:
    return gc.race()


# GC's time ----------------------------------------------------------------------------------
def test_t_c_gc_is_the_ledgers_covariance_time(result):
    led = {it.id: it for it in collect()}   # the session's one computation (conftest)
    assert result.t_c_gc == pytest.approx(led["gc.time_to_sigma_c"].reproduced_value,
                                          rel=1e-12)
    assert PROC.sigma_c == pytest.approx(SIGMA_C, rel=1e-15)
    assert round(result.t_c_gc, 1) == 24.1        # the number at the defaults
    # the GC curve crosses σ_c there
    assert np.interp(result.t_c_gc, result.t_gc, result.sigma_gc) == pytest.approx(
        SIGMA_C, rel=1e-3)


# The acceptance items ------------------------------------------------------------------------
def test_rate_sensor_time_counts_the_turn_and_the_settling(result):
    assert result.t_c_rate_sensor >= PROC.T_rot + PROC.T_settle
    assert result.t_c_rate_sensor == pytest.approx(result.t1 + PROC.overhead + result.t2,
                                                   abs=1e-9)
    # measurement time "chosen to just reach σ_c": one sample less, however it is split
    # between the windows, fails
    m = gc.rate_sensor_model(BASE, PROC)
    assert m.classical_sigma(result.t1, result.t2) <= PROC.sigma_c
    dt = PROC.sample_dt
    n = round((result.t1 + result.t2) / dt)
    assert min(m.classical_sigma_samples(n1, n - 1 - n1) for n1 in range(1, n - 1)) \
        > PROC.sigma_c


def test_windows_chosen_optimally(result):
    # the classical split is the best of its total (checked against every split), and the
    # optimal estimator's position 1 is no worse than a tenth longer or shorter
    m = gc.rate_sensor_model(BASE, PROC)
    dt = PROC.sample_dt
    n1, n2 = round(result.t1 / dt), round(result.t2 / dt)
    best = min(m.classical_sigma_samples(k, n1 + n2 - k) for k in range(1, n1 + n2))
    assert m.classical_sigma_samples(n1, n2) <= best * (1 + 1e-12)
    k1 = round(result.t1_optimal / dt)
    for k in (round(0.9 * k1), round(1.1 * k1)):
        t = m.optimal_run_samples(k, 2 * n2).time_to(PROC.sigma_c)
        assert t >= result.t_c_rate_sensor_optimal - 1e-9


@pytest.mark.parametrize("changes", [
    {}, {"vibration_frame": "sensor"}, {"rate_noise": 6e-14}, {"T_rot": 0.0, "T_settle": 0.0},
    {"sigma1_sq": 0.1 * BASE.sigma1_sq}, {"split": 0.3}, {"shaping_p0": "zero"},
])
def test_optimal_is_never_slower_than_classical(changes):
    sw = gc.race_sweep(cases=[changes])
    assert sw.t_c_rate_sensor_optimal[0] <= sw.t_c_rate_sensor[0]
    assert sw.t_c_rate_sensor_optimal[0] >= PROC.overhead * (1 if "T_rot" not in changes
                                                             else 0)


@pytest.mark.parametrize(("t1", "t2"), [(5.0, 5.0), (20.0, 40.0), (60.8, 60.8)])
def test_optimal_sigma_below_classical_on_the_same_data(t1, t2):
    # the Kalman filter is the best linear estimator on the same samples: its σ at the end
    # of position 2 is at most the half-sum's
    m = gc.rate_sensor_model(BASE, PROC)
    assert m.optimal_run(t1, t2).sigma[-1] <= m.classical_sigma(t1, t2) * (1 + 1e-9)


def test_faster_percent_definition(result):
    assert result.faster_percent == pytest.approx(
        100 * (1 - result.t_c_gc / result.t_c_rate_sensor))
    assert result.faster_percent_optimal == pytest.approx(
        100 * (1 - result.t_c_gc / result.t_c_rate_sensor_optimal))
    assert "race" in result.evidence() and f"{result.t_c_gc:.1f} s" in result.evidence()


# The classical estimator against closed forms --------------------------------------------------
QUIET = replace(BASE, sigma1_sq=1e-30, sigma2_sq=1e-40)
#: The rival's loop without its noises (pickoff and quantization): the old closed forms.
NOLOOP = {"angle_noise_scale": 0.0, "quantization": 0.0}


def test_classical_sigma_white_noise_closed_form():
    # shaping filters silenced, no turning error: only the white noises of the rate sensor
    # and inclinometer z are left, and the half-sum's variance is ¼ Σ q/T + (Ω_v/2g)² Σ C/T
    proc = replace(PROC, sigma_rot=0.0, rate_noise=3e-15, **NOLOOP)
    m = gc.rate_sensor_model(QUIET, proc)
    for t1, t2 in ((1.0, 1.0), (3.0, 7.5), (20.0, 5.0)):
        inv = 1 / t1 + 1 / t2
        want = 0.25 * proc.rate_noise * inv + (QUIET.Omega_v / (2 * QUIET.g))**2 \
            * QUIET.C_incl_z * inv
        assert m.classical_sigma(t1, t2) ** 2 == pytest.approx(want, rel=1e-9)


@pytest.mark.parametrize("frame", ["carrier", "sensor"])
def test_classical_sigma_coloured_noise_double_sum(frame):
    # the half-sum's error is a weighted sum of the N1, N3 samples (plus white noise and the
    # turn): its variance is the double sum of the weights times each shaping filter's
    # autocovariance at the sample lags (expm per lag, not the doubling of the model)
    proc = replace(PROC, vibration_frame=frame, T_rot=7.0, T_settle=5.55, **NOLOOP)
    dt, n1, n2 = proc.sample_dt, 12, 9
    m = gc.rate_sensor_model(BASE, proc)
    got = m.classical_sigma(n1 * dt, n2 * dt) ** 2
    t = np.concatenate((dt * np.arange(1, n1 + 1), n1 * dt + proc.overhead
                        + dt * np.arange(1, n2 + 1)))
    s = np.where(np.arange(n1 + n2) < n1, 1.0, -1.0 if frame == "carrier" else 1.0)
    n = np.where(np.arange(n1 + n2) < n1, n1, n2)
    ub, wz = BASE.omega_ub / BASE.g, BASE.Omega_v / (2 * BASE.g)
    c1 = s * ub / (2 * n) - wz * s / n          # weights of N1 (unbalance, inclinometer z)
    c3 = 1.0 / (2 * n)                          # weights of N3
    lags = np.abs(t[:, None] - t[None, :])
    var = 0.0
    for filt, c in ((BASE.vibration_filter(), c1), (BASE.random_drift_filter(), c3)):
        uniq, inv = np.unique(np.round(lags, 9), return_inverse=True)
        R = np.array([filt.variance() * filt.autocorrelation(x) for x in uniq])
        var += c @ R[inv.reshape(lags.shape)] @ c
    var += 0.25 * proc.rate_noise * (1 / (n1 * dt) + 1 / (n2 * dt))
    var += wz**2 * BASE.C_incl_z * (1 / (n1 * dt) + 1 / (n2 * dt))
    var += m.turn_floor**2
    assert got == pytest.approx(var, rel=1e-7)


@pytest.mark.parametrize("bandwidth", [1.0, 10.0, 30.0])
def test_pickoff_noise_through_the_loop_closed_form(bandwidth):
    # shaping filters silenced, no turn, a tiny torquer noise: the half-sum's error is the
    # float's motion at the four window ends, (f/H)(β_end − β_start)/T per window, with β
    # the pickoff noise low-passed by the loop (first order: variance C_as ω_b / 2; the
    # ends far apart, so independent), plus the pulse count's ends (variance q²/12 each)
    q = 1e-7
    proc = replace(PROC, sigma_rot=0.0, rate_noise=1e-24, loop_bandwidth=bandwidth,
                   quantization=q, sigma_scale=0.0)
    m = gc.rate_sensor_model(QUIET, proc)
    for t1, t2 in ((20.0, 20.0), (30.0, 50.0)):
        ends = 2 * (1 / t1**2 + 1 / t2**2)
        want = 0.25 * ends * ((BASE.f / BASE.H)**2 * BASE.C_as * bandwidth / 2 + q**2 / 12)
        want += (BASE.Omega_v / (2 * BASE.g))**2 * BASE.C_incl_z * (1 / t1 + 1 / t2)
        # the first-order loop leaves out the float's inertia: a share I ω_b / f of the
        # variance (1.6 % at 10 rad/s)
        assert m.classical_sigma(t1, t2)**2 == pytest.approx(
            want, rel=0.01 + 1.2 * BASE.I * bandwidth / BASE.f)


def test_ten_times_the_pickoff_noise_slows_the_rival_by_more_than_20_percent():
    # the acceptance item, for both estimators and across the loop's bandwidths
    for bw in (1.0, 10.0, 100.0):
        pr = replace(PROC, loop_bandwidth=bw)
        sw = gc.race_sweep(BASE, pr, cases=[{}, {"C_as": 10 * BASE.C_as}])
        assert sw.t_c_rate_sensor[1] > 1.2 * sw.t_c_rate_sensor[0]
        assert sw.t_c_rate_sensor_optimal[1] > 1.2 * sw.t_c_rate_sensor_optimal[0]


def test_faster_loop_slows_the_rival():
    # a wider loop passes more pickoff noise: the rival's time grows with the bandwidth
    sw = gc.race_sweep(cases=[{"loop_bandwidth": b} for b in (1.0, 10.0, 100.0)])
    assert np.all(np.diff(sw.t_c_rate_sensor) > 0)
    assert np.all(np.diff(sw.t_c_rate_sensor_optimal) > 0)


def test_turn_floor_and_accuracy_limit():
    limit = gc.turn_accuracy_limit(BASE, PROC.sigma_c)
    m = gc.rate_sensor_model(BASE, replace(PROC, sigma_rot=limit))
    assert m.turn_floor == pytest.approx(PROC.sigma_c, rel=1e-12)
    # E[d²] of d = Ω_h(cos ψ − cos(ε − ψ)) by quadrature of the two normal priors
    x, w = np.polynomial.hermite_e.hermegauss(40)
    w = w / w.sum()
    psi, eps = np.meshgrid(BASE.sigma_psi0 * x, limit * x)
    d = BASE.Omega_h * (np.cos(psi) - np.cos(eps - psi))
    assert math.sqrt(np.einsum("i,j,ij->", w, w, d**2)) / 2 == pytest.approx(PROC.sigma_c,
                                                                             rel=1e-3)


# The optimal estimator against the information form -------------------------------------------
def test_optimal_run_information_form_on_static_states():
    # shaping filters silenced: the states are constants, and the Kalman filter's posterior is
    # the batch one, P⁻¹ = P0⁻¹ + Σ Hᵀ R⁻¹ H over the samples of each phase
    proc = replace(PROC, T_rot=3.0, T_settle=2.0, sigma_rot=math.radians(1.0),
                   angle_noise_scale=0.0, quantization=0.0)   # no loop noise: static states
    m = gc.rate_sensor_model(QUIET, proc)
    n1, n2, ns = 40, 30, 20
    run = m.optimal_run(n1 * proc.sample_dt, n2 * proc.sample_dt)
    k = 5                                         # ω_gc, e, d, δ, γ
    Ri = np.diag(1 / m.r)
    info = np.linalg.inv(m.P0[:k, :k])
    info += n1 * m.H1[:, :k].T @ Ri @ m.H1[:, :k]
    info += ns * m.H2[1:, :k].T @ Ri[1:, 1:] @ m.H2[1:, :k]
    info += n2 * m.H2[:, :k].T @ Ri @ m.H2[:, :k]
    assert run.sigma[-1] == pytest.approx(math.sqrt(np.linalg.inv(info)[0, 0]), rel=1e-6)
    assert [ph[0] for ph in run.phases] == ["position 1", "turn", "settling", "position 2"]
    assert run.phases[-1][2] == pytest.approx(n1 * 0.1 + 5.0 + n2 * 0.1)


def test_optimal_needs_the_turn():
    # the Earth-rate reading is unknown to the method (σ = sigma_scale Ω_h): position 1 alone
    # cannot separate it from ω_gc, so σ stalls near sigma_scale Ω_h until position 2
    m = gc.rate_sensor_model(BASE, PROC)
    run = m.optimal_run(30.0, 1.0)
    s_end_1 = run.sigma[np.searchsorted(run.t, 30.0)]
    assert s_end_1 > 0.9 * PROC.sigma_scale * BASE.Omega_h > PROC.sigma_c


# Monte Carlo: the classical σ on an independent truth -------------------------------------------
def test_monte_carlo_matched_truth_inside_the_band(result):
    mc = gc.rate_sensor_monte_carlo(BASE, PROC, t1=result.t1, t2=result.t2, n_runs=400,
                                    seed=17)
    assert mc.inside, (mc.ratio, mc.band)
    assert mc.sigma == pytest.approx(PROC.sigma_c, rel=0.05)


def test_monte_carlo_wrong_truth_outside_the_band(result):
    # the same check with power: a truth with σ1² × 9 (σ1 × 3) while the model keeps σ1²
    wrong = replace(BASE, sigma1_sq=9 * BASE.sigma1_sq)
    mc = gc.rate_sensor_monte_carlo(BASE, PROC, t1=result.t1, t2=result.t2, n_runs=400,
                                    seed=17, truth_params=wrong)
    assert not mc.inside and mc.ratio > mc.band[1], (mc.ratio, mc.band)


def test_monte_carlo_pickoff_noise_left_out_fails(result):
    # the power of the closed-loop check: a model without the pickoff noise against the
    # truth's closed loop with it
    mc = gc.rate_sensor_monte_carlo(BASE, replace(PROC, angle_noise_scale=0.0), t1=result.t1,
                                    t2=result.t2, n_runs=400, seed=17, truth_procedure=PROC)
    assert not mc.inside and mc.ratio > mc.band[1], (mc.ratio, mc.band)


@pytest.mark.parametrize("bandwidth", [1.0, 100.0])
def test_monte_carlo_closed_loop_other_bandwidths(bandwidth):
    proc = replace(PROC, loop_bandwidth=bandwidth)
    r = gc.race(BASE, proc)
    mc = gc.rate_sensor_monte_carlo(BASE, proc, t1=r.t1, t2=r.t2, n_runs=256, seed=2)
    assert mc.inside, (mc.ratio, mc.band)


def test_monte_carlo_sensor_frame_inside_the_band():
    proc = replace(PROC, vibration_frame="sensor")
    mc = gc.rate_sensor_monte_carlo(BASE, proc, t1=5.0, t2=5.0, n_runs=400, seed=5)
    assert mc.inside, (mc.ratio, mc.band)


def test_monte_carlo_large_turning_error():
    # σ_ε = 2°: the turn dominates, the truth's cos(π + ε − ψ) in full against the model's
    # second moment of d.  d ≈ Ω_h ε²/2 is far from normal, so the χ² band does not apply;
    # the mean of the squared errors is judged by its own standard error (CLT, 4 σ)
    proc = replace(PROC, sigma_rot=math.radians(2.0), **NOLOOP)
    mc = gc.rate_sensor_monte_carlo(BASE, proc, t1=5.0, t2=5.0, n_runs=1000, seed=5)
    m = gc.rate_sensor_model(BASE, proc)
    assert m.turn_floor > 0.8 * mc.sigma          # the turn is what this run tests
    e2 = mc.errors**2
    se = e2.std(ddof=1) / math.sqrt(e2.size)
    assert abs(e2.mean() - mc.sigma**2) < 4 * se
    # and the same check fails for a model without the turning error
    no_turn = m.classical_sigma(5.0, 5.0)**2 - m.turn_floor**2
    assert abs(e2.mean() - no_turn) > 4 * se


def test_monte_carlo_runs_do_not_depend_on_n_runs():
    a = gc.rate_sensor_monte_carlo(t1=1.0, t2=1.0, n_runs=70, seed=9)
    b = gc.rate_sensor_monte_carlo(t1=1.0, t2=1.0, n_runs=130, seed=9)
    np.testing.assert_allclose(a.errors, b.errors[:70], rtol=1e-12, atol=0)


def _numpy_truth_errors(truth, rng, n1: int, n2: int, B: int) -> np.ndarray:
    """The rival's truth as it was written before its numba kernels: the same
    equations stepped with numpy over the lanes, a second implementation of
    ``_Truth.errors`` (the same random draws in the same order)."""
    tp, proc = truth.tp, truth.proc
    dt, q = proc.sample_dt, proc.quantization
    psi = tp.sigma_psi0 * rng.standard_normal(B)
    omega = tp.sigma_gc0 * rng.standard_normal(B)
    gamma = tp.sigma_gamma0 * rng.standard_normal(B)
    k = proc.sigma_scale * rng.standard_normal(B)
    eps = proc.sigma_rot * rng.standard_normal(B)
    x = truth.L @ rng.standard_normal((truth.L.shape[1], B))

    def advance(loop, n_fine, steps, rate_in):
        phi1, gam1, phi2, gam2, phil, gaml, h = steps
        w = rng.standard_normal((n_fine, 3, B))
        sd_n = math.sqrt(truth.c_as / h)
        integral = np.zeros(B)
        for i in range(n_fine):
            w_in = rate_in(x)
            torque = tp.H * w_in - tp.H * truth.k_b * sd_n * w[i, 2]
            loop[:] = phil @ loop + np.outer(gaml, torque)
            integral += h * w_in
            x[0:2] = phi1 @ x[0:2] + np.outer(gam1, w[i, 0])
            x[2:4] = phi2 @ x[2:4] + np.outer(gam2, w[i, 1])
        return integral

    def rate_in_at(theta, s):
        return lambda x_: (tp.Omega_h * np.cos(theta - psi) + tp.Omega_v * gamma + omega
                           + s * truth.ub * x_[0] + x_[2])

    rate1 = rate_in_at(np.zeros(B), 1.0)
    loop = np.vstack([rate1(x) / truth.k_b, np.zeros(B)])
    advance(loop, math.ceil(10.0 / (proc.loop_bandwidth * truth.h)), truth.fine, rate1)

    def window(n, rate_in, s):
        sum_r, sum_z = np.zeros(B), np.zeros(B)
        for _ in range(n):
            b0 = loop.copy()
            integral = advance(loop, truth.substeps, truth.fine, rate_in)
            e = rng.standard_normal((2, B))
            u = (integral - (tp.f * (loop[0] - b0[0]) + tp.I * (loop[1] - b0[1])) / tp.H) / dt
            sum_r += (1.0 + k) * u + truth.sd_rate * e[0]
            sum_z += tp.g * gamma + s * x[0] + truth.sd_z * e[1]
        if q > 0.0:
            a0 = q * rng.random(B)
            sum_r = q * (np.floor((a0 + dt * sum_r) / q) - np.floor(a0 / q)) / dt
        return sum_r / n, sum_z / n

    m1, z1 = window(n1, rate1, 1.0)
    rate2 = rate_in_at(np.pi + eps, truth.s2)
    advance(loop, truth.n_gap, truth.fine, rate2)
    if truth.rest is not None:
        advance(loop, 1, truth.rest, rate2)
    m2, z2 = window(n2, rate2, truth.s2)
    return 0.5 * (m1 + m2) - tp.Omega_v * (z1 + z2) / (2.0 * tp.g) - omega


@pytest.mark.parametrize(("proc", "truth_params"), [
    (PROC, BASE),
    (replace(PROC, T_settle=PROC.T_settle + 0.013, vibration_frame="carrier"),
     replace(BASE, sigma1_sq=9.0 * BASE.sigma1_sq))])
def test_monte_carlo_kernel_is_the_numpy_truth(proc, truth_params):
    """The rival's truth (numba kernels over the lanes) against the same equations stepped
    with numpy, on the same draws: every run's error to 1e-9 of their spread (rounding
    only: 2e-14 seen), with a part-of-a-step gap and the carrier frame in the second case;
    power: the same check fails on a numpy truth whose inclinometer noise is 1 % larger
    (the smallest term of the error: about 1e-8 of the spread)."""
    from gyrolib.gc.racing.rate_sensor import _Truth

    truth = _Truth(truth_params, proc, 10)
    assert (truth.rest is not None) == (proc is not PROC)
    kernel = truth.errors(np.random.default_rng(5), 30, 20, 16)
    ref = _numpy_truth_errors(truth, np.random.default_rng(5), 30, 20, 16)
    assert np.max(np.abs(kernel - ref)) < 1e-9 * np.std(ref)
    wrong = _Truth(truth_params, proc, 10)
    wrong.sd_z *= 1.01
    assert not np.max(np.abs(_numpy_truth_errors(wrong, np.random.default_rng(5), 30, 20, 16)
                             - kernel)) < 1e-9 * np.std(ref)


# Conditions and sweeps ---------------------------------------------------------------------------
@pytest.fixture(scope="module")
def cond(result) -> gc.RaceConditions:
    return result.conditions(50.0)


def test_conditions_at_the_reference_point(result, cond):
    assert cond.t_needed == pytest.approx(2 * result.t_c_gc)
    assert cond.holds_classical == (result.faster_percent > 50)
    assert cond.holds_optimal == (result.faster_percent_optimal > 50)
    assert cond.holds_at_reference == (min(result.faster_percent,
                                           result.faster_percent_optimal) > 50)


def test_conditions_boundaries_are_where_the_saving_crosses_50_percent(cond):
    # rerun the race a little below and above each boundary: the claim (against the optimal
    # estimator) fails below and holds above
    for field in ("loop_bandwidth", "overhead"):
        x = getattr(cond, f"{field}_min")
        assert 0 < x < math.inf
        cases = []
        for f in (0.97, 1.03):
            if field == "overhead":
                cases.append({"T_rot": PROC.T_rot * f * x / PROC.overhead,
                              "T_settle": PROC.T_settle * f * x / PROC.overhead})
            else:
                cases.append({field: f * x})
        below, above = gc.race_sweep(cases=cases).faster_percent("optimal")
        assert below < 50.0 < above


def test_scale_tolerance_of_the_claim(result, cond):
    # κ_max: GC with that scale uncertainty reaches σ_c at half the optimal rival's time
    # (a little below, GC is more than 50 % faster; a little above, not)
    assert cond.kappa_ceiling == pytest.approx(PROC.sigma_c / BASE.Omega_h, rel=1e-12)
    assert cond.kappa_ceiling == pytest.approx(2.26e-4, abs=0.01e-4)   # the 2.3e-4
    assert 0 < cond.kappa_max < cond.kappa_ceiling
    for f, holds in ((0.97, True), (1.03, False)):
        t_gc = gc.race(replace(BASE, sigma_hf_scale=f * cond.kappa_max)).t_c_gc
        assert (t_gc < 0.5 * result.t_c_rate_sensor_optimal) == holds
    # at the ceiling GC never reaches σ_c, and the rival (whose turn cancels the scale) is
    # unchanged
    r = gc.race(replace(BASE, sigma_hf_scale=1.01 * cond.kappa_ceiling))
    assert math.isnan(r.t_c_gc)
    assert r.t_c_rate_sensor == result.t_c_rate_sensor


def test_worst_corner_of_the_ranges(cond):
    # the worst corner takes κ = 10⁻³ > σ_c/Ω_h: GC never gets there, the claim fails
    assert gc.RACE_RANGES["sigma_hf_scale"][1] > cond.kappa_ceiling
    assert math.isnan(cond.worst_t_gc) and not cond.holds_over_ranges
    assert cond.worst_t_optimal < 0.5 * 2 * cond.t_needed


def test_conditions_text_is_readable(cond):
    text = cond.text()
    assert "^" not in text and "rad^2" not in text and "e-1" not in text
    assert "κ" in text and "10⁻⁵" in text and text.endswith(".")


def test_procedure_for_time_hits_the_target():
    q = gc.procedure_for_time(BASE, PROC, "rate_noise", 1200.0)
    sw = gc.race_sweep(cases=[{"rate_noise": q}])
    assert sw.t_c_rate_sensor[0] == pytest.approx(1200.0, rel=0.01)
    o = gc.procedure_for_time(BASE, PROC, "T_settle", 100.0, estimator="optimal")
    sw = gc.race_sweep(cases=[{"T_settle": o}])
    assert sw.t_c_rate_sensor_optimal[0] == pytest.approx(100.0, abs=0.2)
    assert gc.procedure_for_time(BASE, PROC, "overhead", 10.0) == 0.0   # slower even at 0
    b = gc.procedure_for_time(BASE, PROC, "loop_bandwidth", 100.0, estimator="optimal")
    sw = gc.race_sweep(cases=[{"loop_bandwidth": b}])
    assert sw.t_c_rate_sensor_optimal[0] == pytest.approx(100.0, rel=0.01)


@pytest.mark.parametrize("proc", [PROC, replace(PROC, loop_bandwidth=0.5)])
def test_bisections_short_answer_is_the_full_search(proc):
    """The bisections' question "does the optimal rival take longer than the target?"
    (``_optimal_exceeds``, which stops its searches early) answered as the full time from
    ``_rate_time`` answers it, at targets on both sides of the time, at the time itself and
    at the classical time (where its shortcut begins to answer); the same for the classical
    estimator's question (one search of the longest total within the target).  Power: an
    early stop that took the first window tried as the answer, and a total one sample short,
    get some of them wrong."""
    from gyrolib.gc.racing import comparison as C

    part = C._rate_part_at(BASE, proc)
    t_opt, t_cl = part.t_c_optimal, part.t_c
    targets = [0.5 * t_opt, t_opt * (1 - 1e-9), t_opt, t_opt * (1 + 1e-9),
               0.5 * (t_opt + t_cl), t_cl, 2.0 * t_cl]
    full = [C._rate_time(BASE, proc, "optimal") > x for x in targets]
    assert full[:2] == [True, True] and full[3:] == [False] * 4
    assert [C._optimal_exceeds(BASE, proc, x) for x in targets] == full
    # the classical estimator's question, at targets about its own time
    dt = proc.sample_dt
    cl_targets = [0.5 * t_cl, t_cl - dt, t_cl * (1 - 1e-12), t_cl, t_cl + 0.5 * dt, 2 * t_cl]
    cl_full = [C._rate_time(BASE, proc, "classical") > x for x in cl_targets]
    assert cl_full == [True, True, True, False, False, False]
    model = gc.rate_sensor_model(BASE, proc)
    assert [C._classical_exceeds_on(model, x) for x in cl_targets] == cl_full
    with pytest.MonkeyPatch.context() as mp:   # power: one sample short of the longest total
        reaches = C._split_reaches
        mp.setattr(C, "_split_reaches", lambda m, n: reaches(m, n - 1))
        assert [C._classical_exceeds_on(model, x) for x in cl_targets] != cl_full

    def first_window(model, n1_hint, n2_max, enough=-math.inf):
        t = C._optimal_time(model, n1_hint, n2_max)
        if t <= enough:
            raise C._Reached
        return t, n1_hint
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(C, "_optimal_windows", first_window)
        wrong = [C._optimal_exceeds(BASE, proc, x) for x in targets]
    assert wrong != full


def test_sweep_case_equals_the_race():
    r = gc.race(BASE, replace(PROC, T_settle=30.0))
    sw = gc.race_sweep(cases=[{"T_settle": 30.0}])
    assert (sw.t_c_gc[0], sw.t_c_rate_sensor[0]) == pytest.approx(
        (r.t_c_gc, r.t_c_rate_sensor), rel=1e-12)
    assert sw.t_c_rate_sensor_optimal[0] == pytest.approx(r.t_c_rate_sensor_optimal, rel=1e-9)


def test_sample_interval_converged():
    sw = gc.race_sweep(cases=[{"sample_dt": 0.1}, {"sample_dt": 0.02}])
    assert sw.t_c_rate_sensor[0] == pytest.approx(sw.t_c_rate_sensor[1], rel=0.005)
    # the optimal estimator tapers its weights against the differenced pickoff noise, which
    # finer samples help a little: it converges from above (0.1 s is 1.3 % slow, for the
    # rival: so the race errs, if at all, slightly in GC's favour)
    assert sw.t_c_rate_sensor_optimal[0] == pytest.approx(sw.t_c_rate_sensor_optimal[1],
                                                          rel=0.015)
    assert sw.t_c_rate_sensor_optimal[1] <= sw.t_c_rate_sensor_optimal[0]


def test_turn_cancels_a_carrier_vibration():
    # turned sensors see a carrier-fixed vibration with the other sign: the slow N1 largely
    # cancels in the corrected half-sum, which then needs less time than with Eq. (8)'s
    # literal +N1 in both positions
    sw = gc.race_sweep(cases=[{"vibration_frame": "carrier"}, {"vibration_frame": "sensor"}])
    assert sw.t_c_rate_sensor[0] < sw.t_c_rate_sensor[1]


# Bad input ---------------------------------------------------------------------------------------
@pytest.mark.parametrize("field", ["T_rot", "T_settle", "sigma_rot", "sigma_scale",
                                   "quantization", "angle_noise_scale"])
@pytest.mark.parametrize("value", [-1.0, float("nan"), float("inf")])
def test_procedure_rejects_bad_nonnegative(field, value):
    with pytest.raises(ValueError, match=field):
        gc.RateSensorProcedure(**{field: value})


@pytest.mark.parametrize("field", ["rate_noise", "sample_dt", "sigma_c", "t_max",
                                   "loop_bandwidth"])
@pytest.mark.parametrize("value", [0.0, -2.0, float("nan")])
def test_procedure_rejects_bad_positive(field, value):
    with pytest.raises(ValueError, match=field):
        gc.RateSensorProcedure(**{field: value})


@pytest.mark.parametrize(("field", "value", "err"), [
    ("split", 0.0, ValueError), ("split", 1.0, ValueError), ("split", float("nan"), ValueError),
    ("vibration_frame", "platform", ValueError), ("T_rot", "10", TypeError),
    ("rate_noise", True, TypeError),
])
def test_procedure_rejects_other_bad_values(field, value, err):
    with pytest.raises(err, match=field):
        gc.RateSensorProcedure(**{field: value})


def test_functions_reject_bad_arguments(result):
    with pytest.raises(TypeError, match="params"):
        gc.race("paper")
    with pytest.raises(TypeError, match="procedure"):
        gc.race(None, {"T_rot": 1.0})
    with pytest.raises(ValueError, match="cases"):
        gc.race_sweep(cases=[{"T_turn": 1.0}])
    with pytest.raises(TypeError, match="cases"):
        gc.race_sweep(cases={"T_rot": 1.0})
    with pytest.raises(ValueError, match="field"):
        gc.procedure_for_time(None, None, "sigma_rot", 100.0)
    with pytest.raises(ValueError, match="target"):
        gc.procedure_for_time(None, None, "overhead", -1.0)
    with pytest.raises(ValueError, match="estimator"):
        gc.procedure_for_time(None, None, "overhead", 100.0, estimator="best")
    m = gc.rate_sensor_model()
    with pytest.raises(ValueError, match="t1"):
        m.classical_sigma(0.0, 1.0)
    with pytest.raises(ValueError, match="t2"):
        m.optimal_run(1.0, 0.01)
    with pytest.raises(ValueError, match="n_runs"):
        gc.rate_sensor_monte_carlo(t1=1.0, t2=1.0, n_runs=1)
    with pytest.raises(TypeError, match="truth_params"):
        gc.rate_sensor_monte_carlo(t1=1.0, t2=1.0, truth_params=PROC)
    with pytest.raises(ValueError, match="percent"):
        result.conditions(100.0)
    with pytest.raises(ValueError, match="field"):
        gc.plot_race_sweep(gc.race_sweep(cases=[{}]), "T_rot")
    assert len(RS_STATE_NAMES) == m.P0.shape[0]


# The fast paths against the straightforward computation ------------------
# Kept here, private: the doubling loop, the classical σ and the optimal run as they were
# computed before the per-model caches (every power sum from scratch, position 1 from P0 and
# position 2 over the whole window for each n1).
_RTOL = 1e-12
_FAST_MODELS = [
    (BASE, PROC),
    (BASE, replace(PROC, loop_bandwidth=1.0, rate_noise=6e-17, T_rot=5.05, T_settle=4.97)),
    (replace(BASE, sigma1_sq=3 * BASE.sigma1_sq),
     replace(PROC, vibration_frame="sensor", rate_noise=2e-15, quantization=0.0)),
]


def _ref_power_sum(M, Q, k):
    Mk, Sk, B, SB = np.eye(M.shape[0]), np.zeros_like(Q), M.copy(), Q.copy()
    while k:
        if k & 1:
            Sk = SB + B @ Sk @ B.T
            Mk = B @ Mk
        k >>= 1
        if k:
            SB = SB + B @ SB @ B.T
            B = B @ B
    return Mk, Sk


def _ref_gap(m, length):
    from gyrolib.gc.racing.rate_sensor import _discretize
    dt = m.procedure.sample_dt
    k = math.floor(length / dt + 1e-9)
    Phi, Qd = _ref_power_sum(m.Phi, m.Qd, k)
    rest = length - k * dt
    if rest > 1e-12:
        Pr, Qr = _discretize(m.F, m.G, m.Q, rest)
        Phi, Qd = Pr @ Phi, Pr @ Qd @ Pr.T + Qr
    return Phi, Qd


def _ref_classical(m, n1, n2):
    n, na = m.P0.shape[0], m.P0.shape[0] + 4
    P = np.zeros((na, na))
    P[:n, :n] = m.P0
    Mk, Sk = _ref_power_sum(*m._window_step(m.H1, (n, n + 1), na), n1)
    P = Mk @ P @ Mk.T + Sk
    Pg, Qg = _ref_gap(m, m.procedure.overhead)
    A = np.eye(na)
    A[:n, :n] = Pg
    P = A @ P @ A.T
    P[:n, :n] += Qg
    Mk, Sk = _ref_power_sum(*m._window_step(m.H2, (n + 2, n + 3), na), n2)
    P = Mk @ P @ Mk.T + Sk
    c = m._classical_weights(n1, n2)
    return math.sqrt(max(c @ P @ c, 0.0))


def _ref_optimal_sigma(m, n1, n2):
    """σ of ω_gc at every sample of the optimal run, each phase one filter run from its
    start (gyrolib.filtering.covariance_fast on a freshly built model)."""
    from gyrolib.filtering import AffineDiscreteModel, covariance_fast
    n, proc = m.P0.shape[0], m.procedure
    dt = proc.sample_dt

    def kalman(H, r, P, k):
        z = np.zeros((1, n, n))
        mod = AffineDiscreteModel(seg=np.zeros(k, dtype=np.int64), a=np.zeros(k),
                                  b=np.zeros(k), Phi0=m.Phi[None], PhiA=z, PhiB=z,
                                  Qd0=m.Qd[None], QdA=z, QdB=z, H=np.ascontiguousarray(H),
                                  r=np.ascontiguousarray(r))
        return covariance_fast(mod, 0.5 * (P + P.T), k)

    run = kalman(m.H1, m.r, m.P0, n1)
    var = [run.var[:, 0]]
    P = run.P_stored[-1]
    Pg, Qg = _ref_gap(m, proc.T_rot)
    P = Pg @ P @ Pg.T + Qg
    ns = math.floor(proc.T_settle / dt + 1e-9)
    if ns:
        run = kalman(m.H2[1:], m.r[1:], P, ns)
        P = run.P_stored[-1]
        var.append(run.var[1:, 0])
    Pg, Qg = _ref_gap(m, proc.T_settle - ns * dt)
    P = Pg @ P @ Pg.T + Qg
    var.append([P[0, 0]])
    var.append(kalman(m.H2, m.r, P, n2).var[1:, 0])
    return np.sqrt(np.clip(np.concatenate(var), 0.0, None))


def _close(a, b) -> bool:
    a, b = np.asarray(a, float), np.asarray(b, float)
    same = (a == b) | (np.abs(a - b) <= _RTOL * np.abs(b)) | (np.isnan(a) & np.isnan(b))
    return a.shape == b.shape and bool(np.all(same))


@pytest.mark.parametrize(("p", "proc"), _FAST_MODELS)
def test_power_tables_and_classical_cache_match_the_plain_loop(p, proc):
    m = gc.rate_sensor_model(p, proc)
    na = m.P0.shape[0] + 4
    step = m._window_step(m.H2, (na - 2, na - 1), na)
    for k in (1, 2, 3, 7, 64, 1000, 1217, 4097):
        assert all(_close(x, y) for x, y in zip(m._table("w2").power_sum(k),
                                                _ref_power_sum(*step, k)))
    # many windows in a scrambled order, some repeated: the caches must not leak between them
    rng = np.random.default_rng(29)
    pairs = [(int(a), int(b)) for a, b in rng.integers(1, 1500, size=(25, 2))]
    for n1, n2 in pairs + pairs[:5] + [(1, 1), (1500, 1)]:
        assert _close(m.classical_sigma_samples(n1, n2), _ref_classical(m, n1, n2)), (n1, n2)
    # power: the same check on a deliberately wrong model (torquer noise 1e-6 higher) fails
    wrong = gc.rate_sensor_model(p, replace(proc, rate_noise=proc.rate_noise * (1 + 1e-6)))
    assert not _close(m.classical_sigma_samples(*pairs[0]), _ref_classical(wrong, *pairs[0]))


@pytest.mark.parametrize(("p", "proc"), _FAST_MODELS)
def test_optimal_run_and_time_to_match_a_fresh_run_per_n1(p, proc):
    m = gc.rate_sensor_model(p, proc)
    level = proc.sigma_c
    n2_max = 3000
    reached = 0
    # longer and shorter position 1 than any computed so far, repeats: resumed runs
    for n1 in (300, 900, 40, 600, 301, 900, 1, 2000, 2001):
        ref = _ref_optimal_sigma(m, n1, n2_max)
        run = m.optimal_run_samples(n1, n2_max)
        assert _close(run.sigma, ref), n1
        t_ref = gc.OptimalRun(t=run.t, sigma=ref, phases=run.phases).time_to(level)
        t_fast = m.optimal_time_to_samples(n1, n2_max, level)
        assert _close(t_fast, t_ref), (n1, t_fast, t_ref)
        reached += math.isfinite(t_ref)
    assert reached >= 4       # most windows reach σ_c: the early stop is exercised
    # not reached within the window: nan from both
    assert math.isnan(m.optimal_time_to_samples(50, 30, level))
    assert math.isnan(m.optimal_run_samples(50, 30).time_to(level))
    # power: stopping position 2 at its first chunk, whatever σ, gives another answer
    assert not _close(m.optimal_run_samples(900, 64).time_to(level),
                      m.optimal_run_samples(900, n2_max).time_to(level))


def test_race_and_sweep_match_the_straightforward_search(monkeypatch):
    """race() and race_sweep with the optimal search's fast time (position 2 stopped early,
    position 1 resumed, a window that cannot beat the best so far given up) against the
    same search on fresh full runs (the model's caches off for the optimal run), at the
    reference and five other points, the worst corner of the table's ranges among them
    (conditions() and procedure_for_time call the same search; their bisections are
    checked against the claim's own status in test_claim_map)."""
    r0 = gc.RACE_RANGES
    worst = {"loop_bandwidth": r0["loop_bandwidth"][0], "rate_noise": r0["rate_noise"][0]}

    def fast():
        r = gc.race(BASE, PROC)
        sw = gc.race_sweep(BASE, PROC, cases=[{"T_settle": 60.0}, {"split": 0.3},
                                              {"rate_noise": 6e-15, "loop_bandwidth": 3.0},
                                              worst])
        return ([r.t_c_rate_sensor, r.t_c_rate_sensor_optimal, r.t1, r.t2, r.t1_optimal],
                [sw.t_c_rate_sensor, sw.t_c_rate_sensor_optimal],
                r.sigma_optimal, r.sigma_classical)

    _forget_races()
    ours = fast()

    def plain_time_to(self, n1, n2_max, level, *, give_up_after=math.inf):
        # the whole window, never given up: the search's pruning is checked too
        ref = _ref_optimal_sigma(self, n1, n2_max)
        run = self.optimal_run_samples(n1, n2_max)
        return gc.OptimalRun(t=run.t, sigma=ref, phases=run.phases).time_to(level)

    monkeypatch.setattr(gc.RateSensorModel, "optimal_time_to_samples", plain_time_to)
    _forget_races()   # the race's memo would hand back `ours` (a check that cannot fail)
    try:
        ref = fast()
    finally:
        _forget_races()
    assert _close(ours[0], ref[0]), (ours[0], ref[0])
    assert all(_close(a, b) for a, b in zip(ours[1], ref[1]))
    assert _close(ours[2], ref[2]) and _close(ours[3], ref[3])


def _forget_races() -> None:
    """Empty the race's memo (``functools.lru_cache`` per inputs in
    :mod:`gyrolib.gc.racing.comparison`), so that the next call computes."""
    from gyrolib.gc.racing import comparison

    for f in (comparison._rate_time, comparison._rate_part_cached, comparison._boundary,
              comparison._gc_time):
        f.cache_clear()


def test_the_memo_is_emptied_for_the_reference_search():
    """Power of the reference test above: without emptying the memo, a changed
    optimal-time method is not even called."""
    calls = []
    gc.race_margin(BASE, PROC)

    def spy(self, *a, **k):
        calls.append(1)
        return math.nan

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(gc.RateSensorModel, "optimal_time_to_samples", spy)
        gc.race_margin(BASE, PROC)
        assert calls == []
        _forget_races()
        try:
            gc.race_margin(BASE, PROC)
        finally:
            _forget_races()
    assert calls


@pytest.mark.parametrize("change", [
    {}, {"sigma1_sq": 3.0}, {"sigma1_sq": 8.0}, {"sigma1_sq": 0.5},
    {"sigma_as_offset": 5e-6}, {"sigma_hf_scale": 5e-5}, {"measurement_noise": "variance"}])
def test_gc_time_stopped_at_the_crossing_is_the_full_analysis(change):
    """GC's time as the margins compute it (each covariance analysis stopped after σ has
    crossed) against the full analyses over 100 s and 1000 s read by time_to_sigma: the
    same number (the crossing between 100 s and 1000 s, an instrument state and the
    scale's drift included)."""
    from gyrolib.gc.racing.comparison import _gc_part, _gc_time

    p = replace(BASE, **{k: (x * getattr(BASE, k) if k == "sigma1_sq" else x)
                         for k, x in change.items()})
    full = _gc_part(p, PROC.sigma_c, PROC.t_max)[0]
    _forget_races()
    fast = _gc_time(p, PROC.sigma_c, PROC.t_max)
    assert (math.isnan(full) and math.isnan(fast)) or fast == pytest.approx(full, rel=1e-12)
    assert math.isfinite(full) and full > 0.0


@pytest.mark.parametrize("factor", [0.5, 2.0])
def test_worst_corner_gc_time_is_the_gc_part(factor):
    """conditions() skips GC's covariance analyses at the worst corner when the scale's drift
    alone reaches σ_c (factor 0.5): the time is the one _gc_part computes, there and when it
    does not (factor 2)."""
    from gyrolib.gc.racing.comparison import _gc_part
    kappa = gc.RACE_RANGES["sigma_hf_scale"][1]
    proc = replace(PROC, sigma_c=factor * kappa * BASE.Omega_h)
    c = gc.race(BASE, proc).conditions()
    t = _gc_part(replace(BASE, sigma_hf_scale=kappa), proc.sigma_c, proc.t_max)[0]
    assert math.isnan(t) == (factor < 1.0)
    assert (math.isnan(c.worst_t_gc) and math.isnan(t)) or c.worst_t_gc == pytest.approx(
        t, rel=1e-12)


# The optimal rival's search against the same search without its early stop -----------------
# At σ_k (``RateSensorProcedure.sigma_scale``) below about 1.52e-4 the optimal estimator's
# best window puts so much into position 1 that σ reaches σ_c right after the turn, before
# position 2 starts: a window given up because position 2 starts after the best time so far
# can still be the fastest.
def _straightforward_optimal(p: gc.GyrocompassParams, proc: gc.RateSensorProcedure,
                             classical: gc.RaceResult) -> tuple[float, float]:
    """The optimal rival's time to σ_c and its position 1 (s) by the race's search (a grid of
    position-1 lengths around the classical estimator's windows, then halving steps about
    the best), every window run whole (``optimal_run_samples(...).time_to``): no window
    given up, no run stopped early."""
    m = gc.rate_sensor_model(p, proc)
    dt, level = proc.sample_dt, proc.sigma_c
    if math.isfinite(classical.t_c_rate_sensor):
        n1_hint = round(classical.t1 / dt)
        n2_max = max(round(classical.t2 / dt), 1) + n1_hint
    else:
        n_all = math.floor((proc.t_max - proc.overhead) / dt + 1e-9)
        n1_hint, n2_max = n_all // 2, n_all - n_all // 2
    cache: dict[int, float] = {}

    def t(n1: int) -> float:
        n1 = max(1, n1)
        if n1 not in cache:
            x = m.optimal_run_samples(n1, n2_max).time_to(level)
            cache[n1] = math.inf if math.isnan(x) else x
        return cache[n1]

    grid = sorted({max(1, round(f * n1_hint)) for f in np.linspace(0.1, 2.0, 20)})
    best = min(grid, key=t)
    step = max(1, round(0.1 * n1_hint))
    while step >= 1:
        best = max(1, min((best - step, best, best + step), key=t))
        step //= 2
    return t(best), best * dt


def _margin_of(t_gc: float, t_classical: float, t_optimal: float) -> float:
    """The claim's margin (race_margin's definition) from the three times."""
    if not math.isfinite(t_gc):
        return -150.0
    return min(100.0 * (1.0 - t_gc / t) if math.isfinite(t) else 100.0
               for t in (t_classical, t_optimal)) - 50.0


def _rival_grid_disagreements(sigma_k: tuple[float, ...], sigma1: tuple[float, ...],
                              kappa: tuple[float, ...]) -> list[tuple]:
    """The points of the grid (σ_k, σ1² as a factor of the paper's, κ) where the race's
    optimal rival, its position 1 or the claim's margin differ from the straightforward
    search by more than 10⁻⁹ relative (the margin: or 10⁻⁷ points).  The classical
    estimator's windows, the search's starting point, are the race's (checked elsewhere);
    the rival does not read κ, so there is one reference per (σ_k, σ1²)."""
    bad = []
    for sk in sigma_k:
        proc = replace(PROC, sigma_scale=sk)
        for f in sigma1:
            p0 = replace(BASE, sigma1_sq=f * BASE.sigma1_sq)
            _forget_races()
            r = gc.race(p0, proc)
            ref_t, ref_n1 = _straightforward_optimal(p0, proc, r)
            ok = (_close_or_both_nan(r.t_c_rate_sensor_optimal, ref_t)
                  and _close_or_both_nan(r.t1_optimal, ref_n1))
            for kappa_ in kappa:
                p = replace(p0, sigma_hf_scale=kappa_)
                sw = gc.race_sweep(p, proc, cases=[{}])
                t_gc = float(sw.t_c_gc[0])
                margin = gc.race_margin(p, proc)
                ref_margin = _margin_of(t_gc, float(sw.t_c_rate_sensor[0]), ref_t)
                if not (ok and _close_or_both_nan(float(sw.t_c_rate_sensor_optimal[0]), ref_t)
                        and margin == pytest.approx(ref_margin, rel=1e-9, abs=1e-7)):
                    bad.append((sk, f, kappa_, r.t_c_rate_sensor_optimal, ref_t, margin,
                                ref_margin))
    _forget_races()
    return bad


def _close_or_both_nan(a: float, b: float) -> bool:
    return (math.isnan(a) and math.isnan(b)) or a == pytest.approx(b, rel=1e-9)


_SIGMA_K = (1.2e-4, 1.3e-4, 1.45e-4, 1.52e-4, 1.0e-3)


def test_race_matches_the_search_without_early_stop():
    """gc.race's optimal rival (its time and position 1) and the claim's margin equal the
    straightforward search's, every window run whole, to 10⁻⁹ relative, on a grid over σ_k
    (1.2–1.52·10⁻⁴, where σ reaches σ_c right after the turn, and the book's 10⁻³), σ1² and
    κ."""
    bad = _rival_grid_disagreements(_SIGMA_K, (1.0, 1.2), (0.0, 5e-5))
    assert not bad, bad


@pytest.mark.slow
def test_race_matches_the_search_without_early_stop_dense():
    """The same on a denser grid: σ_k from 10⁻⁴ to 2.5·10⁻⁴ in steps of 4 %, σ1² from 0.6
    to 1.4 times the paper's, κ up to the table's high end (where GC never reaches σ_c)."""
    sigma_k = tuple(float(x) for x in np.geomspace(1.0e-4, 2.5e-4, 24))
    kappa = (0.0, gc.RACE_RANGES["sigma_hf_scale"][1])
    bad = _rival_grid_disagreements(sigma_k, (0.6, 1.0, 1.4), kappa)
    assert not bad, bad[:5]


def _pre_fix_time_to(original):
    """The optimal time as the search's early stop gave it before it counted the samples
    ahead of position 2: position 2 cut at the best time so far, and a window whose
    position 2 starts later than that given up whatever σ had done before."""
    def time_to(self, n1, n2_max, level, *, give_up_after=math.inf):
        if math.isfinite(give_up_after) and self._omega_constant:
            dt = self.procedure.sample_dt
            start = n1 * dt + self.procedure.overhead
            n2_max = min(n2_max, math.ceil((give_up_after - start) / dt) + 1)
            if n2_max < 1:
                return math.nan
        return original(self, n1, n2_max, level)
    return time_to


def test_the_comparison_fails_with_the_pre_fix_early_stop(monkeypatch):
    """Power of the grid test: with the early stop that gave up every window whose position
    2 starts after the best time so far, the race at σ_k = 1.3·10⁻⁴ disagrees with the
    straightforward search (its rival 56.4 s instead of 43.3 s, the claim's margin
    positive)."""
    original = gc.RateSensorModel.optimal_time_to_samples
    monkeypatch.setattr(gc.RateSensorModel, "optimal_time_to_samples",
                        _pre_fix_time_to(original))
    try:
        bad = _rival_grid_disagreements((1.3e-4,), (1.0,), (0.0,))
    finally:
        _forget_races()
    assert bad, "the pre-fix early stop should disagree at sigma_k = 1.3e-4"
    (_, _, _, t_opt, t_ref, margin, ref_margin), = bad
    assert t_opt > 1.2 * t_ref and margin > 0.0 > ref_margin


@pytest.mark.parametrize(("sigma_k", "t_independent"), [(1.3e-4, 43.25), (1.45e-4, 46.27)])
def test_optimal_rival_where_sigma_crosses_after_the_turn(sigma_k, t_independent):
    """At σ_k = 1.3·10⁻⁴ and 1.45·10⁻⁴ an independent model of the procedure (its own code)
    gives the optimal rival 43.25 s and 46.27 s, savings of 44.4 % and 48.0 %: the race
    within 3 % of those times, and the claim "more than 50 % faster" fails there."""
    proc = replace(PROC, sigma_scale=sigma_k)
    _forget_races()
    r = gc.race(BASE, proc)
    assert r.t_c_rate_sensor_optimal == pytest.approx(t_independent, rel=0.03)
    assert r.faster_percent_optimal < 50.0
    assert gc.race_margin(BASE, proc) < 0.0
    # σ reaches σ_c before position 2 starts (right after the turn): the route the early
    # stop had missed
    start2 = r.t1_optimal + proc.overhead
    assert r.t_c_rate_sensor_optimal < start2


@pytest.mark.parametrize("n1", [340, 400, 600])
def test_give_up_after_is_exact(n1):
    """optimal_time_to_samples with give_up_after returns the whole run's time whenever that
    time is at most give_up_after, and otherwise nan or that same time: windows whose σ
    reaches σ_c before position 2 (n1 = 340, 400) and after it (600), with give_up_after
    before, at and after the crossing and before position 2 starts."""
    proc = replace(PROC, sigma_scale=1.3e-4)
    m = gc.rate_sensor_model(BASE, proc)
    n2_max, level = 1500, proc.sigma_c
    full = m.optimal_run_samples(n1, n2_max).time_to(level)
    assert math.isfinite(full)
    start2 = n1 * proc.sample_dt + proc.overhead
    for g in (0.5 * full, full - 0.05, full, full + 0.05, start2 - 1.0, start2 + 1.0,
              2.0 * full):
        t = m.optimal_time_to_samples(n1, n2_max, level, give_up_after=g)
        if full <= g:
            assert t == pytest.approx(full, rel=1e-12), (g, t, full)
        else:
            assert math.isnan(t) or t == pytest.approx(full, rel=1e-12), (g, t, full)
    # power: the pre-fix early stop gave up a window that reaches σ_c before position 2
    if full < start2 - 1.0:
        pre = _pre_fix_time_to(gc.RateSensorModel.optimal_time_to_samples)
        assert math.isnan(pre(m, n1, n2_max, level, give_up_after=start2 - 1.0))


@pytest.mark.parametrize("change", [{}, {"sigma1_sq": 2.0 * BASE.sigma1_sq},
                                    {"sigma_hf_scale": 1e-3}])
def test_reference_text_is_the_conditions_first_sentence(change):
    """RaceResult.reference_text (what race prints, without conditions()' searches) is the
    first sentence of conditions().text(): where the claim holds, fails, and where GC never
    reaches σ_c."""
    r = gc.race(replace(BASE, **change), PROC)
    assert r.reference_text() == r.conditions().reference_text()
    assert r.reference_text().startswith(("At the reference point", "GC's method does not"))


def test_rival_kept_without_gcs_instrument_constants():
    """The rival's times are kept without GC's instrument constants (which its model does not
    read): a margin with them ON read through the memo filled at the paper's parameters
    equals the margin computed afresh, and the rival was not computed again."""
    from gyrolib.gc.racing import comparison

    changed = replace(BASE, sigma_clock=3e-5, sigma_hf_scale=5e-5, sigma_as_offset=1e-7,
                      sigma_incl_bias=1e-4)
    _forget_races()
    try:
        gc.race_margin(BASE, PROC)
        misses = comparison._rate_part_cached.cache_info().misses
        via_memo = gc.race_margin(changed, PROC)
        assert comparison._rate_part_cached.cache_info().misses == misses
        _forget_races()
        fresh = comparison._rate_part(gc.rate_sensor_model(changed, PROC))
    finally:
        _forget_races()
    t_gc = comparison._gc_time(changed, PROC.sigma_c, PROC.t_max)
    assert via_memo == pytest.approx(
        min(100.0 * (1.0 - t_gc / t) for t in (fresh.t_c, fresh.t_c_optimal)) - 50.0,
        rel=1e-12)
