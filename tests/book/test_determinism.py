"""Two executions of the chapters give the same numbers.

The test session's book (``conftest.session_book``) executed every chapter into a fresh
jupyter cache.  Each chapter's outputs — every printed text, **every glued value** (the
numbers the prose shows; myst-nb leaves them out of ``jupyter_execute``, so they are read
from the session's jupyter cache), table and figure description, cell by cell — are
compared with a second, independent execution of the same code, the first of:

1. the **recorded outputs** committed in ``tests/recorded_outputs/<chapter>.json``: the
   chapter's outputs from a session build made at another time, usually on another
   machine (a cross-machine determinism check), recorded only after a second execution had
   agreed with it;
2. the project's own jupyter cache (``_build/.jupyter_cache``, filled by
   ``python3 tasks.py book`` in another process), when it holds this chapter's code and was
   made with the same gyrolib sources and pinned environment (its stamp from
   ``_ext/gyrolib_cache.py``);
3. otherwise — a chapter without a record, or whose record differs from this session's
   outputs — the everyday tier names it in a warning and leaves it to the full tier
   (``python3 tasks.py test --full``, CI), which executes **every** chapter again here (two
   kernels at a time) and compares it with the session's outputs, whatever its record says.

A chapter whose outputs agree with its record needs no third execution: two executions, the
recorded one and this session's, agree.  A chapter that differs from its record is not yet
a failure (its code or gyrolib may have changed the numbers on purpose): the full tier
executes it again, and fails if that execution differs from the session's; if it agrees, the
record is *stale* — the test passes, warns, and names the chapters.
``GYROLIB_RECORD_OUTPUTS=1`` executes the stale or missing chapters again in either tier and
writes their agreed outputs into ``tests/recorded_outputs/`` (and removes the records of
chapters that no longer exist), e.g. after a change of numbers, on a kept build::

    GYROLIB_KEEP_BOOK=1 .venv/bin/python -m pytest tests/book/test_determinism.py
    GYROLIB_REUSE_BOOK=/tmp/gyrolib-test-book-…/_build GYROLIB_RECORD_OUTPUTS=1 \\
        .venv/bin/python -m pytest tests/book/test_determinism.py

Random runs take explicit seeds, so the texts must agree.  Numbers are compared as numbers:
decimal numbers equal, or apart by at most one unit in the last printed digit (a value on a
rounding boundary may print either way when the last bit of a sum depends on the order of the
terms); integers and everything else character for character.  Images are not compared
(their bytes depend on the renderer); their text form (``<Figure size …>``) is.  The
project's folder is written ``<ROOT>`` (a record made in another clone still applies).
Power: :func:`test_a_nondeterministic_cell_is_caught` executes a chapter-like notebook whose
printed and glued values are not seeded and checks that the same path fails it.
"""

from __future__ import annotations

import importlib.util
import json
import os
import re
import warnings
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

import pytest

import gyrolib
from tests.conftest import ROOT, session_book

pytestmark = pytest.mark.book

PROJECT_CACHE = ROOT / "_build" / ".jupyter_cache"
#: the committed record of every chapter's outputs (one file per chapter)
RECORDED = ROOT / "tests" / "recorded_outputs"
RECORD_ENV = "GYROLIB_RECORD_OUTPUTS"
TEXT_MIMES = ("text/plain", "text/markdown", "text/html", "text/latex")
#: myst-nb's glue (scrapbook) stores a glued value's mime bundle under this prefix
GLUE_PREFIX = "application/papermill.record/"
ADDRESS = re.compile(r"\b0x[0-9a-fA-F]{6,}\b")
NUMBER = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")


# ----------------------------------------------------------------------------- comparison


def output_texts(nb) -> list[list[str]]:
    """Per code cell, the text of each output: streams, the text forms of results, and each
    glued value as ``glue <key> <mime>: <text>`` (myst-nb's glue outputs, found in an
    executed notebook and in the jupyter cache, not in ``jupyter_execute``).  The project's
    folder is written ``<ROOT>``."""
    cells = []
    for cell in nb.cells:
        if cell.cell_type != "code":
            continue
        texts: list[str] = []
        streams: dict[str, int] = {}  # all of a cell's stdout is one text (nb_merge_streams)
        for out in cell.get("outputs", []):
            if out.get("output_type") == "stream":
                text = out.get("text", "")
                text = text if isinstance(text, str) else "".join(text)
                name = out.get("name")
                if name in streams:
                    texts[streams[name]] += text
                else:
                    streams[name] = len(texts)
                    texts.append(f"{name}: {text}")
                continue
            if out.get("output_type") in ("display_data", "execute_result"):
                data = out.get("data", {})
                texts += [f"{m}: {data[m]}" for m in TEXT_MIMES if m in data]
                glued = (out.get("metadata") or {}).get("scrapbook", {}).get("name")
                if glued:
                    texts += [f"glue {glued} {m}: {data[GLUE_PREFIX + m]}" for m in TEXT_MIMES
                              if GLUE_PREFIX + m in data]
            elif out.get("output_type") == "error":
                texts.append(f"error: {out.get('ename')}: {out.get('evalue')}")
        # trailing blank lines: myst-nb's stream merging drops them, a kernel sends them
        cells.append([_version_free(ADDRESS.sub("0x…", t).replace(str(ROOT), "<ROOT>"))
                      .rstrip() for t in texts])
    return cells


#: gyrolib's version as the chapters print it (``0.5.0``, and ``0_5_0`` in a BibTeX key)
_VERSION = re.compile(r"(?<![\d.])({})(?!\.?\d)|(?<!\d)({})(?!_?\d)".format(
    *(re.escape(gyrolib.__version__.replace(".", sep)) for sep in "._")))


def _version_free(text: str) -> str:
    """``text`` with gyrolib's version written ``<VERSION>``: a release changes it, not a
    computation, so a record stays valid across releases (a version was compared as a
    number: 0.4.0 and 0.5.0 agreed within one unit of the last digit, 0.3.0 did not)."""
    return _VERSION.sub("<VERSION>", text)


def _last_digit_unit(token: str) -> float:
    """One unit in the last printed digit of a formatted float; 0 for an integer (a count
    must be equal)."""
    if not any(c in token for c in ".eE"):
        return 0.0
    mantissa, _, exponent = token.lower().partition("e")
    decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
    return 10.0 ** (int(exponent or 0) - decimals)


def same_text(a: str, b: str) -> bool:
    """``a`` and ``b`` agree: the same text around the numbers, and each pair of numbers
    equal or apart by at most one unit in the last printed digit."""
    if a == b:
        return True
    if NUMBER.split(a) != NUMBER.split(b):
        return False
    for x, y in zip(NUMBER.findall(a), NUMBER.findall(b), strict=True):
        if x != y and abs(float(x) - float(y)) > 1.000001 * max(_last_digit_unit(x),
                                                                 _last_digit_unit(y)):
            return False
    return True


def differences(name: str, first: list[list[str]], second: list[list[str]]) -> list[str]:
    if len(first) != len(second):
        return [f"{name}: {len(first)} code cells against {len(second)}"]
    found = []
    for k, (a, b) in enumerate(zip(first, second, strict=True)):
        if len(a) != len(b):
            found.append(f"{name}, code cell {k + 1}: {len(a)} outputs against {len(b)}")
            continue
        for x, y in zip(a, b, strict=True):
            if not same_text(x, y):
                at = next((i for i, (c, d) in enumerate(zip(x, y)) if c != d),
                          min(len(x), len(y)))
                found.append(f"{name}, code cell {k + 1}: {x[max(0, at - 40):at + 60]!r} != "
                             f"{y[max(0, at - 40):at + 60]!r}")
    return found


def test_stream_merging_leaves_the_executed_notebook_as_the_kernel_sent_it():
    """myst-nb's coalesce_streams merges a cell's stream outputs in place, so the notebook
    written to jupyter_execute got a second print twice (seen in CI); _ext/stream_outputs.py
    makes it merge a copy.  Power: the unpatched function changes its input."""
    import nbformat
    from myst_nb.core import render

    def outputs():
        return [nbformat.v4.new_output("stream", name="stdout", text="first\n"),
                nbformat.v4.new_output("stream", name="stdout", text="second\n")]

    before = render.coalesce_streams
    raw = outputs()
    before(raw)
    assert raw[0]["text"] == "first\nsecond\n"          # the upstream function mutates
    spec = importlib.util.spec_from_file_location("stream_outputs",
                                                  ROOT / "_ext" / "stream_outputs.py")
    ext = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ext)
    try:
        ext._merge_on_a_copy(None, None)
        kept = outputs()
        for _ in range(2):                                  # rendered twice: same page text
            merged = render.coalesce_streams(kept)
            assert [o["text"] for o in merged] == ["first\nsecond\n"]
        assert [o["text"] for o in kept] == ["first\n", "second\n"]
        assert output_texts(nbformat.v4.new_notebook(cells=[
            nbformat.v4.new_code_cell("", outputs=kept)])) == [["stdout: first\nsecond"]]
    finally:
        render.coalesce_streams = before


def test_the_comparison_has_power():
    """A changed digit, a changed count, a changed word and a missing output are all
    flagged; a decimal value that printed one unit apart in its last digit is not."""
    base = [["text/plain: '0.0281'", "stdout: sigma = 1.234e-05 rad/s, 17 runs\n"]]
    assert differences("x", base, base) == []
    assert differences("x", base, [["text/plain: '0.0282'", base[0][1]]]) == []
    assert differences("x", base, [["text/plain: '0.0284'", base[0][1]]])
    assert differences("x", base, [[base[0][0], "stdout: sigma = 1.234e-05 rad/s, 18 runs\n"]])
    assert differences("x", base, [[base[0][0], "stdout: sigma = 1.234e-04 rad/s, 17 runs\n"]])
    assert differences("x", base, [[base[0][0], "stdout: sigma = 1.234e-05 rad/h, 17 runs\n"]])
    assert differences("x", base, [[base[0][0]]])
    assert not same_text("holds", "fails") and same_text("2.5 s", "2.6 s")
    # gyrolib's version is not compared (a release changes it), any other number is
    v = gyrolib.__version__
    assert output_texts(_one_cell(f"gyrolib {v}, @misc{{x_{v.replace('.', '_')},\n", "1" + v)
                        ) == [[f"stdout: gyrolib <VERSION>, @misc{{x_<VERSION>,\n1{v}"]]


def _one_cell(*prints: str):
    import nbformat

    return nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell("", outputs=[
        nbformat.v4.new_output("stream", name="stdout", text=t) for t in prints])])


# ----------------------------------------------------------------------------- second run


@dataclass(frozen=True)
class Chapter:
    """A chapter as the session executed it: ``name`` its path under the book without the
    suffix (``chapters/gc_claims``), ``nb`` the executed notebook, ``texts`` its outputs
    (:func:`output_texts`)."""

    name: str
    nb: object
    texts: list


@dataclass(frozen=True)
class Verdict:
    """What :func:`compare_chapters` found: ``problems`` (outputs of two executions that
    differ), ``second`` the second execution each chapter was compared with (``record``,
    ``project cache`` or ``executed again``), ``stale`` the chapters whose record was missing
    or differed from an agreeing second execution, ``unjudged`` those that differ from their
    record (or have none) and were not executed again (the everyday tier leaves them to the
    full tier)."""

    problems: list
    second: dict
    stale: list
    unjudged: list = field(default_factory=list)


def compare_chapters(chapters: list[Chapter], recorded: dict[str, list],
                     cached: Callable[[Chapter], list | None],
                     execute: Callable[[list[Chapter]], dict[str, list]] | None,
                     every: bool = False) -> Verdict:
    """Compare each chapter with a second execution: its record if that agrees (two
    executions agree), else the project cache's execution (``cached``), else one made now
    (``execute``, called once with every such chapter; with ``execute=None`` such a chapter
    is left ``unjudged``).  ``every``: every chapter is executed again and compared with that
    execution, whatever its record says (the record only decides whether it is stale)."""
    problems, second, stale, again, unjudged = [], {}, [], [], []
    agreeing: set[str] = set()
    for ch in chapters:
        record = recorded.get(ch.name)
        if record is not None and not differences(ch.name, ch.texts, record):
            agreeing.add(ch.name)
            if not every:
                second[ch.name] = "record"
                continue
        other = None if every else cached(ch)
        if other is None:
            (again if execute is not None else unjudged).append(ch)
            continue
        second[ch.name] = "project cache"
        found = differences(ch.name, ch.texts, other)
        problems += found
        if not found:
            stale.append(ch.name)
    if again:
        runs = execute(again)
        for ch in again:
            second[ch.name] = "executed again"
            found = differences(ch.name, ch.texts, runs[ch.name])
            problems += found
            if not found and ch.name not in agreeing:
                stale.append(ch.name)
    return Verdict(problems=problems, second=second, stale=stale,
                   unjudged=[ch.name for ch in unjudged])


def _record_path(name: str, folder: Path = RECORDED) -> Path:
    return folder / f"{Path(name).name}.json"


def load_records(folder: Path = RECORDED) -> dict[str, list]:
    """The committed outputs, chapter name → :func:`output_texts`."""
    records = {}
    for path in sorted(folder.glob("*.json")):
        data = json.loads(path.read_text(encoding="utf-8"))
        records[data["chapter"]] = data["cells"]
    return records


def write_records(chapters: list[Chapter], names: list[str], folder: Path = RECORDED) -> None:
    """Record the outputs of the chapters ``names`` (each agreed with a second execution)
    and remove the records of chapters the book no longer has."""
    folder.mkdir(exist_ok=True)
    for ch in chapters:
        if ch.name in names:
            text = json.dumps({"chapter": ch.name, "cells": ch.texts}, indent=1,
                              ensure_ascii=False)
            _record_path(ch.name, folder).write_text(text + "\n", encoding="utf-8")
    keep = {_record_path(ch.name, folder).name for ch in chapters}
    for path in folder.glob("*.json"):
        if path.name not in keep:
            path.unlink()


def _gyrolib_cache_ext():
    spec = importlib.util.spec_from_file_location("gyrolib_cache",
                                                  ROOT / "_ext" / "gyrolib_cache.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _project_cache(book):
    """The project's jupyter cache, if it is another execution than the session book's and
    was made with the current gyrolib sources and pins; else ``None``."""
    stamp = PROJECT_CACHE / _gyrolib_cache_ext().STAMP
    if (not book.fresh or not stamp.is_file()
            or stamp.read_text().strip() != _gyrolib_cache_ext().library_fingerprint(ROOT)):
        return None
    from jupyter_cache import get_cache

    return get_cache(str(PROJECT_CACHE))


def session_chapters(book) -> list[Chapter]:
    """Every chapter the session's book executed, with its outputs as the session's jupyter
    cache holds them (the glue outputs included)."""
    import nbformat
    from jupyter_cache import get_cache

    cache = get_cache(str(book.cache))
    chapters = []
    for path in sorted(book.executed.rglob("*.ipynb")):
        name = path.relative_to(book.executed).with_suffix("").as_posix()
        try:
            record = cache.match_cache_notebook(nbformat.read(path, as_version=4))
        except KeyError:
            pytest.fail(f"{name}: no record of its execution in {book.cache}")
        nb = cache.get_cache_bundle(record.pk).nb
        chapters.append(Chapter(name=name, nb=nb, texts=output_texts(nb)))
    return chapters


def _execute_again(nb, chapter_dir: Path):
    """The notebook's code executed in a new kernel, as myst-nb runs it (in the chapter's
    folder)."""
    import nbclient
    import nbformat

    fresh = nbformat.from_dict(nb)
    for cell in fresh.cells:
        if cell.cell_type == "code":
            cell.outputs, cell.execution_count = [], None
    # as the book build (_ext/gyrolib_cache.py): a late output is waited for, and an error
    nbclient.NotebookClient(fresh, timeout=600, kernel_name="python3", iopub_timeout=120,
                            raise_on_iopub_timeout=True,
                            resources={"metadata": {"path": str(chapter_dir)}}).execute()
    return fresh


def _execute_chapters(chapters: list[Chapter], folder=lambda ch: ROOT / Path(ch.name).parent
                      ) -> dict[str, list]:
    """Each chapter executed again (two kernels at a time), name → :func:`output_texts`."""
    with ThreadPoolExecutor(max(1, min(2, os.cpu_count() or 1))) as pool:
        runs = pool.map(lambda ch: output_texts(_execute_again(ch.nb, folder(ch))), chapters)
        return {ch.name: texts for ch, texts in zip(chapters, runs, strict=True)}


def _check_session_chapters(monkeypatch, tmp_path, every: bool) -> None:
    """The session's chapters against their second executions (:func:`compare_chapters`):
    ``every`` executes each chapter again here (the full tier); without it a chapter that
    differs from its record is executed again only to record it (:data:`RECORD_ENV`), else
    it is named in a warning and left to the full tier."""
    book = session_book()
    chapters = session_chapters(book)
    assert len(chapters) >= 10, f"only {len(chapters)} executed chapters in {book.executed}"
    project = _project_cache(book)

    def cached(ch: Chapter) -> list | None:
        if project is None:
            return None
        try:
            record = project.match_cache_notebook(ch.nb)
        except KeyError:
            return None
        return output_texts(project.get_cache_bundle(record.pk).nb)

    # the chapters executed again here get a ledger memo of their own (independent of the
    # build's)
    monkeypatch.setenv("GYROLIB_LEDGER_MEMO", str(tmp_path / "ledger"))
    monkeypatch.setenv("MPLBACKEND", "Agg")
    monkeypatch.setenv("OPENBLAS_NUM_THREADS", os.environ.get("OPENBLAS_NUM_THREADS", "1"))
    record = os.environ.get(RECORD_ENV) == "1"
    verdict = compare_chapters(chapters, load_records(), cached,
                               _execute_chapters if every or record else None, every=every)
    compared = sum(len(t) for ch in chapters for t in ch.texts)
    glued = sum(t.startswith("glue ") for ch in chapters for cell in ch.texts
                for t in cell)
    assert compared > 100 and glued > 100, f"only {compared} outputs ({glued} glued) compared"
    assert not verdict.problems, "\n".join(verdict.problems)
    if record:
        write_records(chapters, verdict.stale)
    elif verdict.stale:
        warnings.warn(f"the recorded outputs of {', '.join(verdict.stale)} are stale or "
                      f"missing: executed again here (they agree); record them with "
                      f"{RECORD_ENV}=1 (tests/book/test_determinism.py)", stacklevel=1)
    if verdict.unjudged:
        warnings.warn(f"{', '.join(verdict.unjudged)} differ from their recorded outputs (or "
                      "have none): not executed again here; python3 tasks.py test --full "
                      f"executes every chapter again, and {RECORD_ENV}=1 records them "
                      "(tests/book/test_determinism.py)", stacklevel=1)


def test_the_outputs_agree_with_their_records(tmp_path, monkeypatch):
    """Everyday tier: each chapter's outputs agree with its recorded outputs (two executions
    agree) or with the project's cache; none is executed again."""
    _check_session_chapters(monkeypatch, tmp_path, every=False)


@pytest.mark.full
def test_a_second_execution_of_every_chapter_gives_the_same_outputs(tmp_path, monkeypatch):
    """Full tier: every chapter executed a second time here, two kernels at a time, agrees
    with the session's execution (about one more clean execution of the book)."""
    _check_session_chapters(monkeypatch, tmp_path, every=True)


NONDETERMINISTIC = ["import random\nfrom myst_nb import glue\n"
                    "glue('tiny_x', f'{random.random():.6f}', display=False)",
                    "print(f'{random.random():.6f}')"]
DETERMINISTIC = ["from myst_nb import glue\nglue('tiny_y', f'{2 / 3:.4f}', display=False)\n"
                 "print(17)"]


def test_a_nondeterministic_cell_is_caught(tmp_path):
    """Power, on the test's own path with real kernels: a chapter whose glued value and
    printed value are unseeded random numbers fails (each cell is named), whether it has no
    record or a record that differs; a deterministic chapter whose record differs (stale) is
    executed again and passes as stale; one whose record agrees is not executed again."""
    import nbformat

    def chapter(name, sources):
        nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(s) for s in sources])
        nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3",
                                     "language": "python"}
        return Chapter(name=name, nb=nb, texts=[])

    first = _execute_chapters([chapter("chapters/random", NONDETERMINISTIC),
                               chapter("chapters/fixed", DETERMINISTIC)],
                              folder=lambda ch: tmp_path)
    rnd = Chapter("chapters/random", None, first["chapters/random"])
    fixed = Chapter("chapters/fixed", chapter("", DETERMINISTIC).nb, first["chapters/fixed"])
    assert fixed.texts == [["glue tiny_y text/plain: '0.6667'", "stdout: 17"]]
    rnd = Chapter(rnd.name, chapter("", NONDETERMINISTIC).nb, rnd.texts)
    stale_fixed = [["glue tiny_y text/plain: '0.6671'", "stdout: 17"]]
    stale_random = [[t.replace("0.", "1.") for t in cell] for cell in rnd.texts]
    executed = []

    def execute(chs):
        executed.append(sorted(ch.name for ch in chs))
        return _execute_chapters(chs, folder=lambda ch: tmp_path)

    verdict = compare_chapters([rnd, fixed], {"chapters/fixed": stale_fixed}, lambda ch: None,
                               execute)
    assert executed == [["chapters/fixed", "chapters/random"]]
    assert [p.split(":")[0] for p in verdict.problems] == ["chapters/random, code cell 1",
                                                           "chapters/random, code cell 2"]
    assert verdict.stale == ["chapters/fixed"]
    # a record that differs does not let a nondeterministic chapter pass either
    verdict = compare_chapters([rnd], {"chapters/random": stale_random}, lambda ch: None,
                               lambda chs: {"chapters/random": stale_random})
    assert verdict.problems and verdict.second == {"chapters/random": "executed again"}
    # an agreeing record: no third execution
    verdict = compare_chapters([fixed], {"chapters/fixed": fixed.texts}, lambda ch: None,
                               lambda chs: pytest.fail("executed again"))
    assert verdict == Verdict(problems=[], second={"chapters/fixed": "record"}, stale=[])
    # the everyday tier executes nothing: a chapter that differs from its record is unjudged
    verdict = compare_chapters([rnd, fixed], {"chapters/fixed": fixed.texts},
                               lambda ch: None, None)
    assert verdict == Verdict(problems=[], second={"chapters/fixed": "record"}, stale=[],
                              unjudged=["chapters/random"])
    # the full tier executes every chapter again, an agreeing record or not
    verdict = compare_chapters([rnd, fixed], {"chapters/fixed": fixed.texts},
                               lambda ch: pytest.fail("read the cache"),
                               lambda chs: {"chapters/random": stale_random,
                                            "chapters/fixed": fixed.texts}, every=True)
    assert verdict.second == {"chapters/random": "executed again",
                              "chapters/fixed": "executed again"}
    assert verdict.problems and verdict.stale == []


def test_records_round_trip(tmp_path):
    """What :func:`write_records` writes, :func:`load_records` reads back; the record of a
    chapter the book no longer has is removed."""
    (tmp_path / "gone.json").write_text(json.dumps({"chapter": "chapters/gone", "cells": []}))
    chapters = [Chapter("chapters/a", None, [["glue k text/plain: '1.5'", "stdout: é"]]),
                Chapter("chapters/b", None, [[]])]
    write_records(chapters, ["chapters/a"], tmp_path)
    assert load_records(tmp_path) == {"chapters/a": chapters[0].texts}
