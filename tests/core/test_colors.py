"""Colour arguments: what is accepted, and one-line errors for everything else."""

import numpy as np
import pytest

from rasterkit.colors import parse_color


@pytest.mark.parametrize("value, rgba", [
    ("#ff8000", [255, 128, 0, 255]), ("#f80", [255, 136, 0, 255]), ("#01020304", [1, 2, 3, 4]),
    (" Navy ", [0, 0, 128, 255]), ((1, 2, 3), [1, 2, 3, 255]), ([np.int64(5), np.uint8(2), 3, 4], [5, 2, 3, 4]),
    ((255.0, 0.0, 7.0), [255, 0, 7, 255]), (np.array([9, 8, 7]), [9, 8, 7, 255]),
])
def test_accepted(value, rgba):
    assert parse_color(value).tolist() == rgba


@pytest.mark.parametrize("value, error", [
    ((0.5, 0, 0), ValueError), (("1", 2, 3), TypeError), ((True, 0, 0), TypeError), ((1, 2), ValueError),
    ((1, 2, 3, 4, 5), ValueError), (5, TypeError), (None, TypeError), ((300, 0, 0), ValueError),
    ((-1, 0, 0), ValueError), ((float("nan"), 0, 0), ValueError), ((1j, 0, 0), TypeError), ("x" * 500, ValueError),
    ("#12345", ValueError), (np.zeros((40, 40)), ValueError), ((None, 0, 0), TypeError),
])
def test_refused_in_one_short_line(value, error):
    with pytest.raises(error) as caught:
        parse_color(value)
    message = str(caught.value)
    assert "\n" not in message and len(message) < 120
