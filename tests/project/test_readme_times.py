"""The README's measured times are written from the benchmarks' result files
(``benchmarks/readme_times.py``), never typed: the README holds what the script writes from
``benchmarks/results/``, and the check fails on a README whose time was edited (power)."""

from __future__ import annotations

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
    # every quoted time is a result file's number, rounded to the second
    doc = json.loads((ROOT / "benchmarks/results/test_command.json").read_text("utf-8"))
    (row,) = [r for r in doc["results"] if r["case"].startswith("fresh clone to a finished")]
    assert f"| {row['ours_s']:.0f} s | ≤ 360 s |" in readme
    assert doc["machine"]["cpu_class"] in readme


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
