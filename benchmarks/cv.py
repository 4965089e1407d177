"""Computer-vision maps: a solid frame with everything a vision pipeline reads, against the
plain solid frame.

The ``rasterkit`` side is one ``rasterkit.render(mesh, camera, "solid", ids=True,
normals=True, camera_depth=True)`` followed by ``fb.camera_depth()``: colour, face ids,
camera-space normals and the metric depth (:mod:`rasterkit.raster.vision`), made band by band by the
drawing threads. The other side, ``plain solid``, is ``rasterkit.render(mesh, camera,
"solid")`` alone: the ratio is what the maps cost on top of the image.
"""

from __future__ import annotations

import rasterkit

from .compare import RASTERKIT, compare
from .render import frame, load_models
from .report import Target

FAMILY = "cv"

PLAIN = "plain solid"

TARGET = Target("colour + depth + normals + ids <= 1.5x a plain solid frame", 1.5)
"""The goal of the computer-vision issue, at 1920x1080."""


def vision_frame(mesh, camera):
    """Colour, ids, normals and metric depth of one frame."""
    fb = rasterkit.render(mesh, camera, "solid", ids=True, normals=True, camera_depth=True)
    return fb, fb.camera_depth()


def run(settings, results, peers) -> None:
    """One solid frame of ``settings.cv_model`` at ``settings.cv_size``, with and without the maps."""
    width, height = settings.cv_size
    for model, mesh in load_models(results, FAMILY, (settings.cv_model,)).items():
        camera = frame(mesh, width, height)
        sides = {RASTERKIT: lambda: vision_frame(mesh, camera),
                 PLAIN: lambda: rasterkit.render(mesh, camera, "solid")}
        compare(results, FAMILY, f"cv/solid/{model}/{width}x{height}", sides,
                repeat=settings.repeat, warmup=settings.warmup,
                sizes={"width": width, "height": height, "triangles": len(mesh.faces)},
                work=width * height, unit="pixel/s", targets={PLAIN: TARGET})
