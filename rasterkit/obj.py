"""``load_obj(path) -> Mesh``: a fast Wavefront OBJ loader that takes what real files contain.

The file's bytes are split into statements, and the common ones (``v``, ``vt``, ``vn``, ``f``,
``l``) parsed and triangulated, by Numba kernels (:mod:`rasterkit.kernels.obj_parse`) with no
Python loop over lines; only the rare lines (``g``, ``o``, ``usemtl``, ``mtllib``, unknown
keywords), error messages and ``.mtl`` files go through Python.

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
  may point below the line (as most loaders allow). Polygons of any size: triangles and convex
  quads are split as a fan, everything else by ear clipping in the plane of the polygon's
  Newell normal, so concave polygons (and holes joined by a bridge walked both ways) are
  covered exactly; self-intersecting polygons still give m - 2 triangles. Triangles keep the
  file's winding. Triangles that a repeated vertex makes degenerate (``f 1 2 2 3``) are left
  out.
- ``l`` polylines: ``l 1 2 3`` gives the segments 1-2 and 2-3. ``p`` points are counted and
  reported in a warning, not drawn.
- ``o``, ``g`` (the names of a face's latest ``g`` or ``o`` become ``Mesh.group_names``, with
  ``face_groups`` per triangle; faces before any of them are in group ``default``), ``s``
  (ignored), ``usemtl`` (names in ``Mesh.material_names``), ``mtllib`` (``Kd`` of each used
  material becomes ``Mesh.face_colors``; a material without ``Kd``, and faces without a
  material, get :data:`DEFAULT_KD`; a missing ``.mtl`` file or material is a warning).
- Comments (``#`` at the start of a token), blank lines, LF, CRLF or CR line breaks, tabs, runs
  of spaces, no final newline, a backslash before the line break (continuation), a UTF-8 byte
  order mark. Numbers may be ``1``, ``-2.``, ``.5``, ``+1e-3``, ``1E+02``, ``nan``, ``inf``
  and MSVC's ``1.#IND``/``1.#INF``; every value is the correctly rounded float64 of its text.
- Unknown keywords (``vp``, ``curv``, ``t``, ``vw``...) are skipped and counted in one warning.

Per-vertex attributes
---------------------
``Mesh`` holds one normal and one texture coordinate per vertex, while OBJ gives them per face
corner. A vertex's normal is the sum of the unit ``vn`` of all face corners that use it,
normalised ((0, 0, 0) for a vertex no corner gives a normal: a smooth-shading normal, which
rounds hard edges); its texture coordinate is the ``vt`` of the first corner (in file order)
that gives one ((0, 0) otherwise; at a UV seam the other corners' coordinates are lost).

What fails
----------
:class:`ObjError` (a ``ValueError``), whose message is one line ``PATH:LINE: what is wrong``
(``PATH: what is wrong`` when no line is to blame): an unreadable file, binary content (NUL
bytes, UTF-16/32), a malformed number or index, a wrong count of numbers on ``v``/``vt``/``vn``,
vertex index 0, out of range or (relative) before the first vertex, a face with fewer than 3
or a line with fewer than 2 vertices, and a file with neither faces nor lines (a point cloud
of ``v`` lines only is an error too). When a file has several errors the first line is named.
Bad ``vt``/``vn`` references only drop that attribute, with a warning: the geometry is intact.

Warnings are one-line strings in ``Mesh.warnings``, never printed. Non-finite vertex
coordinates are kept in ``Mesh.vertices``, but the faces and lines using them are dropped.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import numpy as np

from .kernels import obj_parse as kern
from .mesh import Mesh

__all__ = ["DEFAULT_KD", "ObjError", "load_obj"]

DEFAULT_KD = (0.8, 0.8, 0.8)
"""Diffuse colour of faces whose material is unknown or has no ``Kd``."""

_UTF8_BOM = b"\xef\xbb\xbf"
_WIDE_BOMS = {b"\xff\xfe\x00\x00": "UTF-32", b"\x00\x00\xfe\xff": "UTF-32",
              b"\xff\xfe": "UTF-16", b"\xfe\xff": "UTF-16"}
_ATTRIBUTES = (("vertex", "v"), ("texture coordinate", "vt"), ("normal", "vn"))
_NUMBER_COUNTS = {kern.KIND_V: ("v", (3, 4, 6), "3 (x y z), 4 (x y z w) or 6 (x y z r g b)"),
                  kern.KIND_VT: ("vt", (1, 2, 3), "1 to 3 (u v w)"),
                  kern.KIND_VN: ("vn", (3,), "3 (x y z)")}


class ObjError(ValueError):
    """An OBJ file that cannot be loaded.

    Attributes
    ----------
    path : str
        The file, as given to :func:`load_obj`.
    line : int or None
        1-based line where the problem is, or None when it is not one line's fault.
    reason : str
        What is wrong, without the location.
    """

    def __init__(self, path: str, line: int | None, reason: str):
        self.path = path
        self.line = line
        self.reason = reason
        where = path if line is None else f"{path}:{line}"
        super().__init__(f"{where}: {reason}")


def load_obj(path) -> Mesh:
    """Load a Wavefront OBJ file as a triangle :class:`~rasterkit.mesh.Mesh`.

    Parameters
    ----------
    path : str or os.PathLike
        The ``.obj`` file. ``mtllib`` files are looked up next to it.

    Returns
    -------
    Mesh
        ``vertices`` (N, 3) float64 in object space, one per ``v`` line in file order;
        ``faces`` (M, 3) int64 triangles; ``edges`` (E, 2) int64, the unique sides of the
        original polygons and the ``l`` segments; ``lines`` (K, 2) int64; and, when the file has
        them, ``vertex_colors``, ``normals``, ``texcoords``, ``face_colors``, ``face_groups``
        with ``group_names``, and ``material_names``. ``warnings`` lists what was accepted with
        a remark. See the module documentation for every rule.

    Raises
    ------
    ObjError
        With a one-line ``PATH:LINE: message`` naming the first bad line of the file.

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
    doc = _Document.read(os.fsdecode(path))
    report = _Report(doc.name)
    vertices, colors = _read_vertices(doc, report)
    texcoords = _read_numbers(doc, kern.KIND_VT, 3, report)
    normals = _read_numbers(doc, kern.KIND_VN, 3, report)
    faces = _read_elements(doc, kern.KIND_F, 3, "face", report)
    lines = _read_elements(doc, kern.KIND_L, 2, "line", report)
    report.raise_first_error()
    if faces.count == 0 and lines.count == 0:
        raise ObjError(doc.name, None, "no faces or lines, nothing to draw (only "
                                       f"{_count(len(vertices), 'vertex', 'vertices')})")
    _note_skipped(doc, report)
    finite = _finite_vertices(doc, vertices, faces, lines, report)
    keep_polygons = faces.uses_only(finite)
    triangles, triangle_polygon = _triangulate(vertices, faces, keep_polygons)
    segments = lines.segments(lines.uses_only(finite))
    edges = _unique_edges(faces, keep_polygons, segments, len(vertices))
    groups, group_names = _face_labels(doc, (kern.KIND_G, kern.KIND_O), faces, triangle_polygon)
    return Mesh(
        vertices, triangles, edges=edges, lines=segments,
        vertex_colors=colors,
        normals=_vertex_normals(faces, normals, len(vertices)),
        texcoords=_vertex_texcoords(faces, texcoords, len(vertices)),
        face_colors=_face_colors(doc, faces, triangle_polygon, report),
        face_groups=groups, group_names=group_names,
        material_names=_material_names(doc),
        warnings=report.warnings,
    )


@dataclass(frozen=True)
class _Document:
    """The file's bytes and its statements (from the scanning kernel)."""

    name: str
    data: bytes  # the file's bytes after the byte order mark
    text: bytes  # data with continuations blanked out: same length, same offsets
    buf: np.ndarray  # text as uint8
    starts: np.ndarray
    ends: np.ndarray
    kinds: np.ndarray
    ntokens: np.ndarray

    @classmethod
    def read(cls, name: str) -> _Document:
        data = _text_bytes(_read_bytes(name), name)
        text = _blank_continuations(data)
        buf = np.frombuffer(text, np.uint8)
        return cls(name, data, text, buf, *kern.scan_statements(buf))

    def of_kind(self, *kinds) -> np.ndarray:
        """Statement numbers (S,) int64 of the given kinds, in file order."""
        if len(kinds) == 1:
            return np.flatnonzero(self.kinds == kinds[0])
        return np.flatnonzero(np.isin(self.kinds, kinds))

    def line(self, s: int) -> int:
        """1-based line number where statement s starts."""
        return self.data.count(b"\n", 0, self.starts[s]) + 1

    def tokens(self, s: int) -> list[str]:
        """The keyword and tokens of statement s."""
        return _decode(self.text[self.starts[s]:self.ends[s]]).split()

    def argument(self, s: int) -> str:
        """Everything after the keyword of statement s, with single spaces."""
        return " ".join(self.tokens(s)[1:])

    def counts_before(self, rows: np.ndarray) -> np.ndarray:
        """(len(rows), 3) int64: v, vt and vn statements above each of the statements rows."""
        kinds = (kern.KIND_V, kern.KIND_VT, kern.KIND_VN)
        return np.stack([np.searchsorted(self.of_kind(k), rows) for k in kinds], axis=1)

    def count(self, kind: int) -> int:
        return int(np.count_nonzero(self.kinds == kind))


class _Report:
    """Errors (line, message) and warnings met while loading one file."""

    def __init__(self, name: str):
        self.name = name
        self.errors: list[tuple[int, str]] = []
        self.warnings: list[str] = []

    def error(self, line: int, message: str):
        self.errors.append((int(line), message))

    def warn(self, line: int | None, message: str, name: str | None = None):
        """Note a warning about line of this file (or of the file name, e.g. an .mtl)."""
        name = name or self.name
        self.warnings.append(f"{name}: {message}" if line is None else
                             f"{name}:{int(line)}: {message}")

    def raise_first_error(self):
        if self.errors:
            line, message = min(self.errors, key=lambda e: e[0])
            raise ObjError(self.name, line, message)


def _count(n, noun: str, plural: str | None = None) -> str:
    """'1 face', '2 faces'."""
    return f"{int(n)} {noun if n == 1 else plural or noun + 's'}"


def _read_bytes(name: str) -> bytes:
    try:
        return Path(name).read_bytes()
    except OSError as e:
        raise ObjError(name, None, f"cannot read: {e.strerror or e}") from None


def _text_bytes(data: bytes, name: str) -> bytes:
    """The file's bytes without a UTF-8 byte order mark and with LF line breaks where it has
    only CR ones; binary or UTF-16/32 data fails."""
    for bom, encoding in _WIDE_BOMS.items():
        if data.startswith(bom):
            raise ObjError(name, 1, f"{encoding} text is not supported: save the file as UTF-8")
    if data.startswith(_UTF8_BOM):
        data = data[len(_UTF8_BOM):]
    if b"\n" not in data:  # old Mac files break lines with CR alone
        data = data.replace(b"\r", b"\n")
    nul = data.find(b"\0")
    if nul >= 0:
        line = data.count(b"\n", 0, nul) + 1
        raise ObjError(name, line, "NUL byte: binary data, not OBJ text (or UTF-16 without "
                                   "a byte order mark)")
    return data


def _blank_continuations(data: bytes) -> bytes:
    """data with every line continuation (a backslash before the line break) turned into
    spaces, so the two lines read as one and byte offsets stay those of the file."""
    if b"\\" not in data or (b"\\\n" not in data and b"\\\r\n" not in data):
        return data
    return data.replace(b"\\\r\n", b"   ").replace(b"\\\n", b"  ")


def _decode(raw: bytes) -> str:
    """UTF-8 text; Latin-1 for the older files whose names are not UTF-8."""
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError:
        return raw.decode("latin-1")


def _read_numbers(doc: _Document, kind: int, width: int, report: _Report) -> np.ndarray:
    """(S, width) float64 numbers of the statements of one kind (v, vt or vn)."""
    rows = doc.of_kind(kind)
    values, status, bad_token, inexact = kern.parse_number_rows(
        doc.buf, doc.starts[rows], doc.ends[rows], width)
    keyword, counts, spec = _NUMBER_COUNTS[kind]
    for r in np.flatnonzero(status == kern.NUMBER_MALFORMED)[:1]:
        token = doc.tokens(rows[r])[1 + bad_token[r]]
        report.error(doc.line(rows[r]), f"malformed number {token!r} in a {keyword} line")
    for r in np.flatnonzero(~np.isin(doc.ntokens[rows], counts))[:1]:
        report.error(doc.line(rows[r]),
                     f"{keyword} needs {spec} numbers, got {doc.ntokens[rows[r]]}")
    _reparse_exactly(doc, rows, values, inexact)
    return values


def _reparse_exactly(doc: _Document, rows: np.ndarray, values: np.ndarray, inexact: np.ndarray):
    """Replace the values that the kernel could not round exactly (more than 15 significant
    digits or large exponents) by NumPy's correctly rounded conversion of their text."""
    redo = np.flatnonzero(inexact)
    if len(redo) == 0:
        return
    statements = rows[redo]
    text = b"\n".join(doc.text[s:e] for s, e in zip(doc.starts[statements], doc.ends[statements]))
    tokens = np.array(text.split())
    keyword_at = np.concatenate([[0], np.cumsum(doc.ntokens[statements] + 1)[:-1]])
    bits = (inexact[redo, None] >> np.arange(values.shape[1])) & 1
    r, column = np.nonzero(bits)
    with np.errstate(over="ignore", under="ignore"):  # 1e400 is inf, as float() says
        values[redo[r], column] = tokens[keyword_at[r] + 1 + column].astype(np.float64)


def _read_vertices(doc: _Document, report: _Report):
    """Positions (N, 3) float64, and colours (N, 3) float32 in [0, 1] or None."""
    values = _read_numbers(doc, kern.KIND_V, 6, report)
    rows = doc.of_kind(kern.KIND_V)
    colored = doc.ntokens[rows] == 6
    colors = _vertex_colors(doc, rows, values[:, 3:6], colored, report) if colored.any() else None
    return np.ascontiguousarray(values[:, :3]), colors


def _vertex_colors(doc, rows, rgb, colored, report) -> np.ndarray:
    """(N, 3) float32 colours in [0, 1] from the r g b of six-number v lines (0..255 when any
    of them is above 1); white for vertices without a colour or with a non-finite one."""
    scale = 255.0 if (rgb[colored] > 1.0).any() else 1.0
    rgb = rgb / scale
    plain = np.flatnonzero(~colored)
    if len(plain):
        report.warn(doc.line(rows[plain[0]]), f"{len(plain)} of {len(rows)} vertices have no "
                                              "colour while others have one: white")
    bad = colored & ~np.isfinite(rgb).all(axis=1)
    if bad.any():
        report.warn(doc.line(rows[np.argmax(bad)]),
                    f"{_count(np.count_nonzero(bad), 'vertex colour')} not finite: white")
    rgb[~colored | bad] = 1.0
    return np.clip(rgb, 0.0, 1.0).astype(np.float32)


@dataclass(frozen=True)
class _Elements:
    """Faces or polylines: corner indices in runs, one run per statement."""

    statements: np.ndarray  # (K,) statement number of each element
    offsets: np.ndarray  # (K + 1,) run of element k: corners[offsets[k]:offsets[k + 1]]
    corners: np.ndarray  # (C, 3) 0-based v, vt, vn of each corner; -1 where absent

    @property
    def count(self) -> int:
        return len(self.statements)

    @property
    def sizes(self) -> np.ndarray:
        return np.diff(self.offsets)

    @cached_property
    def vertex_indices(self) -> np.ndarray:
        """(C,) int64 vertex of each corner, contiguous for the kernels."""
        return np.ascontiguousarray(self.corners[:, 0])

    def uses_only(self, vertex_ok: np.ndarray) -> np.ndarray:
        """(K,) bool: elements whose vertices all have vertex_ok."""
        if vertex_ok.all() or self.count == 0:
            return np.ones(self.count, bool)
        bad = (~vertex_ok[self.corners[:, 0]]).astype(np.int64)
        return np.add.reduceat(bad, self.offsets[:-1]) == 0

    def segments(self, keep: np.ndarray) -> np.ndarray:
        """(K, 2) int64 segments p[0]-p[1], ..., p[-2]-p[-1] of the kept polylines."""
        v = self.corners[:, 0]
        starts = np.ones(len(v), bool)
        starts[self.offsets[1:] - 1] = False
        starts &= np.repeat(keep, self.sizes)
        first = np.flatnonzero(starts)
        pairs = np.stack([v[first], v[first + 1]], axis=1)
        return pairs[pairs[:, 0] != pairs[:, 1]]


def _read_elements(doc: _Document, kind: int, minimum: int, what: str,
                   report: _Report) -> _Elements:
    """Parse and check the corners of all f (or l) statements."""
    rows = doc.of_kind(kind)
    sizes = doc.ntokens[rows]
    offsets = np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64)
    totals = np.array([doc.count(k) for k in (kern.KIND_V, kern.KIND_VT, kern.KIND_VN)])
    before = doc.counts_before(rows)
    corners, problems = kern.parse_corners(doc.buf, doc.starts[rows], doc.ends[rows], offsets,
                                           before, totals)
    for r in np.flatnonzero(sizes < minimum)[:1]:
        given = {0: "no vertices", 1: "1 vertex"}.get(int(sizes[r]), f"{sizes[r]} vertices")
        report.error(doc.line(rows[r]), f"{what} with {given}: a {what} needs at least "
                                        f"{minimum}")
    vertex_bad = (problems[:, 0] != kern.INDEX_OK) & (problems[:, 2] == 0)
    for r in np.flatnonzero(vertex_bad)[:1]:
        report.error(doc.line(rows[r]), _index_message(doc, rows[r], problems[r], before[r],
                                                        totals))
    for attribute in (1, 2):
        bad = np.flatnonzero((problems[:, 0] != kern.INDEX_OK) & (problems[:, 2] == attribute))
        if len(bad):
            name = _ATTRIBUTES[attribute][0]
            message = _index_message(doc, rows[bad[0]], problems[bad[0]], before[bad[0]], totals)
            report.warn(doc.line(rows[bad[0]]), f"{message}; {name}s ignored in "
                                                 f"{_count(len(bad), what)}")
    return _Elements(rows, offsets, corners)


def _index_message(doc: _Document, s: int, problem, before, totals) -> str:
    """Words for one INDEX_* problem (code, corner, attribute) of statement s."""
    code, corner, attribute = (int(x) for x in problem)
    token = doc.tokens(s)[1 + corner]
    if code == kern.INDEX_MALFORMED:
        return f"malformed vertex reference {token!r}"
    name, keyword = _ATTRIBUTES[attribute]
    raw = token.split("/")[attribute]
    if code == kern.INDEX_ZERO:
        return f"{name} index 0 in {token!r}: OBJ indices start at 1"
    if code == kern.INDEX_BEFORE_FIRST:
        return (f"relative {name} index {raw} in {token!r} points before the first {keyword} "
                f"(only {before[attribute]} above this line)")
    return (f"{name} index {raw} in {token!r} is out of range: the file has "
            f"{_count(totals[attribute], keyword + ' line')}")


def _note_skipped(doc: _Document, report: _Report):
    """Warnings for point elements and unknown keywords."""
    points = doc.of_kind(kern.KIND_P)
    if len(points):
        report.warn(None, f"{_count(doc.ntokens[points].sum(), 'point')} in "
                          f"{_count(len(points), 'p element')} not drawn")
    unknown = doc.of_kind(kern.KIND_OTHER)
    if len(unknown):
        keywords = dict.fromkeys(doc.tokens(s)[0] for s in unknown)
        report.warn(None, f"{_count(len(unknown), 'unknown keyword line')} skipped "
                          f"({', '.join(keywords)})")


def _finite_vertices(doc, vertices, faces, lines, report) -> np.ndarray:
    """(N,) bool: vertices with finite coordinates; warns about the others."""
    finite = np.isfinite(vertices).all(axis=1)
    if not finite.all():
        first = doc.line(doc.of_kind(kern.KIND_V)[np.argmin(finite)])
        dropped_faces = faces.count - np.count_nonzero(faces.uses_only(finite))
        dropped_lines = lines.count - np.count_nonzero(lines.uses_only(finite))
        report.warn(first, f"{_count(np.count_nonzero(~finite), 'vertex', 'vertices')} with "
                           f"NaN or infinite coordinates; {_count(dropped_faces, 'face')} and "
                           f"{_count(dropped_lines, 'line')} using them dropped")
    return finite


def _triangulate(vertices, faces: _Elements, keep: np.ndarray):
    """Triangles (M, 3) int64 of the kept polygons, and the polygon (M,) of each."""
    if faces.count == 0:
        return np.zeros((0, 3), np.int64), np.zeros(0, np.int64)
    triangles = kern.triangulate(vertices, faces.vertex_indices, faces.offsets, keep)
    polygon = np.repeat(np.arange(faces.count), faces.sizes - 2)
    valid = triangles[:, 0] >= 0
    return np.ascontiguousarray(triangles[valid]), polygon[valid]


def _unique_edges(faces: _Elements, keep: np.ndarray, segments: np.ndarray,
                  n_vertices: int) -> np.ndarray:
    """(E, 2) int64 sorted unique undirected edges (lo < hi): the sides of the kept polygons
    and the segments (K, 2)."""
    sides = kern.side_keys(faces.vertex_indices, faces.offsets, keep, n_vertices)
    ends = np.sort(segments, axis=1)
    keys = np.sort(np.concatenate([sides, ends[:, 0] * n_vertices + ends[:, 1]]))
    keys = keys[np.diff(keys, prepend=-1) != 0]
    return np.stack([keys // n_vertices, keys % n_vertices], axis=1)


def _vertex_normals(faces: _Elements, normals: np.ndarray, n_vertices: int):
    """(N, 3) float64 unit normals averaged over each vertex's corners, or None."""
    used = np.ascontiguousarray(faces.corners[:, 2])
    if not (used >= 0).any():
        return None
    total = kern.sum_per_vertex(faces.vertex_indices, used, _unit_rows(normals), n_vertices)
    return _unit_rows(total)


def _unit_rows(a: np.ndarray) -> np.ndarray:
    """Rows of a scaled to length 1; rows of length 0 or not finite become 0."""
    a = np.nan_to_num(a, nan=0.0, posinf=0.0, neginf=0.0)
    length = np.linalg.norm(a, axis=1, keepdims=True)
    return np.divide(a, length, out=np.zeros_like(a), where=length > 0)


def _vertex_texcoords(faces: _Elements, texcoords: np.ndarray, n_vertices: int):
    """(N, 2) float64 texture coordinates of each vertex's first corner with one, or None."""
    used = np.ascontiguousarray(faces.corners[:, 1])
    if not (used >= 0).any():
        return None
    first = kern.first_per_vertex(faces.vertex_indices, used, n_vertices)
    uv = np.nan_to_num(texcoords[:, :2], nan=0.0, posinf=0.0, neginf=0.0)
    return np.where(first[:, None] >= 0, uv[first], 0.0)


def _latest(doc: _Document, kinds, faces: _Elements):
    """Names of the statements of the given kinds (g and o, or usemtl) and, for each face, the
    position in that list of the latest one above it (-1 when there is none)."""
    rows = doc.of_kind(*kinds)
    names = [doc.argument(s) for s in rows]
    return names, np.searchsorted(rows, faces.statements) - 1


def _face_labels(doc, kinds, faces, triangle_polygon):
    """face_groups (M,) int32 and group_names, or (None, ()) when the file names no groups."""
    names, latest = _latest(doc, kinds, faces)
    if not names:
        return None, ()
    names = [n or "default" for n in names]
    unique = list(dict.fromkeys((["default"] if (latest < 0).any() else []) + names))
    position = {n: i for i, n in enumerate(unique)}
    # The extra last entry is what latest == -1 (no statement above) picks.
    ids = np.array([position[n] for n in names] + [position.get("default", 0)])
    return ids[latest[triangle_polygon]].astype(np.int32), tuple(unique)


def _material_names(doc: _Document) -> tuple:
    names = (doc.argument(s) for s in doc.of_kind(kern.KIND_USEMTL))
    return tuple(dict.fromkeys(n for n in names if n))


def _face_colors(doc: _Document, faces: _Elements, triangle_polygon, report: _Report):
    """(M, 3) float32 Kd colour of each triangle's material, or None without materials."""
    libraries = _load_libraries(doc, report)
    names, latest = _latest(doc, (kern.KIND_USEMTL,), faces)
    if not libraries or not names:
        return None
    missing: dict = {}  # name: its first usemtl statement
    for s, name in zip(doc.of_kind(kern.KIND_USEMTL), names):
        if name and name not in libraries:
            missing.setdefault(name, s)
    if missing:
        shown = ", ".join(map(repr, list(missing)[:5])) + (", ..." if len(missing) > 5 else "")
        report.warn(doc.line(next(iter(missing.values()))),
                    f"{_count(len(missing), 'material')} not in the material libraries: {shown}")
    # The extra last row is what latest == -1 (no usemtl above) picks.
    table = np.array([libraries.get(n, DEFAULT_KD) for n in names] + [DEFAULT_KD], np.float32)
    return table[latest[triangle_polygon]]


def _load_libraries(doc: _Document, report: _Report) -> dict:
    """Kd (r, g, b) of every material in the file's mtllib files that can be read."""
    materials: dict = {}
    folder = Path(doc.name).parent
    for s in doc.of_kind(kern.KIND_MTLLIB):
        argument = doc.argument(s)
        files = [argument] if (folder / argument).is_file() else argument.split()
        for file in files:
            try:
                text = _decode((folder / file).read_bytes())
            except OSError as e:
                report.warn(doc.line(s), f"material library {file!r} cannot be read: "
                                          f"{e.strerror or e}")
                continue
            materials.update(_parse_mtl(text, str(folder / file), report))
    return materials


def _parse_mtl(text: str, name: str, report: _Report) -> dict:
    """Kd of each newmtl in an .mtl file's text (DEFAULT_KD when it has none)."""
    materials: dict = {}
    current = None
    for number, line in enumerate(text.splitlines(), 1):
        words = line.split("#", 1)[0].split()
        if len(words) >= 2 and words[0] == "newmtl":
            current = " ".join(words[1:])
            materials[current] = DEFAULT_KD
        elif words and words[0] == "Kd" and current is not None:
            try:
                rgb = [float(w) for w in words[1:4]]
            except ValueError:
                rgb = []
            if len(rgb) not in (1, 3) or not np.isfinite(rgb).all():
                report.warn(number, f"cannot read Kd {line.strip()!r}", name)
                continue
            materials[current] = tuple(np.clip(rgb * (3 // len(rgb)), 0.0, 1.0).tolist())
    return materials
