"""Figures of the paper GC model chapter: each function takes data and returns a Figure.

* :func:`plot_shaping_psd` — the PSDs of ``N1`` and ``N3`` (paper GC, Figure 2);
* :func:`plot_nominal_motion` — the nominal float motion of Eq. (4) and its aperiodic
  approximation;
* :func:`plot_figure1` — paper GC's Figure 1 (frames ``Oxyz`` and ``Oξηζ``, angles ``ψ``,
  ``β``, ``δ``, ``γ``, Earth-rate components ``Ω_h``, ``Ω_v``) redrawn.
"""

from __future__ import annotations

import math

import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Arc, Circle

from gyrolib import _validation as v
from gyrolib.units import ARCSEC

__all__ = ["plot_figure1", "plot_nominal_motion", "plot_shaping_psd"]


def _same_length(names: tuple[str, ...], arrays: tuple[object, ...]) -> list[np.ndarray]:
    out = [v.check_array(n, a, ndim=1, min_size=1) for n, a in zip(names, arrays)]
    if len({a.size for a in out}) != 1:
        raise ValueError(f"{', '.join(names)} must have the same length")
    return out


def plot_shaping_psd(omega: object, psd_n1: object, psd_n3: object, *, alpha1: float,
                     alpha2: float, var_n1: float, var_n3: float) -> Figure:
    """Paper GC, Figure 2: one-sided PSDs (per rad/s) of the vibration acceleration ``N1``
    and of the random drift ``N3``, with the natural frequencies marked.

    Top row: ``Φ(ω)`` on log–log axes.  Bottom row: ``ω Φ(ω)`` against ``log ω``, a plot in
    which equal areas are equal variance (``∫ Φ dω = ∫ ω Φ d ln ω``), shaded; ``var_n1``,
    ``var_n3`` (the variances) are quoted in the panels.
    """
    omega, p1, p3 = _same_length(("omega", "psd_n1", "psd_n3"), (omega, psd_n1, psd_n3))
    a1 = v.check_positive("alpha1", alpha1)
    a2 = v.check_positive("alpha2", alpha2)
    var1 = v.check_positive("var_n1", var_n1)
    var3 = v.check_positive("var_n3", var_n3)
    if np.any(omega <= 0.0):
        raise ValueError("omega must be > 0 (log axes)")
    for name, p in (("psd_n1", p1), ("psd_n3", p3)):
        if np.any(p < 0.0):
            raise ValueError(f"{name} must be >= 0 (a power spectral density)")
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


def plot_nominal_motion(t: object, beta: object, beta_ap: object, t_fast: object,
                        beta_dot_fast: object, beta_dot_ap_fast: object, *, tau: float,
                        lag: float) -> Figure:
    """Nominal float motion, paper GC Eq. (4), against the aperiodic approximation.

    ``t``, ``beta``, ``beta_ap``: time (s) and the two angles (rad) over the run;
    ``t_fast``, ``beta_dot_fast``, ``beta_dot_ap_fast``: the start of the run, rates (rad/s);
    ``tau``: the time constant ``I/f`` (s); ``lag``: the asymptotic difference ``−k τ`` (rad).
    Three panels: the angle in degrees; the rate over the first few ``τ``; the difference
    ``β_n − β_ap`` in arcseconds on a logarithmic time axis.
    """
    t, b, bap = _same_length(("t", "beta", "beta_ap"), (t, beta, beta_ap))
    tf, bd, bdap = _same_length(("t_fast", "beta_dot_fast", "beta_dot_ap_fast"),
                                (t_fast, beta_dot_fast, beta_dot_ap_fast))
    tau = v.check_positive("tau", tau)
    lag = v.check_real("lag", lag)
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
    """
    beta_deg = v.check_in_range("beta_deg", beta_deg, 1.0, 80.0)
    psi_deg = v.check_in_range("psi_deg", psi_deg, 1.0, 80.0)
    tilt_deg = v.check_in_range("tilt_deg", tilt_deg, 1.0, 40.0)
    if not psi_deg < beta_deg:
        raise ValueError("psi_deg must be < beta_deg (for a legible drawing)")
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
