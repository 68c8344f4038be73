"""Sphinx extension: never serve stale chapter results from the jupyter cache.

jupyter-cache keys a notebook on its own code cells only.  Every chapter imports
``gyrolib``, so a change in the library (or in the pinned environment) must re-execute all
chapters.  On ``config-inited`` this extension hashes ``gyrolib/**/*.py``, the
committed ``data/`` the chapters read (records, the sensitivity studies) and
``requirements.txt``; when the hash differs from the one stored beside the cache, the cache is
deleted before myst-nb opens it, and every document is marked outdated, so that Sphinx
re-reads (and myst-nb re-executes) chapters whose own source did not change.

It also sets the environment the chapters' kernels inherit (:func:`_kernel_env`):

* ``GYROLIB_LEDGER_MEMO``, a folder inside the cache: the chapters that show the ledger
  (intro, ledger, citing, errata) and the ledger files written after the build share one
  computation of ``gyrolib.book.ledger.collect()`` (keyed by gyrolib's sources, and wiped
  with the cache);
* ``OPENBLAS_NUM_THREADS=1`` unless set: the chapters' linear algebra is on matrices of at
  most a few dozen rows, where OpenBLAS's threads only wait for each other (three times
  slower on a loaded 2-core machine); parallel work goes through ``executor=`` instead.

And it makes a lost output fail the build (:func:`_no_lost_outputs`).  nbclient waits only
``iopub_timeout`` = 4 s, after a cell's reply, for the cell's last outputs; on a loaded machine
a print at the end of a long cell can arrive later, and nbclient then only logs a warning and
the page silently misses that output.  Here the wait is 120 s and a timeout is an error.
"""

from __future__ import annotations

import hashlib
import os
import shutil
from pathlib import Path

STAMP = "gyrolib.sha256"


def _bytecode(path: Path) -> bool:
    """Python's compiled cache (``__pycache__``, ``.pyc``): written by whatever imports a
    script of ``data/`` (a test of ``data/make_records.py`` does, while the test session
    builds the book), never read by a chapter.  Counted, it changed the fingerprint between
    the session's two builds, and the HTML build executed every chapter again (263 CPU-s;
    issue 36's timeline found it)."""
    return "__pycache__" in path.parts or path.suffix in (".pyc", ".pyo")


def library_fingerprint(root: Path) -> str:
    """SHA-256 over the library sources, the committed data the chapters read and the pinned
    requirements, in a fixed order (Python's bytecode caches left out)."""
    h = hashlib.sha256()
    files = sorted((root / "gyrolib").rglob("*.py"))
    files += sorted(p for p in (root / "data").rglob("*")   # read by chapters
                    if p.is_file() and not _bytecode(p.relative_to(root)))
    files += [root / "requirements.txt"]
    for path in files:
        if path.is_file():
            h.update(path.relative_to(root).as_posix().encode())
            h.update(b"\0")
            h.update(path.read_bytes())
            h.update(b"\0")
    return h.hexdigest()


def _invalidate(app, config) -> None:
    cache = getattr(config, "nb_execution_cache_path", "") or ""
    if not cache:
        return
    root = Path(app.srcdir)
    cache_dir = Path(cache)
    if not cache_dir.is_absolute():
        cache_dir = root / cache_dir
    fingerprint = library_fingerprint(root)
    stamp = cache_dir / STAMP
    if stamp.is_file() and stamp.read_text().strip() == fingerprint:
        app.gyrolib_changed = False
        return
    app.gyrolib_changed = True
    if cache_dir.exists():
        shutil.rmtree(cache_dir)
        print(f"[gyrolib_cache] gyrolib or requirements changed: cleared {cache_dir}")
    cache_dir.mkdir(parents=True, exist_ok=True)
    stamp.write_text(fingerprint + "\n")


def _cache_dir(app, config) -> Path | None:
    cache = getattr(config, "nb_execution_cache_path", "") or ""
    if not cache:
        return None
    cache_dir = Path(cache)
    return cache_dir if cache_dir.is_absolute() else Path(app.srcdir) / cache_dir


def _kernel_env(app, config) -> None:
    """Environment of the kernels myst-nb starts (they inherit this process's)."""
    cache_dir = _cache_dir(app, config)
    if cache_dir is not None:
        os.environ["GYROLIB_LEDGER_MEMO"] = str(cache_dir / "ledger")
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


IOPUB_TIMEOUT_S = 120


def _no_lost_outputs(app, config) -> None:
    """Execute chapters with a long IOPub wait and an error, not a warning, when it runs out.

    myst-nb executes through ``jupyter_cache.executors.utils.single_nb_execution``, which
    calls the module's ``executenb`` (``nbclient.execute``) with no way to pass nbclient's
    ``iopub_timeout`` / ``raise_on_iopub_timeout``; the module's ``executenb`` is wrapped to
    add them.
    """
    from jupyter_cache.executors import utils

    inner = utils.executenb
    if getattr(inner, "gyrolib_no_lost_outputs", False):
        return

    def executenb(nb, **kwargs):
        kwargs.setdefault("iopub_timeout", IOPUB_TIMEOUT_S)
        kwargs.setdefault("raise_on_iopub_timeout", True)
        return inner(nb, **kwargs)

    executenb.gyrolib_no_lost_outputs = True
    utils.executenb = executenb


def _outdated(app, env, added, changed, removed):
    """After a library change every document is stale, not only the edited ones."""
    if getattr(app, "gyrolib_changed", False):
        return sorted(env.found_docs - set(added) - set(changed) - set(removed))
    return []


def setup(app):
    # Priority < 500 so that this runs before myst-nb reads the cache.
    app.connect("config-inited", _invalidate, priority=100)
    app.connect("config-inited", _kernel_env, priority=101)
    app.connect("config-inited", _no_lost_outputs, priority=102)
    app.connect("env-get-outdated", _outdated)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1"}
