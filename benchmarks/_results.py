"""The results file every benchmark writes: ``benchmarks/results/<name>.json``.

Format (read by the book's Performance page, which renders every file it finds)::

    {"benchmark": name, "date": ISO-8601 UTC,
     "machine": {"cpu", "cpu_class", "cpu_family", "cpu_model", "host_cpu", "cores",
                 "python", "numpy"},
     "load": 1-min load average at the start,
     "results": [{"case", "ours_s", "peer", "peer_s", "ratio", "target_s", "note"}]}

``cpu_class`` is ``"AVX-512"`` (``avx512f`` among ``/proc/cpuinfo``'s flags), ``"AVX2"``,
``"AVX"`` or ``"no AVX"``: "AMD EPYC" names machines whose figures differ by 2×, the class
tells them apart (issue 36).  ``cpu_family`` and ``cpu_model`` are ``/proc/cpuinfo``'s
numbers, ``host_cpu`` is ``llvmlite.binding.get_host_cpu_name()`` (what numba compiles for,
e.g. ``znver3``).  Files written before these fields carry ``"class unknown"`` in them.

The whole-command benchmarks (``bench_test_command.py``, ``bench_book_build.py``) also keep,
under ``"other_classes"``, the latest run of each other CPU class (each with its ``date``,
``machine``, ``load``, ``results``): a run on one class does not erase the other's.

``ratio`` is ``peer_s / ours_s`` (how many times faster than the peer), or, for a case
without a peer, ``ours_s / target_s`` (the share of the time budget used); ``note`` says
which.  Fields that do not apply are ``null``.
"""

from __future__ import annotations

import datetime as dt
import json
import os
import platform
import resource
import subprocess
from functools import cache
from pathlib import Path

RESULTS = Path(__file__).resolve().parent / "results"
FIELDS = ("case", "ours_s", "peer", "peer_s", "ratio", "target_s", "note")


#: What a results file written before the CPU class was recorded says in its place.
UNKNOWN = "class unknown"


def children_cpu() -> float:
    """CPU seconds (user + system) of every child process waited for so far, and of theirs
    (``RUSAGE_CHILDREN``: a process still running, or never reaped, is not in it)."""
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def own_cpu() -> float:
    """CPU seconds (user + system) of this process."""
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def cpu_class(flags: set[str]) -> str:
    """The CPU class from the flags of ``/proc/cpuinfo``.

    >>> cpu_class({"avx", "avx2", "avx512f"}), cpu_class({"avx", "avx2"}), cpu_class(set())
    ('AVX-512', 'AVX2', 'no AVX')
    """
    for flag, name in (("avx512f", "AVX-512"), ("avx2", "AVX2"), ("avx", "AVX")):
        if flag in flags:
            return name
    return "no AVX"


def host_cpu_name() -> str:
    """What numba compiles for on this machine (llvmlite's name of the host CPU)."""
    try:
        from llvmlite import binding
        return binding.get_host_cpu_name()
    except (ImportError, OSError, RuntimeError):   # no llvmlite: say so, do not fail
        return "?"


def _number(text: str | None) -> int | str | None:
    return int(text) if text is not None and text.isdigit() else text


@cache
def machine() -> dict[str, object]:
    """The machine, computed once per process: CPU name, class, family, model and llvmlite's
    host CPU name, cores, Python's and NumPy's versions."""
    import numpy

    cpu = platform.processor() or "?"
    fields: dict[str, str] = {}
    cpuinfo = Path("/proc/cpuinfo")
    if cpuinfo.is_file():
        for line in cpuinfo.read_text().splitlines():
            key, _, value = line.partition(":")
            key = key.strip()
            if not key and fields:
                break                                   # the first processor is enough
            fields.setdefault(key, value.strip())
    flags = set(fields.get("flags", "").split())
    return {"cpu": fields.get("model name", cpu),
            "cpu_class": cpu_class(flags) if flags else UNKNOWN,
            "cpu_family": _number(fields.get("cpu family")),
            "cpu_model": _number(fields.get("model")),
            "host_cpu": host_cpu_name(), "cores": os.cpu_count(),
            "python": platform.python_version(), "numpy": numpy.__version__}


def machine_label(m: dict) -> str:
    """``AMD EPYC, AVX2 (family 25, model 1, znver3)``: the CPU as the results quote it."""
    cls = m.get("cpu_class", UNKNOWN)
    if cls == UNKNOWN:
        return f"{m.get('cpu', '?')}, {UNKNOWN}"
    return (f"{m.get('cpu', '?')}, {cls} (family {m.get('cpu_family')}, model "
            f"{m.get('cpu_model')}, {m.get('host_cpu')})")


def previous_tree(dest: Path, commit: str) -> Path | None:
    """``gyrolib/`` at ``commit`` exported into ``dest`` (run the peer with ``PYTHONPATH``
    and ``cwd`` there, so that its modules, not this tree's, are imported), or None when git
    or the commit is not there."""
    root = Path(__file__).resolve().parents[1]
    try:
        archive = subprocess.run(["git", "-C", str(root), "archive", commit, "gyrolib"],
                                 capture_output=True, check=True).stdout
        subprocess.run(["tar", "-x", "-C", str(dest)], input=archive, check=True)
    except (OSError, subprocess.CalledProcessError):
        return None
    return dest


def load() -> float | None:
    try:
        return round(os.getloadavg()[0], 2)
    except (AttributeError, OSError):
        return None


class Recorder:
    """Collects the cases of one benchmark run; :meth:`write` stores the results file."""

    def __init__(self, name: str):
        self.doc = {"benchmark": name,
                    "date": dt.datetime.now(dt.UTC).replace(microsecond=0).isoformat(),
                    "machine": dict(machine()), "load": load(), "results": []}

    def case(self, case: str, ours_s: float, *, peer: str | None = None,
             peer_s: float | None = None, target_s: float | None = None,
             note: str = "") -> dict:
        if peer_s is not None:
            ratio = peer_s / ours_s
        elif target_s is not None:
            ratio = ours_s / target_s
        else:
            ratio = None
        row = {"case": case, "ours_s": round(ours_s, 4), "peer": peer,
               "peer_s": None if peer_s is None else round(peer_s, 4),
               "ratio": None if ratio is None else round(ratio, 3),
               "target_s": target_s, "note": note}
        self.doc["results"].append(row)
        print(json.dumps(row, ensure_ascii=False), flush=True)
        return row

    def write(self, keep_other_classes: bool = False) -> Path:
        """Write the results file.  ``keep_other_classes``: the file also keeps, under
        ``other_classes``, the latest run of every other CPU class that the file it replaces
        held (its own run and its ``other_classes``), so that the README can quote the latest
        result of each class (``readme_times.py``)."""
        RESULTS.mkdir(parents=True, exist_ok=True)
        path = RESULTS / f"{self.doc['benchmark']}.json"
        if keep_other_classes:
            self.doc["other_classes"] = other_classes(path, self.doc["machine"]["cpu_class"])
        path.write_text(json.dumps(self.doc, indent=2, ensure_ascii=False) + "\n",
                        encoding="utf-8")
        print(f"wrote {path}", flush=True)
        return path


def runs_by_class(doc: dict) -> dict[str, dict]:
    """A results file's runs, CPU class -> run (``date``, ``machine``, ``load``,
    ``results``): its own, and those it keeps of other classes (``other_classes``)."""
    runs = {}
    for run in [doc, *doc.get("other_classes", [])]:
        cls = run.get("machine", {}).get("cpu_class", UNKNOWN)
        if cls not in runs or run["date"] > runs[cls]["date"]:
            runs[cls] = {k: run[k] for k in ("date", "machine", "load", "results")}
    return runs


def other_classes(path: Path, cls: str) -> list[dict]:
    """The runs of classes other than ``cls`` kept in the results file ``path`` (none when
    it is missing or unreadable), oldest class first."""
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return []
    runs = runs_by_class(doc)
    return [runs[c] for c in sorted(runs) if c != cls]
