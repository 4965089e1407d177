"""Rendering real models: rasterkit.render against Mesa llvmpipe, every mode and resolution.

Per model (small to large) and resolution, both sides get the same triangles, edge list and
camera matrix (``Camera.frame`` around the bounding sphere). rasterkit's frame is one
``rasterkit.render(...)`` call: a new framebuffer, the vertex transform, shading, the
rasterization and the lines; llvmpipe's is clear + draw + read back into NumPy, its buffers
uploaded once beforehand (see :class:`benchmarks.peers.Llvmpipe` for each mode's GL form:
GL_LINES for wire, a depth pass with glPolygonOffset then depth-tested GL_LINES for hidden
and solid+wire, flat Lambert for solid).
"""

from __future__ import annotations

from functools import partial

import rasterkit

from .compare import RASTERKIT, compare, start
from .report import Target
from .settings import MODES, TARGET_MODELS, TARGET_SIZE, model_path

FAMILY = "render"

TARGETS = {
    "solid": Target("rasterkit <= 0.33x llvmpipe time", 0.33),
    "wire": Target("rasterkit <= 0.1x llvmpipe GL_LINES time", 0.1),
    "hidden": Target("rasterkit <= 0.5x llvmpipe solid-plus-lines time", 0.5),
}
"""Goals of the rasterization issue, at 1920x1080 for the models in ``TARGET_MODELS``."""


def load_models(results, family: str, names) -> dict:
    """{name: Mesh} of the shared models that exist; the missing ones are reported."""
    meshes = {}
    for name in names:
        path = model_path(name)
        if not path.is_file():
            results.skip(family, name, f"model file {path} not found")
            continue
        meshes[name] = rasterkit.load_obj(path)
    return meshes


def frame(mesh, width: int, height: int) -> rasterkit.Camera:
    """The camera of every render workload: the model's bounding sphere filling the view."""
    center, radius = mesh.bounding_sphere()
    return rasterkit.Camera.frame(center, radius, width=width, height=height)


def _targets(model: str, size: tuple, mode: str) -> dict:
    if model in TARGET_MODELS and tuple(size) == TARGET_SIZE and mode in TARGETS:
        return {"llvmpipe": TARGETS[mode]}
    return {}


def run(settings, results, peers) -> None:
    """Every model x resolution x mode of ``settings``."""
    gl = start(results, FAMILY, "llvmpipe", peers.llvmpipe)
    for model, mesh in load_models(results, FAMILY, settings.models).items():
        for width, height in settings.sizes:
            camera = frame(mesh, width, height)
            glmesh = gl.upload(mesh, camera) if gl else None
            for mode in MODES:
                sides = {RASTERKIT: partial(rasterkit.render, mesh, camera, mode=mode)}
                if gl:
                    sides["llvmpipe"] = partial(gl.draw, glmesh, mode)
                is_wire = mode == "wire"
                compare(results, FAMILY, f"render/{mode}/{model}/{width}x{height}", sides,
                        repeat=settings.repeat, warmup=settings.warmup,
                        sizes={"width": width, "height": height, "triangles": len(mesh.faces),
                               "edges": len(mesh.edges)},
                        work=len(mesh.edges) if is_wire else len(mesh.faces),
                        unit="edge/s" if is_wire else "tri/s",
                        targets=_targets(model, (width, height), mode))
