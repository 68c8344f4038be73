"""Ledger items of paper GC: its printed numbers and claims, each reproduced by calling
:mod:`gyrolib.gc` and :mod:`gyrolib.gc` (a covariance analysis of
100 s takes a fraction of a second, so the command line stays fast).

Only the paper's printed values are stored here, in :data:`PRINTED`; the reproduced values
are computed from the parameters, so perturbing a parameter moves the ledger (see
``tests/test_ledger_gc.py``).
"""

from __future__ import annotations

from dataclasses import replace
from typing import Final

import numpy as np

from gyrolib.book.ledger import LedgerItem
from gyrolib.gc.covariance import covariance_analysis, time_to_sigma
from gyrolib.gc.discretization import nominal_half_steps
from gyrolib.gc.params import GyrocompassParams
from gyrolib.units import ARCSEC_PAPER, from_si

__all__ = ["PRINTED", "SIGMA_C", "items"]

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
TREND_FIELDS: Final[tuple[str, ...]] = ("alpha1", "xi1", "sigma1_sq", "alpha2", "xi2",
                                        "sigma2_sq")


def _worst_drop(p: GyrocompassParams) -> float:
    """Largest σ(2 s)/σ(0) of ω_gc over the one-at-a-time variations of :data:`TREND_FIELDS`
    by :data:`TREND_FACTORS` (the "sharp drop in the first 2 s" must survive every one)."""
    worst = 0.0
    for name in TREND_FIELDS:
        for factor in TREND_FACTORS:
            value = getattr(p, name) * factor
            if name.startswith("xi"):
                value = min(value, 1.0)
            res = covariance_analysis(replace(p, **{name: value}), 2.0, store_every=10**6)
            s = res.std("omega_gc")
            worst = max(worst, float(s[-1] / s[0]))
    return worst


def items(params: GyrocompassParams | None = None) -> list[LedgerItem]:
    """Paper GC's items, computed for ``params`` (default: the book's baseline)."""
    p = GyrocompassParams() if params is None else params
    if not isinstance(p, GyrocompassParams):
        raise TypeError("params must be a GyrocompassParams")
    n100 = round(100.0 / p.dt)
    rot = float(np.degrees(nominal_half_steps(p, n100)[-1]))
    cov = covariance_analysis(p, 100.0, store_every=n100)
    s = cov.std("omega_gc")
    s0, s2, s100 = s[0], cov.std_at("omega_gc", 2.0), s[-1]
    sigma_100 = float(from_si(s100, "arcsec_paper/s"))
    t_c = time_to_sigma(cov, "omega_gc", SIGMA_C)
    faster = 100.0 * (1.0 - t_c / (PRINTED["ref2_minutes"] * 60.0))
    # "more than 50 % faster" than ref. [2]: under half of its 17 min, in seconds
    t_half_ref2 = (1.0 - PRINTED["faster_percent"] / 100.0) * PRINTED["ref2_minutes"] * 60.0
    var_n1 = p.vibration_filter().variance()
    var_n3 = p.random_drift_filter().variance()
    rel = abs(sigma_100 / PRINTED["sigma_gc_100s"] - 1.0)
    worst_drop = _worst_drop(p)
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
              "arcsec/s (paper's 1\" = 0.485e-5 rad)", sigma_100,
              "reproduced" if rel < 0.005 else "differs: bracketed",
              "baseline: stationary P0 of N1..N4, R = C/dt, g = 9.80665, float at rest at t = 0;"
              " the other readings of the paper's open choices are tabulated in the chapter",
              _FILTER, "gc-filter-choices", kind="printed number", precision=3,
              evidence="covariance analysis at the paper's parameters; the unstated P0 of "
              "N1..N4 (zero vs stationary) spans the printed value, no single reading gives it"),
        _item("fig3.drop_2s", "Fig. 3 / text", "sigma(2 s)/sigma(0) of omega_gc (sharp drop in"
              " the first 2 s)", "1", s2 / s0,
              "holds" if s2 / s0 < 0.5 else "fails",
              "ratio of the filter's sigma at 2 s to the prior 0.15\"/s", _FILTER,
              "gc-filter-fig3", paper_value="sharp drop", kind="claim", precision=3,
              evidence="covariance analysis: sigma(2 s)/sigma(0) below 1/2"),
        _item("time_to_sigma_c", "Conclusion", "time for sigma_gc to reach sigma_c = 2e-3\"/s",
              "s", t_c, "holds under conditions" if t_c < t_half_ref2 else "fails",
              "the book infers < 8.5 min from 'more than 50 % faster' than ref. [2]'s 17 min",
              _CLAIMS, "gc-claims-speed", paper_value="more than 50 % faster than 17 min",
              kind="claim", precision=3,
              conditions="the paper's shaping filters and the book's stationary P0; 17 min is "
              "ref. [2] without vibration",
              evidence=f"time at which the covariance analysis' sigma crosses sigma_c, against "
              f"the inferred bound {t_half_ref2:.0f} s"),
        _item("faster_percent", "Conclusion", "time saved against ref. [2] (17 min)", "%",
              faster, "holds under conditions" if faster > 50.0 else "fails",
              "100 (1 - t_c / 17 min); against ref. [3] (~20 min) the saving is larger still",
              _CLAIMS, "gc-claims-speed", paper_value="> 50", kind="claim", precision=3,
              conditions="the paper's shaping filters and the book's stationary P0",
              evidence="100 (1 - t_c / 17 min) with t_c from the covariance analysis"),
        _item("fig4", "Fig. 4", "the omega_gc estimate in a first and a second run (curves)", "—",
              None, "redrawn",
              "two seeded runs of the filter on the nonlinear truth model converge onto their "
              "true omega_gc within their sigma band; the paper prints no number from it",
              _CLAIMS, "fig-gcc-runs", paper_value="figure", kind="figure",
              evidence="two seeded Monte Carlo runs drawn by gc.plot_estimates; no number"),
        _item("claim.trend_holds", "text after Fig. 3",
              "largest sigma(2 s)/sigma(0) when each shaping-filter parameter is scaled by 0.1 "
              "and 10", "1", worst_drop,
              "holds under conditions" if worst_drop < 0.5 else "fails",
              "the sharp drop in the first 2 s survives every one-at-a-time variation over two "
              "decades; sigma(100 s) itself varies several-fold (the chapter's sweep)",
              _CLAIMS, "gc-claims-sweep", paper_value="same trend", kind="claim", precision=3,
              conditions="one shaping-filter parameter at a time scaled by 0.1 and 10 (damping "
              "capped at 1); the trend's shape, not sigma(100 s), which varies several-fold",
              evidence="largest sigma(2 s)/sigma(0) over the sweep below 1/2"),
    ]
