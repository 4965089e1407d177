"""The factors of the camera transformation, one small function each, named as in the lecture.

A perspective camera maps world points to homogeneous raster space with the chain

    K = Raster · S_raster · P_parallel · P_persp · S_far · S_xy · H · R · T

(rightmost applied first); a parallel (orthographic, axonometric or oblique) camera with

    K = Raster · S_raster · P_parallel · S_xyz · T_near · R · T.

:func:`perspective_chain` and :func:`parallel_chain` list these factors, first applied first,
for a camera's parameters; :meth:`rasterkit.Camera.chain` calls them. The conventions are in
the docstring of :mod:`rasterkit.camera`.
"""

from __future__ import annotations

import numpy as np

from rasterkit._arrays import unit
from rasterkit.transform import compose, reflect, scale, shear, translate

Factors = list[tuple[str, np.ndarray]]
"""A chain: (lecture name, (4, 4) float64 matrix) pairs, first applied first."""


def camera_frame(eye, target, up) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The camera frame (u, v, w): unit right, up and backward vectors in world space.

    ``w = (eye - target)/|eye - target|``, ``u = up × w`` normalised, ``v = w × u``; the
    unit vectors are found without squaring tiny or huge components (``up`` is made unit
    first when ``up × w`` is too small or too large to normalise directly)."""
    w = unit(np.subtract(eye, target), "eye - target")
    with np.errstate(under="ignore", over="ignore"):
        cross = np.cross(up, w)
    if not 1e-150 < np.max(np.abs(cross)) < 1e150:
        cross = np.cross(unit(np.asarray(up, np.float64), "up"), w)
    u = unit(cross, "up × (eye - target)")
    return u, np.cross(w, u), w


# --- the factors -------------------------------------------------------------------------------


def _T(eye: np.ndarray) -> np.ndarray:
    """T: moves the eye to the origin."""
    return translate(*(-eye))


def _R(u: np.ndarray, v: np.ndarray, w: np.ndarray) -> np.ndarray:
    """R: rotates the camera frame (u, v, w) onto the axes (x, y, z).

    u points right, v up and w backwards (from the target towards the eye), so after R the
    camera looks down -z. The rows of R are u, v and w.
    """
    m = np.eye(4)
    m[:3, :3] = np.stack([u, v, w])
    return m


def _H(center_x: float, center_y: float) -> np.ndarray:
    """H: shears the window centre onto the -z axis.

    The window lies in the plane z = -1 with its centre at (center_x, center_y, -1);
    ``x' = x + center_x·z`` moves that centre to (0, 0, -1) and keeps the eye and every
    plane z = const. A centred window gives the identity.
    """
    return shear(xz=center_x, yz=center_y)


def _S_xy(half_width: float, half_height: float) -> np.ndarray:
    """S_xy: scales x and y so the side planes of the view volume have slope 1 (90° opening).

    The window at z = -1 is [-half_width, half_width] x [-half_height, half_height]; afterwards
    it is [-1, 1]², so the side planes are x = ±z and y = ±z.
    """
    return scale(1.0 / half_width, 1.0 / half_height, 1.0)


def _S_far(far: float) -> np.ndarray:
    """S_far: scales uniformly so the far plane lies at z = -1 (and the near plane at -near/far)."""
    return scale(1.0 / far)


def _P_persp(z_min: float) -> np.ndarray:
    """P_persp: turns the view cone into the canonical parallel view volume (a box).

    The truncated pyramid |x|, |y| <= -z, -1 <= z <= z_min (near plane z_min = -near/far)
    becomes, after the homogeneous divide, the box [-1, 1]² x [-1, 0]: near plane at z = 0,
    far plane at z = -1 (Foley–van Dam). The new w is -z, so w > 0 in front of the eye.
    """
    return np.array(
        [
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0 / (1.0 + z_min), -z_min / (1.0 + z_min)],
            [0.0, 0.0, -1.0, 0.0],
        ]
    )


def _P_parallel(shear_x: float = 0.0, shear_y: float = 0.0, z_fixed: float = 0.0) -> np.ndarray:
    """P_parallel: the parallel projection onto the image plane that keeps the depth.

    Works on the canonical view volume [-1, 1]² x [-1, 0]. x and y are the image
    coordinates; the third coordinate becomes the depth -z in [0, 1] (0 near, 1 far),
    kept for the depth test instead of being dropped.

    For an oblique projection the projectors are not perpendicular to the image plane: first
    ``x' = x - shear_x·(z - z_fixed)``, ``y' = y - shear_y·(z - z_fixed)``, a shear that fixes
    the plane z = z_fixed and moves deeper points by ``shear·(their distance behind it)``.
    With no shear this is the orthographic projection.
    """
    return compose(
        translate(0.0, 0.0, -z_fixed),
        shear(xz=-shear_x, yz=-shear_y),
        translate(0.0, 0.0, z_fixed),
        reflect("z"),
    )


def _S_raster(width: int, height: int) -> np.ndarray:
    """S_raster: scales the [-1, 1]² window to the raster size, [-W/2, W/2] x [-H/2, H/2]."""
    return scale(width / 2.0, height / 2.0, 1.0)


def _Raster(width: int, height: int) -> np.ndarray:
    """Raster: flips y (raster y points down) and moves the origin to the top-left corner."""
    return compose(reflect("y"), translate(width / 2.0, height / 2.0, 0.0))


def _T_near(near: float) -> np.ndarray:
    """T_near (parallel chain): moves the near plane z = -near to z = 0."""
    return translate(0.0, 0.0, near)


def _S_xyz(half_width: float, half_height: float, depth: float) -> np.ndarray:
    """S_xyz (parallel chain): scales the view box to the canonical volume [-1, 1]² x [-1, 0].

    The box is [-half_width, half_width] x [-half_height, half_height] x [-depth, 0] with
    ``depth = far - near``.
    """
    return scale(1.0 / half_width, 1.0 / half_height, 1.0 / depth)


# --- the chains ----------------------------------------------------------------------------


def _view(eye: np.ndarray, basis: tuple[np.ndarray, np.ndarray, np.ndarray]) -> Factors:
    """T, R: world -> camera space, shared by both chains."""
    return [("T", _T(eye)), ("R", _R(*basis))]


def _raster(width: int, height: int) -> Factors:
    """S_raster, Raster: canonical window -> raster pixels, shared by both chains."""
    return [("S_raster", _S_raster(width, height)), ("Raster", _Raster(width, height))]


def perspective_chain(
    *,
    eye: np.ndarray,
    basis: tuple[np.ndarray, np.ndarray, np.ndarray],
    half_window: tuple[float, float],
    shift: tuple[float, float],
    near: float,
    far: float,
    width: int,
    height: int,
) -> Factors:
    """T, R, H, S_xy, S_far, P_persp, P_parallel, S_raster, Raster.

    Parameters
    ----------
    eye : (3,) float64 ndarray
        World-space eye point.
    basis : three (3,) float64 ndarrays
        The camera frame (u, v, w): unit right, up and backward vectors in world space.
    half_window : (float, float)
        Half width and half height of the window at distance 1 from the eye.
    shift : (float, float)
        Window shift in units of the half window width and height.
    near, far : float
        Distances of the near and far planes from the eye, world units.
    width, height : int
        Image size in pixels.
    """
    half_w, half_h = half_window
    return _view(eye, basis) + [
        ("H", _H(shift[0] * half_w, shift[1] * half_h)),
        ("S_xy", _S_xy(half_w, half_h)),
        ("S_far", _S_far(far)),
        ("P_persp", _P_persp(-near / far)),
        ("P_parallel", _P_parallel()),
    ] + _raster(width, height)


def parallel_chain(
    *,
    eye: np.ndarray,
    basis: tuple[np.ndarray, np.ndarray, np.ndarray],
    half_window: tuple[float, float],
    oblique: tuple[float, float],
    target_distance: float,
    near: float,
    far: float,
    width: int,
    height: int,
) -> Factors:
    """T, R, T_near, S_xyz, P_parallel, S_raster, Raster.

    Parameters as for :func:`perspective_chain`, except:

    half_window : (float, float)
        Half width and half height of the view box, world units.
    oblique : (float, float)
        Image offset (x, y up) per world unit of depth behind the image plane (zero for an
        orthographic camera), see :func:`.projections.oblique_offsets`.
    target_distance : float
        Distance from the eye to the target: the oblique shear leaves the plane through the
        target, parallel to the image plane, in place.
    """
    half_w, half_h = half_window
    depth = far - near
    k_x, k_y = oblique
    # The oblique offsets are per world unit of depth; the canonical volume measures
    # x, y in half windows and depth in units of (far - near).
    z_target = (near - target_distance) / depth
    return _view(eye, basis) + [
        ("T_near", _T_near(near)),
        ("S_xyz", _S_xyz(half_w, half_h, depth)),
        ("P_parallel", _P_parallel(k_x * depth / half_w, k_y * depth / half_h, z_target)),
    ] + _raster(width, height)
