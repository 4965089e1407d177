"""Vector lines through a lens: the straight pieces of a drawing made by the undistorted
camera of :func:`rasterkit.raster.distortion.vector_plan`, as the curves a camera with OpenCV's
distortion model sees.

Each piece is cut in two at its middle until every part lies within :data:`TOLERANCE`
pixels of its chord in the distorted image (checked at its middle and quarter points, where
a smooth arc is furthest from its chord), then its ends are moved through the
:class:`~rasterkit.raster.distortion.Lens`. Parts beyond the model's fold (where the image shows
nothing, as in the raster image) are left out, their boundary found by the same halving to
:data:`FOLD_TOLERANCE` pixels; parts are then clipped to the image rectangle. The parts of
one piece share new keys where they meet, so the path planning joins them again into one
polyline (:mod:`rasterkit.svg.paths`).
"""

from __future__ import annotations

import numpy as np

from rasterkit.limits import check_memory

__all__ = ["FOLD_TOLERANCE", "TOLERANCE", "distort_pieces"]

#: Largest distance (distorted pixels) between a drawn part and the curve it stands for:
#: below the drawing's 1/100 pixel coordinates.
TOLERANCE = 0.004
#: Parts are not cut shorter than this (distorted pixels): the curve's error bound where the
#: distortion bends a line tighter than a pixel's radius.
MIN_PART = 0.05
#: The fold's crossing of a piece is located to this many ideal pixels.
FOLD_TOLERANCE = 1e-4
#: Parts wholly beyond the fold at all five samples are cut down to this many ideal pixels
#: (the region the image shows is a disc about the centre, bent at most gently at this scale).
_BEYOND = 4.0
#: Halvings at most (a piece of 2^40 pixels ends in parts below 1e-4 pixels).
_DEPTH = 48
#: Bytes per part while they are cut (its parameters, points and keys, twice over).
_PART_BYTES = 400


def _off_chord(a, b, p):
    """Distance (K,) of the points p (K, 2) from the lines through a and b (K, 2)."""
    d = b - a
    length = np.hypot(d[:, 0], d[:, 1])
    cross = np.abs(d[:, 0] * (p[:, 1] - a[:, 1]) - d[:, 1] * (p[:, 0] - a[:, 0]))
    with np.errstate(invalid="ignore", divide="ignore"):
        off = np.where(length > 0.0, cross / length, np.hypot(*(p - a).T))
    return off, length


def distort_pieces(xy: np.ndarray, keys: np.ndarray, lens, width: int, height: int, first_key: int):
    """The pieces ``xy`` (P, 4) (ideal raster x0, y0, x1, y1) as distorted parts.

    Returns ``(xy (Q, 4) distorted raster, keys (Q, 2), piece (Q,) int64)``: each part's ends,
    their keys (the piece's keys at its unclipped ends, new keys from ``first_key`` where two
    parts of a piece meet, -1 at a fold or the image border) and the piece it belongs to.
    """
    p0, d = xy[:, :2], xy[:, 2:] - xy[:, :2]
    ideal_length = np.hypot(d[:, 0], d[:, 1])
    piece = np.arange(len(xy), dtype=np.int64)
    t0, t1 = np.zeros(len(xy)), np.ones(len(xy))
    k0, k1 = keys[:, 0].copy(), keys[:, 1].copy()
    next_key = first_key
    out = []

    def at(t, owner):
        q = p0[owner] + t[:, None] * d[owner]
        u, v, ok = lens(q[:, 0], q[:, 1])
        return np.c_[u, v], ok

    for level in range(_DEPTH + 1):
        if len(piece) == 0:
            break
        check_memory(len(piece) * _PART_BYTES, f"distorting {len(piece)} parts of an SVG's lines")
        a, a_ok = at(t0, piece)
        b, b_ok = at(t1, piece)
        samples = [at(t0 + f * (t1 - t0), piece) for f in (0.25, 0.5, 0.75)]
        all_ok = a_ok & b_ok & samples[0][1] & samples[1][1] & samples[2][1]
        any_ok = a_ok | b_ok | samples[0][1] | samples[1][1] | samples[2][1]
        with np.errstate(invalid="ignore"):
            off = np.zeros(len(piece))
            for p, _ in samples:
                off = np.maximum(off, _off_chord(a, b, p)[0])
            chord = np.hypot(*(b - a).T)
        span = (t1 - t0) * ideal_length[piece]  # ideal pixels
        last = level == _DEPTH
        # good: drawn as it is; cut: halved; the rest (beyond the fold) left out
        good = all_ok & ((off <= TOLERANCE) | (chord < MIN_PART) | last)
        fold = any_ok & ~all_ok  # crosses the fold: cut down to FOLD_TOLERANCE
        cut = ~good & ((all_ok & (not last)) | (fold & (span > FOLD_TOLERANCE)) | (~any_ok & (span > _BEYOND)))
        ends_ok = fold & ~cut & a_ok & b_ok  # a fold's last cut with both ends shown: drawn
        keep = good | ends_ok
        if keep.any():
            open_a = fold[keep] | ~a_ok[keep]
            open_b = fold[keep] | ~b_ok[keep]
            out.append((np.c_[a[keep], b[keep]], np.where(open_a, -1, k0[keep]),
                        np.where(open_b, -1, k1[keep]), piece[keep]))
        if not cut.any():
            break
        mid = 0.5 * (t0[cut] + t1[cut])
        new = np.arange(next_key, next_key + int(cut.sum()), dtype=np.int64)
        next_key += len(new)
        piece = np.repeat(piece[cut], 2)
        t0 = np.column_stack([t0[cut], mid]).reshape(-1)
        t1 = np.column_stack([mid, t1[cut]]).reshape(-1)
        k0 = np.column_stack([k0[cut], new]).reshape(-1)
        k1 = np.column_stack([new, k1[cut]]).reshape(-1)
    if not out:
        return np.zeros((0, 4)), np.zeros((0, 2), np.int64), np.zeros(0, np.int64)
    parts = np.concatenate([o[0] for o in out])
    part_keys = np.column_stack([np.concatenate([o[1] for o in out]), np.concatenate([o[2] for o in out])])
    owner = np.concatenate([o[3] for o in out])
    return _clip(parts, part_keys, owner, width, height)


def _clip(xy, keys, owner, width, height):
    """The parts clipped to the image rectangle [0, width] x [0, height] (Liang-Barsky);
    a clipped end loses its key."""
    a, d = xy[:, :2], xy[:, 2:] - xy[:, :2]
    lo, hi = np.zeros(len(xy)), np.ones(len(xy))
    with np.errstate(divide="ignore", invalid="ignore"):
        for axis, size in ((0, width), (1, height)):
            for p, q in ((-d[:, axis], a[:, axis]), (d[:, axis], size - a[:, axis])):
                r = q / p
                parallel = p == 0.0
                lo = np.where(~parallel & (p < 0.0), np.maximum(lo, r), lo)
                hi = np.where(~parallel & (p > 0.0), np.minimum(hi, r), hi)
                hi = np.where(parallel & (q < 0.0), -1.0, hi)  # parallel and outside
    inside = lo < hi
    xy, a, d, lo, hi, keys, owner = xy[inside], a[inside], d[inside], lo[inside], hi[inside], keys[inside], owner[inside]
    start, end = lo > 0.0, hi < 1.0
    xy[start, :2] = a[start] + lo[start, None] * d[start]
    xy[end, 2:] = a[end] + hi[end, None] * d[end]
    keys[start, 0] = -1
    keys[end, 1] = -1
    return xy, keys, owner
