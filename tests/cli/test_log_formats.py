"""Everyday log formats: a header in another case (matched, with a note), a
name that matches nothing ("did you mean", and the --columns to try), trailing empty rows
from a spreadsheet (skipped), rows logged before the feedback switch-off (``--t0`` drops
them and says how many), decimal commas, and the unit options.  Each case with one that
must refuse.  The records are 2 s of paper GC's model (seed 3471), read without a
calibration where the reader alone decides."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from gyrolib import gc, records
from gyrolib.cli import main

P = gc.GyrocompassParams()
HEADER = "t,angle_sensor,inclinometer_y,inclinometer_z"


def _run(argv, capsys):
    code = main([str(a) for a in argv])
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.fixture(scope="module")
def rows() -> list[str]:
    r = gc.simulate_record(P, 2.0, seed=3471).record
    return [f"{t:.3f},{a:.12g},{y:.12g},{z:.12g}" for t, a, y, z in
            zip(r.t, r.angle_sensor, r.inclinometer_y, r.inclinometer_z)]


@pytest.fixture(scope="module")
def rows20() -> list[str]:
    """20 s: long enough for the checks at the door to tell a unit (2 s is not)."""
    r = gc.simulate_record(P, 20.0, seed=3472).record
    return [f"{t:.3f},{a:.12g},{y:.12g},{z:.12g}" for t, a, y, z in
            zip(r.t, r.angle_sensor, r.inclinometer_y, r.inclinometer_z)]


def _write(path: Path, header: str, rows: list[str], tail: list[str] = ()) -> Path:
    path.write_text("\n".join([header, *rows, *tail]) + "\n")
    return path


def test_header_in_another_case_is_matched_with_a_note(rows, tmp_path):
    path = _write(tmp_path / "case.csv", "T,Angle_Sensor,INCLINOMETER_Y,inclinometer_z", rows)
    rec, info = records.read_gc(path, return_info=True)
    ref = records.read_gc(_write(tmp_path / "ref.csv", HEADER, rows))
    assert np.array_equal(rec.angle_sensor, ref.angle_sensor)
    assert [n.split(" read from")[0] for n in info.notes] == [
        "column 't'", "column 'angle_sensor'", "column 'inclinometer_y'"]
    assert all("matched ignoring case" in n for n in info.notes)


def test_a_name_that_matches_nothing_gets_did_you_mean(rows, tmp_path, capsys):
    path = _write(tmp_path / "typo.csv", "t,angle_sensr,inclinometer_y,inclinometer_z", rows)
    with pytest.raises(records.RecordError, match="did you mean 'angle_sensr'") as exc:
        records.read_gc(path)
    assert exc.value.hint == "--columns angle_sensor=angle_sensr"
    code, out, err = _run(["calibrate", "gc", path, "--latitude", "paper", "--json"], capsys)
    assert code == 2 and err.count("\n") == 1
    assert json.loads(out)["hint"] == "try: --columns angle_sensor=angle_sensr"
    # nothing close: no guess (the check's power)
    far = _write(tmp_path / "far.csv", "t,xyz,inclinometer_y,inclinometer_z", rows)
    with pytest.raises(records.RecordError) as exc:
        records.read_gc(far)
    assert "did you mean" not in str(exc.value) and exc.value.hint is None


def test_a_missing_column_is_never_pointed_at_another_sensors(rows, tmp_path):
    """A record without ``inclinometer_z``: the closest header is ``inclinometer_y``, which
    another column reads, so no hint names it (``--columns inclinometer_z=inclinometer_y``
    would read one sensor twice); a free header as close is still suggested (power)."""
    three = [",".join(r.split(",")[:3]) for r in rows]
    path = _write(tmp_path / "no_z.csv", "t,angle_sensor,inclinometer_y", three)
    with pytest.raises(records.RecordError, match="not in the header") as exc:
        records.read_gc(path)
    assert exc.value.column == "inclinometer_z" and exc.value.hint is None
    assert "did you mean" not in str(exc.value)
    free = _write(tmp_path / "zz.csv", "t,angle_sensor,inclinometer_y,inclinometer_zz", rows)
    with pytest.raises(records.RecordError) as exc:
        records.read_gc(free)
    assert exc.value.hint == "--columns inclinometer_z=inclinometer_zz"


def test_trailing_empty_rows_are_skipped(rows, tmp_path):
    path = _write(tmp_path / "excel.csv", HEADER, rows, [",,,", ",,,", ""])
    rec, info = records.read_gc(path, return_info=True)
    assert rec.n == len(rows) and info.empty_rows == 2
    assert any("2 empty row(s)" in n for n in info.notes)
    # an empty time with values beside it is still refused, with its line
    bad = _write(tmp_path / "bad.csv", HEADER, [*rows[:5], ",0,0,0", *rows[5:]])
    with pytest.raises(records.RecordError, match="line 7, column 't'"):
        records.read_gc(bad)


def test_t0_drops_the_earlier_rows_and_says_how_many(rows, tmp_path):
    """Rows logged 0.5 s before the switch-off (times shifted by 0.5 s, 500 rows before):
    --t0 0.5 drops them, says so, and gives the record as logged from the switch-off."""
    early = [f"{0.001 * k:.3f},{rows[0].split(',', 1)[1]}" for k in range(1, 500)]
    late = [f"{float(r.split(',')[0]) + 0.5:.3f},{r.split(',', 1)[1]}" for r in rows]
    path = _write(tmp_path / "early.csv", HEADER, [*early, *late])
    rec, info = records.read_gc(path, t0=0.5, return_info=True)
    ref = records.read_gc(_write(tmp_path / "ref.csv", HEADER, rows))
    assert info.rows_dropped == 499 and "the 499 row(s) before it dropped" in info.time_note
    assert rec.n == ref.n and np.allclose(rec.t, ref.t, atol=1e-9)
    # without t0 the early rows stay (the check's power)
    rec, info = records.read_gc(path, return_info=True)
    assert rec.n == ref.n + 499 and info.rows_dropped == 0 and info.time_note is None


@pytest.mark.parametrize(("col", "scale", "option", "unit"), [
    (1, 180.0 / np.pi, "--angle-unit", "deg"),
    (1, 180.0 / np.pi * 3600.0, "--angle-unit", "arcsec"),
    (0, 1000.0, "--time-unit", "ms"),
])
def test_unit_options_convert_and_the_diagnosis_names_them(rows20, tmp_path, capsys, col,
                                                           scale, option, unit):
    """A column in another unit: refused at the door with the option to use as the hint
    (exit 2); read with that option it gives the SI record's estimate."""
    def scaled(r: str) -> str:
        f = r.split(",")
        f[col] = f"{float(f[col]) * scale:.12g}"
        return ",".join(f)

    ref = _write(tmp_path / "si.csv", HEADER, rows20)
    path = _write(tmp_path / f"{unit}.csv", HEADER, [scaled(r) for r in rows20])
    lat = ["--latitude", "paper", "--json"]
    code, out, err = _run(["calibrate", "gc", path, *lat], capsys)
    assert code == 2 and json.loads(out)["hint"] == f"try: {option} {unit}"
    assert f"try: {option} {unit}" in err
    _, out, _ = _run(["calibrate", "gc", ref, *lat], capsys)
    want = json.loads(out)["omega_gc"]
    code, out, _ = _run(["calibrate", "gc", path, *lat, option, unit], capsys)
    assert code == 0 and json.loads(out)["omega_gc"] == pytest.approx(want, rel=1e-6)


def test_inclinometers_in_g(rows20, tmp_path):
    g = P.g

    def in_g(r: str) -> str:
        f = r.split(",")
        return ",".join([f[0], f[1], f"{float(f[2]) / g:.12g}", f"{float(f[3]) / g:.12g}"])

    path = _write(tmp_path / "g.csv", HEADER, [in_g(r) for r in rows20])
    with pytest.raises(records.RecordError) as exc:
        records.read_gc(path)
    assert exc.value.hint == "--accel-unit g"
    rec = records.read_gc(path, units={"accel": "g"})
    ref = records.read_gc(_write(tmp_path / "si.csv", HEADER, rows20))
    np.testing.assert_allclose(rec.inclinometer_y, ref.inclinometer_y * P.g / 9.80665,
                               rtol=1e-9)


def _comma(line: str) -> str:
    return ";".join(c.replace(".", ",") for c in line.split(","))


def test_decimal_commas_detected_told_or_refused_as_ambiguous(rows, tmp_path):
    """';' columns with every number written d,d: read with a decimal comma (detected, with
    a note), the same record as with points; a line mixing d,d and plain integers is
    ambiguous unless told (decimal_comma=True); commas as separators cannot be decimal."""
    ref = records.read_gc(_write(tmp_path / "ref.csv", HEADER, rows))
    path = _write(tmp_path / "dc.csv", HEADER.replace(",", ";"), [_comma(r) for r in rows])
    rec, info = records.read_gc(path, return_info=True)
    assert np.array_equal(rec.angle_sensor, ref.angle_sensor)
    assert np.array_equal(rec.t, ref.t)
    assert any("decimal comma (detected" in n for n in info.notes)
    mixed = [_comma(rows[0]).split(";", 1)[0] + ";0;0;0", *(_comma(r) for r in rows[1:])]
    amb = _write(tmp_path / "amb.csv", HEADER.replace(",", ";"), mixed)
    with pytest.raises(records.RecordError, match="ambiguous decimal separator") as exc:
        records.read_gc(amb, check=False)
    assert exc.value.hint == "--decimal-comma"
    rec = records.read_gc(amb, check=False, decimal_comma=True)
    assert rec.t[0] == pytest.approx(ref.t[0]) and rec.angle_sensor[0] == 0.0
    with pytest.raises(records.RecordError, match="decimal commas need another column"):
        records.read_gc(_write(tmp_path / "c.csv", HEADER, rows), decimal_comma=True)
    # points stay points: the plain file is not read with commas (power)
    assert records.read_gc(tmp_path / "ref.csv", return_info=True)[1].notes == []


def test_a_units_row_is_read_and_skipped(rows20, tmp_path, capsys):
    """A units row under the header ("[s],[deg],[m/s^2],[m/s^2]"): read as the units of the
    columns (the angle converted from degrees, with a note), never as data; an unknown unit
    or one an option contradicts is refused naming the row and column."""
    def deg(r: str) -> str:
        f = r.split(",")
        f[1] = f"{float(f[1]) * 180.0 / np.pi:.15g}"
        return ",".join(f)

    ref = records.read_gc(_write(tmp_path / "si.csv", HEADER, rows20))
    path = _write(tmp_path / "units.csv", HEADER, ["[s],[deg],[m/s^2],[m/s^2]",
                                                   *(deg(r) for r in rows20)])
    rec, info = records.read_gc(path, return_info=True)
    assert rec.n == ref.n and np.allclose(rec.angle_sensor, ref.angle_sensor, rtol=1e-12)
    assert any(n.startswith("units row (line 2) read: t in s, angle_sensor in deg")
               for n in info.notes)
    bad = _write(tmp_path / "bad.csv", HEADER, ["s,furlong,m/s^2,m/s^2", *rows20])
    with pytest.raises(records.RecordError, match="line 2, column 'angle_sensor': the "
                                                  "units row gives 'furlong'"):
        records.read_gc(bad)
    with pytest.raises(records.RecordError, match="contradicts"):
        records.read_gc(path, units={"angle": "rad"})
    # a fault further down is still named at its own line (the units row is not a row)
    broken = _write(tmp_path / "broken.csv", HEADER, ["[s],[deg],[m/s^2],[m/s^2]",
                                                      *rows20[:9], "0.0105,x,0,0",
                                                      *rows20[10:]])
    with pytest.raises(records.RecordError, match="line 12, column 'angle_sensor'"):
        records.read_gc(broken)


def test_iso_date_time_stamps(rows, tmp_path):
    """ISO 8601 stamps ("2024-05-14 10:32:01.251"): taken relative to the first row, exact
    to 1 ns, with a note; --t0 S drops the rows of the first S seconds; a stamp that is not
    one is named at its line."""
    import datetime

    base = datetime.datetime(2024, 5, 14, 10, 32, 1, 251000)

    def iso(r: str) -> str:
        f = r.split(",")
        stamp = base + datetime.timedelta(milliseconds=round(float(f[0]) * 1000))
        return ",".join([stamp.strftime("%Y-%m-%d %H:%M:%S.%f")[:-3], *f[1:]])

    ref = records.read_gc(_write(tmp_path / "ref.csv", HEADER, rows))
    path = _write(tmp_path / "iso.csv", HEADER, [iso(r) for r in rows])
    rec, info = records.read_gc(path, return_info=True)
    np.testing.assert_allclose(rec.t, ref.t - ref.t[0], rtol=0, atol=1e-12)
    assert np.array_equal(rec.angle_sensor, ref.angle_sensor)
    assert info.time_note.startswith("ISO date-time stamps, taken relative to the first row")
    rec, info = records.read_gc(path, t0=0.5, return_info=True)
    assert info.rows_dropped == 500 and rec.t[0] == pytest.approx(0.0, abs=1e-12)
    bad = [iso(r) for r in rows]
    bad[7] = "2024-05-14 xx," + bad[7].split(",", 1)[1]
    with pytest.raises(records.RecordError, match="line 9, column 't'"):
        records.read_gc(_write(tmp_path / "bad.csv", HEADER, bad))


def test_iso_stamps_with_a_zone_are_read_as_utc(rows, tmp_path):
    """ISO 8601 stamps with a zone ("2024-05-14T10:32:01.251+02:00", "Z"): read as UTC, so a
    logger whose local clock switches from +02:00 to +01:00 half-way (the clock reads an
    hour earlier) gives the same record as plain seconds; read without its zones the same
    stamps jump back by 3600 s and are refused (power).  A file mixing zoned and local
    stamps is refused at the first stamp of the other kind."""
    import datetime

    base = datetime.datetime(2024, 5, 14, 8, 32, 1, 251000, tzinfo=datetime.UTC)
    half = len(rows) // 2

    def iso(k: int, r: str, fmt) -> str:
        f = r.split(",")
        stamp = base + datetime.timedelta(milliseconds=round(float(f[0]) * 1000))
        return ",".join([fmt(k, stamp), *f[1:]])

    def local(k, stamp):   # +02:00 for the first half, then +01:00 (the clock set back)
        tz = datetime.timezone(datetime.timedelta(hours=2 if k < half else 1))
        return stamp.astimezone(tz).isoformat(timespec="milliseconds")

    ref = records.read_gc(_write(tmp_path / "ref.csv", HEADER, rows))
    for name, fmt in (("dst", local),
                      ("z", lambda k, st: st.strftime("%Y-%m-%dT%H:%M:%S.%f")[:-3] + "Z"),
                      ("hhmm", lambda k, st: local(k, st).replace("+02:00", "+0200")
                       .replace("+01:00", "+01"))):
        lines = [iso(k, r, fmt) for k, r in enumerate(rows)]
        rec, info = records.read_gc(_write(tmp_path / f"{name}.csv", HEADER, lines),
                                    return_info=True)
        np.testing.assert_allclose(rec.t, ref.t - ref.t[0], rtol=0, atol=1e-12)
        assert np.array_equal(rec.angle_sensor, ref.angle_sensor)
        assert info.time_note.startswith("ISO date-time stamps with a zone, read as UTC")
    assert lines[half - 1].split(",")[0].endswith("+0200")      # the zones really change
    naive = [iso(k, r, local)[:23] + "," + r.split(",", 1)[1] for k, r in enumerate(rows)]
    with pytest.raises(records.RecordError, match=f"line {half + 2}"):
        records.read_gc(_write(tmp_path / "naive.csv", HEADER, naive))
    mixed = [iso(k, r, local) for k, r in enumerate(rows)]
    mixed[9] = naive[9]
    with pytest.raises(records.RecordError, match=r"line 11, column 't': expected an ISO "
                                                  r"date-time stamp with a zone"):
        records.read_gc(_write(tmp_path / "mixed.csv", HEADER, mixed))
