"""The viewer's camera control: an eye orbiting a target, moved by the mouse.

:class:`Orbit` is the state (target, distance, azimuth, elevation) and its moves; it turns into
a :class:`rasterkit.View` with an explicit ``eye``, ``target`` and ``up`` (:meth:`Orbit.view`),
so the command line's ``--eye --target --up --fov`` flags reproduce a viewer's frame exactly.

Angles are in degrees, as the command line's: the azimuth turns about +Y from +Z towards +X,
the elevation is above the horizon (the world's +Y is up). The camera moves the way the mouse
does: dragging right raises the azimuth, dragging up raises the elevation.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

__all__ = ["MAX_ELEVATION", "Orbit"]

#: The elevation stays within this many degrees of the horizon (at 90 the view direction
#: would be parallel to the up vector and the camera's frame undefined).
MAX_ELEVATION = 89.0
#: Degrees the eye turns for a drag over the image's whole height.
TURN_PER_HEIGHT = 180.0
#: How much one wheel step (one notch, 100 units of a browser's ``deltaY``) moves the eye
#: towards the target: its distance times 1.1 (away) or divided by it (towards).
ZOOM_PER_STEP = 1.1
#: The range of distances, as multiples of the model's radius (beyond them the clipping
#: planes, chosen around the model, would lose it).
MIN_DISTANCE, MAX_DISTANCE = 1e-3, 1e4

_UP = (0.0, 1.0, 0.0)


@dataclass(frozen=True)
class Orbit:
    """An eye at ``distance`` from ``target``, seen from (``azimuth``, ``elevation``) degrees;
    ``radius``: the model's (the range of distances and pans scale with it); ``home``: the
    orbit that :meth:`reframe` returns to."""

    target: tuple
    distance: float
    azimuth: float
    elevation: float
    radius: float
    home: Orbit | None = None

    @classmethod
    def around(cls, eye, target, radius: float) -> Orbit:
        """The orbit of an eye at ``eye`` looking at ``target`` (its home as well)."""
        offset = np.subtract(np.asarray(eye, np.float64), np.asarray(target, np.float64))
        distance = float(np.linalg.norm(offset))
        if not distance > 0.0 or not math.isfinite(distance):
            raise ValueError("the eye must differ from the target")
        elevation = math.degrees(math.asin(max(-1.0, min(1.0, offset[1] / distance))))
        azimuth = math.degrees(math.atan2(offset[0], offset[2]))
        orbit = cls(tuple(float(c) for c in target), distance, azimuth,
                    max(-MAX_ELEVATION, min(MAX_ELEVATION, elevation)), float(radius))
        return replace(orbit, home=orbit)

    @property
    def eye(self) -> tuple:
        """The eye's position, world space."""
        az, el = math.radians(self.azimuth), math.radians(self.elevation)
        direction = (math.cos(el) * math.sin(az), math.sin(el), math.cos(el) * math.cos(az))
        return tuple(t + self.distance * d for t, d in zip(self.target, direction))

    def view(self, base):
        """``base`` (a :class:`rasterkit.View`) looking from :attr:`eye` at :attr:`target`."""
        return base.replace(eye=self.eye, target=self.target, up=_UP, distance=None)

    def turn(self, dx: float, dy: float, height: int) -> Orbit:
        """Dragged by (dx, dy) pixels (x right, y down) in an image ``height`` pixels high."""
        scale = TURN_PER_HEIGHT / max(height, 1)
        azimuth = math.remainder(self.azimuth + dx * scale, 360.0)
        elevation = max(-MAX_ELEVATION, min(MAX_ELEVATION, self.elevation - dy * scale))
        return replace(self, azimuth=azimuth, elevation=elevation)

    def pan(self, dx: float, dy: float, height: int, fov: float) -> Orbit:
        """Shifted by (dx, dy) pixels: the point under the mouse at the target's depth follows
        it (``fov``: the vertical field of view, degrees)."""
        per_pixel = 2.0 * self.distance * math.tan(math.radians(fov) / 2.0) / max(height, 1)
        az, el = math.radians(self.azimuth), math.radians(self.elevation)
        right = (math.cos(az), 0.0, -math.sin(az))
        up = (-math.sin(el) * math.sin(az), math.cos(el), -math.sin(el) * math.cos(az))
        target = tuple(t - per_pixel * (dx * r - dy * u) for t, r, u in zip(self.target, right, up))
        limit = MAX_DISTANCE * self.radius
        if not all(math.isfinite(c) and abs(c) <= limit + abs(h) for c, h in zip(target, self.home_target)):
            return self
        return replace(self, target=target)

    def zoom(self, steps: float) -> Orbit:
        """``steps`` wheel notches away from the target (negative: towards it)."""
        distance = self.distance * ZOOM_PER_STEP ** max(-50.0, min(50.0, steps))
        distance = max(MIN_DISTANCE * self.radius, min(MAX_DISTANCE * self.radius, distance))
        return replace(self, distance=distance)

    def reframe(self) -> Orbit:
        """Back to the orbit this one started from."""
        return self if self.home is None else replace(self.home, home=self.home)

    @property
    def home_target(self) -> tuple:
        return (self.home or self).target
