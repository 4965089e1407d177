"""The maps kernel of rasterkit.raster.vision (rasterkit.raster.kernels.maps.surface_maps) against slow NumPy
references: flat and smooth normals and object ids for id images of every kind (background
blocks, mixed blocks, rows whose width is no multiple of the block), on one thread and two."""

from __future__ import annotations

import numpy as np
import pytest

import rasterkit
from rasterkit.runtime.jit import readonly
from rasterkit.runtime.threads import run_workers
from rasterkit.raster.kernels.map_rows import BLOCK
from rasterkit.raster.kernels.maps import surface_maps
from rasterkit.raster.kernels.records import Maps

EMPTY2 = np.empty((0, 0), np.int32)


def _mesh(m=40, seed=1, degenerate=True):
    rng = np.random.default_rng(seed)
    vertices = rng.normal(size=(3 * m, 3))
    faces = np.arange(3 * m).reshape(m, 3)
    if degenerate:
        faces[5] = [0, 0, 1]  # a zero normal: NaN in camera space (never drawn by a render)
    return rasterkit.Mesh(vertices, faces)


def _ids(height, width, m, seed=2):
    """Background, runs of faces and single pixels, and a whole-row run of one face."""
    rng = np.random.default_rng(seed)
    ids = np.full((height, width), -1, np.int32)
    ids[1, :] = 7
    for _ in range(height * 3):
        j, i = rng.integers(height), rng.integers(width)
        ids[j, i:i + rng.integers(1, 40)] = rng.integers(m)
    ids[height - 1, width - 1] = 5
    return ids


def _rotation():
    return rasterkit.Camera.look_at((1.0, 2.0, 5.0), (0.2, -0.1, 0.0), width=8, height=8).rotation()


def _maps(ids, mesh, smooth=False, objects=None, bary=None, normals=True):
    height, width = ids.shape
    out = np.full((height, width, 3), 7.0, np.float32)
    vertex = np.ascontiguousarray(mesh.vertices * 0.5 + 0.1) if smooth else np.zeros((0, 3))
    if objects is None:
        counts, object_ids, face_object, first = None, EMPTY2, np.zeros(0, np.int32), np.zeros(0, np.int64)
    else:
        counts = np.asarray(objects, np.int64)
        first = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.int64)
        face_object = np.repeat(np.arange(len(counts), dtype=np.int32), counts)
        object_ids = np.full((height, width), 9, np.int32)
    flat = normals and not smooth
    return Maps(normals, out if normals else np.empty((0, 0, 3), np.float32), smooth,
                readonly(mesh.face_normals if flat else np.zeros((0, 3), np.float32)), vertex,
                bary if smooth else np.zeros((0, 9)), mesh.faces, _rotation(), objects is not None, object_ids,
                face_object, first, False, np.empty((0, 0), np.float32), 0.1, 100.0, True,
                False, np.empty((0, 0, 2), np.float32), np.zeros((0, 6)))


def _flat_reference(ids, mesh):
    camera = mesh.face_normals.astype(np.float64) @ _rotation().T
    camera[np.all(mesh.face_normals == 0, axis=1)] = np.nan
    out = np.full(ids.shape + (3,), np.nan, np.float32)
    seen = ids >= 0
    out[seen] = camera[ids[seen]]
    return out


@pytest.mark.parametrize("width", [3 * BLOCK, 3 * BLOCK + 5, BLOCK - 1, 1])
@pytest.mark.parametrize("threads", [1, 2])
def test_flat_normals_match_the_numpy_reference(width, threads):
    mesh = _mesh()
    ids = _ids(23, width, len(mesh.faces))
    maps = _maps(ids, mesh)
    run_workers(surface_maps, ids, maps, threads=threads)
    expected = _flat_reference(ids, mesh)
    assert np.array_equal(np.isnan(maps.normals), np.isnan(expected))
    np.testing.assert_allclose(maps.normals, expected, rtol=0, atol=1e-6)
    assert np.isnan(maps.normals[ids == 5]).all() and np.isnan(maps.normals[ids < 0]).all()


def test_smooth_normals_match_the_numpy_reference():
    from rasterkit.raster.kernels.shade import bary_matrices

    mesh = _mesh(degenerate=False)  # smooth normals of a face without area mean nothing
    height, width = 19, 2 * BLOCK + 3
    rng = np.random.default_rng(3)
    clip = np.concatenate([rng.uniform(0, width, (len(mesh.vertices), 2)),
                           rng.uniform(0.5, 2.0, (len(mesh.vertices), 2))], axis=1)
    bary = bary_matrices(clip, mesh.faces)
    ids = _ids(height, width, len(mesh.faces))
    maps = _maps(ids, mesh, smooth=True, bary=bary)
    run_workers(surface_maps, ids, maps, threads=2)
    y, x = np.mgrid[0:height, 0:width] + 0.5
    seen = ids >= 0
    f = ids[seen]
    b = np.stack([bary[f, 3 * k] * x[seen] + bary[f, 3 * k + 1] * y[seen] + bary[f, 3 * k + 2] for k in range(3)], 1)
    b[b.sum(axis=1) < 0] *= -1
    world = np.einsum("pk,pkc->pc", b, maps.vertex_normals[mesh.faces[f]])
    camera = world @ _rotation().T
    expected = np.full((height, width, 3), np.nan)
    expected[seen] = camera / np.linalg.norm(camera, axis=1, keepdims=True)
    assert np.array_equal(np.isnan(maps.normals), np.isnan(expected))
    np.testing.assert_allclose(maps.normals, expected, rtol=0, atol=1e-5)


@pytest.mark.parametrize("normals", [True, False])
def test_object_ids_match_the_numpy_reference(normals):
    mesh = _mesh(m=60)
    ids = _ids(21, 3 * BLOCK + 7, len(mesh.faces))
    objects = [10, 25, 25]
    maps = _maps(ids, mesh, objects=objects, normals=normals)
    original = ids.copy()
    run_workers(surface_maps, ids, maps, threads=2)
    first = np.array([0, 10, 35])
    owner = np.searchsorted(first, original, side="right") - 1
    assert np.array_equal(maps.object_ids, np.where(original >= 0, owner, -1))
    assert np.array_equal(ids, np.where(original >= 0, original - first[np.maximum(owner, 0)], -1))
    if normals:
        np.testing.assert_allclose(maps.normals, _flat_reference(original, mesh), rtol=0, atol=1e-6)


def test_camera_rotation_turns_the_view_direction_to_minus_z_and_is_made_once():
    camera = rasterkit.Camera.look_at((1.0, 2.0, 5.0), (0.2, -0.1, 0.0), up=(0, 1, 0), width=8, height=8)
    r = camera.rotation()
    assert r is camera.rotation() and not r.flags.writeable
    np.testing.assert_allclose(r @ r.T, np.eye(3), atol=1e-12)
    view = np.subtract((0.2, -0.1, 0.0), (1.0, 2.0, 5.0))
    np.testing.assert_allclose(r @ (view / np.linalg.norm(view)), [0, 0, -1], atol=1e-12)
    np.testing.assert_allclose(r @ (0, 1, 0), [0, np.sqrt(1 - (r[2] @ (0, 1, 0)) ** 2), r[2] @ (0, 1, 0)], atol=1e-12)
