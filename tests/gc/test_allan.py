"""Allan deviation of a paper-GC record (:func:`gyrolib.gc.allan_deviation`): white noise
against the closed forms of the Allan variance, the vibration's model curve against a
simulated record, and a record with another vibration spectrum that the paper's curve does
not match (power)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import scipy.stats

from gyrolib import gc

#: The command needs the latitude stated; this file's records have paper GC's Earth rate.
GC_PAPER = ("calibrate", "gc", "--latitude", "paper")

P = gc.GyrocompassParams()


def _agree(series, reference, confidence: float = 0.999) -> np.ndarray:
    """Whether ``reference`` lies in the two-sided ``confidence`` interval of each estimate:
    adev² · edf / reference² is χ²(edf) (edf from Greenhall's algorithm for the series'
    noise type)."""
    e = series.edf
    lo = series.adev * np.sqrt(e / scipy.stats.chi2.ppf(0.5 + confidence / 2, e))
    hi = series.adev * np.sqrt(e / scipy.stats.chi2.ppf(0.5 - confidence / 2, e))
    return (lo <= reference) & (reference <= hi)


def test_white_noise_closed_forms():
    """White angle noise of variance R is white phase noise: σ(τ) = √(3R)/τ for the rate;
    white inclinometer noise of variance C/Δt averages as √(C/τ).  Records built here from
    numpy's generator, not by the simulator."""
    rng = np.random.default_rng(11)
    n = 60000
    t = np.arange(1, n + 1) * P.dt
    r_as, c_in = 2e-10, 5e-15
    beta_n = gc.nominal_motion_aperiodic(P, t).beta
    rec = gc.GCRecord(t=t, angle_sensor=beta_n + np.sqrt(r_as) * rng.standard_normal(n),
                      inclinometer_y=np.sqrt(c_in / P.dt) * rng.standard_normal(n),
                      inclinometer_z=np.sqrt(c_in / P.dt) * rng.standard_normal(n))
    ad = gc.allan_deviation(rec, P)
    a = ad.get("angle_sensor")
    assert np.all(_agree(a, np.sqrt(3 * r_as) / a.tau))
    for name in ("inclinometer_y", "inclinometer_z"):
        s = ad.get(name)
        assert np.all(_agree(s, np.sqrt(c_in / s.tau)))
    assert ad.rows == n and ad.dt == pytest.approx(P.dt) and not ad.filled.any()


@pytest.fixture(scope="module")
def records():
    wide = dataclasses.replace(P, alpha1=10 * P.alpha1)
    return (gc.simulate_record(P, 40.0, seed=77).record,
            gc.simulate_record(wide, 40.0, seed=78).record, wide)


def test_vibration_model_matches_simulated_record(records):
    """The inclinometers of a record of the truth model (Eq. (6)'s N1 integrated on its own
    fine grid) against the model curve √(C/τ + σ²_N1(τ)) from the PSD of Eq. (6)."""
    rec, _, _ = records
    ad = gc.allan_deviation(rec, P)
    for name in ("inclinometer_y", "inclinometer_z"):
        s = ad.get(name)
        assert np.all(_agree(s, s.model)), name
    a = ad.get("angle_sensor")
    assert np.all(_agree(a, a.model))


def test_wider_vibration_is_seen(records):
    """Power: a record whose α1 is ten times the paper's is far from the paper's curve (its
    N1 random walk is √10 stronger) and on the curve of its own parameters."""
    _, rec_w, wide = records
    paper = gc.allan_deviation(rec_w, P).get("inclinometer_y")
    own = gc.allan_deviation(rec_w, wide).get("inclinometer_y")
    use = (paper.tau >= 0.01) & (paper.tau <= 4.0)
    assert np.all(paper.adev[use] / paper.model[use] > 2.0)
    assert np.all(_agree(own, own.model))


def test_longest_stretch_and_filled_cells(records):
    """A gap splits the record: the longest stretch is used; NaN cells are interpolated and
    counted."""
    rec, _, _ = records
    keep = ~((rec.t > 10.0) & (rec.t <= 11.0))
    a = np.array(rec.angle_sensor)
    a[[20000, 20001, 30000]] = np.nan
    cut = gc.GCRecord(t=rec.t[keep], angle_sensor=a[keep],
                      inclinometer_y=rec.inclinometer_y[keep],
                      inclinometer_z=rec.inclinometer_z[keep])
    ad = gc.allan_deviation(cut, P)
    assert ad.t_start == pytest.approx(11.001) and ad.t_end == pytest.approx(40.0)
    assert ad.filled.tolist() == [3, 0, 0]


def test_plot_has_two_panels(records):
    import matplotlib.pyplot as plt

    fig = gc.plot_allan(gc.allan_deviation(records[0], P), title="x")
    assert len(fig.axes) == 2 and fig.axes[0].get_xscale() == "log"
    plt.close(fig)


# The overlapping Allan deviation in numpy, against allantools -----------------
@pytest.mark.parametrize("data_type", ["phase", "freq"])
@pytest.mark.parametrize("taus", ["octave", "decade", "all", "array"])
def test_oadev_equals_allantools(data_type, taus):
    """gyrolib's few lines of numpy against allantools.oadev (a test-only dependency): the
    same averaging times, deviations to 1e-12 relative and the same number of terms."""
    import allantools

    from gyrolib.gc.logs.allan import oadev

    rng = np.random.default_rng(21)
    n = 3000 if taus == "all" else 50000
    x = np.cumsum(rng.standard_normal(n)) * 1e-3 + rng.standard_normal(n)
    t_arg = np.array([0.01, 0.037, 0.5, 3.0, 40.0, 0.01]) if taus == "array" else taus
    tau, ad, nn = oadev(x, 100.0, data_type, t_arg)
    ref_tau, ref_ad, _, ref_n = allantools.oadev(x, rate=100.0, data_type=data_type,
                                                 taus=t_arg)
    np.testing.assert_allclose(tau, ref_tau, rtol=1e-12)
    np.testing.assert_allclose(ad, ref_ad, rtol=1e-10)
    np.testing.assert_array_equal(nn, np.asarray(ref_n, dtype=np.int64))


@pytest.mark.parametrize("alpha", [2, 0, -2])
def test_edf_close_to_greenhall(alpha):
    """NIST SP 1065's edf approximations within 30 % of Greenhall's algorithm
    (allantools.edf_greenhall), over m from 1 to N/10."""
    import allantools

    from gyrolib.gc.logs.allan import edf_oadev

    for N in (1001, 100001):
        for m in (1, 3, 10, 30, 100, N // 10):
            ref = float(allantools.edf_greenhall(alpha=alpha, d=2, m=m, N=N, overlapping=True))
            got = float(edf_oadev(alpha, np.array([m]), N)[0])
            assert 0.7 < got / ref < 1.35, (alpha, N, m, got, ref)


def test_library_does_not_import_allantools_at_run_time():
    code = ("import sys, numpy as np\n"
            "from gyrolib import gc\n"
            "rec = gc.simulate_record(gc.GyrocompassParams(), 2.0, seed=1).record\n"
            "gc.allan_noise_terms(gc.allan_deviation(rec))\n"
            "print('allantools' in sys.modules)\n")
    import subprocess
    import sys

    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.strip() == "False"


# Noise terms (IEEE Std 952) -------------------------------------------------------------------
def _arw_record(n_arw: float, seed: int, t_end: float = 100.0) -> gc.GCRecord:
    """The nominal motion plus an angle random walk of N = n_arw (rad/√s: white rate noise
    of PSD N², integrated) plus the angle sensor's white noise √R₁₁; the inclinometers
    the vibration N1 of Eq. (6) and their white noise."""
    rng = np.random.default_rng(seed)
    n = round(t_end / P.dt)
    t = np.arange(1, n + 1) * P.dt
    sr = np.sqrt(np.diag(gc.measurement_noise_covariance(P)))
    walk = np.cumsum(rng.standard_normal(n)) * n_arw * np.sqrt(P.dt)
    n1 = gc.simulate_shaping_filter(P.vibration_filter(), P.dt, n, seed=seed + 1)
    return gc.GCRecord(t=t, angle_sensor=gc.nominal_motion_aperiodic(P, t).beta + walk
                       + sr[0] * rng.standard_normal(n),
                       inclinometer_y=n1 + sr[1] * rng.standard_normal(n),
                       inclinometer_z=n1 + sr[2] * rng.standard_normal(n))


def test_angle_random_walk_recovered_within_its_uncertainty():
    """A known angle random walk (N = 2e-5 rad/√s = 0.069 °/√h) under the angle sensor's
    white noise: over 12 seeds the estimate lies within its stated 1σ in at least 7 and
    within 3σ in all, and is identified in all; the bias instability and rate random walk
    (absent) are not identified, only bounded.  Power: the same records read as if N were
    twice as large fall outside 3σ."""
    n_arw = 2e-5
    inside, within3 = 0, 0
    for seed in range(12):
        rec = _arw_record(n_arw, seed, 60.0)
        arw, bi, rrw = gc.allan_noise_terms(gc.allan_deviation(rec, P))["angle_sensor"]
        assert arw.identified and not bi.identified and not rrw.identified
        inside += abs(arw.value - n_arw) <= arw.sigma
        within3 += abs(arw.value - n_arw) <= 3 * arw.sigma
        assert abs(arw.value - 2 * n_arw) > 3 * arw.sigma
    assert inside >= 7 and within3 == 12


def test_allan_option_prints_the_noise_terms(tmp_path, capsys):
    """calibrate gc FILE --allan OUT.png on a simulated record with a known angle random
    walk: the printed and JSON angle random walk within its stated 1σ of the truth, in
    °/√h (1 °/√h = (π/180)/60 rad/√s), and the figure written."""
    from gyrolib import records
    from gyrolib.cli import main

    n_arw = 2e-5
    rec = _arw_record(n_arw, 101, 60.0)
    path = records.write_csv(tmp_path / "arw.csv", {
        "t": rec.t, "angle_sensor": rec.angle_sensor, "inclinometer_y": rec.inclinometer_y,
        "inclinometer_z": rec.inclinometer_z}, fmt=["%.3f", "%.12g", "%.12g", "%.12g"])
    png = tmp_path / "allan.png"
    code = main([*GC_PAPER, str(path), "--allan", str(png), "--json"])
    import json

    data = json.loads(capsys.readouterr().out)
    arw = data["allan_noise_terms"]["angle_sensor"][0]
    assert arw["name"] == "angle random walk" and arw["identified"]
    assert abs(arw["value"] - n_arw) <= arw["sigma"]
    assert arw["unit"] == "rad/s*sqrts"
    # a term whose coefficient is 0 is nowhere: no tau_s (absent, as allan --json has it,
    # never null); the library's terms say which coefficients are 0
    lib = gc.allan_noise_terms(gc.allan_deviation(records.read_gc(path, check=False), P))
    for name, terms in data["allan_noise_terms"].items():
        for term, t in zip(terms, lib[name], strict=True):
            assert ("tau_s" in term) == (t.tau is not None), (name, term["name"])
            assert term.get("tau_s", 1.0) is not None
    assert any("tau_s" not in t for ts in data["allan_noise_terms"].values() for t in ts)
    if code == 0:
        assert png.stat().st_size > 1000
    main([*GC_PAPER, str(path), "--allan", str(tmp_path / "b.png")])
    out = capsys.readouterr().out
    deg = n_arw / (np.pi / 180 / 60)
    line = next(ln for ln in out.splitlines() if "angle random walk" in ln)
    assert f"angle random walk = {arw['value'] / (np.pi / 180 / 60):.3g} ± " in line
    assert abs(float(line.split("angle random walk = ")[1].split(" ")[0]) - deg) < 0.2 * deg
