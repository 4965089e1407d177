"""The text of an OFF file as records: its lines that hold tokens, once comments and blank lines
are gone, each with its tokens (:class:`rasterkit.runtime.tokens.Tokens`) and its line number.

Line breaks matter in OFF (a face's colour runs to the end of its line), so the body is read a
record at a time, but with NumPy over all of them at once: tokens, then the line of each token,
then the runs of tokens on one line. ``#`` starts a comment anywhere, to the end of the line.
LF and CRLF end lines, and so does CR in a file without LF (old Mac files).
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

from rasterkit.off.errors import OffError, check
from rasterkit.runtime.tokens import Tokens, tokenize

__all__ = ["BYTES_PER_TOKEN", "Records", "read_records"]

_COMMENT = re.compile(rb"#[^\n]*")
_BOM = b"\xef\xbb\xbf"

#: Bytes per byte of text while it is split (the byte classes), and per token (its offsets,
#: its line, and what reading the numbers makes of it).
BYTES_PER_BYTE = 4
BYTES_PER_TOKEN = 48


@dataclass(frozen=True)
class Records:
    """The records of a text: record r is tokens ``first[r]`` to ``first[r] + size[r]`` of
    ``tokens``, on line ``line[r]`` (1-based) of the file."""

    tokens: Tokens
    first: np.ndarray  # (R,) int32 (int64 beyond 2 GiB of text)
    size: np.ndarray  # (R,) likewise
    line: np.ndarray  # (R,) int32

    def __len__(self) -> int:
        return len(self.first)

    def words(self, r: int, most: int = 8) -> list[bytes]:
        """The first ``most`` tokens of record r."""
        return [self.tokens.raw(k) for k in range(self.first[r], self.first[r] + min(self.size[r], most))]

    def line_of(self, token: int) -> int:
        """The line of token ``token``."""
        return int(self.line[np.searchsorted(self.first, token, side="right") - 1])


def read_records(name: str, data: bytes) -> Records:
    """The records of the OFF text ``data`` (the file ``name``)."""
    text = data.removeprefix(_BOM)
    if b"\n" not in text and b"\r" in text:
        text = text.replace(b"\r", b"\n")
    if b"#" in text:
        text = _COMMENT.sub(b"", text)  # every line stays where it was: the line numbers hold
    check(name, BYTES_PER_BYTE * len(text), f"reading its {len(text)} bytes")
    buf = np.frombuffer(text, np.uint8)
    tokens = tokenize(buf)
    check(name, BYTES_PER_BYTE * len(text) + BYTES_PER_TOKEN * len(tokens), f"reading its {len(tokens)} tokens")
    token_line = np.searchsorted(np.flatnonzero(buf == 10), tokens.starts).astype(np.int32)
    new_line = np.empty(len(token_line), bool)
    new_line[:1] = True
    np.not_equal(token_line[1:], token_line[:-1], out=new_line[1:])
    first = np.flatnonzero(new_line).astype(tokens.starts.dtype)
    if not len(first):
        raise OffError(name, None, "an empty file (no header, no numbers)")
    return Records(tokens, first, np.diff(np.append(first, len(tokens))), token_line[first] + 1)
