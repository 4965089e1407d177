"""The render modes as a table: which passes each draws, how its edges meet its faces, and
which kernels a first run compiles in helper processes.

:func:`rasterkit.render` reads a mode's row instead of comparing names, and so do the memory
estimate (:mod:`rasterkit.raster.memory`) and the first-run helpers
(:mod:`rasterkit.runtime.warm`). A new mode is a new row. Pure Python.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["MODE_TABLE", "Mode", "POLYGON_OFFSET", "mode"]

POLYGON_OFFSET = (1.0, 1e-5)
"""``(factor, units)`` of the polygon offset applied to the faces when edges are drawn over
them (hidden and solid+wire modes): each face is pushed back by ``factor`` times its largest
depth slope per pixel plus ``units``. An edge's depth is sampled on the line, up to half a
pixel from the pixel centre where its face's depth was sampled; the slope term covers that
difference even on faces seen almost edge-on, which a constant bias cannot."""

_KERNELS = "rasterkit.raster.kernels."


@dataclass(frozen=True)
class Mode:
    """One row of :data:`MODE_TABLE`."""

    name: str
    faces: bool  # the triangle pass runs
    shaded: bool  # ... and writes colour (else it fills only the depth buffer)
    edges: bool  # the edge pass runs
    edges_tested: bool  # ... depth-tested against the faces (with the polygon offset)
    edges_clear: bool  # ... and clears the colour buffer, which the faces left untouched

    @property
    def polygon_offset(self) -> tuple[float, float]:
        """The faces' depth offset: :data:`POLYGON_OFFSET` under tested edges, else none."""
        return POLYGON_OFFSET if self.edges_tested else (0.0, 0.0)

    @property
    def depth_kept(self) -> bool:
        """Whether the frame fills its depth buffer as it draws (the edges test against it);
        a solid frame makes it only when it is read."""
        return self.faces and self.edges

    def band_worker(self, aa: bool) -> str:
        """``module:function`` of the largest kernel the mode runs, compiled by a first run's
        helper: the triangles' band worker, or the edges' when the mode draws no faces."""
        if self.faces:
            return _KERNELS + "bands:draw_bands"
        return _KERNELS + ("edges_wu:draw_antialiased_bands" if aa else "edges:draw_wire_bands")

    def helped_kernels(self, aa: bool) -> list[list[str]]:
        """The kernels first-run helpers compile (``module:function``), a list per helper in the
        order the render runs them (:func:`rasterkit.runtime.warm.start`). The band worker is
        the largest kernel, about as long to compile as this process's share of a solid
        render: one helper for it, which also compiles the binning (and the depth offset under
        tested edges) that runs just before it. Faces and edges compile the edges' setup and
        band worker too, about as much again: a second helper for those and the face pass."""
        first = [self.band_worker(aa)]
        if self.faces:
            first[:0] = [_KERNELS + "bands:bin_records"] + ([_KERNELS + "triangle:offset_depths"]
                                                             if self.edges_tested else [])
        helpers = [first]
        if self.faces and self.edges:
            edge_worker = "edges_wu:draw_antialiased_bands" if aa else "edges_tested:draw_edge_bands"
            helpers.append([_KERNELS + "face_setup:setup_faces", _KERNELS + "edge_setup:project_vertices",
                            _KERNELS + "edge_setup:plain_setup", _KERNELS + edge_worker])
        return helpers


#: Every mode of :data:`rasterkit.options.MODES`.
MODE_TABLE = {
    # every edge, no depth test; the edge pass transforms the vertices itself
    "wire": Mode("wire", faces=False, shaded=False, edges=True, edges_tested=False, edges_clear=True),
    # the faces' depth, then only the visible parts of the edges
    "hidden": Mode("hidden", faces=True, shaded=False, edges=True, edges_tested=True, edges_clear=True),
    "solid": Mode("solid", faces=True, shaded=True, edges=False, edges_tested=False, edges_clear=False),
    "solid+wire": Mode("solid+wire", faces=True, shaded=True, edges=True, edges_tested=True, edges_clear=False),
}


def mode(name: str) -> Mode:
    """The row of ``name`` (checked by :class:`rasterkit.RenderOptions`)."""
    return MODE_TABLE[name]
