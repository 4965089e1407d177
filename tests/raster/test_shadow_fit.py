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


def numpy_extent(view, depth, visible, softness):
    """The extent (low, high) across the light of the points that may be in shadow
    (rasterkit.raster.shadows._refit's), with NumPy; None when there are none."""
    size = depth.shape[0]
    basis = view.frame
    span = view.far - view.near
    texel = view.view_height / size
    matrix = view.world_to_raster()

    def dot(vector, rows):
        return vector[0] * rows[0] + vector[1] * rows[1] + vector[2] * rows[2]

    x = dot(matrix[0, :3], visible) + matrix[0, 3]
    y = dot(matrix[1, :3], visible) + matrix[1, 3]
    facing = -dot(basis[2], visible[3:6])
    keep = np.nonzero((x >= 0) & (y >= 0) & (x < size) & (y < size) & (facing > 0.0))[0]
    points, facing = visible[:, keep], facing[keep]
    i, j = x[keep].astype(np.int64), y[keep].astype(np.int64)
    along = dot(basis[2], points) - float(basis[2] @ np.asarray(view.eye))
    slope = np.minimum(np.sqrt(np.maximum(1.0 - facing * facing, 0.0)) / facing, 20.0)
    flat, columns = depth.reshape(-1), [np.clip(i + d, 0, size - 1) for d in (-1, 0, 1)]
    nearest = np.full(len(i), np.inf, np.float32)
    for d in (-1, 0, 1):
        row = np.clip(j + d, 0, size - 1) * size
        for column in columns:
            np.minimum(nearest, flat[row + column], out=nearest)
    shadowed = nearest < (along - texel * (2.0 + 1.5 * slope) - view.near) / span
    if not shadowed.any():
        return None
    points = points[:, shadowed]
    margin = points[6] + (math.ceil(softness) + 4.0) * texel
    across = [dot(basis[0], points), dot(basis[1], points)]
    return (np.array([(a - margin).min() for a in across]), np.array([(a + margin).max() for a in across]),
            int(shadowed.sum()))


@pytest.mark.parametrize("direction", [(-0.5, -0.85, 0.13), (0.3, -1.0, -0.6), (0.0, -1.0, 0.0)])
def test_the_shadowed_extent_a_map_is_fitted_to_is_what_numpy_works_out(direction):
    from rasterkit.raster.kernels.shadow_fit import shadowed_extent

    mesh = rk.shapes.demo()
    camera = rk.Camera.look_at((2.5, 1.5, 3.0), (0, 0, 0), width=640, height=360, fov_y=40)
    low, high = mesh.vertices.min(axis=0), mesh.vertices.max(axis=0)
    corners = shadows._box_corners(np.stack([low, high]))
    centre, radius = (low + high) / 2.0, float(np.linalg.norm(high - low)) / 2.0
    view = shadows._parallel(corners, shadows._seen(camera, centre, radius), np.asarray(direction), 2048)
    coarse = view.with_size(512, 512)
    depth = shadows._depth(mesh.vertices, mesh.faces, coarse)
    visible = shadows._visible(mesh, camera)
    expected = numpy_extent(coarse, depth, visible, 1.0)
    texel = coarse.view_height / 512
    count, low0, low1, high0, high1 = shadowed_extent(
        visible, coarse.world_to_raster(), np.ascontiguousarray(coarse.frame), float(coarse.frame[2] @ coarse.eye),
        depth, texel, float(coarse.near), coarse.far - coarse.near, (1.0 + 4.0) * texel)
    assert expected is not None and count == expected[2] > 20
    np.testing.assert_array_equal([low0, low1], expected[0])
    np.testing.assert_array_equal([high0, high1], expected[1])
