"""A long run of paper GC's filter: 1000 s at Δt = 1 ms, i.e. 10⁶ steps.

The Joseph-form recursion (numba fast path) and an independent square-root recursion
(QR time update, Potter measurement updates; :mod:`gyrolib.filtering.square_root`) must agree,
and the covariance must stay positive definite all the way.  Rounding errors that the Joseph
form lets accumulate would show here as a growing difference; the tolerance, 1e-8 relative
on every standard deviation at every step, is four orders of magnitude above what a 10⁴-step
run shows (≈ 1e-12) and far below anything visible in a figure.

The 10⁶-step run is of the full tier (``python3 tasks.py test --full``; about 30 CPU-s);
the everyday tier runs the same checks over 10 s, 10⁴ steps.
"""

import numpy as np
import pytest

from gyrolib import filtering, gc
from gyrolib.filtering import cholesky_semidefinite, covariance_square_root
from gyrolib.gc import STATE_NAMES, GyrocompassParams, initial_covariance

#: run length (s) -> (steps, store every): the full P every 10 s of the long run, every
#: 0.1 s of the short one (100 stored P each)
RUNS = {10.0: (10_000, 100), 1000.0: (1_000_000, 10_000)}


@pytest.fixture(scope="module", params=[
    pytest.param(10.0, id="1e4_steps"),
    pytest.param(1000.0, id="1e6_steps", marks=pytest.mark.full)])
def runs(request):
    t_end = request.param
    n_steps, store = RUNS[t_end]
    p = GyrocompassParams()
    disc = gc.discretize(p, t_end)
    assert disc.model.n_steps == n_steps
    P0 = initial_covariance(p)
    joseph = filtering.covariance_fast(disc.model, P0, store)
    sqrt_run, min_corr_eig = covariance_square_root(disc.model, P0, store)
    return joseph, sqrt_run, min_corr_eig


def test_joseph_and_square_root_agree_over_the_run(runs):
    """Joseph (numba) and square-root (QR + Potter) recursions agree to 1e-8 on every σ."""
    joseph, sqrt_run, _ = runs
    sj, ss = np.sqrt(joseph.var[1:]), np.sqrt(sqrt_run.var[1:])
    rel = np.abs(sj - ss) / sj
    worst = {name: float(rel[:, i].max()) for i, name in enumerate(STATE_NAMES)}
    assert max(worst.values()) < 1e-8, worst


def test_covariance_stays_positive_definite(runs):
    """P stays symmetric and positive definite on the correlation scale over the run."""
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
