"""``Texture``: an RGB or RGBA image and how it is sampled.

Texture coordinates are OBJ's and glTF's as OpenGL reads them: ``u`` runs to the right,
``v`` up, and ``(0, 0)`` is the **bottom-left** corner of the image (``v = 0`` is the bottom
row, the last row of ``image``, whose row 0 is the top as in every image file). Texel ``(i,
j)`` (column ``i`` from the left, row ``j`` from the bottom) has its centre at ``((i + 0.5) /
width, (j + 0.5) / height)``. (glTF writes its ``v`` downwards, ``v_gl = 1 - v``: a glTF
reader flips it once.)
"""

from __future__ import annotations

import dataclasses
import os
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from rasterkit import values
from rasterkit.options import TEXTURE_FILTERS
from rasterkit._arrays import describe
from rasterkit.limits import check_memory
from rasterkit.material.images import read_image
from rasterkit.material.mipmaps import Mipmaps, build_mipmaps, mipmaps_bytes

__all__ = ["FILTERS", "SETTINGS", "Texture", "WRAPS"]

#: How a texture is filtered (:data:`rasterkit.options.TEXTURE_FILTERS`).
FILTERS = TEXTURE_FILTERS

#: What coordinates outside [0, 1] read: the texture repeated, its edge texels, or the texture
#: repeated and mirrored every other time (GL_REPEAT, GL_CLAMP_TO_EDGE, GL_MIRRORED_REPEAT).
WRAPS = ("repeat", "clamp", "mirror")


def _pair(name: str, value) -> tuple[float, float]:
    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__") or len(value) != 2:
        raise TypeError(f"{name} must be a pair (u, v) of numbers, got {describe(value)}")
    return tuple(values.real(name, v) for v in value)


def _sealed(image: np.ndarray) -> np.ndarray:
    """``image`` as a read-only view of a ``bytes`` object (as a Mesh keeps its arrays): no
    one can make it writeable again; itself when it is one already."""
    base = image
    while isinstance(base, np.ndarray):
        base = base.base
    if type(base) is bytes and not image.flags.writeable and image.flags.c_contiguous:
        return image
    return np.frombuffer(np.ascontiguousarray(image).tobytes(), np.uint8).reshape(image.shape)


def _image(name: str, value) -> np.ndarray:
    """(H, W, 3|4) uint8 from uint8 codes or floats in [0, 1] (rounded to the nearest code)."""
    if not isinstance(value, np.ndarray):
        raise TypeError(f"{name} must be a NumPy array (H, W, 3|4) of uint8 or floats in [0, 1], "
                        f"got {describe(value)}")
    if value.ndim != 3 or value.shape[2] not in (3, 4) or value.shape[0] < 1 or value.shape[1] < 1:
        raise ValueError(f"{name} must have shape (H, W, 3) or (H, W, 4), got {value.shape}")
    height, width, channels = value.shape
    check_memory(2 * value.size + mipmaps_bytes(width, height, channels) + (value.size * 8 if value.dtype.kind == "f" else 0),
                 f"a {width}x{height} texture")
    if value.dtype == np.uint8:
        return _sealed(value)
    if value.dtype.kind != "f":
        raise TypeError(f"{name} must hold uint8 codes or floats in [0, 1], got dtype {value.dtype}")
    if not np.isfinite(value).all() or value.min() < 0.0 or value.max() > 1.0:
        raise ValueError(f"{name}: float colours must be finite and lie in [0, 1]")
    return _sealed(np.floor(value.astype(np.float64) * 255.0 + 0.5).astype(np.uint8))


@dataclass(frozen=True, eq=False)
class Texture:
    """An RGB or RGBA image and the settings it is sampled with. Immutable; compared and
    hashed by identity (share one object between materials and meshes).

    Fields
    ------
    image : (H, W, 3) or (H, W, 4) uint8
        Row 0 at the top. Given as uint8 codes or floats in [0, 1] (rounded to the nearest
        code); kept as a read-only copy.
    filter : {"trilinear", "bilinear", "nearest"}
        :data:`FILTERS`; ``trilinear`` uses the mipmaps (:attr:`mipmaps`). A render filters
        with :attr:`rasterkit.RenderOptions.texture_filter` unless that is None.
    wrap : {"repeat", "clamp", "mirror"}
        :data:`WRAPS`: what coordinates outside [0, 1] read.
    scale, offset : (u, v) floats
        The coordinates sampled are ``(u * scale[0] + offset[0], v * scale[1] + offset[1])``
        (an ``.mtl`` file's ``-s`` and ``-o``); default (1, 1) and (0, 0).
    srgb : bool
        The colours are sRGB (as image files store them) and filtered in linear light; the
        kernels return linear light. False for data (normal, specular, opacity maps). Alpha
        is always linear.
    name : str or None
        The file it was read from (:meth:`open`), for messages.

    Coordinates: ``u`` to the right, ``v`` up, ``(0, 0)`` the bottom-left corner of the
    image (see the module documentation).
    """

    image: np.ndarray
    filter: str = "trilinear"
    wrap: str = "repeat"
    scale: tuple = (1.0, 1.0)
    offset: tuple = (0.0, 0.0)
    srgb: bool = True
    name: str | None = None
    # the mipmaps, per srgb setting: shared by the copies replace() makes
    _chains: dict = field(default_factory=dict, init=False, repr=False)

    def __post_init__(self):
        for name, check in _CHECKS.items():
            object.__setattr__(self, name, check(name, getattr(self, name)))

    def __repr__(self) -> str:
        kind = "RGBA" if self.channels == 4 else "RGB"
        named = f", name={self.name!r}" if self.name is not None else ""
        return (f"Texture({self.width}x{self.height} {kind}{named}, filter={self.filter!r}, wrap={self.wrap!r}, "
                f"scale={self.scale}, offset={self.offset}, srgb={self.srgb})")

    @classmethod
    def open(cls, path, **settings) -> Texture:
        """Read a PNG, JPEG, TGA or BMP file (:mod:`rasterkit.material.images`), with the
        sampling ``settings`` (the fields other than ``image``; ``name`` is the path).

        Raises :class:`~rasterkit.material.TextureError`, a ``ValueError`` of one line naming
        the file (a :class:`~rasterkit.material.TextureLimitError` over the file size or
        memory limit, before the image is decoded)."""
        path = os.fsdecode(path)
        return cls(read_image(path), **{"name": path, **settings})

    @property
    def width(self) -> int:
        return int(self.image.shape[1])

    @property
    def height(self) -> int:
        return int(self.image.shape[0])

    @property
    def channels(self) -> int:
        return int(self.image.shape[2])

    @cached_property
    def mipmaps(self) -> Mipmaps:
        """Every level of the image (:mod:`rasterkit.material.mipmaps`), built on first use
        and shared with the copies :meth:`replace` makes. Level 0 is the image's bytes: from
        then on :attr:`image` is a view of it (the same pixels), so the texture holds them once."""
        chain = self._chains.get(self.srgb)
        if chain is None:
            chain = self._chains[self.srgb] = build_mipmaps(self.image, self.srgb)
            if len(self._chains) == 1:  # the first chain: its level 0 holds the image from now on
                object.__setattr__(self, "image", chain.level(0))
        return chain

    def replace(self, **changes) -> Texture:
        """A copy with other sampling settings, sharing the image and its mipmaps."""
        unknown = set(changes) - SETTINGS
        if unknown:
            raise TypeError(f"unknown texture setting {sorted(unknown)[0]!r} (the settings are: "
                            f"{', '.join(sorted(SETTINGS))})")
        copy = object.__new__(Texture)
        copy.__dict__.update({k: v for k, v in self.__dict__.items() if k != "mipmaps"})
        for name, value in changes.items():
            object.__setattr__(copy, name, _CHECKS[name](name, value))
        return copy

    def __reduce__(self):  # through the constructor: the copy's image is sealed again
        settings = {f.name: getattr(self, f.name) for f in dataclasses.fields(self) if f.init and f.name != "image"}
        return _restore, (np.array(self.image), settings)


def _restore(image, settings):
    return Texture(image, **settings)


#: Each field's check, giving the value as it is stored.
_CHECKS = {
    "image": _image,
    "filter": lambda name, value: values.choice(name, value, FILTERS),
    "wrap": lambda name, value: values.choice(name, value, WRAPS),
    "scale": _pair, "offset": _pair,
    "srgb": values.flag,
    "name": lambda name, value: values.optional(_text, name, value),
}


#: The fields of a Texture other than its image: what :meth:`Texture.replace` may change.
SETTINGS = frozenset(_CHECKS) - {"image"}


def _text(name: str, value) -> str:
    if not isinstance(value, str):
        raise TypeError(f"{name} must be a string or None, got {type(value).__name__}")
    return value
