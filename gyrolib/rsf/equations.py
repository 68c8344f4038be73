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
from numpy.typing import ArrayLike

from gyrolib import _validation as v
from gyrolib.rsf._inputs import _nonzero, _sf, _value
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
def gyro_output(omega_true: ArrayLike, eps1: float, eps0: float = 0.0) -> float | np.ndarray:
    """Roll-gyro reading ω_x = (1 + ε1) ω_true + ε0 (paper RSF, the model before Eq. (2))."""
    w = _value("omega_true", omega_true)
    e1 = _sf("eps1", eps1)
    e0 = _value("eps0", eps0)
    v.check_broadcast(omega_true=w, eps1=e1, eps0=e0)
    return (1.0 + e1) * w + e0


def roll_difference(gamma_sins: ArrayLike, gamma_gs: ArrayLike) -> float | np.ndarray:
    """Δγ_i = γ_SINS,i − γ_GS,i, the GS taken as the reference (paper RSF, Eq. (1))."""
    a, b = _value("gamma_sins", gamma_sins), _value("gamma_gs", gamma_gs)
    v.check_broadcast(gamma_sins=a, gamma_gs=b)
    return a - b


def sf_error_estimate(dgamma: ArrayLike, omega_x: ArrayLike, dt: float) -> float | np.ndarray:
    """ε̂1 = Δγ / (ω_x Δt) over one correction interval (paper RSF, Eq. (2)).

    ``dgamma`` is the roll-angle difference accumulated over the interval of length ``dt``
    and ``omega_x`` the measured (SINS) roll rate.  With the measured rate in the denominator
    the noise-free estimate is ε1/(1 + ε1), not ε1 (see :func:`correction_coefficient`).
    """
    dg, w = _value("dgamma", dgamma), _nonzero("omega_x", omega_x)
    v.check_broadcast(dgamma=dg, omega_x=w)
    return dg / (w * v.check_positive("dt", dt))


def correction_coefficient(eps1_hat: ArrayLike, form: str = "linear") -> float | np.ndarray:
    """Correction coefficient K from the estimate ε̂1 (paper RSF, after Eq. (2)).

    The print is garbled; the two readings are ``form="linear"``: K = 1 − ε̂1, and
    ``form="reciprocal"``: K = 1/(1 + ε̂1).  With ε̂1 from Eq. (2) (measured rate in the
    denominator) the linear form is the exact inverse of the scale factor; the reciprocal
    form is exact when ε̂1 is referred to the true (GS) rate.  They differ by ε̂1² (3.6·10⁻⁷
    at 600 ppm).
    """
    form = v.check_choice("form", form, K_FORMS)
    e = _sf("eps1_hat", eps1_hat)
    return 1.0 - e if form == "linear" else 1.0 / (1.0 + e)


def corrected_rate(omega_x: ArrayLike, k: ArrayLike) -> float | np.ndarray:
    """ω̂_x = K ω_x, every reading of the next interval (paper RSF, Eq. (3))."""
    kk, w = _value("k", k), _value("omega_x", omega_x)
    v.check_broadcast(omega_x=w, k=kk)
    return kk * w


def k_true(eps1: ArrayLike) -> float | np.ndarray:
    """The coefficient that removes a scale-factor error ε1 exactly: K_true = 1/(1 + ε1)."""
    return 1.0 / (1.0 + _sf("eps1", eps1))


def relative_k_error(k: ArrayLike, eps1: ArrayLike) -> float | np.ndarray:
    """δK = (K − K_true)/K_true, the paper's measure of the correction (before Eq. (7)).

    With K_true = 1/(1 + ε1) this is K (1 + ε1) − 1, which is exactly the scale-factor error
    left in the corrected reading K ω_x (:func:`residual_sf_error`).
    """
    kt = k_true(eps1)
    kk = _value("k", k)
    v.check_broadcast(k=kk, eps1=kt)
    return (kk - kt) / kt


def residual_sf_error(eps1: ArrayLike, k: ArrayLike) -> float | np.ndarray:
    """Scale-factor error left after correction: K (1 + ε1) − 1 (paper RSF, Eq. (3))."""
    e, kk = _sf("eps1", eps1), _value("k", k)
    v.check_broadcast(eps1=e, k=kk)
    return kk * (1.0 + e) - 1.0


def fraction_compensated(eps1: ArrayLike, residual: ArrayLike) -> float | np.ndarray:
    """Fraction of the scale-factor error removed: 1 − |residual| / |ε1|.

    ``residual`` is the scale-factor error left after correction, which equals δK
    (:func:`relative_k_error`).  Negative when the "correction" makes things worse.
    """
    e, r = _nonzero("eps1", eps1), _value("residual", residual)
    v.check_broadcast(eps1=e, residual=r)
    return 1.0 - np.abs(r) / np.abs(e)


# Error budget, Eqs. (4)-(7) and (9) ----------------------------------------------------------
def sins_roll_error(eps1: float, omega_true: ArrayLike, t: ArrayLike,
                    eps0: float = 0.0) -> float | np.ndarray:
    """Roll-angle error of the autonomous SINS, Δγ_SINS = ε1 ω t + ε0 t (paper RSF, Eq. (4)).

    The paper neglects ε0 (``eps0=0``, the default); Table 2 uses ω = 3600 °/s.
    """
    e1, w = _sf("eps1", eps1), _value("omega_true", omega_true)
    e0, tt = _value("eps0", eps0), _value("t", t, nonnegative=True)
    v.check_broadcast(eps1=e1, omega_true=w, t=tt, eps0=e0)
    return (e1 * w + e0) * tt


def gs_bias_total(sigma_rep: float, sigma_stab: float) -> float:
    """ε0,GS = √(σ_rep² + σ_stab²): uncorrelated bias repeatability and in-run stability."""
    return math.hypot(v.check_nonnegative("sigma_rep", sigma_rep),
                      v.check_nonnegative("sigma_stab", sigma_stab))


def gs_roll_error_ideal(eps0_gs: float, t: ArrayLike, dgamma_enc: float) -> float | np.ndarray:
    """Roll error of an ideal GS: Δγ_GS = ε0,GS t + Δγ_enc (paper RSF, Eq. (9))."""
    return (v.check_nonnegative("eps0_gs", eps0_gs) * _value("t", t, nonnegative=True)
            + v.check_nonnegative("dgamma_enc", dgamma_enc))


def gs_roll_error_nonideal(eps0_gs: float, eps1_gs: float, omega_unc: float, t: ArrayLike,
                           dgamma_enc: float) -> float | np.ndarray:
    """Roll error of a non-ideal GS (paper RSF, Eq. (6)) for a constant uncompensated rate:

    Δγ_GS = ε0,GS t + ε1,GS ∫ ω_unc dt + Δγ_enc = (ε0,GS + ε1,GS ω_unc) t + Δγ_enc.
    """
    e1 = _sf("eps1_gs", eps1_gs)
    w = v.check_real("omega_unc", omega_unc)
    return (v.check_nonnegative("eps0_gs", eps0_gs) + abs(e1 * w)) \
        * _value("t", t, nonnegative=True) + v.check_nonnegative("dgamma_enc", dgamma_enc)


def difference_error(eps0_gs: float, dt: float, dgamma_enc: float, eps1_gs: float = 0.0,
                     omega_unc: float = 0.0) -> float:
    """Error of the measured difference Δγ_i over one interval Δt (paper RSF, Eq. (5)):

    δΔγ = (ε1 − ε̂1) ω_x Δt = (ε0,GS + ε1,GS |ω_unc|) Δt + Δγ_enc,

    the GS errors over the interval added in magnitude (the paper's worst-case sum of
    uncorrelated terms).  ``eps1_gs=0`` or ``omega_unc=0`` is the ideal GS.
    """
    return float(gs_roll_error_nonideal(eps0_gs, eps1_gs, omega_unc,
                                        v.check_positive("dt", dt), dgamma_enc))


def delta_k(eps0_gs: float, dgamma_enc: float, omega_x: float, dt: float, eps1_gs: float = 0.0,
            omega_unc: float = 0.0) -> float:
    """Relative error of the correction coefficient (paper RSF, Eq. (7)):

    δK ≈ [(ε0,GS + ε1,GS ω_unc) Δt + Δγ_enc] / (ω_x Δt).

    With ``eps1_gs=0`` or ``omega_unc=0`` it is the ideal-GS form
    (ε0,GS Δt + Δγ_enc)/(ω_x Δt) (:func:`delta_k_ideal`).  It is a magnitude: the terms are
    added as worst-case (or 1σ) values.
    """
    w = abs(float(_nonzero("omega_x", v.check_real("omega_x", omega_x))))
    dt = v.check_positive("dt", dt)
    return difference_error(eps0_gs, dt, dgamma_enc, eps1_gs, omega_unc) / (w * dt)


def delta_k_ideal(eps0_gs: float, dgamma_enc: float, omega_x: float, dt: float) -> float:
    """δK for an ideal GS, (ε0,GS Δt + Δγ_enc)/(ω_x Δt): Eq. (7) with ω_unc = 0."""
    return delta_k(eps0_gs, dgamma_enc, omega_x, dt)


# Lateral deviation, Eq. (8) and Figure 3 --------------------------------------------------------
def lateral_acceleration_error(eps1: float, omega: float, t: ArrayLike, g: float = G0, *,
                               small_angle: bool = False) -> float | np.ndarray:
    """Gravity mis-resolved onto the lateral axis, Δa_z = g sin(ε1 ω t) (paper RSF, Fig. 3);
    ``small_angle=True`` gives the paper's first approximation g ε1 ω t."""
    a = _sf("eps1", eps1) * v.check_real("omega", omega)
    x = a * _value("t", t, nonnegative=True)
    g = v.check_positive("g", g)
    small_angle = v.check_bool("small_angle", small_angle)
    return g * x if small_angle else g * np.sin(x)


def lateral_deviation_cubic(eps1: float, omega: float, t: ArrayLike,
                            g: float = G0) -> float | np.ndarray:
    """Lateral position error in the small-angle approximation, g ε1 ω t³ / 6
    (paper RSF, Eq. (8))."""
    t = _value("t", t, nonnegative=True)
    return v.check_positive("g", g) * _sf("eps1", eps1) * v.check_real("omega", omega) \
        * t**3 / 6.0


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
    a = _sf("eps1", eps1) * v.check_real("omega", omega)
    t = _value("t", t, nonnegative=True)
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
    a = _sf("eps1", eps1) * v.check_real("omega", omega)
    t = _value("t", t, nonnegative=True)
    g = v.check_positive("g", g)
    if a == 0.0:
        return 0.0 * np.asarray(t) if isinstance(t, np.ndarray) else 0.0
    out = g * _one_minus_cos_deficit(a * np.asarray(t)) / a**2
    return float(out) if np.ndim(out) == 0 else out
