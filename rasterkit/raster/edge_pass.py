"""Driver of the edge path (wire, hidden-line and solid+wire edges, and ``draw.lines``):
vertex pass -> (plain: per-edge setup, work per row) -> bands -> draw the bands.

The kernels are in :mod:`rasterkit.raster.kernels.edge_setup` and :mod:`rasterkit.raster.kernels.edges`;
this module picks the scratch memory, the number of bands and threads, and runs the passes
in order. Its caller has validated the inputs (``edges`` index ``clip``'s rows).
"""

from __future__ import annotations

import numpy as np

from rasterkit.runtime import threads as _threads
from rasterkit.runtime import scratch as _memory
from rasterkit.runtime.jit import readonly
from rasterkit.runtime.threads import run_workers
from rasterkit.raster.kernels import edge_setup as _setup
from rasterkit.raster.kernels import edges as _kernels
from rasterkit.raster.kernels import edges_tested as _tested
from rasterkit.raster.kernels import edges_wu as _wu

#: Fewer edges than this are drawn by the calling thread alone: handing work to another
#: thread costs about 15 microseconds a pass.
_PARALLEL_EDGES = 2048

#: Plain wireframes of at least this many edges are drawn in a spatial order
#: (:func:`spatial_edges`); below it a band reads few blocks anyway.
SPATIAL_ORDER_EDGES = 16 * _setup.BLOCK

def edge_mode(tested: bool, aa: bool) -> int:
    """The edge kernels' mode bits: plain, depth-tested (``tested``), anti-aliased (``aa``)."""
    return _kernels.MODE_PLAIN | (_kernels.MODE_DEPTH_TEST if tested else 0) | (_kernels.MODE_ANTIALIAS if aa else 0)


_NO_DEPTH = np.empty((0, 0), np.float32)
_NO_BACKGROUND = np.empty(0, np.uint8)
_NO_POINTS = readonly(np.empty((0, 3), np.float64))
_NO_MATRIX = readonly(np.eye(4))



#: Cells per axis of the grid of :func:`spatial_edges`: ``1 << GRID_BITS`` (16: 4096 cells,
#: a few dozen edges each in a model of a hundred thousand; finer grids measured no faster).
GRID_BITS = 4
#: Each 4-bit cell coordinate's bits three places apart (a Morton code of three of them).
_SPREAD = np.array([sum(((q >> bit) & 1) << (3 * bit) for bit in range(GRID_BITS)) for q in range(1 << GRID_BITS)],
                   np.uint16)
#: Blocks of edges sampled by :func:`_scattered`, and the share of the model's extent (along
#: every axis) from which a block counts as scattered (a scanned model's random order: about
#: 0.9; a modeller's export or a grid's rows: 0.0-0.3).
_SAMPLED_BLOCKS, _SCATTERED = 16, 0.5


def spatial_edges(vertices, edges) -> np.ndarray:
    """``edges`` (E, 2) int64 in a spatial order, read-only, for the plain wireframe
    (:mod:`rasterkit.raster.kernels.edges`: each block of ``BLOCK`` consecutive edges is summarised by
    the rows it spans, and a band skips the blocks outside it, which pays when consecutive
    edges lie together). A mesh's edges follow its vertex order; when that order is
    scattered (:func:`_scattered`: a scanned model stored in no spatial order, such as the
    Stanford bunny), the edges are sorted, stably, by the Morton code of the cell of their
    first vertex in a 16^3 grid over the finite vertices (NaN and infinite coordinates count
    as the grid's first or last cell); otherwise they are returned as they are. All of a
    wireframe's edges get one colour: the order changes no pixel. NumPy only (2 ms for the
    bunny's 104k edges, once per Mesh): a compiled sort took 0.8 s to compile on a first run."""
    finite = _finite_rows(vertices)
    if len(edges) == 0 or len(finite) == 0 or not _scattered(vertices, edges, finite):
        return edges
    lo, hi = _bounds(finite)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        extent = hi - lo
        scale = np.where(extent > 0, (1 << GRID_BITS) / extent, 0.0)  # an axis without extent: one cell
        x = (vertices - np.nan_to_num(lo)) * np.nan_to_num(scale, posinf=0.0)
    top = (1 << GRID_BITS) - 1
    q = np.clip(np.nan_to_num(x, nan=0.0, posinf=top, neginf=0.0), 0, top).astype(np.intp)
    cell = _SPREAD[q[:, 0]] | (_SPREAD[q[:, 1]] << 1) | (_SPREAD[q[:, 2]] << 2)
    order = np.argsort(cell[edges[:, 0]], kind="stable")  # 16-bit keys: a radix sort
    rows = np.ascontiguousarray(edges).view(np.dtype((np.void, 16))).reshape(-1)  # a row as one item
    return readonly(rows[order].view(np.int64).reshape(-1, 2))


def _finite_rows(vertices) -> np.ndarray:
    """The vertices without a NaN or infinite coordinate (all of them, not copied, in the
    usual case; a coordinate sum beyond float64 counts as not finite: only the grid's bounds
    depend on it)."""
    with np.errstate(invalid="ignore", over="ignore"):  # columns: ten times NumPy's axis=1 sum
        finite = np.isfinite(vertices[:, 0] + vertices[:, 1] + vertices[:, 2])
    return vertices if finite.all() else vertices[finite]


def _bounds(points) -> tuple[np.ndarray, np.ndarray]:
    """The lowest and highest corner of (N >= 1, 3) ``points``, column by column (NumPy's
    ``min(axis=0)`` over rows of three takes 4 ms for 160k points, this 0.3)."""
    return (np.array([points[:, k].min() for k in range(3)]),
            np.array([points[:, k].max() for k in range(3)]))


def _scattered(vertices, edges, finite) -> bool:
    """Whether consecutive edges lie apart: the finite first vertices of sampled blocks of
    ``BLOCK`` edges span on average more than ``_SCATTERED`` of the model's extent along
    each of its axes (those that have an extent); ``finite``: :func:`_finite_rows`."""
    with np.errstate(invalid="ignore", over="ignore", divide="ignore"):
        low, high = _bounds(finite)
        whole = high - low
        shares = []
        for start in np.linspace(0, max(len(edges) - _setup.BLOCK, 0), _SAMPLED_BLOCKS).astype(np.int64):
            ends = vertices[edges[start:start + _setup.BLOCK, 0]]
            ends = _finite_rows(ends)
            if len(ends) == 0:
                continue
            low, high = _bounds(ends)
            share = (high - low) / whole
            share = share[np.isfinite(share)]  # axes without extent, or beyond float64
            if share.size:
                shares.append(share.min())  # a block along a row of a grid is not scattered
    return bool(shares and np.mean(shares) > _SCATTERED)


def scratch_bytes(n_vertices, n_edges, n_pixels, mode, transform=False) -> int:
    """Bytes of the scratch arrays of a :func:`draw_edges` call (:func:`scratch`, the
    vertices made in the vertex pass with ``transform`` and a plain draw's edges in a
    spatial order, :func:`spatial_edges`), for
    :func:`rasterkit.limits.check_memory`."""
    plain = mode == _kernels.MODE_PLAIN
    recorded = _recorded(mode)
    per_vertex = 32 + (8 if recorded else 0) + (32 if transform else 0)
    per_edge = 4 * _setup.REC_FIELDS if recorded else 0
    blocks = 4 * _setup.BLOCK_FIELDS * _setup.n_blocks(n_edges) if recorded else 0
    if plain and n_edges >= SPATIAL_ORDER_EDGES:  # the edges in a spatial order (kept) and their sort
        per_edge, per_vertex = per_edge + 40, per_vertex + 56
    return n_vertices * per_vertex + n_edges * per_edge + blocks + (n_pixels if plain else 0)


def scratch(n_vertices, n_edges, n_pixels, mode, take=_memory.take):
    """The :class:`rasterkit.raster.kernels.edges.EdgeScratch` of a draw (``n_pixels``: mask bytes,
    0 for none), from recycled memory unless ``take`` says otherwise (``np.empty`` for fresh
    arrays)."""
    plain = mode == _kernels.MODE_PLAIN
    recorded = _recorded(mode)
    return _kernels.EdgeScratch(take((n_vertices, 4), np.float64),
                                take((n_vertices if recorded else 0,), np.int64),
                                take((_setup.REC_FIELDS, n_edges if recorded else 0), np.int32),
                                take((_setup.BLOCK_FIELDS, _setup.n_blocks(n_edges) if recorded else 0), np.int32),
                                take((n_pixels if plain else 0,), np.uint8))


def _recorded(mode) -> bool:
    """Whether edges of ``mode`` get records (plain, and depth-tested without Wu's lines)."""
    return not mode & _kernels.MODE_ANTIALIAS


def _unrecorded(memory, edges) -> bool:
    """Whether :func:`rasterkit.raster.kernels.edge_setup.plain_setup` left edges without a record
    (clipped, or crossing the image's border): they are drawn by a pass of their own."""
    return bool(memory.blocks[_setup.BLOCK_GENERAL, :_setup.n_blocks(len(edges))].any())


def draw_edges(color, depth, clip, edges, rgba, mode, bias=0.0, background=None, *, n_bands=None,
               threads=None, memory=None, transform=None) -> int:
    """Draw the edges ``edges`` (E, 2) int64 of the vertices ``clip`` (N, 4) float64
    (homogeneous raster space) into ``color`` (H, W, C) uint8 with ``rgba`` (C,) uint8, as
    :func:`rasterkit.raster.kernels.edges_tested.draw_edge_bands` describes; ``depth`` (H, W) float32 is
    read in ``MODE_DEPTH_TEST`` only (anything, e.g. an empty array, otherwise).
    ``background`` (C,) uint8 clears the colour buffer first.

    ``n_bands`` (default: the thread count) and ``threads`` (default
    :func:`rasterkit.runtime.threads.get_threads`, one for a few edges) never change the image. ``memory``: scratch arrays
    as :func:`scratch` makes them (default: recycled ones). ``transform``: ``(points,
    matrix)``, (N, 3) and (4, 4) float64, to make ``clip`` (then None) in the vertex pass
    itself. Returns the number of edges dropped (a NaN, infinite or too large coordinate).
    """
    height, width = color.shape[:2]
    if threads is None:
        threads = 1 if len(edges) < _PARALLEL_EDGES else _threads.get_threads()
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
    bounds = _setup.balanced_bands(_setup.band_work(counts, _setup.ROW_WORK if plain else 0, height), n_bands, height)
    if plain:  # a kernel of its own: a wireframe compiles nothing of the other modes
        args = (color, clip, edges, rgba, bounds, background, memory)
        dropped = run_workers(_kernels.draw_wire_bands, *args, threads=threads)
        if _unrecorded(memory, edges):
            dropped = run_workers(_kernels.draw_general_wire_bands, *args, threads=threads)
    else:
        worker = _wu.draw_antialiased_bands if mode & _kernels.MODE_ANTIALIAS else _tested.draw_edge_bands
        args = (color, depth if depth is not None else _NO_DEPTH, clip, edges, rgba, mode, bias, bounds, background,
                memory)
        dropped = run_workers(worker, *args, threads=threads)
        if worker is _tested.draw_edge_bands and _unrecorded(memory, edges):
            dropped = run_workers(_tested.draw_general_edge_bands, *args, threads=threads)  # edges without a record
    return max(dropped)
