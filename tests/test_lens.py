"""Multi-sample renders and the thin-lens camera: sample patterns, coverage against exact
areas, the circle of confusion against the thin-lens formula, cos⁴ vignetting against the
camera's rays, determinism, and the buffers and checks of the new parameters."""

import dataclasses
import math

import numpy as np
import pytest
from PIL import Image

import rasterkit
from rasterkit import Camera, shapes
from rasterkit._notice import MESSAGE
from rasterkit.cli import main
from rasterkit.samples import MAX_SAMPLES, concentric_disc, lens_points, pixel_offsets, square


def _quad(cx, cy, half, z):
    """A square in the plane z = const, facing +z (counter-clockwise seen from +z)."""
    v = np.array([(cx - half, cy - half, z), (cx + half, cy - half, z),
                  (cx + half, cy + half, z), (cx - half, cy + half, z)], np.float64)
    return v, np.array([(0, 1, 2), (0, 2, 3)], np.int64)


# --- the patterns --------------------------------------------------------------------------


@pytest.mark.parametrize("n", [2, 4, 7, 12, 16, 64, 256])
def test_square_patterns_are_stratified_in_2d_and_in_each_axis(n):
    p = square(n)
    assert p.shape == (n, 2) and np.all((p >= 0) & (p < 1))
    for axis in (0, 1):  # one point in every 1/n strip of each axis (n-rooks)
        assert sorted(np.floor(p[:, axis] * n).astype(int)) == list(range(n))
    m = max(d for d in range(1, math.isqrt(n) + 1) if n % d == 0)
    cells = {(int(x * m), int(y * (n // m))) for x, y in p}
    assert len(cells) == n  # one point in every cell of the m x n/m grid


def test_patterns_are_fixed():
    assert np.array_equal(square(16), square(16))
    from rasterkit import samples

    before = np.array(samples.square(16)), [np.array(pixel_offsets(n)) for n in (4, 16, 48)]
    samples._square.cache_clear()
    samples._offsets.cache_clear()
    assert np.array_equal(samples.square(16), before[0])
    assert all(np.array_equal(pixel_offsets(n), b) for n, b in zip((4, 16, 48), before[1]))
    assert np.array_equal(pixel_offsets(1), [[0.0, 0.0]]) and np.array_equal(lens_points(1), [[0.0, 0.0]])


def test_lens_points_cover_the_disc_uniformly():
    points = lens_points(256)
    r = np.hypot(points[:, 0], points[:, 1])
    assert np.all(r <= 1.0 + 1e-12)
    # uniform on the unit disc: a quarter of the points within radius 1/2, E[x²] = E[y²] = 1/4
    assert abs(np.mean(r < 0.5) - 0.25) < 0.03
    assert np.allclose(np.mean(points**2, axis=0), 0.25, atol=0.01)
    assert np.allclose(points.mean(axis=0), 0.0, atol=0.01)
    # the concentric map sends the square's boundary to the circle, its centre to the centre
    edge = concentric_disc(np.array([[1.0, 0.5], [0.5, 1.0], [0.0, 0.0], [0.5, 0.5]]))
    assert np.allclose(edge, [[1, 0], [0, 1], [-math.sqrt(0.5), -math.sqrt(0.5)], [0, 0]])


# --- coverage ------------------------------------------------------------------------------


def _clip_area(polygon, x0, y0):
    """Area of the convex polygon ``polygon`` ([(x, y)]) within the pixel square
    [x0, x0 + 1] x [y0, y0 + 1]: Sutherland–Hodgman against the square's four sides, then
    the shoelace formula."""
    poly = [tuple(map(float, p)) for p in polygon]
    for axis, bound, sign in ((0, x0, 1), (0, x0 + 1, -1), (1, y0, 1), (1, y0 + 1, -1)):
        out = []
        for k, cur in enumerate(poly):
            prev = poly[k - 1]
            cur_in, prev_in = sign * (cur[axis] - bound) >= 0, sign * (prev[axis] - bound) >= 0
            if cur_in != prev_in:
                t = (bound - prev[axis]) / (cur[axis] - prev[axis])
                out.append((prev[0] + t * (cur[0] - prev[0]), prev[1] + t * (cur[1] - prev[1])))
            if cur_in:
                out.append(cur)
        poly = out
        if not poly:
            return 0.0
    return 0.5 * abs(sum(a[0] * b[1] - b[0] * a[1] for a, b in zip(poly, poly[1:] + poly[:1])))


def _coverage(xy, width, height):
    """Exact covered fraction of each pixel square by the triangle ``xy`` (3, 2 raster
    points), (height, width): 1 where the square's four corners are inside all three edges,
    0 where they are all outside one edge, the clipped area (:func:`_clip_area`) elsewhere."""
    X, Y = np.meshgrid(np.arange(width + 1.0), np.arange(height + 1.0))
    inside, outside = np.ones((height, width), bool), np.zeros((height, width), bool)
    sign = np.sign((xy[1, 0] - xy[0, 0]) * (xy[2, 1] - xy[0, 1]) - (xy[1, 1] - xy[0, 1]) * (xy[2, 0] - xy[0, 0]))
    for k in range(3):
        a, b = xy[k], xy[(k + 1) % 3]
        e = sign * ((b[0] - a[0]) * (Y - a[1]) - (b[1] - a[1]) * (X - a[0]))
        corners = np.stack([e[:-1, :-1], e[:-1, 1:], e[1:, :-1], e[1:, 1:]])
        inside &= np.all(corners >= 0, axis=0)
        outside |= np.all(corners <= 0, axis=0)
    exact = inside.astype(np.float64)
    for j, i in zip(*np.nonzero(~inside & ~outside)):
        exact[j, i] = _clip_area(xy, i, j)
    return exact


def _pixel_kind(xy, i, j):
    """'corner' (a vertex inside the pixel), 'two edges' (crossed by two or three edges) or
    'one edge'."""
    if any(i < x < i + 1 and j < y < j + 1 for x, y in xy):
        return "corner"
    crossing = 0
    for k in range(3):  # does edge k cut the open square? (Liang–Barsky)
        (ax, ay), (bx, by) = xy[k], xy[(k + 1) % 3]
        lo, hi = 0.0, 1.0
        for p, q in ((ax - bx, ax - i), (bx - ax, i + 1 - ax), (ay - by, ay - j), (by - ay, j + 1 - ay)):
            if p == 0:
                hi = hi if q > 0 else -1.0
            elif p < 0:
                lo = max(lo, q / p)
            else:
                hi = min(hi, q / p)
        crossing += lo < hi
    return "two edges" if crossing >= 2 else "one edge"


def test_exact_coverage_reference():
    """The reference itself: pixel areas sum to the triangle's area, a unit square clipped
    against pixels, and a fine point sampling of the same triangle agrees within its error."""
    xy = np.array([(3.3, 2.1), (17.8, 5.45), (6.2, 14.9)])
    exact = _coverage(xy, 20, 16)
    (ax, ay), (bx, by) = xy[1] - xy[0], xy[2] - xy[0]
    assert abs(exact.sum() - 0.5 * abs(ax * by - ay * bx)) < 1e-9
    assert _clip_area([(0.5, 0.25), (1.5, 0.25), (1.5, 1.25), (0.5, 1.25)], 1, 0) == pytest.approx(0.375)
    assert _clip_area([(0.2, 0.2), (0.8, 0.2), (0.2, 0.8)], 0, 0) == pytest.approx(0.18)
    sub = 128
    t = (np.arange(20 * sub) + 0.5) / sub
    X, Y = np.meshgrid(t, t[: 16 * sub])
    inside = np.ones(X.shape, bool)
    for k in range(3):
        a, b = xy[k], xy[(k + 1) % 3]
        inside &= ((b[0] - a[0]) * (Y - a[1]) - (b[1] - a[1]) * (X - a[0])) >= 0
    fine = inside.reshape(16, sub, 20, sub).mean(axis=(1, 3))
    assert np.max(np.abs(fine - exact)) < 3 / sub
    assert _pixel_kind(xy, 3, 2) == "corner" and _pixel_kind(xy, 10, 3) == "one edge"


@pytest.mark.parametrize("n", [2, 4, 8, 16, 32, 48, 256])
def test_pixel_offsets_are_whole_fixed_point_units_in_the_pixel(n):
    """Every sample's offset is a whole number of 1/256 pixel (the rasterizer's fixed point),
    inside the pixel, and the n samples are distinct."""
    offsets = pixel_offsets(n)
    units = offsets * 256
    assert offsets.shape == (n, 2) and np.array_equal(units, np.round(units))
    assert np.all((offsets >= -0.5) & (offsets < 0.5))
    assert len({tuple(p) for p in units}) == n


@pytest.mark.parametrize("n, bound", [(4, 0.2501), (8, 0.161), (16, 0.0958), (32, 0.074)])
def test_tuned_pixel_samples_keep_every_half_plane_within_their_bound(n, bound):
    """The bounds rasterkit.samples states for one straight edge across a pixel: for every
    direction (a 720-direction grid and the directions through every two samples) and every
    position of the edge (just before and after each sample: the top-left rule may count a
    sample on the edge either way), the fraction of samples on one side is within the bound
    of the area on that side, computed here by clipping the pixel square. No pattern can beat
    1/n (the edge through two samples), which the measure must find."""
    points = pixel_offsets(n) + 0.5
    i, j = np.triu_indices(n, 1)
    d = points[j] - points[i]
    thetas = np.r_[np.arange(720) * (np.pi / 720), np.arctan2(d[:, 1], d[:, 0]) + np.pi / 2]
    worst = 0.0
    for theta in thetas:
        w = np.array([math.cos(theta), math.sin(theta)])
        t = points @ w
        u = np.array([-w[1], w[0]])
        for c in np.unique(np.round(t, 12)):
            # the half-plane w·p < c as a large quad, clipped to the pixel square
            area = _clip_area([c * w - 4 * u, c * w + 4 * u, c * w + 4 * u - 4 * w, c * w - 4 * u - 4 * w], 0, 0)
            below, upto = np.sum(t < c - 1e-12), np.sum(t <= c + 1e-12)
            worst = max(worst, abs(below / n - area), abs(upto / n - area))
    assert 1 / n - 1e-9 <= worst <= bound


@pytest.mark.parametrize("corners", [
    [(-1.3, -0.9), (1.4, -0.83), (0.1, 1.1)],     # a nearly horizontal edge
    [(-1.2, -1.0), (-1.15, 1.05), (1.3, 0.2)],    # a nearly vertical edge
    [(-0.9, -1.1), (1.2, 0.95), (-1.25, 0.7)],    # near the diagonals
    [(0.03, -1.2), (1.3, 0.77), (-1.33, 0.41)],
])
def test_sixteen_samples_give_each_edge_pixel_its_covered_fraction(corners):
    width, height = 160, 120
    camera = Camera.look_at((0.0, 0.0, 4.0), (0.0, 0.0, 0.0), fov_y=40.0, width=width, height=height)
    v = np.array([(x, y, 0.0) for x, y in corners])
    fb = rasterkit.render((v, np.array([(0, 1, 2)])), camera, "solid", cull="none", color="black",
                          background="white", samples=16)
    dark = 1.0 - fb.color[..., 0] / 255.0
    assert np.array_equal(fb.color[..., 0], fb.color[..., 2])
    xy = camera.project(v)[:, :2]
    exact = _coverage(xy, width, height)
    edge = (exact > 0) & (exact < 1)
    assert edge.sum() > 100
    assert np.max(np.abs(dark - exact)) <= 0.1
    (ax, ay), (bx, by) = xy[1] - xy[0], xy[2] - xy[0]
    area = 0.5 * abs(ax * by - ay * bx)
    assert abs(dark.sum() - area) <= 0.01 * area
    # one sample is the pinhole image: no grey levels
    one = rasterkit.render((v, np.array([(0, 1, 2)])), camera, "solid", cull="none", color="black",
                           background="white")
    assert set(np.unique(one.color)) <= {0, 255}


def test_lines_are_antialiased_by_samples():
    mesh = shapes.cube()
    camera = Camera.frame((0, 0, 0), 2.0, width=96, height=72)
    fb = rasterkit.render(mesh, camera, "wire", samples=8)
    levels = np.unique(fb.color)
    assert len(levels) > 4 and levels.min() < 80 and levels.max() == 255


# --- the thin lens -------------------------------------------------------------------------


def _spread(image):
    """Variance of the intensity about its centroid, the mean of x and y (pixels²)."""
    i = image.astype(np.float64)
    h, w = i.shape
    y, x = np.mgrid[0:h, 0:w] + 0.5
    total = i.sum()
    mx, my = (i * x).sum() / total, (i * y).sum() / total
    return 0.5 * ((i * (x - mx) ** 2).sum() + (i * (y - my) ** 2).sum()) / total


@pytest.mark.parametrize("d", [3.0, 5.0, 10.0])
def test_blur_diameter_follows_the_thin_lens_formula(d):
    size, fov, focus, aperture = 128, 40.0, 5.0, 1.0
    f_px = (size / 2) / math.tan(math.radians(fov / 2))
    side_px = 6.0
    half = side_px / 2 * d / f_px
    camera = Camera.look_at((0, 0, 0), (0, 0, -focus), fov_y=fov, width=size, height=size,
                            near=0.5, far=50.0, aperture=aperture)
    fb = rasterkit.render(_quad(0.0, 0.0, half, -d), camera, "solid", cull="none", color="white",
                          background="black", samples=256)
    # a uniform disc of diameter b has variance b²/16 per axis; the square adds s²/12 and
    # the averaging over the pixel square 1/12
    s = np.ptp(camera.project(_quad(0.0, 0.0, half, -d)[0])[:, 0])
    measured = 4.0 * math.sqrt(max(_spread(fb.color[..., 0]) - s * s / 12 - 1 / 12, 0.0))
    expected = aperture * abs(d - focus) / d * f_px / focus
    if d == focus:
        assert measured <= 1.0
        pinhole = rasterkit.render(_quad(0.0, 0.0, half, -d), dataclasses.replace(camera, aperture=0.0),
                                   "solid", cull="none", color="white", background="black", samples=256)
        assert np.max(np.abs(fb.color.astype(int) - pinhole.color)) <= 8
    else:
        assert expected > 15
        assert abs(measured - expected) <= 0.1 * expected


def test_focus_distance_overrides_the_target_distance():
    camera = Camera.look_at((0, 0, 0), (0, 0, -5), fov_y=40, width=64, height=64, aperture=1.0,
                            focus_distance=3.0)
    assert camera.focus_distance == 3.0
    sharp = rasterkit.render(_quad(0, 0, 0.1, -3.0), camera, "solid", cull="none", color="white",
                             background="black", samples=64)
    blurred = rasterkit.render(_quad(0, 0, 0.1 * 5 / 3, -5.0), camera, "solid", cull="none",
                               color="white", background="black", samples=64)
    assert _spread(sharp.color[..., 0]) * 4 < _spread(blurred.color[..., 0])


# --- vignetting ----------------------------------------------------------------------------


@pytest.mark.parametrize("strength, shift", [(1.0, (0.0, 0.0)), (0.5, (0.0, 0.0)), (1.0, (0.4, -0.3))])
def test_vignetting_is_cos4_of_the_ray_angle(strength, shift):
    width, height = 160, 120
    camera = Camera.look_at((0, 0, 0), (0, 0, -5), fov_y=70, width=width, height=height, shift=shift,
                            far=50.0)
    wall = _quad(0.0, 0.0, 40.0, -5.0)
    plain = rasterkit.render(wall, camera, "solid", color="white", background="white")
    assert np.all(plain.color == 255)
    fb = rasterkit.render(wall, camera, "solid", color="white", background="white", vignette=strength)
    x, y = np.meshgrid(np.arange(width) + 0.5, np.arange(height) + 0.5)
    _, direction = camera.ray(x, y)
    axis = np.subtract(camera.target, camera.eye) / 5.0
    cos = direction @ axis
    expected = 255 * (1 - strength * (1 - cos**4))
    assert np.max(np.abs(fb.color[..., 0] - expected)) <= 0.02 * 255
    assert expected.min() < 0.8 * 255  # the falloff is there to be seen


# --- determinism, buffers, the single-sample path ------------------------------------------


def test_one_and_two_threads_and_two_runs_give_identical_images():
    mesh = shapes.demo()
    center, radius = mesh.bounding_sphere()
    camera = Camera.frame(center, radius, width=96, height=72, aperture=0.3 * radius)
    images = []
    for threads in (1, 2, 1):
        rasterkit.set_threads(threads)
        try:
            images.append(rasterkit.render(mesh, camera, "solid+wire", samples=6, vignette=0.3).color)
        finally:
            rasterkit.set_threads(None)
    assert np.array_equal(images[0], images[1]) and np.array_equal(images[0], images[2])


@pytest.mark.parametrize("mode", ["solid", "hidden", "solid+wire", "wire"])
def test_depth_and_ids_are_those_of_the_centre_sample(mode):
    mesh = shapes.demo()
    center, radius = mesh.bounding_sphere()
    camera = Camera.frame(center, radius, width=64, height=48, aperture=0.2 * radius)
    one = rasterkit.render(mesh, camera, mode, ids=True)
    many = rasterkit.render(mesh, camera, mode, ids=True, samples=4)
    lazy = rasterkit.render(mesh, camera, mode, samples=4)
    assert np.array_equal(many.ids, one.ids)
    assert np.array_equal(many.depth, one.depth) and np.array_equal(lazy.depth, one.depth)
    assert not np.array_equal(many.color, one.color)


def test_one_sample_is_the_pinhole_image_whatever_the_aperture():
    mesh = shapes.demo()
    center, radius = mesh.bounding_sphere()
    pinhole = Camera.frame(center, radius, width=64, height=48)
    lens = dataclasses.replace(pinhole, aperture=radius, focus_distance=radius)
    assert np.array_equal(rasterkit.render(mesh, lens, "solid").color,
                          rasterkit.render(mesh, pinhole, "solid").color)


def test_lens_fields_are_kept_by_with_size_presets_and_frame():
    cam = Camera.look_at((0, 0, 5), (0, 0, 0), aperture=0.5, focus_distance=4.0)
    assert (cam.with_size(32, 24).aperture, cam.with_size(32, 24).focus_distance) == (0.5, 4.0)
    framed = Camera.frame((0, 0, 0), 1.0, aperture=0.2)
    assert framed.aperture == 0.2 and framed.focus_distance is None
    preset = Camera.preset("2-point", (0, 0, 0), 1.0, aperture=0.1, focus_distance=2.0)
    assert (preset.aperture, preset.focus_distance) == (0.1, 2.0)


@pytest.mark.parametrize("kwargs, error", [
    (dict(samples=0), ValueError), (dict(samples=MAX_SAMPLES + 1), ValueError),
    (dict(samples=2.0), TypeError), (dict(samples=True), TypeError), (dict(samples="4"), TypeError),
    (dict(vignette=-0.1), ValueError), (dict(vignette=1.5), ValueError),
    (dict(vignette=float("nan")), ValueError), (dict(vignette="x"), TypeError),
])
def test_bad_samples_and_vignette_are_one_line_errors(kwargs, error):
    camera = Camera.frame((0, 0, 0), 1.0, width=16, height=12)
    with pytest.raises(error) as info:
        rasterkit.render(shapes.cube(), camera, "solid", **kwargs)
    assert "\n" not in str(info.value)


def test_bad_lens_values_are_refused():
    with pytest.raises(ValueError, match="aperture"):
        Camera.look_at((0, 0, 5), (0, 0, 0), aperture=-1.0)
    with pytest.raises(ValueError, match="focus_distance"):
        Camera.look_at((0, 0, 5), (0, 0, 0), focus_distance=0.0)
    with pytest.raises(TypeError):
        Camera.look_at((0, 0, 5), (0, 0, 0), aperture="wide")
    with pytest.raises(ValueError, match="parallel camera has no lens"):
        Camera.frame((0, 0, 0), 1.0, projection="parallel", aperture=0.5)
    with pytest.raises(ValueError, match="parallel camera has no lens"):
        Camera.preset("isometric", (0, 0, 0), 1.0, aperture=0.5)


def test_parallel_cameras_are_antialiased_too():
    camera = Camera.orthographic((0, 0, 5), (0, 0, 0), view_height=3.0, width=64, height=48)
    tri = (np.array([(-1.0, -0.9, 0), (1.1, -0.7, 0), (0.1, 1.0, 0)]), np.array([(0, 1, 2)]))
    fb = rasterkit.render(tri, camera, "solid", cull="none", color="black", background="white",
                          samples=16)
    xy = camera.project(tri[0])[:, :2]
    exact = _coverage(xy, 64, 48)
    assert np.max(np.abs(1.0 - fb.color[..., 0] / 255.0 - exact)) <= 0.1


# --- the command line ----------------------------------------------------------------------


def _run(argv, capsys):
    code = main([str(a) for a in argv])
    return code, capsys.readouterr().err.replace(MESSAGE + "\n", "")


def test_cli_lens_and_samples_match_the_api(tmp_path, capsys):
    out = tmp_path / "dof.png"
    code, err = _run(["render", "--demo", "-o", out, "--size", "64x48", "--mode", "solid", "--samples", "4",
                      "--aperture", "0.3", "--focus", "auto", "--vignette", "0.5"], capsys)
    assert code == 0, err
    mesh = shapes.demo()
    center, radius = mesh.bounding_sphere()
    camera = Camera.preset("perspective", center, radius, width=64, height=48, aperture=0.3)
    expected = rasterkit.render(mesh, camera, "solid", samples=4, vignette=0.5).color
    with Image.open(out) as im:
        assert np.array_equal(np.asarray(im), expected)


@pytest.mark.parametrize("extra", [["--samples", "0"], ["--samples", "300"], ["--focus", "-1"],
                                   ["--focus", "near"], ["--vignette", "2"], ["--aperture", "-1"],
                                   ["--aperture", "0.5", "--projection", "isometric"]])
def test_cli_bad_lens_options_are_one_line_errors(extra, tmp_path, capsys):
    out = tmp_path / "x.png"
    code, err = _run(["render", "--demo", "-o", out, "--size", "32x24", *extra], capsys)
    assert code == 2
    assert err.startswith("rasterkit: error:") and err.count("\n") == 1
    assert not out.exists()


def test_the_average_of_the_sums_rounds_like_integer_division():
    from rasterkit._jit import run_workers
    from rasterkit.kernels.accumulate import add_sample, average_samples

    for n in (2, 3, 4, 7, 16, 100, 255, 256):
        total = np.arange(255 * n + 1, dtype=np.uint16)
        out = np.empty(total.shape, np.uint8)
        run_workers(average_samples, total, out, 1.0 / n, (n // 2 + 0.5) / n)
        assert np.array_equal(out, (total.astype(np.int64) + n // 2) // n)
    total = np.empty(5, np.uint16)
    run_workers(add_sample, total, np.array([0, 1, 2, 254, 255], np.uint8), True)
    run_workers(add_sample, total, np.array([255, 255, 3, 254, 255], np.uint8), False)
    assert total.tolist() == [255, 256, 5, 508, 510]


def test_transparent_samples_average_premultiplied_colour():
    """Over a transparent background an edge pixel keeps its surface colour and gets the
    covered fraction as alpha (premultiplied averaging); its alpha equals, to rounding, the
    grey level of the same render over black."""
    import rasterkit as rk

    vertices = np.array([[-1.0, -0.7, 0.0], [1.2, -1.0, 0.0], [0.3, 1.1, 0.0]])
    mesh = rk.Mesh(vertices, np.array([[0, 1, 2]]))
    camera = rk.Camera.look_at((0.0, 0.0, 4.0), (0.0, 0.0, 0.0), width=40, height=32, fov_y=40.0)
    clear = rk.render(mesh, camera, "solid", color="white", cull="none", background="transparent", samples=16)
    black = rk.render(mesh, camera, "solid", color="white", cull="none", background="black", samples=16)
    alpha = clear.color[..., 3].astype(int)
    edge = (alpha > 0) & (alpha < 255)
    assert edge.sum() > 20
    assert np.all(clear.color[alpha > 0][:, :3] == 255)  # white wherever anything was drawn
    assert np.all(clear.color[alpha == 0][:, :3] == 0)
    assert np.abs(alpha - black.color[..., 0].astype(int)).max() <= 1


def test_sixteen_samples_bound_the_coverage_of_random_triangles():
    """The issue's check over random triangles (not hand-picked ones), restricted to what 16
    point samples can do.

    Family: 40 triangles, vertices uniform in [-1.4, 1.4]² on the plane z = 0 seen by a
    160 x 120 camera (all orientations and shapes), raster area at least 400 px², seed 2026,
    black on white with 16 samples; each pixel's grey against its exact covered fraction
    (:func:`_coverage`, clipping).

    - Every pixel crossed by one edge only (about 98 % of the edge pixels) is within 1/10:
      the pattern keeps every half-plane within 0.0957 of its area (the test above), to
      which snapping the vertices to 1/256 px and rounding to 8 bits add at most 0.006
      (measured over 400 such triangles: 0.0965 at worst).
    - Pixels holding a corner or crossed by two edges are not all within 1/10, and no 16
      samples could make them so (a thin wedge along the line through two samples covers
      2/16 of them and almost no area): they are within 0.2 (the pattern's worst wedge,
      0.189, plus the 0.006), and at least 99.5 % of all the edge pixels are within 1/10
      (measured over 400 triangles: 32 of the 2,331 corner pixels are not).
    - Each triangle's total grey is its area within 1 %.
    """
    width, height = 160, 120
    camera = Camera.look_at((0.0, 0.0, 4.0), (0.0, 0.0, 0.0), fov_y=40.0, width=width, height=height)
    rng = np.random.default_rng(2026)
    errors, done = {"one edge": [], "corner": [], "two edges": []}, 0
    while done < 40:
        v = np.c_[rng.uniform(-1.4, 1.4, (3, 2)), np.zeros(3)]
        xy = camera.project(v)[:, :2]
        (ax, ay), (bx, by) = xy[1] - xy[0], xy[2] - xy[0]
        area = 0.5 * abs(ax * by - ay * bx)
        if area < 400:
            continue
        done += 1
        fb = rasterkit.render((v, np.array([(0, 1, 2)])), camera, "solid", cull="none", color="black",
                              background="white", samples=16)
        dark = 1.0 - fb.color[..., 0] / 255.0
        exact = _coverage(xy, width, height)
        assert np.all(dark[exact == 0] == 0) and np.all(dark[exact == 1] == 1)
        for j, i in zip(*np.nonzero((exact > 0) & (exact < 1))):
            errors[_pixel_kind(xy, i, j)].append(abs(dark[j, i] - exact[j, i]))
        assert abs(dark.sum() - area) <= 0.01 * area
    one, rest = np.array(errors["one edge"]), np.array(errors["corner"] + errors["two edges"])
    assert one.size > 8000 and rest.size > 150
    assert one.max() <= 0.1
    assert rest.max() <= 0.2
    assert np.mean(np.r_[one, rest] <= 0.1) >= 0.995
