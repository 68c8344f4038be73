"""Property-based tests (hypothesis) of model and filter invariants: shaping-filter variances
scale with σ², stationary covariances are positive definite, F's shaping blocks are stable,
unit conversions round-trip, measurement updates keep P positive semi-definite, constant
states lose uncertainty monotonically."""

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gyrolib import units
from gyrolib.gc import GyrocompassParams, random_drift_filter, system_matrix, vibration_filter

positive = st.floats(min_value=1e-6, max_value=1e6, allow_nan=False, allow_infinity=False)

# The validation of GyrocompassParams' fields is covered field by field in
# tests/gc/test_model.py and by the hypothesis tests of tests/gc/test_bad_input.py; this file
# holds the model's and the filter's invariants.


@settings(max_examples=50, deadline=None)
@given(alpha=st.floats(1e-3, 1e2), xi=st.floats(0.05, 1.0), s2=positive,
       scale=st.floats(1e-3, 1e3))
def test_shaping_filter_variance_scales_as_the_input_variance(alpha, xi, s2, scale):
    """Eqs. (6), (7): the Lyapunov variance equals σ² and scales linearly with it."""
    for make in (vibration_filter, random_drift_filter):
        base = make(alpha, xi, s2).variance()
        scaled = make(alpha, xi, s2 * scale).variance()
        assert base == pytest.approx(s2, rel=1e-8)
        assert scaled / base == pytest.approx(scale, rel=1e-8)


# ξ1 = 1 is excluded: there the zero of Eq. (6) cancels a double pole, N1 becomes a
# first-order process and its 2-state covariance is singular by construction (rank 1).
@settings(max_examples=50, deadline=None)
@given(alpha=st.floats(1e-3, 1e2), xi=st.floats(0.05, 0.99), s2=positive)
def test_stationary_covariance_is_symmetric_positive_definite(alpha, xi, s2):
    """The stationary covariance of either shaping filter is symmetric positive definite."""
    for make in (vibration_filter, random_drift_filter):
        P = make(alpha, xi, s2).stationary_covariance()
        np.testing.assert_allclose(P, P.T, rtol=1e-15, atol=0)
        assert np.all(np.linalg.eigvalsh(P / np.max(np.abs(P))) > 0.0)


@settings(max_examples=50, deadline=None)
@given(beta=st.floats(-math.pi, math.pi))
def test_shaping_blocks_of_F_are_stable_for_any_float_angle(beta):
    """The N1, N2 and N3, N4 blocks of F (Eq. (8)) have eigenvalues in the left half-plane."""
    F = system_matrix(GyrocompassParams(), beta)
    for block in (F[6:8, 6:8], F[8:10, 8:10]):
        assert np.all(np.linalg.eigvals(block).real < 0.0)


@settings(max_examples=100, deadline=None)
@given(x=st.floats(-1e12, 1e12), unit=st.sampled_from(sorted(units.UNITS)))
def test_unit_round_trip(x, unit):
    """from_si(to_si(x)) returns x to 1e-14 for every unit of gyrolib.units."""
    assert units.from_si(units.to_si(x, unit), unit) == pytest.approx(x, rel=1e-14, abs=1e-300)


# Kalman-filter invariants -------------------------------------------------------------------
from gyrolib import filtering  # noqa: E402


@st.composite
def _update_problem(draw):
    n = draw(st.integers(2, 6))
    m = draw(st.integers(1, 3))
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    A = rng.standard_normal((n, n))
    scales = 10.0 ** rng.uniform(-6, 2, n)
    P = (A @ A.T + 1e-3 * np.eye(n)) * np.outer(scales, scales)
    H = rng.standard_normal((m, n)) * (rng.random((m, n)) < 0.7)
    R = np.diag(10.0 ** rng.uniform(-8, 1, m))
    return P, H, R


@settings(max_examples=80, deadline=None)
@given(_update_problem())
def test_measurement_update_keeps_p_spd_and_never_increases_a_variance(problem):
    """Joseph and sequential updates keep P symmetric PSD and never raise a variance."""
    P, H, R = problem
    n, m = P.shape[0], H.shape[0]
    for update in (filtering.joseph_update, filtering.sequential_update):
        Pn = update(np.zeros(n), P, np.zeros(m), H, R)[1]
        assert np.allclose(Pn, Pn.T, rtol=0, atol=1e-12 * np.max(np.abs(P)))
        d = np.sqrt(np.diag(P))
        assert np.linalg.eigvalsh(Pn / np.outer(d, d))[0] > -1e-10
        assert np.all(np.diag(Pn) <= np.diag(P) * (1 + 1e-9))


@settings(max_examples=8, deadline=None)
@given(alpha1=st.floats(1e-3, 1e-1), xi1=st.floats(0.1, 0.95),
       alpha2=st.floats(1.0, 30.0), xi2=st.floats(0.1, 0.95),
       scale=st.floats(0.1, 10.0))
def test_constant_states_lose_uncertainty_monotonically_for_any_shaping_filter(
        alpha1, xi1, alpha2, xi2, scale):
    """ψ, ω_gc, δ, γ are constants: their σ never grows over a run, for any shaping filter."""
    from gyrolib.gc import covariance_analysis

    p = dataclasses.replace(GyrocompassParams(), alpha1=alpha1, xi1=xi1, alpha2=alpha2,
                            xi2=xi2, sigma1_sq=1.86e-6 * scale, sigma2_sq=2.35e-15 * scale)
    res = covariance_analysis(p, t_end=2.0, store_every=500)
    for name in ("psi", "omega_gc", "delta", "gamma"):
        s = res.std(name)
        assert np.all(np.diff(s) <= 1e-9 * s[:-1]), name
    for P in res.P_stored:
        np.testing.assert_allclose(P, P.T, rtol=1e-15, atol=0)
