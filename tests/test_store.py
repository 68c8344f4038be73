"""gyrolib.store on a study of its own: the key sees every constant and default, the check fails
by name with the refresh command, refresh writes the header, an executor gives the same file."""

from __future__ import annotations

import json
import types
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import pytest

from gyrolib import __version__, store


def _module(r: float, flags: frozenset = frozenset({"a", "b", "c"})) -> types.ModuleType:
    """A module as the key sees it: an upper-case constant, a set, a default dataclass."""
    m = types.ModuleType("toy_model")

    @dataclass(frozen=True)
    class Params:
        rate: float = r
        gain: float = 2.0

    Params.__module__ = m.__name__
    m.RATE, m.FLAGS, m.Params, m._private = r, flags, Params, object()
    return m


def test_key_sees_constants_and_defaults_and_not_hash_order():
    k = store.model_key([_module(1.0)])
    assert k == store.model_key([_module(1.0, frozenset({"c", "b", "a"}))])
    moved = store.model_key([_module(1.1)])
    only_default = _module(1.1)
    only_default.RATE = 1.0            # the dataclass's default alone moved
    assert store.model_key([only_default]) != k
    assert moved["toy_model"] != k["toy_model"]
    with pytest.raises(store.StaleStudy, match=r"in toy_model \("):
        store.check_key("toy", k, moved)
    store.check_key("toy", k, dict(k))   # the same key: no error


def test_a_name_the_module_declares_no_input_leaves_the_key():
    """A module's ``__key_ignore__`` names upper-case names that are not model inputs (a
    search hint, a table derived from keyed rows): adding or changing one leaves the key as
    it was; power: the same change to a name not listed moves the key, and a listed name
    does not hide a change of another."""
    base = _module(1.0)
    k = store.model_key([base])
    hinted = _module(1.0)
    hinted.SEARCH_HINT = ("gc.sigma1_sq",)
    hinted.__key_ignore__ = ("SEARCH_HINT",)
    assert store.model_key([hinted]) == k
    unlisted = _module(1.0)
    unlisted.SEARCH_HINT = ("gc.sigma1_sq",)
    assert store.model_key([unlisted]) != k
    both = _module(1.1)
    both.SEARCH_HINT = ("gc.sigma1_sq",)
    both.__key_ignore__ = ("SEARCH_HINT",)
    assert store.model_key([both]) != k


def test_compare_and_sign_use_the_declared_tolerance():
    store.compare("toy", "x", 1.0, 1.0 + 5e-7, rtol=1e-6, atol=0.0)
    store.compare("toy", "x", float("nan"), float("nan"), rtol=1e-6, atol=0.0)
    with pytest.raises(store.StaleStudy, match=r"x was 1\.0, the code now gives 1\.00001"):
        store.compare("toy", "x", 1.0, 1.00001, rtol=1e-6, atol=0.0)
    store.same_sign("toy", "m", True, 0.1)
    with pytest.raises(store.StaleStudy, match=r"m should be > 0, the code now gives nan"):
        store.same_sign("toy", "m", True, float("nan"))


# a toy study: y = RATE * x at a few points --------------------------------------------------------
_STATE = {"rate": 1.0}


def _times(x: float, rate: float) -> float:
    return rate * x


def _compute(executor, progress, *, path=None, xs=(1.0, 2.0, 3.0)):
    ex = executor or ThreadPoolExecutor(1)
    ys = list(ex.map(_times, xs, [_STATE["rate"]] * len(xs)))
    if progress is not None:
        progress.update(len(xs))
    return {"xs": list(xs), "ys": ys}


def _check(data) -> int:
    h = store.header_of("toy", data)
    for x, y in zip(data["xs"], data["ys"], strict=True):
        store.compare("toy", f"y at x = {x}", y, _times(x, _STATE["rate"]), rtol=h.rtol,
                      atol=h.atol)
    return len(data["xs"])


@pytest.fixture
def toy(tmp_path, monkeypatch):
    monkeypatch.setitem(_STATE, "rate", 1.0)
    monkeypatch.setenv(store.MEMO_ENV, str(tmp_path / "memo"))   # this test's own memo
    s = store.Study("toy", tmp_path / "toy.json",
                    lambda: store.model_key(constants={"rate": _STATE["rate"]}), _check,
                    _compute, rtol=1e-9, atol=0.0, what="a toy")
    monkeypatch.setitem(store._REGISTRY, "toy", s)
    return s


def test_refresh_writes_the_header_and_the_check_passes(toy):
    with pytest.raises(store.StaleStudy, match="does not exist"):
        store.check("toy")
    path = store.refresh("toy")
    data = json.loads(path.read_text("utf-8"))
    assert data["ys"] == [1.0, 2.0, 3.0]
    h = store.header_of("toy", data)
    assert (h.study, h.version, h.cpu_class, h.rtol) == ("toy", __version__,
                                                         store.cpu_class(), 1e-9)
    assert h.cost_cpu_s is not None and h.cost_cpu_s >= 0 and h.date.startswith("20")
    assert store.check("toy") == 3
    st = store.state("toy")
    assert st["state"] == "fresh" and st["points"] == 3 and st["cpu_class"] == h.cpu_class


def test_a_moved_constant_or_number_fails_by_name(toy, monkeypatch):
    store.refresh("toy")
    monkeypatch.setitem(_STATE, "rate", 1.1)
    with pytest.raises(store.StaleStudy) as exc:
        store.check("toy")
    msg = str(exc.value)
    assert msg.startswith("the stored study toy is stale: its key differs")
    assert msg.endswith("refresh it: python3 tasks.py refresh toy") and "\n" not in msg
    data = json.loads(toy.file.read_text("utf-8"))       # the key alone aside: the points
    with pytest.raises(store.StaleStudy, match=r"y at x = 1\.0 was 1\.0, the code now gives 1\.1"):
        _check(data)
    assert store.state("toy")["state"] == "stale"


def test_a_stale_key_does_not_hide_whether_the_points_agree(toy, monkeypatch):
    """The listing's state says the key's state and the points' apart: a key moved by a
    constant the points do not read (they still agree), and a key and points both moved."""
    store.refresh("toy")
    key = toy.key
    monkeypatch.setitem(store._REGISTRY, "toy", store.Study(
        "toy", toy.file, lambda: {**key(), "extra": "0" * 16}, _check, _compute,
        rtol=1e-9, atol=0.0))
    st = store.state("toy")
    assert (st["state"], st["key"], st["points_state"], st["points"]) == (
        "stale", "differs", "agree", 3)
    assert "in extra" in st["key_reason"] and st["points_reason"] == ""
    monkeypatch.setitem(_STATE, "rate", 1.1)      # the points move too
    st = store.state("toy")
    assert (st["key"], st["points_state"]) == ("differs", "disagree")
    assert "y at x = 1.0 was 1.0" in st["points_reason"] and st["points_reason"] in st["reason"]


# the check memo ------------------------------------------------------------------------------
def _counting(toy, monkeypatch) -> list[int]:
    """Register the toy with a check that counts its calls; returns the counter."""
    calls = [0]

    def counted(data):
        calls[0] += 1
        return _check(data)

    import dataclasses

    monkeypatch.setitem(store._REGISTRY, "toy", dataclasses.replace(toy, check=counted))
    return calls


def test_a_passed_check_is_read_from_the_memo_under_the_same_digest(toy, monkeypatch):
    store.refresh("toy")
    calls = _counting(toy, monkeypatch)
    assert store.check("toy") == 3 and calls[0] == 1          # computed, remembered
    assert store.check("toy") == 3 and calls[0] == 1          # read from the memo
    assert store.state("toy")["from_memo"] is True
    assert store.check("toy", memo=False) == 3 and calls[0] == 2
    (memo,) = (toy.file.parent / "memo").glob("toy-*.json")
    parts = json.loads(memo.read_text("utf-8"))["parts"]
    assert {"file", "sources", "key", "numpy", "cpu_class", "python"} <= set(parts)
    monkeypatch.setenv(store.MEMO_ENV, "off")                 # turned off: computed
    assert store.memo_folder() is None
    assert store.check("toy") == 3 and calls[0] == 3


def test_a_failed_check_is_not_remembered(toy, monkeypatch):
    store.refresh("toy")
    calls = _counting(toy, monkeypatch)
    data = json.loads(toy.file.read_text("utf-8"))
    data["ys"][0] = 1.5                                       # a number moved in the file
    toy.file.write_text(json.dumps(data))
    for n in (1, 2):
        with pytest.raises(store.StaleStudy, match=r"y at x = 1\.0 was 1\.5"):
            store.check("toy")
        assert calls[0] == n
    assert not list((toy.file.parent / "memo").glob("toy-*.json"))


def test_a_memo_written_under_another_cpu_class_is_not_read(toy, monkeypatch):
    store.refresh("toy")
    calls = _counting(toy, monkeypatch)
    here = store.cpu_class()
    other = "AVX2" if here != "AVX2" else "AVX-512"
    monkeypatch.setattr(store, "cpu_class", lambda: other)
    assert store.check("toy") == 3 and calls[0] == 1          # remembered under the other
    assert store.check("toy") == 3 and calls[0] == 1
    monkeypatch.setattr(store, "cpu_class", lambda: here)
    assert store.check("toy") == 3 and calls[0] == 2          # this class: computed
    assert store.state("toy")["from_memo"] is True            # and remembered for it


def test_a_changed_file_of_the_package_misses_the_memo(toy, monkeypatch, tmp_path):
    """The digest covers every file of the package (a function's body, a constant of a
    module the key does not read, a data file): one byte changed, the check is computed."""
    package = tmp_path / "package"
    (package / "sub").mkdir(parents=True)
    (package / "sub" / "model.py").write_text("def f(x):\n    return 2.0 * x\n")
    (package / "sub" / "__pycache__").mkdir()
    monkeypatch.setattr(store, "_PACKAGE", package)
    store.refresh("toy")
    calls = _counting(toy, monkeypatch)
    assert store.check("toy") == 3 and calls[0] == 1
    (package / "sub" / "__pycache__" / "model.pyc").write_bytes(b"bytecode")  # not a source
    assert store.check("toy") == 3 and calls[0] == 1
    (package / "sub" / "model.py").write_text("def f(x):\n    return 2.5 * x\n")
    assert store.check("toy") == 3 and calls[0] == 2
    toy.file.write_text(toy.file.read_text("utf-8") + " ")   # the study's file itself
    assert store.check("toy") == 3 and calls[0] == 3


def test_a_file_without_a_header_is_stale(toy):
    toy.file.write_text(json.dumps({"xs": [1.0], "ys": [1.0]}))
    with pytest.raises(store.StaleStudy, match="no store header"):
        store.check("toy")


def test_an_executor_gives_the_same_file(toy, tmp_path):
    here = json.loads(store.refresh("toy", path=tmp_path / "a.json").read_text("utf-8"))
    with ThreadPoolExecutor(2) as ex:
        there = json.loads(store.refresh("toy", executor=ex, path=tmp_path / "b.json")
                           .read_text("utf-8"))
    assert here["ys"] == there["ys"] and "ThreadPoolExecutor" in there["store"]["note"]


def test_unknown_study_and_bad_registration():
    with pytest.raises(ValueError, match="study must be one of"):
        store.study("no-such-study")
    with pytest.raises(TypeError, match="study must be a Study"):
        store.register("toy")


@pytest.mark.parametrize(("change", "exc", "pattern"), [
    ({"name": ""}, ValueError, "name must be a non-empty str"),
    ({"file": "toy.json"}, TypeError, "file must be a pathlib.Path"),
    ({"check": None}, TypeError, "check must be callable"),
    ({"rtol": -1e-6}, ValueError, r"rtol must be a number in \[0, 1\)"),
])
def test_a_study_is_validated_at_the_door(toy, change, exc, pattern):
    import dataclasses

    with pytest.raises(exc, match=pattern):
        dataclasses.replace(toy, **change)


def test_the_store_imports_no_other_part_of_gyrolib():
    """It sits below every study: the modules that compute them register with it."""
    import ast
    from pathlib import Path

    src = Path(store.__file__).read_text("utf-8")
    named = set()
    for node in ast.walk(ast.parse(src)):
        if isinstance(node, ast.Import):
            named |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom):
            named.add(node.module or "")
    assert {n for n in named if n.startswith("gyrolib")} == {"gyrolib"}


def test_rekey_stamps_the_key_only_while_every_point_agrees(toy, monkeypatch):
    """A key moved by a change the numbers do not read is re-stamped, with the parts and the
    reason in the note; a key moved with the numbers is refused, and nothing is written."""
    store.refresh("toy")
    before = json.loads(toy.file.read_text("utf-8"))
    with pytest.raises(ValueError, match="has the code's key already"):
        store.rekey("toy", "nothing moved")
    # a key that moves while the points agree: the study reads a new, unused constant
    monkeypatch.setitem(store._REGISTRY, "toy", store.Study(
        "toy", toy.file, lambda: store.model_key(constants={"rate": _STATE["rate"],
                                                            "unused": 1}),
        _check, _compute, rtol=1e-9, atol=0.0))
    with pytest.raises(store.StaleStudy, match="its key differs"):
        store.check("toy")
    with pytest.raises(ValueError, match="reason must be"):
        store.rekey("toy", "  ")
    h = store.rekey("toy", "a constant the toy does not compute with")
    after = json.loads(toy.file.read_text("utf-8"))
    assert after["ys"] == before["ys"] and h.date == store.header_of("toy", before).date
    assert "moved none of its 3 fingerprint points" in h.note
    assert h.note.endswith("a constant the toy does not compute with")
    assert store.check("toy", memo=False) == 3
    # the power: a constant the numbers do read moves the points, and rekey refuses
    monkeypatch.setitem(_STATE, "rate", 1.1)
    text = toy.file.read_text("utf-8")
    with pytest.raises(store.StaleStudy, match=r"y at x = 1\.0"):
        store.rekey("toy", "should be refused")
    assert toy.file.read_text("utf-8") == text
