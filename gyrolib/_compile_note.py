"""One line on stderr when numba first compiles a gyrolib kernel in a process.

gyrolib's kernels are compiled by numba on their first call and cached on disk
(``cache=True``); the first call after installing or changing gyrolib spends seconds
compiling, which looked like a hang.  Importing this module (every gyrolib module that
imports numba does) registers a listener on numba's ``numba:compile`` event, which fires on
a compile and not on a load from the cache: at the first compile of a function of gyrolib
in this process it writes :data:`NOTE` to ``sys.stderr``, if that is a terminal (as the
command line's progress bar, never into a pipe, a ``--json`` consumer or a notebook's
output, which must not differ between a fresh and a cached run).
"""

from __future__ import annotations

import sys

from numba.core import event

__all__ = ["NOTE"]

NOTE = ("gyrolib: compiling numba kernels on first use (once: later runs load them from "
        "the cache)")


class _FirstCompileNote(event.Listener):
    """Writes :data:`NOTE` once, at the start of the first compile of a gyrolib function."""

    def __init__(self) -> None:
        self.said = False

    def on_start(self, ev: event.Event) -> None:
        if self.said:
            return
        data = ev.data if isinstance(ev.data, dict) else {}
        func = getattr(data.get("dispatcher"), "py_func", None)
        if not getattr(func, "__module__", "").startswith("gyrolib"):
            return
        self.said = True
        stream = sys.stderr
        try:
            tty = stream is not None and stream.isatty()
        except (AttributeError, ValueError):  # closed or replaced by an object without it
            tty = False
        if tty:
            print(NOTE, file=stream, flush=True)

    def on_end(self, ev: event.Event) -> None:
        pass


event.register("numba:compile", _FirstCompileNote())   # once: a module runs once
