"""Backface culling as the sign of the screen-space signed area.

The lecture's test keeps a face when its normal points towards the viewer, ``n · v > 0``.
After projection the same test is the winding of the projected triangle: a face whose
vertices run counter-clockwise seen from outside (right-handed world, the OBJ convention)
is front-facing. It still looks counter-clockwise to a person looking at the image, but
raster y points *down*, so the usual formula evaluated on raster coordinates

    area2 = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)      (raster x, y)

(twice the signed area) is **negative** for a front face and positive for a back face.
The sign is taken after clipping, on the fixed-point vertices the rasterizer uses, so it is
exact and agrees with what gets drawn.
"""

from __future__ import annotations

import numpy as np
from numba import types
from numba.extending import overload

from rasterkit.runtime.jit import kernel

#: Cull modes, as passed to the kernels (the Python layer maps "none"/"back"/"front").
CULL_NONE = 0
CULL_BACK = 1
CULL_FRONT = 2


@kernel(inline="always")
def is_front_facing(area2):
    """True when a raster-space signed area ``area2`` (see module docstring) is front-facing."""
    return area2 < 0


@kernel(inline="always")
def is_culled(area2, mode):
    """True when a triangle of raster-space signed area ``area2`` is removed by cull ``mode``.

    Parameters
    ----------
    area2 : int or float
        Twice the signed area in raster space, non-zero (zero-area triangles never get here).
    mode : int
        CULL_NONE, CULL_BACK or CULL_FRONT.
    """
    if mode == CULL_BACK:
        return not is_front_facing(area2)
    if mode == CULL_FRONT:
        return is_front_facing(area2)
    return False


def per_face(value, f):
    """``value[f]`` for a per-face array, ``value`` itself for one value every face shares.

    A render passes one cull mode (and one two-sided flag) for all its faces, except when
    some faces are double-sided and the others are not (a glTF file's materials): then an
    array with a value per face (:mod:`rasterkit.raster.sides`). The kernels read it through
    this function, so a render of one value compiles to what it was without arrays, and
    the per-face variant is compiled only for the meshes that need it."""
    return value[f] if isinstance(value, np.ndarray) else value


@overload(per_face, inline="always")
def _per_face(value, f):
    if isinstance(value, types.Array):
        return lambda value, f: value[f]
    return lambda value, f: value
