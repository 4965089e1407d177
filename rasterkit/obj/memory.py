"""How much memory loading an OBJ file takes, estimated before the large arrays are made: a file
whose loading would need more than :func:`rasterkit.limits.memory_limit` is refused with one
line (an :class:`~rasterkit.obj.errors.ObjLimitError`) instead of running the machine out of
memory.

A file within the file size limit can still need many times its size: two bytes (``v`` and a
line break) make a statement that costs a row of every table. The estimates below are made in
two steps, each before the arrays it accounts for: :func:`check_scan` before the statement
table is made (from the count of line breaks), :func:`check_statements` before the geometry is
parsed (from the kinds of the statements and the corners of the faces). They err on the large
side: a real model needs less.
"""

from __future__ import annotations

import numpy as np

from rasterkit.obj.errors import ObjLimitError, count
from rasterkit.obj.kernels.ears import EAR_CLIP_LIMIT
from rasterkit.obj.kernels.scan import (
    KIND_F, KIND_G, KIND_L, KIND_MTLLIB, KIND_O, KIND_USEMTL, KIND_V, KIND_VN, KIND_VT,
)
from rasterkit.limits import LimitError, check_memory, memory_limit

__all__ = ["check_scan", "check_statements", "parse_budget"]

#: Bytes of the statement table per line (start, end, token count, kind), and of the copy of
#: the text that blanking continuations may make, per byte.
SCAN_BYTES_PER_LINE = 25

#: Bytes per statement of each kind while it is parsed and assembled (numbers, corner runs,
#: their checks; names as Python strings), and per other statement.
BYTES_PER_STATEMENT = {KIND_V: 128, KIND_VT: 64, KIND_VN: 64, KIND_F: 64, KIND_L: 64,
                       KIND_G: 160, KIND_O: 160, KIND_USEMTL: 160, KIND_MTLLIB: 160}
BYTES_PER_OTHER_STATEMENT = 8

#: Bytes per face or line corner (indices, triangles, sides, their sorting), more when the
#: file has ``/`` (texture and normal indices), and more for the corners of polygons larger
#: than ear clipping takes (plane coordinates and the sweep's tables).
BYTES_PER_CORNER = 48
BYTES_PER_ATTRIBUTE_CORNER = 32
BYTES_PER_LARGE_POLYGON_CORNER = 160


def _check(name: str, nbytes: float, what: str) -> None:
    try:
        check_memory(nbytes, what)
    except LimitError as e:
        raise ObjLimitError(name, None, str(e)) from None


def check_scan(name: str, text: bytes) -> int:
    """Before the statement table of text (the file's bytes) is made. Returns the number of
    its lines, or more: a file has at most one line more than bytes, and its lines are only
    counted when that many would be over the limit."""
    lines = len(text) + 1
    if len(text) + SCAN_BYTES_PER_LINE * lines > memory_limit():
        lines = text.count(b"\n") + 1
        _check(name, len(text) + SCAN_BYTES_PER_LINE * lines, f"reading its {count(lines, 'line')}")
    return lines


def parse_budget(size: int, lines: int) -> int:
    """The bytes the numbers and corners of a file's statements may take while they are read
    (:mod:`rasterkit.obj.chunks`), before :func:`check_statements` has the whole statement
    table: what the limit leaves beside the text and the statement table of ``lines``
    lines (:func:`check_scan`'s)."""
    return max(0, memory_limit() - size - SCAN_BYTES_PER_LINE * lines)


def check_statements(doc) -> None:
    """Before the statements of doc (a scanned Document) are parsed."""
    kinds = np.bincount(doc.kinds, minlength=16)
    # what is made already (the text and the statement table) is still there at the end
    nbytes = float(len(doc.text) + (SCAN_BYTES_PER_LINE + BYTES_PER_OTHER_STATEMENT) *
                   len(doc.kinds))
    for kind, cost in BYTES_PER_STATEMENT.items():
        nbytes += cost * int(kinds[kind])
    elements = (doc.kinds == KIND_F) | (doc.kinds == KIND_L)
    sizes = doc.ntokens[elements]
    per_corner = BYTES_PER_CORNER + (BYTES_PER_ATTRIBUTE_CORNER if b"/" in doc.text else 0)
    nbytes += per_corner * float(sizes.sum())
    nbytes += BYTES_PER_LARGE_POLYGON_CORNER * float(sizes[sizes > EAR_CLIP_LIMIT].sum())
    _check(doc.name, nbytes, f"loading its {count(len(doc.kinds), 'statement')}")
