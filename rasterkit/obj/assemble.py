"""From the checked statements of an OBJ file to the arrays of its Mesh: finite vertices, the
triangles (fans by NumPy, the rest by the polygon kernels) as the corners of their polygons,
edges, and the group and material of each triangle. (The attributes of the corners:
:mod:`rasterkit.obj.attributes`.)"""

from __future__ import annotations

import numpy as np

from rasterkit.obj.errors import count
from rasterkit.obj.split import split_in_numpy
from rasterkit.obj.statements import Elements, latest_above, per_triangle
from rasterkit.obj.kernels import polygons as obj_polygons
from rasterkit.obj.kernels.fans import simple_polygons
from rasterkit.obj.kernels.scan import KIND_USEMTL, KIND_V

__all__ = ["face_labels", "face_materials", "finite_vertices", "split_polygons", "triangulate"]


def finite_vertices(doc, vertices, faces, lines, report) -> np.ndarray:
    """(N,) bool: vertices with finite coordinates; warns about the others."""
    finite = np.isfinite(vertices).all(axis=1)
    if not finite.all():
        first = doc.line(doc.of_kind(KIND_V)[np.argmin(finite)])
        dropped_faces = faces.count - np.count_nonzero(faces.uses_only(finite))
        dropped_lines = lines.count - np.count_nonzero(lines.uses_only(finite))
        report.warn(first, f"{count(np.count_nonzero(~finite), 'vertex', 'vertices')} with "
                           f"NaN or infinite coordinates; {count(dropped_faces, 'face')} and "
                           f"{count(dropped_lines, 'line')} using them dropped")
    return finite


def triangulate(doc, vertices, faces: Elements, keep: np.ndarray, report):
    """Triangles (M, 3) int64 of the kept polygons as their corners (indices into
    ``faces.vertex``, ``faces.texcoord`` and ``faces.normal``), and the polygon (M,) of
    each; warns about polygons that could not be split exactly."""
    if faces.count == 0:
        return np.zeros((0, 3), np.int64), np.zeros(0, np.int64)
    triangles, counts, inexact = split_polygons(vertices, faces.vertex, faces.offsets, keep)
    if inexact.any():
        first = faces.statements[np.argmax(inexact)]
        report.warn(doc.line(first), f"{count(np.count_nonzero(inexact), 'polygon')} too "
                                     "irregular to split exactly (self-intersecting?): split "
                                     "as a fan")
    return triangles, np.repeat(np.arange(faces.count), counts)


#: A triangle row (three int64) as one item of NumPy's fancy indexing.
_ROW = np.dtype((np.void, 24))


def split_polygons(vertices, corners, offsets, keep):
    """The triangles (T, 3) int64 of the kept polygons in polygon order, as corners (indices
    into ``corners``, the vertex index of each corner: a triangle's vertices are
    ``corners[triangles]``), the count (P,) of each polygon's and whether (P,) it could not
    be split exactly: triangles and convex quads by :mod:`rasterkit.obj.kernels.fans`, the
    others by NumPy where it can (:mod:`rasterkit.obj.split`), by the kernels of
    :mod:`rasterkit.obj.kernels.polygons` (compiled on first use) where not.
    Triangles that a repeated vertex makes degenerate are left out."""
    simple, simple_counts, left = simple_polygons(vertices, corners, offsets, keep)
    inexact = np.zeros(len(keep), bool)
    if not left.any():  # triangles and convex quads: all split in one pass
        return simple, simple_counts, inexact
    # the few polygons left, as a file of their own (their corners gathered: ``at``)
    which = np.flatnonzero(left)
    sizes = offsets[which + 1] - offsets[which]
    own = np.zeros(len(which) + 1, np.int64)
    np.cumsum(sizes, out=own[1:])
    at = np.repeat(offsets[which] - own[:-1], sizes) + np.arange(own[-1])
    rest, rest_counts, inexact[which] = _split_others(vertices, corners[at], own)
    # each polygon's rows come from one of the two: rest's go between simple's, at the rows
    # of the polygons before them and of the rest's before them
    before = np.cumsum(simple_counts) - simple_counts
    placed = np.repeat(before[which], rest_counts) + np.arange(len(rest))
    triangles = np.empty((len(simple) + len(rest), 3), np.int64)
    others = np.ones(len(triangles), bool)
    others[placed] = False
    rows = triangles.view(_ROW).ravel()  # rows as single items: one copy each, not three
    rows[others] = simple.view(_ROW).ravel()
    rows[placed] = at[rest].view(_ROW).ravel()
    counts = simple_counts.copy()
    counts[which] = rest_counts
    return triangles, counts, inexact


def _split_others(vertices, corners, offsets):
    """split_polygons' triangles (T, 3), counts (P,) and inexact (P,) of polygons that are
    not triangles or convex quads (all kept): by NumPy where it can, by the kernels where
    not."""
    polygons = len(offsets) - 1
    parts, inexact, left = split_in_numpy(vertices, corners, offsets, np.ones(polygons, bool))
    parts = [(np.repeat(polygons_, rows.shape[1]), rows.reshape(-1, 3)) for polygons_, rows in parts]
    if left.any():
        split, counts, state = obj_polygons.triangulate(vertices, corners, offsets, left)
        inexact |= state == obj_polygons.INEXACT
        parts.append((np.repeat(np.arange(polygons), counts), split))
        for p in np.flatnonzero(state == obj_polygons.LARGE):
            rows, exact = obj_polygons.split_large(vertices, corners[offsets[p]:offsets[p + 1]].copy())
            inexact[p] = not exact
            parts.append((np.full(len(rows), p), np.where(rows >= 0, rows + offsets[p], -1)))
    rest, counts = _in_polygon_order(parts, polygons, corners)
    return rest, counts, inexact


def _in_polygon_order(parts, polygons: int, corners: np.ndarray):
    """The triangles of parts [(polygon of each row (K,), rows (K, 3) of corners)] merged
    into polygon order (each polygon's rows come from one part, in order there), without the
    rows that are no triangle (-1, or a repeated vertex: ``corners`` holds each corner's);
    and the count (P,) of each polygon's."""
    if not parts:  # no polygon kept (each has a corner that is not finite)
        return np.zeros((0, 3), np.int64), np.zeros(polygons, np.int64)
    kept = []
    for polygon, rows in parts:
        a, b, c = corners[rows.T]
        valid = (rows[:, 0] >= 0) & (a != b) & (b != c) & (c != a)
        kept.append((polygon[valid], rows[valid]))
    every = np.concatenate([polygon for polygon, _ in kept])
    counts = np.bincount(every, minlength=polygons)
    if len(kept) == 1 or not (np.diff(every) < 0).any():  # in polygon order already
        return np.concatenate([rows for _, rows in kept]), counts
    start = np.cumsum(counts) - counts
    out = np.empty((int(counts.sum()), 3), np.int64)
    for polygon, rows in kept:
        if len(rows) == 0:
            continue
        new = np.flatnonzero(np.diff(polygon, prepend=-1))  # each polygon's first row
        first = np.repeat(new, np.diff(np.append(new, len(polygon))))
        out[start[polygon] + np.arange(len(polygon)) - first] = rows
    return out, counts


def face_labels(doc, kinds, faces, triangle_polygon):
    """face_groups (M,) int32 and group_names, or (None, ()) when the file names no groups."""
    names, latest = latest_above(doc, kinds, faces)
    if not names:
        return None, ()
    names = [n or "default" for n in names]
    unique = list(dict.fromkeys((["default"] if (latest < 0).any() else []) + names))
    position = {n: i for i, n in enumerate(unique)}
    # The extra last entry is what latest == -1 (no statement above) picks.
    ids = np.array([position[n] for n in names] + [position.get("default", 0)], np.int32)
    return per_triangle(ids, latest, triangle_polygon), tuple(unique)


def face_materials(doc, faces: Elements, triangle_polygon: np.ndarray, names: tuple):
    """(M,) int32 index into ``names`` (the Mesh's ``material_names``) of each triangle's
    material, the latest ``usemtl`` above its polygon; -1 where there is none (no ``usemtl``
    above, or one without a name); None when the file names no material."""
    if not names:
        return None
    used, latest = latest_above(doc, (KIND_USEMTL,), faces)
    position = {n: i for i, n in enumerate(names)}
    # The extra last entry is what latest == -1 (no statement above) picks.
    ids = np.array([position.get(n, -1) for n in used] + [-1], np.int32)
    return per_triangle(ids, latest, triangle_polygon)
