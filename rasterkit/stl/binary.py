"""Binary STL: an 80-byte header, a little-endian uint32 facet count, then 50 bytes per facet
(normal and three corners as 12 little-endian float32, and a 16-bit attribute word), read with
one structured ``frombuffer``: no Python loop per facet.

A file is binary when its size is exactly ``84 + 50 * count`` (:func:`is_binary`), whatever its
header says: a binary header may start with ``solid`` as an ASCII file does.
"""

from __future__ import annotations

import numpy as np

from rasterkit.stl.colors import face_colors
from rasterkit.stl.errors import StlError, check
from rasterkit.stl.facets import Facets, assembly_bytes

__all__ = ["HEADER_BYTES", "RECORD", "facet_count", "is_binary", "read_binary", "size_error", "where"]

HEADER_BYTES = 84
RECORD = np.dtype([("normal", "<f4", (3,)), ("corners", "<f4", (3, 3)), ("attribute", "<u2")])
"""One facet of a binary STL file: 50 bytes, packed."""


def facet_count(data: bytes) -> int:
    """The facet count of a binary STL header (bytes 80-83); 0 without one."""
    return int.from_bytes(data[80:84], "little") if len(data) >= HEADER_BYTES else 0


def is_binary(data: bytes, size: int | None = None) -> bool:
    """Whether ``data`` (the file's first bytes at least 84 of them, of a file of ``size``
    bytes: ``len(data)`` when None) is a binary STL file: ``84 + 50 * count == size``."""
    size = len(data) if size is None else size
    return len(data) >= HEADER_BYTES and HEADER_BYTES + RECORD.itemsize * facet_count(data) == size


def size_error(name: str, data: bytes, ascii_note: str) -> StlError:
    """The error of ``data``, which is neither ASCII STL (``ascii_note`` says why) nor, by its
    size, binary STL."""
    if not data:
        return StlError(name, None, "an empty file (0 bytes)")
    if len(data) < HEADER_BYTES:
        return StlError(name, None, f"not an STL file: {len(data)} bytes, shorter than a binary STL header "
                                    f"({HEADER_BYTES} bytes), and {ascii_note}")
    count = facet_count(data)
    need = HEADER_BYTES + RECORD.itemsize * count
    whole = (len(data) - HEADER_BYTES) // RECORD.itemsize
    if need > len(data):
        what = f"the file has {len(data)} bytes ({whole} whole facets): truncated?"
    else:
        what = f"the file has {len(data)} bytes ({len(data) - need} more)"
    return StlError(name, None, f"the facet count of a binary STL header is {count} ({need} bytes), but {what} "
                                f"(and {ascii_note})", location="byte 80")


def where(k: int) -> str:
    """The place of facet k in a binary file."""
    return f"facet {k} (byte {HEADER_BYTES + RECORD.itemsize * k})"


def read_binary(name: str, data: bytes) -> Facets:
    """The facets of the binary STL file ``name`` whose bytes are ``data`` (:func:`is_binary`)."""
    count = facet_count(data)
    check(name, count * (RECORD.itemsize + 48) + assembly_bytes(count), f"reading its {count} facets")
    records = np.frombuffer(data, RECORD, count, HEADER_BYTES)
    colors, note = face_colors(data[:80], records["attribute"])
    # copies, always: a view of one record is contiguous, read-only, and would keep the file
    return Facets(records["corners"].copy(), records["normal"].copy(), where,
                  colors=colors, warnings=() if note is None else (note,))
