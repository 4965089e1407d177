"""The command line: the walking skeleton end to end, and one-line errors with exit code 2."""

import os
import subprocess
import sys

import numpy as np
import pytest
from PIL import Image

from rasterkit.runtime.notice import MESSAGE
from rasterkit.cli import main

CUBE_OBJ = """\
v -1 -1 -1
v  1 -1 -1
v  1  1 -1
v -1  1 -1
v -1 -1  1
v  1 -1  1
v  1  1  1
v -1  1  1
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 2 3 7 6
f 3 4 8 7
f 4 1 5 8
"""


@pytest.fixture
def cube_obj(tmp_path):
    path = tmp_path / "cube.obj"
    path.write_text(CUBE_OBJ)
    return path


def _run(argv, capsys):
    code = main([str(a) for a in argv])
    captured = capsys.readouterr()
    # with a cold kernel cache, the first compile in this process adds the notice line
    # (tests/cli/test_cli_startup.py tests it)
    return code, captured.err.replace(MESSAGE + "\n", "")


def test_render_obj_writes_a_png_of_the_requested_size(cube_obj, tmp_path, capsys):
    out = tmp_path / "cube.png"
    code, err = _run(["render", cube_obj, "-o", out, "--size", "120x90"], capsys)
    assert code == 0, err
    with Image.open(out) as im:
        pixels = np.asarray(im)
    assert pixels.shape == (90, 120, 3)
    drawn = np.all(pixels == 0, axis=2)  # black lines on white
    assert np.all((pixels == 0) | (pixels == 255))
    ys, xs = np.nonzero(drawn)
    # framed: the model is in the middle and fills most of the height, touching no border
    assert 0 < xs.min() and xs.max() < 119 and 0 < ys.min() and ys.max() < 89
    assert ys.max() - ys.min() > 0.6 * 90
    # perspective makes the near corner larger, so the outline is only roughly centred
    assert abs((xs.min() + xs.max()) / 2 - 60) < 12 and abs((ys.min() + ys.max()) / 2 - 45) < 12


def test_wire_render_of_a_quad_model_draws_no_triangulation_diagonals(cube_obj, tmp_path, capsys):
    """A cube seen face-on shows a square outline, not the quads' diagonals."""
    out = tmp_path / "front.png"
    code, err = _run(["render", cube_obj, "-o", out, "--size", "101x101",
                      "--azimuth", "0", "--elevation", "0"], capsys)
    assert code == 0, err
    with Image.open(out) as im:
        drawn = np.all(np.asarray(im) == 0, axis=2)
    ys, xs = np.nonzero(drawn)
    cx, cy = (xs.min() + xs.max()) // 2, (ys.min() + ys.max()) // 2
    # the square's interior is empty except for the back face's outline (a smaller square)
    assert not drawn[cy - 2:cy + 3, cx - 2:cx + 3].any()


def test_demo_needs_no_file(tmp_path, capsys):
    out = tmp_path / "demo.png"
    code, err = _run(["render", "--demo", "-o", out, "--size", "64x48"], capsys)
    assert code == 0, err
    with Image.open(out) as im:
        assert im.size == (64, 48) and np.asarray(im).min() == 0


@pytest.mark.parametrize("content, where", [
    ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", ":4:"),     # index out of range
    ("v 0 0 0\nv 1 0 0\nv 0 x 0\nf 1 2 3\n", ":3:"),     # malformed number
    ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", ":4:"),     # index 0
])
def test_bad_obj_gives_one_line_naming_file_and_line_and_no_png(tmp_path, capsys, content, where):
    src = tmp_path / "bad.obj"
    src.write_text(content)
    out = tmp_path / "bad.png"
    code, err = _run(["render", src, "-o", out], capsys)
    assert code == 2
    assert err.count("\n") == 1 and "bad.obj" + where in err and "Traceback" not in err
    assert not out.exists() and list(tmp_path.iterdir()) == [src]


def test_missing_file_and_bad_usage_exit_2(tmp_path, capsys):
    out = tmp_path / "x.png"
    for argv in (["render", tmp_path / "nope.obj", "-o", out],
                 ["render", "--demo", "-o", out, "--size", "12by4"],
                 ["render", "--demo", "-o", out, "--size", "0x4"],
                 ["render", "--demo", "-o", tmp_path / "x.jpg"],
                 ["render", "--demo", "-o", tmp_path / "no" / "dir.png"],
                 ["render", "-o", out],
                 ["render", "--demo", "-o", out, "--mode", "sketchy"],
                 ["render", "--demo", "-o", out, "--azimuth", "nan"],
                 ["frobnicate"]):
        code, err = _run(argv, capsys)
        assert code == 2, (argv, err)
        assert err.startswith("rasterkit: error:") and err.count("\n") == 1, err
    assert "nope.obj" in _run(["render", tmp_path / "nope.obj", "-o", out], capsys)[1]
    assert list(tmp_path.iterdir()) == []


def test_an_existing_output_survives_a_failed_render(tmp_path, capsys):
    out = tmp_path / "keep.png"
    out.write_bytes(b"previous")
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nf 1 2 3\n")
    code, _ = _run(["render", bad, "-o", out], capsys)
    assert code == 2 and out.read_bytes() == b"previous"


def test_python_dash_m_and_console_script_agree(tmp_path):
    out = tmp_path / "m.png"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    done = subprocess.run([sys.executable, "-m", "rasterkit", "render", "--demo", "-o", str(out),
                           "--size", "32x24"], capture_output=True, text=True, env=env, timeout=300)
    assert done.returncode == 0, done.stderr
    assert out.exists()
    bad = subprocess.run([sys.executable, "-m", "rasterkit", "render", str(tmp_path / "missing.obj"),
                          "-o", str(out)], capture_output=True, text=True, env=env, timeout=300)
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1 and "missing.obj" in bad.stderr


# --- the complete command line ------------------------------------------------------------


@pytest.mark.parametrize("projection", ["perspective", "orthographic", "isometric", "dimetric",
                                        "trimetric", "cavalier", "cabinet", "1-point", "2-point",
                                        "3-point"])
def test_every_projection_renders_the_model_inside_the_image(cube_obj, tmp_path, capsys, projection):
    out = tmp_path / "p.png"
    code, err = _run(["render", cube_obj, "-o", out, "--size", "80x60", "--projection", projection,
                      "--mode", "solid+wire"], capsys)
    assert code == 0, err
    with Image.open(out) as im:
        drawn = np.any(np.asarray(im) != 255, axis=2)
    ys, xs = np.nonzero(drawn)
    assert len(xs) > 200 and xs.min() > 0 and xs.max() < 79 and ys.min() >= 0 and ys.max() <= 59


def test_explicit_camera_flags_match_the_python_api(cube_obj, tmp_path, capsys):
    import rasterkit

    out = tmp_path / "c.png"
    code, err = _run(["render", cube_obj, "-o", out, "--size", "64x48", "--eye", "4,3,5",
                      "--target", "0,0.5,0", "--up", "0,1,0", "--fov", "40", "--near", "1",
                      "--far", "20", "--mode", "solid", "--color", "#336699"], capsys)
    assert code == 0, err
    camera = rasterkit.Camera.look_at((4, 3, 5), (0, 0.5, 0), fov_y=40, width=64, height=48,
                                      near=1, far=20)
    expected = rasterkit.render(rasterkit.load_obj(cube_obj), camera, mode="solid", color="#336699")
    with Image.open(out) as im:
        assert np.array_equal(np.asarray(im), expected.color)


def test_distance_moves_the_eye_away_and_the_model_shrinks(cube_obj, tmp_path, capsys):
    sizes = []
    for d in ("5", "10"):
        out = tmp_path / f"d{d}.png"
        assert _run(["render", cube_obj, "-o", out, "--size", "64x64", "--distance", d,
                     "--mode", "solid"], capsys)[0] == 0
        with Image.open(out) as im:
            sizes.append(np.any(np.asarray(im) != 255, axis=2).sum())
    assert sizes[1] < sizes[0] / 3


def test_transparent_background_depth_and_turntable(cube_obj, tmp_path, capsys):
    out, depth = tmp_path / "t.png", tmp_path / "t.npy"
    code, err = _run(["render", cube_obj, "-o", out, "--size", "40x30", "--mode", "solid",
                      "--background", "transparent", "--depth", depth], capsys)
    assert code == 0, err
    with Image.open(out) as im:
        rgba = np.asarray(im)
    d = np.load(depth)
    assert rgba.shape == (30, 40, 4) and d.shape == (30, 40) and d.dtype == np.float32
    assert np.array_equal(rgba[..., 3] == 255, d > 0)  # drawn exactly where depth is
    assert np.all(d >= 0) and np.all(np.isfinite(d))  # metric depth, 0 where nothing was drawn
    for name in ("spin.gif", "spin.png"):
        code, err = _run(["render", cube_obj, "-o", tmp_path / name, "--size", "32x24",
                          "--turntable", "6", "--azimuth", "10"], capsys)
        assert code == 0, err
        with Image.open(tmp_path / name) as im:
            assert im.n_frames == 6


def test_several_models_and_folders_render_into_an_output_folder(cube_obj, tmp_path, capsys):
    models = tmp_path / "models"
    models.mkdir()
    (models / "a.obj").write_text(CUBE_OBJ)
    (models / "b.obj").write_text(CUBE_OBJ.replace("f 1 4 3 2", "f 1 4 3"))
    (models / "notes.txt").write_text("not a model")
    out = tmp_path / "images"
    code, err = _run(["render", models, cube_obj, "-o", out, "--size", "20x20"], capsys)
    assert code == 0, err
    assert sorted(p.name for p in out.iterdir()) == ["a.png", "b.png", "cube.png", "manifest.jsonl"]
    assert "3/3" in err  # progress on stderr


def test_a_bad_model_among_several_is_reported_and_the_others_still_render(cube_obj, tmp_path, capsys):
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nf 1 2 3\n")
    out = tmp_path / "images"
    code, err = _run(["render", bad, cube_obj, "-o", out, "--size", "20x20"], capsys)
    assert code == 2
    assert "bad.obj:2:" in err and "Traceback" not in err
    assert sorted(p.name for p in out.glob("*.png")) == ["cube.png"]


def test_info_prints_counts_bounds_and_warnings(cube_obj, tmp_path, capsys):
    code = main(["info", str(cube_obj)])
    text = capsys.readouterr().out
    assert code == 0
    assert "vertices  8" in text and "triangles 12" in text and "edges     12" in text
    assert "(-1, -1, -1) .. (1, 1, 1)" in text
    odd = tmp_path / "odd.obj"
    odd.write_text("mtllib missing.mtl\n" + CUBE_OBJ + "vp 0.5\n")
    assert main(["info", str(odd)]) == 0
    text = capsys.readouterr().out
    assert "missing.mtl" in text and "warnings  2" in text


def test_help_shows_examples(capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["render", "--help"])
    assert exit_.value.code == 0
    assert "examples:" in capsys.readouterr().out


@pytest.mark.parametrize("argv", [
    ["--projection", "fisheye"], ["--eye", "1,2"], ["--eye", "1,2,inf"], ["--turntable", "0"],
    ["--threads", "0"], ["--threads", "999"], ["--depth", "d.txt"], ["--near", "2", "--far", "1"],
    ["--eye", "0,0,0", "--target", "0,0,0"], ["--color", "#12345"], ["--background", "nope"],
])
def test_bad_flags_exit_2_with_one_line(argv, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, err = _run(["render", "--demo", "-o", "x.png", "--size", "16x16", *argv], capsys)
    assert code == 2, err
    assert err.startswith("rasterkit: error:") and err.count("\n") == 1
    assert list(tmp_path.iterdir()) == []
