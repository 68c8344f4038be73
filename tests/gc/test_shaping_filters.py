"""gyrolib.gc.model.shaping_filters against closed forms (sympy), a second algorithm (PSD quadrature
vs Lyapunov) and statistical bounds (seeded exact simulation), paper GC Eqs. (6), (7)."""

import dataclasses
import math

import numpy as np
import pytest
import scipy.linalg
import sympy as sp

from gyrolib.gc import (
    GyrocompassParams,
    ShapingFilter,
    mean_square_standard_error,
    psd,
    psd_integral,
    psd_two_sided,
    random_drift_filter,
    simulate_shaping_filter,
    stationary_covariance,
    symbolic,
    vibration_filter,
)

S = symbolic.SYMBOLS
PAPER = GyrocompassParams()
# (alpha, xi, sigma²): the paper's values and others spanning the allowed damping range.
VIB_CASES = [(PAPER.alpha1, PAPER.xi1, PAPER.sigma1_sq), (2.0, 0.05, 3.0), (0.1, 1.0, 1e-8)]
DRIFT_CASES = [(PAPER.alpha2, PAPER.xi2, PAPER.sigma2_sq), (50.0, 0.9, 1.0), (0.3, 0.02, 7e-12)]


# Closed forms ------------------------------------------------------------------------------------
def test_sympy_intensities_give_the_printed_variances():
    """Q1 = 2ξ1α1σ1² and Q2 = 4ξ2α2³σ2² give the variances σ1², σ2² (symbolic Lyapunov
    equation)."""
    assert sp.simplify(symbolic.shaping_filter("vibration").output_variance() - S.sigma1_sq) == 0
    assert sp.simplify(symbolic.shaping_filter("drift").output_variance() - S.sigma2_sq) == 0


def test_other_noise_readings_do_not_give_the_printed_variances():
    """The other placements of the noise in Eqs. (6), (7) do not give σ1², σ2² (symbolic)."""
    vib = symbolic.shaping_filter("vibration", "second_line_only").output_variance()
    assert sp.simplify(vib - S.sigma1_sq * (1 - 2 * S.xi1) ** 2 / 2) == 0
    drift = symbolic.shaping_filter("drift", "both_lines").output_variance()
    assert sp.simplify(drift - S.sigma2_sq * (S.alpha2**2 + (1 + 2 * S.xi2 * S.alpha2) ** 2)) == 0


def test_vibration_filter_transfer_function_is_s_plus_alpha_over_second_order():
    """The realization of Eq. (6) has the transfer function (s + α1)/(s² + 2ξ1α1 s + α1²)."""
    tf = symbolic.shaping_filter("vibration").transfer_function()
    a, xi, s = S.alpha1, S.xi1, S.s
    assert sp.simplify(tf - (s + a) / (s**2 + 2 * xi * a * s + a**2)) == 0


@pytest.mark.parametrize("alpha, xi, s2", VIB_CASES)
def test_vibration_variance_lyapunov(alpha, xi, s2):
    """Numeric Lyapunov variance of Eq. (6) equals σ1² for random α, ξ, σ²."""
    filt = vibration_filter(alpha, xi, s2)
    assert filt.variance() == pytest.approx(s2, rel=1e-9)


@pytest.mark.parametrize("alpha, xi, s2", DRIFT_CASES)
def test_drift_variance_lyapunov(alpha, xi, s2):
    """Numeric Lyapunov variance of Eq. (7) equals σ2² for random α, ξ, σ²."""
    filt = random_drift_filter(alpha, xi, s2)
    assert filt.variance() == pytest.approx(s2, rel=1e-9)


def test_psd_equals_the_closed_form_spectrum():
    """The |H(jω)|² PSD equals the closed-form rational spectrum; the two-sided PSD is even;
    the frequencies may come in any order (python-control's ``frequency_response``, which
    gyrolib called until 0.5.0, returns them sorted: the values came back in another order
    than the frequencies asked for); a pole on the axis gives python-control's inf."""
    a, xi, s2 = VIB_CASES[0]
    filt = vibration_filter(a, xi, s2)
    w = np.logspace(-5, 3, 57)
    closed = filt.Q * (w**2 + a**2) / ((a**2 - w**2) ** 2 + (2 * xi * a * w) ** 2)
    np.testing.assert_allclose(psd_two_sided(filt, w), closed, rtol=1e-12)
    np.testing.assert_allclose(psd(filt, w), closed / math.pi, rtol=1e-12)
    a, xi, s2 = DRIFT_CASES[0]
    filt = random_drift_filter(a, xi, s2)
    closed = filt.Q / ((a**2 - w**2) ** 2 + (2 * xi * a * w) ** 2)
    np.testing.assert_allclose(psd_two_sided(filt, w), closed, rtol=1e-12)
    # The two-sided spectrum is even.
    np.testing.assert_allclose(psd_two_sided(filt, -w), psd_two_sided(filt, w), rtol=0)
    # In the order asked for: each value is its frequency's (sorted, the check fails).
    order = np.random.default_rng(7).permutation(w.size)
    np.testing.assert_allclose(psd_two_sided(filt, w[order]), closed[order], rtol=1e-12)
    assert not np.allclose(np.sort(w[order]), w[order])
    # an undamped filter (ξ = 0, α = 1 rad/s: its matrix singular at ω = 1 in exact
    # arithmetic, on any CPU) has its poles at ±j: infinite there, finite elsewhere
    undamped = dataclasses.replace(filt, A=np.array([[0.0, 1.0], [-1.0, 0.0]]))
    with pytest.warns(RuntimeWarning, match="singular"):
        at_pole = psd_two_sided(undamped, [0.5, 1.0])
    assert np.isfinite(at_pole[0]) and np.isinf(at_pole[1])
    with pytest.raises(ValueError, match="omega"):
        psd(filt, -w)


@pytest.mark.parametrize("make, case", [(vibration_filter, c) for c in VIB_CASES]
                         + [(random_drift_filter, c) for c in DRIFT_CASES])
def test_area_under_psd_equals_variance(make, case):
    """The quadrature of the one-sided PSD equals the Lyapunov variance (paper GC, Figure 2)."""
    filt = make(*case)
    assert psd_integral(filt) == pytest.approx(case[2], rel=1e-9)


# Discretization and simulation --------------------------------------------------------------------
@pytest.mark.parametrize("dt", [1e-3, 0.37, 25.0])
def test_discretization_preserves_the_stationary_covariance(dt):
    """Van Loan's Φ, Qd keep the stationary covariance stationary: Φ P Φᵀ + Qd = P."""
    for filt in (PAPER.vibration_filter(), PAPER.random_drift_filter()):
        Phi, Qd = filt.discretize(dt)
        np.testing.assert_allclose(Phi, scipy.linalg.expm(filt.A * dt), rtol=1e-12, atol=1e-15)
        P = filt.stationary_covariance()
        # Exact discretization: P∞ = Φ P∞ Φᵀ + Qd (a consequence of ∫₀^∞ = ∫₀^dt + ∫_dt^∞).
        np.testing.assert_allclose(Phi @ P @ Phi.T + Qd, P, rtol=1e-9,
                                   atol=1e-12 * np.abs(P).max())


# Long seeded runs: N1 has a correlation time ~1/(ξ1 α1) ≈ 110 s, so it is sampled every 5 s
# for 10⁷ s; N3 (≈ 0.4 s) every 0.05 s for 10⁵ s.  The bound is 5 standard errors of the mean
# square, computed with the exact autocovariance (correlation time accounted for).
@pytest.mark.parametrize("which, dt, n, seed", [("vibration", 5.0, 2_000_000, 20260101),
                                                ("drift", 0.05, 2_000_000, 20260102)])
def test_simulated_variance_within_five_standard_errors(which, dt, n, seed):
    """The mean square of a seeded exact simulation lies within 5 standard errors of the
    variance."""
    filt = PAPER.vibration_filter() if which == "vibration" else PAPER.random_drift_filter()
    sigma_sq = PAPER.sigma1_sq if which == "vibration" else PAPER.sigma2_sq
    y = simulate_shaping_filter(filt, dt, n, seed)
    se = mean_square_standard_error(filt, dt, n)
    assert se < 0.01 * sigma_sq  # the run is long enough to test at the per-cent level
    assert abs(np.mean(y**2) - sigma_sq) < 5.0 * se


def test_standard_error_formula_against_replicated_runs():
    # 300 independent seeded runs: the spread of their mean squares estimates the standard
    # error with a relative uncertainty ≈ 1/sqrt(2·300) ≈ 4 %; allow 5 of those.
    """The standard-error formula matches the spread of 300 independent seeded runs (within 5 ×
    4 %)."""
    filt = PAPER.vibration_filter()
    dt, n = 5.0, 10_000
    ms = np.array([np.mean(simulate_shaping_filter(filt, dt, n, seed) ** 2) for seed in range(300)])
    se = mean_square_standard_error(filt, dt, n)
    assert np.std(ms, ddof=1) == pytest.approx(se, rel=5 * 0.041)
    assert abs(ms.mean() - PAPER.sigma1_sq) < 5 * se / math.sqrt(300)


def test_simulation_is_reproducible_and_seed_dependent():
    """Same seed, same series; different seed, different series."""
    filt = PAPER.random_drift_filter()
    a = simulate_shaping_filter(filt, 0.01, 1000, 7)
    np.testing.assert_allclose(a, simulate_shaping_filter(filt, 0.01, 1000, 7), rtol=1e-12, atol=0)
    assert not np.array_equal(a, simulate_shaping_filter(filt, 0.01, 1000, 8))


def test_simulated_lag_one_correlation_matches_the_model():
    """The simulated lag-one covariance matches C Φ P Cᵀ within 5 standard errors."""
    filt = PAPER.random_drift_filter()
    dt, n = 0.05, 1_000_000
    y = simulate_shaping_filter(filt, dt, n, 11)
    Phi, _ = filt.discretize(dt)
    P = filt.stationary_covariance()
    r1 = float((filt.C @ Phi @ P @ filt.C.T)[0, 0])
    # Var[mean y_k y_{k+1}] = (1/n) Σ_j (R_j² + R_{j+1} R_{j−1}) ≤ (2/n) Σ_j R_j²: its standard
    # error is at most that of the mean square (Cauchy–Schwarz), so 5·se is a valid bound.
    se = mean_square_standard_error(filt, dt, n)
    assert abs(np.mean(y[1:] * y[:-1]) - r1) < 5 * se


# The printed sign of F(8,7) -----------------------------------------------------------------------
def test_printed_F87_has_no_stationary_covariance():
    """With the printed F(8,7) the Lyapunov solver refuses the unstable block (no stationary
    covariance)."""
    base = PAPER.vibration_filter()
    printed = ShapingFilter(A=np.array([[0.0, 1.0], [PAPER.alpha1**2, -2 * PAPER.xi1 *
                                                     PAPER.alpha1]]),
                            B=base.B, C=base.C, Q=base.Q)
    assert np.linalg.eigvals(printed.A).real.max() > 0
    with pytest.raises(ValueError, match="Hurwitz"):
        stationary_covariance(printed.A, printed.B, printed.Q)


def test_bad_arguments_are_rejected_by_name():
    """Bad arguments of the shaping-filter functions raise naming the argument."""
    filt = PAPER.random_drift_filter()
    with pytest.raises(ValueError, match="dt"):
        filt.discretize(0.0)
    with pytest.raises(ValueError, match="n"):
        simulate_shaping_filter(filt, 0.1, 0, 1)
    with pytest.raises(TypeError, match="seed"):
        simulate_shaping_filter(filt, 0.1, 10, 1.5)
    with pytest.raises(TypeError, match="filt"):
        psd("not a filter", np.ones(3))


def test_autocorrelation_of_the_drift_filter_matches_the_closed_form():
    """N3 of Eq. (7) (no zero): ρ(τ) = e^{−ξατ}(cos ω_d τ + ξ/√(1−ξ²) sin ω_d τ),
    ω_d = α√(1−ξ²); and ρ(0) = 1 for the vibration filter of Eq. (6)."""
    from gyrolib.gc import GyrocompassParams

    p = GyrocompassParams()
    filt = p.random_drift_filter()
    a, xi = p.alpha2, p.xi2
    wd = a * np.sqrt(1 - xi**2)
    for tau in (0.0, 0.05, 0.3, 1.0, -0.3):
        t = abs(tau)
        want = np.exp(-xi * a * t) * (np.cos(wd * t) + xi / np.sqrt(1 - xi**2) * np.sin(wd * t))
        assert filt.autocorrelation(tau) == pytest.approx(want, rel=1e-10, abs=1e-14)
    assert p.vibration_filter().autocorrelation(0.0) == pytest.approx(1.0, rel=1e-12)
