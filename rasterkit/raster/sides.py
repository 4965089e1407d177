"""Which sides of its faces a render draws and lights: the render's ``cull``, except on the
faces of double-sided materials.

A :class:`rasterkit.Material` with ``double_sided=True`` (glTF's ``doubleSided``) is drawn
from both sides whatever ``cull`` says, and lit on both sides (``|n · l|``: the back of such
a face is lit as if its normal were turned towards the viewer, as glTF asks). ``cull="none"``
already draws and lights every face on both sides. :func:`face_sides` gives the kernels
one value for every face where it can (the ordinary compiled kernels), and an array with a
value per face only for a mesh whose faces differ
(:func:`rasterkit.raster.kernels.cull.per_face`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from rasterkit.raster.kernels.cull import CULL_NONE
from rasterkit.raster.triangle_pass import CULL_CODES
from rasterkit.runtime.jit import readonly

__all__ = ["Sides", "corner_sides", "double_sided_faces", "face_sides"]


class Sides(NamedTuple):
    """How a render treats the two sides of each face."""

    cull: str | np.ndarray
    """A name of :data:`rasterkit.options.CULL` for every face, or (M,) uint8 cull codes
    (:data:`CULL_CODES`), read-only."""
    two_sided: bool | np.ndarray
    """Whether a face is lit on both sides: one bool, or (M,) bool, read-only."""


def double_sided_faces(mesh) -> np.ndarray | None:
    """(M,) bool: the faces whose material is double-sided; None when there are none."""
    if mesh.face_materials is None or not any(getattr(m, "double_sided", False) for m in mesh.materials):
        return None
    flags = np.array([bool(getattr(m, "double_sided", False)) for m in mesh.materials] + [False])
    return flags[mesh.face_materials]  # -1 (no material): the False appended


def face_sides(mesh, cull: str) -> Sides:
    """The :class:`Sides` of ``mesh``'s faces in a render with ``cull``."""
    if cull == "none":
        return Sides("none", True)
    double = double_sided_faces(mesh)
    if double is None or not double.any():
        return Sides(cull, False)
    if double.all():
        return Sides("none", True)
    codes = np.where(double, np.uint8(CULL_NONE), np.uint8(CULL_CODES[cull])).astype(np.uint8)
    return Sides(readonly(codes), readonly(double))


def corner_sides(two_sided, rows: np.ndarray, n_rows: int):
    """``two_sided`` for rows of per-vertex or per-corner lighting: ``two_sided`` itself when
    it is one bool, else (``n_rows``,) bool, True for each row that a two-sided face's
    corner reads (``rows`` (M, 3): each face corner's row). A vertex shared by a double-sided
    face and another is lit on both sides."""
    if not isinstance(two_sided, np.ndarray):
        return two_sided
    flags = np.zeros(n_rows, bool)
    flags[rows[two_sided].ravel()] = True
    return flags
