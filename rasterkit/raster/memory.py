"""The memory a render needs, estimated before anything is allocated (the rule of
``docs/limits.md``), for :func:`rasterkit.raster.render.render` and :func:`rasterkit.raster.render.render_bytes`."""

from __future__ import annotations

from rasterkit.raster import triangle_pass as _triangles
from rasterkit.raster.framebuffer import buffer_bytes
from rasterkit.runtime.threads import get_threads
from rasterkit.mesh import Mesh

__all__ = ["frame_bytes", "maps_bytes"]


def frame_bytes(mesh: Mesh, width: int, height: int, style, alpha: bool, ids: bool) -> int:
    """Bytes a render needs, estimated before anything is allocated (the rule of
    ``docs/limits.md``): the framebuffer (colour, ids, and depth in the modes that keep it),
    the triangle path's scratch (per vertex, per face, per thread) in every mode but wire,
    and the edge path's in every mode but solid (with the wireframe's byte mask of the
    image). ``style``: the render's :class:`rasterkit.raster.plan.Style`."""
    n, m = len(mesh.vertices), len(mesh.faces)
    row = style.mode
    total = buffer_bytes(width, height, alpha, ids, depth=row.depth_kept or style.keep_depth)
    if style.points is not None:  # their homogeneous coordinates
        total += len(style.points.positions) * 32
    if row.faces:
        smooth = style.shading != "flat" and row.shaded
        total += n * 32 + _triangles.scratch_bytes(n, m, width, get_threads(), smooth=smooth,
                                                    band_depth=not row.depth_kept)
        if row.shaded:  # the face normals (float64, then float32), or the vertex colours
            total += m * 36 + (n * 84 if smooth else 0)
    if row.edges:  # imported here, as in the edge pass: a solid render loads no edge kernels
        from rasterkit.raster import edge_pass as _edges

        # (anti-aliased edges count as such, tested or not: their scratch is the larger)
        mode = _edges.edge_mode(False, True) if style.aa else _edges.edge_mode(row.edges_tested, False)
        total += _edges.scratch_bytes(n, len(mesh.edges), width * height, mode, transform=not row.faces)
    return total


def ao_bytes(width: int, height: int, depth_counted: bool) -> int:
    """Bytes of ambient occlusion's images (rasterkit.raster.ao): the grid's depths, rays'
    shares and blurred shares, the map, and the depth buffer it reads unless the frame's
    count has it (``depth_counted``)."""
    from rasterkit.raster.ao import stride

    s = stride(width, height)
    return 12 * -(-width // s) * -(-height // s) + (4 if depth_counted else 8) * width * height


def maps_bytes(mesh: Mesh, pixels: int, normals: bool, objects: bool, metric: bool, uv: bool = False) -> int:
    """Bytes of the normal, object-id, metric depth and texture-coordinate images and their
    per-vertex and per-face terms."""
    return (12 * pixels + len(mesh.vertices) * 80 + len(mesh.faces) * 84 if normals else 0) + \
        (4 * pixels + len(mesh.faces) * 4 if objects else 0) + (4 * pixels if metric else 0) + \
        (8 * pixels + len(mesh.vertices) * 32 + len(mesh.faces) * 168 if uv else 0)
