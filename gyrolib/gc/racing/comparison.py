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

import functools
import math
from dataclasses import dataclass, fields, replace
from typing import Final

import numpy as np
from numpy.typing import NDArray

from gyrolib import _validation as v
from gyrolib._repr import compact_repr
from gyrolib.gc.analysis.covariance import covariance_analysis, time_to_sigma
from gyrolib.gc.analysis.speed_claim import time_to_level
from gyrolib.gc.model import inputs as model_inputs
from gyrolib.gc.model.params import GyrocompassParams, check_params
from gyrolib.gc.racing import inputs as racing_inputs
from gyrolib.gc.racing.rate_sensor import (
    RateSensorModel,
    RateSensorProcedure,
    check_procedure,
    rate_sensor_model,
)

__all__ = [
    "MARGIN_MONOTONE_ROWS",
    "PROCEDURE_TARGETS",
    "RACE_RANGES",
    "RaceConditions",
    "RaceResult",
    "RaceSweep",
    "procedure_for_time",
    "race",
    "race_margin",
    "race_sweep",
]

_PARAM_FIELDS: Final[frozenset[str]] = frozenset(f.name for f in fields(GyrocompassParams))
_PROC_FIELDS: Final[frozenset[str]] = frozenset(f.name for f in fields(RateSensorProcedure))
assert not _PARAM_FIELDS & _PROC_FIELDS, "a sweep case names its fields without a prefix"

#: What :func:`procedure_for_time` can solve for: a procedure field, or ``"overhead"``
#: (``T_rot`` and ``T_settle`` scaled together).
PROCEDURE_TARGETS: Final[tuple[str, ...]] = ("overhead", "T_rot", "T_settle", "rate_noise",
                                             "loop_bandwidth")

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
    ``min(t_max, 1000 s)``).  The drift the scale uncertainty reads as,
    ``params.scale_drift_sigma``, adds in quadrature to the filter's σ (0 by default, the
    paper's model): the filter must then reach ``sqrt(level² − scale_drift_sigma²)``."""
    s_scale = p.scale_drift_sigma
    # the scale enters here in quadrature (first order, unobservable), so the filter is run
    # without the model's scale state (gyrolib.gc.model.instrument), which would count it
    # twice; the other instrument constants ON in p are carried by the covariance analysis
    p_filter = replace(p, sigma_hf_scale=0.0) if p.sigma_hf_scale else p
    horizons = sorted({min(h, t_max) for h in _GC_HORIZONS})
    for horizon in horizons:
        n = max(1, round(horizon / p.dt))
        t_end = horizon if abs(n * p.dt - horizon) < 1e-12 * horizon else n * p.dt
        cov = covariance_analysis(p_filter, t_end, store_every=n)
        if s_scale >= level:
            t_c = math.nan
        else:
            t_c = time_to_sigma(cov, "omega_gc", math.sqrt(level**2 - s_scale**2))
        if np.isfinite(t_c):
            break
    idx = _log_indices(cov.t.size - 1)
    sigma = np.hypot(cov.std("omega_gc")[idx], s_scale)
    return float(t_c), cov.t[idx].copy(), sigma


# The rate-sensor method ----------------------------------------------------------------------
def _split(proc: RateSensorProcedure, n: int) -> tuple[int, int]:
    n1 = min(max(1, round(proc.split * n)), n - 1)
    return n1, n - n1


class _Reached(Exception):
    """A search stopped early: a probed value already answers its question."""


def _best_split(model: RateSensorModel, n: int) -> tuple[float, int]:
    """The smallest classical σ over the splits ``n1 + n2 = n`` (or the procedure's fixed
    split) and its ``n1``: a search over whole samples (σ is unimodal in ``n1``)."""
    proc = model.procedure
    if proc.split is not None:
        n1 = _split(proc, n)[0]
        return model.classical_sigma_samples(n1, n - n1), n1
    cache: dict[int, float] = {}

    def s(n1: int) -> float:
        if n1 not in cache:
            cache[n1] = model.classical_sigma_samples(n1, n - n1)
        return cache[n1]
    lo, hi = 1, n - 1
    while hi - lo > 2:   # ternary search on integers
        m1, m2 = lo + (hi - lo) // 3, hi - (hi - lo) // 3
        if s(m1) <= s(m2):
            hi = m2
        else:
            lo = m1
    best = min(range(lo, hi + 1), key=s)
    return s(best), best


def _fibonacci_min(f, lo: int, hi: int) -> float:
    """The smallest value of ``f`` over the integers ``lo..hi``, ``f`` unimodal: a Fibonacci
    search (each step keeps one of its two points, about 1.44 log₂ of the range evaluations
    in all, against 3.4 log₂ for the ternary search of :func:`_best_split`).  It returns the
    same minimum as any exact search of a unimodal function (the argument of a tie aside)."""
    fib = [1, 1]
    while fib[-1] < hi - lo + 2:
        fib.append(fib[-1] + fib[-2])
    k = len(fib) - 1
    a = lo - 1   # the minimum lies in the open interval (a, a + fib[k])

    def g(x: int) -> float:
        return f(x) if lo <= x <= hi else math.inf
    x1, x2 = a + fib[k - 2], a + fib[k - 1]
    f1, f2 = g(x1), g(x2)
    while k > 3:
        k -= 1
        if f1 <= f2:   # the minimum is in (a, x2)
            x2, f2 = x1, f1
            x1 = a + fib[k - 2]
            f1 = g(x1)
        else:          # in (x1, a + fib[k + 1])
            a, x1, f1 = x1, x2, f2
            x2 = a + fib[k - 1]
            f2 = g(x2)
    known = {x1: f1, x2: f2}
    return min(known[x] if x in known else g(x) for x in range(a + 1, a + fib[k]))


def _split_reaches(model: RateSensorModel, n: int) -> bool:
    """Whether the best split of ``n`` samples reaches σ_c (``_best_split(model, n)[0] <=
    σ_c``, the same answer) with less work: a Fibonacci search for the smallest
    σ, stopped at the first split that reaches σ_c.  Only the answer is used: the split of
    the total found keeps :func:`_best_split`'s own search, so that a tie at the level of
    rounding is broken as before."""
    proc = model.procedure
    if proc.split is not None:
        return _best_split(model, n)[0] <= proc.sigma_c

    def s(n1: int) -> float:
        value = model.classical_sigma_samples(n1, n - n1)
        if value <= proc.sigma_c:
            raise _Reached
        return value
    try:
        return _fibonacci_min(s, 1, n - 1) <= proc.sigma_c
    except _Reached:
        return True


def _classical_samples(model: RateSensorModel) -> tuple[int, int] | None:
    """The fewest samples ``n1 + n2`` (each total split optimally, or by
    ``procedure.split``) for which the classical σ is at most σ_c; ``None`` if not within
    ``t_max``."""
    proc = model.procedure
    n_max = math.floor((proc.t_max - proc.overhead) / proc.sample_dt + 1e-9)
    if n_max < 2:
        return None

    def ok(n: int) -> bool:
        return _split_reaches(model, n)

    lo, hi = 1, 2
    while not ok(hi):
        if hi >= n_max:
            return None
        lo, hi = hi, min(2 * hi, n_max)
    while hi - lo > 1:   # σ falls with the measurement time: the first n that reaches σ_c
        mid = (lo + hi) // 2
        lo, hi = (lo, mid) if ok(mid) else (mid, hi)
    n1 = _best_split(model, hi)[1]
    return n1, hi - n1


def _optimal_time(model: RateSensorModel, n1: int, n2_max: int,
                  beat: float = math.inf) -> float:
    """The optimal estimator's time to σ_c with position 1 lasting ``n1`` samples and
    position 2 ended as soon as σ reaches σ_c (``inf``: not within ``n2_max`` samples, or
    later than ``beat``, a time to beat: that window is then not finished)."""
    t = model.optimal_time_to_samples(n1, n2_max, model.procedure.sigma_c,
                                      give_up_after=beat)
    return math.inf if math.isnan(t) else t


def _optimal_windows(model: RateSensorModel, n1_hint: int, n2_max: int,
                     enough: float = -math.inf) -> tuple[float, int]:
    """The optimal estimator's shortest time to σ_c over the length of position 1 (or the
    classical's ``n1_hint`` when the procedure fixes the split), and that length (samples):
    a coarse grid around the hint, then halving steps about the best.

    With ``enough``, the search raises :class:`_Reached` as soon as a window's time is at
    most ``enough`` (the shortest time is then at most ``enough`` too).

    A window is given up (``inf``) only when one of its samples later than the shortest
    time so far is above σ_c (``give_up_after`` of
    :meth:`~gyrolib.gc.racing.rate_sensor.RateSensorModel.optimal_time_to_samples`): its
    time is then strictly later than that of the best window so far, which takes part in
    every later comparison, so it loses each one as ``inf`` does, and the search returns
    the same time and length as without giving up."""
    if model.procedure.split is not None:
        return _optimal_time(model, n1_hint, n2_max), n1_hint
    cache: dict[int, float] = {}
    shortest = [math.inf]   # the shortest time so far: a window that cannot beat it is given up

    def t(n1: int) -> float:
        n1 = max(1, n1)
        if n1 not in cache:
            # a window given up is strictly later than the best so far (its value here,
            # inf, only has to lose every comparison, as its true time would: the result
            # is the same)
            cache[n1] = _optimal_time(model, n1, n2_max, shortest[0])
            shortest[0] = min(shortest[0], cache[n1])
            if shortest[0] <= enough:
                raise _Reached
        return cache[n1]
    grid = sorted({max(1, round(f * n1_hint)) for f in np.linspace(0.1, 2.0, 20)})
    best = min(grid, key=t)
    step = max(1, round(0.1 * n1_hint))
    while step >= 1:
        best = min((best - step, best, best + step), key=t)
        best = max(1, best)
        step //= 2
    return t(best), best


@dataclass(frozen=True)
class _RatePart:
    t_c: float
    t_c_optimal: float
    n1: int
    n2: int
    n1_optimal: int


def _rate_part(model: RateSensorModel) -> _RatePart:
    proc = model.procedure
    found = _classical_samples(model)
    n_all = math.floor((proc.t_max - proc.overhead) / proc.sample_dt + 1e-9)
    if found is None:
        # the classical estimator never gets there: the optimal one over the longest procedure
        if n_all < 2:
            return _RatePart(math.nan, math.nan, 0, 0, 0)
        n1 = n_all // 2 if proc.split is None else _split(proc, n_all)[0]
        t_opt, n1_opt = _optimal_windows(model, n1, n_all - n1)
        return _RatePart(math.nan, t_opt if np.isfinite(t_opt) else math.nan, 0, 0, n1_opt)
    n1, n2 = found
    t_c = (n1 + n2) * proc.sample_dt + proc.overhead
    t_opt, n1_opt = _optimal_windows(model, n1, max(n2, 1) + n1)
    return _RatePart(t_c, t_opt if np.isfinite(t_opt) else math.nan, n1, n2, n1_opt)


@functools.lru_cache(maxsize=1024)
def _rate_time(p: GyrocompassParams, proc: RateSensorProcedure, estimator: str) -> float:
    """The rate-sensor method's time to σ_c with one estimator (``inf``: not reached), kept
    per inputs (frozen dataclasses; a float result): a race's conditions, its claim map and
    the command line ask for the same points again (work done twice)."""
    if estimator == "classical":
        found = _classical_samples(rate_sensor_model(p, proc))
        return math.inf if found is None else sum(found) * proc.sample_dt + proc.overhead
    t = _rate_part_at(p, proc).t_c_optimal
    return math.inf if math.isnan(t) else t


def _classical_exceeds_on(model: RateSensorModel, target: float) -> bool:
    """Whether the classical estimator's time to σ_c (:func:`_rate_time`) exceeds ``target``:
    the same answer (σ falls with the total, as :func:`_classical_samples`' bisection takes
    it) from one question, whether the longest total within ``target`` (and ``t_max``)
    reaches σ_c (a bisection asks only this)."""
    proc = model.procedure
    n_cap = math.floor((min(target, proc.t_max) - proc.overhead) / proc.sample_dt + 1e-9)
    while n_cap >= 2 and n_cap * proc.sample_dt + proc.overhead > target:
        n_cap -= 1   # the time as _rate_time sums it, within the target
    return not (n_cap >= 2 and _split_reaches(model, n_cap))


def _optimal_exceeds(p: GyrocompassParams, proc: RateSensorProcedure, target: float) -> bool:
    """Whether the optimal estimator's time to σ_c (:func:`_rate_time`) exceeds ``target``,
    with the same answer and less work (a bisection asks only this):

    * the classical estimator's best split of the longest total within ``target`` already
      reaches σ_c: the optimal one, which the search also tries on the classical's windows
      and whose σ is never larger there, is within ``target`` too;
    * otherwise the optimal search stops at its first window within ``target``."""
    model = rate_sensor_model(p, proc)
    if not _classical_exceeds_on(model, target):
        return False
    found = _classical_samples(model)
    n_all = math.floor((proc.t_max - proc.overhead) / proc.sample_dt + 1e-9)
    if found is None:
        if n_all < 2:
            return True   # not reached: _rate_part's nan, an infinite time
        n1 = n_all // 2 if proc.split is None else _split(proc, n_all)[0]
        n2_max = n_all - n1
    else:
        n1, n2_max = found[0], max(found[1], 1) + found[0]
    try:
        t, _ = _optimal_windows(model, n1, n2_max, enough=target)
    except _Reached:
        return False
    return not (np.isfinite(t) and t <= target)


#: GC's instrument constants, which the rival's model does not read (a test checks its
#: arrays): the rival's results are kept without them, so a map's rows of GC's instrument
#: reuse the rival's times.
_GC_ONLY_FIELDS: Final[tuple[str, ...]] = ("sigma_hf_scale", "sigma_as_offset",
                                           "sigma_incl_bias", "sigma_clock")


def _rival_params(p: GyrocompassParams) -> GyrocompassParams:
    """``p`` as the rival reads it: GC's instrument constants at 0."""
    if any(getattr(p, f) for f in _GC_ONLY_FIELDS):
        return replace(p, **dict.fromkeys(_GC_ONLY_FIELDS, 0.0))
    return p


@functools.lru_cache(maxsize=1024)
def _rate_part_cached(p: GyrocompassParams, proc: RateSensorProcedure) -> _RatePart:
    return _rate_part(rate_sensor_model(p, proc))


def _rate_part_at(p: GyrocompassParams, proc: RateSensorProcedure) -> _RatePart:
    """:func:`_rate_part` of the rate-sensor model at ``(p, proc)``, kept per inputs (a
    frozen result), like :func:`_rate_time`; GC's instrument constants, which the rival
    does not read, are left out of the key (:func:`_rival_params`)."""
    return _rate_part_cached(_rival_params(p), proc)



# Result ---------------------------------------------------------------------------------------
#: The plausible ranges over which :meth:`RaceResult.conditions` judges the race beside its
#: reference point, from the table of inputs (:mod:`gyrolib.inputs`, the one source of
#: ranges): the rebalance loop's bandwidth (rad/s), the procedure's overhead
#: ``T_rot + T_settle`` (s), the torquer's white-noise intensity (rad²/s) and the relative
#: uncertainty κ of GC's scale ``H/f`` (``GyrocompassParams.sigma_hf_scale``).  The rival's
#: time grows with the first three and GC's with κ, so the claim's worst case is the low end
#: of the first three with the high end of κ.  Every other input of the race is mapped by
#: :func:`gyrolib.claim_map.map_claim` (the ledger's item ``gc.faster_percent``).
_RACE_ROWS: Final[tuple[tuple[str, str], ...]] = (
    ("loop_bandwidth", "race.loop_bandwidth"), ("overhead", "race.overhead"),
    ("rate_noise", "race.rate_noise"), ("sigma_hf_scale", "gc.sigma_hf_scale"))


#: Rows of the table of inputs in which :func:`race_margin` is monotone, so that a map of
#: the claim can bracket each with the range's two ends (``monotone`` of
#: :func:`gyrolib.claim_map.map_claim`).  Each enters one method only, as a prior variance
#: or a noise intensity, or as the time the rival spends, and the filter's covariance is
#: monotone in its priors and noises (the Riccati recursion):
#:
#: * GC's alone: κ (the filter must reach ``sqrt(σ_c² − κ² Ω_h²)``) and the instrument
#:   constants' priors (the rival's model reads none of them), so GC's time grows with each
#:   and the margin falls;
#: * the rival's alone: its torquer noise, the turning error, the torque sensor's scale
#:   error, the quantization (noises and priors of its model), the loop bandwidth and the
#:   turn and settling (the rival's time grows with each, as :data:`RACE_RANGES` takes
#:   them), so the margin rises.  For these the rival's time is a search's minimum over
#:   windows, monotone as far as the search finds the best window.
MARGIN_MONOTONE_ROWS: Final[tuple[str, ...]] = (
    "gc.sigma_hf_scale", "gc.sigma_as_offset", "gc.sigma_incl_bias", "gc.sigma_clock",
    "race.rate_noise", "race.sigma_rot", "race.sigma_scale", "race.quantization",
    "race.loop_bandwidth", "race.overhead")


def _race_ranges() -> dict[str, tuple[float, float]]:
    rows = {r.name: r for r in model_inputs.ROWS + racing_inputs.ROWS}
    return {key: rows[name].bounds() for key, name in _RACE_ROWS}


RACE_RANGES: Final[dict[str, tuple[float, float]]] = _race_ranges()

#: Not model inputs, so not in a stored study's key (:func:`gyrolib.store.model_key`):
#: ``RACE_RANGES`` is read from the table of inputs' rows, which the key holds already, and
#: ``MARGIN_MONOTONE_ROWS`` only tells ``race --params`` where a coarse bracket suffices,
#: and ``_GC_ONLY_FIELDS`` which fields the rival's memo leaves out of its key (code, which
#: the stored studies' fingerprint points check, not a model constant).
__key_ignore__ = ("RACE_RANGES", "MARGIN_MONOTONE_ROWS", "_GC_ONLY_FIELDS")


def _fmt_sci(x: float, digits: int = 2) -> str:
    """``1.2·10⁻³`` (plain text with superscripts)."""
    if x == 0.0:
        return "0"
    if not math.isfinite(x):
        return "∞"
    e = math.floor(math.log10(abs(x)))
    m = x / 10.0**e
    if round(m, digits - 1) >= 10.0:
        m, e = m / 10.0, e + 1
    sup = str(e).translate(str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹"))
    return f"{m:.{digits - 1}f}·10{sup}"


@dataclass(frozen=True)
class _ReferencePoint:
    """The reference fields of :class:`RaceConditions` (what its first sentence reads)."""

    percent: float
    t_c_gc: float
    t_needed: float
    loop_bandwidth: float
    overhead: float
    rate_noise: float
    kappa: float
    holds_classical: bool
    holds_optimal: bool


@dataclass(frozen=True)
class RaceConditions(_ReferencePoint):
    """The claim "GC is more than ``percent`` % faster than the rate-sensor method", judged
    at the race's own parameters and procedure (its reference point) and over
    :data:`RACE_RANGES` (:meth:`RaceResult.conditions`).

    ``t_needed`` (s): the time the rival must exceed, ``t_c_gc / (1 − percent/100)``.
    ``holds_classical``, ``holds_optimal``: at the reference point, against each estimator;
    ``holds_at_reference``: against both (the rival is granted its best estimator).
    ``worst_t_gc``, ``worst_t_classical``, ``worst_t_optimal`` (s): the times at the
    ranges' worst corner for the claim; ``holds_over_ranges``: the claim holds there (so,
    the times being monotone in each range, everywhere in them).  One at a time, the
    others at the reference point, against the optimal estimator (never slower than the
    classical): ``loop_bandwidth_min`` (rad/s), ``overhead_min`` (s), ``rate_noise_min``
    (rad²/s), the smallest values for which the claim holds (0: at any value; ``inf``: at
    none up to the search's end); ``kappa_max``, the largest relative uncertainty κ of GC's
    scale ``H/f`` for which it holds (0: at none), and ``kappa_ceiling = σ_c/Ω_h``, above
    which GC never reaches σ_c (the rival's turn cancels this error, so it does not slow the
    rival).
    """

    worst_t_gc: float
    worst_t_classical: float
    worst_t_optimal: float
    holds_over_ranges: bool
    loop_bandwidth_min: float
    overhead_min: float
    rate_noise_min: float
    kappa_max: float
    kappa_ceiling: float

    @property
    def holds_at_reference(self) -> bool:
        """The claim holds at the reference point against both estimators."""
        return bool(self.holds_classical and self.holds_optimal)

    def reference_text(self) -> str:
        """The first sentence of :meth:`text`: the reference point and GC's time there."""
        return self.text().split(" At the worst corner")[0].split(" One quantity")[0]

    def text(self) -> str:
        """Where the claim holds and where it fails, in readable sentences.

        Examples
        --------
        >>> from gyrolib import gc
        >>> print(gc.race().conditions().text())   # doctest: +ELLIPSIS
        At the reference point ... GC reaches σ_c in 24.1 s, so ...
        """
        def val(x: float, fmt: str, unit: str, none: str) -> str:
            if x == 0.0:
                return "at any value"
            if not math.isfinite(x):
                return none
            return f"from {format(x, fmt)} {unit} up"
        ranges = _race_ranges()
        lo = {k: v_[0] for k, v_ in ranges.items()}
        hi = {k: v_[1] for k, v_ in ranges.items()}
        if not np.isfinite(self.t_needed):
            return _reference_sentence(self)
        ref = _reference_sentence(self)
        worst = (f" At the worst corner of the plausible ranges (loop bandwidth "
                 f"{lo['loop_bandwidth']:g} rad/s, turn and settling {lo['overhead']:g} s, "
                 f"torquer noise {_fmt_sci(lo['rate_noise'])} rad²/s, κ = "
                 f"{_fmt_sci(hi['sigma_hf_scale'], 1)}) GC takes "
                 + (f"{self.worst_t_gc:.1f} s" if np.isfinite(self.worst_t_gc)
                    else "forever (it never reaches σ_c)")
                 + f" against {self.worst_t_optimal:.1f} s for the rival's optimal estimator, "
                 f"and the claim {'holds' if self.holds_over_ranges else 'fails'} there.")
        one = (" One quantity at a time, the others at the reference point, the claim holds "
               "against "
               "the optimal estimator for a loop bandwidth "
               + val(self.loop_bandwidth_min, ".3g", "rad/s", "nowhere up to 100 rad/s")
               + ", a turn and settling "
               + val(self.overhead_min, ".1f", "s", "at no duration searched")
               + ", a torquer noise "
               + (val(self.rate_noise_min, "", "", "at no intensity searched")
                  if self.rate_noise_min in (0.0, math.inf)
                  else f"from {_fmt_sci(self.rate_noise_min)} rad²/s up")
               + ", and for GC's scale H/f (and the angle sensor's gain) known to κ below "
               + (f"{_fmt_sci(self.kappa_max)}" if self.kappa_max > 0 else "no value")
               + f"; above κ = σ_c/Ω_h = {_fmt_sci(self.kappa_ceiling)} GC never reaches σ_c, "
               "while the rival's turn cancels this error.")
        return ref + worst + one


def _reference_sentence(c: _ReferencePoint) -> str:
    """The first sentence of :meth:`RaceConditions.text`: the reference point, GC's time
    there and the verdict against each estimator (reads only the reference fields)."""
    if not np.isfinite(c.t_needed):
        return (f"GC's method does not reach σ_c within its horizon, so it is not more than "
                f"{c.percent:g} % faster anywhere.")
    scale = ("GC's scale exact" if c.kappa == 0.0 else
             f"GC's scale known to κ = {_fmt_sci(c.kappa)}")
    return (f"At the reference point (loop bandwidth {c.loop_bandwidth:g} rad/s, turn and "
            f"settling {c.overhead:g} s, torquer noise {_fmt_sci(c.rate_noise)} rad²/s, "
            f"{scale}) GC reaches σ_c in {c.t_c_gc:.1f} s, so the claim needs "
            f"the rival to take more than {c.t_needed:.1f} s; it "
            + ("does with both estimators." if c.holds_classical and c.holds_optimal else
               "does not with " + " and ".join(
                   n for n, h in (("the classical", c.holds_classical),
                                  ("the optimal", c.holds_optimal)) if not h)
               + " estimator."))


@compact_repr
@dataclass(frozen=True)
class RaceResult:
    """The race (:func:`race`): times to σ_c (s of elapsed time) and σ of ω_gc against time.

    ``t_c_gc`` — GC's method (covariance analysis of paper GC's filter);
    ``t_c_rate_sensor`` — the rate-sensor method with the classical estimator, the
    measurement time ``t1 + t2`` chosen to just reach σ_c, the turn and settling counted;
    ``t_c_rate_sensor_optimal`` — the optimal estimator on the same procedure, position 1
    lasting ``t1_optimal`` (chosen to reach σ_c soonest) and position 2 ended as soon as its
    σ reaches σ_c (``nan``: not within ``procedure.t_max``); ``t1``, ``t2`` the classical
    estimator's windows (s, chosen the same way).  GC's σ includes the drift its scale
    uncertainty reads as (``params.scale_drift_sigma``, added in quadrature: no measurement
    time removes it; the rival's turn cancels it).  Curves (SI):
    ``t_gc``, ``sigma_gc``; ``t_classical``, ``sigma_classical`` (position 2 only: the
    half-sum needs both positions); ``t_optimal``, ``sigma_optimal`` (on the optimal
    estimator's windows); ``phases`` the procedure's ``(name, start, end)`` for the
    classical windows.
    """

    params: GyrocompassParams
    procedure: RateSensorProcedure
    t_c_gc: float
    t_c_rate_sensor: float
    t_c_rate_sensor_optimal: float
    t1: float
    t2: float
    t1_optimal: float
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
        '83 %'
        """
        return _percent(self.t_c_gc, self.t_c_rate_sensor)

    @property
    def faster_percent_optimal(self) -> float:
        """The same against the optimal estimator (%).

        Examples
        --------
        >>> from gyrolib import gc
        >>> f"{gc.race().faster_percent_optimal:.0f} %"
        '57 %'
        """
        return _percent(self.t_c_gc, self.t_c_rate_sensor_optimal)

    def kappa_max(self, percent: float = 50.0) -> float:
        """The largest relative error κ of GC's scale ``H/f`` for which GC stays more than
        ``percent`` % faster than the optimal rival, the rest as raced: GC's filter must reach
        sqrt(σ_c² − κ² Ω_h²) before the rival's time × (1 − percent/100) (0 when it cannot;
        read from the race's σ curve: :meth:`conditions` reports it with the rest).

        Examples
        --------
        >>> from gyrolib import gc
        >>> f"{gc.race().kappa_max():.2e}"
        '7.19e-05'
        """
        percent = v.check_in_range("percent", percent, 0.0, 100.0, low_open=True,
                                   high_open=True)
        p, proc = self.params, self.procedure
        keep = 1.0 - percent / 100.0
        t_gc_max = (self.t_c_rate_sensor_optimal if np.isfinite(self.t_c_rate_sensor_optimal)
                    else proc.t_max) * keep
        s_f = np.sqrt(np.clip(self.sigma_gc**2 - p.scale_drift_sigma**2, 0.0, None))
        s_at = float(np.interp(t_gc_max, self.t_gc, s_f))
        return (math.sqrt(proc.sigma_c**2 - s_at**2) / p.Omega_h
                if s_at < proc.sigma_c else 0.0)

    def reference_text(self, percent: float = 50.0) -> str:
        """The first sentence of :meth:`conditions`' text (the reference point, GC's time
        there and the verdict against each estimator), without the worst corner and the
        one-at-a-time searches that :meth:`conditions` also runs.

        Examples
        --------
        >>> from gyrolib import gc
        >>> r = gc.race()
        >>> r.reference_text() == r.conditions().reference_text()
        True
        """
        percent = v.check_in_range("percent", percent, 0.0, 100.0, low_open=True,
                                   high_open=True)
        proc = self.procedure
        need = self.t_c_gc / (1.0 - percent / 100.0)
        held = {est: bool(np.isfinite(need) and (not np.isfinite(t) or t > need))
                for est, t in (("classical", self.t_c_rate_sensor),
                               ("optimal", self.t_c_rate_sensor_optimal))}
        return _reference_sentence(_ReferencePoint(
            percent=percent, t_c_gc=self.t_c_gc,
            t_needed=need if np.isfinite(need) else math.inf,
            loop_bandwidth=proc.loop_bandwidth, overhead=proc.overhead,
            rate_noise=proc.rate_noise, kappa=self.params.sigma_hf_scale,
            holds_classical=held["classical"], holds_optimal=held["optimal"]))

    def conditions(self, percent: float = 50.0) -> RaceConditions:
        """The claim "GC more than ``percent`` % faster" at the race's parameters and
        procedure (the reference point), at the worst corner of :data:`RACE_RANGES`, and the
        values of each range (one at a time) from which it holds.

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
        >>> c.holds_at_reference, c.holds_over_ranges, f"{c.kappa_ceiling:.2e}"
        (True, False, '2.26e-04')
        """
        percent = v.check_in_range("percent", percent, 0.0, 100.0, low_open=True,
                                   high_open=True)
        p, proc = self.params, self.procedure
        keep = 1.0 - percent / 100.0
        need = self.t_c_gc / keep
        ceiling = self.procedure.sigma_c / p.Omega_h
        base = {"percent": percent, "t_c_gc": self.t_c_gc, "loop_bandwidth":
                proc.loop_bandwidth, "overhead": proc.overhead, "rate_noise": proc.rate_noise,
                "kappa": p.sigma_hf_scale, "kappa_ceiling": ceiling}
        if not np.isfinite(need):  # GC does not reach σ_c within its horizon: never faster
            return RaceConditions(
                **base, t_needed=math.inf, holds_classical=False, holds_optimal=False,
                worst_t_gc=math.nan, worst_t_classical=math.nan, worst_t_optimal=math.nan,
                holds_over_ranges=False, loop_bandwidth_min=math.inf, overhead_min=math.inf,
                rate_noise_min=math.inf, kappa_max=0.0)
        held = {est: bool(not np.isfinite(t) or t > need) for est, t in
                (("classical", self.t_c_rate_sensor),
                 ("optimal", self.t_c_rate_sensor_optimal))}
        # the worst corner: the rival at its fastest, GC with the largest scale uncertainty
        r = _race_ranges()
        wp = replace(p, sigma_hf_scale=r["sigma_hf_scale"][1])
        wproc = _with(replace(proc, loop_bandwidth=r["loop_bandwidth"][0],
                              rate_noise=r["rate_noise"][0]), "overhead", r["overhead"][0])
        # GC's time there (nan when the scale's drift alone reaches σ_c)
        w_gc = _gc_time(wp, proc.sigma_c, proc.t_max)
        w_part = _rate_part_at(p, wproc)
        w_opt = w_part.t_c_optimal if np.isfinite(w_part.t_c_optimal) else math.inf
        w_holds = bool(np.isfinite(w_gc) and (not np.isfinite(w_opt) or w_opt > w_gc / keep))
        kappa_max = self.kappa_max(percent)
        bounds = {f"{field}_min": _boundary(p, proc, field, need, "optimal")
                  for field in ("loop_bandwidth", "overhead", "rate_noise")}
        return RaceConditions(**base, t_needed=need, holds_classical=held["classical"],
                              holds_optimal=held["optimal"], worst_t_gc=w_gc,
                              worst_t_classical=w_part.t_c, worst_t_optimal=w_opt,
                              holds_over_ranges=w_holds, kappa_max=kappa_max, **bounds)

    def evidence(self) -> str:
        """One sentence for the reproduction ledger: the race's times and savings.

        Examples
        --------
        >>> from gyrolib import gc
        >>> print(gc.race().evidence())   # doctest: +ELLIPSIS
        race (gc.race) under the same disturbances: t_c = 24.1 s (GC) against 141.6 s ...
        """
        proc = self.procedure

        def t(x: float) -> str:
            return f"{x:.1f} s" if np.isfinite(x) else "not reached"

        def pct(x: float) -> str:
            return f"{x:.0f} %" if np.isfinite(x) else "undefined (GC does not reach sigma_c)"
        return (f"race (gc.race) under the same disturbances: t_c = {t(self.t_c_gc)} (GC) "
                f"against {t(self.t_c_rate_sensor)} (rate-sensor method, classical "
                f"half-sum) and {t(self.t_c_rate_sensor_optimal)} (same measurements, "
                f"optimal Kalman), the float in a rebalance loop of {proc.loop_bandwidth:g} "
                f"rad/s that passes the angle sensor's noise, turn {proc.T_rot:g} s and "
                f"settling {proc.T_settle:g} s included: GC faster by "
                f"{pct(self.faster_percent)} and "
                f"{pct(self.faster_percent_optimal)}")


def race_margin(params: GyrocompassParams | None = None,
                procedure: RateSensorProcedure | None = None, percent: float = 50.0) -> float:
    """The margin of the claim "GC is more than ``percent`` % faster than the rate-sensor
    method": the smaller saving over the two estimators minus ``percent`` (%; ``> 0``: the
    claim holds).  The saving is ``100 (1 − t_GC/t_rival)``; when GC never reaches σ_c it is
    −100 % (the margin ``−100 − percent``), when the rival never does +100 %.  The same
    times as :func:`race`, without its curves (the table of inputs maps this margin,
    :mod:`gyrolib.claim_map`).

    Examples
    --------
    >>> from gyrolib import gc
    >>> f"{gc.race_margin():.1f}"
    '7.3'
    """
    p = GyrocompassParams() if params is None else check_params(params)
    proc = RateSensorProcedure() if procedure is None else check_procedure(procedure)
    percent = v.check_in_range("percent", percent, 0.0, 100.0, low_open=True, high_open=True)
    t_gc = _gc_time(p, proc.sigma_c, proc.t_max)
    if not np.isfinite(t_gc):
        return -100.0 - percent
    part = _rate_part_at(p, proc)
    savings = [_percent(t_gc, t if np.isfinite(t) else math.inf)
               for t in (part.t_c, part.t_c_optimal)]
    return float(min(savings)) - percent


@functools.lru_cache(maxsize=256)
def _gc_time(p: GyrocompassParams, level: float, t_max: float) -> float:
    """GC's time to ``level`` (``nan``: not reached), kept per parameters: the rival's rows
    of a map do not change it.  The same number as ``_gc_part(p, level, t_max)[0]``, from
    :func:`gyrolib.gc.time_to_level` (the filter's covariance stopped at the crossing, over
    the same horizons; the margins ran all of 100 s, or 1000 s, to read a time of
    about 25 s)."""
    s_scale = p.scale_drift_sigma
    if s_scale >= level:
        return math.nan
    p_filter = replace(p, sigma_hf_scale=0.0) if p.sigma_hf_scale else p
    horizon = min(max(_GC_HORIZONS), t_max)
    n = max(1, round(horizon / p.dt))
    t_end = horizon if abs(n * p.dt - horizon) < 1e-12 * horizon else n * p.dt
    return time_to_level(p_filter, math.sqrt(level**2 - s_scale**2), t_end)


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


@functools.lru_cache(maxsize=256)
def _boundary(p: GyrocompassParams, proc: RateSensorProcedure, field: str, need: float,
              estimator: str) -> float:
    """Smallest value of ``field`` for which the rate-sensor time exceeds ``need`` (0 if it
    does at the field's lower end; ``inf`` if never); kept per inputs, like
    :func:`_rate_time`."""
    value = procedure_for_time(p, proc, field, need, estimator=estimator)
    return float(value)


def procedure_for_time(params: GyrocompassParams | None, procedure: RateSensorProcedure | None,
                       field: str, target: float, *, estimator: str = "classical",
                       rtol: float = 1e-3) -> float:
    """The value of one procedure quantity at which the rate-sensor method takes ``target``
    seconds to reach σ_c, the others held.

    The rate-sensor time grows with each of these quantities; the value is found by
    bisection (on a log scale for ``rate_noise`` and ``loop_bandwidth``).

    Parameters
    ----------
    params : GyrocompassParams or None
        Paper GC's parameters (``None``: the paper's).
    procedure : RateSensorProcedure or None
        The procedure (``None``: the book's).
    field : {"overhead", "T_rot", "T_settle", "rate_noise", "loop_bandwidth"}
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
        The value (s, rad²/s for ``rate_noise``, rad/s for ``loop_bandwidth``); 0 if the
        method takes longer than ``target`` even at 0 (for ``rate_noise``: at 10⁻⁶ of the
        procedure's, for ``loop_bandwidth`` at 10⁻²); ``inf`` if it takes less at any value
        up to ``target`` (for ``loop_bandwidth``: 10² times the procedure's; for
        ``rate_noise``: 10⁶ times the
        procedure's).

    Examples
    --------
    >>> from gyrolib import gc
    >>> f"{gc.procedure_for_time(None, None, 'overhead', 150.0):.1f} s"
    '27.1 s'
    """
    p = GyrocompassParams() if params is None else check_params(params)
    proc = RateSensorProcedure() if procedure is None else check_procedure(procedure)
    v.check_choice("field", field, PROCEDURE_TARGETS)
    v.check_choice("estimator", estimator, _ESTIMATORS)
    target = v.check_positive("target", target)
    rtol = v.check_in_range("rtol", rtol, 0.0, 0.5, low_open=True)

    def too_slow(x: float) -> bool:
        if estimator == "optimal":
            return _optimal_exceeds(p, _with(proc, field, x), target)
        return _classical_exceeds_on(rate_sensor_model(p, _with(proc, field, x)), target)

    if field in ("rate_noise", "loop_bandwidth"):
        # bracket by decades from the procedure's value, then bisect on a log scale
        q0 = getattr(proc, field)
        down, up = (1e-6, 1e6) if field == "rate_noise" else (1e-2, 1e2)
        if too_slow(q0):
            lo, hi = q0, q0
            while too_slow(lo):
                if lo < q0 * down:
                    return 0.0
                lo, hi = lo / 10.0, lo
        else:
            lo, hi = q0, q0
            while not too_slow(hi):
                if hi > q0 * up:
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
    # the times as the margin keeps them (the same model: the rival reads none of GC's
    # instrument constants), so that a map of the claim at these inputs does not search
    # the rival's windows a second time
    part = _rate_part_at(p, proc)
    if part.n1:
        # the curves run half as long again as the classical procedure's position 2
        n2_plot = part.n2 + max(1, part.n2 // 2)
        t_cl, s_cl = model.classical_curve(part.n1 * proc.sample_dt, n2_plot * proc.sample_dt)
        run = model.optimal_run_samples(part.n1, n2_plot)
        t1, t2 = part.n1 * proc.sample_dt, part.n2 * proc.sample_dt
    else:
        t_cl = s_cl = np.zeros(0)
        n = math.floor((proc.t_max - proc.overhead) / proc.sample_dt + 1e-9)
        n1, n2 = _split(proc, max(n, 2)) if proc.split is not None else (
            max(n, 2) // 2, max(n, 2) - max(n, 2) // 2)
        run = model.optimal_run_samples(n1, n2)
        t1 = t2 = math.nan
    if part.n1_optimal and np.isfinite(part.t_c_optimal):
        # the optimal estimator's own windows: position 2 half as long again as it needs
        n2_opt = math.ceil((part.t_c_optimal - proc.overhead) / proc.sample_dt) \
            - part.n1_optimal
        run = model.optimal_run_samples(part.n1_optimal, max(1, n2_opt + max(1, n2_opt // 2)))
    phases = tuple((name, a, min(b, part.t_c) if name == "position 2" and part.n1 else b)
                   for name, a, b in run.phases)
    return RaceResult(params=p, procedure=proc, t_c_gc=gc_part[0], t_c_rate_sensor=part.t_c,
                      t_c_rate_sensor_optimal=part.t_c_optimal, t1=t1, t2=t2,
                      t1_optimal=part.n1_optimal * proc.sample_dt if part.n1_optimal
                      else math.nan, t_gc=gc_part[1], sigma_gc=gc_part[2], t_classical=t_cl,
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
    ['24.1 s', '141.6 s', '56.4 s']
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
        ['83', '88']
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
    ['141.6', '185.5']
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
    out = np.empty((len(cases), 3))
    for i, c in enumerate(cases):
        q = replace(p, **{k: x for k, x in c.items() if k in _PARAM_FIELDS})
        pr = replace(proc, **{k: x for k, x in c.items() if k in _PROC_FIELDS})
        part = _rate_part_at(q, pr)
        out[i] = _gc_time(q, pr.sigma_c, pr.t_max), part.t_c, part.t_c_optimal
    return RaceSweep(params=p, procedure=proc, cases=cases, t_c_gc=out[:, 0],
                     t_c_rate_sensor=out[:, 1], t_c_rate_sensor_optimal=out[:, 2])
