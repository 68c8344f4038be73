"""Paper GC: Allan deviation of a record's sensors — the view gyro engineers read first —
with the curves paper GC's noise model predicts (:func:`allan_deviation`,
:func:`plot_allan`).  Computed with ``allantools`` (overlapping Allan deviation).

* **angle-sensor rate** — the angle sensor minus the nominal motion β_n(t) of Eq. (4) is
  the *phase* whose rate's Allan deviation is taken (rad/s).  Its white noise of variance
  ``R₁₁ = C_as/Δt`` is white phase noise: ``σ(τ) = √(3 R₁₁)/τ``, exact for every ``τ``
  that is a whole number of samples;
* **inclinometers** — each column is a *frequency* series (m/s²).  The model is the white
  sensor noise ``C_incl/τ`` plus the vibration N1 of Eq. (6) seen through the Allan filter,
  ``σ²(τ) = ∫₀^∞ Φ(ω) · 2 sin⁴(ωτ/2)/(ωτ/2)² dω`` with ``Φ`` the one-sided PSD of N1
  (:func:`gyrolib.gc.psd`); N1 is driven by white noise directly, so for ``τ ≪ 1/α1`` it
  is a random walk of intensity ``Q1`` (``σ² ≈ Q1 τ/3``).  A constant tilt has no Allan
  deviation.

The Allan deviation needs evenly spaced samples: it is taken over the record's longest
stretch without a gap (a step longer than 1.5 median steps), with missing cells filled by
linear interpolation (counted in the result).
"""

from __future__ import annotations

import contextlib
import io
import math
from dataclasses import dataclass
from typing import Final

import numpy as np

from gyrolib import _validation as v
from gyrolib.gc.nominal import nominal_motion_aperiodic
from gyrolib.gc.params import GyrocompassParams
from gyrolib.gc.record import GCRecord
from gyrolib.gc.shaping_filters import psd

__all__ = ["AllanDeviation", "AllanSeries", "allan_deviation", "allan_model_vibration",
           "plot_allan"]

#: The series of :class:`AllanDeviation`, in order.
SERIES: Final[tuple[str, ...]] = ("angle_sensor", "inclinometer_y", "inclinometer_z")


@dataclass(frozen=True)
class AllanSeries:
    """One sensor's Allan deviation: ``tau`` (s), ``adev`` and its 1σ error ``error`` (in
    ``unit``), ``model`` the curve paper GC's model predicts at ``tau``, ``n`` the number of
    terms of each estimate."""

    name: str
    unit: str
    tau: np.ndarray
    adev: np.ndarray
    error: np.ndarray
    model: np.ndarray
    n: np.ndarray


@dataclass(frozen=True)
class AllanDeviation:
    """Allan deviations of a paper-GC record: ``series`` (angle-sensor rate, inclinometer y,
    inclinometer z), over the stretch ``t_start``…``t_end`` of ``rows`` evenly spaced rows at
    ``dt``; ``filled`` (3,) missing cells interpolated per column; ``params`` the model of
    the ``model`` curves."""

    series: tuple[AllanSeries, ...]
    params: GyrocompassParams
    dt: float
    t_start: float
    t_end: float
    rows: int
    filled: np.ndarray

    def get(self, name: str) -> AllanSeries:
        """The series of sensor ``name`` (one of ``angle_sensor``, ``inclinometer_y``,
        ``inclinometer_z``)."""
        for s in self.series:
            if s.name == name:
                return s
        raise ValueError(f"name must be one of {SERIES}; got {name!r}")


def allan_model_vibration(params: GyrocompassParams, tau: np.ndarray, *,
                          n: int = 6000) -> np.ndarray:
    """Allan deviation (m/s²) of the vibration N1 of Eq. (6) at averaging times ``tau`` (s):
    ``√∫₀^∞ Φ(ω) 2 sin⁴(ωτ/2)/(ωτ/2)² dω`` by the trapezoid rule in ``ln ω`` over ten decades
    about ``α1`` and ``1/τ`` (``sin⁴`` replaced by its mean 3/8 where ``ωτ > 200``).

    Examples
    --------
    >>> from gyrolib import gc
    >>> p = gc.GyrocompassParams()                   # τ ≪ 1/α1: a random walk, Q1 τ / 3
    >>> a = allan_model_vibration(p, np.array([0.01]))[0]
    >>> f"{a / np.sqrt(p.Q1 * 0.01 / 3):.3f}"
    '1.000'
    """
    p = v.check_instance("params", params, GyrocompassParams)
    tau = v.check_array("tau", tau, ndim=1)
    filt = p.vibration_filter()
    out = np.empty(tau.size)
    for i, t in enumerate(tau):
        lo = min(p.alpha1, 1.0 / t) * 1e-5
        hi = max(p.alpha1, 1.0 / t) * 1e5
        w = np.geomspace(lo, hi, n)
        x = 0.5 * w * t
        s4 = np.where(w * t > 200.0, 0.375, np.sin(x) ** 4)
        f = psd(filt, w) * 2.0 * s4 / x**2 * w          # d(ln ω) = dω / ω
        out[i] = math.sqrt(float(np.trapezoid(f, np.log(w))))
    return out


def _longest_stretch(t: np.ndarray) -> tuple[int, int, float]:
    dt = float(np.median(np.diff(t)))
    breaks = np.nonzero(np.diff(t) > 1.5 * dt)[0]
    starts = np.concatenate([[0], breaks + 1])
    ends = np.concatenate([breaks + 1, [t.size]])
    k = int(np.argmax(ends - starts))
    return int(starts[k]), int(ends[k]), dt


def _filled(x: np.ndarray, name: str) -> tuple[np.ndarray, int]:
    bad = ~np.isfinite(x)
    if np.count_nonzero(~bad) < 2:
        raise ValueError(f"record.{name} must hold at least two known values in its longest "
                         "stretch without a gap")
    if not np.any(bad):
        return x, 0
    i = np.arange(x.size)
    y = x.copy()
    y[bad] = np.interp(i[bad], i[~bad], x[~bad])
    return y, int(np.count_nonzero(bad))


def _oadev(data: np.ndarray, rate: float, data_type: str, taus) -> tuple[np.ndarray, ...]:
    import allantools

    with contextlib.redirect_stdout(io.StringIO()):   # allantools prints warnings
        tau, ad, err, n = allantools.oadev(data, rate=rate, data_type=data_type, taus=taus)
    return (np.asarray(tau, float), np.asarray(ad, float), np.asarray(err, float),
            np.asarray(n, float))


def allan_deviation(record: GCRecord, params: GyrocompassParams | None = None, *,
                    taus: str | np.ndarray = "octave") -> AllanDeviation:
    """Overlapping Allan deviation of the angle-sensor rate and of both inclinometers of a
    paper-GC record, with the curves of paper GC's noise model (see the module docstring).

    Parameters
    ----------
    record : GCRecord
        The record (SI).
    params : GyrocompassParams, optional
        The model of the nominal motion and of the predicted curves (default the paper's);
        the sample interval is the record's median step.
    taus : {"octave", "decade", "all"} or array_like
        Averaging times (s), as ``allantools`` takes them.

    Returns
    -------
    AllanDeviation

    Examples
    --------
    >>> from gyrolib import gc
    >>> rec = gc.simulate_record(gc.GyrocompassParams(), 20.0, seed=3).record
    >>> ad = gc.allan_deviation(rec)
    >>> s = ad.get("angle_sensor")              # white phase noise: √(3 R₁₁)/τ
    >>> bool(np.all(np.abs(s.adev[:6] / s.model[:6] - 1) < 4 * s.error[:6] / s.adev[:6]))
    True
    """
    import dataclasses

    v.check_instance("record", record, GCRecord)
    p = GyrocompassParams() if params is None else v.check_instance(
        "params", params, GyrocompassParams)
    if record.n < 10:
        raise ValueError(f"record must hold at least 10 rows; got {record.n}")
    if not (isinstance(taus, str) and taus in ("octave", "decade", "all")):
        taus = v.check_array("taus", taus, ndim=1, min_size=1)
        if np.any(taus <= 0):
            raise ValueError("taus must be positive (s)")
    i0, i1, dt = _longest_stretch(record.t)
    if i1 - i0 < 10:
        raise ValueError(f"record must hold a stretch of at least 10 rows without a gap; the "
                         f"longest has {i1 - i0}")
    if p.measurement_noise == "intensity_over_dt":
        p_dt = dataclasses.replace(p, dt=dt)
    else:
        p_dt = p
    t = record.t[i0:i1]
    rate = 1.0 / dt
    series = []
    filled = np.zeros(3, dtype=np.int64)
    R = np.diag([p.C_as, p.C_incl_y, p.C_incl_z]) / (
        dt if p.measurement_noise == "intensity_over_dt" else 1.0)
    for q, name in enumerate(SERIES):
        x, filled[q] = _filled(getattr(record, name)[i0:i1], name)
        if q == 0:
            phase = x - nominal_motion_aperiodic(p_dt, t).beta
            tau, ad, err, n = _oadev(phase, rate, "phase", taus)
            model = np.sqrt(3.0 * R[0, 0]) / tau
            unit = "rad/s"
        else:
            tau, ad, err, n = _oadev(x, rate, "freq", taus)
            white = R[q, q] * dt / tau           # C / τ for R = C/Δt
            model = np.sqrt(white + allan_model_vibration(p_dt, tau) ** 2)
            unit = "m/s²"
        series.append(AllanSeries(name=name, unit=unit, tau=tau, adev=ad, error=err,
                                  model=model, n=n))
    return AllanDeviation(series=tuple(series), params=p, dt=dt, t_start=float(t[0]),
                          t_end=float(t[-1]), rows=int(t.size), filled=filled)


def plot_allan(result: AllanDeviation, *, title: str | None = None):
    """Left: the Allan deviation of the angle-sensor rate (rad/s); right: of the two
    inclinometers (m/s²); each with its error bars and, dashed, paper GC's model.  Returns a
    :class:`matplotlib.figure.Figure`."""
    import matplotlib.pyplot as plt

    if not isinstance(result, AllanDeviation):
        raise TypeError(f"result must be an AllanDeviation; got {type(result).__name__}")
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(9.0, 3.8))
    s = result.series[0]
    ax.errorbar(s.tau, s.adev, yerr=s.error, fmt="o-", ms=3, lw=1, color="C0",
                label="angle-sensor rate")
    ax.plot(s.tau, s.model, "--", color="k", lw=1, label="model: white angle noise √(3R)/τ")
    ax.set_ylabel("Allan deviation (rad/s)")
    for q, s in enumerate(result.series[1:], start=1):
        bx.errorbar(s.tau, s.adev, yerr=s.error, fmt="o-", ms=3, lw=1, color=f"C{q}",
                    label=s.name)
    s = result.series[1]
    bx.plot(s.tau, s.model, "--", color="k", lw=1,
            label="model: sensor noise + vibration N1")
    bx.set_ylabel("Allan deviation (m/s²)")
    for a in (ax, bx):
        a.set_xscale("log")
        a.set_yscale("log")
        a.set_xlabel("τ (s)")
        a.grid(True, which="both", lw=0.3, alpha=0.5)
        a.legend(fontsize=7)
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return fig
