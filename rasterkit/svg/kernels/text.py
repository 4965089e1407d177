"""Path data of an SVG as bytes: ``M x y L x y x y ... [Z]``, numbers in hundredths of a pixel.

Formatting a million coordinates with Python's ``format`` takes about half a second; this
writes them straight into a byte buffer, trailing zeros of the fraction left out
(``12.5``, ``7``, ``0.05``).
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel

#: Bytes one point may take at most: two numbers of up to 19 digits, a sign, a point and
#: two decimals each, a separator and a command letter.
POINT_BYTES = 2 * 24 + 2


@kernel(inline="always")
def _number(buf, at, value):
    """Write the integer ``value`` (hundredths) as a decimal number at ``buf[at]``; returns
    the position after it."""
    if value < 0:
        buf[at] = 45  # '-'
        at += 1
        value = -value
    whole, frac = value // 100, value % 100
    start = at
    while True:
        buf[at] = 48 + whole % 10
        at += 1
        whole //= 10
        if whole == 0:
            break
    i, j = start, at - 1
    while i < j:  # the digits came lowest first
        buf[i], buf[j] = buf[j], buf[i]
        i += 1
        j -= 1
    if frac:
        buf[at] = 46  # '.'
        buf[at + 1] = 48 + frac // 10
        at += 2
        if frac % 10:
            buf[at] = 48 + frac % 10
            at += 1
    return at


@kernel
def path_data(hundredths, offsets, closed, buf):
    """Write the path data of every polyline into ``buf`` (uint8, at least
    ``POINT_BYTES`` per point); returns ``ends`` (Q + 1,) int64: polyline q is
    ``buf[ends[q]:ends[q + 1]]``.

    ``hundredths`` (K, 2) int64: points in hundredths of a pixel; ``offsets`` (Q + 1,)
    int64; ``closed`` (Q,) uint8: 1 to end with ``Z`` instead of the last point (which
    repeats the first).
    """
    q = offsets.shape[0] - 1
    ends = np.empty(q + 1, np.int64)
    at = 0
    ends[0] = 0
    for line in range(q):
        first, last = offsets[line], offsets[line + 1]
        if closed[line]:
            last -= 1
        for k in range(first, last):
            if k == first:
                buf[at] = 77  # 'M'
                at += 1
            elif k == first + 1:
                buf[at] = 76  # 'L'
                at += 1
            else:
                buf[at] = 32
                at += 1
            at = _number(buf, at, hundredths[k, 0])
            buf[at] = 32
            at += 1
            at = _number(buf, at, hundredths[k, 1])
        if closed[line]:
            buf[at] = 90  # 'Z'
            at += 1
        ends[line + 1] = at
    return ends
