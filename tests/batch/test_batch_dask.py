"""Batches on a Dask cluster: a LocalCluster of two worker processes, started by a process
whose kernels have already run; the same images as one process; a worker killed mid-run."""

from __future__ import annotations

import os
import signal
import threading
import time
from pathlib import Path

import pytest

import rasterkit
from rasterkit import shapes
from rasterkit.batch.manifest import read_manifest
from support.frames import batch_matches_the_api, model_folder
from support.objfiles import write_obj

distributed = pytest.importorskip("distributed", reason="Dask's distributed is not installed ('rasterkit[dask]')")


@pytest.fixture(scope="module")
def cluster():
    # kernels run in this process before the workers start
    camera = rasterkit.Camera.look_at((2, 2, 3), (0, 0, 0), width=64, height=48)
    rasterkit.render(shapes.icosphere(3), camera, mode="solid+wire")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                  silence_logs=50) as local, distributed.Client(local) as client:
        yield client


def _folder(tmp_path: Path, n: int, subdivisions: int) -> Path:
    folder = tmp_path / "models"
    folder.mkdir()
    for k in range(n):
        write_obj(folder / f"m{k:02d}.obj", shapes.icosphere(subdivisions) if k % 3 else shapes.torus(rings=16 + k))
    (folder / "zz_broken.obj").write_text("f 1 2 3\n")
    return folder


def test_a_cluster_writes_the_images_of_one_process(cluster, tmp_path):
    folder = _folder(tmp_path, 6, 2)
    local = rasterkit.render_many(folder, tmp_path / "local", size=(64, 48), mode="hidden")
    remote = rasterkit.render_many(folder, tmp_path / "dask", client=cluster, size=(64, 48), mode="hidden")
    assert (remote.done, remote.failed, remote.exit_code) == (local.done, local.failed, local.exit_code) == (6, 1, 2)
    for image in (tmp_path / "local").glob("*.png"):
        assert (tmp_path / "dask" / image.name).read_bytes() == image.read_bytes()
    records = read_manifest(tmp_path / "dask" / "manifest.jsonl")
    assert len(records) == 7 and len({r["input"] for r in records}) == 7
    broken = [r for r in records if r["status"] == "error"]
    assert len(broken) == 1 and "zz_broken.obj:1" in broken[0]["error"]
    # each task rendered with one kernel thread: 2 workers x 1 thread on this host's cores
    threads = cluster.submit(lambda: __import__("rasterkit.runtime.threads").runtime.threads.get_threads(), pure=False).result()
    assert threads == max(1, len(os.sched_getaffinity(0)) // 2)


def test_killing_a_worker_still_yields_every_image_and_a_complete_manifest(cluster, tmp_path):
    folder = _folder(tmp_path, 24, 4)
    result = {}
    thread = threading.Thread(target=lambda: result.update(
        s=rasterkit.render_many(folder, tmp_path / "out", client=cluster, size=(800, 600), mode="solid", samples=32)))
    thread.start()
    manifest = tmp_path / "out" / "manifest.jsonl"
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and len(read_manifest(manifest) if manifest.exists() else []) < 2:
        time.sleep(0.01)
    pids = cluster.run(os.getpid)
    assert thread.is_alive()  # the batch is still running
    os.kill(next(iter(pids.values())), signal.SIGKILL)
    thread.join(timeout=600)
    summary = result["s"]
    assert (summary.done, summary.failed) == (24, 1)
    records = read_manifest(tmp_path / "out" / "manifest.jsonl")
    assert sorted(r["input"] for r in records) == sorted(str(p) for p in folder.glob("*.obj"))
    assert len(list((tmp_path / "out").glob("*.png"))) == 24
    assert not list((tmp_path / "out").glob(".*.tmp"))


def test_the_address_of_a_worker_is_not_taken_for_a_scheduler(cluster):
    from rasterkit.batch import dask_engine as _dask
    from rasterkit.batch.report import UsageError

    worker = next(iter(cluster.scheduler_info()["workers"]))
    with pytest.raises(UsageError, match="not a Dask scheduler .it says Worker"):
        _dask.client_for(worker)
    client = _dask.client_for(cluster.scheduler.address)
    try:
        assert client.scheduler_info()["address"] == cluster.scheduler.address
    finally:
        client.close()


def test_a_cluster_draws_every_field_of_the_render_options(cluster, tmp_path):
    """The task reaches Dask's workers whole: every field of RenderOptions (and the View) in
    the images, bit for bit the API's frames (tests/support/frames.py)."""
    batch_matches_the_api(model_folder(tmp_path / "models"), tmp_path / "out", client=cluster)
