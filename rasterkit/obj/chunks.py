"""An OBJ file's text read in chunks, in parallel: split at line breaks into about two chunks a
thread, each chunk read in one pass by :func:`rasterkit.obj.kernels.chunk.read_lines` on the
threads of :mod:`rasterkit.runtime.threads` (the kernels release the GIL), then put together
in file order: the statement tables and numbers one after another, the corners of ``f`` and
``l`` resolved against the counts of the whole file (a relative index depends on the ``v``
lines above its line in all earlier chunks) by
:func:`rasterkit.obj.kernels.corners.resolve_corners`.

Chunks are whole lines and every statement is one line, so the result is the same for any
number of chunks and threads: the chunks only decide which thread reads which lines.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rasterkit.obj.kernels import chunk as _chunk
from rasterkit.obj.kernels.chunk import read_lines
from rasterkit.obj.kernels.corners import resolve_corners
from rasterkit.obj.kernels.scan import KIND_F, KIND_L, KIND_V, KIND_VN, KIND_VT
from rasterkit.runtime.threads import in_parallel

__all__ = ["CHUNK_BYTES", "Chunk", "Geometry", "Statements", "chunk_bounds", "read_chunk", "read_statements"]

#: The smallest chunk worth a thread of its own: a smaller text is one chunk.
CHUNK_BYTES = 1 << 20
#: Chunks per thread: more than one, so a thread that gets less of the machine reads fewer.
CHUNKS_PER_THREAD = 2

#: Numbers kept per row of v (x y z and r g b), vt and vn statements.
WIDTHS = {KIND_V: 6, KIND_VT: 3, KIND_VN: 3}


@dataclass(frozen=True)
class Geometry:
    """The parsed numbers and corners of a file's geometry statements."""

    numbers: dict  # KIND_V/VT/VN: (values (R, width) float64, status (R,) int8, inexact (R,) int64)
    corners: dict  # KIND_F/L: (vertex, texcoord, normal (C,) int64, errors (E, 3) int64)


@dataclass(frozen=True)
class Statements:
    """The statement table of a file (starts, ends, kinds, ntokens: see
    :func:`~rasterkit.obj.kernels.chunk.read_lines`), and its geometry, or None when keeping
    it would have taken more than the budget."""

    starts: np.ndarray
    ends: np.ndarray
    kinds: np.ndarray
    ntokens: np.ndarray
    geometry: Geometry | None


def chunk_bounds(text: bytes, threads: int) -> list[int]:
    """Where the chunks of text start, and its length: each bound but the first is just
    after a line break, chunks of at least :data:`CHUNK_BYTES` (one when text is shorter)."""
    pieces = max(1, min(CHUNKS_PER_THREAD * threads, len(text) // CHUNK_BYTES))
    bounds = [0]
    for k in range(1, pieces):
        at = text.find(b"\n", max(bounds[-1], len(text) * k // pieces))
        if at < 0:
            break
        if at + 1 < len(text):
            bounds.append(at + 1)
    bounds.append(len(text))
    return bounds


#: Statements (and rows, corners, f and l statements) a chunk makes room for at first; then
#: as many as the part read so far says the chunk needs, and a tenth more.
FIRST_CAPACITY = 1024
#: The arrays read_lines fills, in the order it takes them after ``n``: the dtype and the
#: items per row of each, and which FULL_* grows it.
_GROWING = ((np.int64, 1, _chunk.FULL_TABLE), (np.int64, 1, _chunk.FULL_TABLE), (np.int8, 1, _chunk.FULL_TABLE),
            (np.int64, 1, _chunk.FULL_TABLE),
            (np.float64, 6, _chunk.FULL_V), (np.int64, 1, _chunk.FULL_V),
            (np.float64, 3, _chunk.FULL_VT), (np.int64, 1, _chunk.FULL_VT),
            (np.float64, 3, _chunk.FULL_VN), (np.int64, 1, _chunk.FULL_VN),
            (np.int64, 3, _chunk.FULL_CORNERS), (np.int64, 1, _chunk.FULL_ELEMENTS))
_TABLE = 4  # the first four are the statement table, the others the geometry
#: The count (an index into read_lines' ``n``) of the rows of each FULL_*.
_COUNTS = {_chunk.FULL_TABLE: _chunk.S, _chunk.FULL_V: _chunk.NV, _chunk.FULL_VT: _chunk.NT,
           _chunk.FULL_VN: _chunk.NN, _chunk.FULL_CORNERS: _chunk.NC, _chunk.FULL_ELEMENTS: _chunk.NE}


@dataclass
class Chunk:
    """What :func:`read_chunk` read of one chunk."""

    table: list  # starts, ends, kinds, ntokens (S,)
    numbers: list  # per v, vt, vn: values (rows * width,) float64, flags (rows,) int64
    corners: np.ndarray  # (3 * C,) int64 raw v, vt, vn of each f and l corner token
    malformed: np.ndarray  # (E,) int64 first malformed token of each f and l statement, or -1
    counts: np.ndarray  # read_lines' n
    over: bool  # the geometry was over the budget: not kept (the table is complete)


def read_chunk(buf: np.ndarray, lo: int, hi: int, budget: int) -> Chunk:
    """Read the statements of buf[lo:hi] (whole lines) with
    :func:`~rasterkit.obj.kernels.chunk.read_lines`, its arrays grown each time one is full
    (the numbers and corners while they take at most ``budget`` bytes)."""
    growing = [np.empty(FIRST_CAPACITY * width, dtype) for dtype, width, _ in _GROWING]
    spent = sum(a.nbytes for a in growing[_TABLE:])
    keep = spent <= budget
    n = np.zeros(8, np.int64)
    i = lo
    while True:
        i, full = read_lines(buf, i, hi, keep, n, *growing)
        if full == _chunk.DONE:
            break
        grow = [k for k, (_, _, which) in enumerate(_GROWING) if which == full]
        used = int(n[_COUNTS[full]])
        have = len(growing[grow[0]]) // _GROWING[grow[0]][1]
        # as many as the chunk needs at this rate, and at least twice as many as it has (a
        # statement with more corners than there is room for starts again with more)
        capacity = max(2 * have, int(used * (hi - lo) / max(i - lo, 1) * 1.1) + FIRST_CAPACITY)
        if full != _chunk.FULL_TABLE:
            spent += sum((capacity - have) * growing[k].itemsize * _GROWING[k][1] for k in grow)
            if spent > budget:
                keep = False
                growing[_TABLE:] = [a[:0] for a in growing[_TABLE:]]
                continue
        for k in grow:
            a, width = growing[k], _GROWING[k][1]
            b = np.empty(capacity * width, a.dtype)
            b[:used * width] = a[:used * width]
            growing[k] = b
    if not keep:
        n[1:] = 0
    parts = [a[:int(n[_COUNTS[which]]) * width] for a, (_, width, which) in zip(growing, _GROWING)]
    return Chunk(parts[:_TABLE], [parts[4:6], parts[6:8], parts[8:10]], parts[10], parts[11], n, not keep)


def read_statements(buf: np.ndarray, bounds: list[int], budget: int, attributes: bool) -> Statements:
    """Read the chunks of buf (``bounds`` from :func:`chunk_bounds`), keeping at most
    ``budget`` bytes of numbers and corners, and put them together; ``attributes``: whether
    any corner may name a vt or vn (buf has a ``/``)."""
    n = len(bounds) - 1
    share = budget // n
    chunks = in_parallel(lambda k: read_chunk(buf, bounds[k], bounds[k + 1], share), n)
    over = any(c.over for c in chunks)
    return _put_together(chunks, attributes, table_only=over)


def _put_together(chunks: list, attributes: bool, table_only: bool) -> Statements:
    """The statement table and (unless ``table_only``) the numbers and corners of the chunks,
    in file order; the texture and normal indices of the corners only with ``attributes``
    (else empty)."""
    counts = np.array([c.counts for c in chunks], np.int64)  # (chunks, 8)
    at = np.cumsum(counts, axis=0) - counts  # where each chunk's go
    total = counts.sum(axis=0)
    single = len(chunks) == 1
    table = chunks[0].table if single else [np.empty(total[_chunk.S], a.dtype) for a in chunks[0].table]
    kinds = [(KIND_V, _chunk.NV), (KIND_VT, _chunk.NT), (KIND_VN, _chunk.NN)]
    numbers, corners = {}, {}
    if not table_only:
        for kind, count in kinds:
            rows = total[count]
            numbers[kind] = (chunks[0].numbers[count - 1][0].reshape(rows, WIDTHS[kind]) if single
                             else np.empty((rows, WIDTHS[kind])), np.empty(rows, np.int8), np.empty(rows, np.int64))
        # f corners and elements are those not of l statements
        sizes = {KIND_F: (total[_chunk.NC] - total[_chunk.NLC], total[_chunk.NE] - total[_chunk.NLE]),
                 KIND_L: (total[_chunk.NLC], total[_chunk.NLE])}
        for kind, (c, e) in sizes.items():
            corners[kind] = (np.empty(c, np.int64), np.empty(c if attributes else 0, np.int64),
                             np.empty(c if attributes else 0, np.int64), np.empty((e, 3), np.int64))
    before = at[:, [_chunk.NV, _chunk.NT, _chunk.NN]]
    totals = total[[_chunk.NV, _chunk.NT, _chunk.NN]]

    def place(k):
        chunk, where = chunks[k], at[k]
        if not single:
            for a, b in zip(table, chunk.table):
                a[where[_chunk.S]:where[_chunk.S] + len(b)] = b
        if table_only:
            return
        for kind, count in kinds:
            values, status, inexact = numbers[kind]
            a, b = where[count], where[count] + counts[k, count]
            part_values, flags = chunk.numbers[count - 1]
            if not single:
                values[a:b] = part_values.reshape(-1, WIDTHS[kind])
            np.right_shift(flags, _chunk.STATUS_SHIFT, out=status[a:b], casting="unsafe")
            np.bitwise_and(flags, (1 << _chunk.STATUS_SHIFT) - 1, out=inexact[a:b])
        lines = counts[k, _chunk.NLE]
        for kind, corner, element, mine in (
                (KIND_F, where[_chunk.NC] - where[_chunk.NLC], where[_chunk.NE] - where[_chunk.NLE],
                 counts[k, _chunk.NE] - lines),
                (KIND_L, where[_chunk.NLC], where[_chunk.NLE], lines)):
            if mine:
                resolve_corners(chunk.table[2], chunk.table[3], chunk.corners, chunk.malformed, before[k], totals,
                                *corners[kind], kind, corner, element)

    in_parallel(place, len(chunks))
    return Statements(*table, None if table_only else Geometry(numbers, corners))
