"""Triangle pipeline benchmark: rasterkit against Mesa llvmpipe (OpenGL on the CPU).

Run from the repository root::

    python benchmarks/bench_triangles.py            # all scenes
    python benchmarks/bench_triangles.py --repeat 31 --scenes fill

Scenes (1920 x 1080):

fill
    200 large overlapping triangles, about 18 layers deep, flat colours, depth test, no
    culling. Reported as fragments (covered pixel centres) per second; the same fragments
    for both renderers, counted by rasterkit.
bunny, car
    ``../shared/models/stanford-bunny.obj`` and ``sportsCar.obj`` (skipped, with the
    reason, when the folder is missing), framed by a perspective camera built here, solid
    flat Lambert shading with a headlight, back faces culled.
threads
    The fill scene with 2 threads against 1, rasterkit alone; it runs first, before
    llvmpipe has drawn anything (llvmpipe's runs leave the caches and its worker threads
    in a state that perturbs the comparison).

What is timed
    llvmpipe: clear + draw + read back into a NumPy array (vertex and index buffers are
    uploaded once, as a real application would). rasterkit: vertex transform
    (``raster.kernels.vertex.transform_chunks``) + face normals + Lambert shading + clear + clip +
    cull + bin + rasterize, the image ending in a NumPy array too (the clear is done band by
    band inside the draw, ``clear=``). Runs are interleaved (rasterkit, llvmpipe, ...) after
    warm-up runs, and the medians are reported with their ratio.

Both draw RGBA, so the read-back is the same size; coverage of the two images is compared
as a sanity check (they follow the same fill convention, so only a few edge pixels differ).
The last lines compare the ratios with the targets: fill rate >= 1.5x llvmpipe's, model
time <= 0.33x llvmpipe's, 2 threads >= 1.7x as fast as 1. Parallel timings are only
meaningful on an otherwise idle machine (the script warns when the load average is high).
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numba
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from rasterkit.raster.kernels.shade import face_normals, lambert
from rasterkit.raster.vertex import transform_points
from rasterkit.raster.triangles import rasterize_triangles

WIDTH, HEIGHT = 1920, 1080
MODELS = Path(__file__).resolve().parents[1] / ".." / "shared" / "models"
AMBIENT = 0.2
BASE_COLOR = (200.0, 180.0, 150.0)

# ---------------------------------------------------------------------------- scenes


def fill_scene(seed=1, count=200, spread=0.035):
    """``count`` random triangles over the image: raster (x, y, z) of shape (count, 3, 3).

    Vertices fall in the image grown by ``spread`` on each side, which gives about 18
    layers at the default values; depths are random per vertex (the triangles interpenetrate).
    """
    rng = np.random.default_rng(seed)
    xy = rng.uniform(-spread, 1 + spread, (count, 3, 2)) * [WIDTH, HEIGHT]
    z = rng.uniform(0.05, 0.95, (count, 3, 1))
    return np.concatenate([xy, z], axis=2)


def load_obj_triangles(path):
    """Vertices (N, 3) float64 and fan-triangulated faces (M, 3) int64 from an OBJ's v/f lines."""
    text = Path(path).read_bytes().decode("latin-1")
    vertices, faces = [], []
    for line in text.splitlines():
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "v":
            vertices.append(parts[1:4])
        elif parts[0] == "f":
            corners = [int(p.split("/")[0]) for p in parts[1:]]
            faces.extend((corners[0], corners[k], corners[k + 1]) for k in range(1, len(corners) - 1))
    v = np.array(vertices, dtype=np.float64)
    f = np.array(faces, dtype=np.int64)
    f = np.where(f > 0, f - 1, f + len(v))  # OBJ is 1-based; negative indices count back
    return v, f


def look_at(eye, target, up=(0.0, 1.0, 0.0)):
    """World -> camera (4x4): the camera at ``eye`` looks down -Z at ``target``, +Y up."""
    eye, target, up = (np.asarray(a, dtype=np.float64) for a in (eye, target, up))
    back = eye - target
    back /= np.linalg.norm(back)
    right = np.cross(up, back)
    right /= np.linalg.norm(right)
    true_up = np.cross(back, right)
    view = np.eye(4)
    view[:3, :3] = np.stack([right, true_up, back])
    view[:3, 3] = -view[:3, :3] @ eye
    return view


def perspective_raster(fov_y_deg, near, far):
    """Camera -> homogeneous raster (4x4): x, y in pixels (y down), z in [0, 1], w = -Z."""
    focal = HEIGHT / 2 / np.tan(np.radians(fov_y_deg) / 2)
    a = far / (far - near)
    return np.array(
        [
            [focal, 0.0, -WIDTH / 2, 0.0],
            [0.0, -focal, -HEIGHT / 2, 0.0],
            [0.0, 0.0, -a, -near * a],
            [0.0, 0.0, -1.0, 0.0],
        ]
    )


def frame_model(vertices, fov_y_deg=35.0):
    """A camera looking at the model's bounding box from the front-right, above.

    Returns K (world -> homogeneous raster), the world -> camera matrix, and the light
    direction towards the camera (the camera's +Z axis) in world space: a headlight.
    """
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    centre = (lo + hi) / 2
    radius = np.linalg.norm(hi - lo) / 2
    distance = radius / np.sin(np.radians(fov_y_deg) / 2) * 0.75
    direction = np.array([0.6, 0.45, 1.0])
    direction /= np.linalg.norm(direction)
    view = look_at(centre + distance * direction, centre)
    projection = perspective_raster(
        fov_y_deg, max(distance - 1.5 * radius, distance * 1e-3), distance + 1.5 * radius
    )
    return projection @ view, view, view[2, :3].copy()


# ---------------------------------------------------------------------------- renderers


class RasterkitRenderer:
    """Owns the buffers; ``render`` does the timed per-frame work."""

    def __init__(self):
        self.color = np.zeros((HEIGHT, WIDTH, 4), np.uint8)
        self.depth = np.full((HEIGHT, WIDTH), np.inf, np.float32)
        self.stats = None

    def draw_flat(self, clip, faces, face_colors, cull, threads=None):
        self.stats = rasterize_triangles(
            self.color,
            self.depth,
            clip,
            faces,
            face_colors=face_colors,
            cull=cull,
            clear=(0, 0, 0, 0),
            threads=threads,
        )
        return self.color

    def draw_model(self, vertices, faces, matrix, light, threads=None):
        clip = transform_points(vertices, matrix)
        normals = face_normals(vertices, faces)
        colors = lambert(
            normals, np.array([BASE_COLOR], np.float32), light, np.zeros((0, 3)), False, AMBIENT, False
        )
        return self.draw_flat(clip, faces, colors, "back", threads)


class GLRenderer:
    """llvmpipe through moderngl's headless EGL context."""

    FLAT_VS = """#version 330
        in vec4 in_pos; in vec3 in_col; flat out vec3 col;
        void main() { gl_Position = in_pos; col = in_col; }"""
    FLAT_FS = """#version 330
        flat in vec3 col; out vec4 frag;
        void main() { frag = vec4(col, 1.0); }"""
    MODEL_VS = """#version 330
        uniform mat4 mvp; uniform mat4 view; in vec3 in_pos; out vec3 cam;
        void main() { gl_Position = mvp * vec4(in_pos, 1.0); cam = (view * vec4(in_pos, 1.0)).xyz; }"""
    MODEL_FS = """#version 330
        uniform vec3 base; uniform float ambient; in vec3 cam; out vec4 frag;
        void main() {
            vec3 n = normalize(cross(dFdx(cam), dFdy(cam)));
            float i = ambient + (1.0 - ambient) * max(n.z, 0.0);
            frag = vec4(base * i, 1.0);
        }"""

    def __init__(self):
        import moderngl

        self.gl = moderngl
        self.ctx = moderngl.create_standalone_context(backend="egl")
        self.renderer = self.ctx.info["GL_RENDERER"]
        self.fbo = self.ctx.framebuffer(
            color_attachments=[self.ctx.renderbuffer((WIDTH, HEIGHT), 4)],
            depth_attachment=self.ctx.depth_renderbuffer((WIDTH, HEIGHT)),
        )
        self.fbo.use()
        self.vao = None

    @staticmethod
    def to_gl_clip():
        """Homogeneous raster -> OpenGL clip space (y flipped: GL's window origin is bottom-left)."""
        return np.array(
            [
                [2.0 / WIDTH, 0.0, 0.0, -1.0],
                [0.0, -2.0 / HEIGHT, 0.0, 1.0],
                [0.0, 0.0, 2.0, -1.0],
                [0.0, 0.0, 0.0, 1.0],
            ]
        )

    def setup_flat(self, triangles, face_colors):
        prog = self.ctx.program(vertex_shader=self.FLAT_VS, fragment_shader=self.FLAT_FS)
        clip = np.concatenate([triangles.reshape(-1, 3), np.ones((triangles.shape[0] * 3, 1))], axis=1)
        gl_clip = (clip @ self.to_gl_clip().T).astype(np.float32)
        colors = np.repeat(face_colors / 255.0, 3, axis=0).astype(np.float32)
        vbo, cbo = self.ctx.buffer(gl_clip.tobytes()), self.ctx.buffer(colors.tobytes())
        self.vao = self.ctx.vertex_array(prog, [(vbo, "4f", "in_pos"), (cbo, "3f", "in_col")])
        self.ctx.disable(self.gl.CULL_FACE)
        self.ctx.enable(self.gl.DEPTH_TEST)

    def setup_model(self, vertices, faces, matrix, view):
        prog = self.ctx.program(vertex_shader=self.MODEL_VS, fragment_shader=self.MODEL_FS)
        prog["mvp"].write((self.to_gl_clip() @ matrix).astype(np.float32).T.tobytes())
        prog["view"].write(view.astype(np.float32).T.tobytes())
        prog["base"].value = tuple(np.array(BASE_COLOR) / 255.0)
        prog["ambient"].value = AMBIENT
        vbo = self.ctx.buffer(vertices.astype(np.float32).tobytes())
        ibo = self.ctx.buffer(faces.astype(np.int32).tobytes())
        self.vao = self.ctx.vertex_array(
            prog, [(vbo, "3f", "in_pos")], index_buffer=ibo, index_element_size=4
        )
        self.ctx.enable(self.gl.DEPTH_TEST | self.gl.CULL_FACE)

    def draw(self):
        self.fbo.clear(0.0, 0.0, 0.0, 0.0, depth=1.0)
        self.vao.render()
        image = np.frombuffer(self.fbo.read(components=4), np.uint8).reshape(HEIGHT, WIDTH, 4)
        return image[::-1]  # GL rows run bottom-up


# ---------------------------------------------------------------------------- timing


def interleaved(runs, repeat, warmup):
    """Median seconds of each callable in ``runs``, run alternately (order flipped each round)."""
    for _ in range(warmup):
        for run in runs:
            run()
    times = [[] for _ in runs]
    for r in range(repeat):
        order = range(len(runs)) if r % 2 == 0 else reversed(range(len(runs)))
        for k in order:
            start = time.perf_counter()
            runs[k]()
            times[k].append(time.perf_counter() - start)
    return [float(np.median(t)) for t in times]


def coverage_mismatch(a, b):
    """Fraction of pixels drawn by exactly one of two RGBA images (alpha 0 = background)."""
    return float(np.mean((a[..., 3] > 0) != (b[..., 3] > 0)))


def fill_inputs():
    """The fill scene as rasterkit inputs: clip (3K, 4) with w = 1, faces, flat colours."""
    triangles = fill_scene()
    clip = np.ones((triangles.shape[0] * 3, 4))
    clip[:, :3] = triangles.reshape(-1, 3)
    faces = np.arange(clip.shape[0], dtype=np.int64).reshape(-1, 3)
    colors = np.random.default_rng(2).uniform(40, 255, (faces.shape[0], 3)).astype(np.float32)
    return triangles, clip, faces, colors


def compare(name, rk_run, gl_run, args, rate=None):
    """Time rasterkit (and llvmpipe), print the line and the coverage check; returns times."""
    times = interleaved([rk_run] if gl_run is None else [rk_run, gl_run], args.repeat, args.warmup)
    line = f"  rasterkit {times[0] * 1e3:.2f} ms"
    if rate:
        line += f" ({rate / times[0] / 1e6:.0f} Mpixels/s)"
    if gl_run is not None:
        line += f" | llvmpipe {times[1] * 1e3:.2f} ms"
        if rate:
            line += f" ({rate / times[1] / 1e6:.0f} Mpixels/s)"
        line += f" | time ratio rasterkit / llvmpipe {times[0] / times[1]:.2f}"
        line += f" | coverage mismatch {coverage_mismatch(rk_run(), gl_run()):.4%}"
    print(line)
    return times


def bench_fill(rk, gl, args):
    triangles, clip, faces, colors = fill_inputs()
    rk.draw_flat(clip, faces, colors, "none")
    fragments = rk.stats.fragments
    depth = fragments / (WIDTH * HEIGHT)
    print(f"fill: {faces.shape[0]} triangles, {depth:.1f} layers deep ({fragments / 1e6:.1f} M fragments)")
    if gl:
        gl.setup_flat(triangles, colors)
    times = compare(
        "fill", lambda: rk.draw_flat(clip, faces, colors, "none"), gl and gl.draw, args, fragments
    )
    return ("fill rate rasterkit / llvmpipe", times[1] / times[0], ">=", 1.5) if gl else None


def bench_model(rk, gl, args, name, filename):
    path = MODELS / filename
    if not path.is_file():
        print(f"{name}: skipped, {path} not found")
        return None
    vertices, faces = load_obj_triangles(path)
    matrix, view, light = frame_model(vertices)
    rk.draw_model(vertices, faces, matrix, light)
    s = rk.stats
    print(
        f"{name}: {len(vertices)} vertices, {len(faces)} triangles; drawn {s.drawn}, culled {s.culled}, "
        f"empty {s.empty}; covers {np.isfinite(rk.depth).mean():.1%} of the image"
    )
    if gl:
        gl.setup_model(vertices, faces, matrix, view)
    times = compare(name, lambda: rk.draw_model(vertices, faces, matrix, light), gl and gl.draw, args)
    if args.save:
        save_images(name, rk, gl)
    return (f"{name} time rasterkit / llvmpipe", times[0] / times[1], "<=", 0.33) if gl else None


def save_images(name, rk, gl):
    from PIL import Image

    Image.fromarray(rk.color).save(f"bench-{name}-rasterkit.png")
    if gl:
        Image.fromarray(gl.draw()).save(f"bench-{name}-llvmpipe.png")


def bench_threads(rk, args):
    if numba.config.NUMBA_NUM_THREADS < 2:
        print("threads: skipped, only one thread available")
        return None
    _, clip, faces, colors = fill_inputs()
    one, two = interleaved(
        [lambda n=n: rk.draw_flat(clip, faces, colors, "none", threads=n) for n in (1, 2)],
        args.repeat,
        args.warmup,
    )
    print(f"threads (fill scene): 1 thread {one * 1e3:.2f} ms, 2 threads {two * 1e3:.2f} ms")
    return ("speed-up 2 threads / 1 thread", one / two, ">=", 1.7)


def summary(results):
    print("targets:")
    for label, value, sense, target in results:
        met = value >= target if sense == ">=" else value <= target
        print(f"  {label}: {value:.2f} (target {sense} {target}) {'met' if met else 'MISSED'}")


def open_gl(args):
    """The llvmpipe renderer, or None (with the reason printed) when it cannot be had."""
    if args.no_gl:
        return None
    try:
        gl = GLRenderer()
    except Exception as error:  # noqa: BLE001 - no moderngl or no EGL: still time rasterkit
        print(f"llvmpipe unavailable ({type(error).__name__}: {error}); timing rasterkit only")
        return None
    print(f"OpenGL renderer: {gl.renderer}")
    return gl


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeat", type=int, default=21, help="timed runs per renderer (median reported)")
    parser.add_argument("--warmup", type=int, default=3, help="untimed runs first")
    parser.add_argument("--scenes", default="threads,fill,bunny,car", help="subset of threads,fill,bunny,car")
    parser.add_argument("--no-gl", action="store_true", help="time rasterkit only")
    parser.add_argument("--save", action="store_true", help="write the model images as PNG")
    args = parser.parse_args()
    scenes = args.scenes.split(",")
    load = os.getloadavg()[0]
    print(
        f"{WIDTH}x{HEIGHT}, {numba.get_num_threads()} threads, {os.cpu_count()} CPUs, load average {load:.2f}"
    )
    if load > 0.5:
        print("  warning: the machine is busy; timings of parallel code will be unreliable")
    gl = open_gl(args)
    rk = RasterkitRenderer()
    benches = {
        "fill": lambda: bench_fill(rk, gl, args),
        "bunny": lambda: bench_model(rk, gl, args, "bunny", "stanford-bunny.obj"),
        "car": lambda: bench_model(rk, gl, args, "car", "sportsCar.obj"),
        "threads": lambda: bench_threads(rk, args),
    }
    results = [benches[name]() for name in scenes if name in benches]
    summary([r for r in results if r is not None])


if __name__ == "__main__":
    main()
