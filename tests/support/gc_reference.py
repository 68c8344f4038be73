"""An independent implementation of paper GC's covariance analysis (Figure 3), for tests.

Written from the paper's matrices as printed and transcribed (paper GC's
Eqs. (4)-(8) and the parameter list), with plain numpy/scipy.  It imports nothing from
gyrolib's model or filter: only the numbers of ``GyrocompassParams``' defaults are read.

* F, G, D of Eq. (8) in the order X1 = Δβ, X2 = Δβ' (the order F and D need), F(8,7) = −α1²
  (Eq. (6)), and the vertical-rate coupling of Eq. (5) (γ with cos β_n, δ with −sin β_n);
* the nominal motion Eq. (4) from rest by ``scipy.integrate.solve_ivp`` (DOP853, tight
  tolerance), F frozen at each step's midpoint;
* Φ and Qd by ``scipy.linalg.expm`` of Van Loan's block matrix, one exponential per step;
* P(0): the paper's σ of ψ, ω_gc, δ, γ, zero for Δβ, Δβ', and for N1…N4 either zero or
  their stationary covariance (``scipy.linalg.solve_continuous_lyapunov``);
* R = C/Δt; the Joseph-form update after every prediction, measurements at t_k = kΔt, k ≥ 1.

``wrong`` switches in one deliberate error, to show that a comparison against this reference
can fail: ``"f87_printed"`` (F(8,7) = +α1² as printed) or ``"r_equals_c"`` (R = C).
"""

from __future__ import annotations

import functools

import numpy as np
import scipy.integrate
import scipy.linalg

N = 10
ARCSEC = 0.485e-5  # the paper's arcsecond (rad)


def _matrices(p, wrong):
    a1, x1, a2, x2 = p.alpha1, p.xi1, p.alpha2, p.xi2
    F0 = np.zeros((N, N))            # the constant part of F
    F0[0, 1] = 1.0                   # F(1,2)
    F0[1, 1] = -p.f / p.I            # F(2,2)
    F0[1, 3] = p.H / p.I             # F(2,4)
    F0[1, 6] = p.H * p.omega_ub / (p.I * p.g)   # F(2,7)
    F0[1, 8] = p.H / p.I             # F(2,9)
    F0[6, 7] = 1.0                   # F(7,8)
    F0[7, 6] = (a1**2) if wrong == "f87_printed" else -(a1**2)   # F(8,7)
    F0[7, 7] = -2.0 * x1 * a1        # F(8,8)
    F0[8, 9] = 1.0                   # F(9,10)
    F0[9, 8] = -(a2**2)              # F(10,9)
    F0[9, 9] = -2.0 * x2 * a2        # F(10,10)
    Fs = np.zeros((N, N))            # the part multiplying sin β_n
    Fs[1, 0] = -p.H * p.Omega_h / p.I
    Fs[1, 2] = p.H * p.Omega_h / p.I
    Fs[1, 4] = -p.H * p.Omega_v / p.I
    Fc = np.zeros((N, N))            # the part multiplying cos β_n
    Fc[1, 5] = p.H * p.Omega_v / p.I
    G = np.zeros((N, 2))
    G[6, 0] = 1.0
    G[7, 0] = a1 - 2.0 * x1 * a1
    G[9, 1] = 1.0
    D = np.zeros((3, N))
    D[0, 0] = 1.0
    D[1, 4] = p.g
    D[1, 6] = 1.0
    D[2, 5] = p.g
    D[2, 6] = 1.0
    Q = np.diag([2.0 * x1 * a1 * p.sigma1_sq, 4.0 * x2 * a2**3 * p.sigma2_sq])
    C = np.diag([p.C_as, p.C_incl_y, p.C_incl_z])
    R = C if wrong == "r_equals_c" else C / p.dt
    return F0, Fs, Fc, G, D, Q, R


def _p0(p, F0, G, Q, shaping_p0):
    P0 = np.zeros((N, N))
    for i, s in ((2, p.sigma_psi0), (3, p.sigma_gc0), (4, p.sigma_delta0),
                 (5, p.sigma_gamma0)):
        P0[i, i] = s**2
    if shaping_p0 == "stationary":
        for sl in (slice(6, 8), slice(8, 10)):
            A = F0[sl, sl]
            BQB = G[sl] @ Q @ G[sl].T
            P0[sl, sl] = scipy.linalg.solve_continuous_lyapunov(A, -BQB)
    return P0


def _nominal_mid(p, n_steps):
    """β_n (Eq. (4), from rest) at the step midpoints (k + 1/2) Δt."""
    k_rate = p.H * p.Omega_h / p.I

    def rhs(t, y):
        return [y[1], -p.f / p.I * y[1] + k_rate * np.cos(y[0])]

    t_mid = (np.arange(n_steps) + 0.5) * p.dt
    sol = scipy.integrate.solve_ivp(rhs, (0.0, n_steps * p.dt), [0.0, 0.0], method="DOP853",
                                    t_eval=t_mid, rtol=1e-12, atol=1e-16)
    return sol.y[0]


def sigma_gc_reference(p, times, shaping_p0=("zero", "stationary"), wrong=None,
                       chunk=2000):
    """σ of ω_gc (rad/s) after the update at each of ``times`` (s, multiples of ``p.dt``).

    Returns an array (len(shaping_p0), len(times)); the P0 readings run side by side on the
    same discrete model.
    """
    F0, Fs, Fc, G, D, Q, R = _matrices(p, wrong)
    steps = [round(t / p.dt) for t in times]
    n_steps = max(steps)
    beta = _nominal_mid(p, n_steps)
    P = np.array([_p0(p, F0, G, Q, s) for s in shaping_p0])
    GQG = G @ Q @ G.T
    eye = np.eye(N)
    out = np.empty((len(shaping_p0), len(times)))
    want = {k: i for i, k in enumerate(steps)}
    for start in range(0, n_steps, chunk):
        b = beta[start:start + chunk]
        F = F0 + np.sin(b)[:, None, None] * Fs + np.cos(b)[:, None, None] * Fc
        M = np.zeros((b.size, 2 * N, 2 * N))   # Van Loan: [[-F, GQGᵀ], [0, Fᵀ]] Δt
        M[:, :N, :N] = -F * p.dt
        M[:, :N, N:] = GQG * p.dt
        M[:, N:, N:] = np.swapaxes(F, 1, 2) * p.dt
        E = scipy.linalg.expm(M)
        Phi = np.swapaxes(E[:, N:, N:], 1, 2)
        Qd = Phi @ E[:, :N, N:]
        for j in range(b.size):
            P = Phi[j] @ P @ Phi[j].T + Qd[j]
            S = D @ P @ D.T + R
            K = np.swapaxes(np.linalg.solve(S, D @ P), 1, 2)   # P Dᵀ S⁻¹ (S, P symmetric)
            A = eye - K @ D
            P = A @ P @ np.swapaxes(A, 1, 2) + K @ R @ np.swapaxes(K, 1, 2)
            k = start + j + 1
            if k in want:
                out[:, want[k]] = np.sqrt(P[:, 3, 3])
    return out


#: Times (s) at which the tests compare σ_gc, and the two readings of P0 of N1…N4.
TIMES = (1.0, 2.0, 10.0, 50.0, 100.0)
READINGS = ("zero", "stationary")


@functools.cache
def reference_sigma_gc(wrong=None, t_end=100.0):
    """σ of ω_gc (rad/s) at the :data:`TIMES` up to ``t_end``, both :data:`READINGS`,
    for the default ``GyrocompassParams`` (computed once per process, and the right one once
    per test session, ``conftest.session_memo``: ~30–60 s for 100 s)."""
    from gyrolib.gc.model.params import GyrocompassParams  # the paper's numbers only

    times = tuple(t for t in TIMES if t <= t_end)
    if wrong is not None:
        return times, sigma_gc_reference(GyrocompassParams(), times, READINGS, wrong=wrong)
    # the right reference is read by two test files, maybe in two workers: once a session
    from tests.conftest import session_memo

    return times, session_memo(f"gc_reference_{t_end!r}", lambda: sigma_gc_reference(
        GyrocompassParams(), times, READINGS))
