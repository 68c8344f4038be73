"""Paper RSF, the scale-factor correction of Eqs. (1)–(3) and the δK it leaves.

One routine does the correction for every input, :func:`correct_spans`: it takes the SINS
turn and the GS change over *spans* (stretches of samples over which both sides cover the
same turn), the correction interval each span counts in, and returns Eq. (1) accumulated
per interval, ε̂1 of Eq. (2), K of Eq. (3) and the K in force during each interval (the K
of interval i multiplies every SINS increment of interval i + 1).  Its two callers differ
only in how they cut spans and in what they report:

* :func:`run_correction`, on a simulated ensemble (:class:`~gyrolib.rsf.SensorRecord`):
  nothing is missing, so each interval is one span; the result, :class:`CorrectionRun`,
  judges the correction against the simulation's truth (δK, roll and lateral errors);
* :func:`gyrolib.rsf.calibrate`, on a recorded log (:class:`~gyrolib.rsf.RSFRecord`):
  spans run between known GS angles and leave out gaps and missing values; the result,
  :class:`gyrolib.rsf.CalibrationResult`, reports what a log alone can tell.

:func:`predict_delta_k` gives the δK the error model expects, for a simulation's
configuration or, with ``rate=``, for a record's measured roll rate.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import NamedTuple

import numpy as np

from gyrolib import _validation as v
from gyrolib._repr import compact_repr
from gyrolib.rsf.equations import (
    K_FORMS,
    correction_coefficient,
    delta_k,
    relative_k_error,
    roll_difference,
    sf_error_estimate,
)
from gyrolib.rsf.simulation import SensorRecord, SimulationConfig, gs_angle, lateral_error
from gyrolib.units import G0

__all__ = [
    "CorrectionRun",
    "DeltaKPrediction",
    "predict_delta_k",
    "run_correction",
]


# The correction, Eqs. (1)–(3), over spans ---------------------------------------------------------
class _Intervals(NamedTuple):
    """Eqs. (1)–(3) per correction interval (arrays runs × intervals; NaN where an interval
    holds no turn): ``turn`` ω_x Δt, the SINS turn of the interval's spans; ``eps1_hat``
    (Eq. (2)); ``k`` (Eq. (3)); ``k_in_force`` (runs × (intervals + 1)) the K multiplying
    the SINS increments during each interval and after the last: 1 in the first, then the K
    of the latest interval that has one."""

    turn: np.ndarray
    eps1_hat: np.ndarray
    k: np.ndarray
    k_in_force: np.ndarray

    def corrected_angle(self, increments: np.ndarray, row_interval: np.ndarray) -> np.ndarray:
        """∫ K ω_x dt per row (runs × rows): the SINS increment ending at each row times the K
        in force in that row's interval (``row_interval``, clipped to [0, intervals]), summed
        from the first row (whose increment is 0)."""
        n_int = self.k.shape[-1]
        return np.cumsum(self.k_in_force[:, np.clip(row_interval, 0, n_int)] * increments,
                         axis=-1)


def _per_interval(x: np.ndarray, interval: np.ndarray, n_int: int) -> np.ndarray:
    """Sums of the spans ``x`` (runs × spans) per interval; ``interval`` is nondecreasing."""
    out = np.zeros((x.shape[0], n_int))
    if interval.size:
        starts = np.flatnonzero(np.r_[True, interval[1:] != interval[:-1]])
        out[:, interval[starts]] = np.add.reduceat(x, starts, axis=-1)
    return out


def correct_spans(sins_turn: np.ndarray, gs_turn: np.ndarray, interval: np.ndarray,
                   n_int: int, period: float, k_form: str) -> _Intervals:
    """Paper RSF, Eqs. (1)–(3), from the SINS turn and the GS change over spans.

    ``sins_turn``, ``gs_turn`` (runs × spans): Σ SINS increments and the GS angle change over
    each span; ``interval`` (spans,), nondecreasing: the interval a span counts in (spans
    outside [0, ``n_int``) are left out).  Per interval, Eq. (1) accumulates Δγ over the
    spans, Eq. (2) divides it by the SINS turn ω_x Δt and Eq. (3) turns ε̂1 into K; an
    interval without a turn has no estimate (NaN) and leaves the K before it in force.
    """
    inside = np.flatnonzero((interval >= 0) & (interval < n_int))
    iv = interval[inside]
    sins, gs = sins_turn[:, inside], gs_turn[:, inside]
    turn = _per_interval(sins, iv, n_int)
    dgamma = _per_interval(roll_difference(sins, gs), iv, n_int)      # Eq. (1)
    good = turn != 0.0
    eps1_hat = np.full(turn.shape, np.nan)
    k = np.full(turn.shape, np.nan)
    if np.any(good):
        eps1_hat[good] = sf_error_estimate(dgamma[good], turn[good] / period, period)  # Eq. (2)
        k[good] = correction_coefficient(eps1_hat[good], k_form)                     # Eq. (3)
    # K in force: 1 in the first interval, then the latest K (carried over empty intervals).
    latest = np.maximum.accumulate(np.where(good, np.arange(n_int), -1), axis=-1)
    k1 = np.concatenate([np.ones((k.shape[0], 1)), k], axis=-1)
    k_in_force = np.concatenate([np.ones((k.shape[0], 1)),
                                 np.take_along_axis(k1, latest + 1, axis=-1)], axis=-1)
    return _Intervals(turn=turn, eps1_hat=eps1_hat, k=k, k_in_force=k_in_force)


# On a simulated ensemble ------------------------------------------------------------------------
@compact_repr
@dataclass(frozen=True)
class CorrectionRun:
    """The correction loop applied to a simulated ensemble (:class:`SensorRecord`), judged
    against the simulation's truth (:func:`run_correction`).

    Per interval i (arrays M × n_int): ``k`` the coefficient K_i computed at its end,
    ``eps1_hat`` the estimate of Eq. (2), ``delta_k`` δK_i = K_i (1 + ε1) − 1 (the residual
    scale-factor error of the next interval).  Per sample (M × (N+1)): roll error of the SINS
    without and with correction and of the GS; the lateral errors without and with correction
    (properties, computed on first use with gravity ``g``).
    """

    period: float
    k_form: str
    reset_angle: bool
    t: np.ndarray
    t_boundaries: np.ndarray
    k: np.ndarray
    eps1_hat: np.ndarray
    delta_k: np.ndarray
    roll_error_raw: np.ndarray
    roll_error_corrected: np.ndarray
    roll_error_gs: np.ndarray
    g: float = G0

    def __post_init__(self) -> None:
        v.check_positive("period", self.period)
        v.check_choice("k_form", self.k_form, K_FORMS)
        v.check_bool("reset_angle", self.reset_angle)
        nt = v.check_ndarray("t", self.t, ndim=1).size
        v.check_ndarray("t_boundaries", self.t_boundaries, ndim=1)
        shape = v.check_ndarray("k", self.k, ndim=2).shape
        for name in ("eps1_hat", "delta_k"):
            v.check_ndarray(name, getattr(self, name), shape=shape)
        for name in ("roll_error_raw", "roll_error_corrected", "roll_error_gs"):
            v.check_ndarray(name, getattr(self, name), shape=(shape[0], nt))
        v.check_positive("g", self.g)

    @cached_property
    def lateral_raw(self) -> np.ndarray:
        """Lateral error of the uncorrected SINS, m (computed on first use)."""
        return lateral_error(self.t, self.roll_error_raw, self.g)

    @cached_property
    def lateral_corrected(self) -> np.ndarray:
        """Lateral error of the corrected SINS, m (computed on first use)."""
        return lateral_error(self.t, self.roll_error_corrected, self.g)


def _steps_per_interval(record: SensorRecord, period: float) -> int:
    period = v.check_positive("period", period)
    fs = record.config.sample_rate
    n_per = period * fs
    if abs(n_per - round(n_per)) > 1e-9 * max(1.0, n_per) or round(n_per) < 1:
        raise ValueError(f"period must be a whole number of samples (multiple of "
                         f"{1.0 / fs} s); got {period}")
    n_per = round(n_per)
    if n_per > record.config.n_steps:
        raise ValueError(f"period must be <= the run duration {record.config.duration} s; "
                         f"got {period}")
    return n_per


class _Simulated(NamedTuple):
    """The correction of every complete interval of a simulated ensemble: ``k``,
    ``eps1_hat``, ``delta_k`` (M × n_int), the intervals' boundary samples ``idx``, the
    SINS and GS angles (M × (N+1)) and the :class:`_Intervals` they came from."""

    k: np.ndarray
    eps1_hat: np.ndarray
    delta_k: np.ndarray
    idx: np.ndarray
    sins_angle: np.ndarray
    gs: np.ndarray
    intervals: _Intervals


def interval_estimates(record: SensorRecord, period: float, k_form: str,
                        gs: np.ndarray | None = None) -> _Simulated:
    """Eqs. (1)–(3) for every complete interval of a simulated ensemble: nothing is missing
    in a simulation, so each interval is one span (``gs``: the GS angle if already known)."""
    n_per = _steps_per_interval(record, period)
    n_int = record.config.n_steps // n_per
    idx = np.arange(n_int + 1) * n_per
    sins_angle = np.concatenate([np.zeros((record.sins_inc.shape[0], 1)),
                                 np.cumsum(record.sins_inc, axis=1)], axis=1)
    gs = gs_angle(record) if gs is None else gs
    est = correct_spans(np.diff(sins_angle[:, idx], axis=1), np.diff(gs[:, idx], axis=1),
                         np.arange(n_int), n_int, period, k_form)
    dk = relative_k_error(est.k, record.eps1_sins[:, None])
    return _Simulated(k=est.k, eps1_hat=est.eps1_hat, delta_k=dk, idx=idx,
                      sins_angle=sins_angle, gs=gs, intervals=est)


def run_correction(record: SensorRecord, period: float, *, k_form: str = "linear",
                   reset_angle: bool = False, g: float = G0) -> CorrectionRun:
    """Apply the correction of paper RSF, Eqs. (1)–(3), every ``period`` seconds to a
    simulated ensemble and judge it against the simulation's truth.

    K_i from interval i multiplies every SINS increment of interval i + 1 (K = 1 during the
    first interval).  ``reset_angle=True`` also sets the SINS roll angle to the GS angle at
    each correction instant (not part of the paper's method).  The same correction on a
    recorded log is :func:`~gyrolib.rsf.calibrate`.

    Parameters
    ----------
    record : SensorRecord
        A simulated flight (:func:`~gyrolib.rsf.simulate_flight`).
    period : float
        Correction period Δt, s (a whole number of samples, at most the run).
    k_form : {"linear", "reciprocal"}, optional
        Reading of K (:func:`~gyrolib.rsf.correction_coefficient`).
    reset_angle : bool, optional
        Reset the SINS angle to the GS angle at each correction.
    g : float, optional
        Gravity for the lateral errors, m/s².

    Returns
    -------
    CorrectionRun
        K, ε̂1 and δK per interval; roll and lateral errors per sample.

    Examples
    --------
    >>> from gyrolib import rsf
    >>> rec = rsf.simulate_flight(rsf.SimulationConfig(duration=10.0), seed=0)
    >>> run = rsf.run_correction(rec, 5.0)
    >>> run.delta_k.shape, bool(abs(run.delta_k[0, 0]) < 600e-6)
    ((1, 2), True)
    """
    v.check_instance("record", record, SensorRecord)
    k_form = v.check_choice("k_form", k_form, K_FORMS)
    v.check_bool("reset_angle", reset_angle)
    g = v.check_positive("g", g)
    sim = interval_estimates(record, period, k_form)
    idx, gs = sim.idx, sim.gs
    n = record.sins_inc.shape[1]
    row_interval = (np.arange(n + 1) - 1) // int(idx[1])    # row 0 (t = 0) before interval 0
    increments = np.concatenate([np.zeros((record.sins_inc.shape[0], 1)),
                                 record.sins_inc], axis=1)
    corrected = sim.intervals.corrected_angle(increments, row_interval)
    if reset_angle:
        # From each correction instant on, start again from the GS angle.
        jump = gs[:, idx] - corrected[:, idx]
        jump[:, 0] = 0.0
        corrected = corrected + jump[:, np.minimum(np.arange(n + 1) // int(idx[1]),
                                                   idx.size - 1)]
    truth = record.gamma_true[None, :]
    t = record.t
    return CorrectionRun(period=float(period), k_form=k_form, reset_angle=reset_angle, t=t,
                         t_boundaries=t[idx], k=sim.k, eps1_hat=sim.eps1_hat,
                         delta_k=sim.delta_k, roll_error_raw=sim.sins_angle - truth,
                         roll_error_corrected=corrected - truth, roll_error_gs=gs - truth, g=g)


# Prediction of δK (Eq. (7) and its statistics) ----------------------------------------------------
@dataclass(frozen=True)
class DeltaKPrediction:
    """What Eq. (7) and the error model predict for δK over one interval.

    ``mean``: the systematic part (ε0,GS + ε1,GS ω_unc)/ω − ε0/ω (signs of the ``"fixed"``
    mode; 0 in ``"random"`` mode); ``std_encoder``, ``std_quantization``, ``std_noise``,
    ``std_systematic`` (run-to-run spread in ``"random"`` mode) and ``std`` their RSS;
    ``eq7``: the paper's Eq. (7) with Δγ_enc = the encoder's position error;
    ``omega_unc``: the steady uncompensated rate.
    """

    mean: float
    std_encoder: float
    std_quantization: float
    std_noise: float
    std_systematic: float
    std: float
    eq7: float
    omega_unc: float

    def __post_init__(self) -> None:
        v.check_real("mean", self.mean)
        for name in ("std_encoder", "std_quantization", "std_noise", "std_systematic", "std",
                     "eq7", "omega_unc"):
            v.check_nonnegative(name, getattr(self, name))


def predict_delta_k(config: SimulationConfig, period: float, *,
                    rate: float | None = None) -> DeltaKPrediction:
    """Predicted mean and spread of δK for a constant roll rate (first-order error model).

    The encoder's increment error over one interval is Δγ_enc [sin(θ₁+φ) − sin(θ₀+φ)] with
    θ₁ − θ₀ = (ω − ω_unc)Δt: its standard deviation over a uniform phase is
    √2 Δγ_enc |sin((ω − ω_unc)Δt/2)|, which averages to Δγ_enc (the Eq. (7) term) over the
    phase advance.  Quantization adds q √(f (1 − f)), f the fraction of a count in the
    indicated advance (q/√6 on average over f); the white noises add √((N_SINS² + N_GS²)Δt).
    ``eq7`` is paper RSF's Eq. (7) for the same sensors.

    Parameters
    ----------
    config : SimulationConfig
        The sensors (``sins``, ``gs``, ``encoder``) and error mode; without ``rate``, also
        the roll rate, which must then be constant.
    period : float
        Correction period, s (> 0).
    rate : float, optional
        Roll rate ω, rad/s (> 0), in place of the configuration's: for a record, the mean
        measured rate of its intervals (:attr:`gyrolib.rsf.CalibrationResult.mean_rate`).

    Returns
    -------
    DeltaKPrediction

    Examples
    --------
    >>> from gyrolib import rsf
    >>> p = rsf.predict_delta_k(rsf.SimulationConfig(), 5.0)
    >>> f"Eq. (7) {p.eq7 * 1e6:.0f} ppm, mean {p.mean * 1e6:.0f} ppm"
    'Eq. (7) 170 ppm, mean 66 ppm'
    >>> import math
    >>> q = rsf.predict_delta_k(rsf.SimulationConfig(), 5.0, rate=math.radians(1200.0))
    >>> f"at 1200 °/s: Eq. (7) {q.eq7 * 1e6:.0f} ppm, ω_unc {math.degrees(q.omega_unc):.0f} °/s"
    'at 1200 °/s: Eq. (7) 198 ppm, ω_unc 600 °/s'
    """
    v.check_instance("config", config, SimulationConfig)
    period = v.check_positive("period", period)
    if rate is not None:
        w = v.check_positive("rate", rate)
    elif config.roll.rate_end not in (None, config.roll.rate_start):
        raise ValueError("config must have a constant roll rate (rate_end None or equal to "
                         "rate_start) unless rate is given")
    else:
        w = config.roll.rate_start
    s, gs, enc = config.sins, config.gs, config.encoder
    w_unc = max(w - gs.motor_rate_max, 0.0)
    span = w * period
    systematic = (gs.eps0 + gs.eps1 * w_unc) / w - s.eps0 / w
    advance = (w - w_unc) * period          # body-to-platform turn over one interval
    std_enc = math.sqrt(2.0) * enc.position_error * abs(math.sin(advance / 2.0)) / span
    # Quantization: for an indicated advance whose fraction of a count is f, the difference of
    # the two rounding errors has variance f (1 − f) q²; the position error spreads f over the
    # phase ψ of the interval, so average over ψ.
    psi = np.linspace(0.0, 2.0 * math.pi, 1024, endpoint=False)
    indicated = advance + 2.0 * enc.position_error * math.sin(advance / 2.0) * np.cos(psi)
    frac = np.mod(indicated / enc.resolution, 1.0)
    std_q = enc.resolution * math.sqrt(float(np.mean(frac * (1.0 - frac)))) / span
    std_n = math.sqrt((s.arw**2 + gs.arw**2) * period) / span
    if config.errors == "fixed":
        mean, std_sys = systematic, 0.0
    else:
        mean = 0.0
        std_sys = math.sqrt(gs.eps0**2 + (gs.eps1 * w_unc) ** 2 + s.eps0**2) / w
    std = math.sqrt(std_enc**2 + std_q**2 + std_n**2 + std_sys**2)
    eq7 = delta_k(abs(gs.eps0), enc.position_error, w, period, abs(gs.eps1), w_unc)
    return DeltaKPrediction(mean=mean, std_encoder=std_enc, std_quantization=std_q,
                            std_noise=std_n, std_systematic=std_sys, std=std, eq7=eq7,
                            omega_unc=w_unc)
