"""Materials of an OBJ file: the ``usemtl`` names, its ``mtllib`` (``.mtl``) libraries, each
read once (:func:`read_libraries`), the ``Kd`` colour of each triangle's material
(:func:`face_colors`) and the whole :class:`~rasterkit.Material` of each used material,
textures and all (:func:`make_materials`).

Libraries are looked up next to the ``.obj`` file and read by
:func:`rasterkit.obj.files.read_file` (regular files within the file size limit only); each is
read once however often it is named. One that cannot be read (missing, not a regular file, too
large) is a warning that names it and says why, as is a used material that no library defines.
An ``.mtl`` file is read as the OBJ file is (tokens separated by the blanks of
:data:`rasterkit.obj.kernels.scan.BLANKS`, ``#`` at the start of a token begins a comment), and
only the statements of materials the model uses are kept (:mod:`rasterkit.obj.mtl`): for the
face colours alone their ``newmtl`` and ``Kd`` lines, so a library costs memory only for
those. :func:`make_materials` opens the textures (:mod:`rasterkit.obj.textures`).

Warnings come in this order: the unreadable ``Kd`` lines of each library, the libraries that
cannot be read (:func:`read_libraries`), the used materials no library defines
(:func:`face_colors`), the other unreadable statements of each library and the textures that
cannot be read (:func:`make_materials`).
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field

import numpy as np

from rasterkit.material import DEFAULT_DIFFUSE, Material
from rasterkit.obj.document import Document
from rasterkit.obj.errors import ObjError, Report, count
from rasterkit.obj.files import read_file
from rasterkit.obj.mtl import MaterialSpec, parse_library
from rasterkit.obj.statements import Elements, latest_above, per_triangle
from rasterkit.obj.textures import TextureFiles
from rasterkit.obj.kernels.scan import KIND_MTLLIB, KIND_USEMTL

__all__ = ["DEFAULT_KD", "Libraries", "face_colors", "library_files", "make_materials", "material_names",
           "read_libraries"]

DEFAULT_KD = DEFAULT_DIFFUSE
"""Diffuse colour of faces whose material is unknown or has no ``Kd``
(:data:`rasterkit.material.DEFAULT_DIFFUSE`)."""

#: Libraries that cannot be read are named one warning each up to this many, then counted.
LIBRARY_WARNINGS = 5


@dataclass
class Libraries:
    """What the libraries of one OBJ file say of the materials it uses.

    Attributes
    ----------
    specs : dict
        ``{name: MaterialSpec}`` of the used materials the libraries define, in the order
        they are first defined (a later definition replaces an earlier one): their ``Kd``,
        and every statement of those in ``whole``.
    whole : set
        The names read whole (none when only the face colours are wanted).
    read : list
        The :class:`rasterkit.obj.mtl.Library` of each library that could be read, in file
        order (their other unreadable statements are warned about by :func:`make_materials`).
    """

    specs: dict = field(default_factory=dict)
    whole: set = field(default_factory=set)
    read: list = field(default_factory=list)


def material_names(doc: Document) -> tuple:
    return tuple(dict.fromkeys(n for n in doc.names(KIND_USEMTL) if n))


def face_colors(doc: Document, faces: Elements, triangle_polygon, libraries: Libraries, report: Report):
    """(M, 3) float32 Kd colour of each triangle's material, or None without materials (or
    without a library that could be read)."""
    names, latest = latest_above(doc, (KIND_USEMTL,), faces)
    if not libraries.read or not names:
        return None
    missing: dict = {}  # name: its first usemtl statement
    for s, name in zip(doc.of_kind(KIND_USEMTL), names):
        if name and name not in libraries.specs:
            missing.setdefault(name, s)
    if missing:
        shown = ", ".join(map(repr, list(missing)[:5])) + (", ..." if len(missing) > 5 else "")
        report.warn(doc.line(next(iter(missing.values()))),
                    f"{count(len(missing), 'material')} not in the material libraries: {shown}")
    kd = {name: spec.values.get("diffuse", DEFAULT_KD) for name, spec in libraries.specs.items()}
    # The extra last row is what latest == -1 (no usemtl above) picks.
    table = np.array([kd.get(n, DEFAULT_KD) for n in names] + [DEFAULT_KD], np.float32)
    return per_triangle(table, latest, triangle_polygon)


def read_libraries(doc: Document, report: Report, whole: bool = False) -> Libraries:
    """Read each ``mtllib`` library of the file once: the ``Kd`` of every used material (a
    ``usemtl`` without a name uses a ``newmtl`` without one, for its colour), and, with
    ``whole``, every statement of the named ones. Warns about unreadable ``Kd`` lines and
    libraries that cannot be read."""
    wanted = set(doc.names(KIND_USEMTL))
    libraries = Libraries(whole=wanted - {""} if whole else set())
    failed: list = []  # (statement, file, reason)
    for path, data in library_files(doc, failed):
        library = parse_library(data, path, wanted, libraries.whole)
        library.warn(report, kd=True)
        libraries.specs.update(library.specs)
        libraries.read.append(library)
    _warn_unreadable(doc, failed, report)
    return libraries


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


def make_materials(libraries: Libraries, report: Report) -> dict:
    """``{name: Material}`` of the materials :func:`read_libraries` read whole, in the order
    they are first defined, with their textures (:mod:`rasterkit.obj.mtl` says what is read,
    :mod:`rasterkit.obj.textures` how the texture files are found and opened); warns about
    the libraries' unreadable statements other than ``Kd`` and the textures that cannot be
    read."""
    for library in libraries.read:
        library.warn(report, kd=False)
    files = TextureFiles(report)
    materials = {name: _material(name, spec, files) for name, spec in libraries.specs.items()
                 if name in libraries.whole}
    files.finish()
    return materials


def _material(name: str, spec: MaterialSpec, files: TextureFiles) -> Material:
    values = dict(spec.values)
    if "opacity" not in values and spec.transparency is not None and spec.transparency < 1.0:
        values["opacity"] = 1.0 - spec.transparency  # Tr 1 is opaque: see rasterkit.obj.mtl
    for slot, statement in spec.maps.items():
        values[slot] = files.texture(spec.library, statement, srgb=slot == "diffuse_map")
    return Material(name, **values)
