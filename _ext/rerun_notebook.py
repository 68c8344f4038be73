"""An executed chapter as a notebook that shows what the book's page shows (issue 35, item 1).

A chapter is a MyST Markdown notebook: its prose pastes the values its code computed with
myst-nb's glue roles (``{glue:text}`key```), shows its figures with ``{glue:figure}``
blocks, and cross-links with ``{ref}``, ``{numref}``, ``{eq}`` and ``{cite:p}``.  Only the
book's build (Sphinx) renders them: opened in Jupyter or rendered with nbconvert, the
executed notebook shows the raw roles, and its figures only as glue records
(``application/papermill.record/image/png``), which Jupyter does not display.

:func:`render_notebook` rewrites an executed notebook's Markdown (its Markdown cells and the
Markdown outputs of its code cells) into plain Markdown, from the notebook's own glue outputs:

* ``{glue:text}`` / ``{glue}`` -> the glued value as text (its format spec applied, as
  myst-nb does); ``{glue:md}`` -> the glued Markdown; a ``{glue:figure}`` block -> the
  glued image as a cell attachment (``![alt](attachment:key.png)``) and its caption,
  "Figure N." in front as on the page;
* ``{ref}`` -> the explicit text, else the target section's title, figure's number or the
  label; ``{numref}`` -> "Fig. N"; ``{eq}`` -> "Eq. (N)"; ``{cite:p}``/``{cite:t}`` -> author
  and year, with a "References" cell at the end listing the works cited (from
  ``references.bib``); ``{bdg-*}`` badges -> bold text; any other role -> its text;
* ``(label)=`` lines are removed; a numbered display equation gets its number as a
  ``\\tag``; ``{raw} html`` keeps its HTML, admonitions become block quotes,
  ``{bibliography}`` the reference list, and other directives their body or a line saying
  that the book's page shows them;
* the glue records, which Jupyter does not display, are dropped (their values are in the
  prose now).

A first cell says that the prose's values are those of the run that wrote the notebook, and
how to refresh them.  The numbers of figures and equations are those of the book: figures
and equations are numbered through the book in the order of ``_toc.yml``
(:func:`label_index`; ``tests/book/test_rerun_notebook.py`` checks both against the built HTML).

Used by ``python3 tasks.py chapter NAME`` (:func:`execute_chapter`: ``python
_ext/rerun_notebook.py --execute CHAPTER.md NOTEBOOK``) and by
``_ext/book_release.py`` for the ``.ipynb`` of each page's download menu.  Needs only the
standard library, nbformat and (for the references) pybtex, all in the book's environment
(:func:`execute_chapter` also jupytext and nbclient, there too).
"""

from __future__ import annotations

import ast
import base64
import re
import sys
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
GLUE_PREFIX = "application/papermill.record/"

#: A role: ``{name}`body```.  (Roles do not nest, and their bodies hold no backtick.)
ROLE = re.compile(r"\{(?P<name>[A-Za-z][\w:+.-]*)\}`(?P<body>[^`]*)`")
#: The opening line of a directive: ```` ```{name} args ```` or ``:::{name} args``.
DIRECTIVE = re.compile(r"^(?P<fence>`{3,}|:{3,})\{(?P<name>[\w:+.-]+)\}[ \t]*(?P<args>.*)$")
#: A target label line, ``(label)=``.
LABEL = re.compile(r"^\((?P<label>[^()\s]+)\)=\s*$")
#: A display equation's label after its closing ``$$``.
MATH_LABEL = re.compile(r"^\$\$[ \t]*\((?P<label>[^()\s]+)\)\s*$")
HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")
EXPLICIT = re.compile(r"^(?P<text>.*?)\s*<(?P<target>[^<>]+)>$", re.S)

ADMONITIONS = {"note", "warning", "tip", "important", "caution", "attention", "danger",
               "error", "hint", "seealso", "admonition", "dropdown"}
#: Directives whose output only the book build makes.
BOOK_ONLY = {"tableofcontents", "nb-exec-table", "benchmark-results", "toctree"}

#: The raw-MyST patterns that must not survive in the rendered notebook (the acceptance
#: test's list): a role, a directive fence, a label line, and the named roles/directives.
RAW_MYST = {
    "role": re.compile(r"\{[A-Za-z][\w:+.-]*\}`"),
    "directive": re.compile(r"^\s*(`{3,}|:{3,})\{[\w:+.-]+\}", re.M),
    "label": re.compile(r"^\s*\([^()\s]+\)=\s*$", re.M),
    "eq": re.compile(r"\{eq\}"),
    "numref": re.compile(r"\{numref\}"),
    "glue:md": re.compile(r"\{glue:md\}"),
    "bibliography": re.compile(r"\{bibliography\}"),
    "bdg": re.compile(r"\{bdg-[a-z-]+\}"),
}


def raw_myst(text: str) -> list[str]:
    """The raw-MyST patterns of :data:`RAW_MYST` found in ``text``, one ``name: match`` each.

    >>> raw_myst("a {ref}`x` and (lbl)=")
    ['role: {ref}`']
    >>> raw_myst("(lbl)=\\nplain")
    ['label: (lbl)=']
    """
    found = []
    for name, pattern in RAW_MYST.items():
        found += [f"{name}: {m.group(0).strip()}" for m in pattern.finditer(text)]
    return found


# --------------------------------------------------------------------------------------------
# What the labels of the book point to
# --------------------------------------------------------------------------------------------

@dataclass
class LabelIndex:
    """Readable text for the book's labels: section titles, figure and equation numbers."""

    titles: dict[str, str] = field(default_factory=dict)
    figures: dict[str, int] = field(default_factory=dict)
    equations: dict[str, int] = field(default_factory=dict)


def _toc_files(root: Path) -> list[Path]:
    """The chapters' sources in the order of ``_toc.yml`` (the root first)."""
    text = (root / "_toc.yml").read_text(encoding="utf-8")
    names = re.findall(r"^\s*(?:root|-\s*file)\s*:\s*(\S+)\s*$", text, re.M)
    return [root / f"{n}.md" for n in names if (root / f"{n}.md").is_file()]


def _plain(text: str) -> str:
    """A heading's text without roles' markup (``{glue:text}`k``` -> ``k``)."""
    return ROLE.sub(lambda m: m.group("body"), text).strip()


def _section_titles(text: str) -> dict[str, str]:
    """The labels of ``text`` that stand right before a heading, with its title."""
    titles, pending = {}, []
    for line in text.splitlines():
        if m := LABEL.match(line):
            pending.append(m.group("label"))
        elif m := HEADING.match(line):
            titles.update(dict.fromkeys(pending, _plain(m.group(2))))
            pending = []
        elif line.strip():
            pending = []
    return titles


def label_index(root: Path = ROOT) -> LabelIndex:
    """The book's labels, read from the chapters' sources in the order of ``_toc.yml``.

    A label before a heading names the heading's title; a ``{glue:figure}``'s ``:name:``
    the figure's number, and a display equation's label its number, both counted through
    the book (``use_multitoc_numbering``).
    """
    index = LabelIndex()
    n_fig = n_eq = 0
    for path in _toc_files(root):
        lines = path.read_text(encoding="utf-8").splitlines()
        pending: list[str] = []
        fence = ""  # inside a code cell or code block: its fence, until the closing one
        opened: list[str] = []  # the fences of the directives open here
        for line in lines:
            s = line.strip()
            if fence:
                if s == fence:
                    fence = ""
                continue
            if opened and s == opened[-1]:  # the end of a directive
                opened.pop()
                continue
            if s.startswith("```{") and not s.startswith("```{code-cell}"):
                opened.append(s[:len(s) - len(s.lstrip("`"))])
            elif s.startswith("```"):
                fence = s[:len(s) - len(s.lstrip("`"))]
                continue
            if m := LABEL.match(line):
                pending.append(m.group("label"))
                continue
            if m := HEADING.match(line):
                for label in pending:
                    index.titles[label] = _plain(m.group(2))
                pending = []
                continue
            if line.strip():
                pending = []
            if line.startswith("```{glue:figure}") or line.startswith("```{figure}"):
                n_fig += 1
                index.figures[f"__next_{n_fig}"] = n_fig  # replaced by the :name: below
            elif line.startswith(":name:") and f"__next_{n_fig}" in index.figures:
                del index.figures[f"__next_{n_fig}"]
                index.figures[line.split(":", 2)[2].strip()] = n_fig
            elif m := MATH_LABEL.match(line):
                n_eq += 1
                index.equations[m.group("label")] = n_eq
        index.figures = {k: v for k, v in index.figures.items() if not k.startswith("__next_")}
    return index


# --------------------------------------------------------------------------------------------
# Glue outputs, citations
# --------------------------------------------------------------------------------------------

def glue_outputs(nb) -> dict[str, dict]:
    """The notebook's glued values, ``key -> mime bundle`` (the glue prefix removed)."""
    found: dict[str, dict] = {}
    for cell in nb.cells:
        if cell.cell_type != "code":
            continue
        for out in cell.get("outputs", []):
            meta = out.get("metadata", {}).get("scrapbook")
            if not meta:
                continue
            # myst-nb's build strips the prefix from the data it read (and keeps the metadata)
            prefix = meta.get("mime_prefix", "")
            found[meta["name"]] = {k.removeprefix(prefix): v
                                   for k, v in out.get("data", {}).items()}
    return found


def format_plain_text(text: str, spec: str = "") -> str:
    """A glued ``text/plain`` value as ``{glue:text}`` shows it (myst-nb's rule: the repr
    evaluated, so that a string loses its quotes, then ``spec`` applied).

    >>> format_plain_text("'1.25'"), format_plain_text("0.123456", ".2f")
    ('1.25', '0.12')
    """
    try:
        value = ast.literal_eval(text)
    except (SyntaxError, ValueError):
        value = text
    if not spec:
        return str(value)
    kind = spec[-1]
    if kind == "s":
        value = str(value)
    elif kind in "bcdoxX":
        value = int(value)
    elif kind in "eEfFgGn%":
        value = float(value)
    return format(value, spec)


class Bibliography:
    """Author-year labels and reference entries from ``references.bib`` (pybtex)."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self._data = None

    def _db(self):
        if self._data is None:
            from pybtex.database import parse_file

            self._data = parse_file(str(self.path))
        return self._data

    def label(self, key: str, textual: bool = False) -> str:
        entry = self._db().entries.get(key)
        if entry is None:
            return key
        people = entry.persons.get("author") or entry.persons.get("editor") or []
        names = [" ".join(p.last_names) or str(p) for p in people]
        names = [n.replace("{", "").replace("}", "") for n in names]
        if "others" in names[1:]:  # BibTeX's "and others"
            names = [names[0], "", ""]
        who = (names[0] if len(names) == 1 else f"{names[0]} and {names[1]}" if len(names) == 2
               else f"{names[0]} et al." if names else key)
        year = entry.fields.get("year", "n.d.")
        return f"{who} ({year})" if textual else f"{who}, {year}"

    def entries(self, keys: list[str]) -> list[str]:
        """Each cited entry as one Markdown line (pybtex's plain style)."""
        from pybtex.plugin import find_plugin

        db = self._db()
        keys = [k for k in keys if k in db.entries]
        if not keys:
            return []
        style = find_plugin("pybtex.style.formatting", "plain")()
        out = {}
        for entry in style.format_bibliography(db, keys).entries:
            text = " ".join(entry.text.render_as("markdown").split())
            out[entry.key] = f"{self.label(entry.key, textual=True)}. {text}"
        return [out[k] for k in keys if k in out]


# --------------------------------------------------------------------------------------------
# The rendering
# --------------------------------------------------------------------------------------------

class _Renderer:
    def __init__(self, glue: dict[str, dict], index: LabelIndex, bib: Bibliography | None):
        self.glue = glue
        self.index = index
        self.bib = bib
        self.cited: list[str] = []
        self.attachments: dict[str, dict] = {}
        self.missing: list[str] = []

    # roles ----------------------------------------------------------------------------
    def _glue_text(self, body: str, markdown: bool = False) -> str:
        key, _, spec = body.partition(":")
        bundle = self.glue.get(key.strip())
        if bundle is None:
            self.missing.append(key)
            return f"*[{key}: not computed in this run]*"
        if markdown and "text/markdown" in bundle:
            return "".join(bundle["text/markdown"]).strip()
        text = bundle.get("text/plain")
        if text is None:
            return f"*[{key}]*"
        return format_plain_text("".join(text), spec.strip())

    def _ref(self, name: str, body: str) -> str:
        m = EXPLICIT.match(body)
        text, target = (m.group("text"), m.group("target")) if m else ("", body.strip())
        if name == "eq":  # as the book writes it (_config.yml: math_eqref_format)
            n = self.index.equations.get(target)
            return f"Eq. ({n})" if n else f"Eq. ({target})"
        if name == "numref":
            n = self.index.figures.get(target)
            if text:
                return text.replace("{number}", str(n or "?")).replace("%s", str(n or "?"))
            return f"Fig. {n}" if n else target
        if text:
            return text
        if target in self.index.titles:
            return f"“{self.index.titles[target]}”"
        if target in self.index.figures:
            return f"Fig. {self.index.figures[target]}"
        return target

    def _cite(self, name: str, body: str) -> str:
        keys = [k.strip() for k in body.split(",") if k.strip()]
        for k in keys:
            if k not in self.cited:
                self.cited.append(k)
        textual = name in ("cite:t", "cite:ts")
        labels = [self.bib.label(k, textual) if self.bib else k for k in keys]
        return "; ".join(labels) if textual else "(" + "; ".join(labels) + ")"

    def role(self, m: re.Match) -> str:
        name, body = m.group("name"), m.group("body")
        if name in ("glue", "glue:text", "glue:any"):
            return self._glue_text(body)
        if name == "glue:md":
            return self._glue_text(body, markdown=True)
        if name in ("ref", "numref", "eq", "doc", "term"):
            return self._ref(name, body)
        if name.startswith("cite"):
            return self._cite(name, body)
        if name.startswith("bdg"):
            m2 = EXPLICIT.match(body)
            return f"**{m2.group('text') if m2 else body}**"
        if name == "math":
            return f"${body}$"
        m2 = EXPLICIT.match(body)
        text = m2.group("text") if m2 and m2.group("text") else body
        return f"`{text}`" if name in ("code", "file", "kbd", "samp", "command",
                                       "func", "data", "class", "mod", "meth") else text

    def roles(self, text: str) -> str:
        return ROLE.sub(self.role, text)

    # directives -----------------------------------------------------------------------
    def _figure(self, key: str, options: dict[str, str], caption: str) -> str:
        bundle = self.glue.get(key)
        number = self.index.figures.get(options.get("name", ""))
        head = f"**Fig. {number}.** " if number else ""
        caption = " ".join(self.roles(caption).split())
        if bundle is None or not any(k.startswith("image/") for k in bundle):
            self.missing.append(key)
            return f"*[Figure {key}: not drawn in this run.]*\n\n{head}{caption}"
        mime = "image/png" if "image/png" in bundle else next(
            k for k in bundle if k.startswith("image/"))
        ext = mime.split("/")[1].split("+")[0]
        name = f"{key}.{ext}"
        data = bundle[mime]
        if isinstance(data, list):
            data = "".join(data)
        if mime == "image/svg+xml":  # text in the bundle, base64 in an attachment
            data = base64.b64encode(data.encode()).decode()
        self.attachments[name] = {mime: data}
        alt = " ".join(options.get("alt", key).split()).replace("]", ")").replace("[", "(")
        return f"![{alt}](attachment:{name})\n\n{head}{caption}"

    def directive(self, name: str, args: str, body: list[str]) -> str:
        options: dict[str, str] = {}
        while body and (m := re.match(r"^:([\w-]+):\s*(.*)$", body[0])):
            options[m.group(1)] = m.group(2)
            body = body[1:]
            # an option's value may go on over indented lines (an :alt: text, say)
            while body and body[0].startswith((" ", "\t")) and body[0].strip():
                options[m.group(1)] += " " + body[0].strip()
                body = body[1:]
        text = "\n".join(body).strip("\n")
        if name in ("glue:figure", "glue:any", "glue", "figure"):
            if name == "figure":
                alt = options.get("alt", "")
                return f"![{alt}]({args.strip()})\n\n{self.render(text)}"
            return self._figure(args.strip(), options, text)
        if name == "glue:md":
            return self._glue_text(args.strip(), markdown=True)
        if name == "glue:math":
            return f"$$\n{self._glue_text(args.strip())}\n$$"
        if name in ("math",):
            label = options.get("label")
            tag = f"\n\\tag{{{self.index.equations[label]}}}" if label in (
                self.index.equations) else ""
            return f"$$\n{text}{tag}\n$$"
        if name == "raw":
            return text if args.strip() == "html" else ""
        if name == "bibliography":
            return "\n\n".join(self.bib.entries(list(self.bib._db().entries))) if (
                self.bib) else ""
        if name in BOOK_ONLY:
            return f"*(The book's page shows here what its build generates: `{name}`.)*"
        if name in ADMONITIONS:
            title = args.strip() or name.capitalize()
            inner = self.render(text)
            return "\n".join([f"> **{self.roles(title)}**", ">",
                              *[f"> {ln}" if ln else ">" for ln in inner.splitlines()]])
        return self.render(text)  # an unknown directive: its content

    # whole texts ----------------------------------------------------------------------
    def render(self, text: str) -> str:
        lines = text.splitlines()
        out: list[str] = []
        i = 0
        equation: list[str] | None = None
        while i < len(lines):
            line = lines[i]
            if equation is not None:  # inside a display equation: wait for its closing $$
                if m := MATH_LABEL.match(line):
                    n = self.index.equations.get(m.group("label"))
                    out += [*equation, f"\\tag{{{n}}}" if n else "", "$$"]
                    equation = None
                elif line.strip() == "$$":
                    out += [*equation, "$$"]
                    equation = None
                else:
                    equation.append(line)
                i += 1
                continue
            if line.strip() == "$$":
                equation = [line]
                i += 1
                continue
            if LABEL.match(line):
                i += 1
                continue
            if m := DIRECTIVE.match(line):
                fence = m.group("fence")
                j = i + 1
                while j < len(lines) and not (lines[j].strip().startswith(fence[0] * len(fence))
                                              and set(lines[j].strip()) == {fence[0]}):
                    j += 1
                out.append(self.directive(m.group("name"), m.group("args"), lines[i + 1:j]))
                i = j + 1
                continue
            if line.lstrip().startswith(("```", "~~~")):  # a code block: copied as it is
                fence = line.lstrip()[:3]
                j = i + 1
                while j < len(lines) and not lines[j].lstrip().startswith(fence):
                    j += 1
                out += lines[i:j + 1]
                i = j + 1
                continue
            out.append(self.roles(line))
            i += 1
        if equation is not None:
            out += equation
        return "\n".join(out)


def first_cell_text(name: str) -> str:
    return (
        "**This notebook was written by running the chapter.**  The numbers and figures in "
        "its prose are those of the run that wrote it, pasted in where the book's page has "
        "them; cross-references and citations are shown as text.  Rerunning the cells here "
        "recomputes the outputs under each cell, but not the prose.  To refresh the prose "
        f"too, run `python3 tasks.py chapter {name}` in the repository (it writes "
        f"`_build/chapters/{name}.ipynb`), or build the book (`python3 tasks.py book`).")


def render_notebook(nb, name: str, root: Path = ROOT, index: LabelIndex | None = None,
                    glue: dict[str, dict] | None = None):
    """``nb`` (an executed chapter, nbformat v4) rewritten in place as described in the
    module's docstring; returns it.  ``name`` is the chapter's name (for the first cell);
    ``glue`` the glued values when the notebook no longer holds them (``key -> output``, as
    myst-nb writes them beside the notebook in ``NAME.glue.json``)."""
    import nbformat

    index = index if index is not None else label_index(root)
    own = {}  # the notebook's own sections (a chapter not in the table of contents, say)
    for cell in nb.cells:
        if cell.cell_type == "markdown":
            own.update(_section_titles(cell.source))
    index = LabelIndex({**own, **index.titles}, index.figures, index.equations)
    bib_path = root / "references.bib"
    values = {k: dict(v.get("data", {})) for k, v in (glue or {}).items()}
    values.update(glue_outputs(nb))
    renderer = _Renderer(values, index, Bibliography(bib_path) if bib_path.is_file() else None)
    for cell in nb.cells:
        if cell.cell_type == "markdown":
            renderer.attachments = {}
            cell.source = renderer.render(cell.source)
            if renderer.attachments:
                cell["attachments"] = {**cell.get("attachments", {}), **renderer.attachments}
        elif cell.cell_type == "code":
            # the glue records (display=False) show nothing in Jupyter: their values are
            # in the prose now
            cell.outputs = [o for o in cell.get("outputs", []) if not o.get(
                "metadata", {}).get("scrapbook", {}).get("mime_prefix")]
            for out in cell.outputs:
                data = out.get("data", {})
                if "text/markdown" in data:
                    md = data["text/markdown"]
                    md = "".join(md) if isinstance(md, list) else md
                    data["text/markdown"] = renderer.render(md)
    first = nbformat.v4.new_markdown_cell(first_cell_text(name))
    first.metadata["gyrolib"] = "rerun-note"
    drop = ("rerun-note", "references") if renderer.cited else ("rerun-note",)
    cells = [c for c in nb.cells if c.get("metadata", {}).get("gyrolib") not in drop]
    cells.insert(0, first)
    if renderer.cited and renderer.bib is not None:
        refs = nbformat.v4.new_markdown_cell(
            "## References\n\n" + "\n\n".join(renderer.bib.entries(renderer.cited)))
        refs.metadata["gyrolib"] = "references"
        cells.append(refs)
    nb.cells = cells
    nb.metadata["gyrolib"] = {"rendered_for_jupyter": True,
                              "missing_glue": sorted(set(renderer.missing))}
    return nb


def render_file(path: Path, name: str | None = None, root: Path = ROOT,
                out: Path | None = None, index: LabelIndex | None = None) -> Path:
    """Render the executed notebook ``path`` (in place, or into ``out``), with the glued
    values of ``NAME.glue.json`` beside it when there is one: the book's build (myst-nb)
    moves them there from the notebook it writes to ``_build/jupyter_execute``."""
    import json

    import nbformat

    nb = nbformat.read(str(path), as_version=4)
    glue_file = Path(path).with_name(Path(path).stem + ".glue.json")
    glue = json.loads(glue_file.read_text(encoding="utf-8")) if glue_file.is_file() else None
    render_notebook(nb, name or Path(path).stem, root, index, glue)
    target = out or path
    nbformat.write(nb, str(target))
    return Path(target)


def execute_chapter(src: Path, ipynb: Path, timeout: int = 600) -> Path:
    """Execute the chapter ``src`` (MyST Markdown) as a notebook and write it, rendered, to
    ``ipynb``: jupytext reads it, nbclient executes it in a kernel started in ``ipynb``'s
    folder (as ``jupyter nbconvert --execute`` does, with the same client), and
    :func:`render_notebook` renders it.  One process for the three steps, where three
    commands (``jupytext``, ``jupyter nbconvert``, this script) each started an interpreter
    and imported nbformat and its schema: about 2 CPU-s less per chapter.  The kernel
    inherits this process's environment (``tasks.py chapter`` sets it)."""
    import jupytext
    import nbformat
    from nbclient import NotebookClient

    nb = jupytext.read(str(src))
    NotebookClient(nb, timeout=timeout,
                   resources={"metadata": {"path": str(Path(ipynb).parent)}}).execute()
    render_notebook(nb, Path(src).stem)
    nbformat.write(nb, str(ipynb))
    return Path(ipynb)


if __name__ == "__main__":
    # python _ext/rerun_notebook.py NOTEBOOK.ipynb [NAME]: render an executed notebook
    # python _ext/rerun_notebook.py --execute CHAPTER.md NOTEBOOK.ipynb: execute and render
    if len(sys.argv) == 4 and sys.argv[1] == "--execute":
        print(f"executed {execute_chapter(Path(sys.argv[2]), Path(sys.argv[3]))}")
    elif len(sys.argv) in (2, 3) and not sys.argv[1].startswith("-"):
        print(f"rendered {render_file(Path(sys.argv[1]), *sys.argv[2:3])}")
    else:
        sys.exit("usage: rerun_notebook.py NOTEBOOK.ipynb [CHAPTER_NAME] | "
                 "--execute CHAPTER.md NOTEBOOK.ipynb")
