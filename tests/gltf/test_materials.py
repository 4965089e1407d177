"""Materials: baseColorFactor (linear, encoded to sRGB), baseColorTexture from a buffer view,
a file or a data: URI, samplers' wrap and filters, texCoord sets, alpha modes as rasterkit's
cut-out, doubleSided, and images that cannot be read."""

from __future__ import annotations

import base64

import numpy as np
import pytest

from rasterkit.gltf import GltfError, read_gltf
from rasterkit.gltf.materials import filter_of
from rasterkit.material.colorspace import encode_srgb
from support.gltffiles import GltfBuilder, png_bytes

TRIANGLE = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float64)
UV = np.array([[0, 0], [1, 0], [0, 1]], np.float64)
RGBA = np.array([[[255, 0, 0, 255], [0, 255, 0, 128]], [[0, 0, 255, 64], [255, 255, 255, 0]]], np.uint8)


def textured(material: dict | None = None, pixels=RGBA, sampler=None, uv_set=0, image=None):
    """A triangle with a textured material (``material``: more of its fields)."""
    b = GltfBuilder()
    image = b.image(pixels) if image is None else image(b)
    index = b.textured_material(image, sampler, **(material or {}))
    b.json["materials"][index]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] = uv_set
    attributes = {"POSITION": b.accessor(TRIANGLE), f"TEXCOORD_{uv_set}": b.accessor(UV)}
    b.scene(b.node(mesh=b.mesh({"attributes": attributes, "material": index})))
    return b


def read(b: GltfBuilder, tmp_path, name="m.glb"):
    scene = read_gltf(b.write_glb(tmp_path / name) if name.endswith(".glb") else b.write_gltf(tmp_path / name))
    return scene, scene.objects[0].mesh


def test_a_texture_from_a_buffer_view(tmp_path):
    scene, mesh = read(textured(), tmp_path)
    material = mesh.materials[0]
    assert not scene.warnings and mesh.face_materials.tolist() == [0]
    np.testing.assert_array_equal(material.diffuse_map.image[..., :3], RGBA[..., :3])  # row 0 at the top, as stored
    assert (material.diffuse_map.wrap, material.diffuse_map.filter, material.diffuse_map.srgb) == \
        ("repeat", "trilinear", True)
    assert material.diffuse == (1.0, 1.0, 1.0) and mesh.textured is not None


def test_a_texture_from_a_file_and_from_a_data_uri(tmp_path):
    (tmp_path / "tex").mkdir()
    b = textured(image=lambda b: b.image(RGBA[..., :3], "tex/a%20b.png", tmp_path))
    (tmp_path / "tex" / "a%20b.png").rename(tmp_path / "tex" / "a b.png")  # the URI is percent-encoded
    _, mesh = read(b, tmp_path, "m.gltf")
    np.testing.assert_array_equal(mesh.materials[0].diffuse_map.image, RGBA[..., :3])
    assert mesh.materials[0].diffuse_map.name == str(tmp_path / "tex" / "a b.png")
    uri = "data:image/png;base64," + base64.b64encode(png_bytes(RGBA[..., :3])).decode()
    _, mesh = read(textured(image=lambda b: b.add("images", {"uri": uri})), tmp_path, "d.gltf")
    np.testing.assert_array_equal(mesh.materials[0].diffuse_map.image, RGBA[..., :3])


def test_the_factor_is_linear_and_tints_in_srgb(tmp_path):
    factor = [0.5, 0.25, 1.0, 1.0]
    _, mesh = read(textured({"pbr": {"baseColorFactor": factor}}), tmp_path)
    np.testing.assert_allclose(mesh.materials[0].diffuse, encode_srgb(np.array(factor[:3])))


@pytest.mark.parametrize("sampler,wrap,filtering,warned", [
    ({}, "repeat", "trilinear", False),
    ({"wrapS": 33071, "wrapT": 33071, "magFilter": 9728, "minFilter": 9728}, "clamp", "nearest", False),
    ({"wrapS": 33648, "wrapT": 33648, "minFilter": 9729}, "mirror", "bilinear", False),
    ({"wrapS": 33071, "wrapT": 10497, "minFilter": 9987}, "clamp", "trilinear", True),
])
def test_samplers(tmp_path, sampler, wrap, filtering, warned):
    scene, mesh = read(textured(sampler=sampler), tmp_path)
    texture = mesh.materials[0].diffuse_map
    assert (texture.wrap, texture.filter) == (wrap, filtering)
    assert any("wrapS clamp and wrapT repeat differ: both are clamp" in w for w in scene.warnings) == warned


def test_filters():
    assert [filter_of(m, g) for m, g in [(None, None), (None, 9729), (None, 9728), (9984, 9728), (9986, None),
                                         (9729, None), (9728, 9729), (9728, 9728), (9728, None)]] == \
        ["trilinear", "trilinear", "nearest", "trilinear", "trilinear", "bilinear", "bilinear", "nearest", "nearest"]


def test_a_bad_wrap_is_an_error(tmp_path):
    with pytest.raises(GltfError, match=r"samplers\[0\]\.wrapT: 1 is not a wrap mode"):
        read(textured(sampler={"wrapT": 1}), tmp_path)


def test_a_second_texcoord_set(tmp_path):
    _, mesh = read(textured(uv_set=1), tmp_path)
    np.testing.assert_array_equal(mesh.uv, np.column_stack([UV[:, 0], 1 - UV[:, 1]]))


def test_opaque_drops_the_texture_alpha(tmp_path):
    _, mesh = read(textured(), tmp_path)
    texture = mesh.materials[0].diffuse_map
    assert texture.channels == 3 and mesh.materials[0].opacity == 1.0 and not mesh.textured.cutout


@pytest.mark.parametrize("mode,cutoff,alpha,opacity", [
    ("MASK", None, 1.0, 1.0),  # cut-off 0.5 by default: the renderer's own
    ("MASK", 0.25, 0.25, 0.5),  # 0.5 f / c
    ("BLEND", None, 0.6, 0.6),
])
def test_mask_keeps_the_alpha_and_carries_the_cutoff_in_the_opacity(tmp_path, mode, cutoff, alpha, opacity):
    """The renderer keeps a fragment where alpha * opacity >= 0.5; glTF where alpha * f >= c:
    opacity = 0.5 f / c gives the same test."""
    material = {"alphaMode": mode, "pbr": {"baseColorFactor": [1, 1, 1, alpha]}}
    if cutoff is not None:
        material["alphaCutoff"] = cutoff
    scene, mesh = read(textured(material), tmp_path)
    m = mesh.materials[0]
    assert m.diffuse_map.channels == 4 and m.opacity == pytest.approx(opacity) and mesh.textured.cutout
    assert any("BLEND is drawn as a cut-out at alpha 0.5" in w for w in scene.warnings) == (mode == "BLEND")


def test_a_low_cutoff_scales_the_texture_alpha(tmp_path):
    """alphaCutoff 0.1: a texel of alpha 64/255 (0.25) is kept by glTF; 0.5 / 0.1 = 5 times its
    alpha is at least 0.5 for the renderer; alpha 0 stays 0."""
    _, mesh = read(textured({"alphaMode": "MASK", "alphaCutoff": 0.1}), tmp_path)
    m = mesh.materials[0]
    assert m.opacity == 1.0
    np.testing.assert_array_equal(m.diffuse_map.image[..., 3], [[255, 255], [255, 0]])


def test_a_material_cut_out_whole_is_not_drawn(tmp_path):
    b = GltfBuilder()
    clear = b.add("materials", {"alphaMode": "MASK", "pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 0.2]}})
    pos = b.accessor(TRIANGLE)
    b.scene(b.node(mesh=b.mesh({"attributes": {"POSITION": pos}, "material": clear}, {"attributes": {"POSITION": pos}})))
    scene = read_gltf(b.write_glb(tmp_path / "c.glb"))
    assert len(scene.objects[0].mesh.faces) == 1 and scene.objects[0].mesh.face_colors is None
    assert any("materials[0]: alpha 0.2 is below the cut-off 0.5: its faces are not drawn" in w for w in scene.warnings)


def test_double_sided_and_names(tmp_path):
    _, mesh = read(textured({"doubleSided": True, "name": "paint"}), tmp_path)
    assert mesh.materials[0].double_sided is True and mesh.material_names == ("paint",)
    _, mesh = read(textured(), tmp_path, "n.glb")
    assert mesh.materials[0].double_sided is False and mesh.material_names == ("material0",)


def test_images_that_cannot_be_read_are_warnings(tmp_path):
    """A missing file, a corrupt image, an image without a source: the material is drawn with
    its colour, the file still loads."""
    b = textured(image=lambda b: b.add("images", {"uri": "missing.png"}))
    scene, mesh = read(b, tmp_path, "m.gltf")
    assert mesh.materials[0].diffuse_map is None and mesh.textured is None
    assert any("images[0]: cannot be read (cannot read 'missing.png': No such file or directory)" in w
               for w in scene.warnings)
    scene, mesh = read(textured(image=lambda b: b.add("images", {"bufferView": b.view(b"\x89PNG\r\n\x1a\nbroken")})),
                       tmp_path)
    assert mesh.materials[0].diffuse_map is None and any("cannot read the PNG header" in w for w in scene.warnings)
    b = textured()
    del b.json["textures"][0]["source"]
    scene, mesh = read(b, tmp_path)
    assert mesh.materials[0].diffuse_map is None and any("textures[0]: has no source image" in w for w in scene.warnings)


def test_textures_are_shared_between_materials(tmp_path):
    b = textured()
    b.json["materials"].append(dict(b.json["materials"][0], name="again"))
    prim = b.json["meshes"][0]["primitives"][0]
    b.json["meshes"][0]["primitives"].append(dict(prim, material=1))
    _, mesh = read(b, tmp_path)
    first, second = mesh.materials
    assert first is not second and first.diffuse_map is second.diffuse_map
