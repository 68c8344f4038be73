"""The chapters the cache lacks are executed on several cores before Sphinx reads them
(``_ext/parallel_execute.py``), and a failing chapter still fails the build.

Tiny books in the project's cache mode, with the extension and the project's build flags:

* two chapters whose one cell sleeps 3 s and prints when it started and ended: with
  ``GYROLIB_BUILD_JOBS=2`` the two intervals overlap; with ``1`` they do not (the check's
  power: it can tell parallel from serial execution);
* a chapter with a cell that raises: the build exits non-zero and shows the traceback, as
  without the extension (myst-nb executes the failed chapter again and reports it).
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest
import yaml

pytestmark = pytest.mark.book

ROOT = Path(__file__).resolve().parents[2]
JUPYTER_BOOK = Path(sys.executable).with_name("jupyter-book")
sys.path.insert(0, str(ROOT / "_ext"))

import parallel_execute  # noqa: E402

from tests.book.test_fails_loudly import FRONT_MATTER as FRONT  # noqa: E402

SLEEPER = FRONT + """
# Chapter {name}

```{{code-cell}} ipython3
import time
t0 = time.time()
time.sleep(3)
print("SPAN", t0, time.time())  # chapter {name}: the chapters' code differs
```
"""

FAILING = FRONT + """
# Chapter bad

```{code-cell} ipython3
def tiny_parallel_fail():
    return 1 / 0


tiny_parallel_fail()
```
"""


def _book(folder: Path, chapters: dict[str, str]) -> Path:
    folder.mkdir(parents=True)
    for name, text in chapters.items():
        (folder / f"{name}.md").write_text(text, encoding="utf-8")
    names = list(chapters)
    (folder / "_toc.yml").write_text(yaml.safe_dump(
        {"format": "jb-book", "root": names[0],
         "chapters": [{"file": n} for n in names[1:]]}), encoding="utf-8")
    project = yaml.safe_load((ROOT / "_config.yml").read_text(encoding="utf-8"))
    config = {
        "title": "Tiny parallel book", "author": "gyrolib tests",
        "only_build_toc_files": True, "exclude_patterns": ["_build"],
        "execute": {**project["execute"], "cache": str(folder / "_build" / ".jupyter_cache")},
        "html": {"use_download_button": False},
        "sphinx": {"local_extensions": {"parallel_execute": str(ROOT / "_ext")},
                   "config": {"nitpicky": True}},
    }
    (folder / "_config.yml").write_text(yaml.safe_dump(config), encoding="utf-8")
    return folder


def _build(folder: Path, jobs: int) -> subprocess.CompletedProcess:
    env = dict(os.environ, GYROLIB_BUILD_JOBS=str(jobs), MPLBACKEND="Agg", NO_COLOR="1")
    return subprocess.run([str(JUPYTER_BOOK), "build", str(folder), "-W", "-n",
                           "--keep-going"], capture_output=True, text=True, env=env,
                          timeout=300, check=False)


def _spans(folder: Path) -> list[tuple[float, float]]:
    """The chapters' printed (start, end) times, read from the built pages."""
    spans = []
    for page in sorted((folder / "_build" / "html").glob("*.html")):
        spans += [(float(a), float(b)) for a, b in
                  re.findall(r"SPAN ([\d.]+) ([\d.]+)", page.read_text(encoding="utf-8"))]
    return spans


@pytest.fixture(scope="module")
def builds(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("parallel")
    sleepers = {"a": SLEEPER.format(name="a"), "b": SLEEPER.format(name="b")}
    cases = {"two": (_book(tmp / "two", sleepers), 2),
             "one": (_book(tmp / "one", sleepers), 1),
             "bad": (_book(tmp / "bad", {"a": SLEEPER.format(name="a"), "bad": FAILING}), 2)}
    with ThreadPoolExecutor(max_workers=len(cases)) as pool:
        futures = {k: pool.submit(_build, folder, jobs) for k, (folder, jobs) in cases.items()}
        return {k: (cases[k][0], f.result()) for k, f in futures.items()}


def _overlap(spans: list[tuple[float, float]]) -> float:
    (a0, a1), (b0, b1) = spans
    return min(a1, b1) - max(a0, b0)


def test_two_jobs_execute_two_chapters_at_once(builds):
    folder, run = builds["two"]
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    assert "executing 2 notebooks, 2 at a time" in run.stdout, run.stdout[-3000:]
    spans = _spans(folder)
    assert len(spans) == 2, spans
    assert _overlap(spans) > 1.0, spans  # each sleeps 3 s: together, they overlap by ~3 s


def test_the_downloadable_notebooks_hold_the_outputs(builds):
    """Every chapter is a cache hit after the parallel execution; the executed notebooks
    written for download must still hold their outputs (myst-nb alone writes them empty on a
    cache hit: this assertion failed before ``_merge_into_the_read_notebook``)."""
    folder, _ = builds["two"]
    for name in ("a", "b"):
        nb = json.loads((folder / "_build" / "jupyter_execute" / f"{name}.ipynb")
                        .read_text(encoding="utf-8"))
        outputs = [o for c in nb["cells"] if c["cell_type"] == "code" for o in c["outputs"]]
        text = "".join("".join(o.get("text", "")) for o in outputs)
        assert re.search(r"SPAN [\d.]+ [\d.]+", text), (name, outputs)


def test_one_job_executes_one_chapter_at_a_time(builds):
    folder, run = builds["one"]
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    spans = _spans(folder)
    assert len(spans) == 2, spans
    assert _overlap(spans) < 0, spans


def test_a_failing_chapter_still_fails_the_build_with_its_traceback(builds):
    _, run = builds["bad"]
    out = run.stdout + run.stderr
    assert run.returncode != 0, out[-3000:]
    assert "tiny_parallel_fail" in out and "ZeroDivisionError" in out, out[-3000:]


@pytest.mark.parametrize("raw", ["0", "two", "-1", "1.5"])
def test_a_bad_jobs_variable_is_refused_naming_it(monkeypatch, raw):
    from sphinx.errors import ConfigError

    monkeypatch.setenv("GYROLIB_BUILD_JOBS", raw)
    with pytest.raises(ConfigError, match=f"GYROLIB_BUILD_JOBS .*{re.escape(repr(raw))}"):
        parallel_execute.build_jobs()


def test_jobs_default_to_the_usable_cores(monkeypatch):
    monkeypatch.delenv("GYROLIB_BUILD_JOBS", raising=False)
    assert parallel_execute.build_jobs() == len(os.sched_getaffinity(0))
    monkeypatch.setenv("GYROLIB_BUILD_JOBS", "3")
    assert parallel_execute.build_jobs() == 3


def test_longest_first_reads_the_measured_chapter_times(tmp_path):
    seconds = parallel_execute.measured_seconds(ROOT)
    doc = json.loads((ROOT / parallel_execute.TIMES_FILE).read_text(encoding="utf-8"))
    rows = [r for r in doc["results"] if r["case"].startswith("execution of chapters/")]
    assert len(seconds) == len(rows) > 0
    for r in rows:
        name = r["case"].removeprefix("execution of ").removesuffix(" in the clean build")
        assert seconds[name] == pytest.approx(r["ours_s"], rel=1e-12)
    assert parallel_execute.measured_seconds(tmp_path) == {}  # no file: no times
