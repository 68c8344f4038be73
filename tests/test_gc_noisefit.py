"""gc.fit_noise: the noise parameters of paper GC's model fitted from a record, against the
truth of the sample record made with another vibration spectrum (data/truth.json), the
calibration of its standard errors over seeds, the outliers it leaves out, and the TOML it
writes."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest
import scipy.optimize
import scipy.stats

from gyrolib import gc, records

P = gc.GyrocompassParams()
DATA = Path(__file__).resolve().parents[1] / "data"


@pytest.fixture(scope="module")
def wrong():
    truth = json.loads((DATA / "truth.json").read_text())["gc_record_wrong_spectrum.csv.gz"]
    rec = records.read_gc(DATA / "gc_record_wrong_spectrum.csv.gz")
    return rec, truth, gc.fit_noise(rec, P)


def test_wrong_spectrum_record_recovers_the_vibration_filter(wrong):
    """The record was made with α1 = 10 × the paper's (0.133 rad/s) and the paper's σ1²,
    C_as, C_in (data/make_records.py): each fitted value within 2 standard errors of it,
    the fit converged, and the likelihood rose from the paper's model."""
    _, truth, fit = wrong
    assert truth["alpha1"] == pytest.approx(10 * P.alpha1)
    made = {"alpha1": truth["alpha1"], "sigma1_sq": P.sigma1_sq, "C_as": P.C_as,
            "C_in": P.C_incl_y}
    assert fit.converged, fit.message
    assert fit.names == ("alpha1", "sigma1_sq", "C_as", "C_in")
    for name, value in made.items():
        z = (fit.value(name) - value) / fit.std_error(name)
        assert abs(z) <= 2.0, (name, fit.value(name), fit.std_error(name), value)
    # the paper's α1 is far outside the fitted one's uncertainty (the fit has power)
    assert abs(fit.value("alpha1") - P.alpha1) > 1.5 * fit.std_error("alpha1")
    assert fit.loglik > fit.loglik_start + 1000
    assert fit.params.C_incl_y == fit.params.C_incl_z == fit.value("C_in")


def test_fitted_model_calibrates_the_record(wrong):
    """With the fitted parameters the run is valid, the diagnostics fit and ω_gc is within
    3σ of the truth; with the paper's the same record is invalid and does not fit."""
    rec, truth, fit = wrong
    res = gc.calibrate(rec, fit.params)
    assert res.valid, res.reason
    assert np.all(res.fits()), res.verdict()
    assert abs(res.omega_gc - truth["omega_gc_rad_s"]) <= 3.0 * res.omega_gc_std
    paper = gc.calibrate(rec, P)
    assert not paper.valid and not np.all(paper.fits())


def test_toml_round_trip(wrong, tmp_path):
    """fit.to_toml() is read back by records.gc_params_from_toml into the fitted model,
    every field equal (floats written with repr: exact)."""
    _, _, fit = wrong
    path = tmp_path / "fitted.toml"
    path.write_text(fit.to_toml())
    back = records.gc_params_from_toml(path)
    assert back == fit.params
    assert back != P
    text = fit.to_toml()
    assert "alpha1 = " in text and "# fitted: +- " in text
    s = fit.summary()
    json.dumps(s)
    assert s["fitted"]["alpha1"]["value"] == fit.value("alpha1")


def test_standard_errors_match_the_scatter_over_seeds():
    """C_as and C_in fitted on 12 seeded 3 s records made with twice the paper's noise: the
    z-scores (fit − truth)/SE have mean square within the χ²(24)/24 99 % band (the curvature
    and the delta method give the right standard errors)."""
    made = dataclasses.replace(P, C_as=2 * P.C_as, C_incl_y=2 * P.C_incl_y,
                               C_incl_z=2 * P.C_incl_z)
    z = []
    for seed in range(300, 312):
        rec = gc.simulate_record(made, 3.0, seed=seed).record
        fit = gc.fit_noise(rec, P, fit=("C_as", "C_in"))
        assert fit.converged, fit.message
        z.append((fit.value("C_as") - made.C_as) / fit.std_error("C_as"))
        z.append((fit.value("C_in") - made.C_incl_y) / fit.std_error("C_in"))
    ms = float(np.mean(np.square(z)))
    lo, hi = scipy.stats.chi2.ppf([0.005, 0.995], len(z)) / len(z)
    assert lo <= ms <= hi, (ms, z)


def test_outliers_are_left_out():
    """The sample record's burst of 20 angle-sensor outliers (±0.5 mrad, data/truth.json) is
    left out: C_as within 3 SE of the paper's value it was made with.  Kept in, the burst
    would pull the maximum-likelihood C_as far off (the exclusion has power)."""
    rec = records.read_gc(DATA / "gc_record.csv.gz")
    fit = gc.fit_noise(rec, P, fit=("C_as",))
    assert fit.converged, fit.message
    assert fit.outliers >= 20
    assert abs(fit.value("C_as") - P.C_as) <= 3.0 * fit.std_error("C_as")

    def neg(log_c: float) -> float:
        return -gc.innovation_log_likelihood(rec, dataclasses.replace(P, C_as=np.exp(log_c)))

    raw = scipy.optimize.minimize_scalar(neg, bracket=(np.log(P.C_as), np.log(P.C_as) + 0.5),
                                         tol=1e-4)
    assert abs(np.exp(raw.x) - P.C_as) > 20.0 * fit.std_error("C_as")
