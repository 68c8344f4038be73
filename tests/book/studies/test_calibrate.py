"""The calibrate chapter's stored studies held to the code (gyrolib.book.studies.calibrate
over gyrolib.store).

Everyday tier: each stored study is fresh (its key, then its fingerprint points recomputed:
the noise fit's log-likelihood and filter run at the stored fitted values, two seeds of the
convention study, one defect of the fault study), and each check is shown to fail by the
study's name and with its refresh command when what it reads moves: a model constant
(Omega_v x 1.1) through the key, and, without the key, through the recomputed points
themselves.  Full tier: each study recomputed whole (into ``tmp_path``) agrees with the
stored one within its declared tolerance.  The package's files are only read.
"""

from __future__ import annotations

import copy
import json
import math

import numpy as np
import pytest

from gyrolib import store
from gyrolib.book import studies as book_studies
from gyrolib.book.studies import calibrate as cal
from gyrolib.gc.model.params import GyrocompassParams
from tests.support.stored_studies import patch_default, stale_message

#: The least number of points each check compares (a weaker check fails this test).
MIN_POINTS = {"calibrate-fit-noise": 20, "calibrate-convention": 24, "calibrate-faults": 20}


def _data(name: str) -> dict:
    return json.loads(store.study(name).file.read_text("utf-8"))




# fresh -----------------------------------------------------------------------------------------
def test_the_chapter_studies_are_in_the_one_list():
    assert cal in book_studies.CHAPTER_MODULES
    assert all(n in book_studies.NAMES for n in cal.NAMES)
    assert all(n in store.registered() for n in cal.NAMES)


@pytest.mark.parametrize("name", cal.NAMES)
def test_each_stored_study_is_fresh(name):
    """Key and fingerprint points of the package's file, recomputed; the header says how it
    was computed."""
    assert store.check(name) >= MIN_POINTS[name]
    h = store.header_of(name, _data(name))
    assert h.key == cal.key(name) and h.rtol == 1e-6
    assert h.version and h.cpu_class and h.date[:4] == "2026" and h.cost_cpu_s > 2.0


def test_the_stored_noise_fit_is_the_fit_the_chapter_shows(tmp_path):
    """The NoiseFit rebuilt from the file: converged, its log-likelihood above the start's,
    its values near the wide-spectrum record's truth (alpha1 x 10 the paper's) within a
    few of their standard errors, and its TOML read back as the same parameters."""
    from gyrolib import records

    data = _data("calibrate-fit-noise")
    nf = cal.noise_fit(data)
    assert nf.converged and nf.loglik > nf.loglik_start
    truth = json.loads((cal.RECORDS / "truth.json").read_text())[cal.FIT["record"]]
    assert abs(nf.value("alpha1") - truth["alpha1"]) < 3 * nf.carried_std_error("alpha1")
    assert data["verdict"]["status"] == "ok"
    sigma = data["verdict"]["sigma"]
    assert math.isclose(sigma, math.sqrt(sum(x * x for x in
                                             data["verdict"]["sigma_parts"].values())),
                        rel_tol=1e-12)
    assert abs(data["verdict"]["estimate"] - truth["omega_gc_rad_s"]) < 3 * sigma
    toml = tmp_path / "fitted.toml"
    toml.write_text(nf.to_toml())
    back = records.gc_params_from_toml(toml)
    for f in ("alpha1", "sigma1_sq", "C_as", "C_incl_y", "C_incl_z"):
        assert math.isclose(getattr(back, f), getattr(nf.params, f), rel_tol=1e-12), f


def test_the_stored_convention_study_rebuilds():
    st = cal.convention(_data("calibrate-convention"))
    assert st.seeds.tolist() == list(cal.CONVENTION["seeds"])
    s = st.summary()
    # Eq. (5)'s prediction holds in every run (the chapter quotes the largest deviation)
    assert abs(s["shift_over_prediction"] - 1) < 0.05
    assert s["rms_z_wrong"] > 3 * s["rms_z_right"]


# a model constant changed: the key -------------------------------------------------------------
@pytest.mark.parametrize("name", cal.NAMES)
def test_omega_v_times_1_1_makes_each_study_stale_by_its_key(monkeypatch, name):
    patch_default(monkeypatch, GyrocompassParams, "Omega_v", 1.1 * 5.9e-5)
    with pytest.raises(store.StaleStudy) as exc:
        store.check(name)
    assert "gyrolib.gc.model.params" in stale_message(exc, name)


def test_what_the_chapter_reads_stops_on_a_stale_study(monkeypatch):
    """The chapter reads each study by ``load``: a changed table default (C_as x 1.1, a row
    of the table) stops it with the study's name and refresh command before any number is
    read."""
    patch_default(monkeypatch, GyrocompassParams, "C_as", 1.1 * 2.0e-13)
    for name in cal.NAMES:
        with pytest.raises(store.StaleStudy) as exc:
            cal.load(name)
        assert "gyrolib.gc.model.params" in stale_message(exc, name)


def test_a_changed_setting_of_a_study_makes_it_stale_and_only_it(monkeypatch):
    """The studies' own settings are in their keys: a defect of another size makes the fault
    study stale, not the convention study."""
    faults = (("null offset (″)", 5.0), *cal.FAULTS[1:])
    monkeypatch.setitem(cal._READS["calibrate-faults"][1], "FAULTS", faults)
    with pytest.raises(store.StaleStudy) as exc:
        store.check_key("calibrate-faults", store.header_of(
            "calibrate-faults", _data("calibrate-faults")).key, cal.key("calibrate-faults"))
    assert "constants" in stale_message(exc, "calibrate-faults")
    assert cal.key("calibrate-convention") == store.header_of(
        "calibrate-convention", _data("calibrate-convention")).key


def test_a_changed_record_makes_the_noise_fit_stale(monkeypatch, tmp_path):
    import shutil

    for f in (cal.FIT["record"], "truth.json"):
        shutil.copy(cal.RECORDS / f, tmp_path / f)
    monkeypatch.setattr(cal, "RECORDS", tmp_path)
    assert store.check_key("calibrate-fit-noise", cal.key("calibrate-fit-noise"),
                           store.header_of("calibrate-fit-noise",
                                           _data("calibrate-fit-noise")).key) is None
    (tmp_path / cal.FIT["record"]).write_bytes(b"")
    with pytest.raises(store.StaleStudy) as exc:
        store.check("calibrate-fit-noise")
    assert "record" in stale_message(exc, "calibrate-fit-noise")


# without the key: the fingerprint points themselves ---------------------------------------------
def test_omega_v_times_1_1_breaks_the_convention_points(monkeypatch):
    data = _data("calibrate-convention")
    assert cal._check_convention(data) == 24
    patch_default(monkeypatch, GyrocompassParams, "Omega_v", 1.1 * 5.9e-5)
    with pytest.raises(store.StaleStudy) as exc:
        cal._check_convention(data)
    assert "of seed 1" in stale_message(exc, "calibrate-convention")


def test_omega_v_times_1_1_breaks_the_fault_points(monkeypatch):
    data = _data("calibrate-faults")
    assert cal._check_faults(data) >= MIN_POINTS["calibrate-faults"]
    patch_default(monkeypatch, GyrocompassParams, "Omega_v", 1.1 * 5.9e-5)
    with pytest.raises(store.StaleStudy) as exc:
        cal._check_faults(data)
    assert "null offset" in stale_message(exc, "calibrate-faults")


@pytest.mark.parametrize(("field", "factor", "caught_by"), [
    ("C_as", 1.05, "the log-likelihood"),      # well identified: the likelihood falls
    ("alpha1", 1.01, "omega_gc at the fitted values"),   # flat likelihood: the estimate
])
def test_a_moved_fit_breaks_the_noise_fit_points(field, factor, caught_by):
    """The stored fit with one value moved (a fit the code would not find there): the
    points recomputed at the stored values no longer agree.  The log-likelihood is flat at
    the optimum, so a small move of a poorly identified alpha1 is caught by the estimate."""
    data = copy.deepcopy(_data("calibrate-fit-noise"))
    data["noise_fit"]["params"][field] *= factor
    with pytest.raises(store.StaleStudy) as exc:
        cal._check_fit(data)
    assert caught_by in stale_message(exc, "calibrate-fit-noise")


# the full recomputation -------------------------------------------------------------------------
def _agree(name: str, was: object, now: object, rtol: float, atol: float, where: str = ""):
    """Every number of ``now`` within the tolerance of ``was``; everything else equal."""
    if isinstance(was, dict):
        assert isinstance(now, dict) and set(was) == set(now), where
        for k in was:
            _agree(name, was[k], now[k], rtol, atol, f"{where}.{k}")
    elif isinstance(was, (list, tuple)):
        assert isinstance(now, (list, tuple)) and len(was) == len(now), where
        for i, (a, b) in enumerate(zip(was, now, strict=True)):
            _agree(name, a, b, rtol, atol, f"{where}[{i}]")
    elif isinstance(was, float) and not isinstance(now, bool):
        assert isinstance(now, (int, float)), where
        if not (math.isnan(was) and math.isnan(now)):
            assert abs(now - was) <= atol + rtol * max(abs(was), abs(now)), (where, was, now)
    else:
        assert was == now, (where, was, now)


@pytest.mark.full
@pytest.mark.parametrize("name", cal.NAMES)
def test_the_full_recomputation_agrees_with_the_stored_study(tmp_path, name):
    """Each study recomputed whole (the convention and fault studies on two processes),
    compared with the stored one within its declared tolerance, then checked."""
    from concurrent.futures import ProcessPoolExecutor

    path = tmp_path / f"{name}.json"
    with ProcessPoolExecutor(max_workers=2) as pool:
        store.refresh(name, executor=pool, path=path)
    new, old = json.loads(path.read_text("utf-8")), _data(name)
    h = store.header_of(name, old)
    assert store.header_of(name, new).key == h.key
    new.pop(store.HEADER_KEY)
    old.pop(store.HEADER_KEY)
    _agree(name, old, new, h.rtol, h.atol)
    assert store.check(name, path) >= MIN_POINTS[name]


def test_the_convention_study_round_trips_through_its_file():
    """What the file holds of a convention study (here two short seeds) rebuilds it."""
    import gyrolib.book.studies.calibrate as module

    st = module.convention_study(wiring="z,y", t_end=5.0, seeds=(1, 2))
    d = module._convention_dict(st)
    back = module.convention(d)
    for f in module._CONVENTION_FIELDS:
        np.testing.assert_array_equal(getattr(back, f), getattr(st, f))
    assert back.summary() == st.summary()
