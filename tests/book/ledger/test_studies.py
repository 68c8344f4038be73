"""The book's stored studies held to the code (gyrolib.book.ledger.studies over gyrolib.store).

Each check is shown to pass on the code as it is and to fail, by the study's name and with the
command that refreshes it, when the code moves: a default of the table changed, a model
constant outside the table changed (Omega_v x 1.1), a race margin that gives the wrong sign
next to a stored threshold.  The package's files are only read: what is written goes to
``tmp_path``.
"""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import pytest

from gyrolib import store
from gyrolib.book import studies as book_studies
from gyrolib.book.ledger import claims, studies
from gyrolib.cli import main
from gyrolib.gc.model.params import GyrocompassParams
from gyrolib.rsf.sensors import RollGyroSpec
from tests.support.stored_studies import patch_default, stale_message


def _maps_data() -> dict:
    return json.loads(claims.MAPS_FILE.read_text(encoding="utf-8"))



# every stored study agrees with the code ------------------------------------------------------
@pytest.mark.parametrize("name", book_studies.NAMES)
def test_each_stored_study_is_fresh(name):
    """Key and fingerprint points (every threshold bracketed, every reading, a sample of the
    sweeps and of the Sobol' points) of the package's files, recomputed."""
    assert store.check(name) >= (20 if name in studies.NAMES else 10)


def test_the_header_records_key_tolerance_version_class_date():
    for name in book_studies.NAMES:
        h = store.header_of(name, json.loads(store.study(name).file.read_text("utf-8")))
        assert h.key == store.study(name).key()
        assert 0 < h.rtol <= 1e-6 and h.atol >= 0
        assert h.version and h.cpu_class and h.date[:4] == "2026"


def test_brackets_each_threshold_with_opposite_signs():
    """The fingerprint's brackets: two points per threshold, whose expected signs differ."""
    from gyrolib.claim_map import ClaimMap, fingerprint_points

    m = ClaimMap.from_dict(_maps_data()["maps"]["gc.faster_percent"])
    pts = fingerprint_points(m)
    brackets = [p for p in pts if p.holds is not None and "threshold" in p.label]
    assert len(brackets) == 2 * len(m.thresholds) == 20
    for a, b in zip(brackets[::2], brackets[1::2], strict=True):
        assert a.holds != b.holds
        (x,) = a.changes.values()
        (y,) = b.changes.values()
        assert 1.0 < y / x <= 1.02 / 0.98 + 1e-12


# a changed table default ----------------------------------------------------------------------
@pytest.mark.parametrize(("name", "owner", "field"), [
    ("claim-maps", GyrocompassParams, "C_as"),
    ("sensitivity-gc", GyrocompassParams, "C_as"),
    ("sensitivity-rsf", RollGyroSpec, "sf_error"),
])
def test_a_changed_table_default_makes_the_study_stale(monkeypatch, name, owner, field):
    store.check_key(name, _stored_key(name), studies.key(name))   # as it is: the same key
    patch_default(monkeypatch, owner, field,
                   1.1 * owner.__dataclass_fields__[field].default)
    with pytest.raises(store.StaleStudy) as exc:
        store.check(name)
    msg = stale_message(exc, name)
    assert "table" in msg and "objects" in msg


def test_the_key_holds_only_what_the_study_reads(monkeypatch):
    """Paper GC's C_as is no input of paper RSF's study: its key does not move."""
    patch_default(monkeypatch, GyrocompassParams, "C_as", 2.2e-13)
    store.check_key("sensitivity-rsf", _stored_key("sensitivity-rsf"),
                    studies.key("sensitivity-rsf"))
    with pytest.raises(store.StaleStudy):
        store.check_key("sensitivity-gc", _stored_key("sensitivity-gc"),
                        studies.key("sensitivity-gc"))


def _stored_key(name: str) -> dict:
    return store.header_of(name, json.loads(store.study(name).file.read_text("utf-8"))).key


# a model constant outside the table: Omega_v x 1.1 --------------------------------------------
def test_omega_v_is_not_a_row_of_the_table():
    from gyrolib import inputs

    assert not any("Omega_v" in r.fields for r in inputs.INPUTS)


def test_omega_v_times_1_1_breaks_the_key(monkeypatch):
    patch_default(monkeypatch, GyrocompassParams, "Omega_v", 1.1 * 5.9e-5)
    with pytest.raises(store.StaleStudy) as exc:
        store.check("claim-maps")
    msg = stale_message(exc, "claim-maps")
    assert "differs from the code's in gyrolib.gc.model.params, objects (" in msg


def test_omega_v_times_1_1_breaks_the_fingerprint_itself(monkeypatch):
    """Without the key, the recomputed points alone catch the changed constant; and the same
    points agree with the code as it is."""
    data = _maps_data()
    ids = ("gc.time_to_sigma_c",)
    assert studies._check_maps(data, ids) == 15
    patch_default(monkeypatch, GyrocompassParams, "Omega_v", 1.1 * 5.9e-5)
    with pytest.raises(store.StaleStudy) as exc:
        studies._check_maps(data, ids)
    assert "gc.time_to_sigma_c" in stale_message(exc, "claim-maps")


def test_ledger_json_on_a_stale_study_exits_3_with_one_line(monkeypatch, capsys):
    patch_default(monkeypatch, GyrocompassParams, "Omega_v", 1.1 * 5.9e-5)
    assert main(["ledger", "--json"]) == 3
    out, err = capsys.readouterr()
    assert out == ""
    assert err.count("\n") == 1 and err.startswith("ledger: the stored study claim-maps is ")
    assert "python3 tasks.py refresh claim-maps" in err and "Traceback" not in err
    assert main(["claims", "--check"]) == 3
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "claim-maps" in err


# a race that gives the wrong sign next to a stored threshold ----------------------------------
#: The race's stored threshold in sigma_k (the map says the claim holds above it).
def _sigma_k_threshold() -> float:
    m = claims.stored_maps()["gc.faster_percent"]
    (t,) = [t for t in m.thresholds if t.input == "race.sigma_scale"]
    assert t.holds_when == "above"
    return t.value


def _race_with(monkeypatch, wrong: bool) -> None:
    """The race's margin as the code gives it, except below the stored sigma_k threshold
    (others at the reference), where it is the stored map's verdict (fails: -5.64, the
    margin the map's code gave at 1.3e-4) or, with ``wrong``, the margin at the reference
    (+7.32: a rival search that misses the route crossing sigma_c right after the turn)."""
    real = claims.race_margin
    limit = _sigma_k_threshold()

    def fake(p, proc):
        below = proc.sigma_scale < limit and 1.2e-4 <= proc.sigma_scale
        if below and p == GyrocompassParams():
            return 7.32 if wrong else -5.64
        return real(p, proc)

    monkeypatch.setattr(claims, "race_margin", fake)


def test_a_race_with_the_stored_verdict_passes_the_check(monkeypatch):
    _race_with(monkeypatch, wrong=False)
    assert studies._check_maps(_maps_data(), ("gc.faster_percent",)) == 30


def test_a_wrong_race_margin_near_a_stored_threshold_fails_by_name(monkeypatch):
    _race_with(monkeypatch, wrong=True)
    assert claims.race_claim_margin(
        {"GyrocompassParams": GyrocompassParams(),
         "RateSensorProcedure": dataclasses.replace(_procedure(), sigma_scale=1.3e-4)}) == 7.32
    with pytest.raises(store.StaleStudy) as exc:
        studies._check_maps(_maps_data(), ("gc.faster_percent",))
    msg = stale_message(exc, "claim-maps")
    assert "gc.faster_percent" in msg and "race.sigma_scale" in msg and "should be <= 0" in msg


def _procedure():
    from gyrolib import inputs

    return inputs.reference_objects()["RateSensorProcedure"]


# refresh: here and on a Dask cluster ----------------------------------------------------------
_CHEAP = ("rsf.claim.drz_cubic", "rsf.example.compensated")


def _maps_of(path) -> dict:
    return json.loads(path.read_text("utf-8"))["maps"]


def _agree(a: dict, b: dict, rtol: float, atol: float) -> None:
    assert a["status"] == b["status"] and a["readings"] == b["readings"]
    assert math.isclose(a["margin"], b["margin"], rel_tol=rtol, abs_tol=atol)
    assert len(a["thresholds"]) == len(b["thresholds"])
    for s, t in zip(a["thresholds"], b["thresholds"], strict=True):
        assert s["input"] == t["input"] and s["holds_when"] == t["holds_when"]
        assert math.isclose(s["value"], t["value"], rel_tol=rtol)


def test_refresh_on_a_dask_cluster_gives_the_local_and_the_stored_numbers(tmp_path):
    distributed = pytest.importorskip("distributed")
    here = store.refresh("claim-maps", path=tmp_path / "here.json", ids=_CHEAP, grid=False)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=":0") as cluster, \
            distributed.Client(cluster) as client:
        there = store.refresh("claim-maps", executor=client.get_executor(),
                              path=tmp_path / "there.json", ids=_CHEAP, grid=False)
    h = store.header_of("claim-maps", json.loads(there.read_text("utf-8")))
    assert h.key == studies.key("claim-maps") and h.cpu_class == store.cpu_class()
    assert "distributed" in h.note
    a, b, stored = _maps_of(here), _maps_of(there), _data_maps()
    assert set(a) == set(b) == set(_CHEAP)
    for cid in _CHEAP:
        _agree(a[cid], b[cid], h.rtol, h.atol)
        _agree(a[cid], stored[cid], 1e-3, h.atol)   # the bisection's rtol: 1e-3


def _data_maps() -> dict:
    return _maps_data()["maps"]


def test_refresh_list_and_bad_names(capsys):
    assert main(["refresh", "--list", "sensitivity-rsf"]) == 0
    out = capsys.readouterr().out
    assert "sensitivity-rsf" in out and "fresh" in out and "2026-11-27" in out
    assert main(["refresh", "no-such-study"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "no-such-study" in err and "claim-maps" in err


def test_claims_out_writes_the_store_header(tmp_path, capsys):
    out = tmp_path / "maps.json"
    assert main(["claims", "--out", str(out), "--only", "rsf.claim.drz_cubic"]) == 0
    assert capsys.readouterr().out.startswith("rsf.claim.drz_cubic: fails")
    data = json.loads(out.read_text("utf-8"))
    assert store.header_of("claim-maps", data).key == studies.key("claim-maps")
    _agree(data["maps"]["rsf.claim.drz_cubic"], _data_maps()["rsf.claim.drz_cubic"], 1e-6,
           1e-9)


@pytest.mark.slow
def test_refresh_command_on_a_dask_scheduler_gives_the_stored_study(tmp_path, monkeypatch,
                                                                     capsys):
    """``python -m gyrolib refresh sensitivity-rsf --scheduler ADDRESS`` (what ``tasks.py
    refresh`` runs) against a cluster this test starts, writing into a copy: the same values,
    indices and slopes as the stored (in-process) study, within its declared tolerance."""
    distributed = pytest.importorskip("distributed")
    import numpy as np

    s = store.study("sensitivity-rsf")
    copy = tmp_path / "sensitivity_rsf.json"
    copy.write_bytes(s.file.read_bytes())
    monkeypatch.setitem(store._REGISTRY, s.name, dataclasses.replace(s, file=copy))
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=":0") as cluster:
        assert main(["refresh", "sensitivity-rsf", "--scheduler",
                     cluster.scheduler_address]) == 0
    assert "refresh sensitivity-rsf" in capsys.readouterr().err     # the progress bar
    old = json.loads(s.file.read_text("utf-8"))
    new = json.loads(copy.read_text("utf-8"))
    h = store.header_of(s.name, new)
    assert h.key == studies.key(s.name) and h.date > old["store"]["date"]
    assert new["run"]["executor"].startswith("dask scheduler") and new["run"]["workers"] == 1
    np.testing.assert_allclose(new["values"], old["values"], rtol=h.rtol, atol=h.atol)
    for part in ("first_order", "total"):
        for out, by_input in old[part].items():
            for inp, idx in by_input.items():
                np.testing.assert_allclose(new[part][out][inp]["value"], idx["value"],
                                           rtol=h.rtol, atol=1e-12)
    assert store.check(s.name, copy) == 45


# the check memo, in a copy of the package -----------------------------------------------------
def _listing_in(copy, memo) -> tuple[int, str]:
    """``python -m gyrolib refresh --list sensitivity-rsf`` run on the package at ``copy``
    with the check memo at ``memo``: (exit status, stdout)."""
    import os
    import subprocess
    import sys

    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env.update(PYTHONPATH=str(copy), GYROLIB_CHECK_MEMO=str(memo))
    r = subprocess.run([sys.executable, "-m", "gyrolib", "refresh", "--list",
                        "sensitivity-rsf"], cwd=copy, env=env, capture_output=True,
                       text=True, check=False, timeout=900)
    assert "Traceback" not in r.stderr, r.stderr
    return r.returncode, r.stdout


def _edit(path, old: str, new: str) -> None:
    text = path.read_text("utf-8")
    assert text.count(old) == 1, old
    path.write_text(text.replace(old, new), "utf-8")


@pytest.mark.full
def test_the_check_memo_hides_no_change_of_the_code_in_a_copy(tmp_path, monkeypatch):
    """A check remembered for the package as it is is read by a copy of the same package
    (the memo is used); a copy whose function body changed (delta_k × 1.01: the key, over
    constants and defaults, is the same) recomputes its points and is stale by its points;
    a copy whose constant changed (the "90 %" level, which the key holds) is stale by its
    key and by its points, both shown."""
    import shutil

    import gyrolib

    memo = tmp_path / "memo"
    monkeypatch.setenv(store.MEMO_ENV, str(memo))
    assert store.state("sensitivity-rsf")["state"] == "fresh"   # remembered here
    package = Path(gyrolib.__file__).resolve().parent
    copies = {}
    for name in ("same", "body", "constant"):
        copies[name] = tmp_path / name
        shutil.copytree(package, copies[name] / "gyrolib",
                        ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    _edit(copies["body"] / "gyrolib" / "rsf" / "equations.py",
          "return difference_error(e0, dt, enc, e1, wu) / (w * dt)",
          "return 1.01 * difference_error(e0, dt, enc, e1, wu) / (w * dt)")
    _edit(copies["constant"] / "gyrolib" / "levels.py",
          "COMPENSATED_PERCENT: Final[float] = 90.0", "COMPENSATED_PERCENT: Final[float] = 91.0")
    status, out = _listing_in(copies["same"], memo)
    assert status == 0 and "fresh  same     45 agree (memo)" in out
    status, out = _listing_in(copies["body"], memo)
    assert status == 3 and "stale  same     disagree" in out and "(memo)" not in out
    assert "points: delta_k at the reference was" in out
    status, out = _listing_in(copies["constant"], memo)
    assert status == 3 and "stale  differs  disagree" in out
    assert "key: its key differs from the code's in gyrolib.levels" in out
    assert "points: rsf.example.compensated at the reference was" in out
