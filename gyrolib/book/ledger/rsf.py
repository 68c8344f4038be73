"""Ledger items of paper RSF: every printed number and verbal claim of the roll-gyro
correction paper.

Only the ``paper_value`` column (what the paper prints) is stored here, in :data:`PRINTED`;
every reproduced value is computed by :mod:`gyrolib.rsf` from the sensor records, and so is
every status: a printed number is "reproduced" when the consistent computation agrees with
the print to half a unit of its last digit, "differs: cause shown" when it does not but the
computation with the identified cause (a truncation, a unit slip) does, and "not
reproducible" otherwise; a claim's status and conditions come from the computation that
tests it.  Perturbing a record moves the ledger (see ``tests/test_ledger_rsf.py``).
"""

from __future__ import annotations

import math
from decimal import Decimal
from typing import Final

import numpy as np

from gyrolib.book.ledger import LedgerItem
from gyrolib.rsf.claims import compensation_share, drz_slip_search, gs_vs_sins
from gyrolib.rsf.equations import fraction_compensated
from gyrolib.rsf.sensors import (
    AEDB9340,
    GYPRO4300,
    SIIMU02_ROLL,
    EncoderSpec,
    MemsGyroSpec,
    RollGyroSpec,
)
from gyrolib.rsf.tables import table2, table3, worked_example_delta_k
from gyrolib.units import from_si, to_si

__all__ = ["CLAIM_RATES", "PRINTED", "TIMES", "items"]

#: Table columns of the paper, s.
TIMES: Final[tuple[int, ...]] = (10, 60, 120)

#: Roll rates (°/s) over which the conclusion's "90 %" is judged: the worked example's 900 °/s
#: and the paper's own range, 1800 to 5400 °/s.
CLAIM_RATES: Final[tuple[float, ...]] = (900.0, 1800.0, 2700.0, 3600.0, 4500.0, 5400.0)

#: What paper RSF prints (its units: °, °/h, ppm, °/s, %; Δr_z's unit is lost).
PRINTED: Final[dict[str, float]] = {
    "table1.bias_instability": 100.0,
    "table1.sf_error": 600.0,
    "gs.sigma_rep": 10.0,
    "gs.sigma_stab": 7.0,
    "gs.sf_error": 280.0,
    "gs.eps0_total": 3.3e-3,
    "table2.dgamma_sins_10": 21.6,
    "table2.dgamma_sins_60": 129.6,
    "table2.dgamma_sins_120": 259.2,
    "table2.dr_z_10": 21.25,
    "table2.dr_z_60": 4590.0,
    "table2.dr_z_120": 36730.0,
    "table3.eps0_t_10": 0.033,
    "table3.eps0_t_60": 0.198,
    "table3.eps0_t_120": 0.396,
    "table3.dgamma_gs_10": 0.363,
    "table3.dgamma_gs_60": 0.528,
    "table3.dgamma_gs_120": 0.726,
    "example.delta_K": 0.093,
    "example.compensated": 90.0,
    "claim.gs_vs_sins": 100.0,   # "hundreds of times": at least 100
}

_METHOD = "chapters/rsf_method"


def _half_unit(value: float) -> float:
    """Half a unit of the last significant digit of a printed number (trailing zeros of an
    integer are not significant: 4590 is ± 5, 0.093 is ± 0.0005).

    >>> _half_unit(0.093), _half_unit(4590.0), _half_unit(21.25)
    (0.0005, 5.0, 0.005)
    """
    exponent = Decimal(repr(float(value))).normalize().as_tuple().exponent
    return float(Decimal("0.5").scaleb(int(exponent)))


def _agrees(value: float | None, key: str) -> bool:
    """``value`` (in the paper's unit) is the printed number to the print's digits."""
    if value is None:
        return False
    printed = PRINTED[key]
    return abs(value - printed) <= _half_unit(printed) * (1.0 + 1e-9)


def _verdict(key: str, consistent: float, explained: float | None = None) -> str:
    """Status of a printed number from what the computations give."""
    if _agrees(consistent, key):
        return "reproduced"
    if _agrees(explained, key):
        return "differs: cause shown"
    return "not reproducible"


def _implied_encoder() -> float:
    """Δγ_GS − ε0,GS·t of the printed Table 3 (°), the same in every column."""
    return min(PRINTED[f"table3.dgamma_gs_{t}"] - PRINTED[f"table3.eps0_t_{t}"] for t in TIMES)


def _truncate(value: float, key: str) -> float:
    """``value`` cut (not rounded) to the digits of the printed number ``key``."""
    unit = 2.0 * _half_unit(PRINTED[key])
    return math.floor(value / unit + 1e-9) * unit


def _item(key: str, location: str, quantity: str, unit: str, value: float | None,
          status: str, note: str, anchor: str,
          paper_value: float | str | None = None, *, kind: str, evidence: str,
          conditions: str = "", precision: int = 4) -> LedgerItem:
    return LedgerItem(
        id=f"rsf.{key}", paper="RSF", location=location, quantity=quantity, unit=unit,
        paper_value=PRINTED.get(key) if paper_value is None else paper_value,
        reproduced_value=None if value is None else float(value), status=status, note=note,
        chapter=_METHOD, anchor=anchor, kind=kind, evidence=evidence, conditions=conditions,
        precision=precision,
    )


def _range_text(values: np.ndarray, fmt: str = ".0f") -> str:
    lo, hi = float(np.min(values)), float(np.max(values))
    return f"{lo:{fmt}}×" if f"{lo:{fmt}}" == f"{hi:{fmt}}" else f"{lo:{fmt}}–{hi:{fmt}}×"


def items(*, roll_gyro: RollGyroSpec = SIIMU02_ROLL,
          gs_gyro: MemsGyroSpec = GYPRO4300,
          encoder: EncoderSpec = AEDB9340) -> list[LedgerItem]:
    """The ledger items of paper RSF, in the order the paper prints them.

    The keyword arguments replace the paper's sensor records (for sensitivity checks): the
    values and the statuses move with them.
    """
    for name, value, cls in (("roll_gyro", roll_gyro, RollGyroSpec),
                             ("gs_gyro", gs_gyro, MemsGyroSpec),
                             ("encoder", encoder, EncoderSpec)):
        if not isinstance(value, cls):
            raise TypeError(f"{name} must be a {cls.__name__}; got {type(value).__name__}")
    out: list[LedgerItem] = []
    echoed = "sensor data the paper gives and uses; echoed, not reproduced"
    # Sensor data -------------------------------------------------------------------------
    out.append(_item(
        "table1.bias_instability", "Table 1", "SiIMU02 roll gyro bias instability (1σ)",
        "°/h", from_si(roll_gyro.bias_instability, "deg/h"), "input",
        "unit lost in the extraction; read as °/h, the only reading with ε0 ≪ ε1·ω as the "
        "paper assumes", "rsf-sensors", kind="input", precision=3, evidence=echoed))
    out.append(_item(
        "table1.sf_error", "Table 1", "SiIMU02 roll gyro scale-factor error ε1 (1σ)", "ppm",
        from_si(roll_gyro.sf_error, "ppm"), "input",
        "used as ε1 in Table 2", "rsf-sensors", kind="input", precision=3, evidence=echoed))
    out.append(_item(
        "gs.sigma_rep", "GS gyro table", "GYPRO4300 bias repeatability σ_rep (1σ)", "°/h",
        from_si(gs_gyro.bias_repeatability, "deg/h"), "input", "as printed",
        "rsf-sensors", kind="input", precision=3, evidence=echoed))
    out.append(_item(
        "gs.sigma_stab", "GS gyro table", "GYPRO4300 in-run bias stability σ_stab (1σ)",
        "°/h", from_si(gs_gyro.bias_stability, "deg/h"), "input", "as printed",
        "rsf-sensors", kind="input", precision=3, evidence=echoed))
    out.append(_item(
        "gs.sf_error", "GS gyro table", "GYPRO4300 scale-factor error ε1,GS (1σ)", "ppm",
        from_si(gs_gyro.sf_error, "ppm"), "input",
        "the worked example misprints it as 280·10⁻³ instead of ppm", "rsf-sensors",
        kind="input", precision=3, evidence=echoed))
    eps0_deg_s = float(from_si(gs_gyro.bias_total, "deg/s"))
    eps0_cut = _truncate(eps0_deg_s, "gs.eps0_total")
    out.append(_item(
        "gs.eps0_total", "Table 3 and example", "ε0,GS = √(σ_rep² + σ_stab²)", "°/s",
        eps0_deg_s, _verdict("gs.eps0_total", eps0_deg_s, eps0_cut),
        f"√(σ_rep² + σ_stab²) = {from_si(gs_gyro.bias_total, 'deg/h'):.3g} °/h; cut to the "
        f"print's digits it is {eps0_cut:.2g} °/s", "rsf-table3", kind="printed number",
        precision=3,
        evidence="√(σ_rep² + σ_stab²) from the printed σ's, truncated (not rounded) to the "
        "print's two digits, against the print"))
    out.append(_item(
        "encoder.position_error", "text before Table 3", "AEDB-9340 position error Δγ_enc",
        "°", from_si(encoder.position_error, "deg"), "inferred",
        "value lost in the extraction; Table 3 implies "
        f"{_implied_encoder():.2f}° in all three columns (Δγ_GS − ε0,GS·t)", "rsf-encoder",
        paper_value="lost in the extraction", kind="inferred", precision=2,
        evidence="Δγ_GS − ε0,GS·t of the printed Table 3, the same in all three columns; it "
        "cannot then count as reproducing Table 3"))

    # Table 2 -----------------------------------------------------------------------------
    t2 = table2(roll_gyro)
    printed_drz = [PRINTED[f"table2.dr_z_{t}"] for t in TIMES]
    search = drz_slip_search(printed_drz, TIMES, [_half_unit(p) for p in printed_drz],
                             roll_gyro=roll_gyro)
    for i, t in enumerate(TIMES):
        dg = float(from_si(t2.dgamma_sins[i], "deg"))
        cubic, key = float(t2.dr_z_cubic[i]), f"table2.dr_z_{t}"
        out.append(_item(
            f"table2.dgamma_sins_{t}", "Table 2", f"SINS roll error Δγ_SINS at t = {t} s",
            "°", dg, _verdict(f"table2.dgamma_sins_{t}", dg),
            "Eq. (4), ε1·ω·t with ω = 3600 °/s", "rsf-table2", kind="printed number",
            evidence="Eq. (4) from Table 1's ε1 at 3600 °/s against the print to its digits"))
        out.append(_item(
            key, "Table 2", f"lateral deviation Δr_z at t = {t} s (cubic, Eq. 8)",
            "m", cubic, _verdict(key, cubic, PRINTED[key] if search.hits else None),
            f"printed values follow t³ exactly but at {PRINTED[key] / cubic:.3f}× "
            f"g·ε1·ω·t³/6 (unit lost); {len(search.hits)} of {search.tried} unit-slip "
            f"products reproduce them; exact lateral double integral {t2.dr_z_exact[i]:.4g} m, "
            f"vertical component {t2.dr_y_exact[i]:.4g} m", "rsf-table2", kind="printed number",
            evidence="Eq. (8) from the printed inputs against the print, then every product of "
            "up to three unit slips (drz_slip_search) against the print's rounding window"))

    # The prose's "kilometres" for Δr_z holds for the exact lateral integral, under Eq. (8)'s
    # premise, and leaves out the larger vertical component.
    km = 1000.0
    last = len(TIMES) - 1
    over_km = [t for t, d in zip(TIMES, t2.dr_z_exact) if d >= km]
    if not over_km:
        status, conditions = "fails", ""
    else:
        status = "holds under conditions"
        conditions = (f"1 g of lift normal to the roll axis (Eq. (8)'s premise), lateral "
                      f"component only: exact lateral Δr_z ≥ 1 km at "
                      f"{', '.join(f'{t} s' for t in over_km)} "
                      f"({t2.dr_z_exact[last]:.3g} m at {TIMES[last]} s); the vertical error "
                      f"g (1 − cos Δγ) adds {t2.dr_y_exact[last]:.3g} m at {TIMES[last]} s")
    out.append(_item(
        "claim.drz_kilometres", "text with Table 2",
        f"lateral deviation, exact double integral, at t = {TIMES[last]} s", "m",
        t2.dr_z_exact[last], status,
        "the cubic overstates it; the exact lateral and vertical components are: "
        + ", ".join(f"{z:.3g} m and {y:.3g} m at {t} s"
                    for t, z, y in zip(TIMES, t2.dr_z_exact, t2.dr_y_exact)),
        "rsf-drz-vertical", paper_value="kilometres", kind="claim", precision=3,
        conditions=conditions,
        evidence="exact double integrals of g sin Δγ (lateral) and g (1 − cos Δγ) (vertical) "
        "at Table 2's times, against 1 km"))

    # Table 3 -----------------------------------------------------------------------------
    t3 = table3(gs_gyro, encoder)
    t3p = table3(gs_gyro, encoder, eps0_gs=float(to_si(eps0_cut, "deg/s")))
    for i, t in enumerate(TIMES):
        e0t, e0t_cut = float(from_si(t3.eps0_t[i], "deg")), float(from_si(t3p.eps0_t[i], "deg"))
        out.append(_item(
            f"table3.eps0_t_{t}", "Table 3", f"GS bias error ε0,GS·t at t = {t} s", "°",
            e0t, _verdict(f"table3.eps0_t_{t}", e0t, e0t_cut),
            f"ε0,GS = {eps0_deg_s * 1e3:.3f}·10⁻³ °/s; cut to {eps0_cut * 1e3:.2g}·10⁻³ °/s as "
            f"the paper does it gives {e0t_cut:.3f}°", "rsf-table3", kind="printed number",
            evidence="ε0,GS·t with the consistent and with the truncated ε0,GS against the print"))
        dg, dg_cut = float(from_si(t3.dgamma_gs[i], "deg")), float(from_si(t3p.dgamma_gs[i],
                                                                             "deg"))
        out.append(_item(
            f"table3.dgamma_gs_{t}", "Table 3", f"GS roll error Δγ_GS at t = {t} s (Eq. 9)",
            "°", dg, _verdict(f"table3.dgamma_gs_{t}", dg, dg_cut),
            f"Eq. (9) with Δγ_enc = {from_si(encoder.position_error, 'deg'):.2f}°, itself "
            "inferred from this table (so only the ε0,GS·t part is tested); with the truncated "
            f"ε0,GS it gives {dg_cut:.3f}°", "rsf-table3", kind="printed number",
            evidence="Eq. (9) with the truncated ε0,GS and the Δγ_enc inferred from this same "
            "table against the print: a check of the ε0,GS·t term only"))
    ratios = gs_vs_sins(TIMES, roll_gyro=roll_gyro, gs_gyro=gs_gyro, encoder=encoder)
    many = PRINTED["claim.gs_vs_sins"]
    ok_ideal, ok_non = ratios.ratio_ideal >= many, ratios.ratio_nonideal >= many
    if ok_ideal.all() and ok_non.all():
        status, conditions = "holds", ""
    elif not ok_ideal.any():
        status, conditions = "fails", ""
    else:
        held = ", ".join(f"{t:g} s" for t, ok in zip(ratios.t, ok_ideal) if ok)
        missed = ", ".join(f"{r:.0f}× at {t:g} s" for t, r, ok
                           in zip(ratios.t, ratios.ratio_ideal, ok_ideal) if not ok)
        conditions = (f"the ideal GS of Table 3 at {held}" + (f" ({missed})" if missed else "")
                      + "; the worked example's non-ideal GS (ω_unc = "
                      f"{from_si(ratios.omega_unc, 'deg/s'):.0f} °/s) only "
                      f"{_range_text(ratios.ratio_nonideal)}, tens"
                      + (" at every printed time" if not ok_non.any() else ""))
        status = "holds under conditions"
    out.append(_item(
        "claim.gs_vs_sins", "after Table 3", "Δγ_SINS / Δγ_GS at t = 10 s (ideal GS)", "1",
        ratios.ratio_ideal[0], status,
        f"ideal GS (Eq. 9): {', '.join(f'{r:.0f}×' for r in ratios.ratio_ideal)} at "
        f"{', '.join(f'{t:g}' for t in ratios.t)} s; non-ideal GS (Eq. 6): "
        f"{', '.join(f'{r:.0f}×' for r in ratios.ratio_nonideal)}",
        "rsf-gs-vs-sins", paper_value="hundreds", kind="claim", precision=3,
        conditions=conditions,
        evidence="Eq. (4) over Eq. (9) (ideal GS) and over Eq. (6) (ω_unc = 300 °/s) at each "
        "printed time, against 100"))

    # Worked example and conclusion -------------------------------------------------------------
    dk = worked_example_delta_k(gs_gyro, encoder)
    dk_slip = worked_example_delta_k(
        gs_gyro, encoder, eps0_gs=float(to_si(eps0_cut, "deg/s")),
        eps1_gs=float(to_si(from_si(gs_gyro.sf_error, "ppm"), "permille")))
    out.append(_item(
        "example.delta_K", "worked example, Eq. (7)", "relative error δK of K", "1", dk,
        _verdict("example.delta_K", dk, dk_slip),
        f"the print takes ε1,GS = 280·10⁻³ instead of 280 ppm, which gives {dk_slip:.4f}; "
        f"with 280 ppm δK is {dk_slip / dk:.0f}× smaller", "rsf-example",
        kind="printed number", precision=3,
        evidence="Eq. (7) with the consistent ε1,GS and with ε1,GS read as 10⁻³ instead of ppm "
        "(the unit slip) against the printed 0.093"))
    rates = to_si(np.array(CLAIM_RATES), "deg/s")
    target = PRINTED["example.compensated"] / 100.0
    cs = compensation_share(rates, roll_gyro=roll_gyro, gs_gyro=gs_gyro, encoder=encoder,
                            target=target)
    frac = 100.0 * float(fraction_compensated(roll_gyro.sf_error, dk))
    w_star = float(from_si(cs.rate_for_target, "deg/s"))
    if cs.rate_for_target <= rates[0]:
        status, conditions = "holds", ""
    elif cs.rate_for_target > rates[-1]:
        status, conditions = "fails", ""
    else:
        status = "holds under conditions"
        i3600 = CLAIM_RATES.index(3600.0)
        conditions = (f"roll rate ≥ {w_star:.0f} °/s (Eq. (7), ω_unc = "
                      f"{from_si(cs.omega_unc, 'deg/s'):.0f} °/s, Δt = {cs.period:g} s): "
                      f"{100 * cs.share[i3600]:.0f} % at 3600 °/s, "
                      f"{100 * cs.share[-1]:.0f} % at {CLAIM_RATES[-1]:.0f} °/s, but "
                      f"{frac:.0f} % at the worked example's {CLAIM_RATES[0]:.0f} °/s")
    out.append(_item(
        "example.compensated", "conclusion", "share of the SF error compensated at 900 °/s",
        "%", frac, status,
        "the paper reads 1 − δK (slipped δK) as the share; the residual SF error is δK itself, "
        f"so the share is 1 − δK/ε1; it reaches {100 * target:.0f} % from {w_star:.0f} °/s",
        "rsf-compensated", kind="claim", precision=3, conditions=conditions,
        evidence="1 − δK/ε1 from Eq. (7) over the worked example's 900 °/s and the paper's "
        "1800–5400 °/s, and the closed-form rate where it reaches 90 %"))

    # Figures (drawings and curves without printed numbers) --------------------------------------
    for key, location, quantity, note, anchor in (
        ("fig1", "Fig. 1", "functional scheme of the correction method (block diagram)",
         "redrawn by code as a block diagram from the text and Eqs. (1)-(3)", "fig-rsf-fig1"),
        ("fig2", "Fig. 2", "functional scheme of the improved GS (block diagram)",
         "redrawn by code: PI motor loop, uncompensated rate, encoder angle", "fig-rsf-fig2"),
        ("fig3", "Fig. 3", "gravity projection on the lateral axis and the lateral error growth",
         "redrawn with the small-angle cubic of Eq. (8) and the exact double integral of "
         "g·sin Δγ on one plot", "fig-rsf-fig3"),
    ):
        out.append(_item(key, location, quantity, "—", None, "redrawn", note, anchor,
                         paper_value="figure", kind="figure",
                         evidence="drawn by code from the text; no number"))
    return out
