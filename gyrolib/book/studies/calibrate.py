"""The calibrate chapter's heavy studies in the store (:mod:`gyrolib.store`).

Three studies, each registered under its name (:data:`NAMES`) with its file in
``gyrolib/data/``, its key, its fingerprint check and its computation
(``python3 tasks.py refresh NAME``):

* ``calibrate-fit-noise`` — paper GC's noise fitted from the sample record with the wider
  vibration spectrum (``data/gc_record_wrong_spectrum.csv.gz``) and judged as the command
  judges it (:func:`judged` with ``fit``: :func:`gyrolib.gc.fit_noise`, its likelihood-ratio
  intervals and the fit's share of σ).  Its fingerprint: the log-likelihood at the stored
  fitted values (on the same measurements, the fit's outliers left out) and the filter's
  estimate and σ at them, recomputed — no new optimization;
* ``calibrate-convention`` — :func:`gyrolib.gc.convention_study`, a swapped inclinometer
  pair over the seeds of :data:`CONVENTION`.  Its fingerprint: the runs of
  :data:`CONVENTION_CHECK_SEEDS`, recomputed, every field;
* ``calibrate-faults`` — a record of the paper's model with each defect of :data:`FAULTS`
  (:func:`with_fault`), calibrated with the paper's filter and as the command does, and the
  45° record judged without a latitude, with the paper's and with its own
  (:data:`LATITUDES`).  Its fingerprint: the defects of :data:`FAULTS_CHECKED`, recomputed.

The key of each (:func:`key`) hashes the named constants and default dataclasses of every
module the study reads (the model's parameters, its discretization, the filter, the verdict,
the noise fit or the convention study), the gc rows of the table of inputs (the command's
priors and the fit's plausible ranges are rows), the study's own settings, and, for the noise
fit, the bytes of the record it reads.

Examples
--------
>>> from gyrolib.book.studies import calibrate
>>> calibrate.NAMES
('calibrate-fit-noise', 'calibrate-convention', 'calibrate-faults')
>>> sorted(calibrate.key("calibrate-convention"))[:2]
['constants', 'gyrolib.gc.logs.calibration']
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import json
import math
import tempfile
from collections.abc import Mapping
from pathlib import Path
from typing import Any, Final

import numpy as np

from gyrolib import inputs, records, store, units
from gyrolib.gc.logs import calibration as _calibration
from gyrolib.gc.logs import convention as _convention
from gyrolib.gc.logs import judgement as _judgement
from gyrolib.gc.logs import noise_fit as _noise_fit
from gyrolib.gc.logs.calibration import calibrate, innovation_log_likelihood, simulate_record
from gyrolib.gc.logs.convention import ConventionStudy, InclinometerMapping, convention_study
from gyrolib.gc.logs.judgement import judge_record
from gyrolib.gc.logs.noise_fit import NoiseFit
from gyrolib.gc.logs.record import GCRecord
from gyrolib.gc.model import discretization as _discretization
from gyrolib.gc.model import nominal as _nominal
from gyrolib.gc.model import params as _params
from gyrolib.gc.model import state_space as _state_space
from gyrolib.gc.model.params import GyrocompassParams
from gyrolib.units import ARCSEC_PAPER, G0

__all__ = ["CONVENTION", "CONVENTION_CHECK_SEEDS", "FAULTS", "FAULTS_CHECKED", "FIT",
           "LATITUDES", "MG", "NAMES", "PRIORS", "RECORDS", "command_params",
           "convention", "judged",
           "key", "load", "noise_fit", "with_fault"]

#: The registered studies, in the order ``refresh --list`` shows them.
NAMES: Final[tuple[str, ...]] = ("calibrate-fit-noise", "calibrate-convention",
                                 "calibrate-faults")

#: The sample records (``data/`` of the repository; gyrolib is installed editable from it).
RECORDS: Final[Path] = Path(__file__).resolve().parents[3] / "data"

_FILES: Final[dict[str, Path]] = {
    n: Path(__file__).resolve().parents[2] / "data" / f"{n.replace('-', '_')}.json"
    for n in NAMES}

#: The command's default instrument priors: each the largest plausible value of its row of
#: the table of inputs (the scale of H/f and the gain, the angle sensor's offset, the
#: inclinometers' biases, the logger's clock).
PRIORS: Final[dict[str, float]] = {
    name: inputs.default_prior(f"gc.{name}")
    for name in ("sigma_hf_scale", "sigma_as_offset", "sigma_incl_bias", "sigma_clock")}

#: The noise fit: the record it reads and the names it fits (the command's default).
FIT: Final[dict[str, Any]] = {"record": "gc_record_wrong_spectrum.csv.gz",
                              "fit": ("alpha1", "sigma1_sq", "C_as", "C_in")}

#: The convention study: the wrong wiring, the record length (s) and the seeds.
CONVENTION: Final[dict[str, Any]] = {"wiring": "z,y", "t_end": 100.0,
                                     "seeds": tuple(range(1, 13))}

#: The seeds of the convention study its check recomputes.
CONVENTION_CHECK_SEEDS: Final[tuple[int, ...]] = (1, 12)

#: The defects of the fault study (kind, size); the k-th record has the seed 7100 + k.
FAULTS: Final[tuple[tuple[str, float], ...]] = (
    ("null offset (″)", 4.0), ("angle-sensor gain error", 1e-3),
    ("inclinometer_z bias (mg)", 0.5), ("late start (s)", 0.1),
    ("drift change at 50 s (″/s)", 0.05), ("angle-sensor step at 50 s (µrad)", 10.0),
    ("latitude", 45.0))

#: The first seed of the fault study.
FAULT_SEED: Final[int] = 7100

#: The defects of the fault study its check recomputes (indices into :data:`FAULTS`).
FAULTS_CHECKED: Final[tuple[int, ...]] = (0,)

#: How the fault study's record made at 45° is judged: without a latitude, with the paper's
#: assumed, and with its own (deg N).
LATITUDES: Final[tuple[Any, ...]] = (None, "paper", 45.0)

#: One milli-g (m/s²).
MG: Final[float] = 1e-3 * G0

#: The modules every study reads (their constants and default dataclasses enter the key).
_MODULES: Final[tuple[Any, ...]] = (units, _params, _state_space, _discretization, _nominal,
                                    _calibration)
_READS: Final[dict[str, tuple[tuple[Any, ...], dict[str, Any]]]] = {
    "calibrate-fit-noise": ((_judgement, _noise_fit, _convention),
                            {"PRIORS": PRIORS, "FIT": FIT}),
    "calibrate-convention": ((_convention,), {"CONVENTION": CONVENTION}),
    "calibrate-faults": ((_judgement, _convention),
                         {"PRIORS": PRIORS, "FAULTS": FAULTS, "FAULT_SEED": FAULT_SEED,
                          "LATITUDES": LATITUDES, "MG": MG}),
}


def key(name: str) -> dict[str, str]:
    """The key of study ``name`` now (:func:`gyrolib.store.model_key`): the constants and
    default dataclasses of the modules it reads, the gc rows of the table of inputs, its own
    settings and (the noise fit) the bytes of its record."""
    if name not in NAMES:
        raise ValueError(f"name must be one of {NAMES}; got {name!r}")
    modules, constants = _READS[name]
    rows = tuple(r.name for r in inputs.INPUTS if r.name.startswith("gc."))
    extra = {"table": inputs.table_fingerprint(rows)}
    if name == "calibrate-fit-noise":
        path = RECORDS / FIT["record"]
        extra["record"] = (hashlib.sha256(path.read_bytes()).hexdigest()[:16]
                           if path.is_file() else "missing")
    return store.model_key(_MODULES + modules, constants=constants, extra=extra)


# the command's judgement of a file -------------------------------------------------------------
def judged(path: Path | str, *, latitude: float | str | None = None,
           params: GyrocompassParams | None = None, mapping: str = "y,z",
           **options: Any) -> Any:
    """Paper GC's verdict on the record file ``path`` (:func:`gyrolib.gc.judge_record`) as
    the command judges it by default: the instrument priors :data:`PRIORS` (on ``params``,
    default the paper's), the Earth rate of ``latitude`` (deg N; ``"paper"`` assumes paper
    GC's values) or else of the record's ``# latitude_deg:`` line (neither: the verdict says
    no latitude was stated), the inclinometers read as ``mapping``; ``options`` go to
    :func:`gyrolib.gc.judge_record`.

    Examples
    --------
    >>> from gyrolib.book.studies.calibrate import RECORDS, judged
    >>> judged(RECORDS / "gc_record.csv.gz").status
    'ok'
    """
    rec = records.read_gc(path)
    p = dataclasses.replace(GyrocompassParams() if params is None else params, **PRIORS)
    site = None if latitude == "paper" else (
        np.radians(latitude) if latitude is not None else rec.latitude)
    if site is not None:
        at = GyrocompassParams.at_latitude(site)
        p = dataclasses.replace(p, Omega_h=at.Omega_h, Omega_v=at.Omega_v)
    if latitude is not None:      # a stated latitude wins over the record's line
        rec = dataclasses.replace(rec, latitude=None)
    return judge_record(InclinometerMapping.parse(mapping).apply(rec), p,
                        latitude_stated=latitude is not None or rec.latitude is not None,
                        **options)


def _number(x: float) -> float | None:
    x = float(x)
    return x if math.isfinite(x) else None


def _verdict(ver: Any) -> dict[str, Any]:
    """What the chapter reads of a verdict (JSON-ready; the estimate and σ even when not
    given, ``None`` when not finite)."""
    return {"status": ver.status, "valid": ver.valid, "given": ver.given,
            "reason": ver.reason, "reason_code": ver.reason_code,
            "reason_codes": list(ver.reason_codes), "estimate": _number(ver.estimate),
            "sigma": _number(ver.sigma),
            "sigma_parts": {k: float(x) for k, x in ver.sigma_parts.items()}}


# the noise fit ---------------------------------------------------------------------------------
def _params_dict(p: GyrocompassParams) -> dict[str, Any]:
    return dataclasses.asdict(p)


def _array(x: np.ndarray | None) -> list | None:
    if x is None:
        return None
    return [[_number(y) if isinstance(y, float) else y for y in row] if isinstance(row, list)
            else (_number(row) if isinstance(row, float) else row) for row in x.tolist()]


def _from_list(x: list | None, dtype: Any) -> np.ndarray | None:
    if x is None:
        return None
    if dtype is float:
        return np.array([[np.nan if y is None else y for y in row] if isinstance(row, list)
                         else (np.nan if row is None else row) for row in x], dtype=float)
    return np.array(x, dtype=dtype)


def noise_fit(data: Mapping[str, Any]) -> NoiseFit:
    """The :class:`gyrolib.gc.NoiseFit` of the stored study ``calibrate-fit-noise``."""
    d = data["noise_fit"]
    cells = _from_list(d["outlier_cells"], np.int64)
    return NoiseFit(
        params=GyrocompassParams(**d["params"]), start=GyrocompassParams(**d["start"]),
        names=tuple(d["names"]), values=_from_list(d["values"], float),
        std_errors=_from_list(d["std_errors"], float), cov_log=_from_list(d["cov_log"], float),
        loglik=d["loglik"], loglik_start=d["loglik_start"], converged=d["converged"],
        message=d["message"], n_evaluations=d["n_evaluations"], outliers=d["outliers"],
        intervals=_from_list(d["intervals"], float), level=d["level"],
        outlier_cells=None if cells is None else cells.reshape(-1, 2),
        interval_closed=_from_list(d["interval_closed"], bool))


def _fit_record() -> GCRecord:
    path = RECORDS / FIT["record"]
    if not path.is_file():
        raise store.StaleStudy("calibrate-fit-noise", f"its record {path} does not exist")
    return records.read_gc(path)


def _without_outliers(record: GCRecord, cells: np.ndarray) -> GCRecord:
    """``record`` with the measurements ``cells`` (row, sensor 0/1/2) missing: the
    measurements the fit's likelihood counts."""
    cols = [np.array(c, dtype=float) for c in (record.angle_sensor, record.inclinometer_y,
                                               record.inclinometer_z)]
    for row, q in cells:
        cols[int(q)][int(row)] = np.nan
    return GCRecord(t=record.t, angle_sensor=cols[0], inclinometer_y=cols[1],
                    inclinometer_z=cols[2])


def _compute_fit(executor: object, progress: Any, *, path: Path | None = None,
                 **_: Any) -> dict[str, Any]:
    """One fit, here (it is one sequential optimization: ``executor`` is not used)."""
    if progress is not None:
        progress.total = 1
        progress.refresh()
    ver = judged(RECORDS / FIT["record"], fit=FIT["fit"])
    nf = ver.details["noise_fit"]
    fit = {f.name: getattr(nf, f.name) for f in dataclasses.fields(nf)}
    fit = {k: (_params_dict(x) if isinstance(x, GyrocompassParams) else
               _array(x) if isinstance(x, np.ndarray) else list(x) if isinstance(x, tuple)
               else x) for k, x in fit.items()}
    if progress is not None:
        progress.update(1)
    return {"record": FIT["record"], "fit": list(FIT["fit"]), "noise_fit": fit,
            "verdict": _verdict(ver), "result": ver.result.summary()}


def _check_fit(data: Mapping[str, Any]) -> int:
    """The log-likelihood at the stored fitted values (the fit's outliers left out) and the
    filter's estimate and σ there, recomputed within the header's tolerance."""
    name = "calibrate-fit-noise"
    h = store.header_of(name, data)
    nf = noise_fit(data)
    rec = _fit_record()
    cells = np.zeros((0, 2), np.int64) if nf.outlier_cells is None else nf.outlier_cells
    now = innovation_log_likelihood(_without_outliers(rec, cells), nf.params)
    store.compare(name, "the log-likelihood at the fitted values", nf.loglik, now,
                  rtol=h.rtol, atol=h.atol)
    return 1 + _same_run(name, data["result"], calibrate(rec, nf.params).summary(), h,
                         "at the fitted values")


#: What the checks compare of a run of the filter (:meth:`CalibrationResult.summary`):
#: numbers within the tolerance, the rest equal.
_RUN_NUMBERS: Final[tuple[str, ...]] = ("omega_gc", "omega_gc_std", "log_likelihood")
_RUN_EQUAL: Final[tuple[str, ...]] = ("valid", "lost_lock", "reason_codes",
                                      "samples_used", "samples_rejected")


def _same_run(name: str, was: Mapping[str, Any], now: Mapping[str, Any], h: store.Header,
              where: str) -> int:
    """Compare two summaries of a run of the filter (:data:`_RUN_NUMBERS`, the σ's parts,
    each model test's statistic within the tolerance; :data:`_RUN_EQUAL` and each test's
    verdict equal); the number of points compared."""
    n = 0
    for f in _RUN_NUMBERS:
        store.compare(name, f"{f} {where}", was[f], now[f], rtol=h.rtol, atol=h.atol)
        n += 1
    for part, x in was["omega_gc_std_parts"].items():
        store.compare(name, f"the {part} part of sigma {where}", x,
                      now["omega_gc_std_parts"].get(part, math.nan), rtol=h.rtol, atol=h.atol)
        n += 1
    for f in _RUN_EQUAL:
        if was[f] != now[f]:
            raise store.StaleStudy(name, f"{f} {where} was {was[f]!r}, the code now gives "
                                   f"{now[f]!r}")
        n += 1
    if len(was["model_tests"]) != len(now["model_tests"]):
        raise store.StaleStudy(name, f"the run {where} had {len(was['model_tests'])} model "
                               f"tests, the code now makes {len(now['model_tests'])}")
    for a, b in zip(was["model_tests"], now["model_tests"], strict=True):
        label = f"the {a['sensor']} {a['test']} test {where}"
        store.compare(name, label, math.nan if a["statistic"] is None else a["statistic"],
                      math.nan if b["statistic"] is None else b["statistic"], rtol=h.rtol,
                      atol=h.atol)
        if a["passed"] != b["passed"]:
            raise store.StaleStudy(name, f"{label} passed {a['passed']}, the code now says "
                                   f"{b['passed']}")
        n += 1
    return n


# the convention study --------------------------------------------------------------------------
_CONVENTION_FIELDS: Final[tuple[str, ...]] = (
    "omega_true", "delta", "gamma", "est_right", "std_right", "est_wrong", "std_wrong",
    "predicted_shift")
_CONVENTION_FLAGS: Final[tuple[str, ...]] = ("fits_right", "fits_wrong", "valid_right",
                                             "valid_wrong")


def convention(data: Mapping[str, Any]) -> ConventionStudy:
    """The :class:`gyrolib.gc.ConventionStudy` of the stored study
    ``calibrate-convention``."""
    return ConventionStudy(
        params=GyrocompassParams(), wiring=data["wiring"], t_end=float(data["t_end"]),
        seeds=np.array(data["seeds"], dtype=np.int64),
        **{f: np.array(data[f], dtype=float) for f in _CONVENTION_FIELDS},
        **{f: np.array(data[f], dtype=bool) for f in _CONVENTION_FLAGS})


def _convention_dict(st: ConventionStudy) -> dict[str, Any]:
    return {"wiring": st.wiring, "t_end": st.t_end, "seeds": st.seeds.tolist(),
            **{f: [float(x) for x in getattr(st, f)] for f in _CONVENTION_FIELDS},
            **{f: [bool(x) for x in getattr(st, f)] for f in _CONVENTION_FLAGS}}


def _compute_convention(executor: object, progress: Any, *, path: Path | None = None,
                        **_: Any) -> dict[str, Any]:
    """The seeds of :data:`CONVENTION` on ``executor`` (default: one after the other)."""
    if progress is not None:
        progress.total = 1
        progress.refresh()
    st = convention_study(wiring=CONVENTION["wiring"], t_end=CONVENTION["t_end"],
                          seeds=CONVENTION["seeds"], executor=executor)
    if progress is not None:
        progress.update(1)
    return _convention_dict(st)


def _check_convention(data: Mapping[str, Any]) -> int:
    """The runs of :data:`CONVENTION_CHECK_SEEDS`, recomputed: every number within the
    header's tolerance, every flag the same."""
    name = "calibrate-convention"
    h = store.header_of(name, data)
    if (data["wiring"], float(data["t_end"]), tuple(data["seeds"])) != (
            CONVENTION["wiring"], CONVENTION["t_end"], CONVENTION["seeds"]):
        raise store.StaleStudy(name, "it was computed with other settings than "
                               f"{CONVENTION}")
    now = convention_study(wiring=CONVENTION["wiring"], t_end=CONVENTION["t_end"],
                           seeds=CONVENTION_CHECK_SEEDS)
    n = 0
    for i, seed in enumerate(CONVENTION_CHECK_SEEDS):
        j = list(data["seeds"]).index(seed)
        for f in _CONVENTION_FIELDS:
            store.compare(name, f"{f} of seed {seed}", data[f][j], getattr(now, f)[i],
                          rtol=h.rtol, atol=h.atol)
            n += 1
        for f in _CONVENTION_FLAGS:
            if bool(data[f][j]) != bool(getattr(now, f)[i]):
                raise store.StaleStudy(name, f"{f} of seed {seed} was {data[f][j]}, the "
                                       f"code now gives {bool(getattr(now, f)[i])}")
            n += 1
    return n


# the fault study -------------------------------------------------------------------------------
def with_fault(kind: str, size: float, seed: int,
               t_end: float = 100.0) -> tuple[GCRecord, float, float]:
    """A record of paper GC's model (:func:`gyrolib.gc.simulate_record`) with one defect of
    :data:`FAULTS` put in by this arithmetic of its own; returns the record and the true ω_gc
    at its start and at its end (rad/s).

    Examples
    --------
    >>> from gyrolib.book.studies.calibrate import with_fault
    >>> rec, w0, w1 = with_fault("late start (s)", 0.1, seed=1, t_end=1.0)
    >>> rec.n, w0 == w1
    (1000, True)
    """
    p0 = GyrocompassParams()
    params = p0.at_latitude(np.radians(size)) if kind == "latitude" else p0
    lead = size if kind == "late start (s)" else 0.0
    sim = simulate_record(params, t_end + lead, seed=seed)
    r = sim.record
    t, a, y, z = (np.array(c, float) for c in (r.t, r.angle_sensor, r.inclinometer_y,
                                                r.inclinometer_z))
    w_end = sim.omega_gc
    if kind == "null offset (″)":
        a += size * ARCSEC_PAPER
    elif kind == "angle-sensor gain error":
        a *= 1.0 + size
    elif kind == "inclinometer_z bias (mg)":
        z += size * MG
    elif kind == "late start (s)":              # the logger's clock starts `lead` late
        keep = t > lead + 0.5 * p0.dt
        t, a, y, z = np.round((t[keep] - lead) / p0.dt) * p0.dt, a[keep], y[keep], z[keep]
    elif kind == "drift change at 50 s (″/s)":  # the float turns faster by (H/f) Δω
        s = np.clip(t - 0.5 * t_end, 0.0, None)
        tau = p0.I / p0.f
        a += p0.H / p0.f * size * ARCSEC_PAPER * (s - tau * (1 - np.exp(-s / tau)))
        w_end = sim.omega_gc + size * ARCSEC_PAPER
    elif kind == "angle-sensor step at 50 s (µrad)":
        a[t > 0.5 * t_end] += size * 1e-6
    elif kind != "latitude":
        raise ValueError(f"kind must be one of {[k for k, _ in FAULTS]}; got {kind!r}")
    rec = GCRecord(t=t, angle_sensor=a, inclinometer_y=y, inclinometer_z=z)
    return rec, sim.omega_gc, w_end


def command_params() -> GyrocompassParams:
    """The paper's filter with the command's priors of scale, offset and inclinometer bias
    (as the chapter states them: in ″ and mg)."""
    return dataclasses.replace(
        GyrocompassParams(), sigma_hf_scale=PRIORS["sigma_hf_scale"],
        sigma_as_offset=PRIORS["sigma_as_offset"] / ARCSEC_PAPER * ARCSEC_PAPER,
        sigma_incl_bias=PRIORS["sigma_incl_bias"] / MG * MG)


def _fault_row(k: int) -> dict[str, Any]:
    """The k-th defect of :data:`FAULTS`: its error with the paper's filter and its verdict
    as the command gives it (the latitude: as a logger writes the record, without a
    latitude line, judged as of :data:`LATITUDES`)."""
    kind, size = FAULTS[k]
    rec, w0, w1 = with_fault(kind, size, seed=FAULT_SEED + k)
    p0 = GyrocompassParams()
    old = calibrate(rec, p0)              # the paper's filter; valid = kept lock
    row: dict[str, Any] = {"kind": kind, "size": size, "seed": FAULT_SEED + k,
                           "omega_start": w0, "omega_end": w1,
                           "z_old": (old.omega_gc - w0) / old.omega_gc_std,
                           "lost_lock_old": bool(old.lost_lock), "run_old": _run(old)}
    if kind == "latitude":
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / "fault_latitude.csv"
            records.write_csv(path, {"t": rec.t, "angle_sensor": rec.angle_sensor,
                                     "inclinometer_y": rec.inclinometer_y,
                                     "inclinometer_z": rec.inclinometer_z},
                              fmt=["%.6f", "%.12g", "%.12g", "%.12g"])
            runs = {str(lat): _verdict(judged(path, latitude=lat)) for lat in LATITUDES}
        first = runs[str(None)]
        valid, reason = first["valid"], first["reason"]
        z_new = abs(first["estimate"] - w0) / first["sigma"] if valid else None
        row["latitude_runs"] = runs
    else:
        new = calibrate(rec, command_params())       # the command's defaults
        valid, reason = bool(new.valid), new.reason
        row["run_new"] = _run(new)
        z_new = max(abs(new.omega_gc - w) for w in (w0, w1)) / new.omega_gc_std
    row.update(valid=valid, reason=reason, z_new=z_new)
    return row


def _run(res: Any) -> dict[str, Any]:
    """What the check compares of a run (:func:`_same_run`)."""
    d = res.summary()
    return {k: d[k] for k in (*_RUN_NUMBERS, *_RUN_EQUAL, "omega_gc_std_parts",
                              "model_tests")}


def _compute_faults(executor: object, progress: Any, *, path: Path | None = None,
                    **_: Any) -> dict[str, Any]:
    """Every defect of :data:`FAULTS`, on ``executor`` (default: one after the other)."""
    if progress is not None:
        progress.total = len(FAULTS)
        progress.refresh()
    rows = []
    if executor is None:
        for k in range(len(FAULTS)):
            rows.append(_fault_row(k))
            if progress is not None:
                progress.update(1)
    else:
        futures = [executor.submit(_fault_row, k) for k in range(len(FAULTS))]  # type: ignore[attr-defined]
        for f in futures:
            rows.append(f.result())
            if progress is not None:
                progress.update(1)
    return {"faults": rows}


def _check_faults(data: Mapping[str, Any]) -> int:
    """The defects of :data:`FAULTS_CHECKED`, recomputed: the errors within the header's
    tolerance, the verdict and its reason the same."""
    name = "calibrate-faults"
    h = store.header_of(name, data)
    stored = data["faults"]
    if [(r["kind"], r["size"], r["seed"]) for r in stored] != [
            (kind, size, FAULT_SEED + k) for k, (kind, size) in enumerate(FAULTS)]:
        raise store.StaleStudy(name, "it was computed over other defects than FAULTS")
    n = 0
    for k in FAULTS_CHECKED:
        was, now = stored[k], _fault_row(k)
        for f in ("omega_start", "omega_end", "z_old", "z_new"):
            store.compare(name, f"{f} of {was['kind']}", math.nan if was[f] is None
                          else was[f], math.nan if now[f] is None else now[f],
                          rtol=h.rtol, atol=h.atol)
            n += 1
        for f in ("lost_lock_old", "valid", "reason"):
            if was[f] != now[f]:
                raise store.StaleStudy(name, f"{f} of {was['kind']} was {was[f]!r}, the "
                                       f"code now gives {now[f]!r}")
            n += 1
        for run, who in (("run_old", "the paper's filter"), ("run_new", "the command")):
            if run in was:
                n += _same_run(name, was[run], now[run], h,
                               f"of {was['kind']} with {who}")
    return n


# registration and reading ----------------------------------------------------------------------
for _name, _check, _compute, _rtol, _atol, _what in (
        ("calibrate-fit-noise", _check_fit, _compute_fit, 1e-6, 0.0,
         "paper GC's noise fitted from the wide-spectrum sample record, judged"),
        ("calibrate-convention", _check_convention, _compute_convention, 1e-6, 1e-15,
         "a swapped inclinometer pair over 12 seeds (gc.convention_study)"),
        ("calibrate-faults", _check_faults, _compute_faults, 1e-6, 1e-12,
         "records with an instrument's defects, the paper's filter and the command")):
    store.register(store.Study(_name, _FILES[_name], functools.partial(key, _name), _check,
                               _compute, rtol=_rtol, atol=_atol, what=_what))


def load(name: str) -> dict[str, Any]:
    """The stored study ``name``, checked first (:func:`gyrolib.store.check`: its key, then
    its fingerprint points); :class:`gyrolib.store.StaleStudy` names a stale one and the
    command that refreshes it."""
    if name not in NAMES:
        raise ValueError(f"name must be one of {NAMES}; got {name!r}")
    store.check(name)
    return json.loads(_FILES[name].read_text(encoding="utf-8"))

