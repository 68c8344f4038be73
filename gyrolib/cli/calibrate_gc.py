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
import re
from typing import Final

import numpy as np

from gyrolib import gc, units
from gyrolib.cli import constants
from gyrolib.cli.constants import FIT_UNITS, PLOT_SUFFIXES
from gyrolib.cli.outputs import Outcome, bar_enabled, check_out_path, fmt, progress
from gyrolib.gc.logs import judgement
from gyrolib.gc.model.params import PAPER_LATITUDE, latitude_text
from gyrolib.records.errors import OptionError
from gyrolib.records.params import (
    LATITUDE_RANGE,
    gc_params_from_toml,
    instrument_notes,
    load_toml,
)
from gyrolib.records.reader import GCChunks, read_gc
from gyrolib.verdict import compared

__all__ = ["LAT_NONE", "LAT_OPTION", "LAT_PAPER", "LAT_PARAMS", "LAT_RECORD", "NO_LATITUDE",
           "compared", "options", "run_file"]


def options(args: argparse.Namespace) -> dict:
    """Checked options of ``calibrate gc`` (OptionError / RecordError on a bad one)."""
    _check_ranges(args)
    batch = len(args.files) > 1
    _check_outputs(args, batch)
    params = gc_params_from_toml(args.params)
    toml = load_toml(args.params) if args.params is not None else {}
    params = dataclasses.replace(params, **_priors(args, toml))
    params, latitude, lat_source, lat_sigma = _latitude(args, params, toml)
    return {"params": params, "dt_given": "dt" in toml, "gate": args.gate,
            "latitude": latitude, "latitude_source": lat_source, "latitude_sigma": lat_sigma,
            "false_alarm": args.false_alarm, "accept_misfit": args.accept_misfit,
            "store_every": args.store_every, "max_rejected": args.max_rejected,
            "mapping": _mapping(args), "fit_noise": args.fit_noise, "fit": _fit_names(args),
            "allan": args.allan, "plot": args.plot, "json": args.json,
            "params_notes": instrument_notes(args.params, "calibrate gc"),
            "bar": bar_enabled(args) and not batch}


def _check_ranges(args: argparse.Namespace) -> None:
    """The probabilities, shares and counts among the options, each in its range."""
    if not 0.0 < args.gate < 1.0:
        raise OptionError(f"--gate must be a probability in (0, 1); got {args.gate}")
    if args.store_every < 1:
        raise OptionError(f"--store-every must be >= 1; got {args.store_every}")
    if not 0.0 <= args.max_rejected < 1.0:
        raise OptionError(f"--max-rejected must be a share in [0, 1); got {args.max_rejected}")
    if not (math.isfinite(args.false_alarm) and 0.0 < args.false_alarm < 1.0):
        raise OptionError(f"--false-alarm must be a probability in (0, 1); got "
                          f"{args.false_alarm}")


def _mapping(args: argparse.Namespace) -> gc.InclinometerMapping:
    try:
        return gc.InclinometerMapping.parse(args.inclinometers)
    except ValueError:
        raise OptionError(f"--inclinometers expects two of y, z, -y, -z separated by a comma, "
                          f"each column once (e.g. y,z or z,y or -y,z); got "
                          f"{args.inclinometers!r}") from None


def _fit_names(args: argparse.Namespace) -> tuple[str, ...]:
    fit = tuple(s.strip() for s in args.fit.split(",") if s.strip())
    unknown = [s for s in fit if s not in FIT_UNITS]
    if not fit or unknown or ("C_in" in fit and ({"C_incl_y", "C_incl_z"} & set(fit))):
        raise OptionError(f"--fit expects names among {', '.join(FIT_UNITS)} (C_in not with "
                          f"C_incl_y, C_incl_z), comma-separated; got {args.fit!r}")
    return fit


def _check_outputs(args: argparse.Namespace, batch: bool) -> None:
    """One file per output option, of a suffix it writes, in a writable folder."""
    for opt, val in (("--plot", args.plot), ("--allan", args.allan),
                     ("--fit-noise OUT.toml", args.fit_noise or None)):
        if batch and val:
            raise OptionError(f"{opt} writes one file: give one record, not {len(args.files)} "
                              "(--summary OUT.csv reports a batch)")
    check_out_path(args.plot, PLOT_SUFFIXES, "a plot")
    check_out_path(args.allan, PLOT_SUFFIXES, "a plot")
    check_out_path(args.fit_noise or None, (".toml",), "a TOML")


def _priors(args: argparse.Namespace, toml: dict) -> dict[str, float]:
    """The instrument priors in SI: an option in its unit, else the params file's value
    (left as it is), else the table of inputs' default (an instrument error's largest
    plausible value, stored with the package: gyrolib.cli.constants; the drift prior's
    reference, the field's default)."""
    mg = 1e-3 * units.G0
    priors = {}
    for opt, name, val, default, unit in (
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
        if val is None and name in toml:     # the params file states it
            continue
        priors[name] = default if val is None else val * unit
    if priors.get("sigma_gc0", 1.0) <= 0.0:
        raise OptionError("--drift-prior must be > 0 (a drift known to be exactly 0 is not "
                          "calibrated)")
    return priors


#: ``--latitude 54±0.5``: the value and its 1σ uncertainty (±, +- or +/-).
_PLUS_MINUS: Final[re.Pattern] = re.compile(r"^\s*([^±+/]+?)\s*(?:±|\+-|\+/-)\s*(.+?)\s*$")


def _latitude_value(text: str) -> tuple[float, float | None]:
    """``--latitude``'s number and the uncertainty written with it (``54±0.5``), or None."""
    m = _PLUS_MINUS.match(text)
    value, sigma = (m.group(1), m.group(2)) if m else (text, None)
    try:
        lat = float(value)
        sd = None if sigma is None else float(sigma)
    except ValueError:
        lat, sd = math.nan, None
    if not (math.isfinite(lat) and -90.0 < lat < 90.0):
        raise OptionError(f"--latitude must be {LATITUDE_RANGE}, optionally with its 1-sigma "
                          f"uncertainty (54±0.5), or 'paper' for paper GC's values; got {text}")
    if sd is not None and not (math.isfinite(sd) and sd >= 0.0):
        raise OptionError(f"--latitude's uncertainty (after ±) must be degrees >= 0; got {text}")
    return lat, sd


def _latitude_sigma(args: argparse.Namespace, written: float | None) -> float | None:
    """The latitude's 1σ uncertainty (deg): written with ``--latitude`` or by
    ``--latitude-sigma`` (not both), else None."""
    given = getattr(args, "latitude_sigma", None)
    if given is not None and not (math.isfinite(given) and given >= 0.0):
        raise OptionError(f"--latitude-sigma must be degrees >= 0; got {given}")
    if given is not None and written is not None:
        raise OptionError("--latitude's ± and --latitude-sigma both state the latitude's "
                          "uncertainty: give one")
    return written if given is None else given


def _latitude(args: argparse.Namespace, params: gc.GyrocompassParams, toml: dict
              ) -> tuple[gc.GyrocompassParams, float | None, str, float | None]:
    """The Earth rate from ``--latitude`` or the params file: the parameters with it, the
    latitude (deg), where it came from (:data:`LAT_NONE` when neither states it) and its
    stated 1σ uncertainty (deg, or None)."""
    if args.latitude is not None:
        if {"Omega_h", "Omega_v", "latitude"} & set(toml):
            raise OptionError("--latitude and the params file's latitude/Omega_h/Omega_v both "
                              "state the Earth rate: give one")
        if args.latitude.strip().lower() == "paper":
            return (params, math.degrees(PAPER_LATITUDE), LAT_PAPER,
                    _latitude_sigma(args, None))
        latitude, written = _latitude_value(args.latitude)
        kept = {f.name: getattr(params, f.name) for f in dataclasses.fields(params)
                if f.name not in ("Omega_h", "Omega_v")}
        return (gc.GyrocompassParams.at_latitude(math.radians(latitude), **kept), latitude,
                LAT_OPTION, _latitude_sigma(args, written))
    sigma = _latitude_sigma(args, None)
    if "latitude" in toml:
        return params, float(toml["latitude"]), LAT_PARAMS, sigma
    if {"Omega_h", "Omega_v"} <= set(toml):   # the Earth rate stated by its components
        return params, math.degrees(params.latitude), LAT_PARAMS, sigma
    if {"Omega_h", "Omega_v"} & set(toml):    # half an Earth rate: the other the paper's?
        given, = {"Omega_h", "Omega_v"} & set(toml)
        raise OptionError(f"{args.params} sets {given} but not "
                          f"{({'Omega_h', 'Omega_v'} - {given}).pop()}: give both Earth-rate "
                          "components, or 'latitude' (degrees, north positive), or neither")
    return params, None, LAT_NONE, sigma


#: ``latitude_source`` of the JSON: where the latitude (the Earth rate) came from.
LAT_OPTION: Final[str] = "option"
LAT_PARAMS: Final[str] = "params"
LAT_RECORD: Final[str] = "record header"
LAT_PAPER: Final[str] = "paper (assumed by --latitude paper)"
LAT_NONE: Final[str] = "none"
#: The reason of a record calibrated without a stated latitude (no valid estimate).
NO_LATITUDE: Final[str] = judgement.NO_LATITUDE


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
        data[name] = [_allan_term(t) for t in ts]
    return lines, data


def _allan_term(t) -> dict:
    """One noise term as the JSON holds it, as ``allan --json`` does: a term whose
    coefficient is 0 is nowhere, so it has no ``tau_s``."""
    out = {"name": t.name, "value": t.value, "sigma": t.sigma, "lo": t.lo, "hi": t.hi,
           "unit": t.unit.replace("·", "*").replace("√", "sqrt"), "identified": t.identified}
    if t.tau is not None:
        out["tau_s"] = t.tau
    return out


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
        if not -math.pi / 2 < record_latitude < math.pi / 2:
            raise ValueError(f"the record's latitude {rec_deg:g} deg must be {LATITUDE_RANGE}")
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
                    "Omega_v": params.Omega_v, "latitude_sigma_deg": o.get("latitude_sigma")}


#: The latitude error whose effect on ω̂_gc a whole-degree latitude is warned of (deg).
WHOLE_DEGREE_ERROR: Final[float] = 0.5


def _latitude_warning(earth: dict, ver) -> dict | None:
    """A latitude stated in whole degrees without an uncertainty (from any source): what an
    error of :data:`WHOLE_DEGREE_ERROR` would move ω̂_gc by, in σ of this record
    (:func:`gyrolib.gc.latitude_drift_shift`), or None."""
    lat = earth["latitude_deg"]
    if (not earth["stated"] or earth["source"] == LAT_PAPER or lat is None
            or earth.get("latitude_sigma_deg") is not None or not float(lat).is_integer()
            or not ver.given or not ver.sigma > 0.0):
        return None
    shift = gc.latitude_drift_shift(ver.result.params, math.radians(WHOLE_DEGREE_ERROR))
    n = shift / ver.sigma
    text = (f"the latitude {latitude_text(lat)} is given in whole degrees with no "
            f"uncertainty: an error of {WHOLE_DEGREE_ERROR:g} deg would move omega_gc by "
            f"about {n:.2g} sigma on this record ({shift:.3g} rad/s, Omega_h read as drift); "
            "state the site's latitude more closely, or its uncertainty (--latitude "
            f"{lat:g}±SIGMA or --latitude-sigma DEG), which then enters sigma as the term "
            "'latitude'")
    return {"error_deg": WHOLE_DEGREE_ERROR, "omega_gc_shift": shift,
            "shift_over_sigma": n, "text": text}


def _as_stated(record: gc.GCRecord, earth: dict) -> gc.GCRecord:
    """The record as calibrated: its own ``# latitude_deg:`` line dropped when the Earth rate
    comes from elsewhere (an option or params file that overrides it, said in a note, or no
    latitude at all), so that :func:`gyrolib.gc.calibrate` does not refuse the rate the user
    stated (it checks the parameters against a record's latitude)."""
    if record.latitude is None or earth["source"] == LAT_RECORD:
        return record
    return dataclasses.replace(record, latitude=None)


def run_file(file: str, o: dict) -> Outcome:
    """Calibrate one GC record with the checked options ``o``: read it, state its Earth
    rate, have the library judge it (:func:`gyrolib.gc.judge_record`) and format the
    verdict as text, JSON and a summary row."""
    notes: list[str] = list(o["params_notes"])
    if o["fit_noise"] is not None or o["allan"] is not None:
        ver, raw, params, earth, extra = _judge_whole(file, o, notes)
    else:
        ver, params, earth, extra = _judge_streamed(file, o, notes)
        raw = None
    res = ver.result
    artifacts = []
    if o["plot"]:
        site = (f"latitude {latitude_text(earth['latitude_deg'])} ({earth['source']})"
                if earth["stated"] else "NO latitude given")
        artifacts.append((o["plot"], "plot", (res, f"{file}, {site}")))
    allan_lines: list[str] = []
    if o["allan"]:
        allan = gc.allan_deviation(raw, params)
        artifacts.append((o["allan"], "allan", allan))
        allan_lines, extra["allan_noise_terms"] = _allan_report(allan)
    nf = ver.details["noise_fit"]
    if nf is not None and o["fit_noise"] and ver.valid:
        artifacts.append((o["fit_noise"], "text", nf.to_toml()))
    extra["noise_fit_checks"] = ver.details["noise_fit_checks"]
    if nf is None:
        extra.pop("noise_fit_checks")
    data = _gc_json(file, ver, params, o["mapping"], earth)
    data.update(extra)
    warn = _latitude_warning(earth, ver)
    data["latitude_warning"] = warn
    text = (_gc_text(file, ver, o, earth)
            + (f"  warning: {warn['text']}\n" if warn else "")
            + "".join(f"{ln}\n" for ln in allan_lines)
            + (f"  {ver.hint}\n" if ver.hint else ""))
    row = {"file": file, "method": "gc", "quantity": ver.quantity,
           "notes": "; ".join(ver.notes), "estimate": ver.estimate if ver.given else "",
           "sigma": ver.sigma if ver.given else "", "unit": ver.unit, "valid": ver.valid,
           "status": ver.status, "reason": ver.reason, "reason_code": ver.reason_code,
           "hint": ver.hint}
    message = "" if ver.given else f"{file}: no valid estimate: {ver.reason}"
    return Outcome(file=file, status=ver.status, message=message, text=text, data=data,
                   row=row, artifacts=artifacts)


def _judge(record, params, earth: dict, o: dict, notes: list[str], fit: bool = False,
           **kw):
    """:func:`gyrolib.gc.judge_record` with the options ``o``."""
    sigma = earth.get("latitude_sigma_deg")
    return gc.judge_record(record, params, latitude_stated=earth["stated"],
                           latitude_sigma=math.radians(sigma) if sigma else 0.0,
                           fit=o["fit"] if fit else None, accept_misfit=o["accept_misfit"],
                           gate=o["gate"], store_every=o["store_every"],
                           max_rejected=o["max_rejected"], false_alarm=o["false_alarm"],
                           notes=notes, **kw)


def _judge_whole(file: str, o: dict, notes: list[str]):
    """The record read whole (the fit and the Allan deviation read it many times), judged:
    (verdict, the record as read, the parameters, the Earth rate, the JSON's extras)."""
    params = o["params"]
    raw, info = read_gc(file, params=params, site_from_record=o["latitude_source"] == LAT_NONE,
                        columns=o["columns"], t0=o["t0"],
                        units=o["units"], decimal_comma=o["decimal_comma"], return_info=True)
    extra = _time_notes(info, raw, params, notes)
    params = _with_step(params, raw.t, notes, o["dt_given"])
    params, earth = _with_latitude(params, getattr(raw, "latitude", None), o, notes)
    record = _as_stated(o["mapping"].apply(raw), earth)
    fit = o["fit_noise"] is not None
    with progress(o["bar"] and fit, total=400, desc="fitting the noise",
                  unit="eval") as fit_bar, \
            progress(o["bar"], total=record.n, desc=f"calibrate gc {file}", unit="row") as bar:
        ver = _judge(record, params, earth, o, notes, fit=fit,
                     progress=lambda rows: bar.update(rows - bar.n),
                     fit_progress=lambda n: fit_bar.update(max(0, n - fit_bar.n)))
    return ver, raw, ver.result.params, earth, extra


def _judge_streamed(file: str, o: dict, notes: list[str]):
    """The record streamed in chunks, each checked at the door, judged: (verdict, the
    parameters, the Earth rate, the JSON's extras)."""
    params = o["params"]
    chunks = GCChunks(file, params=params, site_from_record=o["latitude_source"] == LAT_NONE,
                      columns=o["columns"], t0=o["t0"],
                      units=o["units"], decimal_comma=o["decimal_comma"])
    it = iter(chunks)
    try:        # the file and pyarrow's reader closed however the run ends
        first = next(it)
        extra = _time_notes(chunks.info, first, params, notes)
        params = _with_step(params, first.t, notes, o["dt_given"])
        params, earth = _with_latitude(params, getattr(first, "latitude", None), o, notes)

        def mapped():
            yield _as_stated(o["mapping"].apply(first), earth)
            for chunk in it:
                yield _as_stated(o["mapping"].apply(chunk), earth)

        # the next chunk is read (parsed, checked at the door) in one thread while the
        # filter, which releases the GIL, runs on the current one: two chunks in flight
        with concurrent.futures.ThreadPoolExecutor(max_workers=1) as reader, \
                progress(o["bar"], total=100.0, desc=f"calibrate gc {file}", unit="%",
                         bar_format="{desc} {percentage:3.0f}%|{bar}| "
                                    "{elapsed}<{remaining}") as bar:
            ver = _judge(mapped(), params, earth, o, notes, executor=reader,
                         progress=lambda _rows: bar.update(100 * chunks.fraction - bar.n))
    finally:
        it.close()
    return ver, params, earth, extra


def _gc_json(file, ver, params, mapping, earth) -> dict:
    """The JSON of a GC verdict: the filter's summary, then the verdict's fields."""
    res = ver.result
    out = res.summary()
    out["omega_gc_std"] = ver.sigma
    out["omega_gc_std_parts"] = dict(ver.sigma_parts)
    nf = ver.details["noise_fit"]
    out["file"] = str(file)
    out["dt"] = params.dt
    out["notes"] = list(ver.notes)
    out.update(valid=ver.valid, status=ver.status, reason=ver.reason,
               reason_code=ver.reason_code or None, reason_codes=list(ver.reason_codes),
               hint=ver.hint or None, misfit_accepted=ver.status == "misfit")
    out["checks"] = [c.summary() for c in ver.checks]
    out["counts"] = ver.counts.summary()
    out["earth_rate"] = earth
    out["latitude_deg"] = earth["latitude_deg"]
    out["latitude_source"] = earth["source"]
    out["priors"] = {"scale_tolerance": params.sigma_hf_scale,
                     "angle_offset_rad": params.sigma_as_offset,
                     "inclinometer_bias_m_s2": params.sigma_incl_bias,
                     "drift_rad_s": params.sigma_gc0, "clock_tolerance": params.sigma_clock}
    out["inclinometers"] = {"mapping": str(mapping), "delta": _signed(mapping.delta_sign,
                                                                      mapping.delta_column),
                            "gamma": _signed(mapping.gamma_sign, mapping.gamma_column)}
    if nf is not None:
        out["noise_fit"] = nf.summary()
    if not ver.given:   # a failure, not a result: no estimate to pick up
        out["omega_gc"] = None
        out["omega_gc_std"] = None
        out["omega_gc_std_parts"] = None
        out["instrument"] = None
        out.pop("states", None)
    else:               # the drift in the field's units beside SI
        out["omega_gc_in"] = {u: {"estimate": units.drift_in_units(ver.estimate)[u],
                                  "std": units.drift_in_units(ver.sigma)[u]}
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
    "timestamp_jitter": "s, rad, 1", "earth_rate.latitude_sigma_deg": "deg",
    "latitude_warning": "deg (error_deg), rad/s (omega_gc_shift), 1 (shift_over_sigma)"}


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
    sd = earth.get("latitude_sigma_deg")
    sd = f" ± {sd:g} deg (1 sigma)" if sd is not None else ""
    return (f"  Earth rate: latitude {latitude_text(earth['latitude_deg'])}{sd} ({src}{over}): "
            f"{rate}")


def _check_lines(ver) -> list[str]:
    """The checks as the text prints them, one a line (:meth:`gyrolib.verdict.Check.line`:
    its name as the JSON's ``checks`` has it, the value and its one band), then one verdict
    line."""
    failed = ver.failed
    lines = [f"  checks at a {100 * ver.false_alarm:g} % family-wise false-alarm rate (each "
             "statistic's band decides validity): " + ("FAIL" if failed else "all pass")]
    lines += [f"    {c.line()}" for c in ver.checks]
    model = [c for c in ver.checks if c.test == "mean NIS" or c.test.startswith("whiteness")]
    bad = [c for c in model if not c.passed]
    lines.append("  model fits: every sensor's mean NIS is in its band and its innovations "
                 "are white" if model and not bad else
                 "  model does NOT fit: " + "; ".join(c.line() for c in bad) if bad else
                 "  model checks: none (no usable measurement)")
    return lines


def _fit_lines(nf, o: dict, valid: bool) -> list[str]:
    """The fitted noise parameters, each ± its standard error and its interval."""
    parts = [f"{n} = {fmt(nf.value(n))} ± {fmt(nf.carried_std_error(n), 2)}"
             + (" (profile)" if nf.std_error_source(n).startswith("profile") else "")
             + f" [{fmt(nf.interval(n)[0], 3)}, {fmt(nf.interval(n)[1], 3)}]"
             + (f" {FIT_UNITS[n]}" if FIT_UNITS.get(n) else "") for n in nf.names]
    return ["  noise fitted (maximum likelihood, ± standard error (profile: widened to the "
            "interval) [95 % likelihood-ratio interval]): " + ", ".join(parts),
            f"  log-likelihood {nf.loglik:.6g} (start {nf.loglik_start:.6g}), "
            f"{nf.n_evaluations} evaluations, "
            + ("converged" if nf.converged else f"NOT converged: {nf.message}")
            + (f"; written to {o['fit_noise']}" if o["fit_noise"] and valid else "")] + [
        # an interval side much shorter than the curvature's: both figures, marked suspect
        f"  {x}" for x in nf.interval_findings()]


def _estimate_lines(ver) -> list[str]:
    """ω̂_gc ± σ in the field's units, then σ's named terms and the priors."""
    a = units.drift_in_units(ver.estimate)
    s = units.drift_in_units(ver.sigma)
    p = ver.result.params
    head = (f"  MISFIT (accepted with --accept-misfit; sigma may not cover the truth): "
            f"{ver.reason}\n" if ver.status == "misfit" else "")
    terms = ", ".join(f"{k.replace('_', ' ')} {fmt(units.from_si(x, 'arcsec_paper/s'), 2)}"
                      for k, x in ver.sigma_parts.items())
    return [head + f"  omega_gc = {fmt(a['deg/h'])} ± {fmt(s['deg/h'], 2)} deg/h (1 sigma)"
            f"  = {fmt(a['arcsec/s'])} ± {fmt(s['arcsec/s'], 2)} arcsec/s (standard)"
            f"  = {fmt(a['arcsec_paper/s'])} ± {fmt(s['arcsec_paper/s'], 2)} "
            f"arcsec/s (paper's arcsec, 1\" = 0.485e-5 rad)  = {ver.estimate:.4e} ± "
            f"{ver.sigma:.2e} rad/s",
            f"  sigma in parts (adding in quadrature): {terms} arcsec/s (paper's arcsec; "
            f"priors: scale {p.sigma_hf_scale:g}, angle offset "
            f"{units.from_si(p.sigma_as_offset, 'arcsec_paper'):g} arcsec, inclinometer "
            f"bias {p.sigma_incl_bias / (1e-3 * units.G0):g} mg)"]


def _gc_text(file, ver, o, earth) -> str:
    res = ver.result
    mapping = o["mapping"]
    nf = ver.details["noise_fit"]
    lines = [
        f"paper GC calibration of {file}: {res.rows} rows over {res.t_final:.6g} s"
        + (f" ({res.gaps} gap(s), {res.gap_time:.6g} s without rows)" if res.gaps else ""),
        f"  inclinometers (--inclinometers {mapping}): {mapping.describe()}",
        _earth_line(earth)]
    if nf is not None:
        lines += _fit_lines(nf, o, ver.valid)
    lines += (_estimate_lines(ver) if ver.given else [f"  no valid estimate: {ver.reason}"])
    lines.append(f"  {ver.counts.line()} (a rejected measurement: an innovation beyond the "
                 f"{100 * res.gate:g} % chi-square gate); missing values "
                 f"{ver.counts.missing}")
    lines += _check_lines(ver)
    lines += [f"  note: {n}" for n in ver.notes]
    return "\n".join(lines) + "\n"
