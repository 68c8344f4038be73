"""Paper GC: what the filter's linearization of Eq. (3) costs, seen in the Monte Carlo.

The filter linearizes the horizontal-rate torque of Eq. (3) about the nominal motion β_n
(Eq. (5)): ``Ω_h cos(β − ψ) ≈ Ω_h [cos β_n − sin β_n (Δβ − ψ)]``.  The truth of
:func:`gyrolib.gc.monte_carlo` keeps the remainder, per unit ``H`` a drift rate

    ρ = Ω_h [cos(β_n + Δβ − ψ) − cos β_n + sin β_n (Δβ − ψ)] ≈ −Ω_h cos β_n (Δβ − ψ)²/2,

and with ``Δβ ≪ ψ`` (the float stays within microradians of its nominal) it is a constant
of each run, ``−Ω_h cos β_n ψ²/2``: a torque the filter cannot tell from the drift ω_gc.  Its
ω_gc estimate takes it in (:func:`remainder_drift` predicts the shift run by run), while its
estimates of the float's angle and rate follow the truth.  The filter, however, holds ω_gc
tied to the other nine states (by the float's torque balance) hundreds of times more tightly
than its marginal σ, so this shift, a fraction of a percent of σ, weighs in the full-state
NEES as ``E[ρ²] (P⁻¹)_{ω_gc ω_gc}`` (:func:`linearization_effect`).

:func:`linearization_effect` compares a Monte Carlo with the nonlinear truth and one with the
same seeds and the truth's torques linearized (``truth="linear"``): the paired difference
removes the sampling noise, leaving the nonlinearity's effect alone.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrolib import _validation as v
from gyrolib._repr import compact_repr
from gyrolib.filtering.consistency import nees_bounds
from gyrolib.gc.analysis.montecarlo import MonteCarloResult
from gyrolib.gc.model.discretization import nominal_half_steps
from gyrolib.gc.model.params import GyrocompassParams, check_params, state_index

__all__ = [
    "LinearizationEffect",
    "linearization_effect",
    "psi_for_drift",
    "remainder_drift",
]


def remainder_drift(params: GyrocompassParams, psi: ArrayLike, beta_n: ArrayLike = 0.0,
                    dbeta: ArrayLike = 0.0) -> NDArray[np.float64]:
    """The part of Eq. (3)'s horizontal-rate torque that the linearization about ``β_n``
    (Eq. (5)) drops, per unit ``H``: a drift rate (rad/s).

    ``ρ = Ω_h [cos β_n (cos x − 1) − sin β_n (sin x − x)]`` with ``x = Δβ − ψ``
    (``≈ −Ω_h cos β_n x²/2``), written so that nothing cancels.

    Parameters
    ----------
    params : GyrocompassParams
        The truth's parameters (``Omega_h``).
    psi : array_like
        Azimuth misalignment ψ (rad).
    beta_n : array_like
        Nominal float angle (rad).
    dbeta : array_like
        Float angle from its nominal, Δβ (rad).

    Returns
    -------
    ndarray
        ρ (rad/s), broadcast over the inputs.

    Examples
    --------
    >>> from gyrolib import gc
    >>> from gyrolib.units import ARCSEC_PAPER
    >>> p = gc.GyrocompassParams()
    >>> f"{gc.remainder_drift(p, 180 * ARCSEC_PAPER):.3g}"   # ψ at its prior σ: −Ω_h ψ²/2
    '-1.64e-11'
    """
    p = check_params(params)
    x = v.check_array("dbeta", dbeta) - v.check_array("psi", psi)
    b = v.check_array("beta_n", beta_n)
    cm1 = -2.0 * np.sin(0.5 * x) ** 2
    return p.Omega_h * (np.cos(b) * cm1 - np.sin(b) * (np.sin(x) - x))


def psi_for_drift(params: GyrocompassParams, drift: float) -> float:
    """The misalignment ψ (rad) whose remainder drift :func:`remainder_drift` is ``drift``
    in magnitude at ``β_n = Δβ = 0``: ``√(2 |drift| / Ω_h)`` (to second order).

    Examples
    --------
    >>> from gyrolib import gc
    >>> p = gc.GyrocompassParams()
    >>> psi = gc.psi_for_drift(p, 1e-9)
    >>> f"{-gc.remainder_drift(p, psi) / 1e-9:.4f}"
    '1.0000'
    """
    p = check_params(params)
    d = v.check_real("drift", drift)
    return float(np.sqrt(2.0 * abs(d) / p.Omega_h))


@compact_repr
@dataclass(frozen=True)
class LinearizationEffect:
    """The nonlinear truth against the linearized one, with the same seeds (paired).

    At the stored times ``t`` (> 0): the ensemble-average full-state NEES with each truth
    (``nees_nonlinear``, ``nees_linear``) and its 95 % chi-square ``band``; the paired change
    of every state's error, RMS over the runs, in units of that state's σ (``state_shift``,
    time × 10); the paired change of the ω_gc estimate per run (``omega_shift``, rad/s) and its
    prediction :func:`remainder_drift` at the run's ψ (``omega_shift_predicted``); the filter's
    σ of ω_gc (``omega_sigma``) and its ratio to the conditional σ of ω_gc given the other
    nine states (``sigma_ratio``); and the NEES excess that the predicted shift alone makes,
    ``mean(ρ²) (P⁻¹)_{ω_gc ω_gc}`` (``excess_predicted``).  ``shift_sums`` holds, per time,
    the sums over the runs of ρ·shift, ρ² and (shift − ρ)², from which :meth:`slope` and
    :attr:`residual` are computed; :meth:`compact` keeps only the last time of the per-run
    arrays (all a stored study needs).
    """

    t: NDArray[np.float64]
    n_runs: int
    nees_nonlinear: NDArray[np.float64]
    nees_linear: NDArray[np.float64]
    band: tuple[float, float]
    state_shift: NDArray[np.float64]
    omega_shift: NDArray[np.float64]
    omega_shift_predicted: NDArray[np.float64]
    omega_sigma: NDArray[np.float64]
    sigma_ratio: NDArray[np.float64]
    excess_predicted: NDArray[np.float64]
    shift_sums: NDArray[np.float64] | None = None

    def __post_init__(self) -> None:
        if self.shift_sums is None:   # built from the per-run arrays at every time
            x, y = self.omega_shift_predicted, self.omega_shift
            object.__setattr__(self, "shift_sums", np.stack(
                [np.sum(x * y, axis=0), np.sum(x * x, axis=0), np.sum((y - x) ** 2, axis=0)]))
        v.check_ndarray("shift_sums", self.shift_sums, shape=(3, np.size(self.t)))

    def compact(self) -> LinearizationEffect:
        """The same effect with the per-run ω_gc shifts kept at the last time only (what the
        plot's bottom panel and the bias need); :meth:`slope` and :attr:`residual` are
        unchanged, read from ``shift_sums``."""
        return dataclasses.replace(self, omega_shift=self.omega_shift[:, -1:],
                                   omega_shift_predicted=self.omega_shift_predicted[:, -1:])

    @property
    def excess(self) -> NDArray[np.float64]:
        """Paired NEES excess of the nonlinear truth over the linearized one, per time."""
        return self.nees_nonlinear - self.nees_linear

    @property
    def residual(self) -> NDArray[np.float64]:
        """Per time, the RMS over the runs of the ω_gc shift less its prediction, relative
        to the RMS of the prediction (the part of the shift the constant ρ leaves out)."""
        return np.sqrt(self.shift_sums[2] / self.shift_sums[1])

    def inside(self, which: str = "nonlinear") -> float:
        """Share of the stored times at which the full-state NEES of ``which`` truth
        (``"nonlinear"`` or ``"linear"``) lies in its per-time band (about 0.95 expected of
        a consistent filter, with a wide spread: neighbouring times are correlated)."""
        which = v.check_choice("which", which, ("nonlinear", "linear"))
        x = self.nees_nonlinear if which == "nonlinear" else self.nees_linear
        return float(np.mean((x > self.band[0]) & (x < self.band[1])))

    def slope(self, t_min: float = 0.0) -> float:
        """Least-squares slope of the ω_gc shift on its prediction over runs and the times
        ``t >= t_min`` (1 when the remainder drift explains the shift)."""
        t_min = v.check_real("t_min", t_min)
        sel = self.t >= t_min
        if not np.any(sel):
            raise ValueError(f"t_min must be at most the last time {self.t[-1]}; got {t_min}")
        return float(np.sum(self.shift_sums[0, sel]) / np.sum(self.shift_sums[1, sel]))


def linearization_effect(nonlinear: MonteCarloResult, linear: MonteCarloResult,
                         confidence: float = 0.95) -> LinearizationEffect:
    """Compare a Monte Carlo of the nonlinear truth with the same runs of the linearized one.

    Parameters
    ----------
    nonlinear : MonteCarloResult
        From :func:`gyrolib.gc.monte_carlo` (any ``truth``; ``"nonlinear"`` for the paper's).
    linear : MonteCarloResult
        The same call with ``truth="linear"`` (same parameters, seed, runs, times).
    confidence : float
        Two-sided probability of the NEES band.

    Returns
    -------
    LinearizationEffect

    Examples
    --------
    >>> from gyrolib import gc
    >>> p = gc.GyrocompassParams()
    >>> a, b = (gc.monte_carlo(p, 32, 6.0, seed=3, truth=t, store_every=500)
    ...         for t in ("nonlinear", "linear"))
    >>> eff = gc.linearization_effect(a, b)
    >>> f"{eff.slope(t_min=5.0):.2f}"   # the ω_gc estimate shifts by the remainder drift
    '1.00'
    """
    a = v.check_instance("nonlinear", nonlinear, MonteCarloResult)
    b = v.check_instance("linear", linear, MonteCarloResult)
    if b.truth_mode != "linear":
        raise ValueError("linear must come from monte_carlo(..., truth='linear'); got "
                         f"truth_mode={b.truth_mode!r}")
    for field in ("params", "truth_params", "seed", "n_runs"):
        if getattr(a, field) != getattr(b, field):
            raise ValueError(f"nonlinear and linear must share {field}; got "
                             f"{getattr(a, field)!r} and {getattr(b, field)!r}")
    if a.t.shape != b.t.shape or not np.array_equal(a.t, b.t):
        raise ValueError("nonlinear and linear must share their stored times t")
    conf = v.check_in_range("confidence", confidence, 0.0, 1.0, low_open=True, high_open=True)
    p = a.params
    tp = p if a.truth_params is None else a.truth_params
    sel = slice(1, None)
    t = a.t[sel]
    iw, ip = state_index("omega_gc"), state_index("psi")
    sd = np.sqrt(np.diagonal(a.P[sel], axis1=1, axis2=2))
    shift = (a.est - a.tru) - (b.est - b.tru)
    state_shift = np.sqrt(np.mean((shift[:, sel] / sd) ** 2, axis=0))
    k = np.rint(t / p.dt).astype(np.int64)
    beta_n = nominal_half_steps(tp, int(k[-1]))[2 * k]
    pred = remainder_drift(tp, a.tru[:, :1, ip], beta_n[None, :])
    P_inv_ww = np.array([np.linalg.inv(Pt)[iw, iw] for Pt in a.P[sel]])
    return LinearizationEffect(
        t=t, n_runs=a.n_runs, nees_nonlinear=a.nees().mean(axis=0)[sel],
        nees_linear=b.nees().mean(axis=0)[sel], band=nees_bounds(a.est.shape[2], a.n_runs, conf),
        state_shift=state_shift, omega_shift=(a.est - b.est)[:, sel, iw],
        omega_shift_predicted=pred, omega_sigma=sd[:, iw],
        sigma_ratio=np.sqrt(sd[:, iw] ** 2 * P_inv_ww),
        excess_predicted=np.mean(pred**2, axis=0) * P_inv_ww)
