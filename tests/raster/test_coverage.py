"""Multi-sample coverage: the pixel sample patterns (whole 1/256 px offsets, tuned for 4, 8,
16 and 32 samples) against the exact covered fraction of each pixel square, computed here
by clipping the triangle to the square; the grey levels of rendered triangles, the issue's
check over random triangles, and the premultiplied averaging of transparent renders."""

import math

import numpy as np
import pytest

import rasterkit
from rasterkit import Camera, shapes
from rasterkit.raster.samples import pixel_offsets
from support.scripts import import_script

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
    """The bounds rasterkit.raster.samples states for one straight edge across a pixel: for every
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


def test_parallel_cameras_are_antialiased_too():
    camera = Camera.orthographic((0, 0, 5), (0, 0, 0), view_height=3.0, width=64, height=48)
    tri = (np.array([(-1.0, -0.9, 0), (1.1, -0.7, 0), (0.1, 1.0, 0)]), np.array([(0, 1, 2)]))
    fb = rasterkit.render(tri, camera, "solid", cull="none", color="black", background="white",
                          samples=16)
    xy = camera.project(tri[0])[:, :2]
    exact = _coverage(xy, 64, 48)
    assert np.max(np.abs(1.0 - fb.color[..., 0] / 255.0 - exact)) <= 0.1


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


@pytest.mark.parametrize("samples", [4, 16])
def test_every_edge_pixel_of_random_triangles_gets_its_covered_fraction(samples):
    """The issue's check over random triangles (not hand-picked ones), small ones included.

    Family: 30 triangles, vertices uniform in [-1.4, 1.4]² on the plane z = 0 seen by a
    160 x 120 camera (all orientations and shapes), raster area at least 20 px², seeded,
    black on white; each pixel's grey against its exact covered fraction (:func:`_coverage`,
    clipping). Point samples alone cannot do it at the corners (a thin wedge along the line
    through two samples covers 2/16 of them and almost no area; a corner between the samples
    none of them): a pixel where the samples saw one face and the background, or that the
    face's outline crosses, gets the face's exact share. What is left is snapping the
    vertices to 1/256 px and rounding to 8 bits: within 0.01 (0.005 measured over 200
    triangles), for every kind of edge pixel, and the total grey is the area within 1 %."""
    width, height = 160, 120
    camera = Camera.look_at((0.0, 0.0, 4.0), (0.0, 0.0, 0.0), fov_y=40.0, width=width, height=height)
    rng = np.random.default_rng(2026 + samples)
    errors, done = {"one edge": [], "corner": [], "two edges": []}, 0
    while done < 30:
        v = np.c_[rng.uniform(-1.4, 1.4, (3, 2)), np.zeros(3)]
        xy = camera.project(v)[:, :2]
        (ax, ay), (bx, by) = xy[1] - xy[0], xy[2] - xy[0]
        area = 0.5 * abs(ax * by - ay * bx)
        if area < 20:
            continue
        done += 1
        fb = rasterkit.render((v, np.array([(0, 1, 2)])), camera, "solid", cull="none", color="black",
                              background="white", samples=samples)
        dark = 1.0 - fb.color[..., 0] / 255.0
        exact = _coverage(xy, width, height)
        assert np.all(dark[exact == 0] <= 0.01) and np.all(dark[exact == 1] == 1)
        for j, i in zip(*np.nonzero((exact > 0) & (exact < 1))):
            errors[_pixel_kind(xy, i, j)].append(abs(dark[j, i] - exact[j, i]))
        assert abs(dark.sum() - area) <= 0.01 * area
    assert len(errors["one edge"]) > 3000 and len(errors["corner"]) > 60 and len(errors["two edges"]) > 60
    for kind, e in errors.items():
        assert max(e) <= 0.01, kind


def test_pixel_area_is_the_triangle_clipped_to_the_pixel():
    """rasterkit.raster.kernels.coverage.pixel_area (edge integrals) against clipping the
    triangle to each pixel square here, for random fixed-point triangles, both windings,
    corners inside and outside the pixels."""
    from rasterkit.raster.kernels.coverage import pixel_areas

    rng = np.random.default_rng(11)
    pixels = np.array([(i, j) for i in range(-1, 5) for j in range(-1, 5)], np.int64)
    for _ in range(300):
        corners = np.rint(rng.uniform(-3, 6, (3, 2)) * 256).astype(np.int64)
        want = np.array([_clip_area(corners / 256.0, i, j) for i, j in pixels])
        assert np.allclose(pixel_areas(corners.reshape(-1), pixels), want, rtol=0, atol=1e-12)
        assert np.allclose(pixel_areas(corners[::-1].reshape(-1), pixels), want, rtol=0, atol=1e-12)


def test_outlines_of_a_mesh_are_exact_where_one_face_meets_the_background():
    """A convex mesh's outline is the convex hull of its projected vertices: each pixel's
    exact coverage is the hull clipped to it. With 16 samples every pixel is within 1/10,
    and the outline pixels where one face meets the background are exact (within 0.01) and
    on average closer than the samples alone give them."""
    from rasterkit.raster import accumulate as _accumulate

    width, height = 120, 90
    mesh = shapes.icosphere(2)
    camera = Camera.look_at((0.3, 0.4, 3.2), (0.0, 0.0, 0.0), fov_y=40.0, width=width, height=height)
    xy = camera.project(mesh.vertices)[:, :2]
    pts = sorted(map(tuple, xy))
    hull = []
    for chain in (pts, pts[::-1]):  # Andrew's monotone chain
        part = []
        for p in chain:
            while len(part) >= 2 and (part[-1][0] - part[-2][0]) * (p[1] - part[-2][1]) \
                    - (part[-1][1] - part[-2][1]) * (p[0] - part[-2][0]) <= 0:
                part.pop()
            part.append(p)
        hull += part[:-1]
    exact = np.array([[_clip_area(hull, i, j) for i in range(width)] for j in range(height)])
    edge = (exact > 0) & (exact < 1)
    dark = {}
    for on in (True, False):
        _accumulate.EXACT_COVERAGE = on
        try:
            fb = rasterkit.render(mesh, camera, "solid", color="black", background="white", samples=16)
        finally:
            _accumulate.EXACT_COVERAGE = True
        dark[on] = 1.0 - fb.color[..., 0] / 255.0
    error, point_error = np.abs(dark[True] - exact), np.abs(dark[False] - exact)
    assert edge.sum() > 250 and error[edge].max() <= 0.1
    assert error[edge].mean() < 0.75 * point_error[edge].mean()
    assert np.sum(error[edge] <= 0.01) > 1.5 * np.sum(point_error[edge] <= 0.01)


def test_smooth_colours_keep_their_exact_share_too():
    """A triangle whose three vertex colours are one red, smooth-shaded over white: every
    pixel is white plus its exact covered fraction times (red - white), corners and slivers
    between the samples included (their colour is the face's at its corner)."""
    width, height = 96, 72
    camera = Camera.look_at((0.0, 0.0, 4.0), (0.0, 0.0, 0.0), fov_y=40.0, width=width, height=height)
    red = np.array([200, 30, 40])
    rng = np.random.default_rng(8)
    for _ in range(6):
        v = np.c_[rng.uniform(-1.3, 1.3, (3, 2)), np.zeros(3)]
        mesh = rasterkit.Mesh(v, np.array([(0, 1, 2)]), vertex_colors=np.tile(red / 255.0, (3, 1)))
        fb = rasterkit.render(mesh, camera, "solid", cull="none", background="white", shading="smooth",
                              light=None, samples=4)
        exact = _coverage(camera.project(v)[:, :2], width, height)
        want = 255 + exact[..., None] * (red - 255)
        assert np.abs(fb.color.astype(float) - want).max() <= 0.01 * 255 + 1


def test_the_tuning_scripts_measure_exact_errors():
    """scripts/coverage_error.py (which tuned the patterns) against clipping: its half-plane
    areas, and its worst wedge error at an apex inside and one outside the pixel against
    every wedge whose sides pass just before or after two samples."""
    coverage_error = import_script("coverage_error")
    cone_errors, halfplane_area = coverage_error.cone_errors, coverage_error.halfplane_area

    rng = np.random.default_rng(5)
    for theta, c in zip(rng.uniform(0, 2 * np.pi, 20), rng.uniform(-0.8, 1.5, 20)):
        w = np.array([math.cos(theta), math.sin(theta)])
        u = np.array([-w[1], w[0]])
        quad = [c * w - 4 * u, c * w + 4 * u, c * w + 4 * u - 4 * w, c * w - 4 * u - 4 * w]
        assert halfplane_area(w[0], w[1], c) == pytest.approx(_clip_area(quad, 0, 0), abs=1e-12)
    points = pixel_offsets(16) + 0.5
    for apex in (np.array([0.37, 0.61]), np.array([-0.8, 1.3])):
        angles = np.arctan2(*(points - apex).T[::-1])
        sides = np.r_[angles - 1e-7, angles + 1e-7]
        worst = 0.0
        for a in sides:
            for b in sides:
                span = (b - a) % (2 * np.pi)
                if 0 < span < np.pi:  # the convex wedge from angle a to b, as a large triangle
                    rays = a + np.array([0, 0.5, 1]) * span
                    far = apex + 9 * np.c_[np.cos(rays), np.sin(rays)]
                    area = _clip_area([apex, far[0], far[1], far[2]], 0, 0)
                    count = np.sum((angles - a) % (2 * np.pi) < span)
                    worst = max(worst, abs(count / 16 - area))
        assert cone_errors(points, apex[None])[0] == pytest.approx(worst, abs=1e-5)
