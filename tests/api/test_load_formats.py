"""``rasterkit.load``: each file goes to its reader by content, then extension; the result is
the reader's own; what no reader takes is one line naming the file."""

from __future__ import annotations

import shutil
import struct

import numpy as np
import pytest

import rasterkit
from rasterkit.formats import content_format, detect
from support.gltffiles import triangle_builder
from support.paths import MODELS, needs_models

FORMATS = MODELS / "formats"

TETRA_STL = """solid tetra
facet normal 0 0 -1
 outer loop
  vertex 0 0 0
  vertex 0 1 0
  vertex 1 0 0
 endloop
endfacet
facet normal 0 -1 0
 outer loop
  vertex 0 0 0
  vertex 1 0 0
  vertex 0 0 1
 endloop
endfacet
facet normal -1 0 0
 outer loop
  vertex 0 0 0
  vertex 0 0 1
  vertex 0 1 0
 endloop
endfacet
facet normal 1 1 1
 outer loop
  vertex 1 0 0
  vertex 0 1 0
  vertex 0 0 1
 endloop
endfacet
endsolid tetra
"""

SQUARE_OFF = "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n"
SQUARE_PLY = ("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
              "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
              "0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n")
CLOUD_PLY = ("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
             "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n"
             "0 0 0 255 0 0\n1 0 0 0 255 0\n0 1 0 0 0 255\n")
SQUARE_OBJ = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"


def _binary_stl(header: bytes) -> bytes:
    """One facet, (0,0,0) (1,0,0) (0,1,0), after an 80-byte ``header``."""
    facet = struct.pack("<12fH", 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0)
    return header.ljust(80, b" ") + struct.pack("<I", 1) + facet


@pytest.fixture
def files(tmp_path):
    (tmp_path / "tetra.stl").write_text(TETRA_STL)
    (tmp_path / "square.off").write_text(SQUARE_OFF)
    (tmp_path / "square.ply").write_text(SQUARE_PLY)
    (tmp_path / "cloud.ply").write_text(CLOUD_PLY)
    (tmp_path / "square.obj").write_text(SQUARE_OBJ)
    (tmp_path / "binary.stl").write_bytes(_binary_stl(b"solid but binary"))
    triangle_builder().write_glb(tmp_path / "triangle.glb")
    return tmp_path


def test_each_format_by_its_extension_gives_its_readers_result(files):
    tetra = rasterkit.load(files / "tetra.stl")
    assert isinstance(tetra, rasterkit.Mesh) and tetra.faces.shape == (4, 3) and len(tetra.vertices) == 4
    for name in ("square.off", "square.ply", "square.obj"):
        mesh = rasterkit.load(files / name)
        assert isinstance(mesh, rasterkit.Mesh) and mesh.faces.shape == (2, 3), name
        assert sorted(map(tuple, mesh.edges.tolist())) == [(0, 1), (0, 3), (1, 2), (2, 3)], name  # the quad's sides
    cloud = rasterkit.load(files / "cloud.ply")
    np.testing.assert_array_equal(cloud.points, [[0, 0, 0], [1, 0, 0], [0, 1, 0]])
    np.testing.assert_array_equal(cloud.colors, np.eye(3))
    scene = rasterkit.load(files / "triangle.glb")
    assert isinstance(scene, rasterkit.Scene) and len(scene.world_mesh().faces) == 1
    assert rasterkit.load(files / "binary.stl").faces.shape == (1, 3)  # "solid" in a binary header


def test_the_content_decides_when_the_extension_is_wrong_or_missing(files):
    for source, target in [("square.ply", "looks.stl"), ("tetra.stl", "looks.ply"), ("square.off", "looks.obj"),
                           ("triangle.glb", "looks.obj"), ("square.obj", "noextension"), ("binary.stl", "x.off")]:
        shutil.copy(files / source, files / target)
        assert detect(files / target) == detect(files / source), (source, target)
        expected, got = rasterkit.load(files / source), rasterkit.load(files / target)
        if isinstance(expected, rasterkit.Scene):
            expected, got = expected.world_mesh(), got.world_mesh()
        np.testing.assert_array_equal(got.faces, expected.faces)
        np.testing.assert_array_equal(got.vertices, expected.vertices)


def test_format_names_the_reader_and_a_wrong_one_fails_in_its_readers_words(files):
    assert rasterkit.load(files / "square.obj", format="obj").faces.shape == (2, 3)
    assert isinstance(rasterkit.load(files / "triangle.glb", format="glb"), rasterkit.Scene)
    with pytest.raises(ValueError, match="format must be one of obj, stl, ply, off, gltf"):
        rasterkit.load(files / "square.obj", format="fbx")
    with pytest.raises(ValueError) as error:
        rasterkit.load(files / "square.obj", format="ply")
    assert str(error.value).startswith(str(files / "square.obj")) and "\n" not in str(error.value)


def test_unknown_binary_content_and_non_regular_files_are_one_line(files):
    junk = files / "junk"
    junk.write_bytes(b"\x00\x01\x02 not a model" * 10)
    with pytest.raises(ValueError, match=r"junk: not a model format rasterkit reads \(OBJ, STL, PLY, OFF, glTF/GLB\)"):
        rasterkit.load(junk)
    with pytest.raises(ValueError, match="not a regular file"):
        rasterkit.load(files)
    with pytest.raises(ValueError, match="cannot read"):
        rasterkit.load(files / "missing.stl")


@pytest.mark.parametrize("head, size, expected", [
    (b"ply\r\nformat binary_little_endian 1.0\n", 100, "ply"),
    (b"\xef\xbb\xbf  OFF\n", 50, "off"), (b"COFF 8 6 0\n", 50, "off"), (b"STCNOFF\n", 50, "off"),
    (b"OFFICE supplies\n", 50, None), (b"solid x\n facet normal 0 0 1\n", 1000, "stl"),
    (b"solid works\nv 0 0 0\n", 1000, None), (b'{\n "asset": {"version": "2.0"}}', 40, "gltf"),
    (b"glTF\x02\x00\x00\x00", 1000, "gltf"), (b"v 1 2 3\nf 1 2 3\n", 16, None),
])
def test_content_format_of_first_bytes(head, size, expected):
    assert content_format(head, size) == expected


@needs_models
def test_every_shared_format_file_loads_as_its_extension_says():
    if not FORMATS.is_dir():
        pytest.skip(f"{FORMATS} is absent")
    kinds = {".stl": rasterkit.Mesh, ".off": rasterkit.Mesh, ".ply": rasterkit.Mesh, ".gltf": rasterkit.Scene,
             ".glb": rasterkit.Scene}
    paths = [p for p in sorted(FORMATS.rglob("*")) if p.suffix.lower() in kinds and "robustness" not in p.parts]
    assert len(paths) >= 12
    for path in paths:
        model = rasterkit.load(path, textures=False)
        assert isinstance(model, kinds[path.suffix.lower()]), path
        mesh = model.world_mesh() if isinstance(model, rasterkit.Scene) else model
        assert len(mesh.faces) > 0, path
