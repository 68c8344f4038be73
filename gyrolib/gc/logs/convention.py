"""Paper GC: the inclinometer convention — which record column the filter reads as the tilt
δ and which as γ — made explicit, and what a wrong one costs.

Eq. (5) drives the float by ``H Ω_v cos β_n γ − H Ω_v sin β_n δ``: δ (the platform tilt about
the input axis y, read by ``inclinometer_y``) enters with ``−sin β_n``, γ (about the output
axis z, read by ``inclinometer_z``) with ``+cos β_n``.  Eq. (8)'s inclinometers read
``g δ + N1`` and ``g γ + N1``.

* :class:`InclinometerMapping` — which column (and sign) feeds δ and which γ: ``"y,z"`` (the
  default, the columns as named), ``"z,y"`` (a swapped pair), ``"-y,z"`` (one sign flipped);
  :meth:`InclinometerMapping.apply` turns a record into the filter's convention;
* :func:`convention_study` — a seeded Monte Carlo: records of paper GC's model calibrated as
  logged and with the pair wired wrongly, the bias of ω̂_gc in σ, its prediction from
  Eq. (5) and whether the diagnostics notice;
* :func:`plot_convention_study` — its figure.

Because β_n stays small in a calibration run (cos β_n ≈ 1, sin β_n ≈ 0 over 100 s), the
vertical-rate torque of a swapped pair is a constant that the filter cannot tell from the
drift: the estimate shifts by ``Ω_v (cos β̄ (γ − γ') − sin β̄ (δ − δ'))`` with ``δ', γ'`` the
tilts the wrong wiring shows the filter, while every innovation stays white and in band.
"""

from __future__ import annotations

from collections.abc import Iterable
from concurrent.futures import Executor
from dataclasses import dataclass
from typing import Final

import numpy as np

from gyrolib import _validation as v
from gyrolib._repr import compact_repr
from gyrolib.gc.logs.calibration import calibrate, simulate_record
from gyrolib.gc.logs.record import GCRecord
from gyrolib.gc.model.nominal import nominal_motion_aperiodic
from gyrolib.gc.model.params import GyrocompassParams, state_index

__all__ = [
    "ConventionStudy",
    "InclinometerMapping",
    "convention_study",
]

_AXES: Final[dict[str, str]] = {"y": "inclinometer_y", "z": "inclinometer_z"}


@dataclass(frozen=True)
class InclinometerMapping:
    """Which record column (and sign) the filter reads as δ and which as γ.

    ``delta`` and ``gamma`` are the axis letters ``"y"`` or ``"z"`` of the record's columns
    ``inclinometer_y``, ``inclinometer_z`` (each once); ``delta_sign``, ``gamma_sign`` are
    ``+1`` or ``−1``.  The filter's δ channel (Eq. (5): coupled with ``−sin β_n``) reads
    ``delta_sign × column delta``, its γ channel (``+cos β_n``) ``gamma_sign × column gamma``.

    Examples
    --------
    >>> m = InclinometerMapping.parse("z,-y")
    >>> m.delta, m.gamma_sign, str(m)
    ('z', -1.0, 'z,-y')
    >>> InclinometerMapping.parse("y,y")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: mapping must name each of y and z once, ...; got 'y,y'
    """

    delta: str = "y"
    gamma: str = "z"
    delta_sign: float = 1.0
    gamma_sign: float = 1.0

    def __post_init__(self) -> None:
        for name in ("delta", "gamma"):
            v.check_choice(name, getattr(self, name), ("y", "z"))
        if self.delta == self.gamma:
            raise ValueError(f"delta and gamma must be different columns; got both "
                             f"{self.delta!r}")
        for name in ("delta_sign", "gamma_sign"):
            s = v.check_real(name, getattr(self, name))
            if s not in (1.0, -1.0):
                raise ValueError(f"{name} must be +1 or -1; got {s}")
            object.__setattr__(self, name, float(s))

    @classmethod
    def parse(cls, mapping: str) -> InclinometerMapping:
        """From ``"y,z"``, ``"z,y"``, ``"-y,z"``, … (δ's column first, then γ's)."""
        text = v.check_str("mapping", mapping)
        parts = [s.strip() for s in text.split(",")]
        axes, signs = [], []
        for part in parts:
            sign = -1.0 if part.startswith("-") else 1.0
            axes.append(part.lstrip("+-"))
            signs.append(sign)
        if (len(parts) != 2 or sorted(axes) != ["y", "z"]
                or any(p.count("-") + p.count("+") > 1 for p in parts)):
            raise ValueError("mapping must name each of y and z once, as two of y, z, "
                             "-y, -z separated by a comma (e.g. y,z or z,y or -y,z); got "
                             f"{text!r}")
        return cls(axes[0], axes[1], signs[0], signs[1])

    def __str__(self) -> str:
        def one(axis: str, sign: float) -> str:
            return ("-" if sign < 0 else "") + axis
        return f"{one(self.delta, self.delta_sign)},{one(self.gamma, self.gamma_sign)}"

    @property
    def is_identity(self) -> bool:
        """True for ``"y,z"`` (the columns as named)."""
        return str(self) == "y,z"

    @property
    def delta_column(self) -> str:
        """The record column the δ channel reads."""
        return _AXES[self.delta]

    @property
    def gamma_column(self) -> str:
        """The record column the γ channel reads."""
        return _AXES[self.gamma]

    def describe(self) -> str:
        """One line: which column is read as δ and which as γ."""
        def one(sign: float, col: str) -> str:
            return ("−" if sign < 0 else "") + col
        return (f"δ (tilt about the input axis, −sin β_n in Eq. (5)) = "
                f"{one(self.delta_sign, self.delta_column)}, γ (tilt about the output axis, "
                f"+cos β_n) = {one(self.gamma_sign, self.gamma_column)}")

    def apply(self, record: GCRecord) -> GCRecord:
        """The record in the filter's convention: its ``inclinometer_y`` is the δ channel,
        its ``inclinometer_z`` the γ channel.

        Examples
        --------
        >>> rec = GCRecord(t=[0.001], angle_sensor=[0.0], inclinometer_y=[1.0],
        ...                inclinometer_z=[2.0])
        >>> out = InclinometerMapping.parse("-z,y").apply(rec)
        >>> float(out.inclinometer_y[0]), float(out.inclinometer_z[0])
        (-2.0, 1.0)
        """
        v.check_instance("record", record, GCRecord)
        if self.is_identity:
            return record
        cols = {"y": record.inclinometer_y, "z": record.inclinometer_z}
        return GCRecord(t=record.t, angle_sensor=record.angle_sensor,
                        inclinometer_y=self.delta_sign * cols[self.delta],
                        inclinometer_z=self.gamma_sign * cols[self.gamma],
                        latitude=record.latitude)

    def inverse(self) -> InclinometerMapping:
        """The mapping that undoes this one (``m.inverse().apply(m.apply(r))`` is ``r``).

        Examples
        --------
        >>> str(InclinometerMapping.parse("-z,y").inverse())
        'z,-y'
        """
        by_out = {self.delta: ("y", self.delta_sign), self.gamma: ("z", self.gamma_sign)}
        (d_axis, d_sign), (g_axis, g_sign) = by_out["y"], by_out["z"]
        return InclinometerMapping(d_axis, g_axis, d_sign, g_sign)

    def seen_tilts(self, delta: float, gamma: float) -> tuple[float, float]:
        """The tilts ``(δ', γ')`` the filter sees when the true tilts are ``(δ, γ)`` and the
        columns are wired as this mapping says (the log's y column holds
        ``delta_sign × true column delta``, …)."""
        true = {"y": v.check_real("delta", delta), "z": v.check_real("gamma", gamma)}
        return self.delta_sign * true[self.delta], self.gamma_sign * true[self.gamma]


def _as_mapping(mapping: InclinometerMapping | str) -> InclinometerMapping:
    if isinstance(mapping, InclinometerMapping):
        return mapping
    if isinstance(mapping, str):
        return InclinometerMapping.parse(mapping)
    raise TypeError(f"mapping must be an InclinometerMapping or a str such as 'z,y'; got "
                    f"{type(mapping).__name__}")


# The Monte Carlo study -----------------------------------------------------------------------
@compact_repr
@dataclass(frozen=True)
class ConventionStudy:
    """Records of paper GC's model calibrated as logged (``right``) and with the inclinometer
    columns wired as ``wiring`` says (``wrong``), one per seed (SI).

    Per seed (S,): ``omega_true``; the true tilts ``delta``, ``gamma``; the estimates and σ
    ``est_right``, ``std_right``, ``est_wrong``, ``std_wrong``; ``fits_right``,
    ``fits_wrong`` (every sensor's NIS in band and its innovations white); ``valid_right``,
    ``valid_wrong`` (no lost lock); ``predicted_shift`` (rad/s): the shift of the estimate
    Eq. (5) predicts, ``Ω_v (c̄ (γ − γ') − s̄ (δ − δ'))`` with ``c̄``, ``s̄`` the mean cos β_n,
    sin β_n over the record.  The prediction assumes the filter reads the tilts as wired;
    it is exact for a swap, which leaves the tilts' common mode ``(δ + γ)/2`` alone, and an
    upper bound in size for a wiring that flips the common mode, since the filter shares a
    common mode between the tilts and the vibration N1 (both inclinometers read ``+N1``).
    """

    params: GyrocompassParams
    wiring: str
    t_end: float
    seeds: np.ndarray
    omega_true: np.ndarray
    delta: np.ndarray
    gamma: np.ndarray
    est_right: np.ndarray
    std_right: np.ndarray
    est_wrong: np.ndarray
    std_wrong: np.ndarray
    fits_right: np.ndarray
    fits_wrong: np.ndarray
    valid_right: np.ndarray
    valid_wrong: np.ndarray
    predicted_shift: np.ndarray

    @property
    def z_right(self) -> np.ndarray:
        """Error of the estimate as logged, in its σ."""
        return (self.est_right - self.omega_true) / self.std_right

    @property
    def z_wrong(self) -> np.ndarray:
        """Error of the estimate with the wrong wiring, in its σ (the bias it causes)."""
        return (self.est_wrong - self.omega_true) / self.std_wrong

    @property
    def shift(self) -> np.ndarray:
        """``est_wrong − est_right`` (rad/s): what the wiring alone changes."""
        return self.est_wrong - self.est_right

    def summary(self) -> dict:
        """JSON-ready: RMS of the errors in σ, share beyond 3σ, share of runs whose
        diagnostics pass, and the fit of the shift against its prediction."""
        zr, zw = self.z_right, self.z_wrong
        slope = float(np.dot(self.predicted_shift, self.shift)
                      / np.dot(self.predicted_shift, self.predicted_shift))
        return {
            "wiring": self.wiring, "runs": int(self.seeds.size), "t_end": self.t_end,
            "rms_z_right": float(np.sqrt(np.mean(zr**2))),
            "rms_z_wrong": float(np.sqrt(np.mean(zw**2))),
            "beyond_3sigma_right": float(np.mean(np.abs(zr) > 3)),
            "beyond_3sigma_wrong": float(np.mean(np.abs(zw) > 3)),
            "fits_right": float(np.mean(self.fits_right)),
            "fits_wrong": float(np.mean(self.fits_wrong)),
            "valid_right": float(np.mean(self.valid_right)),
            "valid_wrong": float(np.mean(self.valid_wrong)),
            "shift_over_prediction": slope,
        }


def _one_run(params: GyrocompassParams, t_end: float, seed: int,
             wiring: InclinometerMapping) -> tuple[float, ...]:
    sim = simulate_record(params, t_end, seed)
    rec = sim.record
    right = calibrate(rec, params)
    wrong = calibrate(wiring.apply(rec), params)
    d, g = (float(sim.truth[0, state_index(n)]) for n in ("delta", "gamma"))
    d_seen, g_seen = wiring.seen_tilts(d, g)
    beta = nominal_motion_aperiodic(params, rec.t).beta
    c, s = float(np.mean(np.cos(beta))), float(np.mean(np.sin(beta)))
    pred = params.Omega_v * (c * (g - g_seen) - s * (d - d_seen))

    return (sim.omega_gc, d, g, right.omega_gc, right.omega_gc_std, wrong.omega_gc,
            wrong.omega_gc_std, bool(np.all(right.fits())), bool(np.all(wrong.fits())),
            bool(right.valid), bool(wrong.valid), pred)


def convention_study(params: GyrocompassParams | None = None, *,
                     wiring: InclinometerMapping | str = "z,y", t_end: float = 100.0,
                     seeds: Iterable[int] = range(8),
                     executor: Executor | None = None) -> ConventionStudy:
    """Monte Carlo of a wrongly wired inclinometer pair (paper GC, Eqs. (5), (8)).

    For each seed a record of paper GC's model is simulated (:func:`gyrolib.gc.simulate_record`,
    the tilts δ, γ drawn from their priors) and calibrated twice with the same filter: as
    logged, and with its inclinometer columns rearranged as ``wiring`` says (``"z,y"``: the
    pair swapped; ``"-y,-z"``: both signs flipped; the filter then reads them as y, z).

    Parameters
    ----------
    params : GyrocompassParams, optional
        The model simulated and filtered (default the paper's).
    wiring : InclinometerMapping or str
        How the log's columns are wired wrongly.
    t_end : float
        Record length (s).
    seeds : iterable of int
        One run per seed; results are independent of ``executor``.
    executor : concurrent.futures.Executor, optional
        Runs the seeds in parallel (e.g. a ``ProcessPoolExecutor``); default: one after the
        other here.

    Returns
    -------
    ConventionStudy

    Examples
    --------
    >>> from gyrolib import gc
    >>> st = gc.convention_study(wiring="z,y", t_end=5.0, seeds=[1, 2])
    >>> st.est_wrong.shape, bool(np.all(st.fits_wrong))
    ((2,), True)
    """
    p = GyrocompassParams() if params is None else v.check_instance(
        "params", params, GyrocompassParams)
    m = _as_mapping(wiring)
    t_end = v.check_positive("t_end", t_end)
    seeds = np.array([v.check_int("seed", s, 0) for s in seeds], dtype=np.int64)
    if seeds.size == 0:
        raise ValueError("seeds must hold at least one seed")
    if executor is not None and not isinstance(executor, Executor):
        raise TypeError(f"executor must be a concurrent.futures.Executor or None; got "
                        f"{type(executor).__name__}")
    if executor is None:
        rows = [_one_run(p, t_end, int(s), m) for s in seeds]
    else:
        futures = [executor.submit(_one_run, p, t_end, int(s), m) for s in seeds]
        rows = [f.result() for f in futures]
    cols = list(zip(*rows))
    f = [np.array(c, dtype=float) for c in cols]
    b = [np.array(c, dtype=bool) for c in cols]
    return ConventionStudy(
        params=p, wiring=str(m), t_end=t_end, seeds=seeds, omega_true=f[0], delta=f[1],
        gamma=f[2], est_right=f[3], std_right=f[4], est_wrong=f[5], std_wrong=f[6],
        fits_right=b[7], fits_wrong=b[8], valid_right=b[9], valid_wrong=b[10],
        predicted_shift=f[11])
