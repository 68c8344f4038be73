"""gyrolib.gc: nominal motion and truth model against independent solvers, σ of ω_gc
against an independent reference implementation, fast vs reference paths of the Monte Carlo,
the error budget adding up, the ψ/ω_gc information against its closed form (the Monte Carlo
consistency checks, with their power, are in test_gc_monte_carlo.py)."""

from dataclasses import replace

import numpy as np
import pytest
import scipy.stats
from scipy.integrate import solve_ivp

from gyrolib import filtering, gc
from gyrolib.gc import GyrocompassParams, nominal_motion, state_index
from gyrolib.units import ARCSEC_PAPER
from tests.support.gc_reference import READINGS, reference_sigma_gc

P = GyrocompassParams()


def test_nominal_half_steps_matches_radau():
    """ETD2 on the half-step grid against the model's Radau solution (rtol 1e-11) of Eq. (4)
    over 100 s: agreement to 1e-12 rad (β_n reaches 8.6e-3 rad)."""
    n = 100_000
    beta = gc.nominal_half_steps(P, n)
    idx = np.array([0, 1, 2, 5, 40, 2_000, 50_001, 2 * n])
    ref = nominal_motion(P, idx * P.dt / 2)
    assert np.max(np.abs(beta[idx] - ref.beta)) < 1e-12


@pytest.mark.parametrize("psi", [0.05, 0.5])
def test_truth_model_integrates_nonlinear_eq3(psi):
    """Noise off; large offsets (ψ = 0.05 rad so that the nonlinearity matters, and 0.5 rad,
    beyond the kernel's series, to exercise its exact fallback; δ, γ = 120″,
    ω_gc = 0.15″/s, N1, N3 nonzero).  The full nonlinear Eq. (3) with the shaping filters is
    integrated independently by Radau (rtol 1e-12): the truth's β (exponential midpoint rule
    at Δt/10, reported against the filter's nominal) agrees to 1e-11 rad over 5 s (Δβ is
    ~1e-6 rad)."""
    p = P
    x0 = np.zeros(10)
    x0[2] = psi
    x0[3] = 0.15 * ARCSEC_PAPER
    x0[4] = x0[5] = 120 * ARCSEC_PAPER
    x0[6], x0[7], x0[8], x0[9] = 1e-3, 2e-5, 5e-8, -1e-7
    t, X = gc.simulate_truth(p, 5.0, x0, seed=None, store_every=100)
    beta_n = gc.nominal_half_steps(p, 5000)[::200]
    A1 = p.vibration_filter().A
    A2 = p.random_drift_filter().A

    def rhs(_t, y):
        b, bd = y[0], y[1]
        n1, n3 = y[2], y[4]
        torque = (p.H * p.Omega_h * np.cos(b - x0[2]) + p.H * p.Omega_v * x0[5] * np.cos(b)
                  - p.H * p.Omega_v * x0[4] * np.sin(b) + p.H * x0[3] + p.H * n3
                  + p.H * p.omega_ub / p.g * n1)
        return np.concatenate([[bd, (torque - p.f * bd) / p.I], A1 @ y[2:4], A2 @ y[4:6]])

    sol = solve_ivp(rhs, (0, 5.0), [0.0, 0.0, *x0[6:10]], method="Radau", t_eval=t,
                    rtol=1e-12, atol=1e-18)
    beta_truth = beta_n + X[:, 0]
    assert np.max(np.abs(beta_truth - sol.y[0])) < 1e-11
    assert np.max(np.abs(X[:, 6] - sol.y[2])) < 1e-12 * 1e3


@pytest.mark.parametrize("t_end", [10.0, pytest.param(100.0, marks=pytest.mark.full)])
@pytest.mark.parametrize("shaping_p0", READINGS)
def test_sigma_curve_matches_the_independent_reference(shaping_p0, t_end):
    """σ of ω_gc at 1, 2, 10 s (everyday tier) and 50, 100 s too (full tier) against
    tests/support/gc_reference.py (plain numpy/scipy from the transcribed matrices, per-step
    Van Loan, Joseph form; measured agreement ~1e-12, held to 1e-8 relative), and σ(0)
    against the paper's prior 0.15″/s."""
    times, ref = reference_sigma_gc(t_end=t_end)
    res = gc.covariance_analysis(replace(P, shaping_p0=shaping_p0), t_end)
    got = [res.std_at("omega_gc", t) for t in times]
    assert np.allclose(got, ref[READINGS.index(shaping_p0)], rtol=1e-8, atol=0.0)
    assert res.std("omega_gc")[0] == pytest.approx(0.15 * ARCSEC_PAPER, rel=1e-12)


def test_covariance_fast_matches_reference_with_exact_per_step_exponential():
    res_f = gc.covariance_analysis(P, 1.0, store_every=100)
    res_r = gc.covariance_analysis(P, 1.0, store_every=100, method="reference")
    for name in ("dbeta", "psi", "omega_gc", "delta", "N1", "N3"):
        a, b = res_f.std(name)[1:], res_r.std(name)[1:]
        assert np.max(np.abs(a / b - 1.0)) < 1e-9, name


def test_monte_carlo_fast_and_reference_agree_for_same_seed():
    """Two implementations of the truth and filter (numba with series for the torques, plain
    numpy with np.cos): 40 runs = one full and one partial block of 32; estimates and truth
    agree to rounding (1e-9 of the filter's σ), so the two paths draw and use the same random
    numbers."""
    a = gc.monte_carlo(P, 40, 0.3, seed=11, store_every=10)
    b = gc.monte_carlo(P, 40, 0.3, seed=11, store_every=10, method="reference")
    sig = np.sqrt(np.diagonal(a.P, axis1=1, axis2=2))[None, 1:, :]
    assert np.max(np.abs(a.est[:, 1:] - b.est[:, 1:]) / sig) < 1e-9
    assert np.max(np.abs(a.tru[:, 1:] - b.tru[:, 1:]) / sig) < 1e-9
    # same seed → same runs; the first runs do not depend on how many runs there are.  The
    # random draws are identical, but SIMD/BLAS rounding depends on the block width and the
    # CPU, so the estimates agree to rounding (1e-9 σ), not bit for bit.
    c = gc.monte_carlo(P, 5, 0.3, seed=11, store_every=10)
    assert np.max(np.abs(c.est[:, 1:] - a.est[:5, 1:]) / sig) < 1e-9
    assert np.max(np.abs(c.tru[:, 1:] - a.tru[:5, 1:]) / sig) < 1e-9


def test_nees_bounds_match_chi_square():
    """The NEES band is the chi-square quantile of dof·N degrees of freedom over N."""
    lo, hi = filtering.nees_bounds(2, 50, 0.95)
    assert lo == pytest.approx(scipy.stats.chi2.ppf(0.025, 100) / 50)
    assert hi == pytest.approx(scipy.stats.chi2.ppf(0.975, 100) / 50)


def test_error_budget_adds_up_to_the_filter_variance():
    """The sources of the error budget add up to the filter's variance (a second recursion,
    with fixed gains, per source)."""
    bud = gc.error_budget(P, 10.0)
    total = bud.var.sum(axis=0)
    assert np.allclose(total[1:], bud.total[1:], rtol=1e-8, atol=0.0)
    assert np.all(bud.var >= -1e-30)
    assert bud.var[bud.sources.index("initial dbeta")].max() == 0.0  # σ = 0 in the baseline


def test_time_to_sigma_interpolates_the_first_crossing():
    """The crossing time lies between the samples above and below the level; nan if never."""
    res = gc.covariance_analysis(P, 10.0)
    level = 1e-3 * ARCSEC_PAPER * 5
    t = gc.time_to_sigma(res, "omega_gc", level)
    s = res.std("omega_gc")
    k = int(t / P.dt)
    assert s[k] >= level >= s[k + 1]
    assert np.isnan(gc.time_to_sigma(res, "omega_gc", 1e-30))


def test_information_separates_psi_and_omega_as_beta_grows():
    """Once the float runs aperiodically (t ≫ I/f), Δβ responds to ω_gc like t and to ψ like
    t² (sin β_n grows ∝ t): the correlation of the two regressors over [0, T] is
    ∫t·t² / √(∫t² ∫t⁴) = √15/4 ≈ 0.968 whatever T (closed form, to 1e-3)."""
    info = gc.information_psi_omega(P, 100.0)
    corr = info.correlation()
    assert abs(corr[-1]) == pytest.approx(np.sqrt(15) / 4, abs=1e-3)
    ratio = info.sigma_gc_psi_unknown()[1:] / info.sigma_gc_psi_known()[1:]
    assert ratio[-1] == pytest.approx(1 / np.sqrt(1 - 15 / 16), rel=1e-2)
    # a float frozen at a constant angle makes the two regressors proportional: |corr| → 1
    frozen = gc.information_psi_omega(P, 100.0, frozen_beta=0.005)
    assert abs(frozen.correlation()[-1]) > 1 - 1e-6


def test_sweep_matches_single_runs():
    """A sweep point is the covariance analysis at that parameter value."""
    vals = np.array([0.5, 0.7])
    out = gc.sweep_sigma_gc(P, "xi1", vals, 2.0)
    single = gc.covariance_analysis(replace(P, xi1=0.5), 2.0).std("omega_gc")[-1]
    assert out[0] == pytest.approx(single, rel=1e-12)


def test_state_index_used_for_results():
    """Results are indexed by state name in the order of STATE_NAMES."""
    res = gc.covariance_analysis(P, 0.01)
    assert res.var.shape == (11, 10)
    assert res.std("psi")[0] == pytest.approx(np.sqrt(res.var[0, state_index("psi")]))
