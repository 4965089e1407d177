"""Numba kernels behind :func:`rasterkit.load_obj`: OBJ tokenizer, number parsers, triangulator.

Everything here works on the raw bytes of a file (a C-contiguous uint8 array) and on plain
integer and float arrays; :mod:`rasterkit.obj` validates, reports errors with line numbers and
builds the :class:`~rasterkit.mesh.Mesh`. The kernels never raise on bad input: they return
status codes, so the caller can name the first bad line of the file.

A *statement* is one OBJ line: a keyword and its tokens. Whitespace is space, tab, CR, VT and
FF; ``#`` at the start of a token starts a comment that runs to the end of the line. Line
continuations (a backslash before the line break) are blanked out by the caller before the
scan, so here every statement is one physical line.

Speed note: the per-byte loops call only helpers that take scalars. A helper taking the byte
array, inlined into such a loop, adds atomic reference-count updates at every call (the scan was
three times slower); helpers that take the array run once per token or statement.
"""

from __future__ import annotations

import numpy as np

from .._jit import kernel

# Statement kinds returned by scan_statements (blank and comment lines are not statements).
KIND_V, KIND_VT, KIND_VN, KIND_F, KIND_L, KIND_P = 1, 2, 3, 4, 5, 6
KIND_G, KIND_O, KIND_S, KIND_USEMTL, KIND_MTLLIB, KIND_OTHER = 7, 8, 9, 10, 11, 12

# Status of one parsed number.
NUMBER_OK, NUMBER_INEXACT, NUMBER_MALFORMED = 0, 1, 2

# Status codes of one face or line corner (code, corner, attribute) written by parse_corners.
INDEX_OK, INDEX_ZERO, INDEX_BEFORE_FIRST, INDEX_OUT_OF_RANGE, INDEX_MALFORMED = 0, 1, 2, 3, 4

# 10**k for k = 0..22: every one is exact in float64, so m * 10**k and m / 10**k round once.
_POW10 = np.array([10.0**k for k in range(23)])
_EXACT_MANTISSA = 1 << 53

_NL, _HASH, _SLASH, _DOT = 10, 35, 47, 46
_PLUS, _MINUS, _ZERO, _NINE = 43, 45, 48, 57


def _key(word: bytes) -> int:
    """A keyword of up to 7 bytes packed big-endian into one integer, as the scan builds it."""
    return int.from_bytes(word, "big")


_KINDS = {_key(b"v"): KIND_V, _key(b"vt"): KIND_VT, _key(b"vn"): KIND_VN, _key(b"f"): KIND_F,
          _key(b"l"): KIND_L, _key(b"p"): KIND_P, _key(b"g"): KIND_G, _key(b"o"): KIND_O,
          _key(b"s"): KIND_S, _key(b"usemtl"): KIND_USEMTL, _key(b"mtllib"): KIND_MTLLIB}
_KIND_KEYS = np.array(list(_KINDS), np.int64)
_KIND_CODES = np.array(list(_KINDS.values()), np.int8)

_NAN = np.frombuffer(b"nan", np.uint8)
_INF = np.frombuffer(b"inf", np.uint8)
_INFINITY = np.frombuffer(b"infinity", np.uint8)
_MSVC_NAN = (np.frombuffer(b"#ind", np.uint8), np.frombuffer(b"#qnan", np.uint8),
             np.frombuffer(b"#snan", np.uint8))
_MSVC_INF = np.frombuffer(b"#inf", np.uint8)


@kernel(inline="always")
def _is_blank(c):
    return c == 32 or c == 9 or c == 13 or c == 11 or c == 12


@kernel(inline="always")
def _in_token(c):
    """True for a byte that continues a token: anything but whitespace and newline."""
    return not (c == _NL or _is_blank(c))


@kernel(inline="always")
def _is_digit(c):
    return _ZERO <= c <= _NINE


@kernel
def _keyword_kind(key):
    """KIND_* of a keyword packed by scan_statements (-1, a keyword longer than 7 bytes, and
    any other unknown key give KIND_OTHER)."""
    for k in range(len(_KIND_KEYS)):
        if _KIND_KEYS[k] == key:
            return _KIND_CODES[k]
    return np.int8(KIND_OTHER)


@kernel
def scan_statements(buf):
    """Split OBJ text into statements.

    Parameters
    ----------
    buf : (B,) uint8
        The file's bytes, without byte order mark and with continuations blanked out.

    Returns
    -------
    starts, ends : (S,) int64
        Byte range of each statement: from its keyword to the end of its last token (a trailing
        comment is left out). The statement's line number is one more than the count of
        newlines before its start.
    kinds : (S,) int8
        ``KIND_*`` code of the keyword.
    ntokens : (S,) int64
        Number of whitespace-separated tokens after the keyword.
    """
    n = len(buf)
    capacity = 1
    for i in range(n):
        if buf[i] == _NL:
            capacity += 1
    starts = np.empty(capacity, np.int64)
    ends = np.empty(capacity, np.int64)
    kinds = np.empty(capacity, np.int8)
    ntokens = np.empty(capacity, np.int64)
    count = 0
    i = 0
    while i < n:
        while i < n and _is_blank(buf[i]):
            i += 1
        if i == n:
            break
        if buf[i] == _NL:
            i += 1
            continue
        start = i
        comment = buf[i] == _HASH
        key = 0
        while i < n and _in_token(buf[i]):
            key = key * 256 + buf[i] if i - start < 7 else -1
            i += 1
        end = i
        tokens = 0
        while i < n and buf[i] != _NL:
            if _is_blank(buf[i]):
                i += 1
            elif buf[i] == _HASH or comment:
                comment = True
                i += 1
            else:
                while i < n and _in_token(buf[i]):
                    i += 1
                tokens += 1
                end = i
        if buf[start] != _HASH:
            starts[count] = start
            ends[count] = end
            kinds[count] = _keyword_kind(key)
            ntokens[count] = tokens
            count += 1
    return starts[:count], ends[:count], kinds[:count], ntokens[:count]


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
    if buf[a] == _PLUS or buf[a] == _MINUS:
        sign = -1.0 if buf[a] == _MINUS else 1.0
        a += 1
    if _is_word(buf, a, b, _NAN):
        return np.nan, True
    if _is_word(buf, a, b, _INF) or _is_word(buf, a, b, _INFINITY):
        return sign * np.inf, True
    i = a
    while i < b and _is_digit(buf[i]):
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
    if i < b and (buf[i] == _PLUS or buf[i] == _MINUS):
        sign = -1 if buf[i] == _MINUS else 1
        i += 1
    start = i
    e = 0
    while i < b and _is_digit(buf[i]):
        e = min(e * 10 + (buf[i] - _ZERO), 100000)
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
    if buf[i] == _PLUS or buf[i] == _MINUS:
        sign = -1.0 if buf[i] == _MINUS else 1.0
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
            if mantissa > 0 or buf[i] > _ZERO:
                mantissa = mantissa * np.uint64(10) + np.uint64(buf[i] - _ZERO)
                digits += 1
            exponent -= 1 if point else 0
        else:
            exponent += 0 if point else 1
            truncated = truncated or buf[i] > _ZERO
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
def _next_token(buf, i, end):
    """Start and end of the first token at or after i, before end (the end of a statement's
    last token, so there is one)."""
    while _is_blank(buf[i]):
        i += 1
    a = i
    while i < end and _in_token(buf[i]):
        i += 1
    return a, i


@kernel
def parse_number_rows(buf, starts, ends, width):
    """Parse the numbers of statements (v, vt, vn lines) into rows.

    Parameters
    ----------
    buf : (B,) uint8
    starts, ends : (S,) int64
        Statement ranges from :func:`scan_statements`.
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
    values = np.full((rows, width), np.nan)
    status = np.zeros(rows, np.int8)
    bad_token = np.full(rows, -1, np.int64)
    inexact = np.zeros(rows, np.int64)
    for r in range(rows):
        i = _next_token(buf, starts[r], ends[r])[1]  # after the keyword
        k = 0
        while i < ends[r]:
            a, i = _next_token(buf, i, ends[r])
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


@kernel(inline="always")
def _resolve(raw, before, total):
    """0-based index and INDEX_* code of an OBJ index (1-based, or negative = relative)."""
    if raw > 0:
        if raw > total:
            return -1, INDEX_OUT_OF_RANGE
        return raw - 1, INDEX_OK
    if raw < 0:
        if before + raw < 0:
            return -1, INDEX_BEFORE_FIRST
        return before + raw, INDEX_OK
    return -1, INDEX_ZERO


@kernel
def _parse_corner(buf, a, b):
    """One corner token buf[a:b]: ``v``, ``v/vt``, ``v//vn`` or ``v/vt/vn``, where vt and vn
    may be empty (``1//``). Each index is a signed integer of at most 18 digits.

    Returns (v, vt, vn, present, ok): raw indices (0 when absent), bit k of present set when
    field k was given, ok False when the token is malformed.
    """
    v = vt = vn = 0
    present = 0
    field = 0
    value = 0
    sign = 1
    digits = 0
    signed = False
    for i in range(a, b + 1):
        c = buf[i] if i < b else _SLASH  # the end of the token closes the last field
        if c == _SLASH:
            if field > 2 or digits > 18 or (digits == 0 and (signed or field == 0)):
                return 0, 0, 0, 0, False
            if digits > 0:
                present |= 1 << field
                if field == 0:
                    v = sign * value
                elif field == 1:
                    vt = sign * value
                else:
                    vn = sign * value
            field += 1
            value, sign, digits, signed = 0, 1, 0, False
        elif _is_digit(c):
            value = value * 10 + (c - _ZERO)
            digits += 1
        elif (c == _PLUS or c == _MINUS) and digits == 0 and not signed:
            sign = -1 if c == _MINUS else 1
            signed = True
        else:
            return 0, 0, 0, 0, False
    return v, vt, vn, present, True


@kernel
def parse_corners(buf, starts, ends, offsets, before, totals):
    """Parse and resolve the vertex references of f and l statements.

    Parameters
    ----------
    buf : (B,) uint8
    starts, ends : (S,) int64
        Statement ranges.
    offsets : (S + 1,) int64
        Where each statement's corners go in the output (cumulative token counts).
    before : (S, 3) int64
        Number of v, vt, vn statements before each statement (for negative indices).
    totals : (3,) int64
        Number of v, vt, vn statements in the file.

    Returns
    -------
    corners : (C, 3) int64
        0-based v, vt, vn index of each corner; -1 where absent or invalid.
    errors : (S, 3) int64
        (INDEX_* code, corner, attribute 0/1/2) of the statement's first problem: the first bad
        vertex reference if any, else the first bad vt/vn reference; code 0 when all is well.
    """
    rows = len(starts)
    corners = np.full((offsets[rows], 3), -1, np.int64)
    errors = np.zeros((rows, 3), np.int64)
    for r in range(rows):
        i = _next_token(buf, starts[r], ends[r])[1]  # after the keyword
        k = 0
        while i < ends[r]:
            a, i = _next_token(buf, i, ends[r])
            v, vt, vn, present, ok = _parse_corner(buf, a, i)
            if not ok:
                errors[r, 0], errors[r, 1], errors[r, 2] = INDEX_MALFORMED, k, 0
                break
            c = offsets[r] + k
            for attribute, raw in ((0, v), (1, vt), (2, vn)):
                if present & (1 << attribute):
                    index, code = _resolve(raw, before[r, attribute], totals[attribute])
                    corners[c, attribute] = index
                    vertex_first = attribute == 0 and errors[r, 2] != 0
                    if code != INDEX_OK and (errors[r, 0] == INDEX_OK or vertex_first):
                        errors[r, 0], errors[r, 1], errors[r, 2] = code, k, attribute
            k += 1
    return corners, errors


@kernel
def first_per_vertex(vertex_index, attribute_index, n_vertices):
    """(N,) int64: the attribute index of the first corner (in order) of each vertex that has
    one (attribute_index >= 0), else -1."""
    first = np.full(n_vertices, -1, np.int64)
    for c in range(len(vertex_index)):
        v = vertex_index[c]
        if attribute_index[c] >= 0 and first[v] < 0:
            first[v] = attribute_index[c]
    return first


@kernel
def sum_per_vertex(vertex_index, attribute_index, attributes, n_vertices):
    """(N, D) float64: per vertex, the sum of attributes[attribute_index] over its corners
    (corners with attribute_index < 0 add nothing)."""
    total = np.zeros((n_vertices, attributes.shape[1]))
    for c in range(len(vertex_index)):
        a = attribute_index[c]
        if a >= 0:
            for d in range(attributes.shape[1]):
                total[vertex_index[c], d] += attributes[a, d]
    return total


@kernel
def _newell_normal(vertices, ring):
    """Newell's normal (nx, ny, nz) of the closed polygon vertices[ring]: it follows the
    winding by the right-hand rule and its length is twice the area of a planar polygon.
    Coordinates are taken relative to the first vertex to keep them precise."""
    nx = ny = nz = 0.0
    m = len(ring)
    o = vertices[ring[0]]
    for k in range(m):
        p = vertices[ring[k]]
        q = vertices[ring[(k + 1) % m]]
        px, py, pz = p[0] - o[0], p[1] - o[1], p[2] - o[2]
        qx, qy, qz = q[0] - o[0], q[1] - o[1], q[2] - o[2]
        nx += (py - qy) * (pz + qz)
        ny += (pz - qz) * (px + qx)
        nz += (px - qx) * (py + qy)
    return nx, ny, nz


@kernel
def _plane_coordinates(vertices, ring, nx, ny, nz):
    """(m, 2) coordinates of vertices[ring] in the polygon's plane, in a basis (u, w) with
    u x w along the normal (nx, ny, nz): a polygon wound around its normal is CCW there."""
    length = np.sqrt(nx * nx + ny * ny + nz * nz)
    nx, ny, nz = nx / length, ny / length, nz / length
    # u = n x (the coordinate axis least aligned with n), then w = n x u.
    if abs(nx) <= abs(ny) and abs(nx) <= abs(nz):
        ux, uy, uz = 0.0, nz, -ny
    elif abs(ny) <= abs(nz):
        ux, uy, uz = -nz, 0.0, nx
    else:
        ux, uy, uz = ny, -nx, 0.0
    length = np.sqrt(ux * ux + uy * uy + uz * uz)
    ux, uy, uz = ux / length, uy / length, uz / length
    wx, wy, wz = ny * uz - nz * uy, nz * ux - nx * uz, nx * uy - ny * ux
    o = vertices[ring[0]]
    xy = np.empty((len(ring), 2))
    for k in range(len(ring)):
        p = vertices[ring[k]]
        px, py, pz = p[0] - o[0], p[1] - o[1], p[2] - o[2]
        xy[k, 0] = px * ux + py * uy + pz * uz
        xy[k, 1] = px * wx + py * wy + pz * wz
    return xy


@kernel
def _cross(xy, a, b, c):
    """z of (b - a) x (c - b): > 0 when a, b, c turn left (counter-clockwise)."""
    return ((xy[b, 0] - xy[a, 0]) * (xy[c, 1] - xy[b, 1])
            - (xy[b, 1] - xy[a, 1]) * (xy[c, 0] - xy[b, 0]))


@kernel
def _same_point(xy, a, b):
    return xy[a, 0] == xy[b, 0] and xy[a, 1] == xy[b, 1]


@kernel
def _is_ear(xy, prev, nxt, i):
    """True when the triangle (prev[i], i, nxt[i]) turns left and no other reflex or straight
    vertex of the remaining polygon lies inside it or on its border (vertices at the same
    place as a corner of the triangle do not count: polygons with holes repeat them)."""
    a = prev[i]
    c = nxt[i]
    if not _cross(xy, a, i, c) > 0.0:
        return False
    r = nxt[c]
    while r != a:
        if not (_same_point(xy, r, a) or _same_point(xy, r, i) or _same_point(xy, r, c)):
            if (_cross(xy, a, i, r) >= 0.0 and _cross(xy, i, c, r) >= 0.0
                    and _cross(xy, c, a, r) >= 0.0 and _cross(xy, prev[r], r, nxt[r]) <= 0.0):
                return False
        r = nxt[r]
    return True


@kernel
def _most_convex(xy, prev, nxt, start, remaining):
    """The remaining vertex with the largest left turn: the fallback when no ear exists (a
    self-intersecting or degenerate polygon), so that clipping always ends."""
    best = start
    best_turn = -np.inf
    i = start
    for _ in range(remaining):
        turn = _cross(xy, prev[i], i, nxt[i])
        if turn > best_turn:
            best, best_turn = i, turn
        i = nxt[i]
    return best


@kernel
def _ear_clip(xy, ring, out):
    """Triangulate the polygon ring (m,) whose plane coordinates xy (m, 2) wind CCW, writing
    its m - 2 triangles (vertex indices from ring, same winding) into out."""
    m = len(ring)
    prev = np.empty(m, np.int64)
    nxt = np.empty(m, np.int64)
    for k in range(m):
        prev[k] = (k + m - 1) % m
        nxt[k] = (k + 1) % m
    i = 0
    remaining = m
    failures = 0
    t = 0
    while remaining > 3:
        if failures >= remaining:
            i = _most_convex(xy, prev, nxt, i, remaining)
        elif not _is_ear(xy, prev, nxt, i):
            i = nxt[i]
            failures += 1
            continue
        out[t, 0], out[t, 1], out[t, 2] = ring[prev[i]], ring[i], ring[nxt[i]]
        t += 1
        nxt[prev[i]] = nxt[i]
        prev[nxt[i]] = prev[i]
        i = nxt[i]
        remaining -= 1
        failures = 0
    out[t, 0], out[t, 1], out[t, 2] = ring[prev[i]], ring[i], ring[nxt[i]]


@kernel
def _fan(ring, out):
    for t in range(len(ring) - 2):
        out[t, 0], out[t, 1], out[t, 2] = ring[0], ring[t + 1], ring[t + 2]


@kernel
def _convex_quad(vertices, polygon_vertices, o):
    """True when the quad polygon_vertices[o:o + 4] turns the same way as its Newell normal at
    every corner, so that the fan (0, 1, 2), (0, 2, 3) covers it exactly."""
    quad = polygon_vertices[o:o + 4]
    nx, ny, nz = _newell_normal(vertices, quad)
    for k in range(4):
        a = vertices[quad[k]]
        b = vertices[quad[(k + 1) % 4]]
        c = vertices[quad[(k + 2) % 4]]
        e0x, e0y, e0z = b[0] - a[0], b[1] - a[1], b[2] - a[2]
        e1x, e1y, e1z = c[0] - b[0], c[1] - b[1], c[2] - b[2]
        turn = ((e0y * e1z - e0z * e1y) * nx + (e0z * e1x - e0x * e1z) * ny
                + (e0x * e1y - e0y * e1x) * nz)
        if not turn > 0.0:
            return False
    return True


@kernel
def _merge_repeats(polygon):
    """The polygon without consecutive (cyclically) repeated vertex indices."""
    ring = np.empty(len(polygon), np.int64)
    k = 0
    for v in polygon:
        if k == 0 or v != ring[k - 1]:
            ring[k] = v
            k += 1
    while k > 1 and ring[k - 1] == ring[0]:
        k -= 1
    return ring[:k]


@kernel
def _triangulate_polygon(vertices, polygon, out):
    """Triangles of one polygon (m >= 4 vertex indices) into out (m - 2, 3) by ear clipping in
    the polygon's best-fit plane. Repeated consecutive vertices are merged first; rows left over
    stay -1."""
    ring = _merge_repeats(polygon)
    if len(ring) < 3:
        return
    nx, ny, nz = _newell_normal(vertices, ring)
    if len(ring) == 3 or not nx * nx + ny * ny + nz * nz > 0.0:
        _fan(ring, out)
        return
    _ear_clip(_plane_coordinates(vertices, ring, nx, ny, nz), ring, out)


@kernel
def triangulate(vertices, polygon_vertices, offsets, keep):
    """Triangulate polygons given as runs of vertex indices: triangles and convex quads by a
    fan, anything else by ear clipping (correct for concave polygons).

    Parameters
    ----------
    vertices : (N, 3) float64
    polygon_vertices : (C,) int64
        Vertex indices of all polygons, one after another; every index is in [0, N).
    offsets : (P + 1,) int64
        Polygon p is polygon_vertices[offsets[p]:offsets[p + 1]], with at least 3 vertices.
    keep : (P,) bool
        Polygons to triangulate; the others' rows stay -1.

    Returns
    -------
    triangles : (T, 3) int64
        T = sum(m - 2); polygon p's triangles start at row offsets[p] - 2 * p and keep its
        winding. Rows of -1 mark triangles left out: of polygons not kept, and those that
        repeated vertices make degenerate.
    """
    count = len(offsets) - 1
    triangles = np.full((offsets[count] - 2 * count, 3), -1, np.int64)
    for p in range(count):
        if not keep[p]:
            continue
        o = offsets[p]
        m = offsets[p + 1] - o
        t = o - 2 * p
        if m == 3 or (m == 4 and _convex_quad(vertices, polygon_vertices, o)):
            for j in range(m - 2):
                triangles[t + j, 0] = polygon_vertices[o]
                triangles[t + j, 1] = polygon_vertices[o + j + 1]
                triangles[t + j, 2] = polygon_vertices[o + j + 2]
        else:
            _triangulate_polygon(vertices, polygon_vertices[o:o + m], triangles[t:t + m - 2])
        for j in range(t, t + m - 2):
            a, b, c = triangles[j, 0], triangles[j, 1], triangles[j, 2]
            if a == b or b == c or c == a:
                triangles[j] = -1
    return triangles


@kernel
def side_keys(polygon_vertices, offsets, keep, n_vertices):
    """Undirected sides of the kept polygons as keys lo * N + hi (lo < hi), one per side:
    p[0]-p[1], ..., p[-1]-p[0]; sides from a vertex to itself are left out.

    Parameters
    ----------
    polygon_vertices, offsets : as for :func:`triangulate`
    keep : (P,) bool
    n_vertices : int
        N, the number of vertices.

    Returns
    -------
    keys : (E,) int64
    """
    keys = np.empty(offsets[-1], np.int64)
    e = 0
    for p in range(len(offsets) - 1):
        if not keep[p]:
            continue
        first = offsets[p]
        last = offsets[p + 1] - 1
        for k in range(first, last + 1):
            a = polygon_vertices[k]
            b = polygon_vertices[k + 1] if k < last else polygon_vertices[first]
            if a != b:
                keys[e] = min(a, b) * n_vertices + max(a, b)
                e += 1
    return keys[:e]
