"""Paper GC, Figure 4: Monte Carlo runs of a truth model and the filter on its measurements.

The truth does not share the filter's model.  It integrates the **nonlinear** gyrocompass
equation (3) of paper GC,

    I β'' + f β' = H [Ω_h cos(β − ψ) + Ω_v (γ cos β − δ sin β) + ω_gc + ω_ub N1/g + N3],

together with the shaping filters (6), (7), on its own grid of ``substeps`` steps per
sampling interval (``Δt/10`` by default), from its own parameters (``truth_params``, the
filter's by default):

* the float angle as the nominal motion of Eq. (4) (integrated alongside, noise free) plus a
  deviation, both by the exponential midpoint rule (the stiff ``−(f/I) β'`` exact, the
  torque at the predicted midpoint); the torque is evaluated in full, with no linearization
  (``cos x − 1`` and ``sin x − x`` by series for small ``x``, so nothing cancels);
* the shaping filters driven by white noise held constant over each fine step (variance
  ``Q/h``: a zero-order hold, not the filter's exact ``Qd``);
* each sample reads ``D x(t_k)`` plus the sensors' continuous white noise averaged over the
  sampling interval (exactly Gaussian with variance ``C/Δt``; ``C`` itself under the
  ``measurement_noise="variance"`` reading of the truth's parameters).

With ``eq1_sign="-"`` (the literal sign of Eq. (1)) the float turns the other way; like the
filter's model, the truth is written in the mirrored angle, where the tilt term that carries
``sin β`` changes sign.

The filter's Kalman gains come from its own covariance recursion (its affine discrete model,
:func:`gyrolib.gc.discretize`); the truth uses none of it.  A truth with other parameters
than the filter's (``truth_params``) shows what a wrong model does to the claimed σ.
"""

from __future__ import annotations

import math
import os
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Final, NamedTuple

import numpy as np
import scipy.linalg
from numba import njit
from numpy.typing import ArrayLike, NDArray

from gyrolib import _validation as v
from gyrolib.filtering.covariance import _csr, covariance_fast, covariance_reference
from gyrolib.filtering.discretization import covariance_factor
from gyrolib.gc.covariance import _default_store_every
from gyrolib.gc.discretization import N, _check_params, _n_steps, discretize
from gyrolib.gc.params import STATE_NAMES, GyrocompassParams, state_index
from gyrolib.gc.state_space import initial_covariance, measurement_noise_covariance

__all__ = [
    "MonteCarloResult",
    "monte_carlo",
    "simulate_truth",
]

#: Fine steps of the truth per sampling interval of the filter.
TRUTH_SUBSTEPS: Final[int] = 10

#: Steps per block of random numbers (cache-resident blocks).
_CHUNK: Final[int] = 250

#: Runs per block: the unit of SIMD, of threading and of random-number streams.
_RUN_BLOCK: Final[int] = 32


# The truth model -------------------------------------------------------------------------------
class TruthModel(NamedTuple):
    """The truth's arrays, grouped for the kernels (all SI, per unit inertia ``I``).

    ``h``: the fine step; ``E``, ``p1``: exact step of ``(β, β')`` under
    ``β'' = −(f/I) β' + u`` over one fine step with ``u`` held constant; ``beta_mid``
    (``sin_mid``, ``cos_mid``): the nominal angle (its sine, cosine) at each fine step's
    predicted midpoint; ``phi1``, ``gam1`` (``phi2``, ``gam2``): zero-order-hold step of the
    vibration (random-drift) filter and its response to unit white noise, scaled by
    ``sqrt(Q/h)``; ``kh = H Ω_h/I``, ``kv = H Ω_v/I`` (``kd``: the same with the sign of
    the δ term, flipped by ``eq1_sign="-"`` in the mirrored angle), ``hi = H/I``,
    ``ub = H ω_ub/(I g)``; ``g``; ``sr`` the sensors' noise standard deviations per sample;
    ``off_b``, ``off_bd``: the truth's nominal minus the filter's at the samples;
    ``substeps``; ``linear``: 1 to replace the torques by their linearization about the
    nominal (the filter's Eq. (5)).
    """

    h: float
    E: NDArray[np.float64]
    p1: NDArray[np.float64]
    beta_mid: NDArray[np.float64]
    sin_mid: NDArray[np.float64]
    cos_mid: NDArray[np.float64]
    phi1: NDArray[np.float64]
    gam1: NDArray[np.float64]
    phi2: NDArray[np.float64]
    gam2: NDArray[np.float64]
    kh: float
    kv: float
    kd: float
    hi: float
    ub: float
    g: float
    sr: NDArray[np.float64]
    off_b: NDArray[np.float64]
    off_bd: NDArray[np.float64]
    substeps: int
    linear: int


class FilterModel(NamedTuple):
    """The filter's arrays for the kernels: nonzeros of ``Φ_k`` per step (``phis``, CSR
    pattern ``rowptr``, ``colidx``), the measurement matrix ``H`` (CSR ``hptr``, ``hidx``) and
    the gains ``K_k`` (steps × m × n)."""

    phis: NDArray[np.float64]
    rowptr: NDArray[np.int64]
    colidx: NDArray[np.int64]
    H: NDArray[np.float64]
    hptr: NDArray[np.int64]
    hidx: NDArray[np.int64]
    gains: NDArray[np.float64]


@njit(cache=True, fastmath=True)
def _cm1(x):
    """``cos x − 1`` without cancellation (series below 0.05: error < 1e-19 relative)."""
    if abs(x) < 0.05:
        x2 = x * x
        return x2 * (-0.5 + x2 * (1.0 / 24.0 + x2 * (-1.0 / 720.0 + x2 / 40320.0)))
    h = math.sin(0.5 * x)
    return -2.0 * h * h


@njit(cache=True, fastmath=True)
def _sin(x):
    """``sin x`` as ``x + (sin x − x)`` with the bracket by series below 0.05."""
    if abs(x) < 0.05:
        x2 = x * x
        return x + x * x2 * (-1.0 / 6.0 + x2 * (1.0 / 120.0 + x2 * (-1.0 / 5040.0
                                                                      + x2 / 362880.0)))
    return math.sin(x)


#: Below this |x| (rad) the branch-free series of :func:`_cm1_poly`, :func:`_sin_poly` are
#: exact to rounding (first neglected term < 1e-20 relative); above it the kernels switch to
#: :func:`_cm1`, :func:`_sin`.
_POLY_MAX: Final[float] = 0.25


@njit(cache=True, fastmath=True, inline="always")
def _cm1_poly(x):
    """``cos x − 1`` by its Taylor series to ``x¹⁴`` (no branch: the run loop vectorizes)."""
    x2 = x * x
    return x2 * (-0.5 + x2 * (1.0 / 24.0 + x2 * (-1.0 / 720.0 + x2 * (
        1.0 / 40320.0 + x2 * (-1.0 / 3628800.0 + x2 * (1.0 / 479001600.0
                                                       - x2 / 87178291200.0))))))


@njit(cache=True, fastmath=True, inline="always")
def _sin_poly(x):
    """``sin x`` by its Taylor series to ``x¹⁵`` (no branch)."""
    x2 = x * x
    return x * (1.0 + x2 * (-1.0 / 6.0 + x2 * (1.0 / 120.0 + x2 * (-1.0 / 5040.0 + x2 * (
        1.0 / 362880.0 + x2 * (-1.0 / 39916800.0 + x2 * (1.0 / 6227020800.0
                                                          - x2 / 1307674368000.0)))))))


@njit(cache=True)
def _nominal_fine(h, E, p1, kh, n_fine, substeps, beta_mid, b_out, bd_out):
    """Eq. (4) from rest on the fine grid by the exponential midpoint rule: the angle at each
    step's predicted midpoint ``β + h β'/2`` (where the torque is taken), and ``(β_n, β_n')``
    every ``substeps`` steps."""
    b = 0.0
    bd = 0.0
    b_out[0] = 0.0
    bd_out[0] = 0.0
    for i in range(n_fine):
        bm = b + 0.5 * h * bd
        beta_mid[i] = bm
        u = kh * math.cos(bm)
        b, bd = (E[0, 0] * b + E[0, 1] * bd + p1[0] * u,
                 E[1, 0] * b + E[1, 1] * bd + p1[1] * u)
        if (i + 1) % substeps == 0:
            b_out[(i + 1) // substeps] = b
            bd_out[(i + 1) // substeps] = bd


def _zoh(A: np.ndarray, B: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray]:
    """``(e^{Ah}, ∫₀ʰ e^{As} ds B)``: exact step of ``x' = A x + B u`` with ``u`` held."""
    n = A.shape[0]
    M = np.zeros((n + 1, n + 1))
    M[:n, :n] = A * h
    M[:n, n] = B * h
    X = scipy.linalg.expm(M)
    return X[:n, :n].copy(), X[:n, n].copy()


def truth_model(truth: GyrocompassParams, filt: GyrocompassParams, n_steps: int,
                substeps: int = TRUTH_SUBSTEPS, linear: bool = False) -> TruthModel:
    """The truth's arrays over ``n_steps`` samples of ``filt.dt`` (see :class:`TruthModel`);
    ``filt`` only sets the nominal the states are reported against."""
    h = truth.dt / substeps
    n_fine = n_steps * substeps
    Ab = np.array([[0.0, 1.0], [0.0, -truth.f / truth.I]])
    E, p1 = _zoh(Ab, np.array([0.0, 1.0]), h)

    def nominal(p: GyrocompassParams) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        Ap = np.array([[0.0, 1.0], [0.0, -p.f / p.I]])
        Ep, pp = _zoh(Ap, np.array([0.0, 1.0]), h)
        bm = np.empty(n_fine)
        b = np.empty(n_steps + 1)
        bd = np.empty(n_steps + 1)
        _nominal_fine(h, Ep, pp, p.H * p.Omega_h / p.I, n_fine, substeps, bm, b, bd)
        return bm, b, bd

    beta_mid, b_t, bd_t = nominal(truth)
    if filt == truth:
        b_f, bd_f = b_t, bd_t
    else:
        _, b_f, bd_f = nominal(filt)
    vib, drift = truth.vibration_filter(), truth.random_drift_filter()
    phi1, gam1 = _zoh(vib.A, vib.B[:, 0], h)
    phi2, gam2 = _zoh(drift.A, drift.B[:, 0], h)
    return TruthModel(
        h=h, E=E, p1=p1, beta_mid=beta_mid, sin_mid=np.sin(beta_mid), cos_mid=np.cos(beta_mid),
        phi1=phi1, gam1=gam1 * math.sqrt(truth.Q1 / h), phi2=phi2,
        gam2=gam2 * math.sqrt(truth.Q2 / h), kh=truth.H * truth.Omega_h / truth.I,
        kv=truth.H * truth.Omega_v / truth.I,
        kd=(-1.0 if truth.eq1_sign == "-" else 1.0) * truth.H * truth.Omega_v / truth.I,
        hi=truth.H / truth.I,
        ub=truth.H * truth.omega_ub / (truth.I * truth.g), g=truth.g,
        sr=np.sqrt(np.diag(measurement_noise_covariance(truth))), off_b=b_t - b_f,
        off_bd=bd_t - bd_f, substeps=int(substeps), linear=int(linear))


# Fast kernel (numba): one block of runs, the runs in the innermost loops (SIMD) -----------------
@njit(cache=True, nogil=True, fastmath=True)
def _truth_substeps(k, kk, tm, noise, x, u):
    """Advance the truth ``x`` (n×B; rows 0, 1 the deviation from the truth's nominal) over
    the fine steps of sample interval ``k``."""
    B = x.shape[1]
    for sub in range(tm.substeps):
        i = k * tm.substeps + sub
        sm = tm.sin_mid[i]
        cm = tm.cos_mid[i]
        for r in range(B):
            # shaping filters (6), (7), white noise held over the fine step
            w1 = noise[kk, 2 * sub, r]
            w2 = noise[kk, 2 * sub + 1, r]
            n1, n2, n3, n4 = x[6, r], x[7, r], x[8, r], x[9, r]
            x[6, r] = tm.phi1[0, 0] * n1 + tm.phi1[0, 1] * n2 + tm.gam1[0] * w1
            x[7, r] = tm.phi1[1, 0] * n1 + tm.phi1[1, 1] * n2 + tm.gam1[1] * w1
            x[8, r] = tm.phi2[0, 0] * n3 + tm.phi2[0, 1] * n4 + tm.gam2[0] * w2
            x[9, r] = tm.phi2[1, 0] * n3 + tm.phi2[1, 1] * n4 + tm.gam2[1] * w2
            # torque of Eq. (3) minus Eq. (4), per unit I, at the predicted midpoint
            u[r] = (tm.hi * (x[3, r] + 0.5 * (n3 + x[8, r]))
                    + tm.ub * 0.5 * (n1 + x[6, r]))
        if tm.linear:
            for r in range(B):
                dm = x[0, r] + 0.5 * tm.h * x[1, r]
                u[r] += (-tm.kh * sm * (dm - x[2, r])
                         + tm.kv * x[5, r] * cm - tm.kd * x[4, r] * sm)
        else:
            big = 0.0
            for r in range(B):
                dm = x[0, r] + 0.5 * tm.h * x[1, r]
                e = dm - x[2, r]
                big = max(big, abs(e), abs(dm))
                # kh [cos(β_m + dm − ψ) − cos β_m]
                u[r] += tm.kh * (cm * _cm1_poly(e) - sm * _sin_poly(e))
                cd = 1.0 + _cm1_poly(dm)
                sd = _sin_poly(dm)
                # kv γ cos(β_m + dm) − kd δ sin(β_m + dm)
                u[r] += (tm.kv * x[5, r] * (cm * cd - sm * sd)
                         - tm.kd * x[4, r] * (sm * cd + cm * sd))
            if big > _POLY_MAX:  # far from the nominal (never at the paper's priors): redo
                for r in range(B):
                    dm = x[0, r] + 0.5 * tm.h * x[1, r]
                    e = dm - x[2, r]
                    if abs(e) > _POLY_MAX or abs(dm) > _POLY_MAX:
                        cd = 1.0 + _cm1(dm)
                        sd = _sin(dm)
                        u[r] += tm.kh * (cm * (_cm1(e) - _cm1_poly(e))
                                         - sm * (_sin(e) - _sin_poly(e)))
                        u[r] += (tm.kv * x[5, r] * (cm * (cd - 1.0 - _cm1_poly(dm))
                                                     - sm * (sd - _sin_poly(dm)))
                                 - tm.kd * x[4, r] * (sm * (cd - 1.0 - _cm1_poly(dm))
                                                      + cm * (sd - _sin_poly(dm))))
        for r in range(B):
            d, dd = x[0, r], x[1, r]
            x[0, r] = tm.E[0, 0] * d + tm.E[0, 1] * dd + tm.p1[0] * u[r]
            x[1, r] = tm.E[1, 0] * d + tm.E[1, 1] * dd + tm.p1[1] * u[r]


@njit(cache=True, nogil=True, fastmath=True)
def _mc_block_kernel(k0, noise, tm, fm, x, xh, y, u, store_every, est, tru, run0,
                     run_filter):
    """Truth and filter for one block of ``B`` runs (``x``, ``xh``: n×B, updated in place)
    over the samples ``k0 … k0 + len(noise) − 1``.  Releases the GIL: blocks run in
    parallel threads."""
    n, B = x.shape
    n_runs = est.shape[0]
    m = fm.H.shape[0]
    nw = 2 * tm.substeps
    for kk in range(noise.shape[0]):
        k = k0 + kk
        _truth_substeps(k, kk, tm, noise, x, u)
        ob = tm.off_b[k + 1]
        if run_filter:
            # predict: x̂⁻ = Φ_k x̂
            for i in range(n):
                for r in range(B):
                    y[i, r] = 0.0
                for p in range(fm.rowptr[i], fm.rowptr[i + 1]):
                    f = fm.phis[k, p]
                    c = fm.colidx[p]
                    for r in range(B):
                        y[i, r] += f * xh[c, r]
            for i in range(n):
                for r in range(B):
                    xh[i, r] = y[i, r]
            # the truth's samples: Δβ + v0, g δ + N1 + v1, g γ + N1 + v2
            for r in range(B):
                y[0, r] = x[0, r] + ob + tm.sr[0] * noise[kk, nw, r]
                y[1, r] = tm.g * x[4, r] + x[6, r] + tm.sr[1] * noise[kk, nw + 1, r]
                y[2, r] = tm.g * x[5, r] + x[6, r] + tm.sr[2] * noise[kk, nw + 2, r]
            # update, one scalar measurement after the other (the gains of
            # covariance_fast are those of sequential updates):
            # x̂ ← x̂ + K_{k,q} (z_q − H_q x̂)
            for q in range(m):
                for r in range(B):
                    u[r] = y[q, r]
                for p in range(fm.hptr[q], fm.hptr[q + 1]):
                    c = fm.hidx[p]
                    h = fm.H[q, c]
                    for r in range(B):
                        u[r] -= h * xh[c, r]
                for i in range(n):
                    g = fm.gains[k, q, i]
                    for r in range(B):
                        xh[i, r] += g * u[r]
        if (k + 1) % store_every == 0:
            ii = (k + 1) // store_every
            for r in range(B):
                run = run0 + r
                if run < n_runs:
                    for i in range(n):
                        est[run, ii, i] = xh[i, r]
                        tru[run, ii, i] = x[i, r]
                    tru[run, ii, 0] += ob
                    tru[run, ii, 1] += tm.off_bd[k + 1]


@njit(cache=True)
def _step_phi(seg, a, b, Phi0, PhiA, PhiB, rowptr, colidx, out):
    """Nonzeros of ``Φ_k`` for every step (shared by all runs)."""
    for k in range(seg.shape[0]):
        j = seg[k]
        for i in range(rowptr.shape[0] - 1):
            for p in range(rowptr[i], rowptr[i + 1]):
                c = colidx[p]
                out[k, p] = Phi0[j, i, c] + a[k] * PhiA[j, i, c] + b[k] * PhiB[j, i, c]


# Reference path (plain numpy): the same recursion, written like filterpy -----------------------
def _reference_block(k0: int, noise: np.ndarray, tm: TruthModel, Phi: list, H: np.ndarray,
                     gains: np.ndarray | None, X: np.ndarray, Xh: np.ndarray,
                     store: callable) -> None:
    """One chunk of one block (``X``, ``Xh``: B×n, rows are runs), torques by ``np.cos``."""
    M = tm.substeps
    for kk in range(noise.shape[0]):
        k = k0 + kk
        for sub in range(M):
            i = k * M + sub
            w1, w2 = noise[kk, 2 * sub], noise[kk, 2 * sub + 1]
            n1, n3 = X[:, 6].copy(), X[:, 8].copy()
            # N ← e^{A h} N + Γ_h √(Q/h) w   (shaping filters, zero-order hold)
            X[:, 6:8] = X[:, 6:8] @ tm.phi1.T + np.outer(w1, tm.gam1)
            X[:, 8:10] = X[:, 8:10] @ tm.phi2.T + np.outer(w2, tm.gam2)
            bm = tm.beta_mid[i]
            dm = X[:, 0] + 0.5 * tm.h * X[:, 1]
            if tm.linear:
                tq = (-tm.kh * np.sin(bm) * (dm - X[:, 2])
                      + tm.kv * X[:, 5] * np.cos(bm) - tm.kd * X[:, 4] * np.sin(bm))
            else:
                # Eq. (3) minus Eq. (4): kh[cos(β−ψ) − cos β_n] + kv γ cos β − kd δ sin β
                tq = (tm.kh * (np.cos(bm + dm - X[:, 2]) - np.cos(bm))
                      + tm.kv * X[:, 5] * np.cos(bm + dm) - tm.kd * X[:, 4] * np.sin(bm + dm))
            # + (H/I)(ω_gc + N3) + H ω_ub N1/(I g), the noises at the midpoint
            tq = tq + tm.hi * (X[:, 3] + 0.5 * (n3 + X[:, 8])) + tm.ub * 0.5 * (n1 + X[:, 6])
            # (Δβ, Δβ') ← E (Δβ, Δβ') + p1 u
            X[:, 0:2] = X[:, 0:2] @ tm.E.T + np.outer(tq, tm.p1)
        if gains is not None:
            # x̂⁻ = Φ_k x̂
            Xh[:] = Xh @ Phi[k].T
            # z = D x + v: the truth's samples, its nominal offset, noise averaged over Δt
            x_true = X.copy()
            x_true[:, 0] += tm.off_b[k + 1]
            z = np.stack([x_true[:, 0], tm.g * X[:, 4] + X[:, 6], tm.g * X[:, 5] + X[:, 6]],
                         axis=1) + noise[kk, 2 * M:].T * tm.sr
            # x̂ = x̂⁻ + K (z − H x̂⁻)
            Xh[:] = Xh + (z - Xh @ H.T) @ gains[k].T
        store(k, X, Xh)


# Runs in blocks ---------------------------------------------------------------------------------
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


def _run_batch(tm: TruthModel, n_steps: int, X0: np.ndarray, rng: np.random.Generator | None,
               fm: FilterModel | None, store_every: int, method: str,
               phi_of_step: callable | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Propagate truth (and the filter when ``fm`` is given) for all runs.

    Block ``b`` of ``_RUN_BLOCK`` runs draws its standard normals ``(steps, 2 M + 3, B)``
    (per fine step the two shaping-filter noises, then the three sensor noises) chunk after
    chunk from its own generator, so both methods and any number of threads consume the
    same numbers.
    """
    n_runs = X0.shape[0]
    B = _RUN_BLOCK
    nb = -(-n_runs // B)
    width = 2 * tm.substeps + 3
    n_store = n_steps // store_every + 1
    est = np.zeros((n_runs, n_store, N))
    tru = np.zeros((n_runs, n_store, N))
    tru[:, 0] = X0
    Xp = np.zeros((nb * B, N))
    Xp[:n_runs] = X0
    rngs = None if rng is None else _block_rngs(rng, n_runs)

    def noise_chunks(b: int):
        for k0 in range(0, n_steps, _CHUNK):
            steps = min(_CHUNK, n_steps - k0)
            if rngs is None:
                yield k0, np.zeros((steps, width, B))
            else:
                yield k0, rngs[b].standard_normal((steps, width, B))

    if method == "fast":
        run_filter = fm is not None
        if fm is None:  # the kernel needs typed arrays even when the filter is off
            fm = FilterModel(np.zeros((n_steps, 1)), np.zeros(N + 1, np.int64),
                             np.zeros(1, np.int64), np.zeros((3, N)),
                             np.zeros(4, np.int64), np.zeros(1, np.int64),
                             np.zeros((n_steps, 3, N)))

        def task(b: int) -> None:
            x = np.ascontiguousarray(Xp[b * B:(b + 1) * B].T)
            x[0] -= tm.off_b[0]
            x[1] -= tm.off_bd[0]
            xh = np.zeros_like(x)
            y = np.zeros_like(x)
            u = np.zeros(B)
            for k0, noise in noise_chunks(b):
                _mc_block_kernel(k0, noise, tm, fm, x, xh, y, u, store_every, est, tru,
                                 b * B, run_filter)

        n_thr = min(_n_threads(), nb)
        if n_thr > 1:
            with ThreadPoolExecutor(max_workers=n_thr) as pool:
                list(pool.map(task, range(nb)))
        else:
            for b in range(nb):
                task(b)
        return est, tru

    for b in range(nb):
        X = Xp[b * B:(b + 1) * B].copy()
        Xh = np.zeros_like(X)
        rows = slice(b * B, min((b + 1) * B, n_runs))
        nv = rows.stop - rows.start

        def store(k: int, X: np.ndarray, Xh: np.ndarray, rows: slice = rows,
                  nv: int = nv) -> None:
            if (k + 1) % store_every == 0:
                ii = (k + 1) // store_every
                est[rows, ii] = Xh[:nv]
                tru[rows, ii] = X[:nv]
                tru[rows, ii, 0] += tm.off_b[k + 1]
                tru[rows, ii, 1] += tm.off_bd[k + 1]

        for k0, noise in noise_chunks(b):
            _reference_block(k0, noise, tm, phi_of_step, None if fm is None else fm.H,
                             None if fm is None else fm.gains, X, Xh, store)
    return est, tru


@dataclass(frozen=True)
class MonteCarloResult:
    """Monte Carlo runs (paper GC, Figure 4): estimates and truth at ``t`` (every
    ``store_every`` samples), the filter's posterior covariance ``P`` at the same times, the
    filter's ``params`` and the truth's ``truth_params`` (``None``: the same)."""

    params: GyrocompassParams
    t: NDArray[np.float64]
    est: NDArray[np.float64]
    tru: NDArray[np.float64]
    P: NDArray[np.float64]
    seed: int
    truth_params: GyrocompassParams | None = None

    def __post_init__(self) -> None:
        _check_params(self.params)
        if self.truth_params is not None:
            v.check_instance("truth_params", self.truth_params, GyrocompassParams)
        nt = v.check_ndarray("t", self.t, ndim=1).size
        runs = v.check_ndarray("est", self.est, shape=(None, nt, N)).shape[0]
        v.check_ndarray("tru", self.tru, shape=(runs, nt, N))
        v.check_ndarray("P", self.P, shape=(nt, N, N))
        v.check_int("seed", self.seed, 0)

    @property
    def n_runs(self) -> int:
        """Number of runs."""
        return int(self.est.shape[0])

    def estimate(self, name: str) -> NDArray[np.float64]:
        """Estimates of state ``name``, shape ``(n_runs, len(t))``, SI."""
        return self.est[:, :, state_index(name)]

    def truth(self, name: str) -> NDArray[np.float64]:
        """True values of state ``name``, shape ``(n_runs, len(t))``, SI."""
        return self.tru[:, :, state_index(name)]

    def error(self, name: str) -> NDArray[np.float64]:
        """Estimation error (estimate − truth) of state ``name``, ``(n_runs, len(t))``."""
        return self.estimate(name) - self.truth(name)

    def std(self, name: str) -> NDArray[np.float64]:
        """Filter standard deviation of state ``name`` at ``t`` (what the filter claims)."""
        i = state_index(name)
        return np.sqrt(np.clip(self.P[:, i, i], 0.0, None))

    def rms_error(self, name: str) -> NDArray[np.float64]:
        """Ensemble RMS of the estimation error of state ``name`` at ``t`` (what it gets)."""
        return np.sqrt(np.mean(self.error(name) ** 2, axis=0))

    def nees(self, names: tuple[str, ...] | None = None) -> NDArray[np.float64]:
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


def _initial_states(p: GyrocompassParams, n_runs: int, rng: np.random.Generator) -> np.ndarray:
    L0 = covariance_factor(initial_covariance(p))
    return rng.standard_normal((n_runs, N)) @ L0.T


def monte_carlo(params: GyrocompassParams, n_runs: int, t_end: float = 100.0,
                seed: int = 0, *, truth_params: GyrocompassParams | None = None,
                store_every: int | None = None, method: str = "fast",
                truth: str = "nonlinear", substeps: int = TRUTH_SUBSTEPS) -> MonteCarloResult:
    """``n_runs`` seeded runs of the truth model with paper GC's Kalman filter on its
    measurements (paper GC, Figure 4).

    Parameters
    ----------
    params : GyrocompassParams
        The filter's model (its ``F``, ``Qd``, ``R``, ``P(0)``).
    n_runs : int
        Number of runs (>= 1).
    t_end : float
        Length of each run (s), a multiple of ``params.dt``.
    seed : int
        Seed (>= 0); run ``i`` is the same whatever ``n_runs`` and the number of threads.
    truth_params : GyrocompassParams, optional
        The truth's parameters (default: the filter's); they must share ``dt``.  The initial
        states are drawn from the truth's prior.
    store_every : int, optional
        Store every ``store_every``-th sample (default: about 1000 stored times).
    method : {"fast", "reference"}
        ``"fast"``: numba, blocks of runs in parallel; ``"reference"``: plain numpy, the
        same random numbers (a second implementation for the tests).
    truth : {"nonlinear", "linear"}
        ``"linear"`` replaces the torques of Eq. (3) by their linearization (Eq. (5)), to
        isolate the effect of the nonlinearity.
    substeps : int
        Fine steps of the truth per sample (>= 1).

    Returns
    -------
    MonteCarloResult
        Estimates, truth and the filter's covariance at the stored times.

    Examples
    --------
    >>> from gyrolib import gc
    >>> mc = gc.monte_carlo(gc.GyrocompassParams(), 64, 1.0, seed=1)
    >>> ratio = mc.rms_error("omega_gc")[-1] / mc.std("omega_gc")[-1]
    >>> bool(0.7 < ratio < 1.3)   # 64 runs: the RMS error is the filter's σ within sampling
    True
    """
    p = _check_params(params)
    tp = p if truth_params is None else v.check_instance("truth_params", truth_params,
                                                         GyrocompassParams)
    if tp.dt != p.dt:
        raise ValueError(f"truth_params.dt must equal params.dt={p.dt}; got {tp.dt}")
    n_runs = v.check_int("n_runs", n_runs, 1)
    seed = v.check_int("seed", seed, 0)
    v.check_choice("method", method, ("fast", "reference"))
    v.check_choice("truth", truth, ("nonlinear", "linear"))
    substeps = v.check_int("substeps", substeps, 1)
    disc = discretize(p, t_end)
    se = _default_store_every(disc.n_steps) if store_every is None else store_every
    se = v.check_int("store_every", se, 1)
    mdl = disc.model
    P0 = initial_covariance(p)
    if method == "fast":
        run = covariance_fast(mdl, P0, se, keep_gains=True)
    else:
        run = covariance_reference(mdl, P0, se)
    tm = truth_model(tp, p, disc.n_steps, substeps, truth == "linear")
    rowptr, colidx = mdl.sparsity()
    hptr, hidx = _csr(mdl.H != 0)
    phis = np.empty((mdl.n_steps, colidx.size))
    if method == "fast":
        _step_phi(mdl.seg, mdl.a, mdl.b, mdl.Phi0, mdl.PhiA, mdl.PhiB, rowptr, colidx, phis)
    fm = FilterModel(phis, rowptr, colidx, np.ascontiguousarray(mdl.H), hptr, hidx,
                     np.ascontiguousarray(run.gains))
    rng = np.random.default_rng(seed)
    X0 = _initial_states(tp, n_runs, rng)
    phi_of_step = _LazyPhi(mdl) if method == "reference" else None
    est, tru = _run_batch(tm, disc.n_steps, X0, rng, fm, se, method, phi_of_step)
    return MonteCarloResult(params=p, t=disc.t[::se].copy(), est=est, tru=tru,
                            P=run.P_stored, seed=int(seed),
                            truth_params=None if truth_params is None else tp)


class _LazyPhi:
    """``Φ_k`` of the filter's model on demand (the reference path)."""

    def __init__(self, model: object) -> None:
        self.model = model

    def __getitem__(self, k: int) -> np.ndarray:
        return self.model.phi(k)


def simulate_truth(params: GyrocompassParams, t_end: float, x0: ArrayLike, *,
                   seed: int | None = None, store_every: int = 1,
                   substeps: int = TRUTH_SUBSTEPS) -> tuple[NDArray[np.float64],
                                                            NDArray[np.float64]]:
    """The truth model of :func:`monte_carlo` alone, from the state ``x0`` (length 10, SI).

    Parameters
    ----------
    params : GyrocompassParams
        The truth's parameters.
    t_end : float
        Length (s), a multiple of ``params.dt``.
    x0 : array_like
        Initial state (10, SI) in the filter's coordinates (Δβ from the nominal of Eq. (4)).
    seed : int, optional
        ``None`` switches all noises off (to check the integration of Eq. (3) against an
        independent solver).
    store_every : int
        Return every ``store_every``-th sample.
    substeps : int
        Fine steps per sample.

    Returns
    -------
    t : ndarray
        Times (s).
    X : ndarray
        States, shape ``(len(t), 10)``.

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import gc
    >>> x0 = np.zeros(10); x0[3] = 1e-6   # a drift of 1e-6 rad/s, everything else at rest
    >>> t, X = gc.simulate_truth(gc.GyrocompassParams(), 1.0, x0)
    >>> f"{X[-1, 0]:.4g}"   # Δβ ≈ (H/f) ω_gc (t − I/f) after the float's time constant
    '1.997e-06'
    """
    p = _check_params(params)
    x0 = v.check_array("x0", x0, shape=(N,))
    store_every = v.check_int("store_every", store_every, 1)
    seed = None if seed is None else v.check_int("seed", seed, 0)
    substeps = v.check_int("substeps", substeps, 1)
    n_steps = _n_steps(p, t_end)
    tm = truth_model(p, p, n_steps, substeps)
    rng = None if seed is None else np.random.default_rng(seed)
    _, tru = _run_batch(tm, n_steps, x0[None, :], rng, None, store_every, "fast")
    return np.arange(0, n_steps + 1, store_every) * p.dt, tru[0]
