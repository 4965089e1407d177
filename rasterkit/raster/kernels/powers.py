"""Powers without library calls: ``log2``, ``exp2`` and ``x ** s`` as polynomials and bit
operations, so that a loop over pixels that raises to a power (a highlight's shininess)
compiles to vector instructions; the ``pow`` of the C library is one scalar call per pixel.

``log2`` agrees with the library to about 1e-9 absolute, ``exp2`` to 1e-8 relative (so
``x ** s`` to about ``1e-9 s`` relative: far below the 1/255 steps of a colour): ``log2`` from
``x = m 2^e`` with ``m`` in [sqrt(1/2), sqrt(2)), ``ln m = 2 atanh t`` (``t = (m - 1) / (m + 1)``,
``|t| < 0.172``) summed to ``t^9``; ``exp2`` from ``y = n + f`` with ``n`` the nearest integer,
``2^f = e^(f ln 2)`` summed to the 7th power (``|f ln 2| <= 0.35``; both by Estrin's scheme),
times ``2^n`` made from its bits. Integers go through int32 on the way to and from floats: AVX2 converts those four
at a time, not int64.
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.intrinsics import bits_float, float_bits
from rasterkit.runtime.jit import kernel

_SQRT2 = 1.4142135623730951
_INV_LN2 = 1.4426950408889634
_LN2 = 0.6931471805599453
_MANTISSA = 0xFFFFFFFFFFFFF
_ONE_BITS = 0x3FF0000000000000
#: exp2's range: 2^-1020 is far below anything an 8-bit colour shows, 2^1020 below overflow
_EXP_LIMIT = 1020.0


@kernel(inline="always")
def log2(x):
    """log2 of the finite ``x > 0`` (a normal float64; subnormals read as 2^-1022 or so)."""
    bits = float_bits(x)
    e = np.float64(np.int32((bits >> 52) - 1023))
    m = bits_float((bits & _MANTISSA) | _ONE_BITS)  # [1, 2)
    big = m > _SQRT2
    m = m * 0.5 if big else m  # noqa: FURB136 - selects, for the vectoriser
    e = e + 1.0 if big else e  # noqa: FURB136
    t = (m - 1.0) / (m + 1.0)
    t2 = t * t
    t4 = t2 * t2
    # sum of t2^j / (2j + 1), j = 0..4, by Estrin's scheme: short chains of dependent
    # operations, so that a loop of them is not held up by their latency
    series = (1.0 + t2 * (1.0 / 3.0)) + t4 * ((1.0 / 5.0 + t2 * (1.0 / 7.0)) + t4 * (1.0 / 9.0))
    return e + 2.0 * t * series * _INV_LN2


@kernel(inline="always")
def exp2(y):
    """2 ** ``y`` (``y`` clamped to [-1020, 1020]; NaN reads as -1020: the result is finite)."""
    y = y if y > -_EXP_LIMIT else -_EXP_LIMIT  # noqa: FURB136
    y = y if y < _EXP_LIMIT else _EXP_LIMIT  # noqa: FURB136
    n = np.floor(y + 0.5)
    z = (y - n) * _LN2  # |z| <= 0.35
    z2 = z * z
    z4 = z2 * z2
    # sum of z^k / k!, k = 0..7, by Estrin's scheme (see log2)
    term = ((1.0 + z) + z2 * (1.0 / 2.0 + z * (1.0 / 6.0))) \
        + z4 * ((1.0 / 24.0 + z * (1.0 / 120.0)) + z2 * (1.0 / 720.0 + z * (1.0 / 5040.0)))
    scale = bits_float(np.int64(np.int32(n) + 1023) << 52)
    return term * scale


@kernel(inline="always")
def power(x, s):
    """``x ** s`` for ``x >= 0`` and ``s >= 0`` (what Python gives: ``0 ** 0 == 1``,
    ``0 ** s == 0``), as :func:`exp2` of ``s log2 x``."""
    positive = x > 0.0
    value = exp2(s * log2(x if positive else 1.0))
    return value if positive else (1.0 if s == 0.0 else 0.0)
