"""Covariance recursion of a whole run of a linear time-varying Kalman filter.

The model is :class:`AffineDiscreteModel`: ``Φ_k``, ``Qd_k`` affine in two scalars
``(a_k, b_k)`` about expansion points (paper GC's ``F`` is affine in ``(sin β_n, cos β_n)``),
exact to second order.  Two paths:

* :func:`covariance_reference` — plain numpy, a batch Joseph update per step, any per-step
  ``Φ_k``, ``Qd_k``;
* :func:`covariance_fast` — numba, sequential scalar Joseph updates (each O(n²)) and sparse
  rows of ``Φ``, by the kernels of :mod:`gyrolib.filtering.kernels` (shared with
  :func:`gyrolib.gc.calibrate`).  Tests show they agree to 1e-9 relative.

The filter is the discrete optimal filter of {cite:p}`Kalman1960` in the notation of
{cite:p}`BarShalom2001`: predict ``P⁻ = Φ P Φᵀ + Qd``; update with ``z = H x + v``,
``v ~ N(0, R)``.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numba import njit

from gyrolib import _compile_note  # noqa: F401  (a line on stderr at the first compile)
from gyrolib import _validation as v
from gyrolib._repr import compact_repr
from gyrolib.filtering.kernels import (
    joseph_scalar_update_inline,
    measurement_projection_inline,
    predict_covariance_inline,
)
from gyrolib.filtering.updates import joseph_update

__all__ = [
    "AffineDiscreteModel",
    "CovarianceRun",
    "covariance_fast",
    "covariance_reference",
    "propagate_fixed_gains",
]


# Covariance recursion over a run -----------------------------------------------------------
@compact_repr
@dataclass(frozen=True)
class AffineDiscreteModel:
    """A discrete LTV model whose step matrices are affine in two scalars per step.

    Step ``k`` (from ``t_k`` to ``t_{k+1}``) uses expansion point ``j = seg[k]``::

        Φ_k  = Phi0[j] + a[k] PhiA[j] + b[k] PhiB[j]
        Qd_k = Qd0[j]  + a[k] QdA[j]  + b[k] QdB[j]

    Measurements ``z_k = H x_k + v_k`` with ``R = diag(r)`` after every step; optionally
    a measurement matrix that varies along the run, ``H_k = H + h[k] H1`` after step ``k``
    (``H1`` m×n, ``h`` one scalar per step; e.g. a reading proportional to paper GC's
    nominal float angle).  Paper GC's Eq. (8) discretized by :func:`gyrolib.gc.discretize`
    is one.

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import filtering
    >>> one, zero = np.ones((1, 1, 1)), np.zeros((1, 1, 1))
    >>> walk = filtering.AffineDiscreteModel(   # x_{k+1} = x_k + w_k, z = x + v, q = r = 1
    ...     seg=np.zeros(50, dtype=np.int64), a=np.zeros(50), b=np.zeros(50), Phi0=one,
    ...     PhiA=zero, PhiB=zero, Qd0=one, QdA=zero, QdB=zero, H=np.ones((1, 1)), r=np.ones(1))
    >>> walk.n_steps, walk.n
    (50, 1)
    """

    seg: np.ndarray
    a: np.ndarray
    b: np.ndarray
    Phi0: np.ndarray
    PhiA: np.ndarray
    PhiB: np.ndarray
    Qd0: np.ndarray
    QdA: np.ndarray
    QdB: np.ndarray
    H: np.ndarray
    r: np.ndarray
    H1: np.ndarray | None = None
    h: np.ndarray | None = None

    def __post_init__(self) -> None:
        seg = np.asarray(self.seg)
        if seg.ndim != 1 or seg.dtype.kind not in "iu":
            raise TypeError(f"seg must be a 1-D integer array; got dtype {seg.dtype}, "
                            f"shape {seg.shape}")
        object.__setattr__(self, "seg", seg)
        for name in ("a", "b", "Phi0", "PhiA", "PhiB", "Qd0", "QdA", "QdB", "H", "r"):
            arr = getattr(self, name)
            checked = v.check_array(name, arr)
            # keep float64 arrays as given (no copy): the kernels read them in place
            if not (isinstance(arr, np.ndarray) and arr.dtype == np.float64):
                object.__setattr__(self, name, checked)
        if self.Phi0.ndim != 3 or self.Phi0.shape[1] != self.Phi0.shape[2]:
            raise ValueError(f"Phi0 must have shape (J, n, n); got {self.Phi0.shape}")
        if np.any(self.r < 0.0):
            raise ValueError("r must be >= 0 (measurement-noise variances)")
        n_steps = self.seg.shape[0]
        J, n, _ = self.Phi0.shape
        for name in ("a", "b"):
            if getattr(self, name).shape != (n_steps,):
                raise ValueError(f"{name} must have shape ({n_steps},)")
        for name in ("Phi0", "PhiA", "PhiB", "Qd0", "QdA", "QdB"):
            if getattr(self, name).shape != (J, n, n):
                raise ValueError(f"{name} must have shape ({J}, {n}, {n})")
        if self.H.ndim != 2 or self.H.shape[1] != n or self.r.shape != (self.H.shape[0],):
            raise ValueError("H must be m×n and r must have m entries")
        if n_steps and (self.seg.min() < 0 or self.seg.max() >= J):
            raise ValueError("seg must index the expansion points")
        if (self.H1 is None) != (self.h is None):
            raise ValueError("H1 and h must be given together (H_k = H + h[k] H1)")
        if self.H1 is not None:
            object.__setattr__(self, "H1", v.check_array("H1", self.H1, shape=self.H.shape))
            object.__setattr__(self, "h", v.check_array("h", self.h, shape=(n_steps,)))

    @property
    def n_steps(self) -> int:
        return int(self.seg.shape[0])

    @property
    def n(self) -> int:
        return int(self.Phi0.shape[1])

    def _step(self, k: object) -> int:
        k = v.check_int("k", k, 0)
        if k >= self.n_steps:
            raise ValueError(f"k must be a step index in [0, {self.n_steps}); got {k}")
        return k

    def phi(self, k: int) -> np.ndarray:
        """``Φ_k``, the transition of step ``k`` (0 <= k < n_steps)."""
        k = self._step(k)
        j = self.seg[k]
        return self.Phi0[j] + self.a[k] * self.PhiA[j] + self.b[k] * self.PhiB[j]

    def qd(self, k: int) -> np.ndarray:
        """``Qd_k``, the process-noise covariance of step ``k`` (0 <= k < n_steps)."""
        k = self._step(k)
        j = self.seg[k]
        return self.Qd0[j] + self.a[k] * self.QdA[j] + self.b[k] * self.QdB[j]

    def h_matrix(self, k: int) -> np.ndarray:
        """``H_k``, the measurement matrix after step ``k`` (0 <= k < n_steps)."""
        k = self._step(k)
        return self.H.copy() if self.H1 is None else self.H + self.h[k] * self.H1

    def sparsity(self) -> tuple[np.ndarray, np.ndarray]:
        """CSR row pointers and column indices of the union of the nonzeros of ``Φ``."""
        return csr_pattern(np.any((self.Phi0 != 0) | (self.PhiA != 0) | (self.PhiB != 0), axis=0))

    def measurement_sparsity(self) -> tuple[np.ndarray, np.ndarray]:
        """CSR row pointers and column indices of the nonzeros of ``H`` (and of ``H1``)."""
        return csr_pattern((self.H != 0) if self.H1 is None else (self.H != 0) | (self.H1 != 0))


def csr_pattern(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    rowptr = np.zeros(mask.shape[0] + 1, dtype=np.int64)
    rowptr[1:] = np.cumsum(mask.sum(axis=1))
    return rowptr, np.nonzero(mask)[1].astype(np.int64)


@compact_repr
@dataclass(frozen=True)
class CovarianceRun:
    """Result of a covariance recursion.

    ``var[k]`` is the diagonal of the posterior ``P`` at step ``k`` (``k = 0``: the prior
    ``P0``); ``P_stored[i]`` the full posterior at step ``i·store_every``; ``gains[k, q]`` the
    gain of scalar measurement ``q`` at step ``k+1`` (sequential processing; the fast path
    only, when asked) or the batch gain ``K_k`` (``(n_steps, n, m)``, reference path).
    """

    var: np.ndarray
    P_stored: np.ndarray
    store_every: int
    gains: np.ndarray | None

    def __post_init__(self) -> None:
        n = v.check_ndarray("var", self.var, ndim=2).shape[1]
        v.check_ndarray("P_stored", self.P_stored, shape=(None, n, n))
        v.check_int("store_every", self.store_every, 1)
        if self.gains is not None:
            v.check_ndarray("gains", self.gains, ndim=3)


def _check_run(model: AffineDiscreteModel, P0: object, store_every: object) -> tuple:
    if not isinstance(model, AffineDiscreteModel):
        raise TypeError("model must be an AffineDiscreteModel")
    P0 = v.check_covariance("P0", v.check_array("P0", P0, shape=(model.n, model.n)))
    store_every = v.check_int("store_every", store_every, 1)
    return P0, store_every


def covariance_reference(
    model: AffineDiscreteModel | None,
    P0: object,
    store_every: int = 1,
    *,
    step_matrices: Callable[[int], tuple[np.ndarray, np.ndarray]] | None = None,
    n_steps: int | None = None,
    H: np.ndarray | None = None,
    R: np.ndarray | None = None,
) -> CovarianceRun:
    """Plain-numpy reference: per step ``P⁻ = Φ P Φᵀ + Qd`` and a batch :func:`joseph_update`.

    Either ``model`` gives ``Φ_k``, ``Qd_k``, ``H``, ``R``; or ``step_matrices(k)`` returns
    ``(Φ_k, Qd_k)`` (e.g. an exact per-step :func:`van_loan`) with ``n_steps``, ``H``, ``R``.

    Parameters
    ----------
    model : AffineDiscreteModel or None
        The model (``None`` with ``step_matrices``).
    P0 : array_like
        Initial covariance (n×n).
    store_every : int
        Keep the full ``P`` every ``store_every`` steps.
    step_matrices, n_steps, H, R
        The alternative description of the model (``H`` may be a callable ``k -> H_k``,
        the measurement matrix after step ``k``).

    Returns
    -------
    CovarianceRun
        Variances at every step, stored ``P`` and the batch gains ``K_k`` (n×m).

    Examples
    --------
    A random walk observed in unit noise: ``P`` tends to ``(√5 − 1)/2``.

    >>> import numpy as np
    >>> from gyrolib import filtering
    >>> one, zero = np.ones((1, 1, 1)), np.zeros((1, 1, 1))
    >>> walk = filtering.AffineDiscreteModel(   # x_{k+1} = x_k + w_k, z = x + v, q = r = 1
    ...     seg=np.zeros(50, dtype=np.int64), a=np.zeros(50), b=np.zeros(50), Phi0=one,
    ...     PhiA=zero, PhiB=zero, Qd0=one, QdA=zero, QdB=zero, H=np.ones((1, 1)), r=np.ones(1))
    >>> run = filtering.covariance_reference(walk, np.ones((1, 1)))
    >>> f"{run.var[-1, 0]:.4f}"
    '0.6180'
    """
    h_of_step = None
    if step_matrices is None:
        P0, store_every = _check_run(model, P0, store_every)
        step_matrices = lambda k: (model.phi(k), model.qd(k))  # noqa: E731
        n_steps, H, R = model.n_steps, model.H, np.diag(model.r)
        if model.H1 is not None:
            h_of_step = model.h_matrix
    else:
        if not callable(step_matrices):
            raise TypeError("step_matrices must be callable, k -> (Phi_k, Qd_k); "
                            f"got {type(step_matrices).__name__}")
        P0 = v.check_array("P0", P0, ndim=2)
        if P0.shape[0] != P0.shape[1]:
            raise ValueError(f"P0 must be a square matrix; got shape {P0.shape}")
        v.check_covariance("P0", P0)
        store_every = v.check_int("store_every", store_every, 1)
        n_steps = v.check_int("n_steps", n_steps, 0)
        if callable(H):       # H_k after step k
            h_of_step = H
            H = v.check_array("H", h_of_step(0), shape=(None, P0.shape[0]))
        else:
            H = v.check_array("H", H, shape=(None, P0.shape[0]))
        R = v.check_covariance("R", v.check_array("R", R, shape=(H.shape[0], H.shape[0])))
    n, m = P0.shape[0], H.shape[0]
    P = P0.copy()
    var = np.empty((n_steps + 1, n))
    var[0] = np.diag(P)
    P_stored = np.empty((n_steps // store_every + 1, n, n))
    P_stored[0] = P
    gains = np.empty((n_steps, n, m))
    x = np.zeros(n)
    z = np.zeros(m)
    for k in range(n_steps):
        Phi, Qd = step_matrices(k)
        P = Phi @ P @ Phi.T + Qd
        _, P, K = joseph_update(x, P, z, H if h_of_step is None else h_of_step(k), R)
        gains[k] = K
        var[k + 1] = np.diag(P)
        if (k + 1) % store_every == 0:
            P_stored[(k + 1) // store_every] = P
    return CovarianceRun(var=var, P_stored=P_stored, store_every=store_every, gains=gains)


def _predict_joseph(size: int | None):
    """:func:`_predict_joseph_kernel` for a state size fixed at compile time (``None``: read
    from ``P0``): the loops of the inlined kernels unroll (paper GC's 10-state recursion runs
    about 1.7 times as fast).  The closure holds only ``size``, so numba's cache keeps one
    entry per size across processes."""

    @njit(cache=True, nogil=True)
    def _predict_joseph_kernel(seg, a, b, Phi0, PhiA, PhiB, Qd0, QdA, QdB, rowptr, colidx,
                               hptr, hidx, H, H1, hs, tv, r, P0, store_every, var,
                               P_stored, gains, fixed):
        """One kernel for both uses: ``fixed=False`` computes the optimal sequential gains and
        writes them to ``gains`` (if it has ``n_steps`` rows); ``fixed=True`` propagates the
        error covariance with the given ``gains`` (Joseph form, valid for any gain).
        ``rowptr/colidx`` (``hptr/hidx``) list the nonzeros of ``Φ`` (of the rows of ``H``).
        ``tv``: the measurement matrix after step ``k`` is ``H + hs[k] H1``."""
        n = P0.shape[0] if size is None else size
        m = H.shape[0]
        n_steps = seg.shape[0]
        keep = gains.shape[0] == n_steps
        P = P0.copy()
        Phi = np.zeros((n, n))
        Qd = np.zeros((n, n))
        T = np.zeros((n, n))
        Ph = np.zeros(n)
        kv = np.zeros(n)
        Hk = H.copy()
        # element-wise copies: an array-slice assignment costs seconds of numba compile time
        for i in range(n):
            var[0, i] = P[i, i]
            for c in range(n):
                P_stored[0, i, c] = P[i, c]
        for k in range(n_steps):
            j = seg[k]
            ak = a[k]
            bk = b[k]
            for i in range(n):
                for p in range(rowptr[i], rowptr[i + 1]):
                    c = colidx[p]
                    Phi[i, c] = Phi0[j, i, c] + ak * PhiA[j, i, c] + bk * PhiB[j, i, c]
                for c in range(i, n):
                    Qd[i, c] = Qd0[j, i, c] + ak * QdA[j, i, c] + bk * QdB[j, i, c]
            predict_covariance_inline(P, Phi, rowptr, colidx, Qd, T, n)
            if tv:
                hk = hs[k]
                for q in range(m):
                    for p in range(hptr[q], hptr[q + 1]):
                        c = hidx[p]
                        Hk[q, c] = H[q, c] + hk * H1[q, c]
            for q in range(m):
                S = measurement_projection_inline(P, Hk, q, hptr, hidx, Ph, n) + r[q]
                if fixed:
                    for i in range(n):
                        kv[i] = gains[k, q, i]
                else:
                    inv = 1.0 / S
                    for i in range(n):
                        kv[i] = Ph[i] * inv
                    if keep:
                        for i in range(n):
                            gains[k, q, i] = kv[i]
                joseph_scalar_update_inline(P, Ph, kv, S, n)
            for i in range(n):
                var[k + 1, i] = P[i, i]
            if (k + 1) % store_every == 0:
                ii = (k + 1) // store_every
                for i in range(n):
                    for c in range(n):
                        P_stored[ii, i, c] = P[i, c]

    return _predict_joseph_kernel


#: The kernel for any state size (read from the arrays).
_predict_joseph_kernel = _predict_joseph(None)

#: Largest state size given a kernel of its own (loops longer than this gain nothing by
#: unrolling; each size compiles once, then loads from numba's cache).
_SIZED_MAX = 32


@functools.cache
def _sized_kernel(n: int) -> Callable:
    return _predict_joseph(n)


def _run_kernel(model, P0, store_every, gains, fixed, r=None, Qd=None) -> CovarianceRun:
    rowptr, colidx = model.sparsity()
    hptr, hidx = model.measurement_sparsity()
    Qd0, QdA, QdB = Qd if Qd is not None else (model.Qd0, model.QdA, model.QdB)
    r = model.r if r is None else r
    var = np.empty((model.n_steps + 1, model.n))
    P_stored = np.empty((model.n_steps // store_every + 1, model.n, model.n))
    kernel = _sized_kernel(model.n) if model.n <= _SIZED_MAX else _predict_joseph_kernel
    tv = model.H1 is not None
    H1 = model.H1 if tv else np.zeros_like(model.H)
    hs = model.h if tv else np.zeros(1)
    kernel(model.seg, model.a, model.b, model.Phi0, model.PhiA, model.PhiB, Qd0, QdA, QdB,
           rowptr, colidx, hptr, hidx, np.ascontiguousarray(model.H), np.ascontiguousarray(H1),
           hs, tv, r, P0, store_every, var, P_stored, gains, fixed)
    return CovarianceRun(var=var, P_stored=P_stored, store_every=store_every,
                         gains=gains if gains.shape[0] == model.n_steps else None)


def covariance_fast(model: AffineDiscreteModel, P0: object, store_every: int = 1, *,
                    keep_gains: bool = False) -> CovarianceRun:
    """Fast path of :func:`covariance_reference` (numba): sequential scalar Joseph updates
    (``R`` diagonal) and sparse rows of ``Φ`` (paper GC's Figure 3 runs on it).

    Parameters
    ----------
    model : AffineDiscreteModel
        The model.
    P0 : array_like
        Initial covariance (n×n).
    store_every : int
        Keep the full ``P`` every ``store_every`` steps.
    keep_gains : bool
        Store the scalar gains ``(n_steps, m, n)`` for running the filter on measurements.

    Returns
    -------
    CovarianceRun

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import filtering
    >>> one, zero = np.ones((1, 1, 1)), np.zeros((1, 1, 1))
    >>> walk = filtering.AffineDiscreteModel(   # x_{k+1} = x_k + w_k, z = x + v, q = r = 1
    ...     seg=np.zeros(50, dtype=np.int64), a=np.zeros(50), b=np.zeros(50), Phi0=one,
    ...     PhiA=zero, PhiB=zero, Qd0=one, QdA=zero, QdB=zero, H=np.ones((1, 1)), r=np.ones(1))
    >>> run = filtering.covariance_fast(walk, np.ones((1, 1)))
    >>> f"{run.var[-1, 0]:.4f}"   # (√5 − 1)/2
    '0.6180'
    """
    P0, store_every = _check_run(model, P0, store_every)
    keep_gains = v.check_bool("keep_gains", keep_gains)
    m = model.H.shape[0]
    gains = np.zeros((model.n_steps if keep_gains else 0, m, model.n))
    return _run_kernel(model, P0, store_every, gains, False)


def propagate_fixed_gains(model: AffineDiscreteModel, P0: object, gains: object,
                          r: object, Qd: tuple[np.ndarray, np.ndarray, np.ndarray],
                          store_every: int = 1) -> CovarianceRun:
    """Error covariance of the filter with a given (e.g. the optimal) sequential gain
    sequence, for a source with initial covariance ``P0``, process noise ``Qd``
    (``(Qd0, QdA, QdB)`` as in :class:`AffineDiscreteModel`) and measurement variances ``r``.

    The error recursion is linear, so sources that are mutually independent add up in
    covariance: this is how an error budget is split exactly (paper GC's budget).

    Parameters
    ----------
    model : AffineDiscreteModel
        The model (its ``Φ_k``, ``H``).
    P0 : array_like
        Initial covariance of the source (n×n).
    gains : array_like
        Sequential gains ``(n_steps, m, n)`` (from :func:`covariance_fast` with
        ``keep_gains=True``).
    r : array_like
        Measurement variances of the source (m,).
    Qd : tuple of ndarray
        ``(Qd0, QdA, QdB)`` of the source.
    store_every : int
        Keep the full covariance every ``store_every`` steps.

    Returns
    -------
    CovarianceRun

    Examples
    --------
    With the optimal gains and all sources, the optimal covariance comes back:

    >>> import numpy as np
    >>> from gyrolib import filtering
    >>> one, zero = np.ones((1, 1, 1)), np.zeros((1, 1, 1))
    >>> walk = filtering.AffineDiscreteModel(   # x_{k+1} = x_k + w_k, z = x + v, q = r = 1
    ...     seg=np.zeros(50, dtype=np.int64), a=np.zeros(50), b=np.zeros(50), Phi0=one,
    ...     PhiA=zero, PhiB=zero, Qd0=one, QdA=zero, QdB=zero, H=np.ones((1, 1)), r=np.ones(1))
    >>> opt = filtering.covariance_fast(walk, np.ones((1, 1)), keep_gains=True)
    >>> run = filtering.propagate_fixed_gains(walk, np.ones((1, 1)), opt.gains, np.ones(1),
    ...                                       (walk.Qd0, walk.QdA, walk.QdB))
    >>> f"{run.var[-1, 0]:.4f}"
    '0.6180'
    """
    P0, store_every = _check_run(model, P0, store_every)
    m = model.H.shape[0]
    gains = v.check_array("gains", gains, shape=(model.n_steps, m, model.n))
    r = v.check_array("r", r, shape=(m,))
    if np.any(r < 0.0):
        raise ValueError("r must be >= 0 (measurement-noise variances)")
    if not isinstance(Qd, list | tuple) or len(Qd) != 3:
        raise TypeError("Qd must be a tuple (Qd0, QdA, QdB) of three (J, n, n) arrays")
    J = model.Phi0.shape[0]
    Qd = tuple(v.check_array("Qd", q, shape=(J, model.n, model.n)) for q in Qd)
    return _run_kernel(model, P0, store_every, gains, True, r=r, Qd=Qd)
