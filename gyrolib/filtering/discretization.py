"""Exact discretization of ``x' = F x + G w`` over a step ``dt`` with ``F`` frozen.

* :func:`van_loan` — transition ``Φ = exp(F dt)`` and process-noise covariance
  ``Qd = ∫₀^dt exp(F s) G Q Gᵀ exp(Fᵀ s) ds`` by Van Loan's block exponential
  {cite:p}`VanLoan1978`.
* :func:`van_loan_derivatives` — the same plus the exact first derivatives of ``Φ`` and ``Qd``
  along given directions of ``F`` (Fréchet derivative of the matrix exponential), the basis of
  :class:`gyrolib.filtering.AffineDiscreteModel`.
* :func:`covariance_factor` — a factor ``L`` with ``L Lᵀ = Q`` of a symmetric positive
  semi-definite covariance (noise generation).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
from numpy.typing import ArrayLike, NDArray

from gyrolib import _validation as v

__all__ = [
    "covariance_factor",
    "van_loan",
    "van_loan_derivatives",
]


# Discretization --------------------------------------------------------------------------
def _check_model(F: object, G: object, Qc: object, dt: object) -> tuple:
    F = v.check_array("F", F, ndim=2)
    n = F.shape[0]
    if F.shape != (n, n):
        raise ValueError(f"F must be square; got shape {F.shape}")
    G = v.check_array("G", G, shape=(n, None))
    Qc = v.check_array("Qc", Qc, shape=(G.shape[1], G.shape[1]))
    v.check_covariance("Qc", Qc)
    dt = v.check_positive("dt", dt)
    return F, G, Qc, dt


def van_loan(F: ArrayLike, G: ArrayLike, Qc: ArrayLike, dt: float
             ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Exact discretization of ``x' = F x + G w`` (``E[w wᵀ] = Qc δ``) over ``dt``.

    Van Loan (1978): with ``M = [[−F, G Qc Gᵀ], [0, Fᵀ]] dt`` and ``E = exp(M)``,
    ``Φ = E₂₂ᵀ`` and ``Qd = Φ E₁₂`` {cite:p}`VanLoan1978`.  Paper GC's filter is Eq. (8)
    discretized this way.

    Parameters
    ----------
    F : array_like
        System matrix (n×n), frozen over the step.
    G : array_like
        Noise input matrix (n×p).
    Qc : array_like
        Intensity of the white noise ``w`` (p×p, symmetric, diagonal >= 0).
    dt : float
        Step (> 0).

    Returns
    -------
    Phi : ndarray
        Transition matrix ``exp(F dt)`` (n×n).
    Qd : ndarray
        Process-noise covariance of the step (n×n, symmetric).

    Examples
    --------
    Scalar ``x' = −x + w`` with ``Qc = 2``: ``Φ = e^{−dt}``, ``Qd = 1 − e^{−2 dt}``.

    >>> from gyrolib import filtering
    >>> Phi, Qd = filtering.van_loan([[-1.0]], [[1.0]], [[2.0]], 0.5)
    >>> f"{Phi[0, 0]:.4f} {Qd[0, 0]:.4f}"
    '0.6065 0.6321'
    """
    F, G, Qc, dt = _check_model(F, G, Qc, dt)
    n = F.shape[0]
    M = np.zeros((2 * n, 2 * n))
    M[:n, :n] = -F * dt
    M[:n, n:] = G @ Qc @ G.T * dt
    M[n:, n:] = F.T * dt
    E = scipy.linalg.expm(M)
    Phi = E[n:, n:].T.copy()
    Qd = Phi @ E[:n, n:]
    return Phi, 0.5 * (Qd + Qd.T)


def van_loan_derivatives(
    F: ArrayLike, G: ArrayLike, Qc: ArrayLike, dt: float, directions: list[ArrayLike]
) -> tuple[NDArray[np.float64], NDArray[np.float64], list[NDArray[np.float64]],
           list[NDArray[np.float64]]]:
    """``(Φ, Qd)`` of :func:`van_loan` and their exact derivatives along each direction
    ``E`` of ``F`` (``d/dε`` at ``F + ε E``), from the Fréchet derivative of the block
    exponential (Van Loan's block-triangular exponential again, one for all directions,
    {cite:p}`VanLoan1978`): the basis of the affine expansion of paper GC's ``F(β_n)`` in
    ``(sin β_n, cos β_n)``.

    Parameters
    ----------
    F, G, Qc, dt
        As in :func:`van_loan`.
    directions : list of array_like
        Directions ``E`` (n×n each).

    Returns
    -------
    Phi, Qd : ndarray
        As :func:`van_loan`.
    dPhi, dQd : list of ndarray
        Their derivatives along each direction.

    Examples
    --------
    ``d/dε exp((−1 + ε) dt) = dt e^{−dt}`` at ``ε = 0``:

    >>> from gyrolib import filtering
    >>> _, _, dPhi, _ = filtering.van_loan_derivatives([[-1.0]], [[1.0]], [[2.0]], 0.5,
    ...                                                [[[1.0]]])
    >>> f"{dPhi[0][0, 0]:.4f}"
    '0.3033'
    """
    F, G, Qc, dt = _check_model(F, G, Qc, dt)
    if not isinstance(directions, list | tuple):
        raise TypeError("directions must be a list or tuple of n×n arrays; "
                        f"got {type(directions).__name__}")
    n = F.shape[0]
    dirs = [v.check_array("direction", d, shape=(n, n)) for d in directions]
    M = np.zeros((2 * n, 2 * n))
    M[:n, :n] = -F * dt
    M[:n, n:] = G @ Qc @ G.T * dt
    M[n:, n:] = F.T * dt
    # one exponential for all: exp([[M, dM_1, …, dM_k], [0, M, 0 …], …, [0 …, M]]) holds
    # exp(M) on its diagonal and the Fréchet derivative along dM_i in block (0, i)
    m = 2 * n
    B = np.zeros(((len(dirs) + 1) * m, (len(dirs) + 1) * m))
    for i in range(len(dirs) + 1):
        B[i * m:(i + 1) * m, i * m:(i + 1) * m] = M
    for i, d in enumerate(dirs, start=1):
        B[:n, i * m:i * m + n] = -d * dt
        B[n:m, i * m + n:(i + 1) * m] = d.T * dt
    X = scipy.linalg.expm(B)
    E = X[:m, :m]
    Phi = E[n:, n:].T.copy()
    Qd = Phi @ E[:n, n:]
    dPhis, dQds = [], []
    for i in range(1, len(dirs) + 1):
        L = X[:m, i * m:(i + 1) * m]
        dPhi = L[n:, n:].T.copy()
        dQd = dPhi @ E[:n, n:] + Phi @ L[:n, n:]
        dPhis.append(dPhi)
        dQds.append(0.5 * (dQd + dQd.T))
    return Phi, 0.5 * (Qd + Qd.T), dPhis, dQds


def covariance_factor(Q: ArrayLike) -> NDArray[np.float64]:
    """A factor ``L`` (n×n) with ``L Lᵀ = Q`` for a symmetric positive semi-definite ``Q``.

    Diagonally scaled eigendecomposition, so that entries many orders of magnitude apart (as
    in paper GC's ``Qd``) are reproduced to rounding relative to ``√(Qᵢᵢ Qⱼⱼ)``; zero rows
    stay zero.  Used to draw ``N(0, Q)`` samples (paper GC's initial states).

    Parameters
    ----------
    Q : array_like
        Symmetric positive semi-definite matrix (n×n).

    Returns
    -------
    ndarray
        ``L`` (n×n) with ``L Lᵀ = Q``.

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import filtering
    >>> Q = np.array([[4.0, 2.0], [2.0, 1.0]])   # singular
    >>> L = filtering.covariance_factor(Q)
    >>> bool(np.allclose(L @ L.T, Q, rtol=0.0, atol=1e-12))
    True
    """
    Q = v.check_array("Q", Q, ndim=2)
    if Q.shape[0] != Q.shape[1]:
        raise ValueError(f"Q must be a square matrix; got shape {Q.shape}")
    v.check_covariance("Q", Q)
    d = np.sqrt(np.diag(Q))
    nz = d > 0.0
    L = np.zeros_like(Q)
    if not np.any(nz):
        return L
    Dn = d[nz]
    S = Q[np.ix_(nz, nz)] / np.outer(Dn, Dn)
    lam, V = np.linalg.eigh(0.5 * (S + S.T))
    Ls = V * np.sqrt(np.clip(lam, 0.0, None))
    L[np.ix_(nz, nz)] = Dn[:, None] * Ls
    return L
