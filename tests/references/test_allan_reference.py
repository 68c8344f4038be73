"""The Allan deviation and its noise terms on real data: the OCXO, GPS
and Cs records of allantools' source distribution against Stable32's published tables
(``tests/references/data_allantools``, an LGPL excerpt committed with its licence), and the rule
that a term never claims more than the data: its line stays below the measured deviation at every
τ within its uncertainty, else it is an upper bound."""

from __future__ import annotations

import gzip
from pathlib import Path

import numpy as np
import pytest

from gyrolib.gc.logs.allan import AllanSeries, _interval, edf_oadev, noise_terms, oadev

DATA = Path(__file__).resolve().parent / "data_allantools"


@pytest.fixture(scope="module")
def ocxo():
    with gzip.open(DATA / "ocxo_frequency.txt.gz", "rt") as fh:
        f = np.array([float(ln) for ln in fh if ln.strip() and not ln.startswith("#")])
    rows = np.loadtxt(DATA / "stable32_ocxo_oadev_octave.txt", comments="#")
    return f / 1.0e7 - 1.0, rows            # fractional frequency, as Stable32 read it


def test_oadev_matches_stable32_and_allantools(ocxo):
    """Our overlapping ADEV of the OCXO record at every octave τ from 1 s to 4096 s: the
    number of terms equal to Stable32 1.60's table and σ within 1.5·10⁻³ of it (the table
    was made from the counter's own file; allantools 2024.6's test of the same table only
    prints this comparison, its σ differs from the table by the same amounts), and within
    10⁻⁶ of allantools itself (a second implementation, pinned).  Power: the
    non-overlapping estimate at τ = 64 s differs from the table by more."""
    import allantools

    y, rows = ocxo
    tau, ad, n = oadev(y, 1.0, "freq", rows[:, 1])
    np.testing.assert_array_equal(tau, rows[:, 1])
    np.testing.assert_array_equal(n, rows[:, 2])
    np.testing.assert_allclose(ad, rows[:, 5], rtol=1.5e-3)
    _, ref, _, _ = allantools.oadev(y, rate=1.0, data_type="freq", taus=rows[:, 1])
    np.testing.assert_allclose(ad, ref, rtol=1e-6)
    x = np.concatenate([[0.0], np.cumsum(y - y.mean())])
    m = 64
    d = x[2 * m::m] - 2 * x[m:-m:m] + x[:-2 * m:m]
    plain = np.sqrt(np.mean(d ** 2) / 2) / m
    assert abs(plain / rows[6, 5] - 1) > 1.5e-3


def _series(y, rate=1.0):
    tau, ad, n = oadev(y, rate, "freq", "octave")
    edf = edf_oadev(0, np.round(tau * rate), y.size + 1)
    lo, hi = _interval(ad, edf)
    return AllanSeries("ocxo", "1", tau, ad, lo, hi, edf, ad, n.astype(float))


def test_terms_never_above_the_data(ocxo):
    """On the OCXO record (white frequency, then flicker from 32 s on), every term's line
    and the line of its upper bound stay at or below the measured deviation's 68 % upper
    bound over the whole curve at every τ (:func:`_upper`, computed here with
    scipy.stats).  The record's short τ fall as 1/τ (the counter's white phase): the
    white-frequency term (slope −½) is only a bound.  The bias instability is IEEE Std
    952's, the curve's minimum over 0.664: equal to it (2 %) and to Stable32's smallest σ
    over 0.664 (5.04·10⁻¹² at 64 s, within the table's rounding and the 1.5·10⁻³ the two
    curves differ by), and identified (the curve rises after it beyond its 68 % bounds).
    Power: the fitted constant of the Allan variance, √a₀/0.664 (the definition the
    tool used before), is 15 % below it, outside the 2 %."""
    from gyrolib.gc.logs.allan import _power_law_fit

    s = _series(ocxo[0])
    terms = noise_terms(s)
    upper = _upper(s)
    for t in terms:
        for level in (t.value, t.hi):
            assert np.all(FACTOR[t.slope] * level**2 * s.tau**round(2 * t.slope)
                          <= upper * (1 + 1e-9)), t.name
    assert not terms[0].identified
    bi = terms[1]
    assert bi.identified and bi.value == pytest.approx(np.min(s.adev) / 0.664, rel=0.02)
    floor = float(np.min(ocxo[1][:, 5]))
    assert bi.value == pytest.approx(floor / 0.664, rel=2e-3)
    a0 = _power_law_fit(s)[0][2]
    assert abs(np.sqrt(a0) / 0.664 / bi.value - 1) > 0.02


# The GPS receiver's and the Cs clock's records of the same source distribution ------------
def _phase(name: str) -> np.ndarray:
    with gzip.open(DATA / name, "rt") as fh:
        return np.array([float(ln) for ln in fh if ln.strip() and not ln.startswith("#")])


@pytest.fixture(scope="module")
def gps():
    """The 1 PPS of a GPS receiver against an H-maser (time interval, s, 1 s apart: 241218
    readings) and Stable32's octave table of it."""
    return (_phase("gps_1pps_phase_data.txt.gz"),
            np.loadtxt(DATA / "stable32_gps_oadev_octave.txt", comments="#"))


@pytest.fixture(scope="module")
def cs():
    """The 1 PPS of a 5071A caesium clock against an H-maser (556990 readings) and
    Stable32's decade table of it."""
    return (_phase("cs5071a_phase.txt.gz"),
            np.loadtxt(DATA / "stable32_cs5071a_oadev_decade.txt", comments="#"))


#: Stable32's tables print σ to 5 significant figures: at most 5·10⁻⁵ of it by rounding.
STABLE32_ROUNDING = 5e-5


@pytest.mark.parametrize("which", ["gps", "cs"])
def test_oadev_of_phase_records_matches_stable32_and_allantools(which, request):
    """Our overlapping ADEV of each phase record at every τ of Stable32's table (octaves of
    the GPS record to 32768 s, decades of the Cs record to 10⁵ s): the number of terms
    equal to the table's, σ within the table's rounding (5 significant figures; measured
    3.6·10⁻⁵ and 2.9·10⁻⁵), and within 10⁻¹² of allantools (pinned; measured 2·10⁻¹⁵).
    Power: the non-overlapping estimate at the table's second τ differs from the table by
    more than the rounding."""
    import allantools

    x, rows = request.getfixturevalue(which)
    tau, ad, n = oadev(x, 1.0, "phase", rows[:, 1])
    np.testing.assert_array_equal(tau, rows[:, 1])
    np.testing.assert_array_equal(n, rows[:, 2])
    np.testing.assert_allclose(ad, rows[:, 5], rtol=STABLE32_ROUNDING, atol=0)
    _, ref, _, _ = allantools.oadev(x, rate=1.0, data_type="phase", taus=rows[:, 1])
    np.testing.assert_allclose(ad, ref, rtol=1e-12, atol=0)
    m = int(rows[1, 0])
    d = x[2 * m::m] - 2 * x[m:-m:m] + x[:-2 * m:m]
    plain = np.sqrt(np.mean(d ** 2) / 2) / m
    assert abs(plain / rows[1, 5] - 1) > STABLE32_ROUNDING


def _phase_series(x: np.ndarray, name: str) -> AllanSeries:
    tau, ad, n = oadev(x, 1.0, "phase", "octave")
    edf = edf_oadev(2, np.round(tau), x.size)
    lo, hi = _interval(ad, edf)
    return AllanSeries(name, "1", tau, ad, lo, hi, edf, ad, n.astype(float))


def _upper(s: AllanSeries) -> np.ndarray:
    """The measured σ²'s upper bound at each τ that holds at every τ together with 68 %
    probability, computed here with scipy.stats: χ² with the least favourable edf of white
    phase, white and random-walk frequency, each point at the one-sided level
    0.6827^(1/n) (Šidák)."""
    import scipy.stats

    m = np.round(s.tau / s.tau[0])
    n_phase = int(np.max(s.n + 2 * m))
    edf = np.min([edf_oadev(a, m, n_phase) for a in (2, 0, -2)], axis=0)
    below = 0.682689492137086 ** (1 / s.tau.size)
    return s.adev**2 * edf / scipy.stats.chi2.ppf(1 - below, edf)


FACTOR = {-0.5: 1.0, 0.0: 0.664**2, 0.5: 1.0 / 3.0}     # σ² of each term's line / term²


@pytest.mark.parametrize("which", ["gps", "cs"])
def test_terms_of_the_clock_records_never_above_the_data(which, request):
    """The GPS receiver's record is white and flicker phase noise (σ falls as 1/τ to 10⁴ s):
    its white-frequency term (the gyro's angle random walk, slope −½) was once "identified"
    with a line up to 15.6 times the measured deviation.  On it, and on the Cs clock's,
    every term's line and the line of its upper bound stay at or below the measured
    deviation's 68 % upper bound over the whole curve; on the GPS record no term is
    identified (each is an upper bound) and the Cs clock's white frequency noise is,
    1.05·10⁻¹¹/√τ (0.7–1.5·10⁻¹¹): Stable32's table reads σ·√τ = 1.5·10⁻¹¹ and 1.3·10⁻¹¹
    at 1000 s and 4000 s, where the other terms add to it.  Power: each of the GPS
    record's bounds is the largest such line — 1.1 times it crosses the bound at some τ."""
    x, _ = request.getfixturevalue(which)
    s = _phase_series(x, which)
    upper = _upper(s)
    terms = noise_terms(s)
    for t in terms:
        p = round(2 * t.slope)
        for level in (t.value, t.hi):
            assert np.all(FACTOR[t.slope] * level**2 * s.tau**p <= upper * (1 + 1e-9)), t.name
        if which == "gps":     # each bound is the data's, not its own uncertainty's
            assert not t.identified
            assert np.any(1.1**2 * FACTOR[t.slope] * t.value**2 * s.tau**p > upper), t.name
    if which == "cs":          # white frequency identified: 1.05e-11 /√s
        assert terms[0].identified and 0.7e-11 < terms[0].value < 1.5e-11


def test_the_curve_bound_holds_the_true_line_of_white_noise():
    """100 simulated white-rate records (2^14 samples at 100 Hz, N = 10⁻³, seeds 1000-1099):
    the true −½ line lies under the 68 % upper bound over the curve (:func:`_upper`, Šidák
    over the τ) at every τ in at least 68 of them (measured 91: the least favourable edf
    makes it conservative), where each point's own 68 % interval holds it in at most 50
    (measured 27: why the terms are held to the curve's bound, not each point's).  N is
    identified in at least 90 (measured 95), clipped to the bound in at most 10 (measured
    2), and within 3σ of the truth in every one identified."""
    from gyrolib.gc.logs.allan import allan_series

    n_true, dt = 1e-3, 0.01
    curve = point = identified = clipped = covered = 0
    for seed in range(1000, 1100):
        y = np.random.default_rng(seed).standard_normal(2**14) * n_true / np.sqrt(dt)
        s = allan_series(y, 1 / dt)
        line = n_true**2 / s.tau
        curve += bool(np.all(line <= _upper(s)))
        point += bool(np.all(line <= s.hi**2))
        arw = noise_terms(s)[0]
        if arw.identified:
            identified += 1
            clipped += arw.hi == arw.value       # its value is the bound's line
            covered += abs(arw.value - n_true) <= 3 * arw.sigma
    assert curve >= 68 and point <= 50
    assert identified >= 90 and clipped <= 10 and covered == identified
