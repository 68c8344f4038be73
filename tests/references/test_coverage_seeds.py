"""The coverage benchmark's cases (``benchmarks/bench_coverage.py`` runs
100 seeds of each and records the statistics) on two fixed seeds each, small: RSF flights
of 30 s, GC records of 10 s, fitted noise on 10 s records.  Each seed's truth lies within
3 σ (RSF, GC) or inside the fitted parameters' 95 % intervals; the power: a σ made of
RSF's SEM alone misses the same RSF flights by more."""

from __future__ import annotations

import math

import pytest

from tests.support.coverage_cases import fit_case, gc_case, rsf_case, wilson


@pytest.mark.parametrize("seed", [1000, 1001])
def test_rsf_total_sigma_covers(seed):
    r = rsf_case(seed)
    assert r["valid"] and abs(r["z"]) < 3.0, r


@pytest.mark.parametrize("seed", [1000, 1001])
def test_gc_sigma_covers_with_constants_drawn_from_priors(seed):
    r = gc_case(seed, t_end=10.0)
    assert r["valid"] and abs(r["z"]) < 3.0, r


@pytest.mark.parametrize("seed", [2000, 2001])
def test_fitted_intervals_hold_the_truth(seed):
    r = fit_case(seed, t_end=10.0)
    assert r["converged"], r["message"]
    assert set(r["covered"]) == {"alpha1", "sigma1_sq", "C_as", "C_in"}
    assert all(r["covered"].values()), r
    assert abs(r["z"]) < 3.0


def test_wilson_interval_against_its_closed_form():
    """The benchmark's binomial interval: 68 of 100 gives [0.583, 0.763] (Wilson 1927,
    computed by hand: centre (p + z²/2n)/(1 + z²/n), half-width z√(p(1−p)/n + z²/4n²)/(1 +
    z²/n))."""
    lo, hi = wilson(68, 100)
    assert lo == pytest.approx(0.5833, abs=1e-3) and hi == pytest.approx(0.7633, abs=1e-3)
    assert math.isnan(wilson(0, 0)[0])
