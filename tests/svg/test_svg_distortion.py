"""Vector drawings through a distorted camera (issue 25): the SVG draws the curves the lens
makes of the edges, where cv2.projectPoints puts them (to 1/200 pixel) and where the raster
render draws them; and distortion coefficients too strong to show anything are one error."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest
from PIL import Image

import rasterkit
from rasterkit import Camera, Mesh, render, render_svg, shapes
from rasterkit.svg import svg_drawing
from support.hostile import run_cli
from support.svg_raster import f_score, rasterise, svg_segments

cv2 = pytest.importorskip("cv2")

K = np.array([[610.0, 0, 331.0], [0, 600.0, 236.0], [0, 0, 1]])
RVEC, TVEC = np.array([0.25, -0.3, 0.05]), np.array([0.02, -0.01, 0.75])

DISTORTIONS = [
    (-0.28, 0.09, 0.0012, -0.0008, -0.01),  # barrel
    (0.12, -0.03, -0.001, 0.002),  # pincushion
    (0.3, 0.05, 0.001, 0.0, 0.01, 0.2, 0.02, 0.005),  # the rational model
]


def _camera(dist, width=640, height=480):
    return Camera.from_opencv(K, cv2.Rodrigues(RVEC)[0], TVEC, width, height, dist=dist)


def _plane(n=6, half=0.5):
    """An n x n grid of quads in the plane z = 0, ``half`` wide each way: lines across the
    whole image, some leaving it."""
    grid = shapes.grid(n, n, 2 * half)
    return Mesh(grid.vertices[:, [0, 2, 1]], grid.faces, edges=grid.edges)


def _expected(mesh, dist, width, height, samples=600):
    """cv2's projections (raster: + 0.5) of points along every edge, (E, samples, 2)."""
    t = np.linspace(0.0, 1.0, samples)[None, :, None]
    a, b = mesh.vertices[mesh.edges[:, 0]], mesh.vertices[mesh.edges[:, 1]]
    points = (a[:, None] + t * (b - a)[:, None]).reshape(-1, 3)
    uv = cv2.projectPoints(points, RVEC, TVEC, K, np.array(dist))[0].reshape(len(a), samples, 2) + 0.5
    return uv


def _distance_to_segments(points, segments, chunk=400):
    """Distance (N,) of each point to the nearest of the segments (S, 4)."""
    a, d = segments[:, :2], segments[:, 2:] - segments[:, :2]
    dd = np.maximum((d * d).sum(axis=1), 1e-300)
    out = np.empty(len(points))
    for k in range(0, len(points), chunk):
        p = points[k:k + chunk, None, :]
        s = np.clip(((p - a) * d).sum(axis=2) / dd, 0.0, 1.0)
        out[k:k + chunk] = np.sqrt((((a + s[..., None] * d) - p) ** 2).sum(axis=2)).min(axis=1)
    return out


@pytest.mark.parametrize("dist", DISTORTIONS)
def test_distorted_svg_lines_lie_where_opencv_projects_the_edges(dist):
    mesh = _plane()
    camera = _camera(dist)
    curves = _expected(mesh, dist, 640, 480)
    expected_segments = np.concatenate([np.c_[c[:-1], c[1:]] for c in curves])
    inside = np.all((curves > 0.01) & (curves < [640 - 0.01, 480 - 0.01]), axis=2)
    drawing = svg_drawing(mesh, camera, mode="wire")
    lines = drawing.lines
    drawn_segments = np.concatenate([np.c_[lines.points[s:e - 1], lines.points[s + 1:e]]
                                     for s, e in zip(lines.offsets[:-1], lines.offsets[1:])])
    # every point of every edge inside the image is on the drawing, to 1/200 pixel ...
    assert _distance_to_segments(curves[inside], drawn_segments).max() < 0.005
    # ... and every point of the drawing is on an edge's curve (and inside the image)
    assert _distance_to_segments(lines.points, expected_segments).max() < 0.005
    assert np.all((lines.points >= 0) & (lines.points <= [640, 480]))
    # the SVG text: the same, rounded to 1/100 pixel
    text_segments = svg_segments(drawing.text)
    assert _distance_to_segments(text_segments[:, :2], expected_segments).max() < 0.012
    # the undistorted drawing is far from there (what the SVG was before)
    plain = svg_drawing(mesh, _camera(None), mode="wire").lines.points
    assert _distance_to_segments(plain, expected_segments).max() > 5


@pytest.mark.parametrize("dist", DISTORTIONS)
@pytest.mark.parametrize("mode", ["wire", "hidden"])
def test_distorted_svg_agrees_with_the_distorted_png(dist, mode):
    mesh = shapes.torus(major=0.2, minor=0.07, rings=24, sides=12)
    camera = _camera(dist)
    png = (render(mesh, camera, mode).color != 255).any(axis=2)
    drawn = rasterise(svg_segments(render_svg(mesh, camera, mode=mode)), 640, 480)
    undistorted = rasterise(svg_segments(render_svg(mesh, _camera(None), mode=mode)), 640, 480)
    assert f_score(drawn, png) >= 0.99
    assert f_score(undistorted, png) < 0.97


def test_beyond_the_fold_the_svg_draws_nothing_as_the_png():
    camera = Camera.from_opencv(K, np.eye(3), [0, 0, 2.0], 640, 480, dist=(-0.6, 0.0, 0, 0))
    plane = _plane(n=40, half=3.0)
    shown = render(plane, camera, mode="solid", cull="none", ids=True).ids >= 0
    assert shown[240, 320] and not shown[0, 0]
    drawing = svg_drawing(plane, camera, mode="wire")
    points = drawing.lines.points
    assert len(points) > 100
    # each point of the drawing within a pixel of a pixel the raster image shows
    i = np.clip(np.floor(points[:, 0]).astype(int), 0, 639)
    j = np.clip(np.floor(points[:, 1]).astype(int), 0, 479)
    near_shown = shown | np.pad(shown, 1)[2:, 1:-1] | np.pad(shown, 1)[:-2, 1:-1] | \
        np.pad(shown, 1)[1:-1, 2:] | np.pad(shown, 1)[1:-1, :-2]
    assert near_shown[j, i].all()
    png = (render(plane, camera, "wire").color != 255).any(axis=2)
    assert f_score(rasterise(svg_segments(drawing.text), 640, 480), png) >= 0.98


def test_the_command_line_draws_the_distorted_svg(tmp_path):
    camera = tmp_path / "cam.json"
    camera.write_text(json.dumps(dict(K=[[300.0, 0, 160.0], [0, 300.0, 120.0], [0, 0, 1]],
                                      R=[[1, 0, 0], [0, -1, 0], [0, 0, -1]], t=[0, 0, 3.0],
                                      width=320, height=240, dist=[-0.5, 0.2, 0, 0, 0])))
    common = ["--demo", "--camera-opencv", camera, "--mode", "wire"]
    assert run_cli("render", *common, "-o", tmp_path / "x.svg", timeout=300).code == 0
    assert run_cli("render", *common, "-o", tmp_path / "x.png", timeout=300).code == 0
    png = (np.asarray(Image.open(tmp_path / "x.png").convert("RGB")) != 255).any(axis=2)
    drawn = rasterise(svg_segments((tmp_path / "x.svg").read_text()), 320, 240)
    assert f_score(drawn, png) >= 0.98


@pytest.mark.parametrize("dist", [(1e300, 0, 0, 0), (-1e300, 0, 0, 0), (0, 0, 0, 0, 1e300), (-1e5, 0, 0, 0)])
def test_a_distortion_that_shows_nothing_is_one_error_without_warnings(dist):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match=r"^dist \(.*\) is too strong: the distortion model folds"):
            Camera.from_opencv([[500, 0, 100], [0, 500, 75], [0, 0, 1]], np.diag([1, -1, -1.0]), [0, 0, 5],
                               640, 480, dist=dist)


def test_a_fold_inside_the_image_renders_without_warnings():
    """Pixels beyond the fold whose ideal point Newton's method cannot find (NaN) stay empty,
    without a warning about casting NaN (which came once per array it was cast into)."""
    small_k = [[610.0, 0, 32.0], [0, 600.0, 24.0], [0, 0, 1]]  # the fold 3.5 pixels from the centre
    camera = Camera.from_opencv(small_k, np.eye(3), [0, 0, 2.0], 64, 48, dist=(-1e4, 0.0, 0, 0))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fb = rasterkit.render(_plane(n=4, half=3.0), camera, mode="solid", cull="none", ids=True)
        render_svg(_plane(n=4, half=3.0), camera, mode="wire")
    assert fb.ids[24, 32] >= 0 and fb.ids[0, 0] == -1
