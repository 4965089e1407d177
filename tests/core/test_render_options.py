"""RenderOptions and View: one checked record each, passed whole by every path.

Every field of RenderOptions must reach the frame through every way a frame is drawn: the
plain render, a distorted camera, a multi-sample render (here), a batch on local workers
(``--jobs 2``, tests/batch/test_batch_options.py) and a batch on Dask
(tests/batch/test_batch_dask.py). The check: a frame drawn with every field changed from its
default, where putting back any one default changes the pixels (so each field is seen), is
the same bit for bit whichever path draws it.
"""

from __future__ import annotations

import pickle

import numpy as np
import pytest
from PIL import Image

import rasterkit
from rasterkit import Camera, Mesh, RenderOptions, View, shapes
from rasterkit.options import FIELDS
from support.frames import BALL, BOWL, IMAGE, TEXTURED_BOWL

CAMERA = Camera.look_at(eye=(1.6, 2.2, 2.4), target=(0, 0, 0), width=96, height=72)
#: The fields that decide the maps made with the frame, and those of drawn points.
MAPS = dict(ids=True, normals=True, camera_depth=True, uv=True)
POINTS = dict(point_size=3, point_color="red")
#: The fields of textured frames, each away from its default (TEXTURED_BOWL shows them).
TEXTURE = dict(textures=False, texture_filter="nearest")
#: The fields of lit frames, each away from its default.
LIGHTING = dict(lights=(rasterkit.Light.point((1.5, 2.0, 1.0), color="#f5deb3", intensity=6.0),
                        rasterkit.Light.ambient("white", 0.08)), specular=0.7, shininess=6.0, shadows=True,
                shadow_map_size=64, shadow_softness=2.0, ground="#d2b48c", ao=True, ao_radius=0.6, ao_samples=5)
CLOUD = np.array([[0.8, 0.9, 0.9], [1.2, 0.3, 0.8], [0.4, 1.3, 0.5]])  # outside the ball, facing the camera


def test_the_fields_under_test_are_all_the_fields():
    assert set(IMAGE) | set(MAPS) | set(POINTS) | set(TEXTURE) | set(LIGHTING) == FIELDS


def test_render_keywords_are_changes_to_the_options_record():
    by_keywords = rasterkit.render(BOWL, CAMERA, "solid", cull="none", color="red", samples=2)
    by_record = rasterkit.render(BOWL, CAMERA, options=RenderOptions(mode="solid", cull="none", color="red",
                                                                     samples=2))
    assert np.array_equal(by_keywords.color, by_record.color)
    base = RenderOptions(mode="hidden", color="red")
    assert np.array_equal(rasterkit.render(BOWL, CAMERA, "solid", options=base, color="blue").color,
                          rasterkit.render(BOWL, CAMERA, options=RenderOptions(mode="solid", color="blue")).color)
    assert np.array_equal(rasterkit.render(BOWL, CAMERA).color,
                          rasterkit.render(BOWL, CAMERA, options=RenderOptions(mode="wire")).color)


def test_the_record_is_checked_once_and_stored_in_one_form():
    a = RenderOptions(color=(70, 130, 180), light=[1, 2, 3], samples=np.int64(4), crease_angle=np.float32(10))
    b = RenderOptions(color=[70, 130, 180], light=(1.0, 2.0, 3.0), samples=4, crease_angle=10.0)
    assert a == b and hash(a) == hash(b) and pickle.loads(pickle.dumps(a)) == a
    assert a.light == (1.0, 2.0, 3.0) and type(a.samples) is int
    for bad, error, words in [(dict(mode="shiny"), ValueError, "mode must be one of"),
                              (dict(aa=1), TypeError, "aa must be True or False"),
                              (dict(samples=0), ValueError, "samples must be 1 to 256"),
                              (dict(color="nocolour"), ValueError, "color: unknown colour"),
                              (dict(light=(0, 0, 0)), ValueError, "light"),
                              (dict(crease_angle=181), ValueError, "crease_angle"),
                              (dict(vignette=2), ValueError, "vignette must lie in [0, 1]"),
                              (dict(point_size=65), ValueError, "point_size must be 1 to 64")]:
        with pytest.raises(error, match=words.replace("[", r"\[").replace("]", r"\]")):
            RenderOptions(**bad)
    with pytest.raises(TypeError, match="unknown render option 'colour'"):
        rasterkit.render(BOWL, CAMERA, colour="red")
    with pytest.raises(TypeError, match="options must be a rasterkit.RenderOptions"):
        rasterkit.render(BOWL, CAMERA, options={"mode": "solid"})


def test_per_point_colours_go_with_the_points():
    colours = np.array([[255, 0, 0], [0, 255, 0], [0, 0, 255]])
    fb = rasterkit.render(None, CAMERA, points=CLOUD, point_color=colours, point_size=5)
    found = {tuple(c) for c in fb.color.reshape(-1, 3)}
    assert {(255, 0, 0), (0, 255, 0), (0, 0, 255)} <= found


def test_a_view_makes_the_camera_the_command_line_makes():
    view = View(size=(64, 48), projection="dimetric", azimuth=10.0, distance=7.0)
    center, radius = BALL.bounding_sphere()
    expected = Camera.preset("dimetric", center, radius, width=64, height=48, azimuth=10.0, elevation=20.0,
                             fov_y=45.0, distance=7.0)
    assert view.camera_for(BALL) == expected
    assert View(size=[64, 48], eye=np.array([1, 2, 3])) == View(size=(64, 48), eye=(1.0, 2.0, 3.0))
    with pytest.raises(ValueError, match="size must be"):
        View(size=(0, 10))
    with pytest.raises(TypeError, match="eye must be a point"):
        View(eye=(1, 2))
    with pytest.raises(ValueError, match="no extent"):
        View().camera_for(Mesh(np.ones((3, 3)), [[0, 1, 2]]))


# --- every field reaches the frame through every path -----------------------------------

def _distorted(camera: Camera) -> Camera:
    k, r, t = camera.to_opencv()
    return Camera.from_opencv(k, r, t, camera.width, camera.height, near=camera.near, far=camera.far,
                              dist=(0.08, -0.02, 0.0, 0.0, 0.0))


@pytest.mark.parametrize("path", ["plain", "distorted", "one sample"])
def test_every_image_field_changes_the_frame(path):
    """With every field away from its default, putting back any one default changes the
    pixels: each field is seen, in each path (a field the path dropped would not be)."""
    camera = _distorted(CAMERA) if path == "distorted" else CAMERA
    full = RenderOptions(**IMAGE)
    if path == "one sample":
        full = full.replace(samples=1)
    reference = rasterkit.render(BOWL, camera, options=full).color
    unseen = []
    for name in IMAGE:
        if path == "one sample" and name == "samples":
            continue
        changed = rasterkit.render(BOWL, camera, options=full.replace(**{name: getattr(RenderOptions(), name)})).color
        if np.array_equal(changed, reference):
            unseen.append(name)
    assert unseen == []


@pytest.mark.parametrize("path", ["plain", "distorted", "samples"])
def test_the_texture_fields_change_a_textured_frame(path):
    """``textures`` and ``texture_filter`` are seen in each path: turning textures off, or
    filtering another way, changes a textured frame drawn with the other image fields set."""
    camera = _distorted(CAMERA) if path == "distorted" else CAMERA
    full = RenderOptions(**IMAGE).replace(samples=4 if path == "samples" else 1)
    reference = rasterkit.render(TEXTURED_BOWL, camera, options=full).color
    for name, value in TEXTURE.items():
        assert not np.array_equal(rasterkit.render(TEXTURED_BOWL, camera, options=full.replace(**{name: value})).color,
                                  reference), name
    off = rasterkit.render(TEXTURED_BOWL, camera, options=full.replace(textures=False)).color
    assert np.array_equal(off, rasterkit.render(BOWL, camera, options=full).color)


@pytest.mark.parametrize("path", ["plain", "distorted", "samples"])
def test_the_lighting_fields_change_a_lit_frame(path):
    """``lights``, ``specular``, ``shininess`` and the shadow fields are seen in each path: with
    the other image fields set (``light`` aside: the lights replace it), putting back any one
    default changes the frame."""
    camera = _distorted(CAMERA) if path == "distorted" else CAMERA
    full = RenderOptions(**IMAGE, **LIGHTING).replace(samples=4 if path == "samples" else 1)
    reference = rasterkit.render(BOWL, camera, options=full).color
    for name in LIGHTING:
        changed = rasterkit.render(BOWL, camera, options=full.replace(**{name: getattr(RenderOptions(), name)})).color
        assert not np.array_equal(changed, reference), name
    assert np.array_equal(rasterkit.render(BOWL, camera, options=full.replace(light=(0.0, 0.0, 1.0))).color, reference)


@pytest.mark.parametrize("path", ["plain", "distorted", "samples"])
def test_the_maps_and_points_reach_the_frame(path):
    camera = _distorted(CAMERA) if path == "distorted" else CAMERA
    options = RenderOptions(mode="solid", samples=4 if path == "samples" else 1)
    plain = rasterkit.render(BOWL, camera, options=options)
    assert plain.ids is None and plain.normals is None
    mapped = rasterkit.render(BOWL, camera, options=options.replace(**MAPS))
    assert mapped.ids is not None and (mapped.ids >= 0).any()
    assert mapped.normals is not None and np.isfinite(mapped.normals).any()
    assert mapped.uv is not None and mapped.uv.shape == mapped.ids.shape + (2,)
    np.testing.assert_array_equal(mapped.camera_depth(), plain.camera_depth())
    dots = rasterkit.render(BOWL, camera, options=options, points=CLOUD)
    red = rasterkit.render(BOWL, camera, options=options.replace(**POINTS), points=CLOUD)
    assert (np.all(red.color == (255, 0, 0), axis=2).sum() > np.all(dots.color == (255, 0, 0), axis=2).sum())
    assert (red.color != dots.color).any(axis=2).sum() >= 8 * len(CLOUD)  # 3x3 squares, not single pixels


def test_the_metric_depth_is_made_with_the_frame_when_asked():
    fb = rasterkit.render(BOWL, CAMERA, options=RenderOptions(mode="solid", camera_depth=True))
    assert fb._camera_depth is not None  # made by the band worker, not on request
    assert rasterkit.render(BOWL, CAMERA, options=RenderOptions(mode="solid"))._camera_depth is None


def test_feature_edges_through_a_distorted_camera():
    """The feature edges of a distorted camera are those of its undistorted render, not
    every edge (the drift of the copies of the option list this record replaced)."""
    sphere = shapes.icosphere(2)
    k = [[300.0, 0.0, 160.0], [0.0, 300.0, 120.0], [0.0, 0.0, 1.0]]
    r, t = np.eye(3), [0.0, 0.0, 4.0]

    def dark(dist, edges):
        camera = Camera.from_opencv(k, r, t, 320, 240, dist=dist)
        return int((rasterkit.render(sphere, camera, "wire", edges=edges).color.max(axis=2) < 128).sum())

    feature, every = dark((0.001, 0, 0, 0, 0), "feature"), dark((0.001, 0, 0, 0, 0), "all")
    assert feature < every / 5
    assert abs(feature - dark(None, "feature")) < 0.25 * dark(None, "feature")  # resampled: not the same pixels


def test_feature_edges_through_a_distorted_camera_on_the_command_line(tmp_path):
    import json

    from support.hostile import run_cli
    from support.objfiles import write_obj

    camera = {"K": [[300, 0, 160], [0, 300, 120], [0, 0, 1]], "R": np.eye(3).tolist(), "t": [0, 0, 4],
              "width": 320, "height": 240, "dist": [0.001, 0, 0, 0, 0]}
    (tmp_path / "cam.json").write_text(json.dumps(camera))
    model = write_obj(tmp_path / "ball.obj", BALL)
    counts = {}
    for edges in ("feature", "all"):
        out = tmp_path / f"{edges}.png"
        done = run_cli("render", model, "-o", out, "--camera-opencv", tmp_path / "cam.json", "--edges", edges)
        assert done.code == 0, done.describe()
        counts[edges] = int((np.asarray(Image.open(out)).max(axis=2) < 128).sum())
    assert counts["feature"] < counts["all"] / 5
