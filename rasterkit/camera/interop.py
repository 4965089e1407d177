"""Cameras of other conventions in and out: OpenCV (K, R, t, distortion), OpenGL (projection
and view matrices) and trimesh / pyrender poses.

:class:`Interop` is a base of :class:`rasterkit.camera.Camera` that holds only these
methods; the conversions are in :mod:`rasterkit.camera.opencv` and
:mod:`rasterkit.camera.opengl`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Sequence

import numpy as np

from rasterkit.camera import opencv, opengl

if TYPE_CHECKING:
    from rasterkit.camera.camera import Camera


class Interop:
    """Constructors from, and exports to, OpenCV and OpenGL cameras and poses."""

    @classmethod
    def from_opencv(cls, K, R, t, width: int, height: int, near: float = 0.1, far: float = 100.0,
                    dist: Sequence[float] | None = None) -> Camera:
        """The camera of OpenCV's pinhole model: ``x_cam = R @ x_world + t`` (x right, y down,
        z forward), ``u = fx·x/z + cx``, ``v = fy·y/z + cy`` with pixel centres at integers.

        A world point lands at raster ``(u + 0.5, v + 0.5)`` (rasterkit's pixel centres lie
        at +0.5). The principal point becomes the window ``shift``, ``fy/fx`` the
        ``pixel_aspect``; K with a skew is refused.

        Parameters
        ----------
        K : (3, 3) array_like
            ``[[fx, 0, cx], [0, fy, cy], [0, 0, 1]]``, pixels.
        R : (3, 3) array_like
            World -> camera rotation (determinant +1).
        t : (3,) array_like
            World -> camera translation, world units.
        width, height : int
            Image size in pixels.
        near, far : float
            Clipping distances along the optical axis, world units.
        dist : sequence of 4, 5 or 8 float, optional
            OpenCV's distortion coefficients (k1, k2, p1, p2[, k3[, k4, k5, k6]]): a render
            shows the distorted image (:mod:`rasterkit.raster.distortion`).
        """
        return cls(**opencv.from_opencv(K, R, t, width, height, near, far, dist))

    def to_opencv(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(K, R, t) of OpenCV's model for this perspective camera (:meth:`from_opencv`'s
        inverse); the distortion coefficients are :attr:`distortion`."""
        return opencv.to_opencv(self)

    @classmethod
    def from_opengl(cls, projection, view, width: int, height: int) -> Camera:
        """The camera of OpenGL matrices: ``projection`` a ``glFrustum`` / ``gluPerspective``
        (any window shift) or centred ``glOrtho`` matrix, ``view`` the rigid world -> eye
        transform, both (4, 4) for column vectors (:mod:`rasterkit.camera.opengl`)."""
        return cls(**opengl.from_opengl(projection, view, width, height))

    def opengl_matrices(self) -> tuple[np.ndarray, np.ndarray]:
        """(projection, view), (4, 4) float64 each, in OpenGL's convention (NDC z in [-1, 1]):
        what :meth:`from_opengl` takes back."""
        return opengl.opengl_matrices(self)

    @classmethod
    def from_pose(cls, pose, fov_y: float = 45.0, width: int = 640, height: int = 480,
                  near: float = 0.1, far: float = 100.0, K=None) -> Camera:
        """A perspective camera at a trimesh / pyrender pose: the camera -> world (4, 4)
        matrix of a camera node, OpenGL axes (looking down the pose's -z column, its y column
        up). ``fov_y`` in degrees (pyrender's ``yfov`` is in radians); or ``K``, OpenCV's
        intrinsic matrix (pyrender's ``IntrinsicsCamera(fx, fy, cx, cy)``), in its place.

        Examples
        --------
        >>> import numpy as np
        >>> from rasterkit import Camera
        >>> pose = np.eye(4); pose[:3, 3] = (0, 0, 3)   # 3 units back, looking down -z
        >>> cam = Camera.from_pose(pose, fov_y=60.0)
        >>> bool(np.allclose(cam.pose(), pose))
        True
        """
        if K is not None:
            view = np.linalg.inv(opengl.pose_matrix(pose))
            flip = np.diag([1.0, -1.0, -1.0])  # OpenGL's camera axes -> OpenCV's (y down, z ahead)
            return cls.from_opencv(K, flip @ view[:3, :3], flip @ view[:3, 3], width, height, near, far)
        eye, target, up = opengl.from_pose(pose)
        return cls(kind="perspective", eye=eye, target=target, up=up, fov_y=fov_y, width=width,
                   height=height, near=near, far=far)

    def pose(self) -> np.ndarray:
        """The camera -> world pose (4, 4) float64 of trimesh and pyrender: columns right,
        up, backward and the eye (the inverse of :meth:`view_matrix`)."""
        return opengl.pose(self)
