"""Paper GC, Eq. (4): the nominal motion ``β_n(t)`` of the float after the feedback is
switched off, ``I β_n'' + f β_n' = H Ω_h cos β_n`` from rest.

:func:`nominal_motion` integrates Eq. (4) with scipy's implicit Radau method (the equation is
stiff); :func:`nominal_motion_reference` is an independent check (explicit DOP853 on the
difference from the aperiodic solution, tighter tolerance); :func:`nominal_motion_aperiodic`
is the closed form of the inertia-free approximation ``f β' = H Ω_h cos β``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gyrolib import _validation as v
from gyrolib._repr import compact_repr
from gyrolib.gc.model.params import GyrocompassParams, check_params

__all__ = [
    "NominalMotion",
    "nominal_motion",
    "nominal_motion_aperiodic",
    "nominal_motion_reference",
]


# Nominal motion, Eq. (4) ----------------------------------------------------------------------
@compact_repr
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


def _check_times(t: ArrayLike) -> NDArray[np.float64]:
    t = v.check_array("t", t, ndim=1)
    if t.size == 0:
        raise ValueError("t must hold at least one time")
    if t[0] < 0.0 or np.any(np.diff(t) < 0.0):
        raise ValueError("t must be non-negative and non-decreasing")
    return t


def nominal_motion(params: GyrocompassParams, t: ArrayLike, *,
                   rtol: float = 1e-11) -> NominalMotion:
    """Solve paper GC's nominal equation (4), ``I β'' + f β' = H Ω_h cos β``, from rest.

    The initial state is ``β(0) = 0``, ``β'(0) = 0`` (the float at the angle sensor's null when
    the feedback is switched off).  The equation is stiff (time constant ``I/f`` = 1.6 ms over
    100 s), so an implicit Radau method with tight tolerances is used; its error against an
    independent solution is shown in the model chapter.

    Parameters
    ----------
    params : GyrocompassParams
        The model (``I``, ``f``, ``H``, ``Omega_h``).
    t : array_like
        Times (s), 1-D, non-decreasing, from 0.
    rtol : float, default 1e-11
        Relative tolerance of the Radau integrator, in [1e-14, 1e-3].

    Returns
    -------
    NominalMotion
        ``β_n`` (rad) and ``β_n'`` (rad/s) at ``t``.

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import gc
    >>> from gyrolib.units import from_si
    >>> nom = gc.nominal_motion(gc.GyrocompassParams(), np.array([0.0, 100.0]))
    >>> f"{from_si(nom.beta[-1], 'deg'):.4f}"   # paper GC: "about 0.5°"
    '0.4927'
    """
    check_params(params)
    t = _check_times(t)
    v.check_in_range("rtol", rtol, 1e-14, 1e-3)
    k_dd = params.H * params.Omega_h / params.I
    c = params.f / params.I

    def rhs(_t: float, y: np.ndarray) -> NDArray[np.float64]:
        return np.array([y[1], k_dd * np.cos(y[0]) - c * y[1]])

    def jac(_t: float, y: np.ndarray) -> NDArray[np.float64]:
        return np.array([[0.0, 1.0], [-k_dd * np.sin(y[0]), -c]])

    if t[-1] == 0.0:
        zeros = np.zeros_like(t)
        return NominalMotion(t=t, beta=zeros, beta_dot=zeros.copy())
    from scipy.integrate import solve_ivp  # here: 0.2 s of the command line's start

    sol = solve_ivp(rhs, (0.0, float(t[-1])), [0.0, 0.0], method="Radau", t_eval=t,
                    rtol=rtol, atol=1e-16, jac=jac)
    if not sol.success:  # pragma: no cover - Radau does not fail on this smooth problem
        raise RuntimeError(f"nominal motion integration failed: {sol.message}")
    return NominalMotion(t=t, beta=sol.y[0].copy(), beta_dot=sol.y[1].copy())


def nominal_motion_reference(params: GyrocompassParams, t: ArrayLike, *,
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

    Parameters
    ----------
    params : GyrocompassParams
        The model.
    t : array_like
        Times (s), 1-D, non-decreasing, from 0.
    rtol : float, default 1e-13
        Relative tolerance of DOP853.

    Returns
    -------
    NominalMotion
        ``β_n`` and ``β_n'`` at ``t``.

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import gc
    >>> p, t = gc.GyrocompassParams(), np.linspace(0.0, 100.0, 11)
    >>> diff = gc.nominal_motion_reference(p, t).beta - gc.nominal_motion(p, t).beta
    >>> bool(np.max(np.abs(diff)) < 1e-12)
    True
    """
    check_params(params)
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
    from scipy.integrate import solve_ivp

    sol = solve_ivp(rhs, (0.0, float(t[-1])), [0.0, -k], method="DOP853", t_eval=t,
                    rtol=rtol, atol=1e-22, first_step=1e-7)
    if not sol.success:  # pragma: no cover
        raise RuntimeError(f"reference integration failed: {sol.message}")
    return NominalMotion(t=t, beta=ap.beta + sol.y[0], beta_dot=ap.beta_dot + sol.y[1])


def nominal_motion_aperiodic(params: GyrocompassParams, t: ArrayLike) -> NominalMotion:
    """Aperiodic (inertia-free) approximation of Eq. (4): ``f β' = H Ω_h cos β``.

    Separating variables gives the Gudermannian ``β = 2 arctan(tanh(k t / 2))`` with
    ``k = H Ω_h / f``; it holds once ``t ≫ I/f``.

    Parameters
    ----------
    params : GyrocompassParams
        The model.
    t : array_like
        Times (s), 1-D.

    Returns
    -------
    NominalMotion
        ``β_ap`` and its rate ``k cos β_ap`` at ``t``.

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import gc
    >>> from gyrolib.units import from_si
    >>> ap = gc.nominal_motion_aperiodic(gc.GyrocompassParams(), np.array([100.0]))
    >>> f"{from_si(ap.beta[0], 'deg'):.4f}"
    '0.4927'
    """
    check_params(params)
    t = _check_times(t)
    k = params.H * params.Omega_h / params.f
    beta = 2.0 * np.arctan(np.tanh(0.5 * k * t))
    return NominalMotion(t=t, beta=beta, beta_dot=k * np.cos(beta))
