"""rasterkit._arrays.finite_bounds against the box of the finite rows worked out row by row."""

from __future__ import annotations

import numpy as np
import pytest

from rasterkit._arrays import finite_bounds


def rows_box(points):
    finite = [row for row in points.tolist() if all(np.isfinite(row))]
    if not finite:
        return None
    return np.array([min(c) for c in zip(*finite)]), np.array([max(c) for c in zip(*finite)])


@pytest.mark.parametrize("spoil", [None, np.nan, np.inf, -np.inf])
def test_the_box_is_that_of_the_finite_rows(spoil):
    rng = np.random.default_rng(7)
    points = rng.normal(size=(500, 3)) * [1.0, 10.0, 0.1]
    if spoil is not None:
        points[[3, 250, 499], [0, 2, 1]] = spoil
    low, high = finite_bounds(points)
    expected = rows_box(points)
    np.testing.assert_array_equal(low, expected[0])
    np.testing.assert_array_equal(high, expected[1])


def test_no_finite_row_gives_none():
    assert finite_bounds(np.zeros((0, 3))) is None
    assert finite_bounds(np.array([[np.nan, 0.0, 0.0], [1.0, np.inf, 2.0]])) is None
