"""The peer of ``rasterkit render MODEL -o OUT --size WxH --mode solid``: trimesh + moderngl.

Usage: ``python benchmarks/peer_cli.py MODEL.obj OUT.png WIDTH HEIGHT``. It does what the
rasterkit command does, in the short script a user of those libraries would write: load the
OBJ, frame its bounding sphere with the same camera (azimuth 30°, elevation 20°, fov_y 45°),
draw flat Lambert faces lit by a headlight with back faces culled, save a PNG with Pillow.
It does not import rasterkit, so its start-up cost is its own.
"""

from __future__ import annotations

import sys

import moderngl
import numpy as np
import trimesh
from PIL import Image

VS = """#version 330
uniform mat4 mvp; uniform vec3 light;
in vec3 in_pos; in vec3 in_normal; flat out vec3 shade;
void main() {
    gl_Position = mvp * vec4(in_pos, 1.0);
    shade = vec3(0.827) * (0.25 + 0.75 * max(dot(in_normal, light), 0.0));
}"""
FS = """#version 330
flat in vec3 shade; out vec4 frag;
void main() { frag = vec4(shade, 1.0); }"""


def camera(center, radius, width, height, azimuth=30.0, elevation=20.0, fov_y=45.0):
    """OpenGL model-view-projection (4x4) framing the sphere, and the direction to the eye."""
    az, el = np.radians(azimuth), np.radians(elevation)
    back = np.array([np.cos(el) * np.sin(az), np.sin(el), np.cos(el) * np.cos(az)])
    half = np.radians(fov_y) / 2
    if width < height:  # the sphere touches the narrower side of the image
        half = np.arctan(np.tan(half) * width / height)
    distance = radius / np.sin(half)
    eye = center + distance * back
    right = np.cross([0.0, 1.0, 0.0], back)
    right /= np.linalg.norm(right)
    view = np.eye(4)
    view[:3, :3] = np.stack([right, np.cross(back, right), back])
    view[:3, 3] = -view[:3, :3] @ eye
    near, far = max(distance - 1.5 * radius, distance * 1e-3), distance + 1.5 * radius
    f = 1.0 / np.tan(np.radians(fov_y) / 2)
    proj = np.array([[f * height / width, 0, 0, 0], [0, f, 0, 0],
                     [0, 0, (far + near) / (near - far), 2 * far * near / (near - far)],
                     [0, 0, -1, 0]])
    return proj @ view, back


def main(model, out, width, height):
    mesh = trimesh.load(model, force="mesh", process=False)
    vertices, faces = np.asarray(mesh.vertices), np.asarray(mesh.faces)
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    center = (lo + hi) / 2
    mvp, light = camera(center, np.linalg.norm(vertices - center, axis=1).max(), width, height)
    ctx = moderngl.create_standalone_context(backend="egl")
    program = ctx.program(vertex_shader=VS, fragment_shader=FS)
    program["mvp"].write(mvp.astype("f4").T.tobytes())
    program["light"].value = tuple(light)
    normals = np.repeat(np.asarray(mesh.face_normals), 3, axis=0)
    data = np.hstack([vertices[faces.ravel()], normals]).astype("f4")
    vao = ctx.vertex_array(program, [(ctx.buffer(data.tobytes()), "3f 3f", "in_pos", "in_normal")])
    fbo = ctx.framebuffer([ctx.renderbuffer((width, height), 4)], ctx.depth_renderbuffer((width, height)))
    fbo.use()
    fbo.clear(1.0, 1.0, 1.0, 1.0)
    ctx.enable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
    vao.render()
    image = np.frombuffer(fbo.read(components=3, alignment=1), np.uint8).reshape(height, width, 3)
    Image.fromarray(np.ascontiguousarray(image[::-1])).save(out)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4]))
