"""Paper RSF on a record: the standard uncertainty of the mean scale-factor estimate
``eps1_hat_mean`` and the checks that make a run valid (:func:`eps1_uncertainty`).

The mean of ε̂1 over the intervals (Eq. (2)) carries two kinds of error.  The random ones
(the gyros' white noise, the encoder's end-point errors) differ from interval to interval
and the intervals' scatter shows them; the systematic ones are the same in every interval,
so no scatter shows them and no number of intervals removes them.  With Eq. (1) written out
for interval ``i`` (turn ``T_i = ω_i Δt``; SINS bias ``b_S``, GS bias ``b_G``, GS gyro scale
error ``ε1,GS`` on its own turn ``U_i``, GS end-point errors ``e_i``),

    ε̂1_i ≈ ε1 + (b_S − b_G)/ω_i − ε1,GS U_i/T_i − (e_i − e_{i−1})/T_i + w_i/T_i,

so the mean over ``n`` intervals has the systematic part ``(b_S − b_G)·mean(1/ω_i) −
ε1,GS·mean(U_i/T_i)`` and the end-point part ``(e_n − e_0)/Σ T_i`` (for equal turns the
end-point errors telescope; where the roll reverses they add).  :class:`Eps1Uncertainty`
adds, in quadrature, one part per term, each counted once:

* ``random``: the standard error of the mean from the intervals' own scatter, with the lag-1
  autocovariance, ``√(max(γ̂0 + 2(1 − 1/n) γ̂1, 0)/n)`` (the variance of the mean of an MA(1)
  series: neighbouring intervals share an end point with opposite signs, which cancels in the
  mean; with independent intervals it is the SEM, ``eps1_hat_sem``, which is an upper bound
  otherwise), floored by the white noise the sensors' model predicts over the whole turn,
  ``√((N_S² + N_G²) Σ Δt_i)/Σ|T_i|``;
* ``encoder``: the encoder's errors at the end points, which the scatter does not show when
  the intervals agree (a coarse encoder at a steady rate): ``σ_e Σ_j |c_j| / n`` with
  ``σ_e = √(q²/12 + Δγ_enc²/2)`` (``q`` one count: each end's rounding is uniform over a
  count; ``Δγ_enc`` the once-per-turn position error) and ``c_j`` the weight of end point
  ``j`` in the mean (``1/T_i − 1/T_{i+1}`` for the end point two intervals share: 0 for
  equal turns, ``2/T`` where the roll reverses; ``±1/T_i`` at a free end), summed linearly
  because a periodic roll repeats the same end-point errors.  For equal turns it is
  ``2 σ_e/Σ|T_i|``, the two ends of the whole turn;
* ``biases``: ``|mean(1/ω_i)| · √(σ_bS² + σ_bG²)`` with the biases' tolerances (paper RSF:
  the SiIMU02's 100 °/h and the GYPRO4300's √(10² + 7²) °/h).  A roll rate that reverses
  separates the biases from ε1: then ``b = b_S − b_G`` is estimated from the record by least
  squares on ``ε̂1_i = ε1 + b/ω_i`` (weights from the model's per-interval σ) and the part is
  ``|mean(1/ω_i)| · √(b̂² + σ_b̂²)`` (the bias left in the mean at its estimated size);
* ``gs_scale``: the GS angle's scale tolerance times the share of the turn it scales: with
  ``gs_scale`` given, ``gs_scale`` itself (the relative scale of the whole GS angle);
  otherwise ``σ(ε1,GS) · |mean(U_i/T_i)|`` (paper RSF: 280 ppm), with ``U_i`` the GS gyro's
  turn when the record has it, else the uncompensated turn the GS model predicts,
  ``max(|ω_i| − W_max, 0)/|ω_i|`` (0 for a record of encoder counts without a GS gyro
  column: its GS angle is the encoder's);
* ``quantization`` (only when a column is coarse: written to a few decimals, or counted in
  LSBs that are not the encoder's, :attr:`gyrolib.rsf.RSFRecord.resolution`): the rounding
  of the record's own columns.  A SINS increment rounded to a step ``q_S`` errs by
  ``r_k``, uniform over a step; at a steady increment it rounds alike in every sample, so
  a share ``ρ`` of it repeats (``ρ = exp(−2π² σ_w²/q_S²)``, σ_w the increment's white
  noise a sample, :func:`gyrolib.resolution.rounding_correlation`) and the rest is white:
  ``(q_S/√12) √(ρ² N² + (1 − ρ²) N) / Σ|T_i|`` over the ``N`` samples used.  A GS angle
  (or GS gyro angle) rounded to ``q_G`` errs at the end points like the encoder:
  ``(q_G/√12) Σ_j |c_j| / n`` (not when ``q_G`` is the encoder's count, which the
  ``encoder`` part carries).  The two add in quadrature.

The checks (:meth:`Eps1Uncertainty.tests`), at a family-wise false-alarm rate (Šidák):

* ``scatter``: Σ ((ε̂1_i − ε̄)/σ_i)² against the χ²(n − 1) upper quantile, σ_i the random
  σ of δK the sensors' model predicts for interval ``i`` (:func:`gyrolib.rsf.predict_delta_k`
  at its rate, for the turn it used), with the encoder's position-error term at the largest
  variance a record can show (2× its average over the encoder's phase, which a record
  fixes): a record noisier than its sensors' model (or an encoder that slips counts) fails
  it;
* ``bias`` (a reversing roll rate only): ``b̂/√(σ_b² + σ_b̂²)`` two-sided normal: biases far
  beyond their tolerances;
* ``prior``: ``ε̄/√(σ_ε1² + σ²)`` two-sided normal, σ_ε1 the roll gyro's scale-factor
  tolerance (paper RSF, Table 1: 600 ppm): an estimate its gyro's datasheet does not allow
  (a wrong unit, a record of another gyro).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from gyrolib import _validation as v
from gyrolib._repr import compact_repr
from gyrolib.filtering.consistency import chi2_ppf
from gyrolib.resolution import describe_step, rounding_correlation
from gyrolib.rsf.calibration import CalibrationResult
from gyrolib.rsf.correction import predict_delta_k
from gyrolib.rsf.simulation import SimulationConfig

__all__ = ["Eps1Uncertainty", "eps1_uncertainty"]

#: The parts of σ(eps1_hat_mean), in the order they are reported (``quantization`` only
#: for a record with a coarse column).
PARTS: tuple[str, ...] = ("random", "encoder", "biases", "gs_scale", "quantization")

#: ``reason_code`` of each failed check (the command line maps it to the option to try).
REASON_CODES: dict[str, str] = {"scatter": "rsf_scatter", "bias": "rsf_bias",
                                "prior": "rsf_prior"}


@compact_repr
@dataclass(frozen=True)
class Eps1Uncertainty:
    """The standard uncertainty of ``eps1_hat_mean`` and the run's own checks
    (:func:`eps1_uncertainty`; the formulas in :mod:`gyrolib.rsf.uncertainty`).

    ``mean``: ε̄ (the mean of ε̂1 over the intervals without a reversal inside); ``std``:
    its total standard uncertainty; ``parts``: the terms of :data:`PARTS` (add in
    quadrature to ``std``); ``tolerances``: the 1σ tolerances used (SI: ``sins_bias``,
    ``gs_bias`` rad/s, ``gs_gyro_scale``, ``gs_scale``, ``sf_prior`` dimensionless, ``None``
    where not used); ``bias_estimate``, ``bias_estimate_std`` (rad/s): b̂ = b_S − b_G when
    the roll rate reverses (else ``None``); ``checks``: one dict per check (``test``,
    ``statistic``, ``low``, ``high``, ``passed``, ``reason_code``); ``false_alarm``.
    """

    mean: float
    std: float
    parts: dict[str, float]
    tolerances: dict[str, float | None]
    checks: tuple[dict, ...]
    false_alarm: float
    bias_estimate: float | None = None
    bias_estimate_std: float | None = None
    n: int = 0
    notes: tuple[str, ...] = field(default=())

    @property
    def valid(self) -> bool:
        """True when every check passes."""
        return all(c["passed"] for c in self.checks)

    @property
    def reason(self) -> str:
        """Why the run is not valid (``""`` when valid), naming each failed check."""
        return "; ".join(c["message"] for c in self.checks if not c["passed"])

    @property
    def reason_codes(self) -> tuple[str, ...]:
        """The stable codes of the failed checks (:data:`REASON_CODES`)."""
        return tuple(c["reason_code"] for c in self.checks if not c["passed"])

    def summary(self) -> dict:
        """JSON-ready dict (SI)."""
        return {"eps1_hat_mean_std": self.std, "eps1_hat_mean_std_parts": dict(self.parts),
                "tolerances": dict(self.tolerances), "bias_estimate": self.bias_estimate,
                "bias_estimate_std": self.bias_estimate_std,
                "checks": [{k: c[k] for k in ("test", "statistic", "low", "high", "passed",
                                               "reason_code")} for c in self.checks],
                "false_alarm": self.false_alarm, "valid": self.valid, "reason": self.reason,
                "reason_codes": list(self.reason_codes)}


def _tolerance(name: str, given: float | None, default: float) -> float:
    return abs(default) if given is None else v.check_nonnegative(name, given)


def _random_std(config: SimulationConfig, res: CalibrationResult, rate: np.ndarray
                ) -> np.ndarray:
    """The largest σ of δK per interval the sensors' model allows from its random terms
    (encoder, quantization, noise; not the systematic ones) at each interval's rate, for the
    turn the interval used (:meth:`CalibrationResult.delta_k_std`)."""
    out = np.empty(rate.size)
    cache: dict[float, float] = {}
    for i, w in enumerate(rate):
        key = float(np.round(w, 6))
        if key not in cache:
            p = predict_delta_k(config, res.period, rate=float(w))
            # the position error is a sine of the encoder's phase, which a record fixes: its
            # variance over a record's intervals reaches 2× the phase average
            cache[key] = math.sqrt(2.0 * p.std_encoder**2 + p.std_quantization**2
                                   + p.std_noise**2)
        out[i] = cache[key]
    return out


def _end_points(res: CalibrationResult, keep: np.ndarray, rate: np.ndarray, cpr: int,
                position_error: float) -> float:
    """The encoder part: σ_e Σ_j |c_j| / n over the end points ``j`` of the intervals kept,
    with σ_e = √(q²/12 + Δγ_enc²/2) and ``c_j`` the weight of end point ``j`` in the mean
    of ε̂1 (``1/T_i − 1/T_{i+1}`` where two kept intervals share it, ``±1/T_i`` at a free
    end, two free ends more per extra contiguous run inside an interval)."""
    q = 2.0 * math.pi / cpr
    return math.sqrt(q * q / 12.0 + 0.5 * position_error**2) * _end_point_weight(
        res, keep, rate)


def _end_point_weight(res: CalibrationResult, keep: np.ndarray, rate: np.ndarray) -> float:
    """``Σ_j |c_j| / n``: the weight of the GS angle's end-point errors in the mean of ε̂1
    over the ``n`` intervals kept (see :func:`_end_points`)."""
    turn = (rate * res.samples[keep] * res.dt)              # signed T_i
    n = turn.size
    t0 = np.asarray(res.t_start, float)[keep]
    t1 = np.asarray(res.t_end, float)[keep]
    shared = np.abs(t0[1:] - t1[:-1]) < 0.5 * res.dt      # consecutive: one end point
    inv = 1.0 / turn
    weight = float(np.abs(inv[0]) + np.abs(inv[-1]))
    weight += float(np.sum(np.where(shared, np.abs(inv[:-1] - inv[1:]),
                                    np.abs(inv[:-1]) + np.abs(inv[1:]))))
    weight += float(np.sum(2.0 * (res.segments[keep] - 1) * np.abs(inv)))
    return weight / n


def _quantization_part(res: CalibrationResult, iv: _Intervals, config: SimulationConfig,
                       resolution: Mapping[str, float], cpr: int, notes: list[str]) -> float:
    """The rounding of the record's coarse columns (formulas in the module docstring): the
    SINS increments' (a repeating share and a white one) and the GS angle's at the end
    points, in quadrature; a note names each coarse column, its step and what it adds.  A
    GS angle on the grid of the encoder's count (``2π/cpr``) is the encoder's rounding,
    which the ``encoder`` part carries already."""
    q_s = float(resolution.get("sins_increment", 0.0))
    q_g = max(float(resolution.get(c, 0.0)) for c in ("gs_angle", "gs_gyro_angle"))
    if abs(q_g * cpr / (2.0 * math.pi) - 1.0) < 1e-6:
        q_g = 0.0
    parts, rep = {}, ""
    if q_s > 0.0:
        rho = rounding_correlation(q_s, config.sins.arw * math.sqrt(res.dt))
        n_used = iv.time_used / res.dt
        parts["sins_increment"] = (q_s / math.sqrt(12.0) * math.sqrt(
            rho**2 * n_used**2 + (1.0 - rho**2) * n_used) / iv.total_turn)
        rep = f", {100 * rho:.0f} % of it repeating from sample to sample"
    if q_g > 0.0:
        name = "gs_angle" if resolution.get("gs_angle", 0.0) > 0.0 else "gs_gyro_angle"
        parts[name] = q_g / math.sqrt(12.0) * _end_point_weight(res, iv.keep, iv.rate)
    for name, x in parts.items():
        step = q_s if name == "sins_increment" else q_g
        notes.append(f"the {name} column is written to a step of {describe_step(step, 'rad')}"
                     f": its rounding adds {x * 1e6:.3g} ppm to sigma (quantization"
                     f"{rep if name == 'sins_increment' else ''})")
    return math.sqrt(sum(x * x for x in parts.values()))


def eps1_uncertainty(result: CalibrationResult, config: SimulationConfig | None = None, *,
                     sins_bias: float | None = None, gs_bias: float | None = None,
                     gs_gyro_scale: float | None = None, gs_scale: float | None = None,
                     sf_prior: float | None = None, counts_per_rev: int | None = None,
                     false_alarm: float = 0.01,
                     resolution: Mapping[str, float] | None = None) -> Eps1Uncertainty:
    """The total standard uncertainty of ``eps1_hat_mean`` and the run's checks.

    Parameters
    ----------
    result : CalibrationResult
        The correction on a record (:func:`gyrolib.rsf.calibrate`).
    config : SimulationConfig, optional
        The sensors (``sins``, ``gs``, ``encoder``): their noise, the GS motor's speed limit
        and the default tolerances; default the paper's (:class:`SimulationConfig`).
    sins_bias, gs_bias : float, optional
        1σ tolerance of the SINS roll gyro's and the GS gyro's bias, rad/s (default
        ``|config.sins.eps0|``, ``|config.gs.eps0|``: paper RSF's 100 °/h and
        √(10² + 7²) °/h).
    gs_gyro_scale : float, optional
        1σ scale-factor tolerance of the GS gyro, ε1,GS (default ``|config.gs.eps1|``, the
        GYPRO4300's 280 ppm); it scales the GS gyro's own turn.
    gs_scale : float, optional
        1σ relative scale tolerance of the whole GS angle; replaces the ``gs_gyro_scale``
        term when given (a GS angle from another source).
    sf_prior : float, optional
        1σ scale-factor tolerance of the roll gyro, ε1 (default ``|config.sins.eps1|``, the
        SiIMU02's 600 ppm): the prior the estimate is checked against.
    counts_per_rev : int, optional
        The encoder's counts per revolution (default the record's, else
        ``config.encoder.counts_per_rev``).
    false_alarm : float
        Family-wise false-alarm rate of the checks, in (0, 1).
    resolution : mapping, optional
        The step (rad) of the record's columns ``sins_increment``, ``gs_angle``,
        ``gs_gyro_angle`` (:attr:`gyrolib.rsf.RSFRecord.resolution`; 0 or absent: full
        precision): a coarse one adds the ``quantization`` part.

    Returns
    -------
    Eps1Uncertainty

    Examples
    --------
    >>> import math, numpy as np
    >>> from gyrolib import rsf
    >>> cfg = rsf.SimulationConfig(gs=rsf.GsModel(motor_rate_max=math.inf))  # an ideal GS
    >>> sim = rsf.simulate_flight(cfg, seed=1)
    >>> res = rsf.calibrate(rsf.record_from_simulation(sim), 1.0)
    >>> u = rsf.eps1_uncertainty(res, cfg)
    >>> {k: f"{x * 1e6:.1f}" for k, x in u.parts.items()}    # ppm
    {'random': '0.6', 'encoder': '8.7', 'biases': '31.1', 'gs_scale': '0.0'}
    >>> err = u.mean - sim.eps1_sins[0] / (1 + sim.eps1_sins[0])
    >>> sem = res.eps1_stats()["sem"]
    >>> f"error {err * 1e6:.1f} ppm, σ {u.std * 1e6:.1f} ppm, SEM {sem * 1e6:.0f} ppm", u.valid
    ('error 27.3 ppm, σ 32.3 ppm, SEM 95 ppm', True)
    """
    v.check_instance("result", result, CalibrationResult)
    config = SimulationConfig() if config is None else v.check_instance(
        "config", config, SimulationConfig)
    false_alarm = v.check_in_range("false_alarm", false_alarm, 0.0, 1.0, low_open=True,
                                   high_open=True)
    tol_sins = _tolerance("sins_bias", sins_bias, config.sins.eps0)
    tol_gsb = _tolerance("gs_bias", gs_bias, config.gs.eps0)
    tol_gyro = _tolerance("gs_gyro_scale", gs_gyro_scale, config.gs.eps1)
    tol_sf = _tolerance("sf_prior", sf_prior, config.sins.eps1)
    if gs_scale is not None:
        gs_scale = v.check_nonnegative("gs_scale", gs_scale)
    if counts_per_rev is not None:
        cpr = v.check_int("counts_per_rev", counts_per_rev, 2)
    else:
        cpr = result.counts_per_rev or config.encoder.counts_per_rev
    iv = _kept_intervals(result, config)
    notes: list[str] = []
    random = _random_part(iv, config, notes)
    encoder = _end_points(result, iv.keep, iv.rate, cpr, config.encoder.position_error)
    sigma_b = math.hypot(tol_sins, tol_gsb)
    biases, b_hat, b_std = _bias_part(iv, sigma_b, notes)
    gs_part = _gs_scale_part(result, iv, config, tol_gyro, gs_scale)
    parts = {"random": random, "encoder": encoder, "biases": biases, "gs_scale": gs_part}
    quant = _quantization_part(result, iv, config, _check_resolution(resolution), cpr,
                               notes)
    if quant > 0.0:
        parts["quantization"] = quant
    std = math.sqrt(sum(p * p for p in parts.values()))
    checks = _checks(iv, std, sigma_b, b_hat, b_std, tol_sf, false_alarm)
    tolerances = {"sins_bias": tol_sins, "gs_bias": tol_gsb,
                  "gs_gyro_scale": None if gs_scale is not None else tol_gyro,
                  "gs_scale": gs_scale, "sf_prior": tol_sf}
    return Eps1Uncertainty(mean=iv.mean, std=std, parts=parts, tolerances=tolerances,
                           checks=checks, false_alarm=false_alarm,
                           bias_estimate=b_hat, bias_estimate_std=b_std, n=iv.n,
                           notes=tuple(notes))


def _check_resolution(resolution: Mapping[str, float] | None) -> dict[str, float]:
    """The columns' steps, checked: known names, finite values >= 0."""
    if resolution is None:
        return {}
    if not isinstance(resolution, Mapping):
        raise TypeError("resolution must be a mapping of column name to step (rad); got "
                        f"{type(resolution).__name__}")
    known = ("sins_increment", "gs_angle", "gs_gyro_angle", "encoder_counts")
    out = {}
    for name, step in resolution.items():
        if name not in known:
            raise ValueError(f"resolution: unknown column {name!r}; expected one of "
                             f"{', '.join(known)}")
        out[name] = v.check_nonnegative(f"resolution[{name!r}]", step)
    return out


@compact_repr
@dataclass(frozen=True)
class _Intervals:
    """The intervals of a result that the mean uses (those without a reversal inside)."""

    keep: np.ndarray        # mask over the result's intervals
    e: np.ndarray           # ε̂1_i
    rate: np.ndarray        # ω_i, signed
    arate: np.ndarray       # |ω_i|
    time_used: float        # Σ Δt_i, s
    total_turn: float       # Σ |T_i|, rad
    mean: float             # ε̄
    sigma_i: np.ndarray     # the random σ of ε̂1_i the sensors' model predicts

    @property
    def n(self) -> int:
        return int(self.e.size)


def _kept_intervals(result: CalibrationResult, config: SimulationConfig) -> _Intervals:
    """The intervals without a reversal inside, their turns and the model's σ of each."""
    keep = ~np.asarray(result.reversal, bool)
    e = np.asarray(result.eps1_hat, float)[keep]
    if e.size == 0:
        raise ValueError("result must hold at least one interval without a reversal inside")
    rate = np.asarray(result.rate, float)[keep]            # signed
    arate = np.asarray(result.abs_rate, float)[keep]
    turn = arate * result.samples[keep] * result.dt        # |T_i|, the absolute turn used
    sigma_i = _random_std(config, result, arate) * (
        result.period / result.dt / result.samples[keep]) * np.sqrt(result.segments[keep])
    return _Intervals(keep=keep, e=e, rate=rate, arate=arate,
                      time_used=float(np.sum(result.samples[keep]) * result.dt),
                      total_turn=float(np.sum(turn)), mean=float(np.mean(e)), sigma_i=sigma_i)


def _random_part(iv: _Intervals, config: SimulationConfig, notes: list[str]) -> float:
    """The intervals' scatter with the lag-1 autocovariance, floored by the model's noise."""
    noise = math.sqrt((config.sins.arw**2 + config.gs.arw**2) * iv.time_used) / iv.total_turn
    n = iv.n
    if n > 1:
        d = iv.e - iv.mean
        g0 = float(np.sum(d * d)) / n
        g1 = float(np.sum(d[1:] * d[:-1])) / n
        hac = math.sqrt(max(g0 + 2.0 * (1.0 - 1.0 / n) * g1, 0.0) / n)
    else:
        notes.append("one interval: the random part is the sensors' model's alone")
        hac = float(iv.sigma_i[0])
    return max(hac, noise)


def _bias_part(iv: _Intervals, sigma_b: float, notes: list[str]
               ) -> tuple[float, float | None, float | None]:
    """The biases' part, with b̂ = b_S − b_G and its σ when the roll rate reverses (weighted
    least squares on ε̂1_i = ε1 + b/ω_i), else ``None`` for both."""
    m_inv = float(np.mean(1.0 / iv.rate))
    n, rate, e = iv.n, iv.rate, iv.e
    if not (np.any(rate > 0) and np.any(rate < 0) and n >= 3):
        return abs(m_inv) * sigma_b, None, None
    x = np.column_stack([np.ones(n), 1.0 / rate])
    w = 1.0 / iv.sigma_i**2
    a = x.T @ (x * w[:, None])
    cov = np.linalg.inv(a)
    beta = cov @ (x.T @ (w * e))
    chi2_red = float(np.sum(w * (e - x @ beta) ** 2)) / max(n - 2, 1)
    b_hat = float(beta[1])
    b_std = float(math.sqrt(cov[1, 1] * max(chi2_red, 1.0)))
    notes.append(f"the roll rate reverses: the biases' difference b_S − b_G = "
                 f"{math.degrees(b_hat) * 3600:.4g} ± {math.degrees(b_std) * 3600:.3g} "
                 "deg/h estimated from the record")
    return abs(m_inv) * math.hypot(b_hat, b_std), b_hat, b_std


def _gs_scale_part(result: CalibrationResult, iv: _Intervals, config: SimulationConfig,
                   tol_gyro: float, gs_scale: float | None) -> float:
    """The GS angle's scale tolerance times the share of the turn it scales."""
    if gs_scale is not None:
        return gs_scale
    if result.gs_gyro_turn is not None:
        share = np.asarray(result.gs_gyro_turn, float)[iv.keep] / (
            iv.rate * result.samples[iv.keep] * result.dt)
        return tol_gyro * abs(float(np.mean(share)))
    if result.counts_per_rev is not None:      # encoder counts, no GS gyro: the encoder's
        return 0.0
    w_unc = np.maximum(iv.arate - config.gs.motor_rate_max, 0.0)
    return tol_gyro * float(np.mean(w_unc / iv.arate))


def _checks(iv: _Intervals, std: float, sigma_b: float, b_hat: float | None,
            b_std: float | None, tol_sf: float, false_alarm: float) -> tuple[dict, ...]:
    """The run's checks (scatter, bias, prior), Šidák at the family-wise rate."""
    specs: list[tuple[str, float, float | None]] = []   # (test, statistic, dof or None)
    if iv.n > 1:
        specs.append(("scatter", float(np.sum(((iv.e - iv.mean) / iv.sigma_i) ** 2)),
                      iv.n - 1))
    if b_hat is not None:
        specs.append(("bias", b_hat / math.hypot(sigma_b, b_std), None))
    specs.append(("prior", iv.mean / math.hypot(tol_sf, std), None))
    a = 1.0 - (1.0 - false_alarm) ** (1.0 / len(specs))
    zlim = math.sqrt(float(chi2_ppf(1.0 - a, 1)))
    checks = []
    for test, stat, dof in specs:
        if dof is not None:
            lo, hi = 0.0, float(chi2_ppf(1.0 - a, dof))
            passed = stat <= hi
        else:
            lo, hi = -zlim, zlim
            passed = abs(stat) <= zlim
        checks.append({"test": test, "statistic": float(stat), "low": float(lo),
                       "high": float(hi), "passed": bool(passed),
                       "reason_code": REASON_CODES[test],
                       "message": _message(test, stat, hi, dof, iv.mean, b_hat, sigma_b,
                                           tol_sf)})
    return tuple(checks)


def _message(test: str, stat: float, hi: float, dof: int | None, mean: float,
             b_hat: float | None, sigma_b: float, tol_sf: float) -> str:
    """The sentence that says what a failed check means and what to try."""
    if test == "scatter":
        return (f"the intervals' scatter exceeds the sensors' error model: "
                f"sum of squared normalized deviations {stat:.4g} > {hi:.4g} "
                f"(chi-square, {dof} dof): noisier sensors than --params states, or the "
                "GS angle slips")
    if test == "bias":
        return (f"the biases' difference estimated from the reversing roll, "
                f"{math.degrees(b_hat) * 3600:.4g} deg/h, is {stat:+.3g} sigma from 0 "
                f"(tolerance {math.degrees(sigma_b) * 3600:.3g} deg/h): the gyros' "
                "biases exceed their tolerances ([sins] eps0, [gs] eps0)")
    return (f"eps1_hat_mean {mean * 1e6:.4g} ppm is {stat:+.3g} sigma outside the "
            f"roll gyro's scale-factor tolerance {tol_sf * 1e6:.3g} ppm ([sins] "
            "eps1 in --params): a record of another gyro, or a wrong unit")
