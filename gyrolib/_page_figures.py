"""How the figures of the ``plots`` modules are sized for the book's page.

The book shows a figure at ``width_in × dpi`` CSS pixels, shrunk to the column when wider
(the chapters output 2x "retina" PNGs: twice the pixels, the width attribute half of them, see
:func:`gyrolib.book.report.hidpi_figures`).  One image serves the desk (a 672-px column), the
phone (342 px) and the PDF, so every figure is at most :data:`MAX_WIDTH_IN` wide, its panels
stacked, and every text at least :func:`smallest_pt` points: :func:`for_the_page`, applied to
every ``plot_*`` function by :func:`page_figure`, makes it so (sizes only, never what a
figure shows).

:func:`text_problems` measures every visible text artist of a figure (tick labels, axis
labels, titles, annotations, legends) as the reader sees it, against two rules: at least
:data:`MIN_LEGEND_PT` points at the desk's column (:data:`COLUMN_PX`), and at least
:data:`MIN_PHONE_PX` CSS pixels at a phone's column (:data:`PHONE_COLUMN_PX`, a 390-px
window); and it lists the texts that collide (:func:`text_collisions`).  The book's
figures carry that measurement in their PNG (:func:`page_record`, :data:`PNG_KEY`), so that a
test of the built pages can check every figure the reader sees.
"""

from __future__ import annotations

import functools
import json
import math
from collections.abc import Callable
from typing import Any

#: CSS pixels per inch, and the width of the book's output column at a 1280-px window (the
#: figures of the chapters were measured at 672 CSS px by ``tests/book/test_browser.py``).
CSS_DPI = 96.0
COLUMN_PX = 672.0
#: The smallest legend text on the page, in points at display size.
MIN_LEGEND_PT = 9.0
#: Every figure of the book is at most this wide (one image serves the phone,
#: the desk and the PDF; multi-panel figures are stacked, not set side by side).  A wider
#: figure is scaled down to it, its fonts keeping their point size.
MAX_WIDTH_IN = 5.0
#: The output column on a phone (a 390-px window; measured by ``tests/book/test_browser.py``), and
#: the smallest text there, in CSS pixels.
PHONE_COLUMN_PX = 342.0
MIN_PHONE_PX = 9.0
#: The size the plot functions give their small texts (legends, notes, tick labels they set):
#: the smallest that reads at both columns on a figure of :data:`MAX_WIDTH_IN` saved with a
#: tight box (9.86 pt, :func:`smallest_pt`), rounded up.
SMALL_PT = 10.0
#: What a tight box adds on each side of a figure's drawing when it is saved
#: (``bbox_inches="tight"``, matplotlib's ``savefig.pad_inches``): a 5-in figure whose drawing
#: fills it makes a 5.2-in image, shown smaller on a phone than the figure's width says.
TIGHT_PAD_IN = 0.1


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


def smallest_pt(fig: Any) -> float:
    """The smallest font size (points) of ``fig`` that reads at both columns: at least
    :data:`MIN_LEGEND_PT` points at the desk's :data:`COLUMN_PX` and :data:`MIN_PHONE_PX`
    CSS pixels at the phone's :data:`PHONE_COLUMN_PX`, the figure saved with a tight box
    (:data:`TIGHT_PAD_IN` more on each side), rounded up to 0.01 pt.

    >>> from matplotlib.figure import Figure
    >>> smallest_pt(Figure(figsize=(5.0, 3.0), dpi=96.0))  # 9 px / (4/3 px/pt x 342/499.2)
    9.86
    >>> smallest_pt(Figure(figsize=(3.0, 3.0), dpi=96.0))  # fits the phone: the desk's 9 pt
    9.0
    """
    width = fig.get_figwidth() + 2.0 * TIGHT_PAD_IN
    desk = MIN_LEGEND_PT / (shown_px(fig, 1.0, COLUMN_PX, width) * 72.0 / CSS_DPI)
    phone = MIN_PHONE_PX / shown_px(fig, 1.0, PHONE_COLUMN_PX, width)
    return math.ceil(round(max(desk, phone) * 100.0, 6)) / 100.0


def for_the_page(fig: Any) -> Any:
    """``fig`` made for the page: drawn at :data:`CSS_DPI` (so its width attribute is its
    width in inches), no wider than :data:`MAX_WIDTH_IN`, and every text (tick labels, axis
    labels, titles, annotations, legends) at least :func:`smallest_pt` points, so that it
    reads at the desk's column and at a phone's.  Returns the same figure.

    It changes sizes only, never what a figure shows; the layout of a constrained-layout
    figure follows at drawing time.  The plot functions lay their figures out for
    :data:`MAX_WIDTH_IN` (panels stacked), so that this is a safety net, not a shrink.

    >>> from matplotlib.figure import Figure
    >>> fig = Figure(figsize=(10.0, 4.0))
    >>> ax = fig.subplots()
    >>> _ = ax.plot([0, 1], label="a curve")
    >>> _ = ax.legend(fontsize=7)
    >>> _ = ax.tick_params(labelsize=6)
    >>> fig = for_the_page(fig)
    >>> [round(float(x), 6) for x in (fig.get_figwidth(), fig.get_figheight(), fig.dpi)]
    [5.0, 2.0, 96.0]
    >>> ax.get_legend().get_texts()[0].get_fontsize(), smallest_pt(fig)
    (9.86, 9.86)
    >>> ax.xaxis.get_major_ticks()[0].label1.get_fontsize()
    9.86
    """
    from matplotlib.text import Text

    width, height = fig.get_size_inches()
    if width > MAX_WIDTH_IN:
        fig.set_size_inches(MAX_WIDTH_IN, height * MAX_WIDTH_IN / width)
    fig.set_dpi(CSS_DPI)
    smallest = smallest_pt(fig)
    for ax in fig.axes:  # tick labels made later (at drawing) take the axis' tick settings
        for axis in (ax.xaxis, ax.yaxis):
            for which, ticks in (("major", axis.get_major_ticks()),
                                 ("minor", axis.get_minor_ticks())):
                if any(t.label1.get_fontsize() < smallest for t in ticks[:1]):
                    axis.set_tick_params(which=which, labelsize=smallest)
    for text in fig.findobj(Text):
        if text.get_fontsize() < smallest:
            text.set_fontsize(smallest)
    return fig


def legend_below(fig: Any, ax: Any, ncols: int = 1) -> Any:
    """The legend of ``ax`` under the figure's axes (constrained layout makes room): on a
    figure :data:`MAX_WIDTH_IN` wide a legend of several entries inside the axes covers
    the curves.  Returns the legend."""
    return fig.legend(*ax.get_legend_handles_labels(), loc="outside lower center",
                      ncols=ncols, fontsize=SMALL_PT)


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

    undrawn = _undrawn_tick_labels(fig)
    texts = []
    for t in fig.findobj(Text):
        if (t.get_text().strip() and t.get_visible() and shown(t) and t.get_figure() is fig
                and id(t) not in undrawn):
            texts.append(t)
    return texts


def _undrawn_tick_labels(fig: Any) -> set[int]:
    """The ``id`` of every tick label of ``fig`` that is not drawn: an axis keeps ticks at
    locations outside its view limits (and spare ones), whose labels are visible artists at
    places the reader never sees.  The ticks drawn are those the axis draws
    (:func:`_drawn_ticks`); an axes turned off, or an axis
    hidden (a twin's shared one), draws none, nor its axis labels."""
    undrawn: set[int] = set()
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            every = [*axis.majorTicks, *axis.minorTicks]
            shown = ax.axison and axis.get_visible()  # ax.axis("off"), a twin's shared axis
            if not shown:  # the axis is not drawn, nor its labels
                undrawn.update({id(axis.label), id(axis.get_offset_text())})
            drawn = _drawn_ticks(axis) if shown else set()
            undrawn.update(id(label) for t in every if id(t) not in drawn
                           for label in (t.label1, t.label2))
    return undrawn


def _drawn_ticks(axis: Any) -> set[int]:
    """The ``id`` of the ticks ``axis`` draws, through matplotlib's public API, as
    ``Axis.draw`` chooses them: the first ``len(locs)`` ticks of each kind carry the
    locator's locations (the rest are spares), and of those only the ones inside the view
    interval, compared in the axis's transformed coordinates (a log axis: in decades) with
    a tolerance of 10⁻¹⁰ of the interval."""
    tr = axis.get_transform()
    a, b = sorted(float(x) for x in tr.transform(list(axis.get_view_interval())))
    tol = 1e-10 * (b - a)
    drawn = set()
    for locs, ticks in ((axis.get_majorticklocs(), axis.get_major_ticks),
                        (axis.get_minorticklocs(), axis.get_minor_ticks)):
        locs = list(locs)
        if not locs:
            continue
        for tick, loc_t in zip(ticks(len(locs)), tr.transform(locs)):
            if a - tol <= float(loc_t) <= b + tol:
                drawn.add(id(tick))
    return drawn


def shown_px(fig: Any, size_pt: float, column_px: float,
             width_in: float | None = None) -> float:
    """CSS pixels on the page of text of ``size_pt`` points in ``fig``, in a column of
    ``column_px`` (the figure drawn at its dpi, shown at half its 2x pixels, shrunk to the
    column when wider).  ``width_in``: the width of the image as saved (default: the
    figure's).

    >>> from matplotlib.figure import Figure
    >>> round(shown_px(Figure(figsize=(5.0, 3.0), dpi=96.0), 9.0, 342.0), 2)
    8.55
    """
    width_px = (fig.get_figwidth() if width_in is None else width_in) * fig.dpi
    return float(size_pt * fig.dpi / 72.0 * min(1.0, column_px / width_px))


def text_problems(fig: Any, *, texts: list[Any] | None = None) -> list[str]:
    """What does not read in ``fig``, one line each (empty: every text reads): the visible
    texts (:func:`visible_texts`) below :data:`MIN_LEGEND_PT` points at the desk's column or
    :data:`MIN_PHONE_PX` pixels at the phone's, and the texts that collide
    (:func:`text_collisions`); each text measured on the image as saved
    (:func:`saved_width_in`).  ``texts``: :func:`visible_texts` of ``fig``, when known.

    >>> from matplotlib.figure import Figure
    >>> fig = Figure(figsize=(4.0, 3.0), dpi=96.0, layout="constrained")
    >>> ax = fig.subplots()
    >>> _ = ax.set_title("title", fontsize=12)
    >>> _ = ax.tick_params(labelsize=11)
    >>> _ = ax.set_xlabel("x", fontsize=11); _ = ax.set_ylabel("y", fontsize=11)
    >>> text_problems(fig)
    []
    >>> _ = ax.plot([0, 1], label="curve"); _ = ax.legend(fontsize=4.5)
    >>> text_problems(fig)
    ['legend text "curve": 4.5 pt at 672 px (< 9), 5.19 px at 342 px (< 9)']
    """
    problems = []
    texts = visible_texts(fig) if texts is None else texts
    kinds = _kinds(fig)
    width = saved_width_in(fig, texts)
    for t in texts:
        size = t.get_fontsize()
        desk = shown_px(fig, size, COLUMN_PX, width) * 72.0 / CSS_DPI
        phone = shown_px(fig, size, PHONE_COLUMN_PX, width)
        if desk < MIN_LEGEND_PT - 1e-9 or phone < MIN_PHONE_PX - 1e-9:
            kind = _kind(t, kinds)
            problems.append(f'{kind} "{_short(t)}": {desk:.3g} pt at '
                            f"{COLUMN_PX:.0f} px (< {MIN_LEGEND_PT:g}), {phone:.3g} px at "
                            f"{PHONE_COLUMN_PX:.0f} px (< {MIN_PHONE_PX:g})")
    return problems + text_collisions(fig, texts=texts, kinds=kinds)


def saved_width_in(fig: Any, texts: list[Any] | None = None) -> float:
    """The width (inches) at which the page may show ``fig``: its own, or, saved with a tight
    box, its drawing's with :data:`TIGHT_PAD_IN` on each side, whichever is wider (a
    drawing narrower than the figure only shows its text larger).  The drawing's extent is
    that of its axes, legends and visible texts (``texts``: :func:`visible_texts`), what
    reaches furthest in the book's figures."""
    texts = visible_texts(fig) if texts is None else texts
    boxes = [t.get_window_extent() for t in texts] + [ax.bbox for ax in fig.axes]
    boxes += [leg.get_window_extent() for leg in _legends(fig) if leg.get_visible()]
    if not boxes:
        return float(fig.get_figwidth())
    left, right = min(b.x0 for b in boxes), max(b.x1 for b in boxes)
    drawn = (right - left) / fig.dpi + 2.0 * TIGHT_PAD_IN
    return max(float(fig.get_figwidth()), float(drawn))


#: Two texts collide when their boxes overlap by more than this, in CSS pixels of the figure
#: (at :data:`CSS_DPI`) along both axes; a text leaves the figure when it reaches this far
#: past its edge.  One pixel: glyph boxes include the font's ascent and descent, so texts set
#: on neighbouring lines touch without overlapping.
COLLISION_PX = 1.0


def _short(text: Any) -> str:
    return " ".join(text.get_text().split())[:40]


def text_collisions(fig: Any, *, texts: list[Any] | None = None,
                    kinds: dict[int, str] | None = None) -> list[str]:
    """The texts of ``fig`` that collide, one line each (empty: none): two visible texts
    whose boxes overlap (turned texts as turned rectangles), a text under a legend it does
    not belong to, a legend over a labelled curve of its axes, and a text that reaches past
    the figure's edge (saved with a tight box, it widens the image beyond the width it was
    laid out for).  Boxes are the renderer's extents of the laid-out figure;
    overlaps up to :data:`COLLISION_PX` are allowed.

    >>> from matplotlib.figure import Figure
    >>> fig = Figure(figsize=(4.0, 3.0), dpi=96.0, layout="constrained")
    >>> ax = fig.subplots()
    >>> _ = ax.set_xlabel("time (s)"); _ = ax.set_title("a title")
    >>> text_collisions(fig)
    []
    >>> _ = ax.text(0.5, 1.0, "a label on the title", transform=ax.transAxes, ha="center")
    >>> text_collisions(fig)
    ['text "a label on the title" overlaps title "a title"']
    """
    texts = visible_texts(fig) if texts is None else texts
    kinds = _kinds(fig) if kinds is None else kinds
    scale = CSS_DPI / fig.dpi  # figure pixels to CSS pixels of the figure
    tol = COLLISION_PX / scale
    boxes = [t.get_window_extent() for t in texts]  # the figure's own renderer, at its dpi
    owner: dict[int, int] = {}  # text -> the legend it belongs to
    legends = [leg for leg in _legends(fig) if leg.get_visible()]
    for i, leg in enumerate(legends):
        owner.update({id(t): i for t in [*leg.get_texts(), leg.get_title()]})

    def name(t: Any) -> str:
        return f'{_kind(t, kinds)} "{_short(t)}"'

    found = []
    edge = fig.bbox
    for t, b in zip(texts, boxes):
        if (b.x0 < edge.x0 - tol or b.x1 > edge.x1 + tol or b.y0 < edge.y0 - tol
                or b.y1 > edge.y1 + tol):
            found.append(f"{name(t)} reaches past the figure's edge")
    for i in range(len(texts)):
        for j in range(i + 1, len(texts)):
            a, b = boxes[i], boxes[j]
            w = min(a.x1, b.x1) - max(a.x0, b.x0)
            h = min(a.y1, b.y1) - max(a.y0, b.y0)
            if w > tol and h > tol and _rotated_overlap(texts[i], a, texts[j], b, tol):
                found.append(f"{name(texts[i])} overlaps {name(texts[j])}")
    for k, leg in enumerate(legends):
        frame = leg.get_window_extent()
        for t, b in zip(texts, boxes):
            if owner.get(id(t)) == k:
                continue
            w = min(frame.x1, b.x1) - max(frame.x0, b.x0)
            h = min(frame.y1, b.y1) - max(frame.y0, b.y0)
            if w > tol and h > tol:
                found.append(f"{name(t)} lies under the legend")
    found += _legends_over_curves(fig, legends, tol)
    return found


def _corners(text: Any, box: Any) -> Any:
    """The four corners (4 × 2, display pixels) of ``text``'s own rectangle: for a text
    turned by an angle, not the upright box around it (``box``) but the text's box turned
    about that box's centre, which is the turned rectangle's centre."""
    import numpy as np

    angle = float(text.get_rotation()) % 180.0
    if angle in (0.0, 90.0):
        return np.array([[box.x0, box.y0], [box.x1, box.y0], [box.x1, box.y1],
                         [box.x0, box.y1]])
    rotation = text.get_rotation()
    try:  # the text's own size, upright (set back at once)
        text.set_rotation(0.0)
        upright = text.get_window_extent()
    finally:
        text.set_rotation(rotation)
    c, s = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    half = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]]) * [upright.width / 2,
                                                                upright.height / 2]
    centre = np.array([(box.x0 + box.x1) / 2, (box.y0 + box.y1) / 2])
    return centre + half @ np.array([[c, s], [-s, c]])


def _rotated_overlap(ta: Any, a: Any, tb: Any, b: Any, tol: float) -> bool:
    """Whether two texts whose upright boxes ``a``, ``b`` overlap also overlap as turned
    rectangles, by more than ``tol`` along every separating axis (the separating axis
    theorem; upright texts: their boxes, already known to overlap)."""
    import numpy as np

    if float(ta.get_rotation()) % 90.0 == 0.0 and float(tb.get_rotation()) % 90.0 == 0.0:
        return True
    pa, pb = _corners(ta, a), _corners(tb, b)
    for poly in (pa, pb):
        for k in range(2):
            edge = poly[k + 1] - poly[k]
            axis = np.array([-edge[1], edge[0]]) / (np.hypot(*edge) or 1.0)
            ra, rb = pa @ axis, pb @ axis
            if min(ra.max(), rb.max()) - max(ra.min(), rb.min()) <= tol:
                return False
    return True


def _legends_over_curves(fig: Any, legends: list[Any], tol: float) -> list[str]:
    """A legend inside its axes that covers a curve the reader is told about (a line with a
    label of its own): a segment of the line crosses the legend's box, shrunk by ``tol``."""
    import numpy as np

    found = []
    for leg in legends:
        ax = leg.axes
        if ax is None or not leg.get_visible():
            continue
        box = leg.get_window_extent()
        x0, y0, x1, y1 = box.x0 + tol, box.y0 + tol, box.x1 - tol, box.y1 - tol
        if x0 >= x1 or y0 >= y1:
            continue
        for line in ax.get_lines():
            label = str(line.get_label())
            if not line.get_visible() or label.startswith("_") or line.get_linestyle() in (
                    "None", "none", "", " "):
                continue
            xy = line.get_transform().transform(np.asarray(line.get_xydata(), dtype=float))
            xy = xy[np.all(np.isfinite(xy), axis=1)]
            if len(xy) < 2 or not _crosses(xy, x0, y0, x1, y1):
                continue
            found.append(f'the legend covers the curve "{" ".join(label.split())[:40]}"')
    return found


def _crosses(xy: Any, x0: float, y0: float, x1: float, y1: float) -> bool:
    """Whether the polyline ``xy`` (n × 2, display pixels) enters the box: a vertex inside,
    or a segment crossing it (Liang–Barsky clipping of every segment at once)."""
    import numpy as np

    inside = (xy[:, 0] > x0) & (xy[:, 0] < x1) & (xy[:, 1] > y0) & (xy[:, 1] < y1)
    if inside.any():
        return True
    p, q = xy[:-1], xy[1:]
    d = q - p
    t0, t1 = np.zeros(len(p)), np.ones(len(p))
    with np.errstate(divide="ignore", invalid="ignore"):
        for k, lo, hi in ((0, x0, x1), (1, y0, y1)):
            for num, den in ((lo - p[:, k], d[:, k]), (p[:, k] - hi, -d[:, k])):
                # the segment's parameter where it meets the edge: entering when den > 0
                r = num / den
                parallel_out = (den == 0) & (num > 0)
                t0 = np.where(den > 0, np.maximum(t0, r), t0)
                t1 = np.where(den < 0, np.minimum(t1, r), t1)
                t1 = np.where(parallel_out, -1.0, t1)
    return bool(np.any(t0 < t1))


#: The key of the PNG text chunk in which the book's figures carry their measurement
#: (:func:`page_record`), read back from the built pages by ``tests/book/test_page_figures.py``.
PNG_KEY = "gyrolib-figure-text"


def page_record(fig: Any) -> str:
    """The measurement of ``fig`` as the page shows it, as JSON for a PNG text chunk
    (:data:`PNG_KEY`): how many visible texts it has, the smallest font size (points) and
    the figure's width (inches) they were measured at, and :func:`text_problems`.

    >>> from matplotlib.figure import Figure
    >>> fig = Figure(figsize=(5.0, 3.0), dpi=96.0, layout="constrained")
    >>> _ = fig.subplots().set_title("a title", fontsize=10)
    >>> rec = json.loads(page_record(fig))
    >>> rec["smallest_pt"], rec["width_in"], rec["problems"], rec["texts"] > 1
    (10.0, 5.0, [], True)
    """
    texts = visible_texts(fig)
    sizes = [float(t.get_fontsize()) for t in texts]
    problems = text_problems(fig, texts=texts)
    kinds = _kinds(fig)
    # the legends' entries as the figure shows them: a test of the built book compares the
    # numbers a legend quotes with the page's text
    legend = [t.get_text() for t in texts if kinds.get(id(t)) == "legend text"]
    return json.dumps({"texts": len(texts), "smallest_pt": min(sizes, default=None),
                       "width_in": round(float(fig.get_figwidth()), 4),
                       "problems": problems, "legend": legend}, ensure_ascii=True)


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
