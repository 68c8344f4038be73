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

The truth builds its arrays from the parameters itself (:func:`truth_model`,
:func:`truth_prior_factor`): the shaping filters' matrices and white-noise intensities from
α, ξ, σ² as the text after Eqs. (6), (7) defines them, their stationary covariance in closed
form, the sensors' noise from ``C`` and ``Δt``, the prior from the parameters' standard
deviations.  It calls nothing of :mod:`gyrolib.gc.model.shaping_filters`,
:mod:`gyrolib.gc.model.state_space` or :mod:`gyrolib.gc.model.discretization` (the
tests check that the two constructions agree).  What it shares with the filter is the
parameter object, the order of the state vector (:data:`gyrolib.gc.STATE_NAMES`, to compare
estimates with the truth) and the sampling grid.

With ``eq1_sign="-"`` (the literal sign of Eq. (1)) the float turns the other way; like the
filter's model, the truth is written in the mirrored angle, where the tilt term that carries
``sin β`` changes sign.

The filter's Kalman gains come from its own covariance recursion (its affine discrete model,
:func:`gyrolib.gc.discretize`); the truth uses none of it.  A truth with other parameters
than the filter's (``truth_params``) shows what a wrong model does to the claimed σ.

Random numbers: run ``i`` has its own stream, an SFC64 generator seeded by the ``i``-th child
of ``numpy.random.SeedSequence(seed)`` (:func:`run_streams`); it draws the run's initial state
and then, sample after sample, the truth's white noises.  The fast path draws them inside its
numba kernel with numpy's own algorithm (SFC64 and the 256-layer ziggurat of
``Generator.standard_normal``; the tests compare it with numpy), so a run's numbers do not
depend on how many runs there are, how they are grouped, or on how many threads or processes
share the work (``executor``).  Why a copy rather than numpy's generators themselves: with
23 normals per run and step the normals are most of the work, and numpy's
``standard_normal`` (per run, blocks filled on threads) gives the same runs at about twice
the CPU time, on AVX-512 and on AVX2 alike (the copy stays only while numpy's path
costs more than 1.15 times its CPU over the whole Monte Carlo on the AVX2 class;
``benchmarks/bench_gc_monte_carlo.py`` measures both and records the decision, and the whole
Monte Carlo against its draw limit, the CPU time of its normals from numpy's generator).
"""

from __future__ import annotations

import dataclasses
import functools
import math
import os
from concurrent.futures import Executor, ThreadPoolExecutor, as_completed
from dataclasses import dataclass
from typing import Final, NamedTuple

import numpy as np
import scipy.linalg
from numba import int64, njit, uint64
from numpy.typing import ArrayLike, NDArray

from gyrolib import _compile_note  # noqa: F401  (a line on stderr at the first compile)
from gyrolib import _validation as v
from gyrolib._executor import check_executor
from gyrolib._repr import compact_repr
from gyrolib.filtering.consistency import nees_bounds
from gyrolib.filtering.covariance import covariance_fast, covariance_reference
from gyrolib.gc.analysis.covariance import default_store_every
from gyrolib.gc.model.discretization import (
    N,
    discretize_steps,
    steps_in,
)
from gyrolib.gc.model.instrument import (
    InstrumentModel,
    augmented_index,
    build_instrument_model,
    state_names,
    union_names,
)
from gyrolib.gc.model.params import STATE_NAMES, GyrocompassParams, check_params
from gyrolib.gc.model.state_space import ContinuousModel

__all__ = [
    "MonteCarloResult",
    "MonteCarloSummary",
    "monte_carlo",
    "run_streams",
    "simulate_truth",
    "truth_prior_factor",
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
    ``substeps``; ``linear``: which torques are replaced by their linearization about the
    nominal (the filter's Eq. (5)): 0 none, 1 all, 2 the horizontal-rate term, 3 the tilt
    terms (:data:`LINEARIZE`); ``nb`` instrument constants (states ``10 … 10 + nb − 1``,
    constant), whose readings ``(Hb0 + β Hb1) b`` are added to the samples, with ``beta_s``
    the truth's nominal float angle at the samples (:mod:`gyrolib.gc.model.instrument`).
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
    nb: int
    Hb0: NDArray[np.float64]
    Hb1: NDArray[np.float64]
    beta_s: NDArray[np.float64]


class FilterModel(NamedTuple):
    """The filter's arrays for the kernels: nonzeros of ``Φ_k`` per step (``phis``, CSR
    pattern ``rowptr``, ``colidx``), the measurement matrix after step ``k``,
    ``H0 + hs[k] H1`` with ``H = [H0; H1]`` (2m × n: its rows ``m …`` are ``H1``, zero for
    a constant ``H``; CSR ``hptr``, ``hidx`` of the nonzeros of both) and the gains ``K_k``
    (steps × m × n).  (``H1`` rides in ``H``: an array more in the kernel's hot loop costs
    time even when it is zero.)"""

    phis: NDArray[np.float64]
    rowptr: NDArray[np.int64]
    colidx: NDArray[np.int64]
    H: NDArray[np.float64]
    hptr: NDArray[np.int64]
    hidx: NDArray[np.int64]
    gains: NDArray[np.float64]
    hs: NDArray[np.float64]


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


#: Below this |x| (rad) the short series of :func:`_cm1_short`, :func:`_sin_short` are exact
#: to rounding (first neglected term < 1e-19 of the result); the kernel adds the difference to
#: :func:`_cm1`, :func:`_sin` for the rare lanes above it.  The paper's priors keep
#: ``|Δβ|``, ``|Δβ − ψ|`` some 20 standard deviations below it.
_SHORT_MAX: Final[float] = 0.02


@njit(cache=True, fastmath=True, inline="always")
def _cm1_short(x):
    """``cos x − 1`` by its Taylor series to ``x⁸`` (for ``|x| <= _SHORT_MAX``)."""
    x2 = x * x
    return x2 * (-0.5 + x2 * (1.0 / 24.0 + x2 * (-1.0 / 720.0 + x2 / 40320.0)))


@njit(cache=True, fastmath=True, inline="always")
def _sin_short(x):
    """``sin x`` by its Taylor series to ``x⁷`` (for ``|x| <= _SHORT_MAX``)."""
    x2 = x * x
    return x * (1.0 + x2 * (-1.0 / 6.0 + x2 * (1.0 / 120.0 - x2 / 5040.0)))


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


def zoh_discretize(A: np.ndarray, B: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray]:
    """``(e^{Ah}, ∫₀ʰ e^{As} ds B)``: exact step of ``x' = A x + B u`` with ``u`` held."""
    n = A.shape[0]
    M = np.zeros((n + 1, n + 1))
    M[:n, :n] = A * h
    M[:n, n] = B * h
    X = scipy.linalg.expm(M)
    return X[:n, :n].copy(), X[:n, n].copy()


def _truth_shaping(p: GyrocompassParams) -> tuple[tuple[np.ndarray, np.ndarray, float], ...]:
    """The truth's own shaping filters ``(A, b, Q)``: ``x' = A x + b w`` with white ``w`` of
    intensity ``Q``, written out from paper GC's Eqs. (6), (7) and the text after them
    (``Q1 = 2 ξ1 α1 σ1²``, ``Q2 = 4 ξ2 α2³ σ2²``); not from
    :mod:`gyrolib.gc.model.shaping_filters`."""
    a1, x1, a2, x2 = p.alpha1, p.xi1, p.alpha2, p.xi2
    vib = (np.array([[0.0, 1.0], [-(a1**2), -2.0 * x1 * a1]]),
           np.array([1.0, a1 - 2.0 * x1 * a1]), 2.0 * x1 * a1 * p.sigma1_sq)
    drift = (np.array([[0.0, 1.0], [-(a2**2), -2.0 * x2 * a2]]), np.array([0.0, 1.0]),
             4.0 * x2 * a2**3 * p.sigma2_sq)
    return vib, drift


def _stationary_2x2(A: np.ndarray, b: np.ndarray, Q: float) -> np.ndarray:
    """Stationary covariance of ``x' = A x + b w``, ``A = [[0, 1], [−a², −2 ξ a]]``, in closed
    form (the three scalar equations of ``A P + P Aᵀ + Q b bᵀ = 0`` solved by hand):
    ``P12 = −Q b1²/2``, ``P22 = Q (b2² + a² b1²)/(4 ξ a)``,
    ``P11 = (P22 − 2 ξ a P12 + Q b1 b2)/a²``."""
    a2, two_xi_a = -A[1, 0], -A[1, 1]
    p12 = -0.5 * Q * b[0] ** 2
    p22 = Q * (b[1] ** 2 + a2 * b[0] ** 2) / (2.0 * two_xi_a)
    p11 = (p22 - two_xi_a * p12 + Q * b[0] * b[1]) / a2
    return np.array([[p11, p12], [p12, p22]])


def truth_prior_factor(params: GyrocompassParams) -> NDArray[np.float64]:
    """The truth's own factor ``L`` of its prior, ``x(0) = L z`` with ``z`` standard normal.

    Δβ, Δβ', ψ, ω_gc, δ, γ independent with the parameters' standard deviations (paper GC's
    P(0) and the book's readings of the entries it does not print); N1, N2 and N3, N4 with
    their stationary covariance in closed form (times ``shaping_p0_scale``; zero under
    ``shaping_p0="zero"``), factored by hand.  Built without
    :func:`gyrolib.gc.initial_covariance`; the tests check that ``L Lᵀ`` equals it.

    Parameters
    ----------
    params : GyrocompassParams
        The truth's parameters.

    Returns
    -------
    L : ndarray of shape (10, 10)
        Lower triangular.

    Examples
    --------
    >>> from gyrolib import gc
    >>> from gyrolib.units import from_si
    >>> L = gc.truth_prior_factor(gc.GyrocompassParams())
    >>> f"{from_si(L[3, 3], 'arcsec_paper/s'):.2f}"   # σ of ω_gc, ″/s
    '0.15'
    """
    p = check_params(params)
    L = np.zeros((N, N))
    for i, sd in enumerate((p.sigma_dbeta0, p.sigma_dbeta_dot0, p.sigma_psi0, p.sigma_gc0,
                            p.sigma_delta0, p.sigma_gamma0)):
        L[i, i] = sd
    if p.shaping_p0 == "stationary":
        for i0, (A, b, Q) in zip((6, 8), _truth_shaping(p), strict=True):
            S = p.shaping_p0_scale * _stationary_2x2(A, b, Q)
            if S[0, 0] > 0.0:
                l11 = math.sqrt(S[0, 0])
                l21 = S[1, 0] / l11
                L[i0, i0], L[i0 + 1, i0] = l11, l21
                L[i0 + 1, i0 + 1] = math.sqrt(max(S[1, 1] - l21 * l21, 0.0))
    return L


def _truth_noise_sd(p: GyrocompassParams) -> np.ndarray:
    """The sensors' noise standard deviation per sample: continuous white noise of intensity
    ``C`` averaged over ``Δt`` (``√(C/Δt)``), or ``√C`` under the ``"variance"`` reading."""
    C = np.array([p.C_as, p.C_incl_y, p.C_incl_z])
    return np.sqrt(C / p.dt if p.measurement_noise == "intensity_over_dt" else C)


#: ``TruthModel.linear``: which torques of Eq. (3) the truth replaces by their linearization
#: about its nominal (Eq. (5)): none, all, only the horizontal-rate term
#: ``Ω_h cos(β − ψ)``, only the vertical-rate (tilt) terms ``Ω_v (γ cos β − δ sin β)``.
LINEARIZE: Final[dict[str, int]] = {"nonlinear": 0, "linear": 1, "linear_horizontal": 2,
                                    "linear_tilt": 3}


def truth_model(truth: GyrocompassParams, filt: GyrocompassParams, n_steps: int,
                substeps: int = TRUTH_SUBSTEPS, linear: bool | int = False,
                inst: InstrumentModel | None = None) -> TruthModel:
    """The truth's arrays over ``n_steps`` samples of ``filt.dt`` (see :class:`TruthModel`);
    ``filt`` only sets the nominal the states are reported against.  ``linear``: ``False``
    (0) the nonlinear torques, ``True`` (1) all linearized, 2 or 3 one term (see
    :data:`LINEARIZE`).  ``inst``: the instrument constants the truth's state carries after
    its 10 states (their readings; ``None``: none)."""
    if inst is not None and inst.couples_dynamics:
        raise ValueError("inst must not couple a constant into the dynamics (Fb != 0): the "
                         "truth integrates Eq. (3) and reads the constants in its samples "
                         "only")
    h = truth.dt / substeps
    n_fine = n_steps * substeps
    Ab = np.array([[0.0, 1.0], [0.0, -truth.f / truth.I]])
    E, p1 = zoh_discretize(Ab, np.array([0.0, 1.0]), h)

    def nominal(p: GyrocompassParams) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        Ap = np.array([[0.0, 1.0], [0.0, -p.f / p.I]])
        Ep, pp = zoh_discretize(Ap, np.array([0.0, 1.0]), h)
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
    (A1, g1, Q1), (A2, g2, Q2) = _truth_shaping(truth)
    phi1, gam1 = zoh_discretize(A1, g1, h)
    phi2, gam2 = zoh_discretize(A2, g2, h)
    return TruthModel(
        h=h, E=E, p1=p1, beta_mid=beta_mid, sin_mid=np.sin(beta_mid), cos_mid=np.cos(beta_mid),
        phi1=phi1, gam1=gam1 * math.sqrt(Q1 / h), phi2=phi2,
        gam2=gam2 * math.sqrt(Q2 / h), kh=truth.H * truth.Omega_h / truth.I,
        kv=truth.H * truth.Omega_v / truth.I,
        kd=(-1.0 if truth.eq1_sign == "-" else 1.0) * truth.H * truth.Omega_v / truth.I,
        hi=truth.H / truth.I,
        ub=truth.H * truth.omega_ub / (truth.I * truth.g), g=truth.g,
        sr=_truth_noise_sd(truth), off_b=b_t - b_f,
        off_bd=bd_t - bd_f, substeps=int(substeps), linear=int(linear),
        nb=0 if inst is None else inst.nb,
        Hb0=np.zeros((3, 0)) if inst is None else np.ascontiguousarray(inst.H0),
        Hb1=np.zeros((3, 0)) if inst is None else np.ascontiguousarray(inst.H1), beta_s=b_t)


# Fast kernel (numba): one block of runs, the runs in the innermost loops (SIMD) -----------------
@njit(cache=True, nogil=True, fastmath=True)
def _truth_substeps(k, kk, tm, noise, x, u):
    """Advance the truth ``x`` (n×B; rows 0, 1 the deviation from the truth's nominal) over
    the fine steps of sample interval ``k``: one pass over the lanes per fine step (SIMD),
    ``u`` (B) a scratch for the rare lanes far from the nominal."""
    B = x.shape[1]  # the block's lanes (_RUN_BLOCK; 1 for simulate_truth's one run)
    M = tm.substeps
    lin_h = tm.linear == 1 or tm.linear == 2
    lin_v = tm.linear == 1 or tm.linear == 3
    f00, f01, f10, f11 = tm.phi1[0, 0], tm.phi1[0, 1], tm.phi1[1, 0], tm.phi1[1, 1]
    r00, r01, r10, r11 = tm.phi2[0, 0], tm.phi2[0, 1], tm.phi2[1, 0], tm.phi2[1, 1]
    g10, g11, g20, g21 = tm.gam1[0], tm.gam1[1], tm.gam2[0], tm.gam2[1]
    e00, e01, e10, e11 = tm.E[0, 0], tm.E[0, 1], tm.E[1, 0], tm.E[1, 1]
    p0, p1 = tm.p1[0], tm.p1[1]
    hh = 0.5 * tm.h
    kh, kv, kd, hi, ub = tm.kh, tm.kv, tm.kd, tm.hi, tm.ub
    x0, x1, x2, x3, x4 = x[0], x[1], x[2], x[3], x[4]
    x5, x6, x7, x8, x9 = x[5], x[6], x[7], x[8], x[9]
    for r in range(B):
        u[r] = 0.0
    for sub in range(M):
        i = k * M + sub
        sm = tm.sin_mid[i]
        cm = tm.cos_mid[i]
        w1v = noise[kk, 2 * sub]
        w2v = noise[kk, 2 * sub + 1]
        far = False
        if not (lin_h and lin_v):
            big = 0.0
            for r in range(B):
                dm = x0[r] + hh * x1[r]
                big = max(big, abs(dm), abs(dm - x2[r]))
            far = big > _SHORT_MAX
        if far:  # far from the nominal (never at the paper's priors): series → sin, cos
            for r in range(B):
                dm = x0[r] + hh * x1[r]
                e = dm - x2[r]
                if not lin_h and abs(e) > _SHORT_MAX:
                    u[r] += kh * (cm * (_cm1(e) - _cm1_short(e)) - sm * (_sin(e) - _sin_short(e)))
                if not lin_v and abs(dm) > _SHORT_MAX:
                    dc = _cm1(dm) - _cm1_short(dm)
                    ds = _sin(dm) - _sin_short(dm)
                    u[r] += kv * x5[r] * (cm * dc - sm * ds) - kd * x4[r] * (sm * dc + cm * ds)
        for r in range(B):
            # shaping filters (6), (7), white noise held over the fine step
            n1, n2, n3, n4 = x6[r], x7[r], x8[r], x9[r]
            w1, w2 = w1v[r], w2v[r]
            n1n = f00 * n1 + f01 * n2 + g10 * w1
            n2n = f10 * n1 + f11 * n2 + g11 * w1
            n3n = r00 * n3 + r01 * n4 + g20 * w2
            n4n = r10 * n3 + r11 * n4 + g21 * w2
            # torque of Eq. (3) minus Eq. (4), per unit I, at the predicted midpoint:
            # (H/I)(ω_gc + N3) + H ω_ub N1/(I g), the noises at the midpoint, ...
            d, dd = x0[r], x1[r]
            dm = d + hh * dd
            e = dm - x2[r]
            tq = hi * (x3[r] + 0.5 * (n3 + n3n)) + ub * 0.5 * (n1 + n1n) + u[r]
            # ... kh [cos(β_m + dm − ψ) − cos β_m] (linearized: −kh sin β_m (dm − ψ)) ...
            if lin_h:
                tq -= kh * sm * e
            else:
                tq += kh * (cm * _cm1_short(e) - sm * _sin_short(e))
            # ... kv γ cos(β_m + dm) − kd δ sin(β_m + dm) (linearized: at β_m)
            if lin_v:
                tq += kv * x5[r] * cm - kd * x4[r] * sm
            else:
                cd = 1.0 + _cm1_short(dm)
                sd = _sin_short(dm)
                tq += kv * x5[r] * (cm * cd - sm * sd) - kd * x4[r] * (sm * cd + cm * sd)
            # (Δβ, Δβ') ← E (Δβ, Δβ') + p1 u
            x0[r] = e00 * d + e01 * dd + p0 * tq
            x1[r] = e10 * d + e11 * dd + p1 * tq
            x6[r], x7[r], x8[r], x9[r] = n1n, n2n, n3n, n4n
        if far:
            for r in range(B):
                u[r] = 0.0


@njit(cache=True, nogil=True, fastmath=True)
def _filter_and_store(k, kk, noise, tm, fm, x, xh, y, u, store_every, est, tru, run0,
                      run_filter):
    """The filter's step ``k`` on the truth's samples (``run_filter``), then, at a stored
    time, estimates and truth of the block's runs into ``est``, ``tru`` (from row ``run0``)."""
    n, B = x.shape   # the block's lanes (_RUN_BLOCK; 1 for simulate_truth's one run)
    n_runs = est.shape[0]
    m = fm.H.shape[0] // 2
    nw = 2 * tm.substeps
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
        # plus the instrument constants (rows 10 …): (Hb0 + β Hb1) b
        bs = tm.beta_s[k + 1]
        for e in range(tm.nb):
            for q in range(3):
                cq = tm.Hb0[q, e] + bs * tm.Hb1[q, e]
                if cq != 0.0:
                    for r in range(B):
                        y[q, r] += cq * x[10 + e, r]
        # update, one scalar measurement after the other (the gains of
        # covariance_fast are those of sequential updates):
        # x̂ ← x̂ + K_{k,q} (z_q − H_q x̂), H after step k = H + hs[k] H1
        hk = fm.hs[k]
        for q in range(m):
            for r in range(B):
                u[r] = y[q, r]
            for p in range(fm.hptr[q], fm.hptr[q + 1]):
                c = fm.hidx[p]
                h = fm.H[q, c] + hk * fm.H[m + q, c]
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


@njit(cache=True, nogil=True, fastmath=True)
def _mc_block_kernel(k0, noise, tm, fm, x, xh, y, u, store_every, est, tru, run0,
                     run_filter):
    """Truth (:func:`_truth_substeps`) and filter for one block of ``B`` runs (``x``,
    ``xh``: n×B, updated in place) over the samples ``k0 … k0 + len(noise) − 1``.  Releases
    the GIL: blocks run in parallel threads."""
    for kk in range(noise.shape[0]):
        k = k0 + kk
        _truth_substeps(k, kk, tm, noise, x, u)
        _filter_and_store(k, kk, noise, tm, fm, x, xh, y, u, store_every, est, tru, run0,
                          run_filter)


@njit(cache=True)
def _step_phi(seg, a, b, Phi0, PhiA, PhiB, rowptr, colidx, out):
    """Nonzeros of ``Φ_k`` for every step (shared by all runs)."""
    for k in range(seg.shape[0]):
        j = seg[k]
        for i in range(rowptr.shape[0] - 1):
            for p in range(rowptr[i], rowptr[i + 1]):
                c = colidx[p]
                out[k, p] = Phi0[j, i, c] + a[k] * PhiA[j, i, c] + b[k] * PhiB[j, i, c]


# Random numbers: numpy's SFC64 and ziggurat, one stream per run, inside the kernel -----------
def _ziggurat_tables() -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The 256-layer ziggurat of numpy's ``Generator.standard_normal`` (Marsaglia and Tsang's
    construction with numpy's ``r`` and layer area ``v``, 52-bit mantissa): ``ki`` (accept
    thresholds), ``wi`` (widths per unit integer), ``fi`` (densities at the layers' edges).
    Built in double precision: they match numpy's tables to about 1e-14, so a normal agrees
    with numpy's to that precision (tested)."""
    r = _ZIG_R
    v_area = 4.928673233974654931590913431847e-3
    m1 = 2.0**52
    ki = np.zeros(256, np.uint64)
    wi = np.zeros(256)
    fi = np.zeros(256)
    dn = tn = r
    q = v_area / math.exp(-0.5 * dn * dn)
    ki[0] = np.uint64((dn / q) * m1)
    wi[0], wi[255] = q / m1, dn / m1
    fi[0], fi[255] = 1.0, math.exp(-0.5 * dn * dn)
    for i in range(254, 0, -1):
        dn = math.sqrt(-2.0 * math.log(v_area / dn + math.exp(-0.5 * dn * dn)))
        ki[i + 1] = np.uint64((dn / tn) * m1)
        tn = dn
        fi[i] = math.exp(-0.5 * dn * dn)
        wi[i] = dn / m1
    return ki, ki.astype(np.int64), wi, fi


#: Start of the normal's tail in numpy's ziggurat, and its inverse.
_ZIG_R: Final[float] = 3.6541528853610087963519472518
_ZIG_INV_R: Final[float] = 0.27366123732975827203338247596
_ZKI, _ZKI_SIGNED, _ZWI, _ZFI = _ziggurat_tables()

#: Steps of noise drawn at a time per block (the buffer stays in the core's L2 cache).
_NOISE_CHUNK: Final[int] = 16


@njit(cache=True, nogil=True, fastmath=True)
def _sfc64_step(a, b, c, w, out):
    """One output of every lane's SFC64 generator (numpy's ``sfc64_next``), vectorized over
    the lanes ``a, b, c, w`` (the four words of each lane's state)."""
    for r in range(a.shape[0]):
        tmp = a[r] + b[r] + w[r]
        w[r] += uint64(1)
        a[r] = b[r] ^ (b[r] >> uint64(11))
        cc = c[r]
        b[r] = cc + (cc << uint64(3))
        c[r] = ((cc << uint64(24)) | (cc >> uint64(40))) + tmp
        out[r] = tmp


@njit(cache=True, nogil=True, inline="always")
def _sfc64_lane(s, r):
    """The next output of lane ``r``'s SFC64 generator (state ``s[:, r]``)."""
    a, b, c, w = s[0, r], s[1, r], s[2, r], s[3, r]
    tmp = a + b + w
    s[3, r] = w + uint64(1)
    s[0, r] = b ^ (b >> uint64(11))
    s[1, r] = c + (c << uint64(3))
    s[2, r] = ((c << uint64(24)) | (c >> uint64(40))) + tmp
    return tmp


@njit(cache=True, nogil=True, inline="always")
def _uniform_lane(s, r):
    """numpy's ``next_double``: the top 53 bits over 2⁵³."""
    return float(_sfc64_lane(s, r) >> uint64(11)) * (1.0 / 9007199254740992.0)


@njit(cache=True, nogil=True, inline="always")
def _ziggurat_try(u, wi):
    """numpy's first try of the ziggurat from one 64-bit output ``u``: the layer (8 bits),
    the mantissa (52 bits, after the sign bit) and the signed candidate ``x``; accepted when
    the mantissa is below the layer's ``ki``."""
    idx = int64(u & uint64(0xff))
    u >>= uint64(8)
    rabs = (u >> uint64(1)) & uint64(0x000fffffffffffff)
    x = float(rabs) * wi[idx]
    if u & uint64(1):
        x = -x
    return idx, rabs, x


@njit(cache=True, nogil=True)
def _ziggurat_rest(s, r, idx, rabs, x, ki, wi, fi):
    """numpy's ``random_standard_normal`` for lane ``r`` after its first test failed (the
    tail or the wedge, then, if rejected, the whole algorithm again)."""
    while True:
        if idx == 0:
            while True:
                xx = -_ZIG_INV_R * math.log1p(-_uniform_lane(s, r))
                yy = -math.log1p(-_uniform_lane(s, r))
                if yy + yy > xx * xx:
                    return -(_ZIG_R + xx) if (rabs >> uint64(8)) & uint64(1) else _ZIG_R + xx
        elif (fi[idx - 1] - fi[idx]) * _uniform_lane(s, r) + fi[idx] < math.exp(-0.5 * x * x):
            return x
        idx, rabs, x = _ziggurat_try(_sfc64_lane(s, r), wi)
        if rabs < ki[idx]:
            return x


#: The mantissa of numpy's ziggurat (52 bits), and the exponent bits of ``2⁵²``: ``m | _EXP52``
#: read as a double is ``2⁵² + m`` exactly.
_MASK52: Final[int] = 0x000FFFFFFFFFFFFF
_EXP52: Final[int] = 0x4330000000000000


@njit(cache=True, nogil=True, fastmath=True)
def _fill_normals(s, out, ubuf, ki, ki_signed, wi, fi):
    """Standard normals ``out[k, j, r]`` from lane ``r``'s SFC64 state ``s[:, r]``, in the
    order ``k``, then ``j``: lane ``r`` reads exactly what numpy's
    ``Generator(SFC64).standard_normal(out.shape[:2])`` would draw from that state.

    Per draw, all lanes' 64 random bits at once (:func:`_sfc64_step`), the ziggurat's first
    try from them (8 bits layer, 1 bit sign, 52 bits mantissa; accepted about 99 % of the
    time), then the rest of numpy's algorithm for the lanes whose try failed.

    Written so that the first try vectorizes on AVX2 too: the mantissa becomes a
    double through its bits (``2⁵² + m`` minus ``2⁵²``, exact: AVX2 has no instruction for
    int64 → double, AVX-512 has), and the two table look-ups are a scalar loop of their own
    (LLVM does not vectorize a loop that needs gathers on AMD's Zen, whose gathers are slow):
    about 1.7 times faster on a 2-core AMD EPYC (Zen 3) than the loop that did all in one
    (``benchmarks/bench_gc_monte_carlo.py``), the same numbers."""
    a, b, c, w = s[0], s[1], s[2], s[3]
    lanes = _RUN_BLOCK  # a constant (out.shape[2] must be it): the lane loops unroll
    bits = np.empty(lanes, np.uint64)
    mant = bits.view(np.float64)
    wv = np.empty(lanes)
    kv = np.empty(lanes, np.int64)
    for k in range(out.shape[0]):
        for j in range(out.shape[1]):
            _sfc64_step(a, b, c, w, ubuf)
            for r in range(lanes):
                bits[r] = ((ubuf[r] >> uint64(9)) & uint64(_MASK52)) | uint64(_EXP52)
            for r in range(lanes):   # the table look-ups (scalar)
                idx = ubuf[r] & uint64(0xff)
                wv[r] = wi[idx]
                kv[r] = ki_signed[idx]
            o = out[k, j]
            n_failed = 0
            for r in range(lanes):
                ur = ubuf[r]
                x = (mant[r] - 4503599627370496.0) * wv[r]
                o[r] = -x if (ur >> uint64(8)) & uint64(1) else x
                n_failed += int64((ur >> uint64(9)) & uint64(_MASK52)) >= kv[r]
            if n_failed:
                for r in range(lanes):
                    ur = ubuf[r]
                    idx = int64(ur & uint64(0xff))
                    rabs = (ur >> uint64(9)) & uint64(_MASK52)
                    if rabs >= ki[idx]:
                        o[r] = _ziggurat_rest(s, r, idx, rabs, o[r], ki, wi, fi)


def _standard_normals(state: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
    """``shape`` standard normals per lane from the SFC64 states ``state`` (4 × lanes,
    ``uint64``, advanced in place) by the kernels' generator, ``(*shape, lanes)``; for the
    tests, to compare with numpy's."""
    n = state.shape[1]
    out = np.empty((*shape, n))
    B = _RUN_BLOCK
    for lo in range(0, n, B):
        hi = min(lo + B, n)
        st = np.zeros((4, B), np.uint64)   # lanes past the last: a dummy stream
        st[:, :hi - lo] = state[:, lo:hi]
        buf = np.empty((*shape, B))
        _fill_normals(st, buf, np.empty(B, np.uint64), _ZKI, _ZKI_SIGNED, _ZWI, _ZFI)
        out[..., lo:hi] = buf[..., :hi - lo]
        state[:, lo:hi] = st[:, :hi - lo]
    return out


@njit(cache=True, nogil=True)
def _fill_stream_lanes(s, out, lanes, ki, wi, fi):
    """What numpy's ``Generator(SFC64).standard_normal((steps, width, lanes))`` draws from the
    one SFC64 state ``s`` (4 × 1, ``uint64``, advanced in place), of which only the first
    ``out.shape[2]`` lanes are kept in ``out`` ``(steps, width, kept)``.  Every number is
    drawn (the stream must pass the lanes not kept), with numpy's algorithm as
    :func:`_fill_normals` draws it; a block with one run in it (:func:`simulate_truth`) is
    spared numpy's array of all of them.

    The state lives in four local words (written back only around the ziggurat's rare
    second try, :func:`_ziggurat_rest`), and a lane not kept costs its 64 bits and the
    first try's test, not its value: about 5× less than drawing every lane through the
    state array (a 100-s record drew 7.4·10⁷ numbers to keep 2.3·10⁶, 1.0 CPU-s
    of its 1.2 on the 2-core AVX2 machine), the same numbers
    (``tests/gc/test_monte_carlo.py``)."""
    kept = out.shape[2]
    a, b, c, w = s[0, 0], s[1, 0], s[2, 0], s[3, 0]
    for k in range(out.shape[0]):
        for j in range(out.shape[1]):
            for r in range(lanes):
                u = a + b + w                              # numpy's sfc64_next
                w = w + uint64(1)
                a = b ^ (b >> uint64(11))
                b = c + (c << uint64(3))
                c = ((c << uint64(24)) | (c >> uint64(40))) + u
                idx = int64(u & uint64(0xff))              # the ziggurat's first try
                rabs = (u >> uint64(9)) & uint64(_MASK52)
                if rabs < ki[idx]:
                    if r < kept:
                        x = float(rabs) * wi[idx]
                        out[k, j, r] = -x if (u >> uint64(8)) & uint64(1) else x
                else:
                    x = float(rabs) * wi[idx]
                    if (u >> uint64(8)) & uint64(1):
                        x = -x
                    s[0, 0], s[1, 0], s[2, 0], s[3, 0] = a, b, c, w
                    x = _ziggurat_rest(s, 0, idx, rabs, x, ki, wi, fi)
                    a, b, c, w = s[0, 0], s[1, 0], s[2, 0], s[3, 0]
                    if r < kept:
                        out[k, j, r] = x
    s[0, 0], s[1, 0], s[2, 0], s[3, 0] = a, b, c, w


@njit(cache=True, nogil=True)
def _mc_block_run(n_steps, state, noise, ubuf, tm, fm, x, xh, y, u, store_every, est, tru,
                  run0, run_filter, ki, ki_signed, wi, fi):
    """The whole run of one block of lanes: draw ``len(noise)`` steps of noise from the
    lanes' streams, advance truth and filter over them (:func:`_mc_block_kernel`), repeat."""
    chunk = noise.shape[0]
    for k0 in range(0, n_steps, chunk):
        nz = noise[:min(chunk, n_steps - k0)]
        _fill_normals(state, nz, ubuf, ki, ki_signed, wi, fi)
        _mc_block_kernel(k0, nz, tm, fm, x, xh, y, u, store_every, est, tru, run0, run_filter)


# Reference path (plain numpy): the same recursion, written like filterpy -----------------------
def _reference_block(k0: int, noise: np.ndarray, tm: TruthModel, Phi: list, H: np.ndarray,
                     gains: np.ndarray | None, X: np.ndarray, Xh: np.ndarray,
                     store: callable, H1: np.ndarray | None = None,
                     hs: np.ndarray | None = None) -> None:
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
            # Eq. (3) minus Eq. (4): kh[cos(β−ψ) − cos β_n] + kv γ cos β − kd δ sin β, each
            # term in full or linearized about β_n (Eq. (5))
            if tm.linear in (1, 2):
                tq = -tm.kh * np.sin(bm) * (dm - X[:, 2])
            else:
                tq = tm.kh * (np.cos(bm + dm - X[:, 2]) - np.cos(bm))
            if tm.linear in (1, 3):
                tq = tq + tm.kv * X[:, 5] * np.cos(bm) - tm.kd * X[:, 4] * np.sin(bm)
            else:
                tq = tq + tm.kv * X[:, 5] * np.cos(bm + dm) - tm.kd * X[:, 4] * np.sin(bm + dm)
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
            if tm.nb:   # the instrument constants' readings
                z = z + X[:, N:N + tm.nb] @ (tm.Hb0 + tm.beta_s[k + 1] * tm.Hb1).T
            Hk = H if H1 is None else H + hs[k] * H1
            # x̂ = x̂⁻ + K (z − H x̂⁻)
            Xh[:] = Xh + (z - Xh @ Hk.T) @ gains[k].T
        store(k, X, Xh)


# Runs in blocks, one numpy generator per block: the previous path, kept for simulate_truth ----
# (the sample records of data/ are made with its streams; monte_carlo uses _run_all below)
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


def _row_store(rows: slice, store_every: int, est: np.ndarray, tru: np.ndarray,
               tm: TruthModel) -> callable:
    """The reference paths' ``store(k, X, Xh)``: after fine step ``k``, every
    ``store_every``-th sample of the runs ``rows`` (the first ``nv`` lanes of the block) goes
    into ``est`` and ``tru`` (the truth's Δβ, Δβ' plus the nominal offsets)."""
    nv = rows.stop - rows.start

    def store(k: int, X: np.ndarray, Xh: np.ndarray) -> None:
        if (k + 1) % store_every == 0:
            ii = (k + 1) // store_every
            est[rows, ii] = Xh[:nv]
            tru[rows, ii] = X[:nv]
            tru[rows, ii, 0] += tm.off_b[k + 1]
            tru[rows, ii, 1] += tm.off_bd[k + 1]
    return store


def _run_batch(tm: TruthModel, n_steps: int, X0: np.ndarray, rng: np.random.Generator | None,
               fm: FilterModel | None, store_every: int, method: str,
               phi_of_step: callable | None = None, kernel_normals: bool = False
               ) -> tuple[np.ndarray, np.ndarray]:
    """Propagate truth (and the filter when ``fm`` is given) for all runs.

    Block ``b`` of ``_RUN_BLOCK`` runs draws its standard normals ``(steps, 2 M + 3, B)``
    (per fine step the two shaping-filter noises, then the three sensor noises) chunk after
    chunk from its own generator, so both methods and any number of threads consume the
    same numbers.  ``kernel_normals``: drawn by :func:`_fill_stream_lanes` (numpy's numbers,
    to the ziggurat tables' 1e-14), which keeps only the lanes that hold runs, and the
    kernels advance only those (one lane for :func:`simulate_truth`'s one run, not 32);
    else by numpy.
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

    def lanes_of(b: int) -> int:
        """The lanes block ``b`` advances: all ``B``, or with ``kernel_normals`` only those
        that hold runs (the kernels take the lane count from ``x``)."""
        return min(B, n_runs - b * B) if (rngs is not None and kernel_normals) else B

    def noise_chunks(b: int):
        if rngs is not None and kernel_normals:
            state = rngs[b].bit_generator.state["state"]["state"].reshape(4, 1).copy()
            kept_buf = np.empty((_CHUNK, width, lanes_of(b)))
        for k0 in range(0, n_steps, _CHUNK):
            steps = min(_CHUNK, n_steps - k0)
            if rngs is None:
                yield k0, np.zeros((steps, width, B))
            elif kernel_normals:
                _fill_stream_lanes(state, kept_buf[:steps], B, _ZKI, _ZWI, _ZFI)
                yield k0, kept_buf[:steps]
            else:
                yield k0, rngs[b].standard_normal((steps, width, B))

    if method == "fast":
        run_filter = fm is not None
        if fm is None:  # the kernel needs typed arrays even when the filter is off
            fm = FilterModel(np.zeros((n_steps, 1)), np.zeros(N + 1, np.int64),
                             np.zeros(1, np.int64), np.zeros((6, N)),
                             np.zeros(4, np.int64), np.zeros(1, np.int64),
                             np.zeros((n_steps, 3, N)), np.zeros(n_steps))

        def task(b: int) -> None:
            x = np.ascontiguousarray(Xp[b * B:b * B + lanes_of(b)].T)
            x[0] -= tm.off_b[0]
            x[1] -= tm.off_bd[0]
            xh = np.zeros_like(x)
            y = np.zeros_like(x)
            u = np.zeros(x.shape[1])
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

        store = _row_store(rows, store_every, est, tru, tm)

        for k0, noise in noise_chunks(b):
            _reference_block(k0, noise, tm, phi_of_step,
                             None if fm is None else fm.H[:fm.H.shape[0] // 2],
                             None if fm is None else fm.gains, X, Xh, store)
    return est, tru


# Runs with one random stream each; chunks of runs for an executor -------------------------------
def run_streams(seed: int, n_runs: int) -> list[np.random.Generator]:
    """The random streams of :func:`monte_carlo`'s runs: run ``i`` draws from an SFC64
    generator seeded by the ``i``-th child of ``numpy.random.SeedSequence(seed)``, first its
    initial state (10 normals, :func:`truth_prior_factor`), then its noise.

    Parameters
    ----------
    seed : int
        The Monte Carlo's seed (>= 0).
    n_runs : int
        Number of runs (>= 1).

    Returns
    -------
    list of numpy.random.Generator
        One per run; run ``i``'s is the same whatever ``n_runs``.

    Examples
    --------
    >>> from gyrolib import gc
    >>> a, b = gc.run_streams(7, 2)[1], gc.run_streams(7, 5)[1]
    >>> bool(a.standard_normal() == b.standard_normal())
    True
    """
    seed = v.check_int("seed", seed, 0)
    n_runs = v.check_int("n_runs", n_runs, 1)
    return [np.random.Generator(np.random.SFC64(child))
            for child in np.random.SeedSequence(seed).spawn(n_runs)]


def _run_inputs(tp: GyrocompassParams, seed: int, n_runs: int,
                inst: InstrumentModel | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Each run's initial state (n_runs × (10 + nb), from the truth's prior) and the state of
    its generator after drawing it (4 × n_runs ``uint64``: SFC64's ``a, b, c, counter``).
    The instrument constants of ``inst`` with a prior > 0 are drawn after the 10 states,
    from the same stream (none ON: the stream and the runs are those of the paper's
    model)."""
    L = truth_prior_factor(tp)
    nb = 0 if inst is None else inst.nb
    on = np.zeros(0, np.int64) if inst is None else np.nonzero(inst.prior > 0.0)[0]
    X0 = np.zeros((n_runs, N + nb))
    states = np.empty((4, n_runs), np.uint64)
    for i, gen in enumerate(run_streams(seed, n_runs)):
        X0[i, :N] = L @ gen.standard_normal(N)
        if on.size:
            X0[i, N + on] = inst.prior[on] * gen.standard_normal(on.size)
        states[:, i] = gen.bit_generator.state["state"]["state"]
    return X0, states


class _Prepared(NamedTuple):
    """What every chunk of runs needs: the truth's and the filter's arrays and the grid."""

    tm: TruthModel
    fm: FilterModel
    n_steps: int
    store_every: int
    method: str
    phi: object
    names: tuple[str, ...]


@dataclass(frozen=True)
class _Recipe:
    """How to build :class:`_Prepared` (small and picklable: what a worker process gets)."""

    params: GyrocompassParams
    truth_params: GyrocompassParams
    t_end: float
    store_every: int | None
    method: str
    linear: int
    substeps: int


def _instruments(r: _Recipe) -> tuple[InstrumentModel, InstrumentModel]:
    """The instrument constants of the filter and of the truth on one state vector: those
    ON in either (a constant OFF in one has prior 0 there: known to be 0)."""
    names = union_names(r.params, r.truth_params)
    return (build_instrument_model(r.params, names),
            build_instrument_model(r.truth_params, names))


def _prepare(r: _Recipe) -> tuple[_Prepared, np.ndarray]:
    """The filter's gains and model, the truth's arrays; and the filter's stored P."""
    p = r.params
    inst_f, inst_t = _instruments(r)
    cm = ContinuousModel.build(p, inst_f)
    disc = discretize_steps(cm, steps_in(p, r.t_end), "van_loan")
    se = default_store_every(disc.n_steps) if r.store_every is None else r.store_every
    mdl = disc.model
    P0 = cm.P0.copy()
    if r.method == "fast":
        run = covariance_fast(mdl, P0, se, keep_gains=True)
    else:
        run = covariance_reference(mdl, P0, se)
    tm = truth_model(r.truth_params, p, disc.n_steps, r.substeps, r.linear,
                     inst_t if inst_t.nb else None)
    rowptr, colidx = mdl.sparsity()
    hptr, hidx = mdl.measurement_sparsity()
    phis = np.empty((mdl.n_steps, colidx.size))
    if r.method == "fast":
        _step_phi(mdl.seg, mdl.a, mdl.b, mdl.Phi0, mdl.PhiA, mdl.PhiB, rowptr, colidx, phis)
    H1 = np.zeros_like(mdl.H) if mdl.H1 is None else mdl.H1
    fm = FilterModel(phis, rowptr, colidx, np.ascontiguousarray(np.vstack([mdl.H, H1])), hptr,
                     hidx, np.ascontiguousarray(run.gains),
                     np.zeros(mdl.n_steps) if mdl.h is None else mdl.h)
    phi = _LazyPhi(mdl) if r.method == "reference" else None
    return (_Prepared(tm, fm, disc.n_steps, se, r.method, phi, disc.state_names),
            run.P_stored)


@functools.lru_cache(maxsize=1)
def _prepared_in_worker(r: _Recipe) -> _Prepared:
    return _prepare(r)[0]


def _run_chunk(prep: _Prepared, X0: np.ndarray, states: np.ndarray) -> tuple[np.ndarray,
                                                                              np.ndarray]:
    """Truth and filter for the runs of one chunk (initial states ``X0``, generator states
    ``states``), a block of ``_RUN_BLOCK`` lanes after the other; ``(est, tru)``."""
    tm, fm, n_steps, se = prep.tm, prep.fm, prep.n_steps, prep.store_every
    n, B = X0.shape[0], _RUN_BLOCK
    ns = X0.shape[1]      # 10 states and the instrument constants
    width = 2 * tm.substeps + 3
    n_store = n_steps // se + 1
    est = np.zeros((n, n_store, ns))
    tru = np.zeros((n, n_store, ns))
    tru[:, 0] = X0
    for b in range(-(-n // B)):
        lanes = slice(b * B, min((b + 1) * B, n))
        nv = lanes.stop - lanes.start
        st = np.zeros((4, B), np.uint64)   # lanes past the last run: a dummy stream, unused
        st[:, :nv] = states[:, lanes]
        if prep.method == "fast":
            x = np.zeros((ns, B))
            x[:, :nv] = X0[lanes].T
            x[0] -= tm.off_b[0]
            x[1] -= tm.off_bd[0]
            _mc_block_run(n_steps, st, np.empty((_NOISE_CHUNK, width, B)),
                          np.empty(B, np.uint64), tm, fm, x, np.zeros_like(x),
                          np.zeros_like(x), np.zeros(B), se, est, tru, b * B, True,
                          _ZKI, _ZKI_SIGNED, _ZWI, _ZFI)
            continue
        # reference: numpy's own generators from the same states, per-run draws stacked
        gens = []
        for r in range(nv):
            bg = np.random.SFC64()
            bg.state = {"bit_generator": "SFC64", "state": {"state": st[:, r].copy()},
                        "has_uint32": 0, "uinteger": 0}
            gens.append(np.random.Generator(bg))
        X = np.zeros((B, ns))
        X[:nv] = X0[lanes]
        Xh = np.zeros_like(X)

        store = _row_store(lanes, se, est, tru, tm)

        for k0 in range(0, n_steps, _CHUNK):
            steps = min(_CHUNK, n_steps - k0)
            noise = np.zeros((steps, width, B))
            for r, gen in enumerate(gens):
                noise[:, :, r] = gen.standard_normal((steps, width))
            m = fm.H.shape[0] // 2
            _reference_block(k0, noise, tm, prep.phi, fm.H[:m], fm.gains, X, Xh, store,
                             fm.H[m:], fm.hs)
    return est, tru


class _ChunkTask:
    """One chunk of runs for an executor: ``task(X0, states) -> (est, tru)``.  Picklable:
    a worker process gets the recipe, not the arrays, and builds them once
    (:func:`_prepared_in_worker`); threads of this process use the arrays already built."""

    def __init__(self, recipe: _Recipe, prepared: _Prepared | None) -> None:
        self.recipe = recipe
        self.prepared = prepared

    def __getstate__(self) -> dict:
        return {"recipe": self.recipe, "prepared": None}

    def __call__(self, X0: np.ndarray, states: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        prep = self.prepared if self.prepared is not None else _prepared_in_worker(self.recipe)
        return _run_chunk(prep, X0, states)


#: Chunks of runs handed to a caller's executor: at most this many (each of whole blocks).
_EXECUTOR_CHUNKS: Final[int] = 16


def _run_all(task: _ChunkTask, X0: np.ndarray, states: np.ndarray, n_store: int,
             executor: Executor | None) -> tuple[np.ndarray, np.ndarray]:
    """All runs, in chunks of whole blocks: one block per chunk on this process's threads
    (``executor=None``), or up to :data:`_EXECUTOR_CHUNKS` chunks on ``executor``."""
    n = X0.shape[0]
    nb = -(-n // _RUN_BLOCK)
    per = 1 if executor is None else -(-nb // _EXECUTOR_CHUNKS)
    bounds = [(lo, min(lo + per * _RUN_BLOCK, n)) for lo in range(0, n, per * _RUN_BLOCK)]
    est = np.empty((n, n_store, X0.shape[1]))
    tru = np.empty((n, n_store, X0.shape[1]))

    def put(lo: int, hi: int, out: tuple[np.ndarray, np.ndarray]) -> None:
        est[lo:hi], tru[lo:hi] = out

    if executor is None:
        n_thr = min(_n_threads(), len(bounds))
        if n_thr == 1:
            for lo, hi in bounds:
                put(lo, hi, task(X0[lo:hi], states[:, lo:hi]))
            return est, tru
        pool = ThreadPoolExecutor(max_workers=n_thr)
    else:
        pool = executor
    try:
        # each chunk's arrays are copied in and released as soon as it is done: the chunks
        # never all live beside est and tru (which would double the memory of the result)
        pending = {pool.submit(task, X0[lo:hi], states[:, lo:hi]): (lo, hi)
                   for lo, hi in bounds}
        for fut in as_completed(pending):
            lo, hi = pending.pop(fut)
            put(lo, hi, fut.result())
            del fut
    finally:
        if executor is None:
            pool.shutdown()
    return est, tru


@compact_repr
@dataclass(frozen=True)
class MonteCarloResult:
    """Monte Carlo runs (paper GC, Figure 4): estimates and truth at ``t`` (every
    ``store_every`` samples), the filter's posterior covariance ``P`` at the same times, the
    filter's ``params``, the truth's ``truth_params`` (``None``: the same) and which of its
    torques were linearized (``truth_mode``: the ``truth`` of :func:`monte_carlo`).  The
    states are ``names``: Eq. (8)'s, then the instrument constants ON in the filter or the
    truth (:mod:`gyrolib.gc.model.instrument`; one OFF in the filter has estimate and σ 0,
    one OFF in the truth the true value 0)."""

    params: GyrocompassParams
    t: NDArray[np.float64]
    est: NDArray[np.float64]
    tru: NDArray[np.float64]
    P: NDArray[np.float64]
    seed: int
    truth_params: GyrocompassParams | None = None
    truth_mode: str = "nonlinear"
    names: tuple[str, ...] = STATE_NAMES

    def __post_init__(self) -> None:
        check_params(self.params)
        if self.truth_params is not None:
            v.check_instance("truth_params", self.truth_params, GyrocompassParams)
        v.check_choice("truth_mode", self.truth_mode, tuple(LINEARIZE))
        if not isinstance(self.names, tuple) or self.names[:N] != STATE_NAMES:
            raise ValueError("names must be a tuple that starts with STATE_NAMES")
        n = len(self.names)
        nt = v.check_ndarray("t", self.t, ndim=1).size
        runs = v.check_ndarray("est", self.est, shape=(None, nt, n)).shape[0]
        v.check_ndarray("tru", self.tru, shape=(runs, nt, n))
        v.check_ndarray("P", self.P, shape=(nt, n, n))
        v.check_int("seed", self.seed, 0)

    @property
    def n_runs(self) -> int:
        """Number of runs."""
        return int(self.est.shape[0])

    def estimate(self, name: str) -> NDArray[np.float64]:
        """Estimates of state ``name``, shape ``(n_runs, len(t))``, SI."""
        return self.est[:, :, augmented_index(self.names, name)]

    def truth(self, name: str) -> NDArray[np.float64]:
        """True values of state ``name``, shape ``(n_runs, len(t))``, SI."""
        return self.tru[:, :, augmented_index(self.names, name)]

    def error(self, name: str) -> NDArray[np.float64]:
        """Estimation error (estimate − truth) of state ``name``, ``(n_runs, len(t))``."""
        return self.estimate(name) - self.truth(name)

    def std(self, name: str) -> NDArray[np.float64]:
        """Filter standard deviation of state ``name`` at ``t`` (what the filter claims)."""
        i = augmented_index(self.names, name)
        return np.sqrt(np.clip(self.P[:, i, i], 0.0, None))

    def rms_error(self, name: str) -> NDArray[np.float64]:
        """Ensemble RMS of the estimation error of state ``name`` at ``t`` (what it gets)."""
        return np.sqrt(np.mean(self.error(name) ** 2, axis=0))

    def nees(self, names: tuple[str, ...] | None = None) -> NDArray[np.float64]:
        """Normalized estimation error squared per run and time, ``(n_runs, len(t))``,
        for the states ``names`` (default: the filter's, :func:`gyrolib.gc.state_names` of
        ``params``: the 10 of Eq. (8) and its instrument constants); ``nan`` where ``P`` of
        those states is singular (``t = 0`` when a state starts known)."""
        if isinstance(names, str) or not (names is None or isinstance(names, list | tuple)):
            raise TypeError("names must be a tuple or list of state names (or None); "
                            f"got {type(names).__name__}")
        names = state_names(self.params) if names is None else tuple(names)
        if not names:
            raise ValueError("names must name at least one state")
        idx = [augmented_index(self.names, nm) for nm in names]
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

    def mean_nees(self, names: tuple[str, ...] | None = None) -> NDArray[np.float64]:
        """Ensemble-average NEES of the states ``names`` (as :meth:`nees`) at ``t``."""
        return self.nees(names).mean(axis=0)

    def summary(self, states: tuple[str, ...] = ("omega_gc",),
                nees_sets: tuple[tuple[str, ...], ...] = ((), ("omega_gc",)),
                keep_runs: int = 2) -> MonteCarloSummary:
        """The ensemble statistics of these runs that a report reads, small enough to store
        (:class:`MonteCarloSummary`): σ and the RMS error of ``states`` at every stored time,
        the average NEES of each set of ``nees_sets`` (``()``: the filter's states), the
        histories of the first ``keep_runs`` runs, and every run's error and truth at the
        last time.

        Examples
        --------
        >>> from gyrolib import gc
        >>> mc = gc.monte_carlo(gc.GyrocompassParams(), 8, 0.5, seed=1, store_every=100)
        >>> s = mc.summary()
        >>> bool(s.rms_error("omega_gc")[-1] == mc.rms_error("omega_gc")[-1])
        True
        """
        states = tuple(states)
        for nm in states:
            augmented_index(self.names, nm)
        keep = min(v.check_int("keep_runs", keep_runs, 0), self.n_runs)
        sets = tuple(tuple(s) for s in nees_sets)
        return MonteCarloSummary(
            params=self.params, t=self.t, seed=self.seed, n_runs=self.n_runs,
            truth_params=self.truth_params, truth_mode=self.truth_mode, names=self.names,
            states=states,
            sigma=np.stack([self.std(nm) for nm in states], axis=1),
            rms=np.stack([self.rms_error(nm) for nm in states], axis=1),
            nees_sets=sets,
            nees_mean=np.stack([self.mean_nees(s or None) for s in sets]),
            runs_est=self.est[:keep][:, :, [augmented_index(self.names, n) for n in states]],
            runs_tru=self.tru[:keep][:, :, [augmented_index(self.names, n) for n in states]],
            end_error=self.est[:, -1] - self.tru[:, -1], end_truth=self.tru[:, -1])

    def select(self, runs: slice) -> MonteCarloResult:
        """The same Monte Carlo restricted to the runs ``runs`` (a slice of run indices), e.g.
        to compare disjoint sets of runs.

        Examples
        --------
        >>> from gyrolib import gc
        >>> mc = gc.monte_carlo(gc.GyrocompassParams(), 8, 0.01, seed=1)
        >>> mc.select(slice(0, 4)).n_runs
        4
        """
        if not isinstance(runs, slice):
            raise TypeError(f"runs must be a slice of run indices; got {type(runs).__name__}")
        idx = range(self.n_runs)[runs]
        if len(idx) == 0:
            raise ValueError(f"runs must select at least one of the {self.n_runs} runs; "
                             f"got {runs}")
        return dataclasses.replace(self, est=self.est[runs], tru=self.tru[runs])

    def inside_share(self, names: tuple[str, ...] | None = None,
                     confidence: float = 0.95) -> float:
        """Share of the stored times ``t > 0`` at which the ensemble-average NEES of
        ``names`` (default: the filter's states, as :meth:`nees`) lies in its two-sided
        chi-square band of one time {cite:p}`BarShalom2001`.  A consistent filter is inside
        at ``confidence`` of the times on average; neighbouring times are correlated, so the
        share of one set of runs scatters widely around that.

        Examples
        --------
        >>> from gyrolib import gc
        >>> mc = gc.monte_carlo(gc.GyrocompassParams(), 64, 1.0, seed=1, store_every=100)
        >>> 0.0 <= mc.inside_share(("omega_gc",)) <= 1.0
        True
        """
        conf = v.check_in_range("confidence", confidence, 0.0, 1.0, low_open=True,
                                high_open=True)
        x = self.nees(names).mean(axis=0)[1:]
        dof = len(state_names(self.params)) if names is None else len(names)
        lo, hi = nees_bounds(dof, self.n_runs, conf)
        return float(np.mean((x > lo) & (x < hi)))


@compact_repr
@dataclass(frozen=True)
class MonteCarloSummary:
    """What a report reads of a :class:`MonteCarloResult` (its :meth:`~MonteCarloResult.summary`),
    small enough to store: at the stored times ``t``, the filter's σ (``sigma``) and the
    ensemble RMS error (``rms``) of the states ``states`` (time × state), the
    ensemble-average NEES (``nees_mean``, set × time) of each set of states of ``nees_sets``
    (``()``: the filter's states), the histories of the first runs (``runs_est``,
    ``runs_tru``: run × time × state of ``states``), and every run's error and truth at the
    last time (``end_error``, ``end_truth``: run × state of ``names``).  It answers
    :meth:`std`, :meth:`rms_error`, :meth:`mean_nees`, :meth:`inside_share` and, for the
    kept runs, :meth:`estimate` and :meth:`truth` as the result itself does."""

    params: GyrocompassParams
    t: NDArray[np.float64]
    seed: int
    n_runs: int
    truth_params: GyrocompassParams | None
    truth_mode: str
    names: tuple[str, ...]
    states: tuple[str, ...]
    sigma: NDArray[np.float64]
    rms: NDArray[np.float64]
    nees_sets: tuple[tuple[str, ...], ...]
    nees_mean: NDArray[np.float64]
    runs_est: NDArray[np.float64]
    runs_tru: NDArray[np.float64]
    end_error: NDArray[np.float64]
    end_truth: NDArray[np.float64]

    def __post_init__(self) -> None:
        check_params(self.params)
        nt = v.check_ndarray("t", self.t, ndim=1).size
        k, n = len(self.states), len(self.names)
        v.check_ndarray("sigma", self.sigma, shape=(nt, k))
        v.check_ndarray("rms", self.rms, shape=(nt, k))
        if np.shape(self.nees_mean) != (len(self.nees_sets), nt):   # nan where P is singular
            raise ValueError(f"nees_mean must have shape ({len(self.nees_sets)}, {nt}); got "
                             f"{np.shape(self.nees_mean)}")
        m = v.check_ndarray("runs_est", self.runs_est, shape=(None, nt, k)).shape[0]
        v.check_ndarray("runs_tru", self.runs_tru, shape=(m, nt, k))
        v.check_ndarray("end_error", self.end_error, shape=(self.n_runs, n))
        v.check_ndarray("end_truth", self.end_truth, shape=(self.n_runs, n))

    def _col(self, name: str) -> int:
        if name not in self.states:
            raise ValueError(f"name must be one of the summary's states {self.states}; "
                             f"got {name!r}")
        return self.states.index(name)

    def std(self, name: str) -> NDArray[np.float64]:
        """The filter's σ of ``name`` at ``t`` (as :meth:`MonteCarloResult.std`)."""
        return self.sigma[:, self._col(name)]

    def rms_error(self, name: str) -> NDArray[np.float64]:
        """The ensemble RMS error of ``name`` at ``t`` (as :meth:`MonteCarloResult.rms_error`)."""
        return self.rms[:, self._col(name)]

    def mean_nees(self, names: tuple[str, ...] | None = None) -> NDArray[np.float64]:
        """The ensemble-average NEES of ``names`` (``None``: the filter's states) at ``t``."""
        key = () if names is None else tuple(names)
        if key not in self.nees_sets:
            raise ValueError(f"names must be one of the summary's NEES sets {self.nees_sets} "
                             f"(() for the filter's states); got {names!r}")
        return self.nees_mean[self.nees_sets.index(key)]

    def inside_share(self, names: tuple[str, ...] | None = None,
                     confidence: float = 0.95) -> float:
        """As :meth:`MonteCarloResult.inside_share`, from the stored average NEES."""
        conf = v.check_in_range("confidence", confidence, 0.0, 1.0, low_open=True,
                                high_open=True)
        x = self.mean_nees(names)[1:]
        dof = len(state_names(self.params)) if names is None else len(names)
        lo, hi = nees_bounds(dof, self.n_runs, conf)
        return float(np.mean((x > lo) & (x < hi)))

    def estimate(self, name: str) -> NDArray[np.float64]:
        """Estimates of ``name`` in the kept runs, ``(kept runs, len(t))``."""
        return self.runs_est[:, :, self._col(name)]

    def truth(self, name: str) -> NDArray[np.float64]:
        """True values of ``name`` in the kept runs, ``(kept runs, len(t))``."""
        return self.runs_tru[:, :, self._col(name)]

    def error_end(self, name: str) -> NDArray[np.float64]:
        """Every run's error of ``name`` at the last time, ``(n_runs,)``."""
        return self.end_error[:, augmented_index(self.names, name)]

    def truth_end(self, name: str) -> NDArray[np.float64]:
        """Every run's true ``name`` at the last time, ``(n_runs,)``."""
        return self.end_truth[:, augmented_index(self.names, name)]


def monte_carlo(params: GyrocompassParams, n_runs: int, t_end: float = 100.0,
                seed: int = 0, *, truth_params: GyrocompassParams | None = None,
                store_every: int | None = None, method: str = "fast",
                truth: str = "nonlinear", substeps: int = TRUTH_SUBSTEPS,
                executor: Executor | None = None) -> MonteCarloResult:
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
        Seed (>= 0); run ``i`` draws from its own stream (:func:`run_streams`), so it is the
        same whatever ``n_runs``, the executor and the number of threads or processes.
    truth_params : GyrocompassParams, optional
        The truth's parameters (default: the filter's); they must share ``dt``.  The initial
        states are drawn from the truth's prior, and after them, from the same stream, the
        instrument constants ON in the truth (:func:`gyrolib.gc.instrument_model`: a prior
        ``sigma_as_offset``, ``sigma_incl_bias`` or ``sigma_hf_scale`` > 0), which its
        samples then read; the filter carries the constants ON in ``params`` as states.
    store_every : int, optional
        Store every ``store_every``-th sample (default: about 1000 stored times).
    method : {"fast", "reference"}
        ``"fast"``: numba, blocks of runs in parallel; ``"reference"``: plain numpy, the
        same random numbers (a second implementation for the tests).
    truth : {"nonlinear", "linear", "linear_horizontal", "linear_tilt"}
        ``"linear"`` replaces the torques of Eq. (3) by their linearization about the nominal
        (Eq. (5)), to isolate the effect of the nonlinearity; ``"linear_horizontal"`` only
        the horizontal-rate term ``Ω_h cos(β − ψ)``, ``"linear_tilt"`` only the tilt terms
        ``Ω_v (γ cos β − δ sin β)``.
    substeps : int
        Fine steps of the truth per sample (>= 1).
    executor : concurrent.futures.Executor, optional
        Where the runs go, in up to 16 chunks of whole blocks of 32 runs (a
        ``ProcessPoolExecutor``'s workers build the model once each, from the parameters).
        Default: this process, its blocks on one thread per core (the kernels release the
        GIL; a standard-library thread pool for the call, closed before it returns).

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
    p = check_params(params)
    tp = p if truth_params is None else v.check_instance("truth_params", truth_params,
                                                         GyrocompassParams)
    if tp.dt != p.dt:
        raise ValueError(f"truth_params.dt must equal params.dt={p.dt}; got {tp.dt}")
    n_runs = v.check_int("n_runs", n_runs, 1)
    seed = v.check_int("seed", seed, 0)
    v.check_choice("method", method, ("fast", "reference"))
    v.check_choice("truth", truth, tuple(LINEARIZE))
    substeps = v.check_int("substeps", substeps, 1)
    executor = check_executor(executor)
    n_steps = steps_in(p, t_end)
    if store_every is not None:
        store_every = v.check_int("store_every", store_every, 1)
    recipe = _Recipe(p, tp, float(t_end), store_every, method, LINEARIZE[truth], substeps)
    for inst in _instruments(recipe):
        coupled = [nm for nm, col in zip(inst.names, inst.Fb.T, strict=True) if np.any(col)]
        if coupled:
            raise ValueError(f"params: the Monte Carlo's truth reads the instrument constants "
                             f"in its samples only; a term with a dynamics column Fb != 0 "
                             f"({', '.join(coupled)}) is not supported")
    prep, P_stored = _prepare(recipe)
    X0, states = _run_inputs(tp, seed, n_runs, _instruments(recipe)[1])
    est, tru = _run_all(_ChunkTask(recipe, prep), X0, states,
                        n_steps // prep.store_every + 1, executor)
    se = prep.store_every
    return MonteCarloResult(params=p, t=np.arange(0, n_steps + 1, se) * p.dt, est=est,
                            tru=tru, P=P_stored, seed=int(seed),
                            truth_params=None if truth_params is None else tp,
                            truth_mode=truth, names=prep.names)


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
    """The truth model of :func:`monte_carlo` alone, from the state ``x0`` (length 10, SI),
    or from each row of ``x0`` (shape ``(n, 10)``: ``n`` runs at once).

    Its noise comes from the seed's generator as the previous Monte Carlo path drew it (one
    SFC64 stream per block of 32 lanes, this run in lane 0), so the sample records of
    ``data/`` made with it stay as they are; the model integrated is the same.  The stream
    is drawn in the kernel with numpy's algorithm (its numbers to the ziggurat tables'
    1e-14, as :func:`monte_carlo`'s), keeping lane 0 only.  With ``n`` rows, run ``i``
    takes lane ``i`` of the streams (its block's, 32 runs a block): run 0 is the run of
    ``x0[0]`` alone, and the other lanes, drawn and integrated anyway, cost little more
    (20 runs of 100 s: 1.3 CPU-s, one run 0.8).

    Parameters
    ----------
    params : GyrocompassParams
        The truth's parameters.
    t_end : float
        Length (s), a multiple of ``params.dt``.
    x0 : array_like
        Initial state (10, SI) in the filter's coordinates (Δβ from the nominal of Eq. (4)),
        or one per run, ``(n, 10)``.
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
        States, shape ``(len(t), 10)``; ``(n, len(t), 10)`` for ``n`` initial states.

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import gc
    >>> x0 = np.zeros(10); x0[3] = 1e-6   # a drift of 1e-6 rad/s, everything else at rest
    >>> t, X = gc.simulate_truth(gc.GyrocompassParams(), 1.0, x0)
    >>> f"{X[-1, 0]:.4g}"   # Δβ ≈ (H/f) ω_gc (t − I/f) after the float's time constant
    '1.997e-06'
    """
    p = check_params(params)
    x0 = v.check_array("x0", x0)
    if x0.shape != (N,) and not (x0.ndim == 2 and x0.shape[1] == N and x0.shape[0] >= 1):
        raise ValueError(f"x0 must have shape ({N},) or (n, {N}); got {x0.shape}")
    store_every = v.check_int("store_every", store_every, 1)
    seed = None if seed is None else v.check_int("seed", seed, 0)
    substeps = v.check_int("substeps", substeps, 1)
    n_steps = steps_in(p, t_end)
    tm = truth_model(p, p, n_steps, substeps)
    rng = None if seed is None else np.random.default_rng(seed)
    _, tru = _run_batch(tm, n_steps, np.atleast_2d(x0), rng, None, store_every, "fast",
                        kernel_normals=True)
    return np.arange(0, n_steps + 1, store_every) * p.dt, (tru[0] if x0.ndim == 1 else tru)
