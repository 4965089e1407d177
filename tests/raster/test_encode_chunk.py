"""The lit rows' chunk-wise sRGB encoding (rasterkit.raster.kernels.lit_columns.encode_chunk)
against the per-value definition it replaces: ``to_u8(255 * encode(table, x))`` for each
channel, packed with an opaque alpha."""

from __future__ import annotations

import numpy as np

from rasterkit.raster.kernels.lit_columns import AR, CHUNK, SCRATCH, SHADE, encode_chunk
from rasterkit.raster.kernels.shade import to_u8
from rasterkit.raster.kernels.surface import encode, encode_table
from rasterkit.runtime.jit import kernel


@kernel
def _chunked(values, table, n):
    s = np.zeros(SCRATCH)
    for channel in range(3):
        for q in range(n):
            s[AR + np.uint64(channel * CHUNK + q)] = values[q, channel]
    encode_chunk(s, n, table)
    out = np.empty(n, np.int64)
    for q in range(n):
        out[q] = np.int64(s[SHADE + np.uint64(q)])
    return out


@kernel
def _one_by_one(values, table, n):
    out = np.empty(n, np.int64)
    for q in range(n):
        rgba = 255 << 24
        for channel in range(3):
            rgba |= to_u8(encode(table, values[q, channel]) * 255.0) << (8 * channel)
        out[q] = rgba
    return out


def test_the_chunk_encodes_each_value_as_the_per_value_encoding_does():
    rng = np.random.default_rng(3)
    table = encode_table()
    special = np.array([0.0, -0.0, 1.0, 1e-12, -1e-3, 1.5, 1e300, -np.inf, np.inf, np.nan,
                        0.0031308, 0.5, 0.999999, 1.0 / 4096, 2.0 / 4096 - 1e-17])
    for trial in range(40):
        n = int(rng.integers(1, CHUNK + 1))
        values = rng.uniform(-0.05, 1.05, size=(n, 3))
        if trial % 4 == 0:
            values = rng.uniform(0.0, 0.01, size=(n, 3)) ** 2  # the steep, linear part of the curve
        values.flat[rng.integers(0, values.size, size=min(values.size, 6))] = rng.choice(special, 6)[:min(
            values.size, 6)]
        np.testing.assert_array_equal(_chunked(values, table, n), _one_by_one(values, table, n))
