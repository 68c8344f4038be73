"""Reading measurement records and parameter files: CSV files into the plain record objects
:class:`gyrolib.gc.GCRecord` and :class:`gyrolib.rsf.RSFRecord` that the paper subpackages
accept (records imports them; they never import records).

==================  ===============================================================
module              what it holds
==================  ===============================================================
``reader``          :func:`read_csv`, :func:`iter_csv` (CSV or ``.csv.gz`` through pyarrow's
                    CSV reader, streamed in chunks), :func:`read_gc`, :class:`GCChunks` (a
                    long record in chunks), :func:`read_rsf`, :class:`RecordInfo`,
                    :func:`write_csv`
``params``          :func:`load_toml`, :func:`gc_params_from_toml`,
                    :func:`rsf_config_from_toml`
``rate_log``        :func:`read_rate_log`: a gyro's (or clock's) rate or phase log for
                    its Allan deviation, through the same reader (:class:`RateLog`)
``plausibility``    units and conventions at the door: :func:`check_gc`,
                    :func:`check_rsf` (a column in degrees, milliseconds or g refused with
                    the likely mistake named), :func:`angle_bound`, :func:`noise_ratio`
``options``         the command line's format options beside the reader:
                    :func:`add_format_options`, :func:`read_options`, :func:`parse_columns`
``errors``          :class:`RecordError` (a bad file: names the file, row and column),
                    :class:`OptionError` (a bad option)
==================  ===============================================================

Use as ``from gyrolib import records`` then ``records.read_gc("run.csv")``.
"""

import sys

import gyrolib.records.errors as _errors
import gyrolib.records.options as _options

#: Which module defines each public name; the numerical ones are imported on first use, so
#: that the command line's parsers (:mod:`gyrolib.records.options`, :mod:`~.errors`: the
#: standard library only, imported here) load no numpy or pyarrow.
_HOME: dict[str, str] = {
    "RecordError": "errors", "OptionError": "errors",
    "gc_params_from_toml": "params", "load_toml": "params", "rsf_config_from_toml": "params",
    "angle_bound": "plausibility", "check_gc": "plausibility", "check_rsf": "plausibility",
    "noise_ratio": "plausibility", "check_rate_log": "plausibility",
    "RateLog": "rate_log", "read_rate_log": "rate_log",
    "add_format_options": "options", "parse_columns": "options", "read_options": "options",
    "ABSOLUTE_TIME": "reader", "GC_COLUMNS": "reader", "RSF_COLUMNS": "reader",
    "GCChunks": "reader", "GCRecord": "reader", "RecordInfo": "reader", "iter_csv": "reader",
    "read_csv": "reader", "read_gc": "reader", "read_rsf": "reader", "write_csv": "reader",
    "RSFRecord": "reader",
}


def __getattr__(name: str):
    """The names of ``__all__``, each imported from its module on first use (an ``import``
    statement each, which the import graph of ``tests/test_imports.py`` sees);
    ``RSFRecord`` is paper RSF's record (see :mod:`gyrolib.records.reader`)."""
    home = _HOME.get(name)
    if home == "errors":
        module = _errors
    elif home == "options":
        module = _options
    elif home == "params":
        import gyrolib.records.params as module  # start-up: numpy (paper GC's parameters)
    elif home == "plausibility":
        import gyrolib.records.plausibility as module  # start-up: numpy
    elif home in ("reader", "rate_log"):
        import gyrolib.records.rate_log  # noqa: F401 # start-up: numpy, pyarrow (and the reader)

        module = sys.modules[f"gyrolib.records.{home}"]
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(module, name)


def __dir__() -> list[str]:
    return sorted(set(__all__) | set(globals()))


__all__ = [
    "ABSOLUTE_TIME",
    "GC_COLUMNS",
    "RSF_COLUMNS",
    "GCChunks",
    "GCRecord",
    "OptionError",
    "RSFRecord",
    "RateLog",
    "RecordError",
    "RecordInfo",
    "add_format_options",
    "angle_bound",
    "check_gc",
    "check_rate_log",
    "check_rsf",
    "gc_params_from_toml",
    "iter_csv",
    "load_toml",
    "noise_ratio",
    "parse_columns",
    "read_csv",
    "read_gc",
    "read_options",
    "read_rate_log",
    "read_rsf",
    "rsf_config_from_toml",
    "write_csv",
]
