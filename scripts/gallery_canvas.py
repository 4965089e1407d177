"""Drawing helpers of the gallery (scripts/make_gallery.py): panels, labels, overlays, grids.

Only rasterkit's public API, NumPy and Pillow. Images are uint8 (H, W, 3) arrays, raster
space as rasterkit's: x right, y down, pixel (i, j) the square [i, i+1) x [j, j+1).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from rasterkit import draw

WHITE = (255, 255, 255)
GAP = 4  # pixels between panels
_FONT = ImageFont.load_default()

# Colours of the axes x, y, z (red, green, blue, as in every 3D tool).
AXIS_COLORS = ((205, 40, 40), (30, 150, 40), (40, 80, 215))


def blank(width: int, height: int, color=WHITE) -> np.ndarray:
    """A new (height, width, 3) uint8 image of one colour."""
    return np.full((height, width, 3), color, np.uint8)


def label(image: np.ndarray, text: str, xy=(4, 3), color=(0, 0, 0)) -> np.ndarray:
    """Write ``text`` on ``image`` (in place) with Pillow's default font; returns the image."""
    pil = Image.fromarray(image)
    ImageDraw.Draw(pil).text(xy, text, fill=color, font=_FONT)
    image[...] = np.asarray(pil)
    return image


def dots(image: np.ndarray, points, radius: float = 2.5, color=(0, 0, 0), outline=None) -> np.ndarray:
    """Filled circles at raster points ``(x, y)`` (in place)."""
    pil = Image.fromarray(image)
    pen = ImageDraw.Draw(pil)
    for x, y in np.asarray(points, np.float64).reshape(-1, 2):
        if np.isfinite(x) and np.isfinite(y) and abs(x) < 1e5 and abs(y) < 1e5:
            pen.ellipse((x - radius, y - radius, x + radius, y + radius), fill=color, outline=outline)
    image[...] = np.asarray(pil)
    return image


def grid(panels: list[np.ndarray], columns: int, gap: int = GAP, color=(190, 190, 190)) -> np.ndarray:
    """Equal-sized panels in rows of ``columns``, ``gap`` pixels of ``color`` between them."""
    h, w = panels[0].shape[:2]
    rows = -(-len(panels) // columns)
    out = blank(columns * w + (columns - 1) * gap, rows * h + (rows - 1) * gap, color)
    for k, panel in enumerate(panels):
        r, c = divmod(k, columns)
        out[r * (h + gap):r * (h + gap) + h, c * (w + gap):c * (w + gap) + w] = panel
    return out


def stack(images: list[np.ndarray], gap: int = GAP, color=(190, 190, 190)) -> np.ndarray:
    """Images of one width, one above the other."""
    parts = []
    for image in images:
        parts += [image, blank(image.shape[1], gap, color)]
    return np.concatenate(parts[:-1], axis=0)


def segments_3d(image: np.ndarray, camera, starts, ends, color=(0, 0, 0), aa: bool = True,
                bold: bool = False) -> np.ndarray:
    """Draw world-space segments seen by ``camera`` over ``image`` (in place); ``bold``:
    about 2 pixels wide.

    Both ends must lie in front of the eye (the projection has no near-plane clipping);
    ``rasterkit.draw.lines`` clips the rest to the image.
    """
    a = camera.project(np.asarray(starts, np.float64).reshape(-1, 3))[:, :2]
    b = camera.project(np.asarray(ends, np.float64).reshape(-1, 3))[:, :2]
    for offset in ([(0, 0), (0.7, 0.0), (0.0, 0.7)] if bold else [(0, 0)]):
        shift = np.tile(offset, 2)
        draw.lines(image, np.concatenate([a, b], axis=1) + shift, color=color, aa=aa)
    return image


def axes_3d(image: np.ndarray, camera, origin=(0, 0, 0), basis=np.eye(3), length: float = 1.0,
            names=("x", "y", "z")) -> np.ndarray:
    """An axis triad (x red, y green, z blue) at ``origin`` along the rows of ``basis``,
    each axis labelled at its tip."""
    o = np.asarray(origin, np.float64)
    for k in range(3):
        tip = o + length * np.asarray(basis[k], np.float64)
        segments_3d(image, camera, o, tip, AXIS_COLORS[k], bold=True)
        x, y = camera.project(tip[None])[0, :2]
        if names[k] and 0 <= x < image.shape[1] and 0 <= y < image.shape[0]:
            label(image, names[k], (x + 2, y - 11), AXIS_COLORS[k])
    return image


def box_edges(lo, hi) -> tuple[np.ndarray, np.ndarray]:
    """The 12 edges of the axis-aligned box [lo, hi] as (starts, ends), (12, 3) each."""
    lo, hi = np.asarray(lo, np.float64), np.asarray(hi, np.float64)
    corners = np.array([[(hi if (k >> a) & 1 else lo)[a] for a in range(3)] for k in range(8)])
    pairs = [(i, i | 1 << a) for i in range(8) for a in range(3) if not i & 1 << a]
    return corners[[p[0] for p in pairs]], corners[[p[1] for p in pairs]]


def magnify(image: np.ndarray, factor: int) -> np.ndarray:
    """Each pixel a ``factor`` x ``factor`` block (nearest neighbour)."""
    return np.repeat(np.repeat(image, factor, axis=0), factor, axis=1)


def pixel_grid(image: np.ndarray, cell: int, color=(200, 200, 200)) -> np.ndarray:
    """``image`` magnified to ``cell`` pixels a pixel, with a one-pixel grid line between pixels."""
    big = magnify(image, cell)
    big[::cell, :] = color
    big[:, ::cell] = color
    return big


def line_grid(pixels: np.ndarray, width: int, height: int, cell: int, ideal, fill=(70, 70, 70),
              marked=(), mark=(235, 140, 20)) -> np.ndarray:
    """Pixels ``(x, y)`` of a line on a ``width`` x ``height`` grid magnified ``cell`` times,
    pixel centres dotted and the ideal segment ``(x0, y0, x1, y1)`` (raster units) drawn
    over it in red; ``marked`` pixels are filled with ``mark``."""
    small = blank(width, height)
    small[pixels[:, 1], pixels[:, 0]] = fill
    for x, y in marked:
        small[y, x] = mark
    big = pixel_grid(small, cell)
    centres = (np.stack(np.meshgrid(np.arange(width), np.arange(height)), -1).reshape(-1, 2) + 0.5) * cell
    dots(big, centres, radius=1.0, color=(150, 150, 150))
    x0, y0, x1, y1 = (np.asarray(ideal, np.float64) * cell).tolist()
    for d in (-0.5, 0.0, 0.5):  # a 2-pixel-wide anti-aliased stroke
        draw.lines(big, [[x0, y0 + d, x1, y1 + d]], color=(220, 30, 30), aa=True)
    return big


def plot(width: int, height: int, curves, colors, y_range=(0.0, 1.0), margin: int = 6) -> np.ndarray:
    """A small line plot: each curve an (N,) array over equally spaced x; y up."""
    image = blank(width, height)
    lo, hi = y_range
    for curve, color in zip(curves, colors):
        curve = np.asarray(curve, np.float64)
        x = margin + np.linspace(0, width - 2 * margin, len(curve))
        y = height - margin - (curve - lo) / (hi - lo) * (height - 2 * margin)
        draw.lines(image, np.stack([x[:-1], y[:-1], x[1:], y[1:]], 1), color=color, aa=True)
    draw.lines(image, [[margin, height - margin, width - margin, height - margin],
                       [margin, margin, margin, height - margin]], color=(120, 120, 120))
    return image


def save_png(image: np.ndarray, path: Path) -> None:
    """Write ``image`` as a PNG with no metadata: the same array gives the same bytes."""
    Image.fromarray(np.ascontiguousarray(image)).save(path, format="PNG", optimize=True)
