"""Paper GC's ledger items: present, computed from the library, and moving with the
parameters they depend on."""

from dataclasses import replace

import numpy as np
import pytest

from gyrolib.book.ledger import gc
from gyrolib.gc import GyrocompassParams, covariance_analysis
from gyrolib.units import ARCSEC_PAPER

REQUIRED = ("gc.float_rotation_100s", "gc.sigma_gc_100s", "gc.fig2.var_N1", "gc.fig2.var_N3",
            "gc.fig3.drop_2s", "gc.time_to_sigma_c", "gc.faster_percent")


@pytest.fixture(scope="module")
def base():
    return {it.id: it for it in gc.items()}


def test_required_items_present(base):
    assert set(REQUIRED) <= set(base)
    for it in base.values():
        assert it.paper == "GC"
        assert it.chapter in ("chapters/gc_model", "chapters/gc_filter", "chapters/gc_claims")


def test_values_against_the_paper_and_the_library(base):
    # printed: 0.5° (rounded), 1.86e-6 m²/s⁴, 2.35e-15 rad²/s² (shaping-filter variances)
    assert base["gc.float_rotation_100s"].reproduced_value == pytest.approx(0.5, abs=0.01)
    assert base["gc.fig2.var_N1"].reproduced_value == pytest.approx(1.86e-6, rel=1e-9)
    assert base["gc.fig2.var_N3"].reproduced_value == pytest.approx(2.35e-15, rel=1e-9)
    cov = covariance_analysis(GyrocompassParams(), 100.0)
    s100 = cov.std("omega_gc")[-1] / ARCSEC_PAPER
    assert base["gc.sigma_gc_100s"].reproduced_value == pytest.approx(s100, rel=1e-12)
    assert base["gc.time_to_sigma_c"].reproduced_value < 100.0
    assert base["gc.faster_percent"].reproduced_value > 50.0


@pytest.mark.parametrize(
    ("change", "moved"),
    [
        ({"C_as": 8e-13}, ("gc.sigma_gc_100s", "gc.time_to_sigma_c")),
        ({"sigma2_sq": 2 * 2.35e-15}, ("gc.fig2.var_N3", "gc.sigma_gc_100s")),
        ({"sigma1_sq": 2 * 1.86e-6}, ("gc.fig2.var_N1",)),
        ({"H": 0.06}, ("gc.float_rotation_100s", "gc.sigma_gc_100s")),
    ],
)
def test_ledger_moves_when_a_parameter_is_perturbed(base, change, moved):
    new = {it.id: it for it in gc.items(replace(GyrocompassParams(), **change))}
    for key in moved:
        a, b = base[key].reproduced_value, new[key].reproduced_value
        assert not np.isclose(a, b, rtol=1e-6, atol=0.0), key


def test_items_reject_bad_params():
    with pytest.raises(TypeError, match="params"):
        gc.items("baseline")
