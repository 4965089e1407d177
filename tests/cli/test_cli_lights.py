"""The lighting flags: ``--light KIND:NUMBERS[:COLOR[:INTENSITY]]`` (repeatable), ``--shading
phong``, ``--specular``, ``--shininess``: parsed into RenderOptions, bad ones refused in one
line with exit code 2."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

import rasterkit as rk
from rasterkit.cli import _parser
from rasterkit.cli.args import attach_number_lists, task_from_args
from support.hostile import run_cli


def _options(*flags) -> rk.RenderOptions:
    return task_from_args(_parser().parse_args(attach_number_lists(["render", "--demo", "-o", "x.png", *flags]))).options


def test_each_light_flag_is_the_light_it_names():
    options = _options("--shading", "phong", "--specular", "0.6", "--shininess", "12",
                       "--light", "directional:-1,-2,-3", "--light", "point:1,2,3,9:#ff8000:4.5",
                       "--light", "spot:0,3,0,0,-1,0,50,0.3:red:7", "--light", "spot:0,3,0,0,-1,0",
                       "--light", "ambient:gray:0.2", "--light", "headlight::0.5")
    assert options.shading == "phong" and options.specular == 0.6 and options.shininess == 12.0
    assert options.lights == (rk.Light.directional((-1, -2, -3)),
                              rk.Light.point((1, 2, 3), "#ff8000", 4.5, range=9.0),
                              rk.Light.spot((0, 3, 0), (0, -1, 0), 50.0, 0.3, "red", 7.0),
                              rk.Light.spot((0, 3, 0), (0, -1, 0)),
                              rk.Light.ambient("gray", 0.2),
                              rk.Light.headlight(intensity=0.5))
    assert _options().lights == ()
    shadowed = _options("--shadows", "--shadow-map-size", "256", "--shadow-softness", "0.5")
    assert (shadowed.shadows, shadowed.shadow_map_size, shadowed.shadow_softness) == (True, 256, 0.5)


def test_the_command_line_draws_what_the_api_draws(tmp_path):
    out = tmp_path / "lit.png"
    flags = ["--mode", "solid", "--shading", "phong", "--size", "96x72", "--light", "point:1,2,3:#ff8000:6",
             "--light", "ambient::0.1"]
    result = run_cli("render", "--demo", "-o", str(out), *flags)
    assert result.code == 0, result.stderr
    task = task_from_args(_parser().parse_args(["render", "--demo", "-o", str(out), *flags]))
    mesh = rk.shapes.demo()
    expected = rk.render(mesh, task.view.camera_for(mesh), options=task.options).color
    np.testing.assert_array_equal(np.asarray(Image.open(out).convert("RGB")), expected)


@pytest.mark.parametrize("flag, words", [
    ("sun:1,2,3", "unknown kind 'sun'"),
    ("directional:1,2", "a directional light is directional:DX,DY,DZ"),
    ("point:1,2,3,4,5", "a point light is point:X,Y,Z[,RANGE]"),
    ("spot:0,0,0", "a spot light is spot:"),
    ("directional:0,0,0", "direction"),
    ("point:1,2,3:nocolour", "unknown colour"),
    ("point:1,2,3:red:-1", "must be >= 0"),
    ("point:1,2,3:red:1:2", "a point light is"),
    ("spot:0,0,0,0,0,-1,190", "angle"),
    ("directional:1,nan,0", "not a finite number"),
])
def test_a_bad_light_is_refused_in_one_line(tmp_path, flag, words):
    result = run_cli("render", "--demo", "-o", str(tmp_path / "x.png"), "--light", flag)
    assert result.code == 2
    lines = result.stderr.strip().splitlines()
    assert words in lines[-1] and "Traceback" not in result.stderr
    assert not (tmp_path / "x.png").exists()


def test_ambient_occlusion_and_a_shadow_catcher_from_the_command_line(tmp_path):
    options = _options("--ao", "--ao-radius", "0.3", "--ao-samples", "8", "--ground", "shadow")
    assert (options.ao, options.ao_radius, options.ao_samples, options.ground) == (True, 0.3, 8, "shadow")
    assert options.background == "transparent"  # a shadow catcher's default: only the shadow is drawn
    assert _options("--ground", "shadow", "--background", "navy").background == "navy"
    assert _options().background == "white" and _options("--ground").background == "white"
    assert _options("--ground").ground == "#d8d8d8" and _options().ao is False
    out = tmp_path / "caught.png"
    flags = ["--mode", "solid", "--shading", "phong", "--size", "120x90", "--light", "directional:-0.4,-1,-0.3",
             "--shadows", "--ao", "--ground", "shadow", "--background", "transparent"]
    result = run_cli("render", "--demo", "-o", str(out), *flags)
    assert result.code == 0, result.stderr
    task = task_from_args(_parser().parse_args(["render", "--demo", "-o", str(out), *flags]))
    mesh = rk.shapes.demo()
    expected = rk.render(mesh, task.view.camera_for(mesh), options=task.options).color
    got = np.asarray(Image.open(out))
    np.testing.assert_array_equal(got, expected)
    assert got.shape[2] == 4 and ((got[..., 3] > 0) & (got[..., 3] < 255)).sum() > 100  # a translucent shadow


@pytest.mark.parametrize("flags, words", [
    (["--ao-radius", "0"], "--ao-radius: must be positive"),
    (["--ao-radius", "nan"], "--ao-radius"),
    (["--ao-samples", "257"], "--ao-samples"),
    (["--ground", "shadows"], "ground"),
])
def test_bad_ao_and_ground_flags_are_refused_in_one_line(tmp_path, flags, words):
    result = run_cli("render", "--demo", "--mode", "solid", "-o", str(tmp_path / "x.png"), *flags)
    assert result.code == 2, result.stderr
    assert words in result.stderr.strip().splitlines()[-1] and "Traceback" not in result.stderr
    assert not (tmp_path / "x.png").exists()
