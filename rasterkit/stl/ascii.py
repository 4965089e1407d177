"""ASCII STL: ``solid`` blocks of facets.

The grammar (keywords in any case, tokens separated by any whitespace; lines end with LF, CRLF or CR)::

    solid [name to the end of the line]
      facet normal nx ny nz
        outer loop
          vertex x y z
          vertex x y z
          vertex x y z
        endloop
      endfacet
      ...
    endsolid [name to the end of the line]
    (more solid ... endsolid blocks)

The facets are read by one kernel pass over the bytes (:func:`rasterkit.stl.kernels.text.scan_facets`,
:data:`BATCH` facets a call); the numbers it cannot round exactly (more than 15 digits), and
``nan`` or ``inf``, are converted here (:meth:`_Reader.convert`; a token that is no number is
refused there). This module reads the ``solid`` and ``endsolid`` lines between the kernel's
calls. A file whose last block has no ``endsolid`` is read with a warning; anything else out of
place (a facet of more than three vertices, a number missing, a token that is no number, text
after the last ``endsolid``, no ``solid`` at all) is an :class:`~rasterkit.stl.StlError` naming
its line.
"""

from __future__ import annotations

import re

import numpy as np

from rasterkit.runtime.decimal import exact_decimals
from rasterkit.runtime.tokens import BadToken, Tokens, decode, floats, shown
from rasterkit.stl.errors import StlError, check
from rasterkit.stl.facets import Facets, assembly_bytes
from rasterkit.stl.kernels.text import FACET, SCAN_BAD, SCAN_FULL, scan_facets

__all__ = ["BATCH", "read_ascii"]

#: Facets read by one call of the kernel (about 300 bytes each of the kernel's arrays).
BATCH = 1 << 15

_TOKEN = re.compile(rb"[^ \t\n\r\x0b\x0c]+")
_BOM = b"\xef\xbb\xbf"
#: The shortest facet: single-digit numbers and single spaces.
_MIN_FACET_BYTES = 86


class _Reader:
    """The state of reading one file: the kernel's arrays and the facets read so far."""

    def __init__(self, name: str, data: bytes):
        self.name, self.data = name, data
        self.buf = np.frombuffer(data, np.uint8)
        self.batch = (np.empty((BATCH, 12)), np.empty(BATCH, np.int64), np.empty((BATCH, 12), np.int64),
                      np.empty((BATCH, 12), np.int64), np.empty((BATCH, 12), bool))
        self.corners: list[np.ndarray] = []  # (F, 3, 3) corners of each batch
        self.normals: list[np.ndarray] = []  # (F, 3) normals of each batch
        self.offsets: list[np.ndarray] = []  # (F,) byte offset of each facet
        self.blocks: list[int] = []  # the block of each batch
        self.names: list[str] = []
        self.warnings: list[str] = []

    def line(self, offset: int) -> int:
        return self.data.count(b"\n", 0, int(offset)) + 1

    def fail(self, offset: int, reason: str):
        raise StlError(self.name, self.line(offset), reason)

    def token(self, pos: int):
        """The next token at or after byte ``pos``: a match (``start()``, ``end()``,
        ``group()``), or None at the end of the text."""
        return _TOKEN.search(self.data, pos)

    def after_line(self, token) -> int:
        """The end of the line of ``token`` (a ``solid`` or ``endsolid`` line)."""
        end = self.data.find(b"\n", token.end())
        return len(self.data) if end < 0 else end

    def read(self) -> None:
        pos = len(_BOM) if self.data.startswith(_BOM) else 0
        while (token := self.token(pos)) is not None:
            if token.group().lower() != b"solid":
                self.fail(token.start(), f"expected 'solid', got {shown(token.group())}")
            pos = self.after_line(token)
            self.names.append(decode(self.data[token.end():pos].strip()))
            pos = self.block(pos)
        if not self.names:
            raise StlError(self.name, None, "no 'solid' block (an empty file?)")

    def block(self, pos: int) -> int:
        """Read the facets of a block from byte ``pos``, up to its ``endsolid`` line; the byte
        after that line."""
        while True:
            status, pos, count, slot = scan_facets(self.buf, pos, *self.batch)
            self.keep(count)
            if status == SCAN_FULL:
                continue
            if status == SCAN_BAD:
                self.bad_facet(pos, count, slot)
            token = self.token(pos)
            if token is None:
                self.warnings.append(f"no 'endsolid' at the end of the file (block {self.names[-1]!r} is not closed)")
                return len(self.data)
            if token.group().lower() != b"endsolid":
                self.fail(token.start(), f"expected 'facet' or 'endsolid', got {shown(token.group())}")
            return self.after_line(token)

    def bad_facet(self, pos: int, row: int, slot: int):
        """Raise the error of the facet the kernel stopped in, in row ``row`` of its arrays,
        at the token at byte ``pos`` (slot ``slot`` of :data:`FACET`); a number before it
        that is no number comes first."""
        numbers = FACET[:slot].count(None)
        self.convert(self.batch[0][row, :numbers], *(a[row, :numbers] for a in self.batch[2:]))
        word = FACET[slot]
        got = "the end of the file" if pos == len(self.data) else shown(self.token(pos).group())
        reason = f"expected {'a number' if word is None else repr(word.decode())}, got {got}"
        if word == b"endloop" and got == "'vertex'":
            reason += " (a facet of more than 3 vertices: STL facets are triangles)"
        self.fail(pos, reason)

    def convert(self, values: np.ndarray, starts: np.ndarray, ends: np.ndarray, flags: np.ndarray) -> None:
        """Convert the numbers of ``values`` that the kernel flagged, from their tokens: of up to
        19 digits by :func:`rasterkit.runtime.decimal.exact_decimals` (compiled on the first
        file that has such numbers), the rest (``nan``, ``inf``, more digits, no number) by
        :func:`rasterkit.runtime.tokens.floats`."""
        flagged = np.flatnonzero(flags)
        if not len(flagged):
            return
        starts, ends = starts.ravel()[flagged], ends.ravel()[flagged]
        exact = np.empty(len(flagged))
        rest = np.flatnonzero(~exact_decimals(self.buf, starts, ends, exact))
        if len(rest):
            tokens = Tokens(self.buf, starts[rest], ends[rest])
            try:
                exact[rest] = floats(tokens, np.arange(len(rest)))
            except BadToken as e:
                self.fail(tokens.starts[e.index], e.reason)
        np.put(values, flagged, exact)  # in place, by flat index

    def keep(self, count: int) -> None:
        """Keep the ``count`` facets of the kernel's arrays, converting their flagged numbers."""
        if not count:
            return
        values, offsets, starts, ends, flags = (a[:count] for a in self.batch)
        self.convert(values, starts, ends, flags)
        self.corners.append(values[:, 3:].reshape(-1, 3, 3).copy())
        self.normals.append(values[:, :3].copy())
        self.offsets.append(offsets.copy())
        self.blocks.append(len(self.names) - 1)


def read_ascii(name: str, data: bytes) -> Facets:
    """The facets of the ASCII STL file ``name`` whose bytes are ``data``."""
    check(name, assembly_bytes(len(data) // _MIN_FACET_BYTES + 1), "reading it")
    if b"\n" not in data and b"\r" in data:  # lines ended by CR alone (old Mac files)
        data = data.replace(b"\r", b"\n")
    reader = _Reader(name, data)
    reader.read()
    corners = np.concatenate(reader.corners) if reader.corners else np.zeros((0, 3, 3))
    reader.corners.clear()
    normals = np.concatenate(reader.normals) if reader.normals else np.zeros((0, 3))
    offsets = np.concatenate(reader.offsets) if reader.offsets else np.zeros(0, np.int64)
    solids = None
    if len(reader.names) > 1:
        solids = np.repeat(np.array(reader.blocks, np.int32), [len(n) for n in reader.normals])
    reader.normals.clear()
    names = tuple(n or f"solid {i}" for i, n in enumerate(reader.names))
    return Facets(corners, normals, lambda f: f"line {reader.line(offsets[f])}", solids=solids,
                  solid_names=names, warnings=tuple(reader.warnings))
