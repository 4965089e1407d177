"""The facets of an STL file as read (:class:`Facets`), and the Mesh made of them
(:func:`mesh_fields`): in one pass (:func:`rasterkit.stl.weld.weld_facets`), facets with a NaN
or infinite corner or two equal corners dropped, the corners of the others welded into
vertices, and the file's normals kept per facet where they can be trusted
(:mod:`rasterkit.stl.normals`)."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Callable

import numpy as np

from rasterkit.mesh import mesh_bytes
from rasterkit.runtime.files import readable
from rasterkit.stl.errors import check
from rasterkit.stl.kernels.mesh import NOT_FINITE, SOUND, TWO_EQUAL
from rasterkit.stl.normals import kept_normals
from rasterkit.stl.weld import BYTES_PER_CORNER, facet_flaws, weld_facets

__all__ = ["Facets", "assembly_bytes", "mesh_fields", "placed"]

#: Bytes per facet while the Mesh's arrays are made, besides the Mesh's own
#: (:func:`rasterkit.mesh.mesh_bytes`), at most: welding its three corners, its flaw, its
#: vertices (faces) and normal, and its row of ``normal_index``.
BYTES_PER_FACET = 3 * BYTES_PER_CORNER + 1 + 24 + 24 + 24


@dataclass(frozen=True)
class Facets:
    """The facets of one STL file, as the file gives them.

    Attributes
    ----------
    corners : (F, 3, 3) float32 (binary: a view of the file's bytes) or float64 (ASCII)
        The three corners of each facet, in object space, in the file's order.
    normals : (F, 3), the dtype of ``corners``
        The normal the file gives each facet (zero when the writer left it out).
    where : callable, or None
        ``where(k)``: the place of facet k for a message (``"line 12"``, ``"facet 3 (byte 234)"``);
        None once :func:`placed` has used it.
    colors : (F, 3) float32 in [0, 1], or None
    solids : (F,) int32, or None
        The ``solid`` block of each facet, in a file with several.
    solid_names : tuple of str
        The name of each block (``solid <name>``).
    warnings : tuple of str
        What the reader noticed (without the file's name; :func:`mesh_fields` adds it).
    dropped : tuple of str, or None
        The warnings of the facets that are dropped, when :func:`placed` has found them.
    """

    corners: np.ndarray
    normals: np.ndarray
    where: Callable[[int], str]
    colors: np.ndarray | None = None
    solids: np.ndarray | None = None
    solid_names: tuple = ()
    warnings: tuple = ()
    dropped: tuple | None = None


def assembly_bytes(n_facets: int) -> int:
    """Bytes that :func:`mesh_fields` and the Mesh need for ``n_facets`` facets, at most."""
    return n_facets * BYTES_PER_FACET + mesh_bytes(3 * n_facets, n_facets, 0, 0, n_facets, 1)


def mesh_fields(name: str, facets: Facets) -> dict:
    """The arguments of the :class:`~rasterkit.mesh.Mesh` of ``facets`` (read from the file
    ``name``): the facets without those with a NaN or infinite coordinate or with two equal
    corners (which welding would make one vertex: no area), with a warning for each kind
    naming the first; their corners welded (``-0.0`` becomes ``0.0``), their normals kept.
    Nothing of ``facets`` is kept (so the file's bytes may go before the Mesh is made)."""
    check(name, assembly_bytes(len(facets.corners)), f"welding its {len(facets.corners)} facets")
    warnings = [f"{readable(name)}: {w}" for w in facets.warnings]
    welded = weld_facets(facets.corners, facets.normals)
    warnings += _dropped_warnings(name, facets, welded.flaws) if facets.dropped is None else facets.dropped
    colors, solids = facets.colors, facets.solids
    if len(welded.faces) < len(welded.flaws):
        keep = welded.flaws == SOUND
        colors = None if colors is None else colors[keep]
        solids = None if solids is None else solids[keep]
    corner_normals, normal_index, note = kept_normals(welded.normals, welded.missing, welded.backwards)
    if note:
        warnings.append(f"{readable(name)}: {note}")
    return dict(vertices=welded.vertices, faces=welded.faces, face_colors=colors, face_groups=solids,
                group_names=facets.solid_names if solids is not None else (), corner_normals=corner_normals,
                normal_index=normal_index, warnings=tuple(warnings))


def placed(name: str, facets: Facets) -> Facets:
    """``facets`` with the warnings of those :func:`mesh_fields` drops made now (a first pass
    of the kernel finds their flaws) and without ``where``: for an ASCII file, whose places
    are lines of its text, so that the text can go before the weld."""
    return replace(facets, where=None, dropped=tuple(_dropped_warnings(name, facets, facet_flaws(facets.corners))))


def _dropped_warnings(name: str, facets: Facets, flaws: np.ndarray) -> list:
    """The warnings of the facets dropped for their ``flaws``, each kind naming the first."""
    warnings = []
    finite, flat = flaws != NOT_FINITE, flaws == TWO_EQUAL
    if not finite.all():
        warnings.append(_dropped(name, facets, ~finite, "with a NaN or infinite coordinate"))
    if flat.any():
        warnings.append(_dropped(name, facets, flat, "with two corners at one place (no area)"))
    return warnings


def _dropped(name: str, facets: Facets, dropped: np.ndarray, why: str) -> str:
    n = int(np.count_nonzero(dropped))
    noun = "facet" if n == 1 else "facets"
    return f"{readable(name)}: {n} {noun} {why} dropped (the first: {facets.where(int(np.argmax(dropped)))})"
