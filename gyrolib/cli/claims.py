"""The ``claims`` command: every claim of both papers judged over the table of inputs.

``python -m gyrolib claims`` prints the stored maps (status, the inputs that flip each claim
and where, the share of the box that holds, the status under each reading); ``--check``
checks the stored study ``claim-maps`` (:mod:`gyrolib.store`: its key, then its fingerprint
points recomputed; exit 3 and one line naming what moved when it is stale); ``--out FILE``
recomputes them (``--workers K`` processes, or ``--scheduler ADDR`` a Dask cluster) and
writes them with the store's header (``python3 tasks.py refresh claim-maps`` does the same
for the package's file).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

__all__ = ["add_parser", "run"]


def add_parser(sub: argparse._SubParsersAction, parser_class: type) -> None:
    """Add the ``claims`` sub-command to ``sub``."""
    p = sub.add_parser("claims", help="every claim judged over the table of inputs")
    p.add_argument("--json", action="store_true", help="print the maps as JSON")
    p.add_argument("--check", action="store_true",
                   help="recompute the stored maps' fingerprint points (exit 3 if stale)")
    p.add_argument("--out", type=Path, metavar="FILE",
                   help="recompute every map and write them to FILE")
    p.add_argument("--only", metavar="IDS",
                   help="comma-separated claim ids (with --out; empty: none, e.g. with --grid)")
    p.add_argument("--grid", action="store_true",
                   help="with --out: (re)compute the race's verdict grid as well")
    p.add_argument("--workers", type=int, default=1, metavar="K",
                   help="worker processes for --out (default 1: in this process)")
    p.add_argument("--scheduler", metavar="ADDR", help="a Dask scheduler for --out")
    p.add_argument("--n-box", type=int, default=None, metavar="N",
                   help="points drawn in the box of uncertain inputs (default: each claim's, "
                        "400 or 2000)")
    p.add_argument("--seed", type=int, default=None, help="seed of the box (default 2026)")
    p.add_argument("--extend", action="store_true",
                   help="with --out: a stored map that agrees with the code keeps its sweeps "
                        "and gets only the new box points (same seed)")


def _text(maps: dict) -> str:
    from gyrolib import quote
    from gyrolib.claim_map import status_line

    lines = []
    for cid, m in maps.items():
        lines.append(f"{cid}: {status_line(m.status, m.share_holding)} "
                     f"(margin {quote.margin(m.margin)}: {m.meaning})")
        cond = m.conditions()
        if cond:
            lines.append(f"  {cond}")
    return "\n".join(lines) + "\n"


def run(args: argparse.Namespace) -> int:
    """Print, check or recompute the maps; the exit status."""
    from gyrolib.book.ledger import claims

    if args.out is not None:
        ids = (None if args.only is None else
               tuple(x.strip() for x in args.only.split(",") if x.strip()))
        unknown = [i for i in ids or () if i not in claims.CLAIMS]
        if unknown:
            sys.stderr.write(f"claims: error: --only: unknown claim {unknown[0]!r}; known: "
                             f"{', '.join(claims.CLAIMS)}\n")
            return 2
        if args.workers < 1 or (args.n_box is not None and args.n_box < 0):
            sys.stderr.write("claims: error: --workers must be >= 1 and --n-box >= 0\n")
            return 2
        executor, close = None, None
        if args.scheduler:
            from gyrolib._optional import optional

            with optional("dask", "dask", "--scheduler"):
                from dask.distributed import Client
            client = Client(args.scheduler)
            executor, close = client.get_executor(), client.close
        elif args.workers > 1:
            from concurrent.futures import ProcessPoolExecutor

            executor = ProcessPoolExecutor(args.workers)
            close = executor.shutdown
        from gyrolib import store

        try:
            path = store.refresh("claim-maps", executor=executor, path=args.out, ids=ids,
                                 grid=args.grid, n_box=args.n_box,
                                 seed=args.seed, extend=args.extend)
        finally:
            if close is not None:
                close()
        result = {k: claims.ClaimMap.from_dict(v) for k, v in json.loads(
            path.read_text(encoding="utf-8"))["maps"].items()
            if ids is None or k in ids}
        sys.stdout.write(_text(result))
        return 0
    try:
        maps = claims.stored_maps()
        if args.check:
            from gyrolib import store

            n = store.check("claim-maps")
            sys.stdout.write(f"{n} fingerprint points of {len(maps)} maps agree\n")
            return 0
    except (ValueError, FileNotFoundError) as exc:
        sys.stderr.write(f"claims: {' '.join(str(exc).split())}\n")
        return 3
    if args.json:
        sys.stdout.write(json.dumps({k: m.to_dict() for k, m in maps.items()}, indent=1)
                         + "\n")
    else:
        sys.stdout.write(_text(maps))
    return 0
