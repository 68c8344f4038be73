"""Time-domain simulation of the RSF correction loop (gyrolib.rsf.simulation): encoder
unwrapping, the simulated δK against Eq. (7), the error histories against Eqs. (4) and (8),
and the sweeps against their predictions."""

import dataclasses
import math

import numpy as np
import pytest

from gyrolib import rsf
from gyrolib.units import DEG

QUIET_SINS = rsf.SinsGyroModel(eps0=0.0, arw=0.0)
QUIET_GS = rsf.GsModel(arw=0.0)


# Encoder wrap and unwrap -------------------------------------------------------------------------
def test_unwrapping_over_600_revolutions_accumulates_no_error():
    """Unwrapping a count that restarts every revolution equals the never-wrapped count over 600
    revolutions, within the position error and one count."""
    enc = rsf.EncoderModel()                        # 4000 counts, 0.33° position error
    fs, rate, duration = 200.0, 3600.0 * DEG, 60.0  # 10 rev/s for 60 s
    t = np.arange(round(duration * fs) + 1) / fs
    theta = 0.3 + rate * t
    assert theta[-1] / (2 * math.pi) > 600
    wrapped = rsf.encoder_counts(theta, enc, phase=1.0)
    assert wrapped.min() >= 0 and wrapped.max() < enc.counts_per_rev
    unwrapped = rsf.unwrap_counts(wrapped, enc.counts_per_rev)
    # The exact (never wrapped) count, in integers: identical at every sample.
    indicated = theta + enc.position_error * np.sin(theta + 1.0)
    exact = np.floor(indicated / enc.resolution).astype(np.int64)
    np.testing.assert_array_equal(unwrapped - unwrapped[0], exact - exact[0])
    # So the angle error after 600 revolutions is bounded by the position error and one count.
    err = (unwrapped - unwrapped[0]) * enc.resolution - (theta - theta[0])
    assert np.abs(err).max() <= 2 * enc.position_error + enc.resolution


def test_unwrapping_inside_the_simulation_of_an_ideal_gs_at_3600_deg_s():
    """Inside the simulation at 3600 °/s, the GS angle error stays within the encoder bound of the
    bias drift of Eq. (9)."""
    cfg = rsf.SimulationConfig(roll=rsf.RollProfile(3600.0 * DEG),
                               gs=rsf.GsModel(motor_rate_max=math.inf), duration=60.0)
    rec = rsf.simulate_flight(cfg, seed=3)
    revolutions = (rec.theta_rel[0, -1] - rec.theta_rel[0, 0]) / (2 * math.pi)
    assert revolutions > 590
    gs_err = rsf.gs_angle(rec)[0] - rec.gamma_true
    # Eq. (9): bias drift plus the encoder error, no whole-revolution slips.
    drift = rec.eps0_gs[0] * rec.t
    bound = 2 * cfg.encoder.position_error + cfg.encoder.resolution + 6 * cfg.gs.arw * 8
    assert np.abs(gs_err - drift).max() < bound


# δK: simulation against Eq. (7) -----------------------------------------------------------------
def test_noise_free_simulated_delta_k_equals_eq7():
    """Without noise, encoder error or SINS bias, every interval's δK is Eq. (7) exactly
    (its Δγ_enc term set to 0), up to the ω_x-vs-ω factor 1 + ε1 and the fine quantization."""
    cfg = rsf.SimulationConfig(sins=QUIET_SINS, gs=QUIET_GS,
                               encoder=rsf.EncoderModel(counts_per_rev=2**22, position_error=0),
                               duration=30.0)
    rec = rsf.simulate_flight(cfg, seed=0)
    run = rsf.run_correction(rec, 5.0)
    w = cfg.roll.rate_start
    eq7 = rsf.delta_k(cfg.gs.eps0, 0.0, rsf.gyro_output(w, cfg.sins.eps1), 5.0, cfg.gs.eps1,
                     w - cfg.gs.motor_rate_max)
    np.testing.assert_allclose(run.delta_k, eq7, rtol=2e-3)


def test_seeded_delta_k_agrees_with_eq7_within_its_statistical_tolerance():
    """400 seeded runs, δK of the first interval.  Mean: the systematic part of Eq. (7)
    (minus the SINS bias term) within 4 standard errors.  Spread: the encoder term, whose
    standard deviation for the phase advance of this interval is predicted; within 15 %
    (4 standard errors of a standard deviation from 400 samples)."""
    cfg = rsf.SimulationConfig(duration=10.0, n_runs=400)
    rec = rsf.simulate_flight(cfg, seed=20240501)
    dk = rsf.run_correction(rec, 5.0).delta_k[:, 0]
    pred = rsf.predict_delta_k(cfg, 5.0)
    assert abs(dk.mean() - pred.mean) < 4 * pred.std / math.sqrt(dk.size)
    assert dk.std() == pytest.approx(pred.std, rel=0.15)
    # Eq. (7) is the systematic part plus Δγ_enc/(ω_x Δt), with Δγ_enc the rms increment error
    # over a random phase advance: the sum bounds the mean and covers mean + 1σ of the run.
    w = cfg.roll.rate_start
    systematic = (cfg.gs.eps0 + cfg.gs.eps1 * pred.omega_unc) / w
    assert pred.eq7 == pytest.approx(systematic + cfg.encoder.position_error / (w * 5.0),
                                     rel=1e-12)
    assert abs(dk.mean()) < pred.eq7
    # The encoder term is a sinusoid of random phase, δK = mean + A cos ψ with A = √2 σ_enc:
    # the share of intervals inside Eq. (7) is then (1/π)[arccos(lo) − arccos(hi)], within
    # 4 binomial standard errors.
    amp = math.sqrt(2) * pred.std_encoder
    hi = min((pred.eq7 - pred.mean) / amp, 1.0)
    lo = max((-pred.eq7 - pred.mean) / amp, -1.0)
    p_inside = (math.acos(lo) - math.acos(hi)) / math.pi
    inside = np.mean(np.abs(dk) <= pred.eq7)
    assert abs(inside - p_inside) < 4 * math.sqrt(p_inside * (1 - p_inside) / dk.size)


def test_sweep_over_period_matches_prediction_and_saturates_at_a_floor():
    """rms δK against the period matches the error model within 15 % and falls to the GS gyro's
    floor; Eq. (7) stays above it."""
    cfg = rsf.SimulationConfig(duration=60.0, n_runs=100)
    rec = rsf.simulate_flight(cfg, seed=11)
    sw = rsf.sweep_correction_period(rec, [1.0, 2.0, 5.0, 10.0, 20.0])
    np.testing.assert_allclose(sw.rms, sw.predicted_rms, rtol=0.15)
    # Longer intervals help (paper), but only down to the systematic floor of the GS gyro.
    assert np.all(np.diff(sw.eq7) < 0)
    floor = (cfg.gs.eps0 + cfg.gs.eps1 * (cfg.roll.rate_start - cfg.gs.motor_rate_max)) \
        / cfg.roll.rate_start
    assert np.all(sw.eq7 > floor)
    assert sw.rms[0] > 3 * sw.rms[-1]


def test_finer_encoder_helps_only_while_quantization_dominates():
    """Finer encoders lower δK only until the position error dominates; both curves match the
    error model within 15 %."""
    cfg = rsf.SimulationConfig(duration=20.0, n_runs=100)
    rec = rsf.simulate_flight(cfg, seed=5)
    counts = [64, 256, 1024, 4096, 16384]
    a = cfg.encoder.position_error
    with_error = rsf.sweep_encoder(rec, [rsf.EncoderModel(c, a) for c in counts], 5.0)
    no_error = rsf.sweep_encoder(rec, [rsf.EncoderModel(c, 0.0) for c in counts], 5.0)
    np.testing.assert_allclose(no_error.rms, no_error.predicted_rms, rtol=0.15)
    np.testing.assert_allclose(with_error.rms, with_error.predicted_rms, rtol=0.15)
    assert no_error.rms[0] > 5 * no_error.rms[-1]
    # With the 0.33° position error, finer than ~1000 counts changes nothing.
    assert with_error.rms[2] / with_error.rms[-1] < 1.1


# Error histories ----------------------------------------------------------------------------------
def test_uncorrected_errors_follow_eq4_and_the_exact_eq8():
    """The simulated uncorrected roll error follows Eq. (4) and its lateral error the exact double
    integral of Eq. (8)."""
    cfg = rsf.SimulationConfig(roll=rsf.RollProfile(3600.0 * DEG), sins=QUIET_SINS,
                               duration=60.0, sample_rate=200.0)
    rec = rsf.simulate_flight(cfg, seed=1)
    run = rsf.run_correction(rec, 5.0)
    w = cfg.roll.rate_start
    np.testing.assert_allclose(run.roll_error_raw[0],
                               rsf.sins_roll_error(cfg.sins.eps1, w, rec.t), rtol=1e-9,
                               atol=1e-12)
    exact = rsf.lateral_deviation_exact(cfg.sins.eps1, w, rec.t)
    np.testing.assert_allclose(run.lateral_raw[0], exact, rtol=1e-4, atol=1e-6)


def test_correction_reduces_the_rate_error_to_the_gs_error():
    """After the first interval the corrected SINS rate error is the GS error rate
    (ε0,GS + ε1,GS ω_unc) plus the encoder term: the SINS bias is absorbed too."""
    cfg = rsf.SimulationConfig(sins=rsf.SinsGyroModel(arw=0.0),
                               encoder=rsf.EncoderModel(position_error=0.0), duration=60.0)
    rec = rsf.simulate_flight(cfg, seed=2)
    run = rsf.run_correction(rec, 5.0)
    n5 = round(5.0 * cfg.sample_rate)
    slope = np.polyfit(rec.t[n5:], run.roll_error_corrected[0, n5:], 1)[0]
    gs_rate = cfg.gs.eps0 + cfg.gs.eps1 * (cfg.roll.rate_start - cfg.gs.motor_rate_max)
    assert slope == pytest.approx(gs_rate, rel=0.05)
    raw_slope = np.polyfit(rec.t, run.roll_error_raw[0], 1)[0]
    assert raw_slope == pytest.approx(cfg.sins.eps1 * cfg.roll.rate_start + cfg.sins.eps0,
                                      rel=1e-3)
    assert abs(run.lateral_corrected[0, -1]) < abs(run.lateral_raw[0, -1])


def test_reset_angle_pins_the_sins_angle_to_the_gs_at_each_correction():
    """With reset_angle the corrected SINS angle equals the GS angle at every correction instant."""
    rec = rsf.simulate_flight(rsf.SimulationConfig(duration=20.0), seed=4)
    run = rsf.run_correction(rec, 5.0, reset_angle=True)
    idx = np.round(run.t_boundaries[1:] * rec.config.sample_rate).astype(int)
    np.testing.assert_allclose(run.roll_error_corrected[0, idx], run.roll_error_gs[0, idx],
                               atol=1e-12)


def test_the_two_readings_of_k_differ_by_eps1_squared_in_simulation():
    """In the closed loop the two readings of K give δK differing by ε̂1², as derived."""
    rec = rsf.simulate_flight(rsf.SimulationConfig(duration=20.0), seed=8)
    lin = rsf.run_correction(rec, 5.0, k_form="linear")
    rec_ = rsf.run_correction(rec, 5.0, k_form="reciprocal")
    np.testing.assert_allclose(rec_.delta_k - lin.delta_k, lin.eps1_hat**2, rtol=0.01)


def test_pi_loop_saturates_at_the_motor_limit_and_tracks_otherwise():
    """The GS loop leaves ω_unc = ω − W_max when saturated and −ε0,GS/(1 + ε1,GS) when unlimited."""
    cfg = rsf.SimulationConfig(duration=5.0)
    rec = rsf.simulate_flight(cfg, seed=0)
    np.testing.assert_allclose(rec.omega_unc, 300.0 * DEG, rtol=1e-12)
    quiet_ideal = rsf.GsModel(arw=0.0, motor_rate_max=math.inf)
    ideal = rsf.simulate_flight(dataclasses.replace(cfg, gs=quiet_ideal), seed=0)
    # Unsaturated, the loop nulls the MEMS reading: the platform drifts at −ε0,GS/(1 + ε1,GS).
    np.testing.assert_allclose(ideal.omega_unc[0, -200:], -cfg.gs.eps0 / (1 + cfg.gs.eps1),
                               rtol=1e-9)


def test_spin_up_is_tracked_by_the_pi_loop():
    """During a ramp the unlimited PI loop lags by ramp/k_i, as a type-1 loop must."""
    cfg = rsf.SimulationConfig(roll=rsf.RollProfile(900 * DEG, 3600 * DEG),
                               gs=rsf.GsModel(motor_rate_max=math.inf), duration=10.0)
    rec = rsf.simulate_flight(cfg, seed=0)
    # A ramp of α = 270 °/s² leaves α/K_i = 13.5 °/s uncompensated (type-1 loop on the rate).
    ramp = (3600 - 900) * DEG / 10.0
    assert rec.omega_unc[0, -1] == pytest.approx(ramp / cfg.gs.ki, rel=0.05)


def test_seed_makes_runs_reproducible():
    """The same seed gives identical records and another seed different ones."""
    cfg = rsf.SimulationConfig(duration=2.0, n_runs=3)
    a, b, c = rsf.simulate_flight(cfg, 7), rsf.simulate_flight(cfg, 7), rsf.simulate_flight(cfg, 8)
    np.testing.assert_allclose(a.sins_inc, b.sins_inc, rtol=1e-12, atol=0)
    np.testing.assert_allclose(a.theta_rel, b.theta_rel, rtol=1e-12, atol=0)
    assert not np.array_equal(a.sins_inc, c.sins_inc)


# Validation --------------------------------------------------------------------------------------
@pytest.mark.parametrize("make, name", [
    (lambda: rsf.SimulationConfig(sample_rate=10.0, roll=rsf.RollProfile(3600 * DEG)),
     "sample_rate"),
    (lambda: rsf.SimulationConfig(duration=-1.0), "duration"),
    (lambda: rsf.SimulationConfig(duration=1.0, sample_rate=200.5), "duration"),
    (lambda: rsf.SimulationConfig(n_runs=0), "n_runs"),
    (lambda: rsf.SimulationConfig(errors="worst"), "errors"),
    (lambda: rsf.RollProfile(rate_start=0.0), "rate_start"),
    (lambda: rsf.GsModel(kp=-1.0), "kp"),
    (lambda: rsf.GsModel(motor_rate_max=0.0), "motor_rate_max"),
    (lambda: rsf.GsModel(tau_motor=0.0), "tau_motor"),
    (lambda: rsf.SinsGyroModel(eps1=0.9), "eps1"),
    (lambda: rsf.EncoderModel(counts_per_rev=2), "counts_per_rev"),
    (lambda: rsf.EncoderModel(position_error=-1e-3), "position_error"),
    (lambda: rsf.run_correction(rsf.simulate_flight(rsf.SimulationConfig(duration=2.0), 0), 0.0123),
     "period"),
    (lambda: rsf.run_correction(rsf.simulate_flight(rsf.SimulationConfig(duration=2.0), 0), 5.0),
     "period"),
    (lambda: rsf.unwrap_counts(np.array([0, 5000]), 4000), "wrapped"),
])
def test_invalid_simulation_inputs_raise_value_error_naming_the_parameter(make, name):
    """Bad simulation inputs raise ValueError naming the parameter."""
    with pytest.raises(ValueError, match=name):
        make()


def test_invalid_types_raise_type_error():
    """Wrong types to the simulator and the unwrapper raise TypeError naming the argument."""
    with pytest.raises(TypeError, match="wrapped"):
        rsf.unwrap_counts(np.array([0.5, 1.0]), 4000)
    with pytest.raises(TypeError, match="config"):
        rsf.simulate_flight("config", seed=0)
    with pytest.raises(TypeError, match="seed"):
        rsf.simulate_flight(rsf.SimulationConfig(duration=2.0), seed=1.5)


def test_the_simulation_defaults_are_the_datasheet_records_by_hand():
    """SimulationConfig's sensors are built from the one record of each device: the values
    are the paper's, converted by hand (no library conversion)."""
    cfg = rsf.SimulationConfig()
    deg_h = math.pi / 180.0 / 3600.0
    assert cfg.sins.eps1 == pytest.approx(600e-6, rel=1e-15)
    assert cfg.sins.eps0 == pytest.approx(100.0 * deg_h, rel=1e-15)
    assert cfg.gs.eps0 == pytest.approx(math.hypot(10.0, 7.0) * deg_h, rel=1e-15)
    assert cfg.gs.eps1 == pytest.approx(280e-6, rel=1e-15)
    assert cfg.encoder.counts_per_rev == 1000 * 4
    assert cfg.encoder.position_error == pytest.approx(math.radians(0.33), rel=1e-15)
    # A changed record changes the model it builds (the spec is the one description).
    enc = rsf.EncoderModel.from_spec(dataclasses.replace(rsf.AEDB9340, cycles_per_rev=256))
    assert enc.counts_per_rev == 1024 and enc.resolution == pytest.approx(2 * math.pi / 1024)


def test_unwrapped_count_equals_the_never_wrapped_count_at_every_sample():
    """unwrap_counts recovers, to the count, what an encoder that never restarts would show
    (encoder_counts(wrap=False)), over hundreds of revolutions at 3600 °/s."""
    cfg = rsf.SimulationConfig(roll=rsf.RollProfile(math.radians(3600.0)),
                               gs=rsf.GsModel.from_spec(rsf.GYPRO4300, motor_rate_max=math.inf),
                               duration=20.0)
    rec = rsf.simulate_flight(cfg, seed=3)
    args = (rec.theta_rel, cfg.encoder, rec.encoder_phase)
    unwrapped = rsf.unwrap_counts(rsf.encoder_counts(*args), cfg.encoder.counts_per_rev)
    never = rsf.encoder_counts(*args, wrap=False)
    revolutions = (never[0, -1] - never[0, 0]) / cfg.encoder.counts_per_rev
    assert revolutions > 150
    np.testing.assert_array_equal(unwrapped - unwrapped[:, :1], never - never[:, :1])
    # Power: sampled too slowly (a step of more than half a revolution), it would fail.
    coarse = rsf.encoder_counts(rec.theta_rel[:, ::20], cfg.encoder, rec.encoder_phase)
    never_c = never[:, ::20]
    bad = rsf.unwrap_counts(coarse, cfg.encoder.counts_per_rev)
    assert np.any((bad - bad[:, :1]) != (never_c - never_c[:, :1]))
