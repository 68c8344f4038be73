"""gyrolib.quote, the one formatter of a claim's numbers: its declared precision checked
against the value (parsed back, within half a unit of the last digit shown) over many
magnitudes, and its tags (escaped, refused for an unknown quantity or form)."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from gyrolib import quote

_SUP = str.maketrans("⁻⁰¹²³⁴⁵⁶⁷⁸⁹", "-0123456789")


def _parse(text: str) -> float:
    mant, _, exp = text.partition("·10")
    return float(mant) * (10.0 ** int(exp.translate(_SUP)) if exp else 1.0)


def test_number_keeps_three_significant_digits_four_from_1000_up():
    rng = np.random.default_rng(48)
    for x in 10.0 ** rng.uniform(-12, 12, 2000) * rng.choice([-1.0, 1.0], 2000):
        text = quote.number(x)
        got = _parse(text)
        e = math.floor(math.log10(abs(x)))
        digits = 4 if 3 <= e < 5 else 3
        assert abs(got - x) <= 0.5 * 10.0 ** (e - digits + 1) * (1 + 1e-9), (x, text)
        assert "e" not in text, text                     # never Python's exponent form
        if -2 <= e < 4:                                   # well inside [10⁻³, 10⁵)
            assert "·10" not in text, text
        elif e < -4 or e > 5:
            assert "·10" in text, text


def test_factor_margin_and_number_are_one_rule():
    for x in (1.204171866918332, 9.3502924663002, 0.15197169078683057, 2556.94, 7.3e-5):
        assert quote.factor(x) == quote.margin(x) == quote.number(x)
    assert quote.factor(9.3502924663002) == "9.35" != f"{9.3502924663002:.2g}"


@pytest.mark.parametrize(("share", "text"), [
    ((0.0, 0.0, 0.0566), "0 % of the box, 0–6 %"),
    ((0.03125, 0.0086, 0.107), "3 % of the box, 0.9–11 %"),
    ((1.0, 0.943, 1.0), "100 % of the box, 94–100 %"),
])
def test_share_is_whole_percent_with_its_interval(share, text):
    assert quote.share(*share) == text


def test_tag_escapes_and_refuses_what_it_does_not_know():
    t = quote.tag("a < b & c", 'x"y', "margin", html=True)
    assert t == '<span data-claim="x&quot;y" data-quantity="margin">a &lt; b &amp; c</span>'
    assert re.sub(r"<[^>]+>", "", t) == "a &lt; b &amp; c"
    assert quote.tag("1.2", None, "threshold", "gc.sigma1_sq", form="factor", html=True) == "1.2"
    with pytest.raises(ValueError, match="quantity must be one of"):
        quote.tag("1", "c", "size")
    with pytest.raises(ValueError, match="form must be one of"):
        quote.tag("1", "c", "threshold", form="ratio")
