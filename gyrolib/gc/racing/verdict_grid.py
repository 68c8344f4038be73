"""The race's verdict over two inputs and a reading: where "more than 50 % faster" holds.

:func:`race_verdict_grid` evaluates :func:`gyrolib.gc.race_margin` (the smaller saving over
the rival's two estimators minus 50 %) on a grid of the vibration variance σ1² and the angle
sensor's intensity C_as, each as a factor of the parameters given, under each reading of the
printed noise levels (``GyrocompassParams.measurement_noise``), and the three race times
under each reading at the given C_as and σ1².  The book stores one grid (it costs about a
hundred races) with the table's other maps (``python -m gyrolib claims --out``);
:func:`gyrolib.gc.plot_race_verdict` draws it.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from gyrolib import _validation as v
from gyrolib._executor import check_executor, map_ordered
from gyrolib._repr import compact_repr
from gyrolib.gc.model import inputs
from gyrolib.gc.model.params import GyrocompassParams, check_params
from gyrolib.gc.racing.comparison import race, race_margin
from gyrolib.gc.racing.rate_sensor import RateSensorProcedure, check_procedure

__all__ = ["RaceVerdictGrid", "race_verdict_grid"]


@compact_repr
@dataclass(frozen=True)
class RaceVerdictGrid:
    """``margin[r, i, j]`` (%): the claim's margin under reading ``readings[r]`` at
    ``C_as × cas_factors[i]`` and ``σ1² × sigma1_factors[j]`` (``> 0``: it holds);
    ``times[r]``: GC's, the classical and the optimal rival's times to σ_c (s) under reading
    ``r`` at the given parameters; ``params``' C_as and σ1² (SI) as ``C_as``, ``sigma1_sq``."""

    readings: tuple[str, ...]
    cas_factors: NDArray[np.float64]
    sigma1_factors: NDArray[np.float64]
    margin: NDArray[np.float64]
    times: NDArray[np.float64]
    C_as: float
    sigma1_sq: float

    def __post_init__(self) -> None:
        if not self.readings or not all(isinstance(r, str) for r in self.readings):
            raise TypeError("readings must be a non-empty tuple of str")
        for name in ("cas_factors", "sigma1_factors"):
            a = v.check_ndarray(name, getattr(self, name), ndim=1)
            if not np.all(a > 0):
                raise ValueError(f"{name} must be positive factors")
        v.check_ndarray("margin", self.margin, shape=(len(self.readings),
                                                      self.cas_factors.size,
                                                      self.sigma1_factors.size))
        v.check_ndarray("times", self.times, shape=(len(self.readings), 3))
        v.check_positive("C_as", self.C_as)
        v.check_positive("sigma1_sq", self.sigma1_sq)

    def to_dict(self) -> dict[str, Any]:
        return {"readings": list(self.readings), "cas_factors": self.cas_factors.tolist(),
                "sigma1_factors": self.sigma1_factors.tolist(),
                "margin": self.margin.tolist(), "times": self.times.tolist(),
                "C_as": self.C_as, "sigma1_sq": self.sigma1_sq}

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> RaceVerdictGrid:
        """The grid from :meth:`to_dict`'s plain data."""
        keys = ("readings", "cas_factors", "sigma1_factors", "margin", "times", "C_as",
                "sigma1_sq")
        if not isinstance(d, dict) or any(k not in d for k in keys):
            raise ValueError(f"d must be a dict with the keys {keys}")
        return cls(tuple(d["readings"]), np.asarray(d["cas_factors"], float),
                   np.asarray(d["sigma1_factors"], float), np.asarray(d["margin"], float),
                   np.asarray(d["times"], float), float(d["C_as"]), float(d["sigma1_sq"]))


def _margin(p: GyrocompassParams, proc: RateSensorProcedure) -> float:
    return race_margin(p, proc)


def _times(p: GyrocompassParams, proc: RateSensorProcedure) -> list[float]:
    r = race(p, proc)
    return [r.t_c_gc, r.t_c_rate_sensor, r.t_c_rate_sensor_optimal]


def race_verdict_grid(params: GyrocompassParams | None = None,
                      procedure: RateSensorProcedure | None = None, *,
                      sigma1_factors: Sequence[float] | None = None,
                      cas_factors: Sequence[float] | None = None,
                      readings: Sequence[str] | None = None,
                      executor: object = None) -> RaceVerdictGrid:
    """The race's margin over σ1² × C_as under each reading (see the module docstring).

    The defaults are the table of inputs' (:mod:`gyrolib.inputs`): 13 factors over σ1²'s
    range and 3 over C_as's (:func:`gyrolib.inputs.factor_grid`), every reading of
    ``measurement_noise``.

    Examples
    --------
    >>> from gyrolib import gc
    >>> g = gc.race_verdict_grid(sigma1_factors=(1.0,), cas_factors=(1.0,),
    ...                          readings=("intensity_over_dt",))
    >>> f"{g.margin[0, 0, 0]:.1f}", [f"{t:.1f}" for t in g.times[0]]
    ('7.3', ['24.1', '141.6', '56.4'])
    """
    p = GyrocompassParams() if params is None else check_params(params)
    proc = RateSensorProcedure() if procedure is None else check_procedure(procedure)
    ex = check_executor(executor)
    s1 = np.asarray(inputs.factor_grid("gc.sigma1_sq", 13) if sigma1_factors is None
                    else sigma1_factors, float)
    ca = np.asarray(inputs.factor_grid("gc.C_as") if cas_factors is None else cas_factors,
                    float)
    known = inputs.row("gc.measurement_noise").values
    for name, a in (("sigma1_factors", s1), ("cas_factors", ca)):
        if a.ndim != 1 or a.size == 0 or not np.all(np.isfinite(a) & (a > 0)):
            raise ValueError(f"{name} must be a non-empty 1-D sequence of positive factors")
    readings = known if readings is None else tuple(readings)
    if not readings or any(r not in known for r in readings):
        raise ValueError(f"readings must be readings of measurement_noise: {known}")
    args = [(replace(p, measurement_noise=r, C_as=c * p.C_as, sigma1_sq=f * p.sigma1_sq), proc)
            for r in readings for c in ca for f in s1]
    m = np.array(map_ordered(_margin, args, ex)).reshape(len(readings), ca.size, s1.size)
    t = np.array(map_ordered(_times, [(replace(p, measurement_noise=r), proc)
                                      for r in readings], ex))
    return RaceVerdictGrid(tuple(readings), ca, s1, m, t, p.C_as, p.sigma1_sq)
