"""How the chapters put computed numbers and tables into the prose.

One place for the formatting every chapter needs, so that a number reads the same wherever it
appears: scientific notation with superscript exponents (``sci``), thousands grouped by a thin
space (``grouped``), a difference at the level of rounding cited under a declared bound
(``below``), small Markdown tables that a notebook displays as tables
(``markdown_table``), and a ``gluer`` that hands formatted numbers to myst-nb's ``glue``.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from typing import Any

from gyrolib import _validation as v
from gyrolib._page_figures import PNG_KEY, page_record

__all__ = ["MarkdownText", "below", "format_number", "gluer", "grouped", "hidpi_figures",
           "markdown_table", "page_png", "sci"]

_SUPERSCRIPTS = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")

Formatter = str | Callable[[float], str]


def _real(name: str, x: object) -> float:
    """A finite float from a number, numpy scalar or 0-d array (the chapters pass all three)."""
    if not isinstance(x, (str, bytes, bool)) and hasattr(x, "__float__"):
        x = float(x)
    return v.check_real(name, x)


def sci(x: float, digits: int = 3) -> str:
    """``x`` as ``m·10ⁿ`` with ``digits`` significant digits: ``sci(1.704e-4) == '1.70·10⁻⁴'``."""
    x = _real("x", x)
    digits = v.check_int("digits", digits, 1)
    mantissa, exponent = f"{x:.{digits - 1}e}".split("e")
    return f"{mantissa}·10{str(int(exponent)).translate(_SUPERSCRIPTS)}"


def below(x: float, bound: float, what: str = "x") -> str:
    """``x`` cited under a declared ``bound``: ``'below 10⁻¹⁴'``; a ``ValueError`` naming
    ``what`` unless ``|x| < bound``.

    For differences at the level of floating-point rounding (two implementations, two
    integrators, a stored result computed again): their digits depend on the CPU's vector
    width and the order of sums, so the same commit prints 1.4·10⁻¹⁵ on one machine and
    1.6·10⁻¹⁵ on another.  The chapter states the precision it vouches for, the same on
    every machine, and its build fails loudly where the difference reaches it.

    Examples
    --------
    >>> below(1.4e-15, 1e-14)
    'below 10⁻¹⁴'
    >>> below(0.0, 2e-12)
    'below 2·10⁻¹²'
    >>> below(3e-9, 1e-12, "the recomputed points' difference")
    Traceback (most recent call last):
    ...
    ValueError: the recomputed points' difference must be below 1e-12; got 3e-09
    """
    v.check_str("what", what)
    x = _real(what, x)
    bound = v.check_positive("bound", bound)
    if not abs(x) < bound:
        raise ValueError(f"{what} must be below {bound:g}; got {x:.3g}")
    mantissa, exponent = f"{bound:.0e}".split("e")
    power = f"10{str(int(exponent)).translate(_SUPERSCRIPTS)}"
    return f"below {power if mantissa == '1' else f'{mantissa}·{power}'}"


def grouped(x: float, digits: int = 4) -> str:
    """``x`` with ``digits`` significant digits, thousands grouped by a thin space:
    ``grouped(13309.4) == '13 310'`` (with a thin space)."""
    x = v.check_real("x", x)
    digits = v.check_int("digits", digits, 1)
    x = float(f"{x:.{digits}g}")
    if abs(x) >= 1000:
        return f"{x:,.0f}".replace(",", "\u2009")
    return f"{x:.{digits}g}"


def format_number(value: float, fmt: Formatter = ".4g") -> str:
    """``value`` formatted by a format spec (e.g. ``".3f"``) or by a function such as
    :func:`sci`.  Numpy scalars are converted to ``float`` first (their repr would otherwise
    leak into format specs)."""
    if callable(fmt):
        return fmt(value)
    v.check_str("fmt", fmt)
    value = _real("value", value)
    return format(value, fmt)


class MarkdownText(str):
    """A string that Jupyter (and so myst-nb) displays as Markdown."""

    def _repr_markdown_(self) -> str:
        return str(self)


def markdown_table(header: Sequence[object], rows: Iterable[Sequence[object]]) -> MarkdownText:
    """A Markdown table from a header and rows (cells are converted with ``str``)."""
    header = [str(c) for c in header]
    if not header:
        raise ValueError("header must name at least one column")
    lines = ["| " + " | ".join(header) + " |", "|" + " --- |" * len(header)]
    for i, row in enumerate(rows):
        cells = [str(c) for c in row]
        if len(cells) != len(header):
            raise ValueError(f"rows[{i}] must have {len(header)} cells; got {len(cells)}")
        lines.append("| " + " | ".join(cells) + " |")
    return MarkdownText("\n".join(lines))


def page_png(fig: Any, **kwargs: Any) -> tuple[str, dict[str, int]] | None:
    """``fig`` as a 2x "retina" PNG (base64) and its width/height metadata, as IPython's
    ``retina_figure``, with the figure's measurement as the page shows it in a text chunk
    (:func:`gyrolib._page_figures.page_record` under ``PNG_KEY``): a test of the built book
    reads it back from every figure on the pages.  ``kwargs`` go to ``print_figure``."""
    from IPython.core.pylabtools import retina_figure
    from matplotlib.figure import Figure

    if not isinstance(fig, Figure):
        raise TypeError(f"fig must be a matplotlib Figure; got {type(fig).__name__}")

    if not fig.axes and not fig.lines:  # as print_figure: an empty figure shows nothing
        return None
    metadata = {**kwargs.pop("metadata", {}), PNG_KEY: page_record(fig)}
    return retina_figure(fig, base64=True, metadata=metadata, **kwargs)


def hidpi_figures() -> bool:
    """Make the notebook output (and glue) matplotlib figures as 2x "retina" PNGs: twice the
    figure's pixels, with a width attribute of half of them, so that a figure is shown at
    two image pixels per CSS pixel or more (sharp on high-density screens and in the PDF).
    Each PNG carries the figure's text measurement (:func:`page_png`).
    Returns whether it could (``False`` outside an IPython kernel, where it does nothing).

    The setting goes to the inline backend's configuration, so a later ``%matplotlib inline``
    keeps it.  :func:`gluer` calls it: every chapter that glues figures makes a gluer.

    >>> hidpi_figures()  # not in a kernel: nothing to set
    False
    """
    try:
        from IPython import get_ipython
    except ImportError:  # pragma: no cover - the book's environment has IPython
        return False
    shell = get_ipython()
    if shell is None or not hasattr(shell, "display_formatter"):
        return False
    from functools import partial

    from IPython.core.pylabtools import select_figure_formats
    from matplotlib.figure import Figure
    from matplotlib_inline.config import InlineBackend

    config = InlineBackend.instance()
    config.figure_formats = {"retina"}
    select_figure_formats(shell, {"retina"}, **config.print_figure_kwargs)
    shell.display_formatter.formatters["image/png"].for_type(
        Figure, partial(page_png, **config.print_figure_kwargs))
    return True


def gluer(prefix: str, default_fmt: Formatter = ".4g") -> Callable[..., None]:
    """A function ``gl(key, value, fmt=default_fmt)`` that glues ``value``, formatted by
    :func:`format_number`, under ``prefix + key`` for the prose (``{glue:text}`prefix_key```).
    Chapters prefix their keys because glue keys are global across the book.  Making a gluer
    also sets the notebook's figures to 2x PNGs (:func:`hidpi_figures`)."""
    v.check_str("prefix", prefix)
    hidpi_figures()

    def gl(key: str, value: float, fmt: Formatter = default_fmt) -> None:
        from myst_nb import glue  # only the chapters need myst-nb

        glue(f"{prefix}{v.check_str('key', key)}", format_number(value, fmt), display=False)

    return gl
