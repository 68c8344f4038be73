"""Global sensitivity analysis (:mod:`gyrolib.sensitivity`, ``gc.sensitivity``,
``rsf.sensitivity``).

References independent of the code under test: the closed-form Sobol' indices of the Ishigami
function (Ishigami & Homma 1990; Sobol' & Levitan 1999), with a deliberately wrong estimator
(input columns shuffled) that must fail the same check; the serial run as the reference for
the executors (a Dask LocalCluster of 2 worker processes, a process pool); the ledger's own
calls and constants for the GC outputs; Eq. (7) through ``rsf.compensation_share`` for RSF.
"""

from __future__ import annotations

import json
import math
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor
from dataclasses import replace

import numpy as np
import pytest

from gyrolib import gc, inputs, rsf, sensitivity
from gyrolib.book.ledger import gc as lgc
from gyrolib.gc.analysis import sensitivity_study
from gyrolib.units import to_si

A_ISH, B_ISH = 7.0, 0.1


def ishigami(points: np.ndarray, context: object) -> np.ndarray:
    x1, x2, x3 = points.T
    return (np.sin(x1) + A_ISH * np.sin(x2) ** 2
            + B_ISH * x3**4 * np.sin(x1)).reshape(-1, 1)


def ishigami_shuffled(points: np.ndarray, context: object) -> np.ndarray:
    """The wrong estimator: the model reads the input columns in another order."""
    return ishigami(points[:, [1, 2, 0]], context)


def ishigami_exact() -> tuple[dict[str, float], dict[str, float]]:
    """Closed-form first-order and total indices of the Ishigami function on [−π, π]³."""
    a, b, pi = A_ISH, B_ISH, math.pi
    v1 = 0.5 * (1 + b * pi**4 / 5) ** 2
    v2 = a**2 / 8
    v13 = b**2 * pi**8 * (1 / 18 - 1 / 50)
    var = v1 + v2 + v13
    return ({"x1": v1 / var, "x2": v2 / var, "x3": 0.0},
            {"x1": (v1 + v13) / var, "x2": v2 / var, "x3": v13 / var})


ISH_INPUTS = tuple(sensitivity.SobolInput(f"x{i}", f"x{i}", 0.0, -math.pi, math.pi)
                   for i in (1, 2, 3))


def ishigami_study(evaluate) -> sensitivity.SensitivityResult:
    return sensitivity.run_study("ishigami", ISH_INPUTS, ("y",), ("1",), evaluate, None, 4096,
                                 seed=3, chunk_size=4096, second_order=False)


def misses(result: sensitivity.SensitivityResult) -> list[str]:
    """The indices whose confidence interval does not hold the exact value."""
    s1, st = ishigami_exact()
    out = []
    for name in s1:
        if s1[name] not in result.first_order["y"][name]:
            out.append(f"S1[{name}]")
        if st[name] not in result.total["y"][name]:
            out.append(f"ST[{name}]")
    return out


def test_ishigami_indices_lie_within_their_intervals():
    """SALib's estimator through run_study: all six exact indices inside their 95 % bootstrap
    intervals, and the intervals are informative (narrower than 0.05)."""
    r = ishigami_study(ishigami)
    assert misses(r) == []
    assert r.max_conf() < 0.05


def test_a_wrong_estimator_fails_the_ishigami_check():
    """Power: with the input columns shuffled, the same check fails on most indices."""
    assert len(misses(ishigami_study(ishigami_shuffled))) >= 4


def test_unit_sample_is_saltelli_layout_and_prefix_stable():
    """n (2d + 2) rows; each block is A, AB_j (column j from B), BA_j (column j from A), B;
    a larger n extends the same sequence."""
    u = sensitivity.unit_sample(3, 8, seed=1)
    assert u.shape == (64, 3)
    block = u[:8]
    a, b = block[0], block[-1]
    np.testing.assert_allclose(block[1], [b[0], a[1], a[2]], rtol=1e-15, atol=0)   # AB_0
    np.testing.assert_allclose(block[4], [a[0], b[1], b[2]], rtol=1e-15, atol=0)   # BA_0
    np.testing.assert_allclose(sensitivity.unit_sample(3, 16, seed=1)[:64], u, rtol=1e-15, atol=0)


def test_sobol_input_ranges_are_the_tables():
    """A row of the table of inputs as a Sobol' input: a scale-type row a factor of the given
    value on its scale (log-uniform, median at the value), an absolute row its own range
    (uniform); a wrong scale (uniform on a log row) would put the median elsewhere."""
    a = inputs.row("gc.alpha1")
    p = a.sobol_input(2.0)
    assert (p.low, p.high) == pytest.approx((2.0 * a.low, 2.0 * a.high))
    assert p.distribution == "loguniform" and p.value(0.5) == pytest.approx(2.0)
    assert p.value(0.25) == pytest.approx(2.0 / math.sqrt(math.sqrt(a.high / a.low)))
    assert 0.5 * (p.low + p.high) != pytest.approx(2.0, rel=0.1)    # uniform would miss
    x = inputs.row("gc.xi1").sobol_input(0.7)
    assert (x.low, x.high, x.distribution) == (0.1, 1.0, "uniform") and x.nominal == 0.7


@pytest.mark.parametrize("call, exc, name", [
    (lambda: sensitivity.unit_sample(3, 6, 0), ValueError, "n must be a power of 2"),
    (lambda: sensitivity.SobolInput("a", "a", 1.0, 2.0, 1.0), ValueError, "low must be < high"),
    (lambda: sensitivity.SobolInput("a", "a", 1.0, -1.0, 1.0, "loguniform"), ValueError,
     "low must"),
    (lambda: inputs.row("gc.eq1_sign").sobol_input(), ValueError, "gc.eq1_sign is a reading"),
    (lambda: sensitivity.run_study("m", ISH_INPUTS, ("y",), ("1",), ishigami, None, 4, 0,
                           executor="dask"), TypeError, "executor must be"),
    (lambda: sensitivity.run_study("m", ISH_INPUTS, ("y",), ("1",), ishigami, None, 4, 0,
                           chunk_size=0), ValueError, "chunk_size must be"),
    (lambda: sensitivity.result_from_dict({"model": "x"}), ValueError, "data lacks"),
])
def test_bad_input_is_rejected_by_name(call, exc, name):
    with pytest.raises(exc, match="^" + name):
        call()


# GC and RSF studies ------------------------------------------------------------------------
def small_gc(executor=None, chunk_size=5) -> sensitivity.SensitivityResult:
    """A small GC study: 4 base points (112 runs) of 2-s analyses, t_c to a level reached
    within them (so that both outputs vary)."""
    return gc.sensitivity(4, seed=2, executor=executor, t_end=2.0, t_max=4.0,
                          level=float(to_si(0.05, "arcsec_paper/s")), chunk_size=chunk_size)


def assert_same_indices(a: sensitivity.SensitivityResult, b: sensitivity.SensitivityResult) -> None:
    np.testing.assert_allclose(a.values, b.values, rtol=1e-12, atol=0.0)
    for table in ("first_order", "total", "second_order"):
        ta, tb = getattr(a, table), getattr(b, table)
        for o in a.outputs:
            assert ta[o].keys() == tb[o].keys()
            for k in ta[o]:
                assert ta[o][k].value == pytest.approx(tb[o][k].value, rel=1e-12, abs=1e-15)
                assert ta[o][k].conf == pytest.approx(tb[o][k].conf, rel=1e-12, abs=1e-15)


def test_dask_local_cluster_gives_the_serial_indices():
    """The same small study on a dask.distributed LocalCluster with 2 worker processes, through
    Client.get_executor() unchanged: the serial values and indices within 1e-12."""
    distributed = pytest.importorskip("dask.distributed")
    serial = small_gc()
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=":0") as cluster, \
            distributed.Client(cluster) as client:
        on_dask = small_gc(client.get_executor(), chunk_size=3)
    assert_same_indices(serial, on_dask)


def test_process_pool_and_chunk_size_do_not_change_the_result():
    """A standard-library process pool and other chunk sizes: the serial indices (RSF)."""
    serial = rsf.sensitivity(64, seed=4)
    with ProcessPoolExecutor(2) as ex:
        assert_same_indices(serial, rsf.sensitivity(64, seed=4, executor=ex, chunk_size=7))
    with ThreadPoolExecutor(3) as ex:
        assert_same_indices(serial, rsf.sensitivity(64, seed=4, executor=ex, chunk_size=100))


def test_progress_counts_every_point():
    seen = []
    r = rsf.sensitivity(16, seed=0, chunk_size=50, progress=seen.append)
    assert sum(seen) == len(r.values) == 16 * (2 * len(r.inputs) + 2)


def test_gc_outputs_are_the_ledgers_quantities():
    """σ_gc(100 s) and t_c at the paper's values are what the ledger computes: the same level
    and bound, and the covariance analysis read the ledger's way."""
    assert sensitivity_study._LEVEL == lgc.SIGMA_C
    assert sensitivity_study._T_MAX == lgc.T_BOUND
    p = gc.GyrocompassParams()
    s, t = gc.sensitivity_outputs(p)
    cov = gc.covariance_analysis(p, 100.0, store_every=100_000)
    assert s == pytest.approx(cov.std_at("omega_gc", 100.0), rel=1e-12)
    assert t == pytest.approx(gc.time_to_sigma(cov, "omega_gc", lgc.SIGMA_C), rel=1e-12)


def test_gc_t_c_beyond_the_horizon_is_looked_for_then_censored():
    """σ has not crossed σ_c by t_end = 10 s (it does at about 24 s): t_c from a longer
    analysis, as gc.time_to_level finds it; not crossed by t_max = 20 s: recorded as t_max."""
    p = gc.GyrocompassParams()
    lvl = float(to_si(2e-3, "arcsec_paper/s"))
    _, t_short = gc.sensitivity_outputs(p, t_end=10.0, t_max=20.0)
    assert t_short == 20.0
    _, t_long = gc.sensitivity_outputs(p, t_end=10.0, t_max=40.0)
    assert 20.0 < t_long == pytest.approx(gc.time_to_level(p, lvl, 40.0), rel=1e-12)


def test_gc_inputs_are_the_tables_uncertain_rows():
    """Paper GC's uncertain rows of the table, each over its row's range around the given
    parameters (a user's σ1² twice the paper's moves the range with it; ξ1 keeps its
    absolute range), on its row's scale; no operating row (the filter's priors) is
    sampled."""
    rows = inputs.rows(prefix="gc.", kind="uncertain")
    got = {x.name: x for x in gc.sensitivity_inputs()}
    assert list(got) == [r.name.removeprefix("gc.") for r in rows]
    assert not {"sigma_psi0", "sigma_gc0", "sigma_tilt0"} & set(got)
    for r in rows:
        x = got[r.name.removeprefix("gc.")]
        assert (x.low, x.high) == pytest.approx(r.bounds(x.nominal)), r.name
        assert x.distribution == ("loguniform" if r.scale == "log" else "uniform"), r.name
    p = gc.GyrocompassParams()
    mine = {x.name: x for x in gc.sensitivity_inputs(replace(p, sigma1_sq=2 * p.sigma1_sq,
                                                             xi1=0.5))}
    assert mine["sigma1_sq"].high == pytest.approx(2 * got["sigma1_sq"].high, rel=1e-12)
    assert (mine["xi1"].low, mine["xi1"].high) == (got["xi1"].low, got["xi1"].high)
    q = sensitivity_study._at(p, ("C_incl", "sigma_psi0"), np.array([3.0, 1e-4]))
    assert (q.C_incl_y, q.C_incl_z, q.sigma_psi0) == (3.0, 3.0, 1e-4)


def test_rsf_outputs_are_eq7_and_the_claims_share():
    """δK of Eq. (7) and the share as rsf.compensation_share computes it, at the worked
    example; with ε1 sampled too, the share's indices differ from δK's only through ε1."""
    w = float(to_si(900.0, "deg/s"))
    x = {i.name: i.nominal for i in rsf.sensitivity_inputs()}
    op = {"period": 5.0, "omega_x": w, "omega_unc": float(to_si(300.0, "deg/s"))}
    dk, share = rsf.sensitivity_outputs(**x, **op)
    assert share == pytest.approx(float(rsf.compensation_share([w]).share[0]), rel=1e-12)
    assert dk == pytest.approx(rsf.delta_k(x["eps0_gs"], x["encoder_error"], w, 5.0,
                                           x["eps1_gs"], op["omega_unc"]))
    r = rsf.sensitivity(256, seed=1)
    assert r.total["delta_k"]["eps1"].value == pytest.approx(0.0, abs=1e-9)
    assert r.total["share"]["eps1"].value > 0.2
    assert dict(r.conditions) == pytest.approx(op)


def test_rsf_ranges_are_the_tables():
    """The four uncertain rows Eq. (7) and the share read, each over its row's range (half
    to twice a data sheet's value, log-uniform); the operating point is not sampled."""
    got = {x.name: x for x in rsf.sensitivity_inputs()}
    assert set(got) == {"eps0_gs", "encoder_error", "eps1_gs", "eps1"}
    for name, key in (("rsf.gs_bias", "eps0_gs"), ("rsf.encoder_error", "encoder_error"),
                      ("rsf.eps1_gs", "eps1_gs"), ("rsf.eps1", "eps1")):
        r, x = inputs.row(name), got[key]
        assert x.nominal == pytest.approx(r.reference, rel=1e-12)
        assert (x.low, x.high) == pytest.approx(r.bounds()), name
        assert x.distribution == "loguniform"


def test_rsf_elasticities_closed_form():
    """δK = [(ε0 + ε1,GS ω_unc) Δt + Δγ_enc]/(ω_x Δt): ∂ln δK/∂ln ω_x = −1, and the shares of
    the numerator N give the other elasticities: ε0 Δt/N, ε1,GS ω_unc Δt/N (for ε1,GS and
    ω_unc alike), Δγ_enc/N (and −Δγ_enc/N for Δt); the share 1 − δK/ε1 moves by
    −(δK/(ε1 − δK)) times δK's elasticity, and +δK/(ε1 − δK) with ε1."""
    x = {i.name: i.nominal for i in rsf.sensitivity_inputs()}
    x |= {"period": 5.0, "omega_x": float(to_si(900.0, "deg/s")),
          "omega_unc": float(to_si(300.0, "deg/s"))}
    e = rsf.sensitivity_elasticities()
    n = (x["eps0_gs"] + x["eps1_gs"] * x["omega_unc"]) * x["period"] + x["encoder_error"]
    want = {"omega_x": -1.0, "eps0_gs": x["eps0_gs"] * x["period"] / n,
            "eps1_gs": x["eps1_gs"] * x["omega_unc"] * x["period"] / n,
            "omega_unc": x["eps1_gs"] * x["omega_unc"] * x["period"] / n,
            "encoder_error": x["encoder_error"] / n, "period": -x["encoder_error"] / n,
            "eps1": 0.0}
    dk = n / (x["omega_x"] * x["period"])
    k = dk / (x["eps1"] - dk)
    for name, el in want.items():
        assert e.of("delta_k", name) == pytest.approx(el, abs=2e-4), name
        share_el = k if name == "eps1" else -k * el
        assert e.of("share", name) == pytest.approx(share_el, abs=2e-4), name
    # the finding: the GS gyro's scale error times ω_unc carries 55 % of δK at the
    # worked example, the encoder 43 %
    assert want["eps1_gs"] == pytest.approx(0.55, abs=0.005)
    assert want["encoder_error"] == pytest.approx(0.43, abs=0.005)


def test_gc_elasticities_fixed_inputs_and_ranking():
    """The elasticities of t_c at the paper's values: per relative change σ1² moves t_c about
    four times as much as C_as; the fixed inputs (the filter's priors among them) are
    included, H and f through H/f nearly opposite; a second, independent estimate from ±10 %
    secants agrees."""
    e = gc.sensitivity_elasticities()
    assert set(sensitivity_study.FIXED_INPUTS) <= set(e.inputs)
    ratio = e.of("t_c", "sigma1_sq") / e.of("t_c", "C_as")
    assert 3.0 < ratio < 6.0
    assert e.of("t_c", "H") == pytest.approx(-e.of("t_c", "f"), rel=0.05)
    p = gc.GyrocompassParams()
    for name in ("C_as", "sigma1_sq"):
        hi = gc.sensitivity_outputs(replace(p, **{name: 1.1 * getattr(p, name)}))[1]
        lo = gc.sensitivity_outputs(replace(p, **{name: 0.9 * getattr(p, name)}))[1]
        secant = (math.log(hi) - math.log(lo)) / (math.log(1.1) - math.log(0.9))
        assert e.of("t_c", name) == pytest.approx(secant, abs=0.03), name


def test_elasticities_bad_input_and_power():
    from gyrolib.sensitivity import elasticities
    e = elasticities({"a": 2.0}, lambda a: (a**3,), ("y",))
    assert e.of("y", "a") == pytest.approx(3.0, rel=1e-4)
    assert e.of("y", "a") != pytest.approx(2.0, rel=1e-2)     # a wrong exponent is seen
    with pytest.raises(ValueError, match="nominal"):
        elasticities({"a": -1.0}, lambda a: (a,), ("y",))
    with pytest.raises(ValueError, match="outputs"):
        elasticities({"a": 1.0}, lambda a: (a, a), ("y",))
    with pytest.raises(ValueError, match="rel_step"):
        elasticities({"a": 1.0}, lambda a: (a,), ("y",), rel_step=0.7)
    with pytest.raises(ValueError, match="name"):
        e.of("y", "b")

def test_results_file_round_trip_and_recheck_has_power():
    """JSON round trip; the recheck finds a stored value 1e-6 off (the chapter's check at
    1e-9 would fail the build) and none on the true file."""
    r = rsf.sensitivity(32, seed=5)
    back = sensitivity.result_from_dict(json.loads(json.dumps(r.to_dict())))
    assert_same_indices(r, back)
    assert rsf.recheck_sensitivity(back, k=6, seed=1).max_rel_diff < 1e-12
    stale = back.values.copy()
    stale *= 1 + 1e-6
    bad = replace(back, values=stale)
    assert rsf.recheck_sensitivity(bad, k=6, seed=1).max_rel_diff > 1e-9
    with pytest.raises(ValueError, match=r"^result must be a GC study"):
        gc.recheck_sensitivity(back)


def test_rsf_sweeps_take_an_executor():
    """The period sweep on a thread pool equals the serial sweep."""
    rec = rsf.simulate_flight(rsf.SimulationConfig(duration=10.0, n_runs=2), seed=0)
    serial = rsf.sweep_correction_period(rec, [1.0, 2.0, 5.0])
    with ThreadPoolExecutor(2) as ex:
        par = rsf.sweep_correction_period(rec, [1.0, 2.0, 5.0], executor=ex)
    np.testing.assert_allclose(par.rms, serial.rms, rtol=1e-12)
    assert par.net_floor == serial.net_floor
    with pytest.raises(TypeError, match=r"^executor must be"):
        rsf.sweep_roll_rate([10.0], seed=0, executor=2)


def test_a_grown_study_equals_a_fresh_one_and_refuses_another_study():
    small = rsf.sensitivity(16, seed=6)
    grown = rsf.sensitivity(128, seed=6, previous=small)
    assert_same_indices(rsf.sensitivity(128, seed=6), grown)
    with pytest.raises(ValueError, match=r"^previous must be the same study"):
        rsf.sensitivity(128, seed=7, previous=small)
    with pytest.raises(ValueError, match=r"^previous must have n <= 8"):
        rsf.sensitivity(8, seed=6, previous=small)
