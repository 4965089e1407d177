"""Numba kernels for the corners of OBJ ``f`` and ``l`` statements.

A corner (``v``, ``v/vt``, ``v//vn``, ``v/vt/vn``) is parsed and its indices resolved to 0-based
ones. The kernels never raise on bad input: they return status codes, so the caller
(:mod:`rasterkit.obj.statements`) can name the first bad line of the file.
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel
from rasterkit.obj.kernels.scan import MINUS, PLUS, ZERO, is_digit, next_token

# Status codes of one face or line corner (code, corner, attribute) written by parse_corners.
INDEX_OK, INDEX_ZERO, INDEX_BEFORE_FIRST, INDEX_OUT_OF_RANGE, INDEX_MALFORMED = 0, 1, 2, 3, 4

_SLASH = 47


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


@kernel
def _parse_corner(buf, a, b):
    """One corner token buf[a:b]: ``v``, ``v/vt``, ``v//vn`` or ``v/vt/vn``, where vt and vn
    may be empty (``1//``). Each index is a signed integer of at most 18 digits.

    Returns (v, vt, vn, present, ok): raw indices (0 when absent), bit k of present set when
    field k was given, ok False when the token is malformed.
    """
    v = vt = vn = 0
    present = 0
    field = 0
    value = 0
    sign = 1
    digits = 0
    signed = False
    for i in range(a, b + 1):
        c = buf[i] if i < b else _SLASH  # the end of the token closes the last field
        if c == _SLASH:
            if field > 2 or digits > 18 or (digits == 0 and (signed or field == 0)):
                return 0, 0, 0, 0, False
            if digits > 0:
                present |= 1 << field
                if field == 0:
                    v = sign * value
                elif field == 1:
                    vt = sign * value
                else:
                    vn = sign * value
            field += 1
            value, sign, digits, signed = 0, 1, 0, False
        elif is_digit(c):
            value = value * 10 + (c - ZERO)
            digits += 1
        elif (c == PLUS or c == MINUS) and digits == 0 and not signed:
            sign = -1 if c == MINUS else 1
            signed = True
        else:
            return 0, 0, 0, 0, False
    return v, vt, vn, present, True


@kernel
def parse_corners(buf, starts, ends, offsets, before, totals, attributes):
    """Parse and resolve the vertex references of f and l statements.

    Parameters
    ----------
    buf : (B,) uint8
    starts, ends : (S,) int64
        Statement ranges.
    offsets : (S + 1,) int64
        Where each statement's corners go in the output (cumulative token counts).
    before : (S, 3) int64
        Number of v, vt, vn statements before each statement (for negative indices).
    totals : (3,) int64
        Number of v, vt, vn statements in the file.
    attributes : bool
        Whether any corner may name a vt or vn: False when buf has no ``/``, and then
        texcoord and normal are empty (no room is made for them).

    Returns
    -------
    vertex, texcoord, normal : (C,) int64
        0-based v, vt, vn index of each corner; -1 where absent or invalid.
    errors : (S, 3) int64
        (INDEX_* code, corner, attribute 0/1/2) of the statement's first problem: the first bad
        vertex reference if any, else the first bad vt/vn reference; code 0 when all is well.
    """
    rows = len(starts)
    # np.empty and loops: np.full and np.zeros compile an implementation each (~0.2 s)
    vertex = np.empty(offsets[rows], np.int64)
    texcoord = np.empty(offsets[rows] if attributes else 0, np.int64)
    normal = np.empty(offsets[rows] if attributes else 0, np.int64)
    for c in range(len(vertex)):
        vertex[c] = -1
    for c in range(len(texcoord)):
        texcoord[c] = -1
        normal[c] = -1
    errors = np.empty((rows, 3), np.int64)
    for r in range(rows):
        errors[r, 0] = errors[r, 1] = errors[r, 2] = 0
    for r in range(rows):
        i = next_token(buf, starts[r], ends[r])[1]  # after the keyword
        k = 0
        while i < ends[r]:
            a, i = next_token(buf, i, ends[r])
            v, vt, vn, present, ok = _parse_corner(buf, a, i)
            if not ok:
                errors[r, 0], errors[r, 1], errors[r, 2] = INDEX_MALFORMED, k, 0
                break
            c = offsets[r] + k
            for attribute, raw in ((0, v), (1, vt), (2, vn)):
                if present & (1 << attribute):  # vt and vn only where a slash is
                    index, code = _resolve(raw, before[r, attribute], totals[attribute])
                    if attribute == 0:
                        vertex[c] = index
                    elif attribute == 1:
                        texcoord[c] = index
                    else:
                        normal[c] = index
                    vertex_first = attribute == 0 and errors[r, 2] != 0
                    if code != INDEX_OK and (errors[r, 0] == INDEX_OK or vertex_first):
                        errors[r, 0], errors[r, 1], errors[r, 2] = code, k, attribute
            k += 1
    return vertex, texcoord, normal, errors
