"""The outputs and the batch of the ``calibrate`` command: every output written atomically
(a temporary file in its folder, renamed onto its path when complete), the checks of output
paths, the one-line messages, the JSON lines, the ``--summary`` CSV, the progress bar, and
the batch driver that calibrates each file (in worker processes with ``--workers``) and
turns any failure into that file's row.  See :mod:`gyrolib.cli.calibrate` for the command's
behaviour; :mod:`gyrolib.cli.calibrate_gc` and :mod:`gyrolib.cli.calibrate_rsf` are the two
methods' runs of one file."""

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

import numpy as np

from gyrolib.cli import hints
from gyrolib.cli.constants import EXIT_BAD_INPUT, EXIT_INTERRUPTED, EXIT_INVALID, SUMMARY_COLUMNS
from gyrolib.records.errors import OptionError, RecordError
from gyrolib.records.options import read_options

__all__ = ["NoBar", "Outcome", "atomic", "bad", "bar_enabled", "check_out_path",
           "check_outputs", "error_hint", "error_object", "failure_message", "fmt", "guarded",
           "json_line", "one_line", "progress", "run_batch", "run_files", "same_file", "save",
           "summary_csv", "unique_files", "write_artifacts", "write_text"]


# Writing outputs ---------------------------------------------------------------------------
def check_out_path(path: str | None, suffixes: tuple[str, ...], what: str) -> None:
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
def atomic(path: str):
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


def save(fig, path: str) -> None:
    import matplotlib.pyplot as plt

    try:
        with atomic(path) as tmp:
            fig.savefig(tmp, dpi=110, bbox_inches="tight", format=Path(path).suffix[1:])
    except OSError as exc:
        raise RecordError(path, f"cannot write the plot: {exc.strerror or exc}") from None
    finally:
        plt.close(fig)


def write_text(path: str, text: str) -> None:
    try:
        with atomic(path) as tmp:
            Path(tmp).write_text(text)
    except OSError as exc:
        raise RecordError(path, f"cannot write the file: {exc.strerror or exc}") from None


def same_file(a: str, b: str) -> bool:
    """Whether two paths name one file (the same inode, or the same absolute path)."""
    with contextlib.suppress(OSError):
        return os.path.samefile(a, b)
    return os.path.abspath(a) == os.path.abspath(b)


def check_outputs(args: argparse.Namespace, outputs: list[tuple[str, str]]) -> None:
    """Refuse an output that is an input or another output, or (``--no-clobber``) exists."""
    for k, (opt, path) in enumerate(outputs):
        for f in args.files:
            if same_file(path, f):
                raise OptionError(f"{opt} {path} is also an input file: refusing to write over "
                                 "a record (give another output path)")
        for opt2, path2 in outputs[:k]:
            if same_file(path, path2):
                raise OptionError(f"{opt} and {opt2} name the same file {path}")
        if args.no_clobber and os.path.lexists(path):
            raise OptionError(f"{opt} {path} exists and --no-clobber is given: nothing "
                             "written")


def unique_files(files: list[str]) -> tuple[list[str], list[str]]:
    """The files in order with duplicates (the same file under any name) removed, and a
    note for each duplicate."""
    out: list[str] = []
    notes: list[str] = []
    for f in files:
        first = next((g for g in out if same_file(f, g)), None)
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


def json_line(obj: object) -> str:
    """One line of strict JSON; a non-finite float becomes null."""
    return json.dumps(_clean(obj), allow_nan=False) + "\n"


def fmt(x: float, digits: int = 4) -> str:
    return f"{x:.{digits}g}"


def one_line(text: str) -> str:
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


def failure_message(label: str, exc: BaseException) -> str:
    """One line for an error the checks at the door did not catch: gyrolib's message, never
    numpy's or scipy's."""
    if isinstance(exc, RecordError):
        return str(exc)
    if isinstance(exc, MemoryError):
        return (f"{label}: the calibration ran out of memory on this record (MemoryError): "
                "check the time column (t in s from the start, strictly increasing)")
    if not isinstance(exc, ValueError | TypeError | ArithmeticError):
        return f"{label}: the calibration failed ({type(exc).__name__}: {one_line(exc)})"
    if _from_library(exc):
        return f"{label}: {one_line(exc)}"
    return (f"{label}: the calibration failed on this record ({type(exc).__name__} inside "
            "the numerics): check the units (t in s, angles in rad, inclinometers in m/s²) "
            "and the parameters given with --params")


@dataclasses.dataclass
class Outcome:
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


def error_hint(exc: BaseException | None) -> tuple[str, str]:
    """``(reason_code, hint)`` of a bad input or option (:data:`gyrolib.cli.hints.REASONS`):
    ``bad_option``, or ``bad_input`` with the option the error names (a
    :class:`RecordError`'s ``hint``, e.g. a unit option) as its ``try:`` line, else no hint
    (the message itself names the row, column and what was expected)."""
    if isinstance(exc, OptionError):
        return "bad_option", hints.hint("bad_option")
    option = getattr(exc, "hint", None)
    if option:
        return "units" if "-unit" in option else "bad_input", f"try: {option}"
    return "bad_input", ""


def error_object(message: str, code: str, hint: str, file: str | None = None) -> dict:
    """The JSON object of a refusal on bad input (``--json`` writes it on stdout)."""
    return {"file": file, "valid": False, "status": "error", "error": message,
            "reason_code": code, "hint": hint or None}


def bad(method: str, file: str, message: str, exc: BaseException | None = None) -> Outcome:
    """The outcome of a file that could not be calibrated (bad input, or a failure)."""
    quantity = "omega_gc" if method == "gc" else "eps1_hat_mean"
    unit = "rad/s" if method == "gc" else "1"
    code, hint = error_hint(exc)
    return Outcome(file=file, status="error",
                   message=message + (f"; {hint}" if hint else ""),
                   data=error_object(message, code, hint, file),
                   row={"file": file, "method": method, "quantity": quantity, "estimate": "",
                        "sigma": "", "unit": unit, "valid": False, "status": "error",
                        "reason": message, "reason_code": code, "hint": hint, "notes": ""})


# Progress -----------------------------------------------------------------------------------
def bar_enabled(args: argparse.Namespace) -> bool:
    """A progress bar only on a terminal and never with --json."""
    try:
        tty = sys.stderr.isatty()
    except (AttributeError, ValueError):
        tty = False
    return bool(tty and not args.json)


class NoBar:
    """What the code needs of a tqdm bar when none is shown (tqdm not imported: 15 ms)."""

    n: float = 0

    def update(self, k: float = 1) -> None:
        self.n += k

    def __enter__(self) -> NoBar:
        return self

    def __exit__(self, *exc: object) -> None:
        return None


def progress(shown: bool, **kwargs):
    """A tqdm bar on stderr (``leave=False``) when ``shown``, else a :class:`NoBar`."""
    if not shown:
        return NoBar()
    from tqdm import tqdm

    return tqdm(file=sys.stderr, leave=False, **kwargs)


# One file, many files ---------------------------------------------------------------------
#: A run of one file: ``(file, checked options) -> Outcome`` (it may raise).
RunFile = Callable[[str, dict], "Outcome"]
#: One file, any failure turned into its outcome: ``(method, file, options) -> Outcome``; a
#: module-level function, so that worker processes can receive it.
Process = Callable[[str, str, dict], "Outcome"]


def guarded(run_file: RunFile, method: str, file: str, o: dict) -> Outcome:
    """``run_file(file, o)``, any failure turned into the file's outcome (runs in a worker
    process too)."""
    try:
        return run_file(file, o)
    except (OptionError, RecordError) as exc:
        return bad(method, file, str(exc), exc)
    except Exception as exc:       # any failure is this file's row, not the batch's
        return bad(method, file, failure_message(file, exc))


def write_artifacts(outcome: Outcome) -> None:
    """Write the files a valid run produced (plots, the fitted noise's TOML)."""
    from gyrolib import gc

    for path, kind, payload in outcome.artifacts:
        if kind == "plot":
            res, label = payload
            save(gc.plot_calibration(res, label=label), path)
        elif kind == "rsf_plot":
            from gyrolib import rsf

            save(rsf.plot_correction(*payload), path)
        elif kind == "allan":
            save(gc.plot_allan(payload, title=f"Allan deviation of {outcome.file}"), path)
        else:
            write_text(path, payload)


def summary_csv(path: str, outcomes: list[Outcome]) -> None:
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
        with atomic(path) as tmp, open(tmp, "w", newline="") as fh:
            fh.write(buf.getvalue())
    except OSError as exc:
        raise RecordError(path, f"cannot write the summary: {exc.strerror or exc}") from None


def _executor(workers: int, scheduler: str | None = None
              ) -> concurrent.futures.Executor | None:
    """``workers`` processes forked from this one, which has imported gyrolib already (a
    spawned or forkserver worker would import it again: about 4 s, more than a 100 s record
    takes).  They are forked at the first submit, before the progress bar's thread exists,
    so no thread of this process is forked.  With ``scheduler``: the executor of a Dask
    client of that scheduler (:class:`OptionError` when it cannot be reached)."""
    if scheduler:
        from gyrolib._optional import optional

        with optional("dask", "dask", "--scheduler"):
            from dask.distributed import Client
        try:
            client = Client(scheduler, timeout=10)
        except (OSError, TimeoutError) as exc:
            raise OptionError(f"--scheduler: cannot reach the Dask scheduler {scheduler}: "
                              f"{type(exc).__name__}") from None
        return _DaskExecutor(client)
    if workers <= 1:
        return None
    return concurrent.futures.ProcessPoolExecutor(
        max_workers=workers, mp_context=multiprocessing.get_context("fork"),
        initializer=_worker_init)


class _DaskExecutor(concurrent.futures.Executor):
    """A Dask client's executor that closes its client when shut down (and accepts the
    ``cancel_futures`` of :meth:`concurrent.futures.Executor.shutdown`)."""

    def __init__(self, client) -> None:
        self.client = client
        self.inner = client.get_executor()

    def submit(self, fn, /, *args, **kwargs):
        return self.inner.submit(fn, *args, **kwargs)

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        self.inner.shutdown(wait=wait and not cancel_futures)
        self.client.close()


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


def run_files(method: str, args: argparse.Namespace, o: dict,
              emit: Callable[[Outcome], None], process: Process) -> list[Outcome]:
    """Every file, in parallel when --workers > 1; ``emit`` each outcome in input order."""
    files = list(args.unique_files)
    results: list[Outcome | None] = [None] * len(files)
    done = 0

    def flush() -> None:
        nonlocal done
        while done < len(files) and results[done] is not None:
            emit(results[done])
            done += 1

    batch = len(files) > 1
    ex = _executor(args.workers, getattr(args, "scheduler", None))
    futures = ({} if ex is None else    # submitted first: the workers fork before the bar
               {ex.submit(process, method, f, o): i for i, f in enumerate(files)})
    try:
        with progress(batch and bar_enabled(args), total=len(files),
                       desc=f"calibrate {method}", unit="file") as bar:
            if ex is None:
                for i, f in enumerate(files):
                    results[i] = process(method, f, o)
                    bar.update(1)
                    flush()
            else:
                for fut in concurrent.futures.as_completed(futures):
                    i = futures[fut]
                    try:
                        results[i] = fut.result()
                    except Exception as exc:   # e.g. a worker killed (out of memory)
                        results[i] = bad(method, files[i], failure_message(files[i], exc))
                    bar.update(1)
                    flush()
    except KeyboardInterrupt:
        if isinstance(ex, _DaskExecutor):
            ex.shutdown(wait=False, cancel_futures=True)
            ex = None
        elif ex is not None:
            _stop(ex)
            ex = None
        args.done = done
        raise
    finally:
        if ex is not None:
            ex.shutdown(cancel_futures=True)
    return [r for r in results if r is not None]


def run_batch(args: argparse.Namespace, options: Callable[[argparse.Namespace], dict],
              process: Process) -> int:
    """Run ``calibrate gc`` or ``calibrate rsf`` on every file of ``args``: ``options(args)``
    checks the method's options, ``process(method, file, o)`` runs one file.  Exit status 0,
    2 (bad input), 3 (no valid estimate) or 130 (Ctrl-C); see :mod:`gyrolib.cli.calibrate`."""
    try:
        return _run(args, options, process)
    except KeyboardInterrupt:
        done = getattr(args, "done", 0)
        total = len(getattr(args, "unique_files", args.files))
        sys.stdout.flush()
        sys.stderr.write(f"interrupted (Ctrl-C): {done} of {total} file(s) calibrated; no "
                         "partial file left (outputs are written only when complete)\n")
        return EXIT_INTERRUPTED


def _refuse(args: argparse.Namespace, message: str, exc: BaseException) -> int:
    """Bad input or a bad option before or after the files: one line on stderr (with the
    hint when the error names an option), and with ``--json`` a JSON error object on
    stdout; status 2."""
    code, hint = error_hint(exc)
    sys.stderr.write(f"error: {message}" + (f"; {hint}" if hint else "") + "\n")
    if getattr(args, "json", False):
        sys.stdout.write(json_line(error_object(message, code, hint)))
        sys.stdout.flush()
    return EXIT_BAD_INPUT


def _run(args: argparse.Namespace, options: Callable[[argparse.Namespace], dict],
         process: Process) -> int:
    label = args.files[0] if len(args.files) == 1 else f"calibrate {args.method}"
    args.unique_files, dup_notes = unique_files(list(args.files))
    args.done = 0
    try:
        if args.workers < 1:
            raise OptionError(f"--workers must be an integer >= 1; got {args.workers}")
        if getattr(args, "scheduler", None) and args.workers != 1:
            raise OptionError("--scheduler and --workers exclude each other: the cluster's "
                              "workers calibrate the files")
        check_out_path(args.summary, (".csv",), "a summary CSV")
        read = read_options(args)
        o = options(args)
        o.update(read)
        outputs = [(opt, val) for opt, val in (
            ("--summary", args.summary), ("--plot", getattr(args, "plot", None)),
            ("--allan", getattr(args, "allan", None)),
            ("--fit-noise", getattr(args, "fit_noise", None) or None)) if val]
        check_outputs(args, outputs)
    except OptionError as exc:
        return _refuse(args, one_line(exc), exc)
    except (RecordError, ValueError, TypeError) as exc:
        return _refuse(args, failure_message(label, exc), exc)

    def emit(out: Outcome) -> None:
        if out.status in ("ok", "misfit", "invalid"):
            if args.json:
                sys.stdout.write(json_line(out.data))
            else:
                sys.stdout.write(out.text)
        elif args.json:       # a refusal on bad input: its JSON error object
            sys.stdout.write(json_line(out.data))
        if out.message:
            sys.stderr.write(f"error: {one_line(out.message)}\n")
        sys.stdout.flush()

    for note in dup_notes:
        sys.stderr.write(f"note: {one_line(note)}\n")
    try:
        outcomes = run_files(args.method, args, o, emit, process)
    except OptionError as exc:          # a scheduler that cannot be reached: before any file
        return _refuse(args, one_line(exc), exc)
    args.done = len(outcomes)
    for out in outcomes:
        if out.status == "ok":
            try:
                write_artifacts(out)
            except RecordError as exc:
                return _refuse(args, one_line(exc), exc)
    if args.summary:
        try:
            summary_csv(args.summary, outcomes)
        except RecordError as exc:
            return _refuse(args, one_line(exc), exc)
    return max(out.code for out in outcomes) if all(
        out.status != "error" for out in outcomes) else EXIT_BAD_INPUT

