"""Paper GC applied to a measurement record: the 10-state Kalman filter of Eq. (8) run on
the angle-sensor and inclinometer readings of a gyro in gyrocompass mode (:func:`calibrate`).

The filter is the one of the covariance analysis (:func:`gyrolib.gc.covariance_analysis`):
``F`` frozen at the nominal float angle ``β_n`` of each step's midpoint, exact Van Loan
transition and process noise expanded to first order in ``(sin β_n, cos β_n)`` about points
:data:`gyrolib.gc.SEGMENT` rad apart, sequential scalar Joseph updates (the kernels of
:mod:`gyrolib.filtering.kernels`, compiled for the 10 states).  On a record it also

* subtracts the nominal motion ``β_n(t)`` (Eq. (4), from rest at t = 0, integrated along the
  record by the exponential integrator of :func:`gyrolib.gc.nominal_half_steps`) from the
  angle sensor, which then reads ``Δβ``;
* discretizes a step that is not the nominal ``dt`` at its own length: a gap of ``n`` whole
  steps plus a remainder is ``n`` predictions at ``dt`` (no update) and one exact Van Loan
  step of the remainder; a step within 5 % of ``n dt`` (time-stamp jitter) is ``n`` regular
  steps and a short shift ``exp(F δ)`` (Taylor series, exact to O(δ³) in the process
  noise), which costs little more than a regular step;
* skips a missing (NaN) measurement, and rejects a measurement whose normalized innovation
  squared ``ν²/S`` exceeds the χ²(1) quantile of ``gate`` (default 99.99 %), reporting it;
* keeps the diagnostics that say whether the model fits the gyro: the mean normalized
  innovation squared (NIS) of each sensor against its χ² band, and the autocorrelation of
  the normalized innovations (whiteness, a portmanteau test) {cite:p}`BarShalom2001`;
* declares the run invalid when the filter has lost lock (:attr:`CalibrationResult.valid`,
  :attr:`CalibrationResult.reason`): the gate rejected more than ``max_rejected`` of a
  sensor's measurements, or a sensor's mean NIS is far outside its band (``nis_range``) —
  an angle column in degrees, an inclinometer of the wrong sign;
* accumulates the innovations' log-likelihood (:func:`innovation_log_likelihood`, which
  :func:`gyrolib.gc.fit_noise` maximizes);
* streams: the record is processed in chunks with a constant-size state (``x``, ``P``, the
  nominal motion's integrator state), and estimates and σ are stored every ``store_every``
  rows.  A chunked run equals a one-shot run.  The step tables (one Van Loan exponential
  per expansion point) are kept for the next run with the same parameters.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Iterable
from concurrent.futures import Executor
from dataclasses import dataclass
from typing import Final, NamedTuple

import numpy as np
from numba import njit
from numpy.typing import NDArray

from gyrolib import _compile_note  # noqa: F401  (a line on stderr at the first compile)
from gyrolib import _validation as v
from gyrolib._repr import compact_repr
from gyrolib.filtering.consistency import chi2_ppf, gated_nis_band
from gyrolib.filtering.discretization import covariance_factor, van_loan, van_loan_derivatives
from gyrolib.filtering.kernels import kalman_kernels
from gyrolib.gc.analysis.montecarlo import simulate_truth
from gyrolib.gc.logs.record import MEASUREMENT_COLUMNS, GCRecord
from gyrolib.gc.model import instrument
from gyrolib.gc.model.discretization import (
    SEGMENT,
    NominalIntegrator,
    nominal_half_steps,
    system_matrix_parts,
)
from gyrolib.gc.model.params import (
    EARTH_RATE,
    MEASUREMENT_NAMES,
    STATE_NAMES,
    GyrocompassParams,
    latitude_text,
    state_index,
)
from gyrolib.gc.model.state_space import (
    initial_covariance,
    measurement_matrix,
    measurement_noise_covariance,
    noise_input_matrix,
    process_noise_intensity,
)
from gyrolib.units import from_si
from gyrolib.verdict import compared

__all__ = [
    "EARTH_RATE_TOLERANCE",
    "CalibrationResult",
    "SimulatedRecord",
    "calibrate",
    "earth_rate_mismatch",
    "innovation_log_likelihood",
    "simulate_record",
    "simulate_records",
]

N: Final[int] = len(STATE_NAMES)
M: Final[int] = len(MEASUREMENT_NAMES)

#: A step within this fraction of ``dt`` of a whole number of ``dt`` (time-stamp jitter) is
#: propagated by the regular steps and a short Taylor shift, not a matrix exponential.
SMALL_SHIFT: Final[float] = 0.05

#: The constants of a real instrument that :func:`calibrate` estimates with the state (a
#: bias-separated filter), as the model declares them (:data:`gyrolib.gc.TERMS`): a null
#: offset of the angle sensor (rad), a bias of each inclinometer (m/s²) and the relative
#: error κ of the scale common to ``H/f`` and the angle sensor's gain (the reading gains
#: ``κ β_n``).  Their priors are ``params.sigma_as_offset``, ``sigma_incl_bias`` (both
#: inclinometers), ``sigma_hf_scale``.  (:func:`calibrate` reads the declaration at each
#: call; the result's ``bias_names`` are the terms it carried.)
BIAS_NAMES: Final[tuple[str, ...]] = tuple(t.name for t in instrument.TERMS)
NB: Final[int] = len(BIAS_NAMES)

#: Rejected measurements listed individually in a result (all are counted).
MAX_LISTED_REJECTIONS: Final[int] = 10000

# the shared kernels (gyrolib.filtering.kernels) compiled for the 10 states of Eq. (8)
_kernels = kalman_kernels(N)
predict_state = _kernels.predict_state
predict_covariance = _kernels.predict_covariance
measurement_projection = _kernels.measurement_projection
joseph_scalar_update = _kernels.joseph_scalar_update


# Result ---------------------------------------------------------------------------------
@compact_repr
@dataclass(frozen=True)
class CalibrationResult:
    """The filter of paper GC run on a record (SI throughout).

    * ``t`` (ns,), ``x`` (ns, 10), ``std`` (ns, 10): estimate and σ of every state (order
      :data:`gyrolib.gc.STATE_NAMES`) every ``store_every`` rows and at the last row;
      ``nis_window`` (ns, 3): mean NIS of each sensor over the rows since the previous stored
      point (``nan`` where none), ``nis_window_count`` (ns, 3) how many;
    * ``x_final``, ``P_final``, ``t_final``: the filter at the last row;
    * ``rows``; per sensor (3,): ``used``, ``missing`` (NaN), ``rejected`` (gate);
      ``rows_used`` (rows with at least one measurement used and none rejected),
      ``rows_rejected`` (rows with at least one rejected): disjoint, so ``rows_used +
      rows_rejected <= rows``, the rest being rows with every value missing;
      ``rejected_t``, ``rejected_sensor``, ``rejected_nis``: the first
      :data:`MAX_LISTED_REJECTIONS` rejections;
    * ``nis_sum`` (3,): sum of the NIS of the used measurements, ``log_s_sum`` (3,): sum of
      the logarithms of their innovation variances ``S`` (together the innovations'
      log-likelihood, :attr:`log_likelihood`); ``acf`` (3, lags): the autocorrelation at
      lags 1…lags of each sensor's normalized innovations ``ν/√S``;
    * ``gaps`` (steps longer than 1.5 ``dt``), ``gap_time`` (s of missing rows),
      ``irregular_steps`` (remainders discretized exactly at their own length),
      ``jittered_steps`` (steps within 5 % of a whole number of ``dt``, shifted in time),
      ``gate`` (probability);
    * ``bias_names`` (nb,), ``bias_groups``: the instrument constants carried (every term
      of :data:`gyrolib.gc.TERMS`, those with prior 0 known to be 0) and the part of σ(ω_gc)
      each belongs to; ``bias_prior``, ``bias_estimate`` (nb,), ``bias_cov``,
      ``bias_info`` (nb, nb), ``bias_response`` (nb, 10): their bias-separated estimate;
    * ``max_rejected``, ``nis_range``: the limits of a valid run (:attr:`valid`,
      :attr:`reason`): a sensor whose share of gate rejections exceeds ``max_rejected``, or
      whose mean NIS is outside ``nis_range``, has lost lock or is not the sensor the model
      describes, and the estimate is not a result;
    * ``measurement_steps`` (3,): the step each sensor's column is recorded in (SI, 0: full
      precision; :attr:`GCRecord.resolution`), whose rounding, ``step²/12``, the filter adds
      to that sensor's measurement noise (:data:`gyrolib.gc.MEASUREMENT_NAMES` order);
    * ``record_latitude``: the latitude (rad) the record states (:attr:`GCRecord.latitude`),
      or ``None``.  When the parameters' Earth rate is not the one at that latitude
      (:func:`earth_rate_mismatch`), the run is not valid: Ω_h reads as drift, so a rate
      taken for another site moves ω̂_gc by the difference.
    """

    params: GyrocompassParams
    t: np.ndarray
    x: np.ndarray
    std: np.ndarray
    nis_window: np.ndarray
    nis_window_count: np.ndarray
    x_final: np.ndarray
    P_final: np.ndarray
    t_final: float
    rows: int
    used: np.ndarray
    missing: np.ndarray
    rejected: np.ndarray
    rows_used: int
    rows_rejected: int
    rejected_t: np.ndarray
    rejected_sensor: np.ndarray
    rejected_nis: np.ndarray
    nis_sum: np.ndarray
    log_s_sum: np.ndarray
    acf: np.ndarray
    gaps: int
    gap_time: float
    irregular_steps: int
    jittered_steps: int
    gate: float
    store_every: int
    max_rejected: float = 0.01
    nis_range: tuple[float, float] = (0.5, 2.0)
    false_alarm: float = 0.01
    nis_tolerance: float = 0.0
    bias_prior: np.ndarray | None = None
    bias_estimate: np.ndarray | None = None
    bias_cov: np.ndarray | None = None
    bias_info: np.ndarray | None = None
    bias_response: np.ndarray | None = None
    P_filter: np.ndarray | None = None
    bias_names: tuple[str, ...] = BIAS_NAMES
    bias_groups: tuple[str, ...] | None = None
    record_latitude: float | None = None
    measurement_steps: np.ndarray | None = None

    def __post_init__(self) -> None:
        v.check_instance("params", self.params, GyrocompassParams)
        ns = v.check_ndarray("t", self.t, ndim=1).size
        v.check_ndarray("x", self.x, shape=(ns, N))
        v.check_ndarray("std", self.std, shape=(ns, N))
        v.check_ndarray("x_final", self.x_final, shape=(N,))
        v.check_ndarray("P_final", self.P_final, shape=(N, N))
        for name in ("used", "missing", "rejected", "nis_sum", "log_s_sum"):
            if np.shape(getattr(self, name)) != (M,):
                raise ValueError(f"{name} must have shape ({M},)")
        v.check_in_range("max_rejected", self.max_rejected, 0.0, 1.0)
        object.__setattr__(self, "nis_range", _check_nis_range(self.nis_range))
        v.check_in_range("false_alarm", self.false_alarm, 0.0, 1.0, low_open=True,
                         high_open=True)
        v.check_in_range("nis_tolerance", self.nis_tolerance, 0.0, 1.0, high_open=True)
        if not isinstance(self.bias_names, tuple):
            raise TypeError("bias_names must be a tuple of the instrument constants' names")
        nb = len(self.bias_names)
        if self.bias_groups is None:   # the groups of the declared terms of these names
            declared = {t.name: t.group for t in instrument.TERMS}
            object.__setattr__(self, "bias_groups",
                               tuple(declared.get(nm, "instrument_biases")
                                     for nm in self.bias_names))
        if len(self.bias_groups) != nb:
            raise ValueError(f"bias_groups must hold one group per bias name ({nb})")
        for name, shape in (("bias_prior", (nb,)), ("bias_estimate", (nb,)),
                            ("bias_cov", (nb, nb)), ("bias_info", (nb, nb)),
                            ("bias_response", (nb, N)), ("P_filter", (N, N))):
            val = getattr(self, name)
            if val is None:     # no instrument constants: the paper's filter
                val = self.P_final.copy() if name == "P_filter" else np.zeros(shape)
            object.__setattr__(self, name, v.check_ndarray(name, val, shape=shape))

    # estimates -----------------------------------------------------------------------
    def estimate(self, name: str) -> np.ndarray:
        """Stored estimates of state ``name`` (SI) at ``t``."""
        return self.x[:, state_index(name)]

    def sigma(self, name: str) -> np.ndarray:
        """Stored filter standard deviations of state ``name`` (SI) at ``t``."""
        return self.std[:, state_index(name)]

    @property
    def omega_gc(self) -> float:
        """Final estimate of the systematic drift ω_gc (rad/s)."""
        return float(self.x_final[state_index("omega_gc")])

    @property
    def omega_gc_std(self) -> float:
        """Its standard deviation (rad/s) from the filter's covariance."""
        i = state_index("omega_gc")
        return float(math.sqrt(max(self.P_final[i, i], 0.0)))

    def _omega_variance(self, columns: tuple[int, ...]) -> float:
        """Var(ω_gc) of the filter that carries the instrument constants ``columns`` (of
        those with a prior) and no others, from the run's information about them."""
        i = state_index("omega_gc")
        var = float(self.P_filter[i, i])
        idx = [c for c in columns if self.bias_prior[c] > 0.0]
        if not idx:
            return var
        info = self.bias_info[np.ix_(idx, idx)] + np.diag(1.0 / self.bias_prior[idx] ** 2)
        vv = self.bias_response[idx, i]
        return var + float(vv @ np.linalg.solve(info, vv))

    @property
    def omega_gc_std_parts(self) -> dict[str, float]:
        """σ(ω_gc) (rad/s) in three parts that add in quadrature to :attr:`omega_gc_std`:
        ``"noise"`` (the filter of Eq. (8) with the paper's priors), ``"instrument_biases"``
        (what the angle sensor's null offset and the inclinometer biases add, with their
        priors ``sigma_as_offset``, ``sigma_incl_bias``) and ``"scale"`` (what the common
        scale error of ``H/f`` and the gain adds, prior ``sigma_hf_scale``; about
        ``sigma_hf_scale · Ω_h``, :attr:`GyrocompassParams.scale_drift_sigma`)."""
        groups = self.bias_groups
        v0 = self._omega_variance(())
        vb = self._omega_variance(tuple(c for c, g in enumerate(groups)
                                        if g == "instrument_biases"))
        va = self._omega_variance(tuple(range(len(groups))))
        return {"noise": math.sqrt(max(v0, 0.0)),
                "instrument_biases": math.sqrt(max(vb - v0, 0.0)),
                "scale": math.sqrt(max(va - vb, 0.0))}

    @property
    def instrument(self) -> dict[str, dict[str, float]]:
        """The instrument constants (:data:`BIAS_NAMES`, SI): estimate, σ and prior of each
        that has a prior (the others are not estimated)."""
        sd = np.sqrt(np.clip(np.diag(self.bias_cov), 0.0, None))
        return {name: {"estimate": float(self.bias_estimate[c]), "std": float(sd[c]),
                       "prior": float(self.bias_prior[c])}
                for c, name in enumerate(self.bias_names) if self.bias_prior[c] > 0.0}

    # the model checks as a gate ----------------------------------------------------------
    def split_tests(self, fractions: tuple[float, ...] = (0.25, 0.5, 0.75)
                    ) -> list[tuple[float, float]]:
        """The split-record consistency tests: for each fraction ``f``, the time ``t_f`` of
        the stored row nearest to ``f · t_final`` and ``z = (ω̂(t_f) − ω̂_T) /
        √(σ²(t_f) − σ_T²)``.  For a constant ω_gc in a model that fits, the final estimate
        is the efficient one and the difference is independent of it, so its variance is
        the difference of the variances (a Hausman test) and ``z`` is standard normal; a
        drift that changes within the record, or a step in a sensor, moves it."""
        if not isinstance(fractions, tuple | list) or not all(
                isinstance(f, int | float) and not isinstance(f, bool) and 0.0 < f < 1.0
                for f in fractions):
            raise ValueError(f"fractions must be a sequence of numbers in (0, 1); got "
                             f"{fractions!r}")
        i = state_index("omega_gc")
        out = []
        if self.t.size < 3:
            return out
        wt = self.omega_gc
        vt = self.omega_gc_std ** 2
        for f in fractions:
            k = int(np.argmin(np.abs(self.t - f * self.t_final)))
            if k >= self.t.size - 1:
                continue
            dv = float(self.std[k, i]) ** 2 - vt
            if not dv > 1e-6 * vt:     # the later data carry no information: no test
                continue
            out.append((float(self.t[k]), float((self.x[k, i] - wt) / math.sqrt(dv))))
        return out

    def prior_tests(self) -> list[dict]:
        """The estimate of each constant with a prior against that prior: ψ, ω_gc, δ, γ
        (Eq. (8): constant states, prior ``initial_covariance(params)``) and each instrument
        term with a prior > 0 (:data:`gyrolib.gc.TERMS`).  For a constant ``x`` with prior
        ``N(0, P₀)`` and posterior variance ``P``, the estimate ``x̂`` is ``N(0, P₀ − P)``
        when the model holds (the law of total variance: the estimate's spread is what the
        data removed from the prior), so ``z = x̂/√(P₀ − P)`` is standard normal: one
        two-sided test per constant (equivalent, per constant, to the normalized posterior
        ``d = x̂ᵀ(P₀ − P)⁻¹x̂`` against χ²₁; the per-constant form names the constant at
        fault).  A constant the record does not inform (``P₀ − P < 10⁻⁶ P₀``) has no test.
        Each entry: ``constant``, ``z``, ``estimate``, ``prior`` (σ, SI)."""
        p0 = initial_covariance(self.params)
        out = []
        for name in ("psi", "omega_gc", "delta", "gamma"):
            i = state_index(name)
            out.append((name, float(self.x_final[i]), float(p0[i, i]),
                         float(self.P_final[i, i])))
        for c, name in enumerate(self.bias_names):
            if self.bias_prior[c] > 0.0:
                out.append((name, float(self.bias_estimate[c]), float(self.bias_prior[c]) ** 2,
                            float(self.bias_cov[c, c])))
        tests = []
        for name, est, prior_var, post_var in out:
            dv = prior_var - post_var
            if not dv > 1e-6 * prior_var:
                continue
            tests.append({"constant": name, "z": est / math.sqrt(dv), "estimate": est,
                          "prior": math.sqrt(prior_var)})
        return tests

    def _prior_cause(self, name: str, est: float) -> tuple[str, str]:
        """The reason code and the likely cause of a constant far outside its prior."""
        p = self.params
        if name == "omega_gc":
            # Ω_h reads as drift: the latitude whose Ω_h would explain ω̂ (φ from the
            # parameters' own Earth rate)
            # (in the stated hemisphere: Ω_h is the same on both sides of the equator)
            cos_lat = (p.Omega_h + est) / EARTH_RATE
            stated = math.degrees(p.latitude)
            lat = (math.copysign(math.degrees(math.acos(cos_lat)), stated)
                   if abs(cos_lat) <= 1.0 else None)
            text = (f"omega_gc far outside its prior {from_si(p.sigma_gc0, 'arcsec_paper/s'):.3g}"
                    " arcsec/s (paper's arcsec): a site rate for another latitude reads as "
                    f"drift (stated {latitude_text(stated, 4)}"
                    + (f"; about {lat:.3g} deg would explain it: --latitude" if lat is not None
                       else "") + "), or the gyro drifts more than the prior allows "
                    "(--drift-prior), or H/f, the gain or the logger's clock is off by about "
                    f"{est / p.Omega_h:.2g} (--scale-tolerance, --clock-tolerance)")
            return ("prior_latitude" if lat is not None else "prior_drift"), text
        causes = {
            "psi": ("prior_tilt", "the azimuth misalignment psi beyond its prior sigma_psi0"),
            "delta": ("prior_tilt", "the platform tilt delta beyond its prior sigma_delta0 "
                      "(an unlevelled platform, or an inclinometer bias beyond its prior: "
                      "--inclinometer-bias-prior)"),
            "gamma": ("prior_tilt", "the platform tilt gamma beyond its prior sigma_gamma0 "
                      "(an unlevelled platform, or an inclinometer bias beyond its prior: "
                      "--inclinometer-bias-prior)"),
            "angle_offset": ("prior_offset", "the angle sensor's null offset beyond its prior "
                             "(--offset-prior; a logger that starts late, --t0)"),
            "inclinometer_y_bias": ("prior_incl_bias", "inclinometer_y's bias beyond its "
                                    "prior (--inclinometer-bias-prior; wrong unit or sign?)"),
            "inclinometer_z_bias": ("prior_incl_bias", "inclinometer_z's bias beyond its "
                                    "prior (--inclinometer-bias-prior; wrong unit or sign?), "
                                    "or the gyro's input axis tilted out of the horizontal "
                                    f"by about {from_si(-est / p.g, 'arcmin'):.3g} arcmin: "
                                    "it senses Omega_v as a tilt gamma that inclinometer_z "
                                    "does not read, which is the same as that bias"),
            "scale": ("prior_scale", "H/f or the angle sensor's gain off by more than its "
                      "tolerance (--scale-tolerance)"),
            "clock": ("prior_clock", "the logger's time scale off by more than its tolerance "
                      "(--clock-tolerance; a logger rate labelled wrong?)"),
        }
        return causes.get(name, ("prior_" + name, f"{name} beyond its prior"))

    def model_tests(self) -> list[dict]:
        """Every check of the model on the record, each at the level that makes their
        family-wise false-alarm rate :attr:`false_alarm` (Šidák: ``1 − (1 − a)^(1/n)`` for
        ``n`` tests): per sensor the two-sided band of the mean NIS and the portmanteau
        whiteness test of the normalized innovations over ``lags`` lags (χ²(lags)), the
        split-record tests (:meth:`split_tests`, two-sided normal) and the prior of each
        constant (:meth:`prior_tests`, two-sided normal).  The NIS band is that of the
        mean of ``used`` NIS values the χ² gate let through, within :attr:`nis_range` (a
        mean NIS beyond it is a lost lock, ``reason_code`` ``lost_lock_nis``, even where
        the band of a few samples is wider: one band for the statistic)
        (:func:`gyrolib.filtering.gated_nis_band`: centred on 0.998396, not 1, at the
        99.99 % gate), widened by the relative :attr:`nis_tolerance` only when one is
        given (default 0: none is needed; the angle sensor's mean NIS of about 0.996 on
        an hour of the truth model, which a tolerance of 0.5 % used to hide, is the gate's
        0.9984 times the record's own measurement noise, whose sample variance scatters
        by ``√(2/n)``, 0.075 % over an hour: tests/gc/test_nis_expectation.py).  Each
        entry: ``test``,
        ``sensor``, ``statistic``, ``low``, ``high``, ``passed``, ``reason_code`` (and, for
        a prior, ``constant`` and ``cause``)."""
        used = [q for q in range(M) if self.used[q] > 0]
        splits = self.split_tests()
        priors = self.prior_tests()
        n = 2 * len(used) + len(splits) + len(priors)
        if n == 0:
            return []
        a = 1.0 - (1.0 - self.false_alarm) ** (1.0 / n)
        lags = self.acf.shape[1]
        out = []
        for q in used:
            lo, hi = gated_nis_band(float(self.used[q]), self.gate, 0.5 * a, 1.0 - 0.5 * a)
            # one band for the statistic: the test's band within the lock range (a mean
            # NIS beyond nis_range is a lost lock whatever the band of a few samples)
            lo = max(float(lo) * (1.0 - self.nis_tolerance), self.nis_range[0])
            hi = min(float(hi) * (1.0 + self.nis_tolerance), self.nis_range[1])
            nis = float(self.nis_mean[q])
            lock = self.nis_range[0] <= nis <= self.nis_range[1]
            out.append({"test": "mean NIS", "sensor": MEASUREMENT_NAMES[q], "statistic": nis,
                        "low": lo, "high": hi, "passed": bool(lo <= nis <= hi),
                        "reason_code": "misfit_nis" if lock else "lost_lock_nis"})
            w = float(self.whiteness[q])
            lim = float(chi2_ppf(1.0 - a, lags))
            out.append({"test": f"whiteness (portmanteau, {lags} lags)",
                        "sensor": MEASUREMENT_NAMES[q], "statistic": w, "low": 0.0,
                        "high": lim, "passed": bool(w <= lim),
                        "reason_code": "misfit_whiteness"})
        zlim = math.sqrt(float(chi2_ppf(1.0 - a, 1)))     # P(|z| > zlim) = a, z ~ N(0, 1)
        for t_s, z in splits:
            out.append({"test": f"split-record omega_gc (t = {t_s:.4g} s vs end)",
                        "sensor": "angle_sensor", "statistic": z, "low": -zlim, "high": zlim,
                        "passed": bool(abs(z) <= zlim), "reason_code": "misfit_split"})
        for pt in priors:
            code, cause = self._prior_cause(pt["constant"], pt["estimate"])
            out.append({"test": f"prior of {pt['constant']} (estimate/sqrt(P0 - P))",
                        "sensor": "prior", "statistic": pt["z"], "low": -zlim, "high": zlim,
                        "passed": bool(abs(pt["z"]) <= zlim), "reason_code": code,
                        "constant": pt["constant"], "cause": cause})
        return out

    def _misfit_parts(self) -> list[str]:
        parts = []
        for tst in self.model_tests():
            if tst["passed"] or tst["reason_code"] == "lost_lock_nis":  # said as lost lock
                continue
            band = _band(tst["statistic"], tst["low"], tst["high"])
            if tst["sensor"] == "prior":
                parts.append(f"prior of {tst['constant']}: estimate/sqrt(P0 - P) = {band}: "
                             f"{tst['cause']}")
                continue
            parts.append(f"{tst['sensor']}: {tst['test']} failed: {band} (family "
                         f"false-alarm rate {100 * self.false_alarm:.3g} %)")
        return parts

    @property
    def reason_codes(self) -> tuple[str, ...]:
        """Stable codes of what makes the run not valid, in the order of :attr:`reason`
        (each once): ``latitude`` (the Earth rate is not the record's latitude's),
        ``lost_lock_gate``, ``lost_lock_nis``, then the codes of the failed model checks
        (``misfit_nis``, ``misfit_whiteness``, ``misfit_split``, ``prior_latitude``,
        ``prior_drift``, ``prior_scale``, ``prior_clock``, ``prior_offset``,
        ``prior_incl_bias``, ``prior_tilt``); empty when valid."""
        codes = []
        if self.record_latitude is not None and earth_rate_mismatch(self.params,
                                                                    self.record_latitude):
            codes.append("latitude")
        share = self.rejected_share
        lo, hi = self.nis_range
        for q in range(M):
            if share[q] > self.max_rejected:
                codes.append("lost_lock_gate")
            if self.used[q] > 0 and not lo <= self.nis_mean[q] <= hi:
                codes.append("lost_lock_nis")
        codes += [t["reason_code"] for t in self.model_tests() if not t["passed"]]
        return tuple(dict.fromkeys(codes))

    @property
    def misfit(self) -> bool:
        """True when a model check fails (:meth:`model_tests`): the model does not describe
        the record and σ may not cover the truth."""
        return bool(self._misfit_parts())

    @property
    def lost_lock(self) -> bool:
        """True when the gate rejected more than ``max_rejected`` of a sensor's samples or a
        sensor's mean NIS is outside ``nis_range``."""
        return bool(self._invalid_parts())

    # diagnostics ---------------------------------------------------------------------
    @property
    def nis_mean(self) -> np.ndarray:
        """Mean NIS of each sensor over its used measurements (1 when the model fits)."""
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(self.used > 0, self.nis_sum / np.maximum(self.used, 1), np.nan)

    def nis_band(self, confidence: float = 0.99) -> np.ndarray:
        """(3, 2): two-sided ``confidence`` band of the mean NIS of ``used[q]`` independent
        χ²(1) values that the gate let through (:func:`gyrolib.filtering.gated_nis_band`;
        without a gate ``χ²_{(1∓c)/2}(n)/n``)."""
        c = v.check_in_range("confidence", confidence, 0.0, 1.0, low_open=True,
                             high_open=True)
        n = np.maximum(self.used, 1).astype(float)
        lo, hi = gated_nis_band(n, self.gate, 0.5 * (1.0 - c), 0.5 * (1.0 + c))
        return np.column_stack([lo, hi])

    @property
    def whiteness(self) -> np.ndarray:
        """(3,): the portmanteau statistic ``n Σ_l ρ_l²`` of each sensor's normalized
        innovations (χ²(lags) when they are white)."""
        return self.used * np.sum(self.acf**2, axis=1)

    def whiteness_limit(self, confidence: float = 0.99) -> float:
        """The χ²(lags) quantile the :attr:`whiteness` statistic stays below when white."""
        c = v.check_in_range("confidence", confidence, 0.0, 1.0, low_open=True,
                             high_open=True)
        return float(chi2_ppf(c, self.acf.shape[1]))

    def fits(self, confidence: float = 0.99) -> np.ndarray:
        """(3,) bool: each sensor's mean NIS is in its band and its innovations are white."""
        band = self.nis_band(confidence)
        nis = self.nis_mean
        ok = (nis >= band[:, 0]) & (nis <= band[:, 1])
        return ok & (self.whiteness <= self.whiteness_limit(confidence)) & (self.used > 0)

    def verdict(self, confidence: float = 0.99) -> str:
        """One line: does the model fit the record (NIS in band, innovations white)?"""
        ok = self.fits(confidence)
        if np.all(ok):
            return (f"model fits: every sensor's mean NIS is inside its {confidence:.0%} "
                    "chi-square band and its innovations are white")
        band = self.nis_band(confidence)
        parts = []
        for q, name in enumerate(MEASUREMENT_NAMES):
            if ok[q]:
                continue
            if self.used[q] == 0:
                parts.append(f"{name} has no usable measurement")
                continue
            nis = self.nis_mean[q]
            if nis > band[q, 1]:
                parts.append(f"{name} NIS {nis:.3g} above its band (<= {band[q, 1]:.3g})")
            elif nis < band[q, 0]:
                parts.append(f"{name} NIS {nis:.3g} below its band (>= {band[q, 0]:.3g})")
            if self.whiteness[q] > self.whiteness_limit(confidence):
                parts.append(f"{name} innovations correlated (portmanteau "
                             f"{self.whiteness[q]:.3g} > {self.whiteness_limit(confidence):.3g})")
        return "model does NOT fit: " + "; ".join(parts)

    @property
    def log_likelihood(self) -> float:
        """The innovations log-likelihood of the record under ``params``,
        ``−½ Σ (ln 2π S + ν²/S)`` over the used measurements (the prediction-error
        decomposition of the Gaussian likelihood; rejected and missing ones left out)."""
        return _log_likelihood(self.used, self.log_s_sum, self.nis_sum)

    @property
    def rejected_share(self) -> np.ndarray:
        """(3,): the share of each sensor's measurements (not missing) the gate rejected."""
        seen = self.used + self.rejected
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(seen > 0, self.rejected / np.maximum(seen, 1), 0.0)

    def _invalid_parts(self) -> list[str]:
        parts = []
        if self.record_latitude is not None:
            mismatch = earth_rate_mismatch(self.params, self.record_latitude)
            if mismatch:
                parts.append(mismatch)
        share = self.rejected_share
        nis = self.nis_mean
        lo, hi = self.nis_range
        for q, name in enumerate(MEASUREMENT_NAMES):
            if share[q] > self.max_rejected:
                seen = int(self.used[q] + self.rejected[q])
                parts.append(f"{name}: {int(self.rejected[q])} of {seen} samples "
                             f"({100 * share[q]:.3g} %) rejected by the chi-square gate "
                             f"(limit {100 * self.max_rejected:.3g} %)"
                             + _inclinometer_lost(name, share[q], share[0]))
            if self.used[q] > 0 and not lo <= nis[q] <= hi:
                band = next((t for t in self.model_tests()
                             if t["test"] == "mean NIS" and t["sensor"] == name), None)
                shown = ("" if band is None else " NOT in "
                         + _band(nis[q], band["low"], band["high"]))
                parts.append(f"{name}: mean NIS {nis[q]:.4g}{shown}, beyond the lock range: "
                             "the filter lost lock")
        return parts

    @property
    def valid(self) -> bool:
        """False when the filter lost lock on the record (:attr:`lost_lock`) or a check of
        the model fails (:attr:`misfit`, at the family-wise false-alarm rate
        :attr:`false_alarm`); the estimate is then not a result."""
        return not (self._invalid_parts() or self._misfit_parts())

    @property
    def reason(self) -> str:
        """Why the run is not valid, naming each sensor and test at fault (``""`` when
        valid)."""
        return "; ".join(self._invalid_parts() + self._misfit_parts())

    def _rejected_summary(self, limit: int = 100) -> dict:
        """``rejected_t``: the times of the rows the gate rejected, each once (a row whose
        two sensors were rejected is one entry), in order, at most ``limit``;
        ``rejected_t_count``: how many rows were rejected; ``rejected_t_truncated``: whether
        ``rejected_t`` lists fewer than that."""
        times = np.unique(self.rejected_t)
        listed = times[:limit]
        return {"rejected_t": [float(x) for x in listed],
                "rejected_t_count": int(self.rows_rejected),
                "rejected_t_truncated": bool(listed.size < int(self.rows_rejected))}

    def summary(self) -> dict:
        """The result as a JSON-ready dict (SI; a value that is not finite is ``None``).
        ``nis_band``, ``whiteness_limit``, ``model_fits`` and ``verdict`` are those of the
        checks that decide validity (:meth:`model_tests`: each sensor's mean NIS in its
        band, its innovations white, at the family-wise rate :attr:`false_alarm`)."""
        tests = self.model_tests()
        fit_tests = [t for t in tests if t["test"] == "mean NIS"
                     or t["test"].startswith("whiteness")]
        bands = {t["sensor"]: (t["low"], t["high"]) for t in tests if t["test"] == "mean NIS"}
        white = [t["high"] for t in tests if t["test"].startswith("whiteness")]
        failed = [f"{t['sensor']} {t['test']} {_band(t['statistic'], t['low'], t['high'])}"
                  for t in fit_tests if not t["passed"]]
        share = self.rejected_share
        return {
            "valid": self.valid,
            "reason": self.reason,
            "reason_codes": list(self.reason_codes),
            "lost_lock": self.lost_lock,
            "misfit": self.misfit,
            "omega_gc": self.omega_gc,
            "omega_gc_std": self.omega_gc_std,
            "omega_gc_std_parts": self.omega_gc_std_parts,
            "instrument": self.instrument,
            "false_alarm": self.false_alarm,
            "model_tests": self.model_tests(),
            "t_end": self.t_final,
            "rows": self.rows,
            "samples_used": self.rows_used,
            "samples_rejected": self.rows_rejected,
            "measurements": {name: {"used": int(self.used[q]), "missing": int(self.missing[q]),
                                    "rejected": int(self.rejected[q])}
                             for q, name in enumerate(MEASUREMENT_NAMES)},
            "nis": {name: _finite(self.nis_mean[q]) for q, name in enumerate(MEASUREMENT_NAMES)},
            "nis_band": {name: [_finite(bands[name][0]), _finite(bands[name][1])]
                         if name in bands else [None, None] for name in MEASUREMENT_NAMES},
            "whiteness": {name: float(self.whiteness[q])
                          for q, name in enumerate(MEASUREMENT_NAMES)},
            "whiteness_limit": white[0] if white else None,
            "model_fits": bool(fit_tests) and not failed,
            "verdict": ("model fits: every sensor's mean NIS is in its band and its "
                        "innovations are white" if fit_tests and not failed else
                        "model does NOT fit: " + ("; ".join(failed) if failed
                                                  else "no usable measurement")),
            "gate": self.gate,
            "rejected_share": {name: float(share[q])
                               for q, name in enumerate(MEASUREMENT_NAMES)},
            "max_rejected": self.max_rejected,
            "nis_range": list(self.nis_range),
            "log_likelihood": self.log_likelihood,
            "gaps": self.gaps,
            "gap_time": self.gap_time,
            "irregular_steps": self.irregular_steps,
            "jittered_steps": self.jittered_steps,
            **self._rejected_summary(),
            "states": {name: {"estimate": float(self.x_final[i]),
                              "std": float(math.sqrt(max(self.P_final[i, i], 0.0)))}
                       for i, name in enumerate(STATE_NAMES)},
            **self._quantization_summary(),
        }

    def _quantization_summary(self) -> dict:
        """``quantization`` (only for a record with a coarse column): per sensor its step,
        the rounding's variance ``step²/12`` and that variance's share of the sensor's
        measurement noise the filter carried (Eq. (8)'s ``R`` plus the rounding)."""
        steps = self.measurement_steps
        if steps is None or not np.any(steps > 0.0):
            return {}
        r = np.diag(measurement_noise_covariance(self.params))
        var = steps**2 / 12.0
        return {"quantization": {name: {"step": float(steps[q]), "variance": float(var[q]),
                                        "share_of_noise": float(var[q] / (r[q] + var[q]))}
                                 for q, name in enumerate(MEASUREMENT_NAMES) if steps[q] > 0}}


def _log_likelihood(used: np.ndarray, log_s_sum: np.ndarray, nis_sum: np.ndarray) -> float:
    """``−½ Σ (ln 2π S + ν²/S)`` from its per-sensor sums."""
    n = float(np.sum(used))
    return float(-0.5 * (n * math.log(2.0 * math.pi) + np.sum(log_s_sum) + np.sum(nis_sum)))


def _band(x: float, lo: float, hi: float) -> str:
    """``x NOT in [lo, hi]`` as :class:`gyrolib.verdict.Check` prints a band (the digits
    of :func:`gyrolib.verdict.compared`)."""
    sx, slo, shi = compared(x, lo, hi)
    return f"{sx} {'in' if lo <= x <= hi else 'NOT in'} [{slo}, {shi}]"


def _finite(x: float) -> float | None:
    """``x`` as a float, or ``None`` when it is not finite (JSON has no NaN)."""
    x = float(x)
    return x if math.isfinite(x) else None


# Nominal motion along the record ------------------------------------------------------------
class _Nominal:
    """β_n(t) of Eq. (4) on the half-step grid ``i dt/2`` (:class:`gyrolib.gc.NominalIntegrator`),
    integrated forward on demand and kept only over the window the current chunk needs
    (constant memory)."""

    def __init__(self, p: GyrocompassParams) -> None:
        self.integrator = NominalIntegrator(p)
        self.hh = self.integrator.half_step
        self.start = 0              # grid index of buf[0]
        self.buf = np.zeros(1)      # β at grid indices start … integrator.index

    def window(self, t_lo: float, t_hi: float) -> tuple[np.ndarray, int]:
        """β on the grid from ≤ ``t_lo`` to ≥ ``t_hi`` and the grid index of its first value."""
        nom = self.integrator
        lo = max(math.floor(t_lo / self.hh) - 1, 0)
        hi = math.ceil(t_hi / self.hh) + 2
        if lo > nom.index:
            nom.advance(lo - nom.index, keep=False)
            self.buf = np.array([nom.beta])
            self.start = lo
        elif lo > self.start:
            self.buf = self.buf[lo - self.start:]
            self.start = lo
        if hi > nom.index:
            self.buf = np.concatenate([self.buf, nom.advance(hi - nom.index)])
        return self.buf, self.start


# The filter kernel ----------------------------------------------------------------------
class _Model(NamedTuple):
    """The filter's arrays, constant over a run (SI).

    ``phi_tab[j]`` (3, nnz): ``Φ``, ``∂Φ/∂ sin β``, ``∂Φ/∂ cos β`` at expansion point
    ``j · seg_w`` on the nonzeros of ``Φ`` (CSR ``rowptr``, ``colidx``); ``qd_tab[j]``
    (3, nq): the same for ``Qd`` on its nonzeros in the upper triangle (``qi ≤ qj``);
    ``sin_j``, ``cos_j`` at the expansion points; ``dense_ptr``, ``dense_idx``: a CSR pattern
    of a full matrix (the irregular steps' own ``Φ``); ``Fc``, ``Es``, ``Ec``, ``W = G Q Gᵀ``
    for the short time shift; ``H`` with its nonzeros (``hptr``, ``hidx``), ``r`` = diag R;
    ``gate`` the χ²(1) threshold of the normalized innovation squared; ``nb`` the number of
    instrument constants carried (:data:`gyrolib.gc.TERMS`; 0: none, the paper's filter).
    With constants, ``H`` is 3 × (10 + 2 nb): ``D`` of Eq. (8), then their columns ``H0``
    and ``H1`` (sensor ``q`` reads ``(H0[q] + β_n H1[q]) b`` more,
    :func:`gyrolib.gc.instrument_model`); ``hptr``, ``hidx`` list the nonzeros of ``D``
    only."""

    dt: float
    seg_w: float
    sin_j: NDArray[np.float64]
    cos_j: NDArray[np.float64]
    phi_tab: NDArray[np.float64]
    qd_tab: NDArray[np.float64]
    rowptr: NDArray[np.int64]
    colidx: NDArray[np.int64]
    qi: NDArray[np.int64]
    qj: NDArray[np.int64]
    dense_ptr: NDArray[np.int64]
    dense_idx: NDArray[np.int64]
    Fc: NDArray[np.float64]
    Es: NDArray[np.float64]
    Ec: NDArray[np.float64]
    W: NDArray[np.float64]
    H: NDArray[np.float64]
    hptr: NDArray[np.int64]
    hidx: NDArray[np.int64]
    r: NDArray[np.float64]
    gate: float
    nb: int


class _Chunk(NamedTuple):
    """One chunk of rows: times ``t``, measurements ``z`` (rows × 3, NaN missing), the
    nominal angle on the half-step grid (``grid`` from index ``g0``, ``inv_hh = 2/dt``) and
    how each row's step is taken: ``n_whole`` regular steps, then a short ``shift`` (jitter)
    or, where ``irr_idx >= 0``, an exact remainder step ``irr_phi``, ``irr_qd``."""

    t: NDArray[np.float64]
    z: NDArray[np.float64]
    grid: NDArray[np.float64]
    g0: float
    inv_hh: float
    n_whole: NDArray[np.int64]
    shift: NDArray[np.float64]
    irr_idx: NDArray[np.int64]
    irr_phi: NDArray[np.float64]
    irr_qd: NDArray[np.float64]


class _State(NamedTuple):
    """The filter between rows (updated in place): ``x``, ``P``, ``tcur`` (1,) the time of
    ``x``, and scratch arrays.  The instrument constants ``b`` (:data:`BIAS_NAMES`) by bias
    separation {cite:p}`Friedland1969`: ``x``, ``P`` are the filter without them, ``V``
    (NB, N) the response of ``x`` to a unit of each (``x_b = x − Vᵀ b̂``), ``bh`` = ``b̂``,
    ``Mb`` its covariance (from the prior ``diag(σ_b²)``), ``Ab`` the information the
    innovations carry about ``b``; ``u``, ``mu`` scratch."""

    x: NDArray[np.float64]
    P: NDArray[np.float64]
    tcur: NDArray[np.float64]
    Phi: NDArray[np.float64]
    Qd: NDArray[np.float64]
    T: NDArray[np.float64]
    y: NDArray[np.float64]
    Ph: NDArray[np.float64]
    k: NDArray[np.float64]
    Fm: NDArray[np.float64]
    Em: NDArray[np.float64]
    Am: NDArray[np.float64]
    V: NDArray[np.float64]
    Mb: NDArray[np.float64]
    bh: NDArray[np.float64]
    Ab: NDArray[np.float64]
    u: NDArray[np.float64]
    mu: NDArray[np.float64]


class _Rejections(NamedTuple):
    """The first rejections of the gate (time ``t``, sensor ``q``, NIS), ``n`` (1,) how many
    in all (updated in place)."""

    t: NDArray[np.float64]
    q: NDArray[np.int64]
    nis: NDArray[np.float64]
    n: NDArray[np.int64]


class _Store(NamedTuple):
    """What the kernel writes for a chunk: every ``every`` rows of the run (row numbers from
    ``row0`` at the start of the chunk) ``t``, ``x``, ``s`` (σ), with ``n`` (1,) how many;
    for every row and sensor the fate of the measurement ``flag`` (0 missing, 1 used,
    2 rejected) and, when used, its normalized innovation ``e = ν/√S`` and variance ``S``
    (the diagnostics are computed from them after the chunk, vectorized)."""

    every: int
    row0: int
    t: NDArray[np.float64]
    x: NDArray[np.float64]
    s: NDArray[np.float64]
    n: NDArray[np.int64]
    flag: NDArray[np.int8]
    e: NDArray[np.float64]
    S: NDArray[np.float64]


@njit(cache=True, inline="always")
def _beta_at(t, grid, g0, inv_hh):
    u = t * inv_hh - g0
    i = int(math.floor(u))  # noqa: RUF046 - numba: make the index an integer
    if i < 0:
        i = 0
    if i > grid.shape[0] - 2:
        i = grid.shape[0] - 2
    f = u - i
    return grid[i] * (1.0 - f) + grid[i + 1] * f


@njit(cache=True, inline="always")
def _step_matrices(phi_tab, qd_tab, sin_j, cos_j, rowptr, colidx, qi, qj, j, d, Phi, Qd):
    """``Φ``, ``Qd`` of a step of ``dt`` with ``F`` frozen at ``β_n = β_j + d``, from the
    affine tables of expansion point ``j``, with ``(sin β_n − sin β_j, cos β_n − cos β_j)``
    by series in ``d`` (|d| ≤ SEGMENT/2: exact to rounding)."""
    d2 = d * d
    cm1 = d2 * (-0.5 + d2 * (1.0 / 24.0 - d2 / 720.0))          # cos d − 1
    sn = d * (1.0 + d2 * (-1.0 / 6.0 + d2 * (1.0 / 120.0 - d2 / 5040.0)))   # sin d
    a = sin_j[j] * cm1 + cos_j[j] * sn
    b = cos_j[j] * cm1 - sin_j[j] * sn
    for i in range(N):
        for p in range(rowptr[i], rowptr[i + 1]):
            Phi[i, colidx[p]] = phi_tab[j, 0, p] + a * phi_tab[j, 1, p] + b * phi_tab[j, 2, p]
    for p in range(qi.shape[0]):
        Qd[qi[p], qj[p]] = qd_tab[j, 0, p] + a * qd_tab[j, 1, p] + b * qd_tab[j, 2, p]


@njit(cache=True)
def _shift(x, P, F, W, d, E, A, T, y, V, nb):
    """Move the state and covariance on by a short time ``d`` (either sign, |F d| ≪ 1):
    ``E = exp(F d)`` (Taylor to 4th order), ``x ← E x``, ``P ← E (P + Q̃) Eᵀ`` with
    ``Q̃ = W d − (F W + W Fᵀ) d²/2`` so that ``E (P + Q̃) Eᵀ = E P Eᵀ + Qd(d)`` to O(d³)
    (``W = G Q Gᵀ``; for ``d < 0`` this undoes the part of a step that came too far)."""
    n = x.shape[0]
    for i in range(n):
        for j in range(n):
            A[i, j] = F[i, j] * d
    # E = I + A (I + A/2 (I + A/3 (I + A/4)))  (Horner)
    for i in range(n):
        for j in range(n):
            E[i, j] = (1.0 if i == j else 0.0) + A[i, j] * 0.25
    for k in (3.0, 2.0, 1.0):
        for i in range(n):
            for j in range(n):
                s = 0.0
                for c in range(n):
                    s += A[i, c] * E[c, j]
                T[i, j] = (1.0 if i == j else 0.0) + s / k
        for i in range(n):
            for j in range(n):
                E[i, j] = T[i, j]
    # P + Q̃
    for i in range(n):
        for j in range(n):
            fw = 0.0
            wf = 0.0
            for c in range(n):
                fw += F[i, c] * W[c, j]
                wf += W[i, c] * F[j, c]
            A[i, j] = P[i, j] + d * W[i, j] - 0.5 * d * d * (fw + wf)
    for i in range(n):
        sx = 0.0
        for c in range(n):
            sx += E[i, c] * x[c]
        y[i] = sx
    for i in range(n):
        x[i] = y[i]
    for b in range(nb):        # the responses to the instrument constants move as x
        for i in range(n):
            sx = 0.0
            for c in range(n):
                sx += E[i, c] * V[b, c]
            y[i] = sx
        for i in range(n):
            V[b, i] = y[i]
    for i in range(n):
        for j in range(n):
            sm = 0.0
            for c in range(n):
                sm += E[i, c] * A[c, j]
            T[i, j] = sm
    for i in range(n):
        for j in range(i, n):
            sm = 0.0
            for c in range(n):
                sm += T[i, c] * E[j, c]
            P[i, j] = sm
            P[j, i] = sm


@njit(cache=True, inline="always")
def _update(x, P, Ph, k, H, hptr, hidx, r, gate, q, zq, nb, V, Mb, bh, Ab, u, mu, beta_n):
    """The scalar measurement ``zq`` of sensor ``q``: the gate, then the Joseph update
    (:func:`gyrolib.filtering.joseph_scalar_update`) and, with ``nb`` instrument constants,
    their recursive least squares on the innovation (bias separation: the innovation of the
    filter with the constants is ``ν − uᵀ b̂`` with variance ``S + uᵀ Mb u``, where ``u`` is
    the innovation's response to a unit of each constant: its reading by sensor ``q``,
    ``H0[q, c] + β_n H1[q, c]``, from the model's columns that follow the 10 states' in
    ``H`` (see :class:`_Model`), less the response of ``H x``).  Returns ``(used, ν, S)`` of
    the filter with the constants.  (The arrays come one by one: numba keeps them in
    registers, where fields of a tuple would be read again after every store; the constants'
    columns ride in ``H`` for the same reason: an array more in this hot loop costs about
    4 % of calibrate's time.)"""
    hx = 0.0
    for p in range(hptr[q], hptr[q + 1]):
        hx += H[q, hidx[p]] * x[hidx[p]]
    S = measurement_projection(P, H, q, hptr, hidx, Ph) + r[q]
    nu = zq - hx
    nua = nu
    Sa = S
    if nb > 0:
        for c in range(nb):
            hv = 0.0
            for p in range(hptr[q], hptr[q + 1]):
                hv += H[q, hidx[p]] * V[c, hidx[p]]
            # the constant's own reading by sensor q (the model's columns), less its
            # response through the state
            uc = H[q, N + c] + beta_n * H[q, N + nb + c] - hv
            u[c] = uc
            nua -= uc * bh[c]
        for c in range(nb):
            sm = 0.0
            for d in range(nb):
                sm += Mb[c, d] * u[d]
            mu[c] = sm
            Sa += u[c] * sm
    nis = nua * nua / Sa
    if nis > gate:
        return False, nua, Sa
    inv = 1.0 / S
    for p in range(N):
        k[p] = Ph[p] * inv
        x[p] += k[p] * nu
    if nb > 0:
        inva = 1.0 / Sa
        for c in range(nb):
            uc = u[c]
            for p in range(N):
                V[c, p] += k[p] * uc
            bh[c] += mu[c] * nua * inva
            for d in range(nb):
                Ab[c, d] += uc * u[d] * inv
                Mb[c, d] -= mu[c] * mu[d] * inva
    joseph_scalar_update(P, Ph, k, S)
    return True, nua, Sa


@njit(cache=True, inline="always")
def _store_row(x, P, so, t, nb, V, Mb, bh):
    """Store the estimate and σ of the filter with the instrument constants:
    ``x − Vᵀ b̂`` and ``diag(P + Vᵀ Mb V)``."""
    ii = so.n[0]
    so.t[ii] = t
    for p in range(N):
        xv = x[p]
        pv = P[p, p]
        for c in range(nb):
            xv -= V[c, p] * bh[c]
            for d in range(nb):
                pv += V[c, p] * Mb[c, d] * V[d, p]
        so.x[ii, p] = xv
        so.s[ii, p] = math.sqrt(max(pv, 0.0))
    so.n[0] = ii + 1


@njit(cache=True, nogil=True)
def _filter_chunk(md, ch, st, rj, so):
    """Predict and update over the rows of one chunk (``st``, ``rj``, ``so`` in place).
    Releases the GIL: the next chunk of a file can be read meanwhile."""
    # the arrays of the hot loops as locals (see _update)
    x, P, Phi, Qd, T, y, Ph, k = st.x, st.P, st.Phi, st.Qd, st.T, st.y, st.Ph, st.k
    rowptr, colidx, qi, qj = md.rowptr, md.colidx, md.qi, md.qj
    phi_tab, qd_tab, sin_j, cos_j = md.phi_tab, md.qd_tab, md.sin_j, md.cos_j
    H, hptr, hidx, r, gate = md.H, md.hptr, md.hidx, md.r, md.gate
    t, z, grid, g0, inv_hh = ch.t, ch.z, ch.grid, ch.g0, ch.inv_hh
    n_whole, irr_idx = ch.n_whole, ch.irr_idx
    dt, inv_seg = md.dt, 1.0 / md.seg_w
    nb, V, Mb, bh, Ab, u, mu = md.nb, st.V, st.Mb, st.bh, st.Ab, st.u, st.mu
    tcur = st.tcur[0]
    for i in range(t.shape[0]):
        # predict: whole steps of dt, then a short shift or an exact remainder step
        for _ in range(n_whole[i]):
            bm = _beta_at(tcur + 0.5 * dt, grid, g0, inv_hh)
            j = int(bm * inv_seg + 0.5)      # the nearest expansion point (β_n >= 0)
            _step_matrices(phi_tab, qd_tab, sin_j, cos_j, rowptr, colidx, qi, qj, j,
                           bm - j * md.seg_w, Phi, Qd)
            predict_state(x, Phi, rowptr, colidx, y)
            for c in range(nb):
                predict_state(V[c], Phi, rowptr, colidx, y)
            predict_covariance(P, Phi, rowptr, colidx, Qd, T)
            tcur += dt
        d = ch.shift[i]
        if d != 0.0:   # a step of n·dt + d, |d| small: the regular steps, then shift by d
            bm = _beta_at(tcur + 0.5 * d, grid, g0, inv_hh)
            sb = math.sin(bm)
            cb = math.cos(bm)
            for p in range(N):
                for c in range(N):
                    st.Fm[p, c] = md.Fc[p, c] + sb * md.Es[p, c] + cb * md.Ec[p, c]
            _shift(x, P, st.Fm, md.W, d, st.Em, st.Am, T, y, V, nb)
        kk = irr_idx[i]
        if kk >= 0:
            predict_state(x, ch.irr_phi[kk], md.dense_ptr, md.dense_idx, y)
            for c in range(nb):
                predict_state(V[c], ch.irr_phi[kk], md.dense_ptr, md.dense_idx, y)
            predict_covariance(P, ch.irr_phi[kk], md.dense_ptr, md.dense_idx,
                               ch.irr_qd[kk], T)
        tcur = t[i]
        beta_n = _beta_at(t[i], grid, g0, inv_hh)
        for q in range(M):
            zq = z[i, q]
            if math.isnan(zq):
                continue                          # flag 0: missing
            if q == 0:
                zq -= beta_n     # the angle sensor reads β = β_n + Δβ
            used, nu, S = _update(x, P, Ph, k, H, hptr, hidx, r, gate, q, zq, nb, V, Mb, bh,
                                  Ab, u, mu, beta_n)
            if used:
                so.flag[i, q] = 1
                so.e[i, q] = nu / math.sqrt(S)
                so.S[i, q] = S
            else:
                so.flag[i, q] = 2
                kk = rj.n[0]
                if kk < rj.t.shape[0]:
                    rj.t[kk] = t[i]
                    rj.q[kk] = q
                    rj.nis[kk] = nu * nu / S
                rj.n[0] = kk + 1
        if (so.row0 + i + 1) % so.every == 0:
            _store_row(x, P, so, t[i], nb, V, Mb, bh)
    st.tcur[0] = tcur


@njit(cache=True, nogil=True)
def _chunk_diagnostics(flag, e, S, row0, every, counts, row_counts, nis_sum, log_s_sum, ring,
                       ring_n, acf_sum, win_sum, win_cnt, wsum, wcnt):
    """One pass over a chunk's measurement fates ``flag`` (0 missing, 1 used, 2 rejected),
    normalized innovations ``e`` and variances ``S`` (see :class:`_Store`), adding to the
    run's diagnostics in place: ``counts`` (3, M) used / rejected / missing,
    ``row_counts`` (2,) rows with one used and none rejected / one rejected (disjoint),
    the sums of the NIS ``e²`` and of
    ``ln S``, the lag products ``Σ e_k e_{k−l}`` of each sensor's used ``e`` (``acf_sum``,
    continued across chunks through the last ``lags`` values kept in ``ring``, ``ring_n``
    of them so far).  The NIS sum and count since the previous stored row (``win_sum``,
    ``win_cnt``, carried across chunks) are written to ``wsum``, ``wcnt`` at every stored
    row (run row ``row0 + i + 1`` a multiple of ``every``); returns how many."""
    n, m = flag.shape
    lags = ring.shape[1]
    loc_nis = np.zeros(m)
    loc_log = np.zeros(m)
    loc_acf = np.zeros((m, lags))
    k = 0
    for i in range(n):
        any_used = False
        any_rejected = False
        for q in range(m):
            f = flag[i, q]
            if f == 1:
                any_used = True
                counts[0, q] += 1
                ev = e[i, q]
                loc_nis[q] += ev * ev
                loc_log[q] += math.log(S[i, q])
                win_sum[q] += ev * ev
                win_cnt[q] += 1
                seen = ring_n[q]
                for lag in range(1, min(lags, seen) + 1):
                    loc_acf[q, lag - 1] += ev * ring[q, (seen - lag) % lags]
                ring[q, seen % lags] = ev
                ring_n[q] = seen + 1
            elif f == 2:
                any_rejected = True
                counts[1, q] += 1
            else:
                counts[2, q] += 1
        if any_used and not any_rejected:
            row_counts[0] += 1
        if any_rejected:
            row_counts[1] += 1
        if (row0 + i + 1) % every == 0:
            for q in range(m):
                wsum[k, q] = win_sum[q]
                wcnt[k, q] = win_cnt[q]
                win_sum[q] = 0.0
                win_cnt[q] = 0
            k += 1
    for q in range(m):
        nis_sum[q] += loc_nis[q]
        log_s_sum[q] += loc_log[q]
        for lag in range(lags):
            acf_sum[q, lag] += loc_acf[q, lag]
    return k


# The calibrator (streaming state) ------------------------------------------------------------
def _closure(mask: np.ndarray) -> np.ndarray:
    """Reachability (transitive closure, with the diagonal) of a square boolean pattern."""
    R = mask | np.eye(mask.shape[0], dtype=bool)
    while True:
        R2 = (R.astype(np.int64) @ R.astype(np.int64)) > 0
        if np.array_equal(R2, R):
            return R
        R = R2


class _FilterModel:
    """The filter's model for one set of parameters: :class:`_Model` (without the gate) and
    its step tables, filled on demand (one Van Loan exponential per expansion point) and
    kept for the next run with the same parameters (:func:`_filter_model`)."""

    def __init__(self, p: GyrocompassParams) -> None:
        Fc, Es, Ec = system_matrix_parts(p)
        self.G = noise_input_matrix(p)
        self.Qc = process_noise_intensity(p)
        self.dt = p.dt
        # the nonzeros of Φ = exp(F dt) (and of its derivatives): the states each state
        # reaches through F; of Qd: pairs of states reached by the same noise input
        reach = _closure((Fc != 0) | (Es != 0) | (Ec != 0))
        by_noise = (reach.astype(np.int64) @ (self.G != 0).astype(np.int64)) > 0
        qmask = np.zeros((N, N), dtype=bool)
        for w in range(self.G.shape[1]):
            qmask |= np.outer(by_noise[:, w], by_noise[:, w])
        self.phi_mask = reach
        rows, cols = np.nonzero(reach)
        rowptr = np.zeros(N + 1, dtype=np.int64)
        rowptr[1:] = np.cumsum(reach.sum(axis=1))
        qi, qj = np.nonzero(np.triu(qmask))
        J = math.ceil(math.pi / SEGMENT) + 2   # β_n stays in [0, π/2]; room to spare
        self.have = np.zeros(J, dtype=bool)
        H = measurement_matrix(p)
        hmask = H != 0
        hptr = np.zeros(M + 1, dtype=np.int64)
        hptr[1:] = np.cumsum(hmask.sum(axis=1))
        self.model = _Model(
            dt=float(p.dt), seg_w=float(SEGMENT),
            sin_j=np.sin(np.arange(J) * SEGMENT), cos_j=np.cos(np.arange(J) * SEGMENT),
            phi_tab=np.zeros((J, 3, rows.size)), qd_tab=np.zeros((J, 3, qi.size)),
            rowptr=rowptr, colidx=cols.astype(np.int64), qi=qi.astype(np.int64),
            qj=qj.astype(np.int64), dense_ptr=np.arange(0, N * N + 1, N, dtype=np.int64),
            dense_idx=np.tile(np.arange(N, dtype=np.int64), N), Fc=Fc, Es=Es, Ec=Ec,
            W=self.G @ self.Qc @ self.G.T, H=H, hptr=hptr,
            hidx=np.nonzero(hmask)[1].astype(np.int64),
            r=np.diag(measurement_noise_covariance(p)).copy(), gate=math.inf, nb=0)

    def table(self, j: int) -> None:
        """Fill the tables of expansion point ``j`` (once)."""
        if j < 0 or j >= self.have.size:
            raise ValueError(f"the nominal float angle left [0, π] (expansion point {j}); "
                             "check the parameters H, Omega_h, f, I")
        if self.have[j]:
            return
        md = self.model
        F = md.Fc + math.sin(j * SEGMENT) * md.Es + math.cos(j * SEGMENT) * md.Ec
        Phi, Qd, (dPs, dPc), (dQs, dQc) = van_loan_derivatives(F, self.G, self.Qc, self.dt,
                                                               [md.Es, md.Ec])
        for k, arr in enumerate((Phi, dPs, dPc)):
            md.phi_tab[j, k] = arr[self.phi_mask]
        for k, arr in enumerate((Qd, dQs, dQc)):
            md.qd_tab[j, k] = arr[md.qi, md.qj]
        self.have[j] = True


@functools.lru_cache(maxsize=8)
def _filter_model(p: GyrocompassParams) -> _FilterModel:
    return _FilterModel(p)


class _Calibrator:
    """State of :func:`calibrate` between chunks."""

    def __init__(self, p: GyrocompassParams, *, store_every: int, gate: float, lags: int,
                 time_tolerance: float, steps: dict[str, float] | None = None) -> None:
        self.p = p
        self.dt = p.dt
        self.tol = time_tolerance * p.dt
        self.store_every = store_every
        self.gate_prob = gate
        self.nominal = _Nominal(p)
        self.filter_model = _filter_model(p)
        # every declared instrument constant (the model's declaration, read now), each with
        # its prior (0: known to be 0, carried at no cost to the estimate)
        inst = instrument.build_instrument_model(p, tuple(t.name for t in instrument.TERMS))
        coupled = [nm for nm, col in zip(inst.names, inst.Fb.T, strict=True) if np.any(col)]
        if coupled:
            raise ValueError("params: calibrate carries the instrument constants by bias "
                             "separation in the measurements only; a declared term with a "
                             f"dynamics column Fb != 0 ({', '.join(coupled)}) is not "
                             "supported")
        self.instrument = inst
        self.bias_prior = inst.prior.copy()
        nb = inst.nb if np.any(self.bias_prior > 0.0) else 0
        NB = inst.nb     # the constants carried in the state arrays
        self.model = self.filter_model.model._replace(
            gate=float(chi2_ppf(gate, 1)), nb=nb,
            H=np.ascontiguousarray(np.hstack([self.filter_model.model.H, inst.H0, inst.H1])))
        self.state = _State(
            x=np.zeros(N), P=initial_covariance(p), tcur=np.zeros(1), Phi=np.zeros((N, N)),
            Qd=np.zeros((N, N)), T=np.zeros((N, N)), y=np.zeros(N), Ph=np.zeros(N),
            k=np.zeros(N), Fm=np.zeros((N, N)), Em=np.zeros((N, N)), Am=np.zeros((N, N)),
            V=np.zeros((NB, N)), Mb=np.diag(self.bias_prior**2), bh=np.zeros(NB),
            Ab=np.zeros((NB, NB)), u=np.zeros(NB), mu=np.zeros(NB))
        self.rejections = _Rejections(
            t=np.zeros(MAX_LISTED_REJECTIONS), q=np.zeros(MAX_LISTED_REJECTIONS, np.int64),
            nis=np.zeros(MAX_LISTED_REJECTIONS), n=np.zeros(1, dtype=np.int64))
        # diagnostics, per sensor (3,) unless said (see _diagnostics)
        self.lags = lags
        self.counts = np.zeros((3, M), dtype=np.int64)  # used, rejected, missing
        self.row_counts = np.zeros(2, dtype=np.int64)   # rows with one used, one rejected
        self.nis_sum = np.zeros(M)
        self.log_s_sum = np.zeros(M)
        self.acf_sum = np.zeros((M, lags))
        self.ring = np.zeros((M, lags))                 # the last `lags` used e of a sensor
        self.ring_n = np.zeros(M, dtype=np.int64)
        self.win_sum = np.zeros(M)                      # NIS since the last stored row
        self.win_cnt = np.zeros(M, dtype=np.int64)
        self.steps = steps           # the columns' steps (None: the first chunk's)
        self.measurement_steps = np.zeros(M)
        self.rows = 0                # rows filtered
        self.prepared_rows = 0       # rows prepared (prepare runs ahead of run by a chunk)
        self.t_last = 0.0            # the time of the last row prepared
        self.stored: list[tuple[np.ndarray, ...]] = []
        self.gaps = 0
        self.gap_time = 0.0
        self.irregular = 0
        self.shifted = 0

    def _steps(self, t: np.ndarray) -> tuple[np.ndarray, ...]:
        """How each row's step from the previous row is taken (see :class:`_Chunk`)."""
        prev = np.concatenate([[self.t_last], t[:-1]])
        h = t - prev
        # a step near a whole number of dt (jitter, |d| <= SMALL_SHIFT dt): the regular
        # steps and a short shift; anything else: whole steps and an exact remainder step
        n_near = np.rint(h / self.dt)
        d = h - n_near * self.dt
        small = (np.abs(d) > self.tol) & (np.abs(d) <= SMALL_SHIFT * self.dt) & (n_near >= 1)
        n_whole = np.where(small, n_near,
                           np.floor((h + self.tol) / self.dt)).astype(np.int64)
        rem = h - n_whole * self.dt
        irregular = ~small & (rem > self.tol)
        shift = np.where(small, d, 0.0)
        if self.prepared_rows == 0 and t[0] == 0.0:   # a row at t = 0: update only
            n_whole[0] = 0
            irregular[0] = False
            shift[0] = 0.0
        self.shifted += int(np.count_nonzero(small))
        long_ = h > 1.5 * self.dt
        self.gaps += int(np.count_nonzero(long_))
        self.gap_time += float(np.sum(h[long_] - self.dt))
        return prev, n_whole, shift, irregular, rem

    def feed(self, rec: GCRecord) -> None:
        """Filter the rows of ``rec``."""
        self.run(self.prepare(rec))

    def prepare(self, rec: GCRecord) -> tuple[_Chunk, _Store]:
        """What the kernel needs for the rows of ``rec`` (the steps, the nominal motion, the
        step tables) and where it writes: independent of the filter's state, so that the
        next chunk is prepared while the kernel runs on this one (chunks in time order)."""
        if not isinstance(rec, GCRecord):
            raise TypeError(f"record chunks must be GCRecord; got {type(rec).__name__}")
        if self.prepared_rows == 0:
            self.record_latitude = rec.latitude
            self._carry_quantization(self.steps if self.steps is not None
                                     else rec.resolution)
        t = rec.t
        if t[0] <= self.t_last and self.prepared_rows > 0:
            raise ValueError(f"record chunks must continue in time: t = {t[0]} follows "
                             f"{self.t_last}")
        prev, n_whole, shift, irregular, rem = self._steps(t)
        grid, g0 = self.nominal.window(float(prev[0]), float(t[-1]))
        jlo = round(float(np.min(grid)) / SEGMENT)
        jhi = round(float(np.max(grid)) / SEGMENT)
        fm = self.filter_model
        for j in range(max(jlo - 1, 0), min(jhi + 1, fm.have.size - 1) + 1):  # ±1: ties
            fm.table(j)
        if jlo < 0 or jhi >= fm.have.size:
            fm.table(jlo if jlo < 0 else jhi)      # raises: β_n left [0, π]
        irr_rows = np.nonzero(irregular)[0]
        irr_idx = np.full(t.size, -1, dtype=np.int64)
        irr_idx[irr_rows] = np.arange(irr_rows.size)
        irr_phi = np.zeros((irr_rows.size, N, N))
        irr_qd = np.zeros((irr_rows.size, N, N))
        if irr_rows.size:
            grid_t = (g0 + np.arange(grid.size)) * self.nominal.hh
            for k, i in enumerate(irr_rows):
                start = prev[i] + n_whole[i] * self.dt
                bm = float(np.interp(0.5 * (start + t[i]), grid_t, grid))
                md, fm = self.model, self.filter_model
                F = md.Fc + math.sin(bm) * md.Es + math.cos(bm) * md.Ec
                irr_phi[k], irr_qd[k] = van_loan(F, fm.G, fm.Qc, float(rem[i]))
            self.irregular += int(irr_rows.size)
        chunk = _Chunk(t=t, z=np.ascontiguousarray(rec.measurements()), grid=grid,
                       g0=float(g0), inv_hh=1.0 / self.nominal.hh, n_whole=n_whole,
                       shift=shift, irr_idx=irr_idx, irr_phi=irr_phi, irr_qd=irr_qd)
        n_store = t.size // self.store_every + 1
        store = _Store(every=self.store_every, row0=self.prepared_rows, t=np.zeros(n_store),
                       x=np.zeros((n_store, N)), s=np.zeros((n_store, N)),
                       n=np.zeros(1, dtype=np.int64), flag=np.zeros((t.size, M), np.int8),
                       e=np.zeros((t.size, M)), S=np.ones((t.size, M)))
        self.t_last = float(t[-1])
        self.prepared_rows += t.size
        return chunk, store

    def _carry_quantization(self, steps: dict[str, float]) -> None:
        """Add each coarse column's rounding, ``step²/12``, to its sensor's measurement
        noise (set once, before the first chunk is filtered)."""
        q = np.array([float(steps.get(name, 0.0)) for name in MEASUREMENT_COLUMNS])
        self.measurement_steps = q
        if np.any(q > 0.0):   # a new array: the model's r is shared by _filter_model's cache
            self.model = self.model._replace(r=self.model.r + q * q / 12.0)

    def run(self, prepared: tuple[_Chunk, _Store]) -> None:
        """Filter a prepared chunk (the next in time) and add up its diagnostics."""
        chunk, store = prepared
        _filter_chunk(self.model, chunk, self.state, self.rejections, store)
        k = int(store.n[0])
        nis_win, cnt_win = self._diagnostics(store)
        self.stored.append((store.t[:k].copy(), store.x[:k].copy(), store.s[:k].copy(),
                            nis_win, cnt_win))
        self.rows += chunk.t.size

    def _diagnostics(self, store: _Store) -> tuple[np.ndarray, np.ndarray]:
        """Add a chunk's innovations to the diagnostics (:func:`_chunk_diagnostics`); return
        the mean NIS and count of each stored row's window (the rows since the previous
        one)."""
        n_store = store.t.shape[0]
        wsum = np.zeros((n_store, M))
        wcnt = np.zeros((n_store, M), dtype=np.int64)
        k = _chunk_diagnostics(store.flag, store.e, store.S, store.row0, store.every,
                               self.counts, self.row_counts, self.nis_sum, self.log_s_sum,
                               self.ring, self.ring_n, self.acf_sum, self.win_sum,
                               self.win_cnt, wsum, wcnt)
        wsum, wcnt = wsum[:k], wcnt[:k]
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(wcnt > 0, wsum / np.maximum(wcnt, 1), np.nan), wcnt

    def result(self, max_rejected: float, nis_range: tuple[float, float],
               false_alarm: float = 0.01, nis_tolerance: float = 0.0
               ) -> CalibrationResult:
        if self.rows == 0:
            raise ValueError("record must hold at least one row")
        st, rj = self.state, self.rejections
        parts = list(self.stored)
        # the filter with the instrument constants (bias separation): x − Vᵀ b̂, P + Vᵀ M V
        x_fin = st.x - st.V.T @ st.bh
        P_fin = st.P + st.V.T @ st.Mb @ st.V if self.model.nb else st.P.copy()
        P_fin = 0.5 * (P_fin + P_fin.T)
        if self.rows % self.store_every:   # the last row is not a store point: add it
            with np.errstate(invalid="ignore", divide="ignore"):
                win = np.where(self.win_cnt > 0,
                               self.win_sum / np.maximum(self.win_cnt, 1), np.nan)
            parts.append((np.array([st.tcur[0]]), x_fin[None, :].copy(),
                          np.sqrt(np.clip(np.diag(P_fin), 0.0, None))[None, :], win[None, :],
                          self.win_cnt[None, :].copy()))
        cat = [np.concatenate([part[k] for part in parts]) for k in range(5)]
        # the autocorrelation of e: lag products over Σ e² (the NIS sum)
        with np.errstate(invalid="ignore", divide="ignore"):
            acf = np.where(self.nis_sum[:, None] > 0,
                           self.acf_sum / np.where(self.nis_sum > 0, self.nis_sum,
                                                   1.0)[:, None], 0.0)
        nr = min(int(rj.n[0]), MAX_LISTED_REJECTIONS)
        return CalibrationResult(
            params=self.p, t=cat[0], x=cat[1], std=cat[2], nis_window=cat[3],
            nis_window_count=cat[4], x_final=x_fin, P_final=P_fin,
            t_final=float(st.tcur[0]), rows=self.rows, used=self.counts[0].copy(),
            missing=self.counts[2].copy(), rejected=self.counts[1].copy(),
            rows_used=int(self.row_counts[0]), rows_rejected=int(self.row_counts[1]),
            rejected_t=rj.t[:nr].copy(), rejected_sensor=rj.q[:nr].copy(),
            rejected_nis=rj.nis[:nr].copy(), nis_sum=self.nis_sum.copy(),
            log_s_sum=self.log_s_sum.copy(), acf=acf, gaps=self.gaps, gap_time=self.gap_time,
            irregular_steps=self.irregular, jittered_steps=self.shifted, gate=self.gate_prob,
            store_every=self.store_every, max_rejected=max_rejected,
            nis_range=(float(nis_range[0]), float(nis_range[1])), false_alarm=false_alarm,
            nis_tolerance=nis_tolerance,
            bias_prior=self.bias_prior.copy(), bias_estimate=st.bh.copy(),
            bias_cov=st.Mb.copy(), bias_info=st.Ab.copy(), bias_response=st.V.copy(),
            P_filter=st.P.copy(), bias_names=self.instrument.names,
            bias_groups=self.instrument.groups, record_latitude=self.record_latitude,
            measurement_steps=self.measurement_steps.copy())


def _chunks(record: GCRecord, size: int):
    for s in range(0, record.n, size):
        sl = slice(s, s + size)
        yield GCRecord(t=record.t[sl], angle_sensor=record.angle_sensor[sl],
                       inclinometer_y=record.inclinometer_y[sl],
                       inclinometer_z=record.inclinometer_z[sl], latitude=record.latitude)


def _check_nis_range(nis_range: object) -> tuple[float, float]:
    if not isinstance(nis_range, tuple | list) or len(nis_range) != 2:
        raise TypeError("nis_range must be a pair (low, high) of mean-NIS limits; got "
                        f"{type(nis_range).__name__}")
    lo = v.check_in_range("nis_range[0]", nis_range[0], 0.0, 1.0, high_open=True)
    hi = v.check_real("nis_range[1]", nis_range[1], "> 1")
    if not hi > 1.0:
        raise ValueError(f"nis_range[1] must be > 1; got {hi}")
    return lo, hi


def _prefetched(chunks: Iterable, executor: Executor | None):
    """The items of ``chunks``, the next one made through ``executor`` (read, checked,
    prepared) while the current one is filtered (the kernel releases the GIL): two in
    flight."""
    it = iter(chunks)
    if executor is None:
        yield from it
        return
    fut = executor.submit(next, it, None)
    while True:
        chunk = fut.result()
        if chunk is None:
            return
        fut = executor.submit(next, it, None)
        yield chunk


def calibrate(record: GCRecord | Iterable[GCRecord], params: GyrocompassParams | None = None,
              *, chunk_size: int = 65536, store_every: int = 100, gate: float = 0.9999,
              lags: int = 10, time_tolerance: float = 1e-6,
              progress: Callable[[int], None] | None = None, max_rejected: float = 0.01,
              nis_range: tuple[float, float] = (0.5, 2.0), false_alarm: float = 0.01,
              nis_tolerance: float = 0.0, executor: Executor | None = None
              ) -> CalibrationResult:
    """Calibrate the systematic drift ω_gc of a floated gyro from a record (paper GC).

    Runs the 10-state Kalman filter of Eq. (8) on ``record`` (a :class:`GCRecord`, or an
    iterable of them in time order for a long record read in chunks, e.g.
    :class:`gyrolib.records.GCChunks`) with the model ``params`` (default: the paper's).
    See the module docstring for gaps, missing values, the gate and the diagnostics.

    Parameters
    ----------
    record : GCRecord or iterable of GCRecord
        Times ``t`` (s since the feedback was switched off, β = 0 then), angle sensor β
        (rad), inclinometers (m/s²).  NaN marks a missing measurement.
    params : GyrocompassParams, optional
        The model; ``params.dt`` is the nominal sample interval.
    chunk_size : int
        Rows per chunk when ``record`` is a single :class:`GCRecord`.
    store_every : int
        Store the estimates and σ every this many rows (and at the last row).
    gate : float
        Probability of the χ²(1) gate on each scalar innovation; beyond it a measurement is
        rejected (not used) and listed.
    lags : int
        Lags of the innovation autocorrelation (whiteness test).
    time_tolerance : float
        A step within ``time_tolerance · dt`` of a whole number of ``dt`` counts as whole
        steps; a step within 5 % of it is shifted by the difference, any other remainder is
        discretized exactly at its own length.
    progress : callable, optional
        Called with the number of rows processed after each chunk.
    max_rejected : float
        The run is invalid (lost lock, :attr:`CalibrationResult.valid`) when the gate rejects
        more than this share of any sensor's measurements (default 1 %).
    nis_range : (float, float)
        The run is invalid when a sensor's mean NIS is outside this range (far outside its
        χ² band, which is within a few % of 1 on a long record).
    false_alarm : float
        The family-wise false-alarm rate of the model checks that gate validity
        (:meth:`CalibrationResult.model_tests`: mean NIS and whiteness of each sensor, the
        split-record tests; Šidák-corrected): the share of records of a model that fits
        which are declared invalid (default 1 %).
    nis_tolerance : float
        Relative widening of the mean-NIS band of that gate (default 0: the band is the
        gated mean NIS's own, see :meth:`CalibrationResult.model_tests`).
    executor : concurrent.futures.Executor, optional
        Prepares the next chunk through it (reads it, for an iterable ``record`` such as a
        file read in chunks; its steps, nominal motion and step tables) while the current
        one is filtered: the two overlap on two cores, with two chunks in flight.

    Returns
    -------
    CalibrationResult
        ``omega_gc`` ± ``omega_gc_std`` (rad/s), every state over time, diagnostics,
        ``valid`` and ``reason``.

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import gc
    >>> p = gc.GyrocompassParams()
    >>> t = np.arange(1, 201) * p.dt                     # 0.2 s of a gyro at rest in β_n
    >>> beta_n = gc.nominal_motion(p, t).beta
    >>> rec = gc.GCRecord(t=t, angle_sensor=beta_n, inclinometer_y=np.zeros(200),
    ...                   inclinometer_z=np.zeros(200))
    >>> res = gc.calibrate(rec, p)
    >>> res.rows, res.rows_used, bool(res.omega_gc_std < p.sigma_gc0)
    (200, 200, True)
    >>> res.valid                 # noise-free readings: every mean NIS far below 1
    False
    >>> res.reason.split(" outside ")[0][:22]
    'angle_sensor: mean NIS'
    """
    p = GyrocompassParams() if params is None else v.check_instance(
        "params", params, GyrocompassParams)
    chunk_size = v.check_int("chunk_size", chunk_size, 1)
    store_every = v.check_int("store_every", store_every, 1)
    gate = v.check_in_range("gate", gate, 0.0, 1.0, low_open=True, high_open=True)
    lags = v.check_int("lags", lags, 1)
    time_tolerance = v.check_in_range("time_tolerance", time_tolerance, 0.0, 0.5)
    max_rejected = v.check_in_range("max_rejected", max_rejected, 0.0, 1.0)
    nis_range = _check_nis_range(nis_range)
    false_alarm = v.check_in_range("false_alarm", false_alarm, 0.0, 1.0, low_open=True,
                                   high_open=True)
    nis_tolerance = v.check_in_range("nis_tolerance", nis_tolerance, 0.0, 1.0,
                                     high_open=True)
    if progress is not None and not callable(progress):
        raise TypeError(f"progress must be callable or None; got {type(progress).__name__}")
    if executor is not None:
        v.check_instance("executor", executor, Executor)
    if isinstance(record, GCRecord):
        chunks: Iterable[GCRecord] = _chunks(record, chunk_size)
    elif isinstance(record, Iterable) and not isinstance(record,
                                                          str | bytes | dict | np.ndarray):
        chunks = record
    else:
        raise TypeError(f"record must be a GCRecord or an iterable of GCRecord chunks; got "
                        f"{type(record).__name__}")
    cal = _Calibrator(p, store_every=store_every, gate=gate, lags=lags,
                      time_tolerance=time_tolerance,
                      steps=record.resolution if isinstance(record, GCRecord) else None)
    for prepared in _prefetched(map(cal.prepare, chunks), executor):
        cal.run(prepared)
        if progress is not None:
            progress(cal.rows)
    return cal.result(max_rejected, nis_range, false_alarm, nis_tolerance)


def innovation_log_likelihood(record: GCRecord, params: GyrocompassParams | None = None, *,
                              chunk_size: int = 65536) -> float:
    """The Gaussian log-likelihood of ``record`` under the model ``params`` by the
    prediction-error decomposition of the filter of :func:`calibrate` (paper GC, Eq. (8)):
    ``ln L = −½ Σ (ln 2π S + ν²/S)`` over every scalar measurement that is not NaN, with the
    innovation ``ν`` and its variance ``S`` of the sequential scalar updates
    {cite:p}`BarShalom2001`.  No gate: every measurement counts (set outliers to NaN first).
    :func:`gyrolib.gc.fit_noise` maximizes it.

    Parameters
    ----------
    record : GCRecord
        The record (SI), as for :func:`calibrate`.
    params : GyrocompassParams, optional
        The model (default: the paper's).
    chunk_size : int
        Rows per chunk.

    Returns
    -------
    float
        ``ln L`` (nats).

    Examples
    --------
    The true model is more likely than one with a 10× wider vibration spectrum:

    >>> import dataclasses
    >>> from gyrolib import gc
    >>> p = gc.GyrocompassParams()
    >>> rec = gc.simulate_record(p, 5.0, seed=3).record
    >>> wide = dataclasses.replace(p, alpha1=10 * p.alpha1)
    >>> bool(gc.innovation_log_likelihood(rec, p) > gc.innovation_log_likelihood(rec, wide))
    True
    """
    p = GyrocompassParams() if params is None else v.check_instance(
        "params", params, GyrocompassParams)
    v.check_instance("record", record, GCRecord)
    chunk_size = v.check_int("chunk_size", chunk_size, 1)
    cal = _Calibrator(p, store_every=record.n + 1, gate=1.0, lags=1, time_tolerance=1e-6,
                      steps=record.resolution)
    for chunk in _chunks(record, chunk_size):
        cal.feed(chunk)
    return _log_likelihood(cal.counts[0], cal.log_s_sum, cal.nis_sum)


# Simulated records --------------------------------------------------------------------------
@compact_repr
@dataclass(frozen=True)
class SimulatedRecord:
    """A record made by the truth model (:func:`gyrolib.gc.simulate_truth`) with its truth:
    ``record`` (rows at ``t = k dt``, ``k = 1 … n``), ``truth`` (n+1, 10) the true states at
    ``t = k dt``, ``k = 0 … n``, ``params`` the model simulated, ``seed``."""

    record: GCRecord
    truth: np.ndarray
    params: GyrocompassParams
    seed: int

    def __post_init__(self) -> None:
        v.check_instance("record", self.record, GCRecord)
        v.check_ndarray("truth", self.truth, shape=(None, N))
        v.check_instance("params", self.params, GyrocompassParams)
        v.check_int("seed", self.seed, 0)

    @property
    def omega_gc(self) -> float:
        """The true systematic drift (rad/s)."""
        return float(self.truth[0, state_index("omega_gc")])


def simulate_record(params: GyrocompassParams, t_end: float, seed: int, *,
                    omega_gc: float | None = None) -> SimulatedRecord:
    """A seeded record of paper GC's truth model (nonlinear Eq. (3) with the shaping filters)
    over ``(0, t_end]`` at ``params.dt``, in the columns of a :class:`GCRecord`.

    The initial state is drawn from ``P(0)`` (:func:`gyrolib.gc.initial_covariance`; with
    ``omega_gc`` given, the drift is that value, rad/s, the other states drawn); the
    angle sensor reads ``β = β_n + Δβ`` plus white noise of variance ``R₁₁``, the
    inclinometers ``g δ + N1`` and ``g γ + N1`` plus noise of variances ``R₂₂``, ``R₃₃``
    (Eq. (8), :func:`gyrolib.gc.measurement_noise_covariance`).

    Examples
    --------
    >>> from gyrolib import gc
    >>> sim = gc.simulate_record(gc.GyrocompassParams(), 0.01, seed=1)
    >>> sim.record.n, sim.truth.shape
    (10, (11, 10))
    """
    p = v.check_instance("params", params, GyrocompassParams)
    seed = v.check_int("seed", seed, 0)
    rng = np.random.default_rng(seed)
    x0 = covariance_factor(initial_covariance(p)) @ rng.standard_normal(N)
    if omega_gc is not None:
        x0[state_index("omega_gc")] = v.check_real("omega_gc", omega_gc)
    truth_seed = int(rng.integers(0, 2**62))
    t, X = simulate_truth(p, t_end, x0, seed=truth_seed)
    beta_n = nominal_half_steps(p, t.size - 1)[::2]
    D = measurement_matrix(p)
    sr = np.sqrt(np.diag(measurement_noise_covariance(p)))
    Z = X @ D.T + rng.standard_normal((t.size, M)) * sr
    Z[:, 0] += beta_n
    rec = GCRecord(t=t[1:], angle_sensor=Z[1:, 0], inclinometer_y=Z[1:, 1],
                   inclinometer_z=Z[1:, 2])
    return SimulatedRecord(record=rec, truth=X, params=p, seed=seed)


def simulate_records(params: GyrocompassParams, t_end: float, seed: int,
                     n: int) -> tuple[SimulatedRecord, ...]:
    """``n`` independent seeded records of paper GC's truth model, as
    :func:`simulate_record` makes one, for about the price of one: the truth model runs
    them together (:func:`gyrolib.gc.simulate_truth` with ``n`` initial states, one lane of
    the noise streams each, which one run draws anyway).

    Record 0 is ``simulate_record(params, t_end, seed)``, number for number.  Record
    ``i ≥ 1`` draws its initial state and its sensors' noise from the child ``i`` of the
    seed's ``SeedSequence`` and its truth's noise from lane ``i`` of the streams; its
    ``seed`` field is ``seed``.  Memory: ``n`` truths of ``t_end/dt + 1`` rows of 10 states
    (8 MB a record of 100 s at 1 kHz).

    Examples
    --------
    >>> from gyrolib import gc
    >>> p = gc.GyrocompassParams()
    >>> sims = gc.simulate_records(p, 0.01, seed=1, n=3)
    >>> len(sims), bool((sims[0].record.angle_sensor
    ...                  == gc.simulate_record(p, 0.01, seed=1).record.angle_sensor).all())
    (3, True)
    """
    p = v.check_instance("params", params, GyrocompassParams)
    seed = v.check_int("seed", seed, 0)
    n = v.check_int("n", n, 1)
    rng = np.random.default_rng(seed)
    factor = covariance_factor(initial_covariance(p))
    x0 = [factor @ rng.standard_normal(N)]
    truth_seed = int(rng.integers(0, 2**62))
    children = [np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(i,)))
                for i in range(1, n)]
    x0 += [factor @ g.standard_normal(N) for g in children]
    t, X = simulate_truth(p, t_end, np.array(x0), seed=truth_seed)
    beta_n = nominal_half_steps(p, t.size - 1)[::2]
    D = measurement_matrix(p)
    sr = np.sqrt(np.diag(measurement_noise_covariance(p)))
    out = []
    for i, g in enumerate([rng, *children]):
        Z = X[i] @ D.T + g.standard_normal((t.size, M)) * sr
        Z[:, 0] += beta_n
        rec = GCRecord(t=t[1:], angle_sensor=Z[1:, 0], inclinometer_y=Z[1:, 1],
                       inclinometer_z=Z[1:, 2])
        out.append(SimulatedRecord(record=rec, truth=X[i], params=p, seed=seed))
    return tuple(out)


#: Relative agreement (of the Earth's rate) within which the parameters' Ω_h and Ω_v are
#: those of a record's stated latitude: what :meth:`GyrocompassParams.at_latitude` gives,
#: up to rounding.  (Paper GC's printed 4.3·10⁻⁵, 5.9·10⁻⁵ rad/s are 0.1 % off the rate at
#: 53.9° N: enough to move ω̂_gc by several σ of a 100 s run.)
EARTH_RATE_TOLERANCE: Final[float] = 1e-6


def _inclinometer_lost(name: str, share: float, angle_share: float) -> str:
    """What an inclinometer whose every sample the gate rejected, while the angle sensor
    kept lock, may have: a reading offset beyond its prior's reach (its bias; for
    ``inclinometer_z``, the γ column, also a tilt of the gyro's input axis out of the
    horizontal, which reads the same), a wrong unit or sign.  ``""`` otherwise."""
    if name == "angle_sensor" or share < 0.99 or angle_share > 0.5:
        return ""
    tilt, axis = (("delta", ""), ("gamma", ", or the gyro's input axis tilted out of the "
                                   "horizontal, which reads as that bias"))[
        name == "inclinometer_z"]
    return (f": its readings lie beyond the gate from the first sample on: the state "
            f"{name}_bias beyond its prior (--inclinometer-bias-prior){axis}, the tilt "
            f"{tilt} beyond its prior (sigma_{tilt}0 in --params), or a wrong unit or sign")


def earth_rate_mismatch(params: GyrocompassParams, latitude: float) -> str:
    """Why ``params``' Earth rate is not the one at a record's stated ``latitude`` (rad), or
    ``""`` when it is (within :data:`EARTH_RATE_TOLERANCE` of the Earth's rate).

    Ω_h reads as drift in paper GC's method (the float's steady rate is
    ``(H/f)(Ω_h + ω_gc)``), so the difference says how far ω̂_gc moves.

    Examples
    --------
    >>> import math
    >>> from gyrolib import gc
    >>> site = math.radians(45.0)
    >>> gc.earth_rate_mismatch(gc.GyrocompassParams.at_latitude(site), site)
    ''
    >>> gc.earth_rate_mismatch(gc.GyrocompassParams(), site)[:52]
    'the record states latitude 45 deg N, but the Earth r'
    """
    p = v.check_instance("params", params, GyrocompassParams)
    lat = v.check_in_range("latitude", latitude, -math.pi / 2, math.pi / 2)
    want_h, want_v = EARTH_RATE * math.cos(lat), EARTH_RATE * math.sin(lat)
    tol = EARTH_RATE_TOLERANCE * EARTH_RATE
    if abs(p.Omega_h - want_h) <= tol and abs(p.Omega_v - want_v) <= tol:
        return ""
    site = math.degrees(math.atan2(p.Omega_v, p.Omega_h))
    off = float(from_si(p.Omega_h - want_h, "deg/h"))
    return (f"the record states latitude {latitude_text(math.degrees(lat))}, but the Earth rate "
            f"of params (Omega_h = {p.Omega_h:.6g}, Omega_v = {p.Omega_v:.6g} rad/s) is that "
            f"of about {site:.3g} deg: Omega_h off by {off:+.3g} deg/h, which reads as drift "
            "(use GyrocompassParams.at_latitude(record.latitude))")
