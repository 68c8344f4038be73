"""Paper RSF: in-flight correction of a roll gyro's scale factor by a MEMS indicator
gyrostabilizer (GS).

=====================  ===================================================================
module                 paper RSF
=====================  ===================================================================
``sensors``            the sensors' data (Table 1, GS gyro, encoder): :class:`RollGyroSpec`, …
``equations``          Eqs. (1)–(9): :func:`sf_error_estimate`, :func:`delta_k`, …
``tables``             the paper's Tables 2 and 3: :func:`table2`, :func:`table3`
``simulation``         a seeded flight simulation: :func:`simulate_flight`
``correction``         Eqs. (1)–(3): :func:`run_correction` (simulation), :func:`predict_delta_k`
``sweeps``             the correction against its period, the encoder and the roll rate
``claims``             the paper's verbal claims and their conditions: :func:`compensation_share`
``sensitivity_study``  Sobol' indices of δK and the share removed: :func:`sensitivity`
``record``             :class:`RSFRecord`, a recorded log the correction reads (SI)
``calibration``        the correction on a recorded log: :func:`calibrate`
``judgement``          its verdict on a recorded log: :func:`judge_record`
``uncertainty``        σ of the mean ε̂1 with its systematic parts: :func:`eps1_uncertainty`
``plots``              the figures: ``plot_*`` (matplotlib, loaded on first use)
=====================  ===================================================================

Use as ``from gyrolib import rsf`` then ``rsf.table2()``.
"""

from gyrolib.rsf.claims import (
    SLIP_FACTORS,
    CompensationShare,
    FlightShares,
    GsVsSins,
    SlipSearch,
    compensation_share,
    drz_hypotheses,
    drz_slip_search,
    flight_shares,
    gs_vs_sins,
)
from gyrolib.rsf.correction import (
    CorrectionRun,
    DeltaKPrediction,
    predict_delta_k,
    run_correction,
)
from gyrolib.rsf.equations import (
    K_FORMS,
    corrected_rate,
    correction_coefficient,
    delta_k,
    delta_k_ideal,
    difference_error,
    fraction_compensated,
    gs_bias_total,
    gs_roll_error_ideal,
    gs_roll_error_nonideal,
    gyro_output,
    k_true,
    lateral_acceleration_error,
    lateral_deviation_cubic,
    lateral_deviation_exact,
    relative_k_error,
    residual_sf_error,
    roll_difference,
    sf_error_estimate,
    sins_roll_error,
    vertical_deviation_exact,
)
from gyrolib.rsf.sensors import (
    AEDB9340,
    GYPRO4300,
    SIIMU02_ROLL,
    EncoderSpec,
    MemsGyroSpec,
    RollGyroSpec,
)
from gyrolib.rsf.simulation import (
    ERROR_MODES,
    EncoderModel,
    GsModel,
    RollProfile,
    SensorRecord,
    SimulationConfig,
    SinsGyroModel,
    encoder_counts,
    gs_angle,
    lateral_error,
    simulate_flight,
    unwrap_counts,
    with_encoder,
)
from gyrolib.rsf.sweeps import (
    PeriodSweep,
    RateSweep,
    ResolutionSweep,
    sweep_correction_period,
    sweep_encoder,
    sweep_roll_rate,
)
from gyrolib.rsf.tables import (
    TABLE2_OMEGA,
    WORKED_EXAMPLE_OMEGA_UNC,
    WORKED_EXAMPLE_OMEGA_X,
    WORKED_EXAMPLE_PERIOD,
    DeltaKTerms,
    Table2,
    Table3,
    WorkedExample,
    table2,
    table3,
    worked_example_delta_k,
    worked_example_terms,
)

__all__ = [
    "AEDB9340",
    "ERROR_MODES",
    "GYPRO4300",
    "K_FORMS",
    "SIIMU02_ROLL",
    "SLIP_FACTORS",
    "TABLE2_OMEGA",
    "WORKED_EXAMPLE_OMEGA_UNC",
    "WORKED_EXAMPLE_OMEGA_X",
    "WORKED_EXAMPLE_PERIOD",
    "CompensationShare",
    "CorrectionRun",
    "DeltaKPrediction",
    "DeltaKTerms",
    "EncoderModel",
    "EncoderSpec",
    "FlightShares",
    "GsModel",
    "GsVsSins",
    "MemsGyroSpec",
    "PeriodSweep",
    "RateSweep",
    "ResolutionSweep",
    "RollGyroSpec",
    "RollProfile",
    "SensorRecord",
    "SimulationConfig",
    "SinsGyroModel",
    "SlipSearch",
    "Table2",
    "Table3",
    "WorkedExample",
    "compensation_share",
    "corrected_rate",
    "correction_coefficient",
    "delta_k",
    "delta_k_ideal",
    "difference_error",
    "drz_hypotheses",
    "drz_slip_search",
    "encoder_counts",
    "flight_shares",
    "fraction_compensated",
    "gs_angle",
    "gs_bias_total",
    "gs_roll_error_ideal",
    "gs_roll_error_nonideal",
    "gs_vs_sins",
    "gyro_output",
    "k_true",
    "lateral_acceleration_error",
    "lateral_deviation_cubic",
    "lateral_deviation_exact",
    "lateral_error",
    "plot_compensation_share",
    "plot_delta_k_distribution",
    "plot_encoder_sweep",
    "plot_figure3",
    "plot_flight",
    "plot_gs_scheme",
    "plot_method_scheme",
    "plot_period_sweep",
    "plot_rate_sweep",
    "plot_spin_up",
    "predict_delta_k",
    "relative_k_error",
    "residual_sf_error",
    "roll_difference",
    "run_correction",
    "sf_error_estimate",
    "simulate_flight",
    "sins_roll_error",
    "sweep_correction_period",
    "sweep_encoder",
    "sweep_roll_rate",
    "table2",
    "table3",
    "unwrap_counts",
    "vertical_deviation_exact",
    "with_encoder",
    "worked_example_delta_k",
    "worked_example_terms",
]

# Calibration on recorded data
from gyrolib.rsf.calibration import (
    CalibrationResult,
    calibrate,
    record_from_simulation,
)
from gyrolib.rsf.judgement import judge_record
from gyrolib.rsf.record import RSFRecord

# Global sensitivity of delta K and the share removed
from gyrolib.rsf.sensitivity_study import (
    SENSITIVITY_OUTPUTS,
    recheck_sensitivity,
    sensitivity,
    sensitivity_elasticities,
    sensitivity_inputs,
    sensitivity_outputs,
)

# The total standard uncertainty of the mean and the run's checks
from gyrolib.rsf.uncertainty import Eps1Uncertainty, eps1_uncertainty

__all__ += ["CalibrationResult", "RSFRecord", "calibrate", "judge_record",
            "plot_correction", "record_from_simulation"]
__all__ += ["Eps1Uncertainty", "eps1_uncertainty"]
__all__ += ["SENSITIVITY_OUTPUTS", "recheck_sensitivity", "sensitivity",
            "sensitivity_elasticities", "sensitivity_inputs", "sensitivity_outputs"]


# Loaded on first use (PEP 562): the figures import matplotlib, which the command line and
# the numerical functions never need.
#: The names of ``rsf.plots`` re-exported here.
_PLOTS = frozenset({
    "plot_compensation_share", "plot_correction", "plot_delta_k_distribution",
    "plot_encoder_sweep", "plot_figure3", "plot_flight", "plot_gs_scheme", "plot_method_scheme",
    "plot_period_sweep", "plot_rate_sweep", "plot_spin_up"})


def __getattr__(name: str):
    """``rsf.plots`` and its ``rsf.plot_*``, imported on first access (an ``import``
    statement: ``from gyrolib.rsf import plots`` would look the name up here first)."""
    if name == "plots" or name in _PLOTS:
        import gyrolib.rsf.plots as plots  # start-up: matplotlib, about 1 s

        if name == "plots":
            return plots
        value = getattr(plots, name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
