"""Paper RSF: its verbal claims, computed with the conditions under which they hold.

* :func:`compensation_share` — "the method compensates 90 %": the share 1 − δK/ε1 of the
  roll gyro's SF error removed, from Eq. (7) of paper RSF, against the roll rate, and the rate
  from which it reaches a target share (closed form);
* :func:`flight_shares` — the same share flight by flight, with the sensors' systematic
  errors drawn at random per flight (how often the correction helps at all);
* :func:`gs_vs_sins` — "the GS error is hundreds of times smaller than the SINS error":
  Eq. (4) over Eq. (9) (ideal GS, Table 3) and over Eq. (6) (the worked example's non-ideal
  GS, ω_unc = 300 °/s);
* :func:`drz_slip_search` — Table 2's Δr_z against Eq. (8) of paper RSF times every product of
  up to three plausible unit slips (is there a cause that gives the print?).

SI inside; the results carry SI values.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrolib import _validation as v
from gyrolib import stats
from gyrolib._repr import compact_repr
from gyrolib.rsf._inputs import check_times
from gyrolib.rsf.correction import run_correction
from gyrolib.rsf.equations import (
    delta_k,
    fraction_compensated,
    gs_roll_error_ideal,
    gs_roll_error_nonideal,
    lateral_deviation_cubic,
    lateral_deviation_exact,
    sins_roll_error,
)
from gyrolib.rsf.sensors import (
    AEDB9340,
    GYPRO4300,
    SIIMU02_ROLL,
    EncoderSpec,
    MemsGyroSpec,
    RollGyroSpec,
)
from gyrolib.rsf.simulation import SimulationConfig, simulate_flight
from gyrolib.rsf.sweeps import RateSweep
from gyrolib.stats import Estimate
from gyrolib.units import G0, from_si, to_si

__all__ = [
    "SLIP_FACTORS",
    "CompensationShare",
    "FlightShares",
    "GsVsSins",
    "SlipSearch",
    "compensation_share",
    "drz_hypotheses",
    "drz_slip_search",
    "flight_shares",
    "gs_vs_sins",
]

_W300 = float(to_si(300.0, "deg/s"))
_W3600 = float(to_si(3600.0, "deg/s"))


def _specs(roll_gyro: object, gs_gyro: object, encoder: object) -> None:
    v.check_instance("roll_gyro", roll_gyro, RollGyroSpec)
    v.check_instance("gs_gyro", gs_gyro, MemsGyroSpec)
    v.check_instance("encoder", encoder, EncoderSpec)


# "Compensates 90 %" ----------------------------------------------------------------------------
@compact_repr
@dataclass(frozen=True)
class CompensationShare:
    """The share of the roll gyro's SF error removed, 1 − δK/ε1, against the roll rate.

    ``rates`` (rad/s) and, per rate, ``delta_k`` (Eq. (7)) and ``share``; ``eps1`` the roll
    gyro's SF error; ``omega_unc`` (rad/s), ``period`` (s); ``target`` the share asked about
    and ``rate_for_target`` (rad/s) the roll rate from which Eq. (7) gives at least that
    share (closed form); ``simulated`` an optional :class:`~gyrolib.rsf.RateSweep` that
    confirms it.
    """

    rates: NDArray[np.float64]
    delta_k: NDArray[np.float64]
    share: NDArray[np.float64]
    eps1: float
    omega_unc: float
    period: float
    target: float
    rate_for_target: float
    simulated: RateSweep | None = None

    def share_at(self, rate: float) -> float:
        """Share removed at one roll rate (rad/s), from Eq. (7), same sensors and Δt."""
        return 1.0 - self.rate_for_target * (1.0 - self.target) / v.check_positive("rate", rate)


def compensation_share(rates: ArrayLike, *, roll_gyro: RollGyroSpec = SIIMU02_ROLL,
                       gs_gyro: MemsGyroSpec = GYPRO4300, encoder: EncoderSpec = AEDB9340,
                       omega_unc: float = _W300, period: float = 5.0, target: float = 0.9,
                       simulated: RateSweep | None = None) -> CompensationShare:
    """Share of the SF error the correction removes, 1 − δK/ε1, from Eq. (7) of paper RSF.

    δK = N/(ω Δt) with N = (ε0,GS + ε1,GS ω_unc) Δt + Δγ_enc, so the share reaches
    ``target`` from ω* = N / (Δt ε1 (1 − target)) on.

    Parameters
    ----------
    rates : array_like
        Roll rates ω, rad/s (> 0).
    roll_gyro, gs_gyro, encoder : sensor records, optional
        The paper's sensors by default (Table 1, the GS gyro table, the encoder).
    omega_unc : float, optional
        Uncompensated rate, rad/s (default the worked example's 300 °/s).
    period : float, optional
        Correction period Δt, s (default 5 s).
    target : float, optional
        The share asked about, in (0, 1) (default 0.9, the paper's "90 %").
    simulated : RateSweep, optional
        A simulation at some of the rates (:func:`~gyrolib.rsf.sweep_roll_rate`), kept with
        the result so that one plot shows both.

    Returns
    -------
    CompensationShare

    Examples
    --------
    >>> from gyrolib.units import from_si, to_si
    >>> cs = compensation_share(to_si([900.0, 3600.0], "deg/s"))
    >>> [f"{s:.3f}" for s in cs.share], f"{from_si(cs.rate_for_target, 'deg/s'):.0f} °/s"
    (['0.716', '0.929'], '2557 °/s')
    """
    _specs(roll_gyro, gs_gyro, encoder)
    r = v.check_array("rates", rates, ndim=1)
    if np.any(r <= 0.0):
        raise ValueError(f"rates must be > 0 (rad/s); got min {r.min()}")
    omega_unc = v.check_nonnegative("omega_unc", omega_unc)
    period = v.check_positive("period", period)
    target = v.check_in_range("target", target, 0.0, 1.0, low_open=True, high_open=True)
    if simulated is not None:
        v.check_instance("simulated", simulated, RateSweep)
    e1 = roll_gyro.sf_error
    if e1 <= 0.0:
        raise ValueError("roll_gyro.sf_error must be > 0 (the share of a zero SF error is "
                         f"undefined); got {e1}")
    dk = np.array([delta_k(gs_gyro.bias_total, encoder.position_error, float(w), period,
                           gs_gyro.sf_error, omega_unc) for w in r])
    numerator = (gs_gyro.bias_total + gs_gyro.sf_error * omega_unc) * period \
        + encoder.position_error
    return CompensationShare(rates=r, delta_k=dk, share=1.0 - dk / e1, eps1=e1,
                             omega_unc=omega_unc, period=period, target=target,
                             rate_for_target=numerator / (period * e1 * (1.0 - target)),
                             simulated=simulated)


@compact_repr
@dataclass(frozen=True)
class FlightShares:
    """The share 1 − |δK|_rms/|ε1| of each simulated flight's own SF error that the correction
    removes, with the sensors' systematic errors drawn at random per flight: ``share`` and the
    residual ``rms`` δK (one per flight), the correction ``period`` (s), the roll ``rate``
    (rad/s) and the ``seed``."""

    share: NDArray[np.float64]
    rms: NDArray[np.float64]
    period: float
    rate: float
    seed: int

    @property
    def median(self) -> float:
        """The median flight's share."""
        return float(np.median(self.share))

    @property
    def worse(self) -> float:
        """The fraction of flights that end up worse than uncorrected (share < 0)."""
        return float(np.mean(self.share < 0.0))

    def percentile_estimate(self, q: float) -> Estimate:
        """The ``q``-th percentile of the flights' shares with its 95 % distribution-free
        interval (:func:`gyrolib.stats.percentile`; the flights are independent).

        >>> fs = flight_shares(1, n_runs=40)
        >>> est = fs.percentile_estimate(50)
        >>> est.lo <= fs.median <= est.hi
        True
        """
        return stats.percentile(self.share, q)

    def worse_estimate(self) -> Estimate:
        """The fraction of flights worse than uncorrected with its 95 % Wilson interval
        (:func:`gyrolib.stats.proportion`; the flights are independent)."""
        return stats.proportion(int(np.sum(self.share < 0.0)), self.share.size)


def flight_shares(seed: int, *, config: SimulationConfig | None = None, period: float = 5.0,
                  n_runs: int = 400) -> FlightShares:
    """Paper RSF's "compensates 90 %" flight by flight: ``n_runs`` seeded flights whose
    sensors' systematic errors (ε1 and ε0 of both gyros, the encoder's phase) are drawn at
    random from their 1σ values, each corrected every ``period`` by Eqs. (1)–(3), and the
    share of its own SF error removed, 1 − rms δK/|ε1| (negative: made worse).

    Parameters
    ----------
    seed : int
        Seed of the ensemble (>= 0).
    config : SimulationConfig, optional
        Vehicle, sensors, run length and sample rate (default :class:`SimulationConfig()`: the
        paper's sensors at the worked example's 900 °/s); its ``errors`` and ``n_runs`` are
        replaced.
    period : float, optional
        Correction period Δt, s (default the worked example's 5 s).
    n_runs : int, optional
        Number of flights (>= 1).

    Returns
    -------
    FlightShares

    Examples
    --------
    >>> fs = flight_shares(1, n_runs=40)
    >>> 0.0 < fs.worse < 0.5 < fs.median < 0.9
    True
    """
    seed = v.check_int("seed", seed, 0)
    config = SimulationConfig() if config is None else v.check_instance(
        "config", config, SimulationConfig)
    period = v.check_positive("period", period)
    n_runs = v.check_int("n_runs", n_runs, 1)
    cfg = dataclasses.replace(config, errors="random", n_runs=n_runs)
    record = simulate_flight(cfg, seed=seed)
    rms = np.sqrt(np.mean(run_correction(record, period).delta_k ** 2, axis=1))
    share = np.asarray(fraction_compensated(record.eps1_sins, rms), dtype=float)
    return FlightShares(share=share, rms=rms, period=period, rate=float(cfg.roll.rate_start),
                        seed=seed)


# "Hundreds of times smaller" -------------------------------------------------------------------
@compact_repr
@dataclass(frozen=True)
class GsVsSins:
    """Roll errors (rad) of the SINS (Eq. (4)), of the ideal GS (Eq. (9), Table 3) and of the
    non-ideal GS (Eq. (6), uncompensated rate ``omega_unc``) at times ``t``, and the ratios
    ``ratio_ideal`` = SINS / ideal GS and ``ratio_nonideal`` = SINS / non-ideal GS."""

    t: NDArray[np.float64]
    sins: NDArray[np.float64]
    gs_ideal: NDArray[np.float64]
    gs_nonideal: NDArray[np.float64]
    ratio_ideal: NDArray[np.float64]
    ratio_nonideal: NDArray[np.float64]
    omega_unc: float


def gs_vs_sins(times: ArrayLike = (10.0, 60.0, 120.0), *,
               roll_gyro: RollGyroSpec = SIIMU02_ROLL, gs_gyro: MemsGyroSpec = GYPRO4300,
               encoder: EncoderSpec = AEDB9340, omega: float = _W3600,
               omega_unc: float = _W300) -> GsVsSins:
    """How many times smaller the GS's roll error is than the SINS's (paper RSF, after
    Table 3), for the ideal GS of Eq. (9) and the non-ideal GS of Eq. (6).

    Parameters
    ----------
    times : array_like, optional
        Times, s (>= 0; default Table 2's and Table 3's 10, 60 and 120 s).
    roll_gyro, gs_gyro, encoder : sensor records, optional
        The paper's sensors by default.
    omega : float, optional
        Roll rate of Table 2, rad/s (default 3600 °/s).
    omega_unc : float, optional
        Uncompensated rate of the non-ideal GS, rad/s (default 300 °/s, the worked example).

    Returns
    -------
    GsVsSins

    Examples
    --------
    >>> r = gs_vs_sins()
    >>> [f"{x:.0f}" for x in r.ratio_ideal], [f"{x:.0f}" for x in r.ratio_nonideal]
    (['59', '243', '352'], ['18', '23', '24'])
    """
    _specs(roll_gyro, gs_gyro, encoder)
    t = check_times(times)
    omega = v.check_positive("omega", omega)
    omega_unc = v.check_nonnegative("omega_unc", omega_unc)
    sins = np.asarray(sins_roll_error(roll_gyro.sf_error, omega, t), dtype=float)
    ideal = np.asarray(gs_roll_error_ideal(gs_gyro.bias_total, t, encoder.position_error),
                       dtype=float)
    nonideal = np.asarray(gs_roll_error_nonideal(gs_gyro.bias_total, gs_gyro.sf_error,
                                                 omega_unc, t, encoder.position_error),
                          dtype=float)
    return GsVsSins(t=t, sins=sins, gs_ideal=ideal, gs_nonideal=nonideal,
                    ratio_ideal=sins / ideal, ratio_nonideal=sins / nonideal,
                    omega_unc=omega_unc)


# Table 2's Δr_z: is there a unit slip that gives the print? --------------------------------------
#: Plausible slips in a cubic g ε1 ω t³/6 (and their inverses are tried too).
SLIP_FACTORS: Mapping[str, float] = {
    "6": 6.0, "180/π": 180 / math.pi, "2": 2.0, "π": math.pi, "3.6": 3.6, "60": 60.0,
    "g": 9.81, "1000": 1000.0, "3": 3.0, "10": 10.0, "57.3": 57.3, "2π": 2 * math.pi,
    "9.80665/9.81": 9.80665 / 9.81, "3600": 3600.0,
}


@dataclass(frozen=True)
class SlipSearch:
    """The search of :func:`drz_slip_search`: ``c_cubic`` = g ε1 ω/6 (m/s³), ``c_print`` the
    printed Δr_z/t³ of the first column, the window [``lo``, ``hi``] of constants consistent
    with every printed column's rounding, ``tried`` products and the ``hits`` (factor names)
    that land in the window."""

    c_cubic: float
    c_print: float
    lo: float
    hi: float
    tried: int
    hits: tuple[tuple[str, ...], ...]


def drz_slip_search(printed: Sequence[float], times: Sequence[float] = (10.0, 60.0, 120.0),
                    half_digits: Sequence[float] = (0.005, 5.0, 5.0), *,
                    roll_gyro: RollGyroSpec = SIIMU02_ROLL, omega: float = _W3600,
                    g: float = G0, max_factors: int = 3,
                    factors: Mapping[str, float] = SLIP_FACTORS) -> SlipSearch:
    """Search products of up to ``max_factors`` slips (and inverses), in m, km or mm, that turn
    Eq. (8) of paper RSF into the printed Δr_z of Table 2.

    Parameters
    ----------
    printed : sequence of float
        Printed Δr_z, one per time (unit lost).
    times : sequence of float, optional
        Their times, s.
    half_digits : sequence of float, optional
        Half a unit of each printed value's last digit (its rounding).
    roll_gyro : RollGyroSpec, optional
        Gives ε1 (default Table 1).
    omega, g : float, optional
        Roll rate (rad/s, default 3600 °/s) and gravity (m/s²).
    max_factors : int, optional
        Longest product tried (default 3).
    factors : mapping, optional
        Named factors (default :data:`SLIP_FACTORS`).

    Returns
    -------
    SlipSearch

    Examples
    --------
    >>> s = drz_slip_search([21.25, 4590.0, 36730.0])
    >>> s.tried, len(s.hits), f"{s.c_print / s.c_cubic:.3f}"
    (13485, 0, '0.345')
    """
    v.check_instance("roll_gyro", roll_gyro, RollGyroSpec)
    p = v.check_array("printed", printed, ndim=1)
    t = v.check_array("times", times, shape=p.shape)
    half = v.check_array("half_digits", half_digits, shape=p.shape)
    if np.any(t <= 0.0):
        raise ValueError("times must be > 0 (s)")
    max_factors = v.check_int("max_factors", max_factors, 0)
    c_cubic = float(lateral_deviation_cubic(roll_gyro.sf_error, v.check_positive("omega", omega),
                                            1.0, v.check_positive("g", g)))
    lo, hi = float(np.max((p - half) / t**3)), float(np.min((p + half) / t**3))
    pool = [(name, f) for name, value in factors.items()
            for name, f in ((name, value), (f"1/{name}", 1.0 / value))]
    tried, hits = 0, []
    for k in range(max_factors + 1):
        for combo in itertools.combinations_with_replacement(pool, k):
            prod = math.prod(f for _, f in combo)
            for scale_name, scale in (("m", 1.0), ("km", 1e-3), ("mm", 1e3)):
                tried += 1
                if lo <= c_cubic * prod * scale <= hi:
                    hits.append((*(name for name, _ in combo), scale_name))
    return SlipSearch(c_cubic=c_cubic, c_print=float(p[0] / t[0] ** 3), lo=lo, hi=hi,
                      tried=tried, hits=tuple(hits))


#: The rounded gravity a slip might have used, m/s².
G_ROUNDED = 9.81


def drz_hypotheses(t: float = 10.0, *, roll_gyro: RollGyroSpec = SIIMU02_ROLL,
                   omega: float = _W3600) -> tuple[tuple[str, str, float], ...]:
    """Table 2's Δr_z at time ``t`` under the usual slips in Eq. (8) of paper RSF, each as
    (description, unit of the value, value).

    Parameters
    ----------
    t : float, optional
        Time, s (default 10 s, Table 2's first column).
    roll_gyro : RollGyroSpec, optional
        Gives ε1 (default Table 1).
    omega : float, optional
        Roll rate, rad/s (default 3600 °/s).

    Returns
    -------
    tuple of (str, str, float)

    Examples
    --------
    >>> [f"{value:.4g} {unit}" for _, unit, value in drz_hypotheses()][:2]
    ['61.62 m', '3530 m']
    """
    v.check_instance("roll_gyro", roll_gyro, RollGyroSpec)
    t = v.check_positive("t", t)
    omega = v.check_positive("omega", omega)
    e1 = roll_gyro.sf_error
    w_deg = float(from_si(omega, "deg/s"))           # ω in °/s, used as if it were rad/s
    t3 = t**3
    km = float(from_si(1.0, "km"))
    return (
        ("consistent: g ε1 ω t³/6, ω in rad/s, metres", "m",
         float(lateral_deviation_cubic(e1, omega, t))),
        ("ω in °/s used as rad/s", "m", G0 * e1 * w_deg * t3 / 6),
        ("factor 1/6 dropped", "m", G0 * e1 * omega * t3),
        ("ω = 900 °/s (the worked example's rate)", "m",
         float(lateral_deviation_cubic(e1, float(to_si(900.0, "deg/s")), t))),
        (f"g = {G_ROUNDED} instead of {G0}", "m", G_ROUNDED * e1 * omega * t3 / 6),
        ("°/s as rad/s and 1/6 dropped, printed in km", "km", G0 * e1 * w_deg * t3 * km),
        (f"same with g = {G_ROUNDED}, in km", "km", G_ROUNDED * e1 * w_deg * t3 * km),
        ("exact double integral of g sin Δγ", "m", float(lateral_deviation_exact(e1, omega, t))),
    )
