"""The bytes of an OBJ file and its statements: reading the file (byte order marks, binary
content, CR line breaks, continuations), the scanning kernel's statement table, and the text of
single statements for messages and names."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from rasterkit.obj.chunks import Geometry, chunk_bounds, read_statements
from rasterkit.obj.errors import ObjError
from rasterkit.obj.files import read_file
from rasterkit.obj.memory import check_scan, check_statements, parse_budget
from rasterkit.obj.kernels.scan import KIND_V, KIND_VN, KIND_VT, split_tokens
from rasterkit.runtime.threads import get_threads

__all__ = ["Document", "decode"]

_UTF8_BOM = b"\xef\xbb\xbf"
_WIDE_BOMS = {b"\xff\xfe\x00\x00": "UTF-32", b"\x00\x00\xfe\xff": "UTF-32",
              b"\xff\xfe": "UTF-16", b"\xfe\xff": "UTF-16"}


@dataclass(frozen=True)
class Document:
    """The file's bytes, its statements and the numbers and corners of its geometry
    statements (read in chunks: :mod:`rasterkit.obj.chunks`)."""

    name: str
    data: bytes  # the file's bytes after the byte order mark
    text: bytes  # data with continuations blanked out: same length, same offsets
    buf: np.ndarray  # text as uint8
    starts: np.ndarray
    ends: np.ndarray
    kinds: np.ndarray
    ntokens: np.ndarray
    geometry: Geometry
    _rows: dict = field(default_factory=dict, compare=False, repr=False)  # of_kind's and names'

    @classmethod
    def read(cls, name: str) -> Document:
        """Read the file and its statements, within the memory limit (checked before the
        statement table is made, and before the geometry is parsed, or kept: the chunks
        keep it while it takes less than the limit allows, see :func:`read_statements`)."""
        data = _text_bytes(read_file(name), name)
        lines = check_scan(name, data)
        text = _blank_continuations(data)
        buf = np.frombuffer(text, np.uint8)
        bounds = chunk_bounds(text, get_threads())
        attributes = b"/" in text
        read = read_statements(buf, bounds, parse_budget(len(text), lines), attributes)
        doc = cls(name, data, text, buf, read.starts, read.ends, read.kinds, read.ntokens, read.geometry)
        check_statements(doc)
        if read.geometry is None:  # within the limit after all: read again, keeping everything
            read = read_statements(buf, bounds, 1 << 62, attributes)
            doc = cls(name, data, text, buf, read.starts, read.ends, read.kinds, read.ntokens, read.geometry)
        return doc

    def of_kind(self, *kinds) -> np.ndarray:
        """Statement numbers (S,) int64 of the given kinds, in file order (each list made
        once: read-only, shared by the callers)."""
        rows = self._rows.get(kinds)
        if rows is None:
            if len(kinds) == 1:
                rows = np.flatnonzero(self.kinds == kinds[0])
            else:
                rows = np.flatnonzero(np.isin(self.kinds, kinds))
            rows.flags.writeable = False
            self._rows[kinds] = rows
        return rows

    def line(self, s: int) -> int:
        """1-based line number where statement s starts."""
        return self.data.count(b"\n", 0, self.starts[s]) + 1

    def tokens(self, s: int) -> list[str]:
        """The keyword and tokens of statement s, split where the kernels split them."""
        return [decode(t) for t in split_tokens(self.text[self.starts[s]:self.ends[s]])]

    def argument(self, s: int) -> str:
        """Everything after the keyword of statement s, with single spaces."""
        return " ".join(self.tokens(s)[1:])

    def arguments(self, rows: np.ndarray) -> list[str]:
        """:meth:`argument` of each statement of rows; statements of the same text (a file may
        have millions of ``g`` lines naming a few groups) are split and decoded once."""
        text = self.text
        known: dict = {}
        names = []
        for first in range(0, len(rows), 1 << 16):  # Python ints for a chunk at a time
            part = rows[first:first + (1 << 16)]
            for a, b in zip(self.starts[part].tolist(), self.ends[part].tolist()):
                raw = text[a:b]
                name = known.get(raw)
                if name is None:
                    name = known[raw] = " ".join(decode(t) for t in split_tokens(raw)[1:])
                names.append(name)
        return names

    def names(self, *kinds) -> tuple:
        """:meth:`arguments` of the statements of the given kinds, in file order (worked out
        once: several parts of the loader ask for the ``usemtl`` names)."""
        key = ("names",) + kinds
        names = self._rows.get(key)
        if names is None:
            names = self._rows[key] = tuple(self.arguments(self.of_kind(*kinds)))
        return names

    def latest(self, kinds: tuple, statements: np.ndarray) -> np.ndarray:
        """(len(statements),) int64: for each of the statements (ascending), the position among
        the statements of the given kinds of the latest one above it, -1 where there is none
        (worked out once for the same array: read-only)."""
        key = ("latest", id(statements)) + kinds
        found = self._rows.get(key)
        if found is None or found[0] is not statements:  # kept with it: an id is never reused
            latest = np.searchsorted(self.of_kind(*kinds), statements) - 1
            latest.flags.writeable = False
            found = self._rows[key] = (statements, latest)
        return found[1]

    def counts_before(self, rows: np.ndarray) -> np.ndarray:
        """(len(rows), 3) int64: v, vt and vn statements above each of the statements rows."""
        kinds = (KIND_V, KIND_VT, KIND_VN)
        return np.stack([np.searchsorted(self.of_kind(k), rows) for k in kinds], axis=1)

    def count(self, kind: int) -> int:
        return len(self.of_kind(kind))


def _text_bytes(data: bytes, name: str) -> bytes:
    """The file's bytes without a UTF-8 byte order mark and with LF line breaks where it has
    only CR ones; binary or UTF-16/32 data fails."""
    for bom, encoding in _WIDE_BOMS.items():
        if data.startswith(bom):
            raise ObjError(name, 1, f"{encoding} text is not supported: save the file as UTF-8")
    if data.startswith(_UTF8_BOM):
        data = data[len(_UTF8_BOM):]
    if b"\n" not in data:  # old Mac files break lines with CR alone
        data = data.replace(b"\r", b"\n")
    nul = data.find(b"\0")
    if nul >= 0:
        line = data.count(b"\n", 0, nul) + 1
        raise ObjError(name, line, "NUL byte: binary data, not OBJ text (or UTF-16 without "
                                   "a byte order mark)")
    return data


def _blank_continuations(data: bytes) -> bytes:
    """data with every line continuation (a backslash before the line break) turned into
    spaces, so the two lines read as one and byte offsets stay those of the file."""
    if b"\\" not in data or (b"\\\n" not in data and b"\\\r\n" not in data):
        return data
    return data.replace(b"\\\r\n", b"   ").replace(b"\\\n", b"  ")


def decode(raw: bytes) -> str:
    """UTF-8 text; Latin-1 for the older files whose names are not UTF-8."""
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError:
        return raw.decode("latin-1")
