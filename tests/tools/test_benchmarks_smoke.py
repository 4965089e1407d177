"""Smoke test of the benchmark suite: ``python -m benchmarks --quick --tiny`` still runs.

The suite runs once (64x48 images, one timed run) in a subprocess; its timings are not
checked, only that every family produced rasterkit's side, that the output files follow the
documented schema, and that every skipped peer was reported with its reason. Peers
(moderngl, OpenCV, trimesh) are optional: without them rasterkit's side must still run, and
the peer checks are skipped. The longest single step is the ``startup`` family's one cold
demo: ``rasterkit render --demo`` with an empty Numba cache compiles every kernel it needs.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from support.paths import MODELS, ROOT

FAMILIES = {"render", "aa", "cv", "textures", "svg", "fill", "threads", "lines2d", "loading", "cli", "scaling",
            "memory", "startup", "contention", "batch"}
RECORD_KEYS = {"family", "name", "peer", "sizes", "quantity", "rasterkit", "peer_value", "ratio",
               "throughput", "target", "runs", "note"}


@pytest.fixture(scope="module")
def suite(tmp_path_factory):
    out = tmp_path_factory.mktemp("bench")
    done = subprocess.run([sys.executable, "-m", "benchmarks", "--quick", "--tiny", "--out", str(out)],
                          check=False, cwd=ROOT, capture_output=True, text=True, timeout=600,
                          env={**os.environ, "PYTHONPATH": os.pathsep.join(
                              [str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])])})
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    return out, json.loads((out / "results.json").read_text()), done.stdout


def test_rasterkit_side_of_every_family(suite):
    out, results, stdout = suite
    assert results["schema"] == 1 and results["profile"] == "tiny"
    assert {"platform", "cpu_count", "threads", "versions"} <= set(results["machine"])
    records = results["records"]
    families = {r["family"] for r in records}
    without_models = {"render", "aa", "cv", "textures", "svg", "loading", "cli", "memory", "contention", "batch"}
    expected = FAMILIES if MODELS.is_dir() else FAMILIES - without_models
    assert expected <= families
    for r in records:
        assert set(r) == RECORD_KEYS
        assert r["rasterkit"] >= 0 if r["quantity"] == "peak_bytes" else r["rasterkit"] > 0
        if r["peer_value"]:
            assert r["ratio"] == pytest.approx(r["rasterkit"] / r["peer_value"])
    for skipped in results["skipped"]:  # never silently: each reason is printed
        assert skipped["reason"] and skipped["reason"] in stdout
    markdown = (out / "results.md").read_text()
    assert all(r["name"] in markdown for r in records)
    assert (out / "scaling_triangles.png").stat().st_size > 0


def test_peers_measured_when_installed(suite):
    for module in ("moderngl", "cv2", "trimesh"):
        pytest.importorskip(module)
    _, results, _ = suite
    no_gl = [s["reason"] for s in results["skipped"] if s["what"] == "llvmpipe"]
    if no_gl:
        pytest.skip(f"llvmpipe could not start: {no_gl[0]}")
    peers = {r["peer"] for r in results["records"]}
    assert {"llvmpipe", "cv2.polylines", "trimesh"} <= peers
    fill = [r for r in results["records"] if r["family"] == "fill" and r["peer"] == "llvmpipe"]
    assert fill and fill[0]["throughput"]["unit"] == "pixel/s"
    if MODELS.is_dir():
        assert {r["peer"] for r in results["records"] if r["family"] == "contention"} == {"llvmpipe"}
        assert "startup/warm/solid/suzanne/64x48" in {r["name"] for r in results["records"]
                                                      if r["peer"] == "trimesh + moderngl script"}


def test_startup_and_contention_records(suite):
    """The process-starting families: import times, one cold demo (empty Numba cache) with its
    peak memory, the warm CLI run; N processes rendering at once, each and in total."""
    _, results, stdout = suite
    records = {r["name"]: r for r in results["records"]}
    for command in ('python -c "import rasterkit"', "rasterkit --help", "rasterkit render --help"):
        r = records[f"startup/import/{command}"]
        assert r["family"] == "startup" and r["peer"] == "python -c pass" and r["peer_value"] > 0
    assert isinstance(records["startup/import/rasterkit --help"]["sizes"]["imports_numba"], bool)
    assert "rasterkit --help imports numba: " in stdout
    assert records["startup/cold-alone/demo"]["rasterkit"] > 0
    rss = records["startup/cold-alone/demo/max-rss"]
    assert rss["quantity"] == "peak_bytes" and rss["rasterkit"] > 20 * 2**20  # numba alone is more
    assert any(s["what"].startswith("cold sequence") for s in results["skipped"])  # not in tiny
    if not MODELS.is_dir():
        return
    assert records["startup/warm/solid/suzanne/64x48"]["rasterkit"] > 0
    base = "contention/solid/suzanne/64x48"
    for count in (1, 2):
        total = records[f"{base}/{count}proc/total"]
        assert total["sizes"]["processes"] == count and total["throughput"]["unit"] == "frame/s"
        fps = [records[f"{base}/{count}proc/process{k}"]["throughput"]["rasterkit"]
               for k in range(1, count + 1)]
        assert total["throughput"]["rasterkit"] == pytest.approx(sum(fps))
        assert f"{count} process" in stdout
    assert "x of one alone" in stdout


def test_thread_watch_runs_each_checkout_and_rejects_other_folders(tmp_path):
    """``python -m benchmarks.thread_watch``: one run per checkout at least, a summary line per
    checkout; a folder that is not a rasterkit checkout is a one-line usage error (exit 2)."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])])}
    done = subprocess.run([sys.executable, "-m", "benchmarks.thread_watch", "--minutes", "0", "--rounds", "2", "."],
                          check=False, cwd=ROOT, capture_output=True, text=True, timeout=300, env=env)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    lines = done.stdout.splitlines()
    assert len(lines) == 2 and lines[0].endswith("x") and "1 thread" in lines[0]
    assert lines[1].startswith(f"{ROOT}: 1 runs, median ") and "below 1.7x" in lines[1]
    bad = subprocess.run([sys.executable, "-m", "benchmarks.thread_watch", str(tmp_path)],
                         check=False, cwd=ROOT, capture_output=True, text=True, timeout=60, env=env)
    assert bad.returncode == 2 and "not a rasterkit checkout" in bad.stderr and "Traceback" not in bad.stderr


def test_first_renders_in_each_mode_asked_for(tmp_path, monkeypatch):
    """``--first-modes``: each model's first render in every mode asked for, each in a cache
    of its own; solid keeps its record names, the other modes are named after the mode."""
    import dataclasses

    monkeypatch.syspath_prepend(str(ROOT))  # the suite is not installed with the package
    from benchmarks import first_models, report
    from benchmarks.__main__ import main
    from benchmarks.settings import TINY

    for _, path in first_models.MODELS:
        (tmp_path / path).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / path).write_text("v 0 0 0\n")
    monkeypatch.setattr(first_models, "MODELS_DIR", tmp_path)
    launched = []

    def launch(argv, env, scratch):
        launched.append((argv[argv.index("--mode") + 1], env["NUMBA_CACHE_DIR"]))
        return {"seconds": 3.0, "user": 5.0}

    monkeypatch.setattr(first_models, "launch", launch)
    results = report.Results()
    settings = dataclasses.replace(TINY, first_model_runs=1, first_model_modes=("solid", "hidden"))
    first_models.run(settings, results, tmp_path)
    n = len(first_models.MODELS)
    assert [mode for mode, _ in launched] == ["solid"] * n + ["hidden"] * n
    assert len({cache for _, cache in launched}) == 2 * n  # every render in an empty cache of its own
    names = {r.name: r.rasterkit for r in results.records}
    assert names["startup/first-model/beast"] == 3.0
    assert names["startup/first-model/hidden/beast/user-cpu"] == 5.0
    assert main(["--only", "startup", "--first-modes", "solid,dashed"]) == 2
