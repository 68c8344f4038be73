"""The race: the rate-sensor method of paper GC's ref. [3], which GC replaces, and the
comparison of the two methods' times to a target σ.

Every name is re-exported by :mod:`gyrolib.gc`; the table there maps the paper's equations
and figures to these modules.
"""
from gyrolib.gc.racing.comparison import (
    PROCEDURE_TARGETS,
    RACE_RANGES,
    RaceConditions,
    RaceResult,
    RaceSweep,
    procedure_for_time,
    race,
    race_margin,
    race_sweep,
)
from gyrolib.gc.racing.rate_sensor import (
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
from gyrolib.gc.racing.verdict_grid import RaceVerdictGrid, race_verdict_grid

__all__ = [
    "PROCEDURE_TARGETS",
    "RACE_RANGES",
    "RS_STATE_NAMES",
    "VIBRATION_FRAMES",
    "OptimalRun",
    "RaceConditions",
    "RaceResult",
    "RaceSweep",
    "RaceVerdictGrid",
    "RateSensorModel",
    "RateSensorMonteCarlo",
    "RateSensorProcedure",
    "procedure_for_time",
    "race",
    "race_margin",
    "race_sweep",
    "race_verdict_grid",
    "rate_sensor_model",
    "rate_sensor_monte_carlo",
    "turn_accuracy_limit",
]

