"""gyrolib: the library behind the reproduction of papers GC and RSF.

Subpackages, one per subject:

* :mod:`gyrolib.gc` — paper GC (gyrocompass drift calibration with a Kalman filter);
* :mod:`gyrolib.rsf` — paper RSF (roll-gyro scale-factor correction);
* :mod:`gyrolib.filtering` — paper-agnostic discretization and Kalman filtering;
* :mod:`gyrolib.units` — the papers' units, to and from SI;
* :mod:`gyrolib.book` — code only the book uses (prose formats, the reproduction ledger).

Use as ``from gyrolib import gc, rsf, filtering``.
"""

__version__ = "0.1.0"
