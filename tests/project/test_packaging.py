"""Packaging: gyrolib declares what it imports, and installs and imports with
exactly that.

* Every third-party package a gyrolib module imports (read from the source, imports inside
  functions too) is declared in ``pyproject.toml``: an import that runs when a module loads
  in ``[project] dependencies``, one inside a function there or in an extra.  The same check
  with numba taken out of the declarations reports numba (power).
* Slow (a lean install): a fresh venv, ``pip install --no-deps`` of the
  core set at the versions pinned in ``requirements.txt`` (what ``[project] dependencies``
  require, transitively, read from the metadata of the installed environment; extras left
  out) and of a copy of the package, then: the site-packages size recorded and bounded
  (installed with ``--no-compile``, which halves the install time: the files of the wheels,
  644 MB; pip's default byte-compiling adds about 93 MB, 737 MB in all, measured once by
  hand with this test's set-up (after sympy moved to the ``book`` extra), against
  818 MB before and 821 MB with the extras as dependencies), ``pip
  check`` (every requirement of what is installed is installed: the core set is complete),
  every module of gyrolib imported there
  from outside the source tree against the module list of the source tree (all but
  ``gc.model.symbolic``, whose sympy is the ``book`` extra's: it fails naming the extra), and
  the extras' entry points failing with the error that names the extra.  ``tasks.py setup`` installs
  with ``--no-deps``, which would hide a missing declaration; ``pip check`` does not.
  Skipped, saying so, only when pip reaches no index.
"""

from __future__ import annotations

import ast
import importlib.metadata
import os
import shutil
import subprocess
import sys
import tomllib
import venv
from pathlib import Path

import pytest
from packaging.requirements import Requirement
from packaging.utils import canonicalize_name

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = ROOT / "gyrolib"


def source_modules() -> list[str]:
    """gyrolib's module names, from the files of the source tree."""
    names = []
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = path.relative_to(ROOT).with_suffix("").parts
        names.append(".".join(parts[:-1] if parts[-1] == "__init__" else parts))
    return names


def _is_optional_block(node: ast.AST) -> bool:
    """``with optional(...):`` (``gyrolib._optional``): its imports name their extra when
    missing, so they may be an extra's even when the module loads."""
    return isinstance(node, ast.With) and any(
        isinstance(item.context_expr, ast.Call)
        and getattr(item.context_expr.func, "id",
                    getattr(item.context_expr.func, "attr", None)) == "optional"
        for item in node.items)


def third_party_imports(source: dict[Path, str] | None = None) -> dict[str, bool]:
    """Top-level name of every non-stdlib, non-gyrolib import -> whether some module imports
    it when it loads (outside any function and outside any ``with optional(...)`` block)."""
    found: dict[str, bool] = {}
    if source is None:
        source = {path: path.read_text("utf-8") for path in PACKAGE.rglob("*.py")}
    for text in source.values():
        tree = ast.parse(text)
        in_function = set()
        for node in ast.walk(tree):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef) or _is_optional_block(node):
                in_function.update(id(n) for n in ast.walk(node) if n is not node)
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom) and not node.level:
                names = [node.module]
            else:
                continue
            for name in names:
                top = name.split(".")[0]
                if top in sys.stdlib_module_names or top in ("gyrolib", "__future__"):
                    continue
                found[top] = found.get(top, False) or id(node) not in in_function
    return found


def declared(pyproject: dict) -> tuple[set[str], set[str]]:
    """Distributions in ``[project] dependencies`` and in its extras (canonical names)."""
    project = pyproject["project"]
    deps = {canonicalize_name(Requirement(r).name) for r in project.get("dependencies", [])}
    extras = {canonicalize_name(Requirement(r).name)
              for reqs in project.get("optional-dependencies", {}).values() for r in reqs}
    return deps, extras


def undeclared(imports: dict[str, bool], deps: set[str], extras: set[str]) -> list[str]:
    """Imports whose distribution is not declared where it must be."""
    dists = importlib.metadata.packages_distributions()
    missing = []
    for name, at_load in sorted(imports.items()):
        owners = {canonicalize_name(d) for d in dists.get(name, [name])}
        allowed = deps if at_load else deps | extras
        if not owners & allowed:
            missing.append(f"{name} ({'at load' if at_load else 'in a function'})")
    return missing


def test_every_import_is_declared_in_pyproject():
    pyproject = tomllib.loads((ROOT / "pyproject.toml").read_text("utf-8"))
    imports = third_party_imports()
    deps, extras = declared(pyproject)
    # the packages the modules are known to load with (a floor for the AST walk)
    assert {"numpy", "scipy", "matplotlib", "numba", "sympy", "control"} <= set(imports)
    assert imports["numba"], "numba is imported when a module loads"
    # sympy (the book extra) only under `with optional(...)` or in functions
    assert not imports["sympy"]
    assert undeclared(imports, deps, extras) == []
    # power: the same import outside its `with optional(...)` block counts as at load
    symbolic = PACKAGE / "gc" / "model" / "symbolic.py"
    text = symbolic.read_text("utf-8")
    bare = text.replace('with optional("sympy", "book", "gyrolib.gc.model.symbolic"):\n'
                        '    import sympy as sp', "import sympy as sp")
    assert bare != text
    assert undeclared(third_party_imports({symbolic: bare}), deps, extras) == ["sympy (at load)"]
    # power: without numba in the list the check names it
    assert undeclared(imports, deps - {"numba"}, extras) == ["numba (at load)"]
    # and a load-time import listed only in an extra is not enough
    assert undeclared(imports, deps - {"numba"}, extras | {"numba"}) == ["numba (at load)"]


#: What the extras bring and the core install must not: the book, the sensitivity studies
#: (SALib and pandas), Dask, allantools and what its requirements brought (Sphinx, pytest).
EXTRA_ONLY = ("jupyter-book", "myst-nb", "salib", "pandas", "dask", "distributed",
              "allantools", "sphinx", "pytest", "numpydoc", "sympy", "mpmath")

#: Bound on the core install's site-packages (MB, the wheels' files without byte-compiled
#: ``.pyc``).  Measured: 501 MB with the extras moved out, then 672 MB once the CSV
#: reader moved to pyarrow (171 MB, the field's standard reader, which the project's
#: guide names), against 821 MB byte-compiled with the extras as dependencies before.  The
#: issue's aim of 500 MB is not met: llvmlite's shared library (numba's compiler, 179 MB
#: unstripped) and pyarrow are two thirds of it; the rest is what the library computes with
#: (scipy, numpy, matplotlib with fonttools and pillow; listed in the failure message).
#: sympy and mpmath are in the ``book`` extra, 29 MB of files (86 MB
#: byte-compiled): 643.5 MB measured, the bound down by the same 29 MB; pip's default,
#: byte-compiled install of the core measured 737 MB (site-packages with the bare venv's pip,
#: 22 MB), against the issue's 750 MB (818 MB before).  Since the test installs with the
#: project's pip into a venv without one (no ensurepip), the site-packages no longer
#: hold the bare venv's pip 23.2.1 and setuptools 65.5 (22 MB): the bound down by as much.
MAX_INSTALLED_MB = 649


def pinned_versions() -> dict[str, str]:
    """Canonical name -> version of every ``name==version`` line of requirements.txt."""
    out = {}
    for line in (ROOT / "requirements.txt").read_text("utf-8").splitlines():
        line = line.split("#", 1)[0].strip()
        if "==" in line:
            name, ver = line.split("==", 1)
            out[canonicalize_name(name)] = ver.strip()
    return out


def core_set(requirements: list[str]) -> set[str]:
    """The distributions ``requirements`` need, transitively, without extras they do not
    ask for: read from the metadata of this (fully installed) environment."""
    found: dict[str, set[str]] = {}
    todo = [Requirement(r) for r in requirements]
    while todo:
        req = todo.pop()
        name = canonicalize_name(req.name)
        extras = found.get(name)
        if extras is not None and set(req.extras) <= extras:
            continue
        found[name] = (extras or set()) | set(req.extras)
        dist = importlib.metadata.distribution(name)
        for raw in dist.requires or []:
            sub = Requirement(raw)
            envs = [{"extra": e} for e in sorted(found[name]) or [""]]
            if sub.marker is None or any(sub.marker.evaluate(e) for e in envs):
                todo.append(sub)
    return set(found)


def test_core_set_leaves_the_extras_out():
    """The core set of pyproject's dependencies holds none of the extras' packages, is
    pinned in requirements.txt, and the same walk over the extras finds them (power)."""
    pyproject = tomllib.loads((ROOT / "pyproject.toml").read_text("utf-8"))
    core = core_set(pyproject["project"]["dependencies"])
    assert {"numpy", "scipy", "numba", "llvmlite", "matplotlib"} <= core
    assert not core & set(EXTRA_ONLY), core & set(EXTRA_ONLY)
    assert core <= set(pinned_versions()), core - set(pinned_versions())
    extras = pyproject["project"]["optional-dependencies"]
    everything = core_set(pyproject["project"]["dependencies"] + extras["sensitivity"]
                          + extras["allan"] + extras["book"])
    assert {"salib", "pandas", "allantools", "sphinx", "pytest", "myst-nb", "sympy",
            "mpmath"} <= everything


def test_a_missing_extra_is_named():
    """Without SALib, gyrolib.sensitivity says which extra installs it; a missing module
    that is not the one asked for is raised as it is."""

    from gyrolib._optional import optional

    saved = {k: v for k, v in sys.modules.items() if k == "SALib" or k.startswith("SALib.")}
    try:
        for k in [*saved, "SALib"]:
            sys.modules[k] = None
        import gyrolib.sensitivity as sens
        with pytest.raises(ModuleNotFoundError,
                           match=r"^gyrolib.sensitivity needs SALib, an optional dependency: "
                                 r"pip install 'gyrolib\[sensitivity\]'$"):
            sens.unit_sample(3, 4, seed=0)
    finally:
        for k in [*saved, "SALib"]:
            sys.modules.pop(k, None)
        sys.modules.update(saved)
    assert sens.unit_sample(3, 4, seed=0).shape == (32, 3)   # back with SALib
    with pytest.raises(ModuleNotFoundError, match=r"^No module named 'json\.no_such_module_xyz'"):
        with optional("json", "demo", "demo"):   # installed: a missing submodule as it is
            import json.no_such_module_xyz  # noqa: F401


# The fresh environment --------------------------------------------------------------------------
_WALK = """
import importlib, pkgutil, sys, gyrolib
names = ["gyrolib"] + [m.name for m in pkgutil.walk_packages(gyrolib.__path__, "gyrolib.")]
for name in names:
    try:
        importlib.import_module(name)
    except ModuleNotFoundError as exc:   # the book extra's module: its error, on stderr
        print(name + ": " + str(exc), file=sys.stderr)
print(gyrolib.__file__)
print("\\n".join(sorted(names)))
"""

#: The modules of an extra, and what importing them says in the core install.
_EXTRA_MODULES = {
    "gyrolib.gc.model.symbolic": "gyrolib.gc.model.symbolic needs sympy, an optional "
                                 "dependency: pip install 'gyrolib[book]'",
}

_EXTRA = """
from gyrolib.sensitivity import unit_sample
try:
    unit_sample(3, 4, seed=0)
except ModuleNotFoundError as exc:
    print(exc)
"""


def _run(args: list[str], cwd: Path, timeout: float) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    env.update(MPLBACKEND="Agg", PIP_DISABLE_PIP_VERSION_CHECK="1")
    return subprocess.run(args, cwd=cwd, env=env, capture_output=True, text=True,
                          timeout=timeout, check=False)


def _tree_mb(path: Path) -> float:
    return sum(f.stat().st_size for f in path.rglob("*") if f.is_file() and not f.is_symlink())\
        / 1e6


@pytest.mark.full
def test_lean_install_size_imports_and_extras(tmp_path):
    """Full tier (an install into a new environment, about 20 CPU-s; the everyday tier checks
    the declared sets, above): the core install's size, its imports, and the extras."""
    # a copy of what the package is built from, so the build writes nothing into the checkout
    src = tmp_path / "src"
    src.mkdir()
    for name in ("pyproject.toml", "README.md"):
        shutil.copy2(ROOT / name, src / name)
    shutil.copytree(PACKAGE, src / "gyrolib",
                    ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    env_dir = tmp_path / "venv"
    # a bare venv, and the project's pinned pip installs into it (``pip --python``): no
    # ensurepip (6 CPU-s of the test's 27 on the 2-core AVX2 machine), and the
    # site-packages measured hold the core install alone
    venv.EnvBuilder(with_pip=False, clear=True).create(env_dir)
    py = env_dir / ("Scripts" if os.name == "nt" else "bin") / "python"
    pip = [sys.executable, "-m", "pip", "--python", str(py)]
    site = Path(_run([str(py), "-c", "import sysconfig; print(sysconfig.get_path('purelib'))"],
                     tmp_path, timeout=60).stdout.strip())

    pyproject = tomllib.loads((ROOT / "pyproject.toml").read_text("utf-8"))
    pins = pinned_versions()
    core = sorted(core_set(pyproject["project"]["dependencies"]))
    install = _run([*pip, "install", "--quiet", "--no-deps", "--no-compile",
                    *[f"{n}=={pins[n]}" for n in core], str(src)], tmp_path, timeout=1800)
    out = install.stdout + install.stderr
    if install.returncode != 0:
        # skip only when pip finds no index at all (its wording for that varies with the
        # version and the retries, so ask it directly); any other failure is a failure
        probe = _run([*pip, "index", "versions", "numpy"], tmp_path,
                     timeout=300)
        if probe.returncode != 0:
            last = (probe.stdout + probe.stderr).strip().splitlines()[-1:]
            pytest.skip("pip could not reach any package index, so gyrolib's dependencies "
                        f"cannot be installed here ({' '.join(last)})")
    assert install.returncode == 0, f"pip install failed:\n{out[-4000:]}"

    # every requirement of what is installed is installed: the core set is complete
    check = _run([*pip, "check"], tmp_path, timeout=300)
    assert check.returncode == 0, check.stdout + check.stderr

    total_mb = _tree_mb(site)
    per = sorted(((_tree_mb(p), p.name) for p in site.iterdir() if p.is_dir()), reverse=True)
    print(f"installed size: {total_mb:.0f} MB in site-packages, not byte-compiled; "
          f"{len(core)} distributions: {', '.join(core)}")
    print("largest: " + ", ".join(f"{name} {mb:.0f} MB" for mb, name in per[:8]))
    assert total_mb <= MAX_INSTALLED_MB, (f"{total_mb:.0f} MB > {MAX_INSTALLED_MB} MB; "
                                          f"largest: {per[:8]}")

    walk = _run([str(py), "-c", _WALK], tmp_path, timeout=600)
    assert walk.returncode == 0, f"importing gyrolib's modules failed:\n{walk.stderr[-4000:]}"
    location, *names = walk.stdout.split()
    assert Path(location).resolve().is_relative_to(env_dir.resolve())   # not the checkout
    assert names == sorted(source_modules())
    # every module imports but the book extra's, which names the extra (and nothing else)
    failed = dict(line.split(": ", 1) for line in walk.stderr.splitlines() if ": " in line
                  and line.startswith("gyrolib."))
    assert failed == _EXTRA_MODULES, walk.stderr[-4000:]

    # the extras are not there, and asking for one says which to install
    extra = _run([str(py), "-c", _EXTRA], tmp_path, timeout=300)
    assert extra.stdout.strip() == ("gyrolib.sensitivity needs SALib, an optional dependency: "
                                    "pip install 'gyrolib[sensitivity]'"), extra.stderr
    cli = _run([str(py), "-m", "gyrolib", "sensitivity", "rsf", "--n", "8", "--out",
                str(tmp_path / "s.json")], tmp_path, timeout=300)
    assert cli.returncode == 2 and len(cli.stderr.strip().splitlines()) == 1, cli.stderr
    assert "pip install 'gyrolib[sensitivity]'" in cli.stderr
    assert not (tmp_path / "s.json").exists()
