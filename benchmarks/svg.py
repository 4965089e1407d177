"""Vector hidden-line drawings: ``rasterkit.render_svg`` against its time budget and fogleman/ln.

rasterkit's run is one ``render_svg(mesh, camera, mode="hidden")`` call: every polygon edge
clipped, split where it passes behind a face, chained, ordered and written as SVG text. The
targets of issue 16 are absolute, at 1920x1080: a 100k-triangle scan in 2 s (armadillo, the
largest scan of the shared models: 86k triangles) and sportsCar (301k triangles) in 5 s; each
is recorded against a peer named ``budget`` whose time is the budget (met: ratio <= 1).

fogleman/ln (Go) is the reference for the method: its ``Scene.Render`` chops every triangle's
three edges into steps of ``step`` world units and keeps the points from which a ray to the
eye reaches it unblocked (a BVH of the triangles). Its driver, ``benchmarks/ln/main.go``,
loads the same OBJ and renders it with the same camera (eye, target, field of view, near,
far), with ``step`` half a pixel at the target's distance, as rasterkit samples its edges
every half pixel; the time is what ln reports for ``Render`` alone (the OBJ loading
excluded), one run (it takes minutes). Build it (Go >= 1.19) and point
``RASTERKIT_LN`` at the binary (see ``benchmarks/ln/README.md``); without it ln's side is
skipped, with the reason printed.
"""

from __future__ import annotations

import os
import re
import subprocess
from functools import partial

import numpy as np

import rasterkit

from .compare import RASTERKIT, compare
from .render import frame, load_models
from .report import Record, Target
from .settings import TARGET_SIZE, model_path
from .timing import interleaved

FAMILY = "svg"

BUDGETS = {"armadillo": 2.0, "sportsCar": 5.0}
"""Seconds, warm, at 1920x1080: the targets of issue 16."""

LN_VARIABLE = "RASTERKIT_LN"
"""Environment variable holding the path of the built ``benchmarks/ln`` driver."""

LN_TIMEOUT = 900


def run(settings, results, peers) -> None:
    """Hidden-line SVG of each of ``settings.svg_models`` at ``settings.svg_size``; the
    feature-edge drawing of the last one."""
    width, height = settings.svg_size
    meshes = load_models(results, FAMILY, settings.svg_models)
    for model, mesh in meshes.items():
        camera = frame(mesh, width, height)
        name = f"svg/hidden/{model}/{width}x{height}"
        draw = partial(rasterkit.render_svg, mesh, camera, mode="hidden")
        try:
            draw()  # the checking run, and the compile
        except Exception as error:
            results.skip(FAMILY, name, f"failed: {type(error).__name__}: {error}")
            continue
        seconds = interleaved({RASTERKIT: draw}, settings.repeat, max(settings.warmup - 1, 0))[RASTERKIT]
        sizes = {"width": width, "height": height, "triangles": len(mesh.faces), "edges": len(mesh.edges)}
        common = dict(family=FAMILY, name=name, sizes=sizes, rasterkit=seconds, work=len(mesh.faces),
                      unit="tri/s", runs=settings.repeat)
        budget = BUDGETS.get(model) if tuple(settings.svg_size) == TARGET_SIZE else None
        if budget is not None:
            results.add(Record(peer="budget", peer_value=budget,
                               target=Target(f"rasterkit <= {budget:g} s (issue 16)", 1.0), **common))
        ln_seconds = _ln(results, name, model, camera)
        if ln_seconds is not None:
            results.add(Record(peer="ln", peer_value=ln_seconds, note=_LN_NOTE, **common))
        if budget is None and ln_seconds is None:
            results.add(Record(peer=None, **common))
    if meshes:
        model, mesh = list(meshes.items())[-1]
        camera = frame(mesh, width, height)
        compare(results, FAMILY, f"svg/hidden-feature/{model}/{width}x{height}",
                {RASTERKIT: partial(rasterkit.render_svg, mesh, camera, mode="hidden", edges="feature")},
                repeat=settings.repeat, warmup=settings.warmup,
                sizes={"width": width, "height": height, "triangles": len(mesh.faces)},
                work=len(mesh.faces), unit="tri/s")


_LN_NOTE = ("fogleman/ln 12e6c6e, Scene.Render alone (OBJ loading excluded), step = 0.5 px at the target, "
            "1 run")


def ln_arguments(camera, path, out) -> list[str]:
    """Command-line arguments of the ln driver for ``camera``: the model, the size, the eye,
    the target, the vertical field of view, near, far, and the step (half a pixel at the
    target's distance, in world units)."""
    distance = float(np.linalg.norm(np.subtract(camera.eye, camera.target)))
    step = 0.5 * 2 * distance * np.tan(np.radians(camera.fov_y) / 2) / camera.height
    numbers = [camera.width, camera.height, *camera.eye, *camera.target, camera.fov_y, camera.near,
               camera.far, step]
    return [str(path), *(repr(float(v)) for v in numbers), str(out)]


def _ln(results, name: str, model: str, camera) -> float | None:
    """Seconds of ln's ``Render`` on the model, or None (the reason recorded)."""
    binary = os.environ.get(LN_VARIABLE)
    what = f"{name} [ln]"
    if not binary or not os.path.isfile(binary):
        results.skip(FAMILY, what, f"set {LN_VARIABLE} to the built benchmarks/ln driver (see benchmarks/ln/README.md)")
        return None
    if camera.kind != "perspective":
        results.skip(FAMILY, what, "ln's driver takes perspective cameras")
        return None
    try:
        done = subprocess.run([binary, *ln_arguments(camera, model_path(model), os.devnull)],
                              capture_output=True, text=True, timeout=LN_TIMEOUT, check=True)
    except (OSError, subprocess.SubprocessError) as error:
        results.skip(FAMILY, what, f"ln failed: {type(error).__name__}: {str(error).splitlines()[0]}")
        return None
    found = re.search(r"render ([0-9.]+)", done.stdout)
    if not found:
        results.skip(FAMILY, what, f"ln printed no render time: {done.stdout.strip()[:80]!r}")
        return None
    return float(found.group(1))
