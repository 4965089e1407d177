"""KHR_lights_punctual: the lights a file's nodes place become the Scene's rasterkit.Light
records: their kinds, world positions and directions (against NumPy's own composition of
the nodes' TRS), colours moved from linear to sRGB with the brightness above 1 in the
intensity, ranges, spot cones; bad lights are one-line errors naming their JSON path; and a
render of the scene uses them."""

from __future__ import annotations

import json
import math
import pickle

import numpy as np
import pytest

import rasterkit
from rasterkit.gltf import GltfError, GltfLight, read_gltf
from support.gltffiles import GltfBuilder
from support.reference_lighting import linear_to_srgb255

S = math.sqrt(0.5)
QUAD = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], np.float32)


def rotation(q) -> np.ndarray:
    """The 3x3 rotation of the quaternion (x, y, z, w), by Rodrigues' formula about its axis
    (not the reader's formula)."""
    x, y, z, w = np.asarray(q, np.float64) / np.linalg.norm(q)
    angle = 2 * math.atan2(math.sqrt(x * x + y * y + z * z), w)
    axis = np.array([x, y, z]) / (math.sin(angle / 2) or 1.0)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k


def trs(translation=(0, 0, 0), rotation_q=(0, 0, 0, 1), scale=(1, 1, 1)) -> np.ndarray:
    m = np.eye(4)
    m[:3, :3] = rotation(rotation_q) @ np.diag(scale)
    m[:3, 3] = translation
    return m


def node_fields(translation=(0, 0, 0), rotation_q=(0, 0, 0, 1), scale=(1, 1, 1)) -> dict:
    return {"translation": list(translation), "rotation": list(rotation_q), "scale": list(scale)}


def lit_builder(lights: list) -> tuple[GltfBuilder, int]:
    """A quad facing +z at the origin (its own root node) and the file's ``lights``; no node
    places a light yet."""
    b = GltfBuilder()
    mesh = b.mesh({"attributes": {"POSITION": b.accessor(QUAD)},
                   "indices": b.accessor(np.array([0, 1, 2, 0, 2, 3], np.uint16), np.uint16)})
    b.json["extensionsUsed"] = ["KHR_lights_punctual"]
    b.json["extensions"] = {"KHR_lights_punctual": {"lights": lights}}
    return b, b.node(mesh=mesh)


def places(light: int, **fields) -> dict:
    return {"extensions": {"KHR_lights_punctual": {"light": light}}, **fields}


def write(b: GltfBuilder, tmp_path, name="lights.gltf"):
    return b.write_gltf(tmp_path / name, bin_name=None)  # the buffer in a data: URI


# --- placement ------------------------------------------------------------------------------

PARENT = dict(translation=(2, 0, -1), rotation_q=(0, S, 0, S))  # 90 degrees about +y
SPOT_NODE = dict(translation=(0, 3, 4), rotation_q=(0.2, -0.3, 0.1, 0.9))
SUN_NODE = dict(rotation_q=(-0.5, 0.1, 0.2, 0.8))
LAMP_NODE = dict(translation=(-1, 2, 0.5), scale=(2, 3, 4))


def placed_scene(tmp_path):
    """A spot (child of a translated, rotated parent), a directional light (rotated root) and a
    point light (scaled child of the same parent)."""
    b, quad = lit_builder([
        {"type": "spot", "color": [1, 0.5, 0.25], "intensity": 40, "range": 12,
         "spot": {"innerConeAngle": 0.3, "outerConeAngle": 0.6}, "name": "lamp"},
        {"type": "directional", "intensity": 2.5},
        {"type": "point", "color": [0, 1, 0], "intensity": 7},
    ])
    spot = b.node(**places(0, **node_fields(**SPOT_NODE)))
    lamp = b.node(**places(2, **node_fields(**LAMP_NODE)))
    parent = b.node(children=[spot, lamp], **node_fields(**PARENT))
    sun = b.node(**places(1, **node_fields(**SUN_NODE)))
    b.scene(quad, parent, sun)
    return read_gltf(write(b, tmp_path))


def test_lights_are_placed_in_world_space(tmp_path):
    scene = placed_scene(tmp_path)
    assert not scene.warnings
    spot, lamp, sun = scene.lights  # depth first, in the order nodes list their children
    assert all(isinstance(light, rasterkit.Light) for light in scene.lights)
    assert (spot.kind, lamp.kind, sun.kind) == ("spot", "point", "directional")
    spot_world = trs(**PARENT) @ trs(**SPOT_NODE)
    lamp_world = trs(**PARENT) @ trs(**LAMP_NODE)
    sun_world = trs(**SUN_NODE)
    np.testing.assert_allclose(spot.position, spot_world[:3, 3], atol=1e-12)
    np.testing.assert_allclose(lamp.position, lamp_world[:3, 3], atol=1e-12)
    assert sun.position is None and lamp.direction is None
    for light, world in ((spot, spot_world), (sun, sun_world)):
        minus_z = -world[:3, 2] / np.linalg.norm(world[:3, 2])
        np.testing.assert_allclose(light.direction, minus_z, atol=1e-12)
    # the records keep what the file says, with their nodes
    record = scene.gltf_lights[0]
    assert isinstance(record, GltfLight)
    assert (record.kind, record.color, record.intensity, record.range, record.name, record.index, record.node) == \
        ("spot", (1.0, 0.5, 0.25), 40.0, 12.0, "lamp", 0, 1)
    assert (record.inner_cone_angle, record.outer_cone_angle) == (0.3, 0.6)
    assert [r.node for r in scene.gltf_lights] == [1, 2, 4]
    np.testing.assert_allclose(scene.gltf_lights[1].position, lamp.position)


def test_the_scaled_node_gives_a_unit_direction(tmp_path):
    """A node's scale does not reach the direction's length (glTF's lights ignore scale)."""
    b, quad = lit_builder([{"type": "directional"}])
    b.scene(quad, b.node(**places(0, scale=[1, 1, 0.001], rotation=[S, 0, 0, S])))
    (sun,) = read_gltf(write(b, tmp_path)).lights
    np.testing.assert_allclose(sun.direction, [0, 1, 0], atol=1e-12)  # -z turned 90 degrees about +x


def test_one_light_placed_by_two_nodes_is_two_lights(tmp_path):
    b, quad = lit_builder([{"type": "point", "range": 5}])
    b.scene(quad, b.node(**places(0, translation=[1, 0, 0])), b.node(**places(0, translation=[0, 1, 0])))
    scene = read_gltf(write(b, tmp_path))
    assert [light.position for light in scene.lights] == [(1, 0, 0), (0, 1, 0)]
    assert [light.range for light in scene.lights] == [5.0, 5.0]


# --- colours, intensities, ranges, cones ----------------------------------------------------

def one_light(tmp_path, light: dict, **node) -> tuple:
    """``(Light, GltfLight, warnings)`` of a file with ``light`` placed by one node."""
    b, quad = lit_builder([light])
    b.scene(quad, b.node(**places(0, translation=[0, 0, 3], **node)))
    scene = read_gltf(write(b, tmp_path))
    assert len(scene.lights) == len(scene.gltf_lights) == 1
    return scene.lights[0], scene.gltf_lights[0], scene.warnings


def srgb8(linear) -> tuple:
    return tuple(int(c) for c in np.floor(linear_to_srgb255(linear) + 0.5))


@pytest.mark.parametrize("color,intensity,wanted_linear,wanted_intensity", [
    ([2, 1, 0.5], 3, [1, 0.5, 0.25], 6.0),  # above 1: the brightest component goes into the intensity
    ([0.5, 0.25, 0], 2, [0.5, 0.25, 0], 2.0),  # within 0..1: as it is
    (None, None, [1, 1, 1], 1.0),  # the defaults: white, 1
    ([0, 0, 0], 5, [0, 0, 0], 5.0),
    ([1e3, 0, 1e-3], 1e-2, [1, 0, 1e-6], 10.0),
])
def test_linear_colours_become_srgb_with_the_brightness_in_the_intensity(tmp_path, color, intensity, wanted_linear,
                                                                         wanted_intensity):
    light = {"type": "point"}
    if color is not None:
        light["color"] = color
    if intensity is not None:
        light["intensity"] = intensity
    made, record, _ = one_light(tmp_path, light)
    assert made.color == srgb8(wanted_linear)
    assert made.intensity == pytest.approx(wanted_intensity, rel=1e-12)
    assert record.color == tuple(float(c) for c in (color or [1, 1, 1]))  # the record keeps the file's


def test_ranges_of_point_and_spot_lights(tmp_path):
    assert one_light(tmp_path, {"type": "point", "range": 2.5})[0].range == 2.5
    assert one_light(tmp_path, {"type": "spot", "range": 0.25, "spot": {}})[0].range == 0.25
    assert one_light(tmp_path, {"type": "point"})[0].range is None  # infinite
    sun, record, warnings = one_light(tmp_path, {"type": "directional", "range": 3})
    assert sun.range is None and record.range is None
    assert [w.split(": ", 1)[1] for w in warnings] == [
        "extensions.KHR_lights_punctual.lights[0].range: a directional light has no range: ignored"]


@pytest.mark.parametrize("spot,inner,outer", [
    ({"innerConeAngle": 0.3, "outerConeAngle": 0.6}, 0.3, 0.6),
    ({}, 0.0, math.pi / 4),  # glTF's defaults
    ({"outerConeAngle": 0.2}, 0.0, 0.2),
    ({"innerConeAngle": 0.5}, 0.5, math.pi / 4),
    ({"innerConeAngle": 1.5, "outerConeAngle": math.pi / 2}, 1.5, math.pi / 2),  # the widest cone
    ({"innerConeAngle": 0.1, "outerConeAngle": 0.1000001}, 0.1, 0.1000001),  # a hard edge
])
def test_spot_cones_become_angle_and_blend(tmp_path, spot, inner, outer):
    """rasterkit's outer half-angle is angle / 2 and its inner (1 - blend) angle / 2: the
    cosines the spot factor ramps between are glTF's."""
    made, record, warnings = one_light(tmp_path, {"type": "spot", "spot": spot})
    assert not warnings and (record.inner_cone_angle, record.outer_cone_angle) == (inner, outer)
    assert made.angle == pytest.approx(math.degrees(2 * outer), rel=1e-12) and made.angle < 180
    assert made.blend == pytest.approx(1 - inner / outer, rel=1e-9, abs=1e-12)
    half = math.radians(made.angle / 2)
    assert math.cos(half) == pytest.approx(math.cos(outer), abs=1e-12)
    assert math.cos(half * (1 - made.blend)) == pytest.approx(math.cos(inner), abs=1e-9)


def test_a_spot_light_without_its_cone_gets_the_default_one(tmp_path):
    made, record, warnings = one_light(tmp_path, {"type": "spot"})
    assert (record.inner_cone_angle, record.outer_cone_angle) == (0.0, math.pi / 4)
    assert made.angle == pytest.approx(90.0) and made.blend == 1.0
    assert len(warnings) == 1 and "a spot light without 'spot'" in warnings[0]


def test_a_node_that_squashes_the_direction_leaves_aimed_lights_out(tmp_path):
    """A zero scale along z leaves no -Z axis: the directional and spot lights are left out
    with a warning; the point light, which needs none, stays."""
    b, quad = lit_builder([{"type": "directional"}, {"type": "spot", "spot": {}}, {"type": "point"}])
    flat = [1, 1, 0]
    b.scene(quad, *(b.node(**places(k, scale=flat, translation=[0, 0, 2])) for k in range(3)))
    scene = read_gltf(write(b, tmp_path))
    assert [light.kind for light in scene.lights] == ["point"] and scene.lights[0].position == (0, 0, 2)
    assert [w.split(": ", 1)[1] for w in scene.warnings] == [
        f"nodes[{k + 1}]: its {kind} light (extensions.KHR_lights_punctual.lights[{k}]) is left out: the node's "
        "matrix squashes its -Z axis, the light's direction" for k, kind in enumerate(["directional", "spot"])]


# --- bad lights -----------------------------------------------------------------------------

LIGHTS = "extensions.KHR_lights_punctual.lights"


@pytest.mark.parametrize("lights,index,where,reason", [
    ([{"type": "area"}], 0, f"{LIGHTS}[0].type", "must be one of directional, point, spot, got 'area'"),
    ([{"intensity": 1}], 0, f"{LIGHTS}[0].type", "missing"),
    ([{"type": 3}], 0, f"{LIGHTS}[0].type", "must be a string, got 3"),
    ([{"type": "point", "intensity": -1}], 0, f"{LIGHTS}[0].intensity", "must be a number from 0 to inf, got -1"),
    ([{"type": "point", "intensity": "1"}], 0, f"{LIGHTS}[0].intensity", "must be a number from 0 to inf"),
    ([{"type": "point", "color": "red"}], 0, f"{LIGHTS}[0].color", "must be a list of 3 finite numbers, got 'red'"),
    ([{"type": "point", "color": [1, 1]}], 0, f"{LIGHTS}[0].color", "must be a list of 3 finite numbers"),
    ([{"type": "point", "color": [1, -0.5, 1]}], 0, f"{LIGHTS}[0].color", "must be 3 numbers >= 0"),
    ([{"type": "point", "range": 0}], 0, f"{LIGHTS}[0].range", "must be above 0"),
    ([{"type": "spot", "range": -2, "spot": {}}], 0, f"{LIGHTS}[0].range", "must be a number from 0 to inf, got -2"),
    ([{"type": "point"}, {"type": "spot", "spot": {"innerConeAngle": 0.5, "outerConeAngle": 0.5}}], 1,
     f"{LIGHTS}[1].spot.innerConeAngle", "must be below outerConeAngle (0.5), got 0.5"),
    ([{"type": "spot", "spot": {"innerConeAngle": 0.9}}], 0, f"{LIGHTS}[0].spot.innerConeAngle",
     "must be below outerConeAngle (0.785398), got 0.9"),
    ([{"type": "spot", "spot": {"outerConeAngle": 2}}], 0, f"{LIGHTS}[0].spot.outerConeAngle",
     "must be a number from 0 to 1.5708, got 2"),
    ([{"type": "spot", "spot": {"outerConeAngle": 0}}], 0, f"{LIGHTS}[0].spot.outerConeAngle", "must be above 0"),
    ([{"type": "spot", "spot": []}], 0, f"{LIGHTS}[0].spot", "must be an object, got a list of 0"),
    ([{"type": "point", "name": 5}], 0, f"{LIGHTS}[0].name", "must be a string, got 5"),
    ([{"type": "point", "color": [10, 0, 0], "intensity": 1e308}], 0, f"{LIGHTS}[0]",
     "its intensity times its brightest colour component (10) is beyond float64"),
    (["point"], 0, f"{LIGHTS}[0]", "must be an object, got 'point'"),
    ({"type": "point"}, 0, LIGHTS, "must be a list, got an object"),
    ([{"type": "point"}], 1, "nodes[1].extensions.KHR_lights_punctual.light",
     "must be an index of the file's 1 lights, got 1"),
    ([], 0, "nodes[1].extensions.KHR_lights_punctual.light", f"must be an index of {LIGHTS}, which is empty, got 0"),
    ([{"type": "point"}], -1, "nodes[1].extensions.KHR_lights_punctual.light", "must be an integer from 0, got -1"),
    ([{"type": "point"}], "0", "nodes[1].extensions.KHR_lights_punctual.light", "must be an integer from 0, got '0'"),
])
def test_bad_lights_are_one_line_errors_naming_where(tmp_path, lights, index, where, reason):
    b, quad = lit_builder(lights)
    b.scene(quad, b.node(**places(index)))
    path = write(b, tmp_path)
    with pytest.raises(GltfError) as info:
        read_gltf(path)
    message = str(info.value)
    assert "\n" not in message and message.startswith(str(path)), message
    assert info.value.where == where and info.value.reason.startswith(reason), message


def test_a_light_named_without_the_files_lights_is_an_error(tmp_path):
    b, quad = lit_builder([])
    del b.json["extensions"]
    b.scene(quad, b.node(**places(0)))
    with pytest.raises(GltfError) as info:
        read_gltf(write(b, tmp_path))
    assert info.value.where == "nodes[1].extensions.KHR_lights_punctual.light"
    assert info.value.reason == f"names a light, but the file defines none ({LIGHTS} is missing)"


@pytest.mark.parametrize("extension,where", [
    ({"KHR_lights_punctual": 0}, "nodes[1].extensions.KHR_lights_punctual"),
    ({"KHR_lights_punctual": {}}, "nodes[1].extensions.KHR_lights_punctual.light"),
    ([], "nodes[1].extensions"),
])
def test_bad_node_extensions_are_errors(tmp_path, extension, where):
    b, quad = lit_builder([{"type": "point"}])
    b.scene(quad, b.node(extensions=extension))
    with pytest.raises(GltfError) as info:
        read_gltf(write(b, tmp_path))
    assert info.value.where == where


def test_unused_lights_are_not_read(tmp_path):
    """As the file's unused materials and meshes: a light no node of the default scene places
    is not checked."""
    b, quad = lit_builder([{"type": "point"}, {"type": "area"}])
    b.scene(quad, b.node(**places(0)))
    assert [light.kind for light in read_gltf(write(b, tmp_path)).lights] == ["point"]


# --- the scene's lights light the render -----------------------------------------------------

def test_a_render_of_the_file_uses_its_lights(tmp_path):
    """The same file with and without its lights renders differently, and the lit file renders
    as the unlit one given the lights explicitly."""
    b, quad = lit_builder([{"type": "spot", "color": [1, 0.2, 0.1], "intensity": 6, "spot": {"outerConeAngle": 0.4}},
                           {"type": "point", "color": [0.1, 0.3, 1], "intensity": 2, "range": 3}])
    b.scene(quad, b.node(**places(0, translation=[0.3, 0.2, 2.5])), b.node(**places(1, translation=[-1.5, -1.5, 1])))
    lit = read_gltf(write(b, tmp_path, "lit.gltf"))
    document = json.loads((tmp_path / "lit.gltf").read_text())
    for key in ("extensions", "extensionsUsed"):
        del document[key]
    for node in document["nodes"]:
        node.pop("extensions", None)
    (tmp_path / "dark.gltf").write_text(json.dumps(document))
    dark = read_gltf(tmp_path / "dark.gltf")
    assert len(lit.lights) == 2 and dark.lights == []
    camera = rasterkit.Camera.look_at((0, 0, 4), (0, 0, 0), (0, 1, 0), fov_y=40, width=48, height=48)
    with_lights = rasterkit.render(lit, camera, mode="solid").color
    without = rasterkit.render(dark, camera, mode="solid").color
    assert np.abs(with_lights.astype(int) - without.astype(int)).max() > 20
    np.testing.assert_array_equal(with_lights, rasterkit.render(dark, camera, mode="solid", lights=lit.lights).color)
    # flat shading lights each face at its centroid: the red spot outshines the blue point light
    centre = with_lights[24, 26].astype(int)
    assert centre[0] > centre[2] + 40, centre


def test_a_scene_with_lights_pickles(tmp_path):
    scene = placed_scene(tmp_path)
    copy = pickle.loads(pickle.dumps(scene))
    assert copy.lights == scene.lights
    np.testing.assert_array_equal(copy.gltf_lights[0].direction, scene.gltf_lights[0].direction)


def test_the_command_line_lights_a_file_with_its_lights_unless_told_otherwise(tmp_path):
    from support.hostile import run_cli

    scene = placed_scene(tmp_path)
    path = tmp_path / "lights.gltf"
    view = ["--mode", "solid", "--size", "48x40", "--eye", "0,0,6", "--target", "0,0,0", "--fov", "40"]
    for extra, lights in (([], scene.lights), (["--light", "ambient:white:0.3"], [rasterkit.Light.ambient(intensity=0.3)])):
        out = tmp_path / f"cli{len(extra)}.png"
        result = run_cli("render", str(path), "-o", str(out), *view, *extra)
        assert result.code == 0, result.stderr
        camera = rasterkit.Camera.look_at((0, 0, 6), (0, 0, 0), (0, 1, 0), fov_y=40, width=48, height=40)
        expected = rasterkit.render(scene.world_mesh(), camera, mode="solid", lights=lights).color
        from PIL import Image

        np.testing.assert_array_equal(np.asarray(Image.open(out).convert("RGB")), expected)
