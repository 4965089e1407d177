"""The texture sampling kernels (rasterkit.material.kernels.sample, through
rasterkit.material.sampling.sample) against hand-made images with known answers and against
the GL specification's lookup written out in tests/support/reference_texture.py: every filter
and wrap, odd and non-square sizes, RGB and RGBA, sRGB and linear; and hostile coordinates."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from rasterkit.material import Texture
from rasterkit.material.kernels.sample import lod_from_derivatives, texture_lod
from rasterkit.material.sampling import sample, texture_args
from support.reference_texture import Reference, linear_to_srgb, srgb_to_linear

FILTERS = ("nearest", "bilinear", "trilinear")
WRAPS = ("repeat", "clamp", "mirror")

RED, GREEN, BLUE, WHITE = (255, 0, 0), (0, 255, 0), (0, 0, 255), (255, 255, 255)
#: Top row red, green; bottom row blue, white: (u, v) = (0, 0) is the bottom-left corner, blue.
QUAD = np.array([[RED, GREEN], [BLUE, WHITE]], np.uint8)


def texture(image, **settings):
    return Texture(np.asarray(image, np.uint8), **settings)


def reference_of(tex: Texture) -> Reference:
    levels = [tex.mipmaps.level(k) for k in range(len(tex.mipmaps.levels))]
    return Reference(levels, tex.srgb, tex.filter, tex.wrap, tex.scale, tex.offset)


# --- hand-made images -----------------------------------------------------------------------

@pytest.mark.parametrize("filter", FILTERS)
def test_v_runs_up_and_u_to_the_right(filter):
    """The centre of each texel of the 2x2 image reads that texel exactly, with v up."""
    tex = texture(QUAD, filter=filter, srgb=False)
    got = sample(tex, [[0.25, 0.25], [0.75, 0.25], [0.25, 0.75], [0.75, 0.75]])
    expected = np.array([BLUE, WHITE, RED, GREEN]) / 255.0
    np.testing.assert_array_equal(got[:, :3], expected.astype(np.float32))
    np.testing.assert_array_equal(got[:, 3], 1.0)


def test_nearest_takes_the_texel_that_contains_the_point():
    tex = texture(QUAD, filter="nearest", srgb=False)
    # just inside each quadrant's corner
    got = sample(tex, [[0.0, 0.0], [0.4999, 0.4999], [0.5, 0.5], [0.9999, 0.0], [0.0, 0.9999]])
    expected = np.array([BLUE, BLUE, GREEN, WHITE, RED]) / 255.0
    np.testing.assert_array_equal(got[:, :3], expected.astype(np.float32))


def test_bilinear_in_the_middle_is_the_mean_in_linear_light():
    tex = texture(QUAD, filter="bilinear", wrap="clamp")
    r, g, b, a = sample(tex, [[0.5, 0.5]])[0]
    # each channel is 255 in two of the four texels: a mean of 0.5 in linear light
    assert (r, g, b, a) == (np.float32(0.5),) * 3 + (np.float32(1.0),)
    assert round(linear_to_srgb(0.5) * 255) == 188  # so the screen shows 188, not 128


def test_bilinear_weights_follow_texel_centres():
    """A 4x1 ramp of codes 0, 80, 160, 240 (linear data): between the centres of texels 1
    and 2 (u = 0.375 and 0.625) the value is linear in u."""
    ramp = np.array([[[0, 0, 0], [80, 80, 80], [160, 160, 160], [240, 240, 240]]], np.uint8)
    tex = texture(ramp, filter="bilinear", wrap="clamp", srgb=False)
    u = np.array([0.375, 0.4375, 0.5, 0.5625, 0.625])
    got = sample(tex, np.stack([u, np.full_like(u, 0.5)], axis=1))[:, 0]
    np.testing.assert_allclose(got, (80 + (u - 0.375) / 0.25 * 80) / 255, atol=1e-7)
    # outside the outer centres, clamp holds the edge texel
    np.testing.assert_allclose(sample(tex, [[0.0, 0.5], [1.0, 0.5]])[:, 0], [0.0, 240 / 255], atol=1e-7)


def test_wraps_on_a_ramp():
    ramp = np.array([[[0, 0, 0], [100, 100, 100], [200, 200, 200]]], np.uint8)
    centres = np.array([1, 3, 5]) / 6
    for wrap, shifts in [("repeat", {1.0: [0, 100, 200], -2.0: [0, 100, 200]}),
                         ("mirror", {1.0: [200, 100, 0], -1.0: [200, 100, 0], 2.0: [0, 100, 200]}),
                         ("clamp", {1.0: [200, 200, 200], -1.0: [0, 0, 0]})]:
        tex = texture(ramp, filter="nearest", wrap=wrap, srgb=False)
        for shift, codes in shifts.items():
            got = sample(tex, np.stack([centres + shift, np.full(3, 0.5)], axis=1))[:, 0]
            np.testing.assert_array_equal(got * 255, np.float32(codes), err_msg=f"{wrap} {shift}")


def test_repeat_blends_across_the_seam():
    """Bilinear with repeat at u = 0 mixes the first and the last texel half and half; with
    clamp it reads the first only."""
    ramp = np.array([[[0, 0, 0], [100, 100, 100], [200, 200, 200], [40, 40, 40]]], np.uint8)
    repeat = texture(ramp, filter="bilinear", srgb=False)
    clamp = repeat.replace(wrap="clamp")
    assert sample(repeat, [[0.0, 0.5]])[0, 0] == np.float32(20 / 255)
    assert sample(clamp, [[0.0, 0.5]])[0, 0] == np.float32(0.0)


def test_trilinear_blends_two_levels():
    """A 4x4 checker of black and white: level 2 (1x1) is their mean; lod 0 is bilinear on
    level 0, lod 2 the 1x1 level, lod 1.25 three quarters of level 1 and a quarter of level 2."""
    checker = (np.indices((4, 4)).sum(axis=0) % 2 * 255).astype(np.uint8)
    tex = texture(np.repeat(checker[:, :, None], 3, axis=2), filter="trilinear", srgb=False)
    assert [tex.mipmaps.level(k)[0, 0, 0] for k in range(3)] == [0, 128, 128]
    uv = [[0.125, 0.125]]  # the centre of the bottom-left texel, white
    assert sample(tex, uv, 0.0)[0, 0] == sample(tex.replace(filter="bilinear"), uv)[0, 0] == 1.0
    assert sample(tex, uv, 2.0)[0, 0] == np.float32(128 / 255)
    assert sample(tex, uv, 99.0)[0, 0] == np.float32(128 / 255)  # clamped to the last level
    assert sample(tex, uv, -3.0)[0, 0] == 1.0  # magnified: level 0
    level1 = sample(tex, uv, 1.0)[0, 0]
    assert sample(tex, uv, 1.25)[0, 0] == pytest.approx(0.75 * level1 + 0.25 * 128 / 255, abs=1e-7)


def test_rgba_alpha_is_linear_and_rgb_alpha_is_one():
    image = np.zeros((2, 2, 4), np.uint8)
    image[..., 3] = [[0, 255], [255, 0]]
    image[..., 0] = 255
    tex = texture(image, filter="bilinear", wrap="clamp")
    assert sample(tex, [[0.5, 0.5]])[0].tolist() == [1.0, 0.0, 0.0, 0.5]
    assert sample(texture(QUAD), [[0.3, 0.3]])[0, 3] == 1.0


def test_srgb_texels_come_back_as_linear_light():
    grey = np.full((1, 1, 3), 128, np.uint8)
    assert sample(texture(grey), [[0.5, 0.5]])[0, 0] == np.float32(srgb_to_linear(128))
    assert sample(texture(grey, srgb=False), [[0.5, 0.5]])[0, 0] == np.float32(128 / 255)


def test_scale_and_offset_apply_before_the_lookup():
    rng = np.random.default_rng(3)
    image = rng.integers(0, 256, (5, 7, 3), dtype=np.uint8)
    plain = texture(image, filter="bilinear")
    moved = plain.replace(scale=(2.0, -3.0), offset=(0.25, 0.1))
    uv = rng.uniform(-2, 2, (50, 2))
    np.testing.assert_array_equal(sample(moved, uv), sample(plain, uv * [2.0, -3.0] + [0.25, 0.1]))


# --- against the GL specification -----------------------------------------------------------

SIZES = [(1, 1), (2, 2), (4, 4), (5, 3), (3, 7), (1, 6), (8, 2), (6, 5)]


@pytest.mark.parametrize("filter,wrap", list(itertools.product(FILTERS, WRAPS)))
def test_every_filter_and_wrap_matches_the_reference(filter, wrap):
    rng = np.random.default_rng(hash((filter, wrap)) % 2**32)
    for (width, height), channels, srgb in itertools.product(SIZES, (3, 4), (True, False)):
        image = rng.integers(0, 256, (height, width, channels), dtype=np.uint8)
        tex = texture(image, filter=filter, wrap=wrap, srgb=srgb)
        ref = reference_of(tex)
        uv = np.concatenate([rng.uniform(-2.5, 2.5, (40, 2)),
                             # texel centres and edges of level 0 (ties of floor)
                             np.stack([np.arange(-1, 2 * width + 2) / (2 * width),
                                       np.resize(np.arange(-1, 2 * height + 2) / (2 * height), 2 * width + 3)], 1)])
        lod = np.concatenate([rng.uniform(-1, len(ref.levels) + 1, 40), np.resize([0, 0.5, 1, 1.5, np.nan], len(uv) - 40)])
        got = sample(tex, uv, lod)
        expected = np.array([ref.sample(u, v, d) for (u, v), d in zip(uv, lod)])
        np.testing.assert_allclose(got, expected, rtol=0, atol=1e-6,
                                   err_msg=f"{width}x{height}x{channels} srgb={srgb}")


@pytest.mark.parametrize("filter,wrap", list(itertools.product(FILTERS, WRAPS)))
def test_transformed_coordinates_match_the_reference(filter, wrap):
    rng = np.random.default_rng(11)
    image = rng.integers(0, 256, (6, 9, 4), dtype=np.uint8)
    tex = texture(image, filter=filter, wrap=wrap, scale=(1.5, -0.75), offset=(0.3, 2.2))
    ref = reference_of(tex)
    uv = rng.uniform(-3, 3, (200, 2))
    lod = rng.uniform(-0.5, 4.5, 200)
    expected = np.array([ref.sample(u, v, d) for (u, v), d in zip(uv, lod)])
    np.testing.assert_allclose(sample(tex, uv, lod), expected, rtol=0, atol=1e-6)


# --- hostile coordinates and levels ---------------------------------------------------------

HUGE = [1e300, -1e300, np.nan, np.inf, -np.inf, 2.0**62, -(2.0**62) - 0.5, 5e-324, -5e-324, 1e17 + 0.5]


@pytest.mark.parametrize("filter,wrap", list(itertools.product(FILTERS, WRAPS)))
def test_nan_inf_and_huge_coordinates_stay_inside(filter, wrap):
    """Every combination reads a texel of the image: the results are texel values or blends of
    them, finite, in [0, 1]; NaN reads as 0, and so do infinities where there is no edge."""
    rng = np.random.default_rng(5)
    image = rng.integers(0, 256, (3, 5, 4), dtype=np.uint8)
    tex = texture(image, filter=filter, wrap=wrap)
    uv = np.array(list(itertools.product(HUGE + [0.3], repeat=2)))
    for lod in (0.0, np.nan, np.inf, -np.inf, 1e300, 1.7):
        got = sample(tex, uv, lod)
        assert np.isfinite(got).all() and (got >= 0).all() and (got <= 1).all()
    undefined = [[np.nan, np.nan]] if wrap == "clamp" else [[np.nan, np.nan], [np.inf, -np.inf], [np.nan, np.inf]]
    np.testing.assert_array_equal(sample(tex, undefined, 0.5), sample(tex, np.zeros((len(undefined), 2)), 0.5))


def test_clamp_sends_huge_coordinates_to_the_edges():
    ramp = np.array([[[0, 0, 0], [100, 100, 100], [200, 200, 200]]], np.uint8)
    for filter in FILTERS:
        tex = texture(ramp, filter=filter, wrap="clamp", srgb=False)
        got = sample(tex, [[1e300, 0.5], [-1e300, 0.5], [np.inf, 0.5], [-np.inf, 0.5]], 0.0)[:, 0] * 255
        np.testing.assert_array_equal(got, np.float32([200, 0, 200, 0]), err_msg=filter)


def test_repeat_of_huge_whole_numbers_is_the_origin():
    tex = texture(QUAD, filter="nearest", srgb=False)
    for u in (1e300, -1e300, 2.0**60, -(2.0**60)):
        assert sample(tex, [[u, u]])[0, :3].tolist() == [0.0, 0.0, 1.0]  # (0, 0): blue


# --- level of detail ------------------------------------------------------------------------

def test_lod_from_derivatives_is_log2_of_the_longer_texel_step():
    cases = [((1 / 64, 0, 0, 1 / 64, 64, 64), 0.0), ((2 / 64, 0, 0, 1 / 64, 64, 64), 1.0),
             ((0, 0, 0, 4 / 32, 64, 32), 2.0), ((3 / 64, 4 / 64, 0, 0, 64, 64), math.log2(5)),
             ((0.25 / 16, 0, 0, 0.25 / 16, 16, 16), -2.0)]
    for args, expected in cases:
        assert lod_from_derivatives(*args) == pytest.approx(expected, abs=1e-12)
    rng = np.random.default_rng(2)
    for dudx, dvdx, dudy, dvdy in rng.normal(0, 0.05, (100, 4)):
        rho = max(math.hypot(dudx * 40, dvdx * 24), math.hypot(dudy * 40, dvdy * 24))
        assert lod_from_derivatives(dudx, dvdx, dudy, dvdy, 40, 24) == pytest.approx(math.log2(rho), abs=1e-12)
    assert lod_from_derivatives(0.0, 0.0, 0.0, 0.0, 8, 8) == -np.inf
    assert np.isnan(lod_from_derivatives(np.nan, 0.0, 0.0, 0.0, 8, 8))
    assert lod_from_derivatives(np.inf, 0.0, 0.0, 0.0, 8, 8) == np.inf


def test_texture_lod_uses_the_scale_and_level_zero():
    tex = texture(np.zeros((16, 64, 3), np.uint8), scale=(2.0, 4.0))
    args = texture_args([tex])
    lod = texture_lod(args.levels, args.samplers, args.transforms, 0, 1 / 64, 0.0, 0.0, 1 / 16)
    assert lod == pytest.approx(2.0)  # v steps 4 texels after the scale, u 2


def test_several_textures_in_one_set_sample_as_each_alone():
    rng = np.random.default_rng(8)
    textures = [texture(rng.integers(0, 256, (h, w, c), dtype=np.uint8), filter=f, wrap=r, srgb=s)
                for (w, h), c, f, r, s in [((4, 4), 3, "trilinear", "repeat", True), ((5, 3), 4, "bilinear", "mirror", False),
                                           ((2, 7), 3, "trilinear", "clamp", False)]]
    args = texture_args(textures)
    from rasterkit.material.kernels.sample import sample_points

    uv = rng.uniform(-2, 2, (60, 2))
    lod = rng.uniform(0, 3, 60)
    for t, tex in enumerate(textures):
        out = np.empty((60, 4), np.float32)
        sample_points(*args, t, uv, lod, out)
        np.testing.assert_array_equal(out, sample(tex, uv, lod))
    assert texture_args(textures[:1]).texels is textures[0].mipmaps.texels  # one texture: no copy


def test_sample_checks_its_arguments():
    tex = texture(QUAD)
    with pytest.raises(ValueError, match=r"uv must have shape \(N, 2\)"):
        sample(tex, [0.5, 0.5])
    with pytest.raises(ValueError, match="lod must be"):
        sample(tex, [[0.5, 0.5]], [0.0, 1.0])
    with pytest.raises(TypeError, match="uv"):
        sample(tex, [["a", "b"]])
