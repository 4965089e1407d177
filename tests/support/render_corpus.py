"""A fixed set of renders whose images must never change: every mode, shaded and not, lit
(lights, Blinn-Phong, shadows), textured, built-in shapes and real models, several projections, 1 and 2
threads, RGBA, ids, depth and the 2D line helpers. ``python tests/support/render_corpus.py``
prints their SHA-256 digests as JSON (how ``tests/data/render_checksums.json`` was made, before
the kernels were restructured; the lit renders' before the lit resolve was made one kernel);
``tests/raster/test_render_checksums.py`` compares against that file."""

from __future__ import annotations

import hashlib
import json
import sys
from pathlib import Path

import numpy as np

import rasterkit
from rasterkit import Camera, shapes, transform

# a path of its own, not support.paths: this file also runs as a script
MODELS = Path(__file__).resolve().parents[3] / "shared" / "models"
REAL_MODELS = ("stanford-bunny.obj", "sportsCar.obj", "CornellBox-Original.obj")
TEXTURED = "formats/obj/fuze/fuze.obj"  # its .mtl names its texture


def _digest(*arrays) -> str:
    h = hashlib.sha256()
    for a in arrays:
        a = np.ascontiguousarray(a)
        h.update(str((a.dtype.str, a.shape)).encode())
        h.update(a.tobytes())
    return h.hexdigest()


def _sphere(mesh):
    v = mesh.vertices[np.isfinite(mesh.vertices).all(axis=1)]
    center = (v.min(axis=0) + v.max(axis=0)) / 2
    return center, float(np.linalg.norm(v - center, axis=1).max())


def _frame(mesh, width, height, **kw):
    center, radius = _sphere(mesh)
    return Camera.preset(kw.pop("projection", "perspective"), center, radius, width=width, height=height, **kw)


def _cameras(mesh, size):
    w, h = size
    return {
        "persp": _frame(mesh, w, h, azimuth=30, elevation=20),
        "iso": _frame(mesh, w, h, projection="isometric"),
        "cabinet": _frame(mesh, w, h, projection="cabinet"),
        "3-point": _frame(mesh, w, h, projection="3-point"),
    }


def _renders(mesh, name, size, cameras=("persp", "iso", "cabinet", "3-point")):
    cams = _cameras(mesh, size)
    for cam_name in cameras:
        cam = cams[cam_name]
        for mode in ("wire", "hidden", "solid", "solid+wire"):
            yield f"{name}/{cam_name}/{mode}", lambda m=mode, c=cam: _color(rasterkit.render(mesh, c, mode=m))
    cam = cams["persp"]
    yield f"{name}/smooth", lambda: _color(rasterkit.render(mesh, cam, mode="solid", shading="smooth"))
    yield f"{name}/cull-none", lambda: _color(rasterkit.render(mesh, cam, mode="solid", cull="none"))
    yield f"{name}/aa-hidden", lambda: _color(rasterkit.render(mesh, cam, mode="hidden", aa=True))
    yield f"{name}/aa-wire", lambda: _color(rasterkit.render(mesh, cam, mode="wire", aa=True))
    yield f"{name}/rgba-solid+wire", lambda: _color(
        rasterkit.render(mesh, cam, mode="solid+wire", background="transparent"))
    yield f"{name}/ids-depth", lambda: _ids_depth(rasterkit.render(mesh, cam, mode="solid", ids=True))
    yield f"{name}/depth-solid", lambda: _digest(rasterkit.render(mesh, cam, mode="solid").depth)
    yield f"{name}/depth-hidden", lambda: _digest(rasterkit.render(mesh, cam, mode="hidden").depth)


def _lit_renders(mesh, name, size):
    """Lights, Blinn-Phong and shadows (issue 29's renders), placed by the model's bounding sphere."""
    center, radius = _sphere(mesh)
    cam = _frame(mesh, *size, azimuth=30, elevation=20)
    Light = rasterkit.Light
    at = [tuple(center + radius * np.array(v)) for v in ((1.5, 1.0, 1.5), (-1.2, 1.6, 0.8), (0.5, 2.0, -1.0))]
    key = Light.directional((-1, -2, -1), color="#ffe0b0", intensity=0.9)
    fill = Light.point(at[0], color="#80b0ff", intensity=0.3 * radius * radius)
    spot = Light.spot(at[1], tuple(center - np.array(at[1])), angle=40, blend=0.3, intensity=2 * radius * radius)
    ambient = Light.ambient("#202838", 1.0)
    renders = {
        "phong-two": dict(shading="phong", lights=[key, fill]),
        "flat-spot-ambient": dict(shading="flat", lights=[spot, ambient]),
        "smooth-three": dict(shading="smooth", lights=[key, fill, ambient], specular=0.6, shininess=20.5),
        "phong-shadows": dict(shading="phong", lights=[key, ambient], shadows=True, ground="#d8d8d8"),
        "phong-point-shadows": dict(shading="phong", lights=[Light.point(at[2], intensity=4 * radius * radius,
                                                                         shadows=True)], ground="shadow"),
        "phong-spot-shadows-two-sided": dict(shading="phong", lights=[Light.spot(
            at[1], tuple(center - np.array(at[1])), angle=40, blend=0.3, intensity=2 * radius * radius,
            shadows=True)], cull="none"),
        "phong-samples": dict(shading="phong", lights=[key, fill], samples=4),
        "phong-ids-depth": dict(shading="phong", lights=[key], ids=True),
    }
    for label, kw in renders.items():
        digest = _ids_depth if kw.get("ids") else _color
        yield f"{name}/lit/{label}", lambda kw=kw, digest=digest: digest(rasterkit.render(mesh, cam, mode="solid", **kw))


def _textured_renders(mesh, name, size):
    """A model drawn with its textures (issue 27's renders): filters, flat and smooth, lit per
    pixel with and without shadow maps, samples, ids."""
    cam = _frame(mesh, *size, azimuth=25, elevation=15)
    Light = rasterkit.Light
    renders = {
        "smooth": dict(shading="smooth"),
        "flat-nearest": dict(shading="flat", texture_filter="nearest"),
        "bilinear": dict(shading="smooth", texture_filter="bilinear"),
        "phong-two": dict(shading="phong", lights=[Light.directional((-1, -2, -1)), Light.ambient("#303030")]),
        "phong-shadows": dict(shading="phong", lights=[Light.directional((-1, -2, -1), shadows=True)]),
        "samples": dict(shading="smooth", samples=4),
        "ids-depth": dict(shading="smooth", ids=True),
    }
    for label, kw in renders.items():
        digest = _ids_depth if kw.get("ids") else _color
        yield f"{name}/textured/{label}", lambda kw=kw, digest=digest: digest(
            rasterkit.render(mesh, cam, mode="solid", **kw))


def _color(fb):
    return _digest(fb.color)


def _ids_depth(fb):
    return _digest(fb.color, fb.ids, fb.depth)


def _lines():
    rng = np.random.default_rng(7)
    segments = rng.uniform(-20, 220, size=(3000, 4))
    for aa in (False, True):
        img = np.full((160, 200, 3), 255, np.uint8)
        rasterkit.draw.lines(img, segments, color=(10, 20, 200), aa=aa)
        yield f"lines/aa={aa}", img
    pts = [rasterkit.draw.line(0, 0, int(x), int(y), method=m)
           for m in ("bresenham", "dda", "naive") for x, y in rng.integers(-40, 40, size=(20, 2))]
    yield "line/methods", np.concatenate(pts)
    tris = [rasterkit.draw.triangle(*v) for v in rng.uniform(-5, 30, size=(40, 6))]
    yield "triangle/pixels", np.concatenate(tris)


def cases():
    """(name, thunk) pairs; each thunk renders and returns a hex digest."""
    scene_mesh = shapes.torus()
    yield from _renders(shapes.demo(), "demo", (320, 240))
    yield from _renders(shapes.icosphere(3), "icosphere", (257, 191), cameras=("persp", "iso"))
    yield from _lit_renders(shapes.demo(), "demo", (320, 240))
    scene = rasterkit.Scene(Camera.look_at(eye=(3, 2, 4), target=(0, 0, 0), fov_y=40, width=300, height=200))
    scene.add(shapes.cube(), transform.translate(-1, 0, 0), color="red")
    scene.add(scene_mesh, transform.rotate_x(0.5))
    # a near plane through the geometry: cut faces and fans
    close = Camera.look_at(eye=(0.3, 0.2, 1.1), target=(0, 0, 0), fov_y=70, width=320, height=240, near=0.5)
    for mode in ("wire", "hidden", "solid", "solid+wire"):
        yield f"scene/{mode}", lambda m=mode: _color(rasterkit.render(scene, mode=m))
        yield f"near-cut/{mode}", lambda m=mode: _color(rasterkit.render(scene_mesh, close, mode=m))
    for name, value in _lines():
        yield name, lambda v=value: _digest(v)
    for model in REAL_MODELS:
        if (MODELS / model).is_file():
            mesh = rasterkit.load_obj(MODELS / model)
            yield from _renders(mesh, model, (640, 360), cameras=("persp", "iso"))
            yield f"{model}/1080p-solid", lambda m=mesh: _color(
                rasterkit.render(m, _frame(m, 1920, 1080), mode="solid"))
            if model == "stanford-bunny.obj":
                yield from _lit_renders(mesh, model, (640, 360))
    if (MODELS / TEXTURED).is_file():
        yield from _textured_renders(rasterkit.load(MODELS / TEXTURED), TEXTURED, (480, 360))


def digests(threads=(1, 2)) -> dict:
    out = {}
    for n in threads:
        rasterkit.set_threads(n)
        for name, thunk in cases():
            out[f"{name}@{n}"] = thunk()
    rasterkit.set_threads(None)
    return out


if __name__ == "__main__":
    json.dump(digests(), sys.stdout, indent=1, sort_keys=True)
    print()
