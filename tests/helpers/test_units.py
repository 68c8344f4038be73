"""gyrolib.units against exact definitions and the papers' printed conversions."""

import math

import numpy as np
import pytest

from gyrolib import units


def test_arcsec_exact_is_pi_over_648000():
    assert units.ARCSEC == pytest.approx(math.pi / 648000.0, rel=1e-15)
    assert units.to_si(3600.0, "arcsec") == pytest.approx(math.radians(1.0), rel=1e-15)


def test_paper_arcsec_is_the_printed_rounding():
    # Paper GC: "1″ = 0.485·10⁻⁵ rad"; it is 0.04 % larger than the exact arcsecond.
    assert units.ARCSEC_PAPER == 0.485e-5
    assert units.ARCSEC_PAPER / units.ARCSEC - 1.0 == pytest.approx(
        0.485e-5 * 648000.0 / math.pi - 1.0, rel=1e-12)
    assert 0.0 < units.ARCSEC_PAPER / units.ARCSEC - 1.0 < 5e-4  # "0.04 % larger"
    # P(3,3) of paper GC: (180·0.485·10⁻⁵)² rad²
    assert units.to_si(180.0, "arcsec_paper") ** 2 == pytest.approx(7.62129e-7, rel=1e-12)


def test_degree_per_hour_and_second():
    # 1 °/h = 4.8481·10⁻⁶ rad/s (the same number as one arcsecond per second).
    assert units.to_si(1.0, "deg/h") == pytest.approx(4.84813681109536e-06, rel=1e-12)
    assert units.to_si(3600.0, "deg/h") == pytest.approx(units.to_si(1.0, "deg/s"), rel=1e-15)
    assert units.to_si(1.0, "arcsec/s") == pytest.approx(units.to_si(1.0, "deg/h"), rel=1e-15)


def test_ppm_and_g():
    assert units.to_si(600.0, "ppm") == pytest.approx(6e-4, rel=1e-15)
    assert units.to_si(1.0, "g") == 9.80665  # standard gravity, exact by definition


@pytest.mark.parametrize("unit", sorted(units.UNITS))
def test_round_trip_every_unit(unit):
    x = np.array([-2.5, 0.0, 1.0, 123.456])
    np.testing.assert_allclose(units.from_si(units.to_si(x, unit), unit), x, rtol=1e-15)


def test_scalar_in_scalar_out():
    assert isinstance(units.to_si(2, "deg"), float)


def test_unknown_unit_is_a_clear_error():
    with pytest.raises(ValueError, match="unit must be one of"):
        units.to_si(1.0, "furlong/fortnight")
    with pytest.raises(TypeError, match="unit must be a str"):
        units.from_si(1.0, 3)


@pytest.mark.parametrize("bad", ["1.0", True, None, [1, "a"]])
def test_non_numeric_value_is_a_type_error(bad):
    with pytest.raises(TypeError, match="value must be"):
        units.to_si(bad, "deg")
