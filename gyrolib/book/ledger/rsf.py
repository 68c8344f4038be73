"""Ledger items of paper RSF: every printed number of the roll-gyro correction paper.

Only the ``paper_value`` column (what the paper prints) is stored here, in :data:`PRINTED`;
every reproduced value is computed by :mod:`gyrolib.rsf` from the sensor records,
so perturbing a record moves the ledger (see ``tests/test_ledger_rsf.py``).
"""

from __future__ import annotations

from typing import Final

from gyrolib.book.ledger import LedgerItem
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

__all__ = ["PRINTED", "TIMES", "items"]

#: Table columns of the paper, s.
TIMES: Final[tuple[int, ...]] = (10, 60, 120)

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
}

_METHOD = "chapters/rsf_method"


def _implied_encoder() -> float:
    """Δγ_GS − ε0,GS·t of the printed Table 3 (°), the same in every column."""
    return min(PRINTED[f"table3.dgamma_gs_{t}"] - PRINTED[f"table3.eps0_t_{t}"] for t in TIMES)


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


def items(*, roll_gyro: RollGyroSpec = SIIMU02_ROLL,
          gs_gyro: MemsGyroSpec = GYPRO4300,
          encoder: EncoderSpec = AEDB9340) -> list[LedgerItem]:
    """The ledger items of paper RSF, in the order the paper prints them.

    The keyword arguments replace the paper's sensor records (for sensitivity checks).
    """
    for name, value, cls in (("roll_gyro", roll_gyro, RollGyroSpec),
                             ("gs_gyro", gs_gyro, MemsGyroSpec),
                             ("encoder", encoder, EncoderSpec)):
        if not isinstance(value, cls):
            raise TypeError(f"{name} must be a {cls.__name__}; got {type(value).__name__}")
    out: list[LedgerItem] = []
    # Sensor data -------------------------------------------------------------------------
    out.append(_item(
        "table1.bias_instability", "Table 1", "SiIMU02 roll gyro bias instability (1σ)",
        "°/h", from_si(roll_gyro.bias_instability, "deg/h"), "input",
        "unit lost in the extraction; read as °/h, the only reading with ε0 ≪ ε1·ω as the "
        "paper assumes", "rsf-sensors", kind="input", precision=3,
        evidence="sensor data the paper gives and uses; echoed, not reproduced"))
    out.append(_item(
        "table1.sf_error", "Table 1", "SiIMU02 roll gyro scale-factor error ε1 (1σ)", "ppm",
        from_si(roll_gyro.sf_error, "ppm"), "input",
        "used as ε1 in Table 2", "rsf-sensors", kind="input", precision=3,
        evidence="sensor data the paper gives and uses; echoed, not reproduced"))
    out.append(_item(
        "gs.sigma_rep", "GS gyro table", "GYPRO4300 bias repeatability σ_rep (1σ)", "°/h",
        from_si(gs_gyro.bias_repeatability, "deg/h"), "input", "as printed",
        "rsf-sensors", kind="input", precision=3,
        evidence="sensor data the paper gives and uses; echoed, not reproduced"))
    out.append(_item(
        "gs.sigma_stab", "GS gyro table", "GYPRO4300 in-run bias stability σ_stab (1σ)",
        "°/h", from_si(gs_gyro.bias_stability, "deg/h"), "input", "as printed",
        "rsf-sensors", kind="input", precision=3,
        evidence="sensor data the paper gives and uses; echoed, not reproduced"))
    out.append(_item(
        "gs.sf_error", "GS gyro table", "GYPRO4300 scale-factor error ε1,GS (1σ)", "ppm",
        from_si(gs_gyro.sf_error, "ppm"), "input",
        "the worked example misprints it as 280·10⁻³ instead of ppm", "rsf-sensors",
        kind="input", precision=3,
        evidence="sensor data the paper gives and uses; echoed, not reproduced"))
    out.append(_item(
        "gs.eps0_total", "Table 3 and example", "ε0,GS = √(σ_rep² + σ_stab²)", "°/s",
        from_si(gs_gyro.bias_total, "deg/s"), "differs: cause shown",
        f"√(σ_rep² + σ_stab²) = {from_si(gs_gyro.bias_total, 'deg/h'):.3g} °/h; the paper "
        "truncates it to 3.3·10⁻³ °/s",
        "rsf-table3", kind="printed number", precision=3,
        evidence="√(σ_rep² + σ_stab²) from the printed σ's, truncated to two digits, gives the "
        "printed value"))
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
    for t, dg, cubic, exact in zip(TIMES, t2.dgamma_sins, t2.dr_z_cubic, t2.dr_z_exact):
        out.append(_item(
            f"table2.dgamma_sins_{t}", "Table 2", f"SINS roll error Δγ_SINS at t = {t} s",
            "°", from_si(dg, "deg"), "reproduced", "Eq. (4), ε1·ω·t with ω = 3600 °/s",
            "rsf-table2", kind="printed number",
            evidence="Eq. (4) from Table 1's ε1 at 3600 °/s equals the print to its digits"))
        out.append(_item(
            f"table2.dr_z_{t}", "Table 2", f"lateral deviation Δr_z at t = {t} s (cubic, Eq. 8)",
            "m", cubic, "not reproducible",
            f"printed values follow t³ exactly but at {PRINTED[f'table2.dr_z_{t}'] / cubic:.3f}× "
            "g·ε1·ω·t³/6 (unit lost); no unit slip tried reproduces them; exact double "
            f"integral {exact:.4g} m", "rsf-table2", kind="printed number",
            evidence="Eq. (8) from the printed inputs; the print is a constant factor off and "
            "no unit slip among those searched gives it"))

    # Table 3 -----------------------------------------------------------------------------
    t3 = table3(gs_gyro, encoder)
    t3p = table3(gs_gyro, encoder, eps0_gs=float(to_si(PRINTED["gs.eps0_total"], "deg/s")))
    for i, t in enumerate(TIMES):
        out.append(_item(
            f"table3.eps0_t_{t}", "Table 3", f"GS bias error ε0,GS·t at t = {t} s", "°",
            from_si(t3.eps0_t[i], "deg"), "differs: cause shown",
            f"ε0,GS = {from_si(gs_gyro.bias_total, 'deg/s') * 1e3:.3f}·10⁻³ °/s; the print "
            "uses 3.3·10⁻³ °/s and then gives "
            f"{from_si(t3p.eps0_t[i], 'deg'):.3f}°", "rsf-table3", kind="printed number",
            evidence="ε0,GS·t with ε0,GS truncated to 3.3e-3 °/s gives the print"))
        out.append(_item(
            f"table3.dgamma_gs_{t}", "Table 3", f"GS roll error Δγ_GS at t = {t} s (Eq. 9)",
            "°", from_si(t3.dgamma_gs[i], "deg"), "differs: cause shown",
            f"Eq. (9) with Δγ_enc = {from_si(encoder.position_error, 'deg'):.2f}°; with the "
            "truncated ε0,GS the print gives "
            f"{from_si(t3p.dgamma_gs[i], 'deg'):.3f}°", "rsf-table3", kind="printed number",
            evidence="Eq. (9) with the truncated ε0,GS and the inferred Δγ_enc gives the print"))
    ratio = t2.dgamma_sins / t3.dgamma_gs
    out.append(_item(
        "claim.gs_vs_sins", "after Table 3", "Δγ_SINS / Δγ_GS at t = 10 s", "1", ratio[0],
        "holds under conditions",
        f"'hundreds of times smaller' holds at 60 s and 120 s ({ratio[1]:.0f}×, "
        f"{ratio[2]:.0f}×) but not at 10 s",
        "rsf-gs-vs-sins", paper_value="hundreds", kind="claim", precision=3,
        conditions="the ideal GS of Table 3 after 60 s and 120 s; not at 10 s",
        evidence="Table 2's Δγ_SINS over Table 3's Δγ_GS at each printed time"))

    # Worked example and conclusion -------------------------------------------------------------
    dk = worked_example_delta_k(gs_gyro, encoder)
    dk_slip = worked_example_delta_k(
        gs_gyro, encoder, eps0_gs=float(to_si(PRINTED["gs.eps0_total"], "deg/s")),
        eps1_gs=float(PRINTED["gs.sf_error"]) * 1e-3)
    out.append(_item(
        "example.delta_K", "worked example, Eq. (7)", "relative error δK of K", "1", dk,
        "differs: cause shown",
        f"the print takes ε1,GS = 280·10⁻³ instead of 280 ppm, which gives {dk_slip:.4f}; "
        f"with 280 ppm δK is {dk_slip / dk:.0f}× smaller", "rsf-example",
        kind="printed number", precision=3,
        evidence="Eq. (7) with ε1,GS = 280e-3 (the unit slip) gives the printed 0.093"))
    frac = 100.0 * float(fraction_compensated(roll_gyro.sf_error, dk))
    out.append(_item(
        "example.compensated", "conclusion", "share of the SF error compensated", "%", frac,
        "differs: cause shown",
        "the paper reads 1 − δK as the share compensated; the residual SF error is δK itself, "
        "so the share is 1 − δK/ε1", "rsf-compensated", kind="printed number", precision=3,
        evidence="1 − δK with the slipped δK gives the printed 90 %; the residual share is "
        "1 − δK/ε1 at the worked example's 900 °/s"))

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
