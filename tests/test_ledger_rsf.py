"""Ledger items of paper RSF (gyrolib.book.ledger.rsf): present, computed (not stored), agreeing
with the print where they say so, linked to labels of the chapter, and moving with inputs."""

import dataclasses
import math
import re
from pathlib import Path

import pytest

from gyrolib import rsf
from gyrolib.book.ledger import STATUSES
from gyrolib.book.ledger import rsf as ledger_rsf
from gyrolib.units import from_si

ROOT = Path(__file__).resolve().parents[1]
REQUIRED = [
    *[f"rsf.table2.dgamma_sins_{t}" for t in (10, 60, 120)],
    *[f"rsf.table2.dr_z_{t}" for t in (10, 60, 120)],
    *[f"rsf.table3.eps0_t_{t}" for t in (10, 60, 120)],
    *[f"rsf.table3.dgamma_gs_{t}" for t in (10, 60, 120)],
    "rsf.example.delta_K", "rsf.example.compensated",
    "rsf.table1.sf_error", "rsf.table1.bias_instability", "rsf.gs.sf_error",
    "rsf.encoder.position_error",
]


def _by_id(items):
    return {it.id: it for it in items}


@pytest.fixture(scope="module")
def items():
    return _by_id(ledger_rsf.items())


def test_required_ids_are_present_and_well_formed(items):
    assert not [i for i in REQUIRED if i not in items]
    for it in items.values():
        assert it.paper == "RSF" and it.status in STATUSES
        assert it.chapter in ("chapters/rsf_method", "chapters/rsf_simulation")
        assert it.anchor and len(it.note.splitlines()) == 1
        if it.paper_value == "figure":  # drawings: checked in the chapter, no number
            assert it.reproduced_value is None and it.location.startswith("Fig.")
        elif it.status != "not reproducible":
            assert it.reproduced_value is not None and math.isfinite(it.reproduced_value)


def test_every_anchor_is_a_label_of_its_chapter(items):
    for it in items.values():
        source = (ROOT / f"{it.chapter}.md").read_text(encoding="utf-8")
        label = rf"^\({re.escape(it.anchor)}\)=\s*$|^:name: {re.escape(it.anchor)}\s*$"
        assert re.search(label, source, re.M), \
            f"{it.id}: no label ({it.anchor})= in {it.chapter}.md"


def test_reproduced_items_agree_with_the_print(items):
    """'reproduced' means: within half a unit of the last printed digit (0.05 % here)."""
    for it in items.values():
        if it.status == "reproduced" and isinstance(it.paper_value, float):
            assert it.reproduced_value == pytest.approx(it.paper_value, rel=5e-4), it.id


def test_values_are_those_of_the_library(items):
    tab2, tab3 = rsf.table2(), rsf.table3()
    for i, t in enumerate((10, 60, 120)):
        assert items[f"rsf.table2.dgamma_sins_{t}"].reproduced_value \
            == pytest.approx(from_si(tab2.dgamma_sins[i], "deg"), rel=1e-15)
        assert items[f"rsf.table2.dr_z_{t}"].reproduced_value \
            == pytest.approx(tab2.dr_z_cubic[i], rel=1e-15)
        assert items[f"rsf.table3.dgamma_gs_{t}"].reproduced_value \
            == pytest.approx(from_si(tab3.dgamma_gs[i], "deg"), rel=1e-15)
    assert items["rsf.example.delta_K"].reproduced_value \
        == pytest.approx(rsf.worked_example_delta_k(), rel=1e-15)
    # The explained differences: consistent values against the print.
    assert items["rsf.example.delta_K"].reproduced_value == pytest.approx(1.704e-4, rel=1e-3)
    assert items["rsf.example.delta_K"].paper_value == 0.093
    assert items["rsf.example.compensated"].reproduced_value == pytest.approx(71.6, abs=0.1)
    assert items["rsf.table3.eps0_t_10"].reproduced_value == pytest.approx(0.0339, abs=1e-4)


@pytest.mark.parametrize("kwargs, moved, unchanged", [
    ({"roll_gyro": dataclasses.replace(rsf.SIIMU02_ROLL, sf_error=700e-6)},
     ["rsf.table2.dgamma_sins_10", "rsf.table2.dr_z_120", "rsf.example.compensated",
      "rsf.table1.sf_error"],
     ["rsf.table3.dgamma_gs_10", "rsf.example.delta_K"]),
    ({"gs_gyro": dataclasses.replace(rsf.GYPRO4300, bias_repeatability=rsf.GYPRO4300.
                                     bias_repeatability * 2)},
     ["rsf.table3.eps0_t_60", "rsf.table3.dgamma_gs_120", "rsf.example.delta_K",
      "rsf.gs.eps0_total"],
     ["rsf.table2.dgamma_sins_60"]),
    ({"gs_gyro": dataclasses.replace(rsf.GYPRO4300, sf_error=300e-6)},
     ["rsf.example.delta_K", "rsf.example.compensated"],
     ["rsf.table3.dgamma_gs_10"]),
    ({"encoder": dataclasses.replace(rsf.AEDB9340, position_error=rsf.AEDB9340.position_error / 2)},
     ["rsf.table3.dgamma_gs_10", "rsf.example.delta_K", "rsf.encoder.position_error"],
     ["rsf.table3.eps0_t_10", "rsf.table2.dr_z_10"]),
])
def test_ledger_values_move_when_an_input_is_perturbed(items, kwargs, moved, unchanged):
    perturbed = _by_id(ledger_rsf.items(**kwargs))
    for key in moved:
        assert perturbed[key].reproduced_value != pytest.approx(items[key].reproduced_value,
                                                                rel=1e-6), key
    for key in unchanged:
        assert perturbed[key].reproduced_value == items[key].reproduced_value, key


def test_sf_error_perturbation_scales_table2_linearly(items):
    perturbed = _by_id(ledger_rsf.items(
        roll_gyro=dataclasses.replace(rsf.SIIMU02_ROLL, sf_error=700e-6)))
    for t in (10, 60, 120):
        key = f"rsf.table2.dgamma_sins_{t}"
        assert perturbed[key].reproduced_value / items[key].reproduced_value \
            == pytest.approx(7 / 6, rel=1e-12)
