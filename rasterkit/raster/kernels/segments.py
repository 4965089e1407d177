"""Clipping segments (the edges of the line path) in homogeneous raster space.

Segments (the edges of the line path) are clipped by :func:`project_segment` against the
near and far planes and a square guard band of ``±SEGMENT_GUARD_BAND`` pixels, wider than
the triangles' (``GUARD_BAND``): a segment needs no fixed-point edge functions, only
integer Bresenham error terms, and within the wider band its integer line is drawn exactly
as if unclipped. The segment clipper works from a point inside (Liang–Barsky exits; an
inside point found by bisection when both ends are far away), so ends as far out as
``MAX_COORDINATE`` clip accurately.

The visible region and its planes are those of :mod:`rasterkit.raster.kernels.clip`, with
the square guard band of this module instead of the triangles'.
"""

from __future__ import annotations

from rasterkit.runtime.jit import kernel

SEGMENT_GUARD_BAND = 2.0**24 + 0.5
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


@kernel(inline="always")
def _plane_distances(v):
    """Signed distances (>= 0 inside) of homogeneous point ``v`` to the six clip planes.

    The visible region is ``0 <= zh <= w`` (near and far planes) and
    ``|xh|, |yh| <= SEGMENT_GUARD_BAND * w``; it is convex and implies ``w >= 0``.
    """
    xh, yh, zh, w = v
    g = SEGMENT_GUARD_BAND * w
    return (zh, w - zh, g + xh, g - xh, g + yh, g - yh)


@kernel(inline="always")
def segment_outcode(v):
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
    code_a, code_b = segment_outcode(a), segment_outcode(b)
    for _ in range(_MAX_BISECTIONS):
        if code_a == 0:
            return True, a
        if code_b == 0:
            return True, b
        if code_a & code_b:
            return False, a
        m = ((a[0] + b[0]) * 0.5, (a[1] + b[1]) * 0.5, (a[2] + b[2]) * 0.5, (a[3] + b[3]) * 0.5)
        code_m = segment_outcode(m)
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
def clamp(value, lo, hi):
    return min(max(value, lo), hi)


@kernel
def project_segment(p, q):
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
    x0 = clamp(xh0 * inv0, -SEGMENT_GUARD_BAND, SEGMENT_GUARD_BAND)
    y0 = clamp(yh0 * inv0, -SEGMENT_GUARD_BAND, SEGMENT_GUARD_BAND)
    x1 = clamp(xh1 * inv1, -SEGMENT_GUARD_BAND, SEGMENT_GUARD_BAND)
    y1 = clamp(yh1 * inv1, -SEGMENT_GUARD_BAND, SEGMENT_GUARD_BAND)
    return True, x0, y0, zh0 * inv0, x1, y1, zh1 * inv1


@kernel(inline="always")
def all_usable(values):
    """Whether every float of the tuple ``values`` is finite and at most MAX_COORDINATE."""
    for value in values:
        if not abs(value) <= MAX_COORDINATE:
            return False
    return True
