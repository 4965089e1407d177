"""Faces cut by a clipping plane become fans of records (the setup stage's second part).

:func:`rasterkit.raster.kernels.face_setup.setup_faces` flags the faces that cross the near or far
plane or the guard band; :func:`count_fans` cuts each (Sutherland–Hodgman,
:func:`rasterkit.raster.kernels.clip.cut_face`) to count its triangles, the driver makes room for
them, and :func:`setup_cut_faces` cuts them again and sets the triangles up as records
numbered from M up. Cutting twice costs less than keeping every cut polygon between the
passes, and only the few faces near a plane are cut.
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel
from rasterkit.raster.kernels.clip import MAX_POLYGON, clip_planes, cut_face
from rasterkit.raster.kernels.cull import per_face
from rasterkit.runtime.intrinsics import fetch_add
from rasterkit.raster.kernels.face_setup import (
    N_CHUNKS,
    N_STATUS,
    STATUS_DRAWN,
    STATUS_OUTSIDE,
    chunk_range,
    count_bands,
    setup_triangle,
    snap,
)


@kernel
def _count_fan_chunk(ch, clip, faces, planes, cut_mask, n_fan):
    """:func:`count_fans` for the faces of chunk ``ch``; returns their record count."""
    p = np.empty((MAX_POLYGON, 3))
    start, stop = chunk_range(faces.shape[0], ch)
    records = 0
    for f in range(start, stop):
        if cut_mask[f] != 0:
            n_fan[f] = max(cut_face(clip, faces, f, planes, np.int64(cut_mask[f]), p) - 2, 0)
            records += n_fan[f]
    return records


@kernel
def count_fans(slot, counter, clip, faces, width, height, cut_mask, n_fan, records):
    """Cut pass 1: cut the faces flagged by :func:`setup_faces` to count their records.

    Parameters
    ----------
    clip, faces, width, height
        As for :func:`setup_vertices` and :func:`setup_faces`.
    cut_mask : (M,) int8
        From :func:`setup_faces`.
    n_fan : (M,) int8
        Out: records (fan triangles) of each cut face; left alone for the others.

    records : (N_CHUNKS,) int64
        Out: records needed by the cut faces of each chunk.

    A worker of :func:`rasterkit.runtime.threads.run_parallel` (``slot`` unused).
    """
    planes = clip_planes(width, height)
    while True:  # claim the next piece until none is left
        ch = fetch_add(counter, 0, 1)
        if ch >= N_CHUNKS:
            break
        records[ch] = _count_fan_chunk(ch, clip, faces, planes, cut_mask, n_fan)


@kernel
def _setup_fan_chunk(ch, clip, faces, width, height, cull_mode, pad, planes, t, fan_face, records, cuts, counts):
    """:func:`setup_cut_faces` for the faces of chunk ``ch``, from record ``t`` on."""
    tri_xy, tri_z, tri_box = records
    cut_mask = cuts.mask
    band_shift, band_counts, tally = counts
    p = np.empty((MAX_POLYGON, 3))
    start, stop = chunk_range(faces.shape[0], ch)
    m = faces.shape[0]
    for f in range(start, stop):
        if cut_mask[f] == 0:
            continue
        n = cut_face(clip, faces, f, planes, np.int64(cut_mask[f]), p)
        best = STATUS_OUTSIDE
        for k in range(1, n - 1):
            fan_face[t - m] = f
            x0, y0, x1, y1 = snap(p[0, 0]), snap(p[0, 1]), snap(p[k, 0]), snap(p[k, 1])
            x2, y2 = snap(p[k + 1, 0]), snap(p[k + 1, 1])
            drawn = setup_triangle(
                x0,
                y0,
                p[0, 2],
                x1,
                y1,
                p[k, 2],
                x2,
                y2,
                p[k + 1, 2],
                width,
                height,
                per_face(cull_mode, f),
                pad,
                t,
                tri_xy,
                tri_z,
                tri_box,
            )
            if drawn == STATUS_DRAWN:
                count_bands(t, tri_box, band_shift, band_counts, ch)
            best = min(best, drawn)
            t += 1
        tally[ch, STATUS_OUTSIDE] -= 1  # what setup_faces counted it as
        tally[ch, best] += 1
        tally[ch, N_STATUS] += best != STATUS_OUTSIDE


@kernel
def setup_cut_faces(slot, counter, clip, faces, width, height, cull_mode, pad, fan_start, fan_face, records, cuts,
                    counts):
    """Cut pass 2: cut the flagged faces again and set up their fans.

    The fans of chunk ``ch`` go to consecutive records from ``fan_start[ch]`` (>= M), in
    face order (binning walks them in the same order); ``fan_face[t - M]`` is the face of
    fan record ``t``. A cut face is STATUS_DRAWN when any of its triangles is drawn, else
    STATUS_CULLED when any is culled, else STATUS_EMPTY (STATUS_OUTSIDE when nothing was
    left of it). Drawn fan records are added to ``counts.bands``, and the new statuses to
    ``counts.tally``, as in :func:`setup_faces` (``records``, ``cuts`` and ``counts`` are its
    named records, :mod:`rasterkit.raster.kernels.records`); ``pad`` as for
    :func:`rasterkit.raster.kernels.face_setup.setup_triangle`. A worker of :func:`rasterkit.runtime.threads.run_parallel`
    (``slot`` unused).
    """
    planes = clip_planes(width, height)
    while True:  # claim the next piece until none is left
        ch = fetch_add(counter, 0, 1)
        if ch >= N_CHUNKS:
            break
        _setup_fan_chunk(ch, clip, faces, width, height, cull_mode, pad, planes, fan_start[ch], fan_face, records,
                         cuts, counts)
