"""Painting a band's marked pixels: the plain wireframe marks its lines' pixels in a byte
mask (one byte store per pixel, in a buffer that stays in the thread's cache), then paints
the marked pixels of the band's colour rows 8 at a time (:func:`paint_marked`)."""

import numpy as np

from rasterkit.runtime.jit import kernel
from rasterkit.runtime.intrinsics import load_word, store_word
from rasterkit.raster.kernels.line import put_pixel

#: ``bits = (word * _GATHER) >> 56`` turns 8 mask bytes of 0 or 1 into 8 bits (bit k = byte k).
_GATHER = 0x0102040810204080


@kernel
def paint_tables(rgba):
    """For the masked colour pass of C = ``rgba.size`` channels, 8 pixels (C 64-bit words)
    at a time: ``select[bits]``, the C words with 0xFF in the bytes of the pixels whose bit
    is set, and ``paint``, the C words of ``rgba`` repeated over 8 pixels."""
    channels = rgba.size
    select = np.zeros((256, channels), np.uint64)
    paint = np.zeros(channels, np.uint64)
    for b in range(8 * channels):
        word, shift = b // 8, np.uint64(8 * (b % 8))
        paint[word] |= np.uint64(rgba[b % channels]) << shift
        for bits in range(256):
            if (bits >> (b // channels)) & 1:
                select[bits, word] |= np.uint64(0xFF) << shift
    return select, paint


@kernel(refcounts=False)
def paint_marked(cflat, mflat, lo, hi, rgba, select, paint):
    """Colour ``rgba`` into the pixels ``lo .. hi - 1`` whose mask byte is 1 (the others
    are 0): eight pixels per mask word, unmarked groups skipped, each marked group blended
    in C 64-bit words by the byte masks of :func:`paint_tables`."""
    channels = rgba.size
    p = lo
    while p < hi and p % 8 != 0:
        if mflat[p]:
            put_pixel(cflat, p, channels, rgba)
        p += 1
    groups = (hi - p) // 8
    if groups > 0:
        first_byte = p * channels
        for g in range(groups):
            mark = load_word(mflat, p + 8 * g)
            if mark == 0:
                continue
            bits = (mark * np.uint64(_GATHER)) >> np.uint64(56)
            for k in range(channels):
                sel = select[bits, k]
                at = first_byte + 8 * (g * channels + k)
                store_word(cflat, at, (load_word(cflat, at) & ~sel) | (paint[k] & sel))
        p += 8 * groups
    while p < hi:
        if mflat[p]:
            put_pixel(cflat, p, channels, rgba)
        p += 1
