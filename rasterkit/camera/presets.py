"""The named projections of the lecture as ``Camera`` constructors: axonometric (isometric,
dimetric, trimetric), oblique (cavalier, cabinet) and 1/2/3-point perspective.

:class:`NamedProjections` is a base of :class:`rasterkit.camera.Camera` that holds only these
classmethods; the geometry of each (view direction, window, oblique shear) is in
:mod:`rasterkit.camera.projections`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Sequence

from rasterkit.camera import projections

if TYPE_CHECKING:
    from rasterkit.camera.camera import Camera


class NamedProjections:
    """The projection presets, each framing a bounding sphere (``center``, ``radius``)."""

    @classmethod
    def isometric(
        cls, center: Sequence[float] = (0.0, 0.0, 0.0), radius: float = 1.0, *,
        width: int = 640, height: int = 480,
    ) -> Camera:
        """Isometric view: looks along a cube diagonal, (-1, -1, -1)."""
        return cls(**projections.isometric(center, radius, width, height))

    @classmethod
    def dimetric(
        cls, center: Sequence[float] = (0.0, 0.0, 0.0), radius: float = 1.0, *,
        elevation: float = 20.0, width: int = 640, height: int = 480,
    ) -> Camera:
        """Dimetric view: azimuth 45°, so x and z are foreshortened equally, y differently."""
        return cls(**projections.dimetric(center, radius, elevation, width, height))

    @classmethod
    def trimetric(
        cls, center: Sequence[float] = (0.0, 0.0, 0.0), radius: float = 1.0, *,
        azimuth: float = 30.0, elevation: float = 20.0, width: int = 640, height: int = 480,
    ) -> Camera:
        """Trimetric view: a view direction that foreshortens the three axes differently."""
        return cls(**projections.trimetric(center, radius, azimuth, elevation, width, height))

    @classmethod
    def oblique(
        cls, angle: float = 45.0, ratio: float = 1.0, center: Sequence[float] = (0.0, 0.0, 0.0),
        radius: float = 1.0, *, azimuth: float = 0.0, elevation: float = 0.0,
        width: int = 640, height: int = 480,
    ) -> Camera:
        """Oblique parallel projection: the receding axis drawn ``ratio`` long at ``angle``°."""
        return cls(**projections.oblique(angle, ratio, center, radius, azimuth, elevation,
                                         width, height))

    @classmethod
    def cavalier(
        cls, center: Sequence[float] = (0.0, 0.0, 0.0), radius: float = 1.0, *,
        angle: float = 45.0, width: int = 640, height: int = 480,
    ) -> Camera:
        """Cavalier projection: oblique, the receding axis keeps its full length (ratio 1)."""
        return cls(**projections.cavalier(center, radius, angle, width, height))

    @classmethod
    def cabinet(
        cls, center: Sequence[float] = (0.0, 0.0, 0.0), radius: float = 1.0, *,
        angle: float = 45.0, width: int = 640, height: int = 480,
    ) -> Camera:
        """Cabinet projection: oblique, the receding axis is drawn at half length (ratio 1/2)."""
        return cls(**projections.cabinet(center, radius, angle, width, height))

    @classmethod
    def one_point(
        cls, center: Sequence[float] = (0.0, 0.0, 0.0), radius: float = 1.0, *,
        fov_y: float = 45.0, width: int = 640, height: int = 480,
    ) -> Camera:
        """One-point perspective: looks along -Z with up +Y."""
        return cls(**projections.one_point(center, radius, fov_y, width, height))

    @classmethod
    def two_point(
        cls, center: Sequence[float] = (0.0, 0.0, 0.0), radius: float = 1.0, *,
        azimuth: float = 30.0, fov_y: float = 45.0, width: int = 640, height: int = 480,
    ) -> Camera:
        """Two-point perspective: yawed about Y by ``azimuth`` (not a multiple of 90°), level."""
        return cls(**projections.two_point(center, radius, azimuth, fov_y, width, height))

    @classmethod
    def three_point(
        cls, center: Sequence[float] = (0.0, 0.0, 0.0), radius: float = 1.0, *,
        azimuth: float = 30.0, elevation: float = 25.0, fov_y: float = 45.0,
        width: int = 640, height: int = 480,
    ) -> Camera:
        """Three-point perspective: yawed (``azimuth``) and pitched (``elevation`` != 0)."""
        return cls(**projections.three_point(center, radius, azimuth, elevation, fov_y,
                                             width, height))
