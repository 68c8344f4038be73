"""Paper RSF formulas (gyrolib.rsf): hand-checkable cases, SymPy derivations from
the measurement model, and the paper's Tables 2 and 3 against the print."""

import dataclasses
import math

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import quad

from gyrolib import rsf, stats
from gyrolib.rsf.correction import interval_estimates
from gyrolib.units import DEG, G0, PPM, from_si, to_si

W3600 = 3600.0 * DEG
W900 = 900.0 * DEG
W300 = 300.0 * DEG


# Hand-checkable cases ----------------------------------------------------------------------------
def test_measurement_model_by_hand():
    """ω_x = (1 + ε1) ω + ε0 against hand-computed readings."""
    assert rsf.gyro_output(1.0, 1e-3, 2e-3) == pytest.approx(1.003, abs=1e-15)
    np.testing.assert_allclose(rsf.gyro_output(np.array([0.0, 2.0]), 0.5, 0.0), [0.0, 3.0])


def test_eq1_eq2_eq3_by_hand():
    """Eqs. (1)–(3) (difference, ε̂1, both forms of K, corrected rate) against hand arithmetic."""
    assert rsf.roll_difference(1.25, 1.0) == pytest.approx(0.25)
    # 0.01 rad over 5 s at 10 rad/s: 0.01 / 50 = 2e-4.
    assert rsf.sf_error_estimate(0.01, 10.0, 5.0) == pytest.approx(2e-4, rel=1e-14)
    assert rsf.correction_coefficient(2e-4) == pytest.approx(0.9998, rel=1e-15)
    assert rsf.correction_coefficient(2e-4, "reciprocal") == pytest.approx(1 / 1.0002, rel=1e-15)
    assert rsf.corrected_rate(10.0, 0.9998) == pytest.approx(9.998)


def test_eq4_eq9_eq7_by_hand():
    # Eq. (4): 600 ppm of 3600 °/s for 10 s is 21.6°.
    """Eq. (4) (21.6° at 10 s), Eq. (9) (0.363°) and Eq. (7) (0.7665°/4500°) against hand
    arithmetic."""
    assert from_si(rsf.sins_roll_error(600 * PPM, W3600, 10.0), "deg") == pytest.approx(21.6)
    # Eq. (9): 3.3e-3 °/s for 10 s plus 0.33°.
    assert from_si(rsf.gs_roll_error_ideal(3.3e-3 * DEG, 10.0, 0.33 * DEG), "deg") \
        == pytest.approx(0.363)
    # Eq. (7): ((3.3e-3 + 280e-6 * 300) * 5 + 0.33) / (900 * 5) = 0.7665 / 4500.
    dk = rsf.delta_k(3.3e-3 * DEG, 0.33 * DEG, W900, 5.0, 280 * PPM, W300)
    assert dk == pytest.approx(0.7665 / 4500, rel=1e-12)
    # The ideal form is Eq. (7) without the uncompensated-rate term.
    assert rsf.delta_k_ideal(3.3e-3 * DEG, 0.33 * DEG, W900, 5.0) \
        == pytest.approx((0.0165 + 0.33) / 4500, rel=1e-12)


def test_eq8_cubic_by_hand():
    # g ε1 ω t³ / 6 with ω = 62.83 rad/s: 9.80665 * 6e-4 * 62.8319 * 1000 / 6 = 61.617 m.
    """Eq. (8)'s cubic g ε1 ω t³/6 against its hand value, 61.617 m at 10 s."""
    expected = 9.80665 * 6e-4 * (3600 * math.pi / 180) * 1000 / 6
    assert rsf.lateral_deviation_cubic(600 * PPM, W3600, 10.0) == pytest.approx(expected)
    assert expected == pytest.approx(61.617, abs=1e-3)


# SymPy derivations from the measurement model -----------------------------------------------------
eps1, eps0, w, dt, t, g = sp.symbols("epsilon_1 epsilon_0 omega Delta_t t g", positive=True)
e0g, e1g, wu, enc = sp.symbols("epsilon_0GS epsilon_1GS omega_unc Delta_gamma_enc",
                               positive=True)


def _increments():
    """SINS and GS angle increments over one interval from the measurement model."""
    sins = sp.integrate((1 + eps1) * w, (t, 0, dt))     # ε0 neglected, as the paper does
    gs_error = (e0g + e1g * wu) * dt + enc             # Eq. (6) over the interval
    gs = w * dt + gs_error
    return sins, gs, gs_error


def test_eq2_and_the_two_readings_of_k_from_sympy():
    """ε̂1 and both readings of K against a SymPy derivation from the measurement model (linear
    exact, reciprocal off by ε1²)."""
    sins, _, _ = _increments()
    noise_free = sins - w * dt
    eps1_hat = noise_free / (sins / dt * dt)           # Eq. (2): measured rate in the denominator
    assert sp.simplify(eps1_hat - eps1 / (1 + eps1)) == 0
    k_lin = 1 - eps1_hat
    k_rec = 1 / (1 + eps1_hat)
    # The linear reading inverts the scale factor exactly, the reciprocal one to O(ε1²).
    assert sp.simplify(k_lin * (1 + eps1) - 1) == 0
    residual_rec = sp.series(k_rec * (1 + eps1) - 1, eps1, 0, 3).removeO()
    assert sp.simplify(residual_rec - eps1**2) == 0
    # The library agrees with both expressions.
    val = {eps1: 600e-6}
    e_hat = float(eps1_hat.subs(val))
    assert rsf.correction_coefficient(e_hat, "linear") == pytest.approx(float(k_lin.subs(val)),
                                                                       rel=1e-15)
    assert rsf.correction_coefficient(e_hat, "reciprocal") \
        == pytest.approx(float(k_rec.subs(val)), rel=1e-15)
    assert rsf.residual_sf_error(600e-6, rsf.correction_coefficient(e_hat, "reciprocal")) \
        == pytest.approx(600e-6**2, rel=2e-3)


def test_eq3_eq4_eq6_eq9_from_sympy():
    """Eqs. (3), (4), (6) and (9) against their SymPy integrals of the error models."""
    e0, tau = sp.symbols("epsilon_0 tau", positive=True)
    e_hat = sp.Symbol("hat_epsilon_1", positive=True)
    # Eq. (4): integrate the measurement model's error.
    sins_error = sp.integrate((1 + eps1) * w + e0 - w, (tau, 0, t))
    assert sp.simplify(sins_error - (eps1 * w * t + e0 * t)) == 0
    # Eq. (3): K ω_x with K = 1 − ε̂1 is ω (1 + (ε1 − ε̂1)) to first order.
    corrected = sp.expand((1 - e_hat) * (1 + eps1) * w)
    assert sp.simplify(corrected - w * (1 + eps1 - e_hat) + w * eps1 * e_hat) == 0
    # Eq. (6) for a constant ω_unc, and Eq. (9) as its ε1,GS = 0 case.
    gs_error = sp.integrate(e0g + e1g * wu, (tau, 0, t)) + enc
    vals = {e0g: 3.3e-3 * DEG, e1g: 280e-6, wu: W300, enc: 0.33 * DEG, t: 60.0}
    assert rsf.gs_roll_error_nonideal(3.3e-3 * DEG, 280e-6, W300, 60.0, 0.33 * DEG) \
        == pytest.approx(float(gs_error.subs(vals)), rel=1e-12)
    assert rsf.gs_roll_error_ideal(3.3e-3 * DEG, 60.0, 0.33 * DEG) \
        == pytest.approx(float(gs_error.subs({**vals, e1g: 0})), rel=1e-12)
    assert rsf.sins_roll_error(600e-6, W3600, 10.0, eps0=1e-4) == pytest.approx(
        float(sins_error.subs({eps1: 600e-6, w: W3600, t: 10.0, e0: 1e-4})), rel=1e-12)


def test_eq5_and_eq7_from_sympy():
    """Eqs. (5) and (7) against δK derived symbolically from Eqs. (1)–(3) and the GS error."""
    sins, gs, gs_error = _increments()
    dgamma = sins - gs                                  # Eq. (1)
    eps1_hat = dgamma / sins                            # Eq. (2), ω_x Δt = ∫ω_x dt
    k = 1 - eps1_hat
    k_true = 1 / (1 + eps1)
    delta_k = sp.simplify((k - k_true) / k_true)
    # δK = GS error over the interval / (ω Δt): Eq. (7) (and, for ε1,GS = 0, the ideal form).
    assert sp.simplify(delta_k - gs_error / (w * dt)) == 0
    # Eq. (5): the estimation error times ω_x Δt is the GS error over the interval.
    eps1_true_ref = eps1 / (1 + eps1)                   # what ε̂1 estimates without GS errors
    assert sp.simplify((eps1_true_ref - eps1_hat) * sins - gs_error) == 0
    vals = {e0g: 3.3e-3 * DEG, e1g: 280e-6, wu: W300, enc: 0.33 * DEG, w: W900, dt: 5.0,
            eps1: 600e-6}
    lib = rsf.delta_k(3.3e-3 * DEG, 0.33 * DEG, W900, 5.0, 280e-6, W300)
    assert lib == pytest.approx(float(delta_k.subs(vals)), rel=1e-12)
    assert rsf.difference_error(3.3e-3 * DEG, 5.0, 0.33 * DEG, 280e-6, W300) \
        == pytest.approx(float(gs_error.subs(vals)), rel=1e-12)


def test_eq8_from_sympy_cubic_and_exact():
    """The cubic and exact lateral deviation against SymPy's double integrals of g a t and g sin(a
    t)."""
    a, u, s = sp.symbols("a u s", positive=True)
    exact = sp.integrate(sp.integrate(g * sp.sin(a * u), (u, 0, s)), (s, 0, t))
    assert sp.simplify(exact - g * (a * t - sp.sin(a * t)) / a**2) == 0
    cubic = sp.integrate(sp.integrate(g * a * u, (u, 0, s)), (s, 0, t))
    assert sp.simplify(cubic - g * a * t**3 / 6) == 0
    # The cubic is the leading term of the exact integral.
    assert sp.simplify(sp.series(exact, t, 0, 5).removeO() - cubic) == 0
    av = 600e-6 * W3600
    for tv in (0.5, 10.0, 60.0, 120.0):
        sub = {a: av, t: tv, g: G0}
        assert rsf.lateral_deviation_exact(600e-6, W3600, tv) == pytest.approx(
            float(exact.subs(sub)), rel=1e-12)
        assert rsf.lateral_deviation_cubic(600e-6, W3600, tv) == pytest.approx(
            float(cubic.subs(sub)), rel=1e-12)


def test_eq8_exact_against_quadrature_and_small_angle_limit():
    """The closed-form exact Δr_z against adaptive quadrature and, for small angles, the cubic."""
    av = 600e-6 * W3600
    for tv in (1e-3, 10.0, 60.0, 120.0):
        # ∫∫ f = ∫₀ᵗ (t − s) f(s) ds, by adaptive quadrature.
        ref = quad(lambda s, tv=tv: (tv - s) * G0 * math.sin(av * s), 0, tv, epsabs=0,
                   epsrel=1e-13, limit=200)[0]
        assert rsf.lateral_deviation_exact(600e-6, W3600, tv) == pytest.approx(ref, rel=1e-9)
    # Where a·t is tiny the series branch keeps full precision (no cancellation).
    tiny = rsf.lateral_deviation_exact(1e-6, 1.0, 1e-3)
    assert tiny == pytest.approx(G0 * 1e-6 * 1e-9 / 6, rel=1e-12)


def test_eq8_cubic_and_exact_diverge_once_the_angle_is_large():
    """The cubic overstates the exact Δr_z once the roll error reaches tens of degrees (ratios at
    Table 2's times)."""
    tab = rsf.table2()
    ratio = tab.dr_z_exact / tab.dr_z_cubic
    assert ratio[0] == pytest.approx(1.0, abs=0.01)          # 21.6°: small angle still fair
    assert ratio[1] < 0.8 and ratio[2] < 0.4                 # 129.6°, 259.2°: invalid


# The paper's tables against the print ------------------------------------------------------------
def test_table2_roll_error_reproduces_the_print_exactly():
    """Table 2's Δγ_SINS against the printed 21.6°, 129.6°, 259.2° to the print's digits."""
    tab = rsf.table2()
    np.testing.assert_allclose(from_si(tab.dgamma_sins, "deg"), [21.6, 129.6, 259.2],
                               rtol=1e-12)


def test_table2_lateral_deviation_follows_t_cubed_but_not_the_printed_constant():
    """The printed Δr_z scale exactly as t³ but sit a constant factor off g ε1 ω/6."""
    printed = np.array([21.25, 4590.0, 36730.0])
    # The print scales as t³ within its rounding (ratios 216 and 8).
    assert printed[1] / printed[0] == pytest.approx(216.0, rel=1e-3)
    assert printed[2] / printed[1] == pytest.approx(8.0, rel=1e-3)
    tab = rsf.table2()
    assert tab.dr_z_cubic[0] == pytest.approx(61.617, abs=1e-3)
    # The print is 0.345 of the cubic in metres: not a rounding difference.
    np.testing.assert_allclose(printed / tab.dr_z_cubic, 0.3449, rtol=2e-3)


def test_table3_reproduces_the_print_with_the_papers_truncated_bias():
    """Table 3 against the print with ε0,GS = 3.3·10⁻³ °/s, and off it with the consistent ε0,GS."""
    printed_eps0_t = [0.033, 0.198, 0.396]
    printed_gs = [0.363, 0.528, 0.726]
    tab = rsf.table3(eps0_gs=float(to_si(3.3e-3, "deg/s")))
    np.testing.assert_allclose(from_si(tab.eps0_t, "deg"), printed_eps0_t, atol=5e-4)
    np.testing.assert_allclose(from_si(tab.dgamma_gs, "deg"), printed_gs, atol=5e-4)
    # With ε0,GS = √(10² + 7²) °/h = 3.39e-3 °/s the values are 2.8 % higher.
    exact = rsf.table3()
    assert from_si(rsf.GYPRO4300.bias_total, "deg/h") == pytest.approx(math.sqrt(149))
    np.testing.assert_allclose(from_si(exact.eps0_t, "deg") / printed_eps0_t,
                               3.3907 / 3.3, rtol=1e-3)
    # Δγ_GS − ε0,GS·t is the encoder error 0.33° in every printed column.
    np.testing.assert_allclose(np.subtract(printed_gs, printed_eps0_t), 0.33, atol=1e-12)


def test_worked_example_with_and_without_the_ppm_slip():
    """The worked example gives the printed 0.093 only with ε1,GS = 280·10⁻³ and 1.70·10⁻⁴ with
    280 ppm."""
    consistent = rsf.worked_example_delta_k()
    assert consistent == pytest.approx(1.704e-4, rel=1e-3)
    slip = rsf.worked_example_delta_k(eps0_gs=float(to_si(3.3e-3, "deg/s")), eps1_gs=280e-3)
    assert slip == pytest.approx(0.093, abs=5e-4)   # the printed 0.093


def test_delta_k_is_the_residual_scale_factor_error_and_the_share_compensated():
    """δK equals the residual SF error K(1 + ε1) − 1, and the share removed is 1 − δK/ε1 (72 % in
    the example)."""
    for k in (0.999, 0.9994, 1.0):
        assert rsf.relative_k_error(k, 600e-6) == pytest.approx(rsf.residual_sf_error(600e-6, k),
                                                               abs=1e-15)
    assert rsf.fraction_compensated(600e-6, 1.704e-4) == pytest.approx(1 - 1.704 / 6, rel=1e-12)
    # The paper's δK = 0.093 would leave 155 times the uncorrected error.
    assert rsf.fraction_compensated(600e-6, 0.093) == pytest.approx(-154.0, rel=1e-12)


# Sensor records and validation ----------------------------------------------------------------
def test_sensor_records_hold_the_papers_values_in_si():
    """The sensor records hold the paper's values, converted to SI by hand."""
    assert from_si(rsf.SIIMU02_ROLL.bias_instability, "deg/h") == pytest.approx(100.0)
    assert rsf.SIIMU02_ROLL.sf_error == pytest.approx(600e-6)
    assert from_si(rsf.GYPRO4300.bias_repeatability, "deg/h") == pytest.approx(10.0)
    assert from_si(rsf.GYPRO4300.bias_stability, "deg/h") == pytest.approx(7.0)
    assert rsf.GYPRO4300.sf_error == pytest.approx(280e-6)
    assert from_si(rsf.AEDB9340.position_error, "deg") == pytest.approx(0.33)
    assert rsf.AEDB9340.counts_per_rev == 4000
    assert from_si(rsf.AEDB9340.resolution, "deg") == pytest.approx(0.09)
    changed = dataclasses.replace(rsf.GYPRO4300, bias_stability=0.0)
    assert changed.bias_total == pytest.approx(rsf.GYPRO4300.bias_repeatability)


# The claims' computations against independent references ------------------------------------------
@pytest.mark.parametrize("t", [0.5, 10.0, 60.0, 120.0])
def test_vertical_deviation_is_the_double_integral_of_g_one_minus_cos(t):
    """The closed-form vertical deviation against adaptive quadrature of ∫∫ g (1 − cos a u)."""
    a = 600 * PPM * W3600
    inner = lambda s: quad(lambda u: G0 * (1.0 - math.cos(a * u)), 0.0, s)[0]  # noqa: E731
    reference = quad(inner, 0.0, t, limit=200)[0]
    assert rsf.vertical_deviation_exact(600 * PPM, W3600, t) == pytest.approx(reference,
                                                                              rel=1e-8)


def test_vertical_exceeds_lateral_only_past_a_large_roll_error():
    """The vertical component is negligible at 10 s, smaller at 60 s and larger than the lateral
    one at 120 s (259°); its small-angle limit is g a² t⁴/24."""
    tab = rsf.table2()
    # 21.6° at 10 s: vertical ≪ lateral; 129.6°: still smaller; 259.2° at 120 s: larger.
    assert tab.dr_y_exact[0] < 0.1 * tab.dr_z_exact[0]
    assert tab.dr_y_exact[1] < tab.dr_z_exact[1] and tab.dr_y_exact[2] > tab.dr_z_exact[2]
    # Small-angle limit g a² t⁴ / 24 (series of the closed form).
    a = 600 * PPM * W3600
    assert rsf.vertical_deviation_exact(600 * PPM, W3600, 0.01) \
        == pytest.approx(G0 * a**2 * 0.01**4 / 24, rel=1e-6)


def test_compensation_share_threshold_is_where_the_share_crosses_the_target():
    """The closed-form 90 % rate against a grid search of the Eq. (7) share, and the 900 °/s share
    against hand arithmetic."""
    cs = rsf.compensation_share(to_si(np.linspace(900.0, 5400.0, 451), "deg/s"))
    # Second method: the first grid rate (10 °/s steps) whose Eq. (7) share reaches 90 %.
    first = from_si(cs.rates[np.argmax(cs.share >= 0.9)], "deg/s")
    assert from_si(cs.rate_for_target, "deg/s") == pytest.approx(first, abs=10.0)
    assert cs.share_at(cs.rate_for_target) == pytest.approx(0.9, rel=1e-12)
    assert cs.share[0] == pytest.approx(1 - 0.76695 / 4500 / 600e-6, abs=1e-4)  # 71.6 %


def test_simulated_share_confirms_eq7_is_conservative_at_every_rate():
    """Seeded simulation: the share removed exceeds Eq. (7)'s at each rate; with a 10× worse GS
    gyro it falls below 90 % at 3600 °/s."""
    rates = to_si([900.0, 3600.0], "deg/s")
    sim = rsf.sweep_roll_rate(rates, seed=7, n_runs=20, duration=20.0)
    cs = rsf.compensation_share(rates, simulated=sim)
    # Eq. (7) adds 1σ terms linearly: the simulated rms δK lies below it at each rate.
    assert np.all(sim.rms < sim.eq7) and np.all(sim.share > cs.share)
    np.testing.assert_allclose(sim.eq7, cs.delta_k, rtol=1e-12)
    # Power: with the GS gyro's SF error 10× larger the simulated share falls below 90 % at
    # 3600 °/s, as Eq. (7) says it would.
    worse = rsf.SimulationConfig(gs=rsf.GsModel(eps1=2800 * PPM))
    sim_w = rsf.sweep_roll_rate(rates[1:], seed=7, base=worse, n_runs=20, duration=20.0)
    assert sim_w.share[0] < 0.9 < sim.share[1]


def test_gs_vs_sins_by_hand():
    """The ideal and non-ideal GS-to-SINS ratios at 10 s against hand arithmetic."""
    r = rsf.gs_vs_sins([10.0])
    eps0 = math.hypot(10.0, 7.0) / 3600.0                        # °/s
    assert r.ratio_ideal[0] == pytest.approx(21.6 / (eps0 * 10 + 0.33), rel=1e-12)
    assert r.ratio_nonideal[0] == pytest.approx(21.6 / ((eps0 + 0.084) * 10 + 0.33), rel=1e-12)


def test_rate_sweep_share_interval_covers_other_seeds():
    """The share's 95 % interval (bootstrap over runs) from one seed against the spread of the
    share over independent seeds: at least 3 of 4 other seeds' shares fall inside the
    interval widened to the sum of the two ensembles' uncertainty (√2 times its half-width);
    power: an interval a tenth as wide leaves most of them out."""
    rate = to_si([900.0], "deg/s")
    ref = rsf.sweep_roll_rate(rate, seed=11, n_runs=40, duration=10.0)
    est = ref.share_estimate(0)
    assert est.lo <= ref.share[0] <= est.hi and est.n == 40 and est.seed == 11
    others = [rsf.sweep_roll_rate(rate, seed=s, n_runs=40, duration=10.0).share[0]
              for s in (21, 31, 41, 51)]
    half = math.sqrt(2) * 0.5 * (est.hi - est.lo)
    assert sum(abs(x - est.value) <= half for x in others) >= 3
    assert sum(abs(x - est.value) <= 0.1 * half for x in others) < 3
    with pytest.raises(ValueError, match=r"^i must"):
        ref.share_estimate(1)


def test_period_sweep_rms_interval_agrees_with_the_delta_method():
    """The rms δK's interval (bootstrap over runs) against the closed form of the delta
    method, rms = √m̄ with m̄ the mean of the runs' mean squares: half-width
    1.96 sd(m)/(2√(n m̄)).  Power: the bootstrap at 50 % confidence misses the same
    tolerance."""
    rec = rsf.simulate_flight(rsf.SimulationConfig(duration=20.0, n_runs=80), seed=3)
    sw = rsf.sweep_correction_period(rec, [5.0])
    est = sw.rms_estimate(0)
    m = np.mean(interval_estimates(rec, 5.0, "linear", rsf.gs_angle(rec))[2] ** 2, axis=1)
    half = 1.96 * m.std(ddof=1) / (2.0 * math.sqrt(m.size * m.mean()))
    assert est.value == pytest.approx(math.sqrt(m.mean()), rel=1e-12)
    assert est.n == 80 and est.seed == 3
    assert abs(est.lo - (est.value - half)) < 0.25 * half
    assert abs(est.hi - (est.value + half)) < 0.25 * half
    narrow = stats.bootstrap(m, lambda x: np.sqrt(np.mean(x, axis=-1)), seed=3,
                             vectorized=True, confidence=0.5)
    assert not abs(narrow.lo - (est.value - half)) < 0.25 * half
