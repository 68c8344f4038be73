"""Paper GC applied to a measurement record: the 10-state Kalman filter of Eq. (8) run on
the angle-sensor and inclinometer readings of a gyro in gyrocompass mode (:func:`calibrate`).

The filter is the one of the covariance analysis (:func:`gyrolib.gc.covariance_analysis`):
``F`` frozen at the nominal float angle ``β_n`` of each step's midpoint, exact Van Loan
transition and process noise expanded to first order in ``(sin β_n, cos β_n)`` about points
:data:`gyrolib.gc.SEGMENT` rad apart, sequential scalar Joseph updates.  On a record it
also

* subtracts the nominal motion ``β_n(t)`` (Eq. (4), from rest at t = 0, integrated along the
  record by the exponential integrator of :func:`gyrolib.gc.nominal_half_steps`) from the
  angle sensor, which then reads ``Δβ``;
* discretizes a step that is not the nominal ``dt`` at its own length: a gap of ``n`` whole
  steps plus a remainder is ``n`` predictions at ``dt`` (no update) and one exact Van Loan
  step of the remainder; a step within 5 % of ``n dt`` (time-stamp jitter) is ``n`` regular
  steps and a short shift ``exp(F δ)`` (Taylor series, exact to O(δ³) in the process
  noise), which costs little more than a regular step;
* skips a missing (NaN) measurement, and rejects a measurement whose normalized innovation
  squared ``ν²/S`` exceeds the χ²(1) quantile of ``gate`` (default 99.99 %), reporting it;
* keeps the diagnostics that say whether the model fits the gyro: the mean normalized
  innovation squared (NIS) of each sensor against its χ² band, and the autocorrelation of
  the normalized innovations (whiteness, a portmanteau test) {cite:p}`BarShalom2001`;
* streams: the record is processed in chunks with a constant-size state (``x``, ``P``, the
  nominal motion's integrator state), and estimates and σ are stored every ``store_every``
  rows.  A chunked run equals a one-shot run.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import Final

import numpy as np
import scipy.linalg
import scipy.stats
from numba import njit

from gyrolib import _validation as v
from gyrolib.filtering.discretization import van_loan, van_loan_derivatives
from gyrolib.gc.discretization import SEGMENT, _affine_parts, _etd2_advance, _etd2_coefficients
from gyrolib.gc.params import MEASUREMENT_NAMES, STATE_NAMES, GyrocompassParams, state_index
from gyrolib.gc.record import GCRecord
from gyrolib.gc.state_space import (
    initial_covariance,
    measurement_matrix,
    measurement_noise_covariance,
    noise_input_matrix,
    process_noise_intensity,
)

__all__ = [
    "CalibrationResult",
    "SimulatedRecord",
    "calibrate",
    "plot_calibration",
    "simulate_record",
]

N: Final[int] = len(STATE_NAMES)
M: Final[int] = len(MEASUREMENT_NAMES)

#: A step within this fraction of ``dt`` of a whole number of ``dt`` (time-stamp jitter) is
#: propagated by the regular steps and a short Taylor shift, not a matrix exponential.
SMALL_SHIFT: Final[float] = 0.05

#: Rejected measurements listed individually in a result (all are counted).
MAX_LISTED_REJECTIONS: Final[int] = 10000


# Result ---------------------------------------------------------------------------------
@dataclass(frozen=True)
class CalibrationResult:
    """The filter of paper GC run on a record (SI throughout).

    * ``t`` (ns,), ``x`` (ns, 10), ``std`` (ns, 10): estimate and σ of every state (order
      :data:`gyrolib.gc.STATE_NAMES`) every ``store_every`` rows and at the last row;
      ``nis_window`` (ns, 3): mean NIS of each sensor over the rows since the previous stored
      point (``nan`` where none), ``nis_window_count`` (ns, 3) how many;
    * ``x_final``, ``P_final``, ``t_final``: the filter at the last row;
    * ``rows``; per sensor (3,): ``used``, ``missing`` (NaN), ``rejected`` (gate);
      ``rows_used`` (rows with at least one measurement used), ``rows_rejected`` (rows with at
      least one rejected); ``rejected_t``, ``rejected_sensor``, ``rejected_nis``: the first
      :data:`MAX_LISTED_REJECTIONS` rejections;
    * ``nis_sum`` (3,): sum of the NIS of the used measurements; ``acf`` (3, lags): the
      autocorrelation at lags 1…lags of each sensor's normalized innovations ``ν/√S``;
    * ``gaps`` (steps longer than 1.5 ``dt``), ``gap_time`` (s of missing rows),
      ``irregular_steps`` (remainders discretized exactly at their own length),
      ``jittered_steps`` (steps within 5 % of a whole number of ``dt``, shifted in time),
      ``gate`` (probability).
    """

    params: GyrocompassParams
    t: np.ndarray
    x: np.ndarray
    std: np.ndarray
    nis_window: np.ndarray
    nis_window_count: np.ndarray
    x_final: np.ndarray
    P_final: np.ndarray
    t_final: float
    rows: int
    used: np.ndarray
    missing: np.ndarray
    rejected: np.ndarray
    rows_used: int
    rows_rejected: int
    rejected_t: np.ndarray
    rejected_sensor: np.ndarray
    rejected_nis: np.ndarray
    nis_sum: np.ndarray
    acf: np.ndarray
    gaps: int
    gap_time: float
    irregular_steps: int
    jittered_steps: int
    gate: float
    store_every: int

    def __post_init__(self) -> None:
        v.check_instance("params", self.params, GyrocompassParams)
        ns = v.check_ndarray("t", self.t, ndim=1).size
        v.check_ndarray("x", self.x, shape=(ns, N))
        v.check_ndarray("std", self.std, shape=(ns, N))
        v.check_ndarray("x_final", self.x_final, shape=(N,))
        v.check_ndarray("P_final", self.P_final, shape=(N, N))
        for name in ("used", "missing", "rejected", "nis_sum"):
            if np.shape(getattr(self, name)) != (M,):
                raise ValueError(f"{name} must have shape ({M},)")

    # estimates -----------------------------------------------------------------------
    def estimate(self, name: str) -> np.ndarray:
        """Stored estimates of state ``name`` (SI) at ``t``."""
        return self.x[:, state_index(name)]

    def sigma(self, name: str) -> np.ndarray:
        """Stored filter standard deviations of state ``name`` (SI) at ``t``."""
        return self.std[:, state_index(name)]

    @property
    def omega_gc(self) -> float:
        """Final estimate of the systematic drift ω_gc (rad/s)."""
        return float(self.x_final[state_index("omega_gc")])

    @property
    def omega_gc_std(self) -> float:
        """Its standard deviation (rad/s) from the filter's covariance."""
        i = state_index("omega_gc")
        return float(math.sqrt(max(self.P_final[i, i], 0.0)))

    # diagnostics ---------------------------------------------------------------------
    @property
    def nis_mean(self) -> np.ndarray:
        """Mean NIS of each sensor over its used measurements (1 when the model fits)."""
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(self.used > 0, self.nis_sum / np.maximum(self.used, 1), np.nan)

    def nis_band(self, confidence: float = 0.99) -> np.ndarray:
        """(3, 2): two-sided ``confidence`` band of the mean NIS of ``used[q]`` independent
        χ²(1) values, ``χ²_{(1∓c)/2}(n)/n``."""
        c = v.check_in_range("confidence", confidence, 0.0, 1.0, low_open=True,
                             high_open=True)
        n = np.maximum(self.used, 1).astype(float)
        lo = scipy.stats.chi2.ppf(0.5 * (1.0 - c), n) / n
        hi = scipy.stats.chi2.ppf(0.5 * (1.0 + c), n) / n
        return np.column_stack([lo, hi])

    @property
    def whiteness(self) -> np.ndarray:
        """(3,): the portmanteau statistic ``n Σ_l ρ_l²`` of each sensor's normalized
        innovations (χ²(lags) when they are white)."""
        return self.used * np.sum(self.acf**2, axis=1)

    def whiteness_limit(self, confidence: float = 0.99) -> float:
        """The χ²(lags) quantile the :attr:`whiteness` statistic stays below when white."""
        c = v.check_in_range("confidence", confidence, 0.0, 1.0, low_open=True,
                             high_open=True)
        return float(scipy.stats.chi2.ppf(c, self.acf.shape[1]))

    def fits(self, confidence: float = 0.99) -> np.ndarray:
        """(3,) bool: each sensor's mean NIS is in its band and its innovations are white."""
        band = self.nis_band(confidence)
        nis = self.nis_mean
        ok = (nis >= band[:, 0]) & (nis <= band[:, 1])
        return ok & (self.whiteness <= self.whiteness_limit(confidence)) & (self.used > 0)

    def verdict(self, confidence: float = 0.99) -> str:
        """One line: does the model fit the record (NIS in band, innovations white)?"""
        ok = self.fits(confidence)
        if np.all(ok):
            return (f"model fits: every sensor's mean NIS is inside its {confidence:.0%} "
                    "chi-square band and its innovations are white")
        band = self.nis_band(confidence)
        parts = []
        for q, name in enumerate(MEASUREMENT_NAMES):
            if ok[q]:
                continue
            if self.used[q] == 0:
                parts.append(f"{name} has no usable measurement")
                continue
            nis = self.nis_mean[q]
            if nis > band[q, 1]:
                parts.append(f"{name} NIS {nis:.3g} above its band (<= {band[q, 1]:.3g})")
            elif nis < band[q, 0]:
                parts.append(f"{name} NIS {nis:.3g} below its band (>= {band[q, 0]:.3g})")
            if self.whiteness[q] > self.whiteness_limit(confidence):
                parts.append(f"{name} innovations correlated (portmanteau "
                             f"{self.whiteness[q]:.3g} > {self.whiteness_limit(confidence):.3g})")
        return "model does NOT fit: " + "; ".join(parts)

    def summary(self) -> dict:
        """The result as a JSON-ready dict (SI; a value that is not finite is ``None``)."""
        band = self.nis_band()
        return {
            "omega_gc": self.omega_gc,
            "omega_gc_std": self.omega_gc_std,
            "t_end": self.t_final,
            "rows": self.rows,
            "samples_used": self.rows_used,
            "samples_rejected": self.rows_rejected,
            "measurements": {name: {"used": int(self.used[q]), "missing": int(self.missing[q]),
                                    "rejected": int(self.rejected[q])}
                             for q, name in enumerate(MEASUREMENT_NAMES)},
            "nis": {name: _finite(self.nis_mean[q]) for q, name in enumerate(MEASUREMENT_NAMES)},
            "nis_band": {name: [_finite(band[q, 0]), _finite(band[q, 1])]
                         for q, name in enumerate(MEASUREMENT_NAMES)},
            "whiteness": {name: float(self.whiteness[q])
                          for q, name in enumerate(MEASUREMENT_NAMES)},
            "whiteness_limit": self.whiteness_limit(),
            "model_fits": bool(np.all(self.fits())),
            "verdict": self.verdict(),
            "gate": self.gate,
            "gaps": self.gaps,
            "gap_time": self.gap_time,
            "irregular_steps": self.irregular_steps,
            "jittered_steps": self.jittered_steps,
            "rejected_t": [float(x) for x in self.rejected_t[:100]],
            "states": {name: {"estimate": float(self.x_final[i]),
                              "std": float(math.sqrt(max(self.P_final[i, i], 0.0)))}
                       for i, name in enumerate(STATE_NAMES)},
        }


def _finite(x: float) -> float | None:
    """``x`` as a float, or ``None`` when it is not finite (JSON has no NaN)."""
    x = float(x)
    return x if math.isfinite(x) else None


# Nominal motion along the record ------------------------------------------------------------
class _Nominal:
    """β_n(t) of Eq. (4) on the half-step grid ``i dt/2``, integrated forward on demand and
    kept only over the window the current chunk needs (constant memory)."""

    def __init__(self, p: GyrocompassParams) -> None:
        self.hh = 0.5 * p.dt
        self.E, self.p1, self.p2, self.kdd = _etd2_coefficients(p)
        self.y = np.zeros(2)        # state at grid index self.end
        self.start = 0              # grid index of buf[0]
        self.end = 0                # grid index of buf[-1]
        self.buf = np.zeros(1)

    def window(self, t_lo: float, t_hi: float) -> tuple[np.ndarray, int]:
        """β on the grid from ≤ ``t_lo`` to ≥ ``t_hi`` and the grid index of its first value."""
        lo = max(math.floor(t_lo / self.hh) - 1, 0)
        hi = math.ceil(t_hi / self.hh) + 2
        empty = np.zeros(0)
        if lo > self.end:
            _etd2_advance(self.E, self.p1, self.p2, self.kdd, self.y, lo - self.end, empty)
            self.buf = np.array([self.y[0]])
            self.start = self.end = lo
        elif lo > self.start:
            self.buf = self.buf[lo - self.start:]
            self.start = lo
        if hi > self.end:
            new = np.empty(hi - self.end)
            _etd2_advance(self.E, self.p1, self.p2, self.kdd, self.y, hi - self.end, new)
            self.buf = np.concatenate([self.buf, new])
            self.end = hi
        return self.buf, self.start


# The filter kernel ----------------------------------------------------------------------
@njit(cache=True, inline="always")
def _beta_at(t, grid, g0, inv_hh):
    u = t * inv_hh - g0
    i = int(math.floor(u))  # noqa: RUF046 - numba: make the index an integer
    if i < 0:
        i = 0
    if i > grid.shape[0] - 2:
        i = grid.shape[0] - 2
    f = u - i
    return grid[i] * (1.0 - f) + grid[i + 1] * f


@njit(cache=True)
def _predict(x, P, Phi, Qd, T, y):
    n = x.shape[0]
    for i in range(n):
        s = 0.0
        for c in range(n):
            s += Phi[i, c] * x[c]
        y[i] = s
    for i in range(n):
        x[i] = y[i]
    for i in range(n):
        for col in range(n):
            s = 0.0
            for c in range(n):
                s += Phi[i, c] * P[c, col]
            T[i, col] = s
    for i in range(n):
        for jj in range(i, n):
            s = Qd[i, jj]
            for c in range(n):
                s += T[i, c] * Phi[jj, c]
            P[i, jj] = s
            P[jj, i] = s


@njit(cache=True)
def _shift(x, P, F, W, d, E, A, T, y):
    """Move the state and covariance on by a short time ``d`` (either sign, |F d| ≪ 1):
    ``E = exp(F d)`` (Taylor to 4th order), ``x ← E x``, ``P ← E (P + Q̃) Eᵀ`` with
    ``Q̃ = d W − d²/2 (F W + W Fᵀ)``, ``W = G Q Gᵀ``: exact to O(d³) for both signs, since
    ``Qd(h + d) = E (Qd(h) + Q̃) Eᵀ``."""
    n = x.shape[0]
    for i in range(n):
        for j in range(n):
            A[i, j] = F[i, j] * d
    # E = I + A (I + A/2 (I + A/3 (I + A/4)))  (Horner)
    for i in range(n):
        for j in range(n):
            E[i, j] = (1.0 if i == j else 0.0) + A[i, j] * 0.25
    for k in (3.0, 2.0, 1.0):
        for i in range(n):
            for j in range(n):
                s = 0.0
                for c in range(n):
                    s += A[i, c] * E[c, j]
                T[i, j] = (1.0 if i == j else 0.0) + s / k
        for i in range(n):
            for j in range(n):
                E[i, j] = T[i, j]
    # P + Q̃
    for i in range(n):
        for j in range(n):
            fw = 0.0
            wf = 0.0
            for c in range(n):
                fw += F[i, c] * W[c, j]
                wf += W[i, c] * F[j, c]
            A[i, j] = P[i, j] + d * W[i, j] - 0.5 * d * d * (fw + wf)
    for i in range(n):
        sx = 0.0
        for c in range(n):
            sx += E[i, c] * x[c]
        y[i] = sx
    for i in range(n):
        x[i] = y[i]
    for i in range(n):
        for j in range(n):
            sm = 0.0
            for c in range(n):
                sm += E[i, c] * A[c, j]
            T[i, j] = sm
    for i in range(n):
        for j in range(i, n):
            sm = 0.0
            for c in range(n):
                sm += T[i, c] * E[j, c]
            P[i, j] = sm
            P[j, i] = sm


@njit(cache=True)
def _filter_chunk(t, z, grid, g0, inv_hh, dt, n_whole, shift, Fc, Es, Ec, W, irr_idx,
                  irr_phi, irr_qd,
                  Phi0, PhiA, PhiB, Qd0, QdA, QdB, seg_w, H, r, gate, x, P, tcur,
                  row0, store_every, st_t, st_x, st_s, st_nis, st_cnt, n_st,
                  used, missing, rejected, rows_ur, nis_sum, ring, ring_n, acf_sum, acf_sq,
                  rej_t, rej_q, rej_nis, n_rej, win_sum, win_cnt):
    """Predict and update over the rows of one chunk (state arrays updated in place)."""
    n = x.shape[0]
    m = H.shape[0]
    L = ring.shape[1]
    Phi = np.zeros((n, n))
    Qd = np.zeros((n, n))
    T = np.zeros((n, n))
    y = np.zeros(n)
    Ph = np.zeros(n)
    kv = np.zeros(n)
    Fm = np.zeros((n, n))
    Em = np.zeros((n, n))
    Am = np.zeros((n, n))
    for i in range(t.shape[0]):
        # predict: whole steps of dt, then the remainder (exact, precomputed)
        for _ in range(n_whole[i]):
            bm = _beta_at(tcur[0] + 0.5 * dt, grid, g0, inv_hh)
            j = int(round(bm / seg_w))  # noqa: RUF046 - numba integer index
            a = math.sin(bm) - math.sin(j * seg_w)
            b = math.cos(bm) - math.cos(j * seg_w)
            for p in range(n):
                for c in range(n):
                    Phi[p, c] = Phi0[j, p, c] + a * PhiA[j, p, c] + b * PhiB[j, p, c]
                    Qd[p, c] = Qd0[j, p, c] + a * QdA[j, p, c] + b * QdB[j, p, c]
            _predict(x, P, Phi, Qd, T, y)
            tcur[0] += dt
        d = shift[i]
        if d != 0.0:   # a step of n·dt + d, |d| small: the regular steps, then shift by d
            bm = _beta_at(tcur[0] + 0.5 * d, grid, g0, inv_hh)
            sb = math.sin(bm)
            cb = math.cos(bm)
            for p in range(n):
                for c in range(n):
                    Fm[p, c] = Fc[p, c] + sb * Es[p, c] + cb * Ec[p, c]
            _shift(x, P, Fm, W, d, Em, Am, T, y)
        k = irr_idx[i]
        if k >= 0:
            _predict(x, P, irr_phi[k], irr_qd[k], T, y)
        tcur[0] = t[i]
        beta_n = _beta_at(t[i], grid, g0, inv_hh)
        any_used = False
        any_rej = False
        for q in range(m):
            zq = z[i, q]
            if math.isnan(zq):
                missing[q] += 1
                continue
            if q == 0:
                zq -= beta_n     # the angle sensor reads β = β_n + Δβ
            hx = 0.0
            for c in range(n):
                hx += H[q, c] * x[c]
            for p in range(n):
                s = 0.0
                for c in range(n):
                    s += P[p, c] * H[q, c]
                Ph[p] = s
            hPh = 0.0
            for c in range(n):
                hPh += H[q, c] * Ph[c]
            S = hPh + r[q]
            nu = zq - hx
            nis = nu * nu / S
            if nis > gate:
                rejected[q] += 1
                any_rej = True
                kk = n_rej[0]
                if kk < rej_t.shape[0]:
                    rej_t[kk] = t[i]
                    rej_q[kk] = q
                    rej_nis[kk] = nis
                n_rej[0] = kk + 1
                continue
            any_used = True
            used[q] += 1
            nis_sum[q] += nis
            win_sum[q] += nis
            win_cnt[q] += 1
            e = nu / math.sqrt(S)
            acf_sq[q] += e * e
            cnt = ring_n[q]
            for lag in range(1, L + 1):
                if cnt >= lag:
                    acf_sum[q, lag - 1] += e * ring[q, (cnt - lag) % L]
            ring[q, cnt % L] = e
            ring_n[q] = cnt + 1
            inv = 1.0 / S
            for p in range(n):
                kv[p] = Ph[p] * inv
            for p in range(n):
                x[p] += kv[p] * nu
            for p in range(n):
                kp = kv[p]
                pp = Ph[p]
                for jj in range(p, n):
                    val = P[p, jj] - kp * Ph[jj] - pp * kv[jj] + S * kp * kv[jj]
                    P[p, jj] = val
                    P[jj, p] = val
        if any_used:
            rows_ur[0] += 1
        if any_rej:
            rows_ur[1] += 1
        row = row0 + i + 1
        if row % store_every == 0:
            ii = n_st[0]
            st_t[ii] = t[i]
            for p in range(n):
                st_x[ii, p] = x[p]
                st_s[ii, p] = math.sqrt(max(P[p, p], 0.0))
            for q in range(m):
                st_cnt[ii, q] = win_cnt[q]
                st_nis[ii, q] = win_sum[q] / win_cnt[q] if win_cnt[q] > 0 else math.nan
                win_sum[q] = 0.0
                win_cnt[q] = 0
            n_st[0] = ii + 1


# The calibrator (streaming state) ------------------------------------------------------------
class _Calibrator:
    """State of :func:`calibrate` between chunks."""

    def __init__(self, p: GyrocompassParams, *, store_every: int, gate: float, lags: int,
                 time_tolerance: float) -> None:
        self.p = p
        self.dt = p.dt
        self.tol = time_tolerance * p.dt
        self.store_every = store_every
        self.gate_prob = gate
        self.gate = float(scipy.stats.chi2.ppf(gate, 1))
        self.nominal = _Nominal(p)
        self.Fc, self.Es, self.Ec = _affine_parts(p)
        self.G = noise_input_matrix(p)
        self.Qc = process_noise_intensity(p)
        self.W = self.G @ self.Qc @ self.G.T
        J = math.ceil(math.pi / SEGMENT) + 2   # β_n stays in [0, π/2]; room to spare
        self.tables = np.zeros((6, J, N, N))
        self.have = np.zeros(J, dtype=bool)
        self.H = measurement_matrix(p)
        self.r = np.diag(measurement_noise_covariance(p)).copy()
        self.x = np.zeros(N)
        self.P = initial_covariance(p)
        self.tcur = np.zeros(1)
        self.rows = 0
        self.used = np.zeros(M, dtype=np.int64)
        self.missing = np.zeros(M, dtype=np.int64)
        self.rejected = np.zeros(M, dtype=np.int64)
        self.rows_ur = np.zeros(2, dtype=np.int64)
        self.nis_sum = np.zeros(M)
        self.ring = np.zeros((M, lags))
        self.ring_n = np.zeros(M, dtype=np.int64)
        self.acf_sum = np.zeros((M, lags))
        self.acf_sq = np.zeros(M)
        self.rej_t = np.zeros(MAX_LISTED_REJECTIONS)
        self.rej_q = np.zeros(MAX_LISTED_REJECTIONS, dtype=np.int64)
        self.rej_nis = np.zeros(MAX_LISTED_REJECTIONS)
        self.n_rej = np.zeros(1, dtype=np.int64)
        self.win_sum = np.zeros(M)
        self.win_cnt = np.zeros(M, dtype=np.int64)
        self.stored: list[tuple[np.ndarray, ...]] = []
        self.gaps = 0
        self.gap_time = 0.0
        self.irregular = 0
        self.shifted = 0

    def _table(self, j: int) -> None:
        if j < 0 or j >= self.have.size:
            raise ValueError(f"the nominal float angle left [0, π] (expansion point {j}); "
                             "check the parameters H, Omega_h, f, I")
        if self.have[j]:
            return
        F = self.Fc + math.sin(j * SEGMENT) * self.Es + math.cos(j * SEGMENT) * self.Ec
        Phi, Qd, (dPs, dPc), (dQs, dQc) = van_loan_derivatives(F, self.G, self.Qc, self.dt,
                                                               [self.Es, self.Ec])
        for k, arr in enumerate((Phi, dPs, dPc, Qd, dQs, dQc)):
            self.tables[k, j] = arr
        self.have[j] = True

    def feed(self, rec: GCRecord) -> None:
        t = rec.t
        if t[0] <= self.tcur[0] and self.rows > 0:
            raise ValueError(f"record chunks must continue in time: t = {t[0]} follows "
                             f"{self.tcur[0]}")
        prev = np.concatenate([[self.tcur[0]], t[:-1]])
        h = t - prev
        # a step near a whole number of dt (jitter, |d| <= SMALL_SHIFT dt): the regular
        # steps and a short shift; anything else: whole steps and an exact remainder step
        n_near = np.rint(h / self.dt)
        d = h - n_near * self.dt
        small = (np.abs(d) > self.tol) & (np.abs(d) <= SMALL_SHIFT * self.dt) & (n_near >= 1)
        n_whole = np.where(small, n_near,
                           np.floor((h + self.tol) / self.dt)).astype(np.int64)
        rem = h - n_whole * self.dt
        irregular = ~small & (rem > self.tol)
        shift = np.where(small, d, 0.0)
        if self.rows == 0 and t[0] == 0.0:   # a row at t = 0: update only
            n_whole[0] = 0
            irregular[0] = False
            shift[0] = 0.0
        self.shifted += int(np.count_nonzero(small))
        self.gaps += int(np.count_nonzero(h > 1.5 * self.dt))
        self.gap_time += float(np.sum(np.where(h > 1.5 * self.dt, h - self.dt, 0.0)))
        grid, g0 = self.nominal.window(float(prev[0]), float(t[-1]))
        jlo = round(float(grid[0]) / SEGMENT)
        jhi = round(float(grid[-1]) / SEGMENT)
        for j in range(min(jlo, jhi), max(jlo, jhi) + 1):
            self._table(j)
        irr_rows = np.nonzero(irregular)[0]
        irr_idx = np.full(t.size, -1, dtype=np.int64)
        irr_idx[irr_rows] = np.arange(irr_rows.size)
        irr_phi = np.zeros((irr_rows.size, N, N))
        irr_qd = np.zeros((irr_rows.size, N, N))
        if irr_rows.size:
            grid_t = (g0 + np.arange(grid.size)) * self.nominal.hh
            for k, i in enumerate(irr_rows):
                start = prev[i] + n_whole[i] * self.dt
                bm = float(np.interp(0.5 * (start + t[i]), grid_t, grid))
                F = self.Fc + math.sin(bm) * self.Es + math.cos(bm) * self.Ec
                irr_phi[k], irr_qd[k] = van_loan(F, self.G, self.Qc, float(rem[i]))
            self.irregular += int(irr_rows.size)
        z = np.ascontiguousarray(rec.measurements())
        n_store = t.size // self.store_every + 1
        st_t = np.zeros(n_store)
        st_x = np.zeros((n_store, N))
        st_s = np.zeros((n_store, N))
        st_nis = np.zeros((n_store, M))
        st_cnt = np.zeros((n_store, M), dtype=np.int64)
        n_st = np.zeros(1, dtype=np.int64)
        tb = self.tables
        _filter_chunk(t, z, grid, float(g0), 1.0 / self.nominal.hh, self.dt, n_whole, shift,
                      self.Fc, self.Es, self.Ec, self.W, irr_idx, irr_phi, irr_qd, tb[0], tb[1],
                      tb[2], tb[3], tb[4], tb[5], SEGMENT,
                      self.H, self.r, self.gate, self.x, self.P, self.tcur, self.rows,
                      self.store_every, st_t, st_x, st_s, st_nis, st_cnt, n_st, self.used,
                      self.missing, self.rejected, self.rows_ur, self.nis_sum, self.ring,
                      self.ring_n, self.acf_sum, self.acf_sq, self.rej_t, self.rej_q,
                      self.rej_nis, self.n_rej, self.win_sum, self.win_cnt)
        k = int(n_st[0])
        self.stored.append((st_t[:k].copy(), st_x[:k].copy(), st_s[:k].copy(),
                            st_nis[:k].copy(), st_cnt[:k].copy()))
        self.rows += t.size

    def result(self) -> CalibrationResult:
        if self.rows == 0:
            raise ValueError("record must hold at least one row")
        parts = list(self.stored)
        if self.rows % self.store_every:   # the last row is not a store point: add it
            with np.errstate(invalid="ignore", divide="ignore"):
                win = np.where(self.win_cnt > 0, self.win_sum / np.maximum(self.win_cnt, 1),
                               np.nan)
            parts.append((np.array([self.tcur[0]]), self.x[None, :].copy(),
                          np.sqrt(np.clip(np.diag(self.P), 0.0, None))[None, :], win[None, :],
                          self.win_cnt[None, :].copy()))
        cat = [np.concatenate([part[k] for part in parts]) for k in range(5)]
        with np.errstate(invalid="ignore", divide="ignore"):
            acf = np.where(self.acf_sq[:, None] > 0,
                           self.acf_sum / np.where(self.acf_sq > 0, self.acf_sq, 1.0)[:, None],
                           0.0)
        nr = min(int(self.n_rej[0]), MAX_LISTED_REJECTIONS)
        return CalibrationResult(
            params=self.p, t=cat[0], x=cat[1], std=cat[2], nis_window=cat[3],
            nis_window_count=cat[4], x_final=self.x.copy(), P_final=self.P.copy(),
            t_final=float(self.tcur[0]), rows=self.rows, used=self.used.copy(),
            missing=self.missing.copy(), rejected=self.rejected.copy(),
            rows_used=int(self.rows_ur[0]), rows_rejected=int(self.rows_ur[1]),
            rejected_t=self.rej_t[:nr].copy(), rejected_sensor=self.rej_q[:nr].copy(),
            rejected_nis=self.rej_nis[:nr].copy(), nis_sum=self.nis_sum.copy(), acf=acf,
            gaps=self.gaps, gap_time=self.gap_time, irregular_steps=self.irregular,
            jittered_steps=self.shifted, gate=self.gate_prob, store_every=self.store_every)


def _chunks(record: GCRecord, size: int):
    for s in range(0, record.n, size):
        sl = slice(s, s + size)
        yield GCRecord(t=record.t[sl], angle_sensor=record.angle_sensor[sl],
                       inclinometer_y=record.inclinometer_y[sl],
                       inclinometer_z=record.inclinometer_z[sl])


def calibrate(record: GCRecord | Iterable[GCRecord], params: GyrocompassParams | None = None,
              *, chunk_size: int = 65536, store_every: int = 100, gate: float = 0.9999,
              lags: int = 10, time_tolerance: float = 1e-6,
              progress: Callable[[int], None] | None = None) -> CalibrationResult:
    """Calibrate the systematic drift ω_gc of a floated gyro from a record (paper GC).

    Runs the 10-state Kalman filter of Eq. (8) on ``record`` (a :class:`GCRecord`, or an
    iterable of them in time order for a long record read in chunks, e.g.
    :class:`gyrolib.records.GCChunks`) with the model ``params`` (default: the paper's).
    See the module docstring for gaps, missing values, the gate and the diagnostics.

    Parameters
    ----------
    record : GCRecord or iterable of GCRecord
        Times ``t`` (s since the feedback was switched off, β = 0 then), angle sensor β
        (rad), inclinometers (m/s²).  NaN marks a missing measurement.
    params : GyrocompassParams, optional
        The model; ``params.dt`` is the nominal sample interval.
    chunk_size : int
        Rows per chunk when ``record`` is a single :class:`GCRecord`.
    store_every : int
        Store the estimates and σ every this many rows (and at the last row).
    gate : float
        Probability of the χ²(1) gate on each scalar innovation; beyond it a measurement is
        rejected (not used) and listed.
    lags : int
        Lags of the innovation autocorrelation (whiteness test).
    time_tolerance : float
        A step within ``time_tolerance · dt`` of a whole number of ``dt`` counts as whole
        steps; a step within 5 % of it is shifted by the difference, any other remainder is
        discretized exactly at its own length.
    progress : callable, optional
        Called with the number of rows processed after each chunk.

    Returns
    -------
    CalibrationResult
        ``omega_gc`` ± ``omega_gc_std`` (rad/s), every state over time, diagnostics.

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import gc
    >>> p = gc.GyrocompassParams()
    >>> t = np.arange(1, 201) * p.dt                     # 0.2 s of a gyro at rest in β_n
    >>> beta_n = gc.nominal_motion(p, t).beta
    >>> rec = gc.GCRecord(t=t, angle_sensor=beta_n, inclinometer_y=np.zeros(200),
    ...                   inclinometer_z=np.zeros(200))
    >>> res = gc.calibrate(rec, p)
    >>> res.rows, res.rows_used, bool(res.omega_gc_std < p.sigma_gc0)
    (200, 200, True)
    """
    p = GyrocompassParams() if params is None else v.check_instance(
        "params", params, GyrocompassParams)
    chunk_size = v.check_int("chunk_size", chunk_size, 1)
    store_every = v.check_int("store_every", store_every, 1)
    gate = v.check_in_range("gate", gate, 0.0, 1.0, low_open=True, high_open=True)
    lags = v.check_int("lags", lags, 1)
    time_tolerance = v.check_in_range("time_tolerance", time_tolerance, 0.0, 0.5)
    if progress is not None and not callable(progress):
        raise TypeError(f"progress must be callable or None; got {type(progress).__name__}")
    if isinstance(record, GCRecord):
        chunks: Iterable[GCRecord] = _chunks(record, chunk_size)
    elif isinstance(record, Iterable) and not isinstance(record,
                                                          str | bytes | dict | np.ndarray):
        chunks = record
    else:
        raise TypeError(f"record must be a GCRecord or an iterable of GCRecord chunks; got "
                        f"{type(record).__name__}")
    cal = _Calibrator(p, store_every=store_every, gate=gate, lags=lags,
                      time_tolerance=time_tolerance)
    for chunk in chunks:
        if not isinstance(chunk, GCRecord):
            raise TypeError(f"record chunks must be GCRecord; got {type(chunk).__name__}")
        cal.feed(chunk)
        if progress is not None:
            progress(cal.rows)
    return cal.result()


# Simulated records --------------------------------------------------------------------------
@dataclass(frozen=True)
class SimulatedRecord:
    """A record made by the truth model (:func:`gyrolib.gc.simulate_truth`) with its truth:
    ``record`` (rows at ``t = k dt``, ``k = 1 … n``), ``truth`` (n+1, 10) the true states at
    ``t = k dt``, ``k = 0 … n``, ``params`` the model simulated, ``seed``."""

    record: GCRecord
    truth: np.ndarray
    params: GyrocompassParams
    seed: int

    def __post_init__(self) -> None:
        v.check_instance("record", self.record, GCRecord)
        v.check_ndarray("truth", self.truth, shape=(None, N))
        v.check_instance("params", self.params, GyrocompassParams)
        v.check_int("seed", self.seed, 0)

    @property
    def omega_gc(self) -> float:
        """The true systematic drift (rad/s)."""
        return float(self.truth[0, state_index("omega_gc")])


def simulate_record(params: GyrocompassParams, t_end: float, seed: int) -> SimulatedRecord:
    """A seeded record of paper GC's truth model (nonlinear Eq. (3) with the shaping filters)
    over ``(0, t_end]`` at ``params.dt``, in the columns of a :class:`GCRecord`.

    The initial state is drawn from ``P(0)`` (:func:`gyrolib.gc.initial_covariance`); the
    angle sensor reads ``β = β_n + Δβ`` plus white noise of variance ``R₁₁``, the
    inclinometers ``g δ + N1`` and ``g γ + N1`` plus noise of variances ``R₂₂``, ``R₃₃``
    (Eq. (8), :func:`gyrolib.gc.measurement_noise_covariance`).

    Examples
    --------
    >>> from gyrolib import gc
    >>> sim = gc.simulate_record(gc.GyrocompassParams(), 0.01, seed=1)
    >>> sim.record.n, sim.truth.shape
    (10, (11, 10))
    """
    from gyrolib.filtering.discretization import covariance_factor
    from gyrolib.gc.discretization import nominal_half_steps
    from gyrolib.gc.montecarlo import simulate_truth

    p = v.check_instance("params", params, GyrocompassParams)
    seed = v.check_int("seed", seed, 0)
    rng = np.random.default_rng(seed)
    x0 = covariance_factor(initial_covariance(p)) @ rng.standard_normal(N)
    truth_seed = int(rng.integers(0, 2**62))
    t, X = simulate_truth(p, t_end, x0, seed=truth_seed)
    beta_n = nominal_half_steps(p, t.size - 1)[::2]
    D = measurement_matrix(p)
    sr = np.sqrt(np.diag(measurement_noise_covariance(p)))
    Z = X @ D.T + rng.standard_normal((t.size, M)) * sr
    Z[:, 0] += beta_n
    rec = GCRecord(t=t[1:], angle_sensor=Z[1:, 0], inclinometer_y=Z[1:, 1],
                   inclinometer_z=Z[1:, 2])
    return SimulatedRecord(record=rec, truth=X, params=p, seed=seed)


# Figure -----------------------------------------------------------------------------------
def plot_calibration(result: CalibrationResult, truth: float | None = None,
                     confidence: float = 0.99):
    """The ω_gc estimate with its ±σ band over time (paper's ″/s) and, below, the mean NIS
    of each sensor per stored window against its χ² band; ``truth`` (rad/s) draws the true
    drift when known.  Returns a :class:`matplotlib.figure.Figure`."""
    import matplotlib.pyplot as plt

    from gyrolib.units import from_si

    if not isinstance(result, CalibrationResult):
        raise TypeError(f"result must be a CalibrationResult; got {type(result).__name__}")
    conf = v.check_in_range("confidence", confidence, 0.0, 1.0, low_open=True, high_open=True)
    fig, (ax, bx) = plt.subplots(2, 1, figsize=(7.5, 5.6), sharex=True,
                                 gridspec_kw={"height_ratios": [3, 2]})
    est = np.asarray(from_si(result.estimate("omega_gc"), "arcsec_paper/s"))
    sig = np.asarray(from_si(result.sigma("omega_gc"), "arcsec_paper/s"))
    ax.fill_between(result.t, est - sig, est + sig, color="C0", alpha=0.25, lw=0,
                    label="±σ (filter)")
    ax.plot(result.t, est, color="C0", lw=1.2, label="estimate")
    if truth is not None:
        ax.axhline(float(from_si(v.check_real("truth", truth), "arcsec_paper/s")), color="k",
                   ls="--", lw=1, label="truth")
    ax.set_ylabel("ω_gc (″/s, paper's arcsec)")
    lo = float(np.min(est[-max(1, est.size // 2):] - 4 * sig[-max(1, est.size // 2):]))
    hi = float(np.max(est[-max(1, est.size // 2):] + 4 * sig[-max(1, est.size // 2):]))
    if truth is not None:
        tr = float(from_si(truth, "arcsec_paper/s"))
        lo, hi = min(lo, tr - (hi - lo) * 0.1), max(hi, tr + (hi - lo) * 0.1)
    ax.set_ylim(lo, hi)
    ax.legend(loc="upper right", fontsize=8)
    ax.set_title(f"ω_gc = {from_si(result.omega_gc, 'arcsec_paper/s'):.4g} ± "
                 f"{from_si(result.omega_gc_std, 'arcsec_paper/s'):.2g} ″/s", fontsize=10)
    for q, name in enumerate(MEASUREMENT_NAMES):
        bx.plot(result.t, result.nis_window[:, q], lw=0.8, color=f"C{q + 1}", label=name)
    n = np.maximum(np.median(result.nis_window_count, axis=0), 1.0)
    nn = float(np.max(n))
    bx.axhspan(scipy.stats.chi2.ppf(0.5 * (1 - conf), nn) / nn,
               scipy.stats.chi2.ppf(0.5 * (1 + conf), nn) / nn, color="0.85",
               label=f"{conf:.0%} band, {nn:.0f} samples")
    bx.axhline(1.0, color="k", lw=0.6)
    bx.set_ylabel("mean NIS per window")
    bx.set_xlabel("t (s)")
    bx.legend(loc="upper right", fontsize=7, ncol=2)
    fig.tight_layout()
    return fig
