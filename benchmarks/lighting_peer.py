"""The llvmpipe side of the ``lighting`` family (:mod:`benchmarks.lighting`): the same
Blinn-Phong per pixel in GLSL 330 (world position and smooth normal as varyings, the linear
sum encoded to sRGB in the shader) and the shadow pass (depth only into a square depth
texture from the light's camera, then 3x3 compares against the face's plane), on a
:class:`benchmarks.peers.Llvmpipe` context."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import rasterkit

from .peers import gl_clip_matrix

SOFTNESS = 1.0
"""``shadow_softness``: a filter reach of 1 texel, 3x3 texels (the GL side's loop is fixed at 3x3)."""

LIGHTGRAY = (211, 211, 211)  # RenderOptions.color's default, "lightgray"

MAX_LIGHTS = 4

# kind codes of the GL side's light table
AMBIENT, DIRECTIONAL, POINT = 0, 1, 2

_VS = """#version 330
uniform mat4 mvp;
in vec3 in_pos;
in vec3 in_normal;
out vec3 world;
out vec3 normal;
void main() {
    gl_Position = mvp * vec4(in_pos, 1.0);
    world = in_pos;
    normal = in_normal;
}
"""

_FS = """#version 330
#define SHADOWS %d
#define MAX_LIGHTS %d
uniform vec3 eye;
uniform vec3 base;       // linear
uniform vec3 specular;   // linear
uniform float shininess;
uniform int count;
uniform int kinds[MAX_LIGHTS];          // 0 ambient, 1 directional, 2 point
uniform vec3 positions[MAX_LIGHTS];     // world space (point lights)
uniform vec3 directions[MAX_LIGHTS];    // unit, towards the scene (directional lights)
uniform vec3 colors[MAX_LIGHTS];        // linear colour times intensity
#if SHADOWS
uniform int shadowed;                   // the light with the shadow map
uniform sampler2DShadow shadow_map;
uniform mat4 to_map;                    // world -> (u, v, depth) of the map, all in [0, 1]
uniform float size;                     // texels a side
uniform vec3 axis;                      // the light's direction (the map camera's axis)
uniform vec3 map_u;                     // a texel's step along u (right), world space
uniform vec3 map_v;                     // a texel's step along v (up), world space
uniform float depth_scale;              // world distance along the axis -> map depth units
// The share of the 3x3 texels around p's that see nothing nearer the light than p's face
// (percentage-closer filtering), as rasterkit's shadow_factor: none when the light l is behind
// the face (its normal n_face, from the screen-space derivatives, on the side of the shading
// normal n); else each texel's depth is compared with the depth at which the face's plane
// passes the texel's centre (at most 100 texels beyond p's), less a leeway of a texel plus
// the depth the plane slopes over a quarter texel and the filter's reach (1 texel).
float lit_share(vec3 p, vec3 n_face, vec3 n, vec3 l) {
    vec4 s = to_map * vec4(p, 1.0);
    vec3 c = s.xyz / s.w;
    if (c.x < 0.0 || c.y < 0.0 || c.x >= 1.0 || c.y >= 1.0) return 1.0;
    if (dot(n_face, n) < 0.0) n_face = -n_face;
    float towards = dot(n_face, l);
    if (towards <= 0.0) return 0.0;
    float lit = min(towards / length(l), 1.0);
    float facing = dot(n_face, axis);
    vec2 gradient = abs(facing) > 1e-6 ? -vec2(dot(n_face, map_u), dot(n_face, map_v)) / facing * depth_scale
                                       : vec2(0.0);
    float slope = min(sqrt(max(1.0 - lit * lit, 0.0)) / lit, 20.0);
    float texel_depth = length(map_u) * depth_scale;
    float leeway = texel_depth * (1.0 + slope * 1.25);
    vec2 t = c.xy * size;
    vec2 centre = floor(t) + 0.5;
    float seen = 0.0;
    for (int j = -1; j <= 1; ++j)
        for (int i = -1; i <= 1; ++i) {
            vec2 at = centre + vec2(i, j);
            float expected = min(c.z + dot(gradient, at - t), c.z + 100.0 * texel_depth);
            seen += texture(shadow_map, vec3(at / size, expected - leeway));
        }
    return seen / 9.0;
}
#endif
in vec3 world;
in vec3 normal;
out vec4 frag;
vec3 encode(vec3 c) {
    c = clamp(c, 0.0, 1.0);
    return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}
void main() {
    vec3 n = normalize(normal);
    vec3 v = normalize(eye - world);
    vec3 sum = vec3(0.0);
    for (int k = 0; k < count; ++k) {
        if (kinds[k] == 0) { sum += base * colors[k]; continue; }
        vec3 l;
        float a = 1.0;
        if (kinds[k] == 1) {
            l = -directions[k];
        } else {
            vec3 d = positions[k] - world;
            float d2 = dot(d, d);
            l = d * inversesqrt(d2);
            a = 1.0 / d2;
        }
        float ndl = dot(n, l);
        if (ndl <= 0.0) continue;
#if SHADOWS
        if (k == shadowed) a *= lit_share(world, normalize(cross(dFdx(world), dFdy(world))), n, l);
#endif
        vec3 h = normalize(l + v);
        sum += a * colors[k] * (base * ndl + specular * pow(max(dot(n, h), 0.0), shininess));
    }
    frag = vec4(encode(sum), 1.0);
}
"""


def decode_srgb(rgb) -> np.ndarray:
    """Linear light of sRGB values 0..255 (the exact transfer function)."""
    c = np.asarray(rgb, np.float64) / 255.0
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)



@dataclass(frozen=True)
class Scene:
    """The lights of one frame: rasterkit's records and the GL side's uniform table."""

    lights: tuple
    kinds: tuple
    positions: tuple
    directions: tuple
    colors: tuple
    shadowed: int  # the light with a shadow map, -1: none


@dataclass
class LitMesh:
    """A mesh uploaded to llvmpipe for one lit frame: its vertex arrays and uniforms."""

    vao: object
    program: object
    uniforms: dict
    width: int
    height: int
    depth_vao: object = None  # the shadow pass (None: no shadows)
    light_mvp: bytes = b""
    shadow_fbo: object = None
    shadow_texture: object = None


class LitGL:
    """Blinn-Phong frames (and the shadow pass) on a :class:`benchmarks.peers.Llvmpipe` context."""

    def __init__(self, llvmpipe):
        self.peer, self.ctx, self.gl = llvmpipe, llvmpipe.ctx, llvmpipe.gl
        self.programs = {shadows: self.ctx.program(vertex_shader=_VS, fragment_shader=_FS % (shadows, MAX_LIGHTS))
                         for shadows in (0, 1)}
        self._shadow_targets: dict[int, tuple] = {}

    def upload(self, mesh, camera, lights: Scene, map_size: int = 0) -> LitMesh:
        """Upload once: the mesh's corners with their smooth normals (one vertex per distinct
        (vertex, normal) pair, indexed, as rasterkit shades them), the camera and ``lights``;
        with a shadowed light, the positions for the depth pass and the light's camera (the
        one rasterkit fits, ``map_size`` texels a side)."""
        ctx = self.ctx
        normals, corners, _ = mesh.smooth_corners
        pairs, rows = np.unique(np.stack([mesh.faces.ravel(), np.asarray(corners).ravel()], axis=1), axis=0,
                                return_inverse=True)
        data = np.hstack([mesh.vertices[pairs[:, 0]], normals[pairs[:, 1]]]).astype(np.float32)
        index = ctx.buffer(np.asarray(rows, np.int32).ravel().tobytes())
        program = self.programs[1 if lights.shadowed >= 0 else 0]
        vao = ctx.vertex_array(program, [(ctx.buffer(data.tobytes()), "3f 3f", "in_pos", "in_normal")],
                               index_buffer=index, index_element_size=4)
        if len(lights.kinds) > MAX_LIGHTS:
            raise ValueError(f"at most {MAX_LIGHTS} lights on the GL side")
        options = rasterkit.RenderOptions()
        pad = MAX_LIGHTS - len(lights.kinds)
        mvp = (gl_clip_matrix(camera.width, camera.height) @ camera.matrix()).astype(np.float32)
        uniforms = {"mvp": mvp.T.tobytes(), "eye": tuple(float(c) for c in camera.eye),
                    "base": tuple(float(c) for c in decode_srgb(LIGHTGRAY)), "specular": (options.specular,) * 3,
                    "shininess": float(options.shininess), "count": len(lights.kinds),
                    "kinds": list(lights.kinds) + [0] * pad,
                    "positions": list(lights.positions) + [(0.0, 0.0, 0.0)] * pad,
                    "directions": list(lights.directions) + [(0.0, 0.0, 0.0)] * pad,
                    "colors": list(lights.colors) + [(0.0, 0.0, 0.0)] * pad}
        if camera.kind != "perspective":
            raise ValueError("the GL side's viewer is the camera's eye: a perspective camera only")
        lit = LitMesh(vao, program, uniforms, camera.width, camera.height)
        if lights.shadowed >= 0:
            self._shadows(lit, mesh, camera, lights, map_size)
        return lit

    def _shadows(self, lit: LitMesh, mesh, camera, lights: Scene, size: int) -> None:
        """The depth pass's vertex array, the light's camera and its depth texture."""
        from rasterkit.raster.shadows import shadow_maps

        ctx = self.ctx
        maps = shadow_maps(mesh, lights.lights, camera, size, SOFTNESS)  # rasterkit's fit: the same map area
        to_raster = maps.matrices[0]
        axes = maps.axes[0]
        texel_world, near, far = axes[6], axes[8], axes[9]
        lit.light_mvp = (gl_clip_matrix(size, size) @ to_raster).astype(np.float32).T.tobytes()
        # raster (x right, y down, z in [0, 1]) -> texture (u right, v up: GL's rows start at the bottom)
        to_texture = np.array([[1.0 / size, 0, 0, 0], [0, -1.0 / size, 0, 1.0], [0, 0, 1, 0], [0, 0, 0, 1]])
        lit.uniforms.update({"to_map": (to_texture @ to_raster).astype(np.float32).T.tobytes(),
                             "size": float(size), "axis": tuple(float(c) for c in axes[3:6]),
                             "map_u": tuple(float(c) for c in axes[10:13] * texel_world),
                             "map_v": tuple(float(c) for c in -axes[13:16] * texel_world),  # the map's y is down
                             "depth_scale": float(1.0 / (far - near)), "shadowed": lights.shadowed,
                             "shadow_map": 0})
        positions = ctx.buffer(mesh.vertices.astype(np.float32).tobytes())
        faces = ctx.buffer(mesh.faces.astype(np.int32).tobytes())
        lit.depth_vao = ctx.vertex_array(self.peer.plain, [(positions, "3f", "in_pos")], index_buffer=faces,
                                         index_element_size=4)
        lit.shadow_fbo, lit.shadow_texture = self._shadow_target(size)

    def _shadow_target(self, size: int) -> tuple:
        """A depth texture of ``size`` texels a side (nearest, compare ``<=``) and its framebuffer, made once."""
        if size not in self._shadow_targets:
            texture = self.ctx.depth_texture((size, size))
            texture.filter = (self.gl.NEAREST, self.gl.NEAREST)
            texture.compare_func = "<="
            texture.repeat_x = texture.repeat_y = False
            self._shadow_targets[size] = (self.ctx.framebuffer(depth_attachment=texture), texture)
        return self._shadow_targets[size]

    def draw(self, lit: LitMesh) -> np.ndarray:
        """One frame: (the shadow pass: clear the map, draw depth from the light) clear
        (white), draw lit, read back; (H, W, 3) uint8, rows top-down."""
        gl, ctx = self.gl, self.ctx
        ctx.enable(gl.DEPTH_TEST)
        ctx.depth_func = "<"
        ctx.polygon_offset = (0.0, 0.0)
        if lit.depth_vao is not None:
            lit.shadow_fbo.use()
            lit.shadow_fbo.clear(depth=1.0)
            ctx.disable(gl.CULL_FACE)  # casters cast from both sides, as rasterkit's
            self.peer.plain["mvp"].write(lit.light_mvp)
            lit.depth_vao.render(gl.TRIANGLES)
            lit.shadow_texture.use(0)
        fbo = self.peer.framebuffer(lit.width, lit.height)
        fbo.use()
        fbo.clear(1.0, 1.0, 1.0, 1.0, depth=1.0)
        ctx.enable(gl.CULL_FACE)
        program = lit.program
        for name, value in lit.uniforms.items():
            if name not in program:
                continue
            if isinstance(value, bytes):
                program[name].write(value)
            else:
                program[name].value = value
        lit.vao.render(gl.TRIANGLES)
        data = fbo.read(components=3, alignment=1)
        return np.frombuffer(data, np.uint8).reshape(lit.height, lit.width, 3)[::-1]
