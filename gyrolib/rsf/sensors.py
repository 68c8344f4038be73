"""Paper RSF: the sensors' data as frozen dataclasses, with the paper's values as defaults.

* :class:`RollGyroSpec` — the SINS roll gyro of Table 1 (:data:`SIIMU02_ROLL`);
* :class:`MemsGyroSpec` — the GS's MEMS gyro (:data:`GYPRO4300`);
* :class:`EncoderSpec` — the GS's angle encoder (:data:`AEDB9340`).

SI inside: rates in rad/s, scale-factor errors dimensionless.

One description per device: the simulation's model of a device is built from its record
(:meth:`gyrolib.rsf.SinsGyroModel.from_spec`, :meth:`~gyrolib.rsf.GsModel.from_spec`,
:meth:`~gyrolib.rsf.EncoderModel.from_spec`), adding only what a datasheet does not give
(noise, the GS's rate loop); :class:`~gyrolib.rsf.SimulationConfig`'s defaults are built this
way.  Imports run one way: :mod:`gyrolib.rsf.simulation` reads this module, never the reverse.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from gyrolib import _validation as v
from gyrolib.rsf._inputs import SF_LIMIT, check_optional_positive
from gyrolib.rsf.equations import gs_bias_total
from gyrolib.units import to_si

__all__ = [
    "AEDB9340",
    "GYPRO4300",
    "SIIMU02_ROLL",
    "EncoderSpec",
    "MemsGyroSpec",
    "RollGyroSpec",
]


@dataclass(frozen=True)
class RollGyroSpec:
    """Roll gyro of the SINS: paper RSF, Table 1 (Collins Aerospace SiIMU02).

    * ``bias_instability`` (rad/s, 1σ): printed "100" with the unit lost in the extraction;
      read as 100 °/h (the only unit for which ε0 ≪ ε1 ω holds as the paper states, and the
      usual datasheet unit).  It is the additive error ε0 of the measurement model.
    * ``sf_error`` (dimensionless, 1σ): 600 ppm, the ε1 of Table 2.
    * ``dynamic_range`` (rad/s): lost in the extraction (``None``).
    """

    name: str = "Collins Aerospace SiIMU02, roll gyro"
    bias_instability: float = float(to_si(100.0, "deg/h"))
    sf_error: float = float(to_si(600.0, "ppm"))
    dynamic_range: float | None = None

    def __post_init__(self) -> None:
        v.check_str("name", self.name)
        object.__setattr__(self, "bias_instability",
                           v.check_nonnegative("bias_instability", self.bias_instability))
        object.__setattr__(self, "sf_error",
                           v.check_in_range("sf_error", self.sf_error, 0.0, SF_LIMIT,
                                            high_open=True))
        object.__setattr__(self, "dynamic_range",
                           check_optional_positive("dynamic_range", self.dynamic_range))



@dataclass(frozen=True)
class MemsGyroSpec:
    """MEMS gyro of the GS: paper RSF, the GYPRO4300 table (Tronics).

    * ``bias_repeatability`` σ_rep (rad/s, 1σ): 10 °/h;
    * ``bias_stability`` σ_stab (rad/s, 1σ, in run): 7 °/h;
    * ``sf_error`` ε1,GS (dimensionless, 1σ): 280 ppm;
    * ``dynamic_range`` (rad/s): lost in the extraction (``None``).

    :attr:`bias_total` is ε0,GS = √(σ_rep² + σ_stab²) (the paper: the two are uncorrelated).
    """

    name: str = "Tronics GYPRO4300"
    bias_repeatability: float = float(to_si(10.0, "deg/h"))
    bias_stability: float = float(to_si(7.0, "deg/h"))
    sf_error: float = float(to_si(280.0, "ppm"))
    dynamic_range: float | None = None

    def __post_init__(self) -> None:
        v.check_str("name", self.name)
        for field in ("bias_repeatability", "bias_stability"):
            object.__setattr__(self, field, v.check_nonnegative(field, getattr(self, field)))
        object.__setattr__(self, "sf_error",
                           v.check_in_range("sf_error", self.sf_error, 0.0, SF_LIMIT,
                                            high_open=True))
        object.__setattr__(self, "dynamic_range",
                           check_optional_positive("dynamic_range", self.dynamic_range))

    @property
    def bias_total(self) -> float:
        """ε0,GS = √(σ_rep² + σ_stab²), rad/s."""
        return gs_bias_total(self.bias_repeatability, self.bias_stability)



@dataclass(frozen=True)
class EncoderSpec:
    """Optical encoder of the GS: paper RSF, Avago AEDB-9340.

    * ``position_error`` Δγ_enc (rad): "position error per revolution"; the value is lost in
      the encoder's data line, but the worked example of Eq. (7) prints it: 0.33° (≈ 20′;
      its unit lost too, degrees by the other terms).  Table 3 leaves the same 0.33° in all
      three columns (Δγ_GS − ε0,GS·t), a cross-check, not the source.  This is the encoder's
      accuracy (e.g. code-wheel eccentricity), not its resolution.
    * ``cycles_per_rev`` and ``quadrature``: not given by the paper.  The AEDB-9340 family
      is a three-channel (A, B, index) incremental module offered in resolutions up to a few
      thousand cycles per revolution; we *assume* 1000 CPR decoded ×4 (4000 counts per
      revolution, 0.09° per count).  The simulation sweeps this choice.
    """

    name: str = "Avago AEDB-9340"
    position_error: float = float(to_si(0.33, "deg"))
    cycles_per_rev: int = 1000
    quadrature: int = 4

    def __post_init__(self) -> None:
        v.check_str("name", self.name)
        object.__setattr__(self, "position_error",
                           v.check_in_range("position_error", self.position_error, 0.0,
                                            math.pi, high_open=True))
        object.__setattr__(self, "cycles_per_rev",
                           v.check_int("cycles_per_rev", self.cycles_per_rev, 1))
        q = v.check_int("quadrature", self.quadrature, 1)
        if q not in (1, 2, 4):
            raise ValueError(f"quadrature must be one of (1, 2, 4) (decoding factor); got {q}")
        object.__setattr__(self, "quadrature", q)

    @property
    def counts_per_rev(self) -> int:
        """Counts per revolution after quadrature decoding."""
        return self.cycles_per_rev * self.quadrature

    @property
    def resolution(self) -> float:
        """Angle of one count, rad."""
        return 2.0 * math.pi / self.counts_per_rev



#: Paper RSF, Table 1: SiIMU02 roll gyro.
SIIMU02_ROLL = RollGyroSpec()


#: Paper RSF, the GS gyro table: GYPRO4300.
GYPRO4300 = MemsGyroSpec()


#: Paper RSF, the GS encoder: AEDB-9340 (position error as the worked example prints it).
AEDB9340 = EncoderSpec()
