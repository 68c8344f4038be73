"""Paper RSF: how the correction depends on its period Δt, on the encoder's resolution
(sweeps of :func:`gyrolib.rsf.run_correction` over one simulated record) and on the vehicle's
roll rate (one seeded flight ensemble per rate), against Eq. (7) of paper RSF.

Each sweep takes ``executor=`` (any :class:`concurrent.futures.Executor`, e.g. a Dask
cluster's ``Client(...).get_executor()``; ``None`` runs in this process): one task per swept
value, the rows put back in order, so the result does not depend on the executor.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from gyrolib import _validation as v
from gyrolib import stats
from gyrolib._executor import check_executor, map_ordered
from gyrolib._repr import compact_repr
from gyrolib.rsf.correction import interval_estimates, predict_delta_k
from gyrolib.rsf.equations import K_FORMS
from gyrolib.rsf.simulation import (
    EncoderModel,
    RollProfile,
    SensorRecord,
    SimulationConfig,
    gs_angle,
    gs_gyro_angle_of,
    simulate_flight,
    with_encoder,
)
from gyrolib.stats import Estimate
from gyrolib.units import to_si

__all__ = [
    "PeriodSweep",
    "RateSweep",
    "ResolutionSweep",
    "sweep_correction_period",
    "sweep_encoder",
    "sweep_roll_rate",
]


# Sweeps ------------------------------------------------------------------------------------------
def _rms_ci(per_run: np.ndarray, seed: int) -> tuple[float, float]:
    """The 95 % interval of the rms δK over all runs and intervals (``per_run``: runs ×
    intervals): a bootstrap over whole runs (the intervals of one run are not independent),
    seeded with ``seed``."""
    ci = stats.bootstrap(np.mean(per_run**2, axis=1), lambda ms: np.sqrt(np.mean(ms, axis=-1)),
                         seed=seed, vectorized=True)
    return ci.lo, ci.hi


class _RmsIntervals:
    """``rms_estimate(i)`` of a sweep with ``rms``, ``rms_ci`` (n × 2), ``n_runs`` and the
    seed of entry ``i`` (:meth:`_ci_seed`)."""

    def _ci_seed(self, i: int) -> int:
        return self.seed  # type: ignore[attr-defined]

    def rms_estimate(self, i: int) -> Estimate:
        """The rms δK of entry ``i`` with its 95 % interval (:attr:`rms_ci`: a bootstrap
        over whole runs, seeded)."""
        i = v.check_int("i", i, 0)
        rms = self.rms  # type: ignore[attr-defined]
        if i >= rms.size:
            raise ValueError(f"i must index the sweep (< {rms.size}); got {i}")
        lo, hi = self.rms_ci[i]  # type: ignore[attr-defined]
        return Estimate(value=float(rms[i]), lo=float(lo), hi=float(hi), confidence=0.95,
                        n=self.n_runs, method="bootstrap",  # type: ignore[attr-defined]
                        seed=self._ci_seed(i))


@compact_repr
@dataclass(frozen=True)
class PeriodSweep(_RmsIntervals):
    """δK against the correction period: ``mean``, ``rms`` and ``max_abs`` over all runs and
    complete intervals, the predicted rms ``predicted_rms`` and the paper's ``eq7``; ``floor``
    the GS gyro's systematic part (ε0,GS + ε1,GS ω_unc)/ω that no period removes, ``net_floor``
    the same less the SINS bias that K absorbs (signed), ``eps1`` the uncorrected SF error;
    ``rms_ci`` (n × 2) the 95 % interval of each rms (a bootstrap over the ``n_runs`` runs,
    seeded with the record's ``seed``; :meth:`rms_estimate`)."""

    periods: np.ndarray
    mean: np.ndarray
    rms: np.ndarray
    max_abs: np.ndarray
    predicted_rms: np.ndarray
    eq7: np.ndarray
    floor: float = 0.0
    net_floor: float = 0.0
    eps1: float = 0.0
    rms_ci: np.ndarray | None = None
    n_runs: int = 1
    seed: int = 0

    def __post_init__(self) -> None:
        _same_length(self, "periods", "mean", "rms", "max_abs", "predicted_rms", "eq7")


def _same_length(record: object, first: str, *others: str) -> None:
    """The array fields of a result record: 1-D, finite, all as long as ``first``."""
    shape = v.check_ndarray(first, getattr(record, first), ndim=1).shape
    for name in others:
        v.check_ndarray(name, getattr(record, name), shape=shape)


def _period_row(record: SensorRecord, period: float, k_form: str,
                gs: np.ndarray) -> tuple[float, ...]:
    """δK statistics at one correction period (one task of :func:`sweep_correction_period`)."""
    per_run = interval_estimates(record, period, k_form, gs)[2]
    dk = per_run.ravel()
    pred = predict_delta_k(record.config, period)
    return (dk.mean(), math.sqrt(np.mean(dk**2)), np.abs(dk).max(),
            math.hypot(pred.mean, pred.std), pred.eq7, float(pred.mean),
            *_rms_ci(per_run, record.seed))


def sweep_correction_period(record: SensorRecord, periods: Sequence[float],
                            k_form: str = "linear", *,
                            executor: object = None) -> PeriodSweep:
    """δK for each correction period in ``periods``, from one simulated flight ensemble
    (paper RSF: "increasing the interval between corrections ... makes the correction more
    effective"; Eq. (7) and :func:`~gyrolib.rsf.predict_delta_k` alongside).

    Parameters
    ----------
    record : SensorRecord
        A simulated flight ensemble at a constant roll rate.
    periods : sequence of float
        Correction periods, s (> 0, whole numbers of samples).
    k_form : {"linear", "reciprocal"}, optional
        Form of K.
    executor : concurrent.futures.Executor, optional
        Where the periods run, one task each (``None``: in this process).

    Returns
    -------
    PeriodSweep

    Examples
    --------
    >>> from gyrolib import rsf
    >>> rec = rsf.simulate_flight(rsf.SimulationConfig(duration=10.0, n_runs=2), seed=0)
    >>> sw = rsf.sweep_correction_period(rec, [1.0, 5.0])
    >>> f"{sw.floor * 1e6:.0f} ppm floor", bool(sw.rms[1] < sw.rms[0])
    ('97 ppm floor', True)
    """
    v.check_instance("record", record, SensorRecord)
    p = v.check_array("periods", periods, ndim=1)
    if np.any(p <= 0.0):
        raise ValueError(f"periods must be > 0 (s); got min {p.min()}")
    k_form = v.check_choice("k_form", k_form, K_FORMS)
    executor = check_executor(executor)
    gs = gs_angle(record)
    rows = np.array(map_ordered(_period_row, [(record, float(period), k_form, gs)
                                              for period in p], executor))
    cfg = record.config
    w = cfg.roll.rate_start
    w_unc = max(w - cfg.gs.motor_rate_max, 0.0)
    return PeriodSweep(periods=p, mean=rows[:, 0], rms=rows[:, 1], max_abs=rows[:, 2],
                       predicted_rms=rows[:, 3], eq7=rows[:, 4],
                       floor=(abs(cfg.gs.eps0) + abs(cfg.gs.eps1) * w_unc) / w,
                       net_floor=float(rows[-1, 5]), eps1=cfg.sins.eps1, rms_ci=rows[:, 6:8],
                       n_runs=cfg.n_runs, seed=record.seed)


@compact_repr
@dataclass(frozen=True)
class ResolutionSweep(_RmsIntervals):
    """δK against the encoder: ``counts_per_rev`` and ``position_error`` of each encoder,
    ``mean``/``rms``/``max_abs`` of δK, ``predicted_rms`` and the paper's ``eq7``; ``rms_ci``
    (n × 2) the 95 % interval of each rms (a bootstrap over the ``n_runs`` runs, seeded with
    the record's ``seed``; :meth:`rms_estimate`)."""

    counts_per_rev: np.ndarray
    position_error: np.ndarray
    mean: np.ndarray
    rms: np.ndarray
    max_abs: np.ndarray
    predicted_rms: np.ndarray
    eq7: np.ndarray
    rms_ci: np.ndarray | None = None
    n_runs: int = 1
    seed: int = 0

    def __post_init__(self) -> None:
        _same_length(self, "counts_per_rev", "position_error", "mean", "rms", "max_abs",
                     "predicted_rms", "eq7")


def _encoder_row(record: SensorRecord, enc: EncoderModel, period: float, k_form: str,
                 gyro: np.ndarray) -> tuple[float, ...]:
    """δK statistics with one encoder (one task of :func:`sweep_encoder`)."""
    rec = with_encoder(record, enc)
    per_run = interval_estimates(rec, period, k_form, gs_angle(rec, gyro_angle=gyro))[2]
    dk = per_run.ravel()
    pred = predict_delta_k(rec.config, period)
    return (enc.counts_per_rev, enc.position_error, dk.mean(), math.sqrt(np.mean(dk**2)),
            np.abs(dk).max(), math.hypot(pred.mean, pred.std), pred.eq7,
            *_rms_ci(per_run, record.seed))


def sweep_encoder(record: SensorRecord, encoders: Sequence[EncoderModel], period: float,
                  k_form: str = "linear", *, executor: object = None) -> ResolutionSweep:
    """δK for each encoder in ``encoders`` (same flight, same correction period): paper RSF's
    advice of "an encoder of higher resolution", tested.

    Parameters
    ----------
    record : SensorRecord
        A simulated flight ensemble at a constant roll rate.
    encoders : list or tuple of EncoderModel
        The encoders to compare.
    period : float
        Correction period, s.
    k_form : {"linear", "reciprocal"}, optional
        Form of K.
    executor : concurrent.futures.Executor, optional
        Where the encoders run, one task each (``None``: in this process).

    Returns
    -------
    ResolutionSweep

    Examples
    --------
    >>> from gyrolib import rsf
    >>> rec = rsf.simulate_flight(rsf.SimulationConfig(duration=10.0, n_runs=2), seed=0)
    >>> sw = rsf.sweep_encoder(rec, [rsf.EncoderModel(64, 0.0), rsf.EncoderModel(4096, 0.0)], 5.0)
    >>> sw.counts_per_rev.tolist(), bool(sw.rms[1] < sw.rms[0])
    ([64, 4096], True)
    """
    v.check_instance("record", record, SensorRecord)
    if not isinstance(encoders, list | tuple):
        raise TypeError("encoders must be a list or tuple of EncoderModel; "
                        f"got {type(encoders).__name__}")
    if not encoders:
        raise ValueError("encoders must be a non-empty sequence of EncoderModel")
    for i, enc in enumerate(encoders):
        v.check_instance(f"encoders[{i}]", enc, EncoderModel)
    period = v.check_positive("period", period)
    k_form = v.check_choice("k_form", k_form, K_FORMS)
    executor = check_executor(executor)
    gyro = gs_gyro_angle_of(record)    # the same for every encoder
    rows = map_ordered(_encoder_row, [(record, enc, period, k_form, gyro) for enc in encoders],
                       executor)
    cols = [np.array(c) for c in zip(*rows, strict=True)]
    return ResolutionSweep(counts_per_rev=cols[0], position_error=cols[1], mean=cols[2],
                           rms=cols[3], max_abs=cols[4], predicted_rms=cols[5], eq7=cols[6],
                           rms_ci=np.column_stack([cols[7], cols[8]]),
                           n_runs=record.config.n_runs, seed=record.seed)


@compact_repr
@dataclass(frozen=True)
class RateSweep(_RmsIntervals):
    """δK against the vehicle roll rate (one seeded ensemble per rate, constant ω_unc).

    ``rates`` (rad/s); ``mean``, ``rms``, ``max_abs`` of δK over all runs and complete
    intervals; ``predicted_rms`` (:func:`~gyrolib.rsf.predict_delta_k`); ``eq7`` the paper's
    Eq. (7); ``share`` = 1 − rms/|ε1|, the share of the SINS gyro's SF error removed;
    ``omega_unc`` (rad/s) and ``period`` (s) as simulated; ``rms_ci`` (n × 2) the 95 %
    interval of each rms, a bootstrap over whole runs seeded with that rate's seed
    (:func:`gyrolib.stats.bootstrap`), ``eps1`` the SINS gyro's SF error, ``n_runs`` the runs
    per rate and ``seed`` the first rate's seed.
    """

    rates: np.ndarray
    mean: np.ndarray
    rms: np.ndarray
    max_abs: np.ndarray
    predicted_rms: np.ndarray
    eq7: np.ndarray
    share: np.ndarray
    omega_unc: float
    period: float
    rms_ci: np.ndarray
    eps1: float
    n_runs: int = 1
    seed: int = 0

    def _ci_seed(self, i: int) -> int:
        return self.seed + i     # each rate's ensemble has its own seed

    def share_estimate(self, i: int) -> Estimate:
        """The share of ε1 removed at ``rates[i]``, 1 − rms/|ε1|, with its 95 % interval
        (from :attr:`rms_ci`)."""
        rms = self.rms_estimate(i)
        e1 = abs(self.eps1)
        return Estimate(value=float(self.share[i]), lo=1.0 - rms.hi / e1,
                        hi=1.0 - rms.lo / e1, confidence=rms.confidence, n=rms.n,
                        method=rms.method, seed=rms.seed)


def _rate_row(base: SimulationConfig, rate: float, omega_unc: float, n_runs: int,
              duration: float, seed: int, period: float, k_form: str) -> tuple[float, ...]:
    """One seeded ensemble at one roll rate and its δK statistics (one task of
    :func:`sweep_roll_rate`)."""
    cfg = dataclasses.replace(
        base, roll=RollProfile(rate), n_runs=n_runs, duration=duration,
        gs=dataclasses.replace(base.gs, motor_rate_max=rate - omega_unc))
    rec = simulate_flight(cfg, seed=seed)
    per_run = interval_estimates(rec, period, k_form)[2]
    dk = per_run.ravel()
    pred = predict_delta_k(cfg, period)
    return (dk.mean(), math.sqrt(np.mean(dk**2)), np.abs(dk).max(),
            math.hypot(pred.mean, pred.std), pred.eq7, *_rms_ci(per_run, seed))


def sweep_roll_rate(rates: Sequence[float], seed: int, *, period: float = 5.0,
                    omega_unc: float = float(to_si(300.0, "deg/s")),
                    base: SimulationConfig | None = None, n_runs: int = 100,
                    duration: float = 30.0, k_form: str = "linear",
                    executor: object = None) -> RateSweep:
    """Simulate the correction at each constant roll rate and measure δK (paper RSF, Eq. (7)).

    At each rate the GS motor follows up to ω − ``omega_unc`` (so the uncompensated rate stays
    the paper's 300 °/s); the ensemble at ``rates[i]`` is seeded with ``seed + i``.

    Parameters
    ----------
    rates : sequence of float
        Vehicle roll rates, rad/s, each > ``omega_unc``.
    seed : int
        Seed of the first ensemble (>= 0).
    period : float, optional
        Correction period Δt, s (default 5 s, the worked example's).
    omega_unc : float, optional
        Uncompensated rate left by the GS, rad/s (default 300 °/s).
    base : SimulationConfig, optional
        Sensors, sample rate and error mode (default :class:`SimulationConfig()`); its roll
        profile, motor limit, ``n_runs`` and ``duration`` are replaced.
    n_runs, duration : int, float, optional
        Runs per rate and run length, s.
    k_form : {"linear", "reciprocal"}, optional
        Form of the correction coefficient.
    executor : concurrent.futures.Executor, optional
        Where the rates run, one ensemble per task (``None``: in this process); each rate's
        seed is fixed before, so the result does not depend on it.

    Returns
    -------
    RateSweep
        δK statistics and the share of ε1 removed at each rate.

    Examples
    --------
    >>> from gyrolib.units import to_si
    >>> sw = sweep_roll_rate(to_si([900.0, 3600.0], "deg/s"), seed=1, n_runs=4, duration=10.0)
    >>> [f"{s:.2f}" for s in sw.share]
    ['0.83', '0.97']
    """
    r = v.check_array("rates", rates, ndim=1)
    seed = v.check_int("seed", seed, 0)
    omega_unc = v.check_nonnegative("omega_unc", omega_unc)
    if np.any(r <= omega_unc):
        raise ValueError(f"rates must be > omega_unc ({omega_unc:.6g} rad/s); got min {r.min()}")
    base = SimulationConfig() if base is None else v.check_instance("base", base,
                                                                    SimulationConfig)
    period = v.check_positive("period", period)
    k_form = v.check_choice("k_form", k_form, K_FORMS)
    executor = check_executor(executor)
    rows = np.array(map_ordered(_rate_row, [(base, float(rate), omega_unc, n_runs, duration,
                                             seed + i, period, k_form)
                                            for i, rate in enumerate(r)], executor))
    rms = rows[:, 1]
    return RateSweep(rates=r, mean=rows[:, 0], rms=rms, max_abs=rows[:, 2],
                     predicted_rms=rows[:, 3], eq7=rows[:, 4],
                     share=1.0 - rms / abs(base.sins.eps1), omega_unc=omega_unc,
                     period=period, rms_ci=rows[:, 5:7], eps1=float(base.sins.eps1),
                     n_runs=int(n_runs), seed=seed)
