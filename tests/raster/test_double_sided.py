"""Double-sided materials (glTF's ``doubleSided``): their faces are drawn from both sides
whatever ``cull`` says and lit on the back as on the front, while the other faces of the
same mesh keep the render's culling and one-sided lighting.

The expectations are renders of each part alone: a double-sided face must look exactly as
it does with ``cull="none"`` (which draws and lights every face on both sides), a one-sided
face exactly as it does with the render's own ``cull``."""

from __future__ import annotations

import numpy as np
import pytest

from rasterkit import Camera, Material, Mesh, Texture, load, render
from rasterkit.raster.sides import face_sides
from support.gltffiles import GltfBuilder

CAMERA = Camera.look_at((0.3, 0.4, 4.0), (0.0, 0.0, 0.0), fov_y=40.0, width=96, height=72)
# The light comes from behind the camera's right, in front of the +z faces and behind the -z ones.
LIGHT = (0.4, 0.3, 1.0)

#: Two quads side by side, each two triangles: the left one faces the camera (+z), the right
#: one faces away (its winding reversed), a third quad behind both faces away too.
VERTICES = np.array([
    [-1.6, -0.6, 0], [-0.1, -0.6, 0], [-0.1, 0.6, 0], [-1.6, 0.6, 0],  # left
    [0.1, -0.6, 0], [1.6, -0.6, 0], [1.6, 0.6, 0], [0.1, 0.6, 0],  # right
    [-1.2, -1.0, -1], [1.2, -1.0, -1], [1.2, -0.8, -1], [-1.2, -0.8, -1],  # a strip behind, low
], np.float64)
FRONT = [[0, 1, 2], [0, 2, 3]]
BACK = [[4, 6, 5], [4, 7, 6]]
BEHIND = [[8, 10, 9], [8, 11, 10]]


def _mesh(groups, double, texture=None, **fields):
    """A Mesh of the face ``groups``, a material each, double-sided as ``double`` says."""
    faces = np.array([f for g in groups for f in g], np.int64)
    labels = np.repeat(np.arange(len(groups), dtype=np.int32), [len(g) for g in groups])
    materials = tuple(Material(name=f"m{k}", diffuse=(0.9, 0.6, 0.3), double_sided=d,
                               diffuse_map=texture) for k, d in enumerate(double))
    if texture is not None:
        fields["uv"] = (VERTICES[:, :2] + 2.0) / 4.0
    return Mesh(VERTICES, faces, material_names=tuple(m.name for m in materials), materials=materials,
                face_materials=labels, **fields)


def _plain(groups, texture=None, **fields):
    """The same faces with one material, not double-sided."""
    return _mesh([[f for g in groups for f in g]], [False], texture, **fields)


def _checker():
    pixels = np.zeros((8, 8, 3), np.uint8)
    pixels[(np.add.outer(np.arange(8), np.arange(8)) % 2) == 1] = (250, 240, 20)
    pixels[(np.add.outer(np.arange(8), np.arange(8)) % 2) == 0] = (30, 90, 200)
    return Texture(pixels)


@pytest.mark.parametrize("shading", ["flat", "smooth"])
@pytest.mark.parametrize("textured", [False, True])
def test_a_double_sided_face_is_drawn_and_lit_as_without_culling_and_the_others_as_with(shading, textured):
    texture = _checker() if textured else None
    options = dict(mode="solid", shading=shading, light=LIGHT, ids=True)
    mixed = render(_mesh([FRONT, BACK, BEHIND], [False, True, False], texture), CAMERA, **options)
    one_sided = render(_plain([FRONT, BACK, BEHIND], texture), CAMERA, cull="back", **options)
    both = render(_plain([FRONT, BACK, BEHIND], texture), CAMERA, cull="none", **options)
    # ids: faces 0-1 front, 2-3 the double-sided back quad, 4-5 the one-sided strip behind
    back_quad = np.isin(both.ids, [2, 3])
    assert back_quad.sum() > 500 and not np.isin(one_sided.ids, [2, 3]).any()
    np.testing.assert_array_equal(mixed.ids, np.where(np.isin(both.ids, [4, 5]), one_sided.ids, both.ids))
    # the double-sided quad: as with cull="none" (lit by |n.l|: not the ambient level)
    np.testing.assert_array_equal(mixed.color[back_quad], both.color[back_quad])
    # the one-sided front quad: as with cull="back"; the light is in front of it, so both agree there
    front = np.isin(one_sided.ids, [0, 1])
    np.testing.assert_array_equal(mixed.color[front], one_sided.color[front])
    # nothing of the one-sided strip behind is drawn, where cull="none" draws it
    strip = np.isin(both.ids, [4, 5])
    assert strip.sum() > 50 and (mixed.ids[strip] == -1).all()
    np.testing.assert_array_equal(mixed.color[strip], one_sided.color[strip])


@pytest.mark.parametrize("shading", ["flat", "smooth"])
def test_one_sided_faces_keep_one_sided_light_beside_double_sided_ones(shading):
    """Light from behind the front quad: one-sided it is at the ambient level, two-sided it
    would be lit. With a double-sided quad in the mesh, it stays at the ambient level."""
    options = dict(mode="solid", shading=shading, light=(0.3, 0.2, -1.0), ids=True)
    mixed = render(_mesh([FRONT, BACK], [False, True]), CAMERA, **options)
    alone = render(_plain([FRONT]), CAMERA, cull="back", **options)
    lit_both = render(_plain([FRONT]), CAMERA, cull="none", **options)
    front = alone.ids >= 0
    assert front.sum() > 500
    np.testing.assert_array_equal(mixed.color[front], alone.color[front])
    assert (lit_both.color[front].astype(int) - alone.color[front]).max() > 40  # two-sided light differs


def test_a_mesh_whose_materials_are_all_double_sided_is_drawn_as_without_culling():
    mesh = _mesh([FRONT, BACK, BEHIND], [True, True, True])
    assert face_sides(mesh, "back") == ("none", True)
    for mode in ("solid", "solid+wire", "hidden"):
        got = render(mesh, CAMERA, mode=mode, light=LIGHT)
        want = render(_plain([FRONT, BACK, BEHIND]), CAMERA, mode=mode, light=LIGHT, cull="none")
        np.testing.assert_array_equal(got.color, want.color)


@pytest.mark.parametrize("mode", ["hidden", "solid+wire"])
def test_double_sided_faces_hide_lines_behind_them(mode):
    """The strip behind is seen through the gap below the quads only; the back quad, double
    sided, hides what is behind it as cull="none" does."""
    mixed = render(_mesh([FRONT, BACK, BEHIND], [False, True, False]), CAMERA, mode=mode, light=LIGHT)
    both = render(_plain([FRONT, BACK, BEHIND]), CAMERA, mode=mode, light=LIGHT, cull="none")
    one_sided = render(_plain([FRONT, BACK, BEHIND]), CAMERA, mode=mode, light=LIGHT, cull="back")
    assert not np.array_equal(both.color, one_sided.color)
    # the right half of the image (the back quad) is as without culling
    right = (slice(None), slice(CAMERA.width // 2 + 8, None))
    np.testing.assert_array_equal(mixed.color[right][:40], both.color[right][:40])


def test_multi_sample_renders_use_the_same_sides():
    mesh = _mesh([FRONT, BACK, BEHIND], [False, True, False])
    mixed = render(mesh, CAMERA, mode="solid", light=LIGHT, samples=4)
    one = render(mesh, CAMERA, mode="solid", light=LIGHT)
    both = render(_plain([FRONT, BACK, BEHIND]), CAMERA, mode="solid", light=LIGHT, samples=4, cull="none")
    ids = render(_plain([FRONT, BACK, BEHIND]), CAMERA, mode="solid", cull="none", ids=True).ids
    inside = np.isin(ids, [2, 3])
    inside[1:-1, 1:-1] &= inside[:-2, 1:-1] & inside[2:, 1:-1] & inside[1:-1, :-2] & inside[1:-1, 2:]
    assert inside.sum() > 300
    # inside the double-sided quad (away from its edges) every sample sees it as cull="none" does
    np.testing.assert_array_equal(mixed.color[inside], both.color[inside])
    np.testing.assert_array_equal(mixed.color[inside], one.color[inside])


def test_the_sides_of_a_mixed_mesh_are_per_face_and_validated():
    from rasterkit.raster.triangles import rasterize_triangles

    mesh = _mesh([FRONT, BACK, BEHIND], [False, True, False])
    sides = face_sides(mesh, "front")
    np.testing.assert_array_equal(sides.cull, [2, 2, 0, 0, 2, 2])
    np.testing.assert_array_equal(sides.two_sided, [False, False, True, True, False, False])
    assert face_sides(mesh, "none") == ("none", True)
    assert face_sides(_plain([FRONT]), "back") == ("back", False)
    depth = np.empty((4, 4), np.float32)
    clip = np.zeros((len(VERTICES), 4))
    with pytest.raises(ValueError, match=r"cull must be a name or \(6,\) uint8 cull codes"):
        rasterize_triangles(None, depth, clip, mesh.faces, cull=np.zeros(5, np.uint8))
    with pytest.raises(ValueError, match="cull codes"):
        rasterize_triangles(None, depth, clip, mesh.faces, cull=np.full(6, 3, np.uint8))


def test_a_gltf_material_marked_double_sided_is_seen_from_behind(tmp_path):
    """A glTF file of two quads facing away from the camera, one material double-sided: the
    command line's and the API's render show that one only."""
    b = GltfBuilder()
    for k, double in enumerate((True, False)):
        quad = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.float32) + [k * 1.2 - 1.1, -0.5, 0]
        faces = np.array([0, 2, 1, 0, 3, 2], np.uint16)  # clockwise seen from +z: facing away
        b.add("materials", {"doubleSided": double, "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.5, 0.2, 1]}})
        b.add("meshes", {"primitives": [{"attributes": {"POSITION": b.accessor(quad)},
                                         "indices": b.accessor(faces), "material": k}]})
        b.add("nodes", {"mesh": k})
    b.json["scenes"] = [{"nodes": [0, 1]}]
    path = b.write_glb(tmp_path / "sheets.glb")
    fb = render(load(path), CAMERA, mode="solid", ids=True)
    seen = set(np.unique(fb.ids)) - {-1}
    assert seen == {0, 1}, seen  # the first node's two triangles; the second node is culled


def test_a_double_sided_face_hides_what_is_behind_it_in_an_svg_drawing():
    """A quad facing away, a triangle behind it: the drawing of the double-sided quad is that
    of the same quad turned towards the camera (its edges, none of the triangle's); one-sided,
    the triangle shows through."""
    from rasterkit import render_svg

    vertices = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0],
                         [-0.4, -0.4, -1], [0.4, -0.4, -1], [0, 0.4, -1]], np.float64)
    away, towards, triangle = [[0, 2, 1], [0, 3, 2]], [[0, 1, 2], [0, 2, 3]], [[4, 5, 6]]
    camera = Camera.look_at((0.0, 0.0, 4.0), (0.0, 0.0, 0.0), fov_y=50.0, width=120, height=120)

    def mesh(quad, double):
        materials = (Material(name="quad", double_sided=double), Material(name="triangle"))
        return Mesh(vertices, np.array(quad + triangle), material_names=("quad", "triangle"),
                    materials=materials, face_materials=np.array([0, 0, 1], np.int32))

    double = render_svg(mesh(away, True), camera, "hidden")
    assert double == render_svg(mesh(towards, False), camera, "hidden")
    assert double != render_svg(mesh(away, False), camera, "hidden")
