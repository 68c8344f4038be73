"""Paper GC, Eqs. (5)–(8): the linearized model in Cauchy form, ``x' = F x + G w``,
``z = D x + v``.

* :func:`system_matrix` — ``F(β_n)`` of Eq. (8) (Eq. (5) and the shaping filters (6), (7));
* :func:`noise_input_matrix` — ``G``; :func:`measurement_matrix` — ``D``;
* :func:`process_noise_intensity`, :func:`measurement_noise_intensity`,
  :func:`measurement_noise_covariance` — ``Q``, ``C`` and the sampled ``R``;
* :func:`initial_covariance` — ``P(0)``;
* :class:`ContinuousModel` (:func:`continuous_model`) — all of them at once, built once for
  given parameters, with the instrument constants that are ON appended to the state: the one
  object the discretization (:mod:`gyrolib.gc.model.discretization`) takes.
"""

from __future__ import annotations

from dataclasses import dataclass
from types import MappingProxyType
from typing import Final

import numpy as np
from numpy.typing import NDArray

from gyrolib import _validation as v
from gyrolib._repr import compact_repr
from gyrolib.gc.model.instrument import InstrumentModel, build_instrument_model
from gyrolib.gc.model.params import (
    N_STATES,
    STATE_NAMES,
    GyrocompassParams,
    check_params,
    state_index,
)

__all__ = [
    "ContinuousModel",
    "continuous_model",
    "initial_covariance",
    "measurement_matrix",
    "measurement_noise_covariance",
    "measurement_noise_intensity",
    "noise_input_matrix",
    "process_noise_intensity",
    "system_matrix",
]


# State-space model, Eq. (8) -------------------------------------------------------------------
def system_matrix(params: GyrocompassParams, beta_n: float) -> NDArray[np.float64]:
    """State matrix ``F(t)`` of paper GC, Eq. (8), at the nominal float angle ``beta_n``.

    Row 2 is the linearized gyrocompass equation, Eq. (5) of paper GC, divided by ``I``
    (plus the unbalance torque ``H ω_ub N1 / g``); rows 7–10 are the shaping filters,
    Eqs. (6), (7).  State order: :data:`gyrolib.gc.STATE_NAMES` (X1 = Δβ, X2 = Δβ').

    Parameters
    ----------
    params : GyrocompassParams
        The model; ``vertical_coupling`` picks Eq. (5)'s coupling of δ, γ or the printed F
        listing's, and ``eq1_sign="-"`` the literal minus sign of Eq. (1) (in the mirrored
        float angle: the tilt term that carries ``sin β_n`` changes sign).
    beta_n : float
        Nominal float angle β_n (rad), Eq. (4).

    Returns
    -------
    F : ndarray of shape (10, 10)
        The state matrix (1/s, SI states).

    Examples
    --------
    >>> from gyrolib import gc
    >>> F = gc.system_matrix(gc.GyrocompassParams(), 0.0)
    >>> f"{F[1, 1]:.0f} {F[7, 6]:.3g}"   # F(2,2) = -f/I, F(8,7) = -alpha1**2
    '-625 -0.000177'
    """
    return build_system_matrix(check_params(params), v.check_real("beta_n", beta_n))


def build_system_matrix(p: GyrocompassParams, b: float) -> NDArray[np.float64]:
    s, c = np.sin(b), np.cos(b)
    F = np.zeros((N_STATES, N_STATES))
    F[0, 1] = 1.0
    F[1, 0] = -(p.H * p.Omega_h / p.I) * s
    F[1, 1] = -p.f / p.I
    F[1, 2] = (p.H * p.Omega_h / p.I) * s
    F[1, 3] = p.H / p.I
    # the literal "−" of Eq. (1), mirrored back to β_n > 0, flips the tilt term with sin β_n
    ts = -1.0 if p.eq1_sign == "-" else 1.0
    if p.vertical_coupling == "eq5":
        F[1, 4] = -ts * (p.H * p.Omega_v / p.I) * s  # δ carries −sin β_n
        F[1, 5] = (p.H * p.Omega_v / p.I) * c  # γ carries cos β_n
    else:  # the paper's F listing as printed
        F[1, 4] = -(p.H * p.Omega_v / p.I) * c
        F[1, 5] = ts * (p.H * p.Omega_v / p.I) * s
    F[1, 6] = p.H * p.omega_ub / (p.I * p.g)
    F[1, 8] = p.H / p.I
    F[6:8, 6:8] = p.vibration_filter().A
    F[8:10, 8:10] = p.random_drift_filter().A
    return F


def noise_input_matrix(params: GyrocompassParams) -> NDArray[np.float64]:
    """Disturbance matrix ``G`` (10×2) of Eq. (8): ``G(7,1) = 1``, ``G(8,1) = α1 − 2ξ1α1``,
    ``G(10,2) = 1``.

    Parameters
    ----------
    params : GyrocompassParams
        The model (ξ1, α1).

    Returns
    -------
    G : ndarray of shape (10, 2)

    Examples
    --------
    >>> from gyrolib import gc
    >>> G = gc.noise_input_matrix(gc.GyrocompassParams())
    >>> f"{G[6, 0]:g} {G[7, 0]:.3g} {G[9, 1]:g}"
    '1 -0.00532 1'
    """
    return build_noise_input_matrix(check_params(params))


def build_noise_input_matrix(params: GyrocompassParams) -> NDArray[np.float64]:
    G = np.zeros((N_STATES, 2))
    G[6:8, 0] = params.vibration_filter().B[:, 0]
    G[8:10, 1] = params.random_drift_filter().B[:, 0]
    return G


def measurement_matrix(params: GyrocompassParams) -> NDArray[np.float64]:
    """Measurement matrix ``D`` (3×10) of Eq. (8): the angle sensor reads Δβ; inclinometer y
    reads ``g δ + N1``; inclinometer z reads ``g γ + N1``.

    Parameters
    ----------
    params : GyrocompassParams
        The model (``g``).

    Returns
    -------
    D : ndarray of shape (3, 10)

    Examples
    --------
    >>> from gyrolib import gc
    >>> D = gc.measurement_matrix(gc.GyrocompassParams())
    >>> [f"{x:g}" for x in D[1, 4:7]]   # inclinometer y: g δ + N1
    ['9.80665', '0', '1']
    """
    return build_measurement_matrix(check_params(params))


def build_measurement_matrix(params: GyrocompassParams) -> NDArray[np.float64]:
    D = np.zeros((3, N_STATES))
    D[0, 0] = 1.0
    D[1, 4] = params.g
    D[1, 6] = 1.0
    D[2, 5] = params.g
    D[2, 6] = 1.0
    return D


def process_noise_intensity(params: GyrocompassParams) -> NDArray[np.float64]:
    """Intensity ``Q`` (2×2) of the white noises ``w1``, ``w2`` driving Eqs. (6), (7).

    Parameters
    ----------
    params : GyrocompassParams
        The model (shaping-filter parameters).

    Returns
    -------
    Q : ndarray of shape (2, 2)
        ``diag(Q1, Q2)``, ``Q1 = 2 ξ1 α1 σ1²`` (m²/s⁵), ``Q2 = 4 ξ2 α2³ σ2²`` (rad²/s³).

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import gc
    >>> [f"{q:.3g}" for q in np.diag(gc.process_noise_intensity(gc.GyrocompassParams()))]
    ['3.46e-08', '9.31e-13']
    """
    return build_process_noise_intensity(check_params(params))


def build_process_noise_intensity(p: GyrocompassParams) -> NDArray[np.float64]:
    return np.diag([p.Q1, p.Q2])


def measurement_noise_intensity(params: GyrocompassParams) -> NDArray[np.float64]:
    """Continuous intensities of the sensor noises: ``diag(C_as, C_incl_y, C_incl_z)``.

    Parameters
    ----------
    params : GyrocompassParams
        The model (``C_as``, ``C_incl_y``, ``C_incl_z``).

    Returns
    -------
    C : ndarray of shape (3, 3)

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import gc
    >>> [f"{c:g}" for c in np.diag(gc.measurement_noise_intensity(gc.GyrocompassParams()))]
    ['2e-13', '5e-15', '5e-15']
    """
    p = check_params(params)
    return np.diag([p.C_as, p.C_incl_y, p.C_incl_z])


def measurement_noise_covariance(params: GyrocompassParams) -> NDArray[np.float64]:
    """Discrete measurement-noise covariance ``R`` at the sampling interval ``dt``.

    ``"intensity_over_dt"``: ``R = C/Δt`` (continuous white noise of intensity C seen through
    an ideal averaging sampler over Δt); ``"variance"``: ``R = C`` (printed numbers read as
    the per-sample variances).

    Parameters
    ----------
    params : GyrocompassParams
        The model (``measurement_noise``, ``dt`` and the intensities).

    Returns
    -------
    R : ndarray of shape (3, 3)

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import gc
    >>> [f"{r:g}" for r in np.diag(gc.measurement_noise_covariance(gc.GyrocompassParams()))]
    ['2e-10', '5e-12', '5e-12']
    """
    return build_measurement_noise_covariance(check_params(params))


def build_measurement_noise_covariance(p: GyrocompassParams) -> NDArray[np.float64]:
    C = np.diag([p.C_as, p.C_incl_y, p.C_incl_z])
    return C / p.dt if p.measurement_noise == "intensity_over_dt" else C


def initial_covariance(params: GyrocompassParams) -> NDArray[np.float64]:
    """Initial covariance ``P(0)`` (10×10).

    ψ, ω_gc, δ, γ from the paper; Δβ, Δβ' from ``sigma_dbeta0``, ``sigma_dbeta_dot0``;
    N1…N4 from ``shaping_p0`` (their stationary covariance times ``shaping_p0_scale``, or
    zero).

    Parameters
    ----------
    params : GyrocompassParams
        The model and its readings of the unstated P(0) entries.

    Returns
    -------
    P0 : ndarray of shape (10, 10)

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import gc
    >>> from gyrolib.units import from_si
    >>> P0 = gc.initial_covariance(gc.GyrocompassParams())
    >>> f"{from_si(np.sqrt(P0[3, 3]), 'arcsec_paper/s'):.2f}"   # σ of ω_gc, ″/s
    '0.15'
    """
    return build_initial_covariance(check_params(params))


def build_initial_covariance(p: GyrocompassParams) -> NDArray[np.float64]:
    P = np.zeros((N_STATES, N_STATES))
    for name, sigma in (("dbeta", p.sigma_dbeta0), ("dbeta_dot", p.sigma_dbeta_dot0),
                        ("psi", p.sigma_psi0), ("omega_gc", p.sigma_gc0),
                        ("delta", p.sigma_delta0), ("gamma", p.sigma_gamma0)):
        i = state_index(name)
        P[i, i] = sigma**2
    if p.shaping_p0 == "stationary":
        k = p.shaping_p0_scale
        P[6:8, 6:8] = k * p.vibration_filter().stationary_covariance()
        P[8:10, 8:10] = k * p.random_drift_filter().stationary_covariance()
    return P


# The continuous model as one object ----------------------------------------------------------
#: Where each matrix of :class:`ContinuousModel` comes from (paper GC).
SOURCES: Final = MappingProxyType({
    "F": "Eq. (8): Eq. (5) divided by I (row 2) and the shaping filters, Eqs. (6), (7) "
         "(rows 7-10), affine in (sin β_n, cos β_n); the instrument constants' columns Fb",
    "G": "Eq. (8): the shaping filters' inputs, Eqs. (6), (7)",
    "Q": "the intensities of w1, w2 driving Eqs. (6), (7): Q1 = 2 ξ1 α1 σ1², "
         "Q2 = 4 ξ2 α2³ σ2²",
    "H": "Eq. (8): D (angle sensor Δβ, inclinometers g δ + N1, g γ + N1), then the "
         "instrument constants' columns H0 + β_n H1",
    "R": "the sensor noises sampled at dt: C/dt or C (params.measurement_noise)",
    "P0": "the parameter table's priors, the shaping filters' P0 (params.shaping_p0), then "
          "the instrument constants' prior variances",
})


def _pad(A: np.ndarray, n: int, cols: int | None = None) -> np.ndarray:
    """``A`` in the top left corner of an ``n × cols`` (default ``n × n``) zero matrix."""
    out = np.zeros((n, n if cols is None else cols))
    out[:A.shape[0], :A.shape[1]] = A
    return out


def _affine_parts(p: GyrocompassParams) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``F(β) = F_c + sin β · E_s + cos β · E_c`` (exact: F is affine in sin and cos)."""
    F0, F90, F180 = (build_system_matrix(p, b) for b in (0.0, 0.5 * np.pi, np.pi))
    Ec = 0.5 * (F0 - F180)
    Fc = 0.5 * (F0 + F180)
    Es = F90 - Fc
    # sin(π) and cos(π/2) are ~1e-16, not 0: clean the rounding
    for A in (Ec, Fc, Es):
        A[np.abs(A) < 1e-12 * np.max(np.abs(F0))] = 0.0
    return Fc, Es, Ec


@compact_repr
@dataclass(frozen=True, eq=False)
class ContinuousModel:
    """Paper GC's continuous model, Eq. (8), for one set of parameters, with the instrument
    constants that are carried appended to the state (:mod:`gyrolib.gc.model.instrument`):

    ``x' = F(β_n) x + G w``, ``E[w wᵀ] = Q δ(t − s)``, ``z_k = (H0 + β_n H1) x(t_k) + v_k``,
    ``E[v vᵀ] = R``, ``x(0) ~ (0, P0)``,

    with ``F(β) = Fc + sin β · Es + cos β · Ec`` (exact: F is affine in ``(sin β_n, cos
    β_n)``).  ``instrument``: the constants carried (``None``: the 10 states of Eq. (8));
    :data:`SOURCES` (also :attr:`sources`) says where each matrix comes from.  Built once
    (:meth:`build`, :func:`continuous_model`); its arrays are read-only (a model may be
    shared by the library's caches, :func:`gyrolib.gc.model.discretization.kept_discretization`).
    Compared by identity.
    """

    params: GyrocompassParams
    Fc: NDArray[np.float64]
    Es: NDArray[np.float64]
    Ec: NDArray[np.float64]
    G: NDArray[np.float64]
    Q: NDArray[np.float64]
    H0: NDArray[np.float64]
    H1: NDArray[np.float64]
    R: NDArray[np.float64]
    P0: NDArray[np.float64]
    instrument: InstrumentModel | None = None

    def __post_init__(self) -> None:
        check_params(self.params)
        if self.instrument is not None:
            v.check_instance("instrument", self.instrument, InstrumentModel)
        n = self.n
        for name in ("Fc", "Es", "Ec", "P0"):
            v.check_ndarray(name, getattr(self, name), shape=(n, n))
        nw = v.check_ndarray("G", self.G, shape=(n, None)).shape[1]
        v.check_ndarray("Q", self.Q, shape=(nw, nw))
        v.check_ndarray("H0", self.H0, shape=(None, n))
        m = self.H0.shape[0]
        v.check_ndarray("H1", self.H1, shape=(m, n))
        v.check_ndarray("R", self.R, shape=(m, m))
        for name in ("Fc", "Es", "Ec", "G", "Q", "H0", "H1", "R", "P0"):
            getattr(self, name).setflags(write=False)

    @classmethod
    def build(cls, p: GyrocompassParams, inst: InstrumentModel | None = None
              ) -> ContinuousModel:
        """The model of parameters already checked, carrying the constants ``inst``
        (``None``, or none of them: Eq. (8)'s 10 states)."""
        if inst is not None and inst.nb == 0:
            inst = None
        Fc, Es, Ec = _affine_parts(p)
        G = build_noise_input_matrix(p)
        D = build_measurement_matrix(p)
        P0 = build_initial_covariance(p)
        if inst is None:
            H0, H1 = D, np.zeros_like(D)
        else:
            n = N_STATES + inst.nb
            Fc = _pad(Fc, n)
            Fc[:N_STATES, N_STATES:] = inst.Fb
            Es, Ec, G = _pad(Es, n), _pad(Ec, n), _pad(G, n, G.shape[1])
            H0, H1 = np.hstack([D, inst.H0]), np.hstack([np.zeros_like(D), inst.H1])
            P0 = _pad(P0, n)
            P0[N_STATES:, N_STATES:] = np.diag(inst.prior**2)
        return cls(params=p, Fc=Fc, Es=Es, Ec=Ec, G=G, Q=build_process_noise_intensity(p),
                   H0=H0, H1=H1, R=build_measurement_noise_covariance(p), P0=P0,
                   instrument=inst)

    @classmethod
    def with_instruments(cls, p: GyrocompassParams) -> ContinuousModel:
        """:meth:`build` with the instrument constants that are ON for ``p`` (prior > 0)."""
        return cls.build(p, build_instrument_model(p))

    @property
    def n(self) -> int:
        """The number of states."""
        return N_STATES + (0 if self.instrument is None else self.instrument.nb)

    @property
    def state_names(self) -> tuple[str, ...]:
        """Eq. (8)'s states, then the instrument constants carried."""
        return STATE_NAMES + (() if self.instrument is None else self.instrument.names)

    @property
    def sources(self) -> MappingProxyType:
        """Where each matrix comes from (:data:`SOURCES`)."""
        return SOURCES

    def system_matrix(self, beta_n: float) -> NDArray[np.float64]:
        """``F(β_n)`` (a new array): Eq. (8)'s own :func:`system_matrix` on the 10 states
        (no affine rounding), ``Fc + sin β_n Es + cos β_n Ec`` with instrument constants."""
        b = v.check_real("beta_n", beta_n)
        if self.instrument is None:
            return build_system_matrix(self.params, b)
        return self.Fc + np.sin(b) * self.Es + np.cos(b) * self.Ec


def continuous_model(params: GyrocompassParams, *, instrument: bool = False
                     ) -> ContinuousModel:
    """Paper GC's continuous model, Eq. (8), built once as one object.

    Parameters
    ----------
    params : GyrocompassParams
        The model.
    instrument : bool, default False
        Append the instrument constants that are ON for ``params``
        (:func:`gyrolib.gc.instrument_model`) to the state.

    Returns
    -------
    ContinuousModel

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import gc
    >>> p = gc.GyrocompassParams(sigma_as_offset=1e-5)
    >>> m = gc.continuous_model(p, instrument=True)
    >>> m.n, m.state_names[10:], float(m.H0[0, 10])
    (11, ('angle_offset',), 1.0)
    >>> bool(np.allclose(m.system_matrix(0.3)[:10, :10], gc.system_matrix(p, 0.3)))
    True
    """
    p = check_params(params)
    instrument = v.check_bool("instrument", instrument)
    return ContinuousModel.with_instruments(p) if instrument else ContinuousModel.build(p)

