"""Paper GC's chapters' stored studies (gyrolib.book.studies.gc over gyrolib.store).

Everyday (each study's key and fingerprint points are checked, fresh, by
tests/book/ledger/test_studies.py, as for every study of the book): each study holds what the
chapters read, judged against bounds independent of the code that computed it; a
changed model constant outside the table (Omega_v x 1.1) or a changed run count makes it stale
by name with its refresh command, through the key and through the fingerprint alone.  Full
tier: each study recomputed whole and compared with the stored file within its declared
tolerance.  The package's files are only read: what is written goes to ``tmp_path``.
"""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest
from scipy import stats as sps

from gyrolib import gc, store
from gyrolib.book import studies as book_studies
from gyrolib.book.studies import gc as gcs
from gyrolib.gc.model.params import GyrocompassParams
from tests.support.stored_studies import patch_default, stale_message


def _data(name: str) -> dict:
    return json.loads(store.study(name).file.read_text("utf-8"))


def _decoded(name: str) -> dict:
    """The stored study as the chapters read it, without its check (which
    tests/book/ledger/test_studies.py runs for every study of the book)."""
    return gcs.decode({k: x for k, x in _data(name).items() if k != store.HEADER_KEY})




def test_the_studies_are_listed_and_registered():
    assert set(gcs.NAMES) <= set(book_studies.NAMES)
    assert set(gcs.NAMES) <= set(store.registered())
    for name in gcs.NAMES:
        h = store.header_of(name, _data(name))
        assert h.key == gcs.key(name) and (h.rtol, h.atol) == (1e-6, 1e-6)
        assert h.cost_cpu_s is not None and h.cost_cpu_s > 0
        assert f"python3 tasks.py refresh {name}" in gcs.describe(name)


# what the chapters read, against bounds of their own -------------------------------------------
def test_monte_carlo_study_reads_as_a_consistent_filter():
    """The stored paper's truth: the RMS error of ω_gc at 100 s over the runs is the filter's
    σ within the chi-square band of an RMS of N_RUNS runs; the louder truth is outside it."""
    d = _decoded("gc-monte-carlo")
    mc, wrong = d["mc"], d["wrong"]
    assert (mc.n_runs, mc.seed) == (gcs.N_RUNS, gcs.SEED)
    lo, hi = (sps.chi2.ppf(q, gcs.N_RUNS) / gcs.N_RUNS for q in (0.0005, 0.9995))
    r2 = (mc.rms_error("omega_gc")[-1] / mc.std("omega_gc")[-1]) ** 2
    assert lo < r2 < hi
    assert np.isclose(np.sqrt(np.mean(mc.error_end("omega_gc") ** 2)), mc.rms_error("omega_gc")[-1],
                      rtol=1e-12)
    assert (wrong.rms_error("omega_gc")[-1] / wrong.std("omega_gc")[-1]) ** 2 > hi
    lin = d["lin"]
    assert abs(lin.slope(5.0) - 1.0) < 0.05   # the shift follows the remainder (the chapter)
    assert len(d["variants"]) == len(gcs.VARIANTS)
    assert np.all(np.asarray(d["series_gap_runs"]) < 1e-6)


def test_speed_claim_study_brackets_its_boundary():
    d = _decoded("gc-speed-claim")
    b = d["boundary"]
    assert b.sigma[0] < b.level < b.sigma[1] and b.factors[0] < b.factor < b.factors[1]
    assert d["claim"].t_c.shape == (2, 7, 7) and d["sweep"].monotone.all()


def test_race_study_holds_every_case_of_the_chapter():
    d = _decoded("gc-race-sweeps")
    for k, cases in gcs._race_cases().items():
        assert [dict(c) for c in d[k].cases] == cases
    assert d["mc"].n_runs == gcs.RACE_MC_RUNS and d["mc"].inside


# stale by name ---------------------------------------------------------------------------------
@pytest.mark.parametrize("name", gcs.NAMES)
def test_omega_v_times_1_1_makes_each_study_stale_by_its_key(monkeypatch, name):
    patch_default(monkeypatch, GyrocompassParams, "Omega_v", 1.1 * GyrocompassParams().Omega_v)
    with pytest.raises(store.StaleStudy) as exc:
        store.check(name)
    assert "gyrolib.gc.model.params" in stale_message(exc, name)


def test_omega_v_times_1_1_breaks_the_fingerprint_itself(monkeypatch):
    """The speed claim's points alone (no key) catch the changed constant, and pass as is."""
    data = _data("gc-speed-claim")
    assert gcs._check_speed(data) >= 10
    patch_default(monkeypatch, GyrocompassParams, "Omega_v", 1.1 * GyrocompassParams().Omega_v)
    with pytest.raises(store.StaleStudy) as exc:
        gcs._check_speed(data)
    stale_message(exc, "gc-speed-claim")


def test_a_changed_run_count_makes_the_monte_carlo_stale(monkeypatch):
    monkeypatch.setattr(gcs, "N_RUNS", 2 * gcs.N_RUNS)
    with pytest.raises(store.StaleStudy) as exc:
        store.check("gc-monte-carlo")
    assert "gyrolib.book.studies.gc" in stale_message(exc, "gc-monte-carlo")


def test_a_moved_monte_carlo_run_fails_the_fingerprint(tmp_path):
    """A copy of the file whose run 1 error of ω_gc moved by 1e-4 σ fails by name."""
    data = _data("gc-monte-carlo")
    mc = gcs.decode(data["mc"])
    sd = mc.std("omega_gc")[-1]
    i = mc.names.index("omega_gc")
    err = mc.end_error.copy()
    err[1, i] += 1e-4 * sd
    data["mc"] = gcs.encode(dataclasses.replace(mc, end_error=err))
    copy = tmp_path / "gc_monte_carlo.json"
    copy.write_text(json.dumps(data), encoding="utf-8")
    with pytest.raises(store.StaleStudy) as exc:
        store.check("gc-monte-carlo", copy)
    assert "run 1's error of omega_gc" in stale_message(exc, "gc-monte-carlo")


def test_a_race_sweep_that_moves_fails_by_name(monkeypatch):
    real = gc.race_sweep

    def slower(*args, **kw):
        r = real(*args, **kw)
        return dataclasses.replace(r, t_c_rate_sensor=1.001 * r.t_c_rate_sensor)

    monkeypatch.setattr(gc, "race_sweep", slower)
    with pytest.raises(store.StaleStudy) as exc:
        gcs._check_race(_data("gc-race-sweeps"))
    assert "t_c_rate_sensor" in stale_message(exc, "gc-race-sweeps")


# the full recomputation ------------------------------------------------------------------------
def _agree(a, b, rtol: float, where: str = "") -> None:
    """Every number of ``a`` and ``b`` (decoded studies) agrees: arrays to ``rtol`` of their
    largest magnitude, scalars to ``rtol``."""
    if dataclasses.is_dataclass(a):
        assert type(a) is type(b), where
        for f in dataclasses.fields(a):
            _agree(getattr(a, f.name), getattr(b, f.name), rtol, f"{where}.{f.name}")
    elif isinstance(a, dict):
        assert set(a) == set(b), where
        for k in a:
            _agree(a[k], b[k], rtol, f"{where}[{k}]")
    elif isinstance(a, list | tuple):
        assert len(a) == len(b), where
        for i, (x, y) in enumerate(zip(a, b, strict=True)):
            _agree(x, y, rtol, f"{where}[{i}]")
    elif isinstance(a, np.ndarray) and a.dtype != bool:
        scale = np.nanmax(np.abs(a)) if np.any(np.isfinite(a)) else 0.0
        np.testing.assert_allclose(b, a, rtol=rtol, atol=rtol * scale, err_msg=where)
    elif isinstance(a, float):
        assert b == pytest.approx(a, rel=rtol, abs=1e-12, nan_ok=True), where
    else:
        assert np.all(a == b), where


@pytest.mark.full
@pytest.mark.parametrize("name", gcs.NAMES)
def test_full_recomputation_agrees_with_the_stored_study(tmp_path, name):
    path = store.refresh(name, path=tmp_path / f"{name}.json")
    new = json.loads(path.read_text("utf-8"))
    assert store.header_of(name, new).key == gcs.key(name)
    old = _data(name)
    old, new = ({k: x for k, x in d.items() if k != store.HEADER_KEY} for d in (old, new))
    _agree(gcs.decode(old), gcs.decode(new), store.header_of(name, _data(name)).rtol, name)


def test_load_checks_then_reads_and_names_a_stale_study(monkeypatch):
    d = gcs.load("gc-race-sweeps")
    stored = _decoded("gc-race-sweeps")["grid"]
    assert np.array_equal(d["grid"].t_c_rate_sensor, stored.t_c_rate_sensor)
    monkeypatch.setattr(gcs, "RACE_MC_RUNS", 2 * gcs.RACE_MC_RUNS)
    with pytest.raises(store.StaleStudy) as exc:
        gcs.load("gc-race-sweeps")
    stale_message(exc, "gc-race-sweeps")
    with pytest.raises(ValueError, match="name must be one of"):
        gcs.load("gc-nothing")
