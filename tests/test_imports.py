"""The import graph of gyrolib runs one way (issue 20, "the knots"): records and parameters flow
from :mod:`gyrolib.records` into the paper subpackages, never back; the command line sits
above both; datasheet specs never import the simulation that models them.

The graph is read from the source (every ``import``, also inside functions), so a lazy import
that runs back up is caught too.  An edge goes from a module to the module it names
(``from gyrolib.gc.model.params import X`` -> ``gyrolib.gc.model.params``); a package's ``__init__``
re-exports its modules and is left out as a target, as Python resolves the named module.
"""

from __future__ import annotations

import ast
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
    ``__import__`` or ``importlib.import_module`` hiding an edge (issue 22: the ledger loaded
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


# Lazy heavy imports (issue 18, item 6: the command line's start) ---------------------------
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
    loading numpy, numba or pyarrow (issue 34, item 11: they took 2–5 s); importing a
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


# Rooms by role (issue 29, item 1) -------------------------------------------------------------
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
    """Every ``plot_*`` function is defined in a ``plots`` module, none in a compute module."""
    outside = [f"{p.relative_to(ROOT.parent)}:{n.name}" for p in ROOT.rglob("*.py")
               if p.stem != "plots"
               for n in ast.parse(p.read_text("utf-8")).body
               if isinstance(n, ast.FunctionDef) and n.name.startswith("plot_")]
    assert outside == []


def test_gc_is_divided_into_rooms_by_role():
    """``gyrolib.gc`` holds its four rooms and the figures, no loose compute modules; the
    docstring table maps every numbered equation and figure of paper GC to a module that
    exists."""
    import re

    import gyrolib.gc as gc

    loose = sorted(p.name for p in (ROOT / "gc").glob("*.py"))
    assert loose == ["__init__.py", "plots.py"]
    rooms = sorted(p.name for p in (ROOT / "gc").iterdir() if (p / "__init__.py").exists())
    assert rooms == ["analysis", "logs", "model", "racing"]
    doc = gc.__doc__
    for k in range(1, 9):
        assert f"Eq. ({k})" in doc, k
    for k in range(1, 5):
        assert f"Figure {k}" in doc, k
    for module in set(re.findall(r"``gc\.(\w+\.\w+)``", doc)):
        assert (ROOT / "gc" / (module.replace(".", "/") + ".py")).exists(), module
