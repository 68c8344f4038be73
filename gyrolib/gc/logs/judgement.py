"""Paper GC on a record, judged: from a record to one :class:`gyrolib.verdict.Verdict`
(:func:`judge_record`).

The filter (:func:`gyrolib.gc.calibrate`) gives the estimate and its evidence; this module
decides what the evidence makes of it: the status (``ok``, ``misfit`` on request,
``invalid``), the reason and its codes (:func:`evidence_codes`, the table
:data:`gyrolib.reasons.REASONS`), the hint, σ(ω_gc) with every named term (the filter's
three parts and, with a noise fit, the fit's own, :func:`gyrolib.gc.fit_uncertainty`),
every check with its one band, and the counts of the rows.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence
from concurrent.futures import Executor
from typing import Final

import numpy as np

from gyrolib import _validation as v
from gyrolib.gc.logs.calibration import CalibrationResult, calibrate, earth_rate_mismatch
from gyrolib.gc.logs.noise_fit import (
    NoiseFit,
    fit_checks,
    fit_noise,
    fit_uncertainty,
    profile_intervals,
)
from gyrolib.gc.logs.record import GCRecord
from gyrolib.gc.logs.site import equator_note, latitude_drift_sigma
from gyrolib.gc.model.params import MEASUREMENT_NAMES, PAPER_LATITUDE, GyrocompassParams
from gyrolib.gc.model.state_space import measurement_noise_covariance
from gyrolib.reasons import hint, primary
from gyrolib.resolution import describe_step
from gyrolib.verdict import Check, Counts, Verdict

__all__ = ["EARLY_SHARE", "NO_LATITUDE", "cause_code", "evidence_codes", "judge_record",
           "quantization_notes"]

#: Share of the record's start (from its first row) within which gate rejections point to
#: rows logged before the feedback was switched off (``early_release``).
EARLY_SHARE: Final[float] = 0.1

#: The reason of a record calibrated without a stated latitude (no valid estimate).
NO_LATITUDE: Final[str] = (
    "no latitude given (--latitude, a 'latitude' key in --params, or a '# latitude_deg:' "
    "line in the record); the paper's Omega_h, Omega_v correspond to about "
    f"{math.degrees(PAPER_LATITUDE):.1f} deg N (--latitude paper assumes them)")

#: The codes of checks that a lost lock makes meaningless (not named as the cause then).
_SYMPTOMS: Final[tuple[str, ...]] = ("prior_", "misfit", "drift_changes")

#: What each kind of the filter's model tests computes (the check's ``statistic``).
_STATISTIC: Final[dict[str, str]] = {
    "mean NIS": "mean of nu^2/S", "whiteness": "portmanteau Q", "split-record":
    "z = (estimate at t - final)/sqrt(P(t) - P_final)", "prior": "estimate/sqrt(P0 - P)"}


def evidence_codes(res: CalibrationResult, latitude_stated: bool, fit_why: str = ""
                   ) -> tuple[list[str], float | None]:
    """The reason codes (keys of :data:`gyrolib.reasons.REASONS`) of a run that is not
    valid, read from its evidence rather than its message, and the time stamp ``--t0``
    should start from when the evidence is an early release (else None).

    * ``no_latitude``: no Earth rate stated; ``latitude_mismatch``: the params' Earth rate
      is not the one at the record's stated latitude;
    * ``early_release``: the gate's rejections crowd the record's start: at least three,
      and at least three times as many in the first :data:`EARLY_SHARE` of the record as
      that share of all rejected rows (rows logged before the feedback switch-off); the
      suggested ``--t0`` is the end of their first cluster (no gap over 0.5 s), rounded up
      to 0.1 s;
    * ``lost_lock``: a sensor's share of rejections beyond ``max_rejected`` or its mean NIS
      outside ``nis_range``;
    * ``drift_changes``: a split-record test failed; ``misfit``: a mean-NIS or whiteness
      test failed;
    * ``fit_not_converged``, ``fit_not_identified``: from ``fit_why``
      (:meth:`gyrolib.gc.NoiseFit.not_identified`).

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import gc
    >>> p = gc.GyrocompassParams()
    >>> t = np.arange(1, 201) * p.dt
    >>> rec = gc.GCRecord(t=t, angle_sensor=gc.nominal_motion(p, t).beta,
    ...                   inclinometer_y=np.zeros(200), inclinometer_z=np.zeros(200))
    >>> evidence_codes(gc.calibrate(rec, p), latitude_stated=False)[0][:2]
    ['no_latitude', 'lost_lock']
    """
    codes: list[str] = []
    if not latitude_stated:
        codes.append("no_latitude")
    if res.record_latitude is not None and earth_rate_mismatch(res.params,
                                                               res.record_latitude):
        codes.append("latitude_mismatch")
    t0 = None
    rt = np.unique(np.asarray(res.rejected_t, dtype=float))
    start = float(res.t[0]) if res.t.size else 0.0
    span = max(float(res.t_final) - start, 0.0)
    early = rt[rt <= start + EARLY_SHARE * span] if span > 0.0 else rt[:0]
    if early.size >= 3 and early.size >= 3.0 * EARLY_SHARE * max(int(res.rows_rejected), 1):
        # the rejections crowd the record's start: three times their share of it or more
        gaps = np.flatnonzero(np.diff(early) > 0.5)
        end = float(early[gaps[0]] if gaps.size else early[-1])
        codes.append("early_release")
        t0 = math.ceil(10.0 * end) / 10.0
    lo, hi = res.nis_range
    nis = res.nis_mean
    if (np.any(res.rejected_share > res.max_rejected)
            or np.any((res.used > 0) & ~((nis >= lo) & (nis <= hi)))):
        codes.append("lost_lock")
    for tst in res.model_tests():
        if not tst["passed"]:
            code = ("drift_changes" if tst["test"].startswith("split-record") else
                    "lost_lock" if tst.get("reason_code") == "lost_lock_nis" else "misfit")
            if code not in codes:
                codes.append(code)
    if fit_why:
        codes.append("fit_not_converged" if fit_why.startswith("noise fit not converged")
                     else "fit_not_identified")
    return codes, t0


def cause_code(codes: Sequence[str], lost_lock: bool) -> str:
    """The code the evidence points to first (:func:`gyrolib.reasons.primary`); when the
    filter lost lock, its prior and model checks are its symptoms and are not named: the
    option a failed prior names (a bias prior, a tolerance) would mask the fault (a sign, a
    unit, a sensor that is not the model's).

    Examples
    --------
    >>> cause_code(["lost_lock", "prior_incl_bias"], lost_lock=True)
    'lost_lock'
    >>> cause_code(["misfit", "prior_incl_bias"], lost_lock=False)
    'prior_incl_bias'
    """
    return primary([c for c in codes if not (lost_lock and c.startswith(_SYMPTOMS))])


def _model_checks(res: CalibrationResult) -> list[Check]:
    """The filter's checks as :class:`Check` objects: each sensor's gate rejections (the
    lock), then :meth:`CalibrationResult.model_tests` (each with its one band)."""
    out = [Check("gate rejections", name, "share of its samples rejected",
                 float(res.rejected_share[q]), 0.0, float(res.max_rejected), "lost_lock_gate")
           for q, name in enumerate(("angle_sensor", "inclinometer_y", "inclinometer_z"))
           if res.used[q] + res.rejected[q] > 0]
    for t in res.model_tests():
        kind = t["test"]
        if kind == "mean NIS":
            test, subject = kind, t["sensor"]
        elif kind.startswith("whiteness"):
            test, subject = kind, t["sensor"]
        elif kind.startswith("split-record"):
            test, subject = "split-record" + kind[len("split-record omega_gc"):], "omega_gc"
        else:
            test, subject = "prior", t["constant"]
        out.append(Check(test, subject, _STATISTIC[test.split(" (")[0]],
                         float(t["statistic"]), float(t["low"]), float(t["high"]),
                         t["reason_code"], t.get("cause", "")))
    return out


def _fit_check(c: dict) -> Check | None:
    """A check of :func:`gyrolib.gc.fit_checks` as a :class:`Check` whose value in its band
    is the check's pass: the plausible range tests the end of the fitted value's interval
    nearest the range; the common-factor test, when the intensities share one, its z (when
    they move apart it does not apply: None).

    Examples
    --------
    >>> _fit_check({"test": "plausible range", "name": "C_as", "statistic": 5.0, "low": 1.0,
    ...             "high": 4.0, "passed": True, "reason_code": "fit_implausible",
    ...             "message": ""}).passed             # its interval reaches the range
    True
    """
    if c["test"] == "plausible range":
        lo, hi, val = c["low"], c["high"], c["statistic"]
        near = lo if val < lo else hi if val > hi else val
        shown = near if c["passed"] else val
        return Check("plausible range", c["name"], "fitted value's interval end nearest "
                     "the range", float(shown), float(lo), float(hi), c["reason_code"],
                     c["message"])
    if not c["passed"] or abs(c["statistic"]) <= c["high"]:
        return Check("absorbed misfit", c["name"], "log common factor/sigma",
                     float(c["statistic"]), float(c["low"]), float(c["high"]),
                     c["reason_code"], c["message"])
    return None


def quantization_notes(res: CalibrationResult) -> list[str]:
    """A sentence per coarse sensor column (:attr:`CalibrationResult.measurement_steps`):
    its step, and the share of the sensor's measurement noise its rounding (``step²/12``)
    is, which the filter carried; with a warning where the step exceeds twice the noise's
    standard deviation, where the rounding repeats from sample to sample instead of being
    white (the filter's model of it).

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import gc
    >>> p = gc.GyrocompassParams()
    >>> r = gc.simulate_record(p, 0.5, seed=1).record
    >>> q = 1e-5
    >>> rec = gc.GCRecord(t=r.t, angle_sensor=np.round(r.angle_sensor / q) * q,
    ...                   inclinometer_y=r.inclinometer_y, inclinometer_z=r.inclinometer_z)
    >>> quantization_notes(gc.calibrate(rec, p))[0][:59]
    'angle_sensor is recorded in steps of 1e-05 rad (5 decimals)'
    """
    steps = res.measurement_steps
    if steps is None:
        return []
    r = np.diag(measurement_noise_covariance(res.params))
    out = []
    for q, name in enumerate(MEASUREMENT_NAMES):
        step = float(steps[q])
        if step <= 0.0:
            continue
        var = step * step / 12.0
        unit = "rad" if name == "angle_sensor" else "m/s^2"
        text = (f"{name} is recorded in steps of {describe_step(step, unit)}: its "
                f"rounding, step^2/12, is {100 * var / (r[q] + var):.3g} % of that sensor's "
                "measurement noise, carried in the filter")
        if step > 2.0 * math.sqrt(r[q]):
            text += (f"; the step exceeds twice the noise's standard deviation "
                     f"({math.sqrt(r[q]):.3g}), so the rounding is not white, as the filter "
                     "takes it: a finer recording is needed for a result to trust")
        out.append(text)
    return out


def _noise_fit(record: GCRecord, params: GyrocompassParams, names: Sequence[str],
               progress: Callable[[int], None] | None, options: dict
               ) -> tuple[CalibrationResult, NoiseFit]:
    """The run before the fit (its misfit is what a fit must not merely absorb) and the
    fit with each parameter's 95 % likelihood-ratio interval."""
    unfitted = calibrate(record, params, **options)
    # fit_noise's own gate (a far tail: a gate as tight as the calibration's would cut good
    # samples and bias the intensities low)
    fit = fit_noise(record, params, fit=tuple(names), progress=progress)
    return unfitted, profile_intervals(record, fit)


def _latitude_part(params: GyrocompassParams, latitude_sigma: float) -> dict[str, float]:
    """σ(ω_gc)'s term of the latitude's uncertainty, ``{}`` when none is stated."""
    return {"latitude": latitude_drift_sigma(params, latitude_sigma)} if latitude_sigma else {}


def judge_record(record: GCRecord | Iterable[GCRecord],
                 params: GyrocompassParams | None = None, *, latitude_stated: bool = True,
                 latitude_sigma: float = 0.0,
                 fit: Sequence[str] | None = None, accept_misfit: bool = False,
                 gate: float = 0.9999, store_every: int = 100, max_rejected: float = 0.01,
                 false_alarm: float = 0.01, notes: Iterable[str] = (),
                 progress: Callable[[int], None] | None = None,
                 fit_progress: Callable[[int], None] | None = None,
                 executor: Executor | None = None) -> Verdict:
    """Calibrate the drift ω_gc from a record and judge the result (paper GC, Eq. (8)).

    Runs :func:`gyrolib.gc.calibrate` (with ``fit``, first the noise fit:
    :func:`gyrolib.gc.fit_noise`, :func:`gyrolib.gc.profile_intervals`, and the fit's
    checks, :func:`gyrolib.gc.fit_checks`) and decides:

    * ``ok`` when the Earth rate is stated (``latitude_stated``: Ω_h reads as drift, so
      without a stated latitude there is no result), the filter kept lock, every model
      check passes and the fit (if any) converged and passed its checks;
    * ``misfit`` when only model checks fail and ``accept_misfit`` asks for the estimate
      anyway (marked: σ may not cover the truth);
    * ``invalid`` otherwise.

    σ(ω_gc) holds the filter's parts (``noise``, ``instrument_biases``, ``scale``,
    :attr:`CalibrationResult.omega_gc_std_parts`), with a fit ``noise_fit``: what the
    fitted values' own uncertainty adds (:func:`gyrolib.gc.fit_uncertainty`, in
    quadrature), and with a latitude uncertainty ``latitude``
    (:func:`gyrolib.gc.latitude_drift_sigma`: Ω_h reads as drift).  A site near the
    equator gets a note of what the method still estimates there
    (:func:`gyrolib.gc.equator_note`).

    Parameters
    ----------
    record : GCRecord or iterable of GCRecord
        As for :func:`gyrolib.gc.calibrate`; a :class:`GCRecord` in memory with ``fit``.
    params : GyrocompassParams, optional
        The model, its Earth rate stated for the site (default: the paper's).
    latitude_stated : bool
        Whether ``params``' Earth rate is the site's, stated by the user or the record.
    latitude_sigma : float
        1σ uncertainty (rad) of the stated latitude, carried into σ(ω_gc) as the term
        ``latitude`` when > 0.
    fit : sequence of str, optional
        Noise parameters to fit to the record first (:data:`gyrolib.gc.NOISE_FIT_NAMES`).
    accept_misfit : bool
        Give the estimate of a record whose model checks fail, status ``misfit``.
    gate, store_every, max_rejected, false_alarm, progress, executor
        As for :func:`gyrolib.gc.calibrate`.
    notes : iterable of str
        Sentences on the record (its reading) to keep in the verdict's notes, first.
    fit_progress : callable, optional
        Called with the number of likelihood evaluations of the fit.

    Returns
    -------
    Verdict
        ``result`` the :class:`CalibrationResult`; ``details``: ``noise_fit`` (the
        :class:`NoiseFit` or None), ``unfitted`` (the run before the fit or None),
        ``noise_fit_checks`` (the failed checks of the fit, dicts), ``t0_hint`` (the
        ``--t0`` an early release suggests, or None).

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import gc
    >>> p = gc.GyrocompassParams()
    >>> t = np.arange(1, 201) * p.dt                     # 0.2 s of a gyro at rest in β_n
    >>> rec = gc.GCRecord(t=t, angle_sensor=gc.nominal_motion(p, t).beta,
    ...                   inclinometer_y=np.zeros(200), inclinometer_z=np.zeros(200))
    >>> ver = gc.judge_record(rec, p)
    >>> ver.status, ver.reason_code, ver.counts.rows
    ('invalid', 'lost_lock', 200)
    >>> ver.hint[:15]
    'try: --params ('
    """
    v.check_bool("latitude_stated", latitude_stated)
    v.check_nonnegative("latitude_sigma", latitude_sigma)
    v.check_bool("accept_misfit", accept_misfit)
    options = {"gate": gate, "store_every": store_every, "max_rejected": max_rejected,
               "false_alarm": false_alarm}
    out_notes = [str(n) for n in notes]
    nf = unfitted = None
    if fit is not None:
        if not isinstance(record, GCRecord):
            raise TypeError("record must be a GCRecord in memory to fit the noise; got "
                            f"{type(record).__name__}")
        unfitted, nf = _noise_fit(record, GyrocompassParams() if params is None else params,
                                  fit, fit_progress, options)
        params = nf.params
    res = calibrate(record, params, progress=progress, executor=executor, **options)
    reasons = [] if latitude_stated else [NO_LATITUDE]
    reasons += [res.reason] if res.reason else []
    why, ident, made, failed, fit_std = "", "", [], [], 0.0
    if nf is not None:
        duration = float(record.t[-1] - record.t[0]) if record.n > 1 else 1e-9
        ident = nf.not_identified(duration)
        made = fit_checks(nf, unfitted, clock_tolerance=res.params.sigma_clock,
                          false_alarm=false_alarm)
        failed = [c for c in made if not c["passed"]]
        out_notes += nf.nuisance(duration)
        why = ident or "; ".join(c["message"] for c in failed)
        if why:
            reasons.append(f"noise fit: {why}")
        else:
            total = fit_uncertainty(record, nf, at_fit=res, gate=gate,
                                    max_rejected=max_rejected, false_alarm=false_alarm)
            fit_std = math.sqrt(max(total**2 - res.omega_gc_std**2, 0.0))
    valid = not reasons
    codes, t0 = ([], None) if valid else evidence_codes(res, latitude_stated, ident)
    if not valid:   # the library's codes (its prior and model checks) and the fit's checks
        codes += [c for c in (*res.reason_codes, *(c["reason_code"] for c in failed))
                  if c not in codes]
    code = cause_code(codes, res.lost_lock)
    accepted = (not valid and accept_misfit and not res.lost_lock and latitude_stated
                and not why)
    parts = dict(res.omega_gc_std_parts)
    if nf is not None:
        parts["noise_fit"] = fit_std
    parts.update(_latitude_part(res.params, latitude_sigma))
    out_notes += [n for n in (equator_note(res.params),) if n]
    checks = _model_checks(res) + [c for c in map(_fit_check, made) if c is not None]
    return Verdict(
        method="gc", quantity="omega_gc", unit="rad/s", estimate=res.omega_gc,
        sigma=math.sqrt(sum(x * x for x in parts.values())), sigma_parts=parts,
        checks=tuple(checks), false_alarm=res.false_alarm,
        status="ok" if valid else ("misfit" if accepted else "invalid"),
        reason="; ".join(reasons), reason_codes=tuple(codes), reason_code=code,
        hint=hint(code, f"{t0:g}" if code == "early_release" and t0 else "") if code else "",
        counts=Counts(rows=res.rows, used=res.rows_used, rejected=res.rows_rejected,
                      empty=res.rows - res.rows_used - res.rows_rejected,
                      missing=int(res.missing.sum())),
        notes=(*out_notes, *quantization_notes(res)), result=res,
        details={"noise_fit": nf, "unfitted": unfitted, "noise_fit_checks": failed,
                 "t0_hint": t0})
