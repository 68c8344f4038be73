"""Each claim section of gc_claims, gc_race and rsf_method shows its claim's map: a cell that
reads the stored map (never recomputes it) and draws it with plot_claim_map and
threshold_table, and a glued figure of that key, inside the claim's section."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

CHAPTERS = Path(__file__).resolve().parents[2] / "chapters"

#: (chapter, the section's heading, its claim): every claim section of the three chapters.
SECTIONS = (
    ("gc_claims", 'Claim: "more than 50 % faster"', "gc.time_to_sigma_c"),
    ("gc_claims", "Claim: the trend holds when the shaping filters vary widely",
     "gc.claim.trend_holds"),
    ("gc_claims", "Why ψ and ω_gc separate at all", "gc.claim.psi_separable"),
    ("gc_claims", 'The "corresponding gyro": the west gyro', "gc.claim.corresponding_gyro"),
    ("gc_race", 'Verdict: "more than 50 % faster", and where it holds', "gc.faster_percent"),
    ("rsf_method", "Eq. (8): lateral deviation, cubic and exact", "rsf.claim.drz_cubic"),
    ("rsf_method", "Table 2: SINS roll error and lateral deviation", "rsf.claim.drz_kilometres"),
    ("rsf_method", '"Hundreds of times smaller"', "rsf.claim.gs_vs_sins"),
    ("rsf_method", '"Compensates 90 %"', "rsf.example.compensated"),
)


def section(text: str, heading: str) -> str:
    """The text of the section under ``heading`` (## or ###) up to the next heading of the
    same or a higher level (lines inside code fences are not headings)."""
    lines = text.splitlines(keepends=True)
    fence, start, level, out = False, None, 0, []
    for line in lines:
        if line.startswith("```"):
            fence = not fence if line.strip() == "```" or not fence else fence
        m = None if fence else re.match(r"(#+) (.*)\n", line)
        if start is None:
            if m and m.group(2) == heading:
                start, level = True, len(m.group(1))
            continue
        if m and len(m.group(1)) <= level:
            break
        out.append(line)
    assert start, heading
    return "".join(out)


def map_cells(body: str) -> list[tuple[str, str]]:
    """(claim, glue key) of each cell of ``body`` that draws a stored map, whose figure the
    section shows."""
    out = []
    for cell in re.findall(r"```\{code-cell\} ipython3\n(.*?)```", body, flags=re.S):
        m = re.search(r'stored_maps\(\)\["([^"]+)"\]', cell)
        k = re.search(r'glue\("([^"]+)", _fig', cell)
        if m and k and "plot_claim_map(" in cell and "threshold_table(" in cell \
                and "map_claim(" not in cell.replace("plot_claim_map(", ""):
            if f"```{{glue:figure}} {k.group(1)}\n" in body:
                out.append((m.group(1), k.group(1)))
    return out


@pytest.mark.parametrize(("chapter", "heading", "cid"), SECTIONS)
def test_each_claim_section_shows_its_map(chapter, heading, cid):
    body = section((CHAPTERS / f"{chapter}.md").read_text("utf-8"), heading)
    assert cid in [c for c, _ in map_cells(body)]


def test_the_check_has_power():
    """A section whose cell recomputes the map, or shows no figure of its key, is not
    counted."""
    cell = ('```{code-cell} ipython3\n_map = stored_maps()["x"]\n_fig = plot_claim_map(_map)\n'
            'glue("k", _fig, display=False)\nMarkdown(threshold_table(_map))\n```\n')
    assert map_cells(cell + "```{glue:figure} k\n:name: f\n\ncap\n```\n") == [("x", "k")]
    assert map_cells(cell) == []
    assert map_cells(cell.replace("_map = stored", "_map = claim_map.map_claim(c)  # stored")
                     + "```{glue:figure} k\n```\n") == []
