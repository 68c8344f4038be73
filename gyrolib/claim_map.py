"""Every claim judged over the table of inputs by one rule, and the inputs that flip it.

A :class:`Claim` is a *margin*: a function of the owners' instances (see
:mod:`gyrolib.inputs`) whose sign is the verdict (``> 0``: the claim holds there; ``nan``
counts as failing), and the rows of the table it reads.  :func:`map_claim` judges it:

* **at the reference point** (every row at its reference: the fields' defaults, or a user's
  own instances);
* **one input at a time** over each numeric row's range: a grid of ``n_grid`` points on the
  row's scale (the reference among them) brackets every change of status, then bisection on
  the same scale narrows each to a relative width ``rtol`` (an input may flip a claim more than
  once); each boundary is a :class:`Threshold` with the side on which the claim holds;
* **over the box** of the uncertain rows: ``n_box`` points drawn independently on each row's
  scale (operating rows and readings at their reference), with the seed stored; the share
  that holds, with its 95 % Wilson interval (:class:`Share`) — descriptive, never the status;
* **under each reading**, alone, the others at the reference;
* **at isolated points**, for a row the claim names in ``searches`` (:class:`PointSearch`):
  a claim that fails only at isolated values of an input (paper RSF's finer encoder, which
  gains nothing where the interval is a whole number of the GS's half-turns) has no
  threshold a grid and a bisection could find (a bisection converges on one such point and
  calls it a boundary).  Its margin is evaluated at each of the search's points instead, and
  the result is a statement of its own (:class:`IsolatedFailures`): the failing points found,
  how they were searched, the search's resolution (the largest step between searched
  points), and that it holds at every other searched point.

The status (:data:`STATUS_RULE`, :func:`claim_status`): *holds* when the claim holds at the
reference, at every one-at-a-time point, at every box point and under every reading; *holds
under conditions* when it holds at the reference but some input flips it, and the box's
share where it holds may reach one half (its 95 % interval's upper end is at least 50 %);
*holds only near the reference* when it holds at the reference but in less than half of
the box (that upper end below 50 %); *fails* when it fails at the reference.  Each status
has a stable code for programs (:data:`STATUS_CODES`), and :func:`status_line` gives the
words a reader sees, the share included.

Examples
--------
A claim of two inputs with a known boundary (the synthetic claims of the tests):

>>> from gyrolib import claim_map, inputs
>>> c = claim_map.Claim("demo", claim_map.demo_margin, ("gc.sigma1_sq", "gc.C_as"),
...                     "2 - sigma1_sq/reference")
>>> m = claim_map.map_claim(c, n_box=32)
>>> m.status, [(t.input, round(t.factor, 2), t.holds_when) for t in m.thresholds]
('holds under conditions', [('gc.sigma1_sq', 2.0, 'below')])
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any, Final

import numpy as np

from gyrolib import inputs as _inputs
from gyrolib import quote as _quote
from gyrolib._executor import check_executor, map_ordered
from gyrolib._repr import compact_repr

__all__ = [
    "CLAIM_STATUSES",
    "HALF_OF_THE_BOX",
    "STATUS_CODES",
    "STATUS_RULE",
    "Claim",
    "ClaimMap",
    "FingerprintPoint",
    "IsolatedFailures",
    "PointSearch",
    "Share",
    "Threshold",
    "check_fingerprint",
    "check_map",
    "claim_status",
    "demo_margin",
    "extend_box",
    "fingerprint_points",
    "flip_share",
    "map_claim",
    "margin_at",
    "percent",
    "predicted_holds",
    "quote_threshold",
    "status_line",
    "wilson_interval",
]

#: The one rule, in words (quoted by the ledger page).
STATUS_RULE: Final[str] = (
    "holds: it holds at the reference point, at every one-at-a-time point of every range, at "
    "every sampled point of the box of uncertain inputs and under every reading; holds under "
    "conditions: it holds at the reference point but some input flips it (each named, with "
    "where), and the share of the box where it holds may reach one half (the upper end of its "
    "95 % interval is at least 50 %); holds only near the reference: it holds at the "
    "reference point, but the upper end of that interval is below 50 %; fails: it fails at "
    "the reference point (the thresholds say where it would hold).  The status a reader sees "
    "carries the share, e.g. \"holds only near the reference (0 % of the box, 0–6 %)\"")

#: The statuses of a claim judged by the rule (:func:`claim_status`), in the order of the
#: rule, and "not decidable" for a claim no computation can decide.
CLAIM_STATUSES: Final[tuple[str, ...]] = ("holds", "holds under conditions",
                                          "holds only near the reference", "fails",
                                          "not decidable")
#: A stable code per claim status, for programs (the ledger's JSON ``status_code``): the
#: words may gain detail, the code does not change.
STATUS_CODES: Final[dict[str, str]] = {
    "holds": "holds", "holds under conditions": "holds_in_part",
    "holds only near the reference": "holds_near_reference", "fails": "fails",
    "not decidable": "not_decidable"}
#: Below this upper end of the share's 95 % interval a claim that holds at the reference
#: holds "only near the reference": the evidence does not allow it half of the box.
HALF_OF_THE_BOX: Final[float] = 0.5

#: z of a two-sided 95 % interval.
_Z95: Final[float] = 1.959963984540054


def wilson_interval(k: int, n: int, z: float = _Z95) -> tuple[float, float]:
    """The Wilson score interval of a binomial share ``k/n`` (95 % by default).

    Examples
    --------
    >>> [round(x, 4) for x in wilson_interval(32, 64)]
    [0.381, 0.619]
    >>> wilson_interval(0, 10)[0], round(wilson_interval(10, 10)[1], 12)
    (0.0, 1.0)
    """
    if n <= 0 or not 0 <= k <= n:
        raise ValueError(f"need 0 <= k <= n and n > 0; got k={k}, n={n}")
    p = k / n
    d = 1.0 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return (max(0.0, c - h), min(1.0, c + h))


@dataclass(frozen=True)
class PointSearch:
    """A search of one numeric row for the isolated points where a claim fails.

    ``input`` (the row), ``points`` (a module-level function of the owners' mapping giving the
    values, SI, to evaluate: picklable for an executor), ``how`` (how they were chosen, in
    words, for the statement) and ``quantum`` (the resolution to which the margin itself reads
    the input, e.g. a correction interval in whole samples; 0: exactly): a value within half a
    quantum of a failing point is that point.
    """

    input: str
    points: Callable[[Mapping[str, Any]], Sequence[float]]
    how: str
    quantum: float = 0.0


@dataclass(frozen=True)
class IsolatedFailures:
    """Where a claim fails at isolated values of one input (:class:`PointSearch`), the others
    at the reference: ``points`` (SI) where it fails, ``searched`` (how many points were
    evaluated), ``how`` (how they were chosen), ``resolution`` (the largest step between
    searched points, SI), ``quantum`` (see :class:`PointSearch`), ``unit``, and
    ``isolated`` (each failing point's neighbours in the search hold: no failing interval,
    which a threshold would state)."""

    input: str
    points: tuple[float, ...]
    searched: int
    how: str
    resolution: float
    quantum: float
    unit: str
    isolated: bool

    def fails_at(self, value: float) -> bool:
        """Whether ``value`` (SI) is one of the failing points (to half a quantum)."""
        tol = 0.5 * self.quantum if self.quantum else 0.0
        return any(abs(value - p) <= tol + 1e-12 * max(abs(p), abs(value))
                   for p in self.points)

    def text(self, limit: int = 8) -> str:
        """The statement in words."""
        r = _inputs.row(self.input)
        shown = [r.show(p) for p in self.points[:limit]]
        more = (f", … ({len(self.points)} points in all, the last {r.show(self.points[-1])})"
                if len(self.points) > limit else "")
        where = (f"{'only at the isolated' if self.isolated else 'at the'} values "
                 f"{', '.join(shown)}{more}" if self.points else "at none of them")
        return (f"Varied alone, {r.symbol} was searched at {self.searched} points ({self.how}; "
                f"resolution {r.show(self.resolution)}): the claim fails {where}, and holds at "
                f"every other point searched.")

    def as_dict(self) -> dict[str, Any]:
        return {"input": self.input, "points": list(self.points), "searched": self.searched,
                "how": self.how, "resolution": self.resolution, "quantum": self.quantum,
                "unit": self.unit, "isolated": self.isolated}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> IsolatedFailures:
        return cls(d["input"], tuple(float(x) for x in d["points"]), int(d["searched"]),
                   d["how"], float(d["resolution"]), float(d["quantum"]), d["unit"],
                   bool(d["isolated"]))


@dataclass(frozen=True)
class Claim:
    """A claim as a margin over the table of inputs.

    ``id`` (the ledger's item id), ``margin`` (a module-level function of the owners'
    mapping, picklable for an executor; ``> 0`` where the claim holds), ``inputs`` (the
    rows it reads: every row that can move the margin), ``meaning`` (what the margin is, in
    words), ``unit`` (of the margin) and ``per_reading`` (also find every threshold under
    each other reading: for claims cheap enough, so that a threshold's dependence on a
    reading is stated) and ``searches`` (:class:`PointSearch`: the rows at whose isolated
    values the claim may fail, searched point by point instead of bracketed and bisected).
    """

    id: str
    margin: Callable[[Mapping[str, Any]], float]
    inputs: tuple[str, ...]
    meaning: str
    unit: str = "1"
    per_reading: bool = False
    searches: tuple[PointSearch, ...] = ()

    def __post_init__(self) -> None:
        for name in self.inputs:
            _inputs.row(name)  # KeyError naming the known rows
        for sr in self.searches:
            if not isinstance(sr, PointSearch) or sr.input not in self.inputs \
                    or _inputs.row(sr.input).kind == "reading":
                raise ValueError(f"{self.id}: a search must be a PointSearch of one of the "
                                 f"claim's numeric inputs; got {sr!r}")


@dataclass(frozen=True)
class Threshold:
    """Where one input, varied alone, flips a claim: ``value`` (SI), ``factor`` (relative to
    the reference; ``nan`` for a zero reference), ``unit`` and ``holds_when`` (``"below"`` or
    ``"above"``: the side of ``value`` on which the claim holds)."""

    input: str
    value: float
    factor: float
    unit: str
    holds_when: str

    def as_dict(self) -> dict[str, Any]:
        return {"input": self.input, "value": self.value,
                "factor": None if math.isnan(self.factor) else self.factor,
                "unit": self.unit, "holds_when": self.holds_when}


@dataclass(frozen=True)
class Share:
    """The share of the box of uncertain inputs where the claim holds: ``value`` with its 95 %
    Wilson interval ``[lo, hi]``, from ``n`` points drawn with ``seed``."""

    value: float
    lo: float
    hi: float
    n: int
    seed: int

    def as_dict(self) -> dict[str, Any]:
        return {"value": self.value, "lo": self.lo, "hi": self.hi, "n": self.n,
                "seed": self.seed}

    def text(self, claim: str | None = None, html: bool = False) -> str:
        """``"62 % of the box, 50–73 % (95 % interval, 64 points)"``: :meth:`short` and
        how many points it rests on."""
        return f"{self.short(claim, html)} (95 % interval, {self.n} points)"

    def short(self, claim: str | None = None, html: bool = False) -> str:
        """``"62 % of the box, 50–73 %"``: the share and its 95 % interval, as a claim's
        status line carries them (:func:`gyrolib.quote.share`; tagged with ``claim`` for a
        page when ``html``)."""
        return _quote.tag(_quote.share(self.value, self.lo, self.hi), claim, "share",
                          html=html)


def percent(share: float) -> str:
    """A share (0–1) in per cent as the book quotes it (:func:`gyrolib.quote.percent`).

    >>> percent(0.0038), percent(0.59375)
    ('0.4', '59')
    """
    return _quote.percent(share)


def claim_status(holds_at_reference: bool, flips: bool,
                 share: Share | Mapping[str, Any] | None = None) -> str:
    """The status of a claim by the one rule (:data:`STATUS_RULE`).

    Parameters
    ----------
    holds_at_reference : bool
        Whether the claim holds at the reference point.
    flips : bool
        Whether some input flips it within its range (a threshold, a failing box point, an
        isolated failing point or a reading).
    share : Share or dict, optional
        The share of the box where it holds (``None``: no box drawn).

    Returns
    -------
    str
        One of :data:`CLAIM_STATUSES` (never "not decidable").

    Examples
    --------
    >>> claim_status(True, True, Share(0.6, 0.47, 0.71, 64, 1))
    'holds under conditions'
    >>> claim_status(True, True, Share(0.3, 0.2, 0.42, 64, 1))
    'holds only near the reference'
    >>> claim_status(True, False), claim_status(False, True)
    ('holds', 'fails')
    """
    if not holds_at_reference:
        return "fails"
    if not flips:
        return "holds"
    hi = None if share is None else (share.hi if isinstance(share, Share) else share["hi"])
    if hi is not None and float(hi) < HALF_OF_THE_BOX:
        return "holds only near the reference"
    return "holds under conditions"


def status_line(status: str, share: Share | Mapping[str, Any] | None = None,
                part: str = "", *, claim: str | None = None, html: bool = False) -> str:
    """The words a reader sees for a claim's ``status``, the share of the box included (a
    claim that holds everywhere needs none; "fails" says where in the box it would hold).
    ``part`` names the part of the claim the share describes, when its margin judges only
    part of it (then also said for "holds").  ``claim`` and ``html``: the share tagged for a
    page (:func:`gyrolib.quote.tag`).

    Examples
    --------
    >>> status_line("holds only near the reference", Share(0.0, 0.0, 0.0566, 64, 1))
    'holds only near the reference (0 % of the box, 0–6 %)'
    >>> status_line("fails", {"value": 0.09375, "lo": 0.0437, "hi": 0.19, "n": 64, "seed": 1})
    'fails (holds at 9 % of the box, 4–19 %)'
    >>> status_line("holds", Share(1.0, 0.94, 1.0, 64, 1))
    'holds'
    >>> status_line("holds under conditions", Share(1.0, 0.94, 1.0, 64, 1), "its first half")
    'holds under conditions (its first half: 100 % of the box, 94–100 %)'
    """
    if status not in CLAIM_STATUSES:
        raise ValueError(f"status must be one of {CLAIM_STATUSES}; got {status!r}")
    if share is None or status == "not decidable" or (status == "holds" and not part):
        return status
    sh = share if isinstance(share, Share) else Share(**share)
    lead = f"{part}: " if part else ""
    return (f"{status} ({lead}{'holds at ' if status == 'fails' else ''}"
            f"{sh.short(claim, html)})")


def quote_threshold(claim: str | None, t: Threshold | Mapping[str, Any], *,
                    html: bool = False, reference: str = "the reference",
                    form: str = "both") -> str:
    """A threshold as every page and command quotes it (:mod:`gyrolib.quote`): its value in
    the input's unit and its factor of the reference, ``"2.24·10⁻⁶ m²/s⁴ (1.2 × the
    reference)"`` (``form="both"``), or only ``"value"`` or ``"factor"``; each number tagged
    with ``claim`` and the input for a page when ``html``.

    Examples
    --------
    >>> t = Threshold("gc.sigma1_sq", 2.2397596724680975e-06, 1.204171866918332, "m^2/s^4",
    ...               "below")
    >>> quote_threshold("gc.faster_percent", t)
    '2.24·10⁻⁶ m²/s⁴ (1.2 × the reference)'
    >>> quote_threshold("gc.faster_percent", t, form="factor", html=True)
    '<span data-claim="gc.faster_percent" data-input="gc.sigma1_sq" \
data-quantity="threshold" data-form="factor">1.2</span>'
    """
    if form not in ("both", "value", "factor"):
        raise ValueError(f"form must be 'both', 'value' or 'factor'; got {form!r}")
    d = t.as_dict() if isinstance(t, Threshold) else t
    r = _inputs.row(d["input"])
    fac = d.get("factor")
    fac = None if fac is None or math.isnan(float(fac)) else float(fac)
    val = _quote.tag(r.show(float(d["value"])), claim, "threshold", r.name, form="value",
                     html=html)
    if form == "value" or (form == "both" and fac is None):
        return val
    if fac is None:
        raise ValueError(f"the threshold of {r.name} has no factor (a zero reference)")
    f = _quote.tag(_quote.factor(fac), claim, "threshold", r.name, form="factor", html=html)
    return f if form == "factor" else f"{val} ({f} × {reference})"


@dataclass(frozen=True)
class ClaimMap:
    """A claim judged over the table (:func:`map_claim`).

    ``status`` by :data:`STATUS_RULE`; ``margin`` at the reference; ``reference`` (row →
    value); ``thresholds``; ``share_holding`` (``None`` when no uncertain row is read or
    no box was drawn); ``readings`` (row → {reading → "holds" or "fails"} at the reference
    point); ``sweeps`` (row → the grid's ``[value, margin]`` pairs); ``box_fails`` (how
    many box points fail); ``fingerprint`` (a few points with their margins, recomputed to
    check that a stored map is still valid: :func:`check_fingerprint`).
    """

    claim: str
    meaning: str
    status: str
    margin: float
    reference: dict[str, Any]
    thresholds: tuple[Threshold, ...]
    share_holding: Share | None
    readings: dict[str, dict[str, str]]
    sweeps: dict[str, list[list[float]]] = field(default_factory=dict)
    box_fails: int = 0
    fingerprint: tuple[dict[str, Any], ...] = ()
    settings: dict[str, Any] = field(default_factory=dict)
    reading_thresholds: dict[str, dict[str, list[dict[str, Any]]]] = field(
        default_factory=dict)
    isolated: tuple[IsolatedFailures, ...] = ()

    def flipping_inputs(self) -> tuple[str, ...]:
        """Every input that flips the claim: the thresholds' rows and the readings under
        which the status differs from the reference's."""
        ref = "holds" if self.margin > 0 else "fails"
        out = [t.input for t in self.thresholds]
        out += [f.input for f in self.isolated if f.points]
        out += [r for r, st in self.readings.items() if any(s != ref for s in st.values())]
        return tuple(dict.fromkeys(out))

    def threshold_texts(self, given: bool = False, html: bool = False) -> list[str]:
        """Each threshold as the conditions word it, e.g. ``"σ1² below 2.24·10⁻⁶ m²/s⁴
        (1.2 × the reference)"`` (``given``: "the given value"; ``html``: each number
        tagged for a page, :func:`gyrolib.quote.tag`)."""
        ref = "the given value" if given else "the reference"
        return [f"{_inputs.row(t.input).symbol} {t.holds_when} "
                f"{quote_threshold(self.claim, t, html=html, reference=ref)}"
                for t in self.thresholds]

    def conditions(self, given: bool = False, html: bool = False) -> str:
        """Where the claim flips, in sentences (empty when it holds everywhere).  ``given``:
        the map was drawn around a user's own values, not the book's reference point, and the
        sentences say so ("the given value").  ``html``: every threshold and share tagged for
        a page (:func:`gyrolib.quote.tag`)."""
        others = "the others at their given values" if given else "the others at the reference"
        parts = self.threshold_texts(given, html)
        text = ""
        if parts:
            verb = f"It holds, {others}, for " if self.margin > 0 else \
                f"It would hold, {others}, for "
            text = verb + "; ".join(parts) + "."
        for f in self.isolated:
            if f.points:
                text += " " + f.text()
        flips = [(r, st) for r, st in self.readings.items()
                 if any(s != ("holds" if self.margin > 0 else "fails") for s in st.values())]
        for r, st in flips:
            text += (f" Under the readings of {_inputs.row(r).symbol}: "
                     + ", ".join(f"{k}: {s}" for k, s in st.items()) + ".")
        for r, by_value in self.reading_thresholds.items():
            for val, ths in by_value.items():
                if [t["input"] for t in ths] == [t.input for t in self.thresholds] and all(
                        abs(t["value"] / u.value - 1) < 1e-2 if u.value else t["value"] == 0
                        for t, u in zip(ths, self.thresholds, strict=True)):
                    continue   # the same thresholds: nothing to add
                where = "; ".join(f"{_inputs.row(t['input']).symbol} {t['holds_when']} "
                                  f"{_inputs.row(t['input']).show(t['value'])}" for t in ths)
                text += (f" Under {_inputs.row(r).symbol} = {val}: "
                         + (f"it flips for {where}." if ths else
                            "no input flips it within its range, one at a time."))
        if self.share_holding is not None and (self.box_fails or self.margin <= 0):
            text += (f" Over the box of uncertain inputs it holds at "
                     f"{self.share_holding.text(self.claim, html)}.")
        return text.strip()

    def to_dict(self) -> dict[str, Any]:
        return {"claim": self.claim, "meaning": self.meaning, "status": self.status,
                "margin": self.margin, "reference": dict(self.reference),
                "thresholds": [t.as_dict() for t in self.thresholds],
                "share_holding": (None if self.share_holding is None
                                  else self.share_holding.as_dict()),
                "readings": self.readings, "sweeps": self.sweeps,
                "box_fails": self.box_fails, "fingerprint": list(self.fingerprint),
                "settings": self.settings, "reading_thresholds": self.reading_thresholds,
                "isolated": [f.as_dict() for f in self.isolated]}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> ClaimMap:
        share = d.get("share_holding")
        m = cls(claim=d["claim"], meaning=d["meaning"], status=d["status"],
                   margin=float(d["margin"]), reference=dict(d["reference"]),
                   thresholds=tuple(Threshold(t["input"], float(t["value"]),
                                              math.nan if t["factor"] is None
                                              else float(t["factor"]), t["unit"],
                                              t["holds_when"]) for t in d["thresholds"]),
                   share_holding=None if share is None else Share(**share),
                   readings={k: dict(v) for k, v in d["readings"].items()},
                   sweeps={k: [list(map(float, p)) for p in v]
                           for k, v in d.get("sweeps", {}).items()},
                   box_fails=int(d.get("box_fails", 0)),
                   fingerprint=tuple(d.get("fingerprint", ())),
                   settings=dict(d.get("settings", {})),
                   reading_thresholds=dict(d.get("reading_thresholds", {})),
                   isolated=tuple(IsolatedFailures.from_dict(f)
                                  for f in d.get("isolated", ())))
        # the status follows from the map's parts by the rule of this version (a map stored
        # under an older wording of the rule reads the same)
        return replace(m, status=claim_status(m.margin > 0, _flips(m), m.share_holding))


def _holds(m: float) -> bool:
    return bool(m > 0.0)  # nan fails


def _flips(m: ClaimMap) -> bool:
    """Whether some input flips the map's claim within its range (the rule's "flips")."""
    return bool(m.thresholds) or m.box_fails > 0 or bool(m.flipping_inputs())


def margin_at(claim: Claim, objects: Mapping[str, Any], changes: Mapping[str, Any]) -> float:
    """The claim's margin with the rows in ``changes`` set (the others as in ``objects``)."""
    return float(claim.margin(_inputs.apply(objects, changes)))


def _bisect(claim: Claim, objects: Mapping[str, Any], r: _inputs.Input, a: float, b: float,
            holds_a: bool, rtol: float) -> float:
    """The boundary between ``a`` (status ``holds_a``) and ``b`` (the other), to ``rtol``."""
    while True:
        if r.scale == "log":
            if b / a - 1.0 <= rtol:
                return math.sqrt(a * b)
            mid = math.sqrt(a * b)
        else:
            if abs(b - a) <= rtol * max(abs(a), abs(b)):
                return 0.5 * (a + b)
            mid = 0.5 * (a + b)
        if _holds(margin_at(claim, objects, {r.name: mid})) == holds_a:
            a = mid
        else:
            b = mid


def _sweep(claim: Claim, objects: Mapping[str, Any], name: str, n_grid: int,
           rtol: float, ref_margin: float) -> tuple[list[list[float]], list[Threshold]]:
    """One row alone over its range: the grid's margins and every boundary."""
    r = _inputs.row(name)
    ref = float(_inputs.value_of(objects, r))
    xs = r.grid(n_grid, reference=ref if r.relative else None)
    ms = [ref_margin if x == ref else margin_at(claim, objects, {name: float(x)}) for x in xs]
    out = []
    for i in range(len(xs) - 1):
        h0, h1 = _holds(ms[i]), _holds(ms[i + 1])
        if h0 != h1:
            x = _bisect(claim, objects, r, float(xs[i]), float(xs[i + 1]), h0, rtol)
            out.append(Threshold(name, x, x / ref if ref else math.nan, r.unit,
                                 "below" if h0 else "above"))
    return [[float(x), float(m)] for x, m in zip(xs, ms, strict=True)], out


def _search(claim: Claim, objects: Mapping[str, Any], name: str,
            xs: Sequence[float]) -> list[float]:
    return [margin_at(claim, objects, {name: float(x)}) for x in xs]


def _isolated(sr: PointSearch, xs: np.ndarray, ms: Sequence[float]) -> IsolatedFailures:
    """The statement of a search: the failing points among ``xs`` (sorted) and whether each
    is isolated (its neighbours in the search hold)."""
    bad = [i for i, m in enumerate(ms) if not _holds(m)]
    isolated = all((i == 0 or _holds(ms[i - 1])) and (i == len(ms) - 1 or _holds(ms[i + 1]))
                   for i in bad)
    step = float(np.max(np.diff(xs))) if len(xs) > 1 else 0.0
    return IsolatedFailures(sr.input, tuple(float(xs[i]) for i in bad), len(xs), sr.how, step,
                            float(sr.quantum), _inputs.row(sr.input).unit, isolated)


def _box(claim: Claim, objects: Mapping[str, Any], names: Sequence[str],
         values: np.ndarray) -> list[float]:
    return [margin_at(claim, objects, dict(zip(names, map(float, row), strict=True)))
            for row in values]


def _reading(claim: Claim, objects: Mapping[str, Any], name: str, value: str) -> float:
    return margin_at(claim, objects, {name: value})


def map_claim(claim: Claim, objects: Mapping[str, Any] | None = None, *, n_grid: int = 9,
              rtol: float = 1e-3, n_box: int = 64, seed: int = 2026,
              executor: object = None, chunk: int = 8,
              monotone: Sequence[str] = ()) -> ClaimMap:
    """Judge ``claim`` at the reference point and over the table (see the module docstring).

    Parameters
    ----------
    claim : Claim
    objects : mapping, optional
        Owner name → instance: the reference point (default: every owner at its defaults,
        :func:`gyrolib.inputs.reference_objects`).  Ranges of relative rows are factors of
        these instances' values, so a user's own parameters get their own map.
    n_grid : int, default 9
        Grid points per numeric row (on its scale; the reference is added).
    rtol : float, default 1e-3
        Relative width to which each threshold is bisected.
    n_box : int, default 64
        Points drawn in the box of uncertain rows (0: none).
    seed : int, default 2026
        Seed of the box's draws (stored with the share).
    executor : concurrent.futures.Executor, optional
        Where the one-at-a-time sweeps and the box's chunks run (``None``: here).
    chunk : int, default 8
        Box points per task.
    monotone : sequence of str, default ()
        Numeric rows in which the caller knows the margin to be monotone: their grid is the
        range's two ends and the reference (a coarser bracket: a monotone margin changes
        sign at most once, between the reference and the end whose status differs), then
        the same bisection.

    Returns
    -------
    ClaimMap
    """
    _check_map_arguments(claim, n_grid, rtol, n_box, chunk)
    ex = check_executor(executor)
    objs = dict(_inputs.reference_objects() if objects is None else objects)
    rows = [_inputs.row(n) for n in claim.inputs]
    ref_margin = float(claim.margin(objs))
    searched = {sr.input: sr for sr in claim.searches}
    # a searched row is not bracketed: its statement is the search's (see the docstring)
    numeric = [r.name for r in rows if r.kind != "reading" and r.name not in searched]
    uncertain = [r.name for r in rows if r.kind == "uncertain"]
    readings = [r for r in rows if r.kind == "reading"]
    box = _draw_box(objs, uncertain, n_box, seed)
    mono = frozenset(monotone)
    if not mono <= set(numeric):
        raise ValueError(f"monotone must name numeric rows of {claim.id} "
                         f"({', '.join(numeric)}); got {sorted(mono - set(numeric))}")
    plan = _MapPlan(claim, objs, numeric, uncertain, readings, searched, box, ref_margin,
                    n_grid, rtol, chunk, mono)
    results = iter(map_ordered(_call, plan.tasks(), ex))
    sweeps: dict[str, list[list[float]]] = {}
    thresholds: list[Threshold] = []
    for name in numeric:
        grid, ths = next(results)
        sweeps[name] = grid
        thresholds += ths
    box_margins: list[float] = []
    for _ in range(0, box.shape[0], chunk):
        box_margins += next(results)
    ref_status = "holds" if _holds(ref_margin) else "fails"
    read_status = {r.name: {r.values[0]: ref_status,
                            **{val: "holds" if _holds(next(results)) else "fails"
                               for val in r.values[1:]}} for r in readings}
    isolated = [_isolated(searched[n], xs,
                          [m for _ in range(0, xs.size, 4 * chunk) for m in next(results)])
                for n, xs in plan.search_xs.items()]
    per_reading: dict[str, dict[str, list[dict[str, Any]]]] = {}
    for name, val in plan.alts:
        ths2 = [t for _ in numeric for t in next(results)[1]]
        per_reading.setdefault(name, {})[val] = [t.as_dict() for t in ths2]
    share, n_fail = _box_share(box_margins, seed)
    flips = bool(thresholds) or n_fail > 0 or any(f.points for f in isolated) or any(
        s != ref_status for st in read_status.values() for s in st.values())
    status = claim_status(ref_status == "holds", flips, share)
    fp = _first_fingerprint(claim, objs, ref_margin, uncertain, box, box_margins, isolated)
    reference = {r.name: _inputs.value_of(objs, r) for r in rows}
    return ClaimMap(claim=claim.id, meaning=claim.meaning, status=status, margin=ref_margin,
                    reference=reference, thresholds=tuple(thresholds), share_holding=share,
                    readings=read_status, sweeps=sweeps, box_fails=n_fail,
                    fingerprint=tuple(fp),
                    settings={"n_grid": n_grid, "rtol": rtol, "n_box": n_box, "seed": seed,
                              "table": _inputs.table_fingerprint(claim.inputs),
                              **({"monotone": sorted(mono)} if mono else {})},
                    reading_thresholds=per_reading, isolated=tuple(isolated))


def extend_box(claim: Claim, m: ClaimMap, n_box: int,
               objects: Mapping[str, Any] | None = None, *, executor: object = None,
               chunk: int = 8) -> ClaimMap:
    """``m`` with its box share drawn from ``n_box`` points: the same seed, the stored
    ``m.share_holding.n`` points kept (the draws of a seed are a prefix of any longer draw
    with it) and only the new ones evaluated.

    The result is what :func:`map_claim` gives with ``n_box`` (the sweeps, thresholds,
    readings and fingerprint do not depend on the box's size), at the cost of the new points
    alone: a share whose 95 % interval is too wide gets more points, never another seed.  The
    stored map must agree with the code (:func:`check_map`); the caller checks it.

    Parameters
    ----------
    claim : Claim
        The claim ``m`` maps (its id and rows must be the map's).
    m : ClaimMap
        A map with a box share (``m.share_holding`` not ``None``).
    n_box : int
        Points of the new share, at least ``m.share_holding.n``.
    objects : mapping, optional
        The reference point ``m`` was drawn around (default: the owners' defaults).
    executor : concurrent.futures.Executor, optional
        Where the new points' chunks run (``None``: here).
    chunk : int, default 8
        Box points per task.

    Returns
    -------
    ClaimMap

    Examples
    --------
    >>> from gyrolib import claim_map
    >>> c = claim_map.Claim("demo", claim_map.demo_margin, ("gc.sigma1_sq", "gc.C_as"),
    ...                     "2 - sigma1_sq/reference")
    >>> small = claim_map.map_claim(c, n_box=16)
    >>> big = claim_map.extend_box(c, small, 48)
    >>> big.share_holding == claim_map.map_claim(c, n_box=48).share_holding
    True
    """
    if not isinstance(claim, Claim) or claim.id != m.claim \
            or set(claim.inputs) != set(m.reference):
        raise ValueError(f"claim must be the Claim the map {m.claim!r} was drawn for, over "
                         "the same rows")
    if m.share_holding is None:
        raise ValueError(f"{m.claim}: the map has no box share to extend")
    old = m.share_holding
    if not isinstance(n_box, int) or isinstance(n_box, bool) or n_box < old.n:
        raise ValueError(f"n_box must be an int >= the map's {old.n} points; got {n_box!r}")
    ex = check_executor(executor)
    objs = dict(_inputs.reference_objects() if objects is None else objects)
    uncertain = [n for n in claim.inputs if _inputs.row(n).kind == "uncertain"]
    new = _draw_box(objs, uncertain, n_box, old.seed)[old.n:]
    tasks = [(_box, (claim, objs, uncertain, new[i:i + chunk]))
             for i in range(0, new.shape[0], chunk)]
    margins = [x for part in map_ordered(_call, tasks, ex) for x in part]
    n_fail = m.box_fails + sum(not _holds(x) for x in margins)
    lo, hi = wilson_interval(n_box - n_fail, n_box)
    share = Share((n_box - n_fail) / n_box, lo, hi, n_box, old.seed)
    grown = replace(m, share_holding=share, box_fails=n_fail,
                    settings={**m.settings, "n_box": n_box})
    return replace(grown, status=claim_status(grown.margin > 0, _flips(grown), share))


def _check_map_arguments(claim: Any, n_grid: Any, rtol: Any, n_box: Any, chunk: Any) -> None:
    """:func:`map_claim`'s door: the claim's type and the search's settings."""
    if not isinstance(claim, Claim):
        raise TypeError(f"claim must be a Claim; got {type(claim).__name__}")
    for name, val, lo in (("n_grid", n_grid, 2), ("n_box", n_box, 0), ("chunk", chunk, 1)):
        if not isinstance(val, int) or isinstance(val, bool) or val < lo:
            raise ValueError(f"{name} must be an int >= {lo}; got {val!r}")
    if not 0.0 < rtol < 0.5:
        raise ValueError(f"rtol must be in (0, 0.5); got {rtol!r}")


def _draw_box(objs: Mapping[str, Any], uncertain: Sequence[str], n_box: int,
              seed: int) -> np.ndarray:
    """The box's draws (one row a point), on each uncertain row's scale around ``objs``."""
    rng = np.random.default_rng(seed)
    box = np.empty((n_box if uncertain else 0, len(uncertain)))
    if box.size:
        u = rng.random(box.shape)
        for j, name in enumerate(uncertain):
            r = _inputs.row(name)
            ref = float(_inputs.value_of(objs, r))
            box[:, j] = r.to_unit(u[:, j], reference=ref if r.relative else None)
    return box


@compact_repr
@dataclass(frozen=True)
class _MapPlan:
    """The tasks of one map, in the order :func:`map_claim` reads their results: the
    one-at-a-time sweeps, the box's chunks, the readings, the searches, then the sweeps
    again under each other reading (a per-reading claim)."""

    claim: Claim
    objs: Mapping[str, Any]
    numeric: Sequence[str]
    uncertain: Sequence[str]
    readings: Sequence[Any]
    searched: Mapping[str, Any]
    box: np.ndarray
    ref_margin: float
    n_grid: int
    rtol: float
    chunk: int
    mono: frozenset[str]

    @property
    def search_xs(self) -> dict[str, np.ndarray]:
        return {n: np.unique(np.asarray(sr.points(self.objs), dtype=float))
                for n, sr in self.searched.items()}

    @property
    def alts(self) -> list[tuple[str, Any]]:
        return ([(r.name, val) for r in self.readings for val in r.values[1:]]
                if self.claim.per_reading else [])

    def grid_of(self, name: str) -> int:
        return 2 if name in self.mono else self.n_grid

    def tasks(self) -> list[tuple[Callable[..., Any], tuple[Any, ...]]]:
        c, o, chunk = self.claim, self.objs, self.chunk
        tasks: list[tuple[Callable[..., Any], tuple[Any, ...]]] = []
        tasks += [(_sweep, (c, o, n, self.grid_of(n), self.rtol, self.ref_margin))
                  for n in self.numeric]
        tasks += [(_box, (c, o, self.uncertain, self.box[i:i + chunk]))
                  for i in range(0, self.box.shape[0], chunk)]
        tasks += [(_reading, (c, o, r.name, val)) for r in self.readings
                  for val in r.values[1:]]
        for n, xs in self.search_xs.items():
            tasks += [(_search, (c, o, n, xs[i:i + 4 * chunk]))
                      for i in range(0, xs.size, 4 * chunk)]
        for name, val in self.alts:
            o2 = _inputs.apply(o, {name: val})
            m2 = float(c.margin(o2))
            tasks += [(_sweep, (c, o2, n, self.grid_of(n), self.rtol, m2))
                      for n in self.numeric]
        return tasks


def _box_share(box_margins: Sequence[float], seed: int) -> tuple[Share | None, int]:
    """The share of the box's points where the claim holds, with its Wilson interval, and
    the number of failing points (``None`` and 0 without a box)."""
    if not box_margins:
        return None, 0
    ok = sum(_holds(m) for m in box_margins)
    lo, hi = wilson_interval(ok, len(box_margins))
    return Share(ok / len(box_margins), lo, hi, len(box_margins), seed), len(box_margins) - ok


def _first_fingerprint(claim: Claim, objs: Mapping[str, Any], ref_margin: float,
                       uncertain: Sequence[str], box: np.ndarray,
                       box_margins: Sequence[float],
                       isolated: Sequence[IsolatedFailures]) -> list[dict[str, Any]]:
    """The map's own check points: the reference, the box's first two points, and the
    first failing point of each search (the statement's check)."""
    fp: list[dict[str, Any]] = [{"changes": {}, "margin": ref_margin}]
    for i in range(min(2, box.shape[0])):
        fp.append({"changes": dict(zip(uncertain, map(float, box[i]), strict=True)),
                   "margin": float(box_margins[i])})
    for f in isolated:
        if f.points:
            fp.append({"changes": {f.input: f.points[0]},
                       "margin": margin_at(claim, objs, {f.input: f.points[0]})})
    return fp


def _call(fn: Callable[..., Any], args: tuple[Any, ...]) -> Any:
    return fn(*args)


def predicted_holds(m: ClaimMap, name: str, value: float) -> bool:
    """Whether the map says the claim holds with row ``name`` at ``value`` (SI) and every
    other input at the reference: the thresholds of ``name`` split its range into pieces,
    and each threshold says on which side the claim holds; at a failing point of a search
    (:class:`IsolatedFailures`) the claim fails."""
    if any(f.input == name and f.fails_at(value) for f in m.isolated):
        return False
    ths = sorted((t for t in m.thresholds if t.input == name), key=lambda t: t.value)
    if not ths:
        return bool(m.margin > 0)
    for t in ths:
        if value < t.value:
            return t.holds_when == "below"
    return ths[-1].holds_when == "above"


def flip_share(m: ClaimMap, name: str) -> float:
    """The share of row ``name``'s range (on its scale) over which the claim's status
    differs from the reference's, from the map's thresholds (0 when it never flips)."""
    r = _inputs.row(name)
    ref = m.reference[name]
    lo, hi = r.bounds(ref if r.relative else None)
    cuts = sorted(t.value for t in m.thresholds if t.input == name)
    if not cuts:
        return 0.0

    def tr(x: float) -> float:
        return math.log(x) if r.scale == "log" else x
    ref_holds = m.margin > 0
    flipped = 0.0
    for a, b in itertools.pairwise([lo, *cuts, hi]):
        mid = math.sqrt(a * b) if r.scale == "log" else 0.5 * (a + b)
        if predicted_holds(m, name, mid) != ref_holds:
            flipped += tr(b) - tr(a)
    return flipped / (tr(hi) - tr(lo))


def demo_margin(objects: Mapping[str, Any]) -> float:
    """A synthetic claim for the examples: holds while σ1² is below twice the paper's."""
    return 2.0 - objects["GyrocompassParams"].sigma1_sq / 1.86e-6


def check_fingerprint(claim: Claim, m: ClaimMap, objects: Mapping[str, Any] | None = None, *,
                      rtol: float = 1e-6, atol: float = 1e-9) -> None:
    """Recompute the map's fingerprint points and raise ``ValueError`` naming the claim when a
    margin moved by more than ``rtol`` relative (``atol`` absolute): the stored map is then
    stale and must be recomputed (``python -m gyrolib claims --out ...``)."""
    objs = dict(_inputs.reference_objects() if objects is None else objects)
    for pt in m.fingerprint:
        now = margin_at(claim, objs, pt["changes"])
        was = float(pt["margin"])
        same = (math.isnan(now) and math.isnan(was)) or (now == was) or (
            abs(now - was) <= atol + rtol * max(abs(now), abs(was)))
        if not same:
            raise ValueError(f"the stored map of {claim.id} is stale: its margin at "
                             f"{pt['changes'] or 'the reference'} was {was!r}, now {now!r}; "
                             "recompute the maps (python -m gyrolib claims --out)")


@dataclass(frozen=True)
class FingerprintPoint:
    """A point at which a stored map is checked against the code (:func:`fingerprint_points`):
    ``label`` (where, in words), ``changes`` (row → value, the others at the reference),
    and either ``margin`` (the stored margin: recomputed within a tolerance) or ``holds``
    (the stored verdict there: the recomputed margin's sign must agree)."""

    label: str
    changes: dict[str, Any]
    margin: float | None = None
    holds: bool | None = None


def _brackets(m: ClaimMap, ths: Sequence[Threshold] | Sequence[Mapping[str, Any]],
              base: Mapping[str, Any], rel: float, where: str) -> list[FingerprintPoint]:
    """Two points around each threshold, ``×(1 ∓ rel)`` (narrowed to a third of the gap to a
    neighbouring threshold of the same row or to the row's range), with the side on which
    the stored map says the claim holds."""
    items = [t.as_dict() if isinstance(t, Threshold) else dict(t) for t in ths]
    out = []
    for t in items:
        x = float(t["value"])
        r = _inputs.row(t["input"])
        ref = m.reference.get(t["input"])
        lo, hi = r.bounds(float(ref) if r.relative and ref is not None else None)
        gaps = [abs(u["value"] / x - 1.0) for u in items
                if u["input"] == t["input"] and u["value"] != x and x != 0.0]
        gaps += [abs(lo / x - 1.0), abs(hi / x - 1.0)] if x != 0.0 else []
        h = min([rel, *(g / 3.0 for g in gaps if g > 0)])
        below = t["holds_when"] == "below"
        for f, holds in ((1.0 - h, below), (1.0 + h, not below)):
            out.append(FingerprintPoint(
                f"{where}the margin at {t['input']} = {x * f:.6g} ({f:.4g} × its threshold "
                f"{x:.6g}, where the map says it {'holds' if holds else 'fails'})",
                {**base, t["input"]: x * f}, holds=holds))
    return out


def fingerprint_points(m: ClaimMap, *, bracket: float = 0.02,
                       n_sweep: int = 2) -> tuple[FingerprintPoint, ...]:
    """The points at which a stored map is checked against the code (:func:`check_map`).

    * the map's own fingerprint (the reference point, the first box points, the first
      failing point of each search), margins within a tolerance;
    * every threshold **bracketed**: the margin just inside and just outside it
      (``×(1 ∓ bracket)``), whose signs must be the map's (so they differ); the thresholds
      found under each other reading too, under that reading;
    * every **reading**'s status at the reference point;
    * ``n_sweep`` points of the stored one-at-a-time sweeps (a fixed sample: evenly spaced
      over their non-reference points, rows in name order), margins within a tolerance.

    Examples
    --------
    >>> from gyrolib import claim_map
    >>> c = claim_map.Claim("demo", claim_map.demo_margin, ("gc.sigma1_sq", "gc.C_as"),
    ...                     "2 - sigma1_sq/reference")
    >>> m = claim_map.map_claim(c, n_box=4)
    >>> [p.holds for p in claim_map.fingerprint_points(m) if p.holds is not None]
    [True, False]
    """
    pts = [FingerprintPoint("the margin at " + ("the reference" if not p["changes"] else
                                                f"the fingerprint point {i}"),
                            dict(p["changes"]), margin=float(p["margin"]))
           for i, p in enumerate(m.fingerprint)]
    pts += _brackets(m, m.thresholds, {}, bracket, "")
    for name, by_value in m.reading_thresholds.items():
        for val, ths in by_value.items():
            pts += _brackets(m, ths, {name: val}, bracket, f"under {name} = {val}: ")
    for name, statuses in m.readings.items():
        for val, st in list(statuses.items())[1:]:
            pts.append(FingerprintPoint(f"the status under {name} = {val} (stored: {st})",
                                        {name: val}, holds=st == "holds"))
    flat = [(name, x, y) for name in sorted(m.sweeps) for x, y in m.sweeps[name]
            if x != m.reference.get(name)]
    if flat and n_sweep > 0:
        idx = sorted({int((k + 0.5) * len(flat) / n_sweep) for k in range(n_sweep)})
        pts += [FingerprintPoint(f"the sweep's margin at {flat[i][0]} = {flat[i][1]:.6g}",
                                 {flat[i][0]: flat[i][1]}, margin=flat[i][2]) for i in idx]
    return tuple(pts)


def check_map(claim: Claim, m: ClaimMap, objects: Mapping[str, Any] | None = None, *,
              rtol: float = 1e-6, atol: float = 1e-9, bracket: float = 0.02,
              n_sweep: int = 2) -> int:
    """Recompute a stored map's :func:`fingerprint_points` and raise ``ValueError`` naming
    the claim and the first point that disagrees (a margin beyond ``atol + rtol·|margin|``, a
    sign that is not the map's); returns how many points agreed.

    Examples
    --------
    >>> from gyrolib import claim_map
    >>> c = claim_map.Claim("demo", claim_map.demo_margin, ("gc.sigma1_sq",), "demo")
    >>> m = claim_map.map_claim(c, n_box=0)
    >>> claim_map.check_map(c, m)
    5
    >>> from dataclasses import replace
    >>> moved = replace(m, thresholds=(replace(m.thresholds[0], value=1.5 * 1.86e-6),))
    >>> claim_map.check_map(c, moved)
    Traceback (most recent call last):
    ...
    ValueError: demo: the margin at gc.sigma1_sq = 2.8458e-06 (1.02 × ...) should be <= 0, ...
    """
    objs = dict(_inputs.reference_objects() if objects is None else objects)
    n = 0
    for p in fingerprint_points(m, bracket=bracket, n_sweep=n_sweep):
        now = margin_at(claim, objs, p.changes)
        if p.margin is not None:
            was = float(p.margin)
            if not ((math.isnan(now) and math.isnan(was))
                    or abs(now - was) <= atol + rtol * max(abs(now), abs(was))):
                raise ValueError(f"{claim.id}: {p.label} was {was!r}, the code now gives "
                                 f"{now!r} (tolerance rtol {rtol:g}, atol {atol:g})")
        elif _holds(now) != p.holds:
            raise ValueError(f"{claim.id}: {p.label} should be "
                             f"{'> 0' if p.holds else '<= 0'}, the code now gives {now!r}")
        n += 1
    return n
