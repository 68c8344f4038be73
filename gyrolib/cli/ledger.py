"""The ``ledger`` command: ``python -m gyrolib ledger [--json]``.

The stored studies the ledger reads (the claim maps, the Sobol' studies) are checked first
(:func:`gyrolib.book.studies.check_all`): a stale one exits with status 3 and one line
naming it and the command that refreshes it.
"""

from __future__ import annotations

import argparse
import sys

__all__ = ["add_parser", "run"]


def add_parser(sub: argparse._SubParsersAction, parser_class: type) -> None:
    """Add the ``ledger`` sub-command to ``sub``."""
    led = sub.add_parser("ledger", help="print the reproduction ledger")
    led.add_argument("--json", action="store_true", help="print a JSON list of the items")


def run(args: argparse.Namespace) -> int:
    """Print the ledger as a table or as JSON; status 0, or 3 when a stored study is stale."""
    from gyrolib.book import studies  # not at every start
    from gyrolib.book.ledger import collect, to_json, to_table
    from gyrolib.store import StaleStudy

    try:
        studies.check_all()
    except StaleStudy as exc:
        sys.stderr.write(f"ledger: {exc}\n")
        return 3
    items = collect()
    sys.stdout.write(to_json(items) if args.json else to_table(items))
    return 0
