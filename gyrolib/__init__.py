"""gyrolib: the library behind the reproduction of papers GC and RSF.

Modules, one per concept:

* :mod:`gyrolib.units` – the papers' units, to and from SI;
* further modules are added by the chapters that need them (the gyrocompass model, shaping
  filters, Kalman filtering, the roll-correction model).
"""

__version__ = "0.1.0"
