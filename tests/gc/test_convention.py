"""The inclinometer convention (:mod:`gyrolib.gc.logs.convention`): the mapping's algebra, and the
Monte Carlo of a wrongly wired pair against the shift Eq. (5) predicts from the true tilts."""

from __future__ import annotations

import itertools
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from gyrolib import gc

ALL = [f"{sa}{a},{sb}{b}" for (a, b) in (("y", "z"), ("z", "y"))
       for sa, sb in itertools.product(("", "-"), repeat=2)]


@pytest.mark.parametrize("text", ALL)
def test_mapping_round_trip_and_inverse(text):
    m = gc.InclinometerMapping.parse(text)
    assert str(m) == text and str(gc.InclinometerMapping.parse(f" {text} ")) == text
    rng = np.random.default_rng(0)
    rec = gc.GCRecord(t=np.arange(1, 6) * 1e-3, angle_sensor=rng.standard_normal(5),
                      inclinometer_y=rng.standard_normal(5),
                      inclinometer_z=rng.standard_normal(5))
    back = m.inverse().apply(m.apply(rec))
    np.testing.assert_allclose(back.inclinometer_y, rec.inclinometer_y, rtol=1e-15, atol=0)
    np.testing.assert_allclose(back.inclinometer_z, rec.inclinometer_z, rtol=1e-15, atol=0)
    # the tilts the filter sees are what apply() does to g·tilt columns
    d, g = 1e-3, -2e-3
    tilted = gc.GCRecord(t=[1e-3], angle_sensor=[0.0], inclinometer_y=[d],
                         inclinometer_z=[g])
    seen = m.apply(tilted)
    assert m.seen_tilts(d, g) == (float(seen.inclinometer_y[0]),
                                  float(seen.inclinometer_z[0]))


@pytest.fixture(scope="module")
def study():
    return gc.convention_study(wiring="z,y", t_end=20.0, seeds=[101, 102, 103])


def test_swap_shift_is_eq5_prediction(study):
    """The estimate moves by Ω_v (c̄ (γ − δ) − s̄ (δ − γ)) — the vertical-rate torque of
    Eq. (5) attributed to the wrong tilt — to 1 %, and the diagnostics do not notice."""
    np.testing.assert_allclose(study.shift, study.predicted_shift, rtol=0.01)
    assert study.valid_wrong.all()
    s = study.summary()
    assert s["shift_over_prediction"] == pytest.approx(1.0, abs=0.01)
    # the estimate as logged stays within 3σ of the truth (the study's own control)
    assert np.all(np.abs(study.z_right) < 3.0)


def test_both_signs_flipped_is_invisible_too():
    """"-y,-z" keeps N1 common to both channels (it flips with them): invisible.  The shift
    has the sign of the prediction 2 Ω_v γ c̄ but only part of its size: flipping both signs
    flips the tilts' common mode too, which the filter shares between the tilts and the
    vibration N1 (a swap leaves the common mode alone, hence its exact prediction)."""
    st = gc.convention_study(wiring="-y,-z", t_end=20.0, seeds=[104, 105])
    ratio = st.shift / st.predicted_shift
    assert np.all((ratio > 0.5) & (ratio < 1.0))
    assert st.valid_wrong.all()


def test_single_sign_flip_is_seen():
    """Power: one flipped sign makes N1 disagree between the channels, and the run is
    invalid (lost lock) on every seed."""
    st = gc.convention_study(wiring="-y,z", t_end=20.0, seeds=[106, 107])
    assert not st.valid_wrong.any() and st.valid_right.all()


def test_executor_gives_the_same_study(study):
    with ThreadPoolExecutor(max_workers=2) as ex:
        again = gc.convention_study(wiring="z,y", t_end=20.0, seeds=[101, 102, 103],
                                    executor=ex)
    np.testing.assert_allclose(again.est_wrong, study.est_wrong, rtol=1e-12)
    np.testing.assert_allclose(again.std_right, study.std_right, rtol=1e-12)
    assert (again.seeds == study.seeds).all()


def test_plot(study):
    import matplotlib.pyplot as plt

    fig = gc.plot_convention_study(study)
    assert len(fig.axes) == 2
    plt.close(fig)
