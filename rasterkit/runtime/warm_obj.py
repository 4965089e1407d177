"""What the built-in demo's first-run helper does (:mod:`rasterkit.runtime.warm`): read a
small OBJ with every kind of statement, at the lowest priority, so that the OBJ reader's
kernels are in Numba's cache before the first real model needs them."""

from __future__ import annotations

import os

#: An OBJ with a statement of every kind the reader needs: vertices with and without
#: colours, texture coordinates and normals, triangles with every corner form, negative
#: indices, a quad, a line and a point, groups and a material. (Polygons are split by NumPy:
#: :mod:`rasterkit.obj.split`.)
SAMPLE_OBJ = """\
o sample
v 0 0 0 1 0 0
v 1 0 0 0 1 0
v 1 1 0 0 0 1
v 0 1 0.2
vt 0 0
vt 1 0
vt 1 1
vn 0 0 1
g faces
usemtl red
f 1/1/1 2/2/1 3/3/1
f 1/1 3/2 4/3
f 1//1 2//1 4//1
f -4 -3 -1
f 1 2 3 4
l 1 2 3
p 4
"""


def _lower_priority() -> None:
    try:
        os.nice(19)
    except (AttributeError, OSError):  # not on this platform, or not allowed
        pass


def read_sample_obj() -> None:
    """Read :data:`SAMPLE_OBJ` at the lowest priority, which compiles the reader's kernels."""
    import tempfile

    from rasterkit.obj import load_obj

    _lower_priority()
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "sample.obj")
        with open(path, "w") as f:
            f.write(SAMPLE_OBJ)
        load_obj(path, textures=False)
