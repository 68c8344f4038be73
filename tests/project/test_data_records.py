"""``data/README.md`` is what ``data/make_records.py`` writes: its description of the
records and of the sensitivity studies in ``gyrolib/data/`` is read from the files, so it cannot
go on describing studies the package no longer holds (it described the 0.2.0 files until 0.5.2).
"""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def _make_records():
    spec = importlib.util.spec_from_file_location("make_records", ROOT / "data" / "make_records.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_the_data_readme_is_the_one_make_records_writes():
    mod = _make_records()
    truth = json.loads((ROOT / "data" / "truth.json").read_text())
    text = (ROOT / "data" / "README.md").read_text()
    assert text == mod.readme_text(truth)
    # what it says of each study is the file's own: its size and the command that wrote it
    studies = {name: json.loads((ROOT / "gyrolib" / "data" / f"sensitivity_{name}.json")
                                .read_text()) for name in ("gc", "rsf")}
    for study in studies.values():
        assert f"N = {study['n']} " in text and study["run"]["command"] in text
    # power: the 0.2.0 description (N = 2048 over 12 inputs, written to data/) is not it
    stale = text.replace(f"N = {studies['gc']['n']} ", "N = 2048 ")
    assert stale != mod.readme_text(truth)
