"""The resolution of a recorded column: the step its values were written or counted in.

A sensor's column written to a fixed number of decimals, or counted in whole LSBs, holds
values on a grid ``x = x0 + k q`` of step ``q``.  Rounding to the grid adds an error that is
uniform over one step when the signal moves across many steps between samples (variance
``q²/12`` per sample) and that repeats from sample to sample when it does not (a steady
increment rounds the same way every time; B. Widrow, I. Kollár, *Quantization Noise*, 2008).
:func:`column_step` finds ``q`` from the values alone; :func:`rounding_correlation` says
how far a given per-sample spread decorrelates the rounding; :func:`describe_step` words a
step for a message.

The step is the greatest common divisor, within the floats' precision, of the differences
between the column's distinct values (Euclid's algorithm on floats, then every difference
checked to be a whole multiple of it; not when the column moves by exactly one such step
from every sample to the next, which is a noise-free signal at a steady rate, not a
rounding), or, for fewer than ten distinct values, the common divisor of that and of the
decimal step the values show (the most decimals in their shortest representation, which is
all a column of one or two distinct values tells: a steady increment written to 4 decimals
reads ``0.157`` or ``0.1571``, and its step is then known only to within the decimals it
shows).  A column that carries the
floats' own precision has no common step and gives 0; a column converted to SI by a factor
keeps its grid, scaled (1e-4 deg is 1.745e-6 rad); one written to a fixed number of
*significant* digits gives the finest step among its values.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["column_step", "describe_step", "rounding_correlation"]

#: A step must exceed this many units in the last place of the column's largest value
#: (about 2e-8 of it) to count: below it, the grid cannot be told from the floats' own
#: rounding or from ten significant digits (and Euclid's remainders, whose errors grow by
#: their quotients, no longer mean anything); a rounding that fine is far below any
#: sensor's noise.
FLOOR_ULPS = 1e8

#: Every difference between distinct values must lie within this share of a step of a whole
#: number of steps.
ON_GRID = 0.01

#: Distinct values from which the differences' step is taken over the decimal one.
EUCLID_EVIDENCE = 10

#: Distinct values whose decimals are read (what matters for a column of few values).
DECIMAL_VALUES = 200

#: Differences between distinct values that Euclid's algorithm reads (the check reads all).
EUCLID_DIFFERENCES = 2000


def _gcd(a: float, b: float, floor: float) -> float:
    """Greatest common divisor of ``a``, ``b`` > 0 by Euclid's algorithm on floats (exact
    remainders), stopping when the remainder falls to ``floor``."""
    while b > floor:
        a, b = b, abs(math.remainder(a, b))
    return a


def column_step(values: ArrayLike) -> float:
    """The step ``q`` of the grid a column's finite values lie on, or 0.0 when they lie on
    none coarser than the floats' own precision.

    Parameters
    ----------
    values : array_like
        One column (NaN and infinities are skipped), in any unit: ``q`` comes in the same.

    Returns
    -------
    float
        ``q`` > 0, or 0.0 (fewer than two distinct values, no common step, or a step within
        :data:`FLOOR_ULPS` units in the last place of the largest value).

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(1)
    >>> x = 0.157 + 1e-5 * rng.standard_normal(1000)
    >>> column_step(np.round(x, 6)), column_step(x)
    (1e-06, 0.0)
    >>> column_step(np.round(x, 4))        # one value, 0.157: its step shows as 3 decimals
    0.001
    >>> column_step(np.round(np.cumsum(x), 4))            # the angle, written to 4 decimals
    0.0001
    >>> column_step(np.radians(900.0) * np.arange(100) * 0.01)   # ω t: no rounding
    0.0
    >>> counts = rng.integers(0, 65536, 500)
    >>> column_step(counts), f"{column_step(2 * np.pi / 65536 * counts):.6e}"   # rad
    (1.0, '9.587380e-05')
    """
    x = np.asarray(values, dtype=float).ravel()
    u = np.unique(x[np.isfinite(x)])
    if u.size == 0:
        return 0.0
    floor = FLOOR_ULPS * float(np.spacing(np.max(np.abs(u))))
    dec = _decimal_step(u, floor)
    euc = _difference_step(u, floor)
    if euc > 0.0 and _one_step_a_sample(x[np.isfinite(x)], euc):
        euc = 0.0
    if dec > 0.0 and euc > 0.0:
        # many distinct values, all on multiples of euc: the values' grid (an LSB that is
        # a short decimal, 20″ = 9.7e-05 rad, written to 6 decimals); few: the finer one
        if u.size < EUCLID_EVIDENCE:
            return _gcd(euc, dec, floor)
        k = round(euc / dec)
        if k >= 1 and abs(euc / dec - k) <= ON_GRID:
            return k * dec          # the values' grid, a whole number of decimal steps
        return euc
    return max(dec, euc)


def _one_step_a_sample(x: np.ndarray, step: float) -> bool:
    """Whether the column moves by exactly one ``step`` from every sample to the next: a
    signal sampled at a steady rate without noise (an angle ``ω t``) lies on the grid of
    its own increment, which is no rounding (a rounded signal stays on a grid point for
    some samples, or moves by several)."""
    m = np.round(np.abs(np.diff(x)) / step)
    return bool(m.size > 0 and np.all(m == 1.0))


def _decimal_step(u: np.ndarray, floor: float) -> float:
    """``10**-k`` for the most decimals ``k`` among the shortest representations of the
    first :data:`DECIMAL_VALUES` values of ``u``, every value of ``u`` checked to lie on
    that grid; 0.0 when one does not, or when the step is within ``floor``."""
    k = max(len(np.format_float_positional(val, unique=True, trim="-").partition(".")[2])
            for val in u[:DECIMAL_VALUES].tolist())
    step = 10.0 ** -k
    if step <= floor:
        return 0.0
    r = u / step
    return step if bool(np.all(np.abs(r - np.round(r)) <= ON_GRID)) else 0.0


def _difference_step(u: np.ndarray, floor: float) -> float:
    """The greatest common divisor of the differences of the sorted distinct values ``u``
    (at least three, counting values within ``floor`` of each other as one), every
    difference checked to be a whole multiple of it, or 0.0 (none, or within ``floor``)."""
    u = u[np.concatenate([[True], np.diff(u) > floor])]   # values apart by rounding: one
    if u.size < 3:          # one difference is no evidence of a grid (0 and a steady value)
        return 0.0
    d = np.diff(u)
    g = float(d[0])
    for di in d[1:EUCLID_DIFFERENCES].tolist():
        g = _gcd(g, di, floor)
        if g <= floor:
            return 0.0
    if g <= floor:
        return 0.0
    k = np.round(d / g)
    if np.any(np.abs(d / g - k) > ON_GRID):
        return 0.0
    # the step from every difference at once (least squares over the whole multiples):
    # Euclid's remainders carry the errors of the few differences they came from
    return float(np.sum(d * k) / np.sum(k * k))


def rounding_correlation(step: float, spread: float) -> float:
    """How much of the rounding error repeats from sample to sample: the first Fourier
    coefficient of a Gaussian of standard deviation ``spread`` at the grid's period ``step``,
    ``exp(−2π² spread²/step²)`` (1: a steady value that rounds the same way every time; 0: a
    value that moves across many steps, whose rounding is white, ``step²/12`` a sample).

    Examples
    --------
    >>> rounding_correlation(1e-4, 0.0), rounding_correlation(1e-4, 1e-4) < 1e-8
    (1.0, True)
    >>> round(rounding_correlation(1e-4, 2.5e-5), 3)
    0.291
    """
    if step <= 0.0:
        return 0.0
    return math.exp(-2.0 * math.pi**2 * (spread / step) ** 2)


def describe_step(step: float, unit: str) -> str:
    """A step in words for a message: its value and unit, and the decimals it amounts to
    when it is a power of ten.

    Examples
    --------
    >>> describe_step(1e-4, "rad"), describe_step(9.587e-05, "rad")
    ('1e-04 rad (4 decimals)', '9.587e-05 rad')
    """
    text = f"{step:.4g} {unit}" if step > 0 else f"0 {unit}"
    if step > 0:
        k = -math.log10(step)
        if abs(k - round(k)) < 1e-6 and round(k) >= 0:
            return f"{step:.0e} {unit} ({round(k)} decimals)"
    return text
