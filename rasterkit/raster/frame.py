"""Drawing one planned frame (:class:`rasterkit.raster.plan.FramePlan`): the passes its mode's
row names, into a new framebuffer or into one sample of a multi-sample render.

The pipeline, in the spaces its variables are named after::

    object --(model)--> world --(camera chain K)--> homogeneous raster (clip)
    clip --> triangles: near-plane clip, cull, bin, rasterize, z-test  (modes with faces)
    clip --> edges: near-plane clip, 2D clip, Bresenham / Wu, z-test    (modes with edges)
"""

from __future__ import annotations

from functools import partial

import numpy as np

from rasterkit.camera import Camera
from rasterkit.mesh import Mesh
from rasterkit.raster.framebuffer import Framebuffer
from rasterkit.raster.plan import Style
from rasterkit.raster.shading import AMBIENT, per_pixel, shade
from rasterkit.raster.sides import Sides, face_sides
from rasterkit.raster.triangles import rasterize_checked, rasterize_triangles
from rasterkit.raster.vertex import transform_points

__all__ = ["LINE_DEPTH_BIAS", "draw_frame", "new_frame", "shared_setup"]

LINE_DEPTH_BIAS = 1e-5
"""Depth bias of hidden-line edges (depth units; depth runs 0..1 from near to far plane): an
edge is drawn where ``depth_edge - LINE_DEPTH_BIAS <= depth_buffer``."""


def new_frame(mesh: Mesh, camera: Camera, style: Style, background, ids: bool) -> Framebuffer:
    """One sample at the pixel centres through the pinhole: a new framebuffer, drawn."""
    # Every buffer is cleared by the kernels, band by band in the threads that draw it.
    fb = Framebuffer(camera.width, camera.height, background=background, ids=ids, cleared=False)
    draw_frame(mesh, style, fb, camera.world_to_raster())
    return fb


def draw_frame(mesh: Mesh, style: Style, fb: Framebuffer, matrix: np.ndarray, shared=None) -> None:
    """Draw the mesh into every buffer of ``fb`` (cleared on the way) through the world ->
    raster ``matrix``; ``shared``: ``(faces, sample)``, a pinhole render's faces set up once
    (:func:`shared_setup`), drawn at ``sample`` (1/256 px), the offset ``matrix`` adds."""
    row = style.mode
    if not row.faces:  # no depth buffer: it stays "farthest" until someone asks
        if fb.ids is not None:
            fb.ids.fill(-1)
        # the edges' vertex pass transforms the vertices itself: one pass over them less
        _draw_edges(fb, mesh, None, style, transform=(mesh.vertices, matrix))
    else:
        if shared is not None:  # set up once: the edges alone need the vertices transformed
            clip = transform_points(mesh.vertices, matrix) if row.edges else None
            transform = None
        else:  # the triangles' vertex pass transforms them (one pass over the vertices less)
            clip, transform = np.empty((len(mesh.vertices), 4)), (mesh.vertices, matrix)
        _draw_triangles(fb, mesh, clip, style, shared, transform)
        if row.edges:
            _draw_edges(fb, mesh, clip, style)
    if style.points is not None:
        from rasterkit.raster.points import draw_points

        draw_points(fb, style.points, matrix)


def shared_setup(mesh: Mesh, camera: Camera, style: Style):
    """``(setup, whole)``: the faces set up once for every sample of a pinhole render
    (through the centre sample's matrix; None when the mode draws none), and whether they
    are all that a sample draws."""
    row = style.mode
    if not row.faces:
        return None, False
    from rasterkit.raster.shared_samples import SharedTriangles

    clip = transform_points(mesh.vertices, camera.world_to_raster())
    sides = face_sides(mesh, style.cull)
    face_colors, vertex_colors, corners = shade(mesh, style, sides) if row.shaded else (None, None, None)
    whole = not row.edges and style.points is None  # then averaged in one pass, exact on outlines
    setup = SharedTriangles(clip, mesh.faces, width=camera.width, height=camera.height, color=row.shaded,
                            face_colors=face_colors, vertex_colors=vertex_colors, cull=sides.cull,
                            depth_offset=row.polygon_offset, neighbours=mesh.side_neighbours if whole else None,
                            textures=_textures(mesh, style, sides, shared=True) if row.shaded else None,
                            corners=corners)
    return setup, whole


def _draw_triangles(fb: Framebuffer, mesh: Mesh, clip: np.ndarray | None, style: Style, shared=None,
                    transform=None) -> None:
    """Shade and draw the faces, or (a mode whose faces are not shaded) only fill the depth
    buffer. ``transform``: ``(vertices, matrix)`` that the vertex pass writes into ``clip``."""
    row = style.mode
    if shared is not None:  # a sample of a pinhole render: the faces are set up
        triangles, sample = shared
        depth = fb.uncleared_depth() if row.depth_kept or style.keep_depth else None
        triangles.draw(fb.color if row.shaded else None, depth, sample=sample,
                       clear=tuple(int(c) for c in fb.background[: fb.color.shape[2]]) if row.shaded else ())
        return
    sides = face_sides(mesh, style.cull)
    if not row.shaded:  # the colour buffer is cleared by the edge pass
        rasterize_checked(None, fb.uncleared_depth(), clip, mesh.faces, None, None, fb.ids, sides.cull, (),
                          row.polygon_offset, None, maps=style.maps, transform=transform, trusted=True,
                          textures=_cutouts(_textures(mesh, style, sides)))
        return
    face_colors, vertex_colors, corners = shade(mesh, style, sides)
    textures = _textures(mesh, style, sides)
    background = tuple(int(c) for c in fb.background[: fb.color.shape[2]])
    if not row.depth_kept and not style.keep_depth:  # nothing drawn after: depth only if read
        depth = None
        fb.defer_depth(partial(_depth_pass, clip, mesh.faces, sides.cull, _cutouts(textures)))
    else:
        depth = fb.uncleared_depth()
    rasterize_checked(fb.color, depth, clip, mesh.faces, face_colors, vertex_colors, fb.ids, sides.cull, background,
                      row.polygon_offset, None, maps=style.maps, transform=transform, trusted=True, textures=textures,
                      corners=corners)


def _textures(mesh: Mesh, style: Style, sides: Sides, shared: bool = False):
    """The frame's :class:`rasterkit.raster.texturing.FrameTextures`, or None (textures off,
    or no face of ``mesh`` textured, and not lit per pixel); ``sides``: :func:`face_sides` of
    the mesh. An untextured frame lit per pixel has a resolve of its own
    (:mod:`rasterkit.raster.pixel_lights`), but not in the samples of a ``shared`` setup:
    their resolves light it through the textured one."""
    textured = style.textures and bool(mesh.materials) and mesh.textured is not None
    phong = per_pixel(style)
    if not textured and not phong:  # no import for a plain mesh
        return None
    from rasterkit.raster.texturing import FrameTextures, frame_textures

    if not textured and not shared:
        from rasterkit.raster.pixel_lights import pixel_lights

        return FrameTextures(None, None, None, pixel_lights(mesh, style.lights, sides.two_sided,
                                                            style.shading != "flat"))

    return frame_textures(mesh, style.light, AMBIENT, sides.two_sided, style.shading != "flat", style.texture_filter,
                          lit=style.lights, phong=phong, textured=textured)


def _cutouts(textures):
    """The frame's ``textures`` when some face is cut out (a depth pass needs its alpha), else
    None."""
    return textures if textures is not None and textures.cutouts is not None else None


def _depth_pass(clip, faces, cull, textures, depth):
    """The depth buffer of a solid render, made when it is first read: the same triangles,
    depth only (the depths are those the colour pass tested, to the bit; cut-out faces
    ``textures`` cut out)."""
    if textures is None:
        rasterize_triangles(None, depth, clip, faces, cull=cull, clear=())
    else:
        rasterize_checked(None, depth, clip, faces, None, None, None, cull, (), (0.0, 0.0), None, trusted=True,
                          textures=textures)


def _draw_edges(fb: Framebuffer, mesh: Mesh, clip: np.ndarray | None, style: Style, transform=None) -> None:
    # imported here: a solid render (and the command line drawing one) loads no edge kernels
    from rasterkit.raster.edge_pass import SPATIAL_ORDER_EDGES, draw_edges, edge_mode

    row = style.mode
    mode = edge_mode(row.edges_tested, style.aa)
    channels = fb.color.shape[2]
    rgba = np.ascontiguousarray(style.line_color[:channels])
    background = np.ascontiguousarray(fb.background[:channels]) if row.edges_clear else None
    depth = fb.depth if row.edges_tested else np.empty((0, 0), np.float32)
    # plain edges in a spatial order: the same pixels, fewer edges read per band
    spatial = not row.edges_tested and not style.aa and len(mesh.edges) >= SPATIAL_ORDER_EDGES
    edges = mesh.spatial_edges if spatial else mesh.edges
    draw_edges(fb.color, depth, clip, edges, rgba, mode, LINE_DEPTH_BIAS, background, transform=transform)
