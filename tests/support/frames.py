"""Frames in which every render option is seen: shared by the tests of each path that draws
them (tests/core/test_render_options.py: render() and a distorted camera;
tests/batch/test_batch_options.py and test_batch_dask.py: batches)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from PIL import Image

import rasterkit
from rasterkit import Mesh, RenderOptions, View, shapes
from support.objfiles import write_obj, write_textured_obj

BALL = shapes.icosphere(2)
#: An open bowl: where faces are missing its inside shows, so the culling is seen too.
BOWL = Mesh(BALL.vertices, BALL.faces[BALL.vertices[BALL.faces].mean(axis=1)[:, 1] < 0.55])

#: BOWL with a texture (noise, made here) over spherical texture coordinates.
TEXTURED_BOWL = Mesh(BOWL.vertices, BOWL.faces,
                     uv=np.stack([np.arctan2(BOWL.vertices[:, 1], BOWL.vertices[:, 0]) + np.pi,
                                  np.arccos(np.clip(BOWL.vertices[:, 2], -1, 1))], 1),
                     face_materials=np.zeros(len(BOWL.faces), np.int32), material_names=("noise",),
                     materials=(rasterkit.Material(diffuse=(1, 1, 1), diffuse_map=rasterkit.Texture(
                         np.random.default_rng(3).integers(0, 256, (16, 16, 3), dtype=np.uint8))),))

#: Every field that decides the pixels of a frame, each away from its default: putting back
#: any one default changes the frame of BOWL (tests/core/test_render_options.py).
IMAGE = dict(mode="solid+wire", cull="none", shading="smooth", color="steelblue", line_color="orange",
             background="navy", light=(1.0, 0.3, 0.2), aa=True, edges="feature", crease_angle=10.0,
             samples=4, vignette=0.6)


def model_folder(folder: Path) -> Path:
    """``folder`` with bowl.obj, ball.obj and the textured bowl (textured.obj with its .mtl
    and PNG)."""
    folder.mkdir(parents=True, exist_ok=True)
    for name, mesh in (("bowl", BOWL), ("ball", BALL)):
        write_obj(folder / f"{name}.obj", mesh)
    write_textured_obj(folder / "textured.obj", TEXTURED_BOWL, TEXTURED_BOWL.materials[0].diffuse_map.image)
    return folder


def batch_matches_the_api(folder: Path, out: Path, **engine) -> None:
    """``render_many`` of ``folder`` with every IMAGE field (and ``engine``: jobs, client)
    writes the images that ``render`` draws with the same options and view, bit for bit."""
    view = View(size=(96, 72), azimuth=40.0, elevation=35.0)
    summary = rasterkit.render_many(folder, out, options=RenderOptions(**IMAGE), view=view, **engine)
    assert summary.done == 3 and summary.exit_code == 0
    for name in ("bowl", "ball", "textured"):
        mesh = rasterkit.load_obj(folder / f"{name}.obj")
        expected = rasterkit.render(mesh, view.camera_for(mesh), options=RenderOptions(**IMAGE)).color
        assert np.array_equal(np.asarray(Image.open(out / f"{name}.png")), expected), name
    textured = rasterkit.load_obj(folder / "textured.obj")
    plain = rasterkit.render(textured, view.camera_for(textured), options=RenderOptions(**IMAGE, textures=False))
    assert not np.array_equal(np.asarray(Image.open(out / "textured.png")), plain.color)  # drawn with its texture
