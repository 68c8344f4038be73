"""Paper GC: Allan deviation of a record's sensors — the view gyro engineers read first —
with the curves paper GC's noise model predicts (:func:`allan_deviation`,
:func:`plot_allan`), and the noise terms read off it (:func:`noise_terms`).  The overlapping
Allan deviation is computed here in a few lines of numpy (NIST SP 1065, Eq. (11); the tests
check it against ``allantools``, which the library does not need at run time).

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

Confidence intervals (68 %, χ² with the equivalent degrees of freedom) use the edf of the
overlapping Allan variance for the noise that dominates each series (NIST SP 1065, Table 5)
— white phase noise for the angle-sensor rate, random-walk frequency noise (the vibration)
for the inclinometers.

**Noise terms** (IEEE Std 952-1997, Annex C, where the lines of slope −½, 0 and +½ are
read off the log-log Allan deviation).  The angle random walk ``N = √a₋₁`` (the −½ line,
read at τ = 1 s) and the rate random walk ``K = √(3a₁)`` (the +½ line, read at τ = 3 s)
come from the standard fit of the Allan variance, ``σ²(τ) = Σ a_p τ^p`` for p = −2 … 2,
with a_p >= 0 (non-negative least squares weighted by each point's χ² spread, for the
least favourable of white angle, white rate and rate random-walk noise), each with a 1σ
uncertainty from the fit (scaled by :data:`_OVERLAP_INFLATION`: neighbouring overlapping
averages share data).  The bias instability is IEEE Std 952's definition, the curve's
minimum over 0.664 (:data:`FLICKER_FLOOR`), not a fitted constant: the ratio of the two
definitions is 1 by construction.  No term lies above the data: a term's line and the
line of its upper bound stay at or below the measured deviation's 68 % upper bound at
every τ of the curve; a term whose coefficient is not above twice its uncertainty, whose
line would cross that bound, or whose reading τ lies outside the measured τ range is not
identified: only an upper bound is given (the largest line inside the data), with the τ
range it comes from.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Final

import numpy as np

from gyrolib import _validation as v
from gyrolib._repr import compact_repr
from gyrolib.filtering.consistency import chi2_ppf
from gyrolib.gc.logs.record import GCRecord
from gyrolib.gc.model.nominal import nominal_motion_aperiodic
from gyrolib.gc.model.params import GyrocompassParams

__all__ = ["AllanDeviation", "AllanSeries", "NoiseTerm", "allan_deviation",
           "allan_model_vibration", "allan_noise_terms", "allan_series", "curve_upper_bound",
           "edf_oadev", "noise_terms", "oadev", "rest_excursion"]

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


#: The normal distribution's mass within ±1σ, erf(1/√2) = 0.6827: the "68 %" of a 1σ bound.
ONE_SIGMA_MASS: Final[float] = math.erf(1.0 / math.sqrt(2.0))


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


def _factors(n: int, rate: float, taus) -> np.ndarray:
    """Averaging factors m (τ = m/rate) of ``taus`` for ``n`` phase points: "octave" (1, 2,
    4, ...), "decade" (1, 2, 4, 10, 20, 40, ...), "all", or times in s; those with at least
    two terms (2m < n - 1), sorted, without duplicates."""
    if isinstance(taus, str):
        if taus == "octave":
            m = 2.0 ** np.arange(int(math.log2(n)) + 1)
        elif taus == "decade":
            m = np.array([c * 10.0 ** k for k in range(int(math.log10(n)) + 1)
                          for c in (1, 2, 4)])
        else:
            m = np.arange(1.0, n + 1)
    else:
        m = np.round(np.asarray(taus, float) * rate)
    m = np.unique(m[(m >= 1) & (m < n)]).astype(np.int64)
    return m[n - 2 * m > 1]


def oadev(data: np.ndarray, rate: float, data_type: str = "phase",
          taus: str | np.ndarray = "octave") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Overlapping Allan deviation (NIST SP 1065, Eq. (11)): ``(tau, adev, n)``, ``n`` the
    number of second differences of each estimate.  ``data_type`` "phase" (an angle, rad:
    the deviation is of its rate) or "freq" (a rate, or an acceleration), sampled at
    ``rate`` Hz; ``taus`` as in :func:`allan_deviation`.

    Examples
    --------
    >>> x = np.random.default_rng(1).standard_normal(100000)   # white phase: √3 σ/τ
    >>> tau, ad, n = oadev(x, 1.0, "phase", np.array([1.0, 10.0]))
    >>> [f"{a * t / np.sqrt(3):.1f}" for t, a in zip(tau, ad)]
    ['1.0', '1.0']
    """
    v.check_positive("rate", rate)
    v.check_choice("data_type", data_type, ("phase", "freq"))
    x = v.check_array("data", data, ndim=1, min_size=3)
    if data_type == "freq":     # phase = ∫ rate dt, from 0 (the mean removed: rounding)
        x = np.concatenate([[0.0], np.cumsum(x - np.mean(x)) / rate])
    m = _factors(x.size, rate, taus)
    if m.size == 0:
        raise ValueError(f"data must be long enough for one averaging time; got {x.size} "
                         "points")
    ad = np.empty(m.size)
    n = np.empty(m.size, dtype=np.int64)
    for i, mm in enumerate(m):
        d = x[2 * mm:] - 2.0 * x[mm:-mm] + x[:-2 * mm]
        n[i] = d.size
        ad[i] = math.sqrt(float(np.dot(d, d)) / (2.0 * d.size)) * rate / mm
    return m / rate, ad, n


def edf_oadev(alpha: int, m: np.ndarray, n_phase: int) -> np.ndarray:
    """Equivalent degrees of freedom of the overlapping Allan variance at averaging factors
    ``m`` over ``n_phase`` phase points, for power-law noise ``alpha`` (2 white phase,
    0 white frequency, −2 random-walk frequency): NIST SP 1065, Table 5; at least 1.

    Examples
    --------
    >>> f"{edf_oadev(2, np.array([1]), 1001)[0]:.3f}"    # (N+1)(N−2m)/(2(N−m))
    '500.499'
    """
    m = np.asarray(m, float)
    N = float(n_phase)
    if alpha == 2:
        e = (N + 1) * (N - 2 * m) / (2 * (N - m))
    elif alpha == 0:
        e = (3 * (N - 1) / (2 * m) - 2 * (N - 2) / N) * 4 * m**2 / (4 * m**2 + 5)
    elif alpha == -2:
        e = (N - 2) / m * ((N - 1) ** 2 - 3 * m * (N - 1) + 4 * m**2) / (N - 3) ** 2
    else:
        raise ValueError(f"alpha must be one of 2, 0, -2; got {alpha!r}")
    return np.maximum(e, 1.0)


def _interval(ad: np.ndarray, edf: np.ndarray, ci: float = ONE_SIGMA_MASS
              ) -> tuple[np.ndarray, np.ndarray]:
    """``ci`` confidence interval of a deviation with ``edf`` degrees of freedom (χ²)."""
    import scipy.stats

    lo = ad * np.sqrt(edf / scipy.stats.chi2.ppf(0.5 + ci / 2, edf))
    hi = ad * np.sqrt(edf / scipy.stats.chi2.ppf(0.5 - ci / 2, edf))
    return lo, hi


def _oadev(data: np.ndarray, rate: float, data_type: str, taus,
           alpha: int) -> tuple[np.ndarray, ...]:
    """:func:`oadev` and its 68 % interval from the edf of noise ``alpha``."""
    tau, ad, n = oadev(data, rate, data_type, taus)
    n_phase = data.size + (1 if data_type == "freq" else 0)
    edf = edf_oadev(alpha, np.round(tau * rate), n_phase)
    lo, hi = _interval(ad, edf)
    return tau, ad, lo, hi, edf, n.astype(float)


@dataclass(frozen=True)
class NoiseTerm:
    """One noise term read off an Allan deviation (IEEE Std 952): ``name``, ``value`` with
    its 1σ interval ``lo``…``hi`` (SI, ``unit``), ``tau`` (s) where the term contributes
    most of σ² (None for a coefficient of 0: the term is nowhere), ``identified`` (else
    ``value`` = ``hi`` is only an upper bound and ``lo`` is 0), ``slope`` (−½, 0 or +½),
    ``tau_range`` the measured curve's first and last τ (s) and ``read_at`` the τ (s) at
    which IEEE Std 952 reads the term off its line (1 s for the −½ line, 3 s for the +½
    line, the curve's minimum for bias instability): a term read outside ``tau_range``
    is extrapolated, and never identified."""

    name: str
    value: float
    lo: float
    hi: float
    unit: str
    tau: float | None
    identified: bool
    slope: float
    tau_range: tuple[float, float] = (math.nan, math.nan)
    read_at: float = math.nan
    std: float = math.nan

    @property
    def sigma(self) -> float:
        """The 1σ uncertainty of ``value``: the fit's (``std``, before ``hi`` is clipped to
        the data's bound) when given, else half the interval ``lo``…``hi``."""
        return self.std if math.isfinite(self.std) else 0.5 * (self.hi - self.lo)

    @property
    def extrapolated(self) -> bool:
        """Whether IEEE Std 952's reading τ lies outside the measured τ range."""
        lo, hi = self.tau_range
        return not (lo <= self.read_at <= hi)

    def describe(self, scale: float = 1.0, unit: str | None = None) -> str:
        """``"name = value ± sigma unit (at τ = ...)"``, or ``"name <= value"`` when not
        identified (with the τ range the bound comes from when the term is read outside
        it); ``scale`` divides the SI values (a display unit)."""
        u = unit or self.unit
        if not self.identified:
            lo, hi = self.tau_range
            if self.extrapolated:
                why = (f"a bound from tau = {lo:.3g} to {hi:.3g} s; IEEE 952 reads it at "
                       f"tau = {self.read_at:.3g} s, outside the measured range")
            elif self.slope == 0.0:
                why = ("not identified: the curve has no significant minimum between a "
                       "fall and a rise")
            else:
                why = (f"not identified: its tau^{2 * self.slope:+.0f} term is not above "
                       "twice its uncertainty, or its line would rise above the measured "
                       "deviation's 68 % upper bound")
            return f"{self.name} <= {self.value / scale:.3g} {u} ({why})"
        where = (f"curve minimum at tau = {self.tau:.3g} s, divided by 0.664"
                 if self.slope == 0.0 else f"dominant near tau = {self.tau:.3g} s")
        return (f"{self.name} = {self.value / scale:.3g} ± {self.sigma / scale:.2g} {u} "
                f"(1 sigma; {where})")


#: Factor on the fit's standard errors: the octave-spaced overlapping averages share data,
#: which a least-squares fit that treats them as independent does not see.  On simulated
#: records (white rate noise, with and without white angle noise and a rate random walk,
#: 30 seeds each) the normalized error of N had an RMS of 1.5 with the plain standard
#: errors; doubled, the ±1σ interval covers N in about 3 cases out of 4.
_OVERLAP_INFLATION: Final[float] = 1.5

#: The three terms: name and slope of the tangent line.
_TERMS: Final[tuple[tuple[str, float], ...]] = (
    ("angle random walk", -0.5), ("bias instability", 0.0), ("rate random walk", 0.5))

#: IEEE Std 952-1997, Annex C: the flicker floor of the Allan deviation is 0.664 B
#: (√(2 ln 2 / π)), and the bias instability is read as the curve's minimum over it.
FLICKER_FLOOR: Final[float] = 0.664

#: τ (s) at which IEEE Std 952 reads the −½ line (N = σ(1 s)) and the +½ line (K = σ(3 s)).
READ_AT: Final[dict[float, float]] = {-0.5: 1.0, 0.5: 3.0}


def allan_noise_terms(result: AllanDeviation) -> dict[str, tuple[NoiseTerm, ...]]:
    """:func:`noise_terms` of each series of an :class:`AllanDeviation`: for the
    angle-sensor rate the angle random walk, bias instability and rate random walk; for an
    inclinometer the velocity random walk, the bias instability and the +½ slope, which
    on paper GC's platform is the vibration filter N1 of Eq. (6) rising over the record's τ
    (named so: not an acceleration random walk).

    Examples
    --------
    >>> from gyrolib import gc
    >>> rec = gc.simulate_record(gc.GyrocompassParams(), 20.0, seed=3).record
    >>> terms = gc.allan_noise_terms(gc.allan_deviation(rec))
    >>> [t.name for t in terms["inclinometer_y"]]
    ['velocity random walk', 'bias instability', 'vibration N1 (+1/2 slope)']
    """
    v.check_instance("result", result, AllanDeviation)
    # an inclinometer's +½ slope is the vibration filter N1 of Eq. (6) (its spectrum rises
    # over the τ of the record), not a random walk of acceleration
    accel = ("velocity random walk", "bias instability", "vibration N1 (+1/2 slope)")
    return {s.name: noise_terms(s, None if s.name == "angle_sensor" else accel)
            for s in result.series}


def _nnls_cov(M: np.ndarray, b: np.ndarray, active_only: bool = False
              ) -> tuple[np.ndarray, np.ndarray]:
    """Non-negative least squares of ``M a = b`` with the columns scaled to unit norm (the
    powers of τ span many decades), and the covariance of ``a``: of the coefficients left
    free (``active_only``: those above zero; else all of them, for an upper bound)."""
    import scipy.optimize

    norm = np.linalg.norm(M, axis=0)
    norm[norm == 0] = 1.0
    Ms = M / norm
    x, _ = scipy.optimize.nnls(Ms, b)
    a = x / norm
    keep = x > 0 if active_only else np.ones(x.size, dtype=bool)
    cov = np.zeros((x.size, x.size))
    if np.any(keep):
        sub = Ms[:, keep]
        c = np.linalg.pinv(sub.T @ sub)
        cov[np.ix_(keep, keep)] = c / np.outer(norm[keep], norm[keep])
    return a, cov


def noise_terms(series: AllanSeries, names: tuple[str, str, str] | None = None
                ) -> tuple[NoiseTerm, ...]:
    """Angle random walk N, bias instability B and rate random walk K of an Allan
    deviation (see the module docstring; IEEE Std 952-1997, Annex C).  Units: N in
    ``unit``·√s, B in ``unit``, K in ``unit``/√s.  ``names`` renames them (e.g. velocity
    random walk for an accelerometer).

    Every term stays inside the data: its line (``N/√τ``, ``0.664 B``, ``K √(τ/3)``) and
    the line of its upper bound lie at or below the measured deviation's 68 % upper bound
    at every τ of the curve (:func:`curve_upper_bound`: the bound the whole curve stays
    under with 68 % probability).  N and K come from the fit of the Allan variance
    and are identified only when their coefficient is above twice its uncertainty, their
    line inside the data within its 1σ (the value and its upper bound are then clipped to
    the largest line inside the data), and IEEE Std 952's reading τ (1 s, 3 s) inside the
    measured range; otherwise they are upper bounds (the largest such line that stays
    inside the data, at most the fit's coefficient plus twice its uncertainty).  B is IEEE
    Std 952's: the curve's minimum over 0.664, identified when the minimum lies between a
    fall and a significant rise (a later point's 68 % lower bound above the minimum's
    upper bound), else an upper bound.

    Examples
    --------
    >>> rng = np.random.default_rng(4)
    >>> rate = rng.standard_normal(200000) * 0.01 * np.sqrt(100.0)   # N = 0.01, 100 Hz
    >>> tau, ad, n = oadev(rate, 100.0, "freq")
    >>> s = AllanSeries("x", "rad/s", tau, ad, ad, ad, ad, ad, n.astype(float))
    >>> arw, bi, rrw = noise_terms(s)
    >>> f"{arw.value:.4f} ± {arw.sigma:.4f}", arw.identified, bi.identified
    ('0.0100 ± 0.0000', True, False)
    """
    v.check_instance("series", series, AllanSeries)
    names = names or tuple(n for n, _ in _TERMS)
    tau, ad = np.asarray(series.tau), np.asarray(series.adev)
    lo68 = np.minimum(np.asarray(series.lo, dtype=float), ad)
    hi68 = curve_upper_bound(series)
    a, sd, free, scale = _power_law_fit(series)
    powers = np.arange(-2, 3)
    factor = {-0.5: 1.0, 0.0: FLICKER_FLOOR**2, 0.5: 1.0 / 3.0}    # a_p = factor · term²
    span = (float(tau[0]), float(tau[-1]))
    out = []
    for (_, slope), label in zip(_TERMS, names):
        unit = {-0.5: f"{series.unit}·√s", 0.0: series.unit,
                0.5: f"{series.unit}/√s"}[slope]
        if slope == 0.0:
            out.append(_bias_instability(label, unit, tau, ad, lo68, hi68, span))
            continue
        p = round(2 * slope)
        i = int(np.flatnonzero(powers == p)[0])
        ai, si = float(a[i]), float(sd[i])
        # the largest line a τ^p at or below the measured deviation's 68 % upper bound at
        # every τ of the curve
        cap = float(np.min(hi68**2 / tau**p))
        read_at = READ_AT[slope]
        inside = span[0] <= read_at <= span[1]
        # identified: above twice its uncertainty, its line inside the data within its
        # 1σ (the value then clipped to the data's bound), and read inside the τ range
        identified = ai > 2.0 * si and si > 0 and ai - si <= cap and inside
        std = math.nan
        if identified:
            hi_a, lo_a = min(ai + si, cap), max(ai - si, 0.0)
            value = math.sqrt(min(ai, cap) / factor[slope])
            std = 0.5 * (math.sqrt((ai + si) / factor[slope])
                         - math.sqrt(lo_a / factor[slope]))
        else:
            hi_a = min(ai + 2.0 * max(si, math.sqrt(max(free[i], 0.0))), cap)
            lo_a = 0.0
            value = math.sqrt(hi_a / factor[slope])
        # the τ where the term contributes most of σ² (none for a coefficient of 0)
        share = (a[i] * tau**p) / scale
        where = float(tau[int(np.argmax(share))]) if ai > 0.0 else None
        out.append(NoiseTerm(name=label, value=value, lo=math.sqrt(lo_a / factor[slope]),
                             hi=math.sqrt(hi_a / factor[slope]), unit=unit, tau=where,
                             identified=identified, slope=slope, tau_range=span,
                             read_at=read_at, std=std))
    return tuple(out)


def curve_upper_bound(series: AllanSeries, level: float = ONE_SIGMA_MASS) -> np.ndarray:
    """The measured deviation's upper bound at each τ that holds at every τ of the curve
    together with probability ``level`` (default 68 %): each point's χ² bound with the
    least favourable edf of white phase, white rate and random-walk rate noise (NIST SP
    1065, Table 5), at the one-sided level ``level^(1/n)`` over the curve's ``n`` points
    (Šidák).  A term's line that crosses it at some τ claims more than the data show.

    Examples
    --------
    >>> rate = np.random.default_rng(5).standard_normal(2**14)
    >>> s = allan_series(rate, 1.0)
    >>> bool(np.all(curve_upper_bound(s) >= s.hi))      # wider than each point's 68 %
    True
    """
    v.check_instance("series", series, AllanSeries)
    level = v.check_real("level", level)
    if not 0.0 < level < 1.0:
        raise ValueError(f"level must be a probability in (0, 1); got {level}")
    tau, ad = np.asarray(series.tau), np.asarray(series.adev)
    m = np.maximum(np.round(tau / tau[0]), 1.0)
    n_phase = int(np.max(np.asarray(series.n) + 2 * m))
    edf = np.min([edf_oadev(alpha, m, n_phase) for alpha in (2, 0, -2)], axis=0)
    below = level ** (1.0 / tau.size)          # each point's one-sided coverage
    return ad * np.sqrt(edf / chi2_ppf(1.0 - below, edf))


def _bias_instability(label: str, unit: str, tau: np.ndarray, ad: np.ndarray,
                      lo68: np.ndarray, hi68: np.ndarray, span: tuple[float, float]
                      ) -> NoiseTerm:
    """IEEE Std 952's bias instability: the curve's minimum over 0.664, identified when the
    minimum is between a fall and a significant rise; else the bound ``min(hi68)/0.664``,
    the largest flat line at or below the 68 % upper bound at every τ."""
    k = int(np.argmin(ad))
    rises = k + 1 < ad.size and float(np.max(lo68[k + 1:])) > float(hi68[k])
    identified = 0 < k and rises
    top = float(np.min(hi68))
    if identified:
        value, lo, hi = (float(ad[k]) / FLICKER_FLOOR, float(lo68[k]) / FLICKER_FLOOR,
                         top / FLICKER_FLOOR)
    else:
        value, lo, hi = top / FLICKER_FLOOR, 0.0, top / FLICKER_FLOOR
    return NoiseTerm(name=label, value=value, lo=lo, hi=hi, unit=unit, tau=float(tau[k]),
                     identified=identified, slope=0.0, tau_range=span, read_at=float(tau[k]))


def _power_law_fit(series: AllanSeries) -> tuple[np.ndarray, ...]:
    """The fit ``σ²(τ) = Σ a_p τ^p`` over p = −2 … 2 with a_p >= 0: the coefficients, their
    standard deviations (of those left free), those of every coefficient (for a bound),
    and the fitted σ² at each τ."""
    tau, ad = np.asarray(series.tau), np.asarray(series.adev)
    # the edf of each point for the least favourable of white phase, white rate and
    # random-walk rate noise (the series' own edf assumes one noise type throughout)
    m = np.maximum(np.round(tau / tau[0]), 1.0)
    n_phase = int(np.max(np.asarray(series.n) + 2 * m))
    edf = np.min([edf_oadev(alpha, m, n_phase) for alpha in (2, 0, -2)], axis=0)
    # σ²(τ) = Σ a_p τ^p over p = −2 (white phase / quantization), −1 (N²), 0 ((0.664 B)²),
    # 1 (K²/3), 2 (rate ramp), a_p >= 0, least squares weighted by each σ²'s standard
    # deviation √(2/edf) σ²(model) (twice: first with the measured σ², then the fitted)
    powers = np.arange(-2, 3)
    A = tau[:, None] ** powers[None, :]
    y = ad**2
    scale = y.copy()
    for _ in range(3):
        w = np.sqrt(edf / 2.0) / scale
        a, _ = _nnls_cov(A * w[:, None], y * w)
        scale = np.maximum(A @ a, 1e-300)
    w = np.sqrt(edf / 2.0) / scale
    a, cov = _nnls_cov(A * w[:, None], y * w, active_only=True)
    # the σ² points overlap (each average shares data with its neighbours): scale the
    # covariance by the reduced χ² of the fit when above 1 (Birge ratio), and by
    # _OVERLAP_INFLATION²
    dof = max(tau.size - int(np.count_nonzero(a > 0)), 1)
    chi2_red = float(np.sum(((A @ a - y) * w) ** 2)) / dof
    inflate = max(chi2_red, 1.0) * _OVERLAP_INFLATION**2
    free = np.diag(_nnls_cov(A * w[:, None], y * w)[1]) * inflate
    sd = np.sqrt(np.maximum(np.diag(cov * inflate), 0.0))
    return a, sd, free, scale


#: Largest departure (rad/s) of a gyro's rate, averaged over 1 s, from its median over the
#: record for the record to count as at rest (:func:`rest_excursion`): 1 °/s, hundreds of
#: times the Earth's rate and far beyond a MEMS gyro's bias instability, and small against
#: a hand's or a vehicle's motion.
REST_LIMIT: Final[float] = math.radians(1.0)


def rest_excursion(rate: np.ndarray, sample_rate: float, window: float = 1.0) -> float:
    """The largest departure of the rate averaged over ``window`` seconds (non-overlapping
    blocks; the whole record when shorter) from the median of those averages: a sensor at
    rest keeps it at its noise over ``window``; a motion recording (a turn, a hand's
    motion) does not, and its Allan deviation then describes the motion, not the sensor.

    Examples
    --------
    >>> rng = np.random.default_rng(6)
    >>> still = rng.standard_normal(1000) * 0.01             # 100 Hz, 1 s means ~ 1e-3
    >>> turn = still + np.where(np.arange(1000) > 500, 0.5, 0.0)
    >>> rest_excursion(still, 100.0) < REST_LIMIT < rest_excursion(turn, 100.0)
    True
    """
    sample_rate = v.check_positive("sample_rate", sample_rate)
    x = v.check_array("rate", rate, ndim=1, min_size=1)
    k = max(round(window * sample_rate), 1)
    nb = x.size // k
    if nb < 2:
        return 0.0
    means = x[:nb * k].reshape(nb, k).mean(axis=1)
    return float(np.max(np.abs(means - np.median(means))))


def allan_series(rate: np.ndarray, sample_rate: float, *, name: str = "rate",
                 unit: str = "rad/s", taus: str | np.ndarray = "octave",
                 data_type: str = "freq") -> AllanSeries:
    """The overlapping Allan deviation of a plain rate series (any gyro's output, evenly
    sampled at ``sample_rate`` Hz; with ``data_type="phase"`` its integral, an angle or a
    clock's time error, whose rate's deviation is taken), with its 68 % interval (NIST SP
    1065: the edf of white-frequency noise for a rate, of white-phase noise for a phase),
    as an :class:`AllanSeries` for :func:`noise_terms` (``model`` is the measured
    deviation: there is no model curve).  The series of ``python -m gyrolib allan``;
    ``unit`` is the rate's.

    Examples
    --------
    >>> y = np.random.default_rng(2).standard_normal(2**14) * 0.01   # N = 0.001 at 100 Hz
    >>> s = allan_series(y, 100.0)
    >>> f"{noise_terms(s)[0].value:.4f}"
    '0.0010'
    """
    sample_rate = v.check_positive("sample_rate", sample_rate)
    y = v.check_array("rate", rate, ndim=1, min_size=10)
    v.check_choice("data_type", data_type, ("phase", "freq"))
    tau, ad, lo, hi, edf, n = _oadev(y, sample_rate, data_type, taus,
                                     0 if data_type == "freq" else 2)
    return AllanSeries(name=v.check_str("name", name), unit=v.check_str("unit", unit),
                       tau=tau, adev=ad, lo=lo, hi=hi, edf=edf, model=ad, n=n)


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
