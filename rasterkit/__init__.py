"""rasterkit: a JIT-accelerated (Numba) software rasterizer for Python.

NumPy arrays in, NumPy arrays and images out; no GPU, no OpenGL, no display.

>>> import rasterkit
>>> mesh = rasterkit.shapes.torus()
>>> camera = rasterkit.Camera.frame(*mesh.bounding_sphere(), width=64, height=48)
>>> rasterkit.render(mesh, camera, mode="wire").color.shape
(48, 64, 3)

The public names are listed once, in ``__init__.pyi``, and imported on first use (PEP 562),
so ``import rasterkit`` and the command line's ``--help`` load neither NumPy nor Numba; the
kernels load with the first name that needs them.
"""

from __future__ import annotations

import os
import re

from rasterkit.lazy import on_first_use

__version__ = "0.1.0"


def _public_names() -> dict[str, str]:
    """``{name: "module:attribute"}`` from the stub ``__init__.pyi`` beside this file, the
    one list of public names (lines ``from MODULE import NAME as NAME``)."""
    with open(os.path.join(os.path.dirname(__file__), "__init__.pyi"), encoding="utf-8") as stub:
        lines = re.findall(r"^from ([\w.]+) import (\w+) as (\w+)$", stub.read(), re.M)
    return {alias: f"{module}.{name}" if module == __name__ else f"{module}:{name}" for module, name, alias in lines}


_HOMES = _public_names()
__all__ = sorted(_HOMES)
__getattr__, __dir__ = on_first_use(__name__, globals(), _HOMES, submodules=True)
