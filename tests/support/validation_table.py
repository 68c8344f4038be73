"""Shared parts of the bad-input tables (``test_validation_*.py``), one table per subpackage.

The reference here is the contract of CONTRIBUTING.md: bad input raises ``ValueError`` or
``TypeError`` whose message starts with the name of the offending parameter (and, where the
range is a number, states it), never an AttributeError/IndexError/LinAlgError or a numpy
broadcasting error from deep inside, a silent NaN or a wrong figure.

* ``test_bad_input_is_rejected_by_name``: one table, a bad value per parameter kind (type,
  shape, finiteness, physical range, unknown choice) for every public function, class and
  method;
* ``test_table_covers_every_public_callable``: the table's coverage, computed from each
  module's ``__all__`` and the public methods of its classes;
* hypothesis properties over continuous ranges (any non-positive step, duration or count,
  any scale-factor error outside (−1, 1), …) and a check that valid input is not affected.
"""

from __future__ import annotations

import dataclasses
import functools
import inspect
import math
import re

import numpy as np
import pytest
import sympy as sp  # noqa: F401 - used by the tables
from hypothesis import settings
from hypothesis import strategies as st

from gyrolib import (  # noqa: F401
    cli,
    filtering,
    gc,
    rsf,
    units,
)
from gyrolib.book import ledger, report  # noqa: F401
from gyrolib.book.ledger import gc as lgc  # noqa: F401
from gyrolib.book.ledger import rsf as lrsf  # noqa: F401
from gyrolib.gc.model import symbolic  # noqa: F401

NAN, INF = math.nan, math.inf
P = gc.GyrocompassParams()
T5 = np.linspace(0.0, 1.0, 5)
VIB = gc.vibration_filter(1.0, 0.5, 1.0)
I10 = np.eye(10)
ENC = rsf.EncoderModel()


# Small valid objects, built on first use ---------------------------------------------------------
@functools.cache
def disc() -> gc.GCDiscretization:
    return gc.discretize(P, 0.01)  # 10 steps


def model() -> filtering.AffineDiscreteModel:
    return disc().model


def gains() -> np.ndarray:
    return np.zeros((model().n_steps, 3, 10))


def qd() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    return model().Qd0, model().QdA, model().QdB


@functools.cache
def cov() -> gc.CovarianceAnalysis:
    return gc.covariance_analysis(P, 0.01)


@functools.cache
def mc() -> gc.MonteCarloResult:
    return gc.monte_carlo(P, 2, 0.01, seed=1)


@functools.cache
def cfg() -> rsf.SimulationConfig:
    return rsf.SimulationConfig(duration=2.0, n_runs=2)


@functools.cache
def rec() -> rsf.SensorRecord:
    return rsf.simulate_flight(cfg(), 0)


@functools.cache
def corr() -> rsf.CorrectionRun:
    return rsf.run_correction(rec(), 1.0)


def item(**kw) -> ledger.LedgerItem:
    args = {"id": "gc.x", "paper": "GC", "location": "Fig. 3", "quantity": "q", "unit": "m",
            "paper_value": 1.0, "reproduced_value": 1.0, "status": "reproduced", "note": "n",
            "chapter": "chapters/gc_model", "kind": "printed number", "evidence": "e"} | kw
    return ledger.LedgerItem(**args)


def replace(obj, **kw):
    return dataclasses.replace(obj, **kw)



class Table:
    """A table of bad-input cases: ``case(target, call, exc, name, allowed)`` registers that
    ``call()`` must raise ``exc`` with a message that starts with ``name`` (then, if given,
    states ``allowed``); ``target`` is the public callable exercised."""

    def __init__(self) -> None:
        self.cases: list = []
        self.covered: set[str] = set()

    def case(self, target: str, call, exc: type[Exception], name: str,
             allowed: str = "") -> None:
        pattern = "^" + re.escape(name) + (r"\b" if re.match(r".*\w$", name) else "")
        if allowed:
            pattern += ".*" + allowed
        self.covered.add(target)
        self.cases.append(pytest.param(call, exc, pattern, id=f"{target}[{len(self.cases)}]"))

    def check_coverage(self, modules: dict, exempt: dict[str, str]) -> None:
        """Every public callable of ``modules`` (from ``__all__`` and the public methods of
        its classes) has a case, except those in ``exempt`` (name -> why)."""
        public = public_callables(modules)
        missing = public - self.covered - set(exempt)
        assert not missing, f"no bad-input case for: {sorted(missing)}"
        assert not self.covered - public, "the table names a callable that is not public"


def run_case(call, exc, pattern) -> None:
    with pytest.raises(exc, match=pattern) as info:
        call()
    assert type(info.value) is exc  # not a subclass such as numpy's LinAlgError


POS = r"> 0"
NONNEG = r">= 0"
FINITE = r"finite"
NOT_POSITIVE = st.one_of(st.floats(max_value=0.0, allow_nan=False),
                         st.sampled_from([NAN, -INF, INF]))
SETTINGS = settings(max_examples=40, deadline=None)


def _takes_input(fn) -> bool:
    params = list(inspect.signature(fn).parameters.values())
    return bool(params[1:] if params and params[0].name == "self" else params)


def public_callables(modules: dict) -> set[str]:
    out = set()
    for mod_name, mod in modules.items():
        for name in mod.__all__:
            obj = getattr(mod, name)
            if inspect.isclass(obj):
                out.add(f"{mod_name}.{name}")
                for meth_name, meth in vars(obj).items():
                    if isinstance(meth, classmethod | staticmethod):
                        meth = meth.__func__
                    if (not meth_name.startswith("_") and inspect.isfunction(meth)
                            and _takes_input(meth)):
                        out.add(f"{mod_name}.{name}.{meth_name}")
            elif inspect.isfunction(obj) and _takes_input(obj):
                out.add(f"{mod_name}.{name}")
    return out
