"""Smooth shading keeps the faces' own colours (an OBJ's ``Kd``, an STL's or OFF's face
colours): each corner is its face's colour lit by the corner's normal."""

import numpy as np

import rasterkit


def _two_coloured_squares():
    """Two unit squares side by side in the plane z = 0, red and blue, sharing an edge."""
    vertices = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0], [1, 1, 0], [2, 1, 0]], float)
    faces = np.array([[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4]])
    colors = np.array([[1, 0, 0], [1, 0, 0], [0, 0, 1], [0, 0, 1]], np.float32)
    return rasterkit.Mesh(vertices, faces, face_colors=colors)


def test_a_flat_surface_draws_the_same_smooth_and_flat():
    """On a plane every vertex normal is the face normal, so smooth shading's colours are flat
    shading's (up to the rounding of interpolated values)."""
    mesh = _two_coloured_squares()
    camera = rasterkit.Camera.look_at((1, 0.5, 3), (1, 0.5, 0), (0, 1, 0), width=96, height=64, fov_y=50)
    flat = rasterkit.render(mesh, camera, "solid", shading="flat").color.astype(int)
    smooth = rasterkit.render(mesh, camera, "solid", shading="smooth").color.astype(int)
    drawn = (flat != 255).any(axis=2)
    assert drawn.sum() > 1000
    assert np.abs(flat - smooth)[drawn].max() <= 1
    assert {tuple(c) for c in smooth[drawn][:, :3] // 64} >= {(3, 0, 0), (0, 0, 3)}  # red and blue, not grey


def test_each_face_keeps_its_colour_across_a_shared_smooth_vertex():
    """A vertex shared by a red and a blue face is red in the red face and blue in the blue one:
    no colour bleeds across the edge."""
    mesh = _two_coloured_squares()
    camera = rasterkit.Camera.look_at((1, 0.5, 3), (1, 0.5, 0), (0, 1, 0), width=96, height=64, fov_y=50)
    image = rasterkit.render(mesh, camera, "solid", shading="smooth").color.astype(int)
    row = image[32]
    drawn = np.flatnonzero((row != 255).any(axis=1))
    left, right = row[drawn[: len(drawn) // 2 - 2]], row[drawn[len(drawn) // 2 + 2:]]
    assert (left[:, 1] == 0).all() and (left[:, 2] == 0).all() and (left[:, 0] > 0).all()
    assert (right[:, 0] == 0).all() and (right[:, 1] == 0).all() and (right[:, 2] > 0).all()
