"""rasterkit: a JIT-accelerated (Numba) software rasterizer for Python.

NumPy arrays in, NumPy arrays and images out; no GPU, no OpenGL, no display.

>>> import rasterkit
>>> mesh = rasterkit.shapes.torus()
>>> camera = rasterkit.Camera.frame(*mesh.bounding_sphere(), width=64, height=48)
>>> rasterkit.render(mesh, camera, mode="wire").color.shape
(48, 64, 3)

The names below are imported on first use (PEP 562), so ``import rasterkit`` and the
command line's ``--help`` load neither NumPy nor Numba; the kernels load with the first name
that needs them.
"""

from __future__ import annotations

import importlib
import importlib.util
import sys
import types
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # the real imports, for type checkers and editors
    from . import draw, shapes, transform
    from ._jit import set_threads
    from .camera import Camera
    from .colors import parse_color
    from .framebuffer import Framebuffer
    from .mesh import Mesh
    from .obj import ObjError, load_obj
    from .options import PROJECTIONS
    from .batch import render_many
    from .render import render
    from .scene import Scene
    from .svg import render_svg

__all__ = [
    "PROJECTIONS",
    "Camera",
    "Framebuffer",
    "Mesh",
    "ObjError",
    "draw",
    "load_obj",
    "parse_color",
    "render",
    "render_many",
    "render_svg",
    "Scene",
    "set_threads",
    "shapes",
    "transform",
]

__version__ = "0.1.0"

# Where each public name is defined (draw, shapes and transform are submodules themselves).
_HOMES = {
    "PROJECTIONS": ".options",
    "Camera": ".camera",
    "Framebuffer": ".framebuffer",
    "Mesh": ".mesh",
    "ObjError": ".obj",
    "load_obj": ".obj",
    "parse_color": ".colors",
    "render": ".render",
    "render_many": ".batch",
    "render_svg": ".svg",
    "Scene": ".scene",
    "set_threads": "._jit",
}


def __getattr__(name: str):
    if name in _HOMES:
        value = getattr(importlib.import_module(_HOMES[name], __name__), name)
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


class _Package(types.ModuleType):
    """The package's module type: ``rasterkit.render`` stays the function.

    Importing the submodule :mod:`rasterkit.render` (``from rasterkit.render import ...``,
    anywhere) makes the import system bind it on the package under the same name; this
    keeps the function there, as the eager imports of earlier versions did.
    """

    def __setattr__(self, name: str, value) -> None:
        if name == "render" and isinstance(value, types.ModuleType):
            return
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Package
