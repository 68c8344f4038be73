"""``python -m gyrolib race [--params P.toml] [--json]``: the race for a
user's own instrument, its verdict by the ledger's one rule for claims, and bad files
rejected with status 2, one line on stderr and nothing on stdout."""

from __future__ import annotations

import json
from dataclasses import replace

import pytest

from gyrolib import gc
from gyrolib.cli import main


def _run(capsys, argv):
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def test_race_json_at_the_defaults_is_the_ledgers_verdict(capsys):
    code, out, err = _run(capsys, ["race", "--json"])
    assert code == 0 and err == ""
    r = json.loads(out)
    race = gc.race()
    assert r["t_c_gc"] == pytest.approx(race.t_c_gc, rel=1e-12)
    assert r["t_c_rate_sensor_optimal"] == pytest.approx(race.t_c_rate_sensor_optimal,
                                                         rel=1e-12)
    # the verdict by hand from the race's own numbers: more than 50 % against both
    # estimators at the reference point, not at the ranges' worst corner
    assert min(r["faster_percent"], r["faster_percent_optimal"]) > 50.0
    # it holds at the reference, but at none of the box's points: the words say so, with the
    # share, and the code is the ledger's
    assert r["status_code"] == "holds_near_reference"
    share = r["share_holding"]
    assert share["hi"] < 0.5
    assert r["status"] == (f"holds only near the reference ({100 * share['value']:.0f} % of the "
                           f"box, {100 * share['lo']:.0f}–{100 * share['hi']:.0f} %)")
    assert r["kappa_ceiling"] == pytest.approx(race.procedure.sigma_c
                                               / race.params.Omega_h, rel=1e-12)
    assert 0 < r["kappa_max"] < r["kappa_ceiling"]


def test_race_with_a_parameter_file(capsys, tmp_path):
    path = tmp_path / "p.toml"
    path.write_text("C_as = 2e-12\n[procedure]\nT_rot = 2.0\nT_settle = 3.0\n"
                    "loop_bandwidth = 1.0\nrate_noise = 6e-17\n", encoding="utf-8")
    code, out, err = _run(capsys, ["race", "--params", str(path), "--json",
                                   "--no-thresholds"])
    assert code == 0 and err == ""
    r = json.loads(out)
    assert r["thresholds"] is None        # not mapped: the verdict at these inputs only
    assert r["params"]["C_as"] == 2e-12 and r["procedure"]["T_rot"] == 2.0
    # GC is slowed by the tenfold angle-sensor noise (its time rises from 24.1 s), and the
    # verdict follows the numbers: fails when the saving misses 50 % against either estimator
    assert r["t_c_gc"] > 30.0
    at_ref = min(r["faster_percent"], r["faster_percent_optimal"]) > 50.0
    assert (r["status"] == "fails") == (not at_ref)
    assert r["conditions"] != ""


def test_race_text_output(capsys):
    code, out, err = _run(capsys, ["race"])
    assert code == 0 and err == ""
    assert "more than 50 % faster:" in out and "holds only near the reference (" in out
    assert "inputs that flip it" in out and "gc.sigma1_sq" in out


def test_race_thresholds_for_a_users_own_instrument(capsys, tmp_path):
    """The map around a user's parameters (here twice the paper's vibration σ1², which
    alone makes the claim fail): the σ1² threshold moves with the reference (ranges are
    factors of the given values) and is the same point in SI as at the paper's values."""
    s1 = gc.GyrocompassParams().sigma1_sq
    path = tmp_path / "p.toml"
    path.write_text(f"sigma1_sq = {2 * s1!r}\n", encoding="utf-8")
    code, out, err = _run(capsys, ["race", "--params", str(path), "--json",
                                   "--inputs", "gc.sigma1_sq"])
    assert code == 0 and err == ""
    r = json.loads(out)
    assert r["status"] == "fails"
    (t,) = r["thresholds"]
    assert t["input"] == "gc.sigma1_sq" and t["holds_when"] == "below"
    from gyrolib.book.ledger import claims

    (ref,) = [x for x in claims.stored_maps()["gc.faster_percent"].thresholds
              if x.input == "gc.sigma1_sq"]
    assert t["value"] == pytest.approx(ref.value, rel=2e-2)   # rtol 1e-2 of the CLI's map
    assert t["factor"] == pytest.approx(ref.factor / 2, rel=2e-2)


def test_race_never_reaching_sigma_c_names_the_ceiling(capsys, tmp_path):
    path = tmp_path / "k.toml"
    path.write_text("sigma_hf_scale = 1e-3\n", encoding="utf-8")
    code, out, _ = _run(capsys, ["race", "--params", str(path), "--no-thresholds"])
    assert code == 0 and "GC never reaches σ_c" in out and "ceiling" in out
    assert "undefined" not in out


@pytest.mark.parametrize(("text", "words"), [
    ("C_as = -1\n", ("C_as", "> 0")),
    ("[procedure]\nwarp = 1\n", ("procedure.warp", "unknown field")),
    ("procedure = 3\n", ("procedure", "table")),
    ("C_as = \n", ("not valid TOML",)),
])
def test_bad_parameter_file_exits_2_with_one_line(capsys, tmp_path, text, words):
    path = tmp_path / "bad.toml"
    path.write_text(text, encoding="utf-8")
    code, out, err = _run(capsys, ["race", "--params", str(path)])
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and "Traceback" not in err
    for w in words:
        assert w in err


def test_missing_parameter_file(capsys, tmp_path):
    code, out, err = _run(capsys, ["race", "--params", str(tmp_path / "none.toml")])
    assert code == 2 and out == "" and "no such file" in err


def test_a_slower_gc_and_the_users_own_parameters_are_worded_as_such(capsys, tmp_path):
    """Where GC takes longer than the rival the line says "slower", never "faster by -N %",
    and the user's own parameters are "the given parameters", not the book's reference point.
    Power: at the paper's parameters the same lines say "faster" and "the reference point"."""
    path = tmp_path / "k.toml"
    path.write_text("sigma_hf_scale = 2e-4\n", encoding="utf-8")
    code, out, _ = _run(capsys, ["race", "--params", str(path), "--no-thresholds"])
    assert code == 0
    r = gc.race(gc.GyrocompassParams(sigma_hf_scale=2e-4))
    assert r.faster_percent < 0 and r.faster_percent_optimal < 0
    assert f"GC slower by {-r.faster_percent:.0f} %" in out
    assert f"GC slower by {-r.faster_percent_optimal:.0f} %" in out
    assert "faster by -" not in out and "faster by" not in out
    assert "At the given parameters (" in out and "reference point (" not in out
    code, out, _ = _run(capsys, ["race", "--no-thresholds"])
    assert code == 0 and "GC faster by" in out and "At the reference point (" in out


def test_a_users_map_in_text_and_json_names_the_given_parameters(capsys, tmp_path):
    """With its map (one row, to keep it short): the JSON says the map was computed around
    the given parameters, which are not the book's reference point, and no sentence calls
    them so; the text's saving is "slower by", in the same numbers as the JSON's."""
    path = tmp_path / "k.toml"
    path.write_text("sigma_hf_scale = 2e-4\n", encoding="utf-8")
    code, out, _ = _run(capsys, ["race", "--params", str(path), "--json",
                                 "--inputs", "gc.sigma_hf_scale"])
    assert code == 0
    r = json.loads(out)
    assert r["at_reference_point"] is False and r["map_source"] == "computed"
    assert r["checked_points"] is None
    assert r["faster_percent"] < 0 and r["status"] == "fails"
    assert "reference point" not in r["conditions"] and "the given value" in r["conditions"]
    (t,) = r["thresholds"]
    assert t["input"] == "gc.sigma_hf_scale" and t["holds_when"] == "below"
    code, text, _ = _run(capsys, ["race", "--params", str(path),
                                  "--inputs", "gc.sigma_hf_scale"])
    assert code == 0 and "reference point" not in text
    assert f"GC slower by {-r['faster_percent']:.0f} %" in text and "faster by -" not in text
    assert "(the others at the given values)" in text


def test_race_at_the_defaults_prints_the_stored_map_checked(capsys):
    """At the book's reference point the thresholds are the stored map's, read from the
    store and checked by the claim's fingerprint points (none recomputed by a search)."""
    from gyrolib.book.ledger import claims
    from gyrolib.claim_map import fingerprint_points

    code, out, err = _run(capsys, ["race", "--json"])
    assert code == 0 and err == ""
    r = json.loads(out)
    stored = claims.stored_maps()["gc.faster_percent"]
    assert r["at_reference_point"] is True and r["map_source"] == "stored"
    assert r["checked_points"] == len(fingerprint_points(stored))
    assert [(t["input"], t["value"]) for t in r["thresholds"]] == [
        (t.input, t.value) for t in stored.thresholds]


def test_a_stale_stored_map_exits_3_naming_the_study(capsys, tmp_path, monkeypatch):
    """The stored map with its σ1² threshold moved by 10 % (a copy of the file): the check
    brackets it, fails, and the command prints one line naming the study and the refresh
    command, and nothing on stdout."""
    from gyrolib import store
    from gyrolib.book import studies  # noqa: F401  (registers the studies)

    s = store.study("claim-maps")
    data = json.loads(s.file.read_text(encoding="utf-8"))
    for t in data["maps"]["gc.faster_percent"]["thresholds"]:
        if t["input"] == "gc.sigma1_sq":
            t["value"] *= 1.1
    copy = tmp_path / "claim_maps.json"
    copy.write_text(json.dumps(data), encoding="utf-8")
    monkeypatch.setattr(store, "_REGISTRY", {**store._REGISTRY,
                                             "claim-maps": replace(s, file=copy)})
    code, out, err = _run(capsys, ["race"])
    assert code == 3 and out == ""
    assert err.count("\n") == 1 and "claim-maps" in err and "tasks.py refresh" in err
    assert "gc.sigma1_sq" in err
