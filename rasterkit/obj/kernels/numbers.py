"""Numba kernels that parse the numbers of OBJ ``v``, ``vt`` and ``vn`` statements.

Every value is the correctly rounded float64 of its text: the kernels round exactly where one
rounding suffices (Clinger's fast path) and flag the other tokens for the caller
(:mod:`rasterkit.obj.statements`) to convert again. A token that is not a plain decimal number
is flagged too: the caller reads NaN and infinity (``nan``, ``inf``, MSVC's ``1.#IND``...),
rare enough that compiling them here would cost every first run more than it saves, and
names the token when it is no number at all. The kernels never raise on bad input: they
return status codes.
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel
from rasterkit.obj.kernels.scan import MINUS, PLUS, ZERO, is_digit, next_token

# Status of one parsed number: read; to convert again exactly; not a plain decimal number
# (NaN, infinity or no number: the caller decides).
NUMBER_OK, NUMBER_INEXACT, NUMBER_OTHER = 0, 1, 2

# 10**k for k = 0..22: every one is exact in float64, so m * 10**k and m / 10**k round once.
_POW10 = np.array([10.0**k for k in range(23)])
_EXACT_MANTISSA = 1 << 53

_DOT = 46

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
    point).

    Returns
    -------
    value : float
    status : int
        NUMBER_OK; NUMBER_INEXACT when the value may be off by one unit in the last place
        (more than 15 significant digits or an exponent beyond +-22: the caller re-parses
        those tokens exactly); NUMBER_OTHER when the token is not a plain decimal number.
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
        return 0.0, NUMBER_OTHER
    if i < b and buf[i] | 32 == 101:  # e or E
        e, i, ok = _parse_exponent(buf, i + 1, b)
        if not ok:
            return 0.0, NUMBER_OTHER
        exponent += e
    if i != b:
        return 0.0, NUMBER_OTHER
    value, exact = _scale(mantissa, exponent)
    return sign * value, NUMBER_OK if exact and not truncated else NUMBER_INEXACT


@kernel
def parse_number_rows(buf, starts, ends, width):
    """Parse the numbers of statements (v, vt, vn lines) into rows.

    Parameters
    ----------
    buf : (B,) uint8
    starts, ends : (S,) int64
        Statement ranges from :func:`~rasterkit.obj.kernels.scan.scan_statements`.
    width : int
        Numbers kept per row; further tokens are still checked.

    Returns
    -------
    values : (S, width) float64
        Parsed numbers; NaN where a statement has fewer tokens.
    status : (S,) int8
        Worst NUMBER_* status of the statement's tokens (NUMBER_OTHER: the caller reads
        the statement's tokens itself; its values here are incomplete).
    inexact : (S,) int64
        Bit k set when token k (k < width) is NUMBER_INEXACT.
    """
    rows = len(starts)
    # np.empty and loops: np.full and np.zeros compile an implementation each (~0.2 s)
    values = np.empty((rows, width))
    status = np.empty(rows, np.int8)
    inexact = np.empty(rows, np.int64)
    for r in range(rows):
        for k in range(width):
            values[r, k] = np.nan
        status[r] = NUMBER_OK
        inexact[r] = 0
        i = next_token(buf, starts[r], ends[r])[1]  # after the keyword
        k = 0
        while i < ends[r]:
            a, i = next_token(buf, i, ends[r])
            value, s = _parse_number(buf, a, i)
            if s == NUMBER_OTHER:
                status[r] = NUMBER_OTHER
                break
            if k < width:
                values[r, k] = value
                if s == NUMBER_INEXACT:
                    inexact[r] |= np.int64(1) << k
                    status[r] = NUMBER_INEXACT
            k += 1
    return values, status, inexact
