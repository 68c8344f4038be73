"""The row of a table of inputs, and what is read from a set of rows.

A paper's package declares its own rows beside its dataclasses (:mod:`gyrolib.gc.inputs`,
:mod:`gyrolib.rsf.inputs`); :mod:`gyrolib.inputs` collects them into the one table of both
papers and says what the kinds, ranges and reference values mean.  This module knows neither
paper: an :class:`Input` carries the dataclass whose fields it sets (``owner_type``), and the
functions here take the rows they read.

Examples
--------
>>> from dataclasses import dataclass
>>> from gyrolib.input_rows import Input, factor_grid
>>> @dataclass(frozen=True)
... class Spec:
...     noise: float = 2.0
>>> r = Input("x.noise", "N", "Spec", ("noise",), "uncertain", "1", "a stated rule", 0.5,
...           2.0, owner_type=Spec)
>>> r.reference, r.bounds()
(2.0, (1.0, 4.0))
>>> factor_grid((r,), "x.noise")
(0.5, 1.0, 2.0)
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from gyrolib import quote as _quote
from gyrolib.sensitivity.study import SobolInput
from gyrolib.units import from_si

__all__ = ["KINDS", "Input", "apply", "by_name", "combine", "default_prior", "factor_grid",
           "fingerprint", "reference_objects", "row", "select", "value_of"]

#: The kinds of input (see :mod:`gyrolib.inputs`).
KINDS: Final[tuple[str, ...]] = ("uncertain", "operating", "reading")


def combine(mode: str, vals: list[Any]) -> Any:
    if mode == "sum":
        return float(sum(vals))
    if mode == "norm":
        return float(math.sqrt(sum(float(x) ** 2 for x in vals)))
    if any(x != vals[0] for x in vals):
        raise ValueError(f"the fields of one row must have the same value; got {vals}")
    return vals[0]



def _number(x: float) -> str:
    """The declared precision of every quoted value (:func:`gyrolib.quote.number`)."""
    return _quote.number(x)


@dataclass(frozen=True)
class Input:
    """One row of the table of inputs.

    ``name`` (``"gc.sigma1_sq"``), ``symbol`` (as the book prints it), ``owner`` (the name
    of the dataclass ``owner_type`` whose fields the row sets) and ``fields`` (every field
    the row sets; several fields take the same value, or keep their proportions and add up
    to it, ``mode="sum"``, or have it as their root sum of squares, ``mode="norm"``),
    ``kind`` (one of :data:`KINDS`), ``unit`` (SI), ``reason`` (why this range: the paper's
    print, a cited source or a stated rule).  Numeric rows: ``low``, ``high`` (factors of
    the reference when ``relative``, else absolute SI values) and ``scale``; reading rows:
    ``values``, the book's reading first.  ``shown``: the unit (of
    :data:`gyrolib.units.UNITS`) in which the book's text shows the row's values (default:
    SI, ``unit``).
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
    owner_type: type | None = field(default=None, repr=False, compare=False)

    def __post_init__(self) -> None:
        if not (isinstance(self.owner_type, type) and dataclasses.is_dataclass(self.owner_type)
                and self.owner_type.__name__ == self.owner):
            raise ValueError(f"owner_type of {self.name} must be the dataclass {self.owner!r}; "
                             f"got {self.owner_type!r}")
        names = {f.name for f in dataclasses.fields(self.owner_type)}
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
        defaults = [next(f.default for f in dataclasses.fields(self.owner_type)
                         if f.name == name) for name in self.fields]
        return combine(self.mode, defaults)

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


def by_name(rows: Iterable[Input]) -> dict[str, Input]:
    """``rows`` by name (``ValueError`` if two share a name)."""
    out: dict[str, Input] = {}
    for r in rows:
        if not isinstance(r, Input):
            raise TypeError(f"rows must hold Input rows; got {type(r).__name__}")
        if r.name in out:
            raise ValueError(f"two rows of the table of inputs share the name {r.name!r}")
        out[r.name] = r
    return out


def row(rows: Iterable[Input], name: str) -> Input:
    """The row of ``rows`` (the rows, or a name → row mapping, :func:`by_name`) called
    ``name`` (``KeyError`` naming the known rows otherwise)."""
    known = rows if isinstance(rows, dict) else by_name(rows)
    try:
        return known[name]
    except KeyError:
        raise KeyError(f"no input {name!r} in the table; known: {', '.join(known)}") \
            from None


def select(rows: Iterable[Input], *, owner: str | None = None, kind: str | None = None,
           prefix: str | None = None) -> tuple[Input, ...]:
    """The rows of one owner, kind or name prefix (``"gc."``, ``"race."``, ``"rsf."``)."""
    return tuple(r for r in rows if (owner is None or r.owner == owner)
                 and (kind is None or r.kind == kind)
                 and (prefix is None or r.name.startswith(prefix)))


def default_prior(rows: Iterable[Input], name: str) -> float:
    """The default prior (σ, SI) that ``calibrate`` gives an instrument error the papers do not
    model: the upper end of its row's range (the largest plausible value)."""
    r = row(rows, name)
    if r.kind != "uncertain" or r.relative or r.reference != 0.0:
        raise ValueError(f"{name} is not an instrument error with a zero reference")
    return float(r.high)


def factor_grid(rows: Iterable[Input], name: str, n: int = 3) -> tuple[float, ...]:
    """``n`` factors spanning the range of the scale-type row ``name`` on its scale (for a
    grid or a sweep around any reference: the library's default grids are these)."""
    r = row(rows, name)
    if r.kind == "reading" or not r.relative:
        raise ValueError(f"{name} has no range as factors of its reference")
    if isinstance(n, bool) or not isinstance(n, int) or n < 2:
        raise ValueError(f"n must be an integer >= 2; got {n!r}")
    g = np.geomspace(r.low, r.high, n) if r.scale == "log" else np.linspace(r.low, r.high, n)
    return tuple(float(x) for x in g)


def reference_objects(rows: Iterable[Input]) -> dict[str, Any]:
    """Every owner of ``rows`` at its defaults: the reference point of every claim."""
    owners: dict[str, type] = {}
    for r in rows:
        owners.setdefault(r.owner, r.owner_type)
    return {name: cls() for name, cls in owners.items()}


def value_of(objects: Mapping[str, Any], r: Input) -> Any:
    """The value row ``r`` has in ``objects`` (an owner name → instance mapping)."""
    return combine(r.mode, [getattr(objects[r.owner], f) for f in r.fields])


def apply(rows: Iterable[Input], objects: Mapping[str, Any],
          changes: Mapping[str, Any]) -> dict[str, Any]:
    """``objects`` with each row of ``rows`` named in ``changes`` set to its value (a new
    mapping; the instances are frozen dataclasses, replaced, never changed)."""
    known = by_name(rows)
    out = dict(objects)
    for name, value in changes.items():
        r = row(known, name)
        obj = out[r.owner]
        if r.mode in ("sum", "norm"):
            old = [float(getattr(obj, f)) for f in r.fields]
            total = combine(r.mode, old)
            share = (1.0 if r.mode == "sum" else math.sqrt(len(old))) * len(old)
            new = ({f: value * o / total for f, o in zip(r.fields, old, strict=True)} if total
                   else {f: value * len(old) / share for f in r.fields})
        else:
            new = {f: value for f in r.fields}
        out[r.owner] = dataclasses.replace(obj, **new)
    return out


def fingerprint(rows: Iterable[Input], names: tuple[str, ...] | None = None) -> str:
    """A hash of what ``rows`` compute with (each row's name, fields, kind, range, scale and
    reference value or readings; not its words), over the rows ``names`` (default: every
    row): a result computed over those rows is valid only for the same fingerprint."""
    words = ("symbol", "reason", "unit")
    rows = tuple(rows)
    chosen = rows if names is None else tuple(row(rows, n) for n in names)
    blob = json.dumps([{k: v for k, v in r.as_dict().items() if k not in words}
                       for r in chosen], sort_keys=True, default=repr)
    return hashlib.sha256(blob.encode()).hexdigest()[:16]
