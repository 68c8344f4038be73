"""One reader for every command: a record written in each format the reader takes (a units
row, decimal commas, ISO 8601 time stamps, gzip, tabs, ``#`` comments before the header, a
UTF-8 byte-order mark) gives ``calibrate gc``, ``calibrate rsf`` and ``allan`` the same
numbers as the plain CSV (to 1e-12, relative), or the same named refusal; the plain CSV's
numbers are checked against the library called directly (an independent path that reads
no file).  Power: a variant whose values are perturbed by 1e-9 is told apart."""

from __future__ import annotations

import datetime as _dt
import gzip
import json
import re
from pathlib import Path

import numpy as np
import pytest

from gyrolib import gc, rsf
from gyrolib.cli import main
from gyrolib.gc.logs.allan import allan_series, noise_terms

P = gc.GyrocompassParams()
FORMATS = ("plain", "units_row", "decimal_comma", "iso_time", "gzip", "tab", "comments",
           "bom")
_BASE = _dt.datetime(2024, 5, 14, 10, 32, 1, tzinfo=_dt.UTC)


def _text(cols: dict[str, np.ndarray], units: dict[str, str], fmt: str) -> tuple[str, str]:
    """The file's text and suffix of ``cols`` (SI; time to 1 µs) in format ``fmt``."""
    names = list(cols)
    sep = {"decimal_comma": ";", "tab": "\t"}.get(fmt, ",")
    cells = []
    for name, x in cols.items():
        if name == "t" and fmt == "iso_time":
            cells.append([(_BASE + _dt.timedelta(microseconds=round(1e6 * v)))
                          .strftime("%Y-%m-%dT%H:%M:%S.%fZ") for v in x])
        elif name == "t" and fmt == "units_row":
            cells.append([f"{1e3 * v:.3f}" for v in x])       # the time in ms
        else:
            cells.append([f"{v:.6f}" if name == "t" else repr(float(v)) for v in x])
    rows = [sep.join(r) for r in zip(*cells)]
    if fmt == "decimal_comma":
        rows = [r.replace(".", ",") for r in rows]
    lines = [sep.join(names)]
    if fmt == "units_row":
        lines.append(sep.join("ms" if n == "t" else units[n] for n in names))
    if fmt == "comments":
        lines = ["# a logger's comment", "#", "# another, before the header", *lines]
    text = "\n".join([*lines, *rows]) + "\n"
    return ("\ufeff" + text if fmt == "bom" else text), (".csv.gz" if fmt == "gzip"
                                                          else ".csv")


def _write(folder: Path, name: str, cols, units, fmt: str) -> Path:
    text, suffix = _text(cols, units, fmt)
    path = folder / f"{name}_{fmt}{suffix}"
    data = text.encode("utf-8")
    path.write_bytes(gzip.compress(data, mtime=0) if suffix.endswith(".gz") else data)
    return path


def _json(argv: list, capsys) -> tuple[int, dict, str]:
    code = main([str(a) for a in argv] + ["--json"])
    cap = capsys.readouterr()
    return code, json.loads(cap.out), cap.err


def _numbers(d: dict, keys: tuple[str, ...]) -> np.ndarray:
    out = []
    for k in keys:
        v = d[k]
        if isinstance(v, list) and v and isinstance(v[0], dict):
            out += [x["value"] for x in v] + [x["hi"] for x in v]
        else:
            out += list(np.ravel(v))
    return np.array(out, dtype=float)


def _named(err: str) -> str:
    """A refusal without its file and line (a comment or units row moves the line)."""
    err = err.split(": ", 2)[-1] if err.startswith("error: ") else err
    return re.sub(r"line \d+, ", "", err.split(".csv", 1)[-1])


# The three commands' records ------------------------------------------------------------
@pytest.fixture(scope="module")
def gc_cols():
    r = gc.simulate_record(P, 20.0, seed=4701).record
    return {"t": np.round(r.t, 6), "angle_sensor": r.angle_sensor,
            "inclinometer_y": r.inclinometer_y, "inclinometer_z": r.inclinometer_z}


GC_UNITS = {"angle_sensor": "rad", "inclinometer_y": "m/s^2", "inclinometer_z": "m/s^2"}


@pytest.fixture(scope="module")
def rsf_cols():
    flight = rsf.simulate_flight(rsf.SimulationConfig(duration=5.0, sample_rate=1000.0),
                                 seed=4702)
    r = rsf.record_from_simulation(flight)
    return {"t": np.round(r.t, 6), "sins_increment": r.sins_increment,
            "gs_angle": r.gs_angle}


RSF_UNITS = {"sins_increment": "rad", "gs_angle": "rad"}


@pytest.fixture(scope="module")
def rate_cols():
    rng = np.random.default_rng(4703)
    n, dt = 4096, 0.01
    return {"t": np.round(np.arange(n) * dt, 6),
            "rate": 1e-3 * rng.standard_normal(n) + 1e-5 * np.cumsum(rng.standard_normal(n))}


RATE_UNITS = {"rate": "rad/s"}

COMMANDS = {
    "gc": (["calibrate", "gc", "--latitude", "paper"], ("omega_gc", "omega_gc_std")),
    "rsf": (["calibrate", "rsf", "--period", "1"],
            ("eps1_hat", "eps1_hat_mean", "eps1_hat_mean_std")),
    "allan": (["allan"], ("adev", "adev_hi", "noise_terms")),
}


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_every_format_gives_the_plain_csvs_numbers(command, gc_cols, rsf_cols, rate_cols,
                                                   tmp_path, capsys):
    cols, units = {"gc": (gc_cols, GC_UNITS), "rsf": (rsf_cols, RSF_UNITS),
                   "allan": (rate_cols, RATE_UNITS)}[command]
    argv, keys = COMMANDS[command]
    got = {}
    for fmt in FORMATS:
        path = _write(tmp_path, command, cols, units, fmt)
        code, d, err = _json([*argv[:2], path, *argv[2:], *_origin(command, fmt, cols)]
                             if command != "allan" else [*argv, path], capsys)
        assert code == 0, (fmt, err)
        got[fmt] = _numbers(d, keys)
    ref = got["plain"]
    for fmt in FORMATS[1:]:
        np.testing.assert_allclose(got[fmt], ref, rtol=1e-12, atol=0, err_msg=fmt)
    # the plain CSV's numbers are the library's on the arrays themselves
    if command == "allan":
        s = allan_series(cols["rate"], 100.0)
        lib = np.concatenate([s.adev, s.hi, [x.value for x in noise_terms(s)],
                              [x.hi for x in noise_terms(s)]])
    elif command == "gc":
        rec = gc.GCRecord(t=cols["t"], angle_sensor=cols["angle_sensor"],
                          inclinometer_y=cols["inclinometer_y"],
                          inclinometer_z=cols["inclinometer_z"])
        res = gc.calibrate(rec, _gc_params(cols["t"]))
        lib = np.array([res.omega_gc, res.omega_gc_std])
    else:
        res = rsf.calibrate(rsf.RSFRecord(t=cols["t"], sins_increment=cols["sins_increment"],
                                          gs_angle=cols["gs_angle"]), 1.0)
        lib = np.asarray(res.eps1_hat)
    np.testing.assert_allclose(ref[:lib.size], lib, rtol=1e-9, atol=1e-15)
    # power: values perturbed by 1e-9 (relative) are told apart at this tolerance
    nudged = {k: (v if k == "t" else v * (1 + 1e-9)) for k, v in cols.items()}
    path = _write(tmp_path, command + "_nudged", nudged, units, "plain")
    _, d, _ = _json([*argv[:2], path, *argv[2:]] if command != "allan" else [*argv, path],
                    capsys)
    assert not np.allclose(_numbers(d, keys), ref, rtol=1e-12, atol=0)


def _origin(command: str, fmt: str, cols: dict) -> list[str]:
    """ISO stamps are taken relative to the first row; a GC record's first row is one step
    after the switch-off (t = dt), which ``--t0 -dt`` states."""
    if command == "gc" and fmt == "iso_time":
        return ["--t0", repr(-float(cols["t"][0]))]
    return []


def _gc_params(t: np.ndarray) -> gc.GyrocompassParams:
    """The parameters ``calibrate gc`` runs with: the command's default priors, dt the
    record's median step."""
    from gyrolib.cli import constants

    return gc.GyrocompassParams(
        dt=float(f"{float(np.median(np.diff(t))):.9g}"),
        sigma_hf_scale=constants.DEFAULT_SCALE_TOLERANCE,
        sigma_as_offset=constants.DEFAULT_OFFSET_PRIOR_ARCSEC * 0.485e-5,
        sigma_incl_bias=constants.DEFAULT_INCL_BIAS_PRIOR_MG * 1e-3 * 9.80665,
        sigma_clock=constants.DEFAULT_CLOCK_TOLERANCE)


@pytest.mark.parametrize("command", ["gc", "allan"])
def test_every_format_gives_the_same_named_refusal(command, gc_cols, rate_cols, tmp_path,
                                                   capsys):
    """A GC record whose angle is in degrees, and a rate log whose time is in ms (no unit
    stated): each format is refused naming the same column and option."""
    if command == "gc":
        cols = dict(gc_cols, angle_sensor=np.degrees(gc_cols["angle_sensor"]))
        units, argv, want = GC_UNITS, ["calibrate", "gc", "--latitude", "paper"], \
            "--angle-unit deg"
    else:
        cols = dict(rate_cols, t=rate_cols["t"] * 1e3)
        units, argv, want = RATE_UNITS, ["allan"], "--time-unit ms"
    seen = set()
    for fmt in FORMATS:
        if fmt == "units_row":     # it states the unit: the refusal is then not due
            continue
        path = _write(tmp_path, command + "_bad", cols, units, fmt)
        code = main([*argv[:2], str(path), *argv[2:], *_origin(command, fmt, cols)]
                    if command == "gc" else [*argv, str(path)])
        err = capsys.readouterr().err
        assert code == 2 and err.count("\n") == 1 and want in err, (fmt, err)
        seen.add(_named(err))
    assert len(seen) == 1, seen
