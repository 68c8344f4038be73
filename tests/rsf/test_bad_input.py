"""Bad input to paper RSF (:mod:`gyrolib.rsf`) is rejected by name.

The reference is the contract of CONTRIBUTING.md: bad input raises ``ValueError`` or
``TypeError`` whose message starts with the name of the offending parameter (and, where the
range is a number, states it), never an error from deep inside, a silent NaN or a wrong figure.
The table's coverage is computed from the subpackage's ``__all__`` and its classes' public
methods; hypothesis properties cover continuous ranges.
"""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from tests.support.validation_table import *

TABLE = Table()
case = TABLE.case

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
case("rsf.delta_k", lambda: rsf.delta_k(0.1, 0.0, 0.0, 1.0), ValueError, "omega_x",
     "nonzero")
case("rsf.delta_k", lambda: rsf.delta_k(0.1, 0.0, 1.0, -1.0), ValueError, "dt", POS)
case("rsf.delta_k_ideal", lambda: rsf.delta_k_ideal(0.1, -1.0, 1.0, 1.0), ValueError,
     "dgamma_enc", NONNEG)
case("rsf.lateral_deviation_exact", lambda: rsf.lateral_deviation_exact(0.1, INF,
                                                                                   1.0),
     ValueError, "omega", FINITE)
case("rsf.table2", lambda: rsf.table2(None), TypeError, "gyro", "RollGyroSpec")
case("rsf.table2", lambda: rsf.table2(times=[]), ValueError, "times")
case("rsf.table2", lambda: rsf.table2(omega_true=NAN), ValueError, "omega_true")
case("rsf.table3", lambda: rsf.table3(encoder=None), TypeError, "encoder")
case("rsf.table3", lambda: rsf.table3(eps0_gs=-1.0), ValueError, "eps0_gs", NONNEG)
case("rsf.table3", lambda: rsf.table3(times=[-1.0]), ValueError, "times")
case("rsf.Table2", lambda: rsf.Table2("a", T5, T5, T5, T5), TypeError, "t")
case("rsf.Table2", lambda: rsf.Table2(T5, T5, T5[:2], T5, T5), ValueError, "dr_z_cubic")
case("rsf.Table2", lambda: rsf.Table2(T5, T5, T5, T5, T5[:2]), ValueError, "dr_y_exact")
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

# calibration on a record: rsf.calibrate, RSFRecord, CalibrationResult
_RREC = rsf.RSFRecord(t=[0.0, 0.5, 1.0], sins_increment=[0.0, 1.0, 1.0],
                      gs_angle=[0.0, 1.0, 2.0])
_RRES = rsf.calibrate(_RREC, 0.5)
case("rsf.RSFRecord", lambda: rsf.RSFRecord(t=[0.0, 1.0], sins_increment=[0.0, 1.0]),
     ValueError, "exactly one of gs_angle and encoder_counts")
case("rsf.RSFRecord", lambda: rsf.RSFRecord(t=[0.0, 1.0], sins_increment=[0.0, 1.0],
                                             encoder_counts=[0.0, 9.0], counts_per_rev=4),
     ValueError, "encoder_counts", "whole counts")
case("rsf.RSFRecord", lambda: rsf.RSFRecord(t=[0.0, 1.0], sins_increment=[0.0, 1.0],
                                             encoder_counts=[0.0, 1.0], counts_per_rev=1),
     ValueError, "counts_per_rev", ">= 2")
case("rsf.RSFRecord", lambda: replace(_RREC, t=[0.0, 0.0, 1.0]), ValueError, "t",
     "strictly increasing")
case("rsf.eps1_uncertainty", lambda: rsf.eps1_uncertainty("result"), TypeError, "result")
case("rsf.eps1_uncertainty", lambda: rsf.eps1_uncertainty(_RRES, sins_bias=-1.0), ValueError,
     "sins_bias")
case("rsf.eps1_uncertainty", lambda: rsf.eps1_uncertainty(_RRES, false_alarm=1.5), ValueError,
     "false_alarm")
case("rsf.eps1_uncertainty", lambda: rsf.eps1_uncertainty(_RRES, counts_per_rev=1), ValueError,
     "counts_per_rev")
case("rsf.calibrate", lambda: rsf.calibrate(_RREC, 0.0), ValueError, "period", POS)
case("rsf.calibrate", lambda: rsf.calibrate({"t": [0.0]}, 1.0), TypeError, "record",
     "RSFRecord")
case("rsf.calibrate", lambda: rsf.calibrate(_RREC, 0.5, k_form="square"), ValueError,
     "k_form", "one of")
case("rsf.calibrate", lambda: rsf.calibrate(_RREC, 0.5, dt=-1.0), ValueError, "dt", POS)
case("rsf.calibrate", lambda: rsf.calibrate(_RREC, 0.5, time_tolerance=0.0), ValueError,
     "time_tolerance")
case("rsf.calibrate", lambda: rsf.calibrate(_RREC, 0.5, slips="ignore"), ValueError,
     "slips", "one of")
case("rsf.CalibrationResult", lambda: replace(_RRES, reversal=np.zeros(3, bool)), ValueError,
     "reversal", "shape")
case("rsf.CalibrationResult", lambda: replace(_RRES, slips_repaired=-1), ValueError,
     "slips_repaired", ">= 0")
case("rsf.CalibrationResult", lambda: replace(_RRES, k=np.zeros(7)), ValueError, "k",
     "shape")
case("rsf.CalibrationResult", lambda: replace(_RRES, period=0.0), ValueError, "period", POS)
case("rsf.CalibrationResult", lambda: replace(_RRES, gaps=-1), ValueError, "gaps", ">= 0")
case("rsf.CalibrationResult.delta_k", lambda: _RRES.delta_k(1.5), ValueError, "eps1",
     r"\(-1.0, 1.0\)")
case("rsf.CalibrationResult.delta_k_std", lambda: _RRES.delta_k_std(0.1), TypeError,
     "prediction", "DeltaKPrediction")
case("rsf.predict_delta_k", lambda: rsf.predict_delta_k(cfg(), 0.5, rate=-_RRES.mean_rate),
     ValueError, "rate", POS)
case("rsf.predict_delta_k", lambda: rsf.predict_delta_k(
    replace(cfg(), roll=rsf.RollProfile(10.0, 20.0)), 0.5), ValueError, "config", "constant")
case("rsf.record_from_simulation", lambda: rsf.record_from_simulation(None), TypeError,
     "sim", "SensorRecord")
case("rsf.plot_correction", lambda: rsf.plot_correction(None), TypeError, "result",
     "CalibrationResult")
case("rsf.plot_correction", lambda: rsf.plot_correction(_RRES, prediction=3), TypeError,
     "prediction", "DeltaKPrediction")


@pytest.mark.parametrize(("call", "exc", "pattern"), TABLE.cases)
def test_bad_input_is_rejected_by_name(call, exc, pattern):
    """Each bad-input case raises the stated error, its message starting with the parameter's name
    and stating the range."""
    run_case(call, exc, pattern)


#: Public callables without a bad-input case, and why.
# the claims and their conditions
case("rsf.vertical_deviation_exact", lambda: rsf.vertical_deviation_exact(1.0, 1.0, 1.0),
     ValueError, "eps1", r"\(-1.0, 1.0\)")
case("rsf.vertical_deviation_exact", lambda: rsf.vertical_deviation_exact(0.1, 1.0, -1.0),
     ValueError, "t", NONNEG)
case("rsf.compensation_share", lambda: rsf.compensation_share([0.0, 1.0]), ValueError,
     "rates", "> 0")
case("rsf.compensation_share", lambda: rsf.compensation_share([1.0], target=1.0), ValueError,
     "target")
case("rsf.compensation_share", lambda: rsf.compensation_share([1.0], period=0.0), ValueError,
     "period", POS)
case("rsf.compensation_share", lambda: rsf.compensation_share([1.0], gs_gyro=None), TypeError,
     "gs_gyro", "MemsGyroSpec")
case("rsf.compensation_share", lambda: rsf.compensation_share([1.0], simulated=1), TypeError,
     "simulated", "RateSweep")
case("rsf.compensation_share",
     lambda: rsf.compensation_share([1.0], roll_gyro=rsf.RollGyroSpec(sf_error=0.0)),
     ValueError, "roll_gyro.sf_error", "> 0")
case("rsf.flight_shares", lambda: rsf.flight_shares(-1), ValueError, "seed")
case("rsf.flight_shares", lambda: rsf.flight_shares(1, period=0.0), ValueError, "period", POS)
case("rsf.flight_shares", lambda: rsf.flight_shares(1, n_runs=0), ValueError, "n_runs")
case("rsf.flight_shares", lambda: rsf.flight_shares(1, config="x"), TypeError, "config",
     "SimulationConfig")
_FLIGHTS = rsf.FlightShares(share=np.array([0.1, 0.5, 0.9]), rms=np.ones(3), period=5.0,
                            rate=1.0, seed=0)
case("rsf.FlightShares.percentile_estimate", lambda: _FLIGHTS.percentile_estimate(120.0),
     ValueError, "q")
_ONE = np.ones(1)
_RATES = rsf.RateSweep(rates=_ONE, mean=_ONE, rms=_ONE, max_abs=_ONE, predicted_rms=_ONE,
                       eq7=_ONE, share=_ONE, omega_unc=0.0, period=5.0,
                       rms_ci=np.ones((1, 2)), eps1=1e-3)
case("rsf.RateSweep.share_estimate", lambda: _RATES.share_estimate(1), ValueError, "i",
     "index")
case("rsf.CompensationShare.share_at",
     lambda: rsf.compensation_share([1.0]).share_at(0.0), ValueError, "rate", POS)
case("rsf.gs_vs_sins", lambda: rsf.gs_vs_sins([-1.0]), ValueError, "times")
case("rsf.gs_vs_sins", lambda: rsf.gs_vs_sins(omega=0.0), ValueError, "omega", POS)
case("rsf.gs_vs_sins", lambda: rsf.gs_vs_sins(encoder=ENC), TypeError, "encoder",
     "EncoderSpec")
case("rsf.drz_slip_search", lambda: rsf.drz_slip_search([1.0, 2.0]), ValueError, "times")
case("rsf.drz_slip_search", lambda: rsf.drz_slip_search([1.0, 2.0, 3.0], max_factors=-1),
     ValueError, "max_factors")
case("rsf.drz_slip_search", lambda: rsf.drz_slip_search([1.0, 2.0, 3.0], [0.0, 1.0, 2.0]),
     ValueError, "times", "> 0")
case("rsf.sweep_roll_rate", lambda: rsf.sweep_roll_rate([1.0], 0), ValueError, "rates",
     "omega_unc")
case("rsf.sweep_roll_rate", lambda: rsf.sweep_roll_rate([10.0], -1), ValueError, "seed")
case("rsf.sweep_roll_rate", lambda: rsf.sweep_roll_rate([10.0], 0, base=1), TypeError,
     "base", "SimulationConfig")
case("rsf.sweep_roll_rate", lambda: rsf.sweep_roll_rate([10.0], 0, period=0.0), ValueError,
     "period", POS)

case("rsf.SinsGyroModel.from_spec",
     lambda: rsf.SinsGyroModel.from_spec(rsf.SIIMU02_ROLL, arw=-1.0), ValueError, "arw", NONNEG)
case("rsf.SinsGyroModel.from_spec", lambda: rsf.SinsGyroModel.from_spec(rsf.GYPRO4300),
     TypeError, "spec", "RollGyroSpec")
case("rsf.GsModel.from_spec", lambda: rsf.GsModel.from_spec(rsf.GYPRO4300, ki=0.0), ValueError,
     "ki", POS)
case("rsf.GsModel.from_spec", lambda: rsf.GsModel.from_spec(rsf.AEDB9340), TypeError, "spec",
     "MemsGyroSpec")
case("rsf.EncoderModel.from_spec", lambda: rsf.EncoderModel.from_spec(rsf.GYPRO4300), TypeError,
     "spec", "EncoderSpec")
case("rsf.worked_example_terms", lambda: rsf.worked_example_terms(dt=0.0), ValueError, "dt",
     POS)
case("rsf.worked_example_terms", lambda: rsf.worked_example_terms(eps1_gs=-1.0), ValueError,
     "eps1_gs", NONNEG)
case("rsf.worked_example_terms", lambda: rsf.worked_example_terms(encoder=ENC), TypeError,
     "encoder", "EncoderSpec")
case("rsf.drz_hypotheses", lambda: rsf.drz_hypotheses(0.0), ValueError, "t", POS)
case("rsf.drz_hypotheses", lambda: rsf.drz_hypotheses(roll_gyro=1), TypeError, "roll_gyro")
case("rsf.encoder_counts", lambda: rsf.encoder_counts(np.zeros(3), ENC, wrap=1), TypeError,
     "wrap")

# global sensitivity (rsf.sobol) and the sweeps' executor
case("rsf.sensitivity", lambda: rsf.sensitivity(3), ValueError, "n", "power of 2")
case("rsf.sensitivity", lambda: rsf.sensitivity(4, chunk_size=0), ValueError, "chunk_size")
case("rsf.sensitivity", lambda: rsf.sensitivity(4, roll_gyro=1), TypeError, "roll_gyro")
case("rsf.sensitivity_elasticities", lambda: rsf.sensitivity_elasticities(roll_gyro=1),
     TypeError, "roll_gyro")
case("rsf.sensitivity_elasticities", lambda: rsf.sensitivity_elasticities(encoder=1),
     TypeError, "encoder")
case("rsf.sensitivity_elasticities", lambda: rsf.sensitivity_elasticities(period=0.0),
     ValueError, "period", POS)
case("rsf.sensitivity", lambda: rsf.sensitivity(4, period=0.0), ValueError, "period", POS)
case("rsf.sensitivity_inputs", lambda: rsf.sensitivity_inputs(encoder=ENC), TypeError,
     "encoder", "EncoderSpec")
case("rsf.sensitivity_outputs", lambda: rsf.sensitivity_outputs(-1.0, 0.0, 1.0, 1.0, 0.0),
     ValueError, "eps0_gs", NONNEG)
case("rsf.sensitivity_outputs", lambda: rsf.sensitivity_outputs(0.0, 0.0, 1.0, 1.0, 0.0,
                                                                eps1=0.0),
     ValueError, "eps1", POS)
case("rsf.recheck_sensitivity", lambda: rsf.recheck_sensitivity(None), TypeError, "result")
case("rsf.sweep_correction_period", lambda: rsf.sweep_correction_period(rec(), [1.0],
                                                                        executor=1),
     TypeError, "executor")
case("rsf.sweep_encoder", lambda: rsf.sweep_encoder(rec(), [ENC], 1.0, executor="x"),
     TypeError, "executor")
case("rsf.sweep_roll_rate", lambda: rsf.sweep_roll_rate([10.0], 0, executor=1), TypeError,
     "executor")

EXEMPT: dict[str, str] = {
    "rsf.Eps1Uncertainty": "result object made by rsf.eps1_uncertainty, whose inputs are "
                           "checked at its door",
    "rsf.plot_figure3": "plot function: takes result objects, no validation by design",
    "rsf.plot_flight": "plot function: takes result objects, no validation by design",
    "rsf.plot_delta_k_distribution": "plot function: takes result objects, no validation by design",
    "rsf.plot_period_sweep": "plot function: takes result objects, no validation by design",
    "rsf.plot_encoder_sweep": "plot function: takes result objects, no validation by design",
    "rsf.plot_rate_sweep": "plot function: takes result objects, no validation by design",
    "rsf.plot_spin_up": "plot function: takes result objects, no validation by design",
    "rsf.gyro_output": "one-line formula: inputs checked at the doors (records, configs, entry points)",
    "rsf.roll_difference": "one-line formula: inputs checked at the doors (records, configs, entry points)",
    "rsf.corrected_rate": "one-line formula: inputs checked at the doors (records, configs, entry points)",
    "rsf.k_true": "one-line formula: inputs checked at the doors (records, configs, entry points)",
    "rsf.relative_k_error": "one-line formula: inputs checked at the doors (records, configs, entry points)",
    "rsf.residual_sf_error": "one-line formula: inputs checked at the doors (records, configs, entry points)",
    "rsf.fraction_compensated": "one-line formula: inputs checked at the doors (records, configs, entry points)",
    "rsf.sins_roll_error": "one-line formula: inputs checked at the doors (records, configs, entry points)",
    "rsf.gs_bias_total": "one-line formula: inputs checked at the doors (records, configs, entry points)",
    "rsf.gs_roll_error_ideal": "one-line formula: inputs checked at the doors (records, configs, entry points)",
    "rsf.gs_roll_error_nonideal": "one-line formula: inputs checked at the doors (records, configs, entry points)",
    "rsf.difference_error": "one-line formula: inputs checked at the doors (records, configs, entry points)",
    "rsf.lateral_acceleration_error": "one-line formula: inputs checked at the doors (records, configs, entry points)",
    "rsf.lateral_deviation_cubic": "one-line formula: inputs checked at the doors (records, configs, entry points)",
    "rsf.DeltaKTerms": "result object, built by worked_example_terms (checked there)",
    "rsf.CompensationShare": "result object, built by compensation_share (checked there)",
    "rsf.GsVsSins": "result object, built by gs_vs_sins (checked there)",
    "rsf.FlightShares": "result object, built by flight_shares (checked there)",
    "rsf.RateSweep": "result object, built by sweep_roll_rate (checked there)",
    "rsf.SlipSearch": "result object, built by drz_slip_search (checked there)",
    "rsf.plot_compensation_share": "plot function: takes a result object, no validation by "
                                   "design",
}


case("rsf.judge_record", lambda: rsf.judge_record("x", 1.0), TypeError, "record", "RSFRecord")


def test_table_covers_every_public_callable():
    """Every public callable of gyrolib.rsf has a bad-input case or a stated reason for none."""
    TABLE.check_coverage({"rsf": rsf}, EXEMPT)


@SETTINGS
@given(eps1=st.one_of(st.floats(min_value=1.0), st.floats(max_value=-1.0),
                      st.sampled_from([NAN])))
def test_any_scale_factor_error_outside_minus_one_one_is_rejected(eps1):
    """Any scale-factor error outside (−1, 1) or NaN is rejected by name at the entry points."""
    for call in (lambda: rsf.correction_coefficient(eps1),
                 lambda: rsf.lateral_deviation_exact(eps1, 1.0, 1.0)):
        with pytest.raises(ValueError, match=r"^eps1(_hat)? must be "):
            call()


@SETTINGS
@given(a=st.integers(2, 6), b=st.integers(2, 6))
def test_arrays_of_incompatible_lengths_are_rejected_by_name(a, b):
    """Arrays that do not broadcast are rejected with both parameter names."""
    if a == b:
        b += 1
    with pytest.raises(ValueError, match=r"^dgamma, omega_x must have broadcast"):
        rsf.sf_error_estimate(np.zeros(a), np.ones(b), 1.0)


@SETTINGS
@given(duration=st.floats(0.02, 10.0), sample_rate=st.sampled_from([100.0, 200.0]))
def test_durations_off_the_sample_grid_are_rejected(duration, sample_rate):
    """A duration that is not a whole number of samples is rejected."""
    n = duration * sample_rate
    if abs(n - round(n)) < 1e-6:
        return  # on the grid: valid
    with pytest.raises(ValueError, match=r"^duration \* sample_rate must be an integer"):
        rsf.SimulationConfig(duration=duration, sample_rate=sample_rate)


# the worked example's operating point and readings
case("rsf.WorkedExample", lambda: rsf.WorkedExample(omega_x=-1.0), ValueError, "omega_x", POS)
case("rsf.WorkedExample", lambda: rsf.WorkedExample(eps1_gs_unit="%"), ValueError,
     "eps1_gs_unit", "one of")
case("rsf.WorkedExample.omega_unc_at", lambda: rsf.WorkedExample().omega_unc_at(NAN),
     ValueError, "omega")
case("rsf.WorkedExample.eps0_gs", lambda: rsf.WorkedExample().eps0_gs("GYPRO"), TypeError,
     "gyro", "MemsGyroSpec")
case("rsf.WorkedExample.eps1_gs", lambda: rsf.WorkedExample().eps1_gs(None), TypeError,
     "gyro", "MemsGyroSpec")


# Valid input is untouched ------------------------------------------------------------------------
