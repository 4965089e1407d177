"""Turntables with lights: by default the lights stay where they are while the model turns
(its shadows drawn anew for each frame, so they move over it); ``--turn-lights`` turns them
with the model, so that each face keeps its lighting (with a directional light and no
highlight, a flat face's colour depends only on its normal and the light's direction)."""

from __future__ import annotations

import math

import numpy as np
from PIL import Image, ImageSequence

import rasterkit as rk
from rasterkit.cli import _parser
from rasterkit.cli.args import attach_number_lists, task_from_args
from rasterkit.transform import rotate_axis
from support.hostile import run_cli

FRAMES = 4
FLAGS = ["--mode", "solid", "--size", "320x240", "--light", "directional:-0.3,-1,-0.5", "--specular", "0",
         "--turntable", str(FRAMES)]


def _model(tmp_path):
    """An OBJ file of the demo torus tilted (about x) and stretched: no turn about y maps it
    onto itself."""
    mesh = rk.shapes.demo()
    c, s = math.cos(0.5), math.sin(0.5)
    vertices = mesh.vertices @ np.array([[1.6, 0, 0], [0, c, s], [0, -s, c]])
    path = tmp_path / "tilted.obj"
    path.write_text("".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in vertices.tolist())
                    + "".join(f"f {a + 1} {b + 1} {d + 1}\n" for a, b, d in mesh.faces.tolist()))
    return path


def _frames(path):
    return [np.asarray(frame.convert("RGB")) for frame in ImageSequence.Iterator(Image.open(path))]


def _face_colours(frame, ids):
    """{face: its colour} of the faces that cover at least 12 pixels of ``frame`` (one colour each)."""
    out = {}
    for face in np.unique(ids[ids >= 0]):
        pixels = frame[ids == face]
        if len(pixels) >= 12:
            out[int(face)] = tuple(int(c) for c in np.median(pixels, axis=0))
    return out


def _ids(task, k, model):
    mesh = rk.load(model)
    camera, center = task.view.frame(mesh)
    spin = rotate_axis(2 * math.pi * k / FRAMES, (0, 1, 0), center)
    options = task.frame_options().replace(ids=True)
    if task.turn_lights:
        from rasterkit.raster.lights import moved

        options = options.replace(lights=tuple(moved(light, spin) for light in options.lights))
    return rk.render(rk.Scene(camera).add(mesh, spin), options=options)


def test_turned_lights_keep_each_faces_lighting_and_fixed_ones_do_not(tmp_path):
    kept = {}
    model = _model(tmp_path)
    for turn in (True, False):
        out = tmp_path / f"spin{turn}.png"
        flags = FLAGS + (["--turn-lights"] if turn else [])
        result = run_cli("render", str(model), "-o", str(out), *flags)
        assert result.code == 0, result.stderr
        task = task_from_args(_parser().parse_args(attach_number_lists(["render", str(model), "-o", str(out), *flags])))
        assert task.turn_lights is turn
        frames = _frames(out)
        assert len(frames) == FRAMES
        drawn = [_ids(task, k, model) for k in range(FRAMES)]
        for k in range(FRAMES):  # each frame is the API's render of the turned model
            np.testing.assert_array_equal(frames[k], drawn[k].color)
        first = _face_colours(frames[0], drawn[0].ids)
        later = _face_colours(frames[1], drawn[1].ids)
        shared = sorted(set(first) & set(later))
        assert len(shared) > 20
        kept[turn] = sum(np.abs(np.subtract(first[f], later[f])).max() <= 1 for f in shared) / len(shared)
    assert kept[True] == 1.0  # every face seen in both frames keeps its colour
    assert kept[False] < 0.5  # under fixed lights the faces turn to or from them


def test_shadows_of_a_turntable_move_with_the_model(tmp_path):
    out = tmp_path / "shadows.png"
    model = _model(tmp_path)
    flags = FLAGS + ["--shadows", "--ground", "--ao"]
    assert run_cli("render", str(model), "-o", str(out), *flags).code == 0
    task = task_from_args(_parser().parse_args(attach_number_lists(["render", str(model), "-o", str(out), *flags])))
    frames = _frames(out)
    assert len(frames) == FRAMES
    for k in (1, 3):
        np.testing.assert_array_equal(frames[k], _ids(task, k, model).color)
    assert (frames[1] != frames[0]).any()
