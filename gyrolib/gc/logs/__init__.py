"""Paper GC's method used on recorded logs: the record, the calibration, the noise fit, the
inclinometer convention and the Allan deviation.

Every name is re-exported by :mod:`gyrolib.gc`; the table there maps the paper's equations
and figures to these modules.
"""
from gyrolib.gc.logs.allan import (
    AllanDeviation,
    AllanSeries,
    allan_deviation,
    allan_model_vibration,
    allan_noise_terms,
)
from gyrolib.gc.logs.calibration import (
    EARTH_RATE_TOLERANCE,
    CalibrationResult,
    SimulatedRecord,
    calibrate,
    earth_rate_mismatch,
    innovation_log_likelihood,
    simulate_record,
    simulate_records,
)
from gyrolib.gc.logs.convention import (
    ConventionStudy,
    InclinometerMapping,
    convention_study,
)
from gyrolib.gc.logs.judgement import evidence_codes, judge_record
from gyrolib.gc.logs.noise_fit import (
    NOISE_FIT_NAMES,
    NoiseFit,
    fit_checks,
    fit_noise,
    fit_uncertainty,
    profile_intervals,
)
from gyrolib.gc.logs.record import (
    MEASUREMENT_COLUMNS,
    GCRecord,
)
from gyrolib.gc.logs.site import equator_note, latitude_drift_shift, latitude_drift_sigma

__all__ = [
    "EARTH_RATE_TOLERANCE",
    "MEASUREMENT_COLUMNS",
    "NOISE_FIT_NAMES",
    "AllanDeviation",
    "AllanSeries",
    "CalibrationResult",
    "ConventionStudy",
    "GCRecord",
    "InclinometerMapping",
    "NoiseFit",
    "SimulatedRecord",
    "allan_deviation",
    "allan_model_vibration",
    "allan_noise_terms",
    "calibrate",
    "convention_study",
    "earth_rate_mismatch",
    "equator_note",
    "evidence_codes",
    "fit_checks",
    "fit_noise",
    "fit_uncertainty",
    "innovation_log_likelihood",
    "judge_record",
    "latitude_drift_shift",
    "latitude_drift_sigma",
    "profile_intervals",
    "simulate_record",
    "simulate_records",
]
