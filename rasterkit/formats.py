"""``load(path) -> Mesh | Scene | PointCloud``: every model format rasterkit reads, each file
given to its reader by its content or, where the content does not say, by its extension.

========  ===============  =====================================================  ==============================
format    extensions       recognised by its first bytes                          reader, result
========  ===============  =====================================================  ==============================
OBJ       ``.obj``         (plain text: what is left)                             :func:`rasterkit.load_obj`, Mesh
STL       ``.stl``         binary: ``84 + 50 n`` bytes, ``n`` at byte 80;        :func:`rasterkit.stl.read_stl`,
                           ASCII: ``solid`` then ``facet``                        Mesh
PLY       ``.ply``         a first line ``ply``                                   :func:`rasterkit.ply.read_ply`,
                                                                                  Mesh (PointCloud without faces)
OFF       ``.off``         ``OFF`` and its variants (``COFF``, ``NOFF``, ...)     :func:`rasterkit.off.read_off`, Mesh
glTF 2.0  ``.gltf .glb``   ``glTF`` (GLB); JSON with an ``asset``                 :func:`rasterkit.gltf.read_gltf`, Scene
========  ===============  =====================================================  ==============================

The content decides when it names a format (an ``.stl`` that is really a PLY is read as PLY;
a binary STL whose 80-byte header starts with ``solid`` is binary by its size), then the
extension (any case), then plain text is taken as OBJ; anything else is refused in one line.
``format=`` skips the guessing. Each reader's errors are one-line ``ValueError`` messages
that start with the file's name (``ObjError``, ``StlError``, ...); a file that cannot be
read, or is not a regular file, is a :class:`rasterkit.runtime.files.FileError`.
"""

from __future__ import annotations

import os
import re

from rasterkit.runtime.files import FileError, read_head

__all__ = ["FORMATS", "MODEL_SUFFIXES", "content_format", "detect", "load", "texture_maps"]

#: Format names, as ``load(..., format=...)`` takes them (``glb`` is an alias of ``gltf``).
FORMATS = ("obj", "stl", "ply", "off", "gltf")

#: Extensions (lower case) and their formats.
SUFFIXES = {".obj": "obj", ".stl": "stl", ".ply": "ply", ".off": "off", ".gltf": "gltf", ".glb": "gltf"}

#: Every extension a folder batch picks up.
MODEL_SUFFIXES = tuple(SUFFIXES)

#: Bytes read to recognise a file.
HEAD_BYTES = 1024

_OFF = re.compile(rb"(ST)?C?N?4?n?OFF(\s|#|$)")
_PLY = re.compile(rb"ply[ \t]*\r?\n")


def content_format(head: bytes, size: int) -> str | None:
    """The format that the first bytes ``head`` of a file of ``size`` bytes say it is, or
    None when they do not say (OBJ has no signature)."""
    if head.startswith(b"glTF"):
        return "gltf"
    if size >= 84 and len(head) >= 84 and 84 + 50 * int.from_bytes(head[80:84], "little") == size:
        return "stl"
    text = head[3:] if head.startswith(b"\xef\xbb\xbf") else head
    text = text.lstrip(b" \t\r\n")
    if _PLY.match(text):
        return "ply"
    if _OFF.match(text):
        return "off"
    if text.startswith(b"solid") and re.search(rb"\bfacet\b|\bendsolid\b", text):
        return "stl"
    if text.startswith(b"{") and b'"asset"' in text:
        return "gltf"
    return None


def detect(path, head: bytes | None = None, size: int | None = None) -> str:
    """The format of the model file ``path`` (see the module documentation); ``head`` and
    ``size`` are its first bytes and size when the caller has read them. Raises
    :class:`FileError` when the file cannot be read or its format cannot be told."""
    name = os.fsdecode(path)
    if head is None:
        head, size = read_head(name, HEAD_BYTES)
    found = content_format(head, size)
    if found is not None:
        return found
    by_name = SUFFIXES.get(os.path.splitext(name)[1].lower())
    if by_name is not None:
        return by_name
    if b"\0" not in head:
        return "obj"
    raise FileError(name, "not a model format rasterkit reads (OBJ, STL, PLY, OFF, glTF/GLB): name it with format=")


def texture_maps(path) -> frozenset:
    """A quick guess, before ``path`` is read, at the kinds of texture map its materials name
    (``"diffuse"``, ``"alpha"``, ``"normal"``: :func:`rasterkit.obj.peek.map_kinds`), for the
    command line's compiling helpers; for an OBJ file only (empty for the other formats, and
    when the file cannot be read)."""
    try:
        kind = detect(path)
    except (OSError, ValueError):
        return frozenset()
    if kind != "obj":
        return frozenset()
    from rasterkit.obj.peek import map_kinds

    return map_kinds(path)


def load(path, *, format: str | None = None, textures: bool = True):
    """Load the model file ``path``: a :class:`~rasterkit.Mesh` (OBJ, STL, OFF, PLY with
    faces), a :class:`~rasterkit.Scene` (glTF, its nodes' meshes placed by their model
    matrices) or a :class:`rasterkit.ply.PointCloud` (a PLY without faces).

    Parameters
    ----------
    path : str or os.PathLike
    format : {"obj", "stl", "ply", "off", "gltf", "glb"}, optional
        The format; by default told from the file's first bytes and its extension.
    textures : bool
        Open the texture images the model names (OBJ's ``.mtl`` maps, a PLY's
        ``TextureFile``, glTF's images). False reads the geometry and colours only.

    Raises
    ------
    ValueError
        One line naming the file (and where in it): the reader's error (``ObjError``,
        ``StlError``, ``PlyError``, ``OffError``, ``GltfError``), or a ``FileError`` when the
        file cannot be read. An unknown ``format`` is a ``ValueError`` too.
    """
    name = os.fsdecode(path)
    if format is not None:
        kind = "gltf" if format == "glb" else format
        if kind not in FORMATS:
            raise ValueError(f"format must be one of {', '.join(FORMATS)} (or glb), got {format!r}")
    else:
        kind = detect(name)
    if kind == "obj":
        from rasterkit.obj import load_obj

        return load_obj(name, textures=textures)
    if kind == "stl":
        from rasterkit.stl import read_stl

        return read_stl(name)
    if kind == "off":
        from rasterkit.off import read_off

        return read_off(name)
    if kind == "ply":
        from rasterkit.ply import read_ply

        return read_ply(name, textures=textures)
    from rasterkit.gltf import read_gltf

    return read_gltf(name, textures=textures)


def as_drawn(model):
    """``(mesh, cloud)``: what the command line draws of a loaded ``model`` — a Mesh as it
    is, ``(mesh, None)``; a Scene as its :meth:`~rasterkit.Scene.world_mesh` (every object
    placed in the world, materials and textures kept), with a glTF scene's points primitives
    as the cloud drawn with it (``None`` without); a point cloud as ``(None, cloud)``."""
    import numpy as np

    from rasterkit.mesh import Mesh
    from rasterkit.ply.cloud import PointCloud
    from rasterkit.scene import Scene

    if isinstance(model, Mesh):
        return model, None
    if isinstance(model, Scene):
        mesh = model.world_mesh()  # which keeps no warnings: the file's (a GltfScene's) and each object's
        warnings = (*getattr(model, "warnings", ()), *(w for obj in model.objects for w in obj.mesh.warnings))
        if warnings:
            from dataclasses import replace

            mesh = replace(mesh, warnings=tuple(dict.fromkeys(warnings)))
        points, colors = getattr(model, "points", None), getattr(model, "point_colors", None)
        if points is None or not len(points):
            return mesh, None
        return mesh, PointCloud(points, None if colors is None else colors[:, :3] / np.float32(255.0))
    return None, model
