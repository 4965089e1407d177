"""``load_obj(path) -> Mesh``: a fast Wavefront OBJ loader that takes what real files contain.

The file's bytes are split into chunks of whole lines, read in parallel on the threads of
:mod:`rasterkit.runtime.threads` (``rasterkit.obj.chunks``: each chunk in one pass by the
kernel ``rasterkit.obj.kernels.chunk``, statements, numbers and corner tokens) and put together
in file order (relative indices resolved against the whole file's counts by
``rasterkit.obj.kernels.corners``), so the same file gives the same Mesh whatever the number
of chunks and threads. Polygons are triangulated by kernels (triangles and convex quads:
``rasterkit.obj.kernels.fans``) and NumPy (the others: ``rasterkit.obj.split``; the rare ones
that need it, by ``rasterkit.obj.kernels.polygons``) with no Python loop over lines; only the rare
lines (``g``, ``o``, ``usemtl``, ``mtllib``, unknown keywords), error messages and ``.mtl`` files
go through Python.

This module holds the public names (:func:`load_obj`, :class:`ObjError`, :class:`ObjLimitError`,
:data:`DEFAULT_KD`); the loader's parts, in the order it uses them: ``errors`` (the errors
and the report of errors and warnings), ``files`` (reading a file, within the limits),
``memory`` (the memory loading will take, checked first), ``document`` (the file's
bytes and statements, read by ``chunks``), ``statements`` (the numbers and corners of the geometry
statements, checked), ``assemble`` (triangles as the corners of their polygons, by
``split`` and ``ears`` or the kernels, edges, groups and materials of the triangles),
``attributes`` (the texture coordinates and normals of the corners, and per vertex) and
``materials`` (``usemtl`` and the ``.mtl`` files), all modules of this package, its kernels
in ``kernels/``.

What is accepted, and how it is read
------------------------------------
- ``v x y z``; ``v x y z w`` (``w`` is the weight of rational curves and surfaces, meaningless
  for polygons: it is checked to be a number and ignored, nothing is divided by it);
  ``v x y z r g b`` (vertex colours, 0..1; when any colour value in the file is above 1 all
  colours are taken as 0..255 and divided by 255). Vertices without a colour in a file where
  others have one are white (with a warning); a non-finite colour becomes white (warning).
- ``vt u [v [w]]`` (``w`` ignored, a missing ``v`` is 0), ``vn x y z``.
- ``f`` with corners ``v``, ``v/vt``, ``v//vn``, ``v/vt/vn`` (``1//`` too), mixed freely;
  negative indices count back from the last element defined above the line; positive indices
  may point below the line (as most loaders allow). Polygons of any size, split in the plane
  of their Newell normal (``rasterkit.obj.kernels.polygons`` has the details): triangles,
  convex quads and convex polygons as a fan, concave polygons (and holes joined by a bridge
  walked both ways) so that they are covered exactly, by ear clipping up to 80 corners and a
  monotone sweep (O(m log m)) beyond; a polygon that walks one cycle several times
  (``f 1 2 3 1 2 3``) is that cycle once. A self-intersecting polygon, or one that needs too
  much work, is split (or finished) as a fan, with a warning. Triangles keep the file's
  winding. Triangles that a repeated vertex makes degenerate (``f 1 2 2 3``) are left out.
- ``l`` polylines: ``l 1 2 3`` gives the segments 1-2 and 2-3. ``p`` points are counted and
  reported in a warning, not drawn.
- ``o``, ``g`` (the names of a face's latest ``g`` or ``o`` become ``Mesh.group_names``, with
  ``face_groups`` per triangle; faces before any of them are in group ``default``), ``s``
  (ignored), ``usemtl`` (names in ``Mesh.material_names``, in the order of their first
  ``usemtl``, and ``Mesh.face_materials`` per triangle: -1 before any ``usemtl`` and after
  one without a name), ``mtllib`` (``Kd`` of each used
  material becomes ``Mesh.face_colors``; a material without ``Kd``, and faces without a
  material, get :data:`DEFAULT_KD`; a library that cannot be read (missing, not a regular
  file, over the size limit) or a missing material is a warning).
- Comments (``#`` at the start of a token), blank lines, LF, CRLF or CR line breaks, no final
  newline, a backslash before the line break (continuation), a UTF-8 byte order mark. Tokens
  are separated by spaces and tabs (the OBJ convention), and CR, VT and FF, which count as
  spaces; no other byte separates tokens: control bytes 0x1c-0x1f and Unicode spaces (U+00A0,
  U+2003, U+3000...) are part of the token they touch, which is then malformed where a number
  or vertex reference is expected (``rasterkit.obj.kernels.scan``). Numbers may be ``1``,
  ``-2.``, ``.5``, ``+1e-3``, ``1E+02``, ``nan``, ``inf`` and MSVC's ``1.#IND``/``1.#INF``;
  every value is the correctly rounded float64 of its text.
- Unknown keywords (``vp``, ``curv``, ``t``, ``vw``...) are skipped and counted in one warning.

Texture coordinates and normals
-------------------------------
OBJ gives them per face corner, and ``Mesh`` keeps them so (``rasterkit.obj.attributes``):
``Mesh.uv`` (U, 2) holds every ``vt`` line (u, v as written, NaN and infinities too; v = 0
when the line has only u; w dropped) and ``Mesh.corner_normals`` (C, 3) every ``vn`` line
scaled to unit length ((0, 0, 0) for a zero normal or one with a NaN or infinite component);
``Mesh.uv_index`` and ``Mesh.normal_index`` (M, 3) give each triangle corner the row its
polygon's corner names (relative indices resolved), so a UV seam keeps both of its
coordinates and a hard edge (``vn`` differing across it) both of its normals. A polygon split
into triangles gives each triangle corner the attributes of the polygon corner it was cut
from (the splitters return polygon corners, not vertex indices: a vertex a polygon visits
twice, at a hole's bridge, keeps each visit's own; of repeated corners that are merged the
first is kept). A polygon that does not give a valid ``vt`` (``vn``) at every corner has
none: its triangles' rows are -1, -1, -1 (a bad index is warned about with the other bad
references; a polygon that gives them at some corners only, in one warning). A file whose
faces name no ``vt`` (``vn``) has ``uv`` and ``uv_index`` (``corner_normals`` and
``normal_index``) None.

``Mesh`` also holds one normal and one texture coordinate per vertex: a vertex's normal is the
sum of the unit ``vn`` of all face corners that use it, normalised ((0, 0, 0) for a vertex no
corner gives a normal: a smooth-shading normal, which rounds hard edges); its texture
coordinate is the ``vt`` of the first corner (in file order) that gives one ((0, 0)
otherwise).

What fails
----------
:class:`ObjError` (a ``ValueError``), whose message is one line ``PATH:LINE: what is wrong``
(``PATH: what is wrong`` when no line is to blame): a file that cannot be opened, that is not a
regular file (a directory, FIFO, socket or device: ``x.obj: not a regular file (a FIFO)``) or
that is larger than :func:`rasterkit.limits.max_file_size` (default 2 GiB) or whose loading
would need more memory than :func:`rasterkit.limits.memory_limit` (estimated before the large
arrays are made, ``rasterkit.obj.memory``; these two are an :class:`ObjLimitError`, which is a
:class:`~rasterkit.limits.LimitError` too), binary content (NUL bytes, UTF-16/32), a malformed
number or index, a wrong count of numbers on ``v``/``vt``/``vn``, vertex index 0, out of range
or (relative) before the first vertex, a face with fewer than 3 or a line with fewer than 2
vertices, and a file with neither faces nor lines (a point cloud of ``v`` lines only is an
error too). When a file has several errors the first line is named. Bad ``vt``/``vn``
references only drop that attribute, with a warning: the geometry is intact. Text from the
file (tokens, names) is shown with ``repr`` and a file name that is not printable as its
``repr``, so no message or warning is ever more than one line (``rasterkit.obj.errors``).
Every file is read by ``rasterkit.obj.files.read_file``, which says how.

Warnings are one-line strings in ``Mesh.warnings``, never printed. Non-finite vertex
coordinates are kept in ``Mesh.vertices``, but the faces and lines using them are dropped.
Loading issues no NumPy warning, whatever the numbers (``1e308``, ``nan``, ``inf``).
"""

from __future__ import annotations

import os

import numpy as np

from rasterkit.obj.assemble import face_labels, face_materials, finite_vertices, triangulate
from rasterkit.obj.attributes import (
    corner_rows, normal_table, unit_rows, uv_table, vertex_normals, vertex_texcoords,
)
from rasterkit.obj.document import Document
from rasterkit.obj.errors import ObjError, ObjLimitError, Report, count
from rasterkit.material.material import Material
from rasterkit.obj.materials import DEFAULT_KD, face_colors, make_materials, material_names, read_libraries
from rasterkit.obj.statements import note_skipped, read_elements, read_numbers, read_vertices
from rasterkit.obj.kernels.scan import KIND_F, KIND_G, KIND_L, KIND_O, KIND_VN, KIND_VT
from rasterkit.mesh import Mesh, polygon_mesh_edges
from rasterkit.mesh.checks import sealed_empty

__all__ = ["DEFAULT_KD", "ObjError", "ObjLimitError", "load_obj"]


def load_obj(path, *, textures: bool = True) -> Mesh:
    """Load a Wavefront OBJ file as a triangle :class:`~rasterkit.mesh.Mesh`.

    Parameters
    ----------
    path : str or os.PathLike
        The ``.obj`` file. ``mtllib`` files are looked up next to it.
    textures : bool
        Read each used material whole (``Mesh.materials``: :class:`rasterkit.Material` with
        its textures, each file opened once; one that cannot be read is a warning), so that
        renders draw the textures. False reads only each material's ``Kd`` (the faces' colours)
        and opens no texture file.

    Returns
    -------
    Mesh
        ``vertices`` (N, 3) float64 in object space, one per ``v`` line in file order;
        ``faces`` (M, 3) int64 triangles; ``edges`` (E, 2) int64, the unique sides of the
        original polygons and the ``l`` segments; ``lines`` (K, 2) int64; and, when the file has
        them, ``vertex_colors``, ``normals``, ``texcoords``, ``face_colors``, ``face_groups``
        with ``group_names``, ``material_names`` with ``face_materials``, and per corner
        ``uv`` with ``uv_index`` and ``corner_normals`` with ``normal_index``. ``warnings``
        lists what was accepted with a remark. See the module documentation for every rule.

    Raises
    ------
    ObjError
        With a one-line ``PATH:LINE: message`` naming the first bad line of the file, or
        ``PATH: message`` when the file cannot be read; an :class:`ObjLimitError` when it is
        over the file size limit or its loading over the memory limit.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "quad.obj"
    >>> _ = path.write_text("v 0 0 0\\nv 1 0 0\\nv 1 1 0\\nv 0 1 0\\nf 1 2 3 4\\n")
    >>> mesh = load_obj(path)
    >>> mesh.faces
    array([[0, 1, 2],
           [0, 2, 3]])
    >>> mesh.edges.tolist()
    [[0, 1], [0, 3], [1, 2], [2, 3]]
    """
    doc = Document.read(os.fsdecode(path))
    report = Report(doc.name)
    vertices, colors = read_vertices(doc, report)
    texcoords = read_numbers(doc, KIND_VT, 3, report)
    normals = read_numbers(doc, KIND_VN, 3, report)
    faces = read_elements(doc, KIND_F, 3, "face", report)
    lines = read_elements(doc, KIND_L, 2, "line", report)
    report.raise_first_error()
    if faces.count == 0 and lines.count == 0:
        raise ObjError(doc.name, None, "no faces or lines, nothing to draw (only "
                                       f"{count(len(vertices), 'vertex', 'vertices')})")
    note_skipped(doc, report)
    finite = finite_vertices(doc, vertices, faces, lines, report)
    keep_polygons = faces.uses_only(finite)
    corners, triangle_polygon = triangulate(doc, vertices, faces, keep_polygons, report)
    segments = lines.segments(lines.uses_only(finite))
    # None for a file of triangles alone, or of polygons split whole (then with the sides of the
    # polygons flagged): the Mesh works its edges out when they are first needed
    edges, sides = polygon_mesh_edges(faces.vertex, faces.offsets, keep_polygons, corners, triangle_polygon, segments,
                                      len(vertices))
    groups, group_names = face_labels(doc, (KIND_G, KIND_O), faces, triangle_polygon)
    materials = material_names(doc)
    uv_index = corner_rows(faces, "texcoord", corners, triangle_polygon, doc, report)
    normal_index = corner_rows(faces, "normal", corners, triangle_polygon, doc, report)
    unit_normals = unit_rows(normals)
    libraries = read_libraries(doc, report, whole=textures)
    colours = face_colors(doc, faces, triangle_polygon, libraries, report)
    defined = make_materials(libraries, report) if textures else {}
    return Mesh(
        vertices, _face_vertices(faces, corners), edges=edges, lines=segments,
        vertex_colors=colors,
        normals=vertex_normals(faces, unit_normals, len(vertices)),
        texcoords=vertex_texcoords(faces, texcoords, len(vertices)),
        face_colors=colours,
        face_groups=groups, group_names=group_names,
        material_names=materials,
        warnings=report.warnings,
        uv=None if uv_index is None else uv_table(doc, texcoords), uv_index=uv_index,
        corner_normals=None if normal_index is None else normal_table(normals, unit_normals), normal_index=normal_index,
        face_materials=face_materials(doc, faces, triangle_polygon, materials),
        materials=tuple(defined.get(name) or Material(name=name) for name in materials) if textures else (),
        polygon_sides=sides,
    )


def _face_vertices(faces, corners: np.ndarray) -> np.ndarray:
    """The triangles' vertices: each of their ``corners`` (M, 3) a corner of the polygons
    ``faces``; in sealed memory (:func:`rasterkit.mesh.checks.sealed_empty`), which the Mesh
    keeps without a copy."""
    sealed, fill = sealed_empty(corners.shape, np.int64)
    np.take(faces.vertex, corners, out=fill, mode="clip")  # "raise" would buffer: the corners are valid
    return sealed
