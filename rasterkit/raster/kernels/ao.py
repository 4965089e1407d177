"""Screen-space ambient occlusion (:mod:`rasterkit.raster.ao`): rays marched through a
frame's metric depth buffer.

Each pixel's surface point ``P`` and geometric normal ``N`` come from the depth buffer (the
point from the pixel's ray and its axial depth, :func:`~rasterkit.raster.kernels.map_rows.metric_of`
of the buffer's value; the normal from the neighbours on the side whose depth continues the
pixel's). From ``P`` go ``K`` rays in cosine-weighted directions
around ``N``, each marched in ``STEPS`` steps up to the radius ``R``; a ray is blocked at the
first step whose point lies behind the surface the depth buffer holds there, by less than
``R`` (so a surface far in front of the point, which hides it, does not count). The share of
rays blocked estimates ``1 - (1/pi) integral V(P, w) cos(w, N) dw`` for the rays ``w`` that meet
geometry within ``R`` — the ray-traced definition, with the scene as the depth buffer shows it.

The rays' directions turn with each pixel's place in a 4x4 tile (and their steps shift), so
that the 16 pixels of a tile together send ``16 K`` different rays; :func:`ao_blur` averages
each pixel with its tile's neighbours on the same surface. Compiled only when a render asks
for ``ao``.
"""

import math

import numpy as np

from rasterkit.raster.kernels.map_rows import metric_of
from rasterkit.runtime.intrinsics import fetch_add
from rasterkit.runtime.jit import kernel

#: The rows are worked on in this many chunks, shared out among the threads.
N_CHUNKS = 64

#: Steps each ray is marched in.
STEPS = 4

#: The 4x4 tile's order (Bayer's): neighbouring pixels turn their rays far apart.
TILE = np.array([0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5], np.int64)


@kernel(inline="always")
def _point(rays, x, y, d):
    """The world-space point at raster (x, y) with axial depth d: ``O(x, y) + d V(x, y)``."""
    px = rays[0, 0] + x * rays[1, 0] + y * rays[2, 0] + d * (rays[3, 0] + x * rays[4, 0] + y * rays[5, 0])
    py = rays[0, 1] + x * rays[1, 1] + y * rays[2, 1] + d * (rays[3, 1] + x * rays[4, 1] + y * rays[5, 1])
    pz = rays[0, 2] + x * rays[1, 2] + y * rays[2, 2] + d * (rays[3, 2] + x * rays[4, 2] + y * rays[5, 2])
    return px, py, pz


@kernel(inline="always")
def _metric(view, y, x):
    """The axial depth at pixel (x, y) of ``view``: ``(depth buffer (H, W) float32, near,
    far, perspective)`` (0 where nothing was drawn)."""
    depth, near, far, perspective = view
    return metric_of(depth[y, x], near, far, perspective)


@kernel(inline="always")
def _side(view, x, y, dx, dy, d, width, height):
    """The neighbour of (x, y) that continues its surface along (dx, dy): +1 or -1, or 0
    when neither is drawn, and the difference of depths on that side."""
    xa, ya, xb, yb = x + dx, y + dy, x - dx, y - dy
    da = _metric(view, ya, xa) if 0 <= xa < width and 0 <= ya < height else np.float32(0.0)
    db = _metric(view, yb, xb) if 0 <= xb < width and 0 <= yb < height else np.float32(0.0)
    if da > 0.0 and (db <= 0.0 or abs(da - d) <= abs(db - d)):
        return 1, da - d
    if db > 0.0:
        return -1, d - db
    return 0, 0.0


@kernel(inline="always")
def _normal(view, rays, x, y, d, width, height):
    """The unit normal at pixel (x, y) from its neighbours' points, facing the camera, and
    the depth's change over a pixel (across plus down)."""
    cx, cy = x + 0.5, y + 0.5
    p0, p1, p2 = _point(rays, cx, cy, d)
    sx, gx = _side(view, x, y, 1, 0, d, width, height)
    sy, gy = _side(view, x, y, 0, 1, d, width, height)
    vx = rays[3, 0] + cx * rays[4, 0] + cy * rays[5, 0]
    vy = rays[3, 1] + cx * rays[4, 1] + cy * rays[5, 1]
    vz = rays[3, 2] + cx * rays[4, 2] + cy * rays[5, 2]
    if sx == 0 or sy == 0:
        nx, ny, nz = -vx, -vy, -vz
    else:
        a0, a1, a2 = _point(rays, cx + sx, cy, d + sx * gx)
        b0, b1, b2 = _point(rays, cx, cy + sy, d + sy * gy)
        ux, uy, uz = (a0 - p0) * sx, (a1 - p1) * sx, (a2 - p2) * sx
        wx, wy, wz = (b0 - p0) * sy, (b1 - p1) * sy, (b2 - p2) * sy
        nx, ny, nz = uy * wz - uz * wy, uz * wx - ux * wz, ux * wy - uy * wx
        if nx * vx + ny * vy + nz * vz > 0.0:
            nx, ny, nz = -nx, -ny, -nz
    size = math.sqrt(nx * nx + ny * ny + nz * nz)
    if size == 0.0:
        nx, ny, nz, size = -vx, -vy, -vz, math.sqrt(vx * vx + vy * vy + vz * vz)
    return p0, p1, p2, nx / size, ny / size, nz / size, abs(gx) + abs(gy)


@kernel(inline="always")
def _pixel_ao(view, flat, columns, stride, rays, matrix, axis, steps, radius, x, y, d, width, height, where,
              along):
    """The share of the rays from pixel (x, y) (depth d > 0) that are blocked (see
    :func:`ao_raw`); ``steps`` (3, STEPS K) this pixel's steps, ``where`` (STEPS K,) int32
    and ``along`` (STEPS K,) float32 scratch."""
    p0, p1, p2, n0, n1, n2, slope = _normal(view, rays, x, y, d, width, height)
    # a tangent frame (t, b, n)
    if abs(n0) < 0.6:
        t0, t1, t2 = 0.0, -n2, n1
    else:
        t0, t1, t2 = n2, 0.0, -n0
    size = math.sqrt(t0 * t0 + t1 * t1 + t2 * t2)
    t0, t1, t2 = t0 / size, t1 / size, t2 / size
    b0, b1, b2 = n1 * t2 - n2 * t1, n2 * t0 - n0 * t2, n0 * t1 - n1 * t0
    # a grid cell's footprint: the rays start that far off the surface, at s
    footprint = 0.5 * stride * math.sqrt((rays[1, 0] + d * rays[4, 0]) ** 2 + (rays[1, 1] + d * rays[4, 1]) ** 2
                                         + (rays[1, 2] + d * rays[4, 2]) ** 2)
    s0, s1, s2 = p0 + footprint * n0, p1 + footprint * n1, p2 + footprint * n2
    # s, and R times the frame's axes, as homogeneous raster x, y (in grid cells), w and axial
    # depth: a step's are s's plus the same sums of its offset over R in tangent space
    f, r = 1.0 / stride, np.float32(radius)
    sx = np.float32((matrix[0, 0] * s0 + matrix[0, 1] * s1 + matrix[0, 2] * s2 + matrix[0, 3]) * f)
    sy = np.float32((matrix[1, 0] * s0 + matrix[1, 1] * s1 + matrix[1, 2] * s2 + matrix[1, 3]) * f)
    sw = np.float32(matrix[3, 0] * s0 + matrix[3, 1] * s1 + matrix[3, 2] * s2 + matrix[3, 3])
    sd = np.float32(axis[0] * s0 + axis[1] * s1 + axis[2] * s2 + axis[3])
    tx = np.float32((matrix[0, 0] * t0 + matrix[0, 1] * t1 + matrix[0, 2] * t2) * f * radius)
    ty = np.float32((matrix[1, 0] * t0 + matrix[1, 1] * t1 + matrix[1, 2] * t2) * f * radius)
    tw = np.float32((matrix[3, 0] * t0 + matrix[3, 1] * t1 + matrix[3, 2] * t2) * radius)
    td = np.float32((axis[0] * t0 + axis[1] * t1 + axis[2] * t2) * radius)
    bx = np.float32((matrix[0, 0] * b0 + matrix[0, 1] * b1 + matrix[0, 2] * b2) * f * radius)
    by = np.float32((matrix[1, 0] * b0 + matrix[1, 1] * b1 + matrix[1, 2] * b2) * f * radius)
    bw = np.float32((matrix[3, 0] * b0 + matrix[3, 1] * b1 + matrix[3, 2] * b2) * radius)
    bd = np.float32((axis[0] * b0 + axis[1] * b1 + axis[2] * b2) * radius)
    nx = np.float32((matrix[0, 0] * n0 + matrix[0, 1] * n1 + matrix[0, 2] * n2) * f * radius)
    ny = np.float32((matrix[1, 0] * n0 + matrix[1, 1] * n1 + matrix[1, 2] * n2) * f * radius)
    nw = np.float32((matrix[3, 0] * n0 + matrix[3, 1] * n1 + matrix[3, 2] * n2) * radius)
    nd = np.float32((axis[0] * n0 + axis[1] * n1 + axis[2] * n2) * radius)
    slack = np.float32(0.75 * slope * stride + 1e-5 * d)
    last_column, last_row = np.int32(columns - 1), np.int32(flat.shape[0] // columns - 1)
    across = np.int32(columns)
    right, bottom = np.float32(width / stride), np.float32(height / stride)
    zero, one, tiny, outside = np.float32(0.0), np.float32(1.0), np.float32(1e-30), np.int32(flat.shape[0] - 1)
    # every step of every ray (``steps``: its offset over R): the grid cell it falls in
    # (``outside``: off the image or behind the camera) and its axial depth, without branches
    # and in 32-bit numbers (LLVM works on eight at once)
    count = steps.shape[1]
    for m in range(count):
        a, b, c = steps[0, m], steps[1, m], steps[2, m]
        w = sw + a * tw + b * bw + c * nw
        scale = one / max(w, tiny)
        gx = (sx + a * tx + b * bx + c * nx) * scale
        gy = (sy + a * ty + b * by + c * ny) * scale
        inside = (w > zero) & (gx >= zero) & (gx < right) & (gy >= zero) & (gy < bottom)
        cell = min(np.int32(max(gy, zero)), last_row) * across + min(np.int32(max(gx, zero)), last_column)
        where[m] = cell if inside else outside
        along[m] = sd + a * td + b * bd + c * nd
    # a ray is blocked at a step behind the drawn surface by more than ``slack``, less than R
    for m in range(count):
        behind = along[m] - flat[where[m]]
        along[m] = one if (flat[where[m]] > zero) & (behind > slack) & (behind < r) else zero
    rays_count = count // STEPS
    blocked = 0
    for k in range(rays_count):
        hit = False
        for j in range(STEPS):
            hit |= along[j * rays_count + k] > zero
        blocked += hit
    return blocked / rays_count


@kernel(inline="always")
def _grid_pixel(i, stride, size):
    """The pixel (column or row) of grid point ``i``: the middle of its ``stride`` pixels."""
    return min(i * stride + stride // 2, size - 1)


@kernel(refcounts=False)
def ao_raw(slot, counter, view, flat, columns, rays, matrix, axis, steps, radius, stride, where, along, out,
           some):
    """``out`` (Hg, Wg) float32: the share of blocked rays at every ``stride``-th pixel of
    the frame's ``view`` (:func:`_metric`: its depth buffer (H, W) and camera range; -1
    where nothing was drawn in ``out``); grid point (i, j) is the pixel (``i stride + stride // 2``, likewise j), within
    the image, and ``flat`` (Hg Wg + 1,) float32 its depth, row by row (``columns`` = Wg a
    row), then a 0: what the rays are tested against.

    ``rays`` (6, 3) float64: the rows O0, Ox, Oy, V0, Vx, Vy of the world-space point
    ``O0 + x Ox + y Oy + d (V0 + x Vx + y Vy)`` at raster (x, y) with axial depth d;
    ``matrix`` (4, 4) float64 world -> homogeneous raster; ``axis`` (4,) float64: the axial
    depth of a world point, ``axis[:3] . q + axis[3]``; ``steps`` (16, 3, STEPS K) float32:
    for each rank of a 4x4 tile (:data:`TILE`) the steps of its K rays (step j of ray k at
    ``j K + k``), each a point of the ray over R in tangent space (a, b, c; c along the
    normal); ``radius`` > 0, world units. ``where`` (threads, STEPS K) int32 and ``along`` (threads, STEPS K) float32:
    each thread's scratch. ``some`` (Hg,) uint8: 1 where a share of the row is above 0. A
    worker of :func:`rasterkit.runtime.threads.run_workers` over ``N_CHUNKS`` pieces of rows."""
    height, width = view[0].shape
    rows = out.shape[0]
    cells, depths = where[slot], along[slot]
    while True:
        ch = fetch_add(counter, 0, 1)
        if ch >= N_CHUNKS:
            break
        for j in range(rows * ch // N_CHUNKS, rows * (ch + 1) // N_CHUNKS):
            y = _grid_pixel(j, stride, height)
            blocked = False
            for i in range(columns):
                x = _grid_pixel(i, stride, width)
                d = flat[j * columns + i]
                if d <= 0.0:
                    out[j, i] = -1.0
                    continue
                rank = TILE[(j & 3) * 4 + (i & 3)]
                share = _pixel_ao(view, flat, columns, stride, rays, matrix, axis, steps[rank], radius, x, y, d,
                                  width, height, cells, depths)
                out[j, i] = share
                blocked |= share > 0.0
            some[j] = blocked
    return 0


@kernel(refcounts=False)
def ao_grid(slot, counter, view, stride, out):
    """``out`` (Hg, Wg) float32: the axial depth (:func:`_metric`) at every grid point
    (:func:`ao_raw`'s)."""
    height, width = view[0].shape
    rows, columns = out.shape
    while True:
        ch = fetch_add(counter, 0, 1)
        if ch >= N_CHUNKS:
            break
        for j in range(rows * ch // N_CHUNKS, rows * (ch + 1) // N_CHUNKS):
            y = _grid_pixel(j, stride, height)
            for i in range(columns):
                out[j, i] = _metric(view, y, _grid_pixel(i, stride, width))
    return 0


@kernel(refcounts=False)
def ao_blur(slot, counter, grid, raw, some, radius, out):
    """``out`` (Hg, Wg) float32: each grid point's share of ``raw`` (Hg, Wg) (:func:`ao_raw`)
    averaged over the 4x4 grid points around it (i - 1 .. i + 2, j - 1 .. j + 2: a whole
    tile) whose depth (``grid``, :func:`ao_raw`'s) lies within ``radius / 2`` of its own; -1
    where nothing was drawn. ``some``: :func:`ao_raw`'s (rows whose shares are all 0 or -1
    average to themselves)."""
    rows, columns = out.shape
    half = np.float32(0.5 * radius)
    zero = np.float32(0.0)
    while True:
        ch = fetch_add(counter, 0, 1)
        if ch >= N_CHUNKS:
            break
        for j in range(rows * ch // N_CHUNKS, rows * (ch + 1) // N_CHUNKS):
            first, last = max(j - 1, 0), min(j + 3, rows)
            near = False
            for v in range(first, last):
                near |= some[v] != 0
            if not near:
                for i in range(columns):
                    out[j, i] = raw[j, i]
                continue
            for i in range(columns):
                if raw[j, i] < zero:
                    out[j, i] = -1.0
                    continue
                d = grid[j, i]
                total, weight = zero, zero
                for v in range(first, last):
                    for u in range(max(i - 1, 0), min(i + 3, columns)):
                        other = grid[v, u]
                        use = (other > zero) & (abs(other - d) < half)
                        total += raw[v, u] if use else zero
                        weight += np.float32(1.0) if use else zero
                out[j, i] = total / weight
    return 0


@kernel(inline="always")
def _nearest(d, s00, s01, s10, s11, g00, g01, g10, g11):
    """The share (of ``s``, those >= 0) of the grid point whose depth (``g``) is nearest ``d``."""
    share, gap = np.float32(0.0), np.float32(np.inf)
    for corner in range(4):
        s = s00 if corner == 0 else s01 if corner == 1 else s10 if corner == 2 else s11
        off = abs((g00 if corner == 0 else g01 if corner == 1 else g10 if corner == 2 else g11) - d)
        closer = (s >= np.float32(0.0)) & (off < gap)
        share = s if closer else share
        gap = off if closer else gap
    return share


@kernel(inline="always")
def _busy_cells(shares, j0, busy):
    """Marks in ``busy`` the cells of grid row ``j0`` (between it and the next) with a share
    above 0 at a corner (the others' drawn pixels are all 1); whether there are any."""
    rows, columns = shares.shape
    j1 = min(j0 + 1, rows - 1)
    some = False
    for i0 in range(columns):
        i1 = min(i0 + 1, columns - 1)
        high = max(max(shares[j0, i0], shares[j0, i1]), max(shares[j1, i0], shares[j1, i1]))
        busy[i0] = high > np.float32(0.0)
        some |= high > np.float32(0.0)
    return some


@kernel(inline="always")
def _cell_light(view, y, j0, i0, grid, shares, half, fractions, starts, light):
    """``light[x]`` for the pixels x of row ``y`` in cell (j0, i0): one minus the share of
    blocked rays interpolated bilinearly from the cell's corners drawn (share >= 0) within
    ``half`` in depth of the pixel (the nearest in depth when none is), NaN where nothing was
    drawn."""
    rows, columns = shares.shape
    height = view[0].shape[0]
    zero, one = np.float32(0.0), np.float32(1.0)
    j1, i1 = min(j0 + 1, rows - 1), min(i0 + 1, columns - 1)
    fy = fractions[y]
    gy = one - fy
    s00, s01, s10, s11 = shares[j0, i0], shares[j0, i1], shares[j1, i0], shares[j1, i1]
    g00, g01, g10, g11 = grid[j0, i0], grid[j0, i1], grid[j1, i0], grid[j1, i1]
    for x in range(starts[rows + 1 + i0], starts[rows + 1 + i0 + 1]):
        d = _metric(view, y, x)
        if d <= zero:
            light[x] = np.float32(np.nan)
            continue
        fx = fractions[height + x]
        w00 = gy * (one - fx) if (s00 >= zero) & (abs(g00 - d) < half) else zero
        w01 = gy * fx if (s01 >= zero) & (abs(g01 - d) < half) else zero
        w10 = fy * (one - fx) if (s10 >= zero) & (abs(g10 - d) < half) else zero
        w11 = fy * fx if (s11 >= zero) & (abs(g11 - d) < half) else zero
        weight = (w00 + w01) + (w10 + w11)
        if weight > np.float32(1e-6):
            light[x] = one - ((w00 * s00 + w01 * s01) + (w10 * s10 + w11 * s11)) / weight
        else:
            light[x] = one - _nearest(d, s00, s01, s10, s11, g00, g01, g10, g11)


@kernel(refcounts=False)
def ao_shade(slot, counter, view, grid, shares, radius, fractions, starts, marks, light, color, decode, encode):
    """The RGB of ``color`` (H, W, C) uint8 sRGB multiplied in linear light by the light that
    reaches each pixel drawn (:func:`ao_fill`'s value) where it is below 1 (``decode`` (256,)
    float32 sRGB -> linear, ``encode`` (S,) uint8 linear ``i / (S - 1)`` -> sRGB): only the
    pixels of cells with a share above 0 at a corner are read. ``marks`` (threads, Wg) uint8 and
    ``light`` (threads, W) float32: each thread's scratch. A worker over ``N_CHUNKS`` pieces of
    grid rows."""
    rows, columns = shares.shape
    half = np.float32(0.5 * radius)
    one = np.float32(1.0)
    top = np.float32(encode.shape[0] - 1)
    busy, values = marks[slot], light[slot]
    while True:
        ch = fetch_add(counter, 0, 1)
        if ch >= N_CHUNKS:
            break
        for j0 in range(rows * ch // N_CHUNKS, rows * (ch + 1) // N_CHUNKS):
            if not _busy_cells(shares, j0, busy):
                continue
            for y in range(starts[j0], starts[j0 + 1]):
                for i0 in range(columns):
                    if not busy[i0]:
                        continue
                    _cell_light(view, y, j0, i0, grid, shares, half, fractions, starts, values)
                    for x in range(starts[rows + 1 + i0], starts[rows + 1 + i0 + 1]):
                        if values[x] < one:
                            scale = values[x] * top
                            for c in range(3):
                                color[y, x, c] = encode[int(decode[color[y, x, c]] * scale + np.float32(0.5))]
    return 0


@kernel(refcounts=False)
def ao_fill(slot, counter, view, grid, shares, radius, fractions, starts, marks, out):
    """``out`` (H, W) float32: one minus the share of blocked rays at each pixel drawn in
    ``view`` (:func:`_metric`; NaN elsewhere), interpolated bilinearly from the grid
    ``shares`` (Hg, Wg) (:func:`ao_blur`) among the grid points whose depth (``grid``) lies
    within ``radius / 2`` of the pixel's (the nearest in depth when none does).

    ``fractions`` (H + W,) float32: each row's, then each column's, weight of the grid point
    after it; ``starts`` (Hg + 1 + Wg + 1,) int64: the first row between each grid row and
    the next (then H), then the same for columns (then W). ``marks`` (threads, Wg) uint8:
    each thread's scratch. A worker over ``N_CHUNKS`` pieces of grid rows."""
    width = view[0].shape[1]
    rows, columns = shares.shape
    nan = np.float32(np.nan)
    half = np.float32(0.5 * radius)
    zero, one = np.float32(0.0), np.float32(1.0)
    busy = marks[slot]
    while True:
        ch = fetch_add(counter, 0, 1)
        if ch >= N_CHUNKS:
            break
        for j0 in range(rows * ch // N_CHUNKS, rows * (ch + 1) // N_CHUNKS):
            some = _busy_cells(shares, j0, busy)
            for y in range(starts[j0], starts[j0 + 1]):
                row = out[y]
                for x in range(width):
                    row[x] = one if _metric(view, y, x) > zero else nan  # noqa: FURB136
                if some:
                    for i0 in range(columns):
                        if busy[i0]:
                            _cell_light(view, y, j0, i0, grid, shares, half, fractions, starts, row)
    return 0
