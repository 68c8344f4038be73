"""The race's claim map around a user's parameters (``race --params``): GC's time read from a
discretization shared between parameters that differ only in the measurement noise or the
prior, over a short first horizon, gives the same margins and the same thresholds as a
fresh discretization of each parameter set over 100 s (the search before the sharing)."""

from __future__ import annotations

import math
from dataclasses import replace

import pytest

from gyrolib import gc
from gyrolib import inputs as table
from gyrolib.book.ledger import claims
from gyrolib.claim_map import Claim, map_claim
from gyrolib.gc.analysis import speed_claim
from gyrolib.gc.model import discretization
from gyrolib.gc.racing import comparison
from gyrolib.gc.racing.comparison import MARGIN_MONOTONE_ROWS

P = gc.GyrocompassParams()

#: Parameter sets around which the map is drawn: two near the reference and one far from it
#: (ten times the angle sensor's noise, a slow rebalance loop, a short turn): each a
#: ``(GyrocompassParams changes, RateSensorProcedure changes)``.
FILES = {
    "sigma1_sq x2": ({"sigma1_sq": 2 * P.sigma1_sq}, {}),
    "near": ({"sigma1_sq": 0.8 * P.sigma1_sq}, {"T_settle": 30.0}),
    "far": ({"C_as": 10 * P.C_as}, {"T_rot": 2.0, "T_settle": 3.0, "loop_bandwidth": 1.0,
                                    "rate_noise": 6e-17}),
}


def _forget() -> None:
    """Empty the memos of GC's and the rival's times and of the discretizations."""
    for fn in (comparison._gc_time, comparison._rate_part_cached, comparison._rate_time,
               discretization.kept_discretization, discretization.kept_affine_model):
        fn.cache_clear()


def _previous(mp: pytest.MonkeyPatch) -> None:
    """The evaluation before the sharing: every parameter set discretized afresh over the
    first horizon of 100 s (``kept_discretization`` keyed on the whole parameter set)."""
    _forget()
    mp.setattr(speed_claim, "kept_affine_model",
               lambda p, n, method="van_loan":
               discretization.kept_discretization(p, n, method).model)
    mp.setattr(speed_claim, "_SHORT_HORIZON", 100.0)


def _objects(name: str) -> dict:
    dp, dproc = FILES[name]
    return {**table.reference_objects(),
            "GyrocompassParams": replace(P, **dp),
            "RateSensorProcedure": replace(gc.RateSensorProcedure(), **dproc)}


#: GC's times where the sharing and the horizons matter: the noises and priors that share a
#: discretization, the instrument constants (a larger state), a time past 40 s and past 100 s.
CASES = [{}, {"C_as": 10 * P.C_as}, {"C_as": 0.1 * P.C_as}, {"sigma1_sq": 3 * P.sigma1_sq},
         {"sigma_hf_scale": 7e-5}, {"sigma_as_offset": 3e-5}, {"sigma_incl_bias": 1e-3},
         {"C_incl_y": 5 * P.C_incl_y, "C_incl_z": 5 * P.C_incl_z},
         {"sigma_gc0": 3 * P.sigma_gc0}, {"sigma_hf_scale": 9e-5, "C_as": 5 * P.C_as}]


def test_gc_time_is_the_covariance_analysis_time():
    """GC's time of the margin against the full covariance analysis read by
    ``time_to_sigma`` (a separate path: its own discretization over the whole horizon), and
    the shared discretization really shared (power: the C_as case has another r)."""
    proc = gc.RateSensorProcedure()
    _forget()
    times = []
    for c in CASES:
        p = replace(P, **c)
        t = comparison._gc_time(p, proc.sigma_c, proc.t_max)
        full = comparison._gc_part(p, proc.sigma_c, proc.t_max)[0]
        assert t == pytest.approx(full, rel=1e-12), c
        times.append(t)
    assert max(times) > 100.0 and any(40.0 < t < 100.0 for t in times)
    a = discretization.kept_affine_model(P, 1000)
    b = discretization.kept_affine_model(replace(P, C_as=10 * P.C_as), 1000)
    c = discretization.kept_affine_model(replace(P, sigma1_sq=2 * P.sigma1_sq), 1000)
    assert b.Phi0 is a.Phi0 and b.r[0] == pytest.approx(10 * a.r[0], rel=1e-12)
    assert c.Phi0 is not a.Phi0 and not (c.Qd0 == a.Qd0).all()


def test_gc_time_is_the_previous_evaluations_to_the_bit(monkeypatch):
    """Each step's Φ and Qd depend on its own nominal angle only: the 40-s first horizon and
    the shared discretization give the previous times to the bit."""
    proc = gc.RateSensorProcedure()
    _forget()
    now = [comparison._gc_time(replace(P, **c), proc.sigma_c, proc.t_max) for c in CASES]
    with monkeypatch.context() as mp:
        _previous(mp)
        before = [comparison._gc_time(replace(P, **c), proc.sigma_c, proc.t_max)
                  for c in CASES]
    _forget()
    assert now == before


def _thresholds(objs: dict, rows: tuple[str, ...]) -> dict:
    claim = claims.CLAIMS["gc.faster_percent"]
    c = Claim(claim.id, claim.margin, rows, claim.meaning, claim.unit)
    m = map_claim(c, objs, n_grid=5, rtol=1e-2, n_box=0,
                  monotone=[n for n in MARGIN_MONOTONE_ROWS if n in rows])
    return {(t.input, t.holds_when): t.value for t in m.thresholds}


def _compare(name: str, rows: tuple[str, ...], monkeypatch) -> None:
    objs = _objects(name)
    _forget()
    now = _thresholds(objs, rows)
    with monkeypatch.context() as mp:
        _previous(mp)
        before = _thresholds(objs, rows)
    _forget()
    assert now.keys() == before.keys(), name
    # the same margins to the bit give the same bisections; the stated tolerance is the
    # search's own (rtol 1e-2 of the command's map), far wider than any rounding
    for k, x in before.items():
        assert math.isclose(now[k], x, rel_tol=1e-12), (name, k, now[k], x)
    assert now, f"{name}: no threshold among {rows}: the comparison would have no power"


def test_map_around_a_far_parameter_file_has_the_previous_thresholds(monkeypatch):
    _compare("far", ("gc.C_as", "gc.sigma_tilt0", "gc.sigma1_sq"), monkeypatch)


@pytest.mark.full
@pytest.mark.parametrize("name", ["sigma1_sq x2", "near", "far"])
def test_maps_around_parameter_files_have_the_previous_thresholds(name, monkeypatch):
    _compare(name, ("gc.sigma1_sq", "gc.alpha1", "gc.C_as", "gc.sigma_tilt0",
                    "gc.sigma_hf_scale", "race.sigma_scale", "race.overhead"), monkeypatch)
