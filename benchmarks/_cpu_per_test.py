"""pytest plugin for ``bench_budget.py``: the CPU-s of each test's set-up, call and tear-down,
for the process tree (this process and every live process below it, with the children each
has reaped), written as JSON to ``$GYROLIB_CPU_PER_TEST`` at the end of the session.

Loaded with ``-p _cpu_per_test`` (``benchmarks/`` on ``PYTHONPATH``).  A child that ends
between two readings counts once its parent reaps it; one re-parented to init is lost (none
of the measured tests leaves one: the browser, the kernels and nbconvert are reaped).
"""

from __future__ import annotations

import json
import os

import psutil
import pytest

_RESULTS: dict[str, dict[str, float]] = {}


def tree_cpu() -> float:
    """CPU-s (user + system, with reaped children) of this process and its live descendants."""
    me = psutil.Process()
    total = 0.0
    for p in [me, *me.children(recursive=True)]:
        try:
            t = p.cpu_times()
        except psutil.Error:
            continue
        total += t.user + t.system + t.children_user + t.children_system
    return total


def _phase(item: pytest.Item, name: str):
    t0 = tree_cpu()
    yield
    row = _RESULTS.setdefault(item.nodeid, {})
    row[name] = round(tree_cpu() - t0, 3)


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_setup(item):
    yield from _phase(item, "setup")


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_call(item):
    yield from _phase(item, "call")


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_teardown(item):
    yield from _phase(item, "teardown")


def pytest_runtest_logreport(report):
    if report.when == "call" or (report.when == "setup" and report.outcome != "passed"):
        _RESULTS.setdefault(report.nodeid, {})["outcome"] = report.outcome


def pytest_sessionfinish(session):
    path = os.environ.get("GYROLIB_CPU_PER_TEST")
    if path:
        with open(path, "w", encoding="utf-8") as f:
            json.dump(_RESULTS, f, indent=1)
