"""Global (variance-based) sensitivity analysis: Sobol' indices of a model's outputs with
respect to its uncertain inputs, on any ``concurrent.futures.Executor``.

Paper-agnostic; the studies of the two papers are :func:`gyrolib.gc.sensitivity` and
:func:`gyrolib.rsf.sensitivity`.  The estimator is SALib's: Saltelli's extension of the
scrambled Sobol' sequence (``SALib.sample.sobol.sample``, ``N (2D + 2)`` model runs for
``D`` inputs with the second-order indices), and ``SALib.analyze.sobol.analyze``: the
first-order indices S_i (Saltelli et al. 2010), the total indices S_Ti (Jansen's estimator,
ibid.), the second-order indices S_ij (Saltelli 2002), each with a bootstrap confidence
interval.

The model runs are split into chunks of consecutive sample points and mapped on the caller's
executor (``None``: in this process); every point is computed alone and the chunks are put
back in order, so the indices do not depend on the executor, the number of workers or the
chunk size.

Each input is drawn from its range by its inverse distribution function applied to the unit
sample: ``"uniform"`` on ``[low, high]``, ``"loguniform"`` (the logarithm uniform) on
``[low, high]``.  Sobol' indices depend on these distributions: a study states them
(:class:`SobolInput`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Final

import numpy as np
from numpy.typing import NDArray

from gyrolib import _validation as v
from gyrolib._executor import check_executor, map_ordered
from gyrolib._optional import optional
from gyrolib._repr import compact_repr

__all__ = [
    "DISTRIBUTIONS",
    "Recheck",
    "SensitivityResult",
    "SobolIndex",
    "SobolInput",
    "analyze",
    "recheck",
    "result_from_dict",
    "run_study",
    "unit_sample",
]

#: How an input is drawn from its range.
DISTRIBUTIONS: Final[tuple[str, ...]] = ("uniform", "loguniform")

#: Confidence level of the bootstrap intervals, and the number of bootstrap resamples.
CONF_LEVEL: Final[float] = 0.95
NUM_RESAMPLES: Final[int] = 1000


@dataclass(frozen=True)
class SobolInput:
    """One uncertain input of a study: its range and how it is drawn from it.

    Parameters
    ----------
    name : str
        The identifier (a parameter's field name).
    symbol : str
        How the text writes it (``"α1"``).
    nominal : float
        The paper's value (SI).
    low, high : float
        The range (SI), ``low < high`` (both > 0 for ``"loguniform"``).
    distribution : {"uniform", "loguniform"}
        ``"uniform"`` on ``[low, high]`` or log-uniform on it.
    reading : str
        Why this range (what the paper prints, or that it does not).

    Examples
    --------
    The ranges of the papers' inputs are the table of inputs' (:meth:`gyrolib.inputs.Input.
    sobol_input`); a caller's own input states its range:

    >>> from gyrolib.sensitivity import SobolInput
    >>> y = SobolInput("C_as", "C_as", 1.0, 1 / 3, 3.0, "loguniform", "a factor of 3")
    >>> f"{y.value(0.5):.3f}", f"{y.value(1.0):.3f}"
    ('1.000', '3.000')
    """

    name: str
    symbol: str
    nominal: float
    low: float
    high: float
    distribution: str = "uniform"
    reading: str = ""

    def __post_init__(self) -> None:
        v.check_str("name", self.name)
        v.check_str("symbol", self.symbol)
        v.check_str("reading", self.reading)
        v.check_choice("distribution", self.distribution, DISTRIBUTIONS)
        for name in ("nominal", "low", "high"):
            object.__setattr__(self, name, v.check_real(name, getattr(self, name)))
        if not self.low < self.high:
            raise ValueError(f"low must be < high; got [{self.low}, {self.high}] for "
                             f"{self.name!r}")
        if self.distribution == "loguniform" and not self.low > 0.0:
            raise ValueError(f"low must be > 0 for a loguniform input; got {self.low} for "
                             f"{self.name!r}")

    def value(self, u: float | NDArray[np.float64]) -> float | NDArray[np.float64]:
        """The input at unit coordinate(s) ``u`` in [0, 1] (inverse distribution function)."""
        u = np.asarray(u, dtype=float)
        if self.distribution == "uniform":
            x = self.low + u * (self.high - self.low)
        else:
            lo, hi = math.log(self.low), math.log(self.high)
            x = np.exp(lo + u * (hi - lo))
        return float(x) if x.ndim == 0 else x

    def to_dict(self) -> dict[str, object]:
        """The fields as a JSON-ready dict."""
        return {"name": self.name, "symbol": self.symbol, "nominal": self.nominal,
                "low": self.low, "high": self.high, "distribution": self.distribution,
                "reading": self.reading}


@dataclass(frozen=True)
class SobolIndex:
    """A Sobol' index ``value`` and the half-width ``conf`` of its bootstrap confidence
    interval (at the study's ``conf_level``): the interval is ``[low, high]``."""

    value: float
    conf: float

    @property
    def low(self) -> float:
        """Lower end of the confidence interval."""
        return self.value - self.conf

    @property
    def high(self) -> float:
        """Upper end of the confidence interval."""
        return self.value + self.conf

    def __contains__(self, x: float) -> bool:
        return self.low <= x <= self.high


def unit_sample(d: int, n: int, seed: int, second_order: bool = True) -> NDArray[np.float64]:
    """Saltelli's sample on the unit hypercube ``[0, 1]^d`` from the scrambled Sobol'
    sequence seeded with ``seed``: ``n (2d + 2)`` rows (``n (d + 2)`` without the
    second-order indices), in SALib's order.

    Parameters
    ----------
    d : int
        Number of inputs (>= 2).
    n : int
        Base sample size, a power of 2 (the Sobol' sequence's balance needs it).
    seed : int
        Seed of the scrambling (>= 0).
    second_order : bool, default True
        Add the rows the second-order indices need.

    Returns
    -------
    ndarray of shape (n (2d + 2), d)

    Examples
    --------
    >>> from gyrolib.sensitivity import unit_sample
    >>> unit_sample(3, 4, seed=0).shape
    (32, 3)
    """
    with optional("SALib", "sensitivity", "gyrolib.sensitivity"):
        from SALib.sample import sobol as salib_sample

    d = v.check_int("d", d, 2)
    n = _check_n(n)
    seed = v.check_int("seed", seed, 0)
    second_order = v.check_bool("second_order", second_order)
    problem = {"num_vars": d, "names": [f"x{i}" for i in range(d)], "bounds": [[0.0, 1.0]] * d}
    return salib_sample.sample(problem, n, calc_second_order=second_order, scramble=True,
                               seed=seed)


def _check_n(n: object) -> int:
    n = v.check_int("n", n, 2)
    if n & (n - 1):
        raise ValueError(f"n must be a power of 2 (the Sobol' sequence's balance); got {n}")
    return n


def _points(inputs: Sequence[SobolInput], unit: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.column_stack([x.value(unit[:, j]) for j, x in enumerate(inputs)])


def analyze(names: Sequence[str], values: NDArray[np.float64], seed: int,
            second_order: bool = True, num_resamples: int = NUM_RESAMPLES,
            conf_level: float = CONF_LEVEL) -> dict[str, Any]:
    """Sobol' indices of one output from its values on Saltelli's sample (SALib).

    Parameters
    ----------
    names : sequence of str
        The inputs, in the sample's column order.
    values : ndarray
        The output at each sample point, in the sample's row order.
    seed : int
        Seed of the bootstrap resampling (>= 0; SALib is given ``seed + 1``, since it draws
        an unseeded resampling for a seed of 0).
    second_order : bool, default True
        Whether the sample has the second-order rows.
    num_resamples : int, default 1000
        Bootstrap resamples.
    conf_level : float, default 0.95
        Confidence level of the intervals.

    Returns
    -------
    dict
        ``"S1"``, ``"ST"``: ``{input: SobolIndex}``; ``"S2"``: ``{(input, input): SobolIndex}``
        (empty without second order).

    Examples
    --------
    The additive function ``x0 + 2 x1`` of two uniform inputs has S1 = ST = (1/5, 4/5):

    >>> from gyrolib.sensitivity import analyze, unit_sample
    >>> u = unit_sample(2, 1024, seed=0)
    >>> s = analyze(["x0", "x1"], u[:, 0] + 2 * u[:, 1], seed=0)
    >>> f"{s['S1']['x0'].value:.2f} {s['ST']['x1'].value:.2f}"
    '0.20 0.80'
    """
    with optional("SALib", "sensitivity", "gyrolib.sensitivity"):
        from SALib.analyze import sobol as salib_analyze

    names = [v.check_str("names[i]", x) for x in names]
    y = v.check_array("values", values, ndim=1)
    seed = v.check_int("seed", seed, 0)
    d = len(names)
    problem = {"num_vars": d, "names": names, "bounds": [[0.0, 1.0]] * d}
    s = salib_analyze.analyze(problem, y, calc_second_order=second_order,
                              num_resamples=v.check_int("num_resamples", num_resamples, 2),
                              conf_level=v.check_in_range("conf_level", conf_level, 0.0, 1.0,
                                                          low_open=True, high_open=True),
                              seed=seed + 1)
    out: dict[str, Any] = {
        "S1": {x: SobolIndex(float(s["S1"][j]), float(s["S1_conf"][j]))
               for j, x in enumerate(names)},
        "ST": {x: SobolIndex(float(s["ST"][j]), float(s["ST_conf"][j]))
               for j, x in enumerate(names)},
        "S2": {},
    }
    if second_order:
        out["S2"] = {(names[j], names[k]): SobolIndex(float(s["S2"][j, k]),
                                                      float(s["S2_conf"][j, k]))
                     for j in range(d) for k in range(j + 1, d)}
    return out


@compact_repr
@dataclass(frozen=True)
class SensitivityResult:
    """A Sobol' study: the inputs and their ranges, the outputs, the model's values on the
    sample and the indices.

    ``first_order[output][input]`` and ``total[output][input]`` are :class:`SobolIndex`
    (value and confidence interval); ``second_order[output][(input_a, input_b)]`` likewise
    (``input_a`` before ``input_b`` in ``inputs``).  ``values[:, k]`` is output ``k`` (in
    ``units[k]``) at each row of :meth:`points`.  ``conditions`` are the model's fixed
    (discrete) choices and ``settings`` the study's constants; ``model`` names the study
    (``"gc"``, ``"rsf"``).
    """

    model: str
    inputs: tuple[SobolInput, ...]
    outputs: tuple[str, ...]
    units: tuple[str, ...]
    n: int
    seed: int
    values: NDArray[np.float64]
    first_order: Mapping[str, Mapping[str, SobolIndex]]
    total: Mapping[str, Mapping[str, SobolIndex]]
    second_order: Mapping[str, Mapping[tuple[str, str], SobolIndex]]
    conditions: Mapping[str, object] = field(default_factory=dict)
    settings: Mapping[str, object] = field(default_factory=dict)
    conf_level: float = CONF_LEVEL
    num_resamples: int = NUM_RESAMPLES

    def __post_init__(self) -> None:
        v.check_str("model", self.model)
        if not self.inputs or not all(isinstance(x, SobolInput) for x in self.inputs):
            raise TypeError("inputs must be a non-empty tuple of SobolInput")
        if len(self.outputs) != len(self.units):
            raise ValueError("units must hold one unit per output")
        d = len(self.inputs)
        rows = self.n * (2 * d + 2) if self.second_order_computed else self.n * (d + 2)
        v.check_ndarray("values", self.values, shape=(rows, len(self.outputs)))

    @property
    def second_order_computed(self) -> bool:
        """Whether the sample carries the second-order rows."""
        return any(len(s) for s in self.second_order.values())

    @property
    def input_names(self) -> tuple[str, ...]:
        """The inputs' names, in the sample's column order."""
        return tuple(x.name for x in self.inputs)

    def points(self) -> NDArray[np.float64]:
        """The sample (SI values of the inputs), regenerated from ``n`` and ``seed``."""
        u = unit_sample(len(self.inputs), self.n, self.seed, self.second_order_computed)
        return _points(self.inputs, u)

    def max_conf(self, kind: str = "first_and_total") -> float:
        """The widest half-interval among the first-order and total indices
        (``kind="first_and_total"``) or among the second-order ones (``"second"``)."""
        v.check_choice("kind", kind, ("first_and_total", "second"))
        if kind == "second":
            return max((i.conf for s in self.second_order.values() for i in s.values()),
                       default=0.0)
        return max(i.conf for table in (self.first_order, self.total)
                   for s in table.values() for i in s.values())

    def ranked(self, output: str, kind: str = "total") -> list[tuple[str, SobolIndex]]:
        """``(input, index)`` pairs of ``output``, largest index first (``kind``:
        ``"total"``, ``"first"`` or ``"second"``)."""
        v.check_choice("output", output, self.outputs)
        v.check_choice("kind", kind, ("total", "first", "second"))
        table = {"total": self.total, "first": self.first_order,
                 "second": self.second_order}[kind][output]
        return sorted(table.items(), key=lambda kv: -kv[1].value)

    def to_dict(self) -> dict[str, object]:
        """A JSON-ready dict (``values`` as nested lists; the sample is not stored: it is
        regenerated from ``n`` and ``seed``)."""
        def table(t: Mapping[str, Mapping[Any, SobolIndex]]) -> dict[str, object]:
            return {o: {(k if isinstance(k, str) else f"{k[0]}|{k[1]}"):
                        {"value": i.value, "conf": i.conf} for k, i in t[o].items()}
                    for o in self.outputs}
        return {"model": self.model, "inputs": [x.to_dict() for x in self.inputs],
                "outputs": list(self.outputs), "units": list(self.units), "n": self.n,
                "seed": self.seed, "conditions": dict(self.conditions),
                "settings": dict(self.settings), "conf_level": self.conf_level,
                "num_resamples": self.num_resamples,
                "first_order": table(self.first_order), "total": table(self.total),
                "second_order": table(self.second_order),
                "values": self.values.tolist()}


def result_from_dict(data: Mapping[str, Any]) -> SensitivityResult:
    """The :class:`SensitivityResult` written by :meth:`SensitivityResult.to_dict` (extra
    keys, such as a command line's run record, are ignored).

    Examples
    --------
    >>> import json
    >>> from gyrolib import rsf
    >>> from gyrolib.sensitivity import result_from_dict
    >>> r = rsf.sensitivity(8, seed=0)
    >>> back = result_from_dict(json.loads(json.dumps(r.to_dict())))
    >>> back.total["delta_k"]["encoder_error"] == r.total["delta_k"]["encoder_error"]
    True
    """
    if not isinstance(data, Mapping):
        raise TypeError(f"data must be a mapping; got {type(data).__name__}")
    missing = {"model", "inputs", "outputs", "units", "n", "seed", "values", "first_order",
               "total", "second_order"} - set(data)
    if missing:
        raise ValueError(f"data lacks the field(s) {sorted(missing)}")

    def table(t: Mapping[str, Mapping[str, Mapping[str, float]]],
              pairs: bool = False) -> dict[str, dict[Any, SobolIndex]]:
        return {o: {(tuple(k.split("|")) if pairs else k): SobolIndex(float(i["value"]),
                                                                       float(i["conf"]))
                    for k, i in t[o].items()} for o in t}

    return SensitivityResult(
        model=data["model"], inputs=tuple(SobolInput(**x) for x in data["inputs"]),
        outputs=tuple(data["outputs"]), units=tuple(data["units"]), n=int(data["n"]),
        seed=int(data["seed"]), values=np.asarray(data["values"], dtype=float),
        first_order=table(data["first_order"]), total=table(data["total"]),
        second_order=table(data["second_order"], pairs=True),
        conditions=dict(data.get("conditions", {})), settings=dict(data.get("settings", {})),
        conf_level=float(data.get("conf_level", CONF_LEVEL)),
        num_resamples=int(data.get("num_resamples", NUM_RESAMPLES)))


#: A model: ``evaluate(points, context)`` maps an ``(m, D)`` block of sample points (SI) to
#: an ``(m, n_outputs)`` block of outputs; a module-level function (it is pickled).
Evaluate = Callable[[NDArray[np.float64], Any], NDArray[np.float64]]


def _chunks(n_rows: int, chunk_size: int) -> list[slice]:
    return [slice(i, min(i + chunk_size, n_rows)) for i in range(0, n_rows, chunk_size)]


def run_study(model: str, inputs: Sequence[SobolInput], outputs: Sequence[str],
              units: Sequence[str], evaluate: Evaluate, context: object, n: int, seed: int,
              *, executor: object = None, chunk_size: int = 16,
              progress: Callable[[int], None] | None = None,
              conditions: Mapping[str, object] | None = None,
              settings: Mapping[str, object] | None = None,
              second_order: bool = True,
              previous: SensitivityResult | None = None) -> SensitivityResult:
    """Run a Sobol' study: sample, evaluate the model in chunks on ``executor``, analyze.

    Parameters
    ----------
    model : str
        The study's name.
    inputs : sequence of SobolInput
        The uncertain inputs (at least 2).
    outputs, units : sequence of str
        The outputs' names and units (the columns ``evaluate`` returns).
    evaluate : callable
        ``evaluate(points, context) -> (m, len(outputs))`` array; module-level.
    context : object
        Passed to each call of ``evaluate`` (picklable: the fixed model).
    n : int
        Base sample size, a power of 2: ``n (2D + 2)`` model runs.
    seed : int
        Seed of the sample's scrambling and of the bootstrap (>= 0).
    executor : concurrent.futures.Executor, optional
        Where the chunks run (``None``: in this process).
    chunk_size : int, default 16
        Sample points per chunk (>= 1).
    progress : callable, optional
        Called with the number of sample points of each chunk as it finishes.
    conditions, settings : mapping, optional
        Recorded in the result (the model's fixed choices, the study's constants).
    second_order : bool, default True
        Also estimate the second-order indices (``n (2D + 2)`` runs instead of
        ``n (D + 2)``).
    previous : SensitivityResult, optional
        The same study with a smaller ``n``: its values are reused and only the new points
        are computed (the sample of ``n`` base points begins with that of any smaller power
        of 2, so the result equals a study run from scratch).

    Returns
    -------
    SensitivityResult

    Examples
    --------
    Growing a study reuses the smaller one and gives the same values as a fresh run:

    >>> from gyrolib import rsf
    >>> small = rsf.sensitivity(8, seed=1)
    >>> grown = rsf.sensitivity(32, seed=1, previous=small)
    >>> bool((grown.values == rsf.sensitivity(32, seed=1).values).all())
    True
    """
    model = v.check_str("model", model)
    inputs = tuple(inputs)
    if len(inputs) < 2 or not all(isinstance(x, SobolInput) for x in inputs):
        raise TypeError("inputs must be a sequence of at least 2 SobolInput")
    names = [x.name for x in inputs]
    if len(set(names)) != len(names):
        raise ValueError(f"inputs must have distinct names; got {names}")
    outputs, units = tuple(outputs), tuple(units)
    n = _check_n(n)
    seed = v.check_int("seed", seed, 0)
    executor = check_executor(executor)
    chunk_size = v.check_int("chunk_size", chunk_size, 1)
    if progress is not None and not callable(progress):
        raise TypeError("progress must be callable or None")
    second_order = v.check_bool("second_order", second_order)
    conditions, settings = dict(conditions or {}), dict(settings or {})
    pts = _points(inputs, unit_sample(len(inputs), n, seed, second_order))
    done = np.empty((0, len(outputs)))
    if previous is not None:
        done = _reusable(previous, model, inputs, outputs, n, seed, second_order, conditions,
                         settings)
    chunks = _chunks(len(pts) - len(done), chunk_size)
    report = None if progress is None else (lambda i: progress(chunks[i].stop
                                                               - chunks[i].start))
    new = pts[len(done):]
    blocks = map_ordered(evaluate, [(new[c], context) for c in chunks], executor, report)
    values = np.concatenate([done, *(np.asarray(b, dtype=float).reshape(-1, len(outputs))
                                     for b in blocks)])
    if not np.all(np.isfinite(values)):
        raise ValueError("the model returned non-finite outputs on the sample")
    indices = [analyze(names, values[:, k], seed, second_order) for k in range(len(outputs))]
    return SensitivityResult(
        model=model, inputs=inputs, outputs=outputs, units=units, n=n, seed=seed,
        values=values, first_order={o: s["S1"] for o, s in zip(outputs, indices)},
        total={o: s["ST"] for o, s in zip(outputs, indices)},
        second_order={o: s["S2"] for o, s in zip(outputs, indices)},
        conditions=conditions, settings=settings)


def _reusable(previous: object, model: str, inputs: tuple[SobolInput, ...],
              outputs: tuple[str, ...], n: int, seed: int, second_order: bool,
              conditions: dict[str, object], settings: dict[str, object]) -> np.ndarray:
    """The values of ``previous`` if it is the same study with ``n`` no larger."""
    prev = v.check_instance("previous", previous, SensitivityResult)
    same = (prev.model == model and prev.inputs == inputs and prev.outputs == outputs
            and prev.seed == seed and prev.second_order_computed == second_order
            and dict(prev.conditions) == conditions and dict(prev.settings) == settings)
    if not same:
        raise ValueError("previous must be the same study (model, inputs and their ranges, "
                         "outputs, seed, second order, conditions and settings)")
    if prev.n > n:
        raise ValueError(f"previous must have n <= {n}; got {prev.n}")
    return prev.values


@compact_repr
@dataclass(frozen=True)
class Recheck:
    """A few sample points of a stored study computed again: their ``rows`` in the
    sample, the ``stored`` and the ``recomputed`` outputs, and the largest relative
    difference ``max_rel_diff``."""

    rows: NDArray[np.int64]
    stored: NDArray[np.float64]
    recomputed: NDArray[np.float64]

    @property
    def max_rel_diff(self) -> float:
        """max |recomputed − stored| / |stored| over the rows and outputs."""
        scale = np.maximum(np.abs(self.stored), np.finfo(float).tiny)
        return float(np.max(np.abs(self.recomputed - self.stored) / scale))


def recheck(result: SensitivityResult, evaluate: Evaluate, context: object, k: int = 5,
            seed: int = 0) -> Recheck:
    """Compute ``k`` sample points of a stored study again (rows drawn with ``seed``), so
    that a results file cannot go stale silently.

    Parameters
    ----------
    result : SensitivityResult
        The stored study.
    evaluate, context
        Its model, as given to :func:`run_study`.
    k : int, default 5
        Number of points (>= 1).
    seed : int, default 0
        Seed of the choice of rows.

    Returns
    -------
    Recheck
    """
    v.check_instance("result", result, SensitivityResult)
    k = v.check_int("k", k, 1)
    seed = v.check_int("seed", seed, 0)
    pts = result.points()
    rows = np.sort(np.random.default_rng(seed).choice(len(pts), size=min(k, len(pts)),
                                                      replace=False))
    again = np.asarray(evaluate(pts[rows], context), dtype=float).reshape(len(rows), -1)
    return Recheck(rows=rows, stored=result.values[rows], recomputed=again)


# Elasticities at the defaults -----------------------------------------------------------------
@compact_repr
@dataclass(frozen=True)
class Elasticities:
    """Local elasticities ``∂ ln y / ∂ ln x`` of a model's outputs at its defaults
    (:func:`elasticities`): ``values[i, j]`` for output ``outputs[i]`` and input
    ``inputs[j]``; ``nominal`` the inputs' values and ``at`` the outputs there; ``rel_step``
    the relative step of the central differences.

    An elasticity says how much an output moves per relative change of an input, whatever the
    input's range; a Sobol' index says how much of the output's variance an input's range
    causes.  Side by side they show a ranking that the range rule sets.
    """

    inputs: tuple[str, ...]
    outputs: tuple[str, ...]
    nominal: NDArray[np.float64]
    at: NDArray[np.float64]
    values: NDArray[np.float64]
    rel_step: float

    def __post_init__(self) -> None:
        v.check_ndarray("nominal", self.nominal, shape=(len(self.inputs),))
        v.check_ndarray("at", self.at, shape=(len(self.outputs),))
        v.check_ndarray("values", self.values, shape=(len(self.outputs), len(self.inputs)))

    def of(self, output: str, name: str) -> float:
        """The elasticity of ``output`` with respect to the input ``name``.

        Examples
        --------
        >>> e = elasticities({"a": 2.0, "b": 3.0}, lambda a, b: (a * b**2,), ("y",))
        >>> f"{e.of('y', 'b'):.4f}"
        '2.0000'
        """
        if output not in self.outputs:
            raise ValueError(f"output must be one of {self.outputs}; got {output!r}")
        if name not in self.inputs:
            raise ValueError(f"name must be one of {self.inputs}; got {name!r}")
        return float(self.values[self.outputs.index(output), self.inputs.index(name)])


def elasticities(nominal: Mapping[str, float], evaluate: Callable[..., Sequence[float]],
                 outputs: Sequence[str], rel_step: float = 0.01) -> Elasticities:
    """Elasticities ``∂ ln y / ∂ ln x`` at ``nominal`` by central differences in ``ln x``.

    Parameters
    ----------
    nominal : mapping of str to float
        The inputs at their defaults (each > 0).
    evaluate : callable
        ``evaluate(**inputs)`` → the outputs (each > 0 at the defaults), in the order of
        ``outputs``.
    outputs : sequence of str
        The outputs' names.
    rel_step : float, default 0.01
        Relative step (in (0, 0.5)): each input at ``x (1 ± rel_step)``, the others at their
        defaults.

    Returns
    -------
    Elasticities

    Examples
    --------
    >>> e = elasticities({"a": 2.0, "b": 3.0}, lambda a, b: (a * b**2, a / b), ("y", "z"))
    >>> [f"{x:.3f}" for x in e.values.ravel()]
    ['1.000', '2.000', '1.000', '-1.000']
    """
    if not isinstance(nominal, Mapping) or not nominal:
        raise TypeError("nominal must be a non-empty mapping of input names to values")
    names = tuple(nominal)
    x0 = np.array([v.check_positive(f"nominal[{n!r}]", nominal[n]) for n in names])
    if not callable(evaluate):
        raise TypeError("evaluate must be callable")
    outputs = tuple(outputs)
    if not outputs or not all(isinstance(o, str) for o in outputs):
        raise TypeError("outputs must be a non-empty sequence of str")
    h = v.check_in_range("rel_step", rel_step, 0.0, 0.5, low_open=True, high_open=True)

    def run(x: NDArray[np.float64]) -> NDArray[np.float64]:
        y = np.asarray(evaluate(**dict(zip(names, map(float, x), strict=True))), dtype=float)
        if y.shape != (len(outputs),):
            raise ValueError(f"evaluate must return {len(outputs)} outputs; got shape {y.shape}")
        return y

    y0 = run(x0)
    if not np.all(y0 > 0):
        raise ValueError(f"the outputs must be > 0 at the defaults (logarithms); got {y0}")
    out = np.empty((len(outputs), len(names)))
    dlog = math.log1p(h) - math.log1p(-h)
    for j in range(len(names)):
        up, down = x0.copy(), x0.copy()
        up[j] *= 1.0 + h
        down[j] *= 1.0 - h
        out[:, j] = (np.log(run(up)) - np.log(run(down))) / dlog
    return Elasticities(inputs=names, outputs=outputs, nominal=x0, at=y0, values=out,
                        rel_step=h)
