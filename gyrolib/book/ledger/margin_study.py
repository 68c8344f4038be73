"""What flips each verdict, globally: a Sobol' study of the claims' margins over the table of
inputs.

The claims are those of :data:`gyrolib.book.ledger.claims.CLAIMS`, each a *margin* whose sign
is the verdict (the race's saving minus 50 %, ``1 − t_c/510 s``, the share compensated minus
90 %, …).  A study (:data:`STUDIES`) takes one paper's claims and:

* **inputs**: every *uncertain* row of :mod:`gyrolib.inputs` that those claims read (paper
  GC's and the race's rival's for ``"gc-claims"``; paper RSF's for ``"rsf-claims"``), each
  drawn over its row's range on its row's scale (log-uniform on a log row, uniform on a
  linear one): no range is typed here.  Operating rows (roll rate, correction interval, the
  procedure's times, the filter's priors) and readings stay at their reference: the claim
  maps sweep them one at a time (:func:`gyrolib.claim_map.map_claim`), they are not
  uncertain;
* **outputs**: each claim's margin, and the quantity the ledger quotes beside them (paper
  GC's σ_gc(100 s), paper RSF's δK at its worked example); GC's t_c is read from the speed
  claim's margin, ``t_c = 510 s × (1 − margin)``, censored at 510 s (the margin's −1);
* the Sobol' indices of each output (:func:`gyrolib.sensitivity.run_study`, on any
  ``executor``: a Dask cluster's ``client.get_executor()`` included), and
  :func:`margin_slopes`, ∂ output/∂ ln x at the reference point (a margin changes sign, so
  the semi-elasticity, not ∂ ln y/∂ ln x).

The study is computed once, offline (``python3 tasks.py refresh sensitivity-gc``, or
``python -m gyrolib sensitivity gc-claims --n N --out gyrolib/data/sensitivity_gc.json``), and
stored as package data with the store's header (:mod:`gyrolib.store`, checked by
:func:`gyrolib.book.studies.check_all`).  The stored file names the
table's fingerprint over its inputs (:func:`gyrolib.inputs.table_fingerprint`):
:func:`stored_study` refuses a file computed over another table, and :func:`recheck_study`
recomputes a few of its points, so that a study the code no longer reproduces fails the
build loudly.

Examples
--------
>>> from gyrolib.book.ledger import margin_study as ms
>>> [x.name for x in ms.study_inputs("rsf-claims")]
['rsf.eps1', 'rsf.gs_bias', 'rsf.eps1_gs', 'rsf.encoder_error']
>>> ms.study_outputs("rsf-claims")[:2]
('delta_k', 'rsf.example.compensated')
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from gyrolib import _validation as v
from gyrolib import inputs as _inputs
from gyrolib._executor import check_executor, map_ordered
from gyrolib.book.ledger.claims import CLAIMS, sigmas
from gyrolib.rsf.equations import delta_k
from gyrolib.sensitivity import (
    Recheck,
    SensitivityResult,
    SobolInput,
    recheck,
    result_from_dict,
    run_study,
)

__all__ = ["DATA_DIR", "STUDIES", "Study", "margin_slopes", "margin_study", "recheck_study",
           "reference_outputs", "stored_study", "study_file", "study_inputs", "study_outputs"]

#: Where the stored studies are (package data, beside the claim maps).
DATA_DIR: Final[Path] = Path(__file__).resolve().parents[2] / "data"


@dataclass(frozen=True)
class Study:
    """One paper's study: its ``claims`` (ids of :data:`CLAIMS`), the ``quantities`` the
    ledger quotes beside them (outputs before the margins), their ``units``, the file it is
    stored in (``file``, under :data:`DATA_DIR`) and the sample points per task
    (``chunk``: a few seconds of work)."""

    claims: tuple[str, ...]
    quantities: tuple[str, ...]
    units: tuple[str, ...]
    file: str
    chunk: int


#: The two studies, by the name the command line uses.
STUDIES: Final[dict[str, Study]] = {
    "gc-claims": Study(("gc.faster_percent", "gc.time_to_sigma_c", "gc.claim.trend_holds",
                        "gc.claim.psi_separable"), ("sigma_gc_100s",), ("rad/s",),
                       "sensitivity_gc.json", 4),
    "rsf-claims": Study(("rsf.example.compensated", "rsf.claim.gs_vs_sins",
                         "rsf.claim.drz_cubic", "rsf.claim.drz_kilometres"), ("delta_k",),
                        ("1",), "sensitivity_rsf.json", 2048),
}


def _study(model: str) -> Study:
    try:
        return STUDIES[model]
    except KeyError:
        raise ValueError(f"model must be one of {tuple(STUDIES)}; got {model!r}") from None


def study_inputs(model: str) -> tuple[SobolInput, ...]:
    """The uncertain rows the study's claims read, in the table's order, as Sobol' inputs
    over the table's ranges (the reference is the row's ``nominal``)."""
    s = _study(model)
    read = {n for c in s.claims for n in CLAIMS[c].inputs}
    return tuple(r.sobol_input() for r in _inputs.INPUTS
                 if r.name in read and r.kind == "uncertain")


def study_outputs(model: str) -> tuple[str, ...]:
    """The quantities, then the claims' margins (named by the claims' ids)."""
    s = _study(model)
    return s.quantities + s.claims


def _units(model: str) -> tuple[str, ...]:
    s = _study(model)
    return s.units + tuple(CLAIMS[c].unit for c in s.claims)


def _quantities(model: str, objs: Mapping[str, Any]) -> list[float]:
    if model == "gc-claims":   # σ(100 s) of the trend's own covariance analysis (kept)
        return [sigmas(objs["GyrocompassParams"])[2]]
    ex, gs, enc = objs["WorkedExample"], objs["MemsGyroSpec"], objs["EncoderSpec"]
    return [float(delta_k(ex.eps0_gs(gs), enc.position_error, ex.omega_x, ex.period,
                          ex.eps1_gs(gs), ex.omega_unc_at(ex.omega_x)))]


def _outputs_at(model: str, changes: Mapping[str, Any]) -> list[float]:
    objs = _inputs.apply(_inputs.reference_objects(), changes)
    return _quantities(model, objs) + [float(CLAIMS[c].margin(objs))
                                       for c in _study(model).claims]


def reference_outputs(model: str) -> list[float]:
    """The study's outputs at the reference point (every row at its reference)."""
    return _outputs_at(model, {})


def _evaluate(points: NDArray[np.float64], context: tuple) -> NDArray[np.float64]:
    """The outputs at each row of ``points`` (module level: it is pickled)."""
    model, names = context
    return np.array([_outputs_at(model, dict(zip(names, map(float, row), strict=True)))
                     for row in points]).reshape(len(points), -1)


def margin_study(model: str, n: int, seed: int = 0, executor: object = None, *,
                 chunk_size: int | None = None, progress: Callable[[int], None] | None = None,
                 second_order: bool = False,
                 previous: SensitivityResult | None = None) -> SensitivityResult:
    """Sobol' indices of the study's outputs (:func:`study_outputs`) over its inputs
    (:func:`study_inputs`): ``n (D + 2)`` points (``n (2D + 2)`` with ``second_order``),
    in chunks of ``chunk_size`` (default: the study's :attr:`Study.chunk`) on ``executor``.
    ``settings`` record the table's fingerprint over the inputs and the claims;
    ``conditions`` the readings the claims read, at the book's reading.

    Examples
    --------
    >>> from gyrolib.book.ledger import margin_study as ms
    >>> r = ms.margin_study("rsf-claims", 4, seed=0)
    >>> r.values.shape
    (24, 5)
    """
    xs = study_inputs(model)
    names = tuple(x.name for x in xs)
    s = _study(model)
    readings = {r.name: r.reference for r in _inputs.rows(kind="reading")
                if any(r.name in CLAIMS[c].inputs for c in s.claims)}
    return run_study(model, xs, study_outputs(model), _units(model), _evaluate,
                     (model, names), n, seed, executor=executor,
                     chunk_size=s.chunk if chunk_size is None else chunk_size,
                     progress=progress, second_order=second_order, previous=previous,
                     conditions=readings,
                     settings={"table": _inputs.table_fingerprint(names),
                               "claims": list(_study(model).claims)})


def margin_slopes(model: str, rel_step: float = 0.01,
                  executor: object = None) -> dict[str, dict[str, float | None]]:
    """∂ output/∂ ln x at the reference point for each input of the study with a nonzero
    reference (central differences of ``rel_step``), ``None`` for an input whose reference
    is zero (an error the paper's model leaves out: no relative change of it exists):
    ``{output: {input: slope}}``.  A margin's slope says how far a relative change of the
    input moves the verdict's quantity, whatever the input's range; the Sobol' index says
    how much of its variance the range causes."""
    rel_step = v.check_in_range("rel_step", rel_step, 0.0, 0.5, low_open=True,
                                high_open=True)
    xs = [x for x in study_inputs(model) if x.nominal != 0.0]
    calls = [(model, {x.name: x.nominal * (1.0 + s * rel_step)})
             for x in xs for s in (1.0, -1.0)]
    got = map_ordered(_outputs_at, calls, check_executor(executor))
    dlog = math.log1p(rel_step) - math.log1p(-rel_step)
    outs = study_outputs(model)
    slopes: dict[str, dict[str, float | None]] = {o: {} for o in outs}
    for j, x in enumerate(xs):
        up, down = got[2 * j], got[2 * j + 1]
        for k, o in enumerate(outs):
            slopes[o][x.name] = (up[k] - down[k]) / dlog
    for x in study_inputs(model):
        if x.nominal == 0.0:
            for o in outs:
                slopes[o][x.name] = None
    return slopes


def study_file(model: str) -> Path:
    """The stored study's file (package data)."""
    return DATA_DIR / _study(model).file


def stored_study(model: str, path: Path | None = None) -> tuple[SensitivityResult,
                                                                dict[str, Any]]:
    """The stored study and its whole record (the command's run, the slopes).

    Raises ``ValueError`` naming the file when it holds another study, or one computed over
    another table of inputs (other rows, ranges, scales or references) or other claims:
    recompute it (``python -m gyrolib sensitivity MODEL --out FILE``)."""
    if path is not None and not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"path must be a file path (str or os.PathLike); got "
                        f"{type(path).__name__}")
    path = study_file(model) if path is None else Path(path)
    if not path.is_file():
        raise ValueError(f"path must be an existing file; got {path}")
    data = json.loads(path.read_text(encoding="utf-8"))
    again = f"recompute it: python -m gyrolib sensitivity {model} --out {path}"
    if data.get("model") != model:
        raise ValueError(f"{path} holds the study {data.get('model')!r}, not {model!r}; "
                         + again)
    res = result_from_dict(data)
    names = tuple(x.name for x in study_inputs(model))
    if (res.input_names != names or res.settings.get("table")
            != _inputs.table_fingerprint(names)
            or tuple(res.settings.get("claims", ())) != _study(model).claims):
        raise ValueError(f"{path} was computed over another table of inputs or other claims "
                         "than the study reads now; " + again)
    missing = {"at", "slopes", "run"} - set(data)
    if missing:
        raise ValueError(f"{path} lacks {sorted(missing)}; " + again)
    return res, data


def recheck_study(result: SensitivityResult, k: int = 3, seed: int = 0) -> Recheck:
    """Compute ``k`` points of a stored study again (rows drawn with ``seed``)."""
    v.check_instance("result", result, SensitivityResult)
    if result.model not in STUDIES:
        raise ValueError(f"result must be a study of {tuple(STUDIES)}; got model "
                         f"{result.model!r}")
    names = result.input_names
    return recheck(result, _evaluate, (result.model, names), k=k, seed=seed)
