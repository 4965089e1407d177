"""Tune the sub-pixel sample pattern of ``render(..., samples=n)`` for coverage, and measure it.

    python scripts/tune_samples.py tune 16 [--seed 2] [--steps 40000] [--restarts 3]
                                           [--min-angle 10] [--wedge-weight 0.25]
    python scripts/tune_samples.py measure [4 8 16 32]

``tune`` searches for ``n`` points in the pixel square whose fraction on one side of any
straight edge is nearest the area on that side (half-planes: the pixels one edge crosses),
then, keeping that, whose errors over wedges (the pixels a corner is in or near) are
smallest on average (:mod:`coverage_error`), and prints the pattern as offsets from the
pixel centre in 1/256 pixel, the table of :mod:`rasterkit.raster.samples`, with its worst errors.
``measure`` prints the worst errors of the patterns :func:`rasterkit.raster.samples.pixel_offsets`
gives, on grids denser than the search's and shifted from them.

The search is simulated annealing on positions (not only on shuffles of a stratified
pattern): each step moves one point by a random whole number of 1/256 pixel (the
rasterizer snaps vertices to 1/256 pixel, so jitter of whole units keeps every sample's
image exactly on that grid), up to ``reach`` units, ``reach`` shrinking geometrically; a
move is taken when it lowers the score, or else with probability ``exp(-Δ/T)``, the
temperature ``T`` falling geometrically. Half-planes are scored on the directions of every
two samples and a 1024-direction grid (the worst, plus a tenth of the mean of the 32 worst,
which guides the search when a move leaves the worst unchanged); wedges of at least
``--min-angle`` degrees on a 10 x 10 grid of apexes in the pixel and 12 x 12 over [-4, 5]²
around it. Everything is driven by ``numpy.random.default_rng(seed)``: the same command,
the same pattern.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from coverage_error import apex_grid, direction_errors, measure, pair_directions, wedge_errors  # noqa: E402

UNITS = 256  # sample positions are q / 256, q in 1..255 (offsets from the centre: q - 128)
_THETAS = np.arange(1024) * (np.pi / 1024) + 1e-4
_APEXES = apex_grid(10, 12, reach=4.0, shift=0.37)
MIN_ANGLE = 10.0  # degrees: the corners the search keeps within bounds (--min-angle)


WEIGHT = 0.25  # the weight of the wedges' mean error against the half-planes' (--wedge-weight)


def score(points, min_angle: float = MIN_ANGLE, weight: float = WEIGHT) -> tuple[float, float]:
    """(search score, worst training half-plane error): the worst half-plane error, plus a
    tenth of the mean of the 32 worst (which guides the search when a move leaves the worst
    unchanged), plus ``weight`` times the mean over the training apexes of the worst wedge
    (of at least ``min_angle`` degrees) at each (none when ``weight`` is 0)."""
    thetas = np.concatenate([_THETAS, pair_directions(points)])
    half, _ = direction_errors(points, thetas)
    top = np.partition(half, len(half) - 32)[-32:]
    total = top.max() + 0.1 * top.mean()
    if weight:
        total += weight * wedge_errors(points, _APEXES, math.radians(min_angle)).mean()
    return float(total), float(top.max())


def start(n: int, rng) -> np.ndarray:
    """A jittered-grid start: one point in each cell of an m x n/m grid."""
    m = max(d for d in range(1, math.isqrt(n) + 1) if n % d == 0)
    k = n // m
    cells = np.array([(i, j) for j in range(k) for i in range(m)], float)
    xy = (cells + rng.uniform(0.2, 0.8, (n, 2))) / (m, k)
    return np.clip(np.round(xy * UNITS), 1, UNITS - 1).astype(np.int64)


def anneal(n: int, rng, steps: int, q=None, hot: float = 0.01, reach0: int = 48, cap: float = 1.0,
           **kw) -> np.ndarray:
    """One annealing run from ``q`` (integer positions) or a jittered grid, the temperature
    falling from ``hot`` to 0.0002 and the reach from ``reach0`` to 1; moves whose worst
    training half-plane error exceeds ``cap`` are refused. The best pattern seen (integer
    positions, (n, 2))."""
    q = start(n, rng) if q is None else q.copy()
    current, _ = score(q / UNITS, **kw)
    best_q, best = q.copy(), current
    for step in range(steps):
        frac = step / steps
        temperature = hot * (0.0002 / hot) ** frac
        reach = max(1, int(round(reach0 * (1 / reach0) ** frac)))
        i = rng.integers(n)
        trial = q.copy()
        trial[i] = np.clip(trial[i] + rng.integers(-reach, reach + 1, 2), 1, UNITS - 1)
        if len({tuple(p) for p in trial}) < n:
            continue
        s, worst = score(trial / UNITS, **kw)
        if worst > cap:
            continue
        if s <= current or rng.random() < math.exp(-(s - current) / temperature):
            q, current = trial, s
            if s < best:
                best_q, best = trial.copy(), s
    return best_q


def half_plane_worst(q) -> float:
    """The worst half-plane error of integer positions ``q``, on 4096 directions and those
    of every two points."""
    points = q / UNITS
    return float(direction_errors(points, np.r_[np.arange(4096) * (np.pi / 4096), pair_directions(points)])[0].max())


def tune(n: int, seed: int, steps: int, restarts: int, min_angle: float = MIN_ANGLE,
         weight: float = WEIGHT) -> np.ndarray:
    """Two stages; integer positions (n, 2), sorted by row.

    1. Half-planes: ``restarts`` annealing runs (each polished by a cold run of a quarter
       of the steps), the best by :func:`half_plane_worst`.
    2. Wedges: from that pattern, a cold run of half the steps adding the wedges' mean error
       (``weight``), refusing any move that raises the worst training half-plane error."""
    rng = np.random.default_rng(seed)
    best_q, best_half = None, np.inf
    for r in range(restarts):
        q = anneal(n, rng, steps, weight=0.0)
        q = anneal(n, rng, steps // 4, q, hot=0.001, reach0=4, weight=0.0)
        half = half_plane_worst(q)
        print(f"run {r}: half-plane {half:.4f}", file=sys.stderr, flush=True)
        if half < best_half:
            best_q, best_half = q, half
    if weight:
        cap = score(best_q / UNITS, weight=0.0)[1]
        q = anneal(n, rng, steps // 2, best_q, hot=0.001, reach0=8, cap=cap, min_angle=min_angle, weight=weight)
        print(f"wedges: half-plane {half_plane_worst(q):.4f}", file=sys.stderr, flush=True)
        best_q = q
    return best_q[np.lexsort((best_q[:, 0], best_q[:, 1]))]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)
    t = sub.add_parser("tune")
    t.add_argument("n", type=int)
    t.add_argument("--seed", type=int, default=2)
    t.add_argument("--steps", type=int, default=40000)
    t.add_argument("--restarts", type=int, default=3)
    t.add_argument("--min-angle", type=float, default=MIN_ANGLE)
    t.add_argument("--wedge-weight", type=float, default=WEIGHT)
    m = sub.add_parser("measure")
    m.add_argument("n", type=int, nargs="*", default=[4, 8, 16, 32])
    args = parser.parse_args(argv)
    if args.command == "tune":
        q = tune(args.n, args.seed, args.steps, args.restarts, min_angle=args.min_angle, weight=args.wedge_weight)
        offsets = [(int(x) - UNITS // 2, int(y) - UNITS // 2) for x, y in q]
        print(f"{args.n}: {tuple(offsets)},")
        points = q / UNITS
    else:
        from rasterkit.raster.samples import pixel_offsets

        for n in args.n:
            worst = measure(pixel_offsets(n) + 0.5, MIN_ANGLE)
            print(f"{n:3d} samples: " + ", ".join(f"{k} {v:.4f}" for k, v in worst.items()))
        return 0
    worst = measure(points, args.min_angle)
    print("# worst errors: " + ", ".join(f"{k} {v:.4f}" for k, v in worst.items()))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
