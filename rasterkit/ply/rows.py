"""The rows of one element, wherever they lie in the body: the layout of a row, how the rows
are found (all at once when every row has the same list lengths, else by a walk), and the
values of a property.

The body is read through a *source* (:class:`rasterkit.ply.binary.BinarySource` or
:class:`rasterkit.ply.ascii.TokenSource`), which counts in its own units (bytes or
tokens) and offers:

- ``size(dtype)``: the units of one value;
- ``units``: the units of the whole body (a row past it is not there);
- ``strided(at, n, stride, dtype, k)``: ``n`` values (``k`` per row when given) from unit
  ``at``, one row every ``stride`` units, as a read-only array;
- ``runs(starts, counts, dtype)``: the values of each row's run (``counts`` values, or one
  count for all, from unit ``starts[r]``), one run after another;
- ``first_counts(at, layout)``: the list counts (L,) int64 of the row at ``at``, or None
  when they do not make sense (the walk then says why);
- ``walk(at, n, layout, element)``: row starts (n,) and list counts (n, L), by a kernel, or a
  :class:`~rasterkit.ply.errors.PlyError` naming the row where the rows stop making sense;
- ``convert(values, prop, rows, offsets=None)``: the values as the property's result (for
  text, checked to be whole numbers in their type's range), or a ``PlyError`` naming the row
  (``offsets``: of a list's items, to find it);
- ``check_counts(counts, prop, rows)``: that a list's counts fit its count type;
- ``error(at, element, row, reason)``: the ``PlyError`` of a row, at unit ``at``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rasterkit.mesh.checks import sealed_empty
from rasterkit.ply.errors import PlyError, check_limit, count
from rasterkit.ply.header import Element, Property

__all__ = ["Layout", "Rows", "read_rows"]


@dataclass(frozen=True)
class Layout:
    """Where each property lies in a row of ``element``: ``segments`` (L + 1,) int64 units
    of scalars before list 0, between lists and after the last; ``lists`` the L list
    properties; ``places`` {property name: (segment, units into it)} of the scalars (the
    first of a name); ``smallest`` the units of a row whose lists are empty."""

    element: Element
    segments: np.ndarray
    lists: tuple
    places: dict
    count_sizes: np.ndarray
    item_sizes: np.ndarray
    smallest: int

    @classmethod
    def of(cls, element: Element, size) -> Layout:
        segments, lists, places = [0], [], {}
        for p in element.properties:
            if p.is_list:
                lists.append(p)
                segments.append(0)
            else:
                places.setdefault(p.name, (len(segments) - 1, segments[-1]))
                segments[-1] += size(p.dtype)
        count_sizes = np.array([size(p.count) for p in lists], np.int64)
        return cls(element, np.array(segments, np.int64), tuple(lists), places, count_sizes,
                   np.array([size(p.dtype) for p in lists], np.int64), int(sum(segments) + count_sizes.sum()))


class Rows:
    """The ``n`` rows of an element: either uniform (``counts`` (L,): every row's list
    lengths, rows ``stride`` units apart from ``start``) or walked (``starts`` (n,) and
    ``counts`` (n, L))."""

    def __init__(self, source, layout: Layout, start: int, counts: np.ndarray, starts: np.ndarray | None = None):
        self.source, self.layout, self.start = source, layout, start
        self.n = layout.element.count
        self.counts, self.starts = counts, starts
        if starts is None:
            self.stride = int(layout.smallest + (counts * layout.item_sizes).sum())

    @property
    def uniform(self) -> bool:
        return self.starts is None

    def list_counts(self, j: int) -> np.ndarray | int:
        """The counts of list j: (n,) int64, or one int when every row has as many."""
        return int(self.counts[j]) if self.uniform else self.counts[:, j]

    def segment_start(self, j: int):
        """Units from a row's start to segment j: an int for uniform rows (and for walked
        rows when no list comes before it), else (n,) int64."""
        lay = self.layout
        fixed = int(lay.segments[:j].sum() + lay.count_sizes[:j].sum())
        if self.uniform:
            return fixed + int((self.counts[:j] * lay.item_sizes[:j]).sum())
        if j == 0:
            return fixed
        return fixed + self.counts[:, :j] @ lay.item_sizes[:j]

    def row_start(self, row: int) -> int:
        """The first unit of row ``row``."""
        return self.start + row * self.stride if self.uniform else int(self.starts[row])

    def scalar(self, prop: Property) -> np.ndarray:
        """(n,) values of the scalar property ``prop`` (see the source's ``convert``)."""
        segment, into = self.layout.places[prop.name]
        offset = self.segment_start(segment)
        if self.uniform:
            values = self.source.strided(self.start + offset + into, self.n, self.stride, prop.dtype, None)
        else:
            values = self.source.runs(self.starts + offset + into, 1, prop.dtype)
        return self.source.convert(values, prop, self)

    def floats(self, props: tuple) -> np.ndarray:
        """(n, len(props)) float64 values of the float scalar properties ``props`` (each as
        :meth:`scalar` gives it); read as one strided view when they lie side by side in
        each row with one type (x, y, z almost always do), so that they are converted in
        one pass. Sealed (:func:`rasterkit.mesh.checks.sealed_empty`): a Mesh keeps them
        without a copy."""
        sealed, out = sealed_empty((self.n, len(props)), np.float64)
        places = [self.layout.places[p.name] for p in props]
        size = self.source.size(props[0].dtype)
        beside = all(p.dtype == props[0].dtype and p.dtype.kind == "f" for p in props) and \
            all(place == (places[0][0], places[0][1] + k * size) for k, place in enumerate(places))
        if beside and self.uniform:
            segment, into = places[0]
            view = self.source.strided(self.start + self.segment_start(segment) + into, self.n, self.stride,
                                       props[0].dtype, len(props))
            out[...] = self.source.convert(view, props[0], self)
        else:
            for k, p in enumerate(props):
                out[:, k] = self.scalar(p)
        return sealed

    def items(self, prop: Property) -> tuple[np.ndarray, np.ndarray]:
        """The items of the list property ``prop``: values in row order, (C,) or, when every
        row has as many (k), (n, k) (a binary file's: a strided view of its bytes, which the
        caller's conversion copies once); and offsets (n + 1,) int64 (row r's items are
        ``values.reshape(-1)[offsets[r]:offsets[r + 1]]``)."""
        j = self.layout.lists.index(prop)
        counts = self.list_counts(j)
        self.source.check_counts(np.atleast_1d(counts), prop, self)
        first = self.segment_start(j) + int(self.layout.segments[j] + self.layout.count_sizes[j])
        if self.uniform:
            offsets = np.arange(self.n + 1, dtype=np.int64) * counts
            values = self.source.strided(self.start + first, self.n, self.stride, prop.dtype, counts)
        else:
            offsets = np.zeros(self.n + 1, np.int64)
            np.cumsum(counts, out=offsets[1:])
            total = int(offsets[-1])
            check_limit(self.source.name, 16 * total, f"reading {count(total, 'item')} of list {prop.name!r}")
            values = self.source.runs(self.starts + first, counts, prop.dtype)
        return self.source.convert(values, prop, self, offsets), offsets

    def row_of_item(self, offsets: np.ndarray, k: int) -> int:
        return int(np.searchsorted(offsets, k, side="right") - 1)

    def position(self, prop: Property, row: int, k: int | None = None) -> int:
        """The unit where row ``row``'s value of the scalar ``prop`` is, or item ``k`` (an
        index into the row's items) of the list ``prop``."""
        base = self.row_start(row)
        if not prop.is_list:
            segment, into = self.layout.places[prop.name]
            return base + _at(self.segment_start(segment), row) + into
        j = self.layout.lists.index(prop)
        lay = self.layout
        first = base + _at(self.segment_start(j), row) + int(lay.segments[j] + lay.count_sizes[j])
        return first + (k or 0) * int(lay.item_sizes[j])

    def error(self, row: int, reason: str, prop: Property | None = None, k: int | None = None) -> PlyError:
        """The error of row ``row`` (at its value of ``prop``, item ``k``, when given)."""
        at = self.row_start(row) if prop is None else self.position(prop, row, k)
        return self.source.error(at, self.layout.element.name, row, reason)


def _at(offset, row: int) -> int:
    """A segment's offset into row ``row`` (``offset`` an int, or (n,) per row)."""
    return int(offset if np.ndim(offset) == 0 else offset[row])


def read_rows(source, element: Element, at: int) -> tuple[Rows, int]:
    """The rows of ``element`` from unit ``at`` of the body, and the unit after them."""
    layout = Layout.of(element, source.size)
    n = element.count
    left = source.units - at
    if layout.smallest and n > left // layout.smallest:
        unit = source.unit
        raise PlyError(source.name, source.where(at),
                       f"element {element.name!r} declares {count(n, 'row')} of at least "
                       f"{count(layout.smallest, unit)}: more than the {count(left, unit)} left in the file")
    if not layout.lists or n == 0:
        return Rows(source, layout, at, np.zeros(len(layout.lists), np.int64)), at + n * layout.smallest
    counts = source.first_counts(at, layout)
    if counts is not None:
        rows = Rows(source, layout, at, counts)
        if rows.stride * n <= left and _all_equal(source, rows, layout):
            return rows, at + rows.stride * n
    check_limit(source.name, (8 + 8 * len(layout.lists)) * n,
                f"walking the {count(n, 'row')} of element {element.name!r}")
    starts, counts, end = source.walk(at, n, layout, element)
    return Rows(source, layout, at, counts, starts), end


def _all_equal(source, rows: Rows, layout: Layout) -> bool:
    """Whether every row's list counts are those of row 0 (then each row is where a uniform
    layout puts it: row 0 is, and each row's counts place the next)."""
    for j, prop in enumerate(layout.lists):
        at = rows.start + rows.segment_start(j) + int(layout.segments[j])
        counts = source.strided(at, rows.n, rows.stride, prop.count, None)
        if not (counts == rows.counts[j]).all():
            return False
    return True
