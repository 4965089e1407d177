"""rasterkit: a JIT-accelerated (Numba) software rasterizer for Python.

NumPy arrays in, NumPy arrays and images out; no GPU, no OpenGL, no display.

>>> import rasterkit
>>> mesh = rasterkit.shapes.torus()
>>> camera = rasterkit.Camera.frame(*mesh.bounding_sphere(), width=64, height=48)
>>> rasterkit.render(mesh, camera, mode="wire").color.shape
(48, 64, 3)
"""

from . import draw, shapes, transform
from ._jit import set_threads
from .camera import PROJECTIONS, Camera
from .colors import parse_color
from .framebuffer import Framebuffer
from .mesh import Mesh
from .obj import ObjError, load_obj
from .render import render
from .scene import Scene

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
    "Scene",
    "set_threads",
    "shapes",
    "transform",
]

__version__ = "0.1.0"
