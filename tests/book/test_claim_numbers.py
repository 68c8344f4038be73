"""One number per claim on every page of the built book.

Every threshold, share and margin of a claim that a page quotes is formatted by one function
(:mod:`gyrolib.quote`) and tagged ``<span data-claim=… data-input=… data-quantity=…
data-form=…>``.  Over every page of the test session's build:

* each (claim, input, quantity, form) has one text on all pages together;
* each tagged number is the stored map's (``gyrolib/data/claim_maps.json``, read here as
  plain JSON): parsed back from the page's digits, it lies within the rounding of three
  significant digits of the stored threshold (as a factor, or its value in the input's
  shown unit) or share;
* the pages that the tagging was written for carry their tags (a page that lost them would
  pass the first two checks vacuously);
* the legend of the race's verdict figure (Fig. "fig-gcr-verdict") quotes the map's
  threshold with the digits of the text, not a point of the grid.

The checks run first on small synthetic pages, where a page with two values of one tag, a
number that is not the map's and a legend off the text must each fail.
"""

from __future__ import annotations

import json
import math
import re
from html.parser import HTMLParser
from pathlib import Path

import pytest

from gyrolib import quote
from tests.conftest import require_built_book

ROOT = Path(__file__).resolve().parents[2]
MAPS = ROOT / "gyrolib" / "data" / "claim_maps.json"

_SUP = str.maketrans("⁻⁰¹²³⁴⁵⁶⁷⁸⁹", "-0123456789")
#: A number as the pages print it: 1.2, 0.674, 2557, 1.74·10⁻⁵ (the first one of a text).
_NUMBER = re.compile(r"-?\d+(?:\.\d+)?(?:·10[⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+)?")


class _Tags(HTMLParser):
    """Every ``<span data-claim=…>`` of a page: its attributes and its text."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.found: list[tuple[dict[str, str], str]] = []
        self._open: list[tuple[dict[str, str] | None, list[str]]] = []

    def handle_starttag(self, tag, attrs):
        if tag != "span":
            return
        a = {k: v or "" for k, v in attrs}
        self._open.append((a if "data-claim" in a else None, []))

    def handle_endtag(self, tag):
        if tag == "span" and self._open:
            a, text = self._open.pop()
            if a is not None:
                self.found.append((a, "".join(text).strip()))

    def handle_data(self, data):
        for _, text in self._open:
            text.append(data)


def tagged(pages: dict[str, str]) -> dict[tuple[str, str, str, str], dict[str, list[str]]]:
    """(claim, input, quantity, form) → text → the pages quoting it, over ``pages``
    (name → HTML)."""
    out: dict[tuple[str, str, str, str], dict[str, list[str]]] = {}
    for name, html in pages.items():
        p = _Tags()
        p.feed(html)
        for a, text in p.found:
            key = (a["data-claim"], a.get("data-input", ""), a.get("data-quantity", ""),
                   a.get("data-form", ""))
            out.setdefault(key, {}).setdefault(" ".join(text.split()), []).append(name)
    return out


def disagreements(found) -> list[str]:
    """Each tag quoted with more than one text, with where."""
    return [f"{key}: " + "; ".join(f"{t!r} on {sorted(set(p))}" for t, p in texts.items())
            for key, texts in sorted(found.items()) if len(texts) > 1]


def first_number(text: str) -> float:
    """The first number of a page's text: ``"1.74·10⁻⁵ m²/s⁴"`` → 1.74e-5."""
    m = _NUMBER.search(text.replace("\u2009", ""))
    if m is None:
        raise ValueError(f"no number in {text!r}")
    mant, _, exp = m.group(0).partition("·10")
    return float(mant) * (10.0 ** int(exp.translate(_SUP)) if exp else 1.0)


def _three_digits(x: float, shown: float) -> bool:
    """Whether ``shown`` is ``x`` at three significant digits (half a unit of the third)."""
    if x == 0.0:
        return shown == 0.0
    unit = 10.0 ** (math.floor(math.log10(abs(x))) - 2)
    return abs(shown - x) <= 0.5 * unit * (1 + 1e-9) + 1e-15


def _shown_value(input_name: str, value: float) -> float:
    """A threshold's value in the unit its row shows (the table's own unit conversion)."""
    from gyrolib import inputs
    from gyrolib.units import from_si

    r = inputs.row(input_name)
    return float(from_si(value, r.shown)) if r.shown else float(value)


def against_maps(found, maps: dict) -> list[str]:
    """Each tagged number that is not the stored map's at the declared precision."""
    bad = []
    for (claim, inp, quantity, form), texts in found.items():
        m = maps.get(claim)
        if m is None:
            bad.append(f"{claim}: no stored map")
            continue
        for text in texts:
            if quantity == "threshold":
                th = [t for t in m["thresholds"] if t["input"] == inp]
                if not th:
                    bad.append(f"{claim}: {inp} is not one of its thresholds ({text!r})")
                    continue
                want = (th[0]["factor"] if form == "factor"
                        else _shown_value(inp, th[0]["value"]))
                got = first_number(text)
                # the rule's fourth digit from 1000 up: within three digits' rounding anyway
                if want is None or not _three_digits(want, got):
                    bad.append(f"{claim} {inp} {form}: page {text!r}, map {want!r}")
            elif quantity == "share":
                sh = m["share_holding"]
                nums = [float(x) for x in re.findall(r"\d+(?:\.\d+)?", text)[:3]]
                want = [100 * sh["value"], 100 * sh["lo"], 100 * sh["hi"]]
                if len(nums) != 3 or any(abs(a - b) > 0.5 + 1e-9 for a, b in zip(nums, want)):
                    bad.append(f"{claim} share: page {text!r}, map {want}")
            elif quantity == "margin":
                if not _three_digits(m["margin"], first_number(text)):
                    bad.append(f"{claim} margin: page {text!r}, map {m['margin']!r}")
    return bad


_LEGEND = re.compile(r"flips at σ1² × (\S+)")


def legend_problems(legend: list[str], found) -> list[str]:
    """The race figure's legend against the text's σ1² factor of gc.faster_percent."""
    key = ("gc.faster_percent", "gc.sigma1_sq", "threshold", "factor")
    texts = list(found.get(key, {}))
    if len(texts) != 1:
        return [f"the pages quote {key} as {texts}, not once"]
    shown = [m.group(1) for e in legend if (m := _LEGEND.search(e))]
    if not shown:
        return [f"the legend {legend} marks no threshold"]
    return [f"the legend says σ1² × {s}, the text {texts[0]}" for s in shown if s != texts[0]]


# ------------------------------------------------------------------ the checks have power
def _span(claim, inp, quantity, form, text):
    attrs = f'data-claim="{claim}"' + (f' data-input="{inp}"' if inp else "")
    attrs += f' data-quantity="{quantity}"' + (f' data-form="{form}"' if form else "")
    return f"<p>holds for σ1² below <span {attrs}>{text}</span> × the reference</p>"


def _maps() -> dict:
    return json.loads(MAPS.read_text(encoding="utf-8"))["maps"]


def test_one_value_per_tag_passes_agreeing_pages_and_fails_two_values():
    ok = {"a.html": _span("gc.faster_percent", "gc.sigma1_sq", "threshold", "factor", "1.2"),
          "b.html": "<div>" + _span("gc.faster_percent", "gc.sigma1_sq", "threshold",
                                    "factor", "1.2") + "</div>"}
    assert disagreements(tagged(ok)) == []
    assert against_maps(tagged(ok), _maps()) == []
    bad = {**ok, "c.html": _span("gc.faster_percent", "gc.sigma1_sq", "threshold", "factor",
                                 "1.14")}
    problems = disagreements(tagged(bad))
    assert len(problems) == 1 and "'1.14' on ['c.html']" in problems[0], problems
    # the other form of the same threshold is another tag, and a nested span is read whole
    sh = _maps()["gc.time_to_sigma_c"]["share_holding"]
    head, _, tail = quote.share(sh["value"], sh["lo"], sh["hi"]).partition(", ")
    low, _, high = tail.partition("–")
    other = {"d.html": _span("gc.faster_percent", "gc.sigma1_sq", "threshold", "value",
                             "2.24·10⁻⁶ m²/s⁴"),
             "e.html": '<span data-claim="gc.time_to_sigma_c" data-quantity="share">'
                       f"{head}, <span>{low}</span>–{high}</span>"}
    assert disagreements(tagged({**ok, **other})) == []
    assert against_maps(tagged(other), _maps()) == []


def test_a_number_that_is_not_the_maps_fails():
    maps = _maps()
    for text, quantity, form in (("9.4", "threshold", "factor"), ("1.14", "threshold", "factor"),
                                 ("2.1·10⁻⁶ m²/s⁴", "threshold", "value")):
        page = {"p.html": _span("gc.faster_percent", "gc.sigma1_sq", quantity, form, text)}
        assert against_maps(tagged(page), maps), text
    page = {"p.html": '<span data-claim="gc.faster_percent" data-quantity="share">'
                      "3 % of the box, 0–6 %</span>"}
    assert against_maps(tagged(page), maps)
    page = {"p.html": _span("gc.faster_percent", "gc.sigma_as_offset", "threshold", "factor",
                            "1.2")}
    assert against_maps(tagged(page), maps)   # no factor for a zero reference


def test_a_legend_off_the_text_fails():
    found = tagged({"p.html": _span("gc.faster_percent", "gc.sigma1_sq", "threshold",
                                    "factor", "1.2")})
    assert legend_problems(["C_as × 1", "flips at σ1² × 1.2"], found) == []
    assert legend_problems(["C_as × 1", "flips at σ1² × 1.14"], found)
    assert legend_problems(["C_as × 1"], found)


def test_first_number_reads_the_pages_forms():
    assert first_number("1.74·10⁻⁵ m²/s⁴") == pytest.approx(1.74e-5)
    assert first_number("2557°/s") == 2557.0 and first_number("0.674") == 0.674
    assert _three_digits(9.3502924663002, 9.35) and not _three_digits(9.3502924663002, 9.4)


# ------------------------------------------------------------------------ the built book
#: Pages and the tags each must carry (a page that lost its tags fails here).
REQUIRED = {
    "chapters/gc_race.html": [("gc.faster_percent", "gc.sigma1_sq", "threshold", "factor"),
                              ("gc.faster_percent", "gc.sigma_incl_bias", "threshold",
                               "value"),
                              ("gc.faster_percent", "gc.sigma_as_offset", "threshold",
                               "value"),
                              ("gc.faster_percent", "", "share", ""),
                              ("gc.time_to_sigma_c", "gc.sigma1_sq", "threshold", "factor")],
    "chapters/gc_claims.html": [("gc.time_to_sigma_c", "gc.sigma1_sq", "threshold", "factor"),
                                ("gc.time_to_sigma_c", "", "share", ""),
                                ("gc.faster_percent", "gc.sigma1_sq", "threshold", "factor")],
    "chapters/ledger.html": [("gc.faster_percent", "gc.sigma1_sq", "threshold", "factor"),
                             ("rsf.claim.gs_vs_sins", "", "share", "")],
}


@pytest.fixture(scope="module")
def built_pages() -> dict[str, str]:
    root = require_built_book()
    skip = {"_static", "_sources", "_images", "_downloads"}
    return {p.relative_to(root).as_posix(): p.read_text(encoding="utf-8")
            for p in sorted(root.rglob("*.html"))
            if not skip.intersection(p.relative_to(root).parts[:-1])}


def test_every_tagged_number_has_one_value_and_is_the_maps(built_pages):
    found = tagged(built_pages)
    assert sum(len(p) for t in found.values() for p in t.values()) > 50, found
    assert disagreements(found) == []
    assert against_maps(found, _maps()) == []
    for page, keys in REQUIRED.items():
        assert page in built_pages, f"the build has no {page}"
        on_page = tagged({page: built_pages[page]})
        missing = [k for k in keys if k not in on_page]
        assert not missing, f"{page} lost its tags {missing}"


def test_the_race_figures_legend_quotes_the_texts_threshold(built_pages):
    import io

    from PIL import Image

    from gyrolib._page_figures import PNG_KEY
    from tests.book.test_page_figures import _png_of

    root = require_built_book()
    page = "chapters/gc_race.html"
    html = built_pages[page]
    fig = re.search(r'<figure[^>]*id="fig-gcr-verdict".*?</figure>', html, re.S)
    assert fig, "no figure fig-gcr-verdict on gc_race"
    src = re.search(r'<img[^>]*src="([^"]+)"', fig.group(0))
    png = _png_of(src.group(1), root / page)
    legend = json.loads(Image.open(io.BytesIO(png)).info[PNG_KEY])["legend"]
    assert legend_problems(legend, tagged(built_pages)) == []


def status_problems(items: list[dict]) -> list[str]:
    """Ledger items (``ledger.json``'s) whose status says more than their share: a share
    whose 95 % interval's upper end is below one half with "holds under conditions", or a
    mapped claim's status line without its share."""
    bad = []
    for it in items:
        share = it.get("share_holding")
        if it.get("kind") != "claim" or not share:
            continue
        if share["hi"] < 0.5 and it["status"].startswith("holds under conditions"):
            bad.append(f"{it['id']}: {it['status']!r} holds in at most "
                       f"{100 * share['hi']:.0f} % of the box")
        if it["status_code"] != "holds" and "% of the box" not in it["status"]:
            bad.append(f"{it['id']}: {it['status']!r} has no share")
    return bad


def test_the_status_check_fails_a_status_that_says_more_than_its_share():
    share = {"value": 0.0, "lo": 0.0, "hi": 0.0566, "n": 64, "seed": 2026}
    ok = {"id": "c", "kind": "claim", "share_holding": share, "status_code":
          "holds_near_reference", "status": "holds only near the reference (0 % of the box, "
          "0–6 %)"}
    assert status_problems([ok]) == []
    over = {**ok, "status_code": "holds_in_part", "status": "holds under conditions"}
    assert len(status_problems([over])) == 2
    bare = {**ok, "status": "holds only near the reference"}
    assert len(status_problems([bare])) == 1


def test_no_claim_of_the_built_ledger_says_more_than_its_share():
    root = require_built_book()
    items = json.loads((root / "ledger.json").read_text(encoding="utf-8"))["items"]
    assert sum(1 for it in items if it.get("kind") == "claim" and it.get("share_holding")) >= 10
    assert status_problems(items) == []
