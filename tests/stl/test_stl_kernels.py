"""The STL reader's kernels against slow, obvious references: welding (the hash table, its
retries, and the sort it falls back to when corners are made to collide) and the facet
normals."""

import time

import numpy as np
import pytest

from rasterkit.stl.kernels import mesh as kernels
from rasterkit.stl.weld import weld_by_sorting, weld_corners
from support.stlfiles import reference_weld


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("distinct", [3, 40, 10_000])
def test_weld_numbers_rows_by_first_appearance(dtype, distinct):
    rng = np.random.default_rng(distinct)
    corners = rng.integers(0, distinct, (3000, 3)).astype(dtype) / dtype(7)
    corners[rng.random(3000) < 0.1] *= -1  # -0.0 among them
    inverse, first = weld_corners(corners)
    expected_inverse, expected_first = reference_weld(corners)
    assert np.array_equal(inverse, expected_inverse) and np.array_equal(first, expected_first)
    assert (corners[first][inverse] == corners).all()


def test_weld_asks_for_a_larger_table_when_the_vertices_do_not_fit():
    keys = np.arange(30, dtype=np.uint32).reshape(10, 3)
    assert kernels.weld(keys, 3)[2] == kernels.FULL
    inverse, first, n = kernels.weld(keys, 5)
    assert n == 10 and inverse.tolist() == list(range(10)) and first.tolist() == list(range(10))


def colliding_keys(n):
    """n distinct rows of uint64 whose hash, before the finaliser, is one value: each lands in
    the same slot, whatever the table's size."""
    m1, m2, m3 = (int(kernels.M1), int(kernels.M2), int(kernels.M3))
    inverse_m3, mask = pow(m3, -1, 2**64), 2**64 - 1
    rows = []
    for a in range(1, 10 * n):
        c = ((0x1234 ^ (a * m1 & mask) ^ (7 * m2 & mask)) * inverse_m3) & mask
        if np.isfinite(np.uint64(c).view(np.float64)) and c != 1 << 63:
            rows.append((a, 7, c))
        if len(rows) == n:
            return np.array(rows, np.uint64)


def test_weld_gives_up_on_corners_made_to_collide_and_the_driver_sorts_them_instead():
    keys = colliding_keys(3000)
    assert kernels.weld(keys, 16)[2] == kernels.COLLIDING
    corners = np.concatenate([keys, keys[::-1]]).view(np.float64)
    start = time.perf_counter()
    inverse, first = weld_corners(corners)
    assert time.perf_counter() - start < 5
    expected_inverse, expected_first = reference_weld(corners)
    assert np.array_equal(inverse, expected_inverse) and np.array_equal(first, expected_first)


def test_weld_by_sorting_agrees_with_the_hash_table():
    rng = np.random.default_rng(1)
    corners = rng.integers(0, 50, (5000, 3)).astype(np.float32)
    keys = corners.view(np.uint32)
    inverse, first = weld_corners(corners)
    inverse_sorted, first_sorted = weld_by_sorting(keys)
    assert np.array_equal(inverse, inverse_sorted) and np.array_equal(first, first_sorted)


def test_facet_flaws():
    corners = np.zeros((5, 3, 3), np.float32)
    corners[:] = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
    corners[1, 2, 0], corners[3, 0, 1] = np.nan, -np.inf
    corners[2, 2] = corners[2, 0]
    corners[4, 1] = [-0.0, 0, 0]  # equal to corner 0 as a number
    corners[3, 1] = corners[3, 2]  # both: not finite first
    assert kernels.facet_flaws(corners).tolist() == [kernels.SOUND, kernels.NOT_FINITE, kernels.TWO_EQUAL,
                                                     kernels.NOT_FINITE, kernels.TWO_EQUAL]


def test_facet_normals_of_huge_and_tiny_facets_are_unit_vectors():
    vertices = np.array([[0, 0, 0], [1e300, 0, 0], [0, 1e300, 0], [1e-300, 0, 0], [0, 1e-300, 0],
                         [1, 1, 1], [2, 2, 2]], np.float64)
    faces = np.array([[0, 1, 2], [0, 3, 4], [0, 5, 6]])
    out = np.empty((3, 3))
    given = np.array([[0, 0, 0], [0, 0, 0], [0, 0, 0]], np.float64)
    assert kernels.facet_normals(given, vertices, faces, out) == (3, 0)
    assert out.tolist() == [[0, 0, 1], [0, 0, 1], [0, 0, 0]]  # the last facet's corners are on one line
    given = np.array([[0, 0, 1e300], [0, 0, -2], [3, 4, 0]], np.float64)
    assert kernels.facet_normals(given, vertices, faces, out) == (0, 1)
    assert np.allclose(out, [[0, 0, 1], [0, 0, 1], [0.6, 0.8, 0]], rtol=0, atol=1e-15)
