"""Tests of the line kernels (rasterkit.raster.kernels.line) and rasterkit.draw.line."""

from __future__ import annotations

import doctest
import math
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import rasterkit.draw
import rasterkit.raster.draw
from rasterkit.draw import line
from rasterkit.runtime import threads as _threads
from rasterkit.raster.edge_pass import draw_edges
from rasterkit.raster.kernels.edges import MODE_ANTIALIAS, MODE_DEPTH_TEST, MODE_PLAIN
from support.reference_lines import ambiguous_edge, reference_draw_edges, reference_line

METHODS = ["bresenham", "dda", "naive"]
ALL_MODES = [MODE_PLAIN, MODE_DEPTH_TEST, MODE_ANTIALIAS, MODE_DEPTH_TEST | MODE_ANTIALIAS]
WHITE = np.array([255, 255, 255], dtype=np.uint8)

coord = st.integers(-60, 60)
endpoints = st.tuples(coord, coord, coord, coord)


def has_tie(x0, y0, x1, y1):
    """Whether the exact line passes exactly half-way between two pixels at some step."""
    n = max(abs(x1 - x0), abs(y1 - y0))
    return n > 0 and any(
        (Fraction((x1 - x0) * t, n) % 1) == Fraction(1, 2) or (Fraction((y1 - y0) * t, n) % 1) == Fraction(1, 2)
        for t in range(n + 1)
    )


def image_of(pixels, shape=(10, 10)):
    image = np.zeros(shape, dtype=np.uint8)
    for x, y in pixels:
        image[y, x] = 1
    return image


# --- rasterkit.draw.line: properties -----------------------------------------------------------


@settings(deadline=None, max_examples=150)
@given(endpoints)
def test_bresenham_is_the_exact_line_rounded_half_up(ends):
    assert line(*ends).tolist() == [list(p) for p in reference_line(*ends)]


@pytest.mark.parametrize("method", METHODS)
@settings(deadline=None, max_examples=100)
@given(ends=endpoints)
def test_line_is_an_8_connected_run_one_pixel_per_major_step(method, ends):
    x0, y0, x1, y1 = ends
    pixels = line(x0, y0, x1, y1, method)
    n = max(abs(x1 - x0), abs(y1 - y0))
    assert pixels.shape == (n + 1, 2) and pixels.dtype == np.int64
    assert pixels[0].tolist() == [x0, y0] and pixels[-1].tolist() == [x1, y1]
    steps = np.abs(np.diff(pixels, axis=0))
    assert steps.max(initial=0) <= 1
    major = 1 if abs(y1 - y0) > abs(x1 - x0) else 0
    assert np.all(steps[:, major] == 1)


@pytest.mark.parametrize("method", METHODS)
@settings(deadline=None, max_examples=100)
@given(ends=endpoints)
def test_minor_error_is_at_most_half_a_pixel(method, ends):
    x0, y0, x1, y1 = ends
    n = max(abs(x1 - x0), abs(y1 - y0))
    for t, (x, y) in enumerate(line(x0, y0, x1, y1, method).tolist()):
        if n:
            assert abs(x - (x0 + Fraction((x1 - x0) * t, n))) <= Fraction(1, 2)
            assert abs(y - (y0 + Fraction((y1 - y0) * t, n))) <= Fraction(1, 2)


@pytest.mark.parametrize("method", METHODS)
@settings(deadline=None, max_examples=60)
@given(ends=endpoints)
def test_reversed_line_is_the_same_pixels_backwards(method, ends):
    x0, y0, x1, y1 = ends
    assert line(x1, y1, x0, y0, method).tolist() == line(x0, y0, x1, y1, method)[::-1].tolist()


@pytest.mark.parametrize("method", METHODS)
@settings(deadline=None, max_examples=60)
@given(ends=endpoints)
def test_transposed_line_is_the_transposed_pixels(method, ends):
    x0, y0, x1, y1 = ends
    assert line(y0, x0, y1, x1, method).tolist() == line(x0, y0, x1, y1, method)[:, ::-1].tolist()


# --- the three methods agree where exact arithmetic says they must ----------------------------


@settings(deadline=None, max_examples=60)
@given(st.integers(-500, 500), st.integers(-500, 500), st.integers(0, 300), st.sampled_from(["h", "v", "d", "a"]))
def test_methods_agree_on_axis_and_diagonal_lines(x0, y0, length, kind):
    dx, dy = {"h": (length, 0), "v": (0, length), "d": (length, length), "a": (length, -length)}[kind]
    expected = line(x0, y0, x0 + dx, y0 + dy)
    for method in ("dda", "naive"):
        assert np.array_equal(line(x0, y0, x0 + dx, y0 + dy, method), expected)


@settings(deadline=None, max_examples=60)
@given(st.integers(-1000, 1000), st.integers(-1000, 1000), st.integers(0, 9), st.data())
def test_methods_agree_when_the_major_extent_is_a_power_of_two(x0, y0, log_n, data):
    # The slope dv / 2**k and every m u + b are exact binary fractions: ties are exact too.
    n = 2**log_n
    dv = data.draw(st.integers(-n, n))
    sign = data.draw(st.sampled_from([1, -1]))
    for x1, y1 in ((x0 + sign * n, y0 + dv), (x0 + dv, y0 + sign * n)):
        expected = line(x0, y0, x1, y1)
        for method in ("dda", "naive"):
            assert np.array_equal(line(x0, y0, x1, y1, method), expected)


@settings(deadline=None, max_examples=100)
@given(st.tuples(st.integers(-500, 500), st.integers(-500, 500), st.integers(-500, 500), st.integers(-500, 500)))
def test_methods_agree_on_lines_without_ties(ends):
    assume(not has_tie(*ends))
    expected = line(*ends)
    for method in ("dda", "naive"):
        assert np.array_equal(line(*ends, method=method), expected)


def test_dda_can_break_a_tie_the_other_way():
    # At x = 5 the exact line is at y = 7.5; 9 - 0.3 - 0.3 - ... lands just below 7.5.
    bresenham, dda = line(0, 9, 10, 6), line(0, 9, 10, 6, "dda")
    assert bresenham[5].tolist() == [5, 8] and dda[5].tolist() == [5, 7]
    different = np.any(bresenham != dda, axis=1)
    assert different.tolist() == [t == 5 for t in range(11)]


def _dda_reference(x0, y0, x1, y1):
    """DDA as its definition says, in Python floats: from the end with the smaller major
    coordinate, v += m in IEEE double precision, each v rounded half up."""
    steep = abs(y1 - y0) > abs(x1 - x0)
    u0, v0, u1, v1 = (y0, x0, y1, x1) if steep else (x0, y0, x1, y1)
    backwards = u1 < u0
    if backwards:
        u0, v0, u1, v1 = u1, v1, u0, v0
    n = u1 - u0
    m = (v1 - v0) / n if n > 0 else 0.0
    v, pixels = float(v0), []
    for t in range(n + 1):
        pixels.append((math.floor(v + 0.5), u0 + t) if steep else (u0 + t, math.floor(v + 0.5)))
        v += m
    return pixels[::-1] if backwards else pixels


def test_dda_is_the_ieee_running_sum_on_every_machine():
    """The DDA kernel's pixels are those of the running sum in plain IEEE arithmetic (fast-math
    let LLVM reorder the sum, which changed the pixels of 401 of these lines on one machine
    and not on another)."""
    rng = np.random.default_rng(5)
    for x0, y0, x1, y1 in rng.integers(-60, 61, (3000, 4)).tolist():
        assert [tuple(p) for p in line(x0, y0, x1, y1, "dda").tolist()] == _dda_reference(x0, y0, x1, y1)


# --- hand-drawn pictures -------------------------------------------------------------------------


def test_shallow_line_picture():
    expected = np.array(
        [
            [0, 0, 0, 0, 0, 0, 0, 0, 0, 0],
            [0, 0, 0, 0, 0, 0, 0, 0, 0, 0],
            [0, 1, 1, 0, 0, 0, 0, 0, 0, 0],
            [0, 0, 0, 1, 1, 0, 0, 0, 0, 0],
            [0, 0, 0, 0, 0, 1, 1, 0, 0, 0],
            [0, 0, 0, 0, 0, 0, 0, 1, 1, 0],
            [0, 0, 0, 0, 0, 0, 0, 0, 0, 0],
            [0, 0, 0, 0, 0, 0, 0, 0, 0, 0],
            [0, 0, 0, 0, 0, 0, 0, 0, 0, 0],
            [0, 0, 0, 0, 0, 0, 0, 0, 0, 0],
        ]
    )
    for method in METHODS:
        assert np.array_equal(image_of(line(1, 2, 8, 5, method)), expected)


def test_steep_line_drawn_upwards_picture():
    expected = np.array(
        [
            [0, 0, 0, 1, 0, 0, 0, 0, 0, 0],
            [0, 0, 0, 1, 0, 0, 0, 0, 0, 0],
            [0, 0, 0, 0, 1, 0, 0, 0, 0, 0],
            [0, 0, 0, 0, 1, 0, 0, 0, 0, 0],
            [0, 0, 0, 0, 1, 0, 0, 0, 0, 0],
            [0, 0, 0, 0, 0, 1, 0, 0, 0, 0],
            [0, 0, 0, 0, 0, 1, 0, 0, 0, 0],
            [0, 0, 0, 0, 0, 1, 0, 0, 0, 0],
            [0, 0, 0, 0, 0, 0, 1, 0, 0, 0],
            [0, 0, 0, 0, 0, 0, 1, 0, 0, 0],
        ]
    )
    for method in METHODS:
        assert np.array_equal(image_of(line(6, 9, 3, 0, method)), expected)


def test_ties_go_down_for_rising_and_falling_lines_picture():
    # y = t / 4 and y = 9 - t / 4: at t = 2 and 6 the exact line is half-way between rows.
    expected = np.array(
        [
            [1, 1, 0, 0, 0, 0, 0, 0, 0, 0],
            [0, 0, 1, 1, 1, 1, 0, 0, 0, 0],
            [0, 0, 0, 0, 0, 0, 1, 1, 1, 0],
            [0, 0, 0, 0, 0, 0, 0, 0, 0, 0],
            [0, 0, 0, 0, 0, 0, 0, 0, 0, 0],
            [0, 0, 0, 0, 0, 0, 0, 0, 0, 0],
            [0, 0, 0, 0, 0, 0, 0, 0, 0, 0],
            [0, 0, 0, 0, 0, 0, 0, 0, 1, 1],
            [0, 0, 0, 0, 1, 1, 1, 1, 0, 0],
            [0, 1, 1, 1, 0, 0, 0, 0, 0, 0],
        ]
    )
    for method in METHODS:
        pixels = np.vstack([line(0, 0, 8, 2, method), line(9, 7, 1, 9, method)])
        assert np.array_equal(image_of(pixels), expected)


def test_axis_diagonal_and_point_picture():
    expected = np.array(
        [
            [1, 0, 0, 0, 0, 0, 0, 0, 0, 1],
            [0, 0, 1, 0, 0, 0, 0, 0, 1, 0],
            [0, 0, 1, 0, 0, 0, 0, 1, 0, 0],
            [0, 0, 1, 0, 0, 0, 1, 0, 0, 0],
            [0, 0, 1, 0, 0, 1, 0, 0, 0, 0],
            [0, 0, 1, 0, 1, 0, 0, 0, 0, 0],
            [0, 0, 0, 1, 0, 0, 0, 0, 0, 0],
            [0, 0, 1, 0, 1, 1, 1, 1, 1, 0],
            [0, 1, 0, 0, 0, 0, 0, 0, 0, 0],
            [1, 0, 0, 0, 0, 0, 0, 0, 0, 0],
        ]
    )
    for method in METHODS:
        pixels = np.vstack(
            [line(9, 0, 0, 9, method), line(2, 1, 2, 5, method), line(8, 7, 4, 7, method), line(0, 0, 0, 0, method)]
        )
        assert np.array_equal(image_of(pixels), expected)


# --- rasterkit.draw.line: validation and docs ----------------------------------------------------


@pytest.mark.parametrize("bad", [1.0, 2.5, "3", None, True, np.float64(1.0)])
def test_line_rejects_non_integer_coordinates(bad):
    with pytest.raises(TypeError, match="x1"):
        line(0, 0, bad, 0)


def test_line_accepts_numpy_integers():
    assert line(np.int32(0), np.int64(0), np.uint8(2), 1).tolist() == [[0, 0], [1, 1], [2, 1]]


def test_line_rejects_out_of_range_coordinates():
    with pytest.raises(ValueError, match="y0"):
        line(0, 2**29 + 1, 0, 0)


@pytest.mark.parametrize("method", ["Bresenham", "wu", "", 0])
def test_line_rejects_unknown_methods(method):
    with pytest.raises(ValueError, match="method"):
        line(0, 0, 1, 1, method)


def test_draw_module_doctests_pass():
    result = doctest.testmod(rasterkit.raster.draw, optionflags=doctest.NORMALIZE_WHITESPACE)
    assert result.attempted > 0 and result.failed == 0


# --- draw_edges: helpers -------------------------------------------------------------------------


def render(clip, edges, mode=MODE_PLAIN, shape=(24, 32), depth=None, rgba=WHITE, bias=0.0, n_bands=1, color=None,
           threads=1):
    """Run draw_edges into ``color`` (default: a cleared buffer); returns (color, dropped)."""
    height, width = shape
    if color is None:
        color = np.zeros((height, width, len(rgba)), dtype=np.uint8)
    if depth is None:
        depth = np.full(shape, np.inf, dtype=np.float32)
    clip = np.ascontiguousarray(clip, dtype=np.float64)
    edges = np.ascontiguousarray(np.asarray(edges, dtype=np.int64).reshape(-1, 2))
    dropped = draw_edges(color, depth, clip, edges, np.asarray(rgba, dtype=np.uint8), mode, bias, n_bands=n_bands,
                         threads=threads)
    return color, dropped


def raster_edge(x0, y0, x1, y1, z0=0.5, z1=0.5):
    """Clip coordinates (w = 1) and the edge list for one raster-space segment."""
    return np.array([[x0, y0, z0, 1.0], [x1, y1, z1, 1.0]]), [[0, 1]]


def drawn(color):
    return {(int(x), int(y)) for y, x in zip(*np.nonzero(color[..., 0]))}


def assert_matches_reference(clip, edges, mode, depth, bias, n_bands, shape):
    """draw_edges equals the reference, up to near-tie depth tests and Wu's rounding."""
    color = np.zeros(shape + (3,), dtype=np.uint8)
    ours, dropped = render(clip, edges, mode, shape, depth, bias=bias, n_bands=n_bands)
    expected, expected_dropped, uncertain = reference_draw_edges(color, depth, clip, edges, WHITE, mode, bias)
    assert dropped == expected_dropped
    difference = np.abs(ours.astype(int) - expected.astype(int)).max(axis=2)
    difference[uncertain] = 0
    assert difference.max(initial=0) <= (1 if mode & MODE_ANTIALIAS else 0)


# --- draw_edges: against the reference -----------------------------------------------------------

special = st.sampled_from([np.nan, np.inf, -np.inf, 1e12, -1e12, 1e30, -1e30, 1e301, 0.0])
homogeneous_vertex = st.tuples(
    st.one_of(st.floats(-60, 100), special),
    st.one_of(st.floats(-60, 80), special),
    st.one_of(st.floats(-1, 2), special),
    st.one_of(st.floats(-2, 2), st.just(1.0)),
)


@settings(deadline=None, max_examples=80)
@given(
    vertices=st.lists(homogeneous_vertex, min_size=2, max_size=8),
    data=st.data(),
    mode=st.sampled_from(ALL_MODES),
    n_bands=st.integers(1, 5),
)
def test_draw_edges_matches_reference(vertices, data, mode, n_bands):
    shape = (17, 23)
    clip = np.array(vertices, dtype=np.float64)
    index = st.integers(0, len(vertices) - 1)
    edges = data.draw(st.lists(st.tuples(index, index), min_size=1, max_size=10))
    edges = [e for e in edges if not ambiguous_edge(clip[e[0]], clip[e[1]], bool(mode & MODE_ANTIALIAS))]
    depth = np.random.default_rng(len(edges)).uniform(0, 1, shape).astype(np.float32)
    assert_matches_reference(clip, np.array(edges, dtype=np.int64).reshape(-1, 2), mode, depth, 0.01, n_bands, shape)


@settings(deadline=None, max_examples=80)
@given(st.lists(st.floats(-40, 80), min_size=4, max_size=4), st.integers(1, 4))
def test_viewport_clipping_keeps_exactly_the_unclipped_pixels_inside(ends, n_bands):
    x0, y0, x1, y1 = ends
    height, width = shape = (24, 32)
    color, _ = render(*raster_edge(x0, y0, x1, y1), shape=shape, n_bands=n_bands)
    full = reference_line(math.floor(x0), math.floor(y0), math.floor(x1), math.floor(y1))
    assert drawn(color) == {(x, y) for x, y in full if 0 <= x < width and 0 <= y < height}


@pytest.mark.parametrize("big", [1e7, 1e12, 1e30, 1e300])
def test_huge_coordinates_draw_only_the_visible_part(big):
    # Segments up to 1e300 pixels long: only their visible parts are stepped.
    clip = np.array(
        [
            [-big, 5.5, 0.5, 1.0],
            [big, 5.5, 0.5, 1.0],
            [-big, -big, 0.5, 1.0],
            [big, big, 0.5, 1.0],
            [3.5, 20.25, 0.5, 1.0],
            [big, -big / 2, 0.5, 1.0],
        ]
    )
    edges = [[0, 1], [2, 3], [4, 5]]
    assert not any(ambiguous_edge(clip[i], clip[j]) for i, j in edges)
    color, dropped = render(clip, edges)
    assert dropped == 0
    assert {(x, 5) for x in range(32)} | {(i, i) for i in range(24)} <= drawn(color)
    for x, y in drawn(color) - {(x, 5) for x in range(32)} - {(i, i) for i in range(24)}:
        # Pixel centres of the third edge lie within a pixel of y = 20.25 - (x - 3.5) / 2.
        assert abs(y + 0.5 - (20.25 - (x + 0.5 - 3.5) / 2)) <= 1.0
    assert_matches_reference(clip, np.array(edges), MODE_PLAIN, np.full((24, 32), np.inf, np.float32), 0.0, 3, (24, 32))


def test_edge_crossing_the_near_plane_is_cut_where_zh_is_zero():
    # From (10, 5, z 0.5) in front towards a vertex behind the near plane (zh < 0):
    # zh = 0 at t = 1/3, i.e. at (17/3, 4, 0, 5/6), which is raster (6.8, 4.8).
    clip = np.array([[10.0, 5.0, 0.5, 1.0], [-3.0, 2.0, -1.0, 0.5]])
    color, dropped = render(clip, [[0, 1]])
    assert dropped == 0
    assert drawn(color) == set(reference_line(6, 4, 10, 5))


def test_edges_behind_the_eye_or_beyond_the_far_plane_draw_nothing():
    clip = np.array(
        [
            [5.0, 5.0, -0.5, 1.0],  # in front of the near plane
            [20.0, 9.0, -2.0, 2.0],
            [5.0, 5.0, 0.5, -1.0],  # w < 0: behind the eye
            [20.0, 9.0, 0.5, -2.0],
            [5.0, 5.0, 1.5, 1.0],  # beyond the far plane
            [20.0, 9.0, 3.0, 2.0],
        ]
    )
    color, dropped = render(clip, [[0, 1], [2, 3], [4, 5]])
    assert dropped == 0 and not color.any()


def test_non_finite_and_absurd_vertices_drop_their_edges_and_are_counted():
    clip = np.array(
        [
            [1.5, 1.5, 0.5, 1.0],
            [8.5, 1.5, 0.5, 1.0],
            [np.nan, 3.5, 0.5, 1.0],
            [8.5, np.inf, 0.5, 1.0],
            [1e301, 3.5, 0.5, 1.0],
        ]
    )
    color, dropped = render(clip, [[0, 1], [0, 2], [3, 1], [2, 3], [4, 0]])
    assert dropped == 4
    assert drawn(color) == {(x, 1) for x in range(1, 9)}


def test_plain_and_antialiased_modes_need_no_depth_buffer():
    no_depth = np.empty((0, 0), dtype=np.float32)
    for mode in (MODE_PLAIN, MODE_ANTIALIAS):
        with_depth, _ = render(*raster_edge(1.5, 2.5, 6.5, 7.5), mode)
        without, _ = render(*raster_edge(1.5, 2.5, 6.5, 7.5), mode, depth=no_depth)
        assert np.array_equal(with_depth, without) and with_depth.any()


def test_colour_buffer_with_alpha_gets_all_four_channels():
    rgba = np.array([10, 20, 30, 255], dtype=np.uint8)
    color, _ = render(*raster_edge(1.5, 2.5, 6.5, 2.5), rgba=rgba)
    assert np.array_equal(color[2, 1:7], np.tile(rgba, (6, 1)))
    assert color.sum() == 6 * int(rgba.astype(int).sum())


# --- draw_edges: depth test ----------------------------------------------------------------------


def test_depth_test_draws_only_in_front_of_the_depth_buffer_and_never_writes_it():
    depth = np.full((10, 10), 0.25, dtype=np.float32)
    depth[:, 5:] = 0.75
    saved = depth.copy()
    clip, edges = raster_edge(0.5, 4.5, 9.5, 4.5, z0=0.5, z1=0.5)
    color, _ = render(clip, edges, MODE_DEPTH_TEST, (10, 10), depth)
    assert drawn(color) == {(x, 4) for x in range(5, 10)}
    assert np.array_equal(depth, saved)
    color, _ = render(clip, edges, MODE_DEPTH_TEST, (10, 10), depth, bias=0.3)
    assert drawn(color) == {(x, 4) for x in range(10)}


def test_depth_is_interpolated_linearly_at_pixel_centres():
    # z = x / 10 along the edge; at the centre of column m, z = (m + 0.5) / 10 <= 0.5 for m <= 4.
    depth = np.full((10, 10), 0.5, dtype=np.float32)
    clip, edges = raster_edge(0.0, 3.5, 10.0, 3.5, z0=0.0, z1=1.0)
    color, _ = render(clip, edges, MODE_DEPTH_TEST, (10, 10), depth)
    assert drawn(color) == {(x, 3) for x in range(5)}


def test_depth_of_a_perspective_edge_is_affine_in_screen_space():
    # Raster (2, 2.5, z 0) to (8, 2.5, z 0.6) with different w: z at column m's centre is
    # 0.1 * (m + 0.5 - 2); the buffer holds 0.3 everywhere, so columns 2..4 pass.
    clip = np.array([[2.0 * 4, 2.5 * 4, 0.0, 4.0], [8.0 * 0.5, 2.5 * 0.5, 0.6 * 0.5, 0.5]])
    depth = np.full((10, 10), 0.3, dtype=np.float32)
    color, _ = render(clip, [[0, 1]], MODE_DEPTH_TEST, (10, 10), depth)
    assert drawn(color) == {(x, 2) for x in range(2, 5)}


# --- draw_edges: Xiaolin Wu anti-aliasing --------------------------------------------------------


def test_wu_line_through_pixel_centres_has_full_intensity():
    color, _ = render(*raster_edge(2.0, 3.5, 8.0, 3.5), MODE_ANTIALIAS, (10, 10))
    assert drawn(color) == {(x, 3) for x in range(2, 8)}
    assert np.all(color[3, 2:8] == 255)
    color, _ = render(*raster_edge(2.0, 2.0, 8.0, 8.0), MODE_ANTIALIAS, (10, 10))
    assert drawn(color) == {(i, i) for i in range(2, 8)}
    assert np.all(color[np.arange(2, 8), np.arange(2, 8)] == 255)


def test_wu_end_pixels_get_the_covered_fraction():
    color, _ = render(*raster_edge(2.5, 3.5, 7.25, 3.5), MODE_ANTIALIAS, (10, 10))
    assert color[3, :, 0].tolist() == [0, 0, 128, 255, 255, 255, 255, 64, 0, 0]


def test_wu_splits_coverage_between_the_two_nearest_rows():
    # y = 4.75 at every column: a quarter of the way from row 4's centre (4.5) to row 5's.
    color, _ = render(*raster_edge(1.0, 4.75, 9.0, 4.75), MODE_ANTIALIAS, (10, 10))
    assert np.all(color[4, 1:9, 0] == 191) and np.all(color[5, 1:9, 0] == 64)
    assert drawn(color) == {(x, y) for x in range(1, 9) for y in (4, 5)}


@settings(deadline=None, max_examples=40)
@given(st.lists(st.floats(2, 60), min_size=4, max_size=4))
def test_wu_total_intensity_is_the_major_extent(ends):
    x0, y0, x1, y1 = ends
    color, _ = render(*raster_edge(x0, y0, x1, y1), MODE_ANTIALIAS, (64, 64))
    extent = max(abs(x1 - x0), abs(y1 - y0))
    # Rounding to uint8 moves each of the (at most 2 per column) pixels by half a level.
    assert abs(color[..., 0].sum() / 255 - extent) <= (extent + 2) / 255


@settings(deadline=None, max_examples=40)
@given(st.lists(st.floats(-5, 40), min_size=4, max_size=4), st.sampled_from([MODE_ANTIALIAS, MODE_PLAIN]))
def test_wu_and_plain_lines_are_symmetric(ends, mode):
    x0, y0, x1, y1 = ends
    assume(abs(x1 - x0) != abs(y1 - y0))
    forward, _ = render(*raster_edge(x0, y0, x1, y1), mode, (36, 36))
    backward, _ = render(*raster_edge(x1, y1, x0, y0), mode, (36, 36))
    transposed, _ = render(*raster_edge(y0, x0, y1, x1), mode, (36, 36))
    assert np.array_equal(forward, backward)
    assert np.array_equal(forward, transposed.transpose(1, 0, 2))


def test_wu_with_depth_test_blends_only_visible_pixels():
    depth = np.full((10, 10), np.inf, dtype=np.float32)
    depth[:, :5] = 0.1
    color, _ = render(*raster_edge(1.0, 4.75, 9.0, 4.75), MODE_ANTIALIAS | MODE_DEPTH_TEST, (10, 10), depth)
    assert drawn(color) == {(x, y) for x in range(5, 9) for y in (4, 5)}


def test_wu_blends_into_the_existing_colour():
    background = np.full((10, 10, 3), 100, dtype=np.uint8)
    edge = raster_edge(1.0, 4.75, 9.0, 4.75)
    color, _ = render(*edge, MODE_ANTIALIAS, (10, 10), rgba=[200, 0, 100], color=background)
    # Row 4 gets weight 3/4, row 5 weight 1/4.
    assert color[4, 3].tolist() == [175, 25, 100] and color[5, 3].tolist() == [125, 75, 100]


# --- draw_edges: threads and bands ---------------------------------------------------------------


def random_mesh_edges(rng, n_vertices=300, n_edges=600):
    clip = np.empty((n_vertices, 4))
    clip[:, 3] = rng.uniform(0.2, 2.0, n_vertices)
    clip[:, 0] = rng.uniform(-20, 90, n_vertices) * clip[:, 3]
    clip[:, 1] = rng.uniform(-20, 70, n_vertices) * clip[:, 3]
    clip[:, 2] = rng.uniform(-0.2, 1.1, n_vertices) * clip[:, 3]
    return clip, rng.integers(0, n_vertices, (n_edges, 2))


@pytest.mark.parametrize("mode", ALL_MODES)
def test_image_is_bit_identical_for_any_number_of_threads_and_bands(mode):
    clip, edges = random_mesh_edges(np.random.default_rng(mode))
    shape = (50, 70)
    depth = np.random.default_rng(99).uniform(0, 1, shape).astype(np.float32)
    serial, _ = render(clip, edges, mode, shape, depth, bias=0.01, n_bands=1, threads=1)
    for n_bands in (2, 3, 7, 50, 51):
        parallel, _ = render(clip, edges, mode, shape, depth, bias=0.01, n_bands=n_bands,
                             threads=min(2, _threads.MAX_THREADS))
        assert np.array_equal(serial, parallel)
    assert serial.any()


# --- draw.lines: the public batch form -------------------------------------------------------


def test_lines_batch_equals_single_lines_clipped_to_the_image():
    rng = np.random.default_rng(11)
    segs = rng.integers(-30, 70, size=(300, 4))
    image = np.zeros((40, 50, 3), np.uint8)
    rasterkit.draw.lines(image, segs, color="white")
    expected = np.zeros((40, 50), bool)
    for x0, y0, x1, y1 in segs:
        xy = line(int(x0), int(y0), int(x1), int(y1))
        keep = (xy[:, 0] >= 0) & (xy[:, 0] < 50) & (xy[:, 1] >= 0) & (xy[:, 1] < 40)
        expected[xy[keep, 1], xy[keep, 0]] = True
    assert np.array_equal(image[..., 0] == 255, expected)


def test_lines_accepts_pairs_floats_rgba_and_skips_nan():
    image = np.zeros((8, 8, 4), np.uint8)
    rasterkit.draw.lines(image, [[[0.9, 0.2], [7.5, 0.7]], [[np.nan, 0], [3, 3]]], color=(1, 2, 3, 4))
    assert image[0].tolist() == [[1, 2, 3, 4]] * 8 and not image[1:].any()
    with pytest.raises(ValueError):
        rasterkit.draw.lines(np.zeros((8, 8), np.uint8), [[0, 0, 1, 1]])
    with pytest.raises(ValueError):
        rasterkit.draw.lines(np.zeros((8, 8, 3), np.uint8), [[0, 0, 1]])
    with pytest.raises(ValueError):
        rasterkit.draw.lines(np.zeros((8, 8, 3), np.uint8)[:, ::2], [[0, 0, 1, 1]])


def test_an_edge_whose_visible_part_reaches_the_eyes_plane_is_left_to_the_kernel():
    """Found by the property test above: an end on the near plane at the eye's x, y and one
    behind the eye keep, exactly, one point and the eye's plane (w = 0), which the exact clip
    drops and the kernel's float clip keeps as a pixel; the comparison leaves such edges out,
    and only such."""
    p, behind = np.array([0.0, 0.0, 0.0, 1.0]), np.array([0.0, 0.0, 0.0, -0.5])
    assert ambiguous_edge(p, behind)
    assert not ambiguous_edge(p, np.array([3.0, 2.0, 0.5, 1.0]))
    assert not ambiguous_edge(np.array([3.3, 2.2, 0.5, 1.0]), np.array([3.3, 2.2, 0.5, -1.0]))  # cut at w = 0.5
