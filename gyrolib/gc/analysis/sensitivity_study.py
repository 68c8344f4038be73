"""Paper GC: which input the verdicts on σ_gc(100 s) and on the speed claim are sensitive to
(Sobol' indices, :mod:`gyrolib.sensitivity`).

Outputs, both from :func:`gyrolib.gc.covariance_analysis` as the ledger computes them:

* ``sigma_gc_100s``: σ of the ω_gc estimate at 100 s (rad/s; Figure 3 of paper GC prints
  0.0011″/s);
* ``t_c``: the time (s) at which that σ falls to σ_c = 2·10⁻³″/s and stays below
  (:func:`gyrolib.gc.time_to_sigma` over the first 100 s, :func:`gyrolib.gc.time_to_level`
  up to ``t_max`` beyond; a point that has not crossed by ``t_max`` is recorded as
  ``t_max``, censored).

Inputs (:func:`sensitivity_inputs`): the shaping-filter parameters α1, ξ1, σ1² (Eq. (6)) and
α2, ξ2, σ2² (Eq. (7)), the sensor-noise intensities C_as and C_in (both inclinometers
together), the unbalance drift ω_ub and the prior σ of ψ, δ and γ.  A printed value varies
uniformly within ±10 %; a garbled one (the sensor intensities, whose unit the extraction
garbles) log-uniformly within a factor of 3 either way.  The open discrete choices
(``shaping_p0``, ``measurement_noise``, ``eq1_sign``, ``vertical_coupling``) are fixed by
``params``: each is a separate condition, never mixed into the sample.

The inputs the paper prints but the study holds fixed (:data:`FIXED_INPUTS`: I, H, f, Ω_v,
Ω_h and the prior σ of ω_gc, P(4,4)) are not sampled: they are the instrument's and the
site's values rather than uncertain modelling choices, and the committed study (N = 2048,
about an hour of CPU) is not rerun for them.  :func:`sensitivity_elasticities` gives
∂ ln y/∂ ln x of both outputs at the defaults for the sampled and the fixed inputs alike, so
that a ranking set by the ranges shows beside the indices.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import fields, replace
from typing import Final

import numpy as np
from numpy.typing import NDArray

from gyrolib import _validation as v
from gyrolib.gc.analysis.covariance import covariance_analysis, time_to_sigma
from gyrolib.gc.analysis.speed_claim import time_to_level
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
from gyrolib.units import to_si

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

#: σ_c = 2·10⁻³″/s (paper GC, ref. [2]), in rad/s; the ledger's level.
_LEVEL: Final[float] = float(to_si(2e-3, "arcsec_paper/s"))

#: How far t_c is looked for (s): the ledger's bound, half of ref. [2]'s 17 min.
_T_MAX: Final[float] = 0.5 * 17.0 * 60.0

#: Sample points per chunk: about 3 s of work at 0.3 s a point, so that handing a chunk to a
#: worker (milliseconds) costs well under 5 % and the last chunk leaves a worker idle briefly.
_CHUNK: Final[int] = 8


def sensitivity_inputs(params: GyrocompassParams | None = None) -> tuple[SobolInput, ...]:
    """The study's uncertain inputs with their ranges, centred on ``params`` (default: the
    paper's values).

    Printed values (±10 %, uniform): α1, ξ1, σ1² (paper GC after Eq. (6)), α2, ξ2, σ2²
    (after Eq. (7); σ2² taken from its ref. [2]), ω_ub, the prior σ of ψ, δ and γ (its
    parameter table).  Garbled (a factor of 3 either way, log-uniform): C_as and C_in, the
    sensor-noise intensities, printed as "rad² [·s]" and m²/s³ with the extraction losing
    part of the unit and the paper not saying whether they are intensities or variances.

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
    >>> c = gc.sensitivity_inputs()[6]
    >>> c.name, c.distribution, f"{c.high / c.nominal:.0f}"
    ('C_as', 'loguniform', '3')
    """
    p = GyrocompassParams() if params is None else check_params(params)
    pr, un = SobolInput.printed, SobolInput.unstated
    eq6, eq7 = "printed after Eq. (6)", "printed after Eq. (7)"
    table = "printed (parameter table)"
    garbled = ("garbled: unit partly lost ('rad² [·s]'); intensity or variance not said")
    return (
        pr("alpha1", "α1", p.alpha1, reading=eq6),
        pr("xi1", "ξ1", p.xi1, reading=eq6),
        pr("sigma1_sq", "σ1²", p.sigma1_sq, reading=eq6),
        pr("alpha2", "α2", p.alpha2, reading=eq7),
        pr("xi2", "ξ2", p.xi2, reading=eq7),
        pr("sigma2_sq", "σ2²", p.sigma2_sq, reading="printed after Eq. (7), from ref. [2]"),
        un("C_as", "C_as", p.C_as, reading=garbled),
        un("C_incl", "C_in", p.C_incl_y, reading="garbled: continuous intensity (m²/s³), "
           "intensity or variance not said; both inclinometers together"),
        pr("omega_ub", "ω_ub", p.omega_ub, reading="printed after Eq. (6), from ref. [6]"),
        pr("sigma_psi0", "σ_ψ(0)", p.sigma_psi0, reading=table),
        pr("sigma_delta0", "σ_δ(0)", p.sigma_delta0, reading=table),
        pr("sigma_gamma0", "σ_γ(0)", p.sigma_gamma0, reading=table),
    )


#: Inputs the paper prints and the study holds fixed, with their symbols: the float's moment
#: of inertia, angular momentum and friction, the Earth-rate components at the site, and the
#: prior σ of ω_gc (P(4,4)).
FIXED_INPUTS: Final[dict[str, str]] = {
    "I": "I", "H": "H", "f": "f", "Omega_v": "Ω_v", "Omega_h": "Ω_h", "sigma_gc0": "σ_ω(0)",
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
    nominal = {x.name: x.nominal for x in sensitivity_inputs(p)}
    if fixed:
        nominal.update({name: float(getattr(p, name)) for name in FIXED_INPUTS})

    def evaluate(**x: float) -> tuple[float, float]:
        return sensitivity_outputs(_at(p, tuple(x), np.array(list(x.values()))))
    return elasticities(nominal, evaluate, SENSITIVITY_OUTPUTS)


def _at(base: GyrocompassParams, names: tuple[str, ...],
        row: NDArray[np.float64]) -> GyrocompassParams:
    """``base`` with the sampled inputs set (``C_incl`` sets both inclinometers)."""
    changes: dict[str, float] = {}
    for name, x in zip(names, row, strict=True):
        if name == "C_incl":
            changes["C_incl_y"] = changes["C_incl_z"] = float(x)
        else:
            changes[name] = float(x)
    return replace(base, **changes)


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
    skip = set(sampled) | ({"C_incl_y", "C_incl_z"} if "C_incl" in sampled else set())
    return {f.name: getattr(p, f.name) for f in fields(p)
            if f.name in _CONDITIONS
            or (f.name not in skip and getattr(p, f.name) != getattr(default, f.name))}


def sensitivity(n: int, seed: int = 0, executor: object = None, *,
                params: GyrocompassParams | None = None, t_end: float = 100.0,
                level: float = _LEVEL, t_max: float = _T_MAX, chunk_size: int = _CHUNK,
                progress: Callable[[int], None] | None = None,
                second_order: bool = True,
                previous: SensitivityResult | None = None) -> SensitivityResult:
    """Sobol' indices of σ_gc(100 s) and of t_c with respect to the twelve inputs of
    :func:`sensitivity_inputs` (paper GC, Figure 3 and its Conclusion).

    ``n (2·12 + 2) = 26 n`` covariance analyses of ``t_end`` seconds each (a few tenths of
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
    ((52, 2), ('sigma_gc_100s', 't_c'))
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
