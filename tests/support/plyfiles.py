"""Writing PLY files for the tests, independently of the reader: each value packed with
:mod:`struct` (binary) or formatted with ``repr`` (ASCII), row by row.

An element is ``(name, properties, rows)``: properties are ``(type, name)`` or
``("list", count_type, item_type, name)`` with the header's type names, rows are tuples with
one value per property (a sequence for a list).
"""

from __future__ import annotations

import struct

#: struct codes of the PLY types, by both names.
CODES = {"char": "b", "int8": "b", "uchar": "B", "uint8": "B", "short": "h", "int16": "h", "ushort": "H",
         "uint16": "H", "int": "i", "int32": "i", "uint": "I", "uint32": "I", "float": "f", "float32": "f",
         "double": "d", "float64": "d"}

FORMATS = {"ascii": None, "binary_little_endian": "<", "binary_big_endian": ">"}


def header(encoding: str, elements, comments=(), newline: str = "\n") -> bytes:
    lines = ["ply", f"format {encoding} 1.0", *(f"comment {c}" for c in comments)]
    for name, properties, rows in elements:
        lines.append(f"element {name} {len(rows)}")
        for p in properties:
            lines.append("property " + " ".join(p))
    lines.append("end_header")
    return (newline.join(lines) + newline).encode()


def _text(value, kind: str) -> str:
    return repr(float(value)) if CODES[kind] in "fd" else str(int(value))


def body(encoding: str, elements) -> bytes:
    order = FORMATS[encoding]
    out = []
    for _, properties, rows in elements:
        for row in rows:
            if order is None:
                words = []
                for p, value in zip(properties, row):
                    if p[0] == "list":
                        words.append(str(len(value)))
                        words.extend(_text(v, p[2]) for v in value)
                    else:
                        words.append(_text(value, p[0]))
                out.append((" ".join(words) + "\n").encode())
                continue
            for p, value in zip(properties, row):
                if p[0] == "list":
                    out.append(struct.pack(order + CODES[p[1]], len(value)))
                    out.append(struct.pack(order + CODES[p[2]] * len(value), *value))
                else:
                    out.append(struct.pack(order + CODES[p[0]], value))
    return b"".join(out)


def ply_bytes(encoding: str, elements, comments=()) -> bytes:
    return header(encoding, elements, comments) + body(encoding, elements)


def write_ply(path, encoding: str, elements, comments=()):
    path.write_bytes(ply_bytes(encoding, elements, comments))
    return path


XYZ = [("float", "x"), ("float", "y"), ("float", "z")]
FACES = [("list", "uchar", "int", "vertex_indices")]
SQUARE = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]


def square(encoding: str, faces=((0, 1, 2, 3),)) -> list:
    """The unit square's 4 vertices and ``faces``: elements for :func:`write_ply`."""
    return [("vertex", XYZ, SQUARE), ("face", FACES, [(list(f),) for f in faces])]
