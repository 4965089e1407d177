"""Blinn-Phong lighting in plain NumPy, written from the formulas of the lighting docs (not
from the kernel): the reference the lighting tests compare renders and kernels with."""

from __future__ import annotations

import numpy as np


def srgb_to_linear(c):
    c = np.asarray(c, np.float64)
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def linear_to_srgb255(x):
    x = np.clip(np.nan_to_num(np.asarray(x, np.float64), nan=0.0), 0.0, 1.0)
    return 255.0 * np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)


def _unit(v):
    v = np.asarray(v, np.float64)
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    return np.divide(v, n, out=np.zeros_like(v), where=n > 0)


def light_terms(light, points):
    """(l (K, 3) unit towards the light, attenuation (K,)) of one Light at points (K, 3);
    a headlight is a directional light here (the caller passes its direction)."""
    points = np.asarray(points, np.float64)
    if light["kind"] == "directional":
        l = np.broadcast_to(-_unit(light["direction"]), points.shape)
        return l, np.ones(len(points))
    d = np.asarray(light["position"], np.float64) - points
    dist = np.linalg.norm(d, axis=1)
    l = _unit(d)
    a = 1.0 / dist ** 2
    if light.get("range"):
        a = a * np.clip(1.0 - (dist / light["range"]) ** 4, 0.0, 1.0)
    if light["kind"] == "spot":
        half = np.radians(light["angle"]) / 2
        cos_outer, cos_inner = np.cos(half), np.cos(half * (1 - light["blend"]))
        cos = (-l * _unit(light["direction"])).sum(axis=1)
        t = np.clip((cos - cos_outer) / max(1e-3, cos_inner - cos_outer), 0.0, 1.0)
        a = a * t * t
    return l, a


def blinn_phong(points, normals, base255, lights, eye, specular=(0.25, 0.25, 0.25), shininess=32.0,
                emission=(0.0, 0.0, 0.0), two_sided=False, view=None):
    """sRGB 0..255 (K, 3) float64 of points (K, 3) with unit normals (K, 3), sRGB base colours
    (K or 1, 3) 0..255, seen from ``eye`` (or along ``view``, towards the viewer of a parallel
    camera) under ``lights`` (dicts: kind, color (linear rgb times intensity), direction,
    position, range, angle, blend)."""
    points, normals = np.asarray(points, np.float64), np.asarray(normals, np.float64)
    albedo = srgb_to_linear(np.asarray(base255, np.float64) / 255.0)
    v = _unit(np.asarray(eye, np.float64) - points) if view is None else np.broadcast_to(_unit(view), points.shape)
    if two_sided:
        normals = np.where(((normals * v).sum(axis=1) < 0)[:, None], -normals, normals)
    total = np.zeros(points.shape) + np.asarray(emission, np.float64)
    for light in lights:
        c = np.asarray(light["color"], np.float64)
        if light["kind"] == "ambient":
            total += albedo * c
            continue
        l, a = light_terms(light, points)
        ndl = (normals * l).sum(axis=1)
        h = _unit(l + v)
        ndh = np.maximum((normals * h).sum(axis=1), 0.0)
        term = albedo * ndl[:, None] + np.asarray(specular, np.float64) * (ndh ** shininess)[:, None]
        total += np.where((ndl > 0)[:, None], a[:, None] * c * term, 0.0)
    return linear_to_srgb255(total)
