"""Rerunning the chapters in Jupyter with pinned versions.

* ``requirements-lab.txt`` pins every package exactly, and ``tasks.py`` installs nothing
  unpinned (every ``pip install`` takes a pinned requirements file, or the project itself
  with ``--no-deps``);
* the installed JupyterLab environment has exactly the pinned versions,
  ``python3 tasks.py lab --version`` starts the pinned JupyterLab, and ``python3 tasks.py lab``
  serves a chapter's Markdown as a notebook;
* one chapter, converted to ``.ipynb`` by jupytext as JupyterLab opens it, runs to the end on
  that environment's ``python3`` kernel, and the kernel is this environment's (its
  ``sys.prefix``) with this ``gyrolib``;
* every executed chapter is offered for download as ``.ipynb`` by the built HTML.

Under ``python3 tasks.py test`` the lab environment is installed first; elsewhere the tests
that need it skip with the command to run.
"""

from __future__ import annotations

import ast
import json
import os
import re
import subprocess
import sys
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

import pytest

import gyrolib
from tests.conftest import require_built_book

ROOT = Path(__file__).resolve().parents[2]
PIN = re.compile(r"^([A-Za-z0-9][A-Za-z0-9._-]*)==([0-9][A-Za-z0-9.+!-]*)$")


def pins(path: Path) -> dict[str, str]:
    """``name -> version`` of a requirements file; raises on any line that is not ``==``."""
    out = {}
    for n, raw in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        m = PIN.match(line)
        if not m:
            raise ValueError(f"{path.name}:{n}: not an exact pin: {raw!r}")
        out[m.group(1).lower().replace("_", "-")] = m.group(2)
    return out


def unpinned_installs(source: str) -> list[str]:
    """Every ``pip install`` call in a tasks.py source whose arguments are not a pinned
    requirements file (``-r requirements*.txt``), exact pins (``name==version``) or the
    project itself with ``--no-deps``."""
    bad = []
    for node in ast.walk(ast.parse(source)):
        if not isinstance(node, ast.Call):
            continue
        args = [a.value for a in node.args if isinstance(a, ast.Constant)
                and isinstance(a.value, str)]
        if "pip" not in args or "install" not in args:
            continue
        rest = args[args.index("install") + 1:]
        flags = {a for a in rest if a.startswith("-")}
        targets = [a for a in rest if not a.startswith("-")]
        pinned_file = "-r" in flags and all(re.fullmatch(r"requirements[\w-]*\.txt", t)
                                             for t in targets)
        project = targets == ["."] and "--no-deps" in flags
        exact = bool(targets) and "-r" not in flags and all(PIN.match(t) for t in targets)
        if not (pinned_file or project or exact):
            bad.append(ast.unparse(node))
    return bad


def test_lab_requirements_are_exact_pins_compatible_with_the_book():
    lab = pins(ROOT / "requirements-lab.txt")
    book = pins(ROOT / "requirements.txt")
    assert "jupyterlab" in lab
    # MyST Markdown rendered in JupyterLab's notebook view: pinned, for JupyterLab 4
    assert "jupyterlab-myst" in lab and lab["jupyterlab"].startswith("4.")
    clash = {n: (v, book[n]) for n, v in lab.items() if n in book and book[n] != v}
    assert not clash, f"requirements-lab.txt pins other versions than requirements.txt: {clash}"


def test_pin_parser_rejects_a_loose_requirement(tmp_path):
    loose = tmp_path / "r.txt"
    loose.write_text("jupyterlab>=4\n")
    with pytest.raises(ValueError, match="not an exact pin"):
        pins(loose)


def test_tasks_installs_nothing_unpinned():
    source = (ROOT / "tasks.py").read_text(encoding="utf-8")
    assert not unpinned_installs(source)
    # the check sees an unpinned install when there is one
    assert unpinned_installs('run(PY, "-m", "pip", "install", "jupyterlab")')
    assert unpinned_installs('run(PY, "-m", "pip", "install", "-e", ".")')
    assert unpinned_installs('run(PY, "-m", "pip", "install", "--upgrade", "pip")')
    assert not unpinned_installs('run(PY, "-m", "pip", "install", "pip==26.3")')


def _lab_installed() -> None:
    try:
        version("jupyterlab")
    except PackageNotFoundError:
        if os.environ.get("GYROLIB_TEST_COMMAND") == "1":
            pytest.fail("the test command installs requirements-lab.txt before pytest")
        pytest.skip("JupyterLab not installed: run `python3 tasks.py lab --version`")


def test_installed_lab_environment_is_the_pinned_one():
    _lab_installed()
    wrong = {}
    for name, pinned in pins(ROOT / "requirements-lab.txt").items():
        try:
            got = version(name)
        except PackageNotFoundError:
            got = None
        if got != pinned:
            wrong[name] = (got, pinned)
    assert not wrong, f"installed != pinned: {wrong}"
    proc = subprocess.run([sys.executable, str(ROOT / "tasks.py"), "lab", "--version"],
                          cwd=ROOT, capture_output=True, text=True, check=False, timeout=600)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert proc.stdout.strip().splitlines()[-1] == pins(ROOT / "requirements-lab.txt")[
        "jupyterlab"]


def lab_extensions(extra_path: Path | None = None) -> str:
    """What ``jupyter labextension list`` prints (colours removed), computed in this process
    by the command's own code (``ListLabExtensionsApp``'s paths, ``list_extensions``).  The
    npm registry is given, so that no ``node`` is started to read yarn's configuration for
    it (the listing does not use it): the command's interpreter and that ``node`` were about
    3.5 CPU-s.  ``extra_path``: one more folder of prebuilt extensions, searched first."""
    import io
    import logging

    from jupyterlab.commands import YARN_DEFAULT_REGISTRY, AppOptions, list_extensions
    from jupyterlab.labextensions import ListLabExtensionsApp

    app = ListLabExtensionsApp()
    app.initialize([])
    paths = ([str(extra_path)] if extra_path else []) + list(app.labextensions_path)
    out = io.StringIO()
    log = logging.getLogger("gyrolib-test-labextension-list")
    log.setLevel(logging.INFO)
    log.propagate = False
    handler = logging.StreamHandler(out)
    log.addHandler(handler)
    try:
        list_extensions(app_options=AppOptions(app_dir=app.app_dir, logger=log,
                                               core_config=app.core_config,
                                               labextensions_path=paths,
                                               registry=YARN_DEFAULT_REGISTRY))
    finally:
        log.removeHandler(handler)
    return re.sub(r"\x1b\[[0-9;]*m", "", out.getvalue())


def lab_extension_problems(text: str) -> list[str]:
    """What the listing says is wrong: jupyterlab-myst not loaded, or any extension marked
    not compatible (``X``)."""
    problems = [] if re.search(r"jupyterlab-myst v\S+ +enabled +OK", text) else [
        "jupyterlab-myst is not listed as enabled and OK"]
    problems += [line.strip() for line in text.splitlines()
                 if re.search(r" v\S+ .* X\b", line) or "not compatible" in line
                 or "incompatible with the current version" in line]
    return problems


def test_the_pinned_lab_extensions_load():
    """Every lab extension of the pinned environment is one JupyterLab loads: ``jupyter
    labextension list`` marks each "OK", none "not compatible" (jupyterlab-myst 2.7.0 is,
    with JupyterLab 4.6: it would be installed and inert).  Power: a copy of jupyterlab-myst
    that asks for JupyterLab 3 is flagged, and a listing without jupyterlab-myst is."""
    _lab_installed()
    text = lab_extensions()
    assert "jupyterlab-myst" in text and lab_extension_problems(text) == [], text
    assert lab_extension_problems(text.replace("jupyterlab-myst", "other-ext"))


def test_the_lab_extension_check_flags_an_incompatible_extension(tmp_path):
    _lab_installed()
    from jupyterlab.labextensions import ListLabExtensionsApp

    app = ListLabExtensionsApp()
    app.initialize([])
    found = [Path(p) / "jupyterlab-myst" / "package.json" for p in app.labextensions_path]
    package = json.loads(next(p for p in found if p.is_file()).read_text())
    package["name"] = "gyrolib-test-old-ext"
    package["dependencies"] = {"@jupyterlab/application": "^3.0.0"}
    (tmp_path / "gyrolib-test-old-ext").mkdir()
    (tmp_path / "gyrolib-test-old-ext" / "package.json").write_text(json.dumps(package))
    text = lab_extensions(tmp_path)
    assert any("gyrolib-test-old-ext" in p for p in lab_extension_problems(text)), text


@pytest.mark.slow
def test_a_chapter_runs_as_a_notebook_on_the_environment_kernel(tmp_path):
    _lab_installed()
    import jupytext
    from nbclient import NotebookClient
    from nbformat.v4 import new_code_cell

    nb = jupytext.read(ROOT / "chapters" / "status.md")
    assert nb.metadata["kernelspec"]["name"] == "python3"
    nb.cells.append(new_code_cell("import sys, gyrolib\nprint(sys.prefix)\n"
                                  "print(gyrolib.__version__)"))
    NotebookClient(nb, timeout=600, kernel_name="python3",
                   resources={"metadata": {"path": str(ROOT / "chapters")}}).execute()
    errors = [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", [])
              if o.get("output_type") == "error"]
    assert not errors, errors
    last = "".join(o.get("text", "") for o in nb.cells[-1].outputs).split()
    assert last == [sys.prefix, gyrolib.__version__], last


@pytest.mark.book
def test_every_executed_chapter_offers_its_notebook():
    html = require_built_book()
    problems = []
    for md in sorted((ROOT / "chapters").glob("*.md")):
        if "{code-cell}" not in md.read_text(encoding="utf-8"):
            continue
        page = html / "chapters" / f"{md.stem}.html"
        if not page.is_file():  # not in the table of contents
            continue
        href = f"../_sources/chapters/{md.stem}.ipynb"
        if f'href="{href}"' not in page.read_text(encoding="utf-8"):
            problems.append(f"{page.name}: no download link {href}")
            continue
        nb = json.loads((html / "_sources" / "chapters" / f"{md.stem}.ipynb").read_text())
        counts = [c.get("execution_count") for c in nb["cells"] if c["cell_type"] == "code"]
        if not counts or not all(isinstance(n, int) for n in counts):
            problems.append(f"{md.stem}.ipynb: execution counts {counts}: not executed")
    assert not problems, problems


@pytest.mark.full
def test_tasks_lab_serves_the_chapters_as_notebooks(tmp_path):
    """Full tier (a JupyterLab server started and stopped; the everyday tier checks the
    installed environment and its extensions, above): ``python3 tasks.py lab`` starts a
    server on chapters/ whose contents API returns a chapter's MyST Markdown as a notebook
    (jupytext), with the code cells of the file."""
    import signal
    import socket
    import time
    import urllib.request

    _lab_installed()
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    token = "gyrolib-test"
    log = (tmp_path / "lab.log").open("wb")  # a file, not a pipe: the server logs a lot
    proc = subprocess.Popen(
        [sys.executable, str(ROOT / "tasks.py"), "lab", "--no-browser", f"--port={port}",
         "--ServerApp.ip=127.0.0.1", f"--ServerApp.token={token}"],
        cwd=ROOT, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
    url = f"http://127.0.0.1:{port}/api/contents/status.md?type=notebook&token={token}"
    try:
        deadline, model = time.monotonic() + 120, None
        while time.monotonic() < deadline and proc.poll() is None:
            try:
                with urllib.request.urlopen(url, timeout=5) as r:
                    model = json.load(r)
                break
            except OSError:
                time.sleep(0.5)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGTERM)
        proc.wait(timeout=30)
        log.close()
    assert model is not None, (f"no answer from JupyterLab (exit {proc.returncode}): "
                               f"{(tmp_path / 'lab.log').read_text()[-2000:]}")
    assert model["type"] == "notebook"
    source = (ROOT / "chapters" / "status.md").read_text(encoding="utf-8")
    code = [c["source"] for c in model["content"]["cells"] if c["cell_type"] == "code"]
    assert code and all(c.strip() in source for c in code), code


# A stand-in for JupyterLab: on SIGINT it says goodbye after a short clean-up and exits 0.
_SERVER = """
import signal, sys, time
def stop(*_):
    time.sleep(0.5)          # longer than subprocess.run's 0.25 s grace before it kills
    print("server:", "shut down cleanly", flush=True)
    sys.exit(0)
signal.signal(signal.SIGINT, stop)
print("server:", "ready", flush=True)   # not the text of this source, which is echoed
time.sleep(60)
sys.exit(3)
"""


def _ctrl_c(runner: str, tmp_path: Path) -> subprocess.CompletedProcess:
    """Run the stand-in server through ``tasks.<runner>`` in its own process group, then
    send SIGINT to the group, as Ctrl-C at a terminal does."""
    import signal
    import time

    script = (f"import sys; sys.path.insert(0, {str(ROOT)!r}); import tasks\n"
              f"status = tasks.{runner}(sys.executable, '-c', {_SERVER!r})\n"
              "print('status', status)\n")
    out = (tmp_path / f"{runner}.out").open("w+")
    proc = subprocess.Popen([sys.executable, "-c", script], stdout=out, stderr=subprocess.STDOUT,
                            text=True, start_new_session=True)
    deadline = time.monotonic() + 30
    while "server: ready" not in (tmp_path / f"{runner}.out").read_text():
        assert time.monotonic() < deadline and proc.poll() is None, "stand-in did not start"
        time.sleep(0.05)
    os.killpg(proc.pid, signal.SIGINT)
    proc.wait(timeout=30)
    out.close()
    return subprocess.CompletedProcess(proc.args, proc.returncode,
                                       (tmp_path / f"{runner}.out").read_text(), "")


def test_ctrl_c_in_lab_ends_cleanly(tmp_path):
    """``tasks.py lab`` runs JupyterLab through ``run_interactive``: Ctrl-C lets the server
    finish its own shutdown and the command exits with its status, no traceback.  The same
    Ctrl-C through ``tasks.run`` (subprocess.run, as ``lab`` did) prints a
    KeyboardInterrupt traceback and cuts the server's shutdown short: the check has power."""
    ok = _ctrl_c("run_interactive", tmp_path)
    assert ok.returncode == 0, ok.stdout
    assert "Traceback" not in ok.stdout and "KeyboardInterrupt" not in ok.stdout
    assert "server: shut down cleanly" in ok.stdout and "status 0" in ok.stdout
    bad = _ctrl_c("run", tmp_path)
    assert "KeyboardInterrupt" in bad.stdout and "Traceback" in bad.stdout
    assert "server: shut down cleanly" not in bad.stdout
    # tasks.lab passes the server's status on, as the shell reports a signal's exit
    source = (ROOT / "tasks.py").read_text(encoding="utf-8")
    assert "status = run_interactive(BIN / \"jupyter\", \"lab\"" in source
