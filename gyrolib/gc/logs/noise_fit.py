"""Paper GC: the noise parameters of the model fitted from a record (:func:`fit_noise`).

The vibration shaping filter of Eq. (6) (``α1``, ``σ1²``, optionally ``ξ1``) and the sensor
noise intensities (``C_as``; ``C_incl_y``, ``C_incl_z`` together as ``C_in`` or apart) are
found by maximizing the Gaussian log-likelihood of the record by the prediction-error
decomposition, ``ln L = −½ Σ (ln 2π S + ν²/S)`` over the filter's scalar innovations
(:func:`gyrolib.gc.innovation_log_likelihood`) {cite:p}`BarShalom2001`, in the logarithms of
the parameters (positive, and of very different scales), with :mod:`scipy.optimize`
(``trust-exact``: Newton steps in a trust region, on a central-difference gradient and
Hessian).  The standard errors come from the curvature at the optimum: the inverse of the
Hessian of ``−ln L`` in the log-parameters, carried back by the delta method
(``SE(θ) = θ · SE(ln θ)``).

Cost and how it is kept down (a likelihood is one run of the 10-state filter over the
record, about 0.2 s per 100 s at 1 kHz):

1. a start from a cheaper, exact likelihood: the inclinometers alone.  Their states
   ``(δ, γ, N1, N2)`` evolve on their own (Eqs. (6), (8): nothing else drives them), so the
   inclinometers' marginal likelihood is that of a 4-state time-invariant filter, a few ms
   per evaluation; it fits the vibration filter and the inclinometer noise.  (Time steps are
   rounded to whole ``dt`` here: jitter and remainders only move the start.)
2. the full likelihood (every sensor, every time step exact) from there: a few Newton steps,
   each a stencil of ``1 + 2n + n(n−1)/2`` likelihoods for ``n`` fitted parameters.

Outliers: a likelihood without a gate is not robust, a likelihood with one is not smooth.
The measurements the gate of :func:`gyrolib.gc.calibrate` rejects under the current fit are
left out (set missing) and the fit is repeated until that set no longer changes; the fit
keeps that set (:attr:`NoiseFit.outlier_cells`), and its intervals
(:func:`profile_intervals`) are traced on the same measurements, so that the likelihood
whose fall they measure is continuous in the parameters and peaks at the fit.
"""

from __future__ import annotations

import dataclasses
import json
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Final

import numpy as np
from numba import njit
from numpy.typing import NDArray

from gyrolib import _compile_note  # noqa: F401  (a line on stderr at the first compile)
from gyrolib import _validation as v
from gyrolib._repr import compact_repr
from gyrolib.filtering.consistency import chi2_ppf
from gyrolib.filtering.discretization import van_loan
from gyrolib.filtering.kernels import (
    joseph_scalar_update_inline,
    measurement_projection_inline,
    predict_covariance_inline,
)
from gyrolib.gc.logs.calibration import calibrate, innovation_log_likelihood
from gyrolib.gc.logs.record import GCRecord
from gyrolib.gc.model import inputs
from gyrolib.gc.model.params import GyrocompassParams, state_index
from gyrolib.gc.model.state_space import (
    initial_covariance,
    measurement_matrix,
    measurement_noise_covariance,
    noise_input_matrix,
    system_matrix,
)

__all__ = [
    "NOISE_FIT_NAMES",
    "NoiseFit",
    "fit_checks",
    "fit_noise",
    "fit_uncertainty",
    "profile_intervals",
]

#: What :func:`fit_noise` can fit: fields of :class:`GyrocompassParams`, and ``C_in`` (one
#: intensity for both inclinometers, ``C_incl_y = C_incl_z``).
NOISE_FIT_NAMES: Final[tuple[str, ...]] = ("alpha1", "sigma1_sq", "xi1", "C_as", "C_in",
                                           "C_incl_y", "C_incl_z")

#: The names the inclinometers' marginal likelihood depends on (the start, step 1).
_INCLINOMETER_NAMES: Final[frozenset[str]] = frozenset(
    {"alpha1", "sigma1_sq", "xi1", "C_in", "C_incl_y", "C_incl_z"})

#: Finite-difference step in the log-parameters.
_STEP: Final[float] = 1e-3

#: Rounds of (fit, find the outliers under the fit) at most.
_MAX_ROUNDS: Final[int] = 3

#: A likelihood-ratio interval's half-width replaces the curvature's standard error (times
#: the normal quantile) when it is wider by more than this factor (its search's precision).
_WIDER: Final[float] = 1.05



# Result ---------------------------------------------------------------------------------
@compact_repr
@dataclass(frozen=True)
class NoiseFit:
    """The noise parameters fitted from a record (:func:`fit_noise`), SI.

    ``params`` the fitted model (the other fields as given), ``start`` the model the fit
    started from; ``names`` the fitted names (:data:`NOISE_FIT_NAMES`), ``values`` and
    ``std_errors`` in the same order; ``cov_log`` the covariance of their logarithms (the
    inverse Hessian of ``−ln L``); ``loglik``, ``loglik_start`` the log-likelihood at the
    optimum and at the start (the same measurements: outliers left out); ``converged``,
    ``message``, ``n_evaluations`` (likelihoods of the full filter; the inclinometer-only
    start is not counted); ``outliers`` the measurements left out as outliers, and
    ``outlier_cells`` (outliers, 2) which: their row of the record and their sensor (0 angle
    sensor, 1 ``inclinometer_y``, 2 ``inclinometer_z``; the likelihood of
    :func:`profile_intervals` leaves exactly these out; ``None`` for a fit made by hand,
    which :func:`profile_intervals` then refuses unless ``outliers = 0``); ``intervals``
    (n, 2) the 95 % likelihood-ratio interval of each
    (:func:`profile_intervals`; ``None`` until computed, an end ``inf`` or 0 where the
    likelihood does not fall by χ²₁(95 %)/2 inside the plausible range), ``interval_closed``
    (n, 2) whether each side's search found the crossing (``False``: an open end, or the
    outer end of a bracket the search could not close), ``level`` their confidence level.
    The standard errors are NaN when the Hessian at the end is not positive definite.  What
    the fit carries (:attr:`carried_log_std`, :meth:`carried_std_error`) is the curvature's
    standard error widened to the interval where the likelihood is not quadratic; a side
    much shorter than the curvature's is marked (:attr:`suspect_sides`).
    """

    params: GyrocompassParams
    start: GyrocompassParams
    names: tuple[str, ...]
    values: NDArray[np.float64]
    std_errors: NDArray[np.float64]
    cov_log: NDArray[np.float64]
    loglik: float
    loglik_start: float
    converged: bool
    message: str
    n_evaluations: int
    outliers: int
    intervals: NDArray[np.float64] | None = None
    level: float = 0.95
    outlier_cells: NDArray[np.int64] | None = None
    interval_closed: NDArray[np.bool_] | None = None

    def __post_init__(self) -> None:
        v.check_instance("params", self.params, GyrocompassParams)
        v.check_instance("start", self.start, GyrocompassParams)
        names = _check_names(self.names)
        n = len(names)
        object.__setattr__(self, "names", names)
        v.check_ndarray("values", self.values, shape=(n,))
        # NaN standard errors: no curvature (see message)
        for name, shape in (("std_errors", (n,)), ("cov_log", (n, n))):
            arr = getattr(self, name)
            if not isinstance(arr, np.ndarray) or arr.shape != shape or np.any(np.isinf(arr)):
                raise ValueError(f"{name} must be a float array of shape {shape} (finite or "
                                 "NaN)")
        v.check_real("loglik", self.loglik)
        v.check_real("loglik_start", self.loglik_start)
        v.check_bool("converged", self.converged)
        v.check_str("message", self.message)
        v.check_int("n_evaluations", self.n_evaluations, 0)
        v.check_int("outliers", self.outliers, 0)
        if self.intervals is not None:
            arr = self.intervals
            if not isinstance(arr, np.ndarray) or arr.shape != (n, 2):
                raise ValueError(f"intervals must be a float array of shape ({n}, 2)")
        v.check_in_range("level", self.level, 0.0, 1.0, low_open=True, high_open=True)
        if self.outlier_cells is not None:
            arr = self.outlier_cells
            if (not isinstance(arr, np.ndarray) or arr.shape != (self.outliers, 2)
                    or not np.issubdtype(arr.dtype, np.integer) or np.any(arr[:, 0] < 0)
                    or np.any((arr[:, 1] < 0) | (arr[:, 1] > 2))):
                raise ValueError(f"outlier_cells must be an integer array of shape "
                                 f"(outliers, 2) = ({self.outliers}, 2): rows >= 0 and "
                                 "sensors 0 (angle sensor), 1, 2 (inclinometers y, z)")
        if self.interval_closed is not None:
            arr = self.interval_closed
            if not isinstance(arr, np.ndarray) or arr.shape != (n, 2) or arr.dtype != bool:
                raise ValueError(f"interval_closed must be a bool array of shape ({n}, 2)")

    def interval(self, name: str) -> tuple[float, float]:
        """The 95 % likelihood-ratio interval of ``name`` (SI; :func:`profile_intervals`),
        or ``(nan, nan)`` when not computed."""
        i = self._index(name)
        if self.intervals is None:
            return (math.nan, math.nan)
        return (float(self.intervals[i, 0]), float(self.intervals[i, 1]))

    def _index(self, name: object) -> int:
        if not isinstance(name, str) or name not in self.names:
            raise ValueError(f"name must be one of the fitted names {self.names}; got "
                             f"{name!r}")
        return self.names.index(name)

    def value(self, name: str) -> float:
        """The fitted value of ``name`` (SI)."""
        return float(self.values[self._index(name)])

    def std_error(self, name: str) -> float:
        """Its standard error (SI), from the curvature of ``ln L`` at the optimum."""
        return float(self.std_errors[self._index(name)])

    @property
    def interval_sides(self) -> NDArray[np.float64]:
        """(n, 2): the length of each side of each interval in ``ln θ``, ``ln θ̂ − ln lo``
        and ``ln hi − ln θ̂`` (``inf`` at an open end, 0 or ``inf``; NaN without
        intervals)."""
        out = np.full((len(self.names), 2), np.nan)
        if self.intervals is None:
            return out
        theta = np.log(self.values)
        with np.errstate(divide="ignore"):
            out[:, 0] = theta - np.log(self.intervals[:, 0])
            out[:, 1] = np.log(self.intervals[:, 1]) - theta
        return out

    @property
    def curvature_half_widths(self) -> NDArray[np.float64]:
        """(n,): the half-width in ``ln θ`` of the interval the curvature gives at
        :attr:`level`, ``z · SE(ln θ)`` (``z`` = 1.96 at 95 %; NaN without curvature)."""
        return math.sqrt(float(_chi2_ppf(self.level, 1))) * self.relative_std_errors

    @property
    def suspect_sides(self) -> NDArray[np.bool_]:
        """(n, 2): the sides of the intervals shorter than a quarter of the curvature's
        half-width (:attr:`interval_sides` against :attr:`curvature_half_widths`).  A
        likelihood that is not quadratic moves a side from the curvature's, by a factor two
        or three on a skewed one; a side at a quarter of it or less is no such shape but a
        likelihood that jumps (one whose measurements change with the parameter) or a
        search that stopped early: the side is not to be trusted.  ``False`` where either
        figure is missing."""
        sides = self.interval_sides
        quarter = 0.25 * self.curvature_half_widths[:, None]
        with np.errstate(invalid="ignore"):
            return np.isfinite(quarter) & np.isfinite(sides) & (sides < quarter)

    def interval_findings(self) -> list[str]:
        """One sentence for each suspect side (:attr:`suspect_sides`), with both figures.

        Examples
        --------
        >>> import numpy as np
        >>> from gyrolib import gc
        >>> p = gc.GyrocompassParams()
        >>> fit = gc.NoiseFit(params=p, start=p, names=("C_as",), values=np.array([p.C_as]),
        ...                   std_errors=np.array([0.01 * p.C_as]), cov_log=np.array([[1e-4]]),
        ...                   loglik=0.0, loglik_start=0.0, converged=True, message="",
        ...                   n_evaluations=1, outliers=0,
        ...                   intervals=np.array([[0.9998 * p.C_as, 1.02 * p.C_as]]))
        >>> fit.suspect_sides.tolist()
        [[True, False]]
        >>> fit.interval_findings()[0][:70]
        'C_as: the lower side of its 95 % interval is SUSPECT: 0.0002 in ln, sh'
        """
        out = []
        sides = self.interval_sides
        half = self.curvature_half_widths
        z = math.sqrt(float(_chi2_ppf(self.level, 1)))
        for i, j in zip(*np.nonzero(self.suspect_sides)):
            out.append(f"{self.names[i]}: the {('lower', 'upper')[j]} side of its "
                       f"{100 * self.level:g} % interval is SUSPECT: {sides[i, j]:.2g} in ln, "
                       f"shorter than a quarter of the curvature's {half[i]:.2g} ({z:.3g} "
                       "standard errors of ln)")
        return out

    @property
    def carried_log_std(self) -> NDArray[np.float64]:
        """(n, 2): the standard deviation of ``ln θ`` below and above ``θ̂`` that the fit
        carries (into σ(ω_gc) by :func:`fit_uncertainty`, and as the reported standard
        error): the curvature's ``SE(ln θ)``, widened on each side to the half-width of the
        likelihood-ratio interval (:attr:`intervals`, :func:`profile_intervals`) over its
        normal quantile (1.96 at 95 %) where that is wider by more than 5 % (the interval's
        search stops within 2 % of its ends: a smaller excess is its rounding).  The
        likelihood of ``α1``, ``σ1²`` is not quadratic at the scale of one standard error:
        on 20 s with α1 × 5 its interval reaches 8 curvature SE below ``α̂1``
        (tests/gc/test_noise_fit.py).  An end the likelihood does not reach (0 or ``inf``)
        counts at the search's limit (the plausible range ×/÷ 10).  Without intervals, or
        where the curvature is wider (it overstates a side), the curvature's on that side.
        NaN without curvature.
        """
        se = self.relative_std_errors
        out = np.column_stack([se, se])
        if self.intervals is None:
            return out

        z = math.sqrt(float(chi2_ppf(self.level, 1)))
        theta = np.log(self.values)
        for i in range(len(self.names)):
            lo_lim, hi_lim = _search_limits(self, i)
            lo, hi = self.intervals[i]
            below = theta[i] - (math.log(lo) if lo > 0 else lo_lim)
            above = (math.log(hi) if math.isfinite(hi) else hi_lim) - theta[i]
            half = np.array([below, above]) / z
            # wider beyond the search's own precision (it stops within 2 % of an end)
            out[i] = np.where(half > _WIDER * out[i], half, out[i])
        return out

    def carried_std_error(self, name: str) -> float:
        """The standard error of ``name`` (SI) the fit reports and carries: ``θ̂`` times the
        larger side of :attr:`carried_log_std` (the curvature's where no interval is
        wider)."""
        i = self._index(name)
        return float(self.values[i] * np.max(self.carried_log_std[i]))

    def std_error_source(self, name: str) -> str:
        """Where :meth:`carried_std_error` comes from: ``"profile likelihood interval"``
        where the interval is wider than the curvature's, else ``"curvature"``."""
        i = self._index(name)
        wider = np.max(self.carried_log_std[i]) > self.relative_std_errors[i]
        return "profile likelihood interval" if wider else "curvature"

    @property
    def relative_std_errors(self) -> NDArray[np.float64]:
        """The standard errors of the logarithms of the fitted values (≈ relative standard
        errors; NaN without curvature)."""
        with np.errstate(invalid="ignore"):
            return np.sqrt(np.diag(self.cov_log))

    def not_identified(self, duration: float) -> str:
        """Why the fit gives no result on a record of ``duration`` s (``""`` when it does):
        not converged (after the retries of :func:`fit_noise`), or no curvature at the
        optimum.  A parameter the record pins down poorly is not a reason: it is a nuisance
        (:meth:`nuisance`) whose uncertainty :func:`fit_uncertainty` carries into σ(ω_gc).

        Examples
        --------
        >>> import numpy as np
        >>> from gyrolib import gc
        >>> p = gc.GyrocompassParams()
        >>> fit = gc.NoiseFit(params=p, start=p, names=("alpha1",), values=np.array([p.alpha1]),
        ...                   std_errors=np.array([0.1 * p.alpha1]),
        ...                   cov_log=np.array([[0.01]]), loglik=0.0, loglik_start=0.0,
        ...                   converged=False, message="stopped", n_evaluations=1, outliers=0)
        >>> fit.not_identified(100.0)
        'noise fit not converged: stopped'
        """
        v.check_positive("duration", duration)
        if not self.converged:
            return f"noise fit not converged: {self.message}"
        for nm, r in zip(self.names, self.relative_std_errors):
            if not np.isfinite(r):
                return f"{nm} not identified: the likelihood has no curvature at the optimum"
        return ""

    def nuisance(self, duration: float) -> list[str]:
        """The fitted parameters a record of ``duration`` s pins down poorly, one sentence
        each: a relative standard error above 1, or, for ``alpha1``, a record shorter than
        three correlation times ``1/(ξ1 α1)`` of the vibration (Eq. (6)).  They
        are nuisance parameters: :func:`fit_uncertainty` marginalizes over them (their
        covariance, and a vibration as slow as the record), so σ(ω_gc) widens by what they
        can move it, instead of the run being refused.

        Examples
        --------
        >>> import numpy as np
        >>> from gyrolib import gc
        >>> p = gc.GyrocompassParams()
        >>> fit = gc.NoiseFit(params=p, start=p, names=("alpha1",), values=np.array([p.alpha1]),
        ...                   std_errors=np.array([0.1 * p.alpha1]),
        ...                   cov_log=np.array([[0.01]]), loglik=0.0, loglik_start=0.0,
        ...                   converged=True, message="", n_evaluations=1, outliers=0)
        >>> fit.nuisance(100.0)[0][:60]
        'alpha1 poorly identified: the record (100 s) is shorter than'
        >>> fit.nuisance(1000.0)
        []
        """
        duration = v.check_positive("duration", duration)
        out = []
        for nm, r in zip(self.names, self.relative_std_errors):
            if np.isfinite(r) and r > 1.0:
                out.append(f"{nm} poorly identified: relative standard error {r:.3g} > 1")
        if "alpha1" in self.names:
            tc = 1.0 / (self.params.xi1 * self.params.alpha1)
            if duration < 3.0 * tc:
                out.append(f"alpha1 poorly identified: the record ({duration:.4g} s) is "
                           f"shorter than 3 correlation times 1/(xi1 alpha1) = {tc:.4g} s of "
                           "the fitted vibration spectrum; carried into sigma(omega_gc)")
        return out

    def summary(self) -> dict:
        """The fit as a JSON-ready dict (SI)."""
        return {
            "fitted": {nm: {"value": float(self.values[i]),
                            "std_error": self.carried_std_error(nm),
                            "std_error_from": self.std_error_source(nm),
                            "std_error_curvature": float(self.std_errors[i]),
                            "log_std_below_above": [float(x)
                                                    for x in self.carried_log_std[i]],
                            "interval": [_finite_or_none(x) for x in self.interval(nm)],
                            "interval_closed": (None if self.interval_closed is None else
                                                [bool(x) for x in self.interval_closed[i]]),
                            "interval_log_sides": [_finite_or_none(x)
                                                   for x in self.interval_sides[i]],
                            "curvature_log_half_width": _finite_or_none(
                                self.curvature_half_widths[i]),
                            "suspect_sides": [bool(x) for x in self.suspect_sides[i]]}
                       for i, nm in enumerate(self.names)},
            "loglik": self.loglik, "loglik_start": self.loglik_start,
            "converged": self.converged, "message": self.message,
            "n_evaluations": self.n_evaluations, "outliers": self.outliers,
        }

    def to_toml(self) -> str:
        """The fitted values as TOML text, each with its standard error and 95 % interval
        in a comment, for :func:`gyrolib.records.gc_params_from_toml` (``--params`` of the
        command line), and the model fields the fit ran with that differ from the paper's;
        nothing of the record: not ``dt`` (the sample interval comes from each record's time
        stamps) nor the site's ``Omega_h``, ``Omega_v`` (each record's latitude)."""
        fitted = set()
        lines = ["# paper GC model with noise parameters fitted from a record "
                 "(gyrolib.gc.fit_noise:",
                 "# maximum of the innovations log-likelihood; standard errors from its "
                 "curvature, widened to",
                 "# the 95 % likelihood-ratio interval where that is wider); SI units; no dt "
                 "or site rates (each record gives its own)",
                 f"# log-likelihood {self.loglik:.6f} (start {self.loglik_start:.6f}); "
                 f"converged: {str(self.converged).lower()}", ""]
        for i, nm in enumerate(self.names):
            lo, hi = self.interval(nm)
            for field in _fields_of(nm):
                fitted.add(field)
                lines.append(f"{field} = {_toml_value(getattr(self.params, field))}   "
                             f"# fitted: +- {self.carried_std_error(nm):.3g} (standard "
                             f"error, from the {self.std_error_source(nm)}; curvature "
                             f"{self.std_errors[i]:.3g}), interval [{lo:.4g}, {hi:.4g}]")
        default = GyrocompassParams()
        rest = [f.name for f in dataclasses.fields(self.params)
                if f.name not in fitted and f.name not in _RECORD_FIELDS
                and getattr(self.params, f.name) != getattr(default, f.name)]
        if rest:
            lines += ["", "# the model the fit ran with, where it is not the paper's"]
            lines += [f"{nm} = {_toml_value(getattr(self.params, nm))}" for nm in rest]
        return "\n".join(lines) + "\n"


#: Fields that belong to a record or its site, never written for reuse.
_RECORD_FIELDS: Final[frozenset[str]] = frozenset({"dt", "Omega_h", "Omega_v"})


def _chi2_ppf(level: float, dof: int) -> float:
    return float(chi2_ppf(level, dof))


def _finite_or_none(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


#: The row of the table of inputs (:mod:`gyrolib.inputs`) that holds each fitted name's
#: plausible range.
FIT_ROWS: Final[dict[str, str]] = {"alpha1": "gc.alpha1", "sigma1_sq": "gc.sigma1_sq",
                                   "xi1": "gc.xi1", "C_as": "gc.C_as", "C_in": "gc.C_incl",
                                   "C_incl_y": "gc.C_incl", "C_incl_z": "gc.C_incl"}

#: The white-noise intensities: a time base off by ε scales every one by 1 + ε (R = C/dt).
_INTENSITIES: Final[tuple[str, ...]] = ("C_as", "C_in", "C_incl_y", "C_incl_z")


def fit_checks(fit: NoiseFit, unfitted: object | None = None, *, clock_tolerance: float = 0.0,
               model_tolerance: float = 0.0, false_alarm: float = 0.01) -> list[dict]:
    """The checks a noise fit must pass before its calibration is a result, at a
    family-wise false-alarm rate (Šidák over the checks made).

    * **plausible range** (one per fitted name): the fitted value's interval
      ``θ̂ · exp(± z SE(ln θ))`` must reach the plausible range of its row of the table of
      inputs (:data:`FIT_ROWS`, :func:`gyrolib.inputs.row`; ``ξ1`` on a linear scale):
      a fit that lands outside it describes another instrument, or absorbs a fault.
    * **absorbed misfit** (when two or more white-noise intensities are fitted; the message
      says so when the run before the fit, ``unfitted``, failed a model check, whose misfit
      the fit then absorbs): a time base off by ε makes every
      sensor's per-sample variance ``C/dt`` look ``1 + ε`` times larger, the signature of a
      fit that moves every intensity by one common factor.  The ratios fitted/start of the
      intensities are tested for one common factor (χ² of their logarithms about their
      weighted mean, upper quantile); when they share one, its logarithm against
      ``√(SE² + clock_tolerance² + model_tolerance²)`` (two-sided normal;
      ``model_tolerance``, a stated relative tolerance on the model's innovation
      variances, 0 by default: the fit has no model bias that a record resolves.  The
      maximum-likelihood intensities follow the record's realized noise: on the clean
      100-s record with α1 × 10 (seed 5151) that once had both moved by 1.010 ± 0.0032,
      the sensors' noise draws themselves have per-sample variances 1.0096, 1.0102,
      1.0097 times ``C/dt`` (a 3.2-SE common factor of the draw, refused at this check's
      false-alarm rate, as any 3.2-SE draw is), and the fit gives 1.0097 and 1.0108, within
      0.3 SE of them, while 20 other seeds' draws average 1.000 ± 0.001
      (tests/gc/test_noise_fit.py); the unfitted filter predicts the innovation variances
      without a bias that a record resolves (tests/gc/test_nis_expectation.py)):
      a common factor beyond the clock's
      tolerance means the fit moved the levels only to absorb the misfit the unfitted run
      showed (or, on a record too short for the run before the fit to show it, that the
      unfitted run missed), and its ω̂_gc carries the time base's error (about ε Ω_h) that
      no σ holds.  Intensities that move apart are the sensors' own noise: no finding; two
      independent sensors whose noise differs from the start by one factor (within a few
      tenths of a percent at 100 s, 1 kHz) beyond the tolerances would be refused (stated);
      a time base off by 2.4 % is found in a minute of record at 1 kHz, not in 30 s.

    Parameters
    ----------
    fit : NoiseFit
    unfitted : CalibrationResult, optional
        The calibration of the same record with the start's parameters.
    clock_tolerance : float
        The logger's time-scale tolerance (1σ, relative; ``params.sigma_clock``).
    model_tolerance : float
        A stated relative tolerance of the model's innovation variances (default 0: none
        is needed, see above).
    false_alarm : float
        Family-wise false-alarm rate, in (0, 1).

    Returns
    -------
    list of dict
        ``test``, ``name``, ``statistic``, ``low``, ``high``, ``passed``, ``reason_code``
        (``fit_implausible``, ``fit_absorbs_misfit``) and ``message``.

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import gc
    >>> p = gc.GyrocompassParams()
    >>> fit = gc.NoiseFit(params=p, start=p, names=("C_as",), values=np.array([50 * p.C_as]),
    ...                   std_errors=np.array([0.5 * p.C_as]), cov_log=np.array([[1e-4]]),
    ...                   loglik=0.0, loglik_start=0.0, converged=True, message="",
    ...                   n_evaluations=1, outliers=0)
    >>> [(c["name"], c["passed"]) for c in gc.fit_checks(fit)]
    [('C_as', False)]
    """

    v.check_instance("fit", fit, NoiseFit)
    clock_tolerance = v.check_nonnegative("clock_tolerance", clock_tolerance)
    model_tolerance = v.check_nonnegative("model_tolerance", model_tolerance)
    false_alarm = v.check_in_range("false_alarm", false_alarm, 0.0, 1.0, low_open=True,
                                   high_open=True)
    se_log = fit.relative_std_errors
    misfit = unfitted is not None and any(
        c.startswith("misfit") for c in getattr(unfitted, "reason_codes", ()))
    idx = [i for i, nm in enumerate(fit.names) if nm in _INTENSITIES
           and np.isfinite(se_log[i]) and se_log[i] > 0]
    common = len(idx) >= 2
    n_tests = len(fit.names) + (2 if common else 0)
    a = 1.0 - (1.0 - false_alarm) ** (1.0 / n_tests)
    zlim = math.sqrt(float(chi2_ppf(1.0 - a, 1)))
    out = []
    for i, nm in enumerate(fit.names):
        row = inputs.row(FIT_ROWS[nm])
        ref = float(np.mean([getattr(fit.start, f) for f in _fields_of(nm)]))
        lo, hi = row.bounds(ref if row.relative else None)
        val = float(fit.values[i])
        s = float(se_log[i]) if np.isfinite(se_log[i]) else 0.0
        if row.scale == "log":
            stat = math.log(val)
            reach_lo, reach_hi = stat - zlim * s, stat + zlim * s
            ok = reach_hi >= math.log(lo) and reach_lo <= math.log(hi)
            shown = f"{val:.4g} (x/÷ {math.exp(zlim * s):.3g} at the test's level)"
        else:
            stat = val
            ok = val + zlim * val * s >= lo and val - zlim * val * s <= hi
            shown = f"{val:.4g} ± {zlim * val * s:.2g}"
        out.append({"test": "plausible range", "name": nm, "statistic": val, "low": lo,
                    "high": hi, "passed": bool(ok), "reason_code": "fit_implausible",
                    "message": f"fitted {nm} = {shown} is outside its plausible range "
                               f"[{lo:.3g}, {hi:.3g}] ({row.name} of gyrolib.inputs: "
                               f"{row.reason}): another instrument, or a fault the fit "
                               "absorbs"})
    if common:
        start = _log_values(fit.start, fit.names)
        r = np.log(fit.values[idx]) - start[idx]          # ln(fitted / start)
        w = 1.0 / se_log[idx] ** 2
        mean = float(np.sum(w * r) / np.sum(w))
        se = math.sqrt(1.0 / float(np.sum(w)))
        chi = float(np.sum(w * (r - mean) ** 2))
        lim = float(chi2_ppf(1.0 - a, len(idx) - 1))
        names = ", ".join(fit.names[i] for i in idx)
        shared = chi <= lim
        z = mean / math.sqrt(se * se + clock_tolerance**2 + model_tolerance**2)
        eps = math.expm1(mean)
        out.append({"test": "absorbed misfit", "name": names, "statistic": z,
                    "low": -zlim, "high": zlim,
                    "passed": bool(not shared or abs(z) <= zlim),
                    "reason_code": "fit_absorbs_misfit",
                    "message": f"the fit moves every white-noise intensity ({names}) by one "
                               f"common factor {1 + eps:.4g} ± {se:.2g} (their spread about "
                               f"it: chi-square {chi:.3g} <= {lim:.3g})"
                               + (" only to absorb the misfit the run before the fit showed"
                                  if misfit else "") + ": the signature of a "
                               f"time base off by {100 * eps:+.2g} % (a logger rate labelled "
                               "wrong? 1024 Hz read as 1 kHz is +2.4 %), which reads into "
                               "omega_gc as about that share of Omega_h; fix the time stamps "
                               "or state the clock's tolerance (--clock-tolerance)"})
    return out


def profile_intervals(record: GCRecord, fit: NoiseFit, *, level: float = 0.95,
                      max_steps: int = 10) -> NoiseFit:
    """``fit`` with the likelihood-ratio interval of each fitted parameter
    (:attr:`NoiseFit.intervals`): the values of ``θ_i`` where the log-likelihood has fallen
    by ``χ²₁(level)/2`` from its maximum, on each side, searched in ``ln θ_i`` with the
    other parameters moved along the ridge of the curvature (``Δθ = C[:, i]/C_ii · Δθ_i``,
    ``C`` = :attr:`NoiseFit.cov_log`: their conditional optimum for a quadratic likelihood,
    not re-maximized) — a profile likelihood to first order, which follows a skewed
    likelihood (a slow vibration's α1) where the curvature's symmetric ``± 1.96 SE`` does
    not.  Each side is a bracketed root search (:func:`_side_end`): from the quadratic
    guess, interpolation in ``√(2 ΔlnL)`` (linear in the step for a quadratic likelihood)
    kept inside the bracket, bisection where it would leave it; at most ``max_steps``
    likelihoods a side; stopped at the plausible range of the parameter's row of
    :mod:`gyrolib.inputs` (×/÷ 10 beyond it), which then is the end (``0`` or ``inf`` when
    the likelihood never falls that far).  A side the search could not close within
    ``max_steps`` is reported at the outer end of its bracket (open, ``0`` or ``inf``, with
    none): wider, never narrower, than what the record supports.  Whether each side found
    its crossing is :attr:`NoiseFit.interval_closed`; a side much shorter than the
    curvature's is marked (:attr:`NoiseFit.suspect_sides`).

    The likelihood is that of the record less the fit's outliers
    (:attr:`NoiseFit.outlier_cells`), the same cells at every point: the one the fit
    maximized.  With the outliers kept in, a burst of five angle-sensor outliers of 70
    standard deviations dominates ``ln L`` along ``C_as`` (their ``ν²/S`` falls as ``C_as``
    rises): on a 100-s record the lower side of ``C_as`` closed at 0.016 % below ``Ĉ_as``
    against 0.87 % from the curvature, and the upper one went out to +62 %
    (benchmarks/diag_fit_interval.py; tests/gc/test_noise_fit.py).

    The bracket matters on the α1–σ1² ridge of a short record, where the likelihood is flat
    for a decade and then falls by hundreds: unbracketed secant steps jumped between the flat
    part and the wall and stopped where their steps ran out, inside the flat part.  3 of
    the 9 misses of σ1² over 96 records of 100 s were such, with a likelihood ratio at the
    truth of 0.4–2.3 against 3.84.

    A side's search starts from the points an earlier parameter's search already evaluated
    on its line, where there are some (α1 and σ1² lie on one ridge and search the same
    points): they narrow the bracket without new likelihoods.  Cost: one to ``max_steps``
    likelihoods per side (one filter run over the record each: about 0.2 s per 100 s at
    1 kHz).

    Examples
    --------
    >>> import dataclasses
    >>> from gyrolib import gc
    >>> p = gc.GyrocompassParams()
    >>> rec = gc.simulate_record(dataclasses.replace(p, C_as=4e-13), 2.0, seed=1).record
    >>> fit = gc.profile_intervals(rec, gc.fit_noise(rec, p, fit=("C_as",)))
    >>> lo, hi = fit.interval("C_as")
    >>> bool(lo < 4e-13 < hi), bool(lo < fit.value("C_as") < hi)
    (True, True)
    """

    v.check_instance("record", record, GCRecord)
    v.check_instance("fit", fit, NoiseFit)
    level = v.check_in_range("level", level, 0.0, 1.0, low_open=True, high_open=True)
    max_steps = v.check_int("max_steps", max_steps, 1)
    names = fit.names
    theta = _log_values(fit.params, names)
    target = 0.5 * float(chi2_ppf(level, 1))
    # the fit's measurements: its outliers left out, the same cells at every point of the
    # profile (a set that followed the parameter would make the likelihood jump)
    clean = _without_outliers(record, fit)
    ll0 = _loglik_at_fit(clean, fit)
    C = fit.cov_log
    n = len(names)
    out = np.full((n, 2), np.nan)
    closed = np.zeros((n, 2), dtype=bool)
    sd = np.sqrt(np.abs(np.diag(C))) if np.all(np.isfinite(C)) else None
    seen: list[tuple[np.ndarray, float]] = []      # (θ − θ̂, ln L̂ − ln L) evaluated
    for i in range(len(names)):
        finite = bool(np.all(np.isfinite(C))) and C[i, i] > 0
        u = C[:, i] / C[i, i] if finite else np.eye(n)[i]
        s = math.sqrt(C[i, i]) if finite else 0.5
        limits = _search_limits(fit, i)
        for side, j in ((-1.0, 0), (1.0, 1)):
            room = (theta[i] - limits[0]) if side < 0 else (limits[1] - theta[i])

            def drop(d: float, side: float = side, u: np.ndarray = u) -> float:
                try:
                    value = ll0 - innovation_log_likelihood(
                        clean, _with(fit.params, names, theta + side * d * u))
                except ValueError:          # outside the parameter's domain (ξ1 > 1)
                    return math.inf
                if math.isfinite(value):
                    seen.append((side * d * u, value))
                return value if not math.isnan(value) else math.inf

            end, closed[i, j] = _side_search(drop, math.sqrt(2.0 * target) * s, room,
                                             target, max_steps,
                                             _on_line(seen, u, i, side, sd))
            if end >= room * (1 - 1e-9):     # the likelihood does not fall that far
                out[i, j] = 0.0 if side < 0 else math.inf
            else:
                out[i, j] = math.exp(theta[i] + side * end)
    return dataclasses.replace(fit, intervals=out, level=level, interval_closed=closed)


def _side_search(drop: Callable[[float], float], guess: float, room: float, target: float,
                 max_steps: int, known: Sequence[tuple[float, float]] = (),
                 rtol: float = 0.01) -> tuple[float, bool]:
    """The step ``d`` in ``(0, room]`` where ``drop(d)`` (``ln L̂ − ln L`` along a line,
    ``0`` at ``d = 0``) reaches ``target`` — one side of :func:`profile_intervals`; ``room``
    when it does not within ``room``.  A bracketed search on ``r(d) = √(2 drop(d))``
    (linear in ``d`` for a quadratic likelihood): ``lo`` is the largest step known below
    the target, ``hi`` the smallest known above it (``known``: ``(d, drop)`` pairs already
    evaluated on the line); the next step is ``guess`` at first, then the interpolation in
    ``r`` through the origin (no ``hi`` yet) or between ``lo`` and ``hi`` where it falls in
    the bracket's inner 90 %, else the bracket's middle (in ``ln d`` while it spans more
    than ×4).  The Illinois rule (an end kept twice in a row weighs half) stops a curved
    ``r`` from creeping up from one side.  Stops when ``r`` is within ``rtol`` of
    ``√(2 target)`` (2ΔlnL within about 2 ``rtol``) or the bracket within ``rtol`` of its
    end, and returns the step (interpolated in the bracket); after ``max_steps``
    evaluations without that, the bracket's outer end (``hi``, or ``room`` when no step
    reached the target): wider, not narrower.  Returns the step and whether it is a
    crossing found to that tolerance (``False`` for ``room`` or a bracket left open).

    >>> f = lambda d: 0.5 * (3.0 * d) ** 2          # quadratic: 2 drop = (3 d)²
    >>> round(_side_search(f, 0.1, 10.0, 1.92, 10)[0], 3)  # √3.84 / 3
    0.653
    >>> wall = lambda d: 1e-3 * d if d < 2.0 else 1e3 * (d - 2.0) + 2e-3   # flat, then a wall
    >>> round(_side_search(wall, 0.2, 10.0, 1.92, 10)[0], 1)     # at 2.0019, within rtol
    2.0
    >>> _side_search(lambda d: 1e-3 * d, 0.2, 10.0, 1.92, 10)    # never falls that far
    (10.0, False)
    """
    rt = math.sqrt(2.0 * target)
    lo_d, lo_g = 0.0, -rt               # g = r − √(2 target): below 0 at lo, above at hi
    hi_d, hi_g = math.inf, math.inf
    for d, dr in known:
        g = math.sqrt(2.0 * max(dr, 0.0)) - rt
        if g < 0.0 and d > lo_d:
            lo_d, lo_g = d, g
        elif g >= 0.0 and d < hi_d:
            hi_d, hi_g = d, g
    if lo_d >= hi_d:                    # a non-monotone line: keep the nearer crossing
        lo_d, lo_g = 0.0, -rt
    d = min(guess if (lo_d == 0.0 and hi_d == math.inf)
            else _next_step(lo_d, lo_g, hi_d, hi_g, rt, room), room)
    last = 0                            # the end the previous step replaced (−1 lo, +1 hi)
    for _ in range(max_steps):
        dr = drop(d)
        g = (math.sqrt(2.0 * max(dr, 0.0)) if math.isfinite(dr) else math.inf) - rt
        if abs(g) <= rtol * rt:
            return d, True
        if g < 0.0:
            if d >= room * (1 - 1e-9):
                return room, False
            if last == -1 and math.isfinite(hi_g):
                hi_g *= 0.5             # Illinois: the end kept twice weighs half
            lo_d, lo_g, last = d, g, -1
        else:
            if last == 1:
                lo_g *= 0.5
            hi_d, hi_g, last = d, g, 1
        if hi_d < math.inf and hi_d - lo_d <= rtol * hi_d:
            break
        d = _next_step(lo_d, lo_g, hi_d, hi_g, rt, room)
    if hi_d < math.inf and hi_d - lo_d <= rtol * hi_d and math.isfinite(hi_g):
        return lo_d - lo_g * (hi_d - lo_d) / (hi_g - lo_g), True
    return min(hi_d, room), False


def _side_end(drop: Callable[[float], float], guess: float, room: float, target: float,
              max_steps: int, known: Sequence[tuple[float, float]] = (),
              rtol: float = 0.01) -> float:
    """The step of :func:`_side_search` alone."""
    return _side_search(drop, guess, room, target, max_steps, known, rtol)[0]


def _next_step(lo_d: float, lo_g: float, hi_d: float, hi_g: float, rt: float,
               room: float) -> float:
    """:func:`_side_end`'s next step from its bracket ``(lo_d, hi_d)``, with ``g`` there."""
    if hi_d == math.inf:                # no upper end yet: the line through the origin
        lo_r = lo_g + rt
        if lo_r <= 0.0:
            return min(2.0 * lo_d, room)
        return min(max(lo_d * rt / lo_r, 1.25 * lo_d), room)
    w = hi_d - lo_d
    if lo_d > 0.0 and hi_d > 4.0 * lo_d:  # a wide bracket: its middle in ln d
        return math.sqrt(lo_d * hi_d)
    if math.isfinite(hi_g) and hi_g > lo_g:
        d = lo_d - lo_g * w / (hi_g - lo_g)
        if lo_d + 0.05 * w <= d <= hi_d - 0.05 * w:
            return d
    return lo_d + 0.5 * w


def _on_line(seen: list[tuple[np.ndarray, float]], u: np.ndarray, i: int, side: float,
             sd: np.ndarray | None) -> list[tuple[float, float]]:
    """The points an earlier search of :func:`profile_intervals` evaluated on this side's
    line (off it by less than 0.05 standard errors in every coordinate: two parameters
    correlated along a ridge, as α1 and σ1² are, search the same points), as
    ``(step, drop)``."""
    if sd is None:
        return []
    out = []
    for off, dr in seen:
        d = side * off[i]
        if d > 0.0 and np.max(np.abs(off - side * d * u) / np.where(sd > 0, sd, 1.0)) <= 0.05:
            out.append((d, dr))
    return out


def _search_limits(fit: NoiseFit, i: int) -> tuple[float, float]:
    """The ``ln θ`` range :func:`profile_intervals` searches for parameter ``i``: its row's
    plausible range (:mod:`gyrolib.inputs`) ×/÷ 10."""

    nm = fit.names[i]
    row = inputs.row(FIT_ROWS[nm])
    lo_b, hi_b = row.bounds(float(np.mean([getattr(fit.start, f) for f in _fields_of(nm)]))
                            if row.relative else None)
    return (math.log(max(lo_b, 1e-300)) - math.log(10.0), math.log(hi_b) + math.log(10.0))


def _toml_value(x: object) -> str:
    if isinstance(x, str):
        return json.dumps(x)
    x = float(x)
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    return repr(x)


def _fields_of(name: str) -> tuple[str, ...]:
    return ("C_incl_y", "C_incl_z") if name == "C_in" else (name,)


def _check_names(fit: object) -> tuple[str, ...]:
    if isinstance(fit, str) or not isinstance(fit, Sequence):
        raise TypeError(f"fit must be a tuple of names from {NOISE_FIT_NAMES}; got "
                        f"{type(fit).__name__}")
    names = tuple(fit)
    if not names:
        raise ValueError(f"fit must name at least one of {NOISE_FIT_NAMES}")
    for nm in names:
        if not isinstance(nm, str) or nm not in NOISE_FIT_NAMES:
            raise ValueError(f"fit must hold names from {NOISE_FIT_NAMES}; got {nm!r}")
    if len(set(names)) != len(names):
        raise ValueError(f"fit must not repeat a name; got {names}")
    if "C_in" in names and ({"C_incl_y", "C_incl_z"} & set(names)):
        raise ValueError("fit must not hold C_in together with C_incl_y or C_incl_z (C_in "
                         "sets both)")
    return names


def _without_outliers(record: GCRecord, fit: NoiseFit) -> GCRecord:
    """``record`` with the measurements ``fit`` left out as outliers set missing
    (:attr:`NoiseFit.outlier_cells`): the measurements its likelihood was maximized on."""
    cells = fit.outlier_cells
    if cells is None:
        if fit.outliers:
            raise ValueError(f"fit.outlier_cells must say which measurements the fit left "
                             f"out ({fit.outliers} outliers); got None: make the fit with "
                             "fit_noise")
        return record
    if cells.shape[0] == 0:
        return record
    if int(cells[:, 0].max()) >= record.n:
        raise ValueError(f"fit.outlier_cells must name rows of record; got row "
                         f"{int(cells[:, 0].max())}, but record has {record.n} rows: not the "
                         "record fitted")
    return _masked(record, cells[:, 0], cells[:, 1])


def _loglik_at_fit(clean: GCRecord, fit: NoiseFit) -> float:
    """``ln L`` at the fitted model of the record with the fit's outliers left out
    (:func:`_without_outliers`): the fit's own maximum, the same measurements (it differs
    from a new run only by the rounding of the log-parameters' round trip, ~1e-12
    relative)."""
    return float(fit.loglik)


def _slow_vibration(fit: NoiseFit, record: GCRecord, duration: float
                    ) -> GyrocompassParams | None:
    """A vibration correlated over the whole record, ``α1 = 1/(ξ1 · duration)`` with ``σ1²``
    refitted, when the likelihood cannot reject it against the fit (``2 ΔlnL < χ²₁(95 %)``,
    on the record less the fit's outliers); else ``None``."""
    import scipy.optimize

    p = fit.params
    slow = 1.0 / (p.xi1 * duration)
    if "alpha1" not in fit.names or slow >= p.alpha1:
        return None
    clean = _without_outliers(record, fit)      # the fit's measurements, outliers out
    ll_fit = _loglik_at_fit(clean, fit)

    def neg(log_s1: float) -> float:
        q = dataclasses.replace(p, alpha1=slow, sigma1_sq=math.exp(log_s1))
        return -innovation_log_likelihood(clean, q)

    x0 = math.log(p.sigma1_sq)
    best = scipy.optimize.minimize_scalar(neg, bounds=(x0 - 6.0, x0 + 3.0), method="bounded",
                                          options={"xatol": 0.05, "maxiter": 20})
    stat = 2.0 * (ll_fit + float(best.fun))
    if stat < 3.841458820694124:       # χ²(1) at 95 %: not rejected
        return dataclasses.replace(p, alpha1=slow, sigma1_sq=math.exp(float(best.x)))
    return None


def fit_uncertainty(record: GCRecord, fit: NoiseFit, *, samples: int = 16, seed: int = 0,
                    at_fit: object | None = None, **calibrate_options: object) -> float:
    """σ(ω_gc) (rad/s) with the fitted noise parameters' own uncertainty: ``samples`` draws
    of their logarithms from ``N(ln θ̂, C)`` (:attr:`NoiseFit.cov_log`), each side of each
    parameter stretched to what the record supports (:attr:`NoiseFit.carried_log_std`: the
    likelihood-ratio interval where the curvature understates it; a split normal), a
    calibration
    (:func:`gyrolib.gc.calibrate`, ``calibrate_options``) with each, and the law of total
    variance, ``√(mean_k σ_k² + var_k ω̂_k)``: the filter's σ at θ̂ treats the fitted values
    as exact, and it shrinks where the fit overestimates the vibration's bandwidth
   .  The curvature's covariance is not to be trusted for an ``alpha1`` that the
    record barely sees, so a vibration correlated over the whole record
    (``α1 = 1/(ξ1 T)``, ``σ1²`` refitted) that the likelihood cannot reject (likelihood
    ratio below χ²₁'s 95 % point) enters as an alternative model: the variance becomes the
    larger of the two models' plus the square of the difference of their estimates.
    Seeded: the same ``seed`` gives the same value.  ``at_fit``: the caller's
    :func:`gyrolib.gc.calibrate` of ``record`` with ``fit.params`` and the same
    ``calibrate_options`` (its ``omega_gc`` and ``omega_gc_std`` are used; saves a run).

    Examples
    --------
    With no uncertainty in the fit the calibration's own σ comes back:

    >>> import numpy as np
    >>> from gyrolib import gc
    >>> p = gc.GyrocompassParams()
    >>> rec = gc.simulate_record(p, 2.0, seed=1).record
    >>> fit = gc.NoiseFit(params=p, start=p, names=("C_as",), values=np.array([p.C_as]),
    ...                   std_errors=np.array([0.0]), cov_log=np.array([[0.0]]), loglik=0.0,
    ...                   loglik_start=0.0, converged=True, message="", n_evaluations=1,
    ...                   outliers=0)
    >>> s = gc.fit_uncertainty(rec, fit, samples=2)
    >>> bool(np.isclose(s, gc.calibrate(rec, p).omega_gc_std, rtol=1e-9))
    True
    """
    v.check_instance("record", record, GCRecord)
    v.check_instance("fit", fit, NoiseFit)
    samples = v.check_int("samples", samples, 2)
    seed = v.check_int("seed", seed, 0)
    C = fit.cov_log
    if not np.all(np.isfinite(C)):
        raise ValueError("fit has no covariance (cov_log not finite): the parameters are not "
                         "identified, see NoiseFit.not_identified")
    theta = _log_values(fit.params, fit.names)
    # a symmetric square root (C may be singular: a parameter held exactly)
    w, U = np.linalg.eigh(0.5 * (C + C.T))
    root = U * np.sqrt(np.clip(w, 0.0, None))
    # each side of each parameter widened to what the record supports (carried_log_std:
    # the likelihood-ratio interval where the curvature understates it)
    se = np.sqrt(np.clip(np.diag(C), 0.0, None))
    with np.errstate(invalid="ignore", divide="ignore"):
        widen = np.where(se[:, None] > 0, fit.carried_log_std / se[:, None], 1.0)
    rng = np.random.default_rng(seed)
    est, var = [], []
    for _ in range(samples):
        d = root @ rng.standard_normal(theta.size)
        th = theta + d * np.where(d < 0, widen[:, 0], widen[:, 1])
        res = calibrate(record, _with(fit.params, fit.names, th), **calibrate_options)
        est.append(res.omega_gc)
        var.append(res.omega_gc_std ** 2)
    total = float(np.mean(var) + np.var(est, ddof=1))
    if record.n > 1:
        slow = _slow_vibration(fit, record, float(record.t[-1] - record.t[0]))
        if slow is not None:
            if at_fit is None:
                at_fit = calibrate(record, fit.params, **calibrate_options)
            alt = calibrate(record, slow, **calibrate_options)
            total = max(total, alt.omega_gc_std ** 2) + (at_fit.omega_gc - alt.omega_gc) ** 2
    return float(math.sqrt(total))


def _with(p: GyrocompassParams, names: tuple[str, ...], theta: np.ndarray
          ) -> GyrocompassParams:
    """``p`` with the fitted names set to ``exp(theta)``."""
    values = {}
    for nm, th in zip(names, theta):
        for field in _fields_of(nm):
            values[field] = math.exp(float(th))
    return dataclasses.replace(p, **values)


def _log_values(p: GyrocompassParams, names: tuple[str, ...]) -> np.ndarray:
    out = []
    for nm in names:
        fields = _fields_of(nm)
        out.append(np.mean([math.log(getattr(p, f)) for f in fields]))
    return np.array(out)


# The inclinometers' marginal likelihood (the start) --------------------------------------------
_INCL_STATES: Final[tuple[int, ...]] = tuple(state_index(nm)
                                             for nm in ("delta", "gamma", "N1", "N2"))

#: The inclinometer filter's state size, a compile-time constant of its kernel (the shared
#: kernels' bodies, gyrolib.filtering.kernels, inlined with it: their loops unroll).
_N_INCL: Final[int] = len(_INCL_STATES)


@njit(cache=True)
def _inclinometer_kernel(steps, z, Phi, rowptr, colidx, Qd, H, hptr, hidx, r, P0):
    """Σ (ln S + ν²/S) and the number of measurements of the 4-state inclinometer filter;
    ``steps[i]`` whole steps of ``Phi`` (its nonzeros in CSR form: ``rowptr``, ``colidx``),
    ``Qd`` before row ``i``, ``z`` (rows × 2)."""
    n = _N_INCL
    P = P0.copy()
    x = np.zeros(n)
    y = np.zeros(n)
    T = np.zeros((n, n))
    Ph = np.zeros(n)
    k = np.zeros(n)
    total = 0.0
    count = 0
    for i in range(z.shape[0]):
        for _ in range(steps[i]):
            for a in range(n):            # x ← Φ x
                s = 0.0
                for p in range(rowptr[a], rowptr[a + 1]):
                    s += Phi[a, colidx[p]] * x[colidx[p]]
                y[a] = s
            for a in range(n):
                x[a] = y[a]
            predict_covariance_inline(P, Phi, rowptr, colidx, Qd, T, n)
        for q in range(z.shape[1]):
            zq = z[i, q]
            if math.isnan(zq):
                continue
            S = measurement_projection_inline(P, H, q, hptr, hidx, Ph, n) + r[q]
            hx = 0.0
            for p in range(hptr[q], hptr[q + 1]):
                hx += H[q, hidx[p]] * x[hidx[p]]
            nu = zq - hx
            total += math.log(S) + nu * nu / S
            count += 1
            for a in range(n):
                k[a] = Ph[a] / S
                x[a] += k[a] * nu
            joseph_scalar_update_inline(P, Ph, k, S, n)
    return total, count


def _inclinometer_loglik(p: GyrocompassParams, steps: np.ndarray, z: np.ndarray) -> float:
    idx = list(_INCL_STATES)
    F = system_matrix(p, 0.0)[np.ix_(idx, idx)]     # (δ, γ, N1, N2) do not depend on β_n
    G = noise_input_matrix(p)[idx, :1]
    Phi, Qd = van_loan(F, G, np.array([[p.Q1]]), p.dt)
    H = np.ascontiguousarray(measurement_matrix(p)[1:, idx])
    pmask = Phi != 0
    rowptr = np.concatenate([[0], np.cumsum(pmask.sum(axis=1))]).astype(np.int64)
    colidx = np.nonzero(pmask)[1].astype(np.int64)
    hmask = H != 0
    hptr = np.concatenate([[0], np.cumsum(hmask.sum(axis=1))]).astype(np.int64)
    hidx = np.nonzero(hmask)[1].astype(np.int64)
    r = np.diag(measurement_noise_covariance(p))[1:].copy()
    P0 = initial_covariance(p)[np.ix_(idx, idx)]
    total, count = _inclinometer_kernel(steps, z, Phi, rowptr, colidx, Qd, H, hptr, hidx, r,
                                        P0)
    return -0.5 * (count * math.log(2.0 * math.pi) + total)


def _whole_steps(t: np.ndarray, dt: float) -> np.ndarray:
    h = np.diff(np.concatenate([[0.0], t]))
    return np.maximum(np.rint(h / dt), 0).astype(np.int64)


# Maximization in log-parameters ---------------------------------------------------------------
class _BudgetExceeded(Exception):
    pass


class _Objective:
    """``−ln L`` as a function of the coordinates ``φ = A θ`` (``θ`` the log-parameters),
    with a finite-difference gradient and Hessian (diagonal and gradient central, off-diagonal
    forward) from one cached stencil per point; the step of each coordinate follows its
    curvature (a tenth of its standard error), so that a flat direction is resolved above the
    rounding of ``ln L``."""

    def __init__(self, loglik: Callable[[np.ndarray], float], A: np.ndarray,
                 max_evaluations: int, progress: Callable[[int], None] | None,
                 steps: np.ndarray | None = None) -> None:
        self.loglik = loglik
        self.A_inv = np.linalg.inv(A)
        self.max_evaluations = max_evaluations
        self.progress = progress
        self.values: dict[bytes, float] = {}
        self.stencils: dict[bytes, tuple[np.ndarray, np.ndarray]] = {}
        self.n = 0
        self.h = np.full(A.shape[0], _STEP) if steps is None else steps.copy()

    def theta(self, phi: np.ndarray) -> np.ndarray:
        return self.A_inv @ np.asarray(phi, dtype=float)

    def __call__(self, phi: np.ndarray) -> float:
        phi = np.asarray(phi, dtype=float)
        key = phi.tobytes()
        if key not in self.values:
            if self.n >= self.max_evaluations:
                raise _BudgetExceeded
            try:
                val = -self.loglik(self.theta(phi))
            except ValueError:     # a step outside the parameters' range (ξ1 > 1)
                val = math.inf
            self.n += 1
            if self.progress is not None:
                self.progress(self.n)
            self.values[key] = val if math.isfinite(val) else math.inf
        return self.values[key]

    def stencil(self, phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        phi = np.asarray(phi, dtype=float)
        key = phi.tobytes()
        if key in self.stencils:
            return self.stencils[key]
        n = phi.size
        h = self.h
        f0 = self(phi)
        e = np.diag(h)
        fp = np.array([self(phi + e[i]) for i in range(n)])
        fm = np.array([self(phi - e[i]) for i in range(n)])
        g = (fp - fm) / (2.0 * h)
        H = np.diag((fp - 2.0 * f0 + fm) / h**2)
        for i in range(n):
            for j in range(i + 1, n):
                fij = self(phi + e[i] + e[j])
                H[i, j] = H[j, i] = (fij - fp[i] - fp[j] + f0) / (h[i] * h[j])
        self.stencils[key] = (g, H)
        # the next stencil's steps: a tenth of each coordinate's standard error
        d = np.diag(H)
        self.h = np.where(d > 0, np.clip(0.1 / np.sqrt(np.where(d > 0, d, 1.0)), 1e-5, 0.2),
                          self.h)
        return g, H


def _maximize(objective: _Objective | _Sub, phi0: np.ndarray, tol: float
              ) -> tuple[np.ndarray, bool, str]:
    """Minimize ``objective`` from ``phi0`` by scipy's ``trust-exact`` (Newton steps in a
    trust region; an indefinite Hessian is handled), stopped when the Newton decrement
    ``gᵀ H⁻¹ g`` (the squared distance to the optimum in standard errors) is below ``tol``:
    a gradient tolerance would be lost in the rounding of ``ln L``, whose curvatures differ
    by many orders of magnitude between the parameters."""
    best = [np.asarray(phi0, dtype=float).copy()]
    state = {"done": False}

    def fun(phi):
        val = objective(phi)
        if val < objective(best[0]):
            best[0] = np.array(phi, dtype=float)
        return val

    def close_enough(phi) -> bool:
        g, H = objective.stencil(phi)
        try:
            w = np.linalg.eigvalsh(H)
            return bool(w[0] > 0 and g @ np.linalg.solve(H, g) < tol)
        except np.linalg.LinAlgError:
            return False

    def callback(intermediate_result):
        if close_enough(intermediate_result.x):
            state["done"] = True
            raise StopIteration

    if close_enough(phi0):
        return np.asarray(phi0, dtype=float), True, "at the optimum already"
    import scipy.optimize  # here, not at the command line's start

    try:
        res = scipy.optimize.minimize(
            fun, phi0, method="trust-exact", jac=lambda ph: objective.stencil(ph)[0],
            hess=lambda ph: objective.stencil(ph)[1], callback=callback,
            options={"gtol": 1e-12, "initial_trust_radius": 1.0, "max_trust_radius": 5.0,
                     "maxiter": 100})
    except _BudgetExceeded:
        return best[0], False, "stopped after max_evaluations likelihoods"
    if state["done"]:
        return np.asarray(res.x, dtype=float), True, (
            f"converged: Newton decrement below {tol:g} after {res.nit} iterations")
    return np.asarray(res.x, dtype=float), bool(res.success), str(res.message)


def _coordinates(names: tuple[str, ...]) -> np.ndarray:
    """``A`` with ``φ = A θ``: the log-parameters, except that ``ln σ1²`` is replaced by
    ``ln Q1 − ln 2 = ln ξ1 + ln α1 + ln σ1²`` when ``α1`` is fitted with it.  The record
    pins the white-noise intensity ``Q1`` (the vibration's fast part) far better than ``α1``
    (its slow part), so ``(ln α1, ln σ1²)`` lie along a narrow ridge; ``(ln α1, ln Q1)`` do
    not."""
    n = len(names)
    A = np.eye(n)
    if "sigma1_sq" in names and "alpha1" in names:
        i = names.index("sigma1_sq")
        A[i, names.index("alpha1")] = 1.0
        if "xi1" in names:
            A[i, names.index("xi1")] = 1.0
    return A


def _fit_inclinometers(p0: GyrocompassParams, names: tuple[str, ...], record: GCRecord,
                       budget: int) -> tuple[np.ndarray, np.ndarray]:
    """The start (step 1): the inclinometers' marginal likelihood maximized over ``names``
    (all of them inclinometer names); ``α1`` first by a scan over ×/÷ 100 of its start
    (the likelihood is flat for small ``α1``, where Newton steps stall).  Returns the
    log-parameters and the finite-difference steps its curvature asks for."""
    steps = _whole_steps(record.t, p0.dt)
    z = np.column_stack([record.inclinometer_y, record.inclinometer_z])
    A = _coordinates(names)
    obj = _Objective(lambda th: _inclinometer_loglik(_with(p0, names, th), steps, z), A,
                     budget, None)
    phi = A @ _log_values(p0, names)
    if "alpha1" in names:
        ia = names.index("alpha1")
        rest = [i for i in range(len(names)) if i != ia]
        if rest:   # the others at the start's α1
            phi[rest] = _maximize(_Sub(obj, phi, rest), phi[rest], 1e-2)[0]
        grid = phi[ia] + np.linspace(-math.log(100.0), math.log(100.0), 21)
        vals = []
        for a in grid:
            trial = phi.copy()
            trial[ia] = a
            vals.append(obj(trial))
        phi[ia] = grid[int(np.argmin(vals))]
    phi = _maximize(obj, phi, 1e-3)[0]
    obj.stencil(phi)
    return obj.theta(phi), obj.h


class _Sub:
    """``objective`` over the coordinates ``idx`` only, the others held at ``phi``."""

    def __init__(self, objective: _Objective, phi: np.ndarray, idx: list[int]) -> None:
        self.objective = objective
        self.phi = np.asarray(phi, dtype=float).copy()
        self.idx = idx

    def _full(self, sub: np.ndarray) -> np.ndarray:
        out = self.phi.copy()
        out[self.idx] = sub
        return out

    def __call__(self, sub: np.ndarray) -> float:
        return self.objective(self._full(sub))

    def stencil(self, sub: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        g, H = self.objective.stencil(self._full(sub))
        return g[self.idx], H[np.ix_(self.idx, self.idx)]


# The fit ----------------------------------------------------------------------------------
def _masked(record: GCRecord, rows: np.ndarray, sensors: np.ndarray) -> GCRecord:
    cols = [np.array(c, dtype=float) for c in (record.angle_sensor, record.inclinometer_y,
                                               record.inclinometer_z)]
    for q in range(3):
        cols[q][rows[sensors == q]] = np.nan
    return GCRecord(t=record.t, angle_sensor=cols[0], inclinometer_y=cols[1],
                    inclinometer_z=cols[2])


def _rejected_cells(record: GCRecord, res: object) -> tuple[np.ndarray, np.ndarray]:
    """Rows and sensors the gate of a :func:`calibrate` run rejected (sorted)."""
    rows = np.searchsorted(record.t, res.rejected_t)
    order = np.lexsort((res.rejected_sensor, rows))
    return rows[order], res.rejected_sensor[order]


def fit_noise(record: GCRecord, params: GyrocompassParams | None = None, *,
              fit: Sequence[str] = ("alpha1", "sigma1_sq", "C_as", "C_in"),
              gate: float = 1.0 - 1e-9, max_evaluations: int = 400,
              progress: Callable[[int], None] | None = None) -> NoiseFit:
    """Fit the noise parameters of paper GC's model to a record by maximum likelihood.

    Maximizes the innovations log-likelihood (:func:`gyrolib.gc.innovation_log_likelihood`)
    over the parameters ``fit``, in their logarithms, with :func:`scipy.optimize.minimize`
    (see the module docstring: start from the inclinometers' exact marginal likelihood,
    Newton steps on the full one, outliers left out); standard errors from the curvature at
    the optimum.  A fit that does not converge is repeated from other starts (every fitted
    value but ξ1 times 10, 0.1, 3 in turn) and the best converged one is returned.  Paper GC
    models the vibration by Eq. (6) with the HFB 320's spectrum; a gyro on another base
    needs its own ``α1``, ``σ1²`` (and the sensors their own noise).

    Parameters
    ----------
    record : GCRecord
        The record (SI), in memory (the fit reads it many times).
    params : GyrocompassParams, optional
        The model; its values of the fitted names are the start, the others stay fixed
        (default: the paper's).
    fit : sequence of str
        Names from :data:`NOISE_FIT_NAMES`: ``alpha1``, ``sigma1_sq``, ``xi1`` (Eq. (6)),
        ``C_as``, ``C_in`` (both inclinometers alike) or ``C_incl_y``, ``C_incl_z``.
    gate : float
        The gate of :func:`gyrolib.gc.calibrate` that finds the outliers left out (default
        a tail of 1e-9: gross outliers only; a tighter gate would cut the tails of good
        data and bias the intensities low, by 0.2 % at 0.9999).
    max_evaluations : int
        Likelihoods of the full filter at the most (each about 0.2 s per 100 s of record).
    progress : callable, optional
        Called with the number of full likelihoods evaluated so far.

    Returns
    -------
    NoiseFit
        The fitted model, each value with its standard error, ``to_toml()``.

    Examples
    --------
    >>> import dataclasses
    >>> from gyrolib import gc
    >>> p = gc.GyrocompassParams()
    >>> rec = gc.simulate_record(dataclasses.replace(p, C_as=4e-13), 2.0, seed=1).record
    >>> fit = gc.fit_noise(rec, p, fit=("C_as",))
    >>> z = (fit.value("C_as") - 4e-13) / fit.std_error("C_as")
    >>> bool(abs(z) < 3), bool(fit.loglik > fit.loglik_start)
    (True, True)
    """
    v.check_instance("record", record, GCRecord)
    p0 = GyrocompassParams() if params is None else v.check_instance(
        "params", params, GyrocompassParams)
    names = _check_names(fit)
    gate = v.check_in_range("gate", gate, 0.0, 1.0, low_open=True, high_open=True)
    max_evaluations = v.check_int("max_evaluations", max_evaluations, 1)
    if progress is not None and not callable(progress):
        raise TypeError(f"progress must be callable or None; got {type(progress).__name__}")
    best = _fit_once(record, p0, names, gate, max_evaluations, progress)
    if best.converged:
        return best
    # not converged: again from other starts (α1 and σ1² a decade either way, the
    # intensities halved and doubled), the best converged fit wins
    tried = [best]
    for factor in _RETRY_FACTORS:
        start = dataclasses.replace(p0, **{f: getattr(p0, f) * factor
                                           for nm in names for f in _fields_of(nm)
                                           if nm != "xi1"})
        alt = _fit_once(record, start, names, gate, max_evaluations, progress)
        alt = dataclasses.replace(alt, start=p0,
                                  message=f"{alt.message} (retried from the start x {factor:g})",
                                  loglik_start=best.loglik_start)
        tried.append(alt)
        if alt.converged:
            break
    done = [f for f in tried if f.converged]
    return max(done or tried, key=lambda f: f.loglik)


#: The starts of the retries: every fitted value (but ξ1) times these factors in turn.
_RETRY_FACTORS: Final[tuple[float, ...]] = (10.0, 0.1, 3.0)


def _fit_once(record: GCRecord, p0: GyrocompassParams, names: tuple[str, ...], gate: float,
              max_evaluations: int, progress: Callable[[int], None] | None) -> NoiseFit:
    """One maximization of the likelihood from ``p0`` (:func:`fit_noise`'s steps 1, 2)."""
    theta = _log_values(p0, names)
    # 1. the start: the inclinometers' marginal likelihood over the names it depends on
    sub = [i for i, nm in enumerate(names) if nm in _INCLINOMETER_NAMES]
    steps = np.full(len(names), _STEP)
    if sub:
        theta[sub], steps[sub] = _fit_inclinometers(p0, tuple(names[i] for i in sub), record,
                                                    50 * max_evaluations)
    A = _coordinates(names)
    # 2. the full likelihood, the outliers under the current fit left out, until they stay;
    # the angle sensor's intensity starts where its mean NIS is 1 (its innovations are
    # almost all sensor noise)
    objective = None
    rows = sensors = np.zeros(0, dtype=np.int64)
    spent = 0            # full likelihoods of the rounds before the current one
    converged, message = False, ""
    for rnd in range(_MAX_ROUNDS):
        res = calibrate(record, _with(p0, names, theta), gate=gate, store_every=record.n + 1)
        if rnd == 0 and "C_as" in names and res.used[0] > 0:
            ia = names.index("C_as")
            theta[ia] += math.log(float(res.nis_mean[0]))
            # −ln L ≈ Σ ½ (ln S + ν²/S) with S ∝ C_as: curvature n/2 in ln C_as
            steps[ia] = 0.1 * math.sqrt(2.0 / float(res.used[0]))
            res = calibrate(record, _with(p0, names, theta), gate=gate,
                            store_every=record.n + 1)
        new_rows, new_sensors = _rejected_cells(record, res)
        if objective is not None and np.array_equal(new_rows, rows) and np.array_equal(
                new_sensors, sensors):
            break
        if objective is not None:
            spent += objective.n
            steps = objective.h
        rows, sensors = new_rows, new_sensors
        clean = _masked(record, rows, sensors)
        objective = _Objective(
            lambda th, clean=clean: innovation_log_likelihood(clean, _with(p0, names, th)),
            A, max_evaluations - spent,
            None if progress is None else (lambda k, base=spent: progress(base + k)), steps)
        phi, converged, message = _maximize(objective, A @ theta, 1e-4)
        theta = objective.theta(phi)
        if not converged:
            break
    n = len(names)
    cov_log = np.full((n, n), np.nan)
    try:
        _, hess = objective.stencil(A @ theta)
    except _BudgetExceeded:
        converged, message = False, message + "; no budget left for the curvature"
    else:
        if np.all(np.linalg.eigvalsh(0.5 * (hess + hess.T)) > 0):
            A_inv = np.linalg.inv(A)
            cov_log = A_inv @ np.linalg.inv(hess) @ A_inv.T     # back to the log-parameters
        else:
            converged = False
            message += "; the Hessian at the end is not positive definite"
    values = np.exp(theta)
    return NoiseFit(params=_with(p0, names, theta), start=p0, names=names, values=values,
                    std_errors=values * np.sqrt(np.diag(cov_log)), cov_log=cov_log,
                    loglik=-objective(A @ theta),
                    loglik_start=innovation_log_likelihood(_masked(record, rows, sensors), p0),
                    converged=converged, message=message, n_evaluations=spent + objective.n,
                    outliers=int(rows.size),
                    outlier_cells=np.column_stack([rows, sensors]).astype(np.int64))
