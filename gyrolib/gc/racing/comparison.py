"""Paper GC's central claim as a race: its method against the rate-sensor method it replaces
(ref. [3], :mod:`gyrolib.gc.racing.rate_sensor`), under the same disturbances, sensors and accuracy
target.

* :func:`race` → :class:`RaceResult` — the time to σ_c of GC's method (its covariance
  analysis, :func:`gyrolib.gc.covariance_analysis`), of the rate-sensor method with the
  classical estimator (measurement time chosen to just reach σ_c) and with the optimal one,
  counting the turn and the settling, and the σ(t) curves;
* :meth:`RaceResult.conditions` → :class:`RaceConditions` — where "more than 50 % faster"
  holds or fails, in the procedure times and the rate-sensor noise;
* :func:`procedure_for_time` — the procedure time or rate noise at which the rate-sensor
  method takes a given time;
* :func:`race_sweep` → :class:`RaceSweep` — the times over cases of parameter changes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from typing import Final

import numpy as np
from numpy.typing import NDArray

from gyrolib import _validation as v
from gyrolib._repr import compact_repr
from gyrolib.gc.analysis.covariance import covariance_analysis, time_to_sigma
from gyrolib.gc.model.params import GyrocompassParams, check_params
from gyrolib.gc.racing.rate_sensor import (
    RateSensorModel,
    RateSensorProcedure,
    check_procedure,
    rate_sensor_model,
)

__all__ = [
    "PROCEDURE_TARGETS",
    "RaceConditions",
    "RaceResult",
    "RaceSweep",
    "procedure_for_time",
    "race",
    "race_sweep",
]

_PARAM_FIELDS: Final[frozenset[str]] = frozenset(f.name for f in fields(GyrocompassParams))
_PROC_FIELDS: Final[frozenset[str]] = frozenset(f.name for f in fields(RateSensorProcedure))
assert not _PARAM_FIELDS & _PROC_FIELDS, "a sweep case names its fields without a prefix"

#: What :func:`procedure_for_time` can solve for: a procedure field, or ``"overhead"``
#: (``T_rot`` and ``T_settle`` scaled together).
PROCEDURE_TARGETS: Final[tuple[str, ...]] = ("overhead", "T_rot", "T_settle", "rate_noise")

#: Horizons (s) of the covariance analyses of GC's method: the first is the ledger's 100 s;
#: GC's time is searched up to the last (the analysis keeps σ at every 1-ms step).
_GC_HORIZONS: Final[tuple[float, ...]] = (100.0, 1000.0)

_ESTIMATORS: Final[tuple[str, ...]] = ("classical", "optimal")


# GC's method ---------------------------------------------------------------------------------
def _log_indices(n: int, m: int = 1500) -> np.ndarray:
    """About ``m`` indices of ``0 … n``, log-spaced (the start of a σ curve matters most)."""
    return np.unique(np.concatenate(([0], np.geomspace(1, n, m).astype(np.int64), [n])))


def _gc_part(p: GyrocompassParams, level: float, t_max: float) -> tuple[float, np.ndarray,
                                                                         np.ndarray]:
    """GC's time to ``level`` and its σ curve: the covariance analysis over 100 s (the
    ledger's), a longer one only when σ has not crossed (``nan``: not within
    ``min(t_max, 1000 s)``)."""
    horizons = sorted({min(h, t_max) for h in _GC_HORIZONS})
    for horizon in horizons:
        n = max(1, round(horizon / p.dt))
        t_end = horizon if abs(n * p.dt - horizon) < 1e-12 * horizon else n * p.dt
        cov = covariance_analysis(p, t_end, store_every=n)
        t_c = time_to_sigma(cov, "omega_gc", level)
        if np.isfinite(t_c):
            break
    idx = _log_indices(cov.t.size - 1)
    return float(t_c), cov.t[idx].copy(), cov.std("omega_gc")[idx].copy()


# The rate-sensor method ----------------------------------------------------------------------
def _split(proc: RateSensorProcedure, n: int) -> tuple[int, int]:
    n1 = min(max(1, round(proc.split * n)), n - 1)
    return n1, n - n1


def _classical_samples(model: RateSensorModel) -> tuple[int, int] | None:
    """The fewest samples ``n1 + n2`` (split by ``procedure.split``) for which the classical
    σ is at most σ_c; ``None`` if not within ``t_max``."""
    proc = model.procedure
    n_max = math.floor((proc.t_max - proc.overhead) / proc.sample_dt + 1e-9)
    if n_max < 2:
        return None

    def ok(n: int) -> bool:
        return model.classical_sigma_samples(*_split(proc, n)) <= proc.sigma_c

    lo, hi = 1, 2
    while not ok(hi):
        if hi >= n_max:
            return None
        lo, hi = hi, min(2 * hi, n_max)
    while hi - lo > 1:   # σ falls with the measurement time: the first n that reaches σ_c
        mid = (lo + hi) // 2
        lo, hi = (lo, mid) if ok(mid) else (mid, hi)
    return _split(proc, hi)


@dataclass(frozen=True)
class _RatePart:
    t_c: float
    t_c_optimal: float
    n1: int
    n2: int


def _rate_part(model: RateSensorModel) -> _RatePart:
    proc = model.procedure
    found = _classical_samples(model)
    if found is None:
        # the classical estimator never gets there: the optimal one on the same policy over
        # the longest procedure
        n = math.floor((proc.t_max - proc.overhead) / proc.sample_dt + 1e-9)
        if n < 2:
            return _RatePart(math.nan, math.nan, 0, 0)
        n1, n2 = _split(proc, n)
        run = model.optimal_run_samples(n1, n2)
        return _RatePart(math.nan, run.time_to(proc.sigma_c), 0, 0)
    n1, n2 = found
    t_c = (n1 + n2) * proc.sample_dt + proc.overhead
    run = model.optimal_run_samples(n1, n2)
    return _RatePart(t_c, run.time_to(proc.sigma_c), n1, n2)


def _rate_time(p: GyrocompassParams, proc: RateSensorProcedure, estimator: str) -> float:
    """The rate-sensor method's time to σ_c with one estimator (``inf``: not reached)."""
    model = rate_sensor_model(p, proc)
    if estimator == "classical":
        found = _classical_samples(model)
        return math.inf if found is None else sum(found) * proc.sample_dt + proc.overhead
    t = _rate_part(model).t_c_optimal
    return math.inf if math.isnan(t) else t


# Result ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class RaceConditions:
    """Where "GC more than ``percent`` % faster than the rate-sensor method" holds
    (:meth:`RaceResult.conditions`), each condition with the other quantities at the race's
    values.

    ``t_needed`` (s) is the time the rate-sensor method must exceed,
    ``t_c_gc / (1 − percent/100)``.  For each estimator (``classical``, ``optimal``):
    ``holds_*`` at the race's procedure; ``overhead_*`` the smallest ``T_rot + T_settle`` (s,
    both scaled together) for which it holds; ``rate_noise_*`` the smallest rate-noise
    intensity (rad²/s) for which it holds (0: at any value; ``inf``: at none).
    """

    percent: float
    t_c_gc: float
    t_needed: float
    overhead: float
    rate_noise: float
    holds_classical: bool
    holds_optimal: bool
    overhead_classical: float
    overhead_optimal: float
    rate_noise_classical: float
    rate_noise_optimal: float

    def text(self) -> str:
        """The conditions in one sentence (SI units).

        Examples
        --------
        >>> from gyrolib import gc
        >>> print(gc.race().conditions().text())   # doctest: +ELLIPSIS
        more than 50 % faster needs the rate-sensor method to take over 48.1 s; ...
        """
        def side(name: str, holds: bool, o: float, q: float) -> str:
            verdict = "holds" if holds else "fails"
            return (f"against the {name} estimator it {verdict} at T_rot + T_settle = "
                    f"{self.overhead:g} s and rate noise {self.rate_noise:.3g} rad^2/s; it "
                    f"holds for T_rot + T_settle > {o:.1f} s at that noise, or for rate noise "
                    f"> {q:.3g} rad^2/s at those times")
        if not np.isfinite(self.t_needed):
            return (f"GC's method does not reach sigma_c within its horizon, so it is not more "
                    f"than {self.percent:g} % faster at any procedure time or rate noise")
        return (f"more than {self.percent:g} % faster needs the rate-sensor method to take over "
                f"{self.t_needed:.1f} s; "
                + side("classical", self.holds_classical, self.overhead_classical,
                       self.rate_noise_classical) + "; "
                + side("optimal", self.holds_optimal, self.overhead_optimal,
                       self.rate_noise_optimal))


@compact_repr
@dataclass(frozen=True)
class RaceResult:
    """The race (:func:`race`): times to σ_c (s of elapsed time) and σ of ω_gc against time.

    ``t_c_gc`` — GC's method (covariance analysis of paper GC's filter);
    ``t_c_rate_sensor`` — the rate-sensor method with the classical estimator, the
    measurement time ``t1 + t2`` chosen to just reach σ_c, the turn and settling counted;
    ``t_c_rate_sensor_optimal`` — the optimal estimator on the same procedure, position 2 ended
    as soon as its σ reaches σ_c (``nan``: not within ``procedure.t_max``).  Curves (SI):
    ``t_gc``, ``sigma_gc``; ``t_classical``, ``sigma_classical`` (position 2 only: the
    half-sum needs both positions); ``t_optimal``, ``sigma_optimal``; ``phases`` the
    procedure's ``(name, start, end)``.
    """

    params: GyrocompassParams
    procedure: RateSensorProcedure
    t_c_gc: float
    t_c_rate_sensor: float
    t_c_rate_sensor_optimal: float
    t1: float
    t2: float
    t_gc: NDArray[np.float64]
    sigma_gc: NDArray[np.float64]
    t_classical: NDArray[np.float64]
    sigma_classical: NDArray[np.float64]
    t_optimal: NDArray[np.float64]
    sigma_optimal: NDArray[np.float64]
    phases: tuple[tuple[str, float, float], ...]

    def __post_init__(self) -> None:
        check_params(self.params)
        check_procedure(self.procedure)
        for a, b in (("t_gc", "sigma_gc"), ("t_classical", "sigma_classical"),
                     ("t_optimal", "sigma_optimal")):
            n = v.check_ndarray(a, getattr(self, a), ndim=1).size
            v.check_ndarray(b, getattr(self, b), shape=(n,))

    @property
    def faster_percent(self) -> float:
        """How much faster GC's method is than the rate-sensor method with the classical
        estimator: ``100 (1 − t_c_gc / t_c_rate_sensor)`` (%).

        Examples
        --------
        >>> from gyrolib import gc
        >>> f"{gc.race().faster_percent:.0f} %"
        '29 %'
        """
        return _percent(self.t_c_gc, self.t_c_rate_sensor)

    @property
    def faster_percent_optimal(self) -> float:
        """The same against the optimal estimator (%).

        Examples
        --------
        >>> from gyrolib import gc
        >>> f"{gc.race().faster_percent_optimal:.0f} %"
        '28 %'
        """
        return _percent(self.t_c_gc, self.t_c_rate_sensor_optimal)

    def conditions(self, percent: float = 50.0) -> RaceConditions:
        """Where GC's method is more than ``percent`` % faster than the rate-sensor method:
        the smallest procedure overhead and the smallest rate noise at which it is, each with
        the other at the race's value.

        Parameters
        ----------
        percent : float, default 50.0
            The claimed saving (%), in (0, 100).

        Returns
        -------
        RaceConditions

        Examples
        --------
        >>> from gyrolib import gc
        >>> c = gc.race().conditions()
        >>> c.holds_classical, f"{c.overhead_classical:.0f} s"
        (False, '33 s')
        """
        percent = v.check_in_range("percent", percent, 0.0, 100.0, low_open=True,
                                   high_open=True)
        need = self.t_c_gc / (1.0 - percent / 100.0)
        if not np.isfinite(need):  # GC does not reach σ_c within its horizon: never faster
            return RaceConditions(
                percent=percent, t_c_gc=self.t_c_gc, t_needed=math.inf,
                overhead=self.procedure.overhead, rate_noise=self.procedure.rate_noise,
                holds_classical=False, holds_optimal=False, overhead_classical=math.inf,
                overhead_optimal=math.inf, rate_noise_classical=math.inf,
                rate_noise_optimal=math.inf)
        out: dict[str, float | bool] = {}
        for est, t in (("classical", self.t_c_rate_sensor),
                       ("optimal", self.t_c_rate_sensor_optimal)):
            out[f"holds_{est}"] = bool(not np.isfinite(t) or t > need)
            out[f"overhead_{est}"] = _boundary(self.params, self.procedure, "overhead", need,
                                               est)
            out[f"rate_noise_{est}"] = _boundary(self.params, self.procedure, "rate_noise",
                                                 need, est)
        return RaceConditions(percent=percent, t_c_gc=self.t_c_gc, t_needed=need,
                              overhead=self.procedure.overhead,
                              rate_noise=self.procedure.rate_noise, **out)

    def evidence(self) -> str:
        """One sentence for the reproduction ledger: the race's times and savings.

        Examples
        --------
        >>> from gyrolib import gc
        >>> print(gc.race().evidence())   # doctest: +ELLIPSIS
        race (gc.race) under the same disturbances: t_c = 24.1 s (GC) against 34.0 s ...
        """
        proc = self.procedure

        def t(x: float) -> str:
            return f"{x:.1f} s" if np.isfinite(x) else "not reached"

        def pct(x: float) -> str:
            return f"{x:.0f} %" if np.isfinite(x) else "undefined (GC does not reach sigma_c)"
        return (f"race (gc.race) under the same disturbances: t_c = {t(self.t_c_gc)} (GC) "
                f"against {t(self.t_c_rate_sensor)} (rate-sensor method, classical "
                f"half-sum) and {t(self.t_c_rate_sensor_optimal)} (same measurements, "
                f"optimal Kalman), turn {proc.T_rot:g} s and settling {proc.T_settle:g} s "
                f"included: GC faster by {pct(self.faster_percent)} and "
                f"{pct(self.faster_percent_optimal)}")


def _percent(t_gc: float, t_other: float) -> float:
    if not np.isfinite(t_other):
        return 100.0 if np.isfinite(t_gc) else math.nan
    return 100.0 * (1.0 - t_gc / t_other)


def _with(proc: RateSensorProcedure, field: str, value: float) -> RateSensorProcedure:
    if field == "overhead":
        o = proc.overhead
        if o > 0.0:
            return replace(proc, T_rot=proc.T_rot * value / o, T_settle=proc.T_settle * value / o)
        return replace(proc, T_rot=0.5 * value, T_settle=0.5 * value)
    return replace(proc, **{field: value})


def _boundary(p: GyrocompassParams, proc: RateSensorProcedure, field: str, need: float,
              estimator: str) -> float:
    """Smallest value of ``field`` for which the rate-sensor time exceeds ``need`` (0 if it
    does at the field's lower end; ``inf`` if never)."""
    value = procedure_for_time(p, proc, field, need, estimator=estimator)
    return float(value)


def procedure_for_time(params: GyrocompassParams | None, procedure: RateSensorProcedure | None,
                       field: str, target: float, *, estimator: str = "classical",
                       rtol: float = 1e-3) -> float:
    """The value of one procedure quantity at which the rate-sensor method takes ``target``
    seconds to reach σ_c, the others held.

    The rate-sensor time grows with each of these quantities; the value is found by
    bisection (on a log scale for ``rate_noise``).

    Parameters
    ----------
    params : GyrocompassParams or None
        Paper GC's parameters (``None``: the paper's).
    procedure : RateSensorProcedure or None
        The procedure (``None``: the book's).
    field : {"overhead", "T_rot", "T_settle", "rate_noise"}
        What to solve for; ``"overhead"`` scales ``T_rot`` and ``T_settle`` together.
    target : float
        Time (s) of the whole procedure, > 0.
    estimator : {"classical", "optimal"}
        Which estimator's time.
    rtol : float
        Relative tolerance of the value (> 0).

    Returns
    -------
    float
        The value (s, or rad²/s for ``rate_noise``); 0 if the method takes longer than
        ``target`` even at 0 (for ``rate_noise``: at 10⁻⁶ of the procedure's); ``inf`` if it
        takes less at any value up to ``target`` (for ``rate_noise``: 10⁶ times the
        procedure's).

    Examples
    --------
    >>> from gyrolib import gc
    >>> f"{gc.procedure_for_time(None, None, 'overhead', 60.0):.1f} s"
    '44.8 s'
    """
    p = GyrocompassParams() if params is None else check_params(params)
    proc = RateSensorProcedure() if procedure is None else check_procedure(procedure)
    v.check_choice("field", field, PROCEDURE_TARGETS)
    v.check_choice("estimator", estimator, _ESTIMATORS)
    target = v.check_positive("target", target)
    rtol = v.check_in_range("rtol", rtol, 0.0, 0.5, low_open=True)

    def too_slow(x: float) -> bool:
        return _rate_time(p, _with(proc, field, x), estimator) > target

    if field == "rate_noise":
        # bracket by decades from the procedure's value, then bisect on a log scale
        q0 = proc.rate_noise
        if too_slow(q0):
            lo, hi = q0, q0
            while too_slow(lo):
                if lo < q0 * 1e-6:
                    return 0.0
                lo, hi = lo / 10.0, lo
        else:
            lo, hi = q0, q0
            while not too_slow(hi):
                if hi > q0 * 1e6:
                    return math.inf
                lo, hi = hi, hi * 10.0
        while hi / lo > 1.0 + rtol:
            mid = math.sqrt(lo * hi)
            lo, hi = (lo, mid) if too_slow(mid) else (mid, hi)
        return math.sqrt(lo * hi)
    if too_slow(0.0):
        return 0.0
    # the whole procedure lasts longer than its turn and settling: target bounds the value
    lo, hi = 0.0, min(target, proc.t_max)
    if not too_slow(hi):
        return math.inf
    while hi - lo > rtol * max(hi, 1.0):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if too_slow(mid) else (mid, hi)
    return 0.5 * (lo + hi)


def _race(p: GyrocompassParams, proc: RateSensorProcedure,
          gc_part: tuple[float, np.ndarray, np.ndarray]) -> RaceResult:
    model = rate_sensor_model(p, proc)
    part = _rate_part(model)
    if part.n1:
        # the curves run half as long again as the classical procedure's position 2
        n2_plot = part.n2 + max(1, part.n2 // 2)
        t_cl, s_cl = model.classical_curve(part.n1 * proc.sample_dt, n2_plot * proc.sample_dt)
        run = model.optimal_run_samples(part.n1, n2_plot)
        t1, t2 = part.n1 * proc.sample_dt, part.n2 * proc.sample_dt
    else:
        t_cl = s_cl = np.zeros(0)
        n = math.floor((proc.t_max - proc.overhead) / proc.sample_dt + 1e-9)
        n1, n2 = _split(proc, max(n, 2))
        run = model.optimal_run_samples(n1, n2)
        t1 = t2 = math.nan
    phases = tuple((name, a, min(b, part.t_c) if name == "position 2" and part.n1 else b)
                   for name, a, b in run.phases)
    return RaceResult(params=p, procedure=proc, t_c_gc=gc_part[0], t_c_rate_sensor=part.t_c,
                      t_c_rate_sensor_optimal=part.t_c_optimal, t1=t1, t2=t2,
                      t_gc=gc_part[1], sigma_gc=gc_part[2], t_classical=t_cl,
                      sigma_classical=s_cl, t_optimal=run.t, sigma_optimal=run.sigma,
                      phases=phases)


def race(params: GyrocompassParams | None = None,
         procedure: RateSensorProcedure | None = None) -> RaceResult:
    """Paper GC's method against the rate-sensor method it replaces (its ref. [3]), under the
    same disturbances, sensors and accuracy target σ_c.

    GC's time is the first time its filter's σ of ω_gc falls to σ_c (the covariance analysis
    of :func:`gyrolib.gc.covariance_analysis` over 100 s, the one the reproduction ledger
    uses; longer only if σ_c is not reached).  The rate-sensor method's (see
    :mod:`gyrolib.gc.racing.rate_sensor`) is ``T1 + T_rot + T_settle + T2`` with the classical
    estimator (half-sum of the position means corrected by the inclinometer means), the
    measurement time ``T1 + T2`` (split by ``procedure.split``) the shortest that reaches σ_c;
    and with the optimal (Kalman) estimator on the same procedure, position 2 ended as soon as
    its σ reaches σ_c.

    Parameters
    ----------
    params : GyrocompassParams, optional
        Paper GC's parameters, shared by both methods (default: the paper's).
    procedure : RateSensorProcedure, optional
        The rate-sensor procedure and σ_c (default: the book's).

    Returns
    -------
    RaceResult

    Examples
    --------
    >>> from gyrolib import gc
    >>> r = gc.race()
    >>> [f"{t:.1f} s" for t in (r.t_c_gc, r.t_c_rate_sensor, r.t_c_rate_sensor_optimal)]
    ['24.1 s', '34.0 s', '33.3 s']
    """
    p = GyrocompassParams() if params is None else check_params(params)
    proc = RateSensorProcedure() if procedure is None else check_procedure(procedure)
    return _race(p, proc, _gc_part(p, proc.sigma_c, proc.t_max))


# Sweeps ---------------------------------------------------------------------------------------
@compact_repr
@dataclass(frozen=True)
class RaceSweep:
    """Times to σ_c (s) for each case of changes (:func:`race_sweep`): ``t_c_gc``,
    ``t_c_rate_sensor``, ``t_c_rate_sensor_optimal`` in the order of ``cases``."""

    params: GyrocompassParams
    procedure: RateSensorProcedure
    cases: tuple[dict[str, object], ...]
    t_c_gc: NDArray[np.float64]
    t_c_rate_sensor: NDArray[np.float64]
    t_c_rate_sensor_optimal: NDArray[np.float64]

    def __post_init__(self) -> None:
        check_params(self.params)
        check_procedure(self.procedure)
        if not isinstance(self.cases, tuple):
            raise TypeError("cases must be a tuple of {field: value} dicts")
        for name in ("t_c_gc", "t_c_rate_sensor", "t_c_rate_sensor_optimal"):
            arr = getattr(self, name)
            if not isinstance(arr, np.ndarray) or arr.shape != (len(self.cases),):
                raise ValueError(f"{name} must be an array with one time per case "
                                 f"({len(self.cases)})")

    def faster_percent(self, estimator: str = "classical") -> NDArray[np.float64]:
        """``100 (1 − t_c_gc / t_rate_sensor)`` (%) per case.

        Examples
        --------
        >>> from gyrolib import gc
        >>> sw = gc.race_sweep(cases=[{"T_settle": 10.0}, {"T_settle": 60.0}])
        >>> [f"{x:.0f}" for x in sw.faster_percent()]
        ['29', '72']
        """
        v.check_choice("estimator", estimator, _ESTIMATORS)
        t = self.t_c_rate_sensor if estimator == "classical" else self.t_c_rate_sensor_optimal
        return np.array([_percent(a, b) for a, b in zip(self.t_c_gc, t)])


def race_sweep(params: GyrocompassParams | None = None,
               procedure: RateSensorProcedure | None = None, *,
               cases: object) -> RaceSweep:
    """The race for each case of changes to the parameters and the procedure.

    Parameters
    ----------
    params : GyrocompassParams, optional
        The baseline of paper GC's parameters.
    procedure : RateSensorProcedure, optional
        The baseline procedure.
    cases : sequence of dict
        Each a ``{field: value}`` mapping; a field of :class:`GyrocompassParams` changes
        both methods' model, one of :class:`RateSensorProcedure` the procedure (the names
        are disjoint).  GC's time is computed once per distinct set of parameters.

    Returns
    -------
    RaceSweep

    Examples
    --------
    >>> from gyrolib import gc
    >>> sw = gc.race_sweep(cases=[{}, {"rate_noise": 6e-15}])
    >>> [f"{t:.1f}" for t in sw.t_c_rate_sensor]
    ['34.0', '101.6']
    """
    p = GyrocompassParams() if params is None else check_params(params)
    proc = RateSensorProcedure() if procedure is None else check_procedure(procedure)
    if isinstance(cases, dict) or not all(isinstance(c, dict) for c in cases):
        raise TypeError("cases must be a sequence of {field: value} dicts")
    cases = tuple(dict(c) for c in cases)
    for c in cases:
        for name in c:
            if name not in _PARAM_FIELDS and name not in _PROC_FIELDS:
                raise ValueError("cases must name GyrocompassParams or RateSensorProcedure "
                                 f"fields; got {name!r}")
    cache: dict[tuple[GyrocompassParams, float, float], float] = {}
    out = np.empty((len(cases), 3))
    for i, c in enumerate(cases):
        q = replace(p, **{k: x for k, x in c.items() if k in _PARAM_FIELDS})
        pr = replace(proc, **{k: x for k, x in c.items() if k in _PROC_FIELDS})
        key = (q, pr.sigma_c, pr.t_max)
        if key not in cache:
            cache[key] = _gc_part(q, pr.sigma_c, pr.t_max)[0]
        part = _rate_part(rate_sensor_model(q, pr))
        out[i] = cache[key], part.t_c, part.t_c_optimal
    return RaceSweep(params=p, procedure=proc, cases=cases, t_c_gc=out[:, 0],
                     t_c_rate_sensor=out[:, 1], t_c_rate_sensor_optimal=out[:, 2])
