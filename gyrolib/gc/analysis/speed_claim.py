"""Paper GC, its Conclusion and the text after Figure 3: the claims, computed.

* "More than 50 % faster" than ref. [2] (17 min): the time at which the filter's σ of ω_gc
  crosses the required accuracy σ_c = 2·10⁻³″/s, over a grid of shaping-filter parameters
  (:func:`speed_claim_map`), and the factor on one parameter at which that time reaches a
  bound (:func:`claim_boundary`);
* "the same trend when the parameters of the shaping filters vary widely": one parameter at
  a time scaled over two decades (:func:`shaping_sweep`).

Each runs the covariance recursion of :func:`gyrolib.gc.covariance_analysis` (the same
discretization and numba kernel, so the same numbers); nothing here is a threshold typed in:
the level and the bound are arguments (the book derives them from the paper's printed
numbers in :mod:`gyrolib.book.ledger.gc`).

Speed.  The time to a level is found by running the recursion in chunks of
:data:`_CHUNK` steps and stopping at the first step at which σ of ω_gc is at or below the
level.  That first crossing is also the last: ω_gc is a constant state (no process noise, an
identity row of Φ), so its posterior variance is the variance of one random variable given
ever more measurements, which never increases.  The 100-s discretization is extended to
``t_max`` only when σ has not crossed by then, and the run continues from where it stopped
(the longer discretization starts with the same steps), so nothing is computed twice.  The
grid points are independent: ``executor=`` (any :class:`concurrent.futures.Executor`; the
numba kernel releases the GIL, so threads use every core) runs them concurrently, with the
same numbers whatever the executor.  Tolerance: the times agree with one whole
:func:`gyrolib.gc.covariance_analysis` read by :func:`gyrolib.gc.time_to_sigma` to 1e-12
relative, and the results of any executor with those run here to 1e-12 relative
(``tests/gc/test_speed_claim.py``); on the book's map they were identical to the last bit.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from concurrent.futures import Executor
from dataclasses import dataclass, replace
from typing import Final

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrolib import _validation as v
from gyrolib._repr import compact_repr
from gyrolib.filtering.covariance import covariance_fast
from gyrolib.gc.analysis.covariance import covariance_analysis
from gyrolib.gc.model import inputs as model_inputs
from gyrolib.gc.model.discretization import kept_affine_model, steps_in
from gyrolib.gc.model.instrument import build_instrument_model
from gyrolib.gc.model.params import GyrocompassParams, check_params, state_index
from gyrolib.gc.model.state_space import (
    ContinuousModel,
    build_initial_covariance,
)

__all__ = [
    "SHAPING_FIELDS",
    "ClaimBoundary",
    "ShapingSweep",
    "SpeedClaimMap",
    "claim_boundary",
    "shaping_sweep",
    "speed_claim_map",
    "time_to_level",
]

#: The shaping-filter parameters of Eqs. (6), (7).
SHAPING_FIELDS: Final[tuple[str, ...]] = ("alpha1", "xi1", "sigma1_sq", "alpha2", "xi2",
                                          "sigma2_sq")

#: Horizon of a first, short discretization (s); longer only when σ has not crossed.
_FIRST_HORIZON: Final[float] = 100.0

#: A shorter horizon tried before the first (s): paper GC's σ crosses σ_c at about 24 s, so
#: most margins need no more; the steps are the longer discretizations' first ones, to the
#: bit (each step's ``Φ`` and ``Qd`` depend on its own nominal angle only).
_SHORT_HORIZON: Final[float] = 40.0

#: Steps of the covariance recursion run between two looks at σ of ω_gc.
_CHUNK: Final[int] = 5000


def _check_executor(executor: object) -> Executor | None:
    if executor is not None and not isinstance(executor, Executor):
        raise TypeError("executor must be a concurrent.futures.Executor or None; got "
                        f"{type(executor).__name__}")
    return executor


def _map(executor: Executor | None, fn: Callable, tasks: Iterable) -> list:
    """``fn`` over ``tasks`` in order: here, or on ``executor`` (results in task order)."""
    tasks = list(tasks)
    if executor is None:
        return [fn(*t) for t in tasks]
    return list(executor.map(fn, *zip(*tasks, strict=True))) if tasks else []


def _run_omega_gc(ps: tuple[GyrocompassParams, ...], t_first: float, t_max: float,
                  level: float | None, *, instruments: bool = False
                  ) -> list[tuple[float, float]]:
    """The covariance recursion of :func:`gyrolib.gc.covariance_analysis` in chunks, for
    models ``ps`` that differ at most in ``shaping_p0`` (the initial covariance of N1…N4,
    which does not enter the discretization: each discretization is computed once for all).
    ``instruments=True``: with the instrument constants that are ON appended to the state,
    as :func:`gyrolib.gc.covariance_analysis` appends them (else they are refused).

    With ``level``: per model ``(time, nan)``, the time (s) at which σ of ω_gc first falls
    to ``level`` (linear interpolation between the steps on either side, as
    :func:`gyrolib.gc.time_to_sigma`), 0 if it starts there, ``nan`` if not by ``t_max``;
    the discretization covers ``t_first`` first and ``t_max`` only when needed.  Without:
    ``(nan, σ(t_max))``.
    """
    p = ps[0]
    if not instruments and any(build_instrument_model(q).nb for q in ps):
        raise ValueError("params with instrument terms (sigma_hf_scale, sigma_as_offset, "
                         "sigma_incl_bias, ...) need gyrolib.gc.covariance_analysis: this fast "
                         "path runs paper GC's 10-state filter only")
    dt = p.dt
    i = state_index("omega_gc")
    n_max = steps_in(p, t_max)
    n_first = n_max if level is None else min(steps_in(p, t_first), n_max)
    # the horizons discretized in turn, each only when σ has not crossed within the last
    horizons = sorted({n_first, n_max} | ({min(round(_SHORT_HORIZON / dt), n_first)}
                                          if level is not None else set()))

    def model(n: int):
        return kept_affine_model(p, n, "van_loan")

    def run(q: GyrocompassParams) -> tuple[float, float]:
        P = (ContinuousModel.with_instruments(q).P0.copy() if instruments
             else build_initial_covariance(q))
        if level is not None and np.sqrt(max(P[i, i], 0.0)) <= level:
            return 0.0, float("nan")
        m = model(horizons[0])
        k = 0
        while True:
            if k == m.n_steps:
                if m.n_steps == n_max:
                    return float("nan"), float(np.sqrt(max(P[i, i], 0.0)))
                # the longer discretization: the same first steps
                m = model(min(n for n in horizons if n > m.n_steps))
            k1 = min(k + _CHUNK, m.n_steps)
            window = replace(m, seg=m.seg[k:k1], a=m.a[k:k1], b=m.b[k:k1],
                             h=None if m.h is None else m.h[k:k1])
            res = covariance_fast(window, P, store_every=k1 - k)
            P = res.P_stored[-1]
            if level is not None:
                s = np.sqrt(np.clip(res.var[:, i], 0.0, None))  # s[0]: step k
                below = np.nonzero(s[1:] <= level)[0]
                if below.size:
                    last = k + int(below[0])  # the last step above the level
                    t0, t1 = last * dt, (last + 1) * dt
                    s0, s1 = s[last - k], s[last - k + 1]
                    return float(t0 + (s0 - level) / (s0 - s1) * (t1 - t0)), float("nan")
            k = k1

    return [run(q) for q in ps]


def _check_field(name: str, field: object) -> str:
    field = v.check_str(name, field)
    if field not in GyrocompassParams.__dataclass_fields__:
        raise ValueError(f"{name} must be a GyrocompassParams field; got {field!r}")
    return field


def inputs_factor_grid(name: str, n: int = 3) -> tuple[float, ...]:
    """:func:`gyrolib.inputs.factor_grid` of paper GC's rows (:mod:`gyrolib.gc.model.inputs`)."""
    return model_inputs.factor_grid(name, n)


def _decade(field: str) -> tuple[float, ...]:
    """The default factors of ``field``: its row's range in the table of inputs when the row
    is a scale-type one, else the printed shaping parameters' (``gc.alpha1``'s)."""
    rows = [r for r in model_inputs.ROWS if field in r.fields
            and r.kind != "reading" and r.relative]
    return model_inputs.factor_grid(rows[0].name if rows else "gc.alpha1")


def _scaled(p: GyrocompassParams, field: str, factor: float) -> GyrocompassParams:
    """``p`` with ``field`` multiplied by ``factor`` (a damping ratio capped at 1)."""
    value = getattr(p, field) * factor
    if field in ("xi1", "xi2"):
        value = min(value, 1.0)
    return replace(p, **{field: value})


def time_to_level(params: GyrocompassParams, level: float, t_max: float) -> float:
    """Time (s) at which the filter's σ of ω_gc falls to ``level`` (rad/s) and stays below;
    ``nan`` if not within ``t_max`` (s).

    The covariance recursion of :func:`gyrolib.gc.covariance_analysis`, stopped at the first
    crossing (σ of the constant ω_gc never increases, so it stays below; the time is
    interpolated as by :func:`gyrolib.gc.time_to_sigma`); discretized over
    ``min(40 s, t_max)`` first, then ``min(100 s, t_max)`` and ``t_max``, each only when σ
    has not crossed by the end of the last (the discretization is shared with parameters
    that differ only in the measurement noise or the prior,
    :func:`gyrolib.gc.model.discretization.kept_affine_model`).
    Parameters with instrument terms run the same recursion with their constants appended
    to the state, as :func:`gyrolib.gc.covariance_analysis` appends them (the longer horizon
    continues the shorter one: its first steps are not run twice).

    Parameters
    ----------
    params : GyrocompassParams
        The model.
    level : float
        The σ level (rad/s), > 0.
    t_max : float
        The longest analysis (s), a multiple of ``params.dt``.

    Returns
    -------
    float
        The crossing time (s), or ``nan``.

    Examples
    --------
    >>> from gyrolib import gc
    >>> from gyrolib.units import to_si
    >>> t = gc.time_to_level(gc.GyrocompassParams(), to_si(2e-3, "arcsec_paper/s"), 100.0)
    >>> f"{t:.0f} s"
    '24 s'
    """
    p = check_params(params)
    level = v.check_positive("level", level)
    t_max = v.check_positive("t_max", t_max)
    steps_in(p, t_max)   # t_max a multiple of dt
    return _run_omega_gc((p,), _FIRST_HORIZON, t_max, level,
                         instruments=bool(build_instrument_model(p).nb))[0][0]


@compact_repr
@dataclass(frozen=True)
class SpeedClaimMap:
    """Time for σ of ω_gc to reach ``level`` over a grid of two parameters, for each reading
    of the unstated initial covariance of N1…N4 (``shaping_p0``).

    ``t_c[r, i, j]`` (s) is for reading ``readings[r]``, ``y_field`` scaled by
    ``y_factors[i]`` and ``x_field`` by ``x_factors[j]`` (``nan``: not reached within
    ``t_max``).  The claim holds where ``t_c < bound``.
    """

    params: GyrocompassParams
    x_field: str
    x_factors: NDArray[np.float64]
    y_field: str
    y_factors: NDArray[np.float64]
    readings: tuple[str, ...]
    t_c: NDArray[np.float64]
    level: float
    bound: float
    t_max: float

    def holds(self) -> NDArray[np.bool_]:
        """Where the claim holds: ``t_c < bound`` (``nan`` counts as not holding)."""
        with np.errstate(invalid="ignore"):
            return np.nan_to_num(self.t_c, nan=np.inf) < self.bound

    def largest_x_factor_holding(self, reading: str, y_factor: float = 1.0) -> float:
        """Largest grid factor on ``x_field`` at which the claim still holds for
        ``reading`` and the row ``y_factor`` (``nan`` if it holds nowhere)."""
        r = self.readings.index(v.check_choice("reading", reading, self.readings))
        i = int(np.argmin(np.abs(np.log(self.y_factors / y_factor))))
        ok = self.holds()[r, i]
        return float(self.x_factors[ok].max()) if np.any(ok) else float("nan")


def speed_claim_map(params: GyrocompassParams, level: float, bound: float, *,
                    x_field: str = "sigma1_sq", x_factors: ArrayLike | None = None,
                    y_field: str = "alpha1", y_factors: ArrayLike | None = None,
                    readings: tuple[str, ...] = ("stationary", "zero"),
                    t_max: float | None = None,
                    executor: Executor | None = None) -> SpeedClaimMap:
    """Where the speed claim of paper GC's Conclusion holds: the time for σ of ω_gc to reach
    ``level`` (the paper's σ_c) over a grid of two shaping-filter parameters, each scaled by
    its ``factors``, for each reading of the initial covariance of N1…N4.

    Parameters
    ----------
    params : GyrocompassParams
        The baseline model.
    level : float
        The σ level (rad/s), > 0.
    bound : float
        The time (s) the claim requires (the book's reading: half of ref. [2]'s 17 min).
    x_field, y_field : str
        Parameters scaled (damping ratios capped at 1).
    x_factors, y_factors : array_like, optional
        Factors (> 0) on the baseline values (default: each field's range in the table of
        inputs, :func:`gyrolib.inputs.factor_grid`; a decade either way).
    readings : tuple of str
        Values of ``shaping_p0``.
    t_max : float, optional
        Longest analysis (s); default ``1.25 bound`` rounded to a whole second.
    executor : concurrent.futures.Executor, optional
        Runs the grid points concurrently (e.g. a ``ThreadPoolExecutor`` with one worker per
        core); the numbers do not depend on it.

    Returns
    -------
    SpeedClaimMap
        ``t_c`` as :func:`time_to_level` gives it at each grid point.

    Examples
    --------
    >>> from gyrolib import gc
    >>> from gyrolib.units import to_si
    >>> m = gc.speed_claim_map(gc.GyrocompassParams(), to_si(2e-3, "arcsec_paper/s"), 510.0,
    ...                        x_factors=[1.0], y_factors=[1.0], t_max=100.0)
    >>> [f"{t:.0f}" for t in m.t_c[:, 0, 0]]   # stationary and zero P0 of N1…N4
    ['24', '15']
    """
    p = check_params(params)
    level = v.check_positive("level", level)
    bound = v.check_positive("bound", bound)
    xf = _check_field("x_field", x_field)
    yf = _check_field("y_field", y_field)
    xs = v.check_array("x_factors", _decade(xf) if x_factors is None else x_factors, ndim=1,
                       min_size=1)
    ys = v.check_array("y_factors", _decade(yf) if y_factors is None else y_factors, ndim=1,
                       min_size=1)
    for name, arr in (("x_factors", xs), ("y_factors", ys)):
        if np.any(arr <= 0.0):
            raise ValueError(f"{name} must be > 0 (factors on the baseline values)")
    if isinstance(readings, str) or not isinstance(readings, tuple) or not readings:
        raise TypeError("readings must be a non-empty tuple of shaping_p0 values")
    for r in readings:
        v.check_choice("readings", r, ("stationary", "zero"))
    t_max = float(round(1.25 * bound)) if t_max is None else v.check_positive("t_max", t_max)
    steps_in(p, t_max)
    executor = _check_executor(executor)
    # one task per grid point, for every reading (they share the discretization)
    tasks = [(tuple(_scaled(_scaled(replace(p, shaping_p0=r), yf, fy), xf, fx) for r in readings),
              _FIRST_HORIZON, t_max, level) for fy in ys for fx in xs]
    done = _map(executor, _run_omega_gc, tasks)
    t_c = np.array([[t for t, _ in point] for point in done]).T
    t_c = t_c.reshape(len(readings), ys.size, xs.size)
    return SpeedClaimMap(params=p, x_field=xf, x_factors=xs, y_field=yf, y_factors=ys,
                         readings=tuple(readings), t_c=t_c, level=level, bound=bound,
                         t_max=t_max)


@compact_repr
@dataclass(frozen=True)
class ClaimBoundary:
    """Where σ of ω_gc at ``bound`` equals ``level`` as ``field`` is scaled: ``factor``
    (log–log interpolation between the computed ``factors``; ``nan`` if ``level`` is not
    bracketed), with ``sigma`` (rad/s) the σ at ``bound`` for each factor.  Because σ only
    decreases with time, the claim (``t_c < bound``) holds exactly where
    ``sigma < level``."""

    field: str
    factors: NDArray[np.float64]
    sigma: NDArray[np.float64]
    level: float
    bound: float
    factor: float


def claim_boundary(params: GyrocompassParams, level: float, bound: float, *,
                   field: str = "sigma1_sq", factors: ArrayLike | None = None,
                   executor: Executor | None = None) -> ClaimBoundary:
    """The factor on ``field`` at which the time for σ of ω_gc to reach ``level`` equals
    ``bound``: σ at ``bound`` computed at each of ``factors`` and interpolated log–log.

    Parameters
    ----------
    params : GyrocompassParams
        The baseline model.
    level : float
        The σ level (rad/s).
    bound : float
        The time (s), a multiple of ``params.dt``.
    field : str
        The parameter scaled.
    factors : array_like, optional
        Increasing factors (> 0), at least two (default: 1 and the top of the field's range
        in the table of inputs).
    executor : concurrent.futures.Executor, optional
        Runs the factors concurrently; the numbers do not depend on it.

    Returns
    -------
    ClaimBoundary

    Examples
    --------
    >>> from gyrolib import gc
    >>> from gyrolib.units import to_si
    >>> b = gc.claim_boundary(gc.GyrocompassParams(), to_si(2e-3, "arcsec_paper/s"), 60.0,
    ...                       factors=[1.0, 3.0])
    >>> f"{b.factor:.2g}"   # σ1² × this reaches σ_c in exactly 60 s
    '1.9'
    """
    p = check_params(params)
    level = v.check_positive("level", level)
    bound = v.check_positive("bound", bound)
    field = _check_field("field", field)
    fs = v.check_array("factors", (1.0, _decade(field)[-1]) if factors is None else factors,
                       ndim=1, min_size=2)
    if np.any(fs <= 0.0) or np.any(np.diff(fs) <= 0.0):
        raise ValueError("factors must be > 0 and increasing")
    steps_in(p, bound)
    executor = _check_executor(executor)
    sigma = np.array([s for (_, s), in _map(executor, _run_omega_gc,
                                            [((_scaled(p, field, f),), bound, bound, None)
                                             for f in fs])])
    factor = float("nan")
    ls, lf = np.log(sigma / level), np.log(fs)
    for k in range(fs.size - 1):
        if ls[k] <= 0.0 < ls[k + 1] or ls[k] >= 0.0 > ls[k + 1]:
            factor = float(np.exp(lf[k] - ls[k] * (lf[k + 1] - lf[k]) / (ls[k + 1] - ls[k])))
            break
    return ClaimBoundary(field=field, factors=fs, sigma=sigma, level=level, bound=bound,
                         factor=factor)


@compact_repr
@dataclass(frozen=True)
class ShapingSweep:
    """One shaping-filter parameter at a time scaled: for ``fields[f]`` and ``factors[i]``,
    ``values[f, i]`` (the parameter's value), ``sigma_end[f, i]`` (σ of ω_gc at ``t_end``,
    rad/s), ``drop[f, i]`` (σ(``t_drop``)/σ(0), the "sharp drop") and ``monotone[f, i]``
    (σ never increases)."""

    params: GyrocompassParams
    fields: tuple[str, ...]
    factors: NDArray[np.float64]
    values: NDArray[np.float64]
    sigma_end: NDArray[np.float64]
    drop: NDArray[np.float64]
    monotone: NDArray[np.bool_]
    t_end: float
    t_drop: float

    def nominal(self, field: str) -> float:
        """The baseline value of ``field``."""
        return float(getattr(self.params, field))


def _sweep_case(q: GyrocompassParams, field: str, t_end: float,
                t_drop: float) -> tuple[float, float, float, bool]:
    """One case of :func:`shaping_sweep`: the value, σ(t_end), σ(t_drop)/σ(0), monotone."""
    res = covariance_analysis(q, t_end, store_every=10**9)
    s = res.std("omega_gc")
    return (float(getattr(q, field)), float(s[-1]), res.std_at("omega_gc", t_drop) / s[0],
            bool(np.all(np.diff(s) <= 1e-12 * s[:-1])))


def shaping_sweep(params: GyrocompassParams, t_end: float = 100.0, *,
                  fields: tuple[str, ...] = SHAPING_FIELDS,
                  factors: ArrayLike | None = None, t_drop: float = 2.0,
                  executor: Executor | None = None) -> ShapingSweep:
    """Paper GC's "same trend when the parameters of the shaping filters vary widely": each
    of ``fields`` scaled by each of ``factors`` (damping ratios capped at 1), the others at
    the baseline, and the covariance analysis rerun.

    Parameters
    ----------
    params : GyrocompassParams
        The baseline.
    t_end : float
        Length of each analysis (s).
    fields : tuple of str
        Parameters varied one at a time.
    factors : array_like, optional
        Factors (> 0) (default: the shaping parameters' range in the table of inputs, a
        decade either way, :func:`gyrolib.inputs.factor_grid`).
    t_drop : float
        Time (s, ``<= t_end``) of the "sharp drop" ratio σ(t_drop)/σ(0).
    executor : concurrent.futures.Executor, optional
        Runs the cases concurrently; the numbers do not depend on it.

    Returns
    -------
    ShapingSweep

    Examples
    --------
    >>> from gyrolib import gc
    >>> sw = gc.shaping_sweep(gc.GyrocompassParams(), 2.0, fields=("sigma1_sq",))
    >>> f"{sw.drop.max():.2f}"   # σ(2 s)/σ(0) at the worst of σ1² × (0.1, 1, 10)
    '0.19'
    """
    p = check_params(params)
    t_end = v.check_positive("t_end", t_end)
    t_drop = v.check_in_range("t_drop", t_drop, 0.0, t_end, low_open=True)
    if isinstance(fields, str) or not isinstance(fields, tuple) or not fields:
        raise TypeError("fields must be a non-empty tuple of GyrocompassParams fields")
    for f in fields:
        _check_field("fields", f)
    fs = v.check_array("factors", inputs_factor_grid("gc.alpha1") if factors is None
                       else factors, ndim=1, min_size=1)
    if np.any(fs <= 0.0):
        raise ValueError("factors must be > 0")
    steps_in(p, t_end)
    executor = _check_executor(executor)
    cases = _map(executor, _sweep_case, [(_scaled(p, field, f), field, t_end, t_drop)
                                         for field in fields for f in fs])
    shape = (len(fields), fs.size)
    values, sigma_end, drop, monotone = (np.array(col).reshape(shape)
                                         for col in zip(*cases, strict=True))
    return ShapingSweep(params=p, fields=tuple(fields), factors=fs, values=values,
                        sigma_end=sigma_end, drop=drop, monotone=monotone, t_end=t_end,
                        t_drop=t_drop)
