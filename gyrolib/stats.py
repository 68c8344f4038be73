"""Statistics of random runs with their uncertainty.

A percentile, a mean or a share of simulated flights or Monte Carlo runs is a random number:
another seed gives another value.  Every such statistic the book quotes is an
:class:`Estimate`: the value, a 95 % interval, how the interval was computed (with its seed),
and :meth:`Estimate.text`, which prints no digit finer than the interval.

* :func:`bootstrap` — any statistic of a sample, with a percentile-bootstrap interval from
  an explicit seed; a 2-D sample is resampled by rows (whole runs), so the intervals of a
  statistic over correlated samples within a run (intervals of one flight, times of one
  Monte Carlo run) stay honest;
* :func:`percentile` — a percentile of independent runs with its distribution-free
  (order-statistic) interval: exact, no seed;
* :func:`mean` — a mean with its bootstrap interval;
* :func:`proportion` — a share of independent runs with Wilson's score interval (closed
  form, no seed).

**The rounding rule** (:attr:`Estimate.resolution`): the value and the interval are printed
to the power of ten at or below the interval's half-width, i.e. to one significant digit of
the uncertainty; the value is rounded to the nearest multiple, the interval outwards (so
the printed interval contains the computed one).

Examples
--------
>>> import numpy as np
>>> from gyrolib import stats
>>> x = np.random.default_rng(7).normal(50.0, 10.0, 400)
>>> est = stats.percentile(x, 10)
>>> est.text("%")
'37 % (95 % CI 35 to 39 %)'
>>> stats.proportion(81, 400).text("%", scale=100)
'20 % (95 % CI 16 to 25 %)'
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from gyrolib import _validation as v
from gyrolib._repr import compact_repr

__all__ = ["Estimate", "bootstrap", "mean", "percentile", "proportion"]

#: Bootstrap resamples by default: the interval's ends then move by much less than its
#: resolution from one bootstrap seed to another.
N_BOOT = 2000


@compact_repr
@dataclass(frozen=True)
class Estimate:
    """A statistic of random runs and its interval.

    ``value`` the statistic of the sample, [``lo``, ``hi``] its ``confidence`` interval,
    ``n`` the number of independent units (runs, flights) it rests on, ``method`` how the
    interval was computed (``"bootstrap"``, ``"order statistic"``, ``"wilson"``) and
    ``seed`` the bootstrap's seed (``None`` for a closed form).
    """

    value: float
    lo: float
    hi: float
    confidence: float
    n: int
    method: str
    seed: int | None = None

    def __post_init__(self) -> None:
        for name in ("value", "lo", "hi"):
            object.__setattr__(self, name, v.check_real(name, getattr(self, name)))
        if not self.lo <= self.hi:
            raise ValueError(f"lo must be <= hi; got lo={self.lo}, hi={self.hi}")
        v.check_in_range("confidence", self.confidence, 0.0, 1.0, low_open=True,
                         high_open=True)
        v.check_int("n", self.n, 1)
        v.check_str("method", self.method)
        if self.seed is not None:
            v.check_int("seed", self.seed, 0)

    @property
    def resolution(self) -> float | None:
        """The place of the last printed digit: the power of ten at or below the interval's
        half-width (``None`` for an interval of zero width, printed to 3 significant
        digits)."""
        half = 0.5 * (self.hi - self.lo)
        if not half > 0.0:
            return None
        return 10.0 ** math.floor(math.log10(half))

    def scaled(self, factor: float) -> Estimate:
        """The same estimate in another unit (e.g. ``100`` for a share in %)."""
        factor = v.check_positive("factor", factor)
        return Estimate(self.value * factor, self.lo * factor, self.hi * factor,
                        self.confidence, self.n, self.method, self.seed)

    def rounded(self) -> tuple[float, float, float]:
        """``(value, lo, hi)`` at :attr:`resolution`: the value to the nearest multiple,
        ``lo`` down and ``hi`` up (the printed interval contains the computed one)."""
        r = self.resolution
        if r is None:
            return self.value, self.lo, self.hi
        # a relative slack so that a value computed exactly on a multiple is not pushed out
        lo = math.floor(self.lo / r + 1e-9) * r
        hi = math.ceil(self.hi / r - 1e-9) * r
        return round(self.value / r) * r, lo, hi

    def _fmt(self, x: float) -> str:
        r = self.resolution
        if r is None:
            return f"{x:.3g}"
        decimals = max(0, -math.floor(math.log10(r)))
        text = f"{x:.{decimals}f}"
        return text.lstrip("-") if float(text) == 0.0 else text  # no "-0"

    def value_text(self) -> str:
        """The value alone, to :attr:`resolution`: ``'-80'``."""
        return self._fmt(self.rounded()[0])

    def interval_text(self, unit: str = "") -> str:
        """The interval alone: ``'95 % CI -140 to -40 %'``."""
        _, lo, hi = self.rounded()
        u = f" {v.check_str('unit', unit)}" if unit else ""
        return f"{100 * self.confidence:g} % CI {self._fmt(lo)} to {self._fmt(hi)}{u}"

    def text(self, unit: str = "", *, scale: float = 1.0) -> str:
        """The value with its interval, no digit finer than the interval:
        ``'-80 % (95 % CI -140 to -40 %)'``; ``scale`` multiplies all three first."""
        est = self if scale == 1.0 else self.scaled(scale)
        u = f" {v.check_str('unit', unit)}" if unit else ""
        return f"{est.value_text()}{u} ({est.interval_text(unit)})"


def _check_confidence(confidence: object) -> float:
    return v.check_in_range("confidence", confidence, 0.0, 1.0, low_open=True, high_open=True)


def bootstrap(sample: ArrayLike, statistic: Callable[[np.ndarray], float], *, seed: int,
              confidence: float = 0.95, n_boot: int = N_BOOT,
              vectorized: bool = False) -> Estimate:
    """A statistic of a sample of independent runs with its percentile-bootstrap interval.

    The sample is resampled with replacement ``n_boot`` times (along its first axis: a 2-D
    sample is resampled by whole rows, one row per run), the statistic computed on each
    resample, and the interval is the central ``confidence`` range of those values
    {cite:p}`Efron1993`.

    Parameters
    ----------
    sample : array_like
        1-D (one value per run) or 2-D (one row per run) finite values.
    statistic : callable
        ``statistic(sample) -> float`` on an array shaped as ``sample``.
    seed : int
        Seeds the resampling (>= 0): the interval is the same on every run of the book.
    confidence : float, optional
        Of the interval, in (0, 1) (default 0.95).
    n_boot : int, optional
        Number of resamples (>= 100).
    vectorized : bool, optional
        ``statistic(batch)`` takes a stack of resamples, shape ``(b, *sample.shape)``, and
        returns ``b`` values (much faster; the sample itself is passed as a stack of one).

    Returns
    -------
    Estimate

    Examples
    --------
    >>> import numpy as np
    >>> runs = np.random.default_rng(3).normal(size=(50, 4))   # 50 runs, 4 steps each
    >>> est = bootstrap(runs, lambda s: float(np.mean(s[:, -1] ** 2)), seed=0)
    >>> est.n, est.method, est.lo < est.value < est.hi
    (50, 'bootstrap', True)
    """
    x = v.check_array("sample", sample)
    if x.ndim not in (1, 2) or x.shape[0] < 2:
        raise ValueError(f"sample must be 1-D or 2-D with at least 2 runs along its first "
                         f"axis; got shape {x.shape}")
    if not callable(statistic):
        raise TypeError(f"statistic must be callable; got {type(statistic).__name__}")
    seed = v.check_int("seed", seed, 0)
    confidence = _check_confidence(confidence)
    n_boot = v.check_int("n_boot", n_boot, 100)
    vectorized = v.check_bool("vectorized", vectorized)
    rng = np.random.default_rng(seed)
    n = x.shape[0]
    idx = rng.integers(0, n, (n_boot, n))
    if vectorized:
        value = float(np.asarray(statistic(x[None]))[0])
        chunk = max(1, 4_000_000 // x.size)      # resamples per batch: bounded memory
        draws = np.concatenate([np.asarray(statistic(x[idx[i:i + chunk]]), dtype=float)
                                for i in range(0, n_boot, chunk)])
    else:
        value = float(statistic(x))
        draws = np.array([statistic(x[i]) for i in idx], dtype=float)
    if draws.shape != (n_boot,):
        raise ValueError(f"statistic must return one value per resample; got {draws.shape}")
    tail = 50.0 * (1.0 - confidence)
    lo, hi = np.percentile(draws, [tail, 100.0 - tail])
    return Estimate(value=value, lo=float(min(lo, value)), hi=float(max(hi, value)),
                    confidence=confidence, n=n, method="bootstrap", seed=seed)


def percentile(sample: ArrayLike, q: float, *, confidence: float = 0.95) -> Estimate:
    """The ``q``-th percentile of a sample of independent runs with its distribution-free
    interval.

    The number of runs below the population's percentile is binomial(n, q/100) whatever the
    distribution, so the order statistics ``X_(l) ≤ X_(u)`` with ``l`` and ``u`` the
    binomial's ``(1 ∓ confidence)/2`` quantiles (``u`` plus one) bracket it with at least
    that probability {cite:p}`David2003` (exact and seed-free; a percentile bootstrap
    under-covers in a heavy tail, such as the flights' shares below zero).  Where a rank
    falls outside the sample, the end is the sample's extreme and the interval covers
    less than ``confidence`` (``method`` says so).

    Parameters
    ----------
    sample : array_like
        1-D, one value per independent run (>= 2 runs).
    q : float
        Percentile, in [0, 100].
    confidence : float, optional
        Of the interval, in (0, 1) (default 0.95).

    Returns
    -------
    Estimate
        ``value`` the sample's percentile (``numpy.percentile``, linear), ``method``
        ``"order statistic"`` (or ``"order statistic, clipped"``).

    Examples
    --------
    >>> import numpy as np
    >>> x = np.random.default_rng(0).standard_normal(1000)
    >>> percentile(x, 50).text()
    '-0.07 (95 % CI -0.16 to 0.00)'
    """
    x = v.check_array("sample", sample, ndim=1)
    if x.size < 2:
        raise ValueError(f"sample must hold at least 2 runs; got {x.size}")
    q = v.check_in_range("q", q, 0.0, 100.0)
    confidence = _check_confidence(confidence)
    from scipy.stats import binom

    n, p, tail = x.size, q / 100.0, 0.5 * (1.0 - confidence)
    lo_rank = int(binom.ppf(tail, n, p))            # 1-based ranks of the order statistics
    hi_rank = int(binom.ppf(1.0 - tail, n, p)) + 1
    clipped = lo_rank < 1 or hi_rank > n
    xs = np.sort(x)
    value = float(np.percentile(x, q))
    lo = float(xs[min(max(lo_rank, 1), n) - 1])
    hi = float(xs[min(max(hi_rank, 1), n) - 1])
    return Estimate(value=value, lo=min(lo, value), hi=max(hi, value), confidence=confidence,
                    n=n, method="order statistic" + (", clipped" if clipped else ""))


def mean(sample: ArrayLike, *, seed: int, confidence: float = 0.95,
         n_boot: int = N_BOOT) -> Estimate:
    """The mean of a sample of runs (of all entries of a 2-D sample, one row per run) with
    its bootstrap interval.

    Examples
    --------
    >>> import numpy as np
    >>> mean(np.arange(100.0), seed=0).text()
    '50 (95 % CI 43 to 56)'
    """
    x = v.check_array("sample", sample)
    return bootstrap(x, lambda s: np.mean(s.reshape(s.shape[0], -1), axis=1), seed=seed,
                     confidence=confidence, n_boot=n_boot, vectorized=True)


def proportion(successes: int, n: int, *, confidence: float = 0.95) -> Estimate:
    """A share of ``n`` independent runs, ``successes / n``, with Wilson's score interval
    {cite:p}`Wilson1927` (closed form: no seed).

    Parameters
    ----------
    successes : int
        Runs with the property (0 <= successes <= n).
    n : int
        Runs (>= 1).
    confidence : float, optional
        Of the interval, in (0, 1) (default 0.95).

    Returns
    -------
    Estimate
        A share in [0, 1] (use ``text(scale=100)`` for %).

    Examples
    --------
    >>> est = proportion(81, 400)
    >>> f"{est.value:.4f} [{est.lo:.4f}, {est.hi:.4f}]"
    '0.2025 [0.1660, 0.2446]'
    """
    n = v.check_int("n", n, 1)
    k = v.check_int("successes", successes, 0)
    if k > n:
        raise ValueError(f"successes must be <= n = {n}; got {k}")
    confidence = _check_confidence(confidence)
    z = _normal_quantile(0.5 + 0.5 * confidence)
    p = k / n
    denom = 1.0 + z * z / n
    centre = (p + z * z / (2 * n)) / denom
    half = z * math.sqrt(p * (1.0 - p) / n + z * z / (4 * n * n)) / denom
    return Estimate(value=p, lo=max(0.0, min(p, centre - half)), hi=min(1.0, max(p, centre + half)),
                    confidence=confidence, n=n, method="wilson")


def _normal_quantile(p: float) -> float:
    """Φ⁻¹(p) of the standard normal (scipy's ``ndtri``)."""
    from scipy.special import ndtri

    return float(ndtri(p))
