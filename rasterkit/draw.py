"""Pixel sets of simple shapes in raster space: the lecture's line and triangle algorithms.

The public home of :mod:`rasterkit.raster.draw`, where they are drawn: :func:`line` (Bresenham,
DDA or naive), :func:`lines` (segments into an image, optionally anti-aliased) and
:func:`triangle` (the top-left fill rule).
"""

from rasterkit.raster.draw import LINE_METHODS, line, lines, triangle

__all__ = ["LINE_METHODS", "line", "lines", "triangle"]
