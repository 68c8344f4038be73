"""One source of ranges and levels: no range of an input and no printed
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
    "gc/model/discretization.py: _affine_kept_max": "a cache's size (models kept), a count",
    "book/studies/gc.py: WRONG_FACTOR": "the deliberately wrong truth of the claims chapter's "
                                        "power check (σ1² ×9), no input's range",
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


# --------------------------------------------------------------------------------------------
# The chapters (continued): their code cells and their prose.
#
# A chapter's code cell types a grid when it holds
#   * a grid call (geomspace/linspace/logspace/arange) whose ends are numbers;
#   * a tuple, list or set of two or more numbers (outside a subscript; a pair of indices or
#     flags, all of them 0, 1 or -1, is no grid);
#   * a row's field (``BASE.sigma1_sq``, ``PROC.rate_noise``) times a number that ends one of
#     the table's relative ranges (``10 * BASE.sigma1_sq``: a range's end typed);
#   * anything the library's scan flags (a named range or level, σ_c's or 510's value, a
#     row's factors passed to a grid).
# Its prose types a range when it lists two or more numbers joined by ``,``, ``–``, ``-``,
# ``to``, ``and`` or ``or`` (outside glue roles, code spans, math, and equation, reference,
# figure, table and page numbers).  Numbers spelled in words are not read; the chapters'
# "ten times" and "a decade either way" were glued when this scan was written.

CHAPTERS = sorted((ROOT.parent / "chapters").glob("*.md"))
GRID_CALLS = ("geomspace", "linspace", "logspace", "arange")
_FIELDS = {f for r in inputs.INPUTS for f in r.fields}
_RANGE_ENDS = {x for r in inputs.INPUTS if r.kind != "reading" and r.relative
               for x in (r.low, r.high) if x != 1.0}

#: The chapters' typed grids and ranges that are no input's range, by ``chapter: what``
#: (``what``: the name a code cell assigns it to, or the expression, or the prose's words),
#: with the reason.
CHAPTER_ALLOWED: dict[str, str] = {
    # (the Monte Carlo sizes and seeds and the race's sweeps of T_rot, T_settle, the torquer
    # noise and κ are the stored studies' constants: gyrolib/book/studies/gc.py)
    # sweeps that go beyond an input's range on purpose
    "gc_claims.md: psi_priors": "ψ's prior from known exactly (0) to 3°, the prose's "
                                "'uncertainty of degrees': the separability question, "
                                "deliberately beyond σ_ψ(0)'s plausible range",
    # numerical settings and displays
    "calibrate.md: np.linspace(0, 100, 1001)": "a plot's abscissa (s)",
    "gc_filter.md: (0.0, 0.25, 0.5, 0.75, 1.0)": "a colour map's stops",
    "gc_model.md: omega": "a spectrum's frequency axis (rad/s)",
    "gc_model.md: np.logspace(-5, 2, 400)": "a spectrum's frequency axis (rad/s)",
    "gc_model.md: t_fast": "a plot's time axis",
    "gc_model.md: LATE, AP_PCT": "a display's thresholds (time constants, a percentage)",
    "rsf_method.md: tt": "the paper's time axis of Fig. 4 (s)",
    "rsf_method.md: RATE_RUNS, RATE_DURATION": "a simulation's size and length (s)",
    "rsf_method.md: (900.0, 1800.0, 3600.0)": "the paper's printed roll rates",
    "rsf_simulation.md: (10, 50, 90)": "percentiles",
    "rsf_simulation.md: 2 * fast.encoder.position_error": "a difference of two encoder "
        "readings' errors, a bound: no range's end",
    "rsf_method.md: (3600.0, 900.0, 300.0)": "the paper's printed rates (°/s)",
    "rsf_simulation.md: (0.5, 1.0, 3.0, 30.0)": "the simulation's correction intervals (s), "
                                                "inside Δt's range",
    "rsf_simulation.md: [900.0, 1800.0, 2700.0, 3600.0]": "the simulated roll rates (°/s)",
    "rsf_simulation.md: [100.0, 1800.0]": "a plot's axis limits (°/s)",
    "rsf_simulation.md: (1, 2)": "a figure's subplot layout",
    "sensitivity.md: (1.01, 0.5)": "a legend's anchor",
    "errata.md: (60, 120)": "the paper's printed times (s)",
    "intro.md: (10, 60, 120)": "the paper's printed times (s)",
    # prose: the papers' printed numbers, quoted
    "calibrate.md: 1–10": "the whiteness test's lags",
    "errata.md: 21.25, 4590, 36730": "the paper's printed values, quoted",
    "errata.md: 4590 and 36730": "the paper's printed values, quoted",
    "errata.md: 10, 60, 120": "the paper's printed times, quoted",
    "gc_filter.md: 1, 2, 10, 50 and 100": "the times at which two filters are compared",
    "references.md: 52–54": "a reference's pages",
    "rsf_method.md: 4590 and 36 730": "the paper's printed values, quoted",
    "rsf_method.md: 1800–5400": "the paper's printed roll rates, quoted",
    "rsf_method.md: 60 and 120": "the paper's printed times, quoted",
}


def _cell_sources(path: Path) -> list[tuple[str, str]]:
    """(cell type, source) of each cell, as jupytext reads the chapter (IPython magics
    and shell lines dropped from code cells)."""
    import jupytext

    out = []
    nb = jupytext.read(path)
    notebook = "kernelspec" in nb.metadata     # else jupytext made code cells of plain fences
    for cell in nb.cells:
        src = cell.source
        if cell.cell_type == "code" and not notebook:
            continue
        if cell.cell_type == "code":
            src = "\n".join(line for line in src.splitlines()
                            if not line.lstrip().startswith(("%", "!")))
        out.append((cell.cell_type, src))
    return out


def _subscript_parts(tree: ast.AST) -> set[int]:
    return {id(n) for node in ast.walk(tree) if isinstance(node, ast.Subscript)
            for n in ast.walk(node.slice)}


def code_findings(source: str, where: str) -> list[tuple[str, str]]:
    """Each typed grid of a code cell's ``source`` as ``(key, text)``; ``key`` is
    ``"where: name"`` (the name it is assigned to) or ``"where: expression"``."""
    tree = ast.parse(source)
    names = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.Assign) and len(node.targets) == 1:
            t = node.targets[0]
            label = ast.unparse(t).strip("()")
            value = node.value
            if isinstance(value, ast.Call) and value.args:     # np.array([...]), tuple(...)
                names[id(value.args[0])] = label
            names[id(value)] = label
            if isinstance(t, ast.Tuple) and isinstance(value, ast.Tuple):
                names.update({id(e): label for e in value.elts})
    skip = _subscript_parts(tree)
    out = [(key.replace(where + ": ", where + ": ", 1), text)
           for key, text in raw_findings(source, where)]
    for node in ast.walk(tree):
        what = None
        if isinstance(node, ast.Call) and len(node.args) >= 2 and getattr(
                node.func, "attr", getattr(node.func, "id", "")) in GRID_CALLS:
            if number(node.args[0]) is not None and number(node.args[1]) is not None:
                what = "a typed grid"
        elif isinstance(node, (ast.Tuple, ast.List, ast.Set)) and len(node.elts) >= 2 \
                and id(node) not in skip:
            xs = numbers(node) if not isinstance(node, ast.Set) else \
                numbers(ast.Tuple(elts=node.elts))
            if xs and not set(xs) <= {0.0, 1.0, -1.0}:
                what = "typed numbers"
        elif isinstance(node, ast.BinOp) and isinstance(node.op, ast.Mult):
            for a, b in ((node.left, node.right), (node.right, node.left)):
                x = number(a)
                if x is not None and isinstance(b, ast.Attribute) and b.attr in _FIELDS \
                        and any(math.isclose(x, e, rel_tol=1e-9) for e in _RANGE_ENDS):
                    what = "a range's end times a row's field"
        if what:
            label = names.get(id(node), ast.unparse(node))
            out.append((f"{where}: {label}", f"{where}:{node.lineno}: {what} "
                                             f"{ast.unparse(node)}"))
    return out


_NUM = r"\d+(?:[.\u202f ]\d+)?(?:\s*[·×]\s*10[⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+)?"
_SEQ = re.compile(rf"(?<![^\s(\[/:;])({_NUM}(?:\s*(?:,|–|-|\bto\b|\band\b|\bor\b)\s*{_NUM})+)"
                  r"(?![\w)\]/])")
_NOT_PROSE = [
    (re.compile(r"<!--.*?-->", re.S), " "),
    (re.compile(r"^\s*```[^{\n]*\n.*?^\s*```\s*$", re.S | re.M), " "),   # code listings
    (re.compile(r"\$\$.*?\$\$", re.S), " § "),
    (re.compile(r"\{[\w:-]+\}`[^`]*`"), " § "),          # roles: glue, ref, eq, cite, math
    (re.compile(r"`[^`]*`"), " § "),                      # code spans
    (re.compile(r"\$[^$\n]*\$"), " § "),
    (re.compile(r"^\s*(```|:::).*$", re.M), " "),         # directive fences
    (re.compile(r"^\s*:[\w-]+:.*$", re.M), " "),          # directive options (name, alt)
    (re.compile(r"\]\([^)]*\)"), "]"),                    # link targets
    (re.compile(r"\((\w[\w-]*)\)="), " "),                # labels
    (re.compile(r"\b(Eqs?\.|[Rr]efs?\.|Figures?|Fig\.|Tables?|pp?\.|Sections?|[Rr]uns?)"
                r"\s*[\[(]?\d+[\])]?(?:\s*(?:,|and|–)\s*[\[(]?\d+[\])]?)*"), " § "),
]


def prose_findings(markdown: str, where: str) -> list[tuple[str, str]]:
    """Each typed range or list of numbers in a markdown cell's text, as ``(key, text)``."""
    text = markdown
    for pattern, repl in _NOT_PROSE:
        text = pattern.sub(repl, text)
    return [(f"{where}: {' '.join(m.group(1).split())}",
             f"{where}: typed numbers in prose {m.group(1)!r}")
            for m in _SEQ.finditer(text)]


def chapter_candidates(paths=CHAPTERS) -> list[tuple[str, str]]:
    out = []
    for path in paths:
        for kind, src in _cell_sources(path):
            if kind == "code":
                out += code_findings(src, path.name)
            elif kind == "markdown":
                out += prose_findings(src, path.name)
    return out


def test_no_chapter_types_a_range_or_a_grid():
    """The chapters' code cells and prose type no range, grid or level, except the ones
    :data:`CHAPTER_ALLOWED` names with their reasons; each of those is still found (an
    allowance that outlives its grid fails the test)."""
    candidates = chapter_candidates()
    assert sorted({text for key, text in candidates if key not in CHAPTER_ALLOWED}) == []
    assert set(CHAPTER_ALLOWED) <= {key for key, _ in candidates}


@pytest.mark.parametrize("cell", [
    "claim = gc.speed_claim_map(BASE, SIGMA_C, T_BOUND, x_factors=np.logspace(-1, 1, 7))",
    "b = gc.claim_boundary(BASE, SIGMA_C, T_BOUND, factors=(1.0, 10.0))",
    "sweep = gc.shaping_sweep(BASE, 100.0, factors=(0.1, 1.0, 10.0))",
    "S1 = (0.1, 1.0, 10.0)",
    "i = vib.cases.index({'sigma1_sq': 10 * BASE.sigma1_sq})",
    "x = [f * PROC.rate_noise for f in (0.1, 10.0)]",
    "g = np.geomspace(1.0, 100.0, 5)",
    "sigma_c = 2.0e-3 * ARCSEC_PAPER",
])
def test_a_typed_grid_in_a_chapter_is_found(cell):
    """Power: each way the chapters typed their grids before this check is flagged."""
    assert [k for k, _ in code_findings(cell, "injected.md") if k not in CHAPTER_ALLOWED]


@pytest.mark.parametrize("text", [
    "Each of α1, ξ1, σ1², α2, ξ2, σ2² is scaled by 0.1 and 10 (the damping ratios capped).",
    "for loop bandwidths of 1, 10 and 100 rad/s.",
    "swept from 1 to 100 rad/s below",
    "each scaled by 0.1–10; top the stationary P0",
])
def test_a_typed_range_in_prose_is_found(text):
    assert prose_findings(text, "injected.md")


@pytest.mark.parametrize("text", [
    "the shaping filters (6), (7) driven by white noise; refs. [2] and [3]",
    "scaled by {glue:text}`gcc_sweep_lo` and {glue:text}`gcc_sweep_hi`",
    "at 100 s the runs' average, Figure 3 and Table 2",
    "```{glue:figure} x\n:name: fig-x\n:alt: 0.1 and 10\n```",
])
def test_prose_without_a_typed_range_is_not_flagged(text):
    assert prose_findings(text, "neutral.md") == []


def test_the_chapter_scan_flags_an_injected_grid_in_a_real_chapter(tmp_path):
    """Power on a real chapter: gc_race with its vibration grid typed in fails the scan."""
    text = (ROOT.parent / "chapters" / "gc_race.md").read_text(encoding="utf-8")
    typed = text.replace('inputs.factor_grid("gc.sigma1_sq")', "np.logspace(-1, 1, 3)", 1)
    assert typed != text
    (tmp_path / "gc_race.md").write_text(typed, encoding="utf-8")
    found = [t for k, t in chapter_candidates([tmp_path / "gc_race.md"])
             if k not in CHAPTER_ALLOWED]
    assert any("np.logspace(-1, 1, 3)" in t for t in found)
