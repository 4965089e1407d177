"""Textures on the command line: drawn by default, ``--no-textures`` and ``--texture-filter``,
turntables that look their textures up once, and a bad choice refused in one line."""

from __future__ import annotations

import numpy as np
from PIL import Image

from rasterkit.cli import main
from support.frames import TEXTURED_BOWL
from support.hostile import run_cli
from support.objfiles import write_textured_obj


def _model(tmp_path):
    return write_textured_obj(tmp_path / "bowl.obj", TEXTURED_BOWL, TEXTURED_BOWL.materials[0].diffuse_map.image)


def test_textures_are_drawn_unless_turned_off(tmp_path):
    model = _model(tmp_path)
    images = {}
    for name, flags in [("default", []), ("off", ["--no-textures"]), ("nearest", ["--texture-filter", "nearest"])]:
        out = tmp_path / f"{name}.png"
        assert main(["render", str(model), "-o", str(out), "--mode", "solid", "--size", "160x120", *flags]) == 0
        images[name] = np.asarray(Image.open(out)).reshape(-1, 3)
    colours = {name: len(np.unique(image, axis=0)) for name, image in images.items()}
    # the noise texture gives hundreds of colours; its plain white Kd under a headlight, a few dozen shades
    assert colours["default"] > 3 * colours["off"]
    assert not np.array_equal(images["default"], images["nearest"])


def test_a_turntable_builds_its_textures_once(tmp_path):
    from rasterkit.raster import texturing

    model = _model(tmp_path)
    before = texturing._arguments.cache_info()
    out = tmp_path / "spin.gif"
    assert main(["render", str(model), "-o", str(out), "--mode", "solid", "--size", "64x48", "--turntable", "6"]) == 0
    after = texturing._arguments.cache_info()
    assert after.misses - before.misses == 1 and after.hits - before.hits == 5  # one build, reused by 5 frames
    frames = Image.open(out)
    assert frames.n_frames == 6


def test_an_unknown_texture_filter_is_one_line_and_exit_code_2(tmp_path):
    done = run_cli("render", _model(tmp_path), "-o", tmp_path / "x.png", "--texture-filter", "cubic")
    assert done.code == 2 and "--texture-filter" in done.stderr and "Traceback" not in done.stderr
    assert not (tmp_path / "x.png").exists()
