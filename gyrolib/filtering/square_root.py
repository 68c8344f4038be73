"""Square-root covariance Kalman filter: an independent check of the Joseph-form recursion.

The covariance is carried as a factor ``S`` with ``P = S Sᵀ`` and never formed:

* time update — the triangular factor of ``[Φ S, L_Q]`` by a QR decomposition of its
  transpose, where ``L_Q L_Qᵀ = Qd`` (a Cholesky factor that tolerates the exactly singular
  directions of ``Qd``: the noises of paper GC do not reach ψ, ω_gc, δ, γ);
* measurement update — Potter's square-root form for each scalar measurement
  (``R`` diagonal): with ``φ = Sᵀh`` and ``α = φᵀφ + r``,
  ``S⁺ = S − (γ/α) (S φ) φᵀ``, ``γ = 1 / (1 + √(r/α))`` {cite:p}`Bierman1977`.

Because ``P = S Sᵀ`` is symmetric positive semi-definite by construction, this recursion
cannot lose definiteness through rounding; comparing it with the Joseph form over a long run
(10⁶ steps) bounds the rounding error of both.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from gyrolib import _compile_note  # noqa: F401  (a line on stderr at the first compile)
from gyrolib import _validation as v
from gyrolib.filtering.covariance import AffineDiscreteModel, CovarianceRun

__all__ = [
    "cholesky_semidefinite",
    "covariance_square_root",
]


def cholesky_semidefinite(P: object) -> np.ndarray:
    """A factor ``S`` with ``S Sᵀ = P`` for a symmetric positive semi-definite ``P`` (a
    singular direction gives a zero column).

    Parameters
    ----------
    P : array_like
        Symmetric positive semi-definite matrix (n×n).

    Returns
    -------
    ndarray
        ``S`` (n×n).

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import filtering
    >>> P = np.array([[4.0, 2.0], [2.0, 1.0]])   # rank 1
    >>> S = filtering.cholesky_semidefinite(P)
    >>> bool(np.allclose(S @ S.T, P, rtol=0.0, atol=1e-12))
    True
    """
    return _checked_cholesky_semidefinite("P", P)


def _checked_cholesky_semidefinite(name: str, P: object) -> np.ndarray:
    P = v.check_array(name, P, ndim=2)
    if P.shape[0] != P.shape[1] or not np.allclose(P, P.T, rtol=1e-12, atol=0.0):
        raise ValueError(f"{name} must be a symmetric square matrix")
    w, V = np.linalg.eigh(0.5 * (P + P.T))
    if np.any(w < -1e-12 * max(1.0, float(np.max(np.abs(w), initial=0.0)))):
        raise ValueError(f"{name} must be positive semi-definite")
    return V * np.sqrt(np.clip(w, 0.0, None))


@njit(cache=True)
def _cholesky_semidefinite_kernel(A, L):
    """Lower-triangular ``L`` with ``L Lᵀ = A`` for a positive semi-definite ``A``: a pivot
    below 1e-13 of its diagonal entry marks a singular direction and its column is zero."""
    n = A.shape[0]
    for i in range(n):
        for j in range(n):
            L[i, j] = 0.0
    for j in range(n):
        d = A[j, j]
        for p in range(j):
            d -= L[j, p] * L[j, p]
        if d <= 1e-13 * A[j, j] or d <= 0.0:
            continue
        ljj = np.sqrt(d)
        L[j, j] = ljj
        for i in range(j + 1, n):
            s = A[i, j]
            for p in range(j):
                s -= L[i, p] * L[j, p]
            L[i, j] = s / ljj


@njit(cache=True)
def _sqrt_kernel(seg, a, b, Phi0, PhiA, PhiB, Qd0, QdA, QdB, H, r, S0, store_every, var,
                 P_stored, min_eig):
    n = S0.shape[0]
    m = H.shape[0]
    S = S0.copy()
    M = np.zeros((2 * n, n))
    LQ = np.zeros((n, n))
    for i in range(n):
        var[0, i] = np.sum(S[i] ** 2)
    P_stored[0] = S @ S.T
    for k in range(seg.shape[0]):
        j = seg[k]
        Phi = Phi0[j] + a[k] * PhiA[j] + b[k] * PhiB[j]
        Qd = Qd0[j] + a[k] * QdA[j] + b[k] * QdB[j]
        _cholesky_semidefinite_kernel(Qd, LQ)
        M[:n, :] = (Phi @ S).T
        M[n:, :] = LQ.T
        Rt = np.linalg.qr(M)[1]
        S = Rt.T.copy()
        for q in range(m):
            h = H[q]
            phi = S.T @ h
            alpha = phi @ phi + r[q]
            gamma = 1.0 / (1.0 + np.sqrt(r[q] / alpha))
            Sphi = S @ phi
            c = gamma / alpha
            for i in range(n):
                for jj in range(n):
                    S[i, jj] -= c * Sphi[i] * phi[jj]
        for i in range(n):
            var[k + 1, i] = np.sum(S[i] ** 2)
        if (k + 1) % store_every == 0:
            P = S @ S.T
            P_stored[(k + 1) // store_every] = P
            # smallest eigenvalue of the correlation form of P: definiteness through the run
            d = np.sqrt(np.diag(P))
            ok = d > 0.0
            idx = np.nonzero(ok)[0]
            C = P[idx][:, idx] / np.outer(d[idx], d[idx])
            e = np.linalg.eigvalsh(C)[0]
            if e < min_eig[0]:
                min_eig[0] = e


def covariance_square_root(model: AffineDiscreteModel, P0: object,
                           store_every: int = 1) -> tuple[CovarianceRun, float]:
    """Covariance recursion of :func:`gyrolib.filtering.covariance_fast` in square-root form.

    Returns the run (variances at every step, ``P`` at every ``store_every``-th step) and the
    smallest eigenvalue of the correlation matrix of ``P`` over the stored steps (> 0: the
    covariance stayed positive definite on the states that carry uncertainty).  An
    independent algorithm (QR time update, Potter measurement updates) to check the Joseph
    recursion over paper GC's 10⁶-step runs.

    Parameters
    ----------
    model : AffineDiscreteModel
        The model.
    P0 : array_like
        Initial covariance (n×n).
    store_every : int
        Keep the full ``P`` every ``store_every`` steps.

    Returns
    -------
    run : CovarianceRun
        As :func:`gyrolib.filtering.covariance_fast` (without gains).
    min_eig : float
        Smallest correlation eigenvalue over the stored steps.

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import filtering
    >>> one, zero = np.ones((1, 1, 1)), np.zeros((1, 1, 1))
    >>> walk = filtering.AffineDiscreteModel(   # x_{k+1} = x_k + w_k, z = x + v, q = r = 1
    ...     seg=np.zeros(50, dtype=np.int64), a=np.zeros(50), b=np.zeros(50), Phi0=one,
    ...     PhiA=zero, PhiB=zero, Qd0=one, QdA=zero, QdB=zero, H=np.ones((1, 1)), r=np.ones(1))
    >>> run, min_eig = filtering.covariance_square_root(walk, np.ones((1, 1)))
    >>> f"{run.var[-1, 0]:.4f}"   # (√5 − 1)/2, as the Joseph recursion
    '0.6180'
    """
    if not isinstance(model, AffineDiscreteModel):
        raise TypeError("model must be an AffineDiscreteModel")
    if model.H1 is not None:
        raise ValueError("model must have a constant H here (H1 = None): the square-root "
                         "recursion does not take a time-varying measurement matrix")
    P0 = v.check_array("P0", P0, shape=(model.n, model.n))
    store_every = v.check_int("store_every", store_every, 1)
    S0 = _checked_cholesky_semidefinite("P0", P0)
    var = np.empty((model.n_steps + 1, model.n))
    P_stored = np.empty((model.n_steps // store_every + 1, model.n, model.n))
    min_eig = np.array([np.inf])
    _sqrt_kernel(model.seg, model.a, model.b, model.Phi0, model.PhiA, model.PhiB, model.Qd0,
                 model.QdA, model.QdB, np.ascontiguousarray(model.H, dtype=float),
                 model.r.astype(float), S0, store_every, var, P_stored, min_eig)
    return CovarianceRun(var=var, P_stored=P_stored, store_every=store_every,
                         gains=None), float(min_eig[0])
