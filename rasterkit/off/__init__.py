"""``read_off(path) -> Mesh``: OFF files (Geomview's Object File Format, and its COFF, NOFF,
STOFF variants), as ModelNet and many geometry-processing datasets have them.

What is read
------------
- The header (``rasterkit.off.header``): an optional keyword ``[ST][C][N][n]OFF`` (texture
  coordinates, colours, normals per vertex; ``nOFF`` with dimension 3), then ``NVertices
  NFaces [NEdges]``, on the keyword's line, glued to it (``OFF490 518 0``, as in ModelNet) or on
  the next; ``NEdges`` is ignored, and may be missing.
- Vertex and face lines (``rasterkit.off.body``): ``x y z`` with the keyword's normals, colour
  and texture coordinates in Geomview's order; in a file without ``C`` in its keyword, 3 or 4
  numbers more on a vertex line are its colour. ``n v1 ... vn`` faces of any size, vertex indices
  from 0, and after them an optional colour of 3 or 4 numbers (1 or 2 numbers, a colour map
  index, are ignored with a warning). Colours (``rasterkit.off.colors``) are 0..255 when every
  value of the kind (vertex or face colours) is written as an integer or one is above 1, else
  0..1; alpha is dropped.
- ``#`` comments anywhere (to the end of the line), blank lines, any whitespace, LF, CRLF or CR
  line ends, a UTF-8 byte order mark. Numbers are the correctly rounded float64 of their text.
- Polygons are split into triangles as OBJ polygons are (``rasterkit.off.assemble``: concave
  ones exactly), and ``Mesh.edges`` are the polygons' own sides.

The Mesh: ``vertices`` (N, 3) float64 in file order; ``faces`` (M, 3) int64 triangles with the
file's winding; ``edges``; ``normals`` (NOFF, unit length); ``vertex_colors`` and
``face_colors`` (one per triangle, its polygon's) where the file has them; ``texcoords`` and
``uv`` (one per vertex, STOFF). Faces using a vertex with a NaN or infinite coordinate are
dropped with a warning; a file without faces gives a Mesh of vertices only (a point cloud),
with a warning.

What fails
----------
:class:`OffError` (a ``ValueError``), one line ``name:LINE: reason`` (``name: reason`` when
no line is to blame): a file that cannot be read, is not a regular file, or is over
:func:`rasterkit.limits.max_file_size`, or whose reading would need more than
:func:`rasterkit.limits.memory_limit` (these two: :class:`OffLimitError`, also a
:class:`~rasterkit.limits.LimitError`); binary OFF (``OFF BINARY``), ``4OFF`` and ``nOFF`` of
another dimension than 3 (by name); counts that more lines than the file has would be needed
for (checked before anything is allocated); a vertex or face line with a wrong count of numbers,
a malformed number, a face of fewer than 3 vertices or with an index out of range.
"""

from __future__ import annotations

import os

from rasterkit.mesh import Mesh
from rasterkit.off.assemble import to_mesh
from rasterkit.off.body import read_faces, read_vertices
from rasterkit.off.errors import OffError, OffLimitError, read_bytes
from rasterkit.off.header import read_header
from rasterkit.off.records import read_records

__all__ = ["OffError", "OffLimitError", "read_off", "sniff"]

_KEYWORDS = (b"OFF", b"COFF", b"NOFF", b"CNOFF", b"STOFF", b"STCOFF", b"STNOFF", b"STCNOFF", b"nOFF", b"CnOFF",
             b"NnOFF", b"CNnOFF")


def read_off(path=None, *, data: bytes | None = None) -> Mesh:
    """Read an OFF file as a :class:`~rasterkit.mesh.Mesh`.

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
        See the module documentation.

    Raises
    ------
    OffError
        One line ``name:LINE: reason`` (:class:`OffLimitError` for the limits).

    Examples
    --------
    >>> square = b"OFF\\n4 1 4\\n0 0 0\\n1 0 0\\n1 1 0\\n0 1 0\\n4 0 1 2 3 255 0 0\\n"
    >>> mesh = read_off("square.off", data=square)
    >>> mesh.faces.tolist()
    [[0, 1, 2], [0, 2, 3]]
    >>> mesh.edges.tolist()
    [[0, 1], [0, 3], [1, 2], [2, 3]]
    >>> mesh.face_colors.tolist()
    [[1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]
    """
    if data is None:
        if path is None:
            raise TypeError("read_off needs a path or data")
        name = os.fsdecode(path)
        data = read_bytes(name)
    else:
        name = "<bytes>" if path is None else os.fsdecode(path)
        data = bytes(data)
    records = read_records(name, data)
    header = read_header(name, records)
    warnings: list[str] = []
    vertices = read_vertices(name, records, header, warnings)
    faces = read_faces(name, records, header, warnings)
    left = len(records) - header.body - header.n_vertices - header.n_faces
    if left:
        warnings.append(f"{left} lines after the {header.n_faces} faces ignored (the first: line "
                        f"{records.line[len(records) - left]})")
    del records  # the token tables go before the triangles are made
    if not header.n_faces:
        warnings.append("no faces: the vertices alone (a point cloud)")
    return to_mesh(name, vertices, faces, warnings)


def sniff(head: bytes) -> bool:
    """Whether ``head``, the first bytes of a file, look like OFF: a keyword of
    ``[ST][C][N][n]OFF`` first (after comments and blank lines; counts may be glued to it),
    or no keyword and a first line of two or three counts followed by a line of numbers."""
    lines = [line.split(b"#")[0].split() for line in head.removeprefix(b"\xef\xbb\xbf").splitlines()]
    lines = [words for words in lines if words][:2]
    if not lines:
        return False
    keyword = lines[0][0].rstrip(b"0123456789")
    if keyword in _KEYWORDS:
        return keyword == lines[0][0] or len(lines[0]) >= 2
    return (len(lines) == 2 and len(lines[0]) in (2, 3) and all(w.isdigit() for w in lines[0])
            and len(lines[1]) >= 3 and all(_number(w) for w in lines[1]))


def _number(word: bytes) -> bool:
    try:
        float(word)
    except ValueError:
        return False
    return b"_" not in word
