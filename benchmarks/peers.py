"""The peers rasterkit is measured against, and how a missing peer is reported.

:class:`Llvmpipe` is Mesa's CPU OpenGL driver driven through moderngl's headless EGL
context: built once, it keeps its shader programs and one framebuffer per resolution; a mesh
is uploaded once (:meth:`Llvmpipe.upload`, outside any timed region, as rasterkit's ``Mesh``
is built once) and each timed frame is clear + draw + read back into a NumPy array.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass

import numpy as np

LIGHTGRAY = (211 / 255, 211 / 255, 211 / 255)
AMBIENT = 0.25
"""Surface colour and ambient fraction: rasterkit's defaults (``color='lightgray'``,
``rasterkit.raster.render.AMBIENT``), so both sides shade alike."""

POLYGON_OFFSET = (1.0, 1.0)
"""glPolygonOffset(factor, units) pushing the faces back in the depth pass of hidden-line
and solid+wire frames, so the edges of visible faces pass the depth test."""


class PeerUnavailable(Exception):
    """A peer cannot start; the message says why (printed, and recorded in results.json)."""


def require(module: str):
    """Import ``module`` or raise :class:`PeerUnavailable` naming the missing package."""
    try:
        return importlib.import_module(module)
    except Exception as error:  # ImportError, or a broken binary wheel raising anything else
        raise PeerUnavailable(f"cannot import {module} ({type(error).__name__}: {error}); "
                              "install the bench extra: pip install -e '.[bench]'") from None


def gl_clip_matrix(width: int, height: int) -> np.ndarray:
    """(4, 4) float64: homogeneous raster space -> OpenGL clip space.

    Raster x in [0, W] -> NDC [-1, 1]; raster y (down) in [0, H] -> NDC [1, -1] (GL's y is
    up); depth z in [0, 1] -> NDC [-1, 1], which the default depth range maps back to [0, 1].
    """
    return np.array([[2.0 / width, 0.0, 0.0, -1.0],
                     [0.0, -2.0 / height, 0.0, 1.0],
                     [0.0, 0.0, 2.0, -1.0],
                     [0.0, 0.0, 0.0, 1.0]])


_PLAIN_VS = """#version 330
uniform mat4 mvp;
in vec3 in_pos;
void main() { gl_Position = mvp * vec4(in_pos, 1.0); }
"""
_PLAIN_FS = """#version 330
uniform vec3 color;
out vec4 frag;
void main() { frag = vec4(color, 1.0); }
"""
# Flat Lambert with a headlight, computed once per vertex of a face-duplicated mesh (each
# vertex carries its face's normal), so the fragment shader only writes a constant.
_FLAT_VS = """#version 330
uniform mat4 mvp;
uniform vec3 towards_eye;
uniform vec3 base;
uniform float ambient;
in vec3 in_pos;
in vec3 in_normal;
flat out vec3 shade;
void main() {
    gl_Position = mvp * vec4(in_pos, 1.0);
    shade = base * (ambient + (1.0 - ambient) * max(dot(in_normal, towards_eye), 0.0));
}
"""
_FLAT_FS = """#version 330
flat in vec3 shade;
out vec4 frag;
void main() { frag = vec4(shade, 1.0); }
"""


@dataclass
class GLMesh:
    """A mesh uploaded to llvmpipe: vertex arrays for the depth pass, the flat-shaded faces
    and the edges, with the camera's uniforms."""

    depth_vao: object
    flat_vao: object
    lines_vao: object
    mvp: bytes
    towards_eye: tuple
    width: int
    height: int
    cull: bool


def _face_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(M, 3) unit normals of counter-clockwise faces (zero for degenerate faces)."""
    corners = vertices[faces]
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    length = np.linalg.norm(normals, axis=1, keepdims=True)
    return np.divide(normals, length, out=np.zeros_like(normals), where=length > 0)


class Llvmpipe:
    """Mesa llvmpipe through a headless moderngl context (EGL); build it once.

    Raises
    ------
    PeerUnavailable
        moderngl is missing or no EGL context can be made.
    """

    name = "llvmpipe"

    def __init__(self):
        moderngl = require("moderngl")
        try:
            self.ctx = moderngl.create_standalone_context(backend="egl")
        except Exception as error:
            raise PeerUnavailable(f"no headless EGL context ({type(error).__name__}: {error})") from None
        self.gl = moderngl
        self.renderer = f'{self.ctx.info["GL_RENDERER"]}, {self.ctx.info["GL_VERSION"]}'
        self.plain = self.ctx.program(vertex_shader=_PLAIN_VS, fragment_shader=_PLAIN_FS)
        self.flat = self.ctx.program(vertex_shader=_FLAT_VS, fragment_shader=_FLAT_FS)
        self.flat["base"].value = LIGHTGRAY
        self.flat["ambient"].value = AMBIENT
        self._framebuffers: dict[tuple[int, int], object] = {}

    def upload(self, mesh, camera, cull: str = "back") -> GLMesh:
        """Upload ``mesh`` (a rasterkit Mesh) once for frames seen by ``camera``.

        The GL side gets the same triangles, the same edge list and the same camera matrix
        (``camera.matrix()`` followed by the fixed raster -> clip-space map).
        """
        ctx = self.ctx
        vertices = mesh.vertices.astype(np.float32)
        positions = ctx.buffer(vertices.tobytes())
        faces = ctx.buffer(mesh.faces.astype(np.int32).tobytes())
        edges = ctx.buffer(mesh.edges.astype(np.int32).tobytes())
        normals = np.repeat(_face_normals(mesh.vertices, mesh.faces), 3, axis=0).astype(np.float32)
        flat = ctx.buffer(np.hstack([vertices[mesh.faces.ravel()], normals]).tobytes())
        mvp = (gl_clip_matrix(camera.width, camera.height) @ camera.matrix()).astype(np.float32)
        return GLMesh(
            depth_vao=ctx.vertex_array(self.plain, [(positions, "3f", "in_pos")], index_buffer=faces,
                                       index_element_size=4),
            flat_vao=ctx.vertex_array(self.flat, [(flat, "3f 3f", "in_pos", "in_normal")]),
            lines_vao=ctx.vertex_array(self.plain, [(positions, "3f", "in_pos")], index_buffer=edges,
                                       index_element_size=4),
            mvp=mvp.T.tobytes(),  # GLSL matrices are column-major
            towards_eye=tuple(float(c) for c in camera.basis()[2]),
            width=camera.width, height=camera.height, cull=cull == "back")

    def framebuffer(self, width: int, height: int, samples: int = 0):
        """A colour + depth framebuffer of this size (and MSAA ``samples``), made once."""
        key = (width, height, samples)
        if key not in self._framebuffers:
            size = (width, height)
            self._framebuffers[key] = self.ctx.framebuffer(
                color_attachments=[self.ctx.renderbuffer(size, 4, samples=samples)],
                depth_attachment=self.ctx.depth_renderbuffer(size, samples=samples))
        return self._framebuffers[key]

    def draw(self, glmesh: GLMesh, mode: str, samples: int = 0) -> np.ndarray:
        """One frame: clear, draw ``mode`` (as rasterkit's modes), read back.

        ``samples > 0`` draws into a multisampled (MSAA) framebuffer of that many samples and
        resolves it (``copy_framebuffer``, a glBlitFramebuffer) into a single-sample one
        before the read: the resolve is part of the frame.

        Returns
        -------
        (H, W, 3) uint8
            The image, rows top-down (a reversed view of GL's bottom-up rows).
        """
        gl, ctx = self.gl, self.ctx
        fbo = self.framebuffer(glmesh.width, glmesh.height, samples)
        fbo.use()
        fbo.clear(1.0, 1.0, 1.0, 1.0, depth=1.0)
        self.plain["mvp"].write(glmesh.mvp)
        if glmesh.cull:
            ctx.enable(gl.CULL_FACE)
        else:
            ctx.disable(gl.CULL_FACE)
        if mode == "wire":
            ctx.disable(gl.DEPTH_TEST)
        else:
            ctx.enable(gl.DEPTH_TEST)
            ctx.depth_func = "<="
            self._faces(glmesh, mode, fbo)
        if mode != "solid":
            self.plain["color"].value = (0.0, 0.0, 0.0)
            glmesh.lines_vao.render(gl.LINES)
        if samples:
            resolved = self.framebuffer(glmesh.width, glmesh.height)
            ctx.copy_framebuffer(resolved, fbo)
            fbo = resolved
        data = fbo.read(components=3, alignment=1)
        return np.frombuffer(data, np.uint8).reshape(glmesh.height, glmesh.width, 3)[::-1]

    def _faces(self, glmesh: GLMesh, mode: str, fbo) -> None:
        """The triangles: a depth-only pass for hidden lines, flat Lambert otherwise."""
        gl, ctx = self.gl, self.ctx
        ctx.polygon_offset = POLYGON_OFFSET if mode != "solid" else (0.0, 0.0)
        if mode == "hidden":
            fbo.color_mask = (False, False, False, False)
            glmesh.depth_vao.render(gl.TRIANGLES)
            fbo.color_mask = (True, True, True, True)
        else:
            self.flat["mvp"].write(glmesh.mvp)
            self.flat["towards_eye"].value = glmesh.towards_eye
            glmesh.flat_vao.render(gl.TRIANGLES)
        ctx.polygon_offset = (0.0, 0.0)


class Peers:
    """Starts each peer at most once, on first use, and remembers why one could not start.

    Parameters
    ----------
    enabled : bool
        False times rasterkit alone (``--no-peers``): every peer is then unavailable.
    """

    def __init__(self, enabled: bool = True):
        self.enabled = enabled
        self._llvmpipe: Llvmpipe | PeerUnavailable | None = None

    def module(self, name: str):
        """A peer library, imported (raises :class:`PeerUnavailable`)."""
        if not self.enabled:
            raise PeerUnavailable("peers disabled (--no-peers)")
        return require(name)

    def llvmpipe(self) -> Llvmpipe:
        """The one llvmpipe context of the run (raises :class:`PeerUnavailable`)."""
        if self._llvmpipe is None:
            try:
                self._llvmpipe = Llvmpipe() if self.enabled else PeerUnavailable("peers disabled (--no-peers)")
            except PeerUnavailable as reason:
                self._llvmpipe = reason
        if isinstance(self._llvmpipe, PeerUnavailable):
            raise self._llvmpipe
        return self._llvmpipe

    @property
    def gl_renderer(self) -> str | None:
        """GL_RENDERER of the llvmpipe context, if one was started."""
        return self._llvmpipe.renderer if isinstance(self._llvmpipe, Llvmpipe) else None
