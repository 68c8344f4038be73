"""``python3 tasks.py refresh``: what it runs (the library's command, on the local cores unless a
Dask scheduler or ``--list`` is given), without running it."""

import os
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
import tasks  # noqa: E402


@pytest.fixture
def ran(monkeypatch):
    calls: list[tuple[str, ...]] = []
    monkeypatch.setattr(tasks, "setup", lambda: None)
    monkeypatch.setattr(tasks, "run", lambda *cmd, **kw: calls.append(tuple(map(str, cmd))))
    return calls


@pytest.mark.parametrize(("argv", "tail"), [
    (["claim-maps"], ["claim-maps", "--workers", str(os.cpu_count() or 1)]),
    (["--scheduler", "tcp://h:8786"], ["--scheduler", "tcp://h:8786"]),
    (["--list"], ["--list"]),
])
def test_refresh_runs_the_librarys_command(ran, argv, tail):
    tasks.main(["refresh", *argv])
    (cmd,) = ran
    assert list(cmd[1:4]) == ["-m", "gyrolib", "refresh"] and list(cmd[4:]) == tail
