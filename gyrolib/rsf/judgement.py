"""Paper RSF on a record, judged: from a record to one :class:`gyrolib.verdict.Verdict`
(:func:`judge_record`): the correction of Eqs. (1)–(3) per interval
(:func:`gyrolib.rsf.calibrate`), the total standard uncertainty of the mean ε̄1 and the
run's checks (:func:`gyrolib.rsf.eps1_uncertainty`), the status with its reason, code and
hint, and the counts of the rows.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Final

import numpy as np

from gyrolib.reasons import hint, primary
from gyrolib.rsf.calibration import calibrate
from gyrolib.rsf.correction import predict_delta_k
from gyrolib.rsf.record import RSFRecord
from gyrolib.rsf.simulation import SimulationConfig
from gyrolib.rsf.uncertainty import eps1_uncertainty
from gyrolib.verdict import Check, Counts, Verdict

__all__ = ["judge_record"]

#: Each check of :func:`gyrolib.rsf.eps1_uncertainty`: (subject, formula).
_CHECKS: Final[dict[str, tuple[str, str]]] = {
    "scatter": ("eps1_hat", "sum of ((eps1_hat_i - mean)/sigma_i)^2 over the intervals"),
    "bias": ("bias_estimate", "estimate/sqrt(tolerance^2 + its sigma^2)"),
    "prior": ("eps1_hat_mean", "estimate/sqrt(sf_prior^2 + sigma^2)"),
}


def judge_record(record: RSFRecord, period: float, config: SimulationConfig | None = None,
                 *, k_form: str = "linear", slips: str = "repair", false_alarm: float = 0.01,
                 sins_bias: float | None = None, gs_bias: float | None = None,
                 gs_gyro_scale: float | None = None, gs_scale: float | None = None,
                 sf_prior: float | None = None, notes: Iterable[str] = ()) -> Verdict:
    """Apply paper RSF's correction to a record and judge the mean ε̄1 (Eqs. (1)–(3)).

    ``ok`` when every check of :func:`gyrolib.rsf.eps1_uncertainty` passes (the
    intervals' scatter against the sensors' error model, the biases of a reversing roll,
    the estimate against the roll gyro's scale-factor tolerance), else ``invalid``.  σ is
    the total standard uncertainty with its parts (``random``, ``encoder``, ``biases``,
    ``gs_scale``, and ``quantization`` when a column of the record is coarse,
    :attr:`gyrolib.rsf.RSFRecord.resolution`).

    Parameters
    ----------
    record : RSFRecord
    period : float
        Correction interval Δt (s).
    config : SimulationConfig, optional
        The sensors' models (default: paper RSF's); the predicted δK and the tolerances'
        defaults come from it.
    k_form, slips
        As for :func:`gyrolib.rsf.calibrate`.
    false_alarm, sins_bias, gs_bias, gs_gyro_scale, gs_scale, sf_prior
        As for :func:`gyrolib.rsf.eps1_uncertainty` (SI).
    notes : iterable of str
        Sentences on the record (its reading) to keep in the verdict's notes, first.

    Returns
    -------
    Verdict
        ``result`` the :class:`gyrolib.rsf.CalibrationResult`; ``details``:
        ``uncertainty`` (:class:`gyrolib.rsf.Eps1Uncertainty`), ``prediction`` (δK the
        error model predicts at the record's mean rate, :func:`gyrolib.rsf.predict_delta_k`).

    Raises
    ------
    ValueError
        A record shorter than two rows or than ``period``, or without a usable interval.

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import rsf
    >>> t = np.arange(0, 201) * 0.01                       # 2 s at 100 Hz, 900 °/s
    >>> gs = np.radians(900.0) * t
    >>> inc = np.concatenate([[0.0], np.diff(gs)]) * (1 + 600e-6)
    >>> ver = rsf.judge_record(rsf.RSFRecord(t=t, sins_increment=inc, gs_angle=gs), 1.0)
    >>> ver.status, f"{ver.estimate * 1e6:.1f}", sorted(ver.sigma_parts)
    ('ok', '599.6', ['biases', 'encoder', 'gs_scale', 'random'])
    >>> ver.checks[-1].line()[:45]
    'prior of eps1_hat_mean: estimate/sqrt(sf_prio'
    """
    config = SimulationConfig() if config is None else config
    if not isinstance(record, RSFRecord):
        raise TypeError(f"record must be an RSFRecord; got {type(record).__name__}")
    if record.n < 2:
        raise ValueError("expected at least two data rows")
    span = float(record.t[-1] - record.t[0])
    if period > span:
        raise ValueError(f"period {period} s is longer than the record ({span:.6g} s): no "
                         "complete correction interval")
    res = calibrate(record, period, k_form=k_form, slips=slips)
    if res.n_intervals == 0:
        raise ValueError("no correction interval holds a usable sample (every sample is "
                         "missing or follows a gap)")
    pred = predict_delta_k(config, res.period, rate=res.mean_rate)
    unc = eps1_uncertainty(res, config, false_alarm=false_alarm, sins_bias=sins_bias,
                           gs_bias=gs_bias, gs_gyro_scale=gs_gyro_scale, gs_scale=gs_scale,
                           sf_prior=sf_prior, resolution=record.resolution)
    checks = tuple(Check(c["test"], *_CHECKS[c["test"]], float(c["statistic"]),
                         float(c["low"]), float(c["high"]), c["reason_code"], c["message"])
                   for c in unc.checks)
    code = primary(unc.reason_codes)
    reverse = ([f"the roll rate reverses ({int(np.sum(res.rate > 0))} interval(s) turn one "
                f"way, {int(np.sum(res.rate < 0))} the other, {int(np.sum(res.reversal))} "
                "reverse inside and are left out of the mean: their net turn is small, their "
                "eps1_hat ill-conditioned); the rate is reported as mean |omega|"]
               if res.reverses else [])
    return Verdict(
        method="rsf", quantity="eps1_hat_mean", unit="1", estimate=unc.mean, sigma=unc.std,
        sigma_parts=dict(unc.parts), checks=checks, false_alarm=unc.false_alarm,
        status="ok" if unc.valid else "invalid",
        reason="; ".join(f"{c.line()}: {c.cause}" for c in checks if not c.passed),
        reason_codes=tuple(unc.reason_codes), reason_code=code,
        hint=hint(code) if code else "",
        counts=Counts(rows=res.rows, used=res.samples_used, rejected=0,
                      empty=res.rows - res.samples_used, rejected_means="left out"),
        notes=(*notes, *res.notes, *reverse, *unc.notes), result=res,
        details={"uncertainty": unc, "prediction": pred})
