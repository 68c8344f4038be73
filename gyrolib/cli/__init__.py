"""The command line, ``python -m gyrolib COMMAND``; it sits above the paper subpackages and
:mod:`gyrolib.records`, which never import it.

===============  ==================================================================
module           command
===============  ==================================================================
``ledger``       ``python -m gyrolib ledger [--json]``: the reproduction ledger
``calibrate``    ``python -m gyrolib calibrate gc|rsf FILE [...]``: a recorded log
``sensitivity``  ``python -m gyrolib sensitivity gc|rsf --n N [...]``: Sobol' indices
``race``         ``python -m gyrolib race [--params P.toml] [--json]``: GC against ref. [3]
``claims``       ``python -m gyrolib claims [--check | --out FILE]``: claims over the inputs
``allan``        ``python -m gyrolib allan FILE [--json]``: Allan deviation of a rate series
``refresh``      ``python -m gyrolib refresh [STUDY ...] [--list]``: the stored studies
===============  ==================================================================

Each command module offers ``add_parser(sub)`` (its sub-parser) and ``run(args)`` (its exit
status).  Usage errors exit with status 2 and one line on stderr.  Building the parsers loads
no numerics (``--help`` imports no numpy, numba or pyarrow): each command imports its work in
``run``.  ``calibrate``'s runs live in ``calibrate_gc`` and ``calibrate_rsf``, its batch and
atomic outputs in ``outputs``, its shared constants in ``constants``, and its format options
with the reader in :mod:`gyrolib.records.options`.
"""

from __future__ import annotations

import argparse
import os
import sys

#: Environment variables the command line sets to "1" unless already set, before numpy loads.
BLAS_THREADS: tuple[str, ...] = ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")

# One BLAS thread for the command line, unless the user chose otherwise.  Its numerics are
# small matrices (10 states; the 60 x 60 block exponentials of calibrate's step tables), which
# BLAS threads only slow down: on the 2-core development machine scipy's expm of such a
# matrix takes 8 ms on OpenBLAS's threads against 0.13 ms on one, and the threads then spin
# on the core the CSV reader needs (a calibration of 1 h: 1.5 s more wall and CPU time;
# benchmarks/bench_calibrate.py).  Only when numpy is not loaded yet, i.e. in a process the
# command line starts; a program that imported numpy first keeps its own setting.
if "numpy" not in sys.modules:
    for _name in BLAS_THREADS:
        os.environ.setdefault(_name, "1")

from gyrolib.cli import (  # noqa: E402
    allan,
    calibrate,
    claims,
    ledger,
    race,
    refresh,
    sensitivity,
)

__all__ = ["COMMANDS", "entry", "main"]

#: The commands, by name: each a module with ``add_parser`` and ``run``.
COMMANDS = {"ledger": ledger, "calibrate": calibrate, "sensitivity": sensitivity,
            "race": race, "claims": claims, "allan": allan, "refresh": refresh}


def _version() -> str:
    import gyrolib

    return gyrolib.__version__


class OneLineParser(argparse.ArgumentParser):
    """Usage errors as one line on stderr, exit status 2."""

    def error(self, message: str) -> None:  # type: ignore[override]
        sys.stderr.write(f"{self.prog}: error: {' '.join(message.split())}\n")
        raise SystemExit(2)


def main(argv: list[str] | None = None) -> int:
    """Run the command line on ``argv`` (default: ``sys.argv[1:]``); returns the exit code.

    Unknown commands or options exit through argparse (status 2, with the usage)."""
    if argv is not None and (not isinstance(argv, list | tuple)
                             or not all(isinstance(a, str) for a in argv)):
        raise TypeError(f"argv must be a list of str or None; got {argv!r:.80}")
    parser = argparse.ArgumentParser(prog="python -m gyrolib")
    parser.add_argument("--version", action="version", version=f"gyrolib {_version()}")
    sub = parser.add_subparsers(dest="command", required=True)
    for module in COMMANDS.values():
        module.add_parser(sub, OneLineParser)
    args = parser.parse_args(argv)
    return COMMANDS[args.command].run(args)


def entry() -> None:
    """The process entry point (``python -m gyrolib`` and the ``gyrolib`` script): exit with
    :func:`main`'s status.

    The command has written its output and closed its files (every output is written
    atomically, and the CSV reader stops pyarrow's streaming reader before it is dropped:
    :func:`gyrolib.records.reader._stop_reading`), so the process ends at once, after
    flushing its streams, without the interpreter's teardown.  In that teardown a native
    thread of pyarrow's pools that still needs the GIL (a read of a Python file object, the
    release of one) is stopped inside Python, and the process aborts ("terminate called
    without an active exception", SIGABRT, status 134 instead of the command's) or hangs in
    the pools' shutdown.  Measured on a 500 000-row gzip record refused at the door: 9 runs
    in 28 aborted or hung without the reader's stop, 1 in 40 aborted with it, none in 40
    with it and this exit (tests/records/test_reader_exit.py runs the refusals; a known
    hazard of Arrow's pools, apache/arrow#34314, seen after Ctrl-C too, status 130)."""
    code = main()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)
