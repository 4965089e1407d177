"""Binary STL: an 80-byte header, a little-endian uint32 facet count, then 50 bytes per facet
(normal and three corners as 12 little-endian float32, and a 16-bit attribute word), read
through one structured ``frombuffer`` of the file's bytes: no Python loop per facet, and no
copy (the weld reads the corners and normals where they are).

A file is binary when its size is exactly ``84 + 50 * count`` (:func:`is_binary`), whatever its
header says: a binary header may start with ``solid`` as an ASCII file does.
"""

from __future__ import annotations

import numpy as np

from rasterkit.stl.colors import face_colors
from rasterkit.stl.errors import StlError, check
from rasterkit.stl.facets import Facets, assembly_bytes

__all__ = ["FIRST_FACET", "RECORD", "facet_count", "is_binary", "read_binary", "size_error", "where"]

FIRST_FACET = 84
"""Where the facets start: after the 80-byte header and the facet count."""
RECORD = np.dtype([("normal", "<f4", (3,)), ("corners", "<f4", (3, 3)), ("attribute", "<u2")])
"""One facet of a binary STL file: 50 bytes, packed."""


def facet_count(data: bytes) -> int:
    """The facet count of a binary STL header (bytes 80-83); 0 without one."""
    return int.from_bytes(data[80:84], "little") if len(data) >= FIRST_FACET else 0


def is_binary(data: bytes, size: int | None = None) -> bool:
    """Whether ``data`` (the first bytes of a file of ``size`` bytes, at least 84 of them;
    ``size`` None: ``data`` is the whole file) is binary STL: ``84 + 50 * count == size``."""
    size = len(data) if size is None else size
    return len(data) >= FIRST_FACET and FIRST_FACET + RECORD.itemsize * facet_count(data) == size


def size_error(name: str, data: bytes, ascii_note: str) -> StlError:
    """The error of ``data``, which is neither ASCII STL (``ascii_note`` says why) nor, by its
    size, binary STL."""
    if not data:
        return StlError(name, None, "an empty file (0 bytes)")
    if len(data) < FIRST_FACET:
        return StlError(name, None, f"not an STL file: {len(data)} bytes, shorter than a binary STL header "
                                    f"(84 bytes), and {ascii_note}")
    count = facet_count(data)
    need = FIRST_FACET + RECORD.itemsize * count
    whole = (len(data) - FIRST_FACET) // RECORD.itemsize
    if need > len(data):
        what = f"the file has {len(data)} bytes ({whole} whole facets): truncated?"
    else:
        what = f"the file has {len(data)} bytes ({len(data) - need} more)"
    return StlError(name, None, f"the facet count of a binary STL header is {count} ({need} bytes), but {what} "
                                f"(and {ascii_note})", location="byte 80")


def where(k: int) -> str:
    """The place of facet k in a binary file."""
    return f"facet {k} (byte {FIRST_FACET + RECORD.itemsize * k})"


def read_binary(name: str, data: bytes) -> Facets:
    """The facets of the binary STL file ``name`` whose bytes are ``data`` (:func:`is_binary`)."""
    count = facet_count(data)
    check(name, assembly_bytes(count), f"reading its {count} facets")
    records = np.frombuffer(data, RECORD, count, FIRST_FACET)
    colors, note = face_colors(data[:80], records["attribute"])
    return Facets(records["corners"], records["normal"], where, colors=colors, warnings=() if note is None else (note,))
