"""Opening the texture files that an OBJ file's materials name: each file once, shared by
every material (and every map) that names it, within one memory budget.

A file name is taken relative to the folder of the ``.mtl`` file that names it, with ``\\``
read as ``/`` (files written on Windows); an absolute name is used as it is. When the name
has folders and is not found, the bare file name is tried in the ``.mtl``'s folder too
(textures copied beside a model whose library still names the author's own folders).

A texture that cannot be read (missing, not a regular file, over the file size or memory
limit, not a PNG, JPEG, TGA or BMP image, corrupt) is one warning naming the ``.mtl`` file,
its line and the texture file (its first naming line; the first few such files, then their
count), and that map is left out: the material draws with its colours. The memory of the
textures already opened counts against the limit of the next
(:func:`rasterkit.material.images.read_image`).
"""

from __future__ import annotations

import os

from rasterkit.material import Texture, TextureError
from rasterkit.material.images import read_image
from rasterkit.material.mipmaps import mipmaps_bytes
from rasterkit.obj.errors import Report, count
from rasterkit.obj.mtl import MapStatement

__all__ = ["TEXTURE_WARNINGS", "TextureFiles", "map_path"]

#: Textures that cannot be read are named one warning each up to this many, then counted.
TEXTURE_WARNINGS = 5


def map_path(folder: str, file: str) -> str:
    """The file a map statement names (see the module documentation)."""
    name = file.replace("\\", "/")
    path = os.path.join(folder, name)
    if "/" in name and not os.path.lexists(path):
        beside = os.path.join(folder, os.path.basename(name))
        if os.path.isfile(beside):
            return beside
    return path


class TextureFiles:
    """The textures of one OBJ file's materials, opened once each (see the module
    documentation); :meth:`finish` adds the warnings."""

    def __init__(self, report: Report):
        self.report = report
        self.opened: dict = {}  # real path: Texture (srgb as first opened), or the TextureError
        self.variants: dict = {}  # (real path, settings): Texture
        self.spent = 0  # bytes of the textures opened and their mipmaps
        self.failed: list = []  # (.mtl file, statement, reason) of each file that cannot be read

    def texture(self, library: str, statement: MapStatement, srgb: bool) -> Texture | None:
        """The texture that ``statement`` of the ``.mtl`` file ``library`` names, with its
        settings, or None when the file cannot be read."""
        key = map_path(os.path.dirname(library), statement.file)
        try:
            key = os.path.realpath(key)
        except ValueError:  # a NUL byte in the name: read_image says so
            pass
        base = self.opened.get(key)
        if base is None:
            base = self.opened[key] = self._open(key, library, statement)
        if isinstance(base, TextureError):
            return None
        settings = dict(wrap=statement.wrap, scale=statement.scale, offset=statement.offset, srgb=srgb)
        variant = (key, tuple(sorted(settings.items())))
        if variant not in self.variants:
            self.variants[variant] = base.replace(**settings)
        return self.variants[variant]

    def _open(self, path: str, library: str, statement: MapStatement):
        try:
            image = read_image(path, self.spent)
        except TextureError as e:
            self.failed.append((library, statement, e.reason.removeprefix("cannot read: ")))
            return e
        height, width, channels = image.shape
        self.spent += image.nbytes + mipmaps_bytes(width, height, channels)
        return Texture(image, name=path)

    def finish(self) -> None:
        """Warn about the files that could not be read."""
        for library, statement, reason in self.failed[:TEXTURE_WARNINGS]:
            self.report.warn(statement.line, f"{statement.keyword} texture {statement.file!r} cannot be read: "
                                             f"{reason}; drawn without it", library)
        if len(self.failed) > TEXTURE_WARNINGS:
            library, statement, _ = self.failed[TEXTURE_WARNINGS]
            more = count(len(self.failed) - TEXTURE_WARNINGS, "more texture")
            self.report.warn(statement.line, f"{more} cannot be read; drawn without them", library)
