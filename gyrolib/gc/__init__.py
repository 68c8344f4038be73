"""Paper GC: calibration of a floated gyro's systematic drift in gyrocompass mode with a
10-state Kalman filter.

The package has four rooms, one per role, and one module of figures:

=================  ===========================================================================
subpackage         what it holds
=================  ===========================================================================
``gc.model``       the paper's model: parameters, Eqs. (1)–(8), shaping filters, the discrete
                   filter model, and their sympy derivation (``gc.symbolic``)
``gc.analysis``    what the paper's Figures 3 and 4 and its claims rest on
``gc.racing``      the race against the rate-sensor method of ref. [3], which GC replaces
``gc.logs``        the method used on a recorded log
``gc.plots``       every figure (``plot_*``; matplotlib, loaded on first use)
=================  ===========================================================================

Where each of paper GC's equations and figures lives:

=======================  ======================================  ============================
paper GC                 function                                module
=======================  ======================================  ============================
Eq. (1)                  :func:`gyroscopic_torque`               ``gc.model.equations``
Eq. (2)                  :func:`vertical_rate`                   ``gc.model.equations``
Eq. (3)                  :func:`float_acceleration`              ``gc.model.equations``
Eq. (4)                  :func:`nominal_motion`                  ``gc.model.nominal``
Eq. (5)                  :func:`linearized_acceleration`         ``gc.model.equations``
Eq. (6)                  :func:`vibration_filter`                ``gc.model.shaping_filters``
Eq. (7)                  :func:`random_drift_filter`             ``gc.model.shaping_filters``
Eq. (8)                  :func:`system_matrix`,                  ``gc.model.state_space``
                         :func:`measurement_matrix`, …,
                         :func:`continuous_model`
Eqs. (1)–(8), symbolic   ``gc.symbolic``                         ``gc.model.symbolic``
parameters, state        :class:`GyrocompassParams`              ``gc.model.params``
instrument errors        :data:`TERMS`, :func:`state_names`      ``gc.model.instrument``
Δt = 0.001 s model       :func:`discretize`                      ``gc.model.discretization``
Figure 1                 :func:`plot_figure1`                    ``gc.plots``
Figure 2                 :func:`psd`, :func:`plot_shaping_psd`   ``gc.model.shaping_filters``
Figure 3, σ = 0.0011″/s  :func:`covariance_analysis`,            ``gc.analysis.covariance``
                         :func:`time_to_sigma`
Figure 4                 :func:`monte_carlo`                     ``gc.analysis.montecarlo``
σ by source              :func:`error_budget`                    ``gc.analysis.budget``
how ψ and ω_gc separate  :func:`information_psi_omega`           ``gc.analysis.observability``
linearizing Eq. (3)      :func:`linearization_effect`            ``gc.analysis.linearization``
"> 50 % faster"          :func:`speed_claim_map`,                ``gc.analysis.speed_claim``
                         :func:`shaping_sweep`
Sobol' indices           :func:`sensitivity`                     ``gc.analysis.sensitivity_study``
ref. [3]'s method        :func:`rate_sensor_model`,              ``gc.racing.rate_sensor``
                         :class:`RateSensorProcedure`
the race                 :func:`race`, :func:`race_sweep`        ``gc.racing.comparison``
a recorded log           :class:`GCRecord`                       ``gc.logs.record``
calibration on a log     :func:`calibrate`                       ``gc.logs.calibration``
its verdict on a log     :func:`judge_record`                    ``gc.logs.judgement``
the site's latitude      :func:`latitude_drift_sigma`            ``gc.logs.site``
noise fitted to a log    :func:`fit_noise`                       ``gc.logs.noise_fit``
which column is δ, γ     :class:`InclinometerMapping`            ``gc.logs.convention``
Allan deviation          :func:`allan_deviation`                 ``gc.logs.allan``
=======================  ======================================  ============================

Use as ``from gyrolib import gc`` then ``gc.covariance_analysis(gc.GyrocompassParams())``.
"""

import gyrolib.gc.model as _model
from gyrolib.gc.analysis import (
    BUDGET_SOURCES,
    SENSITIVITY_OUTPUTS,
    SHAPING_FIELDS,
    ClaimBoundary,
    CovarianceAnalysis,
    CovarianceSweep,
    ErrorBudget,
    InformationPsiOmega,
    LinearizationEffect,
    MonteCarloResult,
    MonteCarloSummary,
    ShapingSweep,
    SpeedClaimMap,
    claim_boundary,
    covariance_analysis,
    error_budget,
    information_psi_omega,
    linearization_effect,
    monte_carlo,
    parameter_grid,
    psi_for_drift,
    recheck_sensitivity,
    remainder_drift,
    run_streams,
    sensitivity,
    sensitivity_elasticities,
    sensitivity_inputs,
    sensitivity_outputs,
    shaping_sweep,
    simulate_truth,
    speed_claim_map,
    sweep_covariance,
    sweep_sigma_gc,
    time_to_level,
    time_to_sigma,
    truth_prior_factor,
)
from gyrolib.gc.logs import (
    EARTH_RATE_TOLERANCE,
    MEASUREMENT_COLUMNS,
    NOISE_FIT_NAMES,
    AllanDeviation,
    AllanSeries,
    CalibrationResult,
    ConventionStudy,
    GCRecord,
    InclinometerMapping,
    NoiseFit,
    SimulatedRecord,
    allan_deviation,
    allan_model_vibration,
    allan_noise_terms,
    calibrate,
    convention_study,
    earth_rate_mismatch,
    equator_note,
    evidence_codes,
    fit_checks,
    fit_noise,
    fit_uncertainty,
    innovation_log_likelihood,
    judge_record,
    latitude_drift_shift,
    latitude_drift_sigma,
    profile_intervals,
    simulate_record,
    simulate_records,
)
from gyrolib.gc.model import (
    DISCRETIZATIONS,
    F87_READINGS,
    MEASUREMENT_NAMES,
    NOISE_NAMES,
    SEGMENT,
    STATE_NAMES,
    TERMS,
    ContinuousModel,
    GCDiscretization,
    GyrocompassParams,
    InstrumentModel,
    InstrumentTerm,
    NominalIntegrator,
    NominalMotion,
    ShapingFilter,
    continuous_model,
    discretize,
    float_acceleration,
    gyroscopic_torque,
    initial_covariance,
    instrument_model,
    linearized_acceleration,
    mean_square_standard_error,
    measurement_matrix,
    measurement_noise_covariance,
    measurement_noise_intensity,
    noise_input_matrix,
    nominal_half_steps,
    nominal_motion,
    nominal_motion_aperiodic,
    nominal_motion_reference,
    normal_gravity,
    process_noise_intensity,
    psd,
    psd_integral,
    psd_two_sided,
    random_drift_filter,
    simulate_shaping_filter,
    state_index,
    state_names,
    stationary_covariance,
    system_matrix,
    system_matrix_parts,
    vertical_rate,
    vibration_filter,
)
from gyrolib.gc.racing import (
    PROCEDURE_TARGETS,
    RACE_RANGES,
    RS_STATE_NAMES,
    VIBRATION_FRAMES,
    OptimalRun,
    RaceConditions,
    RaceResult,
    RaceSweep,
    RaceVerdictGrid,
    RateSensorModel,
    RateSensorMonteCarlo,
    RateSensorProcedure,
    procedure_for_time,
    race,
    race_margin,
    race_sweep,
    race_verdict_grid,
    rate_sensor_model,
    rate_sensor_monte_carlo,
    turn_accuracy_limit,
)

#: The names of ``gc.plots`` re-exported here (loaded on first use: matplotlib is about 1 s
#: and 60 MB that the command line and the numerical functions never need).
_PLOTS = frozenset({
    "plot_allan",
    "plot_calibration",
    "plot_consistency",
    "plot_convention_study",
    "plot_error_budget",
    "plot_estimates",
    "plot_figure1",
    "plot_information",
    "plot_linearization",
    "plot_mismatch",
    "plot_nominal_motion",
    "plot_p0_scale",
    "plot_race",
    "plot_race_sweep",
    "plot_race_verdict",
    "plot_shaping_psd",
    "plot_sigma_history",
    "plot_speed_claim",
    "plot_sweep",
})

__all__ = [
    "BUDGET_SOURCES",
    "DISCRETIZATIONS",
    "EARTH_RATE_TOLERANCE",
    "F87_READINGS",
    "MEASUREMENT_COLUMNS",
    "MEASUREMENT_NAMES",
    "NOISE_FIT_NAMES",
    "NOISE_NAMES",
    "PROCEDURE_TARGETS",
    "RACE_RANGES",
    "RS_STATE_NAMES",
    "SEGMENT",
    "SENSITIVITY_OUTPUTS",
    "SHAPING_FIELDS",
    "STATE_NAMES",
    "TERMS",
    "VIBRATION_FRAMES",
    "AllanDeviation",
    "AllanSeries",
    "CalibrationResult",
    "ClaimBoundary",
    "ContinuousModel",
    "ConventionStudy",
    "CovarianceAnalysis",
    "CovarianceSweep",
    "ErrorBudget",
    "GCDiscretization",
    "GCRecord",
    "GyrocompassParams",
    "InclinometerMapping",
    "InformationPsiOmega",
    "InstrumentModel",
    "InstrumentTerm",
    "LinearizationEffect",
    "MonteCarloResult",
    "MonteCarloSummary",
    "NoiseFit",
    "NominalIntegrator",
    "NominalMotion",
    "OptimalRun",
    "RaceConditions",
    "RaceResult",
    "RaceSweep",
    "RaceVerdictGrid",
    "RateSensorModel",
    "RateSensorMonteCarlo",
    "RateSensorProcedure",
    "ShapingFilter",
    "ShapingSweep",
    "SimulatedRecord",
    "SpeedClaimMap",
    "allan_deviation",
    "allan_model_vibration",
    "allan_noise_terms",
    "calibrate",
    "claim_boundary",
    "continuous_model",
    "convention_study",
    "covariance_analysis",
    "discretize",
    "earth_rate_mismatch",
    "equator_note",
    "error_budget",
    "evidence_codes",
    "fit_checks",
    "fit_noise",
    "fit_uncertainty",
    "float_acceleration",
    "gyroscopic_torque",
    "information_psi_omega",
    "initial_covariance",
    "innovation_log_likelihood",
    "instrument_model",
    "judge_record",
    "latitude_drift_shift",
    "latitude_drift_sigma",
    "linearization_effect",
    "linearized_acceleration",
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
    "plot_calibration",
    "plot_consistency",
    "plot_convention_study",
    "plot_error_budget",
    "plot_estimates",
    "plot_figure1",
    "plot_information",
    "plot_linearization",
    "plot_mismatch",
    "plot_nominal_motion",
    "plot_p0_scale",
    "plot_race",
    "plot_race_sweep",
    "plot_race_verdict",
    "plot_shaping_psd",
    "plot_sigma_history",
    "plot_speed_claim",
    "plot_sweep",
    "procedure_for_time",
    "process_noise_intensity",
    "profile_intervals",
    "psd",
    "psd_integral",
    "psd_two_sided",
    "psi_for_drift",
    "race",
    "race_margin",
    "race_sweep",
    "race_verdict_grid",
    "random_drift_filter",
    "rate_sensor_model",
    "rate_sensor_monte_carlo",
    "recheck_sensitivity",
    "remainder_drift",
    "run_streams",
    "sensitivity",
    "sensitivity_elasticities",
    "sensitivity_inputs",
    "sensitivity_outputs",
    "shaping_sweep",
    "simulate_record",
    "simulate_records",
    "simulate_shaping_filter",
    "simulate_truth",
    "speed_claim_map",
    "state_index",
    "state_names",
    "stationary_covariance",
    "sweep_covariance",
    "sweep_sigma_gc",
    "symbolic",
    "system_matrix",
    "system_matrix_parts",
    "time_to_level",
    "time_to_sigma",
    "truth_prior_factor",
    "turn_accuracy_limit",
    "vertical_rate",
    "vibration_filter",
]


def __getattr__(name: str):
    """``gc.symbolic`` (sympy, from :mod:`gyrolib.gc.model`, which loads it on first use),
    ``gc.plots`` and its ``gc.plot_*``, imported on first access (an ``import`` statement:
    ``from gyrolib.gc import plots`` would look the name up here first, and recurse)."""
    if name == "symbolic":
        return _model.symbolic
    if name == "plots" or name in _PLOTS:
        import gyrolib.gc.plots as plots  # start-up: matplotlib, about 1 s

        if name == "plots":
            return plots
        value = getattr(plots, name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
