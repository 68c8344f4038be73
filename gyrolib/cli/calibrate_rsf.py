"""Paper RSF's run of the ``calibrate`` command on one record: its options checked
(:func:`options`), the record read, the correction of Eqs. (1)-(3) applied per interval, and
the report as text, JSON and a summary row (:func:`run_file`).  Paper RSF's package is
imported by :func:`run_file`, not by a GC run.  See :mod:`gyrolib.cli.calibrate` for the
command's behaviour."""

from __future__ import annotations

import argparse
import math

import numpy as np

from gyrolib import units
from gyrolib.cli.constants import PLOT_SUFFIXES
from gyrolib.cli.outputs import Outcome, check_out_path, one_line
from gyrolib.records.errors import OptionError, RecordError
from gyrolib.records.params import instrument_notes, rsf_config_from_toml
from gyrolib.records.reader import read_rsf

__all__ = ["options", "run_file"]


def options(args: argparse.Namespace) -> dict:
    if not (math.isfinite(args.period) and args.period > 0):
        raise OptionError(f"--period must be a positive number of seconds; got {args.period}")
    if args.counts_per_rev is not None and args.counts_per_rev < 2:
        raise OptionError(f"--counts-per-rev must be an integer >= 2; got "
                         f"{args.counts_per_rev}")
    if len(args.files) > 1 and args.plot:
        raise OptionError(f"--plot writes one file: give one record, not {len(args.files)} "
                         "(--summary OUT.csv reports a batch)")
    check_out_path(args.plot, PLOT_SUFFIXES, "a plot")
    if not (math.isfinite(args.false_alarm) and 0.0 < args.false_alarm < 1.0):
        raise OptionError(f"--false-alarm must be a probability in (0, 1); got "
                          f"{args.false_alarm}")
    tolerances = {}
    for opt, key, val, unit in (
            ("--sins-bias-tolerance", "sins_bias", args.sins_bias_tolerance, "deg/h"),
            ("--gs-bias-tolerance", "gs_bias", args.gs_bias_tolerance, "deg/h"),
            ("--gs-gyro-scale-tolerance", "gs_gyro_scale", args.gs_gyro_scale_tolerance, "ppm"),
            ("--gs-scale-tolerance", "gs_scale", args.gs_scale_tolerance, "ppm"),
            ("--sf-tolerance", "sf_prior", args.sf_tolerance, "ppm")):
        if val is None:
            continue
        if not (math.isfinite(val) and val >= 0.0):
            raise OptionError(f"{opt} must be a number >= 0 ({unit}); got {val}")
        tolerances[key] = float(units.to_si(val, unit))
    return {"config": rsf_config_from_toml(args.params),
            "params_notes": instrument_notes(args.params, "calibrate rsf"),
            "period": args.period,
            "counts_per_rev": args.counts_per_rev, "k_form": args.k_form, "plot": args.plot,
            "slips": args.slips, "tolerances": tolerances, "false_alarm": args.false_alarm}


def run_file(file: str, o: dict) -> Outcome:
    """Correct one RSF record with the checked options ``o``: read it, have the library
    judge it (:func:`gyrolib.rsf.judge_record`) and format the verdict as text, JSON and a
    summary row."""
    record, info = read_rsf(file, counts_per_rev=o["counts_per_rev"], columns=o["columns"],
                            t0=o["t0"], units=o["units"],
                            decimal_comma=o["decimal_comma"], return_info=True)
    from gyrolib import rsf  # imported by the rsf command only (a gc run does not need it)

    try:
        ver = rsf.judge_record(record, o["period"], o["config"], k_form=o["k_form"],
                               slips=o["slips"], false_alarm=o["false_alarm"],
                               notes=[*o["params_notes"], *info.notes], **o["tolerances"])
    except ValueError as exc:
        raise RecordError(file, one_line(exc).replace("period ", "--period ", 1)) from None
    data = _rsf_json(file, ver, info)
    st = ver.result.eps1_stats()
    row = {"file": file, "method": "rsf", "quantity": ver.quantity,
           "estimate": ver.estimate if ver.valid else "",
           "sigma": ver.sigma if ver.valid else "", "unit": ver.unit, "valid": ver.valid,
           "status": ver.status, "reason": ver.reason, "reason_code": ver.reason_code,
           "hint": ver.hint,
           "notes": "; ".join([*ver.notes, *(["sigma is the total standard uncertainty "
                                              "(eps1_hat_mean_std_parts); the standard error "
                                              f"of the mean alone is {st['sem']:.4g}"]
                                             if st["n"] > 1 else [])])}
    artifacts = ([(o["plot"], "rsf_plot", (ver.result, ver.details["prediction"]))]
                 if o["plot"] and ver.valid else [])
    message = "" if ver.valid else f"{file}: no valid estimate: {ver.reason}"
    return Outcome(file=file, status=ver.status, message=message, text=_rsf_text(file, ver),
                   data=data, row=row, artifacts=artifacts)


#: Units of the RSF JSON's numeric fields (SI).
_RSF_UNITS = {"eps1_hat": "1", "eps1_hat_mean": "1", "eps1_hat_spread": "1",
              "eps1_hat_sem": "1", "K": "1", "rate": "rad/s", "abs_rate": "rad/s",
              "mean_abs_rate": "rad/s", "t_start": "s", "period": "s", "dt": "s",
              "gap_time": "s", "residual_end": "rad", "residual_raw_end": "rad",
              "delta_k_predicted": "1", "eps1_hat_mean_std": "1",
              "eps1_hat_mean_std_parts": "1", "tolerances": "rad/s or 1",
              "bias_estimate": "rad/s", "bias_estimate_std": "rad/s"}


def _rsf_json(file: str, ver, info) -> dict:
    """The JSON of an RSF verdict: the correction's summary, the uncertainty's, then the
    verdict's fields (``checks``: each with its name, value and one band, and the
    message of the uncertainty's check)."""
    res, unc, pred = ver.result, ver.details["uncertainty"], ver.details["prediction"]
    out = res.summary()
    out["file"] = str(file)
    out.update(unc.summary())       # eps1_hat_mean_std (+ parts), checks, valid, reason
    out["checks"] = [{**c.summary(), "message": m["message"]}
                     for c, m in zip(ver.checks, unc.checks)]
    out.update(status=ver.status, reason=ver.reason, reason_code=ver.reason_code,
               hint=ver.hint or None, counts=ver.counts.summary())
    out["delta_k_predicted"] = {"mean": pred.mean, "std": pred.std, "eq7": pred.eq7,
                                "std_per_interval": [float(x) for x in res.delta_k_std(pred)]}
    out["notes"] = list(ver.notes)
    out["time_base"] = info.summary()
    out["units"] = _RSF_UNITS
    return out


def _rsf_text(file: str, ver) -> str:
    res, pred = ver.result, ver.details["prediction"]
    e = np.asarray(units.from_si(res.eps1_hat, "ppm"))
    st = res.eps1_stats()
    rate = units.from_si(res.mean_rate, "deg/s")
    spread = (f"; per-interval spread (SD) {units.from_si(st['spread'], 'ppm'):.4g} ppm, "
              f"standard error of the mean {units.from_si(st['sem'], 'ppm'):.3g} ppm "
              f"(SD/sqrt({st['n']}), independent intervals"
              + (f"; an upper bound here: lag-1 autocorrelation {st['lag1']:.2f}, the GS "
                 "end-point errors cancel in the mean)" if st["lag1"] < -0.25 else ")")
              if st["n"] > 1 else "")
    lines = [
        f"paper RSF correction of {file}: {res.rows} rows, period {res.period:g} s, "
        f"{res.n_intervals} complete interval(s), mean |roll rate| {rate:.5g} deg/s",
        f"  eps1_hat: mean {units.from_si(st['mean'], 'ppm'):.4g} ppm over {st['n']} "
        f"interval(s){spread} (per interval: "
        + ", ".join(f"{x:.4g}" for x in e[:6]) + (", ..." if e.size > 6 else "") + ")",
        (f"  eps1_hat_mean = {units.from_si(ver.estimate, 'ppm'):.4g} ± "
         f"{units.from_si(ver.sigma, 'ppm'):.2g} ppm (1 sigma, total standard uncertainty; "
         "parts adding in quadrature: "
         + ", ".join(f"{k.replace('_', ' ')} {units.from_si(x, 'ppm'):.2g}"
                     for k, x in ver.sigma_parts.items()) + " ppm)" if ver.valid else
         f"  no valid estimate: {ver.reason}"),
        f"  checks at a {100 * ver.false_alarm:g} % family-wise false-alarm rate (each "
        "statistic's band decides validity): " + ("FAIL" if ver.failed else "all pass"),
        *(f"    {c.line()}" for c in ver.checks),
        f"  K (k_form {res.k_form}): mean {np.mean(res.k):.8f}",
        f"  error model at this rate: delta K = {units.from_si(pred.mean, 'ppm'):.3g} ± "
        f"{units.from_si(pred.std, 'ppm'):.3g} ppm per interval",
        f"  {ver.counts.line()} (the first row, missing values or steps across gaps); "
        f"gaps {res.gaps} ({res.gap_time:.4g} s without rows)",
        f"  roll angle vs GS at the end: corrected "
        f"{units.from_si(res.residual[-1], 'deg'):.4g} deg, uncorrected "
        f"{units.from_si(res.residual_raw[-1], 'deg'):.4g} deg",
    ]
    lines += [f"  note: {n}" for n in ver.notes]
    lines += [f"  {ver.hint}"] if ver.hint else []
    return "\n".join(lines) + "\n"
