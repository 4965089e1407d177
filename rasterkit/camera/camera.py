"""The ``Camera``: an immutable perspective or parallel camera and what it computes.

The object ties the package together: its fields are checked by :mod:`.checks`; its
constructors frame a bounding sphere with :mod:`.projections`; :meth:`Camera.chain` lists the
lecture's factors from :mod:`.chain` and :meth:`Camera.ray` gives the rays of :mod:`.rays`.
The conventions are in the docstring of :mod:`rasterkit.camera`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from typing import Sequence

import numpy as np

from rasterkit.transform import compose, from_homogeneous, to_homogeneous
from rasterkit.camera import projections
from rasterkit.camera.chain import camera_frame, parallel_chain, perspective_chain
from rasterkit.camera.checks import KINDS, Vec3, camera_fields, check_matrix
from rasterkit.camera.interop import Interop
from rasterkit.camera.presets import NamedProjections
from rasterkit.camera.rays import parallel_ray, perspective_ray, window_coordinates


@dataclass(frozen=True, kw_only=True)
class Camera(NamedProjections, Interop):
    """An immutable pinhole or thin-lens (perspective) or parallel camera.

    Build cameras with the classmethods (``look_at``, ``orthographic``, ``frame``, the
    axonometric, oblique and 1/2/3-point presets, whose geometry is explained in
    :mod:`rasterkit.camera.projections`; ``from_opencv``, ``from_opengl``, ``from_pose``
    of :mod:`rasterkit.camera.interop`); the constructor validates every field, raising
    ``TypeError`` for what is not a real number (a string, a bool, None, arrays of them) and
    ``ValueError`` for values out of range, and makes the world -> raster matrix once: a
    camera whose matrix is not finite in float64 (sizes and distances too large or too
    small next to each other) is refused with one line.

    Attributes
    ----------
    kind : {'perspective', 'parallel'}
        Perspective: projectors meet in the eye. Parallel: projectors are parallel
        (orthographic, axonometric, or oblique when ``oblique_ratio > 0``).
    eye, target, up : tuple of 3 float
        World-space eye point, point looked at, and up direction (any length, not parallel
        to the view direction; the camera's +y is up made orthogonal to the view direction).
    width, height : int
        Image size in pixels, 1 to :data:`rasterkit.options.MAX_IMAGE_SIZE`.
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
    aperture : float
        Perspective only: diameter of the thin lens, world units; 0 (the default) is the
        pinhole camera. Only :func:`rasterkit.render` with ``samples > 1`` uses it (depth of
        field, :mod:`rasterkit.camera.lens`); the chain and :meth:`ray` are the pinhole's.
    focus_distance : float or None
        Perspective only: distance of the plane in focus from the eye along the viewing
        direction, world units; None: the distance to ``target``.
    pixel_aspect : float
        Width over height of a pixel's footprint in the scene (OpenCV's ``fy/fx``): the
        window is ``pixel_aspect·width/height`` times as wide as it is high. 1: square.
    distortion : tuple of float
        Perspective only: OpenCV's lens distortion coefficients (k1, k2, p1, p2[, k3[, k4,
        k5, k6]]), or () for none; :func:`rasterkit.render` draws the distorted image
        (:mod:`rasterkit.raster.distortion`), while :meth:`matrix`, :meth:`project` and
        :meth:`ray` stay the pinhole's.
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
    aperture: float = 0.0
    focus_distance: float | None = None
    pixel_aspect: float = 1.0
    distortion: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        checked = camera_fields(**{f.name: getattr(self, f.name) for f in fields(self)})
        for name, value in checked.items():
            object.__setattr__(self, name, value)
        with np.errstate(all="ignore"):
            check_matrix(self.world_to_raster(), self)  # made now, once, to be checked

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
        aperture: float = 0.0,
        focus_distance: float | None = None,
    ) -> Camera:
        """Perspective camera at ``eye`` looking at ``target``.

        ``fov_y`` is the vertical field of view in degrees; ``shift`` moves the window off
        centre in units of its half width and half height; ``aperture`` (lens diameter) and
        ``focus_distance`` (default: the distance to ``target``) make it a thin-lens camera
        (see the class docstring). Raises ``ValueError`` for invalid values.
        """
        return cls(kind="perspective", eye=eye, target=target, up=up, fov_y=fov_y,
                   width=width, height=height, near=near, far=far, shift=shift,
                   aperture=aperture, focus_distance=focus_distance)

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
        aperture: float = 0.0,
        focus_distance: float | None = None,
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
        aperture, focus_distance : float
            The lens of a perspective camera (see the class docstring).
        """
        if projection not in KINDS:
            raise ValueError(f"projection must be 'perspective' or 'parallel', got {projection!r}")
        return cls(**projections.framing(center, radius, azimuth, elevation, width, height,
                                         fov_y=fov_y if projection == "perspective" else None),
                   aperture=aperture, focus_distance=focus_distance)

    @classmethod
    def preset(
        cls, projection: str, center: Sequence[float], radius: float, *,
        width: int = 640, height: int = 480, azimuth: float = 30.0, elevation: float = 20.0,
        fov_y: float = 45.0, distance: float | None = None, eye: Sequence[float] | None = None,
        target: Sequence[float] | None = None, up: Sequence[float] | None = None,
        near: float | None = None, far: float | None = None, aperture: float = 0.0,
        focus_distance: float | None = None,
    ) -> Camera:
        """The camera of a projection named in :data:`PROJECTIONS`, framing a bounding sphere.

        ``'perspective'`` and ``'orthographic'`` look from (``azimuth``, ``elevation``) as
        :meth:`frame` does; the other names are the axonometric, oblique and 1/2/3-point
        presets (they choose their own view direction). Then, in this order: ``distance``
        moves the eye along its line to that distance from the target; ``eye``, ``target``
        and ``up`` replace those of the framed camera; ``near`` and ``far`` replace the
        clipping distances, which otherwise enclose the sphere as seen from the final eye.
        A parallel camera keeps its view box whatever the distance. ``aperture`` and
        ``focus_distance`` (None: the final distance to the target) give the lens.
        """
        return projections.preset(
            cls, projection, center, radius, width=width, height=height, azimuth=azimuth,
            elevation=elevation, fov_y=fov_y, distance=distance, eye=eye, target=target, up=up,
            near=near, far=far, aperture=aperture, focus_distance=focus_distance)

    def with_size(self, width: int, height: int) -> Camera:
        """A copy with another image size (the vertical extent of the view and the lens are kept)."""
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
        return camera_frame(self.eye, self.target, self.up)

    def _half_window(self) -> tuple[float, float]:
        """Half width and half height of the window: at distance 1 (perspective), or world units."""
        if self.kind == "perspective":
            half_height = math.tan(math.radians(self.fov_y) / 2.0)
        else:
            half_height = self.view_height / 2.0
        return self.aspect * self.pixel_aspect * half_height, half_height

    def _target_distance(self) -> float:
        return float(np.linalg.norm(np.subtract(self.target, self.eye)))

    def _oblique_offsets(self) -> tuple[float, float]:
        """(k_x, k_y): image offset (x, y up) per world unit of depth, zero unless oblique."""
        return projections.oblique_offsets(self.oblique_angle, self.oblique_ratio)

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
        frame = dict(eye=np.asarray(self.eye), basis=self.basis(), half_window=self._half_window(),
                     near=self.near, far=self.far, width=self.width, height=self.height)
        if self.kind == "perspective":
            return perspective_chain(**frame, shift=self.shift)
        return parallel_chain(**frame, oblique=self._oblique_offsets(),
                              target_distance=self._target_distance())

    def matrix(self) -> np.ndarray:
        """K, the product of :meth:`chain`: world -> homogeneous raster space, (4, 4) float64."""
        return self.world_to_raster().copy()

    def world_to_raster(self) -> np.ndarray:
        """K of :meth:`matrix` without the copy: computed once per camera and read-only.

        A camera never changes, so a renderer drawing many frames with one camera does not
        compose the chain again. (4, 4) float64, not writeable.
        """
        return self._cached("_cached_matrix", lambda: compose(*(m for _, m in self.chain())))

    def backward(self) -> np.ndarray:
        """``w`` of :meth:`basis`: the unit vector from the target to the eye, world space.

        Computed once per camera; (3,) float64, not writeable.
        """
        return self._cached("_cached_backward", lambda: self.basis()[2])

    def rotation(self) -> np.ndarray:
        """The world -> camera rotation: the rows are ``u, v, w`` of :meth:`basis`.

        Computed once per camera (the vision maps turn normals by it every frame); (3, 3)
        float64, not writeable.
        """
        return self._cached("_cached_rotation", lambda: np.stack(self.basis()))

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
        with np.errstate(over="ignore", invalid="ignore"):  # beyond float64: inf, as IEEE gives it
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
        with np.errstate(over="ignore", invalid="ignore"):
            return from_homogeneous(self.project_h(points))

    def ray(self, x: float | np.ndarray, y: float | np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The world-space ray through raster point (x, y): the lecture's ray-tracer camera.

        ``r(t) = origin + t·direction``. A perspective camera's rays start at the eye; a
        parallel camera's rays are parallel and start on the near plane. The derivation is in
        :mod:`rasterkit.camera.rays`.

        Parameters
        ----------
        x, y : float or array_like
            Raster coordinates in pixels (broadcast together).

        Returns
        -------
        origin, direction : float64 ndarray, shape (..., 3)
            World-space origin and unit direction; t in r(t) is in world units.
        """
        a, b = window_coordinates(x, y, self.width, self.height)
        frame = dict(eye=np.asarray(self.eye), basis=self.basis(), half_window=self._half_window())
        if self.kind == "perspective":
            o, d = perspective_ray(a, b, **frame, shift=self.shift)
        else:
            o, d = parallel_ray(a, b, **frame, oblique=self._oblique_offsets(), near=self.near,
                                target_distance=self._target_distance())
        return o.copy(), d / np.linalg.norm(d, axis=-1, keepdims=True)
