"""The Mesh of an OFF file's vertices and faces: polygons split into triangles as an OBJ file's
are (:func:`rasterkit.obj.assemble.split_polygons`: fans for convex polygons, ear clipping or a
monotone sweep for concave ones, so every polygon is covered exactly), the polygons' own sides
as the edges (a quad gives its four sides, not its diagonal), and each triangle the colour of
its polygon."""

from __future__ import annotations

import numpy as np

from rasterkit.mesh import Mesh, polygon_mesh_edges
from rasterkit.obj.assemble import split_polygons
from rasterkit.off.body import Faces, Vertices
from rasterkit.off.colors import count
from rasterkit.runtime.files import readable

__all__ = ["to_mesh"]


def to_mesh(name: str, vertices: Vertices, faces: Faces, warnings: list) -> Mesh:
    """The :class:`~rasterkit.mesh.Mesh` of ``vertices`` and ``faces`` of the file ``name``;
    ``warnings`` (one-line strings) go with it, and so do those about faces dropped or split
    as a fan, each after the file's name."""
    positions = vertices.positions
    finite = np.isfinite(positions).all(axis=1)
    sizes = np.diff(faces.offsets)
    keep = np.ones(len(sizes), bool)
    if not finite.all():
        keep = np.add.reduceat((~finite[faces.corners]).astype(np.int64), faces.offsets[:-1]) == 0 \
            if len(sizes) else keep
        bad = np.count_nonzero(~finite)
        warnings.append(f"{count(bad, 'vertex')} with NaN or infinite coordinates; "
                        f"{count(np.count_nonzero(~keep), 'face')} using {'it' if bad == 1 else 'them'} dropped")
    triangles, counts, inexact = split_polygons(positions, faces.corners, faces.offsets, keep)
    if inexact.any():
        warnings.append(f"{count(np.count_nonzero(inexact), 'polygon')} too irregular to split exactly (self-intersecting?): "
                        f"split as a fan (the first on line {faces.lines[np.argmax(inexact)]})")
    polygon = np.repeat(np.arange(len(sizes)), counts)
    edges, sides = polygon_mesh_edges(faces.corners, faces.offsets, keep, triangles, polygon,
                                      np.zeros((0, 2), np.int64), len(positions))
    return Mesh(positions, faces.corners[triangles], edges=edges, polygon_sides=sides,
                normals=vertices.normals, vertex_colors=vertices.colors,
                texcoords=vertices.texcoords, uv=vertices.texcoords,
                face_colors=None if faces.colors is None else faces.colors[polygon],
                warnings=tuple(f"{readable(name)}: {w}" for w in warnings))
