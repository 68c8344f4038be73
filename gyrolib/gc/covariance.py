"""Paper GC, Figure 3: covariance analysis of the 10-state filter (σ of each state's
estimate over time), the time to reach a σ level, and sweeps over the model's parameters.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from gyrolib import _validation as v
from gyrolib.filtering.covariance import covariance_fast, covariance_reference
from gyrolib.gc.discretization import N, _check_params, discretize
from gyrolib.gc.params import GyrocompassParams, state_index
from gyrolib.gc.state_space import (
    initial_covariance,
)

__all__ = [
    "CovarianceAnalysis",
    "covariance_analysis",
    "sweep_sigma_gc",
    "time_to_sigma",
]


# Covariance analysis (Figure 3) ------------------------------------------------------------
@dataclass(frozen=True)
class CovarianceAnalysis:
    """Posterior covariance of the filter: variances at every step, full ``P`` at
    ``t_stored``.  ``std(name)`` is in SI units (rad, rad/s, m/s², m/s³, rad/s²)."""

    params: GyrocompassParams
    t: np.ndarray
    var: np.ndarray
    t_stored: np.ndarray
    P_stored: np.ndarray

    def __post_init__(self) -> None:
        _check_params(self.params)
        nt = v.check_ndarray("t", self.t, ndim=1).size
        v.check_ndarray("var", self.var, shape=(nt, N))
        ns = v.check_ndarray("t_stored", self.t_stored, ndim=1).size
        v.check_ndarray("P_stored", self.P_stored, shape=(ns, N, N))

    def std(self, name: str) -> np.ndarray:
        return np.sqrt(np.clip(self.var[:, state_index(name)], 0.0, None))

    def std_at(self, name: str, time: float) -> float:
        """Standard deviation at the step nearest to ``time`` (s)."""
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


def _default_store_every(n_steps: int) -> int:
    return max(1, n_steps // 1000)


def covariance_analysis(params: GyrocompassParams, t_end: float = 100.0, *,
                        store_every: int | None = None, method: str = "fast",
                        P0: object | None = None) -> CovarianceAnalysis:
    """Covariance analysis of the discrete Kalman filter of paper GC (Figure 3).

    ``method="fast"``: numba kernel on the affine discretization; ``"reference"``: plain
    numpy with an exact per-step Van Loan exponential and batch Joseph updates (slow: for
    tests and benchmarks).  ``store_every`` (default: about 1000 stored ``P``) sets the
    decimation of the full covariances.  ``P0`` (10×10, symmetric) overrides
    :func:`gyrolib.gc.initial_covariance` (e.g. to study a partly known N1…N4).
    """
    p = _check_params(params)
    v.check_choice("method", method, ("fast", "reference"))
    disc = discretize(p, t_end)
    se = _default_store_every(disc.n_steps) if store_every is None else store_every
    se = v.check_int("store_every", se, 1)
    if P0 is None:
        P0 = initial_covariance(p)
    else:
        P0 = v.check_array("P0", P0, shape=(N, N))
        if not np.allclose(P0, P0.T, rtol=1e-12, atol=0.0) or np.any(np.diag(P0) < 0):
            raise ValueError("P0 must be symmetric with a non-negative diagonal")
        _check_covariance_matrix("P0", P0)
    if method == "fast":
        run = covariance_fast(disc.model, P0, se)
    else:
        run = covariance_reference(
            None, P0, se, step_matrices=disc.exact_step, n_steps=disc.n_steps,
            H=disc.model.H, R=np.diag(disc.model.r))
    t = disc.t
    return CovarianceAnalysis(params=p, t=t, var=run.var, t_stored=t[::se].copy(),
                              P_stored=run.P_stored)


def time_to_sigma(result: CovarianceAnalysis, name: str, level: float) -> float:
    """First time (s) at which ``std(name)`` falls to ``level`` (SI) and stays below it;
    ``nan`` if not reached within the analysed span."""
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


def sweep_sigma_gc(params: GyrocompassParams, field: str, values: object,
                   t_end: float = 100.0) -> np.ndarray:
    """``σ_gc(t_end)`` (rad/s) with ``params.<field>`` set to each of ``values``."""
    p = _check_params(params)
    v.check_str("field", field)
    if field not in GyrocompassParams.__dataclass_fields__:
        raise ValueError(f"field must be a GyrocompassParams field; got {field!r}")
    vals = v.check_array("values", values, ndim=1)
    out = np.empty(vals.size)
    for i, x in enumerate(vals):
        res = covariance_analysis(replace(p, **{field: float(x)}), t_end, store_every=10**9)
        out[i] = res.std("omega_gc")[-1]
    return out
