"""``read_ply(path) -> Mesh | PointCloud``: the Stanford polygon file format (PLY), ASCII and
binary, as a :class:`rasterkit.Mesh` when it has faces and as a :class:`PointCloud` when not.

The reader's parts, in the order it uses them: ``errors`` (:class:`PlyError`, the warnings),
``header`` (the header's elements, properties and comments), ``body`` (the rows of every
element, through ``rows`` from an ``ascii`` or ``binary`` body), ``vertices`` (positions,
colours, normals, texture coordinates), ``faces`` (polygons, triangles, edges, the edge
element), ``corners`` (face colours, per-corner texture coordinates, texture numbers),
``textures`` (``comment TextureFile``) and ``cloud`` (:class:`PointCloud`); its kernels in
``kernels/`` (``tokens``: an ASCII body's numbers; ``rows``: the rows of elements whose lists
vary in length; ``edges``: the polygons' sides as keys).

What is read
------------
- Formats ``ascii``, ``binary_little_endian`` and ``binary_big_endian``, version 1.0; every
  scalar type by both names (``char``/``int8`` ... ``double``/``float64``), lists of any
  count and item type; ``comment`` and ``obj_info`` lines (:mod:`rasterkit.ply.header`).
- Element ``vertex``: ``x y z`` (required), ``nx ny nz``, ``red green blue`` (or
  ``diffuse_red``..., ``r g b``; integers divided by their type's largest value, floats 0 to
  1), texture coordinates ``u v`` (or ``s t``, ``texture_u texture_v``, ``texture_s
  texture_t``) (:mod:`rasterkit.ply.vertices`).
- Element ``face``: ``vertex_indices`` (or ``vertex_index``), polygons of any size split into
  triangles as OBJ polygons are, the polygons' sides as ``Mesh.edges``; ``red green blue`` as
  ``face_colors``; MeshLab's per-corner ``texcoord`` list as ``uv`` with ``uv_index``
  (:mod:`rasterkit.ply.faces`, :mod:`rasterkit.ply.corners`). Element ``edge`` (``vertex1
  vertex2``) as ``Mesh.lines``.
- ``comment TextureFile NAME``: a :class:`rasterkit.Material` whose ``diffuse_map`` is the
  image NAME beside the file, for faces with texture coordinates (per corner or per vertex;
  several such comments are told apart by the faces' ``texnumber``)
  (:mod:`rasterkit.ply.textures`).
- Every other element and property is skipped, wherever it is (unknown lists too, and
  elements before ``vertex``); skipped elements are named in one warning.

A file without faces (no face element, or one of 0 rows) and without edges is a point cloud.

What fails
----------
:class:`PlyError` (a ``ValueError``), one line that starts with the file's name and says
where: ``NAME:LINE: reason`` in the header and in an ASCII body (with ``element 'face' row
K:`` before the reason: rows count from 0), ``NAME: element 'face' row K (byte OFFSET):
reason`` in a binary body. A file that cannot be read, is not a regular file or is over the
file size limit; a header that is not PLY (an unknown keyword, type or format, no
``end_header``, a count that is no whole number, no ``vertex`` element or no ``x``/``y``/``z``,
faces without a list of integers); a body that ends early (every element's rows are checked
against the bytes or values left before anything is allocated for them, so a header claiming
billions of rows fails at once), a list count that is negative or goes past the end, a value
that is no number, an integer property that is no whole number in its type's range, more
values after the last element of an ASCII body; a face of fewer than 3 vertices or an index
out of range; a file with no vertices. Reading that would need more memory than
:func:`rasterkit.limits.memory_limit` is a :class:`PlyLimitError` (also a
:class:`~rasterkit.limits.LimitError`), raised before the large arrays are made.

Warnings (one-line strings in ``Mesh.warnings`` or ``PointCloud.warnings``, never printed):
skipped elements, bytes after the last element of a binary body, faces dropped for NaN or
infinite vertices, polygons split inexactly, colours out of range, NaN normals, texture files
that cannot be read. Reading issues no NumPy warning.
"""

from __future__ import annotations

import os

import numpy as np

from rasterkit.material import Material
from rasterkit.mesh import Mesh, polygon_mesh_edges
from rasterkit.ply.body import read_body
from rasterkit.ply.cloud import PointCloud
from rasterkit.ply.corners import corner_texcoords, corner_uv, face_colors, texture_numbers
from rasterkit.ply.errors import Notes, PlyError, PlyLimitError, count
from rasterkit.ply.faces import MAX_VERTICES, check_face_element, read_lines, read_polygons, triangulate
from rasterkit.ply.header import read_header, sniff
from rasterkit.ply.textures import read_textures, texture_files
from rasterkit.ply.vertices import check_vertex_element, read_vertices
from rasterkit.runtime import files as _files

__all__ = ["PlyError", "PlyLimitError", "PointCloud", "read_ply", "sniff"]

#: The elements the reader knows; others are skipped.
KNOWN_ELEMENTS = ("vertex", "face", "edge")


def read_ply(path, *, textures: bool = True) -> Mesh | PointCloud:
    """Read a PLY file.

    Parameters
    ----------
    path : str or os.PathLike
    textures : bool
        Open the images that ``comment TextureFile`` lines name (as ``Mesh.materials``);
        False opens none.

    Returns
    -------
    Mesh
        When the file has faces (or edges): ``vertices`` (N, 3) float64, one per vertex row;
        ``faces`` (M, 3) int64 triangles; ``edges`` the polygons' sides and ``lines``; and,
        when the file has them, ``vertex_colors``, ``normals`` (unit length), ``texcoords``,
        ``face_colors``, per-corner ``uv`` with ``uv_index`` (or per-vertex ``uv``),
        ``material_names``, ``face_materials`` and ``materials``.
    PointCloud
        When it has neither: ``points`` (N, 3) float64, ``colors`` and ``normals`` or None.

    Raises
    ------
    PlyError
        One line naming the file and where (see the module documentation); a
        :class:`PlyLimitError` over the file size or memory limit.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "quad.ply"
    >>> _ = path.write_text("ply\\nformat ascii 1.0\\nelement vertex 4\\nproperty float x\\n"
    ...                     "property float y\\nproperty float z\\nelement face 1\\n"
    ...                     "property list uchar int vertex_indices\\nend_header\\n"
    ...                     "0 0 0\\n1 0 0\\n1 1 0\\n0 1 0\\n4 0 1 2 3\\n")
    >>> mesh = read_ply(path)
    >>> mesh.faces
    array([[0, 1, 2],
           [0, 2, 3]])
    >>> mesh.edges.tolist()
    [[0, 1], [0, 3], [1, 2], [2, 3]]
    """
    name = os.fsdecode(path)
    data = _read_file(name)
    # NaN, infinities and signalling NaNs of any file convert as IEEE says, without warnings
    with np.errstate(all="ignore"):
        return _read(name, data, textures)


def _read(name: str, data: bytes, textures: bool) -> Mesh | PointCloud:
    header = read_header(data, name)
    vertex = check_vertex_element(header, name)
    face = check_face_element(header, name)
    notes = Notes(name)
    rows = read_body(data, header, name, notes)
    skipped = [e for e in header.elements if e.name not in KNOWN_ELEMENTS and e.count]
    if skipped:
        shown = ", ".join(f"{e.name!r} ({count(e.count, 'row')})" for e in skipped[:5])
        notes.warn(skipped[0].line, f"skipped {count(len(skipped), 'element')} the reader does not know: {shown}"
                                    + (", ..." if len(skipped) > 5 else ""))
    if vertex.count == 0:
        raise PlyError(name, vertex.line, "no vertices: nothing to draw")
    vertices = read_vertices(rows["vertex"], notes)
    edge = header.element("edge")
    finite = np.isfinite(vertices.positions).all(axis=1)
    lines = read_lines(rows["edge"], edge, len(finite), finite, notes) if edge is not None and edge.count else None
    if (face is None or face.count == 0) and lines is None:
        if not finite.all():
            notes.warn(vertex.line, f"{count(np.count_nonzero(~finite), 'point')} with NaN or infinite "
                                    "coordinates (kept; not drawn)")
        return PointCloud(vertices.positions, vertices.colors, vertices.normals, tuple(notes.warnings))
    fields = _mesh_fields(name, header, rows.get(face.name) if face else None, face, vertices, lines, notes,
                          textures)
    del rows  # the body's values (an ASCII file's numbers): not held while the Mesh copies its arrays
    return Mesh(vertices.positions, vertex_colors=vertices.colors, normals=vertices.normals,
                texcoords=vertices.texcoords, warnings=tuple(notes.warnings), **fields)


def _mesh_fields(name, header, face_rows, face, vertices, lines, notes: Notes, textures: bool) -> dict:
    """The Mesh's fields from the face element's rows (``faces``, ``edges``, ``lines``,
    ``face_colors``, ``uv``, ``uv_index`` and the materials), the polygons and their
    triangles' corners dropped once they are made."""
    n = len(vertices.positions)
    if n > MAX_VERTICES:
        raise PlyLimitError(name, None, f"{n} vertices: a mesh of more than {MAX_VERTICES} is not read")
    lines = np.zeros((0, 2), np.int64) if lines is None else lines
    if face is None or face.count == 0:
        return dict(faces=np.zeros((0, 3), np.int64), lines=lines)  # the Mesh's edges: the lines
    texcoord = corner_texcoords(face)
    polygons = read_polygons(face_rows, face, n, texcoord is not None)
    triangles = triangulate(polygons, vertices.positions, notes, face.line)
    uv, uv_index = (None, None) if texcoord is None else corner_uv(face_rows, texcoord, polygons, triangles, notes)
    if uv is None and vertices.texcoords is not None:
        uv = vertices.texcoords
    fields = dict(faces=triangles.faces, lines=lines, uv=uv, uv_index=uv_index,
                  face_colors=face_colors(face_rows, face, triangles, notes))
    files = texture_files(header) if textures else []
    if files and uv is None:
        notes.warn(files[0][0], "TextureFile given, but no texture coordinates: no texture drawn")
    elif files:
        fields.update(_materials(name, files, face_rows, face, triangles, notes))
    keep, corners, polygon = triangles.keep, triangles.corners, triangles.polygon
    del triangles
    fields["edges"], fields["polygon_sides"] = polygon_mesh_edges(polygons.corners, polygons.offsets, keep, corners,
                                                                  polygon, lines, n)
    return fields


def _materials(name, files, face_rows, face, triangles, notes: Notes) -> dict:
    """``material_names``, ``materials`` and ``face_materials`` of the ``TextureFile``
    comments ``files``, or nothing when none of their images can be read."""
    materials = read_textures(name, files, notes)
    if all(m is None for m in materials):
        return {}
    names = _unique([file for _, file in files])
    return dict(material_names=tuple(names),
                materials=tuple(m or Material(name=n) for m, n in zip(materials, names)),
                face_materials=texture_numbers(face_rows, face, triangles, len(files), notes))


def _unique(names: list) -> list:
    """The names, a repeated one with ``#2``, ``#3``... after it."""
    seen: dict = {}
    out = []
    for n in names:
        seen[n] = seen.get(n, 0) + 1
        out.append(n if seen[n] == 1 else f"{n}#{seen[n]}")
    return out


def _read_file(name: str) -> bytes:
    """:func:`rasterkit.runtime.files.read_file`, its errors as :class:`PlyError`."""
    try:
        return _files.read_file(name)
    except _files.FileLimitError as e:
        raise PlyLimitError(e.path, None, e.reason) from None
    except _files.FileError as e:
        raise PlyError(e.path, None, e.reason) from None
