"""The named projections: which camera frames a bounding sphere for each of them.

:data:`PROJECTIONS` (at home in :mod:`rasterkit.options`, which the command line reads
without importing NumPy) lists the names that :meth:`rasterkit.Camera.preset` (and the
command line's ``--projection``) accept. The functions here hold the geometry that the
``Camera`` constructors share: the orbit direction (azimuth, elevation), the oblique
offsets, the camera that frames a sphere, and ``preset``'s choice of constructor and its
overrides. They return plain values or the keyword arguments of a ``Camera``; this module
does not import the ``Camera`` class (it imports this module).
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any, Sequence, TypeVar

import numpy as np

from rasterkit.options import PROJECTIONS
from rasterkit._arrays import length, unit
from rasterkit.camera.checks import finite, fov, point, positive, positive_int

#: Elevation (degrees) of an isometric view: the view direction is a cube diagonal, whose
#: angle with the horizontal plane is atan(1/sqrt(2)) = 35.264°.
ISOMETRIC_ELEVATION = math.degrees(math.atan(1.0 / math.sqrt(2.0)))

# The Camera classmethod that builds each preset of PROJECTIONS ('perspective' and
# 'orthographic' are Camera.frame).
_PRESET_METHODS = {"isometric": "isometric", "dimetric": "dimetric", "trimetric": "trimetric",
                   "cavalier": "cavalier", "cabinet": "cabinet", "1-point": "one_point",
                   "2-point": "two_point", "3-point": "three_point"}

_Camera = TypeVar("_Camera")


def _orbit_direction(azimuth: float, elevation: float) -> np.ndarray:
    """Unit vector from the target to the eye: azimuth about +Y from +Z towards +X, elevation up."""
    az = math.radians(finite(azimuth, "azimuth"))
    el = math.radians(finite(elevation, "elevation"))
    if not abs(el) < math.pi / 2:
        raise ValueError(
            f"elevation must lie strictly between -90 and 90 degrees, got {elevation!r}")
    return np.array([math.cos(el) * math.sin(az), math.sin(el), math.cos(el) * math.cos(az)])


def oblique_offsets(angle: float, ratio: float) -> tuple[float, float]:
    """Image offset (x, y up) per world unit of depth behind the image plane, world units."""
    angle = math.radians(finite(angle, "oblique_angle"))
    ratio = finite(ratio, "oblique_ratio")
    return ratio * math.cos(angle), ratio * math.sin(angle)


def _require_off_axis_view(azimuth: float, elevation: float | None, preset: str) -> None:
    """The 2- and 3-point presets need views that are not aligned with the world axes."""
    if finite(azimuth, "azimuth") % 90.0 == 0.0:
        raise ValueError(
            f"{preset} needs an azimuth that is not a multiple of 90°, got {azimuth!r}")
    if elevation is not None and finite(elevation, "elevation") == 0.0:
        raise ValueError(f"{preset} needs a non-zero elevation")


def framing(
    center: Sequence[float],
    radius: float,
    azimuth: float,
    elevation: float,
    width: int,
    height: int,
    *,
    fov_y: float | None = None,
    oblique_angle: float = 0.0,
    oblique_ratio: float = 0.0,
) -> dict[str, Any]:
    """The ``Camera`` keyword arguments of a camera whose view a bounding sphere fills.

    The shared geometry of ``Camera.frame`` and the presets; ``fov_y=None`` means parallel.
    The eye sits in the direction :func:`_orbit_direction` (azimuth, elevation) from ``center``.
    """
    c = np.array(point(center, "center"))
    r = positive(radius, "radius")
    direction = _orbit_direction(azimuth, elevation)
    aspect = positive_int(width, "width") / positive_int(height, "height")
    kind = "perspective" if fov_y is not None else "parallel"
    view_height = None
    if fov_y is not None:
        # The silhouette cone of the sphere (half-angle asin(r/d)) meets the frustum's
        # narrower pair of side planes.
        half_angle = math.atan(math.tan(math.radians(fov(fov_y)) / 2.0) * min(1.0, aspect))
        distance = r / math.sin(half_angle)
    else:
        # An oblique shear stretches the sphere's image to an ellipse with half axes
        # r·sqrt(1 + k²) along x and y.
        k = oblique_offsets(oblique_angle, oblique_ratio)
        view_height = 2.0 * r * max(math.hypot(1.0, k[1]), math.hypot(1.0, k[0]) / aspect)
        distance = 2.0 * r
    with np.errstate(over="ignore", invalid="ignore"):
        eye = c + distance * direction
    near, far = (distance - r) / 2.0, distance + 2.0 * r
    if not (np.all(np.isfinite(eye)) and math.isfinite(far) and math.isfinite(view_height or 0.0)):
        raise ValueError(f"a sphere of radius {r:g} is too large to frame: the camera's distances overflow "
                         f"float64 (scale the model down)")
    if not near > 0.0 or np.array_equal(eye, c):
        raise ValueError(f"a sphere of radius {r:g} is too small to frame next to its centre's coordinates (up to "
                         f"{float(np.max(np.abs(c))):g}): the eye falls on the centre in float64")
    return dict(kind=kind, eye=tuple(eye), target=tuple(c),
                width=width, height=height, near=near, far=far,
                fov_y=fov_y, view_height=view_height,
                oblique_angle=oblique_angle, oblique_ratio=oblique_ratio)


# --- the presets: the Camera keyword arguments of each named view --------------------------


def isometric(center: Sequence[float], radius: float, width: int, height: int) -> dict[str, Any]:
    """Isometric view: looks along a cube diagonal, (-1, -1, -1).

    The three world axes are foreshortened equally (by sqrt(2/3)) and their images meet
    at 120°. Azimuth 45°, elevation atan(1/sqrt(2)) = 35.26°.
    """
    return framing(center, radius, 45.0, ISOMETRIC_ELEVATION, width, height)


def dimetric(center: Sequence[float], radius: float, elevation: float, width: int,
             height: int) -> dict[str, Any]:
    """Dimetric view: azimuth 45°, so x and z are foreshortened equally, y differently.

    ``elevation`` (degrees) chooses the third foreshortening; at 35.26° the view is
    isometric.
    """
    return framing(center, radius, 45.0, elevation, width, height)


def trimetric(center: Sequence[float], radius: float, azimuth: float, elevation: float,
              width: int, height: int) -> dict[str, Any]:
    """Trimetric view: a view direction that foreshortens the three axes differently.

    The foreshortening of axis i is ``sqrt(1 - d_i²)`` for the unit view direction d;
    the default angles of ``Camera.trimetric`` (30°, 20°) give 0.88 (x), 0.94 (y), 0.58 (z).
    """
    return framing(center, radius, azimuth, elevation, width, height)


def oblique(angle: float, ratio: float, center: Sequence[float], radius: float, azimuth: float,
            elevation: float, width: int, height: int) -> dict[str, Any]:
    """Oblique parallel projection: projectors not perpendicular to the image plane.

    Built as the orthographic chain with the oblique shear placed in P_parallel. At azimuth
    and elevation 0 the image plane is parallel to the world xy plane (looking down -Z) and
    the receding axis is z: a unit vector along -Z is drawn with length ``ratio`` at
    ``angle`` degrees counter-clockwise from the image's x axis, while x and y keep their
    length. The plane through ``center`` parallel to the image plane is the one the shear
    leaves in place, so the centre stays in the middle of the image.
    """
    return framing(center, radius, azimuth, elevation, width, height,
                   oblique_angle=angle, oblique_ratio=ratio)


def cavalier(center: Sequence[float], radius: float, angle: float, width: int,
             height: int) -> dict[str, Any]:
    """Cavalier projection: oblique, the receding axis keeps its full length (ratio 1)."""
    return oblique(angle, 1.0, center, radius, 0.0, 0.0, width, height)


def cabinet(center: Sequence[float], radius: float, angle: float, width: int,
            height: int) -> dict[str, Any]:
    """Cabinet projection: oblique, the receding axis is drawn at half length (ratio 1/2)."""
    return oblique(angle, 0.5, center, radius, 0.0, 0.0, width, height)


def one_point(center: Sequence[float], radius: float, fov_y: float, width: int,
              height: int) -> dict[str, Any]:
    """One-point perspective: looks along -Z with up +Y.

    The image plane is parallel to the x and y axes; only lines parallel to z converge,
    to one vanishing point (the image centre).
    """
    return framing(center, radius, 0.0, 0.0, width, height, fov_y=fov_y)


def two_point(center: Sequence[float], radius: float, azimuth: float, fov_y: float, width: int,
              height: int) -> dict[str, Any]:
    """Two-point perspective: yawed about Y by ``azimuth`` (not a multiple of 90°), level.

    The view direction stays horizontal, so the image plane is parallel to y only: lines
    parallel to x and to z have vanishing points, verticals stay vertical.
    """
    _require_off_axis_view(azimuth, None, "two_point")
    return framing(center, radius, azimuth, 0.0, width, height, fov_y=fov_y)


def three_point(center: Sequence[float], radius: float, azimuth: float, elevation: float,
                fov_y: float, width: int, height: int) -> dict[str, Any]:
    """Three-point perspective: yawed (``azimuth``) and pitched (``elevation`` != 0).

    The image plane is parallel to none of the axes: all three have vanishing points.
    """
    _require_off_axis_view(azimuth, elevation, "three_point")
    return framing(center, radius, azimuth, elevation, width, height, fov_y=fov_y)


def preset(
    camera_cls: type[_Camera], projection: str, center: Sequence[float], radius: float, *,
    width: int, height: int, azimuth: float, elevation: float, fov_y: float,
    distance: float | None, eye: Sequence[float] | None, target: Sequence[float] | None,
    up: Sequence[float] | None, near: float | None, far: float | None,
    aperture: float = 0.0, focus_distance: float | None = None,
) -> _Camera:
    """:meth:`Camera.preset`: the named projection's camera, then the overrides in their order.

    ``camera_cls`` is the ``Camera`` class; its constructor for ``projection`` frames the
    sphere, then ``distance``, ``eye``, ``target``, ``up``, ``near`` and ``far`` replace what
    they name (``near`` and ``far`` otherwise enclose the sphere as seen from the final eye).
    """
    if projection not in PROJECTIONS:
        raise ValueError(f"projection must be one of {', '.join(PROJECTIONS)}, got {projection!r}")
    size = dict(width=width, height=height)
    if projection in ("perspective", "orthographic"):
        kind = "perspective" if projection == "perspective" else "parallel"
        cam = camera_cls.frame(center, radius, azimuth, elevation, fov_y, projection=kind, **size)
    elif projection in ("1-point", "2-point", "3-point"):
        cam = getattr(camera_cls, _PRESET_METHODS[projection])(center, radius, fov_y=fov_y, **size)
    else:
        cam = getattr(camera_cls, _PRESET_METHODS[projection])(center, radius, **size)
    new_target = np.array(point(target, "target") if target is not None else cam.target)
    new_eye = np.array(point(eye, "eye") if eye is not None else cam.eye)
    if distance is not None and eye is None:
        offset = np.subtract(cam.eye, cam.target)
        d = positive(distance, "distance")
        with np.errstate(over="ignore", invalid="ignore"):
            new_eye = new_target + d * unit(offset, "eye - target")
        if not np.all(np.isfinite(new_eye)):
            raise ValueError(f"distance {d:g} is too large: the eye's coordinates overflow float64")
        if np.array_equal(new_eye, new_target):
            raise ValueError(f"distance {d:g} is too small: the eye falls on the target in float64")
    with np.errstate(over="ignore", invalid="ignore"):
        d = length(new_eye - np.array(point(center, "center")))
    r = positive(radius, "radius")
    if not math.isfinite(d + 2.0 * r):
        raise ValueError("the eye is too far from the model: its distance overflows float64")
    auto_near = max(d - r, 1e-3 * r) / 2.0
    return replace(cam, eye=tuple(new_eye), target=tuple(new_target),
                   up=cam.up if up is None else up,
                   near=auto_near if near is None else near,
                   far=d + 2.0 * r if far is None else far,
                   aperture=aperture, focus_distance=focus_distance)
