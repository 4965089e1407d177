"""Line rasterization kernels: single integer lines and framebuffer edges.

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

Framebuffer edges
-----------------
:func:`draw_edges` draws many edges given in homogeneous raster space (see
``ARCHITECTURE.md``). Per vertex, once: classify it and, when it is inside the visible
region, divide by ``w``. Per edge whose ends are not both inside: drop non-finite input;
clip before the divide against the near plane ``zh >= 0``, the far plane ``zh <= w`` and a
guard band of ``+-GUARD_BAND`` pixels (Liang-Barsky from a point inside, found by bisection
when both ends are far away, so that even ends at 1e300 clip accurately); divide by ``w``.
Per band of image rows: round the endpoints down to their pixels, find in closed form the
Bresenham steps inside the band and step only those, so a segment costs its visible pixels
however long it is (clipping a segment again in every band it crosses). Each thread owns a
band of rows, so no two threads write the same pixel, and since every per-pixel value is computed in
closed form the image does not depend on the number of bands or threads.

Plain edges (a wireframe: no depth test, no anti-aliasing) whose ends are both inside the
image take a faster road to the same pixels. The vertex pass also records each such
vertex's pixel; :func:`plain_setup` turns every edge into a 12-byte record (first pixel,
packed ``n``, ``a`` and direction bits, rows spanned) with branch-free arithmetic that
vectorises; :func:`record_work` counts pixels per row so the bands get equal work; each
band marks its edges' pixels in a byte mask, then clears its colour rows and paints the
marked pixels 8 at a time (:func:`_paint_marked`).
"""

from __future__ import annotations

import math

import numpy as np

from rasterkit._jit import kernel
from rasterkit.kernels.intrinsics import fetch_add
from rasterkit.kernels.clear import PATTERN_BYTES, background_pattern, fill_bytes

METHOD_BRESENHAM = 0
METHOD_DDA = 1
METHOD_NAIVE = 2

MODE_PLAIN = 0
MODE_DEPTH_TEST = 1
MODE_ANTIALIAS = 2

GUARD_BAND = 2.0**24 + 0.5
"""Half-size, in pixels, of the square ``[-G, G]^2`` that segments are clipped to before
their endpoints are rounded to integers. Large enough that a segment with both endpoints
inside it is drawn exactly as its unclipped integer line, small enough that the integer
error terms (about ``8 G^2``) fit easily in int64. Its edges run through pixel centres, so
the rounding error of a point clipped to them never changes the pixel the point falls in."""

MAX_COORDINATE = 1e300
"""Largest homogeneous coordinate magnitude accepted; beyond it (and for NaN or inf) an edge
is dropped, which keeps every product and difference of the clipping finite."""

# Each bisection halves a segment at most 2 * MAX_COORDINATE long; after about 2100 halvings
# floating point cannot split it further.
_MAX_BISECTIONS = 2200


# --- integer lines: closed-form Bresenham --------------------------------------------------


@kernel(inline="always")
def _tie_offset(dv):
    """``c`` of the module docstring: ties step towards +v, i.e. only when ``dv > 0``."""
    return 0 if dv > 0 else 1


@kernel(inline="always")
def _minor_steps(t, n, a, c):
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
def _step_range(u0, v0, n, a, sv, c, ulo, uhi, vlo, vhi):
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
    k, r = _minor_steps(0, n, a, _tie_offset(dv))
    v = v0 + sv * k
    for t in range(n + 1):
        out[t] = v
        r += 2 * a
        if r >= 2 * n:
            r -= 2 * n
            v += sv


@kernel
def _minor_dda(u0, v0, n, dv, out):
    """DDA: the minor coordinate grows by the slope ``m`` per major step, rounded half up."""
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


# --- framebuffer edges: per-edge setup --------------------------------------------------------


@kernel(inline="always")
def _plane_distances(v):
    """Signed distances (>= 0 inside) of homogeneous point ``v`` to the six clip planes.

    The visible region is ``0 <= zh <= w`` (near and far planes) and
    ``|xh|, |yh| <= GUARD_BAND * w``; it is convex and implies ``w >= 0``.
    """
    xh, yh, zh, w = v
    g = GUARD_BAND * w
    return (zh, w - zh, g + xh, g - xh, g + yh, g - yh)


@kernel(inline="always")
def _outcode(v):
    """Bit k set when ``v`` is outside clip plane k; 0 inside the visible region."""
    distances = _plane_distances(v)
    code = 0
    for k in range(6):
        if distances[k] < 0.0:
            code |= 1 << k
    return code


@kernel
def _inside_point(p, q):
    """Some point of the segment p-q inside the visible region, found by bisection.

    Returns ``(found, point)``. A point computed as ``p + t (q - p)`` carries an absolute
    error of about ``|p| * 2**-53`` (1e14 pixels when ``|p| = 1e30``); a midpoint
    ``(a + b) / 2`` is accurate relative to its own size instead. So when neither end is
    inside, halve the segment, keeping the half that is not trivially outside (both ends
    beyond one plane, the Sproull-Sutherland test), until an end falls inside or the whole
    segment is rejected. An end already inside, the usual case, costs one outcode.
    """
    a, b = p, q
    code_a, code_b = _outcode(a), _outcode(b)
    for _ in range(_MAX_BISECTIONS):
        if code_a == 0:
            return True, a
        if code_b == 0:
            return True, b
        if code_a & code_b:
            return False, a
        m = ((a[0] + b[0]) * 0.5, (a[1] + b[1]) * 0.5, (a[2] + b[2]) * 0.5, (a[3] + b[3]) * 0.5)
        code_m = _outcode(m)
        # A plane distance is linear, so m is outside a plane only if a or b is too.
        if code_m & code_a:
            a, code_a = m, code_m
        else:
            b, code_b = m, code_m
    return False, a


@kernel(inline="always")
def _exit_point(c, e):
    """The last point of segment c -> e inside the visible region, ``c`` being inside.

    Liang-Barsky from an inside point needs only the exits. ``e`` itself is returned
    bit-exact when it is inside; otherwise the point is ``c + t (e - c)``, accurate because
    ``c`` is not huge and ``t (e - c)`` is about the distance from ``c`` to the exit.
    """
    dc = _plane_distances(c)
    de = _plane_distances(e)
    t = 1.0
    for k in range(6):
        if de[k] < 0.0:
            t = min(t, dc[k] / (dc[k] - de[k]))
    if t == 1.0:
        return e
    return (c[0] + t * (e[0] - c[0]), c[1] + t * (e[1] - c[1]), c[2] + t * (e[2] - c[2]), c[3] + t * (e[3] - c[3]))


@kernel(inline="always")
def _clamp(value, lo, hi):
    return min(max(value, lo), hi)


@kernel
def _project_edge(p, q):
    """Clip a homogeneous segment to the visible region (see _plane_distances), then divide.

    ``p``, ``q`` are 4-tuples ``(xh, yh, zh, w)`` with magnitudes at most
    ``MAX_COORDINATE``. Clipping before the divide means the divide never sees ``w <= 0``
    and its results are bounded by the guard band. Returns
    ``(visible, x0, y0, z0, x1, y1, z1)`` in raster space; ``visible`` is False when
    nothing of the segment is left.
    """
    found, c = _inside_point(p, q)
    if not found:
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    xh0, yh0, zh0, w0 = _exit_point(c, p)
    xh1, yh1, zh1, w1 = _exit_point(c, q)
    if not (w0 > 0.0 and w1 > 0.0):
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    inv0 = 1.0 / w0
    inv1 = 1.0 / w1
    # The clamps only undo rounding at the guard band.
    x0 = _clamp(xh0 * inv0, -GUARD_BAND, GUARD_BAND)
    y0 = _clamp(yh0 * inv0, -GUARD_BAND, GUARD_BAND)
    x1 = _clamp(xh1 * inv1, -GUARD_BAND, GUARD_BAND)
    y1 = _clamp(yh1 * inv1, -GUARD_BAND, GUARD_BAND)
    return True, x0, y0, zh0 * inv0, x1, y1, zh1 * inv1


@kernel(inline="always")
def _all_usable(values):
    """Whether every float of the tuple ``values`` is finite and at most MAX_COORDINATE."""
    for value in values:
        if not abs(value) <= MAX_COORDINATE:
            return False
    return True


VERTEX_CHUNKS = 16
ROWS_PER_BIN = 8


@kernel
def project_vertices(slot, counter, clip, proj, pixels, width, height, counts):
    """Vertex pass of :func:`draw_edges`: divide every vertex that needs no clipping, once.

    ``proj[i]`` becomes ``(x, y, z, 1.0)`` (raster space, exactly as :func:`_project_edge`
    computes an end that is inside) for a vertex inside the visible region with ``w > 0``;
    ``(., ., ., 0.0)`` for a usable vertex outside it, whose edges are clipped one by one;
    ``(., ., ., -1.0)`` for a vertex with a NaN, infinite or too large coordinate, whose
    edges are dropped. A vertex is shared by several edges (three per vertex in a closed
    triangle mesh), so this saves most of the per-edge work.

    Unless ``pixels`` is empty, ``pixels[i]`` (int64) becomes the pixel of a projected
    vertex inside the ``width`` x ``height`` image, ``x | y << 32``, and -1 for every
    other vertex (what :func:`plain_setup` reads).

    ``counts`` (VERTEX_CHUNKS, n_bins) int64, zeros on entry, gets the number of projected
    vertices of each chunk in each ``ROWS_PER_BIN`` rows of an image ``height`` rows tall
    (``n_bins`` rows' worth), a cheap estimate of where the drawing work lies; it stays zero
    when ``pixels`` is given (the plain path balances its bands by :func:`record_work`, and
    the count cost a sixth of this pass).

    A worker of :func:`rasterkit._jit.run_parallel` (``slot`` unused, chunks claimed
    through ``counter``).
    """
    n = clip.shape[0]
    with_pixels = pixels.size > 0
    while True:  # claim the next piece until none is left
        ch = fetch_add(counter, 0, 1)
        if ch >= VERTEX_CHUNKS:
            break
        for i in range(n * ch // VERTEX_CHUNKS, n * (ch + 1) // VERTEX_CHUNKS):
            p = (clip[i, 0], clip[i, 1], clip[i, 2], clip[i, 3])
            pixel = -1
            if not _all_usable(p):
                proj[i, 3] = -1.0
            elif _outcode(p) != 0 or not p[3] > 0.0:
                proj[i, 3] = 0.0
            else:
                inv = 1.0 / p[3]
                x = _clamp(p[0] * inv, -GUARD_BAND, GUARD_BAND)
                y = _clamp(p[1] * inv, -GUARD_BAND, GUARD_BAND)
                proj[i, 0] = x
                proj[i, 1] = y
                proj[i, 2] = p[2] * inv
                proj[i, 3] = 1.0
                if 0.0 <= y < height:
                    if not with_pixels:
                        counts[ch, np.int64(y) // ROWS_PER_BIN] += 1
                    if 0.0 <= x < width:
                        pixel = np.int64(math.floor(x)) | (np.int64(math.floor(y)) << 32)
            if with_pixels:
                pixels[i] = pixel


@kernel
def balanced_bands(counts, n_bands, height):
    """Row boundaries ``(n_bands + 1,)`` splitting ``height`` rows into bands holding about
    equal shares of ``counts`` (per ``ROWS_PER_BIN`` rows; equal row counts when all are
    zero). Band ``b`` is rows ``[bounds[b], bounds[b + 1])``, possibly empty."""
    bounds = np.empty(n_bands + 1, np.int64)
    total = 0
    for c in counts:
        total += c
    bounds[0] = 0
    acc = 0
    bin_ = 0
    for b in range(1, n_bands):
        if total == 0:
            bounds[b] = b * height // n_bands
            continue
        goal = total * b // n_bands
        while bin_ < counts.size and acc + counts[bin_] <= goal:
            acc += counts[bin_]
            bin_ += 1
        bounds[b] = min(max(bin_ * ROWS_PER_BIN, bounds[b - 1]), height)
    bounds[n_bands] = height
    return bounds


@kernel(inline="always")
def _edge_segment(clip, proj, i, j):
    """Edge ``i``-``j`` in raster space: ``(status, (x0, y0, z0, x1, y1, z1))``.

    ``status`` is 1 for a segment to draw, 0 when nothing of it is visible and -1 when it
    is dropped for a non-finite or too large coordinate. Both ends projected by
    :func:`project_vertices` are taken as they are; otherwise the segment is clipped here.
    """
    fi, fj = proj[i, 3], proj[j, 3]
    if fi > 0.0 and fj > 0.0:
        return 1, (proj[i, 0], proj[i, 1], proj[i, 2], proj[j, 0], proj[j, 1], proj[j, 2])
    if fi < 0.0 or fj < 0.0:
        return -1, (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    p = (clip[i, 0], clip[i, 1], clip[i, 2], clip[i, 3])
    q = (clip[j, 0], clip[j, 1], clip[j, 2], clip[j, 3])
    visible, x0, y0, z0, x1, y1, z1 = _project_edge(p, q)
    return (1 if visible else 0), (x0, y0, z0, x1, y1, z1)


# --- framebuffer edges: per-band drawing ----------------------------------------------------


@kernel(inline="always")
def _band_frame(steep, width, ylo, yhi):
    """Strides and ranges of the band in (major u, minor v) terms.

    Returns ``(ustride, vstride, ulo, uhi, vlo, vhi)``: pixel index steps (in pixels of the
    flattened (H, W) image) and the inclusive coordinate ranges of the band.
    """
    if steep:
        return width, 1, ylo, yhi, 0, width - 1
    return 1, width, 0, width - 1, ylo, yhi


@kernel(inline="always")
def _oriented(x0, y0, x1, y1, steep, swap):
    """The segment as ``(u0, v0, u1, v1)``: transposed if steep, reversed if swap."""
    u0, v0, u1, v1 = (y0, x0, y1, x1) if steep else (x0, y0, x1, y1)
    if swap:
        return u1, v1, u0, v0
    return u0, v0, u1, v1


@kernel(inline="always")
def _depth_at(u, u0f, du, z0, gz):
    """Depth of the segment at the centre of major coordinate ``u``, clamped to its ends."""
    return z0 + min(max(u + 0.5 - u0f, 0.0), du) * gz


@kernel(inline="always")
def _blend(cflat, pix, channels, rgba, weight):
    """Blend ``rgba`` into pixel ``pix`` with coverage ``weight`` in [0, 1], rounding."""
    base = pix * channels
    for ch in range(channels):
        old = np.float64(cflat[base + ch])
        cflat[base + ch] = np.uint8(old + (np.float64(rgba[ch]) - old) * weight + 0.5)


@kernel(inline="always")
def _draw_bresenham(cflat, dflat, width, channels, rgba, seg, ylo, yhi, depth_test, bias):
    """Draw one segment's integer line, restricted to rows ``[ylo, yhi]`` of the image."""
    xi0, yi0 = math.floor(seg[0]), math.floor(seg[1])
    xi1, yi1 = math.floor(seg[3]), math.floor(seg[4])
    steep = abs(yi1 - yi0) > abs(xi1 - xi0)
    # Step towards increasing major coordinate; deciding on the real ends also orders the
    # integer ones, and keeps the depth slope's denominator >= 0.
    swap = (seg[4] < seg[1]) if steep else (seg[3] < seg[0])
    u0, v0, u1, v1 = _oriented(xi0, yi0, xi1, yi1, steep, swap)
    u0f, _, u1f, _ = _oriented(seg[0], seg[1], seg[3], seg[4], steep, swap)
    z0, z1 = (seg[5], seg[2]) if swap else (seg[2], seg[5])
    ustride, vstride, ulo, uhi, vlo, vhi = _band_frame(steep, width, ylo, yhi)

    n = u1 - u0
    dv = v1 - v0
    a = abs(dv)
    sv = 1 if dv >= 0 else -1
    c = _tie_offset(dv)
    if min(xi0, xi1) >= 0 and max(xi0, xi1) < width and min(yi0, yi1) >= ylo and max(yi0, yi1) <= yhi:
        tlo, thi, k, r = 0, n, 0, n - c  # the whole line is in the band: the usual case
    else:
        tlo, thi = _step_range(u0, v0, n, a, sv, c, ulo, uhi, vlo, vhi)
        if tlo > thi:
            return
        k, r = _minor_steps(tlo, n, a, c)
    pix = (u0 + tlo) * ustride + (v0 + sv * k) * vstride
    if depth_test:
        du = u1f - u0f
        gz = (z1 - z0) / du if du > 0.0 else 0.0
        for t in range(tlo, thi + 1):
            if _depth_at(u0 + t, u0f, du, z0, gz) - bias <= dflat[pix]:
                _put(cflat, pix, channels, rgba)
            r += 2 * a
            step = r >= 2 * n
            r -= 2 * n if step else 0
            pix += ustride + (sv * vstride if step else 0)
    else:
        _steps(cflat, channels, rgba, pix, thi - tlo + 1, r, 2 * a, 2 * n, ustride, sv * vstride)


@kernel(inline="always")
def _put(cflat, pix, channels, rgba):
    base = pix * channels
    for ch in range(channels):
        cflat[base + ch] = rgba[ch]


@kernel(inline="always")
def _short_steps(cflat, value, pix, count, r, two_a, two_n, ustride, vstride, slots):
    """:func:`_steps` into a one-byte-per-pixel buffer for a line of ``count <= slots``
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
def _steps(cflat, channels, rgba, pix, count, r, two_a, two_n, ustride, vstride):
    """The Bresenham loop without a depth test: ``count`` pixels from pixel index ``pix``,
    ``ustride`` pixels per major step, ``vstride`` more on a minor step. The minor step is
    taken branch-free (a branch would be mispredicted on about every other pixel of a
    diagonal line), and an RGB buffer gets three byte stores per pixel, no channel loop.
    Short lines into a one-channel buffer (a band's mask) take :func:`_short_steps`."""
    if channels == 1 and count <= 4:
        _short_steps(cflat, rgba[0], pix, count, r, two_a, two_n, ustride, vstride, 4)
        return
    if channels == 1 and count <= 8:
        _short_steps(cflat, rgba[0], pix, count, r, two_a, two_n, ustride, vstride, 8)
        return
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
        _put(cflat, pix, channels, rgba)
        r += two_a
        step = r >= two_n
        r -= two_n if step else 0
        pix += ustride + (vstride if step else 0)


@kernel(inline="always")
def _wu_columns(u0f, v0f, u1f, g, ulo, uhi, vlo, vhi):
    """Major columns ``[first, last]`` of a Wu segment that can touch the band.

    Column ``u`` puts the line's minor coordinate ``v(u)`` between the centres of rows
    ``floor(v - 0.5)`` and the next, so it can touch ``[vlo, vhi]`` only when
    ``v in [vlo - 0.5, vhi + 1.5)``; that range is inverted once per edge (with a margin of
    one column for rounding) instead of testing every column.
    """
    first = max(math.floor(u0f), ulo)
    last = min(math.ceil(u1f) - 1, uhi)
    if g == 0.0:
        if not vlo - 0.5 <= v0f < vhi + 1.5:
            return 1, 0
    elif first <= last:
        ua = (vlo - 0.5 - v0f) / g + u0f - 0.5
        ub = (vhi + 1.5 - v0f) / g + u0f - 0.5
        lo = min(max(min(ua, ub), first - 1.0), last + 1.0)
        hi = min(max(max(ua, ub), first - 1.0), last + 1.0)
        first = max(first, math.floor(lo) - 1)
        last = min(last, math.ceil(hi) + 1)
    return first, last


@kernel
def _draw_wu(cflat, dflat, width, channels, rgba, seg, ylo, yhi, depth_test, bias):
    """Draw one segment anti-aliased (Xiaolin Wu), restricted to rows ``[ylo, yhi]``.

    Each major column ``u`` is covered over ``min(u1, u + 1) - max(u0, u)`` of its width;
    that coverage is split between the two pixels whose centres straddle the line at the
    column centre, in proportion to their distance from it.
    """
    steep = abs(seg[4] - seg[1]) > abs(seg[3] - seg[0])
    swap = (seg[4] < seg[1]) if steep else (seg[3] < seg[0])
    u0f, v0f, u1f, v1f = _oriented(seg[0], seg[1], seg[3], seg[4], steep, swap)
    z0, z1 = (seg[5], seg[2]) if swap else (seg[2], seg[5])
    du = u1f - u0f
    if du == 0.0:
        return
    ustride, vstride, ulo, uhi, vlo, vhi = _band_frame(steep, width, ylo, yhi)
    g = (v1f - v0f) / du
    gz = (z1 - z0) / du
    first, last = _wu_columns(u0f, v0f, u1f, g, ulo, uhi, vlo, vhi)
    for u in range(first, last + 1):
        coverage = min(u1f, u + 1.0) - max(u0f, float(u))
        below = v0f + (u + 0.5 - u0f) * g - 0.5
        j = math.floor(below)
        frac = below - j
        z = _depth_at(u, u0f, du, z0, gz) - bias
        for row, weight in ((j, 1.0 - frac), (j + 1, frac)):
            if vlo <= row <= vhi:
                pix = u * ustride + row * vstride
                if not depth_test or z <= dflat[pix]:
                    _blend(cflat, pix, channels, rgba, coverage * weight)


#: Rows of the per-edge records of :func:`plain_setup`, each (E,) int32: the first pixel,
#: the packed steps ``n | a << 15 | steep << 30 | negative << 31`` and the rows
#: ``jlo | jhi << 16`` (-1 for an edge of the general path).
_REC_PIX, _REC_STEPS, _REC_ROWS = range(3)
REC_FIELDS = 3

#: Images at most this many pixels a side fit ``n``, ``a`` and the rows into 15 and 16
#: bits; larger ones draw every edge by the general path.
_PACKED_LIMIT = 1 << 15

#: Work of one plain edge beyond its pixels, in pixel steps (setup, loop entry and exit),
#: for balancing the bands.
_EDGE_WORK = 4
SETUP_CHUNKS = 16
_SETUP_BLOCK = 512
_WORK_LANES = 4  # a power of two
#: Records that :func:`record_work` counts at most (about; it samples beyond).
_WORK_SAMPLES = 1 << 15


@kernel
def plain_setup(slot, counter, pixels, edges, width, height, recs):
    """Per-edge Bresenham setup of plain (no depth test, no anti-aliasing) edges, once.

    An edge whose two ends have a pixel in ``pixels`` (:func:`project_vertices`) lies
    inside the image with its whole integer line; its record (column ``e`` of ``recs``,
    (REC_FIELDS, E) int32) gets the loop state that :func:`_draw_bresenham` would start
    from: the first pixel (index into the flattened image), ``n`` and ``a = |dv|`` with
    two bits (steep; minor steps go negative), and the rows ``jlo <= jhi`` it spans.
    Every other edge gets rows -1 and is drawn by the general path.

    In blocks of ``_SETUP_BLOCK`` edges: first the ends are gathered, then the arithmetic
    runs over the block without a branch, which LLVM turns into vector instructions (16
    edges at a time with AVX-512: ten times faster than edge by edge with branches).
    Stepping from the end with the smaller major coordinate is the same as deciding on the
    real ends (the integer ends differ along the major axis unless the line is a single
    pixel). A worker of :func:`rasterkit._jit.run_parallel` (``slot`` unused, chunks
    claimed through ``counter``).
    """
    m = edges.shape[0]
    packed = width <= _PACKED_LIMIT and height <= _PACKED_LIMIT
    ends = np.empty((2, _SETUP_BLOCK), np.int64)
    while True:  # claim the next piece until none is left
        ch = fetch_add(counter, 0, 1)
        if ch >= SETUP_CHUNKS:
            break
        stop = m * (ch + 1) // SETUP_CHUNKS
        for start in range(m * ch // SETUP_CHUNKS, stop, _SETUP_BLOCK):
            count = min(_SETUP_BLOCK, stop - start)
            for k in range(count):
                ends[0, k] = pixels[edges[start + k, 0]] if packed else -1
                ends[1, k] = pixels[edges[start + k, 1]]
            _setup_block(ends[0], ends[1], count, width, recs[_REC_PIX], recs[_REC_STEPS], recs[_REC_ROWS],
                         start)


@kernel
def _setup_block(first, second, count, width, pix, steps, rows, offset):
    """Records ``offset .. offset + count - 1`` of :func:`plain_setup` from the end pixels
    ``first[k], second[k]`` (``x | y << 32``, -1 outside). 0/1 integers and products in
    place of if/else: no branch, so the loop vectorises (and edge directions are random:
    branches would be mispredicted half the time)."""
    w = np.int32(width)
    one = np.int32(1)
    for k in range(np.uint64(count)):
        p0, p1 = first[k], second[k]
        x0, y0 = np.int32(p0 & 0xFFFFFFFF), np.int32(p0 >> 32)
        x1, y1 = np.int32(p1 & 0xFFFFFFFF), np.int32(p1 >> 32)
        ok = np.int32((x0 | x1) >= 0)
        dx, dy = x1 - x0, y1 - y0
        sx, sy = dx >> np.int32(31), dy >> np.int32(31)  # 0 or -1: the signs
        adx, ady = (dx ^ sx) - sx, (dy ^ sy) - sy
        steep = np.int32(ady > adx)
        n = adx + steep * (ady - adx)
        a = ady + steep * (adx - ady)
        swap = (steep & -sy) | ((one - steep) & -sx)  # step from the second end
        dv = steep * dx + (one - steep) * dy
        negative = (np.int32(dv < 0) ^ swap) & np.int32(a != 0)
        u = np.uint64(offset) + k
        pix[u] = (y0 + swap * dy) * w + x0 + swap * dx
        steps[u] = n | (a << np.int32(15)) | (steep << np.int32(30)) | (negative << np.int32(31))
        jlo = y0 + dy * np.int32(dy < 0)
        rows[u] = ok * ((jlo | ((y0 + y1 - jlo) << np.int32(16))) + one) - one


@kernel
def record_work(recs, height):
    """The work of the records of :func:`plain_setup` (their pixels plus ``_EDGE_WORK``
    each) per ``ROWS_PER_BIN`` image rows, by the row of their middle: what
    :func:`balanced_bands` shares out in plain mode. (The vertex counts of
    :func:`project_vertices` follow the vertices, not the pixels, and left one of two bands
    60 % of the work on some models.) Records of the general path are not counted.

    Counted in four interleaved lanes: consecutive edges mostly fall into the same bin,
    and one counter would make every addition wait for the previous one. Beyond
    ``_WORK_SAMPLES`` records only every ``s``-th is counted, ``s`` times over
    (``s = E // _WORK_SAMPLES``): an estimate is all the balance needs, and counting every
    record cost more than the balance won on the largest models."""
    n_bins = (height + ROWS_PER_BIN - 1) // ROWS_PER_BIN
    work = np.zeros((_WORK_LANES, n_bins), np.int64)
    m = recs.shape[1]
    stride = max(m // _WORK_SAMPLES, 1)
    lane = 0
    for e in range(0, m, stride):
        u = np.uint64(e)
        rows = np.int64(recs[_REC_ROWS, u])
        ok = np.int64(rows >= 0)
        middle = ((rows & 0xFFFF) + (rows >> 16)) >> 1
        n = np.int64(recs[_REC_STEPS, u]) & 0x7FFF
        work[lane, ok * (middle // ROWS_PER_BIN)] += ok * stride * (n + 1 + _EDGE_WORK)
        lane = (lane + 1) & (_WORK_LANES - 1)
    for k in range(1, _WORK_LANES):
        for b in range(n_bins):
            work[0, b] += work[k, b]
    return work[0]


@kernel(inline="always")
def _draw_record(cflat, width, channels, rgba, recs, e):
    """Step the Bresenham line of record ``e`` of :func:`plain_setup`."""
    packed = np.int64(recs[_REC_STEPS, e]) & 0xFFFFFFFF
    n, a = packed & 0x7FFF, (packed >> 15) & 0x7FFF
    steep, negative = (packed >> 30) & 1, packed >> 31
    ustride = 1 + steep * (width - 1)
    vstride = (1 - 2 * negative) * (width - steep * (width - 1))
    r = n - (negative | np.int64(a == 0))  # _tie_offset: dv <= 0
    _steps(cflat, channels, rgba, np.int64(recs[_REC_PIX, e]), n + 1, r, 2 * a, 2 * n, ustride, vstride)


#: ``bits = (word * _GATHER) >> 56`` turns 8 mask bytes of 0 or 1 into 8 bits (bit k = byte k).
_GATHER = 0x0102040810204080


@kernel(inline="always")
def _paint_tables(rgba):
    """For the masked colour pass of C = ``rgba.size`` channels, 8 pixels (C 64-bit words)
    at a time: ``select[bits]``, the C words with 0xFF in the bytes of the pixels whose bit
    is set, and ``paint``, the C words of ``rgba`` repeated over 8 pixels."""
    channels = rgba.size
    select = np.zeros((256, channels), np.uint64)
    paint = np.zeros(channels, np.uint64)
    for b in range(8 * channels):
        word, shift = b // 8, np.uint64(8 * (b % 8))
        paint[word] |= np.uint64(rgba[b % channels]) << shift
        for bits in range(256):
            if (bits >> (b // channels)) & 1:
                select[bits, word] |= np.uint64(0xFF) << shift
    return select, paint


@kernel(inline="always")
def _paint_marked(cflat, mflat, lo, hi, rgba, select, paint):
    """Colour ``rgba`` into the pixels ``lo .. hi - 1`` whose mask byte is 1 (the others
    are 0): eight pixels per mask word, unmarked groups skipped, each marked group blended
    in C 64-bit words by the byte masks of :func:`_paint_tables`."""
    channels = rgba.size
    p = lo
    while p < hi and p % 8 != 0:
        if mflat[p]:
            _put(cflat, p, channels, rgba)
        p += 1
    groups = (hi - p) // 8
    if groups > 0:
        marks = mflat[p: p + 8 * groups].view(np.uint64)
        words = cflat[p * channels: (p + 8 * groups) * channels].view(np.uint64)
        for g in range(groups):
            mark = marks[g]
            if mark == 0:
                continue
            bits = (mark * np.uint64(_GATHER)) >> np.uint64(56)
            for k in range(channels):
                sel = select[bits, k]
                w = g * channels + k
                words[w] = (words[w] & ~sel) | (paint[k] & sel)
        p += 8 * groups
    while p < hi:
        if mflat[p]:
            _put(cflat, p, channels, rgba)
        p += 1


@kernel(inline="always")
def _band_edges(cflat, dflat, width, channels, rgba, clip, proj, edges, recs, ylo, yhi, plain,
                depth_test, antialias, bias):
    """Draw every edge's part in rows ``ylo .. yhi``; returns the number of dropped edges."""
    dropped = 0
    for e in range(edges.shape[0]):
        if plain:
            rows = recs[_REC_ROWS, e]
            if rows >= 0:
                jlo, jhi = rows & 0xFFFF, rows >> 16
                if jhi < ylo or jlo > yhi:
                    continue
                if jlo >= ylo and jhi <= yhi:
                    _draw_record(cflat, width, channels, rgba, recs, e)
                    continue
        status, seg = _edge_segment(clip, proj, edges[e, 0], edges[e, 1])
        if status <= 0:
            dropped += status < 0
            continue
        # Wu's two pixels and its end-column centres reach up to 2 rows beyond the ends.
        if math.floor(min(seg[1], seg[4])) - 2 > yhi or math.floor(max(seg[1], seg[4])) + 2 < ylo:
            continue
        if antialias:
            _draw_wu(cflat, dflat, width, channels, rgba, seg, ylo, yhi, depth_test, bias)
        else:
            _draw_bresenham(cflat, dflat, width, channels, rgba, seg, ylo, yhi, depth_test, bias)
    return dropped


@kernel
def draw_edge_bands(slot, counter, color, depth, clip, edges, rgba, mode, bias, bounds, background, scratch):
    """Draw the edges of a mesh into a framebuffer, band by band: each the next band that
    no worker has claimed yet (through ``counter``), until none are left; returns the
    number of edges this worker dropped (each band sees every edge, so the dropped edges
    of any one band are all of them: the driver reads band 0's, :data:`DROPPED_BAND`).

    A worker of :func:`rasterkit._jit.run_parallel`; ``slot`` is unused. The driver,
    :mod:`rasterkit._edges`, runs :func:`project_vertices` (and, plain, :func:`plain_setup`
    and :func:`record_work`) first, and :func:`balanced_bands` gives ``bounds``.

    Parameters
    ----------
    color : (H, W, C) uint8, C-contiguous, C in {3, 4}
        Colour buffer, modified in place.
    depth : (H, W) float32, C-contiguous
        Depth buffer (smaller = nearer, +inf = empty). Read only with ``MODE_DEPTH_TEST``
        and never written; without the depth test any float32 array will do (e.g.
        ``np.empty((0, 0), np.float32)``).
    clip : (N, 4) float64
        Vertices in homogeneous raster space ``(xh, yh, zh, w)``.
    edges : (E, 2) int64
        Vertex indices into ``clip``, each in ``[0, N)`` (the caller checks).
    rgba : (C,) uint8
        Line colour.
    mode : int
        Bit set of ``MODE_DEPTH_TEST`` and ``MODE_ANTIALIAS``; ``MODE_PLAIN`` (0) is a
        wireframe with neither.
    bias : float
        Depth-test mode draws a pixel only where ``z - bias <= depth[y, x]``, ``z`` being the
        edge's depth (affine in screen space, so interpolated linearly) at the pixel's
        major-axis centre. A small positive bias lets the edges of visible faces pass the
        test against those faces' own depths.
    bounds : (n_bands + 1,) int64
        Band ``b`` is rows ``bounds[b] .. bounds[b + 1] - 1`` (possibly none). The image is
        the same for any bands.
    background : (C,) uint8 or (0,)
        Written to every pixel of a band by the worker that draws the band, right before
        its edges (nothing is cleared when it is empty).
    scratch : tuple
        ``(proj, pixels, recs, mask)``: ``proj`` (N, 4) float64 from
        :func:`project_vertices`; in plain mode ``pixels`` (N,) int64 and ``recs``
        (REC_FIELDS, E) int32 from :func:`plain_setup` (without rows in the other modes).
        ``mask`` (H * W,) uint8 is for plain mode with a background: each band first marks
        its edges' pixels in the mask (one byte store per pixel, in a buffer a third the
        size of an RGB image that stays in the thread's cache), then clears its colour rows
        and paints the marked pixels 8 at a time. With any other mode or without a
        background, or when ``mask`` is smaller, the edges are drawn into the colour buffer
        directly. The image is the same either way.

    Notes
    -----
    Plain and depth-tested edges write ``rgba`` to the pixels of the integer line between
    the pixels containing the (clipped) endpoints, exactly as :func:`line_pixels` draws it
    with Bresenham. Anti-aliased edges use Xiaolin Wu's algorithm on the real-valued
    endpoints and blend ``rgba`` into the colour buffer, all C channels, by coverage; their
    total weight is the segment's extent along its major axis. Edges are drawn in order, so
    overlapping anti-aliased edges blend in index order. Segments are clipped to the near
    and far planes and to the guard band ``[-GUARD_BAND, GUARD_BAND]^2`` in homogeneous
    space; a segment with both ends inside the guard band is drawn exactly. Edges with a
    coordinate beyond ``MAX_COORDINATE`` (or NaN, inf) are dropped and counted. The image
    must be smaller than ``GUARD_BAND`` on each side.
    """
    proj, pixels, recs, mask = scratch
    height, width, channels = color.shape
    depth_test = (mode & MODE_DEPTH_TEST) != 0
    antialias = (mode & MODE_ANTIALIAS) != 0
    plain = not depth_test and not antialias
    cflat = color.reshape(color.size)
    dflat = depth.reshape(depth.size)
    clear = background.size == channels
    pattern = background_pattern(background) if clear else np.empty(0, np.uint8)
    marked = plain and clear and mask.size >= height * width
    # the 8-pixel paint tables, only for the marked (mask) path
    select, paint = _paint_tables(rgba if marked else rgba[:0])
    one = np.ones(1, np.uint8)
    zeros = np.zeros(PATTERN_BYTES, np.uint8)
    dropped = 0
    while True:  # claim the next piece until none is left
        band = fetch_add(counter, 0, 1)
        if band >= bounds.size - 1:
            break
        ylo, yhi = bounds[band], bounds[band + 1] - 1
        if marked:  # into the mask (one channel, value 1), then paint
            fill_bytes(mask, ylo * width, (yhi + 1) * width, zeros)
        elif clear:
            fill_bytes(cflat, ylo * width * channels, (yhi + 1) * width * channels, pattern)
        if marked:  # constants in this copy: one byte per pixel, plain lines
            lost = _band_edges(mask, dflat, width, 1, one, clip, proj, edges, recs, ylo, yhi,
                               True, False, False, 0.0)
        else:
            lost = _band_edges(cflat, dflat, width, channels, rgba, clip, proj, edges, recs, ylo, yhi,
                               plain, depth_test, antialias, bias)
        if band == DROPPED_BAND:
            dropped = lost
        if marked:
            fill_bytes(cflat, ylo * width * channels, (yhi + 1) * width * channels, pattern)
            _paint_marked(cflat, mask, ylo * width, (yhi + 1) * width, rgba, select, paint)
    return dropped


#: The band whose count of dropped edges :func:`draw_edge_bands` reports.
DROPPED_BAND = 0
