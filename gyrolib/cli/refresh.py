"""The ``refresh`` command: ``python -m gyrolib refresh [STUDY ...] [--scheduler ADDR |
--workers K] [--list] [--rekey REASON]`` (``python3 tasks.py refresh`` runs it).

Recomputes the stored studies (:mod:`gyrolib.store`; the book's are registered by
:mod:`gyrolib.book.ledger.studies`) and rewrites their files with a new header (key,
tolerance, version, CPU class, date, cost), with a progress bar on stderr: on the Dask
cluster of ``--scheduler``, on ``--workers K`` local processes (a
``concurrent.futures.ProcessPoolExecutor``), or in this process.  No study name: every study.
``--list`` recomputes no study: it checks each and prints its state (fresh or stale, with
why), whether its key is the code's, whether its fingerprint points still agree (recomputed
even when the key differs, or read from the check memo: :func:`gyrolib.store.check`), its
date, CPU class, the CPU-s it cost and the CPU-s of its check.  ``--rekey REASON`` recomputes
no study either: it stamps the code's key into the named studies whose key differs while
every fingerprint point still agrees (:func:`gyrolib.store.rekey`), REASON in the note.

Exit status 0; 2 for bad arguments (one line, nothing written); with ``--list``, 3 when a
study is stale; with ``--rekey``, 3 when a study's points disagree (nothing written).
"""

from __future__ import annotations

import argparse
import json
import sys

__all__ = ["add_parser", "run"]


def add_parser(sub: argparse._SubParsersAction, parser_class: type) -> None:
    """Add the ``refresh`` sub-command to ``sub``."""
    p = sub.add_parser("refresh", help="recompute the stored studies (or --list their state)")
    p.add_argument("studies", nargs="*", metavar="STUDY",
                   help="the studies to recompute (default: all; --list names them)")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--scheduler", metavar="ADDR", help="a Dask scheduler's address")
    where.add_argument("--workers", type=int, default=None, metavar="K",
                       help="K local worker processes (default: this process)")
    p.add_argument("--rekey", metavar="REASON",
                   help="stamp the code's key into the named studies whose key differs while "
                   "every fingerprint point agrees (a change their numbers do not read), "
                   "with REASON in the header's note; recompute nothing")
    p.add_argument("--list", action="store_true",
                   help="print each study's state, date, CPU class and cost; compute nothing")


def _fail(message: str) -> int:
    sys.stderr.write(f"refresh: error: {' '.join(message.split())}\n")
    return 2


def _listing(names: tuple[str, ...]) -> int:
    from gyrolib import store

    stale = 0
    sys.stdout.write(f"{'study':18s} {'state':6s} {'key':8s} {'points':15s} {'date':26s} "
                     f"{'CPU class':14s} {'cost CPU-s':>10s} {'check CPU-s':>11s}\n")
    for n in names:
        st = store.state(n)
        cost = "?" if st["cost_cpu_s"] is None else f"{st['cost_cpu_s']:.0f}"
        points = (f"{st['points']} agree" if st["points_state"] == "agree" else "disagree")
        points += " (memo)" if st["from_memo"] else ""
        sys.stdout.write(f"{n:18s} {st['state']:6s} {st['key']:8s} {points:15s} "
                         f"{st['date'] or '?':26s} {st['cpu_class'] or '?':14s} {cost:>10s} "
                         f"{st['check_cpu_s']:11.1f}\n")
        if st["state"] != "fresh":
            stale += 1
            for part in ("key", "points"):
                if st[f"{part}_reason"]:
                    sys.stdout.write(f"  {part}: {st[f'{part}_reason']}\n")
    return 3 if stale else 0


def run(args: argparse.Namespace) -> int:
    """Recompute (or list) the studies; the exit status."""
    from gyrolib import store
    from gyrolib.book import studies as _studies

    names = tuple(args.studies) or _studies.NAMES
    unknown = [n for n in names if n not in store.registered()]
    if unknown:
        return _fail(f"unknown study {unknown[0]!r}; known: {', '.join(store.registered())}")
    if args.workers is not None and args.workers < 1:
        return _fail(f"--workers must be an integer >= 1; got {args.workers}")
    if args.rekey is not None:
        if not args.studies:
            return _fail("--rekey needs the studies named")
        for n in names:
            try:
                h = store.rekey(n, args.rekey)
            except (store.StaleStudy, ValueError) as exc:
                sys.stderr.write(f"refresh: {n}: {' '.join(str(exc).split())}\n")
                return 3
            sys.stdout.write(f"{n}: {h.note[h.note.rfind('key re-stamped'):]}\n")
        return 0
    if args.list:
        return _listing(names)
    from tqdm import tqdm

    executor, close, workers, where = None, None, 1, "in-process"
    if args.scheduler:
        from gyrolib._optional import optional

        with optional("dask", "dask", "--scheduler"):
            from dask.distributed import Client
        try:
            client = Client(args.scheduler, timeout=10)
        except (OSError, TimeoutError) as exc:
            sys.stderr.write(f"refresh: cannot reach the Dask scheduler {args.scheduler}: "
                             f"{type(exc).__name__}\n")
            return 1
        executor, close = client.get_executor(), client.close
        workers = len(client.scheduler_info()["workers"])
        where = f"dask scheduler {args.scheduler}"
    elif args.workers is not None and args.workers > 1:
        from concurrent.futures import ProcessPoolExecutor

        executor = ProcessPoolExecutor(args.workers)
        close, workers, where = executor.shutdown, args.workers, "local processes"
    try:
        for n in names:
            with tqdm(total=1, desc=f"refresh {n}", file=sys.stderr, mininterval=1.0) as bar:
                path = store.refresh(n, executor=executor, progress=bar, workers=workers,
                                     where=where)
            h = store.header_of(n, json.loads(path.read_text("utf-8")))
            sys.stderr.write(f"wrote {path}: {h.cost_cpu_s} CPU-s here, {h.cpu_class}\n")
    finally:
        if close is not None:
            close()
    return 0
