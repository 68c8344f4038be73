"""Checks over the built HTML of the book (offline; accessibility).

Read the files of the test session's book (``conftest.session_book``: built as
``python3 tasks.py book`` builds ``_build/html``) and assert, for every page of the book at
once (each test collects all problems, then fails with the full list):

* the book is readable offline: no page loads a script, stylesheet, font or image from an
  ``http(s)://`` (or protocol-relative ``//``) address, no CSS file in ``_static`` imports or
  ``url()``-loads one, and MathJax comes from ``_static/mathjax`` (links *to* doi.org and
  other sites are fine: they are navigation, not resources);
* accessibility basics: every image in a figure has a real alt text (not empty, not a file
  name), every figure has a non-empty caption, headings in the article go down one level at a
  time and there is exactly one ``h1``;
* links: every internal ``href``/``src`` resolves to a file of the build, and every
  ``#anchor`` to an ``id`` on the target page.

A failed build fails these tests with the build's output.
"""

from __future__ import annotations

import re
from functools import cache
from pathlib import Path, PurePosixPath
from urllib.parse import unquote, urlsplit

import pytest

from tests.conftest import require_built_book

bs4 = pytest.importorskip("bs4", reason="beautifulsoup4 (a jupyter-book dependency) is needed")

ROOT = Path(__file__).resolve().parents[2]

# <link rel=...> values that make the browser fetch the target as a resource.
RESOURCE_RELS = {
    "stylesheet", "preload", "modulepreload", "prefetch", "icon", "shortcut", "apple-touch-icon",
    "mask-icon", "manifest", "font", "preconnect", "dns-prefetch",
}
IMAGE_EXT = re.compile(r"\.(png|jpe?g|gif|svg|webp|bmp|pdf)$", re.IGNORECASE)


# ----------------------------------------------------------------------------- the build


@pytest.fixture(scope="session")
def html_dir() -> Path:
    return require_built_book()


def book_pages(root: Path) -> list[Path]:
    """Every HTML page of the book (not the theme's template fragments in _static)."""
    skip = {"_static", "_sources", "_images", "_downloads"}
    return sorted(p for p in root.rglob("*.html")
                  if not skip.intersection(p.relative_to(root).parts[:-1]))


@cache
def soup_of(path: Path) -> bs4.BeautifulSoup:
    return bs4.BeautifulSoup(path.read_text(encoding="utf-8"), "html.parser")


def article_of(soup: bs4.BeautifulSoup):
    """The page's main content: the theme's <article>, else <main>, else <body>."""
    return (soup.select_one("article.bd-article") or soup.find("main") or soup.body or soup)


def is_redirect(soup: bs4.BeautifulSoup) -> bool:
    """index.html is only a <meta http-equiv="Refresh"> to the landing page."""
    return any((m.get("http-equiv") or "").lower() == "refresh" for m in soup.find_all("meta"))


def _rel(path: Path) -> str:
    return path.relative_to(require_built_book()).as_posix()


def _report(title: str, problems: list[str]) -> str:
    return f"{len(problems)} {title}:\n  " + "\n  ".join(problems)


# ----------------------------------------------------------------------------- offline


def _is_remote(url: str | None) -> bool:
    url = (url or "").strip().lower()
    return url.startswith(("http://", "https://", "//"))


def _srcset_urls(srcset: str) -> list[str]:
    return [part.strip().split()[0] for part in srcset.split(",") if part.strip()]


CSS_COMMENT = re.compile(r"/\*.*?\*/", re.DOTALL)
CSS_URL = re.compile(r"""url\(\s*(['"]?)(.*?)\1\s*\)""", re.IGNORECASE)
CSS_IMPORT = re.compile(r"""@import\s+(?:url\(\s*)?(['"]?)([^'")\s;]+)""", re.IGNORECASE)


def remote_css_urls(css: str) -> list[str]:
    """http(s) or protocol-relative URLs loaded by a stylesheet (comments do not count)."""
    css = CSS_COMMENT.sub("", css)
    urls = [m.group(2) for m in CSS_URL.finditer(css)]
    urls += [m.group(2) for m in CSS_IMPORT.finditer(css)]
    return [u for u in urls if _is_remote(u)]


def remote_resources(soup: bs4.BeautifulSoup) -> list[str]:
    """Every remote script, stylesheet, font, icon, image or frame a page would load."""
    found = []
    for tag in soup.find_all("script", src=True):
        if _is_remote(tag["src"]):
            found.append(f"<script src={tag['src']}>")
    for tag in soup.find_all("link", href=True):
        rels = {r.lower() for r in (tag.get("rel") or [])}
        if rels & RESOURCE_RELS and _is_remote(tag["href"]):
            found.append(f"<link rel={' '.join(sorted(rels))} href={tag['href']}>")
    for tag in soup.find_all(["img", "source", "video", "audio", "iframe", "embed", "input"]):
        for attr in ("src", "poster", "data"):
            if _is_remote(tag.get(attr)):
                found.append(f"<{tag.name} {attr}={tag[attr]}>")
        for url in _srcset_urls(tag.get("srcset") or ""):
            if _is_remote(url):
                found.append(f"<{tag.name} srcset={url}>")
    for tag in soup.find_all("object", data=True):
        if _is_remote(tag["data"]):
            found.append(f"<object data={tag['data']}>")
    for tag in soup.find_all("style"):
        found += [f"<style> url {u}" for u in remote_css_urls(tag.get_text())]
    for tag in soup.find_all(style=True):
        found += [f"style=… url {u} on <{tag.name}>" for u in remote_css_urls(tag["style"])]
    return found


def test_index_exists(html_dir):
    index = html_dir / "index.html"
    assert index.is_file() and index.stat().st_size > 0, f"{index} is missing or empty"
    # The landing page is the table of contents' root, reached from index.html.
    pages = {_rel(p) for p in book_pages(html_dir)}
    assert "chapters/intro.html" in pages, f"no landing page chapters/intro.html in {pages}"


def test_remote_url_detector_is_not_blind():
    """The detectors below must flag what they are meant to flag (and not CSS comments)."""
    css = ("/* see https://example.org/x.css */ @import 'https://cdn.example/a.css';\n"
           "@font-face { src: url(//fonts.example/f.woff2) } .x { background: url(img/a.png) }")
    assert remote_css_urls(css) == ["//fonts.example/f.woff2", "https://cdn.example/a.css"]
    html = ('<script src="https://cdn.example/mathjax.js"></script>'
            '<link rel="stylesheet" href="http://cdn.example/s.css">'
            '<link rel="canonical" href="https://example.org/">'
            '<a href="https://doi.org/10.1/x">doi</a><img src="https://example.org/i.png">')
    found = remote_resources(bs4.BeautifulSoup(html, "html.parser"))
    assert len(found) == 3 and not any("doi.org" in f or "canonical" in f for f in found), found


def test_no_page_loads_anything_from_the_internet(html_dir):
    problems = []
    for page in book_pages(html_dir):
        problems += [f"{_rel(page)}: {r}" for r in remote_resources(soup_of(page))]
    for css in sorted((html_dir / "_static").rglob("*.css")):
        text = css.read_text(encoding="utf-8", errors="replace")
        problems += [f"{_rel(css)}: loads {u}" for u in remote_css_urls(text)]
    assert not problems, _report("remote resources (the book must read offline)", problems)


def test_mathjax_is_served_from_the_book(html_dir):
    """Pages with math load MathJax from _static/mathjax, and that file is in the build."""
    problems, math_pages = [], 0
    for page in book_pages(html_dir):
        soup = soup_of(page)
        scripts = [s["src"] for s in soup.find_all("script", src=True)
                   if "mathjax" in s["src"].lower()]
        if not soup.select(".math") and not scripts:
            continue
        math_pages += 1
        local = [s for s in scripts if not _is_remote(s)
                 and "_static/mathjax/" in urlsplit(s).path]
        if not local:
            problems.append(f"{_rel(page)}: has math but no <script> from _static/mathjax "
                            f"(MathJax scripts: {scripts or 'none'})")
        for src in local:
            target = (page.parent / unquote(urlsplit(src).path)).resolve()
            if not target.is_file():
                problems.append(f"{_rel(page)}: MathJax script {src} is not in the build")
    assert not problems, _report("MathJax problems", problems)
    if math_pages == 0:
        pytest.skip("no page of the book has math yet (nothing to check)")


# ----------------------------------------------------------------------------- accessibility


def _looks_like_file_name(alt: str, src: str) -> bool:
    alt = alt.strip()
    return (alt == src or alt == PurePosixPath(src).name or bool(IMAGE_EXT.search(alt))
            or (" " not in alt and "/" in alt))


def test_every_figure_has_alt_text_and_caption(html_dir):
    problems = []
    for page in book_pages(html_dir):
        article = article_of(soup_of(page))
        for n, fig in enumerate(article.find_all("figure"), start=1):
            name = f"{_rel(page)}: figure {n}" + (f" (#{fig['id']})" if fig.get("id") else "")
            imgs = fig.find_all("img")
            for img in imgs:
                alt, src = (img.get("alt") or "").strip(), img.get("src", "")
                if not alt:
                    problems.append(f"{name}: <img src={src}> has no alt text")
                elif _looks_like_file_name(alt, src):
                    problems.append(f"{name}: <img src={src}> alt text {alt!r} is a file "
                                    "name, not a description (add :alt: to the figure)")
            cap = fig.find("figcaption")
            if cap is None or not cap.get_text(strip=True).strip("#¶ "):
                problems.append(f"{name}: no caption (figcaption)")
    assert not problems, _report("figure accessibility problems", problems)


HEADING = re.compile(r"^h[1-6]$")


def test_headings_are_in_order(html_dir):
    problems = []
    for page in book_pages(html_dir):
        if is_redirect(soup_of(page)):
            continue
        article = article_of(soup_of(page))
        headings = [(int(h.name[1]), h.get_text(" ", strip=True).rstrip("#¶ ").strip())
                    for h in article.find_all(HEADING)]
        ones = [text for level, text in headings if level == 1]
        if len(ones) != 1:
            problems.append(f"{_rel(page)}: {len(ones)} h1 in the article (want exactly 1): "
                            f"{ones}")
        previous = 0
        for level, text in headings:
            if level > previous + 1:
                was = f"h{previous}" if previous else "the start of the article"
                problems.append(f"{_rel(page)}: h{level} {text!r} follows {was} "
                                "(a heading level is skipped)")
            previous = level
    assert not problems, _report("heading-order problems", problems)


# ----------------------------------------------------------------------------- links


@cache
def ids_of(path: Path) -> frozenset[str]:
    soup = soup_of(path)
    ids = {t["id"] for t in soup.find_all(id=True)}
    ids |= {t["name"] for t in soup.find_all("a", attrs={"name": True})}
    return frozenset(ids)


def _internal_urls(soup: bs4.BeautifulSoup):
    for tag in soup.find_all(["a", "link", "area"], href=True):
        yield tag.name, tag["href"]
    for tag in soup.find_all(["img", "script", "source", "iframe", "embed", "video", "audio"]):
        if tag.get("src"):
            yield tag.name, tag["src"]
        for url in _srcset_urls(tag.get("srcset") or ""):
            yield tag.name, url


def test_every_internal_link_resolves(html_dir):
    root = html_dir.resolve()
    problems = []
    for page in book_pages(html_dir):
        for tag, url in _internal_urls(soup_of(page)):
            url = url.strip()
            parts = urlsplit(url)
            if parts.scheme or url.startswith("//") or not url or url == "#":
                continue  # external (http, mailto, data, javascript…) or a no-op link
            where = f"{_rel(page)}: <{tag}> {url}"
            target = (page.parent / unquote(parts.path)).resolve() if parts.path else page
            if target.is_dir():
                target = target / "index.html"
            if not target.is_relative_to(root):
                problems.append(f"{where} points outside _build/html")
                continue
            if not target.is_file():
                problems.append(f"{where} -> missing file {target.relative_to(root)}")
                continue
            anchor = unquote(parts.fragment)
            if anchor and target.suffix == ".html" and anchor not in ids_of(target):
                problems.append(f"{where} -> no id {anchor!r} in {target.relative_to(root)}")
    assert not problems, _report("broken internal links", problems)


# ----------------------------------------------------------------------------- benchmarks


def _benchmark_ext():
    import importlib.util

    spec = importlib.util.spec_from_file_location("benchmark_results",
                                                  ROOT / "_ext" / "benchmark_results.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_benchmark_results_files_follow_the_format(tmp_path):
    ext = _benchmark_ext()
    files = sorted((ROOT / "benchmarks" / "results").glob("*.json"))
    assert files, "no benchmarks/results/*.json"
    for path in files:
        doc = ext.load(path)
        assert path.stem == doc["benchmark"], path.name
        # the machine's class: "AMD EPYC" alone names machines 2x apart
        assert doc["machine"]["cpu_class"] in ("AVX-512", "AVX2", "AVX", "no AVX",
                                               "class unknown"), path.name
    # a file with a case missing its peer time is refused, naming the field
    import json

    bad = json.loads(files[0].read_text())
    del bad["results"][0]["peer_s"]
    (tmp_path / "bad.json").write_text(json.dumps(bad))
    with pytest.raises(ValueError, match=r"bad\.json: missing \['results\[0\]\.peer_s'\]"):
        ext.load(tmp_path / "bad.json")
    # and one without the CPU class, naming it
    bad = json.loads(files[0].read_text())
    del bad["machine"]["cpu_class"]
    (tmp_path / "bad.json").write_text(json.dumps(bad))
    with pytest.raises(ValueError, match=r"bad\.json: missing \['machine\.cpu_class'\]"):
        ext.load(tmp_path / "bad.json")


def test_performance_page_shows_every_results_file(html_dir):
    import json

    text = " ".join(article_of(soup_of(html_dir / "chapters" / "benchmarks.html"))
                    .get_text(" ").split())
    text = text.replace("\u2019", "'").replace("\u201c", '"').replace("\u201d", '"')  # smartquotes
    missing = []
    for path in sorted((ROOT / "benchmarks" / "results").glob("*.json")):
        doc = json.loads(path.read_text(encoding="utf-8"))
        for needle in [doc["benchmark"], doc["date"]] + [" ".join(r["case"].split())
                                                         for r in doc["results"]]:
            if needle not in text:
                missing.append(f"{path.name}: {needle!r}")
    assert not missing, f"not on the Performance page: {missing}"


# ----------------------------------------------------------------------------- axe's findings


def test_no_page_has_the_markup_axe_core_flagged(html_dir):
    """The markup behind the violations axe-core found, fixed at build time by
    ``_ext/accessibility.py`` and its template overrides, is on no page: no deprecated
    ``doc-biblioentry`` role, no hidden-cell summary named "Toggle hidden content", no search
    button named other than by its visible text, no titled icon inside the color-mode button;
    and the badge palette's stylesheet is linked.  (tests/book/test_browser.py runs axe-core
    itself; this check holds without a browser.)"""
    problems = []
    for page in book_pages(html_dir):
        soup = soup_of(page)
        if is_redirect(soup):
            continue
        rel = _rel(page)
        if soup.select('[role="doc-biblioentry"]'):
            problems.append(f"{rel}: role=doc-biblioentry (deprecated)")
        if soup.select('summary[aria-label="Toggle hidden content"]'):
            problems.append(f"{rel}: <summary> named 'Toggle hidden content'")
        for button in soup.select("button.search-button-field[aria-label]"):
            problems.append(f"{rel}: search button named {button['aria-label']!r}")
        for icon in soup.select("button.theme-switch-button i"):
            if icon.get("title") or icon.get("aria-hidden") != "true":
                problems.append(f"{rel}: color-mode icon {icon.get('class')} not decorative")
        if not soup.select('link[rel~="stylesheet"][href*="gyrolib-a11y.css"]'):
            problems.append(f"{rel}: no _static/gyrolib-a11y.css (the badge palette)")
    assert not problems, _report("pages with markup axe-core flags", problems)


def png_width(path: Path) -> int:
    """A PNG's pixel width, read from its IHDR chunk (no imaging library needed)."""
    head = path.read_bytes()[:24]
    if head[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path} is not a PNG")
    return int.from_bytes(head[16:20], "big")


def shown_width(img) -> float | None:
    """The CSS width in px an ``<img>`` is given: its ``width`` attribute, or the width of its
    ``style`` (Sphinx writes a notebook image's size as ``style="width: 773px; ..."``)."""
    match = re.search(r"(?:^|;)\s*width:\s*([\d.]+)px", img.get("style", ""))
    if match:
        return float(match.group(1))
    width = str(img.get("width", "")).removesuffix("px")
    return float(width) if width.replace(".", "", 1).isdigit() else None


#: Image pixels per CSS pixel of a figure's width attribute.
MIN_FIGURE_DENSITY = 1.5


def figure_density_problems(html_dir: Path) -> list[str]:
    """Every raster figure of the book is a 2x image: a width attribute (the CSS width it is
    shown at, at most) and at least MIN_FIGURE_DENSITY image pixels per CSS pixel of it.
    The layout stylesheet, which keeps figures within the column, is linked on every page."""
    problems = []
    for page in book_pages(html_dir):
        soup = soup_of(page)
        if is_redirect(soup):
            continue
        rel = page.relative_to(html_dir).as_posix()
        if not soup.select('link[rel~="stylesheet"][href*="gyrolib-layout.css"]'):
            problems.append(f"{rel}: no _static/gyrolib-layout.css (outputs wrap, print)")
        for img in soup.select("article img"):
            src = unquote(urlsplit(img.get("src", "")).path)
            if not src.lower().endswith(".png"):
                continue  # vector figures and icons
            natural = png_width((page.parent / src).resolve())
            width = shown_width(img)
            if width is None:
                problems.append(f"{rel}: {src} ({natural} px) has no width: shown pixel for "
                                f"pixel, or stretched")
            elif natural / width < MIN_FIGURE_DENSITY:
                problems.append(f"{rel}: {src} has {natural} px for a width of {width:g} px")
    return problems


def test_figures_are_2x_images(html_dir):
    problems = figure_density_problems(html_dir)
    assert not problems, _report("figures below 2x", problems)


def test_the_figure_check_finds_a_72_dpi_figure(tmp_path):
    """A tiny book folder with one 2x figure and one drawn at 72 dpi without a width: only
    the second is reported."""
    from matplotlib.figure import Figure

    (tmp_path / "_images").mkdir()
    for name, dpi in (("two_x.png", 192), ("dpi72.png", 72)):
        Figure(figsize=(4.0, 2.0), dpi=dpi).savefig(tmp_path / "_images" / name, dpi=dpi)
    style = '<link rel="stylesheet" href="_static/gyrolib-layout.css">'
    (tmp_path / "page.html").write_text(
        f"<html><head>{style}</head><body><article><img src='_images/two_x.png' width='384'>"
        f"<img src='_images/two_x.png' style='width: 384px; height: 192px;'>"
        f"<img src='_images/dpi72.png'><img src='_images/dpi72.png' style='width: 288px'>"
        f"</article></body></html>", encoding="utf-8")
    problems = figure_density_problems(tmp_path)
    assert len(problems) == 2, problems
    assert "dpi72.png (288 px) has no width" in problems[0], problems
    assert "dpi72.png has 288 px for a width of 288 px" in problems[1], problems
