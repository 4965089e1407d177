"""render(): validate once, build the matrices, pick the kernels once, run the stages.

The pipeline, in the spaces its variables are named after::

    object --(model)--> world --(camera chain K)--> homogeneous raster (clip)
    clip --> triangles: near-plane clip, cull, bin, rasterize, z-test  (solid, hidden)
    clip --> edges: near-plane clip, 2D clip, Bresenham / Wu, z-test    (wire, hidden, solid+wire)
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import partial

import numpy as np

from rasterkit.camera import Camera
from rasterkit.colors import ColorLike, parse_color
from rasterkit.raster import accumulate as _accumulate
from rasterkit.raster.framebuffer import Framebuffer
from rasterkit.limits import check_memory
from rasterkit.raster.memory import maps_bytes, memory_needed
from rasterkit.raster.vertex import transform_points
from rasterkit.mesh import Mesh, as_mesh
from rasterkit.options import CULL, MODES, SHADING, check_choice
from rasterkit.scene import Scene
from rasterkit.raster.shading import AMBIENT, light_direction, shade
from rasterkit.raster.triangles import rasterize_checked, rasterize_triangles

__all__ = ["LINE_DEPTH_BIAS", "MODES", "POLYGON_OFFSET", "render", "render_bytes"]

LINE_DEPTH_BIAS = 1e-5
"""Depth bias of hidden-line edges (depth units; depth runs 0..1 from near to far plane): an
edge is drawn where ``depth_edge - LINE_DEPTH_BIAS <= depth_buffer``."""

POLYGON_OFFSET = (1.0, 1e-5)
"""``(factor, units)`` of the polygon offset applied to the faces when edges are drawn over
them (hidden and solid+wire modes): each face is pushed back by ``factor`` times its largest
depth slope per pixel plus ``units``. An edge's depth is sampled on the line, up to half a
pixel from the pixel centre where its face's depth was sampled; the slope term covers that
difference even on faces seen almost edge-on, which a constant bias cannot."""

@dataclass(frozen=True)
class _Options:
    mode: str
    cull: str
    shading: str
    color: np.ndarray
    line_color: np.ndarray
    aa: bool
    light: np.ndarray  # (3,) unit world-space direction towards the light
    keep_depth: bool = False  # solid: draw the depth buffer in the colour pass, not when read
    points: object = None  # rasterkit.raster.points.Points, drawn last as depth-tested splats
    maps: object = None  # a vision render's Maps (rasterkit.raster.vision.maps_record), made by the band worker


def render(mesh, camera: Camera | None = None, mode: str = "wire", *, cull: str = "back",
           shading: str = "flat", color: ColorLike = "lightgray",
           line_color: ColorLike = "black", background: ColorLike | None = None,
           light=None, aa: bool = False, ids: bool = False, samples: int = 1,
           vignette: float = 0.0, normals: bool = False, camera_depth: bool = False, points=None,
           point_size: int = 1,
           point_color: ColorLike = "black", edges: str = "all",
           crease_angle: float = 30.0) -> Framebuffer:
    """Render a mesh or a scene seen by a camera into a new :class:`Framebuffer`.

    Parameters
    ----------
    mesh : Scene, Mesh, (vertices, faces) tuple, or object with ``.vertices`` and ``.faces``
        Positions in world space, (N, 3) float; faces (M, 3) int, counter-clockwise seen
        from the front. None draws only ``points``. A :class:`Scene` brings its objects' model matrices and colours, and
        the defaults for ``camera``, ``background`` and ``light``.
    camera : Camera
        Gives the image size and the world -> raster chain (optional for a scene that has
        one). A camera with ``distortion`` coefficients (``Camera.from_opencv(...,
        dist=...)``) gives the distorted image: an undistorted render resampled through
        OpenCV's distortion model (:mod:`rasterkit.raster.distortion`).
    mode : {"wire", "hidden", "solid", "solid+wire"}
        ``wire``: every edge, no depth test. ``hidden``: hidden-line removal: a depth pass of
        the triangles, then only the visible parts of the edges. ``solid``: shaded triangles.
        ``solid+wire``: shaded triangles with the visible edges on top.
    cull : {"back", "front", "none"}
        Faces removed before rasterization (the lecture's n·v test, as the sign of the
        screen-space area).
    shading : {"flat", "smooth"}
        Per-face Lambert or per-vertex (Gouraud) Lambert, lit by a headlight at the eye.
    color, line_color, background : colour
        ``'#rrggbb'``, a name, or an ``(r, g, b)`` tuple of 0-255. ``background='transparent'``
        gives an RGBA framebuffer (default white). Vertex or face colours of the mesh take
        the place of ``color``.
    light : (3,) float, optional
        World-space direction towards a distant light; None is a headlight shining along
        the viewing direction.
    aa : bool
        Anti-aliased (Xiaolin Wu) lines.
    ids : bool
        Also fill the framebuffer's id buffer with the index of the visible face; for a
        :class:`Scene`, its index within its object, and ``fb.object_ids`` with the index of
        the object (both -1 where none).
    samples : int
        Samples per pixel, 1 to 256, averaged (rounded to the nearest level). Each sample
        sees the scene at a fixed sub-pixel offset, tuned for coverage (:mod:`rasterkit.raster.samples`):
        anti-aliasing of faces, edges and lines. Through a pinhole the offsets (whole 1/256
        pixels) and the faces' setup are shared by all samples (:mod:`rasterkit.raster.accumulate`);
        in a solid render, a pixel where the samples saw one face and the background (or
        that one face's outline crosses) gets that face's exact share of the pixel, the
        triangle clipped to the pixel square (:mod:`rasterkit.raster.kernels.coverage`). A camera with an ``aperture`` also moves each sample's eye across its lens, keeping
        the focus plane in place: depth of field (:mod:`rasterkit.camera.lens`), a whole
        frame per sample. 1 is one sample at the pixel centre through the pinhole (the
        aperture is then unused). The depth buffer
        and the ids of a render with ``samples > 1`` are those of the centre sample: what
        ``samples=1`` gives with the same camera (the depth is drawn when first read; with
        ``ids`` the centre sample is drawn once more, eagerly).
    edges : {"all", "feature"}
        The edges the wire, hidden and solid+wire modes draw: those of the original
        polygons, or the feature edges seen from this camera (silhouettes, boundaries,
        creases, material boundaries: :mod:`rasterkit.raster.features`), the lines a technical
        drawing shows.
    crease_angle : float
        Degrees between two faces' normals from which their shared edge is a crease
        (``edges="feature"``).
    vignette : float
        In [0, 1]: 1 darkens every pixel (background too) by the natural cos⁴θ falloff of a
        lens camera, θ the angle between the pixel's ray and the optical axis; 0 none (the
        default); in between, ``1 - vignette·(1 - cos⁴θ)``. Parallel cameras have none.
    normals : bool
        Also fill ``fb.normals``, (H, W, 3) float32 unit surface normals in camera space (x
        right, y up, looking down -z), NaN where nothing was drawn: per face with flat
        shading, interpolated (perspective-correct) from the vertex normals with smooth
        shading; the geometric normal, also on back faces drawn with ``cull="none"``.
        With ``samples > 1``, the centre sample's (:mod:`rasterkit.raster.vision`).
    camera_depth : bool
        Also make the metric depth that ``fb.camera_depth()`` returns while drawing, each
        band of rows while it is in the drawing thread's cache, instead of in a pass of its
        own when first asked for; a solid render's depth buffer is then made only when
        :attr:`~rasterkit.Framebuffer.depth` is read. The values are the same either way.
        Only a one-sample render of faces without points makes it so (the others make it
        when asked, as without this option); the normals and scene object ids of such a
        render are made band by band in any case.
    points : (K, 3) array_like of float, optional
        A point cloud, world space, drawn after the faces and edges as squares of
        ``point_size`` pixels (1 to 64) centred on each point, depth-tested against the faces
        and each other (:mod:`rasterkit.raster.points`); ``point_color`` is one colour or (K, 3|4)
        values 0-255, one per point. Points write colour and depth, not ids or normals.

    Returns
    -------
    Framebuffer

    Raises
    ------
    TypeError
        For a mesh, camera or light that is not one (None, a string, arrays of booleans,
        complex numbers or objects).
    ValueError
        For an unknown option, a bad colour or light, or a Mesh whose arrays were changed
        after it was made (:meth:`Mesh.check_intact`).
    rasterkit.limits.LimitError
        When the render would need more memory than :func:`rasterkit.limits.memory_limit`
        (:func:`render_bytes` estimates it before anything is allocated).
    """
    seen_by = mesh.camera if camera is None and isinstance(mesh, Scene) else camera
    if isinstance(seen_by, Camera) and seen_by.distortion:  # an undistorted render, resampled
        from rasterkit.raster.distortion import render_distorted

        return render_distorted(seen_by, lambda ideal: render(
            mesh, ideal, mode, cull=cull, shading=shading, color=color, line_color=line_color,
            background=background, light=light, aa=aa, ids=ids, samples=samples, vignette=vignette,
            normals=normals, points=points, point_size=point_size, point_color=point_color, edges=edges,
            crease_angle=crease_angle))
        # (the distorted depth is resampled from the undistorted one: camera_depth is made when asked)
    plan = _plan(mesh, camera, mode, cull=cull, shading=shading, color=color, line_color=line_color,
                 background=background, light=light, aa=aa, ids=ids, samples=samples, vignette=vignette,
                 normals=normals, camera_depth=camera_depth, points=points, point_size=point_size,
                 point_color=point_color, edges=edges, crease_angle=crease_angle)
    mesh, camera, options, background = plan.mesh, plan.camera, plan.options, plan.background
    samples, vignette, normals, camera_depth = plan.samples, plan.vignette, plan.normals, plan.camera_depth
    one_sample, in_bands, object_faces = plan.one_sample, plan.in_bands, plan.object_faces
    check_memory(plan.need, f"a {camera.width}x{camera.height} {options.mode} render of {len(mesh.faces)} faces")
    if in_bands:  # imported here: a plain render loads none of it
        from rasterkit.raster.vision import maps_record

        options = replace(options, maps=maps_record(camera.height, camera.width, mesh, camera,
                                                    camera.world_to_raster(), options.shading if normals else None,
                                                    object_faces, camera_depth))
    if one_sample:
        fb = _frame(mesh, camera, options, background, ids or normals)
    else:
        fb = _accumulate.render_samples(camera, samples, vignette, background, ids or normals,
                                        partial(_draw_frame, mesh, options),
                                        partial(_shared_setup, mesh, camera, options),
                                        partial(_frame, mesh, camera, options, background))
    fb.camera = camera
    if in_bands:
        from rasterkit.raster.vision import finish_maps

        finish_maps(fb, options.maps)
    elif normals or object_faces is not None:
        from rasterkit.raster.vision import fill_maps

        fill_maps(fb, mesh, camera, camera.world_to_raster(), options.shading if normals else None, object_faces)
    if (normals or object_faces is not None) and not ids:
        fb.ids = None
    return fb


_RENDER_DEFAULTS = dict(render.__kwdefaults__)  # render()'s options, for render_bytes


@dataclass(frozen=True)
class _Plan:
    """What :func:`render` draws, decided from its arguments before anything is allocated."""

    mesh: Mesh
    camera: Camera
    options: _Options
    background: object
    samples: int
    vignette: float
    normals: bool
    camera_depth: bool
    one_sample: bool
    in_bands: bool  # the maps made by the band worker
    object_faces: list | None
    need: int  # bytes, for check_memory


def _plan(mesh, camera, mode, *, cull, shading, color, line_color, background, light, aa, ids, samples, vignette,
          normals, camera_depth, points, point_size, point_color, edges, crease_angle) -> _Plan:
    """Check render()'s arguments (an undistorted camera) and decide what it draws."""
    if points is not None:  # imported here, as the other extras: a plain render loads none
        from rasterkit.raster.points import check_points

        points = check_points(points, point_color, point_size)
        if mesh is None:
            mesh = Mesh(np.zeros((0, 3)), np.zeros((0, 3), np.int64))
    object_faces = None
    if isinstance(mesh, Scene):
        camera = camera if camera is not None else mesh.camera
        background = background if background is not None else mesh.background
        light = light if light is not None else mesh.light
        if ids:
            object_faces = [len(o.mesh.faces) for o in mesh.objects]
        mesh = mesh.world_mesh(color)
    mesh = as_mesh(mesh)
    if not isinstance(camera, Camera):
        raise TypeError(f"camera must be a rasterkit.Camera, got {type(camera).__name__}")
    mesh = _with_edges(mesh, camera, edges, crease_angle, mode)
    light = light_direction(light, camera)
    background = "white" if background is None else background
    options = _Options(check_choice("mode", mode, MODES), check_choice("cull", cull, CULL),
                       check_choice("shading", shading, SHADING), parse_color(color),
                       parse_color(line_color), bool(aa), light)
    samples, vignette = _accumulate.check(samples, vignette)
    normals, camera_depth = bool(normals), bool(camera_depth)
    one_sample = samples == 1 and vignette == 0.0
    # the maps made by the band worker: a one-sample render of faces, nothing drawn after
    in_bands = (normals or object_faces is not None or camera_depth) and one_sample \
        and options.mode != "wire" and points is None
    if (ids or normals) and one_sample and not (camera_depth and in_bands) or points is not None:
        # a vision frame (its depth is wanted too), or points to test against the depth: a
        # deferred depth pass would draw again
        options = replace(options, keep_depth=True, points=points)
    alpha = parse_color(background)[3] < 255
    need = (memory_needed(mesh, camera.width, camera.height, options, alpha, ids or normals)
            + _accumulate.extra_bytes(camera.width, camera.height, alpha, samples, vignette,
                                      len(mesh.faces) if options.mode != "wire" else 0)
            + maps_bytes(mesh, camera.width * camera.height, normals, object_faces is not None,
                          camera_depth and in_bands))
    return _Plan(mesh, camera, options, background, samples, vignette, normals, camera_depth, one_sample, in_bands,
                 object_faces, need)


def render_bytes(mesh: Mesh, camera: Camera, mode: str = "wire", **options) -> int:
    """Bytes that ``render(mesh, camera, mode, **options)`` asks
    :func:`rasterkit.limits.check_memory` for, worked out without drawing (``edges="feature"``
    is counted as ``"all"``, of which the feature edges are a part, so that nothing is worked
    out here). For a camera with ``distortion``: the render's at the same size, without the
    resampling of :func:`rasterkit.raster.distortion.render_distorted`."""
    return _plan(mesh, camera, mode, **{**_RENDER_DEFAULTS, **options, "edges": "all"}).need


def _with_edges(mesh: Mesh, camera: Camera, edges: str, crease_angle, mode: str) -> Mesh:
    """``mesh``, or for ``edges="feature"`` a Mesh whose edges are its feature edges seen by
    ``camera`` (silhouettes depend on the eye)."""
    from rasterkit.raster import features as _features

    _features.check_edges(edges)
    crease_angle = _features.check_crease_angle(crease_angle)
    if edges == "all" or mode == "solid":
        return mesh
    clip = transform_points(mesh.vertices, np.ascontiguousarray(camera.world_to_raster()))
    feature, _ = _features.feature_edges(mesh, clip, crease_angle)
    return replace(mesh, edges=feature)


def _frame(mesh: Mesh, camera: Camera, options: _Options, background, ids: bool) -> Framebuffer:
    """One sample at the pixel centres through the pinhole: a new framebuffer, drawn."""
    # Every buffer is cleared by the kernels, band by band in the threads that draw it.
    fb = Framebuffer(camera.width, camera.height, background=background, ids=ids, cleared=False)
    _draw_frame(mesh, options, fb, camera.world_to_raster())
    return fb


def _draw_frame(mesh: Mesh, options: _Options, fb: Framebuffer, matrix: np.ndarray, shared=None) -> None:
    """Draw the mesh into every buffer of ``fb`` (cleared on the way) through the world ->
    raster ``matrix``; ``shared``: ``(faces, sample)``, a pinhole render's faces set up once
    (:func:`_shared_setup`), drawn at ``sample`` (1/256 px), the offset ``matrix`` adds."""
    if options.mode == "wire":  # no depth buffer: it stays "farthest" until someone asks
        if fb.ids is not None:
            fb.ids.fill(-1)
        # the edges' vertex pass transforms the vertices itself: one pass over them less
        _draw_edges(fb, mesh, None, options, depth_test=False, clear=True,
                    transform=(mesh.vertices, matrix))
    else:
        if shared is not None:  # set up once: the edges alone need the vertices transformed
            clip = None if options.mode == "solid" else transform_points(mesh.vertices, matrix)
            transform = None
        else:  # the triangles' vertex pass transforms them (one pass over the vertices less)
            clip, transform = np.empty((len(mesh.vertices), 4)), (mesh.vertices, matrix)
        _draw_triangles(fb, mesh, clip, options, shared, transform)
        if options.mode != "solid":
            _draw_edges(fb, mesh, clip, options, depth_test=True, clear=options.mode == "hidden")
    if options.points is not None:
        from rasterkit.raster.points import draw_points

        draw_points(fb, options.points, matrix)


def _shared_setup(mesh: Mesh, camera: Camera, options: _Options):
    """``(setup, whole)``: the faces set up once for every sample of a pinhole render
    (through the centre sample's matrix; None when the mode draws none), and whether they
    are all that a sample draws."""
    if options.mode == "wire":
        return None, False
    from rasterkit.raster.shared_samples import SharedTriangles

    clip = transform_points(mesh.vertices, camera.world_to_raster())
    offset = (0.0, 0.0) if options.mode == "solid" else POLYGON_OFFSET
    face_colors, vertex_colors = shade(mesh, options) if options.mode != "hidden" else (None, None)
    whole = options.mode == "solid" and options.points is None  # then averaged in one pass, exact on outlines
    setup = SharedTriangles(clip, mesh.faces, width=camera.width, height=camera.height, color=options.mode != "hidden",
                            face_colors=face_colors, vertex_colors=vertex_colors, cull=options.cull,
                            depth_offset=offset, neighbours=mesh._side_neighbours if whole else None)
    return setup, whole


def _draw_triangles(fb: Framebuffer, mesh: Mesh, clip: np.ndarray | None, options: _Options, shared=None,
                    transform=None) -> None:
    """Solid modes shade and draw the faces; hidden-line mode only fills the depth buffer.
    ``transform``: ``(vertices, matrix)`` that the vertex pass writes into ``clip``."""
    if shared is not None:  # a sample of a pinhole render: the faces are set up
        triangles, sample = shared
        hidden = options.mode == "hidden"
        depth = None if options.mode == "solid" and not options.keep_depth else fb.uncleared_depth()
        triangles.draw(None if hidden else fb.color, depth, sample=sample,
                       clear=() if hidden else tuple(int(c) for c in fb.background[: fb.color.shape[2]]))
        return
    offset = (0.0, 0.0) if options.mode == "solid" else POLYGON_OFFSET
    if options.mode == "hidden":  # the colour buffer is cleared by the edge pass
        rasterize_checked(None, fb.uncleared_depth(), clip, mesh.faces, None, None, fb.ids, options.cull, (), offset, None,
                   maps=options.maps, transform=transform, trusted=True)
        return
    face_colors, vertex_colors = shade(mesh, options)
    background = tuple(int(c) for c in fb.background[: fb.color.shape[2]])
    if options.mode == "solid" and not options.keep_depth:  # nothing drawn after: depth only if read
        depth = None
        fb.defer_depth(partial(_depth_pass, clip, mesh.faces, options.cull))
    else:
        depth = fb.uncleared_depth()
    rasterize_checked(fb.color, depth, clip, mesh.faces, face_colors, vertex_colors, fb.ids, options.cull, background, offset,
               None, maps=options.maps, transform=transform, trusted=True)


def _depth_pass(clip, faces, cull, depth):
    """The depth buffer of a solid render, made when it is first read: the same triangles,
    depth only (the depths are those the colour pass tested, to the bit)."""
    rasterize_triangles(None, depth, clip, faces, cull=cull, clear=())


def _draw_edges(fb: Framebuffer, mesh: Mesh, clip: np.ndarray | None, options: _Options,
                depth_test: bool, clear: bool, transform=None) -> None:
    # imported here: a solid render (and the command line drawing one) loads no edge kernels
    from rasterkit.raster.edge_pass import SPATIAL_ORDER_EDGES, draw_edges
    from rasterkit.raster.kernels import edges as edge_kernels

    mode = edge_kernels.MODE_PLAIN
    if depth_test:
        mode |= edge_kernels.MODE_DEPTH_TEST
    if options.aa:
        mode |= edge_kernels.MODE_ANTIALIAS
    channels = fb.color.shape[2]
    rgba = np.ascontiguousarray(options.line_color[:channels])
    background = np.ascontiguousarray(fb.background[:channels]) if clear else None
    depth = fb.depth if depth_test else np.empty((0, 0), np.float32)
    # plain edges in a spatial order: the same pixels, fewer edges read per band
    spatial = mode == edge_kernels.MODE_PLAIN and len(mesh.edges) >= SPATIAL_ORDER_EDGES
    edges = mesh._spatial_edges if spatial else mesh.edges
    draw_edges(fb.color, depth, clip, edges, rgba, mode, LINE_DEPTH_BIAS, background, transform=transform)
