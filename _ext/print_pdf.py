"""Print the single-page HTML build of the book to one PDF with Chromium.

Run by ``python3 tasks.py pdf`` with the project's environment, after
``jupyter-book build . --builder singlehtml`` (which reuses the HTML build's jupyter cache, so
no chapter is executed again)::

    .venv/bin/python _ext/print_pdf.py _build/singlehtml _build/pdf/book.pdf

Why this route and not LaTeX: the book's pages are HTML with MathJax, glued figures and
sphinx-design badges; Debian's Chromium is already installed for the browser test, so the PDF
needs nothing more than Playwright (pinned in ``requirements.txt``).  A TeX Live install that
typesets this book (xelatex, the fonts for Cyrillic and Greek, latexmk, the extra packages of
sphinx-jupyterbook-latex) is about 1 GB of Debian packages and several minutes of CI per
run, and renders the badges and tables differently from the web pages that the tests check.

The printer serves the build on 127.0.0.1, opens it in Chromium (requests to any other host
are refused: the PDF is made offline), waits until MathJax has typeset every formula and every
image is decoded, then adds a title page (title, version, build date) and a table of contents,
starts each chapter on a new page and prints A4 with page numbers in the footer and a PDF
outline.  Two passes: the first print tells on which page each chapter starts (from the text
of each page, with ``pdftotext``), the second prints the table of contents with those numbers
(the same page, written into its contents: the formulas are typeset once).
"""

from __future__ import annotations

import argparse
import datetime as dt
import functools
import http.server
import json
import shutil
import subprocess
import sys
import tempfile
import threading
from pathlib import Path
from urllib.parse import urlsplit

CHROMIUM = Path("/usr/bin/chromium")
CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                 "--no-first-run", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync"]
TIMEOUT_MS = 120_000

PRINT_CSS = """
@page { size: A4; margin: 18mm 16mm 20mm 16mm; }
html, body { background: #fff !important; }
.bd-header, .bd-header-article, .header-article, .bd-sidebar-primary, .bd-sidebar-secondary,
.bd-footer, .bd-footer-article, .prev-next-area, .bd-search, .search-button-field,
.sidebar-toggle, .theme-switch-button, .headerlink, .copybtn, .toggle-details__summary,
.bd-header-announcement, #pst-back-to-top, .skip-link, .bd-footer-content, dialog,
#jb-print-docs-body {
  display: none !important; }
.bd-container, .bd-container__inner, .bd-page-width, .bd-main, .bd-content,
.bd-article-container, .bd-article { max-width: none !important; width: auto !important;
  margin: 0 !important; padding: 0 !important; display: block !important; }
pre { white-space: pre-wrap !important; word-break: break-word; }
/* a scrolling box is never split across pages: let wide tables and outputs flow instead */
.pst-scrollable-table-container, .table-wrapper, .output, .cell_output, div.highlight {
  overflow: visible !important; max-height: none !important; }
table { font-size: 8.5pt; page-break-inside: auto; }
tr, figure, img, .math { break-inside: avoid; }
h1, h2, h3 { break-after: avoid; }
section.gyrolib-chapter { break-before: page; }
.gyrolib-chapter-title, #gyrolib-title h1 { display: block !important; }
.gyrolib-chapter-title { font-size: 1.9rem !important; margin-top: 0 !important; }
#gyrolib-title { break-after: page; text-align: center; padding-top: 35mm; }
#gyrolib-title h1.gyrolib-title { font-size: 26pt; margin-bottom: 8mm; border: none; }
#gyrolib-title .gyrolib-sub { font-size: 13pt; margin-bottom: 20mm; }
#gyrolib-title .gyrolib-meta { font-size: 11pt; line-height: 1.8; }
#gyrolib-toc { break-after: page; }
#gyrolib-toc ol { list-style: none; padding-left: 0; }
#gyrolib-toc li { display: flex; gap: 0.4em; margin: 0.35em 0; }
#gyrolib-toc li .fill { flex: 1; border-bottom: 1px dotted #888; margin-bottom: 0.3em; }
#gyrolib-toc li a { color: #000; text-decoration: none; }
"""

# Wait until MathJax has typeset and every image is decoded; count what is left undone.
JS_READY = """async () => {
  const t0 = Date.now();
  if (document.querySelector('.math')) {
    while (!(window.MathJax && MathJax.startup && MathJax.startup.promise)) {
      if (Date.now() - t0 > 60000) break;
      await new Promise(r => setTimeout(r, 100));
    }
    if (window.MathJax && MathJax.startup) await MathJax.startup.promise;
  }
  for (const img of Array.from(document.images)) {
    img.loading = 'eager';
    try { await img.decode(); } catch (e) {}
  }
  await document.fonts.ready;
  const untypeset = Array.from(document.querySelectorAll('.math'))
    .filter(e => !e.querySelector('mjx-container')).length;
  const badImages = Array.from(document.images)
    .filter(i => !i.complete || i.naturalWidth === 0).map(i => i.getAttribute('src'));
  return {math: document.querySelectorAll('.math').length, untypeset, badImages};
}"""

# Title page, table of contents, one page per chapter.  In the single page, the root
# document is the article's first section, and every other chapter is the section after a
# ``<span id="document-...">`` marker (nested, so its title is an <h2>/<h3>: it is styled as a
# chapter title); the chapter titles go into the table of contents.
JS_FRONT_MATTER = """(meta) => {
  const article = document.querySelector('article.bd-article') || document.querySelector('main')
    || document.body;
  const sections = [article.querySelector('section')];
  for (const mark of Array.from(article.querySelectorAll('span[id^="document-"]'))) {
    const s = mark.nextElementSibling;
    if (s && s.tagName === 'SECTION') sections.push(s);
  }
  const chapters = [];
  sections.forEach((section, i) => {
    const h = section.querySelector(':scope > h1, :scope > h2, :scope > h3, :scope > h4');
    if (!h) return;
    if (!section.id) section.id = 'gyrolib-chapter-' + i;
    if (i > 0) section.classList.add('gyrolib-chapter');
    h.classList.add('gyrolib-chapter-title');
    const title = Array.from(h.childNodes).filter(c => !(c.classList &&
      c.classList.contains('headerlink'))).map(c => c.textContent).join('').trim();
    chapters.push({id: section.id, title});
  });
  const esc = s => s.replace(/[&<>]/g, c => ({'&': '&amp;', '<': '&lt;', '>': '&gt;'}[c]));
  const title = document.createElement('section');
  title.id = 'gyrolib-title';
  title.innerHTML = `<h1 class="gyrolib-title">${esc(meta.title)}</h1>
    <p class="gyrolib-sub">${esc(meta.subtitle)}</p>
    <p class="gyrolib-meta">Version ${esc(meta.version)}<br>Built ${esc(meta.date)}<br>
    ${esc(meta.author)}</p>`;
  const toc = document.createElement('section');
  toc.id = 'gyrolib-toc';
  toc.innerHTML = '<h2>Contents</h2><ol>' + chapters.map((c, i) =>
    `<li><a href="#${c.id}">${esc(c.title)}</a><span class="fill"></span>` +
    `<span class="page">${esc((meta.pages || {})[c.title] || '')}</span></li>`).join('') +
    '</ol>';
  article.prepend(toc);
  article.prepend(title);
  return chapters.map(c => c.title);
}"""

# The second printing: the table of contents gets each chapter's start page (the same page,
# its formulas typeset once).
JS_TOC_PAGES = """(pages) => {
  for (const li of Array.from(document.querySelectorAll('#gyrolib-toc li'))) {
    li.querySelector('.page').textContent = pages[li.querySelector('a').textContent] || '';
  }
}"""

FOOTER = ('<div style="font-size:8pt;width:100%;padding:0 16mm;display:flex;'
          'justify-content:space-between;color:#555;"><span>{title}, version {version}</span>'
          '<span>page <span class="pageNumber"></span> of <span class="totalPages"></span>'
          '</span></div>')


class _Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, format, *args):  # same signature as the base class
        pass


def _entry_page(folder: Path) -> Path:
    """The single page: the root document (the only large .html in the folder).

    Sphinx's singlehtml builder writes the root document at its own path
    (``chapters/intro.html``) but with every link relative to the output root, so the page
    is copied to the root (``_print.html``) before it is opened.
    """
    pages = [p for p in folder.rglob("*.html") if p.name != "_print.html"
             and not {"_static", "_sources"} & set(p.relative_to(folder).parts)]
    if not pages:
        raise SystemExit(f"no HTML page in {folder}: build with --builder singlehtml first")
    page = max(pages, key=lambda p: p.stat().st_size)
    at_root = folder / "_print.html"
    at_root.write_bytes(page.read_bytes())
    return at_root


def page_texts(pdf: Path) -> list[str]:
    """The text of each page of ``pdf`` (``pdftotext`` separates pages by form feeds)."""
    out = subprocess.run(["pdftotext", "-enc", "UTF-8", str(pdf), "-"], capture_output=True,
                         text=True, check=True).stdout
    texts = out.split("\f")
    return texts[:-1] if texts and not texts[-1].strip() else texts


def _norm(text: str) -> str:
    return " ".join(text.split())


def start_pages(pdf: Path, titles: list[str], after: int) -> dict[str, str]:
    """The page number (1-based) of the first page after page ``after`` (the title page and
    the table of contents come first) that begins with each chapter's title: every chapter
    starts on a new page."""
    pages = [_norm(t) for t in page_texts(pdf)]
    found, start = {}, after
    for title in titles:
        want = _norm(title)
        for i in range(start, len(pages)):
            if pages[i].startswith(want):
                found[title] = str(i + 1)
                start = i
                break
    return found


def print_book(folder: Path, out: Path, meta: dict) -> dict:
    from playwright.sync_api import sync_playwright

    entry = _entry_page(folder)
    handler = functools.partial(_Quiet, directory=str(folder))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    url = (f"http://127.0.0.1:{server.server_address[1]}/"
           f"{entry.relative_to(folder).as_posix()}")
    footer = FOOTER.format(title=meta["title"], version=meta["version"])
    report: dict = {}
    try:
        with tempfile.TemporaryDirectory(prefix="gyrolib-pdf-") as profile, \
                sync_playwright() as pw:
            context = pw.chromium.launch_persistent_context(
                profile, executable_path=str(CHROMIUM), headless=True, args=CHROMIUM_ARGS,
                service_workers="block")
            offsite: list[str] = []

            def route(r):
                host = urlsplit(r.request.url).hostname
                if urlsplit(r.request.url).scheme in ("http", "https") and host not in (
                        "127.0.0.1", "localhost"):
                    offsite.append(r.request.url)
                    r.abort("blockedbyclient")
                else:
                    r.continue_()

            context.route("**/*", route)
            try:
                page = context.new_page()
                page.set_default_timeout(TIMEOUT_MS)
                page.goto(url, wait_until="load")
                ready = page.evaluate(JS_READY)
                if ready["untypeset"] or ready["badImages"]:
                    raise SystemExit(f"not ready to print: {ready['untypeset']} formulas "
                                     f"untypeset, images not decoded: {ready['badImages']}")
                page.add_style_tag(content=PRINT_CSS)
                titles = page.evaluate(JS_FRONT_MATTER, dict(meta, pages={}))
                page.emulate_media(media="print")
                pages: dict[str, str] = {}
                for _pass in (1, 2):   # the second with the chapters' pages in the contents
                    if _pass == 2:
                        page.evaluate(JS_TOC_PAGES, pages)
                    page.pdf(path=str(out), format="A4", print_background=True,
                             display_header_footer=True, header_template="<span></span>",
                             footer_template=footer, outline=True, tagged=True,
                             margin={"top": "18mm", "bottom": "20mm", "left": "16mm",
                                     "right": "16mm"})
                    if _pass == 1:
                        toc_pages = 1 + next(i for i, t in enumerate(page_texts(out))
                                             if "Contents" in t)
                        pages = start_pages(out, titles, toc_pages)
                page.close()
                report = {"chapters": titles, "start_pages": pages, "formulas": ready["math"],
                          "offsite_requests": offsite}
            finally:
                context.close()
    finally:
        server.shutdown()
        server.server_close()
    if offsite:
        raise SystemExit(f"the book asked for pages off this machine: {offsite[:3]}")
    return report


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="Print the single-page build to a PDF.")
    ap.add_argument("folder", type=Path, help="the singlehtml build folder")
    ap.add_argument("out", type=Path, help="the PDF to write")
    ap.add_argument("--title", default="Gyro calibration, reproduced")
    ap.add_argument("--subtitle", default="A reproduction of two gyroscope-calibration papers "
                    "with the gyrolib library")
    ap.add_argument("--author", default="The gyrolib authors")
    args = ap.parse_args(argv)
    if not args.folder.is_dir() or not any(args.folder.glob("**/*.html")):
        print(f"print_pdf: no single-page build in {args.folder}: run `jupyter-book build . "
              "--builder singlehtml` first (python3 tasks.py pdf does)", file=sys.stderr)
        return 2
    for tool, what in ((CHROMIUM, "Debian's chromium"), (Path(shutil.which("pdftotext") or
                                                             "/usr/bin/pdftotext"),
                                                        "Debian's poppler-utils")):
        if not tool.exists():
            print(f"print_pdf: {tool} is missing: install {what} "
                  "(python3 tasks.py pdf does)", file=sys.stderr)
            return 2
    import gyrolib

    meta = {"title": args.title, "subtitle": args.subtitle, "author": args.author,
            "version": gyrolib.__version__,
            "date": dt.datetime.now(dt.UTC).strftime("%Y-%m-%d %H:%M UTC")}
    args.out.parent.mkdir(parents=True, exist_ok=True)
    tmp = args.out.with_suffix(".part.pdf")
    report = print_book(args.folder, tmp, meta)
    tmp.replace(args.out)
    print(json.dumps({"pdf": str(args.out), "pages": len(page_texts(args.out)),
                      "version": meta["version"], **report}, ensure_ascii=False))
    return 0


if __name__ == "__main__":
    sys.exit(main())
