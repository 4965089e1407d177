"""From the checked statements of an OBJ file to the arrays of its Mesh: finite vertices, the
triangles (by the polygon kernels) and edges, per-vertex normals and texture coordinates, and
the group of each triangle."""

from __future__ import annotations

import numpy as np

from ._obj_errors import count
from ._obj_statements import Elements, latest_above
from .kernels import obj_corners, obj_polygons
from .kernels.obj_scan import KIND_V

__all__ = ["face_labels", "finite_vertices", "polygon_sides", "triangulate", "vertex_normals",
           "vertex_texcoords"]


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
    """Triangles (M, 3) int64 of the kept polygons, and the polygon (M,) of each; warns about
    polygons that could not be split exactly."""
    if faces.count == 0:
        return np.zeros((0, 3), np.int64), np.zeros(0, np.int64)
    if np.all(faces.sizes == 3):  # a triangle mesh: the same rows, without compiling the kernel
        triangles = faces.vertex.reshape(-1, 3)
        a, b, c = triangles.T
        valid = keep & (a != b) & (b != c) & (c != a)
        return np.ascontiguousarray(triangles[valid]), np.flatnonzero(valid)
    fans = np.all(faces.sizes <= 4)  # triangles and quads: most likely all fans
    if fans:
        triangles, counts, fans = obj_polygons.triangulate_fans(vertices, faces.vertex, faces.offsets, keep)
        inexact = np.zeros(0, bool)
    if not fans:
        triangles, counts, inexact = obj_polygons.triangulate(vertices, faces.vertex, faces.offsets, keep)
    if inexact.any():
        first = faces.statements[np.argmax(inexact)]
        report.warn(doc.line(first), f"{count(np.count_nonzero(inexact), 'polygon')} too "
                                     "irregular to split exactly (self-intersecting?): split "
                                     "as a fan")
    if len(triangles) < 0.75 * (faces.offsets[-1] - 2 * faces.count):
        triangles = triangles.copy()  # let the rows of the dropped triangles go
    return triangles, np.repeat(np.arange(faces.count), counts)


def polygon_sides(faces: Elements, keep: np.ndarray, n_vertices: int) -> np.ndarray:
    """(E,) int64 keys ``lo * N + hi`` of the sides of the kept polygons, for
    :func:`rasterkit.mesh.unique_edges`."""
    keys = obj_polygons.side_keys(faces.vertex, faces.offsets, keep, n_vertices)
    # Unique here already (NumPy's sort, in place; Numba's quicksort is quadratic on some
    # orders): a polygon that walks round again repeats its sides, and unique_edges copies
    # what it gets several times.
    keys.sort()
    return keys[np.concatenate([[True], keys[1:] != keys[:-1]])] if len(keys) else keys


def vertex_normals(faces: Elements, normals: np.ndarray, n_vertices: int):
    """(N, 3) float64 unit normals averaged over each vertex's corners, or None."""
    used = faces.normal
    if not (used >= 0).any():
        return None
    total = obj_corners.sum_per_vertex(faces.vertex, used, _unit_rows(normals),
                                       n_vertices)
    return _unit_rows(total)


def _unit_rows(a: np.ndarray) -> np.ndarray:
    """Rows of a scaled to length 1; rows of length 0 or not finite become 0."""
    a = np.nan_to_num(a, nan=0.0, posinf=0.0, neginf=0.0)
    # Rows whose squares would overflow (or vanish) are scaled towards 1 first: the other
    # rows keep their exact values.
    biggest = np.abs(a).max(axis=1, keepdims=True)
    extreme = (biggest > 1e150) | ((biggest < 1e-150) & (biggest > 0))
    if extreme.any():
        a = np.where(extreme, a / np.where(extreme, biggest, 1.0), a)
    length = np.linalg.norm(a, axis=1, keepdims=True)
    return np.divide(a, length, out=np.zeros_like(a), where=length > 0)


def vertex_texcoords(faces: Elements, texcoords: np.ndarray, n_vertices: int):
    """(N, 2) float64 texture coordinates of each vertex's first corner with one, or None."""
    used = faces.texcoord
    if not (used >= 0).any():
        return None
    first = obj_corners.first_per_vertex(faces.vertex, used, n_vertices)
    uv = np.nan_to_num(texcoords[:, :2], nan=0.0, posinf=0.0, neginf=0.0)
    return np.where(first[:, None] >= 0, uv[first], 0.0)


def face_labels(doc, kinds, faces, triangle_polygon):
    """face_groups (M,) int32 and group_names, or (None, ()) when the file names no groups."""
    names, latest = latest_above(doc, kinds, faces)
    if not names:
        return None, ()
    names = [n or "default" for n in names]
    unique = list(dict.fromkeys((["default"] if (latest < 0).any() else []) + names))
    position = {n: i for i, n in enumerate(unique)}
    # The extra last entry is what latest == -1 (no statement above) picks.
    ids = np.array([position[n] for n in names] + [position.get("default", 0)])
    return ids[latest[triangle_polygon]].astype(np.int32), tuple(unique)
