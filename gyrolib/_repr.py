"""A compact ``repr`` for result objects: arrays by shape, nested objects by name.

The ``repr`` that :func:`dataclasses.dataclass` writes prints every array in full, so
``print(gc.covariance_analysis(...))`` filled about a hundred lines.  :func:`compact_repr`
replaces it on a result class (one decorator line above ``@dataclass``): scalars as numbers
(6 significant digits), strings as they are (shortened past 40 characters), arrays as
``<ndarray 1001x10 float64>``, nested dataclasses (parameters, other results) as
``GyrocompassParams(...)``, long tuples, lists and dicts by their length; on one line when it
fits in 100 characters, else one field per line.
"""

from __future__ import annotations

import dataclasses
from typing import TypeVar

import numpy as np

__all__ = ["compact_repr"]

T = TypeVar("T", bound=type)

#: Longest one-line repr; past it, one field per line.
_WIDTH = 100

#: Longest string, tuple or list shown in full.
_MAX_STR = 40
_MAX_ITEMS = 4


def _short(value: object) -> str:
    """One field's value in a few characters."""
    if isinstance(value, np.ndarray):
        if value.ndim == 0:
            return _short(value.item())
        shape = "x".join(str(d) for d in value.shape)
        return f"<ndarray {shape} {value.dtype}>"
    if isinstance(value, bool | np.bool_):
        return repr(bool(value))
    if isinstance(value, int | np.integer):
        return repr(int(value))
    if isinstance(value, float | np.floating):
        return f"{float(value):.6g}"
    if isinstance(value, complex | np.complexfloating):
        return f"{complex(value):.6g}"
    if isinstance(value, str):
        return repr(value if len(value) <= _MAX_STR else value[:_MAX_STR - 3] + "...")
    if value is None:
        return "None"
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return f"{type(value).__name__}(...)"
    if isinstance(value, tuple | list):
        parts = [_short(x) for x in value]
        if len(value) <= _MAX_ITEMS and all(len(s) <= 20 for s in parts):
            inner = ", ".join(parts) + ("," if isinstance(value, tuple) and len(value) == 1
                                        else "")
            return f"({inner})" if isinstance(value, tuple) else f"[{inner}]"
        return f"<{type(value).__name__} of {len(value)}>"
    if isinstance(value, dict):
        return f"<dict of {len(value)}>"
    text = repr(value)
    return text if len(text) <= _MAX_STR and "\n" not in text else f"<{type(value).__name__}>"


def _compact(self: object) -> str:
    fields = [f for f in dataclasses.fields(self) if f.repr]
    parts = [f"{f.name}={_short(getattr(self, f.name))}" for f in fields]
    name = type(self).__name__
    line = f"{name}({', '.join(parts)})"
    if len(line) <= _WIDTH:
        return line
    return f"{name}(\n" + "".join(f"    {p},\n" for p in parts) + ")"


_compact.compact = True  # marks the classes that use it (tests/helpers/test_repr.py)


def compact_repr(cls: T) -> T:
    """Class decorator: give the dataclass ``cls`` the compact ``repr`` of this module.

    Put it above ``@dataclass`` (it replaces the ``repr`` the dataclass wrote).

    Examples
    --------
    >>> import dataclasses
    >>> import numpy as np
    >>> @compact_repr
    ... @dataclasses.dataclass(frozen=True)
    ... class Run:
    ...     t: np.ndarray
    ...     P: np.ndarray
    ...     sigma: float
    ...     method: str = "fast"
    >>> Run(np.zeros(1001), np.zeros((1001, 10, 10)), 0.0011023456)
    Run(t=<ndarray 1001 float64>, P=<ndarray 1001x10x10 float64>, sigma=0.00110235, method='fast')
    """
    if not (isinstance(cls, type) and dataclasses.is_dataclass(cls)):
        raise TypeError(f"compact_repr decorates a dataclass; got {cls!r}")
    cls.__repr__ = _compact
    return cls
