"""Reading an image file for a texture: PNG, JPEG, TGA or BMP, through Pillow.

The steps, so that no file can take more than the limits allow:

1. The bytes are read by :func:`rasterkit.runtime.files.read_file` (regular files only, within
   the file size limit).
2. The format is told by the first bytes (PNG, JPEG and BMP signatures; anything else is
   tried as TGA, which has none) and only the header is parsed, by that format's Pillow
   plugin: the image's size and mode, nothing decoded yet.
3. The memory that decoding, converting and the mipmaps will take (:func:`decoding_bytes`,
   plus what the caller has already spent) is checked with
   :func:`rasterkit.limits.check_memory`: a decompression bomb (a small file whose header
   claims a huge image) is refused with one line naming the file, before anything is
   allocated for it.
4. The image is decoded and converted to RGB or RGBA uint8: greyscale, palette, 1-bit, CMYK
   and YCbCr images to RGB, and to RGBA when they have transparency (an alpha channel or a
   transparent palette entry); 16-bit greyscale scaled to 8 bits (``/ 257``, rounded). The
   pixels are taken as stored: a JPEG's EXIF orientation is not applied (texture coordinates
   refer to the stored image, as on a GPU).

Pillow's own decompression-bomb limit (``PIL.Image.MAX_IMAGE_PIXELS``: a warning from 89
million pixels, an error from twice that) is not used: it counts pixels, whatever memory the
machine has, and it warns instead of refusing. Opening the format's plugin directly (not
``Image.open``) leaves it out; step 3 is the limit, the same ``--max-memory`` as for
everything else. Warnings Pillow gives while it reads (about metadata of malformed files) are
not passed on: a file either gives an image or raises :class:`TextureError`, one line naming
it (``cannot decode ...`` for corrupt or truncated data, with Pillow's reason).
"""

from __future__ import annotations

import io
import warnings

import numpy as np

from rasterkit.limits import LimitError, check_memory
from rasterkit.material.errors import TextureError, TextureLimitError
from rasterkit.material.mipmaps import mipmaps_bytes
from rasterkit.runtime import files

__all__ = ["FORMATS", "decode_image", "decoding_bytes", "read_image"]

#: The formats read, by the signature their files start with (TGA has none: the rest).
FORMATS = (("PNG", b"\x89PNG\r\n\x1a\n"), ("JPEG", b"\xff\xd8\xff"), ("BMP", b"BM"), ("TGA", b""))

#: Bytes per pixel that Pillow's decoded image and its RGB(A) conversion take at most (it
#: keeps 4 bytes per pixel for RGB), and the array made from it (4) and its sealed copy (4).
_DECODING_BYTES_PER_PIXEL = 4 + 4 + 4 + 4

_SIXTEEN_BITS = ("I;16", "I;16B", "I;16L", "I;16N", "I")


def decoding_bytes(width: int, height: int) -> int:
    """Memory that reading a ``width`` x ``height`` image as a texture takes: decoding,
    converting, and its mipmaps (counted as RGBA)."""
    return width * height * _DECODING_BYTES_PER_PIXEL + mipmaps_bytes(width, height, 4)


def _plugin(name: str):
    """The Pillow image class that reads the format ``name``."""
    if name == "PNG":
        from PIL.PngImagePlugin import PngImageFile as image_class
    elif name == "JPEG":
        from PIL.JpegImagePlugin import JpegImageFile as image_class
    elif name == "BMP":
        from PIL.BmpImagePlugin import BmpImageFile as image_class
    else:
        from PIL.TgaImagePlugin import TgaImageFile as image_class
    return image_class


def _header(data: bytes, path: str):
    """The Pillow image of ``data`` with only its header read, and its format's name."""
    name = next(name for name, signature in FORMATS if data.startswith(signature))
    try:
        return _plugin(name)(io.BytesIO(data)), name
    except Exception as e:  # noqa: BLE001 - Pillow's parsers raise many types on bad headers
        if name == "TGA":
            raise TextureError(path, "not a PNG, JPEG, TGA or BMP image") from None
        raise TextureError(path, f"cannot read the {name} header: {_reason(e)}") from None


def _reason(error: Exception) -> str:
    text = " ".join(str(error).split()) or type(error).__name__
    return text if len(text) <= 200 else text[:197] + "..."


def _converted(im) -> np.ndarray:
    """The decoded image ``im`` as (H, W, 3|4) uint8."""
    if im.mode in _SIXTEEN_BITS:
        grey = np.asarray(im).astype(np.float64)
        grey = np.floor(np.clip(grey, 0, 65535) / 257.0 + 0.5).astype(np.uint8)
        return np.repeat(grey[:, :, None], 3, axis=2)
    alpha = "A" in im.mode or "a" in im.mode or "transparency" in im.info
    mode = "RGBA" if alpha else "RGB"
    return np.asarray(im if im.mode == mode else im.convert(mode))  # convert() to its own mode copies


def read_image(path: str, spent: int = 0) -> np.ndarray:
    """The image of the file ``path`` as (H, W, 3|4) uint8, row 0 at the top (see the module
    documentation); ``spent``: bytes the caller already holds for other textures, counted
    against the memory limit with this one.

    Raises
    ------
    TextureError
        One line naming the file: it cannot be read, is not a PNG, JPEG, TGA or BMP image, or
        its data are corrupt or truncated; a :class:`TextureLimitError` over the file size
        limit or when decoding it would need more memory than the limit.
    """
    try:
        data = files.read_file(path)
    except files.FileLimitError as e:
        raise TextureLimitError(e.path, e.reason) from None
    except files.FileError as e:
        raise TextureError(e.path, e.reason) from None
    return decode_image(data, path, spent)


def decode_image(data: bytes, path: str, spent: int = 0) -> np.ndarray:
    """The image of the bytes ``data`` of an image file (steps 2 to 4 of the module
    documentation), as :func:`read_image` gives it; ``path`` names the image in errors (a
    file, or where the bytes come from, such as a glTF buffer view)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        im, name = _header(data, path)
        width, height = im.size
        if width < 1 or height < 1:
            raise TextureError(path, f"the {name} image is empty ({width}x{height})")
        try:
            check_memory(decoding_bytes(width, height) + spent, f"decoding the {width}x{height} {name} image")
        except LimitError as e:
            raise TextureLimitError(path, str(e)) from None
        try:
            im.load()
            image = _converted(im)
        except Exception as e:  # noqa: BLE001 - Pillow's decoders raise many types on corrupt data
            raise TextureError(path, f"cannot decode the {name} image: {_reason(e)}") from None
        finally:
            im.close()
    return image
