"""Parameter files (TOML) for the calibration commands: the paper's values by default, any
field overridden by name, in SI.

* GC: top-level keys are fields of :class:`gyrolib.gc.GyrocompassParams`
  (e.g. ``C_as = 2e-13``, ``dt = 0.001``), and ``latitude`` (degrees, north positive, in (−90, 90);
  the one key not in SI): ``Omega_h``, ``Omega_v`` from the Earth's rate
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
from typing import Any, Final

from gyrolib.gc import inputs as gc_inputs
from gyrolib.gc.model.params import GyrocompassParams
from gyrolib.records.errors import RecordError

__all__ = ["INSTRUMENT_TABLES", "LATITUDE_RANGE", "RSF_ROWS", "gc_params_from_toml",
           "instrument_notes", "load_toml", "race_inputs", "rsf_config_from_toml"]

#: What a site's latitude may be, in every message that refuses one: south of the equator
#: ``Omega_v`` is negative, on it 0 (the model carries both); at a pole ``Omega_h`` is 0 and
#: a gyrocompass has no horizontal Earth rate to sense.
LATITUDE_RANGE: Final[str] = (
    "degrees in (-90, 90), north positive, south negative (Omega_h = Omega_E cos(lat), "
    "Omega_v = Omega_E sin(lat); at a pole Omega_h = 0 leaves a gyrocompass nothing to sense)")


#: The tables of one instrument file, and the command that reads each; the top-level keys
#: (fields of GyrocompassParams and ``latitude``, the site) are read by ``calibrate gc`` and
#: ``race``.
INSTRUMENT_TABLES: Final[dict[str, tuple[str, ...]]] = {
    "procedure": ("race",), "sins": ("calibrate rsf",), "gs": ("calibrate rsf",),
    "encoder": ("calibrate rsf",)}
_TOP_READERS: Final[tuple[str, ...]] = ("calibrate gc", "race")

#: The fields of paper RSF's tables that a row of the input table (:mod:`gyrolib.inputs`)
#: ranges, by (table, field): the SINS roll gyro's and the GS gyro's scale-factor error and
#: bias, and the encoder's position error (each model's default is its row's reference).
RSF_ROWS: Final[dict[tuple[str, str], str]] = {
    ("sins", "eps1"): "rsf.eps1", ("sins", "eps0"): "rsf.eps0",
    ("gs", "eps1"): "rsf.eps1_gs", ("gs", "eps0"): "rsf.gs_bias",
    ("encoder", "position_error"): "rsf.encoder_error"}


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
    return _replace(label, base, _top_values(label, load_toml(path)))


def _top_values(label: str, doc: dict) -> dict:
    """The instrument file's top-level values (the tables of :data:`INSTRUMENT_TABLES`
    left out), ``latitude`` turned into ``Omega_h``, ``Omega_v``."""
    values = {k: v for k, v in doc.items()
              if not (k in INSTRUMENT_TABLES and isinstance(v, dict))}
    if "latitude" in values:
        lat = values.pop("latitude")
        if {"Omega_h", "Omega_v"} & set(values):
            raise RecordError(label, "give either 'latitude' or Omega_h/Omega_v, not both")
        if isinstance(lat, bool) or not isinstance(lat, int | float) or not -90.0 < lat < 90.0:
            raise RecordError(label, f"field 'latitude' must be {LATITUDE_RANGE}; got {lat!r}")
        earth = GyrocompassParams.at_latitude(math.radians(lat))
        values = {"Omega_h": earth.Omega_h, "Omega_v": earth.Omega_v, **values}
    return values


def instrument_notes(path: object | None, command: str) -> list[str]:
    """One note per entry of the instrument file ``path`` that ``command`` ("calibrate gc",
    "calibrate rsf" or "race") does not read, naming the command that does."""
    if path is None:
        return []
    doc = load_toml(path)
    out = _range_notes(path, doc, command)
    for key, val in doc.items():
        if key in INSTRUMENT_TABLES and isinstance(val, dict):
            if command not in INSTRUMENT_TABLES[key]:
                out.append(f"{path}: [{key}] ignored by {command} (read by "
                           f"{', '.join(INSTRUMENT_TABLES[key])})")
        elif command not in _TOP_READERS:
            out.append(f"{path}: {key!r} ignored by {command} (read by "
                       f"{', '.join(_TOP_READERS)})")
    return out


def _paper_rsf() -> tuple[Any, Any]:
    """Paper RSF's rows of the table of inputs (:mod:`gyrolib.rsf.inputs`) and its
    simulation's models (:mod:`gyrolib.rsf.simulation`), loaded on first use."""
    from gyrolib.rsf import inputs, simulation  # start-up: a GC run does not load paper RSF

    return inputs, simulation


def _range_notes(path: object, doc: dict, command: str) -> list[str]:
    """A note for each number the command reads from the instrument file that lies outside
    the plausible range of its row in the input table (:mod:`gyrolib.inputs`): top-level
    fields of GyrocompassParams, RateSensorProcedure's in ``[procedure]`` for race, and
    for calibrate rsf the fields of ``[sins]``, ``[gs]``, ``[encoder]`` that a row ranges
    (:data:`RSF_ROWS`; an error's magnitude, its sign being no matter of plausibility)."""
    if command == "calibrate rsf":
        rsf_inputs, _ = _paper_rsf()
        out = []
        for (table, field), name in RSF_ROWS.items():
            val = doc.get(table, {}).get(field) if isinstance(doc.get(table), dict) else None
            if isinstance(val, bool) or not isinstance(val, int | float):
                continue
            r = rsf_inputs.row(name)
            lo, hi = r.bounds()
            if not lo <= abs(val) <= hi:
                out.append(f"{path}: [{table}] {field} = {val:g} lies outside the plausible "
                           f"range [{lo:.3g}, {hi:.3g}] (magnitude) of the input table's row "
                           f"{r.name} ({' '.join(r.reason.split())[:120]})")
        return out

    parts = [("GyrocompassParams", {k: v for k, v in doc.items() if not isinstance(v, dict)})]
    if command == "race" and isinstance(doc.get("procedure"), dict):
        parts.append(("RateSensorProcedure", doc["procedure"]))
    if command not in _TOP_READERS:
        parts = parts[1:]
    out = []
    for owner, values in parts:
        for r in (r for r in gc_inputs.ROWS if r.owner == owner):
            if r.kind == "reading" or len(r.fields) != 1 or r.fields[0] not in values:
                continue
            val = values[r.fields[0]]
            if isinstance(val, bool) or not isinstance(val, int | float):
                continue
            lo, hi = r.bounds()
            if not lo <= val <= hi:
                out.append(f"{path}: {r.fields[0]} = {val:g} lies outside the plausible range "
                           f"[{lo:.3g}, {hi:.3g}] of the input table's row {r.name} "
                           f"({' '.join(r.reason.split())[:120]})")
    return out


def race_inputs(path: object) -> tuple[dict, dict, list[str]]:
    """The ``race`` command's share of an instrument file: the top-level fields of
    :class:`~gyrolib.gc.GyrocompassParams` (``latitude`` as ``Omega_h``, ``Omega_v``), the
    ``[procedure]`` table's fields of :class:`~gyrolib.gc.RateSensorProcedure`, and the
    notes on what it ignores (paper RSF's tables)."""
    label = str(path)
    doc = load_toml(path)
    table = doc.get("procedure", {})
    if not isinstance(table, dict):
        raise RecordError(label, "'procedure' must be a table of RateSensorProcedure fields")
    return _top_values(label, doc), dict(table), instrument_notes(path, "race")


_RSF_TABLES = ("sins", "gs", "encoder")


def rsf_config_from_toml(path: object | None = None, base: object | None = None):
    """:class:`gyrolib.rsf.SimulationConfig` whose ``sins``, ``gs`` and ``encoder`` models
    take the fields of the TOML tables ``[sins]``, ``[gs]``, ``[encoder]``."""
    _, simulation = _paper_rsf()
    cfg = simulation.SimulationConfig() if base is None else base
    if path is None:
        return cfg
    label = str(path)
    doc = load_toml(path)
    parts = {}
    for key, val in doc.items():
        if key in INSTRUMENT_TABLES and key not in _RSF_TABLES and isinstance(val, dict):
            continue                      # another command's table (instrument_notes)
        if not isinstance(val, dict):     # a top-level field: calibrate gc's and race's
            continue
        if key not in _RSF_TABLES:
            raise RecordError(label, f"unknown entry {key!r}: expected the tables "
                              f"[{'], ['.join(_RSF_TABLES)}] of the RSF sensor models")
        parts[key] = _replace(label, getattr(cfg, key), val, where=f"{key}.")
    return dataclasses.replace(cfg, **parts)
