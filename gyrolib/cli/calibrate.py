"""The ``calibrate`` command: ``python -m gyrolib calibrate gc|rsf FILE... [...]``.

Exit status: 0 every file gave a valid estimate; 2 bad input (a missing file or column, a
non-numeric cell, time not increasing, an empty or non-CSV file, an unknown TOML field, a
column whose values are implausible in SI — degrees, milliseconds, g — or a bad option);
3 no valid estimate (paper GC: no latitude stated, or the filter lost lock — the gate
rejected more than the allowed share of a sensor's samples, or a sensor's mean NIS is far
outside its band — or a check of the model failed: a sensor's mean NIS or whiteness, or the
split-record consistency of ω_gc, at a stated family-wise false-alarm rate,
``--false-alarm``; ``--accept-misfit`` gives the estimate of a misfit record anyway, marked
``"misfit"``, with status 0).

Paper GC's σ(ω_gc) carries the instrument constants estimated with the state, each with a
stated prior: the angle sensor's null offset (``--offset-prior``), the inclinometers' biases
(``--inclinometer-bias-prior``) and the scale common to ``H/f`` and the angle sensor's gain
(``--scale-tolerance``); the output prints σ's parts.  The Earth-rate components come from
``--latitude``, a ``latitude`` key of ``--params`` (or both its ``Omega_h`` and ``Omega_v``) or
the record's ``# latitude_deg:`` line; an option or params file wins over the record's line,
and a note says both.  Without any there is no valid estimate (status 3; the Earth rate
reads as drift, so a record made at 45° calibrated with paper GC's values, about 53.9° N, is
hundreds of σ off and fits): ``--latitude paper`` assumes paper GC's values, and the output
says so (``"latitude_source"``).  Bad input
prints one line on stderr naming the file, the row or column and what was expected; a lost
lock prints "no valid estimate" and why (and one line on stderr).  In either case nothing is
written (no plot, no Allan plot, no TOML) — except ``--summary``, the report of a batch.

Outputs never destroy data: every output (``--summary``, ``--plot``, ``--allan``,
``--fit-noise`` TOML) is written to a temporary file in its own folder, then renamed onto its
path, so it is either complete or absent; an output path that is also an input (or another
output) is refused with status 2 before anything runs; an existing output is replaced only
by a complete new file, and never with ``--no-clobber`` (status 2).  Ctrl-C stops the run
with status 130 and one line, and leaves no partial file (outputs finished before are kept).
A file listed twice is calibrated once, with a note on stderr.

Time stamps of an absolute clock (Unix time, any first time of at least
:data:`gyrolib.records.ABSOLUTE_TIME` s) are taken relative to the first row, or to
``--t0``; the report says so.  ``--columns t=time,...`` maps other header names.

Several files (or ``--summary OUT.csv``) make a batch: each file is calibrated on its own
(``--workers K``: in a :class:`concurrent.futures.ProcessPoolExecutor` whose workers are
forked from this process, gyrolib already imported), a bad or invalid file is reported in
its row (status ``error``, with the one-line reason, whatever the failure — also one that
happens inside a worker process) and on stderr while the others proceed, and the exit status
is 2 if any file failed, else 3 if any was invalid.  A progress bar (tqdm) goes to stderr on a
terminal, never with ``--json`` or when stderr is piped.
"""

from __future__ import annotations

import argparse
import concurrent.futures
import contextlib
import csv
import dataclasses
import io
import json
import math
import multiprocessing
import os
import signal
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Final

import numpy as np

import gyrolib
from gyrolib import gc, units
from gyrolib.gc.model.params import MEASUREMENT_NAMES, PAPER_LATITUDE
from gyrolib.records.errors import RecordError
from gyrolib.records.params import gc_params_from_toml, load_toml, rsf_config_from_toml
from gyrolib.records.reader import GCChunks, parse_columns, read_gc, read_rsf

__all__ = ["EXIT_BAD_INPUT", "EXIT_INTERRUPTED", "EXIT_INVALID", "SUMMARY_COLUMNS",
           "add_parser", "run"]

#: Exit status of bad input (unreadable, implausible or a bad option).
EXIT_BAD_INPUT: Final[int] = 2
#: Exit status of a run without a valid estimate (paper GC's filter lost lock).
EXIT_INVALID: Final[int] = 3
#: Exit status of a run stopped by Ctrl-C (128 + SIGINT, the shell's convention).
EXIT_INTERRUPTED: Final[int] = 130

#: Columns of ``--summary OUT.csv``, one row per file.
SUMMARY_COLUMNS: Final[tuple[str, ...]] = (
    "file", "method", "quantity", "estimate", "sigma", "unit", "valid", "status", "reason",
    "notes")

_PLOT_SUFFIXES = (".png", ".pdf", ".svg", ".jpg", ".jpeg")

#: Units of the noise parameters ``--fit-noise`` can fit (for the printed values).
_FIT_UNITS: Final[dict[str, str]] = {
    "alpha1": "rad/s", "sigma1_sq": "m²/s⁴", "xi1": "", "C_as": "rad²·s", "C_in": "m²/s³",
    "C_incl_y": "m²/s³", "C_incl_z": "m²/s³"}
_FIT_DEFAULT: Final[str] = "alpha1,sigma1_sq,C_as,C_in"

#: Default 1σ relative uncertainty of the scale common to H/f and the angle sensor's gain
#: (a floated gyro whose H/f and pick-off gain are known to 0.1 %).
DEFAULT_SCALE_TOLERANCE: Final[float] = 1e-3
#: Default 1σ prior of the angle sensor's null offset (arcsec): covers a logger that starts
#: 1 s late ((H/f) Ω_h · 1 s ≈ 18″).
DEFAULT_OFFSET_PRIOR_ARCSEC: Final[float] = 20.0
#: Default 1σ prior of each inclinometer's bias (mg; real ones: 0.1–1 mg).
DEFAULT_INCL_BIAS_PRIOR_MG: Final[float] = 0.5


# Parser ----------------------------------------------------------------------------------
def add_parser(sub: argparse._SubParsersAction, parser_class: type) -> None:
    """Add ``calibrate`` with its ``gc`` and ``rsf`` sub-commands to ``sub``; usage errors of
    those go through ``parser_class`` (one line, status 2)."""
    cal = sub.add_parser("calibrate", help="apply paper GC or RSF to recorded CSV files")
    methods = cal.add_subparsers(dest="method", required=True,
                                 parser_class=_signed_values(parser_class))
    gcp = methods.add_parser(
        "gc", help="paper GC: drift ω_gc of a floated gyro from a gyrocompass-mode record",
        description="Run paper GC's 10-state Kalman filter on CSV records with the columns "
                    "t (s), angle_sensor (rad), inclinometer_y, inclinometer_z (m/s^2). "
                    "Exit status 0 valid, 2 bad input, 3 no valid estimate (no latitude "
                    "stated, lost lock or a failed model check).")
    gcp.add_argument("files", nargs="+", metavar="FILE", help="CSV record (.csv or .csv.gz)")
    gcp.add_argument("--params", metavar="P.toml",
                     help="TOML file overriding GyrocompassParams fields (SI)")
    gcp.add_argument("--json", action="store_true", help="print one JSON object per file (SI)")
    gcp.add_argument("--plot", metavar="OUT.png", help="write the ω_gc estimate with its ±σ band")
    gcp.add_argument("--gate", type=float, default=0.9999,
                     help="χ² gate probability for an innovation (default 0.9999)")
    gcp.add_argument("--store-every", type=int, default=100, metavar="N",
                     help="store estimates every N rows (default 100)")
    gcp.add_argument("--inclinometers", default="y,z", metavar="MAP",
                     help="which columns the filter reads as δ (tilt about the input axis, "
                          "−sin β_n in Eq. (5)) and γ (+cos β_n): 'y,z' (default), 'z,y' "
                          "(a swapped pair), '-y,z' (y's sign flipped), ...")
    gcp.add_argument("--fit-noise", nargs="?", const="", default=None, metavar="OUT.toml",
                     help="fit the vibration filter and sensor noises to the record by maximum "
                          "likelihood, print them ± SE, calibrate with them, and write them "
                          "to OUT.toml (a file --params accepts) when given")
    gcp.add_argument("--fit", default=_FIT_DEFAULT, metavar="NAMES",
                     help=f"parameters --fit-noise fits, comma-separated (default "
                          f"{_FIT_DEFAULT}; also xi1, C_incl_y, C_incl_z)")
    gcp.add_argument("--allan", metavar="OUT.png",
                     help="write the Allan deviation of the angle-sensor rate and of the "
                          "inclinometers, with paper GC's model curves, and print the angle "
                          "random walk, bias instability and rate random walk read off it "
                          "(IEEE Std 952), each with its uncertainty")
    gcp.add_argument("--max-rejected", type=float, default=0.01, metavar="SHARE",
                     help="largest share of a sensor's samples the gate may reject before "
                          "the run counts as lost lock (default 0.01)")
    gcp.add_argument("--latitude", default=None, metavar="DEG|paper",
                     help="latitude of the test site in degrees north, in (0, 90): Omega_h, "
                          "Omega_v from the Earth's rate (default: the params file's "
                          "'latitude', else the record's '# latitude_deg:' line; without "
                          "any there is no valid estimate, exit 3); 'paper' assumes paper "
                          "GC's Omega_h, Omega_v (about 53.9 N) and says so")
    gcp.add_argument("--scale-tolerance", type=float, default=None, metavar="REL",
                     help="1-sigma relative uncertainty of the scale common to H/f and the "
                          f"angle sensor's gain (default {DEFAULT_SCALE_TOLERANCE:g}); it "
                          "reads as a drift of REL*Omega_h and enters sigma(omega_gc)")
    gcp.add_argument("--offset-prior", type=float, default=None, metavar="ARCSEC",
                     help="1-sigma prior of the angle sensor's null offset, estimated with the "
                          f"state (default {DEFAULT_OFFSET_PRIOR_ARCSEC:g} arcsec; a logger "
                          "that starts late reads as an offset)")
    gcp.add_argument("--inclinometer-bias-prior", type=float, default=None, metavar="MG",
                     help="1-sigma prior of each inclinometer's bias in mg, estimated with "
                          f"the state (default {DEFAULT_INCL_BIAS_PRIOR_MG:g} mg); a bias "
                          "cannot be told from a tilt, so it enters sigma(omega_gc)")
    gcp.add_argument("--false-alarm", type=float, default=0.01, metavar="P",
                     help="family-wise false-alarm rate of the model checks that make a "
                          "record invalid (default 0.01)")
    gcp.add_argument("--accept-misfit", action="store_true",
                     help="give the estimate of a record whose model checks fail, marked "
                          "misfit (exit 0), instead of no valid estimate (exit 3)")
    _batch_options(gcp)
    rsfp = methods.add_parser(
        "rsf", help="paper RSF: roll-gyro scale-factor error per correction interval",
        description="Apply paper RSF's correction (Eqs. (1)-(3)) to CSV records with the "
                    "columns t (s), sins_increment (rad) and gs_angle (rad) or "
                    "encoder_counts (wrapped, with --counts-per-rev). Exit status 0 ok, "
                    "2 bad input.")
    rsfp.add_argument("files", nargs="+", metavar="FILE", help="CSV record (.csv or .csv.gz)")
    rsfp.add_argument("--period", type=float, required=True, metavar="S",
                      help="correction interval Δt in seconds")
    rsfp.add_argument("--counts-per-rev", type=int, metavar="N",
                      help="encoder counts per revolution (for an encoder_counts column)")
    rsfp.add_argument("--k-form", choices=("linear", "reciprocal"), default="linear",
                      help="K = 1 − ε̂1 (linear, default) or 1/(1 + ε̂1)")
    rsfp.add_argument("--params", metavar="P.toml",
                      help="TOML tables [sins], [gs], [encoder] overriding the sensor models "
                           "(for the predicted δK)")
    rsfp.add_argument("--json", action="store_true", help="print one JSON object per file (SI)")
    rsfp.add_argument("--plot", metavar="OUT.png", help="write ε̂1 per interval")
    rsfp.add_argument("--slips", choices=("repair", "refuse"), default="repair",
                      help="a whole-turn jump of the GS angle against the SINS turn: remove it "
                           "with a note (default) or refuse the file; a wrapped gs_angle is "
                           "always unwrapped, a quarter-turn jump always refused")
    _batch_options(rsfp)


def _signed_values(parser_class: type) -> type:
    """``parser_class`` that reads ``--inclinometers -y,z`` as ``--inclinometers=-y,z``
    (argparse would take ``-y,z`` for an option)."""

    class Parser(parser_class):
        def parse_known_args(self, args=None, namespace=None):
            if args is not None:
                src, args = list(args), []
                while src:
                    a = src.pop(0)
                    if a == "--inclinometers" and src and src[0].startswith("-"):
                        a = f"--inclinometers={src.pop(0)}"
                    args.append(a)
            return super().parse_known_args(args, namespace)

    return Parser


def _batch_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--summary", metavar="OUT.csv",
                   help="write one row per file: file, method, quantity, estimate, sigma, "
                        "unit, valid, status (ok, invalid, error), reason, notes")
    p.add_argument("--workers", type=int, default=1, metavar="K",
                   help="calibrate K files at a time in separate processes (default 1)")
    p.add_argument("--columns", metavar="MAP",
                   help="the file's header names of the record's columns, e.g. "
                        "t=time,angle_sensor=gyro (default: the names themselves)")
    p.add_argument("--t0", type=float, metavar="S",
                   help="subtract S seconds from every time stamp (default: the first row's "
                        "time when it is an absolute clock, >= 1000 s; else none)")
    p.add_argument("--no-clobber", action="store_true",
                   help="refuse (status 2) to replace an existing output file; by default an "
                        "existing output is replaced, atomically, once its replacement is "
                        "complete")
    p.add_argument("--version", action="version", version=f"gyrolib {gyrolib.__version__}")


# Small helpers ----------------------------------------------------------------------------
class UsageError(ValueError):
    """A bad option (not a bad file): one line, status 2."""


def _check_out_path(path: str | None, suffixes: tuple[str, ...], what: str) -> None:
    if path is None:
        return
    p = Path(path)
    if p.suffix.lower() not in suffixes:
        raise RecordError(path, f"expected {what} file ending in {', '.join(suffixes)}")
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.is_dir():
        raise RecordError(path, f"cannot write {what} file: directory {str(parent)!r} does "
                          "not exist")
    if not os.access(parent, os.W_OK):
        raise RecordError(path, f"cannot write {what} file: directory {str(parent)!r} is not "
                          "writable")


@contextlib.contextmanager
def _atomic(path: str):
    """Yield a temporary path in ``path``'s folder; on success it is renamed onto ``path``
    (atomic on POSIX: readers see the old file or the complete new one), on any failure or
    Ctrl-C it is removed.  The new file gets the mode of the one it replaces, else 0666
    less the umask."""
    p = Path(path)
    parent = p.parent if str(p.parent) else Path(".")
    fd, tmp = tempfile.mkstemp(dir=parent, prefix=f".{p.name}.", suffix=".part" + p.suffix)
    os.close(fd)
    try:
        try:
            mode = os.stat(p).st_mode & 0o777
        except OSError:
            mode = 0o666 & ~_umask()
        os.chmod(tmp, mode)
        yield tmp
        os.replace(tmp, p)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _save(fig, path: str) -> None:
    import matplotlib.pyplot as plt

    try:
        with _atomic(path) as tmp:
            fig.savefig(tmp, dpi=110, bbox_inches="tight", format=Path(path).suffix[1:])
    except OSError as exc:
        raise RecordError(path, f"cannot write the plot: {exc.strerror or exc}") from None
    finally:
        plt.close(fig)


def _write_text(path: str, text: str) -> None:
    try:
        with _atomic(path) as tmp:
            Path(tmp).write_text(text)
    except OSError as exc:
        raise RecordError(path, f"cannot write the file: {exc.strerror or exc}") from None


def _same_file(a: str, b: str) -> bool:
    """Whether two paths name one file (the same inode, or the same absolute path)."""
    with contextlib.suppress(OSError):
        return os.path.samefile(a, b)
    return os.path.abspath(a) == os.path.abspath(b)


def _check_outputs(args: argparse.Namespace, outputs: list[tuple[str, str]]) -> None:
    """Refuse an output that is an input or another output, or (``--no-clobber``) exists."""
    for k, (opt, path) in enumerate(outputs):
        for f in args.files:
            if _same_file(path, f):
                raise UsageError(f"{opt} {path} is also an input file: refusing to write over "
                                 "a record (give another output path)")
        for opt2, path2 in outputs[:k]:
            if _same_file(path, path2):
                raise UsageError(f"{opt} and {opt2} name the same file {path}")
        if args.no_clobber and os.path.lexists(path):
            raise UsageError(f"{opt} {path} exists and --no-clobber is given: nothing "
                             "written")


def _unique_files(files: list[str]) -> tuple[list[str], list[str]]:
    """The files in order with duplicates (the same file under any name) removed, and a
    note for each duplicate."""
    out: list[str] = []
    notes: list[str] = []
    for f in files:
        first = next((g for g in out if _same_file(f, g)), None)
        if first is None:
            out.append(f)
            continue
        same = "" if f == first else f" (as {f})"
        notes.append(f"{first} is listed more than once{same}: calibrated once")
    return out, notes


def _clean(o):
    if isinstance(o, dict):
        return {k: _clean(x) for k, x in o.items()}
    if isinstance(o, list | tuple):
        return [_clean(x) for x in o]
    if isinstance(o, np.generic):
        o = o.item()
    if isinstance(o, float) and not math.isfinite(o):
        return None
    return o


def _json(obj: object) -> str:
    """One line of strict JSON; a non-finite float becomes null."""
    return json.dumps(_clean(obj), allow_nan=False) + "\n"


def _fmt(x: float, digits: int = 4) -> str:
    return f"{x:.{digits}g}"


def _one_line(text: str) -> str:
    return " ".join(str(text).split())


def _from_library(exc: BaseException) -> bool:
    """Whether ``exc`` was raised by gyrolib's own code (not inside numpy or scipy)."""
    tb = exc.__traceback__
    last = None
    while tb is not None:
        last = tb.tb_frame.f_code.co_filename
        tb = tb.tb_next
    package = str(Path(__file__).resolve().parents[1]) + os.sep
    return last is not None and str(Path(last).resolve()).startswith(package)


def _failure_message(label: str, exc: BaseException) -> str:
    """One line for an error the checks at the door did not catch: gyrolib's message, never
    numpy's or scipy's."""
    if isinstance(exc, RecordError):
        return str(exc)
    if isinstance(exc, MemoryError):
        return (f"{label}: the calibration ran out of memory on this record (MemoryError): "
                "check the time column (t in s from the start, strictly increasing)")
    if not isinstance(exc, ValueError | TypeError | ArithmeticError):
        return f"{label}: the calibration failed ({type(exc).__name__}: {_one_line(exc)})"
    if _from_library(exc):
        return f"{label}: {_one_line(exc)}"
    return (f"{label}: the calibration failed on this record ({type(exc).__name__} inside "
            "the numerics): check the units (t in s, angles in rad, inclinometers in m/s²) "
            "and the parameters given with --params")


@dataclasses.dataclass
class _Outcome:
    """What one file gave: ``status`` "ok", "misfit" (accepted with --accept-misfit),
    "invalid" or "error"; ``message`` the one line for stderr (error: the error; invalid: the
    reason); ``text``/``data`` the report; ``row`` its summary row; ``artifacts`` files to
    write when the run is valid (path → figure or text)."""

    file: str
    status: str
    message: str = ""
    text: str = ""
    data: dict = dataclasses.field(default_factory=dict)
    row: dict = dataclasses.field(default_factory=dict)
    artifacts: list = dataclasses.field(default_factory=list)

    @property
    def code(self) -> int:
        return {"ok": 0, "misfit": 0, "invalid": EXIT_INVALID,
                "error": EXIT_BAD_INPUT}[self.status]


def _bad(method: str, file: str, message: str) -> _Outcome:
    quantity = "omega_gc" if method == "gc" else "eps1_hat_mean"
    unit = "rad/s" if method == "gc" else "1"
    return _Outcome(file=file, status="error", message=message,
                    data={"file": file, "valid": False, "status": "error", "error": message},
                    row={"file": file, "method": method, "quantity": quantity, "estimate": "",
                         "sigma": "", "unit": unit, "valid": False, "status": "error",
                         "reason": message, "notes": ""})


# Progress -----------------------------------------------------------------------------------
def _bar_enabled(args: argparse.Namespace) -> bool:
    """A progress bar only on a terminal and never with --json."""
    try:
        tty = sys.stderr.isatty()
    except (AttributeError, ValueError):
        tty = False
    return bool(tty and not args.json)


class _NoBar:
    """What the code needs of a tqdm bar when none is shown (tqdm not imported: 15 ms)."""

    n: float = 0

    def update(self, k: float = 1) -> None:
        self.n += k

    def __enter__(self) -> _NoBar:
        return self

    def __exit__(self, *exc: object) -> None:
        return None


def _progress(shown: bool, **kwargs):
    """A tqdm bar on stderr (``leave=False``) when ``shown``, else a :class:`_NoBar`."""
    if not shown:
        return _NoBar()
    from tqdm import tqdm

    return tqdm(file=sys.stderr, leave=False, **kwargs)


# Paper GC ---------------------------------------------------------------------------------
def _gc_options(args: argparse.Namespace) -> dict:
    """Checked options of ``calibrate gc`` (UsageError / RecordError on a bad one)."""
    if not 0.0 < args.gate < 1.0:
        raise UsageError(f"--gate must be a probability in (0, 1); got {args.gate}")
    if args.store_every < 1:
        raise UsageError(f"--store-every must be >= 1; got {args.store_every}")
    if not 0.0 <= args.max_rejected < 1.0:
        raise UsageError(f"--max-rejected must be a share in [0, 1); got {args.max_rejected}")
    try:
        mapping = gc.InclinometerMapping.parse(args.inclinometers)
    except ValueError:
        raise UsageError(f"--inclinometers expects two of y, z, -y, -z separated by a comma, "
                         f"each column once (e.g. y,z or z,y or -y,z); got "
                         f"{args.inclinometers!r}") from None
    fit = tuple(s.strip() for s in args.fit.split(",") if s.strip())
    unknown = [s for s in fit if s not in _FIT_UNITS]
    if not fit or unknown or ("C_in" in fit and ({"C_incl_y", "C_incl_z"} & set(fit))):
        raise UsageError(f"--fit expects names among {', '.join(_FIT_UNITS)} (C_in not with "
                         f"C_incl_y, C_incl_z), comma-separated; got {args.fit!r}")
    batch = len(args.files) > 1
    for opt, val in (("--plot", args.plot), ("--allan", args.allan),
                     ("--fit-noise OUT.toml", args.fit_noise or None)):
        if batch and val:
            raise UsageError(f"{opt} writes one file: give one record, not {len(args.files)} "
                             "(--summary OUT.csv reports a batch)")
    _check_out_path(args.plot, _PLOT_SUFFIXES, "a plot")
    _check_out_path(args.allan, _PLOT_SUFFIXES, "a plot")
    _check_out_path(args.fit_noise or None, (".toml",), "a TOML")
    params = gc_params_from_toml(args.params)
    toml = load_toml(args.params) if args.params is not None else {}
    dt_given = "dt" in toml
    if not (math.isfinite(args.false_alarm) and 0.0 < args.false_alarm < 1.0):
        raise UsageError(f"--false-alarm must be a probability in (0, 1); got "
                         f"{args.false_alarm}")
    priors = {}
    for opt, field, val, default, unit in (
            ("--scale-tolerance", "sigma_hf_scale", args.scale_tolerance,
             DEFAULT_SCALE_TOLERANCE, 1.0),
            ("--offset-prior", "sigma_as_offset", args.offset_prior,
             DEFAULT_OFFSET_PRIOR_ARCSEC, units.ARCSEC_PAPER),
            ("--inclinometer-bias-prior", "sigma_incl_bias", args.inclinometer_bias_prior,
             DEFAULT_INCL_BIAS_PRIOR_MG, 1e-3 * units.G0)):
        if val is not None and not (math.isfinite(val) and val >= 0.0):
            raise UsageError(f"{opt} must be a number >= 0; got {val}")
        if val is None and field in toml:     # the params file states it
            continue
        priors[field] = (default if val is None else val) * unit
    params = dataclasses.replace(params, **priors)
    latitude, lat_source = None, LAT_NONE
    if args.latitude is not None:
        if {"Omega_h", "Omega_v", "latitude"} & set(toml):
            raise UsageError("--latitude and the params file's latitude/Omega_h/Omega_v both "
                             "set the Earth rate: give one")
        if args.latitude.strip().lower() == "paper":
            latitude, lat_source = math.degrees(PAPER_LATITUDE), LAT_PAPER
        else:
            try:
                latitude = float(args.latitude)
            except ValueError:
                latitude = math.nan
            if not (math.isfinite(latitude) and 0.0 < latitude < 90.0):
                raise UsageError(f"--latitude must be in degrees north in (0, 90) (paper GC's "
                                 f"model needs both Earth-rate components positive), or "
                                 f"'paper' for paper GC's values; got {args.latitude}")
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
        raise UsageError(f"{args.params} sets {given} but not "
                         f"{({'Omega_h', 'Omega_v'} - {given}).pop()}: give both Earth-rate "
                         "components, or 'latitude' (degrees north), or neither")
    return {"params": params, "dt_given": dt_given, "gate": args.gate,
            "latitude": latitude, "latitude_source": lat_source,
            "false_alarm": args.false_alarm, "accept_misfit": args.accept_misfit,
            "store_every": args.store_every, "max_rejected": args.max_rejected,
            "mapping": mapping, "fit_noise": args.fit_noise, "fit": fit,
            "allan": args.allan, "plot": args.plot, "json": args.json,
            "bar": _bar_enabled(args) and not batch}


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
    if info is not None and info.time_note:
        notes.append(info.time_note)
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
                     (1.0 / 3600.0 / 60.0, "m/s^2/h/sqrt(h)")),
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
                             "N, where paper GC's model holds")
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
    with _progress(bar_ok, total=400, desc="fitting the noise", unit="eval") as bar:
        def progress(n: int) -> None:
            bar.update(max(0, n - bar.n))

        # fit_noise's own gate (a far tail: a gate as tight as the calibration's would cut
        # good samples and bias the intensities low)
        return gc.fit_noise(record, params, fit=o["fit"], progress=progress)


def _as_stated(record: gc.GCRecord, earth: dict) -> gc.GCRecord:
    """The record as calibrated: its own ``# latitude_deg:`` line dropped when the Earth rate
    comes from elsewhere (an option or params file that overrides it, said in a note, or no
    latitude at all), so that :func:`gyrolib.gc.calibrate` does not refuse the rate the user
    stated (it checks the parameters against a record's latitude)."""
    if record.latitude is None or earth["source"] == LAT_RECORD:
        return record
    return dataclasses.replace(record, latitude=None)


def _run_gc_file(file: str, o: dict) -> _Outcome:
    """Calibrate one GC record with the checked options ``o``."""
    params: gc.GyrocompassParams = o["params"]
    mapping: gc.InclinometerMapping = o["mapping"]
    notes: list[str] = []
    fit = None
    whole = o["fit_noise"] is not None or o["allan"] is not None
    if whole:   # the fit and the Allan deviation read the record many times: in memory
        raw, info = read_gc(file, params=params, columns=o["columns"], t0=o["t0"],
                            return_info=True)
        extra = _time_notes(info, raw, params, notes)
        params = _with_step(params, raw.t, notes, o["dt_given"])
        params, earth = _with_latitude(params, getattr(raw, "latitude", None), o, notes)
        record = _as_stated(mapping.apply(raw), earth)
        if o["fit_noise"] is not None:
            fit = _fit_noise(record, params, o, o["bar"])
            params = fit.params
        with _progress(o["bar"], total=record.n, desc=f"calibrate gc {file}",
                       unit="row") as bar:
            res = _calibrate(record, params, o,
                             progress=lambda rows: bar.update(rows - bar.n))
    else:       # stream the file in chunks, each checked at the door
        chunks = GCChunks(file, params=params, columns=o["columns"], t0=o["t0"])
        it = iter(chunks)
        first = next(it)
        info = chunks.info
        extra = _time_notes(info, first, params, notes)
        params = _with_step(params, first.t, notes, o["dt_given"])
        params, earth = _with_latitude(params, getattr(first, "latitude", None), o, notes)

        def mapped():
            yield _as_stated(mapping.apply(first), earth)
            for chunk in it:
                yield _as_stated(mapping.apply(chunk), earth)

        # the next chunk is read (parsed, checked at the door) in one thread while the
        # filter, which releases the GIL, runs on the current one: two chunks in flight
        with concurrent.futures.ThreadPoolExecutor(max_workers=1) as reader, \
                _progress(o["bar"], total=100.0, desc=f"calibrate gc {file}", unit="%",
                          bar_format="{desc} {percentage:3.0f}%|{bar}| {elapsed}<{remaining}"
                          ) as bar:
            res = _calibrate(mapped(), params, o, executor=reader,
                             progress=lambda _rows: bar.update(100 * chunks.fraction - bar.n))
    valid, reason = bool(res.valid), str(res.reason)
    if not earth["stated"]:   # the Earth rate reads as drift: no latitude, no valid estimate
        valid, reason = False, "; ".join(x for x in (NO_LATITUDE, reason) if x)
    fit_std = 0.0
    if fit is not None:      # the fitted noise carries its own uncertainty (issue 26)
        why = fit.not_identified(float(record.t[-1] - record.t[0]) if record.n > 1 else 1e-9)
        if why:
            valid, reason = False, "; ".join(x for x in (reason, f"noise fit: {why}") if x)
        else:
            total = gc.fit_uncertainty(record, fit, gate=o["gate"],
                                       max_rejected=o["max_rejected"],
                                       false_alarm=o["false_alarm"])
            fit_std = math.sqrt(max(total**2 - res.omega_gc_std**2, 0.0))
    # a record the model checks reject (but the filter kept lock): its estimate on request,
    # marked misfit
    accepted = (not valid and o["accept_misfit"] and not res.lost_lock and earth["stated"]
                and not reason.startswith("noise fit:") and "; noise fit:" not in reason)
    status = "ok" if valid else ("misfit" if accepted else "invalid")
    artifacts = []
    if o["plot"]:
        artifacts.append((o["plot"], "plot", res))
    allan_lines: list[str] = []
    if o["allan"]:
        allan = gc.allan_deviation(raw, params)
        artifacts.append((o["allan"], "allan", allan))
        allan_lines, extra["allan_noise_terms"] = _allan_report(allan)
    if fit is not None and o["fit_noise"]:
        artifacts.append((o["fit_noise"], "text", fit.to_toml()))
    std = math.hypot(res.omega_gc_std, fit_std)
    data = _gc_json(file, res, params, mapping, notes, fit, valid, reason, accepted, earth,
                    fit_std)
    data.update(extra)
    text = _gc_text(file, res, mapping, notes, fit, valid, reason, o, accepted,
                    fit_std, earth) + "".join(f"{ln}\n" for ln in allan_lines)
    given = valid or accepted
    row = {"file": file, "method": "gc", "quantity": "omega_gc", "notes": "; ".join(notes),
           "estimate": res.omega_gc if given else "",
           "sigma": std if given else "", "unit": "rad/s", "valid": valid,
           "status": status, "reason": reason}
    message = "" if (valid or accepted) else f"{file}: no valid estimate: {reason}"
    return _Outcome(file=file, status=status, message=message,
                    text=text, data=data, row=row, artifacts=artifacts)


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
                     "inclinometer_bias_m_s2": params.sigma_incl_bias}
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
    "rejected_t": "s", "nis": "1", "gate": "1 (probability)", "max_rejected": "1 (share)",
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


def _gc_text(file, res, mapping, notes, fit, valid, reason, o, accepted=False,
             fit_std=0.0, earth=None) -> str:
    band = res.nis_band()
    lines = [
        f"paper GC calibration of {file}: {res.rows} rows over {res.t_final:.6g} s"
        + (f" ({res.gaps} gap(s), {res.gap_time:.6g} s without rows)" if res.gaps else ""),
        f"  inclinometers (--inclinometers {mapping}): {mapping.describe()}",
    ] + ([_earth_line(earth)] if earth is not None else [])
    if fit is not None:
        parts = [f"{n} = {_fmt(fit.value(n))} ± {_fmt(fit.std_error(n), 2)}"
                 + (f" {_FIT_UNITS[n]}" if _FIT_UNITS.get(n) else "") for n in fit.names]
        lines.append("  noise fitted (maximum likelihood, ± standard error): "
                     + ", ".join(parts))
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
                     + f"  omega_gc = {_fmt(a['deg/h'])} ± {_fmt(s['deg/h'], 2)} deg/h (1 sigma)"
                     f"  = {_fmt(a['arcsec/s'])} ± {_fmt(s['arcsec/s'], 2)} arcsec/s (standard)"
                     f"  = {_fmt(a['arcsec_paper/s'])} ± {_fmt(s['arcsec_paper/s'], 2)} "
                     f"arcsec/s (paper's arcsec, 1\" = 0.485e-5 rad)  = {res.omega_gc:.4e} ± "
                     f"{std:.2e} rad/s")
        parts = res.omega_gc_std_parts
        p = res.params
        lines.append("  sigma in parts (adding in quadrature): "
                     f"noise {_fmt(units.from_si(parts['noise'], 'arcsec_paper/s'), 2)}, "
                     "instrument biases "
                     f"{_fmt(units.from_si(parts['instrument_biases'], 'arcsec_paper/s'), 2)}"
                     f", scale {_fmt(units.from_si(parts['scale'], 'arcsec_paper/s'), 2)}"
                     + (f", noise fit {_fmt(units.from_si(fit_std, 'arcsec_paper/s'), 2)}"
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
        "  mean NIS (99 % band): " + ", ".join(
            f"{nm} {res.nis_mean[q]:.4f} [{band[q, 0]:.4f}, {band[q, 1]:.4f}]"
            for q, nm in enumerate(MEASUREMENT_NAMES)),
        f"  {res.verdict()}",
        f"  model checks at a {100 * res.false_alarm:g} % family-wise false-alarm rate: "
        + ("all pass" if not res.misfit else "FAIL"),
    ]
    lines += [f"  note: {n}" for n in notes]
    return "\n".join(lines) + "\n"


# Paper RSF --------------------------------------------------------------------------------
def _rsf_options(args: argparse.Namespace) -> dict:
    if not (math.isfinite(args.period) and args.period > 0):
        raise UsageError(f"--period must be a positive number of seconds; got {args.period}")
    if args.counts_per_rev is not None and args.counts_per_rev < 2:
        raise UsageError(f"--counts-per-rev must be an integer >= 2; got "
                         f"{args.counts_per_rev}")
    if len(args.files) > 1 and args.plot:
        raise UsageError(f"--plot writes one file: give one record, not {len(args.files)} "
                         "(--summary OUT.csv reports a batch)")
    _check_out_path(args.plot, _PLOT_SUFFIXES, "a plot")
    return {"config": rsf_config_from_toml(args.params), "period": args.period,
            "counts_per_rev": args.counts_per_rev, "k_form": args.k_form, "plot": args.plot,
            "slips": args.slips}


def _rsf_prediction(res, config):
    """δK the error model predicts at the record's mean rate (:func:`rsf.predict_delta_k`)."""
    from gyrolib import rsf

    return rsf.predict_delta_k(config, res.period, rate=res.mean_rate)


def _run_rsf_file(file: str, o: dict) -> _Outcome:
    record, info = read_rsf(file, counts_per_rev=o["counts_per_rev"], columns=o["columns"],
                            t0=o["t0"], return_info=True)
    if record.n < 2:
        raise RecordError(file, "expected at least two data rows")
    span = float(record.t[-1] - record.t[0])
    if o["period"] > span:
        raise RecordError(file, f"--period {o['period']} s is longer than the record "
                          f"({span:.6g} s): no complete correction interval")
    from gyrolib import rsf  # imported by the rsf command only (a gc run does not need it)

    try:
        res = rsf.calibrate(record, o["period"], k_form=o["k_form"], slips=o["slips"])
    except ValueError as exc:
        raise RecordError(file, _one_line(exc)) from None
    if res.n_intervals == 0:
        raise RecordError(file, "no correction interval holds a usable sample (every "
                          "sample is missing or follows a gap)")
    pred = _rsf_prediction(res, o["config"])
    out = res.summary()
    out["file"] = str(file)
    out["valid"] = True
    out["reason"] = ""
    out["delta_k_predicted"] = {"mean": pred.mean, "std": pred.std, "eq7": pred.eq7,
                                "std_per_interval": [float(x) for x in res.delta_k_std(pred)]}
    e = np.asarray(units.from_si(res.eps1_hat, "ppm"))
    st = res.eps1_stats()
    rate = units.from_si(res.mean_rate, "deg/s")
    notes = ([info.time_note] if info.time_note else []) + list(res.notes)
    if res.reverses:
        notes.append(f"the roll rate reverses ({int(np.sum(res.rate > 0))} interval(s) turn "
                     f"one way, {int(np.sum(res.rate < 0))} the other, "
                     f"{int(np.sum(res.reversal))} reverse inside and are left out of the "
                     "mean: their net turn is small, their eps1_hat ill-conditioned); the rate "
                     "is reported as mean |omega|")
    out["notes"] = notes
    out["time_base"] = info.summary()
    out["units"] = {"eps1_hat": "1", "eps1_hat_mean": "1", "eps1_hat_spread": "1",
                    "eps1_hat_sem": "1", "K": "1", "rate": "rad/s", "abs_rate": "rad/s",
                    "mean_abs_rate": "rad/s", "t_start": "s", "period": "s", "dt": "s",
                    "gap_time": "s", "residual_end": "rad", "residual_raw_end": "rad",
                    "delta_k_predicted": "1"}
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
        f"  K (k_form {res.k_form}): mean {np.mean(res.k):.8f}",
        f"  error model at this rate: delta K = {units.from_si(pred.mean, 'ppm'):.3g} ± "
        f"{units.from_si(pred.std, 'ppm'):.3g} ppm per interval",
        f"  samples used {res.samples_used}, skipped {res.samples_skipped} (missing values "
        f"or across gaps), gaps {res.gaps} ({res.gap_time:.4g} s without rows)",
        f"  roll angle vs GS at the end: corrected "
        f"{units.from_si(res.residual[-1], 'deg'):.4g} deg, uncorrected "
        f"{units.from_si(res.residual_raw[-1], 'deg'):.4g} deg",
    ]
    lines += [f"  note: {n}" for n in notes]
    row = {"file": file, "method": "rsf", "quantity": "eps1_hat_mean",
           "estimate": st["mean"], "sigma": st["sem"] if st["n"] > 1 else "", "unit": "1",
           "valid": True, "status": "ok", "reason": "",
           "notes": "; ".join(notes + ([f"sigma is the standard error of the mean; the "
                                        f"per-interval spread is {st['spread']:.4g}"]
                                       if st["n"] > 1 else []))}
    artifacts = [(o["plot"], "rsf_plot", (res, pred))] if o["plot"] else []
    return _Outcome(file=file, status="ok", text="\n".join(lines) + "\n", data=out, row=row,
                    artifacts=artifacts)


# One file, many files ---------------------------------------------------------------------
def _process(method: str, file: str, o: dict) -> _Outcome:
    """One file, any failure turned into its outcome (runs in a worker process too)."""
    try:
        if method == "gc":
            return _run_gc_file(file, o)
        return _run_rsf_file(file, o)
    except (UsageError, RecordError) as exc:
        return _bad(method, file, str(exc))
    except Exception as exc:       # any failure is this file's row, not the batch's
        return _bad(method, file, _failure_message(file, exc))


def _write_artifacts(outcome: _Outcome) -> None:
    for path, kind, payload in outcome.artifacts:
        if kind == "plot":
            _save(gc.plot_calibration(payload), path)
        elif kind == "rsf_plot":
            from gyrolib import rsf

            _save(rsf.plot_correction(*payload), path)
        elif kind == "allan":
            _save(gc.plot_allan(payload, title=f"Allan deviation of {outcome.file}"), path)
        else:
            _write_text(path, payload)


def _summary_csv(path: str, outcomes: list[_Outcome]) -> None:
    def cell(x) -> str:
        if isinstance(x, bool):
            return "true" if x else "false"
        if isinstance(x, float):
            return f"{x:.10g}"
        return str(x)

    buf = io.StringIO(newline="")
    w = csv.writer(buf)
    w.writerow(SUMMARY_COLUMNS)
    for o in outcomes:
        w.writerow([cell(o.row.get(c, "")) for c in SUMMARY_COLUMNS])
    try:
        with _atomic(path) as tmp, open(tmp, "w", newline="") as fh:
            fh.write(buf.getvalue())
    except OSError as exc:
        raise RecordError(path, f"cannot write the summary: {exc.strerror or exc}") from None


def _executor(workers: int) -> concurrent.futures.Executor | None:
    """``workers`` processes forked from this one, which has imported gyrolib already (a
    spawned or forkserver worker would import it again: about 4 s, more than a 100 s record
    takes).  They are forked at the first submit, before the progress bar's thread exists,
    so no thread of this process is forked."""
    if workers <= 1:
        return None
    return concurrent.futures.ProcessPoolExecutor(
        max_workers=workers, mp_context=multiprocessing.get_context("fork"),
        initializer=_worker_init)


def _worker_init() -> None:
    """Workers leave Ctrl-C to this process (which stops them): no traceback from each."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _stop(ex: concurrent.futures.ProcessPoolExecutor) -> None:
    """Stop the worker processes this command started (on Ctrl-C: a worker's file may take
    minutes): pending files cancelled, then every live child that multiprocessing started
    in this process (the command starts no other) terminated, through the public
    ``multiprocessing.active_children`` rather than the pool's private process table."""
    ex.shutdown(wait=False, cancel_futures=True)
    children = multiprocessing.active_children()
    for proc in children:
        with contextlib.suppress(Exception):
            proc.terminate()
    for proc in children:               # gone before this process reports and ends
        with contextlib.suppress(Exception):
            proc.join(timeout=5)


def _run_files(method: str, args: argparse.Namespace, o: dict,
               emit: Callable[[_Outcome], None]) -> list[_Outcome]:
    """Every file, in parallel when --workers > 1; ``emit`` each outcome in input order."""
    files = list(args.unique_files)
    results: list[_Outcome | None] = [None] * len(files)
    done = 0

    def flush() -> None:
        nonlocal done
        while done < len(files) and results[done] is not None:
            emit(results[done])
            done += 1

    batch = len(files) > 1
    ex = _executor(args.workers)
    futures = ({} if ex is None else    # submitted first: the workers fork before the bar
               {ex.submit(_process, method, f, o): i for i, f in enumerate(files)})
    try:
        with _progress(batch and _bar_enabled(args), total=len(files),
                       desc=f"calibrate {method}", unit="file") as bar:
            if ex is None:
                for i, f in enumerate(files):
                    results[i] = _process(method, f, o)
                    bar.update(1)
                    flush()
            else:
                for fut in concurrent.futures.as_completed(futures):
                    i = futures[fut]
                    try:
                        results[i] = fut.result()
                    except Exception as exc:   # e.g. a worker killed (out of memory)
                        results[i] = _bad(method, files[i], _failure_message(files[i], exc))
                    bar.update(1)
                    flush()
    except KeyboardInterrupt:
        if ex is not None:
            _stop(ex)
            ex = None
        args.done = done
        raise
    finally:
        if ex is not None:
            ex.shutdown(cancel_futures=True)
    return [r for r in results if r is not None]


def run(args: argparse.Namespace) -> int:
    """Run ``calibrate gc`` or ``calibrate rsf``: exit status 0, 2 (bad input) or 3 (no valid
    estimate); see the module docstring."""
    try:
        return _run(args)
    except KeyboardInterrupt:
        done = getattr(args, "done", 0)
        total = len(getattr(args, "unique_files", args.files))
        sys.stdout.flush()
        sys.stderr.write(f"interrupted (Ctrl-C): {done} of {total} file(s) calibrated; no "
                         "partial file left (outputs are written only when complete)\n")
        return EXIT_INTERRUPTED


def _run(args: argparse.Namespace) -> int:
    label = args.files[0] if len(args.files) == 1 else f"calibrate {args.method}"
    args.unique_files, dup_notes = _unique_files(list(args.files))
    args.done = 0
    try:
        if args.workers < 1:
            raise UsageError(f"--workers must be an integer >= 1; got {args.workers}")
        _check_out_path(args.summary, (".csv",), "a summary CSV")
        try:
            columns = parse_columns(args.columns) if args.columns is not None else None
        except ValueError as exc:
            raise UsageError(f"--columns: {_one_line(exc)}") from None
        if args.t0 is not None and not math.isfinite(args.t0):
            raise UsageError(f"--t0 must be a finite number of seconds; got {args.t0}")
        o = _gc_options(args) if args.method == "gc" else _rsf_options(args)
        o["columns"], o["t0"] = columns, args.t0
        outputs = [(opt, val) for opt, val in (
            ("--summary", args.summary), ("--plot", getattr(args, "plot", None)),
            ("--allan", getattr(args, "allan", None)),
            ("--fit-noise", getattr(args, "fit_noise", None) or None)) if val]
        _check_outputs(args, outputs)
    except UsageError as exc:
        sys.stderr.write(f"error: {_one_line(exc)}\n")
        return EXIT_BAD_INPUT
    except (RecordError, ValueError, TypeError) as exc:
        sys.stderr.write(f"error: {_failure_message(label, exc)}\n")
        return EXIT_BAD_INPUT

    def emit(out: _Outcome) -> None:
        if out.status in ("ok", "misfit", "invalid"):
            if args.json:
                sys.stdout.write(_json(out.data))
            else:
                sys.stdout.write(out.text)
        elif args.json and (len(args.files) > 1 or args.summary):
            sys.stdout.write(_json(out.data))
        if out.message:
            sys.stderr.write(f"error: {_one_line(out.message)}\n")
        sys.stdout.flush()

    for note in dup_notes:
        sys.stderr.write(f"note: {_one_line(note)}\n")
    outcomes = _run_files(args.method, args, o, emit)
    args.done = len(outcomes)
    for out in outcomes:
        if out.status == "ok":
            try:
                _write_artifacts(out)
            except RecordError as exc:
                sys.stderr.write(f"error: {_one_line(exc)}\n")
                return EXIT_BAD_INPUT
    if args.summary:
        try:
            _summary_csv(args.summary, outcomes)
        except RecordError as exc:
            sys.stderr.write(f"error: {_one_line(exc)}\n")
            return EXIT_BAD_INPUT
    return max(out.code for out in outcomes) if all(
        out.status != "error" for out in outcomes) else EXIT_BAD_INPUT
