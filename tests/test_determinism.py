"""Two builds give the same numbers.

The test command has just built the book (with the jupyter cache).  This test builds it a
second time into a temporary folder with every chapter re-executed (no cache) and compares,
page by page, every glued number, every table cell and every printed output text.  Random
runs take explicit seeds, so the two must agree character for character.
"""

import os
import shutil
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path

import pytest
import yaml
from conftest import require_built_book

ROOT = Path(__file__).resolve().parents[1]
HTML = ROOT / "_build" / "html"
JB = Path(sys.executable).with_name("jupyter-book")

pytestmark = [pytest.mark.book, pytest.mark.slow]


class _Numbers(HTMLParser):
    """Collects the text of glued values, table cells and code-cell outputs."""

    KEEP = ("pasted-text", "output", "cell_output")

    def __init__(self):
        super().__init__()
        self.stack: list[bool] = []
        self.texts: list[str] = []

    def handle_starttag(self, tag, attrs):
        cls = dict(attrs).get("class") or ""
        keep = tag in ("td", "th") or any(k in cls.split() for k in self.KEEP)
        self.stack.append(keep or (bool(self.stack) and self.stack[-1]))

    def handle_endtag(self, tag):
        if self.stack:
            self.stack.pop()

    def handle_data(self, data):
        if self.stack and self.stack[-1] and data.strip():
            self.texts.append(data.strip())


def _numbers(page: Path) -> list[str]:
    parser = _Numbers()
    parser.feed(page.read_text(encoding="utf-8"))
    return parser.texts


def _skip_volatile(rel: str) -> bool:
    # The status page reports execution times, which legitimately differ between builds.
    return rel in ("chapters/status.html", "search.html", "genindex.html")


def test_second_uncached_build_gives_identical_numbers(tmp_path):
    require_built_book()
    cfg = yaml.safe_load((ROOT / "_config.yml").read_text())
    cfg["execute"]["execute_notebooks"] = "force"
    cfg["sphinx"]["local_extensions"] = {name: str(ROOT / path) for name, path
                                         in cfg["sphinx"]["local_extensions"].items()}
    config = tmp_path / "_config.yml"
    config.write_text(yaml.safe_dump(cfg, allow_unicode=True))
    out = tmp_path / "second"
    env = dict(os.environ, MPLBACKEND="Agg")
    proc = subprocess.run(
        [str(JB), "build", str(ROOT), "--builder", "html", "--config", str(config),
         "--path-output", str(out), "-W", "-n", "--keep-going"],
        capture_output=True, text=True, env=env, cwd=ROOT,
    )
    assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-4000:]
    second = out / "_build" / "html"
    differences = []
    for page in sorted(HTML.rglob("*.html")):
        rel = page.relative_to(HTML).as_posix()
        if rel.startswith("_") or _skip_volatile(rel):
            continue
        other = second / rel
        if not other.is_file():
            differences.append(f"{rel}: missing in the second build")
            continue
        a, b = _numbers(page), _numbers(other)
        if a != b:
            diff = next((f"{x!r} != {y!r}" for x, y in zip(a, b) if x != y), "lengths differ")
            differences.append(f"{rel}: {diff}")
    shutil.rmtree(out, ignore_errors=True)
    assert not differences, "\n".join(differences)
