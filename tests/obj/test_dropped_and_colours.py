"""A model whose every face is dropped is an error naming the file, as an empty one is; a
Mesh refuses colours that are not finite or outside [0, 1] instead of drawing them clamped
or black."""

from __future__ import annotations

import re

import numpy as np
import pytest

import rasterkit
from rasterkit import shapes
from support.hostile import run_cli


@pytest.mark.parametrize("text", [
    "v nan 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\nf 1 2 4\n",
    "v 0 0 0\nv inf 0 0\nv 0 1 0\nf 1 2 3\nl 1 2\n",
])
@pytest.mark.parametrize("output", ["x.png", "x.svg"])
def test_a_model_with_every_face_dropped_is_an_error_naming_it(tmp_path, text, output):
    model = tmp_path / "dropped.obj"
    model.write_text(text)
    outcome = run_cli("render", model, "-o", tmp_path / output, "--mode", "wire")
    line = outcome.one_line_error()
    assert re.search(rf"{re.escape(str(model))}:[12]: \d vertex with NaN or infinite", line), line
    assert line.endswith("nothing left to draw")
    assert not (tmp_path / output).exists()


def test_an_empty_model_and_an_all_dropped_one_end_alike(tmp_path):
    (tmp_path / "empty.obj").write_text("")
    (tmp_path / "dropped.obj").write_text("v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    empty = run_cli("render", tmp_path / "empty.obj", "-o", tmp_path / "e.png")
    dropped = run_cli("render", tmp_path / "dropped.obj", "-o", tmp_path / "d.png")
    assert empty.code == dropped.code == 2
    assert "nothing to draw" in empty.one_line_error() and "nothing left to draw" in dropped.one_line_error()


def test_a_model_with_some_faces_left_still_renders_with_its_warning(tmp_path):
    model = tmp_path / "some.obj"
    model.write_text("v nan 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 1 1 1\nf 1 2 3\nf 2 3 4\nf 2 4 5\n")
    outcome = run_cli("render", model, "-o", tmp_path / "s.png", "--size", "32x24")
    assert outcome.code == 0 and "1 face and 0 lines using them dropped" in outcome.stderr
    assert (tmp_path / "s.png").is_file()


@pytest.mark.parametrize("name", ["vertex_colors", "face_colors"])
@pytest.mark.parametrize("bad, words", [
    (np.nan, "must be finite numbers in [0, 1]"),
    (np.inf, "must be finite numbers in [0, 1]"),
    (-0.25, "must lie in [0, 1]"),
    (1.5, "must lie in [0, 1] (divide 0-255 colours by 255)"),
    (255.0, "must lie in [0, 1] (divide 0-255 colours by 255)"),
])
def test_a_mesh_refuses_colours_it_cannot_draw_as_given(name, bad, words):
    cube = shapes.cube()
    rows = len(cube.vertices) if name == "vertex_colors" else len(cube.faces)
    colors = np.full((rows, 3), 0.5)
    colors[3, 1] = bad
    with pytest.raises(ValueError) as caught:
        rasterkit.Mesh(cube.vertices, cube.faces, **{name: colors})
    assert f"{name}[3]" in str(caught.value) and words in str(caught.value)


def test_colours_at_the_ends_of_the_range_are_taken():
    cube = shapes.cube()
    colors = np.tile([[0.0, 1.0, 0.5]], (len(cube.vertices), 1))
    mesh = rasterkit.Mesh(cube.vertices, cube.faces, vertex_colors=colors)
    assert np.array_equal(mesh.vertex_colors, colors.astype(np.float32))
