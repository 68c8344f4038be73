"""Running independent pieces of work on a caller's ``concurrent.futures.Executor``.

The library never starts a pool of processes or a cluster of its own: a parallel function
takes ``executor=`` (any :class:`concurrent.futures.Executor`: a ``ProcessPoolExecutor``, or
the executor of a Dask cluster, ``dask.distributed.Client(...).get_executor()``), and
``None`` runs the same pieces in this process, one after another.  One exception, stated
where it applies: a numba kernel that releases the GIL may run its independent blocks on
this process's own threads (a standard ``concurrent.futures.ThreadPoolExecutor`` sized to
the CPUs the process may use, opened and closed inside the call), as
:func:`gyrolib.gc.monte_carlo` does with ``executor=None``; its numbers are the same as with
any executor or one thread.  The pieces are put back in their order, so a
result never depends on the executor, on the number of workers or on which piece finished
first.
"""

from __future__ import annotations

import concurrent.futures as cf
from collections.abc import Callable, Iterable, Sequence
from typing import Any

__all__ = ["check_executor", "map_ordered"]


def check_executor(executor: object) -> cf.Executor | None:
    """``executor`` as given if it is ``None`` or a :class:`concurrent.futures.Executor`.

    Examples
    --------
    >>> from concurrent.futures import ThreadPoolExecutor
    >>> check_executor(None) is None
    True
    >>> check_executor("dask")
    Traceback (most recent call last):
    ...
    TypeError: executor must be a concurrent.futures.Executor or None; got str
    """
    if executor is not None and not isinstance(executor, cf.Executor):
        raise TypeError("executor must be a concurrent.futures.Executor or None; got "
                        f"{type(executor).__name__}")
    return executor


def map_ordered(fn: Callable[..., Any], args: Iterable[tuple[Any, ...]],
                executor: cf.Executor | None = None,
                progress: Callable[[int], None] | None = None) -> list[Any]:
    """``[fn(*a) for a in args]``, each call on ``executor`` (``None``: here, in order).

    Parameters
    ----------
    fn : callable
        A module-level function (it is pickled for a process or a cluster).
    args : iterable of tuple
        The positional arguments of each call.
    executor : concurrent.futures.Executor, optional
        Where the calls run; ``None`` runs them in this process.
    progress : callable, optional
        Called with the index of each call as it finishes (in completion order).

    Returns
    -------
    list
        The results, in the order of ``args`` whatever the order of completion.

    Examples
    --------
    >>> from concurrent.futures import ThreadPoolExecutor
    >>> with ThreadPoolExecutor(2) as ex:
    ...     map_ordered(pow, [(2, 3), (3, 2)], ex)
    [8, 9]
    """
    executor = check_executor(executor)
    calls: Sequence[tuple[Any, ...]] = list(args)
    if executor is None:
        out = []
        for i, a in enumerate(calls):
            out.append(fn(*a))
            if progress is not None:
                progress(i)
        return out
    futures = {executor.submit(fn, *a): i for i, a in enumerate(calls)}
    results: list[Any] = [None] * len(calls)
    try:
        for fut in cf.as_completed(futures):
            i = futures[fut]
            results[i] = fut.result()
            if progress is not None:
                progress(i)
    except BaseException:
        for fut in futures:
            fut.cancel()
        raise
    return results
