"""Numba kernels that read a decimal number from the bytes of a text file, for the readers'
own kernels (OBJ ``v`` lines, ASCII STL facets).

Every value they give as :data:`NUMBER_OK` is the correctly rounded float64 of its text: they
round exactly where one rounding suffices (Clinger's fast path: at most 15 significant digits
and a power of ten up to 22) and flag the other tokens :data:`NUMBER_INEXACT` for the caller
to convert again (Python's or NumPy's conversion of the few tokens). A token that is not a
plain decimal number is :data:`NUMBER_OTHER`: the caller reads NaN and infinity (``nan``,
``inf``...), rare enough that compiling them here would cost every first run more than it
saves, and names the token when it is no number at all. The kernels never raise on bad input:
they return status codes.

A kernel that calls :func:`parse_decimal` needs IEEE division (no ``arcp``: a division by a
reciprocal would round twice), as the jit policy's fast-math set gives it where it is called
(``test_any_decimal_text_reads_as_pythons_float``) and ``kernel(fastmath=False)`` everywhere.
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel

__all__ = ["NUMBER_INEXACT", "NUMBER_OK", "NUMBER_OTHER", "parse_decimal"]

PLUS, MINUS, ZERO, _NINE = 43, 45, 48, 57


@kernel(inline="always")
def _is_digit(c):
    return ZERO <= c <= _NINE


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
    while i < b and _is_digit(buf[i]):
        e = min(e * 10 + (buf[i] - ZERO), 100000)
        i += 1
    return sign * e, i, i > start


@kernel
def parse_decimal(buf, a, b):
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
    while i < b and (_is_digit(buf[i]) or (buf[i] == _DOT and not point)):
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
