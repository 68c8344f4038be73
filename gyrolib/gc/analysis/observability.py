"""Paper GC, Eq. (5): how the float's turning separates ψ from ω_gc — the information
(observability Gramian) of the two states from the angle sensor, with and without the other
state known.  ψ enters Eq. (5) through ``H Ω_h sin β_n``, ω_gc through ``H``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from gyrolib import _compile_note  # noqa: F401  (a line on stderr at the first compile)
from gyrolib import _validation as v
from gyrolib._repr import compact_repr
from gyrolib.filtering.covariance import AffineDiscreteModel
from gyrolib.filtering.discretization import van_loan
from gyrolib.gc.analysis.covariance import default_store_every
from gyrolib.gc.model.discretization import discretize
from gyrolib.gc.model.params import GyrocompassParams, check_params, state_index
from gyrolib.gc.model.state_space import (
    noise_input_matrix,
    process_noise_intensity,
    system_matrix,
)

__all__ = [
    "InformationPsiOmega",
    "information_psi_omega",
]


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


@compact_repr
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

    Parameters
    ----------
    params : GyrocompassParams
        The model.
    t_end : float
        Length (s), a multiple of ``params.dt``.
    store_every : int, optional
        Keep ``W`` every ``store_every`` steps (default: about 1000 stored times).
    frozen_beta : float, optional
        Hold ``β_n`` at this constant value (rad) instead: a counterfactual float that does not
        turn, to show what the growth of ``sin β_n`` contributes.

    Returns
    -------
    InformationPsiOmega

    Examples
    --------
    The regressors ``t`` (ω_gc) and ``t²`` (ψ) of the aperiodic float correlate as √15/4:

    >>> from gyrolib import gc
    >>> info = gc.information_psi_omega(gc.GyrocompassParams(), 100.0)
    >>> f"{abs(info.correlation()[-1]):.3f}"
    '0.968'
    """
    p = check_params(params)
    disc = discretize(p, t_end)
    se = default_store_every(disc.n_steps) if store_every is None else store_every
    se = v.check_int("store_every", se, 1)
    mdl = disc.model
    if frozen_beta is not None:
        fb = v.check_real("frozen_beta", frozen_beta)
        Phi, Qd = van_loan(system_matrix(p, fb), noise_input_matrix(p),
                                  process_noise_intensity(p), p.dt)
        zero = np.zeros(disc.n_steps)
        mdl = AffineDiscreteModel(
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
