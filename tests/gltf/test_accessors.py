"""Accessors: every component type with and without ``normalized``, byteStride interleaving,
byteOffset on the accessor and the view, sparse accessors, and every range checked before
an array is made."""

from __future__ import annotations

import numpy as np
import pytest

from rasterkit import limits
from rasterkit.gltf import GltfError, GltfLimitError, read_gltf
from support.gltffiles import GltfBuilder, triangle_builder

TRIANGLE = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float64)


def scene_of(b: GltfBuilder, tmp_path, name="m.glb"):
    return read_gltf(b.write_glb(tmp_path / name))


def one_mesh(b: GltfBuilder, tmp_path):
    scene = scene_of(b, tmp_path)
    assert len(scene.objects) == 1
    return scene.objects[0].mesh


def positions_builder(values, dtype, normalized=False, **extra):
    b = GltfBuilder()
    pos = b.accessor(values, dtype, normalized, **extra)
    b.scene(b.node(mesh=b.mesh({"attributes": {"POSITION": pos}})))
    return b


@pytest.mark.parametrize("dtype,normalized,stored,expected", [
    ("f4", False, [[0.5, -2, 3]], [[0.5, -2, 3]]),
    ("i1", False, [[-128, 5, 127]], [[-128, 5, 127]]),
    ("u1", False, [[0, 5, 255]], [[0, 5, 255]]),
    ("i2", False, [[-32768, 5, 32767]], [[-32768, 5, 32767]]),
    ("u2", False, [[0, 5, 65535]], [[0, 5, 65535]]),
    ("u4", False, [[0, 5, 4294967295]], [[0, 5, 4294967295]]),
    # normalized: unsigned c / max, signed max(c / max, -1)
    ("i1", True, [[-128, -127, 127]], [[-1, -1, 1]]),
    ("u1", True, [[0, 51, 255]], [[0, 0.2, 1]]),
    ("i2", True, [[-32768, 0, 16384]], [[-1, 0, 16384 / 32767]]),
    ("u2", True, [[0, 65535, 13107]], [[0, 1, 0.2]]),
])
def test_component_types_and_normalization(tmp_path, dtype, normalized, stored, expected):
    """Every component type (KHR_mesh_quantization positions too), as their values or as
    fractions; little-endian whatever the machine."""
    mesh = one_mesh(positions_builder(np.array(stored * 3), dtype, normalized), tmp_path)
    np.testing.assert_allclose(mesh.vertices, np.array(expected * 3, np.float64), rtol=0, atol=1e-12)


def test_interleaved_attributes_with_a_byte_stride(tmp_path):
    """POSITION, NORMAL and TEXCOORD_0 in one view, 32 bytes a vertex: each read at its offset."""
    b = GltfBuilder()
    normals = np.tile([0.0, 0.0, 1.0], (3, 1))
    uv = np.array([[0, 0], [1, 0.25], [0, 1]])
    pos, nor, tex = b.interleaved(TRIANGLE, normals, uv)
    image = b.image(np.zeros((2, 2, 3), np.uint8))
    material = b.textured_material(image)
    b.scene(b.node(mesh=b.mesh({"attributes": {"POSITION": pos, "NORMAL": nor, "TEXCOORD_0": tex},
                                "material": material})))
    assert b.json["bufferViews"][0]["byteStride"] == 32
    mesh = one_mesh(b, tmp_path)
    np.testing.assert_array_equal(mesh.vertices, TRIANGLE)
    np.testing.assert_array_equal(mesh.normals, normals)
    np.testing.assert_array_equal(mesh.uv, np.column_stack([uv[:, 0], 1 - uv[:, 1]]))


def test_byte_offsets_of_the_accessor_and_the_view_add_up(tmp_path):
    b = GltfBuilder()
    data = np.concatenate([np.full((2, 3), 99.0), TRIANGLE]).astype(np.float32).tobytes()
    view = b.view(bytes(8) + data)
    b.json["bufferViews"][view].update(byteOffset=b.json["bufferViews"][view]["byteOffset"] + 8, byteLength=len(data))
    pos = b.add("accessors", {"bufferView": view, "byteOffset": 24, "componentType": 5126, "count": 3,
                              "type": "VEC3"})
    b.scene(b.node(mesh=b.mesh({"attributes": {"POSITION": pos}})))
    np.testing.assert_array_equal(one_mesh(b, tmp_path).vertices, TRIANGLE)


def test_sparse_accessor_over_a_buffer_view(tmp_path):
    """Elements 0 and 2 replaced; the dense data are untouched elsewhere."""
    b = GltfBuilder()
    rows = b.view(np.array([0, 2], np.uint16).tobytes())
    values = b.view(np.array([[5, 5, 5], [7, 7, 7]], np.float32).tobytes())
    pos = b.accessor(TRIANGLE, sparse={"count": 2, "indices": {"bufferView": rows, "componentType": 5123},
                                       "values": {"bufferView": values}})
    b.scene(b.node(mesh=b.mesh({"attributes": {"POSITION": pos}})))
    np.testing.assert_array_equal(one_mesh(b, tmp_path).vertices, [[5, 5, 5], [1, 0, 0], [7, 7, 7]])


def test_sparse_accessor_without_a_buffer_view_is_zeros_elsewhere(tmp_path):
    b = GltfBuilder()
    rows = b.view(np.array([1], np.uint8).tobytes())
    values = b.view(np.array([[1, 2, 3]], np.float32).tobytes())
    pos = b.add("accessors", {"componentType": 5126, "count": 3, "type": "VEC3", "sparse": {
        "count": 1, "indices": {"bufferView": rows, "componentType": 5121}, "values": {"bufferView": values}}})
    b.scene(b.node(mesh=b.mesh({"attributes": {"POSITION": pos}})))
    np.testing.assert_array_equal(one_mesh(b, tmp_path).vertices, [[0, 0, 0], [1, 2, 3], [0, 0, 0]])


def refusal(b: GltfBuilder, tmp_path) -> GltfError:
    with pytest.raises(GltfError) as info:
        scene_of(b, tmp_path)
    text = str(info.value)
    assert "\n" not in text and text.startswith(str(tmp_path / "m.glb"))
    return info.value


@pytest.mark.parametrize("change,where,reason", [
    (lambda j: j["accessors"][0].update(count=4), "accessors[0]", "4 elements of 12 bytes every 12 from byte 0 need 48 bytes"),
    (lambda j: j["accessors"][0].update(byteOffset=4), "accessors[0]", "need 40 bytes, bufferViews[0] has 36"),
    (lambda j: j["accessors"][0].update(count=2**62), "accessors[0]", "need 55340232221128654848 bytes"),
    (lambda j: j["accessors"][0].update(count=0), "accessors[0].count", "must be an integer from 1"),
    (lambda j: j["accessors"][0].update(count="3"), "accessors[0].count", "must be an integer from 1, got '3'"),
    (lambda j: j["accessors"][0].update(count=True), "accessors[0].count", "got True"),
    (lambda j: j["accessors"][0].update(componentType=5124), "accessors[0].componentType", "not a glTF 2.0 component type"),
    (lambda j: j["accessors"][0].update(type="VEC5"), "accessors[0].type", "is not an accessor type"),
    (lambda j: j["accessors"][0].update(bufferView=9), "accessors[0].bufferView", "must be an index of bufferViews"),
    (lambda j: j["bufferViews"][0].update(byteLength=1000), "bufferViews[0]", "go past the end of buffers[0]"),
    (lambda j: j["bufferViews"][0].update(byteOffset=-4), "bufferViews[0].byteOffset", "from 0, got -4"),
    (lambda j: j["bufferViews"][0].update(byteStride=8), "bufferViews[0].byteStride", "8 bytes, less than the 12"),
    (lambda j: j["bufferViews"][0].update(byteStride=256), "bufferViews[0].byteStride", "from 4 to 252"),
    (lambda j: j["buffers"][0].update(byteLength=10**6), "buffers[0].byteLength", "holds only"),
    (lambda j: j["accessors"][1].update(type="VEC3"), "meshes[0].primitives[0].indices", "accessors[1] is VEC3"),
    (lambda j: j["accessors"][1].update(normalized=True), "meshes[0].primitives[0].indices", "cannot be normalized"),
    (lambda j: j["accessors"][0].update(byteOffset=30, componentType=5123), "accessors[0]", "need 48 bytes"),
])
def test_every_range_is_checked_first(tmp_path, change, where, reason):
    """A count, offset, stride or type past the data: one line naming the JSON path, never an
    array past the buffer (nor one of 2**62 elements)."""
    b = triangle_builder()
    doc = b._document(None)
    change(doc)
    (tmp_path / "m.glb").write_bytes(b.glb(__import__("json").dumps(doc).encode()))
    with pytest.raises(GltfError) as info:
        read_gltf(tmp_path / "m.glb")
    error = info.value
    assert error.where == where and reason in error.reason, str(error)


def test_sparse_ranges_are_checked(tmp_path):
    b = GltfBuilder()
    rows = b.view(np.array([3], np.uint16).tobytes())
    values = b.view(np.array([[1, 2, 3]], np.float32).tobytes())
    pos = b.accessor(TRIANGLE, sparse={"count": 1, "indices": {"bufferView": rows, "componentType": 5123},
                                       "values": {"bufferView": values}})
    b.scene(b.node(mesh=b.mesh({"attributes": {"POSITION": pos}})))
    error = refusal(b, tmp_path)
    assert (error.where, error.reason) == ("accessors[0].sparse.indices", "index 3 >= the accessor's count 3")
    b.json["accessors"][0]["sparse"]["count"] = 2
    error = refusal(b, tmp_path)
    assert error.where == "accessors[0].sparse.indices" and "need 4 bytes, bufferViews[0] has 2" in error.reason


def test_huge_zero_accessors_meet_the_memory_limit(tmp_path):
    """An accessor without a buffer view has no data to bound its count: the memory limit does,
    before the zeros are made."""
    b = GltfBuilder()
    pos = b.add("accessors", {"componentType": 5126, "count": 10**12, "type": "VEC3"})
    b.scene(b.node(mesh=b.mesh({"attributes": {"POSITION": pos}})))
    b.view(bytes(4))
    error = refusal(b, tmp_path)
    assert isinstance(error, GltfLimitError) and isinstance(error, limits.LimitError)
    assert error.where == "accessors[0]" and "zeros of accessors[0]" in error.reason


def test_attributes_of_another_count_are_refused(tmp_path):
    b = GltfBuilder()
    pos = b.accessor(TRIANGLE)
    nor = b.accessor(np.zeros((2, 3)))
    b.scene(b.node(mesh=b.mesh({"attributes": {"POSITION": pos, "NORMAL": nor}})))
    error = refusal(b, tmp_path)
    assert (error.where, error.reason) == ("meshes[0].primitives[0].attributes.NORMAL",
                                           "accessors[1] has 2 elements, POSITION has 3")
