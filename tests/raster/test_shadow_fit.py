"""The visible surface a directional light's shadow map is fitted to
(rasterkit.raster.shadows._visible, its points from rasterkit.raster.kernels.shadow_fit)
against the same points worked out with NumPy array expressions."""

from __future__ import annotations

import math

import numpy as np
import pytest

import rasterkit as rk
from rasterkit.raster import shadows
from rasterkit.raster.triangles import rasterize_checked
from rasterkit.raster.vertex import transform_points


def numpy_visible(mesh, small):
    """The points of ``small``'s drawing of ``mesh``, one per covered pixel, with NumPy."""
    depth = np.full((small.height, small.width), np.inf, np.float32)
    ids = np.full((small.height, small.width), -1, np.int32)
    matrix = small.world_to_raster()
    clip = transform_points(np.ascontiguousarray(mesh.vertices, np.float64), np.ascontiguousarray(matrix))
    rasterize_checked(None, depth, clip, mesh.faces, None, None, ids, "none", (), (0.0, 0.0), None, trusted=True)
    j, i = np.nonzero(np.isfinite(depth) & (ids >= 0))
    raster = (i + 0.5, j + 0.5, depth[j, i].astype(np.float64))
    inverse = np.linalg.inv(matrix)
    world = [inverse[r, 0] * raster[0] + inverse[r, 1] * raster[1] + inverse[r, 2] * raster[2] + inverse[r, 3]
             for r in range(4)]
    out = np.empty((7, len(i)))
    out[0:3] = world[0:3]
    out[0:3] /= world[3]
    out[3:6] = mesh.face_normals[ids[j, i]].T
    backward = np.asarray(small.backward())
    if small.kind == "perspective":
        towards = np.asarray(small.eye)[:, None] - out[0:3]
        along = backward[0] * towards[0] + backward[1] * towards[1] + backward[2] * towards[2]
        out[6] = along * 2.0 * math.tan(math.radians(small.fov_y) / 2.0) / small.height
    else:
        towards = backward[:, None]
        out[6] = small.view_height / small.height
    out[3:6] *= np.where((out[3:6] * towards).sum(axis=0) < 0.0, -1.0, 1.0)
    return out[:, np.isfinite(out).all(axis=0)]


@pytest.mark.parametrize("projection", ["perspective", "parallel"])
def test_the_visible_points_are_those_numpy_works_out_bit_for_bit(projection):
    mesh = rk.shapes.demo()
    camera = rk.Camera.look_at((2.5, 1.5, 3.0), (0, 0, 0), width=640, height=360, fov_y=40)
    if projection == "parallel":
        camera = rk.Camera.orthographic((2.5, 1.5, 3.0), (0, 0, 0), view_height=3.0, width=640, height=360)
    points = shadows._visible(mesh, camera)
    small = camera.with_size(384, 216)
    expected = numpy_visible(mesh, small)
    assert points.shape == expected.shape and points.shape[1] > 1000
    np.testing.assert_array_equal(points, expected)


def test_points_with_a_value_that_is_not_finite_are_left_out():
    # a face with a huge corner: its normal is NaN, so its pixels give no point
    mesh = rk.shapes.demo()
    vertices = mesh.vertices.copy()
    faces = np.concatenate([mesh.faces, [[len(vertices), len(vertices) + 1, len(vertices) + 2]]])
    vertices = np.concatenate([vertices, [[-0.2, -0.2, 1.5], [0.2, -0.2, 1.5], [0.0, 1e308, 1.5]]])
    mesh = rk.Mesh(vertices, faces)
    camera = rk.Camera.look_at((0, 0, 4.0), (0, 0, 0), width=384, height=384, fov_y=50)
    points = shadows._visible(mesh, camera)
    expected = numpy_visible(mesh, camera)
    assert np.isfinite(points).all()
    np.testing.assert_array_equal(points, expected)
