"""OpenCV's pinhole camera in and out: intrinsics K, extrinsics R, t, distortion coefficients.

OpenCV's camera space has x right, y *down* and z *forward*; a world point ``X`` projects to

    x_cam = R @ X + t,   u = fx·x_cam/z_cam + cx,   v = fy·y_cam/z_cam + cy,

with pixel centres at integer (u, v). rasterkit's camera looks down -z with y up, and its
pixel centres lie at +0.5, so the same point lands at raster ``(u + 0.5, v + 0.5)``.

In the lecture's chain the intrinsics are the window: ``fy`` sets the window height
(``fov_y``), ``fx ≠ fy`` a non-square window (``pixel_aspect = fy/fx``: the width of a pixel
over its height, in the scene), and a principal point away from the image centre is the
window shift, the shear ``H``:

    fov_y = 2·atan(H_px / (2·fy)),   shift = ((W - 2·cx - 1)/W, (2·cy + 1 - H_px)/H_px).

The functions return plain values or the keyword arguments of a ``Camera``; this module does
not import the ``Camera`` class.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from rasterkit._arrays import describe, real_array
from rasterkit.camera.checks import distortion_coefficients, image_size, positive

def as_matrix(value, shape: tuple[int, int], name: str) -> np.ndarray:
    m = np.array(real_array(value, name), dtype=np.float64)
    if m.shape != shape or not np.all(np.isfinite(m)):
        raise ValueError(f"{name} must be a finite {shape[0]}x{shape[1]} array, got {describe(value)}")
    return m


def _translation(value) -> np.ndarray:
    t = np.array(real_array(value, "t"), dtype=np.float64)
    if t.size != 3 or t.ndim > 2 or not np.all(np.isfinite(t)):
        raise ValueError(f"t must be 3 finite numbers, got {describe(value)}")
    return t.reshape(3)


def rotation(value, name: str) -> np.ndarray:
    """A 3x3 rotation matrix (orthonormal to 1e-6, determinant +1), as float64."""
    r = as_matrix(value, (3, 3), name)
    if not np.allclose(r @ r.T, np.eye(3), rtol=0.0, atol=1e-6) or np.linalg.det(r) <= 0.0:
        raise ValueError(f"{name} must be a rotation matrix (orthonormal rows, determinant +1)")
    return r


def intrinsics(k) -> tuple[float, float, float, float]:
    """(fx, fy, cx, cy) of a 3x3 intrinsic matrix ``[[fx, 0, cx], [0, fy, cy], [0, 0, 1]]``."""
    k = as_matrix(k, (3, 3), "K")
    if k[0, 1] != 0.0:
        raise ValueError(f"K has a skew K[0, 1] = {k[0, 1]:g}: cameras with skewed pixels are not supported")
    if k[1, 0] != 0.0 or k[2, 0] != 0.0 or k[2, 1] != 0.0 or k[2, 2] != 1.0:
        raise ValueError("K must have the form [[fx, 0, cx], [0, fy, cy], [0, 0, 1]]")
    fx, fy = positive(k[0, 0], "fx = K[0, 0]"), positive(k[1, 1], "fy = K[1, 1]")
    return fx, fy, float(k[0, 2]), float(k[1, 2])


def from_opencv(k, r, t, width: int, height: int, near: float, far: float, dist) -> dict[str, Any]:
    """The ``Camera`` keyword arguments of an OpenCV camera (see the module docstring)."""
    fx, fy, cx, cy = intrinsics(k)
    width, height = image_size(width, "width"), image_size(height, "height")
    r = rotation(r, "R")
    t = _translation(t)
    eye = -r.T @ t
    # the target one step (at least 1, or |eye|) ahead: eye + R[2] loses no digits of R[2]
    target = eye + r[2] * max(1.0, float(np.max(np.abs(eye))))
    return dict(kind="perspective", eye=eye, target=target, up=-r[1], width=width, height=height,
                near=near, far=far, fov_y=math.degrees(2.0 * math.atan(height / (2.0 * fy))),
                pixel_aspect=fy / fx,
                shift=((width - 2.0 * cx - 1.0) / width, (2.0 * cy + 1.0 - height) / height),
                distortion=distortion_coefficients(dist))


def to_opencv(camera) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(K, R, t) of a perspective camera, the inverse of :func:`from_opencv`."""
    if camera.kind != "perspective":
        raise ValueError("to_opencv needs a perspective camera (OpenCV's model is a pinhole)")
    half_w, half_h = camera._half_window()
    fx, fy = camera.width / (2.0 * half_w), camera.height / (2.0 * half_h)
    cx = (camera.width * (1.0 - camera.shift[0]) - 1.0) / 2.0
    cy = (camera.height * (1.0 + camera.shift[1]) - 1.0) / 2.0
    k = np.array([[fx, 0.0, cx], [0.0, fy, cy], [0.0, 0.0, 1.0]])
    u, v, w = camera.basis()
    r = np.stack([u, -v, -w])
    return k, r, -r @ np.asarray(camera.eye)
