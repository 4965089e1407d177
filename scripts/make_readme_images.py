"""Regenerate the README's pictures: ``python scripts/make_readme_images.py`` (writes docs/*.png)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

import rasterkit
from rasterkit import Camera, shapes
from rasterkit.image import save_image

DOCS = Path(__file__).resolve().parents[1] / "docs"
TILE = (360, 270)


def _strip(images: list[np.ndarray]) -> np.ndarray:
    """Images side by side with a one-pixel grey gap."""
    gap = np.full((images[0].shape[0], 1, 3), 200, np.uint8)
    parts = [p for image in images for p in (image, gap)][:-1]
    return np.concatenate(parts, axis=1)


def modes() -> np.ndarray:
    mesh = shapes.demo()
    camera = Camera.frame(*mesh.bounding_sphere(), width=TILE[0], height=TILE[1])
    return _strip([rasterkit.render(mesh, camera, mode=m, color="steelblue").color
                   for m in ("wire", "hidden", "solid", "solid+wire")])


def projections() -> np.ndarray:
    mesh = shapes.cube()
    centre, radius = mesh.bounding_sphere()
    w, h = TILE[0] // 2 * 2 // 2, TILE[1] // 2
    cameras = [
        Camera.one_point(centre, radius * 1.3, width=w, height=h),
        Camera.two_point(centre, radius * 1.3, width=w, height=h),
        Camera.three_point(centre, radius * 1.3, width=w, height=h),
        Camera.isometric(centre, radius * 1.1, width=w, height=h),
        Camera.dimetric(centre, radius * 1.1, width=w, height=h),
        Camera.cavalier(centre, radius * 1.3, width=w, height=h),
        Camera.cabinet(centre, radius * 1.1, width=w, height=h),
    ]
    return _strip([rasterkit.render(mesh, c, mode="solid+wire", color="lightgray").color
                   for c in cameras])


def main() -> None:
    DOCS.mkdir(exist_ok=True)
    save_image(modes(), DOCS / "modes.png")
    save_image(projections(), DOCS / "projections.png")
    print("wrote", DOCS / "modes.png", "and", DOCS / "projections.png")


if __name__ == "__main__":
    main()
