"""Batches whose models have unusual file names: names that are not UTF-8 (bytes, on POSIX)
keep their bytes in the images, the manifest and ``--resume``, and show as printable text in
one-line messages; a ``.obj`` that is a broken link fails like any model, in one line and a
manifest record, instead of being left out without a word."""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest

from rasterkit import shapes
from rasterkit.batch.manifest import read_manifest
from support.hostile import run_cli, run_python

ODD = b"a\xff.obj"  # not UTF-8: Python names it "a\udcff.obj" (surrogateescape)


def _obj(mesh) -> str:
    lines = [f"v {float(x)!r} {float(y)!r} {float(z)!r}" for x, y, z in mesh.vertices]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in mesh.faces]
    return "\n".join(lines) + "\n"


def _write(folder: Path, name: bytes, text: str) -> None:
    with open(os.path.join(os.fsencode(folder), name), "w") as f:
        f.write(text)


@pytest.fixture
def folder(tmp_path):
    models = tmp_path / "models"
    models.mkdir()
    try:
        _write(models, ODD, _obj(shapes.cube()))
    except (OSError, UnicodeError):
        pytest.skip("this file system takes only UTF-8 names")
    _write(models, b"b.obj", _obj(shapes.tetrahedron()))
    _write(models, b"c.obj", _obj(shapes.icosphere(1)))
    return models


def _names(folder: Path) -> list[bytes]:
    return sorted(os.listdir(os.fsencode(folder)))


@pytest.mark.parametrize("jobs", ["1", "2"])
def test_a_name_that_is_not_utf8_renders_and_keeps_its_bytes_in_the_manifest_and_resume(folder, tmp_path, jobs):
    out = tmp_path / "out"
    done = run_cli("render", folder, "-o", out, "--size", "32x24", "--jobs", jobs)
    assert done.code == 0, done.describe()
    assert _names(out) == [b"a\xff.png", b"b.png", b"c.png", b"manifest.jsonl"]
    lines = done.stderr.splitlines()
    # jobs finish in any order with --jobs 2: the count before the name is the order of finishing
    assert any(re.match(r"[123]/3 a\\xff\.obj ok", line) for line in lines), lines
    assert lines[-1].startswith("rasterkit: rendered 3, skipped 0, failed 0")
    (out / "manifest.jsonl").read_bytes().decode("utf-8")  # the file is UTF-8: the byte is an escape in it
    records = read_manifest(out / "manifest.jsonl")
    models = [os.path.join(os.fsencode(folder), name) for name in (ODD, b"b.obj", b"c.obj")]
    assert sorted(os.fsencode(r["input"]) for r in records) == models
    assert sorted(os.fsencode(r["output"]) for r in records) == [
        os.path.join(os.fsencode(out), name) for name in (b"a\xff.png", b"b.png", b"c.png")]
    assert {r["status"] for r in records} == {"ok"}
    # --resume finds the images by those names, and records each model it skips
    again = run_cli("render", folder, "-o", out, "--size", "32x24", "--jobs", jobs, "--resume")
    assert again.code == 0, again.describe()
    assert again.stderr.splitlines()[-1].startswith("rasterkit: rendered 0, skipped 3, failed 0")
    later = read_manifest(out / "manifest.jsonl")[3:]
    assert sorted(os.fsencode(r["input"]) for r in later) == models
    assert {r["status"] for r in later} == {"skipped"}


def test_a_failing_model_whose_name_is_not_utf8_is_one_printable_line(folder, tmp_path):
    _write(folder, b"bad\xfe.obj", "v 1 2\nf 1 2 3\n")
    out = tmp_path / "out"
    done = run_cli("render", folder, "-o", out, "--size", "32x24")
    assert done.code == 2, done.describe()
    errors = [line for line in done.stderr.splitlines() if line.startswith("rasterkit: error: ")]
    assert len(errors) == 1 and "bad\\xfe.obj" in errors[0] and errors[0].isprintable(), done.stderr
    assert done.stderr.splitlines()[-1].startswith("rasterkit: rendered 3, skipped 0, failed 1")
    failed = [r for r in read_manifest(out / "manifest.jsonl") if r["status"] == "error"]
    assert [os.fsencode(r["input"]) for r in failed] == [os.path.join(os.fsencode(folder), b"bad\xfe.obj")]
    assert failed[0]["error"].isprintable()


def test_a_broken_link_in_a_folder_fails_in_one_line_with_a_manifest_record(tmp_path):
    models = tmp_path / "models"
    models.mkdir()
    (models / "a.obj").write_text(_obj(shapes.cube()))
    (models / "gone.obj").symlink_to(tmp_path / "nowhere.obj")
    (models / "sub.obj").mkdir()  # a folder is not a model
    out = tmp_path / "out"
    done = run_cli("render", models, "-o", out, "--size", "32x24")
    assert done.code == 2, done.describe()
    errors = [line for line in done.stderr.splitlines() if line.startswith("rasterkit: error: ")]
    assert len(errors) == 1 and f"{models / 'gone.obj'}: " in errors[0], done.stderr
    assert done.stderr.splitlines()[-1].startswith("rasterkit: rendered 1, skipped 0, failed 1")
    records = {Path(r["input"]).name: r["status"] for r in read_manifest(out / "manifest.jsonl")}
    assert records == {"a.obj": "ok", "gone.obj": "error"}


DASK_BATCH = """
import os, sys
import distributed, rasterkit
from rasterkit.batch.manifest import read_manifest

with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None,
                              silence_logs=50) as cluster, distributed.Client(cluster) as client:
    summary = rasterkit.render_many(FOLDER, OUT, client=client, size=(32, 24))
print(summary.done, summary.failed)
print(sorted(os.listdir(os.fsencode(OUT))))
print(sorted(os.fsencode(os.path.basename(r["input"])) for r in read_manifest(os.path.join(OUT, "manifest.jsonl"))))
"""


def test_a_dask_batch_keeps_a_name_that_is_not_utf8(folder, tmp_path):
    pytest.importorskip("distributed", reason="Dask's distributed is not installed")
    script = DASK_BATCH.replace("FOLDER", repr(str(folder))).replace("OUT", repr(str(tmp_path / "out")))
    done = run_python(script, timeout=120)  # a process of its own: the cluster's threads stay there
    assert done.code == 0, done.describe()
    assert done.stdout.splitlines() == [
        "3 0", repr([b"a\xff.png", b"b.png", b"c.png", b"manifest.jsonl"]), repr([ODD, b"b.obj", b"c.obj"])]
