"""gyrolib.stats: intervals of statistics of random runs, checked against closed forms and
over seeds, each with its power (the same check on a deliberately wrong interval fails)."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from scipy import stats as sp

from gyrolib import stats


@pytest.mark.parametrize("q", [10.0, 50.0, 90.0])
def test_percentile_interval_agrees_with_the_bootstrap(q):
    """A second algorithm: on a light-tailed sample the distribution-free interval and a
    percentile bootstrap (seeded) agree to 15 % of the width; power: the bootstrap at 50 %
    confidence does not."""
    x = np.random.default_rng(5).standard_normal(400)
    est = stats.percentile(x, q)
    assert est.method == "order statistic"
    assert est.value == pytest.approx(np.percentile(x, q))
    width = est.hi - est.lo

    def boot(confidence):
        return stats.bootstrap(x, lambda s: np.percentile(s, q, axis=-1), seed=0,
                               vectorized=True, confidence=confidence)

    def close(b):
        return abs(b.lo - est.lo) < 0.15 * width and abs(b.hi - est.hi) < 0.15 * width

    assert close(boot(0.95))
    assert not close(boot(0.5))


def test_percentile_ranks_by_hand():
    """n = 20, median: the binomial(20, 1/2) ranks 6 and 15 (P = 0.959) by the closed form."""
    x = np.arange(1.0, 21.0)
    est = stats.percentile(x, 50)
    assert (est.lo, est.hi) == (6.0, 15.0)
    tail = sp.binom.cdf(5, 20, 0.5)
    assert 1 - 2 * tail == pytest.approx(0.9586, abs=1e-4)
    short = stats.percentile(np.arange(1.0, 6.0), 10)      # rank 0 does not exist
    assert short.method == "order statistic, clipped" and short.lo == 1.0


def _coverage(confidence: float, n_seeds: int = 400) -> int:
    """How many of ``n_seeds`` samples (200 draws of N(0, 1) each) have an interval of the
    10th percentile that covers the population's, Φ⁻¹(0.1)."""
    true = sp.norm.ppf(0.1)
    hits = 0
    for s in range(n_seeds):
        x = np.random.default_rng(1000 + s).standard_normal(200)
        est = stats.percentile(x, 10.0, confidence=confidence)
        hits += est.lo <= true <= est.hi
    return hits


def test_the_95_percent_interval_covers_the_population_percentile_over_seeds():
    """Over 400 seeds the number of intervals that cover the true 10th percentile is
    binomial(400, c); a 95 % interval must keep c within [0.94, 0.985] (discrete ranks
    over-cover a little): the test fails when the count lies outside the central 99.8 % of
    the end binomials.  Power: intervals labelled 95 % but computed at 50 % fail."""
    n = 400
    low = sp.binom.ppf(0.001, n, 0.94)
    high = sp.binom.ppf(0.999, n, 0.985)
    assert low <= _coverage(0.95, n) <= high
    assert not low <= _coverage(0.50, n) <= high


def test_a_two_dimensional_sample_is_resampled_by_runs():
    """Entries of one run that are equal (perfectly correlated) carry the information of
    one run, not of many: the interval of the mean of a (runs × k) sample whose rows repeat
    one value equals that of the 1-D sample of those values."""
    one = np.random.default_rng(2).standard_normal(60)
    rows = np.repeat(one[:, None], 8, axis=1)
    a, b = stats.mean(one, seed=4), stats.mean(rows, seed=4)
    assert (a.lo, a.hi) == pytest.approx((b.lo, b.hi))
    # power: treating the 480 entries as independent gives a much narrower interval
    flat = stats.mean(rows.ravel(), seed=4)
    assert flat.hi - flat.lo < 0.5 * (b.hi - b.lo)


def test_mean_interval_agrees_with_the_normal_closed_form():
    x = np.random.default_rng(9).normal(3.0, 2.0, 500)
    est = stats.mean(x, seed=1)
    half = 1.96 * x.std(ddof=1) / math.sqrt(x.size)
    assert est.lo == pytest.approx(x.mean() - half, abs=0.1 * half)
    assert est.hi == pytest.approx(x.mean() + half, abs=0.1 * half)


def test_wilson_interval_has_its_coverage_exactly():
    """Exact coverage of the Wilson interval summed over the binomial distribution (no
    simulation): within [0.93, 0.97] at n = 400, p = 0.2.  Power: the interval computed as if
    from n/4 runs over-covers and fails."""
    n, p = 400, 0.2
    ks = np.arange(n + 1)
    pmf = sp.binom.pmf(ks, n, p)

    def coverage(n_used):
        return sum(w for k, w in zip(ks, pmf)
                   if (lambda e: e.lo <= p <= e.hi)(stats.proportion(round(k * n_used / n),
                                                                     n_used)))

    assert 0.93 <= coverage(n) <= 0.97
    assert not 0.93 <= coverage(n // 4) <= 0.97


def test_text_prints_no_digit_finer_than_the_interval():
    est = stats.Estimate(value=-82.67, lo=-131.5, hi=-43.8, confidence=0.95, n=400,
                         method="bootstrap", seed=1)
    assert est.resolution == 10.0
    assert est.text("%") == "-80 % (95 % CI -140 to -40 %)"
    small = stats.Estimate(0.6713, 0.6319, 0.7003, 0.95, 400, "bootstrap", 1)
    assert small.text("%", scale=100) == "67 % (95 % CI 63 to 71 %)"
    # every printed number is a multiple of the resolution (no digit finer than it)
    for e in (est, small.scaled(100), stats.proportion(81, 400).scaled(100)):
        tokens = re.findall(r"-?\d+(?:\.\d+)?", e.text().replace("95 % CI", ""))
        assert len(tokens) == 3
        for token in tokens:
            assert float(token) / e.resolution == pytest.approx(round(float(token)
                                                                      / e.resolution))
    # the printed interval contains the computed one
    _, lo, hi = est.rounded()
    assert lo <= est.lo and hi >= est.hi


def test_same_seed_same_interval_and_other_seed_close():
    x = np.random.default_rng(3).standard_normal(400)
    a, b = stats.mean(x, seed=7), stats.mean(x, seed=7)
    assert (a.lo, a.hi) == (b.lo, b.hi)
    c = stats.mean(x, seed=8)
    assert abs(c.lo - a.lo) < 0.2 * (a.hi - a.lo)


@pytest.mark.parametrize("call, match", [
    (lambda: stats.percentile(np.ones(10), 120), "q"),
    (lambda: stats.mean(np.ones(10), seed=-1), "seed"),
    (lambda: stats.percentile(np.ones(1), 50), "sample"),
    (lambda: stats.percentile([1.0, np.nan, 2.0], 50), "sample"),
    (lambda: stats.proportion(5, 4), "successes"),
    (lambda: stats.proportion(1, 4, confidence=1.0), "confidence"),
    (lambda: stats.bootstrap(np.ones(5), "mean", seed=0), "statistic"),
    (lambda: stats.Estimate(1.0, 2.0, 0.0, 0.95, 10, "x"), "lo"),
])
def test_bad_input_is_named(call, match):
    with pytest.raises((ValueError, TypeError), match=match):
        call()
