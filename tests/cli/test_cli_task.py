"""The command line as a thin adapter: its arguments become a View and a Task once, and
nothing below it sees them."""

from __future__ import annotations

import json

import pytest

from rasterkit import RenderOptions, View
from rasterkit.batch.task import Task
from rasterkit.cli import _parser, _stopped
from rasterkit.cli.args import attach_number_lists, task_from_args


def _task(*flags) -> Task:
    return task_from_args(_parser().parse_args(attach_number_lists(["render", "--demo", "-o", "x.png", *flags])))


def test_the_defaults_are_the_records_defaults():
    task = _task()
    assert task.options == RenderOptions(background="white")  # the command line's default
    assert task.view == View()
    assert (task.turntable, task.hidden, task.depth, task.normals, task.ids) == (None,) * 5


def test_each_flag_lands_in_its_field(tmp_path):
    camera = {"K": [[50, 0, 32], [0, 50, 24], [0, 0, 1]], "R": [[1, 0, 0], [0, 1, 0], [0, 0, 1]],
              "t": [0, 0, 4], "width": 64, "height": 48}
    (tmp_path / "cam.json").write_text(json.dumps(camera))
    task = _task("--mode", "solid+wire", "--cull", "none", "--shading", "smooth", "--color", "#102030",
                 "--line-color", "red", "--background", "transparent", "--aa", "--edges", "feature",
                 "--crease-angle", "12", "--samples", "8", "--vignette", "0.5", "--size", "64x48",
                 "--projection", "cabinet", "--eye", "-1,2,3", "--target", "0,0.5,0", "--up", "0,0,1",
                 "--fov", "30", "--near", "0.5", "--far", "50", "--azimuth", "10", "--elevation", "5",
                 "--distance", "3", "--aperture", "0.1", "--focus", "2", "--turntable", "4",
                 "--camera-opencv", str(tmp_path / "cam.json"))
    assert task.options == RenderOptions(mode="solid+wire", cull="none", shading="smooth", color="#102030",
                                         line_color="red", background="transparent", aa=True, edges="feature",
                                         crease_angle=12.0, samples=8, vignette=0.5)
    assert task.view == View(size=(64, 48), projection="cabinet", eye=(-1, 2, 3), target=(0, 0.5, 0), up=(0, 0, 1),
                             fov=30, near=0.5, far=50, azimuth=10, elevation=5, distance=3, aperture=0.1, focus=2,
                             camera_opencv=tmp_path / "cam.json")
    assert task.view.camera_opencv["K"] == camera["K"] and task.turntable == 4


def test_map_files_ask_the_frame_for_their_maps():
    task = _task("--mode", "solid", "--depth", "d.npy", "--ids", "i.png")
    assert not (task.options.ids or task.options.camera_depth)
    frame = task.frame_options()
    assert frame.ids and frame.camera_depth and not frame.normals


def test_a_bad_colour_is_refused_when_the_task_is_made():
    with pytest.raises(ValueError, match="line_color: unknown colour"):
        _task("--line-color", "nocolour")


def test_an_interrupted_command_stops_the_first_run_helpers(monkeypatch, capsys):
    from rasterkit.runtime import warm

    stopped = []
    monkeypatch.setattr(warm, "stop", lambda: stopped.append(True))
    assert _stopped(True) == 130 and stopped == [True]
    assert capsys.readouterr().err == "rasterkit: interrupted\n"
