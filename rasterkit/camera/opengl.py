"""OpenGL's camera matrices and trimesh / pyrender poses in and out.

OpenGL's camera space is rasterkit's (x right, y up, looking down -z), so a view matrix is
the chain's ``R·T`` and a pose (camera -> world, as trimesh and pyrender store a camera
node) is its inverse: columns right, up, backward and the eye.

A projection matrix in OpenGL's convention (column vectors, NDC z in [-1, 1], near -> -1)

    [[1/half_w, 0,        shift_x,       0           ],
     [0,        1/half_h, shift_y,       0           ],
     [0,        0,        -(f+n)/(f-n),  -2fn/(f-n)  ],
     [0,        0,        -1,            0           ]]

is the perspective chain with the window ``half_w x half_h`` at distance 1 and the window
shift of the shear ``H``; ``glOrtho``'s centred box is the orthographic camera. OpenGL's
window y runs up, rasterkit's raster y down: raster ``y = H - y_window``; both put pixel
centres at +0.5, and OpenGL's depth ``(z_ndc + 1)/2`` equals rasterkit's stored depth.

The functions return plain values or the keyword arguments of a ``Camera``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from rasterkit.camera.checks import image_size
from rasterkit.camera.opencv import as_matrix, rotation


def _frame(view: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(eye, target, up) of a world -> camera rigid transform (OpenGL axes)."""
    if not np.array_equal(view[3], [0.0, 0.0, 0.0, 1.0]):
        raise ValueError("the view matrix must be rigid (last row 0, 0, 0, 1)")
    r = rotation(view[:3, :3], "the view matrix's rotation")
    eye = -r.T @ view[:3, 3]
    return eye, eye - r[2] * max(1.0, float(np.max(np.abs(eye)))), r[1]


def from_opengl(projection, view, width: int, height: int) -> dict[str, Any]:
    """The ``Camera`` keyword arguments of OpenGL matrices (see the module docstring)."""
    p = as_matrix(projection, (4, 4), "projection")
    eye, target, up = _frame(as_matrix(view, (4, 4), "view"))
    width, height = image_size(width, "width"), image_size(height, "height")
    off = (p[0, 1], p[1, 0], p[2, 0], p[2, 1], p[0, 3] if p[3, 3] == 0 else 0.0)
    if any(off) or not (p[0, 0] > 0.0 and p[1, 1] > 0.0):
        raise ValueError("projection must be a glFrustum / gluPerspective or a centred glOrtho matrix")
    frame = dict(eye=eye, target=target, up=up, width=width, height=height,
                 pixel_aspect=p[1, 1] * height / (p[0, 0] * width))
    if np.array_equal(p[3], [0.0, 0.0, -1.0, 0.0]) and p[1, 3] == 0.0:
        return dict(frame, kind="perspective", fov_y=math.degrees(2.0 * math.atan(1.0 / p[1, 1])),
                    shift=(p[0, 2], p[1, 2]), near=p[2, 3] / (p[2, 2] - 1.0), far=p[2, 3] / (p[2, 2] + 1.0))
    if np.array_equal(p[3], [0.0, 0.0, 0.0, 1.0]) and p[0, 2] == p[1, 2] == p[0, 3] == p[1, 3] == 0.0:
        return dict(frame, kind="parallel", view_height=2.0 / p[1, 1],
                    near=(p[2, 3] + 1.0) / p[2, 2], far=(p[2, 3] - 1.0) / p[2, 2])
    raise ValueError("projection must be a glFrustum / gluPerspective or a centred glOrtho matrix")


def opengl_matrices(camera) -> tuple[np.ndarray, np.ndarray]:
    """(projection, view) of a perspective or orthographic camera, OpenGL's convention."""
    if camera.oblique_ratio != 0.0:
        raise ValueError("an oblique camera has no OpenGL projection matrix of glOrtho's form")
    half_w, half_h = camera._half_window()
    n, f = camera.near, camera.far
    p = np.zeros((4, 4))
    p[0, 0], p[1, 1] = 1.0 / half_w, 1.0 / half_h
    if camera.kind == "perspective":
        p[0, 2], p[1, 2] = camera.shift
        p[2, 2], p[2, 3], p[3, 2] = -(f + n) / (f - n), -2.0 * f * n / (f - n), -1.0
    else:
        p[2, 2], p[2, 3], p[3, 3] = -2.0 / (f - n), -(f + n) / (f - n), 1.0
    return p, camera.view_matrix()


def pose_matrix(pose) -> np.ndarray:
    """A camera -> world pose checked: a finite rigid 4x4 matrix (a new float64 array)."""
    m = as_matrix(pose, (4, 4), "pose")
    if not np.array_equal(m[3], [0.0, 0.0, 0.0, 1.0]):
        raise ValueError("pose must be rigid (last row 0, 0, 0, 1)")
    rotation(m[:3, :3], "pose's rotation")
    return m


def from_pose(pose) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(eye, target, up) of a camera -> world pose (4x4, OpenGL axes: the camera looks down
    its -z column, its y column is up)."""
    m = pose_matrix(pose)
    r = m[:3, :3].T
    eye = m[:3, 3]
    return eye, eye - r[2] * max(1.0, float(np.max(np.abs(eye)))), r[1]


def pose(camera) -> np.ndarray:
    """The camera -> world pose: columns right, up, backward (unit vectors) and the eye."""
    m = np.eye(4)
    m[:3, :3] = np.stack(camera.basis(), axis=1)
    m[:3, 3] = camera.eye
    return m
