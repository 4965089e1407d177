"""The viewer's camera moves, against the geometry they promise (projections of world points)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import rasterkit as rk
from rasterkit.viewer.orbit import MAX_ELEVATION, ZOOM_PER_STEP, Orbit

EYE, TARGET = (1.5, 2.0, 3.0), (0.2, -0.1, 0.4)


def _camera(orbit, width=320, height=240, fov=45.0):
    return orbit.view(rk.View(size=(width, height), fov=fov)).camera_for(rk.shapes.demo())


def test_an_orbit_gives_back_the_eye_it_was_made_from():
    orbit = Orbit.around(EYE, TARGET, 1.0)
    np.testing.assert_allclose(orbit.eye, EYE, rtol=0, atol=1e-12)
    assert orbit.target == TARGET and orbit.reframe() == orbit
    offset = np.subtract(EYE, TARGET)
    assert orbit.distance == pytest.approx(np.linalg.norm(offset))
    assert orbit.azimuth == pytest.approx(math.degrees(math.atan2(offset[0], offset[2])))


def test_dragging_right_raises_the_azimuth_and_up_the_elevation_at_a_fixed_distance():
    orbit = Orbit.around(EYE, TARGET, 1.0)
    right, up = orbit.turn(24, 0, 240), orbit.turn(0, -24, 240)
    assert right.azimuth == pytest.approx(orbit.azimuth + 18.0) and right.elevation == orbit.elevation
    assert up.elevation == pytest.approx(orbit.elevation + 18.0) and up.azimuth == orbit.azimuth
    for moved in (right, up):
        assert np.linalg.norm(np.subtract(moved.eye, moved.target)) == pytest.approx(orbit.distance)
    # the eye moves to the camera's right (as the image sees it) when the drag goes right
    u, _, _ = _camera(orbit).basis()
    assert np.dot(np.subtract(right.eye, orbit.eye), u) > 0


def test_the_elevation_stops_short_of_the_poles_and_the_azimuth_wraps():
    orbit = Orbit.around(EYE, TARGET, 1.0)
    assert orbit.turn(0, -10_000, 240).elevation == MAX_ELEVATION
    assert orbit.turn(0, 10_000, 240).elevation == -MAX_ELEVATION
    turned = orbit.turn(240 * 4, 0, 240)  # 720 degrees: back where it was
    assert turned.azimuth == pytest.approx(orbit.azimuth, abs=1e-9) and -180 <= turned.azimuth <= 180


@pytest.mark.parametrize("dx, dy", [(10, 0), (0, 7), (-13, 5)])
def test_a_pan_moves_the_point_at_the_targets_depth_with_the_mouse(dx, dy):
    orbit = Orbit.around(EYE, TARGET, 1.0)
    camera = _camera(orbit)
    moved = orbit.pan(dx, dy, 240, 45.0)
    np.testing.assert_allclose(np.subtract(moved.eye, moved.target), np.subtract(orbit.eye, orbit.target), atol=1e-12)
    before = camera.project(np.array([TARGET]))[0]
    after = _camera(moved).project(np.array([TARGET]))[0]
    np.testing.assert_allclose(after[:2] - before[:2], (dx, dy), atol=1e-6)


def test_zoom_scales_the_distance_by_steps_and_stays_in_range():
    orbit = Orbit.around(EYE, TARGET, 2.0)
    assert orbit.zoom(2).distance == pytest.approx(orbit.distance * ZOOM_PER_STEP ** 2)
    assert orbit.zoom(-1).distance == pytest.approx(orbit.distance / ZOOM_PER_STEP)
    assert orbit.zoom(-1e4).distance >= 2.0 * 1e-3 and orbit.zoom(1e4).distance <= 2.0 * 1e4
    assert orbit.zoom(3).turn(5, 5, 100).pan(3, 3, 100, 45).reframe() == orbit


def test_an_eye_on_the_target_is_refused():
    with pytest.raises(ValueError, match="differ"):
        Orbit.around(TARGET, TARGET, 1.0)
