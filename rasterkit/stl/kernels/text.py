"""A Numba kernel that reads the facets of ASCII STL text in one pass over its bytes.

:func:`scan_facets` reads facets, 21 tokens each, from a byte offset for as long as the next
token is ``facet``: it checks each keyword where the grammar puts it (in any case) and parses
the 12 numbers with :func:`rasterkit.runtime.decimal.parse_decimal`; a number it cannot round
exactly, or that is no plain decimal (``nan``, ``inf``, or no number at all), is flagged with
its place for the caller to convert or refuse. The ``solid`` and ``endsolid`` lines are the
caller's (``rasterkit.stl.ascii``): the kernel stops at any token other than ``facet``.

Tokens are separated by whitespace: space, tab, LF, CR, VT, FF, nothing else.
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.decimal import NUMBER_OK, parse_decimal
from rasterkit.runtime.jit import kernel

__all__ = ["FACET", "SCAN_BAD", "SCAN_FULL", "SCAN_STOP", "scan_facets"]

FACET = (b"facet", b"normal", None, None, None, b"outer", b"loop",
         b"vertex", None, None, None, b"vertex", None, None, None, b"vertex", None, None, None,
         b"endloop", b"endfacet")
"""The 21 tokens of a facet: keywords, and None where a number goes."""

#: Why :func:`scan_facets` returned: its arrays are full; the next token is not ``facet`` (or
#: the text ends); a token of a facet is not what the grammar wants there.
SCAN_FULL, SCAN_STOP, SCAN_BAD = 0, 1, 2

_WORDS = [word for word in dict.fromkeys(FACET) if word is not None]
_WORD_BYTES = np.zeros((len(_WORDS), 8), np.uint8)
for _k, _word in enumerate(_WORDS):
    _WORD_BYTES[_k, :len(_word)] = np.frombuffer(_word, np.uint8)
_WORD_LENGTHS = np.array([len(w) for w in _WORDS], np.int64)
# The word of each slot of a facet (an index into _WORDS), -1 for a number.
_SLOTS = np.array([-1 if w is None else _WORDS.index(w) for w in FACET], np.int64)


@kernel(inline="always")
def _is_space(c):
    return c == 32 or c == 10 or c == 13 or c == 9 or c == 11 or c == 12


@kernel
def _is_word(buf, a, b, w):
    """Whether buf[a:b] is word w of _WORDS, in any case."""
    if b - a != _WORD_LENGTHS[w]:
        return False
    for i in range(b - a):
        if buf[a + i] | 32 != _WORD_BYTES[w, i]:
            return False
    return True


@kernel(fastmath=False)
def scan_facets(buf, pos, values, offsets, starts, ends, flags):
    """Read facets from byte ``pos`` of ``buf`` (uint8 text) into row 0, 1, ... of:

    values : (C, 12) float64
        The numbers of each facet: the normal, then the three corners.
    offsets : (C,) int64
        The byte offset of each facet's ``facet`` token.
    starts, ends : (C, 12) int64
        The bytes of each number flagged in ``flags`` (not written for the others).
    flags : (C, 12) bool
        Numbers that were not read exactly (their value is to be ignored).

    Returns ``(status, at, count, slot)``: ``count`` facets were read; :data:`SCAN_FULL`: the
    arrays are full, go on from byte ``at``; :data:`SCAN_STOP`: the token at byte ``at`` is
    not ``facet`` (``at`` is ``len(buf)`` at the end of the text); :data:`SCAN_BAD`: the token
    at ``at`` (``len(buf)``: the text ended) is not what slot ``slot`` of :data:`FACET` wants.
    """
    n = len(buf)
    capacity = values.shape[0]
    count = 0
    while count < capacity:
        k = 0  # the facet's numbers so far
        for slot in range(21):
            while pos < n and _is_space(buf[pos]):
                pos += 1
            a = pos
            while pos < n and not _is_space(buf[pos]):
                pos += 1
            if a == n:
                return (SCAN_STOP if slot == 0 else SCAN_BAD), a, count, slot
            w = _SLOTS[slot]
            if w >= 0:
                if not _is_word(buf, a, pos, w):
                    return (SCAN_STOP if slot == 0 else SCAN_BAD), a, count, slot
                if slot == 0:
                    offsets[count] = a
            else:
                value, status = parse_decimal(buf, a, pos)
                values[count, k] = value
                flags[count, k] = status != NUMBER_OK
                if status != NUMBER_OK:
                    starts[count, k] = a
                    ends[count, k] = pos
                k += 1
        count += 1
    return SCAN_FULL, pos, count, 0
