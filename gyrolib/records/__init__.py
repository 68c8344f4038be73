"""Reading measurement records and parameter files: CSV files into the plain record objects
:class:`gyrolib.gc.GCRecord` and :class:`gyrolib.rsf.RSFRecord` that the paper subpackages
accept (records imports them; they never import records).

==================  ===============================================================
module              what it holds
==================  ===============================================================
``reader``          :func:`read_csv`, :func:`iter_csv` (CSV or ``.csv.gz`` through pyarrow's
                    CSV reader, streamed in chunks), :func:`read_gc`, :class:`GCChunks` (a
                    long record in chunks), :func:`read_rsf`, :class:`RecordInfo`,
                    :func:`parse_columns`, :func:`write_csv`
``params``          :func:`load_toml`, :func:`gc_params_from_toml`,
                    :func:`rsf_config_from_toml`
``plausibility``    units and conventions at the door: :func:`check_gc`,
                    :func:`check_rsf` (a column in degrees, milliseconds or g refused with
                    the likely mistake named), :func:`angle_bound`, :func:`noise_ratio`
``errors``          :class:`RecordError` (a bad file: names the file, row and column)
==================  ===============================================================

Use as ``from gyrolib import records`` then ``records.read_gc("run.csv")``.
"""

from gyrolib.records.errors import (
    RecordError,
)
from gyrolib.records.params import (
    gc_params_from_toml,
    load_toml,
    rsf_config_from_toml,
)
from gyrolib.records.plausibility import (
    angle_bound,
    check_gc,
    check_rsf,
    noise_ratio,
)
from gyrolib.records.reader import (
    ABSOLUTE_TIME,
    GC_COLUMNS,
    RSF_COLUMNS,
    GCChunks,
    GCRecord,
    RecordInfo,
    iter_csv,
    parse_columns,
    read_csv,
    read_gc,
    read_rsf,
    write_csv,
)


def __getattr__(name: str):
    """``RSFRecord`` (paper RSF's record), imported on first use (see
    :mod:`gyrolib.records.reader`)."""
    if name == "RSFRecord":
        from gyrolib.rsf.record import RSFRecord

        return RSFRecord
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = [
    "ABSOLUTE_TIME",
    "GC_COLUMNS",
    "RSF_COLUMNS",
    "GCChunks",
    "GCRecord",
    "RSFRecord",
    "RecordError",
    "RecordInfo",
    "angle_bound",
    "check_gc",
    "check_rsf",
    "gc_params_from_toml",
    "iter_csv",
    "load_toml",
    "noise_ratio",
    "parse_columns",
    "read_csv",
    "read_gc",
    "read_rsf",
    "rsf_config_from_toml",
    "write_csv",
]
