"""Fill rate: large overlapping triangles at several depth complexities, pixels per second.

The scene is ``count`` random triangles spread over the view (and a little beyond it) at
random depths, seen by an orthographic camera, drawn solid with flat shading, no culling and
the depth test on: about 18 layers deep for 200 triangles. Both sides draw the same
triangles with the same camera matrix; the pixel count (the work) is the area of the
triangles inside the image, computed exactly from the projected corners, so it is the same
number for both sides and independent of either.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial

import numpy as np

import rasterkit

from .compare import RASTERKIT, compare, start
from .report import Target
from .settings import TARGET_SIZE

FAMILY = "fill"
TARGET_COUNT = 200
TARGET = Target("rasterkit >= 1.5x llvmpipe pixel/s", 1 / 1.5)

SPREAD = 0.09
"""Corners fall in the view grown by this fraction on each side (as in bench_triangles.py)."""


@dataclass(frozen=True)
class FillScene:
    """A fill-rate scene: the mesh, its camera and the pixels its triangles cover."""

    mesh: rasterkit.Mesh
    camera: rasterkit.Camera
    pixels: float

    @property
    def layers(self) -> float:
        """Depth complexity: covered pixels per image pixel."""
        return self.pixels / (self.camera.width * self.camera.height)


def _clipped_area(polygon: np.ndarray, width: int, height: int) -> float:
    """Area (pixels) of a convex polygon (K, 2) inside [0, W] x [0, H] (Sutherland-Hodgman)."""
    for axis, limit, keep_below in ((0, 0.0, False), (0, width, True), (1, 0.0, False), (1, height, True)):
        if len(polygon) == 0:
            return 0.0
        inside = polygon[:, axis] <= limit if keep_below else polygon[:, axis] >= limit
        kept = []
        for k in range(len(polygon)):
            a, b = polygon[k], polygon[(k + 1) % len(polygon)]
            if inside[k]:
                kept.append(a)
            if inside[k] != inside[(k + 1) % len(polygon)]:
                t = (limit - a[axis]) / (b[axis] - a[axis])
                kept.append(a + t * (b - a))
        polygon = np.array(kept).reshape(-1, 2)
    x, y = polygon[:, 0], polygon[:, 1]
    return 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))


def scene(count: int, width: int, height: int, seed: int = 1) -> FillScene:
    """``count`` random triangles filling a ``width`` x ``height`` view, several layers deep."""
    rng = np.random.default_rng(seed)
    aspect = width / height
    corners = rng.uniform(-(1 + SPREAD), 1 + SPREAD, (count * 3, 2)) * [aspect, 1.0]
    depths = rng.uniform(-8.0, 8.0, (count * 3, 1))
    mesh = rasterkit.Mesh(np.hstack([corners, depths]), np.arange(count * 3).reshape(count, 3))
    camera = rasterkit.Camera.orthographic(eye=(0.0, 0.0, 10.0), target=(0.0, 0.0, 0.0),
                                           view_height=2.0, width=width, height=height,
                                           near=1.0, far=19.0)
    raster = camera.project(mesh.vertices)[:, :2].reshape(count, 3, 2)
    pixels = sum(_clipped_area(triangle, width, height) for triangle in raster)
    return FillScene(mesh, camera, pixels)


def draw_rasterkit(fill: FillScene) -> np.ndarray:
    """rasterkit's fill frame: solid, flat, no culling."""
    return rasterkit.render(fill.mesh, fill.camera, mode="solid", cull="none").color


def run(settings, results, peers) -> None:
    """One scene per triangle count of ``settings.fill_counts`` at ``settings.fill_size``."""
    gl = start(results, FAMILY, "llvmpipe", peers.llvmpipe)
    width, height = settings.fill_size
    for count in settings.fill_counts:
        fill = scene(count, width, height)
        sides = {RASTERKIT: partial(draw_rasterkit, fill)}
        if gl:
            glmesh = gl.upload(fill.mesh, fill.camera, cull="none")
            sides["llvmpipe"] = partial(gl.draw, glmesh, "solid")
        is_target = count == TARGET_COUNT and tuple(settings.fill_size) == TARGET_SIZE
        compare(results, FAMILY, f"fill/{count}tri/{width}x{height}", sides,
                repeat=settings.repeat, warmup=settings.warmup,
                sizes={"width": width, "height": height, "triangles": count,
                       "layers": round(fill.layers, 1)},
                work=fill.pixels, unit="pixel/s",
                targets={"llvmpipe": TARGET} if is_target else None)
