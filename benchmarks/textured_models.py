"""The textured models of the ``textures`` family and how llvmpipe is given the same mesh.

Only three public OBJs of the shared models have their texture files beside them: spot
(``spot_texture.png``, given through the API: spot.obj has no ``.mtl``), tinyrenderer's
african_head (its diffuse TGA, given through the API) and fuze (its ``.mtl`` names ``fuze
uv.jpg``). None of them is larger than spot (5,856 triangles), and the larger models' own
textures are not in the shared folder (sponza's, lost_empire's atlas). So the larger
textured models are real meshes with their own texture coordinates — beast (64,618
triangles, coordinates from -7.6 to 8.5: the texture repeats) and lost_empire (224,998
triangles, a texture atlas layout) — given ``spot_texture.png`` through the API: the cost of
a frame depends on the coordinates and the texture's size, not on what the texels show.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

import rasterkit

from .settings import MODELS_DIR

__all__ = ["MODELS", "TexturedModel", "gl_levels", "load", "missing", "peer_reason", "upload"]


@dataclass(frozen=True)
class TexturedModel:
    """A textured model: its OBJ and, when the texture is given through the API, the texture.

    Attributes
    ----------
    path : str
        The OBJ, under :data:`benchmarks.settings.MODELS_DIR`.
    texture : str or None
        The diffuse texture given to every face (under ``MODELS_DIR``); None: the ``.mtl``'s.
    target : bool
        Its smooth trilinear frame at 1920x1080 carries the issue's target (spot, and the
        models larger than spot).
    """

    path: str
    texture: str | None
    target: bool = False


SPOT_TEXTURE = "spot_texture.png"

MODELS = {
    "spot": TexturedModel("spot.obj", SPOT_TEXTURE, target=True),
    "african_head": TexturedModel("formats/obj/african_head/african_head.obj",
                                  "formats/obj/african_head/african_head_diffuse.tga"),
    "fuze": TexturedModel("formats/obj/fuze/fuze.obj", None),
    "beast": TexturedModel("beast.obj", SPOT_TEXTURE, target=True),
    "lost_empire": TexturedModel("lost_empire.obj", SPOT_TEXTURE, target=True),
}
"""The models by name; the smallest first. Texture files are opened once per run and shared."""


def missing(name: str) -> str | None:
    """Why model ``name`` cannot be drawn here (its OBJ or texture file is absent), or None."""
    model = MODELS[name]
    for relative in filter(None, (model.path, model.texture)):
        if not (MODELS_DIR / relative).is_file():
            return f"file {MODELS_DIR / relative} not found"
    return None


def load(name: str, opened: dict) -> rasterkit.Mesh:
    """The textured mesh of model ``name``; ``opened`` ({path: Texture}) shares each texture
    file between the models of a run.

    Raises
    ------
    FileNotFoundError
        The OBJ or its texture is not in the shared models folder.
    ValueError
        No face of the mesh is textured (the ``.mtl``'s texture could not be read).
    """
    model, why = MODELS[name], missing(name)
    if why:
        raise FileNotFoundError(why)
    if model.texture is None:
        mesh = rasterkit.load_obj(MODELS_DIR / model.path)
    else:
        path = MODELS_DIR / model.texture
        if path not in opened:
            opened[path] = rasterkit.Texture.open(path)
        mesh = rasterkit.load_obj(MODELS_DIR / model.path, textures=False)  # only the geometry and uv
        mesh = dataclasses.replace(mesh, face_materials=np.zeros(len(mesh.faces), np.int32),
                                   material_names=(path.stem,),
                                   materials=(rasterkit.Material(diffuse_map=opened[path]),))
    if mesh.textured is None:
        raise ValueError(f"no face of {model.path} is textured ({'; '.join(mesh.warnings) or 'no texture'})")
    return mesh


def peer_reason(mesh) -> str | None:
    """Why llvmpipe cannot draw the same frame of ``mesh``, or None: the peer binds one texture
    and draws every face with it."""
    layout = mesh.textured
    if len(layout.textures) != 1:
        return f"{len(layout.textures)} textures (the peer binds one)"
    if (layout.face_texture < 0).any():
        return f"{int((layout.face_texture < 0).sum())} faces untextured (the peer textures every face)"
    texture = layout.textures[0]
    if texture.scale != (1.0, 1.0) or texture.offset != (0.0, 0.0) or texture.wrap == "mirror":
        return "the texture's scale, offset or mirror wrap (the peer samples plain coordinates)"
    return None


def gl_levels(texture) -> list:
    """rasterkit's mip levels of ``texture`` as RGBA images for the peer, so that both sides
    sample the very same texels."""
    levels = [texture.mipmaps.level(k) for k in range(len(texture.mipmaps.levels))]
    return [level if level.shape[2] == 4 else
            np.concatenate([level, np.full(level.shape[:2] + (1,), 255, np.uint8)], axis=2) for level in levels]


def upload(textured_gl, mesh, camera, shading: str, texture_filter: str | None):
    """Upload ``mesh`` to a :class:`benchmarks.texture_peer.TexturedGL` for frames of ``camera``
    shaded ``shading``, textured with ``texture_filter`` (None: untextured, light grey)."""
    layout = mesh.textured
    (texture,) = layout.textures
    normals, corners, _ = mesh.smooth_corners
    return textured_gl.upload(mesh.vertices, mesh.faces, layout.corner_uv.reshape(-1, 3, 2),
                              None if texture_filter is None else texture.image, camera,
                              filter=texture_filter or "nearest", wrap=texture.wrap, shading=shading,
                              corner_normals=normals[corners],
                              levels=gl_levels(texture) if texture_filter == "trilinear" else None)
