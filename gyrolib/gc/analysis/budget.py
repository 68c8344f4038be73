"""Paper GC: error budget of the ω_gc estimate — the variance at each time split by source
(initial conditions, vibration, random drift, sensor noises), propagated with the filter's
fixed gains.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final

import numpy as np

from gyrolib import _validation as v
from gyrolib._repr import compact_repr
from gyrolib.filtering.covariance import covariance_fast, propagate_fixed_gains
from gyrolib.gc.analysis.covariance import default_store_every
from gyrolib.gc.model.discretization import affine_qd, discretize_steps, steps_in
from gyrolib.gc.model.params import GyrocompassParams, check_params, state_index
from gyrolib.gc.model.state_space import ContinuousModel

__all__ = [
    "BUDGET_SOURCES",
    "ErrorBudget",
    "error_budget",
]


# Error budget --------------------------------------------------------------------------------
#: Sources of the error budget, in order.
BUDGET_SOURCES: Final[tuple[str, ...]] = (
    "initial dbeta", "initial dbeta_dot", "initial psi", "initial omega_gc", "initial delta",
    "initial gamma", "initial vibration state (N1, N2)", "initial random drift (N3, N4)",
    "vibration noise w1", "random drift noise w2", "angle sensor noise",
    "inclinometer y noise", "inclinometer z noise",
)


@compact_repr
@dataclass(frozen=True)
class ErrorBudget:
    """Variance of the ω_gc estimation error split by source: ``var[s, i]`` at ``t[i]``
    for source ``sources[s]``; ``total`` is the filter's own variance (the sources add up to
    it exactly, up to rounding)."""

    params: GyrocompassParams
    t: np.ndarray
    sources: tuple[str, ...]
    var: np.ndarray
    total: np.ndarray

    def __post_init__(self) -> None:
        check_params(self.params)
        nt = v.check_ndarray("t", self.t, ndim=1).size
        if not isinstance(self.sources, tuple) or not all(isinstance(s, str)
                                                          for s in self.sources):
            raise TypeError("sources must be a tuple of str")
        v.check_ndarray("var", self.var, shape=(len(self.sources), nt))
        v.check_ndarray("total", self.total, shape=(nt,))

    def at_end(self) -> dict[str, float]:
        """Standard deviation (rad/s) from each source at the last time.

        Examples
        --------
        >>> from gyrolib import gc
        >>> end = gc.error_budget(gc.GyrocompassParams(), 2.0).at_end()
        >>> max(end, key=end.get)
        'angle sensor noise'
        """
        return {s: float(np.sqrt(max(self.var[i, -1], 0.0))) for i, s in enumerate(self.sources)}


def error_budget(params: GyrocompassParams, t_end: float = 100.0, *,
                 name: str = "omega_gc", store_every: int | None = None) -> ErrorBudget:
    """Split the variance of the ``name`` estimation error by source.

    The gains of the full filter are kept fixed; each source's covariance is propagated alone
    through the linear error recursion (Joseph form, valid for any gain).  Sources are
    independent, so their variances add up to the filter's.

    Parameters
    ----------
    params : GyrocompassParams
        The model.
    t_end : float, default 100.0
        Length of the run (s).
    name : str, default "omega_gc"
        The state whose error is split.
    store_every : int, optional
        Decimation of the stored variances (default: about 1000 samples).

    Returns
    -------
    ErrorBudget
        Variance from each of :data:`BUDGET_SOURCES` over time, and the filter's total.

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import gc
    >>> bud = gc.error_budget(gc.GyrocompassParams(), 2.0)
    >>> bool(np.isclose(bud.var[:, -1].sum(), bud.total[-1], rtol=1e-8))
    True
    """
    p = check_params(params)
    ix = state_index(name)
    cm = ContinuousModel.build(p)
    disc = discretize_steps(cm, steps_in(p, t_end), "van_loan")
    se = default_store_every(disc.n_steps) if store_every is None else store_every
    se = v.check_int("store_every", se, 1)
    mdl = disc.model
    P0 = cm.P0.copy()
    # the variances of every step and the gains; no P stored but the last (every step's P
    # would be n_steps × n² floats, 80 MB over 100 s)
    full = covariance_fast(mdl, P0, disc.n_steps, keep_gains=True)
    zeros_q = tuple(np.zeros_like(mdl.Qd0) for _ in range(3))
    zero_r = np.zeros_like(mdl.r)
    Qc = cm.Q
    out = []
    for src in BUDGET_SOURCES:
        P0s = np.zeros_like(P0)
        Qd = zeros_q
        r = zero_r
        if src.startswith("initial "):
            blk = {"initial vibration state (N1, N2)": [6, 7],
                   "initial random drift (N3, N4)": [8, 9]}.get(src)
            blk = blk if blk is not None else [state_index(src.split()[1])]
            P0s[np.ix_(blk, blk)] = P0[np.ix_(blk, blk)]
        elif src.endswith("w1") or src.endswith("w2"):
            q = np.zeros_like(Qc)
            i = 0 if src.endswith("w1") else 1
            q[i, i] = Qc[i, i]
            parts = affine_qd(cm, disc.betas, q)
            Qd = parts[3:]
        else:
            q = ("angle sensor noise", "inclinometer y noise", "inclinometer z noise").index(src)
            r = zero_r.copy()
            r[q] = mdl.r[q]
        if not P0s.any() and Qd is zeros_q and not r.any():
            out.append(np.zeros(disc.n_steps // se + 1))
            continue
        res = propagate_fixed_gains(mdl, P0s, full.gains, r, Qd, se)
        out.append(res.P_stored[:, ix, ix])
    return ErrorBudget(params=p, t=disc.t[::se].copy(), sources=BUDGET_SOURCES,
                       var=np.array(out), total=full.var[::se, ix].copy())
