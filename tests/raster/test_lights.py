"""Lights (rasterkit.Light) and Blinn-Phong flat and smooth shading, against the NumPy
reference of tests/support/reference_lighting.py."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

import rasterkit as rk
from rasterkit.colors import rgba
from rasterkit.raster.kernels.lights import lit_colors
from rasterkit.raster.lights import NO_SHADOWS, light_table
from support.raycast import surface_points
from support.reference_lighting import blinn_phong, linear_to_srgb255, srgb_to_linear

GREY = np.array([[211.0, 211.0, 211.0]])  # "lightgray", the default colour


def as_dict(light: rk.Light, camera=None) -> dict:
    """A Light as the reference reads it (a headlight: directional along the camera's view)."""
    colour = srgb_to_linear(np.array(rgba(light.color)[:3]) / 255.0) * light.intensity
    kind, direction = light.kind, light.direction
    if kind == "headlight":
        kind, direction = "directional", -np.asarray(camera.backward())
    return dict(kind=kind, color=colour, direction=direction, position=light.position, range=light.range,
                angle=light.angle, blend=light.blend)


LIGHTS = [
    rk.Light.directional((-1, -2, -3), color=(255, 200, 150), intensity=0.8),
    rk.Light.point((1.5, 1.0, 2.5), color="white", intensity=6.0, range=8.0),
    rk.Light.spot((0.0, 2.5, 2.0), (0, -1, -0.8), angle=60, blend=0.3, color="#80c0ff", intensity=9.0),
    rk.Light.ambient("white", 0.05),
]


def test_the_kernel_agrees_with_the_reference_for_every_kind_of_light():
    rng = np.random.default_rng(7)
    points = rng.uniform(-1, 1, (400, 3))
    normals = rng.normal(size=(400, 3))
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    base = rng.uniform(0, 255, (400, 3)).astype(np.float32)
    eye = np.array([0.3, 0.5, 4.0])
    camera = rk.Camera.look_at(tuple(eye), (0, 0, 0))
    lights = LIGHTS + [rk.Light.headlight(intensity=0.5)]
    for chosen in [[light] for light in lights] + [lights]:
        table = light_table(tuple(chosen), -np.asarray(camera.backward()))
        got = lit_colors(points, normals, base, np.full((1, 3), 0.3), np.array([20.0]), np.zeros((1, 3)), table, eye,
                         True, np.zeros(3), False, NO_SHADOWS)
        want = blinn_phong(points, normals, base, [as_dict(light, camera) for light in chosen], eye,
                           specular=(0.3, 0.3, 0.3), shininess=20.0)
        np.testing.assert_allclose(got, want, atol=1e-3, err_msg=str(chosen))


def test_a_spot_light_is_full_inside_its_inner_cone_and_dark_outside_its_outer_cone():
    spot = rk.Light.spot((0, 0, 0), (0, 0, -1), angle=60, blend=0.5, intensity=1.0)
    half = np.radians(30)
    angles = np.radians([0, 10, 14.9, 15.1, 20, 29.9, 30.1, 45])  # inner cone: 15 degrees
    points = np.stack([np.sin(angles), np.zeros_like(angles), -np.cos(angles)], axis=1)  # at distance 1
    normals = -points  # facing the light: n.l = 1
    table = light_table((spot,), np.array([0, 0, -1.0]))
    got = lit_colors(points, normals, np.full((1, 3), 255, np.float32), np.zeros((1, 3)), np.array([1.0]),
                     np.zeros((1, 3)), table, np.zeros(3), True, np.zeros(3), False, NO_SHADOWS)[:, 0]
    assert (got[angles < np.radians(15)] > 254.9).all()  # full light: white
    assert (got[angles > half] == 0).all()
    fading = (angles > np.radians(15)) & (angles < half)
    assert (np.diff(got[fading]) < 0).all() and (got[fading] > 0).all() and (got[fading] < 255).all()


def test_flat_faces_are_lit_at_their_centroids_as_the_reference_says():
    mesh = rk.shapes.icosphere(2)
    camera = rk.Camera.look_at((0.4, 0.6, 3.5), (0, 0, 0), width=160, height=120, fov_y=45)
    fb = rk.render(mesh, camera, "solid", lights=LIGHTS, ids=True)
    centroids = mesh.vertices[mesh.faces].mean(axis=1)
    want = np.floor(blinn_phong(centroids, mesh.face_normals.astype(np.float64), GREY,
                                [as_dict(light) for light in LIGHTS], camera.eye) + 0.5)
    seen = fb.ids >= 0
    assert seen.sum() > 5000
    diff = np.abs(fb.color[seen].astype(int) - want[fb.ids[seen]])
    assert diff.max() <= 1, diff.max()


def test_smooth_shading_interpolates_the_corners_colours():
    # one triangle facing a parallel camera: perspective-correct interpolation is linear in the image
    vertices = np.array([[-1.0, -0.8, 0.0], [1.2, -0.6, 0.0], [-0.1, 1.0, 0.0]])
    normals = np.array([[-0.5, -0.3, 1.0], [0.6, -0.2, 1.0], [0.0, 0.5, 1.0]])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    mesh = rk.Mesh(vertices, np.array([[0, 1, 2]]), normals=normals)
    camera = rk.Camera.orthographic((0, 0, 5), (0, 0, 0), view_height=2.4, width=120, height=120)
    lights = [rk.Light.point((0.5, 0.5, 1.0), intensity=1.5), rk.Light.ambient(intensity=0.1)]
    fb = rk.render(mesh, camera, "solid", shading="smooth", lights=lights, ids=True)
    # a parallel camera: the viewer is along its viewing direction, wherever the point
    corner = blinn_phong(vertices, normals, GREY, [as_dict(light) for light in lights], None,
                         view=camera.backward())
    raster = camera.project(vertices)[:, :2]
    j, i = np.nonzero(fb.ids >= 0)
    assert len(j) > 2000
    px, py = i + 0.5, j + 0.5
    (x0, y0), (x1, y1), (x2, y2) = raster
    area = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)
    b1 = ((px - x0) * (y2 - y0) - (x2 - x0) * (py - y0)) / area
    b2 = ((x1 - x0) * (py - y0) - (px - x0) * (y1 - y0)) / area
    b0 = 1 - b1 - b2
    want = b0[:, None] * corner[0] + b1[:, None] * corner[1] + b2[:, None] * corner[2]
    diff = np.abs(fb.color[j, i].astype(float) - np.floor(want + 0.5))
    assert diff.max() <= 1, diff.max()


def test_lights_add_up_in_linear_light():
    mesh = rk.shapes.icosphere(2)
    camera = rk.Camera.look_at((0.4, 0.6, 3.5), (0, 0, 0), width=160, height=120, fov_y=45)
    a = [rk.Light.directional((-1, -1, -2), color="orange", intensity=0.4)]
    b = [rk.Light.point((1, 2, 2), color="#4060ff", intensity=3.0)]
    one, two, both = (rk.render(mesh, camera, "solid", lights=lights, ids=True) for lights in (a, b, a + b))
    seen = both.ids >= 0
    added = linear_to_srgb255(srgb_to_linear(one.color[seen] / 255.0) + srgb_to_linear(two.color[seen] / 255.0))
    assert np.abs(both.color[seen] - added).max() <= 1.5
    assert (both.color[seen].astype(int) >= np.maximum(one.color[seen], two.color[seen]).astype(int) - 1).all()


def test_two_sided_faces_are_lit_on_their_backs_with_the_normal_turned_to_the_viewer():
    mesh = rk.Mesh(np.array([[-1.0, -1, 0], [1, -1, 0], [0, 1, 0]]), np.array([[0, 2, 1]]))  # faces -z
    camera = rk.Camera.look_at((0.3, 0.2, 3), (0, 0, 0), width=80, height=80)
    light = [rk.Light.point((0.5, 0.5, 1.5), intensity=2.0)]
    back = rk.render(mesh, camera, "solid", cull="none", lights=light, ids=True)
    seen = back.ids >= 0
    centroid = mesh.vertices.mean(axis=0, keepdims=True)
    normal = mesh.face_normals.astype(np.float64)
    lit = blinn_phong(centroid, normal, GREY, [as_dict(light[0])], camera.eye, two_sided=True)
    dark = blinn_phong(centroid, normal, GREY, [as_dict(light[0])], camera.eye)
    assert lit.min() > 100 and dark.max() == 0
    assert np.abs(back.color[seen].astype(int) - np.floor(lit + 0.5)).max() <= 1


def test_materials_bring_their_highlight_and_emission():
    mesh = rk.shapes.icosphere(2)
    material = rk.Material(name="shiny", diffuse=(0.2, 0.4, 0.8), specular=(1.0, 1.0, 1.0), shininess=8.0,
                           emission=(0.1, 0.0, 0.0))
    mesh = rk.Mesh(mesh.vertices, mesh.faces, materials=(material,), material_names=("shiny",),
                   face_materials=np.zeros(len(mesh.faces), np.int32), face_colors=np.tile((0.2, 0.4, 0.8),
                                                                                             (len(mesh.faces), 1)))
    camera = rk.Camera.look_at((0.4, 0.6, 3.5), (0, 0, 0), width=160, height=120, fov_y=45)
    lights = [rk.Light.directional((-0.3, -0.5, -1))]
    fb = rk.render(mesh, camera, "solid", lights=lights, ids=True)
    centroids = mesh.vertices[mesh.faces].mean(axis=1)
    want = blinn_phong(centroids, mesh.face_normals.astype(np.float64), np.float32(255) * mesh.face_colors,
                       [as_dict(lights[0])], camera.eye, specular=srgb_to_linear([1.0, 1.0, 1.0]), shininess=8.0,
                       emission=srgb_to_linear([0.1, 0.0, 0.0]))
    seen = fb.ids >= 0
    assert np.abs(fb.color[seen].astype(int) - np.floor(want[fb.ids[seen]] + 0.5)).max() <= 1
    assert fb.color[seen].max() == 255  # the highlight


def test_a_scenes_lights_are_used_unless_the_render_brings_its_own():
    mesh = rk.shapes.icosphere(2)
    camera = rk.Camera.look_at((0.4, 0.6, 3.5), (0, 0, 0), width=96, height=72)
    scene = rk.Scene(camera=camera).add(mesh)
    for light in LIGHTS[:2]:
        scene.add_light(light)
    np.testing.assert_array_equal(rk.render(scene, mode="solid").color,
                                  rk.render(mesh, camera, "solid", lights=LIGHTS[:2]).color)
    np.testing.assert_array_equal(rk.render(scene, mode="solid", lights=LIGHTS[2:]).color,
                                  rk.render(mesh, camera, "solid", lights=LIGHTS[2:]).color)
    assert not np.array_equal(rk.render(scene, mode="solid").color, rk.render(mesh, camera, "solid").color)


def test_lights_are_records_that_compare_hash_and_pickle():
    light = rk.Light.spot((1, 2, 3), (0, -1, 0), angle=30, color=(10, 20, 30), intensity=2, range=5)
    assert pickle.loads(pickle.dumps(light)) == light and hash(light) == hash(pickle.loads(pickle.dumps(light)))
    options = rk.RenderOptions(lights=[light])
    assert options.lights == (light,) and pickle.loads(pickle.dumps(options)) == options
    assert rk.RenderOptions(lights=()) == rk.RenderOptions()


@pytest.mark.parametrize("make, error, words", [
    (lambda: rk.Light.directional((0, 0, 0)), ValueError, "direction"),
    (lambda: rk.Light.directional((0, 0, float("nan"))), ValueError, "direction"),
    (lambda: rk.Light.point((0, 0)), TypeError, "position"),
    (lambda: rk.Light.point((0, 0, 0), intensity=-1), ValueError, "intensity"),
    (lambda: rk.Light.point((0, 0, 0), range=0), ValueError, "range"),
    (lambda: rk.Light.spot((0, 0, 0), (0, 0, 1), angle=180), ValueError, "angle"),
    (lambda: rk.Light.spot((0, 0, 0), (0, 0, 1), blend=1.5), ValueError, "blend"),
    (lambda: rk.Light.ambient(color="no such colour"), ValueError, "color"),
    (lambda: rk.Light("sun"), ValueError, "kind"),
    (lambda: rk.Light("directional", range=3.0, direction=(0, 0, 1)), ValueError, "range"),
    (lambda: rk.Light("ambient", shadows=True), ValueError, "shadows"),
    (lambda: rk.Light.directional((0, 0, 1), shadows=1), TypeError, "shadows"),
    (lambda: rk.RenderOptions(lights=[(0, 0, 1)]), TypeError, "lights[0]"),
    (lambda: rk.RenderOptions(lights=rk.Light.ambient()), TypeError, "lights"),
    (lambda: rk.RenderOptions(specular=2), ValueError, "specular"),
    (lambda: rk.RenderOptions(shininess=-1), ValueError, "shininess"),
    (lambda: rk.Scene().add_light("sun"), TypeError, "light"),
])
def test_bad_lights_fail_with_a_message_that_names_the_field(make, error, words):
    with pytest.raises(error, match=words.replace("[", r"\[").replace("]", r"\]")):
        make()


@pytest.mark.parametrize("kind", ["perspective", "parallel"])
def test_phong_pixels_are_lit_at_their_surface_points_as_a_ray_cast_says(kind):
    mesh = rk.shapes.icosphere(3)
    if kind == "perspective":
        camera = rk.Camera.look_at((0.5, 0.8, 3.2), (0, 0, 0), width=160, height=120, fov_y=45)
    else:
        camera = rk.Camera.orthographic((0.5, 0.8, 3.2), (0, 0, 0), view_height=2.6, width=160, height=120)
    fb = rk.render(mesh, camera, "solid", shading="phong", lights=LIGHTS, ids=True)
    points, weights = surface_points(mesh, camera, fb.ids)
    normals, corners, _ = mesh.smooth_corners
    f = fb.ids[fb.ids >= 0]
    normal = np.einsum("kc,kcd->kd", weights, normals[corners[f]])
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    eye, view = (camera.eye, None) if kind == "perspective" else (None, camera.backward())
    want = blinn_phong(points, normal, GREY, [as_dict(light) for light in LIGHTS], eye, view=view)
    got = fb.color[fb.ids >= 0].astype(int)
    diff = np.abs(got - np.floor(want + 0.5))
    assert len(got) > 5000 and diff.max() <= 1, diff.max()
    # lit within each face, not once per face: the faces drawn show many colours each
    packed = got @ np.array([1, 256, 65536])
    shades = [len(np.unique(packed[f == face])) for face in np.unique(f)]
    assert np.median(shades) >= 5


def _grid(n=24):
    """A (2n x 2n)-quad square in the plane z = 0, facing +z, with texture coordinates."""
    grid = rk.shapes.grid(n, n, 2.0)  # in the xz plane, y = 0
    vertices = grid.vertices[:, [0, 2, 1]] * np.array([1.0, -1.0, 1.0])
    faces = grid.faces
    normal = np.cross(vertices[faces[:, 1]] - vertices[faces[:, 0]], vertices[faces[:, 2]] - vertices[faces[:, 0]])
    if normal[:, 2].mean() < 0:  # wound to face +z
        faces = faces[:, ::-1].copy()
    return vertices, faces


def test_phong_lights_a_textured_face_from_its_texture_times_its_diffuse_colour():
    vertices, faces = _grid()
    material = rk.Material(name="m", diffuse=(0.5, 1.0, 0.8),
                           diffuse_map=rk.Texture(np.array([[[200, 120, 60]]], np.uint8), filter="nearest"))
    uv = (vertices[:, :2] + 1) / 2
    mesh = rk.Mesh(vertices, faces, uv=uv, uv_index=faces, materials=(material,), material_names=("m",),
                   face_materials=np.zeros(len(faces), np.int32))
    camera = rk.Camera.look_at((0.3, -0.4, 2.5), (0, 0, 0), width=120, height=100, fov_y=50)
    lights = [rk.Light.spot((0.2, 0.1, 1.2), (0, 0, -1), angle=70, blend=0.4, intensity=2.0),
              rk.Light.ambient(intensity=0.05)]
    for shading in ("flat", "smooth", "phong"):  # a textured face is lit per pixel under lights, whatever the shading
        fb = rk.render(mesh, camera, "solid", shading=shading, lights=lights, ids=True)
        points, _ = surface_points(mesh, camera, fb.ids)
        albedo = srgb_to_linear(np.array([200, 120, 60]) / 255.0) * srgb_to_linear(np.array([0.5, 1.0, 0.8]))
        want = blinn_phong(points, np.tile([0.0, 0.0, 1.0], (len(points), 1)), linear_to_srgb255(albedo)[None],
                           [as_dict(light) for light in lights], camera.eye, specular=(0.0, 0.0, 0.0))
        diff = np.abs(fb.color[fb.ids >= 0].astype(int) - np.floor(want + 0.5))
        assert diff.max() <= 1, (shading, diff.max())


def test_phong_interpolates_vertex_colours_before_lighting_them():
    vertices, faces = _grid(6)
    colours = np.stack([(vertices[:, 0] + 1) / 2, (vertices[:, 1] + 1) / 2, np.full(len(vertices), 0.3)], axis=1)
    mesh = rk.Mesh(vertices, faces, vertex_colors=colours)
    camera = rk.Camera.look_at((0.3, -0.4, 2.5), (0, 0, 0), width=120, height=100, fov_y=50)
    lights = [rk.Light.point((0.5, 0.5, 1.0), intensity=1.5)]
    fb = rk.render(mesh, camera, "solid", shading="phong", lights=lights, ids=True)
    points, weights = surface_points(mesh, camera, fb.ids)
    base = np.einsum("kc,kcd->kd", weights, colours[faces[fb.ids[fb.ids >= 0]]]) * 255.0
    want = blinn_phong(points, np.tile([0.0, 0.0, 1.0], (len(points), 1)), base, [as_dict(lights[0])], camera.eye)
    assert np.abs(fb.color[fb.ids >= 0].astype(int) - np.floor(want + 0.5)).max() <= 1


def test_phong_without_lights_is_lit_by_a_headlight_and_a_little_ambient_light():
    from rasterkit.raster.lights import PHONG_LIGHTS

    mesh = rk.shapes.icosphere(2)
    camera = rk.Camera.look_at((0.4, 0.6, 3.5), (0, 0, 0), width=96, height=72)
    np.testing.assert_array_equal(rk.render(mesh, camera, "solid", shading="phong").color,
                                  rk.render(mesh, camera, "solid", shading="phong", lights=PHONG_LIGHTS).color)


def test_phong_frames_are_the_same_at_any_thread_count_and_average_their_samples():
    mesh = rk.shapes.icosphere(3)
    camera = rk.Camera.look_at((0.5, 0.8, 3.2), (0, 0, 0), width=160, height=120, fov_y=45)
    frames = {}
    try:
        for threads in (1, 2):
            rk.set_threads(threads)
            frames[threads] = [rk.render(mesh, camera, "solid", shading="phong", lights=LIGHTS, samples=samples).color
                               for samples in (1, 4)]
    finally:
        rk.set_threads(None)
    for one, two in zip(frames[1], frames[2]):
        np.testing.assert_array_equal(one, two)
    single, averaged = frames[1]
    inside = rk.render(mesh, camera, "solid", ids=True).ids >= 0
    inside[1:-1, 1:-1] &= inside[:-2, 1:-1] & inside[2:, 1:-1] & inside[1:-1, :-2] & inside[1:-1, 2:]
    # inside the ball the samples see the same smooth surface: their average is near the centre's
    assert np.abs(single[inside].astype(int) - averaged[inside]).mean() < 2.0
    assert not np.array_equal(single, averaged)


def test_the_edge_pixels_of_a_lit_multi_sample_render_are_the_lit_colour_times_their_coverage():
    # on black, a pixel a face covers in part is its lit colour times its share of the pixel, the
    # same share in every channel; a pixel no sample saw (an edge's sliver or corner) too, not
    # the face's unlit colour (a grey fringe under a coloured light)
    vertices = np.array([[-1.0, -0.9, 0.0], [1.1, -0.7, 0.0], [-0.2, 1.0, 0.0]])
    mesh = rk.Mesh(vertices, np.array([[0, 1, 2]]))
    camera = rk.Camera.look_at((0, 0, 3), (0, 0, 0), width=40, height=40, fov_y=50)
    lights = [rk.Light.directional((0.3, 0.2, -1), color=(255, 120, 40))]
    options = rk.RenderOptions(specular=0.0)  # no highlight: one lit colour across the face
    lit = rk.render(mesh, camera, "solid", shading="phong", lights=lights, background="black",
                    options=options).color[20, 20].astype(float)
    assert lit[0] > 2 * lit[1] > 4 * lit[2] > 0
    averaged = rk.render(mesh, camera, "solid", shading="phong", lights=lights, samples=4, background="black",
                         options=options).color.astype(float)
    partial = (averaged[..., 0] > 0) & (averaged[..., 0] < lit[0] - 1)
    assert partial.sum() > 50
    share = averaged[..., 0] / lit[0]
    assert np.abs(averaged - share[..., None] * lit)[partial].max() <= 1.0


@pytest.mark.parametrize("shading", ["flat", "phong"])
def test_the_untextured_resolve_agrees_with_the_textured_one_on_a_white_texture(shading):
    # an untextured frame lit per pixel has a resolve of its own (rasterkit.raster.kernels.phong_rows,
    # rows lit in chunks of 64 pixels across faces); a face textured white is lit by the textured
    # resolve (lit_shade): the same surface, point, normal and colour, so the same pixels
    from rasterkit.raster.kernels.lit_columns import CHUNK

    ball = rk.shapes.icosphere(3)
    m = len(ball.faces)
    diffuse = (0.8, 0.4, 0.2)  # 8-bit codes exactly: the face colour and the texture's tint agree
    white = rk.Material(name="w", diffuse=diffuse, diffuse_map=rk.Texture(np.full((1, 1, 3), 255, np.uint8)))
    textured = rk.Mesh(ball.vertices, ball.faces, uv=np.zeros((len(ball.vertices), 2)), uv_index=ball.faces,
                       materials=(white,), material_names=("w",), face_materials=np.zeros(m, np.int32))
    plain = rk.Mesh(ball.vertices, ball.faces, face_colors=np.tile(diffuse, (m, 1)),
                    materials=(rk.Material(name="w", diffuse=diffuse),), material_names=("w",),
                    face_materials=np.zeros(m, np.int32))
    camera = rk.Camera.look_at((0.5, 0.8, 3.2), (0, 0, 0), width=320, height=200, fov_y=40)
    # a light that casts shadows: flat frames are lit per pixel too
    lights = LIGHTS[:2] + [rk.Light.directional((1, -1, -1), shadows=True)] + LIGHTS[2:]
    got = rk.render(plain, camera, "solid", shading=shading, lights=lights, ids=True)
    want = rk.render(textured, camera, "solid", shading=shading, lights=lights)
    rows = got.ids >= 0
    assert rows.sum(axis=1).max() > 2 * CHUNK  # rows of the ball longer than the chunk
    diff = np.abs(got.color.astype(int) - want.color)
    assert diff.max() <= 1 and (diff > 0).mean() < 0.001, (diff.max(), (diff > 0).mean())
