"""The container and what it names: sniff, the GLB header and chunks, the JSON, the asset
version, extensions, buffers in data: URIs and files (and the URIs refused), the file
rules of rasterkit.runtime.files, and the errors' form."""

from __future__ import annotations

import json
import os
import pickle
import struct

import numpy as np
import pytest

from rasterkit import limits
from rasterkit.gltf import GltfError, GltfLimitError, read_gltf, sniff
from support.gltffiles import triangle_builder


@pytest.fixture
def restore_limits():
    yield
    limits.set_max_file_size(None)
    limits.set_memory_limit(None)


def refusal(path) -> GltfError:
    with pytest.raises(GltfError) as info:
        read_gltf(path)
    text = str(info.value)
    assert "\n" not in text and text.startswith(os.fspath(path)), text
    return info.value


def test_sniff():
    assert sniff(b"glTF\x02\x00\x00\x00") == "glb"
    assert sniff(b'{"asset": {"version": "2.0"}}') == "gltf"
    assert sniff(b'\xef\xbb\xbf \n{\n  "accessors" : [') == "gltf"
    assert sniff(b'{"foo": 1, "asset": {"generator": "x", "version": "2.0"}}') == "gltf"
    assert sniff(b'{"asset": {"version": "1.0"}}') == "gltf"  # read_gltf then says glTF 1.0 is not read
    for other in (b'{"foo": 1}', b"solid cube", b"ply\n", b"OFF", b"", b"[1, 2]"):
        assert sniff(other) is None, other


def test_gltf_and_glb_give_the_same_scene(tmp_path):
    b = triangle_builder()
    glb = read_gltf(b.write_glb(tmp_path / "t.glb"))
    for name in ("t.gltf", None):
        gltf = read_gltf(b.write_gltf(tmp_path / "u.gltf", bin_name=name and "t.bin"))
        np.testing.assert_array_equal(gltf.objects[0].mesh.vertices, glb.objects[0].mesh.vertices)
        np.testing.assert_array_equal(gltf.objects[0].mesh.faces, glb.objects[0].mesh.faces)
    # the format is told by the bytes, not the name
    (tmp_path / "t.glb").rename(tmp_path / "t.gltf")
    assert len(read_gltf(tmp_path / "t.gltf").objects) == 1


def glb_with(tmp_path, change):
    data = bytearray(triangle_builder().glb())
    change(data)
    path = tmp_path / "bad.glb"
    path.write_bytes(bytes(data))
    return path


@pytest.mark.parametrize("change,where,reason", [
    (lambda d: d.__delitem__(slice(10, None)), "byte 0", "needs a 12-byte header, the file has 10 bytes"),
    (lambda d: d.__setitem__(slice(4, 8), struct.pack("<I", 1)), "byte 4", "GLB version 1 is not supported"),
    (lambda d: d.__setitem__(slice(8, 12), struct.pack("<I", 10**6)), "byte 8", "the header says the file has 1000000"),
    (lambda d: d.__setitem__(slice(12, 16), struct.pack("<I", 10**6)), "byte 12", "the chunk's length 1000000 goes past"),
    (lambda d: d.__setitem__(slice(16, 20), b"BIN\x00"), "byte 12", "the first chunk of a GLB file must be its JSON"),
    (lambda d: d.__setitem__(20, 0x7D), "byte 20", "invalid JSON: Expecting value"),
    (lambda d: d.__setitem__(21, 0xFF), "byte 21", "the JSON is not UTF-8 text"),
])
def test_broken_glb_structure(tmp_path, change, where, reason):
    error = refusal(glb_with(tmp_path, change))
    assert error.where == where and reason in error.reason, str(error)


def test_trailing_bytes_are_ignored_with_a_warning(tmp_path):
    path = glb_with(tmp_path, lambda d: d.extend(b"junk"))
    scene = read_gltf(path)
    assert any("4 bytes after the GLB's length ignored" in w for w in scene.warnings)


@pytest.mark.parametrize("text,where,reason", [
    (b'{"asset": {"version": "2.0"},', "line 1 column 30", "invalid JSON"),
    (b"[1, 2]", None, "the JSON must be an object, got a list of 2"),
    (b'{"asset": {"version": "1.0"}}', "asset.version", "glTF '1.0' is not supported"),
    (b'{"asset": {"version": "2.0", "minVersion": "2.1"}}', "asset.minVersion", "needs glTF '2.1'"),
    (b'{"meshes": []}', "asset", "missing: not a glTF 2.0 file"),
    (b"[" * 100000 + b"]" * 100000, None, "nested too deeply"),
    (b'{"asset": {"version": "2.0"}, "x": ' + b"9" * 5000 + b"}", None, "invalid JSON"),
    (b'{"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}]}', "scenes[0].nodes[0]", "there are no nodes"),
    (b'{"asset": {"version": "2.0"}, "nodes": {}}', "nodes", "must be a list, got an object"),
    (b'{"asset": {"version": "2.0"}}', None, "the default scene draws nothing"),
])
def test_bad_json(tmp_path, text, where, reason):
    path = tmp_path / "bad.gltf"
    path.write_bytes(text)
    error = refusal(path)
    assert error.where == where and reason in error.reason, str(error)


def test_extensions_changing_geometry_are_refused_by_name(tmp_path):
    b = triangle_builder()
    b.json["extensionsUsed"] = b.json["extensionsRequired"] = ["KHR_draco_mesh_compression"]
    error = refusal(b.write_glb(tmp_path / "draco.glb"))
    assert str(error) == (f"{tmp_path / 'draco.glb'}: extensionsRequired: requires extension "
                          "KHR_draco_mesh_compression (Draco-compressed geometry), which rasterkit does not read")
    for name in ("EXT_meshopt_compression", "EXT_mesh_gpu_instancing"):
        b.json["extensionsRequired"] = [name]
        assert f"requires extension {name} " in refusal(b.write_glb(tmp_path / "x.glb")).reason


def test_other_extensions_are_warnings_and_quantization_is_read(tmp_path):
    b = triangle_builder()
    b.json["extensionsUsed"] = ["KHR_mesh_quantization", "KHR_texture_transform", "KHR_draco_mesh_compression"]
    b.json["extensionsRequired"] = ["KHR_mesh_quantization", "KHR_materials_unlit"]
    warnings = read_gltf(b.write_glb(tmp_path / "e.glb")).warnings
    text = " | ".join(warnings)
    assert "requires extension 'KHR_materials_unlit', which rasterkit ignores" in text
    assert "uses extension 'KHR_texture_transform', which rasterkit ignores" in text
    assert "KHR_draco_mesh_compression (Draco-compressed geometry) is not read: its fallback data are" in text
    assert "quantization" not in text and len(warnings) == 3


@pytest.mark.parametrize("uri,reason", [
    ("/etc/passwd", "an absolute path"),
    ("C:\\model\\a.bin", "an absolute path"),
    ("http://example.com/a.bin", "only files beside the model are read, not http: URIs"),
    ("file:///tmp/a.bin", "not file: URIs"),
    ("../outside.bin", "leads outside the model's folder"),
    ("sub/../../outside.bin", "leads outside the model's folder"),
    ("", "names no file"),
    ("%ff.bin", "its percent-encoded bytes are not UTF-8"),
    ("missing.bin", "cannot read 'missing.bin': No such file or directory"),
    ("data:application/octet-stream;base64,AAA", "the data: URI's base64 is invalid"),
    ("data:nocomma", "a data: URI without a ','"),
])
def test_buffer_uris_refused(tmp_path, uri, reason):
    (tmp_path / "outside.bin").write_bytes(bytes(48))
    (tmp_path / "m").mkdir()
    b = triangle_builder()
    doc = b._document(uri)
    (tmp_path / "m" / "m.gltf").write_text(json.dumps(doc))
    error = refusal(tmp_path / "m" / "m.gltf")
    assert error.where == "buffers[0].uri" and reason in error.reason, str(error)


def test_buffer_uris_read(tmp_path):
    """Percent-encoded names, backslashes, ``..`` that stays inside, percent-encoded data URIs."""
    b = triangle_builder()
    (tmp_path / "sub dir").mkdir()
    (tmp_path / "sub dir" / "b.bin").write_bytes(bytes(b.bin))
    for uri in ("sub%20dir/b.bin", "sub dir\\b.bin", "./x/../sub%20dir/b.bin"):
        (tmp_path / "m.gltf").write_text(json.dumps(b._document(uri)))
        assert len(read_gltf(tmp_path / "m.gltf").objects) == 1, uri
    data = "data:application/octet-stream," + "".join(f"%{byte:02x}" for byte in bytes(b.bin))
    (tmp_path / "m.gltf").write_text(json.dumps(b._document(data)))
    assert len(read_gltf(tmp_path / "m.gltf").objects) == 1


def test_files_are_read_by_the_file_rules(tmp_path, restore_limits):
    """Not a regular file, over the file size limit: the model and the buffers it names."""
    os.mkfifo(tmp_path / "fifo.glb")
    assert refusal(tmp_path / "fifo.glb").reason == "not a regular file (a FIFO)"
    b = triangle_builder()
    os.mkfifo(tmp_path / "fifo.bin")
    (tmp_path / "m.gltf").write_text(json.dumps(b._document("fifo.bin")))
    assert refusal(tmp_path / "m.gltf").reason == "cannot read 'fifo.bin': not a regular file (a FIFO)"
    path = b.write_glb(tmp_path / "m.glb")
    limits.set_max_file_size(100)
    error = refusal(path)
    assert isinstance(error, GltfLimitError) and "file size limit" in error.reason
    assert "more than the limit" in str(refusal_memory(path))


def refusal_memory(path) -> GltfError:
    limits.set_max_file_size(None)
    limits.set_memory_limit(200)
    with pytest.raises(GltfLimitError) as info:
        read_gltf(path)
    return info.value


def test_errors_pickle_with_their_parts(tmp_path):
    error = GltfError("a.glb", "accessors[0]", "bad")
    assert str(error) == "a.glb: accessors[0]: bad" and isinstance(error, ValueError)
    copy = pickle.loads(pickle.dumps(error))
    assert (type(copy), copy.path, copy.where, copy.reason, str(copy)) == (GltfError, "a.glb", "accessors[0]", "bad",
                                                                           str(error))
    limit = pickle.loads(pickle.dumps(GltfLimitError("a\nb.glb", None, "too big")))
    assert isinstance(limit, limits.LimitError) and str(limit) == "'a\\nb.glb': too big"


def test_a_json_chunk_padded_with_nuls_is_read(tmp_path):
    """The GLB specification pads the JSON chunk with spaces; some writers use NUL bytes."""
    b = triangle_builder()
    text = json.dumps(b._document(None)).encode()
    path = tmp_path / "nul.glb"
    path.write_bytes(b.glb(text + b"\x00" * (4 - len(text) % 4)))
    assert len(read_gltf(path).objects) == 1
