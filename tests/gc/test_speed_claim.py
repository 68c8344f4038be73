"""gyrolib.gc.analysis.speed_claim: the speed-claim map and the shaping sweep, against hand
values (the scaled parameters, the 510-s bound) and a direct reading of the σ curve at the
crossing."""

from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor
from dataclasses import replace

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


def test_time_to_level_past_the_first_horizon_equals_a_whole_run_read_by_time_to_sigma():
    """The fast path (chunks, stopped at the first crossing, the 100-s discretization
    continued to t_max) against one covariance analysis over the whole span read by
    gc.time_to_sigma (the last step above the level): equal to 1e-12 relative; and σ of ω_gc
    never increases over that span (what makes the first crossing the last)."""
    q = replace(P, sigma1_sq=4.64 * P.sigma1_sq)  # crosses σ_c after about 230 s
    fast = gc.time_to_level(q, SIGMA_C, 300.0)
    res = gc.covariance_analysis(q, 300.0, store_every=10**9)
    whole = gc.time_to_sigma(res, "omega_gc", SIGMA_C)
    assert 100.0 < whole < 300.0
    assert fast == pytest.approx(whole, rel=1e-12, abs=0.0)
    s = res.std("omega_gc")
    assert np.all(np.diff(s) <= 1e-12 * s[:-1])
    # not reached within t_max: nan, as time_to_sigma says on the whole run
    assert np.isnan(gc.time_to_level(q, SIGMA_C, 150.0))


def test_claim_boundary_sigma_is_the_final_sigma_of_a_covariance_analysis():
    b = gc.claim_boundary(P, SIGMA_C, 60.0, factors=[1.0, 3.0])
    ref = [gc.covariance_analysis(replace(P, sigma1_sq=f * P.sigma1_sq), 60.0).final_std()
           for f in (1.0, 3.0)]
    np.testing.assert_allclose(b.sigma, ref, rtol=1e-12, atol=0.0)


@pytest.mark.parametrize("make", [lambda: ThreadPoolExecutor(2), lambda: ProcessPoolExecutor(2)],
                         ids=["threads", "processes"])
def test_results_do_not_depend_on_the_executor(make):
    """The same grid run here and on an executor: equal to 1e-12 relative (nan where nan)."""
    kw = dict(x_factors=[1.0, 4.64], y_factors=[0.5, 1.0], t_max=300.0)
    here = gc.speed_claim_map(P, SIGMA_C, 240.0, **kw)
    sweep_here = gc.shaping_sweep(P, 2.0, fields=("alpha1", "sigma2_sq"))
    bound_here = gc.claim_boundary(P, SIGMA_C, 60.0, factors=[1.0, 3.0])
    with make() as executor:
        there = gc.speed_claim_map(P, SIGMA_C, 240.0, executor=executor, **kw)
        sweep_there = gc.shaping_sweep(P, 2.0, fields=("alpha1", "sigma2_sq"),
                                       executor=executor)
        bound_there = gc.claim_boundary(P, SIGMA_C, 60.0, factors=[1.0, 3.0],
                                        executor=executor)
    assert np.isfinite(here.t_c).sum() >= 6
    np.testing.assert_allclose(there.t_c, here.t_c, rtol=1e-12, atol=0.0, equal_nan=True)
    for name in ("values", "sigma_end", "drop"):
        np.testing.assert_allclose(getattr(sweep_there, name), getattr(sweep_here, name),
                                   rtol=1e-12, atol=0.0)
    assert np.array_equal(sweep_there.monotone, sweep_here.monotone)
    np.testing.assert_allclose(bound_there.sigma, bound_here.sigma, rtol=1e-12, atol=0.0)


def test_executor_must_be_a_concurrent_futures_executor():
    with pytest.raises(TypeError, match=r"executor must be a concurrent\.futures\.Executor"):
        gc.speed_claim_map(P, SIGMA_C, 60.0, x_factors=[1.0], y_factors=[1.0],
                           executor=map)
    with pytest.raises(TypeError, match="executor"):
        gc.shaping_sweep(P, 2.0, executor=4)
