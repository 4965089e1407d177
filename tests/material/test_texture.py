"""rasterkit.Texture: the record (checks, immutability, copies, pickling) and Texture.open
(rasterkit.material.images): PNG, JPEG, TGA and BMP in their modes, and every way a file can
be refused, each as one line naming it."""

from __future__ import annotations

import io
import os
import pickle
import struct
import warnings
import zlib

import numpy as np
import pytest
from PIL import Image

import rasterkit
from rasterkit import limits
from rasterkit.material import Texture, TextureError, TextureLimitError

RNG = np.random.default_rng(7)
PICTURE = RNG.integers(0, 256, (5, 7, 4), dtype=np.uint8)


@pytest.fixture
def restore_limits():
    yield
    limits.set_memory_limit(None)
    limits.set_max_file_size(None)


def save(tmp_path, name, image: Image.Image, **options):
    path = tmp_path / name
    image.save(path, **options)
    return path


# --- the record -------------------------------------------------------------------------------

def test_public_names_and_defaults():
    tex = rasterkit.Texture(PICTURE[..., :3])
    assert (tex.filter, tex.wrap, tex.scale, tex.offset, tex.srgb, tex.name) == \
        ("trilinear", "repeat", (1.0, 1.0), (0.0, 0.0), True, None)
    assert (tex.width, tex.height, tex.channels) == (7, 5, 3)
    assert repr(tex) == ("Texture(7x5 RGB, filter='trilinear', wrap='repeat', scale=(1.0, 1.0), "
                         "offset=(0.0, 0.0), srgb=True)")


def test_the_image_is_a_sealed_copy():
    source = PICTURE.copy()
    tex = Texture(source)
    source[:] = 0
    np.testing.assert_array_equal(tex.image, PICTURE)
    assert not tex.image.flags.writeable
    with pytest.raises(ValueError):
        tex.image.flags.writeable = True
    with pytest.raises(AttributeError):
        tex.filter = "nearest"
    assert Texture(tex.image).image is tex.image  # sealed already: kept


def test_float_images_round_to_the_nearest_code():
    floats = np.array([[[0.0, 0.5, 1.0], [1 / 255, 0.499 / 255, 0.501 / 255]]])
    assert Texture(floats).image.tolist() == [[[0, 128, 255], [1, 0, 1]]]
    assert Texture(floats.astype(np.float32)).image.dtype == np.uint8


@pytest.mark.parametrize("image,error,match", [
    (np.zeros((4, 4), np.uint8), ValueError, r"shape \(H, W, 3\) or \(H, W, 4\)"),
    (np.zeros((4, 4, 2), np.uint8), ValueError, "shape"),
    (np.zeros((0, 4, 3), np.uint8), ValueError, "shape"),
    (np.zeros((2, 2, 3), np.int32), TypeError, "uint8 codes or floats"),
    (np.zeros((2, 2, 3), bool), TypeError, "dtype bool"),
    (np.full((2, 2, 3), 1.5), ValueError, r"lie in \[0, 1\]"),
    (np.full((2, 2, 3), np.nan), ValueError, "finite"),
    ([[[0, 0, 0]]], TypeError, "NumPy array"),
    (None, TypeError, "NumPy array"),
])
def test_bad_images_are_refused(image, error, match):
    with pytest.raises(error, match=match):
        Texture(image)


@pytest.mark.parametrize("settings,error,match", [
    (dict(filter="linear"), ValueError, "filter must be one of 'trilinear', 'bilinear', 'nearest'"),
    (dict(wrap="clamp_to_edge"), ValueError, "wrap must be one of"),
    (dict(wrap=None), ValueError, "wrap must be one of"),
    (dict(scale=(1.0,)), TypeError, r"scale must be a pair \(u, v\)"),
    (dict(scale="11"), TypeError, "scale must be a pair"),
    (dict(offset=(0.0, np.inf)), ValueError, "offset must be a finite number"),
    (dict(offset=(0.0, True)), TypeError, "offset must be a number"),
    (dict(srgb=1), TypeError, "srgb must be True or False"),
    (dict(name=3), TypeError, "name must be a string"),
])
def test_bad_settings_are_refused(settings, error, match):
    with pytest.raises(error, match=match):
        Texture(PICTURE, **settings)


def test_replace_changes_settings_and_shares_the_image():
    tex = Texture(PICTURE, name="x.png")
    other = tex.replace(filter="nearest", scale=(2, 3))
    assert other.image is tex.image and other.name == "x.png"
    assert (other.filter, other.scale, tex.filter) == ("nearest", (2.0, 3.0), "trilinear")
    with pytest.raises(TypeError, match="unknown texture setting 'image'"):
        tex.replace(image=PICTURE)
    with pytest.raises(ValueError, match="wrap"):
        tex.replace(wrap="tile")


def test_textures_compare_by_identity_and_pickle_sealed():
    tex = Texture(PICTURE, wrap="mirror", offset=(0.5, 0.25), srgb=False, name="a.png")
    assert tex != Texture(PICTURE, wrap="mirror", offset=(0.5, 0.25), srgb=False, name="a.png")
    assert len({tex, tex}) == 1
    back = pickle.loads(pickle.dumps(tex))
    np.testing.assert_array_equal(back.image, PICTURE)
    assert (back.wrap, back.offset, back.srgb, back.name) == ("mirror", (0.5, 0.25), False, "a.png")
    with pytest.raises(ValueError):
        back.image.flags.writeable = True


def test_a_texture_too_large_for_the_memory_limit_is_refused(restore_limits):
    limits.set_memory_limit("1K")
    with pytest.raises(limits.LimitError, match="a 64x64 texture needs about"):
        Texture(np.zeros((64, 64, 3), np.uint8))


# --- reading files ----------------------------------------------------------------------------

@pytest.mark.parametrize("mode,expected_channels", [("RGB", 3), ("RGBA", 4), ("L", 3), ("LA", 4), ("P", 3),
                                                    ("1", 3), ("CMYK", 3)])
@pytest.mark.parametrize("fmt", ["png", "tga", "bmp", "jpg"])
def test_modes_become_rgb_or_rgba(tmp_path, mode, expected_channels, fmt):
    source = Image.fromarray(PICTURE if expected_channels == 4 else PICTURE[..., :3]).convert(mode)
    try:
        path = save(tmp_path, f"t.{fmt}", source)
    except (OSError, ValueError):
        pytest.skip(f"Pillow does not write {mode} as {fmt}")
    if (fmt, mode) == ("bmp", "RGBA"):
        expected_channels = 3  # Pillow writes 32-bit BMP as BI_RGB: its fourth byte is no alpha
    tex = Texture.open(path)
    assert tex.image.shape == (5, 7, expected_channels) and tex.name == str(path)
    expected = np.asarray(Image.open(path).convert("RGBA" if expected_channels == 4 else "RGB"))
    np.testing.assert_array_equal(tex.image, expected)
    if fmt != "jpg" and mode in ("RGB", "RGBA"):
        np.testing.assert_array_equal(tex.image, PICTURE[..., :expected_channels])  # lossless


def test_palette_transparency_gives_rgba(tmp_path):
    image = Image.fromarray(PICTURE[..., :3]).convert("P")
    path = save(tmp_path, "p.png", image, transparency=0)
    tex = Texture.open(path)
    assert tex.channels == 4 and (tex.image[..., 3] == np.where(np.asarray(image) == 0, 0, 255)).all()


def test_sixteen_bit_grey_is_scaled_not_clipped(tmp_path):
    grey = np.array([[0, 257, 1000, 32896, 65535]], np.uint16)
    path = save(tmp_path, "g16.png", Image.fromarray(grey))
    assert Texture.open(path).image[0, :, 0].tolist() == [0, 1, 4, 128, 255]


def _tga(width, height, rows_bottom_first: bytes, descriptor=0) -> bytes:
    header = struct.pack("<BBBHHBHHHHBB", 0, 0, 2, 0, 0, 0, 0, 0, width, height, 24, descriptor)
    return header + rows_bottom_first


def test_tga_origins_are_read_the_right_way_up(tmp_path):
    """A hand-written 1x2 TGA: blue above red. Stored bottom row first (origin bottom-left,
    the default) or top row first (descriptor bit 5); the image has the blue row first."""
    blue, red = bytes([255, 0, 0]), bytes([0, 0, 255])  # BGR
    (tmp_path / "bl.tga").write_bytes(_tga(1, 2, red + blue))
    (tmp_path / "tl.tga").write_bytes(_tga(1, 2, blue + red, descriptor=0x20))
    for name in ("bl.tga", "tl.tga"):
        assert Texture.open(tmp_path / name).image[:, 0].tolist() == [[0, 0, 255], [255, 0, 0]], name


def test_rle_tga_reads_as_pillow_writes_it(tmp_path):
    path = save(tmp_path, "rle.tga", Image.fromarray(PICTURE), compression="tga_rle")
    np.testing.assert_array_equal(Texture.open(path).image, PICTURE)


def test_settings_pass_through_open(tmp_path):
    path = save(tmp_path, "s.png", Image.fromarray(PICTURE))
    tex = Texture.open(str(path), filter="nearest", wrap="clamp", scale=(2, 2), srgb=False)
    assert (tex.filter, tex.wrap, tex.scale, tex.srgb) == ("nearest", "clamp", (2.0, 2.0), False)
    assert Texture.open(os.fsencode(path)).name == str(path)


# --- refusals ---------------------------------------------------------------------------------

def _png(width: int, height: int, idat: bytes) -> bytes:
    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    ihdr = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", idat) + chunk(b"IEND", b"")


def good_bytes(fmt: str) -> bytes:
    """A 64x48 image of noise (so that most of the file is pixel data) as ``fmt``."""
    out = io.BytesIO()
    Image.fromarray(np.random.default_rng(1).integers(0, 256, (48, 64, 3), dtype=np.uint8)).save(out, fmt)
    return out.getvalue()


def refusal(path) -> TextureError:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(TextureError) as info:
            Texture.open(path)
    text = str(info.value)
    assert "\n" not in text and text.startswith(str(path) + ": "), text
    assert info.value.path == str(path)
    return info.value


@pytest.mark.parametrize("data,reason", [
    (b"", "not a PNG, JPEG, TGA or BMP image"),
    (b"hello, world: not an image at all", "not a PNG, JPEG, TGA or BMP image"),
    (b"GIF89a" + bytes(40), "not a PNG, JPEG, TGA or BMP image"),
    (b"\x89PNG\r\n\x1a\n" + bytes(30), "cannot read the PNG header"),
    (b"\xff\xd8\xff" + bytes(30), "cannot read the JPEG header"),
    (b"BM" + bytes(60), "cannot read the BMP header"),
    (good_bytes("PNG")[:-40], "cannot decode the PNG image"),
    (good_bytes("PNG")[:60] + bytes(200), "PNG"),
    (good_bytes("JPEG")[: len(good_bytes("JPEG")) * 3 // 4], "cannot decode the JPEG image"),
    (good_bytes("JPEG")[:300], "cannot read the JPEG header"),
    (good_bytes("TGA")[:2000], "cannot decode the TGA image"),
    (good_bytes("BMP")[:1000], "cannot decode the BMP image"),
    (_png(3, 2, zlib.compress(b"\x00" * 5)), "cannot decode the PNG image"),
    (_png(0, 2, b""), "PNG"),
])
def test_corrupt_files_are_one_line_errors(tmp_path, data, reason):
    path = tmp_path / "bad file.img"
    path.write_bytes(data)
    error = refusal(path)
    assert reason in error.reason and not isinstance(error, TextureLimitError)


def test_bytes_decode_as_the_file_does(tmp_path):
    """decode_image: an image file's bytes (a glTF buffer view's) give what read_image gives
    for the file, and a corrupt one the same one-line error, naming what the caller says."""
    from rasterkit.material.images import decode_image, read_image

    path = tmp_path / "a.png"
    path.write_bytes(good_bytes("PNG"))
    np.testing.assert_array_equal(decode_image(good_bytes("PNG"), "buffer view 3"), read_image(str(path)))
    with pytest.raises(TextureError, match=r"^buffer view 3: cannot read the JPEG header"):
        decode_image(good_bytes("JPEG")[:300], "buffer view 3")


def test_missing_and_irregular_files(tmp_path):
    assert "No such file or directory" in refusal(tmp_path / "missing.png").reason
    assert refusal(tmp_path).reason == "not a regular file (a directory)"
    os.mkfifo(tmp_path / "fifo.png")
    assert refusal(tmp_path / "fifo.png").reason == "not a regular file (a FIFO)"


def test_file_size_limit(tmp_path, restore_limits):
    path = tmp_path / "big.png"
    path.write_bytes(good_bytes("PNG"))
    limits.set_max_file_size(100)
    error = refusal(path)
    assert isinstance(error, TextureLimitError) and isinstance(error, limits.LimitError)
    assert "file size limit" in error.reason


def test_a_decompression_bomb_is_refused_before_decoding(tmp_path, restore_limits, monkeypatch):
    """A 70-byte PNG whose header claims 30000x20000 pixels: refused from its header, with the
    memory it would take, before Pillow decodes (or allocates) anything."""
    path = tmp_path / "bomb.png"
    path.write_bytes(_png(30000, 20000, zlib.compress(b"")))
    limits.set_memory_limit("256M")
    from PIL import ImageFile

    def no_decoding(self):
        raise AssertionError("decoded")

    monkeypatch.setattr(ImageFile.ImageFile, "load", no_decoding)
    error = refusal(path)
    assert isinstance(error, TextureLimitError)
    assert error.reason.startswith("decoding the 30000x20000 PNG image needs about ")
    assert "more than the limit of 256 MiB" in error.reason


def test_pillows_pixel_limit_is_not_used(tmp_path, monkeypatch):
    """Pillow warns from MAX_IMAGE_PIXELS and refuses from twice that; rasterkit's memory
    limit takes its place: no warning, no error."""
    path = save(tmp_path, "many.png", Image.fromarray(PICTURE))
    monkeypatch.setattr(Image, "MAX_IMAGE_PIXELS", 4)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        np.testing.assert_array_equal(Texture.open(path).image, PICTURE)


def test_errors_pickle_with_their_parts():
    error = pickle.loads(pickle.dumps(TextureLimitError("a.png", "too big")))
    assert (type(error), error.path, error.reason, str(error)) == (TextureLimitError, "a.png", "too big", "a.png: too big")


# --- the public models --------------------------------------------------------------------------

@pytest.mark.parametrize("name,shape", [("fuze/fuze uv.jpg", (1024, 1024, 3)),
                                        ("african_head/african_head_diffuse.tga", (1024, 1024, 3)),
                                        ("african_head/african_head_nm.tga", (1024, 1024, 4)),
                                        ("african_head/african_head_spec.tga", (1024, 1024, 3))])
def test_the_public_textures(models_dir, name, shape):
    path = models_dir / "formats" / "obj" / name
    if not path.is_file():
        pytest.skip(f"{path} is absent")
    tex = Texture.open(path)
    assert tex.image.shape == shape
    with Image.open(path) as im:
        np.testing.assert_array_equal(tex.image, np.asarray(im.convert("RGBA" if shape[2] == 4 else "RGB")))
    if name.endswith("spec.tga"):  # greyscale: equal channels
        assert (tex.image[..., 0] == tex.image[..., 2]).all()
    assert tex.mipmaps.nbytes <= 1.4 * tex.image.nbytes
