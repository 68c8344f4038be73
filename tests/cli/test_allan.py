"""``python -m gyrolib allan`` (issue 34, item 5): a plain (t, rate) series of white rate
noise with a stated angle random walk gives it back within 3σ, in deg/√h and in the JSON
(SI); the terms the data do not show are bounds; bad input exits 2 with one line on stderr
and, with --json, an error object on stdout."""

from __future__ import annotations

import json
import math

import numpy as np

from gyrolib.cli import main

N_ARW = 0.15 * math.radians(1.0) / 60.0       # 0.15 °/√h in rad/√s


def _series(path, n=2**14, dt=0.01, unit_scale=1.0):
    rng = np.random.default_rng(3)
    t = np.arange(n) * dt
    y = rng.standard_normal(n) * N_ARW / math.sqrt(dt) * unit_scale
    np.savetxt(path, np.column_stack([t, y]), delimiter=",", header="T,Rate", comments="",
               fmt="%.10g")
    return str(path)


def test_angle_random_walk_recovered(tmp_path, capsys):
    path = _series(tmp_path / "r.csv")
    assert main(["allan", path, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    arw, bi, rrw = out["noise_terms"]
    assert arw["identified"] and abs(arw["value"] - N_ARW) < 3 * arw["sigma"]
    assert not bi["identified"] and not rrw["identified"]
    # the same series in deg/s, read with --rate-unit: the same term
    deg = _series(tmp_path / "d.csv", unit_scale=180.0 / math.pi)
    assert main(["allan", deg, "--rate-unit", "deg/s"]) == 0
    text = capsys.readouterr().out
    value = float(text.split("angle random walk = ")[1].split()[0])
    assert abs(value - 0.15) < 3 * 180 / math.pi * 60 * arw["sigma"] and "deg/sqrt(h)" in text


def test_bad_input_exits_2(tmp_path, capsys):
    bad = tmp_path / "bad.csv"
    bad.write_text("time,rate\n0,1\n0.01,2\n")
    assert main(["allan", str(bad), "--json"]) == 2
    cap = capsys.readouterr()
    assert json.loads(cap.out)["status"] == "error" and "t and rate" in cap.err
    assert cap.err.count("\n") == 1
    uneven = tmp_path / "uneven.csv"
    uneven.write_text("t,rate\n" + "".join(f"{k * 0.01 + (0.005 if k == 7 else 0)},1\n"
                                          for k in range(20)))
    assert main(["allan", str(uneven)]) == 2
    assert "even steps" in capsys.readouterr().err
