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
``linearization``       what linearizing Eq. (3) costs: :func:`linearization_effect`
``budget``              :func:`error_budget` (σ of ω_gc by source)
``observability``       :func:`information_psi_omega` (how ψ and ω_gc separate)
``claims``              the speed-claim map and the shaping-filter sweep
``sobol``               Sobol' indices of σ_gc(100 s) and t_c: :func:`sensitivity`
``record``              :class:`GCRecord`, a recorded log the calibration reads (SI)
``calibration``         the filter on a recorded log: :func:`calibrate`
``ratesensor``          ref. [3], the method GC replaces: :class:`RateSensorProcedure`,
                        :func:`rate_sensor_model` (classical and optimal estimators),
                        :func:`rate_sensor_monte_carlo`
``racing``              the race against it: :func:`race`, :func:`race_sweep`,
                        :func:`procedure_for_time`
``noisefit``            noise parameters fitted from a record: :func:`fit_noise`
``convention``          which column is δ, which γ: :class:`InclinometerMapping`,
                        :func:`convention_study` (a wrongly wired pair, Monte Carlo)
``allan``               Allan deviation of a record's sensors: :func:`allan_deviation`
``plots``               the figures: ``plot_*``
======================  ===============================================================

Use as ``from gyrolib import gc`` then ``gc.covariance_analysis(gc.GyrocompassParams())``.
"""

from gyrolib.gc.allan import (
    AllanDeviation,
    AllanSeries,
    allan_deviation,
    allan_model_vibration,
    plot_allan,
)
from gyrolib.gc.budget import (
    BUDGET_SOURCES,
    ErrorBudget,
    error_budget,
)
from gyrolib.gc.convention import (
    ConventionStudy,
    InclinometerMapping,
    convention_study,
    plot_convention_study,
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
    NominalIntegrator,
    discretize,
    nominal_half_steps,
    system_matrix_parts,
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
from gyrolib.gc.shaping_filters import (
    F87_READINGS,
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
    "F87_READINGS",
    "MEASUREMENT_NAMES",
    "NOISE_NAMES",
    "SEGMENT",
    "STATE_NAMES",
    "AllanDeviation",
    "AllanSeries",
    "ConventionStudy",
    "CovarianceAnalysis",
    "CovarianceSweep",
    "ErrorBudget",
    "GCDiscretization",
    "GyrocompassParams",
    "InclinometerMapping",
    "InformationPsiOmega",
    "MonteCarloResult",
    "NominalIntegrator",
    "NominalMotion",
    "ShapingFilter",
    "allan_deviation",
    "allan_model_vibration",
    "convention_study",
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
    "plot_allan",
    "plot_consistency",
    "plot_convention_study",
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
    "system_matrix_parts",
    "time_to_sigma",
    "vibration_filter",
]


# Paper GC's claims, computed (gc.claims), and the claims chapter's figures; calibration on
# recorded data (issue 13)
from gyrolib.gc.calibration import (
    CalibrationResult,
    SimulatedRecord,
    calibrate,
    innovation_log_likelihood,
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
from gyrolib.gc.noisefit import NOISE_FIT_NAMES, NoiseFit, fit_noise

# The race against the rate-sensor method of ref. [3] (issue 17)
from gyrolib.gc.racing import (
    PROCEDURE_TARGETS,
    RaceConditions,
    RaceResult,
    RaceSweep,
    procedure_for_time,
    race,
    race_sweep,
)
from gyrolib.gc.ratesensor import (
    RS_STATE_NAMES,
    VIBRATION_FRAMES,
    OptimalRun,
    RateSensorModel,
    RateSensorMonteCarlo,
    RateSensorProcedure,
    rate_sensor_model,
    rate_sensor_monte_carlo,
    turn_accuracy_limit,
)
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
__all__ += [
    "NOISE_FIT_NAMES",
    "CalibrationResult",
    "GCRecord",
    "NoiseFit",
    "SimulatedRecord",
    "calibrate",
    "fit_noise",
    "innovation_log_likelihood",
    "plot_calibration",
    "simulate_record",
]

__all__ += [
    "PROCEDURE_TARGETS",
    "RS_STATE_NAMES",
    "VIBRATION_FRAMES",
    "OptimalRun",
    "RaceConditions",
    "RaceResult",
    "RaceSweep",
    "RateSensorModel",
    "RateSensorMonteCarlo",
    "RateSensorProcedure",
    "plot_race",
    "plot_race_sweep",
    "procedure_for_time",
    "race",
    "race_sweep",
    "rate_sensor_model",
    "rate_sensor_monte_carlo",
    "turn_accuracy_limit",
]

# What the filter's linearization costs against the nonlinear truth (issue 21, item 6)
from gyrolib.gc.linearization import (  # noqa: E402
    LinearizationEffect,
    linearization_effect,
    psi_for_drift,
    remainder_drift,
)
from gyrolib.gc.montecarlo import run_streams, truth_prior_factor  # noqa: E402

__all__ += ["LinearizationEffect", "linearization_effect", "plot_linearization",
            "psi_for_drift", "remainder_drift", "run_streams", "truth_prior_factor"]
__all__ += ["SENSITIVITY_OUTPUTS", "recheck_sensitivity", "sensitivity", "sensitivity_inputs",
            "sensitivity_outputs"]


# Loaded on first use (PEP 562): the figures (matplotlib) and the sympy derivation are about
# 1.5 s and 100 MB that the command line and the numerical functions never need.
#: The names of ``gc.plots`` re-exported here.
_PLOTS = frozenset({
    "plot_consistency", "plot_error_budget", "plot_estimates", "plot_figure1",
    "plot_information", "plot_linearization", "plot_mismatch", "plot_nominal_motion",
    "plot_p0_scale", "plot_race", "plot_race_sweep", "plot_shaping_psd",
    "plot_sigma_history", "plot_speed_claim", "plot_sweep"})


def __getattr__(name: str):
    """``gc.symbolic``, ``gc.plots`` and its ``gc.plot_*``, imported on first access (an
    ``import`` statement: ``from gyrolib.gc import plots`` would look the name up here
    first, and recurse)."""
    if name == "symbolic":
        import gyrolib.gc.symbolic as symbolic

        return symbolic
    if name == "plots" or name in _PLOTS:
        import gyrolib.gc.plots as plots

        if name == "plots":
            return plots
        value = getattr(plots, name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
