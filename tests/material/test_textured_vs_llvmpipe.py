"""Textured frames against Mesa llvmpipe (moderngl, a GLSL shader doing ``texture()`` with the
same filter; benchmarks/texture_peer.py): real textured models, flat and smooth headlight
shading, bilinear and trilinear filtering. The issue's bars: bilinear, 99 % of the covered
pixels within 2/255 in every channel; trilinear, a mean difference of at most 2/255. llvmpipe
is given rasterkit's mip levels, so both sample the same texels (the levels themselves are
tested in test_mipmaps.py)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import rasterkit
from rasterkit import Material, Texture, View, load_obj
from support.paths import MODELS, needs_models

pytestmark = needs_models


def spot():
    """spot.obj has no .mtl: its texture is given through the API."""
    mesh = load_obj(MODELS / "spot.obj")
    texture = Texture.open(MODELS / "spot_texture.png")
    return dataclasses.replace(mesh, face_materials=np.zeros(len(mesh.faces), np.int32), material_names=("spot",),
                               materials=(Material(diffuse=(1, 1, 1), diffuse_map=texture),))


def fuze():
    """fuze.obj's .mtl names its texture with map_Kd, a file name with a space."""
    return load_obj(MODELS / "formats" / "obj" / "fuze" / "fuze.obj", textures=True)


def african_head():
    """tinyrenderer's head: v/vt/vn, its diffuse TGA given through the API."""
    folder = MODELS / "formats" / "obj" / "african_head"
    mesh = load_obj(folder / "african_head.obj")
    texture = Texture.open(folder / "african_head_diffuse.tga")
    return dataclasses.replace(mesh, face_materials=np.zeros(len(mesh.faces), np.int32), material_names=("head",),
                               materials=(Material(diffuse=(1, 1, 1), diffuse_map=texture),))


MODELS_USED = {"spot": spot, "fuze": fuze, "african_head": african_head}


def _gl_levels(texture: Texture) -> list:
    levels = [texture.mipmaps.level(k) for k in range(len(texture.mipmaps.levels))]
    return [lv if lv.shape[2] == 4 else np.concatenate([lv, np.full(lv.shape[:2] + (1,), 255, np.uint8)], axis=2)
            for lv in levels]


@pytest.mark.parametrize("filter", ["bilinear", "trilinear"])
@pytest.mark.parametrize("shading", ["flat", "smooth"])
@pytest.mark.parametrize("model", sorted(MODELS_USED))
def test_a_textured_model_as_llvmpipe_draws_it(model, shading, filter, gl):
    mesh = MODELS_USED[model]()
    (texture,) = mesh.textured.textures
    camera = View(size=(480, 360), azimuth=30, elevation=20).camera_for(mesh)
    fb = rasterkit.render(mesh, camera, "solid", shading=shading, texture_filter=filter, ids=True)
    normals, corners, _ = mesh.smooth_corners
    uploaded = gl.upload(mesh.vertices, mesh.faces, mesh.textured.corner_uv.reshape(-1, 3, 2), texture.image, camera,
                         filter=filter, shading=shading, corner_normals=normals[corners],
                         levels=_gl_levels(texture) if filter == "trilinear" else None)
    drawn = gl.draw(uploaded).astype(int)
    covered = fb.ids >= 0
    difference = np.abs(fb.color[..., :3].astype(int) - drawn)[covered]
    assert covered.sum() > 15_000
    within = (difference.max(axis=1) <= 2).mean()
    assert within >= 0.99, within
    if filter == "trilinear":
        assert difference.mean() <= 2
    # untextured, the same faces differ: the texture is what agrees
    plain = rasterkit.render(mesh, camera, "solid", shading=shading, textures=False).color[..., :3].astype(int)
    assert (np.abs(plain - drawn)[covered].max(axis=1) <= 2).mean() < 0.5
