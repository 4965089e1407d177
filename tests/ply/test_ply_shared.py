"""read_ply on the public PLY files of ``../shared/models/formats`` (next to the repository on
the developers' machines; these tests skip without it): counts against the folder's README
(made by a parser of its own), positions, faces, colours, normals and texture coordinates
against plyfile and trimesh when they are installed, a render of each, and the broken files
of ``robustness/ply``, each one clean error."""

import re

import numpy as np
import pytest

import rasterkit
from rasterkit.ply import PlyError, read_ply
from support.paths import MODELS

FORMATS = MODELS / "formats"
PLY_FILES = ("ply/bun_zipper.ply", "ply/cube_blender_uv.ply", "obj/fuze/fuze.ply")

pytestmark = pytest.mark.skipif(not FORMATS.is_dir(), reason=f"{FORMATS} is absent (the shared test models are "
                                                             "not part of the repository)")


def readme_counts() -> dict:
    """{file: (vertices, {corners: faces})} from the table of the folder's README."""
    counts = {}
    for line in (FORMATS / "README.md").read_text().splitlines():
        match = re.match(r"\| `([^`]+\.ply)` \| PLY \| [^|]+ \| (\d+) \| \d+ \(corners per face ([^)]+)\)", line)
        if match:
            sizes = dict(map(int, pair.split(":")) for pair in match[3].split(", "))
            counts[match[1]] = (int(match[2]), sizes)
    return counts


def path_of(name):
    return FORMATS / name


@pytest.mark.parametrize("name", PLY_FILES)
def test_counts_as_the_readme_gives_them(name):
    vertices, sizes = readme_counts()[name]
    mesh = read_ply(path_of(name))
    assert len(mesh.vertices) == vertices
    assert len(mesh.faces) == sum(faces * (corners - 2) for corners, faces in sizes.items())
    assert mesh.warnings == ()


@pytest.mark.parametrize("name", PLY_FILES)
def test_positions_faces_and_attributes_as_plyfile_reads_them(name):
    plyfile = pytest.importorskip("plyfile")
    data = plyfile.PlyData.read(str(path_of(name)))
    vertex, face = data["vertex"].data, data["face"].data
    mesh = read_ply(path_of(name))
    np.testing.assert_array_equal(mesh.vertices, np.stack([vertex[c] for c in "xyz"], axis=1).astype(np.float64))
    polygons = [list(p) for p in face["vertex_indices"]]
    if all(len(p) == 3 for p in polygons):
        assert mesh.faces.tolist() == polygons
    else:  # convex quads: fans from their first corner
        assert mesh.faces.tolist() == [[p[0], p[k], p[k + 1]] for p in polygons for k in range(1, len(p) - 1)]
    sides = {tuple(sorted((p[k - 1], p[k]))) for p in polygons for k in range(len(p))}
    assert mesh.edges.tolist() == sorted(map(list, sides))
    names = vertex.dtype.names
    if "red" in names:
        np.testing.assert_array_equal(mesh.vertex_colors, np.stack([vertex[c] for c in ("red", "green", "blue")],
                                                                   axis=1) / np.float32(255))
    if "nx" in names:
        normals = np.stack([vertex[c] for c in ("nx", "ny", "nz")], axis=1).astype(np.float64)
        np.testing.assert_allclose(mesh.normals, normals / np.linalg.norm(normals, axis=1, keepdims=True))
    if "s" in names:
        np.testing.assert_array_equal(mesh.texcoords, np.stack([vertex["s"], vertex["t"]], axis=1))
    if "red" in face.dtype.names:
        np.testing.assert_array_equal(mesh.face_colors, np.stack([face[c] for c in ("red", "green", "blue")],
                                                                 axis=1) / np.float32(255))
    if "texcoord" in face.dtype.names:
        corners = np.concatenate(list(face["texcoord"])).reshape(-1, 2).astype(np.float64)
        np.testing.assert_array_equal(mesh.uv[mesh.uv_index], corners.reshape(-1, 3, 2))


@pytest.mark.parametrize("name", PLY_FILES)
def test_each_face_corner_where_trimesh_has_it(name):
    """trimesh splits vertices at texture seams (fuze: 664) and triangulates quads: each
    triangle's corner positions (and texture coordinates) are compared, up to the order
    of the triangles."""
    trimesh = pytest.importorskip("trimesh")
    theirs = trimesh.load(path_of(name), process=False)
    mesh = read_ply(path_of(name))

    def triangles(vertices, faces):
        """Each triangle's corners from its smallest one (a rotation keeps the winding)."""
        corners = np.asarray(vertices)[np.asarray(faces)].tolist()
        return sorted(tuple(sum(t[t.index(min(t)):] + t[:t.index(min(t))], [])) for t in corners)

    assert triangles(mesh.vertices, mesh.faces) == triangles(theirs.vertices, theirs.faces)
    uv = getattr(theirs.visual, "uv", None)
    if uv is not None and mesh.uv is not None:
        ours = np.concatenate([mesh.vertices[mesh.faces], mesh.uv[mesh.uv_index]], axis=2)
        them = np.concatenate([theirs.vertices[theirs.faces], uv[theirs.faces]], axis=2)
        assert triangles(ours.reshape(-1, 5), np.arange(ours.size // 5).reshape(-1, 3)) == \
            triangles(them.reshape(-1, 5), np.arange(them.size // 5).reshape(-1, 3))


def test_fuze_has_its_texture():
    mesh = read_ply(path_of("obj/fuze/fuze.ply"))
    assert mesh.material_names == ("fuze uv.jpg",)
    texture = mesh.materials[0].diffuse_map
    assert texture.image.shape == (1024, 1024, 3) and texture.name.endswith("fuze uv.jpg")
    assert (mesh.face_materials == 0).all() and (mesh.uv_index >= 0).all()


@pytest.mark.parametrize("name", PLY_FILES)
def test_each_renders(name):
    mesh = read_ply(path_of(name))
    centre, radius = mesh.bounding_sphere()
    camera = rasterkit.Camera.frame(centre, radius, width=48, height=32)
    fb = rasterkit.render(mesh, camera, mode="solid", background="black")
    drawn = fb.color.any(axis=2)
    assert 0.1 < drawn.mean() < 0.95
    if mesh.materials:  # the texture draws: not what the faces' own colours give
        plain = rasterkit.render(mesh, camera, mode="solid", background="black", textures=False)
        assert (plain.color != fb.color).any(axis=2).sum() > drawn.sum() / 2


def test_the_robustness_file_ends_in_one_clean_error():
    files = sorted((FORMATS / "robustness" / "ply").glob("*.ply"))
    assert [f.name for f in files] == ["corrupted_invalid_vertex_count.ply"]
    with pytest.raises(PlyError) as caught:
        read_ply(files[0])
    # 14 vertices declared, 12 there: faces read from the wrong place run out of data
    assert str(caught.value) == (f"{files[0]}: element 'face' row 19 (byte 2163): the file ends inside the row "
                                 "(the header declares 20 rows)")
