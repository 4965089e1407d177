"""Batches: render_many and ``rasterkit render DIR -o OUTDIR`` with --jobs, --resume,
the manifest, the contact sheet; worker processes that die or are started after kernels ran."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

import rasterkit
from rasterkit import shapes
from rasterkit.batch.manifest import complete_image, read_manifest
from support.objfiles import write_obj

OPTIONS = dict(size=(64, 48), mode="solid+wire")


@pytest.fixture
def models(tmp_path):
    folder = tmp_path / "models"
    folder.mkdir()
    write_obj(folder / "a_cube.obj", shapes.cube())
    write_obj(folder / "b_sphere.obj", shapes.icosphere(2))
    write_obj(folder / "c_torus.obj", shapes.torus(rings=24, sides=12))
    write_obj(folder / "d_tetra.obj", shapes.tetrahedron())
    (folder / "e_broken.obj").write_text("v 1 2\nf 1 2 3\n")
    return folder


def _images(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.glob("*.png"))}


def test_one_process_and_two_workers_write_the_same_bytes_and_a_true_manifest(models, tmp_path):
    one = rasterkit.render_many(models, tmp_path / "one", **OPTIONS)
    two = rasterkit.render_many([models], tmp_path / "two", jobs=2, **OPTIONS)
    assert _images(tmp_path / "one") == _images(tmp_path / "two")
    assert len(_images(tmp_path / "one")) == 4
    for summary, folder in ((one, tmp_path / "one"), (two, tmp_path / "two")):
        assert (summary.done, summary.skipped, summary.failed, summary.exit_code) == (4, 0, 1, 2)
        records = read_manifest(folder / "manifest.jsonl")
        assert sorted(r["input"] for r in records) == sorted(str(p) for p in models.glob("*.obj"))
        by_name = {Path(r["input"]).name: r for r in records}
        assert by_name["b_sphere.obj"]["triangles"] == len(shapes.icosphere(2).faces)
        assert by_name["b_sphere.obj"]["status"] == "ok" and by_name["b_sphere.obj"]["error"] is None
        assert by_name["b_sphere.obj"]["output"] == str(folder / "b_sphere.png")
        broken = by_name["e_broken.obj"]
        assert broken["status"] == "error" and "e_broken.obj:1" in broken["error"] and broken["triangles"] is None
        assert "\n" not in broken["error"]
    # the images are what render() draws for the same camera
    mesh = rasterkit.load_obj(models / "b_sphere.obj")
    center, radius = mesh.bounding_sphere()
    camera = rasterkit.Camera.preset("perspective", center, radius, width=64, height=48, azimuth=30.0,
                                     elevation=20.0)
    expected = rasterkit.render(mesh, camera, mode="solid+wire").color
    assert np.array_equal(np.asarray(Image.open(tmp_path / "one" / "b_sphere.png")), expected)


def test_resume_skips_complete_newer_images_only(models, tmp_path):
    out = tmp_path / "out"
    first = rasterkit.render_many(models, out, **OPTIONS)
    assert first.done == 4
    # a truncated image, an image older than its model, a missing image
    data = (out / "a_cube.png").read_bytes()
    (out / "a_cube.png").write_bytes(data[: len(data) // 2])
    assert not complete_image(out / "a_cube.png")
    old = time.time() - 1000
    os.utime(out / "b_sphere.png", (old, old))
    (out / "c_torus.png").unlink()
    second = rasterkit.render_many(models, out, resume=True, **OPTIONS)
    assert (second.done, second.skipped, second.failed) == (3, 1, 1)
    assert sorted((Path(r["input"]).name, r["status"]) for r in second.records) == [
        ("a_cube.obj", "ok"), ("b_sphere.obj", "ok"), ("c_torus.obj", "ok"), ("d_tetra.obj", "skipped"),
        ("e_broken.obj", "error")]
    assert (out / "a_cube.png").read_bytes() == data
    assert read_manifest(out / "manifest.jsonl")[5:] == second.records  # appended, not started anew
    third = rasterkit.render_many(models, out, **OPTIONS)  # no resume: a new manifest
    assert third.done == 4 and len(read_manifest(out / "manifest.jsonl")) == 5


def test_resume_records_the_models_it_skips_so_the_manifest_lists_every_model(models, tmp_path):
    """A killed run can leave images whose manifest line it never wrote: here every line
    but the first is gone. A resumed run skips those images and still records each one."""
    out = tmp_path / "out"
    rasterkit.render_many(models, out, **OPTIONS)
    manifest = out / "manifest.jsonl"
    manifest.write_text(manifest.read_text().splitlines()[0] + "\n")
    resumed = rasterkit.render_many(models, out, resume=True, **OPTIONS)
    assert (resumed.done, resumed.skipped, resumed.failed) == (0, 4, 1)
    last = {Path(r["input"]).name: r for r in read_manifest(manifest)}  # each model's last line
    assert sorted(last) == sorted(p.name for p in models.iterdir())
    assert {name: r["status"] for name, r in last.items()} == {
        "a_cube.obj": "skipped", "b_sphere.obj": "skipped", "c_torus.obj": "skipped", "d_tetra.obj": "skipped",
        "e_broken.obj": "error"}
    assert last["b_sphere.obj"]["output"] == str(out / "b_sphere.png") and last["b_sphere.obj"]["error"] is None


def test_complete_image_knows_png_and_gif(tmp_path):
    rasterkit.render(shapes.cube(), rasterkit.Camera.look_at((2, 2, 3), (0, 0, 0), width=16, height=12)).save(
        tmp_path / "x.png")
    assert complete_image(tmp_path / "x.png")
    Image.new("RGB", (4, 4)).save(tmp_path / "x.gif")
    assert complete_image(tmp_path / "x.gif")
    data = (tmp_path / "x.gif").read_bytes()
    (tmp_path / "y.gif").write_bytes(data[:-1])
    (tmp_path / "z.png").write_bytes(b"not an image at all, just text")
    assert not complete_image(tmp_path / "y.gif") and not complete_image(tmp_path / "z.png")
    assert not complete_image(tmp_path / "missing.png")


def test_cli_batch_with_jobs_contact_sheet_and_exit_code(models, tmp_path):
    out = tmp_path / "out"
    result = subprocess.run([sys.executable, "-m", "rasterkit", "render", str(models), "-o", str(out), "--size",
                             "64x48", "--jobs", "2", "--contact-sheet", str(tmp_path / "sheet.png")],
                            capture_output=True, text=True, timeout=300)
    assert result.returncode == 2, result.stderr
    lines = result.stderr.splitlines()
    assert any(line.startswith("rasterkit: error:") and "e_broken.obj:1" in line for line in lines)
    assert lines[-1].startswith("rasterkit: rendered 4, skipped 0, failed 1 in ")
    assert "Traceback" not in result.stderr
    assert len(_images(out)) == 4
    with Image.open(tmp_path / "sheet.png") as sheet:
        assert sheet.width >= 3 * 64 and sheet.height >= 2 * 48
    mode = (out / "manifest.jsonl").stat().st_mode & 0o777
    umask = os.umask(0)
    os.umask(umask)
    assert mode == 0o666 & ~umask


@pytest.mark.parametrize("argv, words", [
    (["--jobs", "-1"], "must be 0 or more"),
    (["--jobs", "2", "--scheduler", "tcp://127.0.0.1:1"], "not both"),
    (["--contact-sheet", "sheet.jpg"], "must end in .png"),
    (["--contact-sheet", "no/such/folder/sheet.png"], "does not exist"),
])
def test_cli_bad_batch_options_are_one_line_errors(models, tmp_path, argv, words):
    result = subprocess.run([sys.executable, "-m", "rasterkit", "render", str(models), "-o", str(tmp_path / "o"),
                             *argv], capture_output=True, text=True, timeout=120)
    assert result.returncode == 2
    assert len(result.stderr.strip().splitlines()) == 1 and words in result.stderr


def test_render_many_refuses_bad_arguments(models, tmp_path):
    with pytest.raises(TypeError, match="unknown render option"):
        rasterkit.render_many(models, tmp_path / "o", colour="red")
    with pytest.raises(ValueError, match="size"):
        rasterkit.render_many(models, tmp_path / "o", size=(0, 10))
    with pytest.raises(ValueError, match="colour"):
        rasterkit.render_many(models, tmp_path / "o", color="no-such-colour")
    with pytest.raises(ValueError, match="mode"):
        rasterkit.render_many(models, tmp_path / "o", mode="shaded")
    with pytest.raises(ValueError, match="jobs"):
        rasterkit.render_many(models, tmp_path / "o", jobs=-1)
    with pytest.raises(ValueError, match="folder"):
        rasterkit.render_many(models, tmp_path / "o.png")
    with pytest.raises(ValueError, match="does not exist"):
        rasterkit.render_many(models, tmp_path / "o", contact_sheet=tmp_path / "no" / "sheet.png")
    assert not (tmp_path / "o").exists()  # refused before anything rendered


def test_a_worker_that_dies_costs_only_its_model(models, tmp_path):
    import multiprocessing

    copies = tmp_path / "many"
    copies.mkdir()
    for k in range(16):
        write_obj(copies / f"sphere{k:02d}.obj", shapes.icosphere(4))
    out = tmp_path / "out"
    result = {}
    thread = threading.Thread(target=lambda: result.update(
        s=rasterkit.render_many(copies, out, jobs=2, size=(640, 480), samples=128)))  # long enough to be caught
    thread.start()
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and len(read_manifest(out / "manifest.jsonl") if (out / "manifest.jsonl").exists() else []) < 1:
        time.sleep(0.01)
    victim = next((p for p in multiprocessing.active_children() if p.name == "rasterkit-worker"), None)
    assert victim is not None and thread.is_alive()  # results are arriving, the batch is not done
    os.kill(victim.pid, signal.SIGKILL)
    thread.join(timeout=300)
    summary = result["s"]
    assert summary.done + summary.failed == 16 and len(summary.records) == 16
    died = [r for r in summary.records if r["status"] == "error"]
    assert len(died) <= 1 and all("worker process died (signal 9)" in r["error"] for r in died)
    assert len(list(out.glob("*.png"))) == summary.done
    assert not list(out.glob(".*.tmp"))


_FORK_CHILD = """
import os, sys, rasterkit
from rasterkit import shapes
cam = rasterkit.Camera.look_at((2, 2, 3), (0, 0, 0), width=64, height=48)
for mode in ("wire", "solid"):
    rasterkit.render(shapes.icosphere(3), cam, mode=mode)  # kernels ran on 2 threads here
pid = os.fork()
if pid == 0:
    s = rasterkit.render_many(sys.argv[1], sys.argv[2], jobs=2, size=(64, 48), mode="solid+wire")
    rasterkit.render(shapes.icosphere(3), cam, mode="solid")  # the forked process itself renders too
    os._exit(0 if s.done == 4 else 3)
_, status = os.waitpid(pid, 0)
sys.exit(os.waitstatus_to_exitcode(status))
"""


@pytest.mark.skipif(not hasattr(os, "fork"), reason="no fork() here")
def test_a_process_forked_after_kernels_ran_renders_batches(models, tmp_path):
    result = subprocess.run([sys.executable, "-c", _FORK_CHILD, str(models), str(tmp_path / "out")],
                            capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    assert len(_images(tmp_path / "out")) == 4


def test_sigterm_stops_the_workers_and_leaves_no_temporary_file(tmp_path):
    folder = tmp_path / "models"
    folder.mkdir()
    for k in range(24):
        write_obj(folder / f"s{k:02d}.obj", shapes.icosphere(4))
    out = tmp_path / "out"
    child = subprocess.Popen([sys.executable, "-m", "rasterkit", "render", str(folder), "-o", str(out),
                              "--size", "1600x1200", "--samples", "64", "--jobs", "2"],
                             stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and not (
            (out / "manifest.jsonl").exists() and (out / "manifest.jsonl").read_text().count("\n") >= 1):
        time.sleep(0.01)
    assert child.poll() is None  # still rendering
    child.send_signal(signal.SIGTERM)
    _, err = child.communicate(timeout=60)
    assert child.returncode == 143, err
    assert not [p for p in out.iterdir() if p.name.endswith(".tmp")]
    assert len(list(out.glob("*.png"))) < 24  # stopped before the end
    for p in out.glob("*.png"):
        assert complete_image(p)
    assert all(json.loads(line)["status"] == "ok" for line in (out / "manifest.jsonl").read_text().splitlines())


def _workers_of(pid: int) -> list[int]:
    """The batch workers of process ``pid``: its children, but a first run's compiling helper."""
    found = []
    for entry in filter(str.isdigit, os.listdir("/proc")):
        try:
            with open(f"/proc/{entry}/stat") as f:
                parent = int(f.read().rsplit(")", 1)[1].split()[1])
            with open(f"/proc/{entry}/cmdline", "rb") as f:
                helper = b"rasterkit.runtime.warm" in f.read()
        except (OSError, IndexError):
            continue
        if parent == pid and not helper:
            found.append(int(entry))
    return found


def _running(pid: int) -> bool:
    """Whether ``pid`` is a process that has not exited (a zombie has)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


@pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="needs /proc")
@pytest.mark.parametrize("busy", [True, False])
def test_workers_stop_when_the_batch_process_is_killed_outright(tmp_path, busy):
    """kill -9 of the batch: its workers stop too (busy: while rendering, their temporary
    files removed; idle: the parent stopped first, so they wait on their pipes), and a
    --resume run then records every model."""
    folder = tmp_path / "models"
    folder.mkdir()
    count = 8 if busy else 40  # idle: more than the workers render before the parent is stopped
    for k in range(count):
        write_obj(folder / f"s{k:02d}.obj", shapes.icosphere(4))
    out = tmp_path / "out"
    options = ["--size", "1600x1200", "--samples", "64"] if busy else ["--size", "320x240"]
    child = subprocess.Popen([sys.executable, "-m", "rasterkit", "render", str(folder), "-o", str(out), *options,
                              "--jobs", "2"], stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                             stderr=subprocess.PIPE, env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)})
    workers = []
    try:
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline and not (len(_workers_of(child.pid)) == 2 and (
                not busy or (out / "manifest.jsonl").exists() and (out / "manifest.jsonl").read_text())):
            assert child.poll() is None, child.stderr.read()
            time.sleep(0.01 if busy else 0.002)
        workers = _workers_of(child.pid)
        assert len(workers) == 2
        if not busy:
            child.send_signal(signal.SIGSTOP)  # it hands out no more models
            time.sleep(2)  # the workers finish theirs and wait for the next
            assert len(list(out.glob("*.png"))) < count
        child.kill()
        child.wait()
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline and any(map(_running, workers)):
            time.sleep(0.05)
        assert not any(map(_running, workers)), "the workers outlived the batch"
    finally:
        child.kill()
        child.wait()
        child.stderr.close()
        for pid in filter(_running, workers):  # a failed test leaves no process behind
            os.kill(pid, signal.SIGKILL)
    assert not [p.name for p in out.iterdir() if p.name.endswith(".tmp")]
    resumed = subprocess.run([sys.executable, "-m", "rasterkit", "render", str(folder), "-o", str(out), "--size",
                              "32x24", "--resume", "--jobs", "2"], capture_output=True, text=True, timeout=300)
    assert resumed.returncode == 0, resumed.stderr
    last = {Path(r["input"]).name: r["status"] for r in read_manifest(out / "manifest.jsonl")}
    assert sorted(last) == [f"s{k:02d}.obj" for k in range(count)] and set(last.values()) <= {"ok", "skipped"}


def test_workers_are_forked_only_when_no_other_thread_runs():
    """In a fresh interpreter (a test process may hold threads of earlier tests: Dask's)."""
    code = ("import threading\n"
            "from rasterkit.batch.workers import _start_method\n"
            "alone = _start_method()\n"
            "stop = threading.Event()\n"
            "other = threading.Thread(target=stop.wait, name='someone-else')\n"
            "other.start()\n"
            "print(alone, _start_method())\n"
            "stop.set()\n"
            "other.join()\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                          env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)})
    assert done.returncode == 0, done.stderr
    alone, with_a_thread = done.stdout.split()
    assert alone == ("fork" if sys.platform.startswith("linux") else "spawn")
    assert with_a_thread == "spawn"  # its locks could be copied held into a fork
