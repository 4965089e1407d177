"""An OBJ file's text read in chunks, in parallel: split at line breaks into about two chunks a
thread, each chunk read in one pass by :func:`rasterkit.obj.kernels.chunk.read_chunk` on the
threads of :mod:`rasterkit.runtime.threads` (the kernels release the GIL), then put together
in file order: the statement tables and numbers one after another, the corners of ``f`` and
``l`` resolved against the counts of the whole file (a relative index depends on the ``v``
lines above its line in all earlier chunks) by
:func:`rasterkit.obj.kernels.corners.resolve_corners`.

Chunks are whole lines and every statement is one line, so the result is the same for any
number of chunks and threads: the chunks only decide which thread reads which lines.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

from rasterkit.obj.kernels import chunk as _chunk
from rasterkit.obj.kernels.chunk import count_lines, read_lines
from rasterkit.obj.kernels.corners import resolve_corners
from rasterkit.obj.kernels.scan import KIND_F, KIND_L, KIND_V, KIND_VN, KIND_VT
from rasterkit.runtime.threads import get_threads, run_parallel

__all__ = ["CHUNK_BYTES", "Geometry", "Statements", "chunk_bounds", "count_line_breaks", "read_chunk",
           "read_statements"]

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
    """The statement table of a file (:func:`~rasterkit.obj.kernels.chunk.read_chunk`), and
    its geometry, or None when keeping it would have taken more than the budget."""

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


def _in_parallel(task, n: int) -> list:
    """``task(k)`` for k = 0..n-1 on the threads (each claims the next k), results in order."""
    results = [None] * n
    claims = itertools.count()  # next() on it is atomic under the GIL

    def worker(slot):
        for k in iter(claims.__next__, None):
            if k >= n:
                return
            results[k] = task(k)

    if n == 1:
        results[0] = task(0)
    else:
        run_parallel(worker, threads=min(n, get_threads()))
    return results


#: Rows (and corners, and f and l statements) a chunk makes room for at first.
FIRST_CAPACITY = 1024
#: What read_lines fills, in the order it takes them after ``n``: the dtype and the
#: numbers per row of each growing array, and which FULL_* grows it.
_GROWING = ((np.float64, 6, _chunk.FULL_V), (np.int64, 1, _chunk.FULL_V),
            (np.float64, 3, _chunk.FULL_VT), (np.int64, 1, _chunk.FULL_VT),
            (np.float64, 3, _chunk.FULL_VN), (np.int64, 1, _chunk.FULL_VN),
            (np.int64, 3, _chunk.FULL_CORNERS), (np.int64, 1, _chunk.FULL_ELEMENTS))
#: The count (an index into read_lines' ``n``) of the rows of each FULL_*.
_COUNTS = {_chunk.FULL_V: _chunk.NV, _chunk.FULL_VT: _chunk.NT, _chunk.FULL_VN: _chunk.NN,
           _chunk.FULL_CORNERS: _chunk.NC, _chunk.FULL_ELEMENTS: _chunk.NE}


def read_chunk(buf: np.ndarray, lo: int, hi: int, lines: int, budget: int) -> tuple:
    """Read the statements of buf[lo:hi] (whole lines, ``lines`` line breaks among them) with
    :func:`~rasterkit.obj.kernels.chunk.read_lines`, its arrays grown twice as large each
    time one is full while they take at most ``budget`` bytes.

    Returns ``(starts, ends, kinds, ntokens, v, vt, vn, corners, malformed, over)``: the
    statement table (absolute byte offsets into buf); for the v, vt and vn statements
    ``(values (rows * width,) float64, flags (rows,) int64)`` (see ``read_lines``); the raw
    (v, vt, vn) of each f and l corner token (3 * C,) int64; the first malformed token (E,)
    of each f and l statement or -1; and whether the numbers and corners were over the
    budget (then they are empty: the table is complete)."""
    table = [np.empty(lines + 1, np.int64), np.empty(lines + 1, np.int64), np.empty(lines + 1, np.int8),
             np.empty(lines + 1, np.int64)]
    growing = [np.empty(FIRST_CAPACITY * width, dtype) for dtype, width, _ in _GROWING]
    spent = sum(a.nbytes for a in growing)
    keep = spent <= budget
    n = np.zeros(6, np.int64)
    i = lo
    while True:
        i, full = read_lines(buf, i, hi, keep, n, *table, *growing)
        if full == _chunk.DONE:
            break
        grow = [k for k, (_, _, which) in enumerate(_GROWING) if which == full]
        spent += sum(growing[k].nbytes for k in grow)
        if spent > budget:
            keep = False
            growing = [a[:0] for a in growing]
            continue
        used = int(n[_COUNTS[full]])
        for k in grow:
            a, width = growing[k], _GROWING[k][1]
            b = np.empty(2 * len(a), a.dtype)
            b[:used * width] = a[:used * width]
            growing[k] = b
    count = int(n[_chunk.S])
    used = [0 if not keep else int(n[_COUNTS[which]]) * width for _, width, which in _GROWING]
    parts = [a[:u] for a, u in zip(growing, used)]
    return (*(a[:count] for a in table), tuple(parts[0:2]), tuple(parts[2:4]), tuple(parts[4:6]),
            parts[6], parts[7], not keep)


def count_line_breaks(buf: np.ndarray, bounds: list[int]) -> list[int]:
    """The line breaks of each chunk of buf."""
    return _in_parallel(lambda k: int(count_lines(buf, bounds[k], bounds[k + 1])), len(bounds) - 1)


def read_statements(buf: np.ndarray, bounds: list[int], lines: list[int], budget: int,
                    attributes: bool) -> Statements:
    """Read the chunks of buf (``bounds`` from :func:`chunk_bounds`, ``lines`` their line
    breaks), keeping at most ``budget`` bytes of numbers and corners, and put them together;
    ``attributes``: whether any corner may name a vt or vn (buf has a ``/``)."""
    n = len(bounds) - 1
    share = budget // n
    chunks = _in_parallel(lambda k: read_chunk(buf, bounds[k], bounds[k + 1], lines[k], share), n)
    if n == 1:
        (starts, ends, kinds, ntokens, *_, over), = chunks
        return Statements(starts, ends, kinds, ntokens, None if over else _geometry(chunks, attributes))
    table = [np.concatenate([c[f] for c in chunks]) for f in range(4)]
    over = any(c[-1] for c in chunks)
    return Statements(*table, None if over else _geometry(chunks, attributes))


def _geometry(chunks: list, attributes: bool) -> Geometry:
    """The numbers and corners of the chunks (read within the budget), in file order; the
    texture and normal indices of the corners only with ``attributes`` (else empty)."""
    kinds = [KIND_V, KIND_VT, KIND_VN]
    rows = np.array([[len(c[4 + j][1]) for j in range(3)] for c in chunks], np.int64)  # (chunks, 3)
    before = np.cumsum(rows, axis=0) - rows
    totals = rows.sum(axis=0)
    element_kinds = [KIND_F, KIND_L]
    # corners and elements of each chunk, per kind: from the kinds and token counts
    sizes = [[_element_sizes(c[2], c[3], kind) for kind in element_kinds] for c in chunks]
    numbers = {}
    for j, kind in enumerate(kinds):
        width = WIDTHS[kind]
        numbers[kind] = (np.empty((totals[j], width)), np.empty(totals[j], np.int8), np.empty(totals[j], np.int64))
    corners = {}
    corner_at, element_at = {}, {}
    for i, kind in enumerate(element_kinds):
        e = np.array([s[i][0] for s in sizes], np.int64)
        c = np.array([s[i][1] for s in sizes], np.int64)
        element_at[kind], corner_at[kind] = np.cumsum(e) - e, np.cumsum(c) - c
        total = int(c.sum())
        corners[kind] = (np.empty(total, np.int64), np.empty(total if attributes else 0, np.int64),
                         np.empty(total if attributes else 0, np.int64), np.empty((int(e.sum()), 3), np.int64))

    def place(k):
        chunk = chunks[k]
        for j, kind in enumerate(kinds):
            values, status, inexact = numbers[kind]
            a, b = before[k, j], before[k, j] + rows[k, j]
            part_values, flags = chunk[4 + j]
            values[a:b] = part_values.reshape(-1, WIDTHS[kind])
            np.right_shift(flags, _chunk.STATUS_SHIFT, out=status[a:b], casting="unsafe")
            np.bitwise_and(flags, (1 << _chunk.STATUS_SHIFT) - 1, out=inexact[a:b])
        for kind in element_kinds:
            resolve_corners(chunk[2], chunk[3], chunk[7], chunk[8], before[k], totals, *corners[kind],
                            kind, corner_at[kind][k], element_at[kind][k])

    _in_parallel(place, len(chunks))
    return Geometry(numbers, corners)


def _element_sizes(kinds: np.ndarray, ntokens: np.ndarray, kind: int) -> tuple[int, int]:
    """The number of statements of one kind among a chunk's, and of their tokens."""
    mine = kinds == kind
    return int(np.count_nonzero(mine)), int(ntokens[mine].sum())
