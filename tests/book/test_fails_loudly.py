"""The book build fails loudly, and glued numbers reach the page.

Each case builds a tiny Jupyter Book in a temporary folder with the project's own execute,
parse and Sphinx settings (read from ``_config.yml``; only the execution mode is forced to
``force``, so no cache is involved) and the project's build flags ``-W -n --keep-going``:

* the good book (a glued string, a glued float with a format spec, a labelled equation, a
  cross-reference, a citation) builds with exit 0 and its prose shows the glued numbers;
* the same book plus a defect exits non-zero and names it: a cell that raises (its
  traceback); a reference to a missing label and a citation of a missing key, both in one
  build (each gives its own WARNING line, and under ``-W`` any one WARNING fails the build:
  the good book shows that the book without them has none).  The cell error gets a build of
  its own: it stops the build before references are resolved.

The three builds run concurrently to keep the file fast.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import pytest
import yaml

pytestmark = pytest.mark.book

ROOT = Path(__file__).resolve().parents[2]
JUPYTER_BOOK = Path(sys.executable).parent / ("jupyter-book" + (".exe" if os.name == "nt" else ""))
BUILD_FLAGS = ["-W", "-n", "--keep-going"]  # as in tasks.py: warnings and broken refs fail
TIMEOUT_S = 300

FRONT_MATTER = """\
---
jupytext:
  text_representation:
    extension: .md
    format_name: myst
    format_version: 0.13
kernelspec:
  display_name: Python 3
  language: python
  name: python3
---
"""

GOOD_CHAPTER = FRONT_MATTER + """
(tiny-chapter)=
# A tiny chapter

The ratio is {glue:text}`tiny_ratio` and pi is {glue:text}`tiny_pi:.3f` (see {eq}`tiny-eq`,
{ref}`tiny-chapter` and {cite:p}`tiny2020`).

$$
a = \\frac{2}{3}
$$ (tiny-eq)

```{code-cell} ipython3
from myst_nb import glue

glue("tiny_ratio", f"{2 / 3:.4f}", display=False)
glue("tiny_pi", float(3.14159265), display=False)
```

DEFECT_HERE

```{bibliography}
```
"""

BIB = """\
@book{tiny2020,
  author = {Ada Tester},
  title = {A Tiny Reference},
  publisher = {Nowhere Press},
  year = {2020},
}
"""

DEFECTS = {
    "good": "",
    "cell_error": ("```{code-cell} ipython3\ndef tiny_fail_here():\n    return 1 / 0\n\n\n"
                   "tiny_fail_here()\n```"),
    "broken_ref_and_cite": ("A reference to {ref}`tiny-no-such-label`.\n\n"
                            "A citation of {cite:p}`NoSuchKey2099`."),
}


@dataclass(frozen=True)
class Build:
    returncode: int
    output: str
    html: Path


def _tiny_config() -> dict:
    """The project's _config.yml settings that decide failure, on a one-chapter book."""
    project = yaml.safe_load((ROOT / "_config.yml").read_text(encoding="utf-8"))
    execute = dict(project.get("execute") or {})
    execute.pop("cache", None)
    execute["execute_notebooks"] = "force"
    sphinx = project.get("sphinx") or {}
    return {
        "title": "Tiny book",
        "author": "gyrolib tests",
        "only_build_toc_files": True,
        "exclude_patterns": ["_build"],
        "execute": execute,
        "parse": project.get("parse") or {},
        "bibtex_bibfiles": ["references.bib"],
        "html": {"use_download_button": False},
        # The project's Sphinx settings (nitpicky, numfig, bibtex style, …); the project's
        # local extensions (the cache guard) are irrelevant without a cache.
        "sphinx": {"extra_extensions": list(sphinx.get("extra_extensions") or []),
                   "config": dict(sphinx.get("config") or {})},
    }


def _build(folder: Path, defect: str) -> Build:
    folder.mkdir(parents=True)
    (folder / "_config.yml").write_text(yaml.safe_dump(_tiny_config(), sort_keys=False))
    (folder / "_toc.yml").write_text("format: jb-book\nroot: intro\nchapters:\n"
                                     "  - file: chapter\n")
    (folder / "intro.md").write_text("# Tiny book\n\nA book with one chapter.\n")
    (folder / "chapter.md").write_text(GOOD_CHAPTER.replace("DEFECT_HERE", defect))
    (folder / "references.bib").write_text(BIB)
    env = dict(os.environ, MPLBACKEND="Agg", PYDEVD_DISABLE_FILE_VALIDATION="1",
               NO_COLOR="1")
    try:
        proc = subprocess.run(
            [str(JUPYTER_BOOK), "build", str(folder), "--builder", "html", *BUILD_FLAGS],
            cwd=folder, env=env, capture_output=True, text=True, timeout=TIMEOUT_S,
            check=False)
    except subprocess.TimeoutExpired as exc:
        pytest.fail(f"tiny book build in {folder} took more than {TIMEOUT_S} s: {exc}")
    output = re.sub(r"\x1b\[[0-9;]*m", "", proc.stdout + proc.stderr)  # drop ANSI colours
    return Build(proc.returncode, output, folder / "_build" / "html")


@pytest.fixture(scope="module")
def builds(tmp_path_factory) -> dict[str, Build]:
    if not JUPYTER_BOOK.is_file():
        pytest.skip(f"no {JUPYTER_BOOK}: run the tests with the project's .venv python")
    base = tmp_path_factory.mktemp("tiny-books")
    with ThreadPoolExecutor(max_workers=len(DEFECTS)) as pool:
        futures = {name: pool.submit(_build, base / name, defect)
                   for name, defect in DEFECTS.items()}
        return {name: f.result() for name, f in futures.items()}


def _tail(build: Build, n: int = 3000) -> str:
    return build.output[-n:]


def _warning_with(build: Build, *words: str) -> bool:
    """Whether one WARNING line of the build output contains all the words."""
    return any("WARNING" in line and all(w in line for w in words)
               for line in build.output.splitlines())


def test_project_config_makes_failures_loud():
    """The settings the tiny books copy are the loud ones (so the cases below prove it)."""
    execute = yaml.safe_load((ROOT / "_config.yml").read_text(encoding="utf-8"))["execute"]
    assert execute.get("raise_on_error") is True, execute
    assert execute.get("allow_errors") is False, execute
    tasks = (ROOT / "tasks.py").read_text(encoding="utf-8")
    assert re.search(r'"-W",\s*"-n",\s*"--keep-going"', tasks), \
        "tasks.py no longer builds the book with -W -n --keep-going"


def test_good_book_builds_and_shows_glued_numbers(builds):
    good = builds["good"]
    assert good.returncode == 0, f"the good tiny book failed:\n{_tail(good)}"
    assert "WARNING:" not in good.output, _tail(good)    # Sphinx's, not the kernel's "WARNING |"
    bs4 = pytest.importorskip("bs4")
    soup = bs4.BeautifulSoup((good.html / "chapter.html").read_text(encoding="utf-8"),
                             "html.parser")
    prose = next((p.get_text(" ", strip=True) for p in soup.find_all("p")
                  if "The ratio is" in p.get_text()), None)
    assert prose is not None, "the paragraph with the glued numbers is not in chapter.html"
    # 2/3 glued as the string "0.6667"; pi glued as a float and formatted by the role (.3f).
    assert "The ratio is 0.6667 and pi is 3.142" in " ".join(prose.split()), prose
    assert (good.html / "_static" / "mathjax" / "tex-chtml.js").is_file(), \
        "MathJax was not copied into the tiny book (sphinx-mathjax-offline)"


def test_failing_cell_fails_the_build_with_its_traceback(builds):
    bad = builds["cell_error"]
    assert bad.returncode != 0, f"a cell raising ZeroDivisionError built fine:\n{_tail(bad)}"
    assert "ZeroDivisionError: division by zero" in bad.output, _tail(bad)
    # The cell's traceback is printed: it points into the function at the failing line.
    assert "Traceback" in bad.output, _tail(bad)
    assert re.search(r"in tiny_fail_here\(\)\s*\n(.*\n)*?-+> 2\s+return 1 / 0", bad.output), \
        _tail(bad)


def test_broken_cross_reference_fails_the_build(builds):
    bad = builds["broken_ref_and_cite"]
    assert bad.returncode != 0, f"a broken cross-reference built fine:\n{_tail(bad)}"
    assert _warning_with(bad, "undefined label", "tiny-no-such-label"), _tail(bad)


def test_missing_citation_fails_the_build(builds):
    bad = builds["broken_ref_and_cite"]
    assert bad.returncode != 0, f"a citation of a missing key built fine:\n{_tail(bad)}"
    assert _warning_with(bad, "could not find bibtex key", "NoSuchKey2099"), _tail(bad)
