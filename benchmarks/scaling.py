"""How the cost grows: with threads, with the triangle count and with the pixel count.

threads
    The fill-rate scene and a solid frame of the largest model, on 1, 2, ... N Numba threads
    (each side is "n threads" against "1 thread", both rasterkit).
triangle count
    A torus tessellated ever more finely (same image coverage, 1920x1080 unless the profile
    says otherwise), solid, against llvmpipe: the cost per triangle.
pixel count
    One model, solid, at growing resolutions, against llvmpipe: the cost per pixel.

For each sweep and side the exponent ``b`` of the least-squares fit ``time = a * size^b``
(log-log) is reported: 1 is linear growth; well below 1 means a fixed cost dominates.
"""

from __future__ import annotations

from functools import partial

import numba
import numpy as np

import rasterkit

from . import fill
from .compare import RASTERKIT, compare, start
from .render import frame, load_models
from .report import Target
from .settings import TARGET_SIZE

TARGET = Target("2 threads >= 1.7x 1 thread", 1 / 1.7)


def exponent(sizes, seconds) -> float | None:
    """Slope of log(seconds) against log(size), or None with fewer than two points."""
    if len(sizes) < 2:
        return None
    return float(np.polyfit(np.log(sizes), np.log(seconds), 1)[0])


def _solid(mesh, camera):
    """rasterkit's solid frame of ``mesh`` seen by ``camera``."""
    return lambda: rasterkit.render(mesh, camera, mode="solid").color


def _threaded(n: int, draw):
    """``draw`` on ``n`` threads (setting the count is part of the run: it costs nothing)."""
    def run():
        rasterkit.set_threads(n)
        return draw()
    return run


def run_threads(settings, results, peers) -> None:
    """n threads against 1, n = 2 .. NUMBA_NUM_THREADS."""
    most = numba.config.NUMBA_NUM_THREADS
    if most < 2:
        results.skip("threads", "thread scaling", f"only {most} Numba thread on this machine")
        return
    width, height = settings.fill_size
    count = fill.TARGET_COUNT if fill.TARGET_COUNT in settings.fill_counts else settings.fill_counts[-1]
    scene = fill.scene(count, width, height)
    draws = {f"fill/{count}tri": (lambda: fill.draw_rasterkit(scene), {"triangles": count})}
    for model, mesh in load_models(results, "threads", settings.models[-1:]).items():
        draws[f"render/solid/{model}"] = (_solid(mesh, frame(mesh, width, height)),
                                          {"triangles": len(mesh.faces)})
    try:
        for name, (draw, sizes) in draws.items():
            for n in range(2, most + 1):
                is_target = n == 2 and name == f"fill/{fill.TARGET_COUNT}tri" and (width, height) == TARGET_SIZE
                compare(results, "threads", f"threads/{name}/{width}x{height}/{n}",
                        {RASTERKIT: _threaded(n, draw), "rasterkit 1 thread": _threaded(1, draw)},
                        repeat=settings.repeat, warmup=settings.warmup,
                        sizes={"width": width, "height": height, **sizes, "threads": n},
                        targets={"rasterkit 1 thread": TARGET} if is_target else None)
    finally:
        rasterkit.set_threads(None)


def _sweep(settings, results, gl, name: str, cases) -> None:
    """Time each (label, mesh, camera, sizes) case solid on both sides; fit the exponents."""
    points: dict[str, list[tuple[float, float]]] = {}
    for label, mesh, camera, sizes, size in cases:
        sides = {RASTERKIT: _solid(mesh, camera)}
        if gl:
            glmesh = gl.upload(mesh, camera)
            sides["llvmpipe"] = partial(gl.draw, glmesh, "solid")
        medians = compare(results, "scaling", f"scaling/{name}/{label}", sides, repeat=settings.repeat,
                          warmup=settings.warmup, sizes=sizes, work=size,
                          unit="tri/s" if name == "triangles" else "pixel/s")
        for side, seconds in (medians or {}).items():
            points.setdefault(side, []).append((size, seconds))
    for side, xy in points.items():
        b = exponent(*zip(*xy, strict=True))
        if b is not None:
            results.fit(f"{name}", side, b, [x for x, _ in xy])


def run(settings, results, peers) -> None:
    """Thread scaling, then the triangle-count and pixel-count sweeps."""
    run_threads(settings, results, peers)
    gl = start(results, "scaling", "llvmpipe", peers.llvmpipe)
    width, height = settings.fill_size
    tori = []
    for rings in settings.sweep_triangles:
        mesh = rasterkit.shapes.torus(rings=rings, sides=max(rings // 2, 3))
        tori.append((f"torus-{len(mesh.faces)}tri/{width}x{height}", mesh, frame(mesh, width, height),
                     {"width": width, "height": height, "triangles": len(mesh.faces)}, len(mesh.faces)))
    _sweep(settings, results, gl, "triangles", tori)
    models = load_models(results, "scaling", [settings.sweep_model])
    for model, mesh in models.items():
        cases = [(f"{model}/{w}x{h}", mesh, frame(mesh, w, h),
                  {"width": w, "height": h, "triangles": len(mesh.faces)}, w * h)
                 for w, h in settings.sweep_sizes]
        _sweep(settings, results, gl, "pixels", cases)
