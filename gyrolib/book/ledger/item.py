"""One ledger item, the verdict vocabulary, and the one rule by which a computed value agrees
with a printed one.

**The agreement rule.**  A computed value *agrees with a print of n digits* when it lies
within half a unit of the print's last printed digit (boundary included), unless the item
states another tolerance together with its reason.  Every digit printed counts, trailing
zeros of an integer included: "20" is ±0.5, "0.0011" is ±0.00005, "3.3·10⁻³" is ±0.05·10⁻³.
A print stored as a float is read at its shortest representation (``4590.0`` is the print
"4590"); a print whose trailing zeros after the decimal point matter is passed as text
("0.50").  The comparison is exact on the binary value computed (no last-bit slack), so the
verdict does not depend on the CPU.  A tolerance that differs from the rule is never implicit:
:func:`agrees` refuses one without a reason, and the item's evidence quotes it.

**The one rule for every claim** (:func:`judge_claim`, applied by
:func:`gyrolib.claim_map.map_claim` over the table of inputs :mod:`gyrolib.inputs`).  A claim
is judged at its *reference point* — every input at its reference value, set for each kind of
input by the table's one written rule — and over the table: "holds" when it holds at the
reference point, at every one-at-a-time point of every input's range, at every sampled point
of the box of uncertain inputs and under every reading; "holds under conditions" when it
holds at the reference point but some input flips it (the conditions name each input and
where) and the share of the box where it holds may reach one half (the upper end of its 95 %
interval is at least 50 %); "holds only near the reference" when it holds at the reference
point but that upper end is below 50 %; "fails" when it fails at the reference point (the
conditions say where, if anywhere, it would hold).  A claim about several printed points
(times, rates) holds at a point only if it holds at every printed point.  The item's
``judged`` carries the evidence: the reference values, the thresholds, the share of the box
that holds (with its 95 % interval) and the status under each reading.  A qualitative claim
that no computation can decide is "not decidable", with the reason.  No claim's status is set
any other way.  What a reader sees is :attr:`LedgerItem.status_line`, the status with the
share of the box (:func:`gyrolib.claim_map.status_line`); programs read
:attr:`LedgerItem.status_code`, a stable code per status (:data:`STATUS_CODES`).

**Verdicts of a printed number from its candidates** (:func:`printed_verdict`).  The book's
consistent computation is compared first; where it does not agree, every *candidate cause*
the book can name (a truncation, a unit slip, an unstated reading of the paper) is computed
and compared by the same rule.  "differs: cause shown" when any candidate gives the print
(the print follows from that cause; a candidate that misses is refuted by this print, and the
evidence says which); "differs: bracketed" when none does but the print lies between the
candidates' values (where the candidates are readings of a choice the paper leaves open, the
book's own reading among them); "not reproducible" otherwise.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Sequence
from dataclasses import dataclass, fields
from decimal import Decimal, InvalidOperation

import numpy as np

from gyrolib import claim_map as _claim_map

__all__ = ["KINDS", "STATUSES", "STATUSES_BY_KIND", "STATUS_CODES", "STATUS_MARKS", "Candidate",
           "LedgerItem", "agrees", "half_unit", "judge_claim", "printed_verdict"]

#: What an item is, and the statuses that fit each kind (the verdict vocabulary):
#:
#: * ``printed number`` — a number the paper prints as a result;
#: * ``input`` — data the paper gives and uses (echoed, never "reproduced");
#: * ``inferred`` — a value the paper lost or never printed, deduced by the book;
#: * ``figure`` — a figure (redrawn by code; its printed numbers are items of their own);
#: * ``claim`` — a verbal claim (faster, holds when…, compensates…).
#:
#: ``differs: cause shown`` where any candidate cause the book names gives the printed value
#: (the others are refuted by the print); ``differs: bracketed`` where none does but the
#: printed value lies inside the range spanned by the candidates' values (see
#: :func:`printed_verdict`).
STATUSES_BY_KIND: dict[str, tuple[str, ...]] = {
    "printed number": ("reproduced", "differs: cause shown", "differs: bracketed",
                       "not reproducible"),
    "input": ("input",),
    "inferred": ("inferred",),
    "figure": ("redrawn",),
    "claim": _claim_map.CLAIM_STATUSES,
}
KINDS: tuple[str, ...] = tuple(STATUSES_BY_KIND)
#: Every allowed value of :attr:`LedgerItem.status`.
STATUSES: tuple[str, ...] = tuple(s for kind in KINDS for s in STATUSES_BY_KIND[kind])
#: A stable code per status, for programs (the ledger's JSON ``status_code``; its ``status``
#: carries the words a reader sees, :attr:`LedgerItem.status_line`).  A claim's codes are
#: :data:`gyrolib.claim_map.STATUS_CODES`: ``holds``, ``holds_in_part`` (holds under
#: conditions), ``holds_near_reference``, ``fails``, ``not_decidable``.
STATUS_CODES: dict[str, str] = {
    **{s: s.replace(": ", "_").replace(" ", "_") for s in STATUSES},
    **_claim_map.STATUS_CODES}
#: A sphinx-design badge role per status, so that the ledger page shows it at a glance.
STATUS_MARKS: dict[str, str] = {
    "reproduced": "{bdg-success}`reproduced`",
    "differs: cause shown": "{bdg-warning}`differs: cause shown`",
    "differs: bracketed": "{bdg-warning}`differs: bracketed`",
    "not reproducible": "{bdg-danger}`not reproducible`",
    "input": "{bdg-secondary}`input`",
    "inferred": "{bdg-info}`inferred`",
    "redrawn": "{bdg-secondary}`redrawn`",
    "holds": "{bdg-success}`holds`",
    "holds under conditions": "{bdg-warning}`holds under conditions`",
    "holds only near the reference": "{bdg-danger}`holds only near the reference`",
    "fails": "{bdg-danger}`fails`",
    "not decidable": "{bdg-secondary}`not decidable`",
}
#: Claim statuses that carry conditions (:func:`judge_claim`): required for "holds under
#: conditions" (where it stops holding), for "fails" (where, if anywhere, it would hold) and
#: for "not decidable" (why no computation can decide it).
_WITH_CONDITIONS = ("holds under conditions", "holds only near the reference", "fails",
                    "not decidable")


def _is_real(value: object) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


@dataclass(frozen=True)
class LedgerItem:
    """One printed item of a paper and its reproduction.

    ``chapter`` is the Sphinx document name of the chapter that shows it (e.g.
    ``"chapters/rsf_method"``) and ``anchor`` an optional label inside it, so the ledger page
    and tests can link to it.  ``kind`` and ``status`` follow :data:`STATUSES_BY_KIND`;
    ``conditions`` says where a claim stops holding (required for "holds under conditions")
    or where it would hold (required for "fails"; empty for every other status; both set by
    :func:`judge_claim`, the one rule for claims), ``evidence`` in one line what computation
    decides the status, and ``precision`` the significant digits to which
    ``reproduced_value`` is reported and cited (the same on every CPU: see
    :func:`gyrolib.book.ledger.rounded`).  ``judged`` (claims only): the claim over the table
    of inputs, ``{"reference", "thresholds", "share_holding", "readings", ...}``
    (:meth:`gyrolib.claim_map.ClaimMap.to_dict`, or ``None`` where a claim is not mapped),
    with ``"share_of"`` naming the part of the claim the share describes where the mapped
    margin judges only a part.

    Examples
    --------
    >>> it = LedgerItem(id="gc.x", paper="GC", location="Fig. 3", quantity="sigma", unit="1",
    ...                 paper_value=0.5, reproduced_value=0.49, status="reproduced", note="n",
    ...                 chapter="chapters/gc_filter", kind="printed number", evidence="e")
    >>> it.target
    'gc-filter'
    """

    id: str
    paper: str
    location: str
    quantity: str
    unit: str
    paper_value: float | str | None
    reproduced_value: float | None
    status: str
    note: str
    chapter: str
    kind: str
    evidence: str
    conditions: str = ""
    precision: int = 4
    anchor: str = ""
    judged: dict | None = None

    @property
    def status_code(self) -> str:
        """The stable code of :attr:`status`, for programs (:data:`STATUS_CODES`), e.g.
        ``"holds_near_reference"``."""
        return STATUS_CODES[self.status]

    @property
    def status_line(self) -> str:
        """The status as a reader sees it: a mapped claim's carries the share of the box
        where it holds, with its 95 % interval (:func:`gyrolib.claim_map.status_line`, e.g.
        "holds only near the reference (0 % of the box, 0–6 %)"); every other item's is its
        status."""
        judged = self.judged or {}
        share = judged.get("share_holding")
        if self.kind != "claim" or not share:
            return self.status
        # "share_of": the part of the claim the mapped margin judges, where it is a part
        return _claim_map.status_line(self.status, share, judged.get("share_of", ""))

    @property
    def status_html(self) -> str:
        """:attr:`status_line` for a page: the share tagged with the item's id
        (:func:`gyrolib.quote.tag`), so that a test of the built book finds every quoted
        form of it."""
        judged = self.judged or {}
        share = judged.get("share_holding")
        if self.kind != "claim" or not share:
            return self.status
        return _claim_map.status_line(self.status, share, judged.get("share_of", ""),
                                      claim=self.id, html=True)

    @property
    def conditions_html(self) -> str:
        """:attr:`conditions` for a page: the map's thresholds and share tagged with the
        item's id (:func:`gyrolib.quote.tag`); the rest as it is."""
        q = (self.judged or {}).get("conditions_quoted")
        if not q or not q.get("plain"):
            return self.conditions
        return self.conditions.replace(q["plain"], q["html"])

    def quote_threshold(self, input: str, form: str = "both", html: bool = True) -> str:
        """The map's threshold of ``input`` as every page quotes it
        (:func:`gyrolib.claim_map.quote_threshold`; ``form``: ``"both"``, ``"value"`` or
        ``"factor"``), tagged with the item's id for a page when ``html``.  A ``ValueError``
        names the inputs that flip the claim when ``input`` does not."""
        ths = {t["input"]: t for t in ((self.judged or {}).get("thresholds") or ())}
        if input not in ths:
            raise ValueError(f"{self.id} has no threshold of {input!r}; its thresholds: "
                           f"{sorted(ths)}")
        return _claim_map.quote_threshold(self.id, ths[input], html=html, form=form)

    def quote_share(self, html: bool = True) -> str:
        """The share of the box where the claim holds, as every page quotes it
        (:meth:`gyrolib.claim_map.Share.short`), tagged with the item's id when ``html``."""
        share = (self.judged or {}).get("share_holding")
        if not share:
            raise ValueError(f"{self.id} has no share of the box")
        return _claim_map.Share(**share).short(self.id, html)

    @property
    def target(self) -> str:
        """The book label to link to: ``anchor``, or else the chapter's own label (the
        chapter file name with ``_`` as ``-``, e.g. ``chapters/gc_model`` → ``gc-model``)."""
        return self.anchor or self.chapter.rsplit("/", 1)[-1].replace("_", "-")

    def __post_init__(self) -> None:
        for f in fields(self):
            if f.name not in ("paper_value", "reproduced_value", "precision", "judged"):
                value = getattr(self, f.name)
                if not isinstance(value, str):
                    raise TypeError(f"{f.name} must be a str; got {type(value).__name__}")
        if self.kind not in KINDS:
            raise ValueError(f"kind of {self.id} must be one of {KINDS}; got {self.kind!r}")
        allowed = STATUSES_BY_KIND[self.kind]
        if self.status not in allowed:
            raise ValueError(f"status of {self.id} (kind {self.kind!r}) must be one of "
                             f"{allowed}; got {self.status!r}")
        has_conditions = bool(self.conditions.strip())
        if ((self.status in _WITH_CONDITIONS and not has_conditions)
                or (self.status not in _WITH_CONDITIONS and has_conditions)):
            raise ValueError(f"conditions of {self.id} must be non-empty for 'holds under "
                             "conditions' (where it stops holding) and for 'fails' (where it "
                             f"would hold), and empty otherwise; got {self.conditions!r}")
        if not self.evidence.strip() or "\n" in self.evidence:
            raise ValueError(f"evidence of {self.id} must be one non-empty line")
        if (not isinstance(self.precision, int) or isinstance(self.precision, bool)
                or not 1 <= self.precision <= 15):
            raise ValueError(f"precision of {self.id} must be an int in [1, 15]; "
                             f"got {self.precision!r}")
        if self.judged is not None:
            if self.kind != "claim" or not isinstance(self.judged, dict):
                raise ValueError(f"judged of {self.id} must be a dict, and only for a claim")
            missing = {"reference", "thresholds", "share_holding", "readings"} - set(
                self.judged)
            if missing:
                raise ValueError(f"judged of {self.id} lacks {sorted(missing)}")
        if self.kind == "claim" and self.status.startswith("holds "):
            # the status may not say more than the share of the box supports (the one rule)
            share = (self.judged or {}).get("share_holding")
            hi = None if not share else float(share["hi"])
            near = "holds only near the reference"
            if self.status == near and hi is None:
                raise ValueError(f"status of {self.id}: {near!r} needs the share of the box "
                                 "where it holds (judged['share_holding'])")
            if hi is not None and (self.status == near) != (
                    hi < _claim_map.HALF_OF_THE_BOX):
                right = near if hi < _claim_map.HALF_OF_THE_BOX else "holds under conditions"
                raise ValueError(f"status of {self.id} must be {right!r}: the upper end of "
                                 f"the share of the box where it holds is {hi:.3g} (the rule "
                                 f"sets {near!r} below "
                                 f"{_claim_map.HALF_OF_THE_BOX:g}); got {self.status!r}")
        if self.paper not in ("GC", "RSF"):
            raise ValueError(f"paper must be 'GC' or 'RSF'; got {self.paper!r}")
        pv = self.paper_value
        if not (pv is None or isinstance(pv, str) or _is_real(pv)):
            raise TypeError("paper_value must be a real number, a str or None; "
                            f"got {type(pv).__name__}")
        if _is_real(pv) and not math.isfinite(pv):
            raise ValueError(f"paper_value of {self.id} must be finite; got {pv}")
        rv = self.reproduced_value
        if not (rv is None or _is_real(rv)):
            raise TypeError("reproduced_value must be a real number or None; "
                            f"got {type(rv).__name__}")
        if rv is not None and not math.isfinite(rv):
            raise ValueError(f"reproduced_value of {self.id} must be finite")


# The agreement rule --------------------------------------------------------------------------
def _print_decimal(printed: object) -> Decimal:
    """The print as an exact decimal with its printed digits (see the module docstring)."""
    if isinstance(printed, str):
        text = printed.strip().replace(",", ".")
        try:
            d = Decimal(text)
        except InvalidOperation:
            raise ValueError(f"printed must be a number as printed (e.g. '0.0011', '4590', "
                             f"'3.3e-3'); got {printed!r}") from None
        if not d.is_finite():
            raise ValueError(f"printed must be finite; got {printed!r}")
        return d
    if not _is_real(printed):
        raise TypeError(f"printed must be a real number or its printed text (str); "
                        f"got {type(printed).__name__}")
    x = float(printed)  # type: ignore[arg-type]
    if not math.isfinite(x):
        raise ValueError(f"printed must be finite; got {x}")
    # The shortest representation: 4590.0 is the print "4590", 0.0011 the print "0.0011".
    return Decimal(int(x)) if x.is_integer() and abs(x) < 1e16 else Decimal(repr(x))


def half_unit(printed: float | str) -> float:
    """Half a unit of the last printed digit of ``printed``: the default tolerance of the
    agreement rule.

    Parameters
    ----------
    printed : float or str
        The printed number, as a float (read at its shortest representation) or as the text
        printed (with ``.`` or ``,`` as the decimal sign, ``e`` for a power of ten).

    Returns
    -------
    float
        ``0.5·10^k`` where ``10^k`` is the place of the last printed digit.

    Examples
    --------
    >>> half_unit("20"), half_unit(0.0011), half_unit("3.3e-3"), half_unit(4590.0)
    (0.5, 5e-05, 5e-05, 0.5)
    >>> half_unit("0,50")
    0.005
    """
    d = _print_decimal(printed)
    return float(Decimal(5).scaleb(d.as_tuple().exponent - 1))  # type: ignore[operator]


def agrees(value: float | None, printed: float | str, *, tolerance: float | None = None,
           reason: str = "") -> bool:
    """Whether a computed ``value`` agrees with ``printed`` by the ledger's one rule.

    The value agrees when ``|value − printed|`` is at most half a unit of the print's last
    printed digit (:func:`half_unit`), boundary included; or, when the item states another
    ``tolerance``, at most that tolerance, which then needs its ``reason``.  The comparison
    is exact on the binary value.  ``None`` (nothing computed) never agrees.

    Parameters
    ----------
    value : float or None
        The computed value, in the print's unit.
    printed : float or str
        The printed number (see :func:`half_unit`).
    tolerance : float, optional
        Another tolerance (> 0, in the print's unit) that the item states.
    reason : str, optional
        Why the item departs from the rule; required with ``tolerance``.

    Returns
    -------
    bool

    Examples
    --------
    >>> agrees(20.49, "20"), agrees(20.51, "20"), agrees(0.00137, 0.0011)
    (True, False, False)
    >>> agrees(4594.0, 4590.0, tolerance=5.0, reason="four significant digits, as 21.25")
    True
    """
    d_print = _print_decimal(printed)
    if tolerance is None:
        if reason:
            raise ValueError("reason must be empty when no tolerance is stated (the rule "
                             "needs no reason)")
        tol = Decimal(5).scaleb(d_print.as_tuple().exponent - 1)  # type: ignore[operator]
    else:
        if not _is_real(tolerance) or not math.isfinite(tolerance) or tolerance <= 0:
            raise ValueError(f"tolerance must be a finite number > 0; got {tolerance!r}")
        if not isinstance(reason, str) or not reason.strip():
            raise ValueError("reason must say why the item states a tolerance other than "
                             "half a unit of the last printed digit; got none")
        tol = Decimal(float(tolerance))
    if value is None:
        return False
    if not _is_real(value):
        raise TypeError(f"value must be a real number or None; got {type(value).__name__}")
    if not math.isfinite(value):
        raise ValueError(f"value must be finite; got {value}")
    return abs(Decimal(float(value)) - d_print) <= tol


@dataclass(frozen=True)
class Candidate:
    """A candidate cause of a printed number that the book computes differently: a short
    ``name`` (as the evidence quotes it) and the ``value`` it gives, in the print's unit.

    Examples
    --------
    >>> Candidate("ε0,GS cut to two digits", 0.033).name
    'ε0,GS cut to two digits'
    """

    name: str
    value: float

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name.strip():
            raise TypeError(f"name must be a non-empty str; got {self.name!r}")
        if not _is_real(self.value) or not math.isfinite(self.value):
            raise ValueError(f"value of candidate {self.name!r} must be a finite real number; "
                             f"got {self.value!r}")


def printed_verdict(consistent: float, printed: float | str,
                    candidates: Sequence[Candidate] = (), *, tolerance: float | None = None,
                    reason: str = "") -> str:
    """The status of a printed number from the book's consistent value and the candidate
    causes it names, by the one agreement rule (:func:`agrees`).

    * ``"reproduced"``: the consistent value agrees with the print;
    * ``"differs: cause shown"``: it does not, and a candidate agrees: the print follows
      from that cause (when several agree, whichever is true; a candidate that misses is
      refuted by this print, which the item's evidence lists);
    * ``"differs: bracketed"``: no candidate agrees, but the print lies within the range of
      the candidates' values (list the book's own reading among them when the candidates
      are readings of an open choice);
    * ``"not reproducible"``: otherwise.

    Parameters
    ----------
    consistent : float
        The value the book computes from the paper's data and model.
    printed : float or str
        The printed number.
    candidates : sequence of Candidate, optional
        The causes the book names for a difference, each with the value it gives.
    tolerance, reason : optional
        A stated tolerance and its reason (see :func:`agrees`).

    Returns
    -------
    str
        One of the statuses of a printed number.

    Examples
    --------
    >>> printed_verdict(0.0339, 0.033, [Candidate("cut", 0.033), Candidate("12 °/h", 0.0333)])
    'differs: cause shown'
    >>> printed_verdict(0.2034, 0.198, [Candidate("cut", 0.198), Candidate("12 °/h", 0.2)])
    'differs: cause shown'
    >>> printed_verdict(0.00137, 0.0011, [Candidate("stationary P0", 0.00137),
    ...                                   Candidate("zero P0", 0.00084)])
    'differs: bracketed'
    """
    if not all(isinstance(c, Candidate) for c in candidates):
        raise TypeError("candidates must be a sequence of Candidate")
    rule = {"tolerance": tolerance, "reason": reason}
    if agrees(consistent, printed, **rule):
        return "reproduced"
    hits = [agrees(c.value, printed, **rule) for c in candidates]
    if any(hits):
        return "differs: cause shown"
    values = [c.value for c in candidates]
    p = float(_print_decimal(printed))
    if values and min(values) <= p <= max(values):
        return "differs: bracketed"
    return "not reproducible"


# The one rule for every claim ------------------------------------------------------------------
def judge_claim(holds_at_reference: bool, holds_over_ranges: bool,
                conditions: str = "", share: object = None) -> tuple[str, str]:
    """The status of a claim by the ledger's one rule, and the conditions the item carries.

    * ``"holds"``: it holds at the reference point and at every point of the plausible
      ranges (every one-at-a-time point, every box point, every reading);
    * ``"holds under conditions"``: it holds at the reference point but fails at some point
      of the ranges; ``conditions`` says where it stops (required);
    * ``"holds only near the reference"``: so, but the upper end of the 95 % interval of
      ``share`` (the box's share where it holds) is below one half;
    * ``"fails"``: it fails at the reference point; ``conditions`` says where, if anywhere, it
      would hold (required).

    The reference point is the paper's own example where it gives one, else the book's
    defended defaults; the ranges are the item's stated plausible ranges, which contain the
    reference point (so a claim cannot hold over them and fail at it).

    Parameters
    ----------
    holds_at_reference : bool
        Whether the claim holds at its reference point.
    holds_over_ranges : bool
        Whether it holds everywhere in its plausible ranges.
    conditions : str
        Where it stops holding, or where it would hold; ignored for ``"holds"``.
    share : gyrolib.claim_map.Share or dict, optional
        The share of the box where it holds (``None``: not sampled).

    Returns
    -------
    (str, str)
        The status and the conditions the item carries (empty for ``"holds"``).

    Examples
    --------
    >>> judge_claim(True, True)
    ('holds', '')
    >>> judge_claim(True, False, "below 12 s of overhead it fails")[0]
    'holds under conditions'
    >>> judge_claim(True, False, "κ flips it", {"value": 0.0, "lo": 0.0, "hi": 0.06})[0]
    'holds only near the reference'
    >>> judge_claim(False, False, "it would hold above 2557 °/s")[0]
    'fails'
    >>> judge_claim(False, True)   # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: holds_over_ranges cannot be True when holds_at_reference is False...
    """
    for name, value in (("holds_at_reference", holds_at_reference),
                        ("holds_over_ranges", holds_over_ranges)):
        if not isinstance(value, bool | np.bool_):
            raise TypeError(f"{name} must be a bool; got {type(value).__name__}")
    if not isinstance(conditions, str):
        raise TypeError(f"conditions must be a str; got {type(conditions).__name__}")
    if holds_over_ranges and not holds_at_reference:
        raise ValueError("holds_over_ranges cannot be True when holds_at_reference is False: "
                         "the ranges contain the reference point")
    if holds_at_reference and holds_over_ranges:
        return "holds", ""
    status = _claim_map.claim_status(bool(holds_at_reference), True, share)
    if not conditions.strip():
        raise ValueError(f"conditions must say where the claim stops holding or where it "
                         f"would hold (status {status!r}); got none")
    return status, conditions
