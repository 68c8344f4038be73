"""Every heavy study the book reads, kept in the store (:mod:`gyrolib.store`).

A study is computed offline by ``python3 tasks.py refresh NAME``, kept as package data, and
checked against the code on every read (its key, then its fingerprint points recomputed):

* the ledger's studies (:mod:`gyrolib.book.ledger.studies`): the claim maps with the race's
  verdict grid, and the two Sobol' studies of the claims' margins;
* the chapters' studies, one module each in this package, registered when it is imported
  (:data:`CHAPTER_MODULES`).

:data:`NAMES` lists them all in the order ``refresh --list`` shows them; :func:`check_all`
is what the ledger, the ``claims`` command, the chapters and the tests run.

Examples
--------
>>> from gyrolib.book import studies
>>> studies.NAMES[:3]
('claim-maps', 'sensitivity-gc', 'sensitivity-rsf')
"""

from __future__ import annotations

from typing import Final

from gyrolib import store
from gyrolib.book.ledger import studies as ledger_studies
from gyrolib.book.studies import calibrate
from gyrolib.book.studies import gc as gc_studies

__all__ = ["CHAPTER_MODULES", "NAMES", "check_all"]

#: The modules of this package that register a chapter's studies (each has ``NAMES``).
CHAPTER_MODULES: Final[tuple[object, ...]] = (calibrate, gc_studies)

#: Every registered study of the book: the ledger's first, then the chapters'.
NAMES: Final[tuple[str, ...]] = ledger_studies.NAMES + tuple(
    n for m in CHAPTER_MODULES for n in m.NAMES)  # type: ignore[attr-defined]


def check_all(names: tuple[str, ...] | None = None, *, memo: bool = True) -> int:
    """Check every study of ``names`` (default: all of :data:`NAMES`) by
    :func:`gyrolib.store.check` (with ``memo``, a check that passed under the same sources,
    file, key, versions and CPU class is read from the check memo); raises
    :class:`gyrolib.store.StaleStudy` naming the first stale one and its refresh command.
    Returns how many points agreed."""
    return sum(store.check(n, memo=memo) for n in (NAMES if names is None else names))
