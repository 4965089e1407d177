"""The coverage error of ``render(..., samples=n)`` on random triangles, rendered by rasterkit.

    python scripts/coverage_triangles.py [--samples 16] [--triangles 400] [--seed 2026]
                                         [--min-angle 0]

Each triangle (vertices uniform in [-1.4, 1.4]² on the plane z = 0, seen by the tests' 160 x
120 camera; kept when its raster area is at least 400 px² and its smallest angle at least
``--min-angle`` degrees) is rendered black on white; a pixel's grey ``1 - value/255``
(everything the rasterizer does: vertices snapped to 1/256 px, the top-left rule, samples
at the pixel centre plus the pattern's offsets, the average rounded to 8 bits) is compared
with the exact covered fraction of its square (the triangle clipped to the square,
Sutherland–Hodgman, and the shoelace area). The errors are reported by the kind of pixel:
crossed by one edge, holding a corner, crossed by two edges near a corner.
"""

from __future__ import annotations

import argparse
import math

import numpy as np

import rasterkit
from rasterkit import Camera

WIDTH, HEIGHT = 160, 120
CAMERA = Camera.look_at((0.0, 0.0, 4.0), (0.0, 0.0, 0.0), fov_y=40.0, width=WIDTH, height=HEIGHT)


def clip_area(polygon, x0: float, y0: float) -> float:
    """Area of a convex polygon ((k, 2) list) within the pixel square [x0, x0+1] x [y0, y0+1]."""
    poly = [tuple(p) for p in polygon]
    for axis, bound, keep_above in ((0, x0, True), (0, x0 + 1, False), (1, y0, True), (1, y0 + 1, False)):
        out = []
        for k, cur in enumerate(poly):
            prev = poly[k - 1]
            cin = (cur[axis] >= bound) if keep_above else (cur[axis] <= bound)
            pin = (prev[axis] >= bound) if keep_above else (prev[axis] <= bound)
            if cin != pin:
                t = (bound - prev[axis]) / (cur[axis] - prev[axis])
                out.append((prev[0] + t * (cur[0] - prev[0]), prev[1] + t * (cur[1] - prev[1])))
            if cin:
                out.append(cur)
        poly = out
        if not poly:
            return 0.0
    return 0.5 * abs(sum(a[0] * b[1] - b[0] * a[1] for a, b in zip(poly, poly[1:] + poly[:1])))


def pixel_kinds(xy, i: int, j: int) -> str:
    """'corner' (a vertex in the pixel), 'two edges' or 'one edge' (edges crossing it)."""
    if any(i < x < i + 1 and j < y < j + 1 for x, y in xy):
        return "corner"
    crossing = 0
    for k in range(3):
        (ax, ay), (bx, by) = xy[k], xy[(k + 1) % 3]
        lo, hi = 0.0, 1.0  # Liang–Barsky: the part of the segment inside the square
        for p, q in ((-(bx - ax), ax - i), (bx - ax, i + 1 - ax), (-(by - ay), ay - j), (by - ay, j + 1 - ay)):
            if p == 0:
                if q < 0:
                    lo, hi = 1.0, 0.0
            elif p < 0:
                lo = max(lo, q / p)
            else:
                hi = min(hi, q / p)
        crossing += lo < hi
    return "two edges" if crossing >= 2 else "one edge"


def min_angle(xy) -> float:
    """The triangle's smallest angle, degrees."""
    angles = []
    for k in range(3):
        u, v = xy[(k + 1) % 3] - xy[k], xy[(k + 2) % 3] - xy[k]
        angles.append(math.degrees(math.acos(np.clip(u @ v / np.hypot(*u) / np.hypot(*v), -1, 1))))
    return min(angles)


def triangles(count: int, seed: int, smallest: float):
    """Random triangles: (world vertices (3, 3), raster xy (3, 2), raster area)."""
    rng = np.random.default_rng(seed)
    done = 0
    while done < count:
        v = np.c_[rng.uniform(-1.4, 1.4, (3, 2)), np.zeros(3)]
        xy = CAMERA.project(v)[:, :2]
        (ax, ay), (bx, by) = xy[1] - xy[0], xy[2] - xy[0]
        area = 0.5 * abs(ax * by - ay * bx)
        if area >= 400 and min_angle(xy) >= smallest:
            done += 1
            yield v, xy, area


def errors(v, xy, samples: int):
    """[(kind, error)] over the pixels the triangle's edges cross, and the total grey's
    relative error."""
    fb = rasterkit.render((v, np.array([(0, 1, 2)])), CAMERA, "solid", cull="none", color="black",
                          background="white", samples=samples)
    dark = 1.0 - fb.color[..., 0] / 255.0
    x0, y0 = np.maximum(np.floor(xy.min(axis=0)).astype(int), 0)
    x1, y1 = np.minimum(np.ceil(xy.max(axis=0)).astype(int), (WIDTH, HEIGHT))
    out, exact_total = [], 0.0
    for j in range(y0, y1):
        for i in range(x0, x1):
            exact = clip_area(xy, i, j)
            exact_total += exact
            if 0.0 < exact < 1.0:
                out.append((pixel_kinds(xy, i, j), abs(dark[j, i] - exact)))
    return out, abs(dark.sum() - exact_total) / exact_total


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--samples", type=int, default=16)
    parser.add_argument("--triangles", type=int, default=400)
    parser.add_argument("--seed", type=int, default=2026)
    parser.add_argument("--min-angle", type=float, default=0.0)
    args = parser.parse_args(argv)
    by_kind, totals = {}, []
    for v, xy, _ in triangles(args.triangles, args.seed, args.min_angle):
        pixels, total = errors(v, xy, args.samples)
        totals.append(total)
        for kind, e in pixels:
            by_kind.setdefault(kind, []).append(e)
    for kind, e in sorted(by_kind.items()):
        e = np.array(e)
        print(f"{kind:10s} {e.size:7d} pixels: worst {e.max():.4f}, beyond 1/10: {np.sum(e > 0.1)}")
    print(f"total grey against the area: worst {max(totals):.4%}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
