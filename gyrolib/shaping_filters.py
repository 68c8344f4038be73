"""Second-order shaping filters of paper GC, Eqs. (6) and (7).

A shaping filter turns continuous white noise ``w`` of intensity ``Q`` (two-sided:
``E[w(t) w(s)] = Q δ(t − s)``) into a coloured stationary process.  Paper GC uses two:

* Eq. (6), aircraft vibration acceleration ``N1`` (measured on the HFB 320)::

      N1' = N2 + w1
      N2' = −α1² N1 − 2 ξ1 α1 N2 + (α1 − 2 ξ1 α1) w1

  i.e. ``N1(s) = (s + α1) / (s² + 2 ξ1 α1 s + α1²) · w1(s)``, with ``Q1 = 2 ξ1 α1 σ1²``;

* Eq. (7), random gyro drift ``N3 = ω_rnd`` (an oscillatory link)::

      N3' = N4
      N4' = −α2² N3 − 2 ξ2 α2 N4 + w2

  i.e. ``N3(s) = 1 / (s² + 2 ξ2 α2 s + α2²) · w2(s)``, with ``Q2 = 4 ξ2 α2³ σ2²``.

With those intensities the stationary variance of ``N1`` is ``σ1²`` and that of ``N3`` is
``σ2²`` (derived symbolically in the model chapter).
"""

from __future__ import annotations

from dataclasses import dataclass

import control
import numpy as np
import scipy.linalg

from gyrolib._validation import check_array, check_in_range, check_positive

__all__ = [
    "ShapingFilter",
    "random_drift_filter",
    "stationary_covariance",
    "vibration_filter",
]


@dataclass(frozen=True)
class ShapingFilter:
    """A linear shaping filter ``x' = A x + B w``, ``y = C x``, driven by white noise of
    intensity ``Q`` (two-sided, per unit bandwidth in rad/s: ``E[w(t)w(s)] = Q δ(t−s)``)."""

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    Q: float

    def as_control(self) -> control.StateSpace:
        """The filter as a python-control state-space system from ``w`` to ``y``."""
        return control.ss(self.A, self.B, self.C, np.zeros((1, 1)))

    def stationary_covariance(self) -> np.ndarray:
        """Steady-state covariance of the filter state (continuous Lyapunov equation)."""
        return stationary_covariance(self.A, self.B, self.Q)

    def variance(self) -> float:
        """Stationary variance of the output ``y``."""
        P = self.stationary_covariance()
        return float((self.C @ P @ self.C.T)[0, 0])


def vibration_filter(alpha1: float, xi1: float, sigma1_sq: float) -> ShapingFilter:
    """Vibration shaping filter of paper GC, Eq. (6); state ``(N1, N2)``, output ``N1``.

    The white-noise intensity is ``Q1 = 2 ξ1 α1 σ1²`` (paper GC, text after Eq. (6)).
    """
    a = check_positive("alpha1", alpha1)
    xi = check_in_range("xi1", xi1, 0.0, 1.0, low_open=True)
    s2 = check_positive("sigma1_sq", sigma1_sq)
    A = np.array([[0.0, 1.0], [-(a**2), -2.0 * xi * a]])
    B = np.array([[1.0], [a - 2.0 * xi * a]])
    C = np.array([[1.0, 0.0]])
    return ShapingFilter(A=A, B=B, C=C, Q=2.0 * xi * a * s2)


def random_drift_filter(alpha2: float, xi2: float, sigma2_sq: float) -> ShapingFilter:
    """Random-drift shaping filter of paper GC, Eq. (7); state ``(N3, N4)``, output ``N3``.

    The white-noise intensity is ``Q2 = 4 ξ2 α2³ σ2²`` (paper GC, text after Eq. (7)).
    """
    a = check_positive("alpha2", alpha2)
    xi = check_in_range("xi2", xi2, 0.0, 1.0, low_open=True)
    s2 = check_positive("sigma2_sq", sigma2_sq)
    A = np.array([[0.0, 1.0], [-(a**2), -2.0 * xi * a]])
    B = np.array([[0.0], [1.0]])
    C = np.array([[1.0, 0.0]])
    return ShapingFilter(A=A, B=B, C=C, Q=4.0 * xi * a**3 * s2)


def stationary_covariance(A: np.ndarray, B: np.ndarray, Q: float | np.ndarray) -> np.ndarray:
    """Solve ``A P + P Aᵀ + B Q Bᵀ = 0`` for the stationary covariance ``P``.

    ``A`` must be Hurwitz (all eigenvalues in the open left half plane).
    """
    A = check_array("A", A, ndim=2)
    n = A.shape[0]
    B = check_array("B", B, shape=(n, None))
    Qm = np.atleast_2d(check_array("Q", Q))
    if Qm.shape != (B.shape[1], B.shape[1]):
        raise ValueError(f"Q must be {B.shape[1]}x{B.shape[1]}; got shape {Qm.shape}")
    if np.any(np.linalg.eigvals(A).real >= 0.0):
        raise ValueError("A must be Hurwitz (every eigenvalue with negative real part)")
    P = scipy.linalg.solve_continuous_lyapunov(A, -B @ Qm @ B.T)
    return 0.5 * (P + P.T)
