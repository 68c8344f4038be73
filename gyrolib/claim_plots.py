"""A claim's map in view: its figure and its table of thresholds.

:func:`plot_claim_map` takes a :class:`gyrolib.claim_map.ClaimMap` (stored or computed) and
draws, for each numeric input that flips the claim, the margin over the input's range from
the map's one-at-a-time sweep (the others at the reference), the claim's boundary (margin
0), each threshold of that input as a vertical line at its value and the reference as a
star: a reader sees which inputs matter and how far the reference is from each edge.
:func:`threshold_table` gives the same map as a table of thresholds, each symbol defined.
Every number the table quotes is formatted by the book's one formatter
(:func:`gyrolib.claim_map.quote_threshold`, :meth:`gyrolib.claim_map.Share.text`, both over
:mod:`gyrolib.quote`), tagged with the claim for a page when asked.

Nothing here computes a margin: the figure is the stored sweep, the table the stored
thresholds.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, Final

import numpy as np

from gyrolib import _validation as v
from gyrolib import inputs as _inputs
from gyrolib._page_figures import SMALL_PT, for_the_page
from gyrolib.claim_map import ClaimMap, quote_threshold
from gyrolib.units import from_si

__all__ = ["PANEL_HEIGHT_IN", "SYMLOG_RATIO", "input_axis", "plot_claim_map", "plotted_inputs",
           "threshold_table"]

#: The height of one input's panel (inches); the figure is 5 in wide, the panels stacked.
PANEL_HEIGHT_IN: Final[float] = 1.55

#: A panel's margin axis is symmetric-logarithmic (linear within the reference's |margin|)
#: when the sweep reaches this many times farther from the boundary than the reference does.
SYMLOG_RATIO: Final[float] = 20.0

#: Unit labels as the book prints them (the rows' ``shown`` units).
_LABELS: Final[dict[str, str]] = {"arcsec_paper": "″", "arcsec_paper/s": "″/s", "deg": "°",
                                  "deg/s": "°/s", "deg/h": "°/h", "1": ""}


def input_axis(name: str, values: Any) -> np.ndarray:
    """Values (SI) of row ``name`` in the unit its figure axis shows (the row's ``shown``
    unit, else SI): the x of :func:`plot_claim_map`'s panels.

    Examples
    --------
    >>> float(input_axis("rsf.omega_x", np.radians(900.0))[()])
    900.0
    """
    r = _inputs.row(name)
    x = np.asarray(values, dtype=float)
    return np.asarray(from_si(x, r.shown), dtype=float) if r.shown else x


def _unit_label(name: str) -> str:
    r = _inputs.row(name)
    u = r.shown or r.unit
    return _LABELS.get(u, u)


def plotted_inputs(m: ClaimMap, n_closest: int = 2) -> tuple[str, ...]:
    """The rows :func:`plot_claim_map` draws by default: every numeric row that flips the
    claim (a threshold within its range), in the map's order; when none does, the
    ``n_closest`` rows whose sweep comes nearest to the boundary (margin 0), so that a claim
    no single input flips still shows how far it stays from it."""
    v.check_instance("m", m, ClaimMap)
    flips = tuple(dict.fromkeys(t.input for t in m.thresholds if t.input in m.sweeps))
    if flips:
        return flips
    gap = {n: min(abs(y) for _, y in pts) for n, pts in m.sweeps.items()
           if pts and any(y != m.margin for _, y in pts)}
    return tuple(sorted(gap, key=gap.__getitem__)[:n_closest])


def plot_claim_map(m: ClaimMap, inputs: Sequence[str] | None = None, *,
                   n_closest: int = 2, unit: str = "") -> Any:
    """The map of a claim: its margin over each flipping input's range, one panel each.

    Each panel is one row of the table of inputs varied alone over its range (the others at
    the reference), from the map's stored sweep (``m.sweeps``: the grid the thresholds were
    bracketed on): the margin (solid, dots at the grid's points), the claim's boundary
    (margin 0, dashed), each threshold of that row (a vertical line at its value; which side
    holds is where the margin is positive) and the reference point (a star).  A sweep that
    reaches far beyond the reference's distance from the boundary is drawn on a
    symmetric-logarithmic margin axis (:data:`SYMLOG_RATIO`), so that the boundary stays
    visible.  The x axis is the row's range in the unit the book shows it
    (:func:`input_axis`), on the row's scale.

    Parameters
    ----------
    m : ClaimMap
        The map (:func:`gyrolib.claim_map.map_claim`, or a stored one).
    inputs : sequence of str, optional
        The rows to draw (default: :func:`plotted_inputs`); each must have a sweep in ``m``.
    n_closest : int, default 2
        With ``inputs`` not given and no row flipping the claim: how many rows to draw.
    unit : str, optional
        The margin's unit for the y label (the claim's ``unit``; none by default).

    Returns
    -------
    matplotlib.figure.Figure
        One axes per row, stacked; each threshold line carries ``gid`` ``"threshold:<row>"``
        and the star ``gid`` ``"reference"``.

    Examples
    --------
    >>> from gyrolib import claim_map
    >>> from gyrolib.claim_plots import plot_claim_map
    >>> c = claim_map.Claim("demo", claim_map.demo_margin, ("gc.sigma1_sq", "gc.C_as"),
    ...                     "2 - sigma1_sq/reference")
    >>> fig = plot_claim_map(claim_map.map_claim(c, n_box=0))
    >>> [ax.get_xlabel() for ax in fig.axes]
    ['σ1² (m²/s⁴)']
    """
    import matplotlib.pyplot as plt

    v.check_instance("m", m, ClaimMap)
    names = plotted_inputs(m, n_closest) if inputs is None else tuple(inputs)
    missing = [n for n in names if n not in m.sweeps]
    if missing:
        raise ValueError(f"inputs: {missing[0]!r} has no sweep in the map of {m.claim}; "
                         f"rows with one: {', '.join(m.sweeps) or 'none'}")
    if not names:
        raise ValueError(f"the map of {m.claim} has no sweep to draw")
    fig, axes = plt.subplots(len(names), 1, figsize=(5.0, 0.35 + PANEL_HEIGHT_IN * len(names)),
                             layout="constrained", squeeze=False)
    for ax, name in zip(axes[:, 0], names, strict=True):
        _panel(ax, m, name, unit)
    handles, labels = _legend_handles()
    if not any(t.input in names for t in m.thresholds):   # no threshold line drawn
        del handles[1], labels[1]
    fig.legend(handles, labels, loc="outside lower center", ncols=len(labels),
               fontsize=SMALL_PT, frameon=False)
    return for_the_page(fig)


def _legend_handles() -> tuple[list[Any], list[str]]:
    from matplotlib.lines import Line2D

    return ([Line2D([], [], color="tab:blue", marker=".", lw=1.2),
             Line2D([], [], color="tab:red", lw=1.2),
             Line2D([], [], color="k", marker="*", ls="none", ms=10)],
            ["margin (> 0: holds)", "threshold", "reference"])


def _panel(ax: Any, m: ClaimMap, name: str, unit: str) -> None:
    r = _inputs.row(name)
    pts = np.asarray(m.sweeps[name], dtype=float)
    x, y = input_axis(name, pts[:, 0]), pts[:, 1]
    ax.plot(x, y, ".-", color="tab:blue", lw=1.2, ms=5)
    ax.axhline(0.0, color="0.45", lw=0.8, ls="--")
    for t in (t for t in m.thresholds if t.input == name):
        xt = float(input_axis(name, t.value))
        ax.axvline(xt, color="tab:red", lw=1.2, gid=f"threshold:{name}")
    xr = float(input_axis(name, m.reference[name]))
    ax.plot([xr], [m.margin], "*", color="k", ms=11, gid="reference", zorder=5)
    if r.scale == "log" and np.all(x > 0):
        ax.set_xscale("log")
    near = max(abs(m.margin), 1e-12)
    if np.nanmax(np.abs(y)) > SYMLOG_RATIO * near:  # the far margins would flatten the edge
        ax.set_yscale("symlog", linthresh=near)
        # ticks at 0 and the decades beyond the linear part (ticks inside it would collide)
        lo, hi = float(np.nanmin([*y, m.margin])), float(np.nanmax([*y, m.margin]))
        top = math.ceil(math.log10(max(abs(lo), abs(hi))))
        ticks = [0.0] + [sg * 10.0**k for k in range(math.ceil(math.log10(near)), top + 1)
                         for sg in (-1.0, 1.0) if lo <= sg * 10.0**k <= hi]
        ax.set_yticks(sorted(ticks))
    label = _unit_label(name)
    ax.set_xlabel(f"{r.symbol} ({label})" if label else r.symbol)
    ax.set_ylabel("margin" + (f" ({unit})" if unit not in ("", "1") else ""))
    ax.tick_params(labelsize=SMALL_PT)


def _md(text: str) -> str:
    return text.replace("|", "\\|").replace("*", "\\*").replace("_", "\\_")


def threshold_table(m: ClaimMap, html: bool = False) -> str:
    """The map of a claim as a Markdown table: one line per input that flips it (symbol,
    what it is, where it flips, on which side the claim holds, the reference value), the
    readings under which its status differs, the isolated failing points of a search, and
    the share of the box where it holds.  Each symbol is defined in its line (the table of
    inputs' row name and the first clause of its reason).  With ``html``, each threshold and
    the share are tagged with the claim for a page (:mod:`gyrolib.quote`).

    Examples
    --------
    >>> from gyrolib import claim_map
    >>> c = claim_map.Claim("demo", claim_map.demo_margin, ("gc.sigma1_sq", "gc.C_as"),
    ...                     "2 - sigma1_sq/reference")
    >>> line = threshold_table(claim_map.map_claim(c, n_box=0)).splitlines()[2]
    >>> line.split(" | ")[2:4]
    ['3.72·10⁻⁶ m²/s⁴ (2 × the reference)', 'below']
    """
    v.check_instance("m", m, ClaimMap)
    rows = ["| input | what it is | flips at | the claim holds | reference |",
            "| --- | --- | --- | --- | --- |"]
    for t in m.thresholds:
        r = _inputs.row(t.input)
        quoted = quote_threshold(m.claim, t, html=html)
        rows.append(f"| {_md(r.symbol)} | {_define(r)} | {quoted} | "
                    f"{t.holds_when} | {_md(r.show(m.reference[t.input]))} |")
    for f in m.isolated:
        if f.points:
            r = _inputs.row(f.input)
            rows.append(f"| {_md(r.symbol)} | {_define(r)} | at {len(f.points)} isolated "
                        f"values ({f.searched} searched) | between them | "
                        f"{_md(r.show(m.reference[f.input]))} |")
    ref = "holds" if m.margin > 0 else "fails"
    for name, st in m.readings.items():
        if any(s != ref for s in st.values()):
            r = _inputs.row(name)
            rows.append(f"| {_md(r.symbol)} | {_define(r)} (a reading) | "
                        + _md(", ".join(f"{k}: {s}" for k, s in st.items()))
                        + f" | under {_md(next(k for k, s in st.items() if s == 'holds'))}"
                        if any(s == "holds" for s in st.values()) else " | never")
            rows[-1] += f" | {_md(str(m.reference[name]))} |"
    if len(rows) == 2:
        rows.append(f"| — | no input flips it alone within its range | — | "
                    f"{'everywhere' if m.margin > 0 else 'nowhere'} | — |")
    rows.append("| the box | every uncertain input drawn at once | — | at "
                + ("—" if m.share_holding is None else m.share_holding.text(m.claim, html))
                + " | — |")
    return "\n".join(rows)


def _define(r: Any) -> str:
    """The row's definition for the table: its name in the table of inputs and the first
    clause of its reason (what it is, where the paper prints it)."""
    what = r.reason.split(";")[0].strip()
    return f"`{r.name}`: {_md(what)}"
