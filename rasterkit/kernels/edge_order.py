"""The edges of a mesh in a spatial order, for the plain wireframe.

The plain edge path (:mod:`rasterkit.kernels.edges`) summarises each block of
:data:`rasterkit.kernels.edge_setup.BLOCK` consecutive edges by the image rows it spans,
and a band of rows skips the blocks outside it. That pays when consecutive edges lie
together, which the order of a mesh's edges (sorted by vertex index) gives only when the
vertices were stored in a spatial order. A scanned model's often are not (the Stanford
bunny, the armadillo): every block then spans the whole image and every band reads every
edge. Drawn in the order of the cells of a coarse grid over the model, consecutive edges lie
together whatever the vertex order; a wireframe's plain edges all get the same colour, so the
order changes no pixel.

Compiled only when a plain wireframe of at least
:data:`rasterkit._edges.SPATIAL_ORDER_EDGES` edges is drawn.
"""

import numpy as np

from rasterkit._jit import kernel

#: Cells per axis of the grid: ``1 << GRID_BITS`` (16: 4096 cells, a few dozen edges each in
#: a model of a hundred thousand; finer grids measured no faster).
GRID_BITS = 4


@kernel(inline="always")
def _spread(q):
    """The bits of ``q`` (< 1 << GRID_BITS) three places apart, for a Morton code."""
    code = 0
    for bit in range(GRID_BITS):
        code |= ((q >> bit) & 1) << (3 * bit)
    return code


@kernel(inline="always")
def _cell(vertices, i, lo, scale):
    """The grid cell of vertex ``i`` (Morton order; a NaN or infinite coordinate counts as
    the grid's first or last cell along its axis)."""
    top = (1 << GRID_BITS) - 1
    code = 0
    for axis in range(3):
        x = (vertices[i, axis] - lo[axis]) * scale[axis]
        q = 0
        if x >= top:
            q = top
        elif x >= 0.0:
            q = np.int64(x)
        code |= _spread(q) << axis
    return code


@kernel(inline="always")
def _grid(vertices):
    """``(lo, scale)`` (3,) float64 each: the finite vertices' lowest corner and the cells
    per unit along each axis (0 for an axis without extent: one cell)."""
    lo = np.full(3, np.inf)
    hi = np.full(3, -np.inf)
    for i in range(vertices.shape[0]):
        x, y, z = vertices[i, 0], vertices[i, 1], vertices[i, 2]
        if np.isfinite(x) and np.isfinite(y) and np.isfinite(z):
            lo[0], hi[0] = min(lo[0], x), max(hi[0], x)
            lo[1], hi[1] = min(lo[1], y), max(hi[1], y)
            lo[2], hi[2] = min(lo[2], z), max(hi[2], z)
    scale = np.zeros(3)
    for axis in range(3):
        extent = hi[axis] - lo[axis]
        if extent > 0.0:
            s = (1 << GRID_BITS) / extent
            scale[axis] = s if s < np.inf else 0.0  # an extent below ~1e-308: one cell
        else:
            lo[axis] = 0.0
    return lo, scale


@kernel
def spatial_order(vertices, edges, out):
    """``out`` (E, 2) int64: the rows of ``edges`` (E, 2) int64 (indices into ``vertices``
    (N, 3) float64) ordered by the cell of their first vertex in a grid of ``1 << GRID_BITS``
    cells a side over the finite vertices, in Morton order, keeping the given order within a
    cell (a stable counting sort)."""
    lo, scale = _grid(vertices)
    n_cells = 1 << (3 * GRID_BITS)
    cells = np.empty(vertices.shape[0], np.int32)
    for i in range(vertices.shape[0]):
        cells[i] = _cell(vertices, i, lo, scale)
    start = np.zeros(n_cells + 1, np.int64)
    for e in range(edges.shape[0]):
        start[cells[edges[e, 0]] + 1] += 1
    for c in range(n_cells):
        start[c + 1] += start[c]
    for e in range(edges.shape[0]):
        c = cells[edges[e, 0]]
        k = start[c]
        out[k, 0], out[k, 1] = edges[e, 0], edges[e, 1]
        start[c] = k + 1
