"""Fixed sample patterns: where the samples of a multi-sample render fall in a pixel and on a lens.

Every pattern is a pure function of the number of samples (and a fixed seed): the same
points in every run, on every machine, at any thread count.

- :func:`square`: correlated multi-jittered points in the unit square (Kensler 2013): ``n``
  points on an ``m x k`` grid (``m·k = n``, ``m`` the largest divisor of ``n`` up to
  ``sqrt(n)``), one in every cell of the grid (stratified in 2D) and one in every ``1/n``
  strip of each axis (stratified in each 1D projection, the "n-rooks" property), so an edge
  near an axis is sampled as finely as ``n`` allows. The shuffles and jitter come from a
  fixed-seed SplitMix64 stream.
- :func:`concentric_disc`: Shirley and Chiu's concentric map of the square onto the unit
  disc, which keeps the strata (and their areas) of a square pattern.
- :func:`pixel_offsets` and :func:`lens_points`: the pixel jitter and the lens points of
  :func:`rasterkit.render`'s samples; the lens points are shuffled with another seed, so
  that sample ``s``'s lens point does not follow its place in the pixel. Every pixel offset
  is a whole number of 1/256 pixel, the rasterizer's fixed point: for 4, 8, 16 and 32
  samples a table tuned for coverage (:data:`_PIXEL`), for other counts :func:`square`'s
  points moved onto that grid.

A single sample (``n = 1``) is the pixel centre and the lens centre: the pinhole image.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from rasterkit.options import MAX_SAMPLES  # at most 256: the colour sums of a render are 16 bits (256 · 255 < 2**16)

__all__ = ["MAX_SAMPLES", "concentric_disc", "lens_points", "pixel_offsets", "square"]

_MASK64 = (1 << 64) - 1
_PIXEL_SEED, _LENS_SEED, _PAIRING_SEED = 0x5EED_0001, 0x5EED_0002, 0x5EED_0003


def _stream(seed: int):
    """SplitMix64 (Steele, Lea and Flood 2014): a fixed, portable stream of floats in [0, 1)."""
    state = seed & _MASK64
    while True:
        state = (state + 0x9E3779B97F4A7C15) & _MASK64
        z = state
        z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & _MASK64
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & _MASK64
        yield ((z ^ (z >> 31)) >> 11) * (1.0 / (1 << 53))


def _shuffle(n: int, stream) -> list[int]:
    """A permutation of range(n): Fisher–Yates driven by ``stream``."""
    p = list(range(n))
    for i in range(n - 1, 0, -1):
        j = min(int(next(stream) * (i + 1)), i)
        p[i], p[j] = p[j], p[i]
    return p


def _grid(n: int) -> tuple[int, int]:
    """(m, k): m the largest divisor of n with m <= sqrt(n), k = n // m."""
    m = max(d for d in range(1, math.isqrt(n) + 1) if n % d == 0)
    return m, n // m


def check_samples(n) -> int:
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)):
        raise TypeError(f"samples must be an integer, got {type(n).__name__}")
    if not 1 <= n <= MAX_SAMPLES:
        raise ValueError(f"samples must be 1 to {MAX_SAMPLES}, got {n}")
    return int(n)


#: Pixel samples tuned for coverage, as offsets from the pixel centre in 1/256 pixel (whole
#: units of the rasterizer's fixed point: each sample sees the snapped vertices exactly
#: shifted). Found by simulated annealing of the positions on that grid,
#: ``python scripts/tune_samples.py tune N --seed 2`` with ``--steps 20000 --restarts 3``
#: (4, 8), ``--steps 40000 --restarts 3`` (16), ``--steps 20000 --restarts 1
#: --wedge-weight 0`` (32): first the worst error over every half-plane (a pixel one
#: straight edge crosses: the fraction of samples on one side against the exact area, the
#: top-left rule free to count a sample on the edge either way), then the mean error over
#: wedges (the pixels a corner is in or near). Worst errors
#: (``python scripts/tune_samples.py measure``):
#:
#: ====  ==========  ==========================  ==================================
#: n     one edge    two parallel edges (strip)  two edges at any angle (wedge)
#: ====  ==========  ==========================  ==================================
#: 4     0.250       0.500                       0.500
#: 8     0.161       0.312                       0.318
#: 16    0.0957      0.189                       0.189
#: 32    0.0739      0.143                       0.145
#: ====  ==========  ==========================  ==================================
#:
#: (for one edge, the correlated multi-jittered points of :func:`square` give 0.35, 0.23,
#: 0.137 and 0.098; the 16 hand-tuned ones used before, 0.120). No ``n`` points do better
#: than ``1/n`` for one edge or ``2/n`` for two: a line through two samples moves the count
#: by 2, and a thin wedge along it holds two samples and almost no area; for 4 samples 0.250
#: is that least possible. In a rendered pixel, snapping the vertices to 1/256 pixel moves an
#: edge by at most 0.004 of the area and the 8-bit average rounds by at most 0.002. Measured
#: with 16 samples on 400 random triangles (``python scripts/coverage_triangles.py``): none
#: of the 97,460 pixels one edge crosses is beyond 1/10 (worst 0.0965); of the 2,331 pixels
#: holding or near a corner, 32 are (worst 0.147). A solid render through a pinhole does
#: better than its points there: a pixel where they saw one face and the background, or that
#: one face's outline crosses, gets the face's exact share of the pixel
#: (:meth:`rasterkit.raster.shared_samples.SharedTriangles.draw_average`).
_PIXEL = {
    4: ((-94, -111), (54, -37), (-54, 37), (94, 111)),
    8: ((64, -90), (-105, -83), (-15, -68), (98, -2), (-65, 16), (18, 25), (-73, 98), (84, 110)),
    16: ((89, -111), (-23, -105), (-78, -91), (24, -76), (-106, -56), (93, -48), (27, -16), (-88, -1),
         (-24, 0), (88, 16), (-6, 54), (-103, 69), (56, 70), (118, 77), (-66, 97), (7, 111)),
    32: ((-65, -121), (-21, -103), (77, -103), (5, -101), (34, -94), (-80, -78), (110, -69), (-98, -61),
         (-19, -54), (74, -53), (-73, -39), (69, -32), (25, -31), (-24, -21), (110, -16), (-114, -5),
         (-56, 8), (14, 10), (-120, 11), (85, 24), (4, 36), (41, 46), (97, 58), (-68, 64),
         (-26, 72), (106, 78), (-125, 95), (-38, 96), (51, 102), (78, 103), (-102, 108), (17, 121)),
}
_UNIT = 256  # 1 << SUBPIXEL_BITS (rasterkit.raster.kernels.face_setup)


@functools.lru_cache(maxsize=None)
def _square(n: int, seed: int) -> np.ndarray:
    m, k = _grid(n)
    stream = _stream(seed)
    column_shuffle, row_shuffle = _shuffle(m, stream), _shuffle(k, stream)
    points = np.empty((n, 2))
    for s in range(n):
        i, j = s % m, s // m  # the cell: column i of m, row j of k
        jx, jy = next(stream), next(stream)
        # x: strip i of m, sub-strip row_shuffle[j] of k in it; y likewise: n-rooks
        points[s] = ((i + (row_shuffle[j] + jx) / k) / m, (j + (column_shuffle[i] + jy) / m) / k)
    points.flags.writeable = False
    return points


@functools.lru_cache(maxsize=None)
def _offsets(n: int) -> np.ndarray:
    if n == 1:
        units = np.zeros((1, 2))
    elif n in _PIXEL:
        units = np.array(_PIXEL[n], np.float64)
    else:  # the square pattern, each point moved down-left onto the 1/256 grid
        units = np.floor(_square(n, _PIXEL_SEED) * _UNIT) - _UNIT // 2
    offsets = units / _UNIT
    offsets.flags.writeable = False
    return offsets


def square(n: int, seed: int = _PIXEL_SEED) -> np.ndarray:
    """``n`` correlated multi-jittered points in [0, 1)², (n, 2) float64, read-only.

    Raises ``TypeError`` for a non-integer ``n`` and ``ValueError`` outside 1..MAX_SAMPLES.
    """
    return _square(check_samples(n), int(seed))


def concentric_disc(points: np.ndarray) -> np.ndarray:
    """Shirley–Chiu concentric map of points in [0, 1]² onto the unit disc, (n, 2) float64.

    With ``(a, b) = 2p - 1``: where ``|a| > |b|``, radius ``a`` and angle ``(π/4)·b/a``;
    elsewhere radius ``b`` and angle ``π/2 - (π/4)·a/b``. Squares around the centre go to
    rings of the same area, so a stratified square pattern stays stratified on the disc.
    """
    a, b = 2.0 * points[:, 0] - 1.0, 2.0 * points[:, 1] - 1.0
    wide = np.abs(a) > np.abs(b)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.where(wide, a, b)
        phi = np.where(wide, (math.pi / 4) * b / a, math.pi / 2 - (math.pi / 4) * a / b)
    phi = np.where(r == 0.0, 0.0, phi)
    return np.stack([r * np.cos(phi), r * np.sin(phi)], axis=1)


def pixel_offsets(n: int) -> np.ndarray:
    """Sub-pixel offsets of the ``n`` samples of a pixel, in pixels, each in [-1/2, 1/2)² and
    a whole number of 1/256 pixel, (n, 2) float64 (x right, y down), read-only: the tuned
    table of ``n`` (:data:`_PIXEL`) or :func:`square`'s points on the 1/256 grid; one
    sample: the pixel centre, (0, 0)."""
    return _offsets(check_samples(n))


def lens_points(n: int) -> np.ndarray:
    """Points of the ``n`` samples on the unit lens disc (radius 1; x right, y up), (n, 2)
    float64, stratified (:func:`concentric_disc` of :func:`square`) and paired with the pixel
    offsets by a fixed shuffle; one sample: the lens centre, (0, 0)."""
    n = check_samples(n)
    if n == 1:
        return np.zeros((1, 2))
    disc = concentric_disc(np.asarray(square(n, _LENS_SEED)))
    return disc[_shuffle(n, _stream(_PAIRING_SEED))]
