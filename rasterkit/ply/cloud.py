"""``PointCloud``: what a PLY file without faces holds, ready to be drawn by
:func:`rasterkit.render` (``points=``, with per-point ``point_color``)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rasterkit.mesh import Mesh, seal
from rasterkit.mesh.checks import check_unit_colors, checked_array

__all__ = ["PointCloud"]


@dataclass(frozen=True, eq=False)
class PointCloud:
    """Points with optional colours and normals. Immutable: its arrays are read-only.

    Attributes
    ----------
    points : (N, 3) float64
        Positions in object space (NaN and infinite ones too: :func:`rasterkit.render`
        skips them).
    colors : (N, 3) float32 in [0, 1], or None
    normals : (N, 3) float64, or None
    warnings : tuple of str
        What the reader noticed but accepted.

    Drawing it: ``rasterkit.render(None, camera, **cloud.render_arguments())`` (or with a
    mesh), which passes ``points`` and, when the cloud has colours, ``point_color`` as
    (N, 3) values 0 to 255, the form ``render`` takes per-point colours in.

    Examples
    --------
    >>> cloud = PointCloud(np.zeros((2, 3)), colors=np.array([[1, 0, 0], [0, 0, 1]], np.float32))
    >>> sorted(cloud.render_arguments())
    ['point_color', 'points']
    >>> cloud.render_arguments()["point_color"]
    array([[255.,   0.,   0.],
           [  0.,   0., 255.]], dtype=float32)
    """

    points: np.ndarray
    colors: np.ndarray | None = None
    normals: np.ndarray | None = None
    warnings: tuple = ()

    def __post_init__(self):
        points = checked_array(self.points, np.float64, (3,), "points")
        n = len(points)
        set_ = object.__setattr__
        set_(self, "points", seal(points))
        if self.colors is not None:
            colors = checked_array(self.colors, np.float32, (3,), "colors", n)
            check_unit_colors(colors, "colors")
            set_(self, "colors", seal(colors))
        if self.normals is not None:
            set_(self, "normals", seal(checked_array(self.normals, np.float64, (3,), "normals", n)))
        set_(self, "warnings", tuple(self.warnings))

    def render_arguments(self) -> dict:
        """``{"points": ..., "point_color": ...}`` for :func:`rasterkit.render` (no
        ``point_color`` without colours: the render's own then)."""
        arguments = {"points": self.points}
        if self.colors is not None:
            arguments["point_color"] = self.colors * np.float32(255.0)
        return arguments

    @property
    def bounds(self) -> np.ndarray:
        """(2, 3) float64: minimum and maximum corner of the finite points' bounding box."""
        return self.as_mesh().bounds

    def bounding_sphere(self) -> tuple[np.ndarray, float]:
        """Centre (3,) and radius of a sphere holding every finite point, as
        :meth:`rasterkit.Mesh.bounding_sphere` (to frame a camera on it)."""
        return self.as_mesh().bounding_sphere()

    def as_mesh(self) -> Mesh:
        """A :class:`rasterkit.Mesh` of the points and no faces (sharing the sealed points, no
        copy): what a render draws the points with, and its framing helpers."""
        return Mesh(self.points, np.zeros((0, 3), np.int64))

    def __len__(self) -> int:
        return len(self.points)

    def __repr__(self) -> str:
        extras = [name for name in ("colors", "normals") if getattr(self, name) is not None]
        return f"PointCloud({len(self.points)} points{''.join(', ' + e for e in extras)})"
