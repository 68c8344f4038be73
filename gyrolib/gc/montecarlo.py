"""Paper GC, Figure 4: Monte Carlo runs of the truth model and the filter.

The truth model is the nonlinear Eq. (3) with the shaping filters (6), (7): its linear part
(everything ``F`` holds, including the shaping filters driven by exactly discretized white
noise) is propagated exactly, and the nonlinear remainder of the gyroscopic and vertical-rate
torques (of order 10⁻⁵ of the signal) by the exponential midpoint rule.
"""

from __future__ import annotations

import math
import os
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Final

import numpy as np
from numba import njit

from gyrolib import _validation as v
from gyrolib.filtering.covariance import _csr, covariance_fast, covariance_reference
from gyrolib.filtering.discretization import covariance_factor
from gyrolib.gc.covariance import _default_store_every
from gyrolib.gc.discretization import GCDiscretization, N, _check_params, discretize
from gyrolib.gc.params import STATE_NAMES, GyrocompassParams, state_index
from gyrolib.gc.state_space import (
    initial_covariance,
)

__all__ = [
    "MonteCarloResult",
    "monte_carlo",
    "simulate_truth",
]


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
    hptr, hidx = _csr(mdl.H != 0)
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
    L0 = covariance_factor(initial_covariance(p))
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
        run = covariance_fast(disc.model, P0, se, keep_gains=True)
        gains = run.gains
    else:
        run = covariance_reference(disc.model, P0, se)
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
