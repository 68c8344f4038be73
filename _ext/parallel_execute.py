"""Sphinx extension: execute the chapters the jupyter cache lacks on every core, before Sphinx
reads them.

myst-nb executes a notebook when Sphinx reads it, one document after the other, and
jupyter-book 1.x's ``build`` command offers no ``-j`` (Sphinx's parallel read would split the
documents into fixed alphabetical halves, with calibrate and gc_claims, the two longest
chapters, in the same half).  So on ``env-before-read-docs`` this extension

1. reads each document about to be read with myst-nb's own notebook reader (the same
   notebook, hence the same cache key, as myst-nb's parser makes of it), and keeps those whose
   code is not in the jupyter cache;
2. executes them concurrently, a ``concurrent.futures.ThreadPoolExecutor`` of ``jobs``
   workers each driving one kernel process through jupyter-cache's ``single_nb_execution``
   (the call myst-nb makes, so ``_ext/gyrolib_cache.py``'s IOPub guard applies), longest
   chapter first;
3. stores each executed notebook in the cache as myst-nb's cache client does (in this, the
   main, thread: the cache's database is never touched from two threads).

myst-nb then finds every chapter in the cache.  A chapter that fails is not stored: myst-nb
executes it again as it reads it and reports the error with its traceback, exactly as without
this extension, so a failing cell still fails the build loudly.

One fix of myst-nb comes with it, since with this extension every chapter is a cache hit:
myst-nb 1.x writes the downloadable executed notebook (``_build/jupyter_execute/*.ipynb``)
from the notebook object it read, and on a cache hit it merges the cached outputs into a
*copy* (``NotebookClientCache.start_client``), so the download had no outputs at all.
:func:`_merge_into_the_read_notebook` makes the merge land in the object that is written.

``jobs`` is the environment variable ``GYROLIB_BUILD_JOBS`` (a whole number at least 1), by
default the number of cores this process may use.  ``GYROLIB_BUILD_JOBS=1`` executes one
chapter at a time (the least memory: one kernel).  "Longest first" uses the execution times of
the last measured clean build, ``benchmarks/results/book_build.json``; a chapter not listed
there counts by the length of its code.  The order changes only the wall time, never a result:
each chapter runs in its own kernel, with its own seeds.
"""

from __future__ import annotations

import json
import os
import re
import time
from concurrent.futures import ThreadPoolExecutor, as_completed
from pathlib import Path, PurePosixPath

from sphinx.errors import ConfigError
from sphinx.util import logging

logger = logging.getLogger(__name__)

JOBS_ENV = "GYROLIB_BUILD_JOBS"
TIMES_FILE = Path("benchmarks") / "results" / "book_build.json"


def build_jobs() -> int:
    """How many chapters execute at once: ``$GYROLIB_BUILD_JOBS`` or the usable cores."""
    raw = os.environ.get(JOBS_ENV, "").strip()
    if not raw:
        try:
            return max(1, len(os.sched_getaffinity(0)))
        except AttributeError:  # not on Linux
            return max(1, os.cpu_count() or 1)
    try:
        jobs = int(raw)
    except ValueError:
        jobs = 0
    if jobs < 1:
        raise ConfigError(f"{JOBS_ENV} must be a whole number at least 1, not {raw!r}")
    return jobs


def measured_seconds(root: Path) -> dict[str, float]:
    """Each chapter's execution time in the last measured clean build (docname -> s), from
    ``benchmarks/results/book_build.json``; empty when the file is missing or unreadable."""
    try:
        doc = json.loads((root / TIMES_FILE).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
    out = {}
    prefix, suffix = "execution of ", " in the clean build"
    for row in doc.get("results", []):
        case = str(row.get("case", ""))
        if case.startswith(prefix) and case.endswith(suffix):
            try:
                out[case[len(prefix):-len(suffix)]] = float(row["ours_s"])
            except (KeyError, TypeError, ValueError):
                continue
    return out


def _pending(env, docnames):
    """The documents to read whose notebook is not in the cache, as
    ``(docname, path, notebook, read_fmt, nb_config)``."""
    from jupyter_cache import get_cache
    from myst_nb.core.nb_to_tokens import nb_node_to_dict
    from myst_nb.core.read import create_nb_reader

    nb_config = env.mystnb_config
    cache = get_cache(nb_config.execution_cache_path or ".jupyter_cache")
    out = []
    for docname in docnames:
        path = Path(env.doc2path(docname))
        if not path.is_file():
            continue
        text = path.read_text(encoding="utf-8")
        reader = create_nb_reader(str(path), env.myst_config, nb_config, text)
        if reader is None:
            continue
        nb = reader.read(text)
        if not any(cell.cell_type == "code" for cell in nb.cells):
            continue
        posix = PurePosixPath(path.as_posix())
        if any(posix.match(p) for p in nb_config.execution_excludepatterns):
            continue
        # as myst_nb.sphinx_.Parser.parse: kernel aliases, then per-notebook settings
        kernel = nb.metadata.get("kernelspec", {}).get("name")
        for rgx, alias in (nb_config.kernel_rgx_aliases or {}).items():
            if kernel is not None and re.fullmatch(rgx, kernel):
                nb.metadata["kernelspec"]["name"] = alias
                break
        config = nb_config
        if nb_config.metadata_key in nb.metadata:
            overrides = nb_node_to_dict(nb.metadata[nb_config.metadata_key])
            overrides.pop("output_folder", None)
            try:
                config = nb_config.copy(**overrides)
            except Exception:  # myst-nb warns about it when it reads the file
                continue
        try:
            cache.match_cache_notebook(nb)
            continue  # already executed
        except KeyError:
            pass
        out.append((docname, path, nb, reader.read_fmt, config))
    return cache, out


def _run(nb, path: Path, config):
    """Execute one notebook in place (in a worker thread); ``(result, exception)``."""
    from tempfile import TemporaryDirectory

    from jupyter_cache.executors.utils import single_nb_execution

    try:
        if config.execution_in_temp:
            with TemporaryDirectory() as cwd:
                result = single_nb_execution(nb, cwd=cwd, timeout=config.execution_timeout,
                                             allow_errors=config.execution_allow_errors,
                                             meta_override=True)
        else:
            result = single_nb_execution(nb, cwd=str(path.parent),
                                         timeout=config.execution_timeout,
                                         allow_errors=config.execution_allow_errors,
                                         meta_override=True)
        return result, None
    except Exception as exc:  # myst-nb executes it again and reports it
        return None, exc


def execute_pending(app, env, docnames) -> None:
    if env.mystnb_config.execution_mode != "cache":
        return
    cache, todo = _pending(env, docnames)
    if not todo:
        return
    from jupyter_cache.base import CacheBundleIn

    root = Path(app.srcdir)
    seconds = measured_seconds(root)

    def expected(item) -> float:
        docname, _, nb = item[:3]
        if docname in seconds:
            return seconds[docname]
        # unmeasured: before every measured one, longest code first
        return 1e6 + sum(len(c.source) for c in nb.cells if c.cell_type == "code")

    todo.sort(key=expected, reverse=True)
    jobs = min(build_jobs(), len(todo))
    logger.info(f"[parallel_execute] executing {len(todo)} notebooks, {jobs} at a time")
    t0 = time.perf_counter()
    with ThreadPoolExecutor(max_workers=jobs, thread_name_prefix="gyrolib-execute") as pool:
        futures = {pool.submit(_run, nb, path, config): (docname, path, nb, read_fmt)
                   for docname, path, nb, read_fmt, config in todo}
        for future in as_completed(futures):
            docname, path, nb, read_fmt = futures[future]
            result, exc = future.result()
            if exc is not None or result.err is not None:
                # myst-nb executes it again when it reads it and reports the error
                logger.info(f"[parallel_execute] {docname} failed; myst-nb will execute it "
                            "again and report the error")
                continue
            if read_fmt is not None:
                stage = cache.add_nb_to_project(str(path), read_data=read_fmt)
            else:
                stage = cache.add_nb_to_project(str(path))
            cache.cache_notebook_bundle(
                CacheBundleIn(nb, stage.uri, data={"execution_seconds": result.time}),
                check_validity=False, overwrite=True)
            logger.info(f"Executed notebook in {result.time:.2f} seconds",
                        location=docname)
    logger.info(f"[parallel_execute] {len(todo)} notebooks in "
                f"{time.perf_counter() - t0:.1f} s of wall time")


def _merge_into_the_read_notebook(app, config) -> None:
    """On a cache hit, put the cached outputs into the notebook object myst-nb's parser
    writes to ``jupyter_execute`` (see the module docstring)."""
    from myst_nb.core.execute.cache import NotebookClientCache

    inner = NotebookClientCache.start_client
    if getattr(inner, "gyrolib_merge_in_place", False):
        return

    def start_client(self):
        read = self._notebook
        inner(self)
        if self._notebook is not read:  # the cache's outputs, merged into a copy
            read.clear()
            read.update(self._notebook)
            self._notebook = read

    start_client.gyrolib_merge_in_place = True
    NotebookClientCache.start_client = start_client


def setup(app):
    # validate the variable at once, not after minutes of reading
    app.connect("config-inited", lambda app, config: build_jobs())
    app.connect("config-inited", _merge_into_the_read_notebook)
    app.connect("env-before-read-docs", execute_pending)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1"}
