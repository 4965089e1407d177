"""render_many checks every option once, before any model is read: TypeError for a wrong
type, ValueError for a bad value (never an error per model, never a private exception)."""

from __future__ import annotations

import pytest

import rasterkit
from rasterkit.camera.view import FIELDS as VIEW_FIELDS
from rasterkit.cli import _parser
from rasterkit.options import FIELDS as OPTION_FIELDS

#: What render_many takes besides RenderOptions' and View's fields.
TASK_FIELDS = {"turntable", "turn_lights", "hidden"}


def _model(tmp_path):
    path = tmp_path / "tet.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")
    return path


def test_every_option_of_the_render_command_is_a_field_of_a_record():
    """The command line's options are fields of RenderOptions, View or the batch's Task, by
    the same names (the command's maps are files: the frame's flags follow from them)."""
    args = set(vars(_parser().parse_args(["render", "--demo", "-o", "unused.png"])))
    not_per_model = {"models", "demo", "output", "threads", "jobs", "scheduler", "resume", "contact_sheet",
                     "max_file_size", "max_memory", "command"}
    files = {"depth", "normals", "ids"}
    not_on_the_command_line = {"light", "point_color", "camera_depth", "uv"}
    assert args - not_per_model - files == (OPTION_FIELDS | VIEW_FIELDS | TASK_FIELDS) - not_on_the_command_line - files


@pytest.mark.parametrize("name", sorted(OPTION_FIELDS | VIEW_FIELDS | TASK_FIELDS))
def test_a_value_of_no_type_is_refused_before_any_model(tmp_path, name):
    out = tmp_path / "out"
    with pytest.raises((TypeError, ValueError)) as caught:
        rasterkit.render_many([_model(tmp_path)], out, **{name: object()})
    assert name in str(caught.value) or type(caught.value) is TypeError
    assert not out.exists()  # no model read, no manifest


@pytest.mark.parametrize("options, error, words", [
    (dict(turntable=2.0), TypeError, "turntable must be a whole number"),
    (dict(turntable="3"), TypeError, "turntable must be a whole number"),
    (dict(turntable=0), ValueError, "at least 1"),
    (dict(samples=True), TypeError, "samples"),
    (dict(samples=257), ValueError, "samples must be 1 to 256"),
    (dict(aa=1), TypeError, "aa must be True or False"),
    (dict(mode="shiny"), ValueError, "mode must be one of"),
    (dict(hidden="dashed"), ValueError, "SVG"),
    (dict(eye=(1, 2)), TypeError, "eye must be a point"),
    (dict(fov=float("nan")), ValueError, "fov must be a finite number"),
    (dict(vignette=1.5), ValueError, "vignette must lie in [0, 1]"),
    (dict(focus=0), ValueError, "focus must be positive"),
    (dict(color="nocolour"), ValueError, "color"),
    (dict(size=(10.0, 10)), ValueError, "size must be (width, height)"),
    (dict(fov=0.0), ValueError, "fov"),
    (dict(camera_opencv={"K": [[1, 0, 0], [0, 1, 0], [0, 0, 1]]}), TypeError, "camera_opencv"),
    (dict(camera_opencv=3), TypeError, "camera_opencv must be a path or a mapping"),
])
def test_bad_options_are_one_public_error(tmp_path, options, error, words):
    out = tmp_path / "out"
    with pytest.raises(error) as caught:
        rasterkit.render_many([_model(tmp_path)], out, **{"size": (16, 12), **options})
    assert words in str(caught.value)
    assert type(caught.value) is error  # Python's own, not a private class of rasterkit
    assert not out.exists()


def test_a_missing_camera_file_is_a_value_error(tmp_path):
    with pytest.raises(ValueError, match="missing.json") as caught:
        rasterkit.render_many([_model(tmp_path)], tmp_path / "out", camera_opencv=tmp_path / "missing.json")
    assert type(caught.value) is ValueError


def test_a_camera_mapping_renders_as_the_camera_file_does(tmp_path):
    camera = {"K": [[20, 0, 8], [0, 20, 6], [0, 0, 1]], "R": [[1, 0, 0], [0, 1, 0], [0, 0, 1]],
              "t": [-0.3, -0.3, 4], "width": 16, "height": 12}
    (tmp_path / "cam.json").write_text(__import__("json").dumps(camera))
    by_dict = rasterkit.render_many([_model(tmp_path)], tmp_path / "a", mode="solid", camera_opencv=camera)
    by_file = rasterkit.render_many([_model(tmp_path)], tmp_path / "b", mode="solid", camera_opencv=tmp_path / "cam.json")
    assert by_dict.done == by_file.done == 1
    assert (tmp_path / "a" / "tet.png").read_bytes() == (tmp_path / "b" / "tet.png").read_bytes()
