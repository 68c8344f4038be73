"""Two executions of the chapters give the same numbers.

The test session's book (``conftest.session_book``) executed every chapter into a fresh
jupyter cache.  Each chapter's outputs — every printed text, glued value, table and figure
description, cell by cell — are compared with a second, independent execution of the same
code:

* the project's own jupyter cache (``_build/.jupyter_cache``, filled by
  ``python3 tasks.py book`` in another process, at another time), when it holds this
  chapter's code and was made with the same gyrolib sources and pinned environment (its
  stamp from ``_ext/gyrolib_cache.py``);
* otherwise the chapter is executed again here (only the chapters without such a record,
  two kernels at a time).

Random runs take explicit seeds, so the texts must agree.  Numbers are compared as numbers:
decimal numbers equal, or apart by at most one unit in the last printed digit (a value on a
rounding boundary may print either way when the last bit of a sum depends on the order of the
terms); integers and everything else character for character.  Images are not compared
(their bytes depend on the renderer); their text form (``<Figure size …>``) is.
"""

from __future__ import annotations

import importlib.util
import os
import re
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest
from conftest import ROOT, session_book

pytestmark = [pytest.mark.book, pytest.mark.slow]

PROJECT_CACHE = ROOT / "_build" / ".jupyter_cache"
TEXT_MIMES = ("text/plain", "text/markdown", "text/html", "text/latex")
ADDRESS = re.compile(r"\b0x[0-9a-fA-F]{6,}\b")
NUMBER = re.compile(r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?")


# ----------------------------------------------------------------------------- comparison


def output_texts(nb) -> list[list[str]]:
    """Per code cell, the text of each output (streams and the text forms of results)."""
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
            elif out.get("output_type") == "error":
                texts.append(f"error: {out.get('ename')}: {out.get('evalue')}")
        # trailing blank lines: myst-nb's stream merging drops them, a kernel sends them
        cells.append([ADDRESS.sub("0x…", t if isinstance(t, str) else "".join(t)).rstrip()
                      for t in texts])
    return cells


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


# ----------------------------------------------------------------------------- second run


def _gyrolib_cache_ext():
    spec = importlib.util.spec_from_file_location("gyrolib_cache",
                                                  ROOT / "_ext" / "gyrolib_cache.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _project_cache():
    """The project's jupyter cache, if it is another execution than the session book's and
    was made with the current gyrolib sources and pins; else ``None``."""
    book = session_book()
    stamp = PROJECT_CACHE / _gyrolib_cache_ext().STAMP
    if (not book.fresh or not stamp.is_file()
            or stamp.read_text().strip() != _gyrolib_cache_ext().library_fingerprint(ROOT)):
        return None
    from jupyter_cache import get_cache

    return get_cache(str(PROJECT_CACHE))


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


def test_a_second_execution_gives_the_same_outputs(tmp_path, monkeypatch):
    import nbformat

    book = session_book()
    notebooks = sorted(book.executed.rglob("*.ipynb"))
    assert len(notebooks) >= 10, f"only {len(notebooks)} executed chapters in {book.executed}"
    cache = _project_cache()
    first, second, again = {}, {}, []
    for path in notebooks:
        name = path.relative_to(book.executed).with_suffix("").as_posix()
        nb = nbformat.read(path, as_version=4)
        first[name] = output_texts(nb)
        record = None
        if cache is not None:
            try:
                record = cache.match_cache_notebook(nb)
            except KeyError:
                record = None
        if record is not None:
            second[name] = output_texts(cache.get_cache_bundle(record.pk).nb)
        else:
            again.append((name, nb))
    # the chapters without a current record in the project cache: executed once more here,
    # with a ledger memo of their own (independent of the build's)
    monkeypatch.setenv("GYROLIB_LEDGER_MEMO", str(tmp_path / "ledger"))
    monkeypatch.setenv("MPLBACKEND", "Agg")
    monkeypatch.setenv("OPENBLAS_NUM_THREADS", os.environ.get("OPENBLAS_NUM_THREADS", "1"))
    with ThreadPoolExecutor(max(1, min(2, os.cpu_count() or 1))) as pool:
        runs = pool.map(lambda job: (job[0], _execute_again(job[1], ROOT / Path(job[0]).parent)),
                        again)
        for name, nb in runs:
            second[name] = output_texts(nb)
    problems = []
    for name in first:
        problems += differences(name, first[name], second[name])
    compared = sum(len(t) for cells in first.values() for t in cells)
    assert compared > 100, f"only {compared} outputs compared"
    assert not problems, "\n".join(problems)
