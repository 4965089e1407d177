"""Mipmaps (rasterkit.material.mipmaps) and the sRGB transfer functions they use
(rasterkit.material.colorspace): level sizes, the box filter in linear light against plain
references, odd sizes, the flat buffer's layout, and its memory."""

from __future__ import annotations

import numpy as np
import pytest

from rasterkit.material import Texture
from rasterkit.material.colorspace import DECODE, LINEAR_ROW, SRGB_ROW, decode_srgb, encode_srgb, encode_srgb8
from rasterkit.material.mipmaps import box_taps, build_mipmaps, level_sizes, mipmaps_bytes, reduce_level
from support.reference_texture import box_mean, linear_to_srgb, srgb_to_linear

# --- sRGB -----------------------------------------------------------------------------------


def test_decode_table_is_the_srgb_function():
    assert DECODE.shape == (2, 256) and not DECODE.flags.writeable
    np.testing.assert_array_equal(DECODE[LINEAR_ROW], np.arange(256) / 255)
    np.testing.assert_allclose(DECODE[SRGB_ROW], [srgb_to_linear(c) for c in range(256)], rtol=0, atol=1e-15)
    assert DECODE[SRGB_ROW][0] == 0.0 and DECODE[SRGB_ROW][255] == 1.0
    assert DECODE[SRGB_ROW][10] == pytest.approx(10 / 255 / 12.92)  # the linear toe
    assert DECODE[SRGB_ROW][188] == pytest.approx(0.5029, abs=1e-4)


def test_encode_rounds_to_the_nearest_code_and_inverts_decode():
    codes = np.arange(256)
    np.testing.assert_array_equal(encode_srgb8(decode_srgb(codes / 255)), codes)
    x = np.linspace(-0.5, 1.5, 20001)
    expected = [int(np.floor(linear_to_srgb(v) * 255 + 0.5)) for v in x]
    np.testing.assert_array_equal(encode_srgb8(x), expected)
    assert encode_srgb8(np.array([0.5]))[0] == 188 and encode_srgb8(np.array([0.2159]))[0] == 128


# --- sizes and taps ---------------------------------------------------------------------------

def test_encode_srgb_inverts_decode_and_clips():
    x = np.linspace(0.0, 1.0, 101)
    np.testing.assert_allclose(encode_srgb(decode_srgb(x)), x, atol=1e-12)
    np.testing.assert_array_equal(encode_srgb(np.array([-1.0, 1.0, 2.0])), [0.0, 1.0, 1.0])  # 1 exactly
    assert encode_srgb(np.float32([0.5])).dtype == np.float32


def test_level_sizes_are_opengls():
    assert level_sizes(1, 1) == [(1, 1)]
    assert level_sizes(8, 2) == [(8, 2), (4, 1), (2, 1), (1, 1)]
    assert level_sizes(5, 3) == [(5, 3), (2, 1), (1, 1)]
    assert level_sizes(1024, 1024)[-1] == (1, 1) and len(level_sizes(1024, 1024)) == 11
    for w, h in [(1000, 3), (7, 640), (1, 33)]:
        assert len(level_sizes(w, h)) == int(np.floor(np.log2(max(w, h)))) + 1


@pytest.mark.parametrize("n_in", [1, 2, 3, 4, 5, 7, 8, 9, 15, 33])
def test_taps_cover_every_input_texel_equally(n_in):
    n_out = max(1, n_in // 2)
    index, weight = box_taps(n_in, n_out)
    np.testing.assert_allclose(weight.sum(axis=1), 1.0, atol=1e-15)
    assert index.min() >= 0 and index.max() < n_in
    coverage = np.zeros(n_in)
    np.add.at(coverage, index, weight)
    np.testing.assert_allclose(coverage, n_out / n_in, atol=1e-15)  # each input counts the same
    if n_in % 2 == 0:
        assert (weight == [0.5, 0.5, 0.0]).all() and (index[:, 0] == 2 * np.arange(n_out)).all()


# --- the box filter ---------------------------------------------------------------------------

def _two_by_two(level: np.ndarray, srgb: bool) -> np.ndarray:
    """The next level of an even-sized level, plainly: ((a + b) + (c + d)) / 4 of each 2x2
    block, colours decoded from sRGB and encoded back, alpha rounded half up."""
    colour = 3
    linear = level.astype(np.float64)
    if srgb:
        linear[..., :colour] = decode_srgb(level[..., :colour] / 255.0)
    mean = ((linear[0::2, 0::2] + linear[0::2, 1::2]) + (linear[1::2, 0::2] + linear[1::2, 1::2])) / 4
    out = np.floor(mean + 0.5)
    if srgb:
        out[..., :colour] = [[[np.floor(linear_to_srgb(v) * 255 + 0.5) for v in px] for px in row]
                             for row in mean[..., :colour]]
    return out.astype(np.uint8)


@pytest.mark.parametrize("channels", [3, 4])
@pytest.mark.parametrize("srgb", [True, False])
def test_even_levels_are_two_by_two_means_bit_for_bit(channels, srgb):
    rng = np.random.default_rng(channels * 2 + srgb)
    image = rng.integers(0, 256, (16, 8, channels), dtype=np.uint8)
    chain = build_mipmaps(image, srgb)
    expected = image
    for k in range(1, 4):
        expected = _two_by_two(expected, srgb)
        np.testing.assert_array_equal(chain.level(k), expected, err_msg=f"level {k}")
    assert chain.level(4).shape == (1, 1, channels)


def test_a_black_and_white_block_gives_the_linear_mean():
    block = np.array([[[0] * 3, [255] * 3], [[255] * 3, [0] * 3]], np.uint8)
    assert build_mipmaps(block, srgb=True).level(1).tolist() == [[[188, 188, 188]]]
    assert build_mipmaps(block, srgb=False).level(1).tolist() == [[[128, 128, 128]]]  # 127.5 half up
    alpha = np.zeros((2, 2, 4), np.uint8)
    alpha[..., 3] = [[0, 255], [0, 1]]  # mean 64.0
    assert build_mipmaps(alpha, srgb=True).level(1)[0, 0, 3] == 64


@pytest.mark.parametrize("size", [(5, 3), (3, 7), (9, 9), (7, 1), (1, 5), (3, 3), (11, 6)])
@pytest.mark.parametrize("srgb", [True, False])
def test_odd_sizes_are_area_weighted_means(size, srgb):
    """Against a mean over each texel replicated: a reference that never splits a texel."""
    width, height = size
    rng = np.random.default_rng(width * 31 + height)
    level = rng.integers(0, 256, (height, width, 4), dtype=np.uint8)
    w2, h2 = max(1, width // 2), max(1, height // 2)
    linear = level.astype(np.float64)
    if srgb:
        linear[..., :3] = decode_srgb(level[..., :3] / 255.0)
    mean = box_mean(linear, w2, h2)
    got = reduce_level(level, w2, h2, srgb)
    for c in range(4):
        values = mean[..., c] * (255 if srgb and c < 3 else 1)
        if srgb and c < 3:
            values = np.vectorize(linear_to_srgb)(mean[..., c]) * 255
        tie = np.abs(values - np.floor(values) - 0.5) < 1e-9
        expected = np.floor(values + 0.5)
        assert (got[..., c] == expected)[~tie].all()
        assert (np.abs(got[..., c].astype(int) - expected) <= 1).all()


def test_a_3x3_level_becomes_the_mean_of_all_nine():
    values = np.arange(0, 90, 10, dtype=np.uint8).reshape(3, 3, 1)
    level = np.concatenate([values] * 4, axis=2)
    assert reduce_level(level, 1, 1, srgb=False).tolist() == [[[40, 40, 40, 40]]]


@pytest.mark.parametrize("size", [(5, 3), (3, 7), (6, 5), (1, 9)])
def test_odd_sizes_do_not_depend_on_which_way_up(size):
    rng = np.random.default_rng(1)
    level = rng.integers(0, 256, (size[1], size[0], 3), dtype=np.uint8)
    w2, h2 = max(1, size[0] // 2), max(1, size[1] // 2)
    np.testing.assert_array_equal(reduce_level(level[::-1], w2, h2, True)[::-1], reduce_level(level, w2, h2, True))
    np.testing.assert_array_equal(reduce_level(level[:, ::-1], w2, h2, True)[:, ::-1], reduce_level(level, w2, h2, True))


def test_a_flat_colour_stays_that_colour():
    for code in (0, 1, 17, 128, 200, 254, 255):
        chain = build_mipmaps(np.full((13, 6, 4), code, np.uint8), srgb=True)
        assert (chain.texels == code).all()


def test_large_levels_reduce_in_blocks_as_in_one(monkeypatch):
    import rasterkit.material.mipmaps as mipmaps

    rng = np.random.default_rng(4)
    level = rng.integers(0, 256, (37, 21, 4), dtype=np.uint8)
    whole = reduce_level(level, 10, 18, True)
    monkeypatch.setattr(mipmaps, "_BLOCK_VALUES", 200)  # a few rows at a time
    np.testing.assert_array_equal(reduce_level(level, 10, 18, True), whole)


# --- the buffer -------------------------------------------------------------------------------

def test_levels_share_one_flat_buffer_top_row_first():
    image = np.arange(4 * 6 * 3, dtype=np.uint8).reshape(4, 6, 3)
    chain = build_mipmaps(image, srgb=False)
    assert chain.texels.ndim == 1 and chain.texels.dtype == np.uint8 and not chain.texels.flags.writeable
    assert chain.levels.dtype == np.int64 and not chain.levels.flags.writeable
    assert chain.levels.tolist() == [[0, 6, 4], [72, 3, 2], [90, 1, 1]]
    assert len(chain.texels) == 72 + 18 + 3
    np.testing.assert_array_equal(chain.texels[:18], image[0].ravel())  # the top row first, as in the image
    np.testing.assert_array_equal(chain.level(0), image)
    chain.check_intact()
    chain.texels.shape = (3, 31)
    with pytest.raises(ValueError, match="changed in place"):
        chain.check_intact()


def test_texture_builds_its_mipmaps_once_and_shares_them():
    tex = Texture(np.zeros((8, 8, 3), np.uint8))
    assert tex.mipmaps is tex.mipmaps
    assert tex.replace(filter="nearest", wrap="mirror").mipmaps is tex.mipmaps
    data = tex.replace(srgb=False)
    assert data.mipmaps is not tex.mipmaps and data.mipmaps.srgb is False
    assert data.replace(srgb=True).mipmaps is tex.mipmaps


def test_a_texture_holds_its_pixels_once_with_its_mipmaps():
    """The issue's bar: a texture and its mipmaps cost at most 1.4x the texture's pixels. Once
    the chain is built, the image is a view of its level 0 (the same pixels, still read-only)."""
    image = np.random.default_rng(0).integers(0, 256, (256, 192, 3), dtype=np.uint8)
    tex = Texture(image)
    chain = tex.mipmaps
    np.testing.assert_array_equal(tex.image, image)
    assert np.shares_memory(tex.image, chain.texels) and not tex.image.flags.writeable
    assert chain.texels.nbytes <= 1.4 * image.nbytes  # all the texture holds: the image is in it
    with pytest.raises(ValueError):
        tex.image.flags.writeable = True  # a view of bytes: no one can write into it


@pytest.mark.parametrize("size", [(4, 4), (5, 7), (64, 64), (1024, 1024), (1000, 600), (640, 4), (4, 333), (2, 2)])
@pytest.mark.parametrize("channels", [3, 4])
def test_mipmaps_take_at_most_1_4_times_the_image(size, channels):
    width, height = size
    base = width * height * channels
    texels = sum(w * h for w, h in level_sizes(width, height)) * channels
    assert texels <= 1.4 * base
    assert texels <= 4 / 3 * base + 2 * max(width, height) * channels  # strips too (see the module)
    if size == (1024, 1024):
        assert texels / base == pytest.approx(4 / 3, abs=1e-6)
        chain = Texture(np.zeros((height, width, channels), np.uint8)).mipmaps
        assert chain.nbytes <= 1.4 * base and len(chain.texels) == texels
    assert mipmaps_bytes(width, height, channels) >= texels


def test_strips_keep_the_stated_bound():
    for width, height in [(256, 1), (1, 1000), (1025, 3)]:
        texels = sum(w * h for w, h in level_sizes(width, height))
        assert texels <= 4 / 3 * width * height + 2 * max(width, height)
