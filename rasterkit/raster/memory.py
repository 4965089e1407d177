"""The memory a render needs, estimated before anything is allocated (the rule of
``docs/limits.md``), for :func:`rasterkit.raster.render.render` and :func:`rasterkit.raster.render.render_bytes`."""

from __future__ import annotations

from rasterkit.raster import triangle_pass as _triangles
from rasterkit.raster.framebuffer import buffer_bytes
from rasterkit.runtime.threads import get_threads
from rasterkit.mesh import Mesh

__all__ = ["maps_bytes", "memory_needed"]


def memory_needed(mesh: Mesh, width: int, height: int, options, alpha: bool, ids: bool) -> int:
    """Bytes a render needs, estimated before anything is allocated (the rule of
    ``docs/limits.md``): the framebuffer (colour, ids, and depth in the modes that keep it),
    the triangle path's scratch (per vertex, per face, per thread) in every mode but wire,
    and the edge path's in every mode but solid (with the wireframe's byte mask of the
    image)."""
    n, m = len(mesh.vertices), len(mesh.faces)
    total = buffer_bytes(width, height, alpha, ids, depth=options.mode in ("hidden", "solid+wire") or options.keep_depth)
    if options.points is not None:  # their homogeneous coordinates
        total += len(options.points.positions) * 32
    if options.mode != "wire":
        smooth = options.shading == "smooth" and options.mode != "hidden"
        total += n * 32 + _triangles.scratch_bytes(n, m, width, get_threads(), smooth=smooth,
                                                    band_depth=options.mode == "solid")
        if options.mode != "hidden":  # the face normals (float64, then float32), or the vertex colours
            total += m * 36 + (n * 84 if smooth else 0)
    if options.mode != "solid":  # imported here, as in _draw_edges: a solid render loads no edge kernels
        from rasterkit.raster import edge_pass as _edges
        from rasterkit.raster.kernels.edges import MODE_ANTIALIAS, MODE_DEPTH_TEST, MODE_PLAIN

        edge_mode = MODE_ANTIALIAS if options.aa else MODE_DEPTH_TEST if options.mode != "wire" else MODE_PLAIN
        total += _edges.scratch_bytes(n, len(mesh.edges), width * height, edge_mode,
                                      transform=options.mode == "wire")
    return total


def maps_bytes(mesh: Mesh, pixels: int, normals: bool, objects: bool, metric: bool) -> int:
    """Bytes of the normal, object-id and metric depth images and their per-vertex and
    per-face terms."""
    return (12 * pixels + len(mesh.vertices) * 80 + len(mesh.faces) * 84 if normals else 0) + \
        (4 * pixels + len(mesh.faces) * 4 if objects else 0) + (4 * pixels if metric else 0)
