"""Pieces of lines into polylines, and polylines into a short pen-up route (plotter order).

Both are greedy, O(n) for the chaining and close to O(n) for the route on a drawing's
evenly spread lines: a pen plotter's drawing wants the pen lifted rarely and moved little
while up, not an optimal tour.
"""

from __future__ import annotations

import math

import numpy as np

from rasterkit.runtime.jit import kernel


@kernel(inline="always")
def _next_at(node, node_start, node_items, cursor, used):
    """An unused piece end at ``node`` (``piece * 2 + end``), or -1."""
    k = cursor[node]
    stop = node_start[node + 1]
    while k < stop:
        pe = node_items[k]
        if used[pe // 2] == 0:
            cursor[node] = k + 1
            return pe
        k += 1
    cursor[node] = k
    return -1


@kernel
def chain_pieces(node, node_start, node_items):
    """Join pieces that share an end into polylines.

    Parameters
    ----------
    node : (P, 2) int64
        For each end of each piece, its node (ends that coincide share a node), -1 for an
        end that joins nothing.
    node_start : (U + 1,) int64, node_items : (2P',) int64
        The ends at node u are ``node_items[node_start[u]:node_start[u + 1]]``, each
        ``piece * 2 + end``.

    Returns
    -------
    order : (P,) int64
        The pieces, polyline after polyline.
    reverse : (P,) uint8
        1 where a piece runs from its end 1 to its end 0 in its polyline.
    offsets : (Q + 1,) int64
        Polyline q is ``order[offsets[q]:offsets[q + 1]]``.
    """
    n = node.shape[0]
    used = np.zeros(n, np.uint8)
    cursor = node_start[:-1].copy()
    order = np.empty(n, np.int64)
    reverse = np.zeros(n, np.uint8)
    offsets = np.empty(n + 1, np.int64)
    back = np.empty(n, np.int64)
    back_rev = np.empty(n, np.uint8)
    m = 0
    q = 0
    offsets[0] = 0
    for i in range(n):
        if used[i]:
            continue
        used[i] = 1
        nb = 0
        cur = node[i, 0]
        while cur >= 0:  # backwards from the start of piece i
            pe = _next_at(cur, node_start, node_items, cursor, used)
            if pe < 0:
                break
            p, e = pe // 2, pe % 2
            used[p] = 1
            back[nb] = p
            back_rev[nb] = 1 if e == 0 else 0  # its end e meets the chain's start
            nb += 1
            cur = node[p, 1 - e]
        for j in range(nb - 1, -1, -1):
            order[m] = back[j]
            reverse[m] = back_rev[j]
            m += 1
        order[m] = i
        reverse[m] = 0
        m += 1
        cur = node[i, 1]
        while cur >= 0:  # forwards from the end of piece i
            pe = _next_at(cur, node_start, node_items, cursor, used)
            if pe < 0:
                break
            p, e = pe // 2, pe % 2
            used[p] = 1
            order[m] = p
            reverse[m] = 1 if e == 1 else 0
            m += 1
            cur = node[p, 1 - e]
        q += 1
        offsets[q] = m
    return order, reverse, offsets[: q + 1].copy()


@kernel(inline="always")
def _cell(x, y, x0, y0, size, nx, ny):
    cx = min(max(int((x - x0) / size), 0), nx - 1)
    cy = min(max(int((y - y0) / size), 0), ny - 1)
    return cx, cy


@kernel
def pen_route(starts, ends, start_x, start_y):
    """A greedy route through polylines: from the pen's position, the nearest end of a
    polyline not drawn yet, drawn from that end (reversed when it is its last point).

    ``starts``, ``ends`` (Q, 2) float64: first and last points. Returns ``(order (Q,)
    int64, reverse (Q,) uint8)``. Ends are found in a uniform grid, searched in growing
    rings of cells around the pen.
    """
    q = starts.shape[0]
    order = np.empty(q, np.int64)
    reverse = np.zeros(q, np.uint8)
    if q == 0:
        return order, reverse
    x0 = min(starts[:, 0].min(), ends[:, 0].min())
    y0 = min(starts[:, 1].min(), ends[:, 1].min())
    x1 = max(starts[:, 0].max(), ends[:, 0].max())
    y1 = max(starts[:, 1].max(), ends[:, 1].max())
    span = max(x1 - x0, y1 - y0, 1e-9)
    side = max(1, min(1024, int(math.sqrt(q / 2.0)) + 1))
    size = span / side * 1.000001
    nx = max(1, min(side, int((x1 - x0) / size) + 1))
    ny = max(1, min(side, int((y1 - y0) / size) + 1))
    counts = np.zeros(nx * ny + 1, np.int64)
    for k in range(2 * q):
        p = starts[k // 2] if k % 2 == 0 else ends[k // 2]
        cx, cy = _cell(p[0], p[1], x0, y0, size, nx, ny)
        counts[cy * nx + cx + 1] += 1
    for c in range(nx * ny):
        counts[c + 1] += counts[c]
    fill = counts[:-1].copy()
    items = np.empty(2 * q, np.int64)
    for k in range(2 * q):
        p = starts[k // 2] if k % 2 == 0 else ends[k // 2]
        cx, cy = _cell(p[0], p[1], x0, y0, size, nx, ny)
        items[fill[cy * nx + cx]] = k
        fill[cy * nx + cx] += 1
    done = np.zeros(q, np.uint8)
    px, py = start_x, start_y
    for step in range(q):
        cx, cy = _cell(px, py, x0, y0, size, nx, ny)
        best, best_d = -1, np.inf
        r = 0
        while True:
            for gy in range(cy - r, cy + r + 1):
                if gy < 0 or gy >= ny:
                    continue
                ring_row = gy == cy - r or gy == cy + r
                gx = cx - r
                while gx <= cx + r:
                    if 0 <= gx < nx:
                        c = gy * nx + gx
                        for j in range(counts[c], counts[c + 1]):
                            k = items[j]
                            if done[k // 2]:
                                continue
                            p = starts[k // 2] if k % 2 == 0 else ends[k // 2]
                            d = (p[0] - px) ** 2 + (p[1] - py) ** 2
                            if d < best_d:
                                best_d, best = d, k
                    gx += 1 if ring_row or r == 0 else 2 * r
            # cells beyond ring r are at least r * size away from the pen's cell
            if best >= 0 and best_d <= (r * size) ** 2:
                break
            if r > nx + ny:
                break
            r += 1
        line = best // 2
        done[line] = 1
        order[step] = line
        reverse[step] = best % 2
        p = starts[line] if best % 2 else ends[line]
        px, py = p[0], p[1]
    return order, reverse
