"""A rerun chapter shows what the book's page shows.

``python3 tasks.py chapter NAME`` and each page's download menu give an executed notebook
whose prose was rendered by ``_ext/rerun_notebook.py``.  The check
(:func:`notebook_problems`): rendered to HTML by nbconvert, as Jupyter shows it, the notebook

* has no raw MyST in its Markdown cells or Markdown outputs (``rerun_notebook.RAW_MYST``:
  any ``{role}``, a ```` ```{directive} ```` or ``:::{directive}`` fence, a ``(label)=``
  line, and by name ``{eq}``, ``{numref}``, ``{glue:md}``, ``{bibliography}``, ``{bdg-*}``);
* shows at least as many ``<img>`` as the chapter has figures (``{glue:figure}`` blocks in
  its source);
* says in its first cell where its prose's values come from.

Power: the same check on the notebook as the build executed it, before rendering (what an
unrendered download would offer), fails.

The rerun chapter (``rsf_method``) is jupytext's notebook of it with the outputs of the
session book's fresh-kernel execution of the same code, found in the session's jupyter cache
by the hash of its code cells, then rendered as ``tasks.py chapter`` renders it
(:func:`rerun_notebook`): the test command executes it once, not twice.  The command itself
is run end to end on the one-cell ``status`` chapter.
"""

from __future__ import annotations

import base64
import copy
import functools
import json
import re
import subprocess
import sys
from pathlib import Path

import nbformat
import pytest

from tests.conftest import require_built_book, session_book

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "_ext"))
import rerun_notebook as rn  # noqa: E402 - _ext/ is not a package

IMG = re.compile(r"<img\b", re.I)
# a 1x1 PNG, glued as a figure
PNG = base64.b64encode(bytes.fromhex(
    "89504e470d0a1a0a0000000d4948445200000001000000010806000000"
    "1f15c4890000000d49444154789c6360f8cf000000030101005dc2a3"
    "5b0000000049454e44ae426082")).decode()


def n_figures(chapter: str) -> int:
    return (ROOT / "chapters" / f"{chapter}.md").read_text(encoding="utf-8").count(
        "```{glue:figure}")


def notebook_problems(nb, figures: int) -> list[str]:
    """What a reader of ``nb`` in Jupyter would see wrong (module docstring)."""
    problems, images = rendered(nb)
    return problems + too_few_images(images, figures)


def too_few_images(images: int, figures: int) -> list[str]:
    return [f"{images} <img> in the rendered notebook, {figures} figures"] if (
        images < figures) else []


@functools.cache
def _exporter():
    """One nbconvert HTML exporter for the module's renderings: a new one compiles its
    templates again (about 0.15 CPU-s each).  The ``basic`` template: the cells as the
    ``classic`` and ``lab`` templates render them, without the page around them (whose
    style sheets ``classic`` inlines: 0.4 CPU-s at the first rendering; no <img> in it: the
    same count in rsf_method's rerun notebook and gc_model's, rendered and not, with all
    three).  Without the code cells' input: highlighted code escapes "<", so it never adds
    an <img>, and highlighting it was three quarters of the rendering's time."""
    from nbconvert import HTMLExporter

    return HTMLExporter(template_name="basic", exclude_input=True)


def rendered(nb) -> tuple[list[str], int]:
    """The problems of ``nb`` other than too few images, and the number of ``<img>`` in it
    as nbconvert renders it (the figure count is then compared without rendering again)."""
    problems = []
    for i, cell in enumerate(nb.cells):
        texts = [cell.source] if cell.cell_type == "markdown" else [
            "".join(o["data"]["text/markdown"]) for o in cell.get("outputs", [])
            if "text/markdown" in o.get("data", {})]
        for text in texts:
            problems += [f"cell {i}: raw {hit}" for hit in rn.raw_myst(text)]
    # nbconvert renders a copy of ``nb`` (from_notebook_node deep-copies it)
    html, _ = _exporter().from_notebook_node(nb)
    if not (nb.cells and "run that wrote it" in nb.cells[0].source):
        problems.append("no first cell saying where the prose's values come from")
    return problems, len(IMG.findall(html))


def _glued(name: str, data: dict) -> dict:
    return nbformat.v4.new_output(
        "display_data", data={rn.GLUE_PREFIX + k: v for k, v in data.items()},
        metadata={"scrapbook": {"name": name, "mime_prefix": rn.GLUE_PREFIX}})


def small_notebook():
    """A chapter in miniature: a glued value and figure, and every kind of markup."""
    code = nbformat.v4.new_code_cell("glue(...)")
    code.outputs = [_glued("x_sigma", {"text/plain": "'0.0123'"}),
                    _glued("x_fig", {"image/png": PNG, "text/plain": "<Figure>"}),
                    nbformat.v4.new_output("display_data", data={
                        "text/markdown": "| a | b |\n| --- | --- |\n| {ref}`x-sec` | 1 |"})]
    md = nbformat.v4.new_markdown_cell(
        "(x-sec)=\n# A section\n\nσ = {glue:text}`x_sigma` rad/s, {glue:text}`x_sigma:.2%`; see "
        "{numref}`fig-gcm-figure1`, {eq}`gc-eq-1`, {ref}`gcm-derivation`, {ref}`the text "
        "<gcm-derivation>` and {cite:p}`Kalman1960`; {bdg-success}`reproduced`.\n\n"
        "$$\na = b\n$$ (gc-eq-1)\n\n"
        "```{glue:figure} x_fig\n:name: fig-gcm-figure1\n:alt: A drawing\n\nThe caption "
        "({ref}`gcm-derivation`).\n```\n\n:::{note}\nA note.\n:::\n\n"
        "```text\n{ref}`kept in code`\n```")
    return nbformat.v4.new_notebook(cells=[md, code])


@pytest.mark.filterwarnings("ignore:Your element with mimetype")  # the raw glue records
def test_rendering_fills_glue_and_roles_and_the_check_has_power():
    nb = small_notebook()
    raw = notebook_problems(copy.deepcopy(nb), figures=1)
    assert any("raw role" in p for p in raw) and any("<img>" in p for p in raw), raw
    assert any("raw label" in p for p in raw) and any("raw directive" in p for p in raw), raw

    rn.render_notebook(nb, "small")
    code_block = "```text\n{ref}`kept in code`\n```"
    md = nb.cells[1].source
    assert code_block in md  # code is not prose: left as it is
    nb.cells[1].source = md.replace(code_block, "")
    assert notebook_problems(nb, figures=1) == []
    text = nb.cells[1].source
    assert "σ = 0.0123 rad/s, 1.23%" in text  # the value, formatted as myst-nb formats it
    index = rn.label_index()
    assert f"see Fig. {index.figures['fig-gcm-figure1']}, Eq. (1)" in text
    assert f"“{index.titles['gcm-derivation']}”" in text and "the text and" in text
    assert "(Kalman, 1960)" in text and "**reproduced**" in text
    assert "\\tag{1}" in text and "![A drawing](attachment:x_fig.png)" in text
    assert nb.cells[1].attachments["x_fig.png"]["image/png"] == PNG
    assert "> **Note**" in text
    assert nb.cells[-1].source.startswith("## References") and "Kalman" in nb.cells[-1].source
    assert len(nb.cells[2].outputs) == 1  # the glue records dropped: Jupyter shows none
    assert "| “A section” | 1 |" in nb.cells[2].outputs[0]["data"]["text/markdown"]
    # rendering twice gives one first cell and one reference list
    again = rn.render_notebook(copy.deepcopy(nb), "small")
    assert [c.source.strip() for c in again.cells] == [c.source.strip() for c in nb.cells]


def test_a_missing_glue_value_is_shown_as_missing_not_raw():
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_markdown_cell("{glue:text}`nope`")])
    rn.render_notebook(nb, "x")
    assert "nope: not computed in this run" in nb.cells[1].source
    assert nb.metadata["gyrolib"]["missing_glue"] == ["nope"]


@pytest.mark.book
def test_label_numbers_are_the_books():
    """The figure and equation numbers the notebooks print are those of the built pages."""
    html = require_built_book()
    index = rn.label_index()
    wrong = []
    for path in sorted((html / "chapters").glob("*.html")):
        page = path.read_text(encoding="utf-8")
        for m in re.finditer(r'<figure[^>]*id="([^"]+)".*?<span class="caption-number">'
                             r'Fig\. (\d+) </span>', page, re.S):
            if index.figures.get(m.group(1)) != int(m.group(2)):
                wrong.append(f"{path.name}: {m.group(1)} is Fig. {m.group(2)} on the page, "
                             f"{index.figures.get(m.group(1))} in the notebook")
        for m in re.finditer(r'<span class="eqno">\((\d+)\)<a class="headerlink" '
                             r'href="#equation-([^"]+)"', page):
            if index.equations.get(m.group(2)) != int(m.group(1)):
                wrong.append(f"{path.name}: eq. {m.group(2)} is ({m.group(1)}) on the page, "
                             f"{index.equations.get(m.group(2))} in the notebook")
    assert len(index.figures) == sum(n_figures(p.stem) for p in (ROOT / "chapters").glob("*.md"))
    assert not wrong, wrong


@pytest.mark.book
@pytest.mark.filterwarnings("ignore:Your element with mimetype")
def test_the_downloaded_notebook_shows_what_the_page_shows():
    """gc_model's ``.ipynb`` of the download menu passes the check; the notebook as the build
    executed it (before rendering) fails it."""
    build = require_built_book().parent
    name = "gc_model"
    got = nbformat.read(str(build / "html" / "_sources" / "chapters" / f"{name}.ipynb"), 4)
    assert notebook_problems(got, n_figures(name)) == []
    executed = nbformat.read(str(build / "jupyter_execute" / "chapters" / f"{name}.ipynb"), 4)
    assert len(notebook_problems(executed, n_figures(name))) > 10


#: A short chapter with glued values and a glued figure.
RERUN_CHAPTER = "rsf_method"


def rerun_notebook(name: str):
    """The chapter ``name`` as ``python3 tasks.py chapter NAME`` makes it (``rn.execute_chapter``),
    its kernel's outputs taken from the test session's execution of the same code, and
    ``(source, merged)`` besides: the rendered notebook, and the notebook as jupytext read it
    and before rendering (outputs merged).

    ``execute_chapter`` reads the chapter with jupytext, executes it in a fresh kernel
    (nbclient) and renders it with ``rn.render_notebook``.  The session's book build has
    executed every chapter in a fresh kernel (nbclient, through jupyter-cache) into the
    session's jupyter cache, keyed by the hash of the notebook's code cells and kernel:
    jupytext's notebook of the chapter is looked up there (a match means the same code on
    the same kernel) and its outputs merged in (``merge_match_into_notebook``, as myst-nb's
    cache mode does); then the same rendering.  That execution is the book's only one of the
    chapter and costs this test nothing; executing it again here cost about 10 CPU-s.  A
    cache without that code (a reused, older build: ``GYROLIB_REUSE_BOOK``) executes it here
    in a fresh kernel instead.  The command's own steps, end to end, are checked on the
    cheapest chapter (:func:`test_tasks_chapter_writes_the_rendered_notebook`)."""
    import jupytext
    from jupyter_cache import get_cache

    source = jupytext.read(str(ROOT / "chapters" / f"{name}.md"))
    try:
        _, merged = get_cache(str(session_book().cache)).merge_match_into_notebook(source)
    except KeyError:  # not in the cache: executed here, as the command does
        import tempfile

        from nbclient import NotebookClient

        merged = copy.deepcopy(source)
        with tempfile.TemporaryDirectory() as folder:
            NotebookClient(merged, timeout=600, resources={"metadata": {"path": folder}}
                           ).execute()
    return rn.render_notebook(copy.deepcopy(merged), name), merged


@pytest.mark.book
@pytest.mark.filterwarnings("ignore:Your element with mimetype")
def test_a_rerun_chapter_shows_what_the_page_shows():
    """``rsf_method`` rerun as ``python3 tasks.py chapter rsf_method`` makes it
    (:func:`rerun_notebook`) passes the check; unrendered, it fails it.  Power: its figures
    counted against a chapter with more, it fails."""
    nb, merged = rerun_notebook(RERUN_CHAPTER)
    executed = [c.execution_count for c in merged.cells if c.cell_type == "code"]
    assert executed and all(isinstance(n, int) for n in executed), executed
    # the glued values and figures are the kernel's outputs, in the notebook itself
    assert {"rsf_fig1", "rsf_dk_ppm"} <= set(rn.glue_outputs(merged))
    assert sum(len(rn.raw_myst(c.source)) for c in merged.cells if c.cell_type == "markdown"
               ) > 10  # the same check before rendering: raw roles (power)
    problems, images = rendered(nb)  # rendered once, for the check and its power case
    figures = n_figures(RERUN_CHAPTER)
    assert problems + too_few_images(images, figures) == []  # = notebook_problems(nb, figures)
    assert nb.metadata["gyrolib"]["missing_glue"] == []
    assert too_few_images(images, figures + 1)  # one figure short
    text = "\n".join(c.source for c in nb.cells if c.cell_type == "markdown")
    assert "python3 tasks.py chapter rsf_method" in nb.cells[0].source
    assert json.dumps(nb.cells[0].source)  # plain text
    assert "attachment:rsf_fig1.png" in text


@pytest.mark.slow
def test_tasks_chapter_writes_the_rendered_notebook(tmp_path):
    """``python3 tasks.py chapter status FOLDER``, end to end (the cheapest chapter: one code
    cell): the command reads the chapter, executes it in a fresh kernel and writes it
    rendered, and the result passes the check (its label and its book-only directive
    rendered).  Power: the chapter as jupytext reads it fails the same check."""
    name = "status"
    proc = subprocess.run([sys.executable, str(ROOT / "tasks.py"), "chapter", name,
                           str(tmp_path)], cwd=ROOT, capture_output=True, text=True,
                          timeout=900, check=False)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-3000:]
    nb = nbformat.read(str(tmp_path / f"{name}.ipynb"), 4)
    code = [c for c in nb.cells if c.cell_type == "code"]
    assert code and all(isinstance(c.execution_count, int) and c.outputs for c in code)
    assert "gyrolib" in "".join(o.get("text", "") for o in code[0].outputs)
    assert nb.metadata["gyrolib"]["rendered_for_jupyter"] is True
    assert f"python3 tasks.py chapter {name}" in nb.cells[0].source
    assert notebook_problems(nb, n_figures(name)) == []
    import jupytext

    raw = jupytext.read(str(ROOT / "chapters" / f"{name}.md"))
    assert sum(len(rn.raw_myst(c.source)) for c in raw.cells if c.cell_type == "markdown") >= 2
