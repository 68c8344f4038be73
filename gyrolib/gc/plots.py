"""Figures of paper GC: each function takes data or result objects and returns a
:class:`matplotlib.figure.Figure`.

Model:

* :func:`plot_figure1` — paper GC's Figure 1 (frames ``Oxyz`` and ``Oξηζ``, angles ``ψ``,
  ``β``, ``δ``, ``γ``, Earth-rate components ``Ω_h``, ``Ω_v``) redrawn;
* :func:`plot_shaping_psd` — the PSDs of ``N1`` and ``N3`` (paper GC, Figure 2);
* :func:`plot_nominal_motion` — the nominal float motion of Eq. (4) and its aperiodic
  approximation.

Estimator:

* :func:`plot_sigma_history` — paper GC, Figure 3 (σ of the ω_gc estimate against time);
* :func:`plot_p0_scale` — σ(100 s) against the scale of the initial N1…N4 covariance;
* :func:`plot_error_budget` — σ(100 s) by source, and the variance shares over time;

Claims (each takes the result object of :mod:`gyrolib.gc.analysis.montecarlo`,
:mod:`gyrolib.gc.analysis.speed_claim` or :mod:`gyrolib.gc.analysis.observability`; no
validation by design):

* :func:`plot_estimates` — paper GC, Figure 4 (estimates of ω_gc in runs against truth);
* :func:`plot_consistency` — ensemble RMS error against σ, and NEES with chi-square bands;
* :func:`plot_sweep` — σ(100 s) when the shaping-filter parameters vary;
* :func:`plot_information` — how ψ and ω_gc separate as the float turns;
* :func:`plot_speed_claim` — time to σ_c over a grid of shaping-filter parameters;
* :func:`plot_mismatch` — the filter's σ against the actual RMS error for several truths.
* :func:`plot_linearization` — the nonlinear truth against the linearized one: NEES excess
  and its cause.

Use on logs:

* :func:`plot_calibration` — the ω_gc estimate of :func:`gyrolib.gc.calibrate` on a record, with
  its σ band and the mean NIS per window;
* :func:`plot_allan` — the Allan deviation of a record's sensors with paper GC's model;
* :func:`plot_convention_study` — what a wrongly wired inclinometer pair does.

Race (each takes a result of :mod:`gyrolib.gc.racing.comparison`):

* :func:`plot_race` — σ of ω_gc against elapsed time, GC's method and the rate-sensor method
  it replaces (classical and optimal estimators), the procedure's phases shaded;
* :func:`plot_race_sweep` — the three times to σ_c over one swept quantity.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np
from matplotlib import colormaps
from matplotlib.figure import Figure
from matplotlib.patches import Arc, Circle
from numpy.typing import ArrayLike

from gyrolib import _validation as v
from gyrolib import quote
from gyrolib._page_figures import SMALL_PT, legend_below, page_figure
from gyrolib.filtering.consistency import gated_nis_band, nees_bounds
from gyrolib.gc.analysis.budget import ErrorBudget
from gyrolib.gc.analysis.covariance import CovarianceAnalysis, CovarianceSweep
from gyrolib.gc.logs.allan import AllanDeviation
from gyrolib.gc.logs.calibration import CalibrationResult
from gyrolib.gc.logs.convention import ConventionStudy
from gyrolib.gc.model.instrument import state_names
from gyrolib.gc.model.nominal import NominalMotion
from gyrolib.gc.model.params import MEASUREMENT_NAMES, STATE_NAMES
from gyrolib.gc.racing.comparison import RaceResult, RaceSweep
from gyrolib.gc.racing.verdict_grid import RaceVerdictGrid
from gyrolib.units import ARCSEC, from_si

__all__ = [
    "plot_allan",
    "plot_calibration",
    "plot_consistency",
    "plot_convention_study",
    "plot_error_budget",
    "plot_estimates",
    "plot_figure1",
    "plot_information",
    "plot_mismatch",
    "plot_nominal_motion",
    "plot_p0_scale",
    "plot_race",
    "plot_race_sweep",
    "plot_race_verdict",
    "plot_shaping_psd",
    "plot_sigma_history",
    "plot_speed_claim",
    "plot_sweep",
]


@page_figure
def plot_shaping_psd(omega: ArrayLike, psd_n1: ArrayLike, psd_n3: ArrayLike, *,
                     alpha1: float, alpha2: float, var_n1: float, var_n3: float) -> Figure:
    """Paper GC, Figure 2: one-sided PSDs (per rad/s) of the vibration acceleration ``N1``
    and of the random drift ``N3`` (Eqs. (6), (7) of paper GC), natural frequencies marked.

    Parameters
    ----------
    omega : array_like
        Angular frequencies (rad/s, > 0: log axes).
    psd_n1, psd_n3 : array_like
        One-sided PSDs of N1 and N3 at ``omega`` (:func:`gyrolib.gc.psd`).
    alpha1, alpha2 : float
        Natural frequencies (rad/s), drawn as dotted lines.
    var_n1, var_n3 : float
        The variances, quoted in the panels.

    Returns
    -------
    Figure
        Four stacked panels, N1's then N3's: ``Φ(ω)`` on log–log axes, then ``ω Φ(ω)``
        against ``log ω``, where equal areas are equal variance
        (``∫ Φ dω = ∫ ω Φ d ln ω``), shaded.

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import gc
    >>> p = gc.GyrocompassParams()
    >>> w = np.logspace(-4, 2, 50)
    >>> fig = gc.plot_shaping_psd(w, gc.psd(p.vibration_filter(), w),
    ...                           gc.psd(p.random_drift_filter(), w), alpha1=p.alpha1,
    ...                           alpha2=p.alpha2, var_n1=p.sigma1_sq, var_n3=p.sigma2_sq)
    >>> len(fig.axes)
    4
    """
    omega, p1, p3 = (np.asarray(x, dtype=float) for x in (omega, psd_n1, psd_n3))
    a1, a2, var1, var3 = alpha1, alpha2, var_n1, var_n3
    fig = Figure(figsize=(5.0, 10.0), layout="constrained")
    # stacked for the page: N1's two panels, then N3's (each pair shares its ω axis)
    axes = fig.subplots(4, 1, sharex=True).reshape(2, 2).T
    specs = (
        (0, p1, a1, var1, r"$N_1$, vibration acceleration", r"(m/s$^2$)$^2$/(rad/s)",
         r"m$^2$/s$^4$", "C0", r"\alpha_1"),
        (1, p3, a2, var3, r"$N_3 = \omega_{\rm rnd}$, random drift", r"(rad/s)$^2$/(rad/s)",
         r"rad$^2$/s$^2$", "C3", r"\alpha_2"),
    )
    for col, p, a, var, title, unit, var_unit, color, aname in specs:
        ax = axes[0, col]
        ax.loglog(omega, p, color=color)
        ax.axvline(a, color="0.5", ls=":", lw=1)
        ax.text(a, ax.get_ylim()[0], f" ${aname}$ = {a:g} rad/s", rotation=90,
                va="bottom", ha="right", color="0.3", fontsize=SMALL_PT)
        ax.set_title(title)
        ax.set_ylabel(r"$\Phi(\omega)$, " + unit)
        ax.minorticks_off()
        ax.grid(True, which="major", alpha=0.3)
        ax = axes[1, col]
        ax.semilogx(omega, omega * p, color=color)
        ax.fill_between(omega, omega * p, color=color, alpha=0.25)
        ax.axvline(a, color="0.5", ls=":", lw=1)
        ax.set_ylabel(r"$\omega\,\Phi(\omega)$, " + var_unit)
        if col == 1:  # the bottom panel: the four share the ω axis
            ax.set_xlabel(r"angular frequency $\omega$, rad/s")
        ax.minorticks_off()  # eight decades of minor ticks cost seconds of drawing
        ax.text(0.03, 0.9, f"shaded area = variance\n= {var:.4g} {var_unit}",
                transform=ax.transAxes, va="top", fontsize=SMALL_PT)
        ax.grid(True, which="major", alpha=0.3)
    return fig


@page_figure
def plot_nominal_motion(nominal: NominalMotion, aperiodic: NominalMotion,
                        nominal_start: NominalMotion, aperiodic_start: NominalMotion, *,
                        tau: float, lag: float) -> Figure:
    """Nominal float motion, paper GC Eq. (4), against the aperiodic approximation.

    Parameters
    ----------
    nominal, aperiodic : NominalMotion
        :func:`gyrolib.gc.nominal_motion` and :func:`gyrolib.gc.nominal_motion_aperiodic`
        over the run (same times).
    nominal_start, aperiodic_start : NominalMotion
        The same over the first few time constants (same times).
    tau : float
        The time constant ``I/f`` (s).
    lag : float
        The asymptotic difference ``−k τ`` (rad).

    Returns
    -------
    Figure
        Three stacked panels: the angle in degrees; the rate over the first few ``τ``; the
        difference ``β_n − β_ap`` in arcseconds on a logarithmic time axis.

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import gc
    >>> p = gc.GyrocompassParams()
    >>> t, t0 = np.linspace(0.0, 1.0, 11), np.linspace(0.0, 0.01, 11)
    >>> fig = gc.plot_nominal_motion(
    ...     gc.nominal_motion(p, t), gc.nominal_motion_aperiodic(p, t),
    ...     gc.nominal_motion(p, t0), gc.nominal_motion_aperiodic(p, t0),
    ...     tau=p.time_constant, lag=0.0)
    >>> len(fig.axes)
    3
    """
    t, b, bap = nominal.t, nominal.beta, aperiodic.beta
    tf, bd, bdap = nominal_start.t, nominal_start.beta_dot, aperiodic_start.beta_dot
    arcsec = ARCSEC
    fig = Figure(figsize=(5.0, 8.4), layout="constrained")
    ax1, ax2, ax3 = fig.subplots(3, 1)  # stacked for the page
    ax1.plot(t, np.degrees(b), color="C0", label=r"$\beta_n(t)$, Eq. (4)")
    ax1.plot(t, np.degrees(bap), color="C1", ls="--", label="aperiodic approximation")
    ax1.set_xlabel("t, s")
    ax1.set_ylabel("float angle, deg")
    ax1.set_title("(a) nominal float angle")
    ax1.legend(loc="lower right", fontsize=SMALL_PT)
    ax2.plot(tf * 1e3, bd / arcsec, color="C0", label=r"$\dot\beta_n$")
    ax2.plot(tf * 1e3, bdap / arcsec, color="C1", ls="--", label="aperiodic")
    ax2.axvline(tau * 1e3, color="0.5", ls=":", lw=1)
    ax2.text(tau * 1e3, 0.05 * float(np.max(bd)) / arcsec, r" $\tau = I/f$", fontsize=SMALL_PT)
    ax2.set_xlabel("t, ms")
    ax2.set_ylabel("float rate, arcsec/s")
    ax2.set_title("(b) start: rate builds up in τ")
    ax2.legend(loc="lower right", fontsize=SMALL_PT)
    pos = t > 0
    ax3.semilogx(t[pos], (b[pos] - bap[pos]) / arcsec, color="C2",
                 label=r"$\beta_n - \beta_{\rm ap}$")
    ax3.axhline(lag / arcsec, color="0.4", ls="--", lw=1, label=r"$-k\tau$")
    ax3.axvline(tau, color="0.5", ls=":", lw=1)
    ax3.set_xlabel("t, s")
    ax3.set_ylabel("difference, arcsec")
    ax3.set_title("(c) full minus aperiodic")
    ax3.ticklabel_format(axis="y", useOffset=False)
    ax3.legend(loc="upper right", fontsize=SMALL_PT)
    for ax in (ax1, ax2, ax3):
        ax.grid(True, alpha=0.3)
    return fig


def _arrow(ax, x0: float, y0: float, x1: float, y1: float, color: str, lw: float = 1.6,
           ls: str = "-") -> None:
    ax.annotate("", xy=(x1, y1), xytext=(x0, y0),
                arrowprops={"arrowstyle": "-|>", "color": color, "lw": lw, "ls": ls,
                            "shrinkA": 0, "shrinkB": 0, "mutation_scale": 14})


def _angle_arc(ax, r: float, a0_deg: float, a1_deg: float, label: str, color: str,
               label_r: float) -> None:
    lo, hi = sorted((a0_deg, a1_deg))
    ax.add_patch(Arc((0.0, 0.0), 2 * r, 2 * r, theta1=lo, theta2=hi, color=color, lw=1.2))
    mid = math.radians(0.5 * (lo + hi))
    ax.text(label_r * math.cos(mid), label_r * math.sin(mid), label, color=color,
            ha="center", va="center", fontsize=12)


def _dir(angle_from_y_deg: float) -> tuple[float, float]:
    """Unit vector at an angle from the y axis towards x (the sense of β and ψ)."""
    a = math.radians(angle_from_y_deg)
    return math.sin(a), math.cos(a)


@page_figure
def plot_figure1(*, beta_deg: float = 40.0, psi_deg: float = 12.0,
                 tilt_deg: float = 14.0) -> Figure:
    """Paper GC, Figure 1, redrawn: the base frame ``Oxyz``, the float frame ``Oξηζ``, the
    angles ``ψ``, ``β``, ``δ``, ``γ`` and the Earth-rate components ``Ω_h``, ``Ω_v``.

    The angles are exaggerated for legibility (``beta_deg``, ``psi_deg``, ``tilt_deg``; in the
    experiment they are below a degree and a few arcminutes).  Panel (a) looks down the
    output axis ``z = ζ``: the float, and with it the input axis ``η``, turns by ``β`` from
    ``y`` towards ``x``; ``Ω_h`` lies at ``ψ`` from ``y``, so the input rate is
    ``Ω_h cos(β − ψ)`` (Eq. (1)).  Panels (b), (c) are side views of the tilts, drawn for
    Eq. (2) read with ``y`` the input axis: ``δ`` takes ``y`` below the horizon, so the
    vertical rate has the component ``ω_y = −Ω_v δ``; ``γ`` takes ``x`` above it,
    ``ω_x = Ω_v γ``.  (Eqs. (3), (5) exchange the roles of δ and γ; see the model chapter.)

    Parameters
    ----------
    beta_deg, psi_deg, tilt_deg : float
        The drawn angles (degrees; legible for ``psi_deg < beta_deg`` below about 80°).

    Returns
    -------
    Figure
        Panel (a) and, under it, the two side views (b), (c).

    Examples
    --------
    >>> from gyrolib import gc
    >>> len(gc.plot_figure1().axes)
    3
    """
    fig = Figure(figsize=(5.0, 9.0), layout="constrained")
    gs = fig.add_gridspec(3, 1, height_ratios=(2.2, 1.0, 1.0))  # stacked for the page
    ax = fig.add_subplot(gs[0])
    base, flt, earth = "0.15", "C0", "C3"
    # Base frame: x, y in the plane of the page, z (output axis) towards the reader.
    _arrow(ax, 0, 0, 1.0, 0, base)
    _arrow(ax, 0, 0, 0, 1.0, base)
    ax.text(1.03, 0.03, r"$x$", fontsize=13, color=base)
    ax.text(-0.04, 1.05, r"$y$ (input axis at $\beta = 0$)", fontsize=11, color=base,
            ha="right")
    ax.add_patch(Circle((0, 0), 0.045, fill=False, color=base, lw=1.3))
    ax.add_patch(Circle((0, 0), 0.012, color=base))
    ax.text(-0.08, -0.1, r"$O$", fontsize=11, color=base, ha="right")
    # Float frame: η at β from y (towards x), ξ = η × ζ at β below x.
    ex, ey = _dir(beta_deg)
    _arrow(ax, 0, 0, 0.95 * ex, 0.95 * ey, flt)
    ax.text(0.99 * ex, 0.99 * ey, r"$\eta$ (input axis)", fontsize=12, color=flt)
    xx, xy = ey, -ex
    _arrow(ax, 0, 0, 0.8 * xx, 0.8 * xy, flt)
    ax.text(0.84 * xx, 0.84 * xy, r"$\xi$", fontsize=13, color=flt, va="center")
    # Horizontal Earth rate at ψ from y.
    hx, hy = _dir(psi_deg)
    _arrow(ax, 0, 0, 0.8 * hx, 0.8 * hy, earth, lw=2.2)
    ax.text(0.82 * hx + 0.03, 0.82 * hy + 0.04, r"$\Omega_h$ (north)", fontsize=11,
            color=earth, ha="left")  # right of the y axis, not across it
    _angle_arc(ax, 0.42, 90.0, 90.0 - psi_deg, r"$\psi$", earth, label_r=0.5)
    _angle_arc(ax, 0.62, 90.0, 90.0 - beta_deg, r"$\beta$", flt, label_r=0.7)
    _angle_arc(ax, 0.26, 90.0 - psi_deg, 90.0 - beta_deg, "", "0.35", label_r=0.0)
    mid = math.radians(90.0 - 0.5 * (psi_deg + beta_deg))
    ax.annotate(r"$\beta-\psi$", xy=(0.26 * math.cos(mid), 0.26 * math.sin(mid)),
                xytext=(0.55, 0.22), fontsize=11, color="0.35",
                arrowprops={"arrowstyle": "-", "color": "0.5", "lw": 0.8})
    # the notes under the drawing, clear of the axes and the arcs
    ax.text(-0.98, -0.3, r"$z = \zeta$: the output axis, towards the reader", fontsize=SMALL_PT,
            color=base, va="top")
    ax.text(-0.98, -0.48, r"$\Omega_v$: along the vertical $\approx z$; a rate about $z$" "\n"
            r"gives no torque about the output axis $z$", fontsize=SMALL_PT, color=earth,
            va="top")
    ax.set_xlim(-1.0, 1.3)
    ax.set_ylim(-0.85, 1.15)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_title(r"(a) down the output axis: frames $Oxyz$, $O\xi\eta\zeta$", fontsize=11)
    # Side views of the tilts: (axis, angle, tilt sign, rotation axis, projected rate).
    views = ((r"y", r"\delta", -1.0, r"x", r"$\omega_y = -\Omega_v\,\delta$"),
             (r"x", r"\gamma", 1.0, r"y", r"$\omega_x = \Omega_v\,\gamma$"))
    for row, (axis_name, angle_name, sgn, about, proj) in enumerate(views):
        axs = fig.add_subplot(gs[row + 1])
        a = sgn * math.radians(tilt_deg)
        axs.plot([-0.25, 1.15], [0, 0], color="0.6", lw=1, ls="--")
        axs.text(-0.72, 0.02, "horizon", color="0.5", fontsize=SMALL_PT,
                 va="bottom")  # in the panel
        _arrow(axs, 0, 0, math.cos(a), math.sin(a), base)
        axs.text(1.03 * math.cos(a), 1.03 * math.sin(a), rf"${axis_name}$", fontsize=12,
                 color=base, va="center")
        _arrow(axs, 0, 0, -0.5 * math.sin(a), 0.5 * math.cos(a), base, lw=1.0)
        axs.text(-0.5 * math.sin(a) + (0.04 if sgn < 0 else -0.12), 0.5 * math.cos(a) - 0.05,
                 r"$z$", fontsize=11, color=base)
        _arrow(axs, 0, 0, 0, 0.62, earth, lw=2.0)
        axs.text(-0.03, 0.66, r"$\Omega_v$ (vertical)", fontsize=10, color=earth, ha="right")
        lo, hi = sorted((0.0, math.degrees(a)))
        axs.add_patch(Arc((0, 0), 1.3, 1.3, theta1=lo, theta2=hi, color="C2", lw=1.3))
        axs.text(0.7 * math.cos(a / 2) + 0.03, 0.7 * math.sin(a / 2), rf"${angle_name}$",
                 color="C2", fontsize=13, va="center")
        axs.text(0.5, 0.42, rf"tilt about ${about}$", fontsize=SMALL_PT, color="0.3")
        axs.set_xlim(-0.75, 1.45)
        axs.set_ylim(-0.32, 0.72)
        axs.set_aspect("equal")
        axs.axis("off")
        axs.set_title(rf"({'bc'[row]}) tilt ${angle_name}$ of the ${axis_name}$ axis: {proj}",
                      fontsize=10)
    return fig


@page_figure
def plot_sigma_history(runs: Mapping[str, CovarianceAnalysis], *, paper_value: float,
                       paper_time: float = 100.0, unit: str = "arcsec_paper/s",
                       unit_label: str = "″/s", drop_time: float = 2.0,
                       name: str = "omega_gc") -> Figure:
    """Paper GC, Figure 3: σ of the ω_gc estimate against time, one line per analysis.

    Parameters
    ----------
    runs : mapping of str to CovarianceAnalysis
        Label → :func:`gyrolib.gc.covariance_analysis` result; the first is drawn thicker.
    paper_value : float
        The paper's σ at ``paper_time``, in ``unit``, drawn as a star.
    paper_time : float, default 100.0
        Time of the paper's value (s).
    unit, unit_label : str
        A :mod:`gyrolib.units` unit for the σ axis, and how the axis names it.
    drop_time : float, default 2.0
        The first ``drop_time`` seconds are shaded (the paper's "sharp drop").
    name : str, default "omega_gc"
        The state drawn.

    Returns
    -------
    Figure
        Top: linear time; bottom: log time.

    Examples
    --------
    >>> from gyrolib import gc
    >>> res = gc.covariance_analysis(gc.GyrocompassParams(), 0.1)
    >>> fig = gc.plot_sigma_history({"baseline": res}, paper_value=0.0011)
    >>> len(fig.axes)
    2
    """
    pv = paper_value
    curves = {label: (r.t, from_si(r.std(name), unit)) for label, r in runs.items()}
    unit = unit_label
    fig = Figure(figsize=(5.0, 7.0), layout="constrained")
    ax_lin, ax_log = fig.subplots(2, 1)  # stacked for the page
    for i, (label, (tt, ss)) in enumerate(curves.items()):
        lw = 2.0 if i == 0 else 1.2
        ax_lin.semilogy(tt, ss, lw=lw, label=label)
        ax_log.loglog(tt[1:], ss[1:], lw=lw, label=label)
    for ax in (ax_lin, ax_log):
        ax.plot([paper_time], [pv], "k*", ms=11, label=f"paper: {pv:g} {unit} at {paper_time:g} s")
        ax.set_xlabel("time (s)")
        ax.set_ylabel(f"σ of the ω_gc estimate ({unit})")
        ax.grid(True, which="both", alpha=0.3)
    ax_lin.axvspan(0.0, drop_time, color="0.85", zorder=0)
    ax_lin.set_title("linear time")
    ax_log.set_title("log time")
    # below the panels: in a panel the legend would cover the curves near 100 s
    fig.legend(*ax_log.get_legend_handles_labels(), loc="outside lower center", ncols=1,
               fontsize=SMALL_PT)
    return fig


@page_figure
def plot_p0_scale(sweep: CovarianceSweep, *, paper_value: float,
                  field: str = "shaping_p0_scale", unit: str = "arcsec_paper/s",
                  unit_label: str = "″/s") -> Figure:
    """σ of ω_gc at the end of the run against the scale ``κ`` of the stationary covariance
    of N1…N4 in ``P(0)`` (0: the literal reading of paper GC, 1: stationary).

    Parameters
    ----------
    sweep : CovarianceSweep
        :func:`gyrolib.gc.sweep_covariance` over ``field`` (each case sets it).
    paper_value : float
        The paper's σ in ``unit`` (dashed line).
    field : str, default "shaping_p0_scale"
        The swept field, on the horizontal axis.
    unit, unit_label : str
        A :mod:`gyrolib.units` unit for the σ axis, and how the axis names it.

    Returns
    -------
    Figure

    Examples
    --------
    >>> from gyrolib import gc
    >>> sw = gc.sweep_covariance(gc.GyrocompassParams(),
    ...                          gc.parameter_grid(shaping_p0_scale=(0.0, 1.0)), 0.01)
    >>> len(gc.plot_p0_scale(sw, paper_value=0.0011).axes)
    1
    """
    k = np.array([c[field] for c in sweep.cases], dtype=float)
    s = from_si(sweep.final_std(), unit)
    pv, unit = paper_value, unit_label
    t_end = float(sweep.analyses[0].t[-1])
    fig = Figure(figsize=(5.0, 3.4), layout="constrained")
    ax = fig.subplots()
    ax.plot(k, s, "o-")
    ax.axhline(pv, color="k", ls="--", label=f"paper: {pv:g} {unit}")
    ax.set_xlabel("κ: P(0) of N1…N4 = κ × stationary cov.")
    ax.set_ylabel(f"σ of ω_gc at {t_end:g} s ({unit})")
    ax.grid(True, alpha=0.3)
    ax.legend()
    return fig


@page_figure
def plot_error_budget(budget: ErrorBudget, *, unit: str = "arcsec_paper/s",
                      unit_label: str = "″/s") -> Figure:
    """Error budget of the ω_gc estimate (:func:`gyrolib.gc.error_budget`).

    Parameters
    ----------
    budget : ErrorBudget
        The variance of the estimation error from each source alone.
    unit, unit_label : str
        A :mod:`gyrolib.units` unit for σ, and how the axis names it.

    Returns
    -------
    Figure
        Top: σ at the last time per source (log axis); bottom: each source's share of the
        total variance over time (stacked), its legend below.

    Examples
    --------
    >>> from gyrolib import gc
    >>> bud = gc.error_budget(gc.GyrocompassParams(), 0.1)
    >>> len(gc.plot_error_budget(bud).axes)
    2
    """
    t, var, sources = budget.t, budget.var, budget.sources
    scale = float(from_si(1.0, unit)) ** -1
    unit = unit_label
    fig = Figure(figsize=(5.0, 10.0), layout="constrained")
    ax_bar, ax_share = fig.subplots(2, 1, height_ratios=[1.0, 1.0])  # stacked for the page
    end = np.sqrt(np.clip(var[:, -1], 0.0, None)) / scale
    order = np.argsort(end)
    keep = [i for i in order if end[i] > 0]
    ax_bar.barh([sources[i] for i in keep], [end[i] for i in keep], color="C0")
    ax_bar.set_xscale("log")
    ax_bar.set_xlabel(f"σ of ω_gc at {t[-1]:g} s, this source alone ({unit})")
    ax_bar.tick_params(axis="y", labelsize=SMALL_PT)
    ax_bar.grid(True, axis="x", which="both", alpha=0.3)
    total = var.sum(axis=0)
    with np.errstate(invalid="ignore", divide="ignore"):
        share = np.where(total > 0, var / total, 0.0)
    big = [i for i in order[::-1] if end[i] > 0]
    colors = colormaps["tab20"].colors[: len(big)]  # more sources than the default cycle
    ax_share.stackplot(t[1:], share[big][:, 1:], labels=[sources[i] for i in big],
                       colors=colors)
    ax_share.set_xscale("log")
    ax_share.set_xlabel("time (s)")
    ax_share.set_ylabel("share of the variance of ω_gc's error")
    ax_share.set_ylim(0, 1)
    # below the panel: beside it, it would take half the width
    ax_share.legend(fontsize=SMALL_PT, loc="upper center", bbox_to_anchor=(0.5, -0.22),
                    ncols=1)
    return fig


#: Axis labels of the shaping-filter parameters (claims figures).
FIELD_LABELS: dict[str, str] = {
    "alpha1": "α1 (rad/s)", "xi1": "ξ1", "sigma1_sq": "σ1² (m²/s⁴)",
    "alpha2": "α2 (rad/s)", "xi2": "ξ2", "sigma2_sq": "σ2² (rad²/s²)",
}

#: How a unit of :mod:`gyrolib.units` is printed on an axis.
_UNIT_LABELS: dict[str, str] = {"arcsec_paper/s": "″/s", "arcsec_paper": "″"}


def _unit_label(unit: str) -> str:
    return _UNIT_LABELS.get(unit, unit)


@page_figure
def plot_estimates(mc, *, runs: tuple[int, ...] = (0, 1), state: str = "omega_gc",
                   unit: str = "arcsec_paper/s", t_zoom: float | None = 10.0) -> Figure:
    """Paper GC, Figure 4: the estimate of ``state`` in the ``runs`` of a Monte Carlo result
    against each run's true value at ``t = 0`` (constant for ω_gc), with the filter's ±σ band
    around the truth; a second panel zooms on the first ``t_zoom`` seconds (``None``: none).

    Parameters
    ----------
    mc : MonteCarloResult
        From :func:`gyrolib.gc.monte_carlo`.
    runs : tuple of int
        Runs drawn.
    state : str
        State name.
    unit : str
        A unit of :mod:`gyrolib.units` for the vertical axis.
    t_zoom : float or None
        Length of the zoomed panel (s).

    Returns
    -------
    matplotlib.figure.Figure
    """
    t = mc.t
    est = from_si(mc.estimate(state)[list(runs)], unit)
    tru = from_si(mc.truth(state)[list(runs), 0], unit)
    sig = from_si(mc.std(state), unit)
    ul = _unit_label(unit)
    fig = Figure(figsize=(5.0, 7.0 if t_zoom else 3.6), layout="constrained")
    axes = fig.subplots(2 if t_zoom else 1, 1, squeeze=False)[:, 0]  # stacked for the page
    for ax, tmax in zip(axes, (t[-1], t_zoom)):
        sel = t <= tmax
        for i, run in enumerate(runs):
            c = f"C{i}"
            ax.plot(t[sel], est[i, sel], color=c, lw=1.2, label=f"estimate, run {run + 1}")
            ax.axhline(tru[i], color=c, ls="--", lw=1, label=f"true value, run {run + 1}")
            ax.fill_between(t[sel], tru[i] - sig[sel], tru[i] + sig[sel], color=c, alpha=0.15)
        ax.set_xlabel("time (s)")
        ax.set_ylabel(f"{state} ({ul})")
        ax.grid(True, alpha=0.3)
        ax.set_title(f"0 – {tmax:g} s")
    axes[0].legend(fontsize=SMALL_PT)
    return fig


@page_figure
def plot_consistency(mc, *, state: str = "omega_gc", unit: str = "arcsec_paper/s",
                     confidence: float = 0.95) -> Figure:
    """Top: ensemble RMS error of ``state`` and the filter's σ, with the band of an RMS of
    ``n_runs`` runs of a consistent filter.  Bottom: ensemble-average NEES of ``state`` (1 dof)
    and of the full state (10 dof) with their chi-square bands {cite:p}`BarShalom2001`.

    Parameters
    ----------
    mc : MonteCarloResult or MonteCarloSummary
        From :func:`gyrolib.gc.monte_carlo` (or its summary with the NEES of ``(state,)``
        and of the filter's states).
    state : str
        State of the left panel and of the 1-dof NEES.
    unit : str
        A unit of :mod:`gyrolib.units`.
    confidence : float
        Two-sided probability of the bands.

    Returns
    -------
    matplotlib.figure.Figure
    """
    t = mc.t
    s = from_si(mc.std(state), unit)
    r = from_si(mc.rms_error(state), unit)
    b1 = nees_bounds(1, mc.n_runs, confidence)
    dof = len(state_names(mc.params))   # the filter's states (what nees() takes)
    bn = nees_bounds(dof, mc.n_runs, confidence)
    nees = {f"{state} (1 dof)": (mc.mean_nees((state,)), b1),
            f"full state ({dof} dof)": (mc.mean_nees(), bn)}
    pct = f"{100 * confidence:g} %"
    fig = Figure(figsize=(5.0, 7.4), layout="constrained")
    ax_r, ax_n = fig.subplots(2, 1)  # stacked for the page
    ax_r.loglog(t[1:], s[1:], "k", lw=2, label="filter σ")
    ax_r.fill_between(t[1:], np.sqrt(b1[0]) * s[1:], np.sqrt(b1[1]) * s[1:], color="0.8",
                      label=f"{pct} band for the RMS")
    ax_r.loglog(t[1:], r[1:], "C1", lw=1, label="ensemble RMS error")
    ax_r.set_xlabel("time (s)")
    ax_r.set_ylabel(f"{state} error ({_unit_label(unit)})")
    ax_r.grid(True, which="both", alpha=0.3)
    ax_r.legend(fontsize=SMALL_PT)
    for i, (label, (vals, (blo, bhi))) in enumerate(nees.items()):
        c = f"C{i}"
        ax_n.semilogx(t[1:], np.nan_to_num(vals[1:], nan=0.0), color=c, lw=1,
                      label=f"NEES, {label}")
        ax_n.axhspan(blo, bhi, color=c, alpha=0.15)
    ax_n.set_yscale("log")
    ax_n.set_xlabel("time (s)")
    ax_n.set_ylabel("ensemble-average NEES")
    ax_n.set_title(f"bands: {pct} chi-square", fontsize=SMALL_PT)
    ax_n.grid(True, which="both", alpha=0.3)
    ax_n.legend(fontsize=SMALL_PT)
    return fig


@page_figure
def plot_sweep(sweep, *, paper_value: float | None = None, unit: str = "arcsec_paper/s",
               decimal_ticks: bool = True) -> Figure:
    """σ of ω_gc at the end of the analysis when one shaping-filter parameter varies
    (:func:`gyrolib.gc.shaping_sweep`): one log–log panel per parameter, the baseline value
    dotted, ``paper_value`` (rad/s, SI) dashed; ``decimal_ticks`` labels the σ axis with a
    few decimal values instead of powers of ten.

    Parameters
    ----------
    sweep : ShapingSweep
        From :func:`gyrolib.gc.shaping_sweep`.
    paper_value : float, optional
        A reference σ (rad/s) drawn as a horizontal line.
    unit : str
        A unit of :mod:`gyrolib.units`.
    decimal_ticks : bool
        Decimal tick labels on the σ axis.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.ticker import FuncFormatter, MaxNLocator, NullFormatter

    ul = _unit_label(unit)
    n = len(sweep.fields)
    cols = 2 if n > 1 else 1  # two narrow panels a row: 5 in wide for the page
    rows = -(-n // cols)
    fig = Figure(figsize=(5.0, 2.4 * rows + 0.6), layout="constrained")
    axes = np.atleast_1d(fig.subplots(rows, cols, squeeze=False)).ravel()
    for a, (ax, field) in enumerate(zip(axes, sweep.fields)):
        ax.loglog(sweep.values[a], from_si(sweep.sigma_end[a], unit), "o-")
        ax.axvline(sweep.nominal(field), color="0.5", ls=":", label="paper's value")
        if paper_value is not None:
            pv = from_si(paper_value, unit)
            ax.axhline(pv, color="k", ls="--", lw=1, label=f"{pv:g} {ul}")
        ax.set_xlabel(FIELD_LABELS.get(field, field))
        ax.set_ylabel(f"σ at {sweep.t_end:g} s ({ul})")
        ax.grid(True, which="both", alpha=0.3)
        if decimal_ticks:
            lo, hi = ax.get_ylim()
            ticks = [y for y in MaxNLocator(6).tick_values(lo, hi) if lo <= y <= hi]
            ax.set_yticks(ticks)
            ax.yaxis.set_major_formatter(FuncFormatter(lambda y, _: f"{y:.6g}"))
            ax.yaxis.set_minor_formatter(NullFormatter())
            ax.set_ylim(lo, hi)
    legend_below(fig, axes[0], ncols=2)  # in a panel it covers the lines it names
    for ax in axes[n:]:
        ax.set_visible(False)
    return fig


@page_figure
def plot_information(info, frozen=None, *, unit: str = "arcsec_paper/s",
                     beta_frozen: float | None = None,
                     rounding_floor: float | None = 1e-12) -> Figure:
    """Top: σ of ω_gc from the angle sensor's information alone with ψ known and unknown.
    Bottom: ``1 − |correlation|`` of the ψ and ω_gc information for the turning float and (if
    ``frozen`` is given) for a float frozen at ``beta_frozen``, the value ``1 − √15/4`` of
    the regressors ``t`` and ``t²``, and a grey band below ``rounding_floor`` (double-
    precision rounding; ``None``: none).  The first stored time (no information yet) is
    left out.

    Parameters
    ----------
    info, frozen : InformationPsiOmega
        From :func:`gyrolib.gc.information_psi_omega` (``frozen``: with ``frozen_beta``).
    unit : str
        A unit of :mod:`gyrolib.units`.
    beta_frozen : float, optional
        The frozen angle (rad), for the legend.
    rounding_floor : float, optional
        Upper edge of the rounding band.

    Returns
    -------
    matplotlib.figure.Figure
    """
    t = info.t[1:]
    ul = _unit_label(unit)
    fig = Figure(figsize=(5.0, 7.6), layout="constrained")
    ax_s, ax_c = fig.subplots(2, 1)  # stacked for the page
    ax_s.loglog(t, from_si(info.sigma_gc_psi_known()[1:], unit), label="ψ known")
    ax_s.loglog(t, from_si(info.sigma_gc_psi_unknown()[1:], unit),
                label="ψ unknown (no prior)")
    ax_s.set_xlabel("time (s)")
    ax_s.set_ylabel(f"σ of ω_gc ({ul})")
    ax_s.set_title("angle-sensor information only", fontsize=SMALL_PT)
    ax_s.grid(True, which="both", alpha=0.3)
    ax_s.legend(fontsize=SMALL_PT)
    ax_c.semilogx(t, 1.0 - np.abs(info.correlation()[1:]),
                  label="float turning (sin β_n grows)")
    if frozen is not None:
        ax_c.semilogx(frozen.t[1:], np.clip(1.0 - np.abs(frozen.correlation()[1:]), 1e-17,
                                            None),
                      label="float frozen" if beta_frozen is None
                      else f"float frozen at β = {beta_frozen:g} rad")
    ax_c.axhline(1.0 - np.sqrt(15.0) / 4.0, color="k", ls=":", lw=1,
                 label="1 − √15/4 (regressors t and t²)")
    ax_c.set_yscale("log")
    if rounding_floor is not None:
        ax_c.axhspan(ax_c.get_ylim()[0], rounding_floor, color="0.85", zorder=0,
                     label="double-precision rounding")
    ax_c.set_xlabel("time (s)")
    ax_c.set_ylabel("1 − |correlation|")
    ax_c.set_title("correlation of the ψ and ω_gc information", fontsize=SMALL_PT)
    ax_c.grid(True, which="both", alpha=0.3)
    ax_c.legend(fontsize=SMALL_PT)
    return fig


@page_figure
def plot_speed_claim(claim_map) -> Figure:
    """Time for σ of ω_gc to reach σ_c over a grid of two parameters
    (:func:`gyrolib.gc.speed_claim_map`): one panel per reading of the initial covariance of
    N1…N4, colour the time (log scale), a black contour at the claim's bound, hatching where
    σ_c is not reached within the analysed span, and the paper's parameters marked.

    Parameters
    ----------
    claim_map : SpeedClaimMap
        From :func:`gyrolib.gc.speed_claim_map`.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.colors import LogNorm

    m = claim_map
    x = m.x_factors * getattr(m.params, m.x_field)
    y = m.y_factors * getattr(m.params, m.y_field)
    shown = np.nan_to_num(m.t_c, nan=2.0 * m.t_max)
    finite = m.t_c[np.isfinite(m.t_c)]
    norm = LogNorm(vmin=max(1.0, float(finite.min()) if finite.size else 1.0),
                   vmax=2.0 * m.t_max)
    n = len(m.readings)
    fig = Figure(figsize=(5.0, 3.4 * n + 0.6), layout="constrained")
    axes = np.atleast_1d(fig.subplots(n, 1, squeeze=False)).ravel()  # stacked for the page
    mesh = None
    for ax, reading, tc, raw in zip(axes, m.readings, shown, m.t_c):
        mesh = ax.pcolormesh(x, y, tc, norm=norm, shading="nearest", cmap="viridis")
        if np.nanmin(tc) < m.bound < np.nanmax(tc):
            cs = ax.contour(x, y, tc, levels=[m.bound], colors="k", linewidths=2)
            ax.clabel(cs, fmt=lambda _: f"{m.bound:g} s", fontsize=SMALL_PT)
        miss = ~np.isfinite(raw)
        if np.any(miss):
            ax.contourf(x, y, miss.astype(float), levels=[0.5, 1.5], colors="none",
                        hatches=["//"])
        ax.plot(getattr(m.params, m.x_field), getattr(m.params, m.y_field), "r*", ms=14,
                label="paper's parameters")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(FIELD_LABELS.get(m.x_field, m.x_field))
        ax.set_ylabel(FIELD_LABELS.get(m.y_field, m.y_field))
        ax.set_title(f"P0 of N1…N4: {reading}")
        ax.legend(fontsize=SMALL_PT, loc="lower left")
    fig.colorbar(mesh, ax=list(axes), label="time to reach σ_c (s)", location="bottom",
                 shrink=0.9)
    return fig


@page_figure
def plot_mismatch(results: Mapping[str, object], *, state: str = "omega_gc",
                  unit: str = "arcsec_paper/s") -> Figure:
    """What the filter claims against what it gets: for each labelled Monte Carlo result
    (e.g. a truth with a larger vibration than the filter assumes), the filter's σ of
    ``state`` (dashed) and the ensemble RMS error (solid), in one colour per result.

    Parameters
    ----------
    results : Mapping[str, MonteCarloResult]
        Label → result of :func:`gyrolib.gc.monte_carlo`.
    state : str
        State drawn.
    unit : str
        A unit of :mod:`gyrolib.units`.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = Figure(figsize=(5.0, 5.4), layout="constrained")
    ax = fig.subplots()
    for i, (label, mc) in enumerate(results.items()):
        c = f"C{i}"
        ax.loglog(mc.t[1:], from_si(mc.std(state)[1:], unit), color=c, ls="--", lw=1.5,
                  label=f"filter σ, {label}")
        ax.loglog(mc.t[1:], from_si(mc.rms_error(state)[1:], unit), color=c, lw=1,
                  label=f"RMS error, {label}")
    ax.set_xlabel("time (s)")
    ax.set_ylabel(f"{state} ({_unit_label(unit)})")
    ax.grid(True, which="both", alpha=0.3)
    legend_below(fig, ax)  # two entries per result: inside, they cover the curves
    return fig


# The race against the rate-sensor method (gc.racing) ----------------------------------------
#: Shading of the rate-sensor procedure's phases in :func:`plot_race`.
_PHASE_COLORS: dict[str, str] = {"position 1": "#dbe9f6", "turn": "#f6d8d8",
                                 "settling": "#f6ecd2", "position 2": "#dbf0dc"}


@page_figure
def plot_race(result, *, unit: str = "arcsec_paper/s", t_end: float | None = None) -> Figure:
    """σ of ω_gc against elapsed time for GC's method and the rate-sensor method with the
    classical and the optimal estimator (:func:`gyrolib.gc.race`), the procedure's phases
    shaded, σ_c and the three times to it marked.

    Parameters
    ----------
    result : RaceResult
        From :func:`gyrolib.gc.race`.
    unit : str
        A unit of :mod:`gyrolib.units` for σ.
    t_end : float, optional
        Right end of the time axis (s); default a quarter beyond the latest time to σ_c.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from gyrolib import gc
    >>> fig = gc.plot_race(gc.race())
    >>> len(fig.axes)
    1
    """
    r = v.check_instance("result", result, RaceResult)
    times = [t for t in (r.t_c_gc, r.t_c_rate_sensor, r.t_c_rate_sensor_optimal)
             if np.isfinite(t)]
    if t_end is None:
        t_end = 1.25 * max([*times, r.phases[-1][1]])
    t_end = v.check_positive("t_end", t_end)
    ul = _unit_label(unit)
    fig = Figure(figsize=(5.0, 5.2), layout="constrained")
    ax = fig.subplots()
    for name, a, b in r.phases:
        if a < t_end:
            ax.axvspan(a, min(b, t_end), color=_PHASE_COLORS.get(name, "0.9"), zorder=0)
            # upright: on a 5-in figure a band is narrower than its name set across it
            ax.text(0.5 * (a + min(b, t_end)), 0.98, name, transform=ax.get_xaxis_transform(),
                    ha="center", va="top", fontsize=SMALL_PT, rotation=90)
    sc = from_si(r.procedure.sigma_c, unit)
    # (label, t, σ, colour, line style, offset of the time label in points)
    curves = (("GC's method (gyrocompass, Kalman filter)", r.t_gc, r.sigma_gc, "C0", "-",
               (-38, -15)),
              ("rate sensor, classical half-sum", r.t_classical, r.sigma_classical, "C3", "-",
               (4, 6)),
              ("rate sensor, optimal (Kalman) estimator", r.t_optimal, r.sigma_optimal, "C2",
               "--", (4, -15)))
    for (label, t, s, c, ls, off), tc in zip(curves, (r.t_c_gc, r.t_c_rate_sensor,
                                                       r.t_c_rate_sensor_optimal)):
        keep = t <= t_end
        if np.any(keep):
            ax.semilogy(t[keep], from_si(s[keep], unit), color=c, ls=ls, lw=1.8, label=label)
        if np.isfinite(tc) and tc <= t_end:
            ax.plot([tc], [sc], "o", color=c, ms=7, mec="k")
            # on a white ground: a label in a curve's colour on a band of the same hue
            # (green on "position 2") would not read
            ax.annotate(f"{tc:.1f} s", (tc, sc), textcoords="offset points", xytext=off,
                        color=c, fontsize=SMALL_PT,
                        bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": "none",
                              "alpha": 0.9})
    ax.axhline(sc, color="k", lw=1, ls=":", label=f"σ_c = {sc:g} {ul}")
    ax.set_xlim(0.0, t_end)
    ax.set_xlabel("elapsed time (s)")
    ax.set_ylabel(f"σ of the ω_gc estimate ({ul})")
    ax.grid(True, which="both", alpha=0.3)
    # below the axes: in them, on a 5-in figure, it would cover the curves
    legend_below(fig, ax)
    return fig


@page_figure
def plot_race_sweep(sweep, field: str, *, log_x: bool = False,
                    label: str | None = None) -> Figure:
    """Times to σ_c of the three contenders of a :func:`gyrolib.gc.race_sweep` over one
    swept field, with twice GC's time drawn: above it, GC's method is more than 50 % faster.

    Parameters
    ----------
    sweep : RaceSweep
        From :func:`gyrolib.gc.race_sweep`, each case setting ``field`` (other fields fixed).
    field : str
        The swept field (the x axis).
    log_x : bool
        Logarithmic x axis.
    label : str, optional
        x-axis label (default: ``field``).

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from gyrolib import gc
    >>> sw = gc.race_sweep(cases=[{"T_settle": x} for x in (0.0, 30.0)])
    >>> len(gc.plot_race_sweep(sw, "T_settle").axes)
    1
    """
    from matplotlib.ticker import NullFormatter, ScalarFormatter

    sw = v.check_instance("sweep", sweep, RaceSweep)
    field = v.check_str("field", field)
    if not all(field in c for c in sw.cases):
        raise ValueError(f"field must be set by every case of the sweep; got {field!r}")
    x = np.array([float(c[field]) for c in sw.cases])
    order = np.argsort(x)
    fig = Figure(figsize=(5.0, 5.0), layout="constrained")
    ax = fig.subplots()
    for t, lab, c, ls in ((sw.t_c_gc, "GC's method", "C0", "-"),
                          (sw.t_c_rate_sensor, "rate sensor, classical", "C3", "-"),
                          (sw.t_c_rate_sensor_optimal, "rate sensor, optimal", "C2", "--")):
        ax.plot(x[order], t[order], ls, color=c, marker="o", ms=4, label=lab)
    ax.plot(x[order], 2.0 * sw.t_c_gc[order], ":", color="C0",
            label="2 × GC's time (above: more than 50 % faster)")
    if log_x:
        ax.set_xscale("log")
    ax.set_yscale("log")
    ax.yaxis.set_major_formatter(ScalarFormatter())
    ax.yaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel(label or field)
    ax.set_ylabel("time to σ_c (s)")
    ax.grid(True, which="both", alpha=0.3)
    legend_below(fig, ax)
    return fig


@page_figure
def plot_race_verdict(grid, *, thresholds: Mapping[str, float] | None = None) -> Figure:
    """Where "more than 50 % faster" holds: the race's margin (the smaller saving over the
    rival's two estimators minus 50 %) against the vibration variance σ1², one line per
    angle-sensor intensity C_as, one panel per reading of the printed noise levels (stacked,
    so that one image serves a phone and a page).  Above zero the claim holds; the
    reference point (the paper's σ1² and C_as under the book's reading) is marked.

    Parameters
    ----------
    grid : RaceVerdictGrid
        From :func:`gyrolib.gc.race_verdict_grid`.
    thresholds : mapping, optional
        Reading → the σ1² factor where the claim flips at the paper's C_as (a vertical line,
        labelled by :func:`gyrolib.quote.factor`, the digits the text quotes): the claim
        map's threshold, not a point of the grid.

    Returns
    -------
    matplotlib.figure.Figure
    """
    g = v.check_instance("grid", grid, RaceVerdictGrid)
    names = {"intensity_over_dt": "the book's reading: R = C/dt",
             "variance": "the other reading: R = C"}
    n = len(g.readings)
    fig = Figure(figsize=(5.0, 2.6 * n + 0.4), layout="constrained")
    axes = np.atleast_1d(fig.subplots(n, 1, sharex=True))
    colors = {0.1: "C2", 1.0: "C0", 10.0: "C3"}
    for ax, r, m in zip(axes, g.readings, g.margin, strict=True):
        for c, row in zip(g.cas_factors, m, strict=True):
            clipped = np.maximum(row, -60.0)
            ax.plot(g.sigma1_factors, clipped, "-o", ms=3,
                    color=colors.get(float(c), None), label=f"C_as × {c:g}")
        ax.axhline(0.0, color="k", lw=1.0)
        ax.axhspan(0.0, 60.0, color="C2", alpha=0.08)
        i = int(np.argmin(np.abs(g.cas_factors - 1.0)))
        j = int(np.argmin(np.abs(g.sigma1_factors - 1.0)))
        ax.plot([1.0], [m[i, j]], marker="*", ms=12, color="k", zorder=5,
                label="paper's σ1², C_as")
        if thresholds and r in thresholds and np.isfinite(thresholds[r]):
            ax.axvline(thresholds[r], color="C0", ls=":", lw=1.2,
                       label=f"flips at σ1² × {quote.factor(thresholds[r])}")
        ax.set_xscale("log")
        ax.set_ylim(-62.0, 55.0)
        ax.set_ylabel("saving − 50 (%)")
        ax.set_title(names.get(r, r), fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=SMALL_PT, loc="lower left")
    axes[-1].set_xlabel("σ1² as a factor of the paper's")
    return fig


@page_figure
def plot_linearization(effect) -> Figure:
    """Where the full-state NEES of the nonlinear truth goes out of its band, and why
    (:func:`gyrolib.gc.linearization_effect`), three panels stacked.  Top: the full-state
    NEES with the nonlinear and with the linearized truth (same runs), and the nonlinear
    one less the excess that the ω_gc shift predicts, against the per-time chi-square
    band.  Below it: the paired change of each state's error at the last time, RMS over the
    runs, in units of that state's σ.  At the bottom: the paired shift of the ω_gc
    estimate per run at the last time against the remainder drift of Eq. (3)'s
    linearization (paper GC, Eqs. (3), (5)), in units of the filter's σ of ω_gc.

    Parameters
    ----------
    effect : LinearizationEffect
        From :func:`gyrolib.gc.linearization_effect`.

    Returns
    -------
    matplotlib.figure.Figure
    """
    t = effect.t
    fig = Figure(figsize=(5.0, 12.0), layout="constrained")
    # stacked for the page; the NEES panel's legend sits under it (in it, it would cover
    # the curves)
    ax_n, ax_s, ax_w = fig.subplots(3, 1, height_ratios=[1.2, 1.0, 1.2])
    ax_n.axhspan(*effect.band, color="0.85", label="95 % band per time")
    ax_n.semilogx(t, effect.nees_nonlinear, "C3", lw=1,
                  label=f"nonlinear truth ({100 * effect.inside('nonlinear'):.0f} % inside)")
    ax_n.semilogx(t, effect.nees_linear, "C0", lw=1,
                  label=f"linearized truth ({100 * effect.inside('linear'):.0f} % inside)")
    ax_n.semilogx(t, effect.nees_nonlinear - effect.excess_predicted, "k", lw=0.8, ls=":",
                  label="nonlinear less the predicted excess")
    ax_n.set_xlabel("time (s)")
    ax_n.set_ylabel("full-state NEES")
    ax_n.set_title(f"average of {effect.n_runs} runs", fontsize=SMALL_PT)
    ax_n.grid(True, which="both", alpha=0.3)
    ax_n.legend(loc="upper center", bbox_to_anchor=(0.5, -0.25), ncols=1, fontsize=SMALL_PT)
    shift = np.maximum(effect.state_shift[-1], 1e-12)
    ax_s.barh(np.arange(shift.size), shift, color="C1")
    ax_s.set_yticks(np.arange(shift.size), STATE_NAMES, fontsize=SMALL_PT)
    ax_s.invert_yaxis()
    ax_s.set_xscale("log")
    ax_s.set_xlim(1e-8, 1.0)
    ax_s.set_xlabel(f"paired change of the error at {t[-1]:g} s (σ)")
    ax_s.set_ylabel("state")
    ax_s.grid(True, axis="x", which="both", alpha=0.3)
    sig = effect.omega_sigma[-1]
    pred = effect.omega_shift_predicted[:, -1] / sig
    got = effect.omega_shift[:, -1] / sig
    lim = float(np.max(np.abs(np.concatenate([pred, got])))) * 1.05
    ax_w.plot([-lim, lim], [-lim, lim], "k", lw=0.6, label="shift = remainder")
    ax_w.plot(pred, got, ".", color="C3", ms=3, label="runs")
    ax_w.set_xlim(-lim, 0.05 * lim)
    ax_w.set_ylim(-lim, 0.05 * lim)
    ax_w.set_xlabel("remainder −Ω_h cos β_n ψ²/2 (σ of ω_gc)")
    ax_w.set_ylabel(f"shift of ω̂_gc at {t[-1]:g} s (σ)")
    ax_w.set_aspect("equal", adjustable="box")
    ax_w.grid(True, alpha=0.3)
    ax_w.legend(fontsize=SMALL_PT, loc="upper left")
    return fig


@page_figure
def plot_allan(result: AllanDeviation, *, title: str | None = None):
    """Top: the Allan deviation of the angle-sensor rate (rad/s); bottom: of the two
    inclinometers (m/s²); each with its error bars and, dashed, paper GC's model.  Returns a
    :class:`matplotlib.figure.Figure`."""
    import matplotlib.pyplot as plt

    if not isinstance(result, AllanDeviation):
        raise TypeError(f"result must be an AllanDeviation; got {type(result).__name__}")
    fig, (ax, bx) = plt.subplots(2, 1, figsize=(5.0, 7.0), layout="constrained")  # stacked
    s = result.series[0]
    ax.errorbar(s.tau, s.adev, yerr=[s.adev - s.lo, s.hi - s.adev], fmt="o-", ms=3, lw=1,
                color="C0",
                label="angle-sensor rate")
    ax.plot(s.tau, s.model, "--", color="k", lw=1, label="model: white angle noise √(3R)/τ")
    ax.set_ylabel("Allan deviation (rad/s)")
    # the two inclinometers often agree closely: a filled dot on a solid line against an open
    # square on a dotted one, so that each stays visible where they overlap
    styles = [dict(fmt="o-", ms=3.5), dict(fmt="s:", ms=7, mfc="none", mew=1.2)]
    for q, s in enumerate(result.series[1:], start=1):
        bx.errorbar(s.tau, s.adev, yerr=[s.adev - s.lo, s.hi - s.adev], lw=1,
                    color=f"C{q}", zorder=3 - q, label=s.name, **styles[(q - 1) % 2])
    s = result.series[1]
    bx.plot(s.tau, s.model, "--", color="k", lw=1,
            label="model: sensor noise + vibration N1")
    bx.set_ylabel("Allan deviation (m/s²)")
    for a in (ax, bx):
        a.set_xscale("log")
        a.set_yscale("log")
        a.set_xlabel("τ (s)")
        a.grid(True, which="both", lw=0.3, alpha=0.5)
        a.legend(fontsize=SMALL_PT)
    if title:
        fig.suptitle(title, fontsize=10)
    return fig


@page_figure
def plot_convention_study(study: ConventionStudy):
    """Top: the error of ω̂_gc in σ per run, as logged and wrongly wired, marked by whether
    the diagnostics pass.  Bottom: the shift of the estimate the wiring causes against the
    shift Eq. (5) predicts from the true tilts.  Returns a :class:`matplotlib.figure.Figure`."""
    import matplotlib.pyplot as plt

    if not isinstance(study, ConventionStudy):
        raise TypeError(f"study must be a ConventionStudy; got {type(study).__name__}")
    fig, (ax, bx) = plt.subplots(2, 1, figsize=(5.0, 8.4), layout="constrained")  # stacked
    k = np.arange(study.seeds.size)
    for z, fits, x0, color, label in ((study.z_right, study.fits_right, -0.15, "C0",
                                       "columns as logged"),
                                      (study.z_wrong, study.fits_wrong, 0.15, "C3",
                                       f"wired {study.wiring}")):
        ax.scatter(k[fits] + x0, z[fits], color=color, s=22, label=f"{label}: model fits")
        if np.any(~fits):
            ax.scatter(k[~fits] + x0, z[~fits], facecolor="none", edgecolor=color, s=22,
                       label=f"{label}: does not fit")
    ax.axhspan(-3, 3, color="0.9", zorder=0, label="±3σ")
    ax.axhline(0, color="k", lw=0.6)
    ax.set_xlabel("run (seed)")
    ax.set_xticks(k, [str(s) for s in study.seeds], fontsize=SMALL_PT)
    ax.set_ylabel("(ω̂_gc − ω_gc) / σ")
    # below the panel: in it, it would cover the runs
    ax.legend(fontsize=SMALL_PT, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncols=2)
    pred = np.asarray(from_si(study.predicted_shift, "arcsec_paper/s"))
    got = np.asarray(from_si(study.shift, "arcsec_paper/s"))
    lim = 1.1 * float(max(np.max(np.abs(pred)), np.max(np.abs(got)), 1e-12))
    bx.plot([-lim, lim], [-lim, lim], color="k", lw=0.8, label="equal")
    bx.scatter(pred, got, color="C3", s=22)
    bx.set_xlabel("predicted shift Ω_v(γ − γ′) (″/s)")
    bx.set_ylabel("shift of ω̂_gc, wired − logged (″/s)")
    bx.set_xlim(-lim, lim)
    bx.set_ylim(-lim, lim)
    from matplotlib.ticker import MaxNLocator

    bx.xaxis.set_major_locator(MaxNLocator(5))  # "−0.015" a tick: more overprint at 5 in
    bx.legend(fontsize=SMALL_PT, loc="upper left")
    return fig


# Figure -----------------------------------------------------------------------------------
#: Most points of the NIS panel: a longer record's windows are pooled into this many bins.
MAX_NIS_BINS: int = 200


def _binned_nis(result: CalibrationResult, bins: int) -> tuple[np.ndarray, np.ndarray,
                                                                np.ndarray]:
    """(t, mean NIS (k, 3), samples per bin (k, 3)): the stored windows pooled into at most
    ``bins`` consecutive bins, each bin's mean NIS weighted by its windows' sample counts."""
    t, w, c = result.t, result.nis_window, result.nis_window_count.astype(float)
    k = max(1, math.ceil(t.size / bins))
    if k == 1:
        return t, w, c
    edges = np.arange(0, t.size, k)
    wc = np.where(np.isfinite(w) & (c > 0), w * c, 0.0)
    num = np.add.reduceat(wc, edges, axis=0)
    cnt = np.add.reduceat(np.where(np.isfinite(w), c, 0.0), edges, axis=0)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = np.where(cnt > 0, num / np.maximum(cnt, 1.0), np.nan)
    t_end = t[np.minimum(edges + k - 1, t.size - 1)]
    return t_end, mean, cnt


@page_figure
def plot_calibration(result: CalibrationResult, truth: float | None = None,
                     confidence: float = 0.99, label: str | None = None):
    """The ω_gc estimate with its ±σ band over time (paper's ″/s) and, below, the mean NIS
    of each sensor per stored window against its χ² band; ``truth`` (rad/s) draws the true
    drift when known; ``label`` (e.g. the file and its latitude) heads the figure.  A long
    record's windows are pooled into at most :data:`MAX_NIS_BINS` bins, the band drawn for
    a bin's samples.  Returns a :class:`matplotlib.figure.Figure`."""
    import matplotlib.pyplot as plt

    if not isinstance(result, CalibrationResult):
        raise TypeError(f"result must be a CalibrationResult; got {type(result).__name__}")
    conf = v.check_in_range("confidence", confidence, 0.0, 1.0, low_open=True, high_open=True)
    if label is not None and not isinstance(label, str):
        raise TypeError(f"label must be a str or None; got {type(label).__name__}")
    fig, (ax, bx) = plt.subplots(2, 1, figsize=(5.0, 7.0), sharex=True, layout="constrained",
                                 gridspec_kw={"height_ratios": [3, 2]})
    est = np.asarray(from_si(result.estimate("omega_gc"), "arcsec_paper/s"))
    sig = np.asarray(from_si(result.sigma("omega_gc"), "arcsec_paper/s"))
    ax.fill_between(result.t, est - sig, est + sig, color="C0", alpha=0.25, lw=0,
                    label="±σ (filter)")
    ax.plot(result.t, est, color="C0", lw=1.2, label="estimate")
    if truth is not None:
        ax.axhline(float(from_si(v.check_real("truth", truth), "arcsec_paper/s")), color="k",
                   ls="--", lw=1, label="truth")
    ax.set_ylabel("ω_gc (″/s, paper's arcsec)")
    lo = float(np.min(est[-max(1, est.size // 2):] - 4 * sig[-max(1, est.size // 2):]))
    hi = float(np.max(est[-max(1, est.size // 2):] + 4 * sig[-max(1, est.size // 2):]))
    if truth is not None:
        tr = float(from_si(truth, "arcsec_paper/s"))
        lo, hi = min(lo, tr - (hi - lo) * 0.1), max(hi, tr + (hi - lo) * 0.1)
    ax.set_ylim(lo, hi)
    ax.legend(loc="upper right", fontsize=SMALL_PT)
    ax.set_title((f"{label}\n" if label else "")
                 + f"ω_gc = {from_si(result.omega_gc, 'arcsec_paper/s'):.4g} ± "
                 f"{from_si(result.omega_gc_std, 'arcsec_paper/s'):.2g} ″/s", fontsize=10)
    tb, nis, cnt = _binned_nis(result, MAX_NIS_BINS)
    for q, name in enumerate(MEASUREMENT_NAMES):
        bx.plot(tb, nis[:, q], lw=0.8, color=f"C{q + 1}", label=name)
    n = np.maximum(np.median(cnt, axis=0), 1.0)
    nn = float(np.max(n))
    band = gated_nis_band(nn, result.gate, 0.5 * (1 - conf), 0.5 * (1 + conf))
    bx.axhspan(float(band[0]), float(band[1]), color="0.85",   # the gate's band, as the checks'
               label=f"{conf:.0%} band, {nn:.0f} samples")
    bx.axhline(1.0, color="k", lw=0.6)
    bx.set_ylabel("mean NIS per window" if tb.size == result.t.size else
                  f"mean NIS per bin of {math.ceil(result.t.size / MAX_NIS_BINS)} windows")
    bx.set_xlabel("t (s)")
    legend_below(fig, bx, ncols=2)  # in the panel it would cover the NIS curves
    return fig
