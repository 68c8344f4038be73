"""The ``calibrate`` command: ``python -m gyrolib calibrate gc|rsf FILE [...]``.

Bad input (a missing file or column, a non-numeric cell, time not increasing, an empty or
non-CSV file, an unknown TOML field) exits with status 2 and one line on stderr naming the
file, the row or column and what was expected; nothing is written (no JSON, no plot).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from pathlib import Path

import numpy as np

from gyrolib import units
from gyrolib.gc.calibration import calibrate as calibrate_gc
from gyrolib.gc.calibration import plot_calibration
from gyrolib.gc.params import MEASUREMENT_NAMES
from gyrolib.records.errors import RecordError
from gyrolib.records.params import gc_params_from_toml, load_toml, rsf_config_from_toml
from gyrolib.records.tables import GCChunks, read_rsf
from gyrolib.rsf.calibration import calibrate as calibrate_rsf
from gyrolib.rsf.calibration import plot_correction
from gyrolib.rsf.correction import predict_delta_k

__all__ = ["add_parser", "run"]

_PLOT_SUFFIXES = (".png", ".pdf", ".svg", ".jpg", ".jpeg")


def add_parser(sub: argparse._SubParsersAction, parser_class: type) -> None:
    """Add ``calibrate`` with its ``gc`` and ``rsf`` sub-commands to ``sub``; usage errors of
    those go through ``parser_class`` (one line, status 2)."""
    cal = sub.add_parser("calibrate", help="apply paper GC or RSF to a recorded CSV file")
    methods = cal.add_subparsers(dest="method", required=True, parser_class=parser_class)
    gc = methods.add_parser(
        "gc", help="paper GC: drift ω_gc of a floated gyro from a gyrocompass-mode record",
        description="Run paper GC's 10-state Kalman filter on a CSV record with the columns "
                    "t (s), angle_sensor (rad), inclinometer_y, inclinometer_z (m/s^2).")
    gc.add_argument("file", help="CSV record (.csv or .csv.gz)")
    gc.add_argument("--params", metavar="P.toml",
                    help="TOML file overriding GyrocompassParams fields (SI)")
    gc.add_argument("--json", action="store_true", help="print one JSON object (SI)")
    gc.add_argument("--plot", metavar="OUT.png", help="write the ω_gc estimate with its ±σ band")
    gc.add_argument("--gate", type=float, default=0.9999,
                    help="χ² gate probability for an innovation (default 0.9999)")
    gc.add_argument("--store-every", type=int, default=100, metavar="N",
                    help="store estimates every N rows (default 100)")
    rsf = methods.add_parser(
        "rsf", help="paper RSF: roll-gyro scale-factor error per correction interval",
        description="Apply paper RSF's correction (Eqs. (1)-(3)) to a CSV record with the "
                    "columns t (s), sins_increment (rad) and gs_angle (rad) or "
                    "encoder_counts (wrapped, with --counts-per-rev).")
    rsf.add_argument("file", help="CSV record (.csv or .csv.gz)")
    rsf.add_argument("--period", type=float, required=True, metavar="S",
                     help="correction interval Δt in seconds")
    rsf.add_argument("--counts-per-rev", type=int, metavar="N",
                     help="encoder counts per revolution (for an encoder_counts column)")
    rsf.add_argument("--k-form", choices=("linear", "reciprocal"), default="linear",
                     help="K = 1 − ε̂1 (linear, default) or 1/(1 + ε̂1)")
    rsf.add_argument("--params", metavar="P.toml",
                     help="TOML tables [sins], [gs], [encoder] overriding the sensor models "
                          "(for the predicted δK)")
    rsf.add_argument("--json", action="store_true", help="print one JSON object (SI)")
    rsf.add_argument("--plot", metavar="OUT.png", help="write ε̂1 per interval")


class _Progress:
    """A progress bar on stderr, shown only on a terminal and only once a run has taken more
    than ``after`` seconds (short runs print nothing)."""

    def __init__(self, label: str, fraction, after: float = 2.0) -> None:
        self.label = label
        self.fraction = fraction
        self.after = after
        self.t0 = time.perf_counter()
        self.shown = False
        self.enabled = sys.stderr.isatty()

    def __call__(self, _rows: int) -> None:
        if not self.enabled or time.perf_counter() - self.t0 < self.after:
            return
        f = min(max(self.fraction(), 0.0), 1.0)
        bar = "#" * int(30 * f)
        sys.stderr.write(f"\r{self.label} [{bar:<30}] {100 * f:3.0f}%")
        sys.stderr.flush()
        self.shown = True

    def clear(self) -> None:
        if self.shown:
            sys.stderr.write("\r\033[K")
            sys.stderr.flush()
            self.shown = False


def _check_plot_path(path: str | None) -> None:
    if path is None:
        return
    p = Path(path)
    if p.suffix.lower() not in _PLOT_SUFFIXES:
        raise RecordError(path, f"expected a plot file ending in {', '.join(_PLOT_SUFFIXES)}")
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.is_dir():
        raise RecordError(path, f"cannot write the plot: directory {str(parent)!r} does not "
                          "exist")
    if not os.access(parent, os.W_OK):
        raise RecordError(path, f"cannot write the plot: directory {str(parent)!r} is not "
                          "writable")


def _save(fig, path: str) -> None:
    import matplotlib.pyplot as plt

    try:
        fig.savefig(path, dpi=110, bbox_inches="tight")
    except OSError as exc:
        raise RecordError(path, f"cannot write the plot: {exc.strerror or exc}") from None
    finally:
        plt.close(fig)


def _json(obj: object) -> str:
    """One line of strict JSON; a non-finite float becomes null."""
    def clean(o):
        if isinstance(o, dict):
            return {k: clean(x) for k, x in o.items()}
        if isinstance(o, list | tuple):
            return [clean(x) for x in o]
        if isinstance(o, float) and not math.isfinite(o):
            return None
        return o

    return json.dumps(clean(obj), allow_nan=False) + "\n"


def _fmt(x: float, digits: int = 4) -> str:
    return f"{x:.{digits}g}"


def _run_gc(args: argparse.Namespace) -> int:
    _check_plot_path(args.plot)
    if not 0.0 < args.gate < 1.0:
        raise RecordError(args.file, f"--gate must be a probability in (0, 1); got {args.gate}")
    if args.store_every < 1:
        raise RecordError(args.file, f"--store-every must be >= 1; got {args.store_every}")
    params = gc_params_from_toml(args.params)
    dt_given = args.params is not None and "dt" in load_toml(args.params)
    chunks = GCChunks(args.file)
    it = iter(chunks)
    first = next(it)              # checks the header and the first chunk
    notes = []
    if not dt_given and first.n > 1:
        step = float(np.median(np.diff(first.t)))
        step = float(f"{step:.9g}")
        if abs(step - params.dt) > 1e-6 * params.dt:
            import dataclasses

            params = dataclasses.replace(params, dt=step)
            notes.append(f"dt = {step:g} s taken from the record's median step")

    def all_chunks():
        yield first
        yield from it

    bar = _Progress(f"calibrate gc {args.file}", lambda: chunks.fraction)
    try:
        res = calibrate_gc(all_chunks(), params, gate=args.gate, store_every=args.store_every,
                        progress=bar)
    finally:
        bar.clear()
    fig = None
    if args.plot:

        fig = plot_calibration(res)
        _save(fig, args.plot)
    if args.json:
        out = res.summary()
        out["file"] = str(args.file)
        out["dt"] = params.dt
        out["notes"] = notes
        sys.stdout.write(_json(out))
        return 0
    a = units.from_si(res.omega_gc, "arcsec_paper/s")
    s = units.from_si(res.omega_gc_std, "arcsec_paper/s")
    band = res.nis_band()
    lines = [
        f"paper GC calibration of {args.file}: {res.rows} rows over {res.t_final:.6g} s"
        + (f" ({res.gaps} gap(s), {res.gap_time:.6g} s without rows)" if res.gaps else ""),
        f"  omega_gc = {_fmt(a)} ± {_fmt(s, 2)} arcsec/s (paper's arcsec, 1 sigma)"
        f"  = {res.omega_gc:.4e} ± {res.omega_gc_std:.2e} rad/s",
        f"  samples used {res.rows_used}, rejected {res.rows_rejected} (an innovation beyond "
        f"the {100 * res.gate:g} % chi-square gate), missing values "
        f"{int(res.missing.sum())}",
        "  mean NIS (99 % band): " + ", ".join(
            f"{nm} {res.nis_mean[q]:.4f} [{band[q, 0]:.4f}, {band[q, 1]:.4f}]"
            for q, nm in enumerate(MEASUREMENT_NAMES)),
        f"  {res.verdict()}",
    ]
    lines += [f"  note: {n}" for n in notes]
    sys.stdout.write("\n".join(lines) + "\n")
    return 0


def _run_rsf(args: argparse.Namespace) -> int:
    _check_plot_path(args.plot)
    if not (math.isfinite(args.period) and args.period > 0):
        raise RecordError(args.file, f"--period must be a positive number of seconds; got "
                          f"{args.period}")
    if args.counts_per_rev is not None and args.counts_per_rev < 2:
        raise RecordError(args.file, f"--counts-per-rev must be an integer >= 2; got "
                          f"{args.counts_per_rev}")
    config = rsf_config_from_toml(args.params)
    record = read_rsf(args.file, counts_per_rev=args.counts_per_rev)
    if record.n < 2:
        raise RecordError(args.file, "expected at least two data rows")
    span = float(record.t[-1] - record.t[0])
    if args.period > span:
        raise RecordError(args.file, f"--period {args.period} s is longer than the record "
                          f"({span:.6g} s): no complete correction interval")
    try:
        res = calibrate_rsf(record, args.period, k_form=args.k_form)
    except ValueError as exc:
        raise RecordError(args.file, str(exc)) from None
    if res.n_intervals == 0:
        raise RecordError(args.file, "no correction interval holds a usable sample (every "
                          "sample is missing or follows a gap)")
    pred = predict_delta_k(config, res.period, rate=res.mean_rate)
    if args.plot:

        _save(plot_correction(res, pred), args.plot)
    if args.json:
        out = res.summary()
        out["file"] = str(args.file)
        out["delta_k_predicted"] = {"mean": pred.mean, "std": pred.std, "eq7": pred.eq7,
                                    "std_per_interval": [float(x) for x in
                                                         res.delta_k_std(pred)]}
        sys.stdout.write(_json(out))
        return 0
    e = np.asarray(units.from_si(res.eps1_hat, "ppm"))
    rate = units.from_si(float(np.mean(res.rate)), "deg/s")
    spread = f", spread {np.std(e, ddof=1):.4g} ppm" if e.size > 1 else ""
    lines = [
        f"paper RSF correction of {args.file}: {res.rows} rows, period {res.period:g} s, "
        f"{res.n_intervals} complete interval(s), mean roll rate {rate:.5g} deg/s",
        f"  eps1_hat: mean {np.mean(e):.4g} ppm{spread} (per interval: "
        + ", ".join(f"{x:.4g}" for x in e[:6]) + (", ..." if e.size > 6 else "") + ")",
        f"  K (k_form {res.k_form}): mean {np.mean(res.k):.8f}",
        f"  error model at this rate: delta K = {units.from_si(pred.mean, 'ppm'):.3g} ± "
        f"{units.from_si(pred.std, 'ppm'):.3g} ppm per interval",
        f"  samples used {res.samples_used}, skipped {res.samples_skipped} (missing), "
        f"gaps {res.gaps}",
        f"  roll angle vs GS at the end: corrected "
        f"{units.from_si(res.residual[-1], 'deg'):.4g} deg, uncorrected "
        f"{units.from_si(res.residual_raw[-1], 'deg'):.4g} deg",
    ]
    sys.stdout.write("\n".join(lines) + "\n")
    return 0


def run(args: argparse.Namespace) -> int:
    """Run ``calibrate gc`` or ``calibrate rsf``; bad input: one line on stderr, status 2."""
    try:
        if args.method == "gc":
            return _run_gc(args)
        return _run_rsf(args)
    except RecordError as exc:
        sys.stderr.write(f"error: {exc}\n")
        return 2
    except (ValueError, TypeError) as exc:
        # a record that reads but cannot be used (e.g. parameters out of range)
        sys.stderr.write(f"error: {args.file}: {' '.join(str(exc).split())}\n")
        return 2
