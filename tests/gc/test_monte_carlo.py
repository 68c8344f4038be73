"""gyrolib.gc.monte_carlo: the truth model judged against references outside the filter.

The truth integrates Eq. (3) of paper GC on its own grid, from its own parameters; these
tests check (i) that a filter matched to the truth is consistent within the 95 % chi-square
band of its NEES, (ii) that the same check fails when the truth differs from the filter
(vibration variance ×9, angle-sensor noise ×100): the check has power, (iii) that the
truth's shaping filters hold the stationary variances σ1², σ2² of Eqs. (6), (7), (iv) that the
truth builds its own model from the parameters and that it agrees with the filter's
construction, (v) that the kernel's random numbers are numpy's and that a run's numbers do
not depend on threads, executors or the number of runs, and (vi) what the full-state NEES of
the nonlinear truth owes to the linearization (gc.linearization): the shift of the ω_gc
estimate is the closed-form remainder of the horizontal-rate torque, and its NEES excess
follows from it.
"""

from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor
from dataclasses import replace

import numpy as np
import pytest
import scipy.linalg
import scipy.stats

from gyrolib import filtering, gc
from gyrolib.gc import GyrocompassParams
from gyrolib.gc.analysis import montecarlo as mcm
from gyrolib.units import ARCSEC_PAPER

P = GyrocompassParams()
N_RUNS = 200
T_END = 20.0
SEED = 7


@pytest.fixture(scope="module")
def matched() -> gc.MonteCarloResult:
    return gc.monte_carlo(P, N_RUNS, T_END, seed=SEED, store_every=100)


@pytest.fixture(scope="module")
def matched_linear() -> gc.MonteCarloResult:
    return gc.monte_carlo(P, N_RUNS, T_END, seed=SEED, store_every=100, truth="linear")


def test_matched_truth_lies_inside_the_chi_square_band(matched, matched_linear):
    """A filter whose model is the truth's: the ensemble-average NEES of ω_gc (1 dof) at 20 s
    lies in the two-sided 95 % chi-square band of 200 runs, and so does the ratio of the RMS
    error of ω_gc to the filter's σ (square-rooted band).  The full state (10 dof) is checked
    against the truth with the torques linearized as the filter's are (the nonlinear one
    carries a known excess: test_nonlinear_truth_excess_is_the_remainder_drift)."""
    lo1, hi1 = filtering.nees_bounds(1, N_RUNS)
    lo10, hi10 = filtering.nees_bounds(10, N_RUNS)
    assert lo1 < matched.nees(("omega_gc",)).mean(axis=0)[-1] < hi1
    assert lo10 < matched_linear.nees().mean(axis=0)[-1] < hi10
    ratio = matched.rms_error("omega_gc")[-1] / matched.std("omega_gc")[-1]
    assert np.sqrt(lo1) < ratio < np.sqrt(hi1)
    # the share of times inside, counted by hand from the NEES and the chi-square quantiles
    x = matched_linear.nees().mean(axis=0)[1:]
    lo, hi = scipy.stats.chi2.ppf([0.025, 0.975], 10 * N_RUNS) / N_RUNS
    assert matched_linear.inside_share() == pytest.approx(np.mean((x > lo) & (x < hi)))
    # a subset of runs is those runs' own Monte Carlo: same P, their estimates and truth
    part = matched_linear.select(slice(40, 72))
    assert part.n_runs == 32
    np.testing.assert_allclose(part.P, matched_linear.P, rtol=1e-12, atol=0.0)
    np.testing.assert_allclose(part.nees(), matched_linear.nees()[40:72], rtol=1e-12, atol=0.0)


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
    the filter's model and the truth: the NEES of ω_gc at 20 s lies in the 95 % band, and
    that of the full state with the linearized truth."""
    p = replace(P, eq1_sign="-")
    res = gc.monte_carlo(p, N_RUNS, T_END, seed=SEED, store_every=100)
    lin = gc.monte_carlo(p, N_RUNS, T_END, seed=SEED, store_every=100, truth="linear")
    lo1, hi1 = filtering.nees_bounds(1, N_RUNS)
    lo10, hi10 = filtering.nees_bounds(10, N_RUNS)
    assert lo1 < res.nees(("omega_gc",)).mean(axis=0)[-1] < hi1
    assert lo10 < lin.nees().mean(axis=0)[-1] < hi10


# The truth's own construction ------------------------------------------------------------------
@pytest.mark.parametrize("p", [P, replace(P, shaping_p0="zero"), replace(P, shaping_p0_scale=0.3),
                               replace(P, measurement_noise="variance", alpha1=0.5, xi2=1.0)])
def test_truth_builds_its_model_itself_and_agrees_with_the_filters(p):
    """The truth's shaping filters (matrices, noise input, intensity from α, ξ, σ²), its
    prior (closed-form stationary covariance, factored by hand) and its sensor noise equal
    the filter's construction (gc.vibration_filter, gc.random_drift_filter,
    gc.initial_covariance with scipy's Lyapunov solver, gc.measurement_noise_covariance) to
    1e-12: two constructions from the same parameters, not one shared."""
    (A1, b1, Q1), (A2, b2, Q2) = mcm._truth_shaping(p)
    for (A, b, Q), filt in (((A1, b1, Q1), p.vibration_filter()),
                            ((A2, b2, Q2), p.random_drift_filter())):
        np.testing.assert_allclose(A, filt.A, rtol=1e-12, atol=0)
        np.testing.assert_allclose(b, filt.B[:, 0], rtol=1e-12, atol=0)
        assert Q == pytest.approx(filt.Q, rel=1e-12)
    L = gc.truth_prior_factor(p)
    P0 = gc.initial_covariance(p)
    np.testing.assert_allclose(L @ L.T, P0, rtol=1e-12, atol=1e-12 * np.abs(P0).max())
    assert np.allclose(L, np.tril(L))
    np.testing.assert_allclose(mcm._truth_noise_sd(p) ** 2,
                               np.diag(gc.measurement_noise_covariance(p)), rtol=1e-12)


def test_truth_stationary_covariance_in_closed_form_has_power():
    """The closed form of the 2×2 stationary covariance against scipy's Lyapunov solver for
    a filter that is not the paper's (b1, b2 both nonzero); with the sign of P12 flipped
    the same comparison fails."""
    A = np.array([[0.0, 1.0], [-4.0, -1.2]])
    b = np.array([0.7, -0.3])
    S = mcm._stationary_2x2(A, b, 2.5)
    ref = scipy.linalg.solve_continuous_lyapunov(A, -2.5 * np.outer(b, b))
    np.testing.assert_allclose(S, ref, rtol=1e-12)
    wrong = S * np.array([[1.0, -1.0], [-1.0, 1.0]])
    assert not np.allclose(wrong, ref, rtol=1e-3)


# Random streams ----------------------------------------------------------------------------------
def test_kernel_normals_are_numpys():
    """The kernel's generator (SFC64 and the 256-layer ziggurat, in numba) draws what numpy's
    Generator(SFC64).standard_normal draws from the same state, lane by lane: 48 streams ×
    92 000 normals agree to 1e-12 relative (the ziggurat tables are rebuilt in double
    precision, 1e-14 from numpy's), tails beyond the ziggurat's r = 3.654 included, and the
    streams stay in step (a rejection handled differently would shift every later number)."""
    gens = gc.run_streams(123, 48)
    state = np.array([g.bit_generator.state["state"]["state"] for g in gens], dtype=np.uint64).T
    ours = mcm._standard_normals(state, (4000, 23))
    ref = np.stack([g.standard_normal((4000, 23)) for g in gens], axis=2)
    assert np.count_nonzero(np.abs(ref) > 3.6541528853610088) > 100
    np.testing.assert_allclose(ours, ref, rtol=1e-12, atol=0)
    # the states advanced in place are numpy's states after the same draws
    after = np.array([g.bit_generator.state["state"]["state"] for g in gens], dtype=np.uint64).T
    assert np.array_equal(state, after)


def test_stream_lanes_are_numpys():
    """simulate_truth's draw (:func:`gyrolib.gc.analysis.montecarlo._fill_stream_lanes`): the first
    lanes of what numpy's Generator(SFC64).standard_normal((steps, width, 32)) draws from one
    stream, to 1e-12 relative (tails included), and the stream's state after it is numpy's
    after the whole array; keeping one lane or three gives the same numbers."""
    ref_gen = np.random.Generator(np.random.SFC64(2024))
    state = ref_gen.bit_generator.state["state"]["state"].reshape(4, 1).copy()
    ref = ref_gen.standard_normal((3000, 23, mcm._RUN_BLOCK))
    assert np.count_nonzero(np.abs(ref[..., :3]) > 3.6541528853610088) > 10
    out = np.empty((3000, 23, 3))
    mcm._fill_stream_lanes(state, out, mcm._RUN_BLOCK, mcm._ZKI, mcm._ZWI, mcm._ZFI)
    np.testing.assert_allclose(out, ref[..., :3], rtol=1e-12, atol=0)
    assert np.array_equal(state[:, 0], ref_gen.bit_generator.state["state"]["state"])
    one = np.empty((3000, 23, 1))
    state1 = np.random.Generator(np.random.SFC64(2024)).bit_generator.state["state"]["state"]
    mcm._fill_stream_lanes(state1.reshape(4, 1).copy(), one, mcm._RUN_BLOCK, mcm._ZKI,
                           mcm._ZWI, mcm._ZFI)
    np.testing.assert_allclose(one[..., 0], ref[..., 0], rtol=1e-12, atol=0)
    # power: the same draw taken as 31 lanes a step is out of step with numpy's at once
    short = np.empty((3000, 23, 1))
    state2 = np.random.Generator(np.random.SFC64(2024)).bit_generator.state["state"]["state"]
    mcm._fill_stream_lanes(state2.reshape(4, 1).copy(), short, mcm._RUN_BLOCK - 1, mcm._ZKI,
                           mcm._ZWI, mcm._ZFI)
    assert not np.allclose(short[1:, :, 0], ref[1:, :, 0], rtol=1e-6)


def test_simulate_truth_draws_numpys_block_stream():
    """gc.simulate_truth (the kernel's draw of lane 0) against the same model run on numpy's
    draw of the whole block of 32 lanes (the path the sample records of data/ were made with):
    the same truth to 1e-12 of each state's scale."""
    x0 = np.zeros(10)
    x0[3], x0[4], x0[5] = 1e-6, 3e-4, -2e-4
    _, X = gc.simulate_truth(P, 2.0, x0, seed=11)
    n_steps = mcm.steps_in(P, 2.0)
    tm = mcm.truth_model(P, P, n_steps, mcm.TRUTH_SUBSTEPS)
    _, ref = mcm._run_batch(tm, n_steps, x0[None, :], np.random.default_rng(11), None, 1,
                            "fast")
    scale = np.abs(ref[0]).max(axis=0) + 1e-300
    assert np.max(np.abs(X - ref[0]) / scale) < 1e-12
    _, other = mcm._run_batch(tm, n_steps, x0[None, :], np.random.default_rng(12), None, 1,
                              "fast")
    assert np.max(np.abs(other[0] - ref[0]) / scale) > 1e-3     # a different seed differs


def test_simulate_records_are_the_block_streams_lanes():
    """gc.simulate_records (n records for the price of one): record 0 is simulate_record's
    record of the same seed, and record i's truth is the model run on lane i of numpy's
    draw of the whole block (the reference path, not the kernel's draw) from its initial
    state, to 1e-12 of each state's scale; each lane's truth differs from lane 0's (their
    streams are not one)."""
    sims = gc.simulate_records(P, 1.0, seed=5, n=3)
    one = gc.simulate_record(P, 1.0, seed=5)
    for name in ("t", "angle_sensor", "inclinometer_y", "inclinometer_z"):
        np.testing.assert_allclose(getattr(sims[0].record, name), getattr(one.record, name),
                                   rtol=1e-12, atol=0)
    n_steps = mcm.steps_in(P, 1.0)
    tm = mcm.truth_model(P, P, n_steps, mcm.TRUTH_SUBSTEPS)
    rng = np.random.default_rng(5)
    rng.standard_normal(10)
    truth_seed = int(rng.integers(0, 2**62))
    x0 = np.array([s.truth[0] for s in sims])
    _, ref = mcm._run_batch(tm, n_steps, x0, np.random.default_rng(truth_seed), None, 1,
                            "fast")
    for i, s in enumerate(sims):
        scale = np.abs(ref[i]).max(axis=0) + 1e-300
        assert np.max(np.abs(s.truth - ref[i]) / scale) < 1e-12, i
        if i:
            assert np.max(np.abs(s.truth[:, 6] - sims[0].truth[:, 6])) > 0.1 * scale[6]
    with pytest.raises(ValueError, match=r"x0 must have shape \(10,\) or \(n, 10\)"):
        gc.simulate_truth(P, 1.0, np.zeros((2, 9)))


def _assert_same_runs(a: gc.MonteCarloResult, b: gc.MonteCarloResult) -> None:
    """Estimates and truth of the runs of ``a`` equal the first runs of ``b`` to 1e-12 of
    each state's prior scale (never bitwise: SIMD rounding may differ)."""
    n = a.n_runs
    scale = np.sqrt(np.diagonal(b.P, axis1=1, axis2=2)).max(axis=0) + 1e-300
    for x, y in ((a.est, b.est[:n]), (a.tru, b.tru[:n])):
        assert np.max(np.abs(x - y) / scale) < 1e-12


@pytest.fixture(scope="module")
def reference_runs() -> gc.MonteCarloResult:
    return gc.monte_carlo(P, 70, 1.0, seed=5, store_every=50)


@pytest.mark.parametrize("how", ["serial", "threads", "processes", "fewer runs", "one chunk"])
def test_runs_depend_neither_on_threads_executor_nor_run_count(reference_runs, how,
                                                               monkeypatch):
    """Each run has its own stream (SeedSequence(seed).spawn): the same 70 runs on this
    process's threads, on one thread, on a ThreadPoolExecutor or a ProcessPoolExecutor of 2
    workers, in one chunk, and the first 33 of them alone agree to 1e-12."""
    if how == "serial":
        with ThreadPoolExecutor(1) as ex:
            res = gc.monte_carlo(P, 70, 1.0, seed=5, store_every=50, executor=ex)
    elif how == "threads":
        with ThreadPoolExecutor(2) as ex:
            res = gc.monte_carlo(P, 70, 1.0, seed=5, store_every=50, executor=ex)
    elif how == "processes":
        with ProcessPoolExecutor(2) as ex:
            res = gc.monte_carlo(P, 70, 1.0, seed=5, store_every=50, executor=ex)
    elif how == "fewer runs":
        res = gc.monte_carlo(P, 33, 1.0, seed=5, store_every=50)
    else:
        monkeypatch.setattr(mcm, "_EXECUTOR_CHUNKS", 1)
        with ThreadPoolExecutor(2) as ex:
            res = gc.monte_carlo(P, 70, 1.0, seed=5, store_every=50, executor=ex)
    _assert_same_runs(res, reference_runs)
    np.testing.assert_allclose(res.P, reference_runs.P, rtol=1e-12, atol=0)


def test_other_seed_gives_other_runs(reference_runs):
    """The comparison above has power: another seed changes every run by far more."""
    other = gc.monte_carlo(P, 70, 1.0, seed=6, store_every=50)
    scale = np.sqrt(np.diagonal(other.P, axis1=1, axis2=2)).max(axis=0)
    assert np.min(np.max(np.abs(other.tru - reference_runs.tru) / scale, axis=(1, 2))) > 1e-3


def test_bad_executor_and_bad_pairs_are_rejected(matched, matched_linear):
    with pytest.raises(TypeError, match=r"^executor must be"):
        gc.monte_carlo(P, 2, 0.01, executor=4)
    with pytest.raises(ValueError, match=r"^linear must come from monte_carlo"):
        gc.linearization_effect(matched, matched)
    other = gc.monte_carlo(P, N_RUNS, T_END, seed=SEED + 1, store_every=100, truth="linear")
    with pytest.raises(ValueError, match=r"^nonlinear and linear must share seed"):
        gc.linearization_effect(matched, other)


# What the linearization costs --------------------------------------------------
@pytest.fixture(scope="module")
def effect(matched, matched_linear) -> gc.LinearizationEffect:
    return gc.linearization_effect(matched, matched_linear)


def test_nonlinear_truth_excess_is_the_remainder_drift(effect):
    """Nonlinear against linearized truth, same 200 runs, 20 s.  (i) The ω_gc estimate
    shifts, run by run, by the closed-form remainder of the horizontal-rate torque,
    −Ω_h cos β_n ψ²/2 (regression slope 1 ± 0.02 after 5 s); (ii) no state's error moves by
    more than 2 % of its σ (ω_gc), the others by less than 1e-3; (iii) the full-state NEES
    is higher by what that shift predicts, mean(ρ²)·(P⁻¹)_ωω, computed from the truth's ψ
    and the filter's P alone (within 10 %), a systematic excess of more than 0.2 where the
    linearized truth is consistent."""
    assert effect.slope(t_min=5.0) == pytest.approx(1.0, abs=0.02)
    late = effect.t >= 5.0
    i_w = gc.state_index("omega_gc")
    assert effect.state_shift[late, i_w].max() < 0.02
    assert np.delete(effect.state_shift[late], i_w, axis=1).max() < 1e-3
    excess, predicted = effect.excess[late].mean(), effect.excess_predicted[late].mean()
    assert excess > 0.2
    assert excess == pytest.approx(predicted, rel=0.1)
    assert effect.sigma_ratio[late].min() > 50.0   # ω_gc held by the other states


@pytest.mark.parametrize(("truth", "substeps", "share"), [("linear_horizontal", 10, 0.0),
                                                          ("linear_tilt", 10, 1.0),
                                                          ("nonlinear", 5, 1.0)])
def test_only_the_horizontal_rate_remainder_makes_the_excess(effect, matched_linear, truth,
                                                             substeps, share):
    """Switching each cause off: linearizing only the horizontal-rate torque Ω_h cos(β − ψ)
    removes the excess; linearizing only the tilt terms, or halving the truth's step count
    (its discretization), leaves it as it is (within 5 % of the full effect)."""
    kw = dict(seed=SEED, store_every=100, substeps=substeps)
    a = gc.monte_carlo(P, N_RUNS, T_END, truth=truth, **kw)
    # the linearized truth at the default step count is the module's matched_linear (the
    # same call), not run again
    b = (matched_linear if substeps == mcm.TRUTH_SUBSTEPS
         else gc.monte_carlo(P, N_RUNS, T_END, truth="linear", **kw))
    late = effect.t >= 5.0
    full = effect.excess[late].mean()
    got = gc.linearization_effect(a, b).excess[late].mean()
    assert got == pytest.approx(share * full, abs=0.05 * full)


@pytest.mark.parametrize("psi_arcsec", [10.0, 180.0, 3600.0])
def test_remainder_drift_is_the_second_order_term(psi_arcsec):
    """The remainder against the difference of cosines in 40-digit arithmetic (1e-12), and
    against its Taylor terms −Ω_h (cos β_n ψ²/2 + sin β_n ψ³/6) to the fourth-order term."""
    import mpmath

    psi = psi_arcsec * ARCSEC_PAPER
    b = 0.008
    got = float(gc.remainder_drift(P, psi, b))
    mpmath.mp.dps = 40
    x, bb = mpmath.mpf(-psi), mpmath.mpf(b)
    exact = P.Omega_h * (mpmath.cos(bb + x) - mpmath.cos(bb) + mpmath.sin(bb) * x)
    assert got == pytest.approx(float(exact), rel=1e-12)
    taylor = -P.Omega_h * (np.cos(b) * psi**2 / 2 + np.sin(b) * psi**3 / 6)
    assert got == pytest.approx(taylor, rel=5e-5)


def test_the_summary_and_the_compact_effect_read_as_the_runs(matched, effect):
    """What the stored studies keep gives the numbers the whole runs give: the summary's σ,
    RMS error, average NEES and end values; the compact effect's slope and residual (from its
    per-time sums, against the per-run arrays directly)."""
    s = matched.summary(keep_runs=2)
    # the same reductions of the same runs; a tolerance, since a summation's rounding may
    # follow the array's layout
    close = {"rtol": 1e-13, "atol": 0.0}
    np.testing.assert_allclose(s.std("omega_gc"), matched.std("omega_gc"), **close)
    np.testing.assert_allclose(s.rms_error("omega_gc"), matched.rms_error("omega_gc"), **close)
    np.testing.assert_allclose(s.mean_nees(), matched.nees().mean(axis=0), **close)
    assert s.inside_share(("omega_gc",)) == matched.inside_share(("omega_gc",))
    assert np.array_equal(s.estimate("omega_gc"), matched.estimate("omega_gc")[:2])
    assert np.array_equal(s.error_end("psi"), matched.error("psi")[:, -1])
    with pytest.raises(ValueError, match="summary's states"):
        s.std("psi")
    c = effect.compact()
    assert c.omega_shift.shape == (matched.n_runs, 1)
    late = effect.t >= 5.0
    x, y = effect.omega_shift_predicted[:, late], effect.omega_shift[:, late]
    assert c.slope(5.0) == pytest.approx(np.sum(x * y) / np.sum(x * x), rel=1e-12)
    d = effect.omega_shift - effect.omega_shift_predicted
    np.testing.assert_allclose(c.residual, np.sqrt(np.mean(d**2, axis=0) / np.mean(
        effect.omega_shift_predicted**2, axis=0)), rtol=1e-12)
