"""The viewer's state: events in, frames out; a final frame is the render of its camera, and
the flags it reports draw it again on the command line."""

from __future__ import annotations

import io

import numpy as np
import pytest
from PIL import Image

import rasterkit as rk
from rasterkit.batch.render_one import load_drawn
from rasterkit.cli import _parser
from rasterkit.cli.args import attach_number_lists, task_from_args
from rasterkit.viewer.pictures import picture
from rasterkit.viewer.session import ViewerSession

SIZE = (96, 72)


def _session(**options) -> ViewerSession:
    return ViewerSession(load_drawn(None, rk.RenderOptions(mode="solid", **options), False), rk.View(size=SIZE))


def _pixels(frame) -> np.ndarray:
    return np.asarray(Image.open(io.BytesIO(frame.data)))


def test_a_final_frame_is_the_render_of_the_viewers_camera_and_its_flags_draw_it_again():
    session = _session(shading="smooth")
    session.handle({"kind": "drag", "dx": 17, "dy": -9})
    session.handle({"kind": "drag", "dx": 5, "dy": 3, "pan": True})
    session.handle({"kind": "wheel", "steps": -1.5})
    frame = session.render(final=True)
    assert frame.mime == "image/png" and (frame.width, frame.height) == SIZE and frame.final
    mesh = rk.shapes.demo()
    expected = rk.render(mesh, session.camera, options=session.options).color
    np.testing.assert_array_equal(_pixels(frame), expected)
    args = _parser().parse_args(attach_number_lists(["render", "--demo", "-o", "x.png", *session.flags()]))
    task = task_from_args(args)
    assert task.view == session.view
    np.testing.assert_array_equal(rk.render(mesh, task.view.camera_for(mesh), options=task.options).color, expected)
    assert frame.camera["flags"] == session.flags() and frame.camera["eye"] == list(session.view.eye)


def test_the_bar_switches_mode_shading_and_the_map_shown():
    session = _session()
    plain = _pixels(session.render(final=True))
    session.handle({"kind": "set", "mode": "solid+wire", "shading": "phong"})
    assert session.current() == {"mode": "solid+wire", "shading": "phong", "show": "color"}
    assert not np.array_equal(_pixels(session.render(final=True)), plain)
    for shown in ("depth", "normals", "ids"):
        session.handle({"kind": "set", "show": shown})
        fb = rk.render(rk.shapes.demo(), session.camera,
                       options=session.options.replace(ids=True, normals=True, camera_depth=True))
        np.testing.assert_array_equal(_pixels(session.render(final=True)), picture(fb, shown))


def test_the_maps_as_pictures():
    mesh = rk.shapes.demo()
    camera = rk.View(size=SIZE).camera_for(mesh)
    fb = rk.render(mesh, camera, "solid", ids=True, normals=True, camera_depth=True)
    drawn = fb.ids >= 0
    depth = picture(fb, "depth")[..., 0]
    assert (depth[~drawn] == 0).all() and depth[drawn].max() == 255 and depth[drawn].min() == 55
    nearest = np.unravel_index(np.argmin(np.where(drawn, fb.camera_depth(), np.inf)), drawn.shape)
    assert depth[nearest] == 255
    normals = picture(fb, "normals").astype(float) / 127.5 - 1.0
    np.testing.assert_allclose(normals[drawn], fb.normals[drawn], atol=1 / 127.5)
    ids = picture(fb, "ids")
    assert (ids[~drawn] == 0).all()
    faces = {}
    for face, colour in zip(fb.ids[drawn], map(tuple, ids[drawn])):
        assert faces.setdefault(face, colour) == colour  # one colour per face
    assert len(set(faces.values())) > 0.95 * len(faces)  # and mostly different ones


@pytest.mark.parametrize("event, words", [
    ({"kind": "spin"}, "kind must be one of"),
    ("drag", "kind must be one of"),
    ({"kind": "drag", "dx": float("nan")}, "dx must be a finite number"),
    ({"kind": "drag", "dx": 1e300}, "dx must be a finite number"),
    ({"kind": "drag", "dy": True}, "dy must be a finite number"),
    ({"kind": "wheel", "steps": "3"}, "steps must be a finite number"),
    ({"kind": "set", "mode": "x-ray"}, "mode must be one of"),
    ({"kind": "set", "show": "uv"}, "show must be one of"),
])
def test_a_bad_event_is_one_line_and_changes_nothing(event, words):
    session = _session()
    before = (session.orbit, session.options, session.shown)
    with pytest.raises(ValueError) as error:
        session.handle(event)
    assert words in str(error.value) and "\n" not in str(error.value)
    assert (session.orbit, session.options, session.shown) == before


def test_a_slow_preview_is_drawn_smaller_next_time_at_one_of_a_few_sizes(monkeypatch):
    from rasterkit.viewer import session as module

    session = _session()
    monkeypatch.setattr(module, "PREVIEW_SECONDS", 1e-9)  # every frame is too slow
    first = session.render(final=False)
    assert first.mime == "image/jpeg" and (first.width, first.height) == SIZE
    second = session.render(final=False)
    assert (second.width, second.height) == (24, 18)
    assert session.render(final=True).width == SIZE[0]
    monkeypatch.setattr(module, "PREVIEW_SECONDS", 0.3)  # roomier: the scale grows back, by steps
    for _ in range(6):
        session.render(final=False)
        assert session.preview_scale in module.PREVIEW_SCALES  # a few sizes: memory recycled by size


def test_a_models_own_camera_gives_the_first_view_and_the_orbit_takes_over(tmp_path):
    import math

    from support.gltffiles import GltfBuilder

    b = GltfBuilder()
    triangle = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)
    mesh = b.mesh({"attributes": {"POSITION": b.accessor(triangle)}})
    b.json["cameras"] = [{"type": "perspective", "perspective": {"yfov": math.radians(50), "znear": 0.1}}]
    b.scene(b.node(mesh=mesh), b.node(camera=0, translation=[0.3, 0.2, 4.0]))
    path = b.write_glb(tmp_path / "cam.glb")
    view = rk.View(size=SIZE, camera="gltf")
    session = ViewerSession(load_drawn(path, rk.RenderOptions(mode="solid"), False), view)
    own = view.camera_for(rk.load(path))
    np.testing.assert_allclose(session.camera.eye, own.eye, atol=1e-12)
    assert session.camera.fov_y == pytest.approx(50) and session.view.camera is None
    session.handle({"kind": "drag", "dx": 10, "dy": 0})
    assert not np.allclose(session.camera.eye, own.eye)  # the file's camera no longer decides
