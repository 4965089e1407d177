"""How OBJ text splits into statements and tokens (for :func:`rasterkit.load_obj`): the byte
classes, statement kinds and keywords the chunk reader (:mod:`~rasterkit.obj.kernels.chunk`)
uses, and :func:`split_tokens`, which splits as it does, for Python code.

Everything here works on the raw bytes of a file (a C-contiguous uint8 array). A *statement*
is one OBJ line (ended by LF): a keyword and its tokens. ``#`` at the start of a token starts a
comment that runs to the end of the line.

Tokens are separated by *blanks*, the bytes of :data:`BLANKS`: space and tab (the OBJ
convention), and CR, VT and FF, which count as spaces (CR ends the lines of Windows files; VT
and FF are the rest of C's ``isspace``, which many OBJ readers split on). Every other byte is
part of a token: the control bytes 0x1c-0x1f and Unicode spaces (U+0085, U+00A0, U+2003,
U+3000...) separate nothing, so a number or vertex reference that contains one is malformed.
Python code splits a statement's text with :func:`split_tokens`, which agrees with the kernels
on every byte. Line continuations (a
backslash before the line break) are blanked out by the caller before the scan, so here every
statement is one physical line. The byte classes and byte codes here are shared by the chunk
reader and the corner parser (:mod:`~rasterkit.obj.kernels.corners`).
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime.jit import kernel

# Statement kinds of the statement table (blank and comment lines are not statements).
KIND_V, KIND_VT, KIND_VN, KIND_F, KIND_L, KIND_P = 1, 2, 3, 4, 5, 6
KIND_G, KIND_O, KIND_S, KIND_USEMTL, KIND_MTLLIB, KIND_OTHER = 7, 8, 9, 10, 11, 12

# ASCII codes; the signs and the zero are shared with the number and corner parsers.
_NL, _HASH, _NINE = 10, 35, 57
PLUS, MINUS, ZERO = 43, 45, 48


def _key(word: bytes) -> int:
    """A keyword of up to 7 bytes packed big-endian into one integer, as the scan builds it."""
    return int.from_bytes(word, "big")


_KINDS = {_key(b"v"): KIND_V, _key(b"vt"): KIND_VT, _key(b"vn"): KIND_VN, _key(b"f"): KIND_F,
          _key(b"l"): KIND_L, _key(b"p"): KIND_P, _key(b"g"): KIND_G, _key(b"o"): KIND_O,
          _key(b"s"): KIND_S, _key(b"usemtl"): KIND_USEMTL, _key(b"mtllib"): KIND_MTLLIB}
_KIND_KEYS = np.array(list(_KINDS), np.int64)
_KIND_CODES = np.array(list(_KINDS.values()), np.int8)


BLANKS = b" \t\r\x0b\x0c"
"""The bytes that separate tokens (see the module documentation); LF separates statements."""


@kernel(inline="always")
def is_blank(c):
    """True for the bytes of :data:`BLANKS`."""
    return c == 32 or c == 9 or c == 13 or c == 11 or c == 12


#: The class of each byte value for the kernels' loops (one table look-up per byte):
#: TOKEN (part of a token), BLANK (a byte of :data:`BLANKS`) or LINE (LF).
TOKEN, BLANK, LINE = 0, 1, 2
BYTE_CLASS = np.zeros(256, np.uint8)
BYTE_CLASS[list(BLANKS)] = BLANK
BYTE_CLASS[_NL] = LINE


def split_tokens(text: bytes) -> list:
    """The tokens of a statement's text, split as the kernels split them: ``bytes.split()``
    with no argument splits on exactly :data:`BLANKS` and LF (ASCII whitespace), never on the
    Unicode spaces that ``str.split()`` knows."""
    return text.split()


@kernel(inline="always")
def is_digit(c):
    return ZERO <= c <= _NINE


@kernel
def keyword_kind(key):
    """KIND_* of a keyword packed as the chunk reader packs it (-1, a keyword longer than 7 bytes, and
    any other unknown key give KIND_OTHER)."""
    for k in range(len(_KIND_KEYS)):
        if _KIND_KEYS[k] == key:
            return _KIND_CODES[k]
    return np.int8(KIND_OTHER)
