"""Primitives: every mode (strips with their alternating winding fixed, fans, lines, points),
indexed or not, indices checked against the vertex count, and the attributes: normals,
texture coordinates (v flipped), colours (linear to sRGB), primitives of one mesh joined."""

from __future__ import annotations

import numpy as np
import pytest

from rasterkit.gltf import GltfError, read_gltf
from rasterkit.material.colorspace import encode_srgb
from support.gltffiles import GltfBuilder

# a strip of 4 triangles in the z = 0 plane, zig-zag: 0 2 4 on the bottom, 1 3 5 on the top
STRIP = np.array([[0, 0, 0], [0, 1, 0], [1, 0, 0], [1, 1, 0], [2, 0, 0], [2, 1, 0]], np.float64)
# a fan around the origin: a regular hexagon's centre and 5 of its corners, counter-clockwise
FAN = np.array([[0, 0, 0]] + [[np.cos(a), np.sin(a), 0] for a in np.linspace(0, np.pi * 4 / 3, 5)])


def read(b: GltfBuilder, tmp_path):
    return read_gltf(b.write_glb(tmp_path / "p.glb"))


def mesh_of(b: GltfBuilder, tmp_path):
    return read(b, tmp_path).objects[0].mesh


def single(positions, mode=None, indices=None, **attributes):
    b = GltfBuilder()
    prim = {"attributes": {"POSITION": b.accessor(positions)}}
    for name, values in attributes.items():
        prim["attributes"][name] = b.accessor(values)
    if mode is not None:
        prim["mode"] = mode
    if indices is not None:
        prim["indices"] = b.accessor(np.asarray(indices, np.uint8), np.uint8)
    b.scene(b.node(mesh=b.mesh(prim)))
    return b


def normals_z(vertices, faces):
    p = vertices[faces]
    return np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])[:, 2]


def test_strip_triangles_all_face_the_front(tmp_path):
    """glTF's strip: (i, i+1, i+2) for even i, (i, i+2, i+1) for odd: every triangle keeps the
    first one's winding (counter-clockwise seen from +z here... or clockwise: all alike)."""
    mesh = mesh_of(single(STRIP, mode=5), tmp_path)
    np.testing.assert_array_equal(mesh.faces, [[0, 1, 2], [1, 3, 2], [2, 3, 4], [3, 5, 4]])
    z = normals_z(mesh.vertices, mesh.faces)
    assert (np.sign(z) == np.sign(z[0])).all() and z[0] != 0


def test_indexed_strip_reads_through_its_indices(tmp_path):
    mesh = mesh_of(single(STRIP, mode=5, indices=[5, 4, 3, 2]), tmp_path)
    np.testing.assert_array_equal(mesh.faces, [[5, 4, 3], [4, 2, 3]])


def test_fan_triangles_share_the_first_vertex_and_face_one_way(tmp_path):
    mesh = mesh_of(single(FAN, mode=6), tmp_path)
    np.testing.assert_array_equal(mesh.faces, [[1, 2, 0], [2, 3, 0], [3, 4, 0], [4, 5, 0]])
    assert (normals_z(mesh.vertices, mesh.faces) > 0).all()


def test_triangles_indexed_and_not(tmp_path):
    quad = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.float64)
    mesh = mesh_of(single(quad, indices=[0, 1, 2, 0, 2, 3]), tmp_path)
    np.testing.assert_array_equal(mesh.faces, [[0, 1, 2], [0, 2, 3]])
    six = quad[[0, 1, 2, 0, 2, 3]]
    mesh = mesh_of(single(six, mode=4), tmp_path)
    np.testing.assert_array_equal(mesh.faces, [[0, 1, 2], [3, 4, 5]])


def test_a_partial_triangle_is_left_out_with_a_warning(tmp_path):
    scene = read(single(STRIP[:5]), tmp_path)
    assert scene.objects[0].mesh.faces.tolist() == [[0, 1, 2]]
    assert any("5 indices are not whole triangles: the last 2 left out" in w for w in scene.warnings)
    assert scene.objects[0].mesh.warnings == scene.warnings


@pytest.mark.parametrize("mode,lines", [
    (1, [[0, 1], [2, 3]]),
    (2, [[0, 1], [1, 2], [2, 3], [3, 0]]),
    (3, [[0, 1], [1, 2], [2, 3]]),
])
def test_line_modes_become_the_meshs_lines(tmp_path, mode, lines):
    mesh = mesh_of(single(STRIP[:4], mode=mode), tmp_path)
    assert len(mesh.faces) == 0
    np.testing.assert_array_equal(mesh.lines, lines)
    assert {tuple(sorted(e)) for e in mesh.edges.tolist()} == {tuple(sorted(e)) for e in lines}


def test_points_are_world_space_points_of_the_scene(tmp_path):
    b = GltfBuilder()
    pos = b.accessor(STRIP[:3])
    colors = b.accessor(np.array([[255, 0, 0], [0, 255, 0], [0, 0, 255]], np.uint8), np.uint8, normalized=True)
    b.scene(b.node(mesh=b.mesh({"attributes": {"POSITION": pos, "COLOR_0": colors}, "mode": 0}),
                   translation=[10, 0, 0]))
    scene = read(b, tmp_path)
    np.testing.assert_array_equal(scene.points, STRIP[:3] + [10, 0, 0])
    np.testing.assert_array_equal(scene.point_colors, [[255, 0, 0], [0, 255, 0], [0, 0, 255]])
    assert len(scene.objects) == 1 and len(scene.objects[0].mesh.faces) == 0


def test_an_index_past_the_vertices_is_an_error(tmp_path):
    with pytest.raises(GltfError) as info:
        read(single(STRIP[:3], indices=[0, 1, 3]), tmp_path)
    assert (info.value.where, info.value.reason) == ("meshes[0].primitives[0].indices",
                                                     "index 3 >= the vertex count 3")


def test_a_mode_out_of_range_is_an_error(tmp_path):
    with pytest.raises(GltfError, match=r"meshes\[0\]\.primitives\[0\]\.mode: must be an integer from 0 to 6, got 7"):
        read(single(STRIP[:3], mode=7), tmp_path)


def test_a_primitive_without_position_is_skipped(tmp_path):
    b = GltfBuilder()
    pos = b.accessor(STRIP[:3])
    b.scene(b.node(mesh=b.mesh({"attributes": {"NORMAL": pos}}, {"attributes": {"POSITION": pos}})))
    scene = read(b, tmp_path)
    assert len(scene.objects[0].mesh.faces) == 1
    assert any("meshes[0].primitives[0]: has no POSITION: not drawn" in w for w in scene.warnings)


def test_normals_and_flipped_texture_coordinates(tmp_path):
    """NORMAL is per vertex (both Mesh fields); TEXCOORD_0's v runs down the image in glTF
    and up in rasterkit: v' = 1 - v."""
    b = GltfBuilder()
    normals = np.array([[0, 0, 1], [0, 1, 0], [1, 0, 0]], np.float64)
    uv = np.array([[0.0, 0.0], [1.0, 0.25], [0.5, 1.0]])
    material = b.textured_material(b.image(np.zeros((1, 1, 3), np.uint8)))
    b.scene(b.node(mesh=b.mesh({"attributes": {"POSITION": b.accessor(STRIP[:3]), "NORMAL": b.accessor(normals),
                                               "TEXCOORD_0": b.accessor(uv)}, "material": material})))
    mesh = mesh_of(b, tmp_path)
    np.testing.assert_array_equal(mesh.normals, normals)
    np.testing.assert_array_equal(mesh.corner_normals, normals)
    assert mesh.normal_index is mesh.faces or np.array_equal(mesh.normal_index, mesh.faces)
    np.testing.assert_array_equal(mesh.uv, [[0.0, 1.0], [1.0, 0.75], [0.5, 0.0]])


def test_vertex_colors_are_encoded_to_srgb(tmp_path):
    """COLOR_0 is linear light (float or normalized, VEC3 or VEC4: alpha dropped); rasterkit's
    colours are sRGB values."""
    linear = np.array([[0.5, 0.0, 1.0, 0.3], [0.2, 0.2, 0.2, 1.0], [1.0, 1.0, 1.0, 1.0]])
    mesh = mesh_of(single(STRIP[:3], COLOR_0=linear), tmp_path)
    np.testing.assert_allclose(mesh.vertex_colors, encode_srgb(linear[:, :3]), atol=1e-6)
    assert abs(mesh.vertex_colors[0, 0] - 0.7354) < 1e-3  # linear 0.5 is sRGB 0.735


def test_primitives_of_one_mesh_are_joined_and_share_vertices(tmp_path):
    """Two primitives indexing one POSITION accessor keep one copy of it; each face has its
    primitive's material, and faces without a texture colour come from the factor."""
    b = GltfBuilder()
    quad = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.float64)
    pos = b.accessor(quad)
    red = b.add("materials", {"name": "red", "pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 1]}})
    grey = b.add("materials", {"pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.2, 0.2, 1]}})
    b.scene(b.node(mesh=b.mesh(
        {"attributes": {"POSITION": pos}, "indices": b.accessor(np.array([0, 1, 2], np.uint16), np.uint16), "material": red},
        {"attributes": {"POSITION": pos}, "indices": b.accessor(np.array([0, 2, 3], np.uint16), np.uint16), "material": grey},
        {"attributes": {"POSITION": b.accessor(quad[:3] + 5)}})))
    mesh = mesh_of(b, tmp_path)
    assert len(mesh.vertices) == 7
    np.testing.assert_array_equal(mesh.faces, [[0, 1, 2], [0, 2, 3], [4, 5, 6]])
    assert mesh.material_names == ("red", "material1")
    np.testing.assert_array_equal(mesh.face_materials, [0, 1, -1])
    g = encode_srgb(np.array(0.2))
    np.testing.assert_allclose(mesh.face_colors, [[1, 0, 0], [g, g, g], [0.8, 0.8, 0.8]], atol=1e-6)
    assert [m.diffuse for m in mesh.materials] == [(1.0, 0.0, 0.0), (float(g),) * 3]


def test_texture_coordinates_of_some_primitives_only(tmp_path):
    """A textured primitive beside one without TEXCOORD_0: the faces of the second get -1 rows."""
    b = GltfBuilder()
    material = b.textured_material(b.image(np.zeros((1, 1, 3), np.uint8)))
    uv = b.accessor(np.array([[0, 0], [1, 0], [0, 1]], np.float32))
    b.scene(b.node(mesh=b.mesh({"attributes": {"POSITION": b.accessor(STRIP[:3]), "TEXCOORD_0": uv},
                                "material": material},
                               {"attributes": {"POSITION": b.accessor(STRIP[3:])}})))
    mesh = mesh_of(b, tmp_path)
    np.testing.assert_array_equal(mesh.uv_index, [[0, 1, 2], [-1, -1, -1]])
    assert mesh.uv.shape == (6, 2) and mesh.textured is not None


def test_non_finite_normals_and_colours_are_replaced_with_a_warning(tmp_path):
    scene = read(single(STRIP[:3], NORMAL=np.array([[np.nan, 0, 1], [0, 0, 1], [0, 0, 1]]),
                        COLOR_0=np.array([[np.inf, 0, 0], [0, 0, 0], [2, 0, 0]])), tmp_path)
    mesh = scene.objects[0].mesh
    np.testing.assert_array_equal(mesh.corner_normals[0], [0, 0, 0])
    np.testing.assert_array_equal(mesh.vertex_colors[:, 0], [1, 0, 1])
    assert sum("not finite" in w for w in scene.warnings) == 2


def test_warnings_are_capped(tmp_path):
    """A file of 80 primitives without POSITION: 50 warnings, then their count."""
    b = GltfBuilder()
    pos = b.accessor(STRIP[:3])
    b.scene(b.node(mesh=b.mesh({"attributes": {"POSITION": pos}}, *[{"attributes": {"NORMAL": pos}}] * 80)))
    warnings = read(b, tmp_path).warnings
    assert len(warnings) == 51 and warnings[-1].endswith(": 30 more warnings not shown")
    assert warnings[49].endswith("meshes[0].primitives[50]: has no POSITION: not drawn")


def test_vertex_colours_are_tinted_by_the_material_factor(tmp_path):
    """glTF's base colour is COLOR_0 times baseColorFactor, in linear light; a primitive of the
    same mesh without COLOR_0 gets its factor at every vertex."""
    b = GltfBuilder()
    tint = b.add("materials", {"pbrMetallicRoughness": {"baseColorFactor": [0.5, 1.0, 0.25, 1.0]}})
    colors = b.accessor(np.array([[1.0, 0.5, 1.0]] * 3))
    b.scene(b.node(mesh=b.mesh({"attributes": {"POSITION": b.accessor(STRIP[:3]), "COLOR_0": colors}, "material": tint},
                               {"attributes": {"POSITION": b.accessor(STRIP[3:])}, "material": tint})))
    mesh = mesh_of(b, tmp_path)
    assert mesh.face_colors is None
    np.testing.assert_allclose(mesh.vertex_colors[:3], np.tile(encode_srgb(np.array([0.5, 0.5, 0.25])), (3, 1)), atol=1e-6)
    np.testing.assert_allclose(mesh.vertex_colors[3:], np.tile(encode_srgb(np.array([0.5, 1.0, 0.25])), (3, 1)), atol=1e-6)
