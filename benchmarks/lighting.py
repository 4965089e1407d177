"""Lit frames: rasterkit's per-pixel Blinn-Phong against Mesa llvmpipe running the same GLSL.

Three frames of each model of ``settings.lighting_models`` (the built-in demo torus, then
shared models) at ``settings.lighting_size``, every one against llvmpipe:

- ``lighting/phong/two-lights/...``: ``rasterkit.render(mesh, camera, "solid",
  shading="phong", lights=[a warm directional light, a cool point light])``. The peer is a
  GLSL 330 fragment shader doing the same Blinn-Phong per pixel (:class:`LitGL`): the
  world-space position and the smooth normal (``Mesh.smooth_corners``, the normals
  rasterkit interpolates) as varyings, the base colour (rasterkit's default, light grey)
  decoded from sRGB, for each light ``a C (base max(n.l, 0) + specular max(n.h, 0)^shininess)``
  where ``n.l > 0`` (directional ``a = 1``, point ``a = 1 / d^2``), the sum clamped and encoded
  to sRGB in the shader; ``specular`` and ``shininess`` are ``RenderOptions``' (0.25, 32).
  Target: rasterkit <= 0.4x llvmpipe's time at 1920x1080.
- ``lighting/phong/shadowed-directional/...``: one directional light with ``shadows=True``
  (a shadow map ``default_map_size`` texels a side, 2048 at 1920x1080, passed explicitly as
  ``shadow_map_size``; ``shadow_softness=1``: 3x3 percentage-closer filtering). The peer
  draws the same two passes each frame: depth only into a square depth texture of that size
  from the light's orthographic camera (the very camera rasterkit fits,
  :func:`rasterkit.raster.shadows.shadow_maps`, taken once before timing so that both maps
  cover the same area), no culling (rasterkit's casters cast from both sides), then the lit
  pass looking the map up with a ``sampler2DShadow`` (nearest, so each lookup is one
  compare) at the 3x3 texels around the point, each compared, as rasterkit's
  ``shadow_factor`` does, with the depth of the face's plane at that texel (the face normal
  from ``dFdx``/``dFdy`` of the position) less its slope-scaled leeway, none where the light
  is behind the face. (rasterkit fits its map anew in each frame, from a quarter-size map
  and the visible surface: work the peer is spared.) Target: rasterkit <= 0.5x llvmpipe's time at
  1920x1080.
- ``lighting/ao/...``: ``rasterkit.render(mesh, camera, "solid", ao=True)`` (screen-space
  ambient occlusion, its default radius and 8 rays) against the same frame without it, on
  rasterkit's side only ("solid frame"): the issue's bar is that AO adds at most the time
  of a plain solid frame, a ratio of at most 2.
- ``lighting/solid/unlit/...``: the plain solid frame without lights (flat Lambert with a
  headlight, the default) against :meth:`benchmarks.peers.Llvmpipe.draw`'s ``"solid"``, the
  ``render`` family's pair: what the lit frames cost over the unlit one, in the same run.

Each record's note gives the share of covered pixels (rasterkit's ``ids >= 0``) where the
two images differ by more than 2/255 in some channel, and the largest difference, so a row
whose sides draw different pictures shows. A line per model prints what lighting costs each
side over its unlit solid frame. Timing as every family: :func:`benchmarks.compare.compare`
(a checking run, warm-up, interleaved timed runs, medians).
"""

from __future__ import annotations

from functools import partial

import numpy as np

import rasterkit

from .compare import RASTERKIT, compare, start
from .lighting_peer import AMBIENT, DIRECTIONAL, POINT, SOFTNESS, LitGL, Scene, decode_srgb
from .render import frame
from .report import Target
from .settings import TARGET_SIZE, model_path

FAMILY = "lighting"
PEER = "llvmpipe"

DEMO = "demo"
"""The name of the built-in demo model (``rasterkit.shapes.demo()``) in ``lighting_models``."""

TARGETS = {
    "two-lights": Target("rasterkit <= 0.4x llvmpipe time (phong, two lights)", 0.4),
    "shadowed-directional": Target("rasterkit <= 0.5x llvmpipe time (phong, shadowed light, 2 passes)", 0.5),
    "ao": Target("AO adds <= 1x a plain solid frame (solid+AO <= 2x solid)", 2.0),
}

SOLID = "solid frame"
"""The other side of the ``ao`` row: rasterkit's own solid frame without ambient occlusion."""
"""The lighting issue's speed bars, at 1920x1080."""

TOLERANCE = 2
"""A pixel agrees when no channel differs by more than this (of 255)."""


# The lights, sRGB colours as 0-255 triples (the GL side decodes the same numbers).
WARM, COOL, WHITE = (255, 224, 176), (128, 176, 255), (255, 255, 255)


def scene(mesh, camera, shadowed: bool) -> Scene:
    """Lights placed around ``mesh`` as ``camera`` sees it (so that they light its visible
    side): two lights (a warm directional light from the upper right front, a cool point
    light at the left, its intensity 1.5 times the square of the model's radius so that it is
    about as bright as the other on the model), or ``shadowed``: one white directional light casting
    shadows."""
    right, up, backward = (np.asarray(a, np.float64) for a in camera.basis())
    centre, radius = mesh.bounding_sphere()
    centre = np.asarray(centre, np.float64)
    direction = -(0.6 * right + 0.9 * up + 0.5 * backward)
    direction /= np.linalg.norm(direction)
    if shadowed:
        lights = ((rasterkit.Light.directional(tuple(direction), WHITE, 1.0, shadows=True), WHITE),)
    else:
        position = centre + radius * (-1.4 * right + 0.2 * up + 1.2 * backward)
        lights = ((rasterkit.Light.directional(tuple(direction), WARM, 0.9), WARM),
                  (rasterkit.Light.point(tuple(position), COOL, 1.5 * radius * radius), COOL))
    table = []
    for light, srgb in lights:
        kind = {"ambient": AMBIENT, "directional": DIRECTIONAL, "point": POINT}[light.kind]
        table.append((kind, tuple(light.position or (0.0, 0.0, 0.0)), tuple(light.direction or (0.0, 0.0, 0.0)),
                      tuple(float(c) for c in decode_srgb(srgb) * light.intensity)))
    kinds, positions, directions, colors = zip(*table)
    return Scene(tuple(light for light, _ in lights), kinds, positions, directions, colors, 0 if shadowed else -1)


def _agreement(render, drawn: np.ndarray) -> str:
    """How the GL image ``drawn`` differs from rasterkit's (``render(ids=True)``) over the
    covered pixels: the share beyond :data:`TOLERANCE`, the largest difference, and how many
    of those pixels lie on the silhouette (a covered pixel next to an uncovered one)."""
    fb = render(ids=True)
    covered = fb.ids >= 0
    if not covered.any():
        return "no pixel covered"
    difference = np.abs(fb.color[..., :3].astype(np.int16) - drawn.astype(np.int16)).max(axis=2)
    beyond = (difference > TOLERANCE) & covered
    inside = covered.copy()
    inside[1:] &= covered[:-1]
    inside[:-1] &= covered[1:]
    inside[:, 1:] &= covered[:, :-1]
    inside[:, :-1] &= covered[:, 1:]
    count = int(beyond.sum())
    share = count / int(covered.sum())
    text = (f"{100 * share:.2f} % of {int(covered.sum())} covered pixels differ from llvmpipe's by more than "
            f"{TOLERANCE}/255 (largest {int(difference[covered].max())}/255")
    if count:
        text += f"; {100 * (beyond & ~inside).sum() / count:.0f} % of them on the silhouette"
    return text + ")"


def _load(model: str):
    if model == DEMO:
        return rasterkit.shapes.demo()
    path = model_path(model)
    if not path.is_file():
        raise FileNotFoundError(f"model file {path} not found")
    return rasterkit.load_obj(path)


def _map_size(width: int, height: int) -> int:
    """rasterkit's default shadow map side for the image (2048 at 1920x1080)."""
    from rasterkit.raster.shadows import default_map_size

    return default_map_size(width, height)


def _row(results, settings, gl, model: str, mesh, camera, row: str) -> dict | None:
    """Time one row of ``model`` on both sides: {side: median seconds} or None."""
    width, height = camera.width, camera.height
    kind = {"unlit": "solid/unlit", "ao": "ao"}.get(row, "phong/" + row)
    name = f"lighting/{kind}/{model}/{width}x{height}"
    sizes = {"width": width, "height": height, "triangles": len(mesh.faces)}
    note = ""
    if row == "ao":
        target = TARGETS[row] if (width, height) == TARGET_SIZE else None
        sides = {RASTERKIT: partial(rasterkit.render, mesh, camera, "solid", ao=True),
                 SOLID: partial(rasterkit.render, mesh, camera, "solid")}
        return compare(results, FAMILY, name, sides, repeat=settings.repeat, warmup=settings.warmup,
                       sizes={**sizes, "ao": True}, work=len(mesh.faces), unit="tri/s",
                       targets={SOLID: target} if target else {})
    if row == "unlit":
        render = partial(rasterkit.render, mesh, camera, "solid")
        peer = partial(gl.peer.draw, gl.peer.upload(mesh, camera), "solid") if gl else None
        sizes["lights"] = 0
    else:
        lights = scene(mesh, camera, shadowed=row == "shadowed-directional")
        map_size = _map_size(width, height) if lights.shadowed >= 0 else 0
        extra = {"shadow_map_size": map_size, "shadow_softness": SOFTNESS} if map_size else {}
        render = partial(rasterkit.render, mesh, camera, "solid", shading="phong", lights=list(lights.lights),
                         **extra)
        sizes.update({"lights": len(lights.lights), "shading": "phong"})
        if map_size:
            sizes.update({"shadow_map": map_size, "pcf": "3x3"})
            note = f"shadow map {map_size}x{map_size}, 3x3 PCF; "
        peer = None
        if gl:
            try:
                peer = partial(gl.draw, gl.upload(mesh, camera, lights, map_size))
            except Exception as error:  # report and carry on: rasterkit's side still runs
                results.skip(FAMILY, f"{name} [{PEER}]", f"failed: {type(error).__name__}: {error}")
    sides = {RASTERKIT: render}
    if peer is not None:
        try:
            note += _agreement(render, peer())
            sides[PEER] = peer
        except Exception as error:
            results.skip(FAMILY, f"{name} [{PEER}]", f"failed: {type(error).__name__}: {error}")
    target = TARGETS.get(row) if (width, height) == TARGET_SIZE else None
    return compare(results, FAMILY, name, sides, repeat=settings.repeat, warmup=settings.warmup, sizes=sizes,
                   work=len(mesh.faces), unit="tri/s", targets={PEER: target} if target else {},
                   note=note.rstrip("; "))


ROWS = ("two-lights", "shadowed-directional", "ao", "unlit")


def _cost(model: str, medians: dict) -> None:
    """Print what each lit frame adds to each side's unlit solid frame."""
    unlit = medians.get("unlit")
    if not unlit:
        return
    for row in ROWS[:2]:
        lit = medians.get(row)
        if not lit:
            continue
        parts = [f"{side} +{1e3 * (lit[side] - unlit[side]):.1f} ms ({lit[side] / unlit[side]:.2f}x its unlit frame)"
                 for side in lit if side in unlit]
        print(f"  {model}'s phong {row} frame costs: " + ", ".join(parts), flush=True)


def run(settings, results, peers) -> None:
    """The three rows of every model of ``settings.lighting_models`` at ``settings.lighting_size``."""
    llvmpipe = start(results, FAMILY, PEER, peers.llvmpipe)
    gl = None
    if llvmpipe:
        try:
            gl = LitGL(llvmpipe)
        except Exception as error:  # a shader llvmpipe refuses: rasterkit's side still runs
            results.skip(FAMILY, PEER, f"failed: {type(error).__name__}: {error}")
    width, height = settings.lighting_size
    for model in settings.lighting_models:
        try:
            mesh = _load(model)
        except (FileNotFoundError, ValueError) as why:
            results.skip(FAMILY, model, str(why))
            continue
        camera = frame(mesh, width, height)
        medians = {row: _row(results, settings, gl, model, mesh, camera, row) for row in ROWS}
        _cost(model, medians)
