"""The ``allan`` command on two real gyro logs (scikit-kinematics 0.10.4's YEI log, µs time
stamps and rad/s, and its x-IMU log, 256 Hz in deg/s with no time column:
``tests/references/data_gyro``), and the noise terms of those logs and of allantools' clock
records against a second fit written here from IEEE Std 952-1997, Annex C.

* the deviation equals allantools' (pinned, a second implementation) to 1e-12;
* no term's line and no upper-bound line lies above the measured deviation's 68 % upper
  bound over the curve (computed here with scipy.stats) at any τ;
* the bias instability is IEEE Std 952's (the curve's minimum ÷ 0.664), and the angle and
  rate random walks the tool identifies agree with the second fit's within 30 %;
* a term read outside the measured τ range (the YEI log's first 300 rows end at τ = 1.2 s)
  is printed as a bound with its τ range;
* both logs are motion recordings: each gets the warning;
* one missing cell in the x-IMU log's 12 626 rows drops that row, counted, not the file;
* the YEI log with its time in ms is refused naming ``--time-unit ms``, and read with it
  gives the angle random walk of the log in s within 5 %."""

from __future__ import annotations

import gzip
import json
from pathlib import Path

import numpy as np
import pytest

from gyrolib.cli import main
from gyrolib.gc.logs.allan import allan_series, edf_oadev, noise_terms

DATA = Path(__file__).resolve().parent / "data_gyro"
CLOCKS = Path(__file__).resolve().parent / "data_allantools"
AXES = ("gyro_x", "gyro_y", "gyro_z")
XIO_AXES = ("Gyroscope X (deg/s)", "Gyroscope Y (deg/s)", "Gyroscope Z (deg/s)")
YEI_HEADER = ("t,gyro_x,gyro_y,gyro_z,compass_x,compass_y,compass_z,accel_x,accel_y,"
              "accel_z")


def _json(argv, capsys) -> tuple[int, dict, str]:
    code = main([str(a) for a in argv] + ["--json"])
    cap = capsys.readouterr()
    return code, (json.loads(cap.out) if cap.out else {}), cap.err


@pytest.fixture(scope="module")
def yei(tmp_path_factory) -> dict[str, Path]:
    """The YEI log with a header line (it has none: its first line is a comment), its time
    in µs as logged, and rewritten in ms and in s (exact decimals of the same stamps); and
    its first 300 rows."""
    folder = tmp_path_factory.mktemp("yei")
    lines = gzip.decompress((DATA / "data_yei.txt.gz").read_bytes()).decode().splitlines()
    rows = [ln for ln in lines if ln.strip() and not ln.lstrip().startswith("#")]
    out = {}
    for unit, digits, div in (("us", 0, 1), ("ms", 3, 10**3), ("s", 6, 10**6)):
        text = [f"{int(r.split(',', 1)[0]) / div:.{digits}f}," + r.split(",", 1)[1]
                for r in rows]
        out[unit] = folder / f"yei_{unit}.csv"
        out[unit].write_text("\n".join([YEI_HEADER, *text]) + "\n")
    out["first300"] = folder / "yei_300.csv"
    out["first300"].write_text("\n".join([YEI_HEADER, *rows[:300]]) + "\n")
    return out


def _logs(yei) -> list[tuple[str, list[str], int]]:
    """(name, allan arguments, axis) of each log and axis."""
    out = [(f"yei {a}", [yei["us"], "--time-unit", "us", "--columns", f"rate={a}"], k)
           for k, a in enumerate(AXES)]
    out += [(f"x-IMU {a}", [DATA / "00033_CalInertialAndMag.csv.gz", "--rate", "256",
                            "--rate-unit", "deg/s", "--columns", f"rate={a}"], k)
            for k, a in enumerate(XIO_AXES)]
    return out


def _raw(name: str, axis: int) -> tuple[np.ndarray, float]:
    """The log's rate (rad/s) and sample rate, read here with numpy (not the reader)."""
    if name.startswith("yei"):
        text = gzip.decompress((DATA / "data_yei.txt.gz").read_bytes()).decode()
        d = np.loadtxt(text.splitlines()[1:], delimiter=",")
        return d[:, 1 + axis], 1e6 / float(np.median(np.diff(d[:, 0])))
    text = gzip.decompress((DATA / "00033_CalInertialAndMag.csv.gz").read_bytes()).decode()
    d = np.loadtxt(text.splitlines()[1:], delimiter=",")
    return np.radians(d[:, 1 + axis]), 256.0


def _upper(tau, adev, n) -> np.ndarray:
    """The deviation's 68 % upper bound over the whole curve, computed here with
    scipy.stats: χ² with the least favourable edf of white phase, white and random-walk
    frequency noise, each point at the one-sided level 0.6827^(1/points) (Šidák)."""
    import scipy.stats

    tau, adev = np.asarray(tau), np.asarray(adev)
    m = np.round(tau / tau[0])
    n_phase = int(np.max(np.asarray(n) + 2 * m))
    edf = np.min([edf_oadev(a, m, n_phase) for a in (2, 0, -2)], axis=0)
    below = 0.682689492137086 ** (1 / tau.size)
    return adev * np.sqrt(edf / scipy.stats.chi2.ppf(1 - below, edf))


LINE = {-0.5: lambda v, tau: v / np.sqrt(tau), 0.0: lambda v, tau: 0.664 * v + 0 * tau,
        0.5: lambda v, tau: v * np.sqrt(tau / 3.0)}


def _inside(terms: list[dict], tau, bound) -> list[str]:
    """The terms whose line or upper-bound line lies above ``bound`` at some τ."""
    slope = {"angle random walk": -0.5, "bias instability": 0.0, "rate random walk": 0.5}
    return [t["name"] for t in terms for level in (t["value"], t["hi"])
            if np.any(LINE[slope[t["name"]]](level, np.asarray(tau)) > bound * (1 + 1e-9))]


def test_the_deviation_equals_allantools(yei, capsys):
    """Each axis of both logs, read by the command: the overlapping deviation equals
    allantools.oadev of the rate read here with numpy, to 1e-12."""
    import allantools

    for name, argv, axis in _logs(yei):
        code, out, err = _json(["allan", *argv], capsys)
        assert code == 0, err
        rate, fs = _raw(name, axis)
        _, ref, _, _ = allantools.oadev(rate, rate=fs, data_type="freq", taus="octave")
        assert out["rows_dropped_missing"] == 0
        np.testing.assert_allclose(out["adev"], ref[:len(out["adev"])], rtol=1e-12, atol=0,
                                   err_msg=name)


def test_terms_inside_the_data_and_the_motion_warned(yei, capsys):
    """No term line, and no upper-bound line, above the 68 % upper bound over the curve;
    both logs moved (the YEI and x-IMU logs are motion recordings): the warning.  Power:
    each bound is the largest such line, 1.2 times it crosses the bound at some τ."""
    for name, argv, _ in _logs(yei):
        _, out, _ = _json(["allan", *argv], capsys)
        n = [float(x) for x in _counts(out)]
        bound = _upper(out["tau"], out["adev"], n)
        assert _inside(out["noise_terms"], out["tau"], bound) == [], name
        assert not out["at_rest"] and "describe the motion" in out["warnings"][0], name
        grown = [dict(t, value=1.2 * t["value"], hi=1.2 * t["hi"])
                 for t in out["noise_terms"] if not t["identified"]]
        assert set(_inside(grown, out["tau"], bound)) == {t["name"] for t in grown}, name


def _counts(out: dict) -> np.ndarray:
    """The number of second differences of each τ (NIST SP 1065): N + 1 − 2m phase points
    for a rate log of N values."""
    m = np.round(np.asarray(out["tau"]) / out["dt"])
    n = out["rows"] - out["rows_dropped_missing"]
    return n + 1 - 2 * m


def second_fit(tau, adev) -> dict[str, float | None]:
    """IEEE Std 952-1997, Annex C, read off the log-log curve: the −½ line through the
    points whose local slope is within ±¼ of −½, N its value at τ = 1 s; the +½ line
    likewise, K its value at τ = 3 s; B the curve's minimum ÷ 0.664.  None where the curve
    has no point of that slope."""
    lt, ls = np.log(tau), np.log(adev)
    slope = np.gradient(ls, lt)
    out: dict[str, float | None] = {"B": float(np.min(adev)) / 0.664}
    for key, s, at in (("N", -0.5, 1.0), ("K", 0.5, 3.0)):
        sel = np.abs(slope - s) <= 0.25
        out[key] = (float(np.exp(np.mean(ls[sel] - s * lt[sel]) + s * np.log(at)))
                    if sel.any() else None)
    return out


def _agree(terms: list[dict], fit: dict, rel: float = 0.3) -> list[str]:
    """The terms that disagree with the second fit: an identified N or K more than ``rel``
    from it (or absent from it), a bias instability not the curve's minimum ÷ 0.664 when
    identified or below it when a bound."""
    bad = []
    for t, key in zip(terms, ("N", "B", "K")):
        ref = fit[key]
        if key == "B":
            ok = (abs(t["value"] / ref - 1) < 1e-12 if t["identified"]
                  else t["value"] >= ref * (1 - 1e-12))
        else:
            ok = not t["identified"] or (ref is not None and abs(t["value"] / ref - 1) < rel)
        if not ok:
            bad.append(t["name"])
    return bad


def _clock(name: str) -> np.ndarray:
    with gzip.open(CLOCKS / name, "rt") as fh:
        return np.array([float(ln) for ln in fh if ln.strip() and not ln.startswith("#")])


def _as_json(s) -> tuple[list[dict], np.ndarray, np.ndarray]:
    terms = [{"name": t.name, "value": t.value, "hi": t.hi, "identified": t.identified}
             for t in noise_terms(s)]
    return terms, s.tau, s.adev


def test_terms_against_a_second_fit_from_ieee_952(yei, capsys):
    """The gyro logs (each axis, and the YEI log's first 300 rows at rest) and allantools'
    clock records (OCXO frequency, GPS and Cs phase): every term agrees with the second
    fit (identified N and K within 30 %, B its minimum ÷ 0.664 or a bound above it); the
    OCXO's bias instability and the Cs clock's white frequency noise are identified.
    Power: terms twice the tool's disagree."""
    cases = []
    for name, argv, _ in _logs(yei):
        _, out, _ = _json(["allan", *argv], capsys)
        cases.append((name, out["noise_terms"], out["tau"], out["adev"]))
    for a in AXES:
        _, out, _ = _json(["allan", yei["first300"], "--time-unit", "us", "--columns",
                           f"rate={a}"], capsys)
        cases.append((f"yei first 300 {a}", out["noise_terms"], out["tau"], out["adev"]))
    ocxo = allan_series(_clock("ocxo_frequency.txt.gz") / 1.0e7 - 1.0, 1.0, unit="1")
    gps = allan_series(_clock("gps_1pps_phase_data.txt.gz"), 1.0, unit="1",
                       data_type="phase")
    cs = allan_series(_clock("cs5071a_phase.txt.gz"), 1.0, unit="1", data_type="phase")
    for name, s in (("ocxo", ocxo), ("gps", gps), ("cs", cs)):
        cases.append((name, *_as_json(s)))
    identified = set()
    for name, terms, tau, adev in cases:
        fit = second_fit(np.asarray(tau), np.asarray(adev))
        assert _agree(terms, fit) == [], (name, terms, fit)
        identified |= {(name, t["name"]) for t in terms if t["identified"]}
        wrong = [dict(t, value=2.0 * t["value"]) for t in terms]
        assert {t["name"] for t in wrong if t["identified"]} <= set(_agree(wrong, fit)), name
    assert {("ocxo", "bias instability"), ("cs", "angle random walk")} <= identified


def test_a_term_read_outside_the_tau_range_is_a_bound(yei, capsys):
    """The YEI log's first 300 rows (2.7 s, at rest on x and y) end at τ = 1.16 s: the rate
    random walk, which IEEE Std 952 reads at τ = 3 s, is a bound, printed with the τ
    range it comes from, on every axis."""
    for a in AXES:
        argv = ["allan", str(yei["first300"]), "--time-unit", "us", "--columns", f"rate={a}"]
        _, out, _ = _json(argv, capsys)
        rrw = out["noise_terms"][2]
        assert out["tau"][-1] < 3.0 and rrw["extrapolated"] and not rrw["identified"]
        assert main(argv) == 0
        line = next(ln for ln in capsys.readouterr().out.splitlines()
                    if "rate random walk" in ln)
        assert line.lstrip().startswith("rate random walk <=")
        assert f"from tau = {out['tau'][0]:.3g} to {out['tau'][-1]:.3g} s" in line


def test_time_in_milliseconds(yei, capsys):
    """The YEI log with its stamps in ms: refused (exit 2) naming --time-unit ms; read with
    it, its angle random walk (bound or value) is within 5 % of the log's in s; the log in
    µs likewise with --time-unit us.  Power: the ms log read as s (stated so) is √1000
    times off."""
    ms = ["allan", yei["ms"], "--columns", "rate=gyro_y"]
    code, out, err = _json(ms, capsys)
    assert code == 2 and "--time-unit ms" in err and err.count("\n") == 1
    _, ref, _ = _json(["allan", yei["s"], "--columns", "rate=gyro_y"], capsys)
    for argv in ([*ms, "--time-unit", "ms"],
                 ["allan", yei["us"], "--columns", "rate=gyro_y", "--time-unit", "us"]):
        code, out, _ = _json(argv, capsys)
        assert code == 0
        assert out["noise_terms"][0]["value"] == pytest.approx(
            ref["noise_terms"][0]["value"], rel=0.05)
    _, wrong, _ = _json([*ms, "--time-unit", "s"], capsys)
    assert wrong["noise_terms"][0]["value"] > 5 * ref["noise_terms"][0]["value"]


def test_one_missing_value_in_the_x_imu_log(tmp_path, capsys):
    """The x-IMU log (12 626 rows) with one gyro cell emptied: read, that row dropped and
    counted, and the deviation that of the log without the row (allantools, to 1e-12)."""
    import allantools

    lines = gzip.decompress((DATA / "00033_CalInertialAndMag.csv.gz").read_bytes()
                            ).decode().splitlines()
    cells = lines[5001].split(",")
    cells[3] = ""
    path = tmp_path / "xio_nan.csv"
    path.write_text("\n".join([*lines[:5001], ",".join(cells), *lines[5002:]]) + "\n")
    code, out, err = _json(["allan", path, "--rate", "256", "--rate-unit", "deg/s",
                            "--columns", f"rate={XIO_AXES[2]}"], capsys)
    assert code == 0 and err == ""
    assert out["rows"] == 12626 and out["rows_dropped_missing"] == 1
    rate, fs = _raw("x-IMU", 2)
    _, ref, _, _ = allantools.oadev(np.delete(rate, 5000), rate=fs, data_type="freq",
                                    taus="octave")
    np.testing.assert_allclose(out["adev"], ref[:len(out["adev"])], rtol=1e-12, atol=0)
