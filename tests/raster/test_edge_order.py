"""The spatial order of a plain wireframe's edges (rasterkit.raster.edge_pass.spatial_edges): a stable
sort by grid cell against a slow reference when the given order is scattered, the given order
kept when it is not, and the same image either way."""

from __future__ import annotations

import numpy as np
import pytest

import rasterkit
from rasterkit import shapes
from rasterkit.raster import edge_pass as _edges
from rasterkit.raster.edge_pass import GRID_BITS


def _reference(vertices, edges):
    """The rows of ``edges`` by the Morton code of their first vertex's cell, stably."""
    finite = vertices[np.all(np.isfinite(vertices), axis=1)]
    lo, hi = finite.min(axis=0), finite.max(axis=0)
    top = (1 << GRID_BITS) - 1
    codes = []
    with np.errstate(invalid="ignore", divide="ignore"):  # a flat axis: one cell
        scale = (1 << GRID_BITS) / (hi - lo)
    for i in edges[:, 0]:
        code = 0
        for axis in range(3):
            with np.errstate(invalid="ignore"):
                x = (vertices[i, axis] - lo[axis]) * scale[axis]
            q = top if x >= top else int(x) if x >= 0 else 0  # NaN: neither, so 0
            for bit in range(GRID_BITS):
                code |= ((q >> bit) & 1) << (3 * bit + axis)
        codes.append(code)
    return edges[np.argsort(np.array(codes), kind="stable")]


def _shuffled(mesh, seed=0):
    """``mesh`` with its vertices stored in a random order (as a scanned model's are)."""
    rng = np.random.default_rng(seed)
    perm = rng.permutation(len(mesh.vertices))
    inverse = np.empty_like(perm)
    inverse[perm] = np.arange(len(perm))
    return rasterkit.Mesh(mesh.vertices[perm], inverse[mesh.faces])


def test_the_order_is_a_stable_sort_by_grid_cell():
    mesh = _shuffled(shapes.icosphere(3))
    got = _edges.spatial_edges(mesh.vertices, mesh.edges)
    assert np.array_equal(got, _reference(mesh.vertices, mesh.edges))
    assert not got.flags.writeable


def test_a_spatially_coherent_order_is_kept():
    mesh = shapes.torus(1.0, 0.4, 200, 60)  # ring after ring: neighbouring vertices, neighbouring edges
    shuffled = _shuffled(mesh)
    assert _edges.spatial_edges(mesh.vertices, mesh.edges) is mesh.edges
    assert _edges.spatial_edges(shuffled.vertices, shuffled.edges) is not shuffled.edges


def test_non_finite_and_flat_vertices_get_cells_too():
    rng = np.random.default_rng(1)
    vertices = np.c_[rng.uniform(-1, 1, (200, 2)), np.zeros(200)]  # flat in z: one cell
    vertices[3] = [np.nan, 0.5, 0.0]
    vertices[7] = [np.inf, -np.inf, 0.0]
    edges = np.sort(rng.integers(0, 200, (500, 2)), axis=1)
    edges = edges[edges[:, 0] != edges[:, 1]]
    got = _edges.spatial_edges(vertices, edges)
    order = np.lexsort(got.T[::-1])
    assert np.array_equal(got[order], edges[np.lexsort(edges.T[::-1])])  # the same rows
    finite = np.all(np.isfinite(vertices[edges[:, 0]]), axis=1)
    assert np.array_equal(got[np.isin(got[:, 0], edges[finite, 0])],
                          _reference(vertices, edges[finite]))


@pytest.mark.parametrize("threads", [1, 2])
def test_a_wireframe_in_the_spatial_order_is_the_same_image(monkeypatch, threads):
    mesh = _shuffled(shapes.icosphere(4))  # 7680 edges: over the threshold below
    camera = rasterkit.Camera.preset("perspective", np.zeros(3), 1.0, width=320, height=240)
    monkeypatch.setattr(_edges, "SPATIAL_ORDER_EDGES", 1024)
    rasterkit.set_threads(threads)
    try:
        spatial = rasterkit.render(mesh, camera, mode="wire").color
        assert not np.array_equal(mesh.spatial_edges, mesh.edges)  # it was reordered
        monkeypatch.setattr(_edges, "SPATIAL_ORDER_EDGES", 1 << 40)
        given = rasterkit.render(mesh, camera, mode="wire").color
    finally:
        rasterkit.set_threads(None)
    assert np.array_equal(spatial, given)
    assert (spatial != 255).any()
