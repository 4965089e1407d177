"""llvmpipe drawing a textured mesh: the peer of rasterkit's textured frames (speed and exactness).

The GL side gets the same triangles (face-duplicated, so each corner carries its own texture
coordinates and normal), the same camera matrix (``camera.matrix()`` then the fixed raster ->
clip-space map of :func:`benchmarks.peers.gl_clip_matrix`) and the same texture, uploaded as
``GL_SRGB8_ALPHA8`` so that GL filters it in linear light. Mipmaps are either GL's own
(``glGenerateMipmap``) or the levels given, so that a comparison can sample the very same
texels. The fragment shader encodes the filtered colour back to sRGB with the exact transfer
function and multiplies it by the Lambert factor of a headlight (flat: per face; smooth: per
corner, interpolated), as rasterkit shades an untextured face's colour; ``unlit`` writes the
texture alone. Without an image (``upload(..., image=None)``) the faces are drawn untextured
in rasterkit's default colour (light grey) with the same shading: the peer of an untextured
frame (``textures=False``). Each timed frame is clear + draw + read back.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .peers import AMBIENT, LIGHTGRAY, Llvmpipe, gl_clip_matrix

__all__ = ["TexturedGL", "TexturedMesh"]

GL_SRGB8_ALPHA8 = 0x8C43

#: GL's filters for each of rasterkit's: (minification, magnification).
FILTERS = {"nearest": ("NEAREST", "NEAREST"), "bilinear": ("LINEAR", "LINEAR"),
           "trilinear": ("LINEAR_MIPMAP_LINEAR", "LINEAR")}

_VS = """#version 330
uniform mat4 mvp;
uniform vec3 towards_eye;
uniform float ambient;
uniform int lit;
in vec3 in_pos;
in vec2 in_uv;
in vec3 in_normal;
out vec2 uv;
out float shade;
void main() {
    gl_Position = mvp * vec4(in_pos, 1.0);
    uv = in_uv;
    shade = lit == 1 ? ambient + (1.0 - ambient) * max(dot(in_normal, towards_eye), 0.0) : 1.0;
}
"""

_FS = """#version 330
uniform sampler2D tex;
in vec2 uv;
in float shade;
out vec4 frag;
vec3 encode(vec3 c) {
    c = clamp(c, 0.0, 1.0);
    return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}
void main() {
    vec4 texel = texture(tex, uv);
    frag = vec4(encode(texel.rgb) * shade, 1.0);
}
"""

# The untextured frame: the same vertex shader, the surface colour times the shading.
_PLAIN_FS = """#version 330
uniform vec3 base;
in float shade;
out vec4 frag;
void main() { frag = vec4(base * shade, 1.0); }
"""


@dataclass
class TexturedMesh:
    """A textured mesh uploaded to llvmpipe with its camera's uniforms (``texture`` None: drawn
    untextured)."""

    vao: object
    texture: object
    mvp: bytes
    towards_eye: tuple
    width: int
    height: int
    lit: int


class TexturedGL:
    """Textured frames on an :class:`benchmarks.peers.Llvmpipe` context (built once)."""

    def __init__(self, llvmpipe: Llvmpipe):
        self.peer, self.ctx, self.gl = llvmpipe, llvmpipe.ctx, llvmpipe.gl
        self.program = self.ctx.program(vertex_shader=_VS, fragment_shader=_FS)
        self.program["ambient"].value = AMBIENT
        self.plain = self.ctx.program(vertex_shader=_VS, fragment_shader=_PLAIN_FS)
        self.plain["ambient"].value = AMBIENT
        self.plain["base"].value = LIGHTGRAY

    def upload(self, vertices, faces, corner_uv, image, camera, *, filter: str = "trilinear", wrap: str = "repeat",
               shading: str = "flat", corner_normals=None, levels=None) -> TexturedMesh:
        """Upload once: ``vertices`` (N, 3), ``faces`` (M, 3), ``corner_uv`` (M, 3, 2) (OpenGL's
        convention: v up, v = 0 the image's bottom row), ``image`` (H, W, 3|4) uint8 with row
        0 the top (None: untextured, light grey), seen by ``camera``. ``shading``: "flat" (face
        normals), "smooth" (``corner_normals`` (M, 3, 3)) or "unlit". ``levels``: the mip levels
        to upload (each (h, w, 4) uint8, level 0 first), else GL makes them for ``trilinear``."""
        ctx = self.ctx
        vertices = np.asarray(vertices, np.float64)
        faces = np.asarray(faces, np.int64)
        corners = vertices[faces].reshape(-1, 3)
        if shading == "smooth":
            normals = np.asarray(corner_normals, np.float64).reshape(-1, 3)
        else:
            a, b, c = (vertices[faces[:, k]] for k in range(3))
            n = np.cross(b - a, c - a)
            n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
            normals = np.repeat(n, 3, axis=0)
        data = np.hstack([corners, np.asarray(corner_uv, np.float64).reshape(-1, 2), normals]).astype(np.float32)
        buffer = ctx.buffer(data.tobytes())
        if image is None:  # the linker drops the unused coordinates: skip their bytes
            vao = ctx.vertex_array(self.plain, [(buffer, "3f 2x4 3f", "in_pos", "in_normal")])
        else:
            vao = ctx.vertex_array(self.program, [(buffer, "3f 2f 3f", "in_pos", "in_uv", "in_normal")])
        texture = None if image is None else self._texture(image, filter, wrap, levels)
        mvp = (gl_clip_matrix(camera.width, camera.height) @ camera.matrix()).astype(np.float32)
        return TexturedMesh(vao, texture, mvp.T.tobytes(), tuple(float(c) for c in camera.basis()[2]),
                            camera.width, camera.height, 0 if shading == "unlit" else 1)

    def _texture(self, image, filter: str, wrap: str, levels):
        ctx, gl = self.ctx, self.gl
        rgba = np.asarray(image, np.uint8)
        if rgba.shape[2] == 3:
            rgba = np.concatenate([rgba, np.full(rgba.shape[:2] + (1,), 255, np.uint8)], axis=2)
        height, width = rgba.shape[:2]
        texture = ctx.texture((width, height), 4, np.ascontiguousarray(rgba[::-1]).tobytes(),
                              internal_format=GL_SRGB8_ALPHA8)  # GL's rows start at the bottom
        if filter == "trilinear" or levels is not None:
            texture.build_mipmaps()  # GL's own levels (glGenerateMipmap), or the storage for the given ones
        for level, pixels in enumerate(levels or []):
            pixels = np.asarray(pixels, np.uint8)
            if pixels.shape[:2] != (max(1, height >> level), max(1, width >> level)):
                raise ValueError(f"mip level {level} is {pixels.shape[:2]}, GL's is "
                                 f"{(max(1, height >> level), max(1, width >> level))}")
            texture.write(np.ascontiguousarray(pixels[::-1]).tobytes(), level=level)
        minify, magnify = FILTERS[filter]
        texture.filter = (getattr(gl, minify), getattr(gl, magnify))
        if wrap not in ("repeat", "clamp"):
            raise ValueError(f"wrap {wrap!r}: moderngl sets repeat or clamp to edge only")
        texture.repeat_x = texture.repeat_y = wrap == "repeat"
        return texture

    def draw(self, mesh: TexturedMesh, cull: bool = True) -> np.ndarray:
        """One frame: clear (white), draw, read back; (H, W, 3) uint8, rows top-down."""
        gl, ctx = self.gl, self.ctx
        fbo = self.peer.framebuffer(mesh.width, mesh.height)
        fbo.use()
        fbo.clear(1.0, 1.0, 1.0, 1.0, depth=1.0)
        ctx.enable(gl.DEPTH_TEST)
        ctx.depth_func = "<"
        if cull:
            ctx.enable(gl.CULL_FACE)
        else:
            ctx.disable(gl.CULL_FACE)
        program = self.plain if mesh.texture is None else self.program
        program["mvp"].write(mesh.mvp)
        program["towards_eye"].value = mesh.towards_eye
        program["lit"].value = mesh.lit
        if mesh.texture is not None:
            mesh.texture.use(0)
        mesh.vao.render(gl.TRIANGLES)
        data = fbo.read(components=3, alignment=1)
        return np.frombuffer(data, np.uint8).reshape(mesh.height, mesh.width, 3)[::-1]
