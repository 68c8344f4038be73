"""Paper-agnostic discretization and Kalman filtering (used by paper GC, usable on any
linear time-varying model).

==========================  ===========================================================
module                      what it holds
==========================  ===========================================================
``discretization``          :func:`van_loan` (exact Φ, Qd), :func:`van_loan_derivatives`,
                            :func:`covariance_factor`
``updates``                 :func:`joseph_update`, :func:`sequential_update`
``kernels``                 numba kernels of the fast recursions:
                            :func:`predict_state`, :func:`predict_covariance`,
                            :func:`measurement_projection`,
                            :func:`joseph_scalar_update`, :func:`kalman_kernels`
``covariance``              :class:`AffineDiscreteModel`, :func:`covariance_fast`,
                            :func:`covariance_reference`, :func:`propagate_fixed_gains`
``square_root``             :func:`covariance_square_root` (QR + Potter), an independent check
``consistency``             :func:`nees_bounds` (chi-square bands of the NEES),
                            :func:`gated_nis_moments`, :func:`gated_nis_band` (the mean
                            NIS behind a χ² gate)
==========================  ===========================================================

Use as ``from gyrolib import filtering`` then ``filtering.van_loan(F, G, Q, dt)``.
"""

from gyrolib.filtering.consistency import (
    gated_nis_band,
    gated_nis_moments,
    nees_bounds,
)
from gyrolib.filtering.covariance import (
    AffineDiscreteModel,
    CovarianceRun,
    covariance_fast,
    covariance_reference,
    propagate_fixed_gains,
)
from gyrolib.filtering.discretization import (
    covariance_factor,
    van_loan,
    van_loan_derivatives,
)
from gyrolib.filtering.kernels import (
    KalmanKernels,
    joseph_scalar_update,
    kalman_kernels,
    measurement_projection,
    predict_covariance,
    predict_state,
)
from gyrolib.filtering.square_root import (
    cholesky_semidefinite,
    covariance_square_root,
)
from gyrolib.filtering.updates import (
    joseph_update,
    sequential_update,
)

__all__ = [
    "AffineDiscreteModel",
    "CovarianceRun",
    "KalmanKernels",
    "cholesky_semidefinite",
    "covariance_factor",
    "covariance_fast",
    "covariance_reference",
    "covariance_square_root",
    "gated_nis_band",
    "gated_nis_moments",
    "joseph_scalar_update",
    "joseph_update",
    "kalman_kernels",
    "measurement_projection",
    "nees_bounds",
    "predict_covariance",
    "predict_state",
    "propagate_fixed_gains",
    "sequential_update",
    "van_loan",
    "van_loan_derivatives",
]
