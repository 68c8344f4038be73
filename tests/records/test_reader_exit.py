"""No crash at exit: ``calibrate gc``'s refusal paths, run as the user runs them (a fresh
interpreter each time), exit with their status every time — 2 for a record refused at the
door while pyarrow's streaming reader is still reading ahead (a gzip record whose first
chunk is in degrees, its rest unread), 3 for a record read to its end without a valid
estimate (no latitude).  A streaming reader abandoned with its read-ahead running made the
interpreter's exit abort ("terminate called without an active exception", status 134) or
hang in pyarrow's thread-pool shutdown; :func:`gyrolib.records.reader._stop_reading` stops
it first.  10 runs of each in the everyday tier, 100 in the full one; and, in-process, the
stop itself: after an abandoned iteration no read of the file is under way or to come."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from gyrolib import gc, records
from gyrolib.records.reader import GC_COLUMNS, _Reader

P = gc.GyrocompassParams()
ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """``deg.csv.gz``: 70 s of paper GC's model with the angle in degrees, then 430 s more
    rows (the first 70 s tiled: what pyarrow reads ahead, never checked), 500 000 rows;
    ``nolat.csv``: 3 s of the model, valid but with no latitude stated."""
    folder = tmp_path_factory.mktemp("exit")
    r = gc.simulate_record(P, 70.0, seed=4710).record
    reps = 500000 // r.n + 1
    n = reps * r.n
    cols = {"t": np.arange(1, n + 1) * P.dt,
            "angle_sensor": np.tile(np.degrees(r.angle_sensor), reps),
            "inclinometer_y": np.tile(r.inclinometer_y, reps),
            "inclinometer_z": np.tile(r.inclinometer_z, reps)}
    deg = records.write_csv(folder / "deg.csv.gz", cols,
                            fmt=["%.3f", "%.9g", "%.6g", "%.6g"])
    short = gc.simulate_record(P, 3.0, seed=4711).record
    nolat = records.write_csv(folder / "nolat.csv", {c: getattr(short, c)
                                                     for c in GC_COLUMNS})
    return {2: deg, 3: nolat}


def _runs(path: Path, want: int, n: int) -> list[tuple[int, str]]:
    """``n`` runs of ``calibrate gc PATH``; each (status, stderr) that is not ``want`` with
    one line on stderr (a hang counts as status None after 300 s)."""
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    bad = []
    for _ in range(n):
        try:
            p = subprocess.run([sys.executable, "-m", "gyrolib", "calibrate", "gc", str(path)],
                               capture_output=True, text=True, timeout=300, env=env,
                               cwd=ROOT)
        except subprocess.TimeoutExpired:
            bad.append((None, "hung"))
            continue
        if p.returncode != want or p.stderr.count("\n") != 1:
            bad.append((p.returncode, p.stderr[-300:]))
    return bad


@pytest.mark.parametrize("want", [2, 3])
def test_refusals_exit_with_their_status_ten_times(files, want):
    assert _runs(files[want], want, 10) == []


@pytest.mark.full
@pytest.mark.parametrize("want", [2, 3])
def test_refusals_exit_with_their_status_a_hundred_times(files, want):
    assert _runs(files[want], want, 100) == []


def test_an_abandoned_iteration_leaves_no_read_under_way(files):
    """Iterate one chunk of the 500 000-row gzip record and drop the iteration: the source
    pyarrow reads is stopped with no read under way, the file closed, and the reads made
    stopped short of the file's end (the read-ahead did not run on)."""
    reader = _Reader(files[2], GC_COLUMNS, chunk_rows=1000)
    sources = []
    real = _Reader._batches

    def spy(self, rest, *args):
        sources.append(rest)
        return real(self, rest, *args)

    _Reader._batches = spy
    try:
        it = iter(reader)
        _, first = next(it)
        assert first.shape == (1000, 4)
        it.close()
    finally:
        _Reader._batches = real
    rest, = sources
    assert rest._stopped and rest._busy == 0 and rest.stream.closed
    assert rest.read(1 << 20) == b""
