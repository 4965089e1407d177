"""Ambient occlusion (render(..., ao=True)) against its ray-traced definition (hemisphere rays
from each pixel's surface point, tests/support/reference_ao.py), against identities (an open
plane is unoccluded, the colour is multiplied in linear light), and the frame's other promises
(the same at any thread count, nothing changed without ``ao``)."""

from __future__ import annotations

import numpy as np
import pytest

import rasterkit as rk
from rasterkit.raster.ao import camera_geometry, default_radius, directions
from rasterkit.raster.plan import plan_frame
from support.paths import MODELS
from support.reference_ao import ray_traced_ao
from support.reference_lighting import linear_to_srgb255, srgb_to_linear

SIZE = (512, 384)


def framed(mesh, kind="perspective", size=SIZE):
    centre, radius = mesh.bounding_sphere()
    camera = rk.Camera.frame(centre, radius, width=size[0], height=size[1])
    if kind == "orthographic":
        camera = rk.Camera.orthographic(camera.eye, camera.target, camera.up, width=size[0], height=size[1],
                                        view_height=2.4 * radius, near=0.1 * radius, far=20 * radius)
    return camera


def agreement(mesh, camera, pixels=2000, rays=128, **options):
    """Pearson's r between the render's ``ao`` map and the ray-traced one (``pixels`` pixels of
    the model and its ground)."""
    fb = rk.render(mesh, camera, "solid", ao=True, ground="white", ids=True, **options)
    plan = plan_frame(mesh, camera, rk.RenderOptions(mode="solid", ground="white", ao=True, **options))
    ids = np.where(fb.ids >= 0, fb.ids + fb.object_first[np.maximum(fb.object_ids, 0)], -1)
    reference = ray_traced_ao(plan.mesh, camera, ids, plan.ao_radius, rays=rays, pixels=pixels)
    both = ~np.isnan(reference)
    assert not np.isnan(fb.ao[both]).any()
    return np.corrcoef(reference[both], fb.ao[both])[0, 1]


def test_the_demo_models_occlusion_correlates_with_ray_tracing():
    assert agreement(rk.shapes.demo(), framed(rk.shapes.demo())) >= 0.9


def test_a_parallel_cameras_occlusion_correlates_with_ray_tracing():
    mesh = rk.shapes.demo()
    assert agreement(mesh, framed(mesh, "orthographic")) >= 0.9


@pytest.mark.parametrize("name", ["spot.obj", "suzanne.obj", "teapot.obj"])
def test_public_models_occlusion_correlates_with_ray_tracing(name):
    path = MODELS / name
    if not path.exists():
        pytest.skip(f"{path} is not here (the shared models folder is not part of a clone)")
    mesh = rk.load(path)
    assert agreement(mesh, framed(mesh)) >= 0.8


def test_the_surface_point_of_each_pixel_is_that_of_the_cameras_ray():
    for camera in (framed(rk.shapes.demo()), framed(rk.shapes.demo(), "orthographic"),
                   rk.Camera.from_opencv(np.array([[300.0, 0, 150], [0, 280, 90], [0, 0, 1]]), np.eye(3),
                                         np.array([0.1, -0.2, 4.0]), 320, 200)):
        rays, matrix, axis = camera_geometry(camera)
        rng = np.random.default_rng(1)
        x, y = rng.uniform(0, camera.width, 20), rng.uniform(0, camera.height, 20)
        d = rng.uniform(camera.near * 2, camera.far / 2, 20)
        points = rays[0] + x[:, None] * rays[1] + y[:, None] * rays[2] + d[:, None] * (
            rays[3] + x[:, None] * rays[4] + y[:, None] * rays[5])
        origin, direction = camera.ray(x, y)
        along = ((points - origin) * direction).sum(axis=1)
        assert np.allclose(origin + along[:, None] * direction, points, rtol=0, atol=1e-9 * camera.far)
        right, up, backward = camera.basis()
        eye_depth = -((points - np.asarray(camera.eye)) @ np.asarray(backward))
        assert np.allclose(points @ axis[:3] + axis[3], eye_depth, rtol=1e-9, atol=1e-9 * camera.far)
        assert np.allclose(eye_depth, d, rtol=1e-9)
        h = np.c_[points, np.ones(20)] @ matrix.T
        assert np.allclose(h[:, 0] / h[:, 3], x) and np.allclose(h[:, 1] / h[:, 3], y)


def test_an_open_plane_is_not_occluded():
    plane = rk.Mesh([[-1, 0, -1], [1, 0, -1], [1, 0, 1], [-1, 0, 1]], [[0, 2, 1], [0, 3, 2]])
    for eye in ((0, 2, 2), (0.3, 0.4, 3), (0, 3, 0.01)):
        fb = rk.render(plane, rk.Camera.look_at(eye, (0, 0, 0), width=200, height=150), "solid", ao=True,
                       ao_radius=0.3, cull="none")
        drawn = ~np.isnan(fb.ao)
        # (a pixel's normal comes from its neighbours: those of the outline have some missing)
        inside = drawn.copy()
        inside[1:-1, 1:-1] &= drawn[:-2, 1:-1] & drawn[2:, 1:-1] & drawn[1:-1, :-2] & drawn[1:-1, 2:]
        assert inside.sum() > 1000
        assert fb.ao[inside].min() == 1.0


def test_a_floor_is_occluded_by_a_wall_as_the_formula_says():
    # a floor (y = 0) meeting a wall along x = 0 (facing +x), both larger than the radius:
    # of cosine-weighted rays (uniform over the unit disk below the hemisphere) from a floor
    # point at distance x from the wall, those with a component towards it of more than
    # c = x / R reach it within R: a segment of the disk, (acos c - c sqrt(1 - c^2)) / pi
    floor = [[0, 0, -3], [4, 0, -3], [4, 0, 3], [0, 0, 3]]
    wall = [[0, 0, -3], [0, 0, 3], [0, 3, 3], [0, 3, -3]]
    mesh = rk.Mesh(floor + wall, [[0, 2, 1], [0, 3, 2], [4, 6, 5], [4, 7, 6]])
    camera = rk.Camera.look_at((3, 2.5, 0.5), (0.8, 0, 0), width=320, height=240)
    radius = 0.5
    fb = rk.render(mesh, camera, "solid", ao=True, ao_radius=radius, ids=True, cull="none", ao_samples=32)
    plain = rk.render(mesh, camera, "solid", ids=True, cull="none")
    origin, direction = camera.ray(*np.meshgrid(np.arange(320) + 0.5, np.arange(240) + 0.5))
    x = origin[..., 0] - origin[..., 1] / direction[..., 1] * direction[..., 0]  # the floor point's x
    c = np.clip(x / radius, 0.0, 1.0)
    expected = 1.0 - (np.arccos(c) - c * np.sqrt(1.0 - c * c)) / np.pi
    on_floor = (fb.ids >= 0) & (fb.ids <= 1) & (x > 0.01)
    for low, high in ((0.01, 0.1), (0.1, 0.2), (0.2, 0.3), (0.3, 0.4), (0.4, 0.5)):
        band = on_floor & (x >= low) & (x < high)
        assert band.sum() > 50
        assert abs(fb.ao[band].mean() - expected[band].mean()) < 0.08, (low, fb.ao[band].mean(), expected[band].mean())
    far = on_floor & (x > 0.7) & (x < 2.0)
    assert far.sum() > 1000 and fb.ao[far].min() == 1.0
    assert (fb.color[far] == plain.color[far]).all()


def test_the_colour_is_multiplied_in_linear_light():
    mesh = rk.shapes.demo()
    camera = framed(mesh, size=(320, 240))
    plain = rk.render(mesh, camera, "solid", ground="white")
    fb = rk.render(mesh, camera, "solid", ground="white", ao=True)
    drawn = ~np.isnan(fb.ao)
    assert (fb.ao[drawn] < 0.9).sum() > 100
    expected = linear_to_srgb255(srgb_to_linear(plain.color[drawn] / 255.0) * fb.ao[drawn][:, None])
    assert np.abs(fb.color[drawn].astype(float) - expected).max() <= 1.0
    assert (fb.color[~drawn] == plain.color[~drawn]).all()


def test_the_same_at_any_thread_count_and_with_samples():
    mesh = rk.shapes.demo()
    camera = framed(mesh, size=(400, 300))
    try:
        rk.set_threads(1)
        one = rk.render(mesh, camera, "solid", ao=True, ground="white")
        rk.set_threads(2)
        two = rk.render(mesh, camera, "solid", ao=True, ground="white")
    finally:
        rk.set_threads(None)
    assert (one.color == two.color).all()
    np.testing.assert_array_equal(one.ao, two.ao)
    many = rk.render(mesh, camera, "solid", ao=True, ground="white", samples=4)
    # several samples: the AO of the centre sample's depth, on the averaged colour
    np.testing.assert_array_equal(many.ao, one.ao)


def test_the_map_is_made_when_first_read_from_the_depths_the_render_left():
    mesh = rk.shapes.demo()
    camera = framed(mesh, size=(200, 150))
    fb = rk.render(mesh, camera, "solid", ao=True)
    other = rk.render(mesh, camera, "solid", ao=True, camera_depth=True)
    first = fb.ao
    assert fb.ao is first  # made once
    np.testing.assert_array_equal(first, other.ao)
    # NaN exactly where the metric depth says nothing was drawn
    assert (np.isnan(first) == (other.camera_depth() <= 0)).all()
    fb.ao = None
    assert fb.ao is None
    again = rk.render(mesh, camera, "solid", ao=True)
    again.clear()  # a cleared framebuffer shows no AO
    assert again.ao is None


def test_without_ao_nothing_changes_and_wireframes_have_none():
    mesh = rk.shapes.demo()
    camera = framed(mesh, size=(200, 150))
    assert rk.render(mesh, camera, "solid").ao is None
    wire = rk.render(mesh, camera, "wire", ao=True)
    assert wire.ao is None
    assert (wire.color == rk.render(mesh, camera, "wire").color).all()


def test_the_default_radius_is_a_tenth_of_the_models_diagonal_and_directions_are_cosine_weighted():
    vertices = np.array([[0.0, 0, 0], [3, 4, 0], [np.nan, 0, 0]])
    assert default_radius(vertices) == pytest.approx(0.5)
    d = directions(4096)
    assert np.allclose(np.linalg.norm(d, axis=1), 1)
    # cosine-weighted: E[cos] = 2/3, E[cos^2] = 1/2; the mean direction along the normal
    assert d[:, 2].mean() == pytest.approx(2 / 3, abs=1e-3)
    assert (d[:, 2] ** 2).mean() == pytest.approx(0.5, abs=1e-3)
    assert np.abs(d[:, :2].mean(axis=0)).max() < 1e-3


@pytest.mark.parametrize("field, value, error", [
    ("ao", 1, TypeError), ("ao_radius", 0.0, ValueError), ("ao_radius", float("inf"), ValueError),
    ("ao_samples", 0, ValueError), ("ao_samples", 257, ValueError), ("ao_samples", 2.5, TypeError)])
def test_bad_ao_options_are_refused(field, value, error):
    with pytest.raises(error, match=field):
        rk.RenderOptions(**{field: value})


def test_a_distorted_camera_resamples_the_ao_map_with_the_frame():
    mesh = rk.shapes.demo()
    ideal = framed(mesh, size=(160, 120))
    K, R, t = ideal.to_opencv()
    camera = rk.Camera.from_opencv(K, R, t, 160, 120, near=ideal.near, far=ideal.far, dist=(-0.2, 0.05, 0, 0, 0))
    fb = rk.render(mesh, camera, "solid", ao=True, ground="white")
    assert fb.ao is not None and fb.ao.shape == (120, 160)
    drawn = np.isfinite(fb.depth)
    assert (np.isnan(fb.ao) == ~drawn).all() and (fb.ao[drawn] < 1).any()


def test_the_grid_is_blurred_and_interpolated_as_defined():
    # the kernels' shortcuts (rows without a blocked ray near, cells without a share above 0)
    # against the plain definitions: the 4x4 average of the shares on the same surface, and
    # the bilinear interpolation among the corners drawn within R / 2 in depth (else the
    # nearest in depth)
    from rasterkit.raster import ao
    from rasterkit.raster.kernels.ao import ao_blur, ao_fill, ao_shade
    from rasterkit.runtime.threads import MAX_THREADS, run_workers

    mesh = rk.shapes.demo()
    camera = framed(mesh, size=(200, 150))
    fb = rk.render(mesh, camera, "solid", ground="white", camera_depth=True)
    metric = fb.camera_depth().astype(np.float32)
    height, width, s, radius = 150, 200, 4, 0.3
    rng = np.random.default_rng(3)
    ys, xs = ao._grid_pixels(height, s), ao._grid_pixels(width, s)
    grid = np.ascontiguousarray(metric[ys[:, None], xs[None, :]])
    raw = np.where(grid > 0, np.where(rng.random(grid.shape) < 0.1, rng.random(grid.shape), 0.0), -1.0).astype(np.float32)
    raw[28:] = np.where(grid[28:] > 0, 0.0, -1.0)  # rows without a blocked ray
    some = (raw > 0).any(axis=1).astype(np.uint8)
    shares = np.empty_like(raw)
    run_workers(ao_blur, grid, raw, some, radius, shares)
    rows, columns = grid.shape
    expected = np.full_like(raw, -1.0)
    for j, i in zip(*np.nonzero(raw >= 0)):
        window = (slice(max(j - 1, 0), j + 3), slice(max(i - 1, 0), i + 3))
        near = (grid[window] > 0) & (np.abs(grid[window] - grid[j, i]) < radius / 2)
        expected[j, i] = raw[window][near].mean()
    np.testing.assert_allclose(shares, expected, atol=1e-6)

    fractions, starts = ao._interpolation(height, width, s)
    color = fb.color.copy()
    out = np.empty((height, width), np.float32)
    view = (fb.depth, float(camera.near), float(camera.far), True)
    marks = np.empty((MAX_THREADS, columns), np.uint8)
    run_workers(ao_fill, view, grid, shares, radius, fractions, starts, marks, out)
    run_workers(ao_shade, view, grid, shares, radius, fractions, starts, marks,
                np.empty((MAX_THREADS, width), np.float32), color, ao._DECODE, ao._ENCODE)
    (low_y, _), (low_x, _) = ao._between(height, s), ao._between(width, s)
    reference = np.full((height, width), np.nan)
    for y, x in zip(*np.nonzero(metric > 0)):
        fy, fx = fractions[y], fractions[height + x]
        corners = [(low_y[y] + a, low_x[x] + b, (fy if a else 1 - fy) * (fx if b else 1 - fx))
                   for a in (0, 1) for b in (0, 1)]
        corners = [(min(j, rows - 1), min(i, columns - 1), w) for j, i, w in corners]
        drawn = [(shares[j, i], abs(grid[j, i] - metric[y, x]), w) for j, i, w in corners if shares[j, i] >= 0]
        near = [(share, w) for share, off, w in drawn if off < radius / 2]
        weight = sum(w for _, w in near)
        reference[y, x] = 1 - (sum(share * w for share, w in near) / weight if weight > 1e-6 else
                               min(drawn, key=lambda t: t[1])[0])
    assert (reference < 1).sum() > 100
    np.testing.assert_allclose(out, reference, atol=1e-5)
    changed = out < 1
    expected_color = linear_to_srgb255(srgb_to_linear(fb.color[changed][:, :3] / 255.0) * out[changed][:, None])
    assert np.abs(color[changed][:, :3].astype(float) - expected_color).max() <= 1.0
    assert (color[~changed] == fb.color[~changed]).all()


def test_ao_at_1080p_correlates_with_ray_tracing():
    mesh = rk.shapes.demo()
    assert agreement(mesh, framed(mesh, size=(1920, 1080))) >= 0.9
