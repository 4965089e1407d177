"""rasterkit.svg.kernels."""
