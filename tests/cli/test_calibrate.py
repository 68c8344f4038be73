"""``python -m gyrolib calibrate gc|rsf``: acceptance on records simulated here (seeds
independent of data/), the JSON and plot outputs, and every bad-input case (exit 2, one
line on stderr naming the file and the column or row, nothing written)."""

from __future__ import annotations

import dataclasses
import gzip
import json
import math
import re
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pytest

from gyrolib import gc, records, rsf
from gyrolib.cli import main
from gyrolib.units import from_si

#: Records of this file are simulated with paper GC's Earth rate (no '# latitude_deg:' line):
#: the command needs the latitude stated, so it is assumed explicitly.
GC_PAPER = ("calibrate", "gc", "--latitude", "paper")

P = gc.GyrocompassParams()
GC_HEADER = "t,angle_sensor,inclinometer_y,inclinometer_z"


def _run(argv, capsys):
    code = main(argv)
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.fixture(scope="module")
def gc_file(tmp_path_factory):
    """Seed 4242, 100 s: a 2 s gap, NaNs and a burst of angle-sensor outliers."""
    sim = gc.simulate_record(P, 100.0, seed=4242)
    r = sim.record
    rng = np.random.default_rng(4243)
    a, y, z = (np.array(c) for c in (r.angle_sensor, r.inclinometer_y, r.inclinometer_z))
    burst = np.nonzero(r.t > 55.0)[0][:40]
    a[burst] += 8e-4 * rng.choice([-1.0, 1.0], burst.size)
    y[rng.choice(r.n, 60, replace=False)] = np.nan
    a[rng.choice(r.n, 60, replace=False)] = np.nan
    keep = ~((r.t > 25.0) & (r.t <= 27.0))
    path = tmp_path_factory.mktemp("gc") / "run.csv.gz"
    records.write_csv(path, {"t": r.t[keep], "angle_sensor": a[keep],
                             "inclinometer_y": y[keep], "inclinometer_z": z[keep]},
                      fmt=["%.3f", "%.12g", "%.12g", "%.12g"])
    return path, sim, r.t[burst]


def test_gc_json_acceptance(gc_file, capsys):
    path, sim, burst_t = gc_file
    code, out, err = _run([*GC_PAPER, str(path), "--json"], capsys)
    assert code == 0 and err == ""
    d = json.loads(out)
    assert abs(d["omega_gc"] - sim.omega_gc) <= 3.0 * d["omega_gc_std"]
    sigma_cov = float(gc.covariance_analysis(P, 100.0, store_every=10**9).std("omega_gc")[-1])
    # the noise part of σ is the covariance analysis'; the instrument constants' priors (the
    # command's defaults) add the rest in quadrature, the scale part ≈ tolerance · Ω_h
    parts = d["omega_gc_std_parts"]
    assert parts["noise"] == pytest.approx(sigma_cov, rel=0.05)
    assert math.hypot(*parts.values()) == pytest.approx(d["omega_gc_std"], rel=1e-6)
    assert parts["scale"] == pytest.approx(1e-3 * P.Omega_h, rel=0.05)
    assert d["samples_rejected"] >= burst_t.size
    assert d["measurements"]["angle_sensor"]["rejected"] >= burst_t.size
    assert np.all(np.isin(np.round(burst_t, 3), np.round(d["rejected_t"], 3)))
    assert set(d["nis"]) == set(gc.MEASUREMENT_NAMES)
    # rows used and rows with a rejection are disjoint: with the 2000 rows of the gap they
    # make the 100000 rows of 100 s at 1 kHz (the missing cells leave their rows in use)
    assert d["samples_used"] + d["samples_rejected"] + 2000 == pytest.approx(100000, abs=10)
    counts = d["counts"]
    assert counts["used"] + counts["rejected"] + counts["empty"] == counts["rows"] == d["rows"]
    assert (counts["used"], counts["rejected"]) == (d["samples_used"], d["samples_rejected"])


def test_gc_summary_and_plot(gc_file, capsys, tmp_path):
    path, _, _ = gc_file
    png = tmp_path / "est.png"
    code, out, err = _run([*GC_PAPER, str(path), "--plot", str(png)], capsys)
    assert code == 0 and err == ""
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "arcsec/s" in out and "model fits" in out
    # the printed estimate is the JSON's, converted to the paper's arcsec/s
    _, js, _ = _run([*GC_PAPER, str(path), "--json"], capsys)
    val = float(from_si(json.loads(js)["omega_gc"], "arcsec_paper/s"))
    assert re.search(rf"= {val:.4g} ± \S+ arcsec/s \(paper's arcsec", out), out


@pytest.fixture(scope="module")
def rsf_file(tmp_path_factory):
    cfg = rsf.SimulationConfig(duration=60.0, sample_rate=1000.0)
    flight = rsf.simulate_flight(cfg, seed=9191)
    r = rsf.record_from_simulation(flight)
    path = tmp_path_factory.mktemp("rsf") / "flight.csv"
    records.write_csv(path, {"t": r.t, "sins_increment": r.sins_increment,
                             "gs_angle": r.gs_angle}, fmt=["%.3f", "%.12g", "%.15g"])
    return path, flight, cfg


def test_rsf_json_acceptance(rsf_file, capsys):
    path, flight, cfg = rsf_file
    code, out, err = _run(["calibrate", "rsf", str(path), "--period", "1", "--json"], capsys)
    assert code == 0 and err == ""
    d = json.loads(out)
    assert d["period"] == 1.0 and len(d["eps1_hat"]) == len(d["K"]) == 60
    eps1 = float(flight.eps1_sins[0])
    pred = rsf.predict_delta_k(cfg, 1.0)
    dk = np.array(d["K"]) * (1 + eps1) - 1
    assert np.all(np.abs(dk - pred.mean) <= 3.0 * pred.std)
    assert d["delta_k_predicted"]["std"] == pytest.approx(pred.std, rel=0.01)


def test_rsf_encoder_counts_and_plot(capsys, tmp_path):
    flight = rsf.simulate_flight(rsf.SimulationConfig(duration=5.0, sample_rate=1000.0), 5)
    e = rsf.record_from_simulation(flight, encoder=True)
    path = tmp_path / "enc.csv"
    records.write_csv(path, {"t": e.t, "sins_increment": e.sins_increment,
                             "encoder_counts": e.encoder_counts,
                             "gs_gyro_angle": e.gs_gyro_angle},
                      fmt=["%.3f", "%.12g", "%d", "%.15g"])
    png = tmp_path / "eps.png"
    code, out, err = _run(["calibrate", "rsf", str(path), "--period", "1",
                           "--counts-per-rev", "4000", "--json", "--plot", str(png)], capsys)
    assert code == 0 and err == ""
    ref = rsf.calibrate(rsf.record_from_simulation(flight), 1.0)
    np.testing.assert_allclose(json.loads(out)["eps1_hat"], ref.eps1_hat, atol=1e-9)
    assert png.read_bytes()[:4] == b"\x89PNG"


# Bad input -------------------------------------------------------------------------------
def _write(path: Path, text: str) -> Path:
    path.write_text(text)
    return path


GOOD_ROWS = "0.001,0,0,0\n0.002,0,0,0\n"

BAD_GC = {
    "missing column": ("t,angle_sensor,inclinometer_y\n0.001,0,0\n", "'inclinometer_z'"),
    "misnamed column": ("t,angle,inclinometer_y,inclinometer_z\n" + GOOD_ROWS,
                        "'angle_sensor'"),
    "non-numeric cell": (GC_HEADER + "\n0.001,0,0,0\n0.002,0,abc,0\n",
                         "line 3, column 'inclinometer_y'"),
    "time not increasing": (GC_HEADER + "\n0.002,0,0,0\n0.001,0,0,0\n", "line 3, column 't'"),
    "empty file": ("", "empty"),
    "comments only": ("# nothing\n# here\n", "empty"),
    "header only": (GC_HEADER + "\n", "no data rows"),
    "short row": (GC_HEADER + "\n0.001,0,0\n", "line 2"),
    "negative time": (GC_HEADER + "\n-0.001,0,0,0\n", "column 't'"),
    "missing time": (GC_HEADER + "\n,0,0,0\n", "line 2, column 't'"),
}


@pytest.mark.parametrize("case", sorted(BAD_GC))
def test_gc_bad_input(case, capsys, tmp_path):
    text, where = BAD_GC[case]
    path = _write(tmp_path / "bad.csv", text)
    png = tmp_path / "never.png"
    code, out, err = _run([*GC_PAPER, str(path), "--json", "--plot", str(png)],
                          capsys)
    assert code == 2
    assert json.loads(out)["status"] == "error"  # --json: an error object and not png.exists()
    assert err.count("\n") == 1 and err.endswith("\n")
    assert str(path) in err and where in err


def test_bad_binary_and_gzip(capsys, tmp_path):
    for name, data in (("x.csv", bytes(range(256)) * 4), ("x.csv.gz", b"not gzip at all")):
        path = tmp_path / name
        path.write_bytes(data)
        code, out, err = _run([*GC_PAPER, str(path)], capsys)
        assert code == 2 and out == "" and err.count("\n") == 1 and str(path) in err
    path = tmp_path / "ok.csv.gz"
    path.write_bytes(gzip.compress((GC_HEADER + "\n" + GOOD_ROWS).encode()))
    code, out, err = _run([*GC_PAPER, str(path), "--json"], capsys)
    # readable (not status 2); two samples are too few for a valid estimate to be required
    assert code in (0, 3) and json.loads(out)["rows"] == 2


def test_unknown_toml_field_and_missing_file(capsys, tmp_path):
    rec = _write(tmp_path / "ok.csv", GC_HEADER + "\n" + GOOD_ROWS)
    toml = _write(tmp_path / "p.toml", "C_as = 1e-13\nC_az = 2\n")
    code, out, err = _run([*GC_PAPER, str(rec), "--params", str(toml)], capsys)
    assert code == 2 and out == "" and err.count("\n") == 1
    assert str(toml) in err and "'C_az'" in err
    toml = _write(tmp_path / "r.toml", "[gs]\nmotor_rate_max = inf\n[sins]\nbogus = 1\n")
    rrec = _write(tmp_path / "r.csv", "t,sins_increment,gs_angle\n0,0,0\n0.5,1,1\n1,1,1\n")
    code, out, err = _run(["calibrate", "rsf", str(rrec), "--period", "0.5", "--params",
                           str(toml)], capsys)
    assert code == 2 and "'sins.bogus'" in err and str(toml) in err
    code, out, err = _run([*GC_PAPER, str(tmp_path / "nope.csv")], capsys)
    assert code == 2 and "no such file" in err and err.count("\n") == 1


def test_toml_overrides_apply(capsys, tmp_path):
    """TOML fields change the model: on a record simulated with modified parameters, σ
    follows the covariance analysis of those parameters, not the paper's."""
    changed = {"C_as": 100 * P.C_as, "sigma1_sq": 4 * P.sigma1_sq}
    p_changed = dataclasses.replace(P, **changed)
    r = gc.simulate_record(p_changed, 2.0, seed=3).record
    rec = tmp_path / "r.csv"
    records.write_csv(rec, {"t": r.t, "angle_sensor": r.angle_sensor,
                            "inclinometer_y": r.inclinometer_y,
                            "inclinometer_z": r.inclinometer_z})
    toml = _write(tmp_path / "p.toml", "".join(f"{k} = {v!r}\n" for k, v in changed.items()))
    code, b, _ = _run([*GC_PAPER, str(rec), "--json", "--params", str(toml)], capsys)
    assert code == 0
    sigma = float(gc.covariance_analysis(p_changed, 2.0, store_every=10**9).std("omega_gc")[-1])
    sigma_paper = float(gc.covariance_analysis(P, 2.0, store_every=10**9).std("omega_gc")[-1])
    assert json.loads(b)["omega_gc_std_parts"]["noise"] == pytest.approx(sigma, rel=0.01)
    assert sigma_paper < 0.95 * sigma


BAD_RSF = {
    "no gs column": ("t,sins_increment\n0,0\n0.01,1\n", ["--period", "0.01"], "gs_angle"),
    "counts without n": ("t,sins_increment,encoder_counts\n0,0,0\n0.01,1,5\n",
                         ["--period", "0.01"], "--counts-per-rev"),
    "counts out of range": ("t,sins_increment,encoder_counts\n0,0,0\n0.01,1,5000\n",
                            ["--period", "0.01", "--counts-per-rev", "4000"],
                            "column 'encoder_counts'"),
    "period too long": ("t,sins_increment,gs_angle\n0,0,0\n0.01,1,1\n", ["--period", "5"],
                        "--period"),
    "non-numeric": ("t,sins_increment,gs_angle\n0,0,0\n0.01,x,1\n", ["--period", "0.01"],
                    "line 3, column 'sins_increment'"),
}


@pytest.mark.parametrize("case", sorted(BAD_RSF))
def test_rsf_bad_input(case, capsys, tmp_path):
    text, extra, where = BAD_RSF[case]
    path = _write(tmp_path / "bad.csv", text)
    png = tmp_path / "never.png"
    code, out, err = _run(["calibrate", "rsf", str(path), *extra, "--json", "--plot",
                           str(png)], capsys)
    assert code == 2 and json.loads(out)["status"] == "error" and not png.exists()
    assert err.count("\n") == 1 and str(path) in err and where in err


def test_bad_plot_path(capsys, tmp_path):
    rec = _write(tmp_path / "ok.csv", GC_HEADER + "\n" + GOOD_ROWS)
    for plot in (tmp_path / "no" / "dir.png", tmp_path / "x.txt"):
        code, out, err = _run([*GC_PAPER, str(rec), "--plot", str(plot)], capsys)
        assert code == 2 and out == "" and err.count("\n") == 1 and str(plot) in err


def test_subprocess_one_line_no_traceback(tmp_path):
    """Through the real entry point: status 2, one line, no traceback; a usage error of
    calibrate is one line too."""
    path = _write(tmp_path / "bad.csv", GC_HEADER + "\n0.001,0,0,0\n0.002,0,zz,0\n")
    proc = subprocess.run([sys.executable, "-m", "gyrolib", *GC_PAPER, str(path)],
                          capture_output=True, text=True, check=False)
    assert proc.returncode == 2 and proc.stdout == ""
    assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr
    assert "line 3, column 'inclinometer_y'" in proc.stderr
    proc = subprocess.run([sys.executable, "-m", "gyrolib", "calibrate", "rsf", str(path)],
                          capture_output=True, text=True, check=False)
    assert proc.returncode == 2 and proc.stderr.count("\n") == 1 and "--period" in proc.stderr


def test_file_streamed_in_chunks_equals_whole_file(gc_file):
    """Reading the file in small chunks (records.GCChunks) gives the one-shot result."""
    path, _, _ = gc_file
    whole = gc.calibrate(records.read_gc(path), P)
    chunks = records.GCChunks(path, chunk_rows=7000)
    streamed = gc.calibrate(chunks, P)
    assert chunks.fraction == pytest.approx(1.0)
    np.testing.assert_allclose(streamed.x_final, whole.x_final, rtol=1e-12, atol=1e-30)
    np.testing.assert_allclose(streamed.P_final, whole.P_final, rtol=1e-12, atol=1e-40)
    assert streamed.rows == whole.rows and (streamed.rejected == whole.rejected).all()


def test_next_chunk_read_in_a_thread_with_two_chunks_in_flight(gc_file, monkeypatch,
                                                                capsys):
    """gc.calibrate(executor=) reads chunk k+1 in the executor's thread while chunk k is
    filtered: the same result, never more than two chunks read and not yet filtered; the
    command line streams a file that way (a ThreadPoolExecutor of one worker)."""
    import threading
    from concurrent.futures import ThreadPoolExecutor

    path, _, _ = gc_file
    whole = gc.calibrate(records.read_gc(path), P)
    produced, finished, peak, threads = [0], [0], [0], set()

    def counted():
        for chunk in records.GCChunks(path, chunk_rows=7000):
            produced[0] += 1
            peak[0] = max(peak[0], produced[0] - finished[0])
            threads.add(threading.current_thread().name)
            yield chunk

    def progress(_rows):
        finished[0] += 1

    with ThreadPoolExecutor(max_workers=1, thread_name_prefix="reader") as ex:
        res = gc.calibrate(counted(), P, executor=ex, progress=progress)
    np.testing.assert_allclose(res.x_final, whole.x_final, rtol=1e-12, atol=1e-30)
    assert res.rows == whole.rows and produced[0] == finished[0] == 14   # 98 000 rows
    assert 1 <= peak[0] <= 2 and all(t.startswith("reader") for t in threads)
    seen = []
    real = gc.judge_record

    def spy(record, params, **kw):
        seen.append(kw.get("executor"))
        return real(record, params, **kw)

    monkeypatch.setattr(gc, "judge_record", spy)
    code, _, _ = _run([*GC_PAPER, str(path), "--json"], capsys)
    assert code == 0 and len(seen) == 1 and isinstance(seen[0], ThreadPoolExecutor)


class _Tty:
    """A stand-in for stderr: a terminal or a pipe, collecting what is written."""

    def __init__(self, tty: bool) -> None:
        self.text, self.tty = "", tty

    def isatty(self) -> bool:
        return self.tty

    def write(self, s: str) -> int:
        self.text += s
        return len(s)

    def flush(self) -> None:
        pass


@pytest.mark.parametrize("tty, as_json, shown", [(True, False, True), (True, True, False),
                                                  (False, False, False)])
def test_progress_bar_only_on_a_terminal_without_json(tty, as_json, shown, monkeypatch,
                                                      gc_file):
    """tqdm's bar goes to stderr on a terminal, never with --json or when piped."""
    path, _, _ = gc_file
    err = _Tty(tty)
    monkeypatch.setattr(sys, "stderr", err)
    code = main([*GC_PAPER, str(path), *(["--json"] if as_json else [])])
    assert code == 0
    assert ("calibrate gc" in err.text and "%" in err.text) is shown
    if not shown:
        assert err.text == ""


def test_command_line_uses_one_blas_thread_unless_told():
    """A process the command line starts runs BLAS on one thread (its matrices are small;
    benchmarks/bench_calibrate.py), unless the user set the thread count; a program that
    imported numpy first keeps its own setting."""
    import os

    env = {k: v for k, v in os.environ.items() if k not in ("OPENBLAS_NUM_THREADS",
                                                            "MKL_NUM_THREADS")}
    code = "import os, gyrolib.cli; print(os.environ.get('OPENBLAS_NUM_THREADS'))"

    def run(prefix: str = "", **extra: str) -> str:
        return subprocess.run([sys.executable, "-c", prefix + code], capture_output=True,
                              text=True, check=True, env={**env, **extra}).stdout.strip()

    assert run() == "1"
    assert run(OPENBLAS_NUM_THREADS="2") == "2"
    assert run("import numpy; ") == "None"


def test_a_gc_run_loads_only_what_it_needs():
    """``calibrate gc FILE --json`` (no terminal, so no bar) loads neither pandas (which
    ``pyarrow.Array.to_numpy`` would load), tqdm, paper RSF's package nor pyarrow.compute
    (needed only for an absolute clock; pandas then comes with its scalars): each was
    start-up time of the hour-long run (benchmarks/bench_calibrate.py).  ``calibrate rsf``
    does load paper RSF, and an epoch-time record pyarrow.compute: the probe sees them (its
    power)."""
    root = Path(__file__).resolve().parents[2]
    watch = ("pandas", "tqdm", "gyrolib.rsf", "pyarrow.compute")

    def loaded(*argv: str) -> list[str]:
        probe = ("import contextlib, io, sys\nfrom gyrolib.cli import main\n"
                 "with contextlib.redirect_stdout(io.StringIO()):\n"
                 f"    main({list(argv)!r})\n"
                 f"print(' '.join(m for m in {watch!r} if m in sys.modules))\n")
        out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                             check=True, cwd=root)
        return out.stdout.split()

    assert loaded("calibrate", "gc", "data/gc_record.csv.gz", "--json") == []
    assert loaded("calibrate", "rsf", "data/rsf_record.csv.gz", "--period", "1",
                  "--json") == ["gyrolib.rsf"]
    lines = gzip.open(root / "data" / "gc_record.csv.gz", "rt").read().splitlines()[:2005]
    h = next(i for i, ln in enumerate(lines) if not ln.startswith("#"))
    epoch = [f"{1.7e9 + float(r.split(',')[0]):.3f}," + r.split(",", 1)[1]
             for r in lines[h + 1:]]
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "epoch.csv"
        path.write_text("\n".join([*lines[:h + 1], *epoch]) + "\n")
        assert "pyarrow.compute" in loaded("calibrate", "gc", str(path), "--json")
