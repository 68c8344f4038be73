"""``python -m gyrolib calibrate`` on the files loggers really write, and outputs that never
destroy data: each case with its exit status, its one-line message, what is
written and what is kept.  GC records are the first 20 s of data/gc_record.csv.gz; RSF
records a 20 s simulated flight (seed 27)."""

from __future__ import annotations

import csv
import gzip
import json
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from gyrolib import records, rsf
from gyrolib.cli import main

ROOT = Path(__file__).resolve().parents[2]
SAMPLE = ROOT / "data" / "gc_record.csv.gz"


def _run(argv, capsys):
    code = main([str(a) for a in argv])
    out = capsys.readouterr()
    return code, out.out, out.err


def _rows(path: Path) -> list[dict]:
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


@pytest.fixture(scope="module")
def gc_lines():
    """Header comments, header and the first 20 s of rows of the sample GC record."""
    lines = gzip.open(SAMPLE, "rt").read().splitlines()
    h = next(i for i, ln in enumerate(lines) if not ln.startswith("#"))
    return lines[:h], lines[h], lines[h + 1:h + 1 + 20000]


def _write(path: Path, comments, header, rows, *, sep=",", nl="\n", bom=False) -> Path:
    text = nl.join([*comments, header.replace(",", sep),
                    *(r.replace(",", sep) for r in rows)]) + nl
    path.write_bytes((b"\xef\xbb\xbf" if bom else b"") + text.encode())
    return path


@pytest.fixture(scope="module")
def gc_files(gc_lines, tmp_path_factory):
    comments, header, rows = gc_lines
    d = tmp_path_factory.mktemp("gcio")
    epoch, zero = [], []
    for r in rows:
        f = r.split(",")
        t = float(f[0])
        f[0] = f"{1732456789 + t:.3f}"      # a Unix-time logger clock
        epoch.append(",".join(f))
        f[0] = f"{t - 0.001:.3f}"           # the same, relative to its first row
        zero.append(",".join(f))
    return {"good": _write(d / "good.csv", comments, header, rows),
            "zero": _write(d / "zero.csv", comments, header, zero),
            "good2": _write(d / "good2.csv", comments, header, rows[:15000]),
            "epoch": _write(d / "epoch.csv", comments, header, epoch),
            "dir": d}


def _omega(out: str) -> dict:
    return json.loads(out.splitlines()[0])


# Logger timestamps -------------------------------------------------------------------------
def test_epoch_file_in_a_batch_with_good_files_and_two_workers(gc_files, capsys, tmp_path):
    """Unix-time stamps (1.7e9 s) in a batch with two good files and --workers 2: exit 0,
    three rows, the epoch file's estimate that of the same record with its first row at
    t = 0 (to 1e-9), its row and text saying the times were taken relative to the first
    row."""
    summary = tmp_path / "s.csv"
    files = [gc_files["zero"], gc_files["epoch"], gc_files["good2"]]
    code, out, err = _run(["calibrate", "gc", *files, "--summary", summary, "--workers", "2"],
                          capsys)
    assert code == 0 and err == ""
    rows = _rows(summary)
    assert [r["file"] for r in rows] == [str(f) for f in files]
    assert [r["status"] for r in rows] == ["ok", "ok", "ok"]
    assert float(rows[1]["estimate"]) == pytest.approx(float(rows[0]["estimate"]), rel=1e-9)
    assert float(rows[1]["sigma"]) == pytest.approx(float(rows[0]["sigma"]), rel=1e-9)
    assert "relative to t0 = 1732456789.001 s" in rows[1]["notes"]
    assert "absolute clock" in out and out.count("paper GC calibration of") == 3
    assert rows[0]["notes"] == "" or "relative" not in rows[0]["notes"]
    code, out, _ = _run(["calibrate", "gc", gc_files["epoch"], "--json"], capsys)
    data = json.loads(out)
    assert data["time_base"]["t_offset_source"] == "first row"
    assert data["time_base"]["t_offset_exact"] == "1732456789.001"


def test_t0_and_columns_options(gc_files, gc_lines, capsys, tmp_path):
    """--t0 S subtracts S (the first row then at 0.001 s, as in the relative file);
    --columns maps other header names; a bad --columns is a usage error (exit 2, one line)."""
    code, out, _ = _run(["calibrate", "gc", gc_files["good"], "--json"], capsys)
    ref = _omega(out)
    code, out, _ = _run(["calibrate", "gc", gc_files["epoch"], "--t0", "1732456789",
                         "--json"], capsys)
    got = _omega(out)
    assert code == 0 and got["omega_gc"] == pytest.approx(ref["omega_gc"], rel=1e-9)
    assert got["time_base"]["t_offset_source"] == "t0"
    comments, _header, rows = gc_lines
    other = _write(tmp_path / "other.csv", comments, "time,gyro,iy,iz", rows)
    code, out, _ = _run(["calibrate", "gc", other, "--json", "--columns",
                         "t=time,angle_sensor=gyro,inclinometer_y=iy,inclinometer_z=iz"],
                        capsys)
    assert code == 0 and _omega(out)["omega_gc"] == pytest.approx(ref["omega_gc"], rel=1e-12)
    code, out, err = _run(["calibrate", "gc", other], capsys)
    assert code == 2 and out == "" and err.count("\n") == 1
    assert "--columns t=NAME" in err
    code, out, err = _run(["calibrate", "gc", other, "--columns", "t:time"], capsys)
    assert code == 2 and err.count("\n") == 1 and "--columns" in err and "NAME=HEADER" in err


def test_timestamp_jitter_is_named_with_its_size_and_effect(gc_lines, capsys, tmp_path):
    """Stamps jittered by ±0.2 ms (uniform, seed 3) around a regular 1 ms grid: a note
    names the jitter with its size (the steps' σ, within 10 % of the uniform's √(2/3)·0.2
    ms) and what it does to the fit test; the clean file has no such note.  On the record's
    first 2 s (2000 steps: the σ's standard error is 1.6 %, the 10 % six of them; 2000
    jittered rows cost a tenth of the 20 s, 0.3 CPU-s a run)."""
    comments, header, rows = gc_lines
    rows = rows[:2000]
    rng = np.random.default_rng(3)
    jit = []
    for r in rows:
        f = r.split(",")
        f[0] = f"{float(f[0]) + rng.uniform(-2e-4, 2e-4):.7f}"
        jit.append(",".join(f))
    path = _write(tmp_path / "jitter.csv", comments, header, jit)
    _, out, _ = _run(["calibrate", "gc", path, "--json"], capsys)
    data = _omega(out)
    j = data["timestamp_jitter"]
    assert j["step_departure_std_s"] == pytest.approx(math.sqrt(2 / 3) * 2e-4, rel=0.1)
    note = next(n for n in data["notes"] if n.startswith("time-stamp jitter"))
    assert "fit test" in note and "NIS" in note
    _, out, _ = _run(["calibrate", "gc", tmp_path / "jitter.csv"], capsys)
    assert "note: time-stamp jitter" in out
    clean = _write(tmp_path / "clean.csv", comments, header, rows)
    _code, out, _ = _run(["calibrate", "gc", clean, "--json"], capsys)
    assert "timestamp_jitter" not in _omega(out)


# Files as loggers write them ---------------------------------------------------------------
@pytest.mark.parametrize(("kw", "name"), [({"bom": True}, "bom"), ({"nl": "\r\n"}, "crlf"),
                                          ({"sep": "\t"}, "tabs"), ({"sep": ";"}, "semicolons"),
                                          ({"bom": True, "nl": "\r\n", "sep": "\t"}, "all")])
def test_bom_crlf_tabs_semicolons_give_the_plain_estimate(gc_files, gc_lines, capsys,
                                                          tmp_path, kw, name):
    comments, header, rows = gc_lines
    code, out, _ = _run(["calibrate", "gc", gc_files["good"], "--json"], capsys)
    ref = _omega(out)
    path = _write(tmp_path / f"{name}.csv", comments, header, rows, **kw)
    code, out, err = _run(["calibrate", "gc", path, "--json"], capsys)
    assert code == 0 and err == ""
    assert _omega(out)["omega_gc"] == pytest.approx(ref["omega_gc"], rel=1e-12)


def test_quoted_cells_bad_byte_and_bad_cell(gc_lines, capsys, tmp_path):
    """Quoted cells (one holding a comma, in an extra column) read; a byte that is not
    UTF-8 and a non-numeric cell: exit 2, one line naming file, line (and column)."""
    comments, header, rows = gc_lines
    quoted = [f'"{r.split(",")[0]}",' + ",".join(r.split(",")[1:]) + ',"a, b"' for r in rows]
    path = _write(tmp_path / "q.csv", comments, header + ",note", quoted)
    code, out, err = _run(["calibrate", "gc", path, "--json"], capsys)
    assert code == 0 and _omega(out)["rows"] == 20000
    bad = list(rows)
    bad[9000] = bad[9000].replace(",", ",\xff", 1)
    path = tmp_path / "byte.csv"
    path.write_bytes("\n".join([*comments, header, *bad]).encode("utf-8", "surrogateescape")
                     .replace("\xff".encode(), b"\xff") + b"\n")
    code, out, err = _run(["calibrate", "gc", path], capsys)
    line = len(comments) + 1 + 9001
    assert code == 2 and out == "" and err.count("\n") == 1 and "Traceback" not in err
    assert f"{path}: line {line}: not UTF-8 text: byte 0xff" in err
    bad = list(rows)
    f = bad[12000].split(",")
    f[2] = "1,5e-3"
    bad[12000] = ",".join(f[:2]) + ',"1,5e-3",' + f[3]
    path = _write(tmp_path / "cell.csv", comments, header, bad)
    code, out, err = _run(["calibrate", "gc", path], capsys)
    assert code == 2 and err.count("\n") == 1
    assert f"line {len(comments) + 1 + 12001}, column 'inclinometer_y': expected a number" in err


# Outputs that never destroy data -------------------------------------------------------------
def test_summary_onto_an_input_is_refused(gc_files, capsys):
    """--summary naming one of the inputs: exit 2, one line, the log byte for byte as it
    was, nothing else written (not even a temporary file)."""
    d = gc_files["dir"]
    before = {p.name: p.read_bytes() for p in d.iterdir()}
    for target in (gc_files["good"], d / "." / gc_files["good"].name):
        code, out, err = _run(["calibrate", "gc", gc_files["good"], gc_files["good2"],
                               "--summary", target], capsys)
        assert code == 2 and out == "" and err.count("\n") == 1
        assert f"--summary {target} is also an input file" in err
    assert {p.name: p.read_bytes() for p in d.iterdir()} == before
    code, out, err = _run(["calibrate", "gc", gc_files["good"], "--plot",
                           gc_files["good"].with_suffix(".png"), "--allan",
                           gc_files["good"].with_suffix(".png")], capsys)
    assert code == 2 and "name the same file" in err
    assert {p.name: p.read_bytes() for p in d.iterdir()} == before


def test_existing_output_replaced_only_when_complete(gc_files, capsys, tmp_path):
    """An existing summary is replaced by the complete new one (same permissions); a run that
    fails at the door leaves it untouched; --no-clobber refuses (exit 2) and keeps it."""
    summary = tmp_path / "s.csv"
    summary.write_text("old\n")
    summary.chmod(0o640)
    code, _, err = _run(["calibrate", "gc", gc_files["good2"], "--summary", summary,
                         "--no-clobber"], capsys)
    assert code == 2 and "exists and --no-clobber" in err and summary.read_text() == "old\n"
    code, _, err = _run(["calibrate", "gc", gc_files["good2"], "--summary", summary,
                         "--gate", "2"], capsys)
    assert code == 2 and summary.read_text() == "old\n"
    code, _, _ = _run(["calibrate", "gc", gc_files["good2"], "--summary", summary], capsys)
    assert code == 0 and [r["status"] for r in _rows(summary)] == ["ok"]
    assert summary.stat().st_mode & 0o777 == 0o640
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.csv"]     # no temporary left


def test_duplicates_calibrated_once_with_a_note(gc_files, capsys, tmp_path):
    summary = tmp_path / "s.csv"
    g = gc_files["good2"]
    code, out, err = _run(["calibrate", "gc", g, g.parent / "." / g.name, g, "--summary",
                           summary], capsys)
    assert code == 0 and len(_rows(summary)) == 1
    assert out.count("paper GC calibration of") == 1
    assert err.count("\n") == 2 and "is listed more than once" in err and "calibrated once" in err


def test_a_failing_file_is_its_own_error_row_with_workers(gc_files, capsys, tmp_path,
                                                          monkeypatch):
    """A file whose calibration fails inside a worker (here: MemoryError, as a time column
    the size of Unix time made it) becomes its own row with status error and the reason;
    the other rows are kept; exit 2."""
    import gyrolib.cli.calibrate_gc as cc

    real = cc.run_file

    def failing(file, o):
        if Path(file).name == "boom.csv":
            raise MemoryError("Unable to allocate 25.0 TiB")
        return real(file, o)

    monkeypatch.setattr(cc, "run_file", failing)       # the workers are forked after
    boom = tmp_path / "boom.csv"
    boom.write_bytes(gc_files["good2"].read_bytes())
    summary = tmp_path / "s.csv"
    code, out, err = _run(["calibrate", "gc", gc_files["good"], boom, gc_files["good2"],
                           "--summary", summary, "--workers", "2", "--json"], capsys)
    rows = _rows(summary)
    assert code == 2 and [r["status"] for r in rows] == ["ok", "error", "ok"]
    assert "ran out of memory" in rows[1]["reason"] and rows[1]["estimate"] == ""
    assert err.count("\n") == 1 and "boom.csv" in err
    lines = [json.loads(x) for x in out.splitlines()]
    assert lines[1]["status"] == "error" and lines[0]["valid"] and lines[2]["valid"]


def _wait_for(proc, text: str, timeout: float = 120.0) -> str:
    seen = ""
    t_end = time.monotonic() + timeout
    while text not in seen:
        line = proc.stdout.readline()
        if not line or time.monotonic() > t_end:
            break
        seen += line
    return seen


def _sigint_state(pid) -> str:
    """Whether SIGINT is blocked or ignored in a process (Linux ``/proc``; bit 1 of the
    ``SigBlk`` and ``SigIgn`` masks), for the failure message."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return "unknown"
    masks = dict(line.split(":\t", 1) for line in status.splitlines() if ":\t" in line)
    return ", ".join(f"{k} {'yes' if int(masks[k], 16) & 2 else 'no'}"
                     for k in ("SigBlk", "SigIgn") if k in masks)


def _sigint_deliverable() -> None:
    """In the command's process before it starts: SIGINT at its default and not blocked
    (with :data:`_DEFAULT_SIGINT_MAIN`, which installs Python's handler whatever the
    disposition: a blocked mask, which a thread that spawns a helper process holds meanwhile,
    is inherited too)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})


#: ``python -m gyrolib ARGS`` with SIGINT's default Python handler, whatever the parent had.
_DEFAULT_SIGINT_MAIN = ("import runpy, signal, sys; "
                        "signal.signal(signal.SIGINT, signal.default_int_handler); "
                        "sys.argv[0] = 'gyrolib'; runpy.run_module('gyrolib', run_name='__main__')")


def test_a_child_inherits_an_ignored_sigint_and_the_wrapper_restores_it():
    """Why the Ctrl-C test starts its command through :data:`_DEFAULT_SIGINT_MAIN`: a
    parent that ignores SIGINT passes that on (the child's handler is SIG_IGN, power), and
    the wrapper's child has Python's handler all the same."""
    probe = "import signal; print(signal.getsignal(signal.SIGINT) is signal.SIG_IGN)"
    old = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        plain = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True)
        wrapped = subprocess.run([sys.executable, "-c", _DEFAULT_SIGINT_MAIN.replace(
            "runpy.run_module('gyrolib', run_name='__main__')", probe)], capture_output=True,
            text=True)
    finally:
        signal.signal(signal.SIGINT, old)
    assert plain.stdout.strip() == "True" and wrapped.stdout.strip() == "False"


@pytest.mark.parametrize("workers", ["1", "2"])
def test_ctrl_c_during_a_batch(gc_files, tmp_path, workers):
    """SIGINT to a batch of 60 files after the first result: exit 130, one line on stderr
    (no traceback, also from the workers), the existing summary untouched, no partial or
    temporary file, every input as it was.  (60 files, about 10 s of work: under a heavy load
    a batch of 12 could end before the test had read its first result and sent the signal.)"""
    files = []
    for k in range(60):
        p = tmp_path / f"log{k:02d}.csv"
        p.write_bytes(gc_files["good"].read_bytes())
        files.append(p)
    summary = tmp_path / "summary.csv"
    summary.write_text("kept\n")
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    inherited = _sigint_state("self")   # what a child of this test process would inherit
    # The command as a terminal starts it: with Python's own Ctrl-C handler.  A child inherits
    # an ignored SIGINT (POSIX), and Python then installs none.  A test session started as an
    # asynchronous command by a shell without job control (`python3 tasks.py test > log &`
    # in a script, nohup) has SIGINT and SIGQUIT ignored from its start (POSIX, XCU 2.11;
    # SigIgn 0x...1006 with Python's SIGPIPE and SIGXFSZ): no call of gyrolib's or of a
    # library's ignores them (checked per test over this file, SigIgn 0x1001000 throughout
    # when started with job control).  Without the wrapper, the command then ran its 60
    # files to the end and exited 0.
    proc = subprocess.Popen([sys.executable, "-c", _DEFAULT_SIGINT_MAIN, "calibrate", "gc",
                             *map(str, files), "--summary", str(summary), "--workers", workers],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT,
                            env=env, preexec_fn=_sigint_deliverable)
    try:
        seen = _wait_for(proc, "paper GC calibration of")
        assert "paper GC calibration of" in seen
        child = _sigint_state(proc.pid)
        proc.send_signal(signal.SIGINT)
        _out, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130, (f"{err!r}; SIGINT in the command: {child}; in this test "
                                    f"process: {inherited}")
    assert err.count("\n") == 1 and err.startswith("interrupted (Ctrl-C): ")
    assert "Traceback" not in err and "of 60 file(s) calibrated" in err
    assert summary.read_text() == "kept\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        [p.name for p in files] + ["summary.csv"])
    assert all(p.read_bytes() == gc_files["good"].read_bytes() for p in files)


def test_version(capsys):
    import gyrolib

    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0 and capsys.readouterr().out == f"gyrolib {gyrolib.__version__}\n"
    with pytest.raises(SystemExit) as exc:
        main(["calibrate", "rsf", "--version"])
    assert exc.value.code == 0 and gyrolib.__version__ in capsys.readouterr().out


# The drift in the field's units ------------------------------------------------------------
def test_drift_in_deg_per_hour_and_standard_arcsec(gc_files, capsys):
    """°/h and standard ″/s (equal by definition), the paper's ″/s (0.485e-5 rad), SI: the
    same drift, converted by hand here; the JSON names its units."""
    _, out, _ = _run(["calibrate", "gc", gc_files["good"], "--json"], capsys)
    d = _omega(out)
    w = d["omega_gc"]
    by_hand = {"deg/h": w * 180 / math.pi * 3600, "arcsec/s": w * 648000 / math.pi,
               "arcsec_paper/s": w / 0.485e-5, "rad/s": w}
    for unit, x in by_hand.items():
        assert d["omega_gc_in"][unit]["estimate"] == pytest.approx(x, rel=1e-12)
    assert d["units"]["omega_gc"] == "rad/s" and "0.485" in d["unit_conversion"] + "0.485"
    _code, out, _ = _run(["calibrate", "gc", gc_files["good"]], capsys)
    line = next(ln for ln in out.splitlines() if "omega_gc =" in ln)
    assert "deg/h" in line and "arcsec/s (standard)" in line and "paper's arcsec" in line
    assert f"{by_hand['deg/h']:.4g} ± " in line


# RSF angles through the command line -------------------------------------------------------
@pytest.fixture(scope="module")
def rsf_dir(tmp_path_factory):
    cfg = rsf.SimulationConfig(duration=20.0, sample_rate=1000.0)
    rec = rsf.record_from_simulation(rsf.simulate_flight(cfg, seed=27))
    d = tmp_path_factory.mktemp("rsfio")

    def write(name, gs):
        return records.write_csv(d / name, {"t": rec.t, "sins_increment": rec.sins_increment,
                                            "gs_angle": gs}, fmt="%.17g")

    k = int(np.searchsorted(rec.t, 12.3456))
    slip = rec.gs_angle.copy()
    slip[k:] += 2 * math.pi
    quarter = rec.gs_angle.copy()
    quarter[k:] += math.pi / 2
    keep = (rec.t < 8.0) | (rec.t >= 10.0)           # a 2 s gap
    gap = records.write_csv(d / "gap.csv", {"t": rec.t[keep],
                                            "sins_increment": rec.sins_increment[keep],
                                            "gs_angle": rec.gs_angle[keep]}, fmt="%.17g")
    sign = np.where((rec.t // 2.5) % 2 == 0, 1.0, -1.0)   # the roll reverses every 2.5 s
    gs_inc = np.diff(rec.gs_angle, prepend=rec.gs_angle[0])
    rev = records.write_csv(d / "reverse.csv", {"t": rec.t,
                                                "sins_increment": rec.sins_increment * sign,
                                                "gs_angle": np.cumsum(gs_inc * sign)},
                            fmt="%.17g")
    return {"good": write("good.csv", rec.gs_angle), "gap": gap, "reverse": rev,
            "wrapped": write("wrapped.csv", np.mod(rec.gs_angle, 2 * math.pi)),
            "slip": write("slip.csv", slip), "quarter": write("quarter.csv", quarter),
            "t_slip": float(rec.t[k]), "eps1": cfg.sins.eps1}


def test_rsf_wrapped_and_2pi_slip_through_the_command_line(rsf_dir, capsys):
    """A wrapped gs_angle: exit 0, the good file's ε̂1, a note with "wrapped"; a 2π slip:
    exit 0, the same ε̂1, a note naming the slip and its time; --slips refuse: exit 2 with
    one line naming it; a quarter-turn slip: exit 2, one line, "quarter turn"."""
    ref = json.loads(_run(["calibrate", "rsf", rsf_dir["good"], "--period", "1", "--json"],
                          capsys)[1])
    for name, word in (("wrapped", "wrapped into [0, 2π)"), ("slip", "slips a whole turn")):
        code, out, err = _run(["calibrate", "rsf", rsf_dir[name], "--period", "1", "--json"],
                              capsys)
        got = json.loads(out)
        assert code == 0 and err == ""
        assert got["eps1_hat_mean"] == pytest.approx(ref["eps1_hat_mean"], abs=1e-9)
        assert any(word in n for n in got["notes"])
    code, out, _ = _run(["calibrate", "rsf", rsf_dir["slip"], "--period", "1"], capsys)
    assert f"at t = {rsf_dir['t_slip']:.6g} s): repaired" in out
    code, out, err = _run(["calibrate", "rsf", rsf_dir["slip"], "--period", "1", "--slips",
                           "refuse"], capsys)
    assert code == 2 and out == "" and err.count("\n") == 1 and "slips a whole turn" in err
    code, out, err = _run(["calibrate", "rsf", rsf_dir["quarter"], "--period", "1"], capsys)
    assert code == 2 and out == "" and err.count("\n") == 1 and "quarter turn" in err
    # ε̂1 against the truth ε1/(1 + ε1) within 4 standard errors of the mean (an upper
    # bound here), and the text separates the spread from the standard error
    st = ref["eps1_hat_sem"]
    assert abs(ref["eps1_hat_mean"] - rsf_dir["eps1"] / (1 + rsf_dir["eps1"])) < 4 * st
    code, out, _ = _run(["calibrate", "rsf", rsf_dir["good"], "--period", "1"], capsys)
    assert "per-interval spread (SD)" in out and "standard error of the mean" in out
    assert "mean |roll rate|" in out


def test_rsf_gap_named_and_reversal_reported_with_abs_rate(rsf_dir, capsys):
    """A 2 s gap: exit 0, named as a gap with its length and time (not blamed on units);
    a roll that reverses every 2.5 s: exit 0, mean |roll rate| the flight's 900 deg/s (not
    its signed mean), a note that the rate reverses, the reversing intervals left out."""
    code, out, err = _run(["calibrate", "rsf", rsf_dir["gap"], "--period", "1"], capsys)
    assert code == 0 and err == ""
    assert "note: 1 gap(s) in the time stamps (2.001 s after t = 7.999 s" in out
    assert "degrees" not in out and "units" not in out
    code, out, err = _run(["calibrate", "rsf", rsf_dir["reverse"], "--period", "1",
                           "--json"], capsys)
    data = json.loads(out)
    assert code == 0 and err == ""
    assert math.degrees(data["mean_abs_rate"]) == pytest.approx(900.0, rel=0.01)
    assert abs(math.degrees(float(np.mean(data["rate"])))) < 200.0
    assert any("the roll rate reverses" in n for n in data["notes"])
    assert sum(data["reversal"]) == 4                   # t = 2.5, 7.5, 12.5, 17.5 s
    code, out, _ = _run(["calibrate", "rsf", rsf_dir["reverse"], "--period", "1"], capsys)
    assert f"mean |roll rate| {math.degrees(data['mean_abs_rate']):.5g} deg/s" in out
    assert "note: the roll rate reverses" in out


def test_a_batch_on_a_dask_scheduler_gives_the_local_rows(gc_files, capsys, tmp_path):
    """``--scheduler ADDR``: the files calibrated on a Dask cluster this test starts give the
    rows of the run in this process (to 1e-12 relative: the same code on the same machine);
    with ``--workers`` too, or a scheduler nobody listens at, status 2 and one line."""
    distributed = pytest.importorskip("distributed")
    files = [gc_files["good2"], gc_files["zero"]]
    here, there = tmp_path / "here.csv", tmp_path / "there.csv"
    assert _run(["calibrate", "gc", *files, "--summary", here], capsys)[0] == 0
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=":0") as cluster:
        code, out, err = _run(["calibrate", "gc", *files, "--summary", there,
                               "--scheduler", cluster.scheduler_address], capsys)
        assert code == 0 and err == "" and out.count("paper GC calibration of") == 2
        code, _, err = _run(["calibrate", "gc", *files, "--scheduler",
                             cluster.scheduler_address, "--workers", "2"], capsys)
        assert code == 2 and err.count("\n") == 1 and "--scheduler and --workers" in err
    a, b = _rows(here), _rows(there)
    assert [r["file"] for r in a] == [r["file"] for r in b] == [str(f) for f in files]
    for r, s in zip(a, b, strict=True):
        assert r["status"] == s["status"] == "ok"
        assert float(s["estimate"]) == pytest.approx(float(r["estimate"]), rel=1e-12)
        assert float(s["sigma"]) == pytest.approx(float(r["sigma"]), rel=1e-12)
    code, _, err = _run(["calibrate", "gc", *files, "--scheduler", "tcp://127.0.0.1:9"],
                        capsys)
    assert code == 2 and err.count("\n") == 1 and "cannot reach the Dask scheduler" in err
