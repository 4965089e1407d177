"""read_off on the public OFF files of ``../shared/models/formats`` (skipped without them): the
counts of the folder's README, trimesh's vertices and triangles, the colours, renders; and the
broken files of ``robustness/off`` end in one clean error without allocating what their headers
claim."""

import numpy as np
import pytest

import rasterkit
from rasterkit.off import OffError, read_off, sniff
from support.hostile import run_python
from support.paths import MODELS, needs_models

FORMATS = MODELS / "formats"
pytestmark = needs_models

# file: (vertices, polygons, triangles) from formats/README.md (triangles: trimesh's)
COUNTS = {"mushroom.off": (226, 240, 448), "vertcube.off": (8, 6, 12)}


def shared(name):
    path = FORMATS / "off" / name
    if not path.is_file():
        pytest.skip(f"{path} is absent")
    return path


def triangle_set(faces):
    """The triangles, each rotated to start at its smallest index (the winding kept), sorted."""
    faces = np.asarray(faces)
    turn = np.argmin(faces, axis=1)
    rotated = np.stack([faces[np.arange(len(faces)), (turn + k) % 3] for k in range(3)], axis=1)
    return sorted(map(tuple, rotated.tolist()))


@pytest.mark.parametrize("name", sorted(COUNTS))
def test_the_counts_of_the_readme_and_trimeshs_triangles(name):
    mesh = read_off(shared(name))
    vertices, polygons, triangles = COUNTS[name]
    assert (len(mesh.vertices), len(mesh.faces)) == (vertices, triangles) and mesh.warnings == ()
    trimesh = pytest.importorskip("trimesh")
    theirs = trimesh.load(shared(name), process=False)
    assert np.array_equal(mesh.vertices, theirs.vertices)
    assert triangle_set(mesh.faces) == triangle_set(theirs.faces)


def test_the_edges_are_the_polygons_sides():
    mesh = read_off(shared("vertcube.off"))
    assert len(mesh.edges) == 12  # a cube's edges, no diagonals
    lines = [line.split("#")[0].split() for line in shared("mushroom.off").read_text().splitlines()]
    lines = [words for words in lines if words]  # OFF, the counts, 226 vertices, 240 faces
    polygons = [list(map(int, words[1:int(words[0]) + 1])) for words in lines[2 + 226:]]
    assert len(polygons) == 240
    sides = {tuple(sorted((p[k], p[k - 1]))) for p in polygons for k in range(len(p))}
    assert sorted(map(list, sides)) == read_off(shared("mushroom.off")).edges.tolist()


def test_the_colours_of_each_file():
    mushroom = read_off(shared("mushroom.off"))  # every face 1.000000 0.000000 1.000000: floats, magenta
    assert mushroom.face_colors.shape == (448, 3) and np.all(mushroom.face_colors == [1, 0, 1])
    assert mushroom.vertex_colors is None
    cube = read_off(shared("vertcube.off"))  # COFF, r g b 0.75 floats per vertex
    assert cube.face_colors is None and np.allclose(cube.vertex_colors[:2], [[0, 0.8, 0.1], [0.2, 0, 0.8]])


def test_sniff_tells_each_file():
    for name in COUNTS:
        assert sniff(shared(name).read_bytes()[:256])


@pytest.mark.parametrize("name", sorted(COUNTS))
def test_each_file_renders(name):
    mesh = read_off(shared(name))
    center, radius = mesh.bounding_sphere()
    camera = rasterkit.Camera.frame(center, radius, width=64, height=48)
    for mode in ("solid", "solid+wire"):
        fb = rasterkit.render(mesh, camera, mode=mode)
        drawn = np.any(fb.color != fb.color[0, 0], axis=2)
        assert 0.05 < drawn.mean() < 0.95, (mode, drawn.mean())


def test_the_robustness_files_end_in_one_clean_error_in_a_child_with_little_memory():
    folder = FORMATS / "robustness" / "off"
    files = sorted(folder.glob("*.off"))
    assert files
    code = f"""
        import pathlib
        from rasterkit.off import read_off, OffError
        for path in sorted(pathlib.Path({str(folder)!r}).glob("*.off")):
            try:
                read_off(path)
                print("loaded", path)
            except OffError as e:
                print(e)
    """
    done = run_python(code, timeout=120, memory=1 << 30)
    assert done.code == 0, done.describe()
    assert done.stdout.splitlines() == [
        f"{folder}/OutOfMemory.off:2: the header says 353535235358 vertices and 6 faces, but only 14 lines of numbers "
        "follow it (truncated?)",
        f"{folder}/truncated.off:2: the header says 12 vertices and 20 faces, but only 4 lines of numbers follow it "
        "(truncated?)"]
    for path in files:
        with pytest.raises(OffError):
            read_off(path)
