"""Per-corner attributes and per-face materials of a Mesh (issue 27): ``uv`` / ``uv_index``,
``corner_normals`` / ``normal_index``, ``face_materials`` / ``materials``, checked and sealed
like the other arrays, per-vertex data as ``uv_index = faces``, pickled, replaced, counted
in memory, and brought by trimesh meshes."""

from __future__ import annotations

import dataclasses
import pickle

import numpy as np
import pytest

from rasterkit import limits, shapes
from rasterkit.limits import LimitError
from rasterkit.material import DEFAULT_DIFFUSE, Material, Texture
from rasterkit.mesh import Mesh, as_mesh, immutable, mesh_bytes
from rasterkit.mesh.foreign import TRIMESH_UNSET_DIFFUSE

#: A unit square of two triangles whose vertex 0 has two texture coordinates (a seam).
SQUARE = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
FACES = np.array([[0, 1, 2], [0, 2, 3]])
UV = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.5]])
UV_INDEX = np.array([[0, 1, 2], [4, 2, 3]])


def textured(**changes) -> Mesh:
    fields = dict(uv=UV, uv_index=UV_INDEX, corner_normals=[[0, 0, 1], [0, 0, -1]],
                  normal_index=[[0, 0, 0], [1, 1, 1]], face_materials=[1, -1], material_names=("a", "b"),
                  materials=("A", "B"))
    fields.update(changes)
    return Mesh(SQUARE, FACES, **fields)


def test_corners_keep_their_own_rows_and_the_arrays_are_sealed():
    uv_index = UV_INDEX.copy()
    mesh = textured(uv_index=uv_index)
    uv_index[1, 0] = 0  # the Mesh copied it
    assert mesh.uv[mesh.uv_index].tolist() == [[[0, 0], [1, 0], [1, 1]], [[0.5, 0.5], [1, 1], [0, 1]]]
    assert mesh.corner_normals[mesh.normal_index][:, :, 2].tolist() == [[1, 1, 1], [-1, -1, -1]]
    assert mesh.face_materials.tolist() == [1, -1] and mesh.face_materials.dtype == np.int32
    assert mesh.materials == ("A", "B")
    for name, dtype, shape in [("uv", np.float64, (5, 2)), ("uv_index", np.int64, (2, 3)),
                               ("corner_normals", np.float64, (2, 3)), ("normal_index", np.int64, (2, 3)),
                               ("face_materials", np.int32, (2,))]:
        arr = getattr(mesh, name)
        assert arr.dtype == dtype and arr.shape == shape and immutable(arr), name
    assert mesh.texcoords is None and mesh.normals is None  # the per-vertex fields are apart


def test_a_face_without_texture_coordinates_is_a_row_of_minus_ones():
    mesh = textured(uv_index=[[0, 1, 2], [-1, -1, -1]])
    assert mesh.uv_index[1].tolist() == [-1, -1, -1]


def test_per_vertex_data_is_uv_index_equal_to_faces():
    per_vertex = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    mesh = Mesh(SQUARE, FACES, uv=per_vertex, corner_normals=np.tile([0, 0, 1.0], (4, 1)))
    explicit = Mesh(SQUARE, FACES, uv=per_vertex, uv_index=FACES.copy(), corner_normals=np.tile([0, 0, 1.0], (4, 1)),
                    normal_index=FACES.copy())
    assert mesh.uv_index is mesh.faces and mesh.normal_index is mesh.faces  # one array, not a copy
    for name in ("uv", "uv_index", "corner_normals", "normal_index"):
        assert np.array_equal(getattr(mesh, name), getattr(explicit, name)), name
    assert np.array_equal(mesh.uv[mesh.uv_index], per_vertex[FACES])
    assert mesh.nbytes == explicit.nbytes - 2 * FACES.size * 8  # the shared index is counted once
    with pytest.raises(ValueError, match=r"uv has 5 rows and no uv_index: .* one row per vertex \(4\)"):
        Mesh(SQUARE, FACES, uv=UV)


def test_texture_coordinates_may_be_any_float_but_normals_must_be_finite():
    wild = np.array([[np.nan, 0], [np.inf, -np.inf], [1e300, -1e300], [0, 1], [2, 3]])
    assert np.array_equal(textured(uv=wild).uv, wild, equal_nan=True)
    with pytest.raises(ValueError, match=r"corner_normals\[1\] is \[0.0, nan, 1.0\]: normals must be finite"):
        textured(corner_normals=[[0, 0, 1], [0, np.nan, 1]])


@pytest.mark.parametrize("changes, error, message", [
    (dict(uv_index=[[0, 1, 2], [4, 2, 5]]), ValueError, r"uv_index\[1\] is \[4, 2, 5\]: .* rows of uv \[0, 5\)"),
    (dict(uv_index=[[0, 1, 2], [-1, 2, 3]]), ValueError, r"uv_index\[1\] .* or -1, -1, -1 for a face without"),
    (dict(uv_index=[[0, 1, 2], [-2, -2, -2]]), ValueError, r"uv_index\[1\]"),
    (dict(uv_index=[[0, 1], [2, 3]]), ValueError, r"uv_index must have shape \(N, 3\)"),
    (dict(uv_index=[[0, 1, 2]]), ValueError, r"uv_index must have 2 rows, got 1"),
    (dict(uv_index=[[0.0, 1, 2], [4, 2, 3]]), TypeError, r"uv_index must hold integers"),
    (dict(uv_index=np.array([[0, 1, 2], [2**64 - 1] * 3], np.uint64)), ValueError,
     r"uv_index is out of range: .* rows of uv \[0, 5\)"),
    (dict(uv=None), ValueError, r"uv_index is given without uv"),
    (dict(uv=np.zeros((5, 3))), ValueError, r"uv must have shape \(N, 2\)"),
    (dict(uv=[["a", "b"]] * 5), TypeError, r"uv must hold real numbers"),
    (dict(normal_index=[[0, 0, 0], [1, 1, 2]]), ValueError, r"normal_index\[1\] .* rows of corner_normals \[0, 2\)"),
    (dict(corner_normals=None), ValueError, r"normal_index is given without corner_normals"),
    (dict(face_materials=[2, 0]), ValueError, r"face_materials must be \(M,\) \[-1, 2\) into material_names"),
    (dict(face_materials=[0, -2]), ValueError, r"face_materials must be"),
    (dict(face_materials=[0]), ValueError, r"face_materials must be"),
    (dict(face_materials=[0.0, 1.0]), TypeError, r"face_materials must hold integers"),
    (dict(face_materials=[0, 0], material_names=()), ValueError, r"face_materials must be"),
    (dict(materials=("A",)), ValueError, r"materials must be empty or one for each of material_names \(2\), got 1"),
])
def test_bad_corner_arrays_are_refused_naming_the_field(changes, error, message):
    with pytest.raises(error, match=message):
        textured(**changes)


def test_a_mesh_without_materials_objects_or_names_is_fine():
    mesh = textured(materials=())
    assert mesh.materials == () and mesh.material_names == ("a", "b")
    assert Mesh(SQUARE, FACES, face_materials=[-1, -1]).face_materials.tolist() == [-1, -1]


def test_pickling_and_replace_keep_every_corner_array():
    mesh = textured()
    for copy in (pickle.loads(pickle.dumps(mesh)), dataclasses.replace(mesh, vertices=SQUARE * 2)):
        for name in ("uv", "uv_index", "corner_normals", "normal_index", "face_materials"):
            assert np.array_equal(getattr(copy, name), getattr(mesh, name)), name
            assert immutable(getattr(copy, name)), name
        assert copy.materials == ("A", "B") and copy.material_names == ("a", "b")
    per_vertex = pickle.loads(pickle.dumps(Mesh(SQUARE, FACES, uv=UV[:4])))
    assert per_vertex.uv_index is per_vertex.faces


def test_check_intact_catches_a_changed_corner_array():
    mesh = textured()
    mesh.uv_index.shape = (3, 2)
    with pytest.raises(ValueError, match="Mesh.uv_index was changed"):
        mesh.check_intact()
    mesh = textured()
    object.__setattr__(mesh, "face_materials", np.zeros(2, np.int32))
    with pytest.raises(ValueError, match="Mesh.face_materials was changed"):
        mesh.check_intact()


def test_memory_counts_the_corner_arrays():
    plain, mesh = Mesh(SQUARE, FACES), textured()
    extra = UV.nbytes + UV_INDEX.nbytes * 2 + 2 * 3 * 8 + 2 * 4  # uv, both indices, normals, materials
    assert mesh.nbytes - plain.nbytes == extra
    assert mesh_bytes(4, 2, 5, n_uv=5, n_corner_normals=2, corner_indices=2) - mesh_bytes(4, 2, 5) == \
        5 * 2 * 16 + 2 * 2 * 24 + 2 * 2 * (2 * 24 + 32)


def test_a_corner_table_beyond_the_memory_limit_is_refused_before_it_is_copied():
    n_faces = 1000
    faces = np.zeros((n_faces, 3), np.int64)
    plain = mesh_bytes(3, n_faces, 0)  # no edges given: the Mesh works them out when they are first needed
    limits.set_memory_limit(plain + 1000)
    try:
        Mesh(np.zeros((3, 3)), faces)
        with pytest.raises(LimitError, match="a Mesh of 3 vertices and 1000 faces"):
            Mesh(np.zeros((3, 3)), faces, uv=np.zeros((1, 2)), uv_index=faces)
    finally:
        limits.set_memory_limit(None)


def test_a_jobs_memory_counts_the_corner_arrays(tmp_path):
    from rasterkit.batch.api import task_for
    from rasterkit.batch.job_memory import job_bytes

    sphere = shapes.icosphere(2)
    uv = np.random.default_rng(1).random((3 * len(sphere.faces), 2))
    corners = np.arange(uv.shape[0]).reshape(-1, 3)
    mesh = dataclasses.replace(sphere, uv=uv, uv_index=corners, face_materials=np.zeros(len(sphere.faces), np.int32),
                               material_names=("m",))
    task = task_for(turntable=None, changes=dict(size=(64, 48)))
    camera = task.view.camera_for(sphere)
    plain, more = (job_bytes(m, camera, task, tmp_path / "a.png") for m in (sphere, mesh))
    assert more - plain == uv.nbytes + corners.nbytes + 4 * len(sphere.faces)


# --- trimesh -------------------------------------------------------------------------------

def test_a_trimesh_with_a_texture_brings_its_uv_and_a_material():
    trimesh = pytest.importorskip("trimesh")
    from PIL import Image

    box = trimesh.creation.box()
    uv = np.random.default_rng(2).random((len(box.vertices), 2))
    pixels = np.random.default_rng(3).integers(0, 256, (4, 6, 3), dtype=np.uint8)
    box.visual = trimesh.visual.TextureVisuals(uv=uv, image=Image.fromarray(pixels))
    mesh = as_mesh(box)
    assert np.array_equal(mesh.uv, uv) and mesh.uv_index is mesh.faces
    assert np.array_equal(mesh.faces, box.faces)
    (material,) = mesh.materials
    assert isinstance(material, Material) and mesh.material_names == (material.name,)
    texture = material.diffuse_map
    assert isinstance(texture, Texture) and np.array_equal(texture.image, pixels) and immutable(texture.image)
    assert texture.srgb and material.textures == (texture,)
    # trimesh gave no colour (it stores its grey default): the image is drawn as it is
    assert box.visual.material.diffuse.tolist() == list(TRIMESH_UNSET_DIFFUSE)
    assert (material.diffuse, material.opacity) == ((1.0, 1.0, 1.0), 1.0)
    assert mesh.face_materials.tolist() == [0] * len(box.faces)


def test_trimesh_leaves_that_grey_when_it_gives_no_diffuse():
    trimesh = pytest.importorskip("trimesh")
    assert tuple(trimesh.visual.color.DEFAULT_COLOR.tolist()) == TRIMESH_UNSET_DIFFUSE
    assert tuple(trimesh.visual.material.SimpleMaterial().diffuse.tolist()) == TRIMESH_UNSET_DIFFUSE


def test_a_trimesh_simple_material_brings_its_diffuse_colour_and_alpha():
    trimesh = pytest.importorskip("trimesh")
    from PIL import Image

    box = trimesh.creation.box()
    uv = np.zeros((len(box.vertices), 2))
    image = Image.fromarray(np.full((2, 2, 3), 200, np.uint8))
    for diffuse, image, expected in [([255, 51, 0, 102], image, ((1.0, 0.2, 0.0), 0.4)),
                                     # trimesh keeps colours as uint8 codes
                                     ([0.5, 0.25, 1.0], image, ((128 / 255, 64 / 255, 1.0), 1.0)),
                                     # the grey trimesh stores when given none is a colour without an image
                                     (None, None, ((0.4, 0.4, 0.4), 1.0))]:
        material = trimesh.visual.material.SimpleMaterial(image=image, diffuse=diffuse, name="m")
        box.visual = trimesh.visual.TextureVisuals(uv=uv, material=material)
        (got,) = as_mesh(box).materials
        assert got.name == "m" and got.diffuse == pytest.approx(expected[0]) and got.opacity == pytest.approx(expected[1])
        assert (got.diffuse_map is None) == (image is None)


def test_a_trimesh_pbr_material_brings_its_base_colour_texture_and_factor():
    trimesh = pytest.importorskip("trimesh")
    from PIL import Image

    box = trimesh.creation.box()
    uv = np.zeros((len(box.vertices), 2))
    pixels = np.random.default_rng(4).integers(0, 256, (3, 5, 4), dtype=np.uint8)
    texture = Image.fromarray(pixels, "RGBA")
    cases = [(texture, [255, 0, 0, 153], (1.0, 0.0, 0.0), 0.6), (texture, None, (1.0, 1.0, 1.0), 1.0),
             (None, [0, 0, 255, 255], (0.0, 0.0, 1.0), 1.0), (None, None, DEFAULT_DIFFUSE, 1.0)]
    for image, factor, diffuse, opacity in cases:
        material = trimesh.visual.material.PBRMaterial(name="paint", baseColorTexture=image, baseColorFactor=factor)
        box.visual = trimesh.visual.TextureVisuals(uv=uv, material=material)
        (got,) = as_mesh(box).materials
        assert got.name == "paint" and got.diffuse == pytest.approx(diffuse) and got.opacity == pytest.approx(opacity)
        if image is None:
            assert got.diffuse_map is None
        else:
            assert got.diffuse_map.channels == 4 and np.array_equal(got.diffuse_map.image, pixels)


def test_a_palette_image_with_transparency_becomes_rgba():
    trimesh = pytest.importorskip("trimesh")
    from PIL import Image

    image = Image.new("P", (2, 1))
    image.putpalette([255, 0, 0, 0, 0, 255])
    image.putpixel((1, 0), 1)
    image.info["transparency"] = 1
    box = trimesh.creation.box()
    box.visual = trimesh.visual.TextureVisuals(uv=np.zeros((len(box.vertices), 2)), image=image)
    (material,) = as_mesh(box).materials
    assert material.diffuse_map.image.tolist() == [[[255, 0, 0, 255], [0, 0, 255, 0]]]


def test_a_trimesh_multi_material_gives_each_face_its_own():
    trimesh = pytest.importorskip("trimesh")
    box = trimesh.creation.box()
    parts = [trimesh.visual.material.PBRMaterial(name="red", baseColorFactor=[255, 0, 0, 255]),
             trimesh.visual.material.PBRMaterial(baseColorFactor=[0, 255, 0, 255])]
    chosen = np.arange(len(box.faces)) % 2
    box.visual = trimesh.visual.TextureVisuals(uv=np.zeros((len(box.vertices), 2)),
                                               material=trimesh.visual.material.MultiMaterial(parts),
                                               face_materials=chosen)
    mesh = as_mesh(box)
    assert mesh.material_names == ("red", "material_1")
    assert [m.diffuse for m in mesh.materials] == [(1.0, 0.0, 0.0), (0.0, 1.0, 0.0)]
    assert mesh.face_materials.tolist() == chosen.tolist()


def test_a_trimesh_with_colours_brings_them_and_one_without_brings_none():
    trimesh = pytest.importorskip("trimesh")
    box = trimesh.creation.box()
    plain = as_mesh(box)
    assert plain.vertex_colors is None and plain.face_colors is None and plain.uv is None
    colours = np.random.default_rng(5).integers(0, 256, (len(box.vertices), 4), dtype=np.uint8)
    box.visual.vertex_colors = colours
    assert np.allclose(as_mesh(box).vertex_colors, colours[:, :3] / 255.0)
    box = trimesh.creation.box()
    colours = np.random.default_rng(6).integers(0, 256, (len(box.faces), 4), dtype=np.uint8)
    box.visual.face_colors = colours
    mesh = as_mesh(box)
    assert np.allclose(mesh.face_colors, colours[:, :3] / 255.0) and mesh.vertex_colors is None


@pytest.mark.parametrize("kind", ["vertex", "face"])
def test_colours_of_a_ply_file_read_by_trimesh(tmp_path, kind):
    trimesh = pytest.importorskip("trimesh")
    box = trimesh.creation.box()
    rows = len(box.vertices) if kind == "vertex" else len(box.faces)
    colours = np.random.default_rng(7).integers(0, 256, (rows, 4), dtype=np.uint8)
    colours[:, 3] = 255
    setattr(box.visual, f"{kind}_colors", colours)
    box.export(tmp_path / "box.ply")
    loaded = trimesh.load(tmp_path / "box.ply", process=False)
    assert loaded.visual.kind == kind
    mesh = as_mesh(loaded)
    assert np.array_equal(getattr(mesh, f"{kind}_colors"), (colours[:, :3] / 255.0).astype(np.float32))
    assert mesh.uv is None and mesh.materials == ()


def test_trimesh_reads_of_the_fuze_bottle_keep_its_texture(models_dir):
    """trimesh and load_obj read fuze.obj (v/vt/vn, map_Kd "fuze uv.jpg", Kd 1 1 1) alike: the
    same texture coordinates at every face corner (trimesh gives v up, as rasterkit does),
    the same texture pixels and diffuse colour."""
    trimesh = pytest.importorskip("trimesh")
    import rasterkit

    folder = models_dir / "formats" / "obj" / "fuze"
    if not folder.is_dir():
        pytest.skip(f"{folder} is absent")
    loaded = trimesh.load(folder / "fuze.obj", force="mesh", process=False)
    mesh = as_mesh(loaded)
    assert mesh.uv.shape == (len(mesh.vertices), 2) and np.array_equal(mesh.uv, loaded.visual.uv)
    obj = rasterkit.load_obj(folder / "fuze.obj", textures=True)
    assert np.array_equal(mesh.vertices[mesh.faces], obj.vertices[obj.faces])
    assert np.array_equal(mesh.uv[mesh.uv_index], obj.uv[obj.uv_index])
    ((material,), (expected,)) = mesh.materials, obj.materials
    assert material.diffuse_map.image.shape == (1024, 1024, 3) and material.diffuse == expected.diffuse == (1.0, 1.0, 1.0)
    assert np.array_equal(material.diffuse_map.image, expected.diffuse_map.image)
    with __import__("PIL.Image").Image.open(folder / "fuze uv.jpg") as image:
        assert np.array_equal(material.diffuse_map.image, np.asarray(image.convert("RGB")))


@pytest.mark.parametrize("path", ["spot.obj", "formats/obj/african_head/african_head.obj"])
def test_trimesh_and_load_obj_agree_on_the_uv_of_every_corner(models_dir, path):
    """Models without a library: trimesh splits their vertices at UV seams, rasterkit keeps a
    table of rows; at every face corner the two give the same position and (u, v)."""
    trimesh = pytest.importorskip("trimesh")
    import rasterkit

    if not (models_dir / path).is_file():
        pytest.skip(f"{models_dir / path} is absent")
    mesh = as_mesh(trimesh.load(models_dir / path, force="mesh", process=False))
    obj = rasterkit.load_obj(models_dir / path)
    assert len(mesh.vertices) > len(obj.vertices)  # trimesh split the seams
    assert np.array_equal(mesh.vertices[mesh.faces], obj.vertices[obj.faces])
    assert np.array_equal(mesh.uv[mesh.uv_index], obj.uv[obj.uv_index])
