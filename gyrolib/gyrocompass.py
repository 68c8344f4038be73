"""The gyrocompass model of paper GC: parameters, nominal float motion (Eq. 4) and the
linearized state-space model (Eqs. 5–8).

State vector (1-D, SI units), in this order (:data:`STATE_NAMES`)::

    dbeta      Δβ = β − β_n, float angle increment             rad
    dbeta_dot  Δβ'                                             rad/s
    psi        ψ, azimuth misalignment of the input axis       rad
    omega_gc   ω_gc, systematic drift (constant in a run)      rad/s
    delta      δ, platform tilt (about the input axis y)       rad
    gamma      γ, platform tilt (about the output axis z)      rad
    N1, N2     vibration shaping filter, Eq. (6)               m/s², m/s³
    N3, N4     random-drift shaping filter, Eq. (7)            rad/s, rad/s²

The paper prints ``X1 = Δβ'`` and ``X2 = Δβ``, but its F and D (``F(1,2) = 1``,
``F(2,2) = −f/I``, ``D(1,1) = 1``) only make sense with ``X1 = Δβ``, ``X2 = Δβ'``: this module
uses the latter.  ``F(8,7)`` is ``−α1²`` as Eq. (6) requires (printed without the minus).
The vertical-rate coupling follows Eq. (5) (γ carries cos β_n, δ carries −sin β_n) by
default; ``vertical_coupling="printed_F"`` gives the paper's F listing instead.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from typing import Final

import numpy as np
from scipy.integrate import solve_ivp

from gyrolib import _validation as v
from gyrolib.shaping_filters import ShapingFilter, random_drift_filter, vibration_filter
from gyrolib.units import ARCSEC_PAPER, G0

__all__ = [
    "MEASUREMENT_NAMES",
    "NOISE_NAMES",
    "STATE_NAMES",
    "GyrocompassParams",
    "NominalMotion",
    "initial_covariance",
    "measurement_matrix",
    "measurement_noise_covariance",
    "measurement_noise_intensity",
    "noise_input_matrix",
    "nominal_motion",
    "nominal_motion_aperiodic",
    "nominal_motion_reference",
    "process_noise_intensity",
    "state_index",
    "system_matrix",
]

STATE_NAMES: Final[tuple[str, ...]] = (
    "dbeta", "dbeta_dot", "psi", "omega_gc", "delta", "gamma", "N1", "N2", "N3", "N4",
)
MEASUREMENT_NAMES: Final[tuple[str, ...]] = ("angle_sensor", "inclinometer_y", "inclinometer_z")
NOISE_NAMES: Final[tuple[str, ...]] = ("w1", "w2")
N_STATES: Final[int] = len(STATE_NAMES)


def state_index(name: str) -> int:
    """Index of a state by its name (see :data:`STATE_NAMES`)."""
    if name not in STATE_NAMES:
        raise ValueError(f"name must be one of {STATE_NAMES}; got {name!r}")
    return STATE_NAMES.index(name)


_POSITIVE = ("I", "H", "f", "Omega_v", "Omega_h", "g", "alpha1", "sigma1_sq", "alpha2",
             "sigma2_sq", "C_as", "C_incl_y", "C_incl_z", "dt")
_NONNEGATIVE = ("omega_ub", "sigma_dbeta0", "sigma_dbeta_dot0", "sigma_psi0", "sigma_gc0",
                "sigma_delta0", "sigma_gamma0")
_DAMPING = ("xi1", "xi2")
_CHOICES = {
    "shaping_p0": ("stationary", "zero"),
    "measurement_noise": ("intensity_over_dt", "variance"),
    "vertical_coupling": ("eq5", "printed_F"),
}


@dataclass(frozen=True)
class GyrocompassParams:
    """Parameters of paper GC's simulation, SI units, the paper's values as defaults.

    Paper values (its parameter list after Eq. (8), and the text around Eqs. (6), (7)):
    ``I``, ``H``, ``f``, ``Omega_v``, ``Omega_h``, ``omega_ub``, the shaping-filter
    parameters, the sensor noise intensities ``C_as`` (angle sensor, rad²·s) and
    ``C_incl_y``, ``C_incl_z`` (inclinometers, m²/s³), ``dt`` and the initial standard
    deviations of ψ, ω_gc, δ and γ (in the paper's arcsecond, 1″ = 0.485·10⁻⁵ rad).

    Not given by the paper (assumptions, studied in the book):

    * ``g``: standard gravity;
    * ``sigma_dbeta0``, ``sigma_dbeta_dot0``: the float starts at the angle sensor's null,
      held there by the feedback loop until it is switched off;
    * ``shaping_p0``: initial covariance of N1…N4, ``"stationary"`` (the processes are already
      running when the calibration starts) or ``"zero"`` (the literal reading);
    * ``measurement_noise``: how the continuous intensities become discrete variances,
      ``"intensity_over_dt"`` (``R = C/Δt``, sampling of continuous white noise) or
      ``"variance"`` (``R = C``, the printed numbers read as variances);
    * ``vertical_coupling``: ``"eq5"`` (Eq. (5)) or ``"printed_F"`` (the F listing).
    """

    I: float = 4.0e-5
    H: float = 0.05
    f: float = 0.025
    Omega_v: float = 5.9e-5
    Omega_h: float = 4.3e-5
    g: float = G0
    omega_ub: float = 4.84e-8
    alpha1: float = 1.33e-2
    xi1: float = 0.7
    sigma1_sq: float = 1.86e-6
    alpha2: float = 6.28
    xi2: float = 0.4
    sigma2_sq: float = 2.35e-15
    C_as: float = 2.0e-13
    C_incl_y: float = 5.0e-15
    C_incl_z: float = 5.0e-15
    dt: float = 1.0e-3
    sigma_dbeta0: float = 0.0
    sigma_dbeta_dot0: float = 0.0
    sigma_psi0: float = 180.0 * ARCSEC_PAPER
    sigma_gc0: float = 0.15 * ARCSEC_PAPER
    sigma_delta0: float = 120.0 * ARCSEC_PAPER
    sigma_gamma0: float = 120.0 * ARCSEC_PAPER
    shaping_p0: str = "stationary"
    measurement_noise: str = "intensity_over_dt"
    vertical_coupling: str = "eq5"

    def __post_init__(self) -> None:
        for f_ in fields(self):
            name = f_.name
            if name in _POSITIVE:
                v.check_positive(name, getattr(self, name))
            elif name in _NONNEGATIVE:
                v.check_nonnegative(name, getattr(self, name))
            elif name in _DAMPING:
                v.check_in_range(name, getattr(self, name), 0.0, 1.0, low_open=True)
            elif name in _CHOICES:
                v.check_choice(name, getattr(self, name), _CHOICES[name])
        # Store plain floats so that numpy scalars and ints behave identically.
        for name in (*_POSITIVE, *_NONNEGATIVE, *_DAMPING):
            object.__setattr__(self, name, float(getattr(self, name)))

    # Derived quantities -------------------------------------------------------------------
    @property
    def time_constant(self) -> float:
        """Float time constant ``I/f`` (s)."""
        return self.I / self.f

    @property
    def Q1(self) -> float:
        """Vibration white-noise intensity ``Q1 = 2 ξ1 α1 σ1²`` (paper GC, after Eq. (6))."""
        return 2.0 * self.xi1 * self.alpha1 * self.sigma1_sq

    @property
    def Q2(self) -> float:
        """Random-drift white-noise intensity ``Q2 = 4 ξ2 α2³ σ2²`` (after Eq. (7))."""
        return 4.0 * self.xi2 * self.alpha2**3 * self.sigma2_sq

    def vibration_filter(self) -> ShapingFilter:
        """The vibration shaping filter, Eq. (6)."""
        return vibration_filter(self.alpha1, self.xi1, self.sigma1_sq)

    def random_drift_filter(self) -> ShapingFilter:
        """The random-drift shaping filter, Eq. (7)."""
        return random_drift_filter(self.alpha2, self.xi2, self.sigma2_sq)


def _check_params(params: object) -> GyrocompassParams:
    return v.check_instance("params", params, GyrocompassParams)


# Nominal motion, Eq. (4) ----------------------------------------------------------------------
@dataclass(frozen=True)
class NominalMotion:
    """Nominal float angle ``beta`` (rad) and rate ``beta_dot`` (rad/s) at times ``t`` (s)."""

    t: np.ndarray
    beta: np.ndarray
    beta_dot: np.ndarray

    def __post_init__(self) -> None:
        t = v.check_array("t", self.t, ndim=1)
        for name in ("beta", "beta_dot"):
            v.check_array(name, getattr(self, name), shape=t.shape)


def _check_times(t: object) -> np.ndarray:
    t = v.check_array("t", t, ndim=1)
    if t.size == 0:
        raise ValueError("t must hold at least one time")
    if t[0] < 0.0 or np.any(np.diff(t) < 0.0):
        raise ValueError("t must be non-negative and non-decreasing")
    return t


def nominal_motion(params: GyrocompassParams, t: object, *, rtol: float = 1e-11) -> NominalMotion:
    """Solve paper GC's nominal equation (4), ``I β'' + f β' = H Ω_h cos β``, from rest.

    The initial state is ``β(0) = 0``, ``β'(0) = 0`` (the float at the angle sensor's null when
    the feedback is switched off).  The equation is stiff (time constant ``I/f`` = 1.6 ms over
    100 s), so an implicit Radau method with tight tolerances is used; its error against an
    independent solution is shown in the model chapter.
    """
    _check_params(params)
    t = _check_times(t)
    v.check_in_range("rtol", rtol, 1e-14, 1e-3)
    k_dd = params.H * params.Omega_h / params.I
    c = params.f / params.I

    def rhs(_t: float, y: np.ndarray) -> np.ndarray:
        return np.array([y[1], k_dd * np.cos(y[0]) - c * y[1]])

    def jac(_t: float, y: np.ndarray) -> np.ndarray:
        return np.array([[0.0, 1.0], [-k_dd * np.sin(y[0]), -c]])

    if t[-1] == 0.0:
        zeros = np.zeros_like(t)
        return NominalMotion(t=t, beta=zeros, beta_dot=zeros.copy())
    sol = solve_ivp(rhs, (0.0, float(t[-1])), [0.0, 0.0], method="Radau", t_eval=t,
                    rtol=rtol, atol=1e-16, jac=jac)
    if not sol.success:  # pragma: no cover - Radau does not fail on this smooth problem
        raise RuntimeError(f"nominal motion integration failed: {sol.message}")
    return NominalMotion(t=t, beta=sol.y[0].copy(), beta_dot=sol.y[1].copy())


def nominal_motion_reference(params: GyrocompassParams, t: object, *,
                             rtol: float = 1e-13) -> NominalMotion:
    """An independent solution of Eq. (4) to check :func:`nominal_motion` against.

    A different method family (explicit Runge–Kutta DOP853 of order 8 instead of the implicit
    Radau IIA collocation), at a tighter tolerance and with the inertia-free solution
    subtracted: the integrated unknown is ``e = β − β_ap``, with ``β_ap`` the Gudermannian of
    :func:`nominal_motion_aperiodic`, so that the step-size control acts on the small
    correction rather than on β itself.  From ``I β'' + f β' = H Ω_h cos β`` and
    ``f β_ap' = H Ω_h cos β_ap``:
    ``I e'' + f e' = H Ω_h (cos(β_ap + e) − cos β_ap) − I β_ap''``, ``e(0) = 0``,
    ``e'(0) = −k``.
    """
    _check_params(params)
    t = _check_times(t)
    v.check_in_range("rtol", rtol, 2.3e-14, 1e-3)
    k = params.H * params.Omega_h / params.f
    kdd = params.H * params.Omega_h / params.I
    c = params.f / params.I

    def rhs(tt: float, y: np.ndarray) -> list[float]:
        # Scalar math: this explicit method takes many small (stability-limited) steps.
        b = 2.0 * math.atan(math.tanh(0.5 * k * tt))
        # β_ap' = k cos β_ap, so β_ap'' = −k sin β_ap · β_ap' = −k² sin β_ap cos β_ap.
        bdd = -(k**2) * math.sin(b) * math.cos(b)
        e, e_dot = float(y[0]), float(y[1])
        # cos(b + e) − cos b without cancellation.
        dcos = -2.0 * math.sin(b + 0.5 * e) * math.sin(0.5 * e)
        return [e_dot, kdd * dcos - c * e_dot - bdd]

    ap = nominal_motion_aperiodic(params, t)
    if t[-1] == 0.0:
        zeros = np.zeros_like(t)
        return NominalMotion(t=t, beta=zeros, beta_dot=zeros.copy())
    sol = solve_ivp(rhs, (0.0, float(t[-1])), [0.0, -k], method="DOP853", t_eval=t,
                    rtol=rtol, atol=1e-22, first_step=1e-7)
    if not sol.success:  # pragma: no cover
        raise RuntimeError(f"reference integration failed: {sol.message}")
    return NominalMotion(t=t, beta=ap.beta + sol.y[0], beta_dot=ap.beta_dot + sol.y[1])


def nominal_motion_aperiodic(params: GyrocompassParams, t: object) -> NominalMotion:
    """Aperiodic (inertia-free) approximation of Eq. (4): ``f β' = H Ω_h cos β``.

    Separating variables gives the Gudermannian ``β = 2 arctan(tanh(k t / 2))`` with
    ``k = H Ω_h / f``; it holds once ``t ≫ I/f``.
    """
    _check_params(params)
    t = _check_times(t)
    k = params.H * params.Omega_h / params.f
    beta = 2.0 * np.arctan(np.tanh(0.5 * k * t))
    return NominalMotion(t=t, beta=beta, beta_dot=k * np.cos(beta))


# State-space model, Eq. (8) -------------------------------------------------------------------
def system_matrix(params: GyrocompassParams, beta_n: float) -> np.ndarray:
    """State matrix ``F(t)`` of paper GC, Eq. (8), at nominal float angle ``beta_n`` (rad).

    Row 2 is the linearized gyrocompass equation (5) divided by ``I``; rows 7–10 are the
    shaping filters (6), (7).  See the module docstring for the state order.
    """
    p = _check_params(params)
    b = v.check_real("beta_n", beta_n)
    s, c = np.sin(b), np.cos(b)
    F = np.zeros((N_STATES, N_STATES))
    F[0, 1] = 1.0
    F[1, 0] = -(p.H * p.Omega_h / p.I) * s
    F[1, 1] = -p.f / p.I
    F[1, 2] = (p.H * p.Omega_h / p.I) * s
    F[1, 3] = p.H / p.I
    if p.vertical_coupling == "eq5":
        F[1, 4] = -(p.H * p.Omega_v / p.I) * s  # δ carries −sin β_n
        F[1, 5] = (p.H * p.Omega_v / p.I) * c  # γ carries cos β_n
    else:  # the paper's F listing as printed
        F[1, 4] = -(p.H * p.Omega_v / p.I) * c
        F[1, 5] = (p.H * p.Omega_v / p.I) * s
    F[1, 6] = p.H * p.omega_ub / (p.I * p.g)
    F[1, 8] = p.H / p.I
    F[6:8, 6:8] = p.vibration_filter().A
    F[8:10, 8:10] = p.random_drift_filter().A
    return F


def noise_input_matrix(params: GyrocompassParams) -> np.ndarray:
    """Disturbance matrix ``G`` (10×2) of Eq. (8): ``G(7,1) = 1``, ``G(8,1) = α1 − 2ξ1α1``,
    ``G(10,2) = 1``."""
    params = _check_params(params)
    G = np.zeros((N_STATES, 2))
    G[6:8, 0] = params.vibration_filter().B[:, 0]
    G[8:10, 1] = params.random_drift_filter().B[:, 0]
    return G


def measurement_matrix(params: GyrocompassParams) -> np.ndarray:
    """Measurement matrix ``D`` (3×10) of Eq. (8): the angle sensor reads Δβ; inclinometer y
    reads ``g δ + N1``; inclinometer z reads ``g γ + N1``."""
    params = _check_params(params)
    D = np.zeros((3, N_STATES))
    D[0, 0] = 1.0
    D[1, 4] = params.g
    D[1, 6] = 1.0
    D[2, 5] = params.g
    D[2, 6] = 1.0
    return D


def process_noise_intensity(params: GyrocompassParams) -> np.ndarray:
    """Intensity ``Q`` (2×2) of the white noises ``w1``, ``w2`` driving Eqs. (6), (7)."""
    return np.diag([_check_params(params).Q1, params.Q2])


def measurement_noise_intensity(params: GyrocompassParams) -> np.ndarray:
    """Continuous intensities of the sensor noises: ``diag(C_as, C_incl_y, C_incl_z)``."""
    p = _check_params(params)
    return np.diag([p.C_as, p.C_incl_y, p.C_incl_z])


def measurement_noise_covariance(params: GyrocompassParams) -> np.ndarray:
    """Discrete measurement-noise covariance ``R`` at the sampling interval ``dt``.

    ``"intensity_over_dt"``: ``R = C/Δt`` (continuous white noise of intensity C seen through
    an ideal averaging sampler over Δt); ``"variance"``: ``R = C`` (printed numbers read as
    the per-sample variances).
    """
    C = measurement_noise_intensity(_check_params(params))
    return C / params.dt if params.measurement_noise == "intensity_over_dt" else C


def initial_covariance(params: GyrocompassParams) -> np.ndarray:
    """Initial covariance ``P(0)`` (10×10).

    ψ, ω_gc, δ, γ from the paper; Δβ, Δβ' from ``sigma_dbeta0``, ``sigma_dbeta_dot0``;
    N1…N4 from ``shaping_p0`` (their stationary covariance, or zero).
    """
    p = _check_params(params)
    P = np.zeros((N_STATES, N_STATES))
    for name, sigma in (("dbeta", p.sigma_dbeta0), ("dbeta_dot", p.sigma_dbeta_dot0),
                        ("psi", p.sigma_psi0), ("omega_gc", p.sigma_gc0),
                        ("delta", p.sigma_delta0), ("gamma", p.sigma_gamma0)):
        i = state_index(name)
        P[i, i] = sigma**2
    if p.shaping_p0 == "stationary":
        P[6:8, 6:8] = p.vibration_filter().stationary_covariance()
        P[8:10, 8:10] = p.random_drift_filter().stationary_covariance()
    return P
