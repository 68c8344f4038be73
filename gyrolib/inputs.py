"""The one table of inputs: every unstated, uncertain or interpreted input of both papers.

Each paper declares its own rows beside its dataclasses (:mod:`gyrolib.gc.inputs`,
:mod:`gyrolib.rsf.inputs`); this module sits above both papers and collects them (no module
of :mod:`gyrolib.gc` or :mod:`gyrolib.rsf` imports it: a study that needs the table is
handed its rows).  The row type and what is read from rows are :mod:`gyrolib.input_rows`.

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

from collections.abc import Mapping
from typing import Any, Final

from gyrolib import input_rows
from gyrolib.gc import inputs as _gc
from gyrolib.input_rows import KINDS, Input, value_of
from gyrolib.rsf import inputs as _rsf

__all__ = ["INPUTS", "KINDS", "OWNERS", "Input", "apply", "default_prior", "factor_grid",
           "reference_objects",
           "row", "rows", "table_fingerprint", "value_of"]

#: The dataclasses whose fields the rows set, by the name the rows use.
OWNERS: Final[dict[str, type]] = {**_gc.OWNERS, **_rsf.OWNERS}

#: Every row, paper GC first, then the race's rival, then paper RSF.
INPUTS: Final[tuple[Input, ...]] = _gc.ROWS + _rsf.ROWS

_BY_NAME: Final[dict[str, Input]] = input_rows.by_name(INPUTS)


def row(name: str) -> Input:
    """The row called ``name`` (``KeyError`` naming the known rows otherwise)."""
    return input_rows.row(_BY_NAME, name)


def rows(*, owner: str | None = None, kind: str | None = None,
         prefix: str | None = None) -> tuple[Input, ...]:
    """The rows of one owner, kind or name prefix (``"gc."``, ``"race."``, ``"rsf."``)."""
    return input_rows.select(INPUTS, owner=owner, kind=kind, prefix=prefix)


def default_prior(name: str) -> float:
    """The default prior (σ, SI) that ``calibrate`` gives an instrument error the papers do not
    model: the upper end of its row's range (the largest plausible value)."""
    return input_rows.default_prior(_BY_NAME, name)


def factor_grid(name: str, n: int = 3) -> tuple[float, ...]:
    """``n`` factors spanning the range of the scale-type row ``name`` on its scale (for a
    grid or a sweep around any reference: the library's default grids are these).

    Examples
    --------
    >>> from gyrolib import inputs
    >>> inputs.factor_grid("gc.sigma1_sq")
    (0.1, 1.0, 10.0)
    """
    return input_rows.factor_grid(_BY_NAME, name, n)


def reference_objects() -> dict[str, Any]:
    """Every owner at its defaults: the reference point of every claim."""
    return {name: cls() for name, cls in OWNERS.items()}


def apply(objects: Mapping[str, Any], changes: Mapping[str, Any]) -> dict[str, Any]:
    """``objects`` with each row named in ``changes`` set to its value (a new mapping; the
    instances are frozen dataclasses, replaced, never changed)."""
    return input_rows.apply(_BY_NAME.values(), objects, changes)


def table_fingerprint(names: tuple[str, ...] | None = None) -> str:
    """A hash of what the table computes with (each row's name, fields, kind, range, scale
    and reference value or readings; not its words), over the rows ``names`` (default: every
    row): a result computed over those rows is valid only for the same fingerprint."""
    return input_rows.fingerprint(INPUTS if names is None else _BY_NAME.values(), names)
