"""Line rasterization: the pixels of integer lines, and stepping them into a buffer.

Integer lines
-------------
A line between the integer pixels (x0, y0) and (x1, y1) is stepped along its *major* axis
``u`` (the axis with the larger extent; x when |dx| == |dy|), one pixel per step, so it has
``n + 1 = max(|dx|, |dy|) + 1`` pixels. At step ``t`` the ideal *minor* coordinate is
``v0 + dv * t / n`` and the pixel takes that value **rounded half up**: when the ideal line
passes exactly half-way between two pixels, the one with the larger minor coordinate wins
(+y, i.e. downwards, for x-major lines; +x for y-major lines). The rule depends only on the
ideal line, never on the drawing direction, so a reversed line has the same pixel set and a
transposed line (x <-> y) has the transposed pixel set.

Bresenham's midpoint algorithm keeps exactly this rounding in integers. With ``a = |dv|`` and
``c = 0 if dv > 0 else 1`` (the tie rule), let ``N(t) = 2 a t + n - c``. The number of minor
steps taken before step ``t`` is ``k(t) = N(t) // (2 n)`` and the error term is
``r(t) = N(t) % (2 n)``: each step adds ``2 a`` to ``r`` and takes a minor step when ``r``
reaches ``2 n``. Both are closed-form, so a clipped line can start at any step and still
produce exactly the pixels of the unclipped line.

Stepping
--------
:func:`step_line` and :func:`step_mask` write a line's pixels into a flattened colour or
one-byte mask buffer with the same error term, branch-free; :func:`put_pixel` and
:func:`blend_pixel` write or blend one pixel. The edge kernels
(:mod:`rasterkit.raster.kernels.edges`) use them.
"""

from __future__ import annotations

import math

import numpy as np

from rasterkit.runtime.jit import kernel

METHOD_BRESENHAM = 0
METHOD_DDA = 1
METHOD_NAIVE = 2


@kernel(inline="always")
def tie_offset(dv):
    """``c`` of the module docstring: ties step towards +v, i.e. only when ``dv > 0``."""
    return 0 if dv > 0 else 1


@kernel(inline="always")
def minor_steps(t, n, a, c):
    """Minor steps ``k(t)`` taken before major step ``t`` and the error term ``r(t)``."""
    if a == 0:
        return 0, 0
    if t == 0:
        # The usual unclipped start, without a (slow) 64-bit division.
        return 0, n - c
    numerator = 2 * a * t + n - c
    k = numerator // (2 * n)
    return k, numerator - 2 * n * k


@kernel(inline="always")
def step_range(u0, v0, n, a, sv, c, ulo, uhi, vlo, vhi):
    """Major steps ``t`` in ``[0, n]`` whose pixel lies in ``[ulo, uhi] x [vlo, vhi]``.

    The pixel at step ``t`` is ``(u0 + t, v0 + sv * k(t))``. ``k`` is non-decreasing, so the
    steps inside the box form one interval, found by inverting ``k`` in closed form.
    Returns ``(tlo, thi)``; the interval is empty when ``tlo > thi``.
    """
    tlo = max(0, ulo - u0)
    thi = min(n, uhi - u0)
    if sv > 0:
        kmin, kmax = vlo - v0, vhi - v0
    else:
        kmin, kmax = v0 - vhi, v0 - vlo
    if a == 0:
        if kmin > 0 or kmax < 0:
            return 1, 0
        return tlo, thi
    # k(t) >= kmin  <=>  2 a t >= 2 n kmin - n + c   (ceiling division)
    if kmin > 0:
        tlo = max(tlo, -((n - c - 2 * n * kmin) // (2 * a)))
    # k(t) <= kmax  <=>  2 a t <= 2 n (kmax + 1) - n + c - 1
    if kmax < a:
        thi = min(thi, (2 * n * (kmax + 1) - n + c - 1) // (2 * a))
    return tlo, thi


@kernel
def _minor_bresenham(u0, v0, n, dv, out):
    """Bresenham: minor coordinates of steps 0..n into ``out``, integer arithmetic only."""
    a = abs(dv)
    sv = 1 if dv >= 0 else -1
    k, r = minor_steps(0, n, a, tie_offset(dv))
    v = v0 + sv * k
    for t in range(n + 1):
        out[t] = v
        r += 2 * a
        if r >= 2 * n:
            r -= 2 * n
            v += sv


@kernel(fastmath=False)
def _minor_dda(u0, v0, n, dv, out):
    """DDA: the minor coordinate grows by the slope ``m`` per major step, rounded half up
    (IEEE arithmetic as written: the running sum's rounding is what DDA is)."""
    m = dv / n if n > 0 else 0.0
    v = float(v0)
    for t in range(n + 1):
        out[t] = math.floor(v + 0.5)
        v += m


@kernel
def _minor_naive(u0, v0, n, dv, out):
    """Brute force: ``v = m u + b`` evaluated at every major coordinate, rounded half up."""
    m = dv / n if n > 0 else 0.0
    b = v0 - m * u0
    for t in range(n + 1):
        out[t] = math.floor(m * (u0 + t) + b + 0.5)


@kernel
def line_pixels(x0, y0, x1, y1, method):
    """Pixels of the line from (x0, y0) to (x1, y1), endpoints included.

    Parameters
    ----------
    x0, y0, x1, y1 : int
        Endpoint pixels, raster space. ``|coordinate| <= 2**29`` keeps the integer error
        terms inside int64 (the caller checks).
    method : int
        ``METHOD_BRESENHAM``, ``METHOD_DDA`` or ``METHOD_NAIVE``.

    Returns
    -------
    (max(|dx|, |dy|) + 1, 2) int64
        ``(x, y)`` pixels in drawing order from (x0, y0) to (x1, y1).

    Every method steps from the endpoint with the smaller major coordinate and the output is
    reversed afterwards, so reversing a line never changes its pixel set, even for the
    floating-point methods.
    """
    steep = abs(y1 - y0) > abs(x1 - x0)
    major, minor = (1, 0) if steep else (0, 1)
    u0, v0, u1, v1 = (y0, x0, y1, x1) if steep else (x0, y0, x1, y1)
    reverse = u1 < u0
    if reverse:
        u0, v0, u1, v1 = u1, v1, u0, v0
    n = u1 - u0
    v = np.empty(n + 1, dtype=np.int64)
    if method == METHOD_BRESENHAM:
        _minor_bresenham(u0, v0, n, v1 - v0, v)
    elif method == METHOD_DDA:
        _minor_dda(u0, v0, n, v1 - v0, v)
    else:
        _minor_naive(u0, v0, n, v1 - v0, v)
    out = np.empty((n + 1, 2), dtype=np.int64)
    for t in range(n + 1):
        out[t, major] = u0 + t
        out[t, minor] = v[t]
    if reverse:
        return out[::-1].copy()
    return out


@kernel(inline="always")
def put_pixel(cflat, pix, channels, rgba):
    base = pix * channels
    for ch in range(channels):
        cflat[base + ch] = rgba[ch]


@kernel(inline="always")
def blend_pixel(cflat, pix, channels, rgba, weight):
    """Blend ``rgba`` into pixel ``pix`` with coverage ``weight`` in [0, 1], rounding."""
    base = pix * channels
    for ch in range(channels):
        old = np.float64(cflat[base + ch])
        cflat[base + ch] = np.uint8(old + (np.float64(rgba[ch]) - old) * weight + 0.5)


@kernel(inline="always")
def _short_steps(cflat, value, pix, count, r, two_a, two_n, ustride, vstride, slots):
    """:func:`step_line` into a one-byte-per-pixel buffer for a line of ``count <= slots``
    pixels: exactly ``slots`` steps (a constant, so LLVM unrolls them), the ones past the
    line's end marking its last pixel again (harmless), so that no loop exit is mispredicted.
    Most edges of a fine mesh are 1 to 8 pixels long; this halves their cost."""
    for k in range(slots):
        cflat[pix] = value
        r += two_a
        step = r >= two_n
        r -= two_n if step else 0
        pix += np.int64(k + 1 < count) * (ustride + (vstride if step else 0))


@kernel(inline="always")
def step_line(cflat, channels, rgba, pix, count, r, two_a, two_n, ustride, vstride):
    """The Bresenham loop without a depth test: ``count`` pixels from pixel index ``pix``,
    ``ustride`` pixels per major step, ``vstride`` more on a minor step. The minor step is
    taken branch-free (a branch would be mispredicted on about every other pixel of a
    diagonal line), and an RGB buffer gets three byte stores per pixel, no channel loop.
    A one-byte mask takes :func:`step_mask`."""
    if channels == 3:
        byte, ubytes, vbytes = 3 * pix, 3 * ustride, 3 * vstride
        red, green, blue = rgba[0], rgba[1], rgba[2]
        for _ in range(count):
            cflat[byte] = red
            cflat[byte + 1] = green
            cflat[byte + 2] = blue
            r += two_a
            step = r >= two_n
            r -= two_n if step else 0
            byte += ubytes + (vbytes if step else 0)
        return
    for _ in range(count):
        put_pixel(cflat, pix, channels, rgba)
        r += two_a
        step = r >= two_n
        r -= two_n if step else 0
        pix += ustride + (vstride if step else 0)


@kernel(inline="always")
def step_mask(mask, value, pix, count, r, two_a, two_n, ustride, vstride):
    """:func:`step_line` into a one-byte-per-pixel buffer (a band's mask): ``value`` into
    each pixel; lines of up to 4 and 8 pixels by :func:`_short_steps`."""
    if count <= 4:
        _short_steps(mask, value, pix, count, r, two_a, two_n, ustride, vstride, 4)
    elif count <= 8:
        _short_steps(mask, value, pix, count, r, two_a, two_n, ustride, vstride, 8)
    else:
        for _ in range(count):
            mask[pix] = value
            r += two_a
            step = r >= two_n
            r -= two_n if step else 0
            pix += ustride + (vstride if step else 0)
