"""The one table of inputs: every unstated, uncertain or interpreted input of both papers.

Each row names the dataclass field (or fields) it sets — in
:class:`gyrolib.gc.GyrocompassParams`, :class:`gyrolib.gc.RateSensorProcedure` (the race's
rival), and paper RSF's :class:`~gyrolib.rsf.RollGyroSpec`, :class:`~gyrolib.rsf.MemsGyroSpec`,
:class:`~gyrolib.rsf.EncoderSpec` and :class:`~gyrolib.rsf.WorkedExample` — with its plausible
range, the scale on which it is sampled (``"log"``, with a positive lower bound, or
``"linear"``), the reason for that range and its *kind*:

* ``uncertain`` — an instrument property the paper does not give, or gives for another
  instrument (varied one at a time, and sampled in the box);
* ``operating`` — a choice the user makes: roll rate, correction interval, procedure times,
  the filter's priors (varied one at a time, never sampled as if uncertain);
* ``reading`` — an interpretation of the printed text: the row lists every reading, the
  book's first (each is judged alone).

**The rule that sets each reference value** (one rule per kind, the same for paper GC's method
and for the rival it is raced against):

* *uncertain*: the paper's printed value where it prints one (for paper RSF the data sheet it
  quotes); an instrument error that the paper's model does not contain (a scale error of
  ``H/f``, the angle sensor's offset, the inclinometers' biases) is **zero**, the paper's own
  model, on both methods alike; a property of the rival that paper GC does not describe takes
  the book's stated default, chosen in favour of the old method (``RateSensorProcedure``).
* *operating*: the paper's own example (its worked example, its figure, its procedure);
* *reading*: the book's reading, stated in the chapter *Errata and assumptions*.

The reference value is the field's default: the table reads it from the dataclass, so the
two cannot disagree.  **Ranges** of scale-type rows are factors of the reference
(:attr:`Input.relative`), so the same row applies around a user's own parameters; a row
whose reference is zero has an absolute range from zero to the largest plausible value, the
value that ``calibrate`` takes as its default prior (:func:`default_prior`).

Examples
--------
>>> from gyrolib import inputs
>>> r = inputs.row("gc.sigma1_sq")
>>> r.kind, r.scale, r.factors
('uncertain', 'log', (0.1, 10.0))
>>> f"{r.reference:.3g}", [f"{x:.3g}" for x in r.bounds()]
('1.86e-06', ['1.86e-07', '1.86e-05'])
>>> inputs.row("gc.measurement_noise").values
('intensity_over_dt', 'variance')
>>> f"{inputs.default_prior('gc.sigma_hf_scale'):g}"
'0.001'
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from gyrolib.gc.model.params import GyrocompassParams
from gyrolib.gc.racing.rate_sensor import RateSensorProcedure
from gyrolib.rsf.sensors import EncoderSpec, MemsGyroSpec, RollGyroSpec
from gyrolib.rsf.tables import WorkedExample
from gyrolib.units import ARCSEC_PAPER, G0, from_si

__all__ = ["INPUTS", "KINDS", "OWNERS", "Input", "apply", "default_prior", "factor_grid",
           "reference_objects",
           "row", "rows", "table_fingerprint", "value_of"]

#: The kinds of input (see the module docstring).
KINDS: Final[tuple[str, ...]] = ("uncertain", "operating", "reading")

#: The dataclasses whose fields the rows set, by the name the rows use.
OWNERS: Final[dict[str, type]] = {
    "GyrocompassParams": GyrocompassParams,
    "RateSensorProcedure": RateSensorProcedure,
    "RollGyroSpec": RollGyroSpec,
    "MemsGyroSpec": MemsGyroSpec,
    "EncoderSpec": EncoderSpec,
    "WorkedExample": WorkedExample,
}


def _combine(mode: str, vals: list[Any]) -> Any:
    if mode == "sum":
        return float(sum(vals))
    if mode == "norm":
        return float(math.sqrt(sum(float(x) ** 2 for x in vals)))
    if any(x != vals[0] for x in vals):
        raise ValueError(f"the fields of one row must have the same value; got {vals}")
    return vals[0]



def _number(x: float) -> str:
    """Three significant digits (four from 1000 up), ``m·10ⁿ`` outside [10⁻³, 10⁵)."""
    if x == 0.0 or not math.isfinite(x):
        return f"{x:g}"
    e = math.floor(math.log10(abs(x)))
    if -3 <= e < 5:
        return f"{x:.4g}" if e >= 3 else f"{x:.3g}"
    m = x / 10.0**e
    if round(abs(m), 2) >= 10.0:
        m, e = m / 10.0, e + 1
    return f"{m:.2f}·10" + str(e).translate(str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹"))


@dataclass(frozen=True)
class Input:
    """One row of the table of inputs.

    ``name`` (``"gc.sigma1_sq"``), ``symbol`` (as the book prints it), ``owner`` (a key of
    :data:`OWNERS`) and ``fields`` (every field the row sets; several fields take the same
    value, or keep their proportions and add up to it, ``mode="sum"``, or have it as their
    root sum of squares, ``mode="norm"``), ``kind`` (one of
    :data:`KINDS`), ``unit`` (SI), ``reason`` (why this range: the paper's print, a cited
    source or a stated rule).  Numeric rows: ``low``, ``high`` (factors of the reference when
    ``relative``, else absolute SI values) and ``scale``; reading rows: ``values``, the
    book's reading first.  ``shown``: the unit (of :data:`gyrolib.units.UNITS`) in which
    the book's text shows the row's values (default: SI, ``unit``).
    """

    name: str
    symbol: str
    owner: str
    fields: tuple[str, ...]
    kind: str
    unit: str
    reason: str
    low: float = math.nan
    high: float = math.nan
    relative: bool = True
    scale: str = "log"
    values: tuple[str, ...] = ()
    mode: str = "each"
    shown: str = ""

    def __post_init__(self) -> None:
        if self.owner not in OWNERS:
            raise ValueError(f"owner of {self.name} must be one of {tuple(OWNERS)}")
        names = {f.name for f in dataclasses.fields(OWNERS[self.owner])}
        for f in self.fields:
            if f not in names:
                raise ValueError(f"{self.name}: {self.owner} has no field {f!r}")
        if self.kind not in KINDS:
            raise ValueError(f"kind of {self.name} must be one of {KINDS}")
        if self.mode not in ("each", "sum", "norm"):
            raise ValueError(f"mode of {self.name} must be 'each', 'sum' or 'norm'")
        if self.kind == "reading":
            if len(self.values) < 2 or self.values[0] != self.reference:
                raise ValueError(f"{self.name}: a reading lists at least two values, the "
                                 "field's default (the book's reading) first")
            return
        if self.scale not in ("log", "linear"):
            raise ValueError(f"scale of {self.name} must be 'log' or 'linear'")
        lo, hi = self.bounds()
        if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
            raise ValueError(f"range of {self.name} must be finite with low < high")
        if self.scale == "log" and lo <= 0.0:
            raise ValueError(f"{self.name}: a log range needs a positive lower bound")
        if not lo <= self.reference <= hi:
            raise ValueError(f"{self.name}: the reference {self.reference} is outside its "
                             f"range [{lo}, {hi}]")

    @property
    def default(self) -> Any:
        """The field's default in its dataclass (for ``mode="sum"``, the defaults' sum; for
        ``mode="norm"``, their root sum of squares)."""
        defaults = [next(f.default for f in dataclasses.fields(OWNERS[self.owner])
                         if f.name == name) for name in self.fields]
        return _combine(self.mode, defaults)

    @property
    def reference(self) -> Any:
        """The reference value: the field's default (see the rule in the module docstring)."""
        return self.default

    @property
    def factors(self) -> tuple[float, float]:
        """The range as factors of the reference (``nan`` when the reference is 0)."""
        if self.kind == "reading":
            raise ValueError(f"{self.name} is a reading: it has values, not a range")
        if self.relative:
            return (self.low, self.high)
        ref = float(self.reference)
        return (self.low / ref, self.high / ref) if ref else (math.nan, math.nan)

    def bounds(self, reference: float | None = None) -> tuple[float, float]:
        """The range in SI around ``reference`` (default: the row's reference)."""
        if self.kind == "reading":
            raise ValueError(f"{self.name} is a reading: it has values, not a range")
        if not self.relative:
            return (float(self.low), float(self.high))
        ref = float(self.reference if reference is None else reference)
        return (self.low * ref, self.high * ref)

    def grid(self, n: int, reference: float | None = None) -> NDArray[np.float64]:
        """``n`` points spanning the range on the row's scale, the reference added."""
        lo, hi = self.bounds(reference)
        pts = (np.geomspace(lo, hi, n) if self.scale == "log" else np.linspace(lo, hi, n))
        ref = float(self.reference if reference is None else reference)
        return np.unique(np.append(pts, ref))

    def to_unit(self, u: NDArray[np.float64] | float,
                reference: float | None = None) -> NDArray[np.float64]:
        """Map ``u`` in [0, 1] onto the range, on the row's scale (for sampling)."""
        lo, hi = self.bounds(reference)
        u = np.asarray(u, dtype=float)
        if self.scale == "log":
            return np.exp(np.log(lo) + u * (np.log(hi) - np.log(lo)))
        return lo + u * (hi - lo)

    def sobol_input(self, reference: float | None = None, name: str | None = None) -> Any:
        """The row as a :class:`gyrolib.sensitivity.SobolInput` over its range around
        ``reference`` (default: the row's reference), drawn on the row's scale (log-uniform
        on a log row, uniform on a linear one), named ``name`` (default: the row's name).

        Examples
        --------
        >>> from gyrolib import inputs
        >>> x = inputs.row("gc.C_as").sobol_input(2.0, name="C_as")
        >>> x.name, x.distribution, (x.low, x.high)
        ('C_as', 'loguniform', (0.2, 20.0))
        """
        from gyrolib.sensitivity import SobolInput

        if self.kind == "reading":
            raise ValueError(f"{self.name} is a reading: it has values, not a range")
        ref = float(self.reference if reference is None else reference)
        return SobolInput(self.name if name is None else name, self.symbol, ref,
                          *self.bounds(ref), "loguniform" if self.scale == "log" else "uniform",
                          self.reason)

    def show(self, value: float) -> str:
        """``value`` (SI) as text in the row's :attr:`shown` unit, with the unit."""
        if self.kind == "reading":
            return str(value)
        unit = self.shown or self.unit
        x = float(from_si(value, self.shown)) if self.shown else float(value)
        label = {"arcsec_paper": "″", "arcsec_paper/s": "″/s", "deg": "°", "deg/s": "°/s",
                 "deg/h": "°/h", "1": ""}.get(unit, unit)
        num = _number(x)
        sep = "" if label.startswith(("″", "°")) or not label else " "
        return f"{num}{sep}{label}"

    def as_dict(self) -> dict[str, Any]:
        """The row as plain data (JSON), with its reference and SI bounds."""
        out = {"name": self.name, "symbol": self.symbol, "owner": self.owner,
               "fields": list(self.fields), "kind": self.kind, "unit": self.unit,
               "reason": self.reason, "reference": self.reference}
        if self.kind == "reading":
            out["values"] = list(self.values)
        else:
            out.update(scale=self.scale, relative=self.relative, low=self.low,
                       high=self.high, bounds=list(self.bounds()))
        return out


_DECADE = "a printed noise-model value of a stand the book has not seen: a decade either way"
_SHEET = ("a data-sheet figure of the named part: a unit may be half to twice as good as its "
          "sheet's typical value")
_ZERO = ("not in the paper's model (zero at the reference, on both methods alike); up to the "
         "largest value the book deems plausible, the default prior of `calibrate`")


#: Every row, paper GC first, then the race's rival, then paper RSF.
INPUTS: Final[tuple[Input, ...]] = (
    # paper GC: the vibration filter (6), the random drift (7), the sensors
    Input("gc.alpha1", "α1", "GyrocompassParams", ("alpha1",), "uncertain", "rad/s",
          f"printed after Eq. (6); {_DECADE}", 0.1, 10.0),
    Input("gc.xi1", "ξ1", "GyrocompassParams", ("xi1",), "uncertain", "1",
          "printed after Eq. (6); an underdamped second-order filter, as (6) is written: "
          "0.1 to 1", 0.1, 1.0, relative=False, scale="linear"),
    Input("gc.sigma1_sq", "σ1²", "GyrocompassParams", ("sigma1_sq",), "uncertain", "m²/s⁴",
          f"printed after Eq. (6); {_DECADE}", 0.1, 10.0),
    Input("gc.alpha2", "α2", "GyrocompassParams", ("alpha2",), "uncertain", "rad/s",
          f"printed after Eq. (7); {_DECADE}", 0.1, 10.0),
    Input("gc.xi2", "ξ2", "GyrocompassParams", ("xi2",), "uncertain", "1",
          "printed after Eq. (7); an underdamped second-order filter: 0.1 to 1", 0.1, 1.0,
          relative=False, scale="linear"),
    Input("gc.sigma2_sq", "σ2²", "GyrocompassParams", ("sigma2_sq",), "uncertain", "rad²/s²",
          f"printed after Eq. (7), from its ref. [2]; {_DECADE}", 0.1, 10.0),
    Input("gc.omega_ub", "ω_ub", "GyrocompassParams", ("omega_ub",), "uncertain", "rad/s",
          f"printed after Eq. (6), from its ref. [6]; {_DECADE}", 0.1, 10.0),
    Input("gc.C_as", "C_as", "GyrocompassParams", ("C_as",), "uncertain", "rad² s",
          "printed before Eq. (8) with its unit garbled; a decade either way", 0.1, 10.0),
    Input("gc.C_incl", "C_in", "GyrocompassParams", ("C_incl_y", "C_incl_z"), "uncertain",
          "m²/s³", "printed before Eq. (8) with its unit garbled; both inclinometers; a decade "
          "either way", 0.1, 10.0),
    Input("gc.sigma_hf_scale", "κ", "GyrocompassParams", ("sigma_hf_scale",), "uncertain",
          "1", f"the relative error of H/f and the angle sensor's gain: {_ZERO}: 10⁻³, the "
          "tolerance the book gives the rival's torque sensor", 0.0, 1.0e-3, relative=False,
          scale="linear"),
    Input("gc.sigma_as_offset", "σ_off", "GyrocompassParams", ("sigma_as_offset",),
          "uncertain", "rad", f"the angle sensor's null offset: {_ZERO}: 20″", 0.0,
          20.0 * ARCSEC_PAPER, relative=False, scale="linear", shown="arcsec_paper"),
    Input("gc.sigma_incl_bias", "σ_b", "GyrocompassParams", ("sigma_incl_bias",),
          "uncertain", "m/s²", f"the inclinometers' biases: {_ZERO}: 0.5 mg", 0.0,
          0.5e-3 * G0, relative=False, scale="linear", shown="mg"),
    Input("gc.sigma_clock", "ε_t", "GyrocompassParams", ("sigma_clock",), "uncertain", "1",
          f"the logger's time-scale error: {_ZERO}: 10⁻⁴, a logger crystal's tolerance (a "
          "rate labelled wrong, 1024 Hz read as 1 kHz, is 2.4·10⁻²: stated, not a default)",
          0.0, 1.0e-4, relative=False, scale="linear"),
    # paper GC: the filter's priors (a choice of whoever runs the filter)
    Input("gc.sigma_gc0", "σ_ω(0)", "GyrocompassParams", ("sigma_gc0",), "operating",
          "rad/s", "the prior σ of ω_gc, printed in the parameter table: the user states the "
          "drift a gyro of the type may have; a decade either way", 0.1, 10.0,
          shown="arcsec_paper/s"),
    Input("gc.sigma_psi0", "σ_ψ(0)", "GyrocompassParams", ("sigma_psi0",), "operating", "rad",
          "the prior σ of ψ, printed in the parameter table; a decade either way", 0.1, 10.0,
          shown="arcsec_paper"),
    Input("gc.sigma_tilt0", "σ_δ,γ(0)", "GyrocompassParams", ("sigma_delta0", "sigma_gamma0"),
          "operating", "rad", "the prior σ of δ and γ, printed in the parameter table; a "
          "decade either way", 0.1, 10.0, shown="arcsec_paper"),
    # paper GC: the readings of the printed text
    Input("gc.measurement_noise", "R", "GyrocompassParams", ("measurement_noise",),
          "reading", "—", "the printed noise levels read as intensities (R = C/dt) or as "
          "variances (R = C): the unit is garbled", values=("intensity_over_dt", "variance")),
    Input("gc.shaping_p0", "P0(N)", "GyrocompassParams", ("shaping_p0",), "reading", "—",
          "the shaping filters' initial covariance: stationary, or zero (the parameter table "
          "gives none)", values=("stationary", "zero")),
    Input("gc.eq1_sign", "sign of (1)", "GyrocompassParams", ("eq1_sign",), "reading", "—",
          "the sign of Ω_h ψ in Eq. (1), lost in the extraction", values=("+", "-")),
    Input("gc.vertical_coupling", "F(2,5..6)", "GyrocompassParams", ("vertical_coupling",),
          "reading", "—", "the tilt columns of F: from Eq. (5), or as the F listing prints "
          "them", values=("eq5", "printed_F")),
    # the race's rival: the rate-sensor method of paper GC's ref. [3]
    Input("race.loop_bandwidth", "ω_b", "RateSensorProcedure", ("loop_bandwidth",),
          "uncertain", "rad/s", "the rebalance loop's bandwidth, not given by paper GC: a "
          "decade either way of the book's 10 rad/s", 0.1, 10.0),
    Input("race.rate_noise", "q_t", "RateSensorProcedure", ("rate_noise",), "uncertain",
          "rad²/s", "the torquer's white noise, not given: a decade either way of the gyro's "
          "own low-frequency drift intensity", 0.1, 10.0),
    Input("race.sigma_rot", "σ_ε", "RateSensorProcedure", ("sigma_rot",), "uncertain", "rad",
          "the turning error, not given: a decade either way of 1′", 0.1, 10.0, shown="arcmin"),
    Input("race.sigma_scale", "σ_k", "RateSensorProcedure", ("sigma_scale",), "uncertain",
          "1", "the torque sensor's scale error, not given (the reason the rival turns): a "
          "decade either way of 10⁻³", 0.1, 10.0),
    Input("race.quantization", "q", "RateSensorProcedure", ("quantization",), "uncertain",
          "rad", "the weight of one output pulse, not given: a decade either way of 0.01″",
          0.1, 10.0, shown="arcsec_paper"),
    Input("race.overhead", "T_rot + T_settle", "RateSensorProcedure", ("T_rot", "T_settle"),
          "operating", "s", "the turn and the settling after it: 10 s (a fast turn table) to "
          "60 s; paper GC's 'about 20 minutes' leaves room for more", 0.5, 3.0,
          scale="linear", mode="sum"),
    Input("race.sample_dt", "Δt_s", "RateSensorProcedure", ("sample_dt",), "operating", "s",
          "the rival's sample interval: 10 ms to 1 s", 0.1, 10.0),
    Input("race.vibration_frame", "frame of N1", "RateSensorProcedure", ("vibration_frame",),
          "reading", "—", "how sensors turned by 180° see the vibration: fixed to the "
          "carrier, or turning with the sensor", values=("carrier", "sensor")),
    # paper RSF: the data sheets it quotes
    Input("rsf.eps1", "ε1", "RollGyroSpec", ("sf_error",), "uncertain", "1",
          f"Table 1 (SiIMU02, 600 ppm); {_SHEET}", 0.5, 2.0, shown="ppm"),
    Input("rsf.eps0", "ε0", "RollGyroSpec", ("bias_instability",), "uncertain", "rad/s",
          f"Table 1 (SiIMU02, 100 °/h); {_SHEET}", 0.5, 2.0, shown="deg/h"),
    Input("rsf.gs_bias", "ε0,GS", "MemsGyroSpec", ("bias_repeatability", "bias_stability"),
          "uncertain", "rad/s", f"the GS gyro's table (GYPRO4300, 10 and 7 °/h, root sum of "
          f"squares); {_SHEET}", 0.5, 2.0, mode="norm", shown="deg/h"),
    Input("rsf.eps1_gs", "ε1,GS", "MemsGyroSpec", ("sf_error",), "uncertain", "1",
          f"the GS gyro's table (280 ppm); {_SHEET}", 0.5, 2.0, shown="ppm"),
    Input("rsf.encoder_error", "Δγ_enc", "EncoderSpec", ("position_error",), "uncertain",
          "rad", f"the worked example's 0.33° (AEDB-9340); {_SHEET}", 0.5, 2.0, shown="deg"),
    # paper RSF: its example's operating point
    Input("rsf.omega_x", "ω_x", "WorkedExample", ("omega_x",), "operating", "rad/s",
          "the worked example's roll rate, 900 °/s; the paper's rates reach 5400 °/s", 1.0,
          6.0, shown="deg/s"),
    Input("rsf.omega_unc", "ω_unc", "WorkedExample", ("omega_unc",), "operating", "rad/s",
          "the worked example's uncompensated GS rate, 300 °/s: a third to three times", 1 / 3,
          3.0, shown="deg/s"),
    Input("rsf.period", "Δt", "WorkedExample", ("period",), "operating", "s",
          "the worked example's correction interval, 5 s: 0.5 s to 30 s, the simulation's "
          "sweep", 0.1, 6.0),
    Input("rsf.table_rate", "ω", "WorkedExample", ("table_rate",), "operating", "rad/s",
          "Table 2's roll rate, 3600 °/s; the paper's rates span 1800-5400 °/s", 0.5, 1.5,
          shown="deg/s"),
    # paper RSF: the readings of the printed text
    Input("rsf.eps0_gs_digits", "ε0,GS print", "WorkedExample", ("eps0_gs_reading",),
          "reading", "—", "ε0,GS = √(σ_rep² + σ_stab²) as computed, or cut to the two digits "
          "the paper prints (0.0033 °/s)", values=("consistent", "two_digit")),
    Input("rsf.eps1_gs_unit", "ε1,GS unit", "WorkedExample", ("eps1_gs_unit",), "reading",
          "—", "ε1,GS = 280 read in ppm, or as 10⁻³ (the slip that gives the printed δK)",
          values=("ppm", "1e-3")),
    Input("rsf.omega_unc_model", "ω_unc(ω)", "WorkedExample", ("omega_unc_model",), "reading",
          "—", "how ω_unc changes with the roll rate: held at the example's value, limited by "
          "the GS motor (ω − 600 °/s, the book's simulation), or proportional to ω",
          values=("constant", "motor_limited", "proportional")),
)

_BY_NAME: Final[dict[str, Input]] = {r.name: r for r in INPUTS}
if len(_BY_NAME) != len(INPUTS):  # pragma: no cover - a table error
    raise RuntimeError("two rows of the table of inputs share a name")


def row(name: str) -> Input:
    """The row called ``name`` (``KeyError`` naming the known rows otherwise)."""
    try:
        return _BY_NAME[name]
    except KeyError:
        raise KeyError(f"no input {name!r} in the table; known: {', '.join(_BY_NAME)}") \
            from None


def rows(*, owner: str | None = None, kind: str | None = None,
         prefix: str | None = None) -> tuple[Input, ...]:
    """The rows of one owner, kind or name prefix (``"gc."``, ``"race."``, ``"rsf."``)."""
    return tuple(r for r in INPUTS if (owner is None or r.owner == owner)
                 and (kind is None or r.kind == kind)
                 and (prefix is None or r.name.startswith(prefix)))


def default_prior(name: str) -> float:
    """The default prior (σ, SI) that ``calibrate`` gives an instrument error the papers do not
    model: the upper end of its row's range (the largest plausible value)."""
    r = row(name)
    if r.kind != "uncertain" or r.relative or r.reference != 0.0:
        raise ValueError(f"{name} is not an instrument error with a zero reference")
    return float(r.high)


def factor_grid(name: str, n: int = 3) -> tuple[float, ...]:
    """``n`` factors spanning the range of the scale-type row ``name`` on its scale (for a
    grid or a sweep around any reference: the library's default grids are these).

    Examples
    --------
    >>> from gyrolib import inputs
    >>> inputs.factor_grid("gc.sigma1_sq")
    (0.1, 1.0, 10.0)
    """
    r = row(name)
    if r.kind == "reading" or not r.relative:
        raise ValueError(f"{name} has no range as factors of its reference")
    if isinstance(n, bool) or not isinstance(n, int) or n < 2:
        raise ValueError(f"n must be an integer >= 2; got {n!r}")
    g = np.geomspace(r.low, r.high, n) if r.scale == "log" else np.linspace(r.low, r.high, n)
    return tuple(float(x) for x in g)


def reference_objects() -> dict[str, Any]:
    """Every owner at its defaults: the reference point of every claim."""
    return {name: cls() for name, cls in OWNERS.items()}


def value_of(objects: Mapping[str, Any], r: Input) -> Any:
    """The value row ``r`` has in ``objects`` (an owner name → instance mapping)."""
    return _combine(r.mode, [getattr(objects[r.owner], f) for f in r.fields])



def apply(objects: Mapping[str, Any], changes: Mapping[str, Any]) -> dict[str, Any]:
    """``objects`` with each row named in ``changes`` set to its value (a new mapping; the
    instances are frozen dataclasses, replaced, never changed)."""
    out = dict(objects)
    for name, value in changes.items():
        r = row(name)
        obj = out[r.owner]
        if r.mode in ("sum", "norm"):
            old = [float(getattr(obj, f)) for f in r.fields]
            total = _combine(r.mode, old)
            share = (1.0 if r.mode == "sum" else math.sqrt(len(old))) * len(old)
            new = ({f: value * o / total for f, o in zip(r.fields, old, strict=True)} if total
                   else {f: value * len(old) / share for f in r.fields})
        else:
            new = {f: value for f in r.fields}
        out[r.owner] = dataclasses.replace(obj, **new)
    return out


def table_fingerprint(names: tuple[str, ...] | None = None) -> str:
    """A hash of what the table computes with (each row's name, fields, kind, range, scale
    and reference value or readings; not its words), over the rows ``names`` (default: every
    row): a result computed over those rows is valid only for the same fingerprint."""
    words = ("symbol", "reason", "unit")
    chosen = INPUTS if names is None else tuple(row(n) for n in names)
    blob = json.dumps([{k: v for k, v in r.as_dict().items() if k not in words}
                       for r in chosen], sort_keys=True, default=repr)
    return hashlib.sha256(blob.encode()).hexdigest()[:16]
