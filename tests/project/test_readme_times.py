"""The README's measured times are written from the benchmarks' result files
(``benchmarks/readme_times.py``), never typed: the README holds what the script writes from
``benchmarks/results/``, one row per command and CPU class from the latest run of each class,
saying whether the target is met; the check fails on a README whose time was edited (power)."""

from __future__ import annotations

import doctest
import importlib.util
import json

from tests.conftest import ROOT


def _script():
    spec = importlib.util.spec_from_file_location("readme_times",
                                                  ROOT / "benchmarks" / "readme_times.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_the_readme_quotes_the_benchmarks_result_files():
    rt = _script()
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    assert rt.rewrite(readme, rt.block()) == readme, \
        "README.md's times are stale: run python3 benchmarks/readme_times.py"
    # every quoted time is a result file's number, rounded to the second, in its class's row
    doc = json.loads((ROOT / "benchmarks/results/test_command.json").read_text("utf-8"))
    (row,) = [r for r in doc["results"] if r["case"].startswith("fresh clone to a finished")]
    cls = doc["machine"]["cpu_class"]
    assert f"| {cls} | {row['ours_s']:.0f} s | ≤ 360 s |" in readme
    # a row per command and class: the everyday and full test commands and the book
    for command in ("`python3 tasks.py test` on", "`python3 tasks.py test --full`",
                    "`python3 tasks.py book`"):
        for c in rt.CLASSES:
            assert sum(line.startswith(f"| {command}") and f"| {c} |" in line
                       for line in readme.splitlines()) == 1, (command, c)


def test_the_check_fails_on_an_edited_time(tmp_path):
    rt = _script()
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    block = rt.block()
    edited = block.replace(" s | ≤ 360 s |", "0 s | ≤ 360 s |", 1)
    assert edited != block
    assert rt.rewrite(readme, edited) != rt.rewrite(readme, block)
    results = tmp_path / "results"
    results.mkdir()
    for name in ("test_command.json", "book_build.json"):
        doc = json.loads((ROOT / "benchmarks/results" / name).read_text("utf-8"))
        doc["results"][0]["ours_s"] += 100.0
        doc["results"][-1]["ours_s"] += 100.0
        (results / name).write_text(json.dumps(doc), encoding="utf-8")
    assert rt.block(results) != block


def test_each_class_keeps_its_latest_run_and_a_miss_is_said(tmp_path):
    """A file with a newer AVX-512 run that keeps an older AVX2 one (``other_classes``): each
    class's row quotes its own run; of two runs of one class the later wins; a time over its
    target is "missed", under it "met"."""
    rt = _script()
    assert doctest.testmod(rt).failed == 0

    def run(cls, date, seconds, load=0.2):
        return {"date": date, "load": load,
                "machine": {"cpu": "CPU", "cpu_class": cls, "cores": 2, "host_cpu": "x"},
                "results": [{"case": "full clean build, every chapter executed",
                             "ours_s": seconds, "target_s": 90.0, "note": "commit abcdef1"}]}

    doc = {"benchmark": "book_build", **run("AVX-512", "2026-12-02T00:00:00+00:00", 80.0),
           "other_classes": [run("AVX2", "2026-12-01T00:00:00+00:00", 150.0),
                             run("AVX2", "2026-11-01T00:00:00+00:00", 60.0)]}
    (tmp_path / "book_build.json").write_text(json.dumps(doc), encoding="utf-8")
    rows = [line for line in rt.block(tmp_path).splitlines() if "tasks.py book" in line]
    assert len(rows) == 2
    avx2, avx512 = rows
    assert "| AVX2 | 150 s | ≤ 90 s | **missed** (1.7× the target) |" in avx2
    assert "| AVX-512 | 80 s | ≤ 90 s | met |" in avx512
    assert "2026-12-01" in avx2 and "2026-12-02" in avx512


def test_a_new_run_keeps_the_latest_run_of_the_other_classes(tmp_path, monkeypatch):
    """``Recorder.write(keep_other_classes=True)`` over a file of another class keeps that
    run under ``other_classes``, and drops a kept run of its own class (replaced by itself)."""
    monkeypatch.syspath_prepend(str(ROOT / "benchmarks"))
    spec = importlib.util.spec_from_file_location("_results", ROOT / "benchmarks" / "_results.py")
    res = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(res)
    monkeypatch.setattr(res, "RESULTS", tmp_path)
    rec = res.Recorder("book_build")
    mine = rec.doc["machine"]["cpu_class"]
    other = "AVX2" if mine != "AVX2" else "AVX-512"
    old = {"benchmark": "book_build", "date": "2026-01-02T00:00:00+00:00", "load": 0.1,
           "machine": {"cpu_class": other}, "results": [],
           "other_classes": [{"date": "2026-01-01T00:00:00+00:00", "load": 0.1,
                              "machine": {"cpu_class": mine}, "results": []}]}
    (tmp_path / "book_build.json").write_text(json.dumps(old), encoding="utf-8")
    rec.case("full clean build, every chapter executed", 100.0, target_s=90.0)
    doc = json.loads(rec.write(keep_other_classes=True).read_text(encoding="utf-8"))
    assert [r["machine"]["cpu_class"] for r in doc["other_classes"]] == [other]
    assert set(res.runs_by_class(doc)) == {mine, other}
    assert res.runs_by_class(doc)[mine]["results"][0]["ours_s"] == 100.0
