"""Paper RSF: how the correction depends on its period Δt and on the encoder's resolution
(sweeps of :func:`gyrolib.rsf.run_correction` over one simulated record).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from gyrolib import _validation as v
from gyrolib.rsf.correction import _interval_estimates, predict_delta_k
from gyrolib.rsf.equations import K_FORMS
from gyrolib.rsf.simulation import EncoderModel, SensorRecord, _gyro_angle, gs_angle, with_encoder

__all__ = [
    "PeriodSweep",
    "ResolutionSweep",
    "sweep_correction_period",
    "sweep_encoder",
]


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
    k_form = v.check_choice("k_form", k_form, K_FORMS)
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
    k_form = v.check_choice("k_form", k_form, K_FORMS)
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
