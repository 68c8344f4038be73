"""Property-based tests (hypothesis) of input validation and model invariants."""

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gyrolib import units
from gyrolib.gyrocompass import GyrocompassParams, system_matrix
from gyrolib.shaping_filters import random_drift_filter, vibration_filter

POSITIVE_FIELDS = ["I", "H", "f", "Omega_v", "Omega_h", "g", "alpha1", "sigma1_sq", "alpha2",
                   "sigma2_sq", "C_as", "C_incl_y", "C_incl_z", "dt"]
NONNEGATIVE_FIELDS = ["omega_ub", "sigma_dbeta0", "sigma_dbeta_dot0", "sigma_psi0",
                      "sigma_gc0", "sigma_delta0", "sigma_gamma0"]

non_finite = st.sampled_from([math.nan, math.inf, -math.inf])
non_positive = st.one_of(st.just(0.0), st.floats(max_value=-1e-300, allow_nan=False,
                                                 allow_infinity=False))
negative = st.floats(max_value=-1e-300, allow_nan=False, allow_infinity=False)
positive = st.floats(min_value=1e-6, max_value=1e6, allow_nan=False, allow_infinity=False)


@settings(max_examples=60, deadline=None)
@given(name=st.sampled_from(POSITIVE_FIELDS), bad=st.one_of(non_finite, non_positive))
def test_positive_fields_reject_bad_values_by_name(name, bad):
    with pytest.raises(ValueError, match=name):
        dataclasses.replace(GyrocompassParams(), **{name: bad})


@settings(max_examples=40, deadline=None)
@given(name=st.sampled_from(NONNEGATIVE_FIELDS), bad=st.one_of(non_finite, negative))
def test_nonnegative_fields_reject_bad_values_by_name(name, bad):
    with pytest.raises(ValueError, match=name):
        dataclasses.replace(GyrocompassParams(), **{name: bad})


@settings(max_examples=40, deadline=None)
@given(name=st.sampled_from(["xi1", "xi2"]),
       bad=st.one_of(non_finite, st.floats(max_value=0.0), st.floats(min_value=1.0 + 1e-12)))
def test_damping_ratios_outside_zero_one_are_rejected(name, bad):
    with pytest.raises(ValueError, match=rf"{name} must be in \(0\.0, 1\.0\]"):
        dataclasses.replace(GyrocompassParams(), **{name: bad})


@settings(max_examples=30, deadline=None)
@given(name=st.sampled_from(POSITIVE_FIELDS + NONNEGATIVE_FIELDS),
       bad=st.sampled_from(["1", None, [1.0], True, 1 + 2j]))
def test_non_real_values_are_type_errors_by_name(name, bad):
    with pytest.raises(TypeError, match=name):
        dataclasses.replace(GyrocompassParams(), **{name: bad})


@settings(max_examples=50, deadline=None)
@given(alpha=st.floats(1e-3, 1e2), xi=st.floats(0.05, 1.0), s2=positive,
       scale=st.floats(1e-3, 1e3))
def test_shaping_filter_variance_scales_as_the_input_variance(alpha, xi, s2, scale):
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
    for make in (vibration_filter, random_drift_filter):
        P = make(alpha, xi, s2).stationary_covariance()
        assert np.array_equal(P, P.T)
        assert np.all(np.linalg.eigvalsh(P / np.max(np.abs(P))) > 0.0)


@settings(max_examples=50, deadline=None)
@given(beta=st.floats(-math.pi, math.pi))
def test_shaping_blocks_of_F_are_stable_for_any_float_angle(beta):
    F = system_matrix(GyrocompassParams(), beta)
    for block in (F[6:8, 6:8], F[8:10, 8:10]):
        assert np.all(np.linalg.eigvals(block).real < 0.0)


@settings(max_examples=100, deadline=None)
@given(x=st.floats(-1e12, 1e12), unit=st.sampled_from(sorted(units.UNITS)))
def test_unit_round_trip(x, unit):
    assert units.from_si(units.to_si(x, unit), unit) == pytest.approx(x, rel=1e-14, abs=1e-300)
