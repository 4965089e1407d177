"""Scene: model matrices place meshes in the world; render(scene) is render(world mesh)."""

import numpy as np
import pytest

import rasterkit
from rasterkit import Camera, shapes, transform
from rasterkit.scene import Scene


def _camera():
    return Camera.look_at(eye=(0, 1, 8), target=(0, 0, 0), width=80, height=60)


def test_world_mesh_applies_each_model_matrix_and_offsets_indices():
    cube, tet = shapes.cube(), shapes.tetrahedron()
    m1 = transform.compose(transform.scale(2.0), transform.translate(-2, 0, 0))
    m2 = transform.rotate_axis(0.3, (1, 1, 0), origin=(1, 0, 0))
    world = Scene().add(cube, m1).add(tet, m2).world_mesh()
    n = len(cube.vertices)
    assert np.allclose(world.vertices[:n], 2 * cube.vertices + [-2, 0, 0])
    assert np.allclose(world.vertices[n:], transform.apply_points(m2, tet.vertices))
    assert np.array_equal(world.faces[len(cube.faces):], tet.faces + n)
    assert np.array_equal(world.edges[len(cube.edges):], tet.edges + n)


def test_render_scene_equals_render_of_the_world_mesh():
    scene = Scene(camera=_camera(), background="navy")
    scene.add(shapes.cube(), transform.translate(-1.2, 0, 0))
    scene.add(shapes.icosphere(1), transform.translate(1.2, 0, 0))
    for mode in ("wire", "solid+wire"):
        a = rasterkit.render(scene, mode=mode)
        b = rasterkit.render(scene.world_mesh(), _camera(), mode=mode, background="navy")
        assert np.array_equal(a.color, b.color)
        assert np.all(a.color[0, 0] == [0, 0, 128])


def test_object_colours_become_face_colours_and_others_get_the_default():
    scene = Scene().add(shapes.cube(), color="red").add(shapes.cube(), transform.translate(3, 0, 0))
    world = scene.world_mesh(default_color="#0000ff")
    assert np.allclose(world.face_colors[:12], [1, 0, 0]) and np.allclose(world.face_colors[12:], [0, 0, 1])
    assert Scene().add(shapes.cube()).world_mesh().face_colors is None


def test_a_face_seen_head_on_shows_its_object_colour():
    quad = (np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], float), [[0, 1, 2], [0, 2, 3]])
    scene = Scene(camera=Camera.orthographic(eye=(0, 0, 5), target=(0, 0, 0), view_height=4,
                                             width=20, height=20)).add(quad, color=(10, 200, 30))
    assert rasterkit.render(scene, mode="solid").color[10, 10].tolist() == [10, 200, 30]


def test_a_light_from_the_side_darkens_a_face_seen_head_on():
    quad = (np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], float), [[0, 1, 2], [0, 2, 3]])
    cam = Camera.orthographic(eye=(0, 0, 5), target=(0, 0, 0), view_height=4, width=20, height=20)
    lit = rasterkit.render(quad, cam, mode="solid", color="white", light=(0, 0, 1)).color[10, 10]
    grazing = rasterkit.render(quad, cam, mode="solid", color="white", light=(1, 0, 0)).color[10, 10]
    assert lit.tolist() == [255, 255, 255] and grazing.max() < 100


def test_normals_transform_with_the_inverse_transpose():
    mesh = shapes.icosphere(1)
    mesh = rasterkit.Mesh(mesh.vertices, mesh.faces, normals=mesh.vertices)  # sphere normals
    m = transform.scale(3.0, 1.0, 1.0)
    world = Scene().add(mesh, m).world_mesh()
    # the scaled sphere is the ellipsoid (x/3)^2 + y^2 + z^2 = 1; its gradient is the normal
    p = world.vertices
    gradient = p * [1 / 9, 1, 1]
    gradient /= np.linalg.norm(gradient, axis=1, keepdims=True)
    assert np.allclose(world.normals, gradient)


@pytest.mark.parametrize("matrix", [np.eye(3), np.full((4, 4), np.nan), np.ones((4, 4))])
def test_bad_model_matrices_are_rejected(matrix):
    with pytest.raises(ValueError):
        Scene().add(shapes.cube(), matrix)


def test_an_empty_scene_or_a_scene_without_camera_is_an_error():
    with pytest.raises(ValueError):
        Scene(camera=_camera()).world_mesh()
    with pytest.raises(TypeError):
        rasterkit.render(Scene().add(shapes.cube()))


# --- per-corner tables and materials ----------------------------------------------------------

SQUARE = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
TRIANGLE = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)


def _tables_scene():
    """Three objects: a square with uv, corner normals and two materials, scaled along x and
    turned a quarter about x; a moved triangle with corner normals and a material name but no
    Material; a triangle with per-vertex uv only."""
    texture = rasterkit.Texture(np.zeros((2, 2, 3), np.uint8))
    a0, a1 = rasterkit.Material("a0"), rasterkit.Material("a1", diffuse_map=texture)
    square = rasterkit.Mesh(SQUARE, [[0, 1, 2], [0, 2, 3]], uv=[[0, 0], [1, 0], [1, 1], [0, 1]],
                            uv_index=[[0, 1, 2], [0, 2, 3]], corner_normals=[[0, 0, 2], [1, 1, 0]],
                            normal_index=[[0, 0, 1], [-1, -1, -1]], face_materials=[1, -1],
                            material_names=("a0", "a1"), materials=(a0, a1))
    moved = rasterkit.Mesh(TRIANGLE, [[0, 1, 2]], corner_normals=[[3, 0, 0]], normal_index=[[0, 0, 0]],
                           face_materials=[0], material_names=("b0",))
    plain = rasterkit.Mesh(TRIANGLE, [[0, 2, 1]], uv=[[0.5, 0.5], [0.25, 0.5], [0.5, 0.25]])
    turned = transform.compose(transform.scale(2, 1, 1), transform.rotate_x(np.pi / 2))
    scene = Scene().add(square, turned).add(moved, transform.translate(5, 6, 7)).add(plain)
    return scene, (a0, a1)


def test_world_mesh_joins_the_corner_tables():
    world = _tables_scene()[0].world_mesh()
    # uv: the square's 4 rows, then the per-vertex rows of the last triangle (its uv_index is its faces)
    assert world.uv.tolist() == [[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5], [0.25, 0.5], [0.5, 0.25]]
    assert world.uv_index.tolist() == [[0, 1, 2], [0, 2, 3], [-1, -1, -1], [4, 6, 5]]
    # normals: scale (2, 1, 1) takes n to (nx / 2, ny, nz), the quarter turn about x (x, y, z) to (x, -z, y)
    expected = [[0, -1, 0], np.array([1, 0, 2]) / np.sqrt(5), [1, 0, 0]]  # (0, 0, 2); (1, 1, 0) -> (1, 2, 0); (3, 0, 0)
    np.testing.assert_allclose(world.corner_normals, expected, atol=1e-15)
    assert world.normal_index.tolist() == [[0, 0, 1], [-1, -1, -1], [2, 2, 2], [-1, -1, -1]]


def test_world_mesh_joins_the_materials():
    scene, (a0, a1) = _tables_scene()
    world = scene.world_mesh()
    assert world.material_names == ("a0", "a1", "b0")
    assert world.face_materials.tolist() == [1, -1, 2, -1] and world.face_materials.dtype == np.int32
    assert world.materials[:2] == (a0, a1) and world.materials[1].diffuse_map is a1.diffuse_map
    assert world.materials[2] == rasterkit.Material("b0")  # named without a Material: the default
    # the same mesh twice: the second's indices offset past the first's names
    square = scene.objects[0].mesh
    twice = Scene().add(square).add(square).world_mesh()
    assert twice.material_names == ("a0", "a1") * 2 and twice.face_materials.tolist() == [1, -1, 3, -1]
    assert twice.materials == (a0, a1, a0, a1)


def test_world_mesh_without_tables_or_materials():
    world = Scene().add(shapes.cube()).add(shapes.cube(), transform.translate(3, 0, 0)).world_mesh()
    assert world.uv is None and world.corner_normals is None and world.normal_index is None
    assert world.face_materials is None and world.material_names == () and world.materials == ()
    named = rasterkit.Mesh(TRIANGLE, [[0, 1, 2]], face_materials=[0], material_names=("red",))
    world = Scene().add(named).add(shapes.cube()).add(named).world_mesh()
    assert world.material_names == ("red", "red") and world.materials == ()
    assert world.face_materials.tolist() == [0] + [-1] * 12 + [1]


def test_corner_normals_under_a_singular_matrix_or_huge_rows():
    flat = rasterkit.Mesh(TRIANGLE, [[0, 1, 2]], corner_normals=[[0, 0, 1]], normal_index=[[0, 0, 0]])
    huge = rasterkit.Mesh(TRIANGLE, [[0, 1, 2]], corner_normals=[[1e308, 1e308, 0], [0, 0, 0]],
                          normal_index=[[0, 1, 0]])
    world = Scene().add(flat, transform.scale(1, 1, 0)).add(huge, transform.scale(0.5)).world_mesh()
    assert world.normal_index.tolist() == [[-1, -1, -1], [0, 1, 0]]  # the flattened one has none
    np.testing.assert_allclose(world.corner_normals, [[np.sqrt(0.5), np.sqrt(0.5), 0], [0, 0, 0]])
