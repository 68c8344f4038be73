"""The built book in a real browser.

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
  low-contrast paragraph shows that the check can fail;
* the layout at 1280 px: the page does not scroll sideways, no output block runs
  past its box (outputs wrap), no other text spills out of a box that does not scroll; every
  raster figure has at least 1.5 image pixels per CSS pixel it is shown at, and is not
  distorted.  Small pages written by the tests (no book needed), and a book page with an
  injected long output line and 72-dpi figure, show that each check can fail; the print
  stylesheet is checked the same way (no "Show code cell source" toggle, no empty box).

Further tests: the ledger page shows its table; the search page finds "gyrocompass";
screenshots of the landing page and one chapter are saved in ``_build/screenshots/``.

The pages are those of the test session's book (``conftest.session_book``).
"""

from __future__ import annotations

import contextlib
import functools
import http.server
import os
import re
import tempfile
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from types import SimpleNamespace
from urllib.parse import urlsplit

import pytest

from tests.conftest import require_built_book

pytestmark = pytest.mark.browser

ROOT = Path(__file__).resolve().parents[2]
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

        page.inflight = set()      # requests made and not yet finished or failed

        def on_request(request):
            page.inflight.add(request)

        def on_done(request):
            page.inflight.discard(request)

        page.on("console", on_console)
        page.on("pageerror", lambda exc: page.problems.append(f"uncaught exception: {exc}"))
        page.on("request", on_request)
        page.on("requestfinished", on_done)
        page.on("requestfailed", on_done)
        page.on("requestfailed", on_failed)
        page.on("response", on_response)
        return page

    @staticmethod
    def settle(page) -> None:
        """Wait until every request the page made has finished (or failed), its fonts are
        loaded and two frames drawn, and still no request is in flight: the layout and the
        list of requests are final.  (Playwright's "networkidle" waits a fixed 500 ms of
        quiet instead, on every page.)"""
        deadline = time.monotonic() + TIMEOUT_MS / 1000.0
        for _ in range(2):
            while page.inflight:
                if time.monotonic() > deadline:
                    pytest.fail(f"{page.url}: requests still in flight after "
                                f"{TIMEOUT_MS / 1000:.0f} s: "
                                f"{[r.url for r in page.inflight][:5]}")
                page.wait_for_timeout(20)
            page.evaluate(JS_SETTLED)


@pytest.fixture(scope="session")
def _playwright():
    """Playwright, once per session (the book's browser and the small pages' share it)."""
    if not CHROMIUM.exists():
        if os.environ.get("GYROLIB_REQUIRE_BROWSER") == "1":  # set by .ci/run
            pytest.fail("no /usr/bin/chromium, but CI requires the browser test to run")
        pytest.skip("no Chromium: install Debian's chromium, as `python3 tasks.py test` does")
    sync_api = pytest.importorskip("playwright.sync_api",
                                   reason="playwright is pinned in requirements.txt")
    with sync_api.sync_playwright() as pw:
        yield pw


@pytest.fixture(scope="session")
def small_pages(_playwright):
    """A Chromium context at 1280 px for small pages written by the tests (no book needed),
    on which the layout checks show that they can fail."""
    chromium = _playwright.chromium.launch(executable_path=str(CHROMIUM), headless=True,
                                           args=CHROMIUM_ARGS)
    try:
        context = chromium.new_context(viewport={"width": 1280, "height": 900})
        context.set_default_timeout(TIMEOUT_MS)
        context.route("**/*", lambda route: route.abort("blockedbyclient"))
        yield context
    finally:
        chromium.close()


@pytest.fixture(scope="session")
def browser(site, _playwright) -> Iterator[Browser]:
    pw = _playwright
    with tempfile.TemporaryDirectory(prefix="gyrolib-chromium-") as profile:
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


# Layout.  Two ways to run past a box:
# * an output block (a ``<pre>`` of a cell's output, e.g. the CLI output or a ledger citation
#   line) whose lines are wider than the block: outputs must wrap, since a reader scrolling
#   a block sideways loses the end of every line (a scroll bar counts as running past);
# * any other element of the article whose content is wider than its box while neither it
#   nor an ancestor inside the article scrolls it: the text spills over the margin (code
#   cells' input and wide tables may scroll inside their box).  Only the innermost such
#   element is reported.
# The page itself must not scroll sideways at all.
JS_OVERFLOW = """() => {
  const root = document.documentElement;
  const article = document.querySelector('article.bd-article') || document.querySelector('main')
    || document.body;
  const scrolls = new Set(['auto', 'scroll']);
  const visible = el => el.clientWidth > 0 && (!el.checkVisibility || el.checkVisibility());
  const wide = el => el.scrollWidth > el.clientWidth + 1;
  const isOutput = el => el.tagName === 'PRE' && !!el.closest('.cell_output, .output')
                         && !el.closest('.cell_input');
  const spills = el => visible(el) && wide(el) && !scrolls.has(getComputedStyle(el).overflowX);
  const contained = el => {  /* inside a box of the article that scrolls it */
    for (let a = el.parentElement; a && a !== article; a = a.parentElement) {
      if (scrolls.has(getComputedStyle(a).overflowX)) return true;
    }
    return false;
  };
  const describe = el => ({
    tag: el.tagName.toLowerCase() + (el.className && typeof el.className === 'string'
           ? '.' + el.className.trim().split(/\\s+/).slice(0, 2).join('.') : ''),
    box: el.clientWidth, content: el.scrollWidth,
    text: (el.innerText || '').trim().split('\\n')[0].slice(0, 80)});
  const outputs = Array.from(article.querySelectorAll('pre'))
    .filter(el => isOutput(el) && visible(el) && wide(el));
  const all = Array.from(article.querySelectorAll('*')).filter(spills);
  const inner = all.filter(el => !all.some(o => o !== el && el.contains(o)))
                   .filter(el => !contained(el) && !outputs.some(o => o.contains(el)));
  return {
    page: root.scrollWidth > root.clientWidth + 1 ? [root.scrollWidth, root.clientWidth] : null,
    outputs: outputs.map(describe),
    boxes: inner.map(describe),
  };
}"""

# Every raster figure of the article, decoded: its natural width against the CSS width it is
# shown at.  A ratio of 2 is a 2x ("retina") image; 1 is an image shown pixel for pixel (e.g.
# a 72-dpi figure at its own size), which looks blurred on a high-density screen and in print.
JS_FIGURE_DENSITY = """async () => {
  const article = document.querySelector('article.bd-article') || document.querySelector('main')
    || document.body;
  const out = [];
  for (const img of Array.from(article.querySelectorAll('img'))) {
    img.loading = 'eager';
    try { await img.decode(); } catch (e) { continue; }  /* undecoded: reported elsewhere */
    const src = img.currentSrc || img.src;
    if (/\\.svg($|\\?)/i.test(src) || src.startsWith('data:image/svg')) continue;  /* vector */
    const shown = img.getBoundingClientRect().width;
    if (shown === 0 || img.naturalWidth === 0) continue;
    const box = img.getBoundingClientRect();
    out.push({src: src.split('/').pop().slice(0, 40), natural: img.naturalWidth,
              shown: Math.round(shown * 10) / 10,
              aspect: box.width / box.height, naturalAspect: img.naturalWidth / img.naturalHeight});
  }
  return out;
}"""

#: Pixels a figure must have per CSS pixel shown: the issue's "shown at no more than two
#: thirds of their pixel width", i.e. 1.5 (a 2x image on screen, 144 dpi in print).
MIN_FIGURE_DENSITY = 1.5


def overflow_problems(page) -> list[str]:
    """What runs past its box on the page (the page itself scrolling sideways, or an element
    of the article whose content spills out of it), one line each."""
    report = page.evaluate(JS_OVERFLOW)
    found = []
    if report["page"]:
        found.append(f"the page scrolls sideways: {report['page'][0]} px wide in a "
                     f"{report['page'][1]} px window")
    found += [f"output block <{b['tag']}> runs past its box ({b['content']} px of lines in "
              f"{b['box']} px; outputs must wrap): {b['text']!r}" for b in report["outputs"]]
    found += [f"<{b['tag']}> runs past its box ({b['content']} px of content in "
              f"{b['box']} px): {b['text']!r}" for b in report["boxes"]]
    return found


def density_problems(page) -> list[str]:
    """Raster figures shown at more than 1/MIN_FIGURE_DENSITY of their pixel width, or
    distorted (shown with an aspect ratio more than 2 % off their own)."""
    found = []
    for f in page.evaluate(JS_FIGURE_DENSITY):
        if f["natural"] / f["shown"] < MIN_FIGURE_DENSITY - 1e-6:
            found.append(f"figure {f['src']} has {f['natural']} px shown at {f['shown']} CSS "
                         f"px ({f['natural'] / f['shown']:.2f} px per CSS px; at least "
                         f"{MIN_FIGURE_DENSITY})")
        if abs(f["aspect"] / f["naturalAspect"] - 1) > 0.02:
            found.append(f"figure {f['src']} is distorted: shown at an aspect ratio of "
                         f"{f['aspect']:.3f}, drawn at {f['naturalAspect']:.3f}")
    return found


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


#: Regions whose text colour is checked by :data:`JS_REGION_CONTRAST` instead of axe-core's
#: ``color-contrast`` rule (profiled: that rule was 70-85 % of the browser tests'
#: time, mostly spent node by node on MathJax's glyphs, about 8 000 elements on gc_model, and
#: on every highlighted token of a code cell and line of an output).  Every other rule still
#: runs on the whole page, and ``color-contrast`` on everything outside these regions.
CONTRAST_REGIONS = ("mjx-container", "div.highlight", "div.cell_output")

# WCAG 2.x contrast of the text in the CONTRAST_REGIONS, computed from first principles: each
# text-bearing element (a text node's parent, or a MathJax glyph, drawn by CSS) against its
# background, the background colours of its ancestors composited over white up to the first
# opaque one; the colour's alpha times the ancestors' opacity.  A background image in the
# chain cannot be judged this way and is reported.  Large text (24 px, or 18.66 px bold)
# needs 3:1, other text 4.5:1 (WCAG 1.4.3, as axe-core's rule).  Distinct (colour,
# background, size) triples are computed once.
JS_REGION_CONTRAST = """(selectors) => {
  const rgba = c => {
    const m = /rgba?\\(([^)]*)\\)/.exec(c || '');
    if (!m) return null;
    const p = m[1].split(/[\\s,\\/]+/).filter(Boolean).map(Number);
    return [p[0], p[1], p[2], p.length > 3 ? p[3] : 1];
  };
  const over = (top, bottom) => [0, 1, 2].map(i => top[i] * top[3] + bottom[i] * (1 - top[3]))
    .concat([1]);
  const lum = c => {
    const f = x => { x /= 255; return x <= 0.03928 ? x / 12.92 : ((x + 0.055) / 1.055) ** 2.4; };
    return 0.2126 * f(c[0]) + 0.7152 * f(c[1]) + 0.0722 * f(c[2]);
  };
  const background = el => {
    const layers = [];
    let opacity = 1;
    for (let a = el; a; a = a.parentElement) {
      const s = getComputedStyle(a);
      opacity *= Number(s.opacity);
      if (s.backgroundImage && s.backgroundImage !== 'none') return {image: a};
      const c = rgba(s.backgroundColor);
      if (c && c[3] > 0 && !layers.some(l => l[3] >= 1)) layers.push(c);
    }
    let bg = [255, 255, 255, 1];
    for (let i = layers.length - 1; i >= 0; i--) bg = over(layers[i], bg);
    return {bg, opacity};
  };
  const seen = new Set(), memo = new Map(), bad = [];
  let checked = 0;
  const judge = (el, sample) => {
    if (seen.has(el)) return;
    seen.add(el);
    if (el.checkVisibility && !el.checkVisibility()) return;
    const s = getComputedStyle(el);
    const b = background(el);
    const where = (el.closest(selectors.join(',')) || el).tagName.toLowerCase();
    if (b.image) {
      bad.push({where, text: sample, why: 'a background image behind the text'});
      return;
    }
    const size = parseFloat(s.fontSize), bold = Number(s.fontWeight) >= 700;
    const key = [s.color, b.bg.join(','), b.opacity, size >= 24 || (bold && size >= 18.66)]
      .join('|');
    checked += 1;
    const c = rgba(s.color);
    if (!c) {
      bad.push({where, text: sample, why: `a colour this check cannot read: ${s.color}`});
      return;
    }
    if (!memo.has(key)) {
      const fg = over([c[0], c[1], c[2], c[3] * b.opacity], b.bg);
      const [hi, lo] = [lum(fg), lum(b.bg)].sort((x, y) => y - x);
      memo.set(key, {ratio: (hi + 0.05) / (lo + 0.05),
                     need: size >= 24 || (bold && size >= 18.66) ? 3 : 4.5, color: s.color,
                     bg: 'rgb(' + b.bg.slice(0, 3).map(Math.round).join(', ') + ')'});
    }
    const r = memo.get(key);
    if (r.ratio < r.need - 1e-9) {
      bad.push({where, text: sample, why: `contrast ${r.ratio.toFixed(2)}:1, needs ` +
                `${r.need}:1 (${r.color} on ${r.bg})`, id: el.id || ''});
    }
  };
  for (const region of document.querySelectorAll(selectors.join(','))) {
    const walker = document.createTreeWalker(region, NodeFilter.SHOW_TEXT);
    for (let n = walker.nextNode(); n; n = walker.nextNode()) {
      if (n.data.trim() && n.parentElement && !n.parentElement.closest('mjx-assistive-mml')) {
        judge(n.parentElement, n.data.trim().slice(0, 40));
      }
    }
    for (const g of region.querySelectorAll('mjx-c, mjx-utext')) judge(g, 'a MathJax glyph');
  }
  // one line per (region, reason, id), with how many elements share it
  const lines = new Map();
  for (const b of bad) {
    const k = [b.where, b.why, b.id || ''].join('|');
    if (lines.has(k)) lines.get(k).count += 1; else lines.set(k, {...b, count: 1});
  }
  return {checked, bad: Array.from(lines.values())};
}"""


#: axe-core's ``color-contrast`` rule on the elements outside :data:`CONTRAST_REGIONS` (its
#: selector, ``*`` by default): on gc_race it tests the same 471 elements as a run with the
#: regions excluded from the context.
CONTRAST_OUTSIDE_REGIONS = "*" + "".join(f":not({s}):not({s} *)" for s in CONTRAST_REGIONS)

# One axe-core run of ``rules``, ``color-contrast`` restricted by its selector: one pass of
# axe's set-up over the page (about 0.3 CPU-s on gc_race) where a run of the other rules and
# a second of ``color-contrast`` with the regions excluded made two.  Each call injects axe
# afresh (axe_violations), so the changed selector lasts for this run only.
JS_AXE_RUN = """async ([rules, contrastSelector]) => {
  axe.configure({rules: [{id: 'color-contrast', selector: contrastSelector}]});
  const r = await axe.run(document, {runOnly: {type: 'rule', values: rules},
                                     resultTypes: ['violations']});
  const ran = [...r.violations, ...r.passes, ...r.incomplete, ...r.inapplicable]
    .map(x => x.id);
  return {violations: r.violations, ran};
}"""


def axe_violations(page) -> list[str]:
    """axe-core's violations of the WCAG 2.0/2.1 A and AA rules on the page, one line each
    (rule, impact, help, the offending elements), and the text in :data:`CONTRAST_REGIONS`
    below WCAG's contrast (:data:`JS_REGION_CONTRAST`): every rule but ``color-contrast``
    on the whole page, ``color-contrast`` outside those regions (one run,
    :data:`JS_AXE_RUN`)."""
    axe = _axe()
    page.evaluate(axe.axe_script)  # to list the rules: every one with these tags
    rules = page.evaluate("tags => axe.getRules(tags).map(r => r.ruleId)", list(AXE_TAGS))
    assert "color-contrast" in rules and "label-content-name-mismatch" in rules, rules
    result = page.evaluate(JS_AXE_RUN, [rules, CONTRAST_OUTSIDE_REGIONS])
    assert set(result["ran"]) == set(rules), (result["ran"], rules)  # every rule ran
    violations = result["violations"]
    found = [f"axe {v['id']} ({v['impact']}): {v['help']}: "
             + "; ".join(" ".join(n["html"].split())[:160] for n in v["nodes"][:5])
             + (f" (+{len(v['nodes']) - 5} more)" if len(v["nodes"]) > 5 else "")
             for v in violations]
    return found + region_contrast_problems(page)


def region_contrast_problems(page) -> list[str]:
    """The text in :data:`CONTRAST_REGIONS` below WCAG's contrast, one line per region,
    reason and element id (:data:`JS_REGION_CONTRAST`)."""
    report = page.evaluate(JS_REGION_CONTRAST, list(CONTRAST_REGIONS))
    assert report["checked"] > 0 or not page.locator(", ".join(CONTRAST_REGIONS)).count()
    return [f"contrast in <{b['where']}>{' #' + b['id'] if b.get('id') else ''}: "
            f"{b['why']}: {b['text']!r}"
            + (f" (and {b['count'] - 1} more elements)" if b["count"] > 1 else "")
            for b in report["bad"]]


# ----------------------------------------------------------------------------- tests


def _toc_pages() -> list[str]:
    """The book's pages as ``_toc.yml`` lists them (``.html``), with the pages every Sphinx
    build adds (index, general index, search), sorted as :func:`book_pages` sorts them."""
    import yaml

    toc = yaml.safe_load((ROOT / "_toc.yml").read_text(encoding="utf-8"))
    files = [toc["root"], *(c["file"] for part in toc.get("parts", ())
                            for c in part["chapters"]),
             *(c["file"] for c in toc.get("chapters", ()))]
    return sorted({f"{f}.html" for f in files} | {"index.html", "genindex.html", "search.html"})


#: Every page, one test each (known before the book is built, from the table of contents), so
#: that pytest-xdist shares them out page by page; :func:`test_the_page_checks_cover_the_book`
#: checks that they are all the pages the build made.
PAGES = _toc_pages()


def test_the_page_checks_cover_the_book():
    assert "search.html" in PAGES and "chapters/intro.html" in PAGES, PAGES
    assert book_pages(require_built_book()) == PAGES


@pytest.mark.parametrize("rel", PAGES)
def test_every_page_is_clean_in_a_real_browser(site, browser, rel):
    url = site + rel
    browser.offsite.clear()
    page = _visit(browser, url)
    try:
        found = []
        found += [f"<img> not decoded: {src}" for src in page.evaluate(JS_UNDECODED_IMAGES)]
        found += _check_math(page)
        browser.settle(page)
        found += overflow_problems(page)
        found += density_problems(page)
        found += page.problems
        found += [f"request leaves localhost (aborted): {u}"
                  for u in dict.fromkeys(browser.offsite)]
        # after the page's own requests: axe-core preloads the stylesheets itself and
        # resolves theme.css's `@import "../basic.css"` against the page (a 404 of its
        # own making, not the book's)
        found += axe_violations(page)
    finally:
        page.close()
    problems = list(dict.fromkeys(found))
    assert not problems, f"{rel}: {len(problems)} problems:\n  " + "\n  ".join(problems)


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


def test_the_contrast_check_finds_low_contrast_code_and_math(site, browser):
    """The text of code cells, outputs and equations (:data:`CONTRAST_REGIONS`), checked by
    :data:`JS_REGION_CONTRAST` instead of axe-core (which :func:`axe_violations` runs on the
    rest of the page): on a page of the book, over a thousand elements pass; with one code
    token turned light grey and one equation's colour too, both are reported and nothing
    else; the ratio is WCAG's closed form, (1.05)/(L + 0.05) for #aaaaaa on white."""
    page = _visit(browser, site + "chapters/gc_model.html")
    try:
        before = page.evaluate(JS_REGION_CONTRAST, list(CONTRAST_REGIONS))
        assert before["bad"] == [] and before["checked"] > 1000, before["checked"]
        page.evaluate("""() => {
          const token = Array.from(document.querySelectorAll('div.highlight pre span'))
            .find(el => el.children.length === 0 && el.textContent.trim());
          token.id = 'gyrolib-low-code';
          token.style.color = '#aaaaaa';
          const eq = document.querySelector('mjx-container');
          eq.style.color = '#aaaaaa';
          eq.style.background = '#ffffff';
        }""")
        found = region_contrast_problems(page)
    finally:
        page.close()
    lum = ((0xAA / 255 + 0.055) / 1.055) ** 2.4
    ratio = f"{1.05 / (lum + 0.05):.2f}:1"
    assert ratio == "2.32:1"
    code = [f for f in found if "#gyrolib-low-code" in f]
    math = [f for f in found if f.startswith("contrast in <mjx-container>")]
    assert len(code) == 1 and "needs 4.5:1" in code[0], found
    assert len(math) == 1 and f"contrast {ratio}" in math[0], found
    assert all(f.startswith("contrast") for f in found), found


LAYOUT_CSS = ROOT / "_static" / "gyrolib-layout.css"


def _small_page(context, body: str, css: bool = True):
    """A page of the book's shape (an ``article.bd-article`` in a 1280-px window) with
    ``body`` in its article, and the book's layout CSS unless ``css`` is false."""
    style = f"<style>{LAYOUT_CSS.read_text()}</style>" if css else ""
    page = context.new_page()
    page.set_content(f"<!doctype html><html><head>{style}<style>body {{ margin: 0; }} "
                     f"article.bd-article {{ width: 700px; margin: 0 auto; font: 16px "
                     f"monospace; }}</style></head><body><article class='bd-article'>{body}"
                     f"</article></body></html>")
    page.evaluate(JS_SETTLED)
    return page


LONG_LINE = "exit status 0 | " + "a long line of output, " * 12 + "end"


def test_the_overflow_check_finds_an_output_line_that_runs_past_its_box(small_pages):
    """Without the book's CSS a long output line runs past its box (whether the theme would
    scroll it or not) and the check finds it; with the CSS it wraps and nothing is found."""
    body = f"<div class='cell_output'><pre>{LONG_LINE}</pre></div>"
    for scroll in ("visible", "auto"):
        page = _small_page(small_pages, body.replace("<pre>", f"<pre style='overflow-x: "
                                                               f"{scroll}'>"), css=False)
        try:
            found = overflow_problems(page)
        finally:
            page.close()
        # the block itself; a block that does not scroll widens the page as well
        assert [f.split(" ")[0] for f in found] == (["output"] if scroll == "auto"
                                                    else ["the", "output"]), (scroll, found)
        assert "a long line of output" in found[-1], found
    page = _small_page(small_pages, body)
    try:
        assert overflow_problems(page) == []
        # wrapped, not cut: the block is as wide as the article and several lines high
        height = page.evaluate("() => document.querySelector('pre').clientHeight")
        assert height > 3 * 16, height
    finally:
        page.close()


def test_the_overflow_check_finds_spilled_text_and_a_page_that_scrolls_sideways(small_pages):
    spill = f"<p style='white-space: nowrap'>{LONG_LINE}</p>"
    scroller = f"<div style='overflow-x: auto'>{spill}</div>"
    wide = "<p>short</p><div style='width: 2400px; height: 4px'></div>"
    cases = {spill: ["the page", "<p> runs"], scroller: [], wide: ["the page"]}
    for body, expected in cases.items():
        page = _small_page(small_pages, body)
        try:
            found = overflow_problems(page)
        finally:
            page.close()
        assert [f[:len(e)] for f, e in zip(found, expected)] == expected, (body[:60], found)
        assert len(found) == len(expected), (body[:60], found)


def _figure_png(dpi: float, retina: bool) -> tuple[str, int]:
    """A 6 x 3 in matplotlib figure as a base64 PNG and the CSS width it is shown at: at
    ``dpi`` pixel for pixel, or as IPython's retina formatter makes it (2 x dpi pixels, the
    width attribute half of them: what the book's chapters output)."""
    from base64 import b64encode

    from IPython.core.pylabtools import print_figure, retina_figure
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.0, 3.0), dpi=dpi)
    ax = fig.subplots()
    ax.plot([0, 1, 2], [0, 1, 0], label="a curve")
    ax.legend()
    if retina:
        png, meta = retina_figure(fig, base64=True)
        return png, int(meta["width"])
    png = print_figure(fig, "png", bbox_inches=None)
    return b64encode(png).decode(), round(6.0 * dpi)


def test_the_density_check_finds_a_72_dpi_figure_and_passes_a_2x_one(small_pages):
    png72, width72 = _figure_png(72.0, retina=False)
    png2x, width2x = _figure_png(96.0, retina=True)
    body = (f"<img alt='72 dpi' src='data:image/png;base64,{png72}'>"
            f"<img alt='2x' width='{width2x}' src='data:image/png;base64,{png2x}'>")
    page = _small_page(small_pages, body)
    try:
        measured = page.evaluate(JS_FIGURE_DENSITY)
        found = density_problems(page)
    finally:
        page.close()
    assert [m["natural"] for m in measured] == [width72, 2 * width2x], measured
    assert [m["shown"] for m in measured] == pytest.approx([width72, width2x], abs=0.5)
    assert len(found) == 1 and f"has {width72} px shown at" in found[0], found


def test_a_figure_shrunk_to_the_column_keeps_its_proportions(small_pages):
    """Sphinx gives a notebook image its size inline (width and height); shrunk to the column
    by max-width, it would be squashed unless the book's CSS lets its height follow."""
    png2x, width2x = _figure_png(192.0, retina=True)  # 1152 CSS px wide: more than 700
    img = (f"<img alt='wide' style='width: {width2x}px; height: {width2x // 2}px; "
           f"max-width: 100%' src='data:image/png;base64,{png2x}'>")
    found = {}
    for css in (False, True):
        page = _small_page(small_pages, img, css=css)
        try:
            found[css] = density_problems(page)
        finally:
            page.close()
    assert len(found[False]) == 1 and "is distorted" in found[False][0], found
    assert found[True] == [], found


def test_a_wide_equation_scrolls_in_its_box_and_can_be_reached_by_keyboard(small_pages):
    """A display equation wider than the column scrolls inside its box (layout CSS) instead of
    spilling, and _static/gyrolib-scroll.js gives exactly that box a tab stop (axe-core's
    scrollable-region-focusable); without the CSS it spills and the check finds it."""
    wide = "<div class='math'><span style='display: inline-block; width: 900px'>x</span></div>"
    narrow = "<div class='math'><span>y = 1</span></div>"
    page = _small_page(small_pages, wide + narrow, css=False)
    try:
        assert [f.split(" runs")[0] for f in overflow_problems(page)] == ["<div.math>"]
    finally:
        page.close()
    page = _small_page(small_pages, wide + narrow)
    try:
        page.add_script_tag(path=str(ROOT / "_static" / "gyrolib-scroll.js"))
        page.evaluate(JS_SETTLED)
        assert overflow_problems(page) == []
        stops = page.evaluate("() => Array.from(document.querySelectorAll('div.math'))"
                              ".map(e => e.getAttribute('tabindex'))")
    finally:
        page.close()
    assert stops == ["0", None], stops


def _phone_page(context, body: str, css: bool = True, script: bool = True):
    """A page at a phone's 390-px viewport (a 342-px article, as the theme's column there)
    with ``body`` in its article, the book's layout CSS and scroll script unless not."""
    page = _small_page(context, body, css=css)
    page.set_viewport_size({"width": 390, "height": 800})
    page.evaluate("() => { document.querySelector('article').style.width = '342px'; }")
    if script:
        page.add_script_tag(path=str(ROOT / "_static" / "gyrolib-scroll.js"))
    page.evaluate(JS_SETTLED)
    return page


JS_EDGES = """() => Array.from(document.querySelectorAll(
    'div.math, .pst-scrollable-table-container')).map(e => ({
  left: e.classList.contains('gyrolib-cut-left'),
  right: e.classList.contains('gyrolib-cut-right'),
  shadow: getComputedStyle(e).boxShadow !== 'none'}))"""

WIDE_TABLE = ("<div class='pst-scrollable-table-container' style='overflow-x: auto'><table>"
              "<tr>" + "<td>a wide cell of a table</td>" * 8 + "</tr></table></div>")
NARROW_TABLE = ("<div class='pst-scrollable-table-container' style='overflow-x: auto'><table>"
                "<tr><td>x</td></tr></table></div>")


def test_a_wide_table_or_equation_shows_where_it_is_cut_on_a_phone(small_pages):
    """At 390 px a table or equation wider than the column shows a shadow at each edge
    where its content is cut (_static/gyrolib-scroll.js, gyrolib-layout.css): at the right
    before it is scrolled, at the left once it is scrolled to its end; one that fits shows
    none, and without the script nothing shows it (the check has power)."""
    wide_eq = ("<div class='math'><span style='display: inline-block; width: 900px'>x"
               "</span></div>")
    body = wide_eq + WIDE_TABLE + NARROW_TABLE
    page = _phone_page(small_pages, body, script=False)
    try:
        assert not any(e["shadow"] or e["right"] for e in page.evaluate(JS_EDGES))
    finally:
        page.close()
    page = _phone_page(small_pages, body)
    try:
        start = page.evaluate(JS_EDGES)
        page.evaluate("() => document.querySelectorAll('div.math, "
                      ".pst-scrollable-table-container').forEach(e => { e.scrollLeft = "
                      "e.scrollWidth; })")
        page.evaluate(JS_SETTLED)
        end = page.evaluate(JS_EDGES)
    finally:
        page.close()
    cut = {"left": False, "right": True, "shadow": True}
    assert start == [cut, cut, {"left": False, "right": False, "shadow": False}], start
    assert end[:2] == [{"left": True, "right": False, "shadow": True}] * 2, end


JS_EQNO_OVERLAP = """() => {
  const n = document.querySelector('span.eqno').getBoundingClientRect();
  const m = document.querySelector('div.math > .content').getBoundingClientRect();
  const box = document.querySelector('div.math').getBoundingClientRect();
  const seen = {left: Math.max(m.left, box.left), right: Math.min(m.right, box.right)};
  return n.bottom > m.top + 0.5 && n.top < m.bottom - 0.5 && n.left < seen.right
         && n.right > seen.left;
}"""


def test_an_equation_number_never_sits_over_a_cut_equation_on_a_phone(small_pages):
    """At 390 px the number of a wide equation stands on its own line above it (layout CSS),
    not floated over the equation at the column's cut edge; without the CSS it does."""
    eq = ("<div class='math'><span class='eqno'>(15)</span><span class='content' "
          "style='display: block; width: 600px'>x</span></div>")   # as MathJax's block
    basic = "<style>span.eqno { float: right; }</style>"   # Sphinx's basic.css
    found = {}
    for css in (False, True):
        page = _phone_page(small_pages, basic + eq, css=css)
        try:
            if not css:   # the theme's own scrolling box, as the layout CSS gives it
                page.evaluate("() => { document.querySelector('div.math').style.overflowX "
                              "= 'auto'; }")
            found[css] = page.evaluate(JS_EQNO_OVERLAP)
        finally:
            page.close()
    assert found == {False: True, True: False}, found


def test_print_shows_no_toggle_and_no_empty_frame(small_pages):
    """In print (the PDF), a collapsed code cell's "Show code cell source" toggle and an
    empty output box are not drawn, and a collapsed section of the ledger prints open."""
    body = ("<div class='cell tag_hide-input'><details class='hide above-input'>"
            "<summary><span>Show code cell source</span></summary><div class='cell_input'>"
            "<pre>x = 1</pre></div></details><div class='cell_output'></div></div>"
            "<details class='gyrolib-collapsed'><summary>The inputs</summary>"
            "<p id='inside'>An input row.</p></details>")
    page = _small_page(small_pages, body)
    try:
        shown = "s => !!document.querySelector(s) && document.querySelector(s).checkVisibility()"
        on_screen = {s: page.evaluate(shown, s) for s in ("summary", "#inside")}
        page.emulate_media(media="print")
        page.evaluate(JS_SETTLED)
        printed = {s: page.evaluate(shown, s)
                   for s in ("details.hide > summary", "#inside", "div.cell_output")}
        text = page.evaluate("() => document.body.innerText")
    finally:
        page.close()
    assert on_screen == {"summary": True, "#inside": False}, on_screen
    assert printed == {"details.hide > summary": False, "#inside": True,
                       "div.cell_output": False}, printed
    assert "Show code cell source" not in text, text


def test_the_book_fails_the_layout_checks_with_an_injected_wide_line_and_72_dpi_figure(
        site, browser):
    """The same checks on a page of the book with one output line kept from wrapping and
    one 72-dpi figure added: each is found, and nothing else."""
    png72, width72 = _figure_png(72.0, retina=False)
    page = _visit(browser, site + "chapters/gc_model.html")
    try:
        page.evaluate("""([line, png]) => {
          const out = document.createElement('div');
          out.className = 'cell_output';
          out.innerHTML = '<pre style="white-space: pre">' + line + '</pre>'
            + '<img alt="a 72 dpi figure" src="data:image/png;base64,' + png + '">';
          document.querySelector('article.bd-article section').appendChild(out);
        }""", [LONG_LINE, png72])
        page.evaluate(JS_SETTLED)
        found = overflow_problems(page) + density_problems(page)
    finally:
        page.close()
    assert len(found) == 2, found
    assert found[0].startswith("output block <pre>") and "a long line" in found[0], found
    assert f"has {width72} px shown at" in found[1], found


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
            # the ledger's own tables (the results, the inputs); the table of inputs of the
            # one rule and each claim's compact map table are other tables
            rows += n if section.startswith("The papers") else 0
            if n == 0:
                problems.append(f"table {i + 1} (section {section!r}) has a header but no rows")
            collapsed = table.evaluate("t => !!t.closest('details.gyrolib-collapsed')")
            if not table.is_visible() and not collapsed:
                problems.append(f"table {i + 1} (section {section!r}) is not visible")
            if i == 0 and (collapsed or "results" not in section):
                problems.append(f"the page opens with {section!r}, not the papers' results")
            if collapsed and "input" not in section:
                problems.append(f"table {i + 1} (section {section!r}) is collapsed: only the "
                                f"inputs may be")
        expected = _ledger_items()
        if expected is not None and rows != expected:
            problems.append(f"the page shows {rows} ledger rows but gyrolib.book.ledger.collect() "
                            f"has {expected} items (stale build?)")
        assert not problems, "ledger page:\n  " + "\n  ".join(problems)
    finally:
        page.close()


#: What is wider than its box in a page's article at a phone's width: a scroll container that
#: scrolls sideways (a table in its scrollable wrapper), an element reaching past the window,
#: or the page itself; code (a cell's input), which keeps its layout and scrolls in its box
#: by design, is left out.  Power: a six-column ledger table in its
#: scrollable wrapper, is found.
JS_SIDEWAYS = """() => {
  const out = [];
  const root = document.documentElement;
  if (root.scrollWidth > window.innerWidth + 1)
    out.push(`the page is ${root.scrollWidth} px wide in a ${window.innerWidth}-px window`);
  const article = document.querySelector('article.bd-article') || document.body;
  for (const el of article.querySelectorAll('*')) {
    if (!el.offsetParent && getComputedStyle(el).position !== 'fixed') continue;  /* hidden */
    if (el.closest('details:not([open])')) continue;
    /* code keeps its layout and scrolls in its box (gyrolib-layout.css): not the reader's text */
    if (el.closest('div.highlight, .cell_input')) continue;
    const box = el.getBoundingClientRect();
    if (box.width === 0) continue;
    if (el.scrollWidth > el.clientWidth + 1 && el.clientWidth > 0
        && getComputedStyle(el).overflowX !== 'visible') {
      const what = el.tagName.toLowerCase() + (el.className ? '.' + String(el.className)
        .split(' ')[0] : '');
      out.push(`<${what}> scrolls sideways: ${el.scrollWidth} px of content in `
               + `${el.clientWidth} px`);
    } else if (box.right > window.innerWidth + 1) {
      out.push(`<${el.tagName.toLowerCase()}> reaches ${Math.round(box.right)} px, `
               + `past the ${window.innerWidth}-px window`);
    }
  }
  return out.slice(0, 20);
}"""


def test_the_ledger_reads_on_a_phone_without_sideways_scrolling(site, browser):
    """At 390 x 844 (a phone) the ledger's tables fit the screen: nothing in the article
    scrolls sideways or reaches past the window, and the results table shows each item as
    a card, every cell labelled with its column's header."""
    page = browser.open(site + "chapters/ledger.html")
    try:
        page.set_viewport_size({"width": 390, "height": 844})
        page.goto(site + "chapters/ledger.html", wait_until="load")
        browser.settle(page)
        found = page.evaluate(JS_SIDEWAYS)
        assert not found, "ledger page at 390 px:\n  " + "\n  ".join(found)
        first = page.locator("article.bd-article table").first
        labels = first.evaluate("t => Array.from(t.querySelectorAll('tbody tr:first-child td'))"
                                ".map(td => getComputedStyle(td, '::before').content)")
        heads = first.evaluate("t => Array.from(t.querySelectorAll('thead th'))"
                               ".map(th => th.textContent.trim())")
        assert [x.strip('"') for x in labels] == heads, (labels, heads)
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
            browser.settle(page)
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


# ----------------------------------------------------------------------------- navigation

#: The page the navigation is tried on: a long chapter, with its table of contents (38
#: entries).  gc_race rather than gc_model (40 entries): 5 math elements where gc_model has
#: 56, whose typesetting and axe's pass over MathJax's output cost CPU in every test command;
#: gc_model's math is checked by axe in test_every_page_is_clean_in_a_real_browser.  (Not
#: the ledger, which the phone's layout test loads anyway: it has no contents panel.)  The
#: page is loaded once, at the phone's size as a phone loads it; the tablet's and the
#: desk's widths are reached by resizing the window (the shim follows a resize,
#: ``_static/gyrolib-nav.js``), every check made there as before: a load of this page is
#: about 2.5 CPU-s, a resize 0.3.
NAV_PAGE = "chapters/gc_race.html"


@pytest.fixture(scope="module")
def phone_page() -> Iterator[SimpleNamespace]:
    """The navigation tests' one page (:func:`_shared_page`; loaded by the first test)."""
    shared = SimpleNamespace(page=None, fresh=False)
    yield shared
    if shared.page is not None:
        shared.page.close()


@contextlib.contextmanager
def _shared_page(browser: Browser, site: str, shared: SimpleNamespace, width: int,
                 height: int):
    """:data:`NAV_PAGE` at ``width`` x ``height``: the window resized, the page loaded only
    the first time (at that size) and again after a test that failed on it (its panels may
    be left open), so that no test sees another's leftovers."""
    if shared.page is None:
        shared.page = browser.open(site + NAV_PAGE)
    page = shared.page
    page.set_viewport_size({"width": width, "height": height})
    if not shared.fresh:
        page.goto(site + NAV_PAGE, wait_until="load")
    browser.settle(page)  # two frames: the resize's events handled, the layout final
    shared.fresh = False  # a test that raises leaves it so: the next one loads again
    yield page
    shared.fresh = True

# What the reader sees of the two panels and the buttons that open them.
JS_NAV_STATE = """() => {
  const shown = el => {
    if (!el) return false;
    const r = el.getBoundingClientRect(), s = getComputedStyle(el);
    return r.width > 40 && r.height > 40 && s.visibility !== 'hidden' && s.display !== 'none'
      && r.right > 0 && r.left < innerWidth && parseFloat(s.opacity || '1') > 0.1;
  };
  const visible = sel => Array.from(document.querySelectorAll(sel)).filter(b => {
    const r = b.getBoundingClientRect();
    return r.width > 0 && r.height > 0 && getComputedStyle(b).visibility !== 'hidden';
  });
  const pm = document.getElementById('pst-primary-sidebar-modal');
  const sm = document.getElementById('pst-secondary-sidebar-modal');
  const links = el => el ? el.querySelectorAll('a[href]').length : 0;
  return {
    primaryButtons: visible('.primary-toggle').length,
    secondaryButtons: visible('.secondary-toggle').length,
    primaryExpanded: visible('.primary-toggle').map(b => b.getAttribute('aria-expanded')),
    secondaryExpanded: visible('.secondary-toggle').map(b => b.getAttribute('aria-expanded')),
    primaryModalOpen: !!(pm && pm.open), primaryModalLinks: links(pm),
    secondaryModalOpen: !!(sm && sm.open), secondaryModalLinks: links(sm),
    sidebarShown: shown(document.getElementById('pst-primary-sidebar')),
    tocShown: shown(document.getElementById('pst-secondary-sidebar')),
    focus: document.activeElement ? (document.activeElement.className || '') + '' : '',
  };
}"""


def _click_visible(page, selector: str) -> None:
    for button in page.query_selector_all(selector):
        if button.is_visible():
            button.click()
            page.wait_for_timeout(350)  # the themes' transitions: 0.25 s
            return
    raise AssertionError(f"no visible {selector}")


@pytest.mark.parametrize("width,height", [(390, 844), (800, 900)])
def test_navigation_panels_open_and_close_on_a_phone_and_a_tablet(site, browser, phone_page,
                                                                  width, height):
    """Below 992 px: ☰ opens the site navigation, the contents button the page's table of
    contents, each in a modal panel; Escape and a click on the backdrop close it, the
    content goes back, focus returns to the button, and aria-expanded follows."""
    with _shared_page(browser, site, phone_page, width, height) as page:
        state = page.evaluate(JS_NAV_STATE)
        assert state["primaryButtons"] == 1 and state["secondaryButtons"] == 1, state
        assert state["primaryExpanded"] == ["false"], state
        _click_visible(page, ".primary-toggle")
        state = page.evaluate(JS_NAV_STATE)
        assert state["primaryModalOpen"] and state["primaryModalLinks"] > 10, state
        assert state["primaryExpanded"] == ["true"], state
        page.keyboard.press("Escape")
        page.wait_for_timeout(200)
        state = page.evaluate(JS_NAV_STATE)
        assert not state["primaryModalOpen"] and state["primaryExpanded"] == ["false"], state
        assert "primary-toggle" in state["focus"], state
        assert page.evaluate("document.getElementById('pst-primary-sidebar')"
                             ".querySelectorAll('a[href]').length") > 10  # content back

        _click_visible(page, ".secondary-toggle")
        state = page.evaluate(JS_NAV_STATE)
        assert state["secondaryModalOpen"] and state["secondaryModalLinks"] > 3, state
        assert state["secondaryExpanded"] == ["true"], state
        # the backdrop: beside the panel, on its wider side
        box = page.evaluate("(() => { const r = document.getElementById("
                            "'pst-secondary-sidebar-modal').getBoundingClientRect();"
                            " return [r.left, r.right]; })()")
        x = box[0] / 2 if box[0] > width - box[1] else (box[1] + width) / 2
        assert min(abs(x - box[0]), abs(x - box[1])) > 10, (box, width)  # a backdrop to click
        page.mouse.click(x, height / 2)
        page.wait_for_timeout(200)
        state = page.evaluate(JS_NAV_STATE)
        assert not state["secondaryModalOpen"], state
        assert state["secondaryExpanded"] == ["false"], state

        if width == 390:  # the open panel has no accessibility violation either
            _click_visible(page, ".primary-toggle")
            found = axe_violations(page)
            assert not found, found
            page.keyboard.press("Escape")
            page.wait_for_timeout(200)
            assert not page.evaluate(JS_NAV_STATE)["primaryModalOpen"]


def test_navigation_sidebar_collapses_and_returns_on_a_desk(site, browser, phone_page):
    """At 1280 px: ☰ collapses and restores the sidebar (aria-expanded follows), and the
    contents column is visible."""
    with _shared_page(browser, site, phone_page, 1280, 900) as page:
        state = page.evaluate(JS_NAV_STATE)
        assert state["sidebarShown"] and state["tocShown"], state
        assert state["primaryButtons"] == 1 and state["primaryExpanded"] == ["true"], state
        _click_visible(page, ".primary-toggle")
        state = page.evaluate(JS_NAV_STATE)
        assert not state["sidebarShown"] and state["primaryExpanded"] == ["false"], state
        assert not state["primaryModalOpen"], state
        _click_visible(page, ".primary-toggle")
        state = page.evaluate(JS_NAV_STATE)
        assert state["sidebarShown"] and state["primaryExpanded"] == ["true"], state
        assert state["tocShown"], state
