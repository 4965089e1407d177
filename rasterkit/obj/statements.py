"""The geometry statements of an OBJ file read by the parsing kernels and checked: the numbers
of ``v``/``vt``/``vn`` (with vertex colours), the corners of ``f`` and ``l`` (as
:class:`Elements`), the messages for bad numbers and indices, and the skipped ``p`` and unknown
lines."""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

from rasterkit.mesh.checks import sealed_empty
from rasterkit.obj.document import Document, decode
from rasterkit.obj.errors import Report, count, readable
from rasterkit.obj.kernels.corners import INDEX_BEFORE_FIRST, INDEX_MALFORMED, INDEX_OK, INDEX_ZERO
from rasterkit.runtime.decimal import NUMBER_OTHER
from rasterkit.obj.kernels.scan import KIND_OTHER, KIND_P, KIND_V, KIND_VN, KIND_VT, split_tokens

__all__ = ["Elements", "latest_above", "per_triangle", "note_skipped", "read_elements", "read_numbers",
           "read_vertices"]

_REPARSE_CHUNK = 1 << 16  # statements re-parsed at once
_LONG_TOKEN = 64  # a chunk with a longer token is re-parsed token by token

#: NaN and infinity as MSVC prints them (``1.#IND``, ``-1.#INF``, ``1.#QNAN``, ``1.#SNAN``).
_MSVC = re.compile(rb"([+-]?)[0-9]+\.#(?:(ind|qnan|snan)|(inf))\Z", re.IGNORECASE)

_ATTRIBUTES = (("vertex", "v"), ("texture coordinate", "vt"), ("normal", "vn"))
_NUMBER_COUNTS = {KIND_V: ("v", (3, 4, 6), "3 (x y z), 4 (x y z w) or 6 (x y z r g b)"),
                  KIND_VT: ("vt", (1, 2, 3), "1 to 3 (u v w)"),
                  KIND_VN: ("vn", (3,), "3 (x y z)")}


def read_numbers(doc: Document, kind: int, width: int, report: Report) -> np.ndarray:
    """(S, width) float64 numbers of the statements of one kind (v, vt or vn)."""
    rows = doc.of_kind(kind)
    values, status, inexact = doc.geometry.numbers[kind]
    values = values[:, :width]
    keyword, counts, spec = _NUMBER_COUNTS[kind]
    bad = _read_others(doc, rows, values, np.flatnonzero(status == NUMBER_OTHER))
    if bad is not None:
        r, token = bad
        report.error(doc.line(rows[r]), f"malformed number {token!r} in a {keyword} line")
    for r in np.flatnonzero(~np.isin(doc.ntokens[rows], counts))[:1]:
        report.error(doc.line(rows[r]),
                     f"{keyword} needs {spec} numbers, got {doc.ntokens[rows[r]]}")
    _reparse_exactly(doc, rows, values, inexact)
    return values


def _read_others(doc: Document, rows: np.ndarray, values: np.ndarray, others: np.ndarray):
    """Read the statements ``rows[others]``, whose numbers the kernel left to this module
    (not all plain decimals: NaN or infinity among them), into ``values`` (NaN beyond their
    tokens), a bounded chunk of statements at a time; the first token that is no number, as
    ``(index into rows, token)``, or None."""
    width = values.shape[1]
    for first in range(0, len(others), _REPARSE_CHUNK):
        part = others[first:first + _REPARSE_CHUNK]
        starts, ends = doc.starts[rows[part]], doc.ends[rows[part]]
        n = doc.ntokens[rows[part]].astype(np.int64)
        tokens = _statement_tokens(doc.buf, starts, ends)
        numbers = np.delete(np.arange(len(tokens)), np.cumsum(n + 1) - (n + 1))  # not the keywords
        row = np.repeat(part, n)
        column = np.arange(len(numbers)) - np.repeat(np.cumsum(n) - n, n)
        read, ok = _numbers([tokens[k] for k in numbers.tolist()])
        if not ok.all():
            k = int(np.argmin(ok))
            return int(row[k]), decode(tokens[numbers[k]])
        values[part] = np.nan
        kept = column < width
        values[row[kept], column[kept]] = read[kept]
    return None


def _statement_tokens(buf: np.ndarray, starts: np.ndarray, ends: np.ndarray) -> list[bytes]:
    """The tokens of the statements ``buf[starts[i]:ends[i]]`` (in file order, apart), in
    order: the span they cover with every byte outside them made a space, split once."""
    lo, hi = int(starts[0]), int(ends[-1])
    marks = np.zeros(hi - lo + 1, np.int8)
    marks[starts - lo] += 1
    marks[ends - lo] -= 1
    inside = np.cumsum(marks[:-1], dtype=np.int8) > 0
    return split_tokens(np.where(inside, buf[lo:hi], np.uint8(32)).tobytes())


def _numbers(tokens: list[bytes]) -> tuple[np.ndarray, np.ndarray]:
    """The values of number tokens as the kernel's grammar and :data:`_MSVC` spell them, and
    which are numbers at all. Plain ones by NumPy (which reads as Python's float does:
    correctly rounded, as the kernel, and ``nan``, ``inf``, ``infinity`` in any case with a
    sign), MSVC's with NumPy's string functions; token by token when a token is long."""
    if not tokens or max(map(len, tokens)) > _LONG_TOKEN:  # NumPy would make every token as long as the longest
        read = [_number(t) for t in tokens]
        return np.array([np.nan if v is None else v for v in read], np.float64), np.array([v is not None for v in read])
    text = np.array(tokens)
    values, ok = np.full(len(tokens), np.nan), np.zeros(len(tokens), bool)
    msvc = np.char.find(text, b"#") >= 0
    plain = ~msvc & (np.char.find(text, b"_") < 0) & (text.view(np.uint8).reshape(len(tokens), -1) < 128).all(axis=1)
    try:  # float() takes 1_0 and other digits too: those are no numbers here
        with np.errstate(over="ignore", under="ignore"):
            values[plain] = text[plain].astype(np.float64)
        ok[plain] = True
    except ValueError:  # one is no number: find it (the file is refused)
        for k in np.flatnonzero(plain):
            value = _number(tokens[k])
            values[k], ok[k] = (np.nan, False) if value is None else (value, True)
    if msvc.any():
        head, dot, word = np.char.partition(np.char.lower(text[msvc]), b".#").T
        digits = np.char.lstrip(head, b"+-")
        signs = np.char.str_len(head) - np.char.str_len(digits)
        nan, inf = np.isin(word, [b"ind", b"qnan", b"snan"]), word == b"inf"
        ok[msvc] = (dot == b".#") & np.char.isdigit(digits) & (signs <= 1) & (nan | inf)
        values[msvc] = np.where(nan, np.nan, np.where(np.char.startswith(head, b"-"), -np.inf, np.inf))
    return values, ok


def _number(token: bytes) -> float | None:
    """:func:`_numbers` for one token: its value, or None."""
    if token.isascii() and b"_" not in token:
        try:
            return float(token)
        except ValueError:
            pass
    match = _MSVC.match(token)
    if match is None:
        return None
    return np.nan if match[2] else -np.inf if match[1] == b"-" else np.inf


def _reparse_exactly(doc: Document, rows: np.ndarray, values: np.ndarray, inexact: np.ndarray):
    """Replace the values that the kernel could not round exactly (more than 15 significant
    digits or large exponents) by the correctly rounded conversion of their text (NumPy's, or
    Python's float for long tokens), a bounded chunk of statements at a time."""
    redo = np.flatnonzero(inexact)
    for first in range(0, len(redo), _REPARSE_CHUNK):
        part = redo[first:first + _REPARSE_CHUNK]
        statements = rows[part]
        text = b"\n".join(doc.text[s:e] for s, e in zip(doc.starts[statements],
                                                        doc.ends[statements]))
        tokens = split_tokens(text)
        keyword_at = np.concatenate([[0], np.cumsum(doc.ntokens[statements] + 1)[:-1]])
        bits = (inexact[part, None] >> np.arange(values.shape[1])) & 1
        r, column = np.nonzero(bits)
        at = keyword_at[r] + 1 + column
        if max(map(len, tokens)) <= _LONG_TOKEN:
            with np.errstate(over="ignore", under="ignore"):  # 1e400 is inf, as float() says
                values[part[r], column] = np.array(tokens)[at].astype(np.float64)
        else:  # NumPy would make every token as long as the longest
            values[part[r], column] = [float(tokens[k]) for k in at]


def read_vertices(doc: Document, report: Report):
    """Positions (N, 3) float64, and colours (N, 3) float32 in [0, 1] or None."""
    values = read_numbers(doc, KIND_V, 6, report)
    rows = doc.of_kind(KIND_V)
    colored = doc.ntokens[rows] == 6
    colors = _vertex_colors(doc, rows, values[:, 3:6], colored, report) if colored.any() else None
    positions, fill = sealed_empty((len(values), 3), np.float64)  # a Mesh keeps it without a copy
    fill[:] = values[:, :3]
    return positions, colors


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
                    f"{count(np.count_nonzero(bad), 'vertex colour')} not finite: white")
    rgb[~colored | bad] = 1.0
    return np.clip(rgb, 0.0, 1.0).astype(np.float32)


@dataclass(frozen=True)
class Elements:
    """Faces or polylines: corner indices in runs, one run per statement."""

    statements: np.ndarray  # (K,) statement number of each element
    offsets: np.ndarray  # (K + 1,) run of element k: corners offsets[k] to offsets[k + 1]
    vertex: np.ndarray  # (C,) int64 0-based vertex of each corner
    texcoord: np.ndarray  # (C,) int64 its vt, -1 where absent; empty when no corner has one
    normal: np.ndarray  # (C,) int64 its vn, likewise
    reported: np.ndarray  # (K, 2) bool: a bad vt (column 0) or vn (1) reference was reported

    @property
    def count(self) -> int:
        return len(self.statements)

    @property
    def sizes(self) -> np.ndarray:
        return np.diff(self.offsets)

    def uses_only(self, vertex_ok: np.ndarray) -> np.ndarray:
        """(K,) bool: elements whose vertices all have vertex_ok."""
        if vertex_ok.all() or self.count == 0:
            return np.ones(self.count, bool)
        bad = (~vertex_ok[self.vertex]).astype(np.int64)
        return np.add.reduceat(bad, self.offsets[:-1]) == 0

    def segments(self, keep: np.ndarray) -> np.ndarray:
        """(K, 2) int64 segments p[0]-p[1], ..., p[-2]-p[-1] of the kept polylines."""
        v = self.vertex
        starts = np.ones(len(v), bool)
        starts[self.offsets[1:] - 1] = False
        starts &= np.repeat(keep, self.sizes)
        first = np.flatnonzero(starts)
        pairs = np.stack([v[first], v[first + 1]], axis=1)
        return pairs[pairs[:, 0] != pairs[:, 1]]


def read_elements(doc: Document, kind: int, minimum: int, what: str,
                  report: Report) -> Elements:
    """Parse and check the corners of all f (or l) statements."""
    rows = doc.of_kind(kind)
    sizes = doc.ntokens[rows]
    offsets = np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64)
    totals = np.array([doc.count(k) for k in (KIND_V, KIND_VT, KIND_VN)])
    *corners, problems = doc.geometry.corners[kind]
    # A bad reference first: on a line that has both, "malformed vertex reference '2\x1d3'"
    # says more than "face with 2 vertices".
    vertex_bad = (problems[:, 0] != INDEX_OK) & (problems[:, 2] == 0)
    for r in np.flatnonzero(vertex_bad)[:1]:
        report.error(doc.line(rows[r]), _index_message(doc, rows[r], problems[r], totals))
    for r in np.flatnonzero(sizes < minimum)[:1]:
        given = {0: "no vertices", 1: "1 vertex"}.get(int(sizes[r]), f"{sizes[r]} vertices")
        report.error(doc.line(rows[r]), f"{what} with {given}: a {what} needs at least "
                                        f"{minimum}")
    reported = np.zeros((len(rows), 2), bool)
    for attribute in (1, 2):
        bad = np.flatnonzero((problems[:, 0] != INDEX_OK) & (problems[:, 2] == attribute))
        reported[bad, attribute - 1] = True
        if len(bad):
            name = _ATTRIBUTES[attribute][0]
            message = _index_message(doc, rows[bad[0]], problems[bad[0]], totals)
            report.warn(doc.line(rows[bad[0]]), f"{message}; {name}s ignored in "
                                                 f"{count(len(bad), what)}")
    return Elements(rows, offsets, *corners, reported)


def _index_message(doc: Document, s: int, problem, totals) -> str:
    """Words for one INDEX_* problem (code, corner, attribute) of statement s."""
    code, corner, attribute = (int(x) for x in problem)
    token = doc.tokens(s)[1 + corner]
    if code == INDEX_MALFORMED:
        return f"malformed vertex reference {token!r}"
    name, keyword = _ATTRIBUTES[attribute]
    raw = token.split("/")[attribute]
    if code == INDEX_ZERO:
        return f"{name} index 0 in {token!r}: OBJ indices start at 1"
    if code == INDEX_BEFORE_FIRST:
        before = doc.counts_before(np.array([s]))[0]
        return (f"relative {name} index {raw} in {token!r} points before the first {keyword} "
                f"(only {before[attribute]} above this line)")
    return (f"{name} index {raw} in {token!r} is out of range: the file has "
            f"{count(totals[attribute], keyword + ' line')}")


def note_skipped(doc: Document, report: Report):
    """Warnings for point elements and unknown keywords."""
    points = doc.of_kind(KIND_P)
    if len(points):
        report.warn(None, f"{count(doc.ntokens[points].sum(), 'point')} in "
                          f"{count(len(points), 'p element')} not drawn")
    unknown = doc.of_kind(KIND_OTHER)
    if len(unknown):
        keywords = dict.fromkeys(doc.tokens(s)[0] for s in unknown)
        report.warn(None, f"{count(len(unknown), 'unknown keyword line')} skipped "
                          f"({', '.join(map(readable, keywords))})")


def latest_above(doc: Document, kinds, faces: Elements):
    """Names of the statements of the given kinds (g and o, or usemtl) and, for each face, the
    position in that list of the latest one above it (-1 when there is none)."""
    return list(doc.names(*kinds)), doc.latest(kinds, faces.statements)


def per_triangle(table: np.ndarray, latest: np.ndarray, triangle_polygon: np.ndarray) -> np.ndarray:
    """``table[latest[triangle_polygon]]`` (``latest`` from :func:`latest_above`, whose -1 picks
    the last row of ``table``), in sealed memory (:func:`rasterkit.mesh.checks.sealed_empty`),
    which the Mesh keeps without a copy."""
    sealed, fill = sealed_empty((len(triangle_polygon),) + table.shape[1:], table.dtype)
    np.take(table[latest], triangle_polygon, axis=0, out=fill, mode="clip")  # valid polygons: no buffer
    return sealed
