"""Shared test helpers."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
HTML = ROOT / "_build" / "html"


def require_built_book() -> Path:
    """The built book's HTML folder; builds it (``python3 tasks.py book``) when missing.

    Under the test command (``GYROLIB_BOOK_BUILT=1``) the book has just been built, so a
    missing ``index.html`` is a failure, not a reason to build again.
    """
    index = HTML / "index.html"
    if index.is_file():
        return HTML
    if os.environ.get("GYROLIB_BOOK_BUILT") == "1":
        pytest.fail(f"GYROLIB_BOOK_BUILT=1 but {index} is missing: the book build failed or "
                    "wrote elsewhere")
    proc = subprocess.run([sys.executable, str(ROOT / "tasks.py"), "book"], cwd=ROOT,
                          capture_output=True, text=True, check=False)
    if proc.returncode != 0 or not index.is_file():
        tail = (proc.stdout + proc.stderr)[-4000:]
        pytest.fail(f"`python3 tasks.py book` failed (exit {proc.returncode}):\n{tail}")
    return HTML
