"""Measurement updates of the discrete Kalman filter {cite:p}`Kalman1960`.

* :func:`joseph_update` — Joseph form ``P⁺ = (I−KH)P(I−KH)ᵀ + KRKᵀ``, valid for any gain;
* :func:`sequential_update` — the independent alternative: the measurements processed one
  scalar at a time in the conventional form ``P⁺ = P − k hᵀP`` {cite:p}`Bierman1977`.

The numba kernels of the fast recursions (the Joseph form for one scalar measurement among
them) are in :mod:`gyrolib.filtering.kernels`.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrolib import _validation as v

__all__ = [
    "joseph_update",
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
