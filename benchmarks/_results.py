"""The results file every benchmark writes: ``benchmarks/results/<name>.json``.

Format (read by the book's Performance page, which renders every file it finds)::

    {"benchmark": name, "date": ISO-8601 UTC, "machine": {"cpu", "cores", "python", "numpy"},
     "load": 1-min load average at the start,
     "results": [{"case", "ours_s", "peer", "peer_s", "ratio", "target_s", "note"}]}

``ratio`` is ``peer_s / ours_s`` (how many times faster than the peer), or, for a case
without a peer, ``ours_s / target_s`` (the share of the time budget used); ``note`` says
which.  Fields that do not apply are ``null``.
"""

from __future__ import annotations

import datetime as dt
import json
import os
import platform
import subprocess
from pathlib import Path

RESULTS = Path(__file__).resolve().parent / "results"
FIELDS = ("case", "ours_s", "peer", "peer_s", "ratio", "target_s", "note")


def machine() -> dict[str, object]:
    import numpy

    cpu = platform.processor() or "?"
    cpuinfo = Path("/proc/cpuinfo")
    if cpuinfo.is_file():
        cpu = next((line.split(":", 1)[1].strip() for line in cpuinfo.read_text().splitlines()
                    if line.startswith("model name")), cpu)
    return {"cpu": cpu, "cores": os.cpu_count(), "python": platform.python_version(),
            "numpy": numpy.__version__}


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
                    "machine": machine(), "load": load(), "results": []}

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

    def write(self) -> Path:
        RESULTS.mkdir(parents=True, exist_ok=True)
        path = RESULTS / f"{self.doc['benchmark']}.json"
        path.write_text(json.dumps(self.doc, indent=2, ensure_ascii=False) + "\n",
                        encoding="utf-8")
        print(f"wrote {path}", flush=True)
        return path
