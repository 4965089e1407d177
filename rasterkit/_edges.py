"""Driver of the edge path (wire, hidden-line and solid+wire edges, and ``draw.lines``):
vertex pass -> (plain: per-edge setup, work per row) -> bands -> draw the bands.

The kernels are in :mod:`rasterkit.kernels.edge_setup` and :mod:`rasterkit.kernels.edges`;
this module picks the scratch memory, the number of bands and threads, and runs the passes
in order. Its caller has validated the inputs (``edges`` index ``clip``'s rows).
"""

from __future__ import annotations

import numpy as np

from rasterkit import _jit, _memory
from rasterkit._jit import readonly, run_workers
from rasterkit.kernels import edge_setup as _setup
from rasterkit.kernels import edges as _kernels
from rasterkit.kernels import edges_wu as _wu

#: Fewer edges than this are drawn by the calling thread alone: handing work to another
#: thread costs about 15 microseconds a pass.
_PARALLEL_EDGES = 2048

#: Plain wireframes of at least this many edges are drawn in a spatial order
#: (:func:`spatial_edges`); below it a band reads few blocks anyway.
SPATIAL_ORDER_EDGES = 16 * _setup.BLOCK

_NO_DEPTH = np.empty((0, 0), np.float32)
_NO_BACKGROUND = np.empty(0, np.uint8)
_NO_POINTS = readonly(np.empty((0, 3), np.float64))
_NO_MATRIX = readonly(np.eye(4))



def spatial_edges(vertices, edges) -> np.ndarray:
    """``edges`` (E, 2) int64 reordered by the cells of a coarse grid over the finite
    ``vertices`` (N, 3) float64 (:mod:`rasterkit.kernels.edge_order`), read-only."""
    from rasterkit.kernels.edge_order import spatial_order

    out = np.empty_like(edges)
    spatial_order(vertices, edges, out)
    return readonly(out)


def scratch_bytes(n_vertices, n_edges, n_pixels, mode, transform=False) -> int:
    """Bytes of the scratch arrays of a :func:`draw_edges` call (:func:`scratch`, the
    vertices made in the vertex pass with ``transform`` and a plain draw's edges in a
    spatial order, :func:`spatial_edges`), for
    :func:`rasterkit.limits.check_memory`."""
    plain = mode == _kernels.MODE_PLAIN
    recorded = _recorded(mode)
    per_vertex = 32 + (8 if recorded else 0) + (32 if transform else 0)
    per_edge = (4 * _setup.REC_FIELDS if recorded else 0) + (0 if plain or not recorded else 8 * _setup.TERM_FIELDS)
    blocks = 4 * _setup.BLOCK_FIELDS * _setup.n_blocks(n_edges) if recorded else 0
    if plain and n_edges >= SPATIAL_ORDER_EDGES:  # the edges in a spatial order (kept), the cells
        per_edge, per_vertex = per_edge + 16, per_vertex + 4
    return n_vertices * per_vertex + n_edges * per_edge + blocks + (n_pixels if plain else 0)


def scratch(n_vertices, n_edges, n_pixels, mode, take=_memory.take):
    """The :class:`rasterkit.kernels.edges.EdgeScratch` of a draw (``n_pixels``: mask bytes,
    0 for none), from recycled memory unless ``take`` says otherwise (``np.empty`` for fresh
    arrays)."""
    plain = mode == _kernels.MODE_PLAIN
    recorded = _recorded(mode)
    return _kernels.EdgeScratch(take((n_vertices, 4), np.float64),
                                take((n_vertices if recorded else 0,), np.int64),
                                take((_setup.REC_FIELDS, n_edges if recorded else 0), np.int32),
                                take((_setup.BLOCK_FIELDS, _setup.n_blocks(n_edges) if recorded else 0), np.int32),
                                take((n_pixels if plain else 0,), np.uint8),
                                take((_setup.TERM_FIELDS, n_edges if recorded and not plain else 0), np.float64))


def _recorded(mode) -> bool:
    """Whether edges of ``mode`` get records (plain, and depth-tested without Wu's lines)."""
    return not mode & _kernels.MODE_ANTIALIAS


def draw_edges(color, depth, clip, edges, rgba, mode, bias=0.0, background=None, *, n_bands=None,
               threads=None, memory=None, transform=None) -> int:
    """Draw the edges ``edges`` (E, 2) int64 of the vertices ``clip`` (N, 4) float64
    (homogeneous raster space) into ``color`` (H, W, C) uint8 with ``rgba`` (C,) uint8, as
    :func:`rasterkit.kernels.edges.draw_edge_bands` describes; ``depth`` (H, W) float32 is
    read in ``MODE_DEPTH_TEST`` only (anything, e.g. an empty array, otherwise).
    ``background`` (C,) uint8 clears the colour buffer first.

    ``n_bands`` (default: the thread count) and ``threads`` (default
    :func:`rasterkit._jit.get_threads`, one for a few edges) never change the image. ``memory``: scratch arrays
    as :func:`scratch` makes them (default: recycled ones). ``transform``: ``(points,
    matrix)``, (N, 3) and (4, 4) float64, to make ``clip`` (then None) in the vertex pass
    itself. Returns the number of edges dropped (a NaN, infinite or too large coordinate).
    """
    height, width = color.shape[:2]
    if threads is None:
        threads = 1 if len(edges) < _PARALLEL_EDGES else _jit.get_threads()
    n_bands = min(height, threads if n_bands is None else n_bands)
    plain = mode == _kernels.MODE_PLAIN
    background = _NO_BACKGROUND if background is None else background
    points, matrix = _NO_POINTS, _NO_MATRIX
    if transform is not None:
        points, matrix = (readonly(a) for a in transform)
        clip = _memory.take((len(points), 4), np.float64)
    if memory is None:
        memory = scratch(len(clip), len(edges), height * width if background.size else 0, mode)
    proj, pixels = memory.proj, memory.pixels
    edges = readonly(edges)  # as a Mesh's: one compiled kernel for both
    n_bins = -(-height // _setup.ROWS_PER_BIN)
    # the work per chunk and rows: vertices projected, or (plain: the vertex pass leaves it
    # zero) the records' pixels, counted by plain_setup
    counts = np.zeros((max(_setup.VERTEX_CHUNKS, _setup.SETUP_CHUNKS), n_bins), np.int64)
    recorded = _recorded(mode)
    run_workers(_setup.project_vertices, clip, proj, pixels if recorded else pixels[:0], width, height, counts,
                points, matrix, threads=threads)
    if recorded:  # the work of its records (and of clearing and painting rows) in the balance
        run_workers(_setup.plain_setup, pixels, edges, width, height, memory.recs, memory.blocks, counts,
                    threads=threads)
        if not plain:
            run_workers(_setup.depth_terms, proj, edges, memory.recs, memory.terms, threads=threads)
    bounds = _setup.balanced_bands(_setup.band_work(counts, _setup.ROW_WORK if plain else 0, height), n_bands, height)
    if plain:  # a kernel of its own: a wireframe compiles nothing of the other modes
        dropped = run_workers(_kernels.draw_wire_bands, color, clip, edges, rgba, bounds, background, memory,
                            threads=threads)
    else:
        worker = _wu.draw_antialiased_bands if mode & _kernels.MODE_ANTIALIAS else _kernels.draw_edge_bands
        dropped = run_workers(worker, color, depth if depth is not None else _NO_DEPTH, clip, edges, rgba, mode, bias,
                            bounds, background, memory, threads=threads)
    return max(dropped)
