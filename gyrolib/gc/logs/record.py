"""Paper GC: the measurement record the calibration reads (:class:`GCRecord`).

A plain container in SI that :func:`gyrolib.gc.calibrate` accepts; :mod:`gyrolib.records`
reads it from CSV files, and any other source (a data-acquisition API, a simulation) may build
it directly.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from gyrolib import _validation as v
from gyrolib._repr import compact_repr
from gyrolib.resolution import column_step

__all__ = ["MEASUREMENT_COLUMNS", "GCRecord"]

#: The record's sensor columns, in the order of :data:`gyrolib.gc.MEASUREMENT_NAMES`.
MEASUREMENT_COLUMNS: tuple[str, ...] = ("angle_sensor", "inclinometer_y", "inclinometer_z")


@compact_repr
@dataclass(frozen=True)
class GCRecord:
    """A paper-GC measurement record (SI): time ``t`` (s, strictly increasing, >= 0; the
    feedback is switched off at t = 0 with the float at β = 0), the float angle
    ``angle_sensor`` (rad) and the specific forces ``inclinometer_y``, ``inclinometer_z``
    (m/s², Eq. (8)'s measurement model).  NaN marks a missing measurement.  ``latitude``
    (rad, optional) is where the record was made, when the file states it; the calibration
    then takes the Earth-rate components from it (:meth:`GyrocompassParams.at_latitude`).

    Examples
    --------
    >>> rec = GCRecord(t=[0.001, 0.002], angle_sensor=[0.0, 1e-6],
    ...                inclinometer_y=[0.0, 0.0], inclinometer_z=[0.0, float("nan")])
    >>> rec.n, int(rec.missing().sum())
    (2, 1)
    """

    t: np.ndarray
    angle_sensor: np.ndarray
    inclinometer_y: np.ndarray
    inclinometer_z: np.ndarray
    latitude: float | None = None

    def __post_init__(self) -> None:
        if self.latitude is not None:
            object.__setattr__(self, "latitude", v.check_in_range(
                "latitude", self.latitude, -math.pi / 2, math.pi / 2))
        t = v.check_times(self.t)
        if t[0] < 0.0:
            raise ValueError(f"t must be >= 0 (time since the feedback was switched off); "
                             f"got t[0] = {t[0]}")
        object.__setattr__(self, "t", t)
        for name in MEASUREMENT_COLUMNS:
            object.__setattr__(self, name, v.check_series(name, getattr(self, name), t.size))

    @property
    def n(self) -> int:
        """Number of rows."""
        return int(self.t.size)

    def measurements(self) -> np.ndarray:
        """``(n, 3)`` array of the three sensors, in the order of
        :data:`gyrolib.gc.MEASUREMENT_NAMES`."""
        return np.column_stack([self.angle_sensor, self.inclinometer_y, self.inclinometer_z])

    def missing(self) -> np.ndarray:
        """``(n, 3)`` boolean: which measurements are missing (NaN)."""
        return np.isnan(self.measurements())

    @functools.cached_property
    def resolution(self) -> dict[str, float]:
        """The step each sensor column's values lie on (SI: rad, m/s²), 0.0 where a column
        carries the floats' own precision (:func:`gyrolib.resolution.column_step`): an
        angle sensor counted in LSBs, or a column written to a few decimals.  Its rounding,
        ``step²/12`` a sample, adds to the sensor's measurement noise in
        :func:`gyrolib.gc.calibrate`.

        Examples
        --------
        >>> import numpy as np
        >>> rng = np.random.default_rng(1)
        >>> beta = 1e-4 * np.sin(np.arange(1, 501) * 0.01) + 3e-6 * rng.standard_normal(500)
        >>> lsb = 1e-6
        >>> rec = GCRecord(t=np.arange(1, 501) * 1e-3, angle_sensor=np.round(beta / lsb) * lsb,
        ...                inclinometer_y=beta, inclinometer_z=beta)
        >>> {k: f"{q:.3g}" for k, q in rec.resolution.items()}
        {'angle_sensor': '1e-06', 'inclinometer_y': '0', 'inclinometer_z': '0'}
        """
        return {name: column_step(getattr(self, name)) for name in MEASUREMENT_COLUMNS}
