"""The import graph of gyrolib runs one way: records and parameters flow
from :mod:`gyrolib.records` into the paper subpackages, never back; the command line sits
above both; datasheet specs never import the simulation that models them.

The graph is read from the source (every ``import``, also inside functions), so a lazy import
that runs back up is caught too.  An edge goes from a module to the module it names
(``from gyrolib.gc.model.params import X`` -> ``gyrolib.gc.model.params``); a package's ``__init__``
re-exports its modules and is left out as a target, as Python resolves the named module.
"""

from __future__ import annotations

import ast
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1] / "gyrolib"


def _module_name(path: Path) -> str:
    parts = path.relative_to(ROOT.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def import_graph() -> dict[str, set[str]]:
    """Module -> the gyrolib modules it imports (module-level or inside functions)."""
    modules = {_module_name(p): p for p in ROOT.rglob("*.py")}
    graph: dict[str, set[str]] = {}
    for name, path in modules.items():
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        targets: set[str] = set()
        for node in ast.walk(ast.parse(path.read_text("utf-8"))):
            if isinstance(node, ast.Import):
                targets.update(a.name for a in node.names)
            elif isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    base = ".".join(package.split(".")[: len(package.split(".")) - node.level
                                                        + 1] + ([base] if base else []))
                for alias in node.names:  # `from pkg import module` names a module
                    full = f"{base}.{alias.name}"
                    targets.add(full if full in modules else base)
        graph[name] = {t for t in targets if t in modules and t != name}
    return graph


def _reaches(graph: dict[str, set[str]], start: str) -> set[str]:
    seen, todo = set(), [start]
    while todo:
        for nxt in graph.get(todo.pop(), ()):
            if nxt not in seen:
                seen.add(nxt)
                todo.append(nxt)
    return seen


def cycles(graph: dict[str, set[str]]) -> list[tuple[str, str]]:
    """Pairs (a, b) with a importing b and b reaching a again; packages' ``__init__`` files
    are left out as targets (importing a module runs its package's ``__init__``, which is not
    a dependency of the module's code)."""
    packages = {m for m in graph if (ROOT.parent / m.replace(".", "/") / "__init__.py").exists()}
    inner = {m: {t for t in ts if t not in packages} for m, ts in graph.items()}
    return sorted((a, b) for a, ts in inner.items() for b in ts if a in _reaches(inner, b))


GRAPH = import_graph()


def test_the_graph_sees_known_edges():
    """The parser finds imports at module level, inside functions and relative ones."""
    assert "gyrolib.gc.model.params" in GRAPH["gyrolib.gc.analysis.covariance"]
    assert "gyrolib.records.reader" in GRAPH["gyrolib.cli.calibrate_gc"]
    assert "gyrolib.cli.calibrate_gc" in GRAPH["gyrolib.cli.calibrate"]   # inside run()
    assert "gyrolib.rsf.sensors" in GRAPH["gyrolib.rsf.simulation"]


def test_cycle_finder_has_power():
    """A deliberately circular graph is reported, an acyclic one is not."""
    assert cycles({"a": {"b"}, "b": {"a"}, "c": set()}) == [("a", "b"), ("b", "a")]
    assert cycles({"a": {"b"}, "b": set()}) == []


def test_no_module_imports_back_up():
    assert cycles(GRAPH) == []


@pytest.mark.parametrize("package", ["gyrolib.gc", "gyrolib.rsf", "gyrolib.filtering"])
def test_paper_subpackages_never_import_records_or_the_command_line(package):
    mine = [m for m in GRAPH if m == package or m.startswith(package + ".")]
    bad = {(m, t) for m in mine for t in GRAPH[m]
           if t.startswith(("gyrolib.records", "gyrolib.cli"))}
    assert bad == set()


def test_records_never_imports_the_command_line():
    mine = [m for m in GRAPH if m.startswith("gyrolib.records")]
    assert not {t for m in mine for t in GRAPH[m] if t.startswith("gyrolib.cli")}


def test_datasheet_specs_do_not_import_the_simulation():
    assert not _reaches(GRAPH, "gyrolib.rsf.sensors") & {"gyrolib.rsf.simulation"}


def test_no_dynamic_imports():
    """Every import is an ordinary statement that this graph (and a reader) can see: no
    ``__import__`` or ``importlib.import_module`` hiding an edge (the ledger loaded
    its paper modules that way, and they imported the ledger back)."""
    found = []
    for path in ROOT.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text("utf-8"))):
            if isinstance(node, ast.Call):
                f = node.func
                name = f.id if isinstance(f, ast.Name) else getattr(f, "attr", "")
                if name in ("__import__", "import_module"):
                    found.append(f"{path.relative_to(ROOT.parent)}:{node.lineno}")
    assert found == []


# Lazy heavy imports (the command line's start) ---------------------------
HEAVY = ("matplotlib", "sympy", "control", "scipy.stats")


def _fresh(code: str) -> list[str]:
    """The heavy modules loaded after running ``code`` in a fresh interpreter."""
    import subprocess
    import sys

    out = subprocess.run([sys.executable, "-c", code + "\nimport sys\nprint(' '.join(m for m in "
                          f"{HEAVY!r} if m in sys.modules))"], capture_output=True, text=True,
                         check=True)
    return out.stdout.split()


def test_command_line_does_not_import_plotting_or_sympy(tmp_path):
    """Importing the command line, and calibrating a file with --json, loads neither
    matplotlib, sympy, python-control nor scipy.stats; importing gc.plots does (the check
    has power)."""
    assert _fresh("import gyrolib.cli.calibrate") == []
    assert _fresh("import gyrolib.cli") == []
    path = tmp_path / "r.csv"
    t = [0.001 * k for k in range(1, 201)]
    path.write_text("t,angle_sensor,inclinometer_y,inclinometer_z\n"
                    + "".join(f"{x:.3f},0,0,0\n" for x in t))
    run = (f"from gyrolib.cli import main\nimport contextlib, io\n"
           f"with contextlib.redirect_stdout(io.StringIO()):\n"
           f"    main(['calibrate', 'gc', {str(path)!r}, '--json'])")
    assert _fresh(run) == []
    assert set(_fresh("from gyrolib import gc\ngc.plot_figure1\ngc.symbolic")) >= {
        "matplotlib", "sympy"}


def test_help_loads_no_numerics():
    """``python -m gyrolib --help`` and the commands' ``--help`` build the parsers without
    loading numpy, numba or pyarrow (they took 2–5 s); importing a
    calibration's run in the same kind of process loads numpy (the probe's power).
    (``sensitivity --help`` reads its studies' numbers of inputs from the studies: numpy.)"""
    import subprocess
    import sys

    watch = ("numpy", "numba", "pyarrow")
    probe = ("import contextlib, io, sys\nfrom gyrolib.cli import main\n"
             "for argv in (['--help'], ['calibrate', '--help'], ['calibrate', 'gc', '--help'],"
             " ['calibrate', 'rsf', '--help'], ['race', '--help'],"
             " ['ledger', '--help']):\n"
             "    try:\n"
             "        with contextlib.redirect_stdout(io.StringIO()):\n"
             "            main(argv)\n"
             "    except SystemExit as exc:\n"
             "        assert exc.code == 0, argv\n"
             f"print(' '.join(m for m in {watch!r} if m in sys.modules))\n"
             "import gyrolib.cli.calibrate_gc\n"
             f"print(' '.join(m for m in {watch!r} if m in sys.modules))\n")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                         check=True)
    help_loaded, run_loaded = out.stdout.split("\n")[:2]
    assert help_loaded == ""
    assert "numpy" in run_loaded.split()


def test_records_names_resolve_lazily():
    """Every name of ``gyrolib.records.__all__`` resolves on first use to the object of the
    module that defines it, and is listed by dir(); an unknown name is an AttributeError."""
    import gyrolib.records as records
    import gyrolib.records.errors
    import gyrolib.records.options
    import gyrolib.records.reader

    for name in records.__all__:
        assert getattr(records, name) is not None, name
    assert set(records.__all__) <= set(dir(records))
    assert records.read_gc is gyrolib.records.reader.read_gc
    assert records.parse_columns is gyrolib.records.options.parse_columns
    assert records.OptionError is gyrolib.records.errors.OptionError
    with pytest.raises(AttributeError, match="no attribute 'read_nothing'"):
        records.read_nothing  # noqa: B018


@pytest.mark.parametrize("package", ["gyrolib.gc", "gyrolib.rsf"])
def test_lazy_names_still_resolve(package):
    """Every name of ``__all__`` resolves (the plots and gc.symbolic on first access), is
    listed by dir(), and is the object of the module that defines it."""
    import importlib

    pkg = importlib.import_module(package)
    for name in pkg.__all__:
        assert getattr(pkg, name) is not None, name
    assert set(pkg.__all__) <= set(dir(pkg))
    plots = pkg.plots
    lazy = sorted(n for n in pkg.__all__ if n.startswith("plot_") and hasattr(plots, n))
    assert lazy and all(getattr(pkg, n) is getattr(plots, n) for n in lazy)
    with pytest.raises(AttributeError, match="no attribute 'plot_nothing'"):
        pkg.plot_nothing  # noqa: B018
    if package == "gyrolib.gc":
        from gyrolib.gc import plot_figure1, symbolic

        assert plot_figure1 is plots.plot_figure1
        assert symbolic.__name__ == "gyrolib.gc.model.symbolic"


# Rooms by role -------------------------------------------------------------
#: The named-tuple API, whose leading underscore is not a privacy mark.
_NAMEDTUPLE_API = frozenset({"_replace", "_asdict", "_fields", "_make",
                             # the type argparse's add_subparsers returns, which has no
                             # public name: used in annotations only
                             "_SubParsersAction"})
#: Documented public functions of the standard library spelt with an underscore: ``os._exit``
#: (end the process without the interpreter's clean-up).
_STDLIB_PUBLIC = frozenset({("os", "_exit")})


def private_reaches(root: Path = ROOT) -> list[str]:
    """``module:line name`` for every place a gyrolib module uses another object's private
    name: ``from gyrolib.x import _y``, or an attribute ``obj._y`` of anything but ``self``
    and ``cls`` (a package's private helper modules, ``gyrolib._validation`` and the like,
    are imported whole and their public names used)."""
    found = []
    for path in root.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text("utf-8"))):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("gyrolib"):
                found += [f"{path.relative_to(root.parent)}:{node.lineno} {a.name}"
                          for a in node.names if a.name.startswith("_")
                          and not a.name.startswith("__")
                          and f"{node.module}.{a.name}" not in _PRIVATE_MODULES]
            elif (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
                  and node.func.id in ("getattr", "hasattr") and len(node.args) >= 2
                  and isinstance(node.args[1], ast.Constant)
                  and isinstance(node.args[1].value, str)
                  and node.args[1].value.startswith("_")
                  and not node.args[1].value.startswith("__")):
                # the same reach spelt as a string
                found.append(f"{path.relative_to(root.parent)}:{node.lineno} "
                             f"{node.args[1].value}")
            elif (isinstance(node, ast.Attribute) and node.attr.startswith("_")
                  and not node.attr.startswith("__") and node.attr not in _NAMEDTUPLE_API
                  and not (isinstance(node.value, ast.Name)
                           and (node.value.id in ("self", "cls")
                                or (node.value.id, node.attr) in _STDLIB_PUBLIC))):
                found.append(f"{path.relative_to(root.parent)}:{node.lineno} {node.attr}")
    return sorted(found)


_PRIVATE_MODULES = frozenset(_module_name(p) for p in ROOT.rglob("_*.py")
                             if not p.name.startswith("__"))


def test_no_module_reaches_into_another_modules_private_names():
    assert private_reaches() == []


def test_private_reach_finder_has_power(tmp_path):
    """A module that calls another object's private method, or imports a private name, is
    reported; one that uses its own ``self._x`` and a named tuple's ``_replace`` is not."""
    pkg = tmp_path / "gyrolib"
    pkg.mkdir()
    (pkg / "a.py").write_text("from gyrolib.b import _helper\n\ndef f(m):\n"
                              "    return m._optimal_run_n(1), m._replace(x=1)\n\n"
                              "def g(ex):\n    return getattr(ex, '_processes', {})\n")
    (pkg / "b.py").write_text("class B:\n    def g(self):\n        return self._h()\n")
    assert private_reaches(pkg) == ["gyrolib/a.py:1 _helper", "gyrolib/a.py:4 _optimal_run_n",
                                    "gyrolib/a.py:7 _processes"]


def test_figures_live_in_plots_modules():
    """Every ``plot_*`` function is defined in a plots module (``plots``, ``claim_plots``),
    none in a compute module."""
    outside = [f"{p.relative_to(ROOT.parent)}:{n.name}" for p in ROOT.rglob("*.py")
               if not p.stem.endswith("plots")
               for n in ast.parse(p.read_text("utf-8")).body
               if isinstance(n, ast.FunctionDef) and n.name.startswith("plot_")]
    assert outside == []


def test_gc_is_divided_into_rooms_by_role():
    """``gyrolib.gc`` holds its four rooms, the figures and its rows of the table of inputs,
    no loose compute modules; the
    docstring table maps every numbered equation and figure of paper GC to a module that
    exists."""
    import re

    import gyrolib.gc as gc

    loose = sorted(p.name for p in (ROOT / "gc").glob("*.py"))
    assert loose == ["__init__.py", "inputs.py", "plots.py"]
    rooms = sorted(p.name for p in (ROOT / "gc").iterdir() if (p / "__init__.py").exists())
    assert rooms == ["analysis", "logs", "model", "racing"]
    doc = gc.__doc__
    for k in range(1, 9):
        assert f"Eq. ({k})" in doc, k
    for k in range(1, 5):
        assert f"Figure {k}" in doc, k
    for module in set(re.findall(r"``gc\.(\w+\.\w+)``", doc)):
        assert (ROOT / "gc" / (module.replace(".", "/") + ".py")).exists(), module


# In-function imports: start-up time only ------------------------------------------------------
#: Every import of a gyrolib module inside a function, outside the command line: (module,
#: function, imported module) -> why it waits until called.  Nothing else imports inside a
#: function (a module never dodges a circle that way: the layers below forbid the circle).
START_UP_IMPORTS: dict[tuple[str, str, str], str] = {
    ("gyrolib.gc", "__getattr__", "gyrolib.gc.plots"): "matplotlib",
    ("gyrolib.gc.model", "__getattr__", "gyrolib.gc.model.symbolic"): "sympy",
    ("gyrolib.rsf", "__getattr__", "gyrolib.rsf.plots"): "matplotlib",
    ("gyrolib.sensitivity", "__getattr__", "gyrolib.sensitivity.plots"): "matplotlib",
    ("gyrolib.records", "__getattr__", "gyrolib.records.params"): "numpy, not for --help",
    ("gyrolib.records", "__getattr__", "gyrolib.records.plausibility"): "numpy",
    ("gyrolib.records", "__getattr__", "gyrolib.records.rate_log"): "numpy and pyarrow",
    ("gyrolib.records.params", "_paper_rsf", "gyrolib.rsf"): "paper RSF, not for a GC run",
    ("gyrolib.records.plausibility", "check_rsf", "gyrolib.rsf.record"): "paper RSF",
    ("gyrolib.records.reader", "_rsf_record", "gyrolib.rsf.record"): "paper RSF",
}


def in_function_imports(root: Path = ROOT) -> list[tuple[str, str, str, str]]:
    """``(module, function, imported module, source line)`` for every import of a gyrolib
    module inside a function, outside ``gyrolib.cli`` (``from pkg import a, b`` counts once,
    as ``pkg``)."""
    found = []
    for path in sorted(root.rglob("*.py")):
        name = ".".join(path.relative_to(root.parent).with_suffix("").parts).removesuffix(
            ".__init__")
        if name.startswith(f"{root.name}.cli"):
            continue
        lines = path.read_text("utf-8").splitlines()
        tree = ast.parse("\n".join(lines))
        for fn in ast.walk(tree):
            if not isinstance(fn, ast.FunctionDef | ast.AsyncFunctionDef):
                continue
            for node in ast.walk(fn):
                if isinstance(node, ast.Import):
                    targets = [a.name for a in node.names]
                elif isinstance(node, ast.ImportFrom) and not node.level:
                    targets = [node.module or ""]
                else:
                    continue
                found += [(name, fn.name, t, lines[node.lineno - 1]) for t in targets
                          if t == root.name or t.startswith(root.name + ".")]
    return sorted(set(found))


def test_in_function_imports_are_for_start_up_time_only():
    """Outside the command line at most 10 imports of gyrolib modules wait inside a
    function, each on the allow-list and with its reason in a comment on its line."""
    found = in_function_imports()
    assert {f[:3] for f in found} == set(START_UP_IMPORTS)
    assert len(found) <= 10
    assert [f for f in found if "# start-up:" not in f[3]] == []


def test_in_function_import_finder_has_power(tmp_path):
    """An import inside a function is found, nested or not, with its line; one at module
    level and one of another package are not."""
    pkg = tmp_path / "gyrolib"
    (pkg / "gc").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "gc" / "__init__.py").write_text("")
    (pkg / "gc" / "a.py").write_text(
        "import gyrolib.units\n\ndef f():\n    import numpy\n\n    def g():\n"
        "        from gyrolib import inputs  # a circle dodged\n    return g\n")
    assert in_function_imports(pkg) == [
        ("gyrolib.gc.a", "f", "gyrolib", "        from gyrolib import inputs  # a circle dodged"),
        ("gyrolib.gc.a", "g", "gyrolib", "        from gyrolib import inputs  # a circle dodged")]


def test_the_paper_packages_never_import_the_table_of_inputs():
    """The table of inputs sits above both papers: no module of gc or rsf imports it (each
    paper's rows are its own ``inputs`` module)."""
    bad = {(m, t) for m in GRAPH if m.startswith(("gyrolib.gc", "gyrolib.rsf"))
           for t in GRAPH[m] if t == "gyrolib.inputs"}
    assert bad == set()
    assert "gyrolib.inputs" in GRAPH["gyrolib.book.ledger"]          # the finder's power


def test_the_discretization_takes_the_continuous_model_whole():
    """``gc/model/discretization.py`` imports from the continuous side only the model's type,
    :class:`ContinuousModel`, and nothing from the instrument module."""
    tree = ast.parse((ROOT / "gc" / "model" / "discretization.py").read_text("utf-8"))
    names = {(n.module, a.name) for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)
             for a in n.names if n.module and n.module.startswith("gyrolib.gc.model.")}
    assert {m for m, _ in names} == {"gyrolib.gc.model.params", "gyrolib.gc.model.state_space"}
    assert {a for m, a in names if m == "gyrolib.gc.model.state_space"} == {"ContinuousModel"}


def _lint_imports(cwd: Path, pythonpath: Path | None = None) -> subprocess.CompletedProcess:
    import os
    import sys

    env = dict(os.environ)
    if pythonpath is not None:
        env["PYTHONPATH"] = str(pythonpath)
    exe = Path(sys.executable).with_name("lint-imports")
    return subprocess.run([str(exe), "--no-logo", "--no-cache"], cwd=cwd, env=env,
                          capture_output=True, text=True)


def test_the_layers_contract_holds_and_has_power(tmp_path):
    """import-linter keeps the contracts of ``pyproject.toml`` on the tree, and breaks the
    layers on a copy where a paper module imports the table of inputs inside a function."""
    import shutil

    root = ROOT.parent
    kept = _lint_imports(root)
    assert kept.returncode == 0, kept.stdout + kept.stderr
    assert "0 broken" in kept.stdout
    shutil.copytree(ROOT, tmp_path / "gyrolib",
                    ignore=shutil.ignore_patterns("__pycache__", "*.nbi", "*.nbc"))
    shutil.copy(root / "pyproject.toml", tmp_path / "pyproject.toml")
    target = tmp_path / "gyrolib" / "gc" / "model" / "params.py"
    target.write_text(target.read_text("utf-8")
                      + "\n\ndef _rows():\n    from gyrolib import inputs\n\n    return inputs\n")
    broken = _lint_imports(tmp_path, tmp_path)
    assert broken.returncode != 0
    assert "gyrolib.gc.model.params -> gyrolib.inputs" in broken.stdout, broken.stdout


def test_every_public_name_still_imports_from_where_it_did():
    """Every name of every module's ``__all__`` as recorded before the table of inputs was
    split between the papers (``tests/support/public_names.json``) still imports from that
    module."""
    import importlib
    import json

    recorded = json.loads((Path(__file__).parent / "support" / "public_names.json")
                          .read_text("utf-8"))
    missing = [f"{mod}.{name}" for mod, names in recorded.items()
               for name in names if not hasattr(importlib.import_module(mod), name)]
    assert missing == []
    assert len(recorded) == 87 and sum(map(len, recorded.values())) == 993
