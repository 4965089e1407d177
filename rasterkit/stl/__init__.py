"""``read_stl(path) -> Mesh``: STL files, binary and ASCII, as a welded triangle mesh.

What is read
------------
- **Binary** STL (``rasterkit.stl.binary``): a file whose size is exactly ``84 + 50 * count``
  for the facet count in bytes 80-83, whatever its 80-byte header says (a binary header may
  start with ``solid``). Read with one structured ``frombuffer``, welded where it lies.
- **ASCII** STL (``rasterkit.stl.ascii``): any other file that starts with ``solid``; one or
  more ``solid ... endsolid`` blocks (names optional, on ``endsolid`` too), keywords in any
  case, any whitespace between tokens, LF or CRLF, a UTF-8 byte order mark. Numbers are the
  correctly rounded float64 of their text (``nan`` and ``inf`` too: such facets are dropped,
  below). Several blocks give ``Mesh.face_groups`` and ``group_names`` (the blocks' names).
- **Welding** (``rasterkit.stl.weld``): corners with equal coordinates (as numbers: ``-0.0``
  is ``0.0``, and is read as ``0.0``) become one vertex, numbered in order of first appearance
  among the facets kept, so the output depends on nothing but the file; ``edges`` are then the
  mesh's real edges (each side of two facets once), which ``hidden``, ``solid+wire`` and smooth
  shading need. Vertices are float64 (a binary file's float32 converted exactly). Facets keep
  the file's winding. One kernel pass finds the facets' flaws (below), welds and keeps the
  normals.
- **Normals** (``rasterkit.stl.normals``): the file's facet normals become ``corner_normals``
  (one unit row per facet) with ``normal_index`` (each facet's three corners index its row), so
  a smooth render draws the facets flat, as the file describes them; flat shading and culling
  use the corners' winding, as they do for every mesh. Normals that are zero, NaN or infinite,
  or point against their facet's winding, are replaced by the facet's normal from its corners
  (with a warning); a file with no usable normal at all (many writers write zeros) has none
  (``corner_normals`` None), and smooth shading averages around the welded vertices.
- **Colours** (``rasterkit.stl.colors``, binary files only): ``face_colors`` from VisCAM /
  SolidView attribute words (bit 15 set) or from Materialise Magics (``COLOR=`` in the header,
  per facet where bit 15 is clear); none where the attribute words are filler.

What is dropped, with a warning in ``Mesh.warnings``
----------------------------------------------------
Facets with a NaN or infinite coordinate; facets with two equal corners (which welding would
make one vertex: no area, no edges of their own); a missing final ``endsolid``. Their corners
are no vertices.

What fails
----------
:class:`StlError` (a ``ValueError``), one line naming the file and the place: ``name:LINE:
reason`` in ASCII files, ``name: reason`` otherwise. A file that cannot be read, is not a
regular file, or is over :func:`rasterkit.limits.max_file_size` (:class:`StlLimitError`, also
a :class:`~rasterkit.limits.LimitError`, as is a file whose reading would need more than
:func:`rasterkit.limits.memory_limit`, estimated before the large arrays are made); a file that
is neither ASCII (no ``solid`` at the start) nor binary (its size is not ``84 + 50 * count``:
a truncated file, or one with bytes after its facets); ASCII text out of place (a facet of more
than three vertices, a number missing or malformed, text after the last ``endsolid``); a file
without facets. The header's count is checked against the file's size before anything is
allocated.

Speed (``python -m benchmarks.formats_stl_off``): see ``docs/formats-stl-off.md``.
"""

from __future__ import annotations

import os

from rasterkit.mesh import Mesh
from rasterkit.stl.ascii import read_ascii
from rasterkit.stl.binary import FIRST_FACET, RECORD, is_binary, read_binary, size_error
from rasterkit.stl.errors import StlError, StlLimitError, read_bytes
from rasterkit.stl.facets import mesh_fields, placed

__all__ = ["StlError", "StlLimitError", "read_stl", "sniff"]

_TEXT_SPACES = b"\t\n\r\x0b\x0c"


def read_stl(path=None, *, data: bytes | None = None) -> Mesh:
    """Read an STL file (binary or ASCII) as a :class:`~rasterkit.mesh.Mesh`.

    Parameters
    ----------
    path : str or os.PathLike, optional
        The file. With ``data``, only its name (for messages); without a path, messages name
        ``<bytes>``.
    data : bytes, optional
        The file's bytes, when they are at hand already (the file is then not read).

    Returns
    -------
    Mesh
        ``vertices`` (N, 3) float64, the welded corners; ``faces`` (M, 3) int64, one per
        facet kept, in file order; ``edges`` (E, 2) int64 sorted; ``corner_normals`` (M, 3)
        and ``normal_index`` (M, 3), or None; ``face_colors`` (M, 3) float32 or None;
        ``face_groups`` and ``group_names`` for several ``solid`` blocks; ``warnings``.
        See the module documentation for every rule.

    Raises
    ------
    StlError
        One line naming the file and the place (:class:`StlLimitError` for the limits).

    Examples
    --------
    >>> text = b'''solid square
    ... facet normal 0 0 1 outer loop vertex 0 0 0 vertex 1 0 0 vertex 1 1 0 endloop endfacet
    ... facet normal 0 0 1 outer loop vertex 0 0 0 vertex 1 1 0 vertex 0 1 0 endloop endfacet
    ... endsolid square'''
    >>> mesh = read_stl("square.stl", data=text)
    >>> mesh.faces.tolist()
    [[0, 1, 2], [0, 2, 3]]
    >>> mesh.edges.tolist()
    [[0, 1], [0, 2], [0, 3], [1, 2], [2, 3]]
    """
    if data is None:
        if path is None:
            raise TypeError("read_stl needs a path or data")
        name = os.fsdecode(path)
        data = read_bytes(name)
    else:
        name = "<bytes>" if path is None else os.fsdecode(path)
        data = bytes(data)
    if is_binary(data):
        facets = read_binary(name, data)
    elif _looks_ascii(data):
        facets = placed(name, read_ascii(name, data))  # so that the text can go before the weld
    elif data.removeprefix(b"\xef\xbb\xbf").lstrip()[:5].lower() == b"solid":
        raise size_error(name, data, "not ASCII STL either: binary bytes after 'solid'")
    else:
        raise size_error(name, data, "not ASCII STL either: no 'solid' at the start")
    if len(facets.corners) == 0:
        raise StlError(name, None, "no facets, nothing to draw")
    del data
    fields = mesh_fields(name, facets)
    del facets  # the file's bytes (the binary facets are a view of them) go before the Mesh copies its arrays
    return Mesh(**fields)


def _looks_ascii(head: bytes) -> bool:
    """``head`` starts with the ``solid`` keyword (after a byte order mark and whitespace), and
    its first bytes hold no control bytes but whitespace (a binary file's counts and floats do)."""
    text = head.removeprefix(b"\xef\xbb\xbf").lstrip(b" " + _TEXT_SPACES)
    if text[:5].lower() != b"solid" or not (len(text) == 5 or text[5:6] in b" " + _TEXT_SPACES):
        return False
    start = head[:FIRST_FACET + RECORD.itemsize].translate(None, _TEXT_SPACES)
    return not any(b < 32 or b == 127 for b in start)


def sniff(head: bytes, size: int | None = None) -> bool:
    """Whether ``head``, the first bytes of a file (at least 134 for a sure answer), look like
    STL: ASCII text starting with ``solid``, or, when the file's ``size`` is given, a binary
    file (``84 + 50 * count == size``). A binary file cannot be recognised without its size
    (any 84 bytes make a header)."""
    return _looks_ascii(head) or (size is not None and is_binary(head, size))
