"""Driver of the vector hidden-line path: clip the edges, draw the faces' ids, split the
edges where they pass behind a face (:mod:`rasterkit.svg.kernels.visibility`).

Tolerances (documented in ``docs/svg.md``): samples every :data:`STEP` pixels along each
edge, visibility changes found by bisection to :data:`TOLERANCE` pixels, a face hides a line
when it is more than :data:`DEPTH_EPS` (depth units, 0 at the near plane and 1 at the far
one) in front of it; pieces cut off by a change of visibility shorter than :data:`MIN_PIECE`
pixels are left out.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rasterkit.runtime.jit import readonly
from rasterkit.runtime.threads import get_threads, run_workers
from rasterkit.svg.kernels import visibility as _kernels
from rasterkit.raster.triangles import rasterize_triangles

__all__ = ["DEPTH_EPS", "MIN_PIECE", "STEP", "TOLERANCE", "Pieces", "clip_segments", "split_visible"]

#: Distance between the samples along an edge, pixels.
STEP = 0.5
#: Visibility changes are located to this many pixels along the edge.
TOLERANCE = 1e-3
#: Pieces of an edge cut off by a change of visibility shorter than this (pixels) are left
#: out: specks a plotter would dot, below the raster's resolution.
MIN_PIECE = 0.5
#: A face hides a point of a line when its depth there is smaller by more than this.
DEPTH_EPS = 1e-7
#: The same for a face with a corner behind the eye, tested against the depth buffer.
DEPTH_EPS_BUFFER = 1e-4

#: Run boundaries kept per segment in the first pass (segments with more are done again).
_SLOTS = 6


@dataclass(frozen=True)
class Pieces:
    """Straight pieces of the drawing, raster space.

    ``xy`` (P, 4) float64: x0, y0, x1, y1 in pixels; ``edge`` (P,) int64: the edge they
    belong to; ``hidden`` (P,) bool; ``keys`` (P, 2) int64: for each end, the mesh vertex
    it is (an unclipped, unsplit end), else -1.
    """

    xy: np.ndarray
    edge: np.ndarray
    hidden: np.ndarray
    keys: np.ndarray


def clip_segments(clip: np.ndarray, edges: np.ndarray, width: int, height: int):
    """Clip the edges (E, 2) of the homogeneous raster-space vertices ``clip`` (N, 4) to the
    view volume: the near and far planes and the image rectangle (Liang-Barsky, in
    homogeneous space, so edges crossing the eye's plane clip right).

    Returns ``(kept (S,) int64 edge indices, seg (S, 6) float64 raster x, y, z of both
    ends, t (S, 2) float64 the ends' parameters on the homogeneous edge)``; edges with a
    NaN or infinite end are dropped.
    """
    seg = np.empty((len(edges), 6))
    t = np.empty((len(edges), 2))
    kept = _kernels.clip_edges(readonly(clip), readonly(edges), float(width), float(height), seg, t)
    return kept, seg[: len(kept)], t[: len(kept)]


def _vertex_raster(clip: np.ndarray):
    """Raster x, y, z (N, 3) float64 and a flag (N,) uint8: in front of the eye and finite."""
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        proj = clip[:, :3] / clip[:, 3:]
        front = (clip[:, 3] > 0) & np.all(np.isfinite(proj), axis=1)
    return np.ascontiguousarray(np.where(front[:, None], proj, 0.0)), front.astype(np.uint8)


def depth_pass(clip: np.ndarray, faces: np.ndarray, width: int, height: int, cull="back"):
    """Depth (H, W) float32 and face ids (H, W) int32 of the faces, back faces culled (``cull``:
    or per face, :func:`rasterkit.raster.sides.face_sides`: double-sided ones are not)."""
    depth = np.empty((height, width), np.float32)
    ids = np.empty((height, width), np.int32)
    rasterize_triangles(None, depth, clip, faces, ids=ids, cull=cull, clear=())
    return depth, ids


def split_visible(clip: np.ndarray, faces: np.ndarray, edges: np.ndarray, width: int, height: int,
                  visibility: bool = True, cull="back") -> Pieces:
    """The edges (E, 2) of the vertices ``clip`` (N, 4) (homogeneous raster space), clipped
    to the view volume and, with ``visibility``, split into visible and hidden pieces by the
    faces (M, 3) that ``cull`` (:func:`depth_pass`) leaves."""
    kept, seg, t = clip_segments(clip, edges, width, height)
    ends = np.ascontiguousarray(edges[kept])
    if not visibility or len(seg) == 0:
        return _pieces(seg, kept, ends, t, np.ones(len(seg), np.int64), np.zeros((len(seg), 2)),
                       np.zeros(len(seg), np.uint8))
    depth, ids = depth_pass(clip, faces, width, height, cull)
    proj, front = _vertex_raster(clip)
    rec = np.empty((len(faces), _kernels.REC_FIELDS))
    _kernels.face_records(proj, front, readonly(faces), rec)
    args = (rec, ids, depth, STEP, TOLERANCE, DEPTH_EPS, DEPTH_EPS_BUFFER)
    n_seg = len(seg)
    out_t = np.empty((n_seg, _SLOTS))
    out_n = np.empty(n_seg, np.int64)
    out_first = np.empty(n_seg, np.uint8)
    threads = 1 if n_seg < 4 * _kernels.CHUNK else get_threads()
    run_workers(_kernels.visible_runs, seg, ends, np.arange(n_seg, dtype=np.int64), *args, out_t, out_n,
                out_first, threads=threads)
    redo = np.flatnonzero(out_n > _SLOTS - 1)
    if len(redo):  # many changes on one edge: again, with room for all of them
        slots = int(out_n[redo].max()) + 1
        more_t = np.empty((len(redo), slots))
        run_workers(_kernels.visible_runs, seg, ends, redo, *args, more_t, out_n[redo].copy(),
                    out_first[redo].copy(), threads=1)
        return _pieces(seg, kept, ends, t, out_n, out_t, out_first, redo, more_t)
    return _pieces(seg, kept, ends, t, out_n, out_t, out_first)


def _pieces(seg, kept, ends, t, n_runs, out_t, first, redo=None, more_t=None) -> Pieces:
    """Pieces from the runs of every segment (states alternate from ``first``)."""
    if len(seg) == 0:
        empty = np.zeros((0, 2), np.int64)
        return Pieces(np.zeros((0, 4)), np.zeros(0, np.int64), np.zeros(0, bool), empty)
    # the runs, flat and in segment order: (segment, run index, start, end), taken from the
    # first pass's slots, or from the second pass's rows for the segments that overflowed
    fits = np.flatnonzero(n_runs <= out_t.shape[1] - 1)
    rows = [(fits, out_t[fits])]
    if redo is not None:
        rows.append((redo, more_t))
    s_parts, r_parts, u0_parts, u1_parts = [], [], [], []
    for segs, bounds in rows:
        bounds[np.arange(len(segs)), n_runs[segs]] = 1.0  # the kernel ends each row with 1.0 too
        valid = np.arange(bounds.shape[1] - 1)[None, :] < n_runs[segs][:, None]
        row, col = np.nonzero(valid)
        s_parts.append(segs[row])
        r_parts.append(col)
        u0_parts.append(bounds[row, col])
        u1_parts.append(bounds[row, col + 1])
    s_idx = np.concatenate(s_parts)
    order = np.argsort(s_idx, kind="stable")
    s_idx = s_idx[order]
    r_idx, u0, u1 = (np.concatenate(a)[order] for a in (r_parts, u0_parts, u1_parts))
    hidden = ((first[s_idx].astype(np.int64) + r_idx) % 2).astype(bool)
    p0, p1 = seg[s_idx, :2], seg[s_idx, 3:5]
    d = p1 - p0
    # a piece cut off by a change of visibility shorter than MIN_PIECE is a speck (an edge
    # leaving a vertex just before it passes behind a face): left out; whole edges stay
    long = ((u1 - u0) * np.hypot(d[:, 0], d[:, 1]) >= MIN_PIECE) | (n_runs[s_idx] == 1)
    s_idx, r_idx, u0, u1, hidden, p0, d = (a[long] for a in (s_idx, r_idx, u0, u1, hidden, p0, d))
    xy = np.concatenate([p0 + u0[:, None] * d, p0 + u1[:, None] * d], axis=1)
    keys = np.full((len(s_idx), 2), -1, np.int64)
    at_start = (u0 == 0.0) & (t[s_idx, 0] == 0.0)
    at_end = (u1 == 1.0) & (t[s_idx, 1] == 1.0)
    keys[at_start, 0] = ends[s_idx[at_start], 0]
    keys[at_end, 1] = ends[s_idx[at_end], 1]
    xy[at_start, :2] = seg[s_idx[at_start], :2]
    xy[at_end, 2:] = seg[s_idx[at_end], 3:5]
    return Pieces(np.ascontiguousarray(xy), kept[s_idx], hidden, keys)
