"""Measurement updates of the discrete Kalman filter {cite:p}`Kalman1960`.

* :func:`joseph_update` — Joseph form ``P⁺ = (I−KH)P(I−KH)ᵀ + KRKᵀ``, valid for any gain;
* :func:`sequential_update` — the independent alternative: the measurements processed one
  scalar at a time in the conventional form ``P⁺ = P − k hᵀP`` {cite:p}`Bierman1977`;
* the numba kernels of the fast recursions (no input checks; float64 C-contiguous arrays,
  updated in place), shared by :func:`gyrolib.filtering.covariance_fast` and
  :func:`gyrolib.gc.calibrate`: :func:`measurement_projection` (``P h`` and ``hᵀ P h`` for a
  sparse row ``h``) and :func:`joseph_scalar_update` (the Joseph form for one scalar
  measurement).
"""

from __future__ import annotations

import numpy as np
from numba import njit
from numpy.typing import ArrayLike, NDArray

from gyrolib import _validation as v

__all__ = [
    "joseph_scalar_update",
    "joseph_update",
    "measurement_projection",
    "sequential_update",
]


# Measurement updates -----------------------------------------------------------------------
def _check_update(x: object, P: object, z: object, H: object, R: object) -> tuple:
    x = v.check_array("x", x, ndim=1)
    n = x.size
    P = v.check_array("P", P, shape=(n, n))
    H = v.check_array("H", H, shape=(None, n))
    m = H.shape[0]
    z = v.check_array("z", z, shape=(m,))
    R = v.check_array("R", R, shape=(m, m))
    if np.any(np.diag(P) < 0.0):
        raise ValueError("P must have a diagonal >= 0 (variances)")
    if np.any(np.diag(R) < 0.0):
        raise ValueError("R must have a diagonal >= 0 (measurement-noise variances)")
    return x, P, z, H, R


def joseph_update(x: ArrayLike, P: ArrayLike, z: ArrayLike, H: ArrayLike, R: ArrayLike
                  ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Kalman measurement update in Joseph form {cite:p}`BarShalom2001`.

    ``K = P Hᵀ (H P Hᵀ + R)⁻¹``, ``x⁺ = x + K (z − H x)``,
    ``P⁺ = (I − K H) P (I − K H)ᵀ + K R Kᵀ`` (symmetric and positive semi-definite by
    construction).

    Parameters
    ----------
    x : array_like
        Prior state (n,).
    P : array_like
        Prior covariance (n×n).
    z : array_like
        Measurements (m,).
    H : array_like
        Measurement matrix (m×n).
    R : array_like
        Measurement-noise covariance (m×m).

    Returns
    -------
    x : ndarray
        Posterior state.
    P : ndarray
        Posterior covariance.
    K : ndarray
        Gain (n×m).

    Examples
    --------
    >>> from gyrolib import filtering
    >>> x, P, K = filtering.joseph_update([0.0], [[1.0]], [1.0], [[1.0]], [[1.0]])
    >>> f"{x[0]:.2f} {P[0, 0]:.2f} {K[0, 0]:.2f}"
    '0.50 0.50 0.50'
    """
    x, P, z, H, R = _check_update(x, P, z, H, R)
    S = H @ P @ H.T + R
    try:
        K = np.linalg.solve(S, H @ P).T
    except np.linalg.LinAlgError:
        raise ValueError("R (with H P Hᵀ) must make the innovation covariance H P Hᵀ + R "
                         "nonsingular; got a singular one") from None
    A = np.eye(x.size) - K @ H
    Pn = A @ P @ A.T + K @ R @ K.T
    return x + K @ (z - H @ x), 0.5 * (Pn + Pn.T), K


def sequential_update(x: ArrayLike, P: ArrayLike, z: ArrayLike, H: ArrayLike,
                      R: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Kalman update processing the ``m`` measurements one scalar at a time, in the
    conventional form ``k = P h / (hᵀ P h + r)``, ``P⁺ = P − k hᵀ P`` {cite:p}`Bierman1977`.

    Requires a diagonal ``R`` (independent sensor noises, as paper GC's three sensors).  An
    independent algorithm to cross-check :func:`joseph_update`.

    Parameters
    ----------
    x, P, z, H, R
        As in :func:`joseph_update`; ``R`` diagonal.

    Returns
    -------
    x : ndarray
        Posterior state.
    P : ndarray
        Posterior covariance.

    Examples
    --------
    Two unit-variance readings of a unit-variance scalar: ``P⁺ = 1/3``, ``x⁺ = 2/3``.

    >>> import numpy as np
    >>> from gyrolib import filtering
    >>> x, P = filtering.sequential_update([0.0], [[1.0]], [1.0, 1.0], [[1.0], [1.0]],
    ...                                    np.eye(2))
    >>> f"{x[0]:.4f} {P[0, 0]:.4f}"
    '0.6667 0.3333'
    """
    x, P, z, H, R = _check_update(x, P, z, H, R)
    if np.any(R != np.diag(np.diag(R))):
        raise ValueError("R must be diagonal for sequential scalar updates")
    x = x.copy()
    P = P.copy()
    for i in range(H.shape[0]):
        h = H[i]
        Ph = P @ h
        s = float(h @ Ph) + R[i, i]
        if not s > 0.0:
            raise ValueError(f"R[{i}, {i}] (with hᵀ P h) must give a positive innovation "
                             f"variance; got {s}")
        k = Ph / s
        x = x + k * (z[i] - float(h @ x))
        P = P - np.outer(k, Ph)
    return x, 0.5 * (P + P.T)


# Kernels (numba) ---------------------------------------------------------------------------
@njit(cache=True)
def measurement_projection(P, H, q, hptr, hidx, Ph):
    """Numba kernel: ``Ph ← P h`` for the measurement row ``h = H[q]`` whose nonzeros are at
    columns ``hidx[hptr[q]:hptr[q + 1]]`` (CSR), and return ``hᵀ P h``.

    No input checks (a kernel): ``P`` (n×n, symmetric), ``H`` (m×n), ``Ph`` (n,) float64.

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import filtering
    >>> P = np.array([[2.0, 1.0], [1.0, 3.0]]); H = np.array([[0.0, 1.0]])
    >>> Ph = np.zeros(2)
    >>> hph = filtering.measurement_projection(P, H, 0, np.array([0, 1]), np.array([1]), Ph)
    >>> float(hph), Ph.tolist()
    (3.0, [1.0, 3.0])
    """
    n = P.shape[0]
    lo = hptr[q]
    hi = hptr[q + 1]
    for i in range(n):
        s = 0.0
        for p in range(lo, hi):
            c = hidx[p]
            s += P[i, c] * H[q, c]
        Ph[i] = s
    hph = 0.0
    for p in range(lo, hi):
        c = hidx[p]
        hph += H[q, c] * Ph[c]
    return hph


@njit(cache=True)
def joseph_scalar_update(P, Ph, k, S):
    """Numba kernel: the Joseph-form update of ``P`` (in place) for one scalar measurement
    ``z = hᵀ x + v``, ``var v = r``, with any gain ``k`` {cite:p}`BarShalom2001`:

    ``P⁺ = (I − k hᵀ) P (I − k hᵀ)ᵀ + r k kᵀ = P − k (Ph)ᵀ − (Ph) kᵀ + S k kᵀ``

    where ``Ph = P h`` and ``S = hᵀ P h + r`` (from :func:`measurement_projection`).  The
    optimal gain is ``k = Ph / S``; a fixed (suboptimal) gain gives the error covariance of
    that filter.  With ``v = S k / 2 − Ph`` the update is ``P⁺ = P + k vᵀ + v kᵀ`` (two
    products an entry), the same expression for ``(i, j)`` and ``(j, i)``: a symmetric ``P``
    stays symmetric.

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
    n = P.shape[0]
    half = 0.5 * S
    for i in range(n):
        Ph[i] = half * k[i] - Ph[i]
    for i in range(n):
        ki = k[i]
        vi = Ph[i]
        for j in range(n):
            P[i, j] += ki * Ph[j] + vi * k[j]
