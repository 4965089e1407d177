"""The textured models of the README and docs/textures.md: spot (its texture given through
the API), fuze (its .mtl names the texture) and tinyrenderer's African head (its diffuse map
and object-space normal map given through the API), smooth-shaded, trilinear.

``python scripts/make_textured_figure.py`` writes docs/textured.png (needs the shared models
beside the repository: ../shared/models)."""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

import numpy as np

import rasterkit
from rasterkit import Material, Texture, View
from rasterkit.image import save_image

ROOT = Path(__file__).resolve().parents[1]
MODELS = ROOT.parent / "shared" / "models"


def with_material(mesh, material):
    """``mesh`` with ``material`` on every face."""
    return dataclasses.replace(mesh, face_materials=np.zeros(len(mesh.faces), np.int32),
                               material_names=(material.name,), materials=(material,))


def models():
    head = MODELS / "formats" / "obj" / "african_head"
    spot = rasterkit.load_obj(MODELS / "spot.obj")
    yield with_material(spot, Material("spot", diffuse_map=Texture.open(MODELS / "spot_texture.png"))), \
        View(size=(400, 400), azimuth=145, elevation=15)
    yield rasterkit.load_obj(MODELS / "formats" / "obj" / "fuze" / "fuze.obj"), View(size=(400, 400), azimuth=20,
                                                                                   elevation=25)
    yield with_material(rasterkit.load_obj(head / "african_head.obj"),
                        Material("head", diffuse_map=Texture.open(head / "african_head_diffuse.tga"),
                                 normal_map=Texture.open(head / "african_head_nm.tga"), normal_space="object")), \
        View(size=(400, 400), azimuth=0, elevation=0, eye=(0.0, 0.0, 3.2), target=(0.0, 0.0, 0.0))


def main() -> int:
    if not MODELS.is_dir():
        print(f"{MODELS} is absent: the shared models are not part of the repository", file=sys.stderr)
        return 1
    panels = [rasterkit.render(mesh, view.camera_for(mesh), "solid", shading="smooth", samples=4).color
              for mesh, view in models()]
    save_image(np.concatenate(panels, axis=1), ROOT / "docs" / "textured.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
