"""Units and conventions at the door (:mod:`gyrolib.records.plausibility`): no false alarm on
records of the model (several seeds, other parameters), and each common unit mistake named.
The bound on the float's angle is checked against the truth model's own Δβ."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from gyrolib import gc, records, rsf
from gyrolib.records import RecordError
from gyrolib.units import ARCSEC, DEG

P = gc.GyrocompassParams()


def _rec(r: gc.GCRecord, **cols) -> gc.GCRecord:
    d = {"t": r.t, "angle_sensor": r.angle_sensor, "inclinometer_y": r.inclinometer_y,
         "inclinometer_z": r.inclinometer_z}
    d.update(cols)
    return gc.GCRecord(**d)


@pytest.fixture(scope="module")
def sims():
    return [gc.simulate_record(P, 10.0, seed=s) for s in range(300, 306)]


def test_no_false_alarm_on_records_of_the_model(sims):
    """Six seeds, and records with a ten times wider vibration or a noisier angle sensor
    (checked with their own parameters and with the paper's)."""
    for sim in sims:
        records.check_gc(sim.record, P, label="x")
    for change in ({"alpha1": 10 * P.alpha1}, {"C_as": 100 * P.C_as}):
        p = dataclasses.replace(P, **change)
        rec = gc.simulate_record(p, 10.0, seed=310).record
        records.check_gc(rec, p, label="x")
        records.check_gc(rec, P, label="x")


def test_bound_holds_for_the_truth(sims):
    """The float's deviation from the nominal motion in the truth model (Δβ, a state of
    the simulation, not the checked record) stays far inside the bound: below a fifth."""
    for sim in sims:
        dbeta = np.abs(sim.truth[1:, gc.state_index("dbeta")])
        bound = records.angle_bound(P, sim.record.t)
        assert np.all(dbeta < 0.2 * bound)


@pytest.mark.parametrize(("factor", "unit"), [(1 / DEG, "degrees"), (1e3, "milliradians"),
                                              (1 / ARCSEC, "arcseconds")])
def test_angle_units_named(sims, factor, unit):
    r = sims[0].record
    with pytest.raises(RecordError) as info:
        records.check_gc(_rec(r, angle_sensor=r.angle_sensor * factor), P, label="run.csv",
                         rows=(1, r.n))
    e = info.value
    assert e.column == "angle_sensor" and f"read in {unit} it fits" in str(e)
    assert str(e).startswith("run.csv: column 'angle_sensor': ") and "data rows 1–" in str(e)


@pytest.mark.parametrize(("factor", "unit"), [(1e3, "milliseconds"), (1e6, "microseconds")])
def test_time_units_named(sims, factor, unit):
    r = sims[1].record
    with pytest.raises(RecordError) as info:
        records.check_gc(_rec(r, t=r.t * factor), P, label="run.csv")
    assert info.value.column == "t" and f"fit {unit}: read so" in str(info.value)


def test_angle_offset_is_refused_without_a_unit_to_blame(sims):
    """An angle that does not start at the sensor's null (here 0.01 rad): refused, and no unit
    is named because none fits."""
    r = sims[2].record
    with pytest.raises(RecordError) as info:
        records.check_gc(_rec(r, angle_sensor=r.angle_sensor + 0.01), P, label="x")
    msg = str(info.value)
    assert info.value.column == "angle_sensor" and "it fits" not in msg
    assert "expected radians, with t in s since the feedback was switched off" in msg


def test_inclinometers_in_g_and_vertical_axis(sims):
    r = sims[3].record
    with pytest.raises(RecordError, match=r"in g .* instead of m/s²") as info:
        records.check_gc(_rec(r, inclinometer_z=r.inclinometer_z / P.g), P, label="x")
    assert info.value.column == "inclinometer_z"
    with pytest.raises(RecordError, match="the vertical axis") as info:
        records.check_gc(_rec(r, inclinometer_y=r.inclinometer_y + P.g), P, label="x")
    assert info.value.column == "inclinometer_y"
    # a sensor really this quiet passes once its intensity is given
    quiet = dataclasses.replace(P, C_incl_y=P.C_incl_y / P.g**2, C_incl_z=P.C_incl_z / P.g**2,
                                sigma1_sq=P.sigma1_sq / P.g**2)
    records.check_gc(_rec(r, inclinometer_y=r.inclinometer_y / P.g,
                          inclinometer_z=r.inclinometer_z / P.g), quiet, label="x")


@pytest.fixture(scope="module")
def flight():
    cfg = rsf.SimulationConfig(duration=5.0, sample_rate=1000.0)
    f = rsf.simulate_flight(cfg, seed=77)
    return rsf.record_from_simulation(f), rsf.record_from_simulation(f, encoder=True)


def test_rsf_good_records_pass(flight):
    plain, enc = flight
    records.check_rsf(plain, label="x")
    records.check_rsf(enc, label="x")


@pytest.mark.parametrize(("change", "column", "hint"), [
    (lambda r: {"sins_increment": -r.sins_increment}, "sins_increment", "opposite"),
    (lambda r: {"sins_increment": np.degrees(r.sins_increment)}, "sins_increment",
     "in degrees"),
    (lambda r: {"gs_angle": np.degrees(r.gs_angle)}, "gs_angle", "in degrees"),
    (lambda r: {"gs_angle": r.gs_angle / (2 * np.pi)}, "gs_angle", "revolutions"),
    (lambda r: {"sins_increment": np.nancumsum(r.sins_increment)}, "sins_increment",
     "accumulated"),
    (lambda r: {"sins_increment": 1.05 * r.sins_increment}, "sins_increment",
     "expected both in rad"),
    (lambda r: {"t": np.round(r.t * 1000)}, "t", "milliseconds"),
])
def test_rsf_mistakes_named(flight, change, column, hint):
    plain, _ = flight
    d = {"t": plain.t, "sins_increment": plain.sins_increment, "gs_angle": plain.gs_angle}
    d.update(change(plain))
    with pytest.raises(RecordError) as info:
        records.check_rsf(rsf.RSFRecord(**d), label="f.csv")
    assert info.value.column == column and hint in str(info.value)


def test_rsf_one_percent_is_the_line(flight):
    """Power of the agreement check at its stated limit: 0.5 % passes, 2 % does not."""
    plain, _ = flight
    for k, ok in ((1.005, True), (1.02, False)):
        rec = rsf.RSFRecord(t=plain.t, sins_increment=k * plain.sins_increment,
                            gs_angle=plain.gs_angle)
        if ok:
            records.check_rsf(rec, label="x")
        else:
            with pytest.raises(RecordError):
                records.check_rsf(rec, label="x")


def test_a_packet_counter_as_time_is_not_taken_for_milliseconds():
    """A 256 Hz log whose ``t`` is the packet counter (0, 1, 2, … one a sample): refused at
    the door, and no hint names ``--time-unit ms``, which would read the counter as a 1 kHz
    clock, 3.9 times too fast (the float's motion does not fit it); the same log at 1 kHz,
    where the counter is the time in ms, gets that hint (power)."""
    for rate, want in ((256.0, None), (1000.0, "--time-unit ms")):
        p = dataclasses.replace(P, dt=1.0 / rate)
        r = gc.simulate_record(p, 20.0, seed=4701).record
        counter = gc.GCRecord(t=np.round(r.t * rate), angle_sensor=r.angle_sensor,
                              inclinometer_y=r.inclinometer_y, inclinometer_z=r.inclinometer_z)
        with pytest.raises(RecordError) as exc:
            records.check_gc(counter, p, label="counter.csv")
        assert exc.value.column in ("t", "angle_sensor")
        assert exc.value.hint == want, (rate, exc.value.hint, str(exc.value))
