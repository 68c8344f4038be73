"""Functions do one thing: no function of the library runs past 80 lines without its
docstring (counted by Python's own parser, decorators and signature included), so that a
reader can hold each in view; power: a function of 81 such lines is caught, one of 80 is
not, and a long docstring does not count against its function."""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
LIMIT = 80


def long_functions(source: str, where: str = "<source>") -> list[tuple[str, int]]:
    """``(place, lines)`` of each function in ``source`` longer than :data:`LIMIT` lines
    without its docstring."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            continue
        first = node.body[0]
        doc = (first.end_lineno - first.lineno + 1
               if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant)
               and isinstance(first.value.value, str) else 0)
        start = min([node.lineno, *(d.lineno for d in node.decorator_list)])
        n = node.end_lineno - start + 1 - doc
        if n > LIMIT:
            found.append((f"{where}:{node.lineno} {node.name}", n))
    return found


def test_no_library_function_is_longer_than_80_lines_without_its_docstring():
    found = [hit for path in sorted((ROOT / "gyrolib").rglob("*.py"))
             for hit in long_functions(path.read_text(encoding="utf-8"),
                                       str(path.relative_to(ROOT)))]
    assert found == [], found


def _function(n_body: int, doc_lines: int = 0) -> str:
    doc = ['    """' + "\n".join(["x"] * max(doc_lines, 1)) + '"""'] if doc_lines else []
    return "\n".join(["def f():", *doc, *(f"    a{i} = {i}" for i in range(n_body))]) + "\n"


def test_the_count_has_power():
    assert long_functions(_function(80)) != []          # 81 lines with its def
    assert long_functions(_function(79)) == []          # 80 lines: at the limit
    assert long_functions(_function(79, doc_lines=40)) == []


def test_the_tests_are_laid_out_like_the_library():
    """Each subpackage of gyrolib has its room in tests/ (gc, rsf, filtering, records,
    sensitivity, cli, book and book/ledger), and at most five test files stay at the root."""
    rooms = sorted(p.relative_to(ROOT / "gyrolib").as_posix()
                   for p in (ROOT / "gyrolib").rglob("__init__.py")
                   if p.parent != ROOT / "gyrolib"
                   and len(p.parent.relative_to(ROOT / "gyrolib").parts) == 1)
    missing = [r for r in rooms if not (ROOT / "tests" / r.removesuffix("/__init__.py")
                                        ).is_dir()]
    assert missing == []
    assert (ROOT / "tests" / "book" / "ledger").is_dir()
    assert len(list((ROOT / "tests").glob("test_*.py"))) <= 5
