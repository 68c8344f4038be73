"""Measurement records as CSV files: reading (plain or ``.csv.gz``, in chunks), checking and
writing.

A record file has one header line naming its columns, optionally preceded by ``#`` comment
lines (comment and blank lines are skipped anywhere); columns are separated by commas; extra
columns are ignored.  Cells are numbers; an empty cell or ``nan`` is a missing value (the
calibration skips that one measurement).  Time ``t`` (s) must be finite and strictly
increasing.  Anything else raises :class:`~gyrolib.records.RecordError` naming the file, the
line and the column.

A file is read in chunks of :data:`CHUNK_ROWS` rows; a chunk of plain numbers is parsed in one
compiled pass over its bytes (:mod:`gyrolib.records._fastcsv`, the same values as Python's
``float``), any other chunk (comments, quotes, a bad cell, …) line by line, which names the
line and column of what is wrong.

* GC record (paper GC): ``t``, ``angle_sensor`` (rad), ``inclinometer_y``,
  ``inclinometer_z`` (m/s²) — :data:`GC_COLUMNS`, :class:`GCRecord`;
* RSF record (paper RSF): ``t``, ``sins_increment`` (rad) and ``gs_angle`` (rad, unwrapped)
  or ``encoder_counts`` (wrapped counts, optionally with ``gs_gyro_angle``) —
  :data:`RSF_COLUMNS`, :class:`RSFRecord`.
"""

from __future__ import annotations

import gzip
import io
import math
import os
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Final

import numpy as np

from gyrolib import _validation as v
from gyrolib.gc.logs.record import GCRecord
from gyrolib.gc.model.params import GyrocompassParams
from gyrolib.records._fastcsv import parse_rows
from gyrolib.records.errors import RecordError
from gyrolib.records.plausibility import check_gc, check_rsf
from gyrolib.rsf.record import RSFRecord

__all__ = [
    "GC_COLUMNS",
    "RSF_COLUMNS",
    "GCRecord",
    "RSFRecord",
    "iter_csv",
    "read_csv",
    "read_gc",
    "read_rsf",
    "write_csv",
]

#: Columns of a paper-GC record, in SI (s, rad, m/s², m/s²).
GC_COLUMNS: Final[tuple[str, ...]] = ("t", "angle_sensor", "inclinometer_y", "inclinometer_z")

#: Columns of a paper-RSF record (``gs_angle`` may be replaced by ``encoder_counts``).
RSF_COLUMNS: Final[tuple[str, ...]] = ("t", "sins_increment", "gs_angle")

#: Rows parsed at a time: a chunk of 65 536 rows of four columns is 2 MB.
CHUNK_ROWS: Final[int] = 65536

#: Bytes read at a time at least (the header, the comment lines before it).
BLOCK_BYTES: Final[int] = 1 << 20

_MISSING: Final[frozenset[str]] = frozenset({"", "nan", "+nan", "-nan"})


# CSV reading ------------------------------------------------------------------------------
def _open_binary(path: Path) -> tuple[object, object, int]:
    """Byte stream (decompressed for ``.gz``), the raw file (for progress) and its size."""
    raw = open(path, "rb")
    size = os.fstat(raw.fileno()).st_size
    stream = gzip.GzipFile(fileobj=raw, mode="rb") if path.name.endswith(".gz") else raw
    return stream, raw, size


def _decode(line: bytes) -> str:
    return line.decode("utf-8")


def _is_comment(line: str) -> bool:
    s = line.strip()
    return not s or s.startswith("#")


#: ASCII characters that ``str.splitlines`` ends a line at, besides ``\n`` and ``\r``.
_OTHER_LINE_ENDS: Final[tuple[bytes, ...]] = (b"\x0b", b"\x0c", b"\x1c", b"\x1d", b"\x1e")


class _Lines:
    """The bytes of a file as lines, read in blocks: whole lines for the fast path
    (:func:`gyrolib.records._fastcsv.parse_rows` on :attr:`buf` from :attr:`pos`) and one
    decoded line at a time for the exact path.  A line ends at ``\n``, ``\r\n`` or a lone
    ``\r``, as in a text stream opened with ``newline=""``."""

    def __init__(self, stream, block: int) -> None:
        self.stream = stream
        self.block = block
        self.buf = b""
        self.pos = 0
        self.eof = False

    def _read(self, want: int) -> None:
        data = self.stream.read(max(want, self.block))
        self.buf = self.buf[self.pos:] + data
        self.pos = 0
        if not data:
            self.eof = True
            if self.buf and not self.buf.endswith(b"\n"):
                # the last line's end (a lone \r stays a line end: \r\n)
                self.buf += b"\n"

    def fill(self, lines: int, line_bytes: float) -> int:
        """Read until the buffer holds ``lines`` line ends after :attr:`pos` (or the file
        ends); return the end of its last whole line (``len(buf)`` at the end of file)."""
        while not self.eof and self.buf.count(b"\n", self.pos) < lines:
            self._read(int(lines * line_bytes * 1.1) + 4096)
        if self.eof:
            return len(self.buf)
        return self.buf.rindex(b"\n", self.pos) + 1

    def split(self, end: int) -> tuple[bool, list]:
        """The whole lines from :attr:`pos` to ``end`` (a line end): ``(True, str lines)``
        for an ASCII block without the other characters ``str.splitlines`` ends a line at,
        else ``(False, bytes lines)`` to decode one by one (``bytes.splitlines`` ends lines
        exactly at ``\n``, ``\r\n`` and ``\r``, as a text stream with ``newline=""``).
        A str line's length is its length in bytes; the caller moves :attr:`pos`."""
        block = self.buf[self.pos:end]
        if block.isascii() and not any(c in block for c in _OTHER_LINE_ENDS):
            return True, block.decode("ascii").splitlines(keepends=True)
        return False, block.splitlines(keepends=True)

    def next_line(self) -> str | None:
        """The next line with its line end, decoded (None at the end of the file)."""
        while True:
            i = self.buf.find(b"\n", self.pos)
            j = self.buf.find(b"\r", self.pos, i if i >= 0 else len(self.buf))
            if j >= 0 and (j + 1 < len(self.buf) or self.eof):
                end = j + 2 if j + 1 < len(self.buf) and self.buf[j + 1] == 10 else j + 1
                break
            if i >= 0 and j < 0:
                end = i + 1
                break
            if self.eof:
                if self.pos >= len(self.buf):
                    return None
                end = len(self.buf)
                break
            self._read(self.block)
        line = self.buf[self.pos:end]
        self.pos = end
        return line.decode("utf-8")


class _Reader:
    """Iterates over a CSV record in chunks of rows, checking as it goes."""

    def __init__(self, path: object, required: Sequence[str], one_of: Sequence[str] = (),
                 chunk_rows: int = CHUNK_ROWS, optional: Sequence[str] = (),
                 fast: bool = True) -> None:
        if not isinstance(path, str | os.PathLike):
            raise TypeError(f"path must be a str or path; got {type(path).__name__}")
        self.path = Path(path)
        self.label = str(path)
        self.required = tuple(required)
        self.one_of = tuple(one_of)
        self.optional = tuple(optional)
        self.chunk_rows = v.check_int("chunk_rows", chunk_rows, 1)
        self.fast = v.check_bool("fast", fast)
        self.fraction = 0.0

    def _error(self, message: str, **kw) -> RecordError:
        return RecordError(self.label, message, **kw)

    def _header(self, lines: _Lines) -> tuple[list[str], int]:
        line_no = 0
        while (line := lines.next_line()) is not None:
            line_no += 1
            if "\x00" in line:
                raise self._error("not a text CSV file (it holds NUL bytes)")
            if _is_comment(line):
                continue
            names = [c.strip().strip('"').strip("'") for c in line.rstrip("\r\n").split(",")]
            return names, line_no
        want = ", ".join(self.required)
        raise self._error(f"is empty: expected a header line naming the columns {want}")

    def _columns(self, names: list[str], line_no: int) -> tuple[list[str], list[int]]:
        seen = set()
        for nm in names:
            if nm in seen and nm in (*self.required, *self.one_of):
                raise self._error(f"column {nm!r} appears twice in the header", row=line_no)
            seen.add(nm)
        missing = [c for c in self.required if c not in names]
        shown = (", ".join(repr(n[:30]) for n in names[:8])
                 + (" ..." if len(names) > 8 else ""))
        if missing:
            raise self._error(f"not in the header: expected the columns "
                              f"{', '.join(self.required)}; found {shown}",
                              row=line_no, column=missing[0])
        use = list(self.required)
        if self.one_of:
            present = [c for c in self.one_of if c in names]
            if len(present) != 1:
                what = "neither" if not present else "both"
                raise self._error(f"expected exactly one of the columns "
                                  f"{' or '.join(self.one_of)}; found {what} (header: {shown})",
                                  row=line_no, column=self.one_of[0])
            use.append(present[0])
        use += [c for c in self.optional if c in names]
        return use, [names.index(c) for c in use]

    def _parse_slow(self, lines: list[str], line_nos: list[int], use: list[str],
                    idx: list[int]) -> np.ndarray:
        """Cell by cell, to say exactly which cell is wrong (the fast path failed)."""
        out = np.empty((len(lines), len(idx)))
        need = max(idx) + 1
        for r, (line, ln) in enumerate(zip(lines, line_nos)):
            cells = line.rstrip("\r\n").split(",")
            if len(cells) < need:
                raise self._error(f"expected at least {need} comma-separated fields (the "
                                  f"header's columns up to {use[idx.index(max(idx))]!r}); got "
                                  f"{len(cells)}", row=ln)
            for c, (name, i) in enumerate(zip(use, idx)):
                cell = cells[i].strip().strip('"')
                if cell.lower() in _MISSING:
                    out[r, c] = math.nan
                    continue
                try:
                    out[r, c] = float(cell)
                except ValueError:
                    raise self._error(f"expected a number (or an empty cell / nan for a "
                                      f"missing value); got {cell[:40]!r}", row=ln,
                                      column=name) from None
        return out

    def _check(self, data: np.ndarray, line_nos: np.ndarray, use: list[str],
               t_prev: float) -> None:
        t = data[:, 0]
        bad = ~np.isfinite(t)
        if np.any(bad):
            r = int(np.nonzero(bad)[0][0])
            raise self._error(f"expected a finite time (s); got {t[r]}", row=int(line_nos[r]),
                              column="t")
        prev = np.concatenate([[t_prev], t[:-1]])
        bad = t <= prev
        if np.any(bad):
            r = int(np.nonzero(bad)[0][0])
            raise self._error(f"time must be strictly increasing; got {float(t[r])!r} after "
                              f"{float(prev[r])!r}", row=int(line_nos[r]), column="t")
        inf = np.isinf(data[:, 1:])
        if np.any(inf):
            r, c = (int(x[0]) for x in np.nonzero(inf))
            raise self._error("expected a finite number (or empty / nan for a missing "
                              "value); got inf", row=int(line_nos[r]), column=use[c + 1])

    def _exact(self, lines: _Lines, line_no: int, use: list[str], idx: list[int],
               line_bytes: float) -> tuple[np.ndarray | None, np.ndarray, int]:
        """The next chunk line by line (comments and blank lines skipped, every cell checked
        with its line number): ``(data or None at the end, line numbers, last line)``."""
        chunk: list[str] = []
        nos: list[int] = []
        while len(chunk) < self.chunk_rows:
            end = lines.fill(self.chunk_rows - len(chunk), line_bytes)
            if lines.pos >= end:
                break
            text, block = lines.split(end)
            first = line_no
            for line in block if text else map(_decode, block):
                line_no += 1
                if _is_comment(line):
                    continue
                chunk.append(line)
                nos.append(line_no)
                if len(chunk) >= self.chunk_rows:
                    break
            lines.pos += sum(map(len, block[:line_no - first]))
        if not chunk:
            return None, np.zeros(0, dtype=np.int64), line_no
        if "\x00" in "".join(chunk):
            raise self._error("not a text CSV file (it holds NUL bytes)", row=nos[0])
        try:
            data = np.loadtxt(chunk, delimiter=",", usecols=idx, dtype=float, ndmin=2,
                              comments=None, quotechar='"')
        except ValueError:
            data = self._parse_slow(chunk, nos, use, idx)
        return data, np.asarray(nos), line_no

    def _fast(self, lines: _Lines, slot: np.ndarray, line_no: int, line_bytes: float
              ) -> tuple[np.ndarray, np.ndarray, int] | None:
        """The next chunk in one compiled pass (:func:`parse_rows`), or None when a line in
        it is not plain numbers (the caller then reads the chunk by :meth:`_exact`)."""
        end = lines.fill(self.chunk_rows, line_bytes)
        out = np.empty((self.chunk_rows, int(slot.max()) + 1))
        rows, pos, ok = parse_rows(np.frombuffer(lines.buf, dtype=np.uint8), lines.pos, end,
                                   slot, out)
        if not ok:
            return None
        lines.pos = pos
        data = out[:rows] if rows > self.chunk_rows // 2 else out[:rows].copy()
        return data, np.arange(line_no + 1, line_no + rows + 1), line_no + rows

    def __iter__(self) -> Iterator[tuple[list[str], np.ndarray]]:
        try:
            stream, raw, size = _open_binary(self.path)
        except FileNotFoundError:
            raise self._error("no such file") from None
        except IsADirectoryError:
            raise self._error("is a directory, not a CSV file") from None
        except PermissionError:
            raise self._error("cannot be read (permission denied)") from None
        try:
            lines = _Lines(stream, BLOCK_BYTES)
            names, line_no = self._header(lines)
            use, idx = self._columns(names, line_no)
            # field f of a line goes to column slot[f] of a chunk (-1: not used)
            slot = np.full(max(idx) + 1, -1, dtype=np.int64)
            slot[idx] = np.arange(len(idx))
            line_bytes = 64.0       # bytes per line, an estimate for the block reads
            t_prev = -math.inf
            n_rows = 0
            while True:
                start = lines.pos
                got = self._fast(lines, slot, line_no, line_bytes) if self.fast else None
                if got is None:
                    data, line_arr, line_no = self._exact(lines, line_no, use, idx,
                                                          line_bytes)
                    if data is None:
                        break
                else:
                    data, line_arr, line_no = got
                    if data.shape[0] == 0:
                        break
                    line_bytes = max((lines.pos - start) / data.shape[0], 8.0)
                self._check(data, line_arr, use, t_prev)
                t_prev = float(data[-1, 0])
                n_rows += data.shape[0]
                self.fraction = min(1.0, raw.tell() / size) if size else 1.0
                yield use, data
            if n_rows == 0:
                raise self._error("has a header but no data rows", row=line_no)
        except UnicodeDecodeError:
            raise self._error("not a text CSV file (cannot decode it as UTF-8)") from None
        except (gzip.BadGzipFile, EOFError, OSError) as exc:
            if isinstance(exc, RecordError):
                raise
            raise self._error(f"cannot be read as a (gzip) CSV file: {exc}") from None
        finally:
            stream.close()
            raw.close()


def iter_csv(path: object, required: Sequence[str], *, one_of: Sequence[str] = (),
             optional: Sequence[str] = (), chunk_rows: int = CHUNK_ROWS,
             ) -> Iterator[tuple[list[str], np.ndarray]]:
    """Chunks ``(columns, data)`` of a CSV record: ``data`` is ``(rows, len(columns))`` float,
    the ``required`` columns in that order, then the one column of ``one_of`` present, then
    those of ``optional`` present.

    Raises :class:`RecordError` (one line naming the file, line and column) for a missing
    file, an empty or non-text file, a missing column, a short row, a non-numeric cell, a
    non-finite or non-increasing time.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "r.csv"
    >>> _ = p.write_text("# comment\\nt,x,extra\\n0.1,1.5,a\\n0.2,,b\\n")
    >>> [(cols, d.tolist()) for cols, d in iter_csv(p, ["t", "x"])]
    [(['t', 'x'], [[0.1, 1.5], [0.2, nan]])]
    """
    return iter(_Reader(path, required, one_of, chunk_rows, optional))


def read_csv(path: object, required: Sequence[str], *, one_of: Sequence[str] = (),
             optional: Sequence[str] = ()) -> tuple[list[str], np.ndarray]:
    """The whole record at once: ``(columns, data)`` as :func:`iter_csv`."""
    cols: list[str] = []
    parts = []
    for names, data in iter_csv(path, required, one_of=one_of, optional=optional):
        cols = names
        parts.append(data)
    return cols, np.concatenate(parts)


def _gc_from(data: np.ndarray) -> GCRecord:
    return GCRecord(t=data[:, 0], angle_sensor=data[:, 1], inclinometer_y=data[:, 2],
                    inclinometer_z=data[:, 3])


def _check_gc_start(label: str, t0: float) -> None:
    if t0 < 0.0:
        raise RecordError(label, f"expected times >= 0 (s since the feedback was switched "
                          f"off); the first row has t = {t0}", column="t")


class GCChunks:
    """Iterable of :class:`GCRecord` chunks of a file; ``fraction`` is the part of the file
    read so far (for a progress bar).  Each chunk is checked at the door
    (:func:`gyrolib.records.check_gc` with ``params``, default the paper's) unless
    ``check=False``."""

    def __init__(self, path: object, *, chunk_rows: int = CHUNK_ROWS,
                 params: GyrocompassParams | None = None, check: bool = True) -> None:
        self._reader = _Reader(path, GC_COLUMNS, (), chunk_rows)
        self._params = params
        self._check = v.check_bool("check", check)

    @property
    def fraction(self) -> float:
        return self._reader.fraction

    def __iter__(self) -> Iterator[GCRecord]:
        first = True
        row = 0
        for _, data in self._reader:
            if first:
                _check_gc_start(self._reader.label, float(data[0, 0]))
                first = False
            rec = _gc_from(data)
            if self._check:
                check_gc(rec, self._params, label=self._reader.label,
                         rows=(row + 1, row + rec.n))
            row += rec.n
            yield rec


def read_gc(path: object, *, params: GyrocompassParams | None = None,
            check: bool = True) -> GCRecord:
    """A whole paper-GC record file (see the module docstring for the format), checked at
    the door (:func:`gyrolib.records.check_gc` with ``params``) unless ``check=False``."""
    _, data = read_csv(path, GC_COLUMNS)
    _check_gc_start(str(path), float(data[0, 0]))
    rec = _gc_from(data)
    if v.check_bool("check", check):
        check_gc(rec, params, label=str(path))
    return rec


def read_rsf(path: object, *, counts_per_rev: int | None = None,
             check: bool = True) -> RSFRecord:
    """A whole paper-RSF record file: ``t``, ``sins_increment`` and ``gs_angle`` or
    ``encoder_counts`` (then ``counts_per_rev`` is required), checked at the door
    (:func:`gyrolib.records.check_rsf`) unless ``check=False``."""
    label = str(path)
    check = v.check_bool("check", check)
    cols, data = read_csv(path, RSF_COLUMNS[:2], one_of=("gs_angle", "encoder_counts"),
                          optional=("gs_gyro_angle",))
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
        return rec
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
    return rec


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
    np.savetxt(buf, np.column_stack(arrays), delimiter=",", fmt=fmt)
    data = buf.getvalue().encode()
    if path.name.endswith(".gz"):
        with open(path, "wb") as fh, gzip.GzipFile(fileobj=fh, mode="wb", mtime=0,
                                                   filename="") as gz:
            gz.write(data)
    else:
        path.write_bytes(data)
    return path
