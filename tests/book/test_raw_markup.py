"""No raw markup reaches the reader.

Every page of the table of contents, as built, and every sub-command's ``--help`` are
scanned for markup that was meant to be typeset and was not: a MyST or Sphinx role
(``{ref}`x```, ``:func:`x```), a directive fence, a ``(label)=`` line, Markdown emphasis
left as asterisks (``**x**``), reST literals (````x````), and in the math ``\\_`` inside
``\\texttt{}`` (MathJax prints it as it is).  On a page, the visible text is scanned, code
and math excluded (the math is checked for that one pattern).  The counts of pages and
commands scanned are asserted complete, and an injected role is caught.
"""

from __future__ import annotations

import re
from html.parser import HTMLParser
from pathlib import Path

import pytest

from tests.conftest import require_built_book

ROOT = Path(__file__).resolve().parents[2]

RAW = {
    "MyST role": re.compile(r"\{[A-Za-z][\w:+.-]*\}`"),
    "Sphinx role": re.compile(r"(?<![\w:]):[a-z]+(?::[a-z]+)?:`"),
    "directive": re.compile(r"(?:`{3,}|:{3,})\{[\w:+.-]+\}"),
    "label line": re.compile(r"(?m)^\s*\([\w.:-]+\)=\s*$"),
    "Markdown bold": re.compile(r"\*\*[^*\s][^*]*\*\*"),
    "reST literal": re.compile(r"``[^`]+``"),
}
#: In math: an escaped underscore inside \texttt, which MathJax shows as "\_".
TEXTTT_UNDERSCORE = re.compile(r"\\texttt\{[^}]*\\_")
SKIP_TAGS = {"pre", "code", "script", "style", "kbd", "samp", "textarea"}
VOID = {"br", "img", "input", "meta", "link", "hr", "wbr", "source", "col", "area", "base",
        "embed", "param", "track"}


class _Text(HTMLParser):
    """The article's visible text (outside code and math), and its math source."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.stack: list[tuple[str, bool, bool, bool]] = []  # tag, article, skip, math
        self.text: list[str] = []
        self.math: list[str] = []

    def _state(self):
        return self.stack[-1][1:] if self.stack else (False, False, False)

    def handle_starttag(self, tag, attrs):
        if tag in VOID:
            return
        article, skip, math = self._state()
        a = dict(attrs)
        classes = (a.get("class") or "").split()
        article = article or (tag == "article" and "bd-article" in classes)
        skip = skip or tag in SKIP_TAGS or "highlight" in classes or "cell_input" in classes
        math = math or "math" in classes
        self.stack.append((tag, article, skip, math))

    def handle_endtag(self, tag):
        for i in range(len(self.stack) - 1, -1, -1):
            if self.stack[i][0] == tag:
                del self.stack[i:]
                return

    def handle_data(self, data):
        article, skip, math = self._state()
        if not article:
            return
        if math:
            self.math.append(data)
        elif not skip:
            self.text.append(data)


def page_problems(html: str) -> list[str]:
    parser = _Text()
    parser.feed(html)
    text = " ".join(parser.text)
    found = []
    for name, pattern in RAW.items():
        found += [f"{name}: …{text[max(0, m.start() - 30):m.end() + 30]}…"
                  for m in pattern.finditer(text)]
    math = "\n".join(parser.math)
    found += [f"\\_ in \\texttt: …{math[m.start():m.end() + 20]}…"
              for m in TEXTTT_UNDERSCORE.finditer(math)]
    return [" ".join(f.split()) for f in found]


def _toc_pages() -> list[str]:
    import yaml

    toc = yaml.safe_load((ROOT / "_toc.yml").read_text(encoding="utf-8"))
    return [toc["root"], *(c["file"] for part in toc.get("parts", ())
                           for c in part["chapters"])]


def test_the_page_check_catches_an_injected_role_and_skips_code():
    clean = ("<article class='bd-article'><p>Fine text, σ = 1.</p><pre>{ref}`in code`</pre>"
             "<div class='math'>\\(\\texttt{a}\\)</div></article>")
    assert page_problems(clean) == []
    for bad in ("<p>see {ref}`gc-model`</p>", "<p>see :func:`f`</p>", "<p>**previous**</p>",
                "<div class='math notranslate'>\\[\\texttt{printed\\_F}\\]</div>"):
        assert len(page_problems(clean.replace("</article>", bad + "</article>"))) == 1, bad


@pytest.mark.book
def test_no_page_shows_raw_markup():
    html = require_built_book()
    pages = _toc_pages()
    scanned, problems = 0, []
    for page in pages:
        path = html / f"{page}.html"
        assert path.is_file(), path
        problems += [f"{page}: {p}" for p in page_problems(path.read_text(encoding="utf-8"))]
        scanned += 1
    assert scanned == len(pages) == len(list((ROOT / "chapters").glob("*.md")))
    assert not problems, "\n".join(problems)


def help_texts() -> dict[str, str]:
    """``--help`` of ``python -m gyrolib`` and of every command and sub-command, as argparse
    prints it (``format_help``, in this process: no interpreter started per command)."""
    import argparse

    from gyrolib.cli import COMMANDS, OneLineParser

    top = argparse.ArgumentParser(prog="python -m gyrolib")
    sub = top.add_subparsers(dest="command", required=True)
    for module in COMMANDS.values():
        module.add_parser(sub, OneLineParser)
    texts: dict[str, str] = {}

    def walk(parser, name):
        texts[name] = parser.format_help()
        for action in parser._actions:
            if isinstance(action, argparse._SubParsersAction):
                for child, p in action.choices.items():
                    walk(p, f"{name} {child}")

    walk(top, "gyrolib")
    return texts


def help_problems(text: str) -> list[str]:
    found = []
    for name in ("MyST role", "Sphinx role", "directive", "reST literal"):
        found += [f"{name}: {m.group(0)}" for m in RAW[name].finditer(text)]
    return found


def test_no_help_shows_raw_markup():
    from gyrolib.cli import COMMANDS

    texts = help_texts()
    # every command, and below calibrate and sensitivity their gc and rsf
    assert {n.split()[1] for n in texts if n != "gyrolib"} == set(COMMANDS), texts.keys()
    assert len(texts) >= 1 + len(COMMANDS) + 4, list(texts)
    problems = [f"{name}: {p}" for name, text in texts.items() for p in help_problems(text)]
    assert not problems, problems
    assert help_problems("ledger's rule (:func:`gyrolib.judge`)")  # the check can fail
