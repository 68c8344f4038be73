"""tasks.py's numba warm-up before the test session: every call of
``WARM_NUMBA`` runs against the current API (errors are swallowed under the test command, so a
call that no longer fits would silently stop warming the cache), and the kernels it reaches
are then in numba's cache.  (What it saves is measured, not asserted: a cold run of it takes
about 26 s of CPU, a run on the filled cache about 2 s.)"""

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
import tasks  # noqa: E402


def _warm(code: str) -> subprocess.CompletedProcess:
    env = dict(os.environ, GYROLIB_WARM_STRICT="1", PYTHONPATH=str(ROOT), MPLBACKEND="Agg",
               OPENBLAS_NUM_THREADS="1")
    env.pop("NUMBA_CACHE_DIR", None)   # the cache the test session uses: next to the sources
    return subprocess.run([sys.executable, "-c", code], cwd=ROOT, env=env, capture_output=True,
                          text=True, timeout=900, check=False)


def test_warm_up_runs_every_call_and_fills_the_cache():
    """Strict: every call succeeds, and numba's cache then holds the kernels of the
    covariance, square-root, observability, Monte Carlo, calibration and noise-fit modules
    (their index files next to the sources)."""
    proc = _warm(tasks.WARM_NUMBA)
    assert proc.returncode == 0, proc.stderr[-3000:]
    index = {p.name.split(".")[0] for p in (ROOT / "gyrolib").rglob("__pycache__/*.nbi")}
    assert {"covariance", "montecarlo", "calibration", "noise_fit", "observability",
            "square_root"} <= index, index


def test_a_broken_warm_up_call_fails_under_strict():
    """Power: a call that does not fit the API fails the strict run."""
    broken = tasks.WARM_NUMBA.replace(
        "calls = [", "calls = [\n    lambda: gc.monte_carlo(P, 2, 0.05, no_such_option=1),", 1)
    assert broken != tasks.WARM_NUMBA
    proc = _warm(broken)
    assert proc.returncode != 0 and "no_such_option" in proc.stderr


def test_commands_write_bytecode_since_the_set_up_does_not_compile(monkeypatch):
    """The set-up installs with ``--no-compile``; the commands that run the venv's Python get
    an environment with bytecode writing on, so each module is compiled once, on first
    import, even where the caller's environment turns it off (as this sandbox's does).  The
    caller's other variables and the command's own pass through."""
    source = (ROOT / "tasks.py").read_text(encoding="utf-8")
    assert '"install", "--quiet", "--no-compile", "-r", "requirements.txt"' in source
    monkeypatch.setenv("PYTHONDONTWRITEBYTECODE", "1")
    monkeypatch.setenv("GYROLIB_SOME_SETTING", "kept")
    env = tasks.python_env(MPLBACKEND="Agg")
    assert "PYTHONDONTWRITEBYTECODE" not in env
    assert env["GYROLIB_SOME_SETTING"] == "kept" and env["MPLBACKEND"] == "Agg"
    assert "PYTHONDONTWRITEBYTECODE" in dict(os.environ)   # what a plain copy would pass on
    for call in ("def book", "def test", "def chapter", "def lab(", "def warm_numba"):
        body = source.split(call, 1)[1].split("\ndef ", 1)[0]
        assert "python_env(" in body and "os.environ" not in body, call
