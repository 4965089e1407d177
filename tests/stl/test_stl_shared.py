"""read_stl on the public STL files of ``../shared/models/formats`` (skipped without them):
the counts of the folder's README, the same vertices and triangles as trimesh once its corners
are welded, its normals, the colours a file has, renders; and the broken files of
``robustness/stl`` end in one clean error."""

import numpy as np
import pytest

import rasterkit
from rasterkit.stl import StlError, read_stl, sniff
from support.paths import MODELS, needs_models
from support.stlfiles import reference_weld

FORMATS = MODELS / "formats"
pytestmark = needs_models

# file: (distinct positions, facets, degenerate facets once welded) from formats/README.md
COUNTS = {"Spider_binary.stl": (722, 1368, 56), "Spider_ascii.stl": (722, 1368, 56),
          "20mm-xyz-cube.stl": (132, 260, 0), "angle_block.STL": (398, 704, 0)}


def shared(name):
    path = FORMATS / "stl" / name
    if not path.is_file():
        pytest.skip(f"{path} is absent")
    return path


@pytest.mark.parametrize("name", sorted(COUNTS))
def test_the_counts_of_the_readme(name):
    mesh = read_stl(shared(name))
    vertices, facets, degenerate = COUNTS[name]
    assert (len(mesh.vertices), len(mesh.faces)) == (vertices, facets - degenerate)
    assert len(mesh.warnings) == (degenerate > 0) + (name.startswith("Spider"))


@pytest.mark.parametrize("name", sorted(COUNTS))
def test_the_vertices_and_triangles_of_trimesh_welded(name):
    trimesh = pytest.importorskip("trimesh")
    theirs = trimesh.load(shared(name), process=False)
    corners = np.asarray(theirs.vertices)[theirs.faces]
    whole = np.array([len({tuple(c) for c in facet}) == 3 for facet in corners.tolist()])  # no two corners equal
    inverse, first = reference_weld(corners[whole].reshape(-1, 3))
    mesh = read_stl(shared(name))
    assert np.array_equal(mesh.vertices, corners[whole].reshape(-1, 3)[first])
    assert np.array_equal(mesh.faces, inverse.reshape(-1, 3))
    normals = np.asarray(theirs.face_normals)[whole]
    ours = mesh.face_normals if mesh.corner_normals is None else mesh.corner_normals[mesh.normal_index[:, 0]]
    assert np.allclose(ours, normals, atol=2e-6)


def test_the_spider_has_every_normal_against_its_winding_so_none_are_kept():
    for name in ("Spider_binary.stl", "Spider_ascii.stl"):
        mesh = read_stl(shared(name))
        assert mesh.corner_normals is None and "1312 point against their facet's winding" in mesh.warnings[1]


def test_the_spider_in_ascii_and_in_binary_is_one_mesh():
    a, b = read_stl(shared("Spider_ascii.stl")), read_stl(shared("Spider_binary.stl"))
    assert np.array_equal(a.faces, b.faces) and np.abs(a.vertices - b.vertices).max() < 1e-6


def test_the_magics_cube_is_grey_and_the_others_have_no_colours():
    cube = read_stl(shared("20mm-xyz-cube.stl"))  # COLOR=a0a0a0ff, every word 0x4e73: 19/31 grey of its own
    assert cube.face_colors.shape == (260, 3) and np.all(cube.face_colors == np.float32(19 / 31))
    for name in ("Spider_binary.stl", "Spider_ascii.stl", "angle_block.STL"):
        assert read_stl(shared(name)).face_colors is None


def test_sniff_tells_each_file():
    for name in COUNTS:
        data = shared(name).read_bytes()
        assert sniff(data[:256], len(data))
        assert sniff(data[:256]) == name.endswith("ascii.stl")


@pytest.mark.parametrize("name", sorted(COUNTS))
def test_each_file_renders(name):
    mesh = read_stl(shared(name))
    center, radius = mesh.bounding_sphere()
    camera = rasterkit.Camera.frame(center, radius, width=64, height=48)
    for mode in ("solid", "hidden"):
        fb = rasterkit.render(mesh, camera, mode=mode)
        drawn = np.any(fb.color != fb.color[0, 0], axis=2)
        assert 0.05 < drawn.mean() < 0.95, (mode, drawn.mean())


def test_the_robustness_files_end_in_one_clean_error():
    files = sorted((FORMATS / "robustness" / "stl").glob("*"))
    assert files, "no robustness files"
    for path in files:
        with pytest.raises(StlError) as info:
            read_stl(path)
        text = str(info.value)
        assert text.startswith(f"{path}: ") and "\n" not in text
    with pytest.raises(StlError, match="is 20 \\(1084 bytes\\), but the file has 584 bytes \\(10 whole facets\\)"):
        read_stl(FORMATS / "robustness" / "stl" / "truncated.stl")
