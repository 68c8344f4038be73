"""Command line: ``python -m gyrolib ledger [--json]`` and
``python -m gyrolib calibrate gc|rsf FILE [...]``."""

from __future__ import annotations

import argparse
import sys


class _OneLineParser(argparse.ArgumentParser):
    """Usage errors of ``calibrate`` as one line on stderr, exit status 2."""

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
    sub = parser.add_subparsers(dest="command", required=True)
    led = sub.add_parser("ledger", help="print the reproduction ledger")
    led.add_argument("--json", action="store_true", help="print a JSON list of the items")
    cal = sub.add_parser("calibrate", help="apply paper GC or RSF to a recorded CSV file")
    methods = cal.add_subparsers(dest="method", required=True, parser_class=_OneLineParser)
    from gyrolib.records.cli import add_arguments

    add_arguments(methods)
    args = parser.parse_args(argv)
    if args.command == "ledger":
        from gyrolib.book.ledger import collect, to_json, to_table

        items = collect()
        sys.stdout.write(to_json(items) if args.json else to_table(items))
        return 0
    from gyrolib.records.cli import run

    return run(args)


if __name__ == "__main__":
    raise SystemExit(main())
