"""The two tiers of the test command: ``python3 tasks.py test`` (everyday) and
``python3 tasks.py test --full`` (the full tier too; CI's ``.ci/run``).  The command passes
the option to pytest and requires the tier to run; pytest's "no tests" status fails the
command with a line; ``tests/conftest.py`` skips the tests marked ``full`` without the
option, and under ``GYROLIB_REQUIRE_FULL=1`` refuses a session that would skip the tier."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
import tasks  # noqa: E402
from tests import conftest  # noqa: E402


@pytest.fixture
def pytest_call(monkeypatch):
    """``tasks.test`` with its set-up steps stubbed: returns the list the pytest call's
    (command, environment) is appended to; ``status[0]`` is the status pytest returns."""
    for step in ("setup", "ensure_browser", "lint", "lab_setup"):
        monkeypatch.setattr(tasks, step, lambda: None)
    monkeypatch.setattr(tasks, "warm_numba", lambda: [])
    calls, status = [], [0]

    def run(cmd, **kw):
        calls.append((cmd, kw["env"]))
        return subprocess.CompletedProcess(cmd, status[0])

    monkeypatch.setattr(tasks.subprocess, "run", run)
    return calls, status


def test_the_full_command_passes_the_option_and_requires_the_tier(pytest_call):
    calls, _ = pytest_call
    tasks.main(["test"])
    tasks.main(["test", "--full"])
    (everyday, env0), (full, env1) = calls
    assert everyday[1:4] == ["-m", "pytest", "-n"] and "--full" not in everyday
    assert "GYROLIB_REQUIRE_FULL" not in env0
    assert full[-1] == "--full" and env1["GYROLIB_REQUIRE_FULL"] == "1"
    assert env0["GYROLIB_TEST_COMMAND"] == env1["GYROLIB_TEST_COMMAND"] == "1"


@pytest.mark.parametrize(("status", "line"), [(1, ""), (5, "pytest collected no tests")])
def test_a_failing_or_empty_session_fails_the_command(pytest_call, capsys, status, line):
    """A failed test (pytest's 1) and a session that collected nothing (5) both exit with
    pytest's status; the empty one says so on stderr.  A passing session exits normally."""
    _, st = pytest_call
    st[0] = status
    with pytest.raises(SystemExit) as exc:
        tasks.main(["test", "--full"])
    assert exc.value.code == status
    assert line in capsys.readouterr().err
    st[0] = 0
    tasks.main(["test"])


def test_ci_runs_the_full_command_and_an_unknown_option_is_refused():
    lines = [ln.strip() for ln in (ROOT / ".ci" / "run").read_text().splitlines()
             if ln.strip() and not ln.lstrip().startswith("#")]
    assert lines[-1] == "exec python3 tasks.py test --full"
    assert "set -euo pipefail" in lines
    with pytest.raises(SystemExit) as exc:   # a misspelt tier is the usage text, not a run
        tasks.main(["test", "--ful"])
    assert exc.value.code == tasks.__doc__


class _Item:
    def __init__(self, full: bool):
        self.full, self.added = full, []

    def get_closest_marker(self, name):
        return object() if name == "full" and self.full else None

    def add_marker(self, mark):
        self.added.append(mark)


class _Config:
    def __init__(self, full: bool):
        self.full = full

    def getoption(self, name):
        assert name == conftest.FULL_OPTION
        return self.full


def test_the_full_tier_is_skipped_without_the_option(monkeypatch):
    monkeypatch.delenv(conftest.REQUIRE_FULL_ENV, raising=False)
    items = [_Item(True), _Item(False)]
    assert conftest.select_tier(_Config(False), items) == 1
    (mark,) = items[0].added
    assert mark.name == "skip" and mark.kwargs["reason"] == conftest.FULL_SKIP_REASON
    assert items[1].added == []
    items = [_Item(True), _Item(False)]
    assert conftest.select_tier(_Config(True), items) == 1
    assert items[0].added == [] == items[1].added


def test_a_required_full_tier_that_would_not_run_is_an_error(monkeypatch):
    """Under ``GYROLIB_REQUIRE_FULL=1``: no option is a usage error at once; a session with
    the option in which no test of the full tier ran (a lost marker, a filter) is a problem
    that ends it with a usage error's status (``pytest_sessionfinish``)."""
    monkeypatch.setenv(conftest.REQUIRE_FULL_ENV, "1")
    with pytest.raises(pytest.UsageError, match="without --full"):
        conftest.check_required_tier(_Config(False))
    conftest.check_required_tier(_Config(True))
    assert "no test of the full tier ran" in conftest.full_tier_ran(_Config(True), 0)
    assert conftest.full_tier_ran(_Config(True), 3) == ""
    monkeypatch.delenv(conftest.REQUIRE_FULL_ENV)
    conftest.check_required_tier(_Config(False))
    assert conftest.full_tier_ran(_Config(True), 0) == ""


def _pytest(*args: str, **env: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
                           *args], cwd=ROOT, env=dict(os.environ, GYROLIB_REUSE_BOOK="/none",
                                                      **env),
                          capture_output=True, text=True, timeout=300, check=False)


def test_pytest_refuses_a_required_full_tier_that_does_not_run():
    """End to end, in pytest processes (one test file's cheapest test, under xdist as the
    command runs it): with ``GYROLIB_REQUIRE_FULL=1`` and no ``--full`` the session stops
    with a usage error (status 4) naming the option; with ``--full`` but a selection without
    a test of the full tier, the session's tests pass and it still ends with status 4 and
    the reason."""
    cheap = ["tests/filtering/test_long_run.py", "-k", "cholesky"]
    proc = _pytest("-n", "2", *cheap, GYROLIB_REQUIRE_FULL="1")
    assert proc.returncode == 4, proc.stdout[-2000:] + proc.stderr[-2000:]
    assert "without --full" in proc.stdout + proc.stderr
    proc = _pytest("-n", "0", "--full", *cheap, GYROLIB_REQUIRE_FULL="1")
    assert proc.returncode == 4, proc.stdout[-2000:] + proc.stderr[-2000:]
    assert "1 passed" in proc.stdout and "no test of the full tier ran" in proc.stderr
