"""Ray-traced ambient occlusion for the AO tests: from the exact surface point seen at each
pixel (tests/support/raycast.py), cosine-weighted rays over the hemisphere around the face's
geometric normal (turned towards the camera), each tested against every triangle near the
point (a uniform grid of cells ``radius`` wide: a ray no longer than ``radius`` meets only
triangles in the 27 cells around its origin's) — slow and simple, independent of the renderer.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from support.raycast import ray_hits, surface_points
from support.unchecked import as_written


def hemisphere(count: int, seed: int = 7) -> np.ndarray:
    """(count, 3) cosine-weighted unit directions about +z, stratified over a square grid of
    the unit disk (Malley's method), jittered with a fixed seed."""
    side = int(math.ceil(math.sqrt(count)))
    rng = np.random.default_rng(seed)
    a, b = np.meshgrid(np.arange(side), np.arange(side))
    u = ((a.ravel() + rng.random(side * side)) / side)[:count]
    v = ((b.ravel() + rng.random(side * side)) / side)[:count]
    r, phi = np.sqrt(u), 2 * math.pi * v
    return np.stack([r * np.cos(phi), r * np.sin(phi), np.sqrt(1 - u)], axis=1)


def _cells(mesh, radius):
    """The uniform grid: (origin (3,), shape (3,), start (C + 1,), triangles (T,)) — the
    triangles whose bounding box meets each cell, cell-major."""
    corners = mesh.vertices[mesh.faces]
    low, high = corners.min(axis=1), corners.max(axis=1)
    origin = low.min(axis=0) - radius
    shape = np.floor((high.max(axis=0) + radius - origin) / radius).astype(np.int64) + 1
    first = np.floor((low - origin) / radius).astype(np.int64)
    last = np.floor((high - origin) / radius).astype(np.int64)
    extent = last - first + 1
    counts = extent.prod(axis=1)
    owners = np.repeat(np.arange(len(mesh.faces)), counts)
    local = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)  # each cell's place in its box
    e = extent[owners]
    k = first[owners, 2] + local % e[:, 2]
    j = first[owners, 1] + (local // e[:, 2]) % e[:, 1]
    i = first[owners, 0] + local // (e[:, 2] * e[:, 1])
    cells = (i * shape[1] + j) * shape[2] + k
    order = np.argsort(cells, kind="stable")
    start = np.searchsorted(cells[order], np.arange(int(np.prod(shape)) + 1))
    return origin, shape, start.astype(np.int64), owners[order].astype(np.int64)


@numba.njit(cache=False)
def _occlusion(points, normals, rays, radius, a, e1, e2, origin, shape, start, owners, out):
    for p in range(len(points)):
        n = normals[p]
        t = np.array([0.0, -n[2], n[1]]) if abs(n[0]) < 0.6 else np.array([n[2], 0.0, -n[0]])
        t /= math.sqrt((t * t).sum())
        b = np.array([n[1] * t[2] - n[2] * t[1], n[2] * t[0] - n[0] * t[2], n[0] * t[1] - n[1] * t[0]])
        o = points[p]
        c = np.floor((o - origin) / radius).astype(np.int64)
        blocked = 0
        for r in range(len(rays)):
            d = rays[r, 0] * t + rays[r, 1] * b + rays[r, 2] * n
            hit = False
            for ci in range(max(c[0] - 1, 0), min(c[0] + 2, shape[0])):
                for cj in range(max(c[1] - 1, 0), min(c[1] + 2, shape[1])):
                    for ck in range(max(c[2] - 1, 0), min(c[2] + 2, shape[2])):
                        cell = (ci * shape[1] + cj) * shape[2] + ck
                        for q in range(start[cell], start[cell + 1]):
                            s = ray_hits(o[0], o[1], o[2], d[0], d[1], d[2], owners[q], a, e1, e2)
                            if 0.0 < s < radius:
                                hit = True
                                break
                        if hit:
                            break
                    if hit:
                        break
                if hit:
                    break
            blocked += hit
        out[p] = 1.0 - blocked / len(rays)


def ray_traced_ao(mesh, camera, ids, radius: float, rays: int = 256, pixels: int | None = None) -> np.ndarray:
    """(H, W) float64: one minus the share of ``rays`` cosine-weighted hemisphere rays from the
    surface point seen at each pixel of ``ids`` (the face drawn there, -1 for none) that meet a
    triangle of ``mesh`` within ``radius``; NaN where no face was drawn, and (``pixels``: at
    most that many pixels, chosen at random with a fixed seed) where none was cast."""
    j, i = np.nonzero(ids >= 0)
    if pixels is not None and pixels < len(j):
        chosen = np.sort(np.random.default_rng(3).choice(len(j), pixels, replace=False))
        j, i = j[chosen], i[chosen]
        ids = np.where(np.isin(np.arange(ids.size), j * ids.shape[1] + i).reshape(ids.shape), ids, -1)
    points, _ = surface_points(mesh, camera, ids)
    normals = mesh.face_normals[ids[j, i]].astype(np.float64)
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    origin, _ = camera.ray(i + 0.5, j + 0.5)
    facing = ((origin - points) * normals).sum(axis=1) if camera.kind == "perspective" else \
        (np.asarray(camera.backward()) * normals).sum(axis=1)
    normals[facing < 0] *= -1
    scale = float(np.abs(mesh.vertices).max())
    points = points + normals * (1e-6 * scale)
    a = mesh.vertices[mesh.faces[:, 0]].astype(np.float64)
    e1 = mesh.vertices[mesh.faces[:, 1]] - a
    e2 = mesh.vertices[mesh.faces[:, 2]] - a
    origin, shape, start, owners = _cells(mesh, radius)
    values = np.empty(len(points))
    with as_written():
        _occlusion(np.ascontiguousarray(points), np.ascontiguousarray(normals), hemisphere(rays), float(radius),
                   np.ascontiguousarray(a), np.ascontiguousarray(e1), np.ascontiguousarray(e2), origin, shape,
                   start, owners, values)
    out = np.full(ids.shape, np.nan)
    out[j, i] = values
    return out
