"""The header of an OFF file: the optional keyword and the counts.

Geomview's grammar (``[ST][C][N][4][n]OFF``, then ``NVertices NFaces NEdges``)::

    [ST][C][N]OFF [BINARY]     # optional: texture coordinates, colours, normals per vertex
    NVertices NFaces [NEdges]  # NEdges is read by nobody; it may be missing

The counts may be on the keyword's line (``OFF 8 6 12``) or glued to the keyword (``OFF8 6 12``,
as in ModelNet). ``4OFF`` (homogeneous 4D vertices), ``nOFF`` with another dimension than 3, and
binary OFF (``OFF BINARY``) are refused by name. The counts are checked against the lines that
follow them before anything is allocated.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from rasterkit.off.errors import OffError
from rasterkit.off.records import Records
from rasterkit.runtime.tokens import shown

__all__ = ["Header", "read_header"]

_KEYWORD = re.compile(rb"(ST)?(C)?(N)?(4)?(n)?OFF(.*)", re.S)
_COUNT = re.compile(rb"\+?[0-9]{1,18}")


@dataclass(frozen=True)
class Header:
    """What the header says: per-vertex texture coordinates, colours and normals; the counts;
    the record where the vertices start."""

    keyword: str
    texcoords: bool
    colors: bool
    normals: bool
    n_vertices: int
    n_faces: int
    body: int


class _Words:
    """The header's tokens in order, across records, with the line of each."""

    def __init__(self, name: str, records: Records):
        self.name, self.records = name, records
        self.record, self.words = 0, records.words(0)

    def next_record(self) -> None:
        self.record += 1
        self.words = self.records.words(self.record) if self.record < len(self.records) else []

    def fail(self, reason: str):
        line = int(self.records.line[min(self.record, len(self.records) - 1)])
        raise OffError(self.name, line, reason)

    def integer(self, word: bytes, what: str) -> int:
        if not _COUNT.fullmatch(word):
            self.fail(f"expected {what}, got {shown(word)}")
        return int(word)


def read_header(name: str, records: Records) -> Header:
    """The header of the OFF file ``name`` whose records are ``records``."""
    words = _Words(name, records)
    keyword = _KEYWORD.fullmatch(words.words[0])
    flags = (False,) * 5
    if keyword is not None:
        flags = tuple(group is not None for group in keyword.groups()[:5])
        glued = keyword.group(6)
        words.words = ([glued] if glued else []) + words.words[1:]
        if glued and not glued.isdigit():
            words.fail(f"unknown keyword {shown(words.records.words(0)[0])} (OFF, COFF, NOFF, STOFF, CNOFF...)")
        if any(w.upper() == b"BINARY" for w in words.words):
            words.fail("binary OFF (OFF BINARY) is not supported: convert it to text OFF")
        if flags[3]:
            words.fail("4OFF (homogeneous 4D vertices) is not supported")
        if not words.words:
            words.next_record()
    elif not _COUNT.fullmatch(words.words[0]):
        words.fail(f"expected the keyword OFF (or COFF, NOFF, STOFF...) or the counts, got {shown(words.words[0])}")
    if flags[4]:
        dimension = words.integer(words.words[0] if words.words else b"", "the dimension of nOFF")
        if dimension != 3:
            words.fail(f"nOFF with vertices of {dimension} dimensions is not supported (only 3)")
        words.words = words.words[1:]
        if not words.words:
            words.next_record()
    counts = words.words
    if len(counts) not in (2, 3):
        got = "the end of the file" if not counts else f"{len(counts) if len(counts) < 8 else 'more than 3'} numbers"
        words.fail(f"expected the counts NVertices NFaces [NEdges], got {got}")
    n_vertices, n_faces = (words.integer(w, "a count") for w in counts[:2])
    body = words.record + 1
    if n_vertices + n_faces > len(records) - body:
        words.fail(f"the header says {n_vertices} vertices and {n_faces} faces, but only "
                   f"{len(records) - body} lines of numbers follow it (truncated?)")
    text = (keyword.group(0)[:len(keyword.group(0)) - len(keyword.group(6))] if keyword else b"").decode()
    return Header(text, flags[0], flags[1], flags[2], n_vertices, n_faces, body)
