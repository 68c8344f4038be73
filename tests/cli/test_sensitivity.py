"""The ``sensitivity`` command: bad arguments exit 2 with one line and write nothing; an
unreachable scheduler (a closed port on this machine) is reported in one line after the
timeout; a run writes the indices, intervals and the run record, equal to the library's."""

from __future__ import annotations

import json
import socket
import time

import pytest

from gyrolib import __version__, rsf
from gyrolib.cli import main


def closed_port() -> int:
    """A local TCP port nobody listens on (bound, then released)."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


O = ["--out", "{out}"]


@pytest.mark.parametrize("argv, says", [
    (["sensitivity", "gc", "--n", "100", *O], "--n: must be a power of 2"),
    (["sensitivity", "gc", "--n", "x", *O], "--n: must be a power of 2"),
    (["sensitivity", "rsf", "--n", "8", "--workers", "0", *O], "--workers: must be an integer"),
    (["sensitivity", "rsf", "--n", "8", "--workers", "2", "--scheduler", "tcp://h:1", *O],
     "not allowed with"),
    (["sensitivity", "rsf", "--n", "8", "--scheduler", "localhost", *O], "tcp://HOST:PORT"),
    (["sensitivity", "rsf", "--n", "8", "--timeout", "-1", *O], "--timeout: must be"),
    (["sensitivity", "rsf", "--n", "8", "--seed", "-2", *O], "--seed: must be"),
    (["sensitivity", "xyz", "--n", "8", *O], "invalid choice"),
    (["sensitivity", "rsf", "--n", "8"], "--out"),
])
def test_bad_arguments_exit_2_with_one_line_and_write_nothing(tmp_path, capsys, argv, says):
    out = tmp_path / "s.json"
    with pytest.raises(SystemExit) as info:
        main([a.replace("{out}", str(out)) for a in argv])
    assert info.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and says in err
    assert not out.exists()


def test_out_must_be_a_json_file_in_an_existing_folder(tmp_path, capsys):
    for out in (tmp_path / "s.txt", tmp_path / "missing" / "s.json"):
        with pytest.raises(SystemExit) as info:
            main(["sensitivity", "rsf", "--n", "8", "--out", str(out)])
        assert info.value.code == 2
        assert capsys.readouterr().err.count("\n") == 1
        assert not out.exists()


def test_unreachable_scheduler_is_one_line_after_the_timeout(tmp_path, capsys):
    """A closed port on 127.0.0.1: exit 1 and one line, within the timeout and a margin for
    a loaded machine, not a hang; nothing written."""
    pytest.importorskip("dask.distributed")
    out = tmp_path / "s.json"
    port = closed_port()
    t0 = time.perf_counter()
    code = main(["sensitivity", "rsf", "--n", "8", "--scheduler", f"tcp://127.0.0.1:{port}",
                 "--timeout", "2", "--out", str(out)])
    elapsed = time.perf_counter() - t0
    assert code == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert f"tcp://127.0.0.1:{port}" in err and "within 2 s" in err
    assert elapsed < 60.0
    assert not out.exists()


def test_a_run_writes_the_indices_and_the_run_record(tmp_path, capsys):
    out = tmp_path / "s.json"
    assert main(["sensitivity", "rsf", "--n", "64", "--seed", "3", "--out", str(out)]) == 0
    err = capsys.readouterr().err
    runs = 64 * (2 * len(rsf.sensitivity_inputs()) + 2)
    assert "sensitivity rsf" in err and f"{runs}/{runs}" in err     # the tqdm bar on stderr
    data = json.loads(out.read_text())
    ref = rsf.sensitivity(64, seed=3)
    assert data["n"] == 64 and data["seed"] == 3
    run = data["run"]
    assert run["version"] == __version__ and run["workers"] == 1
    assert run["wall_time_s"] > 0 and run["machine"]["cpus"] >= 1
    assert run["model_runs"] == len(data["values"]) == 64 * (2 * len(ref.inputs) + 2)
    for o in ref.outputs:
        for name, idx in ref.total[o].items():
            assert data["total"][o][name]["value"] == pytest.approx(idx.value, rel=1e-12)
            assert data["total"][o][name]["conf"] == pytest.approx(idx.conf, rel=1e-12)


def test_extend_reuses_a_smaller_study_and_refuses_another(tmp_path, capsys):
    """--extend: the grown file equals a study run from scratch; a file of another study (a
    larger N here) exits 2 with one line and writes nothing."""
    small, grown, bad = tmp_path / "s16.json", tmp_path / "s64.json", tmp_path / "bad.json"
    assert main(["sensitivity", "rsf", "--n", "16", "--out", str(small)]) == 0
    assert main(["sensitivity", "rsf", "--n", "64", "--extend", str(small),
                 "--out", str(grown)]) == 0
    data = json.loads(grown.read_text())
    assert data["run"]["model_runs_computed"] == (64 - 16) * (2 * len(rsf.sensitivity_inputs()) + 2)
    assert data["run"]["extends"]["n"] == 16
    ref = rsf.sensitivity(64)
    assert data["values"] == ref.values.tolist()
    capsys.readouterr()
    assert main(["sensitivity", "rsf", "--n", "8", "--extend", str(grown),
                 "--out", str(bad)]) == 2
    assert capsys.readouterr().err.count("\n") == 1
    assert not bad.exists()


def test_help_counts_the_studies_inputs(capsys):
    """``sensitivity --help`` names each study's number of inputs as the study defines it
    (it said 5 where RSF's study has 7), never a typed number."""
    from gyrolib.gc.analysis.sensitivity_study import sensitivity_inputs as gc_inputs
    from gyrolib.rsf.sensitivity_study import sensitivity_inputs as rsf_inputs

    with pytest.raises(SystemExit):
        main(["sensitivity", "--help"])
    out = capsys.readouterr().out
    assert f"t_c over {len(gc_inputs())} inputs" in out
    assert f"share removed over {len(rsf_inputs())} inputs" in out
    with pytest.raises(SystemExit):
        main(["sensitivity", "rsf", "--help"])
    assert f"over {len(rsf_inputs())} inputs" in capsys.readouterr().out
