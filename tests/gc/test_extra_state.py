"""The kernels are generic in the model.  A model with one extra constant
state (the angle sensor's null offset, :data:`gyrolib.gc.TERMS`) runs through the covariance
analysis, the Monte Carlo and ``calibrate``, each checked against something independent:

* the covariance analysis against a plain-numpy augmented-state Kalman covariance recursion
  written here (paper GC's matrices from ``tests/support/gc_reference.py``, which imports nothing of
  gyrolib's model; the constant's columns typed here; β_n by ``solve_ivp``);
* the Monte Carlo's estimate errors of the offset and of ω_gc against the covariance's σ
  (a χ² bound on the NEES summed over the runs);
* ``calibrate`` on a record made by the truth model plus an offset drawn inside the prior
  (added here): the estimate covers the truth and its σ(ω_gc) is the covariance's.

Power: the same checks with the offset switched off in the filter while the truth carries a
large one fail.  And "adding a state is an edit of the model": a term declared only in
:data:`gyrolib.gc.model.instrument.TERMS` (monkeypatched) runs through all three.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import scipy.integrate
import scipy.linalg
import scipy.stats

from gyrolib import gc
from gyrolib.gc.model import instrument
from tests.support.gc_reference import _matrices, _p0

P = gc.GyrocompassParams()
SIG_OFF = 4.0 * 0.485e-5            # 4″ of the paper's arcsecond: the prior of the offset (rad)
P_OFF = dataclasses.replace(P, sigma_as_offset=SIG_OFF)


def reference_covariance(p, t_end, h0, h1, prior, times, fb=None):
    """Plain numpy: the 10 states of Eq. (8) (tests/support/gc_reference.py's matrices) and ``nb``
    constants with readings ``(h0 + β_n(t_k) h1) b`` (h0, h1: 3 × nb), prior σ ``prior``
    and optionally a dynamics column ``fb`` (10 × nb: ``ẋ += fb b``);
    per step Φ, Qd by one Van Loan exponential (F frozen at the midpoint's β_n), a batch
    Joseph update with all three sensors.  Returns ``{t: P}`` at ``times``."""
    F0, Fs, Fc, G, D, Q, R = _matrices(p, None)
    nb = h0.shape[1]
    n = 10 + nb
    k_rate = p.H * p.Omega_h / p.I
    n_steps = round(t_end / p.dt)
    t_eval = np.arange(1, 2 * n_steps + 1) * 0.5 * p.dt
    sol = scipy.integrate.solve_ivp(
        lambda t, y: [y[1], -p.f / p.I * y[1] + k_rate * np.cos(y[0])], (0.0, t_end),
        [0.0, 0.0], method="DOP853", t_eval=t_eval, rtol=1e-12, atol=1e-16)
    beta_mid, beta_k = sol.y[0][0::2], sol.y[0][1::2]
    Pa = np.zeros((n, n))
    Pa[:10, :10] = _p0(p, F0, G, Q, "stationary")
    Pa[10:, 10:] = np.diag(np.asarray(prior) ** 2)
    Ga = np.zeros((n, 2))
    Ga[:10] = G
    GQG = Ga @ Q @ Ga.T
    want = {round(t / p.dt): t for t in times}
    out = {}
    eye = np.eye(n)
    for k in range(n_steps):
        b = beta_mid[k]
        F = np.zeros((n, n))
        F[:10, :10] = F0 + np.sin(b) * Fs + np.cos(b) * Fc
        if fb is not None:
            F[:10, 10:] = fb
        M = np.zeros((2 * n, 2 * n))
        M[:n, :n] = -F * p.dt
        M[:n, n:] = GQG * p.dt
        M[n:, n:] = F.T * p.dt
        E = scipy.linalg.expm(M)
        Phi = E[n:, n:].T
        Qd = Phi @ E[:n, n:]
        Pa = Phi @ Pa @ Phi.T + 0.5 * (Qd + Qd.T)
        H = np.hstack([D, h0 + beta_k[k] * h1])
        S = H @ Pa @ H.T + R
        K = np.linalg.solve(S, H @ Pa).T
        A = eye - K @ H
        Pa = A @ Pa @ A.T + K @ R @ K.T
        if k + 1 in want:
            out[want[k + 1]] = Pa.copy()
    return out


OFFSET_H0 = np.array([[1.0], [0.0], [0.0]])
ZERO_H = np.zeros((3, 1))
TIMES = (0.5, 1.0, 2.0)


@pytest.fixture(scope="module")
def ref_offset():
    return reference_covariance(P_OFF, 2.0, OFFSET_H0, ZERO_H, [SIG_OFF], TIMES)


def _rel(a, b):
    return abs(a / b - 1.0)


def test_default_state_vector_is_the_papers():
    """No prior set: the model is Eq. (8)'s 10 states, and the covariance analysis is
    exactly the paper's (the same numbers as with no instrument module at all)."""
    assert gc.state_names(P) == gc.STATE_NAMES
    res = gc.covariance_analysis(P, 0.5)
    assert res.names == gc.STATE_NAMES and res.var.shape[1] == 10


def test_covariance_with_offset_matches_numpy_reference(ref_offset):
    """σ of ω_gc, of the offset and of Δβ from the fast kernel (time-varying H column
    ``H0 + β_n H1``) agree with the plain-numpy augmented recursion to 1e-6 relative; the
    plain-numpy path of the library too.  Power: the 10-state filter's σ(ω_gc) and the
    reference of a wrong column (the offset read by inclinometer y) differ by far more."""
    res = gc.covariance_analysis(P_OFF, 2.0)
    assert res.names == (*gc.STATE_NAMES, "angle_offset")
    plain = gc.covariance_analysis(P, 2.0)
    for t, Pr in ref_offset.items():
        for name, i in (("omega_gc", 3), ("angle_offset", 10), ("dbeta", 0), ("psi", 2)):
            assert _rel(res.std_at(name, t), np.sqrt(Pr[i, i])) < 1e-6, (name, t)
        # power: the filter without the offset is not the reference
        assert _rel(plain.std_at("omega_gc", t), np.sqrt(Pr[3, 3])) > 1e-3
    wrong = reference_covariance(P_OFF, 2.0, np.array([[0.0], [1.0], [0.0]]), ZERO_H,
                                 [SIG_OFF], (2.0,))
    assert _rel(res.std_at("angle_offset", 2.0), np.sqrt(wrong[2.0][10, 10])) > 1e-2
    ref = gc.covariance_analysis(P_OFF, 0.5, method="reference")
    assert _rel(ref.final_std("omega_gc"), np.sqrt(ref_offset[0.5][3, 3])) < 1e-6
    assert _rel(ref.final_std("angle_offset"), np.sqrt(ref_offset[0.5][10, 10])) < 1e-6


def test_covariance_with_scale_matches_numpy_reference():
    """The scale term's column varies with β_n (``H1``): σ(ω_gc) and σ(κ) against the
    reference to 1e-6; power: the same reference with the column held at β_n = 0 (``H0``
    instead of ``H1``: the term unobservable) differs by far more."""
    ps = dataclasses.replace(P, sigma_hf_scale=1e-3)
    res = gc.covariance_analysis(ps, 2.0)
    ref = reference_covariance(ps, 2.0, ZERO_H, OFFSET_H0, [1e-3], (2.0,))[2.0]
    assert _rel(res.final_std("omega_gc"), np.sqrt(ref[3, 3])) < 1e-6
    assert _rel(res.final_std("scale"), np.sqrt(ref[10, 10])) < 1e-6
    assert res.final_std("scale") < 0.999e-3     # the data did say something about κ
    const = reference_covariance(ps, 2.0, OFFSET_H0, ZERO_H, [1e-3], (2.0,))[2.0]
    assert _rel(res.final_std("scale"), np.sqrt(const[10, 10])) > 1e-2


def _nees_sum_bounds(dof, prob=1e-3):
    """Two-sided χ² bounds of a sum of NEES over runs (``dof`` in all), each tail ``prob``."""
    return scipy.stats.chi2.ppf(prob, dof), scipy.stats.chi2.ppf(1.0 - prob, dof)


def _mc_checks(mc, cov, n_runs):
    """The Monte Carlo's errors at the end of the runs against the covariance analysis' σ:
    the sum over runs of the NEES of ω_gc, of the offset (if the filter carries it) and of
    both jointly inside their χ² bounds (each tail 1e-3).  Returns the failures."""
    fails = []
    assert _rel(mc.std("omega_gc")[-1], cov.final_std("omega_gc")) < 1e-9
    names = [("omega_gc",)]
    if "angle_offset" in cov.names:
        assert _rel(mc.std("angle_offset")[-1], cov.final_std("angle_offset")) < 1e-9
        names += [("angle_offset",), ("omega_gc", "angle_offset")]
    for nm in names:
        total = float(np.sum(mc.nees(nm)[:, -1]))
        lo, hi = _nees_sum_bounds(len(nm) * n_runs)
        if not lo < total < hi:
            fails.append((nm, total, lo, hi))
    return fails


def test_monte_carlo_with_offset_is_consistent():
    """The truth draws the offset from its prior (per run, after its initial state) and its
    angle sensor reads it; the filter carries it as an 11th state.  Over 256 seeded runs of
    2 s the NEES sums of ω_gc, of the offset and of both lie in their χ² bounds; the truth's
    offsets have the prior's spread.  Power: the filter without the offset state (truth
    unchanged, an offset of 20″) fails the ω_gc bound."""
    n = 256
    cov = gc.covariance_analysis(P_OFF, 2.0)
    mc = gc.monte_carlo(P_OFF, n, 2.0, seed=29, store_every=100)
    assert mc.names == cov.names
    b = mc.truth("angle_offset")[:, 0]
    assert np.all(mc.truth("angle_offset") == b[:, None])          # a constant
    lo, hi = _nees_sum_bounds(n)
    assert lo < float(np.sum((b / SIG_OFF) ** 2)) < hi               # drawn from the prior
    assert _mc_checks(mc, cov, n) == []
    # each run's stream draws its 10 initial states first, the offset after them
    base = gc.monte_carlo(P, 4, 0.1, seed=29, store_every=10)
    same = gc.monte_carlo(P_OFF, 4, 0.1, seed=29, store_every=10)
    np.testing.assert_allclose(base.truth("psi"), same.truth("psi"), rtol=0, atol=0)
    # power: the filter without the offset state, on a truth with a large offset
    big = dataclasses.replace(P, sigma_as_offset=20.0 * 0.485e-5)
    off = gc.monte_carlo(P, n, 2.0, seed=29, store_every=100, truth_params=big)
    assert off.std("angle_offset")[-1] == 0.0                        # the filter's: known 0
    assert _mc_checks(off, gc.covariance_analysis(P, 2.0), n) != []


def _calibration_checks(res, omega, cov_sigma, offset=None):
    """Failures of calibrate's answer on a record of known ω_gc (and offset): the estimate
    within 3σ of the truth, and σ(ω_gc) the covariance analysis' to 1e-3 (the gate may drop a
    measurement or two of a clean record)."""
    fails = []
    if not abs(res.omega_gc - omega) <= 3.0 * res.omega_gc_std:
        fails.append(("omega_gc", (res.omega_gc - omega) / res.omega_gc_std))
    if not _rel(res.omega_gc_std, cov_sigma) < 1e-3:
        fails.append(("sigma", res.omega_gc_std / cov_sigma))
    if offset is not None:
        est = res.instrument["angle_offset"]
        if not abs(est["estimate"] - offset) <= 3.0 * est["std"]:
            fails.append(("angle_offset", (est["estimate"] - offset) / est["std"]))
    return fails


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_calibrate_with_offset_covers_the_truth(seed):
    """Records of the truth model (``gc.simulate_record``, 10 s) with a null offset drawn
    from the prior added here to the angle sensor: ``calibrate`` with the offset's prior
    covers ω_gc and the offset within 3σ, and its σ(ω_gc) is the covariance analysis'.
    Power: the filter without the offset state, on the same record with a 20″ offset,
    misses ω_gc by far more than 3σ (and its σ is not the augmented model's)."""
    t_end = 10.0
    sim = gc.simulate_record(P, t_end, seed)
    omega = float(sim.truth[0, 3])
    b = SIG_OFF * float(np.random.default_rng(100 + seed).standard_normal())
    rec = dataclasses.replace(sim.record, angle_sensor=sim.record.angle_sensor + b)
    res = gc.calibrate(rec, P_OFF)
    assert res.bias_names == tuple(t.name for t in gc.TERMS)     # from the model's terms
    assert _calibration_checks(res, omega, gc.covariance_analysis(P_OFF, t_end).final_std(),
                               b) == []
    big = dataclasses.replace(sim.record, angle_sensor=sim.record.angle_sensor + 20 * 0.485e-5)
    assert _calibration_checks(gc.calibrate(big, P), omega,
                               gc.covariance_analysis(P_OFF, t_end).final_std()) != []


def test_a_new_term_is_an_edit_of_the_model_only(monkeypatch):
    """A second angle-sensor-like constant declared only in the model (one more
    :class:`gyrolib.gc.InstrumentTerm` in ``gyrolib.gc.model.instrument.TERMS``, read half
    by the angle sensor, prior ``sigma_as_offset``) runs through the covariance analysis,
    the Monte Carlo and calibrate without a change to any kernel: the covariance matches
    the numpy reference with the two columns, the Monte Carlo's ω_gc errors its σ, and
    calibrate's σ(ω_gc) the covariance's, with the new constant in its result.  Power: the
    reference without the new column differs."""
    new = gc.InstrumentTerm("angle_offset_half", "sigma_as_offset", H0=(0.5, 0.0, 0.0),
                            unit="rad")
    monkeypatch.setattr(instrument, "TERMS", (*instrument.TERMS, new))
    names = (*gc.STATE_NAMES, "angle_offset", "angle_offset_half")
    assert gc.state_names(P_OFF) == names
    t_end = 1.0
    cov = gc.covariance_analysis(P_OFF, t_end)
    assert cov.names == names
    ref = reference_covariance(P_OFF, t_end, np.array([[1.0, 0.5], [0.0, 0.0], [0.0, 0.0]]),
                               np.zeros((3, 2)), [SIG_OFF, SIG_OFF], (t_end,))[t_end]
    one = reference_covariance(P_OFF, t_end, OFFSET_H0, ZERO_H, [SIG_OFF], (t_end,))[t_end]
    assert _rel(cov.final_std("omega_gc"), np.sqrt(ref[3, 3])) < 1e-6
    assert _rel(cov.final_std("angle_offset_half"), np.sqrt(ref[11, 11])) < 1e-6
    assert _rel(cov.final_std("omega_gc"), np.sqrt(one[3, 3])) > 1e-6     # power
    n = 128
    mc = gc.monte_carlo(P_OFF, n, t_end, seed=7, store_every=100)
    assert mc.names == names
    assert _mc_checks(mc, cov, n) == []
    assert np.std(mc.truth("angle_offset_half")[:, 0]) > 0.5 * SIG_OFF   # drawn
    sim = gc.simulate_record(P, t_end, 4)
    rec = dataclasses.replace(sim.record, angle_sensor=sim.record.angle_sensor
                              + 0.7 * SIG_OFF + 0.5 * (-0.4 * SIG_OFF))
    res = gc.calibrate(rec, P_OFF)
    assert res.bias_names[-1] == "angle_offset_half"
    assert set(res.instrument) == {"angle_offset", "angle_offset_half"}
    assert _calibration_checks(res, float(sim.truth[0, 3]), cov.final_std()) == []


def test_a_dynamics_column_in_the_covariance_and_refused_elsewhere(monkeypatch):
    """A declared term with a dynamics column (``Fb``: a second constant drift, entering
    Δβ'' as ω_gc does, H/I) is integrated by the covariance analysis's augmented Van Loan
    discretization: σ(ω_gc) and σ of the term match the numpy reference with the column to
    1e-6, and differ from the reference without it (power).  The Monte Carlo's truth and
    calibrate's bias separation do not take such a term: both refuse it by name."""
    fb = np.zeros(10)
    fb[1] = P.H / P.I
    new = gc.InstrumentTerm("drift_2", "sigma_as_offset", Fb=fb, unit="rad/s")
    monkeypatch.setattr(instrument, "TERMS", (*instrument.TERMS, new))
    # prior σ of the new drift = sigma_as_offset, here set to 0.05″/s (in rad/s)
    p = dataclasses.replace(P, sigma_as_offset=0.05 * 0.485e-5)
    cov = gc.covariance_analysis(p, 1.0)
    assert cov.names[10:] == ("angle_offset", "drift_2")
    h0 = np.array([[1.0, 0.0], [0.0, 0.0], [0.0, 0.0]])
    sig = [p.sigma_as_offset] * 2
    ref = reference_covariance(p, 1.0, h0, np.zeros((3, 2)), sig, (1.0,),
                               fb=np.stack([np.zeros(10), fb], axis=1))[1.0]
    assert _rel(cov.final_std("omega_gc"), np.sqrt(ref[3, 3])) < 1e-6
    assert _rel(cov.final_std("drift_2"), np.sqrt(ref[11, 11])) < 1e-6
    nofb = reference_covariance(p, 1.0, h0, np.zeros((3, 2)), sig, (1.0,))[1.0]
    assert _rel(cov.final_std("omega_gc"), np.sqrt(nofb[3, 3])) > 1e-2
    with pytest.raises(ValueError, match=r"^params: .*\(drift_2\)"):
        gc.monte_carlo(p, 2, 0.01, seed=1)
    sim = gc.simulate_record(P, 0.01, 1)
    with pytest.raises(ValueError, match=r"^params: calibrate carries.*\(drift_2\)"):
        gc.calibrate(sim.record, p)


def test_calibrate_and_covariance_share_the_model_with_every_term_on():
    """Every declared constant ON (the command's kind of priors): the covariance
    analysis carries them as states, calibrate by bias separation; on a clean record (no
    gate rejection) their σ of ω_gc and of each constant agree to 1e-6 (two algorithms, one
    model).  Power: without the scale term in the covariance analysis σ(ω_gc) differs."""
    p = dataclasses.replace(P, sigma_as_offset=SIG_OFF, sigma_incl_bias=0.5e-3 * 9.80665,
                            sigma_hf_scale=1e-3, sigma_clock=1e-4)
    t_end = 2.0
    cov = gc.covariance_analysis(p, t_end)
    assert cov.names[10:] == tuple(t.name for t in gc.TERMS)
    res = gc.calibrate(gc.simulate_record(P, t_end, 5).record, p)
    assert int(np.sum(res.rejected)) == 0
    assert _rel(res.omega_gc_std, cov.final_std("omega_gc")) < 1e-6
    for name, part in res.instrument.items():
        assert _rel(part["std"], cov.final_std(name)) < 1e-6, name
    noscale = gc.covariance_analysis(dataclasses.replace(p, sigma_hf_scale=0.0), t_end)
    assert _rel(res.omega_gc_std, noscale.final_std("omega_gc")) > 1e-3
