"""Paper GC, Figure 3: covariance analysis of the 10-state filter (σ of each state's
estimate over time), the time to reach a σ level, and sweeps over the model's parameters.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrolib import _validation as v
from gyrolib._repr import compact_repr
from gyrolib.filtering.covariance import covariance_fast, covariance_reference
from gyrolib.gc.model.discretization import (
    DISCRETIZATIONS,
    kept_discretization,
    steps_in,
)
from gyrolib.gc.model.instrument import augmented_index
from gyrolib.gc.model.params import STATE_NAMES, GyrocompassParams, check_params

__all__ = [
    "CovarianceAnalysis",
    "CovarianceSweep",
    "covariance_analysis",
    "parameter_grid",
    "sweep_covariance",
    "sweep_sigma_gc",
    "time_to_sigma",
]


# Covariance analysis (Figure 3) ------------------------------------------------------------
@compact_repr
@dataclass(frozen=True)
class CovarianceAnalysis:
    """Posterior covariance of the filter: variances at every step, full ``P`` at
    ``t_stored``, of the states ``names`` (Eq. (8)'s, then the instrument constants that are
    ON, :func:`gyrolib.gc.state_names`).  ``std(name)`` is in SI units (rad, rad/s, m/s²,
    m/s³, rad/s²; the constants in theirs)."""

    params: GyrocompassParams
    t: np.ndarray
    var: np.ndarray
    t_stored: np.ndarray
    P_stored: np.ndarray
    names: tuple[str, ...] = STATE_NAMES

    def __post_init__(self) -> None:
        check_params(self.params)
        if not isinstance(self.names, tuple) or self.names[:len(STATE_NAMES)] != STATE_NAMES:
            raise ValueError("names must be a tuple that starts with STATE_NAMES")
        n = len(self.names)
        nt = v.check_ndarray("t", self.t, ndim=1).size
        v.check_ndarray("var", self.var, shape=(nt, n))
        ns = v.check_ndarray("t_stored", self.t_stored, ndim=1).size
        v.check_ndarray("P_stored", self.P_stored, shape=(ns, n, n))

    def std(self, name: str) -> NDArray[np.float64]:
        """Standard deviation of ``name``'s estimate at every step (SI units).

        Examples
        --------
        >>> from gyrolib import gc
        >>> res = gc.covariance_analysis(gc.GyrocompassParams(), 0.01)
        >>> res.std("omega_gc").shape
        (11,)
        """
        return np.sqrt(np.clip(self.var[:, augmented_index(self.names, name)], 0.0, None))

    def std_at(self, name: str, time: float) -> float:
        """Standard deviation at the step nearest to ``time`` (s).

        Examples
        --------
        >>> from gyrolib import gc
        >>> from gyrolib.units import from_si
        >>> res = gc.covariance_analysis(gc.GyrocompassParams(), 2.0)
        >>> f"{from_si(res.std_at('omega_gc', 2.0), 'arcsec_paper/s'):.4f}"
        '0.0281'
        """
        time = v.check_in_range("time", time, 0.0, float(self.t[-1]))
        return float(self.std(name)[round(time / self.params.dt)])

    def final_std(self, name: str = "omega_gc") -> float:
        """Standard deviation of ``name``'s estimate at the end of the run (SI units).

        Examples
        --------
        >>> from gyrolib import gc
        >>> from gyrolib.units import from_si
        >>> res = gc.covariance_analysis(gc.GyrocompassParams(), 1.0)
        >>> f"{from_si(res.final_std('omega_gc'), 'arcsec_paper/s'):.3f}"  # ″/s after 1 s
        '0.071'
        """
        return float(self.std(name)[-1])


def _check_covariance_matrix(name: str, P: np.ndarray) -> None:
    """``P`` (symmetric, diagonal >= 0) positive semi-definite, judged on its correlation
    form so that variances many orders of magnitude apart are treated alike."""
    d = np.sqrt(np.diag(P))
    nz = d > 0.0
    if np.any(P[~nz] != 0.0):
        raise ValueError(f"{name} must be positive semi-definite (a zero variance needs a "
                         "zero row)")
    if np.any(nz):
        C = P[np.ix_(nz, nz)] / np.outer(d[nz], d[nz])
        if np.linalg.eigvalsh(0.5 * (C + C.T))[0] < -1e-9:
            raise ValueError(f"{name} must be positive semi-definite (a covariance)")


def default_store_every(n_steps: int) -> int:
    return max(1, n_steps // 1000)


def covariance_analysis(params: GyrocompassParams, t_end: float = 100.0, *,
                        store_every: int | None = None, method: str = "fast",
                        P0: ArrayLike | None = None,
                        discretization: str = "van_loan") -> CovarianceAnalysis:
    """Covariance analysis of the discrete Kalman filter of paper GC (its Figure 3).

    Runs the filter's covariance recursion (prediction ``P⁻ = Φ P Φᵀ + Qd``, Joseph-form
    update with the angle sensor and both inclinometers, Eq. (8) of paper GC) over
    ``[0, t_end]``.  The instrument constants that are ON for ``params``
    (:func:`gyrolib.gc.instrument_model`: a prior ``sigma_as_offset``, ``sigma_incl_bias``
    or ``sigma_hf_scale`` > 0) are appended to the state (constant, their prior variance in
    ``P(0)``, their readings ``H0 + β_n(t_k) H1`` at each sample); at the defaults there are
    none.

    Parameters
    ----------
    params : GyrocompassParams
        The model and its open choices (``shaping_p0``, ``measurement_noise``, …).
    t_end : float, default 100.0
        Length of the run (s), a positive multiple of ``params.dt``.
    store_every : int, optional
        Keep the full ``P`` every ``store_every`` steps (default: about 1000 of them).
    method : {"fast", "reference"}, default "fast"
        ``"fast"``: numba kernel on the affine discretization; ``"reference"``: plain numpy
        with a per-step discretization and batch Joseph updates (slow: tests, benchmarks).
    P0 : array_like of shape (n, n), optional
        Initial covariance (symmetric, positive semi-definite) of the ``n`` states
        :func:`gyrolib.gc.state_names`; default :func:`gyrolib.gc.initial_covariance` with
        the constants' prior variances appended (e.g. override to study a partly known
        N1…N4).
    discretization : {"van_loan", "euler"}, default "van_loan"
        How Eq. (8) becomes the discrete model (see :func:`gyrolib.gc.discretize`).

    Returns
    -------
    CovarianceAnalysis
        Variances of every state at every step, full ``P`` at ``t_stored``.

    Examples
    --------
    >>> from dataclasses import replace
    >>> from gyrolib import gc
    >>> from gyrolib.units import from_si
    >>> p = gc.GyrocompassParams()
    >>> for d in ("van_loan", "euler"):
    ...     res = gc.covariance_analysis(p, 2.0, discretization=d)
    ...     print(d, f"{from_si(res.final_std(), 'arcsec_paper/s'):.4f}")
    van_loan 0.0281
    euler 0.0281

    With a prior on the angle sensor's null offset, the offset is an 11th state:

    >>> res = gc.covariance_analysis(replace(p, sigma_as_offset=5e-6), 2.0)
    >>> res.names[10:], f"{res.final_std('angle_offset') / 5e-6:.3f}"
    (('angle_offset',), '0.120')
    """
    p = check_params(params)
    v.check_choice("method", method, ("fast", "reference"))
    v.check_choice("discretization", discretization, DISCRETIZATIONS)
    # the continuous model (with the instrument constants that are ON) built once and
    # discretized, kept per parameters: the claims' margins analyse the same model more
    # than once
    disc = kept_discretization(p, steps_in(p, t_end), discretization)
    cm = disc.continuous
    n = disc.model.n
    se = default_store_every(disc.n_steps) if store_every is None else store_every
    se = v.check_int("store_every", se, 1)
    if P0 is None:
        P0 = cm.P0.copy()
    else:
        P0 = v.check_array("P0", P0, shape=(n, n))
        if not np.allclose(P0, P0.T, rtol=1e-12, atol=0.0) or np.any(np.diag(P0) < 0):
            raise ValueError("P0 must be symmetric with a non-negative diagonal")
        _check_covariance_matrix("P0", P0)
    if method == "fast":
        run = covariance_fast(disc.model, P0, se)
    else:
        mdl = disc.model
        run = covariance_reference(
            None, P0, se, step_matrices=disc.exact_step, n_steps=disc.n_steps,
            H=mdl.H if mdl.H1 is None else mdl.h_matrix, R=np.diag(mdl.r))
    t = disc.t
    return CovarianceAnalysis(params=p, t=t, var=run.var, t_stored=t[::se].copy(),
                              P_stored=run.P_stored, names=disc.state_names)


def time_to_sigma(result: CovarianceAnalysis, name: str, level: float) -> float:
    """First time (s) at which ``std(name)`` falls to ``level`` (SI) and stays below it;
    ``nan`` if not reached within the analysed span.

    Parameters
    ----------
    result : CovarianceAnalysis
        A covariance analysis.
    name : str
        The state (:data:`gyrolib.gc.STATE_NAMES`).
    level : float
        The σ level in SI units (> 0).

    Returns
    -------
    float
        The time (s), linearly interpolated between steps; ``nan`` if not reached.

    Examples
    --------
    >>> from gyrolib import gc
    >>> from gyrolib.units import to_si
    >>> res = gc.covariance_analysis(gc.GyrocompassParams(), 10.0)
    >>> f"{gc.time_to_sigma(res, 'omega_gc', to_si(0.01, 'arcsec_paper/s')):.2f} s"
    '4.13 s'
    """
    if not isinstance(result, CovarianceAnalysis):
        raise TypeError("result must be a CovarianceAnalysis")
    level = v.check_positive("level", level)
    s = result.std(name)
    above = np.nonzero(s > level)[0]
    if above.size == 0:
        return 0.0
    last = above[-1]
    if last == s.size - 1:
        return float("nan")
    # linear interpolation between the last step above and the first below
    t0, t1, s0, s1 = result.t[last], result.t[last + 1], s[last], s[last + 1]
    return float(t0 + (s0 - level) / (s0 - s1) * (t1 - t0))


def sweep_sigma_gc(params: GyrocompassParams, field: str, values: ArrayLike,
                   t_end: float = 100.0) -> NDArray[np.float64]:
    """``σ_gc(t_end)`` (rad/s) with ``params.<field>`` set to each of ``values``.

    Parameters
    ----------
    params : GyrocompassParams
        The baseline.
    field : str
        A ``GyrocompassParams`` field.
    values : array_like
        1-D values of ``field``.
    t_end : float, default 100.0
        Length of each run (s).

    Returns
    -------
    ndarray
        σ of ω_gc at ``t_end`` (rad/s), one per value.

    Examples
    --------
    >>> from gyrolib import gc
    >>> from gyrolib.units import from_si
    >>> s = gc.sweep_sigma_gc(gc.GyrocompassParams(), "xi1", [0.5, 0.7], 2.0)
    >>> [f"{from_si(x, 'arcsec_paper/s'):.4f}" for x in s]
    ['0.0281', '0.0281']
    """
    p = check_params(params)
    v.check_str("field", field)
    if field not in GyrocompassParams.__dataclass_fields__:
        raise ValueError(f"field must be a GyrocompassParams field; got {field!r}")
    vals = v.check_array("values", values, ndim=1)
    out = np.empty(vals.size)
    for i, x in enumerate(vals):
        res = covariance_analysis(replace(p, **{field: float(x)}), t_end, store_every=10**9)
        out[i] = res.std("omega_gc")[-1]
    return out


# Sweeps over the open choices ---------------------------------------------------------------
def parameter_grid(**values: ArrayLike) -> list[dict[str, object]]:
    """Every combination of the given ``GyrocompassParams`` field values (cartesian product,
    the last field varying fastest), as a list of ``{field: value}`` cases.

    Examples
    --------
    >>> from gyrolib import gc
    >>> gc.parameter_grid(shaping_p0=("stationary", "zero"), dt=(1e-3,))
    [{'shaping_p0': 'stationary', 'dt': 0.001}, {'shaping_p0': 'zero', 'dt': 0.001}]
    """
    names = list(values)
    return [dict(zip(names, combo, strict=True))
            for combo in itertools.product(*(tuple(values[n]) for n in names))]


@compact_repr
@dataclass(frozen=True)
class CovarianceSweep:
    """One :class:`CovarianceAnalysis` per case (``{field: value}`` changes to ``params``)."""

    params: GyrocompassParams
    cases: tuple[dict[str, object], ...]
    analyses: tuple[CovarianceAnalysis, ...]

    def __post_init__(self) -> None:
        check_params(self.params)
        if len(self.cases) != len(self.analyses):
            raise ValueError(f"analyses must hold one CovarianceAnalysis per case "
                             f"({len(self.cases)}); got {len(self.analyses)}")

    def final_std(self, name: str = "omega_gc") -> NDArray[np.float64]:
        """σ of ``name`` at the end of each case's run (SI units), in the order of ``cases``.

        Examples
        --------
        >>> from gyrolib import gc
        >>> sw = gc.sweep_covariance(gc.GyrocompassParams(), [{}, {"xi1": 0.5}], 0.01)
        >>> sw.final_std().shape
        (2,)
        """
        return np.array([a.final_std(name) for a in self.analyses])


def sweep_covariance(params: GyrocompassParams, cases: object,
                     t_end: float = 100.0) -> CovarianceSweep:
    """Covariance analysis of paper GC's filter for each case of changes to ``params``.

    Parameters
    ----------
    params : GyrocompassParams
        The baseline.
    cases : sequence of dict
        Each a ``{field: value}`` mapping applied with ``dataclasses.replace`` (see
        :func:`parameter_grid` for a cartesian product).
    t_end : float, default 100.0
        Length of each run (s).

    Returns
    -------
    CovarianceSweep
        The analyses (full ``P`` stored only at the ends), in the order of ``cases``.

    Examples
    --------
    >>> from gyrolib import gc
    >>> from gyrolib.units import from_si
    >>> sw = gc.sweep_covariance(gc.GyrocompassParams(),
    ...                          gc.parameter_grid(shaping_p0=("stationary", "zero")), 10.0)
    >>> [f"{from_si(s, 'arcsec_paper/s'):.5f}" for s in sw.final_std()]
    ['0.00345', '0.00306']
    """
    p = check_params(params)
    if isinstance(cases, dict) or not all(isinstance(c, dict) for c in cases):
        raise TypeError("cases must be a sequence of {field: value} dicts")
    for c in cases:
        for field in c:
            if field not in GyrocompassParams.__dataclass_fields__:
                raise ValueError(f"cases must name GyrocompassParams fields; got {field!r}")
    variants = [replace(p, **c) for c in cases]       # each validated by __post_init__
    n_steps = round(v.check_positive("t_end", t_end) / p.dt)
    analyses = tuple(covariance_analysis(q, t_end, store_every=max(n_steps, 1))
                     for q in variants)
    return CovarianceSweep(params=p, cases=tuple(dict(c) for c in cases), analyses=analyses)
