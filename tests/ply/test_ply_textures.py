"""Texture coordinates per face corner (MeshLab's ``texcoord`` list) and ``comment TextureFile``
as materials."""

import numpy as np
import pytest

from rasterkit.ply import read_ply
from support.plyfiles import FACES, SQUARE, XYZ, write_ply

ENCODINGS = ("ascii", "binary_little_endian", "binary_big_endian")
TEXCOORD = ("list", "uchar", "float", "texcoord")
QUAD_UV = [0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0]


def png(path, colour=(255, 0, 0)):
    from PIL import Image

    Image.new("RGB", (4, 2), colour).save(path)
    return path


def textured(tmp_path, encoding, faces, comments=("TextureFile tex one.png",), name="t.ply", extra=()):
    props = FACES + [TEXCOORD, *extra]
    return write_ply(tmp_path / name, encoding, [("vertex", XYZ, SQUARE), ("face", props, faces)], comments)


@pytest.mark.parametrize("encoding", ENCODINGS)
def test_corner_texture_coordinates_and_the_texture_file(tmp_path, encoding):
    png(tmp_path / "tex one.png")
    mesh = read_ply(textured(tmp_path, encoding, [([0, 1, 2, 3], QUAD_UV), ([0, 2, 1], [0.5, 0.5, 0.25, 0.75, 1, 1])]))
    assert mesh.faces.tolist() == [[0, 1, 2], [0, 2, 3], [0, 2, 1]]
    # a table of one row per polygon corner, and each triangle corner's row
    assert mesh.uv.tolist() == [[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5], [0.25, 0.75], [1, 1]]
    assert mesh.uv_index.tolist() == [[0, 1, 2], [0, 2, 3], [4, 5, 6]]
    assert mesh.material_names == ("tex one.png",)
    assert mesh.face_materials.tolist() == [0, 0, 0]
    texture = mesh.materials[0].diffuse_map
    assert texture.image.shape == (2, 4, 3) and (texture.image == (255, 0, 0)).all()
    assert mesh.materials[0].diffuse == (1.0, 1.0, 1.0)
    assert mesh.warnings == ()


def test_faces_whose_texcoord_list_does_not_fit_have_none(tmp_path):
    png(tmp_path / "tex one.png")
    path = textured(tmp_path, "binary_little_endian", [([0, 1, 2, 3], QUAD_UV), ([0, 2, 1], [0.5, 0.5]),
                                                       ([0, 1, 3], [1, 1, 0, 0, 0.5, 0.5])])
    mesh = read_ply(path)
    assert mesh.uv_index.tolist() == [[0, 1, 2], [0, 2, 3], [-1, -1, -1], [7, 8, 9]]
    assert mesh.uv[7:].tolist() == [[1, 1], [0, 0], [0.5, 0.5]]
    assert mesh.warnings == (f"{path}:10: 1 face whose 'texcoord' list does not hold two values per corner (the "
                             "first: row 1): no texture coordinates for them",)


@pytest.mark.parametrize("encoding", ENCODINGS)
def test_several_texture_files_are_told_apart_by_texnumber(tmp_path, encoding):
    png(tmp_path / "a.png", (0, 255, 0))
    png(tmp_path / "b.png", (0, 0, 255))
    path = textured(tmp_path, encoding, [([0, 1, 2], QUAD_UV[:6], 1), ([0, 2, 3], QUAD_UV[:6], 0),
                                         ([0, 1, 3], QUAD_UV[:6], 7)],
                    comments=("TextureFile a.png", "TextureFile b.png"), extra=[("int", "texnumber")])
    mesh = read_ply(path)
    assert mesh.material_names == ("a.png", "b.png")
    assert mesh.face_materials.tolist() == [1, 0, -1]
    assert mesh.materials[1].diffuse_map.image[0, 0].tolist() == [0, 0, 255]
    assert mesh.warnings == (f"{path}:12: 1 face whose texnumber names no TextureFile (there are 2): drawn "
                             "without a texture",)


def test_a_missing_texture_is_a_warning_and_the_faces_keep_their_coordinates(tmp_path):
    path = textured(tmp_path, "ascii", [([0, 1, 2, 3], QUAD_UV)])
    mesh = read_ply(path)
    assert mesh.materials == () and mesh.material_names == () and mesh.face_materials is None
    assert mesh.uv_index.tolist() == [[0, 1, 2], [0, 2, 3]]
    assert mesh.warnings == (f"{path}:3: texture 'tex one.png' cannot be read: No such file or directory; drawn "
                             "without it",)


@pytest.mark.parametrize("name", ["../outside.png", "/etc/hostname", "sub/../../outside.png"])
def test_no_texture_outside_the_models_folder_is_opened(tmp_path, name):
    folder = tmp_path / "model"
    folder.mkdir()
    png(tmp_path / "outside.png")
    path = textured(folder, "ascii", [([0, 1, 2, 3], QUAD_UV)], comments=(f"TextureFile {name}",))
    mesh = read_ply(path)
    assert mesh.materials == ()
    assert mesh.warnings == (f"{path}:3: texture {name!r} is outside the model's folder: not read",)


def test_a_texture_in_a_subfolder_and_written_with_backslashes(tmp_path):
    (tmp_path / "maps").mkdir()
    png(tmp_path / "maps" / "wood.png")
    mesh = read_ply(textured(tmp_path, "ascii", [([0, 1, 2, 3], QUAD_UV)], comments=("TextureFile maps\\wood.png",)))
    assert mesh.materials[0].diffuse_map.name == str(tmp_path / "maps" / "wood.png")


def test_textures_false_opens_no_image(tmp_path):
    png(tmp_path / "tex one.png")
    mesh = read_ply(textured(tmp_path, "ascii", [([0, 1, 2, 3], QUAD_UV)]), textures=False)
    assert mesh.materials == () and mesh.uv is not None and mesh.warnings == ()


def test_per_vertex_texture_coordinates_with_a_texture_file(tmp_path):
    png(tmp_path / "w.png")
    props = XYZ + [("float", "s"), ("float", "t")]
    rows = [(*v, v[0] / 2, v[1]) for v in SQUARE]
    elements = [("vertex", props, rows), ("face", FACES, [([0, 1, 2, 3],)])]
    mesh = read_ply(write_ply(tmp_path / "t.ply", "ascii", elements, comments=("TextureFile w.png",)))
    assert mesh.uv.tolist() == [[0, 0], [0.5, 0], [0.5, 1], [0, 1]]
    np.testing.assert_array_equal(mesh.uv_index, mesh.faces)
    assert mesh.material_names == ("w.png",) and mesh.face_materials.tolist() == [0, 0]
