"""The vertex element: positions, colours, normals and texture coordinates, by the property
names that writers use.

- positions ``x``, ``y``, ``z`` (required), as float64;
- normals ``nx``, ``ny``, ``nz``, scaled to unit length as the OBJ reader's are
  (:func:`rasterkit.obj.attributes.unit_rows`: a zero normal stays zero; NaN and infinite
  components count as 0, with a warning);
- colours ``red``, ``green``, ``blue`` (or ``diffuse_red``..., or ``r``, ``g``, ``b``):
  integers divided by their type's largest value (``uchar`` by 255, ``ushort`` by 65535...),
  floats taken as 0 to 1, or as 0 to 255 when one of them is above 1 (as the OBJ reader
  does); values left outside [0, 1] are clamped and NaN becomes 1, with a warning.
  ``alpha`` is not read (a Mesh's colours are RGB);
- texture coordinates ``u``, ``v`` (or ``s``, ``t``; ``texture_u``, ``texture_v``;
  ``texture_s``, ``texture_t``), as float64, any value.

Any other property is skipped.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rasterkit.obj.attributes import unit_rows
from rasterkit.ply.errors import Notes, PlyError, check_limit, count
from rasterkit.ply.header import Element, Header

__all__ = ["BYTES_PER_VERTEX", "COLORS", "NORMALS", "POSITIONS", "TEXCOORDS", "VertexData", "check_vertex_element",
           "find_all", "first_of", "read_vertices", "unit_colors"]

#: Bytes per vertex while its attributes are read and made into a Mesh (positions, normals,
#: colours and texture coordinates, their temporaries, and the Mesh's checked copies).
BYTES_PER_VERTEX = 320

POSITIONS = ("x", "y", "z")
NORMALS = ("nx", "ny", "nz")
COLORS = (("red", "green", "blue"), ("diffuse_red", "diffuse_green", "diffuse_blue"), ("r", "g", "b"))
TEXCOORDS = (("u", "v"), ("s", "t"), ("texture_u", "texture_v"), ("texture_s", "texture_t"))


@dataclass(frozen=True)
class VertexData:
    """The arrays of the vertex element (None where the file has no such properties)."""

    positions: np.ndarray  # (N, 3) float64
    colors: np.ndarray | None  # (N, 3) float32 in [0, 1]
    normals: np.ndarray | None  # (N, 3) float64
    texcoords: np.ndarray | None  # (N, 2) float64


def find_all(element: Element, names: tuple, name: str, notes: Notes | None = None) -> tuple | None:
    """The scalar properties ``names`` of ``element`` when it has all of them, else None. A
    list among them is an error naming its line, or with ``notes`` (properties the reader
    can do without) a warning, and None."""
    found = tuple(element.find(n) for n in names)
    if any(p is None for p in found):
        return None
    for p in found:
        if p.is_list:
            reason = f"property {p.name!r} of element {element.name!r} must be a scalar, not a list"
            if notes is None:
                raise PlyError(name, p.line, reason)
            notes.warn(p.line, f"{reason}: skipped")
            return None
    return found


def first_of(element: Element, choices: tuple, notes: Notes) -> tuple | None:
    """The first of ``choices`` (tuples of names) whose scalar properties ``element`` has
    (:func:`find_all`), or None."""
    return next((f for f in (find_all(element, names, notes.name, notes) for names in choices) if f is not None),
                None)


def check_vertex_element(header: Header, name: str) -> Element:
    """The vertex element, with x, y and z (else an error naming the line)."""
    element = header.element("vertex")
    if element is None:
        raise PlyError(name, None, "no element 'vertex'")
    if find_all(element, POSITIONS, name) is None:
        missing = [n for n in POSITIONS if element.find(n) is None]
        raise PlyError(name, element.line, f"element 'vertex' has no property {missing[0]!r}")
    return element


def read_vertices(rows, notes: Notes) -> VertexData:
    """The vertex data of ``rows`` (the vertex element's :class:`~rasterkit.ply.rows.Rows`),
    after checking the memory they will take."""
    element = rows.layout.element
    check_limit(notes.name, BYTES_PER_VERTEX * rows.n, f"reading its {count(rows.n, 'vertex', 'vertices')}")
    positions = _columns(rows, find_all(element, POSITIONS, notes.name), np.float64)
    normals = first_of(element, (NORMALS,), notes)
    if normals is not None:
        line, normals = normals[0].line, _columns(rows, normals, np.float64)
        finite = np.isfinite(normals).all(axis=1)
        if not finite.all():
            notes.warn(line, f"{count(np.count_nonzero(~finite), 'vertex normal')} with NaN or infinite "
                             "components: those components taken as 0")
        normals = unit_rows(normals)
    colors = first_of(element, COLORS, notes)
    if colors is not None:
        colors = unit_colors(rows, colors, notes)
    uv = first_of(element, TEXCOORDS, notes)
    return VertexData(positions, colors, normals, None if uv is None else _columns(rows, uv, np.float64))


def _columns(rows, props: tuple, dtype) -> np.ndarray:
    if all(p.dtype.kind == "f" for p in props):
        return rows.floats(props)
    out = np.empty((rows.n, len(props)), dtype)
    for k, p in enumerate(props):
        out[:, k] = rows.scalar(p)
    return out


def unit_colors(rows, props: tuple, notes: Notes) -> np.ndarray:
    """(n, 3) float32 colours in [0, 1] of the properties ``props`` (see the module
    documentation); warns, naming the header line of the first property, about what it had
    to change."""
    element, line = rows.layout.element.name, props[0].line
    out = np.empty((rows.n, 3), np.float64)
    for k, p in enumerate(props):
        values = rows.scalar(p)
        if p.dtype.kind in "iu":
            out[:, k] = values
            out[:, k] /= np.iinfo(p.dtype).max
        else:
            out[:, k] = values
    floats = [p.dtype.kind == "f" for p in props]
    if any(floats) and rows.n:
        with np.errstate(invalid="ignore"):
            high = np.nanmax(np.where(np.isfinite(out[:, floats]), out[:, floats], 0.0)) > 1.0
        if high:
            out[:, floats] /= 255.0
            notes.warn(line, f"colours of element {element!r} above 1: all taken as 0 to 255")
    with np.errstate(invalid="ignore"):
        bad = ~((out >= 0.0) & (out <= 1.0))
    if bad.any():
        notes.warn(line, f"{count(np.count_nonzero(bad.any(axis=1)), 'colour')} of element {element!r} outside "
                         "0 to 1 (or NaN): clamped, NaN taken as 1")
        out = np.where(np.isnan(out), 1.0, np.clip(out, 0.0, 1.0))
    return out.astype(np.float32)
