"""A gyro's (or a clock's) plain log for its Allan deviation, read through the same reader as
every record (:mod:`gyrolib.records.reader`: units rows, decimal commas, ISO time stamps,
gzip, tabs, ``#`` comments, a byte-order mark, ``columns=`` mapping, unit options).

The log holds one series, ``rate`` (a rate: rad/s, deg/s, deg/h, or ``1`` for a clock's
fractional frequency) or ``phase`` (its integral: rad, deg, or s for a clock's time error),
with a time column ``t`` or at a stated sample rate (no time column, as allantools and
Stable32 read a series).  Rows whose value is missing are dropped and counted, and the
series is read as contiguous.  A time column must step evenly (within 1 % of its median
step), and, for a gyro's rate log read without a stated time unit, must not fit
milliseconds or microseconds (:func:`gyrolib.records.plausibility.check_rate_log`).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from typing import Final

import numpy as np

from gyrolib import _validation as v
from gyrolib._repr import compact_repr
from gyrolib.records.errors import RecordError
from gyrolib.records.plausibility import check_rate_log
from gyrolib.records.reader import RecordInfo, read_csv

__all__ = ["PHASE_UNITS", "RATE_UNITS", "RateLog", "read_rate_log"]

#: Units a rate column may be in (``1``: a clock's fractional frequency).
RATE_UNITS: Final[tuple[str, ...]] = ("rad/s", "deg/s", "deg/h", "1")

#: The unit of a phase column for each rate unit (its integral over time).
PHASE_UNITS: Final[dict[str, str]] = {"rad/s": "rad", "deg/s": "deg", "1": "s"}

#: Largest departure of a step from the median step (relative) of an evenly sampled log.
EVEN_STEPS: Final[float] = 0.01


@compact_repr
@dataclasses.dataclass(frozen=True)
class RateLog:
    """One evenly sampled series read from a file: ``values`` (SI: rad/s or 1 for a rate,
    rad or s for a phase; rows with a missing value dropped), ``kind`` ``"rate"`` or
    ``"phase"``, ``sample_rate`` (Hz), ``rows`` the data rows read, ``dropped`` those with
    a missing value, ``rate_given`` whether the rate was stated (no time column read),
    ``info`` how the file was read."""

    values: np.ndarray
    kind: str
    sample_rate: float
    rows: int
    dropped: int
    rate_given: bool
    info: RecordInfo | None

    @property
    def dt(self) -> float:
        """The sample interval (s)."""
        return 1.0 / self.sample_rate

    @property
    def notes(self) -> list[str]:
        """How the file was read: the reader's notes, and the rows dropped."""
        out = list(self.info.notes) if self.info is not None else []
        if self.dropped:
            out.append(f"{self.dropped} of {self.rows} rows with a missing {self.kind} value "
                       "dropped (the series read as contiguous: each shifts the later "
                       "samples by one step)")
        return out


def read_rate_log(path: object, *, sample_rate: float | None = None, phase: bool = False,
                  unit: str = "rad/s", time_unit: str | None = None,
                  columns: Mapping[str, str] | None = None,
                  decimal_comma: bool | None = None) -> RateLog:
    """Read a rate (or, with ``phase``, a phase) log for its Allan deviation.

    Parameters
    ----------
    path : str or path
        The CSV file (``.csv.gz`` too), in any format :mod:`gyrolib.records.reader` reads.
    sample_rate : float, optional
        The sample rate (Hz) of a log read without a time column; default: the log's
        ``t`` column (s), which must step evenly.
    phase : bool
        The column is ``phase`` (the rate's integral), not ``rate``.
    unit : {"rad/s", "deg/s", "deg/h", "1"}
        The rate's unit (a phase is in its integral's: rad, deg, or s for ``1``).
    time_unit : {"s", "ms", "us", "µs"}, optional
        The time column's unit; when not given, a gyro's log whose steps fit ms or µs is
        refused (:func:`~gyrolib.records.plausibility.check_rate_log`).
    columns : mapping, optional
        The file's header names of ``t``, ``rate``, ``phase``.
    decimal_comma : bool, optional
        As :func:`gyrolib.records.read_csv` (default: detected).

    Raises
    ------
    RecordError
        Naming the file, row and column (as the reader does), or the steps.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "r.csv"
    >>> rows = [f"{k / 100:.2f};{k % 3}.5".replace(".", ",") for k in range(20)]
    >>> rows[4] = "0,04;nan"                     # a missing value: dropped, counted
    >>> _ = p.write_text("t;rate\\n" + "\\n".join(rows) + "\\n")
    >>> log = read_rate_log(p, unit="deg/s")
    >>> log.sample_rate, log.rows, log.dropped
    (100.0, 20, 1)
    """
    v.check_choice("unit", unit, RATE_UNITS)
    phase = v.check_bool("phase", phase)
    if phase and unit not in PHASE_UNITS:
        raise ValueError(f"unit: a phase log's rate unit must be one of "
                         f"{', '.join(PHASE_UNITS)}; got {unit!r}")
    if sample_rate is not None:
        sample_rate = v.check_positive("sample_rate", sample_rate)
    kind = "phase" if phase else "rate"
    label = str(path)
    value_unit = PHASE_UNITS[unit] if phase else unit
    units = {kind: value_unit, "time": time_unit}
    required = [kind] if sample_rate is not None else ["t", kind]
    _, data, info = read_csv(path, required, columns=columns, units=units,
                             decimal_comma=decimal_comma, return_info=True)
    x = data[:, -1]
    rows = int(x.size)
    if sample_rate is None:
        t = data[:, 0]
        if time_unit is None and unit != "1":
            check_rate_log(t, label=label)
        sample_rate = 1.0 / _even_step(t, label)
    known = np.isfinite(x)
    x = x[known]
    if x.size < 10:
        raise RecordError(label, f"expected at least 10 rows with a {kind} value; got "
                          f"{x.size} of {rows}", column=kind)
    return RateLog(values=x, kind=kind, sample_rate=float(sample_rate), rows=rows,
                   dropped=rows - int(x.size), rate_given=len(required) == 1, info=info)


def _even_step(t: np.ndarray, label: str) -> float:
    """The median step of ``t`` (s), every step within :data:`EVEN_STEPS` of it."""
    if t.size < 2:
        raise RecordError(label, "expected at least 10 rows", column="t")
    h = np.diff(t)
    dt = float(np.median(h))
    off = np.abs(h - dt) > EVEN_STEPS * dt
    if not dt > 0 or np.any(off):
        r = int(np.flatnonzero(off)[0]) + 2 if np.any(off) else 2
        raise RecordError(label, f"t must increase in even steps (within "
                          f"{100 * EVEN_STEPS:g} % of the median step {dt:g} s); data row "
                          f"{r} steps {float(h[r - 2]):g} s (gaps are not read: give a "
                          "stretch without one, or --rate HZ to read the values as "
                          "contiguous)", column="t")
    if not math.isfinite(dt):
        raise RecordError(label, "expected finite time stamps", column="t")
    return dt
