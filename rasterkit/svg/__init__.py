"""Vector drawings: wireframes and hidden-line drawings as SVG, for plotters, papers and the web.

The pipeline: edges (every polygon edge, or the feature edges: :mod:`rasterkit.raster.features`)
-> clipped to the view volume and split where they pass behind a face
(:mod:`rasterkit.svg.visibility`) -> joined into polylines and ordered for a short pen-up
route (:mod:`rasterkit.svg.paths`) -> SVG 1.1, one layer of visible lines and one of hidden
(dashed) lines, one sub-group per object of a scene (this module).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from xml.sax.saxutils import quoteattr

import numpy as np

from rasterkit.image.atomic import atomic_write
from rasterkit.raster.features import EDGE_CLASSES, check_crease_angle, check_edges, select_edges
from rasterkit.camera import Camera
from rasterkit.colors import parse_color
from rasterkit.limits import check_memory
from rasterkit.mesh import as_mesh
from rasterkit.options import HIDDEN, SVG_MODES, check_choice
from rasterkit.scene import Scene
from rasterkit.raster.sides import face_sides
from rasterkit.raster.vertex import transform_points

__all__ = ["HIDDEN", "SVG_MODES", "Drawing", "SvgText", "render_svg", "save_svg", "svg_drawing"]

#: Decimals of the coordinates: 1/100 pixel, below any visible difference at any zoom a
#: plotter or a page would use, and 10x finer than the visibility's tolerance needs.
DECIMALS = 2

_HEADER = ('<?xml version="1.0" encoding="UTF-8" standalone="no"?>\n'
           '<svg xmlns="http://www.w3.org/2000/svg" '
           'xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape" '
           'version="1.1" width="{w}" height="{h}" viewBox="0 0 {w} {h}">\n')
_LAYERS = (("visible", ""), ("hidden", ' stroke-dasharray="{dash}"'))


@dataclass(frozen=True)
class Drawing:
    """A vector drawing: its SVG text and what the path planning did.

    ``pen_up_before``: pixels the pen would travel lifted drawing every visible or hidden
    piece on its own, in the mesh's edge order; ``pen_up_after``: the same for the joined
    and ordered polylines. ``pieces`` and ``polylines`` count them; ``lines``: the
    :class:`rasterkit.svg.paths.Polylines` in drawing order, raster pixels (float64).
    """

    text: str
    pieces: int
    polylines: int
    pen_up_before: float
    pen_up_after: float
    lines: object


def _check_width(stroke_width) -> float:
    if isinstance(stroke_width, bool) or not isinstance(stroke_width, (int, float, np.integer, np.floating)):
        raise TypeError(f"stroke_width must be a number, got {type(stroke_width).__name__}")
    if not 0.0 < float(stroke_width) < 1e6:
        raise ValueError(f"stroke_width must be a positive number of pixels, got {stroke_width!r}")
    return float(stroke_width)


def _objects(mesh_or_scene):
    """The world mesh and the first vertex of each object (a Mesh is one object)."""
    if isinstance(mesh_or_scene, Scene):
        mesh = mesh_or_scene.world_mesh()
        starts = np.cumsum([0] + [len(o.mesh.vertices) for o in mesh_or_scene.objects])[:-1]
        return mesh, starts
    return as_mesh(mesh_or_scene), np.zeros(1, np.int64)


def svg_drawing(mesh_or_scene, camera: Camera | None = None, mode: str = "hidden", edges: str = "all",
                crease_angle: float = 30.0, hidden: str | None = None, line_color="black",
                stroke_width: float = 1.0) -> Drawing:
    """:func:`render_svg`, with the path planning's figures (a :class:`Drawing`)."""
    from rasterkit.svg import paths as _svg_paths
    from rasterkit.svg import visibility as _svg_visibility

    if isinstance(mesh_or_scene, Scene) and camera is None:
        camera = mesh_or_scene.camera
    if not isinstance(camera, Camera):
        raise TypeError(f"camera must be a rasterkit.Camera, got {type(camera).__name__}")
    mode = check_choice("mode", mode, SVG_MODES)
    hidden = check_choice("hidden", hidden, HIDDEN)
    check_edges(edges)
    crease_angle = check_crease_angle(crease_angle)
    rgb = parse_color(line_color)
    width_px = _check_width(stroke_width)
    mesh, object_starts = _objects(mesh_or_scene)
    w, h = camera.width, camera.height
    view, lens = camera, None
    if camera.distortion:  # drawn by an undistorted camera, then moved through the lens
        from rasterkit.raster.distortion import vector_plan

        view, lens = vector_plan(camera)
    check_memory(svg_bytes(len(mesh.vertices), len(mesh.faces), len(mesh.edges), view.width, view.height, mode),
                 f"a {w}x{h} {mode} SVG of {len(mesh.faces)} faces")
    clip = transform_points(mesh.vertices, np.ascontiguousarray(view.world_to_raster()))
    chosen, classes = select_edges(mesh, clip, edges, crease_angle)
    pieces = _svg_visibility.split_visible(clip, mesh.faces, np.ascontiguousarray(chosen, np.int64), view.width,
                                           view.height, visibility=mode == "hidden",
                                           cull=face_sides(mesh, "back").cull)  # double-sided faces: both
    keep = ~pieces.hidden if hidden is None else np.ones(len(pieces.hidden), bool)
    xy, keys, edge = pieces.xy[keep], pieces.keys[keep], pieces.edge[keep]
    layer = pieces.hidden[keep].astype(np.int64)
    if lens is not None:
        from rasterkit.svg.distortion import distort_pieces

        xy, keys, part_of = distort_pieces(xy, keys, lens, w, h, first_key=len(mesh.vertices))
        edge, layer = edge[part_of], layer[part_of]
    obj = np.searchsorted(object_starts, chosen[edge, 0], side="right") - 1
    n_obj, n_cls = len(object_starts), len(EDGE_CLASSES)
    route_group = layer * n_obj + obj
    group = route_group * n_cls + classes[edge]
    lines = _svg_paths.chain(xy, keys, group)
    lines = _svg_paths.route(lines, lines.group // n_cls)
    before = _svg_paths.pen_up_distance(xy[:, :2], xy[:, 2:])
    after = _svg_paths.pen_up_distance(*lines.ends())
    text = _svg_text(lines, w, h, n_obj, n_cls, rgb, width_px, (len(xy), before, after))
    return Drawing(text, len(xy), len(lines), before, after, lines)


class SvgText(str):
    """The text of an SVG document (a ``str``), which a notebook shows as the drawing."""

    def _repr_svg_(self) -> str:
        return str(self)


def render_svg(mesh_or_scene, camera: Camera | None = None, mode: str = "hidden", edges: str = "all",
               crease_angle: float = 30.0, hidden: str | None = None, line_color="black",
               stroke_width: float = 1.0, *, stroke=None) -> str:
    """A vector drawing of a mesh or scene: the text of an SVG 1.1 document.

    Parameters
    ----------
    mesh_or_scene : Mesh, Scene, (vertices, faces) tuple, or object with ``.vertices`` and ``.faces``
        World-space geometry; a scene's objects become sub-groups ``object-0``, ``object-1``...
    camera : Camera
        The image size (the SVG's ``viewBox`` is ``0 0 width height``, raster pixels, y down)
        and the projection (optional for a scene that has one). A camera with lens
        ``distortion`` draws the curves the lens makes of the edges (as
        :func:`rasterkit.render` does): each straight piece is cut into parts within 0.004
        pixels of the curve (:mod:`rasterkit.svg.distortion`).
    mode : {"hidden", "wire"}
        ``hidden``: only the visible parts of the edges (hidden-line removal in vector
        precision: each edge is split where it passes behind a front face, to 1/1000 pixel;
        back faces hide nothing, as in ``render(mode="hidden")``). ``wire``: every edge.
    edges : {"all", "feature"}
        ``all``: the edges of the original polygons. ``feature``: silhouettes, boundaries,
        creases and material boundaries (:mod:`rasterkit.raster.features`).
    crease_angle : float
        Degrees between two faces' normals from which their edge is a crease (``feature``).
    hidden : {None, "dashed"}
        Leave the hidden parts out, or draw them dashed in a layer of their own.
    line_color : colour
        Line colour (a name, ``'#rrggbb'`` or an ``(r, g, b)`` tuple), as in :func:`rasterkit.render`
        (``stroke`` is another name for it).
    stroke_width : float
        Line width in pixels.

    Returns
    -------
    str
        (an :class:`SvgText`, which a notebook shows as the drawing) The SVG: top-level groups are Inkscape layers (``visible``, and ``hidden`` with
        ``hidden="dashed"``), holding one group per object, holding one ``<path>`` per
        polyline with the class of its edges (``edge``, ``silhouette``, ``boundary``,
        ``crease``, ``material``). Coordinates in pixels with two decimals at most.
    """
    if stroke is not None:
        if line_color != "black":
            raise TypeError("give line_color or stroke (the same colour), not both")
        line_color = stroke
    return SvgText(svg_drawing(mesh_or_scene, camera, mode, edges, crease_angle, hidden, line_color, stroke_width).text)


def svg_bytes(n_vertices, n_faces, n_edges, width, height, mode) -> int:
    """Bytes of an SVG drawing, estimated before anything is allocated: the vertices in two
    spaces, the faces' adjacency (feature edges), the depth and id buffers and the
    rasterizer's per-face scratch, and per edge its clipping, runs, pieces, polylines and
    text (a few hundred bytes)."""
    total = n_vertices * 96 + n_faces * 3 * 48 + n_edges * 600
    if mode == "hidden":
        total += width * height * 8 + n_faces * (64 + 8 * 13)
    return total


def _svg_text(lines, w, h, n_obj, n_cls, rgb, stroke_width, figures) -> str:
    from rasterkit.svg.kernels.text import POINT_BYTES, path_data

    scale = 10 ** DECIMALS
    hundredths = np.rint(lines.points * scale).astype(np.int64)
    first, last = hundredths[lines.offsets[:-1]], hundredths[lines.offsets[1:] - 1]
    closed = (np.all(first == last, axis=1) & (np.diff(lines.offsets) > 3)).astype(np.uint8)
    buf = np.empty(len(hundredths) * POINT_BYTES + 16, np.uint8)
    ends = path_data(hundredths, lines.offsets, closed, buf)
    data = buf[: ends[-1]].tobytes().decode("ascii")
    color = "#{:02x}{:02x}{:02x}".format(*(int(c) for c in rgb[:3]))
    width_text = f"{stroke_width:g}"
    dash = f"{4 * stroke_width:g} {3 * stroke_width:g}"
    out = [_HEADER.format(w=w, h=h),
           f"<!-- rasterkit: {figures[0]} pieces, {len(lines)} paths; pen-up travel {figures[1]:.0f} px "
           f"as pieces in edge order, {figures[2]:.0f} px joined and ordered -->\n"]
    layer_of = lines.group // n_cls // n_obj
    obj_of = lines.group // n_cls % n_obj
    cls_of = lines.group % n_cls
    prefixes = [f'<path class="{name}" d="' for name in EDGE_CLASSES]
    for k, (name, extra) in enumerate(_LAYERS):
        if k == 1 and not np.any(layer_of == 1):
            continue
        out.append(f'<g id="layer-{name}" inkscape:groupmode="layer" inkscape:label={quoteattr(name)} '
                   f'fill="none" stroke="{color}" stroke-width="{width_text}" stroke-linecap="round" '
                   f'stroke-linejoin="round"{extra.format(dash=dash)}>\n')
        for o in range(n_obj):
            members = np.flatnonzero((layer_of == k) & (obj_of == o))
            suffix = "" if k == 0 else "-hidden"
            out.append(f'<g id="object-{o}{suffix}">\n')
            out.extend(f'{prefixes[cls_of[q]]}{data[ends[q]:ends[q + 1]]}"/>\n' for q in members)
            out.append("</g>\n")
        out.append("</g>\n")
    out.append("</svg>\n")
    return "".join(out)


def save_svg(text: str, path: str | os.PathLike) -> None:
    """Write SVG text to ``path`` atomically (a temporary file renamed when complete, the
    mode a plain ``open`` would give)."""
    with atomic_write(path) as tmp:
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(text)
