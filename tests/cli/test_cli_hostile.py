"""The command line under hostile conditions: folders with bad models and bugs, outputs that
cannot be written, escaped warnings, SIGTERM and Ctrl-C mid-write, file size limits, long
turntables, and the limit flags. Every case ends with one line a failure and a documented
exit code, never a traceback, a temporary file or a half-written output."""

import importlib
import io
import math
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

import rasterkit
from rasterkit import limits
from rasterkit.runtime.notice import MESSAGE
from rasterkit.cli import _stop_signals, main
from support.hostile import run_cli, run_python
from support.objfiles import TETRA
from support.paths import MODELS, ROOT

BAD = "v 0 0 0\nf 1 2 3\n"  # line 2: indices out of range


def _lines(stderr: str) -> list[str]:
    """stderr's lines without the first-compile notice (a cold cache adds it)."""
    return [line for line in stderr.splitlines() if line != MESSAGE]


def _run(argv, capsys):
    code = main([str(a) for a in argv])
    return code, _lines(capsys.readouterr().err)


def _models(folder: Path, **texts) -> Path:
    folder.mkdir()
    for name, text in texts.items():
        (folder / f"{name}.obj").write_text(text)
    return folder


def _temporary_files(*folders) -> list[Path]:
    return [p for folder in folders for p in Path(folder).iterdir() if p.name.endswith(".tmp")]


def _module(name):
    return importlib.import_module(name)  # rasterkit.render is also the function's name


def _failing_loader(monkeypatch, failures: dict):
    """Make load_obj raise failures[stem] for those models."""
    obj = _module("rasterkit.obj")
    load = obj.load_obj

    def load_obj(path, *args, **kwargs):
        error = failures.get(Path(path).stem)
        if error is not None:
            raise error
        return load(path, *args, **kwargs)

    monkeypatch.setattr(obj, "load_obj", load_obj)


# --- a folder: every model that can render, renders --------------------------------------------


def test_a_folder_renders_every_good_model_and_reports_each_failure_in_one_line(tmp_path, capsys, monkeypatch):
    models = _models(tmp_path / "models", a=TETRA, b=BAD, c=TETRA, d=TETRA, e=TETRA)
    out = tmp_path / "out"
    (out / "e.png").mkdir(parents=True)  # e's output cannot be written
    _failing_loader(monkeypatch, {"d": IndexError("list index out of range")})  # a bug of ours
    code, lines = _run(["render", models, "-o", out, "--size", "32x24", "--mode", "solid"], capsys)
    assert code == 1  # an internal error among the failures
    assert sorted(p.name for p in out.iterdir()) == ["a.png", "c.png", "e.png", "manifest.jsonl"]
    for name in ("a.png", "c.png"):
        with Image.open(out / name) as im:
            assert im.size == (32, 24) and np.asarray(im).min() < 255
    progress = [line for line in lines if re.match(r"\d+/5 \S+\.obj (ok|error)", line)]
    messages = [line for line in lines if line not in progress]
    assert messages[0].startswith(f"rasterkit: error: {models / 'b.obj'}:2: ")
    assert messages == [
        messages[0],
        f"rasterkit: internal error: {models / 'd.obj'}: IndexError: list index out of range",
        f"rasterkit: error: {models / 'e.obj'}: {out / 'e.png'}: Is a directory",
        messages[-1],
    ]
    assert messages[-1].startswith("rasterkit: rendered 2, skipped 0, failed 3 in ")
    assert [line.split()[0] for line in progress] == ["1/5", "2/5", "3/5", "4/5", "5/5"]
    assert not _temporary_files(out)


def test_a_folder_with_only_bad_input_exits_2_and_one_without_failures_0(tmp_path, capsys):
    models = _models(tmp_path / "models", a=TETRA, b=BAD)
    code, lines = _run(["render", models, "-o", tmp_path / "out", "--size", "16x16"], capsys)
    assert code == 2 and lines[-1].startswith("rasterkit: rendered 1, skipped 0, failed 1 in ")
    (models / "b.obj").write_text(TETRA)
    code, lines = _run(["render", models, "-o", tmp_path / "out", "--size", "16x16"], capsys)
    assert code == 0 and lines[-1].startswith("rasterkit: rendered 2, skipped 0, failed 0 in ")


@pytest.mark.parametrize("error, message", [
    (ValueError("the camera is inside out"), "the camera is inside out"),
    (MemoryError(), "not enough memory"),
    (OSError(28, "No space left on device"), "No space left on device"),
    (ValueError("two\nlines"), "two lines"),
])
def test_an_error_while_rendering_names_the_model(tmp_path, capsys, monkeypatch, error, message):
    model = tmp_path / "m.obj"
    model.write_text(TETRA)

    def render(*args, **kwargs):
        raise error

    monkeypatch.setattr(_module("rasterkit.raster.render"), "render", render)
    code, lines = _run(["render", model, "-o", tmp_path / "m.png"], capsys)
    assert (code, lines) == (2, [f"rasterkit: error: {model}: {message}"])
    code, lines = _run(["render", tmp_path, "-o", tmp_path / "out"], capsys)  # the same in a folder
    assert code == 2 and f"rasterkit: error: {model}: {message}" in lines
    assert not (tmp_path / "m.png").exists() and [p.name for p in (tmp_path / "out").iterdir()] == ["manifest.jsonl"]


def test_ctrl_c_in_a_folder_stops_at_once(tmp_path, capsys, monkeypatch):
    models = _models(tmp_path / "models", a=TETRA, b=TETRA, c=TETRA)
    _failing_loader(monkeypatch, {"b": KeyboardInterrupt()})
    code, lines = _run(["render", models, "-o", tmp_path / "out", "--size", "16x16"], capsys)
    assert code == 130 and lines[-1] == "rasterkit: interrupted"
    assert not any("rendered" in line for line in lines)
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["a.png", "manifest.jsonl"]


def test_two_models_with_one_output_name_are_a_usage_error(tmp_path, capsys):
    one = _models(tmp_path / "one", x=TETRA)
    two = _models(tmp_path / "two", x=TETRA)
    code, lines = _run(["render", one, two, "-o", tmp_path / "out"], capsys)
    assert code == 2 and len(lines) == 1
    assert lines[0] == (f"rasterkit: error: {one / 'x.obj'} and {two / 'x.obj'} would both be written "
                        f"to {tmp_path / 'out' / 'x.png'}")
    assert not (tmp_path / "out").exists()


@pytest.mark.skipif(not (MODELS / "robustness").is_dir(), reason="../shared/models/robustness is absent")
def test_the_broken_models_of_other_loaders_render_as_folders(tmp_path):
    folders = sorted(p for p in (MODELS / "robustness").iterdir() if p.is_dir())
    files = sorted(p for folder in folders for p in folder.glob("*.obj"))
    out = tmp_path / "out"
    done = run_cli("render", *folders, "-o", out, "--size", "48x36", "--mode", "solid+wire")
    assert done.code in (0, 2), done.describe()  # never an internal error, a crash or a hang
    lines = _lines(done.stderr)
    errors = [line for line in lines if line.startswith("rasterkit: error: ")]
    images = sorted(out.glob("*.png"))
    progress = re.compile(r"\d+/%d \S+\.obj (ok|error) " % len(files))
    assert all(line.startswith(("rasterkit: error: ", "rasterkit: warning: ", "rasterkit: rendered "))
               or progress.match(line) for line in lines), lines
    failed = [next(f for f in files if line.startswith(f"rasterkit: error: {f}")) for line in errors]
    assert sorted(p.stem for p in images) == sorted(f.stem for f in files if f not in failed)
    assert lines[-1].startswith(f"rasterkit: rendered {len(images)}, skipped 0, failed {len(errors)} in ")
    assert done.code == (2 if errors else 0)
    for image in images:
        with Image.open(image) as im:
            assert im.size == (48, 36)


# --- messages: the user's file, one line ---------------------------------------------------------


def test_an_output_in_the_way_is_named_not_the_temporary_file(tmp_path, capsys):
    model = tmp_path / "m.obj"
    model.write_text(TETRA)
    (tmp_path / "out.png").mkdir()
    (tmp_path / "d.npy").mkdir()
    (tmp_path / "spin.gif").mkdir()
    cases = [
        (["--demo", "-o", tmp_path / "out.png"], f"{tmp_path / 'out.png'}: Is a directory"),
        ([model, "-o", tmp_path / "out.png"], f"{tmp_path / 'out.png'}: Is a directory"),  # before the model is read
        (["--demo", "-o", tmp_path / "x.png", "--depth", tmp_path / "d.npy"], f"{tmp_path / 'd.npy'}: Is a directory"),
        (["--demo", "-o", tmp_path / "spin.gif", "--turntable", "3"], f"{tmp_path / 'spin.gif'}: Is a directory"),
    ]
    for argv, message in cases:
        code, lines = _run(["render", *argv, "--size", "16x16"], capsys)
        assert (code, lines) == (2, [f"rasterkit: error: {message}"])
    assert not _temporary_files(tmp_path)


# Python ignores SIGXFSZ, so a write past RLIMIT_FSIZE raises OSError(EFBIG) with no file name.
# The child renders once without the limit (so that no kernel is compiled and cached under it).
FSIZE_CHILD = """
import resource, sys
from rasterkit.cli import main
argv = {argv!r}
assert main(argv) == 0
open(argv[3], "wb").write(b"old")
resource.setrlimit(resource.RLIMIT_FSIZE, (4096, 4096))
sys.exit(main(argv))
"""


@pytest.mark.parametrize("name, extra", [("big.png", []), ("spin.gif", ["--turntable", "4"]),
                                         ("spin.png", ["--turntable", "4"])])
def test_a_file_size_limit_gives_one_line_naming_the_output(tmp_path, name, extra):
    out = tmp_path / name
    argv = ["render", "--demo", "-o", str(out), "--size", "400x300", "--mode", "solid", *extra]
    done = run_python(FSIZE_CHILD.format(argv=argv))
    assert done.code == 2, done.describe()
    assert _lines(done.stderr) == [f"rasterkit: error: {out}: File too large"]
    assert out.read_bytes() == b"old" and [p.name for p in tmp_path.iterdir()] == [name]


WARNING_CHILD = """
import importlib, sys, warnings
import numpy as np
render_module = importlib.import_module("rasterkit.raster.render")
draw = render_module.render

def render(*args, **kwargs):
    np.float64(1.0) / np.float64(0.0)  # RuntimeWarning: divide by zero
    warnings.warn("one\\ntwo")  # a message of two lines
    return draw(*args, **kwargs)

render_module.render = render
from rasterkit.cli import main
sys.exit(main(sys.argv[1:]))
"""


def test_an_escaped_warning_is_one_line_naming_the_model(tmp_path):
    model = tmp_path / "m.obj"
    model.write_text(TETRA)
    done = run_python(WARNING_CHILD.replace("sys.argv[1:]", repr(["render", str(model), "-o", str(tmp_path / "m.png")])))
    assert done.code == 0, done.describe()
    assert _lines(done.stderr) == [
        f"rasterkit: warning: {model}: divide by zero encountered in scalar divide (RuntimeWarning)",
        f"rasterkit: warning: {model}: one two (UserWarning)",
    ]
    assert (tmp_path / "m.png").exists()


# --- SIGTERM and Ctrl-C mid-write --------------------------------------------------------------


def _default_signals():
    """In the child: SIGINT and SIGTERM as an interactive shell starts a command (a test run
    as a background job inherits SIGINT ignored, which the command line keeps ignored)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)


def _stop_mid_write(argv, folder: Path, sig) -> tuple[int, list[str]]:
    """Start the command line, wait until its temporary file has data, send ``sig``."""
    child = subprocess.Popen([sys.executable, "-m", "rasterkit", *map(str, argv)], stdin=subprocess.DEVNULL,
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                             env={**os.environ, "PYTHONPATH": str(ROOT)}, preexec_fn=_default_signals)
    try:
        deadline = time.monotonic() + 120
        while not any(p.stat().st_size > 1000 for p in _temporary_files(folder)):
            assert child.poll() is None, child.stderr.read()
            assert time.monotonic() < deadline, "no temporary file appeared"
            time.sleep(0.05)
        child.send_signal(sig)
        _, err = child.communicate(timeout=30)
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()
    return child.returncode, _lines(err)


@pytest.mark.parametrize("sig, code, word", [(signal.SIGTERM, 143, "terminated"),
                                             (signal.SIGINT, 130, "interrupted")])
def test_a_signal_during_a_long_turntable_leaves_no_temporary_file(tmp_path, sig, code, word):
    out = tmp_path / "spin.gif"
    out.write_bytes(b"old")
    got = _stop_mid_write(["render", "--demo", "-o", out, "--turntable", "100000", "--size", "160x120"],
                          tmp_path, sig)
    assert got == (code, [f"rasterkit: {word}"])
    assert out.read_bytes() == b"old" and [p.name for p in tmp_path.iterdir()] == ["spin.gif"]


def test_sigterm_during_a_folder_stops_it_and_leaves_no_temporary_file(tmp_path):
    models = _models(tmp_path / "models", a=TETRA, b=TETRA)
    out = tmp_path / "out"
    out.mkdir()
    (out / "a.gif").write_bytes(b"old")
    code, lines = _stop_mid_write(["render", models, "-o", out, "--turntable", "100000", "--size", "160x120"],
                                  out, signal.SIGTERM)
    assert code == 143 and lines[-1] == "rasterkit: terminated"
    assert not any("rendered" in line for line in lines)
    assert sorted(p.name for p in out.iterdir()) == ["a.gif", "manifest.jsonl"]
    assert (out / "a.gif").read_bytes() == b"old"


def test_signal_handlers_are_restored_and_an_ignored_signal_stays_ignored(tmp_path, capsys):
    before = signal.getsignal(signal.SIGTERM), signal.getsignal(signal.SIGINT)
    assert main(["render", "--demo", "-o", str(tmp_path / "x.png"), "--size", "8x8"]) == 0
    assert (signal.getsignal(signal.SIGTERM), signal.getsignal(signal.SIGINT)) == before
    previous = signal.signal(signal.SIGTERM, signal.SIG_IGN)  # as nohup or a background job
    # Ctrl-C as an interactive shell leaves it (a background job's shell ignores it)
    previous_int = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        with _stop_signals():
            assert signal.getsignal(signal.SIGTERM) is signal.SIG_IGN
            assert signal.getsignal(signal.SIGINT) is not signal.default_int_handler
        assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    finally:
        signal.signal(signal.SIGTERM, previous)
        signal.signal(signal.SIGINT, previous_int)


# --- turntables: streamed, and the frames are the renders -------------------------------------------


def _api_frames(n: int, size=(64, 48), mode="solid"):
    mesh = rasterkit.shapes.demo()
    center, radius = mesh.bounding_sphere()
    camera = rasterkit.Camera.preset("perspective", center, radius, width=size[0], height=size[1],
                                     azimuth=30.0, elevation=20.0, fov_y=45.0)
    frames = []
    for k in range(n):
        spin = rasterkit.transform.rotate_axis(2 * math.pi * k / n, (0, 1, 0), center)
        frames.append(rasterkit.render(rasterkit.Scene(camera).add(mesh, spin), mode=mode).color.copy())
    return frames


def test_turntable_frames_are_the_renders(tmp_path, capsys):
    expected = _api_frames(5)
    for name in ("spin.png", "spin.apng", "spin.gif"):
        code, lines = _run(["render", "--demo", "-o", tmp_path / name, "--turntable", "5", "--size", "64x48",
                            "--mode", "solid"], capsys)
        assert (code, lines) == (0, [])
        with Image.open(tmp_path / name) as im:
            assert im.n_frames == 5 and im.info["loop"] == 0
            for k in range(5):
                im.seek(k)
                assert im.info["duration"] == 40
                got = np.asarray(im.convert("RGB"))
                if name.endswith("gif"):  # Pillow's quantization of that frame
                    one = io.BytesIO()
                    Image.fromarray(expected[k]).save(one, "GIF")
                    with Image.open(one) as quantized:
                        assert np.array_equal(got, np.asarray(quantized.convert("RGB"))), (name, k)
                else:
                    assert np.array_equal(got, expected[k]), (name, k)


TURNTABLE_CHILD = """
import resource, sys
from rasterkit.cli import main
code = main({argv!r})
print(code, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)
"""


@pytest.mark.parametrize("name", ["spin.gif", "spin.png"])
def test_turntable_memory_does_not_grow_with_the_frame_count(tmp_path, name):
    peaks = {}
    for n in (5, 50):
        argv = ["render", "--demo", "-o", str(tmp_path / name), "--turntable", str(n), "--size", "800x600",
                "--mode", "solid"]
        done = run_python(TURNTABLE_CHILD.format(argv=argv))
        assert done.code == 0 and done.stdout.split()[0] == "0", done.describe()
        peaks[n] = int(done.stdout.split()[1]) * 1024  # ru_maxrss: KiB on Linux
    # keeping 45 more frames of 800x600 would take 65 MB more
    assert peaks[50] - peaks[5] < 25 * 1024**2, peaks


# --- --max-file-size and --max-memory ---------------------------------------------------------------


@pytest.mark.parametrize("flag, value", [("--max-file-size", "12Q"), ("--max-file-size", ""),
                                         ("--max-memory", "0"), ("--max-memory", "-5M"), ("--max-memory", "lots")])
def test_a_bad_limit_is_a_usage_error_without_numpy(flag, value):
    done = run_python(f"""
        import sys
        from rasterkit.cli import main
        code = main(["render", "--demo", "-o", "x.png", {flag + "=" + value!r}])
        print(code, [m for m in ("numba", "numpy") if m in sys.modules])
    """)
    assert done.stdout.split("\n")[0] == "2 []", done.describe()
    assert done.stderr.startswith(f"rasterkit: error: argument {flag}: a size must") and done.stderr.count("\n") == 1


def test_the_limit_flags_apply_while_models_load_and_are_restored_after(tmp_path, capsys, monkeypatch):
    model = tmp_path / "m.obj"
    model.write_text(TETRA)
    seen = []
    obj = _module("rasterkit.obj")
    load = obj.load_obj

    def load_obj(path, *args, **kwargs):
        seen.append((limits.max_file_size(), limits.memory_limit()))
        return load(path, *args, **kwargs)

    monkeypatch.setattr(obj, "load_obj", load_obj)
    limits.set_max_file_size("3M")  # a program's own setting, kept after main returns
    memory = limits.memory_limit()
    try:
        assert main(["render", str(model), "-o", str(tmp_path / "m.png"), "--max-file-size", "1.5K",
                     "--max-memory", "2G"]) == 0
        assert main(["info", str(model), "--max-memory", "300M"]) == 0
        assert seen == [(1536, 2 * 1024**3), (3 * 1024**2, 300 * 1024**2)]
        assert (limits.max_file_size(), limits.memory_limit()) == (3 * 1024**2, memory)
    finally:
        limits.set_max_file_size(None)
    capsys.readouterr()


# --- stdout closed by its reader ------------------------------------------------------------------


def test_info_into_a_closed_pipe_stops_quietly(tmp_path):
    model = tmp_path / "m.obj"
    model.write_text(TETRA)
    # far more output than a pipe buffers: the child writes on after the reader has gone
    child = subprocess.Popen([sys.executable, "-m", "rasterkit", "info", *[str(model)] * 3000],
                             stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             env={**os.environ, "PYTHONPATH": str(ROOT)})
    try:
        assert child.stdout.readline() == f"{model}\n".encode()
        child.stdout.close()
        err = child.stderr.read().decode()
        child.wait(timeout=60)
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()
    assert (child.returncode, _lines(err)) == (141, [])
