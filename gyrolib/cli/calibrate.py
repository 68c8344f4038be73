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
forked from this process, gyrolib already imported; ``--scheduler ADDR``: on the workers of
a Dask cluster, which must read the same paths), a bad or invalid file is reported in
its row (status ``error``, with the one-line reason, whatever the failure — also one that
happens inside a worker process) and on stderr while the others proceed, and the exit status
is 2 if any file failed, else 3 if any was invalid.  A progress bar (tqdm) goes to stderr on a
terminal, never with ``--json`` or when stderr is piped.

The command's rooms: this module holds the parser and loads nothing heavy (``python -m gyrolib
--help`` imports no numpy, numba or pyarrow); :mod:`gyrolib.records.options` the format
options beside the reader; :mod:`gyrolib.cli.calibrate_gc` and
:mod:`gyrolib.cli.calibrate_rsf` the two methods' runs of one file; :mod:`gyrolib.cli.outputs`
the batch and the atomic outputs; :mod:`gyrolib.cli.constants` the exit statuses and the
default priors.
"""

from __future__ import annotations

import argparse

import gyrolib
from gyrolib.cli import constants as _constants
from gyrolib.cli.constants import (
    EXIT_BAD_INPUT,
    EXIT_INTERRUPTED,
    EXIT_INVALID,
    FIT_DEFAULT,
    SUMMARY_COLUMNS,
)
from gyrolib.records.options import add_format_options

__all__ = [  # noqa: F822 - the DEFAULT_* priors are read from the table on first use
           "DEFAULT_INCL_BIAS_PRIOR_MG", "DEFAULT_OFFSET_PRIOR_ARCSEC",
           "DEFAULT_SCALE_TOLERANCE", "EXIT_BAD_INPUT", "EXIT_INTERRUPTED", "EXIT_INVALID",
           "SUMMARY_COLUMNS", "add_parser", "process", "run"]


def __getattr__(name: str) -> float:
    """The default priors (:mod:`gyrolib.cli.constants`), from the table of inputs."""
    if name.startswith("DEFAULT_"):
        return getattr(_constants, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


class _FromTable(str):
    """A help text whose ``{DEFAULT_*}`` are filled in from the table of inputs when argparse
    formats it (its ``%`` formatting), so that building the parser reads no table."""

    def __mod__(self, params: object) -> str:
        text = str(self)
        for name in _constants.FROM_TABLE:
            text = text.replace("{" + name + "}", f"{getattr(_constants, name):g}")
        return str.__mod__(text, params)


# Parser ----------------------------------------------------------------------------------
def add_parser(sub: argparse._SubParsersAction, parser_class: type) -> None:
    """Add ``calibrate`` with its ``gc`` and ``rsf`` sub-commands to ``sub``; usage errors of
    those go through ``parser_class`` (one line, status 2)."""
    cal = sub.add_parser("calibrate", help="apply paper GC or RSF to recorded CSV files")
    methods = cal.add_subparsers(dest="method", required=True,
                                 parser_class=_signed_values(parser_class))
    _add_gc(methods)
    _add_rsf(methods)


def _add_gc(methods: argparse._SubParsersAction) -> None:
    """``calibrate gc`` and its options."""
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
    gcp.add_argument("--fit", default=FIT_DEFAULT, metavar="NAMES",
                     help=f"parameters --fit-noise fits, comma-separated (default "
                          f"{FIT_DEFAULT}; also xi1, C_incl_y, C_incl_z)")
    gcp.add_argument("--allan", metavar="OUT.png",
                     help="write the Allan deviation of the angle-sensor rate and of the "
                          "inclinometers, with paper GC's model curves, and print the angle "
                          "random walk, bias instability and rate random walk read off it "
                          "(IEEE Std 952), each with its uncertainty")
    gcp.add_argument("--max-rejected", type=float, default=0.01, metavar="SHARE",
                     help="largest share of a sensor's samples the gate may reject before "
                          "the run counts as lost lock (default 0.01)")
    gcp.add_argument("--latitude", default=None, metavar="DEG[±SIGMA]|paper",
                     help="latitude of the test site in degrees, north positive, south "
                          "negative, in (-90, 90): Omega_h, Omega_v from the Earth's rate "
                          "(default: the params file's 'latitude', else the record's "
                          "'# latitude_deg:' line; without any there is no valid estimate, "
                          "exit 3); '54±0.5' (or '54+-0.5') states its 1-sigma uncertainty, "
                          "carried into sigma(omega_gc) as the term 'latitude'; a latitude "
                          "in whole degrees without one gets a warning of what a 0.5 deg "
                          "error would do; 'paper' assumes paper GC's Omega_h, Omega_v "
                          "(about 53.9 N) and says so")
    gcp.add_argument("--latitude-sigma", type=float, default=None, metavar="DEG",
                     help="1-sigma uncertainty of the latitude in degrees, wherever it comes "
                          "from (option, params file or the record's line): Omega_h reads "
                          "as drift, so it enters sigma(omega_gc) as the term 'latitude'")
    _add_gc_priors(gcp)
    gcp.add_argument("--false-alarm", type=float, default=0.01, metavar="P",
                     help="family-wise false-alarm rate of the model checks that make a "
                          "record invalid (default 0.01)")
    gcp.add_argument("--accept-misfit", action="store_true",
                     help="give the estimate of a record whose model checks fail, marked "
                          "misfit (exit 0), instead of no valid estimate (exit 3)")
    _batch_options(gcp)


def _add_gc_priors(gcp: argparse.ArgumentParser) -> None:
    """The priors of paper GC's instrument constants, each with its default."""
    gcp.add_argument("--scale-tolerance", type=float, default=None, metavar="REL",
                     help=_FromTable("1-sigma relative uncertainty of the scale common to H/f "
                                     "and the angle sensor's gain (default "
                                     "{DEFAULT_SCALE_TOLERANCE}, the table of inputs' largest "
                                     "plausible value); it reads as a drift of REL*Omega_h "
                                     "and enters sigma(omega_gc)"))
    gcp.add_argument("--offset-prior", type=float, default=None, metavar="ARCSEC",
                     help=_FromTable("1-sigma prior of the angle sensor's null offset, "
                                     "estimated with the state (default "
                                     "{DEFAULT_OFFSET_PRIOR_ARCSEC} arcsec, the table of "
                                     "inputs' largest plausible value; a logger that starts "
                                     "late reads as an offset)"))
    gcp.add_argument("--inclinometer-bias-prior", type=float, default=None, metavar="MG",
                     help=_FromTable("1-sigma prior of each inclinometer's bias in mg, "
                                     "estimated with the state (default "
                                     "{DEFAULT_INCL_BIAS_PRIOR_MG} mg, the table of inputs' "
                                     "largest plausible value); a bias cannot be told from a "
                                     "tilt, so it enters sigma(omega_gc)"))
    gcp.add_argument("--drift-prior", type=float, default=None, metavar="DEG/H",
                     help="1-sigma prior of the drift omega_gc in deg/h (default: the params "
                          "file's sigma_gc0, paper GC's 0.15 arcsec/s = 0.15 deg/h); an "
                          "estimate far outside it is not valid, so a gyro that really drifts "
                          "more needs a wider prior")
    gcp.add_argument("--clock-tolerance", type=float, default=None, metavar="REL",
                     help=_FromTable("1-sigma relative error of the logger's time scale "
                                     "(default {DEFAULT_CLOCK_TOLERANCE}, the table of inputs' "
                                     "largest plausible value, a crystal's tolerance); carried "
                                     "like the scale (a logger of 1024 Hz labelled 1 kHz is "
                                     "2.4e-2)"))


def _add_rsf(methods: argparse._SubParsersAction) -> None:
    """``calibrate rsf`` and its options."""
    rsfp = methods.add_parser(
        "rsf", help="paper RSF: roll-gyro scale-factor error per correction interval",
        description="Apply paper RSF's correction (Eqs. (1)-(3)) to CSV records with the "
                    "columns t (s), sins_increment (rad) and gs_angle (rad) or "
                    "encoder_counts (wrapped, with --counts-per-rev). The mean eps1_hat "
                    "carries a total standard uncertainty: the intervals' scatter plus the "
                    "terms that do not average out (the SINS and GS biases over the roll "
                    "rate, the GS angle's scale, the encoder's end points), each tolerance "
                    "stated. Exit status 0 ok, 2 bad input, 3 no valid estimate (a check of "
                    "the run failed: the intervals' scatter against the sensors' error model, "
                    "the biases of a reversing roll, the estimate against the gyro's "
                    "scale-factor tolerance).")
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
    rsfp.add_argument("--sins-bias-tolerance", type=float, default=None, metavar="DEG/H",
                      help="1-sigma bias of the SINS roll gyro, deg/h (default: [sins] eps0 of "
                           "--params, paper RSF Table 1's 100 deg/h); over the roll rate it "
                           "enters sigma(eps1_hat_mean)")
    rsfp.add_argument("--gs-bias-tolerance", type=float, default=None, metavar="DEG/H",
                      help="1-sigma bias of the GS gyro, deg/h (default: [gs] eps0 of --params, "
                           "the GYPRO4300's sqrt(10^2 + 7^2) = 12.2 deg/h)")
    rsfp.add_argument("--gs-gyro-scale-tolerance", type=float, default=None, metavar="PPM",
                      help="1-sigma scale-factor error of the GS gyro, ppm (default: [gs] eps1 "
                           "of --params, the GYPRO4300's 280 ppm); it scales the GS gyro's own "
                           "turn (measured with a gs_gyro_angle column, else the turn the GS "
                           "motor's speed limit leaves)")
    rsfp.add_argument("--gs-scale-tolerance", type=float, default=None, metavar="PPM",
                      help="1-sigma relative scale error of the whole GS angle, ppm; replaces "
                           "the GS gyro's term (a GS angle from another source)")
    rsfp.add_argument("--sf-tolerance", type=float, default=None, metavar="PPM",
                      help="1-sigma scale-factor error of the roll gyro, ppm, the prior "
                           "eps1_hat_mean is checked against (default: [sins] eps1 of "
                           "--params, paper RSF Table 1's 600 ppm)")
    rsfp.add_argument("--false-alarm", type=float, default=0.01, metavar="P",
                      help="family-wise false-alarm rate of the run's checks (default 0.01)")
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
    p.add_argument("--scheduler", metavar="ADDR",
                   help="calibrate the files on the Dask cluster of this scheduler (its "
                        "workers must read the same paths); not with --workers")
    add_format_options(p)
    p.add_argument("--no-clobber", action="store_true",
                   help="refuse (status 2) to replace an existing output file; by default an "
                        "existing output is replaced, atomically, once its replacement is "
                        "complete")
    p.add_argument("--version", action="version", version=f"gyrolib {gyrolib.__version__}")


# Running ------------------------------------------------------------------------------------
def run(args: argparse.Namespace) -> int:
    """Run ``calibrate gc`` or ``calibrate rsf``: exit status 0, 2 (bad input), 3 (no valid
    estimate) or 130 (Ctrl-C); see the module docstring.  The method's run and the batch are
    imported here, not with the parser."""
    from gyrolib.cli import outputs

    if args.method == "gc":
        from gyrolib.cli import calibrate_gc as method
    else:
        from gyrolib.cli import calibrate_rsf as method
    return outputs.run_batch(args, method.options, process)


def process(method: str, file: str, o: dict):
    """One file by ``method`` ("gc" or "rsf") with the checked options ``o``, any failure
    turned into the file's :class:`~gyrolib.cli.outputs.Outcome` (runs in a worker process
    too; the method's ``run_file`` is looked up at each call)."""
    from gyrolib.cli import outputs

    if method == "gc":
        from gyrolib.cli import calibrate_gc

        return outputs.guarded(calibrate_gc.run_file, method, file, o)
    from gyrolib.cli import calibrate_rsf

    return outputs.guarded(calibrate_rsf.run_file, method, file, o)
