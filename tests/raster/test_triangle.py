"""Tests of the triangle pipeline: clip -> cull -> bin -> rasterize -> shade.

Expectations come from hand-made arrays, the slow NumPy reference in support/reference_raster.py,
an independent ray-plane computation (perspective-correct colours) and invariants
(a tiled rectangle is covered exactly once).
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from rasterkit.runtime import threads as _threads
from rasterkit.raster.kernels.normals import face_normals, vertex_normals
from rasterkit.raster.kernels.shade import lambert
from rasterkit.raster.kernels.triangle import triangle_pixels
from rasterkit.raster.triangles import TriangleStats, rasterize_triangles
from support.reference_raster import (
    clip_near,
    coverage,
    divide,
    fan,
    reference_raster,
    signed_area2,
    snap,
)

# ---------------------------------------------------------------------------- helpers


def buffers(width, height, channels=3):
    """Cleared colour (black), depth (+inf) and id (-1) buffers."""
    color = np.zeros((height, width, channels), np.uint8)
    depth = np.full((height, width), np.inf, np.float32)
    ids = np.full((height, width), -1, np.int32)
    return color, depth, ids


def screen_to_clip(triangles):
    """(K, 3, 3) raster-space triangles -> clip (3K, 4) with w = 1 and faces (K, 3)."""
    triangles = np.asarray(triangles, dtype=np.float64).reshape(-1, 3, 3)
    clip = np.ones((triangles.shape[0] * 3, 4))
    clip[:, :3] = triangles.reshape(-1, 3)
    faces = np.arange(clip.shape[0], dtype=np.int64).reshape(-1, 3)
    return clip, faces


def draw_screen(triangles, width, height, *, cull="none", threads=None, face_colors=None):
    """Draw raster-space triangles with flat colours; returns (color, depth, ids, stats)."""
    clip, faces = screen_to_clip(triangles)
    if face_colors is None:
        face_colors = np.full((faces.shape[0], 3), 200.0, np.float32)
    color, depth, ids = buffers(width, height)
    stats = rasterize_triangles(
        color, depth, clip, faces, face_colors=face_colors, ids=ids, cull=cull, threads=threads
    )
    return color, depth, ids, stats


def draw_screen_clip(clip, width, height, cull="none"):
    """Draw homogeneous vertices, three per face, with flat colours; (color, depth, ids, stats)."""
    faces = np.arange(clip.shape[0], dtype=np.int64).reshape(-1, 3)
    color, depth, ids = buffers(width, height)
    stats = rasterize_triangles(
        color, depth, clip, faces, face_colors=np.ones((faces.shape[0], 3), np.float32), ids=ids, cull=cull
    )
    return color, depth, ids, stats


def camera_matrix(width, height, focal, near, far):
    """World (= camera) -> homogeneous raster, built by hand.

    The camera sits at the origin looking down -Z with +Y up. ``x = W/2 + f X / -Z``,
    ``y = H/2 - f Y / -Z`` (raster y down), ``w = -Z``, and ``zh = a (-Z) + b`` is 0 at
    ``-Z = near`` and ``w`` at ``-Z = far``.
    """
    a = far / (far - near)
    b = -near * far / (far - near)
    return np.array(
        [
            [focal, 0.0, -width / 2, 0.0],
            [0.0, -focal, -height / 2, 0.0],
            [0.0, 0.0, -a, b],
            [0.0, 0.0, -1.0, 0.0],
        ]
    )


def project(matrix, points):
    """(N, 3) points -> (N, 4) homogeneous raster coordinates, C-contiguous float64."""
    points = np.asarray(points, dtype=np.float64)
    homogeneous = np.hstack([points, np.ones((points.shape[0], 1))])
    return np.ascontiguousarray(homogeneous @ matrix.T)


def half_open_rectangle(x0, y0, x1, y1, width, height):
    """Pixels whose centre lies in [x0, x1) x [y0, y1): what a tiled rectangle must cover."""
    cx, cy = np.meshgrid(np.arange(width) + 0.5, np.arange(height) + 0.5)
    return (cx >= x0) & (cx < x1) & (cy >= y0) & (cy < y1)


# ---------------------------------------------------------------------------- fill rule


@st.composite
def rectangle_triangulations(draw):
    """A rectangle tiled by triangles whose vertices lie on the half-pixel grid.

    Grid lines at random half-integers (pixel edges and centres, to force ties), a random
    diagonal per cell, some triangles split at an interior grid point, random windings.
    Returns (rectangle (x0, y0, x1, y1), triangles (K, 3, 2)).
    """
    xs = sorted(draw(st.sets(st.integers(0, 40), min_size=2, max_size=6)))
    ys = sorted(draw(st.sets(st.integers(0, 40), min_size=2, max_size=6)))
    xs, ys = np.array(xs) / 2, np.array(ys) / 2
    triangles = []
    for i in range(len(xs) - 1):
        for j in range(len(ys) - 1):
            a, b = (xs[i], ys[j]), (xs[i + 1], ys[j])
            c, d = (xs[i + 1], ys[j + 1]), (xs[i], ys[j + 1])
            if draw(st.booleans()):
                triangles += [(a, b, c), (a, c, d)]
            else:
                triangles += [(a, b, d), (b, c, d)]
    result = []
    for tri in triangles:
        tri = np.array(tri)
        weights = np.array(draw(st.tuples(*[st.integers(1, 4)] * 3)), dtype=float)
        point = np.round(2 * weights @ tri / weights.sum()) / 2
        split = [np.array([tri[k], tri[(k + 1) % 3], point]) for k in range(3)]
        if draw(st.booleans()) and all(signed_area2(s) * signed_area2(tri) > 0 for s in split):
            pieces = split
        else:
            pieces = [tri]
        result += [p[::-1] if draw(st.booleans()) else p for p in pieces]
    return (xs[0], ys[0], xs[-1], ys[-1]), np.array(result)


@settings(deadline=None, max_examples=40)
@given(rectangle_triangulations())
def test_tiled_rectangle_is_covered_exactly_once(case):
    (x0, y0, x1, y1), triangles = case
    width = height = 24
    expected = half_open_rectangle(x0, y0, x1, y1, width, height)
    screen = np.concatenate([triangles, np.full(triangles.shape[:2] + (1,), 0.5)], axis=2)
    _, _, ids, stats = draw_screen(screen, width, height)
    # Every expected centre is drawn, nothing else, and no centre was covered twice.
    np.testing.assert_array_equal(ids >= 0, expected)
    assert stats.fragments == expected.sum()
    pixels = np.concatenate([triangle_pixels(*t.ravel()) for t in triangles])
    assert len(pixels) == expected.sum()
    counts = np.zeros((height, width), int)
    np.add.at(counts, (pixels[:, 1], pixels[:, 0]), 1)
    np.testing.assert_array_equal(counts, expected)


@settings(deadline=None, max_examples=40)
@given(
    st.tuples(*[st.integers(0, 32)] * 4),
    st.tuples(*[st.integers(-12, 44)] * 4),
)
def test_shared_edge_is_drawn_once_without_gap(edge, apexes):
    """Triangles (a, b, c) and (c, b, d) on both sides of edge bc: centres on bc once."""
    b, c = np.array(edge[:2]) / 2, np.array(edge[2:]) / 2
    a, d = np.array(apexes[:2]) / 2, np.array(apexes[2:]) / 2
    side_a = signed_area2(np.array([b, c, a]))
    side_d = signed_area2(np.array([b, c, d]))
    assume(side_a * side_d < 0)
    width = height = 20
    first = coverage(np.array([a, b, c]), width, height)
    second = coverage(np.array([c, b, d]), width, height)
    _, _, ids, stats = draw_screen(
        np.array([[(*a, 0.5), (*b, 0.5), (*c, 0.5)], [(*c, 0.5), (*b, 0.5), (*d, 0.5)]]), width, height
    )
    assert not (first & second).any()
    assert stats.fragments == first.sum() + second.sum()
    cx, cy = np.meshgrid(np.arange(width) + 0.5, np.arange(height) + 0.5)
    on_edge = (c[0] - b[0]) * (cy - b[1]) - (c[1] - b[1]) * (cx - b[0]) == 0
    between = ((cx - b[0]) * (cx - c[0]) + (cy - b[1]) * (cy - c[1])) < 0
    np.testing.assert_array_equal((first | second)[on_edge & between], True)
    np.testing.assert_array_equal(ids >= 0, first | second)


def test_triangle_pixels_tiny_example():
    # Top and left edges run through pixel centres (drawn); the diagonal does too (not drawn).
    pixels = triangle_pixels(0.5, 0.5, 5.5, 0.5, 0.5, 5.5)
    image = np.zeros((6, 7), int)
    image[pixels[:, 1], pixels[:, 0]] = 1
    expected = np.array(
        [
            [1, 1, 1, 1, 1, 0, 0],
            [1, 1, 1, 1, 0, 0, 0],
            [1, 1, 1, 0, 0, 0, 0],
            [1, 1, 0, 0, 0, 0, 0],
            [1, 0, 0, 0, 0, 0, 0],
            [0, 0, 0, 0, 0, 0, 0],
        ]
    )
    np.testing.assert_array_equal(image, expected)
    # Row by row, left to right; either winding gives the same pixels.
    np.testing.assert_array_equal(pixels, np.argwhere(expected)[:, ::-1])
    np.testing.assert_array_equal(triangle_pixels(0.5, 5.5, 5.5, 0.5, 0.5, 0.5), pixels)
    assert triangle_pixels(0.0, 0.0, 4.0, 4.0, 8.0, 8.0).shape == (0, 2)


@settings(deadline=None, max_examples=40)
@given(st.lists(st.integers(-3 * 256, 23 * 256), min_size=6, max_size=6))
def test_triangle_pixels_match_reference(coords):
    x0, y0, x1, y1, x2, y2 = np.array(coords) / 256
    pixels = triangle_pixels(x0, y0, x1, y1, x2, y2)
    expected = coverage(np.array([[x0, y0], [x1, y1], [x2, y2]]) + 3, 26, 26)
    image = np.zeros((26, 26), bool)
    image[pixels[:, 1] + 3, pixels[:, 0] + 3] = True
    assert len(pixels) == expected.sum()
    np.testing.assert_array_equal(image, expected)


# ---------------------------------------------------------------------------- reference


@st.composite
def small_scenes(draw, sloped, width, height):
    """Up to 6 triangles on a 1/256 grid around a width x height image, depths in (0, 1)."""
    k = draw(st.integers(1, 6))
    xy = (
        np.array(draw(st.lists(st.integers(-4 * 256, (width + 4) * 256), min_size=6 * k, max_size=6 * k)))
        / 256
    )
    xy = xy.reshape(k, 3, 2) * [1.0, height / width]
    if sloped:
        z = np.array(draw(st.lists(st.integers(1, 255), min_size=3 * k, max_size=3 * k))).reshape(k, 3) / 256
    else:
        z = np.array(draw(st.permutations(range(1, 64)))[:k])[:, None].repeat(3, axis=1) / 64
    return np.concatenate([xy, z[..., None]], axis=2)


# 20 x 14: every triangle takes the narrow (per-pixel coverage) path of the rasterizer;
# 150 x 24: most take the span path (bounding boxes wider than BLOCK).
@pytest.mark.parametrize("size", [(20, 14), (150, 24)])
@pytest.mark.parametrize("sloped", [False, True])
@settings(deadline=None, max_examples=25)
@given(data=st.data())
def test_matches_reference_rasterizer(size, sloped, data):
    width, height = size
    scene = data.draw(small_scenes(sloped, width, height))
    cull = data.draw(st.sampled_from(["none", "back", "front"]))
    _, depth, ids, stats = draw_screen(scene, width, height, cull=cull)
    count, ref_ids, ref_depth, margin = reference_raster(scene, width, height, cull=cull)
    assert stats.fragments == count.sum()
    np.testing.assert_array_equal(ids >= 0, count > 0)
    clear = margin > 1e-5
    np.testing.assert_array_equal(ids[clear], ref_ids[clear])
    drawn = count > 0
    np.testing.assert_allclose(depth[drawn], ref_depth[drawn], rtol=0, atol=1e-6)
    assert np.isinf(depth[~drawn]).all()


def test_depth_of_a_height_field_matches_reference():
    """A triangulated grid with random heights: one triangle per pixel, depth to 1e-6."""
    rng = np.random.default_rng(7)
    width, height = 40, 30
    gx, gy = np.meshgrid(np.linspace(-2.5, 42.5, 10), np.linspace(-1.25, 31.25, 8))
    gz = rng.uniform(0.05, 0.95, gx.shape)
    points = np.stack([snap(gx), snap(gy), gz], axis=-1)
    triangles = []
    for i in range(gx.shape[1] - 1):
        for j in range(gx.shape[0] - 1):
            a, b, c, d = points[j, i], points[j, i + 1], points[j + 1, i + 1], points[j + 1, i]
            triangles += [(a, c, b), (a, d, c)]
    triangles = np.array(triangles)
    _, depth, ids, stats = draw_screen(triangles, width, height)
    count, ref_ids, ref_depth, _ = reference_raster(triangles, width, height)
    assert (count == 1).all() and stats.fragments == width * height
    np.testing.assert_array_equal(ids, ref_ids)
    np.testing.assert_allclose(depth, ref_depth, rtol=0, atol=1e-6)


def test_depth_test_respects_existing_buffers():
    color, depth, ids = buffers(8, 4)
    depth[:, :4] = 0.25  # something nearer already drawn on the left half
    ids[:, :4] = 99
    clip, faces = screen_to_clip([[(-1, -1, 0.5), (-1, 20, 0.5), (20, -1, 0.5)]])  # front-facing
    rasterize_triangles(color, depth, clip, faces, face_colors=np.array([[10, 20, 30]], np.float32), ids=ids)
    assert (ids[:, :4] == 99).all() and (depth[:, :4] == 0.25).all() and (color[:, :4] == 0).all()
    assert (ids[:, 4:] == 0).all() and (depth[:, 4:] == 0.5).all() and (color[:, 4:] == [10, 20, 30]).all()


# ---------------------------------------------------------------------------- clipping


def camera_scene_reference(matrix, points, width, height):
    """Reference ids of one face after clipping its homogeneous vertices at the near plane."""
    polygon = clip_near(project(matrix, points))
    if len(polygon) < 3:
        return np.full((height, width), -1)
    _, ids, _, _ = reference_raster(divide(fan(polygon)), width, height)
    return np.where(ids >= 0, 0, -1)


@pytest.mark.parametrize(
    "points",
    [
        [(-1.0, -1.0, -3.0), (1.5, -0.5, -3.0), (0.2, 1.0, 2.0)],  # one vertex behind the eye
        [(-0.5, -0.5, -1.5), (3.0, -1.0, 2.0), (0.0, 3.0, 1.0)],  # two vertices behind
        [(-0.3, -0.2, -0.5), (0.9, -0.4, -5.0), (0.1, 0.8, -0.05)],  # two between eye and near
    ],
)
def test_triangle_crossing_near_plane_draws_its_visible_part(points):
    width, height = 32, 24
    matrix = camera_matrix(width, height, focal=20.0, near=1.0, far=50.0)
    clip = project(matrix, points)
    faces = np.array([[0, 1, 2]], np.int64)
    color, depth, ids = buffers(width, height)
    stats = rasterize_triangles(
        color, depth, clip, faces, face_colors=np.ones((1, 3), np.float32), ids=ids, cull="none"
    )
    expected = camera_scene_reference(matrix, points, width, height)
    assert (expected >= 0).sum() > 20  # the cases do show something
    np.testing.assert_array_equal(ids, expected)
    assert stats.clipped == 1 and stats.drawn == 1
    assert stats.triangles == len(clip_near(clip)) - 2  # one triangle per fan piece
    assert (depth[ids >= 0] >= 0).all() and (depth[ids >= 0] <= 1).all()


def test_nothing_behind_the_eye_wraps_around():
    """Wholly behind the eye: divided naively it would land on screen; it must not draw."""
    width, height = 32, 24
    matrix = camera_matrix(width, height, focal=20.0, near=1.0, far=50.0)
    points = [(-1.0, -1.0, 3.0), (1.0, -1.0, 3.0), (0.0, 1.0, 3.0)]
    clip = project(matrix, points)
    naive = divide(clip)[:, :2]
    assert ((naive >= 0) & (naive < [width, height])).all()
    _, _, ids, stats = draw_screen_clip(clip, width, height)
    assert (ids == -1).all() and stats.outside == 1 and stats.drawn == 0


def test_far_plane_cuts_and_rejects():
    width, height = 16, 16
    # Orthographic-like (w = 1): z = zh is the depth; the far plane is z = 1.
    crossing = [(2.0, 2.0, 0.5), (14.0, 2.0, 1.5), (2.0, 14.0, 0.5)]
    beyond = [(2.0, 2.0, 1.2), (14.0, 2.0, 1.5), (2.0, 14.0, 1.1)]
    _, depth, ids, stats = draw_screen(np.array([crossing, beyond]), width, height)
    assert stats.clipped == 1 and stats.outside == 1
    polygon = np.array([[2.0, 2.0, 0.5], [8.0, 2.0, 1.0], [8.0, 8.0, 1.0], [2.0, 14.0, 0.5]])
    _, ref_ids, ref_depth, _ = reference_raster(fan(polygon), width, height)
    np.testing.assert_array_equal(ids >= 0, ref_ids >= 0)
    np.testing.assert_allclose(depth[ids >= 0], ref_depth[ids >= 0], atol=1e-6)


# ---------------------------------------------------------------------------- robustness


def test_degenerate_triangles_draw_nothing():
    scene = [
        [(1.0, 1.0, 0.5), (5.0, 5.0, 0.5), (9.0, 9.0, 0.5)],  # collinear
        [(3.0, 3.0, 0.5), (3.0, 3.0, 0.5), (7.0, 2.0, 0.5)],  # repeated vertex
        [(4.6, 4.6, 0.5), (4.9, 4.6, 0.5), (4.6, 4.9, 0.5)],  # sub-pixel, between centres
        [(2.0, 2.0, 0.5), (2.001, 2.0, 0.5), (2.0, 2.001, 0.5)],  # snaps to one point
    ]
    color, depth, ids, stats = draw_screen(np.array(scene), 12, 12)
    assert (ids == -1).all() and np.isinf(depth).all() and (color == 0).all()
    assert stats.empty == 4 and stats.drawn == 0 and stats.fragments == 0


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_nonfinite_vertices_drop_their_faces(bad):
    good = [(1.0, 1.0, 0.5), (9.0, 1.0, 0.5), (1.0, 9.0, 0.5)]
    clip, faces = screen_to_clip([good, good])
    clip[4, 0] = bad
    clip[5, 3] = bad
    color, depth, ids = buffers(12, 12)
    stats = rasterize_triangles(
        color, depth, clip, faces, face_colors=np.ones((2, 3), np.float32), ids=ids, cull="none"
    )
    assert stats.dropped_nonfinite == 1 and stats.drawn == 1
    assert set(np.unique(ids)) == {-1, 0}


@pytest.mark.parametrize("big", [1e6, 1e12, 1e30, 1e300])
def test_huge_triangles_cover_the_image_without_hanging(big):
    width, height = 40, 30
    scene = [
        [(-big, -1.0, 0.5), (big, -1.0, 0.5), (width / 2, big, 0.5)],  # covers everything
        [(-big, 3.4, 0.25), (big, 3.4, 0.25), (big, 3.7, 0.25)],  # a long sliver
    ]
    _, depth, ids, stats = draw_screen(np.array(scene), width, height)
    assert (ids >= 0).all()
    assert stats.clipped == (2 if big > 2**20 else 0)
    # Near the image the sliver is y = 3.4 .. 3.55: it covers the centres of row 3 only.
    np.testing.assert_array_equal(np.nonzero(ids == 1)[0], np.full(width, 3))
    assert (depth[ids == 0] == 0.5).all() and (depth[ids == 1] == 0.25).all()


def test_huge_homogeneous_coordinates_and_tiny_w():
    width, height = 16, 16
    clip = np.array(
        [
            [1e30, 1e30, 0.5e30, 1e30],  # the point (1, 1, 0.5) written with w = 1e30
            [14e-30, 1e-30, 0.5e-30, 1e-30],  # (14, 1, 0.5) with w = 1e-30
            [1.0, 14.0, 0.5, 1.0],
            [0.0, 0.0, 0.0, 0.0],  # the eye itself: not a point
            [5.0, 5.0, 0.5, 1.0],
            [9.0, 2.0, 0.5, 1.0],
        ]
    )
    faces = np.array([[0, 1, 2], [3, 4, 5]], np.int64)
    color, depth, ids = buffers(width, height)
    stats = rasterize_triangles(
        color, depth, clip, faces, face_colors=np.ones((2, 3), np.float32), ids=ids, cull="none"
    )
    expected = coverage(np.array([[1.0, 1.0], [14.0, 1.0], [1.0, 14.0]]), width, height)
    np.testing.assert_array_equal(ids >= 0, expected)
    assert stats.drawn == 1 and stats.outside == 1


def test_empty_mesh():
    color, depth, _ = buffers(4, 4)
    no_faces = np.zeros((0, 3), np.int64)
    stats = rasterize_triangles(
        color, depth, np.zeros((0, 4)), no_faces, face_colors=np.zeros((0, 3), np.float32)
    )
    assert stats == TriangleStats(0, 0, 0, 0, 0, 0, 0, 0, 0)
    assert np.isinf(depth).all()


# ---------------------------------------------------------------------------- culling


@pytest.mark.parametrize(
    ("cull", "drawn"),
    [("back", {"front"}), ("front", {"back"}), ("none", {"front", "back"})],
)
def test_culling_with_a_camera(cull, drawn):
    """Counter-clockwise seen from the camera (normal towards it) is front-facing."""
    width, height = 32, 24
    matrix = camera_matrix(width, height, focal=20.0, near=1.0, far=50.0)
    front = [(-2.0, -1.0, -5.0), (-0.5, -1.0, -5.0), (-1.2, 1.0, -5.0)]  # left of the view
    back = [(0.5, -1.0, -5.0), (1.2, 1.0, -5.0), (2.0, -1.0, -5.0)]  # right, clockwise
    normal = np.cross(np.subtract(front[1], front[0]), np.subtract(front[2], front[0]))
    assert normal[2] > 0  # points at the camera (which looks down -Z)
    clip = project(matrix, front + back)
    _, _, ids, stats = draw_screen_clip(clip, width, height, cull=cull)
    seen = {"front"} if (ids[:, : width // 2] == 0).any() else set()
    seen |= {"back"} if (ids[:, width // 2 :] == 1).any() else set()
    assert seen == drawn
    assert stats.culled == 2 - len(drawn)


# ---------------------------------------------------------------------------- threads


@pytest.mark.skipif(_threads.MAX_THREADS < 2, reason="needs 2 threads")
def test_one_and_two_threads_give_identical_images():
    rng = np.random.default_rng(3)
    width, height = 97, 83
    xy = rng.uniform(-10, 105, (300, 3, 2))
    z = rng.choice([0.25, 0.5, 0.75], (300, 1)).repeat(3, axis=1)  # many exact depth ties
    z[::3] = rng.uniform(0, 1, (100, 3))
    scene = np.concatenate([xy, z[..., None]], axis=2)
    colors = rng.uniform(0, 255, (300, 3)).astype(np.float32)
    first = draw_screen(scene, width, height, threads=1, face_colors=colors)
    previous = _threads.get_threads()
    _threads.set_threads(2)
    try:
        second = draw_screen(scene, width, height, face_colors=colors)
    finally:
        _threads.set_threads(previous)
    for a, b in zip(first[:3], second[:3]):
        np.testing.assert_array_equal(a, b)
    assert _threads.get_threads() == previous


# ---------------------------------------------------------------------------- colours


def test_flat_colours_round_and_set_alpha():
    color, depth, _ = buffers(6, 6, channels=4)
    clip, faces = screen_to_clip([[(0, 0, 0.5), (10, 0, 0.5), (0, 10, 0.5)]])
    face_colors = np.array([[10.4, 10.5, 254.6]], np.float32)
    rasterize_triangles(color, depth, clip, faces, face_colors=face_colors, cull="none")
    drawn = np.isfinite(depth)
    assert drawn.sum() > 10
    assert (color[drawn] == [10, 11, 255, 255]).all()
    assert (color[~drawn] == 0).all()


def ray_colors(points, colors, width, height, focal):
    """Expected colour at every pixel centre by casting a ray into the 3D triangle.

    Independent of the renderer: camera-space ray through the pixel centre, its intersection
    with the triangle's plane, and that point's 3D barycentric coordinates.
    """
    p0, p1, p2 = np.asarray(points, dtype=np.float64)
    px, py = np.meshgrid(np.arange(width) + 0.5, np.arange(height) + 0.5)
    rays = np.stack([(px - width / 2) / focal, -(py - height / 2) / focal, -np.ones_like(px)], axis=-1)
    normal = np.cross(p1 - p0, p2 - p0)
    hits = rays * (normal @ p0 / (rays @ normal))[..., None]
    total = normal @ normal
    b1 = np.cross(hits - p0, p2 - p0) @ normal / total
    b2 = np.cross(p1 - p0, hits - p0) @ normal / total
    b0 = 1 - b1 - b2
    return b0[..., None] * colors[0] + b1[..., None] * colors[1] + b2[..., None] * colors[2]


@pytest.mark.parametrize(
    "points",
    [
        [(-3.0, -2.0, -2.0), (4.0, -1.0, -12.0), (-1.0, 3.0, -6.0)],  # slanted, in front
        [(-3.0, -2.0, 1.0), (4.0, -1.0, -12.0), (-1.0, 3.0, -6.0)],  # crosses the near plane
    ],
)
def test_smooth_colours_are_perspective_correct(points):
    width, height, focal = 48, 40, 30.0
    matrix = camera_matrix(width, height, focal=focal, near=0.5, far=100.0)
    colors = np.array([[255.0, 0.0, 0.0], [0.0, 255.0, 0.0], [0.0, 0.0, 255.0]], np.float32)
    color, depth, ids = buffers(width, height)
    clip = project(matrix, points)
    rasterize_triangles(
        color, depth, clip, np.array([[0, 1, 2]], np.int64), vertex_colors=colors, ids=ids, cull="none"
    )
    drawn = ids >= 0
    assert drawn.sum() > 200
    expected = ray_colors(points, colors, width, height, focal)[drawn]
    assert np.abs(color[drawn] - expected).max() <= 1.0
    # Screen-space (affine) interpolation would be visibly wrong here.
    screen = divide(clip)
    affine = reference_affine_colors(screen, colors, width, height)[drawn]
    assert np.abs(affine - expected).max() > 10


def reference_affine_colors(screen, colors, width, height):
    px, py = np.meshgrid(np.arange(width) + 0.5, np.arange(height) + 0.5)
    (x0, y0, _), (x1, y1, _), (x2, y2, _) = screen
    area2 = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)
    w0 = ((x1 - px) * (y2 - py) - (x2 - px) * (y1 - py)) / area2
    w1 = ((x2 - px) * (y0 - py) - (x0 - px) * (y2 - py)) / area2
    return w0[..., None] * colors[0] + w1[..., None] * colors[1] + (1 - w0 - w1)[..., None] * colors[2]


def test_depth_only_draw_leaves_colour_alone():
    width, height = 10, 10
    clip, faces = screen_to_clip([[(0, 0, 0.5), (0, 10, 0.5), (10, 0, 0.5)]])  # front-facing
    _, depth, ids = buffers(width, height)
    stats = rasterize_triangles(None, depth, clip, faces, ids=ids)
    assert stats.drawn == 1 and (ids >= 0).sum() == stats.fragments == np.isfinite(depth).sum()


@pytest.mark.parametrize("channels", [3, 4])
def test_clear_resets_the_buffers_band_by_band(channels):
    width, height = 40, 70  # several bands
    color, depth, ids = buffers(width, height, channels=channels)
    color[:], depth[:], ids[:] = 7, 0.125, 5  # leftovers of an earlier frame, nearer than z
    clip, faces = screen_to_clip([[(2, 2, 0.5), (2, 60, 0.5), (30, 2, 0.5)]])
    face_colors = np.array([[10, 20, 30]], np.float32)
    background = (1, 2, 3, 4)[:channels]
    stats = rasterize_triangles(color, depth, clip, faces, face_colors=face_colors, ids=ids, clear=background)
    drawn = coverage(np.array([[2, 2], [2, 60], [30, 2]]), width, height)
    assert stats.fragments == drawn.sum() > 0
    np.testing.assert_array_equal(ids, np.where(drawn, 0, -1))
    np.testing.assert_array_equal(depth, np.where(drawn, 0.5, np.inf))
    np.testing.assert_array_equal(color, np.where(drawn[..., None], [10, 20, 30, 255][:channels], background))
    # Without a colour buffer, clear=() resets depth and ids only.
    depth[:], ids[:] = 0.125, 5
    rasterize_triangles(None, depth, clip, faces, ids=ids, clear=())
    np.testing.assert_array_equal(ids, np.where(drawn, 0, -1))


# ---------------------------------------------------------------------------- shading


def test_lambert_intensities():
    normals = np.array([[0, 0, 1], [1, 0, 0], [0, 0, -1], [0.6, 0, 0.8]], np.float64)
    base = np.array([[200, 100, 50]], np.float32)
    light = np.array([0.0, 0.0, 1.0])
    none = np.zeros((0, 3))
    one_sided = lambert(normals, base, light, none, False, 0.2, False)
    two_sided = lambert(normals, base, light, none, False, 0.2, True)
    np.testing.assert_allclose(one_sided[:, 0], [200, 40, 40, 200 * 0.84], rtol=1e-6)
    np.testing.assert_allclose(two_sided[:, 0], [200, 40, 200, 200 * 0.84], rtol=1e-6)
    np.testing.assert_allclose(one_sided[0], [200, 100, 50])
    assert one_sided.dtype == np.float32


def test_lambert_point_light_and_per_element_colours():
    normals = np.array([[0, 0, 1], [0, 0, 1]], np.float64)
    points = np.array([[0, 0, 0], [10, 0, 10]], np.float64)
    base = np.array([[100, 100, 100], [50, 60, 70]], np.float32)
    out = lambert(normals, base, np.array([0.0, 0.0, 10.0]), points, True, 0.0, False)
    np.testing.assert_allclose(out, [[100, 100, 100], [0, 0, 0]], atol=1e-5)


def cube(centred_faces):
    """Unit cube [-1, 1]^3, outward CCW faces; each face either 2 triangles or 4 around its centre."""
    corners = np.array([(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    positions, faces = list(corners), []
    for a, b, c, d in quads:
        if centred_faces:
            positions.append(corners[[a, b, c, d]].mean(axis=0))
            m = len(positions) - 1
            faces += [(a, b, m), (b, c, m), (c, d, m), (d, a, m)]
        else:
            faces += [(a, b, c), (a, c, d)]
    return np.array(positions), np.array(faces, np.int64)


def test_face_normals_of_a_cube_point_outwards():
    positions, faces = cube(centred_faces=False)
    normals = face_normals(positions, faces)
    centroids = positions[faces].mean(axis=1)
    # Each normal is the axis of the face's centroid: outward and unit.
    expected = np.where(np.abs(centroids) > 0.5, np.sign(centroids), 0)
    np.testing.assert_allclose(normals, expected, atol=1e-12)


def test_vertex_normals_of_a_cube_and_a_sphere():
    positions, faces = cube(centred_faces=True)
    normals = vertex_normals(positions, faces)
    np.testing.assert_allclose(normals[:8], positions[:8] / np.sqrt(3), atol=1e-12)
    np.testing.assert_allclose(normals[8:], positions[8:], atol=1e-12)
    # A UV sphere: vertex normals approach the radial direction.
    theta, phi = np.meshgrid(
        np.linspace(0.1, np.pi - 0.1, 30), np.linspace(0, 2 * np.pi, 60, endpoint=False), indexing="ij"
    )
    sphere = np.stack(
        [np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], axis=-1
    ).reshape(-1, 3)
    faces = []
    for i in range(29):
        for j in range(60):
            a, b = i * 60 + j, i * 60 + (j + 1) % 60
            faces += [(a, a + 60, b + 60), (a, b + 60, b)]
    normals = vertex_normals(sphere, np.array(faces, np.int64))
    inner = slice(60, 29 * 60)
    assert (np.sum(normals[inner] * sphere[inner], axis=1) > 0.999).all()
    # Degenerate input: an unused vertex and a zero-area face give zero normals.
    assert not vertex_normals(np.zeros((4, 3)), np.array([[0, 1, 2]], np.int64)).any()


# ---------------------------------------------------------------------------- validation


def valid_call():
    color, depth, ids = buffers(8, 6)
    clip, faces = screen_to_clip([[(0, 0, 0.5), (8, 0, 0.5), (0, 6, 0.5)]])
    return {
        "color": color,
        "depth": depth,
        "clip": clip,
        "faces": faces,
        "face_colors": np.ones((1, 3), np.float32),
        "ids": ids,
    }


@pytest.mark.parametrize(
    ("change", "error", "message"),
    [
        ({"depth": np.zeros((6, 8))}, TypeError, "depth must have dtype float32"),
        ({"depth": np.zeros((6, 8), np.float32)[:, ::2]}, ValueError, "C-contiguous"),
        ({"color": np.zeros((6, 7, 3), np.uint8)}, ValueError, "expected"),
        ({"color": np.zeros((6, 8, 2), np.uint8)}, ValueError, "3 or 4 channels"),
        ({"ids": np.zeros((6, 8), np.int64)}, TypeError, "ids must have dtype int32"),
        ({"clip": np.zeros((3, 3))}, ValueError, r"\(N, 4\)"),
        ({"faces": np.array([[0, 1, 3]], np.int64)}, ValueError, "index vertices"),
        ({"faces": np.array([[0, -1, 2]], np.int64)}, ValueError, "index vertices"),
        ({"faces": np.array([[0, 1, 2]], np.int32)}, TypeError, "int64"),
        ({"face_colors": np.ones((2, 3), np.float32)}, ValueError, "one RGB per face"),
        ({"face_colors": np.full((1, 3), np.nan, np.float32)}, ValueError, "finite"),
        ({"vertex_colors": np.ones((3, 3), np.float32)}, ValueError, "not both"),
        ({"face_colors": None}, ValueError, "needs face_colors"),
        ({"cull": "sideways"}, ValueError, "cull must be"),
        ({"threads": 0}, ValueError, "threads"),
        ({"clear": (0, 0)}, ValueError, "clear must be 3 integers"),
        ({"clear": (0.5, 0, 0)}, ValueError, "clear must be 3 integers"),
        ({"clear": (0, 0, 256)}, ValueError, "0..255"),
        ({"clip": [[0, 0, 0, 1]]}, TypeError, "numpy.ndarray"),
    ],
)
def test_invalid_inputs_raise(change, error, message):
    arguments = valid_call()
    arguments.update(change)
    color, depth, clip, faces = (arguments.pop(k) for k in ("color", "depth", "clip", "faces"))
    with pytest.raises(error, match=message):
        rasterize_triangles(color, depth, clip, faces, **arguments)


def test_read_only_buffer_is_rejected():
    arguments = valid_call()
    arguments["depth"].flags.writeable = False
    color, depth, clip, faces = (arguments.pop(k) for k in ("color", "depth", "clip", "faces"))
    with pytest.raises(ValueError, match="writeable"):
        rasterize_triangles(color, depth, clip, faces, **arguments)


def test_depth_offset_pushes_faces_back_by_slope_and_units():
    """glPolygonOffset semantics: offset = factor * max(|dz/dx|, |dz/dy|) + units."""
    clip = np.array([[2, 2, 0.1, 1], [40, 2, 0.1 + 0.038, 1], [2, 30, 0.1 + 0.0084, 1]], np.float64)
    faces = np.array([[0, 2, 1], [0, 1, 2]], np.int64)  # one of the two windings is front
    plain = np.full((32, 48), np.inf, np.float32)
    pushed = plain.copy()
    rasterize_triangles(None, plain, clip, faces, cull="none")
    rasterize_triangles(None, pushed, clip, faces, cull="none", depth_offset=(2.0, 1e-4))
    drawn = np.isfinite(plain)
    assert drawn.sum() > 300
    # dz/dx = 0.001, dz/dy = 0.0003 per pixel
    assert np.allclose(pushed[drawn] - plain[drawn], 2 * 0.001 + 1e-4, atol=1e-6)
    with pytest.raises(ValueError):
        rasterize_triangles(None, plain, clip, faces, depth_offset=(np.nan, 0))


@pytest.mark.parametrize("n_bands", [0, 1, 2, 5, 34])
def test_bin_cursors_are_an_exclusive_scan_in_band_then_chunk_order(n_bands):
    from rasterkit.raster.kernels.bands import N_CHUNKS, bin_cursors

    counts = np.random.default_rng(n_bands).integers(0, 9, (N_CHUNKS, n_bands)).astype(np.int64)
    expected, start, total = counts.copy(), [], 0
    for b in range(n_bands):  # the counting sort's cursors, one at a time
        start.append(total)
        for ch in range(N_CHUNKS):
            expected[ch, b], total = total, total + counts[ch, b]
    band_start = bin_cursors(counts)
    assert band_start.tolist() == start + [total] and band_start.dtype == np.int64
    assert np.array_equal(counts, expected)
