"""The README's command list and layout table against the package: every command that
``python -m gyrolib --help`` lists is in the README's ``python -m gyrolib COMMAND`` list (and
no other), the layout table's ``cli`` row names the same commands, its ``gyrolib/`` row names
every subpackage, and every path its first column names exists.  Each check is shown to fail
on a README that lags the package by one command or one subpackage."""

from __future__ import annotations

import re
import subprocess
import sys

from tests.conftest import ROOT

README = ROOT / "README.md"


def _commands_of_help(out: str) -> list[str]:
    """The commands of a ``--help`` text (its usage's ``{a,b,...}``)."""
    m = re.search(r"\{([a-z_,-]+)\}", out)
    assert m, f"no command list in --help:\n{out}"
    return m.group(1).split(",")


def _help_commands() -> list[str]:
    """The commands as ``python -m gyrolib --help`` prints them."""
    out = subprocess.run([sys.executable, "-m", "gyrolib", "--help"], capture_output=True,
                         text=True, check=True, cwd=ROOT).stdout
    return _commands_of_help(out)


def _readme_commands(text: str) -> list[str]:
    """The commands of the README's list (between ``<!-- commands -->`` markers)."""
    m = re.search(r"<!-- commands -->\n(.*?)<!-- /commands -->", text, flags=re.S)
    assert m, "README.md has no <!-- commands --> list"
    return re.findall(r"^\| `([a-z_-]+)` \|", m.group(1), flags=re.M)


def _layout_rows(text: str) -> dict[str, str]:
    """The layout table: first column (its backticked paths) → the row's text."""
    section = text.split("\n## Layout\n", 1)[1].split("\n## ", 1)[0]
    rows = {}
    for line in section.splitlines():
        if line.startswith("| `"):
            first, rest = line[2:].split(" | ", 1)
            rows[first] = rest
    return rows


def _layout_cli_commands(text: str) -> list[str]:
    row = _layout_rows(text)["`gyrolib/`"]
    m = re.search(r"`cli` \(the commands: ([^)]*)\)", row)
    assert m, "the layout table's gyrolib row does not list the cli's commands"
    return re.findall(r"`([a-z_-]+)`", m.group(1))


def _subpackages() -> list[str]:
    return sorted(p.parent.name for p in (ROOT / "gyrolib").glob("*/__init__.py"))


def _missing(listed: list[str], wanted: list[str]) -> tuple[list[str], list[str]]:
    """(wanted but not listed, listed but not wanted)."""
    return sorted(set(wanted) - set(listed)), sorted(set(listed) - set(wanted))


def test_the_readme_lists_every_command_of_help():
    text = README.read_text(encoding="utf-8")
    commands = _help_commands()
    from gyrolib.cli import COMMANDS

    assert sorted(commands) == sorted(COMMANDS)      # --help lists the package's commands
    assert _missing(_readme_commands(text), commands) == ([], [])
    assert _missing(_layout_cli_commands(text), commands) == ([], [])
    # power: a command added to --help and not to the README is found, in both places
    assert _missing(_readme_commands(text), [*commands, "frobnicate"]) == (["frobnicate"], [])
    assert _missing(_layout_cli_commands(text),
                    [*commands, "frobnicate"]) == (["frobnicate"], [])
    # and a README that drops one is found too
    first = commands[0]
    dropped = re.sub(rf"^\| `{first}` \|.*\n", "", text, count=1, flags=re.M)
    assert _missing(_readme_commands(dropped), commands) == ([first], [])


def test_the_layout_table_matches_the_package():
    text = README.read_text(encoding="utf-8")
    rows = _layout_rows(text)
    for first in rows:
        for path in re.findall(r"`([^`]+)`", first):
            assert (ROOT / path).exists(), f"the layout table names {path}, which is not there"
    gyrolib_row = rows["`gyrolib/`"]
    named = set(re.findall(r"`([a-z_]+)`", gyrolib_row))
    missing = [s for s in _subpackages() if s not in named]
    assert not missing, f"the layout table's gyrolib row does not name {missing}"
    # power: a subpackage the row does not name is found
    assert "frobnicate" not in named and [s for s in [*_subpackages(), "frobnicate"]
                                          if s not in named] == ["frobnicate"]


def test_a_command_added_to_help_and_not_to_the_readme_fails(monkeypatch, capsys):
    """Power, end to end: a command registered with the command line (so ``--help`` lists
    it) but not written into the README's list is found missing by the same checks."""
    import types

    import pytest

    from gyrolib import cli

    def add_parser(sub, parser_class):
        sub.add_parser("frobnicate", help="a command the README does not list")

    fake = types.SimpleNamespace(add_parser=add_parser, run=lambda args: 0)
    monkeypatch.setitem(cli.COMMANDS, "frobnicate", fake)
    with pytest.raises(SystemExit) as exit_:
        cli.main(["--help"])
    assert exit_.value.code == 0
    commands = _commands_of_help(capsys.readouterr().out)
    assert "frobnicate" in commands
    text = README.read_text(encoding="utf-8")
    assert _missing(_readme_commands(text), commands) == (["frobnicate"], [])
    assert _missing(_layout_cli_commands(text), commands) == (["frobnicate"], [])
