"""Figures of the paper GC estimator chapters: each function takes data (arrays, already in
the units to show) and returns a :class:`matplotlib.figure.Figure`.

* :func:`plot_sigma_history` — paper GC, Figure 3 (σ of the ω_gc estimate against time);
* :func:`plot_p0_scale` — σ(100 s) against the scale of the initial N1…N4 covariance;
* :func:`plot_error_budget` — σ(100 s) by source, and the variance shares over time;
* :func:`plot_estimates` — paper GC, Figure 4 (estimates of ω_gc in runs against truth);
* :func:`plot_consistency` — ensemble RMS error against σ, and NEES with chi-square bands;
* :func:`plot_sweep` — σ(100 s) when the shaping-filter parameters vary;
* :func:`plot_information` — how ψ and ω_gc separate as the float turns.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
from matplotlib import colormaps
from matplotlib.figure import Figure

from gyrolib import _validation as v

__all__ = [
    "plot_consistency",
    "plot_error_budget",
    "plot_estimates",
    "plot_information",
    "plot_p0_scale",
    "plot_sigma_history",
    "plot_sweep",
]


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


def plot_sigma_history(t: object, curves: Mapping[str, object], *, paper_value: float,
                       paper_time: float = 100.0, unit: str = "″/s",
                       drop_time: float = 2.0) -> Figure:
    """Paper GC, Figure 3: σ of the ω_gc estimate (in ``unit``) against time (s), log scale;
    one line per entry of ``curves`` (label → σ), the paper's value as a marker, and the
    first ``drop_time`` seconds shaded."""
    if curves is None or (isinstance(curves, Mapping) and not curves):
        raise ValueError("curves must hold at least one curve")
    curves = _mapping("curves", curves)
    pv = v.check_positive("paper_value", paper_value)
    paper_time = v.check_nonnegative("paper_time", paper_time)
    drop_time = v.check_nonnegative("drop_time", drop_time)
    v.check_str("unit", unit)
    for label, s in curves.items():
        _pair("t", t, f"curves[{label!r}]", s, nonnegative=True)
    fig = Figure(figsize=(9.0, 4.2), layout="constrained")
    ax_lin, ax_log = fig.subplots(1, 2)
    for i, (label, s) in enumerate(curves.items()):
        tt, ss = _pair("t", t, f"curves[{label!r}]", s)
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


def plot_p0_scale(kappa: object, sigma: object, *, paper_value: float,
                  unit: str = "″/s") -> Figure:
    """σ(100 s) (``unit``) against the factor ``kappa`` multiplying the stationary
    covariance of N1…N4 in ``P(0)`` (0: the literal reading, 1: stationary)."""
    k, s = _pair("kappa", kappa, "sigma", sigma, nonnegative=True)
    _nonnegative("kappa", k)
    pv = v.check_positive("paper_value", paper_value)
    v.check_str("unit", unit)
    fig = Figure(figsize=(6.0, 3.6), layout="constrained")
    ax = fig.subplots()
    ax.plot(k, s, "o-")
    ax.axhline(pv, color="k", ls="--", label=f"paper: {pv:g} {unit}")
    ax.set_xlabel("κ: P(0) of N1…N4 = κ × stationary covariance")
    ax.set_ylabel(f"σ of ω_gc at 100 s ({unit})")
    ax.grid(True, alpha=0.3)
    ax.legend()
    return fig


def plot_error_budget(t: object, var: object, sources: tuple[str, ...], *,
                      scale: float = 1.0, unit: str = "″/s") -> Figure:
    """Error budget: left, σ at the last time per source (``sqrt(var)/scale``, log axis);
    right, each source's share of the total variance over time (stacked)."""
    if not isinstance(sources, tuple | list) or not all(isinstance(x, str) for x in sources):
        raise TypeError("sources must be a tuple or list of str (one label per row of var)")
    t = v.check_array("t", t, ndim=1, min_size=2)
    var = v.check_array("var", var, shape=(len(sources), t.size))
    scale = v.check_positive("scale", scale)
    v.check_str("unit", unit)
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
