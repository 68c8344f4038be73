"""The CSV reader (pyarrow's CSV reader streamed in chunks, :mod:`gyrolib.records.reader`)
against an independent reference: Python's ``csv`` module and ``float`` on the same text.
The same values (correctly rounded: 0 units in the last place from ``float``), the same
faults found at the same line and column, on plain, gzip and awkward files (BOM, quoting,
CRLF, tabs, semicolons, a bad byte), on random files from a grammar of good and bad cells,
and the time base of a logger's absolute clock."""

from __future__ import annotations

import csv
import gzip
import math
import os
import random
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from gyrolib import records
from gyrolib.records import RecordError
from gyrolib.records.reader import GC_COLUMNS, _Reader

HEADER = ",".join(GC_COLUMNS)
ROOT = Path(__file__).resolve().parents[2]


def _read(path: Path, *, chunk_rows: int = 5000, required=GC_COLUMNS, optional=(),
          **kw) -> tuple[list[str], np.ndarray, list[int]]:
    cols: list[str] = []
    parts = []
    for names, data in _Reader(path, required, chunk_rows=chunk_rows, optional=optional, **kw):
        cols = names
        parts.append(data)
    return cols, np.concatenate(parts), [p.shape[0] for p in parts]


def _same(a: np.ndarray, b: np.ndarray) -> None:
    """The same doubles: 0 units in the last place apart (both convert the decimal text
    correctly rounded), NaN where NaN."""
    assert a.shape == b.shape
    np.testing.assert_array_equal(np.isnan(a), np.isnan(b))
    ok = ~np.isnan(a)
    np.testing.assert_array_max_ulp(a[ok], b[ok], maxulp=0)


def _reference(path: Path, delimiter: str = ",") -> np.ndarray:
    """Python's csv module and float on the file's text: the columns of GC_COLUMNS."""
    opener = gzip.open if path.name.endswith(".gz") else open
    with opener(path, "rt", encoding="utf-8-sig", newline="") as fh:
        rows = [r for r in csv.reader(fh, delimiter=delimiter)
                if r and not r[0].lstrip().startswith("#")]
    names = [c.strip() for c in rows[0]]
    idx = [names.index(c) for c in GC_COLUMNS]
    return np.array([[float(r[i]) if r[i].strip() not in ("", "nan") else math.nan
                      for i in idx] for r in rows[1:]])


def _table(n: int, seed: int) -> dict[str, np.ndarray]:
    rng = np.random.default_rng(seed)
    t = np.arange(1, n + 1) * 1e-3
    return {"t": t, "angle_sensor": rng.normal(0.0, 1e-5, n) + 1e-3 * t,
            "inclinometer_y": rng.normal(0.0, 1e-3, n),
            "inclinometer_z": rng.normal(0.0, 1e-3, n) * 10.0 ** rng.integers(-6, 8, n)}


@pytest.fixture(scope="module")
def plain(tmp_path_factory):
    """22 222 rows in the formats records are written with (%.9g, %.17g, %e, fixed)."""
    d = tmp_path_factory.mktemp("csv")
    cols = _table(22222, 1)
    files = {}
    for name, fmt in (("g9", ["%.3f", "%.9g", "%.9g", "%.9g"]),
                      ("g17", ["%.3f", "%.17g", "%.17g", "%.17g"]),
                      ("e", ["%.6f", "%.8e", "%.12e", "%.3e"]),
                      ("g25", ["%.3f", "%.25g", "%.25g", "%.25g"])):
        files[name] = records.write_csv(d / f"{name}.csv", cols, fmt=fmt)
    files["gz"] = records.write_csv(d / "g9.csv.gz", cols, fmt=["%.3f", "%.9g", "%.9g", "%.9g"])
    return files, cols


@pytest.mark.parametrize("name", ["g9", "g17", "e", "g25", "gz"])
def test_values_are_those_of_python_float(plain, name):
    """Every value as Python's float reads the text (0 ulp), in chunks of chunk_rows."""
    files, cols = plain
    names, data, sizes = _read(files[name], block_bytes=1 << 16)
    assert names == list(GC_COLUMNS)
    _same(data, _reference(files[name]))
    assert sizes[:4] == [5000] * 4 and sum(sizes) == 22222
    written = np.column_stack(list(cols.values()))     # and the values written
    np.testing.assert_allclose(data, written, rtol=1e-8 if name in ("g9", "gz") else 1e-3)


def test_written_text_is_savetxts(tmp_path):
    """records.write_csv writes each row as np.savetxt does (its printf formats, one a
    column or one for all, NaN and infinities included), byte for byte; a format too few is
    refused."""
    import io

    cols = _table(3000, 2)
    cols["inclinometer_y"][[5, 17]] = [np.nan, -np.inf]
    for fmt in (["%.6f", "%.12g", "%.3e", "%.17g"], "%.10g"):
        path = records.write_csv(tmp_path / "w.csv", cols, fmt=fmt, comments=["x: 1"])
        ref = io.StringIO()
        np.savetxt(ref, np.column_stack(list(cols.values())), delimiter=",", fmt=fmt)
        assert path.read_text() == "# x: 1\n" + ",".join(cols) + "\n" + ref.getvalue()
    with pytest.raises(ValueError, match="fmt has 3 formats for 4 columns"):
        records.write_csv(tmp_path / "x.csv", cols, fmt=["%g"] * 3)


@pytest.mark.parametrize("gz", [False, True])
@pytest.mark.parametrize(("line", "cell", "expect"), [
    (12345, "abc", "line 12345, column 'inclinometer_y': expected a number"),
    (17001, None, "line 17001, column 't': time must be strictly increasing"),
    (9999, "", "line 9999, column 't': expected a finite time"),
    (20000, "inf", "line 20000, column 'inclinometer_y': expected a finite number"),
    (15000, "short", "line 15000: expected 4 fields separated by commas"),
    (21000, b"1.5\xff", "line 21000: not UTF-8 text: byte 0xff"),
])
def test_a_bad_cell_deep_in_a_file_is_named(plain, tmp_path, gz, line, cell, expect):
    """Line numbers count the header (line 1) and every line; nothing is yielded after the
    fault, and the message is one line naming the file."""
    files, _ = plain
    lines = files["g9"].read_bytes().splitlines(keepends=True)
    f = lines[line - 1].rstrip(b"\n").split(b",")
    if cell == "short":
        f = f[:3]
    elif cell is None:
        f[0] = b"0.5"
    elif cell == "":
        f[0] = b""
    else:
        f[2] = cell if isinstance(cell, bytes) else cell.encode()
    lines[line - 1] = b",".join(f) + b"\n"
    data = b"".join(lines)
    path = tmp_path / ("bad.csv.gz" if gz else "bad.csv")
    path.write_bytes(gzip.compress(data) if gz else data)
    with pytest.raises(RecordError) as err:
        _read(path)
    msg = str(err.value)
    assert expect in msg and msg.startswith(str(path)) and "\n" not in msg


def test_bom_quotes_crlf_tabs_semicolons(tmp_path):
    """A UTF-8 BOM before a comment line, quoted cells (one holding the separator in an
    unused column), CRLF line ends, a comment line and a blank line inside the data; the
    same file separated by tabs and by semicolons reads alike."""
    ref = np.array([[0.001, 1.5e-3, np.nan, -0.0], [0.002, np.nan, 2.0, 3.0],
                    [0.003, np.nan, 4.25, 0.5], [0.004, 5.0, 100.0, 7e-3]])
    for sep in (",", "\t", ";"):
        rows = [f'0.001{sep}"1.5e-3"{sep}{sep} -0 {sep}"a{sep}b"', f"0.002{sep}NaN{sep}2{sep}3"
                f"{sep}y", "# a note inside the data", "", f"0.003{sep}-nan{sep}+4.25{sep}.5"
                f"{sep}", f'0.004{sep}5.{sep}"1E+2"{sep}7e-3{sep}z']
        header = sep.join(["t ", ' "angle_sensor"', "inclinometer_y", "inclinometer_z",
                           "note"])
        text = "# made by hand\r\n" + header + "\r\n" + "\r\n".join(rows)
        path = tmp_path / "awk.csv"
        path.write_bytes(b"\xef\xbb\xbf" + text.encode())
        names, data, sizes = _read(path, chunk_rows=3)
        assert names == list(GC_COLUMNS) and sizes == [3, 1]
        np.testing.assert_array_equal(np.isnan(data), np.isnan(ref))
        np.testing.assert_allclose(data, ref, rtol=1e-15)
        assert np.signbit(data[0, 3])
        info = records.read_csv(path, GC_COLUMNS, return_info=True)[2]
        assert info.delimiter == sep and info.header_line == 2


def test_separator_faults_are_named(tmp_path):
    """A header two separators split alike, with data that does not decide, is refused as
    ambiguous; a decimal comma in a semicolon file is named; UTF-16 is named."""
    p = tmp_path / "amb.csv"
    p.write_text("t,a;b,angle_sensor,inclinometer_y,inclinometer_z\n1,x;y,2,3,4\n")
    assert _read(p)[1].tolist() == [[1.0, 2.0, 3.0, 4.0]]     # only commas name them all
    p.write_text("t,a;angle_sensor,inclinometer_y,inclinometer_z\n")
    with pytest.raises(RecordError, match="line 1: ambiguous column separator"):
        _read(p)
    p.write_text("t;x,t2;y\n1;2,3;4\n")
    with pytest.raises(RecordError, match=r"ambiguous column separator.*commas and at "
                                          r"semicolons"):
        _read(p, required=["x"])
    p.write_text("t;angle_sensor;inclinometer_y;inclinometer_z\n0,001;0,5;0;0\n")
    with pytest.raises(RecordError, match=r"line 2: ambiguous decimal separator.*'0,001'"):
        _read(p)          # some numbers with a decimal comma, some not
    p.write_bytes("t,x\n1,2\n".encode("utf-16"))
    with pytest.raises(RecordError, match="UTF-16"):
        _read(p, required=["t", "x"])
    p.write_bytes(b"# ok\nt,x\xe9\n1,2\n")
    with pytest.raises(RecordError, match=r"line 2: not UTF-8 text: byte 0xe9"):
        _read(p, required=["t", "x"])


def test_columns_map_other_header_names(tmp_path):
    p = tmp_path / "other.csv"
    p.write_text("time,gyro,incl_y,incl_z\n0.1,1,2,3\n0.2,4,5,6\n")
    cols = records.parse_columns("t=time,angle_sensor=gyro,inclinometer_y=incl_y,"
                                 "inclinometer_z=incl_z")
    _, data, _ = _read(p, columns=cols)
    np.testing.assert_allclose(data, [[0.1, 1, 2, 3], [0.2, 4, 5, 6]], rtol=1e-15)
    with pytest.raises(RecordError, match=r"column 'angle_sensor': not in the header.*"
                                          r"--columns angle_sensor=NAME"):
        _read(p, columns={"t": "time"})
    with pytest.raises(RecordError, match=r"mapped to 'gyr0' by columns"):
        _read(p, columns={**cols, "angle_sensor": "gyr0"})
    with pytest.raises(ValueError, match="NAME=HEADER"):
        records.parse_columns("t:time")
    with pytest.raises(ValueError, match="columns maps 'tt'"):
        _read(p, columns={"tt": "time"})


def test_latitude_comment_sets_the_record_latitude(tmp_path):
    p = tmp_path / "lat.csv"
    body = f"{HEADER}\n0.001,0,0,0\n0.002,0,0,0\n"
    p.write_text("# made by a logger\n# latitude_deg: 53.9\n" + body)
    rec = records.read_gc(p, check=False)
    assert rec.latitude == pytest.approx(math.radians(53.9), rel=1e-15)
    chunks = list(records.GCChunks(p, check=False, chunk_rows=1))
    assert all(c.latitude == pytest.approx(math.radians(53.9), rel=1e-15) for c in chunks)
    p.write_text(body)
    assert records.read_gc(p, check=False).latitude is None
    p.write_text("# latitude_deg: 153.9\n" + body)
    with pytest.raises(RecordError, match=r"line 1: '# latitude_deg:' expects degrees"):
        records.read_gc(p, check=False)


@pytest.mark.parametrize("t_first", [1.7e9, 1e5, 1234.5])
def test_absolute_clock_taken_relative_to_the_first_row(tmp_path, t_first):
    """Unix time or any offset >= ABSOLUTE_TIME: t relative to the first row (exactly, as
    the decimal difference), stated in the info; t0 given overrides it."""
    steps = np.arange(2000) * 1e-3
    p = tmp_path / "epoch.csv"
    with open(p, "w") as fh:
        fh.write("t,x\n")
        for s in steps:
            fh.write(f"{t_first + s:.6f},1\n")
    _, data, info = records.read_csv(p, ["t", "x"], return_info=True)
    assert info.t_offset_source == "first row" and info.t_offset == pytest.approx(t_first)
    # the decimal differences, rounded once (a double of 1.7e9 resolves only 2.4e-7 s)
    np.testing.assert_allclose(data[:, 0], np.round(steps, 6), rtol=1e-15, atol=1e-18)
    assert "relative to t0" in info.time_note and "absolute clock" in info.time_note
    _, data, info = records.read_csv(p, ["t", "x"], t0=t_first - 5.0, return_info=True)
    np.testing.assert_allclose(data[:, 0], np.round(steps, 6) + 5.0, rtol=1e-15)
    assert info.t_offset_source == "t0"
    with open(p, "a") as fh:        # a corrupted last stamp: named, nothing allocated
        fh.write("1e308,1\n")
    with pytest.raises(RecordError, match=rf"line {steps.size + 2}, column 't': expected a "
                                          r"time stamp with at most 9 decimals"):
        records.read_csv(p, ["t", "x"])
    p.write_text("t,x\n0.5,1\n1.5,2\n")
    _, data, info = records.read_csv(p, ["t", "x"], return_info=True)
    assert info.time_note is None and data[0, 0] == pytest.approx(0.5, rel=1e-15)
    p.write_text("t,x\n0.5,1\n1.5,2\n1e308,3\n")
    with pytest.raises(RecordError, match=r"line 4, column 't': a time of 1e\+308 s"):
        records.read_csv(p, ["t", "x"])


# Random files against the reference --------------------------------------------------------
_TOKENS = ["1.5", "-2", "+3.25", ".5", "5.", "1e5", "1E-5", "-1.5e+05", "0", "-0", "0.000123",
           "nan", "NaN", "-nan", "", " 1.5", "2.5 ", "1e", ".", "+", "-", "inf",
           "-inf", "Infinity", "1_0", "0x10", "1e400", "12345678901234567890",
           "1.2345678901234567", "9007199254740993", "abc", '"1.5"',
           "1.5#", "nanx", "1.5.5", "1e5.5", "--1", "e5", "1e22", "1e23", "4.9e-324",
           "0.1", "1 2", "é"]
_NULL = {"", "nan", "-nan", "+nan"}


def _reference_small(text: str) -> tuple[str, object]:
    """('ok', array) or ('error', line) for a t,x file, with csv and float."""
    lines = text.splitlines()
    names = [c.strip() for c in next(csv.reader([lines[0]]))]
    it, ix = names.index("t"), names.index("x")
    out, t_prev = [], -math.inf
    for no, line in enumerate(lines[1:], start=2):
        if not line.strip() or line.strip().startswith("#"):
            continue
        cells = next(csv.reader([line]))
        if len(cells) != len(names):
            return "error", no
        vals = []
        for i in (it, ix):
            c = cells[i].strip()
            if c.lower() in _NULL:
                vals.append(math.nan)
                continue
            try:
                if "_" in c:
                    raise ValueError
                vals.append(float(c))
            except ValueError:
                return "error", no
        if not out and math.isfinite(vals[0]) and abs(vals[0]) >= 1000.0:
            offset = vals[0]           # an absolute clock: relative to the first row
        elif not out:
            offset = 0.0
        if not math.isfinite(vals[0]) or math.isinf(vals[1]):
            return "error", no
        vals[0] -= offset
        if abs(vals[0]) > 1e7 or vals[0] <= t_prev:
            return "error", no
        t_prev = vals[0]
        out.append(vals)
    if not out:
        return "error", None
    return "ok", np.array(out)


def test_random_files_read_as_the_reference(tmp_path):
    """400 small files of good and bad cells, comments, blank lines, short and long rows,
    quotes, line ends \\n, \\r\\n or \\r: the reference's array, or an error at the line the
    reference stops at."""
    rng = random.Random(18)
    kinds = set()
    for k in range(400):
        lines, t = [], 0.0
        for _ in range(rng.randint(1, 8)):
            r = rng.random()
            if r < 0.05:
                lines.append("# c")
                continue
            if r < 0.08:
                lines.append(rng.choice(["", "  "]))
                continue
            t += 1
            tt = f"{t:g}" if rng.random() < 0.9 else rng.choice(_TOKENS)
            x = (rng.choice(_TOKENS) if rng.random() < 0.7
                 else f"{rng.uniform(-1e3, 1e3):.{rng.randint(1, 17)}g}")
            if rng.random() < 0.05:
                lines.append(tt)
                continue
            lines.append(f"{tt},{x}" + rng.choice(["", ",1,2", ","]))
        header = rng.choice(["t,x,e", "x,t,e", "e,t,x", "t , x,e"])
        nl = rng.choice(["\n", "\r\n", "\r"])
        text = header + "\n" + nl.join(lines) + (nl if rng.random() < 0.8 else "")
        # every data line has the header's three fields unless the grammar broke it
        text = "\n".join(ln + ("," if ln.count(",") == 1 and not ln.startswith("#") else "")
                         for ln in text.replace("\r\n", "\n").replace("\r", "\n").split("\n"))
        path = tmp_path / f"r{k}.csv"
        path.write_bytes(text.replace("\n", nl).encode())
        want = _reference_small(text)
        try:
            got = ("ok", _read(path, chunk_rows=rng.choice([1, 2, 100]),
                               required=["t", "x"])[1])
        except RecordError as exc:
            got = ("error", str(exc))
        kinds.add(want[0])
        assert got[0] == want[0], (text, got, want)
        if want[0] == "ok":
            _same(got[1], want[1])
        elif want[1] is not None:
            assert f"line {want[1]}" in got[1], (text, got, want)
    assert kinds == {"ok", "error"}


def test_memory_stays_bounded_while_streaming(tmp_path):
    """A 50 MB file read chunk by chunk in a fresh process: the resident memory after each
    chunk levels off once pyarrow's read-ahead is full; over the second half of the file
    it stays within 8 MB of the first half's peak (a reader that kept the rows would add
    the 6 MB of floats and 12 MB of text of each further quarter of the file)."""
    code = (
        "import sys\n"
        "from pathlib import Path\n"
        "def rss():\n"
        "    for ln in Path('/proc/self/status').read_text().splitlines():\n"
        "        if ln.startswith('VmRSS:'): return int(ln.split()[1]) / 1024\n"
        "import pyarrow.csv, numpy\n"
        "from gyrolib.records.reader import _Reader, GC_COLUMNS\n"
        "r = _Reader(sys.argv[1], GC_COLUMNS, chunk_rows=32768, block_bytes=1 << 20)\n"
        "print(' '.join(f'{rss():.2f}' for _ in r))\n")
    n = 800_000
    path = records.write_csv(tmp_path / "big.csv", _table(n, 3), fmt="%.15g")
    assert path.stat().st_size > 48 * 2**20
    # a fixed mmap threshold: glibc's sliding one lets freed chunk arrays fragment the heap
    env = {**os.environ, "MALLOC_MMAP_THRESHOLD_": "131072"}
    out = subprocess.run([sys.executable, "-c", code, str(path)], capture_output=True,
                         text=True, check=True, cwd=ROOT, env=env)
    rss = [float(x) for x in out.stdout.split()]
    assert len(rss) == math.ceil(n / 32768)
    half = len(rss) // 2
    assert max(rss[half:]) < max(rss[:half]) + 8.0, rss


def test_float_matrix_is_arrow_to_numpy_without_pandas(tmp_path):
    """The reader turns Arrow's float columns into numpy from their buffers (nulls NaN, a
    sliced array's offset honoured): the same doubles as ``pyarrow.Array.to_numpy`` (an
    independent conversion; exact by design: both copy the same 8-byte values), and, in a
    fresh interpreter, without loading pandas, which ``to_numpy`` loads (the check's power)."""
    import pyarrow as pa
    from pyarrow import csv as pacsv

    from gyrolib.records.reader import _float_matrix

    rng = np.random.default_rng(7)
    x = rng.standard_normal((1000, 3))
    lines = ["a,b,c"] + [",".join("" if rng.random() < 0.1 else repr(float(v)) for v in row)
                         for row in x]
    path = tmp_path / "n.csv"
    path.write_text("\n".join(lines) + "\n")
    table = pacsv.read_csv(path, convert_options=pacsv.ConvertOptions(
        column_types={c: pa.float64() for c in "abc"}))
    batch = table.combine_chunks().to_batches()[0]
    for start, stop in ((0, 1000), (3, 997), (17, 18), (999, 1000)):
        cols = [batch.column(j).slice(start, stop - start) for j in range(3)]
        got = _float_matrix(cols)
        want = np.column_stack([c.to_numpy(zero_copy_only=False) for c in cols])
        assert got.shape == (stop - start, 3) and got.dtype == np.float64
        np.testing.assert_array_equal(np.isnan(got), np.isnan(want))
        np.testing.assert_array_equal(got[~np.isnan(got)], want[~np.isnan(want)])
    assert np.isnan(_float_matrix([batch.column(0)])).sum() > 50     # nulls were read
    with pytest.raises(TypeError, match="float64"):
        _float_matrix([pa.array([1, 2])])
    probe = ("import sys\nfrom gyrolib import records\n"
             f"records.read_gc({str(ROOT / 'data' / 'gc_record.csv.gz')!r})\n"
             "print('pandas' in sys.modules)\n"
             "import pyarrow as pa\nfrom pyarrow import csv\n"
             f"t = csv.read_csv({str(path)!r})\n"
             "t.column(0).chunk(0).to_numpy(zero_copy_only=False)\n"
             "print('pandas' in sys.modules)\n")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                         check=True, cwd=ROOT)
    assert out.stdout.split() == ["False", "True"]


def test_rsf_record_resolves_lazily():
    """``records.RSFRecord`` (and ``records.reader.RSFRecord``) is paper RSF's record class,
    imported on first use; another unknown name is an AttributeError."""
    from gyrolib import rsf
    from gyrolib.records import reader

    assert records.RSFRecord is rsf.RSFRecord and reader.RSFRecord is rsf.RSFRecord
    assert "RSFRecord" in records.__all__
    with pytest.raises(AttributeError, match="no attribute 'NoSuchRecord'"):
        records.NoSuchRecord  # noqa: B018
    with pytest.raises(AttributeError, match="no attribute 'NoSuchRecord'"):
        reader.NoSuchRecord  # noqa: B018
