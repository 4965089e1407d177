"""A binary body as a source of values for :mod:`rasterkit.ply.rows`: units are bytes, values
are read with NumPy in the file's byte order (``frombuffer`` views of the file's bytes, which
are copied only when a property is converted), and the rows of elements whose lists vary in
length are walked by :func:`rasterkit.ply.kernels.rows.walk_binary`.

The values of walked rows (at any byte offset) are copied as bytes, run by run
(:func:`rasterkit.ply.kernels.rows.copy_runs`), and viewed as their type.
"""

from __future__ import annotations

import numpy as np

from rasterkit.ply.errors import PlyError, count, row_place
from rasterkit.ply.kernels.rows import BAD_COUNT, PAST_END, SHORT, copy_runs, walk_binary

__all__ = ["BinarySource"]


class BinarySource:
    """The body ``data[body:]`` of the file ``name`` in byte order ``order`` (``<`` or ``>``).
    Positions are offsets in ``data`` (a message shows them so: a byte of the file)."""

    unit = "byte"

    def __init__(self, name: str, data: bytes, order: str):
        self.name, self.data, self.order = name, data, order
        self.buf = np.frombuffer(data, np.uint8)
        self.units = len(data)

    @staticmethod
    def size(dtype: np.dtype) -> int:
        return dtype.itemsize

    def where(self, at: int) -> str:
        return f"byte {int(at)}"

    def error(self, at: int, element: str, row: int, reason: str) -> PlyError:
        """The error of row ``row`` of ``element``, at byte ``at``."""
        return PlyError(self.name, row_place(element, row, at), reason)

    def _typed(self, dtype: np.dtype) -> np.dtype:
        return dtype.newbyteorder(self.order)

    def strided(self, at: int, n: int, stride: int, dtype: np.dtype, k: int | None) -> np.ndarray:
        dtype = self._typed(dtype)
        if k is None:
            return np.ndarray((n,), dtype, self.data, at, (stride,))
        return np.ndarray((n, k), dtype, self.data, at, (stride, dtype.itemsize))

    def runs(self, starts: np.ndarray, counts, dtype: np.dtype) -> np.ndarray:
        dtype = self._typed(dtype)
        lengths = np.broadcast_to(np.asarray(counts, np.int64) * dtype.itemsize, starts.shape)
        return copy_runs(self.buf, starts, np.ascontiguousarray(lengths)).view(dtype)

    def convert(self, values: np.ndarray, prop, rows, offsets=None) -> np.ndarray:
        """The values as they are: of the property's type, in the file's byte order (often a
        read-only view of the file's bytes; NumPy converts them where they are used)."""
        return values

    def first_counts(self, at: int, layout) -> np.ndarray | None:
        counts = []
        for j, prop in enumerate(layout.lists):
            at += int(layout.segments[j])
            size = prop.count.itemsize
            if at + size > self.units:
                return None
            c = int.from_bytes(self.data[at:at + size], "little" if self.order == "<" else "big",
                               signed=prop.count.kind == "i")
            if c < 0:
                return None
            counts.append(c)
            at += size + c * prop.dtype.itemsize
        return np.array(counts, np.int64)

    def check_counts(self, counts: np.ndarray, prop, rows) -> None:
        """Nothing to check: a binary count is of its type."""

    def walk(self, at: int, n: int, layout, element):
        lists = layout.lists
        starts, counts, status, row, j, stop, value = walk_binary(
            self.buf, at, n, layout.segments, layout.count_sizes,
            np.array([p.count.kind == "i" for p in lists]), layout.item_sizes, self.order == ">")
        if status == SHORT:
            raise PlyError(self.name, row_place(element.name, row, starts[row]),
                           f"the file ends inside the row (the header declares {count(element.count, 'row')})")
        if status in (BAD_COUNT, PAST_END):
            why = "is negative" if status == BAD_COUNT else "goes past the end of the file"
            raise PlyError(self.name, row_place(element.name, row, stop),
                           f"the count {int(value)} of list {lists[j].name!r} {why}")
        return starts, counts, stop

