"""The vector visibility and the path kernels against slow, obviously-correct NumPy references."""

from __future__ import annotations

import numpy as np
import pytest

from rasterkit import Camera, Mesh
from rasterkit.svg.paths import chain, pen_up_distance, route
from rasterkit.svg.visibility import DEPTH_EPS, MIN_PIECE, split_visible


def _random_scene(seed, n=40):
    """``n`` random triangles of 0.3-1.0 units in a box, any orientation, and a camera."""
    rng = np.random.default_rng(seed)
    centres = rng.uniform(-1.5, 1.5, (n, 3))
    corners = centres[:, None, :] + rng.normal(0, 0.45, (n, 3, 3))
    mesh = Mesh(corners.reshape(-1, 3), np.arange(3 * n).reshape(n, 3))
    camera = Camera.look_at((2.5, 1.8, 6.0), (0, 0, 0), width=320, height=240)
    return mesh, camera


def _hidden_by_brute_force(mesh, camera, a, b, x, y, z):
    """Whether raster point (x, y) at depth z on the edge a-b lies behind a front face."""
    p = camera.project(mesh.vertices)
    for f in mesh.faces:
        if a in f and b in f:
            continue
        (x0, y0, z0), (x1, y1, z1), (x2, y2, z2) = p[f]
        area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)
        if area >= 0:  # back faces (raster y points down) and degenerate ones hide nothing
            continue
        l1 = ((x - x0) * (y2 - y0) - (x2 - x0) * (y - y0)) / area
        l2 = ((x1 - x0) * (y - y0) - (x - x0) * (y1 - y0)) / area
        if l1 < 0 or l2 < 0 or l1 + l2 > 1:
            continue
        if z0 + l1 * (z1 - z0) + l2 * (z2 - z0) < z - DEPTH_EPS:
            return True
    return False


@pytest.mark.parametrize("seed", range(4))
def test_visibility_matches_a_brute_force_test_of_every_face(seed):
    mesh, camera = _random_scene(seed)
    p = camera.project(mesh.vertices)
    assert (camera.project_h(mesh.vertices)[:, 3] > 0).all()
    pieces = split_visible(camera.project_h(mesh.vertices), mesh.faces, mesh.edges, 320, 240)
    checked = wrong = 0
    for k in range(len(pieces.xy)):
        a, b = mesh.edges[pieces.edge[k]]
        x0, y0, x1, y1 = pieces.xy[k]
        length = np.hypot(x1 - x0, y1 - y0)
        if length < 0.2:
            continue
        (ax, ay, az), (bx, by, bz) = p[a], p[b]
        for u in np.linspace(0.1, 0.9, 5):  # points well inside the piece
            x, y = x0 + u * (x1 - x0), y0 + u * (y1 - y0)
            s = np.hypot(x - ax, y - ay) / np.hypot(bx - ax, by - ay)
            z = az + s * (bz - az)
            inside = 0 <= x <= 320 and 0 <= y <= 240
            if not inside:
                continue
            checked += 1
            wrong += _hidden_by_brute_force(mesh, camera, a, b, x, y, z) != pieces.hidden[k]
    assert checked > 200
    assert wrong <= checked // 200  # the id buffer's neighbourhood may miss a sliver: 0.5 % at most


def test_pieces_cover_each_edge_once_in_order():
    mesh, camera = _random_scene(7)
    pieces = split_visible(camera.project_h(mesh.vertices), mesh.faces, mesh.edges, 320, 240)
    p = camera.project(mesh.vertices)[:, :2]
    for e in np.unique(pieces.edge):
        mine = pieces.xy[pieces.edge == e]
        a, b = p[mesh.edges[e]]
        # consecutive pieces run from a towards b and meet, but for specks left out between them
        gaps = np.hypot(*(mine[1:, :2] - mine[:-1, 2:]).T)
        assert (gaps < MIN_PIECE).all()
        direction = (b - a) / np.hypot(*(b - a))
        assert (np.diff(mine.reshape(-1, 2) @ direction) >= -1e-9).all()
        hidden = pieces.hidden[pieces.edge == e]
        assert (hidden[1:] != hidden[:-1])[gaps == 0].all()
        if (0 <= p[mesh.edges[e]]).all() and (p[mesh.edges[e]] <= [320, 240]).all():
            total = np.hypot(*(mine[:, 2:] - mine[:, :2]).T).sum() + gaps.sum()
            start, end = np.hypot(*(mine[0, :2] - a)), np.hypot(*(mine[-1, 2:] - b))
            assert start < MIN_PIECE and end < MIN_PIECE
            assert total + start + end == pytest.approx(np.hypot(*(b - a)), abs=0.01)


def test_chain_and_route_keep_every_piece_and_shorten_the_travel():
    rng = np.random.default_rng(3)
    # a grid of unit segments, shuffled and randomly reversed: chains join them at shared keys
    nodes = np.arange(100).reshape(10, 10)
    pairs = [(nodes[i, j], nodes[i, j + 1]) for i in range(10) for j in range(9)]
    pairs += [(nodes[i, j], nodes[i + 1, j]) for i in range(9) for j in range(10)]
    pairs = np.array(pairs)[rng.permutation(len(pairs))]
    flip = rng.random(len(pairs)) < 0.5
    pairs[flip] = pairs[flip, ::-1]
    xy_of = np.stack([nodes % 10, nodes // 10], axis=-1).reshape(-1, 2) * 10.0
    xy = np.hstack([xy_of[pairs[:, 0]], xy_of[pairs[:, 1]]])
    lines = chain(xy, pairs.astype(np.int64), np.zeros(len(pairs), np.int64))
    ordered = route(lines, np.zeros(len(lines), np.int64))
    for polylines in (lines, ordered):
        segments = set()
        for q in range(len(polylines)):
            pts = polylines.points[polylines.offsets[q]:polylines.offsets[q + 1]]
            assert len(pts) >= 2
            for s, t in zip(pts[:-1], pts[1:]):
                segments.add(tuple(sorted([tuple(s), tuple(t)])))
        assert segments == {tuple(sorted([tuple(r[:2]), tuple(r[2:])])) for r in xy}
        assert len(polylines.points) - len(polylines) == len(pairs)  # no piece twice
    assert len(lines) < len(pairs) / 3
    assert pen_up_distance(*ordered.ends()) <= pen_up_distance(xy[:, :2], xy[:, 2:])
