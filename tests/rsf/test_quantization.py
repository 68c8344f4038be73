"""RSF records with coarse columns: SINS increments and GS angle written to 4 decimals, and a
65536-count encoder record whose increments and GS gyro angle are written to 5 decimals.
Their rounding is σ's ``quantization`` part (closed form in :mod:`gyrolib.rsf.uncertainty`);
each record is judged against the simulation's truth, and without the part the 4-decimal
record is valid and wrong by more than 3 σ."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from gyrolib import rsf
from gyrolib.resolution import rounding_correlation


def _coarse(seed: int, decimals: int, *, encoder: bool = False):
    """A flight of 30 s with the sensors' errors drawn from their tolerances, its angle
    columns rounded to ``decimals``; (record, config, truth of eps1_hat_mean)."""
    cfg = rsf.SimulationConfig(errors="random", duration=30.0)
    if encoder:
        cfg = dataclasses.replace(cfg, encoder=rsf.EncoderModel(
            counts_per_rev=65536, position_error=cfg.encoder.position_error))
    sim = rsf.simulate_flight(cfg, seed=seed)
    r = rsf.record_from_simulation(sim, encoder=encoder)
    inc = np.round(r.sins_increment, decimals)
    if encoder:
        rec = rsf.RSFRecord(t=r.t, sins_increment=inc, encoder_counts=r.encoder_counts,
                            counts_per_rev=r.counts_per_rev,
                            gs_gyro_angle=np.round(r.gs_gyro_angle, decimals))
    else:
        rec = rsf.RSFRecord(t=r.t, sins_increment=inc, gs_angle=np.round(r.gs_angle, decimals))
    e1 = float(sim.eps1_sins[0])
    return rec, cfg, e1 / (1.0 + e1)


@pytest.mark.parametrize("seed", [1, 2, 3, 6])
def test_four_decimals_covered_within_3_sigma_with_the_step_named(seed):
    rec, cfg, truth = _coarse(seed, 4)
    ver = rsf.judge_record(rec, 1.0, cfg)
    assert ver.status == "ok", ver.reason
    assert abs(ver.estimate - truth) < 3.0 * ver.sigma, (seed, ver.sigma_parts)
    assert ver.sigma_parts["quantization"] > 0.0
    assert any("sins_increment column is written to a step of 1e-04 rad (4 decimals)" in n
               for n in ver.notes), ver.notes


def test_without_the_quantization_part_four_decimals_are_wrong_by_more_than_3_sigma():
    """The power: the same 4-decimal record judged by σ without its rounding (a model
    that leaves the resolution out) is valid and off by more than 3 σ."""
    rec, cfg, truth = _coarse(6, 4)
    res = rsf.calibrate(rec, 1.0)
    u = rsf.eps1_uncertainty(res, cfg)
    assert u.valid and "quantization" not in u.parts
    assert abs(u.mean - truth) > 3.0 * u.std
    with_it = rsf.eps1_uncertainty(res, cfg, resolution=rec.resolution)
    assert abs(with_it.mean - truth) < 3.0 * with_it.std


def test_the_quantization_part_has_its_closed_form():
    """A steady increment ω dt rounded to q with white noise N_S √dt a sample: the SINS
    part is (q/√12) √(ρ² N² + (1 − ρ²) N) / (N ω dt), ρ = exp(−2π² N_S² dt / q²)."""
    rec, cfg, _ = _coarse(1, 4)
    res = rsf.calibrate(rec, 1.0)
    q = 1e-4
    u = rsf.eps1_uncertainty(res, cfg, resolution={"sins_increment": q})
    keep = ~np.asarray(res.reversal, bool)
    n = float(np.sum(res.samples[keep]))
    turn = float(np.sum(np.asarray(res.abs_rate)[keep] * res.samples[keep] * res.dt))
    rho = math.exp(-2 * math.pi**2 * cfg.sins.arw**2 * res.dt / q**2)
    assert rho == pytest.approx(rounding_correlation(q, cfg.sins.arw * math.sqrt(res.dt)))
    expected = q / math.sqrt(12) * math.sqrt(rho**2 * n**2 + (1 - rho**2) * n) / turn
    assert u.parts["quantization"] == pytest.approx(expected, rel=1e-9)
    assert u.std == pytest.approx(math.sqrt(sum(x * x for x in u.parts.values())), rel=1e-12)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_a_65536_count_encoder_record_at_5_decimals_is_covered(seed):
    """At 5 decimals the SINS increment's noise (N_S √dt, 0.44 of a step) dithers the
    rounding: a small part, and the record covered within 3 σ."""
    rec, cfg, truth = _coarse(seed, 5, encoder=True)
    assert rec.resolution["sins_increment"] == pytest.approx(1e-5, rel=1e-9)
    ver = rsf.judge_record(rec, 1.0, cfg)
    assert ver.status == "ok", ver.reason
    assert abs(ver.estimate - truth) < 3.0 * ver.sigma, (seed, ver.sigma_parts)
    assert 0.0 < ver.sigma_parts["quantization"] < 0.1 * ver.sigma


def test_a_full_precision_record_has_no_quantization_part():
    sim = rsf.simulate_flight(rsf.SimulationConfig(duration=5.0), seed=1)
    ver = rsf.judge_record(rsf.record_from_simulation(sim), 1.0)
    assert "quantization" not in ver.sigma_parts


@pytest.mark.parametrize("resolution, exc, words", [
    ({"sins": 1e-4}, ValueError, "unknown column 'sins'"),
    ({"sins_increment": -1e-4}, ValueError, "resolution['sins_increment']"),
    ([1e-4], TypeError, "resolution must be a mapping")])
def test_bad_resolution_is_named(resolution, exc, words):
    sim = rsf.simulate_flight(rsf.SimulationConfig(duration=5.0), seed=1)
    res = rsf.calibrate(rsf.record_from_simulation(sim), 1.0)
    with pytest.raises(exc, match=None) as err:
        rsf.eps1_uncertainty(res, resolution=resolution)
    assert words in str(err.value)
