"""The barycentric rows of a frame's faces made in parallel pieces
(:func:`rasterkit.raster.kernels.shade.bary_chunks`) against the definition: row ``k`` of
``adj([h0 h1 h2])`` is ``h_{k+1} x h_{k+2}`` of the corners' (x, y, w), scaled by their
largest magnitude, zeros for a face without a finite, non-zero one."""

import numpy as np
import pytest

from rasterkit.raster.kernels.shade import bary_chunks, bary_matrices
from rasterkit.runtime.threads import run_workers


def _reference(clip, faces):
    out = np.zeros((len(faces), 9))
    for f, corners in enumerate(faces):
        h = clip[corners][:, [0, 1, 3]]
        scale = np.abs(h).max()
        if not (scale > 0.0 and np.isfinite(scale)):
            continue
        h = h / scale
        for k in range(3):
            out[f, 3 * k:3 * k + 3] = np.cross(h[(k + 1) % 3], h[(k + 2) % 3])
    return out


@pytest.mark.parametrize("threads", [1, 2])
def test_rows_made_in_pieces_equal_the_definition_and_the_whole_table(threads):
    rng = np.random.default_rng(7)
    clip = rng.normal(size=(50, 4)) * rng.choice([1e-3, 1.0, 1e6], size=(50, 1))
    clip[3] = 0.0  # a corner at the origin: a face of it and two other such corners has no scale
    clip[4] = (np.inf, 1.0, 0.0, 1.0)  # an infinite corner
    faces = rng.integers(0, 50, size=(203, 3)).astype(np.int64)  # not a multiple of the pieces
    faces[0] = (3, 3, 3)
    faces[1] = (4, 5, 6)
    out = np.full((len(faces), 9), 7.0)  # stale values: every row is written
    run_workers(bary_chunks, clip, faces, out, threads=threads)
    expected = _reference(clip, faces)
    assert np.array_equal(out[:2], np.zeros((2, 9)))
    np.testing.assert_allclose(out, expected, rtol=1e-12, atol=1e-12)
    assert np.array_equal(out, bary_matrices(clip, faces))  # the same arithmetic, bit for bit
