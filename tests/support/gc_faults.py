"""The tests' own generator of paper-GC records with the defects of real instruments and
logs, for ``tests/cli/test_calibrate_faults.py`` and
``benchmarks/bench_calibrate_faults.py``.

The clean record is the truth model of :func:`gyrolib.gc.simulate_record` (the paper's
nonlinear Eq. (3) with the shaping filters); every defect is put in here, by this module's
own arithmetic, on the readings or on the simulated gyro, never by gyrolib:

* ``null_offset`` (arcsec): the angle sensor reads ``β + b``;
* ``gain`` (relative): the angle sensor reads ``(1 + κ) β``;
* ``hf_scale`` (relative): the gyro's ``H`` is ``(1 + κ)`` times the model's (the float
  turns ``(1 + κ)`` times faster than the model says);
* ``incl_y_bias``, ``incl_z_bias`` (mg): an inclinometer reads ``g δ + N1 + b``;
* ``late_start`` (s): the logger starts ``τ`` after the feedback is switched off, and its
  clock starts at 0 then: the record is the truth's rows after ``τ``, with ``t − τ``;
* ``drift_change`` (arcsec/s): ω_gc changes by ``Δω`` at half the record; the float then
  turns faster by ``(H/f) Δω`` after its time constant ``I/f`` (added to the reading in
  closed form, the restoring torque ``H Ω_h sin β_n Δβ`` over 50 s is below 10⁻³ of it);
* ``angle_step`` (µrad), ``incl_step`` (mg): a step in the angle sensor or in
  inclinometer_z at half the record;
* ``latitude`` (deg): the gyro at that latitude (``Ω_h = Ω_E cos φ``, ``Ω_v = Ω_E sin φ``).

:func:`damage` puts the damage of a real log on any record: a gap, missing cells and a burst
of angle-sensor outliers.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from gyrolib import gc
from gyrolib.units import ARCSEC_PAPER, G0

P = gc.GyrocompassParams()
MG = 1e-3 * G0

#: fault → (unit, sizes inside the issue's range)
FAULTS: dict[str, tuple[str, tuple[float, ...]]] = {
    "null_offset": ("arcsec", (1.0, 4.0, 10.0)),
    "gain": ("1", (1e-3,)),
    "hf_scale": ("1", (1e-3,)),
    "incl_y_bias": ("mg", (0.1, 0.5, 1.0)),
    "incl_z_bias": ("mg", (0.1, 0.5, 1.0)),
    "late_start": ("s", (0.01, 0.1, 1.0)),
    "drift_change": ("arcsec/s", (0.05, 0.5)),
    "angle_step": ("urad", (10.0,)),
    "incl_step": ("mg", (0.5,)),
}


@dataclasses.dataclass(frozen=True)
class FaultRecord:
    """A record with one defect: ``record`` (a :class:`gyrolib.gc.GCRecord`),
    ``omega_gc`` the true drift at the start (rad/s), ``omega_gc_end`` at the end,
    ``params`` the gyro simulated (its Earth rate included)."""

    record: gc.GCRecord
    omega_gc: float
    omega_gc_end: float
    params: gc.GyrocompassParams


#: The faults put on the readings of a clean record of the paper's gyro (the others change
#: the gyro simulated or the record's length).
ON_THE_READINGS = ("null_offset", "gain", "incl_y_bias", "incl_z_bias", "drift_change",
                   "angle_step", "incl_step")


def make(fault: str | None, size: float, seed: int, t_end: float = 100.0) -> FaultRecord:
    """A ``t_end`` record (1 kHz) of seed ``seed`` with ``fault`` of ``size`` (units of
    :data:`FAULTS`; ``None``: clean)."""
    params = P
    lead = 0.0
    if fault == "hf_scale":
        params = dataclasses.replace(P, H=P.H * (1.0 + size))
    elif fault == "latitude":
        params = gc.GyrocompassParams.at_latitude(math.radians(size))
    elif fault == "late_start":
        lead = size
    return _with_fault(fault, size, gc.simulate_record(params, t_end + lead, seed=seed),
                       t_end, lead)


def make_cases(cases: list[tuple[str, float]], seed: int,
               t_end: float = 100.0) -> list[FaultRecord]:
    """:func:`make`'s records of ``cases`` (pairs fault, size), case ``i`` with seed
    ``seed + i``, except that the faults put on the readings of a clean record
    (:data:`ON_THE_READINGS`) are put on records made together
    (:func:`gyrolib.gc.simulate_records` of ``seed``: case ``i`` on its record ``i``, the
    first of them the record of ``seed`` itself), for about the price of one."""
    on = [i for i, (f, _) in enumerate(cases) if f in ON_THE_READINGS]
    sims = gc.simulate_records(P, t_end, seed, max(on) + 1) if on else ()
    return [_with_fault(f, s, sims[i], t_end, 0.0) if i in on else make(f, s, seed + i, t_end)
            for i, (f, s) in enumerate(cases)]


def _with_fault(fault: str | None, size: float, sim, t_end: float,
                lead: float) -> FaultRecord:
    """``fault`` of ``size`` put on the simulated record ``sim`` (see :func:`make`)."""
    params = sim.params
    r = sim.record
    t = np.array(r.t)
    a, y, z = (np.array(c, dtype=float) for c in (r.angle_sensor, r.inclinometer_y,
                                                   r.inclinometer_z))
    w0 = sim.omega_gc
    w1 = w0
    tc = 0.5 * t_end
    after = t > tc
    if fault == "null_offset":
        a += size * ARCSEC_PAPER
    elif fault == "gain":
        a *= 1.0 + size
    elif fault == "incl_y_bias":
        y += size * MG
    elif fault == "incl_z_bias":
        z += size * MG
    elif fault == "late_start":
        keep = t > lead + 0.5 * P.dt
        t, a, y, z = t[keep] - lead, a[keep], y[keep], z[keep]
        t = np.round(t / P.dt) * P.dt          # the logger's own clock, on its grid
    elif fault == "drift_change":
        dw = size * ARCSEC_PAPER
        tau = P.I / P.f
        s = np.clip(t - tc, 0.0, None)
        a += (P.H / P.f) * dw * (s - tau * (1.0 - np.exp(-s / tau)))
        w1 = w0 + dw
    elif fault == "angle_step":
        a[after] += size * 1e-6
    elif fault == "incl_step":
        z[after] += size * MG
    elif fault not in (None, "hf_scale", "latitude"):
        raise ValueError(f"unknown fault {fault!r}")
    rec = gc.GCRecord(t=t, angle_sensor=a, inclinometer_y=y, inclinometer_z=z)
    return FaultRecord(record=rec, omega_gc=w0, omega_gc_end=w1, params=params)


def make_clean(seed: int, n: int, t_end: float = 100.0) -> tuple[FaultRecord, ...]:
    """``n`` clean records of ``t_end`` at once (:func:`gyrolib.gc.simulate_records`: the
    truth model runs them together, for about the price of one); the first is
    ``make(None, 0.0, seed, t_end)``."""
    return tuple(FaultRecord(record=sim.record, omega_gc=sim.omega_gc,
                             omega_gc_end=sim.omega_gc, params=P)
                 for sim in gc.simulate_records(P, t_end, seed, n))


def cli_params(**priors: float) -> gc.GyrocompassParams:
    """The paper's model with the priors of ``python -m gyrolib calibrate gc``'s defaults
    (scale 10⁻³, angle offset 20″, inclinometer bias 0.5 mg), each overridable."""
    base = {"sigma_hf_scale": 1e-3, "sigma_as_offset": 20.0 * ARCSEC_PAPER,
            "sigma_incl_bias": 0.5 * MG}
    return dataclasses.replace(P, **{**base, **priors})


@dataclasses.dataclass(frozen=True)
class DamagedRecord:
    """A record with the damage of a real log (:func:`damage`): ``record``, and the rows of
    it (indices into ``record``) that hold the angle-sensor outliers (``outlier_rows``) and
    the missing ``inclinometer_y`` cells (``nan_rows``)."""

    record: gc.GCRecord
    outlier_rows: np.ndarray
    nan_rows: np.ndarray


def damage(record: gc.GCRecord, seed: int, *, gap: tuple[float, float] = (40.0, 42.0),
           n_nan: int = 100, burst_at: float = 70.0, burst_n: int = 5,
           burst_size: float = 1e-3) -> DamagedRecord:
    """``record`` with the damage real logs carry, put on by this module's own arithmetic:
    the rows with ``gap[0] < t <= gap[1]`` removed (a gap), ``n_nan`` ``inclinometer_y``
    cells at random rows set to NaN, and a burst of ``burst_n`` consecutive angle-sensor
    readings from ``t > burst_at`` moved by ``± burst_size`` rad (random signs; 1 mrad is
    about 70 standard deviations of the paper's angle-sensor noise at 1 kHz, far beyond any
    gate).  Seeded by ``seed``."""
    rng = np.random.default_rng(seed + 7)
    t = np.asarray(record.t)
    a, y, z = (np.array(c, dtype=float) for c in (record.angle_sensor,
                                                   record.inclinometer_y,
                                                   record.inclinometer_z))
    keep = ~((t > gap[0]) & (t <= gap[1]))
    t, a, y, z = t[keep], a[keep], y[keep], z[keep]
    burst = np.nonzero(t > burst_at)[0][:burst_n]
    a[burst] += burst_size * rng.choice([-1.0, 1.0], burst.size)
    others = np.setdiff1d(np.arange(t.size), burst)
    nan_rows = np.sort(rng.choice(others, n_nan, replace=False))
    y[nan_rows] = np.nan
    return DamagedRecord(record=gc.GCRecord(t=t, angle_sensor=a, inclinometer_y=y,
                                            inclinometer_z=z),
                         outlier_rows=burst, nan_rows=nan_rows)
