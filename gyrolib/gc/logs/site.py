"""The test site's latitude in a drift calibration (paper GC, Eqs. (1)–(3)): what an error in
it does to ω̂_gc, and what the method still estimates near the equator.

The gyrocompass senses the horizontal Earth rate ``Ω_h = Ω_E cos φ`` (Eq. (1)) added to the
drift ω_gc (Eq. (3)), so an error in the stated latitude φ reads as drift, one for one:
``Δω̂_gc = −ΔΩ_h = Ω_E (cos φ − cos(φ + Δφ))``.  The vertical rate ``Ω_v = Ω_E sin φ``
(Eq. (2)) only couples the platform's tilts δ, γ into the float's torque: negative south of
the equator, and 0 on it.

* :func:`latitude_drift_shift` — the drift a latitude error ``Δφ`` moves ω̂_gc by;
* :func:`latitude_drift_sigma` — the standard deviation of ω̂_gc from a 1σ latitude
  uncertainty ``σ_φ``: ``Ω_E √(sin²φ σ_φ² + ½ cos²φ σ_φ⁴)`` (the variance of
  ``Ω_E cos(φ + e)``, ``e ~ N(0, σ_φ²)``, to fourth order in ``σ_φ``: on the equator, where
  the first-order term vanishes, the second-order one remains);
* :func:`equator_note` — the sentence a verdict carries for a site near the equator.

The Earth rate ``Ω_E`` and the latitude are the parameters' own: ``hypot(Ω_h, Ω_v)`` and
``atan2(Ω_v, Ω_h)`` (:attr:`GyrocompassParams.latitude`).
"""

from __future__ import annotations

import math
from typing import Final

from gyrolib import _validation as v
from gyrolib.gc.model.params import GyrocompassParams, check_params, latitude_text

__all__ = ["NEAR_EQUATOR", "equator_note", "latitude_drift_shift", "latitude_drift_sigma"]

#: Latitudes (rad) within which a site counts as near the equator: there
#: ``|Ω_v| ≤ Ω_E sin 2° ≈ 0.035 Ω_E``, so a tilt of the paper's prior 120″ torques the float
#: as a drift of at most 0.035 · 120″ · Ω_E ≈ 7·10⁻¹⁰ rad/s.
NEAR_EQUATOR: Final[float] = math.radians(2.0)


def latitude_drift_shift(params: GyrocompassParams, dlat: float) -> float:
    """The largest change (rad/s) of ω̂_gc that an error of ``±dlat`` (rad) in the stated
    latitude makes: ``Ω_E max(|cos(φ + dlat) − cos φ|, |cos(φ − dlat) − cos φ|)``
    (Ω_h reads as drift, Eqs. (1), (3)).

    Examples
    --------
    >>> import math
    >>> from gyrolib import gc
    >>> p = gc.GyrocompassParams.at_latitude(math.radians(54.0))
    >>> f"{latitude_drift_shift(p, math.radians(0.5)):.3e}"        # ≈ Ω_E sin φ · 0.5°
    '5.164e-07'
    >>> equator = gc.GyrocompassParams.at_latitude(0.0)
    >>> f"{latitude_drift_shift(equator, math.radians(0.5)):.3e}"   # second order only
    '2.777e-09'
    """
    p = check_params(params)
    d = v.check_nonnegative("dlat", dlat)
    earth, lat = math.hypot(p.Omega_h, p.Omega_v), p.latitude
    return earth * max(abs(math.cos(lat + d) - math.cos(lat)),
                       abs(math.cos(lat - d) - math.cos(lat)))


def latitude_drift_sigma(params: GyrocompassParams, latitude_sigma: float) -> float:
    """The standard deviation (rad/s) that a 1σ uncertainty ``latitude_sigma`` (rad) of the
    stated latitude adds to ω̂_gc: ``Ω_E √(sin²φ σ_φ² + ½ cos²φ σ_φ⁴)``, the standard
    deviation of ``Ω_E cos(φ + e)`` for ``e ~ N(0, σ_φ²)`` to fourth order.

    Examples
    --------
    >>> import math
    >>> from gyrolib import gc
    >>> p = gc.GyrocompassParams.at_latitude(math.radians(54.0))
    >>> f"{latitude_drift_sigma(p, math.radians(0.5)):.3e}"
    '5.148e-07'
    >>> latitude_drift_sigma(p, 0.0)
    0.0
    """
    p = check_params(params)
    s = v.check_nonnegative("latitude_sigma", latitude_sigma)
    earth, lat = math.hypot(p.Omega_h, p.Omega_v), p.latitude
    return earth * math.sqrt((math.sin(lat) * s) ** 2 + 0.5 * (math.cos(lat) * s * s) ** 2)


def equator_note(params: GyrocompassParams) -> str:
    """What the method still estimates at a site within :data:`NEAR_EQUATOR` of the
    equator (``""`` elsewhere): ``Ω_v ≈ 0`` takes the tilts δ, γ (and an inclinometer's
    bias, or a tilt of the input axis out of the horizontal) out of the float's torque, so
    the inclinometers inform only the tilts themselves; ω_gc is still estimated against
    ``Ω_h``, largest there, and a latitude error moves it to second order only.

    Examples
    --------
    >>> from gyrolib import gc
    >>> equator_note(gc.GyrocompassParams.at_latitude(0.0))[:44]
    'the site (0 deg) is within 2 deg of the equa'
    >>> equator_note(gc.GyrocompassParams())
    ''
    """
    p = check_params(params)
    if abs(p.latitude) > NEAR_EQUATOR:
        return ""
    return (f"the site ({latitude_text(math.degrees(p.latitude), 4)}) is within "
            f"{math.degrees(NEAR_EQUATOR):g} deg of the equator: the vertical Earth rate "
            f"Omega_v = {p.Omega_v:.3g} rad/s is about 0, so the platform's tilts delta, "
            "gamma (and an inclinometer's bias, or a tilt of the gyro's input axis out of "
            "the horizontal) no longer torque the float, and the inclinometers inform only "
            "the tilts themselves; the drift omega_gc is still estimated, against the "
            f"horizontal rate Omega_h = {p.Omega_h:.4g} rad/s (largest on the equator), and "
            "an error in the latitude moves it only to second order")
