"""The book's heavy studies in the store (:mod:`gyrolib.store`): the claim maps with the race's
verdict grid, and the two Sobol' studies of the claims' margins.

Each is registered under a name (:data:`NAMES`) with its file, its key, its fingerprint check
and its computation:

* ``claim-maps`` (``gyrolib/data/claim_maps.json``): every claim of
  :data:`gyrolib.book.ledger.claims.CLAIMS` mapped over the table of inputs, and the race's
  verdict grid.  Its fingerprint (:func:`gyrolib.claim_map.fingerprint_points`): each map's
  stored points, every threshold bracketed (the margin just inside and just outside it must
  have the map's signs), every reading's status, a fixed sample of the sweeps' points; and
  four cells of the verdict grid, where its margin changes sign;
* ``sensitivity-gc`` and ``sensitivity-rsf`` (``gyrolib/data/sensitivity_*.json``): the
  outputs at the reference point and a fixed sample of the study's points, recomputed.

The key of each (:func:`key`) hashes the table's rows, the owners' instances at their
defaults, and the named constants and default dataclasses of every module the margins read
(the Earth rate and the paper's latitude, the printed levels, the units, the race's and the
simulation's defaults): a change of any of them makes the study stale, inside the table or
not.

``python3 tasks.py refresh [NAME ...]`` recomputes them (:func:`gyrolib.store.refresh`);
:func:`gyrolib.book.studies.check_all` (over every stored study of the book) is what the
ledger, the ``claims`` command, the chapters and the tests run.

Examples
--------
>>> from gyrolib.book.ledger import studies
>>> studies.NAMES
('claim-maps', 'sensitivity-gc', 'sensitivity-rsf')
>>> sorted(studies.key("claim-maps"))[:2]
['gyrolib.gc.model.discretization', 'gyrolib.gc.model.params']
"""

from __future__ import annotations

import dataclasses
import functools
import json
import os
import platform
import time
from collections.abc import Mapping
from dataclasses import replace
from datetime import UTC, datetime
from pathlib import Path
from typing import Any, Final

import numpy as np

from gyrolib import __version__, levels, store, units
from gyrolib import inputs as _inputs
from gyrolib.book.ledger import claims as _claims
from gyrolib.book.ledger import margin_study as _ms
from gyrolib.claim_map import ClaimMap, check_map, extend_box
from gyrolib.gc.model import discretization as _gc_discretization
from gyrolib.gc.model import params as _gc_params
from gyrolib.gc.racing import comparison as _race
from gyrolib.gc.racing import rate_sensor as _rate_sensor
from gyrolib.rsf import sensors as _rsf_sensors
from gyrolib.rsf import simulation as _rsf_simulation
from gyrolib.rsf import tables as _rsf_tables
from gyrolib.sensitivity import result_from_dict

__all__ = ["GRID_CELLS", "MODULES", "NAMES", "SAMPLE", "key"]

#: The registered studies, in the order ``refresh --list`` shows them.
NAMES: Final[tuple[str, ...]] = ("claim-maps", "sensitivity-gc", "sensitivity-rsf")

#: The modules whose constants and default dataclasses each study's margins read, the owners
#: of the table it reads (at their defaults) and the prefixes of its rows.
_GC_MODULES: Final[tuple[Any, ...]] = (levels, units, _gc_params, _gc_discretization, _race,
                                       _rate_sensor)
_RSF_MODULES: Final[tuple[Any, ...]] = (levels, units, _rsf_sensors, _rsf_simulation,
                                        _rsf_tables)
_READS: Final[dict[str, tuple[tuple[Any, ...], tuple[str, ...], tuple[str, ...]]]] = {
    "claim-maps": (_GC_MODULES + _RSF_MODULES[2:], tuple(_inputs.OWNERS), ("",)),
    "sensitivity-gc": (_GC_MODULES, ("GyrocompassParams", "RateSensorProcedure"),
                       ("gc.", "race.")),
    "sensitivity-rsf": (_RSF_MODULES, ("RollGyroSpec", "MemsGyroSpec", "EncoderSpec",
                                       "WorkedExample"), ("rsf.",)),
}
#: Every module some study reads.
MODULES: Final[tuple[Any, ...]] = _READS["claim-maps"][0]

#: Points of each Sobol' study recomputed by its check (rows drawn with seed 0).
SAMPLE: Final[dict[str, int]] = {"sensitivity-gc": 3, "sensitivity-rsf": 8}

#: Cells of the race's verdict grid recomputed by the check, per reading: the last cell that
#: holds and the first that fails along σ1² at the middle factor of C_as.
GRID_CELLS: Final[int] = 2

_MODEL: Final[dict[str, str]] = {"sensitivity-gc": "gc-claims", "sensitivity-rsf": "rsf-claims"}


def key(name: str) -> dict[str, str]:
    """The key of study ``name`` now (:func:`gyrolib.store.model_key`): the table's
    fingerprint over the rows it reads, the owners of those rows at their defaults, and the
    constants and default dataclasses of the modules its margins read."""
    if name not in NAMES:
        raise ValueError(f"name must be one of {NAMES}; got {name!r}")
    modules, owners, prefixes = _READS[name]
    ref = _inputs.reference_objects()
    rows = tuple(r.name for r in _inputs.INPUTS if r.name.startswith(prefixes))
    return store.model_key(modules, objects={k: ref[k] for k in owners},
                           extra={"table": _inputs.table_fingerprint(rows)})


# the claim maps --------------------------------------------------------------------------------
def _header(name: str, data: Mapping[str, Any]) -> store.Header:
    return store.header_of(name, data)


def _check_maps(data: Mapping[str, Any], ids: tuple[str, ...] | None = None) -> int:
    """Every map's fingerprint points (:func:`gyrolib.claim_map.check_map`) and the verdict
    grid's cells, within the header's tolerance."""
    h = _header("claim-maps", data)
    maps = {k: ClaimMap.from_dict(v) for k, v in data["maps"].items()}
    chosen = tuple(_claims.CLAIMS) if ids is None else ids
    missing = [i for i in chosen if i not in maps]
    if missing:
        raise store.StaleStudy("claim-maps", f"it has no map of {', '.join(missing)}")
    n = 0
    for i in chosen:
        c = _claims.CLAIMS[i]
        if maps[i].settings.get("table") != _inputs.table_fingerprint(c.inputs) \
                or set(maps[i].reference) != set(c.inputs):
            raise store.StaleStudy("claim-maps", f"{i}: its map was computed over another "
                                   "table of inputs than the claim reads now")
        try:
            n += check_map(c, maps[i], rtol=h.rtol, atol=h.atol)
        except ValueError as exc:
            raise store.StaleStudy("claim-maps", str(exc)) from None
    if ids is None and "race_grid" in data.get("extras", {}):
        n += _check_grid(data["extras"]["race_grid"], h)
    return n


def _grid_cells(grid: Mapping[str, Any]) -> list[tuple[int, int, int]]:
    """(reading, C_as, σ1²) indices of the cells the check recomputes (:data:`GRID_CELLS`)."""
    m = np.asarray(grid["margin"], float)
    j = m.shape[1] // 2
    cells = []
    for r in range(m.shape[0]):
        row = m[r, j]
        flips = [k for k in range(len(row) - 1) if (row[k] > 0) != (row[k + 1] > 0)]
        k = flips[0] if flips else len(row) // 2
        cells += [(r, j, k), (r, j, min(k + 1, len(row) - 1))][:GRID_CELLS]
    return cells


def _check_grid(grid: Mapping[str, Any], h: store.Header) -> int:
    o = _inputs.reference_objects()
    m = np.asarray(grid["margin"], float)
    p = o["GyrocompassParams"]
    for r, j, k in _grid_cells(grid):
        reading = grid["readings"][r]
        s1, ca = float(grid["sigma1_factors"][k]), float(grid["cas_factors"][j])
        # the cell's margin as race_verdict_grid computes it, without the grid's race times
        # (a whole race with its curves per reading, which the check does not compare)
        now = _race.race_margin(dataclasses.replace(
            p, measurement_noise=reading, C_as=ca * p.C_as, sigma1_sq=s1 * p.sigma1_sq),
            o["RateSensorProcedure"])
        store.compare("claim-maps", f"the race's verdict grid at σ1² × {s1:.4g}, C_as × "
                      f"{ca:.4g}, {reading}", m[r, j, k], now, rtol=h.rtol, atol=h.atol)
    return len(_grid_cells(grid))


def _twin(i: str, done: Mapping[str, ClaimMap]) -> ClaimMap | None:
    """A map computed in this run of a claim with the same margin, rows and options as
    ``i`` (Fig. 3's drop and the trend read the same criterion over the same table): its
    map, relabelled, is the one :func:`gyrolib.claim_map.map_claim` would give ``i``."""
    c = _claims.CLAIMS[i]
    for j, m in done.items():
        d = _claims.CLAIMS[j]
        if (d.margin, d.inputs, d.per_reading, d.searches) == (c.margin, c.inputs,
                                                                c.per_reading, c.searches):
            return replace(m, claim=i, meaning=c.meaning)
    return None


def _compute_maps(executor: object, progress: Any, *, path: Path | None = None,
                  ids: tuple[str, ...] | None = None, grid: bool | None = None,
                  n_box: int | None = None, seed: int | None = None,
                  extend: bool = False) -> dict[str, Any]:
    """The maps of ``ids`` (default: every claim) and, with ``grid`` (default: when every
    claim is recomputed), the race's verdict grid; the other maps and the grid are kept from
    the file at ``path`` (default: the stored one).

    ``n_box`` and ``seed`` default to each claim's :data:`~gyrolib.book.ledger.claims.
    BOX_POINTS` and :data:`~gyrolib.book.ledger.claims.BOX_SEED`.  With ``extend``, a stored
    map with the same seed and fewer points that agrees with the code (its fingerprint
    points, :func:`gyrolib.claim_map.check_map`) keeps its sweeps and thresholds and only
    gets the new box points (:func:`gyrolib.claim_map.extend_box`: the same map as a full
    recomputation); any other map is recomputed whole."""
    chosen = tuple(_claims.CLAIMS) if ids is None else tuple(ids)
    unknown = [i for i in chosen if i not in _claims.CLAIMS]
    if unknown:
        raise ValueError(f"ids: unknown claim {unknown[0]!r}; known: "
                         f"{', '.join(_claims.CLAIMS)}")
    grid = ids is None if grid is None else grid
    src = _claims.MAPS_FILE if path is None else Path(path)
    old = json.loads(src.read_text(encoding="utf-8")) if src.is_file() else {}
    maps = dict(old.get("maps", {}))
    extras = dict(old.get("extras", {}))
    if progress is not None:
        progress.total = len(chosen) + int(grid)
        progress.refresh()
    done: dict[str, ClaimMap] = {}
    for i in chosen:
        n = _claims.BOX_POINTS[i] if n_box is None else n_box
        s = _claims.BOX_SEED if seed is None else seed
        m = _twin(i, done) if n == _claims.BOX_POINTS[i] and s == _claims.BOX_SEED else None
        if m is None and extend and i in maps:
            m = _extended(i, ClaimMap.from_dict(maps[i]), n, s, executor)
        if m is None:
            m = _claims.maps((i,), executor=executor, n_box=n, seed=s)[i]
        done[i] = m
        maps[i] = m.to_dict()
        if progress is not None:
            progress.update(1)
    if grid:
        extras["race_grid"] = _claims.race_grid(executor)
        if progress is not None:
            progress.update(1)
    return {"schema": _claims.MAPS_SCHEMA, "maps": maps, "extras": extras}


def _extended(i: str, m: ClaimMap, n_box: int, seed: int, executor: object
              ) -> ClaimMap | None:
    """The stored map ``m`` of ``i`` grown to ``n_box`` points, or ``None`` when it cannot
    be (another seed or table, more points already, no box, or it disagrees with the
    code)."""
    c = _claims.CLAIMS[i]
    sh = m.share_holding
    if (sh is None or sh.seed != seed or sh.n > n_box or set(m.reference) != set(c.inputs)
            or m.settings.get("table") != _inputs.table_fingerprint(c.inputs)):
        return None
    try:
        check_map(c, m)
    except ValueError:
        return None
    return extend_box(c, m, n_box, executor=executor)


# the Sobol' studies ----------------------------------------------------------------------------
def _check_sobol(name: str, data: Mapping[str, Any]) -> int:
    """The outputs at the reference (``"at"``) and :data:`SAMPLE` points of the study,
    recomputed within the header's tolerance."""
    h = _header(name, data)
    model = _MODEL[name]
    res = result_from_dict(data)
    names = tuple(x.name for x in _ms.study_inputs(model))
    if res.input_names != names or res.settings.get("table") != _inputs.table_fingerprint(
            names) or tuple(res.settings.get("claims", ())) != _ms.STUDIES[model].claims:
        raise store.StaleStudy(name, "it was computed over another table of inputs or other "
                               "claims than the study reads now")
    outs = res.outputs
    for o, was, now in zip(outs, data["at"], _ms.reference_outputs(model), strict=True):
        store.compare(name, f"{o} at the reference", was, now, rtol=h.rtol, atol=h.atol)
    chk = _ms.recheck_study(res, k=SAMPLE[name], seed=0)
    for i, row in enumerate(chk.rows):
        for j, o in enumerate(outs):
            store.compare(name, f"{o} at the study's point {int(row)}", chk.stored[i, j],
                          chk.recomputed[i, j], rtol=h.rtol, atol=h.atol)
    return len(outs) * (1 + len(chk.rows))


def _compute_sobol(name: str, executor: object, progress: Any, *, path: Path | None = None,
                   n: int | None = None, seed: int | None = None,
                   second_order: bool | None = None, workers: int | None = None,
                   where: str | None = None) -> dict[str, Any]:
    """The study at the stored file's ``n``, ``seed`` and order unless given, with the
    outputs at the reference and the margins' slopes, and a record of the run (``workers``
    and ``where`` describe the executor: default one, in-process, without one)."""
    model = _MODEL[name]
    src = _ms.study_file(model) if path is None else Path(path)
    old = json.loads(src.read_text(encoding="utf-8")) if src.is_file() else {}
    n = int(old.get("n", 64)) if n is None else n
    seed = int(old.get("seed", 0)) if seed is None else seed
    second_order = bool(old.get("second_order")) if second_order is None else second_order
    total = n * ((2 if second_order else 1) * len(_ms.study_inputs(model)) + 2)
    if progress is not None:
        progress.total = total
        progress.refresh()
    started = datetime.now(UTC).isoformat(timespec="seconds")
    t0 = time.perf_counter()
    res = _ms.margin_study(model, n, seed=seed, executor=executor,
                           progress=None if progress is None else progress.update,
                           second_order=second_order)
    record = {**res.to_dict(), "at": _ms.reference_outputs(model),
              "slopes": _ms.margin_slopes(model, executor=executor)}
    record["run"] = {
        "command": f"python3 tasks.py refresh {name}", "version": __version__,
        "started": started,
        "machine": {"platform": platform.platform(), "processor": platform.machine(),
                    "python": platform.python_version(), "cpus": os.cpu_count()},
        "executor": where or ("in-process" if executor is None else type(executor).__name__),
        "workers": workers or (1 if executor is None else os.cpu_count()),
        "wall_time_s": time.perf_counter() - t0, "model_runs": total,
        "model_runs_computed": total}
    return record


def _compute_maps_any(executor: object, progress: Any, *, workers: int | None = None,
                      where: str | None = None, **options: Any) -> dict[str, Any]:
    return _compute_maps(executor, progress, **options)


# registration ----------------------------------------------------------------------------------
for _name, _file, _check, _compute, _atol, _what in (
        ("claim-maps", _claims.MAPS_FILE, _check_maps, _compute_maps_any, 1e-9,
         "every claim mapped over the table of inputs, and the race's verdict grid"),
        ("sensitivity-gc", _ms.study_file("gc-claims"),
         functools.partial(_check_sobol, "sensitivity-gc"),
         functools.partial(_compute_sobol, "sensitivity-gc"), 1e-18,
         "Sobol' indices of paper GC's claims' margins over the uncertain rows"),
        ("sensitivity-rsf", _ms.study_file("rsf-claims"),
         functools.partial(_check_sobol, "sensitivity-rsf"),
         functools.partial(_compute_sobol, "sensitivity-rsf"), 1e-18,
         "Sobol' indices of paper RSF's claims' margins over the uncertain rows")):
    store.register(store.Study(_name, _file, functools.partial(key, _name), _check, _compute,
                               rtol=1e-6, atol=_atol, what=_what,
                               rows="" if _name == "claim-maps" else "values"))

