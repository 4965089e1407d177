"""Pieces -> polylines -> plotter order: the drawing's paths (:mod:`rasterkit.svg.kernels.paths`).

Pieces join where they meet at a mesh vertex (an end that was neither clipped nor split),
and only pieces of one group (layer, object, class) join. The polylines of one layer and
object are then ordered by a greedy nearest-end route from the top-left corner, each drawn
from the end the pen reaches first.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rasterkit.svg.kernels import paths as _kernels

__all__ = ["Polylines", "chain", "pen_up_distance", "route"]


@dataclass(frozen=True)
class Polylines:
    """Polylines in drawing order.

    ``points`` (K, 2) float64 raster pixels; polyline q is ``points[offsets[q]:offsets[q +
    1]]``; ``group`` (Q,) int64 the group of its pieces.
    """

    points: np.ndarray
    offsets: np.ndarray
    group: np.ndarray

    def __len__(self) -> int:
        return len(self.offsets) - 1

    def ends(self) -> tuple[np.ndarray, np.ndarray]:
        """First and last points (Q, 2) of every polyline."""
        return self.points[self.offsets[:-1]], self.points[self.offsets[1:] - 1]


def pen_up_distance(starts: np.ndarray, ends: np.ndarray) -> float:
    """Pixels the pen travels lifted, drawing lines from ``starts`` to ``ends`` (Q, 2) in
    order, from the first line's start."""
    if len(starts) < 2:
        return 0.0
    return float(np.hypot(*(starts[1:] - ends[:-1]).T).sum())


def _nodes(keys: np.ndarray, group: np.ndarray):
    """Node per piece end: ends with the same vertex in the same group; CSR of the ends."""
    n_groups = int(group.max()) + 1 if len(group) else 1
    k = keys.reshape(-1)
    g = np.repeat(group, 2)
    joinable = k >= 0
    combined = np.where(joinable, k * n_groups + g, -1)
    node = np.full(len(k), -1, np.int64)
    values, inverse = np.unique(combined[joinable], return_inverse=True)
    node[joinable] = inverse
    counts = np.bincount(inverse, minlength=len(values))
    node_start = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    node_items = np.flatnonzero(joinable)[np.argsort(inverse, kind="stable")].astype(np.int64)
    return node.reshape(-1, 2), node_start, node_items


def chain(xy: np.ndarray, keys: np.ndarray, group: np.ndarray) -> Polylines:
    """Join the pieces ``xy`` (P, 4) (x0, y0, x1, y1) whose ends share a key (P, 2) (-1:
    none) within a group (P,) into polylines (in chaining order)."""
    if len(xy) == 0:
        return Polylines(np.zeros((0, 2)), np.zeros(1, np.int64), np.zeros(0, np.int64))
    node, node_start, node_items = _nodes(keys, group)
    order, reverse, offsets = _kernels.chain_pieces(node, node_start, node_items)
    oriented = xy[order].reshape(-1, 2, 2)
    flip = reverse.astype(bool)
    oriented[flip] = oriented[flip, ::-1]
    firsts = offsets[:-1]
    # each polyline: its first piece's start, then every piece's end
    n_points = len(order) + len(firsts)
    points = np.empty((n_points, 2))
    point_offsets = offsets + np.arange(len(offsets))
    starts_at = point_offsets[:-1]
    points[starts_at] = oriented[firsts, 0]
    body = np.ones(n_points, bool)
    body[starts_at] = False
    points[body] = oriented[:, 1]
    return Polylines(points, point_offsets.astype(np.int64), group[order[firsts]])


def route(lines: Polylines, route_group: np.ndarray) -> Polylines:
    """Reorder (and reverse) the polylines for a short pen-up route within each route group
    (``route_group`` (Q,) int64, per polyline); the groups follow each other in increasing
    order, and the pen carries on from where the last group ended."""
    starts, ends = lines.ends()
    sequence, flips = [], []
    pen = (0.0, 0.0)
    for g in np.unique(route_group):
        members = np.flatnonzero(route_group == g)
        order, reverse = _kernels.pen_route(np.ascontiguousarray(starts[members]),
                                            np.ascontiguousarray(ends[members]), pen[0], pen[1])
        chosen = members[order]
        sequence.append(chosen)
        flips.append(reverse.astype(bool))
        last = chosen[-1]
        pen = tuple(starts[last] if flips[-1][-1] else ends[last])
    if not sequence:
        return lines
    sequence, flips = np.concatenate(sequence), np.concatenate(flips)
    sizes = np.diff(lines.offsets)[sequence]
    offsets = np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64)
    # the index of every point in its new place: forwards or backwards through its old polyline
    local = np.arange(offsets[-1]) - np.repeat(offsets[:-1], sizes)
    old_start = np.repeat(lines.offsets[sequence], sizes)
    back = np.repeat(flips, sizes)
    index = np.where(back, old_start + np.repeat(sizes, sizes) - 1 - local, old_start + local)
    return Polylines(lines.points[index], offsets, lines.group[sequence])
