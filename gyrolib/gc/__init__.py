"""Paper GC: calibration of a floated gyro's systematic drift in gyrocompass mode with a
10-state Kalman filter.

======================  ===============================================================
module                  paper GC
======================  ===============================================================
``params``              :class:`GyrocompassParams` (all parameters, SI), the state vector
``nominal``             Eq. (4): :func:`nominal_motion`
``state_space``         Eqs. (5)–(8): :func:`system_matrix`, :func:`measurement_matrix`, …
``shaping_filters``     Eqs. (6), (7): :func:`vibration_filter`, :func:`random_drift_filter`
``symbolic``            Eqs. (1)–(8) derived with sympy (``gc.symbolic``)
``discretization``      the filter's discrete model: :func:`discretize`
``covariance``          Figure 3: :func:`covariance_analysis`, :func:`time_to_sigma`
``montecarlo``          Figure 4: :func:`monte_carlo`
``budget``              :func:`error_budget` (σ of ω_gc by source)
``observability``       :func:`information_psi_omega` (how ψ and ω_gc separate)
``claims``              the speed-claim map and the shaping-filter sweep
``sobol``               Sobol' indices of σ_gc(100 s) and t_c: :func:`sensitivity`
``record``              :class:`GCRecord`, a recorded log the calibration reads (SI)
``calibration``         the filter on a recorded log: :func:`calibrate`
``plots``               the figures: ``plot_*``
======================  ===============================================================

Use as ``from gyrolib import gc`` then ``gc.covariance_analysis(gc.GyrocompassParams())``.
"""

from gyrolib.gc import symbolic
from gyrolib.gc.budget import (
    BUDGET_SOURCES,
    ErrorBudget,
    error_budget,
)
from gyrolib.gc.covariance import (
    CovarianceAnalysis,
    CovarianceSweep,
    covariance_analysis,
    parameter_grid,
    sweep_covariance,
    sweep_sigma_gc,
    time_to_sigma,
)
from gyrolib.gc.discretization import (
    DISCRETIZATIONS,
    SEGMENT,
    GCDiscretization,
    discretize,
    nominal_half_steps,
)
from gyrolib.gc.montecarlo import (
    MonteCarloResult,
    monte_carlo,
    simulate_truth,
)
from gyrolib.gc.nominal import (
    NominalMotion,
    nominal_motion,
    nominal_motion_aperiodic,
    nominal_motion_reference,
)
from gyrolib.gc.observability import (
    InformationPsiOmega,
    information_psi_omega,
)
from gyrolib.gc.params import (
    MEASUREMENT_NAMES,
    NOISE_NAMES,
    STATE_NAMES,
    GyrocompassParams,
    normal_gravity,
    state_index,
)
from gyrolib.gc.plots import (
    plot_consistency,
    plot_error_budget,
    plot_estimates,
    plot_figure1,
    plot_information,
    plot_nominal_motion,
    plot_p0_scale,
    plot_shaping_psd,
    plot_sigma_history,
    plot_sweep,
)
from gyrolib.gc.shaping_filters import (
    ShapingFilter,
    mean_square_standard_error,
    psd,
    psd_integral,
    psd_two_sided,
    random_drift_filter,
    simulate_shaping_filter,
    stationary_covariance,
    vibration_filter,
)
from gyrolib.gc.state_space import (
    initial_covariance,
    measurement_matrix,
    measurement_noise_covariance,
    measurement_noise_intensity,
    noise_input_matrix,
    process_noise_intensity,
    system_matrix,
)

__all__ = [
    "BUDGET_SOURCES",
    "DISCRETIZATIONS",
    "MEASUREMENT_NAMES",
    "NOISE_NAMES",
    "SEGMENT",
    "STATE_NAMES",
    "CovarianceAnalysis",
    "CovarianceSweep",
    "ErrorBudget",
    "GCDiscretization",
    "GyrocompassParams",
    "InformationPsiOmega",
    "MonteCarloResult",
    "NominalMotion",
    "ShapingFilter",
    "covariance_analysis",
    "discretize",
    "error_budget",
    "information_psi_omega",
    "initial_covariance",
    "mean_square_standard_error",
    "measurement_matrix",
    "measurement_noise_covariance",
    "measurement_noise_intensity",
    "monte_carlo",
    "noise_input_matrix",
    "nominal_half_steps",
    "nominal_motion",
    "nominal_motion_aperiodic",
    "nominal_motion_reference",
    "normal_gravity",
    "parameter_grid",
    "plot_consistency",
    "plot_error_budget",
    "plot_estimates",
    "plot_figure1",
    "plot_information",
    "plot_nominal_motion",
    "plot_p0_scale",
    "plot_shaping_psd",
    "plot_sigma_history",
    "plot_sweep",
    "process_noise_intensity",
    "psd",
    "psd_integral",
    "psd_two_sided",
    "random_drift_filter",
    "simulate_shaping_filter",
    "simulate_truth",
    "state_index",
    "stationary_covariance",
    "sweep_covariance",
    "sweep_sigma_gc",
    "symbolic",
    "system_matrix",
    "time_to_sigma",
    "vibration_filter",
]

# Paper GC's claims, computed (gc.claims), and the claims chapter's figures; calibration on
# recorded data (issue 13)
from gyrolib.gc.calibration import (
    CalibrationResult,
    SimulatedRecord,
    calibrate,
    plot_calibration,
    simulate_record,
)
from gyrolib.gc.claims import (
    SHAPING_FIELDS,
    ClaimBoundary,
    ShapingSweep,
    SpeedClaimMap,
    claim_boundary,
    shaping_sweep,
    speed_claim_map,
    time_to_level,
)
from gyrolib.gc.plots import plot_mismatch, plot_speed_claim
from gyrolib.gc.record import GCRecord

# Global sensitivity of sigma_gc(100 s) and t_c (issue 19)
from gyrolib.gc.sobol import (
    SENSITIVITY_OUTPUTS,
    recheck_sensitivity,
    sensitivity,
    sensitivity_inputs,
    sensitivity_outputs,
)

__all__ += [
    "SHAPING_FIELDS",
    "ClaimBoundary",
    "ShapingSweep",
    "SpeedClaimMap",
    "claim_boundary",
    "plot_mismatch",
    "plot_speed_claim",
    "shaping_sweep",
    "speed_claim_map",
    "time_to_level",
]
__all__ += ["CalibrationResult", "GCRecord", "SimulatedRecord", "calibrate",
            "plot_calibration", "simulate_record"]
__all__ += ["SENSITIVITY_OUTPUTS", "recheck_sensitivity", "sensitivity", "sensitivity_inputs",
            "sensitivity_outputs"]
