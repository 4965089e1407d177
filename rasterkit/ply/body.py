"""The body of a PLY file: the rows of every element, in the header's order, read from an
ASCII or a binary body (:mod:`rasterkit.ply.ascii`, :mod:`rasterkit.ply.binary`) by
:mod:`rasterkit.ply.rows`.

Every element is walked, the unknown ones too (the elements after them depend on where they
end). What follows the last element: in an ASCII body, more values are an error (the
header's counts do not describe the body, so what was read is in doubt), whitespace is not;
in a binary body, extra bytes are a warning (a padded or appended-to file reads the same).
"""

from __future__ import annotations

from rasterkit.ply.ascii import TokenSource
from rasterkit.ply.binary import BinarySource
from rasterkit.ply.errors import Notes, PlyError, count
from rasterkit.ply.header import Header
from rasterkit.ply.rows import read_rows

__all__ = ["read_body"]


def read_body(data: bytes, header: Header, name: str, notes: Notes) -> dict:
    """``{element name: Rows}`` of every element of the file ``name`` (bytes ``data``)."""
    if header.encoding == "ascii":
        source, at = TokenSource(name, data, header.body, header.lines), 0
    else:
        source, at = BinarySource(name, data, header.byte_order), header.body
    rows = {}
    for element in header.elements:
        rows[element.name], at = read_rows(source, element, at)
    left = source.units - at
    if left and header.encoding == "ascii":
        last = header.elements[-1].name if header.elements else None
        raise PlyError(name, source.line(at), f"{count(left, 'value')} after the last element"
                                              f"{'' if last is None else f' ({last!r})'}: the header's counts "
                                              "do not match the body")
    if left:
        notes.warn(source.where(at), f"{count(left, 'byte')} after the last element, ignored")
    return rows
