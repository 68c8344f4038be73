"""Paper RSF: time-domain simulation of the roll-gyro scale-factor correction loop.

The paper estimates the correction statically (Eq. (7)).  This module simulates the whole
loop sample by sample, vectorised over Monte Carlo runs:

* **Vehicle**: roll rate ω(t) rising linearly from ``rate_start`` to ``rate_end`` (constant
  when equal), 900…3600 °/s in the paper.  The true roll angle is integrated exactly.
* **SINS roll gyro**: angle increments (1 + ε1) Δγ + ε0 Δt + white noise (angle random
  walk), the measurement model of the paper.
* **GS** (paper's Figure 2): the motor turns the platform relative to the body at W (rad/s);
  the platform's inertial rate is the uncompensated rate ω_unc = ω + W.  The platform's MEMS
  gyro measures (1 + ε1,GS) ω_unc + ε0,GS + noise, and a PI rate loop drives the motor to
  null that reading.  The motor is a first-order speed source with time constant
  ``tau_motor`` and a speed limit ``motor_rate_max``: when the vehicle spins faster than the
  motor can follow, the PI loop saturates and the platform keeps turning at
  ω_unc = ω − W_max.  This is the book's stated model of the non-ideal GS (the paper only
  says that the rate remained uncompensated, ref. [4]); with ``motor_rate_max=inf`` the GS is
  ideal.
* **Encoder**: reads the body angle relative to the platform, θ = γ − γ_platform, with a
  once-per-revolution position error Δγ_enc sin(θ + φ), quantized to ``counts_per_rev``
  counts and wrapped at every revolution (the count restarts at each index pulse).  The GS
  unwraps the wrapped count in integer arithmetic, so no error accumulates however many
  revolutions pass.
* **GS roll angle** (paper's Figure 2): γ̂ = encoder angle + ∫ (MEMS gyro reading) dt.
* **Correction**: every Δt the increments of the SINS angle and of the GS angle over the last
  interval give Δγ_i (Eq. (1)), ε̂1 (Eq. (2)) and K_i; the SINS increments of the next
  interval are multiplied by K_i (Eq. (3)).  Optionally the SINS roll angle is also reset to
  the GS angle (not in the paper).
* **Outputs**: roll-angle and lateral-position error with and without correction, and δK
  per interval, to compare with Eq. (7).

Every random run takes an explicit ``seed``.  All inputs are SI.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from gyrolib import _validation as v
from gyrolib import roll_correction as rc
from gyrolib.units import G0, to_si

__all__ = [
    "ERROR_MODES",
    "CorrectionRun",
    "DeltaKPrediction",
    "EncoderModel",
    "GsModel",
    "PeriodSweep",
    "ResolutionSweep",
    "RollProfile",
    "SensorRecord",
    "SimulationConfig",
    "SinsGyroModel",
    "encoder_counts",
    "gs_angle",
    "lateral_error",
    "predict_delta_k",
    "run_correction",
    "simulate",
    "sweep_correction_period",
    "sweep_encoder",
    "unwrap_counts",
    "with_encoder",
]

#: ``"fixed"``: every run has the sensors' systematic errors at their +1σ values (the
#: paper's arithmetic); ``"random"``: drawn from N(0, σ²) per run.
ERROR_MODES: tuple[str, ...] = ("fixed", "random")

# 1 °/√h = 60 °/h·√s: angle random walk converted through the °/h unit of gyrolib.units.
_DEG_PER_SQRT_HOUR = float(to_si(60.0, "deg/h"))


def _arw(value_deg_per_sqrt_h: float) -> float:
    return value_deg_per_sqrt_h * _DEG_PER_SQRT_HOUR


# Configuration ---------------------------------------------------------------------------------
@dataclass(frozen=True)
class RollProfile:
    """Vehicle roll rate (rad/s), linear from ``rate_start`` at t = 0 to ``rate_end`` at the
    end of the run; ``rate_end=None`` keeps it constant.  Default 900 °/s (worked example)."""

    rate_start: float = float(to_si(900.0, "deg/s"))
    rate_end: float | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "rate_start", v.check_positive("rate_start", self.rate_start))
        if self.rate_end is not None:
            object.__setattr__(self, "rate_end", v.check_positive("rate_end", self.rate_end))

    def rate(self, t: np.ndarray, duration: float) -> np.ndarray:
        """Roll rate at times ``t`` of a run of length ``duration``."""
        t = v.check_array("t", t)
        duration = v.check_positive("duration", duration)
        end = self.rate_start if self.rate_end is None else self.rate_end
        return self.rate_start + (end - self.rate_start) * t / duration


@dataclass(frozen=True)
class SinsGyroModel:
    """SINS roll gyro: scale-factor error ``eps1``, bias ``eps0`` (rad/s) and angle random
    walk ``arw`` (rad/√s).  ``eps1`` and ``eps0`` from Table 1 (:data:`~gyrolib.
    roll_correction.SIIMU02_ROLL`); the ARW is not in the paper: 0.15 °/√h is assumed
    (its effect is negligible, see the simulation chapter)."""

    eps1: float = rc.SIIMU02_ROLL.sf_error
    eps0: float = rc.SIIMU02_ROLL.bias_instability
    arw: float = _arw(0.15)

    def __post_init__(self) -> None:
        object.__setattr__(self, "eps1", v.check_in_range("eps1", self.eps1, -0.5, 0.5))
        object.__setattr__(self, "eps0", v.check_real("eps0", self.eps0))
        object.__setattr__(self, "arw", v.check_nonnegative("arw", self.arw))


@dataclass(frozen=True)
class GsModel:
    """Indicator gyrostabilizer: MEMS gyro errors and the PI rate loop.

    * ``eps0`` (rad/s), ``eps1``: the GYPRO4300's ε0,GS = √(σ_rep² + σ_stab²) and ε1,GS;
    * ``arw`` (rad/√s): not in the paper; 0.2 °/√h assumed;
    * ``motor_rate_max`` (rad/s): the motor's speed limit; 600 °/s leaves the paper's
      ω_unc = 300 °/s at a vehicle rate of 900 °/s; ``math.inf`` gives an ideal GS;
    * ``kp`` (dimensionless), ``ki`` (1/s): PI gains on the MEMS gyro reading;
    * ``tau_motor`` (s): time constant of the motor's speed response.
    """

    eps0: float = rc.GYPRO4300.bias_total
    eps1: float = rc.GYPRO4300.sf_error
    arw: float = _arw(0.2)
    motor_rate_max: float = float(to_si(600.0, "deg/s"))
    kp: float = 1.0
    ki: float = 20.0
    tau_motor: float = 0.02

    def __post_init__(self) -> None:
        object.__setattr__(self, "eps0", v.check_real("eps0", self.eps0))
        object.__setattr__(self, "eps1", v.check_in_range("eps1", self.eps1, -0.5, 0.5))
        object.__setattr__(self, "arw", v.check_nonnegative("arw", self.arw))
        w = self.motor_rate_max
        if w != math.inf:
            w = v.check_positive("motor_rate_max", w)
        object.__setattr__(self, "motor_rate_max", float(w))
        object.__setattr__(self, "kp", v.check_nonnegative("kp", self.kp))
        object.__setattr__(self, "ki", v.check_positive("ki", self.ki))
        object.__setattr__(self, "tau_motor", v.check_positive("tau_motor", self.tau_motor))


@dataclass(frozen=True)
class EncoderModel:
    """Encoder: ``counts_per_rev`` counts per revolution and a once-per-revolution position
    error of amplitude ``position_error`` (rad).  Defaults: the AEDB-9340 record
    (:data:`~gyrolib.roll_correction.AEDB9340`, 4000 counts assumed, 0.33° inferred)."""

    counts_per_rev: int = rc.AEDB9340.counts_per_rev
    position_error: float = rc.AEDB9340.position_error

    def __post_init__(self) -> None:
        object.__setattr__(self, "counts_per_rev",
                           v.check_int("counts_per_rev", self.counts_per_rev, 4))
        object.__setattr__(self, "position_error",
                           v.check_in_range("position_error", self.position_error, 0.0,
                                            0.5))

    @property
    def resolution(self) -> float:
        """Angle of one count, rad."""
        return 2.0 * math.pi / self.counts_per_rev


@dataclass(frozen=True)
class SimulationConfig:
    """One simulation: vehicle, sensors, run length, sample rate and number of runs."""

    roll: RollProfile = RollProfile()
    sins: SinsGyroModel = SinsGyroModel()
    gs: GsModel = GsModel()
    encoder: EncoderModel = EncoderModel()
    duration: float = 60.0
    sample_rate: float = 100.0
    n_runs: int = 1
    errors: str = "fixed"

    def __post_init__(self) -> None:
        for name, cls in (("roll", RollProfile), ("sins", SinsGyroModel), ("gs", GsModel),
                          ("encoder", EncoderModel)):
            if not isinstance(getattr(self, name), cls):
                raise TypeError(f"{name} must be a {cls.__name__}; "
                                f"got {type(getattr(self, name)).__name__}")
        object.__setattr__(self, "duration", v.check_positive("duration", self.duration))
        object.__setattr__(self, "sample_rate",
                           v.check_positive("sample_rate", self.sample_rate))
        object.__setattr__(self, "n_runs", v.check_int("n_runs", self.n_runs, 1))
        v.check_choice("errors", self.errors, ERROR_MODES)
        n = self.duration * self.sample_rate
        if abs(n - round(n)) > 1e-9 * max(1.0, n) or round(n) < 2:
            raise ValueError("duration * sample_rate must be an integer >= 2 (whole samples); "
                             f"got {n}")
        # The wrapped encoder count can only be unwrapped if the body turns by less than
        # half a revolution relative to the platform between two samples.
        end = self.roll.rate_start if self.roll.rate_end is None else self.roll.rate_end
        fastest = max(self.roll.rate_start, end)
        if fastest / self.sample_rate >= math.pi:
            raise ValueError(f"sample_rate must be > {fastest / math.pi:.6g} Hz (more than two "
                             "samples per revolution, to unwrap the encoder); got "
                             f"{self.sample_rate}")

    @property
    def n_steps(self) -> int:
        return round(self.duration * self.sample_rate)

    @property
    def dt(self) -> float:
        return 1.0 / self.sample_rate


# Encoder: position error, quantization, wrap and unwrap -------------------------------------------
def encoder_counts(theta: np.ndarray, encoder: EncoderModel, phase: np.ndarray | float = 0.0,
                   ) -> np.ndarray:
    """Wrapped count of the encoder for body-to-platform angles ``theta`` (rad).

    The indicated angle θ + Δγ_enc sin(θ + φ) is quantized down to whole counts and the count
    restarts at every revolution: values in ``[0, counts_per_rev)``, dtype int64.
    ``phase`` (rad) broadcasts against the leading axes of ``theta``.
    """
    theta = v.check_array("theta", theta)
    v.check_instance("encoder", encoder, EncoderModel)
    ph = v.check_array("phase", phase)
    if ph.ndim and theta.ndim:
        if ph.ndim > theta.ndim or ph.shape != theta.shape[:ph.ndim]:
            raise ValueError(f"phase must be a number or match the leading axes of theta "
                             f"{theta.shape}; got shape {ph.shape}")
        ph = ph.reshape(ph.shape + (1,) * (theta.ndim - ph.ndim))
    elif ph.ndim:
        raise ValueError(f"phase must be a number when theta is; got shape {ph.shape}")
    indicated = theta + encoder.position_error * np.sin(theta + ph)
    counts = np.floor(indicated / encoder.resolution).astype(np.int64)
    return np.mod(counts, encoder.counts_per_rev)


def unwrap_counts(wrapped: np.ndarray, counts_per_rev: int) -> np.ndarray:
    """Unwrap a count that restarts every revolution, along the last axis, exactly.

    Consecutive samples must differ by less than half a revolution.  Integer arithmetic: the
    result is the wrapped count plus a whole number of revolutions, so nothing accumulates.
    The first sample keeps its wrapped value.
    """
    n = v.check_int("counts_per_rev", counts_per_rev, 2)
    w = np.asarray(wrapped)
    if w.dtype.kind not in "iu":
        raise TypeError(f"wrapped must be an integer array; got dtype {w.dtype}")
    if w.size and (w.min() < 0 or w.max() >= n):
        raise ValueError(f"wrapped must be in [0, {n}) (a count within one revolution)")
    w = w.astype(np.int64)
    d = np.diff(w, axis=-1)
    d = np.mod(d + n // 2, n) - n // 2  # the step modulo one revolution, in [−n/2, n/2)
    first = w[..., :1]
    return np.concatenate([first, first + np.cumsum(d, axis=-1)], axis=-1)


# Simulation ------------------------------------------------------------------------------------
@dataclass(frozen=True)
class SensorRecord:
    """Everything measured in one simulation (arrays: runs × samples).

    ``t`` (N+1,) sample times; ``gamma_true`` (N+1,) true roll angle; ``sins_inc`` (M, N)
    SINS gyro angle increments; ``gs_gyro_inc`` (M, N) MEMS gyro angle increments;
    ``omega_unc`` (M, N) true platform (uncompensated) rate; ``theta_rel`` (M, N+1) true
    body-to-platform angle; ``encoder_phase`` (M,) phase of the position error; realized
    errors ``eps1_sins``, ``eps0_sins``, ``eps1_gs``, ``eps0_gs`` (M,).
    """

    config: SimulationConfig
    seed: int
    t: np.ndarray
    gamma_true: np.ndarray
    sins_inc: np.ndarray
    gs_gyro_inc: np.ndarray
    omega_unc: np.ndarray
    theta_rel: np.ndarray
    encoder_phase: np.ndarray
    eps1_sins: np.ndarray
    eps0_sins: np.ndarray
    eps1_gs: np.ndarray
    eps0_gs: np.ndarray

    def __post_init__(self) -> None:
        cfg = v.check_instance("config", self.config, SimulationConfig)
        v.check_int("seed", self.seed, 0)
        m, n = cfg.n_runs, cfg.n_steps
        for name, shape in (("t", (n + 1,)), ("gamma_true", (n + 1,)), ("sins_inc", (m, n)),
                            ("gs_gyro_inc", (m, n)), ("omega_unc", (m, n)),
                            ("theta_rel", (m, n + 1)), ("encoder_phase", (m,)),
                            ("eps1_sins", (m,)), ("eps0_sins", (m,)), ("eps1_gs", (m,)),
                            ("eps0_gs", (m,))):
            v.check_ndarray(name, getattr(self, name), shape=shape)


def _draw(rng: np.random.Generator, sigma: float, n: int, mode: str) -> np.ndarray:
    if mode == "fixed":
        return np.full(n, sigma)
    return sigma * rng.standard_normal(n)


def _pi_loop(omega_body: np.ndarray, gs: GsModel, eps1: np.ndarray, eps0: np.ndarray,
             noise: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """The GS rate loop, step by step (vectorised over runs).

    Returns the platform's true inertial rate and the MEMS gyro reading, both (M, N), held
    constant over each step.  The loop starts in its steady state for the initial rate.
    """
    m_runs, n = noise.shape
    wmax = gs.motor_rate_max
    alpha = -math.expm1(-dt / gs.tau_motor)  # exact step response of the first-order motor
    w0 = float(np.clip(omega_body[0], -wmax, wmax))
    motor = np.full(m_runs, -w0)     # W, motor rate relative to the body
    integ = np.full(m_runs, w0)      # integral term of the PI controller
    # Rows are time steps here (contiguous writes); transposed on return.
    w_p = np.empty((n, m_runs))
    reading = np.empty((n, m_runs))
    noise_t = np.ascontiguousarray(noise.T)
    gain = 1.0 + eps1
    kp, ki_dt = gs.kp, gs.ki * dt
    neg_wmax = -wmax
    tmp = np.empty(m_runs)
    # In-place ufuncs: the loop is sequential in time, so its per-step overhead is the cost.
    for k in range(n):
        wp = w_p[k]
        m = reading[k]
        np.add(motor, omega_body[k], out=wp)
        np.multiply(gain, wp, out=m)
        m += eps0
        m += noise_t[k]
        # Conditional integration (anti-windup): the integrator is clamped at the motor limit.
        np.multiply(m, ki_dt, out=tmp)
        integ += tmp
        np.minimum(integ, wmax, out=integ)
        np.maximum(integ, neg_wmax, out=integ)
        np.multiply(m, kp, out=tmp)
        tmp += integ
        np.negative(tmp, out=tmp)                       # command −(k_p m + ∫)
        np.minimum(tmp, wmax, out=tmp)
        np.maximum(tmp, neg_wmax, out=tmp)
        tmp -= motor
        tmp *= alpha
        motor += tmp
    return w_p.T, reading.T


def simulate(config: SimulationConfig, seed: int) -> SensorRecord:
    """Simulate the vehicle, the SINS roll gyro, the GS and its encoder (no correction yet;
    see :func:`run_correction`).  ``seed`` seeds :func:`numpy.random.default_rng`."""
    if not isinstance(config, SimulationConfig):
        raise TypeError(f"config must be a SimulationConfig; got {type(config).__name__}")
    seed = v.check_int("seed", seed, 0)
    rng = np.random.default_rng(seed)
    m_runs, n, dt = config.n_runs, config.n_steps, config.dt
    t = np.arange(n + 1) * dt
    # Rate at mid-step: for a linear rate profile the increments are then exact.
    omega_body = config.roll.rate(t[:-1] + 0.5 * dt, config.duration)
    gamma_true = np.concatenate([[0.0], np.cumsum(omega_body * dt)])

    s, gs = config.sins, config.gs
    eps1_s = _draw(rng, s.eps1, m_runs, config.errors)
    eps0_s = _draw(rng, s.eps0, m_runs, config.errors)
    eps1_g = _draw(rng, gs.eps1, m_runs, config.errors)
    eps0_g = _draw(rng, gs.eps0, m_runs, config.errors)
    sqdt = math.sqrt(dt)
    # SINS gyro angle increments: the measurement model integrated over one step.
    sins_inc = ((1.0 + eps1_s)[:, None] * (omega_body * dt)[None, :] + eps0_s[:, None] * dt
                + s.arw * sqdt * rng.standard_normal((m_runs, n)))
    gyro_noise = gs.arw / sqdt * rng.standard_normal((m_runs, n))
    w_p, reading = _pi_loop(omega_body, gs, eps1_g, eps0_g, gyro_noise, dt)
    platform = np.concatenate([np.zeros((m_runs, 1)), np.cumsum(w_p * dt, axis=1)], axis=1)
    theta0 = rng.uniform(0.0, 2.0 * math.pi, m_runs)
    phase = rng.uniform(0.0, 2.0 * math.pi, m_runs)
    theta_rel = theta0[:, None] + gamma_true[None, :] - platform
    return SensorRecord(config=config, seed=seed, t=t, gamma_true=gamma_true,
                        sins_inc=sins_inc, gs_gyro_inc=reading * dt, omega_unc=w_p,
                        theta_rel=theta_rel, encoder_phase=phase, eps1_sins=eps1_s,
                        eps0_sins=eps0_s, eps1_gs=eps1_g, eps0_gs=eps0_g)


def with_encoder(record: SensorRecord, encoder: EncoderModel) -> SensorRecord:
    """The same flight read by another encoder (the encoder does not act on the loop)."""
    v.check_instance("record", record, SensorRecord)
    if not isinstance(encoder, EncoderModel):
        raise TypeError(f"encoder must be an EncoderModel; got {type(encoder).__name__}")
    cfg = dataclasses.replace(record.config, encoder=encoder)
    return dataclasses.replace(record, config=cfg)


def _gyro_angle(record: SensorRecord) -> np.ndarray:
    """∫ (MEMS gyro reading) dt, (M, N+1), zero at t = 0."""
    out = np.zeros((record.gs_gyro_inc.shape[0], record.gs_gyro_inc.shape[1] + 1))
    np.cumsum(record.gs_gyro_inc, axis=1, out=out[:, 1:])
    return out


def gs_angle(record: SensorRecord, *, gyro_angle: np.ndarray | None = None) -> np.ndarray:
    """GS roll angle γ̂ = unwrapped encoder angle + ∫ MEMS reading (paper's Figure 2), (M, N+1),
    referred to its value at t = 0.  ``gyro_angle`` may pass a precomputed ∫ MEMS reading."""
    v.check_instance("record", record, SensorRecord)
    if gyro_angle is not None:
        gyro_angle = v.check_array("gyro_angle", gyro_angle, shape=record.theta_rel.shape)
    enc = record.config.encoder
    wrapped = encoder_counts(record.theta_rel, enc, record.encoder_phase)
    counts = unwrap_counts(wrapped, enc.counts_per_rev)
    enc_angle = (counts - counts[:, :1]) * enc.resolution
    return enc_angle + (_gyro_angle(record) if gyro_angle is None else gyro_angle)


def lateral_error(t: np.ndarray, roll_error: np.ndarray, g: float = G0) -> np.ndarray:
    """Lateral position error ∫∫ g sin Δγ dt dt (paper RSF, Eq. (8) without the small-angle
    approximation), along the last axis, trapezoidal rule; zero at t = 0."""
    t = v.check_array("t", t, ndim=1)
    if np.any(np.diff(t) <= 0.0):
        raise ValueError("t must be strictly increasing (sample times)")
    e = v.check_array("roll_error", roll_error)
    if e.shape[-1] != t.size:
        raise ValueError(f"roll_error must have {t.size} samples along its last axis; "
                         f"got shape {e.shape}")
    acc = v.check_positive("g", g) * np.sin(e)
    return _cumtrapz(_cumtrapz(acc, t), t)


def _cumtrapz(y: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Cumulative trapezoidal integral along the last axis, starting at 0."""
    out = np.zeros_like(y)
    np.cumsum(0.5 * (y[..., 1:] + y[..., :-1]) * np.diff(t), axis=-1, out=out[..., 1:])
    return out


@dataclass(frozen=True)
class CorrectionRun:
    """The correction loop applied to a :class:`SensorRecord`.

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
        v.check_choice("k_form", self.k_form, rc.K_FORMS)
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


def _interval_estimates(record: SensorRecord, period: float, k_form: str,
                        gs: np.ndarray | None = None) -> tuple[np.ndarray, ...]:
    """K_i, ε̂1_i, δK_i and the boundary indices for every complete interval."""
    n_per = _steps_per_interval(record, period)
    n_int = record.config.n_steps // n_per
    idx = np.arange(n_int + 1) * n_per
    sins_angle = np.concatenate([np.zeros((record.sins_inc.shape[0], 1)),
                                 np.cumsum(record.sins_inc, axis=1)], axis=1)
    gs = gs_angle(record) if gs is None else gs
    sins_d = np.diff(sins_angle[:, idx], axis=1)    # ∫ ω_x dt over each interval
    gs_d = np.diff(gs[:, idx], axis=1)              # GS angle increment over each interval
    dgamma = rc.roll_difference(sins_d, gs_d)        # Eq. (1), accumulated over the interval
    omega_x = sins_d / period                        # mean measured rate
    eps1_hat = rc.sf_error_estimate(dgamma, omega_x, period)   # Eq. (2)
    k = rc.correction_coefficient(eps1_hat, k_form)
    dk = rc.relative_k_error(k, record.eps1_sins[:, None])
    return k, eps1_hat, dk, idx, sins_angle, gs


def run_correction(record: SensorRecord, period: float, *, k_form: str = "linear",
                   reset_angle: bool = False, g: float = G0) -> CorrectionRun:
    """Apply the paper's correction every ``period`` seconds.

    K_i from interval i multiplies every SINS increment of interval i + 1 (K = 1 during the
    first interval).  ``reset_angle=True`` also sets the SINS roll angle to the GS angle at
    each correction instant (not part of the paper's method).
    """
    if not isinstance(record, SensorRecord):
        raise TypeError(f"record must be a SensorRecord; got {type(record).__name__}")
    k_form = v.check_choice("k_form", k_form, rc.K_FORMS)
    if not isinstance(reset_angle, bool):
        raise TypeError("reset_angle must be a bool")
    k, eps1_hat, dk, idx, sins_angle, gs = _interval_estimates(record, period, k_form)
    m_runs, n = record.sins_inc.shape
    n_per, n_int = int(idx[1]), k.shape[1]
    # K per step: 1 in the first interval, K_i in interval i + 1, the last K to the end.
    k_ext = np.concatenate([np.ones((m_runs, 1)), k], axis=1)
    k_step = k_ext[:, np.minimum(np.arange(n) // n_per, n_int)]
    corrected = np.concatenate([np.zeros((m_runs, 1)),
                                np.cumsum(k_step * record.sins_inc, axis=1)], axis=1)
    if reset_angle:
        # From each correction instant on, start again from the GS angle.
        jump = gs[:, idx] - corrected[:, idx]
        jump[:, 0] = 0.0
        corrected = corrected + jump[:, np.minimum(np.arange(n + 1) // n_per, n_int)]
    truth = record.gamma_true[None, :]
    err_raw = sins_angle - truth
    err_cor = corrected - truth
    err_gs = gs - truth
    t = record.t
    return CorrectionRun(period=float(period), k_form=k_form, reset_angle=reset_angle, t=t,
                         t_boundaries=t[idx], k=k, eps1_hat=eps1_hat, delta_k=dk,
                         roll_error_raw=err_raw, roll_error_corrected=err_cor,
                         roll_error_gs=err_gs, g=v.check_positive("g", g))


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


def predict_delta_k(config: SimulationConfig, period: float) -> DeltaKPrediction:
    """Predicted mean and spread of δK for a constant roll rate (first-order error model).

    The encoder's increment error over one interval is Δγ_enc [sin(θ₁+φ) − sin(θ₀+φ)] with
    θ₁ − θ₀ = (ω − ω_unc)Δt: its standard deviation over a uniform phase is
    √2 Δγ_enc |sin((ω − ω_unc)Δt/2)|, which averages to Δγ_enc (the Eq. (7) term) over the
    phase advance.  Quantization adds q √(f (1 − f)), f the fraction of a count in the
    indicated advance (q/√6 on average over f); the white noises add √((N_SINS² + N_GS²)Δt).
    """
    if not isinstance(config, SimulationConfig):
        raise TypeError(f"config must be a SimulationConfig; got {type(config).__name__}")
    period = v.check_positive("period", period)
    if config.roll.rate_end not in (None, config.roll.rate_start):
        raise ValueError("predict_delta_k needs a constant roll rate (rate_end None or equal "
                         "to rate_start)")
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
    eq7 = rc.delta_k(abs(gs.eps0), enc.position_error, w, period, abs(gs.eps1), w_unc)
    return DeltaKPrediction(mean=systematic if config.errors == "fixed" else mean,
                            std_encoder=std_enc, std_quantization=std_q, std_noise=std_n,
                            std_systematic=std_sys, std=std, eq7=eq7, omega_unc=w_unc)


# Sweeps ------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class PeriodSweep:
    """δK against the correction period: ``mean``, ``rms`` and ``max_abs`` over all runs and
    complete intervals, the predicted rms ``predicted_rms`` and the paper's ``eq7``."""

    periods: np.ndarray
    mean: np.ndarray
    rms: np.ndarray
    max_abs: np.ndarray
    predicted_rms: np.ndarray
    eq7: np.ndarray

    def __post_init__(self) -> None:
        _same_length(self, "periods", "mean", "rms", "max_abs", "predicted_rms", "eq7")


def _same_length(record: object, first: str, *others: str) -> None:
    """The array fields of a result record: 1-D, finite, all as long as ``first``."""
    shape = v.check_ndarray(first, getattr(record, first), ndim=1).shape
    for name in others:
        v.check_ndarray(name, getattr(record, name), shape=shape)


def sweep_correction_period(record: SensorRecord, periods: Sequence[float],
                            k_form: str = "linear") -> PeriodSweep:
    """δK for each correction period in ``periods``, from one simulated flight ensemble."""
    v.check_instance("record", record, SensorRecord)
    p = v.check_array("periods", periods, ndim=1)
    if np.any(p <= 0.0):
        raise ValueError(f"periods must be > 0 (s); got min {p.min()}")
    k_form = v.check_choice("k_form", k_form, rc.K_FORMS)
    gs = gs_angle(record)
    out = {key: [] for key in ("mean", "rms", "max_abs", "pred", "eq7")}
    for period in p:
        dk = _interval_estimates(record, float(period), k_form, gs)[2].ravel()
        pred = predict_delta_k(record.config, float(period))
        out["mean"].append(dk.mean())
        out["rms"].append(math.sqrt(np.mean(dk**2)))
        out["max_abs"].append(np.abs(dk).max())
        out["pred"].append(math.hypot(pred.mean, pred.std))
        out["eq7"].append(pred.eq7)
    return PeriodSweep(periods=p, mean=np.array(out["mean"]), rms=np.array(out["rms"]),
                       max_abs=np.array(out["max_abs"]), predicted_rms=np.array(out["pred"]),
                       eq7=np.array(out["eq7"]))


@dataclass(frozen=True)
class ResolutionSweep:
    """δK against the encoder: ``counts_per_rev`` and ``position_error`` of each encoder,
    ``mean``/``rms``/``max_abs`` of δK, ``predicted_rms`` and the paper's ``eq7``."""

    counts_per_rev: np.ndarray
    position_error: np.ndarray
    mean: np.ndarray
    rms: np.ndarray
    max_abs: np.ndarray
    predicted_rms: np.ndarray
    eq7: np.ndarray

    def __post_init__(self) -> None:
        _same_length(self, "counts_per_rev", "position_error", "mean", "rms", "max_abs",
                     "predicted_rms", "eq7")


def sweep_encoder(record: SensorRecord, encoders: Sequence[EncoderModel], period: float,
                  k_form: str = "linear") -> ResolutionSweep:
    """δK for each encoder in ``encoders`` (same flight, same correction period)."""
    v.check_instance("record", record, SensorRecord)
    if not isinstance(encoders, list | tuple):
        raise TypeError("encoders must be a list or tuple of EncoderModel; "
                        f"got {type(encoders).__name__}")
    if not encoders:
        raise ValueError("encoders must be a non-empty sequence of EncoderModel")
    for i, enc in enumerate(encoders):
        v.check_instance(f"encoders[{i}]", enc, EncoderModel)
    period = v.check_positive("period", period)
    k_form = v.check_choice("k_form", k_form, rc.K_FORMS)
    cols = {key: [] for key in ("c", "a", "mean", "rms", "max_abs", "pred", "eq7")}
    gyro = _gyro_angle(record)    # the same for every encoder
    for enc in encoders:
        rec = with_encoder(record, enc)
        dk = _interval_estimates(rec, period, k_form, gs_angle(rec, gyro_angle=gyro))[2].ravel()
        pred = predict_delta_k(rec.config, period)
        cols["c"].append(enc.counts_per_rev)
        cols["a"].append(enc.position_error)
        cols["mean"].append(dk.mean())
        cols["rms"].append(math.sqrt(np.mean(dk**2)))
        cols["max_abs"].append(np.abs(dk).max())
        cols["pred"].append(math.hypot(pred.mean, pred.std))
        cols["eq7"].append(pred.eq7)
    return ResolutionSweep(counts_per_rev=np.array(cols["c"]),
                           position_error=np.array(cols["a"]), mean=np.array(cols["mean"]),
                           rms=np.array(cols["rms"]), max_abs=np.array(cols["max_abs"]),
                           predicted_rms=np.array(cols["pred"]), eq7=np.array(cols["eq7"]))
