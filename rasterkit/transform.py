"""Affine transformations in homogeneous coordinates (the lecture's 4x4 matrices).

Every function returns a new 4x4 ``float64`` matrix acting on column vectors, ``p' = M @ p``.
Angles are in radians; rotations are right-handed (counter-clockwise when the axis points at
the viewer). ``compose(A, B)`` means "A, then B" and equals ``B @ A``.

Points carry ``w = 1`` and are moved by translations; direction vectors carry ``w = 0`` and
are not; surface normals transform with the inverse transpose of the linear part.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from rasterkit._arrays import describe, real_array, real_number
from rasterkit.limits import check_memory

__all__ = [
    "identity",
    "translate",
    "rotate_x",
    "rotate_y",
    "rotate_z",
    "rotate_axis",
    "scale",
    "reflect",
    "reflect_plane",
    "shear",
    "compose",
    "invert",
    "to_homogeneous",
    "from_homogeneous",
    "apply_points",
    "apply_vectors",
    "apply_normals",
]

_AXES = {"x": 0, "y": 1, "z": 2}


def identity() -> np.ndarray:
    """The 4x4 identity matrix."""
    return np.eye(4)


def translate(dx: float, dy: float, dz: float) -> np.ndarray:
    """Translation T(d): moves points by (dx, dy, dz), leaves vectors alone.

    >>> translate(1, 2, 3) @ [0, 0, 0, 1]
    array([1., 2., 3., 1.])
    """
    m = np.eye(4)
    m[:3, 3] = (real_number(dx, "dx"), real_number(dy, "dy"), real_number(dz, "dz"))
    return m


def _rotation(theta: float, i: int, j: int) -> np.ndarray:
    """Rotation by ``theta`` in the plane of axes i -> j (i turns towards j)."""
    theta = real_number(theta, "theta")
    if not math.isfinite(theta):
        raise ValueError(f"theta must be a finite angle, got {theta}")
    c, s = math.cos(theta), math.sin(theta)
    m = np.eye(4)
    m[i, i] = c
    m[i, j] = -s
    m[j, i] = s
    m[j, j] = c
    return m


def rotate_x(theta: float) -> np.ndarray:
    """Rotation R_x(theta) about the x axis: y turns towards z.

    ``[[1, 0, 0], [0, cos, -sin], [0, sin, cos]]`` in the upper-left 3x3 block.
    """
    return _rotation(theta, 1, 2)


def rotate_y(theta: float) -> np.ndarray:
    """Rotation R_y(theta) about the y axis: z turns towards x.

    ``[[cos, 0, sin], [0, 1, 0], [-sin, 0, cos]]`` in the upper-left 3x3 block.
    """
    return _rotation(theta, 2, 0)


def rotate_z(theta: float) -> np.ndarray:
    """Rotation R_z(theta) about the z axis: x turns towards y.

    ``[[cos, -sin, 0], [sin, cos, 0], [0, 0, 1]]`` in the upper-left 3x3 block.
    """
    return _rotation(theta, 0, 1)


def vector3(v: Sequence[float], name: str) -> np.ndarray:
    a = real_array(v, name)
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be 3 finite numbers, got {describe(v)}")
    return a


def _matrix(m, name: str = "matrix") -> np.ndarray:
    """``m`` as a (4, 4) float64 array of real numbers."""
    a = real_array(m, name)
    if a.shape != (4, 4):
        raise ValueError(f"{name} must be a 4x4 array, got shape {a.shape}")
    return a


def _points(points, name: str, width: int, bytes_per_point: int, what: str) -> np.ndarray:
    """``points`` as an (N, ``width``) float64 array of real numbers, once the
    ``bytes_per_point`` that the call needs for each are known to fit
    (:func:`rasterkit.limits.check_memory`)."""
    p = real_array(points, name, dtype=None)
    if p.ndim != 2 or p.shape[1] != width:
        raise ValueError(f"{name} must have shape (N, {width}), got {p.shape}")
    check_memory(len(p) * bytes_per_point, f"{what} of {len(p)} {name}")
    return p.astype(np.float64, copy=False)


def rotate_axis(
    theta: float, axis: Sequence[float], origin: Sequence[float] = (0.0, 0.0, 0.0)
) -> np.ndarray:
    """Rotation by ``theta`` about the line through ``origin`` with direction ``axis``.

    Built as the lecture builds it: move the axis to the origin, turn it onto the z axis,
    rotate about z, and undo the first two steps::

        T(o) · Ry(phi1) · Rx(-phi2) · Rz(theta) · Rx(phi2) · Ry(-phi1) · T(-o)

    where ``phi1`` is the angle of the axis' projection on the xz plane measured from +z
    towards +x, and ``phi2`` the angle between the axis and the xz plane. The lecture's
    ``tan phi1 = r_x / r_z`` divides by ``r_z``; ``atan2`` makes every direction work,
    the coordinate axes and their negatives included. The rotation is right-handed about
    ``axis`` (counter-clockwise when the axis points at the viewer). ``axis`` need not be
    unit length but must not be zero.
    """
    r = vector3(axis, "axis")
    o = vector3(origin, "origin")
    length = math.hypot(*r)
    if length == 0.0:
        raise ValueError("axis must not be the zero vector")
    rx, ry, rz = r / length
    phi1 = math.atan2(rx, rz)
    phi2 = math.atan2(ry, math.hypot(rx, rz))
    # Ry(-phi1) brings the axis into the yz plane, Rx(phi2) then lays it onto +z.
    return compose(
        translate(*(-o)),
        rotate_y(-phi1),
        rotate_x(phi2),
        rotate_z(theta),
        rotate_x(-phi2),
        rotate_y(phi1),
        translate(*o),
    )


def scale(sx: float, sy: float | None = None, sz: float | None = None) -> np.ndarray:
    """Scaling S(sx, sy, sz) about the origin; ``scale(s)`` scales uniformly."""
    if sy is None and sz is None:
        sy = sz = sx
    elif sy is None or sz is None:
        raise TypeError("scale takes one factor (uniform) or three")
    return np.diag([real_number(sx, "sx"), real_number(sy, "sy"), real_number(sz, "sz"), 1.0])


def reflect(axis: str) -> np.ndarray:
    """Reflection that mirrors one coordinate: ``reflect('z')`` is the lecture's M_z, z -> -z.

    ``axis`` is ``'x'``, ``'y'`` or ``'z'``: the coordinate that changes sign (the mirror is
    the plane where it is zero).
    """
    if axis not in _AXES:
        raise ValueError(f"axis must be 'x', 'y' or 'z', got {axis!r}")
    m = np.eye(4)
    m[_AXES[axis], _AXES[axis]] = -1.0
    return m


def reflect_plane(point: Sequence[float], normal: Sequence[float]) -> np.ndarray:
    """Reflection across the plane through ``point`` with normal ``normal`` (any length).

    Householder form: ``p' = p - 2 ((p - q)·n) n`` with unit ``n``.
    """
    q = vector3(point, "point")
    n = vector3(normal, "normal")
    length = math.hypot(*n)
    if length == 0.0:
        raise ValueError("normal must not be the zero vector")
    n = n / length
    m = np.eye(4)
    m[:3, :3] -= 2.0 * np.outer(n, n)
    m[:3, 3] = 2.0 * np.dot(q, n) * n
    return m


def shear(
    xy: float = 0.0,
    xz: float = 0.0,
    yx: float = 0.0,
    yz: float = 0.0,
    zx: float = 0.0,
    zy: float = 0.0,
) -> np.ndarray:
    """Shear: ``xy`` shifts x in proportion to y (``M[0, 1] = xy``), and so on.

    ``x' = x + xy·y + xz·z``, ``y' = y + yx·x + yz·z``, ``z' = z + zx·x + zy·y``.
    """
    m = np.eye(4)
    m[0, 1], m[0, 2] = real_number(xy, "xy"), real_number(xz, "xz")
    m[1, 0], m[1, 2] = real_number(yx, "yx"), real_number(yz, "yz")
    m[2, 0], m[2, 1] = real_number(zx, "zx"), real_number(zy, "zy")
    return m


def compose(*matrices: np.ndarray) -> np.ndarray:
    """The transformation "first ``matrices[0]``, then ``matrices[1]``, ...".

    ``compose(A, B) == B @ A``; ``compose()`` is the identity.
    """
    result = np.eye(4)
    with np.errstate(over="ignore", invalid="ignore"):  # inf and NaN as IEEE arithmetic gives them
        for k, m in enumerate(matrices):
            result = _matrix(m, f"matrices[{k}]") @ result
    return result


def invert(m: np.ndarray) -> np.ndarray:
    """Inverse of an affine 4x4 matrix (last row 0, 0, 0, 1): ``[A t]⁻¹ = [A⁻¹  -A⁻¹t]``.

    Raises ``ValueError`` when the matrix is not affine or its linear part is singular.
    """
    m = real_array(m, "matrix")
    if m.shape != (4, 4) or not np.array_equal(m[3], [0.0, 0.0, 0.0, 1.0]):
        raise ValueError("invert expects an affine 4x4 matrix (last row 0, 0, 0, 1)")
    if not np.all(np.isfinite(m)):
        raise ValueError("invert expects a finite matrix")
    with np.errstate(all="ignore"):
        try:
            a_inv = np.linalg.inv(m[:3, :3])
        except np.linalg.LinAlgError:
            a_inv = None
        if a_inv is None or not np.all(np.isfinite(a_inv)):
            raise ValueError("the matrix cannot be inverted: its linear part is singular")
        out = np.eye(4)
        out[:3, :3] = a_inv
        out[:3, 3] = -a_inv @ m[:3, 3]
    return out


def to_homogeneous(points: np.ndarray, w: float = 1.0) -> np.ndarray:
    """(N, 3) -> (N, 4) by appending ``w`` (1 for points, 0 for directions)."""
    p = _points(points, "points", 3, 24 + 40, "to_homogeneous")
    return np.concatenate([p, np.full((len(p), 1), real_number(w, "w"))], axis=1)


def from_homogeneous(h: np.ndarray) -> np.ndarray:
    """(N, 4) -> (N, 3) by dividing x, y, z by w.

    A row with ``w == 0`` is a point at infinity (a direction): its result is ``±inf`` in the
    non-zero coordinates and ``nan`` where the coordinate is also 0, as IEEE division gives.
    """
    h = _points(h, "homogeneous points", 4, 32 + 24, "from_homogeneous")
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        return h[:, :3] / h[:, 3:4]


def apply_points(m: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Transform (N, 3) points (w = 1) by ``m``, dividing by the resulting w.

    Arithmetic that overflows gives ``inf`` (and ``nan``) without a warning, as in
    :func:`from_homogeneous`."""
    matrix = _matrix(m)
    p = _points(points, "points", 3, 24 + 32 * 3 + 24, "apply_points")
    with np.errstate(over="ignore", invalid="ignore"):
        return from_homogeneous(to_homogeneous(p, 1.0) @ matrix.T)


def apply_vectors(m: np.ndarray, vectors: np.ndarray) -> np.ndarray:
    """Transform (N, 3) direction vectors (w = 0): the translation part has no effect."""
    matrix = _matrix(m)
    p = _points(vectors, "vectors", 3, 24 + 32 * 3, "apply_vectors")
    with np.errstate(over="ignore", invalid="ignore"):
        v = to_homogeneous(p, 0.0) @ matrix.T
    return v[:, :3]


def apply_normals(m: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """Transform (N, 3) surface normals by the inverse transpose of ``m``'s linear part.

    The results are renormalised to unit length (zero normals stay zero). Unlike directions,
    normals stay perpendicular to the surface under non-uniform scaling and shear.
    """
    linear = _matrix(m)[:3, :3]
    n = _points(normals, "normals", 3, 24 * 4 + 8, "apply_normals")
    with np.errstate(all="ignore"):
        try:
            inverse = np.linalg.inv(linear)
        except np.linalg.LinAlgError:
            inverse = None
        if inverse is None or not np.all(np.isfinite(inverse)):
            raise ValueError("normals cannot be transformed by a matrix whose linear part is singular")
        out = n @ inverse  # row form of inv(A).T @ n
        length = np.linalg.norm(out, axis=1, keepdims=True)
        return np.divide(out, length, out=np.zeros_like(out), where=length > 0)
