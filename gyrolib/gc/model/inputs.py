"""Paper GC's rows of the table of inputs (:mod:`gyrolib.inputs`): every unstated, uncertain
or interpreted input of :class:`~gyrolib.gc.GyrocompassParams`, declared beside the
dataclass whose fields they set.  The race's rival has its rows in
:mod:`gyrolib.gc.racing.inputs`; :mod:`gyrolib.gc.inputs` holds both.

Examples
--------
>>> from gyrolib.gc.model import inputs
>>> r = inputs.row("gc.sigma1_sq")
>>> r.kind, r.scale, r.factors
('uncertain', 'log', (0.1, 10.0))
>>> inputs.factor_grid("gc.sigma1_sq")
(0.1, 1.0, 10.0)
"""

from __future__ import annotations

from typing import Any, Final

from gyrolib import input_rows
from gyrolib.gc.model.params import GyrocompassParams
from gyrolib.input_rows import Input
from gyrolib.units import ARCSEC_PAPER, G0

__all__ = ["ROWS", "default_prior", "factor_grid", "row", "rows"]


def _row(*args: Any, **kw: Any) -> Input:
    return Input(*args, owner_type=GyrocompassParams, **kw)


_DECADE = "a printed noise-model value of a stand the book has not seen: a decade either way"
_ZERO = ("not in the paper's model (zero at the reference, on both methods alike); up to the "
         "largest value the book deems plausible, the default prior of `calibrate`")


#: Paper GC's rows: the vibration filter (6), the random drift (7), the sensors, the
#: instrument errors the paper leaves out, the filter's priors, the readings of the print.
ROWS: Final[tuple[Input, ...]] = (
    # paper GC: the vibration filter (6), the random drift (7), the sensors
    _row("gc.alpha1", "α1", "GyrocompassParams", ("alpha1",), "uncertain", "rad/s",
         f"printed after Eq. (6); {_DECADE}", 0.1, 10.0),
    _row("gc.xi1", "ξ1", "GyrocompassParams", ("xi1",), "uncertain", "1",
         "printed after Eq. (6); an underdamped second-order filter, as (6) is written: "
         "0.1 to 1", 0.1, 1.0, relative=False, scale="linear"),
    _row("gc.sigma1_sq", "σ1²", "GyrocompassParams", ("sigma1_sq",), "uncertain", "m²/s⁴",
         f"printed after Eq. (6); {_DECADE}", 0.1, 10.0),
    _row("gc.alpha2", "α2", "GyrocompassParams", ("alpha2",), "uncertain", "rad/s",
         f"printed after Eq. (7); {_DECADE}", 0.1, 10.0),
    _row("gc.xi2", "ξ2", "GyrocompassParams", ("xi2",), "uncertain", "1",
         "printed after Eq. (7); an underdamped second-order filter: 0.1 to 1", 0.1, 1.0,
         relative=False, scale="linear"),
    _row("gc.sigma2_sq", "σ2²", "GyrocompassParams", ("sigma2_sq",), "uncertain", "rad²/s²",
         f"printed after Eq. (7), from its ref. [2]; {_DECADE}", 0.1, 10.0),
    _row("gc.omega_ub", "ω_ub", "GyrocompassParams", ("omega_ub",), "uncertain", "rad/s",
         f"printed after Eq. (6), from its ref. [6]; {_DECADE}", 0.1, 10.0),
    _row("gc.C_as", "C_as", "GyrocompassParams", ("C_as",), "uncertain", "rad² s",
         "printed before Eq. (8) with its unit garbled; a decade either way", 0.1, 10.0),
    _row("gc.C_incl", "C_in", "GyrocompassParams", ("C_incl_y", "C_incl_z"), "uncertain",
         "m²/s³", "printed before Eq. (8) with its unit garbled; both inclinometers; a decade "
         "either way", 0.1, 10.0),
    _row("gc.sigma_hf_scale", "κ", "GyrocompassParams", ("sigma_hf_scale",), "uncertain",
         "1", f"the relative error of H/f and the angle sensor's gain: {_ZERO}: 10⁻³, the "
         "tolerance the book gives the rival's torque sensor", 0.0, 1.0e-3, relative=False,
         scale="linear"),
    _row("gc.sigma_as_offset", "σ_off", "GyrocompassParams", ("sigma_as_offset",),
         "uncertain", "rad", f"the angle sensor's null offset: {_ZERO}: 20″", 0.0,
         20.0 * ARCSEC_PAPER, relative=False, scale="linear", shown="arcsec_paper"),
    _row("gc.sigma_incl_bias", "σ_b", "GyrocompassParams", ("sigma_incl_bias",),
         "uncertain", "m/s²", f"the inclinometers' biases: {_ZERO}: 0.5 mg", 0.0,
         0.5e-3 * G0, relative=False, scale="linear", shown="mg"),
    _row("gc.sigma_clock", "ε_t", "GyrocompassParams", ("sigma_clock",), "uncertain", "1",
         f"the logger's time-scale error: {_ZERO}: 10⁻⁴, a logger crystal's tolerance (a "
         "rate labelled wrong, 1024 Hz read as 1 kHz, is 2.4·10⁻²: stated, not a default)",
         0.0, 1.0e-4, relative=False, scale="linear"),
    # paper GC: the filter's priors (a choice of whoever runs the filter)
    _row("gc.sigma_gc0", "σ_ω(0)", "GyrocompassParams", ("sigma_gc0",), "operating",
         "rad/s", "the prior σ of ω_gc, printed in the parameter table: the user states the "
         "drift a gyro of the type may have; a decade either way", 0.1, 10.0,
         shown="arcsec_paper/s"),
    _row("gc.sigma_psi0", "σ_ψ(0)", "GyrocompassParams", ("sigma_psi0",), "operating", "rad",
         "the prior σ of ψ, printed in the parameter table; a decade either way", 0.1, 10.0,
         shown="arcsec_paper"),
    _row("gc.sigma_tilt0", "σ_δ,γ(0)", "GyrocompassParams", ("sigma_delta0", "sigma_gamma0"),
         "operating", "rad", "the prior σ of δ and γ, printed in the parameter table; a "
         "decade either way", 0.1, 10.0, shown="arcsec_paper"),
    # paper GC: the readings of the printed text
    _row("gc.measurement_noise", "R", "GyrocompassParams", ("measurement_noise",),
         "reading", "—", "the printed noise levels read as intensities (R = C/dt) or as "
         "variances (R = C): the unit is garbled", values=("intensity_over_dt", "variance")),
    _row("gc.shaping_p0", "P0(N)", "GyrocompassParams", ("shaping_p0",), "reading", "—",
         "the shaping filters' initial covariance: stationary, or zero (the parameter table "
         "gives none)", values=("stationary", "zero")),
    _row("gc.eq1_sign", "sign of (1)", "GyrocompassParams", ("eq1_sign",), "reading", "—",
         "the sign of Ω_h ψ in Eq. (1), lost in the extraction", values=("+", "-")),
    _row("gc.vertical_coupling", "F(2,5..6)", "GyrocompassParams", ("vertical_coupling",),
         "reading", "—", "the tilt columns of F: from Eq. (5), or as the F listing prints "
         "them", values=("eq5", "printed_F")),
)

_BY_NAME: Final[dict[str, Input]] = input_rows.by_name(ROWS)


def row(name: str) -> Input:
    """The row called ``name`` (``KeyError`` naming the known rows otherwise)."""
    return input_rows.row(_BY_NAME, name)


def rows(*, kind: str | None = None, prefix: str | None = None) -> tuple[Input, ...]:
    """The rows of one kind or name prefix."""
    return input_rows.select(ROWS, kind=kind, prefix=prefix)


def factor_grid(name: str, n: int = 3) -> tuple[float, ...]:
    """:func:`gyrolib.input_rows.factor_grid` over these rows."""
    return input_rows.factor_grid(_BY_NAME.values(), name, n)


def default_prior(name: str) -> float:
    """:func:`gyrolib.input_rows.default_prior` over these rows."""
    return input_rows.default_prior(_BY_NAME.values(), name)
