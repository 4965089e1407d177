"""Calls that would need more memory than the limit are refused before they allocate it
(issue 14, item 9).

Every public function that allocates in proportion to its arguments estimates what it needs
and raises :class:`rasterkit.limits.LimitError` (a ValueError, one line: how much, and for
what) when that is more than :func:`rasterkit.limits.memory_limit`. In process the limit is
set low (cheap); the reproductions of the issue run at the default limit in a child process,
whose address space :mod:`support.hostile` limits (the default limit follows it).
"""

from __future__ import annotations

import threading
import tracemalloc
from pathlib import Path

import numpy as np
import pytest

import rasterkit
from rasterkit import Camera, Framebuffer, Mesh, Scene, draw, limits, shapes, transform
from rasterkit.limits import LimitError
from support.hostile import run_python

MIB = 2**20


@pytest.fixture
def limit():
    """Set the memory limit for one test (restored afterwards)."""
    yield limits.set_memory_limit
    limits.set_memory_limit(None)


def _refused_without_allocating(call, what):
    """``call()`` raises a one-line LimitError that names ``what``, having allocated less
    than 1 MiB through NumPy on the way."""
    tracemalloc.start()
    try:
        with pytest.raises(LimitError) as error:
            call()
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    message = str(error.value)
    assert "\n" not in message and what in message and "needs about" in message, message
    assert peak < MIB, f"{peak} bytes allocated before the refusal"
    return message


def _camera(width, height, mesh=None):
    return Camera.frame(*(mesh or shapes.cube()).bounding_sphere(), width=width, height=height)


@pytest.mark.parametrize("mode", ["wire", "hidden", "solid", "solid+wire"])
def test_a_render_whose_framebuffer_alone_does_not_fit_is_refused(limit, mode):
    cube = shapes.cube()
    rasterkit.render(cube, _camera(8, 8), mode=mode)  # modules imported and kernels loaded outside the measurement
    limit(2000 * 2000 * 3 - 1)  # less than the colour buffer alone
    message = _refused_without_allocating(
        lambda: rasterkit.render(cube, _camera(2000, 2000), mode=mode), f"a 2000x2000 {mode} render")
    assert message.startswith(f"a 2000x2000 {mode} render of 12 faces needs about")
    limit(2000 * 2000 * 3 * 4)  # room for every buffer of every mode
    assert rasterkit.render(shapes.cube(), _camera(2000, 2000), mode=mode).color.shape == (2000, 2000, 3)


def test_a_render_of_many_faces_counts_its_per_face_scratch(limit):
    mesh = shapes.icosphere(5)  # 20480 faces: several MiB of scratch, at 8x8 pixels
    limit(MIB)
    _refused_without_allocating(lambda: rasterkit.render(mesh, _camera(8, 8, mesh), mode="solid"), "render")


def test_the_triangle_workspace_checks_its_growth(limit):
    from rasterkit.raster.triangles import rasterize_triangles

    n = 200_000  # 10 MiB of records
    clip = np.tile([[0.0, 0.0, 0.5, 1.0], [4.0, 0.0, 0.5, 1.0], [0.0, 4.0, 0.5, 1.0]], (n, 1))
    faces = np.arange(3 * n, dtype=np.int64).reshape(n, 3)
    color = np.zeros((8, 8, 3), np.uint8)
    errors = []

    def draw():  # in a thread of its own: its workspace starts empty
        try:
            rasterize_triangles(color, None, clip, faces, face_colors=np.ones((n, 3), np.float32))
        except LimitError as e:
            errors.append(str(e))

    limit(4 * MIB)
    worker = threading.Thread(target=draw)
    worker.start()
    worker.join()
    assert len(errors) == 1 and "the triangle path's scratch memory" in errors[0], errors


def test_framebuffers_are_checked_when_made_and_when_their_depth_is_made(limit):
    limit(12 * MIB - 1)  # 2048 x 2048 x 3 bytes is 12 MiB
    _refused_without_allocating(lambda: Framebuffer(2048, 2048), "a 2048x2048 framebuffer")
    limit(8 * MIB - 1)  # RGBA and ids: 8 bytes a pixel
    _refused_without_allocating(lambda: Framebuffer(1024, 1024, ids=True, background="transparent"),
                                "a 1024x1024 framebuffer")
    fb = Framebuffer(1024, 1024)  # 3 MiB
    limit(7 * MIB - 1)  # the depth buffer would make it 7 MiB
    _refused_without_allocating(lambda: fb.depth, "the depth buffer of a 1024x1024 framebuffer")
    limit(7 * MIB)
    assert np.isposinf(fb.depth).all()


@pytest.mark.parametrize("x1, y1", [(100_000, 3), (-3, -100_000)])
def test_a_line_is_refused_when_its_pixels_would_not_fit(limit, x1, y1):
    pixels = draw.line(0, 0, 1000, 3)
    assert pixels.nbytes == 1001 * 16
    limit(100_001 * 16 - 1)  # less than the result alone
    _refused_without_allocating(lambda: draw.line(0, 0, x1, y1), "a line of 100001 pixels")
    limit(100_001 * 40)
    assert len(draw.line(0, 0, x1, y1)) == 100_001


def test_lines_and_triangles_are_refused_when_they_would_not_fit(limit):
    segments = np.zeros((100_000, 4))  # 3.05 MiB given; drawing them needs several times that
    limit(3 * MIB)
    _refused_without_allocating(lambda: draw.lines(np.zeros((4, 4, 3), np.uint8), segments),
                                "drawing 100000 segments")
    limit(4000 * 4000 * 16 - 1)  # the triangle could cover half its 4000x4000 box, 16 bytes a pixel
    _refused_without_allocating(lambda: draw.triangle(0, 0, 3999, 0, 0, 3999), "the pixels of a triangle")


def test_meshes_scenes_shapes_transforms_and_rays_are_refused_when_they_would_not_fit(limit):
    sphere = shapes.icosphere(4)  # 2562 vertices, 5120 faces
    limit(MIB // 2)  # about 0.8 MiB: the arrays checked and copied (the edges are worked out later)
    _refused_without_allocating(lambda: Mesh(sphere.vertices, sphere.faces), "a Mesh of 2562 vertices")
    limit(MIB)
    _refused_without_allocating(lambda: shapes.torus(rings=300, sides=300), "a torus of 300x300 quads")
    _refused_without_allocating(lambda: shapes.grid(400, 400), "a grid of 400x400 quads")
    scene = Scene(_camera(8, 8))
    limit(None)
    for k in range(50):
        scene.add(sphere, transform.translate(k, 0, 0))
    limit(16 * MIB)
    _refused_without_allocating(lambda: rasterkit.render(scene), "the world mesh of a scene of 50 objects")
    points = np.zeros((100_000, 3))  # 2.3 MiB; the homogeneous copies need several times that
    limit(4 * MIB)
    for name, call in [("apply_points", transform.apply_points), ("apply_vectors", transform.apply_vectors),
                       ("apply_normals", transform.apply_normals)]:
        _refused_without_allocating(lambda: call(np.eye(4), points), f"{name} of 100000")
    camera = _camera(8, 8)
    _refused_without_allocating(lambda: camera.ray(np.zeros((1000, 1)), np.zeros((1, 1000))), "1000000 rays")


@pytest.mark.parametrize("mode", ["wire", "hidden", "solid", "solid+wire"])
@pytest.mark.skipif(not Path("/proc/self/clear_refs").exists(), reason="needs Linux's /proc/self/clear_refs")
def test_a_render_needs_about_what_it_estimates(mode):
    """Measured in a child: the peak resident memory a 4096x4096 render adds. A limit of 97 %
    of it refuses the render (the estimate is no smaller than what it measures, give or take
    pages touched by anything else); a limit twice as large, plus some slack, lets it through
    (the estimate is not wildly larger)."""
    outcome = run_python(f"""
        import resource
        import rasterkit
        from rasterkit import limits, shapes
        from rasterkit.limits import LimitError
        mesh = shapes.icosphere(5)
        small = rasterkit.Camera.frame(*mesh.bounding_sphere(), width=64, height=64)
        rasterkit.render(mesh, small, mode={mode!r})  # compiled; the scratch of these faces made
        camera = rasterkit.Camera.frame(*mesh.bounding_sphere(), width=4096, height=4096)
        def peak():  # VmHWM: the resident high-water mark, which clear_refs resets to now
            with open("/proc/self/status") as f:
                return next(int(l.split()[1]) * 1024 for l in f if l.startswith("VmHWM:"))
        with open("/proc/self/clear_refs", "w") as f:  # forget the compiler's peak (cold cache)
            f.write("5")
        before = peak()
        fb = rasterkit.render(mesh, camera, mode={mode!r})
        used = peak() - before
        del fb
        assert used > 40 * 2**20, used  # at least the 48 MiB colour buffer, give or take a page
        limits.set_memory_limit(int(0.97 * used))
        try:
            rasterkit.render(mesh, camera, mode={mode!r})
            print("not refused at", used)
        except LimitError as e:
            print("refused:", e)
        limits.set_memory_limit(2 * used + 32 * 2**20)
        rasterkit.render(mesh, camera, mode={mode!r})
        print("done", used)
    """, timeout=120)
    assert outcome.code == 0 and f"refused: a 4096x4096 {mode} render" in outcome.stdout, outcome.describe()
    assert "done" in outcome.stdout, outcome.describe()


_REPRODUCTIONS = {
    "draw.line(0, 0, 2**29, 3)": ("rasterkit.draw.line(0, 0, 2**29, 3)", "a line of 536870913 pixels"),
    "a 32768x32768 solid+wire render": (
        "m = shapes.cube(); rasterkit.render(m, rasterkit.Camera.frame(*m.bounding_sphere(), width=32768, "
        "height=32768), mode='solid+wire')", "a 32768x32768 solid+wire render of 12 faces"),
    "a 32768x32768 framebuffer with ids": ("rasterkit.Framebuffer(32768, 32768, ids=True)",
                                           "a 32768x32768 framebuffer"),
    "a torus of 10**5 x 10**5 quads": ("shapes.torus(rings=10**5, sides=10**5)", "a torus"),
    "10**10 rays": ("rasterkit.Camera.look_at((0, 0, 5), (0, 0, 0)).ray(np.zeros((10**5, 1)), np.zeros((1, 10**5)))",
                    "10000000000 rays"),
    "a scene of 2000 spheres": (
        "s, sphere = rasterkit.Scene(rasterkit.Camera.look_at((0, 0, 5), (0, 0, 0))), shapes.icosphere(5)\n"
        "for k in range(2000): s.add(sphere)\n"
        "rasterkit.render(s)", "the world mesh of a scene of 2000 objects"),
}


def test_the_reproductions_end_in_a_limit_error_quickly_at_the_default_limit():
    cases = "\n".join(f"""
try:
    t = time.perf_counter()
    {code.replace(chr(10), chr(10) + '    ')}
    print({label!r}, "NOT REFUSED")
except LimitError as e:
    print({label!r}, "|", round(time.perf_counter() - t, 2), "|", e, flush=True)
""" for label, (code, _) in _REPRODUCTIONS.items())
    outcome = run_python("import time\nimport numpy as np\nimport rasterkit\nfrom rasterkit import shapes\n"
                         "from rasterkit.limits import LimitError\n" + cases + "print('done')\n", timeout=120)
    assert not outcome.crashed and not outcome.timed_out and outcome.code == 0, outcome.describe()
    results = {}
    for line in outcome.stdout.splitlines():
        if " | " in line:
            label, seconds, message = line.split(" | ", 2)
            results[label] = float(seconds), message
    for label, (_, what) in _REPRODUCTIONS.items():
        assert label in results, outcome.describe()
        seconds, message = results[label]
        assert seconds < 5.0 and message.startswith(what) and "needs about" in message, (label, seconds, message)
