"""Input checks shared by the paper RSF modules (scale-factor errors, divisors, records).
"""

from __future__ import annotations

import numbers

import numpy as np

from gyrolib import _validation as v

# A scale-factor error is a small number; anything at or beyond ±1 is not a scale-factor
# error of a working gyro (the reading would vanish or change sign).
SF_LIMIT = 1.0


# Input helpers --------------------------------------------------------------------------------
def check_value(name: str, value: object, *, nonnegative: bool = False) -> float | np.ndarray:
    """A finite real number or array of them (``nonnegative``: all >= 0)."""
    if isinstance(value, numbers.Real) and not isinstance(value, bool):
        out: float | np.ndarray = (v.check_nonnegative(name, value) if nonnegative
                                   else v.check_real(name, value))
        return out
    arr = v.check_array(name, value)
    if nonnegative and np.any(arr < 0.0):
        raise ValueError(f"{name} must be >= 0 (finite) everywhere; got min {arr.min()}")
    return arr if arr.ndim else float(arr)


def check_nonzero(name: str, value: object) -> float | np.ndarray:
    """A finite real number (or array) that is nowhere zero: it is a divisor."""
    out = check_value(name, value)
    if np.any(np.asarray(out) == 0.0):
        raise ValueError(f"{name} must be nonzero (finite, != 0); got 0")
    return out


def check_sf(name: str, value: object) -> float | np.ndarray:
    """A scale-factor error: finite and in the open interval (−1, 1)."""
    out = check_value(name, value)
    if np.any(np.abs(np.asarray(out)) >= SF_LIMIT):
        raise ValueError(f"{name} must be in (-1.0, 1.0) (a relative scale-factor error); "
                         f"got {out}")
    return out


# Sensor specification records ------------------------------------------------------------------
def check_optional_positive(name: str, value: object) -> float | None:
    if value is None:
        return None
    return v.check_positive(name, value)


# The paper's tables ---------------------------------------------------------------------------
def check_times(times: object) -> np.ndarray:
    t = v.check_array("times", times, ndim=1)
    if t.size == 0 or np.any(t < 0.0):
        raise ValueError("times must be a non-empty 1-D array of values >= 0")
    return t


def check_same_shape(record: object, first: str, *others: str) -> None:
    """The array fields of a result record: 1-D, finite, all the shape of ``first``."""
    shape = v.check_ndarray(first, getattr(record, first), ndim=1).shape
    for name in others:
        v.check_ndarray(name, getattr(record, name), shape=shape)
