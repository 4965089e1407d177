"""The picture of docs/textures.md: a checkerboard on a plane seen at a grazing angle, its
texture coordinates interpolated in screen space (affine, wrong) and perspective-correctly
(rasterkit's ``fb.uv``), each looked up with the nearest texel.

``python scripts/make_texture_figure.py`` writes docs/perspective.png."""

from __future__ import annotations

from pathlib import Path

import numpy as np

import rasterkit
from rasterkit import Camera, Mesh, Texture
from rasterkit.image import save_image
from rasterkit.material.colorspace import encode_srgb8
from rasterkit.material.sampling import sample

DOCS = Path(__file__).resolve().parents[1] / "docs"
SQUARE = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], float)
FACES = np.array([[0, 1, 2], [0, 2, 3]])
UV = (SQUARE[:, :2] + 1) / 2
CAMERA = Camera.look_at(eye=(0.4, -2.6, 0.8), target=(0, 0.2, 0), width=360, height=270)


def checkerboard(n: int = 8, texels: int = 64) -> Texture:
    cell = (np.arange(texels) * n // texels)
    board = (cell[:, None] + cell[None, :]) % 2
    image = np.where(board[..., None] == 1, (40, 70, 140), (235, 225, 200)).astype(np.uint8)
    return Texture(image, filter="nearest")


def affine_uv(width: int, height: int) -> np.ndarray:
    """(H, W, 2): uv interpolated linearly between the projected corners (NaN outside)."""
    corners = CAMERA.project(SQUARE)[:, :2]
    ys, xs = np.mgrid[0:height, 0:width]
    p = np.stack([xs.ravel() + 0.5, ys.ravel() + 0.5], axis=1)
    out = np.full((len(p), 2), np.nan)
    for tri in FACES:
        a, b, c = corners[tri]
        m = np.array([[b[0] - a[0], c[0] - a[0]], [b[1] - a[1], c[1] - a[1]]])
        st = np.linalg.solve(m, (p - a).T).T
        inside = (st >= 0).all(axis=1) & (st.sum(axis=1) <= 1)
        uv = UV[tri]
        out[inside] = uv[0] + st[inside, :1] * (uv[1] - uv[0]) + st[inside, 1:] * (uv[2] - uv[0])
    return out.reshape(height, width, 2)


def shade(uv: np.ndarray, texture: Texture) -> np.ndarray:
    """The texture's colour at each pixel's uv, white where there is none."""
    image = np.full(uv.shape[:2] + (3,), 255, np.uint8)
    seen = np.isfinite(uv[..., 0])
    linear = sample(texture, uv[seen].astype(np.float64))[:, :3]
    image[seen] = encode_srgb8(linear)
    return image


def main() -> None:
    texture = checkerboard()
    fb = rasterkit.render(Mesh(SQUARE, FACES, texcoords=UV), CAMERA, "solid", uv=True, cull="none")
    gap = np.full((CAMERA.height, 2, 3), 200, np.uint8)
    picture = np.concatenate([shade(affine_uv(CAMERA.width, CAMERA.height), texture), gap,
                              shade(fb.uv, texture)], axis=1)
    save_image(picture, DOCS / "perspective.png")


if __name__ == "__main__":
    main()
