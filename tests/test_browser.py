"""The built book in a real browser (issue 8, item 1).

Playwright (sync API) drives Debian's Chromium (``/usr/bin/chromium``; ``python3 tasks.py test``
installs it, ``playwright install`` is never used) over ``_build/html`` served on 127.0.0.1.
Every page of the book is opened, and the test asserts, collecting all problems first:

* no console error and no uncaught exception;
* no failed request (network error or HTTP status >= 400);
* no request leaves the machine: every request is routed, and one to any host other than
  127.0.0.1/localhost is aborted and reported (the book must read offline);
* every ``<img>`` is decoded (``naturalWidth > 0``);
* where a page has math, MathJax typeset it: one ``mjx-container`` per math element, no MathJax
  error, and no raw ``$$``, ``\\[``, ``\\(`` or ``\\begin{`` left in the visible text;
* no accessibility violation: axe-core runs every rule tagged WCAG 2.0 or 2.1, level A or AA
  (the experimental ones too, such as label-content-name-mismatch) on the settled page.
  axe-core comes inside the pinned ``axe-playwright-python`` wheel (``axe.min.js``) and is
  injected into the page by Playwright: nothing is fetched.  A page with an injected
  low-contrast paragraph shows that the check can fail.

Further tests: the ledger page shows its table; the search page finds "gyrocompass";
screenshots of the landing page and one chapter are saved in ``_build/screenshots/``.

The pages are those of the test session's book (``conftest.session_book``).
"""

from __future__ import annotations

import functools
import http.server
import os
import re
import tempfile
import threading
from collections.abc import Iterator
from pathlib import Path
from urllib.parse import urlsplit

import pytest
from conftest import require_built_book

pytestmark = pytest.mark.browser

ROOT = Path(__file__).resolve().parents[1]
SHOTS = ROOT / "_build" / "screenshots"
CHROMIUM = Path("/usr/bin/chromium")
CHROMIUM_ARGS = [
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
    # Containers often have a small /dev/shm; Chromium then crashes on large pages.
    "--disable-dev-shm-usage",
]
LOCAL_HOSTS = {"127.0.0.1", "localhost"}
TIMEOUT_MS = 30_000
RAW_MATH = ("$$", "\\[", "\\(", "\\begin{")
SEARCH_TERM = "gyrocompass"
AXE_TAGS = ("wcag2a", "wcag2aa", "wcag21a", "wcag21aa")


# ----------------------------------------------------------------------------- fixtures


def book_pages(root: Path) -> list[str]:
    """Every HTML page of the book, as a URL path relative to the root (search.html included;
    the theme's template fragments in _static are not pages)."""
    skip = {"_static", "_sources", "_images", "_downloads"}
    return sorted(p.relative_to(root).as_posix() for p in root.rglob("*.html")
                  if not skip.intersection(p.relative_to(root).parts[:-1]))


class _QuietHandler(http.server.SimpleHTTPRequestHandler):
    def log_message(self, format, *args):  # same signature as the base class
        pass


@pytest.fixture(scope="session")
def site() -> Iterator[str]:
    """Serve _build/html on 127.0.0.1 (ephemeral port); yields the base URL."""
    handler = functools.partial(_QuietHandler, directory=str(require_built_book()))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}/"
    finally:
        server.shutdown()
        server.server_close()
        thread.join(timeout=5)


class Browser:
    """A Chromium context whose every request is routed: off-machine ones are aborted."""

    def __init__(self, context):
        self.context = context
        self.offsite: list[str] = []
        context.set_default_timeout(TIMEOUT_MS)
        context.route("**/*", self._route)

    def _route(self, route):
        url = route.request.url
        parts = urlsplit(url)
        if parts.scheme in ("http", "https", "ws", "wss") and parts.hostname not in LOCAL_HOSTS:
            self.offsite.append(url)
            route.abort("blockedbyclient")
        else:
            route.continue_()

    def open(self, url: str):
        """A new page with its console errors and failed requests recorded."""
        page = self.context.new_page()
        page.problems = []

        def on_console(msg):
            if msg.type == "error":
                where = msg.location.get("url", "") if msg.location else ""
                page.problems.append(f"console error: {msg.text}" + (f" ({where})"
                                                                     if where else ""))

        def on_failed(request):
            if urlsplit(request.url).hostname in LOCAL_HOSTS:  # off-site ones: see .offsite
                page.problems.append(f"failed request: {request.url} ({request.failure})")

        def on_response(response):
            if response.status >= 400:
                page.problems.append(f"HTTP {response.status}: {response.url}")

        page.on("console", on_console)
        page.on("pageerror", lambda exc: page.problems.append(f"uncaught exception: {exc}"))
        page.on("requestfailed", on_failed)
        page.on("response", on_response)
        return page


@pytest.fixture(scope="session")
def browser(site) -> Iterator[Browser]:
    if not CHROMIUM.exists():
        if os.environ.get("GYROLIB_REQUIRE_BROWSER") == "1":  # set by .ci/run
            pytest.fail("no /usr/bin/chromium, but CI requires the browser test to run")
        pytest.skip("no Chromium: install Debian's chromium, as `python3 tasks.py test` does")
    sync_api = pytest.importorskip("playwright.sync_api",
                                   reason="playwright is pinned in requirements.txt")
    with tempfile.TemporaryDirectory(prefix="gyrolib-chromium-") as profile, \
            sync_api.sync_playwright() as pw:
        context = pw.chromium.launch_persistent_context(
            profile, executable_path=str(CHROMIUM), headless=True, args=CHROMIUM_ARGS,
            viewport={"width": 1280, "height": 900}, service_workers="block",
        )
        try:
            yield Browser(context)
        finally:
            context.close()


# ----------------------------------------------------------------------------- in the page

# Decode every image (scrolled into view, so lazy ones load too); list those that fail.
JS_UNDECODED_IMAGES = """async () => {
  const bad = [];
  for (const img of Array.from(document.images)) {
    img.loading = 'eager';
    img.scrollIntoView({block: 'center'});
    try { await img.decode(); } catch (e) { /* reported below */ }
    if (!img.complete || img.naturalWidth === 0) {
      bad.push(img.currentSrc || img.getAttribute('src') || img.outerHTML.slice(0, 120));
    }
  }
  window.scrollTo(0, 0);
  return bad;
}"""

# Wait for MathJax to finish typesetting; report how much math there is and how it went.
JS_MATH_REPORT = """async () => {
  const math = document.querySelectorAll('.math').length;
  if (math === 0) return {math: 0};
  const t0 = Date.now();
  while (!(window.MathJax && MathJax.startup && MathJax.startup.promise)) {
    if (Date.now() - t0 > 15000) break;
    await new Promise(r => setTimeout(r, 50));
  }
  const loaded = !!(window.MathJax && MathJax.startup && MathJax.startup.promise);
  if (loaded) await MathJax.startup.promise;
  const article = document.querySelector('article.bd-article, main') || document.body;
  const skip = 'pre, code, script, style, textarea, mjx-container, .highlight';
  const walker = document.createTreeWalker(article, NodeFilter.SHOW_TEXT);
  let text = '';
  for (let n = walker.nextNode(); n; n = walker.nextNode()) {
    const el = n.parentElement;
    if (!el || el.closest(skip)) continue;
    if (el.checkVisibility && !el.checkVisibility()) continue;
    text += n.data + '\\n';
  }
  const untypeset = Array.from(document.querySelectorAll('.math'))
    .filter(e => !e.querySelector('mjx-container'))
    .map(e => e.textContent.trim().slice(0, 60));
  const errors = Array.from(document.querySelectorAll('mjx-merror'))
    .map(e => e.getAttribute('data-mjx-error') || e.textContent);
  // MathJax's noundefined package shows an unknown macro as red text instead of an error.
  const undefinedMacros = Array.from(
    document.querySelectorAll('mjx-assistive-mml mtext[mathcolor="red"]'))
    .map(e => 'undefined macro ' + e.textContent);
  return {math, loaded, untypeset, errors: errors.concat(undefinedMacros), text};
}"""


# Fonts loaded and two animation frames drawn: the layout is final.
JS_SETTLED = """async () => {
  await document.fonts.ready;
  await new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)));
  return [window.scrollX, document.documentElement.scrollHeight];
}"""


META_REFRESH = re.compile(r"<meta[^>]+http-equiv=[\"']?refresh", re.IGNORECASE)


def _visit(browser: Browser, url: str):
    """Open url, following a <meta refresh> (index.html) to the page it leads to."""
    page = browser.open(url)
    source = require_built_book() / urlsplit(url).path.lstrip("/")
    redirects = source.is_file() and bool(META_REFRESH.search(source.read_text()))
    page.goto(url, wait_until="load")
    if redirects:
        page.wait_for_url(lambda u: u != url)
        page.wait_for_load_state("load")
    return page


def _check_math(page) -> list[str]:
    report = page.evaluate(JS_MATH_REPORT)
    if not report["math"]:
        return []
    problems = []
    if not report["loaded"]:
        problems.append(f"{report['math']} math elements but MathJax never started")
    elif report["untypeset"]:
        problems.append(f"MathJax left {len(report['untypeset'])} of {report['math']} math "
                        f"elements untypeset, e.g. {report['untypeset'][:3]}")
    problems += [f"MathJax error: {e}" for e in dict.fromkeys(report.get("errors", []))]
    text = report.get("text", "")
    for raw in RAW_MATH:
        at = text.find(raw)
        if at >= 0:
            snippet = " ".join(text[max(0, at - 30): at + 50].split())
            problems.append(f"raw {raw!r} left in the visible text: …{snippet}…")
    return problems


@functools.cache
def _axe():
    """axe-playwright-python's Axe: axe-core's script from the installed wheel."""
    try:
        from axe_playwright_python.sync_playwright import Axe
    except ImportError:
        if (os.environ.get("GYROLIB_REQUIRE_BROWSER") == "1"
                or os.environ.get("GYROLIB_TEST_COMMAND") == "1"):
            pytest.fail("axe-playwright-python (pinned in requirements.txt) is not installed")
        pytest.skip("axe-playwright-python (pinned in requirements.txt) is not installed")
    return Axe()


def axe_violations(page) -> list[str]:
    """axe-core's violations of the WCAG 2.0/2.1 A and AA rules on the page, one line each
    (rule, impact, help, the offending elements)."""
    axe = _axe()
    page.evaluate(axe.axe_script)  # to list the rules: every one with these tags
    rules = page.evaluate("tags => axe.getRules(tags).map(r => r.ruleId)", list(AXE_TAGS))
    assert "color-contrast" in rules and "label-content-name-mismatch" in rules, rules
    results = axe.run(page, options={"runOnly": {"type": "rule", "values": rules},
                                     "resultTypes": ["violations"]})
    return [f"axe {v['id']} ({v['impact']}): {v['help']}: "
            + "; ".join(" ".join(n["html"].split())[:160] for n in v["nodes"][:5])
            + (f" (+{len(v['nodes']) - 5} more)" if len(v["nodes"]) > 5 else "")
            for v in results.response["violations"]]


# ----------------------------------------------------------------------------- tests


#: The pages are checked in this many shares (every SHARES-th page each), so that pytest-xdist
#: workers can check them side by side; together the shares cover every page.
SHARES = 2


@pytest.mark.parametrize("share", range(SHARES))
def test_every_page_is_clean_in_a_real_browser(site, browser, share):
    pages = book_pages(require_built_book())
    assert "search.html" in pages and "chapters/intro.html" in pages, pages
    problems: list[str] = []
    for rel in pages[share::SHARES]:
        url = site + rel
        browser.offsite.clear()
        page = _visit(browser, url)
        try:
            found = []
            found += [f"<img> not decoded: {src}" for src in page.evaluate(JS_UNDECODED_IMAGES)]
            found += _check_math(page)
            page.wait_for_load_state("networkidle")
            found += page.problems
            found += [f"request leaves localhost (aborted): {u}"
                      for u in dict.fromkeys(browser.offsite)]
            # after the page's own requests: axe-core preloads the stylesheets itself and
            # resolves theme.css's `@import "../basic.css"` against the page (a 404 of its
            # own making, not the book's)
            found += axe_violations(page)
        finally:
            page.close()
        problems += [f"{rel}: {p}" for p in dict.fromkeys(found)]
    assert not problems, (f"{len(problems)} problems over {len(pages[share::SHARES])} pages:\n  "
                          + "\n  ".join(problems))


def test_the_accessibility_check_finds_an_injected_low_contrast_element(site, browser):
    """The same check on a page of the book with one paragraph of light grey on white
    (#aaaaaa on #ffffff, 2.3:1) added: axe-core reports it, and only it."""
    page = _visit(browser, site + "chapters/intro.html")
    try:
        page.evaluate("""() => {
          const p = document.createElement('p');
          p.id = 'gyrolib-low-contrast';
          p.textContent = 'A paragraph that is hard to read.';
          p.style.cssText = 'color: #aaaaaa; background: #ffffff';
          document.querySelector('article.bd-article').appendChild(p);
        }""")
        found = axe_violations(page)
    finally:
        page.close()
    assert len(found) == 1 and found[0].startswith("axe color-contrast"), found
    assert "gyrolib-low-contrast" in found[0], found


def _ledger_items() -> int | None:
    """How many items gyrolib's ledger has (the page must show them all), if importable."""
    try:
        from gyrolib.book.ledger import collect
    except ImportError:
        return None
    return len(collect())


def test_ledger_page_shows_its_table(site, browser):
    page = _visit(browser, site + "chapters/ledger.html")
    try:
        article = page.locator("article.bd-article")
        if "in preparation" in article.inner_text().lower():
            pytest.skip("chapters/ledger.html says it is in preparation: no ledger table yet")
        tables = article.locator("table")
        assert tables.count() >= 1, "the ledger page has no <table>"
        problems, rows = [], 0
        for i in range(tables.count()):
            table = tables.nth(i)
            section = table.evaluate(
                "t => (t.closest('section')?.querySelector('h1,h2,h3')?.textContent || '')"
                ".replace('#', '').trim()")
            n = table.locator("tbody tr").count()
            rows += n
            if n == 0:
                problems.append(f"table {i + 1} (section {section!r}) has a header but no rows")
            if not table.is_visible():
                problems.append(f"table {i + 1} (section {section!r}) is not visible")
        expected = _ledger_items()
        if expected is not None and rows != expected:
            problems.append(f"the page shows {rows} ledger rows but gyrolib.book.ledger.collect() "
                            f"has {expected} items (stale build?)")
        assert not problems, "ledger page:\n  " + "\n  ".join(problems)
    finally:
        page.close()


def test_search_finds_a_term(site, browser):
    page = _visit(browser, site + f"search.html?q={SEARCH_TERM}")
    try:
        results = page.locator("#search-results ul.search li")
        try:
            results.first.wait_for(state="attached", timeout=TIMEOUT_MS)
        except Exception:  # playwright's TimeoutError: report what the page says instead
            summary = page.locator("#search-results").inner_text() or "(no #search-results)"
            pytest.fail(f"search for {SEARCH_TERM!r} found nothing: {summary[:300]!r}")
        hits = [results.nth(i).locator("a").first.get_attribute("href")
                for i in range(results.count())]
        assert hits and all(hits), hits
        # Independent check: every hit is a page of the book whose text has the term.
        wrong = []
        for href in hits:
            target = require_built_book() / urlsplit(href).path.lstrip("/")
            if not target.is_file() or SEARCH_TERM not in target.read_text().lower():
                wrong.append(href)
        assert not wrong, f"search hits without {SEARCH_TERM!r} in the page: {wrong}"
    finally:
        page.close()


def test_screenshots_of_landing_page_and_a_chapter(site, browser):
    SHOTS.mkdir(parents=True, exist_ok=True)
    # The first chapter (in reading order) with a figure, else the first chapter.
    html = require_built_book()
    chapters = [c for c in ("gc_model", "gc_filter", "gc_claims", "rsf_method",
                            "rsf_simulation") if (html / "chapters" / f"{c}.html").is_file()]
    assert chapters, "no chapter page to photograph"
    chapter = next((c for c in chapters
                    if "<figure" in (html / "chapters" / f"{c}.html").read_text()), chapters[0])
    for old in SHOTS.glob("chapter-*.png"):  # a previous run may have photographed another
        old.unlink()
    shots = {"landing.png": "index.html", f"chapter-{chapter}.png": f"chapters/{chapter}.html"}
    for name, rel in shots.items():
        page = _visit(browser, site + rel)
        try:
            # Let MathJax, fonts and the theme's layout settle before the picture.
            page.evaluate(JS_MATH_REPORT)
            page.wait_for_load_state("networkidle")
            page.evaluate(JS_SETTLED)
            page.screenshot(path=str(SHOTS / name), full_page=True, animations="disabled")
        finally:
            page.close()
        png = (SHOTS / name).read_bytes()
        assert png[:8] == b"\x89PNG\r\n\x1a\n", f"{name} is not a PNG"
        width, height = int.from_bytes(png[16:20], "big"), int.from_bytes(png[20:24], "big")
        assert width == 1280 and height >= 900, f"{name}: {width}x{height}"


def test_every_page_declares_a_favicon_that_loads(site, browser):
    """No page load asks for a missing /favicon.ico: each page names its icon, which loads."""
    page = _visit(browser, site + "chapters/intro.html")
    try:
        icon = page.evaluate("""async () => {
          const link = document.querySelector('link[rel~="icon"]');
          if (!link) return null;
          const r = await fetch(link.href);
          return {href: link.href, status: r.status, type: r.headers.get('content-type'),
                  body: (await r.text()).slice(0, 200)};
        }""")
    finally:
        page.close()
    assert icon is not None, "the page has no <link rel=icon>"
    assert icon["status"] == 200 and "svg" in (icon["type"] or ""), icon
    assert "<svg" in icon["body"], icon
    html = require_built_book()
    missing = [rel for rel in book_pages(html) if 'rel="icon"' not in (html / rel).read_text()
               and "Refresh" not in (html / rel).read_text()[:2000]]
    assert not missing, f"pages without a favicon link: {missing}"
