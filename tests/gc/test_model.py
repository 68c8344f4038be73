"""gyrolib.gc against independent references: the sympy derivation of paper GC's
Eqs. (3)–(8) (gyrolib.gc.symbolic), the paper's printed matrix listing, closed-form and
second-integrator solutions of Eq. (4), and the validation contract of GyrocompassParams."""

import dataclasses
import math
from dataclasses import replace

import numpy as np
import pytest
import sympy as sp

from gyrolib import gc
from gyrolib.gc import (
    STATE_NAMES,
    GyrocompassParams,
    initial_covariance,
    measurement_matrix,
    measurement_noise_covariance,
    noise_input_matrix,
    nominal_motion,
    nominal_motion_aperiodic,
    nominal_motion_reference,
    symbolic,
    system_matrix,
)

S = symbolic.SYMBOLS
BETAS = [0.0, 1e-3, 0.0086, -0.3, 0.7, 1.2, math.pi / 2]
# A second parameter set far from the paper's, so that no coincidence of values hides an error.
OTHER = GyrocompassParams(I=2e-4, H=0.3, f=0.11, Omega_v=3e-5, Omega_h=6e-5, g=9.78,
                          omega_ub=7e-8, alpha1=0.2, xi1=0.35, alpha2=3.0, xi2=0.9)


# Symbolic model = library model ----------------------------------------------------------------
@pytest.mark.parametrize("coupling", symbolic.COUPLINGS)
@pytest.mark.parametrize("params", [GyrocompassParams(), OTHER], ids=["paper", "other"])
def test_library_matrices_equal_sympy_derivation(coupling, params):
    """Numeric F, G, D of Eq. (8) equal the sympy derivation (both couplings, two parameter
    sets, several β_n) to 1e-13."""
    p = dataclasses.replace(params, vertical_coupling=coupling)
    for beta_n in BETAS:
        F_sym, G_sym, D_sym = symbolic.numeric_matrices(p, beta_n)
        F = system_matrix(p, beta_n)
        scale = np.abs(F_sym).max()
        np.testing.assert_allclose(F, F_sym, rtol=1e-13, atol=1e-15 * scale)
        np.testing.assert_allclose(noise_input_matrix(p), G_sym, rtol=1e-14, atol=0)
        np.testing.assert_allclose(measurement_matrix(p), D_sym, rtol=1e-14, atol=0)


def test_symbolic_state_order_is_the_library_order():
    """The sympy state vector is gyrolib's STATE_NAMES order (X1 = Δβ, X2 = Δβ')."""
    names = [str(x) for x in symbolic.state_space().x]
    assert names == [r"\Delta\beta", r"\Delta\dot{\beta}", "psi", "omega_gc", "delta", "gamma",
                     "N_1", "N_2", "N_3", "N_4"]
    assert len(names) == len(STATE_NAMES)


def _mismatches(model):
    return {(r.matrix, r.i, r.j) for r in symbolic.compare_with_paper(model) if not r.equal}


def test_derivation_matches_paper_listing_except_the_settled_errata():
    # With X1 = Δβ, X2 = Δβ', every printed entry is reproduced except F(8,7) (printed without
    # its minus sign) and, for the Eq. (5) coupling, the δ/γ pair F(2,5), F(2,6).
    """The derived F, G, D match the printed listing except F(8,7) and (for eq5) the δ/γ pair;
    the printed X1, X2 labels contradict it."""
    assert _mismatches(symbolic.state_space("eq5")) == {("F", 2, 5), ("F", 2, 6), ("F", 8, 7)}
    assert _mismatches(symbolic.state_space("printed_F")) == {("F", 8, 7)}
    # The printed labels (X1 = Δβ') contradict the printed F and D in many entries.
    assert len(_mismatches(symbolic.state_space("eq5", "printed"))) >= 8


def test_taylor_expansion_gives_eq4_and_the_printed_eq5():
    """Orders 0 and 1 of the Taylor expansion of Eq. (3) are the printed Eqs. (4) and (5) (plus
    the unbalance torque)."""
    lin = symbolic.taylor_linearization()
    t, bn, db = S.t, S.beta_n(S.t), S.dbeta(S.t)
    eq4 = S.I * bn.diff(t, 2) + S.f * bn.diff(t) - S.H * S.Omega_h * sp.cos(bn)
    assert sp.simplify(lin.order0 - eq4) == 0
    # Eq. (5) as printed, plus the unbalance torque H ω_ub N1 / g of the text after Eq. (6).
    lhs = S.I * db.diff(t, 2) + S.f * db.diff(t) + S.H * S.Omega_h * sp.sin(bn) * db
    rhs = (S.H * S.Omega_h * sp.sin(bn) * S.psi + S.H * S.Omega_v * sp.cos(bn) * S.gamma
           - S.H * S.Omega_v * sp.sin(bn) * S.delta + S.H * S.omega_gc + S.H * S.omega_rnd
           + S.H * S.omega_ub * S.N1 / S.g)
    assert sp.expand(lin.order1 - (lhs - rhs)) == 0


def test_minus_sign_in_eq1_mirrors_the_motion_and_flips_only_the_delta_term():
    """With −H Ω_h cos(β − ψ) in Eq. (1), the mirrored linearization differs from Eq. (5) only
    in the sign of the δ term."""
    plus = symbolic.taylor_linearization(sign=1).order1
    minus = symbolic.taylor_linearization(sign=-1).order1
    bn = S.beta_n(S.t)
    mirrored = sp.expand(minus.subs(bn, -bn).doit())
    # Both are "lhs − rhs"; the mirrored model has +HΩ_v sin β_n δ on the right instead of −.
    diff = sp.simplify(mirrored - plus)
    assert sp.simplify(diff + 2 * S.H * S.Omega_v * sp.sin(bn) * S.delta) == 0


def test_relabelling_maps_eq5_with_reversed_unbalance_onto_printed_listing():
    """The signed permutation maps the eq5 model with reversed ω_ub exactly onto the printed
    listing, and leaves P0 and R invariant."""
    rel = symbolic.relabelling()
    a, b = symbolic.state_space("eq5"), symbolic.state_space("printed_F")
    Fa = a.F.subs(S.omega_ub, -S.omega_ub)
    Tinv = rel.T.inv()
    assert (rel.T * Fa * Tinv - b.F).expand() == sp.zeros(10, 10)
    assert (rel.T * a.G * rel.Sw.inv() - b.G).expand() == sp.zeros(10, 2)
    assert (rel.Sm * a.D * Tinv - b.D).expand() == sp.zeros(3, 10)
    # With the same unbalance sign the map fails (only through F(2,7)).
    bad = (rel.T * a.F * Tinv - b.F).expand()
    assert [(i, j) for i in range(10) for j in range(10) if bad[i, j] != 0] == [(1, 6)]
    # Priors, noise intensities and sensor noises are invariant under the map.
    p = GyrocompassParams()
    T = np.array(rel.T, dtype=float)
    Sm = np.array(rel.Sm, dtype=float)
    P0 = initial_covariance(p)
    np.testing.assert_allclose(T @ P0 @ T.T, P0, rtol=0, atol=0)
    R = measurement_noise_covariance(p)
    np.testing.assert_allclose(Sm @ R @ Sm.T, R, rtol=0, atol=0)


def test_printed_F87_makes_the_vibration_filter_unstable():
    """With F(8,7) = +α1² the vibration block has det = −α1² and a positive eigenvalue (closed
    form)."""
    a, xi = S.alpha1, S.xi1
    block = sp.Matrix([[0, 1], [a**2, -2 * xi * a]])
    # det = −α² < 0: the two eigenvalues are real with opposite signs, for every α, ξ > 0.
    assert sp.expand(block.det() + a**2) == 0
    assert sp.expand(sp.Matrix([[0, 1], [-a**2, -2 * xi * a]]).det() - a**2) == 0
    p = GyrocompassParams()
    num = np.linalg.eigvals(np.array([[0.0, 1.0], [p.alpha1**2, -2 * p.xi1 * p.alpha1]]))
    assert num.max() == pytest.approx(p.alpha1 * (-p.xi1 + math.sqrt(p.xi1**2 + 1)), rel=1e-12)


# Nominal motion, Eq. (4) ------------------------------------------------------------------------
def test_nominal_motion_at_100_s_against_an_independent_integrator():
    """Radau solution of Eq. (4) against DOP853 on the difference from the aperiodic solution:
    1e-12 rad over 100 s; 0.5° as printed."""
    p = GyrocompassParams()
    t = np.linspace(0.0, 100.0, 2001)
    radau = nominal_motion(p, t)
    ref = nominal_motion_reference(p, t)
    # Stated tolerance: 1e-12 rad (1e-10 relative); observed ~1e-14 rad.
    assert np.max(np.abs(radau.beta - ref.beta)) < 1e-12
    assert np.max(np.abs(radau.beta_dot - ref.beta_dot)) < 1e-13
    # The reference is converged: tightening its tolerance moves it by < 1e-16 rad.
    ref_loose = nominal_motion_reference(p, t, rtol=1e-11)
    assert np.max(np.abs(ref_loose.beta - ref.beta)) < 1e-16
    # Paper GC: "the float turns through about 0.5°" in 100 s.
    deg = math.degrees(radau.beta[-1])
    assert round(deg, 1) == 0.5
    assert deg == pytest.approx(0.4927, abs=5e-5)


def test_nominal_motion_early_times_match_the_linear_closed_form():
    # For β ≪ 1, cos β ≈ 1 and Eq. (4) is linear: β = k (t − τ (1 − e^{−t/τ})), k = HΩ_h/f.
    """For t ≤ 20 ms (β ≪ 1) Eq. (4) is linear: β = k (t − τ (1 − e^{−t/τ})) to 1e-9."""
    p = GyrocompassParams()
    k, tau = p.H * p.Omega_h / p.f, p.I / p.f
    t = np.linspace(0.0, 0.02, 201)
    exact_linear = k * (t - tau * (1.0 - np.exp(-t / tau)))
    beta = nominal_motion(p, t).beta
    # The neglected cos β − 1 is ≤ β²/2 ≈ 1e-12 relative here.
    np.testing.assert_allclose(beta, exact_linear, rtol=1e-9, atol=1e-18)


def test_aperiodic_approximation_lags_by_k_tau():
    """For t ≫ τ the full nominal motion lags the aperiodic one by k τ (to 1e-4)."""
    p = GyrocompassParams()
    k, tau = p.H * p.Omega_h / p.f, p.I / p.f
    t = np.array([0.05, 1.0, 10.0, 100.0])
    diff = nominal_motion(p, t).beta - nominal_motion_aperiodic(p, t).beta
    # t ≫ τ: β_n(t) ≈ β_ap(t − τ) ⇒ β_n − β_ap ≈ −k τ cos β (β < 0.01 rad here).
    np.testing.assert_allclose(diff, -k * tau, rtol=1e-4)
    assert p.time_constant == pytest.approx(1.6e-3, rel=1e-12)


# Validation of GyrocompassParams ----------------------------------------------------------------
_POSITIVE = ("I", "H", "f", "Omega_h", "g", "alpha1", "sigma1_sq", "alpha2",
             "sigma2_sq", "C_as", "C_incl_y", "C_incl_z", "dt")
_REAL = ("omega_ub", "Omega_v")
_NONNEGATIVE = ("sigma_dbeta0", "sigma_dbeta_dot0", "sigma_psi0", "sigma_gc0",
                "sigma_delta0", "sigma_gamma0", "shaping_p0_scale", "sigma_hf_scale",
                "sigma_as_offset", "sigma_incl_bias", "sigma_clock")
_DAMPING = ("xi1", "xi2")
_CHOICES = ("shaping_p0", "measurement_noise", "vertical_coupling", "eq1_sign")


def test_every_field_is_in_exactly_one_validation_class():
    """Every GyrocompassParams field is in exactly one of the validation classes below."""
    names = [f.name for f in dataclasses.fields(GyrocompassParams)]
    classes = (*_POSITIVE, *_REAL, *_NONNEGATIVE, *_DAMPING, *_CHOICES)
    assert sorted(names) == sorted(classes)


def _bad_values(name):
    wrong_type = ["1.0", None, True, [1.0], 1 + 0j]
    non_finite = [math.nan, math.inf, -math.inf]
    if name in _POSITIVE:
        return [(x, TypeError) for x in wrong_type] + [
            (x, ValueError) for x in (*non_finite, 0.0, -1.0, -1e-300)]
    if name in _NONNEGATIVE:
        return [(x, TypeError) for x in wrong_type] + [
            (x, ValueError) for x in (*non_finite, -1e-300, -1.0)]
    if name in _REAL:
        return [(x, TypeError) for x in wrong_type] + [(x, ValueError) for x in non_finite]
    if name in _DAMPING:
        return [(x, TypeError) for x in wrong_type] + [
            (x, ValueError) for x in (*non_finite, 0.0, -0.2, 1.0000001, 2.0)]
    return [(x, ValueError) for x in ("bogus", "", 1.0, None, "EQ5")]


@pytest.mark.parametrize("name", [f.name for f in dataclasses.fields(GyrocompassParams)])
def test_invalid_values_raise_naming_the_field(name):
    """Wrong types, non-finite and out-of-range values of each field raise naming the field."""
    for bad, err in _bad_values(name):
        with pytest.raises(err, match=rf"\b{name}\b"):
            dataclasses.replace(GyrocompassParams(), **{name: bad})


def test_valid_edge_values_are_accepted_and_stored_as_float():
    """Edge values (ξ = 1, ints, numpy scalars, negative ω_ub, κ = 0) are accepted and stored as
    float; every choice is accepted."""
    p = dataclasses.replace(GyrocompassParams(), xi1=1, xi2=np.float64(1e-9), omega_ub=-1,
                            I=np.int64(1), shaping_p0_scale=0)
    assert p.xi1 == 1.0 and type(p.xi1) is float
    assert type(p.I) is float and type(p.xi2) is float and type(p.omega_ub) is float
    for name in ("shaping_p0", "measurement_noise", "vertical_coupling", "eq1_sign"):
        for choice in {"shaping_p0": ("stationary", "zero"),
                       "measurement_noise": ("intensity_over_dt", "variance"),
                       "vertical_coupling": ("eq5", "printed_F"),
                       "eq1_sign": ("+", "-")}[name]:
            assert getattr(dataclasses.replace(p, **{name: choice}), name) == choice


# Model options: sign of Eq. (1), unbalance sign, P0 scale --------------------------------------
@pytest.mark.parametrize("coupling", symbolic.COUPLINGS)
@pytest.mark.parametrize("params", [GyrocompassParams(), OTHER], ids=["paper", "other"])
def test_eq1_minus_sign_equals_the_mirrored_sympy_model(coupling, params):
    """F with eq1_sign="-" at β_n equals sympy's linearization of Eq. (3) with −H Ω_h cos(β−ψ)
    evaluated on its own (mirrored) nominal motion −β_n; and it differs from the "+" model."""
    p = dataclasses.replace(params, vertical_coupling=coupling, eq1_sign="-")
    model = symbolic.state_space(coupling, sign=-1)
    fn = sp.lambdify([S.beta_n_sym], model.F.subs(symbolic.parameter_values(p)), "numpy")
    for beta_n in BETAS[1:]:
        F_sym = np.array(fn(-beta_n), dtype=float)
        F = system_matrix(p, beta_n)
        np.testing.assert_allclose(F, F_sym, rtol=1e-13, atol=1e-15 * np.abs(F_sym).max())
        plus = system_matrix(dataclasses.replace(p, eq1_sign="+"), beta_n)
        assert np.abs(F - plus).max() > 1e-3 * np.abs(plus[1, 4:6]).max()


def test_reversed_unbalance_makes_the_two_listings_give_the_same_sigma():
    """The symbolic relabelling (T, reversed ω_ub) maps eq5 onto printed_F, so σ_gc of the
    two must agree to rounding (1e-9 over 2 s); with the same unbalance sign they differ."""
    from gyrolib.gc import covariance_analysis

    p = GyrocompassParams()
    prf = dataclasses.replace(p, vertical_coupling="printed_F")
    a = covariance_analysis(p, 2.0).std("omega_gc")[1:]
    b = covariance_analysis(dataclasses.replace(prf, omega_ub=-p.omega_ub), 2.0)
    c = covariance_analysis(prf, 2.0)
    assert np.max(np.abs(b.std("omega_gc")[1:] / a - 1)) < 1e-9
    assert np.max(np.abs(c.std("omega_gc")[1:] / a - 1)) > 1e-6


def test_shaping_p0_scale_multiplies_the_stationary_covariance():
    """P(0) of N1…N4 is κ times the Lyapunov solution; κ = 0 equals the "zero" reading."""
    p = GyrocompassParams()
    P1 = initial_covariance(p)
    Pk = initial_covariance(dataclasses.replace(p, shaping_p0_scale=0.3))
    np.testing.assert_allclose(Pk[6:, 6:], 0.3 * P1[6:, 6:], rtol=1e-15, atol=0)
    np.testing.assert_allclose(Pk[:6, :6], P1[:6, :6], rtol=1e-15, atol=0)
    np.testing.assert_allclose(P1[6:8, 6:8],
                               p.vibration_filter().stationary_covariance(), rtol=1e-15)
    P0 = initial_covariance(dataclasses.replace(p, shaping_p0_scale=0.0))
    np.testing.assert_allclose(P0, initial_covariance(dataclasses.replace(
        p, shaping_p0="zero")), rtol=1e-15, atol=0)


# Discretization options and sweeps -------------------------------------------------------------
def test_euler_discretization_is_the_first_order_step():
    """method="euler": Φ = I + F Δt and Qd = G Q Gᵀ Δt (closed form), against the exact
    Van Loan step which differs at second order (F Δt)²/2."""
    from gyrolib.gc import discretize, process_noise_intensity

    p = GyrocompassParams()
    d = discretize(p, 0.01, method="euler")
    for k in (0, 9):
        F = system_matrix(p, float(d.beta_mid[k]))
        G, Q = noise_input_matrix(p), process_noise_intensity(p)
        Phi, Qd = d.exact_step(k)
        np.testing.assert_allclose(Phi, np.eye(10) + F * p.dt, rtol=1e-15, atol=1e-18)
        np.testing.assert_allclose(Qd, G @ Q @ G.T * p.dt, rtol=1e-15, atol=0)
        np.testing.assert_allclose(d.model.phi(k), Phi, rtol=1e-12, atol=1e-15)
        Phi_exact = discretize(p, 0.01).exact_step(k)[0]
        second = 0.5 * (F @ F) * p.dt**2
        assert np.abs(Phi_exact - Phi).max() == pytest.approx(np.abs(second).max(), rel=0.5)


def test_euler_covariance_fast_path_equals_its_reference_path():
    """The numba path on the Euler affine model equals the plain-numpy path (1e-9, 0.2 s)."""
    from gyrolib.gc import covariance_analysis

    p = GyrocompassParams()
    a = covariance_analysis(p, 0.2, discretization="euler")
    b = covariance_analysis(p, 0.2, discretization="euler", method="reference")
    for name in ("dbeta", "omega_gc", "delta", "N1"):
        np.testing.assert_allclose(a.std(name), b.std(name), rtol=1e-9, atol=0, err_msg=name)


def test_sweep_covariance_equals_single_runs_in_grid_order():
    """sweep_covariance over parameter_grid: one analysis per combination, last field fastest,
    each equal to the direct covariance_analysis of the replaced parameters."""
    from gyrolib.gc import covariance_analysis, parameter_grid, sweep_covariance

    p = GyrocompassParams()
    cases = parameter_grid(shaping_p0=("stationary", "zero"), xi1=(0.5, 0.7))
    assert cases[1] == {"shaping_p0": "stationary", "xi1": 0.7}
    sw = sweep_covariance(p, cases, 0.5)
    for case, got in zip(cases, sw.final_std()):
        want = covariance_analysis(dataclasses.replace(p, **case), 0.5).final_std()
        assert got == pytest.approx(want, rel=1e-12)


# Eqs. (1)-(3), (5) as named functions (gc.model.equations) ------------------------------------
def test_eq5_is_row_two_of_the_state_matrix():
    """Eq. (5) solved for Δβ'' equals row 2 of F(β_n) of Eq. (8) times the state (with the
    vibration and random-drift states zero, which Eq. (5) carries as ω_rnd only), at several
    β_n and a random state; and the check has power: the printed F listing's coupling of δ
    and γ differs."""
    from gyrolib.gc.model.equations import linearized_acceleration

    p = gc.GyrocompassParams()
    rng = np.random.default_rng(5)
    for b in (0.0, 0.4, 1.1, 1.5):
        x = rng.normal(size=10) * np.array([1e-4, 1e-4, 1e-3, 1e-6, 1e-3, 1e-3, 0, 0, 1e-7, 0])
        want = gc.system_matrix(p, b)[1] @ x
        got = linearized_acceleration(p, b, x[0], x[1], psi=x[2], omega_gc=x[3], delta=x[4],
                                      gamma=x[5], omega_rnd=x[8])
        assert got == pytest.approx(want, rel=1e-12, abs=1e-18)
    printed = replace(p, vertical_coupling="printed_F")
    x = np.zeros(10)
    x[4] = 1e-3
    assert gc.system_matrix(printed, 0.4)[1] @ x != pytest.approx(
        float(linearized_acceleration(p, 0.4, 0.0, 0.0, delta=1e-3)), rel=1e-3)


def test_eq5_is_the_derivative_of_eq3():
    """Eq. (5) is Eq. (3) linearized about β_n: a central difference of Eq. (3) in β, ψ, δ,
    γ (with Eq. (4)'s motion subtracted) gives Eq. (5)'s coefficients."""
    from gyrolib.gc.model.equations import float_acceleration, linearized_acceleration

    p = gc.GyrocompassParams()
    b, h = 0.7, 1e-6
    for name in ("beta", "psi", "delta", "gamma"):
        def eq3(e, name=name):
            kw = {"psi": 0.0, "delta": 0.0, "gamma": 0.0}
            beta = b + e if name == "beta" else b
            if name != "beta":
                kw[name] = e
            return float(float_acceleration(p, beta, 0.0, **kw))
        slope = (eq3(h) - eq3(-h)) / (2 * h)
        kw = {"d_beta": 1.0 if name == "beta" else 0.0}
        lin = float(linearized_acceleration(p, b, kw["d_beta"], 0.0,
                                            **({} if name == "beta" else {name: 1.0})))
        assert slope == pytest.approx(lin, rel=1e-6), name


def test_eq1_and_eq2_are_what_eq3_adds_up():
    """Eq. (3)'s right side is Eq. (1)'s torque plus H times the vertical rate of Eq. (2)
    projected on the input axis, plus H ω_gc."""
    from gyrolib.gc.model.equations import float_acceleration, gyroscopic_torque, vertical_rate

    p = gc.GyrocompassParams()
    b, psi, d, g, w = 0.3, 2e-3, 1e-3, -2e-3, 1e-7
    wy, wz = vertical_rate(p, d, g)
    torque = (gyroscopic_torque(p, b, psi) + p.H * (wz * np.cos(b) + wy * np.sin(b))
              + p.H * w)
    assert float(float_acceleration(p, b, 0.0, psi=psi, delta=d, gamma=g, omega_gc=w)) == \
        pytest.approx(float(torque) / p.I, rel=1e-13)
