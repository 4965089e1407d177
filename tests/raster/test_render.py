"""render(): every mode against slow independent references, through the public API."""

import numpy as np
import pytest

import rasterkit
from rasterkit import Camera, shapes
from rasterkit.mesh import as_mesh
from rasterkit.raster.render import AMBIENT
from support.reference_lines import line_in_image
from support.reference_raster import reference_raster

BLACK = np.array([0, 0, 0], np.uint8)


def _camera(mesh, width=96, height=72, **kw):
    centre, radius = mesh.bounding_sphere()
    return Camera.frame(centre, radius, width=width, height=height, **kw)


def _drawn(fb, rgb=(0, 0, 0)):
    return np.all(fb.color[..., :3] == rgb, axis=2)


def _reference_wire(mesh, camera):
    """Each edge's integer line between the pixels holding its projected ends (all in front)."""
    raster = camera.project(mesh.vertices)
    assert np.all(camera.project_h(mesh.vertices)[:, 3] > 0)
    pix = np.floor(raster[:, :2]).astype(int)
    image = np.zeros((camera.height, camera.width), bool)
    for a, b in mesh.edges:
        for x, y in line_in_image(*pix[a], *pix[b], camera.width, camera.height):
            image[y, x] = True
    return image


@pytest.mark.parametrize("make", [shapes.cube, shapes.icosahedron, lambda: shapes.torus(1, 0.4, 10, 6)])
def test_wire_equals_the_reference_lines_of_every_edge(make):
    mesh = make()
    camera = _camera(mesh, azimuth=37, elevation=23)
    fb = rasterkit.render(mesh, camera, mode="wire")
    assert np.array_equal(_drawn(fb), _reference_wire(mesh, camera))
    assert np.all(fb.color[~_drawn(fb)] == 255)  # background untouched elsewhere


def test_wire_clips_edges_that_cross_the_near_plane():
    """Standing inside a grid: edges pass behind the eye; only their visible parts appear."""
    mesh = shapes.grid(8, 8, size=8.0)
    camera = Camera.look_at(eye=(0.1, 0.5, 0.2), target=(0.1, 0.0, -3.0), width=80, height=60,
                            near=0.05, far=50.0)
    fb = rasterkit.render(mesh, camera, mode="wire")
    drawn = _drawn(fb)
    # the grid lies below the horizon: nothing above the image's middle row, lines below it
    horizon = camera.project([[0.1, 0.5, -1e6]])[0, 1]
    assert not drawn[: int(horizon) - 1].any()
    assert drawn[int(horizon) + 2:].any()


def _reference_solid(mesh, camera, cull):
    raster = camera.project(mesh.vertices)
    return reference_raster(raster[mesh.faces], camera.width, camera.height, cull=cull)


@pytest.mark.parametrize("cull", ["back", "none"])
def test_solid_coverage_and_ids_equal_the_reference_rasterizer(cull):
    mesh = shapes.icosphere(1)
    camera = _camera(mesh, azimuth=12, elevation=-31)
    fb = rasterkit.render(mesh, camera, mode="solid", cull=cull, ids=True, background="black",
                          color="white")
    count, ids, depth, margin = _reference_solid(mesh, camera, cull)
    assert np.array_equal(fb.ids >= 0, count > 0)
    clear = margin > 1e-5
    assert np.array_equal(fb.ids[clear], ids[clear])
    assert np.allclose(fb.depth[count > 0], depth[count > 0], atol=1e-6)
    assert np.all(fb.color[count == 0] == 0) and np.all(fb.color[count > 0].max(axis=1) > 0)


def test_back_culling_of_a_closed_mesh_changes_no_pixel():
    mesh = shapes.torus(1, 0.4, 16, 8)
    camera = _camera(mesh)
    back = rasterkit.render(mesh, camera, mode="solid", cull="back", ids=True)
    none = rasterkit.render(mesh, camera, mode="solid", cull="none", ids=True)
    same = back.ids == none.ids
    assert same.mean() > 0.99  # only depth ties between a face and its backside may differ
    front = rasterkit.render(mesh, camera, mode="solid", cull="front", ids=True)
    assert not np.array_equal(front.ids, back.ids)


def test_flat_shading_is_lambert_with_a_headlight():
    """A square facing the eye gets the full colour; tilted by 60 degrees, ambient + half."""
    quad = (np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], float), [[0, 1, 2], [0, 2, 3]])
    cam = Camera.orthographic(eye=(0, 0, 5), target=(0, 0, 0), view_height=4, width=40, height=40)
    fb = rasterkit.render(quad, cam, mode="solid", color=(200, 100, 40))
    assert fb.color[20, 20].tolist() == [200, 100, 40]
    tilted = (quad[0] @ rasterkit.transform.rotate_x(np.pi / 3)[:3, :3].T, quad[1])
    fb = rasterkit.render(tilted, cam, mode="solid", color=(200, 100, 40))
    k = AMBIENT
    expected = np.round(np.array([200, 100, 40]) * (k + (1 - k) * 0.5))
    assert np.abs(fb.color[20, 20].astype(int) - expected).max() <= 1


def test_hidden_mode_draws_only_the_visible_edges_of_a_cube():
    mesh = shapes.cube()
    camera = _camera(mesh, width=120, height=120, azimuth=30, elevation=25)
    hidden = _drawn(rasterkit.render(mesh, camera, mode="hidden"))
    wire = _drawn(rasterkit.render(mesh, camera, mode="wire"))
    assert np.all(hidden <= wire)
    # the corner farthest from the eye is hidden: the middles of its three edges are not drawn
    eye = np.array(camera.eye)
    far = mesh.vertices[np.argmax(np.linalg.norm(mesh.vertices - eye, axis=1))]
    for a, b in mesh.edges:
        mid = (mesh.vertices[a] + mesh.vertices[b]) / 2
        x, y = np.floor(camera.project([mid])[0, :2]).astype(int)
        box = (slice(y - 1, y + 2), slice(x - 1, x + 2))
        touches_far = np.any(np.all(mesh.vertices[[a, b]] == far, axis=1))
        assert hidden[box].any() != touches_far


def test_solid_plus_wire_puts_visible_edges_over_the_shading():
    mesh = shapes.cube()
    camera = _camera(mesh, width=100, height=100)
    both = rasterkit.render(mesh, camera, mode="solid+wire", line_color="red")
    hidden = rasterkit.render(mesh, camera, mode="hidden", line_color="red")
    assert np.array_equal(_drawn(both, (255, 0, 0)), _drawn(hidden, (255, 0, 0)))
    solid = rasterkit.render(mesh, camera, mode="solid")
    lines = _drawn(both, (255, 0, 0))
    assert np.array_equal(both.color[~lines], solid.color[~lines])


@pytest.mark.parametrize("mode", ["wire", "hidden", "solid", "solid+wire"])
def test_one_and_two_threads_give_identical_images(mode):
    mesh = shapes.icosphere(2)
    camera = _camera(mesh, width=64, height=48)
    try:
        rasterkit.set_threads(1)
        one = rasterkit.render(mesh, camera, mode=mode, aa=True, shading="smooth")
        rasterkit.set_threads(min(2, rasterkit.runtime.threads.MAX_THREADS))
        two = rasterkit.render(mesh, camera, mode=mode, aa=True, shading="smooth")
    finally:
        rasterkit.set_threads(None)
    assert np.array_equal(one.color, two.color) and np.array_equal(one.depth, two.depth)


def test_transparent_background_and_anti_aliasing():
    mesh = shapes.cube()
    fb = rasterkit.render(mesh, _camera(mesh), mode="wire", aa=True, background="transparent")
    assert fb.color.shape[2] == 4
    alpha = fb.color[..., 3]
    assert alpha.max() >= 250 and np.any((alpha > 0) & (alpha < 255))  # blended edge pixels


def test_mesh_inputs_are_accepted_in_three_forms():
    cube = shapes.cube()

    class TrimeshLike:
        vertices = cube.vertices.tolist()
        faces = cube.faces.tolist()

    camera = _camera(cube)
    images = [rasterkit.render(m, camera, mode="solid").color
              for m in (cube, (cube.vertices, cube.faces), TrimeshLike())]
    assert np.array_equal(images[0], images[1]) and np.array_equal(images[0], images[2])
    assert as_mesh(TrimeshLike()).faces.dtype == np.int64


@pytest.mark.parametrize("kwargs, error", [
    ({"mode": "sketch"}, ValueError), ({"cull": "sideways"}, ValueError),
    ({"shading": "gouraud"}, ValueError), ({"color": "#12"}, ValueError),
    ({"line_color": (1, 2, 300)}, ValueError),
])
def test_bad_options_are_rejected_before_any_kernel_runs(kwargs, error):
    with pytest.raises(error):
        rasterkit.render(shapes.cube(), _camera(shapes.cube()), **kwargs)


def test_bad_meshes_and_cameras_are_rejected():
    camera = _camera(shapes.cube())
    with pytest.raises(ValueError):
        rasterkit.render((np.zeros((3, 3)), [[0, 1, 3]]), camera)
    with pytest.raises(TypeError):
        rasterkit.render("cube.obj", camera)
    with pytest.raises(TypeError):
        rasterkit.render(shapes.cube(), "camera")


def test_nan_vertices_do_not_crash_and_are_not_drawn():
    mesh = shapes.cube()
    v = mesh.vertices.copy()
    v[0] = np.nan
    bad = rasterkit.Mesh(v, mesh.faces, edges=mesh.edges)
    for mode in ("wire", "hidden", "solid", "solid+wire"):
        fb = rasterkit.render(bad, _camera(mesh), mode=mode)
        assert fb.color.min() < 255
