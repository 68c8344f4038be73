"""The ledger against the committed ledger of release 0.3.0: every item whose
verdict or value changed since then, and every item added or removed, is named in the
CHANGELOG's section of the next release, so a reader citing 0.3.0 learns what moved."""

from __future__ import annotations

import json
import re
from pathlib import Path

from gyrolib.book import ledger

ROOT = Path(__file__).resolve().parents[3]
RELEASE = ROOT / "tests" / "releases" / "ledger-0.3.0.json"


def _code(d: dict) -> str:
    """An item's verdict as a stable code: the file's ``status_code`` (schema 4 on), else
    the code of its ``status`` (before schema 4 the status was the bare verdict)."""
    return d.get("status_code") or ledger.STATUS_CODES[d["status"]]


def _changed(old: list[dict], new: list[dict]) -> set[str]:
    a, b = {d["id"]: d for d in old}, {d["id"]: d for d in new}
    out = set(a) ^ set(b)
    for i in set(a) & set(b):
        if (_code(a[i]), a[i]["reproduced_value"]) != (_code(b[i]), b[i]["reproduced_value"]):
            out.add(i)
    return out


def _unreleased() -> str:
    """The CHANGELOG's sections above release 0.3.0's (the releases since)."""
    text = (ROOT / "CHANGELOG.md").read_text(encoding="utf-8")
    m = re.search(r"^(## .*?)^## 0\.3\.0 ", text, flags=re.S | re.M)
    assert m, "CHANGELOG.md has no section above release 0.3.0's"
    return m.group(1)


def test_every_changed_item_is_in_the_changelog():
    old = json.loads(RELEASE.read_text(encoding="utf-8"))
    assert old["version"] == "0.3.0"
    new = json.loads(ledger.to_json(ledger.collect()))
    changed = _changed(old["items"], new["items"])
    assert changed, "nothing changed since 0.3.0? then this test has no power here"
    section = _unreleased()
    missing = sorted(i for i in changed if f"`{i}`" not in section)
    assert not missing, f"changed since 0.3.0 but not in CHANGELOG: {missing}"


def test_the_comparison_has_power():
    old = json.loads(RELEASE.read_text(encoding="utf-8"))["items"]
    moved = [dict(d) for d in old]
    moved[0]["status"] = "fails" if moved[0]["status"] != "fails" else "holds"
    assert _changed(old, moved) == {old[0]["id"]}
    assert _changed(old, old[1:]) == {old[0]["id"]}
