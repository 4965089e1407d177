"""Clearing colour bytes to a repeated background (rasterkit.raster.kernels.clear), against NumPy:
any byte range, any alignment of the buffer and of the range's ends."""

import numba
import numpy as np
import pytest

from rasterkit.raster.kernels.clear import PATTERN_BYTES, background_pattern, fill_bytes
from rasterkit.runtime.intrinsics import load_word, store_word


@numba.njit
def _fill(flat, lo, hi, background):
    fill_bytes(flat, lo, hi, background_pattern(background))


@numba.njit
def _words(flat, offsets, values):
    out = np.empty(offsets.size, np.uint64)
    for k in range(offsets.size):
        store_word(flat, offsets[k], values[k])
        out[k] = load_word(flat, offsets[k])
    return out


@pytest.mark.parametrize("channels", [1, 2, 3, 4])
def test_fill_bytes_sets_exactly_the_range_to_the_repeated_background(channels):
    rng = np.random.default_rng(channels)
    background = rng.integers(0, 256, channels).astype(np.uint8)
    for _ in range(200):
        size = int(rng.integers(0, 300))
        lo, hi = sorted(int(v) for v in rng.integers(0, size + 1, 2))
        start = int(rng.integers(0, 8))  # the buffer itself at any byte alignment
        memory = rng.integers(0, 256, size + start).astype(np.uint8)
        flat = memory[start:]
        expected = flat.copy()
        expected[lo:hi] = np.resize(background, PATTERN_BYTES)[np.arange(lo, hi) % PATTERN_BYTES]
        _fill(flat, lo, hi, background)
        np.testing.assert_array_equal(flat, expected)


def test_store_word_and_load_word_are_unaligned_native_uint64():
    memory = np.zeros(40, np.uint8)
    flat = memory[3:]  # not 8-byte aligned
    offsets = np.array([0, 9, 19, 27], np.int64)  # apart, at odd places
    values = np.array([0x0102030405060708, 2**64 - 1, 0, 0x8000000000000001], np.uint64)
    np.testing.assert_array_equal(_words(flat, offsets, values), values)
    for offset, value in zip(offsets, values):
        assert flat[offset: offset + 8].view(np.uint64)[0] == value  # NumPy reads the same bytes
    written = np.zeros(flat.size, bool)
    for offset in offsets:
        written[offset: offset + 8] = True
    assert memory[:3].sum() == 0 and flat[~written].sum() == 0  # nothing outside the words
