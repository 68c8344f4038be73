"""gyrolib.gc.claims: the speed-claim map and the shaping sweep, against hand values (the
scaled parameters, the 510-s bound) and a direct reading of the σ curve at the crossing."""

import numpy as np
import pytest

from gyrolib import gc
from gyrolib.gc import GyrocompassParams

P = GyrocompassParams()
SIGMA_C = 2e-3 * 0.485e-5  # the paper's σ_c, 2·10⁻³″/s with its 1″ = 0.485·10⁻⁵ rad


def test_time_to_level_is_where_the_sigma_curve_crosses():
    """The returned time lies between the last sample of a separate 100-s analysis above
    σ_c and the first below it; a level below anything reached gives nan."""
    t = gc.time_to_level(P, SIGMA_C, 100.0)
    s = gc.covariance_analysis(P, 100.0).std("omega_gc")
    k = int(np.floor(t / P.dt))
    assert s[k] > SIGMA_C >= s[k + 1]
    assert np.isnan(gc.time_to_level(P, 1e-3 * SIGMA_C, 2.0))


def test_speed_map_holds_at_the_paper_and_fails_at_ten_times_the_vibration():
    """Bound 0.5 × 17 min = 510 s by hand.  Stationary P0: σ1² ×1 reaches σ_c in well under
    510 s, σ1² ×10 does not (σ grows with σ1²); zero P0 reaches it sooner than stationary at
    the paper's values (a smaller prior)."""
    m = gc.speed_claim_map(P, SIGMA_C, 0.5 * 17 * 60, x_factors=[1.0, 10.0], y_factors=[1.0])
    assert m.t_max == pytest.approx(638.0)
    stationary, zero = m.readings.index("stationary"), m.readings.index("zero")
    assert list(m.holds()[stationary, 0]) == [True, False]
    assert m.t_c[zero, 0, 0] < m.t_c[stationary, 0, 0] < 510.0
    assert m.largest_x_factor_holding("stationary") == 1.0


def test_shaping_sweep_scales_one_parameter_at_a_time_with_damping_capped():
    """The values are the baseline times the factors (by hand), the damping ratios capped at
    1; σ never increases over 2 s, and every drop σ(2 s)/σ(0) is a ratio in (0, 1)."""
    sw = gc.shaping_sweep(P, 2.0, fields=("alpha1", "xi1"), factors=(0.1, 10.0))
    assert sw.values[0] == pytest.approx([1.33e-3, 1.33e-1], rel=1e-12)
    assert sw.values[1] == pytest.approx([0.07, 1.0], rel=1e-12)
    assert sw.monotone.all()
    assert np.all((sw.drop > 0.0) & (sw.drop < 1.0))
