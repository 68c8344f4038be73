"""Reading measurement records and parameter files for the calibration commands.

==================  ===============================================================
module              what it holds
==================  ===============================================================
``csv``             :func:`read_csv`, :func:`iter_csv` (CSV or ``.csv.gz``, ``#`` comments,
                    chunked), :class:`GCRecord`, :class:`RSFRecord`, :func:`read_gc`,
                    :func:`iter_gc`, :func:`read_rsf`
``params``          :func:`load_toml`, :func:`gc_params_from_toml`,
                    :func:`rsf_config_from_toml`
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
from gyrolib.records.tables import (
    GC_COLUMNS,
    RSF_COLUMNS,
    GCChunks,
    GCRecord,
    RSFRecord,
    iter_csv,
    iter_gc,
    read_csv,
    read_gc,
    read_rsf,
    write_csv,
)

__all__ = [
    "GC_COLUMNS",
    "RSF_COLUMNS",
    "GCChunks",
    "GCRecord",
    "RSFRecord",
    "RecordError",
    "gc_params_from_toml",
    "iter_csv",
    "iter_gc",
    "load_toml",
    "read_csv",
    "read_gc",
    "read_rsf",
    "rsf_config_from_toml",
    "write_csv",
]
