"""One record of each coverage study, shared by the tests (two fixed seeds
each) and ``benchmarks/bench_coverage.py`` (at least 100 seeds each): made with every
constant drawn from its prior, so that the prior is part of the truth, and judged by the
σ the tool prints."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from gyrolib import gc, rsf, stats
from gyrolib.units import ARCSEC_PAPER, G0

#: The command line's default priors of ``calibrate gc`` (gyrolib.inputs' rows).
GC_PRIORS = {"sigma_hf_scale": 1e-3, "sigma_as_offset": 20.0 * ARCSEC_PAPER,
             "sigma_incl_bias": 0.5e-3 * G0}

#: The fitted-noise study's truth: the paper's vibration with α1 × 5 and σ1² × 4.
FIT_TRUTH = {"alpha1": 5.0, "sigma1_sq": 4.0}


def rsf_case(seed: int, duration: float = 30.0, period: float = 1.0) -> dict:
    """A flight of paper RSF's simulation with the sensors' errors drawn from their
    tolerances (``errors="random"``), calibrated from its record; ``z`` of eps1_hat_mean
    by its total standard uncertainty (:func:`gyrolib.rsf.eps1_uncertainty`)."""
    cfg = rsf.SimulationConfig(errors="random", duration=duration)
    sim = rsf.simulate_flight(cfg, seed=seed)
    res = rsf.calibrate(rsf.record_from_simulation(sim), period)
    u = rsf.eps1_uncertainty(res, cfg)
    e1 = float(sim.eps1_sins[0])
    return {"z": (u.mean - e1 / (1.0 + e1)) / u.std, "valid": u.valid,
            "z_sem": (u.mean - e1 / (1.0 + e1)) / res.eps1_stats()["sem"]}


def gc_case(seed: int, t_end: float = 100.0) -> dict:
    """A record of paper GC's truth model (ψ, ω_gc, δ, γ drawn from P(0)) with an angle
    offset, inclinometer biases and a gain error drawn from the command's priors, calibrated
    with those priors; ``z`` of ω̂_gc by its σ."""
    p = dataclasses.replace(gc.GyrocompassParams(), **GC_PRIORS)
    sim = gc.simulate_record(p, t_end, seed)
    rng = np.random.default_rng(10_000 + seed)
    r = sim.record
    kappa = rng.normal(0.0, p.sigma_hf_scale)
    rec = gc.GCRecord(t=r.t, angle_sensor=(1.0 + kappa) * r.angle_sensor
                      + rng.normal(0.0, p.sigma_as_offset),
                      inclinometer_y=r.inclinometer_y + rng.normal(0.0, p.sigma_incl_bias),
                      inclinometer_z=r.inclinometer_z + rng.normal(0.0, p.sigma_incl_bias))
    res = gc.calibrate(rec, p)
    truth = float(sim.truth[-1, 3])
    return {"z": (res.omega_gc - truth) / res.omega_gc_std, "valid": bool(res.valid),
            "codes": list(res.reason_codes)}


def fit_record(seed: int, t_end: float = 100.0, damaged: bool = False
               ) -> tuple[gc.SimulatedRecord, gc.GCRecord]:
    """The fitted-noise study's record of ``seed``: the truth model with α1 × 5 and σ1² × 4
    (:data:`FIT_TRUTH`), and its readings as a record, clean or with the damage of a real
    log (``damaged``: :func:`tests.support.gc_faults.damage` with its defaults scaled to
    ``t_end``: a gap of ``t_end``/50 from 40 % of the record, 100 NaN ``inclinometer_y``
    cells, a burst of 5 angle-sensor outliers of 1 mrad at 70 %)."""
    from tests.support.gc_faults import damage

    p = gc.GyrocompassParams()
    truth = dataclasses.replace(p, alpha1=FIT_TRUTH["alpha1"] * p.alpha1,
                                sigma1_sq=FIT_TRUTH["sigma1_sq"] * p.sigma1_sq)
    sim = gc.simulate_record(truth, t_end, seed)
    if not damaged:
        return sim, sim.record
    rec = damage(sim.record, seed, gap=(0.4 * t_end, 0.42 * t_end),
                 burst_at=0.7 * t_end).record
    return sim, rec


def fit_case(seed: int, t_end: float = 100.0, fit: tuple[str, ...] = (
        "alpha1", "sigma1_sq", "C_as", "C_in"), damaged: bool = False) -> dict:
    """A record made with α1 × 5 and σ1² × 4 (:func:`fit_record`, clean or ``damaged``),
    the noise fitted from the paper's values (:func:`gyrolib.gc.fit_noise`) with its 95 %
    intervals (:func:`gyrolib.gc.profile_intervals`): per fitted name, whether the interval
    holds the truth (``covered``) and the interval itself (``intervals``: the estimate, the
    truth, each side's end, ``null`` where open, whether each side's search closed, and
    whether a side is suspect against the curvature with both figures); and ω_gc's ``z``
    with σ from :func:`gyrolib.gc.fit_uncertainty`."""
    p = gc.GyrocompassParams()
    sim, rec = fit_record(seed, t_end, damaged)
    truth = sim.params
    f = gc.fit_noise(rec, p, fit=fit)
    out: dict = {"converged": f.converged, "message": f.message, "damaged": damaged,
                 "outliers": f.outliers, "covered": {}, "intervals": {}}
    if f.not_identified(t_end):
        return out
    f = gc.profile_intervals(rec, f)
    sides, half = f.interval_sides, f.curvature_half_widths
    for i, nm in enumerate(f.names):
        lo, hi = f.interval(nm)
        value = truth.C_incl_y if nm == "C_in" else getattr(truth, nm)
        out["covered"][nm] = bool(lo <= value <= hi)
        out["intervals"][nm] = {
            "value": f.value(nm), "truth": float(value),
            "low": lo if math.isfinite(lo) and lo > 0 else None,
            "high": hi if math.isfinite(hi) else None,
            "closed": [bool(x) for x in f.interval_closed[i]],
            "log_sides": [float(x) if math.isfinite(x) else None for x in sides[i]],
            "curvature_log_half_width": float(half[i]),
            "suspect": [bool(x) for x in f.suspect_sides[i]]}
    res = gc.calibrate(rec, f.params)
    total = gc.fit_uncertainty(rec, f, at_fit=res)
    out["z"] = (res.omega_gc - float(sim.truth[-1, 3])) / total
    out["valid"] = bool(res.valid)
    return out


def wilson(k: int, n: int) -> tuple[float, float]:
    """95 % Wilson score interval of a binomial share ``k/n`` (:func:`gyrolib.stats.proportion`),
    ``(nan, nan)`` for no runs."""
    if n == 0:
        return (math.nan, math.nan)
    est = stats.proportion(k, n)
    return (est.lo, est.hi)
