"""An ASCII body as a source of values for :mod:`rasterkit.ply.rows`: every token of the body
parsed once into one float64 array (:mod:`rasterkit.ply.kernels.tokens`), the rows of an
element then read from it as strided views (every row the same length) or copied run by run (rows
walked by :func:`rasterkit.ply.kernels.rows.walk_tokens`).

Units are tokens. Rows are found by counting tokens, not lines (as a stream of values, the
way most readers take ASCII PLY), so a row split over two lines reads the same; a line's
number is worked out only for a message. Values of integer properties must be whole numbers
within their type's range (``uchar`` 0 to 255...); float properties take any number
(``nan``, ``inf``, ``1e400`` as infinity too), rounded to their declared type (``float``
to float32: the numbers a binary file of the same model holds).
"""

from __future__ import annotations

import re

import numpy as np

from rasterkit.ply.errors import PlyError, check_limit, count, row_place
from rasterkit.ply.kernels.rows import BAD_COUNT, PAST_END, SHORT, copy_runs, walk_tokens
from rasterkit.ply.kernels.tokens import copy_texts, count_tokens, locate_tokens, parse_tokens

__all__ = ["TokenSource"]

#: Bytes per token while the body is parsed (its value and status) and read into rows.
BYTES_PER_TOKEN = 9

#: Tokens the kernel cannot read exactly are read again as bytes strings of at most this
#: many bytes (longer ones one by one).
MAX_TOKEN = 64

_MSVC = re.compile(rb"([+-]?)[0-9]+\.#(IND|QNAN|SNAN|INF)[0-9]*", re.IGNORECASE)


class TokenSource:
    """The tokens of ``data[body:]``, the body of the file ``name`` whose header has
    ``header_lines`` lines."""

    unit = "value"

    def __init__(self, name: str, data: bytes, body: int, header_lines: int):
        self.name, self.data, self.body, self.header_lines = name, data, body, header_lines
        self.buf = np.frombuffer(data, np.uint8)
        n = count_tokens(self.buf, body)
        check_limit(name, BYTES_PER_TOKEN * n, f"reading its {count(n, 'value')}")
        self.values, status = parse_tokens(self.buf, body, n)
        self.units = n
        flagged = np.flatnonzero(status)
        if len(flagged):
            self._read_again(flagged)

    def _read_again(self, flagged: np.ndarray) -> None:
        """Values of the tokens the kernel flagged, read exactly by NumPy's conversion of
        bytes strings (``nan``, ``inf``, ``infinity`` in any case, with a sign), the few it
        cannot take by :func:`_number` (MSVC's ``1.#IND``...); the first that is no number
        is an error naming its line."""
        starts, ends, lines = locate_tokens(self.buf, self.body, flagged)
        lengths = ends - starts
        width = int(min(lengths.max(), MAX_TOKEN))
        check_limit(self.name, (2 * width + 24) * len(flagged), f"reading its {count(len(flagged), 'unusual number')}")
        texts = copy_texts(self.buf, starts, ends, width)
        # read one by one: what NumPy (Python's float) takes, or cuts at a NUL byte, but is
        # no number here (digits with "_", digits of other scripts, a NUL inside), MSVC's "#"
        inside = np.arange(width) < lengths[:, None]
        odd = (lengths > width) | ((texts == ord("_")) | (texts == ord("#")) | (texts >= 128)
                                   | ((texts == 0) & inside)).any(axis=1)
        texts = texts.view(f"S{width}").ravel()
        values = np.full(len(flagged), np.nan)
        bad = len(flagged)
        plain = np.flatnonzero(~odd)
        try:
            values[plain] = texts[plain].astype(np.float64)
        except ValueError:
            bad = int(plain[_first_bad(texts[plain])])
        for k in np.flatnonzero(odd[:bad]):
            value = _number(self.data[starts[k]:ends[k]])
            if value is None:
                bad = int(k)
                break
            values[k] = value
        if bad < len(flagged):
            shown = self.data[starts[bad]:ends[bad]][:40].decode("utf-8", "backslashreplace")
            raise PlyError(self.name, self.header_lines + 1 + int(lines[bad]), f"{shown!r} is not a number")
        self.values[flagged] = values

    @staticmethod
    def size(dtype: np.dtype) -> int:
        return 1

    def line(self, token: int) -> int:
        """The 1-based line of the file where token ``token`` is (the last line when it is
        past the end)."""
        if token >= self.units:
            return self.header_lines + 1 + self.data.count(b"\n", self.body)
        return self.header_lines + 1 + int(locate_tokens(self.buf, self.body, np.array([token]))[2][0])

    def where(self, at: int) -> int:
        return self.line(at)

    def error(self, at: int, element: str, row: int, reason: str) -> PlyError:
        """The error of row ``row`` of ``element``, at token ``at``."""
        return PlyError(self.name, self.line(at), f"{row_place(element, row)}: {reason}")

    def strided(self, at: int, n: int, stride: int, dtype, k: int | None) -> np.ndarray:
        if k is None:
            return self.values[at:at + n * stride:stride]
        return np.lib.stride_tricks.as_strided(self.values[at:], (n, k), (8 * stride, 8), writeable=False)

    def runs(self, starts: np.ndarray, counts, dtype) -> np.ndarray:
        lengths = np.broadcast_to(np.asarray(counts, np.int64), starts.shape)
        return copy_runs(self.values, starts, np.ascontiguousarray(lengths))

    def convert(self, values: np.ndarray, prop, rows, offsets=None) -> np.ndarray:
        """Values of a ``float`` property rounded to float32 (as the file declares them: the
        same numbers as a binary file's), of a ``double`` one as parsed; int64 of an integer
        one, each checked to be a whole number in its type's range (else the error names its
        row and line)."""
        if prop.dtype == np.float32:
            with np.errstate(over="ignore"):  # beyond float32: infinite, as a binary file would hold it
                return values.astype(np.float32)
        if prop.dtype.kind == "f":
            return values
        info = np.iinfo(prop.dtype)
        with np.errstate(invalid="ignore"):
            good = (values >= info.min) & (values <= info.max) & (values == np.floor(values))
        if not good.all():
            k = int(np.argmin(good.reshape(-1)))
            row = k if offsets is None else rows.row_of_item(offsets, k)
            item = None if offsets is None else k - int(offsets[row])
            raise rows.error(row, f"property {prop.name!r} is {_shown(values.reshape(-1)[k])}, not a whole "
                                  f"number from {info.min} to {info.max} ({prop.type_name})", prop, item)
        return values.astype(np.int64).reshape(values.shape)

    def first_counts(self, at: int, layout) -> np.ndarray | None:
        counts = []
        for j in range(len(layout.lists)):
            at += int(layout.segments[j])
            if at >= self.units:
                return None
            c = float(self.values[at])
            if not (c >= 0 and c.is_integer() and c < self.units):
                return None
            counts.append(int(c))
            at += 1 + int(c)
        return np.array(counts, np.int64)

    def check_counts(self, counts: np.ndarray, prop, rows) -> None:
        """Counts of list ``prop`` must fit its count type (``uchar``: at most 255)."""
        info = np.iinfo(prop.count)
        if len(counts) and counts.max() > info.max:
            row = int(np.argmax(counts > info.max))
            raise rows.error(row, f"the count {int(counts[row])} of list {prop.name!r} is beyond its type "
                                  f"{prop.count_name}", prop)

    def walk(self, at: int, n: int, layout, element):
        starts, counts, status, row, j, stop, _ = walk_tokens(self.values, at, n, layout.segments)
        if status == SHORT:
            raise PlyError(self.name, self.line(self.units),
                           f"{row_place(element.name, row)}: the file ends inside the row (the header declares "
                           f"{count(element.count, 'row')})")
        if status in (BAD_COUNT, PAST_END):
            value = _shown(self.values[stop])
            why = "is no whole number >= 0" if status == BAD_COUNT else "goes past the end of the file"
            raise PlyError(self.name, self.line(stop),
                           f"{row_place(element.name, row)}: the count {value} of list {layout.lists[j].name!r} {why}")
        return starts, counts, stop


def _shown(value: float) -> str:
    """A value as the file may have written it: ``3``, ``4.5``, ``nan``."""
    value = float(value)
    return str(int(value)) if value.is_integer() else repr(value)


def _first_bad(texts: np.ndarray) -> int:
    """The first of ``texts`` (bytes strings, one of them no number) that NumPy cannot read,
    by halving: a few conversions, not one per text."""
    low, high = 0, len(texts)  # the first bad one is in [low, high)
    while high - low > 1:
        middle = (low + high) // 2
        try:
            texts[low:middle].astype(np.float64)
            low = middle
        except ValueError:
            high = middle
    return low


def _number(token: bytes) -> float | None:
    """The value of one token, or None: Python's ``float`` on ASCII tokens without ``_``, and
    the NaN and infinity that MSVC's ``printf`` writes (``1.#IND``, ``-1.#INF``, ``1.#QNAN``)."""
    if token.isascii() and b"_" not in token:
        try:
            return float(token)
        except ValueError:
            pass
    match = _MSVC.fullmatch(token)
    if match is None:
        return None
    return np.nan if match[2].upper() != b"INF" else -np.inf if match[1] == b"-" else np.inf
