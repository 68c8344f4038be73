"""Bad input to paper GC (:mod:`gyrolib.gc`, ``gc.symbolic``) is rejected by name.

The reference is the contract of CONTRIBUTING.md: bad input raises ``ValueError`` or
``TypeError`` whose message starts with the name of the offending parameter (and, where the
range is a number, states it), never an error from deep inside, a silent NaN or a wrong figure.
The table's coverage is computed from the subpackage's ``__all__`` and its classes' public
methods; hypothesis properties cover continuous ranges.
"""

from __future__ import annotations

import functools

import pytest
from hypothesis import given
from hypothesis import strategies as st

from tests.support.validation_table import *

TABLE = Table()
case = TABLE.case

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
case("gc.ShapingFilter.autocorrelation", lambda: VIB.autocorrelation(NAN), ValueError,
     "lag", FINITE)
case("gc.vibration_filter", lambda: gc.vibration_filter(NAN, 0.5, 1.0),
     ValueError, "alpha1", POS)
case("gc.vibration_filter", lambda: gc.vibration_filter(1.0, 0.0, 1.0),
     ValueError, "xi1", r"\(0.0, 1.0\]")
case("gc.vibration_filter", lambda: gc.vibration_filter(1.0, 0.5, "1"),
     TypeError, "sigma1_sq")
case("gc.vibration_filter", lambda: gc.vibration_filter(1.0, 0.5, 1.0, f87="+"),
     ValueError, "f87", "one of")
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
case("gc.GyrocompassParams", lambda: replace(P, eq1_sign=-1), ValueError, "eq1_sign",
     "one of")
case("gc.GyrocompassParams", lambda: replace(P, omega_ub=INF), ValueError, "omega_ub",
     FINITE)
case("gc.GyrocompassParams", lambda: replace(P, shaping_p0_scale=-0.5), ValueError,
     "shaping_p0_scale", NONNEG)
case("gc.state_index", lambda: gc.state_index("foo"), ValueError, "name", "one of")
# instrument (the declaration of the instrument's constant errors)
case("gc.InstrumentTerm", lambda: gc.InstrumentTerm("x", "sigma_foo"), ValueError,
     "prior_field", "GyrocompassParams field")
case("gc.InstrumentTerm", lambda: gc.InstrumentTerm("x", "sigma_as_offset", H0=(1.0, 0.0)),
     ValueError, "H0", r"\(3,\)")
case("gc.InstrumentTerm", lambda: gc.InstrumentTerm("x", "sigma_as_offset", Fb=[NAN] * 10),
     ValueError, "Fb", FINITE)
case("gc.InstrumentTerm", lambda: gc.InstrumentTerm("omega_gc", "sigma_as_offset"),
     ValueError, "name", "state of Eq")
case("gc.InstrumentTerm", lambda: gc.InstrumentTerm("x", "sigma_as_offset", group="bias"),
     ValueError, "group", "one of")
case("gc.InstrumentTerm.prior", lambda: gc.TERMS[0].prior("P"), TypeError, "params")
case("gc.InstrumentModel", lambda: gc.InstrumentModel(("a",), np.ones(2), np.ones((3, 1)),
                                                      np.ones((3, 1)), np.ones((10, 1)),
                                                      ("scale",)),
     ValueError, "prior", r"\(1,\)")
case("gc.InstrumentModel.measurement_columns",
     lambda: gc.instrument_model(P).measurement_columns(NAN), ValueError, "beta_n", FINITE)
case("gc.instrument_model", lambda: gc.instrument_model(None), TypeError, "params")
case("gc.instrument_model", lambda: gc.instrument_model(P, names=("offset",)), ValueError,
     "names", "terms of TERMS")
case("gc.instrument_model", lambda: gc.instrument_model(P, names="scale"), TypeError,
     "names", "tuple or list")
case("gc.state_names", lambda: gc.state_names(3), TypeError, "params")
case("gc.normal_gravity", lambda: gc.normal_gravity(2.0), ValueError, "latitude",
     r"\[-1.57")
case("gc.normal_gravity", lambda: gc.normal_gravity("0"), TypeError, "latitude")
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
case("gc.symbolic.to_latex", lambda: symbolic.to_latex(S.t, 3), TypeError, "lhs")
case("gc.symbolic.to_latex_aligned", lambda: symbolic.to_latex_aligned("y", S.t, 0),
     ValueError, "per_line", ">= 1")
case("gc.symbolic.cauchy_form_latex", lambda: symbolic.cauchy_form_latex(None), TypeError,
     "model")
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

# gc_estimation
case("gc.nominal_half_steps", lambda: gc.nominal_half_steps(None, 10), TypeError,
     "params")
case("gc.nominal_half_steps", lambda: gc.nominal_half_steps(P, 0), ValueError,
     "n_steps", ">= 1")
case("gc.discretize", lambda: gc.discretize(P, 0.01, instrument=1), TypeError, "instrument")
case("gc.discretize", lambda: gc.discretize(P, 0.0), ValueError, "t_end", POS)
case("gc.discretize", lambda: gc.discretize(P, 0.0105), ValueError, "t_end",
     "multiple of dt")
case("gc.discretize", lambda: gc.discretize(P, "1"), TypeError, "t_end")
case("gc.discretize", lambda: gc.discretize(P, 0.01, method="rk4"), ValueError, "method",
     "one of")
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
case("gc.covariance_analysis",
     lambda: gc.covariance_analysis(replace(P, sigma_as_offset=1e-5), 0.01, P0=I10),
     ValueError, "P0", r"\(11, 11\)")
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
case("gc.covariance_analysis", lambda: gc.covariance_analysis(
    P, 0.01, discretization="tustin"), ValueError, "discretization", "one of")
case("gc.CovarianceSweep", lambda: gc.CovarianceSweep(P, ({}, {}), ()), ValueError,
     "analyses", "one CovarianceAnalysis per case")
case("gc.sweep_covariance", lambda: gc.sweep_covariance(P, {"xi1": 0.5}, 0.01), TypeError,
     "cases", "sequence")
case("gc.sweep_covariance", lambda: gc.sweep_covariance(P, [{"nope": 1.0}], 0.01),
     ValueError, "cases", "fields")
case("gc.sweep_covariance", lambda: gc.sweep_covariance(P, [{"xi1": 2.0}], 0.01),
     ValueError, "xi1", r"\(0.0, 1.0\]")
case("gc.sweep_covariance", lambda: gc.sweep_covariance(P, [{}], -1.0), ValueError,
     "t_end", POS)
case("gc.CovarianceSweep.final_std", lambda: gc.sweep_covariance(
    P, [{}], 0.01).final_std("x"), ValueError, "name", "one of")
case("gc.CovarianceAnalysis.final_std", lambda: cov().final_std("x"), ValueError, "name",
     "one of")
case("gc.CovarianceAnalysis", lambda: replace(cov(), var=cov().var[:, :3]),
     ValueError, "var")
case("gc.CovarianceAnalysis", lambda: replace(cov(), params=None), TypeError,
     "params")
case("gc.CovarianceAnalysis.std", lambda: cov().std("x"), ValueError, "name",
     "one of")
case("gc.CovarianceAnalysis.final_std", lambda: cov().final_std("Psi"), ValueError, "name",
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
case("gc.monte_carlo", lambda: gc.monte_carlo(P, 1, 0.01, truth_params="p"), TypeError,
     "truth_params")
case("gc.monte_carlo", lambda: gc.monte_carlo(P, 1, 0.01, truth_params=replace(P, dt=2e-3)),
     ValueError, "truth_params.dt")
case("gc.monte_carlo", lambda: gc.monte_carlo(P, 1, 0.01, substeps=0), ValueError,
     "substeps", ">= 1")
case("gc.monte_carlo", lambda: gc.monte_carlo(P, 1, 0.01, executor=4), TypeError,
     "executor", "Executor")
case("gc.run_streams", lambda: gc.run_streams(-1, 2), ValueError, "seed", ">= 0")
case("gc.run_streams", lambda: gc.run_streams(1, 0), ValueError, "n_runs", ">= 1")
case("gc.truth_prior_factor", lambda: gc.truth_prior_factor(None), TypeError, "params")
case("gc.remainder_drift", lambda: gc.remainder_drift(None, 0.0), TypeError, "params")
case("gc.remainder_drift", lambda: gc.remainder_drift(P, NAN), ValueError, "psi", FINITE)
case("gc.remainder_drift", lambda: gc.remainder_drift(P, 0.0, "b"), TypeError, "beta_n")
case("gc.psi_for_drift", lambda: gc.psi_for_drift(P, NAN), ValueError, "drift", FINITE)
case("gc.psi_for_drift", lambda: gc.psi_for_drift(None, 1e-9), TypeError, "params")


@functools.cache
def lin_effect() -> gc.LinearizationEffect:
    return gc.linearization_effect(mc(), gc.monte_carlo(P, 2, 0.01, seed=1, truth="linear"))


case("gc.linearization_effect", lambda: gc.linearization_effect(None, mc()), TypeError,
     "nonlinear")
case("gc.linearization_effect", lambda: gc.linearization_effect(mc(), mc()), ValueError,
     "linear must come from")
case("gc.linearization_effect", lambda: gc.linearization_effect(
    mc(), gc.monte_carlo(P, 3, 0.01, seed=1, truth="linear")), ValueError,
     "nonlinear and linear must share n_runs")
case("gc.LinearizationEffect.inside", lambda: lin_effect().inside("x"), ValueError, "which")
case("gc.LinearizationEffect.slope", lambda: lin_effect().slope(1e9), ValueError, "t_min",
     "at most")
case("gc.LinearizationEffect.slope", lambda: lin_effect().slope(NAN), ValueError, "t_min",
     FINITE)
# claims
SC = units.to_si(2e-3, "arcsec_paper/s")
case("gc.time_to_level", lambda: gc.time_to_level(P, -1.0, 1.0), ValueError, "level", POS)
case("gc.time_to_level", lambda: gc.time_to_level(P, SC, NAN), ValueError, "t_max", FINITE)
case("gc.time_to_level", lambda: gc.time_to_level(None, SC, 1.0), TypeError, "params")
case("gc.speed_claim_map", lambda: gc.speed_claim_map(P, SC, 0.0), ValueError, "bound", POS)
case("gc.speed_claim_map", lambda: gc.speed_claim_map(P, SC, 1.0, x_field="nope"),
     ValueError, "x_field")
case("gc.speed_claim_map", lambda: gc.speed_claim_map(P, SC, 1.0, y_factors=[-1.0]),
     ValueError, "y_factors", "> 0")
case("gc.speed_claim_map", lambda: gc.speed_claim_map(P, SC, 1.0, readings="zero"),
     TypeError, "readings")
case("gc.speed_claim_map", lambda: gc.speed_claim_map(P, SC, 1.0, readings=("x",)),
     ValueError, "readings")
case("gc.claim_boundary", lambda: gc.claim_boundary(P, SC, 1.0, factors=[2.0, 1.0]),
     ValueError, "factors", "increasing")
case("gc.claim_boundary", lambda: gc.claim_boundary(P, SC, 1.0, factors=[1.0]),
     ValueError, "factors")
case("gc.claim_boundary", lambda: gc.claim_boundary(P, SC, 1.0, field=3), TypeError, "field")
case("gc.shaping_sweep", lambda: gc.shaping_sweep(P, 1.0, t_drop=2.0), ValueError, "t_drop")
case("gc.shaping_sweep", lambda: gc.shaping_sweep(P, 1.0, fields=("xi1", "x"), t_drop=0.5), ValueError,
     "fields")
case("gc.shaping_sweep", lambda: gc.shaping_sweep(P, 1.0, factors=[0.0], t_drop=0.5), ValueError,
     "factors", "> 0")
case("gc.SpeedClaimMap.largest_x_factor_holding",
     lambda: gc.speed_claim_map(P, SC, 0.01, x_factors=[1.0], y_factors=[1.0],
                                readings=("zero",), t_max=0.01).largest_x_factor_holding("stationary"),
     ValueError, "reading")
case("gc.MonteCarloResult", lambda: replace(mc(), truth_params=1), TypeError,
     "truth_params")
case("gc.MonteCarloResult", lambda: replace(mc(), tru=mc().tru[:1]), ValueError,
     "tru")
case("gc.MonteCarloResult", lambda: replace(mc(), seed=-3), ValueError, "seed")
case("gc.MonteCarloResult", lambda: replace(mc(), names=(*gc.STATE_NAMES, "scale")),
     ValueError, "est", r"11\)")
case("gc.MonteCarloResult", lambda: replace(mc(), names=("psi",)), ValueError, "names",
     "STATE_NAMES")
case("gc.MonteCarloResult", lambda: replace(mc(), truth_mode="linearized"), ValueError,
     "truth_mode")
case("gc.MonteCarloResult.inside_share", lambda: mc().inside_share(confidence=1.5),
     ValueError, "confidence")
case("gc.MonteCarloResult.inside_share", lambda: mc().inside_share("psi"), TypeError, "names")
case("gc.MonteCarloResult.select", lambda: mc().select(3), TypeError, "runs", "slice")
case("gc.MonteCarloResult.select", lambda: mc().select(slice(5, 9)), ValueError, "runs",
     "at least one")
case("gc.MonteCarloResult.estimate", lambda: mc().estimate("x"), ValueError, "name")
case("gc.MonteCarloResult.truth", lambda: mc().truth(3), ValueError, "name")
case("gc.MonteCarloResult.error", lambda: mc().error(None), ValueError, "name")
case("gc.MonteCarloResult.std", lambda: mc().std("omega"), ValueError, "name")
case("gc.MonteCarloResult.rms_error", lambda: mc().rms_error(""), ValueError, "name")
case("gc.MonteCarloResult.nees", lambda: mc().nees("psi"), TypeError, "names")
case("gc.MonteCarloResult.nees", lambda: mc().nees(()), ValueError, "names")
case("gc.MonteCarloResult.nees", lambda: mc().nees(("psi", "x")), ValueError, "name")
case("gc.simulate_truth", lambda: gc.simulate_truth(P, 0.01, np.zeros(10), seed="a"),
     TypeError, "seed")
case("gc.simulate_truth", lambda: gc.simulate_truth(P, 0.01, np.zeros(10), seed=-1),
     ValueError, "seed", ">= 0")
case("gc.simulate_truth", lambda: gc.simulate_truth(P, 0.01, np.zeros(3)),
     ValueError, "x0", r"\(10,\)")
case("gc.simulate_truth", lambda: gc.simulate_truth(P, 0.01, np.zeros(10), substeps=1.5),
     TypeError, "substeps")
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

# gc_model_plots

# calibration on a record: gc.calibrate, GCRecord, CalibrationResult, simulate_record
_GREC = gc.GCRecord(t=[0.001, 0.002], angle_sensor=[0.0, 0.0], inclinometer_y=[0.0, 0.0],
                    inclinometer_z=[0.0, 0.0])
_GRES = gc.calibrate(_GREC, gc.GyrocompassParams())
case("gc.GCRecord", lambda: gc.GCRecord(t=[0.002, 0.001], angle_sensor=[0, 0],
                                         inclinometer_y=[0, 0], inclinometer_z=[0, 0]),
     ValueError, "t", "strictly increasing")
case("gc.GCRecord", lambda: gc.GCRecord(t=[-1.0], angle_sensor=[0], inclinometer_y=[0],
                                         inclinometer_z=[0]), ValueError, "t", ">= 0")
case("gc.GCRecord", lambda: replace(_GREC, angle_sensor=[0.0, INF]), ValueError,
     "angle_sensor", "finite")
case("gc.GCRecord", lambda: replace(_GREC, inclinometer_z=[0.0]), ValueError,
     "inclinometer_z", "2 values")
case("gc.calibrate", lambda: gc.calibrate(_GREC, "paper"), TypeError, "params",
     "GyrocompassParams")
case("gc.calibrate", lambda: gc.calibrate(np.zeros(3)), TypeError, "record", "GCRecord")
case("gc.calibrate", lambda: gc.calibrate(_GREC, gate=1.0), ValueError, "gate", "in")
case("gc.calibrate", lambda: gc.calibrate(_GREC, store_every=0), ValueError, "store_every",
     ">= 1")
case("gc.calibrate", lambda: gc.calibrate(_GREC, chunk_size=1.5), TypeError, "chunk_size")
case("gc.calibrate", lambda: gc.calibrate(_GREC, lags=0), ValueError, "lags", ">= 1")
case("gc.calibrate", lambda: gc.calibrate(_GREC, time_tolerance=NAN), ValueError,
     "time_tolerance")
case("gc.calibrate", lambda: gc.calibrate(_GREC, progress=3), TypeError, "progress",
     "callable")
case("gc.CalibrationResult", lambda: replace(_GRES, x=np.zeros((5, 10))), ValueError, "x",
     "shape")
case("gc.CalibrationResult", lambda: replace(_GRES, params=None), TypeError, "params")
case("gc.CalibrationResult", lambda: replace(_GRES, bias_names=["scale"]), TypeError,
     "bias_names", "tuple")
case("gc.CalibrationResult",
     lambda: replace(_GRES, bias_names=("scale",), bias_groups=("scale",)), ValueError,
     "bias_prior", r"\(1,\)")
case("gc.CalibrationResult", lambda: replace(_GRES, bias_names=("scale",)), ValueError,
     "bias_groups", "one group per bias name")
case("gc.CalibrationResult.estimate", lambda: _GRES.estimate("drift"), ValueError, "name",
     "one of")
case("gc.CalibrationResult.sigma", lambda: _GRES.sigma(3), ValueError, "name", "one of")
case("gc.CalibrationResult.nis_band", lambda: _GRES.nis_band(1.0), ValueError,
     "confidence", r"\(0.0, 1.0\)")
case("gc.CalibrationResult.whiteness_limit", lambda: _GRES.whiteness_limit(NAN),
     ValueError, "confidence")
case("gc.CalibrationResult.fits", lambda: _GRES.fits(0.0), ValueError, "confidence")
case("gc.CalibrationResult.verdict", lambda: _GRES.verdict("high"), TypeError,
     "confidence")
case("gc.SimulatedRecord", lambda: gc.SimulatedRecord(record=None, truth=np.zeros((1, 10)),
                                                       params=gc.GyrocompassParams(), seed=0),
     TypeError, "record", "GCRecord")
case("gc.SimulatedRecord", lambda: gc.SimulatedRecord(record=_GREC, truth=np.zeros(10),
                                                       params=gc.GyrocompassParams(), seed=0),
     ValueError, "truth", "shape")
case("gc.simulate_record", lambda: gc.simulate_record(None, 1.0, 0), TypeError, "params")
case("gc.simulate_record", lambda: gc.simulate_record(gc.GyrocompassParams(), 1.0, -1),
     ValueError, "seed", ">= 0")
case("gc.simulate_record", lambda: gc.simulate_record(gc.GyrocompassParams(), 0.0, 1),
     ValueError, "t_end", POS)
case("gc.simulate_records", lambda: gc.simulate_records(None, 1.0, 0, 2), TypeError,
     "params")
case("gc.simulate_records", lambda: gc.simulate_records(gc.GyrocompassParams(), 1.0, -1, 2),
     ValueError, "seed", ">= 0")
case("gc.simulate_records", lambda: gc.simulate_records(gc.GyrocompassParams(), 1.0, 1, 0),
     ValueError, "n", ">= 1")
case("gc.simulate_records", lambda: gc.simulate_records(gc.GyrocompassParams(), 1.0, 1, 2.0),
     TypeError, "n")
case("gc.simulate_records", lambda: gc.simulate_records(gc.GyrocompassParams(), 0.0, 1, 2),
     ValueError, "t_end", POS)
case("gc.plot_calibration", lambda: gc.plot_calibration(None), TypeError, "result",
     "CalibrationResult")
case("gc.plot_calibration", lambda: gc.plot_calibration(_GRES, truth=NAN), ValueError,
     "truth", FINITE)
case("gc.plot_calibration", lambda: gc.plot_calibration(_GRES, label=3), TypeError,
     "label", "str or None")

# lost lock, noise fit, likelihood, nominal integrator
case("gc.calibrate", lambda: gc.calibrate(_GREC, max_rejected=1.5), ValueError,
     "max_rejected", r"\[0.0, 1.0\]")
case("gc.calibrate", lambda: gc.calibrate(_GREC, false_alarm=1.5), ValueError,
     "false_alarm", r"\(0.0, 1.0\)")
case("gc.calibrate", lambda: gc.calibrate(_GREC, nis_tolerance=-0.1), ValueError,
     "nis_tolerance", r"\[0.0, 1.0\)")
case("gc.calibrate", lambda: gc.calibrate(_GREC, false_alarm=0.0), ValueError,
     "false_alarm", r"\(0.0, 1.0\)")
case("gc.GyrocompassParams", lambda: gc.GyrocompassParams(sigma_as_offset=-1e-6),
     ValueError, "sigma_as_offset")
case("gc.GyrocompassParams", lambda: gc.GyrocompassParams(sigma_incl_bias=NAN),
     ValueError, "sigma_incl_bias")
case("gc.calibrate", lambda: gc.calibrate(_GREC, nis_range=2.0), TypeError, "nis_range",
     "pair")
case("gc.calibrate", lambda: gc.calibrate(_GREC, nis_range=(0.5, 0.9)), ValueError,
     "nis_range[1]", "> 1")
case("gc.calibrate", lambda: gc.calibrate([_GREC], executor=4), TypeError, "executor",
     "Executor")
case("gc.CalibrationResult", lambda: replace(_GRES, max_rejected=-0.1), ValueError,
     "max_rejected")
case("gc.innovation_log_likelihood", lambda: gc.innovation_log_likelihood([_GREC]),
     TypeError, "record", "GCRecord")
case("gc.innovation_log_likelihood", lambda: gc.innovation_log_likelihood(_GREC, 1.0),
     TypeError, "params", "GyrocompassParams")
case("gc.innovation_log_likelihood",
     lambda: gc.innovation_log_likelihood(_GREC, chunk_size=0), ValueError, "chunk_size",
     ">= 1")
case("gc.fit_noise", lambda: gc.fit_noise(np.zeros(3)), TypeError, "record", "GCRecord")
case("gc.fit_noise", lambda: gc.fit_noise(_GREC, "paper"), TypeError, "params",
     "GyrocompassParams")
case("gc.fit_noise", lambda: gc.fit_noise(_GREC, fit="alpha1"), TypeError, "fit", "tuple")
case("gc.fit_noise", lambda: gc.fit_noise(_GREC, fit=("alpha2",)), ValueError, "fit",
     "names from")
case("gc.fit_noise", lambda: gc.fit_noise(_GREC, fit=()), ValueError, "fit", "at least")
case("gc.fit_noise", lambda: gc.fit_noise(_GREC, fit=("C_as", "C_as")), ValueError, "fit",
     "repeat")
case("gc.fit_noise", lambda: gc.fit_noise(_GREC, fit=("C_in", "C_incl_y")), ValueError,
     "fit", "C_in")
case("gc.fit_noise", lambda: gc.fit_noise(_GREC, gate=1.0), ValueError, "gate", "in")
case("gc.fit_noise", lambda: gc.fit_noise(_GREC, max_evaluations=0), ValueError,
     "max_evaluations", ">= 1")
case("gc.fit_noise", lambda: gc.fit_noise(_GREC, progress="bar"), TypeError, "progress",
     "callable")


@functools.cache
def _nfit() -> gc.NoiseFit:
    return gc.NoiseFit(params=P, start=P, names=("C_as",), values=np.array([P.C_as]),
                       std_errors=np.array([1e-15]), cov_log=np.eye(1), loglik=0.0,
                       loglik_start=-1.0, converged=True, message="", n_evaluations=1,
                       outliers=0)


case("gc.NoiseFit", lambda: replace(_nfit(), names=("beta",)), ValueError, "fit",
     "names from")
case("gc.NoiseFit", lambda: replace(_nfit(), values=np.zeros(2)), ValueError, "values",
     "shape")
case("gc.NoiseFit", lambda: replace(_nfit(), std_errors=np.array([np.inf])), ValueError,
     "std_errors", "shape")
case("gc.NoiseFit", lambda: replace(_nfit(), params=None), TypeError, "params")
case("gc.NoiseFit.value", lambda: _nfit().value("alpha1"), ValueError, "name",
     "fitted names")
case("gc.NoiseFit.std_error", lambda: _nfit().std_error(3), ValueError, "name",
     "fitted names")
case("gc.NoiseFit.carried_std_error", lambda: _nfit().carried_std_error("alpha1"), ValueError,
     "name", "fitted")
case("gc.NoiseFit.std_error_source", lambda: _nfit().std_error_source(None), ValueError, "name",
     "fitted")
case("gc.NoiseFit", lambda: replace(_nfit(), level=1.5), ValueError, "level")
case("gc.NominalIntegrator", lambda: gc.NominalIntegrator(None), TypeError, "params",
     "GyrocompassParams")
case("gc.NominalIntegrator.advance", lambda: gc.NominalIntegrator(P).advance(-1),
     ValueError, "n", ">= 0")
case("gc.NominalIntegrator.advance", lambda: gc.NominalIntegrator(P).advance(1.5),
     TypeError, "n", "integer")
case("gc.NominalIntegrator.advance", lambda: gc.NominalIntegrator(P).advance(2, keep=1),
     TypeError, "keep", "bool")
case("gc.system_matrix_parts", lambda: gc.system_matrix_parts("paper"), TypeError,
     "params", "GyrocompassParams")


case("gc.GyrocompassParams.at_latitude",
     lambda: gc.GyrocompassParams.at_latitude(-math.pi / 2), ValueError, "latitude",
     r"\(-1.57")
case("gc.GyrocompassParams.at_latitude", lambda: gc.GyrocompassParams.at_latitude(45.0),
     ValueError, "latitude")
case("gc.GyrocompassParams.at_latitude",
     lambda: gc.GyrocompassParams.at_latitude(0.5, H=-1.0), ValueError, "H", POS)
case("gc.latitude_drift_shift", lambda: gc.latitude_drift_shift(P, -0.01), ValueError,
     "dlat", ">= 0")
case("gc.latitude_drift_shift", lambda: gc.latitude_drift_shift("paper", 0.01), TypeError,
     "params", "GyrocompassParams")
case("gc.latitude_drift_sigma", lambda: gc.latitude_drift_sigma(P, math.nan), ValueError,
     "latitude_sigma")
case("gc.equator_note", lambda: gc.equator_note(None), TypeError, "params",
     "GyrocompassParams")


# Eqs. (1)-(3), (5) as named functions (gc.model.equations)
case("gc.gyroscopic_torque", lambda: gc.gyroscopic_torque("paper", 0.0), TypeError, "params",
     "GyrocompassParams")
case("gc.vertical_rate", lambda: gc.vertical_rate(None, 0.0, 0.0), TypeError, "params",
     "GyrocompassParams")
case("gc.float_acceleration", lambda: gc.float_acceleration({}, 0.0, 0.0), TypeError,
     "params", "GyrocompassParams")
case("gc.linearized_acceleration", lambda: gc.linearized_acceleration(1.0, 0.0, 0.0, 0.0),
     TypeError, "params", "GyrocompassParams")


# the race against the rate-sensor method (gc.racing); the race computed once
@functools.cache
def _race():
    return gc.race()


_RPROC = gc.RateSensorProcedure()
_RMODEL = gc.rate_sensor_model()
case("gc.RateSensorProcedure", lambda: gc.RateSensorProcedure(T_rot=-1.0), ValueError,
     "T_rot", NONNEG)
case("gc.RateSensorProcedure", lambda: gc.RateSensorProcedure(T_settle=NAN), ValueError,
     "T_settle", FINITE)
case("gc.RateSensorProcedure", lambda: gc.RateSensorProcedure(rate_noise=0.0), ValueError,
     "rate_noise", POS)
case("gc.RateSensorProcedure", lambda: gc.RateSensorProcedure(loop_bandwidth=0.0), ValueError,
     "loop_bandwidth", "> 0")
case("gc.RateSensorProcedure", lambda: gc.RateSensorProcedure(quantization=-1.0), ValueError,
     "quantization", ">= 0")
case("gc.RateSensorProcedure.loop_gain", lambda: _RPROC.loop_gain(_RPROC), TypeError, "params",
     "GyrocompassParams")
case("gc.RateSensorProcedure", lambda: gc.RateSensorProcedure(split=1.0), ValueError,
     "split", r"\(0.0, 1.0\)")
case("gc.RateSensorProcedure", lambda: gc.RateSensorProcedure(vibration_frame="x"),
     ValueError, "vibration_frame", "one of")
case("gc.RateSensorProcedure", lambda: gc.RateSensorProcedure(sample_dt="0.1"), TypeError,
     "sample_dt")
case("gc.RateSensorModel.window_samples", lambda: _RMODEL.window_samples("t1", -1.0),
     ValueError, "t1", POS)
case("gc.RateSensorModel.window_samples", lambda: _RMODEL.window_samples("t2", 1e-9),
     ValueError, "t2", "at least one sample")
case("gc.RateSensorModel.classical_sigma_samples",
     lambda: _RMODEL.classical_sigma_samples(0, 10), ValueError, "n1", ">= 1")
case("gc.RateSensorModel.optimal_run_samples", lambda: _RMODEL.optimal_run_samples(10, 2.5),
     TypeError, "n2", "integer")
case("gc.RateSensorModel.optimal_time_to_samples",
     lambda: _RMODEL.optimal_time_to_samples(10, 20, -1e-8), ValueError, "level", "> 0")
case("gc.RateSensorModel.optimal_time_to_samples",
     lambda: _RMODEL.optimal_time_to_samples(10, 0, 1e-8), ValueError, "n2_max", ">= 1")
case("gc.RateSensorModel.optimal_time_to_samples",
     lambda: _RMODEL.optimal_time_to_samples(10, 20, 1e-8, give_up_after=-1.0), ValueError,
     "give_up_after", "> 0")
case("gc.RateSensorModel.optimal_time_to_samples",
     lambda: _RMODEL.optimal_time_to_samples(10, 20, 1e-8, give_up_after=float("nan")),
     ValueError,
     "give_up_after", "> 0")
case("gc.rate_sensor_model", lambda: gc.rate_sensor_model(procedure=P), TypeError,
     "procedure", "RateSensorProcedure")
case("gc.rate_sensor_model", lambda: gc.rate_sensor_model(_RPROC), TypeError, "params",
     "GyrocompassParams")
case("gc.RateSensorModel", lambda: replace(_RMODEL, F=np.zeros((2, 2))), ValueError, "F",
     "shape")
case("gc.RateSensorModel.classical_sigma", lambda: _RMODEL.classical_sigma(0.0, 1.0),
     ValueError, "t1", POS)
case("gc.RateSensorModel.classical_sigma", lambda: _RMODEL.classical_sigma(1.0, NAN),
     ValueError, "t2", FINITE)
case("gc.RateSensorModel.classical_curve", lambda: _RMODEL.classical_curve(1.0, 0.01),
     ValueError, "t2", "sample")
case("gc.RateSensorModel.optimal_run", lambda: _RMODEL.optimal_run(-1.0, 1.0), ValueError,
     "t1", POS)
case("gc.OptimalRun", lambda: gc.OptimalRun(np.zeros(3), np.zeros(2), ()), ValueError,
     "sigma", "shape")
case("gc.OptimalRun.time_to", lambda: _RMODEL.optimal_run(1.0, 1.0).time_to(NAN),
     ValueError, "level", FINITE)
case("gc.rate_sensor_monte_carlo", lambda: gc.rate_sensor_monte_carlo(t1=1.0, t2=1.0,
                                                                      n_runs=1),
     ValueError, "n_runs", ">= 2")
case("gc.rate_sensor_monte_carlo", lambda: gc.rate_sensor_monte_carlo(t1=1.0, t2=1.0,
                                                                      seed=-1),
     ValueError, "seed", ">= 0")
case("gc.rate_sensor_monte_carlo", lambda: gc.rate_sensor_monte_carlo(t1=0.0, t2=1.0),
     ValueError, "t1", POS)
case("gc.rate_sensor_monte_carlo", lambda: gc.rate_sensor_monte_carlo(
    t1=1.0, t2=1.0, truth_params=_RPROC), TypeError, "truth_params", "GyrocompassParams")
case("gc.RateSensorMonteCarlo", lambda: gc.RateSensorMonteCarlo(
    np.zeros(3), -1.0, (0.9, 1.1), 1.0, 1.0, 0), ValueError, "sigma", POS)
case("gc.turn_accuracy_limit", lambda: gc.turn_accuracy_limit(P, 0.0), ValueError, "level",
     POS)
case("gc.turn_accuracy_limit", lambda: gc.turn_accuracy_limit(_RPROC), TypeError, "params")
case("gc.race", lambda: gc.race("paper"), TypeError, "params", "GyrocompassParams")
case("gc.race", lambda: gc.race(P, {"T_rot": 1.0}), TypeError, "procedure")
case("gc.RaceResult", lambda: replace(_race(), t_gc=np.zeros(2)), ValueError, "sigma_gc",
     "shape")
case("gc.RaceResult.conditions", lambda: _race().conditions(100.0), ValueError, "percent",
     r"\(0.0, 100.0\)")
case("gc.RaceResult.kappa_max", lambda: _race().kappa_max(0.0), ValueError, "percent",
     r"\(0.0, 100.0\)")
case("gc.race_sweep", lambda: gc.race_sweep(cases=[{"T_turn": 1.0}]), ValueError, "cases",
     "fields")
case("gc.race_sweep", lambda: gc.race_sweep(cases={"T_rot": 1.0}), TypeError, "cases")
case("gc.race_sweep", lambda: gc.race_sweep(cases=[{"T_rot": -1.0}]), ValueError, "T_rot",
     NONNEG)
case("gc.RaceSweep", lambda: gc.RaceSweep(P, _RPROC, ({},), np.zeros(2), np.zeros(1),
                                          np.zeros(1)), ValueError, "t_c_gc", "one time")
case("gc.RaceSweep.faster_percent",
     lambda: gc.RaceSweep(P, _RPROC, ({},), np.ones(1), np.ones(1), np.ones(1))
     .faster_percent("best"), ValueError, "estimator", "one of")
case("gc.procedure_for_time", lambda: gc.procedure_for_time(P, None, "sigma_rot", 60.0),
     ValueError, "field", "one of")
case("gc.procedure_for_time", lambda: gc.procedure_for_time(P, None, "overhead", NAN),
     ValueError, "target", FINITE)
case("gc.procedure_for_time", lambda: gc.procedure_for_time(P, None, "overhead", 60.0,
                                                            rtol=0.0),
     ValueError, "rtol")
case("gc.plot_race", lambda: gc.plot_race(None), TypeError, "result", "RaceResult")
case("gc.plot_race", lambda: gc.plot_race(_race(), t_end=-1.0), ValueError, "t_end", POS)
case("gc.plot_race_sweep", lambda: gc.plot_race_sweep(None, "T_rot"), TypeError, "sweep",
     "RaceSweep")


# real logs: the inclinometer convention, its study, the Allan deviation
_MAP = gc.InclinometerMapping()
case("gc.InclinometerMapping", lambda: gc.InclinometerMapping(delta="x"), ValueError, "delta",
     "one of")
case("gc.InclinometerMapping", lambda: gc.InclinometerMapping(gamma="y"), ValueError,
     "delta and gamma", "different")
case("gc.InclinometerMapping", lambda: gc.InclinometerMapping(delta_sign=2.0), ValueError,
     "delta_sign", "1")
case("gc.InclinometerMapping.parse", lambda: gc.InclinometerMapping.parse("y,y"), ValueError,
     "mapping", "each of y and z once")
case("gc.InclinometerMapping.parse", lambda: gc.InclinometerMapping.parse(None), TypeError,
     "mapping")
case("gc.InclinometerMapping.apply", lambda: _MAP.apply(None), TypeError, "record",
     "GCRecord")
case("gc.InclinometerMapping.seen_tilts", lambda: _MAP.seen_tilts(NAN, 0.0), ValueError,
     "delta", FINITE)
case("gc.convention_study", lambda: gc.convention_study(seeds=[]), ValueError,
     "seeds", "at least one")
case("gc.convention_study", lambda: gc.convention_study(wiring="y,x"), ValueError, "mapping")
case("gc.convention_study", lambda: gc.convention_study(t_end=0.0), ValueError, "t_end", POS)
case("gc.convention_study", lambda: gc.convention_study(executor=4), TypeError, "executor",
     "Executor")
case("gc.plot_convention_study", lambda: gc.plot_convention_study(None), TypeError, "study",
     "ConventionStudy")
case("gc.allan_deviation", lambda: gc.allan_deviation(None), TypeError, "record", "GCRecord")
case("gc.allan_deviation", lambda: gc.allan_deviation(_GREC), ValueError, "record",
     "at least 10 rows")
case("gc.allan_deviation",
     lambda: gc.allan_deviation(gc.simulate_record(gc.GyrocompassParams(), 0.02, 1).record,
                                taus=[-1.0]), ValueError, "taus", "positive")
case("gc.allan_noise_terms", lambda: gc.allan_noise_terms(None), TypeError, "result",
     "AllanDeviation")
case("gc.allan_model_vibration", lambda: gc.allan_model_vibration(None, [1.0]), TypeError,
     "params")
case("gc.allan_model_vibration",
     lambda: gc.allan_model_vibration(gc.GyrocompassParams(), [[1.0]]), ValueError, "tau")
case("gc.plot_allan", lambda: gc.plot_allan(None), TypeError, "result", "AllanDeviation")
case("gc.AllanDeviation.get",
     lambda: gc.allan_deviation(gc.simulate_record(gc.GyrocompassParams(), 0.02, 1).record
                                ).get("gyro"), ValueError, "name", "one of")

@pytest.mark.parametrize(("call", "exc", "pattern"), TABLE.cases)
def test_bad_input_is_rejected_by_name(call, exc, pattern):
    run_case(call, exc, pattern)


#: Public callables without a bad-input case, and why.
# global sensitivity (gc.analysis.sensitivity_study)
case("gc.sensitivity", lambda: gc.sensitivity(6), ValueError, "n", "power of 2")
case("gc.sensitivity", lambda: gc.sensitivity(4, seed=-1), ValueError, "seed", ">= 0")
case("gc.sensitivity", lambda: gc.sensitivity(4, executor="dask"), TypeError, "executor")
case("gc.sensitivity", lambda: gc.sensitivity(4, params=1), TypeError, "params")
case("gc.sensitivity", lambda: gc.sensitivity(4, t_end=0.0), ValueError, "t_end", POS)
case("gc.sensitivity_inputs", lambda: gc.sensitivity_inputs(1), TypeError, "params")
case("gc.sensitivity_elasticities", lambda: gc.sensitivity_elasticities(1), TypeError, "params")
case("gc.sensitivity_elasticities", lambda: gc.sensitivity_elasticities(fixed="yes"), TypeError,
     "fixed")
case("gc.sensitivity_outputs", lambda: gc.sensitivity_outputs(P, level=-1.0), ValueError,
     "level", POS)
case("gc.sensitivity_outputs", lambda: gc.sensitivity_outputs(None), TypeError, "params")
case("gc.recheck_sensitivity", lambda: gc.recheck_sensitivity(1), TypeError, "result")
case("gc.recheck_sensitivity", lambda: gc.recheck_sensitivity(rsf.sensitivity(2)), ValueError,
     "result", "GC study")

EXEMPT: dict[str, str] = {
    "gc.symbolic.display_form": "returns non-sympy objects unchanged (documented)",
    **{f"gc.{name}": "result object built by its compute function, which validates"
       for name in ("ClaimBoundary", "ShapingSweep", "SpeedClaimMap", "ShapingSweep.nominal",
                    "LinearizationEffect", "LinearizationEffect.excess",
                    "LinearizationEffect.residual",
                    "AllanDeviation", "AllanSeries", "ConventionStudy")},
    **{f"gc.plot_{name}": "plot function: takes result objects, no validation by design"
       for name in ("estimates", "consistency", "sweep", "information", "speed_claim",
                    "mismatch", "linearization")},
    "gc.plot_sigma_history": "plot function: takes result objects, no validation by design",
    "gc.plot_p0_scale": "plot function: takes result objects, no validation by design",
    "gc.plot_error_budget": "plot function: takes result objects, no validation by design",
    "gc.plot_shaping_psd": "plot function: takes computed PSDs, no validation by design",
    "gc.plot_nominal_motion": "plot function: takes result objects, no validation by design",
    "gc.plot_figure1": "plot function: drawing options only, no validation by design",
    "gc.parameter_grid": "builds cases; sweep_covariance validates them at the door",
    "gc.RaceConditions": "result object built by RaceResult.conditions, which validates",
}


# the continuous model and the judgement of a record
_CM = gc.continuous_model(P)
_T = np.arange(1, 51) * P.dt
_REC = gc.GCRecord(t=_T, angle_sensor=np.zeros(50), inclinometer_y=np.zeros(50),
                   inclinometer_z=np.zeros(50))
case("gc.continuous_model", lambda: gc.continuous_model("x"), TypeError, "params",
     "GyrocompassParams")
case("gc.ContinuousModel", lambda: gc.ContinuousModel(**{
    **{f: getattr(_CM, f) for f in _CM.__dataclass_fields__}, "params": None}), TypeError,
    "params", "GyrocompassParams")
case("gc.ContinuousModel.system_matrix", lambda: _CM.system_matrix("a"), TypeError, "beta_n")
case("gc.ContinuousModel.system_matrix", lambda: _CM.system_matrix(float("nan")), ValueError,
     "beta_n", "finite")
case("gc.judge_record", lambda: gc.judge_record("x", P), TypeError, "record", "GCRecord")
case("gc.judge_record", lambda: gc.judge_record(_REC, "x"), TypeError, "params",
     "GyrocompassParams")
case("gc.judge_record", lambda: gc.judge_record(_REC, P, latitude_sigma=-1.0), ValueError,
     "latitude_sigma", ">= 0")
case("gc.judge_record", lambda: gc.judge_record(_REC, P, gate=2.0), ValueError, "gate",
     r"in \(0\.0, 1\.0\)")
# a Monte Carlo's summary (what a stored study keeps of its runs)
@functools.cache
def _mc():
    return gc.monte_carlo(P, 4, 2.0, seed=1)


case("gc.MonteCarloResult.summary", lambda: _mc().summary(states=("nope",)), ValueError,
     "name", "one of")
case("gc.MonteCarloResult.summary", lambda: _mc().summary(keep_runs=-1), ValueError,
     "keep_runs", ">= 0")
case("gc.MonteCarloResult.mean_nees", lambda: _mc().mean_nees(("nope",)), ValueError, "name",
     "one of")
case("gc.MonteCarloSummary.mean_nees", lambda: _mc().summary().mean_nees(("nope",)),
     ValueError, "names", "NEES sets")
case("gc.MonteCarloSummary.inside_share", lambda: _mc().summary().inside_share(confidence=2.0),
     ValueError, "confidence", r"in \(0\.0, 1\.0\)")
for _m in ("std", "rms_error", "estimate", "truth", "error_end", "truth_end"):
    case(f"gc.MonteCarloSummary.{_m}",
         lambda _m=_m: getattr(_mc().summary(), _m)("nope"), ValueError, "name", "one of")
EXEMPT["gc.MonteCarloSummary"] = "result object built by MonteCarloResult.summary, which " \
                                 "validates"

EXEMPT.update({
    "gc.ContinuousModel.build": "builder on parameters already checked at the public door "
                                "(continuous_model)",
    "gc.ContinuousModel.with_instruments": "builder on parameters already checked at the "
                                           "public door (continuous_model)",
    "gc.evidence_codes": "reads the fields of a calibration's result (a run made by "
                         "gc.calibrate, checked there); duck-typed on purpose: "
                         "tests/cli/test_hints.py feeds it made-up evidence",
    "gc.RaceResult.reference_text": "a sentence of a result object built by gc.race "
                                    "(checked there); takes no argument",
})


def test_table_covers_every_public_callable():
    TABLE.check_coverage({"gc": gc, "gc.symbolic": symbolic}, EXEMPT)


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


POSITIVE_FIELDS = ("I", "H", "f", "Omega_h", "g", "alpha1", "sigma1_sq", "alpha2",
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

# The fitted noise's own uncertainty
_FIT = gc.NoiseFit(params=gc.GyrocompassParams(), start=gc.GyrocompassParams(),
                   names=("C_as",), values=np.array([2e-13]), std_errors=np.array([1e-14]),
                   cov_log=np.array([[np.nan]]), loglik=0.0, loglik_start=0.0, converged=True,
                   message="", n_evaluations=1, outliers=0)
case("gc.fit_uncertainty", lambda: gc.fit_uncertainty(_GREC, "fit"), TypeError, "fit",
     "NoiseFit")
case("gc.fit_uncertainty", lambda: gc.fit_uncertainty(_GREC, _FIT), ValueError, "fit",
     "not identified")
case("gc.CalibrationResult.split_tests",
     lambda: gc.calibrate(_GREC).split_tests((0.5, 1.5)), ValueError, "fractions", "(0, 1)")
case("gc.fit_uncertainty", lambda: gc.fit_uncertainty(_GREC, _FIT, samples=1), ValueError,
     "samples")
case("gc.NoiseFit.not_identified", lambda: _FIT.not_identified(-1.0), ValueError, "duration")
case("gc.NoiseFit.nuisance", lambda: _FIT.nuisance(-1.0), ValueError, "duration")
case("gc.NoiseFit.interval", lambda: _FIT.interval("xi1"), ValueError, "name",
     "fitted names")
case("gc.fit_checks", lambda: gc.fit_checks("fit"), TypeError, "fit", "NoiseFit")
case("gc.fit_checks", lambda: gc.fit_checks(_FIT, clock_tolerance=-1.0), ValueError,
     "clock_tolerance")
case("gc.fit_checks", lambda: gc.fit_checks(_FIT, false_alarm=1.5), ValueError, "false_alarm")
case("gc.profile_intervals", lambda: gc.profile_intervals("rec", _FIT), TypeError, "record")
case("gc.profile_intervals", lambda: gc.profile_intervals(_GREC, _FIT, level=1.5), ValueError,
     "level")
# the outliers a fit left out, and the record they must belong to
case("gc.NoiseFit", lambda: replace(_nfit(), outliers=1, outlier_cells=np.zeros((2, 2), int)),
     ValueError, "outlier_cells", r"\(1, 2\)")
case("gc.NoiseFit", lambda: replace(_nfit(), outliers=1, outlier_cells=np.array([[0, 3]])),
     ValueError, "outlier_cells", "sensors 0")
case("gc.NoiseFit", lambda: replace(_nfit(), interval_closed=np.ones((1, 2))), ValueError,
     "interval_closed", "bool")
case("gc.profile_intervals", lambda: gc.profile_intervals(_GREC, replace(_FIT, outliers=2)),
     ValueError, "fit.outlier_cells", "fit_noise")
case("gc.profile_intervals", lambda: gc.profile_intervals(_GREC, replace(
    _FIT, outliers=1, outlier_cells=np.array([[5, 0]]))), ValueError, "fit.outlier_cells",
    "2 rows: not the record fitted")
case("gc.earth_rate_mismatch", lambda: gc.earth_rate_mismatch("paper", 0.5), TypeError,
     "params", "GyrocompassParams")
case("gc.earth_rate_mismatch", lambda: gc.earth_rate_mismatch(gc.GyrocompassParams(), 2.0),
     ValueError, "latitude")

# the race's margin and its verdict grid
case("gc.race_margin", lambda: gc.race_margin(P, percent=100.0), ValueError, "percent")
case("gc.race_margin", lambda: gc.race_margin("paper"), TypeError, "params")
case("gc.race_verdict_grid", lambda: gc.race_verdict_grid(sigma1_factors=(0.0,)), ValueError,
     "sigma1_factors", "positive")
case("gc.race_verdict_grid", lambda: gc.race_verdict_grid(readings=("C/dt",)), ValueError,
     "readings", "intensity_over_dt")
_GRID = dict(readings=("variance",), cas_factors=np.ones(1), sigma1_factors=np.ones(2),
             margin=np.zeros((1, 1, 2)), times=np.ones((1, 3)), C_as=1e-13, sigma1_sq=1e-6)
case("gc.RaceVerdictGrid", lambda: gc.RaceVerdictGrid(**{**_GRID, "margin": np.zeros(3)}),
     ValueError, "margin")
case("gc.RaceVerdictGrid", lambda: gc.RaceVerdictGrid(**{**_GRID, "cas_factors": -np.ones(1)}),
     ValueError, "cas_factors", "positive")
case("gc.RaceVerdictGrid.from_dict", lambda: gc.RaceVerdictGrid.from_dict({"readings": []}),
     ValueError, "d", "keys")
case("gc.plot_race_verdict", lambda: gc.plot_race_verdict("grid"), TypeError, "grid")
