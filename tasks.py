#!/usr/bin/env python3
"""The project's two commands, runnable on a fresh machine with only Python 3.11+.

    python3 tasks.py book    # set up .venv, build the book into _build/html
    python3 tasks.py pdf     # the book as one PDF: _build/pdf/book.pdf (HTML links to it)
    python3 tasks.py lab     # pinned JupyterLab on chapters/ (args go to jupyter lab)
    python3 tasks.py test    # set up .venv (and a browser), lint, the everyday tests (one
                             # clean book); every commit, before you push
    python3 tasks.py test --full   # the same, and the full tier (full recomputations of the
                             # stored studies, long runs, the PDF): what CI runs (.ci/run)

Set-up is idempotent: the virtual environment ``.venv`` is (re)installed from the pinned
``requirements.txt`` whenever that file or ``pyproject.toml`` changes; ``lab`` adds the pinned
``requirements-lab.txt``.  Nothing is ever installed unpinned.  Other sub-commands: ``setup``
(environment only), ``lint``, ``clean``, ``chapter NAME [FOLDER]`` (execute one chapter as a
notebook from the command line, its prose rendered as the book shows it; into
``_build/chapters`` unless FOLDER is given), ``refresh [STUDY ...] [--scheduler ADDRESS]
[--list]`` (recompute the stored heavy studies and rewrite their files, on a Dask cluster
when given its address, else on the local cores; ``--list``: each study's state, date, CPU
class and cost, computing nothing).
"""

from __future__ import annotations

import hashlib
import json
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
LAB_STAMP = VENV / ".gyrolib-lab.sha256"
BUILD = ROOT / "_build"
PDF = BUILD / "pdf" / "book.pdf"

# Extra Debian packages for the browser test (Playwright drives the system Chromium).
BROWSER = Path("/usr/bin/chromium")


def run(*cmd: str | os.PathLike, **kw) -> None:
    print("+", " ".join(str(c) for c in cmd), flush=True)
    subprocess.run([str(c) for c in cmd], check=True, cwd=ROOT, **kw)


def python_env(**extra: str) -> dict[str, str]:
    """The environment of the commands that run the venv's Python: this one, with
    ``extra``, and with bytecode writing on (``PYTHONDONTWRITEBYTECODE`` dropped): the set-up
    installs without byte-compiling, so the modules are compiled once, on first import, and
    not again in every process."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env.update(extra)
    return env


def run_interactive(*cmd: str | os.PathLike, **kw) -> int:
    """Run a program that handles Ctrl-C itself (JupyterLab: it asks, or shuts down) and
    return its exit status.

    Ctrl-C at the terminal reaches the whole process group: this process ignores its
    ``KeyboardInterrupt`` and keeps waiting while the program shuts down in its own way, so
    the command ends with the program's one-line goodbye instead of a traceback of ours
    (``subprocess.run`` would also kill the program 0.25 s later, mid-shutdown).
    """
    print("+", " ".join(str(c) for c in cmd), flush=True)
    proc = subprocess.Popen([str(c) for c in cmd], cwd=ROOT, **kw)
    while True:
        try:
            return proc.wait()
        except KeyboardInterrupt:
            continue


def _setup_fingerprint(names: tuple[str, ...] = ("requirements.txt", "pyproject.toml")) -> str:
    h = hashlib.sha256()
    for name in names:
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
    run(PY, "-m", "pip", "install", "--quiet", "pip==26.3")  # the installer, pinned too
    # --no-compile: pip byte-compiles every module of every package, most never imported (a
    # fresh set-up 118-172 s with it, 41-63 s without, measured on a busy 2-core machine);
    # the modules used are compiled on first import instead (python_env keeps that on)
    run(PY, "-m", "pip", "install", "--quiet", "--no-compile", "-r", "requirements.txt")
    run(PY, "-m", "pip", "install", "--quiet", "--no-deps", "-e", ".")
    STAMP.write_text(fingerprint + "\n")


def ensure_browser() -> None:
    """Install Debian's Chromium, a text font and poppler-utils (``pdftotext``) for the browser
    test and the PDF when they are missing.

    Idempotent: returns at once when both are installed.  Uses the distribution's apt-get as
    root (or through password-less sudo), never ``playwright install``; where that is not
    possible the browser test skips with a message saying what to install.
    """
    wanted = {  # a file each package installs -> the Debian package
        BROWSER: "chromium",
        Path("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"): "fonts-dejavu-core",
        Path("/usr/bin/pdftotext"): "poppler-utils",
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
    """Build the book into _build/html; warnings, cell errors and broken refs fail it.

    The chapters the cache lacks execute as many at a time as there are cores
    (``_ext/parallel_execute.py``); ``GYROLIB_BUILD_JOBS=1`` runs one at a time, with the
    memory of one kernel.
    """
    setup()
    if clean and BUILD.exists():
        shutil.rmtree(BUILD)
    env = python_env(MPLBACKEND="Agg", PYDEVD_DISABLE_FILE_VALIDATION="1")
    run(BIN / "jupyter-book", "build", ".", "--builder", "html",
        "-W", "-n", "--keep-going", env=env)
    index = BUILD / "html" / "index.html"
    if not index.is_file():
        sys.exit(f"book build did not produce {index}")
    print(f"\nbook built: open {index}")


def pdf() -> None:
    """The whole book as one PDF, ``_build/pdf/book.pdf``, and the HTML linking to it.

    Route: a single-page HTML build printed by Debian's Chromium (the one the browser test
    uses) through Playwright, not LaTeX: nothing more to install, a few seconds to print, and
    the PDF shows the same MathJax equations, figures and tables as the web pages.  The
    single-page build shares ``_build/.jupyter_cache`` with the HTML build, so no chapter is
    executed again.  See ``_ext/print_pdf.py``.
    """
    book()
    ensure_browser()
    env = python_env(MPLBACKEND="Agg", PYDEVD_DISABLE_FILE_VALIDATION="1")
    run(BIN / "jupyter-book", "build", ".", "--builder", "singlehtml",
        "-W", "-n", "--keep-going", env=env)
    run(PY, ROOT / "_ext" / "print_pdf.py", BUILD / "singlehtml", PDF)
    book()  # the footer of every page now links the PDF, copied into _build/html
    if not (BUILD / "html" / PDF.name).is_file():
        sys.exit(f"the HTML build did not pick up {PDF}")
    print(f"\nPDF: {PDF}")


# JupyterLab opens the chapters' MyST Markdown files as notebooks (jupytext's viewer).
LAB_SETTINGS = {"@jupyterlab/docmanager-extension:plugin": {
    "defaultViewers": {"markdown": "Jupytext Notebook", "myst": "Jupytext Notebook"}}}


def lab_setup() -> None:
    """Install the pinned JupyterLab of ``requirements-lab.txt`` into ``.venv``.

    ``--no-deps``: every package JupyterLab needs is pinned in that file (resolved together
    with requirements.txt); ``pip check`` fails if one is missing, instead of pip fetching an
    unpinned version.  Idempotent, like ``setup``.
    """
    setup()
    fingerprint = _setup_fingerprint(("requirements.txt", "requirements-lab.txt",
                                      "pyproject.toml"))
    if not (LAB_STAMP.exists() and LAB_STAMP.read_text().strip() == fingerprint):
        run(PY, "-m", "pip", "install", "--quiet", "--no-compile", "--no-deps", "-r",
            "requirements-lab.txt")
        run(PY, "-m", "pip", "check")
        LAB_STAMP.write_text(fingerprint + "\n")
    settings = VENV / "share" / "jupyter" / "lab" / "settings" / "overrides.json"
    settings.parent.mkdir(parents=True, exist_ok=True)
    settings.write_text(json.dumps(LAB_SETTINGS, indent=2) + "\n")


def lab(*args: str) -> None:
    """Open the chapters as notebooks in the pinned JupyterLab (extra args go to jupyter lab,
    e.g. ``python3 tasks.py lab --no-browser --port 8888``)."""
    lab_setup()
    # root in a container or CI: JupyterLab refuses to start unless told it may
    root = ["--allow-root"] if os.name == "posix" and os.geteuid() == 0 else []
    # the extension manager stays read-only: nothing unpinned installed from the UI either
    status = run_interactive(BIN / "jupyter", "lab", f"--ServerApp.root_dir={ROOT / 'chapters'}",
                             "--LabApp.extension_manager=readonly", *root, *args,
                             env=python_env(MPLBACKEND="Agg"))
    if status:  # a signal's exit (-2 for SIGINT) as the shell reports it: 128 + signal
        sys.exit(128 - status if status < 0 else status)


def lint() -> None:
    setup()
    run(BIN / "ruff", "check", ".")
    # the layers of gyrolib ([tool.importlinter] in pyproject.toml), imports inside
    # functions included
    run(BIN / "lint-imports", "--no-logo")


# numba's kernels compiled once, into their on-disk cache, before the test session: else the
# first test workers and chapter kernels compile the same kernels at the same time (about 25 s
# of CPU each on a fresh clone).  Short calls of every compiled path; a failure is left to the
# tests to report (GYROLIB_WARM_STRICT=1 raises it instead: tests/project/test_tasks.py).
# GYROLIB_WARM_SHARE="i/n" runs every n-th call from the i-th: the test command compiles in
# one process per core (the calls are ordered so that the shares of two take about as long:
# Monte Carlo 6 s, square root 7 s, calibrate 4 s, covariance 2 s, noise fit 1.4 s, the rest
# under 1 s, on a fresh clone).
WARM_NUMBA = """
import os
from dataclasses import replace
import numpy as np
from gyrolib import filtering, gc, records
strict = os.environ.get("GYROLIB_WARM_STRICT") == "1"
P = gc.GyrocompassParams()
calls = [
    lambda: gc.monte_carlo(P, 2, 0.05, seed=1),
    lambda: filtering.covariance_square_root(gc.discretize(P, 0.05).model,
                                             gc.initial_covariance(P)),
    lambda: gc.calibrate(records.read_gc("data/gc_record.csv.gz"), P),
    lambda: gc.covariance_analysis(P, 0.05),
    lambda: gc.fit_noise(gc.GCRecord(*(np.asarray(getattr(rec, k))[:2000] for k in (
        "t", "angle_sensor", "inclinometer_y", "inclinometer_z"))), P, max_evaluations=40),
    lambda: gc.simulate_truth(P, 0.05, np.zeros(10), seed=1),
    lambda: gc.information_psi_omega(P, 0.05),
    # the rival's 15-state kernel (its own compile: 3.6 CPU-s at a race's first call)
    lambda: gc.rate_sensor_model(P, gc.RateSensorProcedure()).optimal_run(1.0, 1.0),
    # the rival's truth (its lane kernels)
    lambda: gc.rate_sensor_monte_carlo(P, t1=0.2, t2=0.2, n_runs=2, seed=1),
    # the covariance kernel at the sizes of the instrument terms' states (11 to 14: one
    # kernel per size, about 3 CPU-s each to compile; 10 and 15 are compiled above), which
    # the claim maps' tests (one input alone ON) and others run: compiled here once, not in
    # whichever test process needs a size first (two at a time under xdist)
    lambda: gc.covariance_analysis(replace(P, sigma_as_offset=5e-6), 0.05),
    lambda: gc.covariance_analysis(replace(P, sigma_incl_bias=5e-4), 0.05),
    lambda: gc.covariance_analysis(replace(P, sigma_as_offset=5e-6, sigma_incl_bias=5e-4),
                                   0.05),
    lambda: gc.covariance_analysis(replace(P, sigma_as_offset=5e-6, sigma_incl_bias=5e-4,
                                           sigma_hf_scale=1e-4), 0.05),
]
share, shares = (int(x) for x in os.environ.get("GYROLIB_WARM_SHARE", "0/1").split("/"))
rec = records.read_gc("data/gc_record.csv.gz")
for call in calls[share::shares]:
    try:
        call()
    except Exception:
        if strict:
            raise
"""


def warm_numba() -> list[subprocess.Popen]:
    """Start compiling numba's kernels into their cache (:data:`WARM_NUMBA`) in the
    background, in one process per core (each a share of the calls); the caller waits for
    them before the test session."""
    shares = max(1, min(4, os.cpu_count() or 1))
    return [subprocess.Popen([str(PY), "-c", WARM_NUMBA], cwd=ROOT,
                             env=python_env(MPLBACKEND="Agg", OPENBLAS_NUM_THREADS="1",
                                            GYROLIB_WARM_SHARE=f"{i}/{shares}"),
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            for i in range(shares)]


#: pytest's exit status when it collected no test (or deselected them all).
PYTEST_NO_TESTS = 5


def test(full: bool = False) -> None:
    """Lint, the pinned JupyterLab environment (a test runs a chapter's notebook with its
    kernel), then the test suite: the everyday tier, and with ``full`` the full tier too.

    The everyday tier is every test except those marked ``full`` (full recomputations of the
    stored studies, long runs, a second execution of every chapter), which pytest skips
    without ``--full`` (``tests/conftest.py``); ``full=True`` passes ``--full`` and
    requires the session to find and run that tier (``GYROLIB_REQUIRE_FULL``).  CI runs
    ``python3 tasks.py test --full`` (``.ci/run``).

    The suite runs on every core (pytest-xdist workers).  It builds the book once, from
    clean, into a temporary folder (every chapter executed, warnings as errors, and in the
    full tier the PDF printed; ``tests/conftest.py``), in the background while the other
    tests run; the HTML, browser, PDF and determinism tests run last and share that build.
    ``_build/`` is left as it is: the determinism test compares the chapters' outputs with
    their recorded outputs (``tests/recorded_outputs/``); the full tier executes every
    chapter a second time.  Exits with pytest's status; a session that collected no test
    (pytest's status 5) fails with a line saying so.
    """
    setup()
    warm = warm_numba()  # while the browser, lint and JupyterLab set-up run
    try:
        ensure_browser()
        lint()
        lab_setup()
    finally:
        for proc in warm:
            proc.wait()
    env = python_env(MPLBACKEND="Agg", GYROLIB_TEST_COMMAND="1")
    tier: list[str] = []
    env.pop("GYROLIB_REQUIRE_FULL", None)   # the everyday tier, even when run from a full one
    if full:
        tier = ["--full"]
        env["GYROLIB_REQUIRE_FULL"] = "1"
    # pytest-xdist: the tests on every core (the book is built once, by one worker, for all)
    cmd = [str(PY), "-m", "pytest", "-n", "auto", "--durations=10", *tier]
    print("+", " ".join(cmd), flush=True)
    status = subprocess.run(cmd, cwd=ROOT, env=env, check=False).returncode
    if status == PYTEST_NO_TESTS:
        print(f"pytest collected no tests (exit {PYTEST_NO_TESTS}): the test command fails",
              file=sys.stderr, flush=True)
    if status:  # a signal's exit (-2 for SIGINT) as the shell reports it: 128 + signal
        sys.exit(128 - status if status < 0 else status)


def chapter(name: str, out: str | os.PathLike | None = None) -> None:
    """Execute one chapter as a notebook from the command line (output in _build/chapters,
    or the folder ``out``).

    The executed notebook's prose is then rendered as the book's page shows it
    (``_ext/rerun_notebook.py``): the glued values and figures of this run pasted in,
    cross-references and citations as text, and a first cell saying so.
    """
    setup()
    src = ROOT / "chapters" / f"{Path(name).stem}.md"
    if not src.is_file():
        sys.exit(f"no chapter {src}")
    out = Path(out).resolve() if out else BUILD / "chapters"
    out.mkdir(parents=True, exist_ok=True)
    ipynb = out / f"{src.stem}.ipynb"
    # the kernel's environment as in the book build (_ext/gyrolib_cache.py): OpenBLAS on one
    # thread, since its threads only spin on the chapters' small matrices
    env = python_env(MPLBACKEND="Agg")
    env.setdefault("OPENBLAS_NUM_THREADS", "1")
    # read (jupytext), executed in a kernel in OUT (nbclient, as `jupyter nbconvert
    # --execute`), rendered: one process (_ext/rerun_notebook.py's execute_chapter)
    run(PY, ROOT / "_ext" / "rerun_notebook.py", "--execute", src, ipynb, env=env)


def refresh(*args: str) -> None:
    """Recompute the stored studies (``python -m gyrolib refresh``, :mod:`gyrolib.store`):
    the studies named (default: all) on the Dask cluster of ``--scheduler ADDRESS``, else on
    as many local worker processes as there are cores; ``--list`` shows their state."""
    setup()
    extra = [] if "--scheduler" in args or "--list" in args or "--workers" in args else \
        ["--workers", str(os.cpu_count() or 1)]
    run(PY, "-m", "gyrolib", "refresh", *args, *extra, env=python_env())


def clean() -> None:
    if BUILD.exists():
        shutil.rmtree(BUILD)


def main(argv: list[str]) -> None:
    cmds = {"setup": setup, "book": book, "pdf": pdf, "test": test, "lint": lint,
            "clean": clean}
    if len(argv) in (2, 3) and argv[0] == "chapter":
        chapter(*argv[1:])
    elif argv == ["test", "--full"]:
        test(full=True)
    elif argv and argv[0] == "lab":
        lab(*argv[1:])
    elif argv and argv[0] == "refresh":
        refresh(*argv[1:])
    elif len(argv) == 1 and argv[0] in cmds:
        cmds[argv[0]]()
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    try:
        main(sys.argv[1:])
    except subprocess.CalledProcessError as exc:
        sys.exit(exc.returncode or 1)
    except KeyboardInterrupt:  # Ctrl-C during set-up, a build or the tests: no traceback
        print("interrupted", file=sys.stderr)
        sys.exit(130)
