"""gyrolib.gc.monte_carlo: the truth model judged against references outside the filter.

The truth integrates Eq. (3) of paper GC on its own grid, from its own parameters; these
tests check (i) that a filter matched to the truth is consistent within the 95 % chi-square
band of its NEES, (ii) that the same check fails when the truth differs from the filter
(vibration variance ×9, angle-sensor noise ×100): the check has power, and (iii) that the
truth's shaping filters hold the stationary variances σ1², σ2² of Eqs. (6), (7).
"""

from dataclasses import replace

import numpy as np
import pytest
import scipy.stats

from gyrolib import filtering, gc
from gyrolib.gc import GyrocompassParams

P = GyrocompassParams()
N_RUNS = 200
T_END = 20.0
SEED = 7


@pytest.fixture(scope="module")
def matched() -> gc.MonteCarloResult:
    return gc.monte_carlo(P, N_RUNS, T_END, seed=SEED)


def test_matched_truth_lies_inside_the_chi_square_band(matched):
    """A filter whose model is the truth's: the ensemble-average NEES of ω_gc (1 dof) and of
    the full state (10 dof) at 20 s lie in the two-sided 95 % chi-square band of 200 runs,
    and so does the ratio of the RMS error of ω_gc to the filter's σ (square-rooted band)."""
    lo1, hi1 = filtering.nees_bounds(1, N_RUNS)
    lo10, hi10 = filtering.nees_bounds(10, N_RUNS)
    assert lo1 < matched.nees(("omega_gc",)).mean(axis=0)[-1] < hi1
    assert lo10 < matched.nees().mean(axis=0)[-1] < hi10
    ratio = matched.rms_error("omega_gc")[-1] / matched.std("omega_gc")[-1]
    assert np.sqrt(lo1) < ratio < np.sqrt(hi1)


@pytest.mark.parametrize(("field", "factor"), [("sigma1_sq", 9.0), ("C_as", 100.0)])
def test_mismatched_truth_falls_outside_the_chi_square_band(field, factor):
    """The same check with a truth the filter does not know (vibration variance σ1² ×9, i.e.
    σ1 ×3; or the angle sensor's noise intensity ×100): the NEES of ω_gc at 20 s is above the
    95 % band, so the matched case passing is evidence, not a tautology."""
    truth = replace(P, **{field: getattr(P, field) * factor})
    res = gc.monte_carlo(P, N_RUNS, T_END, seed=SEED, truth_params=truth)
    _, hi1 = filtering.nees_bounds(1, N_RUNS)
    assert res.nees(("omega_gc",)).mean(axis=0)[-1] > hi1
    # the filter's σ is that of the matched run: the truth's parameters do not reach it
    np.testing.assert_allclose(res.P, gc.monte_carlo(P, 1, T_END, seed=SEED).P,
                               rtol=1e-12, atol=0)


@pytest.mark.parametrize(("state", "field"), [("N1", "sigma1_sq"), ("N3", "sigma2_sq")])
def test_truth_shaping_filters_hold_their_stationary_variance(matched, state, field):
    """N1 and N3 start from their stationary law and are driven by the truth's own
    zero-order-held white noise: their variance over 200 runs at 20 s is σ1² (σ2²), the
    area under the PSD of Eq. (6) (Eq. (7)), inside the 99 % chi-square band of a sample
    variance with 199 degrees of freedom."""
    x = matched.truth(state)[:, -1]
    s2 = np.var(x, ddof=1)
    lo, hi = scipy.stats.chi2.ppf([0.005, 0.995], N_RUNS - 1) / (N_RUNS - 1)
    assert lo < s2 / getattr(P, field) < hi



def test_matched_truth_with_the_literal_sign_of_eq1_is_consistent():
    """The literal minus sign of Eq. (1) (mirrored angle, the δ term's sign flipped) in both
    the filter's model and the truth: the NEES of ω_gc at 20 s lies in the 95 % band."""
    p = replace(P, eq1_sign="-")
    res = gc.monte_carlo(p, N_RUNS, T_END, seed=SEED)
    lo1, hi1 = filtering.nees_bounds(1, N_RUNS)
    lo10, hi10 = filtering.nees_bounds(10, N_RUNS)
    assert lo1 < res.nees(("omega_gc",)).mean(axis=0)[-1] < hi1
    assert lo10 < res.nees().mean(axis=0)[-1] < hi10
