"""The ``sensitivity`` command:
``python -m gyrolib sensitivity gc|rsf --n N [--workers K | --scheduler tcp://HOST:PORT]
--out FILE.json``.

Runs :func:`gyrolib.gc.sensitivity` or :func:`gyrolib.rsf.sensitivity` in this process
(default), on ``K`` local Dask worker processes (``--workers``) or on a running Dask cluster
(``--scheduler``), with a progress bar on stderr, and writes the indices, their intervals,
the model's values on the sample and a record of the run (N, seed, version, machine, number
of workers, wall time) to ``FILE.json``.

Bad arguments exit with status 2 and one line; a scheduler that cannot be reached within
``--timeout`` seconds exits with status 1 and one line.  Nothing is written in either case.
"""

from __future__ import annotations

import argparse
import functools
import json
import logging
import os
import platform
import sys
import time
import types
from collections.abc import Callable
from contextlib import ExitStack
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from gyrolib import __version__
from gyrolib._optional import optional

__all__ = ["add_parser", "run", "write_results"]


def _power_of_two(text: str) -> int:
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a power of 2; got {text!r}") from None
    if n < 2 or n & (n - 1):
        raise argparse.ArgumentTypeError(f"must be a power of 2 (>= 2); got {n}")
    return n


def _int_at_least(minimum: int) -> Callable[[str], int]:
    """An argparse type: an integer >= ``minimum``, else one line saying so."""
    def parse(text: str) -> int:
        try:
            k = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"must be an integer >= {minimum}; got "
                                             f"{text!r}") from None
        if k < minimum:
            raise argparse.ArgumentTypeError(f"must be an integer >= {minimum}; got {k}")
        return k
    return parse


def _timeout(text: str) -> float:
    try:
        t = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number of seconds > 0; got {text!r}") \
            from None
    if not t > 0.0:
        raise argparse.ArgumentTypeError(f"must be a number of seconds > 0; got {text}")
    return t


def _scheduler(text: str) -> str:
    scheme, sep, rest = text.partition("://")
    host, colon, port = rest.rpartition(":")
    if not sep or scheme not in ("tcp", "tls") or not colon or not host or not port.isdigit():
        raise argparse.ArgumentTypeError(f"must look like tcp://HOST:PORT; got {text!r}")
    return text


def _out(text: str) -> Path:
    path = Path(text)
    if path.suffix != ".json":
        raise argparse.ArgumentTypeError(f"must name a .json file; got {text!r}")
    if not path.parent.resolve().is_dir():
        raise argparse.ArgumentTypeError(f"its folder does not exist: {str(path.parent)!r}")
    return path


def _existing(text: str) -> Path:
    path = Path(text)
    if not path.is_file():
        raise argparse.ArgumentTypeError(f"no such file: {text!r}")
    return path


def _previous(args: argparse.Namespace) -> tuple[Any, dict[str, Any]]:
    """The study to extend and its run record, or (None, {}); ValueError if unusable."""
    if args.extend is None:
        return None, {}
    from gyrolib.sensitivity import result_from_dict

    try:
        data = json.loads(args.extend.read_text(encoding="utf-8"))
        prev = result_from_dict(data)
    except (OSError, ValueError, TypeError, KeyError) as exc:
        raise ValueError(f"--extend: {args.extend} is not a results file ({exc})") from None
    if prev.model != args.model or prev.seed != args.seed or prev.n > args.n \
            or prev.second_order_computed != args.second_order:
        raise ValueError(f"--extend: {args.extend} is another study (model {prev.model}, "
                         f"n {prev.n}, seed {prev.seed}, second order "
                         f"{prev.second_order_computed}); it needs model {args.model}, "
                         f"n <= {args.n}, seed {args.seed}, second order {args.second_order}")
    return prev, dict(data.get("run", {}))


#: Placeholders of the help texts: each study's number of sampled inputs.
_COUNTS = ("{gc_inputs}", "{rsf_inputs}")


def _with_counts(text: str) -> str:
    """``text`` with :data:`_COUNTS` replaced by the studies' own numbers of inputs, read
    from them when a help text that names them is printed (they import numpy, which the
    command line's start does not)."""
    if not any(c in text for c in _COUNTS):
        return text
    from gyrolib.gc.analysis.sensitivity_study import sensitivity_inputs as gc_inputs
    from gyrolib.rsf.sensitivity_study import sensitivity_inputs as rsf_inputs

    return (text.replace("{gc_inputs}", str(len(gc_inputs())))
            .replace("{rsf_inputs}", str(len(rsf_inputs()))))


class _Counted(str):
    """A help or description text whose :data:`_COUNTS` are filled in when argparse
    formats it (its ``%`` formatting; a description is formatted when it names ``%(prog)``,
    which this text says it does), so that building the parser reads no study."""

    def __contains__(self, item: object) -> bool:
        return item == "%(prog)" or str.__contains__(self, item)

    def __mod__(self, params: object) -> str:
        return str.__mod__(_with_counts(str(self)), params)


def add_parser(sub: argparse._SubParsersAction, parser_class: type) -> None:
    """Add the ``sensitivity`` sub-command to ``sub``; its usage errors go through
    ``parser_class`` (one line, status 2)."""
    sen = sub.add_parser(
        "sensitivity", help="Sobol' indices of paper GC's or RSF's verdicts",
        description="Global sensitivity analysis (Sobol' indices, SALib) of paper GC's "
                    "sigma_gc(100 s) and t_c, or of paper RSF's delta K and share removed.")
    # ``sub`` builds plain parsers; this one's usage errors (an unknown model) are one line too
    sen.error = types.MethodType(parser_class.error, sen)  # type: ignore[method-assign]
    models = sen.add_subparsers(dest="model", required=True, parser_class=parser_class)
    for name, text in (("gc", "paper GC: sigma_gc(100 s) and t_c over {gc_inputs} inputs"),
                       ("rsf", "paper RSF: delta K and the share removed over {rsf_inputs} "
                               "inputs"),
                       ("gc-claims", "paper GC's claims' margins (the race's rival included) "
                                     "over the table of inputs' uncertain rows"),
                       ("rsf-claims", "paper RSF's claims' margins over the table of inputs' "
                                      "uncertain rows")):
        p = models.add_parser(name, help=_Counted(text), description=_Counted(text))
        p.add_argument("--n", type=_power_of_two, required=True, metavar="N",
                       help="base sample size, a power of 2 (N (2D + 2) model runs)")
        where = p.add_mutually_exclusive_group()
        where.add_argument("--workers", type=_int_at_least(1), metavar="K",
                           help="run on K local Dask worker processes")
        where.add_argument("--scheduler", type=_scheduler, metavar="tcp://HOST:PORT",
                           help="run on the Dask cluster of this scheduler")
        p.add_argument("--no-second-order", dest="second_order", action="store_false",
                       help="first-order and total indices only (N (D + 2) model runs)")
        p.add_argument("--seed", type=_int_at_least(0), default=0, help="seed (default 0)")
        p.add_argument("--timeout", type=_timeout, default=10.0, metavar="S",
                       help="seconds to wait for the scheduler and a worker (default 10)")
        p.add_argument("--out", type=_out, required=True, metavar="FILE.json",
                       help="where to write the results")
        p.add_argument("--extend", type=_existing, metavar="OLD.json",
                       help="a results file of the same study with a smaller N: its model "
                            "runs are reused, only the new ones are computed")


def _fail(message: str, status: int) -> int:
    sys.stderr.write(f"python -m gyrolib sensitivity: error: {' '.join(message.split())}\n")
    return status


def _connect(args: argparse.Namespace, stack: ExitStack) -> tuple[Any, int, str]:
    """The executor, the number of workers and a description of where the study runs."""
    if args.workers is None and args.scheduler is None:
        return None, 1, "in-process"
    with optional("dask", "dask", "--workers and --scheduler"):
        from dask.distributed import Client, LocalCluster

    if args.workers is not None:
        cluster = stack.enter_context(LocalCluster(
            n_workers=args.workers, threads_per_worker=1, processes=True,
            dashboard_address=":0", silence_logs=logging.ERROR))
        client = stack.enter_context(Client(cluster, timeout=args.timeout))
        return client.get_executor(), args.workers, "dask LocalCluster"
    client = stack.enter_context(Client(args.scheduler, timeout=args.timeout))
    client.wait_for_workers(1, timeout=args.timeout)
    return (client.get_executor(), len(client.scheduler_info()["workers"]),
            f"dask scheduler {args.scheduler}")


def write_results(record: dict[str, Any], path: Path) -> None:
    """Write a results record as JSON: indented, the model's values one sample point a line
    (through a temporary file, so that an interrupted write leaves no half file)."""
    from gyrolib.store import dumps

    text = dumps(record, rows="values")
    tmp = path.with_suffix(".json.tmp")
    tmp.write_text(text, encoding="utf-8")
    tmp.replace(path)


def _machine() -> dict[str, object]:
    return {"platform": platform.platform(), "processor": platform.machine(),
            "python": platform.python_version(), "cpus": os.cpu_count()}


def run(args: argparse.Namespace) -> int:
    """Run the study and write ``args.out``; status 0, or 1 if the cluster is unreachable."""
    from tqdm import tqdm

    from gyrolib.gc.analysis.sensitivity_study import sensitivity as gc_sensitivity
    from gyrolib.gc.analysis.sensitivity_study import sensitivity_inputs as gc_inputs
    from gyrolib.rsf.sensitivity_study import sensitivity as rsf_sensitivity
    from gyrolib.rsf.sensitivity_study import sensitivity_inputs as rsf_inputs

    # the number of sampled inputs, from the studies themselves
    if args.model in ("gc-claims", "rsf-claims"):
        from gyrolib.book.ledger import margin_study

        study = (functools.partial(margin_study.margin_study, args.model),
                 len(margin_study.study_inputs(args.model)))
    else:
        study = {"gc": (gc_sensitivity, len(gc_inputs())),
                 "rsf": (rsf_sensitivity, len(rsf_inputs()))}[args.model]
    total = args.n * ((2 if args.second_order else 1) * study[1] + 2)
    try:
        with optional("SALib", "sensitivity", "python -m gyrolib sensitivity"):
            import SALib  # noqa: F401  (before any work: the study needs it)
        if args.workers is not None or args.scheduler is not None:
            with optional("dask", "dask", "--workers and --scheduler"):
                import dask.distributed  # noqa: F401
        previous, prev_run = _previous(args)
    except (ValueError, ModuleNotFoundError) as exc:
        return _fail(str(exc), 2)
    reused = 0 if previous is None else len(previous.values)
    with ExitStack() as stack:
        t0 = time.perf_counter()
        try:
            executor, workers, where = _connect(args, stack)
        except (OSError, TimeoutError) as exc:
            target = args.scheduler or f"{args.workers} local workers"
            return _fail(f"cannot reach the Dask cluster ({target}) within {args.timeout:g} "
                         f"s: {type(exc).__name__}", 1)
        bar = stack.enter_context(tqdm(total=total, initial=reused, file=sys.stderr,
                                       unit="run", desc=f"sensitivity {args.model}",
                                       mininterval=1.0))
        started = datetime.now(UTC).isoformat(timespec="seconds")
        result = study[0](args.n, seed=args.seed, executor=executor, progress=bar.update,
                          second_order=args.second_order, previous=previous)
        extra: dict[str, Any] = {}
        if args.model in ("gc-claims", "rsf-claims"):   # the margins' slopes at the reference
            extra = {"at": margin_study.reference_outputs(args.model),
                     "slopes": margin_study.margin_slopes(args.model, executor=executor)}
        wall = time.perf_counter() - t0
    record = {**result.to_dict(), **extra}
    record["run"] = {"command": " ".join(["python -m gyrolib sensitivity", args.model, "--n",
                                          str(args.n), "--seed", str(args.seed)]
                                         + ([] if args.second_order else ["--no-second-order"])),
                     "version": __version__, "started": started, "machine": _machine(),
                     "executor": where, "workers": workers, "wall_time_s": wall,
                     "model_runs": total, "model_runs_computed": total - reused}
    if previous is not None:
        record["run"]["extends"] = {"file": args.extend.name, "n": previous.n,
                                    "run": prev_run}
    if args.model in ("gc-claims", "rsf-claims"):   # a stored study's header (gyrolib.store)
        from gyrolib import store
        from gyrolib.book.ledger import studies

        name = "sensitivity-" + args.model.split("-")[0]
        s = store.study(name)
        record[store.HEADER_KEY] = store.Header(
            study=name, key=studies.key(name), rtol=s.rtol, atol=s.atol, version=__version__,
            cpu_class=store.cpu_class(), date=started, cost_cpu_s=None,
            note=f"python -m gyrolib sensitivity on {where}, {workers} worker(s), wall "
                 f"{wall:.0f} s; CPU-s not measured").as_dict()
    write_results(record, args.out)
    sys.stderr.write(f"wrote {args.out}: {total} model runs ({total - reused} computed) in "
                     f"{wall:.1f} s on {workers} "
                     f"worker(s) ({where}); widest interval {result.max_conf():.3f}\n")
    return 0
