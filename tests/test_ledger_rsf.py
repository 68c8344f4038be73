"""Ledger items of paper RSF (gyrolib.book.ledger.rsf): present, computed (not stored), each
value and status checked against a hand calculation, linked to labels of the chapter, and
moving (values and statuses) with the inputs."""

import dataclasses
import math
import re
from pathlib import Path

import pytest

from gyrolib import rsf
from gyrolib.book.ledger import STATUSES
from gyrolib.book.ledger import rsf as ledger_rsf

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
    """Every printed item of paper RSF has a ledger entry with a chapter, an anchor and a one-line
    note."""
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
    """Each item's anchor is a label defined in its chapter's source."""
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


def test_values_against_hand_calculations(items):
    """Every ledger number of paper RSF against a hand calculation from the printed inputs
    (not a second call of the library): echoed inputs, Table 2's cubic Δr_z, Table 3's
    ε0,GS·t, the inferred encoder error and the consistent δK and share."""
    for key, hand in (("table1.bias_instability", 100.0), ("table1.sf_error", 600.0),
                      ("gs.sigma_rep", 10.0), ("gs.sigma_stab", 7.0), ("gs.sf_error", 280.0)):
        assert items[f"rsf.{key}"].reproduced_value == pytest.approx(hand, rel=1e-12), key
    g, w = 9.80665, 3600.0 * math.pi / 180.0
    eps0_gs = math.sqrt(10.0**2 + 7.0**2) / 3600.0                         # °/s
    for t in (10, 60, 120):
        assert items[f"rsf.table2.dr_z_{t}"].reproduced_value \
            == pytest.approx(g * 600e-6 * w * t**3 / 6.0, rel=1e-12)
        assert items[f"rsf.table3.eps0_t_{t}"].reproduced_value \
            == pytest.approx(eps0_gs * t, rel=1e-12)
    # Δγ_GS − ε0,GS·t of the printed Table 3: 0.363 − 0.033 = 0.528 − 0.198 = 0.33.
    assert items["rsf.encoder.position_error"].reproduced_value == pytest.approx(0.33, rel=1e-12)
    assert "0.33° in all three columns" in items["rsf.encoder.position_error"].note
    dk = ((eps0_gs + 280e-6 * 300.0) * 5.0 + 0.33) / (900.0 * 5.0)
    assert items["rsf.example.delta_K"].reproduced_value == pytest.approx(dk, rel=1e-12)
    assert dk == pytest.approx(1.704e-4, rel=1e-3) and items["rsf.example.delta_K"].paper_value \
        == 0.093
    assert items["rsf.example.compensated"].reproduced_value \
        == pytest.approx(100 * (1 - dk / 600e-6), rel=1e-12)
    assert items["rsf.example.compensated"].reproduced_value == pytest.approx(71.6, abs=0.1)


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
    """Perturbing one sensor record moves exactly the items computed from it."""
    perturbed = _by_id(ledger_rsf.items(**kwargs))
    for key in moved:
        assert perturbed[key].reproduced_value != pytest.approx(items[key].reproduced_value,
                                                                rel=1e-6), key
    for key in unchanged:
        assert perturbed[key].reproduced_value == items[key].reproduced_value, key


def test_sf_error_perturbation_scales_table2_linearly(items):
    """Raising ε1 from 600 to 700 ppm scales Table 2's roll errors by exactly 7/6."""
    perturbed = _by_id(ledger_rsf.items(
        roll_gyro=dataclasses.replace(rsf.SIIMU02_ROLL, sf_error=700e-6)))
    for t in (10, 60, 120):
        key = f"rsf.table2.dgamma_sins_{t}"
        assert perturbed[key].reproduced_value / items[key].reproduced_value \
            == pytest.approx(7 / 6, rel=1e-12)


# Each status against a hand calculation -----------------------------------------------------------
# Hand values (paper units): ε1 = 600 ppm, ω = 3600 °/s; ε0,GS = √(10² + 7²) °/h; ε1,GS = 280 ppm;
# Δγ_enc = 0.33°; worked example ω_x = 900 °/s, ω_unc = 300 °/s, Δt = 5 s.
EPS0_GS_DEG_S = math.sqrt(10.0**2 + 7.0**2) / 3600.0          # 3.3907e-3 °/s


def test_table2_roll_errors_are_reproduced_by_hand(items):
    """Table 2's roll errors are ε1 ω t by hand and agree with the print to half its last digit:
    reproduced."""
    for t in (10, 60, 120):
        hand = 600e-6 * 3600.0 * t                              # 21.6, 129.6, 259.2 °
        it = items[f"rsf.table2.dgamma_sins_{t}"]
        assert it.reproduced_value == pytest.approx(hand, rel=1e-12)
        assert abs(hand - it.paper_value) <= 0.05 and it.status == "reproduced"


def test_eps0_gs_truncation_is_the_cause_shown(items):
    """ε0,GS rounds to 3.4·10⁻³ but truncates to the printed 3.3·10⁻³ °/s: differs, cause shown."""
    it = items["rsf.gs.eps0_total"]
    assert it.reproduced_value == pytest.approx(EPS0_GS_DEG_S, rel=1e-12)
    # Rounded it is 3.4e-3, cut it is 3.3e-3, the print: a truncation.
    assert f"{EPS0_GS_DEG_S:.1e}" == "3.4e-03" and math.floor(EPS0_GS_DEG_S * 1e4) == 33
    assert it.status == "differs: cause shown"


def test_table3_differs_by_the_truncation_and_the_encoder_is_circular(items):
    """Table 3 is reproduced by the truncated ε0,GS, not the consistent one, and its items say the
    encoder term is circular."""
    for t, printed in ((10, 0.363), (60, 0.528), (120, 0.726)):
        consistent = EPS0_GS_DEG_S * t + 0.33
        truncated = 3.3e-3 * t + 0.33
        it = items[f"rsf.table3.dgamma_gs_{t}"]
        assert it.reproduced_value == pytest.approx(consistent, rel=1e-12)
        assert abs(truncated - printed) < 5e-4 < abs(consistent - printed)
        assert it.status == "differs: cause shown"
        assert "inferred from this" in it.note and "inferred from this same table" in it.evidence


def test_worked_example_slip_gives_the_print_by_hand(items):
    """The ppm-as-10⁻³ slip gives the printed 0.093 by hand; the consistent δK is the ledger's
    value."""
    consistent = ((EPS0_GS_DEG_S + 280e-6 * 300.0) * 5.0 + 0.33) / (900.0 * 5.0)
    slipped = ((3.3e-3 + 280e-3 * 300.0) * 5.0 + 0.33) / (900.0 * 5.0)   # 0.0934
    it = items["rsf.example.delta_K"]
    assert it.reproduced_value == pytest.approx(consistent, rel=1e-12)
    assert abs(slipped - 0.093) < 5e-4 and it.status == "differs: cause shown"


def test_compensated_is_a_claim_with_the_threshold_rate_by_hand(items):
    """'Compensates 90 %' is a claim holding from the hand-computed 2557 °/s, with 72 % at 900 °/s
    and 93 % at 3600 °/s."""
    it = items["rsf.example.compensated"]
    numerator = (EPS0_GS_DEG_S + 280e-6 * 300.0) * 5.0 + 0.33    # ° over one interval
    share_900 = 1.0 - numerator / (900.0 * 5.0) / 600e-6
    share_3600 = 1.0 - numerator / (3600.0 * 5.0) / 600e-6
    w90 = numerator / (5.0 * 600e-6 * 0.1)                        # 2557 °/s
    assert it.kind == "claim" and it.status == "holds under conditions"
    assert it.reproduced_value == pytest.approx(100 * share_900, rel=1e-9)
    assert f"≥ {w90:.0f} °/s" in it.conditions and w90 == pytest.approx(2556.5, abs=0.5)
    assert f"{100 * share_3600:.0f} % at 3600 °/s" in it.conditions
    assert share_3600 == pytest.approx(0.929, abs=1e-3)


def test_gs_vs_sins_conditions_by_hand(items):
    """'Hundreds of times' holds for the ideal GS from 60 s, not at 10 s, and not for the non-
    ideal GS (tens), by hand."""
    it = items["rsf.claim.gs_vs_sins"]
    ideal = [600e-6 * 3600 * t / (EPS0_GS_DEG_S * t + 0.33) for t in (10, 60, 120)]
    nonideal = [600e-6 * 3600 * t / ((EPS0_GS_DEG_S + 280e-6 * 300) * t + 0.33)
                for t in (10, 60, 120)]
    assert it.reproduced_value == pytest.approx(ideal[0], rel=1e-9)
    assert ideal[0] < 100 < min(ideal[1:]) and max(nonideal) < 100
    assert it.status == "holds under conditions"
    assert f"{min(nonideal):.0f}–{max(nonideal):.0f}×" in it.conditions


def test_drz_statuses_follow_the_slip_search():
    # The consistent cubic is 2.9× the print; the search finds no slip: not reproducible.
    """No unit slip gives the printed Δr_z (2.9× off), and the same search does find a planted mm
    slip."""
    hand_cubic_10 = 9.80665 * 600e-6 * math.radians(3600.0) * 10.0**3 / 6.0
    search = rsf.drz_slip_search([21.25, 4590.0, 36730.0])
    assert hand_cubic_10 / 21.25 == pytest.approx(2.900, abs=1e-3)
    assert search.hits == ()
    # Power: the same search finds the cubic itself once the "print" is the cubic ×1000 (mm).
    fake = [hand_cubic_10 * 1e3 * (t / 10) ** 3 for t in (10, 60, 120)]
    assert ("mm",) in rsf.drz_slip_search(fake, half_digits=[0.5, 0.5, 0.5]).hits


# Power: the statuses are computed, so a wrong input changes them ----------------------------
def test_a_wrong_encoder_breaks_table3_and_a_wrong_gs_gyro_breaks_the_slip():
    """Statuses are computed: a wrong encoder makes Table 3 not reproducible and a wrong GS gyro
    the worked example."""
    wrong_enc = _by_id(ledger_rsf.items(encoder=dataclasses.replace(rsf.AEDB9340,
                                                                    position_error=0.005)))
    for t in (10, 60, 120):
        assert wrong_enc[f"rsf.table3.dgamma_gs_{t}"].status == "not reproducible"
        assert wrong_enc[f"rsf.table3.eps0_t_{t}"].status == "differs: cause shown"
    wrong_gs = _by_id(ledger_rsf.items(gs_gyro=dataclasses.replace(rsf.GYPRO4300,
                                                                   sf_error=400e-6)))
    assert wrong_gs["rsf.example.delta_K"].status == "not reproducible"


def test_a_better_gs_makes_the_claims_hold_and_a_worse_one_fails():
    """Statuses are computed: a perfect GS makes both claims hold, a bad encoder makes both fail."""
    ideal_enc = dataclasses.replace(rsf.AEDB9340, position_error=0.0)
    quiet = dataclasses.replace(rsf.GYPRO4300, sf_error=0.0, bias_repeatability=0.0,
                                bias_stability=1e-9)
    good = _by_id(ledger_rsf.items(gs_gyro=quiet, encoder=ideal_enc))
    assert good["rsf.example.compensated"].status == "holds"
    assert good["rsf.claim.gs_vs_sins"].status == "holds"
    bad = _by_id(ledger_rsf.items(encoder=dataclasses.replace(rsf.AEDB9340,
                                                              position_error=0.5)))
    assert bad["rsf.example.compensated"].status == "fails"
    assert bad["rsf.claim.gs_vs_sins"].status == "fails"


def test_kilometres_claim_is_the_lateral_component_with_the_vertical_one_stated():
    """'Kilometres' of lateral deviation: the exact lateral double integral by hand
    (g (x − sin x)/a²) exceeds 1 km within two minutes, and the conditions give the vertical
    component by hand (g (x²/2 − 1 + cos x)/a²); a gyro 600× better makes the claim fail."""
    it = _by_id(ledger_rsf.items())["rsf.claim.drz_kilometres"]
    g, a = 9.80665, 600e-6 * math.radians(3600.0)
    x = a * 120.0
    lateral = g * (x - math.sin(x)) / a**2
    vertical = g * (x**2 / 2 - 1 + math.cos(x)) / a**2
    assert it.reproduced_value == pytest.approx(lateral, rel=1e-9) and lateral > 1000.0
    assert it.status == "holds under conditions" and f"{vertical:.3g} m at 120 s" in it.conditions
    assert vertical > lateral
    better = _by_id(ledger_rsf.items(
        roll_gyro=dataclasses.replace(rsf.SIIMU02_ROLL, sf_error=1e-6)))
    assert better["rsf.claim.drz_kilometres"].status == "fails"
