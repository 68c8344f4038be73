"""gyrolib.filtering: discretization against independent integrations, the Joseph update against
sequential scalar updates, and the fast covariance path against the plain-numpy reference."""

import numpy as np
import pytest
import scipy.linalg

from gyrolib import filtering
from gyrolib.gc import (
    GyrocompassParams,
    discretize,
    initial_covariance,
    noise_input_matrix,
    nominal_motion,
    process_noise_intensity,
    system_matrix,
)


def _rk4_cov(F_of_t, S, P, Phi, t0, t1, n_sub):
    """Fine-step RK4 of dP/dt = F P + P Fᵀ + S and dΦ/dt = F Φ (independent of Van Loan)."""
    h = (t1 - t0) / n_sub

    def rhs(t, P, Phi):
        F = F_of_t(t)
        return F @ P + P @ F.T + S, F @ Phi

    t = t0
    for _ in range(n_sub):
        k1 = rhs(t, P, Phi)
        k2 = rhs(t + h / 2, P + h / 2 * k1[0], Phi + h / 2 * k1[1])
        k3 = rhs(t + h / 2, P + h / 2 * k2[0], Phi + h / 2 * k2[1])
        k4 = rhs(t + h, P + h * k3[0], Phi + h * k3[1])
        P = P + h / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
        Phi = Phi + h / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
        t += h
    return P, Phi


def test_van_loan_matches_fine_step_covariance_ode_for_paper_gc():
    """Paper GC's F at β_n = 0.005 rad: Φ and Qd over Δt = 1 ms against RK4 with 2000
    sub-steps (RK4 error ~ (0.5 µs · 625/s)^4 ≈ 1e-11): agreement to 1e-9 relative."""
    p = GyrocompassParams()
    F = system_matrix(p, 0.005)
    G, Qc = noise_input_matrix(p), process_noise_intensity(p)
    Phi, Qd = filtering.van_loan(F, G, Qc, p.dt)
    Qi, Phii = _rk4_cov(lambda t: F, G @ Qc @ G.T, np.zeros((10, 10)), np.eye(10), 0.0, p.dt,
                        2000)
    scale = np.sqrt(np.outer(np.diag(Qd), np.diag(Qd))) + 1e-300
    assert np.max(np.abs(Qd - Qi) / scale) < 1e-9
    assert np.max(np.abs(Phi - Phii)) < 1e-9


def test_gc_discretization_over_a_time_varying_span_matches_covariance_ode():
    """30 steps (30 ms) from P0, no updates: the product of the affine per-step (Φ_k, Qd_k)
    against RK4 of the covariance ODE with F(β_n(t)) varying continuously (β_n from the
    independent Radau solution of Eq. (4)).  Tolerance 1e-8 relative to √(Pii Pjj)."""
    p = GyrocompassParams()
    n = 30
    disc = discretize(p, n * p.dt)
    P = initial_covariance(p)
    Pk = P.copy()
    for k in range(n):
        Pk = disc.model.phi(k) @ Pk @ disc.model.phi(k).T + disc.model.qd(k)
    tt = np.linspace(0.0, n * p.dt, 20 * n + 1)
    nm = nominal_motion(p, tt)

    def F_of_t(t):
        return system_matrix(p, float(np.interp(t, tt, nm.beta)))

    G, Qc = noise_input_matrix(p), process_noise_intensity(p)
    Pi, _ = _rk4_cov(F_of_t, G @ Qc @ G.T, P, np.eye(10), 0.0, n * p.dt, 20 * n)
    scale = np.sqrt(np.outer(np.diag(Pk), np.diag(Pk))) + 1e-300
    assert np.max(np.abs(Pk - Pi) / scale) < 1e-8


def test_affine_expansion_matches_per_step_matrix_exponential():
    """The first-order expansion in (sin β_n, cos β_n) against a full Van Loan exponential at
    the end of a 100 s run (β_n ≈ 0.0086 rad, farthest from its expansion point)."""
    p = GyrocompassParams()
    disc = discretize(p, 100.0)
    for k in (0, 1000, 37_000, disc.n_steps - 1):
        Phi_e, Qd_e = disc.exact_step(k)
        assert np.max(np.abs(disc.model.phi(k) - Phi_e)) < 1e-13
        scale = np.sqrt(np.outer(np.diag(Qd_e), np.diag(Qd_e))) + 1e-300
        assert np.max(np.abs(disc.model.qd(k) - Qd_e) / scale) < 1e-10


def test_van_loan_derivatives_match_finite_differences():
    """Exact derivatives of Φ and Qd (Fréchet) against central finite differences."""
    p = GyrocompassParams()
    F = system_matrix(p, 0.3)
    G, Qc = noise_input_matrix(p), process_noise_intensity(p)
    E = np.zeros((10, 10))
    E[1, 0], E[1, 2], E[1, 5] = -1.0, 1.0, 0.5
    _, _, (dPhi,), (dQd,) = filtering.van_loan_derivatives(F, G, Qc, p.dt, [E])
    eps = 1e-3
    Pp, Qp = filtering.van_loan(F + eps * E, G, Qc, p.dt)
    Pm, Qm = filtering.van_loan(F - eps * E, G, Qc, p.dt)
    assert np.allclose(dPhi, (Pp - Pm) / (2 * eps), rtol=1e-6, atol=1e-12)
    # dQd is ~1e-11 of Qd: the finite difference is limited by the rounding of Qd
    # (1e-16 |Qd| / eps ≈ 1e-13 |Qd| ≈ 1e-2 |dQd| at worst): compare to 1e-4 of max |dQd|
    scale = np.max(np.abs(dQd))
    assert np.max(np.abs(dQd - (Qp - Qm) / (2 * eps))) < 1e-4 * scale


def test_joseph_and_sequential_updates_agree():
    """Joseph batch update, sequential scalar updates and the information form agree."""
    rng = np.random.default_rng(4)
    n, m = 10, 3
    A = rng.standard_normal((n, n))
    P = A @ A.T + 0.1 * np.eye(n)
    H = rng.standard_normal((m, n))
    R = np.diag([0.3, 2.0, 0.01])
    x = rng.standard_normal(n)
    z = rng.standard_normal(m)
    xj, Pj, _ = filtering.joseph_update(x, P, z, H, R)
    xs, Ps = filtering.sequential_update(x, P, z, H, R)
    assert np.allclose(xj, xs, rtol=1e-12, atol=1e-12)
    assert np.allclose(Pj, Ps, rtol=1e-10, atol=1e-12)
    # independent closed form: information form P⁺ = (P⁻¹ + Hᵀ R⁻¹ H)⁻¹
    Pinf = np.linalg.inv(np.linalg.inv(P) + H.T @ np.linalg.inv(R) @ H)
    assert np.allclose(Pj, Pinf, rtol=1e-9, atol=1e-12)


def test_joseph_is_symmetric_psd_for_a_suboptimal_gain_via_fixed_gain_path():
    """The fixed-gain propagation with the optimal gains reproduces the optimal covariance."""
    p = GyrocompassParams()
    disc = discretize(p, 0.5)
    P0 = initial_covariance(p)
    opt = filtering.covariance_fast(disc.model, P0, 1, keep_gains=True)
    fix = filtering.propagate_fixed_gains(disc.model, P0, opt.gains, disc.model.r,
                                       (disc.model.Qd0, disc.model.QdA, disc.model.QdB))
    assert np.allclose(fix.var, opt.var, rtol=1e-9, atol=0.0)


def test_fast_and_reference_covariance_paths_agree_to_1e_9():
    """Same affine model, fast (numba, sequential scalar Joseph, sparse Φ) against reference
    (numpy, batch Joseph): every variance of every state over 2 s, 1e-9 relative."""
    p = GyrocompassParams()
    disc = discretize(p, 2.0)
    P0 = initial_covariance(p)
    fast = filtering.covariance_fast(disc.model, P0, 100)
    ref = filtering.covariance_reference(disc.model, P0, 100)
    nz = ref.var > 0
    assert np.max(np.abs(fast.var[nz] / ref.var[nz] - 1.0)) < 1e-9
    assert np.all(fast.var[~nz] == 0.0)
    assert np.allclose(fast.P_stored, ref.P_stored, rtol=1e-8, atol=0.0)


def test_sized_and_general_covariance_kernels_agree():
    """covariance_fast runs a kernel compiled for the model's state size (its loops unroll);
    the kernel that reads the size from the arrays (states beyond 32) gives the same variances
    and gains over 2 s of paper GC to 1e-12 relative, with and without fixed gains."""
    from gyrolib.filtering import covariance as fcov

    p = GyrocompassParams()
    m = discretize(p, 2.0).model
    P0 = initial_covariance(p)
    sized = filtering.covariance_fast(m, P0, 100, keep_gains=True)
    rowptr, colidx = m.sparsity()
    hptr, hidx = m.measurement_sparsity()
    var = np.empty((m.n_steps + 1, m.n))
    P_st = np.empty((m.n_steps // 100 + 1, m.n, m.n))
    gains = np.empty((m.n_steps, m.H.shape[0], m.n))
    fcov._predict_joseph_kernel(m.seg, m.a, m.b, m.Phi0, m.PhiA, m.PhiB, m.Qd0, m.QdA, m.QdB,
                                rowptr, colidx, hptr, hidx, m.H, np.zeros_like(m.H),
                                np.zeros(1), False, m.r, P0, 100, var, P_st, gains, False)
    nz = var > 0
    assert np.max(np.abs(sized.var[nz] / var[nz] - 1.0)) < 1e-12
    np.testing.assert_allclose(sized.gains, gains, rtol=1e-12, atol=1e-300)
    np.testing.assert_allclose(sized.P_stored, P_st, rtol=1e-12, atol=1e-300)
    # power: sensor noise larger by 1e-9 relative moves the variances beyond the tolerance
    var2 = np.empty_like(var)
    fcov._predict_joseph_kernel(m.seg, m.a, m.b, m.Phi0, m.PhiA, m.PhiB, m.Qd0, m.QdA, m.QdB,
                                rowptr, colidx, hptr, hidx, m.H, np.zeros_like(m.H),
                                np.zeros(1), False, m.r * (1.0 + 1e-9), P0, 100,
                                var2, P_st.copy(), gains.copy(), False)
    assert np.max(np.abs(sized.var[nz] / var2[nz] - 1.0)) > 1e-12


def test_psd_factor_reproduces_gc_process_noise():
    """The covariance factor of paper GC's Qd (entries decades apart) gives L Lᵀ = Qd."""
    p = GyrocompassParams()
    disc = discretize(p, 0.01)
    Qd = disc.model.Qd0[0]
    L = filtering.covariance_factor(Qd)
    scale = np.sqrt(np.outer(np.diag(Qd), np.diag(Qd))) + 1e-300
    assert np.max(np.abs(L @ L.T - Qd) / scale) < 1e-10


def test_van_loan_for_a_scalar_closed_form():
    """x' = −a x + w: Φ = e^{−a dt}, Qd = q (1 − e^{−2 a dt}) / (2 a)."""
    a, q, dt = 3.0, 0.7, 0.2
    Phi, Qd = filtering.van_loan([[-a]], [[1.0]], [[q]], dt)
    assert Phi[0, 0] == pytest.approx(np.exp(-a * dt), rel=1e-14)
    assert Qd[0, 0] == pytest.approx(q * (1 - np.exp(-2 * a * dt)) / (2 * a), rel=1e-12)
    assert np.allclose(scipy.linalg.expm(np.array([[-a * dt]])), Phi)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"F": np.ones((2, 3))}, "F must be square"),
        ({"dt": 0.0}, "dt must be > 0"),
        ({"G": np.ones((3, 1))}, "G must have shape"),
    ],
)
def test_van_loan_validates(kwargs, match):
    """Bad F, G, Qc, dt are rejected by name."""
    args = {"F": -np.eye(2), "G": np.ones((2, 1)), "Qc": np.eye(1), "dt": 0.1} | kwargs
    with pytest.raises(ValueError, match=match):
        filtering.van_loan(**args)


def test_updates_validate_shapes():
    """Measurement updates reject mismatched shapes by name."""
    with pytest.raises(ValueError, match="z must have shape"):
        filtering.joseph_update(np.zeros(2), np.eye(2), np.zeros(2), np.ones((1, 2)), np.eye(1))
    with pytest.raises(ValueError, match="R must be diagonal"):
        filtering.sequential_update(np.zeros(2), np.eye(2), np.zeros(2), np.eye(2),
                                 np.ones((2, 2)))


def test_chi2_quantile_without_scipy_stats_matches_it():
    """filtering.consistency.chi2_ppf (scipy.special, so that the command line need not
    import scipy.stats) against scipy.stats.chi2.ppf, at the gate and band probabilities and
    the degrees of freedom of a calibration (1 to 3.6e6)."""
    import scipy.stats

    from gyrolib.filtering.consistency import chi2_ppf

    for q in (0.005, 0.025, 0.5, 0.975, 0.995, 0.9999, 1 - 1e-9):
        for dof in (1, 3, 10, 99000, 3.6e6, np.array([1.0, 97995.0, 3599632.0])):
            np.testing.assert_allclose(chi2_ppf(q, dof), scipy.stats.chi2.ppf(q, dof),
                                       rtol=1e-13)
    assert abs(chi2_ppf(0.9999, 1) - 3.8906**2) < 1e-3   # the 99.99 % gate: |nu| < 3.89 sigma
