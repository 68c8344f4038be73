"""Optional dependencies: imported where they are used, with an error naming the extra.

``pip install gyrolib`` brings what the library needs at run time; the sensitivity studies
(SALib, which brings pandas), Dask, the book (myst-nb, jupyter-book) and the Allan view's
reference (allantools) are extras of ``pyproject.toml``.
"""

from __future__ import annotations

import importlib.util
from collections.abc import Iterator
from contextlib import contextmanager

__all__ = ["optional"]


def _installed(package: str) -> bool:
    try:
        return importlib.util.find_spec(package) is not None
    except (ImportError, ValueError):
        return False


@contextmanager
def optional(package: str, extra: str, what: str) -> Iterator[None]:
    """The imports inside the block: if ``package`` is not installed, a
    :class:`ModuleNotFoundError` saying that ``what`` needs it and which extra of gyrolib
    installs it.

    Anything else missing (pandas under SALib, a submodule of an installed package) is
    raised as it is: only ``package`` is an extra of gyrolib.

    Examples
    --------
    >>> with optional("math", "none", "this example"):
    ...     import math
    >>> try:
    ...     with optional("no_such_package_xyz", "demo", "gyrolib.demo"):
    ...         import no_such_package_xyz.sub
    ... except ModuleNotFoundError as exc:
    ...     print(exc)
    gyrolib.demo needs no_such_package_xyz, an optional dependency: pip install 'gyrolib[demo]'
    """
    try:
        yield
    except ModuleNotFoundError as exc:
        if (exc.name is None or exc.name.split(".")[0] != package
                or _installed(package)):
            raise
        raise ModuleNotFoundError(f"{what} needs {package}, an optional dependency: "
                                  f"pip install 'gyrolib[{extra}]'", name=exc.name) from None
