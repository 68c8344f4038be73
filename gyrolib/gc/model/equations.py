"""Paper GC, Eqs. (1)–(3) and (5): the gyrocompass equation of the float, nonlinear and
linearized, as plain functions of the float angle and the disturbances.

* :func:`gyroscopic_torque` — Eq. (1), ``M_g = H Ω_h cos(β − ψ)``;
* :func:`vertical_rate` — Eq. (2), ``ω_y = −Ω_v δ``, ``ω_z = Ω_v γ``;
* :func:`float_acceleration` — Eq. (3), ``I β'' + f β' = H Ω_h cos(β − ψ)
  + H Ω_v γ cos β − H Ω_v δ sin β + H ω_gc + H ω_rnd``, solved for ``β''``;
* :func:`linearized_acceleration` — Eq. (5), Eq. (3) linearized about the nominal motion
  ``β_n`` of Eq. (4): ``I Δβ'' + f Δβ' + H Ω_h sin β_n Δβ = H Ω_h sin β_n ψ
  + H Ω_v cos β_n γ − H Ω_v sin β_n δ + H ω_gc + H ω_rnd``, solved for ``Δβ''``.

Row 2 of the state matrix of Eq. (8) (:func:`gyrolib.gc.system_matrix`) is Eq. (5) divided
by ``I``, with the unbalance torque ``H ω_ub N1 / g`` added; the tests check the two against
each other, and Eq. (5) against a finite difference of Eq. (3).  These functions follow the
equations as printed (``eq1_sign="+"``, ``vertical_coupling="eq5"``); the other readings of
the extracted text are options of :class:`~gyrolib.gc.GyrocompassParams` that only the state
matrix carries.

All quantities in SI: angles in rad, rates in rad/s, torques in N·m.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrolib.gc.model.params import GyrocompassParams, check_params

__all__ = [
    "float_acceleration",
    "gyroscopic_torque",
    "linearized_acceleration",
    "vertical_rate",
]


def gyroscopic_torque(params: GyrocompassParams, beta: ArrayLike,
                      psi: ArrayLike = 0.0) -> NDArray[np.float64]:
    """Paper GC, Eq. (1): the gyroscopic torque ``M_g = H Ω_h cos(β − ψ)`` (N·m).

    Parameters
    ----------
    params : GyrocompassParams
        ``H`` (N·m·s) and ``Omega_h`` (rad/s).
    beta : array_like
        Float angle β (rad).
    psi : array_like, optional
        Azimuth error ψ of the input axis from north (rad).

    Examples
    --------
    >>> from gyrolib import gc
    >>> from gyrolib.gc.model.equations import gyroscopic_torque
    >>> p = gc.GyrocompassParams()
    >>> f"{gyroscopic_torque(p, 0.0) / (p.H * p.Omega_h):.3f}"
    '1.000'
    """
    p = check_params(params)
    return p.H * p.Omega_h * np.cos(np.asarray(beta, float) - np.asarray(psi, float))


def vertical_rate(params: GyrocompassParams, delta: ArrayLike,
                  gamma: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Paper GC, Eq. (2): the vertical Earth rate projected on the base axes of a platform
    tilted by δ and γ: ``(ω_y, ω_z) = (−Ω_v δ, Ω_v γ)`` (rad/s).

    Examples
    --------
    >>> from gyrolib import gc
    >>> from gyrolib.gc.model.equations import vertical_rate
    >>> wy, wz = vertical_rate(gc.GyrocompassParams(Omega_v=1.0), 2.0, 3.0)
    >>> float(wy), float(wz)
    (-2.0, 3.0)
    """
    p = check_params(params)
    return -p.Omega_v * np.asarray(delta, float), p.Omega_v * np.asarray(gamma, float)


def float_acceleration(params: GyrocompassParams, beta: ArrayLike, beta_dot: ArrayLike, *,
                       psi: ArrayLike = 0.0, delta: ArrayLike = 0.0, gamma: ArrayLike = 0.0,
                       omega_gc: ArrayLike = 0.0,
                       omega_rnd: ArrayLike = 0.0) -> NDArray[np.float64]:
    """Paper GC, Eq. (3), the nonlinear gyrocompass equation solved for ``β''`` (rad/s²):

    ``β'' = [H Ω_h cos(β − ψ) + H Ω_v γ cos β − H Ω_v δ sin β + H ω_gc + H ω_rnd − f β'] / I``.

    With ψ = δ = γ = ω_gc = ω_rnd = 0 it is the nominal motion of Eq. (4).

    Examples
    --------
    >>> from gyrolib import gc
    >>> from gyrolib.gc.model.equations import float_acceleration
    >>> p = gc.GyrocompassParams()
    >>> f"{float(float_acceleration(p, 0.0, 0.0)):.4f}"   # H Ω_h / I at rest, β = 0
    '0.0537'
    """
    p = check_params(params)
    b = np.asarray(beta, float)
    torque = (p.H * p.Omega_h * np.cos(b - np.asarray(psi, float))
              + p.H * p.Omega_v * (np.asarray(gamma, float) * np.cos(b)
                                   - np.asarray(delta, float) * np.sin(b))
              + p.H * (np.asarray(omega_gc, float) + np.asarray(omega_rnd, float)))
    return (torque - p.f * np.asarray(beta_dot, float)) / p.I


def linearized_acceleration(params: GyrocompassParams, beta_n: ArrayLike, d_beta: ArrayLike,
                            d_beta_dot: ArrayLike, *, psi: ArrayLike = 0.0,
                            delta: ArrayLike = 0.0, gamma: ArrayLike = 0.0,
                            omega_gc: ArrayLike = 0.0,
                            omega_rnd: ArrayLike = 0.0) -> NDArray[np.float64]:
    """Paper GC, Eq. (5), Eq. (3) linearized about the nominal motion β_n, solved for
    ``Δβ''`` (rad/s²):

    ``Δβ'' = [−f Δβ' − H Ω_h sin β_n Δβ + H Ω_h sin β_n ψ + H Ω_v cos β_n γ
    − H Ω_v sin β_n δ + H ω_gc + H ω_rnd] / I``.

    Examples
    --------
    >>> from gyrolib import gc
    >>> from gyrolib.gc.model.equations import linearized_acceleration
    >>> p = gc.GyrocompassParams()
    >>> a = linearized_acceleration(p, 0.3, 0.0, 0.0, omega_gc=1e-6)
    >>> f"{float(a) * p.I / p.H:.1e}"                    # a drift alone: H ω_gc / I
    '1.0e-06'
    """
    p = check_params(params)
    s, c = np.sin(np.asarray(beta_n, float)), np.cos(np.asarray(beta_n, float))
    k = p.H * p.Omega_h * s
    torque = (-p.f * np.asarray(d_beta_dot, float) - k * np.asarray(d_beta, float)
              + k * np.asarray(psi, float)
              + p.H * p.Omega_v * (c * np.asarray(gamma, float) - s * np.asarray(delta, float))
              + p.H * (np.asarray(omega_gc, float) + np.asarray(omega_rnd, float)))
    return torque / p.I
