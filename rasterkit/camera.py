"""The camera: the lecture's camera transformation, factor by factor, and every projection.

A perspective camera maps world points to homogeneous raster space with the chain

    K = Raster · S_raster · P_parallel · P_persp · S_far · S_xy · H · R · T

(rightmost applied first); a parallel (orthographic, axonometric or oblique) camera with

    K = Raster · S_raster · P_parallel · S_xyz · T_near · R · T.

Each factor is made by its own small function below, named as in the lecture.

Conventions
-----------
- World space is right-handed. Camera space: the eye at the origin, looking down -z, +y up.
- ``fov_y`` is the vertical field of view in degrees.
- Raster space: origin at the top-left corner of the image, x right, y down, in pixels; the
  image covers [0, width] x [0, height] and pixel (i, j) has its centre at (i + 0.5, j + 0.5).
- Homogeneous raster space: ``K @ (x, y, z, 1) = (xh, yh, zh, w)``. After the divide,
  ``xh/w`` and ``yh/w`` are raster pixels and ``zh/w`` is the depth: 0 on the near plane,
  1 on the far plane. The near plane is ``zh = 0`` (inside: ``zh >= 0``), the far plane is
  ``zh = w``; ``w > 0`` in front of the eye (``w = 1`` for parallel cameras).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Sequence

import numpy as np

from .transform import (
    _vector3,
    compose,
    from_homogeneous,
    reflect,
    scale,
    shear,
    to_homogeneous,
    translate,
)

__all__ = ["Camera", "PROJECTIONS"]

Vec3 = tuple[float, float, float]

#: Elevation (degrees) of an isometric view: the view direction is a cube diagonal, whose
#: angle with the horizontal plane is atan(1/sqrt(2)) = 35.264°.
ISOMETRIC_ELEVATION = math.degrees(math.atan(1.0 / math.sqrt(2.0)))

_KINDS = ("perspective", "parallel")

PROJECTIONS = ("perspective", "orthographic", "isometric", "dimetric", "trimetric", "cavalier",
               "cabinet", "1-point", "2-point", "3-point")
"""Names accepted by :meth:`Camera.preset` (and the command line's ``--projection``)."""

_PRESET_METHODS = {"isometric": "isometric", "dimetric": "dimetric", "trimetric": "trimetric",
                   "cavalier": "cavalier", "cabinet": "cabinet", "1-point": "one_point",
                   "2-point": "two_point", "3-point": "three_point"}


# --- the factors of the camera transformation, one small function each -----------------------


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


# --- validation ----------------------------------------------------------------------------


def _finite(value: float, name: str) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a finite number, got {value!r}") from None
    if not math.isfinite(x):
        raise ValueError(f"{name} must be a finite number, got {value!r}")
    return x


def _positive(value: float, name: str) -> float:
    x = _finite(value, name)
    if x <= 0.0:
        raise ValueError(f"{name} must be positive, got {value!r}")
    return x


def _positive_int(value: int, name: str) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value <= 0:
        raise ValueError(f"{name} must be a positive integer, got {value!r}")
    return int(value)


def _fov(value: float) -> float:
    x = _finite(value, "fov_y")
    if not 0.0 < x < 180.0:
        raise ValueError(f"fov_y must lie strictly between 0 and 180 degrees, got {value!r}")
    return x


def _point(value: Sequence[float], name: str) -> Vec3:
    x, y, z = _vector3(value, name)
    return (float(x), float(y), float(z))


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


def _orbit_direction(azimuth: float, elevation: float) -> np.ndarray:
    """Unit vector from the target to the eye: azimuth about +Y from +Z towards +X, elevation up."""
    az = math.radians(_finite(azimuth, "azimuth"))
    el = math.radians(_finite(elevation, "elevation"))
    if not abs(el) < math.pi / 2:
        raise ValueError(
            f"elevation must lie strictly between -90 and 90 degrees, got {elevation!r}")
    return np.array([math.cos(el) * math.sin(az), math.sin(el), math.cos(el) * math.cos(az)])


def _oblique_offsets(angle: float, ratio: float) -> tuple[float, float]:
    """Image offset (x, y up) per world unit of depth behind the image plane, world units."""
    angle = math.radians(_finite(angle, "oblique_angle"))
    ratio = _finite(ratio, "oblique_ratio")
    return ratio * math.cos(angle), ratio * math.sin(angle)


def _require_off_axis_view(azimuth: float, elevation: float | None, preset: str) -> None:
    """The 2- and 3-point presets need views that are not aligned with the world axes."""
    if _finite(azimuth, "azimuth") % 90.0 == 0.0:
        raise ValueError(
            f"{preset} needs an azimuth that is not a multiple of 90°, got {azimuth!r}")
    if elevation is not None and _finite(elevation, "elevation") == 0.0:
        raise ValueError(f"{preset} needs a non-zero elevation")


# --- the camera ----------------------------------------------------------------------------


@dataclass(frozen=True, kw_only=True)
class Camera:
    """An immutable pinhole (perspective) or parallel camera.

    Build cameras with the classmethods (``look_at``, ``orthographic``, ``frame``, the
    axonometric, oblique and 1/2/3-point presets); the constructor validates every field.

    Attributes
    ----------
    kind : {'perspective', 'parallel'}
        Perspective: projectors meet in the eye. Parallel: projectors are parallel
        (orthographic, axonometric, or oblique when ``oblique_ratio > 0``).
    eye, target, up : tuple of 3 float
        World-space eye point, point looked at, and up direction (any length, not parallel
        to the view direction; the camera's +y is up made orthogonal to the view direction).
    width, height : int
        Image size in pixels.
    near, far : float
        Distances of the near and far planes from the eye along the view direction,
        ``0 < near < far``, world units.
    fov_y : float or None
        Perspective only: vertical field of view in degrees, 0 < fov_y < 180. It sets the
        window size: ``2·tan(fov_y/2)`` high at distance 1.
    shift : tuple of 2 float
        Perspective only: window shift (off-centre window, asymmetric frustum) in units of
        the half window width and height; (1, 0) moves the window right by half its width.
        A non-zero shift makes the lecture's shear H a real shear.
    view_height : float or None
        Parallel only: height of the view box in world units (its width is
        ``view_height·width/height``).
    oblique_angle, oblique_ratio : float
        Parallel only: the image of a unit vector pointing straight away from the viewer
        (the receding axis) has length ``oblique_ratio`` (world units) and makes the angle
        ``oblique_angle`` (degrees, counter-clockwise, y up) with the image's x axis. Ratio 0
        is an orthographic camera; 1 is cavalier, 1/2 cabinet.
    """

    kind: str
    eye: Vec3
    target: Vec3
    up: Vec3 = (0.0, 1.0, 0.0)
    width: int = 640
    height: int = 480
    near: float = 0.1
    far: float = 100.0
    fov_y: float | None = None
    shift: tuple[float, float] = (0.0, 0.0)
    view_height: float | None = None
    oblique_angle: float = 0.0
    oblique_ratio: float = 0.0

    def __post_init__(self) -> None:
        if self.kind not in _KINDS:
            raise ValueError(f"kind must be 'perspective' or 'parallel', got {self.kind!r}")
        fields = dict(
            eye=_point(self.eye, "eye"),
            target=_point(self.target, "target"),
            up=_point(self.up, "up"),
            width=_positive_int(self.width, "width"),
            height=_positive_int(self.height, "height"),
            near=_positive(self.near, "near"),
            far=_positive(self.far, "far"),
            shift=self._valid_shift(),
            oblique_angle=_finite(self.oblique_angle, "oblique_angle"),
            oblique_ratio=_finite(self.oblique_ratio, "oblique_ratio"),
        )
        for name, value in fields.items():
            object.__setattr__(self, name, value)
        if not self.near < self.far:
            raise ValueError(f"near must be smaller than far, got near={self.near}, far={self.far}")
        self._check_frame()
        if self.kind == "perspective":
            self._check_perspective()
        else:
            self._check_parallel()

    def _valid_shift(self) -> tuple[float, float]:
        if np.shape(self.shift) != (2,):
            raise ValueError(f"shift must be 2 finite numbers, got {self.shift!r}")
        return (_finite(self.shift[0], "shift[0]"), _finite(self.shift[1], "shift[1]"))

    def _check_frame(self) -> None:
        view = np.subtract(self.target, self.eye)
        if not np.any(view):
            raise ValueError("eye and target must differ")
        up = np.asarray(self.up)
        if not np.any(up):
            raise ValueError("up must not be the zero vector")
        if np.linalg.norm(np.cross(_unit(up), _unit(view))) < 1e-9:
            raise ValueError("up must not be parallel to the view direction (target - eye)")

    def _check_perspective(self) -> None:
        if self.fov_y is None:
            raise ValueError("a perspective camera needs fov_y")
        object.__setattr__(self, "fov_y", _fov(self.fov_y))
        if self.view_height is not None or self.oblique_ratio != 0.0:
            raise ValueError("view_height and oblique_ratio belong to parallel cameras")

    def _check_parallel(self) -> None:
        if self.view_height is None:
            raise ValueError("a parallel camera needs view_height")
        object.__setattr__(self, "view_height", _positive(self.view_height, "view_height"))
        if self.fov_y is not None or self.shift != (0.0, 0.0):
            raise ValueError("fov_y and shift belong to perspective cameras")
        if self.oblique_ratio < 0.0:
            raise ValueError(f"oblique_ratio must not be negative, got {self.oblique_ratio}")

    # --- constructors ----------------------------------------------------------------------

    @classmethod
    def look_at(
        cls,
        eye: Sequence[float],
        target: Sequence[float],
        up: Sequence[float] = (0.0, 1.0, 0.0),
        fov_y: float = 45.0,
        width: int = 640,
        height: int = 480,
        near: float = 0.1,
        far: float = 100.0,
        shift: Sequence[float] = (0.0, 0.0),
    ) -> Camera:
        """Perspective camera at ``eye`` looking at ``target``.

        ``fov_y`` is the vertical field of view in degrees; ``shift`` moves the window off
        centre in units of its half width and half height (see the class docstring).
        Raises ``ValueError`` for invalid values.
        """
        return cls(kind="perspective", eye=eye, target=target, up=up, fov_y=fov_y,
                   width=width, height=height, near=near, far=far, shift=shift)

    @classmethod
    def orthographic(
        cls,
        eye: Sequence[float],
        target: Sequence[float],
        up: Sequence[float] = (0.0, 1.0, 0.0),
        view_height: float = 2.0,
        width: int = 640,
        height: int = 480,
        near: float = 0.1,
        far: float = 100.0,
    ) -> Camera:
        """Orthographic camera: projectors parallel to the view direction ``target - eye``.

        The view box is ``view_height`` world units high and ``view_height·width/height``
        wide, centred on the line through eye and target, from ``near`` to ``far`` in front
        of the eye.
        """
        return cls(kind="parallel", eye=eye, target=target, up=up, view_height=view_height,
                   width=width, height=height, near=near, far=far)

    @classmethod
    def frame(
        cls,
        center: Sequence[float],
        radius: float,
        azimuth: float = 30.0,
        elevation: float = 20.0,
        fov_y: float = 45.0,
        width: int = 640,
        height: int = 480,
        projection: str = "perspective",
    ) -> Camera:
        """Camera looking at a bounding sphere that fills the view.

        The eye sits in the direction (azimuth, elevation) from ``center``: azimuth in
        degrees about +Y, from +Z towards +X; elevation in degrees upwards, strictly between
        -90 and 90; up is +Y. The sphere's image touches the edges of the narrower image
        dimension (pass a larger radius for a margin). ``near`` and ``far`` enclose the
        sphere with room to spare.

        Parameters
        ----------
        center : (3,) float
            World-space centre of the sphere.
        radius : float
            Its radius, > 0.
        projection : {'perspective', 'parallel'}
            'parallel' gives an orthographic camera (``fov_y`` is then unused).
        """
        if projection not in _KINDS:
            raise ValueError(f"projection must be 'perspective' or 'parallel', got {projection!r}")
        return cls._framed(center, radius, azimuth, elevation, width, height,
                           fov_y=fov_y if projection == "perspective" else None)

    @classmethod
    def _framed(
        cls,
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
    ) -> Camera:
        """The shared helper of ``frame`` and the presets; ``fov_y=None`` means parallel."""
        c = np.array(_point(center, "center"))
        r = _positive(radius, "radius")
        direction = _orbit_direction(azimuth, elevation)
        aspect = _positive_int(width, "width") / _positive_int(height, "height")
        kind = "perspective" if fov_y is not None else "parallel"
        view_height = None
        if fov_y is not None:
            # The silhouette cone of the sphere (half-angle asin(r/d)) meets the frustum's
            # narrower pair of side planes.
            half_angle = math.atan(math.tan(math.radians(_fov(fov_y)) / 2.0) * min(1.0, aspect))
            distance = r / math.sin(half_angle)
        else:
            # An oblique shear stretches the sphere's image to an ellipse with half axes
            # r·sqrt(1 + k²) along x and y.
            k = _oblique_offsets(oblique_angle, oblique_ratio)
            view_height = 2.0 * r * max(math.hypot(1.0, k[1]), math.hypot(1.0, k[0]) / aspect)
            distance = 2.0 * r
        return cls(kind=kind, eye=tuple(c + distance * direction), target=tuple(c),
                   width=width, height=height, near=(distance - r) / 2.0, far=distance + 2.0 * r,
                   fov_y=fov_y, view_height=view_height,
                   oblique_angle=oblique_angle, oblique_ratio=oblique_ratio)

    @classmethod
    def isometric(
        cls, center: Sequence[float] = (0.0, 0.0, 0.0), radius: float = 1.0, *,
        width: int = 640, height: int = 480,
    ) -> Camera:
        """Isometric view: looks along a cube diagonal, (-1, -1, -1).

        The three world axes are foreshortened equally (by sqrt(2/3)) and their images meet
        at 120°. Azimuth 45°, elevation atan(1/sqrt(2)) = 35.26°.
        """
        return cls._framed(center, radius, 45.0, ISOMETRIC_ELEVATION, width, height)

    @classmethod
    def dimetric(
        cls, center: Sequence[float] = (0.0, 0.0, 0.0), radius: float = 1.0, *,
        elevation: float = 20.0, width: int = 640, height: int = 480,
    ) -> Camera:
        """Dimetric view: azimuth 45°, so x and z are foreshortened equally, y differently.

        ``elevation`` (degrees) chooses the third foreshortening; at 35.26° the view is
        isometric.
        """
        return cls._framed(center, radius, 45.0, elevation, width, height)

    @classmethod
    def trimetric(
        cls, center: Sequence[float] = (0.0, 0.0, 0.0), radius: float = 1.0, *,
        azimuth: float = 30.0, elevation: float = 20.0, width: int = 640, height: int = 480,
    ) -> Camera:
        """Trimetric view: a view direction that foreshortens the three axes differently.

        The foreshortening of axis i is ``sqrt(1 - d_i²)`` for the unit view direction d;
        the default angles give 0.88 (x), 0.94 (y), 0.58 (z).
        """
        return cls._framed(center, radius, azimuth, elevation, width, height)

    @classmethod
    def oblique(
        cls, angle: float = 45.0, ratio: float = 1.0, center: Sequence[float] = (0.0, 0.0, 0.0),
        radius: float = 1.0, *, azimuth: float = 0.0, elevation: float = 0.0,
        width: int = 640, height: int = 480,
    ) -> Camera:
        """Oblique parallel projection: projectors not perpendicular to the image plane.

        Built as the orthographic chain with the oblique shear placed in P_parallel. By
        default the image plane is parallel to the world xy plane (looking down -Z) and the
        receding axis is z: a unit vector along -Z is drawn with length ``ratio`` at
        ``angle`` degrees counter-clockwise from the image's x axis, while x and y keep their
        length. The plane through ``center`` parallel to the image plane is the one the shear
        leaves in place, so the centre stays in the middle of the image.
        """
        return cls._framed(center, radius, azimuth, elevation, width, height,
                           oblique_angle=angle, oblique_ratio=ratio)

    @classmethod
    def cavalier(
        cls, center: Sequence[float] = (0.0, 0.0, 0.0), radius: float = 1.0, *,
        angle: float = 45.0, width: int = 640, height: int = 480,
    ) -> Camera:
        """Cavalier projection: oblique, the receding axis keeps its full length (ratio 1)."""
        return cls.oblique(angle, 1.0, center, radius, width=width, height=height)

    @classmethod
    def cabinet(
        cls, center: Sequence[float] = (0.0, 0.0, 0.0), radius: float = 1.0, *,
        angle: float = 45.0, width: int = 640, height: int = 480,
    ) -> Camera:
        """Cabinet projection: oblique, the receding axis is drawn at half length (ratio 1/2)."""
        return cls.oblique(angle, 0.5, center, radius, width=width, height=height)

    @classmethod
    def one_point(
        cls, center: Sequence[float] = (0.0, 0.0, 0.0), radius: float = 1.0, *,
        fov_y: float = 45.0, width: int = 640, height: int = 480,
    ) -> Camera:
        """One-point perspective: looks along -Z with up +Y.

        The image plane is parallel to the x and y axes; only lines parallel to z converge,
        to one vanishing point (the image centre).
        """
        return cls._framed(center, radius, 0.0, 0.0, width, height, fov_y=fov_y)

    @classmethod
    def two_point(
        cls, center: Sequence[float] = (0.0, 0.0, 0.0), radius: float = 1.0, *,
        azimuth: float = 30.0, fov_y: float = 45.0, width: int = 640, height: int = 480,
    ) -> Camera:
        """Two-point perspective: yawed about Y by ``azimuth`` (not a multiple of 90°), level.

        The view direction stays horizontal, so the image plane is parallel to y only: lines
        parallel to x and to z have vanishing points, verticals stay vertical.
        """
        _require_off_axis_view(azimuth, None, "two_point")
        return cls._framed(center, radius, azimuth, 0.0, width, height, fov_y=fov_y)

    @classmethod
    def three_point(
        cls, center: Sequence[float] = (0.0, 0.0, 0.0), radius: float = 1.0, *,
        azimuth: float = 30.0, elevation: float = 25.0, fov_y: float = 45.0,
        width: int = 640, height: int = 480,
    ) -> Camera:
        """Three-point perspective: yawed (``azimuth``) and pitched (``elevation`` != 0).

        The image plane is parallel to none of the axes: all three have vanishing points.
        """
        _require_off_axis_view(azimuth, elevation, "three_point")
        return cls._framed(center, radius, azimuth, elevation, width, height, fov_y=fov_y)

    @classmethod
    def preset(
        cls, projection: str, center: Sequence[float], radius: float, *,
        width: int = 640, height: int = 480, azimuth: float = 30.0, elevation: float = 20.0,
        fov_y: float = 45.0, distance: float | None = None, eye: Sequence[float] | None = None,
        target: Sequence[float] | None = None, up: Sequence[float] | None = None,
        near: float | None = None, far: float | None = None,
    ) -> Camera:
        """The camera of a projection named in :data:`PROJECTIONS`, framing a bounding sphere.

        ``'perspective'`` and ``'orthographic'`` look from (``azimuth``, ``elevation``) as
        :meth:`frame` does; the other names are the axonometric, oblique and 1/2/3-point
        presets (they choose their own view direction). Then, in this order: ``distance``
        moves the eye along its line to that distance from the target; ``eye``, ``target``
        and ``up`` replace those of the framed camera; ``near`` and ``far`` replace the
        clipping distances, which otherwise enclose the sphere as seen from the final eye.
        A parallel camera keeps its view box whatever the distance.
        """
        if projection not in PROJECTIONS:
            raise ValueError(f"projection must be one of {', '.join(PROJECTIONS)}, got {projection!r}")
        size = dict(width=width, height=height)
        if projection in ("perspective", "orthographic"):
            kind = "perspective" if projection == "perspective" else "parallel"
            cam = cls.frame(center, radius, azimuth, elevation, fov_y, projection=kind, **size)
        elif projection in ("1-point", "2-point", "3-point"):
            cam = getattr(cls, _PRESET_METHODS[projection])(center, radius, fov_y=fov_y, **size)
        else:
            cam = getattr(cls, _PRESET_METHODS[projection])(center, radius, **size)
        new_target = np.array(_point(target, "target") if target is not None else cam.target)
        new_eye = np.array(_point(eye, "eye") if eye is not None else cam.eye)
        if distance is not None and eye is None:
            offset = np.subtract(cam.eye, cam.target)
            new_eye = new_target + _positive(distance, "distance") * _unit(offset)
        d = float(np.linalg.norm(new_eye - np.array(_point(center, "center"))))
        r = _positive(radius, "radius")
        auto_near = max(d - r, 1e-3 * r) / 2.0
        return replace(cam, eye=tuple(new_eye), target=tuple(new_target),
                       up=cam.up if up is None else up,
                       near=auto_near if near is None else near,
                       far=d + 2.0 * r if far is None else far)

    def with_size(self, width: int, height: int) -> Camera:
        """A copy with another image size (the vertical extent of the view is kept)."""
        return replace(self, width=width, height=height)

    # --- geometry --------------------------------------------------------------------------

    @property
    def aspect(self) -> float:
        """width / height."""
        return self.width / self.height

    def basis(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The camera frame (u, v, w) in world space: unit right, up and backward vectors.

        ``w = (eye - target)/|eye - target|``, ``u = up × w`` normalised, ``v = w × u``.
        """
        w = _unit(np.subtract(self.eye, self.target))
        u = _unit(np.cross(self.up, w))
        return u, np.cross(w, u), w

    def _half_window(self) -> tuple[float, float]:
        """Half width and half height of the window: at distance 1 (perspective), or world units."""
        if self.kind == "perspective":
            half_height = math.tan(math.radians(self.fov_y) / 2.0)
        else:
            half_height = self.view_height / 2.0
        return self.aspect * half_height, half_height

    def _target_distance(self) -> float:
        return float(np.linalg.norm(np.subtract(self.target, self.eye)))

    # --- the chain -------------------------------------------------------------------------

    def chain(self) -> list[tuple[str, np.ndarray]]:
        """The factors of the camera transformation, first applied first.

        Perspective: T, R, H, S_xy, S_far, P_persp, P_parallel, S_raster, Raster.
        Parallel: T, R, T_near, S_xyz, P_parallel, S_raster, Raster.

        Returns
        -------
        list of (str, (4, 4) float64 ndarray)
            ``compose(*matrices)`` is :meth:`matrix`.
        """
        u, v, w = self.basis()
        view = [("T", _T(np.asarray(self.eye))), ("R", _R(u, v, w))]
        raster = [("S_raster", _S_raster(self.width, self.height)),
                  ("Raster", _Raster(self.width, self.height))]
        if self.kind == "perspective":
            return view + self._perspective_factors() + raster
        return view + self._parallel_factors() + raster

    def _perspective_factors(self) -> list[tuple[str, np.ndarray]]:
        half_w, half_h = self._half_window()
        return [
            ("H", _H(self.shift[0] * half_w, self.shift[1] * half_h)),
            ("S_xy", _S_xy(half_w, half_h)),
            ("S_far", _S_far(self.far)),
            ("P_persp", _P_persp(-self.near / self.far)),
            ("P_parallel", _P_parallel()),
        ]

    def _parallel_factors(self) -> list[tuple[str, np.ndarray]]:
        half_w, half_h = self._half_window()
        depth = self.far - self.near
        k_x, k_y = _oblique_offsets(self.oblique_angle, self.oblique_ratio)
        # The oblique offsets are per world unit of depth; the canonical volume measures
        # x, y in half windows and depth in units of (far - near).
        z_target = (self.near - self._target_distance()) / depth
        return [
            ("T_near", _T_near(self.near)),
            ("S_xyz", _S_xyz(half_w, half_h, depth)),
            ("P_parallel", _P_parallel(k_x * depth / half_w, k_y * depth / half_h, z_target)),
        ]

    def matrix(self) -> np.ndarray:
        """K, the product of :meth:`chain`: world -> homogeneous raster space, (4, 4) float64."""
        return self._matrix().copy()

    def _matrix(self) -> np.ndarray:
        """:meth:`matrix`, computed once per camera (a camera never changes) and read-only:
        a renderer drawing many frames with one camera does not compose the chain again."""
        return self._cached("_cached_matrix", lambda: compose(*(m for _, m in self.chain())))

    def _backward(self) -> np.ndarray:
        """``w`` of :meth:`basis` (unit, from the target to the eye), once per camera, read-only."""
        return self._cached("_cached_backward", lambda: self.basis()[2])

    def _cached(self, name: str, compute) -> np.ndarray:
        value = self.__dict__.get(name)
        if value is None:
            value = np.ascontiguousarray(compute(), np.float64)
            value.flags.writeable = False
            object.__setattr__(self, name, value)
        return value

    def view_matrix(self) -> np.ndarray:
        """T then R: world -> camera space (eye at the origin, looking down -z), (4, 4) float64."""
        return compose(*(m for _, m in self.chain()[:2]))

    # --- projecting points and pixel rays --------------------------------------------------

    def project_h(self, points: np.ndarray) -> np.ndarray:
        """World points to homogeneous raster space.

        Parameters
        ----------
        points : (N, 3) array_like of float
            Finite world-space points.

        Returns
        -------
        (N, 4) float64 ndarray
            (xh, yh, zh, w). A point lies in front of the eye when ``w > 0``, between the
            near and far planes when ``0 <= zh <= w``.
        """
        h = to_homogeneous(points)
        if not np.all(np.isfinite(h)):
            raise ValueError("points must be finite")
        return h @ self.matrix().T

    def project(self, points: np.ndarray) -> np.ndarray:
        """World points to raster x, y (pixels) and depth.

        Parameters
        ----------
        points : (N, 3) array_like of float
            Finite world-space points.

        Returns
        -------
        (N, 3) float64 ndarray
            Raster x (right) and y (down) in pixels, origin at the image's top-left corner,
            pixel centres at +0.5; depth in [0, 1] between the near (0) and far (1) planes.
            Points behind the eye (``w <= 0`` in :meth:`project_h`) give meaningless values.
        """
        return from_homogeneous(self.project_h(points))

    def ray(self, x: float | np.ndarray, y: float | np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The world-space ray through raster point (x, y): the lecture's ray-tracer camera.

        Window coordinates of the raster point: ``a = 2x/W - 1`` (-1 at the left edge, +1 at
        the right) and ``b = 1 - 2y/H`` (+1 at the top). With the camera frame (u, v, w) of
        :meth:`basis`:

        Perspective. Origin ``o = eye``; focal vector ``f = -w`` (the window lies at distance
        1); half window sizes ``t = tan(fov_y/2)`` and ``s = t·W/H``, giving the scaled up
        vector ``u' = t·v`` and right vector ``r' = s·u``; the window centre is
        ``f + s_x·r' + s_y·u'`` for the shift (s_x, s_y). The ray through any raster point is

            r(t) = o + t·d,   d = f + (a + s_x)·r' + (b + s_y)·u',

        and through the centre of pixel (i, j): ``a = (2i + 1)/W - 1``, ``b = 1 - (2j + 1)/H``.

        Parallel. All rays share the direction ``d = -w - k_x·u - k_y·v``, where
        ``(k_x, k_y) = ratio·(cos angle, sin angle)`` is the oblique offset per unit depth
        (zero for orthographic cameras). A ray meets the target plane (distance D from the
        eye) at the window point ``target + a·h_w·u + b·h_h·v`` (half sizes h_w, h_h in world
        units); going back to the near plane gives the origin

            o = eye - near·w + (a·h_w + k_x·(D - near))·u + (b·h_h + k_y·(D - near))·v.

        Parameters
        ----------
        x, y : float or array_like
            Raster coordinates in pixels (broadcast together).

        Returns
        -------
        origin, direction : float64 ndarray, shape (..., 3)
            World-space origin and unit direction; t in r(t) is in world units.
        """
        a = 2.0 * np.asarray(x, dtype=np.float64) / self.width - 1.0
        b = 1.0 - 2.0 * np.asarray(y, dtype=np.float64) / self.height
        a, b = np.broadcast_arrays(a, b)
        if not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
            raise ValueError("x and y must be finite")
        a, b = a[..., None], b[..., None]
        u, v, w = self.basis()
        half_w, half_h = self._half_window()
        if self.kind == "perspective":
            f, r_prime, u_prime = -w, half_w * u, half_h * v
            d = f + (a + self.shift[0]) * r_prime + (b + self.shift[1]) * u_prime
            o = np.broadcast_to(np.asarray(self.eye), d.shape)
        else:
            k_x, k_y = _oblique_offsets(self.oblique_angle, self.oblique_ratio)
            back = self._target_distance() - self.near
            o = (np.asarray(self.eye) - self.near * w
                 + (a * half_w + k_x * back) * u + (b * half_h + k_y * back) * v)
            d = np.broadcast_to(-w - k_x * u - k_y * v, o.shape)
        return o.copy(), d / np.linalg.norm(d, axis=-1, keepdims=True)

