"""Point clouds (issue 17): square splats of a given size, depth-tested against faces and each other."""

from __future__ import annotations

import numpy as np
import pytest

import rasterkit
from rasterkit import Camera, shapes


def _camera():
    return Camera.from_opencv([[100.0, 0, 31.5], [0, 100.0, 23.5], [0, 0, 1]], np.diag([1.0, -1, -1]),
                              [0, 0, 5.0], 64, 48, near=1, far=10)


def test_a_point_splats_a_square_of_its_size_where_it_projects():
    camera = _camera()  # world (0, 0, 0) projects to raster (32, 24): the corner of four pixels
    for size, rows, cols in [(1, [23], [32]), (2, [23, 24], [31, 32]), (3, [22, 23, 24], [31, 32, 33])]:
        point = np.array([[0.0005, 0.0005, 0.0]])  # a hair right and up: raster (32.01, 23.99)
        fb = rasterkit.render(None, camera, points=point, point_size=size, point_color="red")
        j, i = np.nonzero(np.all(fb.color == (255, 0, 0), axis=2))
        assert sorted(set(j)) == rows and sorted(set(i)) == cols and len(j) == size * size
        assert fb.camera_depth()[j[0], i[0]] == pytest.approx(5.0, rel=1e-5)


def test_points_are_hidden_behind_faces_and_in_front_of_them():
    camera = _camera()
    behind, front = [[0.0, 0.0, -1.0]], [[0.0, 0.0, 1.0]]  # the cube spans z in [-0.5, 0.5]
    hidden = rasterkit.render(shapes.cube(), camera, "solid", points=behind, point_size=3, point_color="red")
    seen = rasterkit.render(shapes.cube(), camera, "solid", points=front, point_size=3, point_color="red")
    assert not np.any(np.all(hidden.color == (255, 0, 0), axis=2))
    assert np.sum(np.all(seen.color == (255, 0, 0), axis=2)) == 9


def test_nearer_points_win_and_colours_per_point():
    camera = _camera()
    points = [[0.0, 0.0, -2.0], [0.0, 0.0, 2.0], [0.0, 0.0, 0.0]]
    colors = [[255, 0, 0], [0, 255, 0], [0, 0, 255]]
    fb = rasterkit.render(None, camera, points=points, point_color=colors, point_size=2)
    assert np.all(fb.color[23:25, 31:33] == (0, 255, 0))


def test_bad_points_are_refused():
    camera = _camera()
    with pytest.raises(ValueError, match="points must be"):
        rasterkit.render(None, camera, points=[1, 2, 3])
    with pytest.raises(ValueError, match="point_size"):
        rasterkit.render(None, camera, points=[[1, 2, 3]], point_size=0)
    with pytest.raises(ValueError, match="point_color"):
        rasterkit.render(None, camera, points=[[1, 2, 3]], point_color=[[1, 2, 3], [4, 5, 6]])


def test_a_line_set_from_arrays_is_a_mesh_without_faces():
    camera = _camera()
    vertices = np.array([[-0.2, 0.0, 0.0], [0.2, 0.0, 0.0], [0.0, -0.2, 0.0], [0.0, 0.2, 0.0]])
    lines = rasterkit.Mesh(vertices, np.zeros((0, 3), np.int64), lines=[[0, 1], [2, 3]])
    fb = rasterkit.render(lines, camera, "wire", line_color="blue")
    blue = np.all(fb.color == (0, 0, 255), axis=2)
    assert blue.sum(axis=1).max() >= 8 and blue.sum(axis=0).max() >= 8  # a cross, 0.4 units = 8 px
