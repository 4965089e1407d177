"""Textured frames: rasterkit against Mesa llvmpipe drawing the same textured mesh (issue 27).

rasterkit's frame is one ``rasterkit.render(mesh, camera, "solid", shading=...,
texture_filter=...)`` call; llvmpipe's is clear + draw + read back with a GLSL shader doing
``texture()`` with the same filter (:class:`benchmarks.texture_peer.TexturedGL`): the same
triangles, corner coordinates and normals, camera matrix and texture, uploaded once with
rasterkit's own mip levels, so both sides sample the same texels (each record's note gives
how many covered pixels agree within 2/255). The models are in
:mod:`benchmarks.textured_models`.

The first model of ``settings.texture_models`` (spot) is drawn smooth and trilinear (the
issue's main frame), flat and trilinear, smooth and bilinear, and untextured
(``textures=False``) against llvmpipe's untextured smooth frame (the same shader without the
texture), so that what texturing costs each side shows; every other model smooth and
trilinear. The smooth trilinear frames of spot and of the larger models (beast,
lost_empire) at 1920x1080 carry the issue's target, <= 0.5x llvmpipe's time. The memory
rows (the texture's bytes, 50 frames) are :mod:`benchmarks.texture_memory`'s.
"""

from __future__ import annotations

from functools import partial

import numpy as np

import rasterkit

from . import texture_memory
from .compare import RASTERKIT, compare, start
from .render import frame
from .report import Target
from .settings import TARGET_SIZE
from .texture_peer import TexturedGL
from .textured_models import MODELS, load, peer_reason, upload

FAMILY = "textures"
PEER = "llvmpipe"

TARGET = Target("rasterkit <= 0.5x llvmpipe time (textured, smooth, trilinear)", 0.5)
"""The issue's speed bar for spot and a larger textured model, at 1920x1080."""

MAIN = "smooth", "trilinear"
VARIANTS = (MAIN, ("flat", "trilinear"), ("smooth", "bilinear"), ("smooth", None))
"""(shading, texture filter) of the first model's frames; None: untextured."""


def _agreement(mesh, camera, shading: str, texture_filter: str | None, drawn: np.ndarray) -> str:
    """The share of covered pixels where the two images agree within 2/255 per channel."""
    fb = rasterkit.render(mesh, camera, "solid", shading=shading, texture_filter=texture_filter or "trilinear",
                          textures=texture_filter is not None, ids=True)
    covered = fb.ids >= 0
    difference = np.abs(fb.color[..., :3].astype(np.int16) - drawn.astype(np.int16))[covered].max(axis=1)
    share = float((difference <= 2).mean()) if covered.any() else float("nan")
    return f"{100 * share:.2f} % of {int(covered.sum())} covered pixels within 2/255 of llvmpipe's"


def _frame(results, gl, model: str, mesh, camera, shading: str, texture_filter: str | None, settings):
    """Time one frame of ``mesh`` on both sides; {side: median seconds} or None."""
    width, height = camera.width, camera.height
    sides = {RASTERKIT: partial(rasterkit.render, mesh, camera, "solid", shading=shading,
                                texture_filter=texture_filter or "trilinear", textures=texture_filter is not None)}
    texture = mesh.textured.textures[0]
    note = f"texture {texture.width}x{texture.height}" + ("" if texture_filter else ", drawn untextured")
    name = f"textures/{shading}/{texture_filter or 'untextured'}/{model}/{width}x{height}"
    why = peer_reason(mesh) if gl else None
    if why:
        results.skip(FAMILY, f"{name} [{PEER}]", f"llvmpipe cannot draw the same frame: {why}")
    elif gl:
        try:
            peer = partial(gl.draw, upload(gl, mesh, camera, shading, texture_filter))
            note += "; " + _agreement(mesh, camera, shading, texture_filter, peer())
            sides[PEER] = peer
        except Exception as error:  # report and carry on: rasterkit's side still runs
            results.skip(FAMILY, f"{name} [{PEER}]", f"failed: {type(error).__name__}: {error}")
    target = MODELS[model].target and (shading, texture_filter) == MAIN and (width, height) == TARGET_SIZE
    return compare(results, FAMILY, name, sides, repeat=settings.repeat, warmup=settings.warmup,
                   sizes={"width": width, "height": height, "triangles": len(mesh.faces),
                          "shading": shading, "filter": texture_filter or "untextured"},
                   work=len(mesh.faces), unit="tri/s", targets={PEER: TARGET} if target else {}, note=note)


def _cost(model: str, textured: dict | None, untextured: dict | None) -> None:
    """Print what texturing adds to each side's smooth frame."""
    if not textured or not untextured:
        return
    parts = [f"{side} +{1e3 * (textured[side] - untextured[side]):.1f} ms "
             f"({textured[side] / untextured[side]:.2f}x its untextured frame)"
             for side in textured if side in untextured]
    print(f"  texturing {model}'s smooth trilinear frame costs: " + ", ".join(parts), flush=True)


def run(settings, results, peers) -> None:
    """The textured frames of ``settings.texture_models`` at ``settings.texture_size``, then the
    memory rows."""
    llvmpipe = start(results, FAMILY, PEER, peers.llvmpipe)
    gl = TexturedGL(llvmpipe) if llvmpipe else None
    width, height = settings.texture_size
    opened: dict = {}
    for k, model in enumerate(settings.texture_models):
        try:
            mesh = load(model, opened)
        except (FileNotFoundError, ValueError) as why:
            results.skip(FAMILY, model, str(why))
            continue
        camera = frame(mesh, width, height)
        medians = {variant: _frame(results, gl, model, mesh, camera, *variant, settings)
                   for variant in (VARIANTS if k == 0 else (MAIN,))}
        _cost(model, medians.get(MAIN), medians.get(("smooth", None)))
    texture_memory.run(settings, results)
