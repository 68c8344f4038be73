"""Measurement records as CSV files: reading (plain or ``.csv.gz``, streamed in chunks with
bounded memory, through `pyarrow's CSV reader
<https://arrow.apache.org/docs/python/csv.html>`_), checking and writing.

A record file has one header line naming its columns, optionally preceded by ``#`` comment
lines and blank lines; a UTF-8 byte-order mark before the first line is dropped.  Columns are
separated by commas, tabs or semicolons: the separator is the one that splits the header into
the expected columns (a header that two separators split alike, and whose first data line
does not decide, is refused as ambiguous).  Cells may be quoted (``"1.5"``, a quoted field
may hold the separator); line ends are ``\\n``, ``\\r\\n`` or ``\\r``.  Extra columns are
ignored and never parsed.  Other header names are mapped with ``columns={"t": "time", ...}``
(the command line's ``--columns t=time,...``).  Inside the data, blank lines and lines that
start with ``#`` are skipped.

Cells are numbers, converted correctly rounded (the same double as Python's ``float``); an
empty cell, ``nan``, ``NA`` or ``null`` is a missing value (the calibration skips that one
measurement).  Time ``t`` (s) must be finite and strictly increasing.  Anything else raises
:class:`~gyrolib.records.RecordError` naming the file, the line and the column (and, for a
byte that is not UTF-8, its line): the fast reader stops at the first fault, and the file is
then scanned line by line to say where it is.

**Absolute time stamps.**  A logger's clock (Unix time, ≈1.7·10⁹ s, or any offset of at
least :data:`ABSOLUTE_TIME` s) is taken relative to the first row, or to ``t0`` when given;
:attr:`RecordInfo.time_note` says so, and the command line prints it.  The leading comment
``# latitude_deg: 53.9`` sets :attr:`GCRecord.latitude <gyrolib.gc.GCRecord>` (radians).

* GC record (paper GC): ``t``, ``angle_sensor`` (rad), ``inclinometer_y``,
  ``inclinometer_z`` (m/s²) — :data:`GC_COLUMNS`, :class:`GCRecord`;
* RSF record (paper RSF): ``t``, ``sins_increment`` (rad) and ``gs_angle`` (rad) or
  ``encoder_counts`` (wrapped counts, optionally with ``gs_gyro_angle``) —
  :data:`RSF_COLUMNS`, :class:`RSFRecord`.
"""

from __future__ import annotations

import csv
import dataclasses
import decimal
import difflib
import gzip
import io
import math
import os
import re
import threading
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Final

import numpy as np

from gyrolib import _validation as v
from gyrolib.gc.logs.record import GCRecord
from gyrolib.gc.model.params import GyrocompassParams
from gyrolib.records.errors import RecordError
from gyrolib.records.options import parse_columns
from gyrolib.records.plausibility import check_gc, check_rsf
from gyrolib.units import UNITS

if TYPE_CHECKING:
    from gyrolib.rsf.record import RSFRecord


def _rsf_record() -> type:
    """Paper RSF's record class, loaded on first use."""
    from gyrolib.rsf.record import RSFRecord  # start-up: a GC run does not load paper RSF

    return RSFRecord


def __getattr__(name: str):
    """``RSFRecord``, imported on first use: paper RSF's package (20–60 ms) is not loaded by
    a paper-GC run of the command line."""
    if name == "RSFRecord":
        return _rsf_record()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = [
    "ABSOLUTE_TIME",
    "GC_COLUMNS",
    "RSF_COLUMNS",
    "GCChunks",
    "GCRecord",
    "RSFRecord",
    "RecordInfo",
    "iter_csv",
    "parse_columns",
    "read_csv",
    "read_gc",
    "read_rsf",
    "write_csv",
]

#: Columns of a paper-GC record, in SI (s, rad, m/s², m/s²).
GC_COLUMNS: Final[tuple[str, ...]] = ("t", "angle_sensor", "inclinometer_y", "inclinometer_z")

#: Columns of a paper-RSF record (``gs_angle`` may be replaced by ``encoder_counts``).
RSF_COLUMNS: Final[tuple[str, ...]] = ("t", "sins_increment", "gs_angle")

#: Rows per chunk: a chunk of 65 536 rows of four columns is 2 MB.
CHUNK_ROWS: Final[int] = 65536

#: Bytes pyarrow parses at a time (a block per thread, a few read ahead): 1 MB keeps the
#: peak memory of reading an hour at 1 kHz about 100 MB above the start, whatever the
#: file's size (4 MB: 220 MB, and no faster).
BLOCK_BYTES: Final[int] = 1 << 20

#: A first time stamp at least this large (s) is a logger's clock, not the time since the
#: start of the run: times are then taken relative to the first row.
ABSOLUTE_TIME: Final[float] = 1000.0

#: Largest time (s) a record may reach from its start (relative to t0 when one is taken):
#: 116 days; a stamp beyond is corrupt, and would make a calibration's step tables huge.
MAX_TIME: Final[float] = 1e7

#: Decimals of an absolute time stamp read exactly (1 ns): the column is read as a decimal,
#: the offset subtracted exactly, then converted to a double.
TIME_DECIMALS: Final[int] = 9

#: Column separators accepted, in the order tried.
DELIMITERS: Final[tuple[str, ...]] = (",", "\t", ";")

#: Cells read as a missing value (NaN).
NULL_VALUES: Final[tuple[str, ...]] = (
    "", "nan", "NaN", "NAN", "-nan", "+nan", "-NaN", "+NaN", "NA", "N/A", "n/a", "null",
    "NULL")

_BOM: Final[bytes] = b"\xef\xbb\xbf"
_LATITUDE: Final[re.Pattern] = re.compile(r"#\s*latitude_deg\s*[:=]\s*(.*?)\s*$")
#: An ISO 8601 date-time stamp (``2024-05-14 10:32:01.251``, or with a T), with or without a
#: zone: ``Z`` or an offset from UTC (``+02:00``, ``+0200``, ``+02``).
_ISO_TIME: Final[re.Pattern] = re.compile(
    r"(\d{4}-\d{2}-\d{2}[ T]\d{2}:\d{2}(?::\d{2}(?:[.,]\d{1,9})?)?)"
    r"(Z|[+-]\d{2}(?::?\d{2})?)?")


def _iso_ns(cell: str) -> tuple[int, bool]:
    """An ISO 8601 stamp (:data:`_ISO_TIME`) as integer ns since the epoch (UTC when it has
    a zone), and whether it has one.

    >>> _iso_ns("2024-05-14T10:32:01.251+02:00") == _iso_ns("2024-05-14 08:32:01.251Z")
    True
    >>> _iso_ns("1970-01-01 00:00:01.5")
    (1500000000, False)
    """
    m = _ISO_TIME.fullmatch(cell)
    if m is None:
        raise ValueError(f"not an ISO 8601 date-time stamp: {cell!r}")
    ns = int(np.datetime64(m.group(1).replace(" ", "T").replace(",", "."), "ns")
             .astype(np.int64))
    zone = m.group(2)
    if zone is None:
        return ns, False
    if zone != "Z":
        digits = zone[1:].replace(":", "")
        minutes = 60 * int(digits[:2]) + (int(digits[2:]) if len(digits) > 2 else 0)
        ns -= (-1 if zone[0] == "-" else 1) * minutes * 60 * 10**9
    return ns, True
#: The file's end made of rows of separators only (and blank lines), after a line end.
_EMPTY_TAIL: Final[re.Pattern] = re.compile(rb"(?:(?:\r\n|\r|\n)[ \t,;\"]*)+\Z")
_DECIMAL_COMMA: Final[re.Pattern] = re.compile(r"-?\d+,\d+(?:[eE][-+]?\d+)?")
_DELIM_NAMES: Final[dict[str, str]] = {",": "commas", "\t": "tabs", ";": "semicolons"}


@dataclasses.dataclass(frozen=True)
class RecordInfo:
    """What the reader found in a record file besides the numbers.

    ``delimiter`` the column separator; ``header_line`` the header's line number;
    ``columns`` the file's header name of each column read (after ``columns=`` mapping);
    ``latitude`` (rad) from a leading ``# latitude_deg:`` comment, else None; ``t_offset``
    (s) subtracted from every time stamp, with ``t_offset_source`` ``"none"``, ``"first
    row"`` (an absolute clock, see :data:`ABSOLUTE_TIME`) or ``"t0"`` (given);
    ``t_offset_text`` the offset exactly as subtracted (decimal: the time stamps of an offset
    clock are read as decimals to 1 ns, the offset subtracted exactly, then rounded once);
    ``rows_dropped`` the rows before ``t0`` (given) left out; ``empty_rows`` rows whose every
    cell read is empty, skipped; ``header_notes`` a note for each column whose header
    matched only when case is ignored."""

    path: str
    delimiter: str
    header_line: int
    columns: dict
    latitude: float | None
    t_offset: float
    t_offset_source: str
    t_offset_text: str = "0"
    t_exact: bool = False
    rows_dropped: int = 0
    empty_rows: int = 0
    header_notes: tuple[str, ...] = ()

    @property
    def time_note(self) -> str | None:
        """One sentence on the time base, or None when the file's times were used as
        they are."""
        if self.t_offset_source == "none":
            return None
        if self.t_offset_source == "iso" or self.t_offset_text.startswith("iso "):
            text = self.t_offset_text.removeprefix("iso ")
            zoned = _ISO_TIME.fullmatch(text) is not None and bool(
                _ISO_TIME.fullmatch(text).group(2))
            return (f"ISO date-time stamps{' with a zone, read as UTC' if zoned else ''}, "
                    f"taken relative to the first row ({text}), exact to 1 ns"
                    + (f"; the {self.rows_dropped} row(s) before t0 dropped"
                       if self.rows_dropped else ""))
        why = ("an absolute clock (first time stamp >= "
               f"{ABSOLUTE_TIME:g} s): the first row is t = 0, the start of the run (give "
               "t0 otherwise)" if self.t_offset_source == "first row" else "t0 given")
        dropped = (f"; the {self.rows_dropped} row(s) before it dropped"
                   if self.t_offset_source == "t0" else "")
        return (f"times taken relative to t0 = {self.t_offset_text} s ({why}"
                + ("; read as decimals, differences exact to 1 ns" if self.t_exact else "")
                + dropped + ")")

    @property
    def notes(self) -> list[str]:
        """Every note on how the file was read: the time base, headers matched ignoring
        case, empty rows skipped."""
        out = [self.time_note] if self.time_note else []
        out += list(self.header_notes)
        if self.empty_rows:
            out.append(f"{self.empty_rows} empty row(s) (every cell empty, as spreadsheets "
                       "leave at the end) skipped")
        return out

    def summary(self) -> dict:
        """JSON-ready dict (SI, with units)."""
        return {"delimiter": self.delimiter, "header_line": self.header_line,
                "columns": dict(self.columns), "latitude_rad": self.latitude,
                "t_offset_s": self.t_offset, "t_offset_exact": self.t_offset_text,
                "t_offset_source": self.t_offset_source, "rows_dropped": self.rows_dropped,
                "empty_rows": self.empty_rows}


# Reading the lines before the data --------------------------------------------------------
def _line_end(buf: bytes, pos: int) -> tuple[int, int] | None:
    """(end of the line's text, start of the next line) from ``pos``, or None when the
    buffer holds no line end yet."""
    i = buf.find(b"\n", pos)
    j = buf.find(b"\r", pos, i if i >= 0 else len(buf))
    if j >= 0:
        if j + 1 >= len(buf):
            return None         # \r at the end of the buffer: \r\n or a lone \r
        return j, j + 2 if buf[j + 1] == 10 else j + 1
    if i >= 0:
        return i, i + 1
    return None


def _decode(raw: bytes, label: str, line_no: int) -> str:
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise RecordError(label, f"not UTF-8 text: byte 0x{raw[exc.start]:02x} at character "
                          f"{exc.start + 1} of the line (save the file as UTF-8)",
                          row=line_no) from None


def _fields(line: str, delimiter: str) -> list[str]:
    return next(csv.reader([line], delimiter=delimiter, quotechar='"'), [])


def _decimal_time_ok(value: decimal.Decimal) -> bool:
    """Whether an absolute time stamp fits the exact reading: finite, at most
    :data:`TIME_DECIMALS` decimals, below 10^(30 - TIME_DECIMALS) s."""
    return (value.is_finite() and value.as_tuple().exponent >= -TIME_DECIMALS
            and abs(value) < decimal.Decimal(10) ** (30 - TIME_DECIMALS))


def _is_number(cell: str) -> bool:
    """Whether pyarrow's float conversion accepts ``cell`` (Python's ``float`` less the
    digit separators)."""
    if "_" in cell:
        return False
    try:
        float(cell)
    except ValueError:
        return False
    return True


class _Rest:
    """The bytes after the header: what is left of the buffer, then the stream (a file-like
    object pyarrow reads from, in its own I/O threads).  :meth:`stop` ends it early: the
    reads under way finish, and every later one reads the end of the file."""

    def __init__(self, head: bytes, stream) -> None:
        self.head = head
        self.stream = stream
        self.closed = False
        self._stopped = False
        self._busy = 0                        # reads under way (in pyarrow's threads)
        self._idle = threading.Condition()

        self.empty_rows = 0      # rows of separators only, stripped from the file's end
        self._held = b""         # the last bytes read, held until the end is known
        self._eof = False

    def _raw(self, n: int) -> bytes:
        if self.head:
            if n < 0:
                out, self.head = self.head + self.stream.read(), b""
                return out
            out, self.head = self.head[:n], self.head[n:]
            return out
        return self.stream.read() if n < 0 else self.stream.read(n)

    def stop(self, timeout: float = 30.0) -> None:
        """End the stream here: wait for the reads under way, and read the end of the file
        from now on (pyarrow's read-ahead then stops at once)."""
        with self._idle:
            self._stopped = True
            self._idle.wait_for(lambda: self._busy == 0, timeout=timeout)

    def read(self, n: int = -1) -> bytes:
        """Up to ``n`` bytes (all with ``n < 0``); the file's trailing rows of separators
        only (``,,,`` as spreadsheets leave them) are cut off and counted; nothing once
        stopped."""
        with self._idle:
            if self._stopped:
                return b""
            self._busy += 1
        try:
            return self._read(n)
        finally:
            with self._idle:
                self._busy -= 1
                self._idle.notify_all()

    def _read(self, n: int = -1) -> bytes:
        n = -1 if n is None else n
        if self._eof:
            out, self._held = self._held, b""
            return out
        nxt = self._raw(n if n >= 0 else -1)
        if n < 0 or not nxt:
            data = self._held + nxt
            self._held, self._eof = b"", True
            m = _EMPTY_TAIL.search(data)
            if m:
                self.empty_rows = sum(1 for ln in re.split(rb"\r\n|\r|\n", m.group(0))
                                      if ln.strip(b" \t"))
                data = data[:m.start()] + b"\n"
            return data
        out, self._held = self._held, nxt
        return out if out else self._read(n)

    def readable(self) -> bool:
        return True

    def seekable(self) -> bool:
        return False

    def close(self) -> None:
        self.closed = True


# The reader -------------------------------------------------------------------------------
#: The kind of each record column a unit option converts (``encoder_counts`` is counts).
UNIT_KINDS: Final[dict[str, str]] = {
    "t": "time", "rate": "rate", "phase": "phase", "angle_sensor": "angle",
    "sins_increment": "angle", "gs_angle": "angle",
    "gs_gyro_angle": "angle", "inclinometer_y": "accel", "inclinometer_z": "accel"}
#: The units each kind may be read in (names of :data:`gyrolib.units.UNITS`).
READ_UNITS: Final[dict[str, tuple[str, ...]]] = {
    "time": ("s", "ms", "us", "µs"), "angle": ("rad", "mrad", "deg", "arcsec"),
    "accel": ("m/s^2", "mg", "g"), "rate": ("rad/s", "deg/s", "deg/h", "1"),
    "phase": ("rad", "deg", "s")}


#: Unit names a units row may hold, by kind (brackets and parentheses around them dropped).
_ROW_UNITS: Final[dict[str, str]] = {
    "s": "s", "sec": "s", "ms": "ms", "us": "us", "µs": "us", "rad": "rad", "mrad": "mrad",
    "deg": "deg", "°": "deg", "arcsec": "arcsec", '"': "arcsec", "m/s^2": "m/s^2",
    "m/s²": "m/s^2", "m/s2": "m/s^2", "mg": "mg", "g": "g", "rad/s": "rad/s",
    "deg/s": "deg/s", "°/s": "deg/s", "dps": "deg/s", "deg/h": "deg/h", "°/h": "deg/h"}
#: Cells of a units row that name no unit (a count, a ratio).
_ROW_NO_UNIT: Final[frozenset[str]] = frozenset({"", "-", "1", "counts", "count"})


def _units_row(line: str, delim: str) -> list[str] | None:
    """The cells of ``line`` if it is a units row (no cell a number, at least one a unit of
    :data:`_ROW_UNITS`), normalized; else None."""
    cells = [c.strip().strip('"').strip().strip("[]()").strip() for c in _fields(line, delim)]
    if any(_is_number(c.replace(",", ".")) for c in cells if c):
        return None
    if not any(c.lower() in _ROW_UNITS or c in _ROW_UNITS for c in cells):
        return None
    return [_ROW_UNITS.get(c, _ROW_UNITS.get(c.lower(), c)) for c in cells]


def _unit_factors(units: Mapping[str, str | None] | None) -> dict[str, float]:
    """``{"time": "ms", ...}`` -> the SI factor of each kind given (``m/s²`` spelt either
    way); an unknown kind or unit is a ValueError naming the choices."""
    out: dict[str, float] = {}
    for kind, unit in (units or {}).items():
        if unit is None:
            continue
        unit = "m/s^2" if unit == "m/s²" else unit
        if kind not in READ_UNITS or unit not in READ_UNITS[kind]:
            raise ValueError(f"units: expected {kind!r} in "
                             f"{', '.join(READ_UNITS.get(kind, ()))} (kinds: "
                             f"{', '.join(READ_UNITS)}); got {unit!r}")
        out[kind] = float(UNITS[unit])
    return out


class _Reader:
    """Iterates over a CSV record in chunks of rows ``(columns, data)``, checking as it
    goes; :attr:`info` is set once the first chunk is read."""

    def __init__(self, path: object, required: Sequence[str], one_of: Sequence[str] = (),
                 chunk_rows: int = CHUNK_ROWS, optional: Sequence[str] = (), *,
                 columns: Mapping[str, str] | None = None, t0: float | None = None,
                 block_bytes: int = BLOCK_BYTES,
                 units: Mapping[str, str | None] | None = None,
                 decimal_comma: bool | None = None) -> None:
        if not isinstance(path, str | os.PathLike):
            raise TypeError(f"path must be a str or path; got {type(path).__name__}")
        self.path = Path(path)
        self.label = str(path)
        self.required = tuple(required)
        self.one_of = tuple(one_of)
        self.optional = tuple(optional)
        self.chunk_rows = v.check_int("chunk_rows", chunk_rows, 1)
        self.block_bytes = v.check_int("block_bytes", block_bytes, 1024)
        known = (*self.required, *self.one_of, *self.optional)
        self.mapping = dict(columns or {})
        for k, val in self.mapping.items():
            if k not in known or not isinstance(val, str) or not val:
                raise ValueError(f"columns maps {k!r}: expected a column among "
                                 f"{', '.join(known)} mapped to a non-empty header name")
        if t0 is not None:
            t0 = v.check_real("t0", t0)
        self.t0 = t0
        self.units = _unit_factors(units)
        self.decimal_comma = decimal_comma
        self._comma = False
        self.units_row: dict[str, str] | None = None
        self.units_line: int | None = None
        self._iso_ns: int | None = None     # ISO stamps: the offset (ns since the epoch)
        self._iso_zone = False              # ... and whether they carry a zone (read as UTC)
        self.col_factor: dict[str, float] = {}
        self.fraction = 0.0
        self.first_line: str | None = None
        self._decimal_t = False
        self._offset: decimal.Decimal | None = None
        self.info: RecordInfo | None = None
        self.latitude: float | None = None
        #: Whether the first column is the time ``t`` (checked finite and increasing, its
        #: base and unit read); a record without one (a rate log at a stated rate) is not.
        self.has_time = bool(self.required) and self.required[0] == "t"

    def _error(self, message: str, **kw) -> RecordError:
        return RecordError(self.label, message, **kw)

    # opening, the lines before the data
    def _open(self):
        try:
            raw = open(self.path, "rb")
        except FileNotFoundError:
            raise self._error("no such file") from None
        except IsADirectoryError:
            raise self._error("is a directory, not a CSV file") from None
        except PermissionError:
            raise self._error("cannot be read (permission denied)") from None
        size = os.fstat(raw.fileno()).st_size
        stream = (gzip.GzipFile(fileobj=raw, mode="rb") if self.path.name.endswith(".gz")
                  else raw)
        return stream, raw, size

    def _preamble(self, stream) -> tuple[list[str], int, str, bytes]:
        """Leading comments (``# latitude_deg:`` read), the header: its fields, its line
        number, the delimiter, and the bytes after it."""
        buf = stream.read(1 << 16)
        eof = len(buf) < (1 << 16)
        if buf.startswith(_BOM):
            buf = buf[len(_BOM):]
        elif buf[:2] in (b"\xff\xfe", b"\xfe\xff"):
            raise self._error("is UTF-16 text: save it as UTF-8")
        pos, line_no, header = 0, 0, None
        while header is None:
            le = _line_end(buf, pos)
            if le is None and not eof:
                more = stream.read(1 << 16)
                eof = len(more) < (1 << 16)
                buf = buf[pos:] + more
                pos = 0
                continue
            if le is None:           # the last line, without its line end
                if pos >= len(buf):
                    want = ", ".join(self.required)
                    raise self._error(f"is empty: expected a header line naming the "
                                      f"columns {want}")
                le = (len(buf), len(buf))
            end, nxt = le
            line_no += 1
            raw_line = buf[pos:end]
            if b"\x00" in raw_line:
                raise self._error("not a text CSV file (it holds NUL bytes)", row=line_no)
            text = _decode(raw_line, self.label, line_no)
            pos = nxt
            s = text.strip()
            if not s:
                continue
            if s.startswith("#"):
                m = _LATITUDE.match(s)
                if m:
                    self.latitude = self._latitude(m.group(1), line_no)
                continue
            header = text
        rest = buf[pos:]
        first_data = self._first_data_line(rest, stream, eof)
        delim = self._delimiter(header, first_data, line_no)
        names = [c.strip().strip('"').strip() for c in _fields(header, delim)]
        self.first_line = first_data[0]
        after = rest + first_data[1]
        self.units_row, self.units_line = None, None
        row = _units_row(first_data[0], delim) if first_data[0] is not None else None
        if row is not None:        # a units row under the header: read, then skipped
            self.units_row = dict(zip(names, row))
            self.units_line = line_no + first_data[3]
            after = after[first_data[2]:]
            nxt = self._first_data_line(after, stream, False)
            self.first_line = nxt[0]
            after += nxt[1]
        return names, line_no, delim, after

    def _latitude(self, text: str, line_no: int) -> float:
        try:
            deg = float(text)
        except ValueError:
            deg = math.nan
        if not (math.isfinite(deg) and -90.0 <= deg <= 90.0):
            raise self._error(f"'# latitude_deg:' expects degrees in [-90, 90]; got "
                              f"{text[:40]!r}", row=line_no)
        return math.radians(deg)

    def _first_data_line(self, rest: bytes, stream, eof: bool):
        """(first data line as text or None, bytes read beyond ``rest`` to find it, the
        offset in ``rest`` + those bytes after that line, the lines read up to it)."""
        extra = b""
        buf = rest
        pos = 0
        lines = 0
        while True:
            le = _line_end(buf, pos)
            if le is None and not eof and len(buf) < (1 << 20):
                more = stream.read(1 << 16)
                eof = len(more) < (1 << 16)
                extra += more
                buf = rest + extra
                continue
            if le is None:
                le = (len(buf), len(buf))
            end, nxt = le
            if pos >= len(buf):
                return None, extra, pos, lines
            line = buf[pos:end].decode("utf-8", errors="replace").strip()
            pos = nxt
            lines += 1
            if line and not line.startswith("#"):
                return line, extra, pos, lines

    def _row_factors(self, use: list[str]) -> dict[str, float]:
        """The SI factor of each column that the units row names (checked against the unit
        options: a contradiction is refused), with a note."""
        if self.units_row is None:
            return {}
        out: dict[str, float] = {}
        shown = []
        for c in use:
            unit = self.units_row.get(self.files[c], "")
            kind = UNIT_KINDS.get(c)
            if kind is None or unit in _ROW_NO_UNIT:
                continue
            if unit not in READ_UNITS[kind]:
                raise self._error(f"the units row gives {unit!r}: expected one of "
                                  f"{', '.join(READ_UNITS[kind])}", row=self.units_line,
                                  column=c)
            f = float(UNITS[unit])
            given = self.units.get(kind)
            if given is not None and given != f:
                raise self._error(f"the units row gives {unit!r}, which the {kind} unit "
                                  "option contradicts: give one", row=self.units_line,
                                  column=c)
            out[c] = f
            shown.append(f"{c} in {unit}")
        self.header_notes.append(f"units row (line {self.units_line}) read: "
                                 + (", ".join(shown) or "no unit to convert"))
        return out

    def _decimal_comma(self, delim: str, idx: list[int], header_line: int) -> bool:
        """Whether the numbers are written with a decimal comma: as told
        (``decimal_comma``), else detected when the separator is ``;`` and every number of
        the first data line's columns reads ``-?d+,d+``; some cells so and others not is
        refused as ambiguous."""
        if self.decimal_comma is not None:
            if self.decimal_comma and delim == ",":
                raise self._error("decimal commas need another column separator (';' or "
                                  "tabs): the columns are separated by commas",
                                  row=header_line)
            comma = bool(self.decimal_comma)
        else:
            comma = False
            if delim == ";" and self.first_line is not None:
                cells = _fields(self.first_line, delim)
                vals = [cells[i].strip().strip('"') for i in idx if i < len(cells)]
                vals = [c for c in vals if c and c.lower() not in NULL_VALUES]
                hits = [c for c in vals if _DECIMAL_COMMA.fullmatch(c)]
                if hits and len(hits) == len(vals):
                    comma = True
                elif hits:
                    raise self._error(
                        f"ambiguous decimal separator: the first data line holds numbers "
                        f"with a comma ({hits[0]!r}) and without ("
                        f"{next(c for c in vals if c not in hits)!r}); give --decimal-comma "
                        "if the commas are decimal points", row=header_line + 1,
                        hint="--decimal-comma")
        if comma:
            self.header_notes.append("numbers read with a decimal comma"
                                     + ("" if self.decimal_comma else
                                        " (detected: ';' separates the columns and every "
                                        "number of the first data line is written d,d)"))
        return comma

    def _wanted(self) -> list[str]:
        return [self.mapping.get(c, c) for c in self.required]

    def _delimiter(self, header: str, first_data, line_no: int) -> str:
        line = first_data[0] if first_data else None
        cands = [d for d in DELIMITERS if len(_fields(header, d)) > 1]
        if len(cands) <= 1:
            return cands[0] if cands else ","
        want = set(self._wanted())
        good = [d for d in cands
                if want <= {c.strip().strip('"').strip() for c in _fields(header, d)}] or cands
        if len(good) > 1 and line is not None:
            agree = [d for d in good if len(_fields(line, d)) == len(_fields(header, d))]
            good = agree or good
        if len(good) > 1:
            raise self._error("ambiguous column separator: the header splits at "
                              + " and at ".join(_DELIM_NAMES[d] for d in good)
                              + " alike; use one separator", row=line_no)
        return good[0]

    def _columns(self, names: list[str], line_no: int, delim: str
                 ) -> tuple[list[str], list[int]]:
        seen = set()
        files = {c: self.mapping.get(c, c) for c in (*self.required, *self.one_of,
                                                    *self.optional)}
        for nm in names:
            if nm in seen and nm in files.values():
                raise self._error(f"column {nm!r} appears twice in the header", row=line_no)
            seen.add(nm)
        shown = (", ".join(repr(n[:30]) for n in names[:8])
                 + (" ..." if len(names) > 8 else ""))
        sep = _DELIM_NAMES[delim]
        self.header_notes = []
        for c, want in list(files.items()):   # a header in another case: matched, noted
            if want in names:
                continue
            same = [n for n in names if n.lower() == want.lower()]
            if len(same) == 1:
                files[c] = same[0]
                self.header_notes.append(f"column {c!r} read from the header {same[0]!r} "
                                         "(matched ignoring case)")
        missing = [c for c in self.required if files[c] not in names]
        if missing:
            c = missing[0]
            mapped = f" (mapped to {files[c]!r} by columns)" if c in self.mapping else ""
            # never a header another column reads (a hint must not read one sensor twice)
            taken = {files[k].lower() for k in files if k != c}
            close = difflib.get_close_matches(files[c].lower(), [n.lower() for n in names
                                                                 if n.lower() not in taken],
                                              n=1, cutoff=0.6)
            near = next((n for n in names if close and n.lower() == close[0]), None)
            mean = f"; did you mean {near!r}?" if near else ""
            raise self._error(f"not in the header{mapped}: expected the columns "
                              f"{', '.join(self.required)} (or map other names, "
                              f"--columns {c}=NAME); found {shown}, separated by {sep}{mean}",
                              row=line_no, column=c,
                              hint=f"--columns {c}={near}" if near else None)
        use = list(self.required)
        if self.one_of:
            present = [c for c in self.one_of if files[c] in names]
            if len(present) != 1:
                what = "neither" if not present else "both"
                raise self._error(f"expected exactly one of the columns "
                                  f"{' or '.join(self.one_of)}; found {what} (header: {shown})",
                                  row=line_no, column=self.one_of[0])
            use.append(present[0])
        use += [c for c in self.optional if files[c] in names]
        self.files = files
        return use, [names.index(files[c]) for c in use]

    # locating a fault the fast reader stopped at (the slow path: errors only)
    def _scan(self, header_line: int, delim: str, n_fields: int, use: list[str],
              idx: list[int], stop_row: int | None = None):
        """Walk the data lines in Python: raise the first fault with its line and column,
        or, with ``stop_row``, return the line number of data row ``stop_row`` (0-based)."""
        stream, raw, _ = self._open()
        try:
            data = stream.read()
        finally:
            stream.close()
            raw.close()
        if data.startswith(_BOM):
            data = data[len(_BOM):]
        row = -1
        t_prev = -math.inf
        for line_no, raw_line in enumerate(data.splitlines(), start=1):
            if line_no <= header_line:
                continue
            text = _decode(raw_line, self.label, line_no)
            s = text.strip()
            if not s or s.startswith("#") or line_no == self.units_line:
                continue
            row += 1
            if stop_row is not None and row == stop_row:
                return line_no
            cells = _fields(text, delim)
            if len(cells) != n_fields:
                raise self._error(f"expected {n_fields} fields separated by "
                                  f"{_DELIM_NAMES[delim]}, as in the header; got "
                                  f"{len(cells)}", row=line_no)
            values = []
            for name, i in zip(use, idx):
                cell = cells[i].strip()
                if self._comma:
                    cell = cell.replace(",", ".")
                if name == use[0] and self._iso_ns is not None and _ISO_TIME.fullmatch(cell):
                    ns, zoned = _iso_ns(cell)
                    if zoned != self._iso_zone:
                        raise self._error(
                            "expected an ISO date-time stamp " + (
                                "with a zone (Z or +hh:mm), as in the first row" if
                                self._iso_zone else "without a zone, as in the first row")
                            + f"; got {cell[:40]!r} (a mix of local and zoned stamps has no "
                            "one time scale)", row=line_no, column=name)
                    values.append((ns - self._iso_ns) / 1e9)
                    continue
                if name == use[0] and self._decimal_t and _is_number(cell):
                    if not _decimal_time_ok(decimal.Decimal(cell)):
                        raise self._error(
                            f"expected a time stamp with at most {TIME_DECIMALS} decimals "
                            f"below 1e{30 - TIME_DECIMALS} s (an offset clock is read exactly "
                            f"to 1 ns); got {cell[:40]!r}", row=line_no, column=name)
                if cell in NULL_VALUES or cell.lower() in NULL_VALUES:
                    values.append(math.nan)
                    continue
                if _is_number(cell):
                    values.append(float(cell))
                    continue
                hint = (" (a decimal comma? write 0.5, not 0,5)"
                        if delim != "," and re.fullmatch(r"[-+]?\d*,\d+", cell) else "")
                raise self._error(f"expected a number (or an empty cell / nan for a "
                                  f"missing value); got {cell[:40]!r}{hint}", row=line_no,
                                  column=name)
            # the checks of _check, in file order (the fast reader may stop further on)
            if self._decimal_t and math.isfinite(values[0]):
                cell0 = cells[idx[0]].strip()
                values[0] = float(decimal.Decimal(cell0.replace(",", ".") if self._comma
                                                  else cell0) - self._offset)
            elif self._offset is not None and self._iso_ns is None:
                values[0] -= float(self._offset)
            self._check(np.array([values]), 0, None, t_prev, line=line_no)
            t_prev = values[0] if self.has_time else t_prev
        return None

    def _line_of(self, ctx: dict, row: int) -> int | None:
        return self._scan(ctx["header_line"], ctx["delim"], ctx["n_fields"], ctx["use"],
                          ctx["idx"], stop_row=row)

    def _check(self, data: np.ndarray, first_row: int, ctx: dict | None, t_prev: float,
               line: int | None = None) -> None:
        """Finite, increasing time and no infinite value; the fault's line is ``line`` (one
        row) or found by a scan of the file."""
        if line is None:
            def where(r: int) -> int | None:
                return self._line_of(ctx, first_row + r)
        else:
            def where(r: int) -> int | None:
                return line
        inf = np.isinf(data[:, 1:] if self.has_time else data)
        if not self.has_time:
            if np.any(inf):
                r, c = (int(x[0]) for x in np.nonzero(inf))
                raise self._error("expected a finite number (or empty / nan for a missing "
                                  "value); got inf", row=where(r), column=self.use[c])
            return
        t = data[:, 0]
        bad = ~np.isfinite(t)
        if np.any(bad):
            r = int(np.nonzero(bad)[0][0])
            what = "an empty cell" if np.isnan(t[r]) else repr(float(t[r]))
            raise self._error(f"expected a finite time (s); got {what}",
                              row=where(r), column="t")
        far = np.abs(t) > MAX_TIME
        if np.any(far):
            r = int(np.nonzero(far)[0][0])
            raise self._error(f"a time of {float(t[r]):.6g} s from the record's start: "
                              f"expected at most {MAX_TIME:g} s (a corrupted time stamp?)",
                              row=where(r), column="t")
        prev = np.concatenate([[t_prev], t[:-1]])
        bad = t <= prev
        if np.any(bad):
            r = int(np.nonzero(bad)[0][0])
            raise self._error(f"time must be strictly increasing; got {float(t[r])!r} after "
                              f"{float(prev[r])!r}", row=where(r), column="t")
        if np.any(inf):
            r, c = (int(x[0]) for x in np.nonzero(inf))
            raise self._error("expected a finite number (or empty / nan for a missing "
                              "value); got inf", row=where(r), column=self.use[c + 1])

    def _batches(self, rest: _Rest, delim: str, n_fields: int, idx: list[int],
                 offset: decimal.Decimal | None):
        import pyarrow as pa
        from pyarrow import csv as pacsv

        names = [f"c{i}" for i in range(n_fields)]
        keep = [names[i] for i in idx]
        dec = pa.decimal128(30, TIME_DECIMALS)
        types = {c: pa.float64() for c in keep}
        if offset is not None:
            types[keep[0]] = dec
        if self._iso_ns is not None:     # stamps with a zone read as UTC
            types[keep[0]] = pa.timestamp("ns", tz="UTC" if self._iso_zone else None)

        def invalid(row) -> str:       # a comment or blank line inside the data
            s = row.text.strip()
            return "skip" if not s or s.startswith("#") else "error"

        reader = pacsv.open_csv(
            rest,
            read_options=pacsv.ReadOptions(column_names=names, block_size=self.block_bytes),
            parse_options=pacsv.ParseOptions(delimiter=delim, quote_char='"',
                                             ignore_empty_lines=True,
                                             invalid_row_handler=invalid),
            convert_options=pacsv.ConvertOptions(
                column_types=types, include_columns=keep,
                decimal_point="," if self._comma else ".",
                null_values=list(NULL_VALUES), quoted_strings_can_be_null=True))
        try:
            for batch in reader:
                if batch.num_rows:
                    cols = [batch.column(c) for c in keep]
                    if self._iso_ns is not None:   # ns since the epoch, less the offset, exact
                        ns = np.asarray(cols[0].cast(pa.int64()).fill_null(self._iso_ns - 1)
                                        .to_numpy(zero_copy_only=False))
                        sec = (ns - self._iso_ns) / 1e9
                        if cols[0].null_count:
                            sec[np.asarray(cols[0].is_null().to_numpy(zero_copy_only=False))] = \
                                np.nan
                        cols[0] = pa.array(sec, type=pa.float64())
                    if offset is not None:      # exact decimal difference, then one rounding
                        import pyarrow.compute as pc  # only for an absolute clock (50 ms)

                        cols[0] = pc.cast(pc.subtract(cols[0], pa.scalar(offset, dec)),
                                          pa.float64())
                    yield _float_matrix(cols)
        finally:
            _stop_reading(reader, rest)

    def _iso_base(self, delim: str, i_t: int):
        """For ISO 8601 date-time stamps in the first row: ``(offset text, source, True)``,
        the stamps read to 1 ns and taken relative to the first row, or to ``t0`` seconds
        after it; else None."""
        if self.first_line is None:
            return None
        cells = _fields(self.first_line, delim)
        cell = cells[i_t].strip().strip('"') if i_t < len(cells) else ""
        if not _ISO_TIME.fullmatch(cell):
            return None
        first, self._iso_zone = _iso_ns(cell)
        self._iso_ns = first + (round(self.t0 * 1e9) if self.t0 is not None else 0)
        self._iso_text = cell
        return (decimal.Decimal(self._iso_ns) / decimal.Decimal(10**9),
                "t0" if self.t0 is not None else "iso", True)

    def _time_base(self, delim: str, i_t: int) -> tuple[decimal.Decimal | None, str, bool]:
        """The offset subtracted from the time stamps and why (``t0`` when given, else the
        first row's time when it is an absolute clock), and whether the time column is read
        as decimals (an absolute clock: the offset is then subtracted exactly)."""
        first = None
        if self.first_line is not None:
            cells = _fields(self.first_line, delim)
            try:
                cell = cells[i_t].strip() if i_t < len(cells) else ""
                first = decimal.Decimal(cell.replace(",", ".") if self._comma else cell)
            except decimal.InvalidOperation:
                first = None
        absolute = (first is not None and first.is_finite() and abs(first) >= ABSOLUTE_TIME
                    and math.isfinite(float(first)))
        exact = absolute and _decimal_time_ok(first)
        if self.t0 is not None:
            t0 = decimal.Decimal(repr(self.t0))
            return (t0.quantize(decimal.Decimal(1).scaleb(-TIME_DECIMALS)) if exact else t0,
                    "t0", exact)
        if absolute:        # beyond the decimal reading: subtracted as doubles
            return first, "first row", exact
        return None, "none", False

    def __iter__(self) -> Iterator[tuple[list[str], np.ndarray]]:
        """Chunks ``(columns, data)`` of :attr:`chunk_rows` rows (the last one shorter).

        In four roles: :meth:`_layout` reads the lines before the data (header, columns,
        units, time base); :meth:`_parsed` the Arrow batches as float arrays (a fault
        located and named); :meth:`_prepared` each array as the record's (offset, rows
        before ``t0`` dropped, units, checks); :func:`_rechunked` them in chunks.  The
        file and pyarrow's streaming reader are closed when the iteration ends, whether it
        is exhausted, fails or is abandoned (``close()``): a streaming reader left to the
        interpreter's exit reads on in pyarrow's threads, which can abort the process
        ("terminate called without an active exception")."""
        stream, raw, size = self._open()
        batches = None
        try:
            lay = self._layout(stream)
            rest = _Rest(lay.after, stream)
            batches = self._batches(rest, lay.delim, len(lay.names), lay.idx,
                                    lay.offset if lay.exact and self._iso_ns is None
                                    else None)
            state = {"rows": 0, "dropped": 0, "t_prev": -math.inf}
            blocks = (self._prepared(data, lay, state, raw, size)
                      for data in self._parsed(batches, lay))
            for out in _rechunked((b for b in blocks if b.shape[0]), self.chunk_rows):
                yield lay.use, out
            if state["rows"] == 0:
                raise self._error("has a header but no data rows"
                                  + (f" at or after t0 = {self.t0:g} s ({state['dropped']} "
                                     "before it)" if state["dropped"] else ""),
                                  row=lay.header_line)
            if rest.empty_rows and self.info is not None:
                self.info = dataclasses.replace(self.info, empty_rows=rest.empty_rows)
        finally:
            if batches is not None:
                batches.close()         # its finally closes pyarrow's reader
            stream.close()
            raw.close()

    def _layout(self, stream) -> _Layout:
        """The lines before the data read (:meth:`_preamble`), the columns found, the
        decimal separator, the units row's factors and the time base."""
        try:
            names, header_line, delim, after = self._preamble(stream)
        except (gzip.BadGzipFile, EOFError, OSError) as exc:
            if isinstance(exc, RecordError):
                raise
            raise self._error(f"cannot be read as a (gzip) CSV file: {exc}") from None
        use, idx = self._columns(names, header_line, delim)
        self.use = use
        self._comma = self._decimal_comma(delim, idx, header_line)
        self.col_factor = self._row_factors(use)
        if self.has_time:
            offset, source, exact = self._iso_base(delim, idx[0]) or self._time_base(
                delim, idx[0])
        else:
            offset, source, exact = None, "none", False
        self._decimal_t = exact and self._iso_ns is None
        self._offset = offset
        return _Layout(names=names, header_line=header_line, delim=delim, after=after,
                       use=use, idx=idx, offset=offset, source=source, exact=exact)

    def _parsed(self, batches, lay: _Layout) -> Iterator[np.ndarray]:
        """The float arrays of pyarrow's batches; a fault pyarrow stops at is located by a
        scan of the file (:meth:`_scan`) and raised with its line and column."""
        import pyarrow as pa

        while True:
            try:
                data = next(batches, None)
            except (pa.ArrowInvalid, pa.ArrowException) as exc:
                if str(exc).startswith("Empty CSV file"):
                    return              # nothing after the header: said by __iter__
                self._scan(lay.header_line, lay.delim, len(lay.names), lay.use, lay.idx)
                raise self._error("cannot be read as CSV: "
                                  + " ".join(str(exc).split())) from None
            except (gzip.BadGzipFile, EOFError, OSError) as exc:
                raise self._error(f"cannot be read as a (gzip) CSV file: {exc}") from None
            if data is None:
                return
            yield data

    def _prepared(self, data: np.ndarray, lay: _Layout, state: dict, raw,
                  size: int) -> np.ndarray:
        """One parsed array as the record's: the time offset subtracted, rows before
        ``t0`` dropped (counted in ``state``), the columns converted to SI, the rows
        checked (:meth:`_check`); sets :attr:`info` at the first rows."""
        if lay.offset is not None and not lay.exact:
            data[:, 0] -= float(lay.offset)
        if lay.source == "t0" and self.info is None:       # rows before t0: dropped
            before = ~(data[:, 0] >= 0.0) & ~np.isnan(data[:, 0])
            lead = int(np.argmin(before)) if not np.all(before) else len(data)
            data = data[lead:]
            state["dropped"] += lead
        if data.shape[0] == 0:
            return data
        for j, c in enumerate(lay.use):     # the units row, --time-unit, ...
            f = self.col_factor.get(c, self.units.get(UNIT_KINDS.get(c, ""), 1.0))
            if f != 1.0:
                data[:, j] *= f
        ctx = {"header_line": lay.header_line, "delim": lay.delim,
               "n_fields": len(lay.names), "use": lay.use, "idx": lay.idx}
        self._check(data, state["rows"] + state["dropped"], ctx, state["t_prev"])
        state["t_prev"] = float(data[-1, 0])
        if self.info is None:
            self.info = RecordInfo(
                path=self.label, delimiter=lay.delim, header_line=lay.header_line,
                columns={c: self.files[c] for c in lay.use}, latitude=self.latitude,
                t_offset=float(lay.offset or 0.0), t_offset_source=lay.source,
                t_offset_text=(f"iso {self._iso_text}" if self._iso_ns is not None
                               else str(lay.offset or 0)),
                t_exact=lay.exact, rows_dropped=state["dropped"],
                header_notes=tuple(self.header_notes))
        state["rows"] += data.shape[0]
        self.fraction = min(1.0, raw.tell() / size) if size else 1.0
        return data


def _stop_reading(reader, rest: _Rest) -> None:
    """Stop pyarrow's streaming CSV ``reader`` of ``rest`` for good, before the reader is
    dropped: an iteration abandoned early (a refusal at the door, an error) leaves its
    read-ahead running in pyarrow's I/O threads, reading ``rest`` through the GIL; at the
    interpreter's exit those threads are then stopped inside Python, and the process
    aborts ("terminate called without an active exception", status 134) or hangs in
    pyarrow's thread-pool shutdown.  So: the reads under way finish, every later read is
    the end of the file (:meth:`_Rest.stop`), the reader is drained to that end (its
    read-ahead has then finished), and closed."""
    import pyarrow as pa

    rest.stop()
    try:
        while True:
            reader.read_next_batch()
    except (StopIteration, pa.ArrowException, OSError, ValueError):
        pass                    # the end, or a row cut short by the stop: either way done
    reader.close()


@dataclasses.dataclass(frozen=True)
class _Layout:
    """What :meth:`_Reader._layout` found before the data: the header's ``names``, its line
    ``header_line``, the separator ``delim``, the bytes read beyond the header ``after``,
    the columns read ``use`` at the header positions ``idx``, and the time base (``offset``
    subtracted, its ``source``, whether the stamps are read ``exact`` as decimals)."""

    names: list
    header_line: int
    delim: str
    after: bytes
    use: list
    idx: list
    offset: decimal.Decimal | None
    source: str
    exact: bool


def _rechunked(blocks, rows: int) -> Iterator[np.ndarray]:
    """The arrays ``blocks`` regrouped in chunks of ``rows`` rows (the last one shorter).

    >>> [c.shape[0] for c in _rechunked([np.zeros((3, 1)), np.zeros((4, 1))], 2)]
    [2, 2, 2, 1]
    """
    pending: list[np.ndarray] = []
    held = 0
    for data in blocks:
        pending.append(data)
        held += data.shape[0]
        while held >= rows:
            block = pending[0] if len(pending) == 1 else np.concatenate(pending)
            out, rest = block[:rows], block[rows:]
            pending, held = ([rest] if rest.shape[0] else []), rest.shape[0]
            yield out
    if held:
        yield pending[0] if len(pending) == 1 else np.concatenate(pending)


def iter_csv(path: object, required: Sequence[str], *, one_of: Sequence[str] = (),
             optional: Sequence[str] = (), chunk_rows: int = CHUNK_ROWS,
             columns: Mapping[str, str] | None = None, t0: float | None = None,
             units: Mapping[str, str | None] | None = None,
             decimal_comma: bool | None = None,
             ) -> Iterator[tuple[list[str], np.ndarray]]:
    """Chunks ``(columns, data)`` of a CSV record: ``data`` is ``(rows, len(columns))`` float,
    the ``required`` columns in that order, then the one column of ``one_of`` present, then
    those of ``optional`` present.  ``columns`` maps a column to the file's header name;
    ``t0`` (s) is subtracted from every time (default: the first row's time when it is an
    absolute clock, see :data:`ABSOLUTE_TIME`).

    Raises :class:`RecordError` (one line naming the file, line and column) for a missing
    file, an empty or non-text file, a byte that is not UTF-8, a missing column, a row with
    another number of fields than the header, a non-numeric cell, a non-finite or
    non-increasing time.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "r.csv"
    >>> _ = p.write_bytes(b'\\xef\\xbb\\xbf# comment\\r\\nt;x;extra\\r\\n'
    ...                   b'0.1;"1.5";a\\r\\n0.2;;b\\r\\n')
    >>> [(cols, d.tolist()) for cols, d in iter_csv(p, ["t", "x"])]
    [(['t', 'x'], [[0.1, 1.5], [0.2, nan]])]
    """
    return iter(_Reader(path, required, one_of, chunk_rows, optional, columns=columns,
                        units=units, decimal_comma=decimal_comma,
                        t0=t0))


def read_csv(path: object, required: Sequence[str], *, one_of: Sequence[str] = (),
             optional: Sequence[str] = (), columns: Mapping[str, str] | None = None,
             t0: float | None = None, return_info: bool = False,
             units: Mapping[str, str | None] | None = None,
             decimal_comma: bool | None = None):
    """The whole record at once: ``(columns, data)`` as :func:`iter_csv` (and the
    :class:`RecordInfo` as a third item with ``return_info=True``)."""
    reader = _Reader(path, required, one_of, CHUNK_ROWS, optional, columns=columns, t0=t0,
                     units=units, decimal_comma=decimal_comma)
    cols: list[str] = []
    parts = []
    for names, data in reader:
        cols = names
        parts.append(data)
    out = (cols, np.concatenate(parts))
    return (*out, reader.info) if v.check_bool("return_info", return_info) else out


def _float_matrix(cols) -> np.ndarray:
    """The float64 Arrow arrays ``cols`` (equal lengths) as one ``(rows, len(cols))`` float
    array, a null as NaN, read from the arrays' buffers.  ``pyarrow.Array.to_numpy`` gives
    the same values but imports pandas on its first call (0.15–0.35 s of a command's
    start-up, for nothing: benchmarks/bench_calibrate.py)."""
    n = len(cols[0])
    out = np.empty((n, len(cols)))
    for j, c in enumerate(cols):
        if str(c.type) != "double" or len(c) != n:
            raise TypeError(f"expected float64 columns of {n} rows; got {c.type}, {len(c)}")
        valid, data = c.buffers()[:2]
        if data is None:
            out[:, j] = np.nan
            continue
        out[:, j] = np.frombuffer(data, dtype=np.float64, count=c.offset + n)[c.offset:]
        if c.null_count:
            bits = np.unpackbits(np.frombuffer(valid, dtype=np.uint8), count=c.offset + n,
                                 bitorder="little")[c.offset:]
            out[bits == 0, j] = np.nan
    return out


def _gc_from(data: np.ndarray, latitude: float | None) -> GCRecord:
    return GCRecord(t=data[:, 0], angle_sensor=data[:, 1], inclinometer_y=data[:, 2],
                    inclinometer_z=data[:, 3], latitude=latitude)


def _door_params(params: GyrocompassParams | None, latitude: float | None,
                 site_from_record: bool) -> GyrocompassParams | None:
    """The parameters the door check reads a GC record with: ``params`` (default the
    paper's), with the Earth rate at the record's own ``# latitude_deg:`` line when it has
    one and no other states the site (``params`` None, or ``site_from_record``)."""
    if latitude is None or not (params is None or site_from_record):
        return params
    if not -math.pi / 2 < latitude < math.pi / 2:     # a pole: the calibration refuses it
        return params
    earth = GyrocompassParams.at_latitude(latitude)
    base = GyrocompassParams() if params is None else params
    return dataclasses.replace(base, Omega_h=earth.Omega_h, Omega_v=earth.Omega_v)


def _check_gc_start(label: str, t0: float) -> None:
    if t0 < 0.0:
        raise RecordError(label, f"expected times >= 0 (s since the feedback was switched "
                          f"off); the first row has t = {t0}", column="t")


class GCChunks:
    """Iterable of :class:`GCRecord` chunks of a file; ``fraction`` is the part of the file
    read so far (for a progress bar), ``info`` the :class:`RecordInfo` once the first chunk
    is read.  Each chunk is checked at the door (:func:`gyrolib.records.check_gc` with
    ``params``, default the paper's; the Earth rate that of the record's ``# latitude_deg:``
    line when ``params`` is None or ``site_from_record``) unless ``check=False``;
    ``columns`` and ``t0`` as in :func:`iter_csv`."""

    def __init__(self, path: object, *, chunk_rows: int = CHUNK_ROWS,
                 params: GyrocompassParams | None = None, check: bool = True,
                 site_from_record: bool = False,
                 columns: Mapping[str, str] | None = None, t0: float | None = None,
                 units: Mapping[str, str | None] | None = None,
                 decimal_comma: bool | None = None) -> None:
        self._reader = _Reader(path, GC_COLUMNS, (), chunk_rows, columns=columns, t0=t0,
                               units=units, decimal_comma=decimal_comma)
        self._params = params
        self._check = v.check_bool("check", check)
        self._site_from_record = v.check_bool("site_from_record", site_from_record)

    @property
    def fraction(self) -> float:
        return self._reader.fraction

    @property
    def info(self) -> RecordInfo | None:
        return self._reader.info

    def __iter__(self) -> Iterator[GCRecord]:
        first = True
        row = 0
        chunks = iter(self._reader)
        try:
            for _, data in chunks:
                if first:
                    _check_gc_start(self._reader.label, float(data[0, 0]))
                    first = False
                rec = _gc_from(data, self._reader.latitude)
                if self._check:
                    check_gc(rec, _door_params(self._params, rec.latitude,
                                               self._site_from_record),
                             label=self._reader.label, rows=(row + 1, row + rec.n))
                row += rec.n
                yield rec
        finally:        # a refusal or an abandoned run: the file and pyarrow's reader closed
            chunks.close()


def read_gc(path: object, *, params: GyrocompassParams | None = None, check: bool = True,
            site_from_record: bool = False,
            columns: Mapping[str, str] | None = None, t0: float | None = None,
            units: Mapping[str, str | None] | None = None,
            decimal_comma: bool | None = None,
            return_info: bool = False):
    """A whole paper-GC record file (see the module docstring for the format), checked at
    the door (:func:`gyrolib.records.check_gc` with ``params``; the Earth rate that of the
    record's ``# latitude_deg:`` line when ``params`` is None or ``site_from_record``) unless
    ``check=False``; ``(record, info)`` with ``return_info=True``.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "gc.csv"
    >>> _ = p.write_text("# latitude_deg: 53.9\\nt,angle_sensor,inclinometer_y,"
    ...                  "inclinometer_z\\n0.01,0,0,0\\n0.02,0,0,0\\n")
    >>> rec = read_gc(p, check=False)
    >>> f"{math.degrees(rec.latitude):.1f}", rec.n
    ('53.9', 2)
    """
    _, data, info = read_csv(path, GC_COLUMNS, columns=columns, t0=t0, return_info=True,
                             units=units, decimal_comma=decimal_comma)
    _check_gc_start(str(path), float(data[0, 0]))
    rec = _gc_from(data, info.latitude)
    site_from_record = v.check_bool("site_from_record", site_from_record)
    if v.check_bool("check", check):
        check_gc(rec, _door_params(params, rec.latitude, site_from_record), label=str(path))
    return (rec, info) if v.check_bool("return_info", return_info) else rec


def read_rsf(path: object, *, counts_per_rev: int | None = None, check: bool = True,
             columns: Mapping[str, str] | None = None, t0: float | None = None,
             units: Mapping[str, str | None] | None = None,
             decimal_comma: bool | None = None,
             return_info: bool = False):
    """A whole paper-RSF record file: ``t``, ``sins_increment`` and ``gs_angle`` or
    ``encoder_counts`` (then ``counts_per_rev`` is required), checked at the door
    (:func:`gyrolib.records.check_rsf`) unless ``check=False``; ``(record, info)`` with
    ``return_info=True``."""
    label = str(path)
    RSFRecord = _rsf_record()

    check = v.check_bool("check", check)
    return_info = v.check_bool("return_info", return_info)
    cols, data, info = read_csv(path, RSF_COLUMNS[:2], one_of=("gs_angle", "encoder_counts"),
                                optional=("gs_gyro_angle",), columns=columns, t0=t0,
                                units=units, decimal_comma=decimal_comma,
                                return_info=True)
    if cols[2] == "gs_angle":
        if counts_per_rev is not None:
            raise RecordError(label, "counts_per_rev given but the record has a gs_angle "
                              "column, not encoder_counts", column="gs_angle")
        if "gs_gyro_angle" in cols:
            raise RecordError(label, "a gs_gyro_angle column goes with encoder_counts; this "
                              "record has gs_angle (already the full GS angle)",
                              column="gs_gyro_angle")
        rec = RSFRecord(t=data[:, 0], sins_increment=data[:, 1], gs_angle=data[:, 2])
        if check:
            check_rsf(rec, label=label)
        return (rec, info) if return_info else rec
    if counts_per_rev is None:
        raise RecordError(label, "the record has encoder_counts: give the counts per "
                          "revolution (--counts-per-rev N)", column="encoder_counts")
    c = data[:, 2]
    ok = ~np.isnan(c)
    bad = ok & ((c != np.round(c)) | (c < 0) | (c >= counts_per_rev))
    if np.any(bad):
        r = int(np.nonzero(bad)[0][0])
        raise RecordError(label, f"expected whole counts in [0, {counts_per_rev}) (wrapped "
                          f"count, counts per revolution {counts_per_rev}); got {c[r]:g} at "
                          f"data row {r + 1}", column="encoder_counts")
    gyro = data[:, 3] if "gs_gyro_angle" in cols else None
    rec = RSFRecord(t=data[:, 0], sins_increment=data[:, 1], encoder_counts=c,
                    counts_per_rev=counts_per_rev, gs_gyro_angle=gyro)
    if check:
        check_rsf(rec, label=label)
    return (rec, info) if return_info else rec


# CSV writing ------------------------------------------------------------------------------
def write_csv(path: object, columns: dict[str, object], *, comments: Sequence[str] = (),
              fmt: str | Sequence[str] = "%.10g") -> Path:
    """Write ``columns`` (name → 1-D array, equal lengths) as a CSV record with ``#``
    ``comments`` above the header; gzip-compressed when ``path`` ends in ``.gz``
    (deterministic: no time stamp in the gzip header).  NaN is written as ``nan``."""
    path = Path(path)
    if not columns:
        raise ValueError("columns must name at least one column")
    arrays = [np.asarray(a, dtype=float) for a in columns.values()]
    n = arrays[0].size
    if any(a.ndim != 1 or a.size != n for a in arrays):
        raise ValueError("columns must be 1-D arrays of equal length")
    buf = io.StringIO()
    for c in comments:
        buf.write(f"# {c}\n")
    buf.write(",".join(columns) + "\n")
    # the rows as np.savetxt writes them (one printf format a column, or one for the row),
    # formatted from Python floats in one pass: half savetxt's time on 10^5 rows
    if isinstance(fmt, str):
        row = fmt if fmt.count("%") > 1 else ",".join([fmt] * len(arrays))
    else:
        if len(fmt) != len(arrays):
            raise ValueError(f"fmt has {len(fmt)} formats for {len(arrays)} columns")
        row = ",".join(fmt)
    buf.write("".join(map((row + "\n").__mod__, zip(*(a.tolist() for a in arrays)))))
    data = buf.getvalue().encode()
    if path.name.endswith(".gz"):
        with open(path, "wb") as fh, gzip.GzipFile(fileobj=fh, mode="wb", mtime=0,
                                                   filename="") as gz:
            gz.write(data)
    else:
        path.write_bytes(data)
    return path
