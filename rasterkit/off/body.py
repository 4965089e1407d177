"""The body of an OFF file: a record (line) per vertex, then one per face, read with NumPy over
all the records of a kind at once.

A vertex line is ``x y z``, then, in Geomview's order and as the keyword says, ``nx ny nz``
(NOFF), a colour ``r g b [a]`` (COFF) and ``s t`` (STOFF). In a file whose keyword has no
``C``, a vertex line with 3 or 4 more numbers than its keyword wants has a colour at its end
(as many writers put one). A face line is ``n v1 ... vn``, vertex indices from 0, and up to 4
numbers more: a colour ``r g b [a]``; one or two numbers (a colour map index) are ignored with
a warning. Colours: :mod:`rasterkit.off.colors`. Every number is checked
(:func:`rasterkit.runtime.tokens.floats`, :func:`~rasterkit.runtime.tokens.integers`) and the
first bad one named with its line.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rasterkit.off.colors import DEFAULT, count, unit_colors
from rasterkit.off.errors import OffError
from rasterkit.off.header import Header
from rasterkit.off.records import Records
from rasterkit.runtime.tokens import BadToken, floats, integers

__all__ = ["Faces", "Vertices", "read_faces", "read_vertices"]

#: Numbers after a face's indices that make a colour.
COLOR_NUMBERS = (3, 4)


@dataclass(frozen=True)
class Vertices:
    positions: np.ndarray  # (N, 3) float64
    normals: np.ndarray | None  # (N, 3) float64, unit (zero where the file's is zero or not finite)
    colors: np.ndarray | None  # (N, 3) float32 in [0, 1]
    texcoords: np.ndarray | None  # (N, 2) float64


@dataclass(frozen=True)
class Faces:
    offsets: np.ndarray  # (P + 1,) int64: face p's corners are corners[offsets[p]:offsets[p + 1]]
    corners: np.ndarray  # (C,) int64 vertex indices, in [0, N)
    colors: np.ndarray | None  # (P, 3) float32 in [0, 1]
    lines: np.ndarray  # (P,) int64: the line of each face


class _Reader:
    def __init__(self, name: str, records: Records, header: Header, warnings: list):
        self.name, self.records, self.header, self.warnings = name, records, header, warnings
        self.tokens = records.tokens

    def fail(self, line: int, reason: str):
        raise OffError(self.name, int(line), reason)

    def floats(self, which: np.ndarray, what: str = "a number") -> np.ndarray:
        try:
            return floats(self.tokens, which, what)
        except BadToken as e:
            self.fail(self.records.line_of(which[e.index]), e.reason)

    def integers(self, which: np.ndarray, what: str) -> np.ndarray:
        try:
            return integers(self.tokens, which, what)
        except BadToken as e:
            self.fail(self.records.line_of(which[e.index]), e.reason)

    def integral(self, which: np.ndarray) -> bool:
        """Whether every token ``which`` is written as an integer."""
        try:
            integers(self.tokens, which)
        except BadToken:
            return False
        return True

    def colors(self, values: np.ndarray, which: np.ndarray, has: np.ndarray, what: str) -> np.ndarray | None:
        """(K, 3) float32 colours of the K vertices or faces, ``has`` (K,) bool those with one,
        whose numbers are ``values`` (H, 3 or 4), from tokens ``which``; None when none has."""
        if not has.any():
            return None
        rgb, notes = unit_colors(values, self.integral(which), what)
        self.warnings.extend(notes)
        out = np.repeat(DEFAULT[None, :], len(has), axis=0)
        out[has] = rgb
        if not has.all():
            missing = np.count_nonzero(~has)
            self.warnings.append(f"{missing} of {count(len(has), what)} {'has' if missing == 1 else 'have'} no colour: "
                                 "drawn in the default colour")
        return out


def _layout(header: Header) -> tuple[int, str]:
    """The numbers a vertex line has before any colour, and what they are, for messages."""
    parts = ["x y z"] + (["nx ny nz"] if header.normals else []) + (["r g b [a]"] if header.colors else []) + \
            (["s t"] if header.texcoords else [])
    return 3 + 3 * header.normals + 2 * header.texcoords, " ".join(parts)


def read_vertices(name: str, records: Records, header: Header, warnings: list) -> Vertices:
    """The vertices of the file ``name``; warnings are appended to ``warnings``."""
    reader = _Reader(name, records, header, warnings)
    rows = np.arange(header.body, header.body + header.n_vertices)
    sizes = records.size[rows]
    base, layout = _layout(header)
    allowed = np.array([base + 3, base + 4] if header.colors else [base, base + 3, base + 4])
    bad = ~np.isin(sizes, allowed)
    if bad.any():
        r = int(np.argmax(bad))
        extra = "" if header.colors else ", or 3 or 4 more with a colour r g b [a]"
        reader.fail(records.line[rows[r]], f"a vertex line has {sizes[r]} numbers; the vertices of this "
                                           f"{header.keyword or 'OFF'} file have {base + 3 * header.colors}"
                                           f"{' or ' + str(base + 4) if header.colors else ''} ({layout}){extra}")
    n = len(rows)
    positions = np.empty((n, 3))
    normals = np.empty((n, 3)) if header.normals else None
    texcoords = np.empty((n, 2)) if header.texcoords else None
    color_values, color_tokens, has_color = np.empty((n, 3)), [], np.zeros(n, bool)
    for width in np.unique(sizes):
        mine = np.flatnonzero(sizes == width)
        which = (records.first[rows[mine]][:, None] + np.arange(width)).ravel()
        values = reader.floats(which).reshape(-1, width)
        numbers = width - base  # of the colour
        at = 3 + 3 * header.normals if header.colors else base
        positions[mine] = values[:, :3]
        if normals is not None:
            normals[mine] = values[:, 3:6]
        if texcoords is not None:
            start = 3 + 3 * header.normals + (numbers if header.colors else 0)
            texcoords[mine] = values[:, start:start + 2]
        if numbers:
            has_color[mine] = True
            color_values[mine] = values[:, at:at + 3]
            color_tokens.append(which.reshape(-1, width)[:, at:at + 3].ravel())
    colors = None
    if has_color.any():
        colors = reader.colors(color_values[has_color], np.concatenate(color_tokens), has_color, "vertex")
    return Vertices(positions, None if normals is None else _unit(normals), colors, texcoords)


def _unit(normals: np.ndarray) -> np.ndarray:
    """Rows scaled to unit length; zero for zero rows and rows that are not finite."""
    with np.errstate(all="ignore"):
        scaled = normals / np.abs(normals).max(axis=1, keepdims=True)
        unit = scaled / np.linalg.norm(scaled, axis=1, keepdims=True)
    unit[~np.isfinite(unit).all(axis=1)] = 0.0
    return unit


def read_faces(name: str, records: Records, header: Header, warnings: list) -> Faces:
    """The faces of the file ``name``; warnings are appended to ``warnings``."""
    reader = _Reader(name, records, header, warnings)
    start = header.body + header.n_vertices
    rows = np.arange(start, start + header.n_faces)
    first, size, lines = records.first[rows], records.size[rows], records.line[rows]
    counts = reader.integers(first, "the number of vertices of a face")
    extra = size - 1 - counts
    problems = [(counts < 3, lambda p: f"a face of {counts[p]} vertices (at least 3)"),
                (extra < 0, lambda p: f"a face of {counts[p]} vertices, but only {size[p] - 1} numbers follow"),
                (extra > 4, lambda p: f"{extra[p]} numbers after the {counts[p]} vertex indices of a face (a colour "
                                      "has 3 or 4)")]
    bad = np.zeros(len(rows), bool)
    for test, _ in problems:
        bad |= test
    if bad.any():
        p = int(np.argmax(bad))
        reader.fail(lines[p], next(message(p) for test, message in problems if test[p]))
    offsets = np.concatenate([[0], np.cumsum(counts)])
    corner_tokens = np.repeat((first + 1 - offsets[:-1]).astype(records.first.dtype), counts)
    corner_tokens += np.arange(offsets[-1], dtype=corner_tokens.dtype)
    corners = reader.integers(corner_tokens, "a vertex index")
    out = (corners < 0) | (corners >= header.n_vertices)
    if out.any():
        k = int(np.argmax(out))
        reader.fail(records.line_of(corner_tokens[k]), f"vertex index {corners[k]} is out of range: the file has "
                                                       f"{header.n_vertices} vertices, numbered from 0")
    ignored = (extra == 1) | (extra == 2)
    if ignored.any():
        one = np.count_nonzero(ignored) == 1
        warnings.append(f"{count(np.count_nonzero(ignored), 'face')} {'has' if one else 'have'} 1 or 2 numbers after "
                        f"{'its' if one else 'their'} vertex indices (a colour map index?): ignored (the first on line "
                        f"{lines[np.argmax(ignored)]})")
    has = np.isin(extra, COLOR_NUMBERS)
    colors = None
    if has.any():
        which = (first[has] + 1 + counts[has])[:, None] + np.arange(3)
        values = reader.floats(which.ravel()).reshape(-1, 3)
        alpha = first[has & (extra == 4)] + 4 + counts[has & (extra == 4)]
        reader.floats(alpha)  # checked, not used
        colors = reader.colors(values, which.ravel(), has, "face")
    return Faces(offsets, corners, colors, lines)
