"""Whitespace-separated tokens of a text file and the numbers they hold, with NumPy: what the
ASCII readers (STL, OFF) share, without a Python loop per line or per token.

A token is a run of bytes that are not whitespace; whitespace is space, tab, LF, CR, VT and FF
(C's ``isspace``), nothing else: a NUL, a control byte 0x1c-0x1f or a byte of a Unicode space
(U+00A0, U+3000...) is part of the token it touches, which is then no number.

Numbers are checked here before they are converted, so that the conversion cannot take more than
the file's grammar allows:

- :func:`floats`: ``[+-]`` digits with an optional point and an optional exponent (``1``,
  ``-2.``, ``.5``, ``1e-3``, ``1E+02``), or ``nan`` / ``inf`` / ``infinity`` in any case and
  with a sign; each is the correctly rounded float64 of its text (NumPy's conversion of ``S``
  arrays, Python's ``float``). Underscores (``1_0``), hex and MSVC's ``1.#IND`` are refused.
- :func:`integers`: ``[+-]`` and 1 to 18 decimal digits (``|value| < 10**18``), converted by
  NumPy arithmetic.

A bad token raises :class:`BadToken` with its position in the request, for the reader to name
the line. Pure NumPy (no Numba).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["BadToken", "Tokens", "decode", "floats", "integers", "shown", "tokenize"]

SPACES = b" \t\n\r\x0b\x0c"
_SPACE = np.zeros(256, bool)
_SPACE[list(SPACES)] = True

_DIGIT = np.zeros(256, bool)
_DIGIT[list(b"0123456789")] = True
# Bytes that may appear in a number: digits, sign, point, exponent, and the letters of nan/infinity.
_NUMBER_BYTE = _DIGIT.copy()
_NUMBER_BYTE[list(b"+-.eEnNaAiIfFtTyY")] = True

#: Tokens longer than this are converted one by one (a 400-digit number is valid, but rare).
LONG_TOKEN = 40
#: Tokens converted at a time (the temporaries take some 100 bytes per token).
CHUNK = 1 << 18

_WORDS = (b"nan", b"inf", b"infinity")


class BadToken(ValueError):
    """Token ``index`` (a position in the array of tokens asked for) is not what was asked for:
    ``reason`` says why, naming the token."""

    def __init__(self, index: int, reason: str):
        self.index = int(index)
        self.reason = reason
        super().__init__(reason)


@dataclass(frozen=True)
class Tokens:
    """The tokens of ``buf`` (uint8 text): token k is ``buf[starts[k]:ends[k]]`` (integer
    offsets into ``buf``, in order)."""

    buf: np.ndarray
    starts: np.ndarray  # int32 or int64
    ends: np.ndarray

    def __len__(self) -> int:
        return len(self.starts)

    def raw(self, k: int) -> bytes:
        return self.buf[self.starts[k]:self.ends[k]].tobytes()

    def shown(self, k: int) -> str:
        """Token k for a message (:func:`shown`)."""
        return shown(self.raw(k))

    def are(self, which: np.ndarray, word: bytes) -> np.ndarray:
        """(K,) bool: tokens ``which`` are ``word`` (lower-case ASCII letters), in any case."""
        starts = self.starts[which]
        ok = (self.ends[which] - starts) == len(word)
        last = len(self.buf) - 1
        for i, letter in enumerate(word):
            ok &= (self.buf[np.minimum(starts + i, last)] | 0x20) == letter
        return ok


def tokenize(buf: np.ndarray, start: int = 0, end: int | None = None) -> Tokens:
    """The tokens of ``buf[start:end]`` (offsets into ``buf``: int32 when they fit, else
    int64). Takes about 3 bytes of temporaries per byte of text and 8 bytes per token (16
    beyond 2 GiB)."""
    end = len(buf) if end is None else end
    text = np.zeros(end - start + 2, bool)  # a space before and after: every token starts and ends
    np.logical_not(_SPACE[buf[start:end]], out=text[1:-1])
    offsets = np.int32 if end < 2**31 else np.int64
    starts = (np.flatnonzero(text[1:] & ~text[:-1]) + start).astype(offsets)
    ends = (np.flatnonzero(text[:-1] & ~text[1:]) + start).astype(offsets)
    return Tokens(buf, starts, ends)


def decode(raw: bytes) -> str:
    """UTF-8 text; Latin-1 for bytes that are not UTF-8."""
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError:
        return raw.decode("latin-1")


def shown(raw: bytes) -> str:
    """A token for a one-line message: its text as ``repr`` (so no byte can break the line),
    cut after 40 characters."""
    text = decode(raw)
    return repr(text) if len(text) <= LONG_TOKEN else repr(text[:LONG_TOKEN]) + "..."


def _gather(tokens: Tokens, which: np.ndarray, width: int) -> np.ndarray:
    """(K, width) uint8: tokens ``which`` (each at most ``width`` bytes), zero-padded."""
    starts = tokens.starts[which]
    lengths = tokens.ends[which] - starts
    last = len(tokens.buf) - 1
    out = np.zeros((len(which), width), np.uint8)
    for j in range(width):  # a column at a time: no (K, width) int64 index array
        column = tokens.buf[np.minimum(starts + j, last)]
        out[:, j] = np.where(j < lengths, column, 0)
    return out


def _first(bad: np.ndarray) -> int:
    return int(np.argmax(bad))


def _in_chunks(convert, tokens: Tokens, which, what: str, dtype) -> np.ndarray:
    """``convert(tokens, which[chunk], what)`` for chunks of :data:`CHUNK` tokens, so that the
    temporaries of a conversion stay small whatever the file; a BadToken counts in ``which``."""
    which = np.asarray(which, np.int64)
    out = np.empty(len(which), dtype)
    for start in range(0, len(which), CHUNK):
        try:
            out[start:start + CHUNK] = convert(tokens, which[start:start + CHUNK], what)
        except BadToken as e:
            raise BadToken(start + e.index, e.reason) from None
    return out


def floats(tokens: Tokens, which: np.ndarray, what: str = "a number") -> np.ndarray:
    """(K,) float64 values of tokens ``which`` (int64 token indices); :class:`BadToken` (with
    ``what`` was expected) at the first one that is not a number (see the module's rules)."""
    return _in_chunks(_floats, tokens, which, what, np.float64)


def _floats(tokens: Tokens, which: np.ndarray, what: str) -> np.ndarray:
    out = np.empty(len(which), np.float64)
    lengths = tokens.ends[which] - tokens.starts[which]
    long = lengths > LONG_TOKEN
    short = np.flatnonzero(~long)
    if len(short):
        width = int(lengths[short].max())
        block = _gather(tokens, which[short], width)
        padding = np.arange(width) >= lengths[short, None]
        bad = ~(_NUMBER_BYTE[block] | padding).all(axis=1)
        if bad.any():
            k = short[_first(bad)]
            raise BadToken(k, f"expected {what}, got {tokens.shown(which[k])}")
        try:
            with np.errstate(over="ignore"):  # 1e400 is inf, as Python's float says, without a warning
                out[short] = block.view(f"S{width}").ravel().astype(np.float64)
        except ValueError:
            k = short[_first_unreadable(block)]
            raise BadToken(k, f"expected {what}, got {tokens.shown(which[k])}") from None
    for k in np.flatnonzero(long):
        out[k] = _one_float(tokens, which, k, what)
    return out


def _first_unreadable(block: np.ndarray) -> int:
    """The first row of ``block`` (zero-padded number tokens) that Python's float refuses."""
    for k, row in enumerate(block):
        try:
            float(row.tobytes().rstrip(b"\0"))
        except ValueError:
            return k
    return 0


def _one_float(tokens: Tokens, which: np.ndarray, k: int, what: str) -> float:
    raw = tokens.raw(which[k])
    if _NUMBER_BYTE[np.frombuffer(raw, np.uint8)].all():
        try:
            return float(raw)
        except ValueError:
            pass
    raise BadToken(k, f"expected {what}, got {shown(raw)}")


def integers(tokens: Tokens, which: np.ndarray, what: str = "an integer") -> np.ndarray:
    """(K,) int64 values of tokens ``which``: ``[+-]`` and 1 to 18 decimal digits;
    :class:`BadToken` (``what`` was expected) at the first other one."""
    return _in_chunks(_integers, tokens, which, what, np.int64)


def _integers(tokens: Tokens, which: np.ndarray, what: str) -> np.ndarray:
    starts = tokens.starts[which]
    lengths = tokens.ends[which] - starts
    first = tokens.buf[starts]
    signed = (first == ord("+")) | (first == ord("-"))
    digits = lengths - signed
    width = int(min(lengths.max(), 20))
    block = _gather(tokens, which, width)
    ok = (digits >= 1) & (digits <= 18)
    value = np.zeros(len(which), np.int64)
    for j in range(width):
        inside = (j >= signed) & (j < lengths)
        ok &= ~inside | _DIGIT[block[:, j]]
        value = np.where(inside, value * 10 + (block[:, j].astype(np.int64) - ord("0")), value)
    if not ok.all():
        k = _first(~ok)
        raise BadToken(k, f"expected {what}, got {tokens.shown(which[k])}")
    return np.where(first == ord("-"), -value, value)
