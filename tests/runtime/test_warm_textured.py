"""A first textured render: the command line guesses from the model's ``.mtl`` that it will be
drawn textured (:func:`rasterkit.formats.texture_maps`, before the model is read), and its
helpers compile the textured band worker and its resolve, not the untextured ones; this
process then compiles neither, and the image is the one a warm render draws."""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

import rasterkit
from rasterkit.formats import texture_maps
from rasterkit.obj.peek import HEAD_BYTES, map_kinds
from rasterkit.runtime.warm import helper_style
from rasterkit.runtime.warm_lit import LIT_ROWS, TEXTURED_ROWS, frame_resolve
from rasterkit.runtime.warm_mesh import helper_mesh
from support.startup import COMPILE_LOG, ENV

QUAD_OBJ = """\
mtllib {library}
v -1 -1 0
v 1 -1 0
v 1 1 0
v -1 1 0
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vn 0 0 1
usemtl skin
f 1/1/1 2/2/1 3/3/1 4/4/1
"""


def _texture(path: Path) -> None:
    rng = np.random.default_rng(5)
    Image.fromarray(rng.integers(0, 256, (8, 8, 3), dtype=np.uint8)).save(path)


def _model(folder: Path, mtl: str, library: str = "quad.mtl") -> Path:
    (folder / library).write_text(mtl)
    obj = folder / "quad.obj"
    obj.write_text(QUAD_OBJ.format(library=library))
    return obj


def test_the_maps_a_models_library_names_are_guessed_before_it_is_read(tmp_path):
    _texture(tmp_path / "skin uv.png")
    (tmp_path / "maps").mkdir()
    _texture(tmp_path / "maps" / "bumps.png")
    obj = _model(tmp_path, "newmtl skin\nKd 1 1 1\nmap_Kd skin uv.png\n")
    assert map_kinds(obj) == texture_maps(obj) == {"diffuse"}  # a file name with a space
    obj = _model(tmp_path, "newmtl skin\nmap_d -s 2 2 1 skin uv.png\nnewmtl unused\nbump -bm 2 maps\\bumps.png\n")
    assert map_kinds(obj) == {"alpha", "normal"}  # options skipped, Windows folders, every material
    obj = _model(tmp_path, "newmtl skin\nmap_Kd absent.png\nnorm\n")  # a missing file, a map without one
    assert map_kinds(obj) == frozenset()
    obj = _model(tmp_path, "newmtl skin\nmap_Kd skin uv.png\n", library="my library.mtl")
    assert map_kinds(obj) == {"diffuse"}
    (tmp_path / "my library.mtl").unlink()
    assert map_kinds(obj) == frozenset()  # the library is missing: no guess, no error
    # mtllib only after the first HEAD_BYTES: not looked for (the guess stays cheap)
    late = tmp_path / "late.obj"
    late.write_text("# padding\n" * (HEAD_BYTES // 10 + 1) + "mtllib quad.mtl\n" + QUAD_OBJ.format(library="quad.mtl"))
    _model(tmp_path, "newmtl skin\nmap_Kd skin uv.png\n")
    assert map_kinds(late) == frozenset() and map_kinds(tmp_path / "quad.obj") == {"diffuse"}
    stl = tmp_path / "part.stl"
    stl.write_text("solid part\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
                   "endloop\nendfacet\nendsolid part\n")
    assert texture_maps(stl) == frozenset() and texture_maps(tmp_path / "nothing.obj") == frozenset()


def test_a_helpers_sphere_has_the_kinds_of_map_the_model_has():
    """The helper's frame must take the same variant of the band worker as the model's:
    textured, cut out where its opacity is below one half, normal-mapped."""
    for maps, cutout, normal_mapped in ((("diffuse",), False, False), (("alpha", "diffuse"), True, False),
                                        (("diffuse", "normal"), False, True)):
        textured = helper_mesh(maps, vertex_normals=True, face_normals=True).textured
        assert (textured.cutout, textured.normal_mapped) == (cutout, normal_mapped)
    assert helper_mesh((), vertex_normals=True, face_normals=True).textured is None
    options = rasterkit.RenderOptions(shading="smooth")
    assert frame_resolve(helper_style(options, frozenset({"diffuse"}))) == TEXTURED_ROWS
    assert frame_resolve(helper_style(options)) is None
    assert frame_resolve(helper_style(options.replace(shading="phong"))) == LIT_ROWS
    assert helper_style(options.replace(textures=False), frozenset({"diffuse"}))["maps"] == []


# A cold command-line render in this interpreter, Numba's compile events recorded with the
# process that compiled (forked helpers inherit the listener and append their own lines).
FIRST_TEXTURED = COMPILE_LOG + """
from rasterkit.cli import main

code = main(sys.argv[2:])
print(json.dumps({"pid": os.getpid(), "code": code}))
"""


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="the resolve's helper is forked: Linux only")
def test_a_first_textured_render_compiles_its_band_worker_and_resolve_in_helpers(tmp_path):
    _texture(tmp_path / "skin.png")
    obj = _model(tmp_path, "newmtl skin\nKd 1 1 1\nmap_Kd skin.png\n")
    cache = tmp_path / "cache"
    cache.mkdir()
    log, out = tmp_path / "compiled.jsonl", tmp_path / "first.png"
    done = subprocess.run([sys.executable, "-c", FIRST_TEXTURED, str(log), "render", str(obj), "-o", str(out),
                           "--mode", "solid", "--shading", "smooth", "--size", "64x48"],
                          capture_output=True, text=True, env={**ENV, "NUMBA_CACHE_DIR": str(cache)}, timeout=900,
                          stdin=subprocess.DEVNULL)
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout.strip().splitlines()[-1])
    assert report["code"] == 0
    compiled = [tuple(json.loads(line)) for line in log.read_text().splitlines()]
    band = [pid for pid, name in compiled if name == "draw_bands"]
    rows = [pid for pid, name in compiled if name == "resolve_textured_rows"]
    assert len(band) == 1 and len(rows) == 1  # each compiled once, and once only
    assert len({report["pid"], band[0], rows[0]}) == 3  # in two helpers, neither this process
    assert not [name for pid, name in compiled if name == "resolve_lit_rows"]

    # the picture a warm render of the same model draws, through the API
    mesh = rasterkit.load(obj)
    view = rasterkit.View(size=(64, 48))
    fb = rasterkit.render(mesh, view.camera_for(mesh), options=rasterkit.RenderOptions(mode="solid", shading="smooth"))
    assert fb.color.reshape(-1, 3).tolist() != [[255, 255, 255]] * (64 * 48)
    np.testing.assert_array_equal(np.asarray(Image.open(out)), fb.color)
    assert os.path.getsize(out) > 0


class _Pipe:
    def fileno(self):
        return 99

    def close(self):
        pass


class _Process:
    def __init__(self):
        self.stdout = _Pipe()


@pytest.mark.parametrize("forks", [True, False])
def test_a_first_textured_or_lit_render_after_plain_ones_gets_its_helpers(monkeypatch, forks):
    """The plain band worker is cached (a render of the demo came first), the frame's resolve
    is not: the frame's variant of the band worker is not cached either, so the helpers start
    (the resolve's own only where helpers are forked); the guess at the model's maps is made
    only then, and not at all when everything is cached."""
    from rasterkit.runtime import warm

    orders, guesses = [], []
    cached = {"draw_bands", "bin_records"}
    monkeypatch.setattr(warm, "_spawn", lambda order, report=False: orders.append(order) or _Process())
    monkeypatch.setattr(warm, "_forks", lambda: forks)
    monkeypatch.setattr(warm, "_cached", lambda dispatcher: dispatcher.py_func.__name__ in cached)
    monkeypatch.setattr(warm, "_helpers", {})
    monkeypatch.setattr(warm, "_lit_helper", None)
    monkeypatch.setattr(warm._threads, "intercept", lambda hook: None)
    monkeypatch.setattr(warm, "prepare_numba", lambda: None)

    def guess():
        guesses.append(1)
        return frozenset({"diffuse"})

    smooth = rasterkit.RenderOptions(mode="solid", shading="smooth")
    warm.start(smooth, depth=False, loading=True, maps=guess)
    assert guesses == [1]
    resolves = [order for order in orders if order.get("lit_rows")]
    bands = [order for order in orders if "draw_bands" in order.get("workers", ())]
    assert [order["lit_rows"] for order in resolves] == ([TEXTURED_ROWS] if forks else [])
    assert len(bands) == 1 and bands[0]["options"]["maps"] == ["diffuse"]
    assert bands[0].get("resolve") == (TEXTURED_ROWS if forks else None)

    orders.clear()
    monkeypatch.setattr(warm, "_helpers", {})
    monkeypatch.setattr(warm, "_lit_helper", None)
    warm.start(smooth.replace(shading="phong"), depth=False, loading=True)  # lit per pixel, untextured
    assert [order["lit_rows"] for order in orders if order.get("lit_rows")] == ([LIT_ROWS] if forks else [])
    assert any("draw_bands" in order.get("workers", ()) for order in orders)

    orders.clear()
    monkeypatch.setattr(warm, "_helpers", {})
    cached.update({"resolve_textured_rows", "resolve_lit_rows"})
    warm.start(smooth, depth=False, loading=True, maps=guess)
    assert orders == [] and guesses == [1]  # all cached: no helper and no guess
