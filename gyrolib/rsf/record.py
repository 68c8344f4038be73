"""Paper RSF: the measurement record the correction reads (:class:`RSFRecord`).

A plain container in SI that :func:`gyrolib.rsf.calibrate` accepts; :mod:`gyrolib.records`
reads it from CSV files, and any other source may build it directly.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from gyrolib import _validation as v
from gyrolib._repr import compact_repr
from gyrolib.resolution import column_step

__all__ = ["RSFRecord"]


@compact_repr
@dataclass(frozen=True)
class RSFRecord:
    """A paper-RSF record (SI): time ``t`` (s, strictly increasing), the SINS roll-angle
    increment ``sins_increment`` (rad) over the sample ending at ``t``, and either the GS roll
    angle ``gs_angle`` (rad, unwrapped, relative to t = 0) or the wrapped ``encoder_counts``
    with ``counts_per_rev`` (and, for a GS whose platform turns, ``gs_gyro_angle``: the
    integrated reading of its MEMS gyro, rad; the GS angle is encoder angle plus it, paper
    RSF Figure 2).  NaN marks a missing value.

    Examples
    --------
    >>> rec = RSFRecord(t=[0.0, 0.01, 0.02], sins_increment=[0.0, 0.157, 0.157],
    ...                 gs_angle=[0.0, 0.1569, 0.3138])
    >>> rec.n, rec.gs_angle is not None
    (3, True)
    """

    t: np.ndarray
    sins_increment: np.ndarray
    gs_angle: np.ndarray | None = None
    encoder_counts: np.ndarray | None = None
    counts_per_rev: int | None = None
    gs_gyro_angle: np.ndarray | None = None

    def __post_init__(self) -> None:
        t = v.check_times(self.t)
        object.__setattr__(self, "t", t)
        object.__setattr__(self, "sins_increment",
                           v.check_series("sins_increment", self.sins_increment, t.size))
        if (self.gs_angle is None) == (self.encoder_counts is None):
            raise ValueError("exactly one of gs_angle and encoder_counts must be given")
        if self.gs_angle is not None:
            object.__setattr__(self, "gs_angle", v.check_series("gs_angle", self.gs_angle, t.size))
            if self.counts_per_rev is not None or self.gs_gyro_angle is not None:
                raise ValueError("counts_per_rev and gs_gyro_angle go with encoder_counts, "
                                 "not gs_angle")
            return
        if self.gs_gyro_angle is not None:
            object.__setattr__(self, "gs_gyro_angle",
                               v.check_series("gs_gyro_angle", self.gs_gyro_angle, t.size))
        c = v.check_series("encoder_counts", self.encoder_counts, t.size)
        n = v.check_int("counts_per_rev", self.counts_per_rev, 2)
        ok = ~np.isnan(c)
        if np.any((c[ok] != np.round(c[ok])) | (c[ok] < 0) | (c[ok] >= n)):
            i = int(np.nonzero(ok & ((c != np.round(c)) | (c < 0) | (c >= n)))[0][0])
            raise ValueError(f"encoder_counts must be whole counts in [0, {n}) "
                             f"(counts_per_rev = {n}); got {c[i]} at row {i}")
        object.__setattr__(self, "encoder_counts", c)

    @property
    def n(self) -> int:
        return int(self.t.size)

    @functools.cached_property
    def resolution(self) -> dict[str, float]:
        """The step (rad) each angle column's values lie on, 0.0 where a column carries the
        floats' own precision (:func:`gyrolib.resolution.column_step`): ``sins_increment``
        and ``gs_angle`` or ``gs_gyro_angle``, those the record has.  ``encoder_counts`` is
        left out: its step is one count, which the encoder's own term already carries.

        Examples
        --------
        >>> import numpy as np
        >>> t = np.arange(0, 201) * 0.01
        >>> gs = np.radians(900.0) * t + 1e-5 * np.sin(7 * t)
        >>> rec = RSFRecord(t=t, sins_increment=np.round(np.diff(gs, prepend=0.0), 4),
        ...                 gs_angle=gs)
        >>> rec.resolution
        {'sins_increment': 0.0001, 'gs_angle': 0.0}
        """
        cols = ("sins_increment", "gs_angle", "gs_gyro_angle")
        return {c: column_step(getattr(self, c)) for c in cols
                if getattr(self, c) is not None}
