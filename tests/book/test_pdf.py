"""The PDF of the whole book.

``python3 tasks.py pdf`` prints the single-page build with Chromium into
``_build/pdf/book.pdf``; the test session's book (``conftest.session_book``) is built the same
way, and these tests read its PDF and HTML.  This file extracts the
PDF's text with ``pdftotext`` (Debian's poppler-utils) and checks it against sources
independent of the PDF: the chapter titles as the HTML build shows them, every ledger id from
``gyrolib.book.ledger.collect()``, a glued number recomputed from the ledger, the version from
``gyrolib.__version__``; that the title page carries the version and a build date, that the
table of contents lists every chapter with the page it starts on, that every page has a page
number; and that the HTML build links to the PDF.  A deliberately incomplete text shows that
the content check can fail.  They are of the full tier (``python3 tasks.py test --full``):
printing the PDF is a step of the everyday run's longest chain (the session's book build).
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
from functools import cache
from pathlib import Path

import pytest

import gyrolib
from gyrolib.book import ledger
from tests.conftest import require_built_book, session_book

#: the full tier (``--full``): the session's book build prints the PDF only there
pytestmark = [pytest.mark.book, pytest.mark.full]

ROOT = Path(__file__).resolve().parents[2]


def _norm(text: str) -> str:
    return " ".join(text.replace("\u00ad", "").split())


def missing(text: str, needles: list[str]) -> list[str]:
    """The needles not in ``text``; whitespace (line and page breaks) does not count."""
    flat = "".join(text.split())
    return [n for n in needles if "".join(n.split()) not in flat]


@cache
def pages() -> tuple[str, ...]:
    required = os.environ.get("GYROLIB_TEST_COMMAND") == "1"  # set by `python3 tasks.py test`
    if shutil.which("pdftotext") is None:
        if required:
            pytest.fail("pdftotext is missing: `python3 tasks.py test` installs poppler-utils")
        pytest.skip("pdftotext (Debian's poppler-utils) is needed to read the PDF")
    book = session_book()
    if not book.pdf.is_file():
        if required or os.environ.get("GYROLIB_REQUIRE_BROWSER") == "1":
            pytest.fail(f"no PDF of the book: {book.pdf_error}")
        pytest.skip(f"no PDF of the book: {book.pdf_error}")
    out = subprocess.run(["pdftotext", "-enc", "UTF-8", str(book.pdf), "-"],
                         capture_output=True, text=True, check=True).stdout
    return tuple(out.split("\f")[:-1] if out.endswith("\f") else out.split("\f"))


def chapter_titles() -> list[str]:
    """Each chapter's title as its HTML page shows it (the <h1>), in the table-of-contents
    order."""
    import yaml

    bs4 = pytest.importorskip("bs4")
    HTML = require_built_book()
    toc = yaml.safe_load((ROOT / "_toc.yml").read_text(encoding="utf-8"))
    docs = [toc["root"]] + [c["file"] for part in toc.get("parts", [])
                            for c in part.get("chapters", [])]
    titles = []
    for doc in docs:
        soup = bs4.BeautifulSoup((HTML / f"{doc}.html").read_text(encoding="utf-8"),
                                 "html.parser")
        h1 = soup.select_one("article h1") or soup.find("h1")
        for a in h1.select("a.headerlink"):
            a.decompose()
        titles.append(_norm(h1.get_text()))
    return titles


def test_pdf_has_every_chapter_every_ledger_id_and_a_glued_number():
    text = "\n".join(pages())
    titles = chapter_titles()
    assert len(titles) >= 10
    items = {it.id: it for it in ledger.collect()}
    sig = items["gc.sigma_gc_100s"]  # glued into the intro and the ledger at its precision
    glued = f"{ledger.rounded(sig.reproduced_value, sig.precision):.{sig.precision}g}"
    problems = missing(text, titles + list(items) + [glued])
    assert not problems, f"not in the PDF's text: {problems}"


def test_title_page_table_of_contents_and_page_numbers():
    pdf = pages()
    n = len(pdf)
    assert n > 20, f"only {n} pages"
    title = _norm(pdf[0])
    assert "Gyro calibration, reproduced" in title
    assert f"Version {gyrolib.__version__}" in title, title[:300]
    assert re.search(r"Built \d{4}-\d{2}-\d{2} \d{2}:\d{2} UTC", title), title[:300]
    # every page carries "page i of n" in its footer
    unnumbered = [i + 1 for i, p in enumerate(pdf) if f"page {i + 1} of {n}" not in _norm(p)]
    assert not unnumbered, f"pages without their number: {unnumbered[:10]}"
    # the table of contents: every chapter with a page number, and the chapter's title is on
    # that page
    toc_at = next(i for i, p in enumerate(pdf) if "Contents" in p)
    toc = _norm(pdf[toc_at])
    wrong = []
    for title_ in chapter_titles():
        m = re.search(re.escape(title_) + r"\s+(\d+)\b", toc)
        if not m:
            wrong.append(f"{title_!r}: not in the table of contents with a page number")
        elif title_ not in _norm(pdf[int(m.group(1)) - 1]):
            wrong.append(f"{title_!r}: not on page {m.group(1)}")
    assert not wrong, wrong


def test_the_content_check_can_fail():
    text = "\n".join(pages())
    first_id = ledger.collect()[0].id
    assert missing(text.replace(first_id, "x"), [first_id]) == [first_id]
    assert missing("The reproduction\nledger", ["The reproduction ledger"]) == []


def test_html_links_to_the_pdf():
    pages()
    HTML = require_built_book()
    assert (HTML / "book.pdf").read_bytes() == session_book().pdf.read_bytes(), \
        "_build/html/book.pdf is not the current PDF"
    intro = (HTML / "chapters" / "intro.html").read_text(encoding="utf-8")
    assert re.search(r'<a class="gyrolib-pdf-link" href="\.\./book\.pdf"', intro), \
        "the intro page's footer does not link ../book.pdf"
