"""Paper RSF's rows of the table of inputs (:mod:`gyrolib.inputs`): the data-sheet values
of :class:`~gyrolib.rsf.RollGyroSpec`, :class:`~gyrolib.rsf.MemsGyroSpec` and
:class:`~gyrolib.rsf.EncoderSpec`, the operating point and the readings of the print in
:class:`~gyrolib.rsf.WorkedExample`, declared beside those dataclasses.

Examples
--------
>>> from gyrolib.rsf import inputs
>>> r = inputs.row("rsf.eps1")
>>> r.kind, r.factors, r.shown
('uncertain', (0.5, 2.0), 'ppm')
"""

from __future__ import annotations

from typing import Any, Final

from gyrolib import input_rows
from gyrolib.input_rows import Input
from gyrolib.rsf.sensors import EncoderSpec, MemsGyroSpec, RollGyroSpec
from gyrolib.rsf.tables import WorkedExample

__all__ = ["OWNERS", "ROWS", "row", "rows"]

#: The dataclasses whose fields the rows set, by the name the rows use.
OWNERS: Final[dict[str, type]] = {
    "RollGyroSpec": RollGyroSpec,
    "MemsGyroSpec": MemsGyroSpec,
    "EncoderSpec": EncoderSpec,
    "WorkedExample": WorkedExample,
}


def _row(*args: Any, **kw: Any) -> Input:
    return Input(*args, owner_type=OWNERS[args[2]], **kw)


_SHEET = ("a data-sheet figure of the named part: a unit may be half to twice as good as its "
          "sheet's typical value")


#: Paper RSF's rows: the data sheets it quotes, its example's operating point, the readings
#: of its printed text.
ROWS: Final[tuple[Input, ...]] = (
    # paper RSF: the data sheets it quotes
    _row("rsf.eps1", "ε1", "RollGyroSpec", ("sf_error",), "uncertain", "1",
         f"Table 1 (SiIMU02, 600 ppm); {_SHEET}", 0.5, 2.0, shown="ppm"),
    _row("rsf.eps0", "ε0", "RollGyroSpec", ("bias_instability",), "uncertain", "rad/s",
         f"Table 1 (SiIMU02, 100 °/h); {_SHEET}", 0.5, 2.0, shown="deg/h"),
    _row("rsf.gs_bias", "ε0,GS", "MemsGyroSpec", ("bias_repeatability", "bias_stability"),
         "uncertain", "rad/s", f"the GS gyro's table (GYPRO4300, 10 and 7 °/h, root sum of "
         f"squares); {_SHEET}", 0.5, 2.0, mode="norm", shown="deg/h"),
    _row("rsf.eps1_gs", "ε1,GS", "MemsGyroSpec", ("sf_error",), "uncertain", "1",
         f"the GS gyro's table (280 ppm); {_SHEET}", 0.5, 2.0, shown="ppm"),
    _row("rsf.encoder_error", "Δγ_enc", "EncoderSpec", ("position_error",), "uncertain",
         "rad", f"the worked example's 0.33° (AEDB-9340); {_SHEET}", 0.5, 2.0, shown="deg"),
    # paper RSF: its example's operating point
    _row("rsf.omega_x", "ω_x", "WorkedExample", ("omega_x",), "operating", "rad/s",
         "the worked example's roll rate, 900 °/s; the paper's rates reach 5400 °/s", 1.0,
         6.0, shown="deg/s"),
    _row("rsf.omega_unc", "ω_unc", "WorkedExample", ("omega_unc",), "operating", "rad/s",
         "the worked example's uncompensated GS rate, 300 °/s: a third to three times", 1 / 3,
         3.0, shown="deg/s"),
    _row("rsf.period", "Δt", "WorkedExample", ("period",), "operating", "s",
         "the worked example's correction interval, 5 s: 0.5 s to 30 s, the simulation's "
         "sweep", 0.1, 6.0),
    _row("rsf.table_rate", "ω", "WorkedExample", ("table_rate",), "operating", "rad/s",
         "Table 2's roll rate, 3600 °/s; the paper's rates span 1800-5400 °/s", 0.5, 1.5,
         shown="deg/s"),
    # paper RSF: the readings of the printed text
    _row("rsf.eps0_gs_digits", "ε0,GS print", "WorkedExample", ("eps0_gs_reading",),
         "reading", "—", "ε0,GS = √(σ_rep² + σ_stab²) as computed, or cut to the two digits "
         "the paper prints (0.0033 °/s)", values=("consistent", "two_digit")),
    _row("rsf.eps1_gs_unit", "ε1,GS unit", "WorkedExample", ("eps1_gs_unit",), "reading",
         "—", "ε1,GS = 280 read in ppm, or as 10⁻³ (the slip that gives the printed δK)",
         values=("ppm", "1e-3")),
    _row("rsf.omega_unc_model", "ω_unc(ω)", "WorkedExample", ("omega_unc_model",), "reading",
         "—", "how ω_unc changes with the roll rate: held at the example's value, limited by "
         "the GS motor (ω − 600 °/s, the book's simulation), or proportional to ω",
         values=("constant", "motor_limited", "proportional")),
)

_BY_NAME: Final[dict[str, Input]] = input_rows.by_name(ROWS)


def row(name: str) -> Input:
    """The row called ``name`` (``KeyError`` naming the known rows otherwise)."""
    return input_rows.row(_BY_NAME, name)


def rows(*, owner: str | None = None, kind: str | None = None) -> tuple[Input, ...]:
    """The rows of one owner or kind."""
    return input_rows.select(ROWS, owner=owner, kind=kind)
