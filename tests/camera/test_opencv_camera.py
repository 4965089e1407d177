"""Cameras of OpenCV, OpenGL and trimesh/pyrender in and out (issue 17), against cv2.projectPoints
and OpenGL's textbook matrices."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rasterkit import Camera

cv2 = pytest.importorskip("cv2")


def _random_camera(rng):
    """K with fx != fy and the principal point off centre; R from a random rotation vector;
    t putting the origin 3-6 units in front."""
    width, height = int(rng.integers(200, 1200)), int(rng.integers(150, 900))
    fx = rng.uniform(300, 1500)
    k = np.array([[fx, 0, width / 2 + rng.uniform(-80, 80)],
                  [0, fx * rng.uniform(0.8, 1.25), height / 2 + rng.uniform(-60, 60)], [0, 0, 1]])
    rvec = rng.normal(size=3)
    r = cv2.Rodrigues(rvec)[0]
    t = np.array([rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5), rng.uniform(3, 6)])
    return k, rvec, r, t, width, height


def test_from_opencv_projects_points_where_cv2_does_plus_half_a_pixel():
    rng = np.random.default_rng(17)
    for _ in range(10):
        k, rvec, r, t, width, height = _random_camera(rng)
        points = rng.uniform(-1, 1, size=(200, 3))
        expected = cv2.projectPoints(points, rvec, t, k, None)[0].reshape(-1, 2)
        camera = Camera.from_opencv(k, r, t, width, height)
        got = camera.project(points)[:, :2]
        assert np.max(np.abs(got - (expected + 0.5))) < 1e-6


def test_opencv_round_trip():
    rng = np.random.default_rng(3)
    for _ in range(10):
        k, _, r, t, width, height = _random_camera(rng)
        k2, r2, t2 = Camera.from_opencv(k, r, t, width, height).to_opencv()
        assert np.max(np.abs(k2 - k)) < 1e-9
        assert np.max(np.abs(r2 - r)) < 1e-9
        assert np.max(np.abs(t2 - t)) < 1e-9


def test_from_opencv_depth_is_along_the_optical_axis():
    k = np.array([[500.0, 0, 300], [0, 520, 200], [0, 0, 1]])
    camera = Camera.from_opencv(k, np.eye(3), np.zeros(3), 640, 480, near=1.0, far=10.0)
    # OpenCV looks down +z: the point (0, 0, 5) is straight ahead, 5 units away
    x, y, depth = camera.project([[0.0, 0.0, 5.0]])[0]
    assert (x, y) == pytest.approx((300.5, 200.5))
    assert depth == pytest.approx(10.0 * (5.0 - 1.0) / (5.0 * 9.0))


def test_square_pixels_and_centred_principal_point_give_a_plain_look_at_camera():
    camera = Camera.look_at((1, 2, 3), (0, 0, 0), fov_y=50, width=64, height=48)
    again = Camera.from_opencv(*camera.to_opencv(), 64, 48)
    assert again.pixel_aspect == pytest.approx(1.0, abs=1e-15)
    assert np.abs(np.array(again.shift)).max() < 1e-14
    assert np.allclose(again.matrix(), camera.matrix(), rtol=0, atol=1e-12)


@pytest.mark.parametrize("k, message", [
    ([[500, 2, 320], [0, 500, 240], [0, 0, 1]], "skew"),
    ([[500, 0, 320], [0, 500, 240], [0, 0, 2]], "form"),
    ([[-500, 0, 320], [0, 500, 240], [0, 0, 1]], "fx"),
    ([[500, 0, 320], [0, 500, 240]], "3x3"),
])
def test_bad_intrinsics_are_refused_in_one_line(k, message):
    with pytest.raises(ValueError, match=message) as info:
        Camera.from_opencv(k, np.eye(3), np.zeros(3), 640, 480)
    assert "\n" not in str(info.value)


def test_bad_extrinsics_are_refused():
    k = np.diag([500.0, 500.0, 1.0])
    with pytest.raises(ValueError, match="rotation"):
        Camera.from_opencv(k, np.diag([1.0, 1.0, -1.0]), np.zeros(3), 64, 48)
    with pytest.raises(ValueError, match="rotation"):
        Camera.from_opencv(k, 2 * np.eye(3), np.zeros(3), 64, 48)
    with pytest.raises(ValueError, match="t must be"):
        Camera.from_opencv(k, np.eye(3), np.zeros(4), 64, 48)


def test_distortion_coefficients_are_checked_and_kept():
    k = np.diag([500.0, 500.0, 1.0])
    camera = Camera.from_opencv(k, np.eye(3), np.zeros(3), 64, 48, dist=[0.1, 0, 0, 0, 0])
    assert camera.distortion == (0.1, 0.0, 0.0, 0.0, 0.0)
    assert Camera.from_opencv(k, np.eye(3), np.zeros(3), 64, 48, dist=np.zeros(5)).distortion == ()
    with pytest.raises(ValueError, match="dist must be 4, 5 or 8"):
        Camera.from_opencv(k, np.eye(3), np.zeros(3), 64, 48, dist=[0.1, 0.2, 0.3])


# --- OpenGL ------------------------------------------------------------------------------------


def _gl_frustum(left, right, bottom, top, near, far):
    return np.array([
        [2 * near / (right - left), 0, (right + left) / (right - left), 0],
        [0, 2 * near / (top - bottom), (top + bottom) / (top - bottom), 0],
        [0, 0, -(far + near) / (far - near), -2 * far * near / (far - near)],
        [0, 0, -1, 0]])


def _gl_window(p, v, points, width, height):
    """Raster x, y (y down) and depth in [0, 1] of OpenGL's pipeline (glViewport(0, 0, W, H))."""
    h = np.c_[points, np.ones(len(points))] @ (p @ v).T
    ndc = h[:, :3] / h[:, 3:]
    x = (ndc[:, 0] + 1) / 2 * width
    y_up = (ndc[:, 1] + 1) / 2 * height
    return np.c_[x, height - y_up, (ndc[:, 2] + 1) / 2]


def test_from_opengl_matches_opengl_pipeline_and_round_trips():
    rng = np.random.default_rng(5)
    for _ in range(10):
        near, far = rng.uniform(0.1, 1), rng.uniform(20, 200)
        left, right = -rng.uniform(0.05, 0.2), rng.uniform(0.05, 0.2)
        bottom, top = -rng.uniform(0.05, 0.2), rng.uniform(0.05, 0.2)
        p = _gl_frustum(left * near, right * near, bottom * near, top * near, near, far)
        r = cv2.Rodrigues(rng.normal(size=3))[0]
        v = np.eye(4)
        v[:3, :3], v[:3, 3] = r, rng.normal(size=3)
        width, height = int(rng.integers(100, 900)), int(rng.integers(100, 900))
        camera = Camera.from_opengl(p, v, width, height)
        points = (np.linalg.inv(v) @ np.c_[rng.uniform(-1, 1, (50, 2)), -rng.uniform(2, 10, 50),
                                          np.ones(50)].T).T[:, :3]
        assert np.allclose(camera.project(points), _gl_window(p, v, points, width, height), rtol=1e-9, atol=1e-9)
        p2, v2 = camera.opengl_matrices()
        assert np.max(np.abs(p2 - p) / np.maximum(1, np.abs(p))) < 1e-12
        assert np.max(np.abs(v2 - v)) < 1e-12


def test_orthographic_opengl_round_trip():
    camera = Camera.orthographic((0, 0, 5), (0, 0, 0), view_height=3.0, width=64, height=32, near=1, far=9)
    p, v = camera.opengl_matrices()
    assert p[3].tolist() == [0, 0, 0, 1]
    again = Camera.from_opengl(p, v, 64, 32)
    assert again.kind == "parallel" and np.allclose(again.matrix(), camera.matrix(), atol=1e-12)


def test_opengl_refuses_what_it_cannot_represent():
    with pytest.raises(ValueError, match="glFrustum"):
        Camera.from_opengl(np.eye(4) * 2 - np.diag([0, 0, 0, 1]) + np.eye(4, k=1), np.eye(4), 64, 48)
    with pytest.raises(ValueError, match="oblique"):
        Camera.cavalier().opengl_matrices()
    with pytest.raises(ValueError, match="perspective"):
        Camera.cavalier().to_opencv()


# --- poses -------------------------------------------------------------------------------------


def test_pose_is_the_inverse_view_and_round_trips():
    camera = Camera.look_at((2, 1, 4), (0, 0.5, 0), fov_y=40)
    pose = camera.pose()
    assert np.allclose(pose @ camera.view_matrix(), np.eye(4), atol=1e-14)
    again = Camera.from_pose(pose, fov_y=40)
    assert np.max(np.abs(again.pose() - pose)) < 1e-12
    assert np.allclose(again.matrix(), camera.matrix(), atol=1e-12)


def test_pose_of_pyrender_convention():
    """pyrender: a camera at (0, 0, 3) with the identity rotation looks down -z at the origin."""
    pose = np.eye(4)
    pose[:3, 3] = (0, 0, 3)
    camera = Camera.from_pose(pose, fov_y=math.degrees(math.pi / 3), width=100, height=100)
    x, y, _ = camera.project([[0.0, 0.0, 0.0]])[0]
    assert (x, y) == pytest.approx((50, 50))
    x, y, _ = camera.project([[0.0, 0.5, 0.0]])[0]  # up in the world is up in the image
    assert y < 50


def test_pixel_aspect_changes_only_the_window_width():
    square = Camera.look_at((0, 0, 5), (0, 0, 0), fov_y=45, width=80, height=60)
    wide = Camera.look_at((0, 0, 5), (0, 0, 0), fov_y=45, width=80, height=60).__class__(
        kind="perspective", eye=(0, 0, 5), target=(0, 0, 0), fov_y=45, width=80, height=60, pixel_aspect=2.0)
    a, b = square.project([[1.0, 1.0, 0.0]])[0], wide.project([[1.0, 1.0, 0.0]])[0]
    assert b[1] == pytest.approx(a[1]) and (b[0] - 40) == pytest.approx((a[0] - 40) / 2)


def test_pose_with_intrinsics_is_the_opencv_camera_seen_in_opengl_axes():
    """pyrender's IntrinsicsCamera at a pose: the same camera as OpenCV's K with R, t of the
    inverse pose, its y and z axes flipped."""
    rng = np.random.default_rng(11)
    k, rvec, r, t, width, height = _random_camera(rng)
    camera = Camera.from_opencv(k, r, t, width, height)
    pose = camera.pose()
    again = Camera.from_pose(pose, width=width, height=height, K=k)
    points = rng.uniform(-1, 1, size=(50, 3))
    expected = cv2.projectPoints(points, rvec, t, k, None)[0].reshape(-1, 2) + 0.5
    assert np.max(np.abs(again.project(points)[:, :2] - expected)) < 1e-6
    with pytest.raises(ValueError, match="rigid"):
        Camera.from_pose(np.ones((4, 4)), K=k)
