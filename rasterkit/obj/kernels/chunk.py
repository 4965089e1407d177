"""The Numba kernels that read a chunk of an OBJ file (:mod:`rasterkit.obj.chunks`) in one
pass: its statements (the table the rest of the loader reads: where each statement is, its
kind and token count), the numbers of its ``v``, ``vt`` and ``vn`` statements (as
:func:`rasterkit.runtime.decimal.read_decimal` reads them) and the corner tokens of its ``f``
and ``l`` statements as written (their indices are resolved once the chunks are put together:
:func:`rasterkit.obj.kernels.corners.resolve_corners`).

Statements are split as the module documentation of :mod:`~rasterkit.obj.kernels.scan` says:
a statement is one line (the caller blanked continuations out), a keyword and its tokens; ``#``
at the start of a token starts a comment that runs to the end of the line; blank and comment
lines are no statements. A chunk is a run of whole lines, so its statements are those a
reading of the whole text finds there.

:func:`read_lines` allocates nothing, so it runs without reference counting (``refcounts=
False``: no atomic updates per call of the inlined helpers); it stops when an array the caller
gave it is full, and the caller gives it a larger one and lets it go on. The kernels never
raise on bad input.
"""

from __future__ import annotations

import numpy as np

from rasterkit.obj.kernels.corners import ABSENT, parse_corner
from rasterkit.obj.kernels.scan import (
    BLANK, BYTE_CLASS, KIND_F, KIND_L, KIND_V, KIND_VN, KIND_VT, TOKEN, keyword_kind,
)
from rasterkit.runtime.decimal import NUMBER_INEXACT, NUMBER_OTHER, read_decimal
from rasterkit.runtime.jit import kernel

__all__ = ["read_lines"]

_NL, _HASH = 10, 35
_KEY_V, _KEY_F = ord("v"), ord("f")  # the keywords of most statements, packed as keyword_kind's


#: What read_lines stopped for: the end of the text, or no room in one of the arrays.
DONE, FULL_V, FULL_VT, FULL_VN, FULL_CORNERS, FULL_ELEMENTS, FULL_TABLE = 0, 1, 2, 3, 4, 5, 6
#: The counts read_lines keeps in its ``n``: statements, v, vt, vn rows, corners and f and l
#: statements (elements), and of these the corners and elements of l statements.
S, NV, NT, NN, NC, NE, NLC, NLE = 0, 1, 2, 3, 4, 5, 6, 7
#: A row's flags (read_lines' ``*_flags``): bit k set when its token k is NUMBER_INEXACT,
#: and its worst NUMBER_* status shifted by STATUS_SHIFT.
STATUS_SHIFT = 8


@kernel(refcounts=False, fastmath=False)
def read_lines(buf, i, hi, keep, n, starts, ends, kinds, ntokens, v_values, v_flags, t_values, t_flags,
               n_values, n_flags, corners, malformed):
    """Read the statements of buf[i:hi] (i at the start of a line) into the arrays, after
    the ``n`` (8,) int64 counts of what they hold (updated): the statement table (starts,
    ends, kinds, ntokens); the numbers of the v, vt and vn statements (values: 6, 3 and 3
    per row, NaN where the row has fewer tokens; flags per row, see STATUS_SHIFT) and the
    raw (v, vt, vn) of each corner token of the f and l statements (corners, 3 per corner)
    with their first malformed token (malformed, one per statement), these only when
    ``keep``. Returns where it stopped and why: (hi, DONE), or the start of the statement
    for which an array had no room, and which (FULL_*; what the statement had put in the
    others is taken back). IEEE arithmetic (fastmath=False): the numbers are read by
    :func:`~rasterkit.runtime.decimal.read_decimal`, which needs it."""
    count, nv, nt, nn, nc, ne, nlc, nle = n[S], n[NV], n[NT], n[NN], n[NC], n[NE], n[NLC], n[NLE]
    full = DONE
    start = i
    while i < hi:
        c = BYTE_CLASS[buf[i]]
        if c != TOKEN:  # a blank, or the end of a blank line
            i += 1
            continue
        start = i
        if buf[i] == _HASH:  # a comment line: no statement
            while i < hi and buf[i] != _NL:
                i += 1
            continue
        if count == len(starts):
            full = FULL_TABLE
            break
        key = 0
        while i < hi and BYTE_CLASS[buf[i]] == TOKEN:
            key = key * 256 + buf[i] if i - start < 7 else -1
            i += 1
        end = i
        kind = KIND_V if key == _KEY_V else KIND_F if key == _KEY_F else keyword_kind(key)
        values = v_values  # of this statement's numbers, row and width; or its corners
        row = -1
        width = 0
        element = False
        first_corner = nc
        if keep:
            if kind == KIND_V:
                if nv == len(v_flags):
                    full = FULL_V
                    break
                row, width = nv, 6
            elif kind == KIND_VT:
                if nt == len(t_flags):
                    full = FULL_VT
                    break
                values, row, width = t_values, nt, 3
            elif kind == KIND_VN:
                if nn == len(n_flags):
                    full = FULL_VN
                    break
                values, row, width = n_values, nn, 3
            elif kind == KIND_F or kind == KIND_L:
                if ne == len(malformed):
                    full = FULL_ELEMENTS
                    break
                element = True
                malformed[ne] = -1
        for k in range(width):
            values[width * row + k] = np.nan
        flags = 0
        tokens = 0
        while True:
            while i < hi and BYTE_CLASS[buf[i]] == BLANK:
                i += 1
            if i == hi or buf[i] == _NL or buf[i] == _HASH:
                break
            a = i
            if row >= 0 and flags >> STATUS_SHIFT != NUMBER_OTHER:
                value, status, i = read_decimal(buf, a, hi)
                if i < hi and BYTE_CLASS[buf[i]] == TOKEN:  # the token goes on: no number
                    status = NUMBER_OTHER
                if status == NUMBER_OTHER:
                    flags = (flags & 255) | (NUMBER_OTHER << STATUS_SHIFT)
                elif tokens < width:
                    values[width * row + tokens] = value
                    if status == NUMBER_INEXACT:
                        flags |= (1 << tokens) | (NUMBER_INEXACT << STATUS_SHIFT)
            elif element:
                if 3 * nc + 3 > len(corners):
                    full = FULL_CORNERS
                    break
                v = vt = vn = ABSENT
                if malformed[ne] < 0:
                    v, vt, vn, present, ok, i = parse_corner(buf, a, hi)
                    if not ok:
                        malformed[ne] = tokens
                    if not ok or not present & 1:
                        v = ABSENT
                    if not ok or not present & 2:
                        vt = ABSENT
                    if not ok or not present & 4:
                        vn = ABSENT
                corners[3 * nc] = v
                corners[3 * nc + 1] = vt
                corners[3 * nc + 2] = vn
                nc += 1
            while i < hi and BYTE_CLASS[buf[i]] == TOKEN:  # the rest of the token
                i += 1
            tokens += 1
            end = i
        if full != DONE:  # no room for this statement's corners: taken back
            nc = first_corner
            break
        while i < hi and buf[i] != _NL:  # a comment
            i += 1
        if row >= 0:
            if kind == KIND_V:
                v_flags[row] = flags
                nv += 1
            elif kind == KIND_VT:
                t_flags[row] = flags
                nt += 1
            else:
                n_flags[row] = flags
                nn += 1
        elif element:
            ne += 1
            if kind == KIND_L:
                nle += 1
                nlc += nc - first_corner
        starts[count] = start
        ends[count] = end
        kinds[count] = kind
        ntokens[count] = tokens
        count += 1
    n[S], n[NV], n[NT], n[NN], n[NC], n[NE], n[NLC], n[NLE] = count, nv, nt, nn, nc, ne, nlc, nle
    return (i if full == DONE else start), full
