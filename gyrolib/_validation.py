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
) -> np.ndarray:
    """A finite real float array, optionally with a fixed ``ndim`` or ``shape``.

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
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must contain only finite values")
    return arr
