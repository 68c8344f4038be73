"""``calibrate gc`` is never confidently wrong.  Records with the defects of real
instruments and logs, made by the tests' own generator (``tests/support/gc_faults.py``), through the
command: either σ covers the truth (exit 0, ``"valid": true``, |ω̂ − ω| ≤ 3σ) or the command
refuses (non-zero exit, one line on stderr with the reason, no traceback, no estimate)."""

from __future__ import annotations

import csv
import dataclasses
import functools
import json
import math
from pathlib import Path

import numpy as np
import pytest

from gyrolib import gc, records
from gyrolib.cli import main
from gyrolib.units import ARCSEC_PAPER
from tests.support.gc_faults import FAULTS, MG, P, cli_params, make, make_cases, make_clean

#: Records of this file are simulated with paper GC's Earth rate (no '# latitude_deg:' line):
#: the command needs the latitude stated, so it is assumed explicitly.
GC_PAPER = ("calibrate", "gc", "--latitude", "paper")

CASES = [(f, s) for f, (_, sizes) in FAULTS.items() for s in sizes]


@functools.cache
def _made(fault: str | None, size: float, seed: int, t_end: float = 100.0):
    """:func:`gc_faults.make`, once per record in this module: the tests that use the same
    record (the drift change of seed 4100, the offset of seed 902, the latitude of seed
    777, ...) share one simulation (about 0.8 CPU-s a 100 s record) instead of making it
    again.  Nothing here changes a record: each is read only."""
    return make(fault, size, seed=seed, t_end=t_end)


@functools.cache
def _calibrated(fault: str | None, size: float, seed: int, params: gc.GyrocompassParams):
    """``gc.calibrate`` of :func:`_made`'s record with ``params``, once per module."""
    return gc.calibrate(_made(fault, size, seed).record, params)


@functools.cache
def _cases() -> list:
    """The records of :data:`CASES` (:func:`gc_faults.make_cases`, seed 500: the faults on
    the readings put on 18 records made together, the others with seed 500 + the case's
    index as before)."""
    return make_cases(CASES, 500)


@functools.cache
def _clean() -> tuple:
    """The module's 20 clean 100 s records, made together (:func:`gc_faults.make_clean`,
    seed 3000: 1.3 CPU-s for the 20, where one at a time took 0.8 CPU-s each), made on
    first use; the other clean 100 s records of the module are among them."""
    return make_clean(3000, 20)


def _write(path, rec: gc.GCRecord):
    records.write_csv(path, {"t": rec.t, "angle_sensor": rec.angle_sensor,
                             "inclinometer_y": rec.inclinometer_y,
                             "inclinometer_z": rec.inclinometer_z},
                      fmt=["%.6f", "%.12g", "%.12g", "%.12g"])
    return str(path)


def _run(argv, capsys):
    code = main(argv)
    out = capsys.readouterr()
    return code, out.out, out.err


def _covers_or_refuses(code, out, err, truth_values):
    d = json.loads(out)
    if code == 0:
        assert d["valid"] is True and err == ""
        for w in truth_values:
            assert abs(d["omega_gc"] - w) <= 3.0 * d["omega_gc_std"], (d["omega_gc"], w)
        return "covered"
    assert code == 3
    assert d["valid"] is False and d["omega_gc"] is None and d["reason"]
    assert err.count("\n") == 1 and "Traceback" not in err
    assert "no valid estimate" in err
    assert any(name in err for name in gc.MEASUREMENT_NAMES)
    return "refused"


@pytest.mark.parametrize(("fault", "size"), CASES)
def test_fault_is_covered_or_refused(fault, size, tmp_path, capsys):
    """Every fault of the issue at sizes inside its range, through the command with its
    defaults: covered within 3σ, or refused with a reason naming sensor and test.  A drift
    that changes within the record must be covered at both its values or refused."""
    fr = _cases()[CASES.index((fault, size))]
    path = _write(tmp_path / "r.csv", fr.record)
    code, out, err = _run([*GC_PAPER, path, "--json"], capsys)
    how = _covers_or_refuses(code, out, err, {fr.omega_gc, fr.omega_gc_end})
    if fault in ("drift_change", "angle_step", "incl_step") and size >= 0.5:
        assert how == "refused"    # far outside what the model can absorb


def test_faults_without_the_instrument_terms_are_confidently_wrong():
    """Power: with no instrument priors (paper GC's filter as it was) a 4″ null offset, a
    0.1 % gain and a 1 mg inclinometer bias each give an estimate more than 3σ off that
    passes every model check or, for the offset, at least misses by more than 3σ.  The
    records are those of the other tests of the same faults (the offset's of
    test_sigma_parts_and_instrument_estimates, the gain's of its fault case, the bias's of
    test_incl_bias_prior_enters_sigma): shared, not simulated again.  Without the priors
    they miss by 14.6σ, 7.8σ and 10.0σ (with seed 611 before: 16.8σ, 7.7σ, 7.5σ)."""
    gain = _cases()[CASES.index(("gain", 1e-3))]
    runs = {"gain": (gain, gc.calibrate(gain.record, P),
                     gc.calibrate(gain.record, cli_params()))}
    for fault, size, seed in (("null_offset", 4.0, 902), ("incl_z_bias", 1.0, 950)):
        runs[fault] = (_made(fault, size, seed), _calibrated(fault, size, seed, P),
                       _calibrated(fault, size, seed, cli_params()))
    for fault, (fr, res, with_priors) in runs.items():
        assert abs(res.omega_gc - fr.omega_gc) > 3.0 * res.omega_gc_std, fault
        assert abs(with_priors.omega_gc - fr.omega_gc) <= 3.0 * with_priors.omega_gc_std


def _one_line_invalid(code, out, err):
    """Exit 3, one line on stderr naming the missing latitude, no traceback, no estimate."""
    assert code == 3 and err.count("\n") == 1 and "Traceback" not in err
    assert "no valid estimate: no latitude given" in err and "53.9 deg N" in err


def test_latitude_45(tmp_path, capsys):
    """A record made at 45°: ``--latitude 45`` (or ``latitude = 45`` in --params) recovers ω
    within 3σ.  Without a latitude it is NOT valid (exit 3, the reason names what is
    missing, the summary row says the same): this is the power test, the command used to
    answer "valid" with paper GC's Ω_h, Ω_v, hundreds of σ off.  ``--latitude paper`` is the
    user's explicit assumption, said so; here wrongly assumed, the prior check refuses it
    and names the latitude."""
    fr = _made("latitude", 45.0, 777)
    path = _write(tmp_path / "r45.csv", fr.record)
    code, out, err = _run(["calibrate", "gc", path, "--json", "--latitude", "45"], capsys)
    d = json.loads(out)
    assert code == 0 and d["valid"] is True, err
    assert abs(d["omega_gc"] - fr.omega_gc) <= 3.0 * d["omega_gc_std"]
    assert d["latitude_deg"] == 45.0 and d["latitude_source"] == "option"
    assert d["earth_rate"]["latitude_deg"] == 45.0
    assert d["earth_rate"]["Omega_h"] == pytest.approx(7.292115e-5 * math.cos(math.pi / 4),
                                                       rel=1e-12)
    toml = tmp_path / "lat.toml"
    toml.write_text("latitude = 45.0\n")
    code, out2, _ = _run(["calibrate", "gc", path, "--json", "--params", str(toml)], capsys)
    d2 = json.loads(out2)
    assert code == 0 and d2["omega_gc"] == pytest.approx(d["omega_gc"], rel=1e-12)
    assert d2["latitude_source"] == "params" and d2["latitude_deg"] == 45.0
    # no latitude: the estimate is computed, but not valid
    code, out, err = _run(["calibrate", "gc", path], capsys)
    _one_line_invalid(code, out, err)
    assert "no valid estimate: no latitude given (--latitude, a 'latitude' key in --params, " \
           "or a '# latitude_deg:' line in the record); the paper's Omega_h, Omega_v " \
           "correspond to about 53.9 deg N" in out
    assert "Earth rate: NO latitude given" in out and "omega_gc =" not in out
    code, out, err = _run(["calibrate", "gc", path, "--json"], capsys)
    _one_line_invalid(code, out, err)
    d = json.loads(out)
    assert d["valid"] is False and d["omega_gc"] is None and d["omega_gc_std"] is None
    assert d["reason"].startswith("no latitude given")
    assert d["latitude_deg"] is None and d["latitude_source"] == "none"
    assert d["earth_rate"]["stated"] is False and d["earth_rate"]["Omega_h"] == P.Omega_h
    # paper GC's Earth rate, assumed explicitly: the 9 deg between the sites read as a drift
    # far outside its prior, so the prior check refuses it and names the latitude, near 45
    # deg, that would explain it (before, this was "valid" and hundreds of σ off)
    code, out, err = _run(["calibrate", "gc", path, "--json", "--latitude", "paper"], capsys)
    d = json.loads(out)
    assert code == 3 and d["valid"] is False and d["reason_code"] == "prior_latitude"
    assert d["latitude_source"] == "paper (assumed by --latitude paper)"
    assert d["latitude_deg"] == pytest.approx(53.91, abs=0.01)
    assert d["earth_rate"]["Omega_h"] == P.Omega_h and d["earth_rate"]["Omega_v"] == P.Omega_v
    explained = float(d["reason"].split("about ")[1].split(" deg")[0])
    assert abs(explained - 45.0) < 2.0, d["reason"]


def test_no_latitude_is_not_valid_and_paper_is_an_explicit_choice(tmp_path, capsys):
    """A clean record of paper GC's model without a latitude: exit 3, ``"valid": false``,
    the reason, and --accept-misfit does not turn it into an estimate (a missing latitude is
    not a misfit); ``--latitude paper`` gives the valid estimate, and the text says the
    values were assumed.  In a batch the row says invalid with the same reason."""
    fr = _clean()[1]
    path = _write(tmp_path / "clean.csv", fr.record)
    code, out, err = _run(["calibrate", "gc", path, "--json", "--accept-misfit"], capsys)
    _one_line_invalid(code, out, err)
    d = json.loads(out)
    assert d["valid"] is False and d["misfit_accepted"] is False and d["omega_gc"] is None
    assert d["model_fits"] is True        # the record fits: only the latitude is missing
    code, out, err = _run(["calibrate", "gc", path, "--latitude", "paper"], capsys)
    assert code == 0 and err == ""
    assert "Earth rate: latitude 53.9149 deg N (ASSUMED: paper GC's values, by --latitude " \
           "paper): Omega_h = 4.3e-05, Omega_v = 5.9e-05 rad/s" in out
    code, out, err = _run(["calibrate", "gc", path, "--json", "--latitude", "paper"], capsys)
    d = json.loads(out)
    assert code == 0 and d["valid"] is True
    assert abs(d["omega_gc"] - fr.omega_gc) <= 3.0 * d["omega_gc_std"]
    summary = tmp_path / "s.csv"
    header = tmp_path / "header.csv"     # the same rows, with a latitude line
    header.write_text("# latitude_deg: 45\n" + Path(path).read_text())
    code, out, err = _run(["calibrate", "gc", path, str(header), "--summary", str(summary)],
                          capsys)
    assert code == 3
    with summary.open(newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert rows[0]["status"] == "invalid" and rows[0]["valid"] == "false"
    assert rows[0]["reason"].startswith("no latitude given") and rows[0]["estimate"] == ""
    assert "no latitude" not in rows[1]["reason"]     # the header states one


def test_no_latitude_on_the_in_memory_path_writes_nothing(tmp_path, capsys):
    """--allan reads the record whole (not streamed): without a latitude it is not valid
    either (exit 3, the reason) and writes no plot; with the latitude it writes it."""
    fr = _made(None, 0.0, 3003, t_end=20.0)
    path = _write(tmp_path / "r.csv", fr.record)
    png = tmp_path / "allan.png"
    code, out, err = _run(["calibrate", "gc", path, "--allan", str(png)], capsys)
    _one_line_invalid(code, out, err)
    assert not png.exists()
    code, out, err = _run([*GC_PAPER, path, "--allan", str(png)], capsys)
    assert code == 0 and png.stat().st_size > 1000


def test_record_header_latitude_and_a_conflicting_option(tmp_path, capsys):
    """The record's ``# latitude_deg: 45`` line is a stated latitude (valid, within 3σ,
    ``latitude_source`` "record header").  A --latitude that disagrees with it wins (the
    documented rule: an option or params file overrides the record, e.g. a wrong header),
    and the output says both: the note, the Earth-rate line, ``record_latitude_deg``."""
    fr = _made("latitude", 45.0, 777)     # test_latitude_45's record, with the header line
    path = tmp_path / "h45.csv"
    records.write_csv(path, {"t": fr.record.t, "angle_sensor": fr.record.angle_sensor,
                             "inclinometer_y": fr.record.inclinometer_y,
                             "inclinometer_z": fr.record.inclinometer_z},
                      comments=["latitude_deg: 45"], fmt=["%.6f", "%.12g", "%.12g", "%.12g"])
    code, out, err = _run(["calibrate", "gc", str(path), "--json"], capsys)
    d = json.loads(out)
    assert code == 0 and d["valid"] is True and err == ""
    assert d["latitude_source"] == "record header" and d["latitude_deg"] == pytest.approx(45.0)
    assert abs(d["omega_gc"] - fr.omega_gc) <= 3.0 * d["omega_gc_std"]
    assert not any("latitude" in n for n in d["notes"])
    code, out, err = _run(["calibrate", "gc", str(path), "--json", "--latitude", "50"], capsys)
    d = json.loads(out)
    # the option wins, and the 5 deg between the record's site and 50 deg read as a drift
    # far outside its prior: not valid, the latitude named
    assert code == 3 and d["latitude_source"] == "option" and d["latitude_deg"] == 50.0
    assert d["reason_code"] == "prior_latitude", d["reason"]
    assert d["earth_rate"]["record_latitude_deg"] == pytest.approx(45.0)
    assert d["earth_rate"]["Omega_h"] == pytest.approx(
        gc.GyrocompassParams.at_latitude(math.radians(50.0)).Omega_h, rel=1e-12)
    note = next(n for n in d["notes"] if "latitude" in n)
    assert "says 45 deg" in note and "50 deg from --latitude used" in note
    code, out, err = _run(["calibrate", "gc", str(path), "--latitude", "50"], capsys)
    assert "latitude 50 deg N (from --latitude; the record's '# latitude_deg:' line says " \
           "45 deg, overridden)" in out


def test_params_earth_rate_components_state_the_latitude(tmp_path, capsys):
    """Omega_h and Omega_v both in --params state the Earth rate (valid, source params, the
    latitude their angle); one of them alone is refused (exit 2: the other would silently be
    the paper's, or the record header's)."""
    fr = _clean()[2]
    path = _write(tmp_path / "r.csv", fr.record)
    toml = tmp_path / "p.toml"
    toml.write_text(f"Omega_h = {P.Omega_h!r}\nOmega_v = {P.Omega_v!r}\n")
    code, out, err = _run(["calibrate", "gc", path, "--json", "--params", str(toml)], capsys)
    d = json.loads(out)
    assert code == 0 and d["valid"] is True and d["latitude_source"] == "params"
    assert d["latitude_deg"] == pytest.approx(math.degrees(math.atan2(5.9, 4.3)), abs=1e-9)
    toml.write_text(f"Omega_v = {P.Omega_v!r}\n")
    code, out, err = _run(["calibrate", "gc", path, "--json", "--params", str(toml)], capsys)
    assert code == 2 and json.loads(out)["status"] == "error" and err.count("\n") == 1
    assert "sets Omega_v but not Omega_h" in err and str(toml) in err


def test_record_latitude_is_used(tmp_path, capsys):
    """``GCRecord.latitude`` (the reader fills it from a ``# latitude_deg:`` line): used when
    neither --latitude nor the params file give one; without any, not stated."""
    from gyrolib.cli import calibrate_gc as cli

    o = {"latitude": None, "latitude_source": cli.LAT_NONE}
    notes: list[str] = []
    p, earth = cli._with_latitude(P, math.radians(45.0), o, notes)
    assert earth["source"] == "record header" and earth["latitude_deg"] == pytest.approx(45.0)
    assert earth["stated"] is True
    assert p.Omega_h == pytest.approx(p.Omega_v, rel=1e-12) and not notes
    p, earth = cli._with_latitude(P, None, o, notes)
    assert p == P and earth["source"] == "none" and earth["stated"] is False and not notes


def test_python_api_checks_the_earth_rate_against_the_records_latitude():
    """``gc.calibrate`` on a record that states its latitude: with the Earth rate of another
    site (the paper's, about 53.9 deg) it has no valid estimate and says why, since Ω_h
    reads as drift (here several σ off); with ``at_latitude(record.latitude)`` the same
    record is valid and covered.  The difference in Ω_h, by hand, is the drift offset."""
    site = math.radians(45.0)
    sim = gc.simulate_record(gc.GyrocompassParams.at_latitude(site), 100.0, seed=4501)
    rec = dataclasses.replace(sim.record, latitude=site)
    wrong = gc.calibrate(rec, gc.GyrocompassParams())
    assert not wrong.valid and wrong.reason.startswith(
        "the record states latitude 45 deg N, but the Earth rate of params")
    off = (gc.GyrocompassParams().Omega_h - 7.292115e-5 * math.cos(site)) * 180 / math.pi * 3600
    assert f"Omega_h off by {off:+.3g} deg/h" in wrong.reason
    assert abs(wrong.omega_gc - sim.omega_gc) > 10 * wrong.omega_gc_std   # it would mislead
    right = gc.calibrate(rec, gc.GyrocompassParams.at_latitude(rec.latitude))
    assert right.valid, right.reason
    assert abs(right.omega_gc - sim.omega_gc) < 3 * right.omega_gc_std
    # without a stated latitude the record cannot be checked: the caller's rate is taken
    same = gc.calibrate(sim.record, gc.GyrocompassParams())
    assert "states latitude" not in same.reason
    # the paper's printed rates are 0.1 % off the rate at 53.9 deg: a record that states
    # 53.9 deg is refused with them, accepted with at_latitude
    from gyrolib.gc.model.params import PAPER_LATITUDE

    r54 = dataclasses.replace(sim.record, latitude=PAPER_LATITUDE)
    assert gc.earth_rate_mismatch(gc.GyrocompassParams(), r54.latitude)
    assert not gc.earth_rate_mismatch(gc.GyrocompassParams.at_latitude(r54.latitude),
                                      r54.latitude)


def test_scale_beyond_the_stated_tolerance_is_not_caught():
    """A 1 % error of H/f: covered when the user states a 1 % tolerance (the scale part of σ
    is then ≈ 10⁻² Ω_h), NOT covered and NOT refused with the 0.1 % default — a scale error
    reads as a drift of κ Ω_h that no record of this length tells from ω_gc (the bench
    check of the chapter is the only guard).  A 1 % error of the angle sensor's gain alone
    also scales the sensor's noise, by 2 % in variance, which the mean-NIS test sees."""
    fr = make("hf_scale", 1e-2, seed=801)
    res = gc.calibrate(fr.record, cli_params(sigma_hf_scale=1e-2))
    assert res.valid and abs(res.omega_gc - fr.omega_gc) <= 3.0 * res.omega_gc_std
    # at most κ Ω_h: a prior this wide lets the float's transient and cos β_n tell part of
    # the scale from the drift
    assert 0.7 * 1e-2 * P.Omega_h <= res.omega_gc_std_parts["scale"] <= 1.01e-2 * P.Omega_h
    res = gc.calibrate(fr.record, cli_params())
    assert res.valid and abs(res.omega_gc - fr.omega_gc) > 3.0 * res.omega_gc_std
    res = gc.calibrate(make("gain", 1e-2, seed=801).record, cli_params())
    assert not res.valid and "angle_sensor: mean NIS failed" in res.reason


def test_sigma_parts_and_instrument_estimates():
    """σ's parts add in quadrature to σ; the noise part is the paper's filter alone; the scale
    part is ``sigma_hf_scale · Ω_h`` (the closed form of ``scale_drift_sigma``) within 5 %;
    the offset injected (4″) is estimated within 3σ; the response of ω̂ to a unit offset
    that the bias separation carries equals a finite difference of two runs of the filter
    without instrument terms."""
    p = cli_params()
    res = _calibrated("null_offset", 4.0, 902, p)
    parts = res.omega_gc_std_parts
    assert math.hypot(*parts.values()) == pytest.approx(res.omega_gc_std, rel=1e-9)
    clean = gc.calibrate(_made(None, 0.0, 902).record, P)
    assert parts["noise"] == pytest.approx(clean.omega_gc_std, rel=1e-6)
    assert parts["scale"] == pytest.approx(p.scale_drift_sigma, rel=0.05)
    off = res.instrument["angle_offset"]
    assert abs(off["estimate"] - 4.0 * ARCSEC_PAPER) <= 3.0 * off["std"]
    assert off["std"] < 0.1 * ARCSEC_PAPER       # well identified: Δβ(0) = 0 is known
    raw = _calibrated("null_offset", 4.0, 902, P)
    i = gc.state_index("omega_gc")
    fd = (raw.omega_gc - clean.omega_gc) / (4.0 * ARCSEC_PAPER)
    assert res.bias_response[0, i] == pytest.approx(fd, rel=1e-3)


@pytest.fixture(scope="module")
def clean_runs():
    """20 clean 100 s records (:func:`_clean`) and their calibrations with the command's
    default priors, shared by the false-alarm and the split-record tests."""
    p = cli_params()
    return [(fr, gc.calibrate(fr.record, p)) for fr in _clean()]


def test_false_alarm_and_coverage_on_clean_records(clean_runs):
    """20 clean 100 s records with the command's default priors: at most 2 refused (the
    gate's family-wise false-alarm rate is 1 %: P(≥ 3 of 20) = 0.1 %), and of the valid
    ones at least 80 % within 2σ and all within 4σ (95 % and 99.99 % expected; measured: 1
    refused, inclinometer_y's whiteness on record 12, and every valid one within 0.65σ, the
    priors' σ holding terms these records do not carry).  The same gate on a model whose
    angle-sensor noise is 5 % too low refuses every record (power)."""
    p = cli_params()
    z, refused = [], 0
    for fr, res in clean_runs:
        if not res.valid:
            refused += 1
            continue
        z.append((res.omega_gc - fr.omega_gc) / res.omega_gc_std)
    z = np.abs(np.array(z))
    assert refused <= 2
    assert np.mean(z <= 2.0) >= 0.8 and np.all(z <= 4.0)
    wrong = dataclasses.replace(p, C_as=0.95 * p.C_as)
    for fr, _ in clean_runs[:3]:   # the same records, not simulated again
        res = gc.calibrate(fr.record, wrong)
        assert not res.valid and "angle_sensor: mean NIS failed" in res.reason


def test_split_test_is_standard_normal_and_has_power(clean_runs):
    """The split-record statistics of the 20 clean records have mean ≈ 0 and variance ≈ 1
    (3 splits each, 60 values: |mean| < 0.6, variance in [0.5, 2.0]; measured −0.09 and 1.05);
    a 0.05″/s drift change fails it."""
    zs = np.array([z for _, res in clean_runs for _, z in res.split_tests()])
    assert zs.size == 60
    assert abs(zs.mean()) < 0.6 and 0.5 <= zs.var() <= 2.0
    res = _calibrated("drift_change", 0.05, 4100, cli_params())
    assert any("split-record" in t["test"] and not t["passed"] for t in res.model_tests())


def test_accept_misfit_and_batch_rows(tmp_path, capsys):
    """A 0.5″/s drift change: exit 3 and a summary row that says invalid and why; with
    ``--accept-misfit`` exit 0, the estimate given and marked misfit (valid false), its row
    status ``misfit``."""
    bad = _write(tmp_path / "bad.csv", _made("drift_change", 0.05, 4100).record)
    good = _write(tmp_path / "good.csv", _clean()[1].record)
    summary = tmp_path / "s.csv"
    code, out, err = _run([*GC_PAPER, good, bad, "--summary", str(summary)], capsys)
    assert code == 3
    rows = summary.read_text().splitlines()
    assert rows[1].split(",")[7] == "ok" and rows[2].split(",")[7] == "invalid"
    assert "split-record" in rows[2] or "whiteness" in rows[2]
    code, out, err = _run([*GC_PAPER, bad, "--json", "--accept-misfit"], capsys)
    d = json.loads(out)
    assert code == 0 and err == ""
    assert d["valid"] is False and d["misfit"] is True and d["misfit_accepted"] is True
    assert d["omega_gc"] is not None and d["reason"]
    # the text of the batch is each file's text (the bad one's marked MISFIT)
    code, out, err = _run([*GC_PAPER, good, bad, "--summary", str(summary),
                           "--accept-misfit"], capsys)
    assert code == 0 and summary.read_text().splitlines()[2].split(",")[7] == "misfit"
    texts = out.split("paper GC calibration of")
    assert len(texts) == 3 and "MISFIT" not in texts[1] and "MISFIT" in texts[2]


@pytest.fixture(scope="module")
def ten_rows(tmp_path_factory):
    """A record of ten rows of zeros: the options are refused before it is read."""
    rec = gc.GCRecord(t=np.arange(1, 11) * P.dt, angle_sensor=np.zeros(10),
                      inclinometer_y=np.zeros(10), inclinometer_z=np.zeros(10))
    return _write(tmp_path_factory.mktemp("ten") / "r.csv", rec)


@pytest.mark.parametrize(("argv", "words"), [
    (["--latitude", "95"], ["--latitude", "(-90, 90)"]),
    (["--latitude=-90"], ["--latitude", "(-90, 90)", "pole"]),
    (["--latitude", "north"], ["--latitude", "(-90, 90)", "'paper'", "north"]),
    (["--latitude", "nan"], ["--latitude", "(-90, 90)"]),
    (["--latitude", "54±-1"], ["--latitude", "uncertainty", ">= 0"]),
    (["--latitude", "54±0.5", "--latitude-sigma", "0.5"], ["--latitude-sigma", "give one"]),
    (["--latitude-sigma=-1"], ["--latitude-sigma", ">= 0"]),
    (["--scale-tolerance=-1e-3"], ["--scale-tolerance", ">= 0"]),
    (["--offset-prior", "nan"], ["--offset-prior", ">= 0"]),
    (["--inclinometer-bias-prior=-1"], ["--inclinometer-bias-prior", ">= 0"]),
    (["--false-alarm", "1.5"], ["--false-alarm", "(0, 1)"]),
])
def test_bad_options(argv, words, ten_rows, capsys):
    code, out, err = _run(["calibrate", "gc", ten_rows, *argv], capsys)
    assert code == 2 and out == "" and err.count("\n") == 1
    assert all(w in err for w in words), err


@pytest.mark.parametrize(("text", "words"), [
    ("latitude = 95.0\n", ["latitude", "(-90, 90)"]),
    ("latitude = 45.0\nOmega_h = 4e-5\n", ["latitude", "Omega_h"]),
])
def test_bad_toml_latitude(text, words, ten_rows, tmp_path, capsys):
    toml = tmp_path / "p.toml"
    toml.write_text(text)
    code, out, err = _run(["calibrate", "gc", ten_rows, "--params", str(toml)], capsys)
    assert code == 2 and out == "" and err.count("\n") == 1 and str(toml) in err
    assert all(w in err for w in words), err


def test_incl_bias_prior_enters_sigma():
    """A 1 mg inclinometer_z bias cannot be told from a tilt: the bias estimate stays near its
    prior's σ, and σ(ω_gc) carries it (the instrument part is larger than the noise part)."""
    res = _calibrated("incl_z_bias", 1.0, 950, cli_params())
    b = res.instrument["inclinometer_z_bias"]
    assert b["std"] > 0.5 * b["prior"]
    assert abs(b["estimate"] - 1.0 * MG) <= 3.0 * b["std"]
    parts = res.omega_gc_std_parts
    assert parts["instrument_biases"] > parts["noise"]
