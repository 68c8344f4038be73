"""The CSV reader's fast path (:mod:`gyrolib.records._fastcsv`: plain numeric blocks parsed in
one compiled pass) against its exact line-by-line path (``fast=False``, Python's ``float``
and numpy's ``loadtxt``, the one that names a bad cell): the same arrays, the same errors
with the same line and column, on plain, gzip and awkward files, and on random lines from a
grammar of good and bad cells."""

from __future__ import annotations

import gzip
import io
import random
from pathlib import Path

import numpy as np
import pytest

from gyrolib import records
from gyrolib.records import RecordError
from gyrolib.records.reader import GC_COLUMNS, _Lines, _Reader

HEADER = ",".join(GC_COLUMNS)


def _read(path: Path, *, fast: bool, chunk_rows: int = 5000, required=GC_COLUMNS,
          optional=()) -> tuple[list[str], np.ndarray, list[int]]:
    cols: list[str] = []
    parts = []
    for names, data in _Reader(path, required, chunk_rows=chunk_rows, fast=fast,
                               optional=optional):
        cols = names
        parts.append(data)
    return cols, np.concatenate(parts), [p.shape[0] for p in parts]


def _same(a: np.ndarray, b: np.ndarray) -> None:
    """Equal to rounding (the two paths convert the same decimal text with different code:
    both round correctly, compared with a tolerance all the same); NaN where NaN."""
    assert a.shape == b.shape
    np.testing.assert_array_equal(np.isnan(a), np.isnan(b))
    np.testing.assert_allclose(a, b, rtol=1e-15, atol=0.0)


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
                      ("fixed", ["%.3f", "%.12f", "%.10f", "%.15f"])):
        files[name] = records.write_csv(d / f"{name}.csv", cols, fmt=fmt)
    files["gz"] = records.write_csv(d / "g9.csv.gz", cols, fmt=["%.3f", "%.9g", "%.9g", "%.9g"])
    return files, cols


@pytest.mark.parametrize("name", ["g9", "g17", "e", "fixed", "gz"])
def test_fast_and_exact_paths_give_the_same_array(plain, name):
    files, cols = plain
    c1, fast, sizes = _read(files[name], fast=True)
    c2, exact, sizes2 = _read(files[name], fast=False)
    assert c1 == c2 == list(GC_COLUMNS)
    _same(fast, exact)
    assert sizes == sizes2 and sizes[0] == 5000    # the same chunks
    # and the values written (power: a parser that dropped a digit would fail this)
    written = np.column_stack(list(cols.values()))
    np.testing.assert_allclose(fast, written, rtol=1e-8 if name in ("g9", "gz") else 1e-3,
                               atol=0.0 if name != "fixed" else 1e-12)


def test_plain_numbers_take_the_fast_path(plain, monkeypatch):
    """A plain file is read without the exact path; a comment line sends one chunk there (so
    the comparison above compared two different parsers)."""
    files, _ = plain
    calls = []
    exact = _Reader._exact

    def spy(self, *a, **k):
        calls.append(1)
        return exact(self, *a, **k)

    monkeypatch.setattr(_Reader, "_exact", spy)
    _read(files["g9"], fast=True)
    assert calls == []
    _read(files["g17"], fast=True)    # 17 digits: the Eisel-Lemire conversion
    assert calls == []
    many = files["g9"].with_name("g25.csv")    # 25 digits: more than the fast path takes
    records.write_csv(many, {c: _read(files["g9"], fast=True)[1][:, k]
                             for k, c in enumerate(GC_COLUMNS)}, fmt="%.25g")
    _read(many, fast=True)
    assert calls
    calls.clear()
    text = files["g9"].read_text().splitlines(keepends=True)
    text.insert(12000, "# a comment in the middle\n")
    commented = files["g9"].with_name("commented.csv")
    commented.write_text("".join(text))
    _, data, sizes = _read(commented, fast=True)
    _, ref, _ = _read(files["g9"], fast=True)
    _same(data, ref)
    assert len(calls) == 1 and sizes[:3] == [5000, 5000, 5000]


@pytest.mark.parametrize("gz", [False, True])
@pytest.mark.parametrize(("line", "cell", "expect"), [
    (12345, "abc", "line 12345, column 'inclinometer_y': expected a number"),
    (17001, None, "line 17001, column 't': time must be strictly increasing"),
    (9999, "", "line 9999, column 't': expected a finite time"),
    (20000, "inf", "line 20000, column 'inclinometer_y': expected a finite number"),
    (15000, "short", "line 15000: expected at least 4 comma-separated fields"),
])
def test_a_bad_cell_deep_in_a_plain_file_is_named(plain, tmp_path, gz, line, cell, expect):
    """Line numbers count the header (line 1) and every line; a bad block is read again by
    the exact path, a decreasing or missing time is found on the fast path's own chunk."""
    files, _ = plain
    lines = files["g9"].read_text().splitlines(keepends=True)
    f = lines[line - 1].rstrip("\n").split(",")
    if cell == "short":
        f = f[:3]
    elif cell is None:
        f[0] = "0.5"
    elif cell == "":
        f[0] = ""
    else:
        f[2] = cell
    lines[line - 1] = ",".join(f) + "\n"
    data = "".join(lines).encode()
    path = tmp_path / ("bad.csv.gz" if gz else "bad.csv")
    path.write_bytes(gzip.compress(data) if gz else data)
    for fast in (True, False):
        with pytest.raises(RecordError) as err:
            _read(path, fast=fast)
        assert expect in str(err.value) and str(path) in str(err.value)


def test_awkward_but_valid_files_read_alike(tmp_path):
    """CRLF, blanks around cells, empty cells and nan as missing values, -0, a last line
    without its line end, extra and unused columns, a BOM-free header with blanks."""
    rows = ["0.001, 1.5e-3 ,,-0,x", "0.002,NaN,2,3,y", "0.003,-nan,+4.25,.5,",
            "0.004,5.,1E+2,7e-3,z"]
    text = "# made by hand\r\nt , angle_sensor,inclinometer_y,inclinometer_z,note\r\n"
    path = tmp_path / "awk.csv"
    path.write_bytes((text + "\r\n".join(rows)).encode())
    _, fast, _ = _read(path, fast=True, chunk_rows=3)
    _, exact, _ = _read(path, fast=False, chunk_rows=3)
    _same(fast, exact)
    ref = np.array([[0.001, 1.5e-3, np.nan, -0.0], [0.002, np.nan, 2, 3],
                    [0.003, np.nan, 4.25, 0.5], [0.004, 5.0, 100.0, 7e-3]])
    _same(fast, ref)
    assert np.signbit(fast[0, 3])


def test_numbers_convert_as_python_float():
    """The fast path's conversion (Clinger's exact path, else Eisel-Lemire) against Python's
    float on random decimal text: 1 to 19 digits, exponents from -330 to 308, repr and
    %.18e output, exact decimal midpoints between doubles; within one unit in the last
    place (both round correctly), and the common formats never left to the exact path."""
    from decimal import Decimal

    from gyrolib.records._fastcsv import _number

    rng = random.Random(22)
    texts, common = [], []
    for _ in range(20000):
        digits = "".join(rng.choice("0123456789") for _ in range(rng.randint(1, 19)))
        k = rng.randint(0, len(digits))
        texts.append(f"{digits[:k]}.{digits[k:]}e{rng.randint(-330, 308)}")
        x = rng.uniform(-1.0, 1.0) * 10.0 ** rng.randint(-300, 300)
        common += [repr(x), f"{x:.18e}", f"{x:.9g}", f"{x:.17g}", f"{x % 1e6:.6f}"]
        a = Decimal(x)
        texts.append(f"{(a + Decimal(float(np.nextafter(x, np.inf)))) / 2:.18e}")
    got, ref, doubts = [], [], {"random": 0, "common": 0}
    for kind, batch in (("random", texts), ("common", common)):
        for text in batch:
            b = np.frombuffer((text + ",").encode(), dtype=np.uint8)
            ok, value, pos = _number(b, 0, b.size)
            if not ok:
                doubts[kind] += 1
                continue
            assert pos == b.size - 1
            got.append(value)
            ref.append(float(text))
    np.testing.assert_array_max_ulp(np.array(got), np.array(ref), maxulp=1)
    assert doubts["common"] == 0 and doubts["random"] < 0.2 * len(texts)
    assert len(got) > 100000


_TOKENS = ["1.5", "-2", "+3.25", ".5", "5.", "1e5", "1E-5", "-1.5e+05", "0", "-0", "0.000123",
           "nan", "NaN", "-nan", "+NAN", "", " 1.5", "2.5 ", "\t3", "1e", ".", "+", "-", "inf",
           "-inf", "Infinity", "1_0", "0x10", "1e400", "1e-400", "12345678901234567890",
           "1.2345678901234567", "123456789012345678", "9007199254740993", "abc", '"1.5"',
           "1.5#", "nanx", "1.5.5", "1e5.5", "--1", "e5", "1e22", "1e23", "1e-22", "4.9e-324",
           "0.1", "1 2", "é"]


def _random_file(rng: random.Random, path: Path) -> tuple[Path, int]:
    lines, t = [], 0.0
    for _ in range(rng.randint(1, 8)):
        r = rng.random()
        if r < 0.05:
            lines.append("# c")
            continue
        if r < 0.08:
            lines.append(rng.choice(["", "  ", "\t"]))
            continue
        t += 1
        tt = f"{t:g}" if rng.random() < 0.9 else rng.choice(_TOKENS)
        x = (rng.choice(_TOKENS) if rng.random() < 0.7
             else f"{rng.uniform(-1e3, 1e3):.{rng.randint(1, 17)}g}")
        if rng.random() < 0.05:
            lines.append(tt)
            continue
        lines.append(f"{tt},{x}" + rng.choice(["", ",zz", ",1,2", ",", ",#", ',"q"']))
    nl = rng.choice(["\n", "\r\n", "\n", "\r"])
    header = rng.choice(["t,x", "x,t", "a,t,x", "t , x"])
    text = header + "\n" + nl.join(lines) + (nl if rng.random() < 0.8 else "")
    data = text.encode()
    if rng.random() < 0.2:
        path = path.with_name(path.name + ".gz")
        data = gzip.compress(data)
    path.write_bytes(data)
    return path, rng.choice([1, 2, 3, 100])


def test_random_lines_read_alike(tmp_path):
    """400 small files of good and bad cells, comments, blank lines, short rows, quotes,
    line ends \\n, \\r\\n or \\r: the fast path gives the exact path's array or its error."""
    rng = random.Random(18)
    kinds = set()
    for k in range(400):
        path, chunk = _random_file(rng, tmp_path / f"r{k}.csv")
        out = []
        for fast in (True, False):
            try:
                out.append(("ok", _read(path, fast=fast, chunk_rows=chunk, required=["t", "x"])))
            except RecordError as exc:
                out.append(("error", str(exc)))
        kinds.add(out[1][0])
        assert out[0][0] == out[1][0], (path.read_bytes(), out)
        if out[0][0] == "error":
            assert out[0][1] == out[1][1]
        else:
            _same(out[0][1][1], out[1][1][1])
            assert out[0][1][2] == out[1][1][2]
    assert kinds == {"ok", "error"}


def test_lines_split_as_a_text_stream():
    """Lines end at \n, \r\n or a lone \r, as in ``open(newline="")``, whatever the block
    boundaries (blocks of 1 to 4 bytes), one at a time (the header) or a block at a time
    (the exact path), also with the characters ``str.splitlines`` would end a line at."""
    rng = random.Random(5)
    for _ in range(3000):
        s = "".join(rng.choice(["a", "b", "\r", "\n", "\r\n", "é", "\x0b", "\x1c", "\x85",
                                "\u2028"]) for _ in range(rng.randint(0, 30)))
        ref = [ln.rstrip("\r\n") for ln in
               io.TextIOWrapper(io.BytesIO(s.encode()), encoding="utf-8", newline="")]
        lines = _Lines(io.BytesIO(s.encode()), rng.randint(1, 4))
        got = []
        while (ln := lines.next_line()) is not None:
            got.append(ln.rstrip("\r\n"))
        assert got == ref, repr(s)
        lines = _Lines(io.BytesIO(s.encode()), rng.randint(1, 4))
        end = lines.fill(10**6, 8.0)
        text, block = lines.split(end)
        got = [(b if text else b.decode()).rstrip("\r\n") for b in block]
        assert got == ref, repr(s)
        assert sum(map(len, block)) == end    # str lines of an ASCII block: bytes
