"""``calibrate gc`` at any latitude: records simulated on the equator, in the southern
hemisphere (−35°) and far north (70°), with the latitude in the record's header and by
option, are valid and cover the simulated drift within 3σ (one seed each in the everyday
tier, three in the full tier); the header's latitude is honoured by the check at the door;
``--latitude 54±0.5`` carries its uncertainty into σ as the term ``latitude``, and a latitude
in whole degrees gets a warning whose number of σ the filter's own response to a 0.5° change
confirms; on the equator the output says what the method still estimates.

The truth is the drift the simulation drew (``SimulatedRecord.omega_gc``); the filter's
response to a latitude change is measured by running it again, not computed from the
formula under test."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from gyrolib import gc, records
from gyrolib.cli import main
from gyrolib.gc.model.params import EARTH_RATE
from gyrolib.records import RecordError

T_END = 100.0


def _run(argv, capsys):
    code = main([str(a) for a in argv])
    out = capsys.readouterr()
    return code, out.out, out.err


def _write(path, rec: gc.GCRecord, latitude: float | None):
    comments = [] if latitude is None else [f"latitude_deg: {latitude:g}"]
    return records.write_csv(path, {"t": rec.t, "angle_sensor": rec.angle_sensor,
                                    "inclinometer_y": rec.inclinometer_y,
                                    "inclinometer_z": rec.inclinometer_z},
                             comments=comments, fmt=["%.9g", "%.12g", "%.12g", "%.12g"])


def _site(latitude: float, seed: int, tmp_path):
    p = gc.GyrocompassParams.at_latitude(math.radians(latitude))
    sim = gc.simulate_record(p, T_END, seed=seed)
    return sim, _write(tmp_path / f"site_{latitude:g}_{seed}.csv", sim.record, latitude)


def _finite(obj) -> bool:
    """Every number of a JSON object is finite."""
    if isinstance(obj, dict):
        return all(_finite(v) for v in obj.values())
    if isinstance(obj, list):
        return all(_finite(v) for v in obj)
    return not isinstance(obj, float) or math.isfinite(obj)


SEEDS = [pytest.param(11, id="seed11"), pytest.param(12, id="seed12", marks=pytest.mark.full),
         pytest.param(13, id="seed13", marks=pytest.mark.full)]


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("latitude", [0.0, -35.0, 70.0])
def test_any_latitude_is_valid_and_covers_the_truth(latitude, seed, tmp_path, capsys):
    sim, path = _site(latitude, seed, tmp_path)
    by = {}
    for how, extra in (("header", []), ("option", ["--latitude", f"{latitude:g}"])):
        code, out, _ = _run(["calibrate", "gc", path, "--json", *extra], capsys)
        data = json.loads(out)
        assert code == 0 and data["valid"], (how, data["reason"])
        z = (data["omega_gc"] - sim.omega_gc) / data["omega_gc_std"]
        assert abs(z) <= 3.0, (how, z)
        assert data["earth_rate"]["Omega_v"] == pytest.approx(
            EARTH_RATE * math.sin(math.radians(latitude)), abs=1e-15)
        assert _finite(data)
        by[how] = data
    assert by["header"]["latitude_source"] == "record header"
    assert by["option"]["latitude_source"] == "option"
    assert by["header"]["omega_gc"] == pytest.approx(by["option"]["omega_gc"], rel=1e-12)


def test_the_hemisphere_is_in_the_sign_of_omega_v(tmp_path):
    """The −35° record calibrated as +35° (Ω_v's sign wrong, Ω_h the same) moves ω̂_gc by
    what the tilts' torque predicts, ``2 Ω_v (γ cos β̄ − δ sin β̄)`` with the simulated
    tilts: the sign is carried, and a wrong one is not harmless (power)."""
    sim, _ = _site(-35.0, 21, tmp_path)
    south = gc.GyrocompassParams.at_latitude(math.radians(-35.0))
    north = gc.GyrocompassParams.at_latitude(math.radians(35.0))
    right = gc.calibrate(sim.record, south)
    wrong = gc.calibrate(sim.record, north)
    d, g = (float(sim.truth[0, gc.state_index(n)]) for n in ("delta", "gamma"))
    beta = gc.nominal_motion(south, sim.record.t).beta
    c, s = float(np.mean(np.cos(beta))), float(np.mean(np.sin(beta)))
    predicted = 2.0 * south.Omega_v * (g * c - d * s)
    assert abs(right.omega_gc - sim.omega_gc) <= 3.0 * right.omega_gc_std
    assert abs(predicted) > 5.0 * right.omega_gc_std          # the case has power
    assert wrong.omega_gc - right.omega_gc == pytest.approx(predicted, rel=0.1)


def test_the_header_latitude_is_honoured_at_the_door(tmp_path):
    """A 70° record: read with its own header line it passes the door's check; checked
    against the paper's 53.9° Earth rate (what the door used to do) it is refused as a unit
    mistake, so the header is what makes it pass."""
    _, path = _site(70.0, 31, tmp_path)
    rec = records.read_gc(path)
    assert math.degrees(rec.latitude) == pytest.approx(70.0)
    with pytest.raises(RecordError, match="angle_sensor"):
        records.read_gc(path, params=gc.GyrocompassParams())
    records.read_gc(path, params=gc.GyrocompassParams(), site_from_record=True)
    chunks = records.GCChunks(path, params=gc.GyrocompassParams(), site_from_record=True)
    assert sum(c.n for c in chunks) == rec.n


@pytest.fixture(scope="module")
def at_54_4(tmp_path_factory):
    """A record made at 54.4° N, without a header line (seed 41)."""
    d = tmp_path_factory.mktemp("lat54")
    p = gc.GyrocompassParams.at_latitude(math.radians(54.4))
    sim = gc.simulate_record(p, T_END, seed=41)
    return sim, _write(d / "r.csv", sim.record, None)


def test_a_whole_degree_latitude_is_warned_of_with_its_sigma_count(at_54_4, capsys):
    _, path = at_54_4
    runs = {}
    for lat in ("54", "54.5"):
        _, out, _ = _run(["calibrate", "gc", path, "--json", "--latitude", lat], capsys)
        runs[lat] = json.loads(out)
    warn = runs["54"]["latitude_warning"]
    assert warn is not None and runs["54.5"]["latitude_warning"] is None
    # the filter's own response to the 0.5° change, in σ of the run at 54
    seen = abs(runs["54.5"]["omega_gc"] - runs["54"]["omega_gc"]) / runs["54"]["omega_gc_std"]
    assert warn["shift_over_sigma"] == pytest.approx(seen, rel=0.05)
    assert warn["shift_over_sigma"] > 3.0
    _, out, _ = _run(["calibrate", "gc", path, "--latitude", "54"], capsys)
    line = next(ln for ln in out.splitlines() if ln.startswith("  warning: the latitude"))
    assert f"about {warn['shift_over_sigma']:.2g} sigma" in line and "--latitude-sigma" in line


@pytest.mark.parametrize("how", [["--latitude", "54.4±0.5"], ["--latitude", "54.4+-0.5"],
                                 ["--latitude", "54.4", "--latitude-sigma", "0.5"]])
def test_a_latitude_uncertainty_is_a_named_term_of_sigma(at_54_4, capsys, how):
    """The term ``latitude`` is half the filter's own response to ±σ_φ (5 %), σ adds it in
    quadrature, and no whole-degree warning is given."""
    sim, path = at_54_4
    code, out, _ = _run(["calibrate", "gc", path, "--json", *how], capsys)
    data = json.loads(out)
    parts = data["omega_gc_std_parts"]
    assert code == 0 and data["latitude_warning"] is None
    assert data["earth_rate"]["latitude_sigma_deg"] == 0.5
    assert math.sqrt(sum(v * v for v in parts.values())) == pytest.approx(
        data["omega_gc_std"], rel=1e-9)
    ends = []
    for lat in ("53.9", "54.9"):
        _, o, _ = _run(["calibrate", "gc", path, "--json", "--latitude", lat], capsys)
        ends.append(json.loads(o)["omega_gc"])
    assert parts["latitude"] == pytest.approx(abs(ends[1] - ends[0]) / 2.0, rel=0.05)
    assert abs(data["omega_gc"] - sim.omega_gc) <= 3.0 * data["omega_gc_std"]
    code, out, _ = _run(["calibrate", "gc", path, *how], capsys)
    assert "latitude 54.4 deg N ± 0.5 deg (1 sigma)" in out and " latitude " in out.split(
        "sigma in parts")[1].splitlines()[0]


def test_on_the_equator_the_tool_says_what_it_still_estimates(tmp_path, capsys):
    """At 0° Ω_v = 0: the note says the tilts no longer torque the float and that ω_gc is
    still estimated against Ω_h; the whole-degree warning's count is second order (small and
    finite), and the site is printed without a hemisphere."""
    _, path = _site(0.0, 51, tmp_path)
    _, out, _ = _run(["calibrate", "gc", path, "--json"], capsys)
    data = json.loads(out)
    note = next(n for n in data["notes"] if "equator" in n)
    assert "no longer torque the float" in note and "still estimated" in note
    assert 0.0 < data["latitude_warning"]["shift_over_sigma"] < 0.2
    assert data["earth_rate"]["Omega_v"] == 0.0 and _finite(data)
    _, out, _ = _run(["calibrate", "gc", path], capsys)
    assert "latitude 0 deg (from the record's" in out and "note: the site (0 deg)" in out
    # a site at 35° S names its hemisphere
    _, south = _site(-35.0, 52, tmp_path)
    _, out, _ = _run(["calibrate", "gc", south], capsys)
    assert "latitude 35 deg S (from the record's" in out
