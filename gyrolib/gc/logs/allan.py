"""Paper GC: Allan deviation of a record's sensors — the view gyro engineers read first —
with the curves paper GC's noise model predicts (:func:`allan_deviation`,
:func:`plot_allan`).  Computed with ``allantools`` (overlapping Allan deviation).

* **angle-sensor rate** — the angle sensor minus the nominal motion β_n(t) of Eq. (4) is
  the *phase* whose rate's Allan deviation is taken (rad/s).  Its white noise of variance
  ``R₁₁ = C_as/Δt`` is white phase noise: ``σ(τ) = √(3 R₁₁)/τ``, exact for every ``τ``
  that is a whole number of samples;
* **inclinometers** — each column is a *frequency* series (m/s²).  The model is Eq. (8)'s
  measurement sampled every Δt: the white sensor noise (``C_incl/τ``) plus the vibration N1
  of Eq. (6), whose Allan variance follows exactly from its sampled autocovariance
  (:func:`allan_model_vibration`); N1 is driven by white noise directly, so for
  ``τ ≪ 1/α1`` it is a random walk of intensity ``Q1`` (``σ² ≈ Q1 τ/3``).  A constant tilt
  has no Allan deviation.

Confidence intervals (68 %) use the equivalent degrees of freedom of Greenhall's algorithm
(``allantools.edf_greenhall``) for the noise that dominates each series — white phase noise
for the angle-sensor rate, random-walk frequency noise (the vibration) for the
inclinometers.

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
from gyrolib._repr import compact_repr
from gyrolib.gc.logs.record import GCRecord
from gyrolib.gc.model.nominal import nominal_motion_aperiodic
from gyrolib.gc.model.params import GyrocompassParams

__all__ = ["AllanDeviation", "AllanSeries", "allan_deviation", "allan_model_vibration",]

#: The series of :class:`AllanDeviation`, in order.
SERIES: Final[tuple[str, ...]] = ("angle_sensor", "inclinometer_y", "inclinometer_z")


@compact_repr
@dataclass(frozen=True)
class AllanSeries:
    """One sensor's Allan deviation: ``tau`` (s), ``adev`` (in ``unit``) with its 68 %
    confidence interval ``lo``…``hi`` from ``edf`` equivalent degrees of freedom, ``model``
    the curve paper GC's model predicts at ``tau``, ``n`` the number of terms of each
    estimate."""

    name: str
    unit: str
    tau: np.ndarray
    adev: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    edf: np.ndarray
    model: np.ndarray
    n: np.ndarray


@compact_repr
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


def allan_model_vibration(params: GyrocompassParams, tau: np.ndarray) -> np.ndarray:
    """Allan deviation (m/s²) of the vibration N1 of Eq. (6) sampled every ``params.dt``, at
    averaging times ``tau`` (whole multiples ``m dt``): exactly, from the autocovariance
    ``R(j) = C Φʲ P Cᵀ`` of the sampled stationary process (``Φ = exp(A dt)``, ``P`` the
    stationary covariance),
    ``σ²(m) = m⁻² Σ_{|j|<m} (m − |j|) (R(j) − R(m + j))``.

    Examples
    --------
    >>> from gyrolib import gc
    >>> p = gc.GyrocompassParams()      # τ ≪ 1/α1: a random walk of step variance Q1 dt,
    >>> m = 10                          # whose Allan variance is (2m² + 1)/(6m) Q1 dt
    >>> a = allan_model_vibration(p, np.array([m * p.dt]))[0]
    >>> f"{a / np.sqrt((2 * m**2 + 1) / (6 * m) * p.Q1 * p.dt):.4f}"
    '1.0000'
    """
    p = v.check_instance("params", params, GyrocompassParams)
    tau = v.check_array("tau", tau, ndim=1)
    m = np.rint(tau / p.dt).astype(np.int64)
    if np.any(m < 1) or np.any(np.abs(m * p.dt - tau) > 1e-6 * np.maximum(tau, p.dt)):
        raise ValueError(f"tau must be whole multiples of dt = {p.dt} s; got {tau.tolist()}")
    filt = p.vibration_filter()
    phi, _ = filt.discretize(p.dt)
    c = filt.C[0]
    vec = filt.stationary_covariance() @ c                  # P Cᵀ
    n_lag = 2 * int(m.max())
    R = np.empty(n_lag)
    for j in range(n_lag):
        R[j] = float(c @ vec)
        vec = phi @ vec
    out = np.empty(m.size)
    for i, mm in enumerate(m):
        j = np.arange(-(mm - 1), mm)
        w = (mm - np.abs(j)).astype(float)
        out[i] = math.sqrt(max(float(np.sum(w * (R[np.abs(j)] - R[mm + j]))) / mm**2, 0.0))
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


def _oadev(data: np.ndarray, rate: float, data_type: str, taus,
           alpha: int) -> tuple[np.ndarray, ...]:
    """``allantools.oadev`` and a 68 % interval from Greenhall's edf for noise ``alpha``
    (2 white phase, −2 random-walk frequency); where Greenhall has no value (few averaging
    intervals), the number of independent intervals ``N/m − 1``."""
    import allantools

    with contextlib.redirect_stdout(io.StringIO()):   # allantools prints warnings
        tau, ad, _, n = allantools.oadev(data, rate=rate, data_type=data_type, taus=taus)
        tau, ad = np.asarray(tau, float), np.asarray(ad, float)
        edf = np.empty(tau.size)
        lo = np.empty(tau.size)
        hi = np.empty(tau.size)
        for i, t in enumerate(tau):
            m = round(t * rate)
            try:
                e = float(allantools.edf_greenhall(alpha=alpha, d=2, m=m, N=data.size,
                                                   overlapping=True))
            except NotImplementedError:
                e = max(data.size / m - 1.0, 1.0)
            edf[i] = e
            lo[i], hi[i] = allantools.confidence_interval(ad[i], e)
    return tau, ad, lo, hi, edf, np.asarray(n, float)


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
    >>> bool(np.all((s.lo < 1.05 * s.model) & (s.model < 1.05 * s.hi)))
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
            tau, ad, lo, hi, edf, n = _oadev(phase, rate, "phase", taus, 2)
            model = np.sqrt(3.0 * R[0, 0]) / tau
            unit = "rad/s"
        else:
            tau, ad, lo, hi, edf, n = _oadev(x, rate, "freq", taus, -2)
            white = R[q, q] * dt / tau           # C / τ for R = C/Δt
            model = np.sqrt(white + allan_model_vibration(p_dt, tau) ** 2)
            unit = "m/s²"
        series.append(AllanSeries(name=name, unit=unit, tau=tau, adev=ad, lo=lo, hi=hi,
                                  edf=edf, model=model, n=n))
    return AllanDeviation(series=tuple(series), params=p, dt=dt, t_start=float(t[0]),
                          t_end=float(t[-1]), rows=int(t.size), filled=filled)
