"""The numbers of an ASCII PLY body: whitespace-separated tokens, counted, then parsed into
one float64 array (no Python object per token).

A token is a run of bytes other than ASCII whitespace (space, tab, LF, VT, FF, CR). Each is
parsed as ``[+-]digits[.digits][(e|E)[+-]digits]``, exactly where one rounding suffices
(Clinger's fast path: the significant digits read into an integer, scaled by an exact power
of ten); the others are flagged for the caller to read again (``INEXACT``: more digits
or a large exponent; ``OTHER``: not a plain decimal number, such as ``nan``, ``inf`` or no
number at all). The kernels never raise: the caller names the bad token.
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel

__all__ = ["INEXACT", "OK", "OTHER", "copy_texts", "count_tokens", "locate_tokens", "parse_tokens"]

OK, INEXACT, OTHER = 0, 1, 2

_POW10 = np.array([10.0**k for k in range(23)])
_EXACT = 1 << 53
_PLUS, _MINUS, _DOT, _ZERO, _NINE, _E, _LF = 43, 45, 46, 48, 57, 101, 10


@kernel(inline="always")
def _blank(c):
    return c == 32 or (9 <= c <= 13)


@kernel
def count_tokens(buf, start):
    """Tokens in buf[start:]."""
    n = 0
    inside = False
    for i in range(start, len(buf)):
        blank = _blank(buf[i])
        if not blank and not inside:
            n += 1
        inside = not blank
    return n


@kernel(fastmath=False)  # IEEE arithmetic: a division by a reciprocal would round twice
def parse_tokens(buf, start, n):
    """The first ``n`` tokens of buf[start:] (there are that many): values (n,) float64 and
    status (n,) int8 (OK, INEXACT or OTHER; the value is 0 unless OK).

    At most 18 significant digits go into the integer ``mantissa`` (an int64 cannot hold
    every 19-digit number); later digits shift the exponent (before the point) or, when not
    zero, make the value INEXACT. (The two digit loops are written out: as one helper the
    kernel ran at half the speed.)"""
    values = np.empty(n)
    status = np.empty(n, np.int8)
    end = len(buf)
    i = start
    for k in range(n):
        while _blank(buf[i]):
            i += 1
        negative = buf[i] == _MINUS
        if buf[i] == _MINUS or buf[i] == _PLUS:
            i += 1
        mantissa = 0
        digits = 0  # significant digits in mantissa
        seen = 0  # digits of the number
        exponent = 0
        state = OK
        while i < end:
            d = np.int64(buf[i]) - _ZERO
            if d < 0 or d > 9:
                break
            if digits < 18:
                mantissa = mantissa * 10 + d
                digits += mantissa > 0
            else:
                exponent += 1
                state = INEXACT if d > 0 else state
            seen += 1
            i += 1
        if i < end and buf[i] == _DOT:
            i += 1
            while i < end:
                d = np.int64(buf[i]) - _ZERO
                if d < 0 or d > 9:
                    break
                if digits < 18:
                    mantissa = mantissa * 10 + d
                    digits += mantissa > 0
                    exponent -= 1
                elif d > 0:
                    state = INEXACT
                seen += 1
                i += 1
        if seen == 0:
            state = OTHER
        if i < end and buf[i] | 32 == _E:
            i += 1
            sign = 1
            if i < end and (buf[i] == _PLUS or buf[i] == _MINUS):
                sign = -1 if buf[i] == _MINUS else 1
                i += 1
            e = 0
            e_digits = 0
            while i < end and _ZERO <= buf[i] <= _NINE:
                e = min(e * 10 + (np.int64(buf[i]) - _ZERO), 100000)
                e_digits += 1
                i += 1
            if e_digits == 0:
                state = OTHER
            exponent += sign * e
        if i < end and not _blank(buf[i]):  # more bytes in the token: no plain number
            state = OTHER
            while i < end and not _blank(buf[i]):
                i += 1
        value = 0.0
        if state == OK and mantissa != 0:
            if mantissa >= _EXACT or exponent > 22 or exponent < -22:
                state = INEXACT
            elif exponent >= 0:
                value = mantissa * _POW10[exponent]
            else:
                value = mantissa / _POW10[-exponent]
        values[k] = -value if negative else value
        status[k] = state
    return values, status


@kernel
def locate_tokens(buf, start, which):
    """Where tokens ``which`` (ascending token numbers, counted from 0 at ``start``) are:
    their first and end byte (starts, ends (K,) int64) and how many line breaks come before
    each after ``start`` (lines (K,) int64)."""
    k = len(which)
    starts = np.empty(k, np.int64)
    ends = np.empty(k, np.int64)
    lines = np.empty(k, np.int64)
    token = -1
    line = 0
    inside = False
    j = 0
    i = start
    while i < len(buf) and j < k:
        c = buf[i]
        blank = _blank(c)
        if not blank and not inside:
            token += 1
            if token == which[j]:
                starts[j] = i
                lines[j] = line
                end = i
                while end < len(buf) and not _blank(buf[end]):
                    end += 1
                ends[j] = end
                j += 1
                while j < k and which[j] == token:  # the same token asked for again
                    starts[j], ends[j], lines[j] = starts[j - 1], ends[j - 1], lines[j - 1]
                    j += 1
        if c == _LF:
            line += 1
        inside = not blank
        i += 1
    return starts[:j], ends[:j], lines[:j]


@kernel
def copy_texts(buf, starts, ends, width):
    """(K, width) uint8: the bytes of each token ``buf[starts[k]:ends[k]]``, cut at ``width``
    and padded with zeros (for NumPy to read them as one array of bytes strings)."""
    out = np.zeros((len(starts), width), np.uint8)
    for k in range(len(starts)):
        for i in range(min(ends[k] - starts[k], width)):
            out[k, i] = buf[starts[k] + i]
    return out
