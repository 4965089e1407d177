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

import importlib
import importlib.util
import os
import re

__version__ = "0.1.0"


def _public_names() -> dict[str, tuple[str, str]]:
    """``{name: (module, attribute)}`` from the stub ``__init__.pyi`` beside this file, the
    one list of public names (lines ``from MODULE import NAME as NAME``)."""
    with open(os.path.join(os.path.dirname(__file__), "__init__.pyi"), encoding="utf-8") as stub:
        lines = re.findall(r"^from ([\w.]+) import (\w+) as (\w+)$", stub.read(), re.M)
    return {alias: (module, name) for module, name, alias in lines}


_HOMES = _public_names()
__all__ = sorted(_HOMES)


def __getattr__(name: str):
    if name in _HOMES:
        module, attribute = _HOMES[name]
        value = importlib.import_module(f"{module}.{attribute}" if module == __name__ else module)
        if module != __name__:
            value = getattr(value, attribute)
        globals()[name] = value  # found directly from now on
        return value
    # A submodule (`rasterkit.camera` after a bare `import rasterkit`, as when the package
    # imported them all eagerly); the import binds it on the package.
    submodule = (name.isidentifier() and not name.startswith("__")
                 and importlib.util.find_spec(f"{__name__}.{name}") is not None)
    if submodule:
        return importlib.import_module(f".{name}", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
