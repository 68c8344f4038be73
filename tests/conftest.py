"""Shared test helpers: the book built once per test session.

The tests of the built book (HTML checks, the real browser, the PDF, determinism, the ledger
pages, the release footer, the downloadable notebooks) share one build, made by
:func:`session_book` in a temporary folder with a fresh jupyter cache, so every chapter is
executed and every warning shown (``-W -n --keep-going``, as ``python3 tasks.py book``):

1. ``jupyter-book build --builder singlehtml`` — executes every chapter;
2. ``_ext/print_pdf.py`` prints that page to ``pdf/book.pdf`` with Chromium (when installed;
   in the full tier only, ``--full``: the PDF's tests are of that tier);
3. ``jupyter-book build --builder html`` — reads the chapters' outputs from the cache of
   step 1 (nothing executed again) and links the PDF from every page's footer.

The build starts in the background as soon as the tests are collected (when a collected test
module uses the book), and the tests that need it are moved to the end of the run
(:func:`pytest_collection_modifyitems`), so that all the other tests run meanwhile; the
first test that needs the book waits for what is left of the build.  The project's own
``_build/`` is never touched.

Under pytest-xdist (``python3 tasks.py test`` runs ``pytest -n auto``) the workers share one
build: the controlling process makes its folder (``$GYROLIB_SESSION_BOOK_DIR``, removed at the
end) and, as soon as a worker reports a collected module that uses the book, builds it there
in the background, at normal priority, while the workers run the other tests at a lower one
(niceness ``WORKER_NICENESS``) so that the build, the longest chain of the run, is not slowed
by them.  The build holds the folder's file lock; a worker that needs the book takes the lock
after it and reads the build's record (``book.json``), or builds the book itself if it got
the lock first.

``GYROLIB_REUSE_BOOK=1`` skips the build and uses the project's ``_build/`` as
``python3 tasks.py pdf`` left it (``GYROLIB_REUSE_BOOK=/path/to/_build``: another build
folder, e.g. one kept by ``GYROLIB_KEEP_BOOK=1``), for quick local reruns; the determinism
test then compares with the recorded outputs (the full tier executes every chapter a second
time itself).  ``GYROLIB_KEEP_BOOK=1`` keeps the temporary build and prints where it is.

Two tiers: ``--full`` (:data:`FULL_OPTION`, ``python3 tasks.py test --full``, CI) runs the
tests marked ``full`` too; without it they are skipped (:func:`select_tier`).
"""

from __future__ import annotations

import inspect
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
JUPYTER_BOOK = Path(sys.executable).with_name("jupyter-book")
CHROMIUM = Path("/usr/bin/chromium")
BUILD_FLAGS = ["-W", "-n", "--keep-going"]  # as in tasks.py
BUILD_TIMEOUT_S = 1800


@dataclass(frozen=True)
class Book:
    """A built book: ``build`` is its ``_build`` folder.

    ``html`` the HTML pages, ``pdf`` the whole book as one PDF (missing when Chromium is not
    installed: ``pdf_error`` says why), ``executed`` the executed notebooks (myst-nb's
    ``jupyter_execute``), ``cache`` the jupyter cache the chapters were executed into, and
    ``fresh`` whether they were executed in this test session (a new, empty cache).
    ``seconds`` is what each build step took, ``chapters`` each chapter's execution (s, as
    myst-nb reports it).
    """

    build: Path
    fresh: bool
    pdf_error: str = ""
    seconds: tuple[tuple[str, float], ...] = ()
    chapters: tuple[tuple[str, float], ...] = ()

    @property
    def html(self) -> Path:
        return self.build / "html"

    @property
    def pdf(self) -> Path:
        return self.build / "pdf" / "book.pdf"

    @property
    def executed(self) -> Path:
        return self.build / "jupyter_execute"

    @property
    def cache(self) -> Path:
        return self.build / ".jupyter_cache"


def _config(out: Path) -> Path:
    """The project's ``_config.yml`` with the jupyter cache in ``out`` (a fresh one) and the
    local extensions found from anywhere."""
    import yaml

    cfg = yaml.safe_load((ROOT / "_config.yml").read_text(encoding="utf-8"))
    cfg["execute"]["cache"] = str(out / "_build" / ".jupyter_cache")
    cfg["sphinx"]["local_extensions"] = {name: str(ROOT / path) for name, path
                                         in cfg["sphinx"]["local_extensions"].items()}
    path = out / "_config.yml"
    path.write_text(yaml.safe_dump(cfg, allow_unicode=True, sort_keys=False), encoding="utf-8")
    return path


class _BookBuild:
    """The three build steps, run once, in a background thread."""

    def __init__(self) -> None:
        self.book: Book | None = None
        self.error = ""
        self.tmp: Path | None = None
        self.waited = False
        self.logs: dict[str, str] = {}
        self._cancelled = False
        self._proc: subprocess.Popen | None = None
        self._thread: threading.Thread | None = None
        self._lock = threading.Lock()

    def start(self) -> None:
        with self._lock:
            if self._thread is None:
                self._thread = threading.Thread(target=self._run, name="gyrolib-book",
                                                daemon=True)
                self._thread.start()

    def wait(self) -> Book:
        self.waited = True
        self.start()
        self._thread.join()
        if self.book is None:
            pytest.fail(self.error or "the session's book build did not finish")
        return self.book

    def _step(self, name: str, cmd: list[str], seconds: list) -> str | None:
        env = dict(os.environ, MPLBACKEND="Agg", PYDEVD_DISABLE_FILE_VALIDATION="1",
                   NO_COLOR="1")
        t0, start, cpu0 = time.perf_counter(), time.time(), _children_cpu()
        with self._lock:
            if self._cancelled:
                return f"{name}: cancelled"
            # its own process group: a cancelled build ends with its kernels
            self._proc = subprocess.Popen([str(c) for c in cmd], cwd=ROOT, env=env, text=True,
                                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                          start_new_session=True)
        try:
            output, _ = self._proc.communicate(timeout=BUILD_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            self._kill()
            self._proc.communicate()
            return f"{name}: more than {BUILD_TIMEOUT_S} s"
        seconds.append((name, round(time.perf_counter() - t0, 1)))
        _timeline_write({"book_step": name, "start": start, "end": time.time(),
                         "cpu": round(_children_cpu() - cpu0, 2)})
        self.logs[name] = output
        if self._proc.returncode != 0:
            return f"{name} failed (exit {self._proc.returncode}):\n{output[-6000:]}"
        return None

    def _kill(self) -> None:
        """End the running step: jupyter-book and every process under it (the kernels run in
        sessions of their own, so the process group alone would leave them running, and
        holding the step's output pipe open)."""
        proc = self._proc
        if proc is None or proc.poll() is not None:
            return
        import psutil

        try:
            tree = psutil.Process(proc.pid).children(recursive=True)
        except psutil.Error:
            tree = []
        try:
            os.killpg(proc.pid, signal.SIGTERM)
        except ProcessLookupError:
            pass
        for child in tree:
            try:
                child.terminate()
            except psutil.Error:
                pass
        psutil.wait_procs(tree, timeout=10)

    def _run(self) -> None:
        reuse = os.environ.get("GYROLIB_REUSE_BOOK", "")
        if reuse:
            build = ROOT / "_build" if reuse == "1" else Path(reuse)
            if not (build / "html" / "index.html").is_file():
                self.error = (f"GYROLIB_REUSE_BOOK={reuse} but there is no "
                              f"{build}/html/index.html: run `python3 tasks.py pdf` first")
                return
            self.book = Book(build=build, fresh=False,
                             pdf_error="" if (build / "pdf" / "book.pdf").is_file()
                             else f"no {build}/pdf/book.pdf: run `python3 tasks.py pdf`")
            return
        if not JUPYTER_BOOK.is_file():
            self.error = f"no {JUPYTER_BOOK}: run the tests with the project's .venv python"
            return
        shared = os.environ.get(SHARED_ENV, "")
        if shared:
            self._run_shared(Path(shared))
            return
        self.tmp = Path(tempfile.mkdtemp(prefix="gyrolib-test-book-"))
        self._build_into(self.tmp)

    def _run_shared(self, folder: Path) -> None:
        """Under pytest-xdist: the first worker to get the folder's lock builds the book into
        it and records the result in ``book.json``; a worker that gets the lock later reads
        that record instead of building again."""
        import fcntl

        with open(folder / "build.lock", "a") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX)
            try:
                record = folder / "book.json"
                if record.is_file():
                    self.book, self.error = _read_record(record)
                    return
                self._build_into(folder)
                _write_record(record, self.book, self.error)
            finally:
                fcntl.flock(lock, fcntl.LOCK_UN)

    def _build_into(self, tmp: Path) -> None:
        """The three build steps into ``tmp`` (sets ``book`` or ``error``)."""
        config = _config(tmp)
        build = tmp / "_build"
        base = [JUPYTER_BOOK, "build", ROOT, "--config", config, "--path-output", tmp,
                *BUILD_FLAGS, "--builder"]
        seconds: list[tuple[str, float]] = []
        error = self._step("single-page build (executes every chapter)",
                           [*base, "singlehtml"], seconds)
        if error:
            self.error = error
            return
        pdf_error = ""
        if not _PRINT_PDF[0]:
            pdf_error = (f"the PDF is printed in the full tier ({FULL_OPTION}) only: "
                         "tests/book/test_pdf.py")
        elif CHROMIUM.exists():
            pdf_error = self._step("PDF print", [sys.executable, ROOT / "_ext" / "print_pdf.py",
                                                 build / "singlehtml",
                                                 build / "pdf" / "book.pdf"], seconds) or ""
        else:
            pdf_error = f"no {CHROMIUM}: the PDF was not printed"
        error = self._step("HTML build (outputs from the cache)", [*base, "html"], seconds)
        if error:
            self.error = error
            return
        executed = re.findall(r"(\S+)\.md: Executed notebook in ([\d.]+) seconds",
                              "\n".join(self.logs.values()))
        chapters = tuple(sorted(((Path(p).relative_to(ROOT).as_posix(), float(t))
                                 for p, t in executed), key=lambda c: -c[1]))
        self.book = Book(build=build, fresh=True, pdf_error=pdf_error, seconds=tuple(seconds),
                         chapters=chapters)

    def cleanup(self) -> None:
        """At the end of the session: a build nobody waited for is stopped (a run of tests
        that turned out not to need it); the temporary folder is removed."""
        if self._thread is None:
            return
        if not self.waited and not os.environ.get(SHARED_ENV):  # another worker may need it
            with self._lock:
                self._cancelled = True
            self._kill()
        self._thread.join()
        if self.tmp is not None:
            if os.environ.get("GYROLIB_KEEP_BOOK") == "1" and self.book is not None:
                print(f"\nthe test session's book is kept in {self.tmp}")
            else:
                shutil.rmtree(self.tmp, ignore_errors=True)


def _write_record(path: Path, book: Book | None, error: str) -> None:
    data = {"error": error, "book": None if book is None else {
        "build": str(book.build), "fresh": book.fresh, "pdf_error": book.pdf_error,
        "seconds": book.seconds, "chapters": book.chapters}}
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps(data), encoding="utf-8")
    tmp.replace(path)


def _read_record(path: Path) -> tuple[Book | None, str]:
    data = json.loads(path.read_text(encoding="utf-8"))
    b = data["book"]
    book = None if b is None else Book(
        build=Path(b["build"]), fresh=b["fresh"], pdf_error=b["pdf_error"],
        seconds=tuple(tuple(x) for x in b["seconds"]),
        chapters=tuple(tuple(x) for x in b["chapters"]))
    return book, data["error"]


#: Under pytest-xdist, the folder (made by the controlling process) into which the session's
#: book is built once for all the workers.
SHARED_ENV = "GYROLIB_SESSION_BOOK_DIR"
#: Niceness of the xdist workers: the book build keeps the processor first.
WORKER_NICENESS = 10

_BUILD = _BookBuild()


def session_book() -> Book:
    """The book built once for this test session (see the module docstring); a failed build
    fails every test that needs it, with the build's output."""
    return _BUILD.wait()


def require_built_book() -> Path:
    """The HTML folder of :func:`session_book`."""
    return session_book().html


def _uses_the_book(item: pytest.Item) -> bool:
    module = getattr(item, "module", None)
    names = vars(module) if module is not None else {}
    return "session_book" in names or "require_built_book" in names


def _book_callers(module) -> set[str]:
    """Names of the module's functions that call :func:`session_book` or
    :func:`require_built_book`, directly or through one another (read from the source)."""
    sources = {}
    for name, obj in vars(module).items():
        if inspect.isfunction(obj) and obj.__module__ == module.__name__:
            try:
                sources[name] = inspect.getsource(obj)
            except (OSError, TypeError):
                pass
    callers = {"session_book", "require_built_book"}
    while True:
        more = {name for name, src in sources.items() if name not in callers
                and any(f"{c}(" in src for c in callers)}
        if not more:
            return callers
        callers |= more


def _needs_the_book(item: pytest.Item) -> bool:
    """Whether the test, or one of its fixtures, calls :func:`session_book` or
    :func:`require_built_book`, directly or through its module's helpers."""
    module = getattr(item, "module", None)
    if module is None:
        return False
    callers = _book_callers(module)
    funcs = [getattr(item, "function", None)]
    info = getattr(item, "_fixtureinfo", None)
    if info is not None:
        funcs += [fd.func for name in info.names_closure
                  for fd in info.name2fixturedefs.get(name, ())]
    for func in funcs:
        try:
            source = inspect.getsource(func)
        except (OSError, TypeError):
            continue
        if any(f"{c}(" in source for c in callers):
            return True
    return False


#: The full tier: the tests marked ``full`` (a full recomputation of a stored study, a long
#: run, a second execution of every chapter) run only with this option
#: (``python3 tasks.py test --full``, which CI's ``.ci/run`` runs); without it they are
#: skipped, each with :data:`FULL_SKIP_REASON`.  ``slow`` marks a test that is long but runs
#: in both tiers.
FULL_OPTION = "--full"
FULL_SKIP_REASON = "full tier: runs with python3 tasks.py test --full (and in CI)"
#: Set by ``python3 tasks.py test --full``: the session must run the full tier, and it must
#: find tests of it (a misspelt option or a lost marker fails the run instead of skipping the
#: full tier without a word).
REQUIRE_FULL_ENV = "GYROLIB_REQUIRE_FULL"


def pytest_addoption(parser) -> None:
    parser.addoption(FULL_OPTION, action="store_true", default=False,
                     help="also run the full tier (tests marked 'full': full recomputations "
                          "of the stored studies, long runs); python3 tasks.py test --full")


def full_tier(config) -> bool:
    """Whether this session runs the full tier (:data:`FULL_OPTION`)."""
    return bool(config.getoption(FULL_OPTION))


def select_tier(config, items: list) -> int:
    """Mark the full tier's tests skipped unless the session runs it; returns how many of
    ``items`` are of the full tier."""
    full = [item for item in items if item.get_closest_marker("full") is not None]
    if not full_tier(config):
        skip = pytest.mark.skip(reason=FULL_SKIP_REASON)
        for item in full:
            item.add_marker(skip)
    return len(full)


def check_required_tier(config) -> None:
    """Under :data:`REQUIRE_FULL_ENV`, a session without :data:`FULL_OPTION` is a usage
    error (raised before any test is collected)."""
    if os.environ.get(REQUIRE_FULL_ENV) == "1" and not full_tier(config):
        raise pytest.UsageError(f"{REQUIRE_FULL_ENV}=1 but pytest was run without "
                                f"{FULL_OPTION}: the full tier would be skipped")


#: Whether the session's book build prints the PDF: in the full tier only (its tests,
#: ``tests/book/test_pdf.py``, are of the full tier), since the print is a step of the
#: longest chain of the everyday run (set in :func:`pytest_configure`).
_PRINT_PDF = [True]

#: How many reports of tests of the full tier this process saw (the xdist controller sees
#: those of every worker).
_FULL_REPORTS = [0]


def pytest_runtest_logreport(report) -> None:
    if "full" in report.keywords and report.when == "call":
        _FULL_REPORTS[0] += 1


def full_tier_ran(config, reports: int) -> str:
    """The problem of a session that had to run the full tier (:data:`REQUIRE_FULL_ENV`) and
    ran none of its tests, or ``""``."""
    if os.environ.get(REQUIRE_FULL_ENV) == "1" and full_tier(config) and reports == 0:
        return (f"{FULL_OPTION}: no test of the full tier ran (tests marked 'full'): the "
                "full tier was not run")
    return ""


def pytest_collection_modifyitems(session: pytest.Session, config, items: list) -> None:
    """The full tier's tests are skipped unless the session runs it (:func:`select_tier`).
    The tests of the built book run last, in their collected order: the build runs in the
    background while all the other tests run, instead of the first browser test waiting for
    it while the second core idles."""
    select_tier(config, items)
    items.sort(key=lambda item: _uses_the_book(item) and _needs_the_book(item))


def pytest_collection_finish(session: pytest.Session) -> None:
    if os.environ.get(SHARED_ENV) and hasattr(session.config, "workerinput"):
        return  # an xdist worker: the controlling process builds (_XdistController)
    if any(_uses_the_book(item) for item in session.items):
        _BUILD.start()  # in the background while the other tests run


class _XdistController:
    """pytest-xdist hooks of the controlling process: it builds the book itself, in the
    background, as soon as a worker reports a collected test module that uses the book; the
    workers wait for its record (or, if they get the lock first, build it themselves)."""

    def pytest_xdist_node_collection_finished(self, node, ids) -> None:
        if _BUILD._thread is not None:
            return
        files = {nodeid.split("::")[0] for nodeid in ids}
        for name in sorted(files):
            path = ROOT / name
            if path.suffix == ".py" and path.is_file() and re.search(
                    r"\b(session_book|require_built_book)\b",
                    path.read_text(encoding="utf-8")) and path.name != "conftest.py":
                _BUILD.start()
                return


def _xdist_controller(config) -> bool:
    """Whether this process hands the tests to pytest-xdist workers (and runs none)."""
    return (not hasattr(config, "workerinput")
            and getattr(config.option, "dist", "no") != "no"
            and bool(getattr(config.option, "numprocesses", 0)))


#: The ledger's memo (``gyrolib.book.ledger.MEMO_ENV``): the tests' calls of ``collect()``
#: share one computation per session instead of computing the ledger (about 6.5 s of CPU)
#: in each of a dozen tests, processes and workers.  The book build keeps a memo of its own
#: (``_ext/gyrolib_cache.py`` sets the variable for its kernels), so the book's ledger and
#: the tests' stay two independent computations: the command line's JSON, read from the
#: build's memo, is compared with the session's (``tests/book/ledger/test_ledger.py``).
LEDGER_MEMO_ENV = "GYROLIB_LEDGER_MEMO"
#: A folder the session's processes share for results that more than one test computes the
#: same way in whichever worker it runs (``session_memo``; e.g. the independent reference of
#: paper GC's σ curve, about 30 CPU-s, read by two test files).
TEST_MEMO_ENV = "GYROLIB_TEST_MEMO"
#: The stored studies' check memo (``gyrolib.store.MEMO_ENV``): a folder of the session, so
#: that the checks of the stored studies (about 25 CPU-s each time: the ledger's chapter in
#: the session's book build, ``ledger --json``, the tests of the store) are computed once
#: per session and never read from, or written to, the user's cache.
CHECK_MEMO_ENV = "GYROLIB_CHECK_MEMO"


def session_memo(key: str, compute):
    """``compute()``'s numpy array, computed once per test session: the first process to take
    the key's file lock computes and stores it, the others wait and read it (without a
    session folder, as when a test module is imported on its own: computed here)."""
    import fcntl

    import numpy as np

    folder = os.environ.get(TEST_MEMO_ENV)
    if not folder or not Path(folder).is_dir():
        return compute()
    path = Path(folder) / f"{key}.npy"
    with open(path.with_suffix(".lock"), "a") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        try:
            if path.is_file():
                return np.load(path)
            value = np.asarray(compute())
            np.save(path, value)
            return value
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)


def pytest_configure(config) -> None:
    """Under pytest-xdist the workers share one build: its folder is made here, before the
    workers start (they inherit the environment variable), and removed at the end.  The
    ledger's memo for the session (:data:`LEDGER_MEMO_ENV`) is made here too.  A session
    that must run the full tier and was not given the option stops here
    (:func:`check_required_tier`)."""
    check_required_tier(config)
    _PRINT_PDF[0] = full_tier(config)
    if not hasattr(config, "workerinput") and not os.environ.get(LEDGER_MEMO_ENV):
        memo = tempfile.mkdtemp(prefix="gyrolib-test-ledger-")
        os.environ[LEDGER_MEMO_ENV] = memo          # the workers inherit it
        config.gyrolib_ledger_memo = Path(memo)
    if not hasattr(config, "workerinput") and not os.environ.get(TEST_MEMO_ENV):
        memo = tempfile.mkdtemp(prefix="gyrolib-test-memo-")
        os.environ[TEST_MEMO_ENV] = memo
        config.gyrolib_test_memo = Path(memo)
    if not hasattr(config, "workerinput") and not os.environ.get(CHECK_MEMO_ENV):
        memo = tempfile.mkdtemp(prefix="gyrolib-test-checks-")
        os.environ[CHECK_MEMO_ENV] = memo
        config.gyrolib_check_memo = Path(memo)
    _RUNS_TESTS[0] = not _xdist_controller(config)
    if _xdist_controller(config) and not os.environ.get("GYROLIB_REUSE_BOOK"):
        folder = tempfile.mkdtemp(prefix="gyrolib-test-book-")
        os.environ[SHARED_ENV] = folder
        config.gyrolib_book_folder = Path(folder)
        config.pluginmanager.register(_XdistController(), "gyrolib-xdist-controller")
        # the workers (started after this, inheriting it) run BLAS on one thread each: with
        # every core busy, OpenBLAS's threads only spin waiting for each other (a sample of
        # four numerical test files under -n 2: 47 s with them, 31 s without)
        os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    elif hasattr(config, "workerinput") and os.environ.get(SHARED_ENV) and hasattr(os, "nice"):
        # the workers yield the processor to the book build (the longest chain of the run,
        # started by the controlling process at normal priority) and use what it leaves
        os.nice(WORKER_NICENESS)


def pytest_unconfigure(config) -> None:
    for attr, env in (("gyrolib_ledger_memo", LEDGER_MEMO_ENV),
                      ("gyrolib_test_memo", TEST_MEMO_ENV),
                      ("gyrolib_check_memo", CHECK_MEMO_ENV)):
        memo = getattr(config, attr, None)
        if memo is not None:
            os.environ.pop(env, None)
            shutil.rmtree(memo, ignore_errors=True)
    folder = getattr(config, "gyrolib_book_folder", None)
    if folder is None:
        return
    if _BUILD._thread is not None:
        _BUILD._thread.join()  # the controller's build: the workers have all ended
    os.environ.pop(SHARED_ENV, None)
    if os.environ.get("GYROLIB_KEEP_BOOK") == "1" and (folder / "book.json").is_file():
        print(f"\nthe test session's book is kept in {folder}")
    else:
        shutil.rmtree(folder, ignore_errors=True)


def pytest_terminal_summary(terminalreporter, exitstatus: int, config) -> None:
    book = _BUILD.book
    folder = getattr(config, "gyrolib_book_folder", None)
    if book is None and folder is not None and (folder / "book.json").is_file():
        book, _ = _read_record(folder / "book.json")  # built by a worker
    if book is not None and book.seconds:
        steps = ", ".join(f"{name} {s:.0f} s" for name, s in book.seconds)
        terminalreporter.write_line(f"the session's book: {steps}")
        terminalreporter.write_line("chapters executed: " + ", ".join(
            f"{doc} {s:.1f} s" for doc, s in book.chapters))


#: ``GYROLIB_TEST_TIMELINE=FILE`` appends to ``FILE`` one JSON line per test (its worker's
#: pid, start and end, wall and CPU seconds: the worker's own and those of the child
#: processes it waited for, e.g. a command-line run) and one per book build step (CPU of the
#: step's processes, jupyter-book and its kernels): where the test command's core-seconds go
#: (``benchmarks/bench_test_command.py`` sets it).  The browser's CPU is not in any
#: test's: Chromium outlives the tests that drive it.
TIMELINE_ENV = "GYROLIB_TEST_TIMELINE"


def _self_cpu() -> float:
    import resource

    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def _children_cpu() -> float:
    import resource

    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def _timeline_write(record: dict) -> None:
    path = os.environ.get(TIMELINE_ENV)
    if path:
        with open(path, "a", encoding="utf-8") as f:   # one short line: an atomic append
            f.write(json.dumps(record) + "\n")


_TEST_START: dict[str, tuple[float, float, float]] = {}
#: Whether this process runs tests (not an xdist controller, which only reports them).
_RUNS_TESTS = [True]


def pytest_runtest_logstart(nodeid: str, location) -> None:
    if os.environ.get(TIMELINE_ENV) and _RUNS_TESTS[0]:
        _TEST_START[nodeid] = (time.time(), _self_cpu(), _children_cpu())


def pytest_runtest_logfinish(nodeid: str, location) -> None:
    if nodeid in _TEST_START:
        start, own, children = _TEST_START.pop(nodeid)
        end = time.time()
        _timeline_write({"test": nodeid, "pid": os.getpid(), "start": start, "end": end,
                         "wall": round(end - start, 3),
                         "cpu": round(_self_cpu() - own, 3),
                         "cpu_children": round(_children_cpu() - children, 3)})


def pytest_sessionfinish(session: pytest.Session, exitstatus: int) -> None:
    _BUILD.cleanup()
    config = session.config
    if not hasattr(config, "workerinput") and exitstatus == pytest.ExitCode.OK:
        problem = full_tier_ran(config, _FULL_REPORTS[0])
        if problem:  # the session's status: a usage error, with its line
            print(f"\nERROR: {problem}", file=sys.stderr, flush=True)
            session.exitstatus = pytest.ExitCode.USAGE_ERROR
