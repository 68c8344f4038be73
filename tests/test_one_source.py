"""One source of ranges and levels (issue 33, item 1): no range of an input and no printed
level is typed outside :mod:`gyrolib.inputs` (the table of inputs) and :mod:`gyrolib.levels`.

The check reads the library's source (its syntax tree, not its text: docstrings and help
texts may quote a value) and flags, outside those two modules:

* **a named range or level**: a constant whose name says it is one (``…range…``,
  ``…factor…``, ``…spread…``, ``…tolerance…``, ``…prior…``, ``…level…``, ``…sigma_c…``,
  ``…t_max…``, ``…bound…``: an assignment, a dataclass field or a parameter's default) set
  to a non-zero number or a tuple of numbers, unless :data:`ALLOWED` lists it with the
  reason it is no input's range (a numerical tolerance, a confidence level, a search
  horizon).  Numbers are evaluated from literals, :mod:`gyrolib.units`' constants and
  ``to_si``/``from_si`` of literals;
* **a printed level by value**, anywhere: an expression equal to σ_c or to the 510-s bound;
* **a row's factors** ``(low, high)`` passed to ``geomspace``/``linspace``/``logspace``.

Its power: each way the ranges and levels were typed before this check (the GC study's
``to_si(2e-3, "arcsec_paper/s")`` and ``0.5 * 17.0 * 60.0``, the ±10 % and factor-3
constructors, calibrate's ``DEFAULT_SCALE_TOLERANCE = 1e-3``, the rival's
``sigma_c = 2.0e-3 * ARCSEC_PAPER``, a decade as a factor pair) is flagged when injected; and
every entry of :data:`ALLOWED` is a named number the scan finds (dropping one makes it
fail).
"""

from __future__ import annotations

import ast
import math
import re
from pathlib import Path

import pytest

from gyrolib import inputs, levels, units

ROOT = Path(inputs.__file__).resolve().parent
#: The two modules that may type a range or a level.
SOURCES = {ROOT / "inputs.py", ROOT / "levels.py"}
NAMED = re.compile(r"range|factor|spread|tolerance|prior|level|sigma_c|t_max|bound", re.I)


#: Named numbers that are no input's range or level, by ``file: name``, with the reason.
ALLOWED: dict[str, str] = {
    "gc/analysis/montecarlo.py: _SHORT_MAX": "a step-size limit of the truth simulation",
    "gc/analysis/speed_claim.py: y_factor": "a plot's axis scaling",
    "gc/logs/calibration.py: time_tolerance": "a time stamp's rounding tolerance",
    "gc/logs/calibration.py: EARTH_RATE_TOLERANCE": "a consistency check's tolerance",
    "gc/logs/calibration.py: nis_range": "the NIS band's plotting limits",
    "gc/logs/noise_fit.py: level": "a confidence level",
    "gc/logs/noise_fit.py: _RETRY_FACTORS": "an optimizer's restarts, no input's range",
    "gc/racing/rate_sensor.py: t_max": "the rival's search horizon (s), no claim's bound",
    "records/plausibility.py: ANGLE_PRIOR_SIGMAS": "a number of prior σ, a count",
    "rsf/calibration.py: time_tolerance": "a time stamp's tolerance in samples",
    "rsf/claims.py: max_factors": "a count of slip factors searched",
    "sensitivity/study.py: CONF_LEVEL": "a confidence level",
}
LEVELS = (levels.SIGMA_C, levels.T_BOUND)
PAIRS = {(r.low, r.high) for r in inputs.INPUTS if r.kind != "reading" and r.relative}


def number(node: ast.AST) -> float | None:
    """The value of a constant expression of literals, units' constants and to_si/from_si
    of literals; None for anything else."""
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) \
            and not isinstance(node.value, bool):
        return float(node.value)
    if isinstance(node, ast.Name) and isinstance(getattr(units, node.id, None), float):
        return getattr(units, node.id)
    if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) \
            and node.value.id == "units" and isinstance(getattr(units, node.attr, None), float):
        return getattr(units, node.attr)
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
        x = number(node.operand)
        return None if x is None else -x
    if isinstance(node, ast.BinOp):
        a, b = number(node.left), number(node.right)
        if a is None or b is None:
            return None
        ops = {ast.Mult: lambda: a * b, ast.Div: lambda: a / b if b else None,
               ast.Add: lambda: a + b, ast.Sub: lambda: a - b}
        f = ops.get(type(node.op))
        return None if f is None else f()
    if isinstance(node, ast.Call) and len(node.args) == 2 and not node.keywords:
        fname = node.func.attr if isinstance(node.func, ast.Attribute) else \
            getattr(node.func, "id", "")
        if isinstance(node, ast.Call) and fname == "float":
            return None
        if fname in ("to_si", "from_si") and isinstance(node.args[1], ast.Constant):
            x = number(node.args[0])
            return None if x is None else float(getattr(units, fname)(x, node.args[1].value))
    if isinstance(node, ast.Call) and getattr(node.func, "id", "") == "float" \
            and len(node.args) == 1:
        return number(node.args[0])
    return None


def numbers(node: ast.AST) -> list[float] | None:
    """A number, or a tuple/list of numbers, as a list; None otherwise."""
    if isinstance(node, (ast.Tuple, ast.List)):
        xs = [number(e) for e in node.elts]
        return None if not xs or None in xs else xs
    x = number(node)
    return None if x is None else [x]


def findings(source: str, where: str, allowed: dict[str, str] = ALLOWED) -> list[str]:
    """Each typed range or level in ``source`` (a module's text), as ``where:line: what``."""
    return [text for key, text in raw_findings(source, where) if key not in allowed]


def raw_findings(source: str, where: str) -> list[tuple[str, str]]:
    """Each candidate as ``(key, text)``: ``key`` is ``"where: name"`` for a named number
    (what :data:`ALLOWED` may list), ``""`` otherwise."""
    out = []
    for node in ast.walk(ast.parse(source)):
        named: list[tuple[str, ast.AST]] = []
        if isinstance(node, ast.Assign):
            named += [(t.id, node.value) for t in node.targets if isinstance(t, ast.Name)]
        elif isinstance(node, ast.AnnAssign) and node.value is not None \
                and isinstance(node.target, ast.Name):
            named.append((node.target.id, node.value))
        elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            a = node.args
            pos = a.posonlyargs + a.args
            named += [(p.arg, d) for p, d in zip(pos[len(pos) - len(a.defaults):], a.defaults,
                                                 strict=True)]
            named += [(p.arg, d) for p, d in zip(a.kwonlyargs, a.kw_defaults, strict=True)
                      if d is not None]
        for name, value in named:
            xs = numbers(value)
            if NAMED.search(name) and xs and any(xs):
                out.append((f"{where}: {name}",
                            f"{where}:{value.lineno}: {name} = {ast.unparse(value)}"))
        if isinstance(node, (ast.BinOp, ast.Call, ast.Constant)):
            x = number(node)
            if x is not None and any(math.isclose(x, lv, rel_tol=1e-9) for lv in LEVELS):
                out.append(("", f"{where}:{node.lineno}: a printed level {ast.unparse(node)}"))
        if isinstance(node, ast.Call) and len(node.args) >= 2 and getattr(
                node.func, "attr", getattr(node.func, "id", "")) in (
                "geomspace", "linspace", "logspace"):
            pair = (number(node.args[0]), number(node.args[1]))
            if None not in pair and any(math.isclose(pair[0], lo, rel_tol=1e-9)
                                        and math.isclose(pair[1], hi, rel_tol=1e-9)
                                        for lo, hi in PAIRS):
                out.append(("", f"{where}:{node.lineno}: a row's factors {ast.unparse(node)}"))
    return out


def library_candidates() -> list[tuple[str, str]]:
    out = []
    for path in sorted(ROOT.rglob("*.py")):
        if path not in SOURCES:
            out += raw_findings(path.read_text(encoding="utf-8"),
                                str(path.relative_to(ROOT)))
    return out


def test_no_range_or_level_is_typed_outside_the_table():
    """The library's own scan is clean, and every allowed entry is still used (each one,
    dropped, makes the scan fail: the allowance is no blanket)."""
    candidates = library_candidates()
    assert [text for key, text in candidates if key not in ALLOWED] == []
    assert set(ALLOWED) <= {key for key, _ in candidates}


@pytest.mark.parametrize("snippet", [
    '_LEVEL: Final[float] = float(to_si(2e-3, "arcsec_paper/s"))',
    "_T_MAX: Final[float] = 0.5 * 17.0 * 60.0",
    "def printed(cls, name, nominal, spread: float = 0.1): ...",
    "def unstated(cls, name, nominal, factor: float = 3.0): ...",
    "DEFAULT_SCALE_TOLERANCE: Final[float] = 1e-3",
    "DEFAULT_OFFSET_PRIOR = 20.0 * ARCSEC_PAPER",
    "class P:\n    sigma_c: float = 2.0e-3 * ARCSEC_PAPER",
    "def turn_limit(params=None, level: float = 2.0e-3 * units.ARCSEC_PAPER): ...",
    "x = np.geomspace(0.1, 10.0, 5)",
    "TREND_FACTORS = (0.1, 10.0)",
    "def west(params, t_end=510.0): ...",
])
def test_a_typed_range_or_level_is_found(snippet):
    """Power: each way a range or a level was typed before is flagged."""
    assert findings(snippet, "injected")


@pytest.mark.parametrize("snippet", [
    "_STEP: Final[float] = 1e-3",                       # not named as a range or a level
    "clock_tolerance = 0.0",                            # zero: no value
    "xy = (0.9 * r, 1.7 * r)",
    "x = np.geomspace(1e-3, 1.0, 5)",
])
def test_neutral_code_is_not_flagged(snippet):
    assert findings(snippet, "neutral") == []
