"""Shading of a render's faces: per face for flat shading, per vertex (or face corner) for
smooth; Lambert's law under the classic headlight or distant ``light``, or, with ``lights``,
Blinn-Phong under every light of the frame (:mod:`rasterkit.raster.kernels.lights`).

:func:`rasterkit.render` colours the faces through :func:`shade`; its options are those of
:class:`rasterkit.raster.plan.Style` (``shading``, ``cull``, ``color``, ``light``, ``lights``).
"""

from __future__ import annotations

import numpy as np

from rasterkit._arrays import unit_vector
from rasterkit.camera import Camera
from rasterkit.raster.normals import vertex_normals
from rasterkit.material.colorspace import decode_srgb
from rasterkit.raster.kernels import lights as light_kernels
from rasterkit.raster.lights import NO_SHADOWS
from rasterkit.raster.kernels import shade as shade_kernels
from rasterkit.mesh import Mesh
from rasterkit.raster.sides import Sides, corner_sides, face_sides
from rasterkit.raster.triangles import FlatLambert

AMBIENT = 0.25
"""Fraction of the surface colour that unlit faces keep."""


def shade(mesh: Mesh, options, sides: Sides | None = None):
    """Lambert colours lit by a distant light: ``(face_colors, vertex_colors, corners)``, per
    face (a :class:`FlatLambert` that the rasterizer evaluates; the others None) or, smooth,
    per vertex ((N, 3) float32 0..255; ``corners`` None: the faces index them) or, where the
    corners of a vertex have different normals (an authored hard edge, which stays hard), per
    distinct corner ((K, 3) float32, and each face corner's row (M, 3) int64); a mesh with
    face colours (an OBJ's ``Kd``, an STL's or OFF's colours), per face corner: its face's
    colour lit by the corner's normal, so no colour bleeds across an edge.

    The light has one direction for every face, so the triangles of one flat polygon get one
    colour. Faces are lit on both sides as ``sides`` (:func:`rasterkit.raster.sides.face_sides`
    of ``mesh`` and ``options.cull``, worked out when None) says.
    """
    two_sided = (sides or face_sides(mesh, options.cull)).two_sided
    if per_pixel(options):  # lit per pixel (rasterkit.raster.kernels.lit_shade) from these
        return _unlit(mesh, options)
    if options.lights is not None:
        return _lit(mesh, options, two_sided)
    towards_light = options.light
    if options.shading == "flat":
        if mesh.face_colors is not None:  # scaled in the kernel: no (M, 3) product per frame
            base, scale = mesh.face_colors, np.float32(255)
        else:
            base, scale = _base_colors(mesh, options, per_face=True), np.float32(1)
        # Computed by the face setup, for the faces that are drawn only.
        return FlatLambert(mesh.face_normals, base, towards_light, AMBIENT, two_sided, scale), None, None
    normals, corners, split = mesh.smooth_corners
    if mesh.face_colors is not None:  # each corner its face's colour, lit by the corner's normal
        rows = normals[corners] if split else _vertex_normals(mesh)[mesh.faces]
        base = np.repeat(mesh.face_colors * np.float32(255), 3, axis=0)
        return (None, _lambert(rows.reshape(-1, 3), base, towards_light, np.repeat(two_sided, 3)
                               if isinstance(two_sided, np.ndarray) else two_sided),
                np.arange(3 * len(mesh.faces), dtype=np.int64).reshape(-1, 3))
    if split:
        if mesh.vertex_colors is None:
            return None, _lambert(normals, options.color[None, :3].astype(np.float32), towards_light,
                                  corner_sides(two_sided, corners, len(normals))), corners
        # a colour per vertex and a normal per corner: a row per distinct (vertex, normal)
        pairs, rows = np.unique(np.stack([mesh.faces.ravel(), corners.ravel()], axis=1), axis=0, return_inverse=True)
        base = np.ascontiguousarray(mesh.vertex_colors[pairs[:, 0]] * np.float32(255))
        rows = np.ascontiguousarray(rows.reshape(-1, 3), np.int64)
        return None, _lambert(normals[pairs[:, 1]], base, towards_light, corner_sides(two_sided, rows, len(pairs))), rows
    base = _base_colors(mesh, options, per_face=False)
    normals = _vertex_normals(mesh)
    return None, _lambert(normals, base, towards_light, corner_sides(two_sided, mesh.faces, len(normals))), None


def per_pixel(style) -> bool:
    """Whether a frame's faces are lit per pixel (:mod:`rasterkit.raster.kernels.lit_shade`):
    phong shading, or a light that casts shadows."""
    return style.shading == "phong" or (style.lights is not None and style.lights.shadowed)


def _unlit(mesh: Mesh, options):
    """The faces' own colours, which phong shading lights per pixel: per face (face colours,
    or ``color`` packed) or per vertex (vertex colours)."""
    if mesh.face_colors is not None:
        return mesh.face_colors * np.float32(255), None, None
    if mesh.vertex_colors is not None:
        return None, mesh.vertex_colors * np.float32(255), None
    packed = shade_kernels.pack_colors(options.color[None, :3].astype(np.float32))
    return np.full(len(mesh.faces), packed[0], np.uint32), None, None


def _lit(mesh: Mesh, options, two_sided):
    """:func:`shade` under ``options.lights`` (:class:`rasterkit.raster.lights.FrameLights`):
    flat, each face's colour at its centroid with its normal; smooth, each face corner's
    colour at its vertex with its smooth normal (interpolated across the face by the
    rasterizer), so that a point light's falloff and highlights vary within a face."""
    m = len(mesh.faces)
    if options.shading == "flat":
        points = mesh.vertices[mesh.faces].mean(axis=1)
        normals = mesh.face_normals
        base = (mesh.face_colors * np.float32(255) if mesh.face_colors is not None
                else _base_colors(mesh, options, per_face=True))
        return lit_rows(points, normals, base, surface_terms(mesh, options.lights, 1), options.lights, two_sided), None, None
    normals, corners, split = mesh.smooth_corners
    rows = normals[corners] if split else _vertex_normals(mesh)[mesh.faces]
    if mesh.face_colors is not None:
        base = np.repeat(mesh.face_colors * np.float32(255), 3, axis=0)
    else:
        base = _base_colors(mesh, options, per_face=False)
        base = base if len(base) == 1 else base[mesh.faces.ravel()]
    colours = lit_rows(mesh.vertices[mesh.faces.ravel()], rows.reshape(-1, 3), base, surface_terms(mesh, options.lights, 3),
                        options.lights, np.repeat(two_sided, 3) if isinstance(two_sided, np.ndarray) else two_sided)
    return None, colours, np.arange(3 * m, dtype=np.int64).reshape(-1, 3)


def surface_terms(mesh: Mesh, lights, repeat: int):
    """``(specular (S, 3), shininess (S,), emission (S, 3))``, linear, of each face (repeated
    ``repeat`` times: one per row) from its material's ``specular``, ``shininess`` and
    ``emission`` (sRGB colours), or one for all: a white highlight of ``specular`` (linear)
    and ``shininess`` from the frame's lights (:class:`rasterkit.raster.lights.FrameLights`),
    no emission, for faces without a material."""
    plain = np.array([[lights.specular] * 3 + [lights.shininess, 0.0, 0.0, 0.0]])
    if not mesh.materials or mesh.face_materials is None:
        table, rows = plain, None
    else:
        own = [decode_srgb(np.array(mat.specular)).tolist() + [mat.shininess] + decode_srgb(np.array(mat.emission))
               .tolist() if mat is not None else plain[0].tolist() for mat in mesh.materials]
        table = np.array(own + [plain[0].tolist()])  # the last row: faces without a material (-1)
        rows = np.repeat(mesh.face_materials, repeat) if repeat > 1 else mesh.face_materials
    chosen = table if rows is None else table[rows]
    return (np.ascontiguousarray(chosen[:, 0:3]), np.ascontiguousarray(chosen[:, 3]),
            np.ascontiguousarray(chosen[:, 4:7]))


def lit_rows(points, normals, base, surfaces, lights, two_sided):
    """(K, 3) float32 sRGB 0..255: the points (K, 3) with their normals (K, 3) and colours
    ``base`` (K or 1, 3) 0..255, of materials ``surfaces`` (:func:`surface_terms`), lit by
    ``lights`` (:class:`rasterkit.raster.lights.FrameLights`) without shadows."""
    normals = np.nan_to_num(np.ascontiguousarray(normals, np.float64), nan=0.0, posinf=0.0, neginf=0.0)
    base = np.ascontiguousarray(base, np.float32)
    with np.errstate(all="ignore"):  # faces with a non-finite corner are not drawn
        points = np.nan_to_num(np.ascontiguousarray(points, np.float64))
    return light_kernels.lit_colors(points, normals, base, *surfaces, lights.table, lights.eye, lights.perspective,
                                    lights.view, two_sided, NO_SHADOWS)


def _vertex_normals(mesh: Mesh) -> np.ndarray:
    """The mesh's vertex normals, or ones made from its faces. Faces with a NaN or inf corner
    are dropped by the rasterizer; they are kept out of the normals too, so they cannot spoil
    their neighbours'. (A Mesh's faces index its vertices: checked when it was made, and its
    arrays are immutable.)"""
    if mesh.normals is not None:
        return mesh.normals
    faces = mesh.faces
    if not np.isfinite(mesh.vertices).all():
        faces = np.ascontiguousarray(faces[np.all(np.isfinite(mesh.vertices[faces]), axis=(1, 2))])
    return vertex_normals(mesh.vertices, faces)


def light_direction(light, camera: Camera) -> np.ndarray:
    """Unit direction towards the light; None is the headlight (from the target to the eye)."""
    if light is None:
        return camera.backward()
    return unit_vector(light, "light")


def _lambert(normals, base, light, two_sided):
    no_points = np.zeros((0, 3))  # read only by positional lights
    normals = np.nan_to_num(np.ascontiguousarray(normals, np.float64), nan=0.0, posinf=0.0, neginf=0.0)
    return shade_kernels.lambert(normals, base, light, no_points, False, AMBIENT, two_sided)


def _base_colors(mesh: Mesh, options, per_face: bool):
    """Surface colours 0..255 float32: the mesh's vertex colours (averaged over each face
    when ``per_face``) or ``color``. (Face colours are scaled by the flat-shading kernel.)"""
    if mesh.vertex_colors is not None:
        rgb = mesh.vertex_colors * np.float32(255)
        return np.ascontiguousarray(rgb[mesh.faces].mean(axis=1, dtype=np.float32)) if per_face else rgb
    return options.color[None, :3].astype(np.float32)
