"""Re-rasterising a rasterkit SVG with rasterkit's own line drawing (an SVG reader for the
subset rasterkit writes: ``<path d="M x y L x y ... Z">``), and the F-score of two line
images with a tolerance of a pixel."""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET

import numpy as np

from rasterkit.draw import lines

SVG = "{http://www.w3.org/2000/svg}"


def svg_segments(text: str, layer: str = "visible") -> np.ndarray:
    """(K, 4) segments of the paths in the layer labelled ``layer``."""
    root = ET.fromstring(text)
    segs = []
    for g in root.iter(SVG + "g"):
        if g.get("{http://www.inkscape.org/namespaces/inkscape}label") != layer:
            continue
        for path in g.iter(SVG + "path"):
            d = path.get("d")
            pts = np.array(re.findall(r"-?\d+(?:\.\d+)?", d), float).reshape(-1, 2)
            if d.endswith("Z"):
                pts = np.vstack([pts, pts[:1]])
            segs.append(np.hstack([pts[:-1], pts[1:]]))
    return np.vstack(segs) if segs else np.zeros((0, 4))


def rasterise(segments: np.ndarray, width: int, height: int) -> np.ndarray:
    """(H, W) bool: the pixels the segments cover (Bresenham, as the raster modes draw)."""
    img = np.full((height, width, 3), 255, np.uint8)
    lines(img, segments, color="black")
    return (img != 255).any(axis=2)


def _dilate(mask: np.ndarray) -> np.ndarray:
    out = mask.copy()
    padded = np.pad(mask, 1)
    h, w = mask.shape
    for dy in range(3):
        for dx in range(3):
            out |= padded[dy:dy + h, dx:dx + w]
    return out


def f_score(a: np.ndarray, b: np.ndarray) -> float:
    """F-score of line pixels ``a`` against ``b`` with a tolerance of one pixel (8-neighbours)."""
    if not a.any() and not b.any():
        return 1.0
    precision = (a & _dilate(b)).sum() / max(a.sum(), 1)
    recall = (b & _dilate(a)).sum() / max(b.sum(), 1)
    return float(2 * precision * recall / max(precision + recall, 1e-12))
