"""The walk of ``params`` through gc.covariance_analysis enters gyrolib._validation
once, at the door.  Every check of the module is wrapped to count its calls by the name it
checks (its first argument)."""

from __future__ import annotations

import collections
import dataclasses
import inspect
import sys

import pytest

from gyrolib import _validation, gc
from gyrolib.gc.model.discretization import kept_discretization

FIELDS = {f.name for f in dataclasses.fields(gc.GyrocompassParams)}


@pytest.fixture
def counted(monkeypatch):
    calls: collections.Counter = collections.Counter()
    callers: dict[str, list[str]] = collections.defaultdict(list)
    depth = [0]
    for name, fn in inspect.getmembers(_validation, inspect.isfunction):
        if not name.startswith("check_"):
            continue

        def wrapper(*args, _fn=fn, **kwargs):
            if args and isinstance(args[0], str) and depth[0] == 0:   # entries, not nested
                calls[args[0]] += 1
                frame = sys._getframe(1)
                while frame.f_code.co_name == "check_params":   # the shared helper
                    frame = frame.f_back
                callers[args[0]].append(f"{frame.f_code.co_filename.split('gyrolib/')[-1]}:"
                                        f"{frame.f_code.co_name}")
            depth[0] += 1
            try:
                return _fn(*args, **kwargs)
            finally:
                depth[0] -= 1

        monkeypatch.setattr(_validation, name, wrapper)
    return calls, callers


def test_params_fields_are_checked_once_at_construction(counted):
    """Building GyrocompassParams checks each field once (the shaping-filter fields through
    the filters it builds); nothing more."""
    calls, callers = counted
    gc.GyrocompassParams()
    for name in ("alpha1", "xi1", "sigma1_sq", "alpha2", "xi2", "sigma2_sq", "C_as", "dt"):
        assert calls[name] == 1, (name, callers[name])


def test_covariance_analysis_walk_enters_validation_once_at_the_door(counted):
    """After construction, covariance_analysis checks params once at its door and never one
    of its fields again (a walk that rechecked them would count each shaping-filter field 8
    more times).  The other three checks of the params object are the records' own doors
    (ContinuousModel, GCDiscretization, CovarianceAnalysis: a record built by hand with
    params=None must fail by name)."""
    p = gc.GyrocompassParams()
    calls, callers = counted
    # the continuous model is kept per parameters and its discretization per model: an
    # earlier test in this worker may hold them, whose record doors would then not be
    # entered here
    kept_discretization.cache_clear()
    calls.clear()
    callers.clear()
    gc.covariance_analysis(p, 0.01)
    doors = [c for c in callers["params"] if not c.endswith("__post_init__")]
    assert doors == ["gc/analysis/covariance.py:covariance_analysis"], callers["params"]
    records = sorted(c for c in callers["params"] if c.endswith("__post_init__"))
    assert len(records) == 3, callers["params"]
    refields = {name: [c for c in callers[name] if c.startswith("gc/")] for name in FIELDS}
    assert not any(refields.values()), refields
    # the paper-agnostic filtering code never sees params: its doors check its own arguments
    # (dt of the Van Loan step, H the discrete model's measurement matrix, not the gyro's H)
    generic = {name: callers[name] for name in FIELDS if callers[name]}
    assert set(generic) <= {"dt", "H"}, generic
