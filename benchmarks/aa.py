"""Anti-aliasing: rasterkit's ``samples=4`` against llvmpipe's 4x MSAA, solid frames.

rasterkit's frame is one ``rasterkit.render(mesh, camera, "solid", samples=4)`` call (four
jittered samples per pixel, averaged: :mod:`rasterkit.raster.accumulate`); llvmpipe's is clear +
draw into a 4-sample multisampled framebuffer + resolve (``copy_framebuffer``) + read back
(:meth:`benchmarks.peers.Llvmpipe.draw` with ``samples=4``). Same triangles, camera and flat
Lambert shading as the ``render`` family's solid frames.
"""

from __future__ import annotations

from functools import partial

import rasterkit

from .compare import RASTERKIT, compare, start
from .render import frame, load_models
from .report import Target
from .settings import TARGET_SIZE

FAMILY = "aa"

SAMPLES = 4

TARGET = Target("rasterkit samples=4 <= 0.8x llvmpipe 4x MSAA time", 0.8)
"""The goal of the lens-camera issue, at 1920x1080 on a model of about 100k triangles."""


def run(settings, results, peers) -> None:
    """One solid frame of ``settings.aa_model`` at ``settings.aa_size``, 4 samples a pixel."""
    gl = start(results, FAMILY, "llvmpipe", peers.llvmpipe)
    width, height = settings.aa_size
    for model, mesh in load_models(results, FAMILY, (settings.aa_model,)).items():
        camera = frame(mesh, width, height)
        sides = {RASTERKIT: partial(rasterkit.render, mesh, camera, "solid", samples=SAMPLES)}
        if gl:
            sides["llvmpipe"] = partial(gl.draw, gl.upload(mesh, camera), "solid", samples=SAMPLES)
        targets = {"llvmpipe": TARGET} if tuple(settings.aa_size) == TARGET_SIZE else {}
        compare(results, FAMILY, f"aa/solid/{model}/{width}x{height}/{SAMPLES}x", sides,
                repeat=settings.repeat, warmup=settings.warmup,
                sizes={"width": width, "height": height, "triangles": len(mesh.faces), "samples": SAMPLES},
                work=len(mesh.faces), unit="tri/s", targets=targets)
