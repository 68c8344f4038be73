"""The ``ledger`` command: ``python -m gyrolib ledger [--json]``."""

from __future__ import annotations

import argparse
import sys

__all__ = ["add_parser", "run"]


def add_parser(sub: argparse._SubParsersAction, parser_class: type) -> None:
    """Add the ``ledger`` sub-command to ``sub``."""
    led = sub.add_parser("ledger", help="print the reproduction ledger")
    led.add_argument("--json", action="store_true", help="print a JSON list of the items")


def run(args: argparse.Namespace) -> int:
    """Print the ledger as a table or as JSON; status 0."""
    from gyrolib.book.ledger import collect, to_json, to_table  # not at every command's start

    items = collect()
    sys.stdout.write(to_json(items) if args.json else to_table(items))
    return 0
