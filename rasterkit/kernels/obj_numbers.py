"""Numba kernels that parse the numbers of OBJ ``v``, ``vt`` and ``vn`` statements.

Every value is the correctly rounded float64 of its text: the kernels round exactly where one
rounding suffices (Clinger's fast path) and flag the other tokens for the caller
(:mod:`rasterkit._obj_statements`) to convert again. They never raise on bad input: they return
status codes, so the caller can name the first bad line of the file.
"""

from __future__ import annotations

import numpy as np

from rasterkit._jit import kernel
from rasterkit.kernels.obj_scan import MINUS, PLUS, ZERO, is_digit, next_token

# Status of one parsed number.
NUMBER_OK, NUMBER_INEXACT, NUMBER_MALFORMED = 0, 1, 2

# 10**k for k = 0..22: every one is exact in float64, so m * 10**k and m / 10**k round once.
_POW10 = np.array([10.0**k for k in range(23)])
_EXACT_MANTISSA = 1 << 53

_DOT = 46

_NAN = np.frombuffer(b"nan", np.uint8)
_INF = np.frombuffer(b"inf", np.uint8)
_INFINITY = np.frombuffer(b"infinity", np.uint8)
_MSVC_NAN = (np.frombuffer(b"#ind", np.uint8), np.frombuffer(b"#qnan", np.uint8),
             np.frombuffer(b"#snan", np.uint8))
_MSVC_INF = np.frombuffer(b"#inf", np.uint8)


@kernel
def _is_word(buf, a, b, word):
    """True when buf[a:b] is word (lower-case ASCII), in any case."""
    if b - a != len(word):
        return False
    for k in range(len(word)):
        if buf[a + k] | 32 != word[k]:
            return False
    return True


@kernel
def _parse_special(buf, a, b):
    """NaN or infinity spelled ``nan``, ``inf``, ``infinity`` (any case, optional sign) or as
    MSVC prints them (``1.#IND``, ``-1.#INF``, ``1.#QNAN``, ``1.#SNAN``): (value, ok)."""
    sign = 1.0
    if buf[a] == PLUS or buf[a] == MINUS:
        sign = -1.0 if buf[a] == MINUS else 1.0
        a += 1
    if _is_word(buf, a, b, _NAN):
        return np.nan, True
    if _is_word(buf, a, b, _INF) or _is_word(buf, a, b, _INFINITY):
        return sign * np.inf, True
    i = a
    while i < b and is_digit(buf[i]):
        i += 1
    if i == a or i + 1 >= b or buf[i] != _DOT:
        return 0.0, False
    for word in _MSVC_NAN:
        if _is_word(buf, i + 1, b, word):
            return np.nan, True
    if _is_word(buf, i + 1, b, _MSVC_INF):
        return sign * np.inf, True
    return 0.0, False


@kernel(inline="always")
def _scale(mantissa, exponent):
    """mantissa * 10**exponent, and whether that result is correctly rounded.

    Exact operands make one rounding (Clinger's fast path). The jit's fast-math set allows
    LLVM to replace a division by a reciprocal multiplication, which would break that;
    test_any_decimal_text_reads_as_pythons_float checks it does not happen here.
    """
    if mantissa == 0:
        return 0.0, True
    m = float(mantissa)
    if mantissa < _EXACT_MANTISSA and -22 <= exponent <= 22:
        if exponent >= 0:
            return m * _POW10[exponent], True
        return m / _POW10[-exponent], True
    return m * 10.0 ** max(min(exponent, 400), -400), False


@kernel
def _parse_exponent(buf, i, b):
    """The exponent digits ``[+-]digits`` of a number at buf[i:b]: (value, end, ok). Values
    are capped at 100000, far beyond where every double is 0 or infinite."""
    sign = 1
    if i < b and (buf[i] == PLUS or buf[i] == MINUS):
        sign = -1 if buf[i] == MINUS else 1
        i += 1
    start = i
    e = 0
    while i < b and is_digit(buf[i]):
        e = min(e * 10 + (buf[i] - ZERO), 100000)
        i += 1
    return sign * e, i, i > start


@kernel
def _parse_number(buf, a, b):
    """Parse the number token buf[a:b].

    Accepts ``[+-]digits[.digits][(e|E)[+-]digits]`` (digits on at least one side of the
    point), and NaN and infinity as :func:`_parse_special` spells them.

    Returns
    -------
    value : float
    status : int
        NUMBER_OK; NUMBER_INEXACT when the value may be off by one unit in the last place
        (more than 15 significant digits or an exponent beyond +-22: the caller re-parses
        those tokens exactly); NUMBER_MALFORMED when the token is not a number.
    """
    i = a
    sign = 1.0
    if buf[i] == PLUS or buf[i] == MINUS:
        sign = -1.0 if buf[i] == MINUS else 1.0
        i += 1
    # The digits make an integer mantissa of at most 19 significant digits (leading zeros are
    # skipped, later digits only scale it); each digit after the point lowers the exponent.
    mantissa = np.uint64(0)
    digits = 0
    exponent = 0
    truncated = False
    first = i
    point = False
    while i < b and (is_digit(buf[i]) or (buf[i] == _DOT and not point)):
        if buf[i] == _DOT:
            point = True
        elif digits < 19:
            if mantissa > 0 or buf[i] > ZERO:
                mantissa = mantissa * np.uint64(10) + np.uint64(buf[i] - ZERO)
                digits += 1
            exponent -= 1 if point else 0
        else:
            exponent += 0 if point else 1
            truncated = truncated or buf[i] > ZERO
        i += 1
    if i - first == (1 if point else 0):  # no digit at all
        value, ok = _parse_special(buf, a, b)
        return value, NUMBER_OK if ok else NUMBER_MALFORMED
    if i < b and buf[i] | 32 == 101:  # e or E
        e, i, ok = _parse_exponent(buf, i + 1, b)
        if not ok:
            return 0.0, NUMBER_MALFORMED
        exponent += e
    if i != b:
        value, ok = _parse_special(buf, a, b)
        return value, NUMBER_OK if ok else NUMBER_MALFORMED
    value, exact = _scale(mantissa, exponent)
    return sign * value, NUMBER_OK if exact and not truncated else NUMBER_INEXACT


@kernel
def parse_number_rows(buf, starts, ends, width):
    """Parse the numbers of statements (v, vt, vn lines) into rows.

    Parameters
    ----------
    buf : (B,) uint8
    starts, ends : (S,) int64
        Statement ranges from :func:`~rasterkit.kernels.obj_scan.scan_statements`.
    width : int
        Numbers kept per row; further tokens are still checked.

    Returns
    -------
    values : (S, width) float64
        Parsed numbers; NaN where a statement has fewer tokens.
    status : (S,) int8
        Worst NUMBER_* status of the statement's tokens.
    bad_token : (S,) int64
        0-based index of the first malformed token, or -1.
    inexact : (S,) int64
        Bit k set when token k (k < width) is NUMBER_INEXACT.
    """
    rows = len(starts)
    # np.empty and loops: np.full and np.zeros compile an implementation each (~0.2 s)
    values = np.empty((rows, width))
    status = np.empty(rows, np.int8)
    bad_token = np.empty(rows, np.int64)
    inexact = np.empty(rows, np.int64)
    for r in range(rows):
        for k in range(width):
            values[r, k] = np.nan
        status[r] = NUMBER_OK
        bad_token[r] = -1
        inexact[r] = 0
        i = next_token(buf, starts[r], ends[r])[1]  # after the keyword
        k = 0
        while i < ends[r]:
            a, i = next_token(buf, i, ends[r])
            value, s = _parse_number(buf, a, i)
            if s == NUMBER_MALFORMED:
                status[r] = NUMBER_MALFORMED
                bad_token[r] = k
                break
            if k < width:
                values[r, k] = value
                if s == NUMBER_INEXACT:
                    inexact[r] |= np.int64(1) << k
                    status[r] = NUMBER_INEXACT
            k += 1
    return values, status, bad_token, inexact
