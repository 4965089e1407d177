"""The public glTF and GLB files of ``../shared/models/formats``: their counts (the folder's
README), world-space positions, texture coordinates, normals and colours against trimesh's,
the v flip of TextureCoordinateTest, a render of BoxTextured that shows its texture, and the
robustness files, each one clean error. Skipped, with the reason, without the folder (or
without trimesh for the comparisons)."""

from __future__ import annotations

import numpy as np
import pytest

import rasterkit
from rasterkit.gltf import GltfError, read_gltf
from rasterkit.material.colorspace import decode_srgb
from rasterkit.transform import apply_normals, apply_points
from support.paths import MODELS

FORMATS = MODELS / "formats"
pytestmark = pytest.mark.skipif(not FORMATS.is_dir(), reason=f"{FORMATS} is absent (the shared test models are "
                                                              "not part of the repository)")

#: file: (mesh nodes drawn, vertices of the meshes (each once), triangles drawn), from the README.
COUNTS = {
    "gltf/BoxTextured/BoxTextured.gltf": (1, 24, 12),
    "gltf/BoxVertexColors/BoxVertexColors.gltf": (1, 24, 12),
    "gltf/TextureCoordinateTest/TextureCoordinateTest.gltf": (5, 20, 10),
    "glb/OrientationTest.glb": (13, 1048, 524),
    "glb/TextureSettingsTest.glb": (10, 144, 72),
    "glb/CesiumMilkTruck.glb": (3, 3995, 3624),
}


@pytest.mark.parametrize("name", COUNTS)
def test_counts(name):
    scene = read_gltf(FORMATS / name)
    nodes, vertices, drawn = COUNTS[name]
    meshes = {id(o.mesh): o.mesh for o in scene.objects}.values()
    assert (len(scene.objects), sum(len(m.vertices) for m in meshes), sum(len(o.mesh.faces) for o in scene.objects)) \
        == (nodes, vertices, drawn)
    assert len(scene.world_mesh().faces) == drawn


def _rows(vertices, matrix, extra=None) -> np.ndarray:
    """World positions (and per-vertex values) as rows, sorted: order-free comparison."""
    rows = apply_points(matrix, vertices)
    if extra is not None:
        rows = np.hstack([rows, extra])
    return _sorted(rows)


def _sorted(rows):
    """Rows sorted by their values rounded (a value within float noise of a rounding step
    would otherwise put two equal positions' attributes in either order)."""
    return rows[np.lexsort(np.round(rows, 4).T[::-1])]


def _trimesh_rows(tm_scene, what):
    out = []
    for node in tm_scene.graph.nodes_geometry:
        matrix, name = tm_scene.graph[node]
        geometry = tm_scene.geometry[name]
        out.append(_rows(geometry.vertices, matrix, what(geometry, matrix)))
    return _sorted(np.concatenate(out))


def _our_rows(scene, what):
    return _sorted(np.concatenate([_rows(o.mesh.vertices, o.matrix, what(o.mesh, o.matrix)) for o in scene.objects]))


def _unit(normals):
    return normals / np.linalg.norm(normals, axis=1, keepdims=True)


@pytest.mark.parametrize("name", COUNTS)
def test_world_positions_normals_and_uv_match_trimesh(name):
    trimesh = pytest.importorskip("trimesh")
    scene = read_gltf(FORMATS / name)
    theirs = trimesh.load(FORMATS / name, process=False)
    assert sum(len(theirs.geometry[theirs.graph[n][1]].faces) for n in theirs.graph.nodes_geometry) == \
        sum(len(o.mesh.faces) for o in scene.objects)
    np.testing.assert_allclose(_our_rows(scene, lambda m, x: None), _trimesh_rows(theirs, lambda g, x: None),
                               atol=1e-6)
    np.testing.assert_allclose(_our_rows(scene, lambda m, x: _unit(apply_normals(x, m.normals))),
                               _trimesh_rows(theirs, lambda g, x: _unit(apply_normals(x, g.vertex_normals))), atol=1e-5)
    if all(o.mesh.uv is not None for o in scene.objects):
        np.testing.assert_allclose(_our_rows(scene, lambda m, x: m.uv), _trimesh_rows(theirs, lambda g, x: g.visual.uv),
                                   atol=1e-6)


def test_vertex_colours_match_trimesh_in_linear_light():
    """BoxVertexColors' COLOR_0 (linear): ours are sRGB-encoded; decoded they are trimesh's /255."""
    trimesh = pytest.importorskip("trimesh")
    name = "gltf/BoxVertexColors/BoxVertexColors.gltf"
    scene = read_gltf(FORMATS / name)
    ours = _our_rows(scene, lambda m, x: decode_srgb(m.vertex_colors))
    theirs = _trimesh_rows(trimesh.load(FORMATS / name, process=False),
                           lambda g, x: g.visual.vertex_colors[:, :3] / 255.0)
    np.testing.assert_allclose(ours, theirs, atol=0.5 / 255 + 1e-6)


def test_texture_coordinates_put_each_label_where_its_square_is():
    """TextureCoordinateTest: the square at the top left (x < 0, y > 0) shows the top-left
    quarter of the image, whose v (rasterkit's, up) is the high half: glTF's v runs down."""
    scene = read_gltf(FORMATS / "gltf/TextureCoordinateTest/TextureCoordinateTest.gltf")
    squares = [o.mesh for o in scene.objects if o.mesh.uv is not None]
    assert len(squares) == 4
    for mesh in squares:
        x, y = np.sign(mesh.vertices[:, :2].mean(axis=0))
        u, v = mesh.uv.mean(axis=0) - 0.5
        assert (np.sign(u), np.sign(v)) == (x, y), mesh.material_names
        assert mesh.material_names[0].startswith({1: "Top", -1: "Bottom"}[y] + {1: "Right", -1: "Left"}[x])


def test_a_render_of_box_textured_shows_its_texture():
    """Looking straight at one face (orthographic, headlight: Lambert factor 1), nearest
    filtering: each pixel is the texel at its interpolated uv (from the frame's uv map)."""
    from PIL import Image

    scene = read_gltf(FORMATS / "gltf/BoxTextured/BoxTextured.gltf")
    texels = np.asarray(Image.open(FORMATS / "gltf/BoxTextured/CesiumLogoFlat.png").convert("RGB"))
    camera = rasterkit.Camera.orthographic((0, 0, 5), (0, 0, 0), view_height=0.9, width=64, height=64)
    fb = rasterkit.render(scene, camera, "solid", texture_filter="nearest", uv=True, background="black")
    uv = fb.uv.reshape(-1, 2)
    assert np.isfinite(uv).all()  # the face fills the view
    h, w = texels.shape[:2]
    uv = np.mod(uv, 1.0)  # its coordinates run from 3 to 4 on this face: the sampler repeats
    expected = texels[np.minimum(np.floor((1 - uv[:, 1]) * h), h - 1).astype(int),
                      np.minimum(np.floor(uv[:, 0] * w), w - 1).astype(int)]
    difference = np.abs(fb.color.reshape(-1, 3).astype(int) - expected).max(axis=1)
    assert np.mean(difference <= 2) > 0.95, np.mean(difference <= 2)
    assert len(np.unique(fb.color.reshape(-1, 3), axis=0)) > 4  # the logo, not one colour


ROBUSTNESS = {
    "robustness/glb/buffer-invalid-short-size.glb": ("buffers[0].byteLength", "24 bytes, but the GLB's binary chunk "
                                                                             "holds only 12"),
    "robustness/gltf/IndexOutOfRange/IndexOutOfRange.gltf": ("meshes[0].primitives[0].indices",
                                                             "index 255 >= the vertex count 24"),
    "robustness/gltf/MissingBin/BoxTextured.gltf": ("buffers[0].uri", "cannot read 'BoxTextured0.bin': No such file "
                                                                      "or directory"),
}


@pytest.mark.parametrize("name", ROBUSTNESS)
def test_robustness_files_end_in_one_clean_error(name):
    with pytest.raises(GltfError) as info:
        read_gltf(FORMATS / name)
    assert (info.value.where, info.value.reason) == ROBUSTNESS[name]
    assert str(info.value) == f"{FORMATS / name}: {info.value.where}: {info.value.reason}"


def test_every_robustness_file_is_listed():
    found = {str(p.relative_to(FORMATS)) for folder in ("robustness/gltf", "robustness/glb")
             for p in (FORMATS / folder).rglob("*") if p.suffix in (".gltf", ".glb")}
    assert found == set(ROBUSTNESS)
