"""``python -m gyrolib allan``: a plain (t, rate) series of white rate noise with a stated
angle random walk gives it back within 3σ, in deg/√h and in the JSON (SI); the terms the
data do not show are bounds; a term read outside the measured τ range is a bound with its
range; a missing value drops its row (counted), not the file; a log without a time column
(``--rate HZ``) and a phase log (``--phase``) give the rate log's numbers; time in
milliseconds is refused naming ``--time-unit``, and read right with it; a log that is not
at rest is warned about; bad input exits 2 with one line on stderr and, with --json, an
error object on stdout."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest

from gyrolib.cli import main

N_ARW = 0.15 * math.radians(1.0) / 60.0       # 0.15 °/√h in rad/√s


def _rate(n=2**14, dt=0.01, seed=3):
    rng = np.random.default_rng(seed)
    return np.arange(n) * dt, rng.standard_normal(n) * N_ARW / math.sqrt(dt)


def _series(path, n=2**14, dt=0.01, unit_scale=1.0, header="T,Rate", t_scale=1.0):
    t, y = _rate(n, dt)
    np.savetxt(path, np.column_stack([t * t_scale, y * unit_scale]), delimiter=",",
               header=header, comments="", fmt="%.10g")
    return str(path)


def _json(argv, capsys):
    code = main([str(a) for a in argv] + ["--json"])
    cap = capsys.readouterr()
    return code, json.loads(cap.out), cap.err


def test_angle_random_walk_recovered(tmp_path, capsys):
    path = _series(tmp_path / "r.csv")
    code, out, _ = _json(["allan", path], capsys)
    assert code == 0
    arw, bi, rrw = out["noise_terms"]
    assert arw["identified"] and abs(arw["value"] - N_ARW) < 3 * arw["sigma"]
    assert not bi["identified"] and not rrw["identified"]
    # the same series in deg/s, read with --rate-unit: the same term
    deg = _series(tmp_path / "d.csv", unit_scale=180.0 / math.pi)
    assert main(["allan", deg, "--rate-unit", "deg/s"]) == 0
    text = capsys.readouterr().out
    value = float(text.split("angle random walk = ")[1].split()[0])
    assert abs(value - 0.15) < 3 * 180 / math.pi * 60 * arw["sigma"] and "deg/sqrt(h)" in text


def test_a_coefficient_of_zero_has_no_tau(tmp_path, capsys):
    """White rate noise: the rate random walk's fitted coefficient is 0 (non-negative least
    squares), and its JSON term has no tau_s; the angle random walk's has one."""
    code, out, _ = _json(["allan", _series(tmp_path / "r.csv")], capsys)
    arw, _, rrw = out["noise_terms"]
    assert code == 0 and "tau_s" in arw and "tau_s" not in rrw and not rrw["identified"]


def test_a_term_read_outside_the_tau_range_is_a_bound_with_its_range(tmp_path, capsys):
    """64 rows at 100 Hz end at τ = 0.16 s: the −½ line (read at 1 s) and the +½ line (3 s)
    are bounds, printed with the τ range; the same log 4096 rows long identifies N."""
    short = _series(tmp_path / "s.csv", n=64)
    code, out, _ = _json(["allan", short], capsys)
    arw, _, rrw = out["noise_terms"]
    assert code == 0 and out["tau"][-1] < 1.0
    assert arw["extrapolated"] and rrw["extrapolated"]
    assert not arw["identified"] and not rrw["identified"]
    assert main(["allan", short]) == 0
    text = capsys.readouterr().out
    line = next(ln for ln in text.splitlines() if "angle random walk" in ln)
    assert "<=" in line and f"tau = {out['tau'][0]:.3g} to {out['tau'][-1]:.3g} s" in line
    assert "outside the measured range" in line
    _, long, _ = _json(["allan", _series(tmp_path / "l.csv", n=4096)], capsys)
    assert long["noise_terms"][0]["identified"]


def test_one_missing_value_drops_its_row_not_the_file(tmp_path, capsys):
    """12 626 rows (the x-IMU log's length) with one NaN: read, the row dropped and
    counted, and the numbers equal those of the file without that row (to 1e-12)."""
    t, y = _rate(n=12626)
    y_nan = y.copy()
    y_nan[5000] = np.nan
    nan_path = tmp_path / "nan.csv"
    np.savetxt(nan_path, np.column_stack([t, y_nan]), delimiter=",", header="t,rate",
               comments="", fmt="%.10g")
    code, out, err = _json(["allan", nan_path], capsys)
    assert code == 0 and err == ""
    assert out["rows"] == 12626 and out["rows_dropped_missing"] == 1
    assert any("1 of 12626 rows with a missing rate value dropped" in n for n in out["notes"])
    keep = np.arange(t.size) != 5000
    ref_path = tmp_path / "ref.csv"
    np.savetxt(ref_path, np.column_stack([np.arange(keep.sum()) * 0.01, y[keep]]),
               delimiter=",", header="t,rate", comments="", fmt="%.10g")
    _, ref, _ = _json(["allan", ref_path], capsys)
    np.testing.assert_allclose(out["adev"], ref["adev"], rtol=1e-12, atol=0)


def test_a_log_without_time_at_a_stated_rate_and_a_phase_log(tmp_path, capsys):
    """--rate 100 on the rate column alone, and --phase on its integral, give the (t, rate)
    log's deviation (to 1e-12 and 1e-9: the phase is a cumulative sum, rounded)."""
    _, y = _rate(n=4096)
    path = _series(tmp_path / "r.csv", n=4096)
    _, ref, _ = _json(["allan", path], capsys)
    bare = tmp_path / "bare.csv"
    np.savetxt(bare, y, header="rate", comments="", fmt="%.10g")
    code, out, _ = _json(["allan", bare, "--rate", "100"], capsys)
    assert code == 0 and out["rate_given"] and out["dt"] == pytest.approx(0.01, rel=1e-15)
    np.testing.assert_allclose(out["adev"], ref["adev"], rtol=1e-12, atol=0)
    y_file = np.loadtxt(path, delimiter=",", skiprows=1)[:, 1]
    phase = np.concatenate([[0.0], np.cumsum(y_file) * 0.01])
    ph = tmp_path / "phase.csv"
    np.savetxt(ph, phase, header="phase", comments="", fmt="%.17g")
    code, out, _ = _json(["allan", ph, "--rate", "100", "--phase"], capsys)
    assert code == 0 and out["kind"] == "phase"
    np.testing.assert_allclose(out["adev"], ref["adev"], rtol=1e-9, atol=0)
    # power: the phase read as a rate is another curve entirely
    _, wrong, _ = _json(["allan", ph, "--rate", "100", "--columns", "rate=phase"], capsys)
    k = min(len(wrong["adev"]), len(ref["adev"]))
    assert not np.allclose(wrong["adev"][:k], ref["adev"][:k], rtol=1e-3)


def test_time_in_milliseconds_is_refused_naming_the_option(tmp_path, capsys):
    """The same log with t in ms: exit 2 naming --time-unit ms; with --time-unit ms its
    angle random walk is within 5 % of the log in s (here equal: the same samples)."""
    s_path = _series(tmp_path / "s.csv")
    ms_path = _series(tmp_path / "ms.csv", t_scale=1000.0)
    code, out, err = _json(["allan", ms_path], capsys)
    assert code == 2 and out["status"] == "error" and "--time-unit ms" in err
    assert err.count("\n") == 1
    _, ref, _ = _json(["allan", s_path], capsys)
    code, out, _ = _json(["allan", ms_path, "--time-unit", "ms"], capsys)
    assert code == 0
    assert out["noise_terms"][0]["value"] == pytest.approx(ref["noise_terms"][0]["value"],
                                                           rel=0.05)
    # power: read as seconds (a slow log stated so), the term is √1000 times off
    code, wrong, _ = _json(["allan", ms_path, "--time-unit", "s"], capsys)
    assert code == 0
    assert wrong["noise_terms"][0]["value"] > 5 * ref["noise_terms"][0]["value"]


def test_a_log_not_at_rest_is_warned_about(tmp_path, capsys):
    """A turn of 5 deg/s for 10 s in the middle of the log: the warning, in the text and the
    JSON; the log at rest has none.  The help says what triggers it."""
    t, y = _rate(n=2**14)
    turn = y + np.where((t > 60) & (t < 70), math.radians(5.0), 0.0)
    path = tmp_path / "turn.csv"
    np.savetxt(path, np.column_stack([t, turn]), delimiter=",", header="t,rate",
               comments="", fmt="%.10g")
    code, out, _ = _json(["allan", path], capsys)
    assert code == 0 and not out["at_rest"]
    assert "describe the motion" in out["warnings"][0]
    assert math.degrees(out["rest_excursion_rad_s"]) == pytest.approx(5.0, rel=0.05)
    assert main(["allan", str(path)]) == 0
    assert "WARNING: not at rest" in capsys.readouterr().out
    _, still, _ = _json(["allan", _series(tmp_path / "r.csv")], capsys)
    assert still["at_rest"] and still["warnings"] == []
    helptext = subprocess.run([sys.executable, "-m", "gyrolib", "allan", "--help"],
                              capture_output=True, text=True, check=True).stdout
    assert "averaged over 1 s, departs from its median by more than 1 deg/s" in \
        " ".join(helptext.split())


def test_bad_input_exits_2(tmp_path, capsys):
    bad = tmp_path / "bad.csv"
    bad.write_text("time,rate\n0,1\n0.01,2\n")
    code, out, err = _json(["allan", bad], capsys)
    assert code == 2 and out["status"] == "error" and "column 't'" in err
    assert "--columns t=NAME" in err and err.count("\n") == 1
    assert "try: --rate HZ (a log without a time column)" in err
    uneven = tmp_path / "uneven.csv"
    uneven.write_text("t,rate\n" + "".join(f"{k * 0.01 + (0.005 if k == 7 else 0)},1\n"
                                          for k in range(20)))
    assert main(["allan", str(uneven)]) == 2
    assert "even steps" in capsys.readouterr().err
    assert main(["allan", str(uneven), "--rate", "-1"]) == 2
    assert "--rate" in capsys.readouterr().err
