"""The rows of the table of inputs (:mod:`gyrolib.inputs`) of the race's rival, the
rate-sensor method of paper GC's ref. [3] (:class:`~gyrolib.gc.RateSensorProcedure`),
declared beside its dataclass.

Examples
--------
>>> from gyrolib.gc.racing import inputs
>>> inputs.row("race.overhead").mode
'sum'
"""

from __future__ import annotations

from typing import Any, Final

from gyrolib import input_rows
from gyrolib.gc.racing.rate_sensor import RateSensorProcedure
from gyrolib.input_rows import Input

__all__ = ["ROWS", "row"]


def _row(*args: Any, **kw: Any) -> Input:
    return Input(*args, owner_type=RateSensorProcedure, **kw)


#: The rival's rows: its instrument, its procedure's times, the reading of its vibration.
ROWS: Final[tuple[Input, ...]] = (
    # the race's rival: the rate-sensor method of paper GC's ref. [3]
    _row("race.loop_bandwidth", "ω_b", "RateSensorProcedure", ("loop_bandwidth",),
         "uncertain", "rad/s", "the rebalance loop's bandwidth, not given by paper GC: a "
         "decade either way of the book's 10 rad/s", 0.1, 10.0),
    _row("race.rate_noise", "q_t", "RateSensorProcedure", ("rate_noise",), "uncertain",
         "rad²/s", "the torquer's white noise, not given: a decade either way of the gyro's "
         "own low-frequency drift intensity", 0.1, 10.0),
    _row("race.sigma_rot", "σ_ε", "RateSensorProcedure", ("sigma_rot",), "uncertain", "rad",
         "the turning error, not given: a decade either way of 1′", 0.1, 10.0, shown="arcmin"),
    _row("race.sigma_scale", "σ_k", "RateSensorProcedure", ("sigma_scale",), "uncertain",
         "1", "the torque sensor's scale error, not given (the reason the rival turns): a "
         "decade either way of 10⁻³", 0.1, 10.0),
    _row("race.quantization", "q", "RateSensorProcedure", ("quantization",), "uncertain",
         "rad", "the weight of one output pulse, not given: a decade either way of 0.01″",
         0.1, 10.0, shown="arcsec_paper"),
    _row("race.overhead", "T_rot + T_settle", "RateSensorProcedure", ("T_rot", "T_settle"),
         "operating", "s", "the turn and the settling after it: 10 s (a fast turn table) to "
         "60 s; paper GC's 'about 20 minutes' leaves room for more", 0.5, 3.0,
         scale="linear", mode="sum"),
    _row("race.sample_dt", "Δt_s", "RateSensorProcedure", ("sample_dt",), "operating", "s",
         "the rival's sample interval: 10 ms to 1 s", 0.1, 10.0),
    _row("race.vibration_frame", "frame of N1", "RateSensorProcedure", ("vibration_frame",),
         "reading", "—", "how sensors turned by 180° see the vibration: fixed to the "
         "carrier, or turning with the sensor", values=("carrier", "sensor")),
)

_BY_NAME: Final[dict[str, Input]] = input_rows.by_name(ROWS)


def row(name: str) -> Input:
    """The row called ``name`` (``KeyError`` naming the known rows otherwise)."""
    return input_rows.row(_BY_NAME, name)
