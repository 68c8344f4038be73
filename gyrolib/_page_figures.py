"""How the figures of the ``plots`` modules are sized for the book's page.

The book shows a figure at ``width_in × dpi`` CSS pixels, shrunk to the column when wider
(the chapters output 2x "retina" PNGs: twice the pixels, the width attribute half of them, see
:func:`gyrolib.book.report.hidpi_figures`).  A legend of ``f`` points then shows at
``f × display_scale(fig)`` points, so on a figure wider than the column a legend must be drawn
larger to be readable.  :func:`for_the_page` does that for every legend of a figure, and caps a
figure's width so that its other text does not shrink much below its size either; it changes
sizes only, never what a figure shows.

:func:`text_problems` measures every visible text artist of a figure (tick labels, axis
labels, titles, annotations, legends) as the reader sees it, against two rules: at least
:data:`MIN_LEGEND_PT` points at the desk's column (:data:`COLUMN_PX`), and at least
:data:`MIN_PHONE_PX` CSS pixels at a phone's column (:data:`PHONE_COLUMN_PX`, a 390-px window;
issue 35, item 3).
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
#: The output column on a phone (a 390-px window; measured by ``tests/test_browser.py``), and
#: the smallest text there, in CSS pixels (issue 35).
PHONE_COLUMN_PX = 342.0
MIN_PHONE_PX = 9.0


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


def visible_texts(fig: Any) -> list[Any]:
    """Every text artist of ``fig`` a reader sees: visible, not empty, with every ancestor
    visible (tick labels, axis labels, titles, annotations, legend texts, free text).  The
    figure is laid out first (``draw_without_rendering``), so that its ticks exist."""
    from matplotlib.text import Text

    fig.draw_without_rendering()

    def shown(artist: Any) -> bool:
        while artist is not None:
            if not artist.get_visible():
                return False
            artist = getattr(artist, "axes", None) if artist is not getattr(
                artist, "axes", None) else None
        return True

    texts = []
    for t in fig.findobj(Text):
        if t.get_text().strip() and t.get_visible() and shown(t) and t.get_figure() is fig:
            texts.append(t)
    return texts


def shown_px(fig: Any, size_pt: float, column_px: float) -> float:
    """CSS pixels on the page of text of ``size_pt`` points in ``fig``, in a column of
    ``column_px`` (the figure drawn at its dpi, shown at half its 2x pixels, shrunk to the
    column when wider).

    >>> from matplotlib.figure import Figure
    >>> round(shown_px(Figure(figsize=(5.0, 3.0), dpi=96.0), 9.0, 342.0), 2)
    8.55
    """
    width_px = fig.get_figwidth() * fig.dpi
    return float(size_pt * fig.dpi / 72.0 * min(1.0, column_px / width_px))


def text_problems(fig: Any) -> list[str]:
    """The visible texts of ``fig`` (:func:`visible_texts`) below :data:`MIN_LEGEND_PT` points
    at the desk's column or :data:`MIN_PHONE_PX` pixels at the phone's, one line each (empty:
    every text reads).

    >>> from matplotlib.figure import Figure
    >>> fig = Figure(figsize=(4.0, 3.0), dpi=96.0)
    >>> ax = fig.subplots()
    >>> _ = ax.set_title("title", fontsize=12)
    >>> _ = ax.tick_params(labelsize=11)
    >>> _ = ax.set_xlabel("x", fontsize=11); _ = ax.set_ylabel("y", fontsize=11)
    >>> text_problems(fig)
    []
    >>> _ = ax.plot([0, 1], label="curve"); _ = ax.legend(fontsize=4.5)
    >>> text_problems(fig)
    ['legend text "curve": 4.5 pt at 672 px (< 9), 5.34 px at 342 px (< 9)']
    """
    problems = []
    texts = visible_texts(fig)
    kinds = _kinds(fig)
    for t in texts:
        size = t.get_fontsize()
        desk = shown_px(fig, size, COLUMN_PX) * 72.0 / CSS_DPI
        phone = shown_px(fig, size, PHONE_COLUMN_PX)
        if desk < MIN_LEGEND_PT - 1e-9 or phone < MIN_PHONE_PX - 1e-9:
            kind = _kind(t, kinds)
            problems.append(f'{kind} "{" ".join(t.get_text().split())[:40]}": {desk:.3g} pt at '
                            f"{COLUMN_PX:.0f} px (< {MIN_LEGEND_PT:g}), {phone:.3g} px at "
                            f"{PHONE_COLUMN_PX:.0f} px (< {MIN_PHONE_PX:g})")
    return problems


def _kinds(fig: Any) -> dict[int, str]:
    """What each text artist of ``fig`` is, by ``id``: legend text, tick label, axis label,
    title (any other text: "text")."""
    from matplotlib.text import Text

    kinds: dict[int, str] = {}
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            for tick in [*axis.get_major_ticks(), *axis.get_minor_ticks()]:
                kinds.update({id(tick.label1): "tick label", id(tick.label2): "tick label"})
            kinds[id(axis.label)] = "axis label"
            kinds[id(axis.get_offset_text())] = "tick label"
        titles = {ax.get_title(loc) for loc in ("left", "center", "right")} - {""}
        for child in ax.get_children():  # the three title artists (public API: their text)
            if isinstance(child, Text) and id(child) not in kinds and child.get_text() in titles:
                kinds[id(child)] = "title"
    for leg in _legends(fig):
        kinds.update({id(t): "legend text" for t in [*leg.get_texts(), leg.get_title()]})
    suptitle = fig.get_suptitle() if hasattr(fig, "get_suptitle") else ""
    if suptitle:
        for t in fig.findobj(Text):
            if t.axes is None and t.get_text() == suptitle:
                kinds[id(t)] = "title"
    return kinds


def _kind(text: Any, kinds: dict[int, str] | None = None) -> str:
    """What a text artist is, for a message (:func:`_kinds`)."""
    kinds = _kinds(text.get_figure()) if kinds is None else kinds
    return kinds.get(id(text), "text")
