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

Spectral conventions (all per rad/s; ``H(jω)`` the filter's frequency response):

* two-sided, :func:`psd_two_sided`: ``S(ω) = Q |H(jω)|²`` for ``−∞ < ω < ∞``, the Fourier
  transform of the autocovariance, ``var = (1/2π) ∫_{−∞}^{∞} S(ω) dω``;
* one-sided, :func:`psd` (the one plotted, "area under the graph = variance"):
  ``Φ(ω) = S(ω)/π`` for ``ω ≥ 0``, ``var = ∫_0^∞ Φ(ω) dω``.  Per hertz it would be
  ``2π Φ(2π ν)``.

Also: exact discretization (:meth:`ShapingFilter.discretize`), an exact seeded simulation of
a stationary output series (:func:`simulate_shaping_filter`) and the standard error of its
mean square (:func:`mean_square_standard_error`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import scipy.linalg
from numpy.typing import ArrayLike, NDArray

if TYPE_CHECKING:  # python-control and scipy.signal are imported where used: together they
    import control  # are 1 s and 80 MB of every chapter's start-up otherwise

from gyrolib._repr import compact_repr
from gyrolib._validation import (
    check_array,
    check_choice,
    check_in_range,
    check_int,
    check_nonnegative,
    check_positive,
    check_real,
)

__all__ = [
    "F87_READINGS",
    "ShapingFilter",
    "mean_square_standard_error",
    "psd",
    "psd_integral",
    "psd_two_sided",
    "random_drift_filter",
    "simulate_shaping_filter",
    "stationary_covariance",
    "vibration_filter",
]


@compact_repr
@dataclass(frozen=True)
class ShapingFilter:
    """A linear shaping filter ``x' = A x + B w``, ``y = C x``, driven by white noise of
    intensity ``Q`` (two-sided, per unit bandwidth in rad/s: ``E[w(t)w(s)] = Q δ(t−s)``)."""

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    Q: float

    def __post_init__(self) -> None:
        # Single input w, single output y: A n×n, B n×1, C 1×n, Q a scalar intensity.
        A = check_array("A", self.A, ndim=2, min_size=1)
        n = A.shape[0]
        if A.shape != (n, n):
            raise ValueError(f"A must be a square matrix; got shape {A.shape}")
        object.__setattr__(self, "A", A)
        object.__setattr__(self, "B", check_array("B", self.B, shape=(n, 1)))
        object.__setattr__(self, "C", check_array("C", self.C, shape=(1, n)))
        object.__setattr__(self, "Q", check_nonnegative("Q", self.Q))

    def as_control(self) -> control.StateSpace:
        """The filter as a python-control state-space system from ``w`` to ``y``.

        Examples
        --------
        >>> from gyrolib import gc
        >>> gc.GyrocompassParams().random_drift_filter().as_control().nstates
        2
        """
        import control

        return control.ss(self.A, self.B, self.C, np.zeros((1, 1)))

    def poles(self) -> NDArray[np.complex128]:
        """The filter's poles, the eigenvalues of ``A`` (1/s), sorted by real part: the
        filter is stable when every real part is negative.

        Examples
        --------
        >>> from gyrolib import gc
        >>> gc.GyrocompassParams().vibration_filter().poles().real.round(5)
        array([-0.00931, -0.00931])
        """
        return np.sort_complex(np.linalg.eigvals(self.A).astype(complex))

    def stationary_covariance(self) -> NDArray[np.float64]:
        """Steady-state covariance of the filter state (continuous Lyapunov equation).

        Examples
        --------
        >>> from gyrolib import gc
        >>> gc.GyrocompassParams().vibration_filter().stationary_covariance().shape
        (2, 2)
        """
        return stationary_covariance(self.A, self.B, self.Q)

    def variance(self) -> float:
        """Stationary variance of the output ``y``.

        Examples
        --------
        >>> from gyrolib import gc
        >>> f"{gc.GyrocompassParams().vibration_filter().variance():.3g}"
        '1.86e-06'
        """
        P = self.stationary_covariance()
        return float((self.C @ P @ self.C.T)[0, 0])

    def autocorrelation(self, lag: float) -> float:
        """Correlation coefficient of the stationary output ``y`` over ``lag`` (s):
        ``C exp(A |τ|) P Cᵀ / (C P Cᵀ)``.

        Parameters
        ----------
        lag : float
            Time lag τ (s).

        Returns
        -------
        float
            ``E[y(t) y(t + τ)] / E[y²]``.

        Examples
        --------
        >>> from gyrolib import gc
        >>> p = gc.GyrocompassParams()
        >>> f"{p.vibration_filter().autocorrelation(100.0):.2f}"   # N1 of Eq. (6) at 100 s
        '0.23'
        """
        lag = abs(check_real("lag", lag))
        P = self.stationary_covariance()
        cov = self.C @ scipy.linalg.expm(self.A * lag) @ P @ self.C.T
        return float(cov[0, 0]) / self.variance()

    def discretize(self, dt: float) -> tuple[np.ndarray, np.ndarray]:
        """Exact discretization over ``dt``: ``Φ = exp(A dt)`` and
        ``Qd = ∫₀^dt exp(A s) B Q Bᵀ exp(Aᵀ s) ds`` (Van Loan's block exponential,
        {cite:p}`VanLoan1978`).

        Examples
        --------
        >>> import numpy as np
        >>> from gyrolib import gc
        >>> filt = gc.GyrocompassParams().random_drift_filter()
        >>> Phi, Qd = filt.discretize(0.01)
        >>> P = filt.stationary_covariance()
        >>> bool(np.allclose(Phi @ P @ Phi.T + Qd, P, rtol=1e-9, atol=1e-12 * abs(P).max()))
        True
        """
        dt = check_positive("dt", dt)
        n = self.A.shape[0]
        M = np.zeros((2 * n, 2 * n))
        M[:n, :n] = -self.A * dt
        M[:n, n:] = self.B @ np.atleast_2d(self.Q) @ self.B.T * dt
        M[n:, n:] = self.A.T * dt
        E = scipy.linalg.expm(M)
        Phi = E[n:, n:].T.copy()
        Qd = Phi @ E[:n, n:]
        return Phi, 0.5 * (Qd + Qd.T)


#: Readings of F(8,7) of paper GC: ``"eq6"`` (−α1², as Eq. (6) requires) or ``"printed"``
#: (+α1², as the listing prints it: the filter is unstable).
F87_READINGS = ("eq6", "printed")


def vibration_filter(alpha1: float, xi1: float, sigma1_sq: float, *,
                     f87: str = "eq6") -> ShapingFilter:
    """Vibration shaping filter of paper GC, Eq. (6); state ``(N1, N2)``, output ``N1``.

    The white-noise intensity is ``Q1 = 2 ξ1 α1 σ1²`` (paper GC, text after Eq. (6)).
    ``f87="printed"`` gives the filter with F(8,7) = +α1² as the paper's F listing prints it
    (a dropped minus sign): one pole is then positive and the filter has no stationary
    variance.  The one place the book computes that pole (:meth:`ShapingFilter.poles`).

    Parameters
    ----------
    alpha1 : float
        Natural frequency α1 (rad/s, > 0).
    xi1 : float
        Damping ratio ξ1, in (0, 1].
    sigma1_sq : float
        Variance σ1² of N1 (m²/s⁴, > 0).
    f87 : {"eq6", "printed"}, optional
        The sign of F(8,7): Eq. (6)'s −α1² (default) or the listing's +α1².

    Returns
    -------
    ShapingFilter

    Examples
    --------
    >>> from gyrolib import gc
    >>> f"{gc.vibration_filter(1.33e-2, 0.7, 1.86e-6).variance():.3g}"
    '1.86e-06'
    >>> gc.vibration_filter(1.33e-2, 0.7, 1.86e-6, f87="printed").poles().real.round(4)
    array([-0.0255,  0.0069])
    """
    a = check_positive("alpha1", alpha1)
    xi = check_in_range("xi1", xi1, 0.0, 1.0, low_open=True)
    s2 = check_positive("sigma1_sq", sigma1_sq)
    check_choice("f87", f87, F87_READINGS)
    sign = -1.0 if f87 == "eq6" else 1.0
    A = np.array([[0.0, 1.0], [sign * a**2, -2.0 * xi * a]])
    B = np.array([[1.0], [a - 2.0 * xi * a]])
    C = np.array([[1.0, 0.0]])
    return ShapingFilter(A=A, B=B, C=C, Q=2.0 * xi * a * s2)


def random_drift_filter(alpha2: float, xi2: float, sigma2_sq: float) -> ShapingFilter:
    """Random-drift shaping filter of paper GC, Eq. (7); state ``(N3, N4)``, output ``N3``.

    The white-noise intensity is ``Q2 = 4 ξ2 α2³ σ2²`` (paper GC, text after Eq. (7)).

    Parameters
    ----------
    alpha2 : float
        Natural frequency α2 (rad/s, > 0).
    xi2 : float
        Damping ratio ξ2, in (0, 1].
    sigma2_sq : float
        Variance σ2² of N3 (rad²/s², > 0).

    Returns
    -------
    ShapingFilter

    Examples
    --------
    >>> from gyrolib import gc
    >>> f"{gc.random_drift_filter(6.28, 0.4, 2.35e-15).variance():.3g}"
    '2.35e-15'
    """
    a = check_positive("alpha2", alpha2)
    xi = check_in_range("xi2", xi2, 0.0, 1.0, low_open=True)
    s2 = check_positive("sigma2_sq", sigma2_sq)
    A = np.array([[0.0, 1.0], [-(a**2), -2.0 * xi * a]])
    B = np.array([[0.0], [1.0]])
    C = np.array([[1.0, 0.0]])
    return ShapingFilter(A=A, B=B, C=C, Q=4.0 * xi * a**3 * s2)


def stationary_covariance(A: ArrayLike, B: ArrayLike,
                          Q: float | ArrayLike) -> NDArray[np.float64]:
    """Solve ``A P + P Aᵀ + B Q Bᵀ = 0`` for the stationary covariance ``P``.

    ``A`` must be Hurwitz (all eigenvalues in the open left half plane).

    Parameters
    ----------
    A : array_like of shape (n, n)
        Hurwitz state matrix.
    B : array_like of shape (n, 1)
        Noise input.
    Q : float or array_like
        White-noise intensity (>= 0).

    Returns
    -------
    P : ndarray of shape (n, n)

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import gc
    >>> gc.stationary_covariance(np.array([[-1.0]]), np.array([[1.0]]), 2.0)
    array([[1.]])
    """
    A = check_array("A", A, ndim=2, min_size=1)
    n = A.shape[0]
    if A.shape != (n, n):
        raise ValueError(f"A must be a square matrix; got shape {A.shape}")
    B = check_array("B", B, shape=(n, None))
    Qm = np.atleast_2d(check_array("Q", Q))
    if Qm.shape != (B.shape[1], B.shape[1]):
        raise ValueError(f"Q must be {B.shape[1]}x{B.shape[1]}; got shape {Qm.shape}")
    if np.any(np.diag(Qm) < 0.0):
        raise ValueError("Q must be a noise intensity with a diagonal >= 0")
    if np.any(np.linalg.eigvals(A).real >= 0.0):
        raise ValueError("A must be Hurwitz (every eigenvalue with negative real part)")
    P = scipy.linalg.solve_continuous_lyapunov(A, -B @ Qm @ B.T)
    return 0.5 * (P + P.T)


# Spectra --------------------------------------------------------------------------------------
def _check_filter(filt: object) -> ShapingFilter:
    if not isinstance(filt, ShapingFilter):
        raise TypeError(f"filt must be a ShapingFilter; got {type(filt).__name__}")
    return filt


def psd_two_sided(filt: ShapingFilter, omega: ArrayLike) -> NDArray[np.float64]:
    """Two-sided PSD of the output per rad/s, ``S(ω) = Q |H(jω)|²`` with
    ``H(jω) = C (jωI − A)⁻¹ B``, so that ``var = (1/2π) ∫_{−∞}^{∞} S(ω) dω``.

    ``H`` is evaluated as python-control's ``frequency_response`` does it (one linear solve
    per frequency, the same LAPACK solve), all frequencies in one call; at a pole on the
    imaginary axis (an unstable filter), by python-control itself, which warns and returns
    ``inf`` there.

    ``omega`` (rad/s) is a 1-D array; ``S`` is even in ``ω``.

    Parameters
    ----------
    filt : ShapingFilter
    omega : array_like
        Angular frequencies (rad/s), 1-D.

    Returns
    -------
    ndarray
        ``S(ω)``, (output unit)² per rad/s.

    Examples
    --------
    >>> from gyrolib import gc
    >>> f"{gc.psd_two_sided(gc.GyrocompassParams().random_drift_filter(), [0.0])[0]:.3g}"
    '5.99e-16'
    """
    filt = _check_filter(filt)
    omega = check_array("omega", omega, ndim=1)
    n = filt.A.shape[0]
    s = 1j * np.abs(omega)
    try:  # (jωI − A) X = B at every ω: python-control's loop, as one batched solve
        x = np.linalg.solve(s[:, None, None] * np.eye(n) - filt.A,
                            np.broadcast_to(filt.B.astype(complex), (s.size, n, 1)))
    except np.linalg.LinAlgError:  # a pole on the axis: python-control's inf and warning
        import control

        resp = control.frequency_response(filt.as_control(), np.abs(omega))
        mag = np.asarray(resp.magnitude, dtype=float).reshape(omega.shape)
        return filt.Q * mag**2
    mag = np.abs((filt.C @ x)[:, 0, 0])
    return filt.Q * mag**2


def psd(filt: ShapingFilter, omega: ArrayLike) -> NDArray[np.float64]:
    """One-sided PSD of the output per rad/s, ``Φ(ω) = Q |H(jω)|² / π`` for ``ω ≥ 0``.

    The area under it is the variance: ``∫_0^∞ Φ(ω) dω = var`` (paper GC, Figure 2: "the
    areas under the graphs equal σ1² and σ2²").  Units: (output unit)² per rad/s.

    Parameters
    ----------
    filt : ShapingFilter
    omega : array_like
        Angular frequencies (rad/s, >= 0), 1-D.

    Returns
    -------
    ndarray
        ``Φ(ω)``.

    Examples
    --------
    >>> from gyrolib import gc
    >>> f"{gc.psd(gc.GyrocompassParams().random_drift_filter(), [0.0])[0]:.3g}"
    '1.91e-16'
    """
    omega = check_array("omega", omega, ndim=1)
    if np.any(omega < 0.0):
        raise ValueError("omega must be >= 0 for the one-sided PSD")
    return psd_two_sided(filt, omega) / np.pi


def psd_integral(filt: ShapingFilter, *, decades: float = 6.0, n: int = 4001) -> float:
    """Area under the one-sided PSD, ``∫_0^∞ Φ(ω) dω``, by quadrature.

    The trapezoid rule in ``ln ω`` (spectrally accurate for this smooth, decaying integrand)
    over ``decades`` decades either side of the filter's natural frequencies, plus both tails
    in closed form: ``Φ(ω_lo) ω_lo`` below (``Φ`` is flat there) and
    ``Φ(ω_hi) ω_hi / (p − 1)`` above, where ``Φ ~ ω^{−p}`` with ``p`` the fitted slope.
    With the defaults the relative error is ~10⁻¹¹ for paper GC's filters (it falls as
    ``1/n²``: the tails' closed forms are first-order accurate in the grid step).

    Parameters
    ----------
    filt : ShapingFilter
    decades : float, default 6.0
        Decades either side of the natural frequencies (> 0).
    n : int, default 4001
        Quadrature points (>= 101).

    Returns
    -------
    float
        The variance, (output unit)².

    Examples
    --------
    >>> from gyrolib import gc
    >>> f"{gc.psd_integral(gc.GyrocompassParams().random_drift_filter()):.3g}"
    '2.35e-15'
    """
    filt = _check_filter(filt)
    decades = check_positive("decades", decades)
    n = check_int("n", n, 101)
    lam = np.abs(np.linalg.eigvals(filt.A))
    lo = lam.min() * 10.0**-decades
    hi = lam.max() * 10.0**decades
    u = np.linspace(np.log(lo), np.log(hi), n)
    omega = np.exp(u)
    phi = psd(filt, omega)
    body = float(np.trapezoid(phi * omega, u))
    slope = -(np.log(phi[-1]) - np.log(phi[-2])) / (u[-1] - u[-2])
    if not slope > 1.0:
        raise ValueError("the PSD must decay faster than 1/ω for a finite variance")
    return body + float(phi[0] * omega[0]) + float(phi[-1] * omega[-1] / (slope - 1.0))


# Simulation -----------------------------------------------------------------------------------
def _covariance_sqrt(M: np.ndarray) -> NDArray[np.float64]:
    """A square root ``L`` with ``L Lᵀ = M`` for a symmetric positive semi-definite ``M``."""
    w, V = np.linalg.eigh(0.5 * (M + M.T))
    return V * np.sqrt(np.clip(w, 0.0, None))


def simulate_shaping_filter(filt: ShapingFilter, dt: float, n: int,
                            seed: int) -> NDArray[np.float64]:
    """Exact simulation of the stationary output ``y(t_k)``, ``t_k = k·dt``, ``k < n``.

    The state starts from its stationary distribution ``N(0, P∞)`` and steps with the exact
    discrete model (:meth:`ShapingFilter.discretize`): ``x_{k+1} = Φ x_k + L e_k``,
    ``L Lᵀ = Qd``, ``e_k ~ N(0, I)`` from ``numpy.random.default_rng(seed)``.  There is no
    time-step error at any ``dt``.  The recursion runs as IIR filters (``scipy.signal.lfilter``)
    on each noise channel and on the initial state, which is the same linear map evaluated in
    compiled code.

    Parameters
    ----------
    filt : ShapingFilter
    dt : float
        Sampling interval (s, > 0).
    n : int
        Number of samples (>= 1).
    seed : int
        Seed of ``numpy.random.default_rng`` (>= 0).

    Returns
    -------
    ndarray of shape (n,)

    Examples
    --------
    >>> from gyrolib import gc
    >>> gc.simulate_shaping_filter(gc.GyrocompassParams().random_drift_filter(), 0.05, 1000,
    ...                            seed=1).shape
    (1000,)
    """
    import scipy.signal

    filt = _check_filter(filt)
    dt = check_positive("dt", dt)
    n = check_int("n", n, 1)
    seed = check_int("seed", seed, 0)
    rng = np.random.default_rng(seed)
    Phi, Qd = filt.discretize(dt)
    L = _covariance_sqrt(Qd)
    x0 = _covariance_sqrt(filt.stationary_covariance()) @ rng.standard_normal(Phi.shape[0])
    e = rng.standard_normal((n, L.shape[1]))
    zero = np.zeros((1, 1))
    y = np.zeros(n)
    for i in range(L.shape[1]):
        b, a = scipy.signal.ss2tf(Phi, L[:, [i]], filt.C, zero)
        y += scipy.signal.lfilter(b[0], a, e[:, i])
    # Free response C Φ^k x0: the impulse response of C (zI − Φ)⁻¹ x0, shifted by one step.
    b, a = scipy.signal.ss2tf(Phi, x0[:, None], filt.C, zero)
    impulse = np.zeros(n + 1)
    impulse[0] = 1.0
    y += scipy.signal.lfilter(b[0], a, impulse)[1:]
    return y


def mean_square_standard_error(filt: ShapingFilter, dt: float, n: int) -> float:
    """Standard deviation of the mean square ``(1/n) Σ y_k²`` of ``n`` stationary samples.

    For a zero-mean Gaussian series with autocovariance ``R_k = C Φ^k P∞ Cᵀ``,
    ``Var[(1/n) Σ y_k²] ≈ (2/n) Σ_{k=−∞}^{∞} R_k²`` (valid for ``n`` much longer than the
    correlation length).  ``Σ_{k≥0} R_k² = vᵀ W v`` with ``v = P∞ Cᵀ`` and ``W`` from the
    discrete Lyapunov equation ``W = Φᵀ W Φ + Cᵀ C`` — the correlation time is accounted
    for exactly.

    Parameters
    ----------
    filt : ShapingFilter
    dt : float
        Sampling interval (s, > 0).
    n : int
        Number of samples (>= 1).

    Returns
    -------
    float
        Standard error of the mean square, (output unit)².

    Examples
    --------
    >>> from gyrolib import gc
    >>> p = gc.GyrocompassParams()
    >>> se = gc.mean_square_standard_error(p.random_drift_filter(), 0.05, 1000)
    >>> f"{se / p.sigma2_sq:.2f}"
    '0.11'
    """
    filt = _check_filter(filt)
    dt = check_positive("dt", dt)
    n = check_int("n", n, 1)
    Phi, _ = filt.discretize(dt)
    P = filt.stationary_covariance()
    vvec = P @ filt.C.T
    W = scipy.linalg.solve_discrete_lyapunov(Phi.T, filt.C.T @ filt.C)
    r0 = float((filt.C @ vvec)[0, 0])
    one_sided = float((vvec.T @ W @ vvec)[0, 0])
    return float(np.sqrt(2.0 / n * (2.0 * one_sided - r0**2)))
