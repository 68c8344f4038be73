"""A pytest plugin for ``bench_budget.py``: import, before any test, the modules that every
worker of the test command has imported by the time an issue's tests run there.

The test command runs its ~75 test files in two pytest-xdist workers, each one interpreter:
``gyrolib`` and these subpackages are imported once per worker, by whichever test comes
first, whatever the issue under measurement adds.  A test file measured in a process of its
own pays them again; a run with this plugin pays them before its tests, and so does the run
it is compared with (the start-up, or the same tests at the base), so that the difference is
the file's own cost in a worker: its tests, its fixtures, and the modules only it imports.
``bench_budget.py`` records how many of the base's test files import each module (none of
them is the issue's own), and counts what these imports cost more here than at the base
once per worker (the ``worker imports`` line).
"""

from __future__ import annotations

import importlib

#: The modules imported before the tests (each imported by many of the base's test files).
MODULES: tuple[str, ...] = ("numpy", "scipy.stats", "gyrolib", "gyrolib.units", "gyrolib.gc",
                            "gyrolib.rsf", "gyrolib.book.ledger")

for _name in MODULES:
    importlib.import_module(_name)
