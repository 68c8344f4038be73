"""Paper RSF, Tables 2 and 3 and the worked example of δK, recomputed from the sensor data.

* :func:`table2` — Table 2: the SINS roll error Δγ (Eq. (4)) and the lateral deviation Δr_z
  (Eq. (8)) against time, at the roll rate :data:`TABLE2_OMEGA`;
* :func:`table3` — Table 3: the ideal GS's roll error (Eq. (9)) against time, from the GS gyro
  table's ε0,GS and the encoder error Δγ_enc = 0.33° that the worked example prints (an
  input: Table 3 is not used to find it, so recomputing Table 3 tests both terms);
* :func:`worked_example_delta_k` — the worked example of Eq. (7) (δK ≈ 0.093 as printed), with
  its printed inputs :data:`WORKED_EXAMPLE_PERIOD`, :data:`WORKED_EXAMPLE_OMEGA_UNC` and
  :data:`WORKED_EXAMPLE_OMEGA_X`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from gyrolib import _validation as v
from gyrolib._repr import compact_repr
from gyrolib.rsf._inputs import check_same_shape, check_times
from gyrolib.rsf.equations import (
    delta_k,
    gs_roll_error_ideal,
    lateral_deviation_cubic,
    lateral_deviation_exact,
    sins_roll_error,
    vertical_deviation_exact,
)
from gyrolib.rsf.sensors import (
    AEDB9340,
    GYPRO4300,
    SIIMU02_ROLL,
    EncoderSpec,
    MemsGyroSpec,
    RollGyroSpec,
)
from gyrolib.units import G0, from_si, to_si

__all__ = [
    "GS_MOTOR_RATE_MAX",
    "TABLE2_OMEGA",
    "WORKED_EXAMPLE_OMEGA_UNC",
    "WORKED_EXAMPLE_OMEGA_X",
    "WORKED_EXAMPLE_PERIOD",
    "DeltaKTerms",
    "Table2",
    "Table3",
    "WorkedExample",
    "table2",
    "table3",
    "worked_example_delta_k",
    "worked_example_terms",
]

#: The roll rate of Table 2, 3600 °/s (rad/s), as the paper prints it.
TABLE2_OMEGA: float = float(to_si(3600.0, "deg/s"))
#: The worked example's correction period Δt (s), uncompensated rate ω_unc and vehicle roll
#: rate ω_x (rad/s), as the paper prints them (5 s, 300 °/s, 900 °/s).
WORKED_EXAMPLE_PERIOD: float = 5.0
WORKED_EXAMPLE_OMEGA_UNC: float = float(to_si(300.0, "deg/s"))
WORKED_EXAMPLE_OMEGA_X: float = float(to_si(900.0, "deg/s"))
#: The GS motor's speed limit of the book's simulation (rad/s, 600 °/s): above it the vehicle's
#: roll rate is left uncompensated (``GsModel.motor_rate_max``), 300 °/s at the worked example.
GS_MOTOR_RATE_MAX: float = float(to_si(600.0, "deg/s"))

#: The readings of the worked example that the table of inputs (:mod:`gyrolib.inputs`) names.
_EXAMPLE_READINGS = {"eps0_gs_reading": ("consistent", "two_digit"),
                     "eps1_gs_unit": ("ppm", "1e-3"),
                     "omega_unc_model": ("constant", "motor_limited", "proportional")}


@dataclass(frozen=True)
class WorkedExample:
    """Paper RSF's operating point and the readings of its printed example, as the claims
    are judged (:mod:`gyrolib.inputs`; SI units).

    ``omega_x`` the vehicle's roll rate (900 °/s), ``omega_unc`` the GS's uncompensated rate
    at it (300 °/s), ``period`` the correction interval Δt (5 s), ``table_rate`` Table 2's
    roll rate (3600 °/s).  Readings: ``eps0_gs_reading`` — ε0,GS as computed
    (``"consistent"``) or cut to the printed two digits, 0.0033 °/s (``"two_digit"``);
    ``eps1_gs_unit`` — ε1,GS = 280 in ``"ppm"`` or slipped to ``"1e-3"``;
    ``omega_unc_model`` — how ω_unc follows the roll rate ω: ``"constant"`` (held at
    ``omega_unc``), ``"motor_limited"`` (ω − :data:`GS_MOTOR_RATE_MAX`, the book's simulated
    GS) or ``"proportional"`` (``omega_unc · ω/900 °/s``: the example's ratio kept).

    Examples
    --------
    >>> from gyrolib.units import from_si, to_si
    >>> ex = WorkedExample(omega_unc_model="motor_limited")
    >>> f"{from_si(ex.omega_unc_at(to_si(3600.0, 'deg/s')), 'deg/s'):.0f}"
    '3000'
    >>> f"{from_si(WorkedExample().omega_unc_at(to_si(3600.0, 'deg/s')), 'deg/s'):.0f}"
    '300'
    """

    omega_x: float = WORKED_EXAMPLE_OMEGA_X
    omega_unc: float = WORKED_EXAMPLE_OMEGA_UNC
    period: float = WORKED_EXAMPLE_PERIOD
    table_rate: float = TABLE2_OMEGA
    eps0_gs_reading: str = "consistent"
    eps1_gs_unit: str = "ppm"
    omega_unc_model: str = "constant"

    def __post_init__(self) -> None:
        for name in ("omega_x", "omega_unc", "period", "table_rate"):
            v.check_positive(name, getattr(self, name))
        for name, allowed in _EXAMPLE_READINGS.items():
            if getattr(self, name) not in allowed:
                raise ValueError(f"{name} must be one of {allowed}; got {getattr(self, name)!r}")

    def omega_unc_at(self, omega: float) -> float:
        """ω_unc (rad/s) at the roll rate ``omega`` (rad/s), by :attr:`omega_unc_model`."""
        omega = v.check_positive("omega", omega)
        if self.omega_unc_model == "constant":
            return self.omega_unc
        if self.omega_unc_model == "motor_limited":
            return max(float(omega) - GS_MOTOR_RATE_MAX, 0.0)
        return self.omega_unc * float(omega) / WORKED_EXAMPLE_OMEGA_X

    def eps0_gs(self, gyro: MemsGyroSpec) -> float:
        """ε0,GS (rad/s) of ``gyro`` by the reading: as computed, or cut to two digits in °/s."""
        v.check_instance("gyro", gyro, MemsGyroSpec)
        e0 = gyro.bias_total
        if self.eps0_gs_reading == "two_digit":
            deg = float(from_si(e0, "deg/s"))
            digits = 1 - int(np.floor(np.log10(deg)))
            return float(to_si(np.floor(deg * 10.0**digits) / 10.0**digits, "deg/s"))
        return e0

    def eps1_gs(self, gyro: MemsGyroSpec) -> float:
        """ε1,GS of ``gyro`` by the reading: as given, or its ppm read as 10⁻³."""
        v.check_instance("gyro", gyro, MemsGyroSpec)
        return gyro.sf_error * (1e3 if self.eps1_gs_unit == "1e-3" else 1.0)



@compact_repr
@dataclass(frozen=True)
class Table2:
    """Paper RSF, Table 2: SINS roll error (rad) and lateral deviation (m) at times ``t``.

    ``dr_z_cubic`` is Eq. (8), ``dr_z_exact`` its double integral without the small-angle
    approximation (lateral component only) and ``dr_y_exact`` the vertical component of the
    same mis-resolved 1 g, g (1 − cos Δγ) integrated twice, which the paper leaves out.
    """

    t: np.ndarray
    dgamma_sins: np.ndarray
    dr_z_cubic: np.ndarray
    dr_z_exact: np.ndarray
    dr_y_exact: np.ndarray

    def __post_init__(self) -> None:
        check_same_shape(self, "t", "dgamma_sins", "dr_z_cubic", "dr_z_exact", "dr_y_exact")


def table2(gyro: RollGyroSpec = SIIMU02_ROLL, omega_true: float = TABLE2_OMEGA,
           times: ArrayLike = (10.0, 60.0, 120.0), g: float = G0) -> Table2:
    """Recompute Table 2 of paper RSF from Eqs. (4) and (8) with the gyro's SF error.

    Parameters
    ----------
    gyro : RollGyroSpec, optional
        The roll gyro (default Table 1's SiIMU02).
    omega_true : float, optional
        Roll rate, rad/s (default 3600 °/s, as the paper).
    times : array_like, optional
        Times, s (default 10, 60, 120 s).
    g : float, optional
        Gravity, m/s² (> 0).

    Returns
    -------
    Table2
        Roll error, cubic and exact lateral deviation and the vertical component.

    Examples
    --------
    >>> from gyrolib.units import from_si
    >>> [f"{x:.1f}" for x in from_si(table2().dgamma_sins, "deg")]
    ['21.6', '129.6', '259.2']
    """
    if not isinstance(gyro, RollGyroSpec):
        raise TypeError(f"gyro must be a RollGyroSpec; got {type(gyro).__name__}")
    t = check_times(times)
    omega_true = v.check_real("omega_true", omega_true)
    g = v.check_positive("g", g)
    e1 = gyro.sf_error
    return Table2(
        t=t,
        dgamma_sins=np.asarray(sins_roll_error(e1, omega_true, t)),
        dr_z_cubic=np.asarray(lateral_deviation_cubic(e1, omega_true, t, g)),
        dr_z_exact=np.asarray(lateral_deviation_exact(e1, omega_true, t, g)),
        dr_y_exact=np.asarray(vertical_deviation_exact(e1, omega_true, t, g)),
    )


@compact_repr
@dataclass(frozen=True)
class Table3:
    """Paper RSF, Table 3: GS roll error (rad) at times ``t`` for an ideal GS, Eq. (9)."""

    t: np.ndarray
    eps0_t: np.ndarray
    dgamma_gs: np.ndarray

    def __post_init__(self) -> None:
        check_same_shape(self, "t", "eps0_t", "dgamma_gs")


def table3(gyro: MemsGyroSpec = GYPRO4300, encoder: EncoderSpec = AEDB9340,
           times: ArrayLike = (10.0, 60.0, 120.0), eps0_gs: float | None = None) -> Table3:
    """Recompute Table 3 of paper RSF from Eq. (9).

    Parameters
    ----------
    gyro : MemsGyroSpec, optional
        The GS gyro (default the GYPRO4300 of the GS gyro table).
    encoder : EncoderSpec, optional
        The encoder (default the AEDB-9340 with the position error 0.33° that the worked
        example prints).
    times : array_like, optional
        Times, s.
    eps0_gs : float, optional
        Overrides ε0,GS = √(σ_rep² + σ_stab²), rad/s (the paper truncates it to
        3.3·10⁻³ °/s).

    Returns
    -------
    Table3

    Examples
    --------
    >>> from gyrolib.units import from_si, to_si
    >>> t3 = table3(eps0_gs=to_si(3.3e-3, "deg/s"))
    >>> [f"{x:.3f}" for x in from_si(t3.dgamma_gs, "deg")]
    ['0.363', '0.528', '0.726']
    """
    if not isinstance(gyro, MemsGyroSpec):
        raise TypeError(f"gyro must be a MemsGyroSpec; got {type(gyro).__name__}")
    if not isinstance(encoder, EncoderSpec):
        raise TypeError(f"encoder must be an EncoderSpec; got {type(encoder).__name__}")
    t = check_times(times)
    e0 = gyro.bias_total if eps0_gs is None else v.check_nonnegative("eps0_gs", eps0_gs)
    return Table3(
        t=t,
        eps0_t=np.asarray(gs_roll_error_ideal(e0, t, 0.0)),
        dgamma_gs=np.asarray(gs_roll_error_ideal(e0, t, encoder.position_error)),
    )


def worked_example_delta_k(gyro: MemsGyroSpec = GYPRO4300, encoder: EncoderSpec = AEDB9340, *,
                           omega_x: float = WORKED_EXAMPLE_OMEGA_X,
                           omega_unc: float = WORKED_EXAMPLE_OMEGA_UNC,
                           dt: float = WORKED_EXAMPLE_PERIOD, eps0_gs: float | None = None,
                           eps1_gs: float | None = None) -> float:
    """δK of the paper's worked example (Eq. (7)): Δt = 5 s, ω_unc = 300 °/s, ω_x = 900 °/s.

    ``eps0_gs`` and ``eps1_gs`` override the gyro's values (to reproduce the print, which
    uses ε0,GS = 3.3·10⁻³ °/s and, by a slip, ε1,GS = 280·10⁻³ instead of 280 ppm).

    Parameters
    ----------
    gyro : MemsGyroSpec, optional
        The GS gyro.
    encoder : EncoderSpec, optional
        The GS encoder.
    omega_x, omega_unc : float, optional
        Roll rate and uncompensated rate, rad/s.
    dt : float, optional
        Correction period, s.
    eps0_gs, eps1_gs : float, optional
        Override the gyro's bias (rad/s) and SF error.

    Returns
    -------
    float
        δK.

    Examples
    --------
    >>> from gyrolib.units import to_si
    >>> f"{worked_example_delta_k():.3g}"
    '0.00017'
    >>> f"{worked_example_delta_k(eps0_gs=to_si(3.3e-3, 'deg/s'), eps1_gs=280e-3):.3f}"
    '0.093'
    """
    v.check_instance("gyro", gyro, MemsGyroSpec)
    v.check_instance("encoder", encoder, EncoderSpec)
    e0 = gyro.bias_total if eps0_gs is None else eps0_gs
    e1 = gyro.sf_error if eps1_gs is None else eps1_gs
    return delta_k(e0, encoder.position_error, omega_x, dt, e1, omega_unc)


@dataclass(frozen=True)
class DeltaKTerms:
    """The terms of Eq. (7) of paper RSF over one interval, rad: ``bias`` ε0,GS Δt,
    ``sf`` ε1,GS ω_unc Δt, ``encoder`` Δγ_enc, their sum ``numerator``, the roll angle of the
    interval ``span`` ω_x Δt, and ``delta_k`` = numerator / span."""

    bias: float
    sf: float
    encoder: float
    numerator: float
    span: float
    delta_k: float


def worked_example_terms(gyro: MemsGyroSpec = GYPRO4300, encoder: EncoderSpec = AEDB9340, *,
                         omega_x: float = WORKED_EXAMPLE_OMEGA_X,
                         omega_unc: float = WORKED_EXAMPLE_OMEGA_UNC,
                         dt: float = WORKED_EXAMPLE_PERIOD, eps0_gs: float | None = None,
                         eps1_gs: float | None = None) -> DeltaKTerms:
    """Eq. (7) of paper RSF term by term, as the worked example writes it out.

    Parameters as :func:`worked_example_delta_k`; ``eps0_gs``, ``eps1_gs`` override the gyro.

    Returns
    -------
    DeltaKTerms
        The three terms (rad), the numerator, the interval's roll angle and δK.

    Examples
    --------
    >>> from gyrolib.units import from_si, to_si
    >>> t = worked_example_terms()
    >>> f"{from_si(t.numerator, 'deg'):.4f}° / {from_si(t.span, 'deg'):.0f}° = {t.delta_k:.3g}"
    '0.7670° / 4500° = 0.00017'
    """
    v.check_instance("gyro", gyro, MemsGyroSpec)
    v.check_instance("encoder", encoder, EncoderSpec)
    dt = v.check_positive("dt", dt)
    omega_x = v.check_positive("omega_x", omega_x)
    omega_unc = v.check_nonnegative("omega_unc", omega_unc)
    e0 = gyro.bias_total if eps0_gs is None else v.check_nonnegative("eps0_gs", eps0_gs)
    e1 = gyro.sf_error if eps1_gs is None else v.check_nonnegative("eps1_gs", eps1_gs)
    bias, sf, enc = e0 * dt, e1 * omega_unc * dt, encoder.position_error
    return DeltaKTerms(bias=bias, sf=sf, encoder=enc, numerator=bias + sf + enc,
                       span=omega_x * dt, delta_k=delta_k(e0, enc, omega_x, dt, e1, omega_unc))
