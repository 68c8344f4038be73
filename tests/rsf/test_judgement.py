"""rsf.judge_record: from a record to one verdict, decided by the library, on 10 s of a
simulated flight (seed 9393) at paper RSF's sensors."""

from __future__ import annotations

import math

import pytest

from gyrolib import rsf


@pytest.fixture(scope="module")
def record() -> rsf.RSFRecord:
    flight = rsf.simulate_flight(rsf.SimulationConfig(duration=10.0, sample_rate=1000.0),
                                 seed=9393)
    return rsf.record_from_simulation(flight)


def test_the_verdict_holds_the_uncertainty_and_its_checks(record):
    ver = rsf.judge_record(record, 1.0)
    unc = rsf.eps1_uncertainty(rsf.calibrate(record, 1.0), rsf.SimulationConfig())
    assert ver.status == "ok" and ver.reason == "" and ver.hint == ""
    assert (ver.estimate, ver.sigma) == (unc.mean, unc.std)
    assert dict(ver.sigma_parts) == unc.parts
    assert math.hypot(*ver.sigma_parts.values()) == pytest.approx(ver.sigma, rel=1e-12)
    assert [c.test for c in ver.checks] == [c["test"] for c in unc.checks]
    c = ver.counts
    assert c.used + c.rejected + c.empty == c.rows == record.n and c.rejected == 0


def test_a_prior_failure_names_its_state_value_and_band(record):
    """A roll-gyro tolerance of 1 ppm: the prior check of eps1_hat_mean fails, its value the
    closed form ε̄/√(tol² + σ²) and its band the two-sided normal limit; the reason prints
    the check's own line, and the hint names --sf-tolerance.  The default tolerance passes
    (power: the tolerance alone moves the verdict)."""
    ver = rsf.judge_record(record, 1.0, sf_prior=1e-6)
    prior = next(c for c in ver.checks if c.test == "prior")
    assert prior.name == "prior of eps1_hat_mean" and not prior.passed
    assert prior.value == pytest.approx(ver.estimate / math.hypot(1e-6, ver.sigma), rel=1e-12)
    assert prior.low == -prior.high and abs(prior.value) > prior.high
    assert ver.status == "invalid" and ver.reason_code == "rsf_prior"
    assert prior.line() in ver.reason and ver.hint.startswith("try: --sf-tolerance (")
    assert rsf.judge_record(record, 1.0).status == "ok"


def test_a_record_shorter_than_the_period_is_refused(record):
    with pytest.raises(ValueError, match=r"period 20\.0 s is longer than the record"):
        rsf.judge_record(record, 20.0)
