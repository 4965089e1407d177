# rasterkit's public names: the one list. Type checkers read these imports; at run time
# rasterkit/__init__.py reads the same lines and imports each name on first use.
from rasterkit import draw as draw
from rasterkit import shapes as shapes
from rasterkit import transform as transform
from rasterkit.batch import render_many as render_many
from rasterkit.camera import Camera as Camera
from rasterkit.colors import parse_color as parse_color
from rasterkit.formats import load as load
from rasterkit.material import Material as Material
from rasterkit.material import Texture as Texture
from rasterkit.mesh import Mesh as Mesh
from rasterkit.obj import ObjError as ObjError
from rasterkit.obj import load_obj as load_obj
from rasterkit.camera.view import View as View
from rasterkit.options import PROJECTIONS as PROJECTIONS
from rasterkit.options import RenderOptions as RenderOptions
from rasterkit.raster.framebuffer import Framebuffer as Framebuffer
from rasterkit.raster.lights import Light as Light
from rasterkit.raster.render import render as render
from rasterkit.viewer.turntable import turntable as turntable
from rasterkit.runtime.threads import set_threads as set_threads
from rasterkit.scene import Scene as Scene
from rasterkit.svg import render_svg as render_svg
from rasterkit.viewer.widget import Viewer as Viewer

__version__: str
__all__: list[str]
