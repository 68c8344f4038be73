"""Input validation of every public callable of gyrolib (issue 8, item 3).

The reference here is the contract of CONTRIBUTING.md: bad input raises ``ValueError`` or
``TypeError`` whose message starts with the name of the offending parameter (and, where the
range is a number, states it), never an AttributeError/IndexError/LinAlgError or a numpy
broadcasting error from deep inside, a silent NaN or a wrong figure.

* ``test_bad_input_is_rejected_by_name``: one table, a bad value per parameter kind (type,
  shape, finiteness, physical range, unknown choice) for every public function, class and
  method;
* ``test_table_covers_every_public_callable``: the table's coverage, computed from each
  module's ``__all__`` and the public methods of its classes;
* hypothesis properties over continuous ranges (any non-positive step, duration or count,
  any scale-factor error outside (−1, 1), …) and a check that valid input is not affected.
"""

from __future__ import annotations

import dataclasses
import functools
import inspect
import math
import re

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from gyrolib import __main__ as cli
from gyrolib import filtering, gc, rsf, units
from gyrolib.book import ledger, report
from gyrolib.book.ledger import gc as lgc
from gyrolib.book.ledger import rsf as lrsf
from gyrolib.gc import symbolic

NAN, INF = math.nan, math.inf
P = gc.GyrocompassParams()
T5 = np.linspace(0.0, 1.0, 5)
VIB = gc.vibration_filter(1.0, 0.5, 1.0)
I10 = np.eye(10)
ENC = rsf.EncoderModel()


# Small valid objects, built on first use ---------------------------------------------------------
@functools.cache
def disc() -> gc.GCDiscretization:
    return gc.discretize(P, 0.01)  # 10 steps


def model() -> filtering.AffineDiscreteModel:
    return disc().model


def gains() -> np.ndarray:
    return np.zeros((model().n_steps, 3, 10))


def qd() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    return model().Qd0, model().QdA, model().QdB


@functools.cache
def cov() -> gc.CovarianceAnalysis:
    return gc.covariance_analysis(P, 0.01)


@functools.cache
def mc() -> gc.MonteCarloResult:
    return gc.monte_carlo(P, 2, 0.01, seed=1)


@functools.cache
def cfg() -> rsf.SimulationConfig:
    return rsf.SimulationConfig(duration=2.0, n_runs=2)


@functools.cache
def rec() -> rsf.SensorRecord:
    return rsf.simulate_flight(cfg(), 0)


@functools.cache
def corr() -> rsf.CorrectionRun:
    return rsf.run_correction(rec(), 1.0)


def item(**kw) -> ledger.LedgerItem:
    args = {"id": "gc.x", "paper": "GC", "location": "Fig. 3", "quantity": "q", "unit": "m",
            "paper_value": 1.0, "reproduced_value": 1.0, "status": "reproduced", "note": "n",
            "chapter": "chapters/gc_model"} | kw
    return ledger.LedgerItem(**args)


def replace(obj, **kw):
    return dataclasses.replace(obj, **kw)


# The table: (target, call, exception, parameter named, optional allowed range) -------------------
CASES: list = []
COVERED: set[str] = set()


def case(target: str, call, exc: type[Exception], name: str, allowed: str = "") -> None:
    """``call()`` must raise ``exc`` with a message that starts with ``name`` (then, if given,
    states ``allowed``); ``target`` is the public callable exercised."""
    pattern = "^" + re.escape(name) + (r"\b" if re.match(r".*\w$", name) else "")
    if allowed:
        pattern += ".*" + allowed
    COVERED.add(target)
    CASES.append(pytest.param(call, exc, pattern, id=f"{target}[{len(CASES)}]"))


POS = r"> 0"
NONNEG = r">= 0"
FINITE = r"finite"

# units
case("units.to_si", lambda: units.to_si(NAN, "deg"), ValueError, "value", "NaN")
case("units.to_si", lambda: units.to_si("1", "deg"), TypeError, "value", "real")
case("units.to_si", lambda: units.to_si(1j, "deg"), TypeError, "value", "real")
case("units.to_si", lambda: units.to_si(True, "deg"), TypeError, "value", "bool")
case("units.to_si", lambda: units.to_si([[1.0], [1.0, 2.0]], "deg"), TypeError, "value")
case("units.to_si", lambda: units.to_si(1.0, "furlong"), ValueError, "unit", "one of")
case("units.from_si", lambda: units.from_si([1.0, NAN], "deg"), ValueError, "value", "NaN")
case("units.from_si", lambda: units.from_si(1.0, None), TypeError, "unit", "str")

# shaping_filters
case("gc.ShapingFilter", lambda: gc.ShapingFilter("a", VIB.B, VIB.C, VIB.Q),
     TypeError, "A", "real")
case("gc.ShapingFilter", lambda: replace(VIB, A=np.ones((2, 3))), ValueError, "A",
     "square")
case("gc.ShapingFilter", lambda: replace(VIB, B=np.ones((3, 1))), ValueError, "B",
     r"\(2, 1\)")
case("gc.ShapingFilter", lambda: replace(VIB, C=np.ones((1, 3))), ValueError, "C",
     r"\(1, 2\)")
case("gc.ShapingFilter", lambda: gc.ShapingFilter(VIB.A, VIB.B, VIB.C, -1.0),
     ValueError, "Q", NONNEG)
case("gc.ShapingFilter", lambda: gc.ShapingFilter(VIB.A, VIB.B, VIB.C, NAN),
     ValueError, "Q", FINITE)
case("gc.ShapingFilter.discretize", lambda: VIB.discretize(0.0), ValueError, "dt",
     POS)
case("gc.vibration_filter", lambda: gc.vibration_filter(NAN, 0.5, 1.0),
     ValueError, "alpha1", POS)
case("gc.vibration_filter", lambda: gc.vibration_filter(1.0, 0.0, 1.0),
     ValueError, "xi1", r"\(0.0, 1.0\]")
case("gc.vibration_filter", lambda: gc.vibration_filter(1.0, 0.5, "1"),
     TypeError, "sigma1_sq")
case("gc.random_drift_filter", lambda: gc.random_drift_filter(-1.0, 0.5, 1.0),
     ValueError, "alpha2", POS)
case("gc.random_drift_filter", lambda: gc.random_drift_filter(1.0, 1.5, 1.0),
     ValueError, "xi2")
case("gc.random_drift_filter", lambda: gc.random_drift_filter(1.0, 0.5, 0.0),
     ValueError, "sigma2_sq", POS)
case("gc.stationary_covariance",
     lambda: gc.stationary_covariance(np.ones((2, 3)), np.ones((2, 1)), 1.0), ValueError, "A",
     "square")
case("gc.stationary_covariance",
     lambda: gc.stationary_covariance(VIB.A, np.ones((3, 1)), 1.0), ValueError, "B")
case("gc.stationary_covariance", lambda: gc.stationary_covariance(VIB.A, VIB.B,
                                                                                -1.0),
     ValueError, "Q", NONNEG)
case("gc.stationary_covariance", lambda: gc.stationary_covariance(-VIB.A, VIB.B,
                                                                                1.0),
     ValueError, "A", "Hurwitz")
case("gc.psd_two_sided", lambda: gc.psd_two_sided(None, [1.0]), TypeError, "filt")
case("gc.psd_two_sided", lambda: gc.psd_two_sided(VIB, [[1.0]]), ValueError,
     "omega", "1-D")
case("gc.psd", lambda: gc.psd(VIB, [NAN]), ValueError, "omega", FINITE)
case("gc.psd", lambda: gc.psd(VIB, [-1.0]), ValueError, "omega", NONNEG)
case("gc.psd_integral", lambda: gc.psd_integral(VIB, decades=-1.0), ValueError,
     "decades", POS)
case("gc.psd_integral", lambda: gc.psd_integral(VIB, n=True), TypeError, "n",
     ">= 101")
case("gc.simulate_shaping_filter", lambda: gc.simulate_shaping_filter(VIB, 0.1, 10, -1), ValueError, "seed",
     ">= 0")
case("gc.simulate_shaping_filter", lambda: gc.simulate_shaping_filter(VIB, 0.1, 0, 1), ValueError, "n", ">= 1")
case("gc.simulate_shaping_filter", lambda: gc.simulate_shaping_filter(VIB, INF, 10, 1), ValueError, "dt", POS)
case("gc.simulate_shaping_filter", lambda: gc.simulate_shaping_filter("VIB", 0.1, 10, 1), TypeError, "filt")
case("gc.mean_square_standard_error",
     lambda: gc.mean_square_standard_error(VIB, NAN, 10), ValueError, "dt", FINITE)
case("gc.mean_square_standard_error",
     lambda: gc.mean_square_standard_error(VIB, 0.1, 2.5), TypeError, "n")

# gyrocompass
case("gc.GyrocompassParams", lambda: gc.GyrocompassParams(I=-1.0), ValueError, "I",
     POS)
case("gc.GyrocompassParams", lambda: gc.GyrocompassParams(dt=NAN), ValueError, "dt")
case("gc.GyrocompassParams", lambda: gc.GyrocompassParams(H="0.05"), TypeError, "H")
case("gc.GyrocompassParams", lambda: gc.GyrocompassParams(sigma_psi0=-1e-6),
     ValueError, "sigma_psi0", NONNEG)
case("gc.GyrocompassParams", lambda: gc.GyrocompassParams(xi2=0.0), ValueError, "xi2",
     r"\(0.0, 1.0\]")
case("gc.GyrocompassParams", lambda: gc.GyrocompassParams(shaping_p0="x"), ValueError,
     "shaping_p0", "one of")
case("gc.GyrocompassParams", lambda: replace(P, measurement_noise=None), ValueError,
     "measurement_noise", "one of")
case("gc.GyrocompassParams", lambda: replace(P, vertical_coupling="eq6"), ValueError,
     "vertical_coupling", "one of")
case("gc.state_index", lambda: gc.state_index("foo"), ValueError, "name", "one of")
case("gc.NominalMotion", lambda: gc.NominalMotion("a", T5, T5), TypeError, "t")
case("gc.NominalMotion", lambda: gc.NominalMotion(T5, T5[:3], T5), ValueError, "beta",
     r"\(5,\)")
case("gc.NominalMotion", lambda: gc.NominalMotion(T5, T5, T5 * NAN), ValueError,
     "beta_dot", FINITE)
case("gc.nominal_motion", lambda: gc.nominal_motion(None, T5), TypeError, "params")
case("gc.nominal_motion", lambda: gc.nominal_motion(P, [1.0, 0.5]), ValueError, "t",
     "non-decreasing")
case("gc.nominal_motion", lambda: gc.nominal_motion(P, []), ValueError, "t")
case("gc.nominal_motion", lambda: gc.nominal_motion(P, T5, rtol=1.0), ValueError,
     "rtol", r"\[1e-14, 0.001\]")
case("gc.nominal_motion_reference", lambda: gc.nominal_motion_reference(P, [NAN]),
     ValueError, "t", FINITE)
case("gc.nominal_motion_reference", lambda: gc.nominal_motion_reference(P, T5,
                                                                                  rtol="a"),
     TypeError, "rtol")
case("gc.nominal_motion_aperiodic", lambda: gc.nominal_motion_aperiodic(P, [[1.0]]),
     ValueError, "t", "1-D")
case("gc.nominal_motion_aperiodic", lambda: gc.nominal_motion_aperiodic({}, T5),
     TypeError, "params")
case("gc.system_matrix", lambda: gc.system_matrix(None, 0.0), TypeError, "params")
case("gc.system_matrix", lambda: gc.system_matrix(P, NAN), ValueError, "beta_n",
     FINITE)
case("gc.noise_input_matrix", lambda: gc.noise_input_matrix(None), TypeError,
     "params")
case("gc.measurement_matrix", lambda: gc.measurement_matrix("P"), TypeError, "params")
case("gc.process_noise_intensity", lambda: gc.process_noise_intensity(None),
     TypeError, "params")
case("gc.measurement_noise_intensity", lambda: gc.measurement_noise_intensity(1.0),
     TypeError, "params")
case("gc.measurement_noise_covariance", lambda: gc.measurement_noise_covariance(None),
     TypeError, "params")
case("gc.initial_covariance", lambda: gc.initial_covariance(None), TypeError,
     "params")

# gc_symbolic
S = symbolic.SYMBOLS
case("gc.symbolic.ModelSymbols", lambda: replace(S, t="t"), TypeError, "t", "Symbol")
case("gc.symbolic.float_input_axis", lambda: symbolic.float_input_axis(None), TypeError, "beta")
case("gc.symbolic.float_input_axis", lambda: symbolic.float_input_axis(NAN), ValueError, "beta",
     FINITE)
case("gc.symbolic.earth_rate_in_base", lambda: symbolic.earth_rate_in_base("eq6"), ValueError,
     "coupling", "one of")
case("gc.symbolic.gyroscopic_torque", lambda: symbolic.gyroscopic_torque(S.t, 2), ValueError, "sign",
     r"\+1 or -1")
case("gc.symbolic.gyroscopic_torque", lambda: symbolic.gyroscopic_torque("b"), TypeError, "beta")
case("gc.symbolic.gyrocompass_equation", lambda: symbolic.gyrocompass_equation(unbalance="no"),
     TypeError, "unbalance", "bool")
case("gc.symbolic.gyrocompass_equation", lambda: symbolic.gyrocompass_equation(coupling="x"),
     ValueError, "coupling")
case("gc.symbolic.gyrocompass_equation", lambda: symbolic.gyrocompass_equation(sign=True), ValueError,
     "sign")
case("gc.symbolic.taylor_linearization", lambda: symbolic.taylor_linearization(sign=[1]), ValueError,
     "sign")
case("gc.symbolic.taylor_linearization", lambda: symbolic.taylor_linearization(unbalance=1),
     TypeError, "unbalance")
case("gc.symbolic.taylor_linearization", lambda: symbolic.taylor_linearization(coupling=["eq5"]),
     ValueError, "coupling")
case("gc.symbolic.ShapingFilterSym", lambda: symbolic.ShapingFilterSym(None, None, None, None),
     TypeError, "A")
case("gc.symbolic.ShapingFilterSym", lambda: symbolic.ShapingFilterSym(sp.eye(2), sp.Matrix([1]),
                                                                  sp.Matrix([[1, 0]]), S.s),
     ValueError, "B", r"\(2, 1\)")
case("gc.symbolic.shaping_filter", lambda: symbolic.shaping_filter("x"), ValueError, "which",
     "one of")
case("gc.symbolic.shaping_filter", lambda: symbolic.shaping_filter("drift", "second_line_only"),
     ValueError, "reading", "one of")
case("gc.symbolic.lyapunov_variance", lambda: symbolic.lyapunov_variance(None, sp.Matrix([1]),
                                                                    sp.Matrix([1]), 1),
     TypeError, "A")
case("gc.symbolic.lyapunov_variance", lambda: symbolic.lyapunov_variance(
    sp.eye(2), sp.Matrix([1, 2, 3]), sp.Matrix([[1, 0]]), 1), ValueError, "B")
case("gc.symbolic.lyapunov_variance", lambda: symbolic.lyapunov_variance(
    -sp.eye(2), sp.Matrix([1, 0]), sp.Matrix([[1, 0, 0]]), 1), ValueError, "C")
case("gc.symbolic.lyapunov_variance", lambda: symbolic.lyapunov_variance(
    -sp.eye(2), sp.Matrix([1, 0]), sp.Matrix([[1, 0]]), NAN), ValueError, "Q", FINITE)
case("gc.symbolic.StateSpaceSym", lambda: replace(symbolic.state_space(), coupling="x"), ValueError,
     "coupling")
case("gc.symbolic.StateSpaceSym", lambda: replace(symbolic.state_space(), F=None), TypeError, "F")
case("gc.symbolic.state_space", lambda: symbolic.state_space(["eq5"]), ValueError, "coupling")
case("gc.symbolic.state_space", lambda: symbolic.state_space("eq5", "x"), ValueError, "state_order")
case("gc.symbolic.state_space", lambda: symbolic.state_space(sign=3), ValueError, "sign")
case("gc.symbolic.compare_with_paper", lambda: symbolic.compare_with_paper(None), TypeError, "model")
case("gc.symbolic.parameter_values", lambda: symbolic.parameter_values(None), TypeError, "params")
case("gc.symbolic.numeric_matrices", lambda: symbolic.numeric_matrices(None, 0.0), TypeError,
     "params")
case("gc.symbolic.numeric_matrices", lambda: symbolic.numeric_matrices(P, INF), ValueError, "beta_n",
     FINITE)
case("gc.symbolic.numeric_matrices", lambda: symbolic.numeric_matrices(P, 0.0, "x"), ValueError,
     "coupling")

# kalman
case("filtering.van_loan", lambda: filtering.van_loan(np.ones((2, 3)), np.ones((2, 1)), [[1.0]], 0.1),
     ValueError, "F", "square")
case("filtering.van_loan", lambda: filtering.van_loan([[NAN]], [[1.0]], [[1.0]], 0.1), ValueError, "F",
     FINITE)
case("filtering.van_loan", lambda: filtering.van_loan(-np.eye(2), np.ones((3, 1)), [[1.0]], 0.1),
     ValueError, "G")
case("filtering.van_loan", lambda: filtering.van_loan(-np.eye(2), np.ones((2, 1)), np.eye(2), 0.1),
     ValueError, "Qc", r"\(1, 1\)")
case("filtering.van_loan", lambda: filtering.van_loan(-np.eye(2), np.ones((2, 1)), [[-1.0]], 0.1),
     ValueError, "Qc", NONNEG)
case("filtering.van_loan", lambda: filtering.van_loan(-np.eye(2), np.ones((2, 1)), [[1.0]], 0.0),
     ValueError, "dt", POS)
case("filtering.van_loan_derivatives", lambda: filtering.van_loan_derivatives(
    -np.eye(2), np.ones((2, 1)), [[1.0]], 0.1, None), TypeError, "directions")
case("filtering.van_loan_derivatives", lambda: filtering.van_loan_derivatives(
    -np.eye(2), np.ones((2, 1)), [[1.0]], 0.1, [np.eye(3)]), ValueError, "direction")
case("filtering.covariance_factor", lambda: filtering.covariance_factor(np.ones((2, 3))), ValueError, "Q", "square")
case("filtering.covariance_factor", lambda: filtering.covariance_factor([[1.0, 2.0], [0.0, 1.0]]), ValueError, "Q",
     "symmetric")
case("filtering.covariance_factor", lambda: filtering.covariance_factor(-np.eye(2)), ValueError, "Q", NONNEG)
case("filtering.joseph_update", lambda: filtering.joseph_update([0.0, NAN], np.eye(2), [0.0],
                                                          [[1.0, 0.0]], [[1.0]]),
     ValueError, "x", FINITE)
case("filtering.joseph_update", lambda: filtering.joseph_update(np.zeros(2), np.eye(3), [0.0],
                                                          [[1.0, 0.0]], [[1.0]]),
     ValueError, "P", r"\(2, 2\)")
case("filtering.joseph_update", lambda: filtering.joseph_update(np.zeros(2), -np.eye(2), [0.0],
                                                          [[1.0, 0.0]], [[1.0]]),
     ValueError, "P", NONNEG)
case("filtering.joseph_update", lambda: filtering.joseph_update(np.zeros(2), np.eye(2), [0.0, 1.0],
                                                          [[1.0, 0.0]], [[1.0]]),
     ValueError, "z")
case("filtering.joseph_update", lambda: filtering.joseph_update(np.zeros(2), np.eye(2), [0.0],
                                                          [[1.0, 0.0, 0.0]], [[1.0]]),
     ValueError, "H")
case("filtering.joseph_update", lambda: filtering.joseph_update(np.zeros(2), np.eye(2), [0.0],
                                                          [[1.0, 0.0]], [[-1.0]]),
     ValueError, "R", NONNEG)
case("filtering.joseph_update", lambda: filtering.joseph_update(np.zeros(2), np.zeros((2, 2)), [0.0],
                                                          [[1.0, 0.0]], [[0.0]]),
     ValueError, "R", "nonsingular")
case("filtering.sequential_update", lambda: filtering.sequential_update(
    np.zeros(2), np.eye(2), [0.0, 0.0], np.eye(2), [[1.0, 0.5], [0.5, 1.0]]), ValueError, "R",
    "diagonal")
case("filtering.sequential_update", lambda: filtering.sequential_update(
    np.zeros(2), np.zeros((2, 2)), [0.0], [[1.0, 0.0]], [[0.0]]), ValueError, "R[0, 0]",
    "positive")
case("filtering.AffineDiscreteModel", lambda: replace(model(), seg=model().seg.astype(float)),
     TypeError, "seg", "integer")
case("filtering.AffineDiscreteModel", lambda: replace(model(), a=model().a * NAN), ValueError, "a",
     FINITE)
case("filtering.AffineDiscreteModel", lambda: replace(model(), b=model().b[:3]), ValueError, "b")
case("filtering.AffineDiscreteModel", lambda: replace(model(), Phi0=model().Phi0[0]), ValueError,
     "Phi0")
case("filtering.AffineDiscreteModel", lambda: replace(model(), QdB=model().QdB[:, :3]), ValueError,
     "QdB")
case("filtering.AffineDiscreteModel", lambda: replace(model(), r=-model().r), ValueError, "r",
     NONNEG)
case("filtering.AffineDiscreteModel", lambda: replace(model(), seg=model().seg + 99), ValueError,
     "seg")
case("filtering.AffineDiscreteModel.phi", lambda: model().phi(10), ValueError, "k", r"\[0, 10\)")
case("filtering.AffineDiscreteModel.phi", lambda: model().phi(-1), ValueError, "k", ">= 0")
case("filtering.AffineDiscreteModel.qd", lambda: model().qd("a"), TypeError, "k")
case("filtering.CovarianceRun", lambda: filtering.CovarianceRun(np.ones((2, 3)), np.ones((1, 2, 2)),
                                                          1, None),
     ValueError, "P_stored", r"\('any', 3, 3\)")
case("filtering.CovarianceRun", lambda: filtering.CovarianceRun(np.ones((2, 3)), np.ones((1, 3, 3)),
                                                          0, None),
     ValueError, "store_every")
case("filtering.covariance_reference", lambda: filtering.covariance_reference(None, I10), TypeError,
     "model")
case("filtering.covariance_reference", lambda: filtering.covariance_reference(
    None, I10, 1, step_matrices=5, n_steps=1, H=model().H, R=np.eye(3)), TypeError,
    "step_matrices", "callable")
case("filtering.covariance_reference", lambda: filtering.covariance_reference(
    None, I10, 1, step_matrices=lambda k: (I10, I10), n_steps=None, H=model().H, R=np.eye(3)),
    TypeError, "n_steps")
case("filtering.covariance_reference", lambda: filtering.covariance_reference(
    None, I10, 1, step_matrices=lambda k: (I10, I10), n_steps=1, H=model().H, R=-np.eye(3)),
    ValueError, "R", NONNEG)
case("filtering.covariance_reference", lambda: filtering.covariance_reference(model(), -I10),
     ValueError, "P0", NONNEG)
case("filtering.covariance_fast", lambda: filtering.covariance_fast(model(), np.eye(3)), ValueError,
     "P0", r"\(10, 10\)")
case("filtering.covariance_fast", lambda: filtering.covariance_fast(model(), I10 * NAN), ValueError,
     "P0", FINITE)
case("filtering.covariance_fast", lambda: filtering.covariance_fast(model(), I10, 0), ValueError,
     "store_every", ">= 1")
case("filtering.covariance_fast", lambda: filtering.covariance_fast(model(), I10, keep_gains="yes"),
     TypeError, "keep_gains", "bool")
case("filtering.propagate_fixed_gains", lambda: filtering.propagate_fixed_gains(
    model(), I10, gains()[:3], model().r, qd()), ValueError, "gains")
case("filtering.propagate_fixed_gains", lambda: filtering.propagate_fixed_gains(
    model(), I10, gains(), -model().r, qd()), ValueError, "r", NONNEG)
case("filtering.propagate_fixed_gains", lambda: filtering.propagate_fixed_gains(
    model(), I10, gains(), model().r, qd()[:1]), TypeError, "Qd")
case("filtering.propagate_fixed_gains", lambda: filtering.propagate_fixed_gains(
    "model", I10, gains(), model().r, qd()), TypeError, "model")

# square_root_filter
case("filtering.cholesky_semidefinite", lambda: filtering.cholesky_semidefinite(np.ones((2, 3))),
     ValueError, "P", "square")
case("filtering.cholesky_semidefinite", lambda: filtering.cholesky_semidefinite(-np.eye(2)), ValueError,
     "P", "positive semi-definite")
case("filtering.cholesky_semidefinite", lambda: filtering.cholesky_semidefinite(None), TypeError, "P")
case("filtering.covariance_square_root", lambda: filtering.covariance_square_root(None, I10),
     TypeError, "model")
case("filtering.covariance_square_root", lambda: filtering.covariance_square_root(model(),
                                                                                      -I10),
     ValueError, "P0", "positive semi-definite")
case("filtering.covariance_square_root", lambda: filtering.covariance_square_root(model(),
                                                                                      I10, 0),
     ValueError, "store_every")

# gc_estimation
case("gc.nominal_half_steps", lambda: gc.nominal_half_steps(None, 10), TypeError,
     "params")
case("gc.nominal_half_steps", lambda: gc.nominal_half_steps(P, 0), ValueError,
     "n_steps", ">= 1")
case("gc.discretize", lambda: gc.discretize(P, 0.0), ValueError, "t_end", POS)
case("gc.discretize", lambda: gc.discretize(P, 0.0105), ValueError, "t_end",
     "multiple of dt")
case("gc.discretize", lambda: gc.discretize(P, "1"), TypeError, "t_end")
case("gc.GCDiscretization", lambda: replace(disc(), n_steps=0), ValueError,
     "n_steps")
case("gc.GCDiscretization", lambda: replace(disc(), model=None), TypeError, "model")
case("gc.GCDiscretization", lambda: replace(disc(), Gamma=disc().Gamma[:, :3]),
     ValueError, "Gamma")
case("gc.GCDiscretization.exact_step", lambda: disc().exact_step(-1), ValueError,
     "k", ">= 0")
case("gc.GCDiscretization.exact_step", lambda: disc().exact_step(10), ValueError,
     "k", r"\[0, 10\)")
case("gc.GCDiscretization.exact_step", lambda: disc().exact_step(1.5), TypeError,
     "k")
case("gc.covariance_analysis", lambda: gc.covariance_analysis(P, 0.01, method="x"),
     ValueError, "method", "one of")
case("gc.covariance_analysis", lambda: gc.covariance_analysis(P, 0.01,
                                                                         store_every=0),
     ValueError, "store_every")
case("gc.covariance_analysis", lambda: gc.covariance_analysis(
    P, 0.01, P0=np.triu(np.ones((10, 10)))), ValueError, "P0", "symmetric")
case("gc.covariance_analysis", lambda: gc.covariance_analysis(
    P, 0.01, P0=I10 - 0.5 * np.ones((10, 10))), ValueError, "P0", "positive semi-definite")
case("gc.covariance_analysis", lambda: gc.covariance_analysis(P, -100.0), ValueError,
     "t_end", POS)
case("gc.CovarianceAnalysis", lambda: replace(cov(), var=cov().var[:, :3]),
     ValueError, "var")
case("gc.CovarianceAnalysis", lambda: replace(cov(), params=None), TypeError,
     "params")
case("gc.CovarianceAnalysis.std", lambda: cov().std("x"), ValueError, "name",
     "one of")
case("gc.CovarianceAnalysis.std_at", lambda: cov().std_at("psi", -1.0), ValueError,
     "time", r"\[0.0, 0.01\]")
case("gc.CovarianceAnalysis.std_at", lambda: cov().std_at("Psi", 0.0), ValueError,
     "name")
case("gc.time_to_sigma", lambda: gc.time_to_sigma(None, "psi", 1.0), TypeError,
     "result")
case("gc.time_to_sigma", lambda: gc.time_to_sigma(cov(), "psi", 0.0), ValueError,
     "level", POS)
case("gc.time_to_sigma", lambda: gc.time_to_sigma(cov(), "x", 1.0), ValueError,
     "name")
case("gc.sweep_sigma_gc", lambda: gc.sweep_sigma_gc(P, "nope", [1.0], 0.01),
     ValueError, "field")
case("gc.sweep_sigma_gc", lambda: gc.sweep_sigma_gc(P, ["xi1"], [1.0], 0.01),
     TypeError, "field", "str")
case("gc.sweep_sigma_gc", lambda: gc.sweep_sigma_gc(P, "xi1", [NAN], 0.01),
     ValueError, "values", FINITE)
case("gc.sweep_sigma_gc", lambda: gc.sweep_sigma_gc(P, "xi1", [2.0], 0.01),
     ValueError, "xi1", r"\(0.0, 1.0\]")
case("gc.sweep_sigma_gc", lambda: gc.sweep_sigma_gc(None, "xi1", [0.5], 0.01),
     TypeError, "params")
case("gc.monte_carlo", lambda: gc.monte_carlo(P, 0, 0.01), ValueError, "n_runs",
     ">= 1")
case("gc.monte_carlo", lambda: gc.monte_carlo(P, 1, 0.01, seed=-1), ValueError,
     "seed", ">= 0")
case("gc.monte_carlo", lambda: gc.monte_carlo(P, 1, 0.01, seed=None), TypeError,
     "seed")
case("gc.monte_carlo", lambda: gc.monte_carlo(P, 1, -1.0), ValueError, "t_end", POS)
case("gc.monte_carlo", lambda: gc.monte_carlo(P, 1, 0.01, method="slow"),
     ValueError, "method")
case("gc.monte_carlo", lambda: gc.monte_carlo(P, 1, 0.01, truth="x"), ValueError,
     "truth")
case("gc.monte_carlo", lambda: gc.monte_carlo(P, 1, 0.01, store_every=0),
     ValueError, "store_every")
case("gc.MonteCarloResult", lambda: replace(mc(), tru=mc().tru[:1]), ValueError,
     "tru")
case("gc.MonteCarloResult", lambda: replace(mc(), seed=-3), ValueError, "seed")
case("gc.MonteCarloResult.estimate", lambda: mc().estimate("x"), ValueError, "name")
case("gc.MonteCarloResult.truth", lambda: mc().truth(3), ValueError, "name")
case("gc.MonteCarloResult.error", lambda: mc().error(None), ValueError, "name")
case("gc.MonteCarloResult.std", lambda: mc().std("omega"), ValueError, "name")
case("gc.MonteCarloResult.rms_error", lambda: mc().rms_error(""), ValueError, "name")
case("gc.MonteCarloResult.nees", lambda: mc().nees("psi"), TypeError, "names")
case("gc.MonteCarloResult.nees", lambda: mc().nees(()), ValueError, "names")
case("gc.MonteCarloResult.nees", lambda: mc().nees(("psi", "x")), ValueError, "name")
case("filtering.nees_bounds", lambda: filtering.nees_bounds(0, 10), ValueError, "dof", ">= 1")
case("filtering.nees_bounds", lambda: filtering.nees_bounds(1, 1.0), TypeError, "n_runs")
case("filtering.nees_bounds", lambda: filtering.nees_bounds(1, 10, 1.0), ValueError, "confidence",
     r"\(0.0, 1.0\)")
case("gc.simulate_truth", lambda: gc.simulate_truth(P, 0.01, np.zeros(10), seed="a"),
     TypeError, "seed")
case("gc.simulate_truth", lambda: gc.simulate_truth(P, 0.01, np.zeros(10), seed=-1),
     ValueError, "seed", ">= 0")
case("gc.simulate_truth", lambda: gc.simulate_truth(P, 0.01, np.zeros(3)),
     ValueError, "x0", r"\(10,\)")
case("gc.simulate_truth", lambda: gc.simulate_truth(P, 0.0, np.zeros(10)),
     ValueError, "t_end")
case("gc.simulate_truth", lambda: gc.simulate_truth(P, 0.01, np.zeros(10),
                                                               store_every=-2),
     ValueError, "store_every")
case("gc.error_budget", lambda: gc.error_budget(P, 0.01, name="x"), ValueError,
     "name")
case("gc.error_budget", lambda: gc.error_budget(P, 0.01, store_every=0), ValueError,
     "store_every")
case("gc.error_budget", lambda: gc.error_budget(P, INF), ValueError, "t_end")
case("gc.ErrorBudget", lambda: gc.ErrorBudget(P, T5, ("a", 1), np.ones((2, 5)),
                                                         np.ones(5)),
     TypeError, "sources")
case("gc.ErrorBudget", lambda: gc.ErrorBudget(P, T5, ("a",), np.ones((2, 5)),
                                                         np.ones(5)),
     ValueError, "var")
case("gc.information_psi_omega",
     lambda: gc.information_psi_omega(P, 0.01, frozen_beta=NAN), ValueError, "frozen_beta",
     FINITE)
case("gc.information_psi_omega", lambda: gc.information_psi_omega(P, -1.0),
     ValueError, "t_end")
case("gc.information_psi_omega", lambda: gc.information_psi_omega(P, 0.01,
                                                                             store_every=0.5),
     TypeError, "store_every")
case("gc.InformationPsiOmega", lambda: gc.InformationPsiOmega(T5, np.ones((5, 3, 3))),
     ValueError, "W", r"\(5, 2, 2\)")

# gc_plots
case("gc.plot_sigma_history", lambda: gc.plot_sigma_history(T5, [T5], paper_value=1.0),
     TypeError, "curves", "Mapping")
case("gc.plot_sigma_history", lambda: gc.plot_sigma_history(T5, {}, paper_value=1.0),
     ValueError, "curves")
case("gc.plot_sigma_history", lambda: gc.plot_sigma_history(T5, {"a": T5[:3]},
                                                                  paper_value=1.0),
     ValueError, "t and curves['a']", "same length")
case("gc.plot_sigma_history", lambda: gc.plot_sigma_history(T5, {"a": -T5},
                                                                  paper_value=1.0),
     ValueError, "curves['a']", NONNEG)
case("gc.plot_sigma_history", lambda: gc.plot_sigma_history([], {"a": []},
                                                                  paper_value=1.0),
     ValueError, "t", "at least 2")
case("gc.plot_sigma_history", lambda: gc.plot_sigma_history(T5, {"a": T5},
                                                                  paper_value=0.0),
     ValueError, "paper_value", POS)
case("gc.plot_sigma_history", lambda: gc.plot_sigma_history(T5, {"a": T5}, paper_value=1.0,
                                                                  paper_time=NAN),
     ValueError, "paper_time")
case("gc.plot_sigma_history", lambda: gc.plot_sigma_history(T5, {"a": T5}, paper_value=1.0,
                                                                  drop_time="2"),
     TypeError, "drop_time")
case("gc.plot_sigma_history", lambda: gc.plot_sigma_history(T5, {"a": T5}, paper_value=1.0,
                                                                  unit=None),
     TypeError, "unit", "str")
case("gc.plot_p0_scale", lambda: gc.plot_p0_scale(T5, T5 * NAN, paper_value=1.0),
     ValueError, "sigma", FINITE)
case("gc.plot_p0_scale", lambda: gc.plot_p0_scale(-T5, T5, paper_value=1.0), ValueError,
     "kappa", NONNEG)
case("gc.plot_p0_scale", lambda: gc.plot_p0_scale(T5, T5[:2], paper_value=1.0),
     ValueError, "kappa and sigma")
case("gc.plot_error_budget", lambda: gc.plot_error_budget(T5, np.ones((2, 5)), None),
     TypeError, "sources")
case("gc.plot_error_budget", lambda: gc.plot_error_budget(T5, np.ones((3, 5)),
                                                                ("a", "b")),
     ValueError, "var", r"\(2, 5\)")
case("gc.plot_error_budget", lambda: gc.plot_error_budget([], np.ones((2, 0)),
                                                                ("a", "b")),
     ValueError, "t")
case("gc.plot_error_budget", lambda: gc.plot_error_budget(T5, np.ones((2, 5)),
                                                                ("a", "b"), scale=-1.0),
     ValueError, "scale", POS)
case("gc.plot_estimates", lambda: gc.plot_estimates(T5, np.ones((2, 5)), [1.0, 1.0], T5,
                                                          t_zoom=NAN),
     ValueError, "t_zoom")
case("gc.plot_estimates", lambda: gc.plot_estimates(T5, np.ones((2, 5)), [1.0, 1.0], -T5),
     ValueError, "sigma", NONNEG)
case("gc.plot_estimates", lambda: gc.plot_estimates(T5, np.ones((2, 5)), [1.0], T5),
     ValueError, "truths", r"\(2,\)")
case("gc.plot_estimates", lambda: gc.plot_estimates(T5, np.ones((0, 5)), [], T5),
     ValueError, "estimates", "at least 1")
case("gc.plot_estimates", lambda: gc.plot_estimates(T5, np.ones((2, 4)), [1.0, 1.0], T5),
     ValueError, "estimates")
case("gc.plot_consistency", lambda: gc.plot_consistency(T5, T5, T5, (1.0, 2.0, 3.0), {}),
     TypeError, "rms_band", "pair")
case("gc.plot_consistency", lambda: gc.plot_consistency(T5, T5, T5, (2.0, 1.0), {}),
     ValueError, "rms_band", "low <= high")
case("gc.plot_consistency", lambda: gc.plot_consistency(T5, T5, T5, (1.0, 2.0), [T5]),
     TypeError, "nees", "Mapping")
case("gc.plot_consistency", lambda: gc.plot_consistency(T5, T5, T5, (1.0, 2.0),
                                                              {"a": T5}),
     TypeError, "nees['a']", "pair")
case("gc.plot_consistency", lambda: gc.plot_consistency(T5, T5, T5, (1.0, 2.0),
                                                              {"a": (T5, (NAN, 1.0))}),
     ValueError, "nees['a'] bounds", POS)
case("gc.plot_consistency", lambda: gc.plot_consistency(T5, -T5, T5, (1.0, 2.0), {}),
     ValueError, "rms", NONNEG)
case("gc.plot_sweep", lambda: gc.plot_sweep([(T5, T5, 1.0)], paper_value=1.0), TypeError,
     "sweeps", "Mapping")
case("gc.plot_sweep", lambda: gc.plot_sweep({"a": (T5, T5)}, paper_value=1.0), TypeError,
     "sweeps['a']", "triple")
case("gc.plot_sweep", lambda: gc.plot_sweep({"a": (T5 + 1, T5 + 1, NAN)},
                                                  paper_value=1.0),
     ValueError, "sweeps['a'] nominal", POS)
case("gc.plot_sweep", lambda: gc.plot_sweep({"a": (T5, T5 + 1, 1.0)}, paper_value=1.0),
     ValueError, "sweeps['a'] values", r"> 0 \(log axes\)")
case("gc.plot_information", lambda: gc.plot_information(T5, T5, T5, T5[:2], T5),
     ValueError, "t and corr", "same length")
case("gc.plot_information", lambda: gc.plot_information(T5, T5, T5, T5 + 1.5, T5),
     ValueError, "corr", r"\[-1, 1\]")
case("gc.plot_information", lambda: gc.plot_information(T5, -T5, T5, T5, T5), ValueError,
     "sig_known", NONNEG)

# gc_model_plots
PSD = {"alpha1": 1.0, "alpha2": 1.0, "var_n1": 1.0, "var_n3": 1.0}
case("gc.plot_shaping_psd", lambda: gc.plot_shaping_psd([0.0, 1.0], [1, 1], [1, 1],
                                                                     **PSD),
     ValueError, "omega", r"> 0")
case("gc.plot_shaping_psd", lambda: gc.plot_shaping_psd([], [], [], **PSD),
     ValueError, "omega", "at least 1")
case("gc.plot_shaping_psd", lambda: gc.plot_shaping_psd([1.0, 2.0], [-1, 1], [1, 1],
                                                                     **PSD),
     ValueError, "psd_n1", NONNEG)
case("gc.plot_shaping_psd", lambda: gc.plot_shaping_psd([1.0, 2.0], [1, 1], [1],
                                                                     **PSD),
     ValueError, "omega, psd_n1, psd_n3", "same length")
case("gc.plot_shaping_psd", lambda: gc.plot_shaping_psd(
    [1.0, 2.0], [1, 1], [1, 1], **(PSD | {"var_n3": -1.0})), ValueError, "var_n3", POS)
case("gc.plot_nominal_motion", lambda: gc.plot_nominal_motion(
    T5, T5, T5, [], [], [], tau=1.0, lag=0.0), ValueError, "t_fast", "at least 1")
case("gc.plot_nominal_motion", lambda: gc.plot_nominal_motion(
    T5, T5, T5, T5, T5, T5, tau=0.0, lag=0.0), ValueError, "tau", POS)
case("gc.plot_nominal_motion", lambda: gc.plot_nominal_motion(
    T5, T5, T5, T5, T5, T5, tau=1.0, lag=NAN), ValueError, "lag", FINITE)
case("gc.plot_figure1", lambda: gc.plot_figure1(beta_deg=90.0), ValueError,
     "beta_deg", r"\[1.0, 80.0\]")
case("gc.plot_figure1", lambda: gc.plot_figure1(beta_deg=10.0, psi_deg=20.0),
     ValueError, "psi_deg", "< beta_deg")
case("gc.plot_figure1", lambda: gc.plot_figure1(tilt_deg="14"), TypeError,
     "tilt_deg")

# roll_correction
case("rsf.RollGyroSpec", lambda: rsf.RollGyroSpec(sf_error=2.0), ValueError,
     "sf_error", r"\[0.0, 1.0\)")
case("rsf.RollGyroSpec", lambda: rsf.RollGyroSpec(bias_instability=-1.0), ValueError,
     "bias_instability", NONNEG)
case("rsf.RollGyroSpec", lambda: rsf.RollGyroSpec(dynamic_range=0.0), ValueError,
     "dynamic_range", POS)
case("rsf.MemsGyroSpec", lambda: rsf.MemsGyroSpec(bias_stability=-1.0), ValueError,
     "bias_stability", NONNEG)
case("rsf.MemsGyroSpec", lambda: rsf.MemsGyroSpec(name=1), TypeError, "name")
case("rsf.EncoderSpec", lambda: rsf.EncoderSpec(quadrature=3), ValueError,
     "quadrature", r"\(1, 2, 4\)")
case("rsf.EncoderSpec", lambda: rsf.EncoderSpec(cycles_per_rev=0), ValueError,
     "cycles_per_rev", ">= 1")
case("rsf.EncoderSpec", lambda: rsf.EncoderSpec(position_error=4.0), ValueError,
     "position_error")
case("rsf.gyro_output", lambda: rsf.gyro_output(1.0, 1.0), ValueError, "eps1",
     r"\(-1.0, 1.0\)")
case("rsf.gyro_output", lambda: rsf.gyro_output([1.0, 2.0], [0.1] * 3), ValueError,
     "omega_true, eps1, eps0", "broadcast")
case("rsf.gyro_output", lambda: rsf.gyro_output(1.0, 0.1, NAN), ValueError, "eps0",
     FINITE)
case("rsf.roll_difference", lambda: rsf.roll_difference([1.0, 2.0], [1.0, 2.0, 3.0]),
     ValueError, "gamma_sins, gamma_gs", "broadcast")
case("rsf.roll_difference", lambda: rsf.roll_difference(None, 1.0), TypeError,
     "gamma_sins")
case("rsf.sf_error_estimate", lambda: rsf.sf_error_estimate(1.0, 0.0, 1.0),
     ValueError, "omega_x", "nonzero")
case("rsf.sf_error_estimate", lambda: rsf.sf_error_estimate(1.0, 1.0, 0.0),
     ValueError, "dt", POS)
case("rsf.sf_error_estimate", lambda: rsf.sf_error_estimate([1.0, 2.0], [1.0] * 3,
                                                                       1.0),
     ValueError, "dgamma, omega_x", "broadcast")
case("rsf.correction_coefficient", lambda: rsf.correction_coefficient(0.1, "x"),
     ValueError, "form", "one of")
case("rsf.correction_coefficient", lambda: rsf.correction_coefficient(NAN),
     ValueError, "eps1_hat", FINITE)
case("rsf.corrected_rate", lambda: rsf.corrected_rate([1.0, 2.0], [1.0] * 3),
     ValueError, "omega_x, k", "broadcast")
case("rsf.corrected_rate", lambda: rsf.corrected_rate(1.0, "a"), TypeError, "k")
case("rsf.k_true", lambda: rsf.k_true(-1.0), ValueError, "eps1", r"\(-1.0, 1.0\)")
case("rsf.relative_k_error", lambda: rsf.relative_k_error([1.0, 2.0], [0.1] * 3),
     ValueError, "k, eps1", "broadcast")
case("rsf.relative_k_error", lambda: rsf.relative_k_error(1.0, 1.5), ValueError,
     "eps1")
case("rsf.residual_sf_error", lambda: rsf.residual_sf_error([0.1] * 2, [1.0] * 3),
     ValueError, "eps1, k", "broadcast")
case("rsf.fraction_compensated", lambda: rsf.fraction_compensated(0.0, 0.1),
     ValueError, "eps1", "nonzero")
case("rsf.fraction_compensated", lambda: rsf.fraction_compensated([0.1] * 2,
                                                                             [0.1] * 3),
     ValueError, "eps1, residual", "broadcast")
case("rsf.sins_roll_error", lambda: rsf.sins_roll_error(0.1, 1.0, -1.0), ValueError,
     "t", NONNEG)
case("rsf.sins_roll_error", lambda: rsf.sins_roll_error(0.1, [1.0, 2.0], [1.0] * 3),
     ValueError, "eps1, omega_true, t, eps0", "broadcast")
case("rsf.gs_bias_total", lambda: rsf.gs_bias_total(-1.0, 1.0), ValueError,
     "sigma_rep", NONNEG)
case("rsf.gs_bias_total", lambda: rsf.gs_bias_total(1.0, None), TypeError,
     "sigma_stab")
case("rsf.gs_roll_error_ideal", lambda: rsf.gs_roll_error_ideal(-1.0, 1.0, 0.0),
     ValueError, "eps0_gs", NONNEG)
case("rsf.gs_roll_error_ideal", lambda: rsf.gs_roll_error_ideal(1.0, 1.0, -0.1),
     ValueError, "dgamma_enc", NONNEG)
case("rsf.gs_roll_error_nonideal",
     lambda: rsf.gs_roll_error_nonideal(0.1, 0.1, NAN, 1.0, 0.0), ValueError, "omega_unc", FINITE)
case("rsf.gs_roll_error_nonideal",
     lambda: rsf.gs_roll_error_nonideal(0.1, 1.0, 1.0, 1.0, 0.0), ValueError, "eps1_gs")
case("rsf.difference_error", lambda: rsf.difference_error(0.1, 0.0, 0.0), ValueError,
     "dt", POS)
case("rsf.delta_k", lambda: rsf.delta_k(0.1, 0.0, 0.0, 1.0), ValueError, "omega_x",
     "nonzero")
case("rsf.delta_k", lambda: rsf.delta_k(0.1, 0.0, 1.0, -1.0), ValueError, "dt", POS)
case("rsf.delta_k_ideal", lambda: rsf.delta_k_ideal(0.1, -1.0, 1.0, 1.0), ValueError,
     "dgamma_enc", NONNEG)
case("rsf.lateral_acceleration_error",
     lambda: rsf.lateral_acceleration_error(0.1, 1.0, 1.0, 0.0), ValueError, "g", POS)
case("rsf.lateral_acceleration_error",
     lambda: rsf.lateral_acceleration_error(0.1, 1.0, 1.0, small_angle="no"), TypeError,
     "small_angle", "bool")
case("rsf.lateral_deviation_cubic", lambda: rsf.lateral_deviation_cubic(0.1, 1.0,
                                                                                   -1.0),
     ValueError, "t", NONNEG)
case("rsf.lateral_deviation_exact", lambda: rsf.lateral_deviation_exact(0.1, INF,
                                                                                   1.0),
     ValueError, "omega", FINITE)
case("rsf.table2", lambda: rsf.table2(None), TypeError, "gyro", "RollGyroSpec")
case("rsf.table2", lambda: rsf.table2(times=[]), ValueError, "times")
case("rsf.table2", lambda: rsf.table2(omega_true=NAN), ValueError, "omega_true")
case("rsf.table3", lambda: rsf.table3(encoder=None), TypeError, "encoder")
case("rsf.table3", lambda: rsf.table3(eps0_gs=-1.0), ValueError, "eps0_gs", NONNEG)
case("rsf.table3", lambda: rsf.table3(times=[-1.0]), ValueError, "times")
case("rsf.Table2", lambda: rsf.Table2("a", T5, T5, T5), TypeError, "t")
case("rsf.Table2", lambda: rsf.Table2(T5, T5, T5[:2], T5), ValueError, "dr_z_cubic")
case("rsf.Table3", lambda: rsf.Table3(T5, T5 * NAN, T5), ValueError, "eps0_t",
     FINITE)
case("rsf.worked_example_delta_k", lambda: rsf.worked_example_delta_k(None),
     TypeError, "gyro", "MemsGyroSpec")
case("rsf.worked_example_delta_k", lambda: rsf.worked_example_delta_k(encoder=None),
     TypeError, "encoder", "EncoderSpec")
case("rsf.worked_example_delta_k", lambda: rsf.worked_example_delta_k(dt=0.0),
     ValueError, "dt", POS)
case("rsf.worked_example_delta_k", lambda: rsf.worked_example_delta_k(eps1_gs=2.0),
     ValueError, "eps1_gs")

# rsf_simulation
case("rsf.RollProfile", lambda: rsf.RollProfile(-1.0), ValueError, "rate_start", POS)
case("rsf.RollProfile", lambda: rsf.RollProfile(1.0, NAN), ValueError, "rate_end")
case("rsf.RollProfile.rate", lambda: rsf.RollProfile().rate(T5, 0.0), ValueError,
     "duration", POS)
case("rsf.RollProfile.rate", lambda: rsf.RollProfile().rate([NAN], 1.0), ValueError,
     "t", FINITE)
case("rsf.SinsGyroModel", lambda: rsf.SinsGyroModel(eps1=1.0), ValueError, "eps1",
     r"\[-0.5, 0.5\]")
case("rsf.SinsGyroModel", lambda: rsf.SinsGyroModel(arw=-1.0), ValueError, "arw",
     NONNEG)
case("rsf.GsModel", lambda: rsf.GsModel(ki=0.0), ValueError, "ki", POS)
case("rsf.GsModel", lambda: rsf.GsModel(motor_rate_max=NAN), ValueError,
     "motor_rate_max")
case("rsf.GsModel", lambda: rsf.GsModel(tau_motor=-0.1), ValueError, "tau_motor")
case("rsf.EncoderModel", lambda: rsf.EncoderModel(counts_per_rev=2), ValueError,
     "counts_per_rev", ">= 4")
case("rsf.EncoderModel", lambda: rsf.EncoderModel(position_error=1.0), ValueError,
     "position_error", r"\[0.0, 0.5\]")
case("rsf.SimulationConfig", lambda: rsf.SimulationConfig(n_runs=0), ValueError,
     "n_runs", ">= 1")
case("rsf.SimulationConfig", lambda: rsf.SimulationConfig(errors="x"), ValueError,
     "errors", "one of")
case("rsf.SimulationConfig", lambda: rsf.SimulationConfig(roll=None), TypeError,
     "roll", "RollProfile")
case("rsf.SimulationConfig", lambda: rsf.SimulationConfig(duration=0.015),
     ValueError, "duration * sample_rate", "integer")
case("rsf.SimulationConfig", lambda: rsf.SimulationConfig(sample_rate=4.0),
     ValueError, "sample_rate")
case("rsf.encoder_counts", lambda: rsf.encoder_counts(T5, None), TypeError,
     "encoder", "EncoderModel")
case("rsf.encoder_counts", lambda: rsf.encoder_counts(T5, ENC, NAN), ValueError,
     "phase", FINITE)
case("rsf.encoder_counts", lambda: rsf.encoder_counts(np.ones((2, 5)), ENC,
                                                                 [1.0, 2.0, 3.0]),
     ValueError, "phase", "leading axes")
case("rsf.encoder_counts", lambda: rsf.encoder_counts("x", ENC), TypeError, "theta")
case("rsf.unwrap_counts", lambda: rsf.unwrap_counts(T5, 10), TypeError, "wrapped",
     "integer")
case("rsf.unwrap_counts", lambda: rsf.unwrap_counts(np.array([1, 20]), 10),
     ValueError, "wrapped", r"\[0, 10\)")
case("rsf.unwrap_counts", lambda: rsf.unwrap_counts(np.array([1, 2]), 1), ValueError,
     "counts_per_rev", ">= 2")
case("rsf.simulate_flight", lambda: rsf.simulate_flight(None, 0), TypeError, "config")
case("rsf.simulate_flight", lambda: rsf.simulate_flight(cfg(), -1), ValueError, "seed", ">= 0")
case("rsf.simulate_flight", lambda: rsf.simulate_flight(cfg(), 1.5), TypeError, "seed")
case("rsf.SensorRecord", lambda: replace(rec(), sins_inc=rec().sins_inc[:1]),
     ValueError, "sins_inc")
case("rsf.SensorRecord", lambda: replace(rec(), seed=None), TypeError, "seed")
case("rsf.with_encoder", lambda: rsf.with_encoder(None, ENC), TypeError, "record")
case("rsf.with_encoder", lambda: rsf.with_encoder(rec(), rsf.AEDB9340), TypeError,
     "encoder", "EncoderModel")
case("rsf.gs_angle", lambda: rsf.gs_angle(None), TypeError, "record")
case("rsf.gs_angle", lambda: rsf.gs_angle(rec(), gyro_angle=np.zeros(3)), ValueError,
     "gyro_angle", r"\(2, 201\)")
case("rsf.lateral_error", lambda: rsf.lateral_error(T5, np.ones(3)), ValueError,
     "roll_error", "5 samples")
case("rsf.lateral_error", lambda: rsf.lateral_error(T5, T5, 0.0), ValueError, "g",
     POS)
case("rsf.lateral_error", lambda: rsf.lateral_error(T5[::-1], T5), ValueError, "t",
     "increasing")
case("rsf.run_correction", lambda: rsf.run_correction(None, 1.0), TypeError,
     "record")
case("rsf.run_correction", lambda: rsf.run_correction(rec(), 0.0), ValueError,
     "period", POS)
case("rsf.run_correction", lambda: rsf.run_correction(rec(), 0.015), ValueError,
     "period", "whole number of samples")
case("rsf.run_correction", lambda: rsf.run_correction(rec(), 10.0), ValueError,
     "period", "<= the run duration")
case("rsf.run_correction", lambda: rsf.run_correction(rec(), 1.0, k_form="x"),
     ValueError, "k_form", "one of")
case("rsf.run_correction", lambda: rsf.run_correction(rec(), 1.0, reset_angle=1),
     TypeError, "reset_angle", "bool")
case("rsf.run_correction", lambda: rsf.run_correction(rec(), 1.0, g=NAN), ValueError,
     "g")
case("rsf.CorrectionRun", lambda: replace(corr(), k_form="x"), ValueError, "k_form")
case("rsf.CorrectionRun", lambda: replace(corr(), delta_k=corr().delta_k[:, :0]),
     ValueError, "delta_k")
case("rsf.predict_delta_k", lambda: rsf.predict_delta_k(None, 1.0), TypeError,
     "config")
case("rsf.predict_delta_k", lambda: rsf.predict_delta_k(cfg(), 0.0), ValueError,
     "period", POS)
case("rsf.DeltaKPrediction", lambda: rsf.DeltaKPrediction(0.0, -1.0, 0, 0, 0, 0, 0,
                                                                     0),
     ValueError, "std_encoder", NONNEG)
case("rsf.DeltaKPrediction", lambda: rsf.DeltaKPrediction(NAN, 0, 0, 0, 0, 0, 0, 0),
     ValueError, "mean", FINITE)
case("rsf.sweep_correction_period", lambda: rsf.sweep_correction_period(None, [1.0]),
     TypeError, "record")
case("rsf.sweep_correction_period", lambda: rsf.sweep_correction_period(
    rec(), [1.0], k_form="x"), ValueError, "k_form", "one of")
case("rsf.sweep_correction_period", lambda: rsf.sweep_correction_period(rec(), [0.0]),
     ValueError, "periods", POS)
case("rsf.sweep_correction_period", lambda: rsf.sweep_correction_period(rec(),
                                                                                   [[1.0]]),
     ValueError, "periods", "1-D")
case("rsf.PeriodSweep", lambda: rsf.PeriodSweep(T5, T5, T5, T5, T5, T5[:2]),
     ValueError, "eq7")
case("rsf.sweep_encoder", lambda: rsf.sweep_encoder(rec(), ENC, 1.0), TypeError,
     "encoders", "list or tuple")
case("rsf.sweep_encoder", lambda: rsf.sweep_encoder(rec(), [], 1.0), ValueError,
     "encoders", "non-empty")
case("rsf.sweep_encoder", lambda: rsf.sweep_encoder(rec(), [None], 1.0), TypeError,
     "encoders[0]", "EncoderModel")
case("rsf.sweep_encoder", lambda: rsf.sweep_encoder(None, [ENC], 1.0), TypeError,
     "record")
case("rsf.sweep_encoder", lambda: rsf.sweep_encoder(rec(), [ENC], 1.0, k_form="x"),
     ValueError, "k_form")
case("rsf.sweep_encoder", lambda: rsf.sweep_encoder(rec(), [ENC], 0.0), ValueError,
     "period", POS)
case("rsf.ResolutionSweep", lambda: rsf.ResolutionSweep(T5, T5, T5, "a", T5, T5, T5),
     TypeError, "rms")

# rsf_plots
F3 = (0.1, T5, T5, T5, T5, T5, T5)
case("rsf.plot_figure3", lambda: rsf.plot_figure3(NAN, *F3[1:]), ValueError,
     "dgamma_example", FINITE)
case("rsf.plot_figure3", lambda: rsf.plot_figure3(0.1, T5, T5[:2], *F3[3:]), ValueError,
     "roll_error", "length of t")
case("rsf.plot_figure3", lambda: rsf.plot_figure3(0.1, "abc", *F3[2:]), TypeError, "t")
case("rsf.plot_figure3", lambda: rsf.plot_figure3(0.1, [], [], [], [], [], []), ValueError,
     "t", "at least 2")
case("rsf.plot_figure3", lambda: rsf.plot_figure3(*F3, (1.0, 2.0), (1.0,)), ValueError,
     "printed_dr", "length of table_t")
case("rsf.plot_figure3", lambda: rsf.plot_figure3(*F3, (0.0,), (1.0,)), ValueError,
     "table_t", r"> 0 \(log axis\)")
FL = (T5, T5, T5, T5, T5, T5)
case("rsf.plot_flight", lambda: rsf.plot_flight(T5, T5, T5[:2], T5, T5, T5), ValueError,
     "roll_corrected", "length of t")
case("rsf.plot_flight", lambda: rsf.plot_flight(T5, None, T5, T5, T5, T5), TypeError,
     "roll_raw")
case("rsf.plot_flight", lambda: rsf.plot_flight(T5, T5 * NAN, T5, T5, T5, T5), ValueError,
     "roll_raw", FINITE)
case("rsf.plot_flight", lambda: rsf.plot_flight(*FL, [NAN]), ValueError, "t_boundaries",
     FINITE)
case("rsf.plot_flight", lambda: rsf.plot_flight(*FL, (), T5[:3]), ValueError, "roll_reset")
case("rsf.plot_flight", lambda: rsf.plot_flight(*FL, (), None, "x"), TypeError,
     "lateral_reset")
case("rsf.plot_delta_k_distribution", lambda: rsf.plot_delta_k_distribution("a", 0, 1, 0),
     TypeError, "delta_k")
case("rsf.plot_delta_k_distribution", lambda: rsf.plot_delta_k_distribution([], 0, 1, 0),
     ValueError, "delta_k", "at least 1")
case("rsf.plot_delta_k_distribution", lambda: rsf.plot_delta_k_distribution(T5, 0, -1, 0),
     ValueError, "predicted_std", NONNEG)
case("rsf.plot_delta_k_distribution", lambda: rsf.plot_delta_k_distribution(T5, NAN, 1, 0),
     ValueError, "predicted_mean", FINITE)
case("rsf.plot_delta_k_distribution", lambda: rsf.plot_delta_k_distribution(T5, 0, 1, "0"),
     TypeError, "eq7")
case("rsf.plot_delta_k_distribution", lambda: rsf.plot_delta_k_distribution(T5, 0, 1, 0,
                                                                                 INF),
     ValueError, "eq7_paper", FINITE)
case("rsf.plot_period_sweep", lambda: rsf.plot_period_sweep(T5 + 1, T5[:2], T5, T5, 1, 1),
     ValueError, "rms", "length of periods")
case("rsf.plot_period_sweep", lambda: rsf.plot_period_sweep(T5, T5, T5, T5, 1, 1),
     ValueError, "periods", r"> 0")
case("rsf.plot_period_sweep", lambda: rsf.plot_period_sweep(T5 + 1, T5, T5, T5, NAN, 1),
     ValueError, "floor", FINITE)
case("rsf.plot_period_sweep", lambda: rsf.plot_period_sweep(T5 + 1, T5, T5, -T5, 1, 1),
     ValueError, "eq7", NONNEG)
case("rsf.plot_period_sweep", lambda: rsf.plot_period_sweep(T5 + 1, T5, T5, T5, 1, None),
     TypeError, "eps1")
case("rsf.plot_encoder_sweep", lambda: rsf.plot_encoder_sweep(T5 + 1, T5, T5, T5, T5,
                                                                   T5[:2]),
     ValueError, "predicted_without", "length of counts")
case("rsf.plot_encoder_sweep", lambda: rsf.plot_encoder_sweep(-T5, T5, T5, T5, T5, T5),
     ValueError, "counts", r"> 0")
case("rsf.plot_rate_sweep", lambda: rsf.plot_rate_sweep(T5, T5[:2], T5, T5), ValueError,
     "rms", "length of rates")
case("rsf.plot_rate_sweep", lambda: rsf.plot_rate_sweep(T5, T5, -T5, T5), ValueError,
     "predicted_rms", NONNEG)
case("rsf.plot_spin_up", lambda: rsf.plot_spin_up(T5, T5[:2], T5, T5), ValueError, "rate",
     "length of t")
case("rsf.plot_spin_up", lambda: rsf.plot_spin_up(T5, "a", T5, T5), TypeError, "rate")
case("rsf.plot_spin_up", lambda: rsf.plot_spin_up(T5[::-1], T5, T5, T5), ValueError, "t",
     "increasing")

# ledger
case("ledger.LedgerItem", lambda: item(id=None), TypeError, "id", "str")
case("ledger.LedgerItem", lambda: item(note=1.0), TypeError, "note", "str")
case("ledger.LedgerItem", lambda: item(reproduced_value="1"), TypeError, "reproduced_value")
case("ledger.LedgerItem", lambda: item(reproduced_value=True), TypeError, "reproduced_value")
case("ledger.LedgerItem", lambda: item(reproduced_value=INF), ValueError, "reproduced_value",
     FINITE)
case("ledger.LedgerItem", lambda: item(paper_value=NAN), ValueError, "paper_value", FINITE)
case("ledger.LedgerItem", lambda: item(paper_value=[1]), TypeError, "paper_value")
case("ledger.LedgerItem", lambda: item(status="close enough"), ValueError, "status", "one of")
case("ledger.LedgerItem", lambda: item(paper="XYZ"), ValueError, "paper", "'GC' or 'RSF'")
case("ledger.to_json", lambda: ledger.to_json(None), TypeError, "items", "LedgerItem")
case("ledger.to_json", lambda: ledger.to_json([1]), TypeError, "items")
case("ledger.to_table", lambda: ledger.to_table("abc"), TypeError, "items")
case("ledger.summary", lambda: ledger.summary([item(), 1]), TypeError, "items")
case("ledger.to_markdown", lambda: ledger.to_markdown([item()], "XYZ"), ValueError, "paper",
     "'GC' or 'RSF'")
case("ledger.to_markdown", lambda: ledger.to_markdown(None, "GC"), TypeError, "items")
case("ledger.gc.items", lambda: lgc.items("x"), TypeError, "params", "GyrocompassParams")
case("ledger.rsf.items", lambda: lrsf.items(roll_gyro=None), TypeError, "roll_gyro",
     "RollGyroSpec")
case("ledger.rsf.items", lambda: lrsf.items(gs_gyro="x"), TypeError, "gs_gyro", "MemsGyroSpec")
case("ledger.rsf.items", lambda: lrsf.items(encoder=rsf.EncoderModel()), TypeError, "encoder",
     "EncoderSpec")
case("ledger.format_value", lambda: ledger.format_value([1.0]), TypeError, "value", "real")
case("ledger.format_value", lambda: ledger.format_value(NAN), ValueError, "value", FINITE)

# report
case("report.sci", lambda: report.sci(NAN), ValueError, "x", FINITE)
case("report.sci", lambda: report.sci("1e-4"), TypeError, "x", "real")
case("report.sci", lambda: report.sci(1.0, 0), ValueError, "digits", ">= 1")
case("report.grouped", lambda: report.grouped(INF), ValueError, "x", FINITE)
case("report.grouped", lambda: report.grouped(1.0, 2.5), TypeError, "digits")
case("report.format_number", lambda: report.format_number(1.0, 3), TypeError, "fmt", "str")
case("report.format_number", lambda: report.format_number(NAN, ".3f"), ValueError, "value",
     FINITE)
case("report.format_number", lambda: report.format_number("x", ".3f"), TypeError, "value")
case("report.markdown_table", lambda: report.markdown_table([], []), ValueError, "header")
case("report.markdown_table", lambda: report.markdown_table(["a", "b"], [[1]]), ValueError,
     "rows[0]", "2 cells")
case("report.gluer", lambda: report.gluer(None), TypeError, "prefix", "str")

# __main__
case("__main__.main", lambda: cli.main("ledger"), TypeError, "argv", "list of str")
case("__main__.main", lambda: cli.main([1]), TypeError, "argv")


@pytest.mark.parametrize(("call", "exc", "pattern"), CASES)
def test_bad_input_is_rejected_by_name(call, exc, pattern):
    with pytest.raises(exc, match=pattern) as info:
        call()
    assert type(info.value) is exc  # not a subclass such as numpy's LinAlgError


def test_cli_rejects_an_unknown_command_with_usage(capsys):
    with pytest.raises(SystemExit) as info:
        cli.main(["nope"])
    assert info.value.code == 2
    assert "invalid choice: 'nope'" in capsys.readouterr().err


# Coverage of the table -------------------------------------------------------------------------
MODULES = {"units": units, "gc": gc, "gc.symbolic": symbolic, "filtering": filtering,
           "rsf": rsf, "ledger": ledger, "ledger.gc": lgc, "ledger.rsf": lrsf, "report": report}
#: Public callables without a bad input: no parameters, or any object is valid by contract.
NO_BAD_INPUT = {"gc.symbolic.display_form": "returns non-sympy objects unchanged (documented)",
                "report.MarkdownText": "a str subclass: any text is valid"}


def _takes_input(fn) -> bool:
    params = list(inspect.signature(fn).parameters.values())
    return bool(params[1:] if params and params[0].name == "self" else params)


def public_callables() -> set[str]:
    out = set()
    for mod_name, mod in MODULES.items():
        for name in mod.__all__:
            obj = getattr(mod, name)
            if inspect.isclass(obj):
                out.add(f"{mod_name}.{name}")
                for meth_name, meth in vars(obj).items():
                    if (not meth_name.startswith("_") and inspect.isfunction(meth)
                            and _takes_input(meth)):
                        out.add(f"{mod_name}.{name}.{meth_name}")
            elif inspect.isfunction(obj) and _takes_input(obj):
                out.add(f"{mod_name}.{name}")
    return out | {"__main__.main"}


def test_table_covers_every_public_callable():
    missing = public_callables() - COVERED - set(NO_BAD_INPUT)
    assert not missing, f"no bad-input case for: {sorted(missing)}"
    assert not COVERED - public_callables(), "the table names a callable that is not public"
    assert len(CASES) >= 2 * len(COVERED)  # several parameter kinds per callable, on average


# Hypothesis: continuous ranges -----------------------------------------------------------------
NOT_POSITIVE = st.one_of(st.floats(max_value=0.0, allow_nan=False),
                         st.sampled_from([NAN, -INF, INF]))
SETTINGS = settings(max_examples=40, deadline=None)


@SETTINGS
@given(dt=NOT_POSITIVE)
def test_any_non_positive_or_non_finite_dt_is_rejected(dt):
    with pytest.raises(ValueError, match=r"^dt must be > 0"):
        filtering.van_loan(-np.eye(2), np.ones((2, 1)), [[1.0]], dt)
    with pytest.raises(ValueError, match=r"^dt must be > 0"):
        VIB.discretize(dt)
    with pytest.raises(ValueError, match=r"^dt\b"):
        replace(P, dt=dt)


@SETTINGS
@given(t_end=NOT_POSITIVE)
def test_any_non_positive_t_end_is_rejected(t_end):
    with pytest.raises(ValueError, match=r"^t_end must be > 0"):
        gc.discretize(P, t_end)
    with pytest.raises(ValueError, match=r"^t_end must be > 0"):
        gc.covariance_analysis(P, t_end)


@SETTINGS
@given(k=st.integers(0, 10**5), frac=st.floats(0.01, 0.99))
def test_any_t_end_off_the_dt_grid_is_rejected(k, frac):
    t_end = (k + frac) * P.dt
    with pytest.raises(ValueError, match=r"^t_end must be a positive multiple of dt"):
        gc.discretize(P, t_end)


@SETTINGS
@given(n=st.integers(max_value=0))
def test_any_run_count_below_one_is_rejected(n):
    with pytest.raises(ValueError, match=r"^n_runs must be an integer >= 1"):
        gc.monte_carlo(P, n, 0.01)
    with pytest.raises(ValueError, match=r"^n_runs must be an integer >= 1"):
        rsf.SimulationConfig(n_runs=n)
    with pytest.raises(ValueError, match=r"^n_runs must be an integer >= 1"):
        filtering.nees_bounds(1, n)


@SETTINGS
@given(seed=st.one_of(st.integers(max_value=-1), st.floats(allow_nan=True), st.text(max_size=3),
                      st.none()))
def test_any_seed_that_is_not_a_non_negative_int_is_rejected(seed):
    with pytest.raises((ValueError, TypeError), match=r"^seed must be an integer >= 0"):
        gc.simulate_shaping_filter(VIB, 0.1, 10, seed)
    with pytest.raises((ValueError, TypeError), match=r"^seed must be an integer >= 0"):
        rsf.simulate_flight(cfg(), seed)


POSITIVE_FIELDS = ("I", "H", "f", "Omega_v", "Omega_h", "g", "alpha1", "sigma1_sq", "alpha2",
                   "sigma2_sq", "C_as", "C_incl_y", "C_incl_z", "dt")


@SETTINGS
@given(field=st.sampled_from(POSITIVE_FIELDS), value=NOT_POSITIVE)
def test_any_non_positive_physical_parameter_is_rejected_by_name(field, value):
    with pytest.raises(ValueError, match=rf"^{field} must be > 0"):
        replace(P, **{field: value})


@SETTINGS
@given(field=st.sampled_from(("xi1", "xi2")),
       xi=st.one_of(st.floats(max_value=0.0), st.floats(min_value=1.0, exclude_min=True)))
def test_any_damping_outside_zero_one_is_rejected(field, xi):
    with pytest.raises(ValueError, match=rf"^{field} must be "):
        replace(P, **{field: xi})


@SETTINGS
@given(eps1=st.one_of(st.floats(min_value=1.0), st.floats(max_value=-1.0),
                      st.sampled_from([NAN])))
def test_any_scale_factor_error_outside_minus_one_one_is_rejected(eps1):
    for call in (lambda: rsf.k_true(eps1), lambda: rsf.gyro_output(1.0, eps1),
                 lambda: rsf.lateral_deviation_exact(eps1, 1.0, 1.0)):
        with pytest.raises(ValueError, match=r"^eps1 must be "):
            call()


@SETTINGS
@given(values=st.lists(st.floats(-1e6, 1e6), min_size=1, max_size=8), where=st.integers(0, 7))
def test_a_nan_anywhere_in_a_unit_conversion_is_rejected(values, where):
    values[where % len(values)] = NAN
    with pytest.raises(ValueError, match=r"^value must be a number or ±inf, not NaN"):
        units.to_si(values, "deg/h")


@SETTINGS
@given(a=st.integers(2, 6), b=st.integers(2, 6))
def test_arrays_of_incompatible_lengths_are_rejected_by_name(a, b):
    if a == b:
        b += 1
    with pytest.raises(ValueError, match=r"^gamma_sins, gamma_gs must have broadcast"):
        rsf.roll_difference(np.zeros(a), np.zeros(b))


@SETTINGS
@given(duration=st.floats(0.02, 10.0), sample_rate=st.sampled_from([100.0, 200.0]))
def test_durations_off_the_sample_grid_are_rejected(duration, sample_rate):
    n = duration * sample_rate
    if abs(n - round(n)) < 1e-6:
        return  # on the grid: valid
    with pytest.raises(ValueError, match=r"^duration \* sample_rate must be an integer"):
        rsf.SimulationConfig(duration=duration, sample_rate=sample_rate)


# Valid input is untouched ------------------------------------------------------------------------
@SETTINGS
@given(x=st.floats(-1e6, 1e6), unit=st.sampled_from(sorted(units.UNITS)))
def test_finite_and_infinite_values_still_convert_exactly(x, unit):
    assert units.to_si(x, unit) == x * units.UNITS[unit]
    assert units.from_si(INF, unit) == INF
