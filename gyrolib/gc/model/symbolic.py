"""Symbolic derivation of paper GC's model, Eqs. (1)–(8), with sympy.

The model chapter shows these derivations and the tests compare :mod:`gyrolib.gc`
with them, so both use one source:

* :func:`gyroscopic_torque` (Eq. (1)) and :func:`earth_rate_in_base` (Eq. (2) and the
  horizontal Earth rate) give the torques about the float's output axis;
  :func:`gyrocompass_equation` assembles Eq. (3) from them;
* :func:`taylor_linearization` expands Eq. (3) about the nominal motion to first order in a
  bookkeeping parameter ``ε``: order 0 is the nominal equation (4), order 1 the linearized
  equation (5);
* :func:`state_space` writes Eq. (5) and the shaping filters (6), (7) in Cauchy form and
  returns the matrices ``F``, ``G``, ``D`` of Eq. (8) as Jacobians;
* :func:`paper_listing` holds the matrix entries exactly as the paper prints them, and
  :func:`compare_with_paper` compares entry by entry;
* :func:`relabelling` is the signed permutation that maps one reading of the vertical-rate
  coupling onto the other;
* :func:`shaping_filter` and :func:`lyapunov_variance` give the shaping filters' transfer
  functions and stationary variances in closed form;
* :func:`numeric_matrices` evaluates the symbolic ``F``, ``G``, ``D`` for a
  :class:`~gyrolib.gc.GyrocompassParams` (lambdified).

Geometry used for Eq. (1)–(3) (paper GC, Figure 1, whose drawing did not survive the text
extraction): the base frame ``Oxyz`` has ``y`` along the gyro's input axis at ``β = 0`` and
``z`` along the output axis, about which the float turns by ``β``; the horizontal Earth rate
``Ω_h`` lies in the ``xy`` plane at the angle ``ψ`` from ``y``.  This is the only geometry in
which the printed ``cos(β − ψ)`` of Eq. (1) arises (both angles are measured in the plane in
which the float's input axis ``η`` turns).

sympy is the ``book`` extra's (``pip install 'gyrolib[book]'``): the derivations are the
book's; the numeric library does not need them.  Without it, importing this module says so.
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass, fields
from functools import cache
from typing import Final

import numpy as np

from gyrolib import _validation as v
from gyrolib._optional import optional

with optional("sympy", "book", "gyrolib.gc.model.symbolic"):
    import sympy as sp
from gyrolib.gc.model.params import check_params

__all__ = [
    "COUPLINGS",
    "NOISE_READINGS",
    "STATE_ORDERS",
    "SYMBOLS",
    "ModelSymbols",
    "ShapingFilterSym",
    "StateSpaceSym",
    "cauchy_form_latex",
    "compare_with_paper",
    "display_form",
    "earth_rate_in_base",
    "float_input_axis",
    "gyrocompass_equation",
    "gyroscopic_torque",
    "lyapunov_variance",
    "measurement_equations",
    "numeric_matrices",
    "paper_listing",
    "parameter_values",
    "relabelling",
    "shaping_filter",
    "state_space",
    "taylor_linearization",
    "to_latex",
    "to_latex_aligned",
]


#: Readings of the vertical-rate coupling: ``"eq5"`` as in Eqs. (3), (5) (γ carries cos β),
#: ``"printed_F"`` as in the printed F listing (δ carries cos β); see :func:`earth_rate_in_base`.
COUPLINGS: Final[tuple[str, ...]] = ("eq5", "printed_F")


#: State orders: ``"corrected"`` (X1 = Δβ, X2 = Δβ', gyrolib's order) or ``"printed"``
#: (X1 = Δβ', X2 = Δβ, as the paper labels them).
STATE_ORDERS: Final[tuple[str, ...]] = ("corrected", "printed")


#: Readings of where the white noise enters the shaping filters (6) and (7).
NOISE_READINGS: Final[dict[str, tuple[str, ...]]] = {
    "vibration": ("paper", "second_line_only"),
    "drift": ("paper", "both_lines"),
}


@dataclass(frozen=True)
class ModelSymbols:
    """The sympy symbols of paper GC's model (all real; physical constants positive)."""

    t: sp.Symbol
    eps: sp.Symbol
    I: sp.Symbol
    H: sp.Symbol
    f: sp.Symbol
    Omega_h: sp.Symbol
    Omega_v: sp.Symbol
    g: sp.Symbol
    omega_ub: sp.Symbol
    alpha1: sp.Symbol
    xi1: sp.Symbol
    sigma1_sq: sp.Symbol
    alpha2: sp.Symbol
    xi2: sp.Symbol
    sigma2_sq: sp.Symbol
    psi: sp.Symbol
    delta: sp.Symbol
    gamma: sp.Symbol
    omega_gc: sp.Symbol
    omega_rnd: sp.Symbol
    N1: sp.Symbol
    N2: sp.Symbol
    N3: sp.Symbol
    N4: sp.Symbol
    w1: sp.Symbol
    w2: sp.Symbol
    beta: sp.Function
    beta_n: sp.Function
    dbeta: sp.Function
    beta_n_sym: sp.Symbol
    x_dbeta: sp.Symbol
    x_dbeta_dot: sp.Symbol
    s: sp.Symbol

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if not isinstance(value, sp.Symbol | sp.core.function.UndefinedFunction):
                raise TypeError(f"{f.name} must be a sympy Symbol or undefined Function; "
                                f"got {type(value).__name__}")


def _make_symbols() -> ModelSymbols:
    pos = {"positive": True}
    real = {"real": True}
    return ModelSymbols(
        t=sp.Symbol("t", **real),
        eps=sp.Symbol("epsilon", **real),
        I=sp.Symbol("I", **pos),
        H=sp.Symbol("H", **pos),
        f=sp.Symbol("f", **pos),
        Omega_h=sp.Symbol("Omega_h", **pos),
        Omega_v=sp.Symbol("Omega_v", **pos),
        g=sp.Symbol("g", **pos),
        omega_ub=sp.Symbol("omega_ub", **real),
        alpha1=sp.Symbol("alpha_1", **pos),
        xi1=sp.Symbol("xi_1", **pos),
        sigma1_sq=sp.Symbol("sigma_1^2", **pos),
        alpha2=sp.Symbol("alpha_2", **pos),
        xi2=sp.Symbol("xi_2", **pos),
        sigma2_sq=sp.Symbol("sigma_2^2", **pos),
        psi=sp.Symbol("psi", **real),
        delta=sp.Symbol("delta", **real),
        gamma=sp.Symbol("gamma", **real),
        omega_gc=sp.Symbol("omega_gc", **real),
        omega_rnd=sp.Symbol("omega_rnd", **real),
        N1=sp.Symbol("N_1", **real),
        N2=sp.Symbol("N_2", **real),
        N3=sp.Symbol("N_3", **real),
        N4=sp.Symbol("N_4", **real),
        w1=sp.Symbol("w_1", **real),
        w2=sp.Symbol("w_2", **real),
        beta=sp.Function("beta", real=True),
        beta_n=sp.Function("beta_n", real=True),
        dbeta=sp.Function(r"\Delta\beta", real=True),
        beta_n_sym=sp.Symbol("beta_n", **real),
        x_dbeta=sp.Symbol(r"\Delta\beta", **real),
        x_dbeta_dot=sp.Symbol(r"\Delta\dot{\beta}", **real),
        s=sp.Symbol("s"),
    )


#: The one set of symbols every function of this module uses.
SYMBOLS: Final[ModelSymbols] = _make_symbols()


def _check_coupling(coupling: str) -> str:
    return v.check_choice("coupling", coupling, COUPLINGS)


def _check_sign(sign: object) -> int:
    if isinstance(sign, bool) or not isinstance(sign, numbers.Real) or sign not in (1, -1):
        raise ValueError(f"sign must be +1 or -1; got {sign!r}")
    return int(sign)


def _check_angle(name: str, value: object) -> sp.Expr:
    """A sympy expression or a finite real number (an angle, symbolic or numeric)."""
    if isinstance(value, sp.Expr):
        return value
    x = v.check_real(name, value)
    return sp.Integer(int(value)) if isinstance(value, numbers.Integral) else sp.Float(x)


def _check_matrix(name: str, value: object, rows: int | None = None,
                  cols: int | None = None) -> sp.MatrixBase:
    """A sympy matrix, optionally with a fixed number of rows or columns."""
    v.check_instance(name, value, sp.MatrixBase)
    if (rows is not None and value.rows != rows) or (cols is not None and value.cols != cols):
        want = ("any" if rows is None else rows, "any" if cols is None else cols)
        raise ValueError(f"{name} must have shape {want}; got {value.shape}")
    return value


def display_form(expr: object) -> object:
    """``expr`` with the functions of time ``β(t)``, ``β_n(t)``, ``Δβ(t)`` and their first two
    derivatives replaced by plain (dotted) symbols, for compact display.  Lists and tuples
    are converted element by element; other non-sympy objects are returned unchanged.

    Parameters
    ----------
    expr : sympy expression, list or tuple
        What to display.

    Returns
    -------
    object
        ``expr`` with plain symbols for the functions of time.

    Examples
    --------
    >>> from gyrolib.gc.model import symbolic
    >>> S = symbolic.SYMBOLS
    >>> symbolic.display_form(S.beta(S.t).diff(S.t))
    \\dot\\beta
    """
    if isinstance(expr, list | tuple):
        return type(expr)(display_form(e) for e in expr)
    if not isinstance(expr, sp.Basic):
        return expr
    S = SYMBOLS
    t = S.t
    reps: dict[sp.Basic, sp.Basic] = {}
    for fn, (b0, b1, b2) in ((S.beta, (r"\beta", r"\dot\beta", r"\ddot\beta")),
                             (S.beta_n, (r"\beta_n", r"\dot\beta_n", r"\ddot\beta_n")),
                             (S.dbeta, (r"\Delta\beta", r"\Delta\dot\beta",
                                        r"\Delta\ddot\beta"))):
        f = fn(t)
        reps[f.diff(t, 2)] = sp.Symbol(b2, real=True)
        reps[f.diff(t)] = sp.Symbol(b1, real=True)
        reps[f] = sp.Symbol(b0, real=True)
    return expr.xreplace(reps)


def to_latex(expr: object, lhs: str | None = None) -> str:
    r"""LaTeX of :func:`display_form` of ``expr``, optionally as ``lhs = expr``.

    Examples
    --------
    >>> from gyrolib.gc.model import symbolic
    >>> S = symbolic.SYMBOLS
    >>> print(symbolic.to_latex(S.beta(S.t).diff(S.t), r"\omega"))
    \omega = \dot\beta
    """
    body = sp.latex(display_form(expr))
    return body if lhs is None else f"{v.check_str('lhs', lhs)} = {body}"


def to_latex_aligned(lhs: object, rhs: object, per_line: int = 3) -> str:
    r"""LaTeX of ``lhs = rhs`` in an ``aligned`` block, the expanded right side broken into
    lines of ``per_line`` terms (for the long rows of Eqs. (3), (5) and (8)).

    Examples
    --------
    >>> import sympy as sp
    >>> from gyrolib.gc.model import symbolic
    >>> a, b, c = sp.symbols("a b c")
    >>> print(symbolic.to_latex_aligned("y", a + b - c, per_line=2))
    \begin{aligned} & y \\ &= a + b \\ &\quad - c\end{aligned}
    """
    per_line = v.check_int("per_line", per_line, 1)
    lhs_tex = lhs if isinstance(lhs, str) else sp.latex(display_form(lhs))
    return (r"\begin{aligned} & " + lhs_tex + r" \\ &= " + _tex_sum(rhs, per_line)
            + r"\end{aligned}")


def _tex_sum(expr: object, per_line: int) -> str:
    terms = sp.Add.make_args(sp.expand(display_form(expr)))
    lines = []
    for i in range(0, len(terms), per_line):
        chunk = sp.latex(sp.Add(*terms[i:i + per_line]))
        lines.append(chunk if i == 0 or chunk.startswith("-") else "+ " + chunk)
    return r" \\ &\quad ".join(lines)


def cauchy_form_latex(model: StateSpaceSym, per_line: int = 4) -> str:
    """LaTeX of the first-order system of Eq. (8), one row per state (``aligned``); the
    long Δβ'' row is multiplied by ``I`` and broken into lines of ``per_line`` terms.

    Parameters
    ----------
    model : StateSpaceSym
    per_line : int, default 4
        Terms per line of the long row.

    Returns
    -------
    str

    Examples
    --------
    >>> from gyrolib.gc.model import symbolic
    >>> symbolic.cauchy_form_latex(symbolic.state_space()).startswith(r"\\begin{aligned}")
    True
    """
    per_line = v.check_int("per_line", per_line, 1)
    v.check_instance("model", model, StateSpaceSym)
    S = SYMBOLS
    rows = []
    for x, f in zip(model.x, model.rhs):
        if x == S.x_dbeta_dot:
            rows.append(r"I\,\Delta\ddot\beta &= " + _tex_sum(S.I * f, per_line))
        elif x == S.x_dbeta:
            rows.append(r"\Delta\dot\beta &= " + sp.latex(f))
        else:
            rows.append(r"\dot{" + sp.latex(x) + "} &= " + sp.latex(f))
    return r"\begin{aligned}" + r" \\ ".join(rows) + r"\end{aligned}"


# Geometry and torques, Eqs. (1)–(3) -----------------------------------------------------------
def float_input_axis(beta: sp.Expr) -> sp.Matrix:
    """Unit vector of the float's input axis ``η`` in the base frame ``Oxyz``.

    The float turns by ``β`` about the output axis ``z``; at ``β = 0`` ``η`` is ``y``, and a
    positive ``β`` turns ``η`` from ``y`` towards ``x``: ``η = (sin β, cos β, 0)``.

    Parameters
    ----------
    beta : sympy expression
        The float angle β.

    Returns
    -------
    sympy.Matrix
        η in ``Oxyz`` (3×1).

    Examples
    --------
    >>> from gyrolib.gc.model import symbolic
    >>> S = symbolic.SYMBOLS
    >>> symbolic.float_input_axis(S.beta(S.t)).T
    Matrix([[sin(beta(t)), cos(beta(t)), 0]])
    """
    beta = _check_angle("beta", beta)
    Rz = sp.Matrix([[sp.cos(beta), sp.sin(beta), 0],
                    [-sp.sin(beta), sp.cos(beta), 0],
                    [0, 0, 1]])  # rotation by −β about z
    return Rz * sp.Matrix([0, 1, 0])


def earth_rate_in_base(coupling: str = "eq5") -> tuple[sp.Matrix, sp.Matrix]:
    """Horizontal and vertical Earth-rate vectors in the base frame, to first order in the
    tilts (paper GC, Eq. (2) and the definition of ``ψ``).

    The horizontal rate ``Ω_h`` lies at ``ψ`` from the ``y`` axis (towards ``x``, like β).
    The vertical rate ``Ω_v`` gets in-plane components from the tilts.  Eq. (2) names them
    ``ω_y = −Ω_v δ``, ``ω_z = Ω_v γ``; but ``z`` is the output axis, and a rate about it gives
    no gyroscopic torque (``η`` has no ``z`` component), so one of the two labels must stand
    for the in-plane axis ``x``.  Keeping the printed signs, the two readings are:

    * ``"printed_F"``: ``y`` is the input axis as printed, ``z`` stands for ``x``:
      ``ω_y = −Ω_v δ``, ``ω_x = Ω_v γ``; this gives the paper's F listing (δ carries cos β);
    * ``"eq5"``: ``y`` stands for ``x`` and ``z`` for ``y``: ``ω_x = −Ω_v δ``,
      ``ω_y = Ω_v γ``; this gives Eqs. (3) and (5) (γ carries cos β).

    Parameters
    ----------
    coupling : {"eq5", "printed_F"}, default "eq5"
        The reading of the axis labels of Eq. (2).

    Returns
    -------
    (sympy.Matrix, sympy.Matrix)
        ``Ω_h`` and ``Ω_v`` in ``Oxyz`` (3×1 each).

    Examples
    --------
    >>> from gyrolib.gc.model import symbolic
    >>> omega_h, omega_v = symbolic.earth_rate_in_base("eq5")
    >>> omega_v.T
    Matrix([[-Omega_v*delta, Omega_v*gamma, Omega_v]])
    """
    S = SYMBOLS
    coupling = _check_coupling(coupling)
    omega_h = S.Omega_h * sp.Matrix([sp.sin(S.psi), sp.cos(S.psi), 0])
    if coupling == "printed_F":
        omega_v = S.Omega_v * sp.Matrix([S.gamma, -S.delta, 1])
    else:
        omega_v = S.Omega_v * sp.Matrix([-S.delta, S.gamma, 1])
    return omega_h, omega_v


def gyroscopic_torque(beta: sp.Expr, sign: int = 1) -> sp.Expr:
    """Gyroscopic torque of the horizontal Earth rate about the output axis, paper GC Eq. (1):
    ``M_g = sign · H (Ω_h · η) = sign · H Ω_h cos(β − ψ)``.

    The paper's own equations (3)–(5) use ``sign = +1``; the extracted text of Eq. (1) shows a
    minus sign (``sign = −1``), discussed in the model chapter.

    Parameters
    ----------
    beta : sympy expression
        The float angle β.
    sign : {1, -1}, default 1
        The sign of Eq. (1).

    Returns
    -------
    sympy expression

    Examples
    --------
    >>> from gyrolib.gc.model import symbolic
    >>> S = symbolic.SYMBOLS
    >>> symbolic.gyroscopic_torque(S.beta(S.t))
    H*Omega_h*cos(psi - beta(t))
    """
    S = SYMBOLS
    sign = _check_sign(sign)
    beta = _check_angle("beta", beta)
    omega_h, _ = earth_rate_in_base()
    return sp.simplify(sign * S.H * (omega_h.T * float_input_axis(beta))[0, 0])


def vertical_rate_torque(beta: sp.Expr, coupling: str = "eq5") -> sp.Expr:
    """Gyroscopic torque of the tilted vertical Earth rate, ``H (ω_v · η)`` (Eqs. (2), (3)).

    Parameters
    ----------
    beta : sympy expression
        The float angle β.
    coupling : {"eq5", "printed_F"}, default "eq5"
        The reading of Eq. (2).

    Returns
    -------
    sympy expression

    Examples
    --------
    >>> from gyrolib.gc.model import symbolic
    >>> S = symbolic.SYMBOLS
    >>> symbolic.vertical_rate_torque(S.beta(S.t), "eq5")
    -H*Omega_v*delta*sin(beta(t)) + H*Omega_v*gamma*cos(beta(t))
    """
    S = SYMBOLS
    beta = _check_angle("beta", beta)
    _, omega_v = earth_rate_in_base(coupling)
    return sp.expand(S.H * (omega_v.T * float_input_axis(beta))[0, 0])


def gyrocompass_equation(*, sign: int = 1, coupling: str = "eq5",
                         unbalance: bool = True) -> sp.Eq:
    """Nonlinear gyrocompass equation, paper GC Eq. (3), assembled from the torques.

    ``I β'' + f β' = M_g + H(ω_v·η) + H ω_gc + H ω_rnd [+ (H ω_ub/g) N1]``.  The last term is
    the unbalance torque of the vibration acceleration ``N1`` (text after Eq. (6)); the paper
    leaves it out of (3) but puts it in ``F(2,7)``.

    Parameters
    ----------
    sign : {1, -1}, default 1
        The sign of Eq. (1).
    coupling : {"eq5", "printed_F"}, default "eq5"
        The reading of Eq. (2).
    unbalance : bool, default True
        Add the unbalance torque ``H ω_ub N1 / g``.

    Returns
    -------
    sympy.Eq
        ``I β'' + f β' = torques``.

    Examples
    --------
    >>> from gyrolib.gc.model import symbolic
    >>> eq = symbolic.gyrocompass_equation(unbalance=False)
    >>> len(eq.rhs.args)   # Eq. (3): five torques
    5
    """
    S = SYMBOLS
    sign = _check_sign(sign)
    coupling = _check_coupling(coupling)
    unbalance = v.check_bool("unbalance", unbalance)
    b = S.beta(S.t)
    rhs = (gyroscopic_torque(b, sign) + vertical_rate_torque(b, coupling)
           + S.H * S.omega_gc + S.H * S.omega_rnd)
    if unbalance:
        rhs += S.H * S.omega_ub / S.g * S.N1
    lhs = S.I * b.diff(S.t, 2) + S.f * b.diff(S.t)
    return sp.Eq(lhs, rhs)


def nominal_equation(sign: int = 1) -> sp.Eq:
    """Nominal equation, paper GC Eq. (4): ``I β_n'' + f β_n' = sign · H Ω_h cos β_n``.

    Parameters
    ----------
    sign : {1, -1}, default 1
        The sign of Eq. (1).

    Returns
    -------
    sympy.Eq

    Examples
    --------
    >>> from gyrolib.gc.model import symbolic
    >>> symbolic.nominal_equation().rhs
    H*Omega_h*cos(beta_n(t))
    """
    S = SYMBOLS
    bn = S.beta_n(S.t)
    return sp.Eq(S.I * bn.diff(S.t, 2) + S.f * bn.diff(S.t),
                 gyroscopic_torque(bn, sign).subs(S.psi, 0))


# Taylor linearization, Eqs. (4), (5) ----------------------------------------------------------
@dataclass(frozen=True)
class Linearization:
    """Orders 0 and 1 in ``ε`` of Eq. (3) written as ``lhs − rhs = 0``."""

    order0: sp.Expr
    order1: sp.Expr

    def nominal(self) -> sp.Eq:
        """Order 0 as an equation in ``β_n`` (Eq. (4))."""
        return _as_equation(self.order0)

    def linear(self) -> sp.Eq:
        """Order 1 as an equation in ``Δβ`` (Eq. (5)), derivative terms on the left."""
        return _as_equation(self.order1)


def _as_equation(expr: sp.Expr) -> sp.Eq:
    """Split ``expr = 0`` into ``lhs = rhs`` with the unknown function's terms on the left."""
    S = SYMBOLS
    expr = sp.expand(expr)
    left = sp.Add(*[term for term in sp.Add.make_args(expr) if term.has(S.dbeta(S.t))])
    if left == 0:  # order 0: derivative terms of β_n on the left
        left = sp.Add(*[term for term in sp.Add.make_args(expr) if term.has(sp.Derivative)])
    return sp.Eq(sp.collect(left, [S.I, S.f, S.H]), sp.collect(left - expr, [S.H]))


def taylor_linearization(*, sign: int = 1, coupling: str = "eq5",
                         unbalance: bool = True) -> Linearization:
    """Linearize Eq. (3) about the nominal motion by a Taylor expansion in ``ε``.

    Substitute ``β = β_n + ε Δβ`` and scale every small quantity (``ψ``, ``δ``, ``γ``,
    ``ω_gc``, ``ω_rnd``, ``N1``) by ``ε``; sympy's ``series`` in ``ε`` to first order gives
    the nominal equation (order 0, paper GC Eq. (4)) and the linearized equation (order 1,
    Eq. (5)).  Cached per (validated) argument set.

    Parameters
    ----------
    sign : {1, -1}, default 1
        The sign of Eq. (1).
    coupling : {"eq5", "printed_F"}, default "eq5"
        The reading of Eq. (2).
    unbalance : bool, default True
        Include the unbalance torque.

    Returns
    -------
    Linearization
        ``order0`` (Eq. (4)) and ``order1`` (Eq. (5)) as ``lhs − rhs``.

    Examples
    --------
    >>> from gyrolib.gc.model import symbolic
    >>> symbolic.taylor_linearization().nominal().rhs
    H*Omega_h*cos(beta_n(t))
    """
    return _taylor_linearization(_check_sign(sign), _check_coupling(coupling),
                                 v.check_bool("unbalance", unbalance))


@cache
def _taylor_linearization(sign: int, coupling: str, unbalance: bool) -> Linearization:
    S = SYMBOLS
    eq = gyrocompass_equation(sign=sign, coupling=coupling, unbalance=unbalance)
    expr = eq.lhs - eq.rhs
    small = {S.psi: S.eps * S.psi, S.delta: S.eps * S.delta, S.gamma: S.eps * S.gamma,
             S.omega_gc: S.eps * S.omega_gc, S.omega_rnd: S.eps * S.omega_rnd,
             S.N1: S.eps * S.N1}
    expr = expr.subs(small, simultaneous=True)
    expr = expr.subs(S.beta(S.t), S.beta_n(S.t) + S.eps * S.dbeta(S.t)).doit()
    series = sp.series(expr, S.eps, 0, 2).removeO()
    series = sp.expand(series)
    return Linearization(order0=series.coeff(S.eps, 0),
                         order1=sp.expand(series.coeff(S.eps, 1)))


# Shaping filters, Eqs. (6), (7) ---------------------------------------------------------------
@dataclass(frozen=True)
class ShapingFilterSym:
    """A second-order shaping filter ``x' = A x + B w``, ``y = C x``, intensity ``Q``."""

    A: sp.Matrix
    B: sp.Matrix
    C: sp.Matrix
    Q: sp.Expr

    def __post_init__(self) -> None:
        _check_matrix("A", self.A, 2, 2)
        _check_matrix("B", self.B, 2, 1)
        _check_matrix("C", self.C, 1, 2)
        v.check_instance("Q", self.Q, sp.Expr)

    def transfer_function(self) -> sp.Expr:
        """``C (sI − A)⁻¹ B`` as a rational function of ``s``."""
        s = SYMBOLS.s
        return sp.factor(sp.simplify((self.C * (s * sp.eye(2) - self.A).inv() * self.B)[0, 0]))

    def output_variance(self) -> sp.Expr:
        """Stationary variance of the output, from the Lyapunov equation."""
        return lyapunov_variance(self.A, self.B, self.C, self.Q)


def shaping_filter(which: str, reading: str = "paper") -> ShapingFilterSym:
    """Symbolic shaping filter of paper GC: ``"vibration"`` (Eq. (6)) or ``"drift"`` (Eq. (7)).

    ``reading`` places the white noise: ``"paper"`` is the reading consistent with the
    printed G (``G(7,1) = 1``, ``G(8,1) = α1 − 2ξ1α1``; ``G(10,2) = 1``).  The alternatives are
    ``"second_line_only"`` for Eq. (6) (the noise only in the ``N2`` line) and
    ``"both_lines"`` for Eq. (7) (the extraction shows a noise symbol on both lines).

    Parameters
    ----------
    which : {"vibration", "drift"}
        Eq. (6) or Eq. (7).
    reading : str, default "paper"
        Where the white noise enters (:data:`NOISE_READINGS`).

    Returns
    -------
    ShapingFilterSym

    Examples
    --------
    >>> from gyrolib.gc.model import symbolic
    >>> symbolic.shaping_filter("drift").output_variance()
    sigma_2^2
    """
    S = SYMBOLS
    which = v.check_choice("which", which, tuple(NOISE_READINGS))
    reading = v.check_choice("reading", reading, NOISE_READINGS[which])
    if which == "vibration":
        a, xi = S.alpha1, S.xi1
        B = sp.Matrix([1, a - 2 * xi * a]) if reading == "paper" else sp.Matrix(
            [0, a - 2 * xi * a])
        Q = 2 * xi * a * S.sigma1_sq
    else:
        a, xi = S.alpha2, S.xi2
        B = sp.Matrix([0, 1]) if reading == "paper" else sp.Matrix([1, 1])
        Q = 4 * xi * a**3 * S.sigma2_sq
    A = sp.Matrix([[0, 1], [-a**2, -2 * xi * a]])
    return ShapingFilterSym(A=A, B=B, C=sp.Matrix([[1, 0]]), Q=Q)


def lyapunov_variance(A: sp.Matrix, B: sp.Matrix, C: sp.Matrix, Q: sp.Expr) -> sp.Expr:
    """Solve ``A P + P Aᵀ + B Q Bᵀ = 0`` symbolically (P symmetric) and return ``C P Cᵀ``.

    ``A`` n×n, ``B`` n×k, ``C`` 1×n (sympy matrices); ``Q`` a sympy expression or number
    (k = 1) or a k×k sympy matrix.

    Parameters
    ----------
    A, B, C : sympy.Matrix
        State, input and output matrices (A Hurwitz).
    Q : sympy expression
        White-noise intensity.

    Returns
    -------
    sympy expression
        ``C P Cᵀ`` with ``A P + P Aᵀ + B Q Bᵀ = 0``.

    Examples
    --------
    >>> import sympy as sp
    >>> from gyrolib.gc.model import symbolic
    >>> a, q = sp.symbols("a q", positive=True)
    >>> symbolic.lyapunov_variance(sp.Matrix([[-a]]), sp.Matrix([[1]]), sp.Matrix([[1]]), q)
    q/(2*a)
    """
    A = _check_matrix("A", A)
    n = A.rows
    if A.cols != n or n == 0:
        raise ValueError(f"A must be a non-empty square matrix; got shape {A.shape}")
    B = _check_matrix("B", B, n)
    C = _check_matrix("C", C, 1, n)
    if isinstance(Q, sp.MatrixBase):
        _check_matrix("Q", Q, B.cols, B.cols)
    elif B.cols != 1:
        raise ValueError(f"Q must be a {B.cols}x{B.cols} sympy matrix when B has {B.cols} "
                         "columns")
    elif not isinstance(Q, sp.Expr):
        v.check_real("Q", Q)
    p = sp.symbols(f"p0:{n * (n + 1) // 2}")
    P = sp.zeros(n, n)
    k = 0
    for i in range(n):
        for j in range(i, n):
            P[i, j] = P[j, i] = p[k]
            k += 1
    lyap = A * P + P * A.T + B * Q * B.T
    sol = sp.solve([lyap[i, j] for i in range(n) for j in range(i, n)], p, dict=True)
    if len(sol) != 1:  # pragma: no cover - a Hurwitz A gives a unique solution
        raise ValueError("the Lyapunov equation has no unique solution")
    return sp.simplify((C * P.subs(sol[0]) * C.T)[0, 0])


# Cauchy form and the matrices of Eq. (8) ------------------------------------------------------
@dataclass(frozen=True)
class StateSpaceSym:
    """Paper GC's Eq. (8) in symbols: ``x' = F x + G w``, ``z = D x``."""

    x: tuple[sp.Symbol, ...]
    w: tuple[sp.Symbol, ...]
    rhs: sp.ImmutableMatrix
    F: sp.ImmutableMatrix
    G: sp.ImmutableMatrix
    D: sp.ImmutableMatrix
    coupling: str
    state_order: str

    def __post_init__(self) -> None:
        _check_coupling(self.coupling)
        v.check_choice("state_order", self.state_order, STATE_ORDERS)
        for name in ("rhs", "F", "G", "D"):
            _check_matrix(name, getattr(self, name))


def measurement_equations() -> sp.Matrix:
    """Measurements of Eq. (8): the angle sensor reads ``Δβ`` (β minus the stored ``β_n``);
    inclinometer y reads ``g δ + N1``, inclinometer z reads ``g γ + N1``.

    Returns
    -------
    sympy.Matrix
        The three sensor readings (3×1) in the state symbols.

    Examples
    --------
    >>> from gyrolib.gc.model import symbolic
    >>> symbolic.measurement_equations()[1]
    N_1 + delta*g
    """
    S = SYMBOLS
    return sp.Matrix([S.x_dbeta, S.g * S.delta + S.N1, S.g * S.gamma + S.N1])


def state_space(coupling: str = "eq5", state_order: str = "corrected",
                *, sign: int = 1) -> StateSpaceSym:
    """Cauchy form of Eq. (5) with the shaping filters (6), (7): paper GC Eq. (8).

    ``Δβ'' `` is solved from the Taylor linearization (with ``ω_rnd = N3`` and the unbalance
    torque), the shaping filters are appended, ``ψ, ω_gc, δ, γ`` are random constants.  ``F``,
    ``G``, ``D`` are the Jacobians of the right-hand sides and of the measurements.  ``β_n``
    appears as the symbol ``SYMBOLS.beta_n_sym``.  Cached per (validated) argument set.

    Parameters
    ----------
    coupling : {"eq5", "printed_F"}, default "eq5"
        The reading of Eq. (2).
    state_order : {"corrected", "printed"}, default "corrected"
        X1 = Δβ (corrected) or the printed X1 = Δβ'.
    sign : {1, -1}, default 1
        The sign of Eq. (1).

    Returns
    -------
    StateSpaceSym
        States, right-hand sides and the Jacobians F, G, D.

    Examples
    --------
    >>> from gyrolib.gc.model import symbolic
    >>> symbolic.state_space().F[1, 3]   # F(2,4)
    H/I
    """
    return _state_space(_check_coupling(coupling),
                        v.check_choice("state_order", state_order, STATE_ORDERS),
                        _check_sign(sign))


@cache
def _state_space(coupling: str, state_order: str, sign: int) -> StateSpaceSym:
    S = SYMBOLS
    lin = taylor_linearization(sign=sign, coupling=coupling, unbalance=True)
    ddb = sp.Symbol("ddb")
    t = S.t
    order1 = lin.order1.subs(S.dbeta(t).diff(t, 2), ddb).subs(
        S.dbeta(t).diff(t), S.x_dbeta_dot).subs(S.dbeta(t), S.x_dbeta)
    order1 = order1.subs(S.beta_n(t), S.beta_n_sym).subs(S.omega_rnd, S.N3)
    # Eq. (5) is linear in Δβ'': solve it by its coefficient (sympy's solve is needlessly slow).
    ddbeta = sp.expand(-order1.subs(ddb, 0) / order1.coeff(ddb))
    vib = shaping_filter("vibration")
    drift = shaping_filter("drift")
    n12 = vib.A * sp.Matrix([S.N1, S.N2]) + vib.B * S.w1
    n34 = drift.A * sp.Matrix([S.N3, S.N4]) + drift.B * S.w2
    derivs = {S.x_dbeta: S.x_dbeta_dot, S.x_dbeta_dot: sp.expand(ddbeta),
              S.psi: 0, S.omega_gc: 0, S.delta: 0, S.gamma: 0,
              S.N1: n12[0], S.N2: n12[1], S.N3: n34[0], S.N4: n34[1]}
    x = [S.x_dbeta, S.x_dbeta_dot, S.psi, S.omega_gc, S.delta, S.gamma,
         S.N1, S.N2, S.N3, S.N4]
    if state_order == "printed":
        x[0], x[1] = x[1], x[0]
    w = (S.w1, S.w2)
    rhs = sp.Matrix([derivs[xi] for xi in x])
    F = rhs.jacobian(x)
    G = rhs.jacobian(w)
    D = measurement_equations().jacobian(x)
    im = sp.ImmutableMatrix
    return StateSpaceSym(x=tuple(x), w=w, rhs=im(rhs), F=im(F), G=im(G), D=im(D),
                         coupling=coupling, state_order=state_order)


def paper_listing() -> dict[tuple[str, int, int], sp.Expr]:
    """The nonzero entries of F, G and D exactly as paper GC prints them (1-based indices).

    ``F(2,2)`` is printed ``−F/I``; the ``F`` there is the friction coefficient ``f`` (the
    parameter list also calls it ``F``).

    Returns
    -------
    dict
        ``(matrix, i, j) → entry`` with 1-based indices.

    Examples
    --------
    >>> from gyrolib.gc.model import symbolic
    >>> symbolic.paper_listing()[("F", 8, 7)]   # printed without its minus sign
    alpha_1**2
    """
    S = SYMBOLS
    H, I, bn = S.H, S.I, S.beta_n_sym
    return {
        ("F", 1, 2): sp.Integer(1),
        ("F", 2, 2): -S.f / I,
        ("F", 2, 4): H / I,
        ("F", 2, 7): H * S.omega_ub / (I * S.g),
        ("F", 2, 9): H / I,
        ("F", 7, 8): sp.Integer(1),
        ("F", 8, 7): S.alpha1**2,
        ("F", 8, 8): -2 * S.xi1 * S.alpha1,
        ("F", 9, 10): sp.Integer(1),
        ("F", 10, 9): -S.alpha2**2,
        ("F", 10, 10): -2 * S.xi2 * S.alpha2,
        ("F", 2, 1): -(H * S.Omega_h / I) * sp.sin(bn),
        ("F", 2, 3): (H * S.Omega_h / I) * sp.sin(bn),
        ("F", 2, 5): -(H * S.Omega_v / I) * sp.cos(bn),
        ("F", 2, 6): (H * S.Omega_v / I) * sp.sin(bn),
        ("G", 7, 1): sp.Integer(1),
        ("G", 8, 1): S.alpha1 - 2 * S.xi1 * S.alpha1,
        ("G", 10, 2): sp.Integer(1),
        ("D", 1, 1): sp.Integer(1),
        ("D", 2, 5): S.g,
        ("D", 2, 7): sp.Integer(1),
        ("D", 3, 6): S.g,
        ("D", 3, 7): sp.Integer(1),
    }


@dataclass(frozen=True)
class EntryComparison:
    """One matrix entry: the paper's printed value, the derived value, and whether equal."""

    matrix: str
    i: int
    j: int
    printed: sp.Expr
    derived: sp.Expr
    equal: bool


def compare_with_paper(model: StateSpaceSym) -> list[EntryComparison]:
    """Compare every entry that is nonzero in the paper's listing or in ``model``.

    Parameters
    ----------
    model : StateSpaceSym
        A derived model.

    Returns
    -------
    list of EntryComparison
        One per entry nonzero in the listing or the derivation.

    Examples
    --------
    >>> from gyrolib.gc.model import symbolic
    >>> rows = symbolic.compare_with_paper(symbolic.state_space("printed_F"))
    >>> [(r.matrix, r.i, r.j) for r in rows if not r.equal]
    [('F', 8, 7)]
    """
    v.check_instance("model", model, StateSpaceSym)
    listing = paper_listing()
    keys = set(listing)
    mats = {"F": model.F, "G": model.G, "D": model.D}
    for name, M in mats.items():
        for i in range(M.shape[0]):
            for j in range(M.shape[1]):
                if M[i, j] != 0:
                    keys.add((name, i + 1, j + 1))
    rows = []
    for name, i, j in sorted(keys, key=lambda k: ("FGD".index(k[0]), k[1], k[2])):
        printed = listing.get((name, i, j), sp.Integer(0))
        derived = mats[name][i - 1, j - 1]
        rows.append(EntryComparison(name, i, j, printed, derived,
                                    sp.expand(printed - derived) == 0))
    return rows


# Relabelling between the two readings of the vertical-rate coupling ---------------------------
@dataclass(frozen=True)
class Relabelling:
    """Signed permutations with ``x_p = T x``, ``w_p = Sw w``, ``z_p = Sm z``."""

    T: sp.Matrix
    Sw: sp.Matrix
    Sm: sp.Matrix


def relabelling() -> Relabelling:
    """The signed permutation taking the ``"eq5"`` model to the ``"printed_F"`` model.

    ``δ_p = −γ``, ``γ_p = −δ``, ``N1_p = −N1``, ``N2_p = −N2`` (all other states unchanged),
    ``w1_p = −w1``, and the two inclinometer readings swap with a sign change.  It maps
    ``F_eq5`` with unbalance ``−ω_ub`` onto ``F_printed`` with ``+ω_ub``:
    ``F_p = T F T⁻¹``, ``G_p = T G Sw⁻¹``, ``D_p = Sm D T⁻¹``.

    Returns
    -------
    Relabelling
        ``T`` (10×10 states), ``Sw`` (2×2 noises), ``Sm`` (3×3 measurements).

    Examples
    --------
    >>> from gyrolib.gc.model import symbolic
    >>> symbolic.relabelling().T.shape
    (10, 10)
    """
    T = sp.eye(10)
    T[4, 4] = T[5, 5] = 0
    T[4, 5] = T[5, 4] = -1
    T[6, 6] = T[7, 7] = -1
    Sw = sp.diag(-1, 1)
    Sm = sp.Matrix([[1, 0, 0], [0, 0, -1], [0, -1, 0]])
    return Relabelling(T=T, Sw=Sw, Sm=Sm)


# Numbers ---------------------------------------------------------------------------------------
def parameter_values(params: object) -> dict[sp.Symbol, float]:
    """Map the model's symbols to the values of a ``GyrocompassParams``.

    Parameters
    ----------
    params : GyrocompassParams

    Returns
    -------
    dict
        Symbol → float.

    Examples
    --------
    >>> from gyrolib.gc import GyrocompassParams, symbolic
    >>> symbolic.parameter_values(GyrocompassParams())[symbolic.SYMBOLS.H]
    0.05
    """
    check_params(params)
    S = SYMBOLS
    names = ("I", "H", "f", "Omega_h", "Omega_v", "g", "omega_ub", "alpha1", "xi1",
             "sigma1_sq", "alpha2", "xi2", "sigma2_sq")
    return {getattr(S, n): float(getattr(params, n)) for n in names}


_PARAM_ORDER: Final[tuple[str, ...]] = ("I", "H", "f", "Omega_h", "Omega_v", "g", "omega_ub",
                                        "alpha1", "xi1", "alpha2", "xi2")


@cache
def _lambdified(coupling: str):
    S = SYMBOLS
    model = state_space(coupling)
    args = (S.beta_n_sym, *[getattr(S, n) for n in _PARAM_ORDER])
    return tuple(sp.lambdify(args, M, modules="numpy") for M in (model.F, model.G, model.D))


def numeric_matrices(params: object, beta_n: float,
                     coupling: str | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Evaluate the symbolic ``F``, ``G``, ``D`` of Eq. (8) at ``β_n`` for ``params``.

    ``coupling`` defaults to ``params.vertical_coupling``.

    Parameters
    ----------
    params : GyrocompassParams
    beta_n : float
        Nominal float angle (rad).
    coupling : {"eq5", "printed_F"}, optional

    Returns
    -------
    (F, G, D) : tuple of ndarray

    Examples
    --------
    >>> from gyrolib.gc import GyrocompassParams, symbolic
    >>> F, G, D = symbolic.numeric_matrices(GyrocompassParams(), 0.0)
    >>> f"{F[1, 1]:.0f}"
    '-625'
    """
    check_params(params)
    coupling = _check_coupling(params.vertical_coupling if coupling is None else coupling)
    b = v.check_real("beta_n", beta_n)
    vals = [float(getattr(params, n)) for n in _PARAM_ORDER]
    return tuple(np.array(fn(b, *vals), dtype=float) for fn in _lambdified(coupling))
