"""Bad input to :mod:`gyrolib.filtering` is rejected by name.

The reference is the contract of CONTRIBUTING.md: bad input raises ``ValueError`` or
``TypeError`` whose message starts with the name of the offending parameter (and, where the
range is a number, states it), never an error from deep inside, a silent NaN or a wrong figure.
The table's coverage is computed from the subpackage's ``__all__`` and its classes' public
methods; hypothesis properties cover continuous ranges.
"""

from __future__ import annotations

import pytest

from tests.support.validation_table import *

TABLE = Table()
case = TABLE.case

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
case("filtering.AffineDiscreteModel.h_matrix", lambda: model().h_matrix(10), ValueError, "k",
     r"\[0, 10\)")
case("filtering.AffineDiscreteModel", lambda: replace(model(), H1=model().H), ValueError, "H1",
     "together")
case("filtering.AffineDiscreteModel",
     lambda: replace(model(), H1=model().H[:, :3], h=np.zeros(model().n_steps)), ValueError,
     "H1")
case("filtering.AffineDiscreteModel",
     lambda: replace(model(), H1=model().H, h=np.zeros(3)), ValueError, "h")
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
case("filtering.covariance_square_root",
     lambda: filtering.covariance_square_root(
         replace(model(), H1=model().H, h=np.zeros(model().n_steps)), I10),
     ValueError, "model", "constant H")
case("filtering.covariance_square_root", lambda: filtering.covariance_square_root(None, I10),
     TypeError, "model")
case("filtering.covariance_square_root", lambda: filtering.covariance_square_root(model(),
                                                                                      -I10),
     ValueError, "P0", "positive semi-definite")
case("filtering.covariance_square_root", lambda: filtering.covariance_square_root(model(),
                                                                                      I10, 0),
     ValueError, "store_every")


# consistency
case("filtering.gated_nis_moments", lambda: filtering.gated_nis_moments(-1.0), ValueError,
     "gate", "(0.0, 1.0)")
case("filtering.gated_nis_moments", lambda: filtering.gated_nis_moments("x"), TypeError, "gate")
case("filtering.gated_nis_band", lambda: filtering.gated_nis_band(0, 0.9999, 0.005, 0.995),
     ValueError, "n", "positive")
case("filtering.gated_nis_band", lambda: filtering.gated_nis_band(10, 16.0, 0.005, 0.995),
     ValueError, "gate", "(0.0, 1.0)")
case("filtering.nees_bounds", lambda: filtering.nees_bounds(0, 10), ValueError, "dof", ">= 1")
case("filtering.nees_bounds", lambda: filtering.nees_bounds(1, 1.0), TypeError, "n_runs")
case("filtering.nees_bounds", lambda: filtering.nees_bounds(1, 10, 1.0), ValueError, "confidence",
     r"\(0.0, 1.0\)")

# kernels (numba kernels themselves take no checks: the factory checks the size)
case("filtering.kalman_kernels", lambda: filtering.kalman_kernels(0), ValueError, "n", ">= 1")
case("filtering.kalman_kernels", lambda: filtering.kalman_kernels(2.0), TypeError, "n",
     "integer")


@pytest.mark.parametrize(("call", "exc", "pattern"), TABLE.cases)
def test_bad_input_is_rejected_by_name(call, exc, pattern):
    run_case(call, exc, pattern)


#: Public callables without a bad-input case, and why.
EXEMPT: dict[str, str] = {
    "filtering.KalmanKernels": "a NamedTuple of compiled kernels built by kalman_kernels, which "
                               "validates the state size",
}


def test_table_covers_every_public_callable():
    TABLE.check_coverage({"filtering": filtering}, EXEMPT)


