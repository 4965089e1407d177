"""Face and vertex normals of a mesh's arrays: the driver of :mod:`rasterkit.raster.kernels.normals`.

Imports no ``Mesh``: :attr:`rasterkit.Mesh.face_normals` asks for them here, and the shading
and the vision maps do too."""

from __future__ import annotations

import numpy as np

from rasterkit.raster.kernels import normals as _kernels

__all__ = ["face_normals", "vertex_normals"]


def face_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(M, 3) float32 unit normals of ``faces`` (checked indices into ``vertices``), counter-
    clockwise seen from the front pointing out: zero for a degenerate face, NaN for one with a
    non-finite corner."""
    return _kernels.face_normals(vertices, faces).astype(np.float32)


def vertex_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(N, 3) unit vertex normals: the area-weighted sums of the normals of ``faces`` (checked
    indices into ``vertices``) around each vertex."""
    return _kernels.vertex_normals(vertices, faces)
