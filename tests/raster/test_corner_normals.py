"""Smooth shading with the mesh's own normal at each face corner: an authored hard edge (the
corners of one vertex with different ``vn``) stays hard, a soft one stays soft."""

from __future__ import annotations

import dataclasses

import numpy as np

import rasterkit
from rasterkit import Camera, load_obj
from rasterkit.raster.kernels.shade import bary_matrices
from rasterkit.raster.vertex import transform_points

CUBE_OBJ = """\
v -1 -1 -1
v 1 -1 -1
v 1 1 -1
v -1 1 -1
v -1 -1 1
v 1 -1 1
v 1 1 1
v -1 1 1
vn 0 0 -1
vn 0 0 1
vn 0 -1 0
vn 0 1 0
vn -1 0 0
vn 1 0 0
f 1//1 4//1 3//1 2//1
f 5//2 6//2 7//2 8//2
f 1//3 2//3 6//3 5//3
f 4//4 8//4 7//4 3//4
f 1//5 5//5 8//5 4//5
f 2//6 3//6 7//6 6//6
"""
CAMERA = Camera.look_at((2.5, 1.8, 3.2), (0, 0, 0), width=160, height=120)


def _cube(tmp_path):
    path = tmp_path / "cube.obj"
    path.write_text(CUBE_OBJ)
    return load_obj(path)


def test_hard_edges_stay_hard_in_smooth_shading(tmp_path):
    """Every corner of a face has the face's normal: smooth shading is the flat colours (to
    the rounding of float32 face normals), where the per-vertex average would shade each
    face from one colour to another."""
    cube = _cube(tmp_path)
    assert cube.smooth_corners[2]  # split: each vertex has three normals
    smooth = rasterkit.render(cube, CAMERA, "solid", shading="smooth", ids=True)
    flat = rasterkit.render(cube, CAMERA, "solid", shading="flat").color.astype(int)
    covered = smooth.ids >= 0
    assert covered.sum() > 3000
    assert np.abs(smooth.color.astype(int) - flat)[covered].max() <= 1
    averaged = dataclasses.replace(cube, corner_normals=None, normal_index=None)
    soft = rasterkit.render(averaged, CAMERA, "solid", shading="smooth").color.astype(int)
    assert np.mean(np.abs(soft - flat)[covered].max(axis=1) > 8) > 0.3
    # three visible faces, each of one colour
    for face in range(len(cube.faces)):
        on = smooth.ids == face
        if on.sum() > 20:
            assert len(np.unique(smooth.color[on], axis=0)) == 1


def test_hard_edges_with_vertex_colours(tmp_path):
    """Colours per vertex and normals per corner: a row per distinct (vertex, normal), each
    interpolated perspective-correctly; a face's colours are its vertices' colours lit by
    its own normal."""
    cube = _cube(tmp_path)
    colours = np.random.default_rng(2).uniform(0.2, 1.0, (8, 3)).astype(np.float32)
    coloured = dataclasses.replace(cube, vertex_colors=colours)
    fb = rasterkit.render(coloured, CAMERA, "solid", shading="smooth", ids=True, light=(0.3, 0.5, 0.8))
    light = np.array([0.3, 0.5, 0.8]) / np.linalg.norm([0.3, 0.5, 0.8])
    ys, xs = np.nonzero(fb.ids >= 0)
    faces = fb.ids[ys, xs]
    clip = transform_points(cube.vertices, np.ascontiguousarray(CAMERA.world_to_raster()))
    rows = bary_matrices(clip, cube.faces).reshape(-1, 3, 3)[faces]
    b = rows[:, :, 0] * (xs + 0.5)[:, None] + rows[:, :, 1] * (ys + 0.5)[:, None] + rows[:, :, 2]
    b /= b.sum(axis=1, keepdims=True)
    normals = cube.corner_normals[cube.normal_index[faces, 0]]  # one normal per face here
    intensity = 0.25 + 0.75 * np.maximum(normals @ light, 0.0)
    corner_colours = colours[cube.faces[faces]] * 255.0  # (P, 3 corners, rgb)
    expected = np.floor((b[:, :, None] * corner_colours).sum(axis=1) * intensity[:, None] + 0.5)
    assert len(xs) > 3000
    assert np.abs(fb.color[ys, xs].astype(int) - expected).max() <= 1
