"""Sphinx extension: every page passes axe-core's WCAG 2.0/2.1 A and AA rules (issue 20).

The theme and the extensions write four kinds of markup that axe-core flags; each is fixed at
build time, so the pages are right without JavaScript too:

* **Label in name** (WCAG 2.5.3).  The theme's search button is named "Search" while it shows
  "Search Ctrl+K", and its color-mode button contains icons whose titles are not in its name
  "Color mode": two small template overrides in ``_ext/templates`` (the search button is
  named by its visible text; the mode icons are decorative, ``aria-hidden``).  myst-nb names
  the summary of every hidden code cell "Toggle hidden content" while it shows "Show code
  cell source": the ``aria-label`` is dropped, so the name is the visible prompt.
* **Deprecated role** (``doc-biblioentry``, deprecated in DPUB-ARIA 1.1) on each entry of
  docutils' citation list, whose ``role="list"`` then has no list items
  (``aria-required-children``): the entries become ``role="listitem"``.
* **Contrast** of the status badges: ``_static/gyrolib-a11y.css`` (every badge at least
  4.5:1 in the light and the dark mode).

``tests/book/test_browser.py`` runs axe-core on every page and fails on any violation.
"""

from __future__ import annotations

from pathlib import Path

TEMPLATES = Path(__file__).resolve().parent / "templates"

#: Exact markup written by the pinned myst-nb (1.4) and docutils (0.21), and its fix.
BODY_FIXES: tuple[tuple[str, str], ...] = (
    ('<summary aria-label="Toggle hidden content">', "<summary>"),
    (' role="doc-biblioentry"', ' role="listitem"'),
)


def _templates(app, config) -> None:
    paths = list(config.templates_path or [])
    if str(TEMPLATES) not in paths:
        config.templates_path = [str(TEMPLATES), *paths]


def fix_body(body: str) -> str:
    """The page body with the markup of :data:`BODY_FIXES` replaced.

    >>> fix_body('<div class="citation" id="x" role="doc-biblioentry">')
    '<div class="citation" id="x" role="listitem">'
    """
    for old, new in BODY_FIXES:
        body = body.replace(old, new)
    return body


def _page(app, pagename, templatename, context, doctree) -> None:
    body = context.get("body")
    if isinstance(body, str):
        context["body"] = fix_body(body)


def setup(app):
    app.connect("config-inited", _templates)
    app.connect("html-page-context", _page)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1"}
