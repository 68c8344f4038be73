"""Citing the book and a single reproduced result.

One source for where the book lives: ``pyproject.toml``'s ``[project.urls]``
(``Repository``, ``Book``).  :func:`project_urls` reads it; ``CITATION.cff``,
``.zenodo.json`` and ``_config.yml`` are tested equal to it (``tests/book/test_cite.py``).  When
the book has a URL, an item's citation points to it absolutely
(``<Book>/chapters/ledger.html#<anchor>``); when it has none (an unpublished build), the
citation says so, with the version and the release date of ``CITATION.cff``
(``date-released``) — never a relative link, and never the date of the build.

BibTeX: :func:`bibtex_escape` escapes the characters TeX treats specially
(``# $ % & _ { } ~ ^ \\``), so that a title such as ``sigma_gc`` does not stop LaTeX
("Missing $ inserted"); :func:`book_bibtex` and :func:`item_bibtex` write the entries the
"How to cite" page shows.
"""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

import gyrolib
from gyrolib import _validation

#: The source tree (an installed copy without it has no URLs and no release date).
ROOT = Path(__file__).resolve().parents[2]
PYPROJECT = ROOT / "pyproject.toml"
CITATION_CFF = ROOT / "CITATION.cff"
TITLE = "Gyro calibration, reproduced"
AUTHORS = "The gyrolib authors"

#: TeX's special characters and their escapes in running text.
_ESCAPES = {
    "\\": r"\textbackslash{}", "{": r"\{", "}": r"\}", "#": r"\#", "$": r"\$", "%": r"\%",
    "&": r"\&", "_": r"\_", "~": r"\textasciitilde{}", "^": r"\textasciicircum{}",
}
_SPECIAL = re.compile(r"[\\{}#$%&_~^]")


def project_urls(pyproject: Path | None = None) -> dict[str, str]:
    """``[project.urls]`` of ``pyproject.toml`` (empty when none is set).

    >>> isinstance(project_urls(), dict)
    True
    """
    path = PYPROJECT if pyproject is None else Path(pyproject)
    if not path.is_file():
        return {}
    urls = tomllib.loads(path.read_text(encoding="utf-8")).get("project", {}).get("urls", {})
    urls = {k: str(v).strip().rstrip("/") for k, v in urls.items() if str(v).strip()}
    for k, v in urls.items():
        if not re.fullmatch(r"https?://[^\s{}\\\"<>]+", v):
            raise ValueError(f"{path.name} [project.urls] {k} must be an http(s) URL without "
                             f"spaces, braces or backslashes; got {v!r}")
    return urls


def date_released(cff: Path | None = None) -> str | None:
    """``date-released`` of ``CITATION.cff`` (``None`` when the file is not there)."""
    path = CITATION_CFF if cff is None else Path(cff)
    if not path.is_file():
        return None
    m = re.search(r"^date-released:\s*[\"']?(\d{4}-\d{2}-\d{2})", path.read_text(
        encoding="utf-8"), re.M)
    return m.group(1) if m else None


def release_label(cff: Path | None = None) -> str:
    """``version X of YYYY-MM-DD`` (the release date of ``CITATION.cff``).

    >>> release_label().startswith(f"version {gyrolib.__version__}")
    True
    """
    date = date_released(cff)
    return f"version {gyrolib.__version__}" + (f" of {date}" if date else "")


def ledger_location(anchor: str, pyproject: Path | None = None,
                    cff: Path | None = None) -> str:
    """Where a ledger item is found: its absolute URL when the book has one, else
    ``unpublished build, version X of DATE``.

    >>> ledger_location("gc-x", pyproject=Path("/nonexistent"))[:27]
    'unpublished build, version '
    """
    if not re.fullmatch(r"[A-Za-z0-9][\w.-]*", str(anchor)):
        raise ValueError(f"anchor must be a ledger item's anchor (letters, digits, '-', "
                         f"'.', '_'); got {anchor!r}")
    book = project_urls(pyproject).get("Book")
    if book:
        return f"{book}/chapters/ledger.html#{anchor}"
    return f"unpublished build, {release_label(cff)}"


def bibtex_escape(text: str) -> str:
    """``text`` with TeX's special characters escaped, for a BibTeX field.

    >>> print(bibtex_escape("sigma_gc 100 % & #1 {x} ~a^2 \\\\"))
    sigma\\_gc 100 \\% \\& \\#1 \\{x\\} \\textasciitilde{}a\\textasciicircum{}2 \\textbackslash{}
    """
    return _SPECIAL.sub(lambda m: _ESCAPES[m.group(0)], str(text))


def unescaped_specials(value: str) -> list[str]:
    """The TeX special characters of a BibTeX field's value that are not escaped (outside
    ``\\textbackslash{}``-style macros and ``\\x`` escapes), each with its neighbours; an
    empty list for a value LaTeX typesets.  Braces are left to the BibTeX parser.

    >>> unescaped_specials(r"a\\_b \\textasciitilde{}"), unescaped_specials("a_b")
    ([], ['a_b'])
    """
    bare = re.sub(r"\\(?:[A-Za-z]+(?:\{\})?|[\\{}#$%&_~^])", "", value)
    return [bare[max(0, m.start() - 10):m.end() + 10] for m in re.finditer(r"[#$%&_~^]", bare)]


#: BibTeX fields written as they are: a URL (verbatim in biblatex; natbib's styles print it
#: with ``\\url``, which takes ``#``, ``%``, ``_`` and ``~`` literally).
VERBATIM_FIELDS = ("url",)


#: Fields holding one name that BibTeX must not split into first and last names (a
#: corporate author): written in an extra pair of braces.
CORPORATE_FIELDS = ("author",)


def _value(name: str, value: str) -> str:
    if name in VERBATIM_FIELDS:
        return value
    if name in CORPORATE_FIELDS:
        return "{" + bibtex_escape(value) + "}"
    return bibtex_escape(value)


def _entry(kind: str, key: str, fields: dict[str, str]) -> str:
    width = max(len(k) for k in fields)
    body = ",\n".join(f"  {k:<{width}} = {{{_value(k, v)}}}" for k, v in fields.items())
    return f"@{kind}{{{key},\n{body}\n}}"


def _common(cff: Path | None, pyproject: Path | None) -> dict[str, str]:
    date = date_released(cff)
    fields = {"author": AUTHORS, "year": date[:4] if date else "n.d.",
              "version": gyrolib.__version__}
    urls = project_urls(pyproject)
    if urls.get("Book") or urls.get("Repository"):
        fields["url"] = urls.get("Book") or urls["Repository"]
    return fields


def book_bibtex(title: str, cff: Path | None = None, pyproject: Path | None = None) -> str:
    """The BibTeX entry of the book (``title``: the one of ``CITATION.cff``)."""
    fields = {"title": title, **_common(cff, pyproject)}
    if "url" not in fields:
        fields["note"] = f"Jupyter Book and Python library (gyrolib); unpublished build, " \
                         f"{release_label(cff)}"
    else:
        fields["note"] = ("Jupyter Book and Python library (gyrolib); a reproduced value is "
                          "cited by its ledger item id and this version")
    return _entry("misc", f"gyrocalibration_reproduced_{gyrolib.__version__.replace('.', '_')}",
                  fields)


def item_bibtex(item_id: str, quantity: str, anchor: str, note: str,
                cff: Path | None = None, pyproject: Path | None = None) -> str:
    """The BibTeX entry of one ledger item (its id, quantity, anchor and a note saying what
    was reproduced)."""
    fields = {"title": f"{quantity} (ledger item {item_id})", **_common(cff, pyproject)}
    location = ledger_location(anchor, pyproject, cff)
    fields["howpublished"] = (f"{TITLE}, {release_label(cff)}, reproduction ledger, item "
                              f"{item_id}")
    if location.startswith("http"):
        fields["url"] = location
    else:
        fields["howpublished"] += f" ({location})"
    fields["note"] = note
    key = "gyrocalibration_reproduced_" + re.sub(r"\W", "_", anchor)
    return _entry("misc", key, fields)


def rounded(value: float | str | None, precision: int) -> float | str | None:
    """``value`` rounded to ``precision`` significant digits (text and ``None`` unchanged).

    Cited values must not depend on the CPU's last-bit rounding: the ledger files and the
    command line report every number at its item's declared precision.

    >>> rounded(0.0013742137, 3)
    0.00137
    """
    if value is None or isinstance(value, str):
        return value
    return float(f"{_validation.check_real('value', value):.{precision}g}")


def anchor(item_id: str) -> str:
    """The HTML id of an item's entry on the ledger page (Sphinx's id for the label
    ``item_id``), e.g. ``gc.sigma_gc_100s`` → ``gc-sigma-gc-100s``.

    >>> anchor("gc.sigma_gc_100s")
    'gc-sigma-gc-100s'
    """
    from docutils.nodes import make_id  # start-up: docutils only when an anchor is made

    return make_id(_validation.check_str("item_id", item_id))


def ledger_item_bibtex(item, cff: Path | None = None, pyproject: Path | None = None) -> str:
    """:func:`item_bibtex` of a ledger item (:class:`gyrolib.book.ledger.LedgerItem`): its
    reproduced value rounded to its declared precision, the paper's print and the verdict in
    the note."""
    it = item
    if it.reproduced_value is None:
        value = "none"
    else:
        value = f"{rounded(it.reproduced_value, it.precision):.{it.precision}g}"
    unit = "" if it.unit in ("", "—") else f" {it.unit}"
    note = (f"Reproduced value {value}{unit}; paper {it.paper}, {it.location}, printed "
            f"{it.paper_value}; status: {it.status_line}")
    return item_bibtex(it.id, it.quantity, anchor(it.id), note, cff, pyproject)
