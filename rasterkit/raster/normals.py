"""Face and vertex normals of a mesh's arrays: the driver of :mod:`rasterkit.raster.kernels.normals`.

Imports no ``Mesh``: :attr:`rasterkit.Mesh.face_normals` asks for them here, and the shading
and the vision maps do too."""

from __future__ import annotations

import numpy as np

from rasterkit.raster.kernels import normals as _kernels

__all__ = ["face_normals", "smooth_corners", "vertex_normals"]


def face_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(M, 3) float32 unit normals of ``faces`` (checked indices into ``vertices``), counter-
    clockwise seen from the front pointing out: zero for a degenerate face, NaN for one with a
    non-finite corner."""
    return _kernels.face_normals(vertices, faces).astype(np.float32)


def vertex_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(N, 3) unit vertex normals: the area-weighted sums of the normals of ``faces`` (checked
    indices into ``vertices``) around each vertex."""
    return _kernels.vertex_normals(vertices, faces)


def smooth_corners(mesh) -> tuple[np.ndarray, np.ndarray, bool]:
    """``(normals, corners, split)``: a table of unit normals (K, 3) float64 and, per face
    corner, its row (M, 3) int64: the mesh's own normals of each corner (``corner_normals``
    through ``normal_index``) where it has them, the vertex normals elsewhere
    (``Mesh.normals``, else the area-weighted normals of the faces around each vertex);
    ``split``: some vertex has corners with different normals (an authored hard edge)."""
    faces = mesh.faces
    if mesh.normals is not None:
        per_vertex = np.asarray(mesh.normals, np.float64)
    else:
        finite = np.all(np.isfinite(mesh.vertices[faces]), axis=(1, 2))
        per_vertex = vertex_normals(mesh.vertices, np.ascontiguousarray(faces[finite]))
    if mesh.corner_normals is None:
        return unit(per_vertex), faces, False
    own = np.asarray(mesh.corner_normals, np.float64)
    index = faces if mesh.normal_index is None else mesh.normal_index
    table = unit(np.concatenate([own, per_vertex]))
    corners = _sealed(np.ascontiguousarray(np.where(index >= 0, index, len(own) + faces), np.int64))
    return table, corners, _split(faces, corners, table)


def _split(faces: np.ndarray, corners: np.ndarray, normals: np.ndarray) -> bool:
    """Whether some vertex's corners have different ``normals`` (compared by value)."""
    vertex = faces.ravel()
    order = np.argsort(vertex, kind="stable")
    vectors = normals[corners.ravel()[order]]
    same_vertex = vertex[order][1:] == vertex[order][:-1]
    return bool(np.any(same_vertex & np.any(vectors[1:] != vectors[:-1], axis=1)))


def unit(normals: np.ndarray) -> np.ndarray:
    """Rows scaled to unit length (zero and non-finite rows: zero), C-contiguous, read-only."""
    normals = np.nan_to_num(np.asarray(normals, np.float64), nan=0.0, posinf=0.0, neginf=0.0)
    length = np.linalg.norm(normals, axis=1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        unit = np.where(length > 0.0, normals / length, 0.0)
    return _sealed(np.ascontiguousarray(unit))


def _sealed(a: np.ndarray) -> np.ndarray:
    a.flags.writeable = False
    return a
