"""The jupyter cache is cleared when gyrolib or the pinned environment changes."""

import importlib.util
import shutil
from pathlib import Path
from types import SimpleNamespace

ROOT = Path(__file__).resolve().parents[2]


def _load_extension():
    path = ROOT / "_ext" / "gyrolib_cache.py"
    spec = importlib.util.spec_from_file_location("gyrolib_cache", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _project(tmp_path: Path) -> Path:
    (tmp_path / "gyrolib").mkdir()
    (tmp_path / "gyrolib" / "model.py").write_text("X = 1\n")
    (tmp_path / "requirements.txt").write_text("numpy==2.4.6\n")
    return tmp_path


def _run(ext, root: Path) -> Path:
    cache = root / "_build" / ".jupyter_cache"
    app = SimpleNamespace(srcdir=str(root))
    config = SimpleNamespace(nb_execution_cache_path="_build/.jupyter_cache")
    ext._invalidate(app, config)
    return cache


def test_cache_kept_when_nothing_changes(tmp_path):
    ext = _load_extension()
    root = _project(tmp_path)
    cache = _run(ext, root)
    (cache / "global.db").write_text("cached results")
    _run(ext, root)
    assert (cache / "global.db").read_text() == "cached results"


def test_cache_cleared_when_library_changes(tmp_path):
    ext = _load_extension()
    root = _project(tmp_path)
    cache = _run(ext, root)
    (cache / "global.db").write_text("cached results")
    (root / "gyrolib" / "model.py").write_text("X = 2\n")
    _run(ext, root)
    assert not (cache / "global.db").exists()
    assert (cache / ext.STAMP).read_text().strip() == ext.library_fingerprint(root)


def test_cache_cleared_when_requirements_change(tmp_path):
    ext = _load_extension()
    root = _project(tmp_path)
    cache = _run(ext, root)
    (cache / "global.db").write_text("cached results")
    (root / "requirements.txt").write_text("numpy==2.5.0\n")
    _run(ext, root)
    assert not (cache / "global.db").exists()


def test_new_module_changes_fingerprint(tmp_path):
    ext = _load_extension()
    root = _project(tmp_path)
    before = ext.library_fingerprint(root)
    (root / "gyrolib" / "extra.py").write_text("")
    assert ext.library_fingerprint(root) != before
    shutil.rmtree(root / "gyrolib")
    assert ext.library_fingerprint(root) != before


def test_bytecode_of_a_data_script_leaves_the_fingerprint(tmp_path):
    """Importing a script of data/ (as tests/project/test_data_records.py does while the test
    session builds the book) writes data/__pycache__: the cache must survive it, or the session's
    second build executes every chapter again.  Power: a changed data file does change it."""
    ext = _load_extension()
    root = _project(tmp_path)
    (root / "data").mkdir()
    (root / "data" / "make_records.py").write_text("X = 1\n")
    (root / "data" / "record.csv").write_text("t,x\n0,1\n")
    before = ext.library_fingerprint(root)
    spec = importlib.util.spec_from_file_location("make_records",
                                                  root / "data" / "make_records.py")
    spec.loader.exec_module(importlib.util.module_from_spec(spec))
    (root / "data" / "__pycache__").mkdir(exist_ok=True)
    (root / "data" / "__pycache__" / "make_records.cpython-311.pyc").write_bytes(b"\0" * 16)
    assert ext.library_fingerprint(root) == before
    (root / "data" / "record.csv").write_text("t,x\n0,2\n")
    assert ext.library_fingerprint(root) != before


def test_book_config_wires_the_extension_and_loud_failures():
    import yaml

    cfg = yaml.safe_load((ROOT / "_config.yml").read_text())
    assert cfg["execute"]["execute_notebooks"] == "cache"
    assert cfg["execute"]["raise_on_error"] is True
    assert cfg["execute"]["allow_errors"] is False
    assert cfg["sphinx"]["local_extensions"]["gyrolib_cache"] == "_ext"
    assert "sphinx-mathjax-offline" in cfg["sphinx"]["extra_extensions"]


def test_jupyter_book_is_pinned_below_2():
    pins = dict(
        line.split("==")
        for line in (ROOT / "requirements.txt").read_text().splitlines()
        if "==" in line and not line.startswith("#")
    )
    assert pins["jupyter-book"].startswith("1.")
    for name in ("numpy", "scipy", "control", "matplotlib", "sympy", "myst-nb",
                 "sphinxcontrib-bibtex", "pytest", "ruff"):
        assert name in pins, name


def test_library_change_marks_every_document_outdated(tmp_path):
    ext = _load_extension()
    root = _project(tmp_path)
    app = SimpleNamespace(srcdir=str(root))
    config = SimpleNamespace(nb_execution_cache_path="_build/.jupyter_cache")
    env = SimpleNamespace(found_docs={"a", "b", "c"})
    ext._invalidate(app, config)  # first build: no stamp yet, so everything is new
    assert ext._outdated(app, env, {"a"}, set(), set()) == ["b", "c"]
    ext._invalidate(app, config)  # nothing changed since
    assert ext._outdated(app, env, set(), {"a"}, set()) == []
    (root / "gyrolib" / "model.py").write_text("X = 3\n")
    ext._invalidate(app, config)
    assert ext._outdated(app, env, set(), {"a"}, set()) == ["b", "c"]
