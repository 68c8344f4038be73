"""Citable from a paper.

* Every ledger item's BibTeX entry parses with pybtex (an independent BibTeX parser) and has
  no TeX special character left unescaped in any field; an injected bare ``_`` is caught.
* With a URL set in ``pyproject.toml [project.urls]``, every item's citation line and entry
  point to it absolutely; with none, each says "unpublished build" with the version and
  ``CITATION.cff``'s ``date-released`` (not the date of the build), never a relative link.
* ``CITATION.cff``, ``.zenodo.json`` and ``_config.yml`` carry the URLs of
  ``[project.urls]`` and no other (none while none is set).
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
import yaml

import gyrolib
from gyrolib.book import cite, ledger

ROOT = Path(__file__).resolve().parents[2]
BOOK_URL = "https://example.org/gyro_book"
REPO_URL = "https://example.org/src/gyro_lib"


@pytest.fixture(scope="module")
def items():
    return ledger.collect()


def parse_bibtex(text: str):
    """pybtex's BibTeX parser on ``text``: what ``pybtex.database.parse_string(text,
    "bibtex")`` does, without its look-up of the parser among the installed packages' entry
    points at every call (about 20 ms each: 1.4 CPU-s for the ledger's entries; the
    parser is the same class, a fresh one per text)."""
    from pybtex.database.input.bibtex import Parser

    return Parser().parse_string(text)


def bibtex_problems(entry: str) -> list[str]:
    """What stops LaTeX in ``entry``: a pybtex parse error, or an unescaped special
    character in a field other than the verbatim ``url``."""
    from pybtex.scanner import PybtexError

    try:
        data = parse_bibtex(entry)
    except PybtexError as exc:
        return [f"pybtex: {exc}"]
    problems = []
    for key, e in data.entries.items():
        fields = dict(e.fields)
        for role, people in e.persons.items():
            fields[role] = " and ".join(str(p) for p in people)
        for name, value in fields.items():
            if name.lower() in cite.VERBATIM_FIELDS:
                if not re.fullmatch(r"https?://\S+", value):
                    problems.append(f"{key}.{name}: not a bare URL: {value!r}")
                continue
            problems += [f"{key}.{name}: unescaped …{s}…" for s in cite.unescaped_specials(value)]
    return problems


def _pyproject(tmp_path, urls: dict[str, str]) -> Path:
    text = "[project]\nname = 'x'\n[project.urls]\n" + "".join(
        f'{k} = "{v}"\n' for k, v in urls.items())
    path = tmp_path / "pyproject.toml"
    path.write_text(text, encoding="utf-8")
    return path


def test_every_item_bibtex_parses_and_escapes(items):
    assert len(items) > 20
    problems = []
    for it in items:
        problems += bibtex_problems(cite.ledger_item_bibtex(it))
    assert not problems, problems
    book = cite.book_bibtex("A title with 100 % & a_b")
    assert not bibtex_problems(book), book
    # the corporate author stays one name: no first name "The", no last name "authors"
    for entry in (book, cite.ledger_item_bibtex(items[0])):
        (person,) = next(iter(parse_bibtex(entry).entries.values())).persons["author"]
        assert not person.first_names and not person.middle_names, str(person)
        assert person.last_names == ["{The gyrolib authors}"], person.last_names


def test_the_bibtex_check_fails_on_an_injected_underscore(items):
    it = next(i for i in items if "_" in i.id)
    entry = cite.ledger_item_bibtex(it)
    assert "\\_" in entry  # the id's underscore, escaped
    broken = entry.replace("\\_", "_", 1)
    assert any("unescaped" in p for p in bibtex_problems(broken)), broken
    assert bibtex_problems(entry.replace("}", "", 1))  # unbalanced: pybtex refuses it
    # parse_bibtex's parser is the one pybtex registers for "bibtex"
    from pybtex.database.input.bibtex import Parser
    from pybtex.plugin import find_plugin

    assert find_plugin("pybtex.database.input", "bibtex") is Parser


def test_without_a_url_every_citation_says_unpublished_build(items, tmp_path, monkeypatch):
    monkeypatch.setattr(cite, "PYPROJECT", _pyproject(tmp_path, {}))
    released = cite.date_released()
    assert released == str(yaml.safe_load((ROOT / "CITATION.cff").read_text())["date-released"])
    expected = f"unpublished build, version {gyrolib.__version__} of {released}"
    bad = [it.id for it in items
           if expected not in ledger.citation(it) or "ledger.html" in ledger.citation(it)
           or expected not in cite.ledger_item_bibtex(it).replace("\n", " ")]
    assert not bad, bad


def test_with_a_url_every_citation_is_absolute(items, tmp_path, monkeypatch):
    monkeypatch.setattr(cite, "PYPROJECT", _pyproject(tmp_path, {"Book": BOOK_URL + "/",
                                                                 "Repository": REPO_URL}))
    bad = []
    for it in items:
        url = f"{BOOK_URL}/chapters/ledger.html#{ledger.anchor(it.id)}"
        line, entry = ledger.citation(it), cite.ledger_item_bibtex(it)
        relative = re.findall(r"(?<![/\w])ledger\.html", line + entry)
        if url not in line or f"url          = {{{url}}}" not in entry or relative:
            bad.append(it.id)
        if "unpublished" in line + entry or bibtex_problems(entry):
            bad.append(it.id)
    assert not bad, bad


def test_a_malformed_url_is_refused(tmp_path):
    with pytest.raises(ValueError, match="Book must be an http"):
        cite.project_urls(_pyproject(tmp_path, {"Book": "ledger.html"}))


def declared_urls(root: Path) -> dict[str, set[str]]:
    """The URLs each release file of ``root`` carries."""
    cff = yaml.safe_load((root / "CITATION.cff").read_text(encoding="utf-8"))
    zen = json.loads((root / ".zenodo.json").read_text(encoding="utf-8"))
    cfg = yaml.safe_load((root / "_config.yml").read_text(encoding="utf-8"))
    return {
        "CITATION.cff": {cff[k].rstrip("/") for k in ("url", "repository-code") if cff.get(k)},
        ".zenodo.json": {r["identifier"].rstrip("/") for r in zen.get("related_identifiers", [])
                         if str(r.get("identifier", "")).startswith("http")},
        "_config.yml": {str(u).rstrip("/") for u in [(cfg.get("repository") or {}).get("url")]
                        if u},
    }


def test_release_files_carry_the_pyproject_urls():
    urls = cite.project_urls()
    want = {"CITATION.cff": {urls[k] for k in ("Book", "Repository") if k in urls},
            ".zenodo.json": {urls[k] for k in ("Book", "Repository") if k in urls},
            "_config.yml": {urls["Repository"]} if "Repository" in urls else set()}
    assert declared_urls(ROOT) == want, (declared_urls(ROOT), want)


def test_the_url_check_catches_a_file_that_disagrees(tmp_path):
    for name in ("CITATION.cff", ".zenodo.json", "_config.yml"):
        (tmp_path / name).write_text((ROOT / name).read_text(encoding="utf-8"), "utf-8")
    cff = tmp_path / "CITATION.cff"
    cff.write_text(cff.read_text() + f"url: {BOOK_URL}\n")
    assert declared_urls(tmp_path)["CITATION.cff"] == {BOOK_URL}
