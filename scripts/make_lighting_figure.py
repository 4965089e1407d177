"""The lighting figure of the README and docs/lighting.md: the same scene (the built-in demo
torus and a ball) under the classic headlight, Blinn-Phong (phong shading, its default
lights), three coloured lights, a key light casting shadows on the ground, ambient
occlusion, and the shadow alone over a transparent background (shown over a checkerboard).

``python scripts/make_lighting_figure.py`` writes docs/lighting.png."""

from __future__ import annotations

from pathlib import Path

import numpy as np

import rasterkit
from rasterkit import Light, shapes, transform
from rasterkit.image import save_image

ROOT = Path(__file__).resolve().parents[1]
SIZE = (400, 300)

KEY = Light.directional((-1.0, -1.6, -0.8), color="white", intensity=1.0)
THREE = [Light.directional((-1.0, -1.6, -0.8), color="#fff0d8", intensity=0.9),   # key, warm
         Light.point((-2.5, 1.2, 2.0), color="#80a8ff", intensity=6.0),            # fill, blue
         Light.spot((1.5, 2.5, -2.5), (-0.5, -0.8, 1.0), angle=50, color="#ff9060", intensity=14.0),  # rim
         Light.ambient(intensity=0.04)]


def scene() -> rasterkit.Scene:
    ball = shapes.icosphere(4, 0.45)
    return rasterkit.Scene().add(shapes.demo(), color="#c8c8c8").add(ball, transform.translate(1.35, 0.0, 0.6),
                                                                      color="#d09060")


PANELS = {
    "headlight (flat, the default)": dict(),
    "phong": dict(shading="phong"),
    "three lights": dict(shading="phong", lights=THREE),
    "shadows on the ground": dict(shading="phong", lights=[KEY, Light.ambient(intensity=0.08)], shadows=True,
                                  ground="#e0e0e0", shadow_softness=1.5),
    "ambient occlusion": dict(shading="phong", lights=[KEY, Light.ambient(intensity=0.3)], ao=True, ground="#e0e0e0"),
    "only the shadow, over a transparent background": dict(shading="phong", lights=[KEY, Light.ambient(intensity=0.3)],
                                                           shadows=True, ao=True, ground="shadow",
                                                           shadow_softness=1.5),
}


def _over_checkerboard(rgba: np.ndarray) -> np.ndarray:
    """``rgba`` composited over a light grey checkerboard of 16-pixel squares."""
    y, x = np.indices(rgba.shape[:2])
    board = np.where(((x // 16 + y // 16) % 2 == 0)[..., None], 236.0, 200.0)
    a = rgba[..., 3:4] / 255.0
    return np.rint(rgba[..., :3] * a + board * (1.0 - a)).astype(np.uint8)


def main() -> None:
    model = scene()
    camera = rasterkit.View(size=SIZE, azimuth=25, elevation=28).camera_for(model)
    frames = [rasterkit.render(model, camera, "solid", samples=4, **options).color for options in PANELS.values()]
    frames = [_over_checkerboard(f) if f.shape[2] == 4 else f for f in frames]
    rows = [np.concatenate(frames[k:k + 2], axis=1) for k in range(0, len(frames), 2)]
    save_image(np.concatenate(rows, axis=0), ROOT / "docs" / "lighting.png")


if __name__ == "__main__":
    main()
