"""Paper GC: which input the verdicts on σ_gc(100 s) and on the speed claim are sensitive to
(Sobol' indices, :mod:`gyrolib.sensitivity`).

Outputs, both from :func:`gyrolib.gc.covariance_analysis` as the ledger computes them:

* ``sigma_gc_100s``: σ of the ω_gc estimate at 100 s (rad/s; Figure 3 of paper GC prints
  0.0011″/s);
* ``t_c``: the time (s) at which that σ falls to σ_c = 2·10⁻³″/s and stays below
  (:func:`gyrolib.gc.time_to_sigma` over the first 100 s, :func:`gyrolib.gc.time_to_level`
  up to ``t_max`` beyond; a point that has not crossed by ``t_max`` is recorded as
  ``t_max``, censored).

Inputs (:func:`sensitivity_inputs`): paper GC's *uncertain* rows of the table of inputs
(:mod:`gyrolib.inputs`) — the shaping-filter parameters α1, ξ1, σ1² (Eq. (6)) and α2, ξ2, σ2²
(Eq. (7)), the unbalance drift ω_ub, the sensor-noise intensities C_as and C_in (both
inclinometers together), and the instrument errors the paper's model leaves at zero (κ,
σ_off, σ_b, ε_t) — each over its row's range around ``params`` (a factor of the value for a
scale-type row, the row's absolute range otherwise) on its row's scale: no range is typed
here.  The *operating* rows (the filter's priors) are the user's choice, not uncertain: they
are held at ``params`` and get elasticities only.  The readings (``shaping_p0``,
``measurement_noise``, ``eq1_sign``, ``vertical_coupling``) are fixed by ``params``: each is
a separate condition, never mixed into the sample.  σ_c and the bound of t_c are the printed
levels of :mod:`gyrolib.levels`, the ledger's.

The inputs the paper prints and the study holds fixed (:data:`FIXED_INPUTS`: I, H, f, Ω_v,
Ω_h and the filter's priors) are not sampled: they are the instrument's and the site's values
or the user's choices rather than uncertain modelling choices.
:func:`sensitivity_elasticities` gives ∂ ln y/∂ ln x of both outputs at the defaults for the
sampled inputs with a non-zero value and the fixed inputs alike, so that a ranking set by the
ranges shows beside the indices.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import fields, replace
from typing import Final

import numpy as np
from numpy.typing import NDArray

from gyrolib import _validation as v
from gyrolib import input_rows, levels
from gyrolib.gc.analysis.covariance import covariance_analysis, time_to_sigma
from gyrolib.gc.analysis.speed_claim import time_to_level
from gyrolib.gc.model import inputs as model_inputs
from gyrolib.gc.model.params import GyrocompassParams, check_params
from gyrolib.sensitivity import (
    Elasticities,
    Recheck,
    SensitivityResult,
    SobolInput,
    elasticities,
    recheck,
    run_study,
)

__all__ = [
    "FIXED_INPUTS",
    "SENSITIVITY_OUTPUTS",
    "recheck_sensitivity",
    "sensitivity",
    "sensitivity_elasticities",
    "sensitivity_inputs",
    "sensitivity_outputs",
]

#: The study's outputs and their (SI) units.
SENSITIVITY_OUTPUTS: Final[tuple[str, ...]] = ("sigma_gc_100s", "t_c")
_UNITS: Final[tuple[str, ...]] = ("rad/s", "s")

#: The discrete choices a study holds fixed (its condition).
_CONDITIONS: Final[tuple[str, ...]] = ("shaping_p0", "measurement_noise", "vertical_coupling",
                                       "eq1_sign")

#: σ_c (rad/s) and how far t_c is looked for (s): the ledger's level and bound.
_LEVEL: Final[float] = levels.SIGMA_C
_T_MAX: Final[float] = levels.T_BOUND

#: Sample points per chunk: about 3 s of work at 0.3 s a point, so that handing a chunk to a
#: worker (milliseconds) costs well under 5 % and the last chunk leaves a worker idle briefly.
_CHUNK: Final[int] = 8


def _rows() -> tuple:
    """Paper GC's uncertain rows of the table of inputs (:mod:`gyrolib.gc.model.inputs`)."""
    return model_inputs.rows(prefix="gc.", kind="uncertain")


def sensitivity_inputs(params: GyrocompassParams | None = None) -> tuple[SobolInput, ...]:
    """The study's uncertain inputs: paper GC's uncertain rows of the table of inputs, each
    over its row's range around its value in ``params`` (default: the paper's values).

    A scale-type row's range is a factor of the value (α1, σ1², α2, σ2², ω_ub, C_as, C_in:
    a decade either way, log-uniform); ξ1, ξ2 and the instrument errors whose reference is
    zero (κ, σ_off, σ_b, ε_t) have the row's absolute range, uniform.  Each input is named
    by its row without the ``gc.`` prefix (``"C_incl"`` sets both inclinometers).

    Parameters
    ----------
    params : GyrocompassParams, optional
        The centre of the ranges.

    Returns
    -------
    tuple of SobolInput

    Examples
    --------
    >>> from gyrolib import gc
    >>> [x.symbol for x in gc.sensitivity_inputs()][:3]
    ['α1', 'ξ1', 'σ1²']
    >>> c = gc.sensitivity_inputs()[7]
    >>> c.name, c.distribution, f"{c.high / c.nominal:.0f}"
    ('C_as', 'loguniform', '10')
    """
    p = GyrocompassParams() if params is None else check_params(params)
    objs = {"GyrocompassParams": p}
    return tuple(r.sobol_input(float(input_rows.value_of(objs, r)),
                               name=r.name.removeprefix("gc."))
                 for r in _rows())


#: Inputs the paper prints and the study holds fixed, with their symbols: the float's moment
#: of inertia, angular momentum and friction, the Earth-rate components at the site, and the
#: filter's priors (the table's operating rows: P(4,4), ψ, δ, γ).
FIXED_INPUTS: Final[dict[str, str]] = {
    "I": "I", "H": "H", "f": "f", "Omega_v": "Ω_v", "Omega_h": "Ω_h", "sigma_gc0": "σ_ω(0)",
    "sigma_psi0": "σ_ψ(0)", "sigma_delta0": "σ_δ(0)", "sigma_gamma0": "σ_γ(0)",
}


def sensitivity_elasticities(params: GyrocompassParams | None = None, *,
                             fixed: bool = True) -> Elasticities:
    """∂ ln y/∂ ln x of σ_gc(100 s) and t_c at ``params`` for every sampled input of
    :func:`sensitivity_inputs` and, with ``fixed``, for the printed inputs the study holds
    fixed (:data:`FIXED_INPUTS`); central differences of ±1 %, two covariance analyses per
    input.

    Parameters
    ----------
    params : GyrocompassParams, optional
        The defaults (default: the paper's values).
    fixed : bool, default True
        Include :data:`FIXED_INPUTS`.

    Returns
    -------
    gyrolib.sensitivity.Elasticities

    Examples
    --------
    >>> from gyrolib import gc
    >>> e = gc.sensitivity_elasticities(fixed=False)
    >>> f"{e.of('t_c', 'C_as'):.2f}", f"{e.of('t_c', 'sigma1_sq'):.2f}"
    ('0.17', '0.71')
    """
    p = GyrocompassParams() if params is None else check_params(params)
    v.check_bool("fixed", fixed)
    nominal = {x.name: x.nominal for x in sensitivity_inputs(p) if x.nominal != 0.0}
    if fixed:
        nominal.update({name: float(getattr(p, name)) for name in FIXED_INPUTS})

    def evaluate(**x: float) -> tuple[float, float]:
        return sensitivity_outputs(_at(p, tuple(x), np.array(list(x.values()))))
    return elasticities(nominal, evaluate, SENSITIVITY_OUTPUTS)


def _at(base: GyrocompassParams, names: tuple[str, ...],
        row: NDArray[np.float64]) -> GyrocompassParams:
    """``base`` with the inputs set: a row of the table by its rule (``C_incl`` sets both
    inclinometers), a fixed input (:data:`FIXED_INPUTS`) by its field."""
    by_row = {r.name.removeprefix("gc."): r.name for r in _rows()}
    changes = {by_row[n]: float(x) for n, x in zip(names, row, strict=True) if n in by_row}
    p = input_rows.apply(model_inputs.ROWS, {"GyrocompassParams": base},
                         changes)["GyrocompassParams"]
    return replace(p, **{n: float(x) for n, x in zip(names, row, strict=True)
                         if n not in by_row})


def sensitivity_outputs(params: GyrocompassParams, *, t_end: float = 100.0,
                        level: float = _LEVEL, t_max: float = _T_MAX) -> tuple[float, float]:
    """The study's two outputs for one model: σ_gc(``t_end``) (rad/s) and t_c (s).

    The same calls as the ledger: one covariance analysis of ``t_end``
    (:func:`~gyrolib.gc.covariance_analysis`, :func:`~gyrolib.gc.time_to_sigma`), and
    :func:`~gyrolib.gc.time_to_level` up to ``t_max`` when σ has not reached ``level`` by
    then; ``t_max`` if not even by ``t_max`` (censored).

    Parameters
    ----------
    params : GyrocompassParams
        The model.
    t_end : float, default 100.0
        When σ_gc is read (s).
    level : float, optional
        σ_c (rad/s), default 2·10⁻³″/s.
    t_max : float, optional
        The longest time looked at for t_c (s), default 510 s.

    Returns
    -------
    tuple of float
        (σ_gc(t_end) in rad/s, t_c in s).

    Examples
    --------
    >>> from gyrolib import gc
    >>> from gyrolib.units import from_si
    >>> s, t = gc.sensitivity_outputs(gc.GyrocompassParams())
    >>> f"{from_si(s, 'arcsec_paper/s'):.5f} ″/s, {t:.0f} s"
    '0.00137 ″/s, 24 s'
    """
    p = check_params(params)
    t_end = v.check_positive("t_end", t_end)
    level = v.check_positive("level", level)
    t_max = v.check_positive("t_max", t_max)
    cov = covariance_analysis(p, t_end, store_every=10**9)
    t_c = time_to_sigma(cov, "omega_gc", level)
    if np.isnan(t_c) and t_max > t_end:
        t_c = time_to_level(p, level, t_max)
    return cov.final_std("omega_gc"), (t_max if np.isnan(t_c) else float(t_c))


def _evaluate(points: NDArray[np.float64], context: tuple) -> NDArray[np.float64]:
    """The outputs at each row of ``points`` (a chunk; module level: it is pickled)."""
    base, names, t_end, level, t_max = context
    return np.array([sensitivity_outputs(_at(base, names, row), t_end=t_end, level=level,
                                         t_max=t_max) for row in points]).reshape(-1, 2)


def _conditions(p: GyrocompassParams, sampled: tuple[str, ...]) -> dict[str, object]:
    """The fixed part of ``p``: the discrete choices, and every other field that differs
    from the paper's value (so that the condition can be rebuilt)."""
    default = GyrocompassParams()
    skip = {f for r in _rows() if r.name.removeprefix("gc.") in sampled for f in r.fields}
    return {f.name: getattr(p, f.name) for f in fields(p)
            if f.name in _CONDITIONS
            or (f.name not in skip and getattr(p, f.name) != getattr(default, f.name))}


def sensitivity(n: int, seed: int = 0, executor: object = None, *,
                params: GyrocompassParams | None = None, t_end: float = 100.0,
                level: float = _LEVEL, t_max: float = _T_MAX, chunk_size: int = _CHUNK,
                progress: Callable[[int], None] | None = None,
                second_order: bool = True,
                previous: SensitivityResult | None = None) -> SensitivityResult:
    """Sobol' indices of σ_gc(100 s) and of t_c with respect to the thirteen inputs of
    :func:`sensitivity_inputs` (paper GC, Figure 3 and its Conclusion).

    ``n (2·13 + 2) = 28 n`` covariance analyses of ``t_end`` seconds each (a few tenths of
    a second apiece), in chunks of ``chunk_size`` points on ``executor``.

    Parameters
    ----------
    n : int
        Base sample size, a power of 2.
    seed : int, default 0
        Seed of the sample's scrambling and of the bootstrap intervals.
    executor : concurrent.futures.Executor, optional
        Where the chunks run (``None``: in this process); e.g.
        ``dask.distributed.Client(...).get_executor()``.  The indices do not depend on it.
    params : GyrocompassParams, optional
        The condition: the discrete choices and the fixed parameters (default: the book's
        baseline); the ranges are centred on its values.
    t_end : float, default 100.0
        When σ_gc is read (s).
    level, t_max : float, optional
        σ_c (rad/s, default 2·10⁻³″/s) and the longest time looked at for t_c (s, default
        510 s, the ledger's bound).
    chunk_size : int, default 8
        Sample points per chunk.
    progress : callable, optional
        Called with the number of points of each finished chunk.
    second_order : bool, default True
        Also estimate the second-order indices (the sample grows from ``n (D + 2)`` to
        ``n (2D + 2)`` points).
    previous : SensitivityResult, optional
        The same study with a smaller ``n``, whose points are reused (see
        :func:`gyrolib.sensitivity.run_study`).

    Returns
    -------
    SensitivityResult
        Outputs ``"sigma_gc_100s"`` (rad/s) and ``"t_c"`` (s).

    Examples
    --------
    A tiny, fast study (2 base points, 2-s analyses, t_c to a coarse level):

    >>> from gyrolib import gc
    >>> from gyrolib.units import to_si
    >>> r = gc.sensitivity(2, seed=0, t_end=2.0, t_max=2.0, level=to_si(0.05, "arcsec_paper/s"))
    >>> r.values.shape, r.outputs
    ((56, 2), ('sigma_gc_100s', 't_c'))
    """
    p = GyrocompassParams() if params is None else check_params(params)
    inputs = sensitivity_inputs(p)
    names = tuple(x.name for x in inputs)
    t_end = v.check_positive("t_end", t_end)
    level = v.check_positive("level", level)
    t_max = v.check_positive("t_max", t_max)
    return run_study("gc", inputs, SENSITIVITY_OUTPUTS, _UNITS, _evaluate,
                     (p, names, t_end, level, t_max), n, seed, executor=executor,
                     chunk_size=chunk_size, progress=progress,
                     second_order=second_order, previous=previous,
                     conditions=_conditions(p, names),
                     settings={"t_end": t_end, "level": level, "t_max": t_max})


def recheck_sensitivity(result: SensitivityResult, k: int = 5, seed: int = 0) -> Recheck:
    """Compute ``k`` points of a stored GC study again (rows drawn with ``seed``): the
    condition is rebuilt from ``result.conditions``, the sample from ``n`` and ``seed``.

    Examples
    --------
    >>> from gyrolib import gc
    >>> from gyrolib.units import to_si
    >>> r = gc.sensitivity(2, seed=0, t_end=2.0, t_max=2.0, level=to_si(0.05, "arcsec_paper/s"))
    >>> gc.recheck_sensitivity(r, k=2).max_rel_diff < 1e-12
    True
    """
    v.check_instance("result", result, SensitivityResult)
    if result.model != "gc":
        raise ValueError(f"result must be a GC study (model 'gc'); got {result.model!r}")
    base = GyrocompassParams(**dict(result.conditions))
    s = result.settings
    context = (base, result.input_names, float(s["t_end"]), float(s["level"]),
               float(s["t_max"]))
    return recheck(result, _evaluate, context, k=k, seed=seed)
