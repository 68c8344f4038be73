"""One formatter for every number the book quotes of a claim: its thresholds, its share of
the box and its margin.

Every place that quotes one of these (the ledger, the chapters, the command line, a figure's
legend) formats it here, so that a number reads the same wherever it appears.  The declared
precision, one rule per quantity:

* a **threshold** as a factor of the reference, and a threshold's value, and a **margin**:
  three significant digits (four from 1000 up), ``m·10ⁿ`` with two decimals outside
  [10⁻³, 10⁵), trailing zeros dropped (:func:`number`, :func:`factor`);
* a **share** of the box: whole per cent (one significant digit under 1 %, so that a share
  that is not zero never reads "0"), with its 95 % interval in the same form, as
  ``"3 % of the box, 1–11 %"`` (:func:`percent`, :func:`share`).

For a web page each number is wrapped in a tag that names its claim, its input and its
quantity, ``<span data-claim="gc.faster_percent" data-input="gc.sigma1_sq"
data-quantity="threshold" data-form="factor">1.2</span>``, so that a test of the built book
can find every quoted form of it (:func:`tag`); in plain text (the command line, a figure's
legend) the same digits carry no tag.  ``data-form`` tells a threshold's factor of the
reference (``"factor"``) from its value in the input's unit (``"value"``).

This module is a leaf: it imports nothing of gyrolib, so that every layer may use it.

Examples
--------
>>> number(9.3502924663002), number(2.0880126953125e-4), number(2556.6), number(0.0)
('9.35', '2.09·10⁻⁴', '2557', '0')
>>> share(0.03125, 0.0086, 0.107)
'3 % of the box, 0.9–11 %'
>>> tag(factor(1.204171866918332), "gc.faster_percent", "threshold", "gc.sigma1_sq",
...     form="factor", html=True)
'<span data-claim="gc.faster_percent" data-input="gc.sigma1_sq" data-quantity="threshold" \
data-form="factor">1.2</span>'
>>> tag("1.2", "gc.faster_percent", "threshold", "gc.sigma1_sq", form="factor")
'1.2'
"""

from __future__ import annotations

import html as _html
import math
from typing import Final

__all__ = ["FORMS", "QUANTITIES", "factor", "margin", "number", "percent", "share", "tag"]

#: What a tagged number is (``data-quantity``).
QUANTITIES: Final[tuple[str, ...]] = ("threshold", "share", "margin")
#: How a threshold is quoted (``data-form``): as a factor of the reference or as a value.
FORMS: Final[tuple[str, ...]] = ("factor", "value", "")

_SUPERSCRIPTS: Final = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def number(x: float) -> str:
    """``x`` at the declared precision: three significant digits (four from 1000 up),
    ``m·10ⁿ`` with two decimals outside [10⁻³, 10⁵); ``0``, ``inf`` and ``nan`` as ``%g``.

    Examples
    --------
    >>> number(1.739154398731837e-05), number(0.31774241737030234), number(13309.4)
    ('1.74·10⁻⁵', '0.318', '13310')
    >>> number(-12.34), number(9.996e-6)
    ('-12.3', '1.00·10⁻⁵')
    """
    x = float(x)
    if x == 0.0 or not math.isfinite(x):
        return f"{x:g}"
    e = math.floor(math.log10(abs(x)))
    if -3 <= e < 5:
        # from 1000 up: four significant digits, never an exponent (13309.4 → 13310)
        return f"{float(f'{x:.4g}'):.0f}" if e >= 3 else f"{x:.3g}"
    m = x / 10.0**e
    if round(abs(m), 2) >= 10.0:
        m, e = m / 10.0, e + 1
    return f"{m:.2f}·10" + str(e).translate(_SUPERSCRIPTS)


def factor(x: float) -> str:
    """A threshold as a factor of the reference, at the declared precision (:func:`number`).

    >>> factor(1.204171866918332), factor(9.3502924663002), factor(0.15197169078683057)
    ('1.2', '9.35', '0.152')
    """
    return number(x)


def margin(x: float) -> str:
    """A claim's margin at the declared precision (:func:`number`).

    >>> margin(-12.345)
    '-12.3'
    """
    return number(x)


def percent(x: float) -> str:
    """A share (0–1) in per cent as the book quotes it: whole per cent, except that a share
    that is not zero but under 1 % keeps one significant digit, so that it never reads "0".
    Below 10⁻¹² (a Wilson interval's lower end at no point, 0 but for rounding) it is 0.

    Examples
    --------
    >>> percent(0.0), percent(0.0038), percent(0.0566), percent(0.59375), percent(1.0)
    ('0', '0.4', '6', '59', '100')
    >>> percent(8.673617379884035e-19)
    '0'
    """
    x = 100.0 * float(x)
    if abs(x) < 1e-10:
        return "0"
    if abs(x) < 0.95:
        return f"{x:.1g}"
    return f"{x:.0f}"


def share(value: float, lo: float, hi: float) -> str:
    """The share of the box where a claim holds and its 95 % interval, the one form every
    page, the ledger and the command line quote: ``"62 % of the box, 50–73 %"``.

    >>> share(0.0, 0.0, 0.0566)
    '0 % of the box, 0–6 %'
    """
    return f"{percent(value)} % of the box, {percent(lo)}–{percent(hi)} %"


def tag(text: str, claim: str | None, quantity: str, input: str = "", *, form: str = "",
        html: bool = False) -> str:
    """``text`` (a number formatted here) as a page quotes it: wrapped in a ``<span>`` that
    names its claim, input, quantity and form when ``html`` and ``claim`` are given, else as
    it is (plain text: the command line, a legend).

    Parameters
    ----------
    text : str
        The formatted number (with its unit, if any).
    claim : str or None
        The claim's ledger id (``None``: nothing to tag).
    quantity : str
        One of :data:`QUANTITIES`.
    input : str, optional
        The row of the table of inputs a threshold belongs to (empty for a share or margin).
    form : str, optional
        One of :data:`FORMS`: ``"factor"`` or ``"value"`` for a threshold.
    html : bool, default False
        Whether to tag (Markdown with inline HTML, for a page).

    Examples
    --------
    >>> tag("3 % of the box, 1–11 %", "gc.time_to_sigma_c", "share", html=True)
    '<span data-claim="gc.time_to_sigma_c" data-quantity="share">3 % of the box, 1–11 %</span>'
    >>> tag("1", "x", "size")
    Traceback (most recent call last):
    ...
    ValueError: quantity must be one of ('threshold', 'share', 'margin'); got 'size'
    """
    if quantity not in QUANTITIES:
        raise ValueError(f"quantity must be one of {QUANTITIES}; got {quantity!r}")
    if form not in FORMS:
        raise ValueError(f"form must be one of {FORMS}; got {form!r}")
    if not html or not claim:
        return text
    attrs = [("data-claim", claim)]
    if input:
        attrs.append(("data-input", input))
    attrs.append(("data-quantity", quantity))
    if form:
        attrs.append(("data-form", form))
    a = " ".join(f'{k}="{_html.escape(v, quote=True)}"' for k, v in attrs)
    return f"<span {a}>{_html.escape(text, quote=False)}</span>"
