"""Paper GC, Eqs. (5)–(8): the linearized model in Cauchy form, ``x' = F x + G w``,
``z = D x + v``.

* :func:`system_matrix` — ``F(β_n)`` of Eq. (8) (Eq. (5) and the shaping filters (6), (7));
* :func:`noise_input_matrix` — ``G``; :func:`measurement_matrix` — ``D``;
* :func:`process_noise_intensity`, :func:`measurement_noise_intensity`,
  :func:`measurement_noise_covariance` — ``Q``, ``C`` and the sampled ``R``;
* :func:`initial_covariance` — ``P(0)``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from gyrolib import _validation as v
from gyrolib.gc.model.params import N_STATES, GyrocompassParams, check_params, state_index

__all__ = [
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
