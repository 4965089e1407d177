"""The command line: the walking skeleton end to end, and one-line errors with exit code 2."""

import os
import subprocess
import sys

import numpy as np
import pytest
from PIL import Image

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
    return code, captured.err


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
