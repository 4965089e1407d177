"""The camera file of ``--camera-opencv`` under hostile conditions (issue 25): it is read by
rasterkit's one bounded reader of regular files (a FIFO or a device is refused at once, a
file over ``--max-file-size`` is not read), and every bad file or value is one line naming
the file and what is wrong, exit code 2, from ``render`` and ``explain`` alike."""

import json
import os

import numpy as np
import pytest

from rasterkit.camera.opencv_file import read_camera_file
from rasterkit.runtime.files import FileError, FileLimitError, read_file
from rasterkit import limits
from support.hostile import run_cli

GOOD = {"K": [[100.0, 0, 32.0], [0, 100.0, 24.0], [0, 0, 1]], "R": [[1, 0, 0], [0, -1, 0], [0, 0, -1]],
        "t": [0, 0, 4.0], "width": 64, "height": 48}


def _camera(tmp_path, name="cam.json", **changes):
    path = tmp_path / name
    path.write_text(json.dumps(dict(GOOD, **changes)))
    return path


def _both(tmp_path, camera, *extra, timeout=60):
    """The one error line of ``render`` and of ``explain`` with this camera file (they agree)."""
    render = run_cli("render", "--demo", "-o", tmp_path / "out.png", "--camera-opencv", camera, *extra,
                     timeout=timeout).one_line_error()
    explain = run_cli("explain", "--camera-opencv", camera, *extra, timeout=timeout).one_line_error()
    assert render == explain
    assert not (tmp_path / "out.png").exists()
    return render


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
def test_a_fifo_as_the_camera_file_is_refused_at_once(tmp_path):
    fifo = tmp_path / "cam.json"
    os.mkfifo(fifo)
    assert _both(tmp_path, fifo) == f"rasterkit: error: {fifo}: not a regular file (a FIFO)"


@pytest.mark.skipif(not os.path.exists("/dev/zero"), reason="no /dev/zero")
def test_a_device_as_the_camera_file_is_refused_not_read():
    # a child with little memory: reading /dev/zero without bound would end in MemoryError
    outcome = run_cli("explain", "--camera-opencv", "/dev/zero", timeout=60)
    assert outcome.one_line_error() == "rasterkit: error: /dev/zero: not a regular file (a character device)"


def test_a_camera_file_over_the_size_limit_is_not_read(tmp_path):
    path = tmp_path / "cam.json"
    with open(path, "w") as f:  # valid JSON of 3 MB: whitespace inside the object
        f.write('{"K": [[100, 0, 32], [0, 100, 24], [0, 0, 1]],' + " " * 3_000_000
                + '"R": [[1, 0, 0], [0, -1, 0], [0, 0, -1]], "t": [0, 0, 4], "width": 64, "height": 48}')
    line = _both(tmp_path, path, "--max-file-size", "1M")
    assert line == (f"rasterkit: error: {path}: 2.86 MiB, more than the file size limit of 1 MiB "
                    "(--max-file-size, RASTERKIT_MAX_FILE_SIZE)")
    assert run_cli("explain", "--camera-opencv", path, "--max-file-size", "4M", timeout=60).code == 0


def test_the_shared_reader_reads_no_more_than_the_limit(tmp_path, monkeypatch):
    path = tmp_path / "x.json"
    path.write_bytes(b"{}" + b" " * 2000)
    monkeypatch.setattr(limits, "_max_file_size", 1000)
    with pytest.raises(FileLimitError) as caught:
        read_camera_file(str(path))
    assert isinstance(caught.value, limits.LimitError) and isinstance(caught.value, ValueError)
    monkeypatch.setattr(limits, "_max_file_size", 4000)
    assert read_file(path) == path.read_bytes()
    with pytest.raises(FileError, match="^.*nothing.json: cannot read: No such file or directory$"):
        read_file(tmp_path / "nothing.json")


def test_deeply_nested_json_is_one_line(tmp_path):
    path = tmp_path / "cam.json"
    path.write_text("[" * 100_000 + "]" * 100_000)
    assert _both(tmp_path, path) == f"rasterkit: error: {path}: cannot read the camera: its JSON is nested too deeply"


@pytest.mark.parametrize("changes, reason", [
    (dict(R=np.eye(4).tolist()), "R must be a finite 3x3 array, got list of shape (4, 4) and dtype float64"),
    (dict(t=[0, 0]), "t must be 3 finite numbers, got (0, 0)"),
    (dict(K=[[100, 0, 32], [0, 100, 24]]), "K must be a finite 3x3 array"),
    (dict(width=0), "width must be a positive integer, got 0"),
    (dict(dist=[0.1, 0.2]), "dist must be 4, 5 or 8 finite numbers"),
    (dict(near=-1), "near must be positive, got -1"),
    (dict(far="x"), "far must be a real number"),
])
def test_a_bad_value_names_the_file_and_the_key(tmp_path, changes, reason):
    camera = _camera(tmp_path, **changes)
    with pytest.raises(ValueError) as caught:
        read_camera_file(str(camera))
    assert str(caught.value).startswith(f"{camera}: {reason}")
    assert "\n" not in str(caught.value)
    assert run_cli("explain", "--camera-opencv", camera, timeout=60).one_line_error() == \
        f"rasterkit: error: {caught.value}"


def test_a_camera_too_far_for_near_and_far_says_so(tmp_path):
    camera = _camera(tmp_path, t=[0, 0, 1e300])
    outcome = run_cli("explain", "--camera-opencv", camera, timeout=60)
    line = outcome.one_line_error()  # no RuntimeWarning on the way
    assert line.startswith(f"rasterkit: error: {camera}: near 1e+300 is not smaller than far 1e+300 "
                           "(near and far chosen from the camera's distance to the model, 1e+300,")
    assert line.endswith("give near and far in the file or with --near and --far")
    # given near and far, the error is the camera's own about them
    assert "near must be smaller than far" in run_cli(
        "explain", "--camera-opencv", camera, "--near", "1e300", "--far", "1e300", timeout=60).one_line_error()


def test_a_missing_camera_file_is_a_value_error(tmp_path):
    with pytest.raises(ValueError, match=r"nothing\.json: cannot read: No such file or directory$"):
        read_camera_file(str(tmp_path / "nothing.json"))


def test_explain_names_a_model_without_extent(tmp_path):
    model = tmp_path / "point.obj"
    model.write_text("v 1 2 3\nv 1 2 3\nv 1 2 3\nf 1 2 3\n")
    assert run_cli("explain", model, timeout=120).one_line_error() == \
        f"rasterkit: error: {model}: the model has no extent (all vertices coincide)"


@pytest.mark.parametrize("output", [".png", "sub/.PNG", ".svg"])
def test_an_output_without_a_file_name_says_so(tmp_path, output):
    (tmp_path / "sub").mkdir()
    out = tmp_path / output
    assert run_cli("render", "--demo", "-o", out, timeout=60).one_line_error() == \
        f"rasterkit: error: {out}: no file name before {out.name!r}"


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
def test_resume_does_not_open_a_fifo_in_place_of_the_image(tmp_path):
    model = tmp_path / "m.obj"
    model.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    out = tmp_path / "m.png"
    os.mkfifo(out)
    os.utime(model, (1, 1))  # the "image" is newer than the model: --resume looks inside it
    outcome = run_cli("render", model, "-o", out, "--resume", "--size", "8x8", timeout=60)
    assert outcome.code == 0, outcome.describe()  # not complete: rendered again, in its place
    assert out.is_file()
