"""gc.judge_record: from a record to one verdict (status, reason, code, hint, σ with its
named terms, every check with its one band, the counts of the rows), decided by the
library, on 20 s of paper GC's model (seed 3401) and its damaged copies."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from gyrolib import gc
from gyrolib.verdict import Counts

P = gc.GyrocompassParams()


@pytest.fixture(scope="module")
def clean() -> gc.GCRecord:
    return gc.simulate_record(P, 20.0, seed=3401).record


def test_a_clean_record_is_ok_and_its_estimate_is_calibrates(clean):
    ver = gc.judge_record(clean, P)
    res = gc.calibrate(clean, P)
    assert ver.status == "ok" and ver.reason == "" and ver.reason_code == "" == ver.hint
    assert ver.estimate == res.omega_gc
    # σ's named terms are the filter's parts and add in quadrature to σ
    assert dict(ver.sigma_parts) == res.omega_gc_std_parts
    assert math.hypot(*ver.sigma_parts.values()) == pytest.approx(ver.sigma, rel=1e-12)
    # one check per lock share, NIS, whiteness, split and prior test, each passed
    n_tests = 3 + len(res.model_tests())
    assert len(ver.checks) == n_tests and all(c.passed for c in ver.checks)
    names = [c.name for c in ver.checks]
    assert len(set(names)) == len(names)
    assert {"prior of omega_gc", "prior of delta", "mean NIS of angle_sensor"} <= set(names)


def test_no_latitude_is_invalid_with_its_code_and_hint(clean):
    ver = gc.judge_record(clean, P, latitude_stated=False)
    assert ver.status == "invalid" and not ver.given
    assert ver.reason.startswith(gc.logs.judgement.NO_LATITUDE)
    assert ver.reason_code == "no_latitude" and ver.hint.startswith("try: --latitude (")
    # the same record with the latitude stated is ok (the flag, not the data, decides)
    assert gc.judge_record(clean, P, latitude_stated=True).status == "ok"


def test_a_misfit_is_given_only_on_request(clean):
    """The angle sensor's noise doubled in variance: a model check fails (invalid); with
    ``accept_misfit`` the estimate is given, marked misfit; a lost lock never is."""
    sd = math.sqrt(gc.measurement_noise_covariance(P)[0, 0])
    rng = np.random.default_rng(3402)
    noisy = dataclasses.replace(clean, angle_sensor=clean.angle_sensor
                                + sd * rng.standard_normal(clean.n))
    ver = gc.judge_record(noisy, P)
    assert ver.status == "invalid" and "misfit_nis" in ver.reason_codes
    failed = {c.name for c in ver.failed}
    assert "mean NIS of angle_sensor" in failed
    acc = gc.judge_record(noisy, P, accept_misfit=True)
    assert acc.status == "misfit" and acc.given and acc.reason == ver.reason
    flipped = dataclasses.replace(clean, inclinometer_y=-clean.inclinometer_y)
    lost = gc.judge_record(flipped, P, accept_misfit=True)
    assert lost.status == "invalid" and lost.reason_code == "lost_lock"


def test_counts_never_exceed_the_rows():
    """499 rows with one inclinometer's sign flipped (the gate rejects nearly every one of
    its samples while the others are used): the rows used, with a rejection and with
    nothing to use partition the 499 rows; rows with both a used and a rejected
    measurement are counted once."""
    rec = gc.simulate_record(P, 0.5, seed=3403).record
    rec = gc.GCRecord(t=rec.t[:499], angle_sensor=rec.angle_sensor[:499],
                      inclinometer_y=-50.0 * rec.inclinometer_y[:499],
                      inclinometer_z=rec.inclinometer_z[:499])
    ver = gc.judge_record(rec, P)
    c = ver.counts
    assert c.rows == rec.n == 499
    assert c.used + c.rejected + c.empty == c.rows
    assert max(c.used, c.rejected, c.empty) <= c.rows
    res = ver.result
    assert res.rejected[1] > 0 and res.used[0] > 0     # rows with both fates exist
    assert c.rejected >= res.rejected[1]
    with pytest.raises(ValueError, match="must equal rows"):
        Counts(rows=499, used=5, rejected=499, empty=0)


def test_the_mean_nis_band_is_one_band_within_the_lock_range(clean):
    """The mean-NIS check's band is the test's band within ``nis_range``: a value beyond
    the lock range is outside it, with the lock's code, even where the band of a few
    samples is wider (5 samples: [2e-07, 12.6] at the family-wise level)."""
    res = gc.calibrate(clean, P)
    for t in res.model_tests():
        if t["test"] == "mean NIS":
            assert res.nis_range[0] <= t["low"] < 1.0 < t["high"] <= res.nis_range[1]
    short = dataclasses.replace(clean, t=clean.t[:5], angle_sensor=3.0 * clean.angle_sensor[:5],
                                inclinometer_y=clean.inclinometer_y[:5],
                                inclinometer_z=clean.inclinometer_z[:5])
    few = gc.calibrate(short, P)
    for t in few.model_tests():
        if t["test"] == "mean NIS":
            assert (t["low"], t["high"]) == pytest.approx(
                (max(t["low"], 0.5), min(t["high"], 2.0)))
            if not 0.5 <= t["statistic"] <= 2.0:
                assert not t["passed"] and t["reason_code"] == "lost_lock_nis"


def test_a_lost_lock_is_named_before_its_symptoms():
    """A filter that lost lock has no estimate to test: a failed prior check is its symptom,
    and the option it names would mask the fault; without a lost lock the prior's code is
    the cause (power: the rule changes the answer)."""
    from gyrolib.gc.logs.judgement import cause_code

    codes = ["lost_lock", "prior_incl_bias", "lost_lock_gate", "misfit_nis"]
    assert cause_code(codes, lost_lock=True) == "lost_lock"
    assert cause_code(codes, lost_lock=False) == "prior_incl_bias"
    assert cause_code(["early_release", "lost_lock", "prior_drift"], True) == "early_release"
