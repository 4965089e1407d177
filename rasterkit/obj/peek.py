"""A quick look at an OBJ file's materials before the file is read: which kinds of texture
map they name.

The command line starts its compiling helpers before it reads the model
(:mod:`rasterkit.runtime.warm`); a textured frame compiles other variants of the largest
kernels than an untextured one, so the helpers ask here first. This is a guess, cheap and
never an error: it looks only at the ``mtllib`` statements in the first
:data:`HEAD_BYTES` of the file (exporters write them at the top) and at every material of
those libraries (used by the model or not), as the reader would parse them
(:func:`rasterkit.obj.mtl.parse_library`), and counts a map whose file exists. When it guesses
wrong, the render compiles what it needs itself; the images never depend on it.
"""

from __future__ import annotations

import os
import re

from rasterkit.obj.files import read_file
from rasterkit.obj.mtl import parse_library
from rasterkit.obj.textures import map_path

__all__ = ["HEAD_BYTES", "map_kinds"]

#: How much of the start of the OBJ file is searched for ``mtllib`` statements.
HEAD_BYTES = 1 << 20
_MTLLIB = re.compile(rb"^[ \t]*mtllib[ \t]+([^\r\n#]*)", re.M)
#: The kind of each map a material may have (its Material field).
_KINDS = {"diffuse_map": "diffuse", "opacity_map": "alpha", "normal_map": "normal"}


class _Every:
    """Every material name (what :func:`parse_library` is to read)."""

    def __contains__(self, name) -> bool:
        return True


def map_kinds(path) -> frozenset:
    """The kinds of texture map, of ``"diffuse"`` (``map_Kd``), ``"alpha"`` (``map_d``) and
    ``"normal"`` (``map_Bump``, ``bump``, ``norm``), that the libraries named near the start
    of the OBJ file ``path`` name with a file that exists; empty when there are none or
    something cannot be read."""
    try:
        with open(path, "rb") as f:
            head = f.read(HEAD_BYTES)
    except (OSError, ValueError):
        return frozenset()
    folder = os.path.dirname(os.fsdecode(path))
    kinds = set()
    for match in _MTLLIB.finditer(head):
        argument = match.group(1).decode("utf-8", "replace").strip()
        for file in [argument] if os.path.isfile(os.path.join(folder, argument)) else argument.split():
            library = os.path.join(folder, file)
            try:
                specs = parse_library(read_file(library), library, _Every(), _Every()).specs
            except (OSError, ValueError):
                continue
            for spec in specs.values():
                for slot, statement in spec.maps.items():
                    if slot in _KINDS and os.path.isfile(map_path(os.path.dirname(library), statement.file)):
                        kinds.add(_KINDS[slot])
    return frozenset(kinds)
