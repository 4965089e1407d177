"""Framebuffer clearing and saving, colour parsing, atomic image writing."""

import numpy as np
import pytest
from PIL import Image

from rasterkit.colors import parse_color
from rasterkit.raster.framebuffer import Framebuffer
from rasterkit.image import save_animation, save_image


def test_colours_parse_names_hex_and_tuples():
    assert parse_color("#102030").tolist() == [16, 32, 48, 255]
    assert parse_color("#abc").tolist() == [0xAA, 0xBB, 0xCC, 255]
    assert parse_color("#10203040").tolist() == [16, 32, 48, 64]
    assert parse_color(" White ").tolist() == [255, 255, 255, 255]
    assert parse_color((1, 2, 3, 4)).tolist() == [1, 2, 3, 4]
    for bad in ["#12345", "#gggggg", "chartreuse-ish", (1, 2), (0, 0, 256)]:
        with pytest.raises(ValueError):
            parse_color(bad)
    for bad in [("a", 1, 2), 7]:  # not colours at all (tests/core/test_colors.py has the rest)
        with pytest.raises(TypeError):
            parse_color(bad)


def test_framebuffer_clears_to_background_and_farthest():
    fb = Framebuffer(5, 3, background="#010203", ids=True)
    assert fb.color.shape == (3, 5, 3) and fb.color.dtype == np.uint8
    assert np.all(fb.color == [1, 2, 3])
    assert fb.depth.dtype == np.float32 and np.all(np.isposinf(fb.depth))
    assert fb.ids.dtype == np.int32 and np.all(fb.ids == -1)
    fb.color[...] = 9
    fb.depth[...] = 0.5
    fb.ids[...] = 4
    fb.clear()
    assert np.all(fb.color == [1, 2, 3]) and np.all(np.isposinf(fb.depth)) and np.all(fb.ids == -1)


def test_transparent_background_gives_rgba(tmp_path):
    fb = Framebuffer(4, 2, background="transparent")
    assert fb.alpha and fb.color.shape == (2, 4, 4) and np.all(fb.color == 0)
    fb.save(tmp_path / "t.png")
    with Image.open(tmp_path / "t.png") as im:
        assert im.mode == "RGBA" and im.size == (4, 2)


@pytest.mark.parametrize("size", [(0, 4), (4, 0), (2.5, 4), (40000, 1), (True, 3)])
def test_framebuffer_rejects_bad_sizes(size):
    with pytest.raises(ValueError):
        Framebuffer(*size)


def test_png_round_trip_and_repr_png(tmp_path):
    fb = Framebuffer(3, 2)
    fb.color[1, 2] = (255, 0, 0)
    fb.save(tmp_path / "a.png")
    with Image.open(tmp_path / "a.png") as im:
        assert np.array_equal(np.asarray(im), fb.color)
    assert fb._repr_png_().startswith(b"\x89PNG")


def test_failed_write_leaves_neither_partial_file_nor_replaces_a_good_one(tmp_path):
    target = tmp_path / "out.png"
    target.write_bytes(b"good")
    with pytest.raises(ValueError):
        save_image(np.zeros((2, 2), np.float64), target)  # not an image
    with pytest.raises(ValueError):
        save_image(np.zeros((2, 2, 3), np.uint8), tmp_path / "out.jpg")
    assert target.read_bytes() == b"good"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.png"]


def test_animation_gif_and_apng(tmp_path):
    frames = [np.full((4, 4, 3), i * 60, np.uint8) for i in range(4)]
    for name in ["a.gif", "a.png"]:
        save_animation(frames, tmp_path / name, fps=10)
        with Image.open(tmp_path / name) as im:
            assert im.n_frames == 4


@pytest.mark.parametrize("shape", [(1, 1, 3), (1, 1, 4), (7, 5, 3), (33, 17, 4), (480, 641, 3)])
def test_encode_png_round_trips_through_pillow(shape):
    import io

    from PIL import Image

    from rasterkit.image import encode_png

    pixels = np.random.default_rng(sum(shape)).integers(0, 256, shape, dtype=np.uint8)
    data = encode_png(pixels)
    with Image.open(io.BytesIO(data)) as image:
        image.verify()  # CRCs and structure
    with Image.open(io.BytesIO(data)) as image:
        assert image.mode == ("RGB" if shape[2] == 3 else "RGBA")
        assert np.array_equal(np.asarray(image), pixels)


def test_encode_png_rejects_what_it_cannot_write():
    from rasterkit.image import encode_png

    for bad in (np.zeros((2, 2, 3), np.float32), np.zeros((2, 2), np.uint8), np.zeros((0, 2, 3), np.uint8),
                np.zeros((2, 2, 2), np.uint8)):
        with pytest.raises(ValueError):
            encode_png(bad)


def test_encode_png_splits_a_long_stream_into_several_idat_chunks(monkeypatch):
    import io

    from PIL import Image

    from rasterkit.image import files as image

    pixels = np.random.default_rng(3).integers(0, 256, (40, 50, 3), dtype=np.uint8)
    monkeypatch.setattr(image, "_IDAT_BYTES", 1000)
    data = image.encode_png(pixels)
    assert data.count(b"IDAT") > 3
    with Image.open(io.BytesIO(data)) as decoded:
        assert np.array_equal(np.asarray(decoded), pixels)
