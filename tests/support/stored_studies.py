"""Shared by the tests of the stored studies (tests/book/ledger/test_studies.py,
tests/book/studies/test_calibrate.py, tests/book/test_gc_studies.py): a changed default in a
test's copy of the code, and the one-line message a stale study must give."""

from __future__ import annotations

import dataclasses

import pytest


def patch_default(monkeypatch: pytest.MonkeyPatch, cls: type, name: str, value: object):
    """Change a dataclass field's default for this test: the field (which the table of inputs
    reads) and the generated ``__init__`` (which ``cls()`` reads)."""
    names = [f.name for f in dataclasses.fields(cls)]
    defaults = list(cls.__init__.__defaults__)
    assert len(defaults) == len(names)   # every field has a default: the index is the field's
    defaults[names.index(name)] = value
    monkeypatch.setattr(cls.__init__, "__defaults__", tuple(defaults))
    monkeypatch.setattr(cls.__dataclass_fields__[name], "default", value)
    assert getattr(cls(), name) == value


def stale_message(exc: pytest.ExceptionInfo, name: str) -> str:
    """The message of a :class:`gyrolib.store.StaleStudy` raised for ``name``: it names the
    study and its refresh command, on one line."""
    msg = str(exc.value)
    assert exc.value.study == name
    assert f"python3 tasks.py refresh {name}" in msg and "\n" not in msg
    return msg
