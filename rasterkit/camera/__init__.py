"""The camera: the lecture's camera transformation, factor by factor, and every projection.

A perspective camera maps world points to homogeneous raster space with the chain

    K = Raster · S_raster · P_parallel · P_persp · S_far · S_xy · H · R · T

(rightmost applied first); a parallel (orthographic, axonometric or oblique) camera with

    K = Raster · S_raster · P_parallel · S_xyz · T_near · R · T.

The package, one part per module:

- ``chain``: each factor made by its own small function, named as in the lecture, and the
  two chains built from a camera's parameters;
- ``projections``: :data:`PROJECTIONS`, the framing of a bounding sphere, and the
  axonometric, oblique and 1/2/3-point presets;
- ``rays``: the lecture's ray-tracer camera, the ray through a raster point;
- ``lens``: the thin lens and the per-sample matrices of a multi-sample render (sub-pixel
  jitter and lens points as window shifts, so the shear H does real work), and vignetting;
- ``opencv``, ``opengl``: OpenCV's K, R, t (and distortion coefficients), OpenGL's
  projection and view matrices and trimesh / pyrender poses, in and out; ``interop``: their
  ``Camera`` methods;
- ``checks``: the rules for a valid camera;
- ``camera``: the ``Camera`` object, which validates its fields and ties the others together.

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

from rasterkit.camera.camera import Camera
from rasterkit.camera.checks import Vec3  # noqa: F401  (importable from rasterkit.camera)
from rasterkit.camera.projections import ISOMETRIC_ELEVATION, PROJECTIONS  # noqa: F401  (likewise)

__all__ = ["Camera", "PROJECTIONS"]
