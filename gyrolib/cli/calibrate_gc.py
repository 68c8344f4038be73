"""Paper GC's run of the ``calibrate`` command on one record: its options checked
(:func:`options`), the record read (streamed in chunks, or whole for ``--fit-noise`` and
``--allan``), the Earth rate stated (``--latitude``, the params file or the record's line),
the filter run, and the report as text, JSON and a summary row (:func:`run_file`).  See
:mod:`gyrolib.cli.calibrate` for the command's behaviour."""

from __future__ import annotations

import argparse
import concurrent.futures
import dataclasses
import math
from typing import Final

import numpy as np

from gyrolib import gc, units
from gyrolib.cli import constants, hints
from gyrolib.cli.constants import FIT_UNITS, PLOT_SUFFIXES
from gyrolib.cli.outputs import Outcome, bar_enabled, check_out_path, fmt, progress
from gyrolib.gc.model.params import PAPER_LATITUDE
from gyrolib.records.errors import OptionError
from gyrolib.records.params import (
    NORTHERN_ONLY,
    gc_params_from_toml,
    instrument_notes,
    load_toml,
)
from gyrolib.records.reader import GCChunks, read_gc

__all__ = ["LAT_NONE", "LAT_OPTION", "LAT_PAPER", "LAT_PARAMS", "LAT_RECORD", "NO_LATITUDE",
           "options", "run_file"]


def options(args: argparse.Namespace) -> dict:
    """Checked options of ``calibrate gc`` (OptionError / RecordError on a bad one)."""
    if not 0.0 < args.gate < 1.0:
        raise OptionError(f"--gate must be a probability in (0, 1); got {args.gate}")
    if args.store_every < 1:
        raise OptionError(f"--store-every must be >= 1; got {args.store_every}")
    if not 0.0 <= args.max_rejected < 1.0:
        raise OptionError(f"--max-rejected must be a share in [0, 1); got {args.max_rejected}")
    try:
        mapping = gc.InclinometerMapping.parse(args.inclinometers)
    except ValueError:
        raise OptionError(f"--inclinometers expects two of y, z, -y, -z separated by a comma, "
                         f"each column once (e.g. y,z or z,y or -y,z); got "
                         f"{args.inclinometers!r}") from None
    fit = tuple(s.strip() for s in args.fit.split(",") if s.strip())
    unknown = [s for s in fit if s not in FIT_UNITS]
    if not fit or unknown or ("C_in" in fit and ({"C_incl_y", "C_incl_z"} & set(fit))):
        raise OptionError(f"--fit expects names among {', '.join(FIT_UNITS)} (C_in not with "
                         f"C_incl_y, C_incl_z), comma-separated; got {args.fit!r}")
    batch = len(args.files) > 1
    for opt, val in (("--plot", args.plot), ("--allan", args.allan),
                     ("--fit-noise OUT.toml", args.fit_noise or None)):
        if batch and val:
            raise OptionError(f"{opt} writes one file: give one record, not {len(args.files)} "
                             "(--summary OUT.csv reports a batch)")
    check_out_path(args.plot, PLOT_SUFFIXES, "a plot")
    check_out_path(args.allan, PLOT_SUFFIXES, "a plot")
    check_out_path(args.fit_noise or None, (".toml",), "a TOML")
    params = gc_params_from_toml(args.params)
    toml = load_toml(args.params) if args.params is not None else {}
    dt_given = "dt" in toml
    if not (math.isfinite(args.false_alarm) and 0.0 < args.false_alarm < 1.0):
        raise OptionError(f"--false-alarm must be a probability in (0, 1); got "
                         f"{args.false_alarm}")
    # defaults: the table of inputs' (an instrument error's largest plausible value, stored
    # with the package: gyrolib.cli.constants; the drift prior's reference, the field's
    # default), in SI; an option in its unit
    mg = 1e-3 * units.G0
    priors = {}
    for opt, field, val, default, unit in (
            ("--scale-tolerance", "sigma_hf_scale", args.scale_tolerance,
             constants.DEFAULT_SCALE_TOLERANCE, 1.0),
            ("--offset-prior", "sigma_as_offset", args.offset_prior,
             constants.DEFAULT_OFFSET_PRIOR_ARCSEC * units.ARCSEC_PAPER, units.ARCSEC_PAPER),
            ("--inclinometer-bias-prior", "sigma_incl_bias", args.inclinometer_bias_prior,
             constants.DEFAULT_INCL_BIAS_PRIOR_MG * mg, mg),
            ("--drift-prior", "sigma_gc0", args.drift_prior,
             gc.GyrocompassParams().sigma_gc0, units.DEG_PER_HOUR),
            ("--clock-tolerance", "sigma_clock", args.clock_tolerance,
             constants.DEFAULT_CLOCK_TOLERANCE, 1.0)):
        if val is not None and not (math.isfinite(val) and val >= 0.0):
            raise OptionError(f"{opt} must be a number >= 0; got {val}")
        if val is None and field in toml:     # the params file states it
            continue
        priors[field] = default if val is None else val * unit
    if priors.get("sigma_gc0", 1.0) <= 0.0:
        raise OptionError("--drift-prior must be > 0 (a drift known to be exactly 0 is not "
                          "calibrated)")
    params = dataclasses.replace(params, **priors)
    latitude, lat_source = None, LAT_NONE
    if args.latitude is not None:
        if {"Omega_h", "Omega_v", "latitude"} & set(toml):
            raise OptionError("--latitude and the params file's latitude/Omega_h/Omega_v both "
                             "set the Earth rate: give one")
        if args.latitude.strip().lower() == "paper":
            latitude, lat_source = math.degrees(PAPER_LATITUDE), LAT_PAPER
        else:
            try:
                latitude = float(args.latitude)
            except ValueError:
                latitude = math.nan
            if not (math.isfinite(latitude) and 0.0 < latitude < 90.0):
                raise OptionError(f"--latitude must be in degrees north in (0, 90), or 'paper' "
                                  f"for paper GC's values: {NORTHERN_ONLY}; got "
                                  f"{args.latitude}")
            lat_source = LAT_OPTION
            params = gc.GyrocompassParams.at_latitude(
                math.radians(latitude), **{k: getattr(params, k) for k in
                                           (f.name for f in dataclasses.fields(params))
                                           if k not in ("Omega_h", "Omega_v")})
    elif "latitude" in toml:
        latitude, lat_source = float(toml["latitude"]), LAT_PARAMS
    elif {"Omega_h", "Omega_v"} <= set(toml):   # the Earth rate stated by its components
        latitude = math.degrees(math.atan2(params.Omega_v, params.Omega_h))
        lat_source = LAT_PARAMS
    elif {"Omega_h", "Omega_v"} & set(toml):    # half an Earth rate: the other the paper's?
        given, = {"Omega_h", "Omega_v"} & set(toml)
        raise OptionError(f"{args.params} sets {given} but not "
                         f"{({'Omega_h', 'Omega_v'} - {given}).pop()}: give both Earth-rate "
                         "components, or 'latitude' (degrees north), or neither")
    return {"params": params, "dt_given": dt_given, "gate": args.gate,
            "latitude": latitude, "latitude_source": lat_source,
            "false_alarm": args.false_alarm, "accept_misfit": args.accept_misfit,
            "store_every": args.store_every, "max_rejected": args.max_rejected,
            "mapping": mapping, "fit_noise": args.fit_noise, "fit": fit,
            "allan": args.allan, "plot": args.plot, "json": args.json,
            "params_notes": instrument_notes(args.params, "calibrate gc"),
            "bar": bar_enabled(args) and not batch}


#: ``latitude_source`` of the JSON: where the latitude (the Earth rate) came from.
LAT_OPTION: Final[str] = "option"
LAT_PARAMS: Final[str] = "params"
LAT_RECORD: Final[str] = "record header"
LAT_PAPER: Final[str] = "paper (assumed by --latitude paper)"
LAT_NONE: Final[str] = "none"
#: The reason of a record calibrated without a stated latitude (no valid estimate).
NO_LATITUDE: Final[str] = (
    "no latitude given (--latitude, a 'latitude' key in --params, or a '# latitude_deg:' "
    "line in the record); the paper's Omega_h, Omega_v correspond to about "
    f"{math.degrees(PAPER_LATITUDE):.1f} deg N (--latitude paper assumes them)")


def _with_step(params: gc.GyrocompassParams, t: np.ndarray, notes: list[str],
               dt_given: bool) -> gc.GyrocompassParams:
    """``params`` with ``dt`` the record's median step (unless the TOML file gave one)."""
    if dt_given or t.size < 2:
        return params
    step = float(f"{float(np.median(np.diff(t))):.9g}")
    if abs(step - params.dt) > 1e-6 * params.dt:
        notes.append(f"dt = {step:g} s taken from the record's median step")
        return dataclasses.replace(params, dt=step)
    return params


#: Spread of the steps around the median step (relative) above which jitter is reported.
_JITTER_NOTED: Final[float] = 1e-3


def _jitter(t: np.ndarray) -> tuple[float, float, float] | None:
    """(median step, largest and standard deviation of the steps' departure from it) over
    the regular steps (gaps, longer than 1.5 median steps, left out), or None when the
    steps depart by less than :data:`_JITTER_NOTED` of the median step."""
    if t.size < 3:
        return None
    h = np.diff(t)
    m = float(np.median(h))
    dev = h[h < 1.5 * m] - m
    if dev.size < 2 or float(np.max(np.abs(dev))) <= _JITTER_NOTED * m:
        return None
    return m, float(np.max(np.abs(dev))), float(np.std(dev))


def _time_notes(info, record, params, notes: list[str]) -> dict:
    """Notes on the time base (an absolute clock taken relative) and on time-stamp jitter,
    with what jitter does to paper GC's fit test; returns their JSON fields."""
    out: dict = {"time_base": info.summary() if info is not None else None}
    if info is not None:
        notes.extend(info.notes)
    jit = _jitter(record.t)
    if jit is None:
        return out
    step, dev_max, dev_sd = jit
    # a stamp off by δt makes the model compare the angle reading with β(t + δt): an error
    # of β' δt; β' read off the record over blocks of 100 rows (the sensor noise averaged)
    a, t = record.angle_sensor[::100], record.t[::100]
    ok = ~np.isnan(a)
    rate = (float(np.median(np.abs(np.diff(a[ok]) / np.diff(t[ok])))) if ok.sum() > 2
            else 0.0)
    stamp_sd = dev_sd / math.sqrt(2.0)    # a step's departure holds two stamps' errors
    sigma_as = math.sqrt(float(gc.measurement_noise_covariance(params)[0, 0]))
    ratio = rate * stamp_sd / sigma_as
    notes.append(
        f"time-stamp jitter: steps depart from the median step {step:.6g} s by up to "
        f"±{dev_max:.3g} s (σ {dev_sd:.3g} s, {100 * dev_sd / step:.2g} % of the step).  The "
        f"filter steps by each row's own interval: right when the samples were taken at "
        f"their stamps; if the samples were regular and only the stamps jitter, each angle "
        f"reading is compared with the model {stamp_sd:.2g} s off, an error β'δt ≈ "
        f"{rate * stamp_sd:.2g} rad = {ratio:.2g} × the angle sensor's noise σ, which raises "
        f"its mean NIS by up to about {ratio ** 2:.2g} and can fail the fit test on its own")
    out["timestamp_jitter"] = {"median_step_s": step, "step_departure_max_s": dev_max,
                               "step_departure_std_s": dev_sd,
                               "angle_error_if_stamps_only_rad": rate * stamp_sd,
                               "ratio_to_angle_noise": ratio}
    return out


#: Display units of the Allan noise terms: (SI factor, unit) per series and slope.
_ALLAN_UNITS: Final[dict[str, tuple[tuple[float, str], ...]]] = {
    "angle_sensor": ((units.UNITS["deg/sqrt_h"], "deg/sqrt(h)"),
                     (units.DEG_PER_HOUR, "deg/h"),
                     (units.DEG_PER_HOUR / 60.0, "deg/h/sqrt(h)")),
    "inclinometer": ((1.0 / 60.0, "m/s/sqrt(h)"), (units.G0 * 1e-6, "ug"),
                     (1.0 / 3600.0 / 60.0, "m/s/h/sqrt(h)")),
}


def _allan_report(allan) -> tuple[list[str], dict]:
    """Lines and JSON of the noise terms of each Allan deviation (IEEE Std 952)."""
    terms = gc.allan_noise_terms(allan)
    lines = [f"  Allan deviation over {allan.rows} rows ({allan.t_start:.6g} to "
             f"{allan.t_end:.6g} s), noise terms (IEEE Std 952, fit of the Allan variance, "
             "1 sigma; '<=' an upper bound):"]
    data: dict = {}
    for name, ts in terms.items():
        shown = _ALLAN_UNITS["angle_sensor" if name == "angle_sensor" else "inclinometer"]
        what = "angle-sensor rate" if name == "angle_sensor" else name
        lines.append(f"    {what}: " + "; ".join(
            t.describe(scale, unit) for t, (scale, unit) in zip(ts, shown)))
        data[name] = [{"name": t.name, "value": t.value, "sigma": t.sigma, "lo": t.lo,
                       "hi": t.hi, "unit": t.unit.replace("·", "*").replace("√", "sqrt"),
                       "identified": t.identified, "tau_s": t.tau} for t in ts]
    return lines, data


def _calibrate(record, params, o: dict, progress=None, executor=None):
    return gc.calibrate(record, params, gate=o["gate"], store_every=o["store_every"],
                        max_rejected=o["max_rejected"], false_alarm=o["false_alarm"],
                        progress=progress, executor=executor)


def _with_latitude(params: gc.GyrocompassParams, record_latitude: float | None, o: dict,
                   notes: list[str]) -> tuple[gc.GyrocompassParams, dict]:
    """The Earth rate stated, never assumed: from --latitude or the params file (already in
    ``params``), else the record's latitude (rad), else none: paper GC's values are used
    for the estimate, which is then not valid (``"stated": False``; :data:`NO_LATITUDE`).
    ``--latitude paper`` states paper GC's values.  An option or params file that disagrees
    with the record's ``# latitude_deg:`` line wins, and a note says both."""
    lat, source = o["latitude"], o["latitude_source"]
    rec_deg = None if record_latitude is None else math.degrees(record_latitude)
    if source == LAT_NONE and record_latitude is not None:
        if not 0.0 < record_latitude < math.pi / 2:
            raise ValueError(f"the record's latitude {rec_deg:g} deg is outside (0, 90) deg "
                             f"N: {NORTHERN_ONLY}")
        lat, source = rec_deg, LAT_RECORD
        params = dataclasses.replace(params, **{
            k: getattr(gc.GyrocompassParams.at_latitude(record_latitude), k)
            for k in ("Omega_h", "Omega_v")})
    elif rec_deg is not None and lat is not None and abs(rec_deg - lat) > 0.01:
        given = {LAT_OPTION: "--latitude", LAT_PARAMS: "the params file",
                 LAT_PAPER: "--latitude paper (paper GC's values)"}[source]
        notes.append(f"the record's '# latitude_deg:' line says {rec_deg:.6g} deg; "
                     f"{lat:.4g} deg from {given} used (an option or params file wins over "
                     "the record)")
    return params, {"latitude_deg": lat, "source": source, "stated": source != LAT_NONE,
                    "record_latitude_deg": rec_deg, "Omega_h": params.Omega_h,
                    "Omega_v": params.Omega_v}


def _fit_noise(record, params, o: dict, bar_ok: bool):
    with progress(bar_ok, total=400, desc="fitting the noise", unit="eval") as bar:
        def advance(n: int) -> None:
            bar.update(max(0, n - bar.n))

        # fit_noise's own gate (a far tail: a gate as tight as the calibration's would cut
        # good samples and bias the intensities low)
        return gc.fit_noise(record, params, fit=o["fit"], progress=advance)


def _as_stated(record: gc.GCRecord, earth: dict) -> gc.GCRecord:
    """The record as calibrated: its own ``# latitude_deg:`` line dropped when the Earth rate
    comes from elsewhere (an option or params file that overrides it, said in a note, or no
    latitude at all), so that :func:`gyrolib.gc.calibrate` does not refuse the rate the user
    stated (it checks the parameters against a record's latitude)."""
    if record.latitude is None or earth["source"] == LAT_RECORD:
        return record
    return dataclasses.replace(record, latitude=None)


def run_file(file: str, o: dict) -> Outcome:
    """Calibrate one GC record with the checked options ``o``."""
    params: gc.GyrocompassParams = o["params"]
    mapping: gc.InclinometerMapping = o["mapping"]
    notes: list[str] = list(o["params_notes"])
    fit = None
    whole = o["fit_noise"] is not None or o["allan"] is not None
    if whole:   # the fit and the Allan deviation read the record many times: in memory
        raw, info = read_gc(file, params=params, columns=o["columns"], t0=o["t0"],
                            units=o["units"],
                            decimal_comma=o["decimal_comma"],
                            return_info=True)
        extra = _time_notes(info, raw, params, notes)
        params = _with_step(params, raw.t, notes, o["dt_given"])
        params, earth = _with_latitude(params, getattr(raw, "latitude", None), o, notes)
        record = _as_stated(mapping.apply(raw), earth)
        if o["fit_noise"] is not None:
            # the run before the fit: its misfit is what a fit must not merely absorb
            unfitted = _calibrate(record, params, o)
            fit = _fit_noise(record, params, o, o["bar"])
            # each fitted parameter's 95 % interval (about 8 likelihoods a parameter)
            fit = gc.profile_intervals(record, fit)
            params = fit.params
        with progress(o["bar"], total=record.n, desc=f"calibrate gc {file}",
                       unit="row") as bar:
            res = _calibrate(record, params, o,
                             progress=lambda rows: bar.update(rows - bar.n))
    else:       # stream the file in chunks, each checked at the door
        chunks = GCChunks(file, params=params, columns=o["columns"], t0=o["t0"],
                          units=o["units"], decimal_comma=o["decimal_comma"])
        it = iter(chunks)
        try:        # the file and pyarrow's reader closed however the run ends
            first = next(it)
            info = chunks.info
            extra = _time_notes(info, first, params, notes)
            params = _with_step(params, first.t, notes, o["dt_given"])
            params, earth = _with_latitude(params, getattr(first, "latitude", None), o,
                                           notes)

            def mapped():
                yield _as_stated(mapping.apply(first), earth)
                for chunk in it:
                    yield _as_stated(mapping.apply(chunk), earth)

            # the next chunk is read (parsed, checked at the door) in one thread while the
            # filter, which releases the GIL, runs on the current one: two chunks in flight
            with concurrent.futures.ThreadPoolExecutor(max_workers=1) as reader, \
                    progress(o["bar"], total=100.0, desc=f"calibrate gc {file}", unit="%",
                              bar_format="{desc} {percentage:3.0f}%|{bar}| "
                                         "{elapsed}<{remaining}") as bar:
                res = _calibrate(mapped(), params, o, executor=reader,
                                 progress=lambda _rows: bar.update(100 * chunks.fraction
                                                                   - bar.n))
        finally:
            it.close()
    valid, reason = bool(res.valid), str(res.reason)
    if not earth["stated"]:   # the Earth rate reads as drift: no latitude, no valid estimate
        valid, reason = False, "; ".join(x for x in (NO_LATITUDE, reason) if x)
    fit_std = 0.0
    if fit is not None:      # the fitted noise carries its own uncertainty (issue 26)
        why = fit.not_identified(float(record.t[-1] - record.t[0]) if record.n > 1 else 1e-9)
        duration = float(record.t[-1] - record.t[0]) if record.n > 1 else 1e-9
        failed = [c for c in gc.fit_checks(fit, unfitted, clock_tolerance=params.sigma_clock,
                                           false_alarm=o["false_alarm"]) if not c["passed"]]
        extra["noise_fit_checks"] = failed
        notes.extend(fit.nuisance(duration))
        if failed and not why:
            why = "; ".join(c["message"] for c in failed)
        if why:
            valid, reason = False, "; ".join(x for x in (reason, f"noise fit: {why}") if x)
        else:
            total = gc.fit_uncertainty(record, fit, at_fit=res, gate=o["gate"],
                                       max_rejected=o["max_rejected"],
                                       false_alarm=o["false_alarm"])
            fit_std = math.sqrt(max(total**2 - res.omega_gc_std**2, 0.0))
    codes, t0_hint = ([], None) if valid else reason_codes(
        res, earth, why if fit is not None else "")
    if not valid:   # the library's codes (its prior and model checks) and the fit's checks
        codes += [c for c in (*res.reason_codes,
                              *(c["reason_code"] for c in extra.get("noise_fit_checks", [])))
                  if c not in codes]
    code = hints.primary(codes)
    hint = hints.hint(code, f"{t0_hint:g}" if code == "early_release" and t0_hint else "") \
        if code else ""
    # a record the model checks reject (but the filter kept lock): its estimate on request,
    # marked misfit
    accepted = (not valid and o["accept_misfit"] and not res.lost_lock and earth["stated"]
                and not reason.startswith("noise fit:") and "; noise fit:" not in reason)
    status = "ok" if valid else ("misfit" if accepted else "invalid")
    artifacts = []
    if o["plot"]:
        site = (f"latitude {earth['latitude_deg']:.6g} deg N ({earth['source']})"
                if earth["stated"] else "NO latitude given")
        artifacts.append((o["plot"], "plot", (res, f"{file}, {site}")))
    allan_lines: list[str] = []
    if o["allan"]:
        allan = gc.allan_deviation(raw, params)
        artifacts.append((o["allan"], "allan", allan))
        allan_lines, extra["allan_noise_terms"] = _allan_report(allan)
    if fit is not None and o["fit_noise"] and valid:
        artifacts.append((o["fit_noise"], "text", fit.to_toml()))
    std = math.hypot(res.omega_gc_std, fit_std)
    data = _gc_json(file, res, params, mapping, notes, fit, valid, reason, accepted, earth,
                    fit_std)
    data.update(extra)
    data.update(reason_code=code or None, reason_codes=codes, hint=hint or None)
    text = (_gc_text(file, res, mapping, notes, fit, valid, reason, o, accepted, fit_std, earth)
            + "".join(f"{ln}\n" for ln in allan_lines) + (f"  {hint}\n" if hint else ""))
    given = valid or accepted
    row = {"file": file, "method": "gc", "quantity": "omega_gc", "notes": "; ".join(notes),
           "estimate": res.omega_gc if given else "",
           "sigma": std if given else "", "unit": "rad/s", "valid": valid,
           "status": status, "reason": reason, "reason_code": code, "hint": hint}
    message = "" if (valid or accepted) else f"{file}: no valid estimate: {reason}"
    return Outcome(file=file, status=status, message=message,
                    text=text, data=data, row=row, artifacts=artifacts)


#: Share of the record's start (from its first row) within which gate rejections point to
#: rows logged before the feedback was switched off (``early_release``).
EARLY_SHARE: Final[float] = 0.1


def reason_codes(res, earth: dict, fit_why: str = "") -> tuple[list[str], float | None]:
    """The reason codes (keys of :data:`gyrolib.cli.hints.REASONS`) of a run that is not
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
      outside ``nis_range`` (when not an early release);
    * ``drift_changes``: a split-record test failed; ``misfit``: a mean-NIS or whiteness
      test failed;
    * ``fit_not_converged``, ``fit_not_identified``: from ``fit_why``
      (:meth:`gyrolib.gc.NoiseFit.not_identified`).
    """
    codes: list[str] = []
    if not earth["stated"]:
        codes.append("no_latitude")
    if res.record_latitude is not None and gc.earth_rate_mismatch(res.params,
                                                                  res.record_latitude):
        codes.append("latitude_mismatch")
    t0 = None
    rt = np.unique(np.asarray(res.rejected_t, dtype=float))
    start = float(res.t[0]) if res.t.size else 0.0
    span = max(float(res.t_final) - start, 0.0)
    tests = res.model_tests()
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
    for tst in tests:
        if not tst["passed"]:
            code = "drift_changes" if tst["test"].startswith("split-record") else "misfit"
            if code not in codes:
                codes.append(code)
    if fit_why:
        codes.append("fit_not_converged" if fit_why.startswith("noise fit not converged")
                     else "fit_not_identified")
    return codes, t0


def _gc_json(file, res, params, mapping, notes, fit, valid, reason, accepted=False,
             earth=None, fit_std=0.0) -> dict:
    out = res.summary()
    if fit is not None:
        out["omega_gc_std"] = math.hypot(res.omega_gc_std, fit_std)
        out["omega_gc_std_parts"]["noise_fit"] = fit_std
    out["file"] = str(file)
    out["dt"] = params.dt
    out["notes"] = notes
    out["valid"] = valid
    out["reason"] = reason
    out["misfit_accepted"] = bool(accepted)
    out["earth_rate"] = earth
    out["latitude_deg"] = None if earth is None else earth["latitude_deg"]
    out["latitude_source"] = None if earth is None else earth["source"]
    out["priors"] = {"scale_tolerance": params.sigma_hf_scale,
                     "angle_offset_rad": params.sigma_as_offset,
                     "inclinometer_bias_m_s2": params.sigma_incl_bias,
                     "drift_rad_s": params.sigma_gc0, "clock_tolerance": params.sigma_clock}
    out["inclinometers"] = {"mapping": str(mapping), "delta": _signed(mapping.delta_sign,
                                                                      mapping.delta_column),
                            "gamma": _signed(mapping.gamma_sign, mapping.gamma_column)}
    if fit is not None:
        out["noise_fit"] = fit.summary()
    if not valid and not accepted:   # a failure, not a result: no estimate to pick up
        out["omega_gc"] = None
        out["omega_gc_std"] = None
        out["omega_gc_std_parts"] = None
        out["instrument"] = None
        out.pop("states", None)
    else:               # the drift in the field's units beside SI
        out["omega_gc_in"] = {u: {"estimate": units.drift_in_units(res.omega_gc)[u],
                                  "std": units.drift_in_units(res.omega_gc_std)[u]}
                              for u, _ in units.DRIFT_UNITS}
    out["units"] = _GC_UNITS
    out["unit_conversion"] = units.drift_conversion()
    return out


#: Units of the GC JSON's numeric fields (SI; the ``omega_gc_in`` table is keyed by unit).
_GC_UNITS: Final[dict[str, str]] = {
    "omega_gc": "rad/s", "omega_gc_std": "rad/s", "t_end": "s", "dt": "s", "gap_time": "s",
    "rejected_t": "s", "rejected_t_count": "1 (rows)", "nis": "1", "gate": "1 (probability)",
    "max_rejected": "1 (share)",
    "rejected_share": "1 (share)", "log_likelihood": "1 (natural log)",
    "states": "SI per state (rad, rad/s, m/s^2)", "time_base.t_offset_s": "s",
    "timestamp_jitter": "s, rad, 1"}


def _signed(sign: float, column: str) -> str:
    return ("-" if sign < 0 else "") + column


def _earth_line(earth: dict) -> str:
    """One line: the latitude, where it came from, and the Earth-rate components used."""
    rate = f"Omega_h = {earth['Omega_h']:.5g}, Omega_v = {earth['Omega_v']:.5g} rad/s"
    if not earth["stated"]:
        return (f"  Earth rate: NO latitude given; paper GC's {rate} (about "
                f"{math.degrees(PAPER_LATITUDE):.1f} deg N) used, so the estimate is not "
                "valid")
    src = {LAT_OPTION: "from --latitude", LAT_PARAMS: "from the params file",
           LAT_RECORD: "from the record's '# latitude_deg:' line",
           LAT_PAPER: "ASSUMED: paper GC's values, by --latitude paper"}[earth["source"]]
    rec = earth.get("record_latitude_deg")
    over = (f"; the record's '# latitude_deg:' line says {rec:.6g} deg, overridden"
            if earth["source"] != LAT_RECORD and rec is not None
            and abs(rec - earth["latitude_deg"]) > 0.01 else "")
    return f"  Earth rate: latitude {earth['latitude_deg']:.6g} deg N ({src}{over}): {rate}"


def compared(x: float, lo: float | None, hi: float | None) -> tuple[str, str, str]:
    """``x``, ``lo`` and ``hi`` formatted with as many significant digits (4 at least, 12 at
    most) as it takes for the printed numbers to compare as the numbers do, so that no
    printed comparison reads false ("23.2 > 23.2"); a missing bound prints as "".

    Examples
    --------
    >>> compared(23.24, None, 23.2351)
    ('23.24', '', '23.235')
    >>> compared(0.99812, 0.998123, 1.0021)
    ('0.99812', '0.998123', '1.0021')
    """
    def ok(d: int) -> bool:
        fx = float(f"{x:.{d}g}")
        return all((float(f"{b:.{d}g}") < fx) == (b < x)
                   and (float(f"{b:.{d}g}") > fx) == (b > x) for b in (lo, hi) if b is not None)

    d = next((d for d in range(4, 13) if ok(d)), 12)
    return (f"{x:.{d}g}", "" if lo is None else f"{lo:.{d}g}",
            "" if hi is None else f"{hi:.{d}g}")


def _check_lines(res) -> list[str]:
    """The model checks as the text prints them: every test of :meth:`model_tests` with the
    band or limit that decides validity (the same tolerance and family-wise level), each
    comparison rounded so that it reads true, then one verdict line."""
    tests = res.model_tests()
    lines = [f"  model checks at a {100 * res.false_alarm:g} % family-wise false-alarm rate "
             "(the bands that decide validity): " + ("all pass" if not res.misfit
                                                     else "FAIL")]
    groups: dict[str, list[str]] = {}
    failed: list[str] = []
    for t in tests:
        x, lo, hi = compared(t["statistic"], t["low"], t["high"])
        if t["test"] == "mean NIS":
            key = "mean NIS"
            shown = f"{t['sensor']} {x} {'in' if t['passed'] else 'NOT in'} [{lo}, {hi}]"
        elif t["test"].startswith("whiteness"):
            key = t["test"]
            shown = f"{t['sensor']} {x} {'<=' if t['passed'] else '>'} {hi}"
        else:
            key = "split-record omega_gc, z"
            shown = (t["test"].split("(", 1)[1].rstrip(")") + f": {x} "
                     + ("within" if t["passed"] else "outside") + f" ±{hi}")
        groups.setdefault(key, []).append(shown)
        if not t["passed"]:
            failed.append(f"{key}: {shown}")
    lines += [f"    {key}: " + "; ".join(v) for key, v in groups.items()]
    lines.append("  model fits: every check passes" if not failed and tests else
                 "  model does NOT fit: " + "; ".join(failed) if failed else
                 "  model checks: none (no usable measurement)")
    return lines


def _gc_text(file, res, mapping, notes, fit, valid, reason, o, accepted=False,
             fit_std=0.0, earth=None) -> str:
    lines = [
        f"paper GC calibration of {file}: {res.rows} rows over {res.t_final:.6g} s"
        + (f" ({res.gaps} gap(s), {res.gap_time:.6g} s without rows)" if res.gaps else ""),
        f"  inclinometers (--inclinometers {mapping}): {mapping.describe()}",
    ] + ([_earth_line(earth)] if earth is not None else [])
    if fit is not None:
        parts = [f"{n} = {fmt(fit.value(n))} ± {fmt(fit.carried_std_error(n), 2)}"
                 + (" (profile)" if fit.std_error_source(n).startswith("profile") else "")
                 + " "
                 f"[{fmt(fit.interval(n)[0], 3)}, {fmt(fit.interval(n)[1], 3)}]"
                 + (f" {FIT_UNITS[n]}" if FIT_UNITS.get(n) else "") for n in fit.names]
        lines.append("  noise fitted (maximum likelihood, ± standard error (profile: widened "
                     "to the interval) [95 % likelihood-ratio interval]): " + ", ".join(parts))
        lines.append(f"  log-likelihood {fit.loglik:.6g} (start {fit.loglik_start:.6g}), "
                     f"{fit.n_evaluations} evaluations, "
                     + ("converged" if fit.converged else f"NOT converged: {fit.message}")
                     + (f"; written to {o['fit_noise']}" if o["fit_noise"] and valid else ""))
    if valid or accepted:
        std = math.hypot(res.omega_gc_std, fit_std)
        a = units.drift_in_units(res.omega_gc)
        s = units.drift_in_units(std)
        lines.append(("  MISFIT (accepted with --accept-misfit; sigma may not cover the "
                      f"truth): {reason}\n" if accepted else "")
                     + f"  omega_gc = {fmt(a['deg/h'])} ± {fmt(s['deg/h'], 2)} deg/h (1 sigma)"
                     f"  = {fmt(a['arcsec/s'])} ± {fmt(s['arcsec/s'], 2)} arcsec/s (standard)"
                     f"  = {fmt(a['arcsec_paper/s'])} ± {fmt(s['arcsec_paper/s'], 2)} "
                     f"arcsec/s (paper's arcsec, 1\" = 0.485e-5 rad)  = {res.omega_gc:.4e} ± "
                     f"{std:.2e} rad/s")
        parts = res.omega_gc_std_parts
        p = res.params
        lines.append("  sigma in parts (adding in quadrature): "
                     f"noise {fmt(units.from_si(parts['noise'], 'arcsec_paper/s'), 2)}, "
                     "instrument biases "
                     f"{fmt(units.from_si(parts['instrument_biases'], 'arcsec_paper/s'), 2)}"
                     f", scale {fmt(units.from_si(parts['scale'], 'arcsec_paper/s'), 2)}"
                     + (f", noise fit {fmt(units.from_si(fit_std, 'arcsec_paper/s'), 2)}"
                        if fit is not None else "")
                     + f" arcsec/s (paper's arcsec; priors: scale {p.sigma_hf_scale:g}, angle "
                     f"offset {units.from_si(p.sigma_as_offset, 'arcsec_paper'):g} arcsec, "
                     f"inclinometer bias {p.sigma_incl_bias / (1e-3 * units.G0):g} mg)")
    else:
        lines.append(f"  no valid estimate: {reason}")
    lines += [
        f"  samples used {res.rows_used}, rejected {res.rows_rejected} (an innovation beyond "
        f"the {100 * res.gate:g} % chi-square gate), missing values "
        f"{int(res.missing.sum())}",
        *_check_lines(res),
    ]
    lines += [f"  note: {n}" for n in notes]
    return "\n".join(lines) + "\n"
