"""The raster of a triangle setup shared by the samples of a multi-sample render: a record
drawn at a sample point, or the records moved to one.

A pinhole render with ``samples > 1`` sets its faces up once (:mod:`rasterkit.raster.shared_samples`)
and draws them at each sample point ``P + (sx, sy) / 256`` of every pixel ``P``, which is the
same, to the bit, as drawing the snapped vertices moved by ``-(sx, sy)``:
:func:`raster_band_at` draws one record that way, :func:`move_records` moves every record for
today's band raster (:func:`rasterkit.raster.kernels.triangle.raster_band`).
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel
from rasterkit.runtime.intrinsics import fetch_add
from rasterkit.raster.kernels.face_setup import N_CHUNKS, chunk_range, pixel_bounds
from rasterkit.raster.kernels.triangle import raster_vertices


@kernel(inline="always")
def moved_box(x0, y0, x1, y1, x2, y2, width, y_lo, y_hi):
    """The pixel box of a fixed-point triangle as :func:`rasterkit.raster.kernels.face_setup.setup_triangle`
    bounds it, its columns clamped to ``0 .. width - 1`` and its rows to ``y_lo .. y_hi``;
    ``(0, -1, 0, -1)`` when empty."""
    i_lo, i_hi = pixel_bounds(min(x0, x1, x2), max(x0, x1, x2))
    j_lo, j_hi = pixel_bounds(min(y0, y1, y2), max(y0, y1, y2))
    i_lo, i_hi = max(i_lo, 0), min(i_hi, width - 1)
    j_lo, j_hi = max(j_lo, y_lo), min(j_hi, y_hi)
    if i_lo > i_hi or j_lo > j_hi:
        return np.int64(0), np.int64(-1), np.int64(0), np.int64(-1)
    return i_lo, i_hi, j_lo, j_hi


@kernel(inline="always")
def raster_band_at(t, tag, tri_xy, tri_z, sample, y0, y1, depth, lid, row_lo, row_hi):
    """:func:`rasterkit.raster.kernels.triangle.raster_band` of record ``t`` sampled at ``sample``
    from the pixel centres.

    Sampling each pixel at ``P + (sx, sy) / 256`` instead of its centre ``P`` is the same,
    to the bit, as drawing the record whose snapped vertices are moved by ``-(sx, sy)``
    (what the setup makes of a scene whose raster image is moved by the same exact
    amount): the edge functions, the depth plane and the box (:func:`moved_box`) are those
    of the moved vertices, the top-left rule (which depends on the edges' directions only)
    included. ``sample`` is a :class:`rasterkit.raster.kernels.records.Sample`; the records come
    from a setup with padded boxes (their boxes are not read).
    """
    sx, sy = sample
    x0, y0_, x1 = np.int64(tri_xy[t, 0]) - sx, np.int64(tri_xy[t, 1]) - sy, np.int64(tri_xy[t, 2]) - sx
    y1_, x2, y2 = np.int64(tri_xy[t, 3]) - sy, np.int64(tri_xy[t, 4]) - sx, np.int64(tri_xy[t, 5]) - sy
    i_lo, i_hi, j_lo, j_hi = moved_box(x0, y0_, x1, y1_, x2, y2, np.int64(depth.shape[1]), np.int64(y0),
                                       np.int64(y1) - 1)
    if j_lo > j_hi:
        return 0
    return raster_vertices(x0, y0_, x1, y1_, x2, y2, tri_z, t, i_lo, i_hi, j_lo, j_hi, tag, y0, depth, lid, row_lo,
                           row_hi)


@kernel
def move_records(slot, counter, records, moved, n_records, sample, width, height):
    """The records moved to a sample point: ``moved.xy`` the vertices moved by ``-sample``
    (fixed point), ``moved.box`` their box (:func:`moved_box`, clamped to the image), for
    every record whose (padded) box is not empty; the others get an empty box. Drawing the
    moved records with :func:`rasterkit.raster.kernels.triangle.raster_band` samples the records at ``sample``, to the bit
    as :func:`raster_band_at` does. A worker of :func:`rasterkit.runtime.threads.run_parallel`
    (``slot`` unused; the records are shared out in N_CHUNKS chunks through ``counter``).
    """
    tri_xy, _, tri_box = records
    xy, _, box = moved
    sx, sy = sample
    while True:  # claim the next piece until none is left
        ch = fetch_add(counter, 0, 1)
        if ch >= N_CHUNKS:
            break
        start, stop = chunk_range(n_records, ch)
        for t in range(start, stop):
            if tri_box[t, 2] > tri_box[t, 3]:
                box[t, 0], box[t, 1], box[t, 2], box[t, 3] = 0, -1, 0, -1
                continue
            for k in range(3):
                xy[t, 2 * k] = tri_xy[t, 2 * k] - sx
                xy[t, 2 * k + 1] = tri_xy[t, 2 * k + 1] - sy
            box[t, 0], box[t, 1], box[t, 2], box[t, 3] = moved_box(
                np.int64(xy[t, 0]), np.int64(xy[t, 1]), np.int64(xy[t, 2]), np.int64(xy[t, 3]),
                np.int64(xy[t, 4]), np.int64(xy[t, 5]), np.int64(width), np.int64(0), np.int64(height) - 1)
