"""The heavy studies of paper GC's chapters in the store (:mod:`gyrolib.store`).

Three studies, each registered under its name (:data:`NAMES`) with its file in
``gyrolib/data/``, its key, its fingerprint check and its computation:

* ``gc-monte-carlo`` (``gc_monte_carlo.json``): the Monte Carlo sets of the claims chapter
  (:func:`gyrolib.gc.monte_carlo`): the paper's truth, the linearized truth and the truth
  with σ1² × :data:`WRONG_FACTOR`, :data:`N_RUNS` runs over :data:`T_END` s with seed
  :data:`SEED`, kept as :class:`~gyrolib.gc.MonteCarloSummary` and a compact
  :class:`~gyrolib.gc.LinearizationEffect`; the bootstrap intervals of the NEES shares; the
  shares of :data:`N_SETS` disjoint sets; the NEES excess of each truth variant of
  :data:`VARIANTS` run by run, and the gap of the fast kernel's series to ``np.cos`` run by
  run.  Its fingerprint: the first :data:`CHECK_RUNS` runs of each set recomputed with their
  seeds (every state's error at the end in units of the filter's σ, of the paper's truth; the
  ω_gc shift of the linearized truth), the first two runs of the variants
  :data:`CHECK_VARIANTS` and the first run's series gap;
* ``gc-speed-claim`` (``gc_speed_claim.json``): the speed-claim map of σ1² × α1 for both
  readings of P0 (:func:`gyrolib.gc.speed_claim_map`), its boundary along σ1²
  (:func:`gyrolib.gc.claim_boundary`) and the shaping sweep
  (:func:`gyrolib.gc.shaping_sweep`).  Its fingerprint: three points of the map at the
  paper's α1 (the paper's σ1², the last that holds, the largest; both readings), the
  boundary bracketed (σ of ω_gc at the bound below σ_c at
  × (1 − 2 %) of the stored factor, above it at × (1 + 2 %)), and two points of the sweep;
* ``gc-race-sweeps`` (``gc_race_sweeps.json``): the race chapter's sweeps
  (:func:`gyrolib.gc.race_sweep`) and its three Monte Carlo checks of the rate-sensor method
  (:func:`gyrolib.gc.rate_sensor_monte_carlo`).  Its fingerprint: one case of each sweep and
  the first :data:`CHECK_RUNS` runs of each Monte Carlo check.

The key of each (:func:`key`) hashes the constants and default dataclasses of every module
whose constants and defaults the study reads (this one's included: its run counts, seeds
and grids) and the rows of the table of inputs it reads.  Every number a check compares is
of order one or more in its unit (errors in σ, NEES, σ in σ_c, times in s) and must agree to
the declared ``rtol`` 1e-6, ``atol`` 1e-6.

:func:`load` is how a chapter reads a study: checked (:func:`gyrolib.store.check`, a stale
one raises :class:`gyrolib.store.StaleStudy` naming it and its refresh command), or, with
``refresh=True``, recomputed here without writing anything.

Examples
--------
>>> from gyrolib.book.studies import gc as gcs
>>> gcs.NAMES
('gc-monte-carlo', 'gc-speed-claim', 'gc-race-sweeps')
>>> gcs.decode(gcs.encode((1.0, {"a": np.arange(3.0)})))[1]["a"].tolist()
[0.0, 1.0, 2.0]
"""

from __future__ import annotations

import dataclasses
import functools
import json
import sys
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any, Final

import numpy as np

import gyrolib
from gyrolib import gc, levels, stats, store, units
from gyrolib import inputs as _inputs
from gyrolib.book.ledger import gc as _ledger_gc
from gyrolib.filtering.consistency import nees_bounds
from gyrolib.gc.analysis import covariance as _covariance
from gyrolib.gc.analysis import linearization as _linearization
from gyrolib.gc.analysis import montecarlo as _montecarlo
from gyrolib.gc.analysis import speed_claim as _speed_claim
from gyrolib.gc.model import discretization as _discretization
from gyrolib.gc.model import params as _params
from gyrolib.gc.racing import comparison as _race
from gyrolib.gc.racing import rate_sensor as _rate_sensor

__all__ = [
    "CHECK_RUNS",
    "NAMES",
    "N_RUNS",
    "N_SETS",
    "RACE_MC_RUNS",
    "SEED",
    "T_END",
    "VARIANTS",
    "WRONG_FACTOR",
    "decode",
    "describe",
    "encode",
    "key",
    "load",
    "nees_share",
]

#: not inputs of a study: its name, its words, and what its check recomputes
__key_ignore__ = ("NAMES", "CHECK_RUNS", "CHECK_VARIANTS", "_WHAT")

#: The registered studies, in the order ``refresh --list`` shows them.
NAMES: Final[tuple[str, ...]] = ("gc-monte-carlo", "gc-speed-claim", "gc-race-sweeps")

_DATA: Final[Path] = Path(gyrolib.__file__).resolve().parent / "data"

#: The claims chapter's Monte Carlo: runs, seed, length (s) and the wrong truth's σ1² factor.
N_RUNS: Final[int] = 256
SEED: Final[int] = 20240
T_END: Final[float] = 100.0
WRONG_FACTOR: Final[float] = 9.0
#: Disjoint sets of the linearized truth's runs, each judged against its own band.
N_SETS: Final[int] = 8
#: The truth variants over 10 s with half the runs: (label, truth, substeps).
VARIANTS: Final[tuple[tuple[str, str, int], ...]] = (
    ("nonlinear (the paper's Eq. (3))", "nonlinear", 10),
    ("only Ω_h cos(β − ψ) linearized", "linear_horizontal", 10),
    ("only the tilt terms Ω_v(γ cos β − δ sin β) linearized", "linear_tilt", 10),
    ("nonlinear, truth's step Δt/5", "nonlinear", 5),
    ("nonlinear, truth's step Δt/20", "nonlinear", 20))
#: The variants' length (s), storing step and the time after which the excess is averaged.
VARIANT_T: Final[float] = 10.0
VARIANT_STORE_EVERY: Final[int] = 100
EXCESS_AFTER: Final[float] = 5.0
#: Runs and length (s) of the fast kernel against the plain-numpy path.
SERIES_RUNS: Final[int] = 32
SERIES_T: Final[float] = 1.0
#: Runs of each recomputed from its seed by a check.
CHECK_RUNS: Final[int] = 3
#: The variants whose first two runs a check recomputes: one per code path that the paper's
#: truth's runs do not take (the horizontal term linearized, the tilt terms linearized, a
#: finer truth step); the others run the paper's truth's code with other substeps.
CHECK_VARIANTS: Final[tuple[int, ...]] = (1, 2, 4)

#: The race chapter's sweeps: case lists by name (fields of GyrocompassParams or
#: RateSensorProcedure, relative to the defaults where a factor is given).
T_ROT: Final[tuple[float, ...]] = (0.0, 10.0, 30.0, 60.0)
T_SETTLE: Final[tuple[float, ...]] = (0.0, 10.0, 30.0, 60.0, 120.0, 300.0)
NOISE: Final[tuple[float, ...]] = (0.1, 1.0, 10.0, 100.0, 1000.0)
KAPPA: Final[tuple[float, ...]] = (0.0, 5e-5, 1e-4, 2e-4)
#: The race's Monte Carlo checks: runs, seed and the wrong truth's σ1² factor.
RACE_MC_RUNS: Final[int] = 400
RACE_MC_SEED: Final[int] = 2024
RACE_WRONG: Final[float] = 9.0

_ROWS: Final[dict[str, tuple[str, ...]]] = {
    "gc-monte-carlo": (),
    "gc-speed-claim": ("gc.sigma1_sq", "gc.alpha1"),
    "gc-race-sweeps": ("race.sigma_scale", "race.loop_bandwidth", "gc.C_as",
                       "race.rate_noise", "gc.sigma1_sq"),
}
_GC_MODULES: Final[tuple[Any, ...]] = (levels, units, _params, _discretization, _covariance)
_MODULES: Final[dict[str, tuple[Any, ...]]] = {
    "gc-monte-carlo": (*_GC_MODULES, _montecarlo, _linearization),
    "gc-speed-claim": (*_GC_MODULES, _speed_claim, _ledger_gc),
    "gc-race-sweeps": (*_GC_MODULES, _montecarlo, _race, _rate_sensor),
}


def key(name: str) -> dict[str, str]:
    """The key of study ``name`` now (:func:`gyrolib.store.model_key`): the constants and
    default dataclasses of the modules it reads, this module's included, and the table's
    fingerprint over the rows it reads."""
    if name not in NAMES:
        raise ValueError(f"name must be one of {NAMES}; got {name!r}")
    return store.model_key(_MODULES[name] + (sys.modules[__name__],),
                           extra={"table": _inputs.table_fingerprint(_ROWS[name])})


# the file's encoding ---------------------------------------------------------------------------
_TYPES: Final[dict[str, type]] = {c.__name__: c for c in (
    gc.GyrocompassParams, gc.RateSensorProcedure, gc.MonteCarloSummary,
    gc.LinearizationEffect, gc.SpeedClaimMap, gc.ClaimBoundary, gc.ShapingSweep,
    gc.RaceSweep, gc.RateSensorMonteCarlo, stats.Estimate)}


def encode(x: Any) -> Any:
    """``x`` as JSON values: the result dataclasses of :data:`_TYPES` by their fields, an
    array as its dtype, shape and values (exact reprs on one line), a tuple tagged."""
    if dataclasses.is_dataclass(x) and not isinstance(x, type):
        name = type(x).__name__
        if _TYPES.get(name) is not type(x):
            raise TypeError(f"x: cannot store a {name}")
        return {"__type__": name, **{f.name: encode(getattr(x, f.name))
                                     for f in dataclasses.fields(x) if f.init}}
    if isinstance(x, np.ndarray):
        flat = x.ravel().tolist()
        return {"__array__": x.dtype.str, "shape": list(x.shape),
                "data": " ".join(str(int(b)) if x.dtype.kind == "b" else repr(float(b))
                                 for b in flat)}
    if isinstance(x, tuple):
        return {"__tuple__": [encode(i) for i in x]}
    if isinstance(x, list):
        return [encode(i) for i in x]
    if isinstance(x, dict):
        return {str(k): encode(i) for k, i in x.items()}
    if isinstance(x, np.generic):
        return x.item()
    return x


def decode(x: Any) -> Any:
    """The inverse of :func:`encode`."""
    if isinstance(x, list):
        return [decode(i) for i in x]
    if not isinstance(x, dict):
        return x
    if "__array__" in x:
        dt = np.dtype(x["__array__"])
        vals = x["data"].split()
        a = np.array([int(s) for s in vals], dtype=bool) if dt.kind == "b" else \
            np.array([float(s) for s in vals], dtype=dt)
        return a.reshape(x["shape"])
    if "__tuple__" in x:
        return tuple(decode(i) for i in x["__tuple__"])
    if "__type__" in x:
        cls = _TYPES[x["__type__"]]
        return cls(**{k: decode(i) for k, i in x.items() if k != "__type__"})
    return {k: decode(i) for k, i in x.items()}


def _done(futures: list[Any]) -> list[Any]:
    return [f.result() if hasattr(f, "result") else f for f in futures]


def _submit(executor: Any, fn: Callable[..., Any], *args: Any, **kw: Any) -> Any:
    """``fn(*args, **kw)`` on ``executor`` (a future), or here (the value)."""
    return fn(*args, **kw) if executor is None else executor.submit(fn, *args, **kw)


def _tick(progress: Any, n: int = 1) -> None:
    if progress is not None:
        progress.update(n)


def _total(progress: Any, n: int) -> None:
    if progress is not None:
        progress.total = n
        progress.refresh()


# the claims chapter's Monte Carlo --------------------------------------------------------------
def nees_share(band: tuple[float, float]) -> Callable[[np.ndarray], np.ndarray]:
    """Share of the stored times at which the runs' average NEES lies in ``band``, for a
    stack of resampled ensembles (a vectorized statistic for :func:`gyrolib.stats.bootstrap`,
    as :meth:`gyrolib.gc.MonteCarloResult.inside_share`)."""
    def share(runs: np.ndarray) -> np.ndarray:
        avg = runs.mean(axis=1)
        return np.mean((avg > band[0]) & (avg < band[1]), axis=1)
    return share


def _wrong() -> gc.GyrocompassParams:
    base = gc.GyrocompassParams()
    return dataclasses.replace(base, sigma1_sq=WRONG_FACTOR * base.sigma1_sq)


def _variant_excess(mode: str, sub: int, n_runs: int, executor: Any) -> tuple[np.ndarray, float]:
    """Per run, the NEES excess of truth ``mode`` over the linearized one averaged over
    ``t >= EXCESS_AFTER``, and the ensemble's predicted excess there."""
    base = gc.GyrocompassParams()
    kw = dict(seed=SEED, store_every=VARIANT_STORE_EVERY, substeps=sub, executor=executor)
    a = gc.monte_carlo(base, n_runs, VARIANT_T, truth=mode, **kw)
    b = gc.monte_carlo(base, n_runs, VARIANT_T, truth="linear", **kw)
    sel = a.t >= EXCESS_AFTER
    per_run = (a.nees() - b.nees())[:, sel].mean(axis=1)
    pred = 0.0
    if mode != "linear_horizontal":
        eff = gc.linearization_effect(a, b)
        pred = float(eff.excess_predicted[eff.t >= EXCESS_AFTER].mean())
    return per_run, pred


def _series_gap(n_runs: int) -> np.ndarray:
    """Per run, the largest gap of the fast kernel's estimates to the plain-numpy path's
    (``np.cos``), in units of the filter's σ."""
    base = gc.GyrocompassParams()
    a = gc.monte_carlo(base, n_runs, SERIES_T, seed=SEED, store_every=VARIANT_STORE_EVERY)
    b = gc.monte_carlo(base, n_runs, SERIES_T, seed=SEED, store_every=VARIANT_STORE_EVERY,
                       method="reference")
    sd = np.sqrt(np.diagonal(a.P, axis1=1, axis2=2))[None, 1:]
    return np.max(np.abs(a.est - b.est)[:, 1:] / sd, axis=(1, 2))


def _compute_mc(executor: Any, progress: Any, *, path: Path | None = None,
                **_: Any) -> dict[str, Any]:
    base = gc.GyrocompassParams()
    _total(progress, 5 + len(VARIANTS))
    mc = gc.monte_carlo(base, N_RUNS, T_END, seed=SEED, executor=executor)
    b1 = nees_bounds(1, N_RUNS)
    b10 = nees_bounds(len(gc.STATE_NAMES), N_RUNS)
    in_gc = stats.bootstrap(mc.nees(("omega_gc",))[:, 1:], nees_share(b1), seed=SEED,
                            vectorized=True)
    in_full = stats.bootstrap(mc.nees()[:, 1:], nees_share(b10), seed=SEED, vectorized=True)
    _tick(progress)
    mc_lin = gc.monte_carlo(base, N_RUNS, T_END, seed=SEED, truth="linear", executor=executor)
    lin = gc.linearization_effect(mc, mc_lin)
    sets = [mc_lin.select(slice(i * N_RUNS // N_SETS, (i + 1) * N_RUNS // N_SETS))
            for i in range(N_SETS)]
    shares = np.array([[m.inside_share(("omega_gc",)) for m in sets],
                       [m.inside_share() for m in sets]])
    summary = mc.summary(states=("omega_gc",), keep_runs=2)
    del mc_lin, sets
    _tick(progress)
    del mc
    mc_wrong = gc.monte_carlo(base, N_RUNS, T_END, seed=SEED, truth_params=_wrong(),
                              executor=executor)
    wrong = mc_wrong.summary(states=("omega_gc",), keep_runs=0)
    del mc_wrong
    _tick(progress)
    variants = []
    for label, mode, sub in VARIANTS:
        per_run, pred = _variant_excess(mode, sub, N_RUNS // 2, executor)
        variants.append({"label": label, "truth": mode, "substeps": sub,
                         "excess_runs": per_run, "excess_predicted": pred})
        _tick(progress)
    gap = _series_gap(SERIES_RUNS)
    _tick(progress)
    return encode({"mc": summary, "in_gc": in_gc, "in_full": in_full,
                   "lin": lin.compact(), "set_shares": shares, "wrong": wrong,
                   "variants": variants, "series_gap_runs": gap})


def _check_runs(name: str, label: str, was: gc.MonteCarloSummary, h: store.Header,
                errors: bool = True, **kw: Any) -> gc.MonteCarloResult:
    """The first :data:`CHECK_RUNS` runs of ``was`` recomputed (``kw`` to
    :func:`gyrolib.gc.monte_carlo`) and, with ``errors``, every state's error at the end
    compared with the stored one, in units of the filter's σ."""
    now = gc.monte_carlo(was.params, CHECK_RUNS, float(was.t[-1]), seed=was.seed,
                         store_every=round((was.t[1] - was.t[0]) / was.params.dt), **kw)
    sd = np.sqrt(np.diagonal(now.P[-1]))
    for r in range(CHECK_RUNS if errors else 0):
        for i, st in enumerate(now.names):
            if sd[i] > 0:
                store.compare(name, f"{label}: run {r}'s error of {st} at {now.t[-1]:g} s, "
                              "in the filter's σ", was.end_error[r, i] / sd[i],
                              (now.est[r, -1, i] - now.tru[r, -1, i]) / sd[i],
                              rtol=h.rtol, atol=h.atol)
    return now


def _check_mc(data: Mapping[str, Any]) -> int:
    name = "gc-monte-carlo"
    h = store.header_of(name, data)
    d = decode({k: data[k] for k in ("mc", "wrong", "lin", "variants", "series_gap_runs")})
    n = len(gc.STATE_NAMES)
    mc = d["mc"]
    if mc.n_runs != N_RUNS or mc.seed != SEED or mc.params != gc.GyrocompassParams():
        raise store.StaleStudy(name, "it was computed with other runs, seed or parameters")
    now = _check_runs(name, "the paper's truth", mc, h)
    sd_w = np.sqrt(np.diagonal(now.P[:, :1, :1], axis1=1, axis2=2))[:, 0]
    for r in range(2):
        store.compare(name, f"run {r}'s ω_gc estimate at the end, in σ",
                      mc.estimate("omega_gc")[r, -1] / sd_w[-1],
                      now.estimate("omega_gc")[r, -1] / sd_w[-1], rtol=h.rtol, atol=h.atol)
    lin_now = _check_runs(name, "the linearized truth", mc, h, errors=False, truth="linear")
    lin = d["lin"]
    iw = gc.STATE_NAMES.index("omega_gc")
    for r in range(CHECK_RUNS):
        store.compare(name, f"run {r}'s ω_gc shift of the linearized truth at the end, in σ",
                      lin.omega_shift[r, -1] / lin.omega_sigma[-1],
                      (now.est[r, -1, iw] - lin_now.est[r, -1, iw]) / lin.omega_sigma[-1],
                      rtol=h.rtol, atol=h.atol)
    if d["wrong"].truth_params != _wrong():
        raise store.StaleStudy(name, "its louder truth has other parameters than the code's")
    for v_ in (d["variants"][i] for i in CHECK_VARIANTS):
        per_run, _ = _variant_excess(v_["truth"], v_["substeps"], 2, None)
        for r in range(2):
            store.compare(name, f"{v_['label']}: run {r}'s NEES excess", v_["excess_runs"][r],
                          per_run[r], rtol=h.rtol, atol=h.atol)
    gap = _series_gap(1)
    for r in range(1):
        store.compare(name, f"run {r}'s gap of the fast kernel to np.cos, in σ",
                      d["series_gap_runs"][r], gap[r], rtol=h.rtol, atol=h.atol)
    return CHECK_RUNS * n + 2 + CHECK_RUNS + 2 * len(CHECK_VARIANTS) + 1


# the speed claim -------------------------------------------------------------------------------
def _map_inputs() -> dict[str, Any]:
    return dict(x_field="sigma1_sq", x_factors=_inputs.factor_grid("gc.sigma1_sq", 7),
                y_field="alpha1", y_factors=_inputs.factor_grid("gc.alpha1", 7))


def _compute_speed(executor: Any, progress: Any, *, path: Path | None = None,
                   **_: Any) -> dict[str, Any]:
    base = gc.GyrocompassParams()
    _total(progress, 3)
    claim = gc.speed_claim_map(base, _ledger_gc.SIGMA_C, _ledger_gc.T_BOUND, **_map_inputs(),
                               executor=executor)
    _tick(progress)
    boundary = gc.claim_boundary(base, _ledger_gc.SIGMA_C, _ledger_gc.T_BOUND,
                                 field="sigma1_sq",
                                 factors=(1.0, _inputs.row("gc.sigma1_sq").high),
                                 executor=executor)
    _tick(progress)
    sweep = gc.shaping_sweep(base, T_END, factors=_inputs.factor_grid("gc.alpha1"),
                             executor=executor)
    _tick(progress)
    return encode({"claim": claim, "boundary": boundary, "sweep": sweep})


def _check_speed(data: Mapping[str, Any]) -> int:
    name = "gc-speed-claim"
    h = store.header_of(name, data)
    d = decode({k: data[k] for k in ("claim", "boundary", "sweep")})
    claim, boundary, sweep = d["claim"], d["boundary"], d["sweep"]
    base = gc.GyrocompassParams()
    mi = _map_inputs()
    if not (np.allclose(claim.x_factors, mi["x_factors"]) and
            np.allclose(claim.y_factors, mi["y_factors"])):
        raise store.StaleStudy(name, "its map was computed over another grid than the table "
                               "of inputs gives now")
    n = 0
    i1 = int(np.argmin(np.abs(np.log(claim.y_factors))))
    # at the paper's α1: the paper's σ1², the last point where the claim holds with the
    # stationary P0 and the largest σ1², both readings
    j0 = int(np.argmin(np.abs(np.log(claim.x_factors))))
    held = np.flatnonzero(claim.holds()[0, i1])
    cols = sorted({j0, int(held[-1]) if held.size else j0, claim.x_factors.size - 1})
    now = gc.speed_claim_map(base, claim.level, claim.bound, x_field=claim.x_field,
                             x_factors=claim.x_factors[cols], y_field=claim.y_field,
                             y_factors=claim.y_factors[i1:i1 + 1], readings=claim.readings)
    for c, j in enumerate(cols):
        for r, reading in enumerate(claim.readings):
            store.compare(name, f"the time to σ_c at σ1² × {claim.x_factors[j]:.4g}, "
                          f"{reading} P0 (s)", claim.t_c[r, i1, j], now.t_c[r, 0, c],
                          rtol=h.rtol, atol=h.atol)
            n += 1
    f = boundary.factor
    lo, hi = gc.claim_boundary(base, boundary.level, boundary.bound, field=boundary.field,
                               factors=(0.98 * f, 1.02 * f)).sigma
    store.same_sign(name, f"σ_c − σ of ω_gc at the bound, σ1² × {0.98 * f:.4g} (just inside "
                    "the stored boundary)", True, boundary.level - lo)
    store.same_sign(name, f"σ_c − σ of ω_gc at the bound, σ1² × {1.02 * f:.4g} (just outside "
                    "the stored boundary)", False, boundary.level - hi)
    n += 2
    for a, k in ((sweep.fields.index("sigma1_sq"), -1), (sweep.fields.index("alpha1"), 0)):
        field = sweep.fields[a]
        now = gc.shaping_sweep(base, sweep.t_end, fields=(field,),
                               factors=sweep.factors[[k]], t_drop=sweep.t_drop)
        store.compare(name, f"the sweep's σ at {sweep.t_end:g} s, {field} × "
                      f"{sweep.factors[k]:.4g}, in σ_c", sweep.sigma_end[a, k] / levels.SIGMA_C,
                      now.sigma_end[0, 0] / levels.SIGMA_C, rtol=h.rtol, atol=h.atol)
        store.compare(name, f"the sweep's σ({sweep.t_drop:g} s)/σ(0), {field} × "
                      f"{sweep.factors[k]:.4g}", sweep.drop[a, k], now.drop[0, 0],
                      rtol=h.rtol, atol=h.atol)
        n += 2
    return n


# the race chapter's sweeps ---------------------------------------------------------------------
def _race_cases() -> dict[str, list[dict[str, Any]]]:
    """The race chapter's sweeps, case by case."""
    base, proc = gc.GyrocompassParams(), gc.RateSensorProcedure()
    bw = _inputs.row("race.loop_bandwidth").grid(5)
    cas = (1.0, _inputs.row("gc.C_as").high)
    return {
        "dt_check": [{"sample_dt": 0.1}, {"sample_dt": 0.02}],
        "scale_check": [{"sigma_scale": x} for x in _inputs.row("race.sigma_scale").grid(3)],
        "loop": [{"loop_bandwidth": b, "C_as": f * base.C_as} for f in cas for b in bw],
        "grid": [{"T_rot": a, "T_settle": b} for a in T_ROT for b in T_SETTLE],
        "noise": [{"rate_noise": f * proc.rate_noise} for f in NOISE],
        "vib": [{"sigma1_sq": f * base.sigma1_sq, "vibration_frame": fr}
                for fr in gc.VIBRATION_FRAMES for f in _inputs.factor_grid("gc.sigma1_sq")],
        "scale": [{"sigma_hf_scale": k} for k in KAPPA],
    }


def _race_mc_cases(t1: float, t2: float) -> dict[str, dict[str, Any]]:
    base, proc = gc.GyrocompassParams(), gc.RateSensorProcedure()
    common = dict(t1=t1, t2=t2, seed=RACE_MC_SEED)
    return {
        "mc": dict(params=base, procedure=proc, **common),
        "mc_wrong": dict(params=base, procedure=proc, truth_params=dataclasses.replace(
            base, sigma1_sq=RACE_WRONG * base.sigma1_sq), **common),
        "mc_nopick": dict(params=base, procedure=dataclasses.replace(proc, angle_noise_scale=0.0),
                          truth_procedure=proc, **common),
    }


def _compute_race(executor: Any, progress: Any, *, path: Path | None = None,
                  **_: Any) -> dict[str, Any]:
    base, proc = gc.GyrocompassParams(), gc.RateSensorProcedure()
    cases = _race_cases()
    _total(progress, sum(len(c) for c in cases.values()) + 3)
    race = gc.race(base, proc)
    mcs = {k: _submit(executor, gc.rate_sensor_monte_carlo, n_runs=RACE_MC_RUNS, **kw)
           for k, kw in _race_mc_cases(race.t1, race.t2).items()}
    futures = {k: [_submit(executor, gc.race_sweep, base, proc, cases=[c]) for c in cs]
               for k, cs in cases.items()}
    out: dict[str, Any] = {}
    for k, fs in futures.items():
        parts = []
        for f in fs:
            parts.append(_done([f])[0])
            _tick(progress)
        out[k] = gc.RaceSweep(params=base, procedure=proc,
                              cases=tuple(c for p in parts for c in p.cases),
                              **{a: np.concatenate([getattr(p, a) for p in parts])
                                 for a in ("t_c_gc", "t_c_rate_sensor",
                                           "t_c_rate_sensor_optimal")})
    for k, f in mcs.items():
        out[k] = _done([f])[0]
        _tick(progress)
    out["t1"], out["t2"] = float(race.t1), float(race.t2)
    return encode(out)


def _check_race(data: Mapping[str, Any]) -> int:
    name = "gc-race-sweeps"
    h = store.header_of(name, data)
    base, proc = gc.GyrocompassParams(), gc.RateSensorProcedure()
    d = decode(dict(data))
    cases = _race_cases()
    n = 0
    for k, cs in cases.items():
        sw = d[k]
        if [dict(c) for c in sw.cases] != cs:
            raise store.StaleStudy(name, f"its sweep {k} was computed over other cases than "
                                   "the table of inputs and the defaults give now")
        i = 0 if k != "noise" else NOISE.index(1.0)   # the cheapest case of each
        now = gc.race_sweep(base, proc, cases=[cs[i]])
        for a in ("t_c_gc", "t_c_rate_sensor", "t_c_rate_sensor_optimal"):
            store.compare(name, f"the sweep {k}'s {a} at {cs[i]} (s)", getattr(sw, a)[i],
                          getattr(now, a)[0], rtol=h.rtol, atol=h.atol)
            n += 1
    for k, kw in _race_mc_cases(d["t1"], d["t2"]).items():
        now = gc.rate_sensor_monte_carlo(n_runs=max(CHECK_RUNS, 2), **kw)
        was = d[k]
        store.compare(name, f"{k}: the computed σ, in σ_c", was.sigma / levels.SIGMA_C,
                      now.sigma / levels.SIGMA_C, rtol=h.rtol, atol=h.atol)
        for r in range(now.n_runs):
            store.compare(name, f"{k}: run {r}'s error, in the computed σ",
                          was.errors[r] / was.sigma, now.errors[r] / was.sigma,
                          rtol=h.rtol, atol=h.atol)
            n += 1
        n += 1
    return n


# registration and reading ----------------------------------------------------------------------
_FILES: Final[dict[str, Path]] = {n: _DATA / (n.replace("-", "_") + ".json") for n in NAMES}
_COMPUTE: Final[dict[str, Callable[..., dict[str, Any]]]] = {
    "gc-monte-carlo": _compute_mc, "gc-speed-claim": _compute_speed,
    "gc-race-sweeps": _compute_race}
_CHECK: Final[dict[str, Callable[[Mapping[str, Any]], int]]] = {
    "gc-monte-carlo": _check_mc, "gc-speed-claim": _check_speed, "gc-race-sweeps": _check_race}
_WHAT: Final[dict[str, str]] = {
    "gc-monte-carlo": "the claims chapter's Monte Carlo sets: the paper's, the linearized and "
                      "a louder truth, the truth variants and the series check",
    "gc-speed-claim": "the speed-claim map over σ1² and α1, its boundary and the shaping "
                      "sweep",
    "gc-race-sweeps": "the race chapter's sweeps of the rival's procedure and its Monte Carlo "
                      "checks"}

for _name in NAMES:
    store.register(store.Study(_name, _FILES[_name], functools.partial(key, _name),
                               _CHECK[_name], _COMPUTE[_name], rtol=1e-6, atol=1e-6,
                               what=_WHAT[_name]))


def describe(name: str) -> str:
    """One line on the stored study ``name``: what it holds, and what recomputing it cost
    (its header's CPU-s, CPU class and date)."""
    if name not in NAMES:
        raise ValueError(f"name must be one of {NAMES}; got {name!r}")
    h = store.header_of(name, json.loads(_FILES[name].read_text(encoding="utf-8")))
    cost = "an unmeasured time" if h.cost_cpu_s is None else f"{h.cost_cpu_s:.0f} CPU-s"
    return (f"{name}: {_WHAT[name]}; REFRESH = True recomputes it here ({cost} when it was "
            f"stored, on an {h.cpu_class} machine, {h.date[:10]}; "
            f"`{store.REFRESH.format(name=name)}` rewrites it)")


def load(name: str, *, refresh: bool = False, executor: Any = None) -> dict[str, Any]:
    """The stored study ``name`` decoded (its results as the library's objects), after
    :func:`gyrolib.store.check` (a stale one raises :class:`gyrolib.store.StaleStudy` with
    its name and refresh command); with ``refresh``, recomputed here on ``executor``
    instead, and nothing written."""
    if name not in NAMES:
        raise ValueError(f"name must be one of {NAMES}; got {name!r}")
    if refresh:
        return decode(_COMPUTE[name](executor, None))
    store.check(name)
    data = json.loads(_FILES[name].read_text(encoding="utf-8"))
    return decode({k: x for k, x in data.items() if k != store.HEADER_KEY})
