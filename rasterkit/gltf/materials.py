"""glTF materials as :class:`rasterkit.Material` records (:func:`look`), each made once and
shared by every primitive that uses it.

What is read of a material, and how rasterkit draws it:

- ``pbrMetallicRoughness.baseColorFactor`` (linear RGBA, default white): its RGB, encoded to
  sRGB, is the Material's ``diffuse`` (the tint of its texture) and the colour of its faces
  without a texture. rasterkit's colours are sRGB values multiplied by the shading, so the
  linear factor is encoded once here; under a texture ``encode(t * f)`` becomes
  ``encode(t) * encode(f)``, exact for white and black and within a few codes elsewhere.
- ``baseColorTexture``: the image (PNG or JPEG, from a buffer view or a URI; Pillow decodes
  it, within the memory limit) as an sRGB :class:`rasterkit.Texture`, read through the
  ``TEXCOORD_<texCoord>`` set. Its sampler: ``wrapS``/``wrapT`` (REPEAT, CLAMP_TO_EDGE,
  MIRRORED_REPEAT) become the Texture's one ``wrap`` (``wrapS``'s, with a warning when
  ``wrapT`` differs); the filters become ``trilinear`` (a mipmapped ``minFilter``, or none
  given, unless ``magFilter`` is NEAREST), ``bilinear`` (``minFilter`` LINEAR, or NEAREST
  with a LINEAR ``magFilter``) or ``nearest``. An image that cannot be read is a warning,
  and the material is drawn with its colour.
- ``alphaMode``: rasterkit cuts out the fragments of a textured face whose alpha (the
  texture's times the Material's ``opacity``) is below 0.5 (:mod:`rasterkit.raster.kernels.
  cutout`). ``OPAQUE`` (the default) draws every fragment: the texture's alpha is dropped.
  ``MASK`` with ``alphaCutoff`` ``c`` (default 0.5) keeps a fragment where the texture's
  alpha times the factor's alpha ``f`` is at least ``c``: ``opacity`` is ``0.5 f / c``, so
  that the renderer's test at 0.5 is glTF's at ``c``, or, when that is above 1, the
  texture's alpha is scaled by ``0.5 f / c`` (clipped to 1; a new texture). ``BLEND`` is
  drawn as ``MASK`` at 0.5, with a warning. Without a texture with alpha, the whole
  material is kept or cut out (``hidden``: its primitives are left out, with a warning).
- ``doubleSided``: the Material's ``double_sided``.
- ``name`` (else ``material<i>``). The rest (metallic-roughness, normal, occlusion and
  emissive textures, emissive factor, extensions) is not used.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rasterkit.gltf.buffers import buffer_view
from rasterkit.gltf.document import Document, Obj, shown
from rasterkit.gltf.uris import local_path, uri_bytes
from rasterkit.gltf.errors import GltfError
from rasterkit.material import Material, Texture, TextureError
from rasterkit.material.colorspace import encode_srgb
from rasterkit.material.images import decode_image
from rasterkit.material.mipmaps import mipmaps_bytes

__all__ = ["ALPHA_MODES", "Look", "WRAPS", "filter_of", "look"]

#: glTF's wrap modes -> rasterkit.Texture's.
WRAPS = {10497: "repeat", 33071: "clamp", 33648: "mirror"}
_NEAREST, _LINEAR = 9728, 9729
_MIPMAPPED = (9984, 9985, 9986, 9987)
ALPHA_MODES = ("OPAQUE", "MASK", "BLEND")
#: The alpha below which rasterkit cuts a textured fragment out (rasterkit.raster.kernels.cutout).
_CUTOFF = 0.5


@dataclass(frozen=True)
class Look:
    """How the faces of one glTF material are drawn: its ``material``, the sRGB ``color`` of
    its faces without a texture (its linear ``factor``, RGB), the TEXCOORD set its texture
    reads (``uv_set``, None without a texture) and whether it is cut out whole (``hidden``)."""

    material: Material
    color: tuple
    factor: tuple
    uv_set: int | None
    hidden: bool


def look(doc: Document, index: int | None) -> Look | None:
    """The :class:`Look` of ``materials[index]`` (None for None: glTF's default material,
    drawn with the render's colour), made once."""
    if index is None:
        return None
    key = ("material", index)
    if key not in doc.cache:
        doc.cache[key] = _look(doc, doc.item("materials", index), index)
    return doc.cache[key]


def _look(doc: Document, m: Obj, index: int) -> Look:
    pbr = m.obj("pbrMetallicRoughness", None)
    factor = (1.0, 1.0, 1.0, 1.0) if pbr is None else pbr.numbers("baseColorFactor", (4,), (1.0, 1.0, 1.0, 1.0))
    if not all(0.0 <= f <= 1.0 for f in factor):
        doc.warn(m.path("pbrMetallicRoughness.baseColorFactor"), "values outside [0, 1] are clipped")
        factor = tuple(min(max(f, 0.0), 1.0) for f in factor)
    mode = m.string("alphaMode", "OPAQUE")
    if mode not in ALPHA_MODES:
        doc.warn(m.path("alphaMode"), f"{shown(mode)} is not an alpha mode: drawn as OPAQUE")
        mode = "OPAQUE"
    cutoff = m.number("alphaCutoff", _CUTOFF, low=0.0) if mode == "MASK" else _CUTOFF
    if mode == "BLEND":
        doc.warn(m.path("alphaMode"), "BLEND is drawn as a cut-out at alpha 0.5 (MASK)")
    info = None if pbr is None else pbr.obj("baseColorTexture", None)
    texture, uv_set = (None, None) if info is None else _texture_of(doc, info)
    alpha = factor[3]
    opacity = 1.0
    if mode == "OPAQUE" or cutoff == 0.0:
        texture = None if texture is None else _opaque(doc, texture)
    elif texture is not None and _has_alpha(texture):
        scale = alpha * _CUTOFF / cutoff
        opacity = scale if scale <= 1.0 else 1.0
        if scale > 1.0:
            texture = _scaled_alpha(doc, texture, scale)
    hidden = mode != "OPAQUE" and (texture is None or not _has_alpha(texture)) and alpha < cutoff
    if hidden:
        doc.warn(m.where, f"alpha {alpha:g} is below the cut-off {cutoff:g}: its faces are not drawn")
    color = tuple(float(c) for c in encode_srgb(np.array(factor[:3])))
    material = Material(m.string("name", f"material{index}"), diffuse=color, opacity=opacity, diffuse_map=texture,
                        double_sided=m.flag("doubleSided", False))
    return Look(material, color, factor[:3], uv_set if texture is not None else None, hidden)


def _texture_of(doc: Document, info: Obj):
    """``(Texture or None, uv_set)`` of a ``textureInfo``."""
    uv_set = info.int("texCoord", 0)
    t = doc.item("textures", info.ref("index", "textures"))
    if not doc.textures:  # read_gltf(textures=False): no image is decoded
        return None, uv_set
    source = t.ref("source", "images", None)
    if source is None:
        doc.warn(t.where, "has no source image that rasterkit reads (an extension's?): drawn without it")
        return None, uv_set
    image = _image(doc, source)
    if image is None:
        return None, uv_set
    sampler = t.ref("sampler", "samplers", None)
    key = ("texture", source, sampler)
    if key not in doc.cache:
        wrap, filtering = _sampling(doc, None if sampler is None else doc.item("samplers", sampler))
        doc.cache[key] = Texture(image[0], wrap=wrap, filter=filtering, name=image[1])
    return doc.cache[key], uv_set


def _image(doc: Document, index: int):
    """``(pixels, name)``: the decoded ``images[index]`` ((H, W, 3|4) uint8) and the name
    its Texture gets, or None after a warning (it cannot be read, or is over a limit); read
    once."""
    key = ("image", index)
    if key in doc.cache:
        return doc.cache[key]
    im = doc.item("images", index)
    doc.cache[key] = None
    try:
        uri = im.string("uri", None)
        if uri is not None and uri[:5].lower() != "data:":
            data = uri_bytes(doc, uri, im.path("uri"))
            name = local_path(doc, uri, im.path("uri"))
        elif uri is not None:
            data = uri_bytes(doc, uri, im.path("uri"))
            name = f"{doc.path} {im.where}"
        else:
            data = buffer_view(doc, im.ref("bufferView", "bufferViews")).data
            name = f"{doc.path} {im.where}"
        image = decode_image(bytes(data), name, doc.spent)
    except (GltfError, TextureError) as e:
        doc.warn(im.where, f"cannot be read ({e.reason}): drawn without it")
        return None
    height, width, channels = image.shape
    doc.spent += image.nbytes + mipmaps_bytes(width, height, channels)
    doc.cache[key] = image, name
    return doc.cache[key]


def filter_of(min_filter: int | None, mag_filter: int | None) -> str:
    """rasterkit's texture filter for glTF's sampler filters (see the module documentation)."""
    if min_filter in _MIPMAPPED or (min_filter is None and mag_filter != _NEAREST):
        return "trilinear"
    if min_filter == _LINEAR or (min_filter == _NEAREST and mag_filter == _LINEAR):
        return "bilinear"
    return "nearest"


def _sampling(doc: Document, s: Obj | None) -> tuple[str, str]:
    if s is None:
        return "repeat", "trilinear"
    wrap_s, wrap_t = s.int("wrapS", 10497), s.int("wrapT", 10497)
    for key, value in (("wrapS", wrap_s), ("wrapT", wrap_t)):
        if value not in WRAPS:
            raise doc.error(s.path(key), f"{value} is not a wrap mode ({', '.join(map(str, WRAPS))})")
    if wrap_s != wrap_t:
        doc.warn(s.where, f"wrapS {WRAPS[wrap_s]} and wrapT {WRAPS[wrap_t]} differ: both are {WRAPS[wrap_s]}")
    return WRAPS[wrap_s], filter_of(s.int("minFilter", None), s.int("magFilter", None))


def _has_alpha(texture: Texture) -> bool:
    return texture.channels == 4 and int(texture.image[..., 3].min()) < 255


def _opaque(doc: Document, texture: Texture) -> Texture:
    """``texture`` without its alpha (the same texture when it has none below 255)."""
    if not _has_alpha(texture):
        return texture
    return _variant(doc, texture, "opaque", lambda image: image[..., :3])


def _scaled_alpha(doc: Document, texture: Texture, scale: float) -> Texture:
    """``texture`` with its alpha times ``scale`` (clipped to 255)."""
    def scaled(image):
        out = np.array(image)
        out[..., 3] = np.minimum(np.floor(image[..., 3] * scale + 0.5), 255)
        return out

    return _variant(doc, texture, ("alpha", scale), scaled)


def _variant(doc: Document, texture: Texture, kind, change) -> Texture:
    key = ("variant", id(texture), kind)
    if key not in doc.cache:
        doc.check_memory(3 * texture.image.nbytes + mipmaps_bytes(texture.width, texture.height, 4),
                         f"a copy of the {texture.width}x{texture.height} texture", None)
        doc.cache[key] = Texture(change(texture.image), filter=texture.filter, wrap=texture.wrap, name=texture.name)
        doc.spent += texture.image.nbytes
    return doc.cache[key]
