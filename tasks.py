#!/usr/bin/env python3
"""The project's two commands, runnable on a fresh machine with only Python 3.11+.

    python3 tasks.py book    # set up .venv, build the book into _build/html
    python3 tasks.py test    # set up .venv (and a browser), lint, clean book build, all tests

Set-up is idempotent: the virtual environment ``.venv`` is (re)installed from the pinned
``requirements.txt`` whenever that file or ``pyproject.toml`` changes.  Other sub-commands:
``setup`` (environment only), ``lint``, ``clean``, ``chapter NAME`` (execute one chapter as a
notebook from the command line).
"""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import sys
import venv
from pathlib import Path

ROOT = Path(__file__).resolve().parent
VENV = ROOT / ".venv"
BIN = VENV / ("Scripts" if os.name == "nt" else "bin")
PY = BIN / "python"
STAMP = VENV / ".gyrolib-setup.sha256"
BUILD = ROOT / "_build"

# Extra Debian packages for the browser test (Playwright drives the system Chromium).
BROWSER = Path("/usr/bin/chromium")


def run(*cmd: str | os.PathLike, **kw) -> None:
    print("+", " ".join(str(c) for c in cmd), flush=True)
    subprocess.run([str(c) for c in cmd], check=True, cwd=ROOT, **kw)


def _setup_fingerprint() -> str:
    h = hashlib.sha256()
    for name in ("requirements.txt", "pyproject.toml"):
        h.update((ROOT / name).read_bytes())
    h.update(sys.version.encode())
    return h.hexdigest()


def setup() -> None:
    """Create .venv and install the pinned environment and gyrolib (editable)."""
    if sys.version_info < (3, 11):  # noqa: UP036 - tasks.py runs under any system python
        sys.exit(f"Python 3.11 or newer is needed; this is {sys.version.split()[0]}")
    fingerprint = _setup_fingerprint()
    if PY.exists() and STAMP.exists() and STAMP.read_text().strip() == fingerprint:
        return
    if not PY.exists():
        print(f"creating virtual environment {VENV}", flush=True)
        venv.EnvBuilder(with_pip=True, clear=True).create(VENV)
    run(PY, "-m", "pip", "install", "--quiet", "--upgrade", "pip")
    run(PY, "-m", "pip", "install", "--quiet", "-r", "requirements.txt")
    run(PY, "-m", "pip", "install", "--quiet", "--no-deps", "-e", ".")
    STAMP.write_text(fingerprint + "\n")


def ensure_browser() -> None:
    """Install Debian's Chromium and a text font for the browser test when they are missing.

    Idempotent: returns at once when both are installed.  Uses the distribution's apt-get as
    root (or through password-less sudo), never ``playwright install``; where that is not
    possible the browser test skips with a message saying what to install.
    """
    wanted = {  # a file each package installs -> the Debian package
        BROWSER: "chromium",
        Path("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"): "fonts-dejavu-core",
    }
    missing = [pkg for path, pkg in wanted.items() if not path.exists()]
    if not missing:
        return
    if os.name != "posix" or shutil.which("apt-get") is None:
        print(f"note: no apt-get to install {' '.join(missing)}: the browser test will skip "
              "without /usr/bin/chromium", flush=True)
        return
    if os.geteuid() == 0:
        sudo: list[str] = []
    elif shutil.which("sudo") and subprocess.run(["sudo", "-n", "true"],
                                                 capture_output=True).returncode == 0:
        sudo = ["sudo", "-n"]
    else:
        print(f"note: not root: install {' '.join(missing)} with apt-get, or the browser test "
              "will skip", flush=True)
        return
    apt = [*sudo, "env", "DEBIAN_FRONTEND=noninteractive", "apt-get", "-qq"]
    install = [*apt, "install", "-y", "--no-install-recommends", *missing]
    try:
        try:
            run(*install)  # package lists already present: no download of the index
        except subprocess.CalledProcessError:
            print("note: package lists missing or stale: apt-get update", flush=True)
            run(*apt, "update")
            run(*install)
    except (subprocess.CalledProcessError, OSError) as exc:
        print(f"note: could not install {' '.join(missing)} ({exc}); the browser test will "
              "skip", flush=True)
        return
    if BROWSER.exists():  # a broken install (missing libraries) shows up here, not in pytest
        check = subprocess.run([str(BROWSER), "--headless", "--no-sandbox", "--version"],
                               capture_output=True, text=True, check=False)
        print(f"browser: {check.stdout.strip() or check.stderr.strip()}", flush=True)


def book(clean: bool = False) -> None:
    """Build the book into _build/html; warnings, cell errors and broken refs fail it."""
    setup()
    if clean and BUILD.exists():
        shutil.rmtree(BUILD)
    env = dict(os.environ, MPLBACKEND="Agg", PYDEVD_DISABLE_FILE_VALIDATION="1")
    run(BIN / "jupyter-book", "build", ".", "--builder", "html",
        "-W", "-n", "--keep-going", env=env)
    index = BUILD / "html" / "index.html"
    if not index.is_file():
        sys.exit(f"book build did not produce {index}")
    print(f"\nbook built: open {index}")


def lint() -> None:
    setup()
    run(BIN / "ruff", "check", ".")


def test() -> None:
    """Lint, clean full book build (warnings as errors), then the whole test suite."""
    setup()
    ensure_browser()
    lint()
    book(clean=True)
    env = dict(os.environ, MPLBACKEND="Agg", GYROLIB_BOOK_BUILT="1")
    run(PY, "-m", "pytest", env=env)


def chapter(name: str) -> None:
    """Execute one chapter as a notebook from the command line (output in _build/chapters)."""
    setup()
    src = ROOT / "chapters" / f"{Path(name).stem}.md"
    if not src.is_file():
        sys.exit(f"no chapter {src}")
    out = BUILD / "chapters"
    out.mkdir(parents=True, exist_ok=True)
    ipynb = out / f"{src.stem}.ipynb"
    run(BIN / "jupytext", "--to", "ipynb", "--output", ipynb, src)
    run(BIN / "jupyter", "nbconvert", "--to", "notebook", "--execute", "--inplace",
        "--ExecutePreprocessor.timeout=600", ipynb, env=dict(os.environ, MPLBACKEND="Agg"))
    print(f"executed {ipynb}")


def clean() -> None:
    if BUILD.exists():
        shutil.rmtree(BUILD)


def main(argv: list[str]) -> None:
    cmds = {"setup": setup, "book": book, "test": test, "lint": lint, "clean": clean}
    if len(argv) == 2 and argv[0] == "chapter":
        chapter(argv[1])
    elif len(argv) == 1 and argv[0] in cmds:
        cmds[argv[0]]()
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    try:
        main(sys.argv[1:])
    except subprocess.CalledProcessError as exc:
        sys.exit(exc.returncode or 1)
