"""Named records that the triangle driver hands to the setup kernels (Numba takes
``collections.namedtuple`` arguments and unpacks them like tuples), instead of long
positional argument lists.
"""

from collections import namedtuple

#: The triangle records of :mod:`rasterkit.kernels.setup`: ``xy`` (T, 6) int32 fixed-point
#: vertices, ``z`` (T, 3) float32 depths, ``box`` (T, 4) int32 clamped pixel boxes.
Records = namedtuple("Records", "xy z box")

#: Which faces need cutting: ``mask`` (M,) int8, the planes that cut each face (0: none),
#: and ``n_fan`` (M,) int8, the fan records of each cut face (0 for the others).
Cuts = namedtuple("Cuts", "mask n_fan")

#: What the setup counts: ``shift``, log2 of the rows per band; ``bands`` (N_CHUNKS, n_bands)
#: int64, drawn records per face chunk and band; ``tally`` (N_CHUNKS, N_STATUS + 1) int64,
#: faces per chunk and outcome (the last column: cut faces with something left).
Counts = namedtuple("Counts", "shift bands tally")
