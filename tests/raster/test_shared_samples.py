"""The triangle setup shared by the samples of a pinhole multi-sample render.

The reference for a sample at offset ``s`` (a multiple of 1/256 pixel) is a full single
draw (:func:`rasterkit.raster.triangles.rasterize_triangles`, today's path) of the vertices moved
by ``-s`` in raster space, built here from the clip coordinates; the tests check that the
move is exact in fixed point (every snapped vertex moves by exactly ``-256 s``), the premise
of the bit-for-bit equality.
"""

import numpy as np
import pytest

import rasterkit
from rasterkit import Camera, shapes
from rasterkit.runtime.threads import get_threads
from rasterkit.raster.shared_samples import SharedTriangles
from rasterkit.raster.render import AMBIENT
from rasterkit.raster.samples import pixel_offsets
from rasterkit.raster.triangles import FlatLambert, rasterize_triangles

W, H = 67, 45  # wider than a vertex block, two bands and a bit

OFFSETS = [(0, 0), (1, 0), (0, -1), (-128, -128), (128, 128), (-128, 127), (37, -91), (256, -256), (-256, 255)]


def _snap(v):
    return np.floor(v * 256.0 + 0.5)


def _mesh(seed, n_loose=60):
    """Clip coordinates (w a power of two, so xh / w is exact) and faces: a grid whose
    triangles share edges (the top-left rule) and loose triangles of every size, some
    smaller than a pixel, some beyond the image's sides (within the guard band), some on
    one plane at equal depths (the first drawn wins)."""
    rng = np.random.default_rng(seed)
    gx, gy = np.meshgrid(np.linspace(-3.3, W + 2.7, 9), np.linspace(-2.1, H + 3.2, 7))
    grid = np.stack([gx.ravel() + rng.uniform(-2, 2, gx.size), gy.ravel() + rng.uniform(-2, 2, gx.size)], 1)
    cols, rows = 9, 7
    faces = []
    for j in range(rows - 1):
        for i in range(cols - 1):
            a = j * cols + i
            faces += [(a, a + 1, a + cols + 1), (a, a + cols + 1, a + cols)]
    centres = rng.uniform([-4, -4], [W + 4, H + 4], (n_loose, 2))
    sizes = np.exp(rng.uniform(np.log(0.2), np.log(30), n_loose))
    loose = (centres[:, None, :] + rng.normal(size=(n_loose, 3, 2)) * sizes[:, None, None]).reshape(-1, 2)
    xy = np.concatenate([grid, loose])
    n = len(xy)
    faces += [(len(grid) + 3 * k, len(grid) + 3 * k + 1, len(grid) + 3 * k + 2) for k in range(n_loose)]
    faces += [faces[k] for k in rng.choice(len(faces), 10)]  # repeated faces: equal depths
    w = 2.0 ** rng.integers(-2, 3, n)
    z = rng.uniform(0.05, 0.95, n)
    clip = np.stack([xy[:, 0] * w, xy[:, 1] * w, z * w, w], 1)
    return clip, np.array(faces, np.int64)


def _moved(clip, sample):
    """The clip coordinates of the raster image moved by ``-sample / 256`` pixel, checked
    to be exact in fixed point."""
    sx, sy = sample
    w = clip[:, 3]
    x, y = clip[:, 0] / w - sx / 256.0, clip[:, 1] / w - sy / 256.0
    moved = np.stack([x * w, y * w, clip[:, 2], w], 1)
    assert np.array_equal(_snap(moved[:, 0] / w), _snap(clip[:, 0] / w) - sx)
    assert np.array_equal(_snap(moved[:, 1] / w), _snap(clip[:, 1] / w) - sy)
    assert np.array_equal(moved[:, 2] / w, clip[:, 2] / w)
    return moved


def _full(clip, faces, colors, cull, offset, channels=3, smooth=False):
    color = np.empty((H, W, channels), np.uint8)
    depth = np.empty((H, W), np.float32)
    kw = dict(vertex_colors=colors) if smooth else dict(face_colors=colors)
    rasterize_triangles(color, depth, clip, faces, cull=cull, clear=(9, 200, 77, 0)[:channels], depth_offset=offset,
                        **kw)
    return color, depth


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("cull", ["back", "none"])
def test_a_shared_sample_is_the_full_draw_of_the_moved_vertices(seed, cull):
    clip, faces = _mesh(seed)
    rng = np.random.default_rng(100 + seed)
    colors = rng.integers(0, 2**32, len(faces), dtype=np.uint64).astype(np.uint32)
    offset = (1.0, 1e-5) if seed % 2 else (0.0, 0.0)
    shared = SharedTriangles(clip, faces, width=W, height=H, color=True, face_colors=colors, cull=cull,
                             depth_offset=offset)
    drawn_somewhere = 0
    samples = OFFSETS + [tuple(rng.integers(-256, 257, 2)) for _ in range(6)]
    drawn = []  # all shared draws first: a full draw uses the scratch memory the setup lives in
    for sample in samples:
        color, depth = np.empty((H, W, 3), np.uint8), np.empty((H, W), np.float32)
        shared.draw(color, depth, sample=sample, clear=(9, 200, 77))
        drawn.append((color, depth))
    for sample, (color, depth) in zip(samples, drawn):
        want_color, want_depth = _full(_moved(clip, sample), faces, colors, cull, offset)
        assert np.array_equal(color, want_color), sample
        assert np.array_equal(depth, want_depth), sample
        drawn_somewhere += np.isfinite(depth).sum()
    assert drawn_somewhere > 40 * len(samples)  # not vacuous (the grid is culled as back faces)


def test_a_shared_depth_pass_and_rgba_are_the_full_draws_too():
    clip, faces = _mesh(7)
    depth_only = SharedTriangles(clip, faces, width=W, height=H, color=False, cull="none", depth_offset=(1.0, 1e-5))
    depths = []
    for sample in OFFSETS:
        depths.append(np.empty((H, W), np.float32))
        depth_only.draw(None, depths[-1], sample=sample, clear=())
    for sample, depth in zip(OFFSETS, depths):
        want = np.empty((H, W), np.float32)
        rasterize_triangles(None, want, _moved(clip, sample), faces, cull="none", clear=(), depth_offset=(1.0, 1e-5))
        assert np.array_equal(depth, want)
    with pytest.raises(RuntimeError):  # a draw since the setup: its scratch memory is gone
        depth_only.draw(None, np.empty((H, W), np.float32))
    colors = np.random.default_rng(3).uniform(0, 255, (len(faces), 3)).astype(np.float32)
    rgba = SharedTriangles(clip, faces, width=W, height=H, color=True, face_colors=colors, cull="none")
    images = [np.empty((H, W, 4), np.uint8) for _ in OFFSETS]
    for sample, color in zip(OFFSETS, images):
        rgba.draw(color, None, sample=sample, clear=(9, 200, 77, 0))
    for sample, color in zip(OFFSETS, images):
        assert np.array_equal(color, _full(_moved(clip, sample), faces, colors, "none", (0.0, 0.0), 4)[0])


def test_smooth_colours_are_interpolated_at_the_sample_point():
    """Coverage and depth to the bit; the colours from the centre's barycentric terms
    evaluated at the sample point, which the moved draw rounds differently: to one level."""
    clip, faces = _mesh(11)
    colors = np.random.default_rng(5).uniform(0, 255, (len(clip), 3)).astype(np.float32)
    shared = SharedTriangles(clip, faces, width=W, height=H, color=True, vertex_colors=colors, cull="none")
    drawn = [(np.empty((H, W, 3), np.uint8), np.empty((H, W), np.float32)) for _ in OFFSETS]
    for sample, (color, depth) in zip(OFFSETS, drawn):
        shared.draw(color, depth, sample=sample, clear=(9, 200, 77))
    for sample, (color, depth) in zip(OFFSETS, drawn):
        want_color, want_depth = _full(_moved(clip, sample), faces, colors, "none", (0.0, 0.0), smooth=True)
        assert np.array_equal(depth, want_depth)
        assert np.abs(color.astype(int) - want_color).max() <= 1


@pytest.mark.parametrize("smooth", [False, True])
def test_the_one_pass_average_is_the_sum_of_the_samples(smooth):
    clip, faces = _mesh(13)
    rng = np.random.default_rng(6)
    if smooth:
        kw = dict(vertex_colors=rng.uniform(0, 255, (len(clip), 3)).astype(np.float32))
    else:
        kw = dict(face_colors=rng.uniform(0, 255, (len(faces), 3)).astype(np.float32))
    shared = SharedTriangles(clip, faces, width=W, height=H, color=True, cull="back", **kw)
    samples = np.array(OFFSETS[:7] + [(5, 5)] * 9)  # 16 samples
    total = np.zeros((H, W, 3), np.int64)
    for sample in samples:
        color = np.empty((H, W, 3), np.uint8)
        shared.draw(color, None, sample=tuple(sample), clear=(250, 3, 128))
        total += color
    average = np.empty((H, W, 3), np.uint8)
    shared.draw_average(average, samples, clear=(250, 3, 128), exact=False)
    n = len(samples)
    assert np.array_equal(average, (total + n // 2) // n)
    assert len(np.unique(average)) > 20
    # exact: only pixels that the samples found partly covered, or that hold a corner, change
    exact = np.empty((H, W, 3), np.uint8)
    shared.draw_average(exact, samples, clear=(250, 3, 128))
    changed = (exact != average).any(axis=2)
    assert changed.any()
    assert not (changed & _uniform_and_off_the_sides(samples, clip, faces)).any()


def _parallel_scene():
    """A mesh and a parallel camera: w = 1, so the raster image moves exactly."""
    mesh = shapes.icosphere(2)
    camera = Camera.orthographic((0.3, 0.2, 3.0), (0.0, 0.0, 0.0), view_height=2.5, width=W, height=H)
    return mesh, camera


def _uniform_and_off_the_sides(samples, clip, faces):
    """Pixels whose samples all saw the same face (or none), each sample's ids drawn by a
    full draw of the moved faces, and that no side of a face crosses (points every 1/1024
    pixel along each side, and 1/256 pixel either way)."""
    ids = []
    for sample in samples:
        ids_image = np.empty((H, W), np.int32)
        rasterize_triangles(np.empty((H, W, 3), np.uint8), None, _moved(clip, tuple(sample)), faces,
                            face_colors=np.zeros((len(faces), 3), np.float32), ids=ids_image, clear=(0, 0, 0),
                            cull="back")
        ids.append(ids_image)
    ids = np.array(ids)
    xy = clip[:, :2] / clip[:, 3:]
    lo = np.stack(np.meshgrid(np.arange(W), np.arange(H)), axis=-1) - 1 / 256  # each pixel's square, grown
    hi = lo + 1 + 2 / 256
    crossed = np.zeros((H, W), bool)
    for a, b in ((0, 1), (1, 2), (2, 0)):
        for p, q in zip(xy[faces[:, a]], xy[faces[:, b]]):  # Liang-Barsky against every square
            d = q - p
            with np.errstate(divide="ignore", invalid="ignore"):
                t_lo, t_hi = (lo - p) / d, (hi - p) / d
            enter = np.where(d == 0, np.where((lo <= p) & (p <= hi), -np.inf, np.inf), np.minimum(t_lo, t_hi))
            leave = np.where(d == 0, np.where((lo <= p) & (p <= hi), np.inf, -np.inf), np.maximum(t_lo, t_hi))
            crossed |= np.maximum(enter.max(axis=-1), 0.0) <= np.minimum(leave.min(axis=-1), 1.0)
    return (ids == ids[0]).all(axis=0) & ~crossed


@pytest.mark.parametrize("samples", [4, 16])
def test_a_pinhole_render_averages_full_draws_at_the_rounded_sample_offsets(monkeypatch, samples):
    mesh, camera = _parallel_scene()
    from rasterkit.raster.vertex import transform_points

    clip = transform_points(np.ascontiguousarray(mesh.vertices), np.ascontiguousarray(camera.world_to_raster()))
    assert np.all(clip[:, 3] == 1.0)
    gray = rasterkit.colors.parse_color("lightgray")[None, :3].astype(np.float32)
    lambert = FlatLambert(mesh.face_normals, gray, camera.backward(), AMBIENT)
    total = np.zeros((H, W, 3), np.int64)
    offsets = np.rint(pixel_offsets(samples) * 256).astype(int)
    for sx, sy in offsets:
        color = np.empty((H, W, 3), np.uint8)
        rasterize_triangles(color, None, _moved(clip, (sx, sy)), mesh.faces, face_colors=lambert, clear=(255, 255, 255))
        total += color
    from rasterkit.raster import accumulate as _accumulate

    monkeypatch.setattr(_accumulate, "EXACT_COVERAGE", False)  # the frames have no exact step
    fb = rasterkit.render(mesh, camera, "solid", samples=samples)
    assert np.array_equal(fb.color, (total + samples // 2) // samples)
    assert 0 < np.mean((fb.color != 255).any(axis=2)) < 1


@pytest.mark.parametrize("mode", ["solid", "hidden", "solid+wire"])
@pytest.mark.parametrize("shading", ["flat", "smooth"])
def test_shared_multi_sample_renders_do_not_depend_on_the_thread_count(mode, shading):
    mesh = shapes.icosphere(3)
    camera = Camera.look_at((2.0, 1.5, 3.0), (0.0, 0.0, 0.0), width=150, height=110)
    images = []
    previous = get_threads()
    for threads in (1, 2):
        rasterkit.set_threads(threads)
        try:
            images.append(rasterkit.render(mesh, camera, mode, shading=shading, samples=16).color)
            images.append(rasterkit.render(mesh, camera, mode, shading=shading, samples=4,
                                           background="transparent").color)
        finally:
            rasterkit.set_threads(previous)
    assert np.array_equal(images[0], images[2]) and np.array_equal(images[1], images[3])
    assert len(np.unique(images[0])) > 4


@pytest.mark.parametrize("mode", ["solid", "hidden", "solid+wire"])
@pytest.mark.parametrize("background", ["white", "transparent"])
@pytest.mark.parametrize("near", [None, 0.5])
def test_shared_renders_match_a_frame_per_sample_at_the_same_offsets(monkeypatch, mode, background, near):
    """Against today's path, every sample a whole frame through its jittered matrix (what a
    lens camera's samples still get), at the same offsets on the 1/256 grid: the matrices
    move the image by the offsets up to float rounding, which may move a snapped vertex (or
    a corner where the near plane cuts a face: ``near=0.5`` cuts some) by 1/256 pixel here
    and there (none does in these scenes)."""
    from rasterkit.raster import accumulate as _accumulate

    mesh = shapes.icosphere(3)
    camera = Camera.look_at((0.1, 0.2, 1.3), (0.0, 0.0, 0.0), fov_y=90.0, width=150, height=110, near=near) \
        if near else Camera.look_at((2.0, 1.5, 3.0), (0.0, 0.0, 0.0), width=150, height=110)
    if near:
        from rasterkit.raster.vertex import transform_points

        clip = transform_points(np.ascontiguousarray(mesh.vertices), np.ascontiguousarray(camera.world_to_raster()))
        depth = np.empty((110, 150), np.float32)
        assert rasterize_triangles(None, depth, clip, mesh.faces, cull="none", clear=()).clipped > 10
    options = dict(samples=16, background=background, shading="smooth", cull="none")
    monkeypatch.setattr(_accumulate, "EXACT_COVERAGE", False)  # the frames have no exact step
    shared = rasterkit.render(mesh, camera, mode, **options).color
    rounded = np.rint(pixel_offsets(16) * 256) / 256
    monkeypatch.setattr(_accumulate, "pinhole", lambda camera: False)
    monkeypatch.setattr(_accumulate, "pixel_offsets", lambda n: rounded)
    frames = rasterkit.render(mesh, camera, mode, **options).color
    differ = np.abs(shared.astype(int) - frames).max(axis=2)
    assert np.mean(differ > 0) < 1e-3 and differ.max() <= 16
    assert len(np.unique(shared)) > 4



def _sample_band_textures(**kwargs):
    """``(textures, cutouts, mapped)`` that a 4-sample solid render of a ball hands its band
    worker (the worker runs as usual)."""
    from rasterkit.runtime import threads

    calls = []
    threads.intercept(lambda worker, args: calls.append(args[-3:]) if worker.py_func.__name__ == "draw_sample_bands"
                      else None)
    try:
        camera = Camera.look_at((0.5, 0.8, 3.2), (0, 0, 0), width=48, height=40, fov_y=45)
        rasterkit.render(shapes.icosphere(2), camera, "solid", samples=4, **kwargs)
    finally:
        threads.intercept(None)
    (arguments,) = calls
    return arguments


def test_a_multi_sample_frame_without_textures_is_lit_without_the_textured_rows():
    """Every face of an untextured phong frame is lit per pixel: its samples call the lighting
    alone (``lit_shade.lit_untextured_rgba`` from ``sample_rows.add_textured_row``; ``textures``
    None, ``mapped`` the lights' record), not the texture and normal-map code of the textured
    faces, which took as long again to compile; to the bit the textured rows' colours (the render
    checksums' ``phong-samples`` row); also under the default headlight and in a flat frame lit
    per pixel for its shadows. A frame not lit per pixel has neither."""
    light = rasterkit.Light.directional((-1, -2, -1))
    for flags, lights in (({"shading": "phong", "lights": [light]}, 1), ({"shading": "phong"}, 2),
                          ({"shading": "flat", "lights": [light], "shadows": True}, 1)):
        textures, cutouts, mapped = _sample_band_textures(**flags)
        assert textures is None and cutouts is None and mapped is not None
        assert mapped.lights.shape[0] == lights and mapped.phong  # the headlight and its ambient term: 2 rows
    assert _sample_band_textures(shading="smooth", lights=[light]) == (None, None, None)
