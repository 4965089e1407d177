"""``--max-memory`` holds for a whole render command: the estimate of rasterkit.batch.job_memory
covers the turntable's frames, GIF quantisation, PNG streams, the depth, normals and ids
files and the contact sheet; a job over the limit is refused up front in one line (exit 2,
no file), a job under it runs, and the estimate stays above the peak memory measured."""

from __future__ import annotations

import io
import json
import struct

import numpy as np
import pytest

from rasterkit import shapes
from rasterkit.image import png as _png
from rasterkit.image import encode_png
from support.hostile import run_cli, run_python
from support.objfiles import write_obj


@pytest.fixture
def model(tmp_path):
    return write_obj(tmp_path / "ball.obj", shapes.icosphere(3))


def _estimate(model, output, size, **flags):
    """The job estimate for ``rasterkit render MODEL -o OUTPUT --size W x H`` with ``flags``
    (the command's option names), worked out here as the command does."""
    from rasterkit.batch.api import task_for
    from rasterkit.batch.job_memory import job_bytes
    from rasterkit.obj import load_obj

    maps = {k: flags.pop(k) for k in ("depth", "normals", "ids") if k in flags}
    task = task_for(turntable=flags.pop("turntable", None), changes=dict(flags, size=size)).replace(**maps)
    mesh = load_obj(model)
    return job_bytes(mesh, task.view.camera_for(mesh), task, output)


# --- the PNG stream is written as zlib makes it, the same bytes ---------------------------

@pytest.mark.parametrize("shape", [(1, 1, 3), (7, 5, 4), (120, 90, 3), (600, 500, 3)])
def test_a_streamed_png_is_encode_png_byte_for_byte(shape):
    image = np.random.default_rng(len(shape) + shape[0]).integers(0, 256, shape, dtype=np.uint8)
    f = io.BytesIO()
    _png.write_png(f, image)
    assert f.getvalue() == encode_png(image)
    stream = _png.compressed(image)
    for limit in (1, 5, len(stream) - 1, len(stream), len(stream) + 1):
        f = io.BytesIO()
        assert _png.write_chunks(f, image, b"fdAT", limit, 7) == 7 + len(_png.pieces(stream, limit))
        want = [_png.chunk(b"fdAT", struct.pack(">I", 7 + k) + p) for k, p in enumerate(_png.pieces(stream, limit))]
        assert f.getvalue() == b"".join(want)


# --- refused below the estimate, done above it -------------------------------------------

JOBS = [
    ("a.gif", dict(mode="solid", turntable=2)),
    ("a.png", dict(mode="wire", turntable=2)),
    ("a.png", dict(mode="solid", depth="d.png", normals="n.png", ids="i.png")),
    ("a.png", dict(mode="hidden", samples=4, background="transparent")),
]


def _flags(flags):
    out = []
    for name, value in flags.items():
        out += [f"--{name}", str(value)]
    return out


@pytest.mark.parametrize("output, flags", JOBS)
def test_a_job_is_refused_below_its_estimate_and_done_above_it(tmp_path, model, output, flags):
    need = _estimate(model, tmp_path / output, (320, 240), **flags)
    files = [output] + [flags[k] for k in ("depth", "normals", "ids") if k in flags]
    argv = ["render", model, "-o", output, "--size", "320x240", *_flags(flags)]
    refused = run_cli(*argv, "--max-memory", str(need - 1), cwd=tmp_path)
    line = refused.one_line_error()
    assert "needs about" in line and "more than the limit" in line and "ball.obj" in line
    assert not any((tmp_path / f).exists() for f in files)
    done = run_cli(*argv, "--max-memory", str(need + 1), cwd=tmp_path)
    assert done.code == 0, done.describe()
    assert all((tmp_path / f).is_file() for f in files)


# --- the estimate is above the peak measured ----------------------------------------------

PEAK = """
import json, sys
from pathlib import Path

def status(key):
    for line in open("/proc/self/status"):
        if line.startswith(key):
            return int(line.split()[1]) * 1024

from rasterkit import cli
from rasterkit.runtime import scratch as _memory
argv = json.loads(sys.argv[1])
warm = list(argv)
warm[warm.index("--size") + 1] = "16x12"
assert cli.main(warm) == 0  # the kernels loaded: what follows is the job's own memory
_memory.release()
with open("/proc/self/clear_refs", "w") as f:
    f.write("5")  # the peak (VmHWM) starts again from here
base = status("VmRSS:")
code = cli.main(argv)
print(json.dumps({"code": code, "peak": status("VmHWM:") - base}))
"""

# MALLOC_MMAP_THRESHOLD_: freed arrays go back to the system at once, so a run's peak is
# not hidden in memory that the warm-up run left to malloc
EXACT_MALLOC = {"MALLOC_MMAP_THRESHOLD_": "131072", "MALLOC_TRIM_THRESHOLD_": "131072"}


@pytest.mark.skipif(not __import__("os").path.exists("/proc/self/clear_refs"), reason="needs Linux's clear_refs")
@pytest.mark.parametrize("output, flags", [
    ("a.png", dict(mode="solid")),
    ("a.png", dict(mode="wire")),
    ("a.png", dict(mode="solid", turntable=2)),
    ("a.gif", dict(mode="solid", turntable=2, shading="smooth")),
    ("a.png", dict(mode="solid", depth="d.png", normals="n.png", ids="i.png")),
    ("a.png", dict(mode="hidden", depth="d.npy", ids="i.npy")),
])
def test_the_estimate_is_above_the_peak_measured(tmp_path, model, output, flags):
    size = (2000, 1500)
    argv = ["render", str(model), "-o", output, "--size", "2000x1500", *_flags(flags)]
    outcome = run_python(PEAK.replace("sys.argv[1]", repr(json.dumps(argv))), cwd=tmp_path, env=EXACT_MALLOC)
    assert outcome.code == 0, outcome.describe()
    measured = json.loads(outcome.stdout.splitlines()[-1])
    assert measured["code"] == 0
    need = _estimate(model, tmp_path / output, size, **flags)
    assert measured["peak"] <= need <= 5 * measured["peak"], (measured["peak"], need)


# --- the reproductions of issue 25, refused before they allocate -------------------------

@pytest.mark.parametrize("argv", [
    ["-o", "m.png", "--size", "16000x16000", "--mode", "solid", "--max-memory", "800M", "--turntable", "2"],
    ["-o", "m.gif", "--size", "16000x16000", "--mode", "solid", "--max-memory", "800M", "--turntable", "1"],
    ["-o", "m.png", "--size", "30000x30000", "--max-memory", "2G"],
    ["-o", "m.png", "--size", "4000x4000", "--mode", "solid", "--depth", "d.png", "--normals", "n.png", "--ids",
     "i.png", "--max-memory", "500M"],  # the render alone fits; making the PNGs does not
])
def test_a_job_past_the_limit_is_refused_before_it_allocates(tmp_path, model, argv):
    outcome = run_cli("render", model, *argv, cwd=tmp_path, memory=2 * 1024**3)
    assert "needs about" in outcome.one_line_error()
    assert list(tmp_path.iterdir()) == [model]


def test_a_batch_whose_contact_sheet_is_past_the_limit_is_refused_before_any_model(tmp_path, model):
    folder = tmp_path / "models"
    folder.mkdir()
    for name in ("a", "b", "c"):
        write_obj(folder / f"{name}.obj", shapes.icosphere(1))
    outcome = run_cli("render", folder, "-o", tmp_path / "out", "--size", "4000x3000", "--mode", "solid",
                      "--contact-sheet", tmp_path / "sheet.png", "--max-memory", "100M")
    line = outcome.one_line_error()
    assert "the contact sheet of 3 images of 4000x3000 needs about" in line
    assert not (tmp_path / "out").exists() and not (tmp_path / "sheet.png").exists()


def test_render_many_refuses_a_batch_past_the_limit_before_any_model(tmp_path):
    import rasterkit
    from rasterkit import limits

    model = write_obj(tmp_path / "ball.obj", shapes.icosphere(1))
    limits.set_memory_limit("200M")
    try:
        with pytest.raises(limits.LimitError, match="each model's a 8000x6000 solid turntable of 2 frames"):
            rasterkit.render_many([model], tmp_path / "out", size=(8000, 6000), mode="solid", turntable=2)
        limits.set_memory_limit("200M")  # the wireframes fit (~100 MiB), their sheet not (~207 MiB)
        with pytest.raises(limits.LimitError, match="the contact sheet of 1 images of 5000x4000"):
            rasterkit.render_many([model], tmp_path / "out", size=(5000, 4000), contact_sheet=tmp_path / "s.png")
    finally:
        limits.set_memory_limit(None)
    assert not (tmp_path / "out").exists()
