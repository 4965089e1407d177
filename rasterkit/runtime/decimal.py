"""Numba kernels that read a decimal number from the bytes of a text file, for the readers'
own kernels (OBJ ``v`` lines, ASCII STL facets).

Every value :func:`parse_decimal` gives as :data:`NUMBER_OK` is the correctly rounded float64
of its text: exact where one rounding suffices (Clinger's fast path: at most 15 significant
digits and a power of ten up to 22); it flags the other tokens :data:`NUMBER_INEXACT` for the
caller to convert again. :func:`exact_decimals` is that second conversion for the tokens of up
to 19 significant digits, in a kernel of its own (compiled only when a file needs it): the
Eisel-Lemire algorithm (Daniel Lemire, "Number Parsing at a Gigabyte per Second", 2021,
sections 5-6, as Rust's ``dec2flt`` implements it: the 128-bit product of the digits and a
truncated power of five, which is exact or says it is not). What neither can round for sure
(more than 19 significant digits, or the rare product too close to a halfway point) is left to
Python's or NumPy's conversion of the few tokens. A token that is not a plain decimal number is
:data:`NUMBER_OTHER`: the caller reads NaN and infinity (``nan``, ``inf``...), rare enough that
compiling them here would cost every first run more than it saves, and names the token when it
is no number at all. The kernels never raise on bad input: they return status codes.

A kernel that calls :func:`parse_decimal` needs IEEE division (no ``arcp``: a division by a
reciprocal would round twice), as the jit policy's fast-math set gives it where it is called
(``test_any_decimal_text_reads_as_pythons_float``) and ``kernel(fastmath=False)`` everywhere.
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.intrinsics import bits_float
from rasterkit.runtime.jit import kernel

__all__ = ["NUMBER_INEXACT", "NUMBER_OK", "NUMBER_OTHER", "exact_decimals", "parse_decimal", "read_decimal"]

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


def _powers_of_five() -> np.ndarray:
    """(651, 2) uint64: 5**q for q = -342..308 as 128 bits (high word, low word) with the top
    bit set, truncated (rounded up for negative q), as fast_float's table generator makes them."""
    table = np.empty((651, 2), np.uint64)
    for q in range(-342, 309):
        p = 5 ** abs(q)
        if q < 0:
            z = p.bit_length()
            c = 2 ** (z + 127) // p + 1 if q >= -27 else 2 ** (2 * z + 128) // p + 1
        else:
            c = p
        c = c << max(128 - c.bit_length(), 0) >> max(c.bit_length() - 128, 0)
        table[q + 342] = (c >> 64, c & (2**64 - 1))
    return table


_POW5 = _powers_of_five()
_LOW32 = np.uint64(0xFFFFFFFF)
_ALL = np.uint64(0xFFFFFFFFFFFFFFFF)
_ONE = np.uint64(1)
_TOP = np.uint64(1 << 63)
_INF_BITS = 0x7FF << 52


@kernel
def _multiply(a, b):
    """The 128-bit product of uint64 a and b: (high word, low word)."""
    a0, a1, b0, b1 = a & _LOW32, a >> np.uint64(32), b & _LOW32, b >> np.uint64(32)
    p00, p01, p10 = a0 * b0, a0 * b1, a1 * b0
    middle = (p00 >> np.uint64(32)) + (p01 & _LOW32) + (p10 & _LOW32)
    high = a1 * b1 + (p01 >> np.uint64(32)) + (p10 >> np.uint64(32)) + (middle >> np.uint64(32))
    return high, (middle << np.uint64(32)) | (p00 & _LOW32)


@kernel(inline="always")
def _eisel_lemire(w, q):
    """The bits (int64) of the float64 nearest to w * 10**q (w: uint64, 1 to 19 digits), and
    whether they are sure (False: the product was too close to call)."""
    if q < -342 or w == 0:
        return 0, True
    if q > 308:
        return _INF_BITS, True
    lz = 0
    while w < _TOP:  # normalise: the top bit set
        w <<= _ONE
        lz += 1
    high, low = _multiply(w, _POW5[q + 342, 0])
    if high & np.uint64(0x1FF) == np.uint64(0x1FF):  # 9 bits below the 55 kept: the low word may carry
        second, _ = _multiply(w, _POW5[q + 342, 1])
        low += second
        if second > low:
            high += _ONE
    if low == _ALL and not -27 <= q <= 55:
        return 0, False
    upper = np.int64(high >> np.uint64(63))
    shift = np.uint64(upper + 9)
    mantissa = high >> shift
    power2 = ((q * 217706) >> 16) + 63 + upper - lz + 1023
    if power2 <= 0:  # subnormal
        if -power2 + 1 >= 64:
            return 0, True
        mantissa >>= np.uint64(-power2 + 1)
        mantissa += mantissa & _ONE
        mantissa >>= _ONE
        return np.int64(mantissa), True  # a carry into bit 52 makes it the smallest normal
    if low <= _ONE and -4 <= q <= 23 and mantissa & np.uint64(3) == _ONE and (mantissa << shift) == high:
        mantissa &= ~_ONE  # exactly halfway: round to even, down
    mantissa += mantissa & _ONE
    mantissa >>= _ONE
    if mantissa >= (_ONE << np.uint64(53)):
        mantissa = _ONE << np.uint64(52)
        power2 += 1
    if power2 >= 0x7FF:
        return _INF_BITS, True
    return (power2 << 52) | np.int64(mantissa & ~(_ONE << np.uint64(52))), True


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


@kernel(inline="always")
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


@kernel(inline="always")
def _prefix(buf, a, b):
    """The parts of the plain decimal number at the start of buf[a:b],
    ``[+-]digits[.digits][(e|E)[+-]digits]`` (digits on at least one side of the point):
    ``(sign, mantissa, exponent, truncated, ok, end)``, the number being
    ``sign * mantissa * 10**exponent``; ``mantissa`` holds its first 19 significant digits
    (leading zeros are skipped, later digits only scale it), ``truncated`` says a later one is
    not zero; ``ok`` False when it starts no plain decimal; ``end`` where it ends (only
    digits, ``.``, ``e``, ``E`` and signs are read)."""
    i = a
    sign = 1.0
    if buf[i] == PLUS or buf[i] == MINUS:
        sign = -1.0 if buf[i] == MINUS else 1.0
        i += 1
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
        return sign, mantissa, exponent, truncated, False, i
    if i < b and buf[i] | 32 == 101:  # e or E
        e, i, ok = _parse_exponent(buf, i + 1, b)
        if not ok:
            return sign, mantissa, exponent, truncated, False, i
        exponent += e
    return sign, mantissa, exponent, truncated, True, i


@kernel(inline="always")
def _parts(buf, a, b):
    """:func:`_prefix` of the whole of buf[a:b]: ``(sign, mantissa, exponent, truncated,
    ok)``, ok False when buf[a:b] is no plain decimal number."""
    sign, mantissa, exponent, truncated, ok, end = _prefix(buf, a, b)
    return sign, mantissa, exponent, truncated, ok and end == b


@kernel(inline="always")
def read_decimal(buf, a, hi):
    """The number at the start of buf[a:hi], for a reader's loop over many number tokens
    (inlined into the caller: no call per number, and in a kernel without reference
    counting no atomic reference count update): ``(value, status, end)``, ``end`` where the
    number's characters (digits, ``.``, ``e``, ``E``, signs) end. ``value, status`` are
    :func:`parse_decimal`'s of buf[a:end], so they are those of a token buf[a:b] when
    end == b (the caller checks that the token ends there: else it is NUMBER_OTHER)."""
    sign, mantissa, exponent, truncated, ok, end = _prefix(buf, a, hi)
    if not ok:
        return 0.0, NUMBER_OTHER, end
    value, exact = _scale(mantissa, exponent)
    return sign * value, NUMBER_OK if exact and not truncated else NUMBER_INEXACT, end


@kernel
def parse_decimal(buf, a, b):
    """Parse the number token buf[a:b] (see :func:`_parts` for the syntax).

    Returns
    -------
    value : float
    status : int
        NUMBER_OK; NUMBER_INEXACT when the value may be off by one unit in the last place
        (more than 15 significant digits or an exponent beyond +-22: the caller converts those
        tokens again, exactly); NUMBER_OTHER when the token is not a plain decimal number.
    """
    sign, mantissa, exponent, truncated, ok = _parts(buf, a, b)
    if not ok:
        return 0.0, NUMBER_OTHER
    value, exact = _scale(mantissa, exponent)
    return sign * value, NUMBER_OK if exact and not truncated else NUMBER_INEXACT


@kernel(fastmath=False)
def exact_decimals(buf, starts, ends, out):
    """Convert the number tokens ``buf[starts[k]:ends[k]]`` exactly where this can be sure:
    ``out[k]`` the correctly rounded float64 of plain decimals of up to 19 significant digits
    (Clinger's fast path, else Eisel-Lemire); returns (K,) bool, which ``out[k]`` are so (the
    others are for the caller to convert: more digits, ``nan``, ``inf``, no number)."""
    sure = np.zeros(len(starts), np.bool_)
    for k in range(len(starts)):
        sign, mantissa, exponent, truncated, ok = _parts(buf, starts[k], ends[k])
        if not ok or truncated:
            continue
        value, exact = _scale(mantissa, exponent)
        if not exact:
            bits, exact = _eisel_lemire(mantissa, exponent)
            value = bits_float(bits)
        out[k] = sign * value
        sure[k] = exact
    return sure
