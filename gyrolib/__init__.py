"""gyrolib: the library behind the reproduction of papers GC and RSF.

Subpackages, one per subject:

* :mod:`gyrolib.gc` — paper GC (gyrocompass drift calibration with a Kalman filter);
* :mod:`gyrolib.rsf` — paper RSF (roll-gyro scale-factor correction);
* :mod:`gyrolib.filtering` — paper-agnostic discretization and Kalman filtering;
* :mod:`gyrolib.units` — the papers' units, to and from SI;
* :mod:`gyrolib.stats` — statistics of random runs with their 95 % intervals;
* :mod:`gyrolib.book` — code only the book uses (prose formats, the reproduction ledger).

Use as ``from gyrolib import gc, rsf, filtering``.
"""


def _version() -> str:
    """The installed distribution's version; from ``pyproject.toml`` when not installed."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("gyrolib")
    except PackageNotFoundError:  # a source tree on sys.path without `pip install -e .`
        import re
        from pathlib import Path

        text = (Path(__file__).resolve().parents[1] / "pyproject.toml").read_text("utf-8")
        found = re.search(r'^version\s*=\s*"([^"]+)"', text, re.MULTILINE)
        return found.group(1) if found else "0+unknown"


__version__: str = _version()
