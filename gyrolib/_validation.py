"""Input checks shared by every public function of :mod:`gyrolib`.

Each check raises :class:`TypeError` or :class:`ValueError` whose message names the
parameter and the allowed range, so that bad input never turns into a silent NaN.
"""

from __future__ import annotations

import math
import numbers

import numpy as np


def check_real(name: str, value: object, allowed: str = "finite") -> float:
    """Return ``value`` as a finite float, or raise naming ``name`` and ``allowed``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a real number ({allowed}); got {type(value).__name__}")
    v = float(value)
    if not math.isfinite(v):
        raise ValueError(f"{name} must be {allowed}; got {v}")
    return v


def check_positive(name: str, value: object) -> float:
    """A finite real number > 0."""
    allowed = "> 0 (a finite positive number)"
    v = check_real(name, value, allowed)
    if not v > 0.0:
        raise ValueError(f"{name} must be {allowed}; got {v}")
    return v


def check_nonnegative(name: str, value: object) -> float:
    """A finite real number >= 0."""
    allowed = ">= 0 (finite)"
    v = check_real(name, value, allowed)
    if v < 0.0:
        raise ValueError(f"{name} must be {allowed}; got {v}")
    return v


def check_in_range(
    name: str,
    value: object,
    low: float,
    high: float,
    *,
    low_open: bool = False,
    high_open: bool = False,
) -> float:
    """A finite real number in the interval between ``low`` and ``high``."""
    interval = f"{'(' if low_open else '['}{low}, {high}{')' if high_open else ']'}"
    v = check_real(name, value, f"in {interval}")
    lo_ok = v > low if low_open else v >= low
    hi_ok = v < high if high_open else v <= high
    if not (lo_ok and hi_ok):
        raise ValueError(f"{name} must be in {interval}; got {v}")
    return v


def check_int(name: str, value: object, minimum: int = 1) -> int:
    """An integer >= ``minimum``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be an integer >= {minimum}; got {type(value).__name__}")
    if int(value) < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}; got {value}")
    return int(value)


def check_choice(name: str, value: object, choices: tuple[str, ...]) -> str:
    """One of a fixed set of strings."""
    if not isinstance(value, str) or value not in choices:
        raise ValueError(f"{name} must be one of {choices}; got {value!r}")
    return value


def check_array(
    name: str,
    value: object,
    *,
    shape: tuple[int | None, ...] | None = None,
    ndim: int | None = None,
    min_size: int = 0,
) -> np.ndarray:
    """A finite real float array, optionally with a fixed ``ndim`` or ``shape`` and at least
    ``min_size`` elements.

    ``None`` in ``shape`` matches any length along that axis.
    """
    try:
        arr = np.asarray(value)
    except Exception as exc:  # pragma: no cover - numpy raises many types here
        raise TypeError(f"{name} must be array-like of real numbers") from exc
    if arr.dtype.kind not in "iuf":
        raise TypeError(f"{name} must be array-like of real numbers; got dtype {arr.dtype}")
    arr = arr.astype(float)
    if ndim is not None and arr.ndim != ndim:
        raise ValueError(f"{name} must be {ndim}-D; got shape {arr.shape}")
    if shape is not None:
        ok = arr.ndim == len(shape) and all(s is None or s == n for s, n in zip(shape, arr.shape))
        if not ok:
            want = tuple("any" if s is None else s for s in shape)
            raise ValueError(f"{name} must have shape {want}; got {arr.shape}")
    if arr.size < min_size:
        raise ValueError(f"{name} must hold at least {min_size} value(s); got {arr.size}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must contain only finite values")
    return arr


def check_instance(name: str, value: object, cls: type | tuple[type, ...]) -> object:
    """An instance of ``cls`` (a class or a tuple of classes)."""
    if not isinstance(value, cls):
        names = " or ".join(c.__name__ for c in (cls if isinstance(cls, tuple) else (cls,)))
        article = "an" if names[0] in "AEIOU" else "a"
        raise TypeError(f"{name} must be {article} {names}; got {type(value).__name__}")
    return value


def check_covariance(name: str, M: np.ndarray) -> np.ndarray:
    """A (noise or state) covariance matrix, already a float array: symmetric to rounding
    (1e-9 of its largest entry), with a diagonal >= 0."""
    scale = float(np.max(np.abs(M))) if M.size else 0.0
    if np.any(np.abs(M - M.T) > 1e-9 * scale):
        raise ValueError(f"{name} must be a symmetric matrix (a covariance)")
    if np.any(np.diag(M) < 0.0):
        raise ValueError(f"{name} must have a diagonal >= 0 (variances); "
                         f"got min {np.diag(M).min()}")
    return M


def check_bool(name: str, value: object) -> bool:
    """``True`` or ``False`` (numpy booleans included), not a truthy stand-in."""
    if not isinstance(value, bool | np.bool_):
        raise TypeError(f"{name} must be a bool (True or False); got {type(value).__name__}")
    return bool(value)


def check_str(name: str, value: object) -> str:
    """A string (any content)."""
    if not isinstance(value, str):
        raise TypeError(f"{name} must be a str; got {type(value).__name__}")
    return value


def check_broadcast(**arrays: object) -> tuple[int, ...]:
    """The common shape of arrays (or numbers) given by name, or an error naming them all."""
    shapes = {name: np.shape(a) for name, a in arrays.items()}
    try:
        return np.broadcast_shapes(*shapes.values())
    except ValueError:
        listed = ", ".join(f"{n} {s}" for n, s in shapes.items())
        raise ValueError(f"{', '.join(shapes)} must have broadcast-compatible shapes "
                         f"(equal, or 1 along an axis); got {listed}") from None


def check_ndarray(name: str, value: object, *, ndim: int | None = None,
                  shape: tuple[int | None, ...] | None = None) -> np.ndarray:
    """An existing real numpy array with finite entries, checked without a copy (for the
    large arrays of result records); ``None`` in ``shape`` matches any length."""
    if not isinstance(value, np.ndarray) or value.dtype.kind not in "iuf":
        raise TypeError(f"{name} must be a real numpy array; got {type(value).__name__}"
                        + (f" of dtype {value.dtype}" if isinstance(value, np.ndarray) else ""))
    if ndim is not None and value.ndim != ndim:
        raise ValueError(f"{name} must be {ndim}-D; got shape {value.shape}")
    if shape is not None and not (value.ndim == len(shape) and all(
            s is None or s == n for s, n in zip(shape, value.shape))):
        want = tuple("any" if s is None else s for s in shape)
        raise ValueError(f"{name} must have shape {want}; got {value.shape}")
    if value.dtype.kind == "f" and not np.isfinite(value).all():
        raise ValueError(f"{name} must contain only finite values")
    return value


def check_series(name: str, value: object, n: int | None = None) -> np.ndarray:
    """A 1-D float series (a record's column): NaN (a missing value) allowed, ±inf not;
    ``n`` values when given."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name} must be a 1-D array of real numbers") from exc
    if arr.ndim != 1:
        raise ValueError(f"{name} must be 1-D; got shape {arr.shape}")
    if n is not None and arr.size != n:
        raise ValueError(f"{name} must have {n} values (one per time t); got {arr.size}")
    if np.any(np.isinf(arr)):
        raise ValueError(f"{name} must be finite or NaN (missing); got ±inf")
    return arr


def check_times(t: object) -> np.ndarray:
    """A record's time column ``t``: 1-D, finite, strictly increasing."""
    t = check_array("t", t, ndim=1, min_size=1)
    if np.any(np.diff(t) <= 0.0):
        i = int(np.nonzero(np.diff(t) <= 0.0)[0][0]) + 1
        raise ValueError(f"t must be strictly increasing; t[{i}] = {t[i]} follows "
                         f"t[{i - 1}] = {t[i - 1]}")
    return t
