"""How the figures of the ``plots`` modules are sized for the book's page.

The book shows a figure at ``width_in × dpi`` CSS pixels, shrunk to the column when wider
(the chapters output 2x "retina" PNGs: twice the pixels, the width attribute half of them, see
:func:`gyrolib.book.report.hidpi_figures`).  A legend of ``f`` points then shows at
``f × display_scale(fig)`` points, so on a figure wider than the column a legend must be drawn
larger to be readable.  :func:`for_the_page` does that for every legend of a figure, and caps a
figure's width so that its other text does not shrink much below its size either; it changes
sizes only, never what a figure shows.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any

#: CSS pixels per inch, and the width of the book's output column at a 1280-px window (the
#: figures of the chapters were measured at 672 CSS px by ``tests/test_browser.py``).
CSS_DPI = 96.0
COLUMN_PX = 672.0
#: The smallest legend text on the page, in points at display size (issue 29).
MIN_LEGEND_PT = 9.0
#: Figures wider than this are scaled down to it (their fonts keep their point size).
MAX_WIDTH_IN = 8.0


def display_scale(fig: Any, column_px: float = COLUMN_PX) -> float:
    """The factor by which the page shrinks ``fig`` (1 when it fits the column): CSS pixels
    shown per CSS pixel of the figure at :data:`CSS_DPI`.

    >>> from matplotlib.figure import Figure
    >>> display_scale(Figure(figsize=(7.0, 3.0))), display_scale(Figure(figsize=(5.0, 3.0)))
    (1.0, 1.0)
    >>> round(display_scale(Figure(figsize=(8.0, 3.0))), 3)
    0.875
    """
    return min(1.0, float(column_px / (fig.get_figwidth() * CSS_DPI)))


def _legends(fig: Any) -> list[Any]:
    found = list(fig.legends)
    for ax in fig.axes:
        leg = ax.get_legend()
        if leg is not None:
            found.append(leg)
    return found


def for_the_page(fig: Any) -> Any:
    """``fig`` made for the page: drawn at :data:`CSS_DPI` (so its width attribute is its
    width in inches), no wider than :data:`MAX_WIDTH_IN`, and every legend's text at least
    :data:`MIN_LEGEND_PT` points at display size.  Returns the same figure.

    >>> from matplotlib.figure import Figure
    >>> fig = Figure(figsize=(10.0, 4.0))
    >>> ax = fig.subplots()
    >>> _ = ax.plot([0, 1], label="a curve")
    >>> _ = ax.legend(fontsize=7)
    >>> fig = for_the_page(fig)
    >>> [round(float(x), 6) for x in (fig.get_figwidth(), fig.get_figheight(), fig.dpi)]
    [8.0, 3.2, 96.0]
    >>> size = ax.get_legend().get_texts()[0].get_fontsize()
    >>> round(size * display_scale(fig), 2) >= MIN_LEGEND_PT
    True
    """
    width, height = fig.get_size_inches()
    if width > MAX_WIDTH_IN:
        fig.set_size_inches(MAX_WIDTH_IN, height * MAX_WIDTH_IN / width)
    fig.set_dpi(CSS_DPI)
    smallest = MIN_LEGEND_PT / display_scale(fig)
    for leg in _legends(fig):
        for text in [*leg.get_texts(), leg.get_title()]:
            if text.get_text() and text.get_fontsize() < smallest:
                text.set_fontsize(smallest)
    return fig


def page_figure(plot: Callable[..., Any]) -> Callable[..., Any]:
    """Decorate a ``plot_*`` function so that the figure it returns is :func:`for_the_page`."""

    @functools.wraps(plot)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        return for_the_page(plot(*args, **kwargs))

    return wrapper
