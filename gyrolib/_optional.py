"""Optional dependencies: imported where they are used, with an error naming the extra.

``pip install gyrolib`` brings what the library needs at run time; the sensitivity studies
(SALib, which brings pandas), Dask, the book (myst-nb, jupyter-book) and the Allan view's
reference (allantools) are extras of ``pyproject.toml``.
"""

from __future__ import annotations

import importlib
import importlib.util
from types import ModuleType

__all__ = ["require"]


def _installed(top: str) -> bool:
    try:
        return importlib.util.find_spec(top) is not None
    except (ImportError, ValueError):
        return False


def require(module: str, extra: str, what: str) -> ModuleType:
    """Import ``module``, or raise :class:`ModuleNotFoundError` saying that ``what`` needs
    it and which extra of gyrolib installs it.

    Anything else missing (pandas under SALib, a submodule of an installed package) is
    raised as it is: only the package asked for is an extra of gyrolib.

    Examples
    --------
    >>> require("math", "none", "this example").sqrt(4.0)
    2.0
    >>> try:
    ...     require("no_such_package_xyz.sub", "demo", "gyrolib.demo")
    ... except ModuleNotFoundError as exc:
    ...     print(exc)
    gyrolib.demo needs no_such_package_xyz, an optional dependency: pip install 'gyrolib[demo]'
    """
    try:
        return importlib.import_module(module)
    except ModuleNotFoundError as exc:
        top = module.split(".")[0]
        if exc.name is None or exc.name.split(".")[0] != top or _installed(top):
            raise
        raise ModuleNotFoundError(f"{what} needs {top}, an optional dependency: "
                                  f"pip install 'gyrolib[{extra}]'", name=exc.name) from None
