"""Sealed memory for readers (:func:`rasterkit.mesh.checks.sealed_empty`): an array filled
once through its writeable twin, which a Mesh then keeps as it is, and which nothing can
write to afterwards."""

from __future__ import annotations

import numpy as np
import pytest

from rasterkit.mesh import Mesh, immutable
from rasterkit.mesh.checks import sealed_empty


@pytest.mark.parametrize("shape, dtype", [((4, 3), np.float64), ((1000, 3), np.int64), ((7,), np.uint8),
                                          ((0, 3), np.int64), ((1,), np.uint8)])
def test_the_sealed_array_shows_what_its_twin_writes_and_cannot_be_made_writeable(shape, dtype):
    sealed, fill = sealed_empty(shape, dtype)
    assert sealed.shape == fill.shape == shape and sealed.dtype == fill.dtype == dtype
    assert immutable(sealed) and not sealed.any()
    values = np.arange(1, fill.size + 1, dtype=dtype).reshape(shape)  # no zero: the one-byte array too
    fill[...] = values
    np.testing.assert_array_equal(sealed, values)
    with pytest.raises(ValueError):
        sealed.flags.writeable = True
    with pytest.raises(ValueError):
        sealed[...] = 0


def test_the_memory_lives_as_long_as_either_array():
    sealed, fill = sealed_empty((1 << 16,), np.int64)
    del sealed
    fill[:] = 5  # the twin keeps the bytes alive
    assert int(fill.sum()) == 5 << 16
    sealed, fill = sealed_empty((1 << 16,), np.int64)
    fill[:] = 3
    del fill
    assert int(sealed.sum()) == 3 << 16


def test_a_mesh_keeps_sealed_arrays_without_a_copy_and_copies_others():
    vertices, fill_v = sealed_empty((4, 3), np.float64)
    fill_v[:] = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
    faces, fill_f = sealed_empty((2, 3), np.int64)
    fill_f[:] = [[0, 1, 2], [0, 2, 3]]
    del fill_v, fill_f
    mesh = Mesh(vertices, faces)
    assert mesh.vertices is vertices and mesh.faces is faces
    plain = np.array([[0, 1, 2], [0, 2, 3]])
    other = Mesh(vertices, plain)
    assert not np.shares_memory(other.faces, plain) and immutable(other.faces)
