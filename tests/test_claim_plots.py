"""The figure and the table of a claim's map (gyrolib.claim_plots): each threshold line at
the map's threshold, the star at the reference, every text legible at a phone's column, and
the table quoting every threshold with its symbol defined."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from gyrolib import claim_map as cm
from gyrolib import claim_plots as cp
from gyrolib import inputs
from gyrolib._page_figures import text_problems
from gyrolib.claim_map import quote_threshold
from gyrolib.units import from_si

TWO = ("gc.sigma1_sq", "gc.sigma_psi0")


def two_flips(o):
    """Holds while σ1² is below 2× its reference and σ_ψ(0) above 0.5× its reference."""
    p = o["GyrocompassParams"]
    return min(2.0 - p.sigma1_sq / 1.86e-6, p.sigma_psi0 / inputs.row("gc.sigma_psi0")
               .reference - 0.5)


@pytest.fixture(scope="module")
def demo():
    return cm.map_claim(cm.Claim("demo", two_flips, TWO, "two flips"), n_box=16)


def _lines(fig, gid):
    return [ln for ax in fig.axes for ln in ax.get_lines() if ln.get_gid() == gid]


def test_threshold_lines_sit_at_the_maps_thresholds(demo):
    """One panel per flipping row; each threshold line's x is the map's threshold in the
    row's shown unit (converted here by gyrolib.units), the star at the reference."""
    fig = cp.plot_claim_map(demo)
    assert len(fig.axes) == 2
    for ax, t in zip(fig.axes, demo.thresholds, strict=True):
        (line,) = [ln for ln in ax.get_lines() if ln.get_gid() == f"threshold:{t.input}"]
        shown = inputs.row(t.input).shown
        want = float(from_si(t.value, shown)) if shown else t.value
        assert np.allclose(line.get_xdata(), want, rtol=1e-12)
        (star,) = [ln for ln in ax.get_lines() if ln.get_gid() == "reference"]
        ref = demo.reference[t.input]
        assert star.get_xdata()[0] == pytest.approx(float(from_si(ref, shown)) if shown
                                                    else ref, rel=1e-12)
        assert star.get_ydata()[0] == pytest.approx(demo.margin)
    # the closed forms: σ1² flips at 2× its reference, σ_ψ(0) at 0.5×
    assert [round(t.factor, 2) for t in demo.thresholds] == [2.0, 0.5]


def test_a_moved_threshold_moves_its_line(demo):
    """Power: a map whose threshold is moved draws its line at the moved value, not at the
    old one."""
    t = demo.thresholds[0]
    moved = dataclasses.replace(demo, thresholds=(dataclasses.replace(t, value=1.5 * t.value),
                                                  *demo.thresholds[1:]))
    (line,) = _lines(cp.plot_claim_map(moved), f"threshold:{t.input}")
    assert not np.allclose(line.get_xdata(), cp.input_axis(t.input, t.value))


def test_every_text_reads_at_a_phones_column(demo):
    """Tick labels and every other text: at least 9 px at the phone's 342-px column (and
    9 pt at the desk's), no collisions (gyrolib._page_figures.text_problems)."""
    fig = cp.plot_claim_map(demo)
    assert text_problems(fig) == []
    assert fig.get_figwidth() <= 5.0


def test_no_flipping_input_draws_the_nearest(demo):
    """A map with no threshold draws the rows whose sweeps come nearest to the boundary; a
    row without a sweep is refused by name."""
    none = dataclasses.replace(demo, thresholds=())
    assert cp.plotted_inputs(none, n_closest=1) in (("gc.sigma1_sq",), ("gc.sigma_psi0",))
    with pytest.raises(ValueError, match=r"gc\.C_as"):
        cp.plot_claim_map(demo, ["gc.C_as"])
    with pytest.raises(TypeError, match="m"):
        cp.plot_claim_map("not a map")


def test_table_defines_each_symbol_and_quotes_each_threshold(demo):
    """One line per threshold with the row's symbol, its table name and what it is, the
    threshold as the book's formatter gives it (tagged for a page with html=True), and the
    share's line."""
    text = cp.threshold_table(demo)
    for t in demo.thresholds:
        r = inputs.row(t.input)
        sym = r.symbol.replace("_", "\\_")
        (line,) = [ln for ln in text.splitlines() if ln.startswith(f"| {sym} |")]
        assert f"`{r.name}`:" in line
        assert quote_threshold(demo.claim, t) in line
        assert f"| {t.holds_when} |" in line
    assert demo.share_holding.text(demo.claim) in text.splitlines()[-1]
    tagged = cp.threshold_table(demo, html=True)
    assert tagged.count(f'data-claim="{demo.claim}"') == len(demo.thresholds) * 2 + 1
