"""The texture coordinates and normals of an OBJ file's face corners, for the Mesh: the
``vt`` and ``vn`` tables, each triangle corner's row of them (``uv_index``,
``normal_index``: the row its polygon's corner names, so that a seam keeps both of its
coordinates and a hard edge both of its normals), and the per-vertex ``texcoords`` and
``normals`` made from them.

A face has texture coordinates (normals) at all of its corners or at none: a polygon whose
corners do not all give a valid ``vt`` (``vn``) has rows ``-1, -1, -1`` in every triangle
(one with a bad index was reported when its statement was read; one that gives them at some
corners only is reported here)."""

from __future__ import annotations

import numpy as np

from rasterkit.mesh.checks import sealed_empty
from rasterkit.obj.errors import count
from rasterkit.obj.statements import Elements
from rasterkit.obj.kernels import normals as normal_kernels
from rasterkit.obj.kernels.scan import KIND_VT

__all__ = ["corner_rows", "normal_table", "unit_rows", "uv_table", "vertex_normals", "vertex_texcoords"]

#: Column of Elements.reported and the words of the warning, per attribute.
_ATTRIBUTES = {"texcoord": (0, "texture coordinates"), "normal": (1, "normals")}


def uv_table(doc, texcoords: np.ndarray) -> np.ndarray:
    """(U, 2) float64 (u, v) of every ``vt`` line (``texcoords`` (U, 3) as read), as the
    file gives them (NaN and infinities too), v = 0 where the line has only u; ``w`` is
    dropped."""
    uv, fill = sealed_empty((len(texcoords), 2), np.float64)  # the Mesh's own: not copied again
    fill[:] = texcoords[:, :2]
    fill[doc.ntokens[doc.of_kind(KIND_VT)] < 2, 1] = 0.0
    return uv


def corner_rows(faces: Elements, attribute: str, triangle_corners: np.ndarray, triangle_polygon: np.ndarray,
                doc, report) -> np.ndarray | None:
    """(M, 3) int64 row of the ``vt`` (``attribute="texcoord"``) or ``vn`` (``"normal"``)
    table of each triangle corner, -1 rows for triangles of polygons without one at every
    corner; None when no triangle has any. Warns about the polygons that give them at some
    corners only (and had no bad index reported)."""
    index = getattr(faces, attribute)
    if len(triangle_corners) == 0 or not len(index):
        return None
    absent = index < 0
    if absent.all():  # a file of v/vt corners has no vn, and the other way round
        return None
    rows, fill = sealed_empty(triangle_corners.shape, np.int64)  # the Mesh's own: not copied again
    np.take(index, triangle_corners, out=fill, mode="clip")  # valid corners ("raise" would buffer)
    if absent.any():
        starts = faces.offsets[:-1]
        without = np.logical_or.reduceat(absent, starts)
        column, words = _ATTRIBUTES[attribute]
        partial = np.flatnonzero(without & ~np.logical_and.reduceat(absent, starts) & ~faces.reported[:, column])
        if len(partial):
            report.warn(doc.line(faces.statements[partial[0]]),
                        f"{count(len(partial), 'face')} with {words} at some corners only: none kept for their corners")
        fill[without[triangle_polygon]] = -1
    return rows if (rows[:, 0] >= 0).any() else None


def normal_table(normals: np.ndarray, unit: np.ndarray) -> np.ndarray:
    """(C, 3) float64 the ``vn`` table for ``Mesh.corner_normals``: ``unit`` (the rows of
    ``normals`` as :func:`unit_rows`), and 0 where the file's normal has a NaN or infinite
    component."""
    if np.isfinite(normals).all():
        return unit
    return np.where(np.isfinite(normals).all(axis=1)[:, None], unit, 0.0)


def unit_rows(a: np.ndarray) -> np.ndarray:
    """Rows of a (N, 3) scaled to length 1, NaN and infinite components taken as 0; rows of
    length 0 become 0 (:func:`rasterkit.obj.kernels.normals.unit_rows`: rows whose squares
    would overflow or vanish are scaled towards 1 first, the other rows keep their exact
    values); in sealed memory (:func:`rasterkit.mesh.checks.sealed_empty`)."""
    sealed, fill = sealed_empty((len(a), 3), np.float64)  # a Mesh keeps it without a copy
    normal_kernels.unit_rows(np.ascontiguousarray(a, dtype=np.float64), fill)
    return sealed


def vertex_normals(faces: Elements, unit: np.ndarray, n_vertices: int):
    """(N, 3) float64 unit normals averaged over each vertex's corners, or None; ``unit``:
    the ``vn`` table as :func:`unit_rows`."""
    used = faces.normal
    if not (used >= 0).any():
        return None
    # summed in corner order, as np.bincount would
    return unit_rows(normal_kernels.corner_normal_sums(faces.vertex, used, unit, n_vertices))


def vertex_texcoords(faces: Elements, texcoords: np.ndarray, n_vertices: int):
    """(N, 2) float64 texture coordinates of each vertex's first corner with one, or None."""
    used = faces.texcoord
    if not (used >= 0).any():
        return None
    given = np.flatnonzero(used >= 0)
    vertex, at = np.unique(faces.vertex[given], return_index=True)  # each vertex's first
    first = np.full(n_vertices, -1, np.int64)
    first[vertex] = used[given[at]]
    uv = np.nan_to_num(texcoords[:, :2], nan=0.0, posinf=0.0, neginf=0.0)
    return np.where(first[:, None] >= 0, uv[first], 0.0)
