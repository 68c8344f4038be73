"""The printed levels the papers' claims are judged against, in one leaf module.

The ledger's item builders (:mod:`gyrolib.book.ledger.gc`, :mod:`gyrolib.book.ledger.rsf`),
the claims' margins (:mod:`gyrolib.book.ledger.claims`), the race's rival
(:class:`gyrolib.gc.RateSensorProcedure`'s ``sigma_c``) and paper GC's study of σ_gc and t_c
(:func:`gyrolib.gc.sensitivity`) read them from here, so that no level is typed twice.  The
module imports nothing of gyrolib but :mod:`gyrolib.units` (itself a leaf), so that the library
below the book can import it without a cycle.

Examples
--------
>>> from gyrolib import levels
>>> round(levels.T_BOUND), levels.TIMES, levels.CUBIC_EXPONENT
(510, (10, 60, 120), 2.9)
"""

from __future__ import annotations

from typing import Final

from gyrolib.units import ARCSEC_PAPER

__all__ = ["AREA_TOLERANCE", "COMPENSATED_PERCENT", "CUBIC_EXPONENT", "FASTER_PERCENT",
           "GS_VS_SINS_RATIO", "REF2_MINUTES", "SIGMA_C", "SIGMA_C_PRINTED", "TIMES", "T_BOUND"]

# paper GC ------------------------------------------------------------------------------------
#: The required calibration accuracy of the north gyro as printed, σ_c = 2·10⁻³ ″/s (paper
#: GC, after its ref. [2]; the paper's 1″ = 0.485·10⁻⁵ rad), and in rad/s.
SIGMA_C_PRINTED: Final[float] = 2e-3
SIGMA_C: Final[float] = SIGMA_C_PRINTED * ARCSEC_PAPER

#: Ref. [2]'s calibration time (min) and the claim "more than 50 % faster" (%).
REF2_MINUTES: Final[float] = 17.0
FASTER_PERCENT: Final[float] = 50.0

#: The book's reading of "more than 50 % faster" than ref. [2]'s 17 min: σ_c reached in less
#: than half of 17 min, in seconds (510 s).  An inference from two printed numbers, not a
#: printed value.
T_BOUND: Final[float] = (1.0 - FASTER_PERCENT / 100.0) * REF2_MINUTES * 60.0

#: Relative tolerance of Fig. 2's "the area under the PSD equals σ²" (the quadrature's own
#: accuracy is far better; the claim is an identity of the shaping filters, not a print to
#: digits).
AREA_TOLERANCE: Final[float] = 1e-6

# paper RSF -----------------------------------------------------------------------------------
#: The times of Tables 2 and 3 (s).
TIMES: Final[tuple[int, ...]] = (10, 60, 120)

#: "Grows as t³" (Eq. (8)): the local exponent the book requires at every printed time.
CUBIC_EXPONENT: Final[float] = 2.9

#: "Compensates 90 %" (the conclusion), in %.
COMPENSATED_PERCENT: Final[float] = 90.0

#: "Hundreds of times smaller" (after Table 3): at least 100.
GS_VS_SINS_RATIO: Final[float] = 100.0
