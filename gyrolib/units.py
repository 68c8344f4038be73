"""Units of the two papers, converted to and from SI in one place.

Everything inside :mod:`gyrolib` is SI (rad, rad/s, m/s², s).  The papers speak in
arcseconds, arcseconds per second, degrees per hour, degrees per second, ppm and g; this
module is the only place where those units are turned into SI and back.

Paper GC converts arcseconds with the rounded factor 1″ = 0.485·10⁻⁵ rad (its parameter
table); the standard arc second is π/648000 rad = 4.8481·10⁻⁶ rad.  Both are offered: the
unit ``"arcsec"`` is the standard one, ``"arcsec_paper"`` the paper's rounded factor (0.04 %
larger: a drift of 1 paper ″/s is 1.00038 standard ″/s = 1.00038 °/h).  Gyro drift in the
field's unit is ``"deg/h"`` (1 °/h = 1″/s standard exactly, = 4.8481·10⁻⁶ rad/s);
:data:`DRIFT_UNITS` lists the three side by side and :func:`drift_conversion` states them.
"""

from __future__ import annotations

import math
from typing import Final

import numpy as np
from numpy.typing import ArrayLike

__all__ = [
    "ARCMIN",
    "ARCSEC",
    "ARCSEC_PAPER",
    "DEG",
    "DEG_PER_HOUR",
    "DEG_PER_S",
    "DRIFT_UNITS",
    "G0",
    "PPM",
    "UNITS",
    "drift_conversion",
    "drift_in_units",
    "from_si",
    "to_si",
]

#: One degree in radians.
DEG: Final[float] = math.pi / 180.0
#: One arcminute in radians.
ARCMIN: Final[float] = DEG / 60.0
#: One arcsecond in radians, exact (π/648000).
ARCSEC: Final[float] = DEG / 3600.0
#: One arcsecond in radians as paper GC rounds it: 0.485·10⁻⁵ rad.
ARCSEC_PAPER: Final[float] = 0.485e-5
#: One degree per hour in rad/s.
DEG_PER_HOUR: Final[float] = DEG / 3600.0
#: One degree per second in rad/s.
DEG_PER_S: Final[float] = DEG
#: One part per million (dimensionless).
PPM: Final[float] = 1e-6
#: Standard gravity, m/s² (CGPM 1901, exact by definition).
G0: Final[float] = 9.80665

#: SI value of one of each named unit.  Keys are the unit names accepted by
#: :func:`to_si` and :func:`from_si`.
UNITS: Final[dict[str, float]] = {
    "rad": 1.0,
    "deg": DEG,
    "arcmin": ARCMIN,
    "arcsec": ARCSEC,
    "arcsec_paper": ARCSEC_PAPER,
    "rad/s": 1.0,
    "deg/s": DEG_PER_S,
    "deg/h": DEG_PER_HOUR,
    "arcsec/s": ARCSEC,
    "arcsec_paper/s": ARCSEC_PAPER,
    "ppm": PPM,
    "g": G0,
    "m/s^2": 1.0,
    "1": 1.0,
    "permille": 1e-3,
    "m": 1.0,
    "km": 1000.0,
    "deg/sqrt_h": DEG / 60.0,
    "s": 1.0,
    "ms": 1e-3,
    "us": 1e-6,
    "µs": 1e-6,
    "mrad": 1e-3,
    "min": 60.0,
    "Hz": 2.0 * math.pi,
    "mHz": 2.0 * math.pi * 1e-3,
    "mg": G0 * 1e-3,
    "%": 1e-2,
}


def _factor(unit: str) -> float:
    if not isinstance(unit, str):
        raise TypeError(f"unit must be a str, one of {sorted(UNITS)}; got {type(unit).__name__}")
    try:
        return UNITS[unit]
    except KeyError:
        raise ValueError(f"unit must be one of {sorted(UNITS)}; got {unit!r}") from None


def _as_number(value: ArrayLike) -> float | np.ndarray:
    if isinstance(value, bool):
        raise TypeError("value must be a real number or array of real numbers, not bool")
    try:
        arr = np.asarray(value)
    except ValueError:  # ragged nested sequences
        raise TypeError("value must be real (number or array); got a ragged sequence") from None
    if arr.dtype.kind not in "iuf":
        raise TypeError(f"value must be real (number or array); got dtype {arr.dtype}")
    # ±inf converts exactly (e.g. an unlimited rate); NaN is no quantity and would pass silently
    if arr.dtype.kind == "f" and np.isnan(arr).any():
        raise ValueError("value must be a number or ±inf, not NaN")
    return float(arr) if arr.ndim == 0 else arr.astype(float)


def to_si(value: ArrayLike, unit: str) -> float | np.ndarray:
    """Convert ``value`` expressed in ``unit`` to SI.

    >>> f"{to_si(1.0, 'deg/h'):.4g}"  # 1 °/h in rad/s
    '4.848e-06'
    """
    return _as_number(value) * _factor(unit)


def from_si(value: ArrayLike, unit: str) -> float | np.ndarray:
    """Convert an SI ``value`` to ``unit``.

    >>> from_si(ARCSEC_PAPER, "arcsec_paper")
    1.0
    """
    return _as_number(value) / _factor(unit)


#: The drift units a calibration reports, with their printed symbols: the field's °/h, the
#: standard arc second per second, the paper's arc second per second, and SI.
DRIFT_UNITS: Final[tuple[tuple[str, str], ...]] = (
    ("deg/h", "°/h"), ("arcsec/s", "″/s (standard)"), ("arcsec_paper/s", "″/s (paper's)"),
    ("rad/s", "rad/s"))


def drift_in_units(value: float) -> dict[str, float]:
    """An SI drift rate (rad/s) in each of :data:`DRIFT_UNITS`.

    >>> {k: round(x, 6) for k, x in drift_in_units(to_si(1.0, "deg/h")).items()}
    {'deg/h': 1.0, 'arcsec/s': 1.0, 'arcsec_paper/s': 0.999616, 'rad/s': 5e-06}
    """
    x = float(_as_number(value))
    return {u: float(from_si(x, u)) for u, _ in DRIFT_UNITS}


def drift_conversion() -> str:
    """One sentence stating the conversions between the drift units.

    >>> drift_conversion()[-45:]
    'aper ″/s = 1.00038 ″/s standard = 1.00038 °/h'
    """
    return (f"1 °/h = 1 ″/s (standard arc second, π/648000 rad) = {DEG_PER_HOUR:.5g} rad/s; "
            f"paper GC's arc second is {ARCSEC_PAPER:.3g} rad, so 1 paper ″/s = "
            f"{ARCSEC_PAPER / ARCSEC:.5f} ″/s standard = {ARCSEC_PAPER / DEG_PER_HOUR:.5f} °/h")
