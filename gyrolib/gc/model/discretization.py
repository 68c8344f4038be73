"""Paper GC, the discrete model of the filter: Eq. (8) discretized at ``Δt`` (1 ms).

``F`` is frozen at the nominal float angle of each step's midpoint, ``β_n(t_k + Δt/2)``: exact
transition and process noise by Van Loan's method {cite:p}`VanLoan1978`, expanded to first
order in ``(sin β_n, cos β_n)`` about expansion points ``SEGMENT`` rad apart
(:class:`gyrolib.filtering.AffineDiscreteModel`; error ≈ 10⁻¹³, tested against a per-step
matrix exponential).  The nominal motion Eq. (4) is integrated on the half-step grid by a
second-order exponential integrator (:func:`nominal_half_steps`, tested against
:func:`gyrolib.gc.model.nominal`).

``method="euler"`` replaces the exact step by Euler's first-order one, ``Φ = I + F Δt``,
``Qd = G Q Gᵀ Δt`` (exactly affine in ``(sin β_n, cos β_n)``), to measure what the exact
discretization buys.

The discretization takes the continuous model as one object,
:class:`gyrolib.gc.model.state_space.ContinuousModel` (``F``, ``G``, ``Q``, ``H``, ``R``,
``P(0)``, built once for given parameters), and asks the continuous side for nothing else.

Measurements ``z_k = D x(t_k) + v_k`` at ``t_k = k Δt``, ``k ≥ 1``; the filter starts from
``x̂(0) = 0``, ``P(0)`` = :func:`gyrolib.gc.initial_covariance`.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass
from typing import Final

import numpy as np
import scipy.linalg
from numba import njit
from numpy.typing import NDArray

from gyrolib import _compile_note  # noqa: F401  (a line on stderr at the first compile)
from gyrolib import _validation as v
from gyrolib._repr import compact_repr
from gyrolib.filtering.covariance import AffineDiscreteModel
from gyrolib.filtering.discretization import covariance_factor, van_loan, van_loan_derivatives
from gyrolib.gc.model.params import STATE_NAMES, GyrocompassParams, check_params
from gyrolib.gc.model.state_space import ContinuousModel

__all__ = [
    "DISCRETIZATIONS",
    "SEGMENT",
    "GCDiscretization",
    "NominalIntegrator",
    "discretize",
    "nominal_half_steps",
    "system_matrix_parts",
]


#: Spacing (rad) of the β_n expansion points of the affine discretization.
SEGMENT: Final[float] = 0.01


N: Final[int] = len(STATE_NAMES)


#: The discretizations :func:`discretize` offers.
DISCRETIZATIONS: Final[tuple[str, ...]] = ("van_loan", "euler")


def steps_in(params: GyrocompassParams, t_end: object) -> int:
    t_end = v.check_positive("t_end", t_end)
    n = round(t_end / params.dt)
    if n < 1 or abs(n * params.dt - t_end) > 1e-9 * max(t_end, 1.0):
        raise ValueError(f"t_end must be a positive multiple of dt={params.dt}; got {t_end}")
    return n


# Nominal motion on the half-step grid --------------------------------------------------------
@njit(cache=True)
def _etd2_advance(E, p1, p2, kdd, y, n, out):
    """``n`` half steps of the ETD2 scheme of :func:`nominal_half_steps` from the state
    ``y = (β, β')`` (updated in place, so a run can be continued chunk by chunk);
    ``out`` (length >= n, or 0 to discard) receives β after each half step."""
    y0 = y[0]
    y1 = y[1]
    store = out.shape[0] >= n
    for i in range(n):
        u0 = kdd * math.cos(y0)
        a0 = E[0, 0] * y0 + E[0, 1] * y1 + p1[0] * u0
        a1 = E[1, 0] * y0 + E[1, 1] * y1 + p1[1] * u0
        du = kdd * math.cos(a0) - u0
        y0 = a0 + p2[0] * du
        y1 = a1 + p2[1] * du
        if store:
            out[i] = y0
    y[0] = y0
    y[1] = y1


def _etd2_coefficients(p: GyrocompassParams) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """The half-step ETD2 coefficients of Eq. (4): ``E = exp(A h)`` of the linear part and the
    two forcing columns (Van Loan's augmented exponential), and ``H Ω_h / I``."""
    h = 0.5 * p.dt
    M = np.zeros((4, 4))
    M[0, 1] = h
    M[1, 1] = -p.f / p.I * h
    M[1, 2] = h
    M[2, 3] = 1.0
    Ex = scipy.linalg.expm(M)
    return Ex[:2, :2].copy(), Ex[:2, 2].copy(), Ex[:2, 3].copy(), p.H * p.Omega_h / p.I


def nominal_half_steps(params: GyrocompassParams, n_steps: int) -> NDArray[np.float64]:
    """Nominal float angle ``β_n`` (rad), Eq. (4) from rest, at ``t = i Δt/2``,
    ``i = 0 … 2 n_steps``.

    Exponential time differencing (ETD2RK, Cox–Matthews): the stiff linear part
    ``β'' = −(f/I) β'`` is exact, the slowly varying torque ``H Ω_h cos β / I`` is
    interpolated linearly over each half step.

    Parameters
    ----------
    params : GyrocompassParams
        The model.
    n_steps : int
        Number of filter steps (>= 1).

    Returns
    -------
    ndarray of shape (2 n_steps + 1,)
        β_n (rad) on the half-step grid.

    Examples
    --------
    >>> from gyrolib import gc
    >>> b = gc.nominal_half_steps(gc.GyrocompassParams(), 1000)
    >>> b.shape, f"{b[-1]:.3g}"
    ((2001,), '8.59e-05')
    """
    return _nominal_half_steps(check_params(params), v.check_int("n_steps", n_steps, 1))


def _nominal_half_steps(p: GyrocompassParams, n_steps: int) -> NDArray[np.float64]:
    out = np.empty(2 * n_steps + 1)
    out[0] = 0.0  # the float at rest at the sensor's null when the feedback is switched off
    _etd2_advance(*_etd2_coefficients(p), np.zeros(2), 2 * n_steps, out[1:])
    return out


class NominalIntegrator:
    """β_n of Eq. (4) from rest, advanced on demand on the half-step grid ``t = i Δt/2`` by
    the scheme of :func:`nominal_half_steps` (constant memory: a run continued chunk by chunk
    equals one run).  ``index`` is the grid index reached, ``beta`` the angle there (rad).

    Parameters
    ----------
    params : GyrocompassParams
        The model.

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import gc
    >>> p = gc.GyrocompassParams()
    >>> nom = gc.NominalIntegrator(p)
    >>> b = np.concatenate([nom.advance(700), nom.advance(1300)])
    >>> nom.index, bool(np.allclose(b, gc.nominal_half_steps(p, 1000)[1:], rtol=1e-14))
    (2000, True)
    """

    def __init__(self, params: GyrocompassParams) -> None:
        p = check_params(params)
        self.half_step = 0.5 * p.dt
        self._coef = _etd2_coefficients(p)
        self._y = np.zeros(2)
        self.index = 0

    @property
    def beta(self) -> float:
        """β_n (rad) at grid index ``index``."""
        return float(self._y[0])

    def advance(self, n: int, keep: bool = True) -> NDArray[np.float64]:
        """Advance ``n`` half steps; return β_n after each of them (``keep=False``: an empty
        array, for skipping ahead)."""
        n = v.check_int("n", n, 0)
        keep = v.check_bool("keep", keep)
        out = np.empty(n if keep else 0)
        _etd2_advance(*self._coef, self._y, n, out)
        self.index += n
        return out


# Discretization ------------------------------------------------------------------------------
def system_matrix_parts(params: GyrocompassParams
                        ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """``F(β) = F_c + sin β · E_s + cos β · E_c``: the state matrix of Eq. (8) is affine in
    ``(sin β_n, cos β_n)`` exactly; returns ``(F_c, E_s, E_c)``.

    Parameters
    ----------
    params : GyrocompassParams
        The model.

    Returns
    -------
    tuple of ndarray of shape (10, 10)

    Examples
    --------
    >>> import numpy as np
    >>> from gyrolib import gc
    >>> p = gc.GyrocompassParams()
    >>> Fc, Es, Ec = gc.system_matrix_parts(p)
    >>> bool(np.allclose(Fc + np.sin(0.3) * Es + np.cos(0.3) * Ec, gc.system_matrix(p, 0.3)))
    True
    """
    m = ContinuousModel.build(check_params(params))
    return m.Fc.copy(), m.Es.copy(), m.Ec.copy()


def affine_qd(model: ContinuousModel, betas: np.ndarray, Qc: np.ndarray | None = None
              ) -> tuple:
    """Van Loan's ``Φ``, ``Qd`` and their derivatives in ``(sin β, cos β)`` at each expansion
    point of ``betas``, for the noise intensity ``Qc`` (default the model's ``Q``)."""
    Fc, Es, Ec, G = model.Fc, model.Es, model.Ec, model.G
    Qc = model.Q if Qc is None else Qc
    dt = model.params.dt
    n = model.n
    J = betas.size
    out = [np.zeros((J, n, n)) for _ in range(6)]
    for j, b in enumerate(betas):
        F = Fc + np.sin(b) * Es + np.cos(b) * Ec
        Phi, Qd, (dPs, dPc), (dQs, dQc) = van_loan_derivatives(F, G, Qc, dt, [Es, Ec])
        for arr, val in zip(out, (Phi, dPs, dPc, Qd, dQs, dQc)):
            arr[j] = val
    return tuple(out)


def _affine_euler(model: ContinuousModel, betas: np.ndarray, Qc: np.ndarray | None = None
                  ) -> tuple:
    """Euler steps: ``Φ = I + F Δt`` is affine in (sin, cos) exactly; ``Qd = G Q Gᵀ Δt``."""
    Fc, Es, Ec, G = model.Fc, model.Es, model.Ec, model.G
    Qc = model.Q if Qc is None else Qc
    dt = model.params.dt
    N = model.n   # the state size of this model
    J = betas.size
    Phi0 = np.eye(N) + (Fc + np.sin(betas)[:, None, None] * Es
                        + np.cos(betas)[:, None, None] * Ec) * dt
    Qd0 = np.broadcast_to(G @ Qc @ G.T * dt, (J, N, N)).copy()
    zeros = np.zeros((J, N, N))
    return (Phi0, np.broadcast_to(Es * dt, (J, N, N)).copy(),
            np.broadcast_to(Ec * dt, (J, N, N)).copy(), Qd0, zeros, zeros.copy())


@compact_repr
@dataclass(frozen=True)
class GCDiscretization:
    """Paper GC discretized over ``n_steps`` steps of ``params.dt``.

    ``beta_half`` is ``β_n`` at ``t = i Δt/2``; ``betas`` the expansion points; ``model`` the
    affine discrete model; ``Gamma[j]`` the response over one step to a unit constant
    acceleration on ``Δβ''`` (for the nonlinear remainder); ``noise_factor[j]`` (n × n_w) a
    factor of ``Qd`` at expansion point ``j`` for drawing the process noise; ``method`` the
    discretization (``"van_loan"`` or ``"euler"``); ``continuous`` the continuous model it
    discretizes (:class:`gyrolib.gc.model.state_space.ContinuousModel`; default Eq. (8)'s
    for ``params``), whose ``instrument`` constants (``None``: the 10 states of Eq. (8)) are
    appended to the state, their readings after step ``k`` making
    ``model.H + model.h[k] model.H1`` with ``model.h[k]`` the nominal float angle at
    ``t_{k+1}``.
    """

    params: GyrocompassParams
    n_steps: int
    beta_half: np.ndarray
    betas: np.ndarray
    model: AffineDiscreteModel
    Gamma: np.ndarray
    noise_factor: np.ndarray
    method: str = "van_loan"
    continuous: ContinuousModel | None = None

    def __post_init__(self) -> None:
        check_params(self.params)
        if self.continuous is None:
            object.__setattr__(self, "continuous", ContinuousModel.build(self.params))
        v.check_instance("continuous", self.continuous, ContinuousModel)
        if self.continuous.params != self.params:
            raise ValueError("continuous must be the model of params")
        n = v.check_int("n_steps", self.n_steps, 1)
        v.check_ndarray("beta_half", self.beta_half, shape=(2 * n + 1,))
        J = v.check_ndarray("betas", self.betas, ndim=1).size
        v.check_instance("model", self.model, AffineDiscreteModel)
        ns = self.continuous.n
        if self.model.n != ns:
            raise ValueError(f"model must have {ns} states; got {self.model.n}")
        v.check_ndarray("Gamma", self.Gamma, shape=(J, ns))
        v.check_ndarray("noise_factor", self.noise_factor, shape=(J, ns, None))
        v.check_choice("method", self.method, DISCRETIZATIONS)

    @property
    def instrument(self):
        """The instrument constants appended to the state (``None``: Eq. (8)'s 10 states)."""
        return self.continuous.instrument

    @property
    def state_names(self) -> tuple[str, ...]:
        """The names of the model's states: Eq. (8)'s, then the instrument constants."""
        return self.continuous.state_names

    @property
    def t(self) -> NDArray[np.float64]:
        return np.arange(self.n_steps + 1) * self.params.dt

    @property
    def beta_mid(self) -> NDArray[np.float64]:
        return self.beta_half[1::2]

    def exact_step(self, k: int) -> tuple[np.ndarray, np.ndarray]:
        """``(Φ_k, Qd_k)`` at ``β_n`` of the midpoint of step ``k`` without the affine
        expansion: a full Van Loan matrix exponential (or the Euler step, with
        ``method="euler"``), the reference the affine model is tested against."""
        k = v.check_int("k", k, 0)
        if k >= self.n_steps:
            raise ValueError(f"k must be a step index in [0, {self.n_steps}); got {k}")
        cm = self.continuous
        dt = self.params.dt
        F = cm.system_matrix(float(self.beta_mid[k]))   # Eq. (8)'s F exactly on 10 states
        if self.method == "euler":
            return np.eye(F.shape[0]) + F * dt, cm.G @ cm.Q @ cm.G.T * dt
        return van_loan(F, cm.G, cm.Q, dt)


def discretize(params: GyrocompassParams, t_end: float = 100.0, *,
               method: str = "van_loan", instrument: bool = False) -> GCDiscretization:
    """Discretize paper GC's model, Eq. (8), over ``[0, t_end]`` at ``params.dt``.

    Parameters
    ----------
    params : GyrocompassParams
        The model.
    t_end : float, default 100.0
        Length of the run (s), a positive multiple of ``params.dt``.
    method : {"van_loan", "euler"}, default "van_loan"
        ``"van_loan"``: exact ``Φ = exp(F Δt)`` and ``Qd`` for ``F`` frozen at each step's
        midpoint {cite:p}`VanLoan1978`; ``"euler"``: ``Φ = I + F Δt``, ``Qd = G Q Gᵀ Δt``.
    instrument : bool, default False
        Append the instrument constants that are ON for ``params``
        (:func:`gyrolib.gc.instrument_model`) to the state; at the default priors (0) there
        are none and the model is Eq. (8)'s either way.

    Returns
    -------
    GCDiscretization
        The affine discrete model of every step, the nominal motion on the half-step grid.

    Examples
    --------
    >>> from gyrolib import gc
    >>> d = gc.discretize(gc.GyrocompassParams(), 1.0)
    >>> d.n_steps, f"{d.beta_half[-1] * 1e3:.3f} mrad"
    (1000, '0.086 mrad')
    >>> d = gc.discretize(gc.GyrocompassParams(sigma_as_offset=1e-5), 1.0, instrument=True)
    >>> d.state_names[10:], d.model.n
    (('angle_offset',), 11)
    """
    p = check_params(params)
    n_steps = steps_in(p, t_end)
    v.check_choice("method", method, DISCRETIZATIONS)
    instrument = v.check_bool("instrument", instrument)
    cm = ContinuousModel.with_instruments(p) if instrument else ContinuousModel.build(p)
    return discretize_steps(cm, n_steps, method)


def discretize_steps(cm: ContinuousModel, n_steps: int, method: str) -> GCDiscretization:
    """:func:`discretize` of the continuous model ``cm`` on arguments already checked by the
    public entry point."""
    p = cm.params
    inst = cm.instrument
    beta_half = _nominal_half_steps(p, n_steps)
    bm = beta_half[1::2]
    idx = np.rint(bm / SEGMENT).astype(np.int64)
    uniq, seg = np.unique(idx, return_inverse=True)
    betas = uniq * SEGMENT
    affine = _affine_euler if method == "euler" else affine_qd
    Phi0, PhiA, PhiB, Qd0, QdA, QdB = affine(cm, betas)
    model = AffineDiscreteModel(
        seg=seg.astype(np.int64).ravel(), a=np.sin(bm) - np.sin(betas)[seg].ravel(),
        b=np.cos(bm) - np.cos(betas)[seg].ravel(), Phi0=Phi0, PhiA=PhiA, PhiB=PhiB,
        Qd0=Qd0, QdA=QdA, QdB=QdB, H=cm.H0.copy(), r=np.diag(cm.R).copy(),
        H1=None if inst is None else cm.H1.copy(),
        h=None if inst is None else beta_half[2::2].copy())
    n = cm.n
    Gamma = np.zeros((betas.size, n))
    factors = []
    for j, b in enumerate(betas):
        F = cm.Fc + np.sin(b) * cm.Es + np.cos(b) * cm.Ec
        M = np.zeros((n + 1, n + 1))
        M[:n, :n] = F * p.dt
        M[1, n] = p.dt
        Gamma[j] = M[:n, n] if method == "euler" else scipy.linalg.expm(M)[:n, n]
        factors.append(covariance_factor(Qd0[j]))
    nz = np.any(np.abs(np.array(factors)) > 0, axis=(0, 1))
    noise_factor = np.ascontiguousarray(np.array(factors)[:, :, nz])
    return GCDiscretization(params=p, n_steps=n_steps, beta_half=beta_half, betas=betas,
                            model=model, Gamma=Gamma, noise_factor=noise_factor,
                            method=method, continuous=cm)


#: The affine models :func:`kept_affine_model` keeps, at most ``_affine_kept_max`` (a 100-s
#: model holds about 3 MB); lower-case: a cache's size, not a model constant of the key.
_affine_kept: dict[tuple, AffineDiscreteModel] = {}
_affine_kept_max = 8


def _dynamics_key(cm: ContinuousModel, n_steps: int, method: str) -> tuple:
    """Everything :func:`discretize_steps` reads to build the steps' ``Φ`` and ``Qd``: the
    nominal motion's constants (:func:`_etd2_coefficients`), the step, the state matrix's
    parts, ``G`` and ``Q``; not the measurement matrices, their noise or the prior."""
    p = cm.params
    arrays = (cm.Fc, cm.Es, cm.Ec, cm.G, cm.Q)
    return (n_steps, method, cm.n, p.dt, p.f, p.I, p.H, p.Omega_h,
            *((a.shape, a.tobytes()) for a in arrays))


def kept_affine_model(p: GyrocompassParams, n_steps: int,
                      method: str = "van_loan") -> AffineDiscreteModel:
    """``kept_discretization(p, n_steps, method).model`` with the discretization shared
    between parameters that differ only where it does not look (the measurement matrices,
    their noise ``R`` and the prior ``P(0)``: ``C_as``, ``C_incl``, the priors of ω_gc, ψ
    and the tilts): the steps' ``Φ`` and ``Qd`` are those of the first such parameters, to
    the bit (the same inputs), and ``H``, ``r`` and ``H1`` are ``p``'s own.  For the
    library's read-only use, as :func:`kept_discretization`.

    Examples
    --------
    >>> import dataclasses
    >>> from gyrolib import gc
    >>> p = gc.GyrocompassParams()
    >>> a = kept_affine_model(p, 10)
    >>> b = kept_affine_model(dataclasses.replace(p, C_as=2 * p.C_as), 10)
    >>> b.Phi0 is a.Phi0, bool(b.r[0] == 2 * a.r[0])
    (True, True)
    """
    cm = ContinuousModel.with_instruments(p)
    key = _dynamics_key(cm, n_steps, method)
    base = _affine_kept.get(key)
    if base is None:
        base = discretize_steps(cm, n_steps, method).model
        while len(_affine_kept) >= _affine_kept_max:
            _affine_kept.pop(next(iter(_affine_kept)))
        _affine_kept[key] = base
    H1 = None if cm.instrument is None else cm.H1.copy()
    return dataclasses.replace(base, H=cm.H0.copy(), r=np.diag(cm.R).copy(), H1=H1,
                               h=base.h if H1 is not None else None)


kept_affine_model.cache_clear = _affine_kept.clear   # as the functools memos are emptied


@functools.lru_cache(maxsize=32)
def kept_discretization(p: GyrocompassParams, n_steps: int,
                        method: str = "van_loan") -> GCDiscretization:
    """:func:`discretize_steps` of the continuous model with the instrument constants that
    are ON for ``p`` (:meth:`ContinuousModel.with_instruments`; none: Eq. (8)), kept per
    arguments for the library's own read-only use: a claim's margins read the same model
    more than once (the race's GC time and the trend's covariance analysis at the same
    parameters, over the same 100 s).  Its arrays are shared: not for callers that hand
    them on (:func:`discretize` makes its own); ``.continuous`` is the model it used."""
    return discretize_steps(ContinuousModel.with_instruments(p), n_steps, method)
