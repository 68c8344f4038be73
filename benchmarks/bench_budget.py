"""An issue's CPU budget: the CPU-s its tests add to the test command, measured before (the
commit the round started from) and after (this tree) on the same machine, and the figure
measurement's share of a clean book build (issue 35's allowance: 30 CPU-s of tests, 10 s of
build).

Which tests are an issue's is written in :data:`ISSUES` (file -> how it is measured), so that
another issue's budget is one more entry:

* ``new``: a file the issue added: measured here only (before = 0), its cost the run of the
  whole file less the start-up of pytest with no test file (interpreter, plugins, conftest);
* ``whole``: a file that existed at the base and that only this issue changed: the whole file
  at the base and here, the difference;
* ``added`` (with an ``anchor``): test functions the issue added to a file that others changed
  too: the run of anchor + added less the run of the anchor alone, here only; the anchor is
  a cheap test of the same file that sets up the same module and session fixtures (a
  browser, a served site), or, when none, the file's collection (``--collect-only``): what
  the test command pays for that file anyway;
* ``changed``: test functions that existed at the base and that the issue changed: the same
  node ids at the base and here, the difference.

Every run is one pytest process (``-n 0 -p no:cacheprovider``), its CPU-s those of its process
tree (below), rounds alternating the base and this tree. Every run first imports what each of
the test command's two xdist workers has imported anyway by the time an issue's tests run there
(``_worker_imports.py``: numpy, scipy.stats, gyrolib and its ``gc``, ``rsf``, ``units`` and
``book.ledger``, each imported by 7 to 44 of the base's test files, counted in the record): a
file run in a process of its own would otherwise pay an interpreter's imports (about 1 CPU-s:
1.1 a file for issue 33) that the test command pays once per worker, whatever the issue adds.
What those imports cost more here than at the base (the issue's new modules among them) is the
``worker imports`` line, counted once per worker. ``--per-process`` runs without them (the
method of the budgets recorded before 2026-11-29). The ledger's session memo (below) is
computed once a side; what it costs more here is counted in the sum too. The verdict's sum
counts every line's saving (a file, or the memo, cheaper here than at the base) as 0: a saving
in a file other issues changed too may be theirs (a library made faster since the base). The
net sum, savings included (the budgets recorded until 2026-11-29), is recorded beside it.

The base is checked out with ``git worktree add`` into a temporary folder and run with this
tree's ``.venv`` (its pins may differ from the base's own: the result says so). Tests of the
built book get one prebuilt book (``GYROLIB_REUSE_BOOK``, conftest.py), built by
``_book_once.py`` as the test session builds it (``--book`` reuses one): no test's CPU includes
the build; likewise the ledger, which the test command computes once per session for the dozen
tests that read it (``GYROLIB_LEDGER_MEMO``), is computed once per tree before the rounds
(counted in no test; what it costs more here than at the base is a line of the sum); numba's
kernels are compiled into each tree's cache before the rounds too, as the test command does
(``WARM_NUMBA``, tasks.py). A run's CPU-s are the larger of the reaped children's
(``RUSAGE_CHILDREN``) and the sum over every process seen below it, read every 0.1 s
(``psutil``): Chromium's renderers are not all reaped inside the tree, so ``RUSAGE_CHILDREN``
alone misses part of a browser test (about a quarter of one navigation test). The plugin
``_cpu_per_test.py`` adds each test's set-up, call and tear-down CPU-s (per-test figures, not
reliable for the browser tests, whose renderers end between readings); the verdict uses the
process totals.

The build's share: in that build every figure's measurement (``page_record``: the layout pass,
text metrics and the checks that the PNG carries) appends its own ``time.process_time()`` to
``figure_cpu.jsonl`` (``GYROLIB_FIGURE_CPU_LOG``).  Its CPU-s are summed per chapter; the
wall-s it adds to a clean build are estimated by replaying the build's schedule
(``_ext/parallel_execute.py``: chapters longest first on as many kernels as cores) over the
last quiet clean build's execution times (``results/book_build.json``) with and without each
chapter's share (on a quiet machine a kernel has a core: its wall-s are its CPU-s), plus the
Sphinx process's own figures (the Performance page's charts, drawn in each Sphinx step: twice
in the test session's build, once in ``tasks.py book``).  The same replay over this build's
own (loaded) times is recorded too.

An issue whose build cost is a step of its own (``build_probe``: issue 33's check of the
stored maps' fingerprints in the ledger chapter) has that step run in a fresh interpreter,
``--rounds`` times, instead (:func:`probe_build`).  An issue whose tests read no built book
says ``"book": False`` (no build); one without a build allowance (``"build_allowance_s":
None``) gets no build share: its record says "none".

Writes ``benchmarks/results/budget_<issue>.json``.  The machine is shared: the 1-minute load
is recorded at the start, per round and at the end; the spread over rounds is in the notes.

    .venv/bin/python benchmarks/bench_budget.py --issue 35 [--rounds 3] [--book DIR/_build]
    .venv/bin/python benchmarks/bench_budget.py --issue 33 --list
    .venv/bin/python benchmarks/bench_budget.py --compare main tests/test_x.py [...]
"""

from __future__ import annotations

import argparse
import heapq
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _results import Recorder, children_cpu, load, machine_label

ROOT = Path(__file__).resolve().parents[1]
BENCH = Path(__file__).resolve().parent
PY = Path(sys.executable)

#: issue -> its base commit, its allowances, and file -> how it is measured (module docstring).
ISSUES: dict[int, dict] = {
    35: {
        "title": "Rerun, read anywhere",
        "base": "5ddf2b6",
        "test_allowance_cpu_s": 30.0,
        "build_allowance_s": 10.0,
        "files": {
            "tests/book/test_rerun_notebook.py": {"new": True},
            "tests/book/test_cite.py": {"new": True},
            "tests/book/test_raw_markup.py": {"new": True},
            "gyrolib/book/cite.py": {"new": True},  # its doctests
            "tests/book/test_page_figures.py": {"whole": True},
            "gyrolib/_page_figures.py": {"whole": True},  # its doctests
            "tests/book/test_browser.py": {
                "added": ["test_the_ledger_reads_on_a_phone_without_sideways_scrolling",
                          "test_navigation_panels_open_and_close_on_a_phone_and_a_tablet",
                          "test_navigation_sidebar_collapses_and_returns_on_a_desk"],
                "anchor": "test_search_finds_a_term"},
            "tests/project/test_lab.py": {
                "added": ["test_the_pinned_lab_extensions_load",
                          "test_the_lab_extension_check_flags_an_incompatible_extension"],
                "changed": ["test_lab_requirements_are_exact_pins_compatible_with_the_book"]},
            "tests/book/ledger/test_ledger.py": {
                "changed": ["test_json_and_markdown_of_a_known_item"]},
        },
    },
    # The files and tests issue 33 added or changed since the round's start (``git log
    # 5ddf2b6..main``: its commits, and the helper branches sens, sens2, sens3, stats).
    # Left out: test_ledger.py's test_json_and_markdown_of_a_known_item (counted in #35's,
    # which changed it too), test_gc_priors.py's other tests and test_cli_sensitivity.py's
    # help count (issue 34's), the cases #33 added to the tables of test_validation_gc.py and
    # test_validation_rsf.py (milliseconds each, among issue 34's).  test_validation_book.py
    # is counted whole: its few cases of other issues (page_png, gated_nis_band) are in it.
    33: {
        "title": "Verdicts that show where they hold",
        "base": "5ddf2b6",
        "test_allowance_cpu_s": 30.0,
        "build_allowance_s": 10.0,
        # the build: the ledger chapter's check of the stored maps' fingerprint points,
        # which #33 added (the chapters' other changes are not separated from #34's and
        # #36's in a before/after build: not measured here)
        "build_probe": ("the ledger chapter's claims.check_stored() (fingerprint points of "
                        "the stored maps, recomputed)",
                        "from gyrolib.book.ledger import claims as c; import time; "
                        "t = time.process_time(); "
                        "c.check_stored(); print(time.process_time() - t)"),
        "files": {
            "tests/test_claim_map.py": {"new": True},
            "tests/book/ledger/test_margin_study.py": {"new": True},
            "tests/test_inputs.py": {"new": True},
            "tests/book/ledger/test_remaining.py": {"new": True},
            "tests/book/ledger/test_release.py": {"new": True},
            "tests/test_stats.py": {"new": True},
            "tests/project/test_data_records.py": {"new": True},
            # their doctests
            "gyrolib/claim_map.py": {"new": True},
            "gyrolib/inputs.py": {"new": True},
            "gyrolib/levels.py": {"new": True},
            "gyrolib/stats.py": {"new": True},
            "gyrolib/book/ledger/margin_study.py": {"new": True},
            "gyrolib/gc/racing/verdict_grid.py": {"new": True},
            "tests/book/ledger/test_gc.py": {"whole": True},
            "tests/book/ledger/test_rsf.py": {"whole": True},
            "tests/book/ledger/test_rule.py": {"whole": True},
            "tests/sensitivity/test_study.py": {"whole": True},
            "tests/cli/test_race.py": {"whole": True},
            "tests/book/test_bad_input.py": {"whole": True},
            "tests/gc/test_priors.py": {
                "added": ["test_command_default_priors_are_the_table_of_inputs"]},
            "tests/book/ledger/test_ledger.py": {
                "changed": ["test_statuses_and_fields",
                            "test_every_kind_but_inferred_has_an_item_and_the_review_cases"
                            "_are_classified"]},
            "tests/cli/test_sensitivity.py": {
                "changed": ["test_a_run_writes_the_indices_and_the_run_record",
                            "test_extend_reuses_a_smaller_study_and_refuses_another"]},
        },
    },
    # Issue 34's tests: the commits since 5ddf2b6 of its branches cli, sigma, sigma2, sigma3
    # and nis (merges 06a4b7a, 6e80429, a7db5b8, 0131538, 39dccfe, 0b1385a) and the lead's
    # follow-ups on main that name it (51b2760, 6420dc9, 92b6e9b and noise_fit's docstring
    # lines).  'new': files those branches added (test_gc_priors: #33's 1d800f7/5e2c892 and
    # 15a2313 edited the body of #34's one test there, added none); 'whole': files only #34
    # changed; test_gc_monte_carlo (#36's 9f0773a too) and test_cli_sensitivity (#33's
    # d68c258 too): the one test #34 added.  Doctests: the modules #34 added, and the modules
    # only #34 changed (their doctests run the changed code).  Left out: test_one_source.py
    # (#33's file; sigma3 deleted one exception), test_validation_gc/rsf.py (#34's rows are
    # bad-input cases of tables that #33 and #36 grew too; the tool selects whole functions),
    # and the tests #34 did not touch that run its changed code (gc.calibrate's prior checks).
    34: {
        "title": "Every σ covers the truth",
        "base": "5ddf2b6",
        "test_allowance_cpu_s": 40.0,
        "build_allowance_s": None,  # none: the issue gives no build allowance
        "book": False,  # none of these tests reads the built book: no build
        "files": {
            "tests/references/test_allan_reference.py": {"new": True},
            "tests/cli/test_allan.py": {"new": True},
            "tests/cli/test_hints.py": {"new": True},
            "tests/cli/test_log_formats.py": {"new": True},
            "tests/references/test_coverage_seeds.py": {"new": True},
            "tests/gc/test_nis_expectation.py": {"new": True},
            "tests/gc/test_priors.py": {"new": True},
            "tests/rsf/test_uncertainty.py": {"new": True},
            "gyrolib/rsf/uncertainty.py": {"new": True},  # its doctests, as below
            "gyrolib/cli/hints.py": {"new": True},
            "gyrolib/cli/calibrate_gc.py": {"new": True},
            "gyrolib/records/options.py": {"new": True},
            "tests/cli/test_calibrate_faults.py": {"whole": True},
            "tests/cli/test_calibrate.py": {"whole": True},
            "tests/cli/test_calibrate_io.py": {"whole": True},
            "tests/cli/test_calibrate_logs.py": {"whole": True},
            "tests/gc/test_model.py": {"whole": True},
            "tests/gc/test_noise_fit.py": {"whole": True},
            "tests/gc/test_extra_state.py": {"whole": True},
            "tests/records/test_reader.py": {"whole": True},
            "tests/test_imports.py": {"whole": True},
            "gyrolib/gc/logs/allan.py": {"whole": True},
            "gyrolib/gc/logs/calibration.py": {"whole": True},
            "gyrolib/gc/logs/noise_fit.py": {"whole": True},
            "gyrolib/gc/model/params.py": {"whole": True},
            "gyrolib/gc/model/instrument.py": {"whole": True},
            "gyrolib/filtering/consistency.py": {"whole": True},
            "gyrolib/rsf/calibration.py": {"whole": True},
            "gyrolib/records/reader.py": {"whole": True},
            "gyrolib/records/errors.py": {"whole": True},
            "gyrolib/records/plausibility.py": {"whole": True},
            "gyrolib/units.py": {"whole": True},
            "tests/gc/test_monte_carlo.py": {
                "added": ["test_simulate_records_are_the_block_streams_lanes"],
                "anchor": "test_simulate_truth_draws_numpys_block_stream"},
            "tests/cli/test_sensitivity.py": {"added": ["test_help_counts_the_studies_inputs"]},
        },
    },
}


def _worker_modules() -> tuple[str, ...]:
    """The modules ``_worker_imports.py`` imports (its ``MODULES``, read without importing
    it: importing it here would import them into this process)."""
    import ast

    body = ast.parse((BENCH / "_worker_imports.py").read_text(encoding="utf-8")).body
    return next(ast.literal_eval(n.value) for n in body if isinstance(n, ast.AnnAssign)
                and getattr(n.target, "id", "") == "MODULES")


def clean_env(tree: Path) -> dict[str, str]:
    """The environment of a run in ``tree``: no ``GYROLIB_*`` of the caller's but the
    ledger's memo of that tree (:func:`ledger_memo`), the plugin found on ``PYTHONPATH``."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("GYROLIB_")}
    env.update(MPLBACKEND="Agg", PYTHONPATH=str(BENCH), PYDEVD_DISABLE_FILE_VALIDATION="1")
    # BLAS on one thread, as the test command's xdist workers run it (tests/conftest.py)
    env.setdefault("OPENBLAS_NUM_THREADS", "1")
    memo = MEMOS.get(tree)
    if memo is not None:
        env["GYROLIB_LEDGER_MEMO"] = str(memo)
    return env


#: Every run imports first what each worker of the test command has imported anyway
#: (``_worker_imports.py``); ``--per-process`` turns it off (the method of the budgets
#: recorded before 2026-11-29, which charged every new file its interpreter's imports).
WORKER_IMPORTS = True


def importers(tree: Path, modules: tuple[str, ...], skip: set[str]) -> dict[str, int]:
    """How many test files of ``tree`` (those in ``skip`` left out) import each of
    ``modules``, directly or by a submodule: the evidence that a worker imports them anyway."""
    import ast

    count = dict.fromkeys(modules, 0)
    for f in sorted((tree / "tests").glob("test_*.py")):
        if f"tests/{f.name}" in skip:
            continue
        names: set[str] = set()
        for node in ast.walk(ast.parse(f.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                names |= {a.name for a in node.names}
            elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
                names |= {node.module} | {f"{node.module}.{a.name}" for a in node.names}
        for m in modules:
            if any(n == m or n.startswith(m + ".") for n in names):
                count[m] += 1
    return count


#: tree -> the folder of its ledger memo (:func:`ledger_memo`).
MEMOS: dict[Path, Path] = {}


def ledger_memo(tree: Path, folder: Path) -> float:
    """Compute the ledger of ``tree`` once into a memo in ``folder``, which every run in that
    tree then reads: the test command computes it once per session for the dozen tests that
    call ``ledger.collect()`` (``tests/conftest.py``), as it builds the book once.  Returns
    the CPU-s it took (reported, not counted in any test)."""
    folder.mkdir(parents=True, exist_ok=True)
    MEMOS[tree] = folder
    cpu0 = children_cpu()
    subprocess.run([str(PY), "-c", "from gyrolib.book import ledger; ledger.collect()"],
                   cwd=tree, env=clean_env(tree), check=True)
    return children_cpu() - cpu0


def warm_numba(tree: Path) -> float:
    """Compile ``tree``'s numba kernels into its cache as the test command does before its
    session (``WARM_NUMBA`` of that tree's ``tasks.py``), so that no measured run pays a
    compilation the test command does not (a fresh base worktree has no cache: its first run
    of each kernel would).  Returns the CPU-s it took (reported, not counted in any test)."""
    import ast

    source = next(ast.literal_eval(node.value) for node in
                  ast.parse((tree / "tasks.py").read_text(encoding="utf-8")).body
                  if isinstance(node, ast.Assign)
                  and any(getattr(t, "id", "") == "WARM_NUMBA" for t in node.targets))
    cpu0 = children_cpu()
    subprocess.run([str(PY), "-c", source], cwd=tree, env=clean_env(tree), check=True)
    return children_cpu() - cpu0


def pytest_run(tree: Path, args: list[str], book: Path | None) -> dict:
    """One pytest process in ``tree`` (this tree's interpreter): CPU-s of its process tree,
    wall-s, exit status, and each test's phases (``_cpu_per_test``)."""
    env = clean_env(tree)
    if book is not None:
        env["GYROLIB_REUSE_BOOK"] = str(book)
    with tempfile.NamedTemporaryFile(suffix=".json", delete=False) as f:
        per_test = Path(f.name)
    env["GYROLIB_CPU_PER_TEST"] = str(per_test)
    cmd = [str(PY), "-m", "pytest", *args, "-q", "-n", "0", "-p", "no:cacheprovider",
           "-p", "_cpu_per_test", *(["-p", "_worker_imports"] if WORKER_IMPORTS else [])]
    cpu0, t0 = children_cpu(), time.perf_counter()
    with tempfile.TemporaryFile("w+") as out:
        child = subprocess.Popen(cmd, cwd=tree, env=env, stdout=out, stderr=subprocess.STDOUT,
                                 text=True)
        sampled = sample_tree(child)
        out.seek(0)
        stdout = out.read()
    proc = subprocess.CompletedProcess(cmd, child.returncode, stdout, "")
    wall, reaped = time.perf_counter() - t0, children_cpu() - cpu0
    # the larger of the two: Chromium's renderers are not all reaped inside the tree
    # (RUSAGE_CHILDREN misses their CPU), a process shorter than a sampling period is missed
    # by the sampling (RUSAGE_CHILDREN has it)
    cpu = max(reaped, sampled)
    try:
        tests = json.loads(per_test.read_text() or "{}")
    except (OSError, ValueError):
        tests = {}
    per_test.unlink(missing_ok=True)
    tail = proc.stdout.strip().splitlines()[-1:] if proc.stdout.strip() else []
    return {"cpu_s": cpu, "reaped_cpu_s": reaped, "sampled_cpu_s": sampled, "wall_s": wall,
            "exit": proc.returncode, "summary": " ".join(tail),
            "tests": tests, "output_tail": proc.stdout[-1500:] if proc.returncode not in (0, 5)
            else ""}


def sample_tree(child: subprocess.Popen, period: float = 0.1) -> float:
    """Wait for ``child``; every ``period`` s read the CPU-s (user + system) of it and of
    every process below it; return the sum over the processes seen of the last reading."""
    import psutil

    seen: dict[tuple[int, float], float] = {}
    try:
        root = psutil.Process(child.pid)
    except psutil.Error:
        child.wait()
        return 0.0
    while child.poll() is None:
        try:
            procs = [root, *root.children(recursive=True)]
        except psutil.Error:
            procs = [root]
        for q in procs:
            try:
                t = q.cpu_times()
                key = (q.pid, q.create_time())
                seen[key] = max(seen.get(key, 0.0), t.user + t.system)
            except psutil.Error:
                pass
        time.sleep(period)
    return sum(seen.values())


def node_ids(tree: Path, file: str, names: list[str] | None) -> list[str]:
    """The node ids of ``file`` in ``tree`` whose function is one of ``names`` (all: None)."""
    proc = subprocess.run([str(PY), "-m", "pytest", file, "--collect-only", "-q", "-n", "0",
                           "-p", "no:cacheprovider"], cwd=tree, capture_output=True, text=True,
                          env={**os.environ, "PYTHONPATH": str(BENCH)}, check=False)
    ids = [line.strip() for line in proc.stdout.splitlines() if "::" in line]
    if names is None:
        return ids
    got = [i for i in ids if i.split("::")[-1].split("[")[0] in names]
    missing = set(names) - {i.split("::")[-1].split("[")[0] for i in got}
    if missing:
        raise SystemExit(f"{tree}: {file} has no test {sorted(missing)}")
    return got


def plan(issue: dict, base: Path, head: Path) -> list[dict]:
    """The runs to make, as units: each names the runs at the base and here whose CPU-s are
    added (``plus``) and subtracted (``minus``)."""
    startup = ("startup", ["tests/conftest.py"])  # no test file: pytest and conftest alone
    units = []
    for file, how in issue["files"].items():
        if how.get("new"):
            units.append({"file": file, "how": "new: the file here less pytest's start-up",
                          "plus": [("head", file, [file])],
                          "minus": [("head", *startup)]})
        if how.get("whole"):
            units.append({"file": file, "how": "whole file, here less at the base",
                          "plus": [("head", file, [file])],
                          "minus": [("base", file, [file])]})
        if how.get("added"):
            anchor = how.get("anchor")
            a_ids = (node_ids(head, file, [anchor]) if anchor
                     else [file, "--collect-only"])
            added = node_ids(head, file, how["added"])
            units.append({"file": file, "tests": how["added"],
                          "how": f"added: with the anchor {anchor or 'collection'} less the "
                                 "anchor alone, here",
                          "plus": [("head", f"{file} anchor+added", a_ids + added
                                    if anchor else added)],
                          "minus": [("head", f"{file} anchor", a_ids)]})
        if how.get("changed"):
            units.append({"file": file, "tests": how["changed"],
                          "how": "changed: the same tests here less at the base",
                          "plus": [("head", f"{file} changed", node_ids(head, file,
                                                                        how["changed"]))],
                          "minus": [("base", f"{file} changed", node_ids(base, file,
                                                                         how["changed"]))]})
    if WORKER_IMPORTS:  # what the issue made those imports cost more, once per worker
        workers = os.cpu_count() or 1
        units.append({"file": "worker imports",
                      "how": f"imports: the start-up with the worker's imports here less at "
                             f"the base, once per worker ({workers})",
                      "plus": [("head", *startup)] * workers,
                      "minus": [("base", *startup)] * workers})
    return units


def measure(units: list[dict], trees: dict[str, Path], book: Path | None, rounds: int,
            loads: list) -> dict[tuple[str, str], list[dict]]:
    """Every distinct run of ``units``, ``rounds`` times, the base's and this tree's runs
    alternating in order from round to round."""
    runs: dict[tuple[str, str], list[str]] = {}
    for u in units:
        for side, key, args in u["plus"] + u["minus"]:
            runs[(side, key)] = args
    results: dict[tuple[str, str], list[dict]] = {k: [] for k in runs}
    for r in range(rounds):
        order = sorted(runs, key=lambda k: (k[1], (k[0] == "head") == (r % 2 == 0)))
        loads.append(load())
        for side, key in order:
            res = pytest_run(trees[side], runs[(side, key)], book)
            results[(side, key)].append(res)
            print(f"round {r + 1} {side:4s} {res['cpu_s']:7.2f} CPU-s {res['wall_s']:6.1f} s "
                  f"exit {res['exit']} {key}: {res['summary']}", flush=True)
    return results


def med(xs: list[float]) -> float:
    return statistics.median(xs) if xs else 0.0


def unit_figures(u: dict, results: dict) -> dict:
    """A unit's CPU-s: median over rounds of plus − minus, with its spread, and the tests'
    phases (median per test) of its runs here."""
    def cpu(side_key):
        return [r["cpu_s"] for r in results[side_key]]

    plus = [sum(x) for x in zip(*(cpu(k[:2]) for k in u["plus"]), strict=True)]
    minus = [sum(x) for x in zip(*(cpu(k[:2]) for k in u["minus"]), strict=True)]
    deltas = [p - m for p, m in zip(plus, minus, strict=True)]
    tests: dict[str, dict] = {}
    for side, key, _ in u["plus"] + u["minus"]:
        for res in results[(side, key)]:
            for node, ph in res["tests"].items():
                row = tests.setdefault(f"{side}: {node}", {"cpu": [], "outcome": set()})
                row["cpu"].append(sum(v for k, v in ph.items() if k != "outcome"))
                row["outcome"].add(ph.get("outcome", "?"))
    exits = {f"{side}: {key}": sorted({r["exit"] for r in results[(side, key)]})
             for side, key, _ in u["plus"] + u["minus"]}
    return {"file": u["file"], "how": u["how"], "tests_named": u.get("tests"),
            "cpu_s": round(med(deltas), 2), "cpu_s_rounds": [round(d, 2) for d in deltas],
            "plus_cpu_s": round(med(plus), 2), "minus_cpu_s": round(med(minus), 2),
            "runs": {f"{side}: {key}": {
                "cpu_s": [round(r["cpu_s"], 2) for r in results[(side, key)]],
                "reaped_cpu_s": [round(r["reaped_cpu_s"], 2) for r in results[(side, key)]],
                "sampled_cpu_s": [round(r["sampled_cpu_s"], 2) for r in results[(side, key)]]}
                for side, key, _ in u["plus"] + u["minus"]},
            "exit_status": exits,
            "per_test_cpu_s": {n: {"cpu_s": round(med(v["cpu"]), 2),
                                   "outcome": sorted(v["outcome"])}
                               for n, v in sorted(tests.items())}}


def base_tree(commit: str, folder: Path) -> Path:
    path = folder / "base"
    subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", str(path), commit],
                   check=True, capture_output=True)
    return path


# ----------------------------------------------------------------------------- the build


def build_share(book: Path, jobs: int) -> dict:
    """The figure measurement's CPU-s in the build of ``book`` (its ``figure_cpu.jsonl``),
    per chapter (the kernel's glue prefix -> chapter), and the wall-s it adds, estimated by
    replaying the parallel execution (longest chapter first on ``jobs`` kernels) with each
    chapter's execution time less its share."""
    folder = book.parent
    lines = [json.loads(x) for x in (folder / "figure_cpu.jsonl").read_text().splitlines()
             if x.strip()]
    prefix_of = {x["pid"]: x["gluer"] for x in lines if "gluer" in x}
    chapter_of_prefix = {}
    for md in (ROOT / "chapters").glob("*.md"):
        text = md.read_text(encoding="utf-8")
        for p in set(prefix_of.values()):
            if f'gluer("{p}"' in text:
                chapter_of_prefix[p] = md.stem
    per: dict[str, dict] = {}
    for x in lines:
        if "cpu" not in x:
            continue
        name = chapter_of_prefix.get(prefix_of.get(x["pid"], ""), f"pid {x['pid']} (Sphinx)")
        row = per.setdefault(name, {"figures": 0, "cpu_s": 0.0, "wall_s": 0.0, "pids": set()})
        row["figures"] += 1
        row["cpu_s"] += x["cpu"]
        row["wall_s"] += x["end"] - x["start"]
        row["pids"].add(x["pid"])
    record = json.loads((book / "budget_build.json").read_text())
    exec_s = {Path(c).stem: s for c, s in record["chapters"]}

    def makespan(times: dict[str, float]) -> float:
        heap = [0.0] * jobs
        for t in sorted(times.values(), reverse=True):
            heapq.heappush(heap, heapq.heappop(heap) + t)
        return max(heap)

    # this build's own times (a busy machine: the kernels' wall-s are stretched by the load)
    with_fig = makespan(exec_s)
    without = makespan({c: s - per.get(c, {}).get("wall_s", 0.0) for c, s in exec_s.items()})
    kernels = {c: r for c, r in per.items() if c in exec_s}
    sphinx = {c: r for c, r in per.items() if c not in exec_s}
    # a quiet machine: the last quiet clean build's execution times (the ones parallel_execute
    # orders by), each less its chapter's figure CPU-s (a kernel alone on a core: wall = CPU)
    quiet = measured_seconds()
    q_with = makespan(quiet) if quiet else None
    q_without = makespan({c: s - per.get(c, {}).get("cpu_s", 0.0) for c, s in quiet.items()})
    sphinx_steps = max(len(sphinx), 1)  # the test session's build runs Sphinx twice, book once
    sphinx_per_build = sum(r["cpu_s"] for r in sphinx.values()) / sphinx_steps
    return {
        "build_wall_s": record["wall_s"], "build_cpu_s": record["cpu_s"],
        "build_steps_s": record["steps"], "jobs": jobs,
        "figures": sum(r["figures"] for r in per.values()),
        "cpu_s": round(sum(r["cpu_s"] for r in per.values()), 2),
        "kernels_cpu_s": round(sum(r["cpu_s"] for r in kernels.values()), 2),
        "sphinx_cpu_s": round(sum(r["cpu_s"] for r in sphinx.values()), 2),
        "sphinx_steps": len(sphinx),
        "clean_build_cpu_s": round(sum(r["cpu_s"] for r in kernels.values())
                                   + sphinx_per_build, 2),
        "execution_makespan_s": round(with_fig, 1),
        "execution_makespan_without_s": round(without, 1),
        "wall_s_this_build": round(with_fig - without
                                   + sum(r["wall_s"] for r in sphinx.values()) / sphinx_steps,
                                   2),
        "quiet_execution_makespan_s": None if q_with is None else round(q_with, 1),
        "quiet_execution_makespan_without_s": None if q_with is None else round(q_without, 1),
        "wall_s_estimate": None if q_with is None else round(q_with - q_without
                                                              + sphinx_per_build, 2),
        "per_chapter": {c: {"figures": r["figures"], "cpu_s": round(r["cpu_s"], 2),
                            "wall_s": round(r["wall_s"], 2),
                            "execution_s": exec_s.get(c)} for c, r in sorted(per.items())},
    }


def probe_build(issue: dict, rounds: int) -> dict:
    """An issue's own step of the build (``build_probe``: what, and the code that runs it and
    prints its CPU-s), run ``rounds`` times here in a fresh interpreter: none at the base
    (the step is the issue's), so its CPU-s are what it adds; in a build it runs in one
    kernel, alone on a core on a quiet machine (wall-s = CPU-s), and adds that much wall
    only when its chapter is on the build's longest path (an upper bound)."""
    what, code = issue["build_probe"]
    cpu = []
    for _ in range(rounds):
        proc = subprocess.run([str(PY), "-c", code], cwd=ROOT, env=clean_env(ROOT),
                              capture_output=True, text=True, check=True)
        cpu.append(float(proc.stdout.strip().splitlines()[-1]))
    value = round(med(cpu), 2)
    return {"what": what, "cpu_s": value, "cpu_s_rounds": [round(x, 2) for x in cpu],
            "wall_s_estimate": value, "allowance_s": issue["build_allowance_s"],
            "verdict": "within" if value <= issue["build_allowance_s"] else "over",
            "note": f"{what}: {value} CPU-s (rounds {[round(x, 2) for x in cpu]}), none at "
                    "the base; the wall it adds to a clean build at most that (one kernel); "
                    "the issue's other changes to the chapters' execution are not separated "
                    "here from other issues' (not measured)"}


def measured_seconds() -> dict[str, float]:
    """Each chapter's execution time in the last measured (quiet) clean build, by chapter
    name (``benchmarks/results/book_build.json``, as ``_ext/parallel_execute.py`` reads it)."""
    sys.path.insert(0, str(ROOT / "_ext"))
    try:
        from parallel_execute import measured_seconds as read
    except ImportError:  # Sphinx missing: no estimate
        return {}
    return {Path(k).stem: v for k, v in read(ROOT).items()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--issue", type=int, default=35, choices=sorted(ISSUES))
    ap.add_argument("--list", action="store_true",
                    help="print the runs of --issue's plan (node ids) and exit")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--book", type=Path, help="a book built by _book_once.py (its _build)")
    ap.add_argument("--base", help="the commit to compare with (default: the issue's base)")
    ap.add_argument("--compare", nargs="+", metavar="FILE",
                    help="only these files or node ids (A+B: one process for both), at "
                         "--base and here (a cut's before/after)")
    ap.add_argument("--cuts", nargs="+", metavar="TEST", default=[],
                    help="with --cuts-base: these tests (A+B: one process) at that commit and "
                         "here too, in the same rounds (cuts' before/after; not in the sum)")
    ap.add_argument("--cuts-base", help="the commit before the cuts")
    ap.add_argument("--out", help="results name (default budget_<issue>)")
    ap.add_argument("--per-process", action="store_true",
                    help="no worker imports before the tests: each file pays its own "
                         "interpreter's imports (the method before 2026-11-29)")
    args = ap.parse_args()
    global WORKER_IMPORTS
    WORKER_IMPORTS = not args.per_process
    issue = ISSUES[args.issue]
    start_load = load()
    t_start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="gyrolib-budget-") as tmp:
        tmp = Path(tmp)
        book = args.book
        if book is None and issue.get("book", True):  # "book": False: no test reads it
            sys.path.insert(0, str(BENCH))
            from _book_once import build
            record = build(tmp / "book")
            if record["error"]:
                raise SystemExit(record["error"][-3000:])
            book = tmp / "book" / "_build"
        base_commit = args.base or issue["base"]
        base = base_tree(base_commit, tmp)
        try:
            head_commit = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short",
                                          "HEAD"], capture_output=True, text=True).stdout.strip()
            dirty = subprocess.run(["git", "-C", str(ROOT), "status", "--porcelain", "-uno"],
                                   capture_output=True, text=True).stdout.strip()
            if args.compare:
                units = [{"file": f, "how": "the same tests, here less at the base",
                          "plus": [("head", f, f.split("+"))],
                          "minus": [("base", f, f.split("+"))]}
                         for f in args.compare]
            else:
                units = plan(issue, base, ROOT)
            if args.list:  # the plan only: every named test exists at both trees
                for u in units:
                    print(u["file"], "|", u["how"], "|",
                          [(side, key, len(a)) for side, key, a in u["plus"] + u["minus"]])
                return
            trees = {"base": base, "head": ROOT}
            if args.cuts:
                trees["before"] = before = tmp / "before"
                subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach",
                                str(before), args.cuts_base], check=True, capture_output=True)
                units += [{"file": f, "cut": True,
                           "how": f"cut: the same tests here less at {args.cuts_base}",
                           "plus": [("head", f"cut {f}", f.split("+"))],
                           "minus": [("before", f"cut {f}", f.split("+"))]}
                          for f in args.cuts]
            own = {f for f, how in issue["files"].items() if how.get("new")}
            worker_importers = (importers(base, _worker_modules(), own)
                                if WORKER_IMPORTS else None)
            warm_cpu = {side: round(warm_numba(tree), 1) for side, tree in trees.items()}
            memo_cpu = {side: round(ledger_memo(tree, tmp / f"ledger-{side}"), 1)
                        for side, tree in trees.items()}
            loads: list = []
            results = measure(units, trees, book, args.rounds, loads)
        finally:
            for tree in (base, tmp / "before"):
                if tree.exists():
                    subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force",
                                    str(tree)], capture_output=True)
    figures = [unit_figures(u, results) for u in units if not u.get("cut")]
    cuts = [unit_figures(u, results) for u in units if u.get("cut")]
    # the ledger's memo, computed once per test command: what it costs more here counts
    # (one measurement each side, before the rounds; it also carries other issues' changes)
    memo_added = round(memo_cpu["head"] - memo_cpu["base"], 2) if not args.compare else 0.0
    # Two sums.  The net one lets a file that costs less here than at the base offset the
    # others (the budgets recorded until 2026-11-29 did); but a whole file's saving may be
    # another issue's doing (a library made faster since the base), so the verdict takes the
    # sum with every saving counted as 0: no credit for savings, each cost counted in full.
    net = round(sum(f["cpu_s"] for f in figures) + memo_added, 2)
    total = round(sum(max(f["cpu_s"], 0.0) for f in figures) + max(memo_added, 0.0), 2)
    savings = {f["file"]: f["cpu_s"] for f in figures if f["cpu_s"] < 0}
    if memo_added < 0:
        savings["the ledger's session memo"] = memo_added
    name = args.out or (f"budget_{args.issue}" if not args.compare else
                        f"budget_{args.issue}_compare")
    rec = Recorder(name)
    rec.doc["load"] = start_load
    allowance = issue["test_allowance_cpu_s"]
    note = (f"{machine_label(rec.doc['machine'])}; base {base_commit} (git worktree, run with "
            f"this tree's .venv: the base's own pins may differ) against {head_commit}"
            f"{' with uncommitted changes' if dirty else ''}; {args.rounds} rounds alternating, "
            f"median; 1-min load {start_load} at the start, {load()} at the end (shared "
            "machine: CPU-s vary by about 20 %)")
    for f in figures:
        rec.case(f"{f['file']}: CPU-s added ({f['how'].split(':')[0]})", max(f["cpu_s"], 1e-4)
                 if f["cpu_s"] > 0 else 1e-4,
                 note=f"{f['how']}; rounds {f['cpu_s_rounds']}; {note}")
    for f in cuts:
        rec.case(f"{f['file']}: CPU-s of a cut, after less before", abs(f["cpu_s"]) or 1e-4,
                 note=f"{'saves' if f['cpu_s'] < 0 else 'adds'} {abs(f['cpu_s'])} CPU-s: "
                      f"{f['plus_cpu_s']} after, {f['minus_cpu_s']} before "
                      f"({args.cuts_base}); rounds {f['cpu_s_rounds']}; {note}")
    if not args.compare:
        rec.case(f"the ledger's session memo: CPU-s added (here {memo_cpu['head']}, at the "
                 f"base {memo_cpu['base']})", max(memo_added, 1e-4),
                 note=f"ledger.collect() once per test command (tests/conftest.py), one run "
                      f"each side before the rounds; counted in the sum when positive; it "
                      f"carries every issue's change to the ledger since the base; {note}")
    verdict = "within" if total <= allowance else "over"
    method = ("" if WORKER_IMPORTS else
              " by the per-process method, for comparison (each file pays its own "
              "interpreter's imports; the budget's method is the worker imports')")
    rec.case(f"issue {args.issue}: CPU-s added to the test command{method}",
             max(total, 1e-4), target_s=allowance,
             note=f"allowance {allowance} CPU-s: {verdict}; every line's saving counted as 0 "
                  f"(net, with the savings {savings}: {net}); {note}")
    budget = {"issue": args.issue, "title": issue["title"], "base": base_commit,
              "head": head_commit, "dirty": bool(dirty), "rounds": args.rounds,
              "base_run_with": f"this tree's .venv ({PY})", "book": book and str(book),
              "numba_warm_cpu_s": warm_cpu, "ledger_memo_cpu_s": memo_cpu,
              "ledger_memo_added_cpu_s": memo_added,
              "method": ("worker imports: every run imports first "
                         f"{list(_worker_modules())} (benchmarks/_worker_imports.py), as "
                         "each of the test command's workers has by the time the issue's "
                         "tests run; what they cost more here than at the base is the "
                         "'worker imports' line, once per worker" if WORKER_IMPORTS else
                         "per process: every file pays its own interpreter's imports"),
              "worker_module_importers_at_base": worker_importers,
              "load_start": start_load, "load_rounds": loads, "load_end": load(),
              "benchmark_wall_s": round(time.perf_counter() - t_start, 1),
              "tests": figures, "cuts": cuts, "cuts_base": args.cuts_base,
              "test_cpu_s": total, "test_cpu_s_net": net, "savings_not_credited": savings,
              "test_allowance_cpu_s": allowance,
              "test_verdict": verdict}
    if issue.get("build_allowance_s") is None:
        budget["build"] = "none: the issue gives no build allowance"
    elif not args.compare and issue.get("build_probe"):
        share = probe_build(issue, args.rounds)
        budget["build"] = share
        rec.case(f"issue {args.issue}: {share['what']} in a clean build (CPU-s)",
                 max(share["cpu_s"], 1e-4), target_s=issue["build_allowance_s"],
                 note=f"{share['note']}; allowance {issue['build_allowance_s']} s: "
                      f"{share['verdict']}; {note}")
    elif not args.compare and book is not None and (book / "budget_build.json").is_file():
        share = build_share(book, jobs=os.cpu_count() or 1)
        share["allowance_s"] = issue["build_allowance_s"]
        share["verdict"] = ("within" if share["wall_s_estimate"] <= issue["build_allowance_s"]
                            else "over")
        budget["build"] = share
        rec.case(f"issue {args.issue}: the figure measurement in a clean build (wall-s, "
                 "estimated)", max(share["wall_s_estimate"], 1e-4),
                 target_s=issue["build_allowance_s"],
                 note=f"{share['cpu_s']} CPU-s over {share['figures']} figures; wall estimated "
                      f"by replaying the execution on {share['jobs']} kernels; allowance "
                      f"{issue['build_allowance_s']} s: {share['verdict']}; {note}")
    rec.doc["budget"] = budget
    rec.write()
    build = budget.get("build", {})
    print(json.dumps({"test_cpu_s": total, "net": net, "verdict": verdict,
                      "build": build if isinstance(build, str) else build.get("wall_s_estimate")}))


if __name__ == "__main__":
    main()
