"""A GC record whose angle column is counted in coarse LSBs: the filter and the noise fit
carry the rounding, ``LSB²/12`` a sample, in the angle sensor's measurement noise.  Judged
against the simulation's truth (ω_gc, C_as) and the closed form of the rounding's variance;
the same record with the rounding left out (the step not detected) fails the same checks."""

from __future__ import annotations

import numpy as np
import pytest

import gyrolib.gc.logs.record as record_module
from gyrolib import gc
from gyrolib.units import ARCSEC_PAPER

#: An angle sensor counted in 5″ steps: its rounding, (5″)²/12, is about a fifth of the
#: paper's angle-sensor noise variance at 1 kHz.
LSB = 5.0 * ARCSEC_PAPER


@pytest.fixture(scope="module")
def coarse():
    p = gc.GyrocompassParams()
    sim = gc.simulate_record(p, 20.0, seed=1)
    r = sim.record
    rec = gc.GCRecord(t=r.t, angle_sensor=np.round(r.angle_sensor / LSB) * LSB,
                      inclinometer_y=r.inclinometer_y, inclinometer_z=r.inclinometer_z)
    return p, sim, rec


def _blind(monkeypatch, rec):
    """The same record, with the step detection switched off (a record object of its own,
    so that no cached resolution is reused)."""
    monkeypatch.setattr(record_module, "column_step", lambda values: 0.0)
    return gc.GCRecord(t=rec.t, angle_sensor=rec.angle_sensor,
                       inclinometer_y=rec.inclinometer_y, inclinometer_z=rec.inclinometer_z)


def test_the_angle_lsb_is_found_and_reported(coarse):
    p, _, rec = coarse
    assert rec.resolution["angle_sensor"] == pytest.approx(LSB, rel=1e-9)
    res = gc.calibrate(rec, p)
    assert res.measurement_steps[0] == pytest.approx(LSB, rel=1e-9)
    q = res.summary()["quantization"]
    r11 = p.C_as / p.dt
    assert list(q) == ["angle_sensor"]
    assert q["angle_sensor"]["variance"] == pytest.approx(LSB**2 / 12.0, rel=1e-9)
    assert q["angle_sensor"]["share_of_noise"] == pytest.approx(
        LSB**2 / 12.0 / (r11 + LSB**2 / 12.0), rel=1e-9)


def test_a_full_precision_record_reports_no_quantization(coarse):
    p, sim, _ = coarse
    res = gc.calibrate(sim.record, p)
    assert not np.any(res.measurement_steps > 0.0)
    assert "quantization" not in res.summary()


def test_the_filter_carries_the_rounding_and_covers_the_truth(coarse, monkeypatch):
    """With the rounding carried, the angle sensor's mean NIS is in its band and ω̂_gc is
    within 3 σ of the truth; without it, the NIS is about 1 + LSB²/(12 R₁₁) and the run is
    refused."""
    p, sim, rec = coarse
    truth = float(sim.truth[-1, 3])
    res = gc.calibrate(rec, p)
    assert res.valid, res.reason
    assert abs(res.omega_gc - truth) < 3.0 * res.omega_gc_std
    lo, hi = res.summary()["nis_band"]["angle_sensor"]
    assert lo <= res.nis_mean[0] <= hi
    blind = gc.calibrate(_blind(monkeypatch, rec), p)
    expected = 1.0 + LSB**2 / 12.0 / (p.C_as / p.dt)
    assert blind.nis_mean[0] == pytest.approx(expected, rel=0.05)
    assert not blind.valid and "angle_sensor" in blind.reason


def test_the_noise_fit_finds_the_sensor_s_own_intensity(coarse, monkeypatch):
    """C_as fitted with the rounding carried is within 3 SE of the simulated C_as; left
    out, the fit takes the rounding for sensor noise, C_as·(1 + LSB²/(12 C_as/dt)), and
    misses by far more."""
    p, _, rec = coarse
    f = gc.fit_noise(rec, p, fit=("C_as",))
    assert abs(f.value("C_as") - p.C_as) < 3.0 * f.std_error("C_as")
    blind = gc.fit_noise(_blind(monkeypatch, rec), p, fit=("C_as",))
    inflated = p.C_as + LSB**2 / 12.0 * p.dt
    assert blind.value("C_as") == pytest.approx(inflated, rel=0.05)
    assert (blind.value("C_as") - p.C_as) > 10.0 * blind.std_error("C_as")


def test_a_record_read_in_chunks_carries_the_first_chunk_s_step(coarse):
    """A record fed as chunks (as ``GCChunks`` reads a file) takes the step from its first
    chunk: the same steps and the same ω̂_gc as the record in memory."""
    p, _, rec = coarse
    half = rec.n // 2
    chunks = [gc.GCRecord(t=rec.t[sl], angle_sensor=rec.angle_sensor[sl],
                          inclinometer_y=rec.inclinometer_y[sl],
                          inclinometer_z=rec.inclinometer_z[sl])
              for sl in (slice(0, half), slice(half, None))]
    whole, parts = gc.calibrate(rec, p), gc.calibrate(iter(chunks), p)
    np.testing.assert_allclose(parts.measurement_steps, whole.measurement_steps, rtol=1e-9)
    assert parts.omega_gc == pytest.approx(whole.omega_gc, rel=1e-9)


def test_the_verdict_notes_name_the_step_and_warn_when_it_is_not_white(coarse):
    """The note gives the step and the rounding's share of the noise (closed form); a step
    above twice the noise's σ (20″ against 2.9″) is said not to be white."""
    from gyrolib.gc.logs.judgement import quantization_notes

    p, _, rec = coarse
    r11 = p.C_as / p.dt
    (note,) = quantization_notes(gc.calibrate(rec, p))
    share = 100 * LSB**2 / 12 / (r11 + LSB**2 / 12)
    assert note.startswith(f"angle_sensor is recorded in steps of {LSB:.4g} rad")
    assert f"is {share:.3g} % of that sensor's measurement noise" in note
    assert "not white" not in note
    big = 4 * LSB
    coarser = gc.GCRecord(t=rec.t, angle_sensor=np.round(rec.angle_sensor / big) * big,
                          inclinometer_y=rec.inclinometer_y, inclinometer_z=rec.inclinometer_z)
    assert coarser.resolution["angle_sensor"] == pytest.approx(big, rel=1e-9)
    (note,) = quantization_notes(gc.calibrate(coarser, p))
    assert "the step exceeds twice the noise's standard deviation" in note
