"""The default scene's node hierarchy: matrix and TRS transforms composed down the tree
(compared with NumPy), the choice of the default scene, graphs that are not trees, cameras
(the record and the rasterkit.Camera of it) and KHR_lights_punctual lights."""

from __future__ import annotations

import math

import numpy as np
import pytest

import rasterkit
from rasterkit.gltf import GltfCamera, GltfError, GltfScene, camera_of, read_gltf
from support.gltffiles import GltfBuilder

TRIANGLE = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float64)


def rotation_z(angle):
    c, s = math.cos(angle), math.sin(angle)
    m = np.eye(4)
    m[:2, :2] = [[c, -s], [s, c]]
    return m


def trs(t, q, s):
    """T @ R @ S from a quaternion (x, y, z, w), by the axis-angle formula (independent of the reader's)."""
    x, y, z, w = np.asarray(q) / np.linalg.norm(q)
    angle = 2 * math.atan2(math.sqrt(x * x + y * y + z * z), w)
    axis = np.array([x, y, z]) / (math.sin(angle / 2) or 1.0)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    r = np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k
    m = np.eye(4)
    m[:3, :3] = r @ np.diag(s)
    m[:3, 3] = t
    return m


def builder_with_mesh():
    b = GltfBuilder()
    mesh = b.mesh({"attributes": {"POSITION": b.accessor(TRIANGLE)}})
    return b, mesh


def world_points(scene: GltfScene) -> list:
    return [rasterkit.transform.apply_points(o.matrix, o.mesh.vertices) for o in scene.objects]


def test_matrix_and_trs_compose_down_the_tree(tmp_path):
    """root (column-major matrix) -> child (TRS) -> grandchild (TRS) with the mesh, and a
    second mesh node beside: world positions as NumPy computes them."""
    b, mesh = builder_with_mesh()
    root_m = rotation_z(0.3) @ np.diag([2.0, 2.0, 2.0, 1.0])
    root_m[:3, 3] = [1, 2, 3]
    child = dict(translation=[0, 5, 0], rotation=[0, 0.6, 0, 0.8], scale=[1, 2, 3])
    grandchild = dict(translation=[-1, 0, 0.5], rotation=[0.1, 0.2, 0.3, 0.9])
    g = b.node(mesh=mesh, **grandchild)
    c = b.node(children=[g], **child)
    other = b.node(mesh=mesh, matrix=np.eye(4).ravel().tolist())
    root = b.node(children=[c, other], matrix=root_m.T.ravel().tolist())  # glTF: column-major
    b.scene(root)
    scene = read_gltf(b.write_glb(tmp_path / "t.glb"))
    expected = root_m @ trs(child["translation"], child["rotation"], child["scale"]) @ \
        trs(grandchild["translation"], grandchild["rotation"], [1, 1, 1])
    first, second = world_points(scene)
    np.testing.assert_allclose(first, rasterkit.transform.apply_points(expected, TRIANGLE), atol=1e-12)
    np.testing.assert_allclose(second, rasterkit.transform.apply_points(root_m, TRIANGLE), atol=1e-12)
    assert scene.objects[0].mesh is scene.objects[1].mesh  # a mesh is read once, shared by its nodes


def test_the_default_scene_is_chosen(tmp_path):
    """``scene`` when given, else scenes[0], else every root node."""
    b, mesh = builder_with_mesh()
    a = b.node(mesh=mesh, translation=[1, 0, 0])
    c = b.node(mesh=mesh, translation=[2, 0, 0])
    parent = b.node(children=[c], translation=[0, 10, 0])
    b.json["scenes"] = [{"nodes": [a]}, {"nodes": [parent]}]
    b.json["scene"] = 1
    offsets = lambda: [o.matrix[:3, 3].tolist() for o in read_gltf(b.write_glb(tmp_path / "s.glb")).objects]  # noqa: E731
    assert offsets() == [[2, 10, 0]]
    del b.json["scene"]
    assert offsets() == [[1, 0, 0]]
    del b.json["scenes"]
    assert offsets() == [[1, 0, 0], [2, 10, 0]]  # roots a and parent, in index order


@pytest.mark.parametrize("nodes,roots,where", [
    ([{"children": [0]}], [0], "nodes[0].children"),  # itself
    ([{"children": [1]}, {"children": [0]}], [0], "nodes[1].children"),  # a cycle
    ([{"children": [2]}, {"children": [2]}, {}], [0, 1], "nodes[1].children"),  # two parents
    ([{"children": [1]}, {}], [0, 1], "scenes[0].nodes"),  # a root that is also a child
])
def test_graphs_that_are_not_trees_are_refused(tmp_path, nodes, roots, where):
    b, mesh = builder_with_mesh()
    b.json["nodes"] = nodes + [{"mesh": mesh}]
    b.scene(*roots)
    with pytest.raises(GltfError) as info:
        read_gltf(b.write_glb(tmp_path / "c.glb"))
    assert info.value.where == where and "is reached a second time" in info.value.reason


def test_a_deep_chain_of_nodes_is_walked_without_recursion(tmp_path):
    b, mesh = builder_with_mesh()
    n = 5000
    b.json["nodes"] = [{"children": [k + 1], "translation": [1, 0, 0]} for k in range(n)] + [{"mesh": mesh}]
    b.scene(0)
    scene = read_gltf(b.write_glb(tmp_path / "deep.glb"))
    assert scene.objects[0].matrix[0, 3] == n


@pytest.mark.parametrize("node,where,reason", [
    ({"rotation": [0, 0, 0, 0]}, "nodes[0].rotation", "is not a rotation"),
    ({"scale": [1, 1]}, "nodes[0].scale", "must be a list of 3 finite numbers"),
    ({"matrix": [1] * 16}, "nodes[0].matrix", "must be affine"),
    ({"translation": [1e308, 0, 0], "scale": [1e308, 1, 1], "children": [1]}, "nodes[1]", "beyond float64"),
    ({"mesh": 5}, "nodes[0].mesh", "must be an index of meshes (meshes has 1 entries), got 5"),
])
def test_bad_transforms_are_refused(tmp_path, node, where, reason):
    b, mesh = builder_with_mesh()
    b.node(**node)
    b.node(mesh=mesh, translation=[1e308, 0, 0])
    b.scene(0)
    with pytest.raises(GltfError) as info:
        read_gltf(b.write_glb(tmp_path / "bad.glb"))
    assert info.value.where == where and reason in info.value.reason, str(info.value)


def test_a_scene_without_anything_to_draw_is_refused(tmp_path):
    b, _ = builder_with_mesh()
    b.scene(b.node(name="empty"))
    with pytest.raises(GltfError, match=r"the default scene draws nothing \(no node with a mesh of triangles, lines "
                                        r"or points\)$"):
        read_gltf(b.write_glb(tmp_path / "empty.glb"))
    b.scene(b.node(mesh=b.mesh({"attributes": {"NORMAL": 0}})))  # what was skipped is named
    with pytest.raises(GltfError, match=r"points; 1 warnings, the first: meshes\[1\]\.primitives\[0\]: has no "
                                        r"POSITION: not drawn\)$"):
        read_gltf(b.write_glb(tmp_path / "empty.glb"))


def camera_file(tmp_path, camera: dict, **node):
    b, mesh = builder_with_mesh()
    b.json["cameras"] = [camera]
    cam = b.node(camera=0, **node)
    b.scene(b.node(mesh=mesh), b.node(children=[cam], translation=[0, 0, 1]))
    return b.write_glb(tmp_path / "cam.glb")


def test_the_first_camera_is_recorded_and_made_a_rasterkit_camera(tmp_path):
    """A camera 5 units up +z (through its parent) looking down -z: the triangle's corner
    (0, 0, 0) projects to the image centre; yfov is radians."""
    path = camera_file(tmp_path, {"type": "perspective", "perspective": {"yfov": math.radians(60), "znear": 0.5,
                                                                        "zfar": 50, "aspectRatio": 1.5}},
                       translation=[0, 0, 4])
    scene = read_gltf(path)
    found = scene.gltf_camera
    assert isinstance(found, GltfCamera) and scene.camera is None
    assert (found.kind, found.aspect_ratio, found.znear, found.zfar, found.node) == ("perspective", 1.5, 0.5, 50, 0)
    np.testing.assert_array_equal(found.pose[:3, 3], [0, 0, 5])
    camera = camera_of(scene, 64, 48)
    assert camera.kind == "perspective" and camera.fov_y == pytest.approx(60) and (camera.near, camera.far) == (0.5, 50)
    np.testing.assert_allclose(camera.project([[0, 0, 0]])[0, :2], [32, 24], atol=1e-9)
    # a point up the camera's +y is above the centre (raster y down)
    assert camera.project([[0, 1, 0]])[0, 1] < 24
    np.testing.assert_allclose(camera_of(path, 64, 48).matrix(), camera.matrix())


def test_a_rotated_camera_looks_along_its_minus_z(tmp_path):
    """Rotated 90 degrees about +y, the camera looks down world -x."""
    s = math.sqrt(0.5)
    path = camera_file(tmp_path, {"type": "perspective", "perspective": {"yfov": 1.0, "znear": 0.1}},
                       translation=[5, 0, -1], rotation=[0, s, 0, s])
    camera = camera_of(path, 32, 32)
    np.testing.assert_allclose(camera.eye, [5, 0, 0], atol=1e-12)
    np.testing.assert_allclose(camera.backward(), [1, 0, 0], atol=1e-12)
    assert camera.far > 5.0  # no zfar: just past the scene's bounding sphere


def test_orthographic_cameras(tmp_path):
    path = camera_file(tmp_path, {"type": "orthographic", "orthographic": {"xmag": 3, "ymag": 2, "znear": 0,
                                                                          "zfar": 20}}, translation=[0, 0, 4])
    camera = camera_of(path, 40, 20)
    assert camera.kind == "parallel" and camera.view_height == 4.0 and camera.far == 20 and 0 < camera.near < 1e-3
    np.testing.assert_allclose(camera.project([[0, 1, 0]])[0, :2], [20, 5], atol=1e-9)  # 1 of 2 half-heights up


@pytest.mark.parametrize("camera,where", [
    ({"type": "fisheye"}, "cameras[0].type"),
    ({"type": "perspective", "perspective": {"yfov": 0, "znear": 1}}, "cameras[0].perspective"),
    ({"type": "perspective", "perspective": {"yfov": 1, "znear": 1, "zfar": 0.5}}, "cameras[0].perspective"),
    ({"type": "perspective", "perspective": {"yfov": "1", "znear": 1}}, "cameras[0].perspective.yfov"),
    ({"type": "orthographic", "orthographic": {"xmag": 1, "ymag": 1, "znear": 0}}, "cameras[0].orthographic.zfar"),
])
def test_bad_cameras_are_refused(tmp_path, camera, where):
    with pytest.raises(GltfError) as info:
        read_gltf(camera_file(tmp_path, camera))
    assert info.value.where == where


def test_no_camera_is_an_error_of_camera_of(tmp_path):
    b, mesh = builder_with_mesh()
    b.scene(b.node(mesh=mesh))
    with pytest.raises(GltfError, match="has no camera node"):
        camera_of(b.write_glb(tmp_path / "n.glb"), 32, 32)


def test_lights_are_kept_in_world_space(tmp_path):
    b, mesh = builder_with_mesh()
    b.json["extensionsUsed"] = ["KHR_lights_punctual"]
    b.json["extensions"] = {"KHR_lights_punctual": {"lights": [
        {"type": "spot", "color": [1, 0.5, 0], "intensity": 3, "spot": {"outerConeAngle": 0.5}, "name": "lamp"},
        {"type": "directional"}]}}
    s = math.sqrt(0.5)
    spot = b.node(translation=[1, 2, 3], extensions={"KHR_lights_punctual": {"light": 0}})
    sun = b.node(rotation=[-s, 0, 0, s], extensions={"KHR_lights_punctual": {"light": 1}})
    b.scene(b.node(mesh=mesh), spot, sun)
    scene = read_gltf(b.write_glb(tmp_path / "l.glb"))
    assert not scene.warnings
    first, second = scene.gltf_lights  # the file's records (tests/gltf/test_lights_punctual.py: the Lights)
    assert (first.kind, first.color, first.intensity, first.name, first.node) == ("spot", (1.0, 0.5, 0.0), 3.0,
                                                                                    "lamp", 0)
    assert (first.inner_cone_angle, first.outer_cone_angle, first.range) == (0.0, 0.5, None)
    np.testing.assert_array_equal(first.position, [1, 2, 3])
    np.testing.assert_allclose(first.direction, [0, 0, -1])
    np.testing.assert_allclose(second.direction, [0, -1, 0], atol=1e-12)  # tilted down: shines along -y
    assert [light.kind for light in scene.lights] == ["spot", "directional"]
    np.testing.assert_allclose(scene.lights[1].direction, [0, -1, 0], atol=1e-12)


def test_a_scene_pickles_whole(tmp_path):
    """Batches send scenes to worker processes: the copy keeps its camera, lights and shared meshes."""
    import pickle

    path = camera_file(tmp_path, {"type": "perspective", "perspective": {"yfov": 1.0, "znear": 0.1}})
    scene = read_gltf(path)
    copy = pickle.loads(pickle.dumps(scene))
    assert type(copy) is GltfScene and copy.path == scene.path and copy.gltf_camera.yfov == 1.0
    np.testing.assert_array_equal(copy.objects[0].mesh.vertices, TRIANGLE)
    np.testing.assert_allclose(camera_of(copy, 32, 32).matrix(), camera_of(scene, 32, 32).matrix())
