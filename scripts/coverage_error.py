"""The coverage error of a sample pattern: how far the fraction of a pixel's samples that a
shape covers can be from the fraction of the pixel square it covers (numpy only).

A pattern is ``n`` points in the unit pixel square [0, 1]² (the pixel centre at (1/2, 1/2)).
For a region R the error is ``|k/n - area(R ∩ square)|``, ``k`` the samples in R. Edges of
the rasterizer may pass exactly through a sample (the top-left rule then decides), so every
sup below takes both limits: a sample on the boundary counted in and counted out.

- Half-planes (:func:`direction_errors`): for a direction θ and the half-planes
  ``{p : n·p < c}`` (``n = (cos θ, sin θ)``), the signed error ``e(c) = k(c)/n - A(c)``
  (A the exact area, :func:`halfplane_area`) is piecewise smooth and monotone between the
  samples' projections, so its extremes are at the projections, just before and after
  each. The worst half-plane of direction θ is ``max |e|``; the worst strip between two
  parallel lines, ``max e - min e`` (a strip's error is a difference of two ``e``).
- Cones (:func:`cone_errors`): for an apex ``a``, the sectors around ``a`` sorted by angle
  give ``e(φ) = k(φ)/n - S(φ)`` (S the exact area of the square within the angles below φ,
  :func:`sector_area`; outside the square a half-plane area); every region between two rays
  from ``a``, the two half-planes that meet at a triangle's corner, has the error
  ``e(φ2) - e(φ1)``, so the worst over all such wedges is ``max e - min e``. An apex inside
  the square is a pixel holding a corner; outside, a pixel near a corner that both of its
  edges cross (thin slivers included: a far apex is a strip).

- Wedges of a least opening (:func:`wedge_errors`): the same, the two sides at least
  ``min_angle`` apart (a triangle's corner of at least that angle).

The sups over θ and over the apex are taken on grids (:func:`measure`), those over the
position of the lines exactly. ``tests/raster/test_coverage.py`` checks these against clipping.
"""

from __future__ import annotations

import numpy as np

__all__ = ["apex_grid", "cone_errors", "direction_errors", "halfplane_area", "measure", "pair_directions",
           "sector_area", "wedge_errors"]

_TIE = 1e-12  # projections or angles closer than this are one (samples on one line)


def halfplane_area(nx, ny, c):
    """Area of ``{p in [0, 1]² : nx·px + ny·py < c}`` for unit normals (arrays broadcast).

    The projection ``n·p`` of a uniform point is the sum of uniform variables on ``[0, |nx|]``
    and ``[0, |ny|]`` (shifted by the negative parts): a trapezoidal density, whose
    distribution function is this area."""
    nx, ny, c = np.broadcast_arrays(np.asarray(nx, float), np.asarray(ny, float), np.asarray(c, float))
    a, b = np.minimum(np.abs(nx), np.abs(ny)), np.maximum(np.abs(nx), np.abs(ny))
    t = c - np.minimum(nx, 0.0) - np.minimum(ny, 0.0)
    t = np.clip(t, 0.0, a + b)
    tiny = a < 1e-12
    a_safe = np.where(tiny, 1.0, a)
    ramp_up = t * t / (2 * a_safe * b)
    flat = (t - a / 2) / b
    ramp_down = 1.0 - (a + b - t) ** 2 / (2 * a_safe * b)
    area = np.where(t < a, ramp_up, np.where(t <= b, flat, ramp_down))
    return np.clip(np.where(tiny, t / b, area), 0.0, 1.0)


def sector_area(ax, ay, phi):
    """Area of the square seen from an inside apex ``(ax, ay)`` at angles in ``[-π, phi)``.

    Each side at distance ``h`` from the apex, between the angles ``lo`` and ``hi`` from its
    normal, adds the triangle ``h²/2·(tan ψ - tan lo)`` up to ``ψ = clip(phi - ν, lo, hi)``
    (the left side, which the angle -π cuts, counts as two pieces)."""
    ax, ay, phi = np.broadcast_arrays(np.asarray(ax, float), np.asarray(ay, float), np.asarray(phi, float))
    hr, ht, hl, hb = 1.0 - ax, 1.0 - ay, ax, ay
    pieces = (  # (h, normal angle ν, lo, hi)
        (hr, 0.0, -np.arctan(ay / hr), np.arctan((1 - ay) / hr)),
        (ht, np.pi / 2, -np.arctan((1 - ax) / ht), np.arctan(ax / ht)),
        (hl, np.pi, -np.arctan((1 - ay) / hl), 0.0 * hl),
        (hl, -np.pi, 0.0 * hl, np.arctan(ay / hl)),
        (hb, -np.pi / 2, -np.arctan(ax / hb), np.arctan((1 - ax) / hb)),
    )
    total = np.zeros(phi.shape)
    for h, nu, lo, hi in pieces:
        psi = np.clip(phi - nu, lo, hi)
        total += 0.5 * h * h * (np.tan(psi) - np.tan(lo))
    return total


def _extremes(key, area, n):
    """Signed errors at both limits of every sample: ``key`` (M, n) the samples' projections
    or angles, ``area`` (M, n) the exact area below each. Returns (M, 2n)."""
    below = (key[:, None, :] < key[:, :, None] - _TIE).sum(axis=2)
    upto = (key[:, None, :] <= key[:, :, None] + _TIE).sum(axis=2)
    return np.concatenate([below / n - area, upto / n - area], axis=1)


def direction_errors(points, thetas):
    """Worst half-plane and worst strip error of each direction: two (len(thetas),) arrays."""
    p = np.asarray(points, float)
    n = len(p)
    nx, ny = np.cos(thetas)[:, None], np.sin(thetas)[:, None]
    t = nx * p[:, 0] + ny * p[:, 1]
    e = _extremes(t, halfplane_area(nx, ny, t), n)
    half = np.abs(e).max(axis=1)
    strip = np.maximum(e.max(axis=1), 0.0) - np.minimum(e.min(axis=1), 0.0)
    return half, strip


def cone_errors(points, apexes):
    """Worst error over the wedges with each apex, (len(apexes),): ``max e - min e``.

    An apex inside the square uses angles in [-π, π) and :func:`sector_area`; outside, the
    angles from the direction to the square's centre (the square lies within ±π/2 of it) and
    the half-plane left of each ray."""
    p = np.asarray(points, float)
    a = np.asarray(apexes, float)
    n = len(p)
    inside = np.all((a > 0) & (a < 1), axis=1)
    out = np.empty(len(a))
    if inside.any():
        ai = a[inside]
        phi = np.arctan2(p[None, :, 1] - ai[:, 1:2], p[None, :, 0] - ai[:, 0:1])
        e = _extremes(phi, sector_area(ai[:, 0:1], ai[:, 1:2], phi), n)
        out[inside] = np.maximum(e.max(axis=1), 0.0) - np.minimum(e.min(axis=1), 0.0)
    if (~inside).any():
        ao = a[~inside]
        base = np.arctan2(0.5 - ao[:, 1:2], 0.5 - ao[:, 0:1])
        psi = np.arctan2(p[None, :, 1] - ao[:, 1:2], p[None, :, 0] - ao[:, 0:1]) - base
        psi = (psi + np.pi) % (2 * np.pi) - np.pi
        ux, uy = np.cos(base + psi), np.sin(base + psi)
        nx, ny = -uy, ux  # the samples clockwise of the ray: n·q < n·a
        area = halfplane_area(nx, ny, nx * ao[:, 0:1] + ny * ao[:, 1:2])
        e = _extremes(psi, area, n)
        out[~inside] = np.maximum(e.max(axis=1), 0.0) - np.minimum(e.min(axis=1), 0.0)
    return out


def _angles(points, apexes):
    """The samples' angles around each apex, (M, n), and ``e(φ)`` for any angles (M, k):
    inside the square absolute angles in [-π, π); outside, angles from the direction to the
    square's centre, in (-π/2, π/2) (e = 0 beyond)."""
    p, a = np.asarray(points, float), np.asarray(apexes, float)
    n = len(p)
    inside = np.all((a > 0) & (a < 1), axis=1)[:, None]
    base = np.where(inside, 0.0, np.arctan2(0.5 - a[:, 1:2], 0.5 - a[:, 0:1]))
    phi = np.arctan2(p[None, :, 1] - a[:, 1:2], p[None, :, 0] - a[:, 0:1]) - base
    phi = (phi + np.pi) % (2 * np.pi) - np.pi

    def area(angle):
        ux, uy = np.cos(base + angle), np.sin(base + angle)
        half = halfplane_area(-uy, ux, -uy * a[:, 0:1] + ux * a[:, 1:2])
        return np.where(inside, sector_area(a[:, 0:1], a[:, 1:2], angle), half)

    def e_at(angle):
        wrapped = (angle + np.pi) % (2 * np.pi) - np.pi
        ang = np.where(inside, wrapped, angle)
        count = (phi[:, None, :] < ang[:, :, None]).sum(axis=2)
        e = count / n - area(ang)
        return np.where(inside | (np.abs(ang) < np.pi / 2), e, 0.0)

    return phi, area(phi), e_at, inside


def wedge_errors(points, apexes, min_angle: float):
    """Worst error over the convex wedges with each apex whose opening is ``min_angle`` to π
    (a triangle's corner of at least that angle), (len(apexes),).

    The error of the wedge from φ1 to φ2 is ``e(φ2) - e(φ1)``; between samples ``e``
    decreases, so the extremes put each side just before or after a sample, or, where the
    opening bounds it, at a sample's angle ± ``min_angle`` or ± π. (Both sides free at the
    opening ``min_angle`` are taken on a 64-angle grid.)"""
    p = np.asarray(points, float)
    n = len(p)
    phi, area, e_at, inside = _angles(p, apexes)
    below = (phi[:, None, :] < phi[:, :, None] - _TIE).sum(axis=2) / n - area
    upto = (phi[:, None, :] <= phi[:, :, None] + _TIE).sum(axis=2) / n - area
    span = phi[:, None, :] - phi[:, :, None]  # [m, a, b]: from sample a to sample b
    span = np.where(inside[:, :, None], span % (2 * np.pi), span)
    ok = (span >= min_angle) & (span <= np.pi)
    pair = np.maximum(np.abs(upto[:, None, :] - below[:, :, None]), np.abs(below[:, None, :] - upto[:, :, None]))
    worst = np.where(ok, pair, 0.0).max(axis=(1, 2))
    for shift in (min_angle, np.pi):
        after, before = e_at(phi + shift), e_at(phi - shift)
        for ends in ((after, below), (after, upto), (upto, before), (below, before)):
            worst = np.maximum(worst, np.abs(ends[0] - ends[1]).max(axis=1))
    grid = np.arange(64) * (2 * np.pi / 64) - np.pi
    g = np.where(inside, grid[None, :], np.linspace(-np.pi / 2, np.pi / 2 - min_angle, 64)[None, :])
    return np.maximum(worst, np.abs(e_at(g + min_angle) - e_at(g)).max(axis=1))


def pair_directions(points):
    """Normals of the lines through every two samples (where projections tie), in [0, π)."""
    p = np.asarray(points, float)
    i, j = np.triu_indices(len(p), 1)
    d = p[j] - p[i]
    return (np.arctan2(d[:, 1], d[:, 0]) + np.pi / 2) % np.pi


def apex_grid(inside: int, outside: int, reach: float = 3.0, shift: float = 0.0):
    """Apexes: an ``inside x inside`` grid in the square and an ``outside x outside`` grid of
    ``[-reach, 1 + reach]²`` without the square, both kept off the 1/256 grid of the samples."""
    g = (np.arange(inside) + 0.5 + shift) / inside + 1 / 1024 / np.pi
    ins = np.stack(np.meshgrid(g, g), axis=-1).reshape(-1, 2)
    h = np.linspace(-reach, 1 + reach, outside) + 1 / 1024 / np.e + shift / outside
    out = np.stack(np.meshgrid(h, h), axis=-1).reshape(-1, 2)
    out = out[~np.all((out >= 0) & (out <= 1), axis=1)]
    return np.concatenate([ins[np.all((ins > 0) & (ins < 1), axis=1)], out])


def measure(points, min_angle: float = 20.0, directions: int = 4096, inside: int = 64, outside: int = 48,
            shifts: int = 2):
    """The worst errors of a pattern, a dict: ``half-plane`` (one edge), ``strip`` (two
    parallel edges), ``wedge`` (two edges at any angle: a corner in the pixel or near it)
    and ``wedge >= A°`` (corners of at least ``min_angle`` degrees), each a max over dense
    grids (the directions of every two samples and a grid; ``shifts`` shifted apex grids)."""
    thetas = np.concatenate([np.arange(directions) * (np.pi / directions), pair_directions(points)])
    half, strip = direction_errors(points, thetas)
    wedge, wide = 0.0, 0.0
    for s in range(shifts):
        apexes = apex_grid(inside, outside, reach=4.0, shift=s / shifts)
        for chunk in np.array_split(apexes, max(1, len(apexes) // 512)):
            wedge = max(wedge, float(cone_errors(points, chunk).max()))
            wide = max(wide, float(wedge_errors(points, chunk, np.radians(min_angle)).max()))
    return {"half-plane": float(half.max()), "strip": float(strip.max()), "wedge": wedge,
            f"wedge >= {min_angle:g} deg": wide}
