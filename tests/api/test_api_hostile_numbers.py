"""Numbers at the ends of float64 give one clear line, never a RuntimeWarning or an array in
a message (issue 14, item 8).

Every case runs with warnings turned into errors: a RuntimeWarning printed on the way (as
NumPy prints it, lines before the error) fails the test.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import rasterkit
from rasterkit import Camera, Mesh, Scene, shapes, transform

BIG = 1.7e308  # within float64, its square and any sum of two of them are not


@pytest.fixture(autouse=True)
def warnings_are_errors():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        yield


def _one_line(error) -> str:
    message = str(error.value)
    assert "\n" not in message and "array(" not in message and "[" not in message, message
    return message


def test_a_model_whose_extent_overflows_float64_says_so():
    mesh = Mesh([[BIG, 0, 0], [-BIG, BIG, 0], [0, 0, BIG]], [[0, 1, 2]])
    with pytest.raises(ValueError) as error:
        mesh.bounding_sphere()
    assert _one_line(error).startswith("the model's extent overflows float64")


def test_a_model_near_the_top_of_float64_frames_or_says_why_not():
    mesh = Mesh([[1e308, 0, 0], [-1e308, 1e308, 0], [0, 0, 1e308]], [[0, 1, 2]])
    centre, radius = mesh.bounding_sphere()  # the squares overflow; the radius does not
    assert np.isclose(radius, np.linalg.norm(mesh.vertices[0] / 1e300 - centre / 1e300) * 1e300)
    with pytest.raises(ValueError) as error:
        Camera.frame(centre, radius)
    assert _one_line(error).startswith("a sphere of radius 1.22474e+308 is too large to frame")
    with pytest.raises(ValueError) as error:
        Camera.preset("perspective", centre, radius)
    assert "too large to frame" in _one_line(error)


def test_all_nan_vertices_are_reported_as_such_not_as_coinciding():
    for value in (np.nan, np.inf, -np.inf):
        mesh = Mesh(np.full((3, 3), value), [[0, 1, 2]])
        with pytest.raises(ValueError) as error:
            mesh.bounding_sphere()
        assert _one_line(error) == "all 3 vertices are NaN or infinite: the model has no extent"
    assert Mesh(np.zeros((0, 3)), np.zeros((0, 3), int)).bounding_sphere()[1] == 0.0  # no vertices: no extent
    centre, radius = Mesh([[np.nan, 0, 0], [1, 2, 3], [1, 2, 3]], [[0, 1, 2]]).bounding_sphere()
    assert radius == 0.0 and centre.tolist() == [1, 2, 3]  # one point: coinciding indeed


def test_a_tiny_model_frames_and_renders_like_a_scaled_up_one():
    small = Mesh(shapes.cube().vertices * 1e-300, shapes.cube().faces, edges=shapes.cube().edges)
    centre, radius = small.bounding_sphere()  # the squares underflow; the radius does not
    assert np.isclose(radius, np.sqrt(3) / 2 * 1e-300, rtol=1e-12)
    image = rasterkit.render(small, Camera.frame(centre, radius, width=48, height=32), mode="wire").color
    reference = rasterkit.render(shapes.cube(), Camera.frame(*shapes.cube().bounding_sphere(), width=48, height=32),
                                 mode="wire").color
    assert (image != reference).any(axis=2).mean() < 0.02  # the same picture, to a few rounded pixels


@pytest.mark.parametrize("distance, message", [
    (1e-300, None),  # beside a target at the origin a distance of 1e-300 is a position like any
    (1e300, None),
])
def test_preset_distances_far_from_one_work_where_float64_can_hold_them(distance, message):
    camera = Camera.preset("perspective", (0, 0, 0), 1.0, distance=distance)
    assert np.isclose(np.linalg.norm(np.asarray(camera.eye) / distance), 1.0)
    assert np.all(np.isfinite(camera.world_to_raster()))


@pytest.mark.parametrize("kwargs, start", [
    (dict(center=(1, 1, 1), radius=1.0, distance=1e-300), "distance 1e-300 is too small: the eye falls on the target"),
    (dict(center=(0, 0, 0), radius=1.0, target=(1e308, 0, 0), distance=BIG), "distance 1.7e+308 is too large"),
    (dict(center=(0, 0, 0), radius=1.0, eye=(BIG, BIG, 0)), "the eye is too far from the model"),
])
def test_preset_distances_beyond_float64_are_one_line(kwargs, start):
    with pytest.raises(ValueError) as error:
        Camera.preset("perspective", **kwargs)
    assert _one_line(error).startswith(start)


@pytest.mark.parametrize("call, start", [
    (lambda: Camera.look_at((0, 0, BIG), (0, 0, -BIG)), "eye and target are too far apart"),
    (lambda: Camera.look_at((0, 0, 5), (0, 0, 0), near=1e-320, far=1e-310),
     "the camera's transformation overflows float64"),
    (lambda: Camera.look_at((0, 0, 5), (0, 0, 0), fov_y=1e-320), "the camera's transformation overflows float64"),
    (lambda: Camera.orthographic((0, 0, 5), (0, 0, 0), view_height=1e-320),
     "the camera's transformation overflows float64"),
    (lambda: Camera.frame((0, 0, 0), 1e308), "a sphere of radius 1e+308 is too large to frame"),
    (lambda: Camera.frame((1e16, 0, 0), 1e-300), "the camera's transformation overflows float64"),
    (lambda: Camera.frame((1e300, 1e300, 1e300), 1e-300), "a sphere of radius 1e-300 is too small to frame"),
    (lambda: Camera.look_at((0, 0, 5), (0, 0, 0), width=10**400), "width must be at most 32768 pixels"),
    (lambda: Camera.look_at(np.zeros(1000), (0, 0, 0)), "eye must be 3 finite numbers"),
    (lambda: transform.invert(transform.scale(0.0)), "the matrix cannot be inverted"),
    (lambda: transform.apply_normals(transform.scale(0, 1, 1), [[1.0, 0, 0]]), "normals cannot be transformed"),
    (lambda: transform.rotate_x(np.inf), "theta must be a finite angle"),
])
def test_cameras_and_transforms_beyond_float64_are_one_line(call, start):
    with pytest.raises(ValueError) as error:
        call()
    assert _one_line(error).startswith(start)


@pytest.mark.parametrize("camera", [
    lambda: Camera.look_at((0, 0, 1e-300), (0, 0, 0)),
    lambda: Camera.look_at((0, 0, 1e-170), (0, 0, 0)),
    lambda: Camera.look_at((0, 0, 5), (0, 0, 0), up=(0, 1e-320, 0)),
    lambda: Camera.look_at((0, 0, 1e300), (0, 0, 0), far=1e301),
    lambda: Camera.frame((1e300, 0, 0), 1e290),
])
def test_cameras_with_tiny_or_huge_but_sound_numbers_work(camera):
    cam = camera()
    u, v, w = cam.basis()
    assert np.allclose([np.linalg.norm(u), np.linalg.norm(v), np.linalg.norm(w)], 1.0)
    assert np.all(np.isfinite(cam.world_to_raster()))


def test_renders_of_overflowing_geometry_and_lights_draw_without_warnings():
    camera = Camera.look_at((0, 0, 5), (0, 0, 0), width=32, height=24)
    huge = Mesh([[BIG, 0, 0], [-BIG, BIG, 0], [0, 0, BIG], [0, 0, 0]], [[0, 1, 2], [0, 1, 3]])
    for mode in ("wire", "hidden", "solid", "solid+wire"):
        rasterkit.render(huge, camera, mode=mode, shading="smooth")
    cube = shapes.cube()
    for light in [(1e-320, 0, 0), (BIG, BIG, 0)]:
        lit = rasterkit.render(cube, camera, mode="solid", light=light).color
        expected = rasterkit.render(cube, camera, mode="solid", light=np.sign(light)).color
        assert np.array_equal(lit, expected)
    assert np.isinf(camera.project([[BIG, BIG, 0]])).any()
    scene = Scene(camera).add(huge, transform.scale(10.0))
    rasterkit.render(scene, mode="wire")
    assert np.all(np.isinf(transform.apply_points(transform.scale(10.0), [[BIG, BIG, BIG]])))


def test_a_singular_model_matrix_drops_the_normals_instead_of_failing():
    cube = shapes.cube()
    with_normals = Mesh(cube.vertices, cube.faces, normals=cube.vertices)
    flat = Scene(Camera.look_at((3, 2, 5), (0, 0, 0), width=32, height=24)).add(with_normals, transform.scale(1, 1, 0))
    assert flat.world_mesh().normals is None
    rasterkit.render(flat, mode="solid", shading="smooth")
