"""The ``textures`` benchmark family at the tiny profile, and the ``startup`` family's first
textured render (its processes faked), so that neither rots.

``python -m benchmarks --only textures --tiny`` runs in a subprocess (64x48 frames, one timed
run): timings are not checked, only the records — every frame of spot and fuze, against
llvmpipe when moderngl can start it, the texture's memory and the 50 frames — and that every
skip was reported with its reason.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys

import pytest

from support.paths import MODELS, ROOT

FRAMES = ("smooth/trilinear/spot", "flat/trilinear/spot", "smooth/bilinear/spot", "smooth/untextured/spot",
          "smooth/trilinear/fuze")


@pytest.fixture(scope="module")
def family(tmp_path_factory):
    out = tmp_path_factory.mktemp("textures")
    done = subprocess.run([sys.executable, "-m", "benchmarks", "--only", "textures", "--tiny", "--out", str(out)],
                          check=False, cwd=ROOT, capture_output=True, text=True, timeout=600,
                          env={**os.environ, "PYTHONPATH": os.pathsep.join(
                              [str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])])})
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    results = json.loads((out / "results.json").read_text())
    return {r["name"]: r for r in results["records"]}, results["skipped"], done.stdout


def test_every_skip_is_reported_with_its_reason(family):
    records, skipped, stdout = family
    assert all(r["family"] == "textures" for r in records.values())
    for skip in skipped:
        assert skip["reason"] and skip["reason"] in stdout
    if not MODELS.is_dir():
        assert not records and any("not found" in s["reason"] for s in skipped)


def test_textured_frames_of_spot_and_fuze(family, models_dir):
    records, skipped, stdout = family
    for frame in FRAMES:
        r = records[f"textures/{frame}/64x48"]
        assert r["quantity"] == "seconds" and r["rasterkit"] > 0 and r["throughput"]["unit"] == "tri/s"
        assert r["target"] is None  # the bar is at 1920x1080 only
    gl = [r for r in records.values() if r["peer"] == "llvmpipe"]
    if not gl:
        pytest.skip(f"llvmpipe did not run: {[s['reason'] for s in skipped]}")
    for r in gl:  # both sides drew the same image
        share = float(re.search(r"([\d.]+) % of \d+ covered pixels within 2/255", r["note"]).group(1))
        assert share > 90, r["note"]
    assert "texturing spot's smooth trilinear frame costs: rasterkit +" in stdout


def test_texture_memory_and_fifty_frames(family, models_dir):
    records, _, _ = family
    held = records["textures/memory/spot_texture.png/held"]
    assert held["quantity"] == "bytes" and held["peer_value"] == 1024 * 1024 * 3
    assert held["target"]["max_ratio"] == 1.4
    assert held["ratio"] >= 4 / 3  # the mipmaps alone are a third more than the image
    for what in ("rss", "traced"):
        r = records[f"textures/memory/spot/64x48/50-frames/{what}"]
        assert r["rasterkit"] > 0 and r["peer_value"] > 0 and r["sizes"]["frames"] == 50
        assert "shared: yes" in r["note"]
    assert records["textures/memory/spot/64x48/50-frames/traced-peak"]["quantity"] == "peak_bytes"


def test_first_textured_render_against_untextured(tmp_path, monkeypatch):
    """Each render in an empty cache of its own, the order alternating; the difference of the
    medians is recorded against the 8 s budget."""
    import dataclasses

    monkeypatch.syspath_prepend(str(ROOT))  # the suite is not installed with the package
    from benchmarks import first_textured, launch as launching, report
    from benchmarks.settings import TINY

    fuze = tmp_path / first_textured.MODEL[1]
    fuze.parent.mkdir(parents=True)
    fuze.write_text("v 0 0 0\n")
    monkeypatch.setattr(first_textured, "MODELS_DIR", tmp_path)
    launched = []

    def launch(argv, env, scratch):
        textured = first_textured.UNTEXTURED not in argv
        launched.append((textured, env["NUMBA_CACHE_DIR"]))
        assert argv[-4:] == ["--mode", "solid", "--shading", "smooth"] or argv[-1] == first_textured.UNTEXTURED
        return {"seconds": 20.0 if textured else 14.0, "user": 30.0 if textured else 21.0}

    monkeypatch.setattr(launching, "launch", launch)
    results = report.Results()
    first_textured.run(TINY, results, tmp_path)
    assert not results.records and "not measured in the tiny profile" in results.skipped[0]["reason"]
    first_textured.run(dataclasses.replace(TINY, textured_cold_runs=2), results, tmp_path)
    assert [textured for textured, _ in launched] == [True, False, False, True]
    assert len({cache for _, cache in launched}) == 4
    records = {r.name: r for r in results.records}
    assert records["startup/first-textured/fuze"].ratio == pytest.approx(20 / 14)
    assert records["startup/first-textured/fuze/user-cpu"].peer_value == 21.0
    added = records["startup/first-textured/fuze/added"]
    assert added.rasterkit == pytest.approx(6.0) and added.peer_value == 8.0 and added.met


def test_first_lit_renders_against_the_plain_one(tmp_path, monkeypatch):
    """Phong, shadows and AO first renders each in an empty cache of its own, the order
    rotating; each one's difference of medians is recorded against the 8 s budget."""
    import dataclasses

    monkeypatch.syspath_prepend(str(ROOT))
    from benchmarks import first_lit, launch as launching, report
    from benchmarks.settings import TINY

    (tmp_path / f"{first_lit.MODEL}.obj").write_text("v 0 0 0\n")
    monkeypatch.setattr(first_lit, "model_path", lambda name: tmp_path / f"{name}.obj")
    seconds = {"plain": 14.0, "phong": 20.0, "shadows": 21.0, "ao": 25.0}
    launched = []

    def launch(argv, env, scratch):
        flags = argv[argv.index("solid") + 1:]
        label = next((name for name, wanted in first_lit.VARIANTS.items() if flags == wanted), "plain")
        assert label != "plain" or not flags
        launched.append((label, env["NUMBA_CACHE_DIR"]))
        return {"seconds": seconds[label], "user": 2 * seconds[label]}

    monkeypatch.setattr(launching, "launch", launch)
    results = report.Results()
    first_lit.run(TINY, results, tmp_path)
    assert not results.records and "not measured in the tiny profile" in results.skipped[0]["reason"]
    first_lit.run(dataclasses.replace(TINY, lit_cold_runs=2), results, tmp_path)
    assert [label for label, _ in launched] == ["plain", "phong", "shadows", "ao", "phong", "shadows", "ao", "plain"]
    assert len({cache for _, cache in launched}) == 8
    records = {r.name: r for r in results.records}
    for label in ("phong", "shadows", "ao"):
        added = records[f"startup/first-lit/{label}/stanford-bunny/added"]
        assert added.rasterkit == pytest.approx(seconds[label] - 14.0) and added.peer_value == 8.0
        assert added.met == (seconds[label] - 14.0 <= 8.0)
