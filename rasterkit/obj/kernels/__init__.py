"""rasterkit.obj.kernels."""
