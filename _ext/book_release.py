"""Sphinx extension: what a reader needs to cite a result and rerun a chapter.

* **Version.**  The book's version is gyrolib's (one string, in ``pyproject.toml``, read by
  ``gyrolib.__version__``).  It is set as Sphinx's ``version``/``release`` and shown in every
  page's footer, with a link to the PDF of the book when ``_build/pdf/book.pdf`` exists
  (``python3 tasks.py pdf`` writes it, then rebuilds the HTML so that the link appears;
  the PDF is looked for beside the output folder, ``_build/pdf`` for ``_build/html``).
* **Ledger data.**  After an HTML build, ``ledger.json`` and ``ledger.csv`` (the output of
  ``gyrolib.book.ledger.to_json``/``to_csv``, the same as ``python -m gyrolib ledger``, both
  carrying the version) are written to the root of the built site; the ledger page links to
  them.
* **Executed notebooks.**  Each chapter page's download menu offers the executed ``.ipynb``
  (myst-nb writes it to ``_build/jupyter_execute``; it is written next to the ``.md`` source in
  ``_sources``), as sphinx-book-theme does when launch buttons are configured; this book has
  none (it loads nothing from the internet), so the copy is done here.  The copy's prose is
  rendered as the page shows it (``_ext/rerun_notebook.py``): glued values and figures
  pasted in, cross-references and citations as text.
* **Status table.**  myst-nb's execution table marks each chapter with an emoji, which shows as
  a missing-glyph box on machines without an emoji font; it says "passed"/"failed" instead.
"""

from __future__ import annotations

import functools
import json
import shutil
from pathlib import Path

# _ext/ is on sys.path (Jupyter Book's local_extensions): the sibling module
import rerun_notebook

PDF_NAME = "book.pdf"


def _book_version() -> str:
    import gyrolib

    return gyrolib.__version__


def _pdf_path(app) -> Path:
    """``pdf/book.pdf`` beside the output folder (``_build/html`` -> ``_build/pdf``), so that
    a build elsewhere (``--path-output``, the test session's book) finds its own PDF."""
    return Path(app.outdir).parent / "pdf" / PDF_NAME


def _config_inited(app, config) -> None:
    version = _book_version()
    config.version = version
    config.release = version
    footer = f"Gyro calibration, reproduced — version {version}."
    # (no builder yet at config-inited: the html build writes to a folder named "html")
    if Path(app.outdir).name == "html" and _pdf_path(app).is_file():
        footer += ' <a class="gyrolib-pdf-link" href="{pdf}">PDF of the whole book</a>.'
    options = dict(config.html_theme_options or {})
    options["extra_footer"] = footer
    config.html_theme_options = options


def _add_context(app, pagename, templatename, context, doctree) -> None:
    """Per page: resolve the footer's PDF link; offer the executed notebook for download."""
    footer = context.get("theme_extra_footer")
    if isinstance(footer, str) and "{pdf}" in footer:
        # pathto(name, 1): the file at the output root, relative to this page
        context["theme_extra_footer"] = footer.replace("{pdf}", context["pathto"](PDF_NAME, 1))
    if app.builder.name != "html":
        return
    executed = Path(app.outdir).parent / "jupyter_execute" / f"{pagename}.ipynb"
    if executed.is_file():
        target = Path(app.outdir) / "_sources" / f"{pagename}.ipynb"
        target.parent.mkdir(parents=True, exist_ok=True)
        # the prose as the page shows it: glued values and figures pasted in, roles as text
        rerun_notebook.render_file(executed, Path(pagename).name, Path(app.srcdir),
                                   out=target, index=_label_index(app.srcdir))
        context["ipynb_source"] = f"{pagename}.ipynb"


@functools.cache
def _label_index(srcdir: str):
    return rerun_notebook.label_index(Path(srcdir))


def _write_ledger_data(app, exception) -> None:
    if exception is not None or app.builder.name != "html":
        return
    from gyrolib.book import ledger

    items = ledger.collect()
    outdir = Path(app.outdir)
    data = ledger.to_json(items)
    if not isinstance(data, str):
        data = json.dumps(data, indent=2, ensure_ascii=False) + "\n"
    (outdir / "ledger.json").write_text(data, encoding="utf-8")
    (outdir / "ledger.csv").write_text(ledger.to_csv(items), encoding="utf-8")
    pdf = _pdf_path(app)
    if pdf.is_file():
        shutil.copy2(pdf, outdir / PDF_NAME)


def _plain_status_marks(app) -> None:
    from myst_nb.ext import execution_tables

    execution_tables._key2transform["succeeded"] = (
        lambda ok: "passed" if ok is True else "failed")


def setup(app):
    app.connect("config-inited", _config_inited)
    app.connect("builder-inited", _plain_status_marks)
    # before sphinx-book-theme's header buttons (priority 501) read ipynb_source
    app.connect("html-page-context", _add_context, priority=500)
    app.connect("build-finished", _write_ledger_data)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1"}
