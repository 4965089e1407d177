"""Tests for rasterkit.camera: the chain against OpenGL's textbook matrices, each factor's job,
pixel rays, and the axonometric, oblique and 1/2/3-point projections."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from rasterkit.camera import Camera
from rasterkit.transform import compose, from_homogeneous

SETTINGS = settings(max_examples=40, deadline=None)


# --- an independent OpenGL-style reference: gluLookAt, glFrustum / glOrtho, glViewport -------


def _normalize(v):
    return v / np.linalg.norm(v)


def gl_look_at(eye, center, up):
    """gluLookAt: rows s, u, -f and the translation by -eye."""
    eye = np.asarray(eye, float)
    f = _normalize(np.asarray(center, float) - eye)
    s = _normalize(np.cross(f, up))
    u = np.cross(s, f)
    m = np.eye(4)
    m[0, :3], m[1, :3], m[2, :3] = s, u, -f
    m[:3, 3] = -m[:3, :3] @ eye
    return m


def gl_frustum(left, right, bottom, top, near, far):
    """glFrustum: the (possibly asymmetric) perspective frustum to the NDC cube [-1, 1]³."""
    return np.array(
        [
            [2 * near / (right - left), 0, (right + left) / (right - left), 0],
            [0, 2 * near / (top - bottom), (top + bottom) / (top - bottom), 0],
            [0, 0, -(far + near) / (far - near), -2 * far * near / (far - near)],
            [0, 0, -1, 0],
        ]
    )


def gl_ortho(left, right, bottom, top, near, far):
    """glOrtho: the view box to the NDC cube [-1, 1]³."""
    return np.array(
        [
            [2 / (right - left), 0, 0, -(right + left) / (right - left)],
            [0, 2 / (top - bottom), 0, -(top + bottom) / (top - bottom)],
            [0, 0, -2 / (far - near), -(far + near) / (far - near)],
            [0, 0, 0, 1],
        ]
    )


def gl_window(clip, width, height):
    """Perspective divide and glViewport with glDepthRange(0, 1); y flipped to a top-left origin."""
    ndc = clip[:, :3] / clip[:, 3:]
    x = (ndc[:, 0] + 1) * width / 2
    y = height - (ndc[:, 1] + 1) * height / 2
    return np.stack([x, y, (ndc[:, 2] + 1) / 2], axis=1)


def gl_window_edges(cam):
    """glFrustum's left, right, bottom, top for the camera's (possibly shifted) window."""
    top = cam.near * math.tan(math.radians(cam.fov_y) / 2)
    right = top * cam.width / cam.height
    sx, sy = cam.shift
    return right * (sx - 1), right * (sx + 1), top * (sy - 1), top * (sy + 1)


def gl_project(cam, points):
    view = gl_look_at(cam.eye, cam.target, cam.up)
    m = gl_frustum(*gl_window_edges(cam), cam.near, cam.far) @ view
    return gl_window(np.c_[points, np.ones(len(points))] @ m.T, cam.width, cam.height)


def frustum_points(cam, a, b, depth):
    """World points at window coordinates (a, b) in [-1, 1]² and distance ``depth`` along the view.

    Built from gluLookAt's frame and glFrustum's window edges, not from the camera's code.
    """
    m = gl_look_at(cam.eye, cam.target, cam.up)
    s, u, back = m[0, :3], m[1, :3], m[2, :3]
    left, right, bottom, top = (e / cam.near for e in gl_window_edges(cam))
    x = left + (np.asarray(a) + 1) / 2 * (right - left)
    y = bottom + (np.asarray(b) + 1) / 2 * (top - bottom)
    depth = np.asarray(depth)[:, None]
    return np.asarray(cam.eye) + depth * (-back + x[:, None] * s + y[:, None] * u)


def box_points(cam, a, b, depth):
    """World points of an orthographic camera's view box, from gluLookAt's frame."""
    m = gl_look_at(cam.eye, cam.target, cam.up)
    s, u, back = m[0, :3], m[1, :3], m[2, :3]
    half_h = cam.view_height / 2
    half_w = half_h * cam.width / cam.height
    return (np.asarray(cam.eye) - np.asarray(depth)[:, None] * back
            + (np.asarray(a) * half_w)[:, None] * s + (np.asarray(b) * half_h)[:, None] * u)


CORNERS_A = np.array([-1, 1, -1, 1, -1, 1, -1, 1], float)
CORNERS_B = np.array([-1, -1, 1, 1, -1, -1, 1, 1], float)
CORNERS_NEAR = np.array([True] * 4 + [False] * 4)


def corner_depths(cam):
    return np.where(CORNERS_NEAR, cam.near, cam.far)


# --- strategies -----------------------------------------------------------------------------


coords = st.floats(-50, 50, allow_nan=False)
vectors = st.tuples(coords, coords, coords)


@st.composite
def unit_vectors(draw):
    v = np.array(draw(st.tuples(*[st.floats(-1, 1)] * 3)))
    assume(np.linalg.norm(v) > 0.2)
    return _normalize(v)


@st.composite
def view_frames(draw):
    """eye, target, up with up at least ~6° away from the view direction."""
    eye = np.array(draw(vectors))
    direction = draw(unit_vectors())
    target = eye + draw(st.floats(0.5, 50)) * direction
    up = draw(unit_vectors())
    assume(np.linalg.norm(np.cross(up, direction)) > 0.1)
    return tuple(eye), tuple(target), tuple(up)


sizes = st.tuples(st.integers(1, 2000), st.integers(1, 2000))
near_far = st.tuples(st.floats(0.01, 5), st.floats(1.5, 1000)).map(lambda t: (t[0], t[0] * t[1]))


@st.composite
def perspective_cameras(draw, shifted=None):
    eye, target, up = draw(view_frames())
    width, height = draw(sizes)
    near, far = draw(near_far)
    if shifted is None:
        shifted = draw(st.booleans())
    shift = (0.0, 0.0)
    if shifted:
        shift = draw(st.tuples(st.floats(-1.5, 1.5), st.floats(-1.5, 1.5)))
        assume(max(map(abs, shift)) > 0.01)
    return Camera.look_at(eye, target, up, fov_y=draw(st.floats(5, 150)), width=width,
                          height=height, near=near, far=far, shift=shift)


@st.composite
def orthographic_cameras(draw):
    eye, target, up = draw(view_frames())
    width, height = draw(sizes)
    near, far = draw(near_far)
    return Camera.orthographic(eye, target, up, view_height=draw(st.floats(0.1, 100)),
                               width=width, height=height, near=near, far=far)


@st.composite
def parallel_cameras(draw):
    """Orthographic cameras and framed oblique ones."""
    if draw(st.booleans()):
        return draw(orthographic_cameras())
    width, height = draw(sizes)
    return Camera.oblique(draw(st.floats(-180, 180)), draw(st.floats(0, 2)), draw(vectors),
                          draw(st.floats(0.1, 20)), azimuth=draw(st.floats(-180, 180)),
                          elevation=draw(st.floats(-80, 80)), width=width, height=height)


seeds = st.integers(0, 2**32 - 1)


def random_frustum_points(cam, seed, n=50):
    rng = np.random.default_rng(seed)
    a, b = rng.uniform(-1, 1, (2, n))
    return frustum_points(cam, a, b, rng.uniform(cam.near, cam.far, n))


def canonical_tol(cam):
    """Error to expect in the canonical volume: rounding of world points (about |eye|·eps),
    magnified by the narrowest half window at the near plane."""
    half_h = cam.near * math.tan(math.radians(cam.fov_y) / 2)
    narrowest = half_h * min(1.0, cam.width / cam.height)
    return 1e-9 + 1e-13 * (1 + np.abs(cam.eye).max() + cam.far) / narrowest


def partial(cam, last):
    """Product of the chain's factors up to and including ``last``."""
    names = [name for name, _ in cam.chain()]
    return compose(*(m for _, m in cam.chain()[: names.index(last) + 1]))


def apply_h(m, points):
    return np.c_[points, np.ones(len(points))] @ m.T


# --- the chain against OpenGL ---------------------------------------------------------------


@SETTINGS
@given(perspective_cameras(), seeds)
def test_perspective_chain_matches_opengl(cam, seed):
    points = random_frustum_points(cam, seed)
    ours, gl = cam.project(points), gl_project(cam, points)
    size = max(cam.width, cam.height)
    np.testing.assert_allclose(ours[:, :2], gl[:, :2], rtol=0, atol=1e-9 * size)
    np.testing.assert_allclose(ours[:, 2], gl[:, 2], rtol=0, atol=1e-9)


@SETTINGS
@given(orthographic_cameras(), seeds)
def test_orthographic_chain_matches_opengl(cam, seed):
    rng = np.random.default_rng(seed)
    a, b = rng.uniform(-1, 1, (2, 50))
    points = box_points(cam, a, b, rng.uniform(cam.near, cam.far, 50))
    half_h = cam.view_height / 2
    half_w = half_h * cam.width / cam.height
    m = gl_ortho(-half_w, half_w, -half_h, half_h, cam.near, cam.far) @ gl_look_at(
        cam.eye, cam.target, cam.up)
    gl = gl_window(apply_h(m, points), cam.width, cam.height)
    ours = cam.project(points)
    size = max(cam.width, cam.height)
    np.testing.assert_allclose(ours[:, :2], gl[:, :2], rtol=0, atol=1e-9 * size)
    np.testing.assert_allclose(ours[:, 2], gl[:, 2], rtol=0, atol=1e-9)


@SETTINGS
@given(perspective_cameras())
def test_frustum_corners_map_to_raster_box_corners(cam):
    corners = cam.project(frustum_points(cam, CORNERS_A, CORNERS_B, corner_depths(cam)))
    expected = np.c_[(CORNERS_A + 1) / 2 * cam.width, (1 - CORNERS_B) / 2 * cam.height,
                     np.where(CORNERS_NEAR, 0.0, 1.0)]
    size = max(cam.width, cam.height)
    np.testing.assert_allclose(corners[:, :2], expected[:, :2], rtol=0, atol=1e-9 * size)
    np.testing.assert_allclose(corners[:, 2], expected[:, 2], rtol=0, atol=1e-9)


@SETTINGS
@given(perspective_cameras(), seeds)
def test_points_inside_the_frustum_map_inside_the_raster_box(cam, seed):
    h = cam.project_h(random_frustum_points(cam, seed))
    p = from_homogeneous(h)
    tol = 1e-9 * max(cam.width, cam.height)
    assert np.all(h[:, 3] > 0)
    assert np.all((p[:, 0] >= -tol) & (p[:, 0] <= cam.width + tol))
    assert np.all((p[:, 1] >= -tol) & (p[:, 1] <= cam.height + tol))
    assert np.all((p[:, 2] >= -1e-9) & (p[:, 2] <= 1 + 1e-9))


def test_known_camera_by_hand():
    # Eye at +5z looking at the origin, 90° opening, 4x2 image: the origin is the image centre;
    # (1, 0, 0) is at 1/5 of the half width right of it.
    cam = Camera.look_at((0, 0, 5), (0, 0, 0), fov_y=90, width=4, height=2, near=1, far=9)
    np.testing.assert_allclose(cam.project([[0, 0, 0], [1, 0, 0], [0, 0, 4], [0, 0, -4]]),
                               [[2, 1, 0.9], [2 + 0.2 * 2 / 2, 1, 0.9], [2, 1, 0], [2, 1, 1]])


# --- each factor does what its docstring says ------------------------------------------------


def test_chain_names_and_product():
    persp = Camera.look_at((1, 2, 3), (0, 0, 0))
    para = Camera.orthographic((1, 2, 3), (0, 0, 0))
    assert [n for n, _ in persp.chain()] == ["T", "R", "H", "S_xy", "S_far", "P_persp",
                                             "P_parallel", "S_raster", "Raster"]
    assert [n for n, _ in para.chain()] == ["T", "R", "T_near", "S_xyz", "P_parallel",
                                            "S_raster", "Raster"]
    for cam in (persp, para):
        product = np.eye(4)
        for _, m in cam.chain():
            assert m.shape == (4, 4) and m.dtype == np.float64
            product = m @ product
        np.testing.assert_array_equal(cam.matrix(), product)


@SETTINGS
@given(perspective_cameras())
def test_T_and_R_bring_the_camera_to_the_origin_looking_down_minus_z(cam):
    eye, target = np.asarray(cam.eye), np.asarray(cam.target)
    np.testing.assert_allclose(apply_h(partial(cam, "T"), [eye])[0], [0, 0, 0, 1], atol=1e-12)
    view = partial(cam, "R")
    np.testing.assert_allclose(view, cam.view_matrix())
    distance = np.linalg.norm(target - eye)
    t = apply_h(view, [target])[0]
    np.testing.assert_allclose(t[:3], [0, 0, -distance], atol=1e-9 * (1 + distance))
    up = view[:3, :3] @ cam.up
    assert abs(up[0]) < 1e-12 and up[1] > 0
    np.testing.assert_allclose(view[:3, :3] @ view[:3, :3].T, np.eye(3), atol=1e-12)
    assert np.linalg.det(view[:3, :3]) == pytest.approx(1.0)


@SETTINGS
@given(perspective_cameras())
def test_after_S_xy_the_side_planes_have_slope_one(cam):
    corners = frustum_points(cam, CORNERS_A, CORNERS_B, corner_depths(cam))
    p = apply_h(partial(cam, "S_xy"), corners)
    tol = canonical_tol(cam) * cam.far
    np.testing.assert_allclose(p[:, 0], CORNERS_A * -p[:, 2], rtol=0, atol=tol)
    np.testing.assert_allclose(p[:, 1], CORNERS_B * -p[:, 2], rtol=0, atol=tol)
    np.testing.assert_allclose(-p[:, 2], corner_depths(cam), rtol=1e-9)


@SETTINGS
@given(perspective_cameras())
def test_after_S_far_the_far_plane_is_at_minus_one(cam):
    corners = frustum_points(cam, CORNERS_A, CORNERS_B, corner_depths(cam))
    z = apply_h(partial(cam, "S_far"), corners)[:, 2]
    np.testing.assert_allclose(z, np.where(CORNERS_NEAR, -cam.near / cam.far, -1.0), rtol=1e-9)


@SETTINGS
@given(perspective_cameras(), seeds)
def test_after_P_persp_the_frustum_is_the_canonical_box(cam, seed):
    corners = frustum_points(cam, CORNERS_A, CORNERS_B, corner_depths(cam))
    box = from_homogeneous(apply_h(partial(cam, "P_persp"), corners))
    expected = np.c_[CORNERS_A, CORNERS_B, np.where(CORNERS_NEAR, 0.0, -1.0)]
    tol = canonical_tol(cam)
    np.testing.assert_allclose(box, expected, atol=tol)
    # Straight lines stay straight: inside points stay inside the box.
    inside = from_homogeneous(apply_h(partial(cam, "P_persp"), random_frustum_points(cam, seed)))
    assert np.all(np.abs(inside[:, :2]) <= 1 + tol)
    assert np.all((inside[:, 2] <= tol) & (inside[:, 2] >= -1 - tol))


@SETTINGS
@given(perspective_cameras())
def test_P_parallel_keeps_depth_in_zero_one_and_w_positive(cam):
    corners = frustum_points(cam, CORNERS_A, CORNERS_B, corner_depths(cam))
    h = apply_h(partial(cam, "P_parallel"), corners)
    assert np.all(h[:, 3] > 0)
    tol = canonical_tol(cam)
    np.testing.assert_allclose(h[:, 2] / h[:, 3], np.where(CORNERS_NEAR, 0.0, 1.0), atol=tol)
    np.testing.assert_allclose(h[:, :2] / h[:, 3:], np.c_[CORNERS_A, CORNERS_B], atol=tol)


def test_S_raster_and_Raster():
    cam = Camera.look_at((0, 0, 5), (0, 0, 0), width=8, height=6)
    factors = dict(cam.chain())
    window = [[-1, -1, 0.5, 1], [1, 1, 0.5, 1], [0, 0, 0.5, 1]]
    scaled = np.asarray(window) @ factors["S_raster"].T
    np.testing.assert_array_equal(scaled[:, :2], [[-4, -3], [4, 3], [0, 0]])
    raster = scaled @ factors["Raster"].T
    # Bottom-left of the window is the raster's bottom-left (0, H); top-right is (W, 0).
    np.testing.assert_array_equal(raster[:, :3], [[0, 6, 0.5], [8, 0, 0.5], [4, 3, 0.5]])


@SETTINGS
@given(orthographic_cameras())
def test_parallel_factors_T_near_and_S_xyz(cam):
    corners = box_points(cam, CORNERS_A, CORNERS_B, corner_depths(cam))
    z = apply_h(partial(cam, "T_near"), corners)[:, 2]
    np.testing.assert_allclose(z, np.where(CORNERS_NEAR, 0.0, cam.near - cam.far),
                               atol=1e-9 * (1 + cam.far))
    box = apply_h(partial(cam, "S_xyz"), corners)
    expected = np.c_[CORNERS_A, CORNERS_B, np.where(CORNERS_NEAR, 0.0, -1.0)]
    np.testing.assert_allclose(box[:, :3], expected, atol=1e-9 * (1 + cam.far / cam.near))
    h = cam.project_h(corners)
    np.testing.assert_array_equal(h[:, 3], 1.0)


@SETTINGS
@given(perspective_cameras(shifted=False))
def test_H_is_the_identity_for_a_centred_window(cam):
    np.testing.assert_array_equal(dict(cam.chain())["H"], np.eye(4))


@SETTINGS
@given(perspective_cameras(shifted=True))
def test_H_shears_the_window_centre_onto_the_minus_z_axis(cam):
    h = dict(cam.chain())["H"]
    assert not np.array_equal(h, np.eye(4))
    assert np.linalg.det(h) == pytest.approx(1.0)
    left, right, bottom, top = (e / cam.near for e in gl_window_edges(cam))
    centre = h @ [(left + right) / 2, (bottom + top) / 2, -1, 1]
    np.testing.assert_allclose(centre, [0, 0, -1, 1], atol=1e-12)
    # A shear: z (and so every plane z = const) stays, and the eye stays at the origin.
    np.testing.assert_array_equal(h[2], [0, 0, 1, 0])
    np.testing.assert_array_equal(h[:, 3], [0, 0, 0, 1])


# --- projecting, pixel rays -----------------------------------------------------------------


def test_project_h_w_tells_front_from_behind():
    cam = Camera.look_at((0, 0, 5), (0, 0, 0))
    w = cam.project_h([[0, 0, 0], [0, 0, 6], [3, 1, 5]])[:, 3]
    assert w[0] > 0 and w[1] < 0 and w[2] == 0


@SETTINGS
@given(st.one_of(perspective_cameras(), parallel_cameras()), seeds)
def test_points_along_a_ray_project_back_onto_its_raster_point(cam, seed):
    rng = np.random.default_rng(seed)
    x, y = rng.uniform(0, cam.width, 20), rng.uniform(0, cam.height, 20)
    origin, direction = cam.ray(x, y)
    np.testing.assert_allclose(np.linalg.norm(direction, axis=1), 1.0)
    if cam.kind == "perspective":
        np.testing.assert_array_equal(origin, np.broadcast_to(cam.eye, origin.shape))
        t = rng.uniform(cam.near, cam.far, (20, 1))
    else:
        # One common direction; the origins lie on the near plane (depth 0).
        np.testing.assert_allclose(direction, np.broadcast_to(direction[0], direction.shape))
        np.testing.assert_allclose(cam.project(origin)[:, 2], 0.0, atol=1e-9)
        t = rng.uniform(0, cam.far - cam.near, (20, 1))
    p = cam.project(origin + t * direction)
    tol = 1e-9 * max(cam.width, cam.height)
    np.testing.assert_allclose(p[:, 0], x, rtol=0, atol=tol)
    np.testing.assert_allclose(p[:, 1], y, rtol=0, atol=tol)


def test_ray_through_a_pixel_centre_by_hand():
    cam = Camera.look_at((0, 0, 5), (0, 0, 0), fov_y=90, width=2, height=2)
    origin, direction = cam.ray(1.5, 0.5)  # pixel (1, 0): upper right quadrant
    assert origin.shape == direction.shape == (3,)
    np.testing.assert_array_equal(origin, [0, 0, 5])
    np.testing.assert_allclose(direction, _normalize(np.array([0.5, 0.5, -1])))
    ortho = Camera.orthographic((0, 0, 5), (0, 0, 0), view_height=2, width=2, height=2, near=1)
    origin, direction = ortho.ray(1.5, 0.5)
    np.testing.assert_allclose(origin, [0.5, 0.5, 4])
    np.testing.assert_allclose(direction, [0, 0, -1])


# --- axonometric and oblique projections ----------------------------------------------------


def axis_images(cam, center=(0.0, 0.0, 0.0)):
    """Raster images (x, y up) of the unit vectors along X, Y, Z placed at ``center``."""
    p = cam.project(np.asarray(center) + np.vstack([np.zeros(3), np.eye(3)]))
    d = p[1:, :2] - p[0, :2]
    return d * [1, -1]


def angle_between(a, b):
    return math.degrees(math.acos(np.dot(a, b) / np.linalg.norm(a) / np.linalg.norm(b)))


def test_isometric_axes_equal_length_and_120_degrees_apart():
    images = axis_images(Camera.isometric((1, 2, 3), 2.0, width=300, height=200), (1, 2, 3))
    lengths = np.linalg.norm(images, axis=1)
    np.testing.assert_allclose(lengths, lengths[0], rtol=1e-12)
    for i, j in [(0, 1), (1, 2), (0, 2)]:
        assert angle_between(images[i], images[j]) == pytest.approx(120.0, abs=1e-9)
    # The vertical axis stays vertical.
    assert images[1][0] == pytest.approx(0.0, abs=1e-9)


@pytest.mark.parametrize("elevation", [10.0, 20.0, 50.0, -30.0])
def test_dimetric_two_axes_foreshortened_equally(elevation):
    lengths = np.linalg.norm(axis_images(Camera.dimetric(elevation=elevation)), axis=1)
    assert lengths[0] == pytest.approx(lengths[2], rel=1e-12)
    assert abs(lengths[1] - lengths[0]) > 1e-3 * lengths[0]


@pytest.mark.parametrize("azimuth, elevation", [(30.0, 20.0), (-70.0, 40.0), (120.0, -15.0)])
def test_trimetric_three_axes_foreshortened_differently(azimuth, elevation):
    lengths = np.linalg.norm(axis_images(Camera.trimetric(azimuth=azimuth, elevation=elevation)),
                             axis=1)
    for i, j in [(0, 1), (1, 2), (0, 2)]:
        assert abs(lengths[i] - lengths[j]) > 1e-3 * lengths.max()


def test_orthographic_axes_foreshortening_matches_the_view_direction():
    cam = Camera.trimetric(azimuth=30.0, elevation=20.0)
    d = _normalize(np.subtract(cam.target, cam.eye))
    lengths = np.linalg.norm(axis_images(cam), axis=1)
    ppu = cam.height / cam.view_height  # pixels per world unit
    np.testing.assert_allclose(lengths, ppu * np.sqrt(1 - d**2), rtol=1e-12)


@pytest.mark.parametrize("make, ratio", [(Camera.cavalier, 1.0), (Camera.cabinet, 0.5)])
def test_cavalier_and_cabinet_receding_axis_length(make, ratio):
    x_img, y_img, z_img = axis_images(make(angle=30.0))
    ppu = np.linalg.norm(x_img)
    # x and y are drawn at full length, along the image axes.
    np.testing.assert_allclose(x_img, [ppu, 0], atol=1e-9)
    np.testing.assert_allclose(y_img, [0, ppu], atol=1e-9)
    # -Z (away from the viewer) is drawn at the angle with length ratio.
    np.testing.assert_allclose(-z_img, ratio * ppu * np.array([math.cos(math.radians(30)),
                                                                math.sin(math.radians(30))]),
                               atol=1e-9)


@SETTINGS
@given(st.floats(-180, 180), st.floats(0, 3), vectors, st.floats(0.1, 10))
def test_general_oblique_follows_angle_and_ratio(angle, ratio, center, radius):
    cam = Camera.oblique(angle, ratio, center, radius)
    x_img, _, z_img = axis_images(cam, center)
    ppu = np.linalg.norm(x_img)
    rad = math.radians(angle)
    expected = ratio * ppu * np.array([math.cos(rad), math.sin(rad)])
    np.testing.assert_allclose(-z_img, expected, atol=1e-9 * cam.width)
    # The centre stays in the middle of the image.
    np.testing.assert_allclose(cam.project([center])[0, :2], [cam.width / 2, cam.height / 2],
                               atol=1e-9 * cam.width)


# --- vanishing points -----------------------------------------------------------------------


def finite_vanishing_points(cam):
    """Vanishing points of the world axes: the images of the points at infinity (d, 0)."""
    h = np.c_[np.eye(3), np.zeros(3)] @ cam.matrix().T
    finite = np.abs(h[:, 3]) > 1e-12 * np.abs(h).max()
    return h[finite, :2] / h[finite, 3:]


def test_one_two_three_point_perspective_vanishing_points():
    one = Camera.one_point((1, 1, 1), 2.0, width=320, height=240)
    assert len(finite_vanishing_points(one)) == 1
    np.testing.assert_allclose(finite_vanishing_points(one)[0], [160, 120], atol=1e-9)
    assert len(finite_vanishing_points(Camera.two_point((1, 1, 1), 2.0, azimuth=40.0))) == 2
    three = Camera.three_point((1, 1, 1), 2.0, azimuth=40.0, elevation=-20.0)
    assert len(finite_vanishing_points(three)) == 3


def test_two_point_keeps_verticals_vertical():
    cam = Camera.two_point(azimuth=25.0)
    p = cam.project([[0.3, -1, 0.2], [0.3, 1, 0.2]])
    assert p[0, 0] == pytest.approx(p[1, 0], abs=1e-9)


def test_parallel_lines_meet_at_the_vanishing_point():
    cam = Camera.three_point(azimuth=30.0, elevation=20.0)
    h = cam.matrix() @ [0, 0, -1, 0]
    vp = h[:2] / h[3]
    # A far point on a line along -Z from (0.5, 0.2, 0) projects close to the vanishing point.
    far = cam.project([[0.5, 0.2, -1e7]])[0, :2]
    np.testing.assert_allclose(far, vp, atol=1e-3)


# --- ratios along lines ---------------------------------------------------------------------


@SETTINGS
@given(perspective_cameras(), seeds)
def test_perspective_does_not_keep_midpoints(cam, seed):
    rng = np.random.default_rng(seed)
    a, b = rng.uniform(-0.9, 0.9, (2, 2))
    ends = frustum_points(cam, a, b, np.array([cam.near, cam.far]))
    images = cam.project(np.vstack([ends, ends.mean(axis=0)]))
    assume(np.linalg.norm(images[0, :2] - images[1, :2]) > 1e-3 * max(cam.width, cam.height))
    assert np.linalg.norm(images[2, :2] - images[:2, :2].mean(axis=0)) > 1e-6


@SETTINGS
@given(parallel_cameras(), vectors, vectors)
def test_parallel_projections_keep_midpoints(cam, p, q):
    images = cam.project(np.array([p, q, np.add(p, q) / 2]))
    np.testing.assert_allclose(images[2], images[:2].mean(axis=0),
                               atol=1e-9 * max(cam.width, cam.height))


# --- frame() --------------------------------------------------------------------------------


def sphere_points(center, radius, n=4000):
    """Fibonacci lattice on the sphere."""
    i = np.arange(n) + 0.5
    z = 1 - 2 * i / n
    phi = math.pi * (1 + 5**0.5) * i
    r = np.sqrt(1 - z**2)
    return np.asarray(center) + radius * np.c_[r * np.cos(phi), r * np.sin(phi), z]


def assert_sphere_fills_view(cam, center, radius):
    p = cam.project(sphere_points(center, radius))
    tol = 1e-9 * max(cam.width, cam.height)
    assert np.all((p[:, 0] >= -tol) & (p[:, 0] <= cam.width + tol))
    assert np.all((p[:, 1] >= -tol) & (p[:, 1] <= cam.height + tol))
    assert np.all((p[:, 2] > 0) & (p[:, 2] < 1))
    fill = max(np.ptp(p[:, 0]) / cam.width, np.ptp(p[:, 1]) / cam.height)
    assert fill > 0.98


@SETTINGS
@given(vectors, st.floats(0.01, 100), st.floats(-180, 180), st.floats(-85, 85),
       st.floats(10, 120), sizes, st.sampled_from(["perspective", "parallel"]))
def test_frame_fits_the_sphere_into_the_image(center, radius, azimuth, elevation, fov, size,
                                              projection):
    cam = Camera.frame(center, radius, azimuth, elevation, fov, *size, projection=projection)
    assert cam.kind == projection
    np.testing.assert_array_equal(cam.target, center)
    assert_sphere_fills_view(cam, center, radius)


def test_frame_azimuth_and_elevation_place_the_eye():
    cam = Camera.frame((0, 0, 0), 1.0, azimuth=90.0, elevation=0.0)
    eye = np.asarray(cam.eye)
    np.testing.assert_allclose(eye / np.linalg.norm(eye), [1, 0, 0], atol=1e-12)
    cam = Camera.frame((0, 0, 0), 1.0, azimuth=0.0, elevation=30.0)
    eye = np.asarray(cam.eye)
    np.testing.assert_allclose(eye / np.linalg.norm(eye), [0, 0.5, math.sqrt(3) / 2], atol=1e-12)


@pytest.mark.parametrize("make", [Camera.isometric, Camera.dimetric, Camera.trimetric,
                                  Camera.cavalier, Camera.cabinet, Camera.one_point,
                                  Camera.two_point, Camera.three_point])
@pytest.mark.parametrize("size", [(320, 240), (100, 300)])
def test_presets_frame_their_target(make, size):
    cam = make((1, -2, 3), 1.5, width=size[0], height=size[1])
    assert_sphere_fills_view(cam, (1, -2, 3), 1.5)


# --- the camera object ----------------------------------------------------------------------


def test_properties_and_with_size():
    cam = Camera.look_at((0, 0, 5), (0, 0, 0), fov_y=60, width=64, height=48, near=1, far=10)
    assert (cam.kind, cam.fov_y, cam.width, cam.height, cam.near, cam.far) == (
        "perspective", 60.0, 64, 48, 1.0, 10.0)
    assert cam.eye == (0.0, 0.0, 5.0) and cam.target == (0.0, 0.0, 0.0)
    assert cam.up == (0.0, 1.0, 0.0)
    bigger = cam.with_size(128, 32)
    assert (bigger.width, bigger.height) == (128, 32) and (cam.width, cam.height) == (64, 48)
    assert dataclasses.replace(bigger, width=64, height=48) == cam
    with pytest.raises(dataclasses.FrozenInstanceError):
        cam.width = 10
    ortho = Camera.orthographic((0, 0, 5), (0, 0, 0), view_height=3.0)
    assert (ortho.kind, ortho.fov_y, ortho.view_height) == ("parallel", None, 3.0)


@pytest.mark.parametrize("cam", [Camera.look_at((1, 2, 3), (0, 0.5, 0), shift=(0.2, -0.1)),
                                 Camera.cabinet((1, 0, 0), 2.0)])
def test_world_to_raster_is_the_cached_read_only_product_of_the_chain(cam):
    k = cam.world_to_raster()
    assert k.shape == (4, 4) and k.dtype == np.float64 and not k.flags.writeable
    assert cam.world_to_raster() is k
    np.testing.assert_array_equal(k, compose(*(m for _, m in cam.chain())))
    np.testing.assert_array_equal(k, cam.matrix())
    with pytest.raises(ValueError):
        k[0, 0] = 1.0


@pytest.mark.parametrize("cam", [Camera.look_at((1, 2, 3), (0, 0.5, 0)),
                                 Camera.orthographic((0, 4, 0), (0, 0, 0), up=(0, 0, -1))])
def test_backward_is_the_cached_read_only_unit_vector_from_target_to_eye(cam):
    w = cam.backward()
    assert w.shape == (3,) and w.dtype == np.float64 and not w.flags.writeable
    assert cam.backward() is w
    direction = np.subtract(cam.eye, cam.target)
    np.testing.assert_allclose(w, direction / np.linalg.norm(direction), atol=1e-15)
    np.testing.assert_array_equal(w, cam.basis()[2])
    with pytest.raises(ValueError):
        w[0] = 1.0


@pytest.mark.parametrize(
    "kwargs",
    [
        dict(eye=(0, 0, 0), target=(0, 0, 0)),
        dict(up=(0, 0, 2)),
        dict(up=(0, 0, 0)),
        dict(eye=(0, 0, np.inf)),
        dict(target=(0, 0)),
        dict(fov_y=0),
        dict(fov_y=180),
        dict(fov_y=float("nan")),
        dict(width=0),
        dict(height=-3),
        dict(width=64.0),
        dict(width=True),
        dict(near=0),
        dict(near=2, far=2),
        dict(far=float("inf")),
        dict(shift=(0.1,)),
        dict(shift=0.5),
        dict(shift=(0.0, float("nan"))),
    ],
)
def test_look_at_rejects_invalid_input(kwargs):
    args = dict(eye=(0, 0, 5), target=(0, 0, 0))
    args.update(kwargs)
    with pytest.raises(ValueError):
        Camera.look_at(**args)


@pytest.mark.parametrize(
    "call",
    [
        lambda: Camera.orthographic((0, 0, 5), (0, 0, 0), view_height=0),
        lambda: Camera.frame((0, 0, 0), 0.0),
        lambda: Camera.frame((0, 0, 0), 1.0, elevation=90),
        lambda: Camera.frame((0, 0, 0), 1.0, projection="fisheye"),
        lambda: Camera.frame((0, 0, 0), 1.0, fov_y=200),
        lambda: Camera.oblique(45, -1.0),
        lambda: Camera.two_point(azimuth=90.0),
        lambda: Camera.three_point(elevation=0.0),
        lambda: Camera.three_point(azimuth=0.0),
        lambda: Camera(kind="fisheye", eye=(0, 0, 1), target=(0, 0, 0)),
        lambda: Camera(kind="perspective", eye=(0, 0, 1), target=(0, 0, 0)),
        lambda: Camera(kind="parallel", eye=(0, 0, 1), target=(0, 0, 0), view_height=1, fov_y=40),
        lambda: Camera.look_at((0, 0, 5), (0, 0, 0)).with_size(0, 10),
        lambda: Camera.look_at((0, 0, 5), (0, 0, 0)).project(np.zeros((3, 2))),
        lambda: Camera.look_at((0, 0, 5), (0, 0, 0)).project([[0, 0, np.nan]]),
        lambda: Camera.look_at((0, 0, 5), (0, 0, 0)).ray(np.inf, 0),
    ],
)
def test_other_invalid_input_raises(call):
    with pytest.raises(ValueError):
        call()
