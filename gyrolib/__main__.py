"""Command line: ``python -m gyrolib ledger [--json]``."""

from __future__ import annotations

import argparse
import sys


def main(argv: list[str] | None = None) -> int:
    """Run the command line on ``argv`` (default: ``sys.argv[1:]``); returns the exit code.

    Unknown commands or options exit through argparse (status 2, with the usage)."""
    if argv is not None and (not isinstance(argv, list | tuple)
                             or not all(isinstance(a, str) for a in argv)):
        raise TypeError(f"argv must be a list of str or None; got {argv!r:.80}")
    parser = argparse.ArgumentParser(prog="python -m gyrolib")
    sub = parser.add_subparsers(dest="command", required=True)
    led = sub.add_parser("ledger", help="print the reproduction ledger")
    led.add_argument("--json", action="store_true", help="print a JSON list of the items")
    args = parser.parse_args(argv)
    if args.command == "ledger":
        from gyrolib.book.ledger import collect, to_json, to_table

        items = collect()
        sys.stdout.write(to_json(items) if args.json else to_table(items))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
