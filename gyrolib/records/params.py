"""Parameter files (TOML) for the calibration commands: the paper's values by default, any
field overridden by name, in SI.

* GC: top-level keys are fields of :class:`gyrolib.gc.GyrocompassParams`
  (e.g. ``C_as = 2e-13``, ``dt = 0.001``), and ``latitude`` (degrees north, in (0, 90); the
  one key not in SI): ``Omega_h``, ``Omega_v`` from the Earth's rate
  (:meth:`~gyrolib.gc.GyrocompassParams.at_latitude`), not with those two keys;
* RSF: tables ``[sins]``, ``[gs]``, ``[encoder]`` whose keys are fields of
  :class:`gyrolib.rsf.SinsGyroModel`, :class:`~gyrolib.rsf.GsModel`,
  :class:`~gyrolib.rsf.EncoderModel` (``motor_rate_max = inf`` is TOML's infinity).

An unknown key, a value of the wrong type or out of range raises
:class:`~gyrolib.records.RecordError` naming the file and the key.
"""

from __future__ import annotations

import dataclasses
import math
import os
import tomllib
from pathlib import Path

from gyrolib.gc.model.params import GyrocompassParams
from gyrolib.records.errors import RecordError

__all__ = ["gc_params_from_toml", "load_toml", "rsf_config_from_toml"]


def load_toml(path: object) -> dict:
    """The TOML file ``path`` as a dict (:class:`RecordError` if missing or not TOML)."""
    if not isinstance(path, str | os.PathLike):
        raise TypeError(f"path must be a str or path; got {type(path).__name__}")
    label = str(path)
    try:
        with open(Path(path), "rb") as fh:
            return tomllib.load(fh)
    except FileNotFoundError:
        raise RecordError(label, "no such file") from None
    except IsADirectoryError:
        raise RecordError(label, "is a directory, not a TOML file") from None
    except UnicodeDecodeError:
        raise RecordError(label, "not a TOML text file (cannot decode it as UTF-8)") from None
    except tomllib.TOMLDecodeError as exc:
        raise RecordError(label, f"not valid TOML: {exc}") from None


def _replace(label: str, obj: object, values: dict, where: str = "") -> object:
    """``dataclasses.replace(obj, **values)`` with errors naming the file and key."""
    names = [f.name for f in dataclasses.fields(obj)]
    for key, val in values.items():
        if key not in names:
            raise RecordError(label, f"unknown field {where + key!r}: expected one of "
                              f"{', '.join(names)}")
        if isinstance(val, dict | list):
            raise RecordError(label, f"field {where + key!r} must be a number or string; got "
                              f"a {type(val).__name__}")
    try:
        return dataclasses.replace(obj, **values)
    except (TypeError, ValueError) as exc:
        raise RecordError(label, f"bad value: {exc}") from None


def gc_params_from_toml(path: object | None = None, base: object | None = None):
    """:class:`gyrolib.gc.GyrocompassParams` with the fields of the TOML file ``path``
    (``None``: the paper's values) applied over ``base`` (default: the paper's values)."""
    base = GyrocompassParams() if base is None else base
    if path is None:
        return base
    label = str(path)
    values = dict(load_toml(path))
    if "latitude" in values:
        lat = values.pop("latitude")
        if {"Omega_h", "Omega_v"} & set(values):
            raise RecordError(label, "give either 'latitude' or Omega_h/Omega_v, not both")
        if isinstance(lat, bool) or not isinstance(lat, int | float) or not 0.0 < lat < 90.0:
            raise RecordError(label, f"field 'latitude' must be degrees north in (0, 90) "
                              f"(paper GC's model needs both Earth-rate components "
                              f"positive); got {lat!r}")
        earth = GyrocompassParams.at_latitude(math.radians(lat))
        values = {"Omega_h": earth.Omega_h, "Omega_v": earth.Omega_v, **values}
    return _replace(label, base, values)


_RSF_TABLES = ("sins", "gs", "encoder")


def rsf_config_from_toml(path: object | None = None, base: object | None = None):
    """:class:`gyrolib.rsf.SimulationConfig` whose ``sins``, ``gs`` and ``encoder`` models
    take the fields of the TOML tables ``[sins]``, ``[gs]``, ``[encoder]``."""
    from gyrolib.rsf.simulation import SimulationConfig  # not loaded by a GC run

    cfg = SimulationConfig() if base is None else base
    if path is None:
        return cfg
    label = str(path)
    doc = load_toml(path)
    parts = {}
    for key, val in doc.items():
        if key not in _RSF_TABLES or not isinstance(val, dict):
            raise RecordError(label, f"unknown entry {key!r}: expected the tables "
                              f"[{'], ['.join(_RSF_TABLES)}] of the RSF sensor models")
        parts[key] = _replace(label, getattr(cfg, key), val, where=f"{key}.")
    return dataclasses.replace(cfg, **parts)
