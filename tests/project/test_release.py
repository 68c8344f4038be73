"""One version everywhere: ``pyproject.toml`` is the source.

``gyrolib.__version__``, ``CITATION.cff``, ``.zenodo.json``, the newest ``CHANGELOG.md``
entry and the "How to cite" page must carry the same string; in the built book, so must the
footer of every page and the ledger data files.  Each file is read with its own parser, and
the checker is shown to catch a file that lags behind.
"""

from __future__ import annotations

import csv
import html
import json
import re
import shutil
import tomllib
from pathlib import Path

import pytest
import yaml

import gyrolib
from tests.conftest import require_built_book

ROOT = Path(__file__).resolve().parents[2]


def declared_versions(root: Path) -> dict[str, str | None]:
    """The version each release file of the tree at ``root`` declares (None: none found)."""
    found: dict[str, str | None] = {}
    found["pyproject.toml"] = tomllib.loads(
        (root / "pyproject.toml").read_text(encoding="utf-8"))["project"]["version"]
    found["CITATION.cff"] = str(yaml.safe_load(
        (root / "CITATION.cff").read_text(encoding="utf-8"))["version"])
    found[".zenodo.json"] = json.loads((root / ".zenodo.json").read_text(encoding="utf-8"))[
        "version"]
    heading = re.search(r"^## (\S+)", (root / "CHANGELOG.md").read_text(encoding="utf-8"),
                        re.MULTILINE)
    found["CHANGELOG.md (newest entry)"] = heading.group(1) if heading else None
    return found


def disagreements(found: dict[str, str | None], version: str) -> list[str]:
    return [f"{name}: {got!r} != {version!r}" for name, got in found.items() if got != version]


def test_every_release_file_has_the_pyproject_version():
    found = declared_versions(ROOT)
    version = found["pyproject.toml"]
    assert re.fullmatch(r"\d+\.\d+\.\d+", version), version
    assert gyrolib.__version__ == version
    assert not disagreements(found, version), found


def test_release_date_agrees():
    cff = str(yaml.safe_load((ROOT / "CITATION.cff").read_text())["date-released"])
    zenodo = json.loads((ROOT / ".zenodo.json").read_text())["publication_date"]
    newest = re.search(r"^## \S+ — (\d{4}-\d{2}-\d{2})", (ROOT / "CHANGELOG.md").read_text(),
                       re.MULTILINE)
    assert newest and cff == zenodo == newest.group(1), (cff, zenodo, newest)


def test_the_check_catches_a_file_left_behind(tmp_path):
    for name in ("pyproject.toml", "CITATION.cff", ".zenodo.json", "CHANGELOG.md"):
        shutil.copy(ROOT / name, tmp_path / name)
    version = declared_versions(tmp_path)["pyproject.toml"]
    cff = tmp_path / "CITATION.cff"
    cff.write_text(re.sub(r"^version: .*$", "version: 0.0.1", cff.read_text(), flags=re.M))
    problems = disagreements(declared_versions(tmp_path), version)
    assert problems == [f"CITATION.cff: '0.0.1' != {version!r}"]


def test_no_page_types_the_version_by_hand():
    """The pages that show the version take it from gyrolib (the built page is checked
    below); a version literal in their source would go stale at the next release."""
    version = gyrolib.__version__
    typed = [name for name in ("citing", "intro", "ledger", "references", "status")
             if version in (ROOT / "chapters" / f"{name}.md").read_text(encoding="utf-8")]
    assert not typed, f"version {version} typed into chapters: {typed}"


def test_version_falls_back_to_pyproject_without_installed_metadata(monkeypatch):
    import importlib.metadata as md

    def missing(name):
        raise md.PackageNotFoundError(name)

    monkeypatch.setattr(md, "version", missing)
    assert gyrolib._version() == tomllib.loads(
        (ROOT / "pyproject.toml").read_text())["project"]["version"]


@pytest.mark.book
def test_built_book_shows_the_version_in_footer_citation_and_ledger_data():
    HTML = require_built_book()
    version = gyrolib.__version__
    pages = [p for p in HTML.rglob("*.html")
             if not {"_static", "_sources", "_images"} & set(p.relative_to(HTML).parts)
             and "Refresh" not in p.read_text(encoding="utf-8")[:2000]]
    assert len(pages) > 5
    no_footer = [p.relative_to(HTML).as_posix() for p in pages
                 if f"version {version}" not in p.read_text(encoding="utf-8")]
    assert not no_footer, f"pages without 'version {version}' in the footer: {no_footer}"
    citing = html.unescape(re.sub(r"<[^>]+>", "", (HTML / "chapters" / "citing.html")
                                  .read_text(encoding="utf-8")))  # text, without highlighting
    assert re.search(r"version\s*=\s*\{" + re.escape(version) + r"\}", citing), \
        "the BibTeX of the book on the How to cite page does not carry the version"
    data = json.loads((HTML / "ledger.json").read_text(encoding="utf-8"))
    assert data["version"] == version
    lines = (HTML / "ledger.csv").read_text(encoding="utf-8").splitlines()
    assert lines[0].startswith("# ") and lines[0].endswith(f" {version}"), lines[0]
    rows = list(csv.DictReader(lines[1:]))
    assert [r["id"] for r in rows] == [it["id"] for it in data["items"]]
