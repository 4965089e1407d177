"""Numba kernels of :mod:`rasterkit.material`, imported by that package's modules only:
``sample`` (texture lookups, wrapping, levels of detail)."""
