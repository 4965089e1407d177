"""Multi-sample renders and the thin-lens camera: sample patterns, the circle of confusion
against the thin-lens formula, cos⁴ vignetting against the camera's rays, determinism, and
the buffers and checks of the new parameters (coverage against exact areas:
tests/raster/test_coverage.py)."""

import dataclasses
import math

import numpy as np
import pytest
from PIL import Image

import rasterkit
from rasterkit import Camera, shapes
from rasterkit.runtime.notice import MESSAGE
from rasterkit.cli import main
from rasterkit.raster.samples import MAX_SAMPLES, concentric_disc, lens_points, pixel_offsets, square


def _quad(cx, cy, half, z):
    """A square in the plane z = const, facing +z (counter-clockwise seen from +z)."""
    v = np.array([(cx - half, cy - half, z), (cx + half, cy - half, z),
                  (cx + half, cy + half, z), (cx - half, cy + half, z)], np.float64)
    return v, np.array([(0, 1, 2), (0, 2, 3)], np.int64)


# --- the patterns --------------------------------------------------------------------------


@pytest.mark.parametrize("n", [2, 4, 7, 12, 16, 64, 256])
def test_square_patterns_are_stratified_in_2d_and_in_each_axis(n):
    p = square(n)
    assert p.shape == (n, 2) and np.all((p >= 0) & (p < 1))
    for axis in (0, 1):  # one point in every 1/n strip of each axis (n-rooks)
        assert sorted(np.floor(p[:, axis] * n).astype(int)) == list(range(n))
    m = max(d for d in range(1, math.isqrt(n) + 1) if n % d == 0)
    cells = {(int(x * m), int(y * (n // m))) for x, y in p}
    assert len(cells) == n  # one point in every cell of the m x n/m grid


def test_patterns_are_fixed():
    assert np.array_equal(square(16), square(16))
    from rasterkit.raster import samples

    before = np.array(samples.square(16)), [np.array(pixel_offsets(n)) for n in (4, 16, 48)]
    samples._square.cache_clear()
    samples._offsets.cache_clear()
    assert np.array_equal(samples.square(16), before[0])
    assert all(np.array_equal(pixel_offsets(n), b) for n, b in zip((4, 16, 48), before[1]))
    assert np.array_equal(pixel_offsets(1), [[0.0, 0.0]]) and np.array_equal(lens_points(1), [[0.0, 0.0]])


def test_lens_points_cover_the_disc_uniformly():
    points = lens_points(256)
    r = np.hypot(points[:, 0], points[:, 1])
    assert np.all(r <= 1.0 + 1e-12)
    # uniform on the unit disc: a quarter of the points within radius 1/2, E[x²] = E[y²] = 1/4
    assert abs(np.mean(r < 0.5) - 0.25) < 0.03
    assert np.allclose(np.mean(points**2, axis=0), 0.25, atol=0.01)
    assert np.allclose(points.mean(axis=0), 0.0, atol=0.01)
    # the concentric map sends the square's boundary to the circle, its centre to the centre
    edge = concentric_disc(np.array([[1.0, 0.5], [0.5, 1.0], [0.0, 0.0], [0.5, 0.5]]))
    assert np.allclose(edge, [[1, 0], [0, 1], [-math.sqrt(0.5), -math.sqrt(0.5)], [0, 0]])


# --- the thin lens -------------------------------------------------------------------------


def _spread(image):
    """Variance of the intensity about its centroid, the mean of x and y (pixels²)."""
    i = image.astype(np.float64)
    h, w = i.shape
    y, x = np.mgrid[0:h, 0:w] + 0.5
    total = i.sum()
    mx, my = (i * x).sum() / total, (i * y).sum() / total
    return 0.5 * ((i * (x - mx) ** 2).sum() + (i * (y - my) ** 2).sum()) / total


@pytest.mark.parametrize("d", [3.0, 5.0, 10.0])
def test_blur_diameter_follows_the_thin_lens_formula(d):
    size, fov, focus, aperture = 128, 40.0, 5.0, 1.0
    f_px = (size / 2) / math.tan(math.radians(fov / 2))
    side_px = 6.0
    half = side_px / 2 * d / f_px
    camera = Camera.look_at((0, 0, 0), (0, 0, -focus), fov_y=fov, width=size, height=size,
                            near=0.5, far=50.0, aperture=aperture)
    fb = rasterkit.render(_quad(0.0, 0.0, half, -d), camera, "solid", cull="none", color="white",
                          background="black", samples=256)
    # a uniform disc of diameter b has variance b²/16 per axis; the square adds s²/12 and
    # the averaging over the pixel square 1/12
    s = np.ptp(camera.project(_quad(0.0, 0.0, half, -d)[0])[:, 0])
    measured = 4.0 * math.sqrt(max(_spread(fb.color[..., 0]) - s * s / 12 - 1 / 12, 0.0))
    expected = aperture * abs(d - focus) / d * f_px / focus
    if d == focus:
        assert measured <= 1.0
        pinhole = rasterkit.render(_quad(0.0, 0.0, half, -d), dataclasses.replace(camera, aperture=0.0),
                                   "solid", cull="none", color="white", background="black", samples=256)
        assert np.max(np.abs(fb.color.astype(int) - pinhole.color)) <= 8
    else:
        assert expected > 15
        assert abs(measured - expected) <= 0.1 * expected


def test_focus_distance_overrides_the_target_distance():
    camera = Camera.look_at((0, 0, 0), (0, 0, -5), fov_y=40, width=64, height=64, aperture=1.0,
                            focus_distance=3.0)
    assert camera.focus_distance == 3.0
    sharp = rasterkit.render(_quad(0, 0, 0.1, -3.0), camera, "solid", cull="none", color="white",
                             background="black", samples=64)
    blurred = rasterkit.render(_quad(0, 0, 0.1 * 5 / 3, -5.0), camera, "solid", cull="none",
                               color="white", background="black", samples=64)
    assert _spread(sharp.color[..., 0]) * 4 < _spread(blurred.color[..., 0])


# --- vignetting ----------------------------------------------------------------------------


@pytest.mark.parametrize("strength, shift", [(1.0, (0.0, 0.0)), (0.5, (0.0, 0.0)), (1.0, (0.4, -0.3))])
def test_vignetting_is_cos4_of_the_ray_angle(strength, shift):
    width, height = 160, 120
    camera = Camera.look_at((0, 0, 0), (0, 0, -5), fov_y=70, width=width, height=height, shift=shift,
                            far=50.0)
    wall = _quad(0.0, 0.0, 40.0, -5.0)
    plain = rasterkit.render(wall, camera, "solid", color="white", background="white")
    assert np.all(plain.color == 255)
    fb = rasterkit.render(wall, camera, "solid", color="white", background="white", vignette=strength)
    x, y = np.meshgrid(np.arange(width) + 0.5, np.arange(height) + 0.5)
    _, direction = camera.ray(x, y)
    axis = np.subtract(camera.target, camera.eye) / 5.0
    cos = direction @ axis
    expected = 255 * (1 - strength * (1 - cos**4))
    assert np.max(np.abs(fb.color[..., 0] - expected)) <= 0.02 * 255
    assert expected.min() < 0.8 * 255  # the falloff is there to be seen


# --- determinism, buffers, the single-sample path ------------------------------------------


def test_one_and_two_threads_and_two_runs_give_identical_images():
    mesh = shapes.demo()
    center, radius = mesh.bounding_sphere()
    camera = Camera.frame(center, radius, width=96, height=72, aperture=0.3 * radius)
    images = []
    for threads in (1, 2, 1):
        rasterkit.set_threads(threads)
        try:
            images.append(rasterkit.render(mesh, camera, "solid+wire", samples=6, vignette=0.3).color)
        finally:
            rasterkit.set_threads(None)
    assert np.array_equal(images[0], images[1]) and np.array_equal(images[0], images[2])


@pytest.mark.parametrize("mode", ["solid", "hidden", "solid+wire", "wire"])
def test_depth_and_ids_are_those_of_the_centre_sample(mode):
    mesh = shapes.demo()
    center, radius = mesh.bounding_sphere()
    camera = Camera.frame(center, radius, width=64, height=48, aperture=0.2 * radius)
    one = rasterkit.render(mesh, camera, mode, ids=True)
    many = rasterkit.render(mesh, camera, mode, ids=True, samples=4)
    lazy = rasterkit.render(mesh, camera, mode, samples=4)
    assert np.array_equal(many.ids, one.ids)
    assert np.array_equal(many.depth, one.depth) and np.array_equal(lazy.depth, one.depth)
    assert not np.array_equal(many.color, one.color)


def test_one_sample_is_the_pinhole_image_whatever_the_aperture():
    mesh = shapes.demo()
    center, radius = mesh.bounding_sphere()
    pinhole = Camera.frame(center, radius, width=64, height=48)
    lens = dataclasses.replace(pinhole, aperture=radius, focus_distance=radius)
    assert np.array_equal(rasterkit.render(mesh, lens, "solid").color,
                          rasterkit.render(mesh, pinhole, "solid").color)


def test_lens_fields_are_kept_by_with_size_presets_and_frame():
    cam = Camera.look_at((0, 0, 5), (0, 0, 0), aperture=0.5, focus_distance=4.0)
    assert (cam.with_size(32, 24).aperture, cam.with_size(32, 24).focus_distance) == (0.5, 4.0)
    framed = Camera.frame((0, 0, 0), 1.0, aperture=0.2)
    assert framed.aperture == 0.2 and framed.focus_distance is None
    preset = Camera.preset("2-point", (0, 0, 0), 1.0, aperture=0.1, focus_distance=2.0)
    assert (preset.aperture, preset.focus_distance) == (0.1, 2.0)


@pytest.mark.parametrize("kwargs, error", [
    (dict(samples=0), ValueError), (dict(samples=MAX_SAMPLES + 1), ValueError),
    (dict(samples=2.0), TypeError), (dict(samples=True), TypeError), (dict(samples="4"), TypeError),
    (dict(vignette=-0.1), ValueError), (dict(vignette=1.5), ValueError),
    (dict(vignette=float("nan")), ValueError), (dict(vignette="x"), TypeError),
])
def test_bad_samples_and_vignette_are_one_line_errors(kwargs, error):
    camera = Camera.frame((0, 0, 0), 1.0, width=16, height=12)
    with pytest.raises(error) as info:
        rasterkit.render(shapes.cube(), camera, "solid", **kwargs)
    assert "\n" not in str(info.value)


def test_bad_lens_values_are_refused():
    with pytest.raises(ValueError, match="aperture"):
        Camera.look_at((0, 0, 5), (0, 0, 0), aperture=-1.0)
    with pytest.raises(ValueError, match="focus_distance"):
        Camera.look_at((0, 0, 5), (0, 0, 0), focus_distance=0.0)
    with pytest.raises(TypeError):
        Camera.look_at((0, 0, 5), (0, 0, 0), aperture="wide")
    with pytest.raises(ValueError, match="parallel camera has no lens"):
        Camera.frame((0, 0, 0), 1.0, projection="parallel", aperture=0.5)
    with pytest.raises(ValueError, match="parallel camera has no lens"):
        Camera.preset("isometric", (0, 0, 0), 1.0, aperture=0.5)


# --- the command line ----------------------------------------------------------------------


def _run(argv, capsys):
    code = main([str(a) for a in argv])
    return code, capsys.readouterr().err.replace(MESSAGE + "\n", "")


def test_cli_lens_and_samples_match_the_api(tmp_path, capsys):
    out = tmp_path / "dof.png"
    code, err = _run(["render", "--demo", "-o", out, "--size", "64x48", "--mode", "solid", "--samples", "4",
                      "--aperture", "0.3", "--focus", "auto", "--vignette", "0.5"], capsys)
    assert code == 0, err
    mesh = shapes.demo()
    center, radius = mesh.bounding_sphere()
    camera = Camera.preset("perspective", center, radius, width=64, height=48, aperture=0.3)
    expected = rasterkit.render(mesh, camera, "solid", samples=4, vignette=0.5).color
    with Image.open(out) as im:
        assert np.array_equal(np.asarray(im), expected)


@pytest.mark.parametrize("extra", [["--samples", "0"], ["--samples", "300"], ["--focus", "-1"],
                                   ["--focus", "near"], ["--vignette", "2"], ["--aperture", "-1"],
                                   ["--aperture", "0.5", "--projection", "isometric"]])
def test_cli_bad_lens_options_are_one_line_errors(extra, tmp_path, capsys):
    out = tmp_path / "x.png"
    code, err = _run(["render", "--demo", "-o", out, "--size", "32x24", *extra], capsys)
    assert code == 2
    assert err.startswith("rasterkit: error:") and err.count("\n") == 1
    assert not out.exists()


def test_the_average_of_the_sums_rounds_like_integer_division():
    from rasterkit.runtime.threads import run_workers
    from rasterkit.raster.kernels.accumulate import add_sample, average_samples

    for n in (2, 3, 4, 7, 16, 100, 255, 256):
        total = np.arange(255 * n + 1, dtype=np.uint16)
        out = np.empty(total.shape, np.uint8)
        run_workers(average_samples, total, out, 1.0 / n, (n // 2 + 0.5) / n)
        assert np.array_equal(out, (total.astype(np.int64) + n // 2) // n)
    total = np.empty(5, np.uint16)
    run_workers(add_sample, total, np.array([0, 1, 2, 254, 255], np.uint8), True)
    run_workers(add_sample, total, np.array([255, 255, 3, 254, 255], np.uint8), False)
    assert total.tolist() == [255, 256, 5, 508, 510]
