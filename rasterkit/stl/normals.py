"""The facet normals an STL file gives, kept as per-corner normals of the Mesh.

rasterkit's flat shading and its culling use the winding of a face's corners (the right-hand
rule, :attr:`rasterkit.Mesh.face_normals`), whatever normals a file gives; smooth shading uses
a mesh's own per-corner normals where it has them (``corner_normals`` through
``normal_index``). An STL facet's normal is a flat normal for its three corners: kept so, a
smooth render of an STL file draws the facets flat, as the file describes them (its edges are
all "authored" hard edges), and lit as flat shading lights them:

- each facet gets one row of ``corner_normals`` (unit length) and its three corners index it;
- a normal that is zero, NaN or infinite, or that points to the back of its facet (against the
  winding that culling and flat shading follow), is replaced by the facet's own normal from its
  corners (zero for a facet whose corners are on one line), and counted in a warning;
- a file whose every normal is zero, NaN or infinite (many writers leave them out) has no
  normals at all (``corner_normals`` None): smooth shading then averages the faces around each
  welded vertex, as it does for an OBJ file without ``vn``.
"""

from __future__ import annotations

import numpy as np

from rasterkit.mesh.checks import sealed_empty

__all__ = ["kept_normals"]


def kept_normals(unit: np.ndarray, missing: int, backwards: int):
    """``(corner_normals (M, 3) float64, normal_index (M, 3) int64, note)`` of M facets whose
    unit normals are ``unit`` (M, 3) float64, of which ``missing`` replace a file normal that
    is zero, NaN or infinite and ``backwards`` one against its facet's winding (by
    :func:`rasterkit.stl.kernels.mesh.assemble`); the first two None when no file normal is
    kept. ``note``: a warning (normals replaced), or None."""
    total = len(unit)
    if missing == total:
        return None, None, None
    note = _note(total, missing, backwards, kept=missing + backwards < total) if missing + backwards else None
    if missing + backwards == total:
        return None, None, note
    index, fill = sealed_empty((total, 3), np.int64)  # the Mesh's own: not copied again
    fill[:] = np.arange(total, dtype=np.int64)[:, None]
    return unit, index, note


def _note(total: int, missing: int, backwards: int, kept: bool) -> str:
    """The warning about the normals that are not used."""
    parts = ([f"{missing} are zero, NaN or infinite"] if missing else []) + \
            ([f"{backwards} point against their facet's winding (the order of its corners, which culling and flat "
              "shading follow)"] if backwards else [])
    what = "replaced by the normals of the corners" if kept else "so the file's normals are not used"
    return f"of {total} facet normals, {' and '.join(parts)}: {what}"
