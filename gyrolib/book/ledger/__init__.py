"""The reproduction ledger: every printed figure, table entry and headline number of both
papers, with the value this book computes and whether the two agree.

Items are computed, never stored: each paper's module (:mod:`gyrolib.book.ledger.gc`,
:mod:`gyrolib.book.ledger.rsf`) builds its items, one small function per table or claim, by
calling the same library functions the chapters call.  :mod:`gyrolib.book.ledger.item` holds
:class:`LedgerItem`, the verdict vocabulary and the one agreement rule every item uses
(:func:`agrees`: within half a unit of the last printed digit, unless the item states another
tolerance with its reason; :func:`printed_verdict` for a printed number and its candidate
causes).  This package adds the files and pages built from the items.
``python -m gyrolib ledger [--json]`` prints the ledger.
"""

from __future__ import annotations

import csv
import hashlib
import io
import json
import os
from collections.abc import Mapping
from contextlib import contextmanager
from dataclasses import asdict, fields
from pathlib import Path
from typing import Any

import gyrolib
from gyrolib import _validation as v
from gyrolib import claim_map as _claim_map
from gyrolib import inputs as _inputs
from gyrolib.book import cite
from gyrolib.book.cite import anchor, rounded
from gyrolib.book.ledger import (
    gc,
    remaining,
    rsf,
    studies,  # noqa: F401  (registers the stored studies)
)
from gyrolib.book.ledger.item import (
    KINDS,
    STATUS_CODES,
    STATUS_MARKS,
    STATUSES,
    STATUSES_BY_KIND,
    Candidate,
    LedgerItem,
    agrees,
    half_unit,
    printed_verdict,
)

__all__ = [
    "KINDS",
    "KIND_PLURALS",
    "MAP_FIELDS",
    "SCHEMA_VERSION",
    "STATUSES",
    "STATUSES_BY_KIND",
    "STATUS_CODES",
    "STATUS_MARKS",
    "TITLE",
    "Candidate",
    "LedgerItem",
    "agrees",
    "anchor",
    "citation",
    "claim_map_markdown",
    "collect",
    "entries_markdown",
    "format_value",
    "half_unit",
    "kinds_markdown",
    "printed_verdict",
    "rounded",
    "side_by_side_markdown",
    "summary",
    "table_markdown",
    "to_csv",
    "to_json",
    "to_table",
]

#: The book's title, as cited with the ledger's data files.
TITLE = "Gyro calibration, reproduced"


def _check_items(items: object) -> list[LedgerItem]:
    if not isinstance(items, list | tuple) or not all(isinstance(it, LedgerItem)
                                                      for it in items):
        raise TypeError("items must be a list of LedgerItem")
    return list(items)


#: Environment variable naming a folder where :func:`collect` keeps its items between
#: processes (the book build sets it, so the chapters that show the ledger compute it once).
MEMO_ENV = "GYROLIB_LEDGER_MEMO"


def _memo_file() -> Path | None:
    """``$GYROLIB_LEDGER_MEMO/ledger-<hash of gyrolib's sources and the study file it
    quotes>.json``, or ``None``."""
    folder = os.environ.get(MEMO_ENV)
    if not folder:
        return None
    h = hashlib.sha256()
    package = Path(gyrolib.__file__).resolve().parent
    for path in sorted(package.rglob("*.py")):
        h.update(path.relative_to(package).as_posix().encode() + b"\0" + path.read_bytes())
    if gc.STUDY_FILE.is_file():  # a data file the ledger quotes
        h.update(b"study\0" + gc.STUDY_FILE.read_bytes())
    return Path(folder) / f"ledger-{h.hexdigest()[:32]}.json"


def collect() -> list[LedgerItem]:
    """All ledger items, paper GC first, each paper in the order of its printed items.

    With ``$GYROLIB_LEDGER_MEMO`` set (the book build does), the items are computed once for
    a given state of gyrolib's sources and read back from that folder afterwards.
    """
    memo = _memo_file()
    if memo is None:
        return _collect()
    if memo.is_file():
        return _read_memo(memo)
    memo.parent.mkdir(parents=True, exist_ok=True)
    # chapters executed at the same time wait for the first one's computation, not redo it
    with _exclusive(memo.with_suffix(".lock")):
        if memo.is_file():
            return _read_memo(memo)
        items = _collect()
        tmp = memo.with_suffix(f".{os.getpid()}.tmp")
        tmp.write_text(json.dumps([asdict(it) for it in items]), encoding="utf-8")
        tmp.replace(memo)  # atomic: a concurrent reader sees the whole file or none
    return items


def _read_memo(memo: Path) -> list[LedgerItem]:
    return [LedgerItem(**d) for d in json.loads(memo.read_text(encoding="utf-8"))]


@contextmanager
def _exclusive(lock: Path):
    """An exclusive lock on the file ``lock`` between processes (``fcntl.flock``; where
    there is no ``fcntl``, no lock: two processes may then both compute the same items)."""
    try:
        import fcntl
    except ImportError:  # not POSIX
        yield
        return
    with open(lock, "a") as fh:
        fcntl.flock(fh, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(fh, fcntl.LOCK_UN)


def _collect() -> list[LedgerItem]:
    items = [*gc.items(), *remaining.items_gc(), *rsf.items(), *remaining.items_rsf()]
    ids = [it.id for it in items]
    if len(ids) != len(set(ids)):
        raise RuntimeError("duplicate ledger ids")
    return items


#: The version of the ledger's file format (JSON and CSV).  2: each claim carries
#: ``reference``, ``thresholds``, ``share_holding`` and ``readings`` (release 0.3.0's files,
#: without these fields, are version 1); 3 (release 0.5.2): and ``isolated``, the statements
#: of the isolated points where a claim fails (:class:`gyrolib.claim_map.IsolatedFailures`);
#: 4: ``status`` carries the words a reader sees (a mapped claim's with the share of the box
#: where it holds, :attr:`LedgerItem.status_line`) and ``status_code`` a stable code for
#: programs (:data:`STATUS_CODES`).
SCHEMA_VERSION = 4

#: The fields a claim's map adds to its record (``None`` for the other kinds).
MAP_FIELDS = ("reference", "thresholds", "share_holding", "readings", "margin", "mapped",
              "isolated")


def _sig(x: object, digits: int = 4) -> object:
    """Floats in a claim's map at ``digits`` significant digits (the same on every CPU)."""
    if isinstance(x, float):
        return float(f"{x:.{digits}g}")
    if isinstance(x, dict):
        return {k: _sig(val, digits) for k, val in x.items()}
    if isinstance(x, list | tuple):
        return [_sig(val, digits) for val in x]
    return x


def _record(it: LedgerItem) -> dict[str, object]:
    d = asdict(it)
    d.pop("anchor")
    judged = d.pop("judged") or {}
    d["status"] = it.status_line
    d = {**{k: d[k] for k in list(d)[:list(d).index("status") + 1]},
         "status_code": it.status_code, **d}      # the code right after the words
    d["reproduced_value"] = rounded(it.reproduced_value, it.precision)
    for key in MAP_FIELDS:
        d[key] = _sig(judged.get(key)) if it.kind == "claim" else None
    return d


def to_json(items: list[LedgerItem]) -> str:
    """The ledger as one JSON object: ``{"title", "version", "schema_version", "items":
    [...]}``, every value rounded to its item's precision (a claim's map to four significant
    digits), so that the text is the same on every machine."""
    items = _check_items(items)
    doc = {"title": TITLE, "version": gyrolib.__version__, "schema_version": SCHEMA_VERSION,
           "items": [_record(it) for it in items]}
    return json.dumps(doc, indent=2, ensure_ascii=False, sort_keys=False) + "\n"


def to_csv(items: list[LedgerItem]) -> str:
    """The ledger as CSV: a ``# <title> (ledger schema N) <version>`` comment line, a
    header, one row per item (values rounded to each item's precision; a claim's map fields as JSON
    text)."""
    items = _check_items(items)
    buf = io.StringIO()
    buf.write(f"# {TITLE} (ledger schema {SCHEMA_VERSION}) {gyrolib.__version__}\n")
    records = [_record(it) for it in items]
    for r in records:  # a claim's map as JSON text in its cell (empty for the other kinds)
        for key in MAP_FIELDS:
            r[key] = "" if r[key] is None else json.dumps(r[key], ensure_ascii=False,
                                                          sort_keys=True)
    names = [f.name for f in fields(LedgerItem) if f.name not in ("anchor", "judged")]
    names.insert(names.index("status") + 1, "status_code")
    writer = csv.DictWriter(buf, fieldnames=[*names, *MAP_FIELDS], lineterminator="\n")
    writer.writeheader()
    writer.writerows(records)
    return buf.getvalue()


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
    header = ("id", "kind", "paper value", "reproduced", "unit", "status")
    rows = [(it.id, it.kind, format_value(it.paper_value),
             format_value(rounded(it.reproduced_value, it.precision)), it.unit,
             it.status_line) for it in items]
    widths = [max(len(r[i]) for r in [header, *rows]) for i in range(len(header))]
    lines = ["  ".join(c.ljust(w) for c, w in zip(header, widths))]
    lines.append("  ".join("-" * w for w in widths))
    lines += ["  ".join(c.ljust(w) for c, w in zip(r, widths)) for r in rows]
    counts = summary(items)
    lines.append("")
    for kind in KINDS:
        by_status = counts[kind]
        if sum(by_status.values()):
            lines.append(f"{kind + ':':16}" + ", ".join(f"{n} {status}"
                                                        for status, n in by_status.items() if n))
    return "\n".join(lines) + "\n"


def summary(items: list[LedgerItem]) -> dict[str, object]:
    """Counts per kind and status, plus ``"total"``: ``{kind: {status: n}, "total": n}``.

    "reproduced" exists only under ``"printed number"``: inputs, inferred values, redrawn
    figures and claims are counted under their own kinds, never as reproduced.
    """
    items = _check_items(items)
    counts: dict[str, object] = {kind: dict.fromkeys(STATUSES_BY_KIND[kind], 0)
                                 for kind in KINDS}
    for it in items:
        counts[it.kind][it.status] += 1  # type: ignore[index]
    counts["total"] = len(items)
    return counts


# Rendering for the book's pages (MyST) ------------------------------------------------------
#: How each kind is named in running text.
KIND_PLURALS: dict[str, str] = {"printed number": "printed numbers", "input": "inputs",
                                "inferred": "inferred values", "figure": "figures",
                                "claim": "claims"}


def _md_escape(text: object) -> str:
    return str(text).replace("|", "\\|").replace("\n", " ")


def _shown(value: float | str | None, precision: int) -> str:
    """A value as the ledger shows it: the item's precision, text as is, ``—`` for none."""
    if value is None:
        return "—"
    if isinstance(value, str):
        return value
    return f"{float(value):.{precision}g}"


def kinds_markdown(items: list[LedgerItem]) -> str:
    """A bullet list of the items per kind, each with its statuses as badges."""
    counts = summary(items)
    lines = []
    for kind in KINDS:
        by_status = counts[kind]
        n = sum(by_status.values())
        if n:
            parts = ", ".join(f"{c} {STATUS_MARKS[s]}" for s, c in by_status.items() if c)
            lines.append(f"* **{KIND_PLURALS[kind]}**: {n} — {parts}")
    return "\n".join(lines)


def table_markdown(items: list[LedgerItem], paper: str) -> str:
    """MyST table of one paper's items, six columns so that it fits a page: the verdict
    (status badge over the kind), the item (id linked to its entry, quantity), the printed
    value, the reproduced value with its unit, the conditions and the evidence, and where the
    book shows it.  Links are ``{ref}`` roles, so a broken one fails the book build."""
    items = _check_items(items)
    if paper not in ("GC", "RSF"):
        raise ValueError(f"paper must be 'GC' or 'RSF'; got {paper!r}")
    rows = ["| verdict | item | printed | reproduced | conditions · evidence | where |",
            "|" + " --- |" * 6]
    for it in items:
        if it.paper != paper:
            continue
        unit = "" if it.unit in ("", "1", "—") or it.reproduced_value is None else f" {it.unit}"
        why = (f"**conditions:** {_md_escape(it.conditions_html)}<br>" if it.conditions
               else "")
        # the share of the box, on the status's own line (a claim's status line, its numbers
        # tagged for the page: gyrolib.quote)
        share = it.status_html[len(it.status):].strip()
        rows.append(
            f"| {STATUS_MARKS[it.status]}{' ' + _md_escape(share) if share else ''}"
            f"<br>*{it.kind}* | {{ref}}`{it.id} <{it.id}>`<br>"
            f"{_md_escape(it.quantity)} | {_md_escape(_shown(it.paper_value, it.precision))} | "
            f"{_shown(it.reproduced_value, it.precision)}{_md_escape(unit)} | "
            f"{why}**evidence:** {_md_escape(it.evidence)} | "
            f"{{ref}}`{_md_escape(it.location)} <{it.target}>` |")
    return "\n".join(rows)


def _sentence(text: str) -> str:
    """``text`` as the start of a sentence: a lower-case Latin first letter raised (a symbol
    such as δ or σ is left as it is: its capital is another symbol), and nothing else.

    >>> _sentence("the print takes ε1,GS"), _sentence("δK of K")
    ('The print takes ε1,GS', 'δK of K')
    """
    return text[:1].upper() + text[1:] if text[:1].isascii() and text[:1].islower() else text


def citation(item: LedgerItem) -> str:
    """One line a reader can paste into a paper: the value, the verdict, the item's id and
    the book's version, and where the item is found: the ledger page's absolute URL, or
    "unpublished build" with the version and release date (:mod:`gyrolib.book.cite`)."""
    it = v.check_instance("item", item, LedgerItem)
    printed = _shown(it.paper_value, it.precision)
    got = _shown(it.reproduced_value, it.precision)
    # a pure number carries no unit: "1" after a value would read as one more digit
    unit = "" if it.unit in ("", "1", "—") else f" {it.unit}"
    what = f"{it.quantity}: {got}{unit}" if it.reproduced_value is not None else it.quantity
    what = _sentence(what)
    return (f"{what} (paper {it.paper}, {it.location}, printed: {printed}; "
            f"{it.status_line}). "
            f"{TITLE}, version {gyrolib.__version__}, ledger item {it.id} "
            f"({cite.ledger_location(anchor(it.id))}).")


def claim_map_markdown(item: LedgerItem) -> str:
    """A claim's map over the table of inputs as a compact MyST table: each input that flips
    it (the threshold, on which side it holds; or the isolated points where it fails), the
    status under each reading, and the share
    of the box of uncertain inputs that holds (with its 95 % interval).  Empty for an item
    that is not a mapped claim."""
    it = v.check_instance("item", item, LedgerItem)
    j = it.judged or {}
    if it.kind != "claim" or not j.get("mapped"):
        return ""
    rows = ["| input | where it flips | the claim holds |", "| --- | --- | --- |"]
    for t in j["thresholds"]:
        r = _inputs.row(t["input"])
        rows.append(f"| {_md_escape(r.symbol)} `{t['input']}` | "
                    f"{_claim_map.quote_threshold(it.id, t, html=True)} | "
                    f"{t['holds_when']} |")
    for f in j.get("isolated") or []:
        if f["points"]:
            r = _inputs.row(f["input"])
            pts = f["points"]
            shown = ", ".join(r.show(x) for x in pts[:3]) + (f", …, {r.show(pts[-1])}"
                                                             if len(pts) > 3 else "")
            rows.append(f"| {_md_escape(r.symbol)} `{f['input']}` | at {len(pts)} isolated "
                        f"points ({_md_escape(shown)}; {f['searched']} searched, resolution "
                        f"{r.show(f['resolution'])}) | between them |")
    for name, st in j["readings"].items():
        r = _inputs.row(name)
        rows.append(f"| {_md_escape(r.symbol)} `{name}` (reading) | "
                    + ", ".join(f"{k}: {val}" for k, val in st.items()) + " | — |")
    share = j.get("share_holding")
    if share:
        rows.append(f"| the box of uncertain inputs | {share['n']} points, seed "
                    f"{share['seed']} | {it.quote_share()} (95 % interval) |")
    return "\n".join(rows) if len(rows) > 2 else ""


def side_by_side_markdown(claims: Mapping[str, tuple[str, Any]]) -> str:
    """Claims that are alike, side by side, as a MyST table: one column per claim (its id),
    a row for what it is judged against, its status, each input that flips either (the
    threshold, or "does not flip it") and the share of the box.  Every threshold and share
    is quoted by the one formatter and tagged for the page (:mod:`gyrolib.quote`).

    Parameters
    ----------
    claims : mapping
        Claim id → (what it is judged against, in words; its verdict: a
        :class:`LedgerItem` or :class:`gyrolib.book.ledger.claims.Verdict`, anything with
        ``status`` and ``judged``).
    """
    if len(claims) < 2:
        raise ValueError(f"claims must name at least two claims; got {list(claims)}")
    ids = list(claims)
    judged = {i: (claims[i][1].judged or {}) for i in ids}
    ths = {i: {t["input"]: t for t in (judged[i].get("thresholds") or ())} for i in ids}
    rows = ["| claim | " + " | ".join(f"`{i}`" for i in ids) + " |",
            "|" + " --- |" * (len(ids) + 1),
            "| judged against | " + " | ".join(_md_escape(claims[i][0]) for i in ids) + " |",
            "| status | " + " | ".join(
                _md_escape(_claim_map.status_line(claims[i][1].status,
                                                  judged[i].get("share_holding"),
                                                  claim=i, html=True)) for i in ids) + " |"]
    for name in dict.fromkeys(n for i in ids for n in ths[i]):
        r = _inputs.row(name)
        cells = [f"{t['holds_when']} {_claim_map.quote_threshold(i, t, html=True)}"
                 if (t := ths[i].get(name)) else "does not flip it" for i in ids]
        rows.append(f"| {_md_escape(r.symbol)} | " + " | ".join(cells) + " |")
    return "\n".join(rows)


def entries_markdown(items: list[LedgerItem], paper: str) -> str:
    """One labelled entry per item of ``paper`` (the target of ``ledger.html#<anchor>``):
    quantity, where it is shown, the note, and the citation line in a copyable block."""
    items = _check_items(items)
    if paper not in ("GC", "RSF"):
        raise ValueError(f"paper must be 'GC' or 'RSF'; got {paper!r}")
    out = []
    for it in items:
        if it.paper == paper:
            table = claim_map_markdown(it)
            table = f"\n\n{table}" if table else ""
            note = _sentence(it.note.strip())
            note += "" if note.endswith((".", "!", "?")) else "."
            out.append(f"({it.id})=\n**`{it.id}`** — {_md_escape(it.quantity)} "
                       f"({{ref}}`{_md_escape(it.location)} <{it.target}>`). "
                       f"{_md_escape(note)}{table}\n\n```text\n{citation(it)}\n```\n")
    return "\n".join(out)
