"""The compact ``repr`` of result objects: ``print(result)`` shows arrays
by shape and nested parameters by name, in a few lines, never the arrays' values."""

import dataclasses
import importlib
import inspect
import pkgutil

import numpy as np
import pytest

import gyrolib
from gyrolib import gc, rsf
from gyrolib._repr import compact_repr

P = gc.GyrocompassParams()


def _array_dataclasses() -> list[type]:
    """Every dataclass of gyrolib with a field annotated as an array."""
    found = []
    for info in pkgutil.walk_packages(gyrolib.__path__, "gyrolib."):
        mod = importlib.import_module(info.name)
        for obj in vars(mod).values():
            if (inspect.isclass(obj) and dataclasses.is_dataclass(obj)
                    and obj.__module__ == mod.__name__
                    and any("NDArray" in str(f.type) or "ndarray" in str(f.type)
                            for f in dataclasses.fields(obj))):
                found.append(obj)
    return found


def _fits(text: str, max_lines: int) -> bool:
    lines = text.splitlines()
    return len(lines) <= max_lines and max(len(ln) for ln in lines) <= 100


def _dataclass_repr(obj: object) -> str:
    """What ``@dataclass`` alone prints (every field's own repr)."""
    inner = ", ".join(f"{f.name}={getattr(obj, f.name)!r}" for f in dataclasses.fields(obj))
    return f"{type(obj).__name__}({inner})"


def test_every_array_result_has_the_compact_repr():
    """A result class added later without ``@compact_repr`` fails here (more than 30 such
    classes exist, so the walk finds them)."""
    classes = _array_dataclasses()
    assert len(classes) > 30
    missing = [f"{c.__module__}.{c.__qualname__}" for c in classes
               if not getattr(c.__repr__, "compact", False)]
    assert missing == []


def test_covariance_analysis_prints_in_a_few_lines():
    """``print(gc.covariance_analysis(...))``: 7 lines of at most 100 characters, each array
    by its shape; the dataclass's own repr of the same object runs to hundreds of lines (the
    check has power)."""
    res = gc.covariance_analysis(P, 1.0)
    text = repr(res)
    assert _fits(text, 10)
    n = res.t.size
    assert f"var=<ndarray {n}x10 float64>" in text
    assert f"P_stored=<ndarray {res.t_stored.size}x10x10 float64>" in text
    assert "params=GyrocompassParams(...)" in text
    assert not _fits(_dataclass_repr(res), 10)


def test_scalars_keep_six_significant_digits():
    """A result's scalar fields read back within 5e-6 relative (6 significant digits)."""
    mc = gc.monte_carlo(P, 4, 0.1, seed=3)
    assert "seed=3" in repr(mc) and "truth_mode='nonlinear'" in repr(mc)

    @compact_repr
    @dataclasses.dataclass(frozen=True)
    class Run:
        sigma: float
        n: int
        names: tuple
        grid: np.ndarray

    run = Run(0.0011023456789, 7, ("a", "b"), np.linspace(0, 1, 5))
    text = repr(run)
    value = float(text.split("sigma=")[1].split(",")[0])
    assert value == pytest.approx(run.sigma, rel=5e-6)
    assert value != pytest.approx(run.sigma, rel=1e-8)   # rounded, not the full float
    assert "n=7" in text and "names=('a', 'b')" in text and "grid=<ndarray 5 float64>" in text
    assert len(text.splitlines()) == 1


def test_rsf_results_and_long_tuples():
    """RSF's Table 2 prints its arrays by shape; a tuple longer than 4 by its length."""
    text = repr(rsf.table2())
    assert _fits(text, 8) and "<ndarray 3 float64>" in text

    @compact_repr
    @dataclasses.dataclass(frozen=True)
    class Many:
        cases: tuple

    assert repr(Many(tuple(range(10)))) == "Many(cases=<tuple of 10>)"


def test_compact_repr_rejects_a_plain_class():
    with pytest.raises(TypeError, match="compact_repr decorates a dataclass"):
        compact_repr(int)
