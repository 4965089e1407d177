"""Materials of an OBJ file: the ``usemtl`` names, the ``Kd`` colours read from its ``mtllib``
(``.mtl``) files, and the colour of each triangle's material."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ._obj_document import Document, decode
from ._obj_errors import Report, count
from ._obj_statements import Elements, latest_above
from .kernels.obj_scan import KIND_MTLLIB, KIND_USEMTL

__all__ = ["DEFAULT_KD", "face_colors", "material_names"]

DEFAULT_KD = (0.8, 0.8, 0.8)
"""Diffuse colour of faces whose material is unknown or has no ``Kd``."""


def material_names(doc: Document) -> tuple:
    names = (doc.argument(s) for s in doc.of_kind(KIND_USEMTL))
    return tuple(dict.fromkeys(n for n in names if n))


def face_colors(doc: Document, faces: Elements, triangle_polygon, report: Report):
    """(M, 3) float32 Kd colour of each triangle's material, or None without materials."""
    libraries = _load_libraries(doc, report)
    names, latest = latest_above(doc, (KIND_USEMTL,), faces)
    if not libraries or not names:
        return None
    missing: dict = {}  # name: its first usemtl statement
    for s, name in zip(doc.of_kind(KIND_USEMTL), names):
        if name and name not in libraries:
            missing.setdefault(name, s)
    if missing:
        shown = ", ".join(map(repr, list(missing)[:5])) + (", ..." if len(missing) > 5 else "")
        report.warn(doc.line(next(iter(missing.values()))),
                    f"{count(len(missing), 'material')} not in the material libraries: {shown}")
    # The extra last row is what latest == -1 (no usemtl above) picks.
    table = np.array([libraries.get(n, DEFAULT_KD) for n in names] + [DEFAULT_KD], np.float32)
    return table[latest[triangle_polygon]]


def _load_libraries(doc: Document, report: Report) -> dict:
    """Kd (r, g, b) of every material in the file's mtllib files that can be read."""
    materials: dict = {}
    folder = Path(doc.name).parent
    for s in doc.of_kind(KIND_MTLLIB):
        argument = doc.argument(s)
        files = [argument] if (folder / argument).is_file() else argument.split()
        for file in files:
            try:
                text = decode((folder / file).read_bytes())
            except OSError as e:
                report.warn(doc.line(s), f"material library {file!r} cannot be read: "
                                          f"{e.strerror or e}")
                continue
            materials.update(_parse_mtl(text, str(folder / file), report))
    return materials


def _parse_mtl(text: str, name: str, report: Report) -> dict:
    """Kd of each newmtl in an .mtl file's text (DEFAULT_KD when it has none)."""
    materials: dict = {}
    current = None
    for number, line in enumerate(text.splitlines(), 1):
        words = line.split("#", 1)[0].split()
        if len(words) >= 2 and words[0] == "newmtl":
            current = " ".join(words[1:])
            materials[current] = DEFAULT_KD
        elif words and words[0] == "Kd" and current is not None:
            try:
                rgb = [float(w) for w in words[1:4]]
            except ValueError:
                rgb = []
            if len(rgb) not in (1, 3) or not np.isfinite(rgb).all():
                report.warn(number, f"cannot read Kd {line.strip()!r}", name)
                continue
            materials[current] = tuple(np.clip(rgb * (3 // len(rgb)), 0.0, 1.0).tolist())
    return materials
