"""The verdict of a calibration on a recorded log, one object for both papers.

:func:`gyrolib.gc.judge_record` (paper GC's drift ω_gc) and :func:`gyrolib.rsf.judge_record`
(paper RSF's scale-factor error ε̄1) each return a :class:`Verdict`: the estimate, its total
σ with every named term (adding in quadrature), each check (:class:`Check`: the state or
statistic it tests, its value and its one band), the status (``ok``, ``misfit``,
``invalid``) with the reason, its ``reason_code`` and hint (:mod:`gyrolib.reasons`), and the
counts of the record's rows (:class:`Counts`, each at most the rows).  The command line
(``python -m gyrolib calibrate``) and the book print this object and decide nothing.

A check's band is printed by :meth:`Check.line` alone, with the digits
(:func:`compared`) that make the printed comparison read as the numbers compare; the text,
the JSON (:meth:`Check.summary`) and the object hold the same name, value and band.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Final

from gyrolib._repr import compact_repr

__all__ = ["STATUSES", "Check", "Counts", "Verdict", "compared"]

#: The statuses of a verdict: ``ok`` (every check passes: the estimate is a result),
#: ``misfit`` (a model check fails and the estimate was asked for anyway, marked: σ may
#: not cover the truth), ``invalid`` (no estimate).
STATUSES: Final[tuple[str, ...]] = ("ok", "misfit", "invalid")


def compared(x: float, lo: float | None, hi: float | None) -> tuple[str, str, str]:
    """``x``, ``lo`` and ``hi`` formatted with as many significant digits (4 at least, 12 at
    most) as it takes for the printed numbers to compare as the numbers do, so that no
    printed comparison reads false ("23.2 > 23.2"); a missing bound prints as "".

    Examples
    --------
    >>> compared(23.24, None, 23.2351)
    ('23.24', '', '23.235')
    >>> compared(0.99812, 0.998123, 1.0021)
    ('0.99812', '0.998123', '1.0021')
    """
    def ok(d: int) -> bool:
        fx = float(f"{x:.{d}g}")
        return all((float(f"{b:.{d}g}") < fx) == (b < x)
                   and (float(f"{b:.{d}g}") > fx) == (b > x) for b in (lo, hi) if b is not None)

    d = next((d for d in range(4, 13) if ok(d)), 12)
    return (f"{x:.{d}g}", "" if lo is None else f"{lo:.{d}g}",
            "" if hi is None else f"{hi:.{d}g}")


def _number(x: float | None) -> float | None:
    """``x`` as a float, ``None`` when missing or not finite (JSON has no NaN)."""
    return None if x is None or not math.isfinite(float(x)) else float(x)


@dataclass(frozen=True)
class Check:
    """One check of a verdict: ``test`` (its kind: ``"prior"``, ``"mean NIS"``, …) of
    ``subject`` (the state or statistic it tests, named as the JSON and the result name it:
    ``"delta"``, ``"omega_gc"``, ``"angle_sensor"``, ``"eps1_hat_mean"``), the
    ``formula`` of the statistic computed (``"estimate/sqrt(P0 - P)"``), its ``value`` and
    its one band
    [``low``, ``high``] (passed when inside, ends included), the ``reason_code`` of a
    failure (:data:`gyrolib.reasons.REASONS`) and its ``cause`` (a sentence; ``""`` when
    none is known).

    Examples
    --------
    >>> c = Check("prior", "delta", "estimate/sqrt(P0 - P)", 3.612, -3.383, 3.383,
    ...           "prior_tilt")
    >>> c.passed, c.name
    (False, 'prior of delta')
    >>> c.line()
    'prior of delta: estimate/sqrt(P0 - P) = 3.612 NOT in [-3.383, 3.383]'
    """

    test: str
    subject: str
    formula: str
    value: float
    low: float
    high: float
    reason_code: str
    cause: str = ""

    @property
    def passed(self) -> bool:
        """True when :attr:`value` lies in [:attr:`low`, :attr:`high`]."""
        return bool(self.low <= self.value <= self.high)

    @property
    def name(self) -> str:
        """``"<test> of <subject>"``: the check's name in the text and the JSON."""
        return f"{self.test} of {self.subject}"

    def band(self) -> str:
        """The band as printed everywhere: ``[low, high]`` with the digits of
        :func:`compared`."""
        _, lo, hi = compared(self.value, self.low, self.high)
        return f"[{lo}, {hi}]"

    def line(self) -> str:
        """The check in one line: name, formula, value, in or NOT in its band."""
        x, _, _ = compared(self.value, self.low, self.high)
        return (f"{self.name}: {self.formula} = {x} {'in' if self.passed else 'NOT in'} "
                f"{self.band()}")

    def summary(self) -> dict:
        """The check as a JSON-ready dict: ``name``, ``test``, ``subject``, ``formula``,
        ``statistic`` (the value), ``low``, ``high``, ``band`` (the printed band),
        ``passed``, ``reason_code``, ``cause``."""
        return {"name": self.name, "test": self.test, "subject": self.subject,
                "formula": self.formula, "statistic": _number(self.value),
                "low": _number(self.low), "high": _number(self.high), "band": self.band(),
                "passed": self.passed, "reason_code": self.reason_code, "cause": self.cause}


@dataclass(frozen=True)
class Counts:
    """The record's rows as the calibration used them, a partition: ``used`` (rows whose
    measurements were all used, or missing, and one at least used), ``rejected`` (rows with
    a measurement the gate rejected, or that the method left out), ``empty`` (rows with
    nothing to use: every value missing, or across a gap); ``used + rejected + empty ==
    rows``.  ``missing``: missing values (cells), counted apart.

    Examples
    --------
    >>> Counts(rows=499, used=0, rejected=499, empty=0).line()
    'rows 499: used 0, with a rejected measurement 499, with nothing to use 0'
    """

    rows: int
    used: int
    rejected: int
    empty: int
    missing: int = 0
    rejected_means: str = "with a rejected measurement"

    def __post_init__(self) -> None:
        for name in ("rows", "used", "rejected", "empty", "missing"):
            val = getattr(self, name)
            if isinstance(val, bool) or not isinstance(val, int) or val < 0:
                raise ValueError(f"{name} must be an integer >= 0; got {val!r}")
        if self.used + self.rejected + self.empty != self.rows:
            raise ValueError(f"used + rejected + empty ({self.used} + {self.rejected} + "
                             f"{self.empty}) must equal rows ({self.rows})")

    def line(self) -> str:
        """The partition in one line."""
        return (f"rows {self.rows}: used {self.used}, {self.rejected_means} {self.rejected}, "
                f"with nothing to use {self.empty}")

    def summary(self) -> dict:
        """JSON-ready: ``rows``, ``used``, ``rejected``, ``empty``, ``missing``."""
        return {"rows": self.rows, "used": self.used, "rejected": self.rejected,
                "empty": self.empty, "missing": self.missing}


@compact_repr
@dataclass(frozen=True)
class Verdict:
    """A calibration on a record, judged (SI).

    * ``method`` (``"gc"``, ``"rsf"``), ``quantity`` (``"omega_gc"``, ``"eps1_hat_mean"``)
      and its ``unit``; ``estimate`` and ``sigma``, its total standard uncertainty, with
      ``sigma_parts`` (every named term; they add in quadrature to ``sigma``);
    * ``checks``: every :class:`Check` made, passed or not; ``false_alarm``: their
      family-wise false-alarm rate;
    * ``status`` (:data:`STATUSES`), ``reason`` (why it is not ``ok``: ``""`` when it is),
      ``reason_codes`` (every code of the evidence), ``reason_code`` (the one the evidence
      points to first, :func:`gyrolib.reasons.primary`) and ``hint``
      (:func:`gyrolib.reasons.hint`);
    * ``counts`` (:class:`Counts`), ``notes`` (sentences on the record and the run);
    * ``result``: the method's own result (:class:`gyrolib.gc.CalibrationResult`,
      :class:`gyrolib.rsf.CalibrationResult`); ``details``: the method's other objects by
      name (the noise fit, the uncertainty, the prediction).
    """

    method: str
    quantity: str
    unit: str
    estimate: float
    sigma: float
    sigma_parts: Mapping[str, float]
    checks: tuple[Check, ...]
    false_alarm: float
    status: str
    reason: str
    reason_codes: tuple[str, ...]
    reason_code: str
    hint: str
    counts: Counts
    notes: tuple[str, ...] = ()
    result: object = None
    details: Mapping[str, object] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.status not in STATUSES:
            raise ValueError(f"status must be one of {STATUSES}; got {self.status!r}")
        if (self.status == "ok") != (not self.reason):
            raise ValueError("reason must be empty exactly when status is 'ok'")
        total = math.sqrt(sum(p * p for p in self.sigma_parts.values()))
        if math.isfinite(self.sigma) and not math.isclose(total, self.sigma, rel_tol=1e-9,
                                                          abs_tol=1e-300):
            raise ValueError(f"sigma_parts must add in quadrature to sigma ({total} != "
                             f"{self.sigma})")

    @property
    def valid(self) -> bool:
        """True when the status is ``ok``."""
        return self.status == "ok"

    @property
    def given(self) -> bool:
        """True when the estimate is reported (``ok``, or ``misfit`` on request)."""
        return self.status != "invalid"

    @property
    def failed(self) -> tuple[Check, ...]:
        """The checks that failed."""
        return tuple(c for c in self.checks if not c.passed)

    def summary(self) -> dict:
        """The verdict as a JSON-ready dict: ``method``, ``quantity``, ``unit``,
        ``estimate``, ``sigma``, ``sigma_parts`` (``None`` when not given), ``status``,
        ``valid``, ``reason``, ``reason_code`` (``None`` when none), ``reason_codes``,
        ``hint`` (``None`` when none), ``false_alarm``, ``checks``, ``counts``."""
        given = self.given
        return {"method": self.method, "quantity": self.quantity, "unit": self.unit,
                "estimate": _number(self.estimate) if given else None,
                "sigma": _number(self.sigma) if given else None,
                "sigma_parts": ({k: float(x) for k, x in self.sigma_parts.items()} if given
                                else None),
                "status": self.status, "valid": self.valid, "reason": self.reason,
                "reason_code": self.reason_code or None,
                "reason_codes": list(self.reason_codes), "hint": self.hint or None,
                "false_alarm": self.false_alarm,
                "checks": [c.summary() for c in self.checks],
                "counts": self.counts.summary()}
