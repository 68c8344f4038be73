"""Paper RSF, the correction loop run on a simulated record: Eqs. (1)–(3) every Δt, and the
δK that Eq. (7) predicts for the record's sensors (:func:`predict_delta_k`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from gyrolib import _validation as v
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
    dgamma = roll_difference(sins_d, gs_d)        # Eq. (1), accumulated over the interval
    omega_x = sins_d / period                        # mean measured rate
    eps1_hat = sf_error_estimate(dgamma, omega_x, period)   # Eq. (2)
    k = correction_coefficient(eps1_hat, k_form)
    dk = relative_k_error(k, record.eps1_sins[:, None])
    return k, eps1_hat, dk, idx, sins_angle, gs


def run_correction(record: SensorRecord, period: float, *, k_form: str = "linear",
                   reset_angle: bool = False, g: float = G0) -> CorrectionRun:
    """Apply the correction of paper RSF, Eqs. (1)–(3), every ``period`` seconds.

    K_i from interval i multiplies every SINS increment of interval i + 1 (K = 1 during the
    first interval).  ``reset_angle=True`` also sets the SINS roll angle to the GS angle at
    each correction instant (not part of the paper's method).

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
    if not isinstance(record, SensorRecord):
        raise TypeError(f"record must be a SensorRecord; got {type(record).__name__}")
    k_form = v.check_choice("k_form", k_form, K_FORMS)
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
    ``eq7`` is paper RSF's Eq. (7) for the same sensors.

    Parameters
    ----------
    config : SimulationConfig
        A configuration with a constant roll rate.
    period : float
        Correction period, s (> 0).

    Returns
    -------
    DeltaKPrediction

    Examples
    --------
    >>> from gyrolib import rsf
    >>> p = rsf.predict_delta_k(rsf.SimulationConfig(), 5.0)
    >>> f"Eq. (7) {p.eq7 * 1e6:.0f} ppm, mean {p.mean * 1e6:.0f} ppm"
    'Eq. (7) 170 ppm, mean 66 ppm'
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
    eq7 = delta_k(abs(gs.eps0), enc.position_error, w, period, abs(gs.eps1), w_unc)
    return DeltaKPrediction(mean=systematic if config.errors == "fixed" else mean,
                            std_encoder=std_enc, std_quantization=std_q, std_noise=std_n,
                            std_systematic=std_sys, std=std, eq7=eq7, omega_unc=w_unc)
