"""Figures sized for the page: the book's figures are 2x PNGs with legends
of at least 9 pt at display size, and curves that overlap stay distinguishable; every
figure is at most 5 in wide with every text readable at the desk's 672-px column (9 pt) and a
phone's 342-px column (9 px), and no text collides; the built book's
every figure is measured (its PNG carries the measurement) and counted against the pages.

The display size is computed here from first principles (a figure of ``w`` inches drawn at
96 px/in is shown at ``min(w·96, 672)`` CSS px, 672 px being the output column the browser
test measured at a 1280-px window), not by the helper under test.
"""

from __future__ import annotations

import functools
import re
from pathlib import Path

import numpy as np
import pytest
from matplotlib.figure import Figure

from gyrolib import gc
from gyrolib._page_figures import MIN_LEGEND_PT, for_the_page
from tests.conftest import require_built_book

COLUMN_PX = 672.0


def shown_pt(fig, size_pt: float) -> float:
    """Points at display size of text of ``size_pt`` points in ``fig``."""
    width_px = fig.get_figwidth() * fig.dpi
    return size_pt * min(1.0, COLUMN_PX / width_px) * fig.dpi / 96.0


def legend_sizes(fig) -> list[float]:
    legends = list(fig.legends) + [ax.get_legend() for ax in fig.axes if ax.get_legend()]
    return [t.get_fontsize() for leg in legends for t in leg.get_texts()]


def _figure(width: float, legend_pt: float) -> Figure:
    fig = Figure(figsize=(width, 3.0), layout="constrained")
    ax = fig.subplots()
    ax.plot([0, 1], [0, 1], label="one")
    ax.plot([0, 1], [1, 0], label="two")
    ax.legend(fontsize=legend_pt)
    return fig


@pytest.mark.parametrize("width", [5.0, 7.0, 8.0, 10.0, 12.0])
def test_legends_are_at_least_9_pt_at_display_size(width):
    before = _figure(width, 7.0)
    if width > COLUMN_PX / 96.0:  # without the helper, a 7-pt legend shows smaller still
        assert shown_pt(before, 7.0) < 7.0
    fig = for_the_page(before)
    assert fig.dpi == pytest.approx(96.0, abs=1e-9)
    assert fig.get_figwidth() <= 5.0 + 1e-9
    sizes = legend_sizes(fig)
    assert len(sizes) == 2
    assert min(shown_pt(fig, s) for s in sizes) >= MIN_LEGEND_PT - 1e-9, sizes
    # a large legend is left as it is
    big = for_the_page(_figure(width, 20.0))
    assert legend_sizes(big) == [20.0, 20.0]


def test_the_check_fails_on_a_figure_not_made_for_the_page():
    fig = _figure(10.0, 7.0)
    fig.set_dpi(100.0)
    assert min(shown_pt(fig, s) for s in legend_sizes(fig)) < MIN_LEGEND_PT


def test_plot_functions_return_figures_made_for_the_page():
    P = gc.GyrocompassParams()
    t, t_fast = np.linspace(0.0, 100.0, 200), np.linspace(0.0, 0.01, 100)
    fig = gc.plot_nominal_motion(gc.nominal_motion(P, t), gc.nominal_motion_aperiodic(P, t),
                                 gc.nominal_motion(P, t_fast),
                                 gc.nominal_motion_aperiodic(P, t_fast),
                                 tau=P.time_constant, lag=0.0)
    assert fig.get_figwidth() <= 5.0 + 1e-9  # at most 5 in, panels stacked
    assert fig.dpi == pytest.approx(96.0, abs=1e-9)
    sizes = legend_sizes(fig)
    assert sizes and min(shown_pt(fig, s) for s in sizes) >= MIN_LEGEND_PT - 1e-9, sizes


def test_the_inclinometer_curves_of_the_allan_figure_are_distinguishable():
    """Two inclinometers with the same noise give nearly the same curve: they must differ in
    marker and line style, not in color only, so that the one drawn first stays visible."""
    P = gc.GyrocompassParams()
    rng = np.random.default_rng(7)
    n = 20000
    t = np.arange(1, n + 1) * P.dt
    beta_n = gc.nominal_motion_aperiodic(P, t).beta
    noise = np.sqrt(5e-15 / P.dt)
    rec = gc.GCRecord(t=t, angle_sensor=beta_n + 1e-5 * rng.standard_normal(n),
                      inclinometer_y=noise * rng.standard_normal(n),
                      inclinometer_z=noise * rng.standard_normal(n))
    fig = gc.plot_allan(gc.allan_deviation(rec, P))
    lines = {c.get_label(): c.lines[0] for c in fig.axes[1].containers
             if c.get_label() in ("inclinometer_y", "inclinometer_z")}
    y, z = lines["inclinometer_y"], lines["inclinometer_z"]
    assert y.get_marker() != z.get_marker()
    assert y.get_linestyle() != z.get_linestyle()
    # the open marker of one lets the filled marker of the other show through
    assert "none" in (str(y.get_markerfacecolor()), str(z.get_markerfacecolor()))


def test_notebook_figures_are_2x_pngs_shown_at_half_their_pixels():
    """In an IPython shell, after :func:`gyrolib.book.report.hidpi_figures`, a figure's PNG
    has twice the pixels of its width attribute (what the browser test measures as 2 image
    pixels per CSS pixel)."""
    IPython = pytest.importorskip("IPython")
    from IPython.core.interactiveshell import InteractiveShell

    from gyrolib.book.report import hidpi_figures

    shell = InteractiveShell.instance()
    try:
        assert hidpi_figures()
        fig = for_the_page(_figure(6.0, 9.0))
        data, meta = shell.display_formatter.format(fig)
        png = __import__("base64").b64decode(data["image/png"])
        width = int.from_bytes(png[16:20], "big")
        assert meta["image/png"]["width"] == width // 2
        # drawn at 6 in, capped at 5; bbox_inches="tight" trims or adds a
        # little: about 5 in at 96 px/in, doubled
        assert width == pytest.approx(2 * 5.0 * 96.0, rel=0.1)
        # and it carries its measurement (read back from the built pages, below)
        import io
        import json

        from PIL import Image

        from gyrolib._page_figures import PNG_KEY
        record = json.loads(Image.open(io.BytesIO(png)).info[PNG_KEY])
        assert record["problems"] == [] and record["texts"] >= 4, record
    finally:
        InteractiveShell.clear_instance()
    assert IPython.get_ipython() is None


def not_made_for_the_page(*modules) -> list[str]:
    """The ``plot_*`` functions of ``modules`` whose figure does not go through
    :func:`for_the_page` (neither decorated by ``page_figure`` nor calling it)."""
    import inspect

    missing = []
    for module in modules:
        for name, func in inspect.getmembers(module, inspect.isfunction):
            if not name.startswith("plot_") or func.__module__ != module.__name__:
                continue
            wrapped = getattr(func, "__wrapped__", None) is not None
            if not (wrapped or "for_the_page(" in inspect.getsource(func)):
                missing.append(f"{module.__name__}.{name}")
    return missing


def test_every_plot_function_returns_its_figure_made_for_the_page(tmp_path, monkeypatch):
    """Every ``plot_*`` of the plots modules goes through :func:`for_the_page` (decorated by
    ``page_figure``); sensitivity's ``plot_indices`` calls it on a figure of its own.  A
    module with an undecorated plot function is reported."""
    import importlib

    from gyrolib.gc import plots as gc_plots
    from gyrolib.rsf import plots as rsf_plots
    from gyrolib.sensitivity import plots as sens_plots

    assert not_made_for_the_page(gc_plots, rsf_plots, sens_plots) == []
    (tmp_path / "bare_plots.py").write_text(
        "from gyrolib._page_figures import page_figure\n\n\n"
        "@page_figure\ndef plot_ok():\n    pass\n\n\n"
        "def plot_bare():\n    pass\n", encoding="utf-8")
    monkeypatch.syspath_prepend(str(tmp_path))
    assert not_made_for_the_page(importlib.import_module("bare_plots")) == [
        "bare_plots.plot_bare"]


# ------------------------------------------------------------------- every text, on a phone
# (at least 9 pt at the desk's 672-px column and 9 px at a phone's 342 px)

def _readable_figure() -> Figure:
    """A 5-in figure whose every text is 10 pt: 9.5 px at 342 px, 10 pt at 672 px."""
    fig = Figure(figsize=(5.0, 3.0), dpi=96.0, layout="constrained")
    ax = fig.subplots()
    ax.plot([0, 1], [0, 1], label="a curve")
    ax.tick_params(labelsize=10)
    ax.set_xlabel("t (s)", fontsize=10)
    ax.set_ylabel("σ (rad/s)", fontsize=10)
    ax.set_title("a title", fontsize=10)
    ax.annotate("a note", (0.5, 0.5), fontsize=10)
    ax.legend(fontsize=10)
    fig.suptitle("a figure title", fontsize=10)
    hidden = ax.text(0.1, 0.9, "hidden", fontsize=3)
    hidden.set_visible(False)
    return fig


def test_every_visible_text_artist_is_measured():
    from gyrolib._page_figures import _kind, visible_texts

    fig = _readable_figure()
    texts = visible_texts(fig)
    kinds = {_kind(t) for t in texts}
    assert kinds == {"legend text", "tick label", "axis label", "title", "text"}, kinds
    words = {t.get_text() for t in texts}
    assert {"a curve", "t (s)", "σ (rad/s)", "a title", "a note", "a figure title"} <= words
    assert "hidden" not in words
    assert sum(_kind(t) == "tick label" for t in texts) >= 4  # both axes' labels


def test_the_phone_rule_passes_a_readable_figure_and_fails_an_injected_6_px_legend():
    from gyrolib._page_figures import shown_px, text_problems

    fig = _readable_figure()
    assert text_problems(fig) == []
    # a legend of 6 px at 342 px, first principles: 6 px / (96/72 px/pt × 342/480)
    size = 6.0 / (96.0 / 72.0 * 342.0 / 480.0)
    assert shown_px(fig, size, 342.0) == pytest.approx(6.0)
    fig.axes[0].legend(fontsize=size)
    problems = text_problems(fig)
    assert len(problems) == 1 and problems[0].startswith('legend text "a curve"'), problems
    assert "6 px at 342 px" in problems[0], problems
    # 9 pt on a 5-in figure passes the desk (9 pt) but not the phone (8.55 px)
    fig.axes[0].legend(fontsize=9.0)
    assert len(text_problems(fig)) == 1


# The figures drawn without data (gc.plot_figure1, rsf.plot_method_scheme, rsf.plot_gs_scheme)
# are checked where the book draws them: test_every_figure_of_the_book_reads_at_the_desk_and_
# on_a_phone reads each one's measurement (both columns, collisions, and its width) from its
# PNG, as every other figure's; drawing them again here repeated the build's measurement.


# ------------------------------------------------------------------------- text that collides

def test_the_collision_check_finds_injected_overlaps_and_passes_a_clean_figure():
    """Power of :func:`text_collisions`: a readable figure has none; a note written over the
    title, an annotation under the legend and a label out of the figure are each found, by
    name; the overlap is read from the laid-out boxes, so moving the note clear removes it."""
    from gyrolib._page_figures import text_collisions

    fig = _readable_figure()
    assert text_collisions(fig) == []
    ax = fig.axes[0]
    note = ax.text(0.5, 1.0, "over the title", transform=ax.transAxes, ha="center",
                   va="bottom", fontsize=10)
    found = text_collisions(fig)
    assert found and all("over the title" in f for f in found), found
    assert any('title "a title"' in f for f in found), found
    note.set_position((0.5, 0.35))  # clear of the title and of the legend (upper left)
    note.set_transform(ax.transAxes)
    assert text_collisions(fig) == [], text_collisions(fig)
    legend_box = ax.get_legend().get_window_extent()
    x, y = fig.transFigure.inverted().transform(((legend_box.x0 + legend_box.x1) / 2,
                                                  (legend_box.y0 + legend_box.y1) / 2))
    fig.text(x, y, "hidden under", fontsize=10, ha="center", va="center")
    assert [f for f in text_collisions(fig) if "under the legend" in f], text_collisions(fig)
    fig2 = _readable_figure()
    fig2.text(0.98, 0.5, "a label that runs off the right edge", fontsize=10)
    assert any("past the figure's edge" in f for f in text_collisions(fig2))
    # a legend over a labelled curve: a level line through the legend's box (no vertex in
    # it: the segment is clipped against the box), then the legend moved off it
    fig3 = Figure(figsize=(5.0, 3.0), dpi=96.0, layout="constrained")
    ax3 = fig3.subplots()
    x = np.linspace(0.0, 1.0, 50)
    ax3.plot(x, x, label="rising")
    ax3.axhline(0.9, label="level")
    ax3.tick_params(labelsize=10)
    ax3.legend(loc="upper left", fontsize=10)
    assert text_collisions(fig3) == ['the legend covers the curve "level"']
    ax3.legend(loc="lower right", fontsize=10)
    assert text_collisions(fig3) == []
    # turned tick labels are compared as turned rectangles: twelve long labels at 45° do not
    # touch (their upright boxes do), at 10° they overprint
    for angle, collide in ((45, False), (10, True)):
        fig4 = Figure(figsize=(5.0, 3.4), dpi=96.0, layout="constrained")
        ax4 = fig4.subplots()
        ax4.bar(range(12), np.arange(12))
        ax4.set_xticks(range(12), [f"label σ_{k}(0)" for k in range(12)], rotation=angle,
                       fontsize=10)
        ax4.tick_params(labelsize=10)
        found = text_collisions(fig4)
        assert bool(found) == collide and all("tick label" in f for f in found), (angle, found)


# ------------------------------------------------------------------ every figure of the book
# (acceptance: "The test measures every figure of the book. It asserts that
# the number of figures measured equals the number on the pages, and it fails on an injected
# 6-px legend.")  Each figure's PNG carries its measurement (gyrolib.book.report.page_png,
# _ext/benchmark_results.py): how many texts, the smallest size in points, the problems found
# by text_problems.  The size each text is shown at is computed here from the PNG itself (its
# pixels and dpi) and the size the page declares for it, not by the code under test.

PHONE_COLUMN_PX = 342.0
#: Every figure at most 5 in wide (one image for phone, desk and PDF).
MAX_WIDTH_IN = 5.0


def _png_of(src: str, page: Path) -> bytes | None:
    import base64
    from urllib.parse import unquote

    if src.startswith("data:"):
        head, _, data = src.partition(",")
        return base64.b64decode(data) if ";base64" in head else None
    path = (page.parent / unquote(src.split("#")[0].split("?")[0])).resolve()
    return path.read_bytes() if path.is_file() else None


IMG_TAG = re.compile(r"<img\b[^>]*>", re.I)
ATTR = re.compile(r'([\w-]+)\s*=\s*(?:"([^"]*)"|\'([^\']*)\')')


def _attributes(tag: str) -> dict[str, str]:
    import html

    return {m.group(1).lower(): html.unescape(m.group(2) if m.group(2) is not None
                                              else m.group(3)) for m in ATTR.finditer(tag)}


def _declared_css_width(img: dict[str, str]) -> float | None:
    style = re.search(r"(?:^|;)\s*width:\s*([\d.]+)px", img.get("style") or "")
    if style:
        return float(style.group(1))
    width = (img.get("width") or "").removesuffix("px")
    return float(width) if width.replace(".", "", 1).isdigit() else None


def _article(html: str) -> str:
    """The page's article (the theme's ``<article class="bd-article">``), else the page."""
    start = html.find('<article class="bd-article"')
    end = html.rfind("</article>")
    return html[start:end] if 0 <= start < end else html


def measure_figures(pages: dict[str, tuple[Path, str]]) -> tuple[int, int, list[str]]:
    """The figures (``<img>`` in the article) of ``pages`` (name → (file, HTML)): how many
    there are, how many carry a measurement, and every problem, one line each: a figure
    without a measurement, a problem its measurement lists, and a smallest text below 9 pt
    at the 672-px column or 9 px at the phone's 342 px as this test computes it."""
    shown = measured = 0
    problems: list[str] = []
    for name, (path, html) in sorted(pages.items()):
        s, m, p = _measure_page(name, path, html)
        shown, measured, problems = shown + s, measured + m, problems + p
    return shown, measured, problems


@functools.cache
def _measure_page(name: str, path: Path, html: str) -> tuple[int, int, list[str]]:
    import io
    import json

    from PIL import Image

    from gyrolib._page_figures import PNG_KEY

    shown = measured = 0
    problems: list[str] = []
    for n, tag in enumerate(IMG_TAG.findall(_article(html)), 1):
        img = _attributes(tag)
        shown += 1
        where = f"{name}, figure {n} ({(img.get('alt') or '')[:50]!r})"
        data = _png_of(img.get("src") or "", path)
        image = Image.open(io.BytesIO(data)) if data and data[:4] == b"\x89PNG" else None
        # read before the pixels (the chunk precedes them): .text would decode the image
        record = image.info.get(PNG_KEY) if image else None
        if record is None:
            problems.append(f"{where}: not measured (no {PNG_KEY} in its PNG)")
            continue
        measured += 1
        rec = json.loads(record)
        problems += [f"{where}: {p}" for p in rec["problems"]]
        if rec["width_in"] > MAX_WIDTH_IN + 1e-9:
            problems.append(f"{where}: {rec['width_in']:g} in wide (> {MAX_WIDTH_IN:g} in)")
        if not rec["texts"]:
            problems.append(f"{where}: no text measured")
            continue
        dpi = float(image.info.get("dpi", (192.0, 192.0))[0])
        width_in = image.size[0] / dpi  # the image as saved (tight box included)
        declared = _declared_css_width(img) or image.size[0] / 2.0
        for column, rule, unit in ((COLUMN_PX, 9.0, "pt"), (PHONE_COLUMN_PX, 9.0, "px")):
            px_per_in = min(declared, column) / width_in
            size_px = rec["smallest_pt"] / 72.0 * px_per_in
            size = size_px * 72.0 / 96.0 if unit == "pt" else size_px
            if size < rule - 1e-6:
                problems.append(f"{where}: smallest text {size:.3g} {unit} at "
                                f"{column:g} px (< {rule:g})")
    return shown, measured, problems


def _book_pages(root: Path) -> dict[str, tuple[Path, str]]:
    skip = {"_static", "_sources", "_images", "_downloads"}
    return {p.relative_to(root).as_posix(): (p, p.read_text(encoding="utf-8"))
            for p in sorted(root.rglob("*.html"))
            if not skip.intersection(p.relative_to(root).parts[:-1])}


def _glue_figures_in_the_chapters() -> int:
    root = Path(__file__).resolve().parents[2]
    return sum(p.read_text(encoding="utf-8").count("```{glue:figure}")
               for p in (root / "chapters").glob("*.md"))


def _six_px_legend_png() -> str:
    """A 5-in figure, readable but for a legend of 6 px at the phone's column, as the book
    writes its figures (:func:`gyrolib.book.report.page_png`)."""
    fig = _readable_figure()
    fig.axes[0].legend(fontsize=6.0 / (96.0 / 72.0 * PHONE_COLUMN_PX / 480.0))
    return _img_tag(fig, "injected")


def _img_tag(fig, alt: str) -> str:
    from gyrolib.book.report import page_png

    data, meta = page_png(fig, bbox_inches="tight")
    return (f'<img alt="{alt}" src="data:image/png;base64,{data}" '
            f'width="{meta["width"]}" height="{meta["height"]}">')


def test_every_figure_of_the_book_reads_at_the_desk_and_on_a_phone():
    pages = _book_pages(require_built_book())
    shown, measured, problems = measure_figures(pages)
    assert shown >= _glue_figures_in_the_chapters() > 30, shown
    assert not problems, f"{len(problems)} figure problems:\n  " + "\n  ".join(problems)
    assert measured == shown


def test_the_book_check_fails_on_an_injected_6_px_legend_and_an_unmeasured_figure():
    """Power: one built page with a figure whose legend shows at 6 px on a phone, one with a
    figure saved without its measurement, and one with a readable figure 6 in wide: each is
    found, and nothing else."""
    import base64
    import io

    pages = _book_pages(require_built_book())
    shown, measured, problems = measure_figures(pages)
    name = "chapters/gc_model.html"
    path, html = pages[name]
    injected = dict(pages)
    injected[name] = (path, html.replace("</article>", _six_px_legend_png() + "</article>", 1))
    s2, m2, p2 = measure_figures(injected)
    assert (s2, m2) == (shown + 1, measured + 1)
    new = [p for p in p2 if p not in problems]
    assert new and all("injected" in p for p in new), new
    assert any('legend text "a curve"' in p for p in new), new
    phone = [float(m.group(1)) for p in new
             if (m := re.search(r"smallest text ([\d.]+) px at 342 px", p))]
    assert len(phone) == 1 and 5.5 < phone[0] < 7.0, new  # 6 px, a little more: tight box
    buf = io.BytesIO()
    _readable_figure().savefig(buf, format="png", dpi=192)
    plain = base64.b64encode(buf.getvalue()).decode()
    injected[name] = (path, html.replace(
        "</article>", f'<img alt="plain" src="data:image/png;base64,{plain}"></article>', 1))
    s3, m3, p3 = measure_figures(injected)
    assert (s3, m3) == (shown + 1, measured)
    new = [p for p in p3 if p not in problems]
    assert len(new) == 1 and "'plain'" in new[0] and "not measured" in new[0], new
    # a figure 6 in wide, its texts 12.5 pt (readable at both columns): too wide, and
    # nothing else
    from matplotlib.text import Text

    wide = _readable_figure()
    wide.set_figwidth(6.0)
    wide.axes[0].tick_params(labelsize=12.5)
    for t in wide.findobj(Text):
        t.set_fontsize(12.5)
    injected[name] = (path, html.replace("</article>", _img_tag(wide, "wide") + "</article>",
                                         1))
    s4, m4, p4 = measure_figures(injected)
    assert (s4, m4) == (shown + 1, measured + 1)
    new = [p for p in p4 if p not in problems]
    assert len(new) == 1 and "'wide'" in new[0] and "6 in wide (> 5 in)" in new[0], new
