"""Sphinx extension: keep the built pages clean in a real browser.

Sphinx 7.4 with jupyter-book 1.x registers sphinx-thebe's inline configuration script twice,
so every page throws "Identifier 'THEBE_JS_URL' has already been declared" in the console.
That inline script also names thebe's CDN address, and the book has no launch buttons (it
must load nothing from the internet), so this extension drops sphinx-thebe's scripts and any
remaining duplicate script entries from each page's context before rendering.
"""

from __future__ import annotations


def _script_key(script) -> tuple:
    attrs = getattr(script, "attributes", {}) or {}
    return (str(getattr(script, "filename", script)),
            tuple(sorted((k, str(v)) for k, v in attrs.items())))


def _is_thebe(script) -> bool:
    attrs = getattr(script, "attributes", {}) or {}
    name = str(getattr(script, "filename", script) or "")
    return "sphinx-thebe" in name or "THEBE_JS_URL" in str(attrs.get("body", ""))


def _dedupe_scripts(app, pagename, templatename, context, doctree) -> None:
    scripts = context.get("script_files")
    if not scripts:
        return
    seen: set[tuple] = set()
    unique = []
    for script in scripts:
        if _is_thebe(script):
            continue
        key = _script_key(script)
        if key in seen:
            continue
        seen.add(key)
        unique.append(script)
    scripts[:] = unique


def setup(app):
    app.connect("html-page-context", _dedupe_scripts, priority=900)
    return {"parallel_read_safe": True, "parallel_write_safe": True, "version": "1"}
