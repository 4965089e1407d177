"""Numba kernels for the corners of OBJ ``f`` and ``l`` statements.

A corner (``v``, ``v/vt``, ``v//vn``, ``v/vt/vn``) is parsed as the chunk reader scans it
(:func:`parse_corner`), and its indices resolved to 0-based ones once the chunks are put
together (:func:`resolve_corners`). The kernels never raise on bad input: they return status codes, so the caller
(:mod:`rasterkit.obj.statements`) can name the first bad line of the file.
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel
from rasterkit.obj.kernels.scan import (
    BYTE_CLASS, KIND_F, KIND_L, KIND_V, KIND_VN, KIND_VT, MINUS, PLUS, TOKEN, ZERO, is_digit,
)

#: The raw index of a corner field that is not given (``1//3`` has no vt), or of a corner
#: not read (at and after a malformed one): no index of 18 digits or fewer is this.
ABSENT = np.iinfo(np.int64).min

# Status codes of one face or line corner (code, corner, attribute) written by resolve_corners.
INDEX_OK, INDEX_ZERO, INDEX_BEFORE_FIRST, INDEX_OUT_OF_RANGE, INDEX_MALFORMED = 0, 1, 2, 3, 4

_SLASH, _NL = 47, 10


@kernel(inline="always")
def _resolve(raw, before, total):
    """0-based index and INDEX_* code of an OBJ index (1-based, or negative = relative)."""
    if raw > 0:
        if raw > total:
            return -1, INDEX_OUT_OF_RANGE
        return raw - 1, INDEX_OK
    if raw < 0:
        if before + raw < 0:
            return -1, INDEX_BEFORE_FIRST
        return before + raw, INDEX_OK
    return -1, INDEX_ZERO


@kernel(inline="always")
def parse_corner(buf, a, hi):
    """The corner token that starts at buf[a] (and ends before the first blank or line
    break, or at hi): ``v``, ``v/vt``, ``v//vn`` or ``v/vt/vn``, where vt and vn may be
    empty (``1//``). Each index is a signed integer of at most 18 digits.

    Returns (v, vt, vn, present, ok, end): raw indices (0 when absent), bit k of present set
    when field k was given, ok False when the token is malformed; end is where the token
    ends (ok) or where it was found malformed (not ok: the token may go on).
    """
    v = vt = vn = 0
    present = 0
    field = 0
    value = 0
    sign = 1
    digits = 0
    signed = False
    i = a
    while True:
        c = buf[i] if i < hi else _NL  # the end of the token closes the last field
        if c == _SLASH or BYTE_CLASS[c] != TOKEN:
            if field > 2 or digits > 18 or (digits == 0 and (signed or field == 0)):
                return 0, 0, 0, 0, False, i
            if digits > 0:
                present |= 1 << field
                if field == 0:
                    v = sign * value
                elif field == 1:
                    vt = sign * value
                else:
                    vn = sign * value
            if c != _SLASH:
                return v, vt, vn, present, True, i
            field += 1
            value, sign, digits, signed = 0, 1, 0, False
        elif is_digit(c):
            value = value * 10 + (c - ZERO)
            digits += 1
        elif (c == PLUS or c == MINUS) and digits == 0 and not signed:
            sign = -1 if c == MINUS else 1
            signed = True
        else:
            return 0, 0, 0, 0, False, i
        i += 1


@kernel
def resolve_corners(kinds, ntokens, raw, malformed, before, totals, vertex, texcoord, normal, errors,
                    kind, corner, element):
    """Resolve the raw corners of one chunk's statements of one kind (f or l) into the
    file's arrays.

    Parameters
    ----------
    kinds, ntokens : (S,) int8, int64
        The chunk's statement table.
    raw : (3 * C,) int64
        The raw v, vt, vn of each corner token of the chunk's f and l statements, in order
        (:func:`rasterkit.obj.kernels.chunk.read_lines`; ``ABSENT`` where not given).
    malformed : (E,) int64
        First malformed token of each of those statements, or -1.
    before : (3,) int64
        Number of v, vt, vn statements in the file above the chunk (for negative indices).
    totals : (3,) int64
        Number of v, vt, vn statements in the file.
    vertex, texcoord, normal : (C_file,) int64
        The file's corners of this kind, written from ``corner`` on: 0-based index, -1 where
        absent or invalid; texcoord and normal may be empty (the file has no ``/``).
    errors : (E_file, 3) int64
        The file's (INDEX_* code, corner, attribute) of each statement of this kind, from
        ``element`` on: the first bad vertex reference if any, else the first bad vt/vn
        reference; code 0 when all is well.
    kind : int
        KIND_F or KIND_L: the statements resolved.
    """
    counts = before.copy()
    c = 0  # corner token of the chunk
    e = 0  # f or l statement of the chunk
    attributes = len(texcoord) > 0
    for s in range(len(kinds)):
        k_s = kinds[s]
        if k_s == KIND_V or k_s == KIND_VT or k_s == KIND_VN:
            counts[k_s - KIND_V] += 1
            continue
        if k_s != KIND_F and k_s != KIND_L:
            continue
        n = ntokens[s]
        if k_s != kind:
            c += n
            e += 1
            continue
        bad = malformed[e]
        errors[element, 0] = errors[element, 1] = errors[element, 2] = 0
        for k in range(n):
            out = corner + k
            vertex[out] = -1
            if attributes:
                texcoord[out] = -1
                normal[out] = -1
            if bad >= 0 and k >= bad:
                continue
            for attribute in range(3):
                value = raw[3 * (c + k) + attribute]
                if value == ABSENT:
                    continue
                index, code = _resolve(value, counts[attribute], totals[attribute])
                if attribute == 0:
                    vertex[out] = index
                elif attribute == 1:
                    texcoord[out] = index
                else:
                    normal[out] = index
                vertex_first = attribute == 0 and errors[element, 2] != 0
                if code != INDEX_OK and (errors[element, 0] == INDEX_OK or vertex_first):
                    errors[element, 0], errors[element, 1], errors[element, 2] = code, k, attribute
        if bad >= 0:
            errors[element, 0], errors[element, 1], errors[element, 2] = INDEX_MALFORMED, bad, 0
        c += n
        e += 1
        corner += n
        element += 1
