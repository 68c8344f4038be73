"""Paper RSF: in-flight correction of the scale factor of a roll gyro by a MEMS indicator
gyrostabilizer (GS).

SI inside: angles in rad, rates in rad/s, time in s, accelerations in m/s², scale-factor
errors dimensionless (use :mod:`gyrolib.units` for °/s, °/h, ppm at the edges).

The roll-gyro measurement model of the paper (before its Eq. (2))::

    ω_x = (1 + ε1) ω_true + ε0

and Eqs. (1)–(9) as functions:

=========  =====================================================================
Eq. (1)    :func:`roll_difference`  Δγ_i = γ_SINS,i − γ_GS,i
Eq. (2)    :func:`sf_error_estimate`  ε̂1 = Δγ / (ω_x Δt)
K          :func:`correction_coefficient`  K = 1 − ε̂1 ("linear") or 1/(1 + ε̂1)
Eq. (3)    :func:`corrected_rate`  ω̂_x = K ω_x
Eq. (4)    :func:`sins_roll_error`  Δγ_SINS = ε1 ω t (+ ε0 t)
Eq. (5)    :func:`difference_error`  error of the measured Δγ over one interval
Eq. (6)    :func:`gs_roll_error_nonideal`  ε0,GS t + ε1,GS ∫ω_unc dt + Δγ_enc
Eq. (7)    :func:`delta_k`  δK = [(ε0,GS + ε1,GS ω_unc)Δt + Δγ_enc] / (ω_x Δt)
Eq. (8)    :func:`lateral_deviation_cubic`, :func:`lateral_deviation_exact` (and the
           vertical component the paper leaves out, :func:`vertical_deviation_exact`)
Eq. (9)    :func:`gs_roll_error_ideal`  ε0,GS t + Δγ_enc
=========  =====================================================================
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrolib import _validation as v
from gyrolib.rsf._inputs import check_nonzero, check_sf, check_value
from gyrolib.units import G0

__all__ = [
    "K_FORMS",
    "corrected_rate",
    "correction_coefficient",
    "delta_k",
    "delta_k_ideal",
    "difference_error",
    "fraction_compensated",
    "gs_bias_total",
    "gs_roll_error_ideal",
    "gs_roll_error_nonideal",
    "gyro_output",
    "k_true",
    "lateral_acceleration_error",
    "lateral_deviation_cubic",
    "lateral_deviation_exact",
    "relative_k_error",
    "residual_sf_error",
    "roll_difference",
    "sf_error_estimate",
    "sins_roll_error",
    "vertical_deviation_exact",
]


#: The two readings of the garbled correction coefficient: ``"linear"`` K = 1 − ε̂1,
#: ``"reciprocal"`` K = 1/(1 + ε̂1).
K_FORMS: tuple[str, ...] = ("linear", "reciprocal")


# The measurement model and Eqs. (1)-(3) ----------------------------------------------------------
# One-line formulas take numbers or arrays as they come (numpy broadcasting); their inputs are
# checked at the doors: the sensor records, the simulation's configuration and the entry
# points that the chapters and the command line call (sf_error_estimate, correction_coefficient,
# delta_k, the tables and the claims).
def _arr(x: ArrayLike) -> float | NDArray[np.float64]:
    """A float for a 0-d result, else the float array."""
    out = np.asarray(x, dtype=float)
    return float(out) if out.ndim == 0 else out


def gyro_output(omega_true: ArrayLike, eps1: ArrayLike,
                eps0: ArrayLike = 0.0) -> float | NDArray[np.float64]:
    """Roll-gyro reading ω_x = (1 + ε1) ω_true + ε0 (paper RSF, the model before Eq. (2)).

    Parameters
    ----------
    omega_true : array_like
        True roll rate, rad/s.
    eps1 : array_like
        Scale-factor error (dimensionless).
    eps0 : array_like, optional
        Additive error, rad/s (default 0).

    Returns
    -------
    float or numpy.ndarray
        The reading, rad/s.

    Examples
    --------
    >>> f"{gyro_output(10.0, 1e-3, 2e-3):.4f}"
    '10.0120'
    """
    return _arr((1.0 + np.asarray(eps1)) * np.asarray(omega_true) + np.asarray(eps0))


def roll_difference(gamma_sins: ArrayLike, gamma_gs: ArrayLike) -> float | NDArray[np.float64]:
    """Δγ_i = γ_SINS,i − γ_GS,i, the GS taken as the reference (paper RSF, Eq. (1)).

    Parameters
    ----------
    gamma_sins, gamma_gs : array_like
        Roll angles of the SINS and of the GS, rad.

    Returns
    -------
    float or numpy.ndarray
        The difference, rad.

    Examples
    --------
    >>> f"{roll_difference(1.25, 1.0):.2f}"
    '0.25'
    """
    return _arr(np.asarray(gamma_sins, dtype=float) - np.asarray(gamma_gs, dtype=float))


def sf_error_estimate(dgamma: ArrayLike, omega_x: ArrayLike,
                      dt: float) -> float | NDArray[np.float64]:
    """ε̂1 = Δγ / (ω_x Δt) over one correction interval (paper RSF, Eq. (2)).

    With the measured rate in the denominator the noise-free estimate is ε1/(1 + ε1), not ε1
    (see :func:`correction_coefficient`).  An entry point (the calibration command calls it):
    its inputs are checked.

    Parameters
    ----------
    dgamma : array_like
        Roll-angle difference accumulated over the interval, rad.
    omega_x : array_like
        Measured (SINS) roll rate, rad/s, nowhere zero.
    dt : float
        Interval length, s (> 0).

    Returns
    -------
    float or numpy.ndarray
        The estimate ε̂1 (dimensionless).

    Examples
    --------
    >>> f"{sf_error_estimate(0.01, 10.0, 5.0):.3g}"
    '0.0002'
    """
    dg, w = check_value("dgamma", dgamma), check_nonzero("omega_x", omega_x)
    v.check_broadcast(dgamma=dg, omega_x=w)
    return dg / (w * v.check_positive("dt", dt))


def correction_coefficient(eps1_hat: ArrayLike,
                           form: str = "linear") -> float | NDArray[np.float64]:
    """Correction coefficient K from the estimate ε̂1 (paper RSF, after Eq. (2)).

    The print is garbled; the two readings are ``form="linear"``: K = 1 − ε̂1, and
    ``form="reciprocal"``: K = 1/(1 + ε̂1).  With ε̂1 from Eq. (2) (measured rate in the
    denominator) the linear form is the exact inverse of the scale factor; the reciprocal
    form is exact when ε̂1 is referred to the true (GS) rate.  They differ by ε̂1² (3.6·10⁻⁷
    at 600 ppm).  An entry point (the calibration command calls it): its inputs are checked.

    Parameters
    ----------
    eps1_hat : array_like
        Estimated scale-factor error, in (−1, 1).
    form : {"linear", "reciprocal"}, optional
        Reading of the garbled formula (default ``"linear"``).

    Returns
    -------
    float or numpy.ndarray
        K (dimensionless).

    Examples
    --------
    >>> f"{correction_coefficient(2e-4):.4f}", f"{correction_coefficient(2e-4, 'reciprocal'):.8f}"
    ('0.9998', '0.99980004')
    """
    form = v.check_choice("form", form, K_FORMS)
    e = check_sf("eps1_hat", eps1_hat)
    return 1.0 - e if form == "linear" else 1.0 / (1.0 + e)


def corrected_rate(omega_x: ArrayLike, k: ArrayLike) -> float | NDArray[np.float64]:
    """ω̂_x = K ω_x, every reading of the next interval (paper RSF, Eq. (3)).

    Parameters
    ----------
    omega_x : array_like
        Measured roll rate, rad/s.
    k : array_like
        Correction coefficient.

    Returns
    -------
    float or numpy.ndarray
        Corrected rate, rad/s.

    Examples
    --------
    >>> f"{corrected_rate(10.0, 0.9998):.4f}"
    '9.9980'
    """
    return _arr(np.asarray(k, dtype=float) * np.asarray(omega_x, dtype=float))


def k_true(eps1: ArrayLike) -> float | NDArray[np.float64]:
    """The coefficient that removes a scale-factor error ε1 exactly: K_true = 1/(1 + ε1)
    (paper RSF, before Eq. (7)).

    Parameters
    ----------
    eps1 : array_like
        Scale-factor error.

    Returns
    -------
    float or numpy.ndarray

    Examples
    --------
    >>> f"{k_true(0.25):.2f}"
    '0.80'
    """
    return _arr(1.0 / (1.0 + np.asarray(eps1, dtype=float)))


def relative_k_error(k: ArrayLike, eps1: ArrayLike) -> float | NDArray[np.float64]:
    """δK = (K − K_true)/K_true, the paper's measure of the correction (before Eq. (7)).

    With K_true = 1/(1 + ε1) this is K (1 + ε1) − 1, which is exactly the scale-factor error
    left in the corrected reading K ω_x (:func:`residual_sf_error`).

    Parameters
    ----------
    k : array_like
        Correction coefficient.
    eps1 : array_like
        True scale-factor error.

    Returns
    -------
    float or numpy.ndarray
        δK (dimensionless).

    Examples
    --------
    >>> f"{relative_k_error(1.0, 6e-4):.1e}"
    '6.0e-04'
    """
    kt = k_true(eps1)
    return _arr((np.asarray(k, dtype=float) - kt) / kt)


def residual_sf_error(eps1: ArrayLike, k: ArrayLike) -> float | NDArray[np.float64]:
    """Scale-factor error left after correction: K (1 + ε1) − 1 (paper RSF, Eq. (3)).

    Parameters
    ----------
    eps1 : array_like
        True scale-factor error.
    k : array_like
        Correction coefficient.

    Returns
    -------
    float or numpy.ndarray

    Examples
    --------
    >>> f"{residual_sf_error(6e-4, 1 - 6e-4):.1e}"
    '-3.6e-07'
    """
    return _arr(np.asarray(k, dtype=float) * (1.0 + np.asarray(eps1, dtype=float)) - 1.0)


def fraction_compensated(eps1: ArrayLike, residual: ArrayLike) -> float | NDArray[np.float64]:
    """Fraction of the scale-factor error removed: 1 − |residual| / |ε1| (paper RSF, the
    conclusion's "compensates 90 %", read correctly).

    ``residual`` is the scale-factor error left after correction, which equals δK
    (:func:`relative_k_error`).  Negative when the "correction" makes things worse.

    Parameters
    ----------
    eps1 : array_like
        Scale-factor error before correction (nonzero).
    residual : array_like
        Scale-factor error after correction.

    Returns
    -------
    float or numpy.ndarray

    Examples
    --------
    >>> f"{fraction_compensated(600e-6, 170e-6):.3f}"
    '0.717'
    """
    return _arr(1.0 - np.abs(np.asarray(residual, dtype=float))
                / np.abs(np.asarray(eps1, dtype=float)))


# Error budget, Eqs. (4)-(7) and (9) ----------------------------------------------------------
def sins_roll_error(eps1: ArrayLike, omega_true: ArrayLike, t: ArrayLike,
                    eps0: ArrayLike = 0.0) -> float | NDArray[np.float64]:
    """Roll-angle error of the autonomous SINS, Δγ_SINS = ε1 ω t + ε0 t (paper RSF, Eq. (4)).

    The paper neglects ε0 (``eps0=0``, the default); Table 2 uses ω = 3600 °/s.

    Parameters
    ----------
    eps1 : array_like
        Scale-factor error.
    omega_true : array_like
        Roll rate, rad/s.
    t : array_like
        Time, s.
    eps0 : array_like, optional
        Additive error, rad/s.

    Returns
    -------
    float or numpy.ndarray
        Roll error, rad.

    Examples
    --------
    >>> import math
    >>> f"{math.degrees(sins_roll_error(600e-6, math.radians(3600.0), 10.0)):.4g}"
    '21.6'
    """
    e1, w = np.asarray(eps1, dtype=float), np.asarray(omega_true, dtype=float)
    return _arr((e1 * w + np.asarray(eps0, dtype=float)) * np.asarray(t, dtype=float))


def gs_bias_total(sigma_rep: float, sigma_stab: float) -> float:
    """ε0,GS = √(σ_rep² + σ_stab²): uncorrelated bias repeatability and in-run stability
    (paper RSF, before Table 3).

    Parameters
    ----------
    sigma_rep, sigma_stab : float
        Bias repeatability and in-run stability, any one rate unit.

    Returns
    -------
    float
        ε0,GS in that unit.

    Examples
    --------
    >>> f"{gs_bias_total(10.0, 7.0):.4g}"
    '12.21'
    """
    return math.hypot(sigma_rep, sigma_stab)


def gs_roll_error_ideal(eps0_gs: ArrayLike, t: ArrayLike,
                        dgamma_enc: ArrayLike) -> float | NDArray[np.float64]:
    """Roll error of an ideal GS: Δγ_GS = ε0,GS t + Δγ_enc (paper RSF, Eq. (9)).

    Parameters
    ----------
    eps0_gs : array_like
        GS gyro bias, rad/s.
    t : array_like
        Time, s.
    dgamma_enc : array_like
        Encoder position error, rad.

    Returns
    -------
    float or numpy.ndarray
        Roll error, rad.

    Examples
    --------
    >>> import math
    >>> f"{math.degrees(gs_roll_error_ideal(math.radians(3.3e-3), 10.0, math.radians(0.33))):.3f}"
    '0.363'
    """
    return _arr(np.asarray(eps0_gs, dtype=float) * np.asarray(t, dtype=float)
                + np.asarray(dgamma_enc, dtype=float))


def gs_roll_error_nonideal(eps0_gs: ArrayLike, eps1_gs: ArrayLike, omega_unc: ArrayLike,
                           t: ArrayLike, dgamma_enc: ArrayLike) -> float | NDArray[np.float64]:
    """Roll error of a non-ideal GS (paper RSF, Eq. (6)) for a constant uncompensated rate:

    Δγ_GS = ε0,GS t + ε1,GS ∫ ω_unc dt + Δγ_enc = (ε0,GS + |ε1,GS ω_unc|) t + Δγ_enc,

    the terms added in magnitude as the paper does.

    Parameters
    ----------
    eps0_gs : array_like
        GS gyro bias, rad/s.
    eps1_gs : array_like
        GS gyro scale-factor error.
    omega_unc : array_like
        Uncompensated platform rate, rad/s.
    t : array_like
        Time, s.
    dgamma_enc : array_like
        Encoder position error, rad.

    Returns
    -------
    float or numpy.ndarray
        Roll error, rad.

    Examples
    --------
    >>> import math
    >>> r = math.radians
    >>> f"{math.degrees(gs_roll_error_nonideal(0.0, 280e-6, r(300.0), 10.0, 0.0)):.3f}"
    '0.840'
    """
    rate = np.asarray(eps0_gs, dtype=float) + np.abs(np.asarray(eps1_gs, dtype=float)
                                                     * np.asarray(omega_unc, dtype=float))
    return _arr(rate * np.asarray(t, dtype=float) + np.asarray(dgamma_enc, dtype=float))


def difference_error(eps0_gs: float, dt: float, dgamma_enc: float, eps1_gs: float = 0.0,
                     omega_unc: float = 0.0) -> float:
    """Error of the measured difference Δγ_i over one interval Δt (paper RSF, Eq. (5)):

    δΔγ = (ε1 − ε̂1) ω_x Δt = (ε0,GS + ε1,GS |ω_unc|) Δt + Δγ_enc,

    the GS errors over the interval added in magnitude (the paper's worst-case sum of
    uncorrelated terms).  ``eps1_gs=0`` or ``omega_unc=0`` is the ideal GS.

    Parameters
    ----------
    eps0_gs : float
        GS gyro bias, rad/s.
    dt : float
        Interval, s.
    dgamma_enc : float
        Encoder position error, rad.
    eps1_gs, omega_unc : float, optional
        GS gyro SF error and uncompensated rate (rad/s).

    Returns
    -------
    float
        The error, rad.

    Examples
    --------
    >>> import math
    >>> f"{math.degrees(difference_error(math.radians(3.3e-3), 5.0, math.radians(0.33))):.4f}"
    '0.3465'
    """
    return float(gs_roll_error_nonideal(eps0_gs, eps1_gs, omega_unc, dt, dgamma_enc))


def delta_k(eps0_gs: float, dgamma_enc: float, omega_x: float, dt: float, eps1_gs: float = 0.0,
            omega_unc: float = 0.0) -> float:
    """Relative error of the correction coefficient (paper RSF, Eq. (7)):

    δK ≈ [(ε0,GS + ε1,GS ω_unc) Δt + Δγ_enc] / (ω_x Δt).

    With ``eps1_gs=0`` or ``omega_unc=0`` it is the ideal-GS form
    (ε0,GS Δt + Δγ_enc)/(ω_x Δt) (:func:`delta_k_ideal`).  It is a magnitude: the terms are
    added as worst-case (or 1σ) values.  The entry point of the error budget: its inputs are
    checked.

    Parameters
    ----------
    eps0_gs : float
        GS gyro bias, rad/s (>= 0).
    dgamma_enc : float
        Encoder position error, rad (>= 0).
    omega_x : float
        Measured roll rate, rad/s (nonzero).
    dt : float
        Correction period, s (> 0).
    eps1_gs : float, optional
        GS gyro scale-factor error, in (−1, 1).
    omega_unc : float, optional
        Uncompensated rate, rad/s.

    Returns
    -------
    float
        δK (dimensionless).

    Examples
    --------
    >>> import math
    >>> r = math.radians
    >>> f"{delta_k(r(3.3e-3), r(0.33), r(900.0), 5.0, 280e-6, r(300.0)):.4g}"
    '0.0001703'
    """
    w = abs(float(check_nonzero("omega_x", v.check_real("omega_x", omega_x))))
    dt = v.check_positive("dt", dt)
    e0 = v.check_nonnegative("eps0_gs", eps0_gs)
    enc = v.check_nonnegative("dgamma_enc", dgamma_enc)
    e1 = check_sf("eps1_gs", eps1_gs)
    wu = v.check_real("omega_unc", omega_unc)
    return difference_error(e0, dt, enc, e1, wu) / (w * dt)


def delta_k_ideal(eps0_gs: float, dgamma_enc: float, omega_x: float, dt: float) -> float:
    """δK for an ideal GS, (ε0,GS Δt + Δγ_enc)/(ω_x Δt): Eq. (7) of paper RSF with ω_unc = 0.

    Parameters
    ----------
    eps0_gs, dgamma_enc, omega_x, dt : float
        As :func:`delta_k`.

    Returns
    -------
    float

    Examples
    --------
    >>> import math
    >>> f"{delta_k_ideal(0.0, math.radians(0.33), math.radians(900.0), 5.0):.3g}"
    '7.33e-05'
    """
    return delta_k(eps0_gs, dgamma_enc, omega_x, dt)


# Lateral deviation, Eq. (8) and Figure 3 --------------------------------------------------------
def lateral_acceleration_error(eps1: float, omega: float, t: ArrayLike, g: float = G0, *,
                               small_angle: bool = False) -> float | NDArray[np.float64]:
    """Gravity mis-resolved onto the lateral axis, Δa_z = g sin(ε1 ω t) (paper RSF, Fig. 3);
    ``small_angle=True`` gives the paper's first approximation g ε1 ω t.

    Parameters
    ----------
    eps1 : float
        Scale-factor error.
    omega : float
        Roll rate, rad/s.
    t : array_like
        Time, s.
    g : float, optional
        Gravity, m/s².
    small_angle : bool, optional
        The paper's linearization.

    Returns
    -------
    float or numpy.ndarray
        Lateral acceleration error, m/s².

    Examples
    --------
    >>> f"{lateral_acceleration_error(0.5, 1.0, 1.0, g=1.0, small_angle=True):.2f}"
    '0.50'
    """
    x = eps1 * omega * np.asarray(t, dtype=float)
    return _arr(g * x if small_angle else g * np.sin(x))


def lateral_deviation_cubic(eps1: float, omega: float, t: ArrayLike,
                            g: float = G0) -> float | NDArray[np.float64]:
    """Lateral position error in the small-angle approximation, g ε1 ω t³ / 6
    (paper RSF, Eq. (8)).

    Parameters
    ----------
    eps1 : float
        Scale-factor error.
    omega : float
        Roll rate, rad/s.
    t : array_like
        Time, s.
    g : float, optional
        Gravity, m/s².

    Returns
    -------
    float or numpy.ndarray
        Lateral deviation, m.

    Examples
    --------
    >>> import math
    >>> f"{lateral_deviation_cubic(600e-6, math.radians(3600.0), 10.0):.4g}"
    '61.62'
    """
    return _arr(g * eps1 * omega * np.asarray(t, dtype=float) ** 3 / 6.0)


def _x_minus_sin(x: np.ndarray) -> np.ndarray:
    """x − sin x without cancellation: its Taylor series where |x| is small."""
    x = np.asarray(x, dtype=float)
    x2 = x * x
    series = x * x2 / 6.0 * (1.0 - x2 / 20.0 * (1.0 - x2 / 42.0 * (1.0 - x2 / 72.0)))
    return np.where(np.abs(x) < 1e-2, series, x - np.sin(x))


def lateral_deviation_exact(eps1: float, omega: float, t: ArrayLike,
                            g: float = G0) -> float | np.ndarray:
    """The double integral of Eq. (8) without the small-angle approximation:

    Δr_z(t) = ∫₀ᵗ∫₀ˢ g sin(ε1 ω u) du ds = g (a t − sin a t) / a²,   a = ε1 ω.

    Equal to the cubic g a t³/6 for a t ≪ 1; much smaller once the roll error a t reaches
    tens of degrees, because sin saturates and then changes sign.
    """
    a = check_sf("eps1", eps1) * v.check_real("omega", omega)
    t = check_value("t", t, nonnegative=True)
    g = v.check_positive("g", g)
    if a == 0.0:
        return 0.0 * np.asarray(t) if isinstance(t, np.ndarray) else 0.0
    out = g * _x_minus_sin(a * np.asarray(t)) / a**2
    return float(out) if np.ndim(out) == 0 else out


def _one_minus_cos_deficit(x: np.ndarray) -> np.ndarray:
    """x²/2 − (1 − cos x) without cancellation: its Taylor series where |x| is small."""
    x = np.asarray(x, dtype=float)
    x2 = x * x
    series = x2 * x2 / 24.0 * (1.0 - x2 / 30.0 * (1.0 - x2 / 56.0 * (1.0 - x2 / 90.0)))
    return np.where(np.abs(x) < 1e-2, series, 0.5 * x2 - 2.0 * np.sin(0.5 * x) ** 2)


def vertical_deviation_exact(eps1: float, omega: float, t: ArrayLike,
                             g: float = G0) -> float | np.ndarray:
    """Vertical position error from the same roll error, which Eq. (8) of paper RSF omits.

    A roll error Δγ = ε1 ω t resolves the 1 g of lift (normal to the roll axis, as Eq. (8)
    presumes) as g cos Δγ on the vertical axis instead of g: the vertical acceleration error
    is g (1 − cos Δγ), and its double integral

    Δr_y(t) = ∫₀ᵗ∫₀ˢ g (1 − cos a u) du ds = g [(a t)²/2 − (1 − cos a t)] / a²,  a = ε1 ω.

    It grows as g a² t⁴/24 at first (second order in the roll error, negligible next to the
    lateral cubic); its acceleration exceeds the lateral one once the roll error passes 90°,
    and the deviation itself overtakes the lateral one at a roll error of about 190° (at
    about 88 s in Table 2's case).

    Parameters
    ----------
    eps1 : float
        Scale-factor error of the roll gyro, in (−1, 1).
    omega : float
        Roll rate, rad/s.
    t : array_like
        Times, s (>= 0).
    g : float, optional
        Gravity, m/s² (default standard gravity).

    Returns
    -------
    float or numpy.ndarray
        Vertical deviation, m (>= 0), shaped as ``t``.

    Examples
    --------
    >>> from gyrolib.units import to_si
    >>> w = to_si(3600.0, "deg/s")
    >>> lat = lateral_deviation_exact(600e-6, w, 120.0)
    >>> ver = vertical_deviation_exact(600e-6, w, 120.0)
    >>> f"{lat:.3g} m lateral, {ver:.3g} m vertical"
    '3.8e+04 m lateral, 6.24e+04 m vertical'
    """
    a = check_sf("eps1", eps1) * v.check_real("omega", omega)
    t = check_value("t", t, nonnegative=True)
    g = v.check_positive("g", g)
    if a == 0.0:
        return 0.0 * np.asarray(t) if isinstance(t, np.ndarray) else 0.0
    out = g * _one_minus_cos_deficit(a * np.asarray(t)) / a**2
    return float(out) if np.ndim(out) == 0 else out
