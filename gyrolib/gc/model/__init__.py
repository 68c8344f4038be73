"""The model of paper GC: its parameters, equations, shaping filters and the discrete
filter model.

Every name is re-exported by :mod:`gyrolib.gc`; the table there maps the paper's equations
and figures to these modules.
"""
from gyrolib.gc.model.discretization import (
    DISCRETIZATIONS,
    SEGMENT,
    GCDiscretization,
    NominalIntegrator,
    discretize,
    nominal_half_steps,
    system_matrix_parts,
)
from gyrolib.gc.model.equations import (
    float_acceleration,
    gyroscopic_torque,
    linearized_acceleration,
    vertical_rate,
)
from gyrolib.gc.model.instrument import (
    TERMS,
    InstrumentModel,
    InstrumentTerm,
    instrument_model,
    state_names,
)
from gyrolib.gc.model.nominal import (
    NominalMotion,
    nominal_motion,
    nominal_motion_aperiodic,
    nominal_motion_reference,
)
from gyrolib.gc.model.params import (
    MEASUREMENT_NAMES,
    NOISE_NAMES,
    STATE_NAMES,
    GyrocompassParams,
    normal_gravity,
    state_index,
)
from gyrolib.gc.model.shaping_filters import (
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
from gyrolib.gc.model.state_space import (
    ContinuousModel,
    continuous_model,
    initial_covariance,
    measurement_matrix,
    measurement_noise_covariance,
    measurement_noise_intensity,
    noise_input_matrix,
    process_noise_intensity,
    system_matrix,
)

__all__ = [
    "DISCRETIZATIONS",
    "F87_READINGS",
    "MEASUREMENT_NAMES",
    "NOISE_NAMES",
    "SEGMENT",
    "STATE_NAMES",
    "TERMS",
    "ContinuousModel",
    "GCDiscretization",
    "GyrocompassParams",
    "InstrumentModel",
    "InstrumentTerm",
    "NominalIntegrator",
    "NominalMotion",
    "ShapingFilter",
    "continuous_model",
    "discretize",
    "float_acceleration",
    "gyroscopic_torque",
    "initial_covariance",
    "instrument_model",
    "linearized_acceleration",
    "mean_square_standard_error",
    "measurement_matrix",
    "measurement_noise_covariance",
    "measurement_noise_intensity",
    "noise_input_matrix",
    "nominal_half_steps",
    "nominal_motion",
    "nominal_motion_aperiodic",
    "nominal_motion_reference",
    "normal_gravity",
    "process_noise_intensity",
    "psd",
    "psd_integral",
    "psd_two_sided",
    "random_drift_filter",
    "simulate_shaping_filter",
    "state_index",
    "state_names",
    "stationary_covariance",
    "symbolic",
    "system_matrix",
    "system_matrix_parts",
    "vertical_rate",
    "vibration_filter",
]


def __getattr__(name: str):
    """``symbolic`` (sympy, about 1 s to import), imported on first access."""
    if name == "symbolic":
        import gyrolib.gc.model.symbolic as symbolic  # start-up: sympy, about 1 s

        return symbolic
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
