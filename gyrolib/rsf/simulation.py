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
from dataclasses import dataclass

import numpy as np

from gyrolib import _validation as v
from gyrolib._repr import compact_repr
from gyrolib.rsf.sensors import (
    AEDB9340,
    GYPRO4300,
    SIIMU02_ROLL,
    EncoderSpec,
    MemsGyroSpec,
    RollGyroSpec,
)
from gyrolib.units import G0, to_si

__all__ = [
    "ERROR_MODES",
    "EncoderModel",
    "GsModel",
    "RollProfile",
    "SensorRecord",
    "SimulationConfig",
    "SinsGyroModel",
    "encoder_counts",
    "gs_angle",
    "lateral_error",
    "simulate_flight",
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
    """SINS roll gyro as simulated: scale-factor error ``eps1``, bias ``eps0`` (rad/s) and
    angle random walk ``arw`` (rad/√s).  Build it from the datasheet record,
    ``SinsGyroModel.from_spec(SIIMU02_ROLL, arw=...)`` (ε1, ε0 from Table 1 of paper RSF);
    the ARW is not in the paper: 0.15 °/√h is assumed (its effect is
    negligible, see the simulation chapter).  Set ``eps0``/``eps1`` directly only for
    what-if runs (e.g. a quiet gyro)."""

    eps1: float = SIIMU02_ROLL.sf_error
    eps0: float = SIIMU02_ROLL.bias_instability
    arw: float = _arw(0.15)

    def __post_init__(self) -> None:
        object.__setattr__(self, "eps1", v.check_in_range("eps1", self.eps1, -0.5, 0.5))
        object.__setattr__(self, "eps0", v.check_real("eps0", self.eps0))
        object.__setattr__(self, "arw", v.check_nonnegative("arw", self.arw))

    @classmethod
    def from_spec(cls, spec: RollGyroSpec, **simulation: float) -> SinsGyroModel:
        """The model of the gyro ``spec``: ε1 = ``sf_error``, ε0 = ``bias_instability`` (at
        +1σ), plus ``simulation`` keywords (``arw``).

        >>> f"{SinsGyroModel.from_spec(SIIMU02_ROLL, arw=0.0).eps1:.1e}"
        '6.0e-04'
        """
        v.check_instance("spec", spec, RollGyroSpec)
        return cls(eps1=spec.sf_error, eps0=spec.bias_instability, **simulation)


@dataclass(frozen=True)
class GsModel:
    """Indicator gyrostabilizer as simulated: MEMS gyro errors and the PI rate loop
    (paper RSF, Figure 2).  Build it from the gyro's record,
    ``GsModel.from_spec(GYPRO4300, motor_rate_max=...)``.

    * ``eps0`` (rad/s), ``eps1``: the GYPRO4300's ε0,GS = √(σ_rep² + σ_stab²) and ε1,GS;
    * ``arw`` (rad/√s): not in the paper; 0.2 °/√h assumed;
    * ``motor_rate_max`` (rad/s): the motor's speed limit; 600 °/s leaves the paper's
      ω_unc = 300 °/s at a vehicle rate of 900 °/s; ``math.inf`` gives an ideal GS;
    * ``kp`` (dimensionless), ``ki`` (1/s): PI gains on the MEMS gyro reading;
    * ``tau_motor`` (s): time constant of the motor's speed response.
    """

    eps0: float = GYPRO4300.bias_total
    eps1: float = GYPRO4300.sf_error
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

    @classmethod
    def from_spec(cls, spec: MemsGyroSpec, **simulation: float) -> GsModel:
        """The GS with the MEMS gyro ``spec``: ε0,GS = ``spec.bias_total``, ε1,GS =
        ``spec.sf_error`` (at +1σ), plus ``simulation`` keywords (``arw``,
        ``motor_rate_max``, ``kp``, ``ki``, ``tau_motor``).

        >>> import math
        >>> f"{GsModel.from_spec(GYPRO4300, motor_rate_max=math.inf).eps1:.1e}"
        '2.8e-04'
        """
        v.check_instance("spec", spec, MemsGyroSpec)
        return cls(eps0=spec.bias_total, eps1=spec.sf_error, **simulation)


@dataclass(frozen=True)
class EncoderModel:
    """Encoder as simulated: ``counts_per_rev`` counts per revolution and a once-per-revolution
    position error of amplitude ``position_error`` (rad).  Build it from the datasheet record,
    ``EncoderModel.from_spec(AEDB9340)`` (4000 counts assumed, 0.33° as the worked example
    of paper RSF prints it); set the fields directly for resolution sweeps."""

    counts_per_rev: int = AEDB9340.counts_per_rev
    position_error: float = AEDB9340.position_error

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

    @classmethod
    def from_spec(cls, spec: EncoderSpec) -> EncoderModel:
        """The model of the encoder ``spec``: its counts per revolution and position error.

        >>> EncoderModel.from_spec(AEDB9340).counts_per_rev
        4000
        """
        v.check_instance("spec", spec, EncoderSpec)
        return cls(counts_per_rev=spec.counts_per_rev, position_error=spec.position_error)


# The paper's devices, each built from its one datasheet record.
_PAPER_SINS = SinsGyroModel.from_spec(SIIMU02_ROLL)
_PAPER_GS = GsModel.from_spec(GYPRO4300)
_PAPER_ENCODER = EncoderModel.from_spec(AEDB9340)


@dataclass(frozen=True)
class SimulationConfig:
    """One simulation: vehicle, sensors, run length, sample rate and number of runs."""

    roll: RollProfile = RollProfile()
    sins: SinsGyroModel = _PAPER_SINS
    gs: GsModel = _PAPER_GS
    encoder: EncoderModel = _PAPER_ENCODER
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
                   *, wrap: bool = True) -> np.ndarray:
    """Count of the encoder for body-to-platform angles ``theta`` (rad): the GS's angle
    sensor of paper RSF, Figure 2 (its position error Δγ_enc is the one of Eqs. (6), (9)).

    The indicated angle θ + Δγ_enc sin(θ + φ) is quantized down to whole counts and the count
    restarts at every revolution: values in ``[0, counts_per_rev)``, dtype int64.
    ``phase`` (rad) broadcasts against the leading axes of ``theta``.  ``wrap=False`` gives the
    count an encoder that never restarts would show (the reference for :func:`unwrap_counts`).

    Examples
    --------
    >>> import numpy as np
    >>> enc = EncoderModel(counts_per_rev=8, position_error=0.0)
    >>> theta = np.array([0.1, 3.0, 6.5])
    >>> encoder_counts(theta, enc).tolist(), encoder_counts(theta, enc, wrap=False).tolist()
    ([0, 3, 0], [0, 3, 8])
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
    return np.mod(counts, encoder.counts_per_rev) if v.check_bool("wrap", wrap) else counts


def unwrap_counts(wrapped: np.ndarray, counts_per_rev: int) -> np.ndarray:
    """Unwrap a count that restarts every revolution, along the last axis, exactly.

    Consecutive samples must differ by less than half a revolution.  Integer arithmetic: the
    result is the wrapped count plus a whole number of revolutions, so nothing accumulates.
    The first sample keeps its wrapped value.  (The GS of paper RSF, Figure 2, reads its
    encoder this way; the paper does not say how.)

    Parameters
    ----------
    wrapped : numpy.ndarray of int
        Counts in ``[0, counts_per_rev)``, samples along the last axis.
    counts_per_rev : int
        Counts per revolution (>= 2).

    Returns
    -------
    numpy.ndarray of int64
        The unwrapped count.

    Examples
    --------
    >>> import numpy as np
    >>> unwrap_counts(np.array([3990, 5, 20, 3995]), 4000).tolist()
    [3990, 4005, 4020, 3995]
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
@compact_repr
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


def simulate_flight(config: SimulationConfig, seed: int) -> SensorRecord:
    """Simulate the vehicle, the SINS roll gyro, the GS and its encoder of paper RSF (no
    correction yet; see :func:`~gyrolib.rsf.run_correction`).

    Parameters
    ----------
    config : SimulationConfig
        Vehicle, sensors, run length, sample rate, number of runs and error mode.
    seed : int
        Seeds :func:`numpy.random.default_rng` (>= 0).

    Returns
    -------
    SensorRecord
        Every sensor's increments and the true angles, runs × samples.

    Examples
    --------
    >>> from gyrolib import rsf
    >>> rec = rsf.simulate_flight(rsf.SimulationConfig(duration=2.0), seed=0)
    >>> rec.sins_inc.shape, f"{rec.omega_unc[0, -1] * 180 / 3.141592653589793:.0f} °/s"
    ((1, 200), '300 °/s')
    """
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
    """The same flight read by another encoder (the encoder does not act on the GS loop).

    Parameters
    ----------
    record : SensorRecord
        A simulated flight.
    encoder : EncoderModel
        The other encoder (e.g.
        ``EncoderModel.from_spec(dataclasses.replace(AEDB9340, cycles_per_rev=256))``).

    Returns
    -------
    SensorRecord

    Examples
    --------
    >>> from gyrolib import rsf
    >>> rec = rsf.simulate_flight(rsf.SimulationConfig(duration=2.0), seed=0)
    >>> rsf.with_encoder(rec, rsf.EncoderModel(counts_per_rev=256)).config.encoder.counts_per_rev
    256
    """
    v.check_instance("record", record, SensorRecord)
    if not isinstance(encoder, EncoderModel):
        raise TypeError(f"encoder must be an EncoderModel; got {type(encoder).__name__}")
    cfg = dataclasses.replace(record.config, encoder=encoder)
    return dataclasses.replace(record, config=cfg)


def gs_gyro_angle_of(record: SensorRecord) -> np.ndarray:
    """∫ (MEMS gyro reading) dt, (M, N+1), zero at t = 0."""
    out = np.zeros((record.gs_gyro_inc.shape[0], record.gs_gyro_inc.shape[1] + 1))
    np.cumsum(record.gs_gyro_inc, axis=1, out=out[:, 1:])
    return out


def gs_angle(record: SensorRecord, *, gyro_angle: np.ndarray | None = None) -> np.ndarray:
    """GS roll angle γ̂ = unwrapped encoder angle + ∫ MEMS reading (paper RSF, Figure 2),
    referred to its value at t = 0.

    Parameters
    ----------
    record : SensorRecord
        A simulated flight.
    gyro_angle : numpy.ndarray, optional
        A precomputed ∫ MEMS reading (the same for every encoder of a sweep).

    Returns
    -------
    numpy.ndarray
        γ̂, rad, runs × (samples + 1).

    Examples
    --------
    >>> import math
    >>> from gyrolib import rsf
    >>> rec = rsf.simulate_flight(rsf.SimulationConfig(duration=2.0), seed=0)
    >>> err = rsf.gs_angle(rec)[0] - rec.gamma_true
    >>> bool(abs(err).max() < 2 * rec.config.encoder.position_error + 0.1)
    True
    """
    v.check_instance("record", record, SensorRecord)
    if gyro_angle is not None:
        gyro_angle = v.check_array("gyro_angle", gyro_angle, shape=record.theta_rel.shape)
    enc = record.config.encoder
    wrapped = encoder_counts(record.theta_rel, enc, record.encoder_phase)
    counts = unwrap_counts(wrapped, enc.counts_per_rev)
    enc_angle = (counts - counts[:, :1]) * enc.resolution
    return enc_angle + (gs_gyro_angle_of(record) if gyro_angle is None else gyro_angle)


def lateral_error(t: np.ndarray, roll_error: np.ndarray, g: float = G0) -> np.ndarray:
    """Lateral position error ∫∫ g sin Δγ dt dt (paper RSF, Eq. (8) without the small-angle
    approximation), along the last axis, trapezoidal rule; zero at t = 0.

    Parameters
    ----------
    t : numpy.ndarray
        Sample times, s, strictly increasing.
    roll_error : numpy.ndarray
        Roll error, rad, samples along the last axis.
    g : float, optional
        Gravity, m/s².

    Returns
    -------
    numpy.ndarray
        Lateral error, m, shaped as ``roll_error``.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0.0, 10.0, 1001)
    >>> f"{lateral_error(t, 1e-3 * t)[-1]:.4g}"   # ≈ g a t³/6 = 1.634 m
    '1.634'
    """
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
