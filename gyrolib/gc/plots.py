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
* :func:`plot_estimates` — paper GC, Figure 4 (estimates of ω_gc in runs against truth);
* :func:`plot_consistency` — ensemble RMS error against σ, and NEES with chi-square bands;
* :func:`plot_sweep` — σ(100 s) when the shaping-filter parameters vary;
* :func:`plot_information` — how ψ and ω_gc separate as the float turns.
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
from gyrolib.gc.budget import ErrorBudget
from gyrolib.gc.covariance import CovarianceAnalysis, CovarianceSweep
from gyrolib.gc.nominal import NominalMotion
from gyrolib.units import ARCSEC, from_si

__all__ = [
    "plot_consistency",
    "plot_error_budget",
    "plot_estimates",
    "plot_figure1",
    "plot_information",
    "plot_nominal_motion",
    "plot_p0_scale",
    "plot_shaping_psd",
    "plot_sigma_history",
    "plot_sweep",
]


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
        Top row: ``Φ(ω)`` on log–log axes.  Bottom row: ``ω Φ(ω)`` against ``log ω``, where
        equal areas are equal variance (``∫ Φ dω = ∫ ω Φ d ln ω``), shaded.

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
    fig = Figure(figsize=(10.0, 6.4), layout="constrained")
    axes = fig.subplots(2, 2, sharex="col")
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
                va="bottom", ha="right", color="0.3", fontsize=8)
        ax.set_title(title)
        ax.set_ylabel(r"$\Phi(\omega)$, " + unit)
        ax.minorticks_off()
        ax.grid(True, which="major", alpha=0.3)
        ax = axes[1, col]
        ax.semilogx(omega, omega * p, color=color)
        ax.fill_between(omega, omega * p, color=color, alpha=0.25)
        ax.axvline(a, color="0.5", ls=":", lw=1)
        ax.set_ylabel(r"$\omega\,\Phi(\omega)$, " + var_unit)
        ax.set_xlabel(r"angular frequency $\omega$, rad/s")
        ax.minorticks_off()  # eight decades of minor ticks cost seconds of drawing
        ax.text(0.03, 0.9, f"shaded area = variance\n= {var:.4g} {var_unit}",
                transform=ax.transAxes, va="top", fontsize=9)
        ax.grid(True, which="major", alpha=0.3)
    return fig


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
        Three panels: the angle in degrees; the rate over the first few ``τ``; the
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
    fig = Figure(figsize=(11.0, 3.6), layout="constrained")
    ax1, ax2, ax3 = fig.subplots(1, 3)
    ax1.plot(t, np.degrees(b), color="C0", label=r"$\beta_n(t)$, Eq. (4)")
    ax1.plot(t, np.degrees(bap), color="C1", ls="--", label="aperiodic approximation")
    ax1.set_xlabel("t, s")
    ax1.set_ylabel("float angle, deg")
    ax1.set_title("(a) nominal float angle")
    ax1.legend(loc="upper left", fontsize=8)
    ax2.plot(tf * 1e3, bd / arcsec, color="C0", label=r"$\dot\beta_n$")
    ax2.plot(tf * 1e3, bdap / arcsec, color="C1", ls="--", label="aperiodic")
    ax2.axvline(tau * 1e3, color="0.5", ls=":", lw=1)
    ax2.text(tau * 1e3, 0.05 * float(np.max(bd)) / arcsec, r" $\tau = I/f$", fontsize=9)
    ax2.set_xlabel("t, ms")
    ax2.set_ylabel("float rate, arcsec/s")
    ax2.set_title("(b) start: rate builds up in τ")
    ax2.legend(loc="lower right", fontsize=8)
    pos = t > 0
    ax3.semilogx(t[pos], (b[pos] - bap[pos]) / arcsec, color="C2",
                 label=r"$\beta_n - \beta_{\rm ap}$")
    ax3.axhline(lag / arcsec, color="0.4", ls="--", lw=1, label=r"$-k\tau$")
    ax3.axvline(tau, color="0.5", ls=":", lw=1)
    ax3.set_xlabel("t, s")
    ax3.set_ylabel("difference, arcsec")
    ax3.set_title("(c) full minus aperiodic")
    ax3.ticklabel_format(axis="y", useOffset=False)
    ax3.legend(loc="upper right", fontsize=8)
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
        Panel (a) and the two side views (b), (c).

    Examples
    --------
    >>> from gyrolib import gc
    >>> len(gc.plot_figure1().axes)
    3
    """
    fig = Figure(figsize=(11.0, 4.8), layout="constrained")
    gs = fig.add_gridspec(2, 2, width_ratios=(1.3, 1.0))
    ax = fig.add_subplot(gs[:, 0])
    base, flt, earth = "0.15", "C0", "C3"
    # Base frame: x, y in the plane of the page, z (output axis) towards the reader.
    _arrow(ax, 0, 0, 1.0, 0, base)
    _arrow(ax, 0, 0, 0, 1.0, base)
    ax.text(1.03, 0.03, r"$x$", fontsize=13, color=base)
    ax.text(-0.04, 1.05, r"$y$ (input axis at $\beta = 0$)", fontsize=11, color=base,
            ha="right")
    ax.add_patch(Circle((0, 0), 0.045, fill=False, color=base, lw=1.3))
    ax.add_patch(Circle((0, 0), 0.012, color=base))
    ax.text(-0.08, -0.1, r"$O$;  $z = \zeta$: output axis, towards the reader", fontsize=9.5,
            color=base, ha="right")
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
    ax.text(0.82 * hx - 0.03, 0.82 * hy + 0.04, r"$\Omega_h$ (north)", fontsize=11,
            color=earth, ha="center")
    _angle_arc(ax, 0.42, 90.0, 90.0 - psi_deg, r"$\psi$", earth, label_r=0.5)
    _angle_arc(ax, 0.62, 90.0, 90.0 - beta_deg, r"$\beta$", flt, label_r=0.7)
    _angle_arc(ax, 0.26, 90.0 - psi_deg, 90.0 - beta_deg, "", "0.35", label_r=0.0)
    mid = math.radians(90.0 - 0.5 * (psi_deg + beta_deg))
    ax.annotate(r"$\beta-\psi$", xy=(0.26 * math.cos(mid), 0.26 * math.sin(mid)),
                xytext=(0.55, 0.22), fontsize=11, color="0.35",
                arrowprops={"arrowstyle": "-", "color": "0.5", "lw": 0.8})
    ax.text(-0.95, 0.55, r"$\Omega_v$: along the vertical $\approx z$;" "\n"
            r"a rate about $z$ gives no torque" "\n" r"about the output axis $z$",
            fontsize=9.5, color=earth)
    ax.set_xlim(-1.0, 1.3)
    ax.set_ylim(-0.62, 1.15)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_title(r"(a) down the output axis: frames $Oxyz$ and $O\xi\eta\zeta$", fontsize=11)
    # Side views of the tilts: (axis, angle, tilt sign, rotation axis, projected rate).
    views = ((r"y", r"\delta", -1.0, r"x", r"$\omega_y = -\Omega_v\,\delta$"),
             (r"x", r"\gamma", 1.0, r"y", r"$\omega_x = \Omega_v\,\gamma$"))
    for row, (axis_name, angle_name, sgn, about, proj) in enumerate(views):
        axs = fig.add_subplot(gs[row, 1])
        a = sgn * math.radians(tilt_deg)
        axs.plot([-0.25, 1.15], [0, 0], color="0.6", lw=1, ls="--")
        axs.text(1.16, 0.0, "horizon", color="0.5", fontsize=8, va="center")
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
        axs.text(0.5, 0.42, rf"tilt about ${about}$", fontsize=9, color="0.3")
        axs.set_xlim(-0.75, 1.45)
        axs.set_ylim(-0.32, 0.72)
        axs.set_aspect("equal")
        axs.axis("off")
        axs.set_title(rf"({'bc'[row]}) tilt ${angle_name}$ of the ${axis_name}$ axis: {proj}",
                      fontsize=10)
    return fig


def _pair(name_t: str, t: object, name_y: str, y: object, *,
          nonnegative: bool = False) -> tuple[np.ndarray, np.ndarray]:
    # two points at least: the log-time panels draw from the second sample on
    t = v.check_array(name_t, t, ndim=1, min_size=2)
    y = v.check_array(name_y, y, ndim=1)
    if t.size != y.size:
        raise ValueError(f"{name_t} and {name_y} must have the same length")
    if nonnegative:
        _nonnegative(name_y, y)
    return t, y


def _nonnegative(name: str, y: np.ndarray) -> np.ndarray:
    if np.any(y < 0.0):
        raise ValueError(f"{name} must be >= 0 everywhere (a standard deviation or scale); "
                         f"got min {y.min()}")
    return y


def _mapping(name: str, value: object) -> Mapping:
    v.check_instance(name, value, Mapping)
    if not value:
        raise ValueError(f"{name} must hold at least one entry")
    return value


def _band(name: str, value: object) -> tuple[float, float]:
    """A pair ``(low, high)`` of positive numbers with low <= high."""
    if not isinstance(value, tuple | list) or len(value) != 2:
        raise TypeError(f"{name} must be a pair (low, high) of positive numbers; "
                        f"got {value!r}")
    lo, hi = (v.check_positive(name, b) for b in value)
    if lo > hi:
        raise ValueError(f"{name} must have low <= high; got ({lo}, {hi})")
    return lo, hi


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
        Left: linear time; right: log time.

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
    fig = Figure(figsize=(9.0, 4.2), layout="constrained")
    ax_lin, ax_log = fig.subplots(1, 2)
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
    ax_log.legend(fontsize=8, loc="lower left")
    return fig


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
    fig = Figure(figsize=(6.0, 3.6), layout="constrained")
    ax = fig.subplots()
    ax.plot(k, s, "o-")
    ax.axhline(pv, color="k", ls="--", label=f"paper: {pv:g} {unit}")
    ax.set_xlabel("κ: P(0) of N1…N4 = κ × stationary covariance")
    ax.set_ylabel(f"σ of ω_gc at {t_end:g} s ({unit})")
    ax.grid(True, alpha=0.3)
    ax.legend()
    return fig


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
        Left: σ at the last time per source (log axis); right: each source's share of the
        total variance over time (stacked).

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
    fig = Figure(figsize=(10.0, 4.4), layout="constrained")
    ax_bar, ax_share = fig.subplots(1, 2, width_ratios=[1.0, 1.2])
    end = np.sqrt(np.clip(var[:, -1], 0.0, None)) / scale
    order = np.argsort(end)
    keep = [i for i in order if end[i] > 0]
    ax_bar.barh([sources[i] for i in keep], [end[i] for i in keep], color="C0")
    ax_bar.set_xscale("log")
    ax_bar.set_xlabel(f"σ of ω_gc at {t[-1]:g} s from this source alone ({unit})")
    ax_bar.tick_params(axis="y", labelsize=8)
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
    ax_share.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.0, 0.5))
    return fig


def plot_estimates(t: object, estimates: object, truths: object, sigma: object, *,
                   unit: str = "″/s", t_zoom: float | None = 10.0) -> Figure:
    """Paper GC, Figure 4: the ω_gc estimate of each run (rows of ``estimates``) against its
    true value (``truths``, one per run), with the filter's ±σ band around the truth; a
    second panel zooms on the first ``t_zoom`` seconds (``None`` or 0: no zoom)."""
    t = v.check_array("t", t, ndim=1, min_size=1)
    est = v.check_array("estimates", estimates, shape=(None, t.size), min_size=1)
    tru = v.check_array("truths", truths, shape=(est.shape[0],))
    sig = _nonnegative("sigma", v.check_array("sigma", sigma, shape=(t.size,)))
    if t_zoom is not None:  # 0 (like None) draws no zoomed panel
        t_zoom = v.check_nonnegative("t_zoom", t_zoom)
    v.check_str("unit", unit)
    fig = Figure(figsize=(10.0, 4.0), layout="constrained")
    axes = fig.subplots(1, 2 if t_zoom else 1, squeeze=False)[0]
    for ax, tmax in zip(axes, (t[-1], t_zoom)):
        sel = t <= tmax
        for i in range(est.shape[0]):
            c = f"C{i}"
            ax.plot(t[sel], est[i, sel], color=c, lw=1.2, label=f"estimate, run {i + 1}")
            ax.axhline(tru[i], color=c, ls="--", lw=1, label=f"true ω_gc, run {i + 1}")
            ax.fill_between(t[sel], tru[i] - sig[sel], tru[i] + sig[sel], color=c, alpha=0.15)
        ax.set_xlabel("time (s)")
        ax.set_ylabel(f"ω_gc ({unit})")
        ax.grid(True, alpha=0.3)
        ax.set_title(f"0 – {tmax:g} s")
    axes[0].legend(fontsize=8)
    return fig


def plot_consistency(t: object, rms: object, sigma: object, rms_band: tuple[float, float],
                     nees: Mapping[str, tuple[object, tuple[float, float]]], *,
                     unit: str = "″/s") -> Figure:
    """Left: ensemble RMS error of ω_gc and the filter's σ (``unit``), with the 95 % band
    of an RMS of ``n`` runs (``rms_band`` = factors on σ).  Right: ensemble-average NEES for
    each entry of ``nees`` (label → (values, (low, high) bounds))."""
    t, r = _pair("t", t, "rms", rms, nonnegative=True)
    _, s = _pair("t", t, "sigma", sigma, nonnegative=True)
    lo, hi = _band("rms_band", rms_band)
    v.check_instance("nees", nees, Mapping)
    for label, entry in nees.items():
        if not isinstance(entry, tuple | list) or len(entry) != 2:
            raise TypeError(f"nees[{label!r}] must be a pair (values, (low, high)); "
                            f"got {type(entry).__name__}")
        _band(f"nees[{label!r}] bounds", entry[1])
    v.check_str("unit", unit)
    fig = Figure(figsize=(10.0, 4.0), layout="constrained")
    ax_r, ax_n = fig.subplots(1, 2)
    ax_r.loglog(t[1:], s[1:], "k", lw=2, label="filter σ")
    ax_r.fill_between(t[1:], lo * s[1:], hi * s[1:], color="0.8", label="95 % band for the RMS")
    ax_r.loglog(t[1:], r[1:], "C1", lw=1, label="ensemble RMS error")
    ax_r.set_xlabel("time (s)")
    ax_r.set_ylabel(f"ω_gc error ({unit})")
    ax_r.grid(True, which="both", alpha=0.3)
    ax_r.legend(fontsize=8)
    for i, (label, (vals, (blo, bhi))) in enumerate(nees.items()):
        _, y = _pair("t", t, f"nees[{label!r}]", np.nan_to_num(vals, nan=0.0))
        c = f"C{i}"
        ax_n.semilogx(t[1:], y[1:], color=c, lw=1, label=f"NEES, {label}")
        ax_n.axhspan(blo, bhi, color=c, alpha=0.15)
    ax_n.set_yscale("log")
    ax_n.set_xlabel("time (s)")
    ax_n.set_ylabel("ensemble-average NEES (bands: 95 % chi-square)")
    ax_n.grid(True, which="both", alpha=0.3)
    ax_n.legend(fontsize=8)
    return fig


def plot_sweep(sweeps: Mapping[str, tuple[object, object, float]], *, paper_value: float,
               unit: str = "″/s") -> Figure:
    """σ(100 s) of ω_gc (``unit``) when one shaping-filter parameter varies: ``sweeps`` maps
    a parameter label to ``(values, sigma, nominal value)``; log–log panels."""
    if sweeps is None or (isinstance(sweeps, Mapping) and not sweeps):
        raise ValueError("sweeps must hold at least one parameter")
    sweeps = _mapping("sweeps", sweeps)
    pv = v.check_positive("paper_value", paper_value)
    v.check_str("unit", unit)
    for label, entry in sweeps.items():
        if not isinstance(entry, tuple | list) or len(entry) != 3:
            raise TypeError(f"sweeps[{label!r}] must be a triple (values, sigma, nominal); "
                            f"got {entry!r:.80}")
        x, s = _pair(f"sweeps[{label!r}] values", entry[0], f"sweeps[{label!r}] sigma",
                     entry[1])
        # log–log panels: values, sigma and the nominal value must be > 0
        if np.any(x <= 0.0) or np.any(s <= 0.0):
            raise ValueError(f"sweeps[{label!r}] values and sigma must be > 0 (log axes)")
        v.check_positive(f"sweeps[{label!r}] nominal", entry[2])
    n = len(sweeps)
    cols = 3
    rows = -(-n // cols)
    fig = Figure(figsize=(10.0, 3.0 * rows), layout="constrained")
    axes = np.atleast_1d(fig.subplots(rows, cols, squeeze=False)).ravel()
    for ax, (label, (x, s, nominal)) in zip(axes, sweeps.items()):
        xx, ss = _pair("values", x, "sigma", s)
        ax.loglog(xx, ss, "o-")
        ax.axvline(nominal, color="0.5", ls=":", label="paper's value")
        ax.axhline(pv, color="k", ls="--", lw=1, label=f"{pv:g} {unit}")
        ax.set_xlabel(label)
        ax.set_ylabel(f"σ at 100 s ({unit})")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=7)
    for ax in axes[n:]:
        ax.set_visible(False)
    return fig


def plot_information(t: object, sig_known: object, sig_unknown: object, corr: object,
                     corr_frozen: object, *, unit: str = "″/s",
                     beta_frozen: float | None = None) -> Figure:
    """Left: σ of ω_gc from the angle sensor's information alone with ψ known and unknown
    (``unit``).  Right: |correlation| of the ψ and ω_gc information, for the turning float
    and for a float frozen at a constant angle."""
    t, a = _pair("t", t, "sig_known", sig_known, nonnegative=True)
    _, b = _pair("t", t, "sig_unknown", sig_unknown, nonnegative=True)
    _, c = _pair("t", t, "corr", corr)
    _, d = _pair("t", t, "corr_frozen", corr_frozen)
    for name, arr in (("corr", c), ("corr_frozen", d)):
        # a correlation, up to rounding
        if np.any(np.abs(arr) > 1.0 + 1e-9):
            raise ValueError(f"{name} must be in [-1, 1] (a correlation)")
    v.check_str("unit", unit)
    fig = Figure(figsize=(10.0, 4.0), layout="constrained")
    ax_s, ax_c = fig.subplots(1, 2)
    ax_s.loglog(t[1:], a[1:], label="ψ known")
    ax_s.loglog(t[1:], b[1:], label="ψ unknown (no prior)")
    ax_s.set_xlabel("time (s)")
    ax_s.set_ylabel(f"σ of ω_gc, angle-sensor information only ({unit})")
    ax_s.grid(True, which="both", alpha=0.3)
    ax_s.legend(fontsize=8)
    ax_c.semilogx(t[1:], 1.0 - np.abs(c[1:]), label="float turning (sin β_n grows)")
    ax_c.semilogx(t[1:], np.clip(1.0 - np.abs(d[1:]), 1e-17, None),
                  label="float frozen" if beta_frozen is None
                  else f"float frozen at β = {v.check_real('beta_frozen', beta_frozen):g} rad")
    ax_c.axhline(1.0 - np.sqrt(15.0) / 4.0, color="k", ls=":", lw=1,
                 label="1 − √15/4 (regressors t and t²)")
    ax_c.set_yscale("log")
    ax_c.set_xlabel("time (s)")
    ax_c.set_ylabel("1 − |correlation of ψ and ω_gc information|")
    ax_c.grid(True, which="both", alpha=0.3)
    ax_c.legend(fontsize=8)
    return fig
