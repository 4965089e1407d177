"""Depth-tested edges stepped from their records (rasterkit.raster.kernels.edges_tested._band_depth_tested,
_depth_terms) against the general path alone, which clips and
sets up every edge in every band: the same pixels, to the bit, for edges in every direction,
edges within one pixel whose real ends point the other way than their integer ones, edges
crossing the bands' edges, and edges leaving the image."""

from __future__ import annotations

import numpy as np
import pytest

from rasterkit.raster import edge_pass as _edges
from rasterkit.runtime.threads import run_workers
from rasterkit.raster.kernels import edge_setup
from rasterkit.raster.kernels import edges_tested
from rasterkit.raster.kernels.edges import MODE_DEPTH_TEST, EdgeScratch

H, W = 61, 83
RGBA = np.array([200, 30, 40], np.uint8)


def _general_only(clip, edges, depth, bias, bounds):
    """The image of draw_edge_bands and its second pass, draw_general_edge_bands, without
    usable records: every edge by the general path."""
    color = np.zeros((H, W, 3), np.uint8)
    proj = np.empty((len(clip), 4))
    counts = np.zeros((max(edge_setup.VERTEX_CHUNKS, edge_setup.SETUP_CHUNKS), -(-H // edge_setup.ROWS_PER_BIN)),
                      np.int64)
    run_workers(edge_setup.project_vertices, clip, proj, np.empty(0, np.int64), W, H, counts, _edges._NO_POINTS,
                _edges._NO_MATRIX, threads=1)
    # every record "outside the image" (rows -1) and every block general: no edge is stepped
    # from a record
    recs = np.full((edge_setup.REC_FIELDS, len(edges)), -1, np.int32)
    blocks = np.ones((edge_setup.BLOCK_FIELDS, edge_setup.n_blocks(len(edges))), np.int32)
    none = EdgeScratch(proj, np.empty(0, np.int64), recs, blocks, np.empty(0, np.uint8))
    for worker in (edges_tested.draw_edge_bands, edges_tested.draw_general_edge_bands):
        run_workers(worker, color, depth, clip, edges, RGBA, MODE_DEPTH_TEST, bias, np.asarray(bounds, np.int64),
                    np.zeros(3, np.uint8), none, threads=1)
    return color


def _scene(seed, n=3000):
    rng = np.random.default_rng(seed)
    pts = np.c_[rng.uniform(-8, W + 8, n), rng.uniform(-8, H + 8, n), rng.uniform(0.05, 0.95, n), np.ones(n)]
    short = rng.random(n) < 0.4  # many edges of a pixel or two, as a fine mesh has
    partner = np.where(short, np.arange(n), rng.integers(0, n, n))
    pts2 = pts[partner] + np.where(short[:, None], np.c_[rng.uniform(-1.2, 1.2, (n, 2)), rng.uniform(-.2, .2, n),
                                                           np.zeros(n)], 0)
    clip = np.ascontiguousarray(np.r_[pts, pts2])
    edges = np.c_[np.arange(n), n + np.arange(n)].astype(np.int64)
    # edges within one pixel whose real ends run backwards along the major axis
    clip[n:n + 50, :2] = np.floor(clip[:50, :2]) + rng.uniform(0, 1, (50, 2))
    depth = rng.uniform(0.0, 1.0, (H, W)).astype(np.float32)
    return clip, edges, depth


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("n_bands", [1, 3])
def test_records_draw_the_general_paths_pixels(seed, n_bands):
    clip, edges, depth = _scene(seed)
    bias = 0.01
    color = np.zeros((H, W, 3), np.uint8)
    _edges.draw_edges(color, depth, clip, edges, RGBA, MODE_DEPTH_TEST, bias, background=np.zeros(3, np.uint8),
                      n_bands=n_bands, threads=1 if n_bands == 1 else 2)
    bounds = np.linspace(0, H, n_bands + 1).astype(np.int64)
    expected = _general_only(clip, edges, depth, bias, bounds)
    assert (expected > 0).any() and (expected == 0).any()
    assert np.array_equal(color, expected)
