"""Lens distortion (issue 17): rendered markers land where cv2.projectPoints with distCoeffs
puts them; the inverse map against OpenCV's undistortPoints."""

from __future__ import annotations

import numpy as np
import pytest

import rasterkit
from rasterkit import Camera, Mesh
from rasterkit.raster.distortion import distort, ideal_camera, undistort

cv2 = pytest.importorskip("cv2")

K = np.array([[610.0, 0, 331.0], [0, 600.0, 236.0], [0, 0, 1]])


def _markers(corners, half):
    """A small square (two triangles, facing +z) centred on each board corner."""
    offsets = np.array([[-half, -half, 0], [half, -half, 0], [half, half, 0], [-half, half, 0]])
    vertices = (corners[:, None, :] + offsets[None]).reshape(-1, 3)
    base = 4 * np.arange(len(corners))[:, None]
    faces = np.concatenate([base + [0, 1, 2], base + [0, 2, 3]], axis=1).reshape(-1, 3)
    return Mesh(vertices, faces)


def _board(dist):
    gx, gy = np.meshgrid(np.arange(-6, 7) * 0.07, np.arange(-4, 5) * 0.07)
    corners = np.c_[gx.ravel(), gy.ravel(), np.zeros(gx.size)]
    rvec, tvec = np.array([0.25, -0.3, 0.05]), np.array([0.02, -0.01, 0.75])
    camera = Camera.from_opencv(K, cv2.Rodrigues(rvec)[0], tvec, 640, 480, dist=dist)
    expected = cv2.projectPoints(corners, rvec, tvec, K, np.array(dist))[0].reshape(-1, 2) + 0.5
    inside = np.all((expected > 15) & (expected < [625, 465]), axis=1)
    return corners, camera, expected, inside


def _weighted_centroid(weight, x, y, half=12):
    x0, y0 = int(x) - half, int(y) - half
    window = weight[y0:y0 + 2 * half + 1, x0:x0 + 2 * half + 1]
    j, i = np.mgrid[y0:y0 + 2 * half + 1, x0:x0 + 2 * half + 1] + 0.5
    return np.array([(window * i).sum(), (window * j).sum()]) / window.sum()


DISTORTIONS = [
    (-0.28, 0.09, 0.0012, -0.0008, -0.01),  # barrel
    (0.12, -0.03, -0.001, 0.002),  # pincushion
    (0.3, 0.05, 0.001, 0.0, 0.01, 0.2, 0.02, 0.005),  # the rational model
]


@pytest.mark.parametrize("dist", DISTORTIONS)
def test_checkerboard_markers_land_where_cv2_projects_them(dist):
    """Marker centres (anti-aliased, darkness-weighted centroids) within 0.5 px of
    cv2.projectPoints(..., distCoeffs) + 0.5 (measured: 0.1 px at most)."""
    corners, camera, expected, inside = _board(dist)
    fb = rasterkit.render(_markers(corners, 0.006), camera, mode="solid", cull="none", color="black",
                          background="white", samples=16)
    darkness = 255.0 - fb.color[..., 0]
    assert inside.sum() > 80
    error = [np.linalg.norm(_weighted_centroid(darkness, *p) - p) for p in expected[inside]]
    assert max(error) < 0.25
    # without the distortion the markers would be far from there
    plain = camera.project(corners)[:, :2]
    assert np.max(np.linalg.norm(plain[inside] - expected[inside], axis=1)) > 5


@pytest.mark.parametrize("dist", DISTORTIONS)
def test_checkerboard_marker_ids_land_where_cv2_projects_them(dist):
    """The ids (nearest ideal pixel, no anti-aliasing): each marker's pixels centred within
    a pixel of cv2's point (a 10-pixel square's own rasterisation moves its centroid by up to
    half a pixel)."""
    corners, camera, expected, inside = _board(dist)
    fb = rasterkit.render(_markers(corners, 0.006), camera, mode="solid", cull="none", ids=True)
    marker = np.where(fb.ids >= 0, fb.ids // 2, -1)
    j, i = np.nonzero(marker >= 0)
    counts = np.bincount(marker[j, i], minlength=len(corners))
    assert np.all(counts[inside] >= 25)
    centroid = np.c_[np.bincount(marker[j, i], i + 0.5, len(corners)),
                     np.bincount(marker[j, i], j + 0.5, len(corners))] / np.maximum(counts, 1)[:, None]
    assert np.max(np.linalg.norm(centroid[inside] - expected[inside], axis=1)) < 1.0


def test_undistort_inverts_opencv():
    dist = (-0.3, 0.1, 0.001, -0.002, -0.02)
    rng = np.random.default_rng(1)
    pixels = rng.uniform([0, 0], [640, 480], size=(300, 2))
    ideal = cv2.undistortPoints(pixels.reshape(-1, 1, 2), K, np.array(dist),
                                criteria=(cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, 100, 1e-14)).reshape(-1, 2)
    xd, yd = (pixels[:, 0] - K[0, 2]) / K[0, 0], (pixels[:, 1] - K[1, 2]) / K[1, 1]
    x, y, ok = undistort(xd, yd, dist)
    assert ok.all() and np.allclose(np.c_[x, y], ideal, atol=1e-7)
    back_x, back_y, _ = distort(x, y, dist)
    assert np.allclose(back_x, xd, atol=1e-12) and np.allclose(back_y, yd, atol=1e-12)


def test_distorted_maps_agree_and_depth_is_metric():
    camera = Camera.from_opencv(K, np.eye(3), [0, 0, 2.0], 160, 120, dist=(-0.2, 0.05, 0, 0))
    plane = Mesh(np.array([[-3, -3, 0], [3, -3, 0], [3, 3, 0], [-3, 3, 0.0]]), np.array([[0, 2, 1], [0, 3, 2]]))
    fb = rasterkit.render(plane, camera, mode="solid", cull="none", ids=True, normals=True)
    drawn = fb.ids >= 0
    assert np.array_equal(drawn, ~np.isnan(fb.normals[..., 0]))
    assert np.allclose(fb.camera_depth()[drawn], 2.0, rtol=1e-5)
    assert ideal_camera(camera).width >= 160


def test_strong_barrel_distortion_leaves_the_corners_empty():
    camera = Camera.from_opencv(K, np.eye(3), [0, 0, 2.0], 640, 480, dist=(-0.6, 0.0, 0, 0))
    plane = Mesh(np.array([[-30, -30, 0], [30, -30, 0], [30, 30, 0], [-30, 30, 0.0]]),
                 np.array([[0, 2, 1], [0, 3, 2]]))
    fb = rasterkit.render(plane, camera, mode="solid", cull="none", ids=True)
    assert fb.ids[240, 320] >= 0 and fb.ids[0, 0] == -1
