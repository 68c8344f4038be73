"""Allan deviation of a paper-GC record (:func:`gyrolib.gc.allan_deviation`): white noise
against the closed forms of the Allan variance, the vibration's model curve against a
simulated record, and a record with another vibration spectrum that the paper's curve does
not match (power)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import scipy.stats

from gyrolib import gc

P = gc.GyrocompassParams()


def _agree(series, reference, confidence: float = 0.999) -> np.ndarray:
    """Whether ``reference`` lies in the two-sided ``confidence`` interval of each estimate:
    adev² · edf / reference² is χ²(edf) (edf from Greenhall's algorithm for the series'
    noise type)."""
    e = series.edf
    lo = series.adev * np.sqrt(e / scipy.stats.chi2.ppf(0.5 + confidence / 2, e))
    hi = series.adev * np.sqrt(e / scipy.stats.chi2.ppf(0.5 - confidence / 2, e))
    return (lo <= reference) & (reference <= hi)


def test_white_noise_closed_forms():
    """White angle noise of variance R is white phase noise: σ(τ) = √(3R)/τ for the rate;
    white inclinometer noise of variance C/Δt averages as √(C/τ).  Records built here from
    numpy's generator, not by the simulator."""
    rng = np.random.default_rng(11)
    n = 60000
    t = np.arange(1, n + 1) * P.dt
    r_as, c_in = 2e-10, 5e-15
    beta_n = gc.nominal_motion_aperiodic(P, t).beta
    rec = gc.GCRecord(t=t, angle_sensor=beta_n + np.sqrt(r_as) * rng.standard_normal(n),
                      inclinometer_y=np.sqrt(c_in / P.dt) * rng.standard_normal(n),
                      inclinometer_z=np.sqrt(c_in / P.dt) * rng.standard_normal(n))
    ad = gc.allan_deviation(rec, P)
    a = ad.get("angle_sensor")
    assert np.all(_agree(a, np.sqrt(3 * r_as) / a.tau))
    for name in ("inclinometer_y", "inclinometer_z"):
        s = ad.get(name)
        assert np.all(_agree(s, np.sqrt(c_in / s.tau)))
    assert ad.rows == n and ad.dt == pytest.approx(P.dt) and not ad.filled.any()


@pytest.fixture(scope="module")
def records():
    wide = dataclasses.replace(P, alpha1=10 * P.alpha1)
    return (gc.simulate_record(P, 40.0, seed=77).record,
            gc.simulate_record(wide, 40.0, seed=78).record, wide)


def test_vibration_model_matches_simulated_record(records):
    """The inclinometers of a record of the truth model (Eq. (6)'s N1 integrated on its own
    fine grid) against the model curve √(C/τ + σ²_N1(τ)) from the PSD of Eq. (6)."""
    rec, _, _ = records
    ad = gc.allan_deviation(rec, P)
    for name in ("inclinometer_y", "inclinometer_z"):
        s = ad.get(name)
        assert np.all(_agree(s, s.model)), name
    a = ad.get("angle_sensor")
    assert np.all(_agree(a, a.model))


def test_wider_vibration_is_seen(records):
    """Power: a record whose α1 is ten times the paper's is far from the paper's curve (its
    N1 random walk is √10 stronger) and on the curve of its own parameters."""
    _, rec_w, wide = records
    paper = gc.allan_deviation(rec_w, P).get("inclinometer_y")
    own = gc.allan_deviation(rec_w, wide).get("inclinometer_y")
    use = (paper.tau >= 0.01) & (paper.tau <= 4.0)
    assert np.all(paper.adev[use] / paper.model[use] > 2.0)
    assert np.all(_agree(own, own.model))


def test_longest_stretch_and_filled_cells(records):
    """A gap splits the record: the longest stretch is used; NaN cells are interpolated and
    counted."""
    rec, _, _ = records
    keep = ~((rec.t > 10.0) & (rec.t <= 11.0))
    a = np.array(rec.angle_sensor)
    a[[20000, 20001, 30000]] = np.nan
    cut = gc.GCRecord(t=rec.t[keep], angle_sensor=a[keep],
                      inclinometer_y=rec.inclinometer_y[keep],
                      inclinometer_z=rec.inclinometer_z[keep])
    ad = gc.allan_deviation(cut, P)
    assert ad.t_start == pytest.approx(11.001) and ad.t_end == pytest.approx(40.0)
    assert ad.filled.tolist() == [3, 0, 0]


def test_plot_has_two_panels(records):
    import matplotlib.pyplot as plt

    fig = gc.plot_allan(gc.allan_deviation(records[0], P), title="x")
    assert len(fig.axes) == 2 and fig.axes[0].get_xscale() == "log"
    plt.close(fig)
