"""Every model format on the command line: ``render`` and ``info`` take STL, OFF, PLY (meshes and
point clouds) and glTF as they take OBJ, a folder batch picks up every known extension,
``--camera gltf`` uses the file's camera, and a broken file is one line with exit code 2."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

import rasterkit
from rasterkit.cli import main
from support.gltffiles import GltfBuilder

from api.test_load_formats import CLOUD_PLY, SQUARE_OFF, SQUARE_PLY, TETRA_STL


def _cube_glb(path, camera: bool):
    """A unit cube on one node, and (``camera``) a perspective camera node at (0, 0, 4)
    looking down -Z at it."""
    cube = rasterkit.shapes.cube()
    b = GltfBuilder()
    pos = b.accessor(cube.vertices.astype(np.float32))
    idx = b.accessor(cube.faces.astype(np.uint16).ravel())
    nodes = [b.node(mesh=b.mesh({"attributes": {"POSITION": pos}, "indices": idx}))]
    if camera:
        b.add("cameras", {"type": "perspective", "perspective": {"yfov": 0.6, "znear": 0.1, "zfar": 100}})
        nodes.append(b.node(camera=0, translation=[0, 0, 4]))
    b.scene(*nodes)
    return b.write_glb(path)


@pytest.fixture
def models(tmp_path):
    folder = tmp_path / "models"
    folder.mkdir()
    (folder / "tetra.stl").write_text(TETRA_STL)
    (folder / "square.off").write_text(SQUARE_OFF)
    (folder / "square.ply").write_text(SQUARE_PLY)
    (folder / "cloud.ply").write_text(CLOUD_PLY)
    _cube_glb(folder / "cube.glb", camera=True)
    (folder / "notes.txt").write_text("not a model")
    return folder


def _drawn(path) -> int:
    """Pixels of an image that are not the white background."""
    image = np.asarray(Image.open(path).convert("RGB"))
    return int((image != 255).any(axis=2).sum())


@pytest.mark.parametrize("name", ["tetra.stl", "square.off", "square.ply", "cloud.ply", "cube.glb"])
def test_render_draws_each_format(models, tmp_path, name):
    out = tmp_path / f"{name}.png"
    flags = ["--point-size", "6"] if name == "cloud.ply" else []
    assert main(["render", str(models / name), "-o", str(out), "--mode", "solid", "--size", "96x72", *flags]) == 0
    assert _drawn(out) > 30


def test_a_point_cloud_draws_its_own_colours_and_spins_in_a_turntable(models, tmp_path):
    out = tmp_path / "cloud.png"
    assert main(["render", str(models / "cloud.ply"), "-o", str(out), "--size", "96x72", "--point-size", "8"]) == 0
    colours = {tuple(c) for c in np.asarray(Image.open(out).convert("RGB")).reshape(-1, 3)}
    assert {(255, 0, 0), (0, 255, 0), (0, 0, 255)} <= colours
    spin = tmp_path / "spin.gif"
    assert main(["render", str(models / "cloud.ply"), "-o", str(spin), "--size", "64x48", "--turntable", "3",
                 "--point-size", "6"]) == 0
    with Image.open(spin) as gif:
        frames = []
        for k in range(gif.n_frames):
            gif.seek(k)
            frames.append(np.asarray(gif.convert("RGB")))
    assert len(frames) == 3 and not np.array_equal(frames[0], frames[1])


def test_a_folder_batch_renders_every_model_format_and_skips_other_files(models, tmp_path):
    (models / "square.ply").rename(models / "plain.PLY")  # extensions in any case
    out = tmp_path / "out"
    assert main(["render", str(models), "-o", str(out), "--size", "64x48", "--mode", "solid"]) == 0
    images = sorted(out.glob("*.png"))
    assert [p.name for p in images] == ["cloud.png", "cube.png", "plain.png", "square.png", "tetra.png"]
    assert all(_drawn(p) >= (3 if p.name == "cloud.png" else 30) for p in images)  # a 1-pixel point each


def test_two_models_of_one_name_in_a_folder_are_refused_before_anything_renders(models, tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["render", str(models), "-o", str(out), "--size", "64x48"]) == 2
    assert "would both be written to" in capsys.readouterr().err
    assert not out.exists() or not any(out.iterdir())


def test_info_names_each_format(models, capsys):
    assert main(["info", *(str(models / n) for n in ("tetra.stl", "square.off", "square.ply", "cloud.ply",
                                                      "cube.glb"))]) == 0
    text = capsys.readouterr().out
    for line in ("format    STL", "format    OFF", "format    PLY", "format    PLY point cloud", "format    glTF 2.0",
                 "points    3", "triangles 12"):
        assert line in text, line


def test_camera_gltf_renders_through_the_files_camera(models, tmp_path, capsys):
    scene = rasterkit.load(models / "cube.glb")
    from rasterkit.gltf import camera_of

    expected = rasterkit.render(scene, camera_of(scene, 80, 60), "solid")
    out = tmp_path / "cube.png"
    assert main(["render", str(models / "cube.glb"), "-o", str(out), "--size", "80x60", "--mode", "solid",
                 "--camera", "gltf"]) == 0
    np.testing.assert_array_equal(np.asarray(Image.open(out).convert("RGB")), expected.color)
    plain = tmp_path / "plain.glb"
    _cube_glb(plain, camera=False)
    assert main(["render", str(plain), "-o", str(tmp_path / "x.png"), "--camera", "gltf"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and str(plain) in err[0] and "camera node" in err[0]


@pytest.mark.parametrize("name, text", [("broken.stl", "solid x\nfacet normal 0 0 1\n outer loop\n vertex 0 0\n"),
                                        ("broken.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n"),
                                        ("broken.ply", "ply\nformat ascii 1.0\nelement vertex 9\nend_header\n"),
                                        ("broken.gltf", '{"asset": {"version": "2.0"}, "nodes": 3}')])
def test_a_broken_file_is_one_line_and_exit_code_2(tmp_path, capsys, name, text):
    path = tmp_path / name
    path.write_text(text)
    assert main(["render", str(path), "-o", str(tmp_path / "x.png")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and str(path) in err[0], err
    assert not (tmp_path / "x.png").exists()


def test_a_gltf_files_own_warnings_are_printed(tmp_path, capsys):
    from support.gltffiles import triangle_builder

    builder = triangle_builder()
    builder.json["extensionsUsed"] = ["EXT_made_up"]
    path = builder.write_glb(tmp_path / "warned.glb")
    assert main(["render", str(path), "-o", str(tmp_path / "x.png"), "--size", "32x24"]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"rasterkit: warning: {path}: extensionsUsed: uses extension 'EXT_made_up', which rasterkit ignores"]


def test_a_gltf_scenes_points_are_drawn_with_its_faces_and_spun_in_a_turntable(tmp_path, capsys):
    """A cube with three coloured points beside it (a mode-0 primitive): the command line
    draws the points in their colours, as the API does with ``points=``, and spins them
    with the cube."""
    cube = rasterkit.shapes.cube()
    b = GltfBuilder()
    pos = b.accessor(cube.vertices.astype(np.float32))
    idx = b.accessor(cube.faces.astype(np.uint16).ravel())
    dots = b.accessor(np.array([[1.2, 0.4, 0], [1.2, 0, 0], [1.2, -0.4, 0]], np.float32))
    colors = b.accessor(np.array([[255, 0, 0], [0, 255, 0], [0, 0, 255]], np.uint8), np.uint8, normalized=True)
    b.scene(b.node(mesh=b.mesh({"attributes": {"POSITION": pos}, "indices": idx},
                               {"attributes": {"POSITION": dots, "COLOR_0": colors}, "mode": 0})))
    path = b.write_glb(tmp_path / "dots.glb")
    out = tmp_path / "dots.png"
    flags = ["--size", "96x72", "--point-size", "5", "--azimuth", "0", "--elevation", "0"]
    assert main(["render", str(path), "-o", str(out), "--mode", "solid", *flags]) == 0
    image = np.asarray(Image.open(out).convert("RGB"))
    colours = {tuple(c) for c in image.reshape(-1, 3)}
    assert {(255, 0, 0), (0, 255, 0), (0, 0, 255)} <= colours
    scene = rasterkit.load(path)
    camera = rasterkit.View(size=(96, 72), azimuth=0, elevation=0).frame(scene)[0]
    api = rasterkit.render(scene.world_mesh(), camera, mode="solid", point_size=5, points=scene.points,
                           point_color=scene.point_colors.astype(np.float32))
    assert np.array_equal(api.color, image)
    assert main(["info", str(path)]) == 0
    assert "  points    3" in capsys.readouterr().out
    spin = tmp_path / "dots.gif"
    assert main(["render", str(path), "-o", str(spin), "--turntable", "4", *flags]) == 0
    with Image.open(spin) as gif:
        gif.seek(2)  # half a turn: the points are on the other side of the cube
        half = np.asarray(gif.convert("RGB"))
    red = np.argwhere((half == [255, 0, 0]).all(axis=2))
    first = np.argwhere((image == [255, 0, 0]).all(axis=2))
    assert len(red) and len(first) and np.sign(red[:, 1].mean() - 48) == -np.sign(first[:, 1].mean() - 48)
