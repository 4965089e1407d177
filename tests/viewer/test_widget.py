"""The notebook widget's Python side, without a browser: the page's messages in, frames and
the camera out."""

from __future__ import annotations

import io

import numpy as np
import pytest
from PIL import Image

import rasterkit as rk

pytest.importorskip("anywidget")


@pytest.fixture
def viewer():
    mesh = rk.shapes.icosphere(2)
    camera = rk.Camera.look_at((0.5, 1.0, 3.0), (0, 0, 0), width=10, height=10, fov_y=40)
    viewer = rk.Viewer(mesh, camera, options=rk.RenderOptions(mode="solid", shading="smooth"), size=(80, 60))
    viewer.sent = []
    viewer.send = lambda content, buffers=None: viewer.sent.append((content, buffers))  # no front end here
    yield viewer
    viewer.close()


def test_the_widget_starts_at_its_camera_and_sends_frames_with_their_camera(viewer):
    first = viewer.wait_frame(0)
    assert first.final and viewer.size == [80, 60]
    np.testing.assert_allclose(viewer.camera.eye, (0.5, 1.0, 3.0), atol=1e-12)
    assert viewer.camera.fov_y == 40 and (viewer.camera.width, viewer.camera.height) == (80, 60)
    viewer._message(viewer, {"kind": "hello"}, [])  # a new view of the widget asks for the frame
    content, buffers = viewer.sent[-1]
    assert content["kind"] == "frame" and content["number"] == first.number and buffers == [first.data]
    viewer._message(viewer, {"kind": "drag", "dx": -20, "dy": 0, "seq": 5}, [])
    viewer._message(viewer, {"kind": "release", "seq": 6}, [])
    frame = first
    while not (frame.final and frame.seq == 6):
        frame = viewer.wait_frame(frame.number, 60)
        assert frame is not None
    assert frame.camera["azimuth"] == pytest.approx(first.camera["azimuth"] - 20 * 180 / 60)
    assert viewer.options == rk.RenderOptions(mode="solid", shading="smooth")
    expected = rk.render(rk.shapes.icosphere(2), viewer.camera, options=viewer.options).color
    np.testing.assert_array_equal(np.asarray(Image.open(io.BytesIO(frame.data))), expected)
    assert viewer.view.eye == tuple(viewer.camera.eye) and "--eye" in viewer.flags


def test_a_bad_message_is_answered_with_one_line_and_the_bar_follows_the_settings(viewer):
    viewer.wait_frame(0)
    viewer._message(viewer, {"kind": "set", "shading": "toon"}, [])
    assert viewer.sent[-1][0] == {"kind": "error", "error": "shading must be one of flat, smooth, phong"}
    viewer._message(viewer, {"kind": "set", "show": "normals"}, [])
    assert viewer.current["show"] == "normals"


def test_the_viewer_takes_only_models_views_and_options():
    with pytest.raises(TypeError, match="camera must be"):
        rk.Viewer(rk.shapes.cube(), camera="front")
    with pytest.raises(TypeError, match="options must be"):
        rk.Viewer(rk.shapes.cube(), options={"mode": "solid"})
