"""Units and conventions checked at the door: records whose values are physically implausible
in SI raise :class:`~gyrolib.records.RecordError` naming the file, the column and the likely
unit mistake, before any filter runs.

Paper GC (:func:`check_gc`):

* **angle sensor** — after the feedback is switched off the float follows the nominal motion
  β_n(t) of Eq. (4); Eq. (5) drives the deviation ``Δβ`` by torques that the model's priors
  bound, so ``|Δβ'| ≤ (H/f) U`` with ``U = Ω_h |ψ| + |Ω_v| (|δ| + |γ|) + |ω_gc| + |ω_rnd| +
  |ω_ub| |N1|/g`` taken at ``k = 10`` prior standard deviations (inertia only slows the float
  down).  A sample is *beyond what the float can turn* when
  ``|β − β_n(t)| > (H/f) U t + k (σ_Δβ0 + σ_n)``, ``σ_n`` the angle noise (the model's
  ``√R₁₁`` or the column's own, whichever is larger).  When more than half of a block's
  samples are, or its median step exceeds 100 float time constants ``I/f`` (0.16 s for the
  paper's gyro), the block is refused, and the common mistakes are tried in turn — the time
  in milliseconds or microseconds, the angle in degrees, mrad, µrad or arcseconds — to name
  the one under which the record fits;
* **inclinometers** — the sample-to-sample noise (first differences, a robust median-based
  σ) is compared with the model's ``√(2 C_incl/h + Q1 h)`` at the record's median step ``h``
  (the sensor's white noise twice, and the vibration's increment: Eq. (6) drives N1 by white
  noise of intensity ``Q1`` directly): a ratio
  near ``1/g`` is a column in g (or an angle in rad) instead of m/s²; a reading whose median
  is beyond ``g sin 0.1`` (a tilt of 5.7°, far outside the small tilts Eq. (5) linearizes) is
  refused too, naming the vertical axis when it reads about ``g``.

A gyro's rate log (:func:`check_rate_log`, the ``allan`` command):

* **time** — a median step of 0.5 or more is a rate of 2 Hz or less in seconds, slow for a
  gyro's log, and a rate of 10 Hz to 2 kHz in milliseconds (a step from 100 to 10⁵: in
  microseconds), as gyro logs are sampled: refused, naming ``--time-unit ms`` (``us``), or
  ``--time-unit s`` for a log really sampled that slowly (the option states the unit, and
  the check then does not run).

Paper RSF (:func:`check_rsf`):

* **time** — a median step of at least 0.5 s in whole numbers fits milliseconds;
* **SINS against GS** — over the samples where both are known, the SINS turn (the sum of
  ``sins_increment``) and the GS turn (the change of ``gs_angle``, or of the wrapped encoder
  counts modulo a revolution plus ``gs_gyro_angle``) agree to the scale-factor errors
  (ppm–‰); they must agree within 1 % once the roll has turned a revolution, otherwise the
  ratio is matched against −1 (a sign convention), 180/π (degrees), 2π (revolutions), an
  accumulated instead of a per-sample ``sins_increment``, or the encoder's counts per
  revolution.
"""

from __future__ import annotations

import dataclasses
import math
from typing import TYPE_CHECKING, Final

import numpy as np

from gyrolib import _validation as v
from gyrolib.gc.logs.record import GCRecord
from gyrolib.gc.model.nominal import nominal_motion_aperiodic
from gyrolib.gc.model.params import GyrocompassParams
from gyrolib.records.errors import RecordError
from gyrolib.units import ARCSEC, ARCSEC_PAPER, DEG

if TYPE_CHECKING:    # imported when used: a GC run does not load paper RSF's package
    from gyrolib.rsf.record import RSFRecord

__all__ = ["ANGLE_PRIOR_SIGMAS", "angle_bound", "check_gc", "check_rate_log", "check_rsf",
           "noise_ratio"]

#: Prior standard deviations the bound on the float's deviation allows (k in the docstring).
ANGLE_PRIOR_SIGMAS: Final[float] = 10.0

#: Share of a block's samples beyond the bound that marks a unit mistake (not an outlier).
_BEYOND_SHARE: Final[float] = 0.5

#: Share of samples still beyond the bound under which a unit hypothesis "fits".
_FITS_SHARE: Final[float] = 0.01

#: Largest median step, in float time constants I/f, of a GC record in seconds.
_MAX_STEP_TIME_CONSTANTS: Final[float] = 100.0

#: Largest tilt (rad) the small-angle model of Eq. (5) is read with at the door.
_MAX_TILT: Final[float] = 0.1

#: Largest share of an RSF record's steps whose GS and SINS turns differ by more than π/4
#: that are read as wraps or slips (left to rsf.calibrate) rather than a unit mistake.
_JUMP_SHARE: Final[float] = 0.01

#: Agreement of the SINS and GS turns (relative) below which an RSF record passes.
_TURN_AGREEMENT: Final[float] = 0.01

#: (name, SI factor, the command line's unit option that reads it, or None).
_ANGLE_UNITS: Final[tuple[tuple[str, float, str | None], ...]] = (
    ("degrees", DEG, "--angle-unit deg"), ("milliradians", 1e-3, "--angle-unit mrad"),
    ("microradians", 1e-6, None), ("arcseconds", ARCSEC, "--angle-unit arcsec"),
    ("the paper's arcseconds", ARCSEC_PAPER, None))
_TIME_UNITS: Final[tuple[tuple[str, float, str | None], ...]] = (
    ("milliseconds", 1e-3, "--time-unit ms"), ("microseconds", 1e-6, "--time-unit us"))


# GC -------------------------------------------------------------------------------------
def angle_bound(params: GyrocompassParams, t: np.ndarray, *,
                k: float = ANGLE_PRIOR_SIGMAS, noise: float | None = None) -> np.ndarray:
    """The largest ``|β − β_n(t)|`` (rad) the float can reach at times ``t`` (s) under paper
    GC's model: ``(H/f) U t + k (σ_Δβ0 + σ_n)``, ``U`` the torque rate of Eq. (5) at ``k``
    prior standard deviations of ψ, δ, γ, ω_gc, the random drift and the vibration, ``σ_n``
    the angle sensor's noise (default the model's ``√R₁₁`` at ``params.dt``).

    Examples
    --------
    >>> from gyrolib.gc import GyrocompassParams
    >>> b = angle_bound(GyrocompassParams(), np.array([0.0, 100.0]))
    >>> [f"{x:.3g}" for x in b]
    ['0.000141', '0.00191']
    """
    p = v.check_instance("params", params, GyrocompassParams)
    t = np.asarray(t, dtype=float)
    sigma1 = math.sqrt(p.sigma1_sq)
    sigma2 = math.sqrt(p.sigma2_sq)
    u = k * (p.Omega_h * p.sigma_psi0 + abs(p.Omega_v) * (p.sigma_delta0 + p.sigma_gamma0)
             + p.sigma_gc0 + sigma2 + abs(p.omega_ub) * sigma1 / p.g)
    if noise is None:
        r11 = p.C_as / p.dt if p.measurement_noise == "intensity_over_dt" else p.C_as
        noise = math.sqrt(r11)
    return (p.H / p.f) * u * t + k * (p.sigma_dbeta0 + noise)


def _beyond(params: GyrocompassParams, t: np.ndarray, angle: np.ndarray,
            noise: float) -> np.ndarray:
    """Boolean: which samples are beyond what the float can turn."""
    beta_n = nominal_motion_aperiodic(params, np.maximum(t, 0.0)).beta
    return np.abs(angle - beta_n) > angle_bound(params, t, noise=noise)


def _median_step(t: np.ndarray) -> float:
    return float(np.median(np.diff(t))) if t.size > 1 else math.nan


def noise_ratio(values: np.ndarray, sigma_diff: float) -> float:
    """Sample-to-sample noise of ``values`` over the model's: the robust σ of the first
    differences (median absolute deviation / 0.6745) over ``sigma_diff``, the σ of a first
    difference the model predicts; NaN when fewer than 10 differences are known.

    Examples
    --------
    >>> rng = np.random.default_rng(0)                      # white noise of σ 3
    >>> f"{noise_ratio(3.0 * rng.standard_normal(20000), 3.0 * np.sqrt(2.0)):.2f}"
    '1.00'
    """
    d = np.diff(np.asarray(values, dtype=float))
    d = d[np.isfinite(d)]
    if d.size < 10:
        return math.nan
    mad = float(np.median(np.abs(d - np.median(d))))
    return mad / 0.6744897501960817 / sigma_diff


def _check_angle(label: str, rec: GCRecord, p: GyrocompassParams, where: str) -> None:
    ok = np.isfinite(rec.angle_sensor)
    if np.count_nonzero(ok) < 10:
        return
    step = _median_step(rec.t)
    # the angle sensor's noise: the model's at the record's step, or what the column shows
    # (first differences, robust), whichever is larger — a unit hypothesis rescales the latter
    model_noise = float(angle_bound(p, np.zeros(1), k=1.0)[0]) - p.sigma_dbeta0
    seen_noise = noise_ratio(rec.angle_sensor, math.sqrt(2.0))
    seen_noise = seen_noise if math.isfinite(seen_noise) else 0.0
    t, a = rec.t[ok], rec.angle_sensor[ok]
    # a few hundred samples spread over the block decide (the bound is smooth in t)
    pick = np.unique(np.linspace(0, t.size - 1, min(t.size, 2000)).astype(int))
    t, a = t[pick], a[pick]

    def share_beyond(tt, aa, scale: float = 1.0) -> float:
        noise = max(model_noise, scale * seen_noise)
        return float(np.mean(_beyond(p, tt, aa, noise)))

    beyond = _beyond(p, t, a, max(model_noise, seen_noise))
    share = float(np.mean(beyond))
    slow = step > _MAX_STEP_TIME_CONSTANTS * p.time_constant
    if share <= _BEYOND_SHARE and not slow:
        return
    for unit, factor, option in _TIME_UNITS:
        if (step * factor <= _MAX_STEP_TIME_CONSTANTS * p.time_constant
                and share_beyond(t * factor, a) <= _FITS_SHARE):
            raise RecordError(label, f"a median step of {step:.6g} and the last time "
                              f"{rec.t[-1]:.6g}{where} fit {unit}: read so, the angle sensor "
                              "follows the nominal motion β_n(t) of Eq. (4); expected t in s "
                              "since the feedback was switched off", column="t", hint=option)
    if slow:
        raise RecordError(label, f"a median step of {step:.6g} s{where} is more than "
                          f"{_MAX_STEP_TIME_CONSTANTS:g} float time constants (I/f = "
                          f"{p.time_constant:.3g} s): expected t in s, sampled fast enough "
                          "for the filter to follow the float", column="t")
    i = int(np.nonzero(beyond)[0][-1])
    bound = float(angle_bound(p, t[i:i + 1], noise=max(model_noise, seen_noise))[0])
    beta_n = float(nominal_motion_aperiodic(p, t[i:i + 1]).beta[0])
    share_text = (f"{100 * share:.0f} % of the samples{where} are farther from the nominal "
                  "motion β_n(t) of Eq. (4) than the float can turn")
    example = (f"e.g. at t = {t[i]:.6g} it reads {a[i]:.4g} where β_n = {beta_n:.4g} ± "
               f"{bound:.2g} rad")
    for unit, factor, option in _ANGLE_UNITS:
        if share_beyond(t, a * factor, factor) <= _FITS_SHARE:
            raise RecordError(label, f"{share_text} ({example}); read in {unit} it fits: "
                              "expected radians", column="angle_sensor", hint=option)
    raise RecordError(label, f"{share_text} ({example}): expected radians, with t in s since "
                      "the feedback was switched off (β = 0 then); if the gyro is not paper "
                      "GC's, give its parameters with --params", column="angle_sensor")


def _check_inclinometer(label: str, name: str, values: np.ndarray, step: float,
                        p: GyrocompassParams, c: float, where: str) -> None:
    x = values[np.isfinite(values)]
    if x.size < 10:
        return
    level = float(np.median(np.abs(x)))
    if level > p.g * math.sin(_MAX_TILT):
        hint = (f"it reads about g ({p.g:.4g} m/s²): the vertical axis?"
                if abs(level / p.g - 1.0) < 0.2 else
                f"a tilt of {math.degrees(math.asin(min(level / p.g, 1.0))):.3g}° is far "
                f"outside the small tilts Eq. (5) linearizes (< "
                f"{math.degrees(_MAX_TILT):.2g}°): units not m/s²?")
        raise RecordError(label, f"median |value|{where} {level:.4g}; {hint} expected the "
                          "specific force along the platform axis in m/s² (g · tilt + "
                          "vibration)", column=name)
    if not (math.isfinite(step) and step > 0):
        return
    # a first difference: twice the sensor's white noise R = C/h plus the vibration's own
    # increment (N1' = N2 + w1 of Eq. (6) carries white noise of intensity Q1 directly)
    r = c / step if p.measurement_noise == "intensity_over_dt" else c
    sigma = math.sqrt(2.0 * r + p.Q1 * step)
    rho = noise_ratio(values, sigma)
    if math.isfinite(rho) and 0.5 <= rho * p.g <= 2.0:
        raise RecordError(label, f"its sample-to-sample noise{where} is {rho:.3g} of the "
                          f"model's √(2C/h + Q1 h) = {sigma:.3g} m/s² (h = {step:.6g} s), "
                          "about 1/g: "
                          "in g (or an angle in rad) instead of m/s²? expected m/s²; if the "
                          "sensor really is this quiet, give its C_incl_y / C_incl_z with "
                          "--params", column=name, hint="--accel-unit g")


def check_gc(record: GCRecord, params: GyrocompassParams | None = None, *, label: str,
             rows: tuple[int, int] | None = None) -> None:
    """Refuse a paper-GC record (or a block of one) whose values are implausible in SI.

    Parameters
    ----------
    record : GCRecord
        The record or a block of it (times since the feedback was switched off).
    params : GyrocompassParams, optional
        The model the record will be calibrated with (default the paper's); the sample
        interval is the record's median step, not ``params.dt``.
    label : str
        The file, for the message.
    rows : (int, int), optional
        The block's first and last data row, for the message.

    Raises
    ------
    RecordError
        Naming the file, the column and the likely unit mistake.

    Examples
    --------
    >>> from gyrolib import gc
    >>> sim = gc.simulate_record(gc.GyrocompassParams(), 20.0, seed=1)
    >>> check_gc(sim.record, label="ok.csv")                # passes
    >>> r = sim.record
    >>> deg = gc.GCRecord(t=r.t, angle_sensor=np.degrees(r.angle_sensor),
    ...                   inclinometer_y=r.inclinometer_y, inclinometer_z=r.inclinometer_z)
    >>> try:
    ...     check_gc(deg, label="deg.csv")
    ... except RecordError as e:
    ...     print(e.column, "degrees" in str(e))
    angle_sensor True
    """
    p = GyrocompassParams() if params is None else v.check_instance(
        "params", params, GyrocompassParams)
    v.check_instance("record", record, GCRecord)
    where = "" if rows is None else f" of data rows {rows[0]}–{rows[1]}"
    step = _median_step(record.t)
    if math.isfinite(step) and step > 0 and p.measurement_noise == "intensity_over_dt":
        p = dataclasses.replace(p, dt=step)
    _check_angle(label, record, p, where)
    _check_inclinometer(label, "inclinometer_y", record.inclinometer_y, step, p, p.C_incl_y,
                        where)
    _check_inclinometer(label, "inclinometer_z", record.inclinometer_z, step, p, p.C_incl_z,
                        where)


# A gyro's rate log ------------------------------------------------------------------------
#: A median step (in the time column's unit) from which a gyro's rate log is refused as
#: likely milliseconds or microseconds (2 Hz or slower in seconds).
RATE_LOG_SLOW_STEP: Final[float] = 0.5

#: The sample rates (Hz) a gyro's log is taken to have when its time column is read in
#: milliseconds or microseconds instead of seconds.
_GYRO_RATES: Final[tuple[float, float]] = (10.0, 1e4)


def check_rate_log(t: np.ndarray, *, label: str) -> None:
    """Refuse a gyro's rate log whose time column fits milliseconds or microseconds: a
    median step of at least :data:`RATE_LOG_SLOW_STEP` (2 Hz or slower in seconds) that,
    read in ms (or µs), is a rate of 10 Hz to 10 kHz.  The refusal names ``--time-unit``
    (with ``s`` for a log really sampled that slowly).

    Raises
    ------
    RecordError
        Naming the file, the column ``t`` and the likely unit.

    Examples
    --------
    >>> check_rate_log(np.arange(100) * 0.01, label="ok.csv")     # 100 Hz in s: passes
    >>> try:
    ...     check_rate_log(np.arange(100) * 10.0, label="ms.csv")  # 100 Hz in ms
    ... except RecordError as e:
    ...     print(e.hint)
    --time-unit ms
    """
    t = np.asarray(t, dtype=float)
    step = _median_step(t)
    if not (math.isfinite(step) and step >= RATE_LOG_SLOW_STEP):
        return
    for unit, factor, option in _TIME_UNITS:
        rate = 1.0 / (step * factor)
        if _GYRO_RATES[0] <= rate <= _GYRO_RATES[1]:
            raise RecordError(label, f"a median step of {step:.6g} ({1.0 / step:.3g} Hz if "
                              f"in s, slow for a gyro's log) fits {unit} ({rate:.4g} Hz): "
                              f"expected t in s; give {option}, or --time-unit s if the log "
                              "really is sampled this slowly", column="t", hint=option)


# RSF ------------------------------------------------------------------------------------
def _gs_steps(record: RSFRecord) -> np.ndarray:
    """GS turn of each row over the previous one (NaN where unknown), as the record gives it:
    ``gs_angle`` differences, or the encoder step modulo one revolution plus the GS gyro."""
    out = np.full(record.n, np.nan)
    if record.gs_angle is not None:
        out[1:] = np.diff(record.gs_angle)
        return out
    n = int(record.counts_per_rev)
    d = np.diff(record.encoder_counts)
    ok = np.isfinite(d)
    step = np.full(d.shape, np.nan)
    step[ok] = np.mod(d[ok] + n // 2, n) - n // 2
    out[1:] = step * (2.0 * math.pi / n)
    if record.gs_gyro_angle is not None:
        out[1:] += np.diff(record.gs_gyro_angle)
    return out


def _near(x: float, target: float, rel: float = 0.05) -> bool:
    return math.isfinite(x) and abs(x - target) <= rel * abs(target)


def check_rsf(record: RSFRecord, *, label: str) -> None:
    """Refuse a paper-RSF record whose values are implausible in SI: a time column that fits
    milliseconds, or SINS and GS turns that disagree by more than 1 % (then the ratio names
    the likely mistake: a sign, degrees, revolutions, an accumulated increment, the encoder's
    counts per revolution).

    Raises
    ------
    RecordError
        Naming the file, the column and the likely unit mistake.

    Examples
    --------
    >>> from gyrolib.rsf import RSFRecord
    >>> t = np.arange(0, 1001) * 0.01                       # 10 s at 100 Hz, 900 °/s
    >>> gs = np.radians(900.0) * t
    >>> inc = np.concatenate([[0.0], np.diff(gs)]) * (1 + 600e-6)
    >>> check_rsf(RSFRecord(t=t, sins_increment=inc, gs_angle=gs), label="ok.csv")
    >>> try:
    ...     check_rsf(RSFRecord(t=t, sins_increment=np.degrees(inc), gs_angle=gs), label="x")
    ... except RecordError as e:
    ...     print(e.column, "degrees" in str(e))
    sins_increment True
    """
    from gyrolib.rsf.record import RSFRecord  # start-up: a GC run does not load paper RSF

    v.check_instance("record", record, RSFRecord)
    t = record.t
    step = _median_step(t)
    if math.isfinite(step) and step >= 0.5 and np.mean(t == np.round(t)) >= 0.99:
        raise RecordError(label, f"a median step of {step:.6g} in whole numbers over "
                          f"{t[-1] - t[0]:.6g}: milliseconds instead of seconds? expected t "
                          "in s (a SINS log holds many samples per second)", column="t",
                          hint="--time-unit ms")
    gs = _gs_steps(record)
    inc = record.sins_increment
    ok = np.isfinite(gs) & np.isfinite(inc)
    ok[0] = False
    # steps across a gap (rows missing: the GS turned through it, the SINS increment is one
    # sample's) and a few jumps of the GS angle (wraps, slips: rsf.calibrate unwraps or
    # refuses them, naming them) are not a unit mistake: left out of the comparison
    if math.isfinite(step):
        ok[1:] &= np.diff(t) <= 1.5 * step
    jump = ok & (np.abs(gs - inc) > math.pi / 4)
    if np.count_nonzero(jump) <= _JUMP_SHARE * np.count_nonzero(ok):
        ok &= ~jump
    turn_gs = float(np.sum(gs[ok]))
    if np.count_nonzero(ok) < 2 or abs(turn_gs) < 2.0 * math.pi:
        return   # less than a revolution: too little turn to compare
    turn_sins = float(np.sum(inc[ok]))
    ratio = turn_sins / turn_gs
    if abs(ratio - 1.0) <= _TURN_AGREEMENT:
        return
    gs_col = "gs_angle" if record.gs_angle is not None else "encoder_counts"
    seen = (f"the SINS turns {turn_sins:.6g} where the GS ({gs_col}) turns {turn_gs:.6g} over "
            f"the same samples, a ratio of {ratio:.5g} (expected 1 within "
            f"{100 * _TURN_AGREEMENT:g} %: scale-factor errors are ppm)")
    # an accumulated angle instead of increments: its own differences match the GS turn
    dinc = np.concatenate([[np.nan], np.diff(inc)])
    ok2 = ok & np.isfinite(dinc)
    acc = (float(np.sum(dinc[ok2])) / float(np.sum(gs[ok2]))
           if np.count_nonzero(ok2) > 1 and float(np.sum(gs[ok2])) != 0.0 else math.nan)
    hints: list[tuple[str, str]] = []
    if _near(ratio, -1.0, 0.02):
        hints.append(("sins_increment", "they turn in opposite directions: the sign "
                      "convention of sins_increment or of the GS angle; expected both "
                      "positive in the same roll sense"))
    elif _near(acc, 1.0, 0.02):
        hints.append(("sins_increment", "it looks like the accumulated roll angle, not the "
                      "increment over each sample; expected per-sample increments (rad)"))
    elif _near(ratio, 1.0 / DEG):
        hints.append(("sins_increment", "sins_increment in degrees? expected rad"))
    elif _near(ratio, DEG):
        hints.append((gs_col, "the GS angle in degrees? expected rad"
                      if gs_col == "gs_angle" else
                      "gs_gyro_angle in degrees? expected rad"))
    elif _near(ratio, 2.0 * math.pi):
        hints.append((gs_col, "the GS angle in revolutions? expected rad"))
    elif _near(ratio, 1.0 / (2.0 * math.pi)):
        hints.append(("sins_increment", "sins_increment in revolutions? expected rad"))
    if gs_col == "encoder_counts" and not hints:
        hints.append(("encoder_counts", f"is --counts-per-rev {record.counts_per_rev} the "
                      "encoder's? expected the counts of one revolution"))
    if not hints:
        hints.append(("sins_increment", "expected both in rad, the SINS increment over each "
                      "sample and the GS angle in the same roll sense"))
    column, hint = hints[0]
    raise RecordError(label, f"{seen}; {hint}", column=column)

