"""The header of a PLY file: its format, its elements with their properties, and its comments.

::

    ply
    format binary_little_endian 1.0
    comment TextureFile wood.png
    element vertex 8
    property float x
    property list uchar int vertex_indices
    end_header

Lines end with LF or CR LF; words are separated by spaces and tabs; blank lines are
skipped. ``comment`` and ``obj_info`` lines may hold any bytes. The format is ``ascii``,
``binary_little_endian`` or ``binary_big_endian``, version 1.0. Scalar types go by both
their names (``char``/``int8``, ``uchar``/``uint8``, ``short``/``int16``,
``ushort``/``uint16``, ``int``/``int32``, ``uint``/``uint32``, ``float``/``float32``,
``double``/``float64``); a list's count type must be an integer type. Anything else (an
unknown keyword or type, a property before any element, a missing or repeated ``format``, a
count that is no whole number, words left over on a line, no ``end_header`` line) is a
:class:`~rasterkit.ply.errors.PlyError` naming the line.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

from rasterkit.ply.errors import PlyError

__all__ = ["ENCODINGS", "Element", "Header", "MAX_HEADER_LINES", "Property", "TYPES", "read_header"]

#: Every scalar type, by both of its names, as a NumPy type (native byte order).
TYPES = {
    "char": np.dtype(np.int8), "int8": np.dtype(np.int8),
    "uchar": np.dtype(np.uint8), "uint8": np.dtype(np.uint8),
    "short": np.dtype(np.int16), "int16": np.dtype(np.int16),
    "ushort": np.dtype(np.uint16), "uint16": np.dtype(np.uint16),
    "int": np.dtype(np.int32), "int32": np.dtype(np.int32),
    "uint": np.dtype(np.uint32), "uint32": np.dtype(np.uint32),
    "float": np.dtype(np.float32), "float32": np.dtype(np.float32),
    "double": np.dtype(np.float64), "float64": np.dtype(np.float64),
}

#: The formats, and the byte order of their binary values (None: text).
ENCODINGS = {"ascii": None, "binary_little_endian": "<", "binary_big_endian": ">"}

#: A header of more lines is refused (a hostile file of comments would take long to read).
MAX_HEADER_LINES = 100_000

_END = re.compile(rb"(?m)^end_header[ \t]*(?:\r?\n|\r?\Z)")
_WHOLE = re.compile(r"[0-9]+")


@dataclass(frozen=True)
class Property:
    """One property of an element: its ``name``, its (item) type ``dtype``, the type of its
    count when it is a list (``count``, else None), the header line declaring it, and the
    types as the header names them (``words``: ``("uchar",)`` or ``("uchar", "int")``)."""

    name: str
    dtype: np.dtype
    count: np.dtype | None
    line: int
    words: tuple = ()

    @property
    def type_name(self) -> str:
        return self.words[-1] if self.words else self.dtype.name

    @property
    def count_name(self) -> str | None:
        return self.words[0] if self.count is not None and self.words else None

    @property
    def is_list(self) -> bool:
        return self.count is not None


@dataclass(frozen=True)
class Element:
    """One element: its ``name``, the ``count`` of its rows, its properties in file order
    and the header line declaring it."""

    name: str
    count: int
    properties: tuple
    line: int

    def find(self, *names: str) -> Property | None:
        """The first property with one of ``names`` (tried in order), or None."""
        for name in names:
            for p in self.properties:
                if p.name == name:
                    return p
        return None

    @property
    def has_lists(self) -> bool:
        return any(p.is_list for p in self.properties)


@dataclass(frozen=True)
class Header:
    """The parsed header: ``encoding`` (a key of :data:`ENCODINGS`), ``elements`` in file
    order, ``comments`` ((line, text bytes) of each ``comment`` line), ``body`` (the offset
    of the body's first byte) and ``lines`` (the header's line count: an ASCII body's first
    line is ``lines + 1``)."""

    encoding: str
    elements: tuple
    comments: tuple
    body: int
    lines: int

    @property
    def byte_order(self) -> str | None:
        return ENCODINGS[self.encoding]

    def element(self, name: str) -> Element | None:
        return next((e for e in self.elements if e.name == name), None)


def sniff(head: bytes) -> bool:
    """Whether ``head`` (a file's first bytes) starts as a PLY file: ``ply`` and a line break."""
    return head.startswith((b"ply\n", b"ply\r\n"))


def read_header(data: bytes, name: str) -> Header:
    """The header of the file ``name`` whose bytes are ``data``."""
    if not sniff(data):
        shown = data[:16].split(b"\n")[0]
        raise PlyError(name, 1, f"not a PLY file: it starts with {shown!r}, not 'ply' and a line break")
    end = _END.search(data)
    if end is None:
        raise PlyError(name, None, "the header has no 'end_header' line (not a PLY file, or cut short)")
    text = data[:end.start()]
    if text.count(b"\n") > MAX_HEADER_LINES:
        raise PlyError(name, None, f"the header has more than {MAX_HEADER_LINES} lines")
    parser = _Parser(name)
    lines = text.split(b"\n")
    for number, line in enumerate(lines[1:-1] if lines[-1] == b"" else lines[1:], start=2):
        parser.line(number, line.rstrip(b"\r"))
    return parser.finish(end.end(), text.count(b"\n") + 1)


class _Parser:
    """The header's lines, one at a time."""

    def __init__(self, name: str):
        self.name = name
        self.encoding: str | None = None
        self.elements: list = []  # [name, count, [Property], line]
        self.comments: list = []

    def fail(self, number: int, reason: str):
        raise PlyError(self.name, number, reason)

    def line(self, number: int, line: bytes) -> None:
        words = line.split()
        if not words:
            return
        keyword = words[0]
        if keyword in (b"comment", b"obj_info"):
            if keyword == b"comment":
                self.comments.append((number, line.split(None, 1)[1] if len(words) > 1 else b""))
            return
        try:
            words = [w.decode("utf-8") for w in words]
        except UnicodeDecodeError:
            self.fail(number, f"the header line {line[:60]!r} is not UTF-8 text")
        if keyword == b"format":
            self.format(number, words)
        elif keyword == b"element":
            self.element(number, words)
        elif keyword == b"property":
            self.property(number, words)
        else:
            self.fail(number, f"unknown header line {' '.join(words)[:60]!r} (expected format, element, "
                              "property, comment, obj_info or end_header)")

    def format(self, number: int, words: list) -> None:
        if self.encoding is not None:
            self.fail(number, "a second 'format' line")
        if len(words) != 3:
            self.fail(number, "expected 'format ENCODING 1.0'")
        if words[1] not in ENCODINGS:
            self.fail(number, f"unknown format {words[1]!r} (expected {', '.join(ENCODINGS)})")
        try:
            version = float(words[2])
        except ValueError:
            version = None
        if version != 1.0:
            self.fail(number, f"version {words[2]!r} is not read (only 1.0)")
        self.encoding = words[1]

    def element(self, number: int, words: list) -> None:
        if len(words) != 3:
            self.fail(number, "expected 'element NAME COUNT'")
        if not _WHOLE.fullmatch(words[2]):
            self.fail(number, f"the count of element {words[1]!r} must be a whole number >= 0, got {words[2][:40]!r}")
        if len(words[2].lstrip("0")) > 18:  # no file holds 10**18 rows (and Python reads at most 4300 digits)
            self.fail(number, f"the count of element {words[1]!r} is too large ({len(words[2])} digits)")
        if any(e[0] == words[1] for e in self.elements):
            self.fail(number, f"element {words[1]!r} is declared twice")
        self.elements.append([words[1], int(words[2]), [], number])

    def property(self, number: int, words: list) -> None:
        if not self.elements:
            self.fail(number, "a property before any element")
        if len(words) >= 2 and words[1] == "list":
            if len(words) != 5:
                self.fail(number, "expected 'property list COUNT_TYPE ITEM_TYPE NAME'")
            count, item, name = self.type(number, words[2]), self.type(number, words[3]), words[4]
            if count.kind not in "iu":
                self.fail(number, f"the count type of list {name!r} must be an integer type, got {words[2]!r}")
            types = (words[2], words[3])
        else:
            if len(words) != 3:
                self.fail(number, "expected 'property TYPE NAME' or 'property list COUNT_TYPE ITEM_TYPE NAME'")
            count, item, name, types = None, self.type(number, words[1]), words[2], (words[1],)
        self.elements[-1][2].append(Property(name, item, count, number, types))

    def type(self, number: int, word: str) -> np.dtype:
        if word not in TYPES:
            self.fail(number, f"unknown type {word!r} (expected one of {', '.join(TYPES)})")
        return TYPES[word]

    def finish(self, body: int, lines: int) -> Header:
        if self.encoding is None:
            self.fail(2, "no 'format' line")
        elements = tuple(Element(n, c, tuple(p), line) for n, c, p, line in self.elements)
        return Header(self.encoding, elements, tuple(self.comments), body, lines)
