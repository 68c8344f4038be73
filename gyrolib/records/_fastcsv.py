"""The fast path of the CSV reader: rows of plain decimal numbers parsed in one compiled pass
over the bytes of a block (:func:`parse_rows`), the used columns written straight into a
float array.

It takes only what it can read exactly as the line-by-line path does
(:class:`gyrolib.records.reader._Reader`): ASCII lines ending in ``\\n`` or ``\\r\\n``, cells
separated by commas, blanks around a cell, a used cell a decimal number (``[+-]digits[.digits]
[e[+-]digits]``), ``nan`` in any case with an optional sign, or empty (both a missing value);
an unused cell anything but a quote, ``#`` or a non-ASCII byte.  A number is converted as
Python's ``float`` converts it, correctly rounded: digits (at most 19) and a power of ten
that are both exact doubles by one IEEE multiplication or division (Clinger's fast path),
else by the Eisel–Lemire algorithm (a 128-bit product with a table of the powers of ten),
else, for an exact binary fraction it leaves undecided, by the whole quotient
``digits / 5**k``.  Anything else — a comment or blank line, a quote, a short row, more
digits, a subnormal number, ``inf``, a lone ``\\r`` — is a *doubt*: the caller reads the
block again by the exact path, which also says which line and column is wrong.
"""

from __future__ import annotations

import math
from typing import Final

import numpy as np
from numba import njit

from gyrolib import _compile_note  # noqa: F401  (a line on stderr at the first compile)

__all__ = ["parse_rows"]

#: 10**k, k = 0 … 22: every one an exact double.
_POW10: Final[np.ndarray] = np.array([10.0**k for k in range(23)])

#: Digits counted into a mantissa before the parser gives up (uint64 holds 19 decimal digits).
_MAX_DIGITS: Final[int] = 19

_TWO53: Final[int] = 2**53


def _powers_of_ten(lo: int, hi: int) -> tuple[np.ndarray, np.ndarray]:
    """10**e, e = lo … hi, as 128-bit mantissas rounded down with the top bit set: the high
    and low 64 bits (the table of the Eisel–Lemire algorithm, computed exactly here)."""
    his, los = [], []
    for e in range(lo, hi + 1):
        if e >= 0:
            v = 10**e
            m = v >> (v.bit_length() - 128) if v.bit_length() > 128 else v << (128 - v.bit_length())
        else:
            d = 10**-e
            k = d.bit_length() + 127
            m = (1 << k) // d
            if m.bit_length() < 128:
                m = (1 << (k + 1)) // d
        his.append(m >> 64)
        los.append(m & (2**64 - 1))
    return np.array(his, dtype=np.uint64), np.array(los, dtype=np.uint64)


#: 5**k, k = 0 … 27, as uint64 (5**27 < 2**64).
_POW5: Final[np.ndarray] = np.array([5**k for k in range(28)], dtype=np.uint64)

_POW10_MIN: Final[int] = -348
_POW10_HI, _POW10_LO = _powers_of_ten(_POW10_MIN, 347)
_U1, _U9, _U32, _U52, _U63 = (np.uint64(k) for k in (1, 9, 32, 52, 63))
_MASK32: Final = np.uint64(0xFFFFFFFF)
_MASK9: Final = np.uint64(0x1FF)
_MASK64: Final = np.uint64(0xFFFFFFFFFFFFFFFF)


@njit(cache=True, nogil=True, inline="always")
def _mul64(a, b):
    """The 128-bit product of two uint64: (high, low)."""
    a0, a1 = a & _MASK32, a >> _U32
    b0, b1 = b & _MASK32, b >> _U32
    w0 = a0 * b0
    t = a1 * b0 + (w0 >> _U32)
    w1 = (t & _MASK32) + a0 * b1
    hi = a1 * b1 + (t >> _U32) + (w1 >> _U32)
    return hi, a * b


@njit(cache=True, nogil=True)
def _eisel_lemire(man, e10):
    """``man · 10**e10`` correctly rounded to a double (``man`` a nonzero uint64), or
    ``(False, 0)`` where the algorithm cannot decide (a near tie) or the result is not a
    normal double (D. Lemire, "Number parsing at a gigabyte per second", 2021; the form of
    Go's ``strconv.eiselLemire64``)."""
    if e10 < _POW10_MIN or e10 > _POW10_MIN + _POW10_HI.shape[0] - 1:
        return False, 0.0
    clz = 0
    m = man
    for k in (32, 16, 8, 4, 2, 1):       # normalize: the top bit set
        if m >> np.uint64(64 - k) == np.uint64(0):
            m = m << np.uint64(k)
            clz += k
    ret_exp2 = ((217706 * e10) >> 16) + 64 + 1023 - clz
    i = e10 - _POW10_MIN
    x_hi, x_lo = _mul64(m, _POW10_HI[i])
    if (x_hi & _MASK9) == _MASK9 and x_lo + m < m:       # the wider approximation
        y_hi, y_lo = _mul64(m, _POW10_LO[i])
        merged_hi, merged_lo = x_hi, x_lo + y_hi
        if merged_lo < x_lo:
            merged_hi += _U1
        if (merged_hi & _MASK9) == _MASK9 and merged_lo == _MASK64 and y_lo + m < m:
            return False, 0.0
        x_hi, x_lo = merged_hi, merged_lo
    msb = x_hi >> _U63
    mant = x_hi >> (msb + _U9)
    if msb == np.uint64(0):
        ret_exp2 -= 1
    if x_lo == np.uint64(0) and (x_hi & _MASK9) == np.uint64(0) and \
            (mant & np.uint64(3)) == _U1:                # a tie the bits cannot decide
        return False, 0.0
    mant += mant & _U1
    mant >>= _U1
    if mant >> np.uint64(53) > np.uint64(0):
        mant >>= _U1
        ret_exp2 += 1
    if ret_exp2 <= 0 or ret_exp2 >= 0x7FF:               # subnormal, zero or overflow
        return False, 0.0
    return True, math.ldexp(float(mant), ret_exp2 - 1075)

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
    mant = np.uint64(0)
    nd = 0
    e10 = 0
    digits = False
    while pos < end and _ZERO <= buf[pos] <= _NINE:
        d = buf[pos] - _ZERO
        digits = True
        if mant != 0 or d != 0:
            if nd >= _MAX_DIGITS:
                return False, 0.0, pos
            mant = mant * np.uint64(10) + np.uint64(d)
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
                mant = mant * np.uint64(10) + np.uint64(d)
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
    if mant == np.uint64(0):
        return True, -0.0 if neg else 0.0, pos
    if mant >= np.uint64(_TWO53) or not -22 <= e10 <= 22:
        # trailing zeros ("%.18e" of 0.125) off the mantissa: Clinger's path may fit then
        while mant % np.uint64(10) == np.uint64(0):
            mant //= np.uint64(10)
            e10 += 1
    if mant < np.uint64(_TWO53) and -22 <= e10 <= 22:   # Clinger's fast path: exact
        val = float(mant) * _POW10[e10] if e10 >= 0 else float(mant) / _POW10[-e10]
    else:
        ok, val = _eisel_lemire(mant, e10)
        if not ok and -_POW5.shape[0] < e10 < 0 and mant % _POW5[-e10] == np.uint64(0):
            # an exact binary fraction the algorithm leaves undecided (568347475453083.75):
            # mant · 10**e10 = (mant / 5**-e10) · 2**e10, the quotient a whole number, its
            # conversion rounded once, the power of two exact
            ok, val = True, math.ldexp(float(mant // _POW5[-e10]), e10)
        if not ok:
            return False, 0.0, pos
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
