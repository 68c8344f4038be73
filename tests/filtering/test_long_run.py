"""A long run of paper GC's filter: 1000 s at Δt = 1 ms, i.e. 10⁶ steps.

The Joseph-form recursion (numba fast path) and an independent square-root recursion
(QR time update, Potter measurement updates; :mod:`gyrolib.filtering.square_root`) must agree,
and the covariance must stay positive definite all the way.  Rounding errors that the Joseph
form lets accumulate would show here as a growing difference; the tolerance, 1e-8 relative
on every standard deviation at every step, is four orders of magnitude above what a 10⁴-step
run shows (≈ 1e-12) and far below anything visible in a figure.
"""

import numpy as np
import pytest

from gyrolib import filtering, gc
from gyrolib.filtering import cholesky_semidefinite, covariance_square_root
from gyrolib.gc import STATE_NAMES, GyrocompassParams, initial_covariance

pytestmark = pytest.mark.slow

T_END = 1000.0
STORE = 10_000  # full P every 10 s


@pytest.fixture(scope="module")
def runs():
    p = GyrocompassParams()
    disc = gc.discretize(p, T_END)
    assert disc.model.n_steps == 1_000_000
    P0 = initial_covariance(p)
    joseph = filtering.covariance_fast(disc.model, P0, STORE)
    sqrt_run, min_corr_eig = covariance_square_root(disc.model, P0, STORE)
    return joseph, sqrt_run, min_corr_eig


def test_joseph_and_square_root_agree_over_a_million_steps(runs):
    """Joseph (numba) and square-root (QR + Potter) recursions agree to 1e-8 on every σ."""
    joseph, sqrt_run, _ = runs
    sj, ss = np.sqrt(joseph.var[1:]), np.sqrt(sqrt_run.var[1:])
    rel = np.abs(sj - ss) / sj
    worst = {name: float(rel[:, i].max()) for i, name in enumerate(STATE_NAMES)}
    assert max(worst.values()) < 1e-8, worst


def test_covariance_stays_positive_definite(runs):
    """P stays symmetric and positive definite on the correlation scale over 10⁶ steps."""
    joseph, _, min_corr_eig = runs
    # Square-root form: positive definite by construction; its smallest correlation
    # eigenvalue over the run must stay clearly above rounding.
    assert min_corr_eig > 1e-13
    # Joseph form: every stored P symmetric, and positive definite on the correlation scale.
    for P in joseph.P_stored[1:]:
        np.testing.assert_allclose(P, P.T, rtol=1e-15, atol=0)
        d = np.sqrt(np.diag(P))
        assert np.all(d > 0.0)
        assert np.linalg.eigvalsh(P / np.outer(d, d))[0] > 1e-13


def test_constant_states_never_gain_uncertainty(runs):
    """ψ, ω_gc, δ, γ are constants: their variance never increases."""
    joseph, _, _ = runs
    for name in ("psi", "omega_gc", "delta", "gamma"):
        s = joseph.var[:, STATE_NAMES.index(name)]
        assert np.all(np.diff(s) <= 1e-12 * s[:-1]), name


def test_cholesky_semidefinite_rejects_indefinite_matrices():
    """Indefinite or asymmetric input is rejected; a semidefinite one is factored."""
    with pytest.raises(ValueError, match="positive semi-definite"):
        cholesky_semidefinite(np.diag([1.0, -1.0]))
    with pytest.raises(ValueError, match="symmetric"):
        cholesky_semidefinite(np.array([[1.0, 0.5], [0.0, 1.0]]))
    S = cholesky_semidefinite(np.diag([4.0, 0.0]))
    np.testing.assert_allclose(S @ S.T, np.diag([4.0, 0.0]), atol=1e-15)
