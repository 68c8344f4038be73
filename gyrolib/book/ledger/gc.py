"""Ledger items of paper GC: its printed numbers and claims, each reproduced by calling
:mod:`gyrolib.gc` (a covariance analysis of 100 s takes a fraction of a second, so the
command line stays fast; the speed claim's boundary takes two analyses of 510 s).

Only the paper's printed values are stored here, in :data:`PRINTED`; the reproduced values
are computed from the parameters, so perturbing a parameter moves the ledger (see
``tests/test_ledger_gc.py``).
"""

from __future__ import annotations

from dataclasses import replace
from typing import Final

import numpy as np

from gyrolib.book.ledger import LedgerItem
from gyrolib.gc.claims import claim_boundary, shaping_sweep, time_to_level
from gyrolib.gc.covariance import covariance_analysis, time_to_sigma
from gyrolib.gc.discretization import nominal_half_steps
from gyrolib.gc.params import GyrocompassParams
from gyrolib.units import ARCSEC_PAPER, from_si

__all__ = ["PRINTED", "SIGMA_C", "T_BOUND", "items"]

#: What paper GC prints (its units: °, ″/s with 1″ = 0.485·10⁻⁵ rad, m²/s⁴, rad²/s², s, %).
PRINTED: Final[dict[str, float]] = {
    "float_rotation_100s": 0.5,
    "sigma_gc_100s": 0.0011,
    "fig2.var_N1": 1.86e-6,
    "fig2.var_N3": 2.35e-15,
    "ref2_minutes": 17.0,
    "ref3_minutes": 20.0,
    "faster_percent": 50.0,
}

#: The required calibration accuracy of the north gyro, σ_c = 2·10⁻³ ″/s (paper GC, ref. [2]).
SIGMA_C: Final[float] = 2e-3 * ARCSEC_PAPER

#: The book's reading of "more than 50 % faster" than ref. [2]'s 17 min: σ_c reached in less
#: than half of 17 min, in seconds (510 s).  An inference from two printed numbers, not a
#: printed value.
T_BOUND: Final[float] = (1.0 - PRINTED["faster_percent"] / 100.0) * PRINTED["ref2_minutes"] * 60.0

_MODEL = "chapters/gc_model"
_FILTER = "chapters/gc_filter"
_CLAIMS = "chapters/gc_claims"


def _item(key: str, location: str, quantity: str, unit: str, value: float | None, status: str,
          note: str, chapter: str, anchor: str = "",
          paper_value: float | str | None = None, *, kind: str, evidence: str,
          conditions: str = "", precision: int = 4) -> LedgerItem:
    return LedgerItem(
        id=f"gc.{key}", paper="GC", location=location, quantity=quantity, unit=unit,
        paper_value=PRINTED.get(key) if paper_value is None else paper_value,
        reproduced_value=None if value is None else float(value), status=status, note=note,
        chapter=chapter, anchor=anchor, kind=kind, evidence=evidence, conditions=conditions,
        precision=precision)


#: Factors applied, one parameter at a time, to test the claim that the trend of Figure 3
#: holds when the shaping-filter parameters vary widely (damping ratios capped at 1).
TREND_FACTORS: Final[tuple[float, ...]] = (0.1, 10.0)


def _printed_digits(x: float) -> int:
    """Significant digits of a printed number (0.0011 → 2)."""
    return len(f"{x:g}".replace("0.", "").lstrip("0").replace(".", "").split("e")[0])


def _arcsec_s(x: float) -> float:
    return float(from_si(x, "arcsec_paper/s"))


def items(params: GyrocompassParams | None = None) -> list[LedgerItem]:
    """Paper GC's items, computed for ``params`` (default: the book's baseline)."""
    p = GyrocompassParams() if params is None else params
    if not isinstance(p, GyrocompassParams):
        raise TypeError("params must be a GyrocompassParams")
    n100 = round(100.0 / p.dt)
    rot = float(np.degrees(nominal_half_steps(p, n100)[-1]))
    cov = covariance_analysis(p, 100.0, store_every=n100)
    other = "zero" if p.shaping_p0 == "stationary" else "stationary"
    cov_other = covariance_analysis(replace(p, shaping_p0=other), 100.0, store_every=n100)
    s = cov.std("omega_gc")
    s0, s2, s100 = s[0], cov.std_at("omega_gc", 2.0), s[-1]
    sigma_100 = _arcsec_s(s100)
    sigma_100_other = _arcsec_s(cov_other.final_std("omega_gc"))
    # σ_gc(100 s): reproduced to the printed digits, bracketed by the two P0 readings, or not
    printed = PRINTED["sigma_gc_100s"]
    half_ulp = 0.5 * 10.0 ** (np.floor(np.log10(printed)) - _printed_digits(printed) + 1)
    lo_b, hi_b = sorted((sigma_100, sigma_100_other))
    if abs(sigma_100 - printed) <= half_ulp:
        sigma_status = "reproduced"
    elif lo_b <= printed <= hi_b:
        sigma_status = "differs: bracketed"
    else:
        sigma_status = "not reproducible"
    # the sharp drop: the share of the 100-s reduction of σ achieved in the first 2 s
    drop_share = float((s0 - s2) / (s0 - s100))
    # the speed claim
    t_c = time_to_sigma(cov, "omega_gc", SIGMA_C)
    if np.isnan(t_c):  # not within 100 s: look up to the bound (nan: not before it)
        t_c = time_to_level(p, SIGMA_C, T_BOUND)
    t_c_text = f"{t_c:.0f} s" if np.isfinite(t_c) else f"not reached within {T_BOUND:.0f} s"
    t_c_other = time_to_sigma(cov_other, "omega_gc", SIGMA_C)
    faster = 100.0 * (1.0 - t_c / (PRINTED["ref2_minutes"] * 60.0))
    wide = max(TREND_FACTORS)
    bnd = claim_boundary(p, SIGMA_C, T_BOUND, field="sigma1_sq", factors=(1.0, wide))
    cov_other_wide = covariance_analysis(
        replace(p, shaping_p0=other, sigma1_sq=wide * p.sigma1_sq), 100.0, store_every=n100)
    t_c_other_wide = time_to_sigma(cov_other_wide, "omega_gc", SIGMA_C)
    if not t_c < T_BOUND:
        speed_status, speed_cond = "fails", ""
    elif np.isnan(bnd.factor):
        speed_status, speed_cond = "holds", ""
    else:
        speed_status = "holds under conditions"
        speed_cond = (
            f"{p.shaping_p0} P0 of N1..N4: holds for sigma1^2 below {bnd.factor:.2g} times "
            f"the paper's value at its alpha1 (sigma_gc({T_BOUND:.0f} s) crosses sigma_c "
            f"there), fails at {wide:g} times; {other} P0: t_c = {t_c_other:.0f} s at the "
            f"paper's sigma1^2 and {t_c_other_wide:.0f} s at {wide:g} times it")
    speed_evidence = (
        f"covariance analysis: t_c = {t_c_text} ({other} P0: {t_c_other:.0f} s) against "
        f"the inferred bound {T_BOUND:.0f} s; sigma_gc({T_BOUND:.0f} s)/sigma_c = "
        f"{bnd.sigma[0] / SIGMA_C:.2f} at the paper's sigma1^2, "
        f"{bnd.sigma[-1] / SIGMA_C:.2f} at {wide:g} times it")
    var_n1 = p.vibration_filter().variance()
    var_n3 = p.random_drift_filter().variance()
    sweep = shaping_sweep(p, 2.0, factors=TREND_FACTORS)
    worst_drop = float(sweep.drop.max())
    worst_field = sweep.fields[int(np.argmax(sweep.drop.max(axis=1)))]
    return [
        _item("fig1", "Fig. 1", "frames Oxyz, Oξηζ and the angles ψ, β, δ, γ (drawing)", "—",
              None, "redrawn",
              "redrawn by code from the text; the direction of the output axis is inferred "
              "from cos(β − ψ)", _MODEL, "fig-gcm-figure1", paper_value="figure",
              kind="figure", evidence="drawn by gc.plot_figure1 from the text; no number"),
        _item("fig2.var_N1", "Fig. 2 / Eq. (6)", "stationary variance of N1 (area under PSD)",
              "m^2/s^4", var_n1,
              "input",
              "Lyapunov equation of the shaping filter (6) with Q1 = 2 xi1 alpha1 sigma1^2",
              _MODEL, kind="input",
              evidence="the paper gives sigma1^2 and uses it; the Lyapunov variance of Eq. (6) "
              "returning it checks the noise placement, it reproduces nothing"),
        _item("fig2.var_N3", "Fig. 2 / Eq. (7)", "stationary variance of N3 (area under PSD)",
              "rad^2/s^2", var_n3,
              "input",
              "Lyapunov equation of the shaping filter (7) with Q2 = 4 xi2 alpha2^3 sigma2^2",
              _MODEL, kind="input",
              evidence="the paper gives sigma2^2 and uses it; the Lyapunov variance of Eq. (7) "
              "returning it checks the noise placement, it reproduces nothing"),
        _item("float_rotation_100s", "text after Fig. 3", "float rotation after 100 s", "deg",
              rot,
              "reproduced" if round(rot, 1) == PRINTED["float_rotation_100s"]  # "about"
              else "not reproducible",
              "nominal motion Eq. (4) from rest; the paper rounds to 0.5", _MODEL,
              kind="printed number", precision=3,
              evidence="Eq. (4) integrated from rest; rounded to the printed 0.1 deg it equals "
              "the printed 'about 0.5'"),
        _item("sigma_gc_100s", "Fig. 3 / text", "sigma of the omega_gc estimate at 100 s",
              "arcsec/s (paper's 1\" = 0.485e-5 rad)", sigma_100, sigma_status,
              "baseline: stationary P0 of N1..N4, R = C/dt, g = 9.80665, float at rest at t = 0;"
              " the other readings of the paper's open choices are tabulated in the chapter",
              _FILTER, "gc-filter-choices", kind="printed number", precision=3,
              evidence=f"covariance analysis at the paper's parameters: {sigma_100:.5f} "
              f"({p.shaping_p0} P0 of N1..N4) and {sigma_100_other:.5f} ({other} P0); the "
              f"printed {printed:g} lies {'inside' if lo_b <= printed <= hi_b else 'outside'}"
              f" [{lo_b:.5f}, {hi_b:.5f}]"),
        _item("fig3.drop_2s", "Fig. 3 / text", "share of the 100-s reduction of sigma(omega_gc)"
              " achieved in the first 2 s (sharp drop)", "1", drop_share,
              "holds" if drop_share > 0.5 else "fails",
              "the first 2 s are 2 % of the run; 'sharp' is read as: most of the reduction of "
              "sigma over 100 s happens in them", _FILTER,
              "gc-filter-fig3", paper_value="sharp drop", kind="claim", precision=3,
              evidence=f"covariance analysis: (sigma(0) - sigma(2 s))/(sigma(0) - sigma(100 s))"
              f" = {drop_share:.2f}; sigma(2 s)/sigma(0) = {s2 / s0:.2f}"),
        _item("time_to_sigma_c", "Conclusion", "time for sigma_gc to reach sigma_c = 2e-3\"/s",
              "s", t_c if np.isfinite(t_c) else None, speed_status,
              f"the book infers < {T_BOUND:.0f} s from 'more than 50 % faster' than ref. [2]'s "
              "17 min (ref. [2]: no vibration modelled; ref. [3]: about 20 min for its whole "
              "procedure); the 0.0011\"/s of Fig. 3 is another quantity", _CLAIMS,
              "gc-claims-speed", paper_value="more than 50 % faster than 17 min",
              kind="claim", precision=3, conditions=speed_cond, evidence=speed_evidence),
        _item("faster_percent", "Conclusion", "time saved against ref. [2] (17 min)", "%",
              faster if np.isfinite(faster) else None, speed_status,
              "100 (1 - t_c / 17 min); against ref. [3] (~20 min) the saving is larger still",
              _CLAIMS, "gc-claims-speed", paper_value="> 50", kind="claim", precision=3,
              conditions=speed_cond, evidence=f"100 (1 - t_c / 17 min) = {faster:.0f} % with "
              f"t_c = {t_c_text} from the covariance analysis; see gc.time_to_sigma_c"),
        _item("fig4", "Fig. 4", "the omega_gc estimate in a first and a second run (curves)", "—",
              None, "redrawn",
              "two seeded runs of the filter on the nonlinear truth model converge onto their "
              "true omega_gc within their sigma band; the paper prints no number from it",
              _CLAIMS, "fig-gcc-runs", paper_value="figure", kind="figure",
              evidence="two seeded Monte Carlo runs drawn by gc.plot_estimates; no number"),
        _item("claim.trend_holds", "text after Fig. 3",
              "largest sigma(2 s)/sigma(0) when each shaping-filter parameter is scaled by "
              f"{min(TREND_FACTORS):g} and {max(TREND_FACTORS):g}", "1", worst_drop,
              "holds under conditions" if worst_drop < 0.5 else "fails",
              "the sharp drop in the first 2 s survives every one-at-a-time variation over two "
              "decades; the level sigma(100 s) is another matter (the chapter's sweep)",
              _CLAIMS, "gc-claims-sweep", paper_value="same trend", kind="claim", precision=3,
              conditions=f"one shaping-filter parameter at a time scaled by {min(TREND_FACTORS):g}"
              f" and {max(TREND_FACTORS):g} (damping capped at 1): the trend's shape holds; "
              "the level at 100 s is not part of this item (gc.shaping_sweep over 100 s in "
              "the chapter)",
              evidence=f"gc.shaping_sweep over 2 s: sigma(2 s)/sigma(0) at most "
              f"{worst_drop:.2f} (at {worst_field}) against {s2 / s0:.2f} at the baseline: "
              "more than half of the prior is removed in 2 s in every variation"),
    ]
