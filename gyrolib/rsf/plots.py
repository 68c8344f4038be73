"""Figures of paper RSF: the functional schemes (Figures 1 and 2) as block diagrams, the
gravity projection and lateral error growth (Figure 3), and the simulation's results.

Every function takes result objects (or, for the schemes and Figure 3, closed-form data in
SI) and returns a :class:`matplotlib.figure.Figure`; nothing here computes a result and
nothing here validates: the inputs were checked where the results were computed.
"""

from __future__ import annotations

from collections.abc import Sequence
from itertools import pairwise

import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Circle, FancyArrowPatch, FancyBboxPatch, Polygon

from gyrolib import _validation as v
from gyrolib._page_figures import SMALL_PT, legend_below, page_figure
from gyrolib.rsf.calibration import CalibrationResult
from gyrolib.rsf.claims import CompensationShare
from gyrolib.rsf.correction import CorrectionRun, DeltaKPrediction
from gyrolib.rsf.simulation import SensorRecord
from gyrolib.rsf.sweeps import PeriodSweep, RateSweep, ResolutionSweep
from gyrolib.units import from_si

__all__ = [
    "plot_compensation_share",
    "plot_correction",
    "plot_delta_k_distribution",
    "plot_encoder_sweep",
    "plot_figure3",
    "plot_flight",
    "plot_gs_scheme",
    "plot_method_scheme",
    "plot_period_sweep",
    "plot_rate_sweep",
    "plot_spin_up",
]


# Block-diagram primitives ----------------------------------------------------------------------
class _Diagram:
    """Boxes, summing junctions and arrows on an axes whose unit is the inch, laid out from
    the top: a point is ``(x, d)``, ``x`` from the left edge and ``d`` down from the top edge
    of a figure :data:`~gyrolib._page_figures.MAX_WIDTH_IN` wide (the signal flows down the
    page, so that the text reads at the page's size on a phone)."""

    def __init__(self, height: float, width: float = 5.0):
        self.height = height
        self.fig = Figure(figsize=(width, height))
        self.ax = self.fig.add_axes((0.0, 0.0, 1.0, 1.0))
        self.ax.set_xlim(0, width)
        self.ax.set_ylim(0, height)
        self.ax.set_aspect("equal")
        self.ax.axis("off")

    def xy(self, p: tuple[float, float]) -> tuple[float, float]:
        return p[0], self.height - p[1]

    def text(self, x: float, d: float, text: str, **kw) -> None:
        self.ax.text(*self.xy((x, d)), text, fontsize=kw.pop("fontsize", SMALL_PT), **kw)

    def box(self, x: float, d: float, w: float, h: float, text: str, *,
            color: str = "#e8f0fb") -> dict[str, tuple[float, float]]:
        """A rounded box centred at (x, d); returns its side midpoints (x, d)."""
        x0, y0 = self.xy((x - w / 2, d + h / 2))
        self.ax.add_patch(FancyBboxPatch((x0, y0), w, h,
                                         boxstyle="round,pad=0.02,rounding_size=0.08",
                                         fc=color, ec="#1f3b63", lw=1.2))
        self.text(x, d, text, ha="center", va="center")
        return {"l": (x - w / 2, d), "r": (x + w / 2, d), "t": (x, d - h / 2),
                "b": (x, d + h / 2)}

    def junction(self, x: float, d: float, r: float = 0.19, symbol: str = "Σ",
                 signs: dict[str, str] | None = None) -> dict[str, tuple[float, float]]:
        """A summing junction; ``signs`` maps sides ("l", "r", "t", "b") to "+" or "−"."""
        self.ax.add_patch(Circle(self.xy((x, d)), r, fc="white", ec="#1f3b63", lw=1.2))
        self.text(x, d, symbol, ha="center", va="center")
        offsets = {"l": (-1.7 * r, -0.9 * r), "t": (0.9 * r, -1.7 * r),
                   "b": (0.9 * r, 1.7 * r), "r": (1.7 * r, -0.9 * r)}
        for side, sign in (signs or {}).items():
            dx, dd = offsets[side]
            self.text(x + dx, d + dd, sign, ha="center", va="center", fontweight="bold")
        return {"l": (x - r, d), "r": (x + r, d), "t": (x, d - r), "b": (x, d + r)}

    def arrow(self, points: Sequence[tuple[float, float]]) -> None:
        """A polyline through ``points`` (x, d) ending in an arrowhead."""
        pts = [self.xy(p) for p in points]
        for p, q in pairwise(pts[:-1]):
            self.ax.plot([p[0], q[0]], [p[1], q[1]], color="#1f3b63", lw=1.2)
        self.ax.add_patch(FancyArrowPatch(pts[-2], pts[-1], arrowstyle="-|>",
                                          mutation_scale=12, color="#1f3b63", lw=1.2,
                                          shrinkA=0, shrinkB=0))

    def line(self, points: Sequence[tuple[float, float]]) -> None:
        pts = [self.xy(p) for p in points]
        self.ax.plot([p[0] for p in pts], [p[1] for p in pts], color="#1f3b63", lw=1.2)

    def dot(self, x: float, d: float) -> None:
        self.ax.plot(*self.xy((x, d)), "o", color="#1f3b63", ms=4)


@page_figure
def plot_method_scheme() -> Figure:
    """Paper RSF, Figure 1: functional scheme of the correction method, drawn top to bottom
    (the vehicle's rate at the top, the coefficient ``K_i`` fed back at the bottom)."""
    d = _Diagram(6.0)
    veh = d.box(2.4, 0.35, 2.3, 0.45, r"vehicle: roll rate $\omega$")
    gyro = d.box(1.2, 1.45, 2.2, 0.7, "SINS roll gyro\n"
                 r"$\omega_x = (1+\varepsilon_1)\,\omega + \varepsilon_0$")
    gs = d.box(3.65, 1.45, 2.1, 0.7, "indicator GS\n(MEMS gyro + encoder)")
    d.dot(2.4, 0.85)
    d.line([veh["b"], (2.4, 0.85)])
    d.arrow([(2.4, 0.85), (gyro["t"][0], 0.85), gyro["t"]])
    d.arrow([(2.4, 0.85), (gs["t"][0], 0.85), gs["t"]])
    tap = (1.2, 2.55)
    integ = d.box(2.6, 2.55, 1.3, 0.6, r"$\int\omega_x\,dt$" "\n" r"over $\Delta t$")
    d.line([gyro["b"], tap])
    d.dot(*tap)
    d.text(1.3, 2.05, r"$\omega_x$ (measurement 1)", ha="left", va="center")
    d.arrow([tap, integ["l"]])
    summ = d.junction(3.65, 3.25, signs={"l": "+", "t": "−"})
    d.text(3.95, 3.35, "Eq. (1)", ha="left", va="center")
    d.arrow([integ["b"], (integ["b"][0], summ["l"][1]), summ["l"]])
    d.text(2.7, 3.12, r"$\gamma_{SINS}$", ha="left", va="bottom")
    d.arrow([gs["b"], summ["t"]])
    d.text(3.75, 2.3, r"$\gamma_{GS}$" "\n(measurement 2)", ha="left", va="center")
    est = d.box(3.65, 4.15, 2.4, 0.7,
                r"$\hat\varepsilon_1 = \Delta\gamma_i/(\omega_x\Delta t)$" "\nEq. (2)")
    d.arrow([summ["b"], est["t"]])
    d.text(3.75, 3.62, r"$\Delta\gamma_i$", ha="left", va="center")
    coef = d.box(3.65, 5.2, 2.4, 0.7, r"$K_i = 1 - \hat\varepsilon_1$" "\n"
                 r"held for the next $\Delta t$")
    d.arrow([est["b"], coef["t"]])
    mult = d.junction(1.2, 3.75, symbol="×")
    d.arrow([tap, mult["t"]])
    nav = d.box(1.2, 5.05, 1.7, 0.7, "SINS navigation\nalgorithm")
    d.arrow([mult["b"], nav["t"]])
    d.text(1.3, 4.3, r"$\hat\omega_x = K_i\,\omega_x$" "\n(Eq. 3)", ha="left", va="center")
    d.arrow([coef["b"], (coef["b"][0], 5.8), (0.15, 5.8), (0.15, mult["l"][1]), mult["l"]])
    d.text(2.0, 5.75, r"$K_i$", ha="center", va="bottom")
    return d.fig


@page_figure
def plot_gs_scheme() -> Figure:
    """Paper RSF, Figure 2: functional scheme of the indicator gyrostabilizer (GS), drawn top
    to bottom (the vehicle's rate at the top, the GS's angle estimate at the bottom)."""
    d = _Diagram(5.45)
    sum1 = d.junction(1.2, 0.75, signs={"t": "+", "r": "+"})
    d.arrow([(1.2, 0.05), sum1["t"]])
    d.text(1.3, 0.28, r"$\omega$ (vehicle)", ha="left", va="center")
    plat = d.box(1.2, 1.55, 1.5, 0.45, "platform")
    d.arrow([sum1["b"], plat["t"]])
    d.text(1.1, 1.13, r"$\omega_{unc}$", ha="right", va="center")
    mems = d.box(1.2, 2.45, 2.2, 0.7, "MEMS gyro\n"
                 r"$(1+\varepsilon_{1GS})\,\omega_{unc} + \varepsilon_{0GS}$")
    d.arrow([plat["b"], mems["t"]])
    tap = (1.2, 3.2)
    d.line([mems["b"], tap])
    d.dot(*tap)
    d.text(1.1, 3.0, r"$\hat\omega_{unc}$", ha="right", va="center")
    integ = d.box(1.2, 3.75, 1.0, 0.45, r"$\int dt$")
    d.arrow([tap, integ["t"]])
    pi = d.box(3.5, 3.2, 1.7, 0.45, "PI controller")
    d.arrow([tap, pi["l"]])
    motor = d.box(3.5, 2.1, 1.7, 0.6, "motor\n(speed limit)")
    d.arrow([pi["t"], motor["b"]])
    d.text(3.6, 2.62, "u", ha="left", va="center")
    tap2 = (3.5, 0.75)
    d.line([motor["t"], tap2])
    d.dot(*tap2)
    d.text(3.6, 1.3, r"$W_r$", ha="left", va="center")
    d.arrow([tap2, sum1["r"]])
    enc = d.box(3.5, 4.55, 2.1, 0.65, "encoder\n" r"$\gamma_{enc} = -\int W_r\,dt$")
    d.arrow([tap2, (4.75, 0.75), (4.75, 4.55), enc["r"]])
    sum2 = d.junction(1.2, 4.55, signs={"t": "+", "r": "+"})
    d.arrow([integ["b"], sum2["t"]])
    d.text(1.1, 4.17, r"$\gamma_{unc}$", ha="right", va="center")
    d.arrow([enc["l"], sum2["r"]])
    d.text(1.9, 4.47, r"$\gamma_{enc}$", ha="center", va="bottom")
    d.arrow([sum2["b"], (1.2, 5.4)])
    d.text(1.3, 5.1, r"$\hat\gamma = \gamma_{enc} + \gamma_{unc}$", ha="left",
           va="center")
    return d.fig


# Figure 3 ----------------------------------------------------------------------------------------
@page_figure
def plot_figure3(dgamma_example: float, t: np.ndarray, roll_error: np.ndarray,
                 acc_exact: np.ndarray, acc_small: np.ndarray, dr_exact: np.ndarray,
                 dr_cubic: np.ndarray, table_t: Sequence[float] = (),
                 printed_dr: Sequence[float] = ()) -> Figure:
    """Paper RSF, Figure 3 and Eq. (8): (a) gravity resolved with a roll error
    ``dgamma_example`` (rad); (b) Δa_z = g sin Δγ against g Δγ; (c) Δr_z, exact double
    integral against the cubic, with the printed Table 2 values (unit lost) as markers.
    The three panels are stacked."""
    t, roll_error, dr_exact, dr_cubic = (np.asarray(a, dtype=float)
                                         for a in (t, roll_error, dr_exact, dr_cubic))
    fig = Figure(figsize=(5.0, 11.0), layout="constrained")
    # stacked for the page: the sketch, then the two plots
    ax0, ax1, ax2 = fig.subplots(3, 1, height_ratios=[0.8, 1.0, 1.0])
    # (a) geometry: body cross-section, true vertical and the vertical the SINS believes.
    ax0.set_aspect("equal")
    ax0.axis("off")
    ax0.add_patch(Circle((0, 0), 1.0, fc="#f3f3f3", ec="#555555"))
    ax0.annotate("", (0, -1.45), (0, 0), arrowprops={"arrowstyle": "-|>", "color": "k"})
    ax0.text(-0.12, -1.4, "g", fontsize=11, ha="right")
    dg = dgamma_example
    tip = (1.45 * np.sin(dg), -1.45 * np.cos(dg))
    ax0.annotate("", tip, (0, 0), arrowprops={"arrowstyle": "-|>", "color": "#c0392b",
                                              "ls": "--"})
    ax0.text(tip[0] + 0.1, tip[1] + 0.35, "g as resolved\nby the SINS", color="#c0392b",
             fontsize=SMALL_PT, va="center", ha="left")
    ax0.plot([0, tip[0]], [tip[1], tip[1]], color="#2e86c1", lw=0.8, ls=":")
    ax0.annotate("", tip, (0, tip[1]),
                 arrowprops={"arrowstyle": "-|>", "color": "#2e86c1", "lw": 2})
    ax0.text(0.5 * tip[0], tip[1] - 0.15, r"$\Delta a_z = g\,\sin\Delta\gamma$",
             color="#2e86c1", fontsize=SMALL_PT, ha="center", va="top")
    arc = np.linspace(-np.pi / 2, -np.pi / 2 + dg, 30)
    ax0.plot(0.55 * np.cos(arc), 0.55 * np.sin(arc), color="k", lw=0.8)
    ax0.text(0.22, -0.72, r"$\Delta\gamma$", fontsize=SMALL_PT)
    ax0.add_patch(Polygon([[-0.06, 0.06], [0.06, 0.06], [0.06, -0.06], [-0.06, -0.06]],
                          fc="k"))
    ax0.set_xlim(-1.2, 2.1)
    ax0.set_ylim(-2.0, 1.2)
    ax0.set_title("(a) gravity and a roll error", fontsize=10, loc="left")
    # (b) lateral acceleration error.
    ax1.plot(t, acc_small, "--", color="#7f8c8d", label=r"$g\,\Delta\gamma$ (first approximation)")
    ax1.plot(t, acc_exact, color="#2e86c1", label=r"$g\,\sin\Delta\gamma$")
    ax1.axhline(0, color="k", lw=0.5)
    twin = ax1.twiny()
    twin.set_xlim(from_si(roll_error[0], "deg"), from_si(roll_error[-1], "deg"))
    twin.set_xlabel(r"$\Delta\gamma_{SINS}$ (°)", fontsize=SMALL_PT)
    ax1.set_xlim(t[0], t[-1])
    ax1.set_xlabel("t (s)")
    ax1.set_ylabel(r"$\Delta a_z$ (m/s²)")
    ax1.legend(fontsize=SMALL_PT, loc="lower left")  # under the rising curve, clear of it
    # the top axis carries Δγ: the panel's name goes above its label
    ax1.set_title("(b) gravity mis-resolved onto z", fontsize=10, loc="left", pad=22)
    # (c) lateral deviation.
    pos = t >= 1.0
    ax2.loglog(t[pos], dr_cubic[pos], "--", color="#7f8c8d",
               label=r"$g\,\varepsilon_1\omega t^3/6$ (Eq. 8)")
    ax2.loglog(t[pos], dr_exact[pos], color="#2e86c1",
               label=r"$\iint g\,\sin\Delta\gamma\;dt\,dt$ (exact)")
    if len(table_t):
        ax2.loglog(table_t, printed_dr, "s", color="#c0392b", mfc="none",
                   label="Table 2 as printed (unit lost)")
    ax2.set_xlabel("t (s)")
    ax2.set_ylabel(r"$\Delta r_z$ (m)")
    # below the panel: in it, it would cover the curves or the printed values
    ax2.legend(fontsize=SMALL_PT, loc="upper center", bbox_to_anchor=(0.5, -0.2))
    ax2.grid(True, which="both", alpha=0.3)
    ax2.set_title("(c) lateral deviation", fontsize=10, loc="left")
    return fig


# Simulation figures ---------------------------------------------------------------------------
@page_figure
def plot_flight(run: CorrectionRun, reset: CorrectionRun | None = None, *,
                index: int = 0) -> Figure:
    """Roll-angle error (°) and lateral error (m) of one simulated flight (run ``index``),
    with and without the correction of paper RSF, Eqs. (1)–(3); ``reset`` adds the same
    correction with the SINS angle reset to the GS angle.  The correction instants are
    vertical ticks.

    Parameters
    ----------
    run : CorrectionRun
        From :func:`~gyrolib.rsf.run_correction`.
    reset : CorrectionRun, optional
        The run with ``reset_angle=True``.
    index : int, optional
        Which run of the ensemble.

    Returns
    -------
    matplotlib.figure.Figure
    """
    t = run.t
    fig = Figure(figsize=(5.0, 7.6), layout="constrained")
    ax0, ax1 = fig.subplots(2, 1, sharex=True)  # stacked for the page
    ax0.plot(t, from_si(run.roll_error_raw[index], "deg"), color="#c0392b",
             label="SINS, uncorrected")
    ax0.plot(t, from_si(run.roll_error_corrected[index], "deg"), color="#2e86c1",
             label="SINS, corrected")
    if reset is not None:
        ax0.plot(t, from_si(reset.roll_error_corrected[index], "deg"), color="#27ae60",
                 label="corrected + angle reset")
    ax0.plot(t, from_si(run.roll_error_gs[index], "deg"), color="#7f8c8d", lw=0.8,
             label="GS reference")
    for tb in run.t_boundaries:
        ax0.axvline(tb, color="k", lw=0.3, alpha=0.4)
    ax0.set_yscale("symlog", linthresh=0.1)
    ax0.set_ylabel("roll-angle error (°)")
    ax0.legend(fontsize=SMALL_PT)
    ax1.plot(t, run.lateral_raw[index], color="#c0392b", label="uncorrected")
    ax1.plot(t, run.lateral_corrected[index], color="#2e86c1", label="corrected")
    if reset is not None:
        ax1.plot(t, reset.lateral_corrected[index], color="#27ae60",
                 label="corrected + angle reset")
    ax1.set_yscale("symlog", linthresh=1.0)
    ax1.set_xlabel("t (s)")
    ax1.set_ylabel("lateral error Δr_z (m)")
    ax1.legend(fontsize=SMALL_PT)
    return fig


@page_figure
def plot_delta_k_distribution(run: CorrectionRun, prediction: DeltaKPrediction) -> Figure:
    """Histogram of simulated δK (one value per run and interval) against the predicted
    mean ± std and Eq. (7) of paper RSF.

    Parameters
    ----------
    run : CorrectionRun
        From :func:`~gyrolib.rsf.run_correction`.
    prediction : DeltaKPrediction
        From :func:`~gyrolib.rsf.predict_delta_k` for the same configuration and period.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = Figure(figsize=(5.0, 3.6), layout="constrained")
    ax = fig.subplots()
    ax.hist(from_si(run.delta_k.ravel(), "ppm"), bins=40, color="#aed6f1", ec="#2e86c1",
            label="simulation (per run and interval)")
    ax.axvline(from_si(prediction.mean, "ppm"), color="k", label="predicted mean")
    for s in (-1, 1):
        ax.axvline(from_si(prediction.mean + s * prediction.std, "ppm"), color="k", ls=":",
                   label="predicted mean ± σ" if s == 1 else None)
    ax.axvline(from_si(prediction.eq7, "ppm"), color="#c0392b", lw=2, label="Eq. (7), 280 ppm")
    ax.set_xlabel("δK (ppm)")
    ax.set_ylabel("count")
    # below the axes: the histogram fills the whole width of its panel
    legend_below(fig, ax)
    return fig


@page_figure
def plot_period_sweep(sweep: PeriodSweep, *, net_floor: bool = True) -> Figure:
    """rms δK against the correction period, with the prediction, Eq. (7) of paper RSF, the
    systematic floor, the uncorrected scale-factor error and (``net_floor``) the floor net of
    the SINS bias that K absorbs.

    Parameters
    ----------
    sweep : PeriodSweep
        From :func:`~gyrolib.rsf.sweep_correction_period`.
    net_floor : bool, optional
        Draw the net floor (default True).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = Figure(figsize=(5.0, 5.0), layout="constrained")
    ax = fig.subplots()
    p = sweep.periods
    ax.loglog(p, from_si(sweep.rms, "ppm"), "o", color="#2e86c1", label="simulation, rms δK")
    ax.loglog(p, from_si(sweep.predicted_rms, "ppm"), "-", color="#2e86c1", lw=0.8,
              label="predicted rms")
    ax.loglog(p, from_si(sweep.eq7, "ppm"), "--", color="#c0392b", label="Eq. (7)")
    ax.axhline(from_si(sweep.floor, "ppm"), color="k", ls=":",
               label="floor (ε0,GS + ε1,GS ω_unc)/ω")
    ax.axhline(from_si(sweep.eps1, "ppm"), color="#7f8c8d", label="uncorrected ε1")
    if net_floor:
        ax.axhline(from_si(abs(sweep.net_floor), "ppm"), color="k", ls="-.", lw=0.8,
                   label="net floor, with the SINS bias absorbed")
    ax.set_xlabel("correction period Δt (s)")
    ax.set_ylabel("residual SF error δK (ppm)")
    ax.grid(True, which="both", alpha=0.3)
    legend_below(fig, ax)  # six entries: inside, they cover the curves
    return fig


@page_figure
def plot_encoder_sweep(with_error: ResolutionSweep, without_error: ResolutionSweep) -> Figure:
    """rms δK against the encoder's counts per revolution, with and without its position
    error (paper RSF: "an encoder of higher resolution").

    Parameters
    ----------
    with_error, without_error : ResolutionSweep
        From :func:`~gyrolib.rsf.sweep_encoder` over the same counts.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = Figure(figsize=(5.0, 3.8), layout="constrained")
    ax = fig.subplots()
    c = with_error.counts_per_rev
    ax.loglog(c, from_si(with_error.rms, "ppm"), "o", color="#2e86c1",
              label="simulation, with position error")
    ax.loglog(c, from_si(with_error.predicted_rms, "ppm"), "-", color="#2e86c1", lw=0.8)
    ax.loglog(without_error.counts_per_rev, from_si(without_error.rms, "ppm"), "s",
              color="#27ae60", label="simulation, quantization only")
    ax.loglog(without_error.counts_per_rev, from_si(without_error.predicted_rms, "ppm"), "-",
              color="#27ae60", lw=0.8)
    ax.loglog(c, from_si(with_error.eq7, "ppm"), "--", color="#c0392b", label="Eq. (7)")
    ax.set_xlabel("encoder counts per revolution")
    ax.set_ylabel("rms δK (ppm)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=SMALL_PT)
    return fig


@page_figure
def plot_rate_sweep(sweep: RateSweep) -> Figure:
    """rms δK against the vehicle roll rate (°/s), with the prediction and Eq. (7) of paper
    RSF.

    Parameters
    ----------
    sweep : RateSweep
        From :func:`~gyrolib.rsf.sweep_roll_rate`.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = Figure(figsize=(5.0, 3.6), layout="constrained")
    ax = fig.subplots()
    r = from_si(sweep.rates, "deg/s")
    ax.plot(r, from_si(sweep.rms, "ppm"), "o", color="#2e86c1", label="simulation, rms δK")
    ax.plot(r, from_si(sweep.predicted_rms, "ppm"), "-", color="#2e86c1", lw=0.8,
            label="predicted rms")
    ax.plot(r, from_si(sweep.eq7, "ppm"), "--", color="#c0392b", label="Eq. (7)")
    ax.set_xlabel("vehicle roll rate (°/s)")
    ax.set_ylabel("δK (ppm)")
    ax.set_ylim(bottom=0)
    ax.legend(fontsize=SMALL_PT)
    return fig


@page_figure
def plot_spin_up(limited: SensorRecord, unlimited: SensorRecord, *, index: int = 0) -> Figure:
    """Vehicle roll rate and the GS's uncompensated rate during a spin-up (°/s), with the
    motor's speed limit and without (paper RSF, Figure 2's loop as simulated).

    Parameters
    ----------
    limited, unlimited : SensorRecord
        The same flight (same roll profile) with a limited and an unlimited motor.
    index : int, optional
        Which run of the ensemble.

    Returns
    -------
    matplotlib.figure.Figure
    """
    cfg = limited.config
    t = limited.t[:-1]
    rate = cfg.roll.rate(t + 0.5 * cfg.dt, cfg.duration)
    fig = Figure(figsize=(5.0, 3.4), layout="constrained")
    ax = fig.subplots()
    ax.plot(t, from_si(rate, "deg/s"), color="k", label="vehicle roll rate ω")
    ax.plot(t, from_si(limited.omega_unc[index], "deg/s"), color="#c0392b",
            label=f"ω_unc, motor limited to {from_si(cfg.gs.motor_rate_max, 'deg/s'):.0f} °/s")
    ax.plot(t, from_si(unlimited.omega_unc[index], "deg/s"), color="#2e86c1",
            label="ω_unc, unlimited motor")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("rate (°/s)")
    ax.set_yscale("symlog", linthresh=10.0)
    ax.legend(fontsize=SMALL_PT)
    return fig


@page_figure
def plot_compensation_share(result: CompensationShare) -> Figure:
    """The share of the SF error removed against the roll rate (paper RSF, Eq. (7) and the
    conclusion's "90 %"), with the simulation if the result carries one.

    Parameters
    ----------
    result : CompensationShare
        From :func:`~gyrolib.rsf.compensation_share` (no validation here: it takes a result
        object).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = Figure(figsize=(5.0, 3.6), layout="constrained")
    ax = fig.subplots()
    r = from_si(result.rates, "deg/s")
    ax.plot(r, 100 * result.share, "-", color="#c0392b", label="Eq. (7): 1 − δK/ε1")
    if result.simulated is not None:
        sim = result.simulated
        ax.plot(from_si(sim.rates, "deg/s"), 100 * sim.share, "o", color="#2e86c1",
                label="simulation: 1 − rms δK/ε1")
    ax.axhline(100 * result.target, color="k", ls=":", lw=0.8,
               label=f"{100 * result.target:.0f} % (the paper's claim)")
    ax.axvline(from_si(result.rate_for_target, "deg/s"), color="#7f8c8d", ls="--", lw=0.8,
               label="rate from which Eq. (7) gives it")
    ax.set_xlabel("vehicle roll rate (°/s)")
    ax.set_ylabel("share of ε1 removed (%)")
    ax.legend(fontsize=SMALL_PT, loc="lower right")
    ax.grid(True, alpha=0.3)
    return fig


@page_figure
def plot_correction(result: CalibrationResult, prediction: DeltaKPrediction | None = None,
                    eps1: float | None = None) -> Figure:
    """ε̂1 per interval (ppm) with, when given, the ±2σ band of δK the error model predicts
    (``prediction`` from :func:`gyrolib.rsf.predict_delta_k` at the record's
    :attr:`~CalibrationResult.mean_rate`) about ``(ε1 − mean δK)/(1 + ε1)`` (``eps1`` the
    true error if known; else about the mean estimate), and below the roll angle against the
    GS with and without correction.  Returns a :class:`matplotlib.figure.Figure`."""
    v.check_instance("result", result, CalibrationResult)
    if prediction is not None:
        v.check_instance("prediction", prediction, DeltaKPrediction)
    from matplotlib.figure import Figure

    fig = Figure(figsize=(5.0, 6.0), layout="constrained")
    ax, bx = fig.subplots(2, 1)
    mid = 0.5 * (result.t_start + result.t_end)
    e = np.asarray(from_si(result.eps1_hat, "ppm"))
    ax.plot(mid, e, "o", ms=3.5, color="C0", label="ε̂1 per interval (Eq. (2))")
    if prediction is not None:
        # δK = K(1+ε1) − 1 with K = 1 − ε̂1, so ε̂1 = (ε1 − δK)/(1 + ε1)
        if eps1 is None:
            c = float(np.mean(result.eps1_hat))
        else:
            e1 = float(v.check_real("eps1", eps1))
            c = (e1 - prediction.mean) / (1.0 + e1)
        s = prediction.std
        ax.axhspan(float(from_si(c - 2 * s, "ppm")), float(from_si(c + 2 * s, "ppm")),
                   color="0.88", label="error model: ±2σ of δK")
        ax.axhline(float(from_si(c, "ppm")), color="k", lw=0.8, ls="--")
    ax.set_ylabel("ε̂1 (ppm)")
    ax.set_xlabel("t (s), middle of the interval")
    ax.legend(loc="lower right", fontsize=SMALL_PT, framealpha=0.9)
    bx.plot(result.t, from_si(result.residual_raw, "deg"), color="C3", lw=1,
            label="uncorrected SINS − GS")
    bx.plot(result.t, from_si(result.residual, "deg"), color="C0", lw=1,
            label="corrected SINS − GS")
    bx.set_ylabel("roll angle difference (°)")
    bx.set_xlabel("t (s)")
    bx.legend(loc="upper left", fontsize=SMALL_PT)
    return fig
