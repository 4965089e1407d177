"""The facets of an STL file as read (:class:`Facets`), and the Mesh made of them: facets with
a NaN or infinite corner or two equal corners dropped (:func:`usable`), then corners welded into
vertices, the edges, and the file's normals kept per facet where they can be trusted
(:func:`to_mesh`, :mod:`rasterkit.stl.normals`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from rasterkit.mesh import Mesh, mesh_bytes
from rasterkit.runtime.files import readable
from rasterkit.stl.errors import check
from rasterkit.stl.kernels.mesh import NOT_FINITE, TWO_EQUAL, facet_flaws
from rasterkit.stl.normals import facet_normals
from rasterkit.stl.weld import BYTES_PER_CORNER, weld_corners

__all__ = ["Facets", "assembly_bytes", "to_mesh", "usable"]

#: Bytes per facet while the Mesh is made, besides the Mesh's own (:func:`rasterkit.mesh.mesh_bytes`):
#: welding its three corners, the vertices and faces, the edges' buckets, the normals' work.
BYTES_PER_FACET = 3 * BYTES_PER_CORNER + 72 + 24 + 96 + 48 + 160


@dataclass(frozen=True)
class Facets:
    """The facets of one STL file, as the file gives them.

    Attributes
    ----------
    corners : (F, 3, 3) float32 (binary) or float64 (ASCII)
        The three corners of each facet, in object space, in the file's order.
    normals : (F, 3), the dtype of ``corners``
        The normal the file gives each facet (zero when the writer left it out).
    where : callable, or None
        ``where(k)``: the place of facet k for a message (``"line 12"``, ``"facet 3 (byte 234)"``);
        None once :func:`usable` has used it.
    colors : (F, 3) float32 in [0, 1], or None
    solids : (F,) int32, or None
        The ``solid`` block of each facet, in a file with several.
    solid_names : tuple of str
        The name of each block (``solid <name>``).
    warnings : tuple of str
        What the reader noticed (without the file's name; :func:`usable` adds it).
    """

    corners: np.ndarray
    normals: np.ndarray
    where: Callable[[int], str] | None
    colors: np.ndarray | None = None
    solids: np.ndarray | None = None
    solid_names: tuple = ()
    warnings: tuple = ()

    def subset(self, keep: np.ndarray) -> "Facets":
        """The facets where ``keep`` (F,) bool is True (without ``where``: it would count anew)."""
        return Facets(self.corners[keep], self.normals[keep], None, None if self.colors is None else self.colors[keep],
                      None if self.solids is None else self.solids[keep], self.solid_names, self.warnings)


def assembly_bytes(n_facets: int) -> int:
    """Bytes that :func:`to_mesh` needs for ``n_facets`` facets, at most."""
    return n_facets * BYTES_PER_FACET + mesh_bytes(3 * n_facets, n_facets, 3 * n_facets, 0, n_facets, 1)


def usable(name: str, facets: Facets) -> Facets:
    """``facets`` without those with a NaN or infinite coordinate or with two equal corners
    (which welding would make one vertex: no area), with a warning for each kind naming the
    first; ``where`` is dropped (so the file's text may go before the mesh is made)."""
    check(name, assembly_bytes(len(facets.corners)), f"welding its {len(facets.corners)} facets")
    warnings = [f"{readable(name)}: {w}" for w in facets.warnings]
    flaws = facet_flaws(facets.corners)
    finite, flat = flaws != NOT_FINITE, flaws == TWO_EQUAL
    if not finite.all():
        warnings.append(_dropped(name, facets, ~finite, "with a NaN or infinite coordinate"))
    if flat.any():
        warnings.append(_dropped(name, facets, flat, "with two corners at one place (no area)"))
    keep = finite & ~flat
    facets = facets if keep.all() else facets.subset(keep)
    return Facets(facets.corners, facets.normals, None, facets.colors, facets.solids, facets.solid_names,
                  tuple(warnings))


def to_mesh(name: str, facets: Facets) -> Mesh:
    """The :class:`~rasterkit.mesh.Mesh` of ``facets`` (read from the file ``name``, and
    :func:`usable`): their corners welded, in place (``-0.0`` becomes ``0.0``)."""
    warnings = list(facets.warnings)
    corners = facets.corners.reshape(-1, 3)
    inverse, first = weld_corners(corners)
    vertices = corners[first].astype(np.float64)
    faces = inverse.reshape(-1, 3)
    corner_normals, normal_index, note = facet_normals(facets.normals, vertices, faces)
    if note:
        warnings.append(f"{readable(name)}: {note}")
    return Mesh(vertices, faces, face_colors=facets.colors,
                face_groups=facets.solids, group_names=facets.solid_names if facets.solids is not None else (),
                corner_normals=corner_normals, normal_index=normal_index, warnings=tuple(warnings))


def _dropped(name: str, facets: Facets, dropped: np.ndarray, why: str) -> str:
    n = int(np.count_nonzero(dropped))
    noun = "facet" if n == 1 else "facets"
    return f"{readable(name)}: {n} {noun} {why} dropped (the first: {facets.where(int(np.argmax(dropped)))})"
