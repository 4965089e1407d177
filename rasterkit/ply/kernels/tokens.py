"""The numbers of an ASCII PLY body: whitespace-separated tokens, counted, then parsed into
one float64 array (no Python object per token).

A token is a run of bytes other than ASCII whitespace (space, tab, LF, VT, FF, CR). Each is
parsed as ``[+-]digits[.digits][(e|E)[+-]digits]``, exactly where one rounding suffices
(Clinger's fast path: at most 19 significant digits read into an integer, scaled by an exact
power of ten); the others are flagged for the caller to read again (``INEXACT``: more digits
or a large exponent; ``OTHER``: not a plain decimal number, such as ``nan``, ``inf`` or no
number at all). The kernels never raise: the caller names the bad token.
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel

__all__ = ["INEXACT", "OK", "OTHER", "count_tokens", "locate_tokens", "parse_tokens"]

OK, INEXACT, OTHER = 0, 1, 2

_POW10 = np.array([10.0**k for k in range(23)])
_EXACT = np.uint64(1 << 53)
_PLUS, _MINUS, _DOT, _ZERO, _LF = 43, 45, 46, 48, 10


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


@kernel(fastmath=False)  # IEEE division: a reciprocal would round twice
def _number(buf, a, b):
    """(value, status) of the token buf[a:b] (see the module documentation)."""
    i = a
    negative = buf[i] == _MINUS
    if buf[i] == _PLUS or buf[i] == _MINUS:
        i += 1
    mantissa = np.uint64(0)
    digits = 0
    exponent = 0
    truncated = False
    point = False
    first = i
    while i < b:
        c = buf[i]
        if c == _DOT and not point:
            point = True
        elif 48 <= c <= 57:
            if digits < 19:
                if mantissa > 0 or c > _ZERO:
                    mantissa = mantissa * np.uint64(10) + np.uint64(c - _ZERO)
                    digits += 1
                if point:
                    exponent -= 1
            else:
                if not point:
                    exponent += 1
                truncated = truncated or c > _ZERO
        else:
            break
        i += 1
    if i - first == (1 if point else 0):  # no digit
        return 0.0, OTHER
    if i < b and buf[i] | 32 == 101:  # e or E
        i += 1
        sign = 1
        if i < b and (buf[i] == _PLUS or buf[i] == _MINUS):
            sign = -1 if buf[i] == _MINUS else 1
            i += 1
        e_first = i
        e = 0
        while i < b and 48 <= buf[i] <= 57:
            e = min(e * 10 + (buf[i] - _ZERO), 100000)
            i += 1
        if i == e_first:
            return 0.0, OTHER
        exponent += sign * e
    if i != b:
        return 0.0, OTHER
    if mantissa == 0:
        return -0.0 if negative else 0.0, OK
    if truncated or mantissa >= _EXACT or exponent > 22 or exponent < -22:
        return 0.0, INEXACT
    m = float(mantissa)
    value = m * _POW10[exponent] if exponent >= 0 else m / _POW10[-exponent]
    return -value if negative else value, OK


@kernel
def parse_tokens(buf, start, n):
    """The first ``n`` tokens of buf[start:] (there are that many): values (n,) float64 and
    status (n,) int8 (OK, INEXACT or OTHER; the value is 0 unless OK)."""
    values = np.empty(n)
    status = np.empty(n, np.int8)
    i = start
    for k in range(n):
        while _blank(buf[i]):
            i += 1
        a = i
        while i < len(buf) and not _blank(buf[i]):
            i += 1
        values[k], status[k] = _number(buf, a, i)
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
