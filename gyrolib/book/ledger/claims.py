"""Every claim of both papers as a margin over the table of inputs (:mod:`gyrolib.inputs`).

Each function here takes the owners' instances (``"GyrocompassParams"``,
``"RateSensorProcedure"``, ``"RollGyroSpec"``, ``"MemsGyroSpec"``, ``"EncoderSpec"``,
``"WorkedExample"``) and returns the claim's *margin*, a number whose sign is the verdict
(``> 0``: it holds).  :data:`CLAIMS` pairs each with the rows it reads; :func:`maps` judges
them all by the one rule of :func:`gyrolib.claim_map.map_claim`, and :func:`stored_maps`
reads the maps computed once, offline (``python -m gyrolib claims --out``), and shipped as
package data (``gyrolib/data/claim_maps.json``).

A claim about several printed points (times, rates) holds at a point of the table only if it
holds at every printed point: its margin is the smallest over them.
"""

from __future__ import annotations

import functools
import json
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Final

import numpy as np

from gyrolib import inputs as _inputs
from gyrolib import levels
from gyrolib.claim_map import (
    Claim,
    ClaimMap,
    PointSearch,
    check_fingerprint,
    map_claim,
    status_line,
)
from gyrolib.gc.analysis.covariance import covariance_analysis, time_to_sigma
from gyrolib.gc.analysis.observability import information_psi_omega
from gyrolib.gc.analysis.speed_claim import time_to_level
from gyrolib.gc.racing.comparison import race_margin
from gyrolib.gc.racing.verdict_grid import race_verdict_grid
from gyrolib.rsf.equations import (
    delta_k,
    fraction_compensated,
    gs_roll_error_ideal,
    lateral_deviation_exact,
    sins_roll_error,
)
from gyrolib.rsf.simulation import SimulationConfig

__all__ = [
    "BOX_POINTS",
    "BOX_SEED",
    "CLAIMS",
    "MAPS_FILE",
    "MAPS_SCHEMA",
    "Verdict",
    "area_margin",
    "check_stored",
    "compensated_margin",
    "coordinate_accuracy_margin",
    "drop_2s_margin",
    "drz_cubic_margin",
    "drz_kilometres_margin",
    "gs_vs_sins_margin",
    "maps",
    "only_small_eps1_margin",
    "psi_separable_margin",
    "race_claim_margin",
    "race_grid",
    "stored_extras",
    "stored_maps",
    "time_to_sigma_c_margin",
    "verdict",
    "west_gyro_margin",
    "write_maps",
]

#: The stored maps (package data) and the version of their format.
MAPS_FILE: Final[Path] = Path(__file__).resolve().parents[2] / "data" / "claim_maps.json"
MAPS_SCHEMA: Final[int] = 1

#: σ_c, the speed claim's bound (510 s), paper RSF's printed times and levels: one leaf module
#: (:mod:`gyrolib.levels`) that the ledger's items read too.
_SIGMA_C: Final[float] = levels.SIGMA_C
_T_BOUND: Final[float] = levels.T_BOUND
_TIMES: Final[tuple[int, ...]] = levels.TIMES


# paper GC ------------------------------------------------------------------------------------
def race_claim_margin(o: Mapping[str, Any]) -> float:
    """"More than 50 % faster than the rate-sensor method" (paper GC, conclusion): the smaller
    saving over the two estimators minus 50 % (:func:`gyrolib.gc.race_margin`)."""
    return race_margin(o["GyrocompassParams"], o["RateSensorProcedure"])


def time_to_sigma_c_margin(o: Mapping[str, Any]) -> float:
    """"More than 50 % faster than ref. [2]'s 17 min": ``1 − t_c/510 s``, with t_c the time
    for σ of ω_gc (the scale's drift added in quadrature) to reach σ_c; −1 when it does not
    within 510 s."""
    p = o["GyrocompassParams"]
    s_scale = p.scale_drift_sigma
    if s_scale >= _SIGMA_C:
        return -1.0
    pf = replace(p, sigma_hf_scale=0.0) if p.sigma_hf_scale else p
    level = math.sqrt(_SIGMA_C**2 - s_scale**2)
    n = round(100.0 / pf.dt)
    t_c = time_to_sigma(covariance_analysis(pf, 100.0, store_every=n), "omega_gc", level)
    if not np.isfinite(t_c):
        t_c = time_to_level(pf, level, _T_BOUND)
    return -1.0 if not np.isfinite(t_c) else 1.0 - float(t_c) / _T_BOUND


@functools.lru_cache(maxsize=64)
def sigmas(p: Any) -> tuple[float, float, float]:
    """σ of ω_gc at 0, 2 and 100 s (rad/s) under ``p`` (kept per parameters: the sensitivity
    study reads σ(100 s) at the same point as the trend's margin)."""
    n100 = round(100.0 / p.dt)
    cov = covariance_analysis(p, 100.0, store_every=n100)
    s = cov.std("omega_gc")
    return float(s[0]), float(cov.std_at("omega_gc", 2.0)), float(s[-1])


def drop_2s_margin(o: Mapping[str, Any]) -> float:
    """"σ drops sharply in the first 2 s" (Fig. 3 and the text after it): the share of the
    100-s reduction of σ(ω_gc) achieved in the first 2 s, minus one half."""
    s0, s2, s100 = sigmas(o["GyrocompassParams"])
    return (s0 - s2) / (s0 - s100) - 0.5 if s0 > s100 else -0.5


def psi_separable_margin(o: Mapping[str, Any]) -> float:
    """"ψ and ω_gc can be separated" (text after Eq. (5)): ``1 − |correlation|`` of their
    information in the angle sensor over 100 s, minus 10⁻⁹ (parallel to the last bits)."""
    info = information_psi_omega(o["GyrocompassParams"], 100.0)
    return float(1.0 - abs(info.correlation()[-1])) - 1e-9


# paper RSF -----------------------------------------------------------------------------------
def compensated_margin(o: Mapping[str, Any]) -> float:
    """"Compensates 90 %" (conclusion): ``1 − δK/ε1`` from Eq. (7) at the example's roll
    rate, with ω_unc by the example's reading, minus 0.90."""
    ex, gs, enc, roll = (o["WorkedExample"], o["MemsGyroSpec"], o["EncoderSpec"],
                         o["RollGyroSpec"])
    dk = delta_k(ex.eps0_gs(gs), enc.position_error, ex.omega_x, ex.period, ex.eps1_gs(gs),
                 ex.omega_unc_at(ex.omega_x))
    return float(fraction_compensated(roll.sf_error, dk)) - levels.COMPENSATED_PERCENT / 100.0


def gs_vs_sins_margin(o: Mapping[str, Any]) -> float:
    """"The GS's roll error is hundreds of times smaller than the SINS's" (after Table 3):
    ``log10`` of the smallest Δγ_SINS/Δγ_GS over the printed times (ideal GS, Eq. (9)),
    minus 2."""
    ex, gs, enc, roll = (o["WorkedExample"], o["MemsGyroSpec"], o["EncoderSpec"],
                         o["RollGyroSpec"])
    t = np.array(_TIMES)
    sins = np.asarray(sins_roll_error(roll.sf_error, ex.table_rate, t), dtype=float)
    ideal = np.asarray(gs_roll_error_ideal(ex.eps0_gs(gs), t, enc.position_error),
                       dtype=float)
    return float(np.log10(np.min(sins / ideal))) - math.log10(levels.GS_VS_SINS_RATIO)


def _exponent(eps1: float, omega: float, t: float, h: float = 1e-3) -> float:
    a, b = (float(lateral_deviation_exact(eps1, omega, t * (1.0 + s * h))) for s in (-1, 1))
    return math.log(b / a) / math.log((1.0 + h) / (1.0 - h))


def drz_cubic_margin(o: Mapping[str, Any]) -> float:
    """"The lateral deviation grows as t³" (Eq. (8)): the smallest local exponent
    d ln Δr_z/d ln t of the exact double integral over the printed times, minus 2.9."""
    ex, roll = o["WorkedExample"], o["RollGyroSpec"]
    return (min(_exponent(roll.sf_error, ex.table_rate, t) for t in _TIMES)
            - levels.CUBIC_EXPONENT)


def drz_kilometres_margin(o: Mapping[str, Any]) -> float:
    """"The deviation reaches kilometres" (the unit of Table 2's Δr_z): ``log10`` of the
    exact lateral Δr_z at the end of Table 2's flight (its last printed time, 120 s), in km.
    One point, the flight: a deviation that grows cannot be kilometres at every time."""
    ex, roll = o["WorkedExample"], o["RollGyroSpec"]
    d = float(lateral_deviation_exact(roll.sf_error, ex.table_rate, _TIMES[-1]))
    return float(np.log10(d / 1000.0))


# the remaining items (their margins live with their items, read when called: those modules
# import this one) ------------------------------------------------------------------------------
#: The margins registered by the modules that define them (:func:`register_margin`).
_MARGINS: dict[str, Callable[[Mapping[str, Any]], float]] = {}


def register_margin(fn: Callable[[Mapping[str, Any]], float]
                    ) -> Callable[[Mapping[str, Any]], float]:
    """Register ``fn`` as the margin of its name (a decorator): the remaining items'
    margins live in :mod:`gyrolib.book.ledger.remaining`, which imports this module, so this
    one names them (:class:`_Registered`) instead of importing them.  The package's
    ``__init__`` imports that module, so any import of this one (an executor's worker
    unpickling a claim too) has them registered."""
    _MARGINS[fn.__name__] = fn
    return fn


@dataclass(frozen=True)
class _Registered:
    """The margin registered under ``name`` (picklable, for an executor's workers)."""

    name: str

    def __call__(self, o: Mapping[str, Any]) -> float:
        return float(_MARGINS[self.name](o))


@dataclass(frozen=True)
class _RegisteredPoints:
    """The search points registered under ``name`` (:class:`gyrolib.claim_map.PointSearch`;
    picklable, as :class:`_Registered`)."""

    name: str

    def __call__(self, o: Mapping[str, Any]) -> np.ndarray:
        return np.asarray(_MARGINS[self.name](o), dtype=float)


west_gyro_margin = _Registered("west_gyro_margin")
area_margin = _Registered("area_margin")
coordinate_accuracy_margin = _Registered("coordinate_accuracy_margin")
only_small_eps1_margin = _Registered("only_small_eps1_margin")
finer_encoder_margin = _Registered("finer_encoder_margin")
_period_search_points = _RegisteredPoints("period_search_points")


def _names(*prefixes: str, kinds: tuple[str, ...] = _inputs.KINDS,
           exclude: tuple[str, ...] = ()) -> tuple[str, ...]:
    return tuple(r.name for r in _inputs.INPUTS
                 if r.name.startswith(prefixes) and r.kind in kinds and r.name not in exclude)


_GC_ALL = _names("gc.")
_RSF_EXAMPLE = _names("rsf.", exclude=("rsf.eps0", "rsf.table_rate"))
_RSF_TABLES = ("rsf.eps1", "rsf.gs_bias", "rsf.encoder_error", "rsf.table_rate",
               "rsf.eps0_gs_digits")
_RSF_DRZ = ("rsf.eps1", "rsf.table_rate")
#: The shaping filters' rows (Fig. 2's areas read nothing else).
_GC_SHAPING = ("gc.alpha1", "gc.xi1", "gc.sigma1_sq", "gc.alpha2", "gc.xi2", "gc.sigma2_sq")
#: The west gyro runs the paper's filter: its noises, sensors, priors and readings; the
#: instrument errors the paper's model leaves at zero (κ, σ_off, σ_b, ε_t) are not appended
#: to it (more unknowns only raise σ: they cannot make the failing claim hold).
_GC_WEST = _names("gc.", exclude=("gc.sigma_hf_scale", "gc.sigma_as_offset",
                                  "gc.sigma_incl_bias", "gc.sigma_clock"))
#: The seeded flights: the sensors' rows, the roll rate and the correction interval (the
#: readings of the worked example's printed text do not enter a simulation).
_RSF_FLIGHTS = ("rsf.eps1", "rsf.eps0", "rsf.gs_bias", "rsf.eps1_gs", "rsf.encoder_error",
                "rsf.omega_x", "rsf.period")

#: Every claim the table maps: the ledger's item id → its margin and the rows it reads.
CLAIMS: Final[dict[str, Claim]] = {c.id: c for c in (
    Claim("gc.faster_percent", race_claim_margin, _GC_ALL + _names("race."),
          "the smaller saving over the rival's two estimators minus 50", "%"),
    Claim("gc.time_to_sigma_c", time_to_sigma_c_margin, _GC_ALL,
          "1 − t_c/510 s (t_c: σ of ω_gc reaches σ_c)"),
    Claim("gc.fig3.drop_2s", drop_2s_margin, _GC_ALL,
          "share of the 100-s reduction of σ(ω_gc) in the first 2 s, minus 0.5 (Fig. 3's "
          "drop, mapped over the whole table: the printed parameters are inputs too)"),
    Claim("gc.claim.trend_holds", drop_2s_margin, _GC_ALL,
          "share of the 100-s reduction of σ(ω_gc) in the first 2 s, minus 0.5, over the "
          "table"),
    Claim("gc.claim.psi_separable", psi_separable_margin, _GC_ALL,
          "1 − |correlation| of the ψ and ω_gc information over 100 s, minus 1e-9"),
    Claim("rsf.example.compensated", compensated_margin, _RSF_EXAMPLE,
          "1 − δK/ε1 from Eq. (7) minus 0.90", per_reading=True),
    Claim("rsf.claim.gs_vs_sins", gs_vs_sins_margin, _RSF_TABLES,
          "log10 of the smallest Δγ_SINS/Δγ_GS at 10, 60, 120 s, minus 2", per_reading=True),
    Claim("rsf.claim.drz_cubic", drz_cubic_margin, _RSF_DRZ,
          "the smallest local exponent of Δr_z at 10, 60, 120 s, minus 2.9"),
    Claim("rsf.claim.drz_kilometres", drz_kilometres_margin, _RSF_DRZ,
          "log10 of the lateral Δr_z at the end of Table 2's flight (120 s), in km"),
    Claim("gc.fig2.areas", area_margin, _GC_SHAPING,
          f"log10 of the tolerance {levels.AREA_TOLERANCE:g} over the larger |PSD area/σ² − 1| "
          "of N1 and N3"),
    Claim("gc.claim.corresponding_gyro", west_gyro_margin, _GC_WEST,
          "log10 of σ_c over the west gyro's σ of ω_gc at 510 s"),
    Claim("rsf.claim.coordinate_accuracy", coordinate_accuracy_margin, _RSF_FLIGHTS,
          "−log10 of the upper 95 % bound of the median flight's corrected/uncorrected "
          "lateral error (the ledger's seeded flights)"),
    Claim("rsf.claim.longer_finer", finer_encoder_margin, _RSF_FLIGHTS,
          "ln of the rms δK with the coarsest encoder of the sweep over the finest, minus 1e-9 "
          "(the sweep's seeded flights; the 'longer interval' part is judged on the sweep)",
          searches=(
              PointSearch("rsf.period", _period_search_points,
                          "every fifth sample of its range; the simulation's interval is a "
                          "whole number of samples",
                          quantum=1.0 / SimulationConfig().sample_rate),)),
    Claim("rsf.claim.only_small_eps1", only_small_eps1_margin, _RSF_FLIGHTS,
          "log10 of the upper 95 % bound of the median flight's lateral error with the angle "
          "reset over uncorrected (the ledger's seeded flights)"),
)}


#: Points of each claim's box (its share's 95 % Wilson interval is then at most 10 points
#: wide: 384 points suffice at a share of one half): 2,000 where one margin costs under
#: 10 ms, else 400.  Costs measured per margin at four box points (CPU time, under load):
#: the race 3.6 s, the seeded flights 0.5–2.2 s, the west gyro 0.43 s, the 100-s covariance
#: of Fig. 3's drop 0.26 s, ψ's information 0.11 s; paper RSF's closed forms under 1 ms;
#: Fig. 2's areas 10–15 ms (2,000 kept: 29 CPU-s); the speed claim 5 ms where κ alone fails
#: it, but over 75 ms on average (1,936 points took more than 145 CPU-s): 400.  The seed
#: (:data:`BOX_SEED`) is the same for every claim: more points extend the draw
#: (:func:`gyrolib.claim_map.extend_box`).
BOX_POINTS: Final[dict[str, int]] = {
    "gc.faster_percent": 400, "gc.time_to_sigma_c": 400, "gc.fig3.drop_2s": 400,
    "gc.claim.trend_holds": 400, "gc.claim.psi_separable": 400,
    "rsf.example.compensated": 2000, "rsf.claim.gs_vs_sins": 2000,
    "rsf.claim.drz_cubic": 2000, "rsf.claim.drz_kilometres": 2000, "gc.fig2.areas": 2000,
    "gc.claim.corresponding_gyro": 400, "rsf.claim.coordinate_accuracy": 400,
    "rsf.claim.longer_finer": 400, "rsf.claim.only_small_eps1": 400}
BOX_SEED: Final[int] = 2026


def maps(ids: tuple[str, ...] | None = None, objects: Mapping[str, Any] | None = None, *,
         executor: object = None, **settings: Any) -> dict[str, ClaimMap]:
    """Judge the claims ``ids`` (default: all of :data:`CLAIMS`) over the table around
    ``objects`` (default: the reference point); ``settings`` go to
    :func:`gyrolib.claim_map.map_claim` (default: each claim's :data:`BOX_POINTS` and
    :data:`BOX_SEED`)."""
    chosen = tuple(CLAIMS) if ids is None else ids
    return {i: map_claim(CLAIMS[i], objects, executor=executor,
                         **{"n_box": BOX_POINTS[i], "seed": BOX_SEED, **settings})
            for i in chosen}


@functools.lru_cache(maxsize=4)
def _stored(path: Path, mtime: float) -> dict[str, ClaimMap]:
    return stored_maps(path)


def stored_maps(path: Path | None = None) -> dict[str, ClaimMap]:
    """The maps computed offline for the reference point, as shipped with the package.

    Raises ``ValueError`` when a map was computed over other rows than its claim reads now,
    or other ranges or references of them (the fingerprint of the claim's rows differs), or
    in another format; ``FileNotFoundError`` when the file is absent.
    """
    path = MAPS_FILE if path is None else path
    data = json.loads(Path(path).read_text(encoding="utf-8"))
    if data.get("schema") != MAPS_SCHEMA:
        raise ValueError(f"{path}: schema {data.get('schema')!r}, expected {MAPS_SCHEMA}")
    out = {k: ClaimMap.from_dict(v) for k, v in data["maps"].items()}
    for k, m in out.items():
        if k in CLAIMS and (m.settings.get("table") != _inputs.table_fingerprint(
                CLAIMS[k].inputs) or set(m.reference) != set(CLAIMS[k].inputs)):
            raise ValueError(f"{path}: the map of {k} was computed over another table of "
                             "inputs than the claim reads now; recompute it: python -m "
                             f"gyrolib claims --out {path} --only {k}")
    return out


def write_maps(result: Mapping[str, ClaimMap], path: Path | None = None,
               extras: Mapping[str, Any] | None = None) -> None:
    """Write ``result`` (claim id → map) and ``extras`` (name → plain data, e.g. the race's
    verdict grid) as the stored maps (the format :func:`stored_maps` reads)."""
    data = {"schema": MAPS_SCHEMA, "maps": {k: m.to_dict() for k, m in result.items()},
            "extras": dict(extras or {})}
    path = MAPS_FILE if path is None else path
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(path).with_suffix(".json.tmp")
    tmp.write_text(json.dumps(data, indent=1, sort_keys=True) + "\n", encoding="utf-8")
    tmp.replace(path)


def stored_extras(path: Path | None = None) -> dict[str, Any]:
    """The extras stored with the maps (``"race_grid"``: :class:`gyrolib.gc.RaceVerdictGrid`
    as plain data), checked against the table like the maps."""
    path = MAPS_FILE if path is None else path
    stored_maps(path)
    return dict(json.loads(Path(path).read_text(encoding="utf-8")).get("extras", {}))


def race_grid(executor: object = None) -> dict[str, Any]:
    """The race's verdict over σ1² × C_as under each reading of the printed noise levels, at
    the reference point (:func:`gyrolib.gc.race_verdict_grid`), as plain data."""
    o = _inputs.reference_objects()
    return race_verdict_grid(o["GyrocompassParams"], o["RateSensorProcedure"],
                             executor=executor).to_dict()


def check_stored(path: Path | None = None, ids: tuple[str, ...] | None = None) -> int:
    """Recompute the maps' own fingerprint points (the reference, two box points, a search's
    failing point) and raise ``ValueError`` when one moved.  Returns how many points were
    checked.  The store's check of the study ``claim-maps`` (:mod:`gyrolib.store`,
    :func:`gyrolib.book.studies.check_all`: the key, every threshold bracketed, every
    reading, a sample of the sweeps) is the one the ledger, the build and ``claims --check``
    run."""
    stored = stored_maps(path)
    missing = set(CLAIMS) - set(stored)
    if missing:
        raise ValueError(f"{path} has no map of {sorted(missing)}; recompute it")
    n = 0
    for i in (tuple(CLAIMS) if ids is None else ids):
        check_fingerprint(CLAIMS[i], stored[i])
        n += len(stored[i].fingerprint)
    return n


@dataclass(frozen=True)
class Verdict:
    """A claim's ledger verdict by the one rule: ``status``, ``conditions`` (the inputs that
    flip it and where, then ``context``) and ``judged`` (what the ledger's JSON carries:
    reference, thresholds, share of the box, readings; ``mapped`` says whether the claim was
    mapped over the table around these inputs)."""

    status: str
    conditions: str
    judged: dict

    @property
    def status_line(self) -> str:
        """The status as a reader sees it, with the share of the box where the claim holds
        (:func:`gyrolib.claim_map.status_line`; the status alone where none was drawn)."""
        return status_line(self.status, self.judged.get("share_holding"))

    @property
    def conditions_html(self) -> str:
        """:attr:`conditions` for a page: the map's thresholds and share tagged with the
        claim's id (:func:`gyrolib.quote.tag`); the rest as it is."""
        q = self.judged.get("conditions_quoted")
        if not q or not q.get("plain"):
            return self.conditions
        return self.conditions.replace(q["plain"], q["html"])

    def status_html(self, claim: str) -> str:
        """:attr:`status_line` for a page, its share tagged with ``claim``
        (:func:`gyrolib.quote.tag`)."""
        return status_line(self.status, self.judged.get("share_holding"), claim=claim,
                           html=True)


#: The parts of a map the ledger's JSON carries (the sweeps and fingerprint stay in the file).
_JUDGED_KEYS: Final[tuple[str, ...]] = ("meaning", "margin", "reference", "thresholds",
                                        "share_holding", "readings", "settings",
                                        "reading_thresholds", "isolated")


def _is_reference(objects: Mapping[str, Any]) -> bool:
    ref = _inputs.reference_objects()
    return all(objects[k] == v for k, v in ref.items())


def verdict(claim_id: str, objects: Mapping[str, Any] | None = None, *,
            context: str = "") -> Verdict:
    """The verdict on ``claim_id`` at ``objects`` (default: the reference point).

    At the reference point the stored map is read (its table and numbers are checked by
    :func:`check_stored` in the tests and the book build).  Around other inputs (a user's own
    parameters, a perturbation) only the margin at that point is computed: the claim then
    "fails" or "holds under conditions" — never "holds", since the inputs that may flip it
    were not searched there (``python -m gyrolib claims`` or :func:`maps` map them).
    """
    claim = CLAIMS[claim_id]
    objs = {**_inputs.reference_objects(), **(objects or {})}
    if _is_reference(objs):
        m = _stored(MAPS_FILE, MAPS_FILE.stat().st_mtime_ns)[claim_id]
        d = m.to_dict()
        judged = {k: d[k] for k in _JUDGED_KEYS}
        judged["mapped"] = True
        cond = m.conditions()
        conditions = "" if m.status == "holds" else f"{cond} {context}".strip()
        # the same sentences with every threshold and share tagged for a page
        judged["conditions_quoted"] = {"plain": cond, "html": m.conditions(html=True)}
        return Verdict(m.status, conditions, judged)
    margin = float(claim.margin(objs))
    status = "holds under conditions" if margin > 0 else "fails"
    conditions = ("Judged at these inputs only: the claim was not mapped over the table of "
                  "inputs around them (the stored maps are for the reference point), so the "
                  f"inputs that may flip it are not named here. {context}").strip()
    judged = {"meaning": claim.meaning, "margin": margin,
              "reference": {n: _inputs.value_of(objs, _inputs.row(n)) for n in claim.inputs},
              "thresholds": None, "share_holding": None, "readings": None, "settings": {},
              "isolated": None, "mapped": False}
    return Verdict(status, conditions, judged)
