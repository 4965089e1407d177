"""Sums of the samples of a multi-sample render, and their average (rasterkit.raster.accumulate)."""

import numpy as np

from rasterkit.runtime.jit import kernel
from rasterkit.runtime.intrinsics import fetch_add

#: The pixels are summed in this many contiguous chunks, shared out among the threads.
N_CHUNKS = 32


@kernel(refcounts=False)
def add_sample(slot, counter, total, color, first):
    """``total += color`` ((P,) uint16 and (P,) uint8, the flattened images); ``first``
    writes ``total = color`` instead (no separate clear). A worker of
    :func:`rasterkit.runtime.threads.run_workers` (``slot`` unused; chunks claimed through ``counter``).
    """
    n = total.shape[0]
    while True:
        ch = fetch_add(counter, 0, 1)
        if ch >= N_CHUNKS:
            break
        lo, hi = n * ch // N_CHUNKS, n * (ch + 1) // N_CHUNKS
        if first:
            for i in range(lo, hi):
                total[i] = color[i]
        else:
            for i in range(lo, hi):
                total[i] += color[i]


@kernel(refcounts=False)
def average_samples(slot, counter, total, color, scale, bias):
    """``color = floor(total·scale + bias)``: with ``scale = 1/n`` and ``bias = (n//2 + 1/2)/n``
    this is ``(total + n//2) // n``, the sum of n samples divided with rounding (the extra
    ``1/(2n)`` keeps the floor off the float rounding: the exact quotient's fraction lies in
    [1/(2n), 1 - 1/(2n)]). A worker like :func:`add_sample`.
    """
    n = total.shape[0]
    while True:
        ch = fetch_add(counter, 0, 1)
        if ch >= N_CHUNKS:
            break
        for i in range(n * ch // N_CHUNKS, n * (ch + 1) // N_CHUNKS):
            color[i] = int(total[i] * scale + bias)


@kernel(refcounts=False)
def add_sample_rgba(slot, counter, premultiplied, alpha, color, first):
    """RGBA images: ``premultiplied += colour·alpha`` ((P, 3) uint32) and ``alpha += alpha``
    ((P,) uint32), from ``color`` (P, 4) uint8; ``first`` writes instead of adding. Averaging
    premultiplied colour keeps a half-covered edge over a transparent background its own
    colour at half opacity (straight averages would darken it towards the background's
    black). A worker like :func:`add_sample`."""
    n = alpha.shape[0]
    keep = np.uint32(0 if first else 1)  # 0: the uninitialised sums are overwritten
    while True:
        ch = fetch_add(counter, 0, 1)
        if ch >= N_CHUNKS:
            break
        for i in range(n * ch // N_CHUNKS, n * (ch + 1) // N_CHUNKS):
            a = np.uint32(color[i, 3])
            alpha[i] = alpha[i] * keep + a
            for c in range(3):
                premultiplied[i, c] = premultiplied[i, c] * keep + np.uint32(color[i, c]) * a


@kernel(refcounts=False)
def average_samples_rgba(slot, counter, premultiplied, alpha, color, n_samples):
    """The average of :func:`add_sample_rgba`'s sums of ``n_samples`` samples into ``color``
    (P, 4) uint8, straight (not premultiplied) as every RGBA image of rasterkit: colour =
    the sum of colour·alpha over the sum of alpha (0 where nothing is opaque), alpha = the
    mean alpha, both rounded to nearest."""
    n = alpha.shape[0]
    while True:
        ch = fetch_add(counter, 0, 1)
        if ch >= N_CHUNKS:
            break
        for i in range(n * ch // N_CHUNKS, n * (ch + 1) // N_CHUNKS):
            a = alpha[i]
            for c in range(3):
                color[i, c] = (premultiplied[i, c] + a // 2) // a if a > 0 else 0
            color[i, 3] = (a + n_samples // 2) // n_samples
