"""The fast path of the CSV reader: rows of plain decimal numbers parsed in one compiled pass
over the bytes of a block (:func:`parse_rows`), the used columns written straight into a
float array.

It takes only what it can read exactly as the line-by-line path does
(:class:`gyrolib.records.tables._Reader`): ASCII lines ending in ``\\n`` or ``\\r\\n``, cells
separated by commas, blanks around a cell, a used cell a decimal number (``[+-]digits[.digits]
[e[+-]digits]``), ``nan`` in any case with an optional sign, or empty (both a missing value);
an unused cell anything but a quote, ``#`` or a non-ASCII byte.  A number is converted exactly
when its significant digits (at most 18) fit 2⁵³ and its decimal exponent is within ±22: the
digits and the power of ten are then both exact doubles and one IEEE multiplication or
division rounds correctly (Clinger's fast path), which is what Python's ``float`` and numpy's
parsers return.  Anything else — a comment or blank line, a quote, a short row, a longer
mantissa, ``inf``, a lone ``\\r`` — is a *doubt*: the caller reads the block again by the exact
path, which also says which line and column is wrong.
"""

from __future__ import annotations

import math
from typing import Final

import numpy as np
from numba import njit

__all__ = ["parse_rows"]

#: 10**k, k = 0 … 22: every one an exact double.
_POW10: Final[np.ndarray] = np.array([10.0**k for k in range(23)])

#: Digits counted into a mantissa before the parser gives up (int64 holds 18 decimal digits).
_MAX_DIGITS: Final[int] = 18

_TWO53: Final[int] = 2**53

# byte values
_TAB, _LF, _CR, _SP, _QUOTE, _HASH = 9, 10, 13, 32, 34, 35
_PLUS, _COMMA, _MINUS, _DOT, _ZERO, _NINE = 43, 44, 45, 46, 48, 57


@njit(cache=True, nogil=True, inline="always")
def _blank(b):
    return b == _SP or b == _TAB


@njit(cache=True, nogil=True)
def _number(buf, pos, end):
    """The number at ``buf[pos:]`` (blanks skipped by the caller): ``(ok, value, pos)`` with
    ``pos`` after the token; an empty token is NaN (a missing value)."""
    neg = False
    first = pos
    b = buf[pos] if pos < end else _LF
    signed = b == _PLUS or b == _MINUS
    if signed:
        neg = b == _MINUS
        pos += 1
        b = buf[pos] if pos < end else _LF
    if b == 110 or b == 78:                      # n / N: nan in any case
        if (pos + 2 < end and (buf[pos + 1] == 97 or buf[pos + 1] == 65)
                and (buf[pos + 2] == 110 or buf[pos + 2] == 78)):
            return True, math.nan, pos + 3
        return False, 0.0, pos
    mant = 0
    nd = 0
    e10 = 0
    digits = False
    while pos < end and _ZERO <= buf[pos] <= _NINE:
        d = buf[pos] - _ZERO
        digits = True
        if mant != 0 or d != 0:
            if nd >= _MAX_DIGITS:
                return False, 0.0, pos
            mant = mant * 10 + d
            nd += 1
        pos += 1
    if pos < end and buf[pos] == _DOT:
        pos += 1
        while pos < end and _ZERO <= buf[pos] <= _NINE:
            d = buf[pos] - _ZERO
            digits = True
            if mant != 0 or d != 0:
                if nd >= _MAX_DIGITS:
                    return False, 0.0, pos
                mant = mant * 10 + d
                nd += 1
            e10 -= 1
            pos += 1
    if not digits:
        # an empty cell is a missing value; a lone sign or dot is not a number
        b = buf[pos] if pos < end else _LF
        ok = pos == first and (b == _COMMA or b == _LF or b == _CR or _blank(b))
        return ok, math.nan, pos
    if pos < end and (buf[pos] == 101 or buf[pos] == 69):    # e / E
        pos += 1
        eneg = False
        if pos < end and (buf[pos] == _PLUS or buf[pos] == _MINUS):
            eneg = buf[pos] == _MINUS
            pos += 1
        ex = 0
        edig = False
        while pos < end and _ZERO <= buf[pos] <= _NINE:
            if ex < 100000:
                ex = ex * 10 + (buf[pos] - _ZERO)
            edig = True
            pos += 1
        if not edig:
            return False, 0.0, pos
        e10 += -ex if eneg else ex
    if mant == 0:
        return True, -0.0 if neg else 0.0, pos
    if mant >= _TWO53 or e10 < -22 or e10 > 22:
        return False, 0.0, pos
    val = float(mant) * _POW10[e10] if e10 >= 0 else float(mant) / _POW10[-e10]
    return True, -val if neg else val, pos


@njit(cache=True, nogil=True)
def parse_rows(buf, start, end, slot, out):
    """Parse whole lines of ``buf[start:end]`` (uint8) into ``out`` (rows × columns): field
    ``f`` of a line goes to column ``slot[f]`` (``-1``: not used; fields from
    ``len(slot)`` on are not used either), at most ``out.shape[0]`` lines.

    Returns ``(rows, pos, ok)``: the lines parsed and the position after them; ``ok`` is
    False at the first line the fast path does not read exactly as the line-by-line path
    (see the module docstring), ``pos`` is then that line's start.
    """
    need = slot.shape[0]
    pos = start
    r = 0
    max_rows = out.shape[0]
    while r < max_rows and pos < end:
        line = pos
        f = 0
        empty0 = True               # the first field holds nothing but blanks
        while True:
            while pos < end and _blank(buf[pos]):
                pos += 1
            c = slot[f] if f < need else -1
            here = pos
            if c >= 0:
                ok, val, pos = _number(buf, pos, end)
                if not ok:
                    return r, line, False
                out[r, c] = val
            else:
                while pos < end:
                    b = buf[pos]
                    if b == _COMMA or b == _LF or b == _CR:
                        break
                    if b == _QUOTE or b == _HASH or b >= 128 or b == 0:
                        return r, line, False
                    pos += 1
            if f == 0:
                empty0 = pos == here
            while pos < end and _blank(buf[pos]):
                pos += 1
            if pos >= end:          # a last line without its line end: the exact path
                return r, line, False
            b = buf[pos]
            if b == _COMMA:
                f += 1
                pos += 1
                continue
            if b == _LF:
                pos += 1
            elif b == _CR and pos + 1 < end and buf[pos + 1] == _LF:
                pos += 2
            else:                   # a lone \r (a line end of its own) or anything else
                return r, line, False
            break
        if (f == 0 and empty0) or f + 1 < need:    # a blank line, a short row
            return r, line, False
        r += 1
    return r, pos, True
