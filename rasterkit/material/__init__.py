"""Materials and textures: :class:`Material` (how a surface looks, as an ``.mtl`` file says)
and :class:`Texture` (an image and how it is sampled).

Modules, one job each: ``errors`` (:class:`TextureError`), ``images`` (reading PNG, JPEG,
TGA and BMP files through Pillow, within the limits), ``colorspace`` (sRGB and linear
light), ``mipmaps`` (the levels of a texture in one buffer), ``texture`` (:class:`Texture`),
``material`` (:class:`Material`), ``sampling`` (the kernels' arguments, and lookups from
Python); the lookups themselves are the kernels of ``kernels/sample.py``, which a renderer's
band worker calls per pixel.

Conventions: ``u`` to the right and ``v`` up, ``(0, 0)`` the bottom-left corner of the image
(OBJ's and OpenGL's); texel centres at ``(i + 0.5) / width``; colours sRGB, filtered in linear
light, looked up as linear light (the renderer encodes the shaded colour back to sRGB once).
"""

from rasterkit.material.errors import TextureError, TextureLimitError
from rasterkit.material.material import DEFAULT_DIFFUSE, MAPPED_DIFFUSE, Material
from rasterkit.material.texture import FILTERS, WRAPS, Texture

__all__ = ["DEFAULT_DIFFUSE", "FILTERS", "MAPPED_DIFFUSE", "Material", "Texture", "TextureError", "TextureLimitError", "WRAPS"]
