"""The resolution of a recorded column (:func:`gyrolib.resolution.column_step`) on records
written to a known number of decimals, counted in a known LSB, or at full precision, and read
back through the reader: the step found is the one written (a closed form), never one the
column does not have."""

from __future__ import annotations

import math

import numpy as np
import pytest

from gyrolib import gc, records, rsf
from gyrolib.resolution import column_step, describe_step, rounding_correlation
from gyrolib.units import ARCSEC_PAPER


@pytest.mark.parametrize("decimals", [1, 3, 4, 5, 7])
def test_a_column_written_to_k_decimals_has_the_step_ten_to_minus_k(decimals):
    rng = np.random.default_rng(decimals)
    x = np.round(rng.uniform(-3.0, 3.0, 5000), decimals)
    assert column_step(x) == pytest.approx(10.0**-decimals, rel=1e-9)


@pytest.mark.parametrize("lsb", [2 * math.pi / 65536, ARCSEC_PAPER, 20 * ARCSEC_PAPER,
                                 0.37e-6, 2.0**-20, 1e-6])
def test_a_column_counted_in_lsbs_has_the_lsb_as_its_step(lsb):
    counts = np.random.default_rng(7).integers(-40000, 40000, 3000)
    assert column_step(counts * lsb) == pytest.approx(lsb, rel=1e-9)


@pytest.mark.parametrize("make", [
    lambda rng: rng.standard_normal(5000),                    # full precision
    lambda rng: 1e-5 * rng.standard_normal(5000),
    lambda rng: np.cumsum(0.157 + 1e-6 * rng.standard_normal(5000)),
    lambda rng: np.array([float(f"{x:.10g}") for x in rng.standard_normal(2000)])])
def test_a_column_at_full_or_relative_precision_has_no_step(make):
    """Floats' own precision and ten significant digits (a grid that changes with the
    magnitude): no common step, or one far below what a sensor's noise could notice."""
    x = make(np.random.default_rng(3))
    q = column_step(x)
    assert q == 0.0 or q < 1e-9 * float(np.max(np.abs(x))), q


def test_decimals_converted_by_a_factor_keep_their_grid_scaled():
    """Degrees written to 4 decimals, converted to rad: the step is 1e-4 deg in rad."""
    x = np.round(np.random.default_rng(5).uniform(0, 1, 2000), 4) * math.radians(1.0)
    assert column_step(x) == pytest.approx(math.radians(1e-4), rel=1e-9)


def test_one_value_off_the_grid_is_no_grid():
    """A value off the 1e-4 grid: no grid, or only the finer one its decimals show."""
    x = np.round(np.random.default_rng(1).uniform(0, 1, 1000), 4)
    x[500] += math.pi * 1e-6
    assert column_step(x) == 0.0
    x[500] = 0.5432033
    assert column_step(x) == pytest.approx(1e-7, rel=1e-9)


def test_nan_and_few_values():
    assert column_step([np.nan, np.nan]) == 0.0
    assert column_step([]) == 0.0
    # two values: only the decimals they show; three: also their differences
    assert column_step([0.25, np.nan, 0.5, np.inf]) == pytest.approx(0.01)
    assert column_step([0.0, math.pi / 8, 3 * math.pi / 8]) == pytest.approx(math.pi / 8)
    assert column_step([0.0, math.pi / 8]) == 0.0
    assert column_step([3.0, 5.0, 9.0]) == pytest.approx(1.0)


def test_a_steady_noise_free_signal_is_no_rounding():
    """ω t sampled without noise lies on the grid of its own increment, and a steady
    increment after a leading 0 takes two values: neither is a rounding."""
    t = np.arange(0, 201) * 0.01
    gs = math.radians(900.0) * t
    assert column_step(gs) == 0.0
    assert column_step(np.concatenate([[0.0], np.diff(gs)]) * (1 + 600e-6)) == 0.0


def test_rounding_correlation_closed_form_and_words():
    assert rounding_correlation(1e-4, 0.0) == 1.0
    assert rounding_correlation(0.0, 1.0) == 0.0
    assert rounding_correlation(2.0, 1.0) == pytest.approx(math.exp(-math.pi**2 / 2))
    assert describe_step(1e-4, "rad") == "1e-04 rad (4 decimals)"
    assert describe_step(ARCSEC_PAPER, "rad") == "4.85e-06 rad"


def test_the_reader_keeps_the_step_a_rsf_file_was_written_to(tmp_path):
    """An RSF record written with 4 decimals and read back: both angle columns have the
    step 1e-4 rad; the same record written at full precision has none."""
    sim = rsf.simulate_flight(rsf.SimulationConfig(duration=5.0), seed=2)
    r = rsf.record_from_simulation(sim)
    cols = {"t": r.t, "sins_increment": r.sins_increment, "gs_angle": r.gs_angle}
    coarse = records.read_rsf(records.write_csv(tmp_path / "c.csv", cols,
                                                fmt=["%.2f", "%.4f", "%.4f"]), check=False)
    fine = records.read_rsf(records.write_csv(tmp_path / "f.csv", cols,
                                              fmt=["%.2f", "%.17g", "%.17g"]), check=False)
    # a steady increment shows only the decimals it has (0.1571 or 0.157): <= 1e-3
    assert 1e-4 * (1 - 1e-9) <= coarse.resolution["sins_increment"] <= 1e-3 * (1 + 1e-9)
    assert coarse.resolution["gs_angle"] == pytest.approx(1e-4, rel=1e-9)
    assert fine.resolution == {"sins_increment": 0.0, "gs_angle": 0.0}


def test_the_reader_keeps_the_lsb_of_a_gc_angle_column_in_arcsec(tmp_path):
    """A GC angle column written in whole arcseconds (a units row): after the reader's
    conversion to rad its step is one arcsecond in rad; the inclinometers, written with
    ten significant digits, have none."""
    sim = gc.simulate_record(gc.GyrocompassParams(), 2.0, seed=4)
    r = sim.record
    path = tmp_path / "gc.csv"
    path.write_text("# latitude_deg: 53.9\nt,angle_sensor,inclinometer_y,inclinometer_z\n"
                    "s,arcsec,m/s^2,m/s^2\n" + "".join(
                        f"{t:.3f},{round(a / ARCSEC_PAPER):d},{y:.10g},{z:.10g}\n"
                        for t, a, y, z in zip(r.t, r.angle_sensor, r.inclinometer_y,
                                              r.inclinometer_z, strict=True)))
    rec = records.read_gc(path, check=False)
    from gyrolib.units import to_si
    assert rec.resolution["angle_sensor"] == pytest.approx(float(to_si(1.0, "arcsec")),
                                                           rel=1e-9)
    assert rec.resolution["inclinometer_y"] == 0.0
    assert rec.resolution["inclinometer_z"] == 0.0
