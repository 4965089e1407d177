"""Walking the rows of an element whose lists differ in length from row to row: where each
row starts and the count of each of its lists (each row's place depends on the counts of
the rows before it, so this is one pass in order).

A row is laid out as ``segments[0]`` units of scalar properties, then list 0 (its count,
then its items), ``segments[1]`` units, list 1, ..., ``segments[L]`` units. Units are bytes
in a binary body and tokens in an ASCII one. The walks never raise: they return a status
and the row where the walk stopped. :func:`copy_runs` then gathers a property's values from
the rows.
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel

__all__ = ["BAD_COUNT", "PAST_END", "SHORT", "WALKED", "copy_runs", "walk_binary", "walk_tokens"]

#: Statuses: every row walked; the data end inside a row; a count that is negative (or, in
#: text, no whole number); a count whose items go past the end of the data.
WALKED, SHORT, BAD_COUNT, PAST_END = 0, 1, 2, 3


@kernel
def _count(buf, at, size, signed, big):
    """The integer of ``size`` (1, 2 or 4) bytes at buf[at], in the byte order ``big``."""
    value = np.int64(0)
    for k in range(size):
        byte = np.int64(buf[at + (size - 1 - k if not big else k)])
        value = (value << 8) | byte
    if signed and value >= np.int64(1) << (8 * size - 1):
        value -= np.int64(1) << (8 * size)
    return value


@kernel
def walk_binary(buf, start, n, segments, count_sizes, count_signed, item_sizes, big):
    """Walk ``n`` rows of a binary body from byte ``start``.

    Returns ``starts`` (n,) int64 (each row's first byte), ``counts`` (n, L) int64,
    ``status``, ``row`` and ``list`` (where it stopped: -1, -1 when all were walked; list L
    when a row's scalars after its lists are cut short), ``at`` (the byte after the last
    row walked, or the bad count's byte) and ``value`` (the bad count)."""
    lists = len(count_sizes)
    starts = np.empty(n, np.int64)
    counts = np.empty((n, lists), np.int64)
    end = len(buf)
    at = start
    for r in range(n):
        starts[r] = at
        for j in range(lists):
            at += segments[j]
            if at + count_sizes[j] > end:
                return starts, counts, SHORT, r, j, at, 0
            c = _count(buf, at, count_sizes[j], count_signed[j], big)
            if c < 0:
                return starts, counts, BAD_COUNT, r, j, at, c
            if c > (end - at - count_sizes[j]) // max(item_sizes[j], 1):
                return starts, counts, PAST_END, r, j, at, c
            counts[r, j] = c
            at += count_sizes[j] + c * item_sizes[j]
        at += segments[lists]
        if at > end:
            return starts, counts, SHORT, r, lists, at, 0
    return starts, counts, WALKED, -1, -1, at, 0


@kernel
def walk_tokens(values, start, n, segments):
    """Walk ``n`` rows of an ASCII body's numbers ``values`` from token ``start`` (every
    count a token of its own, every item one token). Returns as :func:`walk_binary`, with
    ``at`` a token number."""
    lists = len(segments) - 1
    starts = np.empty(n, np.int64)
    counts = np.empty((n, lists), np.int64)
    end = len(values)
    at = start
    for r in range(n):
        starts[r] = at
        for j in range(lists):
            at += segments[j]
            if at >= end:
                return starts, counts, SHORT, r, j, at, 0
            v = values[at]
            if not (v >= 0.0 and v == np.floor(v)):
                return starts, counts, BAD_COUNT, r, j, at, 0
            if v > end - at - 1:
                return starts, counts, PAST_END, r, j, at, 0
            c = np.int64(v)
            counts[r, j] = c
            at += 1 + c
        at += segments[lists]
        if at > end:
            return starts, counts, SHORT, r, lists, at, 0
    return starts, counts, WALKED, -1, -1, at, 0


@kernel
def copy_runs(source, starts, lengths):
    """The runs ``source[starts[r]:starts[r] + lengths[r]]`` one after another (the values of
    walked rows: each row's run of bytes or tokens); the runs lie within ``source``."""
    total = 0
    for r in range(len(starts)):
        total += lengths[r]
    out = np.empty(total, source.dtype)
    at = 0
    for r in range(len(starts)):
        first = starts[r]
        for k in range(lengths[r]):
            out[at + k] = source[first + k]
        at += lengths[r]
    return out
