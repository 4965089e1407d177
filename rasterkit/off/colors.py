"""Colours of an OFF file (per vertex or per face) as float32 RGB in [0, 1].

Geomview's rule is that 3 or 4 integers are RGB[A] in 0..255 and 3 or 4 floats are RGB[A] in
0..1; ``1 0 0`` fits both. Here the choice is made once per file for each kind of colour (the
vertices', the faces'): 0..255 when every value is written as an integer (``255 128 0``) or any
value is above 1, else 0..1 (``1.0 0.5 0``, ``1 0.5 0``). Alpha is read and dropped. A value
below 0 or above the range is clipped, and a NaN or infinite colour becomes
:data:`rasterkit.material.DEFAULT_DIFFUSE`, with one warning each.
"""

from __future__ import annotations

import numpy as np

from rasterkit.material import DEFAULT_DIFFUSE

__all__ = ["DEFAULT", "count", "unit_colors"]

DEFAULT = np.asarray(DEFAULT_DIFFUSE, np.float32)
"""The colour of a face (or vertex) without one in a file where others have one."""


def count(n: int, noun: str) -> str:
    """'1 face', '2 faces', '3 vertices'."""
    plural = noun[:-2] + "ices" if noun.endswith("ex") else noun + "s"
    return f"{int(n)} {noun if n == 1 else plural}"


def unit_colors(values: np.ndarray, integral: bool, what: str) -> tuple[np.ndarray, list[str]]:
    """``values`` (K, 3 or 4) float64 as RGB (K, 3) float32 in [0, 1] (see the module's
    rules; ``integral``: every value was written as an integer), and the warnings, which name
    ``what`` ("vertex", "face")."""
    rgb = np.asarray(values, np.float64)[:, :3]
    finite = np.isfinite(rgb).all(axis=1)
    with np.errstate(invalid="ignore"):
        scale = 255.0 if integral or (rgb[finite] > 1.0).any() else 1.0
        rgb = rgb / scale
        outside = finite & ((rgb < 0.0) | (rgb > 1.0)).any(axis=1)
    warnings = []
    if outside.any():
        warnings.append(f"{count(np.count_nonzero(outside), what + ' colour')} outside 0..{scale:g}: clipped")
    if not finite.all():
        warnings.append(f"{count(np.count_nonzero(~finite), what + ' colour')} with NaN or infinite values: drawn "
                        "in the default colour")
    out = np.clip(np.where(finite[:, None], rgb, DEFAULT), 0.0, 1.0).astype(np.float32)
    return out, warnings
