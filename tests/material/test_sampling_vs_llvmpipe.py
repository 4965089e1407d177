"""The sampling kernels against Mesa llvmpipe: a plane seen at a grazing angle, textured with
noise (every mip level differs) repeated 4 times, looked up at rasterkit's per-pixel texture
coordinates (``fb.uv``) with OpenGL's level of detail from their exact screen-space
derivatives, and drawn by llvmpipe (benchmarks/texture_peer.py) from the same mip levels.
The issue's bars: bilinear, 99 % of pixels within 2/255; trilinear, mean difference 2/255."""

from __future__ import annotations

import numpy as np
import pytest

import rasterkit
from rasterkit import Camera, Mesh, Texture
from rasterkit.material.colorspace import encode_srgb8
from rasterkit.material.sampling import sample
from rasterkit.raster.kernels.shade import bary_matrices
from rasterkit.raster.vertex import transform_points

SQUARE = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], float) * 3
FACES = np.array([[0, 1, 2], [0, 2, 3]])
UV = (SQUARE[:, :2] / 3 + 1) / 2 * 4  # the texture 4 times across
CAMERA = Camera.look_at(eye=(0.4, -6, 1.0), target=(0, 1, 0), width=320, height=240)
NOISE = np.random.default_rng(1).integers(0, 256, (256, 256, 3), dtype=np.uint8)


def _uv_and_lod():
    """Per covered pixel: its (x, y), uv, and OpenGL's level of detail from the exact
    derivatives of the perspective-correct uv (the quotient rule on the barycentric rows)."""
    mesh = Mesh(SQUARE, FACES, texcoords=UV)
    fb = rasterkit.render(mesh, CAMERA, "solid", ids=True, cull="none")
    ys, xs = np.nonzero(fb.ids >= 0)
    rows = bary_matrices(transform_points(mesh.vertices, np.ascontiguousarray(CAMERA.world_to_raster())),
                         mesh.faces).reshape(-1, 3, 3)[fb.ids[ys, xs]]
    b = rows[:, :, 0] * (xs + 0.5)[:, None] + rows[:, :, 1] * (ys + 0.5)[:, None] + rows[:, :, 2]
    corners = UV[FACES[fb.ids[ys, xs]]]
    s, u = b.sum(1)[:, None], (b[:, :, None] * corners).sum(1)
    derivative = [((rows[:, :, k, None] * corners).sum(1) * s - u * rows[:, :, k].sum(1)[:, None]) / s ** 2
                  for k in (0, 1)]
    lengths = [((d * 256) ** 2).sum(1) for d in derivative]
    return xs, ys, u / s, 0.5 * np.log2(np.maximum(*lengths))


@pytest.mark.parametrize("filter", ["nearest", "bilinear", "trilinear"])
def test_the_kernels_sample_what_llvmpipe_draws(filter, gl):
    texture = Texture(NOISE, filter=filter)
    levels = [texture.mipmaps.level(k) for k in range(len(texture.mipmaps.levels))]
    opaque = [np.concatenate([lv, np.full(lv.shape[:2] + (1,), 255, np.uint8)], axis=2) for lv in levels]
    drawn = gl.draw(gl.upload(SQUARE, FACES, UV[FACES], NOISE, CAMERA, filter=filter, shading="unlit",
                              levels=opaque if filter == "trilinear" else None), cull=False)
    xs, ys, uv, lod = _uv_and_lod()
    ours = encode_srgb8(sample(texture, uv, lod)[:, :3]).astype(int)
    difference = np.abs(ours - drawn[ys, xs].astype(int))
    assert len(xs) > 15_000 and lod.min() > 1  # minified: the levels matter
    if filter == "trilinear":
        assert difference.mean() <= 2
    assert (difference.max(axis=1) <= 2).mean() >= 0.99, (difference.max(axis=1) <= 2).mean()
