"""Limits the kernels' arithmetic is sized for; plain constants, importable without Numba.

The command line checks ``--size`` against :data:`MAX_IMAGE_SIZE` (through
:mod:`rasterkit.options`) before it loads any kernel.
"""

#: Largest width or height of an image, in pixels: the guard band arithmetic of
#: :mod:`rasterkit.raster.kernels.clip` is sized for it.
MAX_IMAGE_SIZE = 2**15
