"""The method paper GC replaces (its ref. [3], p. 52): the north gyro in rate-sensor mode on
the caged platform, two positions 180° apart, and what two estimators make of it.

The procedure, as paper GC lists it after its Figure 1:

1. measure the torque-sensor output for ``T1`` in position 1;
2. turn the rate sensor's base by 180° (``T_rot``, turning error ``sigma_rot``);
3. wait ``T_settle`` for the rate sensor's transient;
4. measure for ``T2`` in position 2;
5. correct for the vertical Earth rate from the inclinometers.

The model uses paper GC's disturbances and priors: the vibration ``N1`` of Eq. (6) through the
unbalance and on the inclinometers, the random drift ``N3`` of Eq. (7), the inclinometer
noises, the priors of ω_gc, δ, γ (and of ψ, through the Earth-rate terms).  The float is held
at its null by the feedback loop, so the output is the right-hand side of Eq. (3) over ``H``
at ``β = 0``, with the base's azimuth ``θ`` (0, then ``π + ε``) in the horizontal term::

    r = (1 + k) [Ω_h cos(θ − ψ) + Ω_v γ + ω_gc + s ω_ub N1 / g + N3] + v_r

``k`` is the torque sensor's scale-factor error and ``v_r`` its white output noise (intensity
``rate_noise``); ``s = ±1`` the sign with which the turned sensors see the carrier's vibration.

**The rebalance loop.**  The float is held at the null of its angle sensor by a proportional
rebalance loop of bandwidth ``ω_b`` (``loop_bandwidth``): the commanded rate is
``u = k_b (β + n_as)`` with ``k_b = f ω_b / H`` (the loop's crossover is ``ω_b`` when
``ω_b ≪ f/I``), ``n_as`` the angle sensor's white noise (intensity ``C_as``, the same sensor as
GC's).  The float obeys ``I β'' + f β' = H (ω_in − u)``, so the loop makes it follow the
pickoff noise, and the mean of the output over a sample of length ``Δt`` is, exactly,
``ω_in − (f/H) Δβ/Δt − (I/H) Δβ'/Δt``: over a window the float's motion telescopes to
``(f/H)(β_end − β_start)/T`` — the pickoff noise differentiated, paper GC's noise that the
measurement time must average out (p. 52).  The output is counted in pulses of
``quantization`` (rad) of the accumulated angle, a further ``(a_k − a_{k−1})/Δt`` with ``a``
uniform (variance ``q²/12``).  The float's closed-loop response to the slowly varying input
rate itself is left out of the model (the truth of :func:`rate_sensor_monte_carlo` keeps it,
and the transient of the turn, which the settling time must cover).
A turn about the local vertical keeps the tilt of the input axis, so the vertical Earth rate
``Ω_v γ`` does not change sign and has to be corrected (step 5); the horizontal term does.
Linearized (the known ``±Ω_h`` removed), position 1 reads ``ω_gc + e + Ω_v γ + …`` and
position 2 ``ω_gc − e + d + Ω_v γ + …`` with

* ``e = (1 + k) Ω_h cos ψ − Ω_h`` — the part of the Earth-rate reading the method does not
  know (to first order ``k Ω_h``: with the input axis near north, ψ enters only as ψ²/2);
  the turn cancels it;
* ``d = (1 + k) Ω_h [cos ψ − cos(ε − ψ)] ≈ Ω_h (ε²/2 − ε ψ)`` — what the turning error ε
  leaves behind, second order, with ``E[d²] = Ω_h² (σ_ψ² σ_ε² + 3 σ_ε⁴ / 4)``.

State vector of the model (:data:`RS_STATE_NAMES`, SI)::

    omega_gc  ω_gc                                     rad/s
    earth     e, unknown part of the Earth-rate reading rad/s
    turn      d, left by the turning error              rad/s
    delta     δ, gamma γ: platform tilts                rad
    N1, N2    vibration, Eq. (6)                        m/s², m/s³
    N3, N4    random drift, Eq. (7)                     rad/s, rad/s²
    beta, beta_rate         float angle β, β' (loop)    rad, rad/s
    beta_prev, beta_rate_prev  the same one sample earlier
    quant, quant_prev       quantization residual a_k, a_(k−1)  rad

Sampled every ``sample_dt`` (rate sensor and both inclinometers; a continuous white noise of
intensity ``C`` averaged over a sample has variance ``C/sample_dt``).

* :class:`RateSensorProcedure` — the procedure's parameters (the paper gives none);
* :func:`rate_sensor_model` → :class:`RateSensorModel` — the discrete model, the classical
  estimator's σ (:meth:`RateSensorModel.classical_sigma`) and the optimal one's
  (:meth:`RateSensorModel.optimal_run`, a Kalman covariance analysis built from
  :mod:`gyrolib.filtering`);
* :func:`rate_sensor_monte_carlo` — the classical estimator on an independent truth.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from functools import cached_property
from typing import Final

import numpy as np
import scipy.linalg
from numba import njit
from numpy.typing import NDArray

from gyrolib import _validation as v
from gyrolib import levels
from gyrolib._repr import compact_repr
from gyrolib.filtering.consistency import nees_bounds
from gyrolib.filtering.covariance import AffineDiscreteModel, covariance_fast
from gyrolib.filtering.discretization import covariance_factor, van_loan
from gyrolib.gc.analysis.montecarlo import TRUTH_SUBSTEPS, zoh_discretize
from gyrolib.gc.model.params import GyrocompassParams, check_params
from gyrolib.units import ARCMIN, ARCSEC_PAPER

__all__ = [
    "RS_STATE_NAMES",
    "VIBRATION_FRAMES",
    "OptimalRun",
    "RateSensorModel",
    "RateSensorMonteCarlo",
    "RateSensorProcedure",
    "rate_sensor_model",
    "rate_sensor_monte_carlo",
    "turn_accuracy_limit",
]

#: States of the rate-sensor model, in order.
RS_STATE_NAMES: Final[tuple[str, ...]] = (
    "omega_gc", "earth", "turn", "delta", "gamma", "N1", "N2", "N3", "N4",
    "beta", "beta_rate", "beta_prev", "beta_rate_prev", "quant", "quant_prev",
)

#: How the turned sensors see the vibration ``N1`` in position 2: ``"carrier"`` (a
#: horizontal acceleration of the carrier, seen with the opposite sign by sensors turned by
#: 180°) or ``"sensor"`` (Eq. (8) read literally: the same ``+N1`` in both positions).
VIBRATION_FRAMES: Final[tuple[str, ...]] = ("carrier", "sensor")

_N: Final[int] = len(RS_STATE_NAMES)
(_OMEGA, _EARTH, _TURN, _DELTA, _GAMMA, _N1, _N2, _N3, _N4,
 _B, _BR, _BP, _BRP, _A, _AP) = range(_N)

_NONNEGATIVE = ("T_rot", "T_settle", "sigma_rot", "sigma_scale", "quantization",
                "angle_noise_scale")
_POSITIVE = ("rate_noise", "sample_dt", "sigma_c", "t_max", "loop_bandwidth")


@dataclass(frozen=True)
class RateSensorProcedure:
    """The rate-sensor method's procedure and sensor (ref. [3] as paper GC describes it, p. 52).

    Paper GC gives none of these numbers ("about 20 minutes, depending on the chosen
    measurement time"); the defaults are the book's, each stated and swept in the chapter
    "Racing the method it replaces".  SI units.

    Attributes
    ----------
    rate_noise : float, default 6.0e-16
        Intensity (rad²/s) of the white noise of the torque-sensor output (feedback amplifier,
        torque sensor), on top of the gyro's own random drift ``N3``.  Default: the
        low-frequency intensity of ``N3`` at the paper's values, ``4 ξ2 σ2² / α2`` =
        5.99·10⁻¹⁶ — electronics as quiet as the gyro.
    T_rot : float, default 10.0
        Time (s) to turn the base by 180°.
    T_settle : float, default 10.0
        Wait (s) after the turn for the rate sensor's transient.
    sigma_rot : float, default 1′
        Standard deviation (rad) of the turning error ε.
    sigma_scale : float, default 1e-3
        Standard deviation of the torque sensor's scale-factor error ``k`` (relative): the
        reason the Earth-rate reading is not known to σ_c and the base is turned.
    split : float or None, default None
        ``T1 / (T1 + T2)``, the share of the measurement time spent in position 1; ``None``:
        chosen optimally (the race picks the windows that reach σ_c soonest, for each
        estimator).
    vibration_frame : {"carrier", "sensor"}, default "carrier"
        How sensors turned by 180° see ``N1`` (:data:`VIBRATION_FRAMES`).
    sample_dt : float, default 0.1
        Sample interval (s) of the rate sensor and the inclinometers.
    sigma_c : float, default 2·10⁻³ ″/s
        The required accuracy σ_c (rad/s) of the north gyro's drift (paper GC, after ref. [2]).
    t_max : float, default 7200.0
        Longest procedure (s) searched for σ_c.
    loop_bandwidth : float, default 10.0
        Bandwidth ``ω_b`` (rad/s) of the rebalance loop that holds the float at null (its
        proportional gain ``k_b = f ω_b / H``); the book sweeps it from 1 to 100 rad/s.  The
        settling time should cover several ``1/ω_b`` (the model assumes the loop settled).
    quantization : float, default 0.01″
        Weight (rad) of one output pulse of the accumulated angle (0: no quantization).
    angle_noise_scale : float, default 1.0
        Factor on the angle sensor's intensity ``C_as`` (paper GC's) as it enters the rival's
        loop; 0 leaves the pickoff noise out (the old noiseless pickoff, kept for checks).

    Examples
    --------
    >>> from dataclasses import replace
    >>> from gyrolib import gc
    >>> proc = gc.RateSensorProcedure()
    >>> proc.overhead
    20.0
    >>> replace(proc, T_settle=-1.0)
    Traceback (most recent call last):
    ...
    ValueError: T_settle must be >= 0 (finite); got -1.0
    >>> replace(proc, rate_noise=float("nan"))
    Traceback (most recent call last):
    ...
    ValueError: rate_noise must be > 0 (a finite positive number); got nan
    """

    rate_noise: float = 6.0e-16
    T_rot: float = 10.0
    T_settle: float = 10.0
    sigma_rot: float = ARCMIN
    sigma_scale: float = 1.0e-3
    split: float | None = None
    vibration_frame: str = "carrier"
    sample_dt: float = 0.1
    sigma_c: float = levels.SIGMA_C
    t_max: float = 7200.0
    loop_bandwidth: float = 10.0
    quantization: float = 0.01 * ARCSEC_PAPER
    angle_noise_scale: float = 1.0

    def __post_init__(self) -> None:
        for f_ in fields(self):
            name = f_.name
            if name in _NONNEGATIVE:
                v.check_nonnegative(name, getattr(self, name))
            elif name in _POSITIVE:
                v.check_positive(name, getattr(self, name))
        if self.split is not None:
            v.check_in_range("split", self.split, 0.0, 1.0, low_open=True, high_open=True)
            object.__setattr__(self, "split", float(self.split))
        v.check_choice("vibration_frame", self.vibration_frame, VIBRATION_FRAMES)
        for name in (*_NONNEGATIVE, *_POSITIVE):
            object.__setattr__(self, name, float(getattr(self, name)))

    @property
    def overhead(self) -> float:
        """``T_rot + T_settle`` (s): the time between the two measurements."""
        return self.T_rot + self.T_settle

    def loop_gain(self, params: GyrocompassParams) -> float:
        """The rebalance loop's proportional gain ``k_b = f ω_b / H`` (1/s).

        Examples
        --------
        >>> from gyrolib import gc
        >>> gc.RateSensorProcedure().loop_gain(gc.GyrocompassParams())
        5.0
        """
        p = check_params(params)
        return p.f * self.loop_bandwidth / p.H


def check_procedure(procedure: object) -> RateSensorProcedure:
    return v.check_instance("procedure", procedure, RateSensorProcedure)


def _frozen(a: np.ndarray) -> np.ndarray:
    """``a`` made read-only (a cached result shared between calls)."""
    a.flags.writeable = False
    return a


class _PowerTable:
    """The doubling table of one step ``y ← M y + w``, ``Cov w = Q``: ``B_j = M^(2^j)`` and
    ``SB_j = Σ_{i<2^j} M^i Q M^iᵀ``, built once (extended on demand) and shared by every
    :meth:`power_sum` of the same step, so each costs only its combine steps."""

    def __init__(self, M: np.ndarray, Q: np.ndarray):
        self._B = [M.copy()]
        self._SB = [Q.copy()]
        self._sums: dict[int, tuple[np.ndarray, np.ndarray]] = {}

    @property
    def step(self) -> tuple[np.ndarray, np.ndarray]:
        """``(M, Q)`` (the table's own arrays: do not modify)."""
        return self._B[0], self._SB[0]

    def _level(self, j: int) -> tuple[np.ndarray, np.ndarray]:
        while len(self._B) <= j:
            B, SB = self._B[-1], self._SB[-1]
            self._SB.append(SB + B @ SB @ B.T)
            self._B.append(B @ B)
        return self._B[j], self._SB[j]

    def power_sum(self, k: int) -> tuple[np.ndarray, np.ndarray]:
        """``(M^k, Σ_{j<k} M^j Q M^jᵀ)``: the covariance of ``k`` steps, in O(log k)
        products (the same products, in the same order, as doubling from scratch); kept
        per ``k`` (read-only arrays)."""
        if k in self._sums:
            return self._sums[k]
        k0 = k
        Mk = np.eye(self._B[0].shape[0])
        Sk = np.zeros_like(self._SB[0])
        j = 0
        while k:
            if k & 1:
                B, SB = self._level(j)
                Sk = SB + B @ Sk @ B.T
                Mk = B @ Mk
            k >>= 1
            j += 1
        self._sums[k0] = (_frozen(Mk), _frozen(Sk))
        return Mk, Sk


def _late_and_above(t: np.ndarray, sigma: np.ndarray, after: float, level: float) -> bool:
    """Whether a sample later than ``after`` has σ above ``level`` (the comparison
    :meth:`OptimalRun.time_to` makes): the time to ``level`` is then later than ``after``."""
    return bool(np.any((t > after) & (sigma > level)))


@compact_repr
@dataclass(frozen=True)
class OptimalRun:
    """The optimal estimator's σ of ω_gc over a procedure (:meth:`RateSensorModel.optimal_run`):
    ``t`` (s, elapsed since the start of position 1) and ``sigma`` (rad/s) at every sample and
    phase boundary; ``phases`` the ``(name, start, end)`` of each phase (s)."""

    t: NDArray[np.float64]
    sigma: NDArray[np.float64]
    phases: tuple[tuple[str, float, float], ...]

    def __post_init__(self) -> None:
        n = v.check_ndarray("t", self.t, ndim=1).size
        v.check_ndarray("sigma", self.sigma, shape=(n,))
        if not isinstance(self.phases, tuple) or not all(
                isinstance(ph, tuple) and len(ph) == 3 for ph in self.phases):
            raise TypeError("phases must be a tuple of (name, start, end) tuples")

    def time_to(self, level: float) -> float:
        """First elapsed time (s) at which ``sigma`` falls to ``level`` (rad/s) and stays
        below it, linearly interpolated; ``nan`` if not reached.

        Examples
        --------
        >>> from gyrolib import gc
        >>> m = gc.rate_sensor_model(gc.GyrocompassParams(), gc.RateSensorProcedure())
        >>> run = m.optimal_run(20.0, 40.0)
        >>> f"{run.time_to(1e-8):.1f} s"
        '56.1 s'
        """
        level = v.check_positive("level", level)
        above = np.nonzero(self.sigma > level)[0]
        if above.size == 0:
            return float(self.t[0])
        last = above[-1]
        if last == self.sigma.size - 1:
            return float("nan")
        t0, t1, s0, s1 = self.t[last], self.t[last + 1], self.sigma[last], self.sigma[last + 1]
        return float(t0 + (s0 - level) / (s0 - s1) * (t1 - t0))


@compact_repr
@dataclass(frozen=True)
class RateSensorModel:
    """The rate-sensor method's discrete model (:func:`rate_sensor_model`).

    ``F``, ``G``, ``Q``: the continuous model of the nine states :data:`RS_STATE_NAMES` (the
    shaping filters (6), (7); the rest constant); ``Phi``, ``Qd``: its exact step over
    ``procedure.sample_dt``; ``P0`` the prior; ``H1``, ``H2`` (3×9): rate sensor, inclinometer y,
    inclinometer z in positions 1 and 2; ``r`` (3,) their noise variances per sample.

    The model keeps what its searches ask for repeatedly (the doubling tables of one
    sample, power sums, the covariance after window 1, the classical σ per pair of windows,
    the optimal filter's position 1): build a new model (:func:`rate_sensor_model`,
    ``dataclasses.replace``) rather than changing its arrays in place.
    """

    params: GyrocompassParams
    procedure: RateSensorProcedure
    F: np.ndarray
    G: np.ndarray
    Q: np.ndarray
    Phi: np.ndarray
    Qd: np.ndarray
    P0: np.ndarray
    H1: np.ndarray
    H2: np.ndarray
    r: np.ndarray

    def __post_init__(self) -> None:
        check_params(self.params)
        check_procedure(self.procedure)
        for name in ("F", "Phi", "Qd", "P0"):
            v.check_ndarray(name, getattr(self, name), shape=(_N, _N))
        v.check_ndarray("G", self.G, shape=(_N, 3))
        v.check_ndarray("Q", self.Q, shape=(3, 3))
        v.check_ndarray("H1", self.H1, shape=(3, _N))
        v.check_ndarray("H2", self.H2, shape=(3, _N))
        v.check_ndarray("r", self.r, shape=(3,))

    # -- helpers -------------------------------------------------------------------------------
    def window_samples(self, name: str, t: object) -> int:
        """The number of sample intervals ``sample_dt`` in a window of ``t`` seconds (at
        least one); ``name`` names the window in the error."""
        t = v.check_positive(name, t)
        n = round(t / self.procedure.sample_dt)
        if n < 1:
            raise ValueError(f"{name} must be at least one sample interval "
                             f"sample_dt={self.procedure.sample_dt}; got {t}")
        return n

    def _gap(self, length: float) -> tuple[np.ndarray, np.ndarray]:
        """``(Φ, Qd)`` over ``length`` (s): whole samples by doubling (a single matrix
        exponential over minutes would overflow in Van Loan's block), the rest exactly."""
        cache = self._cache("gap")
        if length not in cache:
            dt = self.procedure.sample_dt
            k = math.floor(length / dt + 1e-9)
            Phi, Qd = self._table("phi").power_sum(k)
            rest = length - k * dt
            if rest > 1e-12:
                Pr, Qr = _discretize(self.F, self.G, self.Q, rest)
                Phi, Qd = Pr @ Phi, Pr @ Qd @ Pr.T + Qr
            cache[length] = (_frozen(Phi), _frozen(Qd))
        return cache[length]

    # -- per-model caches (the dataclass is frozen; its __dict__ holds them) ------------------
    def _cache(self, name: str) -> dict:
        """A dict kept on this model (created on first use) for results that depend only on
        the model and the key."""
        key = "_cache_" + name
        d = self.__dict__.get(key)
        if d is None:
            d = {}
            object.__setattr__(self, key, d)
        return d

    def _table(self, which: str) -> _PowerTable:
        """The doubling table of one sample: ``"phi"`` (the state alone), ``"w1"``,
        ``"w2"`` (the augmented step of window 1 or 2, :meth:`_window_step`)."""
        cache = self._cache("tables")
        if which not in cache:
            if which == "phi":
                cache[which] = _PowerTable(self.Phi, self.Qd)
            elif which == "w1":
                cache[which] = _PowerTable(*self._window_step(self.H1, (_N, _N + 1), _N + 4))
            else:
                cache[which] = _PowerTable(*self._window_step(self.H2, (_N + 2, _N + 3),
                                                              _N + 4))
        return cache[which]

    def _window_step(self, H: np.ndarray, slots: tuple[int, int],
                     na: int) -> tuple[np.ndarray, np.ndarray]:
        """One sample of a window on the augmented state ``[x; sums]``: the state steps by
        ``Φ`` and the rate and inclinometer-z samples are added to their sums."""
        ir, iz = slots
        M = np.eye(na)
        M[:_N, :_N] = self.Phi
        M[ir, :_N] = H[0] @ self.Phi
        M[iz, :_N] = H[2] @ self.Phi
        S = np.zeros((na, _N))
        S[:_N] = np.eye(_N)
        S[ir] = H[0]
        S[iz] = H[2]
        Qa = S @ self.Qd @ S.T
        Qa[ir, ir] += self.r[0]
        Qa[iz, iz] += self.r[2]
        return M, Qa

    def _classical_weights(self, n1: int, n2: int) -> np.ndarray:
        """The classical estimate minus ω_gc as a functional of ``[x; Σr1, Σz1, Σr2, Σz2]``:
        ``½ (m1 + m2) − (Ω_v / 2g) (z̄1 + z̄2)``, each mean a sum over its samples."""
        p = self.params
        c = np.zeros(_N + 4)
        c[_OMEGA] = -1.0
        c[_N] = 0.5 / n1
        c[_N + 2] = 0.5 / n2
        c[_N + 1] = -p.Omega_v / (2.0 * p.g * n1)
        c[_N + 3] = -p.Omega_v / (2.0 * p.g * n2)
        return c

    @cached_property
    def _gap_overhead(self) -> tuple[np.ndarray, np.ndarray]:
        """``(Φ, Qd)`` over the turn and the settling (computed once per model)."""
        return self._gap(self.procedure.overhead)

    def _classical_after_w1(self, n1: int) -> np.ndarray:
        """The augmented covariance after window 1 of ``n1`` samples, the turn and the
        settling (computed once per ``n1``; read-only)."""
        cache = self._cache("after_w1")
        if n1 not in cache:
            na = _N + 4
            P = np.zeros((na, na))
            P[:_N, :_N] = self.P0
            Mk, Sk = self._table("w1").power_sum(n1)
            P = Mk @ P @ Mk.T + Sk
            Pg, Qg = self._gap_overhead
            A = np.eye(na)
            A[:_N, :_N] = Pg
            P = A @ P @ A.T
            P[:_N, :_N] += Qg
            cache[n1] = _frozen(P)
        return cache[n1]

    # -- the classical estimator ---------------------------------------------------------------
    def classical_sigma(self, t1: float, t2: float) -> float:
        """σ (rad/s) of the classical estimate of ω_gc: the half-sum of the two position
        means of the rate sensor, corrected by the means of inclinometer z,
        ``ω̂ = ½ (m1 + m2) − Ω_v (z̄1 + z̄2) / (2 g)`` (paper GC, p. 52, steps 1–5).

        Computed exactly on the discrete model: the sums of the samples are states of an
        augmented linear system whose covariance is propagated over each window by doubling.

        Parameters
        ----------
        t1, t2 : float
            Measurement times (s) in positions 1 and 2, rounded to whole samples.

        Returns
        -------
        float
            The σ of the estimation error (rad/s).

        Examples
        --------
        >>> from gyrolib import gc
        >>> from gyrolib.units import from_si
        >>> m = gc.rate_sensor_model(gc.GyrocompassParams(), gc.RateSensorProcedure())
        >>> f"{from_si(m.classical_sigma(10.0, 10.0), 'arcsec_paper/s'):.5f}"
        '0.01053'
        """
        n1, n2 = self.window_samples("t1", t1), self.window_samples("t2", t2)
        return self.classical_sigma_samples(n1, n2)

    def classical_sigma_samples(self, n1: int, n2: int) -> float:
        """:meth:`classical_sigma` with windows of ``n1`` and ``n2`` samples."""
        n1, n2 = v.check_int("n1", n1, 1), v.check_int("n2", n2, 1)
        cache = self._cache("classical")
        if (n1, n2) not in cache:
            P = self._classical_after_w1(n1)
            Mk, Sk = self._table("w2").power_sum(n2)
            P = Mk @ P @ Mk.T + Sk
            c = self._classical_weights(n1, n2)
            cache[n1, n2] = float(math.sqrt(max(c @ P @ c, 0.0)))
        return cache[n1, n2]

    def classical_curve(self, t1: float, t2: float) -> tuple[NDArray[np.float64],
                                                             NDArray[np.float64]]:
        """σ (rad/s) of the classical estimate after each sample of position 2, position 1
        lasting ``t1``: what the procedure would give if stopped then.

        Parameters
        ----------
        t1, t2 : float
            Measurement time in position 1 and the longest in position 2 (s).

        Returns
        -------
        t : ndarray
            Elapsed time (s) since the start of position 1.
        sigma : ndarray
            σ of the classical estimate (rad/s).

        Examples
        --------
        >>> from gyrolib import gc
        >>> m = gc.rate_sensor_model(gc.GyrocompassParams(), gc.RateSensorProcedure())
        >>> t, s = m.classical_curve(10.0, 10.0)
        >>> f"{t[-1]:.1f} s", bool(s[-1] == m.classical_sigma(10.0, 10.0))
        ('40.0 s', True)
        """
        n1, n2 = self.window_samples("t1", t1), self.window_samples("t2", t2)
        dt = self.procedure.sample_dt
        P = self._classical_after_w1(n1)
        M, Qa = self._table("w2").step
        sigma = np.empty(n2)
        for k in range(n2):
            P = M @ P @ M.T + Qa
            c = self._classical_weights(n1, k + 1)
            sigma[k] = math.sqrt(max(c @ P @ c, 0.0))
        if n2:
            # the last point exactly as classical_sigma computes it (doubling)
            sigma[-1] = self.classical_sigma_samples(n1, n2)
        t = n1 * dt + self.procedure.overhead + dt * np.arange(1, n2 + 1)
        return t, sigma

    # -- the optimal estimator -----------------------------------------------------------------
    def _kalman(self, H: np.ndarray, r: np.ndarray, P: np.ndarray, n: int, *,
                symmetrize: bool = True):
        """The filter's covariance run of ``n`` samples measuring ``H`` (noise variances
        ``r``) from ``P`` (symmetrized unless ``symmetrize=False``: a run resumed from the
        kernel's own, already symmetric, covariance); the discrete model of each
        ``(H, r, n)`` is built once per model."""
        cache = self._cache("kalman")
        key = (H.tobytes(), r.tobytes(), n)
        model = cache.get(key)
        if model is None:
            z = np.zeros((1, _N, _N))
            model = AffineDiscreteModel(
                seg=np.zeros(n, dtype=np.int64), a=np.zeros(n), b=np.zeros(n),
                Phi0=self.Phi[None], PhiA=z, PhiB=z, Qd0=self.Qd[None], QdA=z, QdB=z,
                H=np.ascontiguousarray(H), r=np.ascontiguousarray(r))
            cache[key] = model
        return covariance_fast(model, 0.5 * (P + P.T) if symmetrize else P, n)

    def _position1(self, n1: int) -> tuple[np.ndarray, np.ndarray]:
        """The optimal filter over position 1 of ``n1`` samples: the covariance at its end
        (read-only) and the variance of ω_gc at samples ``0 … n1``.

        Position 1 of any length is a prefix of the same filter run from ``P0``, so the run
        is kept per model: a longer ``n1`` resumes from the longest one computed, a shorter
        one from the nearest computed below it.  The kernel's state between steps is its
        covariance alone, so a resumed run repeats the floating-point operations of a
        single run from ``P0`` (the same numbers, to the bit)."""
        at = self._cache("pos1_P")
        var = self._cache("pos1_var")
        if not at:
            at[0] = _frozen(0.5 * (self.P0 + self.P0.T))
            var["omega"] = np.array([at[0][_OMEGA, _OMEGA]])
        if n1 not in at:
            start = max(k for k in at if k < n1)
            run = self._kalman(self.H1, self.r, at[start], n1 - start, symmetrize=False)
            at[n1] = _frozen(run.P_stored[-1].copy())
            known = var["omega"]
            if n1 + 1 > known.size:
                longer = np.concatenate((known, run.var[known.size - start:, _OMEGA]))
                if longer.size > var["omega"].size:   # (another thread may have gone further)
                    var["omega"] = longer
        return at[n1], var["omega"][:n1 + 1]

    def optimal_run(self, t1: float, t2: float) -> OptimalRun:
        """σ of ω_gc of the optimal (Kalman) estimator over the procedure.

        A covariance analysis of the discrete Kalman filter on the same measurement model,
        the turn a known time-varying input (it switches the signs of the Earth-rate reading
        and of the turned sensors' vibration, and brings in the turning error): position 1
        (rate sensor and both inclinometers every sample), the turn (no sample: the sensors
        are moving), the settling (inclinometers only: the rate sensor's transient is not
        modelled), position 2 (all three).  Built from :class:`gyrolib.filtering
        .AffineDiscreteModel`, :func:`gyrolib.filtering.covariance_fast` and
        :func:`gyrolib.filtering.van_loan`.

        Parameters
        ----------
        t1, t2 : float
            Measurement times (s) in positions 1 and 2.

        Returns
        -------
        OptimalRun

        Examples
        --------
        >>> from gyrolib import gc
        >>> from gyrolib.units import from_si
        >>> m = gc.rate_sensor_model(gc.GyrocompassParams(), gc.RateSensorProcedure())
        >>> run = m.optimal_run(10.0, 10.0)
        >>> f"{from_si(run.sigma[-1], 'arcsec_paper/s'):.5f}"   # classical: 0.01053
        '0.00401'
        """
        n1, n2 = self.window_samples("t1", t1), self.window_samples("t2", t2)
        return self.optimal_run_samples(n1, n2)

    def optimal_run_samples(self, n1: int, n2: int) -> OptimalRun:
        """:meth:`optimal_run` with windows of ``n1`` and ``n2`` samples."""
        n1, n2 = v.check_int("n1", n1, 1), v.check_int("n2", n2, 1)
        ts, ss, phases, P, t = self._optimal_to_position2(n1)
        run = self._kalman(self.H2, self.r, P, n2)
        dt = self.procedure.sample_dt
        ts.append(t + dt * np.arange(1, n2 + 1))
        ss.append(np.sqrt(np.clip(run.var[1:, _OMEGA], 0.0, None)))
        phases.append(("position 2", t, t + n2 * dt))
        return OptimalRun(t=np.concatenate(ts), sigma=np.concatenate(ss), phases=tuple(phases))

    def _optimal_to_position2(self, n1: int) -> tuple[list, list, list, np.ndarray, float]:
        """The optimal run up to the start of position 2 (position 1 of ``n1`` samples, the
        turn, the settling): the pieces of ``t`` and ``sigma``, the phases, the covariance
        and the elapsed time (s) at the start of position 2."""
        proc = self.procedure
        dt = proc.sample_dt
        P, var1 = self._position1(n1)
        ts = [dt * np.arange(n1 + 1)]
        ss = [np.sqrt(np.clip(var1, 0.0, None))]
        t = n1 * dt
        phases = [("position 1", 0.0, t)]
        # the turn: no sample (the sensors are moving); the state only propagates
        Pg, Qg = self._gap(proc.T_rot)
        P = Pg @ P @ Pg.T + Qg
        phases.append(("turn", t, t + proc.T_rot))
        t += proc.T_rot
        # the settling: the inclinometers (turned) only
        ns = math.floor(proc.T_settle / dt + 1e-9)
        if ns:
            run = self._kalman(self.H2[1:], self.r[1:], P, ns)
            P = run.P_stored[-1]
            ts.append(t + dt * np.arange(1, ns + 1))
            ss.append(np.sqrt(np.clip(run.var[1:, _OMEGA], 0.0, None)))
        Pg, Qg = self._gap(proc.T_settle - ns * dt)
        P = Pg @ P @ Pg.T + Qg
        phases.append(("settling", t, t + proc.T_settle))
        t += proc.T_settle
        ts.append(np.array([t]))
        ss.append(np.sqrt([max(P[_OMEGA, _OMEGA], 0.0)]))
        return ts, ss, phases, P, t

    @cached_property
    def _omega_constant(self) -> bool:
        """ω_gc is a constant of the discrete model to the bit (its row of ``Φ`` is the unit
        row, no process noise reaches it): the filter's variance of ω_gc then never grows
        while it measures (prediction leaves it, each update lowers it)."""
        unit = np.zeros(_N)
        unit[_OMEGA] = 1.0
        return bool(np.array_equal(self.Phi[_OMEGA], unit) and not self.Qd[_OMEGA].any()
                    and not self.Qd[:, _OMEGA].any())

    def optimal_time_to_samples(self, n1: int, n2_max: int, level: float, *,
                                give_up_after: float = math.inf) -> float:
        """The optimal estimator's first time (s) at which σ of ω_gc falls to ``level`` and
        stays below it, position 1 lasting ``n1`` samples and position 2 at most ``n2_max``:
        ``optimal_run_samples(n1, n2_max).time_to(level)``, with position 2 run only as far
        as that answer needs (``nan``: not reached).

        Position 2 is run in growing chunks, each resumed from the covariance at the end of
        the last (the same floating-point operations as one run); it stops after the chunk
        in which the variance of ω_gc falls below ``level² (1 − 10⁻⁶)``.  When ω_gc is a
        constant of the model (:attr:`_omega_constant`, checked; otherwise the whole window
        is run) that variance does not grow in position 2, so no later sample can be above
        ``level`` again (the margin covers rounding, whose relative size is 10⁻¹⁶ per step)
        and the last sample above ``level`` — all that :meth:`OptimalRun.time_to` reads —
        is among those computed: the same time as the full run.

        Parameters
        ----------
        n1, n2_max : int
            Samples in position 1, and at most in position 2 (>= 1).
        level : float
            The σ of ω_gc to reach (rad/s, > 0).
        give_up_after : float, default inf
            An elapsed time (s, > 0) beyond which the answer is not wanted: as soon as a
            sample later than ``give_up_after`` is computed with σ above ``level``,
            ``nan`` is returned without running further (a search over ``n1`` passes its
            best time so far: a window that cannot beat it is not finished).  This is
            exact: :meth:`OptimalRun.time_to` reads the *last* sample above ``level``, so
            the full run's time is then later than that sample, hence strictly later than
            ``give_up_after`` (or ``nan``).  Every sample counts, those of position 1 and
            of the settling too: the estimate can reach ``level`` before position 2
            starts (right after the turn), at a time earlier than ``give_up_after`` even
            when position 2 starts later.  A time at or before ``give_up_after`` is
            returned as without it.

        Returns
        -------
        float
            Elapsed time (s) since the start of position 1, or ``nan`` (not reached within
            ``n2_max`` samples, or later than ``give_up_after``).

        Examples
        --------
        >>> from gyrolib import gc
        >>> m = gc.rate_sensor_model(gc.GyrocompassParams(), gc.RateSensorProcedure())
        >>> n1, n2 = m.window_samples("t1", 20.0), m.window_samples("t2", 40.0)
        >>> t = m.optimal_time_to_samples(n1, n2, 1e-8)
        >>> f"{t:.1f} s", t == m.optimal_run_samples(n1, n2).time_to(1e-8)
        ('56.1 s', True)
        """
        n1, n2_max = v.check_int("n1", n1, 1), v.check_int("n2_max", n2_max, 1)
        level = v.check_positive("level", level)
        if not (isinstance(give_up_after, float | int) and give_up_after == math.inf):
            give_up_after = v.check_positive("give_up_after", give_up_after)  # or inf
        dt = self.procedure.sample_dt
        ts, ss, phases, P, t = self._optimal_to_position2(n1)
        if any(_late_and_above(tk, sk, give_up_after, level) for tk, sk in zip(ts, ss)):
            return math.nan   # a sample before position 2, later than give_up_after, above
        # position 2's sample j (1, 2, ...) is at t + j dt: the first one later than
        # give_up_after ends a chunk, so that a window that cannot win stops there
        j_late = (max(1, math.floor((give_up_after - t) / dt) + 1)
                  if math.isfinite(give_up_after) else n2_max)
        safe = level**2 * (1.0 - 1e-6)
        done, chunk, sym = 0, 64, True
        while done < n2_max:
            n = min(chunk, n2_max - done)
            if done < j_late:
                n = min(n, j_late - done)
            run = self._kalman(self.H2, self.r, P, n, symmetrize=sym)
            var = run.var[1:, _OMEGA]
            ts.append(t + dt * np.arange(done + 1, done + n + 1))
            ss.append(np.sqrt(np.clip(var, 0.0, None)))
            done += n
            if self._omega_constant and np.any(var <= safe):
                break
            if _late_and_above(ts[-1], ss[-1], give_up_after, level):
                return math.nan
            P, chunk, sym = run.P_stored[-1], 2 * chunk, False
        phases.append(("position 2", t, t + done * dt))
        run = OptimalRun(t=np.concatenate(ts), sigma=np.concatenate(ss), phases=tuple(phases))
        return run.time_to(level)

    @property
    def turn_floor(self) -> float:
        """σ (rad/s) that the turning error alone leaves in the classical estimate,
        ``sqrt(E[d²]) / 2`` (no measurement time removes it).

        Examples
        --------
        >>> from gyrolib import gc
        >>> m = gc.rate_sensor_model(gc.GyrocompassParams(), gc.RateSensorProcedure())
        >>> f"{m.turn_floor:.2e} rad/s"
        '5.68e-12 rad/s'
        """
        return 0.5 * math.sqrt(self.P0[_TURN, _TURN])


def rate_sensor_model(params: GyrocompassParams | None = None,
                      procedure: RateSensorProcedure | None = None) -> RateSensorModel:
    """The rate-sensor method's model under paper GC's disturbances and priors.

    Parameters
    ----------
    params : GyrocompassParams, optional
        Paper GC's parameters (default: the paper's): the shaping filters (6), (7), the
        unbalance, the inclinometer noises, the priors of ω_gc, ψ, δ, γ and ``shaping_p0``.
    procedure : RateSensorProcedure, optional
        The procedure and the rate sensor (default: the book's).

    Returns
    -------
    RateSensorModel

    Examples
    --------
    >>> from gyrolib import gc
    >>> m = gc.rate_sensor_model()
    >>> m.H1[0, :5].tolist(), m.H2[0, :5].tolist()   # ω_gc, e, d, δ, γ in the rate reading
    ([1.0, 1.0, 0.0, 0.0, 5.9e-05], [1.0, -1.0, 1.0, 0.0, 5.9e-05])
    """
    p = GyrocompassParams() if params is None else check_params(params)
    proc = RateSensorProcedure() if procedure is None else check_procedure(procedure)
    vib, drift = p.vibration_filter(), p.random_drift_filter()
    F = np.zeros((_N, _N))
    F[_N1:_N2 + 1, _N1:_N2 + 1] = vib.A
    F[_N3:_N4 + 1, _N3:_N4 + 1] = drift.A
    # the rebalance loop: I β'' + f β' = −f ω_b (β + n_as) (the input rate's share left out)
    wf, fi = proc.loop_bandwidth * p.f / p.I, p.f / p.I
    F[_B, _BR] = 1.0
    F[_BR, _B], F[_BR, _BR] = -wf, -fi
    G = np.zeros((_N, 3))
    G[_N1:_N2 + 1, 0] = vib.B[:, 0]
    G[_N3:_N4 + 1, 1] = drift.B[:, 0]
    G[_BR, 2] = -wf
    Q = np.diag([p.Q1, p.Q2, _angle_intensity(p, proc)])
    Phi, Qd = _discretize(F, G, Q, proc.sample_dt)
    # the delayed copies and the quantization residual, one sample at a time
    for cur, prev in ((_B, _BP), (_BR, _BRP), (_A, _AP)):
        Phi[prev, :] = 0.0
        Phi[prev, cur] = 1.0
    Phi[_A, :] = 0.0
    Qd[_A, _A] = proc.quantization**2 / 12.0
    # prior: paper GC's for ω_gc, δ, γ, N1…N4; e and d from k, ψ and ε (second moments)
    P0 = np.zeros((_N, _N))
    P0[_OMEGA, _OMEGA] = p.sigma_gc0**2
    sk, sp, se = proc.sigma_scale, p.sigma_psi0, proc.sigma_rot
    P0[_EARTH, _EARTH] = p.Omega_h**2 * (sk**2 + 0.75 * sp**4)
    P0[_TURN, _TURN] = p.Omega_h**2 * (sp**2 * se**2 + 0.75 * se**4)
    P0[_EARTH, _TURN] = P0[_TURN, _EARTH] = -0.25 * p.Omega_h**2 * sp**2 * se**2
    P0[_DELTA, _DELTA] = p.sigma_delta0**2
    P0[_GAMMA, _GAMMA] = p.sigma_gamma0**2
    if p.shaping_p0 == "stationary":
        k = p.shaping_p0_scale
        P0[_N1:_N2 + 1, _N1:_N2 + 1] = k * vib.stationary_covariance()
        P0[_N3:_N4 + 1, _N3:_N4 + 1] = k * drift.stationary_covariance()
    # the loop in its stationary state, and its value one sample earlier
    loop = slice(_B, _BR + 1)
    Ps = _loop_stationary(F, G, Q)
    lag = Phi[loop, loop] @ Ps
    P0[_B:_BR + 1, _B:_BR + 1] = Ps
    P0[_BP:_BRP + 1, _BP:_BRP + 1] = Ps
    P0[_B:_BR + 1, _BP:_BRP + 1] = lag
    P0[_BP:_BRP + 1, _B:_BR + 1] = lag.T
    P0[_A, _A] = P0[_AP, _AP] = proc.quantization**2 / 12.0
    # measurements: rate sensor, inclinometer y, inclinometer z
    s2 = -1.0 if proc.vibration_frame == "carrier" else 1.0
    ub = p.omega_ub / p.g
    dt = proc.sample_dt
    # the output's mean over a sample: ω_in − (f/H) Δβ/Δt − (I/H) Δβ'/Δt + Δa/Δt
    loop_cols = [_B, _BP, _BR, _BRP, _A, _AP]
    loop_coef = np.array([-p.f / p.H, p.f / p.H, -p.I / p.H, p.I / p.H, 1.0, -1.0]) / dt
    H1 = np.zeros((3, _N))
    H1[0, [_OMEGA, _EARTH, _GAMMA, _N1, _N3]] = (1.0, 1.0, p.Omega_v, ub, 1.0)
    H1[0, loop_cols] = loop_coef
    H1[1, [_DELTA, _N1]] = (p.g, 1.0)
    H1[2, [_GAMMA, _N1]] = (p.g, 1.0)
    H2 = np.zeros((3, _N))
    H2[0, [_OMEGA, _EARTH, _TURN, _GAMMA, _N1, _N3]] = (1.0, -1.0, 1.0, p.Omega_v, s2 * ub, 1.0)
    H2[0, loop_cols] = loop_coef
    H2[1, [_DELTA, _N1]] = (p.g, s2)
    H2[2, [_GAMMA, _N1]] = (p.g, s2)
    # the inclinometers' intensities as GC reads them; per sample of proc.sample_dt
    c_incl = np.array([p.C_incl_y, p.C_incl_z])
    if p.measurement_noise == "variance":   # printed numbers = variances per sample of p.dt
        c_incl = c_incl * p.dt
    r = np.concatenate(([proc.rate_noise], c_incl)) / proc.sample_dt
    return RateSensorModel(params=p, procedure=proc, F=F, G=G, Q=Q, Phi=Phi, Qd=Qd, P0=P0,
                           H1=H1, H2=H2, r=r)


_BASE = slice(0, _B)            # the states of paper GC's disturbances
_LOOP = slice(_B, _BR + 1)      # the float in its rebalance loop


def _loop_stationary(F: np.ndarray, G: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """Stationary covariance of the loop's ``(β, β')`` (continuous Lyapunov equation)."""
    Ps = scipy.linalg.solve_continuous_lyapunov(F[_LOOP, _LOOP],
                                                -(G[_LOOP] @ Q @ G[_LOOP].T))
    return 0.5 * (Ps + Ps.T)


def _discretize(F: np.ndarray, G: np.ndarray, Q: np.ndarray,
                h: float) -> tuple[np.ndarray, np.ndarray]:
    """``(Φ, Qd)`` of the continuous model over ``h``: paper GC's disturbances by Van Loan;
    the loop, whose poles (down to ``−f/I``) are too fast for Van Loan's block exponential,
    by ``Φ = e^{F h}`` and ``Qd = P_s − Φ P_s Φᵀ`` (exact for a stationary linear loop); the
    delayed copies and the quantization residual held."""
    Phi, Qd = np.eye(_N), np.zeros((_N, _N))
    Phi[_BASE, _BASE], Qd[_BASE, _BASE] = van_loan(F[_BASE, _BASE], G[_BASE, :2],
                                                   Q[:2, :2], h)
    Pl = scipy.linalg.expm(F[_LOOP, _LOOP] * h)
    Ps = _loop_stationary(F, G, Q)
    Phi[_LOOP, _LOOP] = Pl
    Ql = Ps - Pl @ Ps @ Pl.T
    Qd[_LOOP, _LOOP] = 0.5 * (Ql + Ql.T)
    return Phi, Qd


def _angle_intensity(p: GyrocompassParams, proc: RateSensorProcedure) -> float:
    """The angle sensor's white-noise intensity (rad²·s) in the rival's loop: paper GC's
    ``C_as`` as GC's filter reads it, times ``angle_noise_scale``."""
    c = p.C_as * (p.dt if p.measurement_noise == "variance" else 1.0)
    return c * proc.angle_noise_scale


def turn_accuracy_limit(params: GyrocompassParams | None = None,
                        level: float = levels.SIGMA_C) -> float:
    """The turning error σ_ε (rad) at which the turn alone leaves ``level`` (rad/s) in the
    classical estimate: ``Ω_h² (σ_ψ² σ_ε² + 3 σ_ε⁴/4) / 4 = level²`` solved for σ_ε — what
    "turn by 180° with the required accuracy" (paper GC, p. 52) has to mean.

    Parameters
    ----------
    params : GyrocompassParams, optional
        For ``Omega_h`` and ``sigma_psi0``.
    level : float
        The σ (rad/s), > 0; default σ_c.

    Returns
    -------
    float
        σ_ε (rad).

    Examples
    --------
    >>> from gyrolib import gc
    >>> from gyrolib.units import from_si
    >>> f"{from_si(gc.turn_accuracy_limit(), 'deg'):.2f} deg"
    '1.31 deg'
    """
    p = GyrocompassParams() if params is None else check_params(params)
    level = v.check_positive("level", level)
    a, b, c = 0.75, p.sigma_psi0**2, -4.0 * level**2 / p.Omega_h**2
    x = (-b + math.sqrt(b * b - 4.0 * a * c)) / (2.0 * a)
    return math.sqrt(x)


# Monte Carlo check of the classical estimator on an independent truth -----------------------
@compact_repr
@dataclass(frozen=True)
class RateSensorMonteCarlo:
    """Runs of the classical estimator on a simulated truth (:func:`rate_sensor_monte_carlo`):
    ``errors`` (rad/s) one per run, ``sigma`` (rad/s) the σ the model computes for it,
    ``band`` the two-sided 95 % χ² band of ``mean(errors²) / sigma²``."""

    errors: NDArray[np.float64]
    sigma: float
    band: tuple[float, float]
    t1: float
    t2: float
    seed: int
    truth_params: GyrocompassParams | None = None

    def __post_init__(self) -> None:
        if v.check_ndarray("errors", self.errors, ndim=1).size < 2:
            raise ValueError("errors must hold at least 2 runs")
        v.check_positive("sigma", self.sigma)
        lo, hi = (v.check_nonnegative("band", b) for b in self.band)
        if not lo <= hi:
            raise ValueError(f"band must be (low, high) with low <= high; got {self.band}")
        if self.truth_params is not None:
            v.check_instance("truth_params", self.truth_params, GyrocompassParams)

    @property
    def n_runs(self) -> int:
        """Number of runs."""
        return int(self.errors.size)

    @property
    def ratio(self) -> float:
        """``mean(errors²) / sigma²`` (1 for a σ that holds)."""
        return float(np.mean(self.errors**2) / self.sigma**2)

    @property
    def rms(self) -> float:
        """RMS of the errors (rad/s)."""
        return float(np.sqrt(np.mean(self.errors**2)))

    @property
    def inside(self) -> bool:
        """``ratio`` inside ``band``: the computed σ holds for this truth."""
        return bool(self.band[0] <= self.ratio <= self.band[1])


def rate_sensor_monte_carlo(params: GyrocompassParams | None = None,
                            procedure: RateSensorProcedure | None = None, *,
                            t1: float, t2: float, n_runs: int = 400, seed: int = 0,
                            truth_params: GyrocompassParams | None = None,
                            truth_procedure: RateSensorProcedure | None = None,
                            substeps: int = TRUTH_SUBSTEPS) -> RateSensorMonteCarlo:
    """The classical estimator of the rate-sensor method on a simulated truth.

    The truth shares no discretization with :func:`rate_sensor_model`: each run draws ψ,
    ω_gc, δ, γ, the scale-factor error ``k``, the turning error ε and the shaping-filter
    states from the truth's priors; integrates the shaping filters (6), (7) on its own grid of
    ``substeps`` steps per sample, white noise held over each fine step (the zero-order-hold
    steps of :mod:`gyrolib.gc.analysis.montecarlo`), and on the same grid the float in its
    closed rebalance loop, ``I β'' + f β' = H ω_in − H k_b (β + n_as)`` (the full second-order
    float, the pickoff noise ``n_as`` held over each fine step, the loop started settled
    at its steady offset in position 1 and left to settle through the turn and the
    settling); the input rate is Eq. (3)'s at the float's null in full,
    ``Ω_h cos(θ − ψ) + Ω_v γ + ω_gc + s ω_ub N1/g + N3`` with the base's azimuth ``θ = 0``
    in position 1 and ``π + ε`` after the turn, the turned sensors seeing the vibration with
    the sign ``s`` of ``vibration_frame``; the output, scaled by ``(1 + k)``, is the
    commanded rate's mean over each sample (from the float's equation integrated), plus the
    torquer's white noise, counted over each window in pulses of ``quantization`` from a
    random phase.  The estimator is the paper's half-sum corrected by the inclinometer
    means.

    Parameters
    ----------
    params : GyrocompassParams, optional
        The model the computed σ uses.
    procedure : RateSensorProcedure, optional
        The procedure (the model's, and the truth's unless ``truth_procedure``).
    t1, t2 : float
        Measurement times (s) in positions 1 and 2.
    n_runs : int
        Number of runs (>= 2).
    seed : int
        Seed (>= 0); run ``i`` is the same whatever ``n_runs``.
    truth_params : GyrocompassParams, optional
        The truth's parameters (default: ``params``), e.g. a larger vibration.
    truth_procedure : RateSensorProcedure, optional
        The truth's procedure and sensor (default: ``procedure``), e.g. the pickoff noise
        present while the model leaves it out (``angle_noise_scale=0``).
    substeps : int
        Fine steps of the truth per sample (>= 1).

    Returns
    -------
    RateSensorMonteCarlo

    Examples
    --------
    >>> from gyrolib import gc
    >>> mc = gc.rate_sensor_monte_carlo(t1=10.0, t2=10.0, n_runs=200, seed=3)
    >>> mc.inside, f"{mc.ratio:.2f}"
    (True, '1.05')
    """
    p = GyrocompassParams() if params is None else check_params(params)
    proc = RateSensorProcedure() if procedure is None else check_procedure(procedure)
    tp = p if truth_params is None else v.check_instance("truth_params", truth_params,
                                                         GyrocompassParams)
    n_runs = v.check_int("n_runs", n_runs, 2)
    seed = v.check_int("seed", seed, 0)
    substeps = v.check_int("substeps", substeps, 1)
    model = rate_sensor_model(p, proc)
    n1, n2 = model.window_samples("t1", t1), model.window_samples("t2", t2)
    sigma = model.classical_sigma_samples(n1, n2)
    tproc = proc if truth_procedure is None else check_procedure(truth_procedure)
    errors = _truth_classical_errors(tp, tproc, n1, n2, n_runs, seed, substeps)
    return RateSensorMonteCarlo(errors=errors, sigma=sigma, band=nees_bounds(1, n_runs),
                                t1=n1 * proc.sample_dt, t2=n2 * proc.sample_dt, seed=seed,
                                truth_params=truth_params)


_BLOCK: Final[int] = 64      # runs per random stream (run i is the same whatever n_runs)


class _Truth:
    """The truth's fixed arrays: zero-order-hold steps of the shaping filters and of the float
    in its rebalance loop on the fine grid ``h`` (and over the part of the gap shorter than
    ``h``), noise levels, signs."""

    def __init__(self, tp: GyrocompassParams, proc: RateSensorProcedure, substeps: int):
        self.tp, self.proc, self.substeps = tp, proc, substeps
        dt = proc.sample_dt
        h = dt / substeps
        self.h = h
        self.vib, self.drift = tp.vibration_filter(), tp.random_drift_filter()
        # the float: I β'' + f β' = H ω_in − H k_b (β + n_as), inputs held over a fine step
        self.k_b = proc.loop_gain(tp)
        self.A_loop = np.array([[0.0, 1.0], [-tp.H * self.k_b / tp.I, -tp.f / tp.I]])
        self.fine = self._steps(h)
        self.n_gap = math.floor(proc.overhead / h + 1e-9)
        rest = proc.overhead - self.n_gap * h
        self.rest = self._steps(rest) if rest > 1e-12 else None
        self.rest_h = rest
        c_z = tp.C_incl_z * (tp.dt if tp.measurement_noise == "variance" else 1.0)
        self.sd_rate = math.sqrt(proc.rate_noise / dt)
        self.sd_z = math.sqrt(c_z / dt)
        self.c_as = _angle_intensity(tp, proc)
        self.s2 = -1.0 if proc.vibration_frame == "carrier" else 1.0
        self.ub = tp.omega_ub / tp.g
        P = np.zeros((4, 4))
        if tp.shaping_p0 == "stationary":
            P[:2, :2] = tp.shaping_p0_scale * self.vib.stationary_covariance()
            P[2:, 2:] = tp.shaping_p0_scale * self.drift.stationary_covariance()
        self.L = covariance_factor(P) if np.any(P) else np.zeros((4, 1))

    def _steps(self, h: float) -> tuple[np.ndarray, ...]:
        phi1, gam1 = zoh_discretize(self.vib.A, self.vib.B[:, 0], h)
        phi2, gam2 = zoh_discretize(self.drift.A, self.drift.B[:, 0], h)
        phil, gaml = zoh_discretize(self.A_loop, np.array([0.0, 1.0 / self.tp.I]), h)
        return (phi1, gam1 * math.sqrt(self.tp.Q1 / h), phi2,
                gam2 * math.sqrt(self.tp.Q2 / h), phil, gaml, h)

    def advance(self, x: np.ndarray, loop: np.ndarray, n_fine: int,
                steps: tuple[np.ndarray, ...], rng: np.random.Generator,
                base: np.ndarray, s: float) -> None:
        """``n_fine`` fine steps of N1…N4 (rows of ``x``) and of the float ``(β, β')``
        (rows of ``loop``), white noise held over each (:func:`_advance_lanes`); the input
        rate ``base + s ω_ub N1/g + N3`` with the shaping states at each step's start."""
        phi1, gam1, phi2, gam2, phil, gaml, h = steps
        # the fine steps' noises in the order drawn: step i's three in row 3 i … 3 i + 2
        w = rng.standard_normal((n_fine, 3, x.shape[1])).reshape(1, 3 * n_fine, x.shape[1])
        hks = self.tp.H * self.k_b * math.sqrt(self.c_as / h)
        _advance_lanes(x, loop, w, 0, n_fine, phi1, gam1, phi2, gam2, phil, gaml, h, hks,
                       self.tp.H, base, s * self.ub, np.zeros(x.shape[1]))

    def errors(self, rng: np.random.Generator, n1: int, n2: int, B: int) -> np.ndarray:
        """Classical-estimate errors of ``B`` runs drawn from ``rng``."""
        tp, proc = self.tp, self.proc
        dt, q = proc.sample_dt, proc.quantization
        # each run's constants and initial shaping-filter states, from the truth's priors
        psi = tp.sigma_psi0 * rng.standard_normal(B)
        omega = tp.sigma_gc0 * rng.standard_normal(B)
        gamma = tp.sigma_gamma0 * rng.standard_normal(B)
        k = proc.sigma_scale * rng.standard_normal(B)
        eps = proc.sigma_rot * rng.standard_normal(B)
        x = self.L @ rng.standard_normal((self.L.shape[1], B))      # N1, N2, N3, N4

        def base_at(theta: np.ndarray) -> np.ndarray:
            # the input rate of Eq. (3) at the float's null, the base at azimuth θ, in full,
            # but the shaping states' part (s ω_ub N1/g + N3, added step by step)
            return tp.Omega_h * np.cos(theta - psi) + tp.Omega_v * gamma + omega

        # the float in its loop: at rest at its steady offset ω_in/k_b, then settled a while
        base1 = base_at(np.zeros(B))
        loop = np.vstack([(base1 + self.ub * x[0] + x[2]) / self.k_b, np.zeros(B)])
        self.advance(x, loop, math.ceil(10.0 / (proc.loop_bandwidth * self.h)), self.fine,
                     rng, base1, 1.0)
        phi1, gam1, phi2, gam2, phil, gaml, h = self.fine
        hks = tp.H * self.k_b * math.sqrt(self.c_as / h)
        M = self.substeps

        def window(n: int, base: np.ndarray, s: float) -> tuple[np.ndarray, np.ndarray]:
            # per sample, the fine steps' noises (M × 3) then the rate sensor's and the
            # inclinometer's (2): one draw for the window, in the order of the samples
            w = rng.standard_normal((n, 3 * M + 2, B))
            sum_r = np.zeros(B)
            sum_z = np.zeros(B)
            _window_lanes(x, loop, w, M, phi1, gam1, phi2, gam2, phil, gaml, h, hks, tp.H,
                          base, s * self.ub, s, tp.f, tp.I, dt, k, self.sd_rate, self.sd_z,
                          tp.g, gamma, sum_r, sum_z)
            if q > 0.0:   # pulses of q counted over the window, from a random phase
                a0 = q * rng.random(B)
                sum_r = q * (np.floor((a0 + dt * sum_r) / q) - np.floor(a0 / q)) / dt
            return sum_r / n, sum_z / n

        m1, z1 = window(n1, base1, 1.0)
        base2 = base_at(np.pi + eps)
        self.advance(x, loop, self.n_gap, self.fine, rng, base2, self.s2)  # turn, settling
        if self.rest is not None:
            self.advance(x, loop, 1, self.rest, rng, base2, self.s2)
        m2, z2 = window(n2, base2, self.s2)
        est = 0.5 * (m1 + m2) - tp.Omega_v * (z1 + z2) / (2.0 * tp.g)
        return est - omega


@njit(cache=True, nogil=True)
def _advance_lanes(x, loop, w, j, n_fine, phi1, gam1, phi2, gam2, phil, gaml, h, hks, H, base,
                   s_ub, integral):
    """``n_fine`` fine steps of every lane (column) of the rival's truth, the noises of fine
    step ``i`` in ``w[j, 3 i:3 i + 3]`` (``w`` a window's (samples, 3 M + 2, lanes) array,
    :func:`_window_lanes`, or one row of 3 ``n_fine``): the shaping
    filters N1, N2 (rows 0, 1 of ``x``) and N3, N4 (rows 2, 3), the float ``(β, β')`` in its
    loop (``loop``), the input rate ``base + s_ub N1 + N3`` at each step's start, its
    integral added to ``integral``.  Each lane runs the steps of the numpy loop it replaces
    (that loop's small array operations were the rival's Monte Carlo's time)."""
    B = x.shape[1]
    for r in range(B):
        n1, n2, n3, n4 = x[0, r], x[1, r], x[2, r], x[3, r]
        l0, l1 = loop[0, r], loop[1, r]
        acc = integral[r]
        for i in range(n_fine):
            wa, wb, wc = w[j, 3 * i, r], w[j, 3 * i + 1, r], w[j, 3 * i + 2, r]
            w_in = base[r] + s_ub * n1 + n3
            # the feedback on β is in the loop's own step; the inputs: rate and pickoff noise
            torque = H * w_in - hks * wc
            l0, l1 = (phil[0, 0] * l0 + phil[0, 1] * l1 + gaml[0] * torque,
                      phil[1, 0] * l0 + phil[1, 1] * l1 + gaml[1] * torque)
            acc += h * w_in
            n1, n2 = (phi1[0, 0] * n1 + phi1[0, 1] * n2 + gam1[0] * wa,
                      phi1[1, 0] * n1 + phi1[1, 1] * n2 + gam1[1] * wa)
            n3, n4 = (phi2[0, 0] * n3 + phi2[0, 1] * n4 + gam2[0] * wb,
                      phi2[1, 0] * n3 + phi2[1, 1] * n4 + gam2[1] * wb)
        x[0, r], x[1, r], x[2, r], x[3, r] = n1, n2, n3, n4
        loop[0, r], loop[1, r] = l0, l1
        integral[r] = acc


@njit(cache=True, nogil=True)
def _window_lanes(x, loop, w, M, phi1, gam1, phi2, gam2, phil, gaml, h, hks, H, base, s_ub,
                  s, f, inertia, dt, k, sd_rate, sd_z, g, gamma, sum_r, sum_z):
    """The samples of one measurement window (``w``: per sample the ``M`` fine steps' noises,
    then the rate sensor's and the inclinometer's): each sample's output, the commanded
    rate's mean from the float's equation integrated, ``∫ u = ∫ ω_in − (f Δβ + I Δβ') / H``,
    scaled by ``1 + k``, plus the torquer's noise, summed into ``sum_r``; the inclinometer z
    into ``sum_z``."""
    B = x.shape[1]
    integral = np.zeros(B)
    for j in range(w.shape[0]):
        b0 = loop.copy()
        integral[:] = 0.0
        _advance_lanes(x, loop, w, j, M, phi1, gam1, phi2, gam2, phil, gaml, h, hks, H, base,
                       s_ub, integral)
        for r in range(B):
            u = (integral[r] - (f * (loop[0, r] - b0[0, r])
                                + inertia * (loop[1, r] - b0[1, r])) / H) / dt
            sum_r[r] += (1.0 + k[r]) * u + sd_rate * w[j, 3 * M, r]
            sum_z[r] += g * gamma[r] + s * x[0, r] + sd_z * w[j, 3 * M + 1, r]


def _truth_classical_errors(tp: GyrocompassParams, proc: RateSensorProcedure, n1: int,
                            n2: int, n_runs: int, seed: int, substeps: int) -> np.ndarray:
    """Classical-estimate errors of ``n_runs`` truth runs (see
    :func:`rate_sensor_monte_carlo`): one random stream per block of :data:`_BLOCK` runs."""
    truth = _Truth(tp, proc, substeps)
    n_blocks = -(-n_runs // _BLOCK)
    streams = np.random.default_rng(seed).bit_generator.seed_seq.spawn(n_blocks)
    out = np.concatenate([truth.errors(np.random.Generator(np.random.PCG64(ss)), n1, n2,
                                       _BLOCK) for ss in streams])
    return out[:n_runs]
