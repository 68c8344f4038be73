"""Paper GC, the estimator: covariance analysis (Figure 3), Monte Carlo runs of the truth model
and the filter (Figure 4), an error budget, and the computations behind the paper's claims.

The model is :mod:`gyrolib.gyrocompass` (paper GC, Eq. (8)), discretized at ``Δt`` (1 ms) with
``F`` frozen at the nominal float angle of each step's midpoint, ``β_n(t_k + Δt/2)``: exact
transition and process noise by Van Loan's method {cite:p}`VanLoan1978`, expanded to first
order in ``(sin β_n, cos β_n)`` about expansion points ``SEGMENT`` rad apart
(:class:`gyrolib.kalman.AffineDiscreteModel`; error ≈ 10⁻¹³, tested against a per-step
matrix exponential).  The nominal motion Eq. (4) is integrated on the half-step grid by a
second-order exponential integrator (tested against :func:`gyrolib.gyrocompass.nominal_motion`).

Measurements ``z_k = D x(t_k) + v_k`` at ``t_k = k Δt``, ``k ≥ 1``; the filter starts from
``x̂(0) = 0``, ``P(0)`` = :func:`gyrolib.gyrocompass.initial_covariance`.

The truth model is the nonlinear Eq. (3) with the shaping filters (6), (7): its linear part
(everything ``F`` holds, including the shaping filters driven by exactly discretized white
noise) is propagated exactly, and the nonlinear remainder of the gyroscopic and vertical-rate
torques (of order 10⁻⁵ of the signal) by the exponential midpoint rule.
"""

from __future__ import annotations

import math
import os
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, replace
from typing import Final

import numpy as np
import scipy.linalg
import scipy.stats
from numba import njit

from gyrolib import _validation as v
from gyrolib import kalman
from gyrolib.gyrocompass import (
    STATE_NAMES,
    GyrocompassParams,
    initial_covariance,
    measurement_matrix,
    measurement_noise_covariance,
    noise_input_matrix,
    process_noise_intensity,
    state_index,
    system_matrix,
)

__all__ = [
    "BUDGET_SOURCES",
    "SEGMENT",
    "CovarianceAnalysis",
    "ErrorBudget",
    "GCDiscretization",
    "InformationPsiOmega",
    "MonteCarloResult",
    "covariance_analysis",
    "discretize",
    "error_budget",
    "information_psi_omega",
    "monte_carlo",
    "nees_bounds",
    "nominal_half_steps",
    "simulate_truth",
    "sweep_sigma_gc",
    "time_to_sigma",
]

#: Spacing (rad) of the β_n expansion points of the affine discretization.
SEGMENT: Final[float] = 0.01
N: Final[int] = len(STATE_NAMES)


def _check_params(params: object) -> GyrocompassParams:
    return v.check_instance("params", params, GyrocompassParams)


def _n_steps(params: GyrocompassParams, t_end: object) -> int:
    t_end = v.check_positive("t_end", t_end)
    n = round(t_end / params.dt)
    if n < 1 or abs(n * params.dt - t_end) > 1e-9 * max(t_end, 1.0):
        raise ValueError(f"t_end must be a positive multiple of dt={params.dt}; got {t_end}")
    return n


# Nominal motion on the half-step grid --------------------------------------------------------
@njit(cache=True)
def _etd2_kernel(E, p1, p2, kdd, n_half, out):
    y0 = 0.0
    y1 = 0.0
    out[0] = 0.0
    for i in range(n_half):
        u0 = kdd * math.cos(y0)
        a0 = E[0, 0] * y0 + E[0, 1] * y1 + p1[0] * u0
        a1 = E[1, 0] * y0 + E[1, 1] * y1 + p1[1] * u0
        du = kdd * math.cos(a0) - u0
        y0 = a0 + p2[0] * du
        y1 = a1 + p2[1] * du
        out[i + 1] = y0


def nominal_half_steps(params: GyrocompassParams, n_steps: int) -> np.ndarray:
    """Nominal float angle ``β_n`` (rad), Eq. (4) from rest, at ``t = i Δt/2``,
    ``i = 0 … 2 n_steps``.

    Exponential time differencing (ETD2RK, Cox–Matthews): the stiff linear part
    ``β'' = −(f/I) β'`` is exact, the slowly varying torque ``H Ω_h cos β / I`` is
    interpolated linearly over each half step.
    """
    p = _check_params(params)
    n_steps = v.check_int("n_steps", n_steps, 1)
    h = 0.5 * p.dt
    M = np.zeros((4, 4))
    M[0, 1] = h
    M[1, 1] = -p.f / p.I * h
    M[1, 2] = h
    M[2, 3] = 1.0
    Ex = scipy.linalg.expm(M)
    out = np.empty(2 * n_steps + 1)
    _etd2_kernel(Ex[:2, :2].copy(), Ex[:2, 2].copy(), Ex[:2, 3].copy(),
                 p.H * p.Omega_h / p.I, 2 * n_steps, out)
    return out


# Discretization ------------------------------------------------------------------------------
def _affine_parts(p: GyrocompassParams) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``F(β) = F_0 + sin β · E_s + cos β · E_c`` (exact: F is affine in sin and cos)."""
    F0, F90, F180 = (system_matrix(p, b) for b in (0.0, 0.5 * np.pi, np.pi))
    Ec = 0.5 * (F0 - F180)
    Fc = 0.5 * (F0 + F180)
    Es = F90 - Fc
    # sin(π) and cos(π/2) are ~1e-16, not 0: clean the rounding
    for A in (Ec, Fc, Es):
        A[np.abs(A) < 1e-12 * np.max(np.abs(F0))] = 0.0
    return Fc, Es, Ec


def _affine_qd(p: GyrocompassParams, betas: np.ndarray, Qc: np.ndarray) -> tuple:
    Fc, Es, Ec = _affine_parts(p)
    G = noise_input_matrix(p)
    J = betas.size
    out = [np.zeros((J, N, N)) for _ in range(6)]
    for j, b in enumerate(betas):
        F = Fc + np.sin(b) * Es + np.cos(b) * Ec
        Phi, Qd, (dPs, dPc), (dQs, dQc) = kalman.van_loan_derivatives(F, G, Qc, p.dt, [Es, Ec])
        for arr, val in zip(out, (Phi, dPs, dPc, Qd, dQs, dQc)):
            arr[j] = val
    return tuple(out)


@dataclass(frozen=True)
class GCDiscretization:
    """Paper GC discretized over ``n_steps`` steps of ``params.dt``.

    ``beta_half`` is ``β_n`` at ``t = i Δt/2``; ``betas`` the expansion points; ``model`` the
    affine discrete model; ``Gamma[j]`` the response over one step to a unit constant
    acceleration on ``Δβ''`` (for the nonlinear remainder); ``noise_factor[j]`` (n × n_w) a
    factor of ``Qd`` at expansion point ``j`` for drawing the process noise.
    """

    params: GyrocompassParams
    n_steps: int
    beta_half: np.ndarray
    betas: np.ndarray
    model: kalman.AffineDiscreteModel
    Gamma: np.ndarray
    noise_factor: np.ndarray

    def __post_init__(self) -> None:
        _check_params(self.params)
        n = v.check_int("n_steps", self.n_steps, 1)
        v.check_ndarray("beta_half", self.beta_half, shape=(2 * n + 1,))
        J = v.check_ndarray("betas", self.betas, ndim=1).size
        v.check_instance("model", self.model, kalman.AffineDiscreteModel)
        v.check_ndarray("Gamma", self.Gamma, shape=(J, N))
        v.check_ndarray("noise_factor", self.noise_factor, shape=(J, N, None))

    @property
    def t(self) -> np.ndarray:
        return np.arange(self.n_steps + 1) * self.params.dt

    @property
    def beta_mid(self) -> np.ndarray:
        return self.beta_half[1::2]

    def exact_step(self, k: int) -> tuple[np.ndarray, np.ndarray]:
        """``(Φ_k, Qd_k)`` by a full Van Loan matrix exponential at ``β_n`` of the midpoint
        of step ``k`` (the reference the affine model is tested against)."""
        k = v.check_int("k", k, 0)
        if k >= self.n_steps:
            raise ValueError(f"k must be a step index in [0, {self.n_steps}); got {k}")
        p = self.params
        F = system_matrix(p, float(self.beta_mid[k]))
        return kalman.van_loan(F, noise_input_matrix(p), process_noise_intensity(p), p.dt)


def discretize(params: GyrocompassParams, t_end: float = 100.0) -> GCDiscretization:
    """Discretize paper GC, Eq. (8), over ``[0, t_end]`` at ``params.dt``."""
    p = _check_params(params)
    n_steps = _n_steps(p, t_end)
    beta_half = nominal_half_steps(p, n_steps)
    bm = beta_half[1::2]
    idx = np.rint(bm / SEGMENT).astype(np.int64)
    uniq, seg = np.unique(idx, return_inverse=True)
    betas = uniq * SEGMENT
    Phi0, PhiA, PhiB, Qd0, QdA, QdB = _affine_qd(p, betas, process_noise_intensity(p))
    R = measurement_noise_covariance(p)
    model = kalman.AffineDiscreteModel(
        seg=seg.astype(np.int64).ravel(), a=np.sin(bm) - np.sin(betas)[seg].ravel(),
        b=np.cos(bm) - np.cos(betas)[seg].ravel(), Phi0=Phi0, PhiA=PhiA, PhiB=PhiB,
        Qd0=Qd0, QdA=QdA, QdB=QdB, H=measurement_matrix(p), r=np.diag(R).copy())
    Fc, Es, Ec = _affine_parts(p)
    Gamma = np.zeros((betas.size, N))
    factors = []
    for j, b in enumerate(betas):
        F = Fc + np.sin(b) * Es + np.cos(b) * Ec
        M = np.zeros((N + 1, N + 1))
        M[:N, :N] = F * p.dt
        M[1, N] = p.dt
        Gamma[j] = scipy.linalg.expm(M)[:N, N]
        factors.append(kalman.psd_factor(Qd0[j]))
    nz = np.any(np.abs(np.array(factors)) > 0, axis=(0, 1))
    noise_factor = np.ascontiguousarray(np.array(factors)[:, :, nz])
    return GCDiscretization(params=p, n_steps=n_steps, beta_half=beta_half, betas=betas,
                            model=model, Gamma=Gamma, noise_factor=noise_factor)


# Covariance analysis (Figure 3) ------------------------------------------------------------
@dataclass(frozen=True)
class CovarianceAnalysis:
    """Posterior covariance of the filter: variances at every step, full ``P`` at
    ``t_stored``.  ``std(name)`` is in SI units (rad, rad/s, m/s², m/s³, rad/s²)."""

    params: GyrocompassParams
    t: np.ndarray
    var: np.ndarray
    t_stored: np.ndarray
    P_stored: np.ndarray

    def __post_init__(self) -> None:
        _check_params(self.params)
        nt = v.check_ndarray("t", self.t, ndim=1).size
        v.check_ndarray("var", self.var, shape=(nt, N))
        ns = v.check_ndarray("t_stored", self.t_stored, ndim=1).size
        v.check_ndarray("P_stored", self.P_stored, shape=(ns, N, N))

    def std(self, name: str) -> np.ndarray:
        return np.sqrt(np.clip(self.var[:, state_index(name)], 0.0, None))

    def std_at(self, name: str, time: float) -> float:
        """Standard deviation at the step nearest to ``time`` (s)."""
        time = v.check_in_range("time", time, 0.0, float(self.t[-1]))
        return float(self.std(name)[round(time / self.params.dt)])


def _check_psd(name: str, P: np.ndarray) -> None:
    """``P`` (symmetric, diagonal >= 0) positive semi-definite, judged on its correlation
    form so that variances many orders of magnitude apart are treated alike."""
    d = np.sqrt(np.diag(P))
    nz = d > 0.0
    if np.any(P[~nz] != 0.0):
        raise ValueError(f"{name} must be positive semi-definite (a zero variance needs a "
                         "zero row)")
    if np.any(nz):
        C = P[np.ix_(nz, nz)] / np.outer(d[nz], d[nz])
        if np.linalg.eigvalsh(0.5 * (C + C.T))[0] < -1e-9:
            raise ValueError(f"{name} must be positive semi-definite (a covariance)")


def _default_store_every(n_steps: int) -> int:
    return max(1, n_steps // 1000)


def covariance_analysis(params: GyrocompassParams, t_end: float = 100.0, *,
                        store_every: int | None = None, method: str = "fast",
                        P0: object | None = None) -> CovarianceAnalysis:
    """Covariance analysis of the discrete Kalman filter of paper GC (Figure 3).

    ``method="fast"``: numba kernel on the affine discretization; ``"reference"``: plain
    numpy with an exact per-step Van Loan exponential and batch Joseph updates (slow: for
    tests and benchmarks).  ``store_every`` (default: about 1000 stored ``P``) sets the
    decimation of the full covariances.  ``P0`` (10×10, symmetric) overrides
    :func:`gyrolib.gyrocompass.initial_covariance` (e.g. to study a partly known N1…N4).
    """
    p = _check_params(params)
    v.check_choice("method", method, ("fast", "reference"))
    disc = discretize(p, t_end)
    se = _default_store_every(disc.n_steps) if store_every is None else store_every
    se = v.check_int("store_every", se, 1)
    if P0 is None:
        P0 = initial_covariance(p)
    else:
        P0 = v.check_array("P0", P0, shape=(N, N))
        if not np.allclose(P0, P0.T, rtol=1e-12, atol=0.0) or np.any(np.diag(P0) < 0):
            raise ValueError("P0 must be symmetric with a non-negative diagonal")
        _check_psd("P0", P0)
    if method == "fast":
        run = kalman.covariance_fast(disc.model, P0, se)
    else:
        run = kalman.covariance_reference(
            None, P0, se, step_matrices=disc.exact_step, n_steps=disc.n_steps,
            H=disc.model.H, R=np.diag(disc.model.r))
    t = disc.t
    return CovarianceAnalysis(params=p, t=t, var=run.var, t_stored=t[::se].copy(),
                              P_stored=run.P_stored)


def time_to_sigma(result: CovarianceAnalysis, name: str, level: float) -> float:
    """First time (s) at which ``std(name)`` falls to ``level`` (SI) and stays below it;
    ``nan`` if not reached within the analysed span."""
    if not isinstance(result, CovarianceAnalysis):
        raise TypeError("result must be a CovarianceAnalysis")
    level = v.check_positive("level", level)
    s = result.std(name)
    above = np.nonzero(s > level)[0]
    if above.size == 0:
        return 0.0
    last = above[-1]
    if last == s.size - 1:
        return float("nan")
    # linear interpolation between the last step above and the first below
    t0, t1, s0, s1 = result.t[last], result.t[last + 1], s[last], s[last + 1]
    return float(t0 + (s0 - level) / (s0 - s1) * (t1 - t0))


def sweep_sigma_gc(params: GyrocompassParams, field: str, values: object,
                   t_end: float = 100.0) -> np.ndarray:
    """``σ_gc(t_end)`` (rad/s) with ``params.<field>`` set to each of ``values``."""
    p = _check_params(params)
    v.check_str("field", field)
    if field not in GyrocompassParams.__dataclass_fields__:
        raise ValueError(f"field must be a GyrocompassParams field; got {field!r}")
    vals = v.check_array("values", values, ndim=1)
    out = np.empty(vals.size)
    for i, x in enumerate(vals):
        res = covariance_analysis(replace(p, **{field: float(x)}), t_end, store_every=10**9)
        out[i] = res.std("omega_gc")[-1]
    return out


# Truth model and Monte Carlo (Figure 4) -----------------------------------------------------
@njit(cache=True, fastmath=True)
def _cm1(x):
    """``cos x − 1`` without cancellation (series below 0.05: error < 1e-19 relative)."""
    if abs(x) < 0.05:
        x2 = x * x
        return x2 * (-0.5 + x2 * (1.0 / 24.0 + x2 * (-1.0 / 720.0 + x2 / 40320.0)))
    h = math.sin(0.5 * x)
    return -2.0 * h * h


@njit(cache=True, fastmath=True)
def _sin_minus_x(x):
    """``sin x − x`` without cancellation (series below 0.05: error < 1e-19 relative)."""
    if abs(x) < 0.05:
        x2 = x * x
        return x * x2 * (-1.0 / 6.0 + x2 * (1.0 / 120.0 + x2 * (-1.0 / 5040.0
                                                                  + x2 / 362880.0)))
    return math.sin(x) - x


@njit(cache=True, fastmath=True)
def _remainder(db, psi, de, ga, sn, cn, kh, kv, printed):
    """Nonlinear remainder of paper GC's Eq. (3) torques per unit ``I`` (rad/s²) beyond the
    linear terms of ``F``: gyroscopic ``kh[cos(β_n+Δβ−ψ) − cos β_n + sin β_n (Δβ−ψ)]`` and
    vertical ``kv[γ(cos β − cos β_n) − δ(sin β − sin β_n)]`` (``β = β_n + Δβ``)."""
    u = db - psi
    rho = kh * (cn * _cm1(u) - sn * _sin_minus_x(u))
    cd = _cm1(db)
    sd = _sin_minus_x(db) + db
    rho += kv * (ga * (cn * cd - sn * sd) - de * (sn * cd + cn * sd))
    if printed:  # F holds the printed listing instead of Eq. (5): add the difference
        rho += kv * ((-sn * de + cn * ga) - (-cn * de + sn * ga))
    return rho


@njit(cache=True)
def _step_phi(seg, a, b, Phi0, PhiA, PhiB, rowptr, colidx, out):
    """Nonzeros of ``Φ_k`` for every step (shared by all runs)."""
    for k in range(seg.shape[0]):
        j = seg[k]
        for i in range(rowptr.shape[0] - 1):
            for p in range(rowptr[i], rowptr[i + 1]):
                c = colidx[p]
                out[k, p] = Phi0[j, i, c] + a[k] * PhiA[j, i, c] + b[k] * PhiB[j, i, c]


@njit(cache=True, nogil=True, fastmath=True)
def _mc_block_kernel(k0, phis, seg, rowptr, colidx, Gam, Lf, lrows, hptr, hidx, H, sr, gains,
                     sin_mid, cos_mid, dt, kh, kv, printed, noise, x, xh, y, rho,
                     store_every, est, tru, run0, run_filter):
    """Truth and filter for one block of ``B`` runs (``x``, ``xh``: n×B, updated in place)
    over the steps ``k0 … k0 + len(noise) − 1``; the inner loops run over the runs of the
    block (SIMD).  Releases the GIL: blocks run in parallel threads."""
    n, B = x.shape
    n_runs = est.shape[0]
    m = H.shape[0]
    nw = Lf.shape[2]
    for kk in range(noise.shape[0]):
        k = k0 + kk
        j = seg[k]
        for r in range(B):
            rho[r] = _remainder(x[0, r] + 0.5 * dt * x[1, r], x[2, r], x[4, r], x[5, r],
                                sin_mid[k], cos_mid[k], kh, kv, printed)
        for i in range(n):
            g = Gam[j, i]
            for r in range(B):
                y[i, r] = g * rho[r]
            for p in range(rowptr[i], rowptr[i + 1]):
                f = phis[k, p]
                c = colidx[p]
                for r in range(B):
                    y[i, r] += f * x[c, r]
        for ir in range(lrows.shape[0]):  # only the rows that receive process noise
            i = lrows[ir]
            for w in range(nw):
                f = Lf[j, i, w]
                for r in range(B):
                    y[i, r] += f * noise[kk, w, r]
        for i in range(n):
            for r in range(B):
                x[i, r] = y[i, r]
        if run_filter:
            for i in range(n):
                for r in range(B):
                    y[i, r] = 0.0
                for p in range(rowptr[i], rowptr[i + 1]):
                    f = phis[k, p]
                    c = colidx[p]
                    for r in range(B):
                        y[i, r] += f * xh[c, r]
            for i in range(n):
                for r in range(B):
                    xh[i, r] = y[i, r]
            for q in range(m):
                s = sr[q]
                for r in range(B):
                    rho[r] = s * noise[kk, nw + q, r]
                for p in range(hptr[q], hptr[q + 1]):
                    c = hidx[p]
                    h = H[q, c]
                    for r in range(B):
                        rho[r] += h * (x[c, r] - xh[c, r])
                for i in range(n):
                    g = gains[k, q, i]
                    for r in range(B):
                        xh[i, r] += g * rho[r]
        if (k + 1) % store_every == 0:
            ii = (k + 1) // store_every
            for r in range(B):
                run = run0 + r
                if run < n_runs:
                    for i in range(n):
                        est[run, ii, i] = xh[i, r]
                        tru[run, ii, i] = x[i, r]


#: Steps per block of random numbers (500 steps × 9 × 32 runs: about 1 MB, cache-resident).
_CHUNK: Final[int] = 500
#: Runs per block: the unit of SIMD, of threading and of random-number streams.
_RUN_BLOCK: Final[int] = 32


def _block_rngs(rng: np.random.Generator, n_runs: int) -> list[np.random.Generator]:
    """One child generator per block of ``_RUN_BLOCK`` runs: run ``i`` gets the same numbers
    whatever ``n_runs`` and the number of threads.  SFC64 streams (seeded by spawning the
    parent's ``SeedSequence``) draw normals about 15 % faster than PCG64 here."""
    n_blocks = -(-n_runs // _RUN_BLOCK)
    return [np.random.Generator(np.random.SFC64(s))
            for s in rng.bit_generator.seed_seq.spawn(n_blocks)]


def _n_threads() -> int:
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not on Linux
        return max(1, os.cpu_count() or 1)


@dataclass(frozen=True)
class MonteCarloResult:
    """Monte Carlo runs: estimates and truth at ``t`` (every ``store_every`` steps) and the
    filter's posterior covariance ``P`` at the same times."""

    params: GyrocompassParams
    t: np.ndarray
    est: np.ndarray
    tru: np.ndarray
    P: np.ndarray
    seed: int

    def __post_init__(self) -> None:
        _check_params(self.params)
        nt = v.check_ndarray("t", self.t, ndim=1).size
        runs = v.check_ndarray("est", self.est, shape=(None, nt, N)).shape[0]
        v.check_ndarray("tru", self.tru, shape=(runs, nt, N))
        v.check_ndarray("P", self.P, shape=(nt, N, N))
        v.check_int("seed", self.seed, 0)

    @property
    def n_runs(self) -> int:
        return int(self.est.shape[0])

    def estimate(self, name: str) -> np.ndarray:
        """Estimates of state ``name``, shape ``(n_runs, len(t))``, SI."""
        return self.est[:, :, state_index(name)]

    def truth(self, name: str) -> np.ndarray:
        """True values of state ``name``, shape ``(n_runs, len(t))``, SI."""
        return self.tru[:, :, state_index(name)]

    def error(self, name: str) -> np.ndarray:
        return self.estimate(name) - self.truth(name)

    def std(self, name: str) -> np.ndarray:
        """Filter standard deviation at ``t``."""
        i = state_index(name)
        return np.sqrt(np.clip(self.P[:, i, i], 0.0, None))

    def rms_error(self, name: str) -> np.ndarray:
        """Ensemble RMS of the estimation error at ``t``."""
        return np.sqrt(np.mean(self.error(name) ** 2, axis=0))

    def nees(self, names: tuple[str, ...] | None = None) -> np.ndarray:
        """Normalized estimation error squared per run and time, ``(n_runs, len(t))``,
        for the states ``names`` (default: all 10); ``nan`` where ``P`` of those states is
        singular (``t = 0`` when a state starts known)."""
        if isinstance(names, str) or not (names is None or isinstance(names, list | tuple)):
            raise TypeError("names must be a tuple or list of state names (or None); "
                            f"got {type(names).__name__}")
        names = STATE_NAMES if names is None else tuple(names)
        if not names:
            raise ValueError("names must name at least one state")
        idx = [state_index(nm) for nm in names]
        e = (self.est - self.tru)[:, :, idx]
        out = np.full(e.shape[:2], np.nan)
        for ti in range(self.t.size):
            P = self.P[ti][np.ix_(idx, idx)]
            d = np.sqrt(np.diag(P))
            if np.any(d <= 0):
                continue
            C = P / np.outer(d, d)
            es = e[:, ti, :] / d
            sol = np.linalg.solve(C, es.T)
            out[:, ti] = np.sum(es.T * sol, axis=0)
        return out


def nees_bounds(dof: int, n_runs: int, confidence: float = 0.95) -> tuple[float, float]:
    """Two-sided chi-square bounds on the ensemble-average NEES of ``n_runs`` runs of a
    ``dof``-dimensional consistent estimator {cite:p}`BarShalom2001`."""
    dof = v.check_int("dof", dof, 1)
    n_runs = v.check_int("n_runs", n_runs, 1)
    confidence = v.check_in_range("confidence", confidence, 0.0, 1.0, low_open=True,
                                  high_open=True)
    lo = scipy.stats.chi2.ppf(0.5 * (1 - confidence), dof * n_runs) / n_runs
    hi = scipy.stats.chi2.ppf(0.5 * (1 + confidence), dof * n_runs) / n_runs
    return float(lo), float(hi)


def _coupling_flags(p: GyrocompassParams) -> tuple[float, float, bool]:
    return p.H * p.Omega_h / p.I, p.H * p.Omega_v / p.I, p.vertical_coupling == "printed_F"


def _run_batch(disc: GCDiscretization, X0: np.ndarray, rng: np.random.Generator | None,
               gains: np.ndarray | None, store_every: int, method: str,
               truth: str = "nonlinear") -> tuple:
    """Propagate truth (and the filter when ``gains`` is given) for all runs.

    Runs are processed in blocks of ``_RUN_BLOCK``; block ``b`` draws its standard normals
    ``(steps, 9, B)`` (process noise, then sensor noise) chunk after chunk from its own
    generator, so both methods and any number of threads consume the same numbers.
    """
    p = disc.params
    mdl = disc.model
    n_runs = X0.shape[0]
    m = mdl.H.shape[0]
    nw = disc.noise_factor.shape[2]
    width = nw + m
    B = _RUN_BLOCK
    nb = -(-n_runs // B)
    n_store = disc.n_steps // store_every + 1
    est = np.zeros((n_runs, n_store, N))
    tru = np.zeros((n_runs, n_store, N))
    tru[:, 0] = X0
    Xp = np.zeros((nb * B, N))
    Xp[:n_runs] = X0
    kh, kv, printed = _coupling_flags(p)
    if truth == "linear":  # the truth obeys the filter's linearized model exactly
        kh, kv, printed = 0.0, 0.0, False
    sr = np.sqrt(mdl.r)
    rowptr, colidx = mdl.sparsity()
    hptr, hidx = kalman._csr(mdl.H != 0)
    lrows = np.nonzero(np.any(disc.noise_factor != 0, axis=(0, 2)))[0].astype(np.int64)
    run_filter = gains is not None
    g = gains if run_filter else np.zeros((mdl.n_steps, m, N))
    sin_mid, cos_mid = np.sin(disc.beta_mid), np.cos(disc.beta_mid)
    rngs = None if rng is None else _block_rngs(rng, n_runs)

    def noise_chunks(b: int):
        for k0 in range(0, disc.n_steps, _CHUNK):
            steps = min(_CHUNK, disc.n_steps - k0)
            if rngs is None:
                yield k0, np.zeros((steps, width, B))
            else:
                yield k0, rngs[b].standard_normal((steps, width, B))

    if method == "fast":
        phis = np.empty((mdl.n_steps, colidx.size))
        _step_phi(mdl.seg, mdl.a, mdl.b, mdl.Phi0, mdl.PhiA, mdl.PhiB, rowptr, colidx, phis)

        def task(b: int) -> None:
            x = np.ascontiguousarray(Xp[b * B:(b + 1) * B].T)
            xh = np.zeros_like(x)
            y = np.zeros_like(x)
            rho = np.zeros(B)
            for k0, noise in noise_chunks(b):
                _mc_block_kernel(k0, phis, mdl.seg, rowptr, colidx, disc.Gamma,
                                 disc.noise_factor, lrows, hptr, hidx, mdl.H, sr, g, sin_mid,
                                 cos_mid, p.dt, kh, kv, printed, noise, x, xh, y, rho,
                                 store_every, est, tru, b * B, run_filter)

        n_thr = min(_n_threads(), nb)
        if n_thr > 1:
            with ThreadPoolExecutor(max_workers=n_thr) as pool:
                list(pool.map(task, range(nb)))
        else:
            for b in range(nb):
                task(b)
        return est, tru

    # plain-numpy reference: the same recursion, one block at a time, vectorized over its
    # runs, with batch gains and the torques evaluated directly with cos/sin
    for b in range(nb):
        X = Xp[b * B:(b + 1) * B].copy()
        Xh = np.zeros_like(X)
        rows = slice(b * B, min((b + 1) * B, n_runs))
        nv = rows.stop - rows.start
        for k0, noise in noise_chunks(b):
            for kk in range(noise.shape[0]):
                k = k0 + kk
                j = mdl.seg[k]
                Phi = mdl.phi(k)
                bn = disc.beta_mid[k]
                sn, cn = sin_mid[k], cos_mid[k]
                db = X[:, 0] + 0.5 * p.dt * X[:, 1]
                bt = bn + db
                lin_de, lin_ga = (-kv * cn, kv * sn) if printed else (-kv * sn, kv * cn)
                rho = (kh * (np.cos(bt - X[:, 2]) - cn)
                       + kv * (X[:, 5] * np.cos(bt) - X[:, 4] * np.sin(bt))
                       - (-kh * sn * db + kh * sn * X[:, 2] + lin_de * X[:, 4]
                          + lin_ga * X[:, 5]))
                X = (X @ Phi.T + rho[:, None] * disc.Gamma[j]
                     + noise[kk, :nw].T @ disc.noise_factor[j].T)
                if run_filter:
                    z = X @ mdl.H.T + noise[kk, nw:].T * sr
                    Xh = Xh @ Phi.T
                    Xh = Xh + (z - Xh @ mdl.H.T) @ gains[k].T
                if (k + 1) % store_every == 0:
                    est[rows, (k + 1) // store_every] = Xh[:nv]
                    tru[rows, (k + 1) // store_every] = X[:nv]
    return est, tru


def _initial_states(p: GyrocompassParams, n_runs: int, rng: np.random.Generator) -> np.ndarray:
    L0 = kalman.psd_factor(initial_covariance(p))
    return rng.standard_normal((n_runs, N)) @ L0.T


def monte_carlo(params: GyrocompassParams, n_runs: int, t_end: float = 100.0,
                seed: int = 0, *, store_every: int | None = None, method: str = "fast",
                truth: str = "nonlinear") -> MonteCarloResult:
    """``n_runs`` seeded runs of the truth model (nonlinear Eq. (3), see module docstring)
    with the Kalman filter on its measurements (paper GC, Figure 4).

    The gain sequence does not depend on the data: it is computed once by the covariance
    recursion, then all runs are propagated as a batch.  ``method="fast"`` (numba, parallel
    over runs) and ``"reference"`` (plain numpy, batch Joseph gains) draw the same random
    numbers and give the same estimates.  ``truth="linear"`` replaces Eq. (3) by the
    filter's own linearized model (to isolate the effect of the linearization).
    """
    p = _check_params(params)
    n_runs = v.check_int("n_runs", n_runs, 1)
    v.check_choice("truth", truth, ("nonlinear", "linear"))
    seed = v.check_int("seed", seed, 0)
    v.check_choice("method", method, ("fast", "reference"))
    disc = discretize(p, t_end)
    se = _default_store_every(disc.n_steps) if store_every is None else store_every
    se = v.check_int("store_every", se, 1)
    P0 = initial_covariance(p)
    if method == "fast":
        run = kalman.covariance_fast(disc.model, P0, se, keep_gains=True)
        gains = run.gains
    else:
        run = kalman.covariance_reference(disc.model, P0, se)
        gains = run.gains
    rng = np.random.default_rng(seed)
    X0 = _initial_states(p, n_runs, rng)
    est, tru = _run_batch(disc, X0, rng, gains, se, method, truth)
    return MonteCarloResult(params=p, t=disc.t[::se].copy(), est=est, tru=tru,
                            P=run.P_stored, seed=int(seed))


def simulate_truth(params: GyrocompassParams, t_end: float, x0: object, *,
                   seed: int | None = None, store_every: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """The truth model alone from the state ``x0`` (length 10, SI): returns ``(t, X)`` with
    ``X`` of shape ``(len(t), 10)``.  ``seed=None`` switches all noises off (for checking
    the integration of Eq. (3) against an independent solver)."""
    p = _check_params(params)
    x0 = v.check_array("x0", x0, shape=(N,))
    store_every = v.check_int("store_every", store_every, 1)
    seed = None if seed is None else v.check_int("seed", seed, 0)
    disc = discretize(p, t_end)
    rng = None if seed is None else np.random.default_rng(seed)
    _, tru = _run_batch(disc, x0[None, :], rng, None, store_every, "fast")
    return disc.t[::store_every].copy(), tru[0]


# Error budget --------------------------------------------------------------------------------
#: Sources of the error budget, in order.
BUDGET_SOURCES: Final[tuple[str, ...]] = (
    "initial dbeta", "initial dbeta_dot", "initial psi", "initial omega_gc", "initial delta",
    "initial gamma", "initial vibration state (N1, N2)", "initial random drift (N3, N4)",
    "vibration noise w1", "random drift noise w2", "angle sensor noise",
    "inclinometer y noise", "inclinometer z noise",
)


@dataclass(frozen=True)
class ErrorBudget:
    """Variance of the ω_gc estimation error split by source: ``var[s, i]`` at ``t[i]``
    for source ``sources[s]``; ``total`` is the filter's own variance (the sources add up to
    it exactly, up to rounding)."""

    params: GyrocompassParams
    t: np.ndarray
    sources: tuple[str, ...]
    var: np.ndarray
    total: np.ndarray

    def __post_init__(self) -> None:
        _check_params(self.params)
        nt = v.check_ndarray("t", self.t, ndim=1).size
        if not isinstance(self.sources, tuple) or not all(isinstance(s, str)
                                                          for s in self.sources):
            raise TypeError("sources must be a tuple of str")
        v.check_ndarray("var", self.var, shape=(len(self.sources), nt))
        v.check_ndarray("total", self.total, shape=(nt,))

    def at_end(self) -> dict[str, float]:
        """Standard deviation (rad/s) from each source at the last time."""
        return {s: float(np.sqrt(max(self.var[i, -1], 0.0))) for i, s in enumerate(self.sources)}


def error_budget(params: GyrocompassParams, t_end: float = 100.0, *,
                 name: str = "omega_gc", store_every: int | None = None) -> ErrorBudget:
    """Split the variance of the ``name`` estimation error by source.

    The gains of the full filter are kept fixed; each source's covariance is propagated alone
    through the linear error recursion (Joseph form, valid for any gain).  Sources are
    independent, so their variances add up to the filter's.
    """
    p = _check_params(params)
    ix = state_index(name)
    disc = discretize(p, t_end)
    se = _default_store_every(disc.n_steps) if store_every is None else store_every
    se = v.check_int("store_every", se, 1)
    mdl = disc.model
    P0 = initial_covariance(p)
    full = kalman.covariance_fast(mdl, P0, 1, keep_gains=True)
    zeros_q = tuple(np.zeros_like(mdl.Qd0) for _ in range(3))
    zero_r = np.zeros_like(mdl.r)
    Qc = process_noise_intensity(p)
    out = []
    for src in BUDGET_SOURCES:
        P0s = np.zeros_like(P0)
        Qd = zeros_q
        r = zero_r
        if src.startswith("initial "):
            blk = {"initial vibration state (N1, N2)": [6, 7],
                   "initial random drift (N3, N4)": [8, 9]}.get(src)
            blk = blk if blk is not None else [state_index(src.split()[1])]
            P0s[np.ix_(blk, blk)] = P0[np.ix_(blk, blk)]
        elif src.endswith("w1") or src.endswith("w2"):
            q = np.zeros_like(Qc)
            i = 0 if src.endswith("w1") else 1
            q[i, i] = Qc[i, i]
            parts = _affine_qd(p, disc.betas, q)
            Qd = parts[3:]
        else:
            q = ("angle sensor noise", "inclinometer y noise", "inclinometer z noise").index(src)
            r = zero_r.copy()
            r[q] = mdl.r[q]
        if not P0s.any() and Qd is zeros_q and not r.any():
            out.append(np.zeros(disc.n_steps // se + 1))
            continue
        res = kalman.propagate_fixed_gains(mdl, P0s, full.gains, r, Qd, se)
        out.append(res.P_stored[:, ix, ix])
    return ErrorBudget(params=p, t=disc.t[::se].copy(), sources=BUDGET_SOURCES,
                       var=np.array(out), total=full.var[::se, ix].copy())


# Why ψ and ω_gc separate -------------------------------------------------------------------
@njit(cache=True)
def _gramian_kernel(seg, a, b, Phi0, PhiA, PhiB, r0, store_every, S, T, W_out):
    """Sensitivities ``S`` (m×2) of the first ``m`` states to unit ψ(0) and ω_gc(0) through
    the leading m×m block of ``Φ_k`` (the float, ψ, ω_gc: ``m = 4``); accumulate the angle
    sensor's information ``W``.  Sizes come from the arrays (no unrolled constant loops:
    that keeps numba's compile time small)."""
    m, p = S.shape
    W = np.zeros((p, p))
    for k in range(seg.shape[0]):
        j = seg[k]
        ak = a[k]
        bk = b[k]
        for i in range(m):
            for c in range(p):
                s = 0.0
                for q in range(m):
                    s += (Phi0[j, i, q] + ak * PhiA[j, i, q] + bk * PhiB[j, i, q]) * S[q, c]
                T[i, c] = s
        for i in range(m):
            for c in range(p):
                S[i, c] = T[i, c]
        for c1 in range(p):
            for c2 in range(p):
                W[c1, c2] += S[0, c1] * S[0, c2] / r0
        if (k + 1) % store_every == 0:
            # element-wise: an array-slice assignment costs seconds of numba compile time
            ii = (k + 1) // store_every
            for c1 in range(p):
                for c2 in range(p):
                    W_out[ii, c1, c2] = W[c1, c2]


@dataclass(frozen=True)
class InformationPsiOmega:
    """Observability Gramian (Fisher information) of ``(ψ, ω_gc)`` from the angle sensor
    alone, the linearized float dynamics and no other error source: ``W[i]`` (2×2) at
    ``t[i]``."""

    t: np.ndarray
    W: np.ndarray

    def __post_init__(self) -> None:
        nt = v.check_ndarray("t", self.t, ndim=1).size
        v.check_ndarray("W", self.W, shape=(nt, 2, 2))

    def sigma_gc_psi_known(self) -> np.ndarray:
        """σ of ω_gc if ψ were known: ``1/√W_ωω`` (rad/s)."""
        with np.errstate(divide="ignore"):
            return 1.0 / np.sqrt(self.W[:, 1, 1])

    def sigma_gc_psi_unknown(self) -> np.ndarray:
        """σ of ω_gc with ψ unknown (no prior): ``√(W⁻¹)_ωω`` (rad/s)."""
        det = self.W[:, 0, 0] * self.W[:, 1, 1] - self.W[:, 0, 1] ** 2
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.sqrt(self.W[:, 0, 0] / det)

    def correlation(self) -> np.ndarray:
        """Correlation of the ψ and ω_gc information, ``W_ψω/√(W_ψψ W_ωω)``: ±1 means the
        two are indistinguishable."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return self.W[:, 0, 1] / np.sqrt(self.W[:, 0, 0] * self.W[:, 1, 1])


def information_psi_omega(params: GyrocompassParams, t_end: float = 100.0, *,
                          store_every: int | None = None, frozen_beta: float | None = None
                          ) -> InformationPsiOmega:
    """Information about ``(ψ, ω_gc)`` in the angle-sensor samples (paper GC, Eq. (5)): ψ
    enters through ``H Ω_h sin β_n``, which grows from zero as the float turns, while
    ω_gc enters through the constant ``H``; the Gramian quantifies how this separates them.

    ``frozen_beta`` (rad) holds ``β_n`` at a constant value instead (a counterfactual float
    that does not turn), to show what the growth of ``sin β_n`` contributes.
    """
    p = _check_params(params)
    disc = discretize(p, t_end)
    se = _default_store_every(disc.n_steps) if store_every is None else store_every
    se = v.check_int("store_every", se, 1)
    mdl = disc.model
    if frozen_beta is not None:
        fb = v.check_real("frozen_beta", frozen_beta)
        Phi, Qd = kalman.van_loan(system_matrix(p, fb), noise_input_matrix(p),
                                  process_noise_intensity(p), p.dt)
        zero = np.zeros(disc.n_steps)
        mdl = kalman.AffineDiscreteModel(
            seg=np.zeros(disc.n_steps, dtype=np.int64), a=zero, b=zero, Phi0=Phi[None],
            PhiA=np.zeros_like(Phi)[None], PhiB=np.zeros_like(Phi)[None], Qd0=Qd[None],
            QdA=np.zeros_like(Qd)[None], QdB=np.zeros_like(Qd)[None], H=mdl.H, r=mdl.r)
    W = np.zeros((disc.n_steps // se + 1, 2, 2))
    S = np.zeros((4, 2))
    S[state_index("psi"), 0] = 1.0
    S[state_index("omega_gc"), 1] = 1.0
    _gramian_kernel(mdl.seg, mdl.a, mdl.b, mdl.Phi0, mdl.PhiA, mdl.PhiB, float(mdl.r[0]),
                    se, S, np.zeros_like(S), W)
    return InformationPsiOmega(t=disc.t[::se].copy(), W=W)
