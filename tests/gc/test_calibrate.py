"""gc.calibrate on records: against the covariance analysis (a separate kernel), a plain-numpy
reference filter written here (exact per-step Van Loan, Radau nominal motion, conventional
scalar updates), the truth of seeded simulations, and the gates, gaps, NaNs and streaming."""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest
import scipy.stats

from gyrolib import filtering, gc
from gyrolib.gc.logs.calibration import _Nominal

P = gc.GyrocompassParams()


# A record with the damage of a real log ------------------------------------------------------
def _damaged(seed: int, t_end: float = 100.0, gap=(40.0, 42.0), n_nan: int = 300,
             burst_at: float = 70.0, burst_n: int = 50, burst_size: float = 1e-3):
    sim = gc.simulate_record(P, t_end, seed=seed)
    r = sim.record
    rng = np.random.default_rng(seed + 1000)
    a, y, z = (np.array(c) for c in (r.angle_sensor, r.inclinometer_y, r.inclinometer_z))
    burst = np.nonzero(r.t > burst_at)[0][:burst_n]
    a[burst] += burst_size * rng.choice([-1.0, 1.0], burst.size)
    cells = rng.choice(r.n, n_nan, replace=False)
    for k, col in enumerate((a, y, z)):
        col[cells[k::3]] = np.nan
    keep = ~((r.t > gap[0]) & (r.t <= gap[1]))
    rec = gc.GCRecord(t=r.t[keep], angle_sensor=a[keep], inclinometer_y=y[keep],
                      inclinometer_z=z[keep])
    return sim, rec, r.t[burst], int(np.count_nonzero(keep[cells]))


@pytest.fixture(scope="module")
def damaged():
    return _damaged(seed=101)


@pytest.fixture(scope="module")
def cov100():
    return gc.covariance_analysis(P, 100.0)


def test_acceptance_damaged_record(damaged, cov100):
    """2 s gap, NaNs and an outlier burst: ω_gc within 3σ of the truth, σ equal to the
    covariance analysis' σ at the end within 5 %, the outliers rejected and reported."""
    sim, rec, burst_t, nan_kept = damaged
    res = gc.calibrate(rec, P)
    assert abs(res.omega_gc - sim.omega_gc) <= 3.0 * res.omega_gc_std
    sigma_cov = float(cov100.std("omega_gc")[-1])
    assert res.omega_gc_std == pytest.approx(sigma_cov, rel=0.05)
    assert np.all(np.isin(burst_t, res.rejected_t))
    assert res.rejected[0] >= burst_t.size
    assert int(res.missing.sum()) == nan_kept
    assert res.gaps == 1 and res.gap_time == pytest.approx(2.0, abs=1e-9)
    assert res.t_final == pytest.approx(100.0)


def test_sigma_equals_covariance_analysis_on_clean_record(cov100):
    """No gate hits (gate at 1 − 1e-12), no gaps: the filter's σ of every state at every
    stored time equals the covariance analysis (a separate numba kernel) to 1e-6."""
    sim = gc.simulate_record(P, 100.0, seed=5)
    res = gc.calibrate(sim.record, P, gate=1 - 1e-12, store_every=1000)
    assert res.rejected.sum() == 0
    k = np.rint(res.t / P.dt).astype(int)
    np.testing.assert_allclose(res.std**2, cov100.var[k], rtol=1e-6, atol=0)


def test_estimates_consistent_over_seeds():
    """Across seeds, (ω̂ − ω)/σ has mean square near 1 (χ²(8)/8 in [0.16, 2.5], 99 %)."""
    z = []
    for seed in range(201, 209):
        sim = gc.simulate_record(P, 20.0, seed=seed)
        res = gc.calibrate(sim.record, P)
        z.append((res.omega_gc - sim.omega_gc) / res.omega_gc_std)
    ms = float(np.mean(np.square(z)))
    lo, hi = scipy.stats.chi2.ppf([0.005, 0.995], 8) / 8
    assert lo <= ms <= hi


def test_diagnostics_fit_and_detect_wrong_spectrum():
    """The right model: every NIS in band and white; a 10× wider vibration spectrum: the
    inclinometer NIS far above its band (the check has power)."""
    good = gc.calibrate(gc.simulate_record(P, 30.0, seed=11).record, P)
    assert np.all(good.fits(0.999)), good.verdict()
    wrong_p = dataclasses.replace(P, alpha1=10 * P.alpha1)
    bad = gc.calibrate(gc.simulate_record(wrong_p, 30.0, seed=11).record, P)
    assert not np.all(bad.fits(0.999))
    assert bad.nis_mean[1] > 2.0 * bad.nis_band(0.999)[1, 1]
    assert "does NOT fit" in bad.verdict()


def test_gate_rejects_what_the_chi2_threshold_says():
    """Each rejected NIS exceeds the χ²(1) quantile of the gate, and on a clean record the
    rejection rate is the gate's false-alarm rate (binomial 99.9 % bounds)."""
    sim = gc.simulate_record(P, 30.0, seed=12)
    res = gc.calibrate(sim.record, P, gate=0.999)
    thr = scipy.stats.chi2.ppf(0.999, 1)
    assert np.all(res.rejected_nis > thr)
    n = 3 * sim.record.n
    lo, hi = scipy.stats.binom.ppf([0.0005, 0.9995], n, 1e-3)
    assert lo <= res.rejected.sum() <= hi


# Streaming -----------------------------------------------------------------------------
def test_chunked_run_equals_one_shot(damaged):
    _, rec, _, _ = damaged
    one = gc.calibrate(rec, P, chunk_size=10**7)
    for size in (997, 20000):
        ch = gc.calibrate(rec, P, chunk_size=size)
        np.testing.assert_allclose(ch.x_final, one.x_final, rtol=1e-12, atol=1e-30)
        np.testing.assert_allclose(ch.P_final, one.P_final, rtol=1e-12, atol=1e-40)
        np.testing.assert_allclose(ch.t, one.t, rtol=1e-15, atol=0)
        np.testing.assert_allclose(ch.x, one.x, rtol=1e-12, atol=1e-30)
        np.testing.assert_allclose(ch.nis_window, one.nis_window, rtol=1e-12)
        assert (ch.used == one.used).all() and (ch.rejected == one.rejected).all()
        np.testing.assert_allclose(ch.acf, one.acf, rtol=1e-9, atol=1e-15)


def test_nominal_window_equals_library_integrator():
    """The streaming nominal motion equals gc.nominal_half_steps (same scheme, restarted)."""
    nom = _Nominal(P)
    ref = gc.nominal_half_steps(P, 3000)
    for lo, hi in ((0.0, 0.5), (0.4, 1.2), (2.0, 2.9)):
        grid, g0 = nom.window(lo, hi)
        np.testing.assert_allclose(grid, ref[g0:g0 + grid.size], rtol=1e-13, atol=1e-18)


# Against an independent plain-numpy filter ----------------------------------------------------
def _reference(rec: gc.GCRecord, p: gc.GyrocompassParams, gate: float = 0.9999):
    """Plain numpy: exact Van Loan per step at the Radau nominal motion's midpoint, scalar
    conventional updates (filtering.sequential_update), gate, NaN skip."""
    G = gc.noise_input_matrix(p)
    Qc = gc.process_noise_intensity(p)
    H = gc.measurement_matrix(p)
    R = gc.measurement_noise_covariance(p)
    thr = scipy.stats.chi2.ppf(gate, 1)
    # the times at which the nominal motion is needed
    steps = []
    tc = 0.0
    for ti in rec.t:
        n = math.floor((ti - tc) / p.dt + 1e-6)
        for _ in range(n):
            steps.append((tc, p.dt))
            tc += p.dt
        if ti - tc > 1e-6 * p.dt:
            steps.append((tc, ti - tc))
        tc = ti
        steps.append((ti, 0.0))   # 0: an update
    mids = np.array([a + 0.5 * h for a, h in steps])
    beta = gc.nominal_motion(p, np.concatenate([[0.0], np.sort(mids)])).beta[1:]
    beta = beta[np.argsort(np.argsort(mids))]
    x = np.zeros(10)
    Pm = gc.initial_covariance(p)
    row = 0
    rejected = []
    for (a, h), b in zip(steps, beta):
        if h > 0:
            Phi, Qd = filtering.van_loan(gc.system_matrix(p, b), G, Qc, h)
            x = Phi @ x
            Pm = Phi @ Pm @ Phi.T + Qd
            continue
        z = np.array([rec.angle_sensor[row] - b, rec.inclinometer_y[row],
                      rec.inclinometer_z[row]])
        for q in range(3):
            if np.isnan(z[q]):
                continue
            S = H[q] @ Pm @ H[q] + R[q, q]
            nu = z[q] - H[q] @ x
            if nu * nu / S > thr:
                rejected.append((a, q))
                continue
            x, Pm = filtering.sequential_update(x, Pm, z[q:q + 1], H[q:q + 1],
                                                R[q:q + 1, q:q + 1])
        row += 1
    return x, Pm, rejected


def test_matches_plain_numpy_reference_with_gap_nan_irregular_and_outliers():
    sim = gc.simulate_record(P, 1.5, seed=31)
    r = sim.record
    t = r.t.copy()
    t[700] += 0.4 * P.dt          # one irregular sample time
    a = r.angle_sensor.copy()
    a[900:905] += 2e-3            # outliers
    y = r.inclinometer_y.copy()
    y[100] = np.nan
    keep = ~((t > 0.3) & (t <= 0.55))   # a 0.25 s gap
    rec = gc.GCRecord(t=t[keep], angle_sensor=a[keep], inclinometer_y=y[keep],
                      inclinometer_z=r.inclinometer_z[keep])
    res = gc.calibrate(rec, P, chunk_size=333)
    x, Pm, rejected = _reference(rec, P)
    # the shifted sample ends a step of 1.4 dt (1 whole + a 0.4 dt remainder), the next one
    # a step of 0.6 dt; the gap is a whole number of steps
    assert res.irregular_steps == 2
    sd = np.sqrt(np.diag(Pm))
    np.testing.assert_allclose(res.x_final, x, rtol=0, atol=1e-6 * sd.max())
    np.testing.assert_allclose((res.x_final - x) / sd, 0.0, atol=1e-5)
    np.testing.assert_allclose(np.sqrt(np.diag(res.P_final)), sd, rtol=1e-6)
    assert res.rejected.sum() == len(rejected)
    assert sorted(res.rejected_t.tolist()) == sorted(a_ for a_, _ in rejected)


def test_jittered_time_stamps_match_the_exact_reference():
    """±20 µs of jitter on every 1 ms time stamp: the Taylor time shift equals the exact
    per-step Van Loan discretization of the reference filter to 1e-8 σ (estimates) and 1e-10
    (σ).  Ignoring the jitter (a tolerance that treats every step as dt) misses by 1e-5 σ and
    1e-6: small, but the comparison resolves it (power)."""
    sim = gc.simulate_record(P, 1.0, seed=32)
    r = sim.record
    t = r.t + np.random.default_rng(5).uniform(-2e-5, 2e-5, r.n)
    rec = gc.GCRecord(t=t, angle_sensor=r.angle_sensor, inclinometer_y=r.inclinometer_y,
                      inclinometer_z=r.inclinometer_z)
    res = gc.calibrate(rec, P, gate=1 - 1e-12)
    assert res.jittered_steps == rec.n and res.irregular_steps == 0
    x, Pm, _ = _reference(rec, P, gate=1 - 1e-12)
    sd = np.sqrt(np.diag(Pm))
    np.testing.assert_allclose((res.x_final - x) / sd, 0.0, atol=1e-8)
    np.testing.assert_allclose(np.sqrt(np.diag(res.P_final)), sd, rtol=1e-10)
    crude = gc.calibrate(rec, P, gate=1 - 1e-12, time_tolerance=0.05)
    assert crude.jittered_steps == 0
    assert np.max(np.abs((crude.x_final - x) / sd)) > 1e-6
    assert np.max(np.abs(np.sqrt(np.diag(crude.P_final)) / sd - 1)) > 1e-7


# Bad input at the door -------------------------------------------------------------------
def test_record_and_argument_errors():
    with pytest.raises(ValueError, match="t must be strictly increasing"):
        gc.GCRecord(t=[0.002, 0.001], angle_sensor=[0, 0], inclinometer_y=[0, 0],
                    inclinometer_z=[0, 0])
    with pytest.raises(ValueError, match="t must be >= 0"):
        gc.GCRecord(t=[-0.001, 0.001], angle_sensor=[0, 0], inclinometer_y=[0, 0],
                    inclinometer_z=[0, 0])
    with pytest.raises(ValueError, match="inclinometer_z must have 2 values"):
        gc.GCRecord(t=[0.001, 0.002], angle_sensor=[0, 0], inclinometer_y=[0, 0],
                    inclinometer_z=[0])
    rec = gc.GCRecord(t=[0.001], angle_sensor=[0.0], inclinometer_y=[0.0],
                      inclinometer_z=[0.0])
    with pytest.raises(TypeError, match="params must be a GyrocompassParams"):
        gc.calibrate(rec, params="paper")
    with pytest.raises(ValueError, match="gate must be in"):
        gc.calibrate(rec, P, gate=1.0)
    with pytest.raises(TypeError, match="record must be a GCRecord"):
        gc.calibrate(np.zeros((3, 4)), P)


# Lost lock: the run is invalid, with a reason naming the sensor ---------------------------------
@pytest.fixture(scope="module")
def sample():
    from gyrolib import records
    return records.read_gc(Path(__file__).resolve().parents[2] / "data" / "gc_record.csv.gz")


def _with_columns(rec: gc.GCRecord, **cols) -> gc.GCRecord:
    base = {"t": rec.t, "angle_sensor": rec.angle_sensor,
            "inclinometer_y": rec.inclinometer_y, "inclinometer_z": rec.inclinometer_z}
    return gc.GCRecord(**{**base, **cols})


def test_good_sample_record_is_valid(sample):
    """The sample record (gap, NaNs, a 20-row outlier burst): valid, no reason, and the
    estimate within 3σ of the truth in data/truth.json."""
    truth = json.loads((Path(__file__).resolve().parents[2] / "data" / "truth.json")
                       .read_text())["gc_record.csv.gz"]
    res = gc.calibrate(sample, gc.GyrocompassParams.at_latitude(sample.latitude))
    assert res.valid and res.reason == ""
    assert np.all(res.rejected_share <= 0.01)
    assert abs(res.omega_gc - truth["omega_gc_rad_s"]) <= 3 * res.omega_gc_std
    s = res.summary()
    assert s["valid"] is True and s["reason"] == ""
    json.dumps(s)   # JSON-ready


def test_sign_flipped_inclinometer_is_invalid(sample):
    """inclinometer_y negated: the filter follows y (processed first) and the gate rejects
    almost every z sample; the run is invalid and the reason names the inclinometer whose
    samples were rejected (the data cannot tell which of the two is flipped)."""
    res = gc.calibrate(_with_columns(sample, inclinometer_y=-sample.inclinometer_y), P)
    assert not res.valid
    assert res.rejected_share[2] > 0.5
    assert "inclinometer_z" in res.reason and "rejected by the chi-square gate" in res.reason
    assert "angle_sensor" not in res.reason
    assert res.summary()["valid"] is False


def test_angle_in_degrees_is_invalid(sample):
    """The angle column in degrees: nearly every angle-sensor sample rejected; invalid, the
    reason names angle_sensor (and only it)."""
    res = gc.calibrate(_with_columns(sample, angle_sensor=np.degrees(sample.angle_sensor)), P)
    assert not res.valid
    assert res.rejected_share[0] > 0.99
    assert res.reason.startswith("angle_sensor: ")
    assert "inclinometer" not in res.reason


def test_validity_limits_are_parameters(sample):
    """The limits decide: no rejection allowed makes the sample record's 30 angle-sensor
    rejections (its outlier burst) invalid; a NIS range of ±0.1 % about 1 (tighter than the
    sampling spread of a mean over 99 000 samples) fails every sensor."""
    res = gc.calibrate(sample, P.at_latitude(sample.latitude), max_rejected=0.0)
    assert not res.valid and res.reason.startswith("angle_sensor: ")
    assert int(res.rejected[0]) >= 20
    res = gc.calibrate(sample, P.at_latitude(sample.latitude), nis_range=(0.999, 1.001))
    assert not res.valid
    assert all(f"{name}: mean NIS" in res.reason for name in gc.MEASUREMENT_NAMES)


def test_log_likelihood_equals_the_batch_gaussian_density():
    """ln L of the prediction-error decomposition (recursive, the filter's S and ν) equals the
    log-density of all 3·n measurements under their joint Gaussian, built in one batch from
    the same discrete model (Φ_k, Qd_k of gc.discretize): a second algorithm."""
    n = 40
    sim = gc.simulate_record(P, n * P.dt, seed=41)
    rec = sim.record
    disc = gc.discretize(P, n * P.dt)
    mdl = disc.model
    # x_k = Φ_{k-1} x_{k-1} + w: the states at k = 1..n as a linear map of (x_0, w_0..w_{n-1})
    P0 = gc.initial_covariance(P)
    L = np.zeros((n, 10, 10 * (n + 1)))
    X = np.zeros((10, 10 * (n + 1)))
    X[:, :10] = np.eye(10)
    blocks = [P0] + [mdl.qd(k) for k in range(n)]
    for k in range(n):
        X = mdl.phi(k) @ X
        X[:, 10 * (k + 1):10 * (k + 2)] += np.eye(10)
        L[k] = X
    from scipy.linalg import block_diag
    Sx = block_diag(*blocks)
    D = gc.measurement_matrix(P)
    M = np.concatenate([D @ L[k] for k in range(n)])              # (3n, 10(n+1))
    R = np.kron(np.eye(n), gc.measurement_noise_covariance(P))
    C = M @ Sx @ M.T + R
    z = np.column_stack([rec.angle_sensor - disc.beta_half[2::2], rec.inclinometer_y,
                         rec.inclinometer_z]).ravel()
    batch = scipy.stats.multivariate_normal(mean=np.zeros(3 * n), cov=C).logpdf(z)
    ll = gc.innovation_log_likelihood(rec, P)
    assert ll == pytest.approx(batch, rel=1e-9, abs=1e-6)
    res = gc.calibrate(rec, P, gate=1 - 1e-12)
    assert res.rejected.sum() == 0 and res.log_likelihood == pytest.approx(ll, rel=1e-12)
    # power: a wrong model gives another number
    wrong = gc.innovation_log_likelihood(rec, dataclasses.replace(P, C_as=2 * P.C_as))
    assert abs(wrong - batch) > 1.0
