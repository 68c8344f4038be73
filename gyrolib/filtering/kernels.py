"""Numba kernels of the fast Kalman recursions, shared by
:func:`gyrolib.filtering.covariance_fast` and :func:`gyrolib.gc.calibrate` (no input checks:
float64 C-contiguous arrays, updated in place).

* :func:`predict_state`, :func:`predict_covariance` — ``x ← Φ x``, ``P ← Φ P Φᵀ + Qd`` with
  the nonzeros of ``Φ`` in CSR form;
* :func:`measurement_projection` — ``P h`` and ``hᵀ P h`` for a sparse measurement row ``h``;
* :func:`joseph_scalar_update` — the Joseph form for one scalar measurement, with any gain
  {cite:p}`BarShalom2001` (the batch form is :func:`gyrolib.filtering.joseph_update`).

Each kernel is made by a factory for a state size fixed at compile time, or read from the
arrays (``None``): one source each.  The module-level kernels are the general ones;
:func:`kalman_kernels` gives them compiled for one size, where loops of a known length
unroll (paper GC's 10-state filter runs about twice as fast).
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import NamedTuple

from numba import njit

from gyrolib import _compile_note  # noqa: F401  (a line on stderr at the first compile)
from gyrolib import _validation as v

__all__ = [
    "KalmanKernels",
    "joseph_scalar_update",
    "kalman_kernels",
    "measurement_projection",
    "predict_covariance",
    "predict_state",
]


@njit(cache=True, inline="always")
def _sparse_times(Phi, rowptr, colidx, A, out, n):
    """``out = Φ A`` (n×n) with the nonzeros of ``Φ`` in CSR form, row by row: each row of
    ``out`` a sum of rows of ``A`` (contiguous, vectorized loops)."""
    for i in range(n):
        for col in range(n):
            out[i, col] = 0.0
        for p in range(rowptr[i], rowptr[i + 1]):
            c = colidx[p]
            f = Phi[i, c]
            for col in range(n):
                out[i, col] += f * A[c, col]


# The bodies of the kernels below, inlined into their callers with the state size ``n`` as an
# argument: where ``n`` is a compile-time constant (a kernel made for one size, or a caller's
# own sized kernel, e.g. gyrolib.filtering.covariance's), the loops unroll.
@njit(cache=True, inline="always")
def predict_covariance_inline(P, Phi, rowptr, colidx, Qd, T, n):
    """The body of :func:`predict_covariance` for ``n`` states (inlined into the caller)."""
    _sparse_times(Phi, rowptr, colidx, P, T, n)      # T = Φ P
    # P ← Φ Tᵀ = Φ P Φᵀ: Tᵀ written into P (free now), then Φ times it
    for i in range(n):
        for col in range(n):
            P[col, i] = T[i, col]
    _sparse_times(Phi, rowptr, colidx, P, T, n)
    # symmetric to the bit (the two halves differ in rounding), plus Qd
    for i in range(n):
        for jj in range(i, n):
            s = 0.5 * (T[i, jj] + T[jj, i]) + Qd[i, jj]
            P[i, jj] = s
            P[jj, i] = s


@njit(cache=True, inline="always")
def measurement_projection_inline(P, H, q, hptr, hidx, Ph, n):
    """The body of :func:`measurement_projection` for ``n`` states (inlined into the
    caller)."""
    lo = hptr[q]
    hi = hptr[q + 1]
    # P h as a sum of rows of P (P symmetric: contiguous, vectorized)
    for i in range(n):
        Ph[i] = 0.0
    for p in range(lo, hi):
        c = hidx[p]
        f = H[q, c]
        for i in range(n):
            Ph[i] += f * P[c, i]
    hph = 0.0
    for p in range(lo, hi):
        c = hidx[p]
        hph += H[q, c] * Ph[c]
    return hph


@njit(cache=True, inline="always")
def joseph_scalar_update_inline(P, Ph, k, S, n):
    """The body of :func:`joseph_scalar_update` for ``n`` states (inlined into the caller)."""
    half = 0.5 * S
    for i in range(n):
        Ph[i] = half * k[i] - Ph[i]
    for i in range(n):
        ki = k[i]
        vi = Ph[i]
        for j in range(i, n):     # the upper triangle, mirrored
            val = P[i, j] + (ki * Ph[j] + vi * k[j])
            P[i, j] = val
            P[j, i] = val


def _predict_state(size: int | None):
    """:func:`predict_state` for a state size (``None``: read from ``x``)."""

    @njit(cache=True)
    def predict_state(x, Phi, rowptr, colidx, y):
        """Numba kernel: ``x ← Φ x`` in place, with the nonzeros of ``Φ`` in CSR form (as
        :func:`predict_covariance`); ``y`` (n,) is scratch.  No input checks (a kernel).

        Examples
        --------
        >>> import numpy as np
        >>> from gyrolib import filtering
        >>> x = np.array([1.0, 2.0]); Phi = np.array([[1.0, 0.1], [0.0, 1.0]])
        >>> filtering.predict_state(x, Phi, np.array([0, 2, 3]), np.array([0, 1, 1]),
        ...                         np.zeros(2))
        >>> x.tolist()
        [1.2, 2.0]
        """
        n = x.shape[0] if size is None else size
        for i in range(n):
            s = 0.0
            for p in range(rowptr[i], rowptr[i + 1]):
                s += Phi[i, colidx[p]] * x[colidx[p]]
            y[i] = s
        for i in range(n):
            x[i] = y[i]

    return predict_state


predict_state = _predict_state(None)


def _predict_covariance(size: int | None):
    """:func:`predict_covariance` for a state size fixed at compile time (``None``: read
    from ``P``)."""

    @njit(cache=True)
    def predict_covariance(P, Phi, rowptr, colidx, Qd, T):
        """Numba kernel: ``P ← Φ P Φᵀ + Qd`` in place, with the nonzeros of ``Φ`` listed in CSR
        form (row ``i`` at columns ``colidx[rowptr[i]:rowptr[i + 1]]``; values in the dense
        ``Phi``); reads the upper triangle of ``Qd``, writes ``P`` symmetric (the mean of the
        two triangles of ``Φ P Φᵀ``).  Both products are sums of rows (vectorized loops):
        ``T = Φ P``, then ``Φ Tᵀ``.  ``T`` (n×n) is scratch.  No input checks (a kernel).

        Examples
        --------
        >>> import numpy as np
        >>> from gyrolib import filtering
        >>> Phi = np.array([[1.0, 0.1], [0.0, 1.0]]); P = np.eye(2); Qd = 0.01 * np.eye(2)
        >>> rowptr, colidx = np.array([0, 2, 3]), np.array([0, 1, 1])
        >>> filtering.predict_covariance(P, Phi, rowptr, colidx, Qd, np.zeros((2, 2)))
        >>> bool(np.allclose(P, Phi @ Phi.T + Qd))
        True
        """
        predict_covariance_inline(P, Phi, rowptr, colidx, Qd, T,
                                  P.shape[0] if size is None else size)

    return predict_covariance


predict_covariance = _predict_covariance(None)


def _measurement_projection(size: int | None):
    """:func:`measurement_projection` for a state size (``None``: read from ``P``)."""

    @njit(cache=True)
    def measurement_projection(P, H, q, hptr, hidx, Ph):
        """Numba kernel: ``Ph ← P h`` for the measurement row ``h = H[q]`` whose nonzeros are at
        columns ``hidx[hptr[q]:hptr[q + 1]]`` (CSR), and return ``hᵀ P h``.

        No input checks (a kernel): ``P`` (n×n, symmetric: its rows are read), ``H`` (m×n),
        ``Ph`` (n,) float64.

        Examples
        --------
        >>> import numpy as np
        >>> from gyrolib import filtering
        >>> P = np.array([[2.0, 1.0], [1.0, 3.0]]); H = np.array([[0.0, 1.0]])
        >>> Ph = np.zeros(2)
        >>> hptr, hidx = np.array([0, 1]), np.array([1])
        >>> hph = filtering.measurement_projection(P, H, 0, hptr, hidx, Ph)
        >>> float(hph), Ph.tolist()
        (3.0, [1.0, 3.0])
        """
        return measurement_projection_inline(P, H, q, hptr, hidx, Ph,
                                             P.shape[0] if size is None else size)

    return measurement_projection


measurement_projection = _measurement_projection(None)


def _joseph_scalar_update(size: int | None):
    """:func:`joseph_scalar_update` for a state size (``None``: read from ``P``)."""

    @njit(cache=True)
    def joseph_scalar_update(P, Ph, k, S):
        """Numba kernel: the Joseph-form update of ``P`` (in place) for one scalar measurement
        ``z = hᵀ x + v``, ``var v = r``, with any gain ``k`` {cite:p}`BarShalom2001`:

        ``P⁺ = (I − k hᵀ) P (I − k hᵀ)ᵀ + r k kᵀ = P − k (Ph)ᵀ − (Ph) kᵀ + S k kᵀ``

        where ``Ph = P h`` and ``S = hᵀ P h + r`` (from :func:`measurement_projection`).  The
        optimal gain is ``k = Ph / S``; a fixed (suboptimal) gain gives the error covariance of
        that filter.  With ``v = S k / 2 − Ph`` the update is ``P⁺ = P + k vᵀ + v kᵀ`` (two
        products an entry), on the upper triangle, mirrored: ``P`` stays symmetric.

        No input checks (a kernel): ``P`` (n×n), ``Ph``, ``k`` (n,) float64; ``Ph`` is
        overwritten with ``v``.

        Examples
        --------
        A unit-variance scalar read with unit noise: ``P⁺ = 1/2`` (as :func:`joseph_update`).

        >>> import numpy as np
        >>> from gyrolib import filtering
        >>> P = np.ones((1, 1)); Ph = np.ones(1); S = 2.0
        >>> filtering.joseph_scalar_update(P, Ph, Ph / S, S)
        >>> float(P[0, 0])
        0.5
        """
        joseph_scalar_update_inline(P, Ph, k, S, P.shape[0] if size is None else size)

    return joseph_scalar_update


joseph_scalar_update = _joseph_scalar_update(None)


class KalmanKernels(NamedTuple):
    """The numba kernels of the fast recursions for one state size (see
    :func:`kalman_kernels`)."""

    predict_state: Callable
    predict_covariance: Callable
    measurement_projection: Callable
    joseph_scalar_update: Callable


def kalman_kernels(n: int) -> KalmanKernels:
    """:func:`predict_state`, :func:`predict_covariance`, :func:`measurement_projection` and
    :func:`joseph_scalar_update` compiled for the state size ``n``: the
    same code, with loops of a length known at compile time (they unroll; paper GC's
    10-state filter runs about twice as fast).  Call them only with ``n``-state arrays.

    Parameters
    ----------
    n : int
        State size (>= 1).

    Returns
    -------
    KalmanKernels

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import filtering
    >>> k2 = filtering.kalman_kernels(2)
    >>> P = np.eye(2); Ph = np.zeros(2)
    >>> S = k2.measurement_projection(P, np.array([[1.0, 0.0]]), 0, np.array([0, 1]),
    ...                               np.array([0]), Ph) + 1.0
    >>> k2.joseph_scalar_update(P, Ph, Ph / S, S)
    >>> P.diagonal().tolist()
    [0.5, 1.0]
    """
    return _kalman_kernels(v.check_int("n", n, 1))


@functools.cache
def _kalman_kernels(n: int) -> KalmanKernels:
    return KalmanKernels(_predict_state(n), _predict_covariance(n), _measurement_projection(n),
                         _joseph_scalar_update(n))
