"""Polygons of many corners (issue 14, item 5): each one is covered exactly (as many triangles
as it needs, wound like it, as much area as its shoelace area, each inside it) or, when it is
not simple, split as a fan with a warning; and huge ones load in bounded time and memory.

The geometry is checked against slow, obvious references written here (shoelace area, even-odd
point in polygon), never against the loader's own helpers.
"""

import math
import textwrap

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rasterkit.obj.kernels.ears import EAR_CLIP_LIMIT, ear_clip
from rasterkit.obj.kernels.monotone import triangulate_monotone
from rasterkit.obj.assemble import split_polygons
from rasterkit.obj.kernels.polygons import EXACT, LARGE, triangulate
from rasterkit.obj import load_obj
from support.hostile import run_python

IRREGULAR = "too irregular to split exactly (self-intersecting?): split as a fan"


# --- shapes (2D, counter-clockwise) and references ------------------------------------------------

def regular(n, radius=1.0):
    t = 2 * np.pi * np.arange(n) / n
    return np.stack([radius * np.cos(t), radius * np.sin(t)], axis=1)


def star(n, radii=(1.0, 0.5)):
    return regular(n) * np.resize(np.asarray(radii, float), n)[:, None]


def random_star(n, seed):
    return regular(n) * np.random.default_rng(seed).uniform(0.1, 1.0, n)[:, None]


def comb(teeth, depth=10.0):
    top = []
    for k in range(teeth - 1, -1, -1):
        top += [(2.0 * k + 2, depth), (2.0 * k + 1, depth), (2.0 * k + 1, 1.0)]
    return np.array([(0.0, 0.0), (2.0 * teeth, 0.0), *top, (0.0, depth)])


def spiral(n, turns):
    t = np.linspace(0.5, turns, n // 2) * 2 * np.pi
    r = t / (2 * np.pi)
    outer = np.stack([(r + 0.4) * np.cos(t), (r + 0.4) * np.sin(t)], axis=1)
    return np.concatenate([outer, np.stack([r * np.cos(t), r * np.sin(t)], axis=1)[::-1]])


def histogram(heights):
    """Bars side by side on the x axis: many horizontal sides, corners at equal heights, and a
    corner repeated where two neighbouring bars are as high."""
    top = []
    for k in range(len(heights) - 1, -1, -1):
        top += [(k + 1.0, float(heights[k])), (float(k), float(heights[k]))]
    return np.array([(0.0, 0.0), (float(len(heights)), 0.0), *top])


def with_holes(k):
    """A rectangle with k square holes (clockwise), each joined to corner 0 by a bridge walked
    both ways: points and the ring of point indices."""
    points = [(0.0, 0.0), (3.0 * k + 1, 0.0), (3.0 * k + 1, 4.0), (0.0, 4.0)]
    ring = [0]
    for i in range(k):
        x = 3.0 * i + 1
        base = len(points)
        points += [(x, 1.0), (x, 3.0), (x + 2, 3.0), (x + 2, 1.0)]
        ring += [base, base + 1, base + 2, base + 3, base, 0]
    return np.array(points), np.array(ring + [1, 2, 3])


def shoelace(ring_points):
    x, y = ring_points[:, 0], ring_points[:, 1]
    return 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)


def inside(points, ring_points):
    """Even-odd test of many points against a ring (a bridge walked both ways cancels)."""
    x, y = points[:, :1], points[:, 1:2]
    x0, y0 = ring_points[:, 0], ring_points[:, 1]
    x1, y1 = np.roll(x0, -1), np.roll(y0, -1)
    with np.errstate(divide="ignore", invalid="ignore"):
        crossing = ((y0 > y) != (y1 > y)) & (x < x0 + (y - y0) * (x1 - x0) / (y1 - y0))
    return np.count_nonzero(crossing, axis=1) % 2 == 1


def signed_areas(triangles):
    a, b, c = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    return 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1])
                  - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))


def assert_covers(points, ring, triangles, count=None):
    """Triangles (T, 3) of indices into points cover the ring exactly: `count` of them (m - 2
    by default), none turning right, as much area as the ring, every one inside it."""
    ring_points = points[ring]
    expected = shoelace(ring_points)
    assert expected > 0
    assert len(triangles) == (len(ring) - 2 if count is None else count)
    areas = signed_areas(points[triangles])
    assert areas.min() >= -1e-9 * expected
    assert areas.sum() == pytest.approx(expected, rel=1e-9)
    real = areas > 1e-9 * expected / len(ring)
    assert inside(points[triangles[real]].mean(axis=1), ring_points).all()


def write_polygon(folder, points, ring=None, z=0.0, rotation=None, name="p.obj"):
    ring = np.arange(len(points)) if ring is None else ring
    xyz = np.column_stack([points, np.full(len(points), z)])
    if rotation is not None:
        xyz = xyz @ rotation.T
    text = "".join(f"v {x!r} {y!r} {w!r}\n" for x, y, w in xyz.tolist())
    text += "f " + " ".join(str(i + 1) for i in ring) + "\n"
    path = folder / name
    path.write_text(text)
    return path


def rotation(a, b, c):
    rx = np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])
    ry = np.array([[math.cos(b), 0, math.sin(b)], [0, 1, 0], [-math.sin(b), 0, math.cos(b)]])
    rz = np.array([[math.cos(c), -math.sin(c), 0], [math.sin(c), math.cos(c), 0], [0, 0, 1]])
    return rz @ ry @ rx


# --- exact cover of large simple polygons ---------------------------------------------------------

def test_the_large_polygons_here_are_larger_than_ear_clipping_takes():
    assert EAR_CLIP_LIMIT < 200


SHAPES = {
    "concave star": lambda: star(3000),
    "random star": lambda: random_star(3000, seed=1),
    "comb": lambda: comb(700),
    "spiral": lambda: spiral(4000, turns=10),
    "regular": lambda: regular(5000),
    "histogram": lambda: histogram(np.random.default_rng(2).integers(1, 4, 700)),
}


@pytest.mark.parametrize("shape", SHAPES)
def test_large_simple_polygons_are_covered_exactly(tmp_path, shape):
    points = SHAPES[shape]()
    mesh = load_obj(write_polygon(tmp_path, points))
    assert mesh.warnings == ()
    ring = np.arange(len(points))
    # a corner at the same place as the one before it makes no triangle
    places = np.count_nonzero(np.any(points != np.roll(points, 1, axis=0), axis=1))
    assert_covers(points, ring, mesh.faces, count=places - 2)


@pytest.mark.parametrize("holes", [30, 300])
def test_large_polygons_with_holes_joined_by_bridges_are_covered(tmp_path, holes):
    points, ring = with_holes(holes)
    mesh = load_obj(write_polygon(tmp_path, points, ring))
    assert mesh.warnings == ()
    areas = signed_areas(points[mesh.faces])
    assert areas.min() >= 0
    assert areas.sum() == pytest.approx((3 * holes + 1) * 4 - 4 * holes, rel=1e-12)
    centres = points[mesh.faces].mean(axis=1)
    assert inside(centres, points[ring]).all()
    assert len(mesh.faces) <= len(ring) - 2


@settings(deadline=None, max_examples=25)
@given(radii=st.lists(st.floats(0.2, 3.0), min_size=EAR_CLIP_LIMIT + 1, max_size=400),
       angles=st.tuples(*[st.floats(-math.pi, math.pi)] * 3),
       offset=st.tuples(*[st.floats(-1e3, 1e3)] * 3), clockwise=st.booleans())
def test_star_shaped_polygons_in_any_plane_are_covered_exactly(tmp_path_factory, radii, angles,
                                                               offset, clockwise):
    n = len(radii)
    flat = regular(n) * np.array(radii)[:, None]
    ring = np.arange(n)[::-1] if clockwise else np.arange(n)
    points = np.column_stack([flat, np.zeros(n)]) @ rotation(*angles).T + np.array(offset)
    folder = tmp_path_factory.mktemp("star")
    text = "".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in points.tolist())
    (folder / "s.obj").write_text(text + "f " + " ".join(str(i + 1) for i in ring) + "\n")
    mesh = load_obj(folder / "s.obj")
    assert mesh.warnings == ()
    # back in the polygon's plane: the rotation undone
    plane = ((mesh.vertices - np.array(offset)) @ rotation(*angles))[:, :2]
    assert_covers(plane, ring if not clockwise else ring[::-1],
                  mesh.faces if not clockwise else mesh.faces[:, ::-1])


@pytest.mark.parametrize("seed", range(6))
def test_both_methods_cover_the_polygons_ear_clipping_takes(seed):
    """The sweep also covers small polygons, and ear clipping (what the polygon kernel uses for
    them) the same ones; corners at the same place as the one before make no triangle."""
    rng = np.random.default_rng(seed)
    for n in (4, 7, 20, EAR_CLIP_LIMIT):
        for points in (random_star(n, int(rng.integers(1 << 30))), star(max(n - n % 2, 4)),
                       histogram(rng.integers(1, 3, max(n // 2, 2)))):
            ring = np.arange(len(points))
            places = np.count_nonzero(np.any(points != np.roll(points, 1, axis=0), axis=1))
            xy = np.ascontiguousarray(points)
            out = np.full((len(ring) - 2, 3), -1, np.int64)
            assert triangulate_monotone(xy, ring, out)
            assert_covers(xy, ring, out[(out >= 0).all(axis=1)], count=places - 2)
            vertices = np.column_stack([points, np.zeros(len(points))])
            triangles, counts, state = triangulate(vertices, ring, np.array([0, len(ring)]),
                                                   np.ones(1, bool))
            assert state[0] == (LARGE if len(ring) > EAR_CLIP_LIMIT else EXACT)
            if state[0] == EXACT:
                assert_covers(xy, ring, triangles, count=len(triangles))
            triangles, counts, inexact = split_polygons(vertices, ring, np.array([0, len(ring)]),
                                                        np.ones(1, bool))
            assert not inexact[0]
            nonflat = triangles[signed_areas(points[triangles]) != 0]
            assert_covers(xy, ring, triangles, count=len(triangles))
            assert len(nonflat) <= places - 2


# --- convex polygons, repeated cycles, self-intersecting polygons ---------------------------------

@pytest.mark.parametrize("n", [5, 50, 2000])
def test_convex_polygons_are_the_fan_ear_clipping_cuts(tmp_path, n):
    points = regular(n, 3.0)
    mesh = load_obj(write_polygon(tmp_path, points, rotation=rotation(0.3, -1.1, 2.0)))
    fan = [[n - 1, k, k + 1] for k in range(n - 2)]
    np.testing.assert_array_equal(mesh.faces, fan)
    if n <= EAR_CLIP_LIMIT:  # what the ear clipper itself cuts
        out = np.full((n - 2, 3), -1, np.int64)
        assert ear_clip(np.ascontiguousarray(points), np.arange(n), out)
        np.testing.assert_array_equal(out, fan)


def test_a_cycle_walked_several_times_is_the_cycle_once(tmp_path):
    square = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
    (tmp_path / "m.obj").write_text(square + "f " + " 1 2 3 4" * 3 + "\nf 1 2 4 3 4\n")
    mesh = load_obj(tmp_path / "m.obj")
    np.testing.assert_array_equal(mesh.faces[:2], [[3, 0, 1], [3, 1, 2]])
    assert mesh.warnings == ()


@pytest.mark.parametrize("step, winding", [(2, "twice"), (1, "figure eight")])
def test_large_self_intersecting_polygons_are_a_fan_with_a_warning(tmp_path, step, winding):
    n = 201
    if step == 2:  # a star polygon: every second corner of a circle, round twice
        ring = (np.arange(n) * 2) % n
        points = regular(n)
    else:  # a figure eight: round one loop counter-clockwise, the other clockwise
        t = 2 * np.pi * np.arange(n) / n
        points = np.stack([np.sin(t), np.sin(t) * np.cos(t)], axis=1)
        ring = np.arange(n)
        points[0] += 1e-3  # the crossing is not a corner
    path = write_polygon(tmp_path, points, ring)
    mesh = load_obj(path)
    assert mesh.warnings == (f"{path}:{n + 1}: 1 polygon {IRREGULAR}",), winding
    np.testing.assert_array_equal(mesh.faces, [[ring[0], ring[k], ring[k + 1]]
                                               for k in range(1, n - 1)])


def test_small_self_intersecting_polygons_end(tmp_path):
    rng = np.random.default_rng(5)
    for n in (5, 30, EAR_CLIP_LIMIT):
        points = rng.random((n, 2))
        mesh = load_obj(write_polygon(tmp_path, points))
        assert len(mesh.faces) <= n - 2
        assert all(IRREGULAR in w for w in mesh.warnings)


# --- time and memory of huge polygons, in a child process -----------------------------------------

def test_huge_polygons_load_in_bounded_time_and_memory(tmp_path):
    """Each of these took from 11 s to minutes (or gigabytes) when every polygon beyond a
    convex quad was ear clipped; here all of them together get 120 s and 3 GiB of address
    space (they take a few seconds)."""
    rng = np.random.default_rng(0)
    cases = {
        "convex": (regular(200_000), np.arange(200_000), 200_000 - 2, False),
        "star": (star(100_000), np.arange(100_000), 100_000 - 2, False),
        "cycled": (regular(3), np.tile([0, 1, 2], 100_000), 1, False),
        "repeated": (regular(3), np.r_[np.zeros(300_000, int), 1, 2], 1, False),
        "walked round": (regular(1000), np.arange(1_000_500) % 1000, None, True),
        "random": (regular(1000), rng.integers(0, 1000, 1_000_000), None, True),
    }
    for name, (points, ring, _, _) in cases.items():
        write_polygon(tmp_path, points, ring, name=f"{name}.obj")
    outcome = run_python(textwrap.dedent(f"""
        from rasterkit import load_obj
        for name in {list(cases)!r}:
            mesh = load_obj({str(tmp_path)!r} + "/" + name + ".obj")
            print(name, len(mesh.faces), len(mesh.warnings), sep="|")
    """), timeout=120)
    assert outcome.code == 0, outcome.describe()
    printed = {name: rest for name, *rest in map(lambda s: s.split("|"),
                                                 outcome.stdout.splitlines())}
    for name, (_, ring, triangles, warned) in cases.items():
        faces, warnings = map(int, printed[name])
        assert warnings == (1 if warned else 0), name
        assert faces == triangles if triangles is not None else 0 < faces <= len(ring) - 2, name


def test_numpy_splits_polygons_as_the_kernel_does():
    """split_polygons (NumPy for triangles, quads convex or not, convex and concave polygons
    of a few corners, quads with a repeated corner; the kernels for the rest) gives the very
    rows, counts and warnings of the general kernel, dropped polygons included, for polygons
    whose turns are far from 0 (where rounding cannot decide)."""
    rng = np.random.default_rng(11)
    vertices = list(rng.uniform(-1, 1, (60, 3)))  # the triangles' corners, shared
    polygons = []
    for _ in range(600):
        kind = rng.integers(5)
        if kind == 0:  # a triangle, now and then with a repeated corner (dropped)
            ring = rng.choice(60, 3, replace=False)
            if rng.random() < 0.1:
                ring[1] = ring[0]
        else:  # a star-shaped polygon of 4 to 12 corners, convex or not, in a random plane
            m = 4 if kind < 3 else int(rng.integers(5, 13))
            angles = np.sort(rng.uniform(0, 2 * np.pi, m))
            radii = rng.uniform(0.2, 1, m) if kind % 2 else np.ones(m)
            basis = np.linalg.qr(rng.normal(size=(3, 3)))[0]
            flat = np.stack([radii * np.cos(angles), radii * np.sin(angles), 0.05 * rng.normal(size=m)], axis=1)
            ring = np.arange(len(vertices), len(vertices) + m)
            vertices += list(rng.uniform(-1, 1, 3) + flat @ basis.T)
            if m == 4 and rng.random() < 0.1:
                ring[int(rng.integers(4))] = ring[int(rng.integers(4))]  # a repeat
        polygons.append(ring)
    vertices = np.array(vertices)
    offsets = np.cumsum([0] + [len(r) for r in polygons])
    flat = np.concatenate(polygons).astype(np.int64)
    keep = rng.random(len(polygons)) < 0.9
    triangles, counts, inexact = split_polygons(vertices, flat, offsets, keep)
    expected, expected_counts, state = triangulate(vertices, flat, offsets, keep)
    np.testing.assert_array_equal(triangles, expected)
    np.testing.assert_array_equal(counts, expected_counts)
    np.testing.assert_array_equal(inexact, state != EXACT)
    assert len(triangles) > 1000
