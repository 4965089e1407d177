"""The images of a vision pipeline (issue 17): metric depth against ray-plane intersection,
normals against a sphere's analytic normals, object ids of a scene, visible faces, files."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

import rasterkit
from rasterkit import Camera, Mesh, Scene, shapes, transform


def _plane(point, normal, size=20.0):
    """A square of side ``size`` through ``point`` facing ``normal``: two triangles."""
    normal = np.asarray(normal, float) / np.linalg.norm(normal)
    a = np.cross(normal, [0.3, 1.0, 0.1])
    a /= np.linalg.norm(a)
    b = np.cross(normal, a)
    corners = np.asarray(point) + size / 2 * np.array([-a - b, a - b, a + b, -a + b])
    faces = np.array([[0, 1, 2], [0, 2, 3]])
    if np.dot(np.cross(corners[1] - corners[0], corners[2] - corners[0]), normal) < 0:
        faces = faces[:, ::-1]
    return Mesh(corners, faces)


def _pixel_rays(camera):
    y, x = np.mgrid[0:camera.height, 0:camera.width] + 0.5
    return camera.ray(x, y)


def _optical_axis(camera):
    return -camera.basis()[2]


@pytest.mark.parametrize("camera", [
    Camera.look_at((0.5, 1.0, 6.0), (0, 0, 0), fov_y=50, width=160, height=120, near=0.5, far=50),
    Camera.from_opencv([[300, 0, 70], [0, 340, 65], [0, 0, 1]], np.eye(3), [0.2, -0.1, 4.0], 160, 120,
                       near=0.1, far=100),
    Camera.orthographic((1, 2, 7), (0, 0, 0), view_height=6, width=96, height=80, near=1, far=20),
])
def test_camera_depth_equals_the_ray_plane_depth(camera):
    point, normal = np.array([0.1, -0.2, 0.3]), np.array([0.4, 0.3, 1.0])
    plane = _plane(point, normal)
    n = normal / np.linalg.norm(normal)
    if np.dot(n, camera.basis()[2]) < 0:  # seen from its back: turn it round
        plane = Mesh(plane.vertices, plane.faces[:, ::-1])
    fb = rasterkit.render(plane, camera, mode="solid", cull="none")
    depth = fb.camera_depth()
    assert depth.dtype == np.float32 and depth.shape == (camera.height, camera.width)
    origin, direction = _pixel_rays(camera)
    t = ((point - origin) @ n) / (direction @ n)
    hit = origin + t[..., None] * direction
    expected = (hit - np.asarray(camera.eye)) @ _optical_axis(camera)
    drawn = depth > 0
    assert drawn.mean() > 0.9  # the plane fills the view
    assert np.max(np.abs(depth[drawn] - expected[drawn]) / expected[drawn]) < 1e-4
    assert np.all(depth[~drawn] == 0)


def test_camera_depth_is_zero_where_nothing_is_drawn_and_needs_a_render():
    camera = Camera.look_at((0, 0, 5), (0, 0, 0), width=32, height=24)
    fb = rasterkit.render(shapes.cube(0.5), camera, mode="solid")
    depth = fb.camera_depth()
    assert depth[0, 0] == 0 and depth[12, 16] == pytest.approx(4.75, rel=1e-5)
    with pytest.raises(ValueError, match="render"):
        rasterkit.Framebuffer(4, 4).camera_depth()


def _sphere_normals(camera, center, radius):
    """Analytic camera-space normals where the pixel rays hit the sphere, NaN elsewhere."""
    origin, direction = _pixel_rays(camera)
    oc = origin - center
    b = np.einsum("...k,...k", oc, direction)
    disc = b * b - (np.einsum("...k,...k", oc, oc) - radius * radius)
    t = -b - np.sqrt(np.where(disc > 0, disc, np.nan))
    world = (origin + t[..., None] * direction - center) / radius
    return world @ camera.view_matrix()[:3, :3].T


@pytest.mark.parametrize("shading, limit", [("smooth", 1.0), ("flat", 3.0)])
@pytest.mark.parametrize("size", [(200, 160), (360, 240)])  # the maps on one thread, and shared out
def test_normals_of_a_subdivided_sphere(shading, limit, size):
    center, radius = np.array([0.3, -0.2, 0.1]), 1.2
    mesh = shapes.icosphere(5, radius)
    mesh = Mesh(mesh.vertices + center, mesh.faces)
    camera = Camera.look_at((1.0, 2.0, 5.0), center, fov_y=40, width=size[0], height=size[1])
    fb = rasterkit.render(mesh, camera, mode="solid", shading=shading, normals=True)
    assert fb.ids is None and fb.normals.dtype == np.float32 and fb.normals.shape == (size[1], size[0], 3)
    drawn = ~np.isnan(fb.normals[..., 0])
    assert np.all(np.isnan(fb.normals[~drawn]))
    assert np.allclose(np.linalg.norm(fb.normals[drawn], axis=1), 1.0, atol=1e-5)
    expected = _sphere_normals(camera, center, radius)
    both = drawn & ~np.isnan(expected[..., 0])
    assert both.sum() > 0.95 * drawn.sum()
    cos = np.clip(np.einsum("ik,ik->i", fb.normals[both], expected[both]), -1, 1)
    assert np.median(np.degrees(np.arccos(cos))) <= limit
    assert np.all(fb.normals[both][:, 2] > -0.2)  # the visible side faces the camera (+z)


def test_normals_of_a_flat_face_are_its_camera_space_normal():
    camera = Camera.look_at((0, 0, 5), (0, 0, 0), width=40, height=30)
    fb = rasterkit.render(_plane((0, 0, 0), (0, 0, 1), 2.0), camera, mode="solid", normals=True, ids=True)
    assert fb.ids is not None
    drawn = fb.ids >= 0
    assert np.allclose(fb.normals[drawn], [0, 0, 1], atol=1e-6)


def _three_objects():
    scene = Scene()
    scene.add(shapes.cube(0.8), transform.translate(-1.5, 0, 0), color="red")
    scene.add(shapes.icosphere(2, 0.5), transform.translate(0, 0, 0))
    scene.add(shapes.torus(0.5, 0.2), transform.compose(transform.rotate_x(1.0), transform.translate(1.5, 0, 0)))
    return scene


@pytest.mark.parametrize("size", [(160, 90), (400, 225)])  # the maps on one thread, and shared out
def test_object_ids_of_a_three_object_scene(size):
    scene = _three_objects()
    camera = Camera.look_at((0, 0.5, 6), (0, 0, 0), fov_y=45, width=size[0], height=size[1])
    fb = rasterkit.render(scene, camera, mode="solid", ids=True)
    assert fb.object_ids.dtype == np.int32
    for k, obj in enumerate(scene.objects):
        alone = rasterkit.render(Scene().add(obj.mesh, obj.matrix), camera, mode="solid", ids=True)
        seen = alone.ids >= 0
        assert seen.any()
        assert np.array_equal(fb.object_ids == k, seen)  # the objects do not overlap in the image
        assert np.array_equal(fb.ids[seen], alone.ids[seen])  # face index within the object
    assert np.all(fb.object_ids[fb.ids < 0] == -1) and np.all(fb.ids[fb.object_ids < 0] == -1)
    faces, counts = fb.visible_faces()
    merged = rasterkit.render(scene.world_mesh(), camera, mode="solid", ids=True).ids
    expected_faces, expected_counts = np.unique(merged[merged >= 0], return_counts=True)
    assert np.array_equal(faces, expected_faces) and np.array_equal(counts, expected_counts)


def test_a_mesh_render_without_ids_has_no_object_ids():
    camera = Camera.look_at((0, 0, 5), (0, 0, 0), width=32, height=24)
    fb = rasterkit.render(shapes.cube(), camera, mode="solid", ids=True)
    assert fb.object_ids is None and fb.normals is None
    faces, counts = fb.visible_faces()
    assert counts.sum() == (fb.ids >= 0).sum() and set(faces) == set(np.unique(fb.ids[fb.ids >= 0]))
    with pytest.raises(ValueError, match="ids=True"):
        rasterkit.render(shapes.cube(), camera, mode="solid").visible_faces()


def test_samples_keep_the_centre_samples_maps():
    camera = Camera.look_at((0, 1, 5), (0, 0, 0), width=48, height=36)
    one = rasterkit.render(_three_objects(), camera, mode="solid", ids=True, normals=True)
    many = rasterkit.render(_three_objects(), camera, mode="solid", ids=True, normals=True, samples=4)
    assert np.array_equal(one.object_ids, many.object_ids)
    assert np.array_equal(one.normals, many.normals, equal_nan=True)


def test_saved_depth_normals_and_ids(tmp_path):
    camera = Camera.look_at((0, 0, 3), (0, 0, 0), width=40, height=30, near=0.5, far=10)
    fb = rasterkit.render(_three_objects(), camera, mode="solid", ids=True, normals=True)
    depth = fb.camera_depth()
    fb.save_depth(tmp_path / "d.npy")
    assert np.array_equal(np.load(tmp_path / "d.npy"), depth)
    fb.save_depth(tmp_path / "d.png")
    png = np.asarray(Image.open(tmp_path / "d.png"))
    assert png.dtype in (np.uint16, np.int32) and np.array_equal(png, np.rint(depth * 1000).astype(png.dtype))
    fb.save_normals(tmp_path / "n.png")
    assert np.asarray(Image.open(tmp_path / "n.png")).shape == (30, 40, 3)
    fb.save_ids(tmp_path / "o.png", objects=True)
    assert np.array_equal(np.asarray(Image.open(tmp_path / "o.png")).astype(int) - 1, fb.object_ids)
    fb.save_ids(tmp_path / "i.npy")
    assert np.array_equal(np.load(tmp_path / "i.npy"), fb.ids)
    with pytest.raises(ValueError, match="extension"):
        fb.save_depth(tmp_path / "d.jpg")


# --- against Mesa llvmpipe's depth buffer, the same OpenGL matrices -----------------------------

_GL_VS = """#version 330
uniform mat4 projection;
uniform mat4 view;
in vec3 in_pos;
void main() { gl_Position = projection * view * vec4(in_pos, 1.0); }
"""
_GL_FS = """#version 330
out vec4 frag;
void main() { frag = vec4(1.0); }
"""


def _llvmpipe_depth(mesh, camera):
    """llvmpipe's depth buffer (rows top-down), linearised with the camera's near and far."""
    moderngl = pytest.importorskip("moderngl")
    try:
        ctx = moderngl.create_standalone_context(backend="egl")
    except Exception as error:  # no EGL on this machine
        pytest.skip(f"no headless EGL context: {error}")
    projection, view = camera.opengl_matrices()
    program = ctx.program(vertex_shader=_GL_VS, fragment_shader=_GL_FS)
    program["projection"].write(projection.T.astype("f4").tobytes())  # GLSL is column-major
    program["view"].write(view.T.astype("f4").tobytes())
    vao = ctx.vertex_array(program, [(ctx.buffer(mesh.vertices.astype("f4").tobytes()), "3f", "in_pos")],
                           index_buffer=ctx.buffer(mesh.faces.astype("i4").tobytes()), index_element_size=4)
    size = (camera.width, camera.height)
    depth_texture = ctx.depth_texture(size)
    fbo = ctx.framebuffer(color_attachments=[ctx.renderbuffer(size)], depth_attachment=depth_texture)
    fbo.use()
    fbo.clear(0, 0, 0, 0, depth=1.0)
    ctx.enable(moderngl.DEPTH_TEST | moderngl.CULL_FACE)
    vao.render(moderngl.TRIANGLES)
    window = np.frombuffer(depth_texture.read(), "f4").reshape(camera.height, camera.width)[::-1].astype(float)
    ctx.release()
    n, f = camera.near, camera.far
    return np.where(window < 1.0, f * n / (f - window * (f - n)), 0.0)


@pytest.mark.parametrize("name", ["suzanne", "cow"])
def test_camera_depth_equals_llvmpipe_linearised_depth(name, models_dir):
    path = models_dir / f"{name}.obj"
    if not path.is_file():
        pytest.skip(f"{path} is absent")
    mesh = rasterkit.load_obj(path)
    center, radius = mesh.bounding_sphere()
    k = np.array([[420.0, 0, 150.0], [0, 400.0, 130.0], [0, 0, 1]])
    r = np.array([[1.0, 0, 0], [0, -1, 0], [0, 0, -1]])  # OpenCV camera looking down world -z
    t = -r @ (np.asarray(center) + [0, 0, 3.0 * radius])
    camera = Camera.from_opencv(k, r, t, 320, 240, near=0.5 * radius, far=10 * radius)
    ours = rasterkit.render(mesh, camera, mode="solid").camera_depth().astype(float)
    theirs = _llvmpipe_depth(mesh, camera)
    both = (ours > 0) & (theirs > 0)
    assert both.sum() > 0.98 * max((ours > 0).sum(), (theirs > 0).sum())
    assert np.median(np.abs(ours[both] - theirs[both]) / theirs[both]) < 1e-4


# --- the command line --------------------------------------------------------------------------


def test_cli_renders_an_opencv_camera_with_depth_normals_and_ids(tmp_path):
    import json

    from rasterkit.cli import main

    k = [[100.0, 0, 30.0], [0, 110.0, 22.0], [0, 0, 1]]
    r = [[1, 0, 0], [0, -1, 0], [0, 0, -1]]  # looking down world -z, from z = 4
    cam = tmp_path / "cam.json"
    cam.write_text(json.dumps(dict(K=k, R=r, t=[0, 0, 4.0], width=64, height=48)))
    out = tmp_path / "rgb.png"
    args = ["render", "--demo", "-o", str(out), "--mode", "solid", "--camera-opencv", str(cam),
            "--depth", str(tmp_path / "d.npy"), "--normals", str(tmp_path / "n.png"), "--ids", str(tmp_path / "i.png")]
    assert main(args) == 0
    assert Image.open(out).size == (64, 48)
    depth = np.load(tmp_path / "d.npy")
    ids = np.asarray(Image.open(tmp_path / "i.png")).astype(int) - 1
    assert np.array_equal(depth > 0, ids >= 0) and (ids >= 0).any()
    mesh = shapes.demo()
    camera = Camera.from_opencv(k, r, [0, 0, 4.0], 64, 48, near=depth[depth > 0].min() / 2, far=100)
    expected = rasterkit.render(mesh, camera, mode="solid").camera_depth()
    assert np.allclose(depth, expected, rtol=1e-4)
    assert np.asarray(Image.open(tmp_path / "n.png")).shape == (48, 64, 3)
    assert main(["render", "--demo", "-o", str(out), "--depth", str(tmp_path / "d.txt")]) == 2
    cam.write_text(json.dumps(dict(K=k, R=r, t=[0, 0, 4.0])))
    assert main(["render", "--demo", "-o", str(out), "--camera-opencv", str(cam)]) == 2


def test_a_plain_render_loads_none_of_the_vision_passes_and_compiles_no_maps():
    import subprocess
    import sys

    code = ("import sys, rasterkit; from rasterkit import Camera, shapes; "
            "from rasterkit.raster.kernels.bands import draw_bands; "
            "fb = rasterkit.render(shapes.cube(), Camera.look_at((0, 0, 5), (0, 0, 0), width=32, height=24), 'solid'); "
            "fb.depth; print(sorted(m for m in sys.modules if m.split('.')[-1] in "
            "('maps', 'vision', 'points', 'distortion'))); "
            "print([str(s[-2]) + ' ' + str(s[-1]) for s in draw_bands.signatures])")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    # the band worker was compiled without the maps and the textures (its last arguments None: pruned)
    assert out.stdout.split("\n")[:2] == ["[]", "['none none']"]
