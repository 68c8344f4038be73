"""The first numba compile says so: one line on a terminal's stderr, none
when the kernels come from the cache, none into a pipe."""

import os
import pty
import subprocess
import sys
from pathlib import Path

from gyrolib._compile_note import NOTE

ROOT = Path(__file__).resolve().parents[2]

# two gyrolib kernels compiled (the Cholesky kernel, then the Monte Carlo truth's cos x - 1):
# one note
SCRIPT = """
import numpy as np
from gyrolib import filtering
from gyrolib.gc.analysis import montecarlo
filtering.cholesky_semidefinite(np.eye(2))
montecarlo._cm1(0.5)
print("done", flush=True)
"""


def _run(cache: Path, tty: bool) -> tuple[str, str]:
    """``(stdout, stderr)`` of SCRIPT in a fresh process with numba's cache in ``cache``;
    stderr a pseudo-terminal when ``tty``."""
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache), PYTHONPATH=str(ROOT))
    if not tty:
        proc = subprocess.run([sys.executable, "-c", SCRIPT], capture_output=True, text=True,
                              env=env, timeout=300, check=True)
        return proc.stdout, proc.stderr
    main, child = pty.openpty()
    proc = subprocess.Popen([sys.executable, "-c", SCRIPT], stdout=subprocess.PIPE,
                            stderr=child, env=env, text=True)
    os.close(child)
    out, _ = proc.communicate(timeout=300)
    chunks = []
    while True:
        try:
            data = os.read(main, 4096)
        except OSError:  # the terminal's other end closed: all read
            break
        if not data:
            break
        chunks.append(data)
    os.close(main)
    assert proc.returncode == 0
    return out, b"".join(chunks).decode()


def test_first_compile_says_so_once_and_the_cache_is_silent(tmp_path):
    """Fresh cache on a terminal: exactly one note for two kernels compiled.  The same
    script again (the kernels now load from the cache): no note, so the note is tied to a
    compile, not printed at every start.  Into a pipe with a fresh cache: no note."""
    out, err = _run(tmp_path / "cache", tty=True)
    assert out.strip() == "done"
    assert err.splitlines().count(NOTE) == 1, err
    assert any((tmp_path / "cache").rglob("*.nbi"))   # it did compile and cache
    _, err_cached = _run(tmp_path / "cache", tty=True)
    assert NOTE not in err_cached
    _, err_pipe = _run(tmp_path / "other", tty=False)
    assert NOTE not in err_pipe
