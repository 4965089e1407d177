"""The textures a PLY file names: ``comment TextureFile NAME`` (MeshLab's and VCGlib's way;
several of them are told apart by the faces' ``texnumber``), each a
:class:`rasterkit.Material` with the image as its ``diffuse_map``.

``NAME`` is the rest of the comment, without the blanks around it (so it may hold spaces),
a file relative to the PLY file's folder (``\\`` read as ``/``); as with the other model
files rasterkit reads, no file outside that folder is opened (an absolute name, or one that
climbs out with ``..``: a warning). A texture that cannot be read (missing, not a regular
file, over the file size or memory limit, not a PNG, JPEG, TGA or BMP image) is a warning
in ``Mesh.warnings`` naming the comment's line, and its faces are drawn with their colours.
Each file is opened once however often it is named.
"""

from __future__ import annotations

import os

from rasterkit.material import Material, Texture, TextureError
from rasterkit.material.images import read_image
from rasterkit.material.mipmaps import mipmaps_bytes
from rasterkit.ply.errors import Notes
from rasterkit.ply.header import Header

__all__ = ["read_textures", "texture_files"]

_KEYWORD = b"texturefile"


def texture_files(header: Header) -> list:
    """``[(line, name)]`` of the ``comment TextureFile NAME`` lines, in file order."""
    found = []
    for line, text in header.comments:
        words = text.split(None, 1)
        if words and words[0].lower() == _KEYWORD and len(words) == 2 and words[1].strip():
            found.append((line, os.fsdecode(words[1].strip())))
    return found


def _inside(folder: str, name: str) -> str | None:
    """The path of ``name`` in ``folder``, or None when it would be outside it."""
    name = name.replace("\\", "/")
    if os.path.isabs(name) or name.startswith("/"):
        return None
    path = os.path.normpath(os.path.join(folder, name))
    base = os.path.normpath(folder)
    if os.path.relpath(path, base).split(os.sep)[0] == os.pardir:
        return None
    return path


def read_textures(path: str, files: list, notes: Notes) -> list:
    """One :class:`rasterkit.Material` per entry of ``files`` (from :func:`texture_files`),
    named after the file, with its texture as ``diffuse_map``, or None where it cannot be
    read (warned about)."""
    folder = os.path.dirname(path) or "."
    opened: dict = {}
    spent = 0
    materials = []
    for line, name in files:
        target = _inside(folder, name)
        if target is None:
            notes.warn(line, f"texture {name!r} is outside the model's folder: not read")
            materials.append(None)
            continue
        if target not in opened:
            try:
                image = read_image(target, spent)
            except TextureError as e:
                notes.warn(line, f"texture {name!r} cannot be read: {e.reason.removeprefix('cannot read: ')}; "
                                 "drawn without it")
                opened[target] = None
            else:
                height, width, channels = image.shape
                spent += image.nbytes + mipmaps_bytes(width, height, channels)
                opened[target] = Texture(image, name=target)
        texture = opened[target]
        materials.append(None if texture is None else Material(name=name, diffuse_map=texture))
    return materials
