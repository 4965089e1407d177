"""Materials of an OBJ file: the ``usemtl`` names, the ``Kd`` colours read from its ``mtllib``
(``.mtl``) files and the colour of each triangle's material (:func:`face_colors`), and the
whole :class:`~rasterkit.Material` of each used material, textures and all
(:func:`read_materials`).

Libraries are looked up next to the ``.obj`` file and read by
:func:`rasterkit.obj.files.read_file` (regular files within the file size limit only); each is
read once however often it is named. One that cannot be read (missing, not a regular file, too
large) is a warning that names it and says why, as is a used material that no library defines.
An ``.mtl`` file is read as the OBJ file is (tokens separated by the blanks of
:data:`rasterkit.obj.kernels.scan.BLANKS`, ``#`` at the start of a token begins a comment), and
for the face colours only the ``newmtl`` and ``Kd`` lines of materials the model uses are
kept, so a library costs memory only for those. :func:`read_materials` reads the other
statements of those materials (:mod:`rasterkit.obj.mtl`) and opens their textures
(:mod:`rasterkit.obj.textures`).
"""

from __future__ import annotations

import os
import re

import numpy as np

from rasterkit.material import DEFAULT_DIFFUSE, Material
from rasterkit.obj.document import Document, decode
from rasterkit.obj.errors import ObjError, Report, count
from rasterkit.obj.files import read_file
from rasterkit.obj.mtl import MaterialSpec, parse_library
from rasterkit.obj.statements import Elements, latest_above
from rasterkit.obj.textures import TextureFiles
from rasterkit.obj.kernels.scan import BLANKS, KIND_MTLLIB, KIND_USEMTL, split_tokens

__all__ = ["DEFAULT_KD", "face_colors", "library_files", "material_names", "read_materials"]

DEFAULT_KD = DEFAULT_DIFFUSE
"""Diffuse colour of faces whose material is unknown or has no ``Kd``
(:data:`rasterkit.material.DEFAULT_DIFFUSE`)."""

#: Libraries that cannot be read are named one warning each up to this many, then counted.
LIBRARY_WARNINGS = 5

_BLANK = re.escape(BLANKS).decode()
_STATEMENT = re.compile(f"^[{_BLANK}]*(?:newmtl|Kd)(?![^{_BLANK}\n])[^\n]*".encode(), re.M)


def material_names(doc: Document) -> tuple:
    names = doc.arguments(doc.of_kind(KIND_USEMTL))
    return tuple(dict.fromkeys(n for n in names if n))


def face_colors(doc: Document, faces: Elements, triangle_polygon, report: Report):
    """(M, 3) float32 Kd colour of each triangle's material, or None without materials."""
    names, latest = latest_above(doc, (KIND_USEMTL,), faces)
    libraries, any_read = _load_libraries(doc, set(names), report)
    if not any_read or not names:
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


def _load_libraries(doc: Document, wanted: set, report: Report):
    """Kd (r, g, b) of the wanted materials in the file's mtllib files that can be read, and
    whether any library could be read."""
    materials: dict = {}
    failed: list = []  # (statement, file, reason)
    read = 0
    for path, data in library_files(doc, failed):
        read += 1
        materials.update(_parse_mtl(data, path, wanted, report))
    _warn_unreadable(doc, failed, report)
    return materials, read > 0


def library_files(doc: Document, failed: list):
    """``(path, bytes)`` of each ``mtllib`` library of the file that can be read, once each
    however often it is named, in file order; ``(statement, file, reason)`` of each that
    cannot be read is appended to ``failed``."""
    folder = os.path.dirname(doc.name)
    seen = set()
    for s in doc.of_kind(KIND_MTLLIB):
        words = doc.tokens(s)[1:]
        argument = " ".join(words)  # one name with spaces, or several names
        files = [argument] if os.path.isfile(os.path.join(folder, argument)) else words
        for file in files:
            path = os.path.join(folder, file)
            if path in seen:
                continue
            seen.add(path)
            try:
                data = read_file(path)
            except ObjError as e:
                failed.append((s, file, e.reason.removeprefix("cannot read: ")))
                continue
            yield path, data


def _warn_unreadable(doc: Document, failed: list, report: Report) -> None:
    for s, file, reason in failed[:LIBRARY_WARNINGS]:
        report.warn(doc.line(s), f"material library {file!r} cannot be read: {reason}")
    if len(failed) > LIBRARY_WARNINGS:
        more = count(len(failed) - LIBRARY_WARNINGS, "more material library",
                     "more material libraries")
        report.warn(doc.line(failed[LIBRARY_WARNINGS][0]), f"{more} cannot be read")


def read_materials(doc: Document, report: Report) -> dict:
    """``{name: Material}`` of the materials the file uses (``usemtl``) that its libraries
    define, in the order they are first defined, with their textures
    (:mod:`rasterkit.obj.mtl` says what is read, :mod:`rasterkit.obj.textures` how the
    texture files are found and opened).

    The warnings about the libraries themselves (one that cannot be read, a used material
    that none defines, a bad ``Kd``) are left to :func:`face_colors`, which reads the same
    libraries, so that a loader calling both says each once; this adds those of the other
    statements and of the textures.
    """
    wanted = set(material_names(doc))
    specs: dict = {}
    if wanted:
        for path, data in library_files(doc, []):
            specs.update(parse_library(data, path, wanted, report))
    files = TextureFiles(report)
    materials = {name: _material(name, spec, files) for name, spec in specs.items()}
    files.finish()
    return materials


def _material(name: str, spec: MaterialSpec, files: TextureFiles) -> Material:
    values = dict(spec.values)
    if "opacity" not in values and spec.transparency is not None and spec.transparency < 1.0:
        values["opacity"] = 1.0 - spec.transparency  # Tr 1 is opaque: see rasterkit.obj.mtl
    for field, statement in spec.maps.items():
        values[field] = files.texture(spec.library, statement, srgb=field == "diffuse_map")
    return Material(name, **values)


def _words(line: bytes) -> list:
    """The tokens of an .mtl line before its comment."""
    words = split_tokens(line)
    for k, word in enumerate(words):
        if word.startswith(b"#"):
            return words[:k]
    return words


def _parse_mtl(data: bytes, name: str, wanted: set, report: Report) -> dict:
    """Kd of each wanted newmtl in an .mtl file's bytes (DEFAULT_KD when it has none)."""
    if b"\n" not in data:  # old Mac files break lines with CR alone
        data = data.replace(b"\r", b"\n")
    materials: dict = {}
    current = None
    bad = []  # offsets of unreadable Kd lines of wanted materials
    for match in _STATEMENT.finditer(data):
        words = _words(match.group())
        if words[0] == b"newmtl":
            current = " ".join(decode(w) for w in words[1:])
            if current in wanted:
                materials[current] = DEFAULT_KD
        elif current in materials:
            try:
                rgb = [float(w) for w in words[1:4]]
            except ValueError:
                rgb = []
            if len(rgb) not in (1, 3) or not np.isfinite(rgb).all():
                bad.append(match.start())
                continue
            materials[current] = tuple(np.clip(rgb * (3 // len(rgb)), 0.0, 1.0).tolist())
    if bad:
        end = data.find(b"\n", bad[0])
        line = decode(data[bad[0]:end if end >= 0 else len(data)]).strip()
        more = f" (and {count(len(bad) - 1, 'more such line')})" if len(bad) > 1 else ""
        report.warn(data.count(b"\n", 0, bad[0]) + 1, f"cannot read Kd {line!r}{more}", name)
    return materials
