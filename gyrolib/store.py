"""One store for the heavy studies: a result computed once, kept as package data, and held to
the code by its key and its fingerprint.

A *study* (:class:`Study`) is a result that costs minutes to compute (the claim maps, the
Sobol' studies): it is computed offline (``python3 tasks.py refresh NAME``), written as a JSON
file, and read by the chapters, the ledger and the tests.  Its file carries a *header*
(:class:`Header`, the ``"store"`` entry of the file):

* the **key** (:func:`model_key`): a hash per part of what the study reads — the rows of the
  table of inputs, the defaults of every parameter dataclass and the named constants of every
  module the study names (an Earth rate, a latitude, a printed level), so that a change of
  any of them, inside the table or not, makes the study stale;
* the **tolerance** to which its fingerprint points must agree (relative ``rtol``, absolute
  ``atol``);
* the gyrolib **version**, the **CPU class** (:func:`cpu_class`) and the **date** it was
  computed, and its **cost** in CPU-s.

:func:`check` compares the key and recomputes the study's fingerprint points (each study says
which: :attr:`Study.check`); a disagreement raises :class:`StaleStudy`, whose one-line
message names the study and the command that refreshes it.  Nothing here recomputes a study
silently: :func:`refresh` is the only writer.

A check that passed is remembered on disk (the *check memo*, :func:`memo_folder`: the user's
cache folder, or ``$GYROLIB_CHECK_MEMO``), under a digest of everything the check depends on:
the study's file, every file of the gyrolib package (its sources and data), the key now, the
versions of Python and of the numerical packages (NumPy, SciPy, numba, SALib,
python-control), and the CPU class.  A later check with the same
digest reads the number of points that agreed instead of recomputing them; a change of any
source file, a constant or a function body included, or another CPU class, misses the memo,
and the points are recomputed.  The key is compared every time, memo or not.  The memo trusts
that the code in memory is the code on disk: a test that replaces a function in memory
checks with ``memo=False``.

This module imports no other part of gyrolib: the studies are registered by the modules that
compute them (:func:`register`), which pass their own modules to :func:`model_key`.

Examples
--------
>>> import math
>>> k = model_key(constants={"EARTH_RATE": 7.292115e-5})
>>> k == model_key(constants={"EARTH_RATE": 7.292115e-5})
True
>>> k == model_key(constants={"EARTH_RATE": 1.1 * 7.292115e-5})
False
>>> try:
...     compare("demo", "the margin at the reference", 1.0, 1.1, rtol=1e-6, atol=0.0)
... except StaleStudy as exc:
...     print(exc.study, "|", exc.refresh)
demo | python3 tasks.py refresh demo
"""

from __future__ import annotations

import contextlib
import dataclasses
import datetime as _dt
import hashlib
import importlib.metadata
import json
import math
import os
import platform
import resource
import time
import types
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Final

from gyrolib import __version__

__all__ = ["HEADER_KEY", "MEMO_ENV", "REFRESH", "Header", "StaleStudy", "Study", "check",
           "check_key", "compare", "cpu_class", "dumps", "header_of", "memo_digest",
           "memo_folder", "model_key", "refresh", "register", "registered", "rekey",
           "same_sign", "state", "study", "write"]

#: The entry of a study's file that holds its header.
HEADER_KEY: Final[str] = "store"

#: The command that refreshes a study (``{name}``: the study's name).
REFRESH: Final[str] = "python3 tasks.py refresh {name}"


class StaleStudy(ValueError):
    """A stored study that the code no longer reproduces: ``study`` (its name), ``reason``
    (what disagreed, in words) and ``refresh`` (the command that recomputes it).  Its message
    is one line."""

    def __init__(self, study: str, reason: str) -> None:
        self.study = study
        self.reason = " ".join(str(reason).split())
        self.refresh = REFRESH.format(name=study)
        super().__init__(f"the stored study {study} is stale: {self.reason}; refresh it: "
                         f"{self.refresh}")


# the key ---------------------------------------------------------------------------------------
def _plain(value: Any) -> bool:
    """Whether ``value`` has a repr that says what it computes with (no addresses)."""
    if isinstance(value, (bool, int, float, str, type(None))):
        return True
    if isinstance(value, (tuple, list, set, frozenset)):
        return all(_plain(x) for x in value)
    if isinstance(value, dict):
        return all(_plain(k) and _plain(x) for k, x in value.items())
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return " at 0x" not in repr(value)
    return False


def _canon(value: Any) -> str:
    """A repr that does not depend on hash order (sets sorted, dicts by key)."""
    if isinstance(value, (set, frozenset)):
        return "{" + ", ".join(sorted(_canon(x) for x in value)) + "}"
    if isinstance(value, dict):
        return "{" + ", ".join(sorted(f"{_canon(k)}: {_canon(x)}" for k, x in value.items())) \
            + "}"
    if isinstance(value, (tuple, list)):
        return "(" + ", ".join(_canon(x) for x in value) + ")"
    return repr(value)


def _module_part(module: types.ModuleType) -> str:
    """The repr of a module's named constants (upper-case names with plain values) and of
    the default instance of each dataclass it defines (those constructible without
    arguments), in name order.

    A module names in ``__key_ignore__`` the upper-case names that are not model inputs (a
    search's settings, a table derived from rows the key holds already), with the reason
    beside it: they leave the key unchanged."""
    ignore = frozenset(getattr(module, "__key_ignore__", ()))
    parts = []
    for name in sorted(vars(module)):
        if name in ignore:
            continue
        obj = getattr(module, name)
        if isinstance(obj, type) and dataclasses.is_dataclass(obj) \
                and obj.__module__ == module.__name__:
            try:
                inst = obj()
            except (TypeError, ValueError):   # no defaults: nothing to key
                continue
            parts.append(f"{name}()={inst!r}")
        elif name.isupper() and not name.startswith("__") and _plain(obj):
            parts.append(f"{name}={_canon(obj)}")
    return "\n".join(parts)


def _hash(text: str) -> str:
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def model_key(modules: Iterable[types.ModuleType] = (), *,
              objects: Mapping[str, Any] | None = None,
              constants: Mapping[str, Any] | None = None,
              extra: Mapping[str, str] | None = None) -> dict[str, str]:
    """The key of a study: part name → a 16-hex-digit hash.

    Parameters
    ----------
    modules : iterable of modules
        Each gives a part (its name): the reprs of its upper-case constants with plain values
        and of the default instance of every dataclass it defines.
    objects : mapping, optional
        Name → an instance the study starts from (e.g. the owners of the table of inputs at
        their defaults); a part ``"objects"``.
    constants : mapping, optional
        Further named values; a part ``"constants"``.
    extra : mapping, optional
        Parts already hashed (e.g. the table's own fingerprint), kept as given.

    Returns
    -------
    dict
        A change of any default or constant changes its part (:func:`check_key` names it).
    """
    key: dict[str, str] = {}
    for m in modules:
        key[m.__name__] = _hash(_module_part(m))
    if objects is not None:
        key["objects"] = _hash("\n".join(f"{k}={objects[k]!r}" for k in sorted(objects)))
    if constants is not None:
        key["constants"] = _hash("\n".join(f"{k}={_canon(constants[k])}"
                                           for k in sorted(constants)))
    key.update(dict(extra or {}))
    return key


def check_key(study: str, stored: Mapping[str, str], now: Mapping[str, str]) -> None:
    """Raise :class:`StaleStudy` naming the parts of the key that differ."""
    moved = sorted(k for k in set(stored) | set(now) if stored.get(k) != now.get(k))
    if moved:
        raise StaleStudy(study, "its key differs from the code's in "
                         + ", ".join(moved) + " (a default, a constant or a row of the table "
                         "it reads changed)")


# the fingerprint -------------------------------------------------------------------------------
def compare(study: str, label: str, was: float, now: float, *, rtol: float,
            atol: float) -> None:
    """Raise :class:`StaleStudy` when ``now`` differs from ``was`` by more than
    ``atol + rtol · max(|was|, |now|)`` (two ``nan`` agree)."""
    was, now = float(was), float(now)
    if math.isnan(was) and math.isnan(now):
        return
    if not abs(now - was) <= atol + rtol * max(abs(now), abs(was)):
        raise StaleStudy(study, f"{label} was {was!r}, the code now gives {now!r} "
                         f"(tolerance rtol {rtol:g}, atol {atol:g})")


def same_sign(study: str, label: str, expect_positive: bool, now: float) -> None:
    """Raise :class:`StaleStudy` when ``now > 0`` is not ``expect_positive`` (``nan`` counts
    as not positive)."""
    if bool(now > 0.0) != expect_positive:
        raise StaleStudy(study, f"{label} should be {'> 0' if expect_positive else '<= 0'}, "
                         f"the code now gives {float(now)!r}")


# the header ------------------------------------------------------------------------------------
def cpu_class() -> str:
    """The CPU class of this machine from ``/proc/cpuinfo``'s flags: ``"AVX-512"``,
    ``"AVX2"``, ``"AVX"``, ``"no AVX"`` or ``"class unknown"`` (no ``/proc/cpuinfo``)."""
    path = Path("/proc/cpuinfo")
    if not path.is_file():
        return "class unknown"
    flags: set[str] = set()
    for line in path.read_text(errors="replace").splitlines():
        if line.startswith("flags"):
            flags = set(line.partition(":")[2].split())
            break
    for flag, name in (("avx512f", "AVX-512"), ("avx2", "AVX2"), ("avx", "AVX")):
        if flag in flags:
            return name
    return "no AVX" if flags else "class unknown"


@dataclass(frozen=True)
class Header:
    """What a stored study records besides its numbers (the ``"store"`` entry of its file):
    ``study``, ``key`` (:func:`model_key`), ``rtol`` and ``atol`` (its fingerprint's declared
    tolerance), ``version`` (gyrolib's), ``cpu_class``, ``date`` (ISO 8601, UTC),
    ``cost_cpu_s`` (CPU seconds of the computation: this process and the processes it waited
    for; a Dask cluster's workers are not counted, ``None`` when not measured) and ``note``
    (how it was computed, in words)."""

    study: str
    key: dict[str, str]
    rtol: float
    atol: float
    version: str
    cpu_class: str
    date: str
    cost_cpu_s: float | None = None
    note: str = ""

    def as_dict(self) -> dict[str, Any]:
        return dataclasses.asdict(self)

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Header:
        names = {f.name for f in dataclasses.fields(cls)}
        return cls(**{k: v for k, v in d.items() if k in names})


def header_of(name: str, data: Mapping[str, Any]) -> Header:
    """The header of a study's file contents; :class:`StaleStudy` when it has none."""
    h = data.get(HEADER_KEY)
    if not isinstance(h, Mapping):
        raise StaleStudy(name, "its file has no store header (key, tolerance, version, CPU "
                         "class, date)")
    return Header.from_dict(h)


# the studies -----------------------------------------------------------------------------------
@dataclass(frozen=True)
class Study:
    """A heavy study kept in the store.

    ``name`` (as :func:`refresh` and the command line name it), ``file`` (its JSON file),
    ``key`` (a function returning its :func:`model_key` now), ``check`` (a function of the
    file's contents that recomputes the fingerprint points, raises :class:`StaleStudy` on a
    disagreement and returns how many points it checked; it reads the tolerance from the
    header), ``compute`` (a function ``(executor, progress, **options)`` returning the file's
    new contents without the header; ``progress`` is ``None`` or a tqdm-like object with
    ``total`` and ``update``), ``rtol`` and ``atol`` (the declared tolerance written into a
    refreshed file) and ``what`` (one line)."""

    name: str
    file: Path
    key: Callable[[], dict[str, str]]
    check: Callable[[Mapping[str, Any]], int]
    compute: Callable[..., dict[str, Any]]
    rtol: float = 1e-6
    atol: float = 1e-9
    what: str = ""
    rows: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name:
            raise ValueError(f"name must be a non-empty str; got {self.name!r}")
        if not isinstance(self.file, Path):
            raise TypeError(f"file must be a pathlib.Path; got {type(self.file).__name__}")
        for f in ("key", "check", "compute"):
            if not callable(getattr(self, f)):
                raise TypeError(f"{f} must be callable; got {getattr(self, f)!r}")
        for f in ("rtol", "atol"):
            x = getattr(self, f)
            if not isinstance(x, (int, float)) or not 0.0 <= x < 1.0:
                raise ValueError(f"{f} must be a number in [0, 1); got {x!r}")


_REGISTRY: dict[str, Study] = {}


def register(s: Study) -> Study:
    """Register the study ``s`` under its name (the module that computes it calls this)."""
    if not isinstance(s, Study):
        raise TypeError(f"study must be a Study; got {type(s).__name__}")
    _REGISTRY[s.name] = s
    return s


def registered() -> tuple[str, ...]:
    """The names of the registered studies."""
    return tuple(_REGISTRY)


def study(name: str) -> Study:
    """The registered study ``name``; ``ValueError`` naming the known ones otherwise."""
    try:
        return _REGISTRY[name]
    except KeyError:
        raise ValueError(f"study must be one of {registered()}; got {name!r}") from None


def _raw(s: Study, path: Path | None) -> bytes:
    p = s.file if path is None else Path(path)
    if not p.is_file():
        raise StaleStudy(s.name, f"its file {p} does not exist")
    return p.read_bytes()


# the check memo --------------------------------------------------------------------------------
#: Environment variable naming the check memo's folder; ``off`` (or ``0``, or empty) turns the
#: memo off.  Unset: ``$XDG_CACHE_HOME/gyrolib/checks`` (``~/.cache/gyrolib/checks``).
MEMO_ENV: Final[str] = "GYROLIB_CHECK_MEMO"

#: The version of the memo's digest (a new one when what it covers changes).
_MEMO_FORMAT: Final[int] = 1

#: The package whose files the memo's digest covers (this module's folder).
_PACKAGE: Final[Path] = Path(__file__).resolve().parent


def memo_folder() -> Path | None:
    """The check memo's folder (:data:`MEMO_ENV`), or ``None`` when it is turned off."""
    value = os.environ.get(MEMO_ENV)
    if value is not None:
        return None if value.strip().lower() in ("", "0", "off", "no") else Path(value)
    cache = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(cache) / "gyrolib" / "checks"


def _bytecode(path: Path) -> bool:
    return "__pycache__" in path.parts or path.suffix in (".pyc", ".pyo")


def _sources_digest(package: Path | None = None) -> str:
    """SHA-256 over every file of ``package`` (default: gyrolib's; relative path and bytes,
    in path order), Python's bytecode caches left out."""
    package = _PACKAGE if package is None else package
    h = hashlib.sha256()
    for f in sorted(p for p in package.rglob("*") if p.is_file()):
        rel = f.relative_to(package)
        if _bytecode(rel) or f.suffix == ".tmp":
            continue
        h.update(rel.as_posix().encode() + b"\0" + f.read_bytes() + b"\0")
    return h.hexdigest()


def _version(dist: str) -> str:
    try:
        return importlib.metadata.version(dist)
    except importlib.metadata.PackageNotFoundError:
        return "absent"


def memo_digest(name: str, file_bytes: bytes, key: Mapping[str, str]) -> dict[str, str]:
    """What a check of the study ``name`` depends on, part by part: the study's file
    (``file_bytes``), every file of the gyrolib package, the key now (``key``), the
    versions of Python, NumPy, SciPy, numba, SALib and python-control, the machine and the
    CPU class (:func:`cpu_class`).  A memo is read only under the same parts."""
    return {"format": str(_MEMO_FORMAT), "study": name,
            "file": hashlib.sha256(file_bytes).hexdigest(),
            "sources": _sources_digest(),
            "key": _hash(json.dumps(dict(key), sort_keys=True)),
            "python": platform.python_version(), "numpy": _version("numpy"),
            "scipy": _version("scipy"), "numba": _version("numba"),
            "SALib": _version("SALib"), "control": _version("control"),
            "machine": platform.machine(), "cpu_class": cpu_class()}


def _memo_path(folder: Path, parts: Mapping[str, str]) -> Path:
    h = hashlib.sha256(json.dumps(dict(parts), sort_keys=True).encode()).hexdigest()[:32]
    return folder / f"{parts['study']}-{h}.json"


def _memo_read(path: Path, parts: Mapping[str, str]) -> int | None:
    try:
        d = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    if not isinstance(d, dict) or d.get("parts") != dict(parts) \
            or not isinstance(d.get("points"), int):
        return None
    return int(d["points"])


def _memo_write(path: Path, parts: Mapping[str, str], points: int, cpu_s: float) -> None:
    d = {"parts": dict(parts), "points": int(points), "check_cpu_s": round(cpu_s, 2),
         "date": _dt.datetime.now(_dt.UTC).replace(microsecond=0).isoformat()}
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_suffix(f".{os.getpid()}.tmp")
        tmp.write_text(json.dumps(d, sort_keys=True), encoding="utf-8")
        tmp.replace(path)   # atomic: a concurrent reader sees the whole file or none
    except OSError:         # a read-only cache: the check stands, unremembered
        return


@contextlib.contextmanager
def _exclusive(lock: Path):
    """An exclusive lock on ``lock`` between processes (``fcntl.flock``; without ``fcntl``
    or a writable folder, none: two processes may then both check)."""
    try:
        import fcntl
        lock.parent.mkdir(parents=True, exist_ok=True)
        fh = open(lock, "a")
    except (ImportError, OSError):
        yield
        return
    with fh:
        fcntl.flock(fh, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(fh, fcntl.LOCK_UN)


# checking a study ------------------------------------------------------------------------------
def _points(s: Study, data: Mapping[str, Any], raw: bytes, key: Mapping[str, str],
            memo: bool) -> tuple[int, bool]:
    """The study's fingerprint points recomputed, or read from the memo: (how many agreed,
    whether read from the memo).  Raises :class:`StaleStudy`."""
    folder = memo_folder() if memo else None
    if folder is None:
        return int(s.check(data)), False
    parts = memo_digest(s.name, raw, key)
    path = _memo_path(folder, parts)
    n = _memo_read(path, parts)
    if n is not None:
        return n, True
    # processes checking at the same time wait for the first one's check, not redo it
    with _exclusive(folder / f"{s.name}.lock"):
        n = _memo_read(path, parts)
        if n is not None:
            return n, True
        t0 = time.process_time()
        n = int(s.check(data))
        _memo_write(path, parts, n, time.process_time() - t0)
    return n, False


def check(name: str, path: Path | None = None, *, memo: bool = True) -> int:
    """Check the stored study ``name`` (its file, or ``path``): its key against the code's,
    then its fingerprint points recomputed (or, with ``memo``, read from the check memo
    when nothing they depend on changed: :func:`memo_digest`).  Returns how many points
    agreed; raises :class:`StaleStudy` (one line: the study, what disagreed, the refresh
    command)."""
    s = study(name)
    raw = _raw(s, path)
    data = json.loads(raw)
    h = header_of(name, data)
    now = s.key()
    check_key(name, h.key, now)
    return _points(s, data, raw, now, memo)[0]


def state(name: str, path: Path | None = None, *, memo: bool = True) -> dict[str, Any]:
    """The study's state for a listing: ``name``; ``state`` (``"fresh"`` when its key and
    its points agree with the code, else ``"stale"``) and ``reason`` (why stale, else
    ``""``); ``key`` (``"same"`` or ``"differs"``) and ``key_reason``; ``points_state``
    (``"agree"`` or ``"disagree"``: the points are recomputed even when the key differs,
    so that a stale key does not hide whether they still agree), ``points`` (how many
    agreed), ``points_reason`` and ``from_memo`` (read from the check memo); ``check_cpu_s``
    (the check's CPU seconds) and the header's ``date``, ``cpu_class``, ``version`` and
    ``cost_cpu_s``."""
    s = study(name)
    t0 = time.process_time()
    out: dict[str, Any] = {"name": name, "state": "fresh", "reason": "", "key": "same",
                           "key_reason": "", "points_state": "agree", "points": 0,
                           "points_reason": "", "from_memo": False}
    try:
        raw = _raw(s, path)
        data = json.loads(raw)
        h = header_of(name, data)
    except StaleStudy as exc:
        out.update(state="stale", reason=exc.reason, key="differs", key_reason=exc.reason,
                   points_state="disagree", points_reason=exc.reason, date=None,
                   cpu_class=None, version=None, cost_cpu_s=None,
                   check_cpu_s=time.process_time() - t0)
        return out
    now = s.key()
    try:
        check_key(name, h.key, now)
    except StaleStudy as exc:
        out.update(key="differs", key_reason=exc.reason)
    try:
        # under a differing key no memo can match (the key is part of its digest)
        out["points"], out["from_memo"] = _points(s, data, raw, now, memo)
    except StaleStudy as exc:
        out.update(points_state="disagree", points_reason=exc.reason)
    reasons = [r for r in (out["key_reason"], out["points_reason"]) if r]
    if reasons:
        out.update(state="stale", reason="; ".join(reasons))
    out["check_cpu_s"] = time.process_time() - t0
    out.update(date=h.date, cpu_class=h.cpu_class, version=h.version,
               cost_cpu_s=h.cost_cpu_s)
    return out


def _cpu() -> float:
    r, c = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime + c.ru_utime + c.ru_stime


def dumps(data: Mapping[str, Any], rows: str = "") -> str:
    """A study's file as text: indented JSON with sorted keys, or, with ``rows``, in the
    order given and the list under ``rows`` last, one item a line (a sample's values).

    Examples
    --------
    >>> print(dumps({"n": 2, "values": [[1, 2], [3, 4]]}, rows="values"), end="")
    {
     "n": 2,
     "values": [
    [1, 2],
    [3, 4]
     ]
    }
    """
    if not rows:
        return json.dumps(data, indent=1, sort_keys=True) + "\n"
    body = {k: v for k, v in data.items() if k != rows}
    text = json.dumps(body, indent=1, ensure_ascii=False)
    lines = ",\n".join(json.dumps(row) for row in data.get(rows, []))
    return text[:-2] + f',\n "{rows}": [\n' + lines + "\n ]\n}\n"


def write(name: str, data: Mapping[str, Any], header: Header, path: Path | None = None) -> Path:
    """Write a study's contents with its header (atomically: a temporary file, renamed)."""
    s = study(name)
    p = s.file if path is None else Path(path)
    out = {**{k: v for k, v in data.items() if k != HEADER_KEY}, HEADER_KEY: header.as_dict()}
    p.parent.mkdir(parents=True, exist_ok=True)
    tmp = p.with_suffix(p.suffix + ".tmp")
    tmp.write_text(dumps(out, s.rows), encoding="utf-8")
    tmp.replace(p)
    return p


def rekey(name: str, reason: str, path: Path | None = None) -> Header:
    """Stamp the code's key into the stored study ``name`` whose key differs while every one
    of its fingerprint points still agrees: for a change its numbers do not read (the range
    a parameter's validation accepts, a constant renamed).

    The points are recomputed here (never read from the check memo); a disagreement raises
    :class:`StaleStudy` and nothing is written: such a study must be recomputed
    (:func:`refresh`).  The numbers, and the header's version, CPU class, date and cost of
    their computation, are kept; the note records the parts whose key moved, how many
    points agreed, the date and ``reason`` (a non-empty sentence).  Returns the new header.
    """
    if not isinstance(reason, str) or not reason.strip():
        raise ValueError(f"reason must be a non-empty sentence; got {reason!r}")
    s = study(name)
    data = json.loads(_raw(s, path))
    h = header_of(name, data)
    now = s.key()
    moved = sorted(k for k in set(h.key) | set(now) if h.key.get(k) != now.get(k))
    if not moved:
        raise ValueError(f"the stored study {name} has the code's key already; nothing to "
                         "re-stamp")
    points = int(s.check(data))
    day = _dt.datetime.now(_dt.UTC).replace(microsecond=0).isoformat()
    note = (f"{h.note}; " if h.note else "") + (
        f"key re-stamped {day} after a change in {', '.join(moved)} that moved none of its "
        f"{points} fingerprint points: {' '.join(reason.split())}")
    header = dataclasses.replace(h, key=now, note=note)
    write(name, data, header, path)
    return header


def refresh(name: str, *, executor: object = None, progress: Any = None,
            path: Path | None = None, note: str = "", **options: Any) -> Path:
    """Recompute the study ``name`` (on ``executor``, any ``concurrent.futures.Executor``;
    ``None``: here), write it with a new header (the key now, the declared tolerance, the
    version, CPU class, date and the CPU-s it took) to its file or ``path``, and return the
    path.  ``options`` go to the study's ``compute`` (e.g. a subset of a study's parts)."""
    s = study(name)
    t0 = _cpu()
    data = s.compute(executor, progress, path=path, **options)
    cost = _cpu() - t0
    header = Header(study=name, key=s.key(), rtol=s.rtol, atol=s.atol, version=__version__,
                    cpu_class=cpu_class(),
                    date=_dt.datetime.now(_dt.UTC).replace(microsecond=0).isoformat(),
                    cost_cpu_s=round(cost, 1), note=note or (
                        "computed here" if executor is None else
                        f"computed on {type(executor).__module__}.{type(executor).__name__}"
                        " (its workers' CPU is not counted unless they are this process's "
                        "children)"))
    return write(name, data, header, path)

