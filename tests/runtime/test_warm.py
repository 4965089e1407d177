"""rasterkit.runtime.warm, the first run's helper process: it compiles only the mode's band worker
into Numba's cache, the main process then loads that worker instead of compiling it, and a
first CLI render (with the helper) draws the same image as a cached one; the demo's helper
compiles the OBJ reader for the first model.

Each test compiles kernels into an empty NUMBA_CACHE_DIR of its own, in fresh interpreters
(about 5-15 s each on two cores)."""

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

import rasterkit
from rasterkit.runtime import warm as _warm
from rasterkit.runtime import warm_helper
from rasterkit.runtime.forked import Forked
from rasterkit.runtime.notice import MESSAGE
from rasterkit.cli import _parser
from rasterkit.cli.args import view_from_args
from rasterkit.obj import load_obj
from rasterkit.obj.chunks import CHUNK_BYTES
from rasterkit.options import RenderOptions
from support.startup import COMPILE_LOG, ENV

SOLID_ORDER = {
    "options": {"mode": "solid", "cull": "back", "shading": "flat", "background": "white", "aa": False},
    "depth": False,
    "workers": ["draw_bands"],
}

CUBE_OBJ = """\
# a cube, quads counter-clockwise seen from outside
v -1 -1 -1
v 1 -1 -1
v 1 1 -1
v -1 1 -1
v -1 -1 1
v 1 -1 1
v 1 1 1
v -1 1 1
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 3 4 8 7
f 2 3 7 6
f 1 5 8 4
"""


def _env(cache: Path) -> dict:
    cache.mkdir(exist_ok=True)
    assert not any(cache.iterdir())
    return {**ENV, "NUMBA_CACHE_DIR": str(cache)}


def _run(argv, env, timeout=180) -> subprocess.CompletedProcess:
    return subprocess.run(argv, capture_output=True, text=True, env=env, timeout=timeout, stdin=subprocess.DEVNULL)


def _indexes(cache: Path) -> list[str]:
    """File names of Numba's cache indexes (``module.function-line.pyXY.nbi``)."""
    return sorted(p.name for p in cache.rglob("*.nbi"))


def _kernel_indexes(cache: Path, module: str, function: str) -> list[str]:
    return [name for name in _indexes(cache) if name.startswith(f"{module}.{function}-")]


# Renders a small solid mesh and prints, as JSON, the names of the functions Numba compiled
# (numba:compile fires only for a real compile, after the on-disk cache was tried).
SOLID_RENDER = """
import json
from numba.core import event

compiled = []

class Record(event.Listener):
    def on_start(self, ev):
        compiled.append(ev.data["dispatcher"].py_func.__name__)

    def on_end(self, ev):
        pass

event.register("numba:compile", Record())

import rasterkit
from rasterkit import shapes
from rasterkit.camera import Camera

camera = Camera.look_at(eye=(2.0, 1.5, 3.0), target=(0.0, 0.0, 0.0), width=40, height=30)
fb = rasterkit.render(shapes.icosphere(1), camera, mode="solid")
print(json.dumps({"compiled": sorted(set(compiled)), "colours": len({tuple(p) for p in fb.color.reshape(-1, 3)})}))
"""


def test_helpers_compile_only_their_workers_in_order_and_the_render_loads_them(tmp_path):
    """A helper compiles only the workers it is given, in the render's order, naming each as it
    is cached; a second helper adds to the same cache; the render's own process then compiles
    none of them. (One cache for both helpers: each cold compile of a render costs 10-20 s.)"""
    def names(style):
        return [[w.py_func.__name__ for w in workers] for workers in _warm.helped_workers(RenderOptions(**style))]

    assert names(SOLID_ORDER["options"]) == [["bin_records", "draw_bands"]]
    hidden = {**SOLID_ORDER["options"], "mode": "hidden"}
    assert names(hidden) == [["bin_records", "offset_depths", "draw_bands"],
                             ["setup_faces", "project_vertices", "plain_setup", "draw_edge_bands"]]
    assert names({**hidden, "mode": "wire"}) == [["draw_wire_bands"]]
    assert names({**hidden, "aa": True})[1][-1] == "draw_antialiased_bands"

    cache = tmp_path / "cache"
    env = _env(cache)
    helper = _run([sys.executable, "-m", "rasterkit.runtime.warm", json.dumps(SOLID_ORDER)], env)
    assert helper.returncode == 0, helper.stderr
    assert helper.stdout == "draw_bands\n"  # what it compiled, named as each is cached
    assert len(_kernel_indexes(cache, "bands", "draw_bands")) == 1, _indexes(cache)
    # The setup, binning and edge workers went through run_parallel's hook: not compiled.
    for module, function in [("face_setup", "setup_faces"), ("face_setup", "setup_vertices"), ("face_setup", "_setup_chunk"),
                             ("bands", "bin_records"), ("fans", "setup_cut_faces"),
                             ("edges_tested", "draw_edge_bands"), ("edges", "draw_wire_bands")]:
        assert not _kernel_indexes(cache, module, function), _indexes(cache)
    assert not [name for name in _indexes(cache) if "setup_" in name], _indexes(cache)

    # without "normals" the helper takes the face normals from NumPy: the face pass it
    # compiles with them is the one the render (normals from the kernel) loads
    workers = ["setup_vertices", "setup_faces", "bin_records"]
    order = {**SOLID_ORDER, "workers": workers, "normals": False}
    helper = _run([sys.executable, "-m", "rasterkit.runtime.warm", json.dumps(order)], env)
    assert helper.returncode == 0, helper.stderr
    assert helper.stdout.split() == workers

    main = _run([sys.executable, "-c", textwrap.dedent(SOLID_RENDER)], env)
    assert main.returncode == 0, main.stderr
    report = json.loads(main.stdout.splitlines()[-1])
    assert not {"draw_bands", *workers} & set(report["compiled"])  # loaded from the helpers' cache entries
    assert report["compiled"]  # the listener does see this process's compiles (the hand-off's small kernels)
    assert report["colours"] > 2  # background and some shades: the loaded workers drew
    assert len(_kernel_indexes(cache, "bands", "draw_bands")) == 1


def _png(path: Path) -> np.ndarray:
    with Image.open(path) as image:
        return np.asarray(image.convert("RGB"))


def _quad_grid(n: int) -> str:
    """An OBJ of n x n quads over a wavy sheet: more than two of the reader's chunks."""
    lines = [f"v {i / n:.6f} {j / n:.6f} {((i * 7 + j * 3) % 11) / 50:.6f}"
             for j in range(n + 1) for i in range(n + 1)]
    lines += [f"f {j * (n + 1) + i + 1} {j * (n + 1) + i + 2} {(j + 1) * (n + 1) + i + 2} {(j + 1) * (n + 1) + i + 1}"
              for j in range(n) for i in range(n)]
    return "\n".join(lines) + "\n"


def test_first_cli_render_announces_its_compile_once_and_equals_a_cached_one_and_the_api(tmp_path):
    """A user's first ``rasterkit render model.obj`` (an empty cache, its warm helpers, a model
    read in chunks on the threads) prints the one notice, draws what the cached run draws
    silently, and what the API draws."""
    model = tmp_path / "grid.obj"
    model.write_text(_quad_grid(300))
    assert model.stat().st_size > 2 * CHUNK_BYTES
    env = _env(tmp_path / "cache")
    options = ["--mode", "solid", "--size", "64x48"]
    images = []
    for k in range(2):
        out = tmp_path / f"out{k}.png"
        done = _run([sys.executable, "-m", "rasterkit", "render", str(model), "-o", str(out), *options], env,
                    timeout=600)
        assert done.returncode == 0, done.stderr
        assert done.stderr == (MESSAGE + "\n" if k == 0 else "")  # the notice on the first run only
        images.append(_png(out))
    assert _kernel_indexes(tmp_path / "cache", "bands", "draw_bands")

    first, second = images
    assert first.shape == (48, 64, 3)
    np.testing.assert_array_equal(first, second)
    colours = {tuple(p) for p in first.reshape(-1, 3)}
    assert (255, 255, 255) in colours and len(colours) >= 3  # background and several lit faces

    # The same picture in this process, through the API, with the command line's camera.
    args = _parser().parse_args(["render", str(model), "-o", "unused.png", *options])
    mesh = load_obj(model)
    fb = rasterkit.render(mesh, view_from_args(args).camera_for(mesh), mode="solid", cull=args.cull,
                          shading=args.shading, color=args.color, line_color=args.line_color,
                          background=args.background, aa=args.aa)
    np.testing.assert_array_equal(fb.color, first)


# Loads an OBJ file and prints, as JSON, the names of the functions Numba compiled.
LOAD_OBJ = """
import json, sys
from numba.core import event

compiled = []

class Record(event.Listener):
    def on_start(self, ev):
        compiled.append(ev.data["dispatcher"].py_func.__module__ + "." + ev.data["dispatcher"].py_func.__name__)

    def on_end(self, ev):
        pass

event.register("numba:compile", Record())

from rasterkit.obj import load_obj
from rasterkit.obj.chunks import CHUNK_BYTES

mesh = load_obj(sys.argv[1])
print(json.dumps({"compiled": sorted(set(compiled)), "faces": len(mesh.faces)}))
"""


READER_HELPER = """
import sys
from rasterkit.runtime import warm_helper, warm_obj

warm_obj._lower_priority = lambda: None
warm_helper.helper_main(sys.argv[1])
"""


def test_the_demos_helper_compiles_the_obj_reader_for_the_first_model(tmp_path):
    """The demo's helper reads its sample OBJ: afterwards a triangle model with texture
    coordinates, normals and a line loads without compiling any of the reader's kernels."""
    cache = tmp_path / "cache"
    env = _env(cache)
    # the helper's own entry, at this test's priority: at the lowest, which the helper takes,
    # the other tests on both cores left it so little time that it took 66-210 s in CI
    helper = _run([sys.executable, "-c", READER_HELPER, json.dumps({"obj": True})], env, timeout=900)
    assert helper.returncode == 0, helper.stderr
    for module, function in _warm.PARSER:  # Numba names a cache file after the module's last part
        assert _kernel_indexes(cache, module.rsplit(".", 1)[-1], function), _indexes(cache)
    model = tmp_path / "model.obj"
    model.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0.5 0.5\nvn 0 0 1\n"
                     "f 1/1/1 2/1/1 3/1/1\nf 1//1 3//1 4//1\nf 2 3 4\nl 1 3\n")
    loaded = _run([sys.executable, "-c", textwrap.dedent(LOAD_OBJ), str(model)], env)
    assert loaded.returncode == 0, loaded.stderr
    report = json.loads(loaded.stdout.splitlines()[-1])
    assert report["faces"] == 3
    assert not [name for name in report["compiled"] if name.startswith("rasterkit.")], report["compiled"]


def test_the_readers_helper_reads_its_sample_at_the_lowest_priority(monkeypatch):
    """Nothing waits for the demo's reader helper: it yields the cores to anything that does
    (the test above runs its work at the test's own priority)."""
    from rasterkit import obj
    from rasterkit.runtime import warm_obj

    calls = []
    monkeypatch.setattr(warm_obj.os, "nice", lambda step: calls.append(("nice", step)) or 19)
    monkeypatch.setattr(obj, "load_obj", lambda path, textures=True: calls.append(
        ("read", Path(path).read_text() == warm_obj.SAMPLE_OBJ, textures)))
    warm_obj.read_sample_obj()
    assert calls == [("nice", 19), ("read", True, False)]


def test_only_the_demo_starts_the_readers_helper_and_only_with_a_second_core(monkeypatch):
    orders = []
    monkeypatch.setattr(_warm, "_spawn", lambda order: orders.append(order) or object())
    monkeypatch.setattr(_warm, "_cached", lambda dispatcher: dispatcher.py_func.__name__ == "draw_wire_bands")
    monkeypatch.setattr(_warm, "_helpers", {})
    monkeypatch.setattr(_warm, "_parser_helper", None)
    wire = RenderOptions(mode="wire")
    monkeypatch.setattr(rasterkit.runtime.threads, "_threads", 1)
    _warm.start(wire, depth=False, loading=False)
    assert orders == []  # one core: the helper would only take it from the demo
    monkeypatch.setattr(rasterkit.runtime.threads, "_threads", 2)
    _warm.start(wire, depth=False, loading=True)  # a model: its own process compiles the reader
    assert orders == []
    _warm.start(wire, depth=False, loading=False)
    _warm.start(wire, depth=False, loading=False)  # once per process
    assert orders == [{"obj": True}]
    monkeypatch.setattr(_warm, "_parser_helper", None)
    monkeypatch.setattr(_warm, "_cached", lambda dispatcher: True)
    _warm.start(wire, depth=False, loading=False)  # all cached: no helper
    assert orders == [{"obj": True}]


class _Helper:
    """A stand-in for the reader's helper process: records what is asked of it; ``busy``: its
    first wait with a timeout times out."""
    stdout = None

    def __init__(self, busy=False):
        self.calls, self.busy = [], busy

    def wait(self, timeout=None):
        self.calls.append("wait")
        if self.busy and timeout is not None:
            self.busy = False
            raise subprocess.TimeoutExpired("helper", timeout)
        return 0

    def terminate(self):
        self.calls.append("terminate")


def _demo_with_a_readers_helper(monkeypatch) -> _Helper:
    helper = _Helper()
    parser = {function for _, function in _warm.PARSER}
    monkeypatch.setattr(_warm, "_spawn", lambda order, report=False: helper if order == {"obj": True} else None)
    monkeypatch.setattr(_warm, "_cached", lambda dispatcher: dispatcher.py_func.__name__ not in parser)
    monkeypatch.setattr(_warm, "_helpers", {})
    monkeypatch.setattr(_warm, "_parser_helper", None)
    monkeypatch.setattr(rasterkit.runtime.threads, "_threads", 2)
    return helper


def test_the_command_line_returns_only_after_the_readers_helper_has_ended(monkeypatch, tmp_path):
    """The demo's helper compiles while the demo renders; the command waits for it at its end
    (a script removing the environment right after must not race a process writing into it),
    and stops it, without waiting for its work, when the command itself fails."""
    from rasterkit.batch import plan, render_one
    from rasterkit.cli import main

    helper = _demo_with_a_readers_helper(monkeypatch)
    assert main(["render", "--demo", "-o", str(tmp_path / "x.png"), "--size", "16x12"]) == 0
    assert helper.calls == ["wait"] and _warm._parser_helper is None

    helper = _demo_with_a_readers_helper(monkeypatch)

    def fails(*args, **kwargs):
        raise RuntimeError("broken on purpose")

    monkeypatch.setattr(render_one, "load_drawn", fails)  # the model's failure, reported by the batch
    assert main(["render", "--demo", "-o", str(tmp_path / "y.png"), "--size", "16x12"]) == 1
    assert helper.calls == ["wait"] and _warm._parser_helper is None

    helper = _demo_with_a_readers_helper(monkeypatch)

    def escapes(*args, **kwargs):
        _warm.start(RenderOptions(), depth=False, loading=False)
        raise RuntimeError("broken on purpose")

    monkeypatch.setattr(plan, "render_jobs", escapes)  # an error out of the command itself
    assert main(["render", "--demo", "-o", str(tmp_path / "z.png"), "--size", "16x12"]) == 1
    assert helper.calls == ["terminate", "wait"] and _warm._parser_helper is None


def test_the_command_line_stops_a_helper_that_has_not_ended_in_time(monkeypatch):
    """The reader's helper runs at the lowest priority: where other work keeps the cores busy
    it may not end soon, and the command does not wait for it longer than FINISH_SECONDS."""
    helper = _Helper(busy=True)
    monkeypatch.setattr(_warm, "_parser_helper", helper)
    monkeypatch.setattr(_warm, "_lit_helper", None)
    _warm.finish()
    assert helper.calls == ["wait", "terminate", "wait"] and _warm._parser_helper is None


@pytest.mark.parametrize("forks", [True, False])
def test_a_wire_demo_gets_a_band_worker_helper_only_where_helpers_are_forked(monkeypatch, forks):
    """A forked helper costs no imports, so even the demo's wireframe (little else to compile
    here) hands its band worker to one; the reader's helper of low priority starts after it.
    A new interpreter would spend about a second importing: then only the reader's."""
    orders = []
    monkeypatch.setattr(_warm, "_spawn", lambda order, report=False: orders.append(order) or None)
    monkeypatch.setattr(_warm, "_forks", lambda: forks)
    monkeypatch.setattr(_warm, "_cached", lambda dispatcher: False)
    monkeypatch.setattr(_warm, "_helpers", {})
    monkeypatch.setattr(_warm, "_parser_helper", None)
    monkeypatch.setattr(rasterkit.runtime.threads, "_threads", 2)
    wire = RenderOptions(mode="wire", background="white")
    _warm.start(wire, depth=False, loading=False)
    style = _warm.helper_style(wire)
    band = {"options": style, "depth": False, "workers": ["draw_wire_bands"], "normals": True, "frame_only": False}
    assert orders == ([band] if forks else []) + [{"obj": True}]


def test_a_hidden_render_of_a_model_starts_a_helper_for_each_band_worker(monkeypatch):
    """Faces and edges: one helper for the triangles' binning, depth offset and band worker,
    one for the face pass and the edges' setup and band worker; only the workers that are not
    cached; none when all are."""
    orders = []
    monkeypatch.setattr(_warm, "_spawn", lambda order, report=False: orders.append(order) or None)
    monkeypatch.setattr(_warm, "_helpers", {})
    monkeypatch.setattr(_warm, "_cached", lambda dispatcher: dispatcher.py_func.__name__ == "project_vertices")
    hidden = RenderOptions(**{**SOLID_ORDER["options"], "mode": "hidden"})
    _warm.start(hidden, depth=False, loading=True)
    assert [order["workers"] for order in orders] == [["bin_records", "offset_depths", "draw_bands"],
                                                      ["setup_faces", "plain_setup", "draw_edge_bands"]]
    assert [order["normals"] for order in orders] == [False, False]  # this process compiles them
    orders.clear()
    monkeypatch.setattr(_warm, "_cached", lambda dispatcher: True)
    _warm.start(hidden, depth=False, loading=True)
    assert orders == []


def test_a_forked_helper_can_be_waited_for_and_stopped():
    import signal
    import time

    import pytest

    if not hasattr(os, "fork"):
        pytest.skip("no fork on this platform")
    pid = os.fork()
    if pid == 0:  # the child only sleeps
        time.sleep(30)
        os._exit(0)
    helper = Forked(pid, None)
    with pytest.raises(subprocess.TimeoutExpired):
        helper.wait(timeout=0.05)
    helper.terminate()
    assert helper.wait(timeout=10) == -signal.SIGTERM
    helper.terminate()  # ended: nothing to stop, no error
    assert helper.wait() == -signal.SIGTERM


FORKED_HELPER = """
import json, sys
from rasterkit.runtime import warm as _warm
from rasterkit.runtime.forked import Forked
helper = _warm._spawn({"options": json.loads(sys.argv[1]), "depth": False, "workers": ["bin_records"]}, report=True)
print(json.dumps({"forked": isinstance(helper, Forked), "reports": helper.stdout.read().decode().split(),
                  "code": helper.wait(timeout=120)}))
"""


def test_a_helper_is_forked_on_linux_and_reports_on_its_pipe(tmp_path):
    """Forked (no new interpreter) on Linux when no other thread runs, as at the start of a
    command-line render; it names what it compiled on its pipe as a new interpreter's does."""
    import pytest

    if not sys.platform.startswith("linux"):
        pytest.skip("forks only on Linux")
    done = _run([sys.executable, "-c", FORKED_HELPER, json.dumps(SOLID_ORDER["options"])], _env(tmp_path / "cache"))
    assert done.returncode == 0, done.stderr
    assert json.loads(done.stdout) == {"forked": True, "reports": ["bin_records"], "code": 0}
    assert _kernel_indexes(tmp_path / "cache", "bands", "bin_records")


LIT_HELPERS = COMPILE_LOG + """
from rasterkit.options import RenderOptions
from rasterkit.runtime import warm

warm.start(RenderOptions(mode="solid", shading="phong"), depth=False, loading=True)
lit, band = warm._lit_helper, warm._helpers["draw_bands"]
reports = band.stdout.read().decode().split()
print(json.dumps({"lit": lit.pid, "band": band.pid, "reports": reports, "codes": [band.wait(), lit.wait()]}))
"""


def test_a_phong_frames_lit_resolve_compiles_in_a_helper_of_its_own_and_the_band_workers_loads_it(tmp_path):
    """The lit resolve, the largest kernel, compiles in a helper of its own beside the band
    worker's helper; the band worker's helper waits for it and loads it from the cache instead
    of compiling it again, so it compiles exactly once (numba:compile fires only for a real
    compile, after the on-disk cache was tried). The arguments the helper makes
    (warm_lit.rows_args) are the band worker's records passed on as they are and slices of its
    scratch: what this shows for a flat phong frame holds for the other lit variants. The
    resolve's helper runs the kernels before the band worker as plain Python instead of
    compiling them (warm_lit.interpret_kernels): it compiles none that the band worker's
    helper compiles."""
    import pytest

    if not sys.platform.startswith("linux"):
        pytest.skip("forks only on Linux")
    log = tmp_path / "compiled.jsonl"
    done = _run([sys.executable, "-c", LIT_HELPERS, str(log)], _env(tmp_path / "cache"))
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout)
    assert report["codes"] == [0, 0] and "draw_bands" in report["reports"]
    compiled = [tuple(json.loads(line)) for line in log.read_text().splitlines()]
    assert [pid for pid, name in compiled if name == "resolve_lit_rows"] == [report["lit"]]
    assert [pid for pid, name in compiled if name == "draw_bands"] == [report["band"]]
    assert _kernel_indexes(tmp_path / "cache", "phong_rows", "resolve_lit_rows")
    numba_own = {"impl", "<lambda>"}  # Numba's implementations of NumPy functions, compiled in each process
    by_lit = {name for pid, name in compiled if pid == report["lit"]} - numba_own
    by_band = {name for pid, name in compiled if pid == report["band"]} - numba_own
    assert "pack_colors" in by_band and not by_lit & by_band


def test_only_frames_lit_per_pixel_get_the_lit_resolves_helper():
    """Phong frames and frames with a light that casts shadows are lit per pixel (the lit
    resolve); flat and smooth frames under lights without shadows are lit per face or corner."""
    from rasterkit.runtime import warm_lit

    light = rasterkit.Light.directional((-1, -2, -1))
    assert warm_lit.lit_per_pixel(_warm.helper_style(RenderOptions(shading="phong")))
    assert not warm_lit.lit_per_pixel(_warm.helper_style(RenderOptions(shading="smooth", lights=[light])))
    assert warm_lit.lit_per_pixel(_warm.helper_style(RenderOptions(shading="flat", shadows=True, lights=[light])))
    assert not warm_lit.lit_per_pixel(_warm.helper_style(RenderOptions(shading="flat", shadows=True)))


def test_a_plain_python_worker_waits_for_no_helper():
    """run_parallel also runs plain functions (the OBJ reader's chunks): with helpers
    compiling, such a worker is no helper's and runs at once (it once raised AttributeError
    on the first render of an OBJ file with an empty cache)."""
    from rasterkit.runtime import warm

    def chunk_worker():
        pass

    saved = dict(warm._helpers)
    warm._helpers["draw_bands"] = object()  # a helper busy with another worker
    try:
        assert warm._wait_for_helper(chunk_worker, ()) is None
    finally:
        warm._helpers.clear()
        warm._helpers.update(saved)


def test_a_lit_renders_helper_draws_with_a_light_the_same_variant_of_every_kernel(monkeypatch):
    """Which lights a frame has changes no kernel's argument types, only whether it has some
    (and has ambient occlusion, whether some light casts shadows, and whether a spot or
    point light does: their maps are perspective, another resolve): the helper's order says
    so in JSON, and the helper lights its frame with one directional light, shadowed when one
    of the render's lights is, and a shadowed spot light when a spot or point casts shadows."""
    lit = RenderOptions(mode="solid", shading="phong", ao=True, shadows=True,
                        lights=[rasterkit.Light.point((1, 2, 3)), rasterkit.Light.ambient()])
    style = _warm.helper_style(lit)
    assert json.loads(json.dumps(style)) == style
    assert style["lights"] is True and style["ao"] is True and style["shadows"] is True
    assert style["perspective_shadows"] is True
    assert _warm.helper_style(RenderOptions(mode="solid"))["lights"] is False
    unshadowed = RenderOptions(shading="phong", lights=[rasterkit.Light.point((1, 2, 3))])
    assert _warm.helper_style(unshadowed)["shadows"] is False
    assert _warm.helper_style(unshadowed)["perspective_shadows"] is False
    one = RenderOptions(shading="phong", lights=[rasterkit.Light.ambient(), rasterkit.Light.spot(
        (0, 2, 0), (0, -1, 0), 30, 0.2, shadows=True)])
    assert _warm.helper_style(one)["shadows"] is True and _warm.helper_style(one)["perspective_shadows"] is True
    parallel = RenderOptions(shading="phong", lights=[rasterkit.Light.directional((0, -1, 0), shadows=True),
                                                      rasterkit.Light.point((1, 2, 3))])
    assert _warm.helper_style(parallel)["shadows"] is True
    assert _warm.helper_style(parallel)["perspective_shadows"] is False
    seen = []
    monkeypatch.setattr(rasterkit, "render", lambda mesh, camera, options: seen.append(options) or
                        rasterkit.Framebuffer(4, 4))
    monkeypatch.setattr(_warm._threads, "intercept", lambda hook: None)
    for options, kinds in ((lit, ["directional", "spot"]), (parallel, ["directional"])):
        seen.clear()
        warm_helper.run({"options": _warm.helper_style(options), "depth": False, "workers": ["draw_bands"]})
        (drawn,) = seen
        assert [light.kind for light in drawn.lights] == kinds
        assert all(light.shadows for light in drawn.lights)
        assert (drawn.shading, drawn.ao) == ("phong", options.ao)


def test_a_shadowed_frames_helper_compiles_the_frames_own_band_worker_and_leaves_the_maps(monkeypatch):
    """A frame with shadow maps calls the band worker first for the maps (depth only) and
    the visible surface, then for itself (lit per pixel: another variant, the longer one to
    compile). The helper compiles the frame's call only, and this process does not wait for
    it on the others (it compiles those itself meanwhile)."""
    from rasterkit.runtime import warm

    compiled, calls = [], []
    monkeypatch.setattr(warm._jit, "compile_apart", lambda worker, args: compiled.append((worker, args)))
    hook = warm_helper.compile_only(["draw_bands"], frame_only=True)
    monkeypatch.setattr(warm._threads, "_intercept", lambda worker, args: calls.append((worker, args))
                        or hook(worker, args))
    mesh = rasterkit.shapes.icosphere(1)
    camera = rasterkit.Camera.look_at(eye=(2.0, 1.5, 3.0), target=(0.0, 0.0, 0.0), width=64, height=48)
    rasterkit.render(mesh, camera, "solid", shading="phong",
                     lights=[rasterkit.Light.directional((-1, -2, -1), shadows=True)])
    bands = [(worker, args) for worker, args in calls if worker.py_func.__name__ == "draw_bands"]
    assert len(bands) >= 2 and not warm_helper.frame_call(*bands[0]) and warm_helper.frame_call(*bands[-1])
    (worker, args), = compiled
    assert worker is bands[-1][0] and args[-1] is not None  # the frame's own call, with its lights

    saved = dict(warm._helpers)
    monkeypatch.setattr(warm, "_frame_only", True)
    warm._helpers["draw_bands"] = object()  # would block if read from
    try:
        assert warm._wait_for_helper(*bands[0]) is None
    finally:
        warm._helpers.clear()
        warm._helpers.update(saved)


def test_an_ao_frames_band_worker_helper_compiles_the_occlusion_passes_too(monkeypatch):
    """The AO's passes run after the frame: the band worker's helper, which has the least to
    compile otherwise, compiles them too, in the order the frame runs them (a helper's render
    reaches each, on the zeroed buffers of the workers it does not run)."""
    from rasterkit.runtime import warm

    names = [worker.py_func.__name__ for worker in warm.helped_workers(RenderOptions(mode="solid", ao=True))[0]]
    assert names == ["bin_records", "draw_bands", "ao_grid", "ao_raw", "ao_blur", "ao_shade"]
    for mode in ("wire", "solid"):  # no AO asked, or none drawn (a wireframe has no surface)
        workers = warm.helped_workers(RenderOptions(mode=mode, ao=mode == "wire"))
        assert not [w for helper in workers for w in helper if w.py_func.__name__.startswith("ao_")]
    compiled = []
    monkeypatch.setattr(warm._jit, "compile_apart", lambda worker, args: compiled.append(worker.py_func.__name__))
    monkeypatch.setattr(warm._threads, "_intercept", warm_helper.compile_only(names))
    camera = rasterkit.Camera.look_at(eye=(2.0, 1.5, 3.0), target=(0.0, 0.0, 0.0), width=64, height=48)
    rasterkit.render(rasterkit.shapes.icosphere(1), camera, "solid", ao=True)
    assert compiled == names
