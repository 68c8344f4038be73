"""The reproduction ledger: every printed figure, table entry and headline number of both
papers, with the value this book computes and whether the two agree.

Items are computed, never stored: each paper's module (:mod:`gyrolib.book.ledger.gc`,
:mod:`gyrolib.book.ledger.rsf`) builds its items by calling the same library functions the
chapters call.  ``python -m gyrolib ledger [--json]`` prints the ledger.
"""

from __future__ import annotations

import json
import math
import numbers
from dataclasses import asdict, dataclass, fields

from gyrolib import _validation as v

__all__ = ["STATUSES", "STATUS_MARKS", "LedgerItem", "collect", "format_value", "summary",
           "to_json", "to_markdown", "to_table"]

#: The allowed values of :attr:`LedgerItem.status`.
STATUSES: tuple[str, ...] = ("reproduced", "differs (explained)", "not reproducible")
#: A sphinx-design badge role per status, so that the ledger page shows it at a glance.
STATUS_MARKS: dict[str, str] = {
    "reproduced": "{bdg-success}`reproduced`",
    "differs (explained)": "{bdg-warning}`differs (explained)`",
    "not reproducible": "{bdg-danger}`not reproducible`",
}


@dataclass(frozen=True)
class LedgerItem:
    """One printed item of a paper and its reproduction.

    ``chapter`` is the Sphinx document name of the chapter that shows it (e.g.
    ``"chapters/rsf_method"``) and ``anchor`` an optional label inside it, so the ledger page
    and tests can link to it.
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
    anchor: str = ""

    @property
    def target(self) -> str:
        """The book label to link to: ``anchor``, or else the chapter's own label (the
        chapter file name with ``_`` as ``-``, e.g. ``chapters/gc_model`` → ``gc-model``)."""
        return self.anchor or self.chapter.rsplit("/", 1)[-1].replace("_", "-")

    def __post_init__(self) -> None:
        for f in fields(self):
            if f.name not in ("paper_value", "reproduced_value"):
                value = getattr(self, f.name)
                if not isinstance(value, str):
                    raise TypeError(f"{f.name} must be a str; got {type(value).__name__}")
        if self.status not in STATUSES:
            raise ValueError(f"status must be one of {STATUSES}; got {self.status!r}")
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


def _is_real(value: object) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def _check_items(items: object) -> list[LedgerItem]:
    if not isinstance(items, list | tuple) or not all(isinstance(it, LedgerItem)
                                                      for it in items):
        raise TypeError("items must be a list of LedgerItem")
    return list(items)


def collect() -> list[LedgerItem]:
    """All ledger items, paper GC first, each paper in the order of its printed items."""
    items: list[LedgerItem] = []
    for module_name in ("gc", "rsf"):
        try:
            module = __import__(f"gyrolib.book.ledger.{module_name}", fromlist=["items"])
        except ModuleNotFoundError as exc:
            if exc.name != f"gyrolib.book.ledger.{module_name}":
                raise
            continue
        items.extend(module.items())
    ids = [it.id for it in items]
    if len(ids) != len(set(ids)):
        raise RuntimeError("duplicate ledger ids")
    return items


def to_json(items: list[LedgerItem]) -> str:
    """JSON list of the items, byte-identical for identical inputs."""
    items = _check_items(items)
    out = []
    for it in items:
        d = asdict(it)
        d.pop("anchor")
        out.append(d)
    return json.dumps(out, indent=2, ensure_ascii=False, sort_keys=False) + "\n"


def format_value(value: float | str | None) -> str:
    """A paper or reproduced value as the ledger shows it: 4 significant digits, text as is,
    ``—`` for no value."""
    if value is None:
        return "—"
    if isinstance(value, str):
        return value
    return f"{v.check_real('value', value):.4g}"


def to_table(items: list[LedgerItem]) -> str:
    """A plain-text table for the terminal."""
    items = _check_items(items)
    header = ("id", "paper value", "reproduced", "unit", "status")
    rows = [(it.id, format_value(it.paper_value), format_value(it.reproduced_value), it.unit,
             it.status) for it in items]
    widths = [max(len(r[i]) for r in [header, *rows]) for i in range(len(header))]
    lines = ["  ".join(c.ljust(w) for c, w in zip(header, widths))]
    lines.append("  ".join("-" * w for w in widths))
    lines += ["  ".join(c.ljust(w) for c, w in zip(r, widths)) for r in rows]
    return "\n".join(lines) + "\n"


def summary(items: list[LedgerItem]) -> dict[str, int]:
    """Count of items per status, plus ``"total"``."""
    items = _check_items(items)
    counts = {status: 0 for status in STATUSES}
    for it in items:
        counts[it.status] += 1
    counts["total"] = len(items)
    return counts


def _md_escape(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def to_markdown(items: list[LedgerItem], paper: str) -> str:
    """MyST for one paper's items: a compact status table, then one note per item.

    The "where" column links with ``{ref}`` roles, so a broken link fails the book build.
    """
    items = _check_items(items)
    if paper not in ("GC", "RSF"):
        raise ValueError(f"paper must be 'GC' or 'RSF'; got {paper!r}")
    lines = [
        "| status | item | where | paper | reproduced | unit |",
        "| --- | --- | --- | --- | --- | --- |",
    ]
    notes = []
    for it in items:
        if it.paper != paper:
            continue
        link = f"{{ref}}`{_md_escape(it.location)} <{it.target}>`"
        lines.append(
            f"| {STATUS_MARKS[it.status]} | `{it.id}`<br>{_md_escape(it.quantity)} | {link} | "
            f"{format_value(it.paper_value)} | {format_value(it.reproduced_value)} | "
            f"{_md_escape(it.unit)} |"
        )
        notes.append(f"`{it.id}`\n: {_md_escape(it.note)}\n")
    return "\n".join(lines) + "\n\n" + "\n".join(notes)
