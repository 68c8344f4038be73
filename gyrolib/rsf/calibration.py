"""Paper RSF applied to a measurement record: the scale-factor correction of Eqs. (1)–(3)
computed from recorded SINS increments and GS angles (:func:`calibrate`), by the same
routine as the simulation's (:mod:`gyrolib.rsf.correction`); this module cuts the record
into spans and reports the result (:class:`CalibrationResult`).

Per correction interval ``i`` of length ``period`` (from the first row on):

* Eq. (1): Δγ_i = Σ SINS increments − Σ GS increments over the interval;
* Eq. (2): ε̂1_i = Δγ_i / (ω_x Δt), with ω_x Δt = Σ SINS increments (the measured turn);
* Eq. (3): K_i = 1 − ε̂1_i (``k_form="linear"``) or 1/(1 + ε̂1_i), applied to every SINS
  increment of interval ``i + 1`` (K = 1 in the first interval).

The sums run over spans between consecutive known GS angles: the GS change over a span is
the difference of its end angles (so the encoder's position and quantization errors
telescope away inside it, as they do over a whole interval) and is paired with the SINS
increments of the span's rows.  A span is used only when no row is missing inside it (no
step longer than 1.5 nominal intervals; shorter jitter is harmless, a sample's SINS
increment and GS change cover the same time whatever its length) and every row has its SINS
increment: a gap or a missing SINS increment removes the span from both sums, so the two
sides always cover the same turn.  A
missing GS angle merely joins two spans.  Wrapped encoder counts are unwrapped per sample
(the step modulo one revolution, as :func:`gyrolib.rsf.unwrap_counts`), so there a missing
count removes the two samples it touches.

**Wraps and slips.**  Over a usable span the GS change and the SINS turn agree to the
scale-factor errors (ppm to ‰ of a turn of a few degrees).  A span where they differ by a
whole number of turns (2πk, within π/8) is a wrap (a ``gs_angle`` kept in [0, 2π) or
(−π, π]) or a whole-turn slip (a lost encoder revolution): with ``slips="repair"`` (default)
the 2πk is removed and :attr:`CalibrationResult.notes` says where and how many, with
``slips="refuse"`` a :class:`ValueError` names it.  A quarter-turn slip (π/2 k: a
quadrature decoder's fault) or any other jump of more than π/4 is refused with its time: a
repair would be a guess.

**Reversals.**  The roll rate may change sign: the mean rate is reported as the mean of
|ω| per interval (:attr:`CalibrationResult.mean_rate`), and an interval whose net turn is less
than half its absolute turn is flagged in :attr:`CalibrationResult.reversal` (its ε̂1 divides
by a small net turn: ill-conditioned).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Final

import numpy as np

from gyrolib import _validation as v
from gyrolib._repr import compact_repr
from gyrolib.rsf._inputs import check_sf
from gyrolib.rsf.correction import DeltaKPrediction, correct_spans
from gyrolib.rsf.equations import K_FORMS, relative_k_error
from gyrolib.rsf.record import RSFRecord

if TYPE_CHECKING:   # matplotlib is imported where a figure is drawn (not at the CLI's start)
    pass
from gyrolib.rsf.simulation import SensorRecord, encoder_counts, gs_angle

__all__ = [
    "CalibrationResult",
    "calibrate",
    "record_from_simulation",
]


@compact_repr
@dataclass(frozen=True)
class CalibrationResult:
    """The correction of paper RSF computed on a recorded log (SI), by :func:`calibrate`:
    what a log alone can tell (no truth; the simulation's counterpart, judged against its
    truth, is :class:`gyrolib.rsf.CorrectionRun`).

    Per complete interval (n_int,): ``t_start``, ``t_end``, ``eps1_hat`` (Eq. (2)), ``k``
    (Eq. (3)), ``samples`` (samples used), ``segments`` (contiguous runs of used samples: 1
    when nothing is missing), ``rate`` (mean measured roll rate, rad/s).
    Per row (n,): ``t``, ``corrected_angle`` (∫ K ω_x dt, the corrected SINS roll angle from
    the first row, missing increments counted as 0), ``residual`` (corrected minus GS angle,
    accumulated over the usable samples only), ``residual_raw`` (the same without
    correction).  ``period``, ``k_form``, ``rows``, ``samples_used``, ``samples_skipped``
    (rows not in a usable span: missing values, steps across gaps), ``gaps`` (steps longer
    than 1.5 nominal intervals), ``gap_time`` (s without rows in them), ``dt`` (nominal
    interval, the median step).  Per interval also ``abs_rate`` (mean |ω|, rad/s: the
    absolute SINS turn over the time used) and ``reversal`` (its net turn is less than half
    its absolute turn: the roll rate reverses inside) and ``gs_gyro_turn`` (the GS gyro's
    own turn over the spans used, rad: the platform's uncompensated turn, whose scale error
    ε1,GS reads into ε̂1; ``None`` when the record has no ``gs_gyro_angle``) and
    ``counts_per_rev`` (the record's encoder counts per turn; ``None`` for a ``gs_angle``).
    ``slips_repaired`` (whole-turn jumps
    of the GS angle removed; a wrapped angle's wraps not counted) and ``notes`` (one
    sentence per wrap, slip or gap).
    """

    period: float
    k_form: str
    t_start: np.ndarray
    t_end: np.ndarray
    eps1_hat: np.ndarray
    k: np.ndarray
    samples: np.ndarray
    segments: np.ndarray
    rate: np.ndarray
    t: np.ndarray
    corrected_angle: np.ndarray
    residual: np.ndarray
    residual_raw: np.ndarray
    rows: int
    samples_used: int
    samples_skipped: int
    gaps: int
    dt: float
    abs_rate: np.ndarray | None = None
    reversal: np.ndarray | None = None
    gap_time: float = 0.0
    slips_repaired: int = 0
    notes: tuple[str, ...] = ()
    gs_gyro_turn: np.ndarray | None = None
    counts_per_rev: int | None = None

    def __post_init__(self) -> None:
        n_int = v.check_ndarray("eps1_hat", self.eps1_hat, ndim=1).size
        for name in ("t_start", "t_end", "k", "rate", "samples", "segments"):
            v.check_ndarray(name, getattr(self, name), shape=(n_int,))
        nt = v.check_ndarray("t", self.t, ndim=1).size
        for name in ("corrected_angle", "residual", "residual_raw"):
            v.check_ndarray(name, getattr(self, name), shape=(nt,))
        v.check_positive("period", self.period)
        v.check_choice("k_form", self.k_form, K_FORMS)
        v.check_positive("dt", self.dt)
        for name in ("rows", "samples_used", "samples_skipped", "gaps", "slips_repaired"):
            v.check_int(name, getattr(self, name), 0)
        if self.abs_rate is None:
            object.__setattr__(self, "abs_rate", np.abs(np.asarray(self.rate, float)))
        if self.reversal is None:
            object.__setattr__(self, "reversal", np.zeros(n_int, dtype=bool))
        v.check_ndarray("abs_rate", self.abs_rate, shape=(n_int,))
        if np.shape(self.reversal) != (n_int,):
            raise ValueError(f"reversal must have shape ({n_int},); got "
                             f"{np.shape(self.reversal)}")
        object.__setattr__(self, "reversal", np.asarray(self.reversal, dtype=bool))
        if self.gs_gyro_turn is not None:
            v.check_ndarray("gs_gyro_turn", self.gs_gyro_turn, shape=(n_int,))
        object.__setattr__(self, "notes", tuple(str(x) for x in self.notes))

    @property
    def n_intervals(self) -> int:
        return int(self.eps1_hat.size)

    @property
    def mean_rate(self) -> float:
        """Mean of |ω| over the intervals, rad/s (a roll that reverses turns at this rate,
        not at its net mean): the ``rate`` at which :func:`gyrolib.rsf.predict_delta_k`
        predicts δK for this record."""
        if self.n_intervals == 0:
            raise ValueError("mean_rate needs at least one complete interval; the result "
                             "has none")
        return float(np.mean(self.abs_rate))

    @property
    def reverses(self) -> bool:
        """Whether the roll rate changes sign (between or inside intervals)."""
        r = np.asarray(self.rate)
        return bool(np.any(self.reversal) or (np.any(r > 0) and np.any(r < 0)))

    def eps1_stats(self) -> dict:
        """ε̂1 over the intervals without a reversal inside: ``mean``, ``spread`` (the
        per-interval standard deviation: how much one interval's ε̂1 scatters), ``sem``
        (the standard error of the mean, spread/√n: exact when the intervals' errors are
        independent, an upper bound when they are the GS angle's end-point errors, which
        neighbouring intervals share with opposite signs and which cancel in the mean),
        ``lag1`` (the lag-1 autocorrelation of ε̂1: about 0 for independent errors, −½ for
        pure end-point errors, when ``sem`` is far too large), ``n`` and ``left_out``
        (intervals with a reversal).  NaN where undefined (n < 2 for the spread, n < 3
        for lag1)."""
        keep = ~np.asarray(self.reversal, bool)
        e = np.asarray(self.eps1_hat, float)[keep]
        n = int(e.size)
        spread = float(np.std(e, ddof=1)) if n > 1 else math.nan
        lag1 = math.nan
        if n > 2 and spread > 0:
            d = e - e.mean()
            lag1 = float(np.sum(d[1:] * d[:-1]) / np.sum(d * d))
        return {"mean": float(np.mean(e)) if n else math.nan, "spread": spread,
                "sem": spread / math.sqrt(n) if n > 1 else math.nan, "lag1": lag1, "n": n,
                "left_out": int(np.count_nonzero(~keep))}

    def delta_k(self, eps1: float) -> np.ndarray:
        """δK_i = K_i (1 + ε1) − 1 for a known true scale-factor error ``eps1``
        (:func:`gyrolib.rsf.relative_k_error`); ``eps1`` is checked here, at the door."""
        return np.asarray(relative_k_error(self.k, check_sf("eps1", eps1)))

    def delta_k_std(self, prediction: DeltaKPrediction) -> np.ndarray:
        """Per interval, the σ of δK that ``prediction`` (for a whole interval,
        :func:`gyrolib.rsf.predict_delta_k` at :attr:`mean_rate`) implies for the turn
        actually used: the encoder and quantization errors enter at the ends of each
        contiguous run of samples, so σ scales as ``√segments`` over the fraction of the
        interval covered."""
        v.check_instance("prediction", prediction, DeltaKPrediction)
        full = self.period / self.dt
        return prediction.std * (full / self.samples) * np.sqrt(self.segments)

    def summary(self) -> dict:
        """The result as a JSON-ready dict (SI)."""
        return {
            "period": self.period,
            "k_form": self.k_form,
            "eps1_hat": [float(x) for x in self.eps1_hat],
            "K": [float(x) for x in self.k],
            "t_start": [float(x) for x in self.t_start],
            "samples": [int(x) for x in self.samples],
            "segments": [int(x) for x in self.segments],
            "rate": [float(x) for x in self.rate],
            "eps1_hat_mean": _none(self.eps1_stats()["mean"]) if self.n_intervals else None,
            "eps1_hat_spread": _none(self.eps1_stats()["spread"]) if self.n_intervals else None,
            "eps1_hat_sem": _none(self.eps1_stats()["sem"]) if self.n_intervals else None,
            "eps1_hat_lag1": _none(self.eps1_stats()["lag1"]) if self.n_intervals else None,
            "eps1_hat_std": (float(np.std(self.eps1_hat, ddof=1)) if self.n_intervals > 1
                             else None),
            "abs_rate": [float(x) for x in self.abs_rate],
            "mean_abs_rate": float(np.mean(self.abs_rate)) if self.n_intervals else None,
            "reversal": [bool(x) for x in self.reversal],
            "gap_time": self.gap_time,
            "slips_repaired": self.slips_repaired,
            "notes": list(self.notes),
            "rows": self.rows,
            "samples_used": self.samples_used,
            "samples_skipped": self.samples_skipped,
            "gaps": self.gaps,
            "dt": self.dt,
            "residual_end": float(self.residual[-1]),
            "residual_raw_end": float(self.residual_raw[-1]),
        }


def _none(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


#: A span whose GS change and SINS turn differ by more than this (rad) has jumped.
_JUMP: Final[float] = math.pi / 4


def _jumps(gs_span: np.ndarray, sins_span: np.ndarray, t0: np.ndarray, t1: np.ndarray,
           record: RSFRecord, slips: str) -> tuple[np.ndarray, int, list[str]]:
    """The GS changes with whole-turn wraps and slips removed (or refused), the number of
    slips removed (wraps of a wrapped angle not counted) and the notes; a quarter-turn or
    other jump raises ValueError."""
    r = gs_span - sins_span
    big = np.abs(r) > _JUMP
    if not np.any(big):
        return gs_span, 0, []
    k = np.round(r / (2.0 * math.pi))
    whole = big & (k != 0) & (np.abs(r - 2.0 * math.pi * k) < math.pi / 8)
    q = np.round(r / (0.5 * math.pi))
    quarter = big & ~whole & (np.abs(r - 0.5 * math.pi * q) < math.pi / 16)
    other = big & ~whole & ~quarter
    col = "gs_angle" if record.gs_angle is not None else "the GS angle (encoder_counts)"
    for mask, what in ((quarter, "a quarter turn"), (other, "a jump")):
        if np.any(mask):
            i = int(np.flatnonzero(mask)[0])
            n = int(np.count_nonzero(mask))
            size = (f"{q[i]:+.0f} π/2" if what == "a quarter turn" else f"{r[i]:+.4g} rad")
            raise ValueError(
                f"{col} slips {what} ({size}) against the SINS increments between t = "
                f"{t0[i]:.6g} s and {t1[i]:.6g} s ({n} such step(s)): refused, a repair would "
                "be a guess (check the encoder's decoding, or the record's rows there)")
    gs = record.gs_angle
    wrapped = False
    if gs is not None:
        lo, hi = float(np.nanmin(gs)), float(np.nanmax(gs))
        wrapped = (lo >= -math.pi - 1e-9 and hi <= 2.0 * math.pi + 1e-9
                   and abs(float(np.sum(sins_span))) > 2.0 * math.pi)
    n = int(np.count_nonzero(whole))
    i = int(np.flatnonzero(whole)[0])
    if wrapped:
        band = "[0, 2π)" if lo >= -1e-9 else "(−π, π]"
        note = (f"gs_angle is wrapped into {band}: unwrapped with the SINS increments ({n} "
                f"wrap(s), the first between t = {t0[i]:.6g} s and {t1[i]:.6g} s)")
        n_slips = 0
    else:
        turns = ", ".join(f"{k[j]:+.0f}×2π at t = {t1[j]:.6g} s"
                          for j in np.flatnonzero(whole)[:3]) + (", ..." if n > 3 else "")
        note = f"{col} slips a whole turn against the SINS increments {n} time(s) ({turns})"
        if slips == "refuse":
            raise ValueError(note + ": refused (slips='refuse')")
        note += ": repaired (the whole turns removed; check the encoder)"
        n_slips = n
    fixed = gs_span - 2.0 * math.pi * np.where(whole, k, 0.0)
    return fixed, n_slips, [note]


def _gs_increments(record: RSFRecord) -> np.ndarray:
    """GS angle increment of each row over the previous one (NaN for row 0 / unknown), from
    wrapped encoder counts (one step modulo a turn) plus the platform's own turn."""
    c = record.encoder_counts
    n = record.counts_per_rev
    d = np.diff(c)
    ok = ~np.isnan(d)
    di = np.full(d.shape, np.nan)
    di[ok] = np.mod(d[ok].astype(np.int64) + n // 2, n) - n // 2
    out = np.full(record.n, np.nan)
    out[1:] = di * (2.0 * math.pi / n)
    if record.gs_gyro_angle is not None:   # non-ideal GS: add the platform's own turn
        out[1:] += np.diff(record.gs_gyro_angle)
    return out


def _gs_spans(record: RSFRecord) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Start row, end row and GS angle change of every span between consecutive known GS
    angles (with wrapped counts, of every sample whose two counts are known)."""
    if record.gs_angle is not None:
        # the GS change over a span telescopes: its encoder errors cancel inside
        known = np.flatnonzero(~np.isnan(record.gs_angle))
        return known[:-1], known[1:], np.diff(record.gs_angle[known])
    gs_inc = _gs_increments(record)
    j1 = np.flatnonzero(~np.isnan(gs_inc))
    return j1 - 1, j1, gs_inc[j1]


def calibrate(record: RSFRecord, period: float, *, k_form: str = "linear",
              dt: float | None = None, time_tolerance: float = 0.5,
              slips: str = "repair") -> CalibrationResult:
    """Apply paper RSF's scale-factor correction (Eqs. (1)–(3)) to a record.

    The spans between known GS angles that hold no gap and no missing SINS increment go to
    the correction routine the simulation uses too (:func:`gyrolib.rsf.run_correction`),
    each in the interval of its last row.

    Parameters
    ----------
    record : RSFRecord
        SINS roll increments and the GS angle (or wrapped encoder counts).
    period : float
        Correction interval Δt (s); intervals start at the first row's time.
    k_form : {"linear", "reciprocal"}
        The reading of the correction coefficient (:func:`gyrolib.rsf.correction_coefficient`).
    dt : float, optional
        Nominal sample interval (s); default the median step of the record.
    time_tolerance : float
        A step longer than ``(1 + time_tolerance) dt`` is a gap: rows are missing, so its
        sample is not used.  Shorter steps (time-stamp jitter) are used as they are: the SINS
        increment and the GS change of a sample cover the same time whatever its length.
    slips : {"repair", "refuse"}
        What to do with a whole-turn jump of the GS angle against the SINS turn (a wrapped
        ``gs_angle`` is always unwrapped): remove it with a note, or raise ValueError.
        Quarter-turn and other jumps are always refused.

    Returns
    -------
    CalibrationResult
        ε̂1 and K per complete interval, the corrected angle and residuals per row.

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import rsf
    >>> t = np.arange(0, 201) * 0.01                       # 2 s at 100 Hz, 900 °/s
    >>> gs = np.radians(900.0) * t
    >>> inc = np.concatenate([[0.0], np.diff(gs)]) * (1 + 600e-6)
    >>> res = rsf.calibrate(rsf.RSFRecord(t=t, sins_increment=inc, gs_angle=gs), 1.0)
    >>> [f"{e * 1e6:.1f}" for e in res.eps1_hat]         # ε1/(1 + ε1) in ppm
    ['599.6', '599.6']
    """
    if not isinstance(record, RSFRecord):   # "an RSFRecord": the article goes by the sound
        raise TypeError(f"record must be an RSFRecord; got {type(record).__name__}")
    period = v.check_positive("period", period)
    k_form = v.check_choice("k_form", k_form, K_FORMS)
    time_tolerance = v.check_in_range("time_tolerance", time_tolerance, 0.0, 10.0,
                                      low_open=True)
    slips = v.check_choice("slips", slips, ("repair", "refuse"))
    t = record.t
    if t.size < 2:
        raise ValueError("record must hold at least two rows")
    h = np.diff(t)
    dt = float(np.median(h)) if dt is None else v.check_positive("dt", dt)
    if period < dt * (1.0 - 1e-9):
        raise ValueError(f"period must be at least one sample interval ({dt} s); got {period}")
    inc = record.sins_increment
    # a span is usable when every row in it is regular and has its SINS increment
    bad_row = np.ones(t.size, dtype=bool)
    bad_row[1:] = (h > (1.0 + time_tolerance) * dt) | np.isnan(inc[1:])
    cum_bad = np.cumsum(bad_row)
    j0, j1, gs_span = _gs_spans(record)
    ok = (cum_bad[j1] - cum_bad[j0]) == 0
    j0, j1, gs_span = j0[ok], j1[ok], gs_span[ok]
    inc0 = np.where(np.isnan(inc), 0.0, inc)
    inc0[0] = 0.0
    cum_inc = np.cumsum(inc0)
    sins_span = cum_inc[j1] - cum_inc[j0]
    gs_span, n_slips, notes = _jumps(gs_span, sins_span, t[j0], t[j1], record, slips)
    long_ = h > (1.0 + time_tolerance) * dt
    gap_time = float(np.sum(h[long_] - dt))
    if np.any(long_):
        g = np.flatnonzero(long_)
        where = ", ".join(f"{h[i]:.4g} s after t = {t[i]:.6g} s" for i in g[:3])
        notes.append(f"{g.size} gap(s) in the time stamps ({where}"
                     + (", ..." if g.size > 3 else "") + f"; {gap_time:.4g} s without rows): "
                     "the samples across a gap are left out of both sums")
    # interval of each row: the sample ending at t[k] lies in ((k-1) dt, k dt] from t[0];
    # a span counts in the interval of its last row
    n_int = math.floor((t[-1] - t[0]) / period * (1.0 + 1e-12))
    row_interval = np.floor((t - t[0] - 0.5 * dt) / period).astype(np.int64)
    row_interval[0] = -1
    sidx = row_interval[j1]
    est = correct_spans(sins_span[None], gs_span[None], sidx, n_int, period, k_form)
    keep = np.flatnonzero(~np.isnan(est.eps1_hat[0]))
    corrected = est.corrected_angle(inc0[None], row_interval)[0]
    # bookkeeping of the spans: samples used and contiguous runs per interval
    cnt = np.bincount(sidx, weights=j1 - j0, minlength=n_int + 1)[:n_int]
    abs_turn = np.bincount(sidx, weights=np.abs(sins_span), minlength=n_int + 1)[:n_int]
    starts = np.ones(j1.size, dtype=bool)
    starts[1:] = (j0[1:] != j1[:-1]) | (sidx[1:] != sidx[:-1])
    seg = np.bincount(sidx[starts], minlength=n_int + 1)[:n_int]
    cover = np.zeros(t.size + 1, dtype=np.int64)
    np.add.at(cover, j0 + 1, 1)
    np.add.at(cover, j1 + 1, -1)
    used = int(np.count_nonzero(np.cumsum(cover[:-1]) > 0))    # rows inside a usable span
    # residuals against the GS, accumulated over the usable spans only
    res_inc = np.zeros(t.size)
    raw_inc = np.zeros(t.size)
    np.add.at(res_inc, j1, (corrected[j1] - corrected[j0]) - gs_span)
    np.add.at(raw_inc, j1, sins_span - gs_span)
    gyro_turn = None
    if record.gs_gyro_angle is not None:
        gyro = record.gs_gyro_angle
        gyro_turn = np.bincount(sidx, weights=np.nan_to_num(gyro[j1] - gyro[j0]),
                                minlength=n_int + 1)[:n_int][keep]
    return CalibrationResult(
        period=period, k_form=k_form, t_start=t[0] + keep * period,
        t_end=t[0] + (keep + 1) * period, eps1_hat=est.eps1_hat[0, keep], k=est.k[0, keep],
        samples=cnt[keep].astype(np.int64), segments=seg[keep].astype(np.int64),
        rate=est.turn[0, keep] / (cnt[keep] * dt), t=t, corrected_angle=corrected,
        residual=np.cumsum(res_inc), residual_raw=np.cumsum(raw_inc), rows=int(t.size),
        samples_used=used, samples_skipped=int(t.size - 1 - used),
        gaps=int(np.count_nonzero(h > 1.5 * dt)), dt=dt,
        abs_rate=abs_turn[keep] / (cnt[keep] * dt),
        reversal=np.abs(est.turn[0, keep]) < 0.5 * abs_turn[keep], gap_time=gap_time,
        slips_repaired=n_slips, notes=tuple(notes), gs_gyro_turn=gyro_turn,
        counts_per_rev=record.counts_per_rev)


def record_from_simulation(sim: SensorRecord, run: int = 0, *,
                           encoder: bool = False) -> RSFRecord:
    """The columns of an :class:`RSFRecord` from run ``run`` of a simulated flight
    (:func:`gyrolib.rsf.simulate_flight`): the SINS increments (0 at t = 0) and the GS angle
    (:func:`gyrolib.rsf.gs_angle`); with ``encoder=True`` the wrapped encoder counts and the
    GS gyro's integrated angle instead (the GS angle is their sum, paper RSF Figure 2)."""
    v.check_instance("sim", sim, SensorRecord)
    run = v.check_int("run", run, 0)
    if run >= sim.sins_inc.shape[0]:
        raise ValueError(f"run must be < {sim.sins_inc.shape[0]}; got {run}")
    inc = np.concatenate([[0.0], sim.sins_inc[run]])
    if not encoder:
        return RSFRecord(t=sim.t, sins_increment=inc, gs_angle=gs_angle(sim)[run])
    enc = sim.config.encoder
    c = encoder_counts(sim.theta_rel[run], enc, sim.encoder_phase[run]).astype(float)
    gyro = np.concatenate([[0.0], np.cumsum(sim.gs_gyro_inc[run])])
    return RSFRecord(t=sim.t, sins_increment=inc, encoder_counts=c,
                     counts_per_rev=enc.counts_per_rev, gs_gyro_angle=gyro)
